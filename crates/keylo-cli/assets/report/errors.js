// keylo report: records every script error and console error on <html data-errors="…">, so
// that a headless browser (crates/keylo-cli/tests/report.rs) can see them.
(function () {
  var errors = [];
  function note(message) {
    errors.push(String(message));
    document.documentElement.setAttribute('data-errors', JSON.stringify(errors));
  }
  window.addEventListener('error', function (e) { note(e.message || e); });
  window.addEventListener('unhandledrejection', function (e) { note(e.reason); });
  var original = console.error;
  console.error = function () {
    note(Array.prototype.join.call(arguments, ' '));
    original.apply(console, arguments);
  };
  document.documentElement.setAttribute('data-errors', '[]');
})();

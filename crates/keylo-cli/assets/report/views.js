// keylo report: draws each <div class="view" data-scene="N"> with three.js (window.THREE,
// bundled from the npm package `three`), and records on <body data-views="…"> how many
// pixels each view drew, so that a headless browser can check the canvases are not blank.
(function () {
  var scenes = JSON.parse(document.getElementById('keylo-scenes').textContent);
  var BACKGROUND = 0x141414;
  var results = [];

  function floats(b64) {
    var bin = atob(b64);
    var bytes = new Uint8Array(bin.length);
    for (var i = 0; i < bin.length; i++) bytes[i] = bin.charCodeAt(i);
    return new Float32Array(bytes.buffer);
  }

  // The box holding the 2nd to 98th percentile of the points on each axis (all of a
  // line's), so that a few far points do not shrink the view to a dot.
  function extend(bounds, xyz, robust) {
    var n = xyz.length / 3;
    var step = Math.max(1, Math.floor(n / 20000));
    for (var k = 0; k < 3; k++) {
      var v = [];
      for (var i = 0; i < n; i += step) v.push(xyz[3 * i + k]);
      v.sort(function (a, b) { return a - b; });
      if (!v.length) return;
      var lo = robust ? v[Math.floor(0.02 * (v.length - 1))] : v[0];
      var hi = robust ? v[Math.ceil(0.98 * (v.length - 1))] : v[v.length - 1];
      bounds.min[k] = Math.min(bounds.min[k], lo);
      bounds.max[k] = Math.max(bounds.max[k], hi);
    }
  }

  function geometry(b64, bounds, robust) {
    var xyz = floats(b64);
    extend(bounds, xyz, robust);
    var g = new THREE.BufferGeometry();
    g.setAttribute('position', new THREE.Float32BufferAttribute(xyz, 3));
    return g;
  }

  function drawnPixels(renderer, width, height) {
    var gl = renderer.getContext();
    var px = new Uint8Array(width * height * 4);
    gl.readPixels(0, 0, width, height, gl.RGBA, gl.UNSIGNED_BYTE, px);
    var bg = [(BACKGROUND >> 16) & 255, (BACKGROUND >> 8) & 255, BACKGROUND & 255];
    var n = 0;
    for (var i = 0; i < px.length; i += 4) {
      if (Math.abs(px[i] - bg[0]) + Math.abs(px[i + 1] - bg[1]) + Math.abs(px[i + 2] - bg[2]) > 24) n++;
    }
    return n;
  }

  function show(el, s) {
    var scene = new THREE.Scene();
    scene.background = new THREE.Color(BACKGROUND);
    var bounds = { min: [Infinity, Infinity, Infinity], max: [-Infinity, -Infinity, -Infinity] };
    s.clouds.forEach(function (c) {
      var m = new THREE.PointsMaterial({ color: c.colour, size: c.size, sizeAttenuation: false });
      scene.add(new THREE.Points(geometry(c.xyz, bounds, true), m));
    });
    // Trajectories are drawn over the map (no depth test), as a line and a dot per pose.
    s.lines.forEach(function (l) {
      var g = geometry(l.xyz, bounds, false);
      var line = new THREE.Line(g, new THREE.LineBasicMaterial({ color: l.colour, depthTest: false }));
      var dots = new THREE.Points(g, new THREE.PointsMaterial({
        color: l.colour, size: l.size, sizeAttenuation: false, depthTest: false }));
      line.renderOrder = dots.renderOrder = 1;
      scene.add(line);
      scene.add(dots);
    });
    if (!isFinite(bounds.min[0])) bounds = { min: [-1, -1, -1], max: [1, 1, 1] };
    var c = new THREE.Vector3(
      (bounds.min[0] + bounds.max[0]) / 2, (bounds.min[1] + bounds.max[1]) / 2,
      (bounds.min[2] + bounds.max[2]) / 2);
    var r = Math.max(1, 0.5 * Math.hypot(bounds.max[0] - bounds.min[0],
      bounds.max[1] - bounds.min[1], bounds.max[2] - bounds.min[2]));
    var width = el.clientWidth || 800, height = el.clientHeight || 560;
    var camera = new THREE.PerspectiveCamera(45, width / height, r / 1000, r * 20);
    camera.up.set(0, 0, 1);
    camera.position.set(c.x - 0.9 * r, c.y - 1.3 * r, c.z + 1.1 * r);
    var renderer = new THREE.WebGLRenderer({ antialias: true, preserveDrawingBuffer: true });
    renderer.setPixelRatio(1);
    renderer.setSize(width, height);
    el.appendChild(renderer.domElement);
    var controls = new THREE.OrbitControls(camera, renderer.domElement);
    controls.target.copy(c);
    controls.screenSpacePanning = true;
    controls.update();
    var render = function () { renderer.render(scene, camera); };
    controls.addEventListener('change', render);
    render();
    return drawnPixels(renderer, width, height);
  }

  document.querySelectorAll('.view[data-scene]').forEach(function (el) {
    var s = scenes[Number(el.getAttribute('data-scene'))];
    try {
      results.push({ title: s.title, drawn: show(el, s) });
    } catch (e) {
      el.className += ' failed';
      el.textContent = 'This 3-D view could not be drawn (it needs WebGL): ' + e;
      results.push({ title: s.title, drawn: 0, error: String(e) });
      console.error('keylo report: ' + s.title + ': ' + e);
    }
  });
  document.body.setAttribute('data-views', JSON.stringify(results));
})();

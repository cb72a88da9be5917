// Minimal host for @foxglove/studio-base 1.48.0 (mirrors packages/studio-web Root).
(async function () {
  const S = window; // UMD exports were copied onto window
  const h = React.createElement;
  const log = (...a) => console.log("[host]", ...a);
  window.onerror = (...args) => console.error("[host] onerror", ...args);

  class MemAppConfig {
    constructor(defaults) { this.v = new Map(Object.entries(defaults || {})); this.l = new Map(); }
    get(k) { return this.v.get(k); }
    async set(k, val) { this.v.set(k, val); for (const cb of this.l.get(k) || []) cb(val); }
    addChangeListener(k, cb) { if (!this.l.has(k)) this.l.set(k, new Set()); this.l.get(k).add(cb); }
    removeChangeListener(k, cb) { this.l.get(k)?.delete(cb); }
  }
  class MemLayoutStorage {
    constructor() { this.ns = new Map(); }
    m(n) { if (!this.ns.has(n)) this.ns.set(n, new Map()); return this.ns.get(n); }
    async list(n) { return [...this.m(n).values()]; }
    async get(n, id) { return this.m(n).get(id); }
    async put(n, layout) { this.m(n).set(layout.id, layout); return layout; }
    async delete(n, id) { this.m(n).delete(id); }
    async importLayouts({ fromNamespace, toNamespace }) {
      for (const l of await this.list(fromNamespace)) await this.put(toNamespace, l);
    }
  }
  // Suppress the one-time "Open settings to configure topics" onboarding tooltip.
  if (!localStorage.getItem("studio.profile-data")) {
    localStorage.setItem("studio.profile-data", JSON.stringify(
      { onboarding: { settingsTooltipShownForPanelTypes: ["3D", "Plot", "RawMessages", "ImageViewPanel"] } }));
  }
  try {
    S.overwriteFetch();
    await S.waitForFonts();
    await S.initI18n();
  } catch (e) { console.error("[host] init error", e); }
  const dataSources = [
    new S.FoxgloveWebSocketDataSourceFactory(),
    new S.RemoteDataSourceFactory(),
    new S.McapLocalDataSourceFactory(),
    new S.SampleNuscenesDataSourceFactory(),
  ];
  // Optional: seed a layout from ./layout.json (LayoutData) as id "shot"; open with &layoutId=shot
  const layoutStorage = new MemLayoutStorage();
  try {
    const r = await fetch(new URLSearchParams(location.search).get("layoutFile") || "layout.json");
    if (r.ok) {
      const data = await r.json();
      await layoutStorage.put("local", { id: "shot", name: "Screenshot", permission: "CREATOR_WRITE",
        baseline: { data, savedAt: new Date().toISOString() }, working: undefined, syncInfo: undefined });
      log("seeded layout 'shot'");
    }
  } catch (e) { console.error("[host] layout seed failed", e); }
  const app = h(S.App, {
    enableLaunchPreferenceScreen: false,
    deepLinks: [window.location.href],
    dataSources,
    appConfiguration: new MemAppConfig({}),
    layoutStorage,
    extensionLoaders: [],
    enableGlobalCss: true,
  });
  ReactDOM.render(app, document.getElementById("root"));
  log("rendered");
})();

//! All four plugin stages through the C ABI: a Rust plugin (exported into this test binary
//! with `export_plugin!`) wraps keylo's own FAST detector, BRIEF descriptor, matched
//! keypoint-neighbourhood downsampler and KISS-ICP; images, keypoints, descriptors, frames
//! (with every scan point of an unorganised source, ABI version 2), clouds and poses cross
//! the ABI both ways, and the trajectory is the built-in one exactly.

use std::path::Path;
use std::sync::Arc;

use keylo::config::RawConfig;
use keylo::plugin::host::{register_plugin, Plugin};
use keylo::plugin::FromConfig;
use keylo::{
    CoreError, Descriptor, Descriptors, Detector, Downsampler, FrameFeatures, Image, Keypoint,
    LidarFrame, Pipeline, PointCloud, Registrar, Registration, Registry,
};

/// A built-in backend of `kind = inner`, the other keys its parameters.
fn inner<T: ?Sized + 'static>(
    pick: fn(&Registry) -> &keylo::registry::Backends<T>,
    mut params: toml::Table,
) -> Result<Box<T>, String> {
    let kind = params
        .remove("inner")
        .and_then(|v| v.as_str().map(str::to_string))
        .ok_or("`inner` (a built-in kind) is required")?;
    let registry = keylo::registry();
    let factory = pick(&registry)
        .get(&kind)
        .ok_or(format!("no built-in `{kind}`"))?;
    let params = factory
        .resolve(&params)
        .map_err(|(k, m)| format!("{k}: {m}"))?;
    factory
        .build(&params, &Default::default())
        .map_err(|e| e.to_string())
}

struct WrapDetector(Box<dyn Detector>);
struct WrapDescriptor(Box<dyn Descriptor>);
struct WrapDownsampler(Box<dyn Downsampler>);
struct WrapRegistrar(Box<dyn Registrar>);

impl FromConfig for WrapDetector {
    type Params = toml::Table;
    fn from_params(p: toml::Table) -> Result<Self, String> {
        inner(|r| &r.detectors, p).map(Self)
    }
}
impl FromConfig for WrapDescriptor {
    type Params = toml::Table;
    fn from_params(p: toml::Table) -> Result<Self, String> {
        inner(|r| &r.descriptors, p).map(Self)
    }
}
impl FromConfig for WrapDownsampler {
    type Params = toml::Table;
    fn from_params(p: toml::Table) -> Result<Self, String> {
        inner(|r| &r.downsamplers, p).map(Self)
    }
}
impl FromConfig for WrapRegistrar {
    type Params = toml::Table;
    fn from_params(p: toml::Table) -> Result<Self, String> {
        inner(|r| &r.registrars, p).map(Self)
    }
}

impl Detector for WrapDetector {
    fn detect(&mut self, image: &Image) -> Result<Vec<Keypoint>, CoreError> {
        self.0.detect(image)
    }
}
impl Descriptor for WrapDescriptor {
    fn describe(
        &mut self,
        image: &Image,
        keypoints: &mut Vec<Keypoint>,
    ) -> Result<Descriptors, CoreError> {
        self.0.describe(image, keypoints)
    }
}
impl Downsampler for WrapDownsampler {
    fn downsample(
        &mut self,
        frame: &LidarFrame,
        features: &FrameFeatures,
    ) -> Result<PointCloud, CoreError> {
        self.0.downsample(frame, features)
    }
}
impl Registrar for WrapRegistrar {
    fn register(&mut self, cloud: &PointCloud) -> Result<Registration, CoreError> {
        self.0.register(cloud)
    }
    fn map_size(&self) -> usize {
        self.0.map_size()
    }
}

keylo::plugin::export_plugin! {
    name: "wrap",
    version: "1.0.0",
    detector: WrapDetector => "a built-in detector behind the C ABI",
    descriptor: WrapDescriptor => "a built-in descriptor behind the C ABI",
    downsampler: WrapDownsampler => "a built-in downsampler behind the C ABI",
    registrar: WrapRegistrar => "a built-in registrar behind the C ABI",
}

const CONFIG: &str = r#"
[source]
kind = "sim"
scene = "lab"
frames = 4
sensor = "os1-64"
columns = 512

[image]
kind = "lidar"
images = ["signal"]
width = 512
height = 64

[detector]
kind = "fast"
threshold = 20

[descriptor]
kind = "brief"

[downsampler]
kind = "keypoint-neighbourhood"
windows = { signal = 5 }
keypoints = "matched"

[registrar]
kind = "kiss-icp"
"#;

/// `text` with every stage's kind moved to `inner` and `kind = "plugin:wrap"`.
fn wrapped(text: &str) -> RawConfig {
    let mut raw = RawConfig::parse("wrapped", text).unwrap();
    for section in ["detector", "descriptor", "downsampler", "registrar"] {
        let t = raw.table[section].as_table_mut().unwrap();
        let kind = t.remove("kind").unwrap();
        t.insert("inner".into(), kind);
        t.insert("kind".into(), "plugin:wrap".into());
    }
    raw
}

fn run(raw: &RawConfig, registry: &Registry) -> Vec<(usize, keylo::Pose)> {
    let config = registry.resolve(raw).unwrap();
    let mut pipeline = Pipeline::build(&config, registry).unwrap();
    let mut out = Vec::new();
    while let Some(r) = pipeline.step() {
        let r = r.unwrap();
        out.push((r.cloud_points, r.pose));
    }
    out
}

#[test]
fn every_stage_crosses_the_abi_unchanged() {
    let mut registry = keylo::registry();
    // SAFETY: the table comes from this binary's own `keylo_plugin_entry`.
    let plugin = unsafe { Plugin::from_info(keylo_plugin_entry(), Path::new("(this test)")) }
        .map(Arc::new)
        .unwrap();
    assert_eq!(
        plugin.offered(),
        "detector, descriptor, downsampler, registrar"
    );
    register_plugin(&mut registry, &plugin);

    let builtin = run(&RawConfig::parse("built-in", CONFIG).unwrap(), &registry);
    let via_abi = run(&wrapped(CONFIG), &registry);
    assert_eq!(builtin.len(), 4);
    assert!(
        builtin[3].1.translation.vector.norm() > 0.01,
        "the sensor moves"
    );
    for ((n_b, p_b), (n_p, p_p)) in builtin.iter().zip(&via_abi) {
        assert_eq!(n_b, n_p, "cloud sizes");
        assert!(n_b < &(512 * 64), "the matched keypoints select a subset");
        let d = (p_b.translation.vector - p_p.translation.vector).norm();
        assert!(
            d < 1e-9 && p_b.rotation.angle_to(&p_p.rotation) < 1e-9,
            "{p_b} vs {p_p}"
        );
    }
}

/// `CONFIG` reading `dir` (KITTI `.bin` files) instead of the simulator: unorganised frames,
/// on a grid coarse enough that many pixels hold several points.
fn on_bins(dir: &Path) -> String {
    let source = format!(
        "[source]\nkind = \"kitti\"\npath = {:?}\n\n[source.projection]\nrows = 32\ncols = 256\n\n",
        dir.to_str().unwrap()
    );
    let rest = &CONFIG[CONFIG.find("[image]").unwrap()..];
    source + &rest.replace("width = 512\nheight = 64\n", "")
}

#[test]
fn every_point_of_an_unorganised_scan_crosses_the_abi() {
    use keylo::sim::{SceneKind, SensorKind, SimConfig, Simulator};
    let sim = Simulator::new(&SimConfig {
        scene: SceneKind::Lab,
        frames: 4,
        sensor: SensorKind::Os1_64,
        columns: 512,
        ..SimConfig::default()
    })
    .unwrap();
    let dir = tempfile::tempdir().unwrap();
    for k in 0..4 {
        let path = dir.path().join(format!("{k:06}.bin"));
        keylo::io::kitti_bin::write_kitti_bin(&path, &sim.frame(k)).unwrap();
    }
    let mut registry = keylo::registry();
    // SAFETY: the table comes from this binary's own `keylo_plugin_entry`.
    let plugin = unsafe { Plugin::from_info(keylo_plugin_entry(), Path::new("(this test)")) }
        .map(Arc::new)
        .unwrap();
    register_plugin(&mut registry, &plugin);

    let text = on_bins(dir.path());
    let builtin = run(&RawConfig::parse("built-in", &text).unwrap(), &registry);
    let via_abi = run(&wrapped(&text), &registry);
    assert_eq!(builtin.len(), 4);
    for ((n_b, p_b), (n_p, p_p)) in builtin.iter().zip(&via_abi) {
        assert_eq!(n_b, n_p, "cloud sizes");
        let d = (p_b.translation.vector - p_p.translation.vector).norm();
        assert!(
            d < 1e-9 && p_b.rotation.angle_to(&p_p.rotation) < 1e-9,
            "{p_b} vs {p_p}"
        );
    }
    // The selected pixels hold more points than the one each shows: a plugin that saw only
    // the grids would have registered these smaller clouds.
    let nearest = text.replace(
        "keypoints = \"matched\"",
        "keypoints = \"matched\"\npixel_points = \"nearest\"",
    );
    let nearest = run(&RawConfig::parse("nearest", &nearest).unwrap(), &registry);
    let total = |r: &[(usize, keylo::Pose)]| r.iter().map(|(n, _)| n).sum::<usize>();
    assert!(
        total(&via_abi) > total(&nearest),
        "{} scan points vs {} pixels",
        total(&via_abi),
        total(&nearest)
    );
}

//! The images of `--data`: a folder of PNG files, or the chosen channel of any source's frames.

use std::path::{Path, PathBuf};

use anyhow::{bail, Context, Result};
use keylo::kpeval::{EvalSpec, Plane};

use super::InputArgs;
use crate::arg_groups::DataArgs;
use crate::configs;

/// The evaluation spec: `--config` (or the defaults) with `--channel` on top.
pub fn spec(args: &InputArgs) -> Result<EvalSpec> {
    let mut spec = match &args.config {
        Some(p) => {
            let text = std::fs::read_to_string(p)
                .with_context(|| format!("--config {}: cannot read", p.display()))?;
            let spec = EvalSpec::from_toml(&text, &p.display().to_string())?;
            spec.check_trust(&format!("--config {}", p.display()), args.trust.trust())?;
            spec
        }
        None => EvalSpec::default(),
    };
    if let Some(c) = &args.channel {
        spec.image.channel = c.clone();
        spec.validate("--channel")?;
    }
    Ok(spec)
}

/// What both commands prepare before evaluating.
pub struct Prepared {
    pub registry: keylo::Registry,
    pub set: keylo::kpeval::ComboSet,
    pub combos: Vec<keylo::kpeval::Combo>,
    pub planes: Vec<Plane>,
    pub jobs: usize,
}

/// The registry (with plugins), the combinations, the images and the job count; creates
/// `--out`.
pub fn prepare(args: &InputArgs, spec: &EvalSpec, threads: Option<usize>) -> Result<Prepared> {
    let registry = registry(args)?;
    let set = keylo::kpeval::ComboSet::parse(&args.combos);
    let combos = keylo::kpeval::parse_combos(&set, &registry).context("--combos")?;
    let planes = planes(args, spec)?;
    let jobs = jobs(args.jobs, threads)?;
    std::fs::create_dir_all(args.out())
        .with_context(|| format!("creating {}", args.out().display()))?;
    Ok(Prepared {
        registry,
        set,
        combos,
        planes,
        jobs,
    })
}

/// Jobs: `--jobs`, else `--threads`, else one per core.
pub(crate) fn jobs(asked: Option<usize>, threads: Option<usize>) -> Result<usize> {
    let n = asked.or(threads).unwrap_or_else(|| {
        std::thread::available_parallelism().map_or(1, std::num::NonZeroUsize::get)
    });
    if n == 0 {
        bail!("--jobs 0: expected at least 1");
    }
    Ok(n)
}

/// keylo's registry with the plugins of the search path registered as `plugin:NAME` (only
/// looked for when the combinations name a plugin or are `all`).
pub fn registry(args: &InputArgs) -> Result<keylo::Registry> {
    let mut registry = keylo::registry();
    let wants = args.combos.contains("plugin:") || args.combos.trim() == "all";
    if !wants {
        return Ok(registry);
    }
    let search = keylo::plugin::SearchPath::new(&args.plugin_dirs);
    for lib in search.libraries() {
        match keylo::plugin::Plugin::open(&lib) {
            Ok(p) => keylo::plugin::host::register_plugin(&mut registry, &p),
            // Other shared libraries may share a folder with plugins.
            Err(e) => tracing::info!("{}: not loaded as a plugin: {e}", lib.display()),
        }
    }
    Ok(registry)
}

/// The PNG files of `dir` in natural name order (none: not a PNG folder).
pub(crate) fn png_files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut files: Vec<PathBuf> = entries
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|e| e.eq_ignore_ascii_case("png")))
        .collect();
    files
        .sort_by(|a, b| keylo::io::folder::natural_cmp(&a.to_string_lossy(), &b.to_string_lossy()));
    files
}

/// Indices `start, start + stride, …`, at most `frames` of them, below `n` when known.
fn wanted(i: usize, args: &InputArgs) -> Option<bool> {
    if i < args.start {
        return Some(false);
    }
    let k = i - args.start;
    if k / args.stride >= args.frames {
        return None;
    }
    Some(k.is_multiple_of(args.stride))
}

/// Reads the images to evaluate.
pub fn planes(args: &InputArgs, spec: &EvalSpec) -> Result<Vec<Plane>> {
    if args.stride == 0 {
        bail!("--stride 0: expected at least 1");
    }
    if args.frames < 2 {
        bail!(
            "--frames {}: the match metrics need at least 2 consecutive images",
            args.frames
        );
    }
    if !args.data().exists() {
        bail!(
            "--data {}: no such file or directory",
            args.data().display()
        );
    }
    let pngs = if args.data().is_dir() {
        png_files(args.data())
    } else {
        Vec::new()
    };
    let mut out = Vec::new();
    if !pngs.is_empty() {
        for (i, p) in pngs.iter().enumerate() {
            match wanted(i, args) {
                None => break,
                Some(false) => continue,
                Some(true) => out.push(Plane::from_png(p, &spec.image.png_normalise())?),
            }
        }
        return Ok(out);
    }
    let channel = spec.image.channel()?;
    let data = DataArgs {
        data: args.data().to_path_buf(),
        meta: args.meta.clone(),
        sets: Vec::new(),
    };
    let mut registry = keylo::registry();
    let (_, mut source) = configs::open_data(&mut registry, &data)?;
    let mut i = 0usize;
    while let Some(frame) = source.next_frame() {
        let frame =
            frame.with_context(|| format!("--data {}: frame {i}", args.data().display()))?;
        match wanted(i, args) {
            None => break,
            Some(false) => {}
            Some(true) => out.push(Plane::from_frame(
                &frame,
                channel,
                &spec.image.normalise_for(channel, &frame.beams.model),
                format!("frame {i}"),
            )),
        }
        i += 1;
    }
    Ok(out)
}

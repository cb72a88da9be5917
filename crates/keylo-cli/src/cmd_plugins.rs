//! `keylo plugins list` and `keylo plugins check FILE`.

use std::fmt::Write;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{Context, Result};
use clap::Subcommand;
use keylo::config::{RawConfig, Trust};
use keylo::plugin::host::{self, Instance, CONFIG_DIRS};
use keylo::plugin::{Plugin, PluginError, SearchPath};

#[derive(Debug, Subcommand)]
pub enum PluginsCommand {
    /// Every plugin found in the search path: name, version, kinds, ABI, file. The folders are
    /// CONFIG's `[plugins] dirs`, then KEYLO_PLUGIN_PATH, then ~/.local/lib/keylo/plugins.
    List {
        /// A config whose `[plugins] dirs` are searched first.
        config: Option<PathBuf>,
        /// Another folder to search first (repeatable).
        #[arg(long = "dir")]
        dirs: Vec<PathBuf>,
        #[command(flatten)]
        trust: crate::arg_groups::TrustArgs,
    },
    /// Load one plugin library, check its table and create + configure (default parameters)
    /// + destroy each of its kinds.
    Check {
        /// The plugin's shared library.
        file: PathBuf,
    },
}

pub fn run(cmd: PluginsCommand) -> Result<ExitCode> {
    match cmd {
        PluginsCommand::List {
            config,
            dirs,
            trust,
        } => list(config.as_deref(), &dirs, trust.trust()),
        PluginsCommand::Check { file } => check(&file),
    }
}

/// Where a folder given with `--dir` came from.
const DIR_FLAG: &str = "--dir";

fn list(config: Option<&Path>, extra: &[PathBuf], trust: Trust) -> Result<ExitCode> {
    let mut config_dirs = Vec::new();
    if let Some(path) = config {
        let raw = RawConfig::from_file(path)?;
        config_dirs = raw.plugins()?.dir_paths(&raw.base_dir);
    }
    let mut search = SearchPath::new(&config_dirs);
    search
        .dirs
        .splice(0..0, extra.iter().map(|d| (d.clone(), DIR_FLAG)));
    let mut rows = Vec::new();
    let mut broken = Vec::new();
    let mut untrusted = Vec::new();
    for (lib, from) in search.libraries_with_origin() {
        // A config's own folders: listed, not loaded, unless the config is trusted.
        if from == CONFIG_DIRS && trust == Trust::Installed {
            untrusted.push(lib.display().to_string());
            continue;
        }
        match Plugin::open(&lib) {
            Ok(p) => rows.push(p),
            // Other shared libraries may share a folder with plugins.
            Err(PluginError::MissingEntry { .. }) => {}
            Err(e) => broken.push(e.to_string()),
        }
    }
    print!("{}", table(&rows));
    let searched: Vec<String> = search
        .dirs
        .iter()
        .map(|(d, from)| format!("{} ({from})", d.display()))
        .collect();
    println!("searched: {}", searched.join("; "));
    for b in &broken {
        eprintln!("warning: {b}");
    }
    if !untrusted.is_empty() {
        eprintln!(
            "note: not loaded, being in the config's own [plugins] dirs (--trust-plugins \
             loads them): {}",
            untrusted.join(", ")
        );
    }
    Ok(ExitCode::SUCCESS)
}

fn table(plugins: &[std::sync::Arc<Plugin>]) -> String {
    if plugins.is_empty() {
        return "no plugin found\n".into();
    }
    let mut out = String::new();
    let _ = writeln!(
        out,
        "{:<20} {:<10} {:<4} {:<36} PATH",
        "NAME", "VERSION", "ABI", "KINDS"
    );
    for p in plugins {
        let kinds: Vec<String> = p
            .kinds
            .iter()
            .map(|k| k.stage.section().to_string())
            .collect();
        let _ = writeln!(
            out,
            "{:<20} {:<10} {:<4} {:<36} {}",
            format!("plugin:{}", p.name),
            p.version,
            p.abi_version,
            kinds.join(","),
            p.path.display()
        );
    }
    out
}

fn check(file: &Path) -> Result<ExitCode> {
    if !file.is_file() {
        anyhow::bail!("{}: no such file", file.display());
    }
    let plugin = Plugin::open(file)?;
    print!("{}", table(std::slice::from_ref(&plugin)));
    for kind in &plugin.kinds {
        let inst = Instance::new(plugin.clone(), kind.clone(), &toml::Table::new())
            .with_context(|| format!("{} with default parameters", kind.stage.section()))?;
        drop(inst);
        println!(
            "ok: {} `{}`: {} (created, configured with defaults, destroyed)",
            kind.stage.section(),
            format_args!("{}{}", host::KIND_PREFIX, plugin.name),
            kind.summary
        );
    }
    Ok(ExitCode::SUCCESS)
}

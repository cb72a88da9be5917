//! Opening a plugin library and checking its descriptor table.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use libloading::Library;

use crate::abi::*;
use crate::convert::c_str;
use crate::PluginError;

/// The ABI versions this keylo accepts: every version up to its own (a newer version only
/// extends what keylo lends, see [`crate::abi`]).
pub const SUPPORTED_ABI: std::ops::RangeInclusive<u32> = 1..=KEYLO_PLUGIN_ABI_VERSION;

/// The accepted ABI versions for an error message: `1, 2`.
pub fn supported_abi_list() -> String {
    let v: Vec<String> = SUPPORTED_ABI.map(|v| v.to_string()).collect();
    v.join(", ")
}

/// The entry symbol's name.
pub const ENTRY_SYMBOL: &str = "keylo_plugin_entry";

/// A stage a plugin kind implements.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Stage {
    Detector,
    Descriptor,
    Downsampler,
    Registrar,
}

impl Stage {
    /// The stage of an ABI `KEYLO_STAGE_*` value.
    pub fn from_abi(v: u32) -> Option<Self> {
        Some(match v {
            KEYLO_STAGE_DETECTOR => Self::Detector,
            KEYLO_STAGE_DESCRIPTOR => Self::Descriptor,
            KEYLO_STAGE_DOWNSAMPLER => Self::Downsampler,
            KEYLO_STAGE_REGISTRAR => Self::Registrar,
            _ => return None,
        })
    }

    /// The config section of the stage.
    pub fn section(self) -> &'static str {
        match self {
            Self::Detector => "detector",
            Self::Descriptor => "descriptor",
            Self::Downsampler => "downsampler",
            Self::Registrar => "registrar",
        }
    }
}

/// The function pointers of one kind, checked non-NULL where required.
#[derive(Debug, Clone, Copy)]
pub struct KindFns {
    pub create: unsafe extern "C" fn(*mut KeyloError) -> *mut std::ffi::c_void,
    pub configure: unsafe extern "C" fn(
        *mut std::ffi::c_void,
        *const std::ffi::c_char,
        *mut KeyloError,
    ) -> i32,
    pub destroy: unsafe extern "C" fn(*mut std::ffi::c_void),
    pub detect: KeyloDetectFn,
    pub describe: KeyloDescribeFn,
    pub downsample: KeyloDownsampleFn,
    pub register_cloud: KeyloRegisterFn,
    pub set_motion_prior: KeyloMatrixFn,
    pub set_pose: KeyloMatrixFn,
    pub reset: KeyloResetFn,
    pub local_map: KeyloLocalMapFn,
}

/// [`KeyloPluginKind`] as ABI versions 1 and 2 lay it out: without the SLAM hooks. A plugin of
/// those versions fills an array of these, so it is read with this element size.
#[repr(C)]
#[derive(Clone, Copy)]
pub struct KindV2 {
    pub stage: u32,
    pub summary: *const std::ffi::c_char,
    pub create: KeyloCreateFn,
    pub configure: KeyloConfigureFn,
    pub destroy: KeyloDestroyFn,
    pub detect: KeyloDetectFn,
    pub describe: KeyloDescribeFn,
    pub downsample: KeyloDownsampleFn,
    pub register_cloud: KeyloRegisterFn,
}

impl From<&KeyloPluginKind> for KindV2 {
    /// The version-2 prefix of a kind (its hooks dropped).
    fn from(k: &KeyloPluginKind) -> Self {
        Self {
            stage: k.stage,
            summary: k.summary,
            create: k.create,
            configure: k.configure,
            destroy: k.destroy,
            detect: k.detect,
            describe: k.describe,
            downsample: k.downsample,
            register_cloud: k.register_cloud,
        }
    }
}

impl From<KindV2> for KeyloPluginKind {
    fn from(k: KindV2) -> Self {
        Self {
            stage: k.stage,
            summary: k.summary,
            create: k.create,
            configure: k.configure,
            destroy: k.destroy,
            detect: k.detect,
            describe: k.describe,
            downsample: k.downsample,
            register_cloud: k.register_cloud,
            set_motion_prior: None,
            set_pose: None,
            reset: None,
            local_map: None,
        }
    }
}

/// One kind a plugin offers.
#[derive(Debug, Clone)]
pub struct Kind {
    pub stage: Stage,
    pub summary: String,
    pub fns: KindFns,
}

/// A loaded, checked plugin. Its library is never unloaded.
#[derive(Debug)]
pub struct Plugin {
    pub name: String,
    pub version: String,
    pub abi_version: u32,
    pub path: PathBuf,
    pub kinds: Vec<Kind>,
}

impl Plugin {
    /// The kind offered for `stage`.
    pub fn kind(&self, stage: Stage) -> Option<&Kind> {
        self.kinds.iter().find(|k| k.stage == stage)
    }

    /// The sections of the offered kinds, joined by ", ".
    pub fn offered(&self) -> String {
        let v: Vec<&str> = self.kinds.iter().map(|k| k.stage.section()).collect();
        if v.is_empty() {
            "nothing".into()
        } else {
            v.join(", ")
        }
    }

    /// Opens the library at `path` and checks its table.
    pub fn open(path: &Path) -> Result<Arc<Self>, PluginError> {
        // Before the library's code can run (its initialisers run when it is opened).
        tracing::info!("loading plugin library {}", path.display());
        // SAFETY: loading a library runs its initialisers; a plugin is trusted code the
        // user asked for by name or path.
        let lib = unsafe { Library::new(path) }.map_err(|e| PluginError::Open {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        // Never unloaded: function pointers into it live in factories and instances.
        let lib: &'static Library = Box::leak(Box::new(lib));
        // SAFETY: the symbol is declared as `KeyloPluginEntryFn` by the ABI.
        let entry =
            unsafe { lib.get::<KeyloPluginEntryFn>(ENTRY_SYMBOL.as_bytes()) }.map_err(|_| {
                PluginError::MissingEntry {
                    path: path.to_path_buf(),
                    symbol: ENTRY_SYMBOL.into(),
                }
            })?;
        // SAFETY: the entry function takes no argument and returns the table pointer.
        let info = unsafe { entry() };
        // SAFETY: a non-NULL table stays valid while the library is loaded (forever).
        unsafe { Self::from_info(info, path) }.map(Arc::new)
    }

    /// Checks the table `info` (as returned by an entry function) found in `path`.
    ///
    /// # Safety
    /// `info` must be NULL or point to a table that starts with a `u32` ABI version and, when
    /// that version is supported, is a [`KeyloPluginInfo`] valid for the life of the process.
    pub unsafe fn from_info(
        info: *const KeyloPluginInfo,
        path: &Path,
    ) -> Result<Self, PluginError> {
        let invalid = |message: String| PluginError::Invalid {
            path: path.to_path_buf(),
            message,
        };
        if info.is_null() {
            return Err(invalid(format!("{ENTRY_SYMBOL}() returned NULL")));
        }
        // Only the first field is read before the version is known to be supported.
        // SAFETY: every ABI version starts with the `u32` version (caller's contract).
        let found = unsafe { info.cast::<u32>().read() };
        if !SUPPORTED_ABI.contains(&found) {
            return Err(PluginError::AbiMismatch {
                path: path.to_path_buf(),
                found,
                supported: supported_abi_list(),
            });
        }
        // SAFETY: a supported version, and `KeyloPluginInfo` is the same in all of them.
        let info = unsafe { &*info };
        // SAFETY: the strings are NULL or NUL-terminated per the ABI.
        let name = unsafe { c_str(info.name, "name") }.map_err(|e| invalid(e.to_string()))?;
        if name.is_empty() || name.contains(|c: char| c.is_whitespace() || c == ':') {
            return Err(invalid(format!(
                "name `{name}` must be non-empty, without spaces or `:`"
            )));
        }
        // SAFETY: as above.
        let version =
            unsafe { c_str(info.version, "version") }.map_err(|e| invalid(e.to_string()))?;
        if info.kind_count > 0 && info.kinds.is_null() {
            return Err(invalid(format!(
                "kinds is NULL with kind_count {}",
                info.kind_count
            )));
        }
        let raw: Vec<KeyloPluginKind> = if info.kind_count == 0 {
            Vec::new()
        } else if found <= 2 {
            // SAFETY: non-NULL, `kind_count` entries of the version-1/2 layout per the ABI.
            unsafe { std::slice::from_raw_parts(info.kinds.cast::<KindV2>(), info.kind_count) }
                .iter()
                .map(|&k| k.into())
                .collect()
        } else {
            // SAFETY: non-NULL, `kind_count` entries per the ABI.
            unsafe { std::slice::from_raw_parts(info.kinds, info.kind_count) }.to_vec()
        };
        let mut kinds: Vec<Kind> = Vec::new();
        for (i, k) in raw.iter().enumerate() {
            // SAFETY: `k` is a kind of a valid table.
            let kind = unsafe { check_kind(k) }.map_err(|m| invalid(format!("kind {i}: {m}")))?;
            if kinds.iter().any(|o| o.stage == kind.stage) {
                return Err(invalid(format!(
                    "kind {i}: a second {} (at most one kind per stage)",
                    kind.stage.section()
                )));
            }
            kinds.push(kind);
        }
        if kinds.is_empty() {
            return Err(invalid("offers no kind (kind_count is 0)".into()));
        }
        Ok(Self {
            name,
            version,
            abi_version: found,
            path: path.to_path_buf(),
            kinds,
        })
    }
}

/// # Safety
/// `k.summary` must be NULL or NUL-terminated.
unsafe fn check_kind(k: &KeyloPluginKind) -> Result<Kind, String> {
    let stage = Stage::from_abi(k.stage).ok_or_else(|| {
        format!(
            "stage {} is not one of KEYLO_STAGE_DETECTOR..KEYLO_STAGE_REGISTRAR (1..4)",
            k.stage
        )
    })?;
    // SAFETY: forwarded from the caller.
    let summary = unsafe { c_str(k.summary, "summary") }.unwrap_or_default();
    let need = |what: &str| format!("{} kind without a `{what}` function", stage.section());
    let (Some(create), Some(configure), Some(destroy)) = (k.create, k.configure, k.destroy) else {
        return Err(need("create/configure/destroy"));
    };
    let has_run = match stage {
        Stage::Detector => k.detect.is_some(),
        Stage::Descriptor => k.describe.is_some(),
        Stage::Downsampler => k.downsample.is_some(),
        Stage::Registrar => k.register_cloud.is_some(),
    };
    if !has_run {
        let run = ["detect", "describe", "downsample", "register_cloud"][stage as usize];
        return Err(need(run));
    }
    Ok(Kind {
        stage,
        summary,
        fns: KindFns {
            create,
            configure,
            destroy,
            detect: k.detect,
            describe: k.describe,
            downsample: k.downsample,
            register_cloud: k.register_cloud,
            set_motion_prior: k.set_motion_prior,
            set_pose: k.set_pose,
            reset: k.reset,
            local_map: k.local_map,
        },
    })
}

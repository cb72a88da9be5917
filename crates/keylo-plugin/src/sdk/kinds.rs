//! The kind table entry of each stage (used by `export_plugin!`): the shims of `shims.rs`,
//! plus a registrar's SLAM hooks from `hooks.rs`.

use keylo_core::{Descriptor, Detector, Downsampler, Registrar};

use super::hooks;
use super::shims::{common, describe, detect, downsample, register_cloud};
use super::{FromConfig, KindSpec};
use crate::abi::*;

/// The kind of a detector backend `T` (used by `export_plugin!`).
pub fn detector<T: FromConfig + Detector>(summary: &str) -> KindSpec {
    let mut kind = common::<T>(KEYLO_STAGE_DETECTOR);
    kind.detect = Some(detect::<T>);
    KindSpec {
        kind,
        summary: summary.into(),
    }
}

/// The kind of a descriptor backend `T` (used by `export_plugin!`).
pub fn descriptor<T: FromConfig + Descriptor>(summary: &str) -> KindSpec {
    let mut kind = common::<T>(KEYLO_STAGE_DESCRIPTOR);
    kind.describe = Some(describe::<T>);
    KindSpec {
        kind,
        summary: summary.into(),
    }
}

/// The kind of a downsampler backend `T` (used by `export_plugin!`).
pub fn downsampler<T: FromConfig + Downsampler>(summary: &str) -> KindSpec {
    let mut kind = common::<T>(KEYLO_STAGE_DOWNSAMPLER);
    kind.downsample = Some(downsample::<T>);
    KindSpec {
        kind,
        summary: summary.into(),
    }
}

/// The kind of a registrar backend `T` (used by `export_plugin!`).
pub fn registrar<T: FromConfig + Registrar>(summary: &str) -> KindSpec {
    let mut kind = common::<T>(KEYLO_STAGE_REGISTRAR);
    kind.register_cloud = Some(register_cloud::<T>);
    hooks::fill::<T>(&mut kind);
    KindSpec {
        kind,
        summary: summary.into(),
    }
}

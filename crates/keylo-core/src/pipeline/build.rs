//! Building a stage from its config section through the registry's backends.

use crate::config::{PipelineConfig, StageConfig};
use crate::registry::Backends;
use crate::stages::ImageSource;
use crate::{BuildContext, CoreError, Registry};

pub(super) fn build_stage<T: ?Sized + 'static>(
    backends: &Backends<T>,
    section: &str,
    stage: &StageConfig,
    ctx: &BuildContext,
) -> Result<Box<T>, CoreError> {
    let factory = backends.get(&stage.kind).ok_or_else(|| {
        CoreError::stage(
            section,
            format!("backend `{}` is not registered", stage.kind),
        )
    })?;
    factory.build(&stage.params, ctx)
}

pub(super) fn build_optional<T: ?Sized + 'static>(
    backends: &Backends<T>,
    section: &str,
    stage: &StageConfig,
    ctx: &BuildContext,
) -> Result<Option<Box<T>>, CoreError> {
    if stage.is_none() {
        return Ok(None);
    }
    build_stage(backends, section, stage, ctx).map(Some)
}

/// Builds only the source of a resolved config (for tools that read data without running
/// odometry: `keylo info`, `keylo convert`).
pub fn build_source(
    config: &PipelineConfig,
    registry: &Registry,
) -> Result<Box<dyn ImageSource>, CoreError> {
    let ctx = BuildContext {
        base_dir: config.base_dir.clone(),
        trust: config.trust,
    };
    build_stage(&registry.sources, "source", &config.source, &ctx)
}

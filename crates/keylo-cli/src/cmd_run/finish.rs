//! The end of `keylo run`: the pose graph written, the closing messages and the exit status.

use std::path::Path;
use std::process::ExitCode;

use anyhow::Result;
use keylo::map::PoseGraph;

use crate::degenerate_out::DegenerateLog;
use crate::report::Summary;
use crate::{EXIT_DEGENERATE, EXIT_FRAME_FAILED, EXIT_INTERRUPTED};

/// `pose_graph.g2o` in `out`, with a warning when some frames had no covariance estimate.
pub(super) fn write_pose_graph(graph: &PoseGraph, out: &Path) -> Result<()> {
    graph.write(&out.join("pose_graph.g2o"))?;
    if graph.fallbacks > 0 {
        tracing::warn!(
            "pose_graph.g2o: {} frame(s) had no covariance estimate; their edges use the \
             fallback variance {}",
            graph.fallbacks,
            keylo::map::FALLBACK_VARIANCE
        );
    }
    Ok(())
}

/// Says how the run ended, when not plainly, and gives its exit status: a recording that
/// could not be closed (`view_error`) is said first and exits 1 unless the run itself has a
/// more telling status (a failed or `interrupted` frame, every frame degenerate).
pub(super) fn exit_status(
    summary: &Summary,
    (interrupted, degenerate): (bool, &DegenerateLog),
    view_error: Option<&anyhow::Error>,
    out: &Path,
) -> ExitCode {
    if let Some(e) = view_error {
        eprintln!(
            "error: {e:#}\n       the run's results are written to {}",
            out.display()
        );
    }
    if let Some(f) = &summary.failed {
        f.say(summary.frames, out);
        let code = if interrupted {
            EXIT_INTERRUPTED
        } else {
            EXIT_FRAME_FAILED
        };
        return ExitCode::from(code);
    }
    if let Some(line) = degenerate.closing(summary.frames) {
        tracing::warn!("{line}");
    }
    if summary.all_degenerate {
        eprintln!(
            "error: no frame of the {} was registered with all six pose directions constrained \
             (every frame after the first degenerate): the trajectory is the motion model's \
             prediction, not odometry (written to {} all the same)",
            summary.frames,
            out.display()
        );
        return ExitCode::from(EXIT_DEGENERATE);
    }
    if view_error.is_some() {
        return ExitCode::FAILURE;
    }
    ExitCode::SUCCESS
}

//! `keylo run`'s frame loop: each frame through the pipeline, its results to every output,
//! and the run's policy on bad, degenerate and interrupted frames.

use std::time::Instant;

use indicatif::ProgressBar;
use keylo::config::{OnBadFrame, OnDegenerate, PipelineConfig};
use keylo::map::{MapBuilder, PoseGraph};
use keylo::{CoreError, Pipeline, Trajectory};

use crate::degeneracy_out::DegeneracyRow;
use crate::degenerate_out::{self, DegenerateLog};
use crate::journal::Journal;
use crate::overlay::Pictures;
use crate::report::{self, Failure, Totals};
use crate::{resources, view_out};

#[derive(Default)]
pub(super) struct RunState {
    pub(super) trajectory: Trajectory,
    pub(super) totals: Totals,
    pub(super) skipped: usize,
    pub(super) failure: Option<Failure>,
    pub(super) interrupted: bool,
    pub(super) degeneracy: Vec<DegeneracyRow>,
    pub(super) degenerate: DegenerateLog,
    /// Index of the first frame registered.
    pub(super) first_frame: Option<u64>,
}

/// Where each frame's results go besides the trajectory.
pub(super) struct Outputs<'a> {
    pub(super) journal: &'a mut Journal,
    pub(super) pictures: Option<&'a mut Pictures>,
    pub(super) map: Option<&'a mut MapBuilder>,
    pub(super) pose_graph: Option<&'a mut PoseGraph>,
    pub(super) view: Option<&'a mut view_out::Session>,
}

pub(super) fn process_all(
    pipeline: &mut Pipeline,
    config: &PipelineConfig,
    progress: &ProgressBar,
    outputs: &mut Outputs,
    st: &mut RunState,
) {
    // Ctrl-C or SIGTERM: the run stops after the current frame and writes what it has.
    crate::interrupt::install("Ctrl-C will not save partial results");
    // Index of the next frame, for messages about a frame the source could not read.
    let mut next = 0u64;
    loop {
        if crate::interrupt::requested() {
            st.failure = Some(Failure {
                frame: next,
                error: "interrupted (Ctrl-C or SIGTERM)".into(),
            });
            st.interrupted = true;
            break;
        }
        let frame = match pipeline.source.next_frame() {
            None => break,
            Some(Ok(f)) => f,
            Some(Err(e)) => {
                st.failure = Some(Failure {
                    frame: next,
                    error: e.to_string(),
                });
                break;
            }
        };
        next = frame.index + 1;
        let pictured = outputs
            .pictures
            .as_ref()
            .is_some_and(|p| p.wants(frame.index));
        let mapped = (outputs.map.as_ref()).is_some_and(|m| m.config().keyframe_features);
        let viewed = outputs.view.is_some();
        let t = Instant::now();
        let result = pipeline
            .odometry
            .process_guarded(&frame, pictured || mapped || viewed);
        let seconds = t.elapsed().as_secs_f64();
        st.totals.odometry_seconds += seconds;
        progress.inc(1);
        match result {
            Ok((r, features)) => {
                if let Some(why) = r.degenerate {
                    let name = frame_name(pipeline, frame.index);
                    st.degenerate
                        .record(frame.index, &name, why, r.cloud_points);
                    if config.output.on_degenerate == OnDegenerate::Error {
                        st.failure = Some(Failure {
                            frame: frame.index,
                            error: degenerate_out::stop_message(&why),
                        });
                        break;
                    }
                }
                st.first_frame.get_or_insert(frame.index);
                st.trajectory.push(r.stamp, r.pose);
                st.totals.add(&r);
                if let Some(fit) = r.fit.filter(|f| !f.tracking) {
                    tracing::warn!(
                        "{}: not tracking in the map (fitness {:.2}); its pose is not to be \
                         trusted",
                        frame_name(pipeline, frame.index),
                        fit.fitness
                    );
                }
                let row = report::FrameRow {
                    frame: frame.index,
                    stamp: r.stamp,
                    keypoints: r.keypoints,
                    cloud_points: r.cloud_points,
                    registered_points: r.registered_points,
                    map_points: r.map_points,
                    odometry_ms: 1e3 * seconds,
                    rss_mb: resources::rss_mb(),
                    degenerate: r.degenerate.map(|d| d.label()),
                };
                if let Some(d) = r.degeneracy.clone() {
                    tracing::debug!(
                        "frame {}: condition {:.3e}, {} weak direction(s), weakest {:?}",
                        frame.index,
                        d.condition,
                        d.weak,
                        d.eigenvectors[0]
                    );
                    st.degeneracy.push(DegeneracyRow {
                        frame: frame.index,
                        degeneracy: d,
                    });
                }
                let recorded = outputs
                    .journal
                    .record(r.stamp, &r.pose, &row)
                    .and_then(|()| match (outputs.pictures.as_deref_mut(), &features) {
                        (Some(p), Some(f)) if pictured => p.record(&pipeline.odometry, &frame, f),
                        _ => Ok(()),
                    })
                    .map(|()| {
                        if let Some(g) = outputs.pose_graph.as_deref_mut() {
                            g.add(&r);
                        }
                    })
                    .and_then(|()| match outputs.map.as_deref_mut() {
                        Some(m) => m
                            .add(&frame, &r, features.as_ref())
                            .map(|_| ())
                            .map_err(Into::into),
                        None => Ok(()),
                    });
                if let Some(v) = outputs.view.as_deref_mut() {
                    v.frame(&pipeline.odometry, &frame, &r, features.as_ref(), seconds);
                }
                if let Err(e) = recorded {
                    st.failure = Some(Failure {
                        frame: frame.index,
                        error: crate::error_chain(&e),
                    });
                    break;
                }
            }
            Err(e @ CoreError::BadFrame { .. })
                if config.output.on_bad_frame == OnBadFrame::Skip =>
            {
                tracing::warn!("skipping {}: {e}", frame_name(pipeline, frame.index));
                st.skipped += 1;
            }
            Err(e) => {
                let error = match pipeline.source.frame_origin(frame.index) {
                    Some(file) => format!("{e} (file {file})"),
                    None => e.to_string(),
                };
                st.failure = Some(Failure {
                    frame: frame.index,
                    error,
                });
                break;
            }
        }
    }
}

/// "frame N" and, when the source reads one file per frame, "(FILE)".
fn frame_name(pipeline: &Pipeline, index: u64) -> String {
    match pipeline.source.frame_origin(index) {
        Some(file) => format!("frame {index} ({file})"),
        None => format!("frame {index}"),
    }
}

//! One table row per run and the criterion it is judged by.

use serde::Serialize;

/// When a run counts as diverged (printed under every table).
pub type Criterion = keylo::eval::divergence::Criterion;

/// The criterion in words, with the flags that set it.
pub fn describe(c: &Criterion) -> String {
    format!(
        "a run is **diverged** when its largest aligned translation error (APE, SE(3) \
         Umeyama alignment as `evo_ape -a`) exceeds {} m (`--diverge-ape`), when one step \
         between consecutive estimated poses exceeds {} m (`--diverge-step`), or when a \
         pose is not finite; **failed** when `keylo run` stopped before the end of the \
         data (its figures cover the frames before the failure); accuracy of a diverged \
         or failed run is shown as N/A in the paper-shaped tables; APE is over the poses \
         paired with ground truth within {} s (`--t-max-diff`, evo's `--t_max_diff`); \
         where fewer than 90 % of a run's poses pair, its reason and a warning under the \
         tables say so, with the likely cause (`--gt-time-scale`, `--gt-time-offset` fix a \
         reference on another clock)",
        c.max_ape_m, c.max_step_m, c.t_max_diff_s
    )
}

/// One run's figures. Field order is the column order of the CSV and Markdown tables.
#[derive(Debug, Clone, Default, Serialize)]
pub struct Row {
    pub data: String,
    pub variant: String,
    pub config: String,
    pub registrar: String,
    pub downsampler: String,
    /// `ok`, `diverged` or `failed`.
    pub verdict: String,
    /// Why the verdict (the criterion that fired, or the error).
    pub reason: String,
    /// The run was found finished and not run again.
    pub resumed: bool,
    pub frames: Option<usize>,
    /// Frames whose registration could not constrain the pose (summary.json's
    /// `frames_degenerate`: too few points, a direction without information).
    pub degenerate_frames: Option<usize>,
    /// Poses paired with ground truth (APE is over these).
    pub associated_poses: Option<usize>,
    pub trans_mean_m: Option<f64>,
    pub trans_rmse_m: Option<f64>,
    pub trans_max_m: Option<f64>,
    pub rot_mean_deg: Option<f64>,
    pub rot_rmse_deg: Option<f64>,
    pub rpe_trans_m: Option<f64>,
    pub rpe_rot_deg: Option<f64>,
    pub cpu_percent: Option<f64>,
    pub peak_rss_mb: Option<f64>,
    /// Playback speed of a `--realtime` run (1: the sensor's rate; `None`: un-paced); said
    /// once above compare.md's tables, not a column.
    #[serde(skip)]
    pub playback_speed: Option<f64>,
    /// Frames of a `--realtime` run released later than their time (odometry fell behind).
    pub frames_late: Option<usize>,
    /// Mean points the downsampler handed to the registrar (the paper's "Avg Pts").
    pub mean_points: Option<f64>,
    /// Mean points the registrar aligned after its own voxel filter.
    pub mean_registered_points: Option<f64>,
    /// Frames per second of the odometry stages, un-throttled (source reading excluded).
    pub odometry_hz: Option<f64>,
    /// Odometry rate relative to the raw-cloud (`passthrough`) run of the same data and
    /// registrar kind, when the comparison has one.
    pub rate_vs_raw: Option<f64>,
    /// Estimated poses paired with ground truth / estimated poses, e.g. `16/154`.
    pub associated: Option<String>,
    /// The ground truth's name (`--gt-label`, else its file name).
    pub reference: Option<String>,
    /// The association in full (JSON only): counts, both time ranges, the likely cause.
    pub association: Option<keylo::eval::coverage::Coverage>,
    /// The warning when fewer than 90 % of the poses were paired (JSON only).
    pub association_warning: Option<String>,
}

//! Which levels of OpenCV's AKAZE scale space can hold a keypoint on an image of a given size,
//! and the smallest AKAZE (octaves, sublevels) that computes exactly those levels.
//!
//! OpenCV builds `n_octaves × n_octave_layers` levels (fewer on small images: an octave below
//! 80 columns or 40 rows is not built) and searches level *j* for keypoints only
//! `border_j = round(smax · sigma_size_j) + 1` pixels from the edges (`smax` = 10√2 for the MLDB
//! descriptors, 12√2 for KAZE's; `sigma_size_j = round(1.6 · 2^(j / layers + octave) · 1.5 /
//! 2^octave)`), so that a descriptor never samples outside the image. On a 1024×64 LiDAR image
//! level 0's border is 29 rows and every later level's at least 43, more than half the height:
//! only level 0 can yield a keypoint. Levels after the last one that can are pure cost: they
//! never hold a keypoint, the filters between neighbouring levels only remove keypoints a
//! level actually holds, and levels are built from earlier levels only. Level 0 is the input
//! smoothed at σ = 1.6 whatever the number of levels, so when it is the only one that can
//! hold keypoints, a one-level AKAZE (1 octave, 1 sublevel) gives the same keypoints and
//! descriptors; otherwise octaves after the last useful one are dropped and the sublevels
//! kept (the levels' scales depend on the sublevel count). `tests/akaze_levels.rs` checks the
//! equality on real and simulated images.

/// OpenCV's AKAZE defaults that `AKAZE::create` does not expose.
const SIGMA_OFFSET: f32 = 1.6;
const DERIVATIVE_FACTOR: f32 = 1.5;
/// OpenCV builds no octave (after the first) smaller than this.
const MIN_OCTAVE_COLS: usize = 80;
const MIN_OCTAVE_ROWS: usize = 40;

/// One level of the scale space: its octave, its size and its search border.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) struct Level {
    pub octave: i32,
    pub rows: usize,
    pub cols: usize,
    pub border: usize,
}

impl Level {
    /// Whether OpenCV's extremum search visits any pixel of this level.
    pub fn searchable(&self) -> bool {
        self.border + 1 < self.rows && 2 * self.border < self.rows && 2 * self.border < self.cols
    }
}

/// Round half to even, as OpenCV's `cvRound` on a float (the SSE conversion).
fn cv_round(v: f32) -> usize {
    v.round_ties_even().max(0.0) as usize
}

/// The levels OpenCV's AKAZE builds on a `rows × cols` image; `kaze_descriptor`: the
/// descriptor is KAZE's (a wider sampling area than MLDB's).
pub(crate) fn levels(
    rows: usize,
    cols: usize,
    n_octaves: i32,
    n_layers: i32,
    kaze_descriptor: bool,
) -> Vec<Level> {
    let smax = if kaze_descriptor { 12.0f32 } else { 10.0f32 } * 2.0f32.sqrt();
    let mut out = Vec::new();
    for octave in 0..n_octaves.max(0) {
        let power = 1i64 << octave.min(30);
        let rfactor = 1.0f32 / power as f32;
        let level_rows = (rows as f32 * rfactor) as usize;
        let level_cols = (cols as f32 * rfactor) as usize;
        if octave != 0 && (level_cols < MIN_OCTAVE_COLS || level_rows < MIN_OCTAVE_ROWS) {
            break;
        }
        for j in 0..n_layers.max(0) {
            let esigma = SIGMA_OFFSET * 2.0f32.powf(j as f32 / n_layers as f32 + octave as f32);
            let sigma_size = cv_round(esigma * DERIVATIVE_FACTOR / power as f32);
            out.push(Level {
                octave,
                rows: level_rows,
                cols: level_cols,
                border: cv_round(smax * sigma_size as f32) + 1,
            });
        }
    }
    out
}

/// The (octaves, sublevels) of an AKAZE equal to `(n_octaves, n_layers)` on a `rows × cols`
/// image that builds no level after the last searchable one, and how many levels it builds.
pub(crate) fn pruned(
    rows: usize,
    cols: usize,
    n_octaves: i32,
    n_layers: i32,
    kaze_descriptor: bool,
) -> (i32, i32, usize) {
    let all = levels(rows, cols, n_octaves, n_layers, kaze_descriptor);
    match all.iter().rposition(Level::searchable) {
        // No level can hold a keypoint: level 0 alone finds none either.
        None | Some(0) => (1, 1, 1),
        Some(last) => {
            let octaves = all[last].octave + 1;
            let built = all.iter().filter(|l| l.octave < octaves).count();
            (octaves, n_layers, built)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_borders_of_a_lidar_image_leave_level_zero_only() {
        let l = levels(64, 1024, 4, 4, false);
        // The 32-row octave is below OpenCV's 40-row minimum: one octave of four sublevels.
        assert_eq!(l.len(), 4);
        let borders: Vec<usize> = l.iter().map(|l| l.border).collect();
        assert_eq!(borders, vec![29, 43, 43, 58]);
        assert_eq!(
            l.iter().map(Level::searchable).collect::<Vec<_>>(),
            vec![true, false, false, false]
        );
        assert_eq!(pruned(64, 1024, 4, 4, false), (1, 1, 1));
    }

    #[test]
    fn taller_images_keep_the_sublevels_up_to_the_last_useful_octave() {
        // 2048×128: octave 1 (64 rows) can still hold keypoints at its first sublevel.
        assert_eq!(pruned(128, 2048, 4, 4, false), (2, 4, 8));
        // A camera-sized image keeps everything OpenCV builds.
        assert_eq!(pruned(480, 640, 4, 4, false), (4, 4, 16));
        // KAZE's descriptor samples wider: level 0's border is 35, still inside 64 rows.
        assert_eq!(levels(64, 1024, 4, 4, true)[0].border, 35);
        assert_eq!(pruned(64, 1024, 4, 4, true), (1, 1, 1));
    }

    #[test]
    fn an_image_too_small_for_any_keypoint_builds_one_level() {
        assert_eq!(pruned(32, 1024, 4, 4, false), (1, 1, 1));
        assert!(!levels(32, 1024, 4, 4, false)[0].searchable());
    }
}

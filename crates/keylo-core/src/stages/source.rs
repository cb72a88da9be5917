use crate::{CoreError, LidarFrame, Trajectory};

/// What a source knows about itself before reading.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SourceInfo {
    /// Human-readable description (e.g. the path or the simulated scene).
    pub description: String,
    /// Number of frames, when known in advance.
    pub frames: Option<usize>,
}

/// Yields organised [`LidarFrame`]s, one per sensor revolution.
///
/// Owns: the file handles or simulator state and the decoding of its format. The frames it
/// yields are owned by the caller. Formats stay inside the source: no other stage sees a file.
pub trait ImageSource: Send {
    /// Description and length hint.
    fn info(&self) -> SourceInfo;
    /// The next frame, `None` at the end; an `Err` names the file and the frame that failed.
    fn next_frame(&mut self) -> Option<Result<LidarFrame, CoreError>>;
    /// What the data holds beyond the frames, as `(label, value)` lines for `keylo info`:
    /// sensor, firmware, profile, topics, fields, … Empty by default.
    fn details(&self) -> Vec<(String, String)> {
        Vec::new()
    }
    /// Told by the pipeline whether any stage reads the frames' image grid. An unorganised
    /// source may then skip projecting its points (the frame keeps every point in `scan` and
    /// has an empty `0 × 0` grid); by default, and for organised sources, this does nothing.
    fn set_grid_needed(&mut self, needed: bool) {
        let _ = needed;
    }
    /// Where frame `index` came from (its file), for messages about that frame; `None` when
    /// the source has no per-frame file (a pcap, a bag, the simulator).
    fn frame_origin(&self, index: u64) -> Option<String> {
        let _ = index;
        None
    }
    /// Counts the source keeps while reading (`packets_lost`, `datagrams_other_size`, …), for
    /// the run's summary and log. Empty by default.
    fn counters(&self) -> Vec<(String, u64)> {
        Vec::new()
    }
    /// Ground truth shipped with the data (e.g. the simulator's `gt.tum`), if any.
    fn ground_truth(&self) -> Option<crate::Trajectory> {
        None::<Trajectory>
    }
}

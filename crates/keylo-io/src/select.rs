//! Rate control shared by every source: `start`, `stride`, `max_frames`.

/// Why a selection reads no frame.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SelectionError {
    #[error("`source.stride` = 0; expected 1 or more (1 reads every frame)")]
    ZeroStride,
    #[error("`source.start` = {start} but the source holds {total} frames (0..{total})")]
    StartBeyondEnd { start: usize, total: usize },
    /// A file sequence whose stamps do not pair with its files.
    #[error("{stamps} stamps for {files} files")]
    StampCount { stamps: usize, files: usize },
}

/// Which frames of a source are read: frame `start`, then every `stride`-th, at most
/// `max_frames` of them (0 = no limit). Indices count the frames of the source as stored.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameSelection {
    pub start: usize,
    pub stride: usize,
    pub max_frames: usize,
}

impl FrameSelection {
    /// Checks the values; the error names the key.
    pub fn new(start: usize, stride: usize, max_frames: usize) -> Result<Self, SelectionError> {
        if stride == 0 {
            return Err(SelectionError::ZeroStride);
        }
        Ok(Self {
            start,
            stride,
            max_frames,
        })
    }

    /// Whether stored frame `i` is read.
    pub fn wants(&self, i: usize) -> bool {
        i >= self.start && (i - self.start).is_multiple_of(self.stride) && !self.past_end(i)
    }

    /// True once no frame at or after `i` can be wanted (the reader may stop).
    pub fn past_end(&self, i: usize) -> bool {
        let end = self
            .max_frames
            .saturating_mul(self.stride)
            .saturating_add(self.start);
        self.max_frames != 0 && i >= end
    }

    /// The selected indices of a source holding `total` frames; the error says why none is
    /// selected.
    pub fn indices(&self, total: usize) -> Result<Vec<usize>, SelectionError> {
        if self.start >= total {
            return Err(SelectionError::StartBeyondEnd {
                start: self.start,
                total,
            });
        }
        Ok((self.start..total).filter(|&i| self.wants(i)).collect())
    }

    /// How many frames of a source holding `total` are selected, without listing them (a
    /// recording's index may declare any count); the error is that of [`Self::indices`].
    pub fn count(&self, total: usize) -> Result<usize, SelectionError> {
        if self.start >= total {
            return self.indices(total).map(|v| v.len());
        }
        let n = (total - self.start).div_ceil(self.stride);
        Ok(if self.max_frames == 0 {
            n
        } else {
            n.min(self.max_frames)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn start_stride_and_limit() {
        let s = FrameSelection::new(1, 2, 3).unwrap();
        assert_eq!(s.indices(20).unwrap(), vec![1, 3, 5]);
        assert!(s.past_end(7));
        assert!(!s.past_end(6));
        assert_eq!(
            FrameSelection::new(0, 1, 0).unwrap().indices(3).unwrap(),
            vec![0, 1, 2]
        );
        assert!(s
            .indices(1)
            .unwrap_err()
            .to_string()
            .contains("source.start"));
        assert_eq!(
            FrameSelection::new(0, 0, 0).unwrap_err(),
            SelectionError::ZeroStride
        );
    }

    #[test]
    fn counts_match_indices_and_huge_values_neither_overflow_nor_allocate() {
        for (start, stride, max) in [(0, 1, 0), (1, 2, 3), (2, 3, 0), (0, 4, 100)] {
            let s = FrameSelection::new(start, stride, max).unwrap();
            for total in 3..40 {
                assert_eq!(s.count(total).unwrap(), s.indices(total).unwrap().len());
            }
        }
        // A recording's index declaring u64::MAX messages (found by fuzzing: listing them hung).
        let all = FrameSelection::new(0, 1, 0).unwrap();
        assert_eq!(all.count(usize::MAX).unwrap(), usize::MAX);
        let huge = FrameSelection::new(usize::MAX - 1, usize::MAX, usize::MAX).unwrap();
        assert!(!huge.past_end(usize::MAX - 1));
        assert!(huge.wants(usize::MAX - 1));
        assert_eq!(huge.count(usize::MAX).unwrap(), 1);
    }
}

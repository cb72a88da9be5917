//! Rate control shared by every source: `start`, `stride`, `max_frames`.

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
    pub fn new(start: usize, stride: usize, max_frames: usize) -> Result<Self, String> {
        if stride == 0 {
            return Err("`source.stride` = 0; expected 1 or more (1 reads every frame)".into());
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
        self.max_frames != 0 && i >= self.start + self.max_frames * self.stride
    }

    /// The selected indices of a source holding `total` frames; the error says why none is
    /// selected.
    pub fn indices(&self, total: usize) -> Result<Vec<usize>, String> {
        if self.start >= total {
            return Err(format!(
                "`source.start` = {} but the source holds {total} frames (0..{total})",
                self.start
            ));
        }
        Ok((self.start..total).filter(|&i| self.wants(i)).collect())
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
        assert!(s.indices(1).unwrap_err().contains("source.start"));
        assert!(FrameSelection::new(0, 0, 0).unwrap_err().contains("stride"));
    }
}

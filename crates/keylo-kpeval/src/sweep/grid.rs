//! The axes of a sweep (interpolation × width × height) and the cells they span.

use keylo_features::image::Interpolation;

use crate::spec::interpolation_name;
use crate::KpEvalError;

/// The five interpolations, in the paper's order.
pub const INTERPOLATIONS: [Interpolation; 5] = [
    Interpolation::Cubic,
    Interpolation::Lanczos4,
    Interpolation::Area,
    Interpolation::Nearest,
    Interpolation::Linear,
];

/// Sizes from `MIN:MAX:STEP` or a comma-separated list; `what` names the option in errors.
pub fn parse_sizes(spec: &str, what: &str) -> Result<Vec<usize>, KpEvalError> {
    let bad = |m: String| KpEvalError::setting("sweep", what, format!("`{spec}`: {m}"));
    let num = |s: &str| {
        s.trim()
            .parse::<usize>()
            .ok()
            .filter(|v| *v > 0)
            .ok_or_else(|| bad(format!("`{s}` is not a positive whole number")))
    };
    let out: Vec<usize> = if spec.contains(':') {
        let parts: Vec<&str> = spec.split(':').collect();
        let [lo, hi, step] = parts.as_slice() else {
            return Err(bad("expected MIN:MAX:STEP".into()));
        };
        let (lo, hi, step) = (num(lo)?, num(hi)?, num(step)?);
        if lo > hi {
            return Err(bad("MIN is above MAX".into()));
        }
        (lo..=hi).step_by(step).collect()
    } else {
        spec.split(',').map(num).collect::<Result<_, _>>()?
    };
    if out.is_empty() {
        return Err(bad("no size".into()));
    }
    Ok(out)
}

/// One preprocessing setting.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Cell {
    pub interpolation: Interpolation,
    pub width: usize,
    pub height: usize,
}

impl Cell {
    pub(super) fn key(&self) -> (String, usize, usize) {
        (
            interpolation_name(self.interpolation),
            self.width,
            self.height,
        )
    }
}

/// The axes of a sweep.
#[derive(Debug, Clone)]
pub struct SweepGrid {
    pub interpolations: Vec<Interpolation>,
    pub widths: Vec<usize>,
    pub heights: Vec<usize>,
}

impl Default for SweepGrid {
    /// The paper's grid: 5 interpolations × widths 512–4096 step 128 × heights 32–256 step 32.
    fn default() -> Self {
        Self {
            interpolations: INTERPOLATIONS.to_vec(),
            widths: (512..=4096).step_by(128).collect(),
            heights: (32..=256).step_by(32).collect(),
        }
    }
}

impl SweepGrid {
    /// Every cell, interpolation-major as in Algorithm 1.
    pub fn cells(&self) -> Vec<Cell> {
        let mut out = Vec::new();
        for &interpolation in &self.interpolations {
            for &width in &self.widths {
                for &height in &self.heights {
                    out.push(Cell {
                        interpolation,
                        width,
                        height,
                    });
                }
            }
        }
        out
    }
}

//! Upstream's adaptive correspondence threshold: the deviation of the constant-velocity
//! prediction from the registration result, accumulated over frames that moved enough.

use nalgebra::Isometry3;

/// Adaptive threshold σ = sqrt(model_sse / num_samples).
#[derive(Debug, Clone)]
pub struct AdaptiveThreshold {
    min_motion: f64,
    max_range: f64,
    model_sse: f64,
    samples: usize,
}

impl AdaptiveThreshold {
    /// Starts from `initial_threshold` (one sample).
    pub fn new(initial_threshold: f64, min_motion: f64, max_range: f64) -> Self {
        Self {
            min_motion,
            max_range,
            model_sse: initial_threshold * initial_threshold,
            samples: 1,
        }
    }

    /// The current σ.
    pub fn threshold(&self) -> f64 {
        (self.model_sse / self.samples as f64).sqrt()
    }

    /// Adds the deviation between prediction and result when it exceeds the motion gate.
    pub fn update(&mut self, deviation: &Isometry3<f64>) {
        let theta = deviation.rotation.angle();
        let error =
            deviation.translation.vector.norm() + 2.0 * self.max_range * (theta / 2.0).sin();
        if error > self.min_motion {
            self.model_sse += error * error;
            self.samples += 1;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn small_motions_do_not_count() {
        let mut t = AdaptiveThreshold::new(2.0, 0.1, 100.0);
        t.update(&Isometry3::translation(0.05, 0.0, 0.0));
        assert!((t.threshold() - 2.0).abs() < 1e-12);
        t.update(&Isometry3::translation(0.5, 0.0, 0.0));
        assert!((t.threshold() - ((4.0 + 0.25) / 2.0f64).sqrt()).abs() < 1e-12);
    }
}

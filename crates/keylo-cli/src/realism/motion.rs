//! The simulated motion matched to a real stretch's: the lab's walk, at full speed from the
//! first frame, its speed (and sway) scaled until the median horizontal shift between
//! consecutive signal images is the real one's.

use anyhow::Result;
use keylo::sim::{SimConfig, Simulator};
use keylo::Channel;

use super::{median_shift, sim_planes};

/// Rounds of scaling: the shift grows about in proportion to the speed, so two or three
/// bring it within a few per cent.
const ROUNDS: usize = 3;

/// Bounds of the speed scale searched.
const SCALES: (f64, f64) = (0.005, 10.0);

/// The motion found.
#[derive(Debug, Clone)]
pub struct Motion {
    /// The simulator's parameters for the moving half.
    pub config: SimConfig,
    /// Median horizontal shift of the real stretch, pixels between consecutive images.
    pub real_shift: f64,
    /// The same of the simulated sequence of `config`'s first layout.
    pub sim_shift: f64,
}

/// `config` moving as the real stretch whose median shift is `real_shift`: `speed_scale`
/// and `sway_scale` scaled together, `start_ramp_s = 0`, measured on `config`'s own layout.
pub fn matched(config: &SimConfig, real_shift: f64, quiet: bool) -> Result<Motion> {
    let mut scale = 1.0f64;
    let mut moving = config.clone();
    let mut sim_shift = 0.0;
    for round in 0..ROUNDS {
        moving = SimConfig {
            speed_scale: scale,
            sway_scale: scale,
            start_ramp_s: 0.0,
            ..config.clone()
        };
        let sim = Simulator::new(&moving)?;
        let planes = sim_planes(&sim, &[Channel::Signal], None)
            .into_iter()
            .next()
            .map(|(_, p)| p)
            .unwrap_or_default();
        sim_shift = median_shift(&planes)?;
        if !quiet {
            eprintln!(
                "motion, round {}: speed_scale {scale:.4}: {sim_shift:.3} px per frame \
                 (real {real_shift:.3})",
                round + 1
            );
        }
        if sim_shift <= 0.0 || real_shift <= 0.0 {
            break;
        }
        scale = (scale * real_shift / sim_shift).clamp(SCALES.0, SCALES.1);
    }
    Ok(Motion {
        config: moving,
        real_shift,
        sim_shift,
    })
}

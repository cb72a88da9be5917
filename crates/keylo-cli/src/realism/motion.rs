//! The simulated motion matched to a real stretch's. Two numbers describe how consecutive
//! images differ (`keylo::kpeval::motion`): the horizontal shift (how far the view turned) and
//! the change beyond it (parallax as the sensor travels, tilt, noise). Two knobs move the
//! simulated sensor: `speed_scale` (how far it travels per frame, and so the change) and
//! `sway_scale` (how much it turns and tilts about its heading, and so the shift). Each round
//! measures both numbers on the first layouts and scales each knob towards its number.

use anyhow::Result;
use keylo::sim::{SimConfig, Simulator};
use keylo::Channel;

use keylo::kpeval::motion::steps;
use keylo::kpeval::EvalSpec;

use super::{sim_planes, Moved};

/// Rounds of scaling.
const ROUNDS: usize = 8;

/// Layouts each round measures (the first ones; fewer if the protocol has fewer): a single
/// layout's few steps give a noisy median.
const LAYOUTS: u64 = 8;

/// Bounds of both scales.
const SCALES: (f64, f64) = (0.005, 10.0);

/// The most a knob moves in one round (times or divided by).
const MAX_STEP: f64 = 3.0;

/// The first guess: the lab's walk at a fifth of its speed and sway.
const FIRST: (f64, f64) = (0.2, 0.2);

/// The motion found.
#[derive(Debug, Clone)]
pub struct Motion {
    /// The simulator's parameters for the moving half.
    pub config: SimConfig,
    /// How the real stretch moves between consecutive images (median shift and change).
    pub real: Moved,
    /// The same of the simulated sequences of `config`'s first layouts.
    pub sim: Moved,
    /// The simulated sensor held still: the change of its noise alone.
    pub still: Moved,
    /// Layouts measured.
    pub layouts: u64,
}

/// `config` moving as the real stretch that moves as `real`: started `start_lap` of a lap on,
/// at full speed from the first frame (`start_ramp_s = 0`), its `speed_scale` and
/// `sway_scale` found in [`ROUNDS`] rounds, measured on `layouts` layouts (at most
/// [`LAYOUTS`]).
pub fn matched(
    config: &SimConfig,
    real: Moved,
    start_lap: f64,
    layouts: usize,
    quiet: bool,
) -> Result<Motion> {
    let base = SimConfig {
        start_ramp_s: 0.0,
        start_lap,
        ..config.clone()
    };
    let layouts = (layouts as u64).clamp(1, LAYOUTS);
    let still = measure(&scaled(&base, 0.0, 0.0), layouts)?;
    let (mut speed, mut sway) = (Knob::new(FIRST.0), Knob::new(FIRST.1));
    let mut best: Option<(f64, SimConfig, Moved)> = None;
    for round in 0..ROUNDS {
        let moving = scaled(&base, speed.at, sway.at);
        let sim = measure(&moving, layouts)?;
        if !quiet {
            eprintln!(
                "motion, round {}: speed_scale {:.4}, sway_scale {:.4}: shift {:.3} px, \
                 change {:.2} (real {:.3} px, {:.2}; simulated still: change {:.2})",
                round + 1,
                speed.at,
                sway.at,
                sim.shift,
                sim.change,
                real.shift,
                real.change,
                still.change
            );
        }
        let miss = relative(sim.shift, real.shift).abs() + relative(sim.change, real.change).abs();
        if best.as_ref().is_none_or(|b| miss < b.0) {
            best = Some((miss, moving, sim));
        }
        // The change above the still sensor's follows the way travelled; the shift follows the
        // sway (the walk's own turning adds to it, so the sway scale may fall to its bound).
        let (speed_at, sway_at) = (speed.at, sway.at);
        speed.next(
            real.change - still.change,
            sim.change - still.change,
            sway_at,
        );
        sway.next(real.shift, sim.shift, speed_at);
    }
    let (_, config, sim) = best.unwrap_or((0.0, base, still));
    Ok(Motion {
        config,
        real,
        sim,
        still,
        layouts,
    })
}

fn scaled(base: &SimConfig, speed: f64, sway: f64) -> SimConfig {
    SimConfig {
        speed_scale: speed,
        sway_scale: sway,
        ..base.clone()
    }
}

/// One knob's search: scaled by `want / got` (at most [`MAX_STEP`]) until two settings
/// bracket the wanted number, then between them by interpolation in log–log (the shift grows
/// steeply and unevenly with the sway, and plain scaling jumps back and forth past it). Each
/// knob also moves the other's number a little (turning more changes the view more), so a
/// bracket end measured while the other knob stood elsewhere (by more than [`SAME_OTHER`]) is
/// forgotten.
#[derive(Debug, Clone, Copy)]
struct Knob {
    /// The setting measured next.
    at: f64,
    /// The highest setting measured below the wanted number.
    below: Option<Point>,
    /// The lowest setting measured above it.
    above: Option<Point>,
}

/// A knob's setting, what it gave, and where the other knob stood then.
#[derive(Debug, Clone, Copy)]
struct Point {
    at: f64,
    got: f64,
    other: f64,
}

/// The most the other knob may have moved (times or divided by) for a bracket end to stand.
const SAME_OTHER: f64 = 1.15;

impl Knob {
    fn new(at: f64) -> Self {
        Knob {
            at,
            below: None,
            above: None,
        }
    }

    /// Records that [`Knob::at`] gave `got` with the other knob at `other`, and moves it
    /// towards `want`.
    fn next(&mut self, want: f64, got: f64, other: f64) {
        let current = |p: &Point| (other / p.other).ln().abs() <= SAME_OTHER.ln();
        self.below = self.below.filter(current);
        self.above = self.above.filter(current);
        if want > 0.0 && got > 0.0 {
            let point = Some(Point {
                at: self.at,
                got,
                other,
            });
            if got < want {
                if self.below.is_none_or(|p| self.at > p.at) {
                    self.below = point;
                }
            } else if self.above.is_none_or(|p| self.at < p.at) {
                self.above = point;
            }
        }
        self.at = match (self.below, self.above) {
            (Some(lo), Some(hi)) if lo.at < hi.at && lo.got < hi.got => {
                // The share of the way from lo to hi (in logs) kept within its middle 80 %, so
                // that a curved response still narrows the bracket every round.
                let t = ((want.ln() - lo.got.ln()) / (hi.got.ln() - lo.got.ln())).clamp(0.1, 0.9);
                (lo.at.ln() + t * (hi.at.ln() - lo.at.ln())).exp()
            }
            _ => self.at * ratio(want, got),
        }
        .clamp(SCALES.0, SCALES.1);
    }
}

/// `want / got`, limited to [`MAX_STEP`] either way and to a knob's bounds; 1 where either is
/// not positive.
fn ratio(want: f64, got: f64) -> f64 {
    if want <= 0.0 || got <= 0.0 {
        return if want <= 0.0 && got > 0.0 {
            1.0 / MAX_STEP
        } else {
            1.0
        };
    }
    (want / got).clamp(1.0 / MAX_STEP, MAX_STEP)
}

/// `(a − b) / b`, 0 where `b` is 0.
fn relative(a: f64, b: f64) -> f64 {
    if b == 0.0 {
        0.0
    } else {
        (a - b) / b
    }
}

/// Median shift and change of the signal images of `config`'s first `layouts` layouts.
fn measure(config: &SimConfig, layouts: u64) -> Result<Moved> {
    let mut moved = Vec::new();
    for k in 0..layouts {
        let seeded = SimConfig {
            seed: config.seed + k,
            ..config.clone()
        };
        let sim = Simulator::new(&seeded)?;
        let planes = sim_planes(&sim, &[Channel::Signal], None)
            .into_iter()
            .next()
            .map(|(_, p)| p)
            .unwrap_or_default();
        moved.extend(steps(&planes, &EvalSpec::default().image)?);
    }
    Ok(Moved::of(&moved))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_round_moves_a_knob_towards_its_number_at_most_threefold() {
        assert_eq!(ratio(2.0, 1.0), 2.0);
        assert_eq!(ratio(10.0, 1.0), MAX_STEP);
        assert_eq!(ratio(1.0, 10.0), 1.0 / MAX_STEP);
        // The real change at or below the still sensor's noise: slow down.
        assert_eq!(ratio(-0.1, 2.0), 1.0 / MAX_STEP);
        // Nothing measured: stay.
        assert_eq!(ratio(1.0, 0.0), 1.0);
        assert_eq!(relative(1.5, 1.0), 0.5);
        assert_eq!(relative(1.5, 0.0), 0.0);
    }

    #[test]
    fn a_bracketed_knob_converges_on_a_steep_uneven_response() {
        // A response that jumps: 0.25 below a setting of 0.4, then steeply up (as the median
        // shift does with the sway); wanted 0.55, reached at about 0.419.
        let response = |k: f64| {
            if k < 0.4 {
                0.25 * k / 0.4
            } else {
                0.25 + 15.0 * (k - 0.4)
            }
        };
        let mut knob = Knob::new(0.2);
        let mut last = 0.0;
        for _ in 0..ROUNDS {
            last = response(knob.at);
            knob.next(0.55, last, 1.0);
        }
        assert!(
            (response(knob.at) - 0.55).abs() < 0.05,
            "{} gives {}",
            knob.at,
            last
        );
        // Plain scaling alone stays on the coarse steps of at most threefold.
        let mut knob = Knob::new(1.0);
        knob.next(2.0, 8.0, 1.0);
        assert!((knob.at - 1.0 / MAX_STEP).abs() < 1e-12);
        // A bracket end measured with the other knob elsewhere is forgotten: below at 0.2
        // (other knob 0.2), above at 0.21 (other knob 0.6); with the other knob now at 0.8
        // 0.2 gives far more, so the knob is scaled down, not held between 0.2 and 0.21.
        let mut knob = Knob::new(0.2);
        knob.next(4.0, 3.0, 0.2);
        knob.at = 0.21;
        knob.next(4.0, 5.6, 0.6);
        knob.next(4.0, 6.0, 0.8);
        assert!(knob.below.is_none());
        assert!(knob.at < 0.2, "{}", knob.at);
        // Nothing measured: stays.
        let mut knob = Knob::new(0.3);
        knob.next(1.0, 0.0, 1.0);
        assert_eq!(knob.at, 0.3);
    }
}

//! More–Thuente line search (More & Thuente 1994) as PCL's NDT runs it: at most 10 trials,
//! the step bounded to `[step_min, step_max]`, sufficient decrease μ = 1e-4 and curvature
//! ν = 0.9, the auxiliary function ψ until the interval of uncertainty is closed.

/// Sufficient-decrease constant μ.
const MU: f64 = 1e-4;
/// Curvature constant ν.
const NU: f64 = 0.9;
/// Trials after the first at most.
const MAX_TRIALS: usize = 10;

/// One end of the interval of uncertainty: step, function value, derivative.
#[derive(Debug, Clone, Copy)]
struct End {
    a: f64,
    f: f64,
    g: f64,
}

/// The outcome of a search.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Step {
    /// The step length where the search stopped (the last one evaluated).
    pub length: f64,
    /// Trials after the first (0: the first trial was accepted).
    pub trials: usize,
}

/// Searches a step along a descent direction of φ, with φ(0) = `phi0` and φ'(0) = `dphi0`
/// (< 0). `phi(α, trial)` evaluates (φ(α), φ'(α)); the first call is trial 0 at
/// `step_init` clamped to the bounds.
///
/// ```
/// use keylo_registration::ndt::line_search::more_thuente;
/// // φ(α) = (α − 0.3)²: the search lands near the minimum.
/// let s = more_thuente(0.09, -0.6, 1.0, 0.0, 2.0, |a, _| ((a - 0.3f64).powi(2), 2.0 * (a - 0.3)));
/// assert!((s.length - 0.3).abs() < 0.1);
/// ```
pub fn more_thuente(
    phi0: f64,
    dphi0: f64,
    step_init: f64,
    step_min: f64,
    step_max: f64,
    mut phi: impl FnMut(f64, usize) -> (f64, f64),
) -> Step {
    let bound = |a: f64| a.min(step_max).max(step_min);
    let psi = |a: f64, f: f64| f - phi0 - MU * dphi0 * a;
    let dpsi = |g: f64| g - MU * dphi0;
    let start = End {
        a: 0.0,
        f: psi(0.0, phi0),
        g: dpsi(dphi0),
    };
    let (mut lo, mut hi) = (start, start);
    let mut converged = step_max < step_min;
    let mut open = true;
    let mut a = bound(step_init);
    let (mut f, mut g) = phi(a, 0);
    let mut trials = 0;
    while !converged && trials < MAX_TRIALS && (psi(a, f) > 0.0 || g > -NU * dphi0) {
        let t = if open {
            End {
                a,
                f: psi(a, f),
                g: dpsi(g),
            }
        } else {
            End { a, f, g }
        };
        let next = trial_value(&lo, &hi, &t);
        // A broken interpolation (NaN) falls back to bisection instead of poisoning the pose.
        a = bound(if next.is_finite() {
            next
        } else {
            0.5 * (lo.a + hi.a)
        });
        (f, g) = phi(a, trials + 1);
        let (psi_t, dpsi_t) = (psi(a, f), dpsi(g));
        if open && psi_t <= 0.0 && dpsi_t >= 0.0 {
            open = false;
            for end in [&mut lo, &mut hi] {
                end.f += phi0 - MU * dphi0 * end.a;
                end.g += MU * dphi0;
            }
        }
        let t = if open {
            End {
                a,
                f: psi_t,
                g: dpsi_t,
            }
        } else {
            End { a, f, g }
        };
        converged = update_interval(&mut lo, &mut hi, &t);
        trials += 1;
    }
    Step { length: a, trials }
}

/// The minimiser of the cubic through (a, fa, ga) and (b, fb, gb).
fn cubic_min(a: &End, b: &End) -> f64 {
    let z = 3.0 * (b.f - a.f) / (b.a - a.a) - b.g - a.g;
    let w = (z * z - b.g * a.g).sqrt();
    a.a + (b.a - a.a) * (w - a.g - z) / (b.g - a.g + 2.0 * w)
}

/// The next trial step from the interval ends `lo`, `hi` and the current trial `t`
/// (More–Thuente section 4, cases 1–4).
fn trial_value(lo: &End, hi: &End, t: &End) -> f64 {
    if t.a == lo.a && t.a == hi.a {
        return t.a;
    }
    if t.a != lo.a && t.f > lo.f {
        // Case 1: a higher value; the minimum is bracketed by lo and t.
        let c = cubic_min(lo, t);
        let q = lo.a - 0.5 * (lo.a - t.a) * lo.g / (lo.g - (lo.f - t.f) / (lo.a - t.a));
        return if (c - lo.a).abs() < (q - lo.a).abs() {
            c
        } else {
            0.5 * (q + c)
        };
    }
    if t.a != lo.a && t.g * lo.g < 0.0 {
        // Case 2: derivatives of opposite sign.
        let c = cubic_min(lo, t);
        let s = lo.a - (lo.a - t.a) / (lo.g - t.g) * lo.g;
        return if (c - t.a).abs() >= (s - t.a).abs() {
            c
        } else {
            s
        };
    }
    if t.a != lo.a && t.g.abs() <= lo.g.abs() {
        // Case 3: the derivative decreases in magnitude; extrapolate, but safeguarded.
        let c = cubic_min(lo, t);
        let s = lo.a - (lo.a - t.a) / (lo.g - t.g) * lo.g;
        let next = if (c - t.a).abs() < (s - t.a).abs() {
            c
        } else {
            s
        };
        let limit = t.a + 0.66 * (hi.a - t.a);
        return if t.a > lo.a {
            limit.min(next)
        } else {
            limit.max(next)
        };
    }
    // Case 4: the derivative does not decrease; the cubic through hi and t.
    cubic_min(hi, t)
}

/// The updating algorithm; true when the interval cannot shrink any more.
fn update_interval(lo: &mut End, hi: &mut End, t: &End) -> bool {
    if t.f > lo.f {
        *hi = *t;
        return false;
    }
    let side = t.g * (lo.a - t.a);
    if side > 0.0 {
        *lo = *t;
        false
    } else if side < 0.0 {
        *hi = *lo;
        *lo = *t;
        false
    } else {
        true
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn wolfe(phi0: f64, dphi0: f64, a: f64, f: f64, g: f64) -> bool {
        // PCL's acceptance: sufficient decrease and φ'(α) ≤ −ν φ'(0).
        f <= phi0 + MU * a * dphi0 && g <= -NU * dphi0
    }

    #[test]
    fn a_quartic_gets_a_step_meeting_the_conditions() {
        // φ(α) = (α − 1.7)⁴ − 3α, minimum past the initial step.
        let phi = |a: f64| ((a - 1.7).powi(4) - 3.0 * a, 4.0 * (a - 1.7).powi(3) - 3.0);
        let (p0, d0) = phi(0.0);
        assert!(d0 < 0.0);
        let s = more_thuente(p0, d0, 0.2, 0.0, 10.0, |a, _| phi(a));
        let (f, g) = phi(s.length);
        assert!(wolfe(p0, d0, s.length, f, g), "{s:?} f={f} g={g}");
        assert!(s.trials <= MAX_TRIALS);
    }

    #[test]
    fn the_step_never_leaves_its_bounds() {
        let s = more_thuente(0.0, -1.0, 5.0, 0.01, 0.1, |a, _| (-a, -1.0));
        assert!((s.length - 0.1).abs() < 1e-15, "{s:?}");
        let s = more_thuente(0.0, -1.0, 1e-6, 0.01, 0.1, |a, _| (-a, -1.0));
        assert!((0.01..=0.1).contains(&s.length), "{s:?}");
    }

    #[test]
    fn an_accepted_first_trial_stops_at_once() {
        let mut calls = 0;
        let s = more_thuente(1.0, -2.0, 1.0, 0.0, 1.0, |a, _| {
            calls += 1;
            ((a - 1.0).powi(2), 2.0 * (a - 1.0))
        });
        assert_eq!((s.length, s.trials, calls), (1.0, 0, 1));
    }

    #[test]
    fn equal_bounds_skip_the_search() {
        let s = more_thuente(0.0, -1.0, 0.3, 0.05, 0.05, |a, _| {
            ((a - 3.0).powi(2), 2.0 * (a - 3.0))
        });
        assert_eq!(s.length, 0.05);
    }
}

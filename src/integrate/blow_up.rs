//! Detection of finite-time blow-up (SPEC X8): an observer that recognises a phase-space rate
//! growing like a power of the time left, `‖ż‖ ∝ (t* − t)^{−α}`, stops the run and reports the
//! singular time `t*` and the exponent `α`, so that a singularity of the motion is reported as
//! such and not as a step-size failure of the integrator.
//!
//! For a rate `r(t) = C (t* − t)^{−α}` the inverse logarithmic derivative is linear in time,
//!
//! ```math
//! w(t) = \Big(\frac{d\ln r}{dt}\Big)^{-1} = \frac{t^* - t}{\alpha},
//! ```
//!
//! so a straight line fitted to `w` over the last accepted steps gives `α = −1/w′` and `t*` as its
//! zero. The rate of a step is its mean phase-space speed `‖z₁ − z₀‖/|h|`, attributed to the
//! midpoint, and `d ln r/dt` is the difference quotient of consecutive steps. A blow-up is
//! declared when, on two consecutive steps, the fit over the window is
//! - growing (`d ln r/dt > 0` throughout) with `0 < α ≤` [`BlowUpDetector::MAX_EXPONENT`] (an
//!   exponential growth has a constant `w` and no finite `t*`),
//! - straight (largest deviation of `w` from the line at most a tenth of its first value),
//! - close (the predicted `t*` lies ahead of the last step by at most
//!   [`BlowUpDetector::REACH`] times the window's length),
//!
//! and the rate has grown by the factor [`BlowUpDetector::with_growth`] (default 10) over its
//! smallest value in the run. A blow-up is declared when accepted fits on consecutive steps agree
//! on `t*` (each within the previous time to go) while the time to go shrinks by
//! [`BlowUpDetector::SHRINK`]: a regular motion that only passes close to a singularity follows
//! the power law over a limited range of scales and is not reported. The folded rope of Ardema 9.3 (`μ̇ ∝ (1 − μ)^{−1/2}`, `α = 1/3`)
//! and `ẋ = x²` (`α = 2`) are the tests; regular motions never satisfy all four conditions.
//!
//! Reference: the local power-law fit is the rate analysis of G. F. Corliss & Y. F. Chang,
//! "Solving ordinary differential equations using Taylor series", ACM TOMS 8 (1982) 114–144, §4,
//! applied here to the accepted steps of any method instead of the Taylor coefficients.

use super::{Control, Observer, StepView};
use crate::error::{Error, Result};
use crate::phase::State;

/// Steps in the fitting window.
const WINDOW: usize = 5;

/// A finite-time singularity found by [`BlowUpDetector`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Singularity {
    /// The extrapolated singular time `t*`.
    pub t_star: f64,
    /// The exponent `α` of `‖ż‖ ∝ (t* − t)^{−α}`.
    pub exponent: f64,
    /// The time the run reached (end of the last accepted step).
    pub t_reached: f64,
    /// The mean phase-space rate of the last step.
    pub rate: f64,
    /// The change of the `t*` estimate between the last two fits: a measure of its uncertainty.
    pub spread: f64,
}

/// The blow-up observer (module docs). Combine it with other observers as a pair
/// `(detector, other)`; after the run, [`BlowUpDetector::singularity`] tells whether it stopped
/// the run, and [`BlowUpDetector::check`] turns a detection into [`Error::BlowUp`].
#[derive(Clone, Debug)]
pub struct BlowUpDetector {
    samples: [(f64, f64); WINDOW],
    len: usize,
    min_rate: f64,
    growth: f64,
    /// `(t*, time to go)` of the previous fit and the time to go when the current run of
    /// consistent fits began.
    streak: Option<(f64, f64, f64)>,
    found: Option<Singularity>,
}

impl Default for BlowUpDetector {
    fn default() -> Self {
        Self::new()
    }
}

impl BlowUpDetector {
    /// The largest exponent `α` accepted as a power law; beyond it the growth is treated as
    /// exponential (no finite `t*`).
    pub const MAX_EXPONENT: f64 = 50.0;

    /// How far ahead of the last step, in lengths of the fitting window, the predicted `t*` may
    /// lie: an adaptive method approaching a power-law singularity takes steps shrinking roughly
    /// geometrically with the time left, so the window spans a fixed fraction of it.
    pub const REACH: f64 = 4.0;

    /// A detector with the default growth factor 10.
    pub fn new() -> Self {
        Self {
            samples: [(0.0, 0.0); WINDOW],
            len: 0,
            min_rate: f64::INFINITY,
            growth: 10.0,
            streak: None,
            found: None,
        }
    }

    /// The factor by which the rate must have grown over its smallest value in the run before a
    /// blow-up is declared.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] unless `growth` is finite and `≥ 1`.
    pub fn with_growth(mut self, growth: f64) -> Result<Self> {
        if !(growth.is_finite() && growth >= 1.0) {
            return Err(Error::out_of_domain(
                "blow-up growth factor",
                growth,
                "finite, ≥ 1",
            ));
        }
        self.growth = growth;
        Ok(self)
    }

    /// The singularity that stopped the run, if any.
    pub fn singularity(&self) -> Option<Singularity> {
        self.found
    }

    /// `Ok(())` if no blow-up was detected, otherwise [`Error::BlowUp`] naming `what`.
    ///
    /// # Errors
    /// [`Error::BlowUp`] with the singular time, the exponent and the time reached.
    pub fn check(&self, what: &str) -> Result<()> {
        match self.found {
            None => Ok(()),
            Some(s) => Err(Error::BlowUp {
                what: what.to_string(),
                t_star: s.t_star,
                exponent: s.exponent,
                t_reached: s.t_reached,
            }),
        }
    }

    /// By how much the time to go must shrink while consecutive fits agree before a blow-up is
    /// declared: a motion that only passes near a singularity (a periapsis passage at high
    /// eccentricity) looks like a power law over a limited range of scales, `(1 − e)^{−3/2}` for
    /// Kepler, and is not reported unless that range exceeds this factor.
    pub const SHRINK: f64 = 1e4;

    /// The power-law fit over the window: `(t*, α, time to go)` if it meets the conditions of the
    /// module docs.
    fn fit(&self, t_last: f64) -> Option<(f64, f64, f64)> {
        if self.len < WINDOW {
            return None;
        }
        // (σ_i, w_i) from consecutive samples.
        let mut pts = [(0.0, 0.0); WINDOW - 1];
        for i in 1..WINDOW {
            let (t0, l0) = self.samples[i - 1];
            let (t1, l1) = self.samples[i];
            let slope = (l1 - l0) / (t1 - t0);
            if !(slope.is_finite() && slope * (t1 - t0).signum() > 0.0) {
                return None;
            }
            pts[i - 1] = (0.5 * (t0 + t1), 1.0 / slope);
        }
        let n = pts.len() as f64;
        let (ms, mw) = pts
            .iter()
            .fold((0.0, 0.0), |(a, b), &(s, w)| (a + s / n, b + w / n));
        let (sxx, sxy) = pts.iter().fold((0.0, 0.0), |(a, b), &(s, w)| {
            (a + (s - ms) * (s - ms), b + (s - ms) * (w - mw))
        });
        let b = sxy / sxx;
        let a = mw - b * ms;
        let alpha = -1.0 / b;
        let t_star = -a / b;
        let first = self.samples[0].0;
        let length = (t_last - first).abs();
        let worst = pts
            .iter()
            .map(|&(s, w)| (w - (a + b * s)).abs())
            .fold(0.0, f64::max);
        let ahead = (t_star - t_last) * (t_last - first).signum();
        let ok = alpha.is_finite()
            && alpha > 0.0
            && alpha <= Self::MAX_EXPONENT
            && worst <= 0.1 * pts[0].1.abs()
            && ahead > 0.0
            && ahead <= Self::REACH * length;
        ok.then_some((t_star, alpha, ahead))
    }
}

impl<const N: usize> Observer<N> for BlowUpDetector {
    fn start(&mut self, _state: &State<N>) {
        *self = Self {
            growth: self.growth,
            ..Self::new()
        };
    }

    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        let h = step.next.t - step.prev.t;
        let dq = step.next.q - step.prev.q;
        let dp = step.next.p - step.prev.p;
        let rate = (dq.norm_squared() + dp.norm_squared()).sqrt() / h.abs();
        if !(rate.is_finite() && rate > 0.0) {
            return Control::Continue;
        }
        self.min_rate = self.min_rate.min(rate);
        let sample = (step.prev.t + 0.5 * h, rate.ln());
        if self.len < WINDOW {
            self.samples[self.len] = sample;
            self.len += 1;
        } else {
            self.samples.rotate_left(1);
            self.samples[WINDOW - 1] = sample;
        }
        let fit = if rate >= self.growth * self.min_rate {
            self.fit(step.next.t)
        } else {
            None
        };
        let Some((t_star, exponent, to_go)) = fit else {
            self.streak = None;
            return Control::Continue;
        };
        // Consecutive fits must agree on t* to within the time to go of the previous one.
        let start = match self.streak {
            Some((before, before_to_go, start)) if (t_star - before).abs() <= before_to_go => start,
            _ => to_go,
        };
        let spread = self
            .streak
            .map_or(f64::INFINITY, |(b, _, _)| (t_star - b).abs());
        self.streak = Some((t_star, to_go, start));
        if to_go * Self::SHRINK <= start {
            self.found = Some(Singularity {
                t_star,
                exponent,
                t_reached: step.next.t,
                rate,
                spread,
            });
            return Control::Stop;
        }
        Control::Continue
    }
}

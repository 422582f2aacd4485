//! Quadratures between turning points [Ardema 9.2, eqs. 9.13–9.15; 10.1].
//!
//! Separating the Hamilton–Jacobi equation reduces every coordinate to integrals of the form
//!
//! ```math
//! \int_{x_1}^{x} \frac{g(x)\\,dx}{\sqrt{F(x)}}, \qquad F(x) = (x - x_1)(x_2 - x)\\,P(x),
//! ```
//!
//! where `F = p²` is the radicand of the separated momentum and `x₁ < x₂` are the turning points
//! (simple roots of `F`, `P > 0` on `[x₁, x₂]`). The integrand has inverse-square-root end points.
//! The substitution
//!
//! ```math
//! x = \tfrac12(x_1 + x_2) - \tfrac12(x_2 - x_1)\cos s, \qquad s \in [0, \pi],
//! ```
//!
//! gives `x − x₁ = L sin²(s/2)`, `x₂ − x = L cos²(s/2)` (`L = x₂ − x₁`) and
//! `dx/√F = ds/√P(x)`: a smooth integrand. Both offsets are computed from `s` directly (never as a
//! difference of nearly equal numbers), and the upper half `s ∈ [π/2, π]` is integrated in the
//! reflected variable `σ = π − s`, so each turning point sits at the origin of its own variable.
//! For a known factorisation (Kepler, pendulum, heavy top) the caller supplies `P` exactly
//! ([`Libration::new`]); otherwise [`Libration::from_radicand`] finds the roots of a generic `F` and
//! evaluates `P = F/((x − x₁)(x₂ − x))`; near a root, where that division would amplify the
//! rounding of `F`, it uses `F(x₁ + d) = d ∫₀¹ F′(x₁ + τd) dτ` with the AD derivative instead
//! ([`Factored`]).
//!
//! In `s` the period integrals are those of smooth periodic functions; when the two roots merge
//! (a double root: circular orbit, steady precession) the integrals tend to the finite
//! small-oscillation limit `π g(x₀)/√P(x₀)`, which a factorised `P` reproduces exactly (`L = 0`).
//! A generic `F` with a double root is refused ([`Error::Separatrix`]), as is one whose turning
//! point is (numerically) a double root: that is a separatrix, where the time to reach it diverges.
//!
//! Integrals use the Clenshaw–Curtis rule of the `quadrature` crate on each half (the integrands are
//! analytic there, so it converges geometrically and, unlike the crate's double-exponential rule
//! whose tabulated weights limit it to about 1e−14 relative, to rounding level), bisected
//! adaptively until the requested relative tolerance is met (sharply peaked integrands such as the
//! swept angle near periapsis at e → 1 are resolved by the subdivision). Every result carries its
//! error estimate and the number of integrand evaluations; a non-finite integrand value is an
//! error, never silently dropped.

use crate::error::{finite, Error, Result};
use num_dual::{Dual3_64, Dual64, DualNum};
use std::cell::Cell;
use std::f64::consts::{FRAC_PI_2, PI};

/// A radicand `F(x)` (the square of a separated momentum), written once for every dual type so
/// that its derivatives at the turning points come from AD.
pub trait Radicand {
    /// `F(x)`.
    fn radicand<D: DualNum<f64> + Copy>(&self, x: D) -> D;
}

impl<R: Radicand + ?Sized> Radicand for &R {
    fn radicand<D: DualNum<f64> + Copy>(&self, x: D) -> D {
        (**self).radicand(x)
    }
}

/// The reduced radicand `P(x) = F(x)/((x − x₁)(x₂ − x))`, evaluated from `x` and the exactly
/// computed offsets `d₁ = x − x₁ ≥ 0`, `d₂ = x₂ − x ≥ 0`.
pub trait ReducedRadicand {
    /// `P(x)`; must be positive on `[x₁, x₂]`.
    fn reduced(&self, x: f64, d1: f64, d2: f64) -> f64;
    /// Relative accuracy of [`reduced`](Self::reduced) (default: a few rounding errors). The
    /// adaptive quadrature does not subdivide below this noise level.
    fn noise(&self) -> f64 {
        4.0 * f64::EPSILON
    }
    /// Relative accuracy of `P` at one point (default: [`noise`](Self::noise) everywhere).
    fn noise_at(&self, _x: f64, _d1: f64, _d2: f64) -> f64 {
        self.noise()
    }
}

impl<F: Fn(f64, f64, f64) -> f64> ReducedRadicand for F {
    fn reduced(&self, x: f64, d1: f64, d2: f64) -> f64 {
        self(x, d1, d2)
    }
}

/// `P = F/(d₁ d₂)` for a generic [`Radicand`]. Near a root the quotient would divide the
/// rounding error of `F` (absolute, from its own terms) by a small `d`; there `F` is replaced by
/// the integral of its AD derivative from the root,
///
/// ```math
/// F(x_1 + d_1) = d_1 \int_0^1 F'(x_1 + \tau d_1)\,d\tau,
/// ```
///
/// by 8-point Gauss–Legendre (exact to degree 15 in `τ`), which involves no cancellation. The switch
/// is at `d = 0.1 ℓ`, with `ℓ` the smaller of the interval width and the root's own length scale
/// `|F′/F″|`, so the Gauss rule spans at most a tenth of the distance over which `F′` changes.
#[derive(Clone, Debug)]
pub struct Factored<R> {
    radicand: R,
    x1: f64,
    x2: f64,
    /// Offsets from `x₁` and `x₂` below which the derivative form is used.
    switch: [f64; 2],
    /// Relative accuracy of `P` at worst (see [`ReducedRadicand::noise`]).
    noise: f64,
    /// The absolute rounding noise `σ` of `F`.
    sigma: f64,
}

/// 8-point Gauss–Legendre nodes and weights on `[0, 1]`.
const GAUSS8: [(f64, f64); 8] = [
    (0.019855071751231856, 0.05061426814518815),
    (0.10166676129318664, 0.11119051722668725),
    (0.2372337950418355, 0.15685332293894366),
    (0.4082826787521751, 0.181341891689181),
    (0.591717321247825, 0.181341891689181),
    (0.7627662049581645, 0.15685332293894366),
    (0.8983332387068134, 0.11119051722668725),
    (0.9801449282487682, 0.05061426814518815),
];

impl<R: Radicand> Factored<R> {
    fn new(radicand: R, x1: f64, x2: f64) -> Self {
        let l = x2 - x1;
        let scale = |x: f64| {
            let d = radicand.radicand(num_dual::Dual2_64::from_re(x).derivative());
            let local = (d.v1 / d.v2).abs();
            0.1 * if local.is_finite() { local.min(l) } else { l }
        };
        let switch = [scale(x1), scale(x2)];
        // The direct quotient's relative error where it takes over is the absolute rounding noise
        // of F (measured, see `rounding_noise`: it reflects the size of F's terms, which may be far
        // larger than F itself) over the value of F there.
        let (xa, xb) = (x1 + switch[0], x2 - switch[1]);
        let sigma = rounding_noise(&radicand, xa, 0.01 * switch[0]).max(rounding_noise(
            &radicand,
            xb,
            0.01 * switch[1],
        ));
        let small = radicand.radicand(xa).abs().min(radicand.radicand(xb).abs());
        // Plus the offset loss: x = x₁ + d rounds to ulp(x), which moves F by F′·ulp(x), i.e.
        // relatively ulp(x)/d at the switch (large when |x| ≫ L).
        let offset = f64::EPSILON * x1.abs().max(x2.abs()) / switch[0].min(switch[1]);
        let noise = (8.0 * sigma / small + 2.0 * offset).max(40.0 * f64::EPSILON);
        Self {
            radicand,
            x1,
            x2,
            switch,
            noise,
            sigma,
        }
    }
    /// The radicand.
    pub fn radicand(&self) -> &R {
        &self.radicand
    }
    /// `∫₀¹ F′(x₀ + σ τ d) dτ` (`σ = ±1`).
    fn mean_slope(&self, x0: f64, sigma: f64, d: f64) -> f64 {
        GAUSS8
            .iter()
            .map(|&(t, w)| {
                let x = x0 + sigma * t * d;
                w * self.radicand.radicand(Dual64::from_re(x).derivative()).eps
            })
            .sum()
    }
}

impl<R: Radicand> ReducedRadicand for Factored<R> {
    fn reduced(&self, x: f64, d1: f64, d2: f64) -> f64 {
        if d1 <= self.switch[0] && d1 <= d2 {
            self.mean_slope(self.x1, 1.0, d1) / d2
        } else if d2 <= self.switch[1] {
            -self.mean_slope(self.x2, -1.0, d2) / d1
        } else {
            self.radicand.radicand(x) / (d1 * d2)
        }
    }
    /// The worst case, at the switch: `8σ/|F|` plus the offset loss `2ε|x|/d` (at least `40ε`).
    /// Near a separatrix, or for a radicand that cancels (nearly circular orbits), `F` is tiny at
    /// the switch and this grows: the generic route's accuracy degrades, and the quadrature stops
    /// refining at that level instead of failing.
    fn noise(&self) -> f64 {
        self.noise
    }
    /// `8σ/|F(x)| + 2ε|x|/min(d₁, d₂)` where the quotient is used, `40ε` in the derivative form.
    fn noise_at(&self, x: f64, d1: f64, d2: f64) -> f64 {
        let floor = 40.0 * f64::EPSILON;
        if (d1 <= self.switch[0] && d1 <= d2) || d2 <= self.switch[1] {
            return floor;
        }
        let f = self.radicand.radicand(x).abs();
        let offset = f64::EPSILON * x.abs() / d1.min(d2);
        (8.0 * self.sigma / f + 2.0 * offset)
            .max(floor)
            .min(self.noise)
    }
}

/// A quadrature result: value, error estimate and cost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quadrature {
    /// The integral.
    pub value: f64,
    /// Estimated absolute error (from the Clenshaw–Curtis rule's successive refinements).
    pub error: f64,
    /// Integrand evaluations.
    pub evaluations: usize,
}

impl Quadrature {
    fn zero() -> Self {
        Self {
            value: 0.0,
            error: 0.0,
            evaluations: 0,
        }
    }
    fn add(self, o: Self) -> Self {
        Self {
            value: self.value + o.value,
            error: self.error + o.error,
            evaluations: self.evaluations + o.evaluations,
        }
    }
    /// The result multiplied by a constant.
    pub fn scale(self, c: f64) -> Self {
        Self {
            value: self.value * c,
            error: self.error * c.abs(),
            evaluations: self.evaluations,
        }
    }
}

/// A point of the libration interval as seen by an integrand: the substitution variable and the
/// offsets from both turning points, all exact.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// `x`.
    pub x: f64,
    /// `x − x₁ = L sin²(s/2)`.
    pub d1: f64,
    /// `x₂ − x = L cos²(s/2)`.
    pub d2: f64,
    /// The reduced radicand `P(x) > 0`.
    pub reduced: f64,
}

impl Node {
    /// `√F(x) = √(d₁ d₂ P)`, the separated momentum's magnitude.
    pub fn sqrt_radicand(&self) -> f64 {
        (self.d1 * self.d2 * self.reduced).sqrt()
    }
    /// `dx/ds = √(d₁ d₂)`.
    pub fn jacobian(&self) -> f64 {
        (self.d1 * self.d2).sqrt()
    }
}

/// Default relative tolerance of the turning-point quadratures.
pub const DEFAULT_TOLERANCE: f64 = 1e-14;

/// Maximum bisection depth of the adaptive Clenshaw–Curtis rule: enough to grade geometrically
/// down to the smallest subnormal spacing at an end point (e.g. the pendulum's logarithmic peak of
/// width `√δ` at the separatrix); the evaluation budget bounds the cost.
const MAX_DEPTH: u32 = 1100;

/// Budget of integrand evaluations per adaptive integral; exceeding it is reported as
/// [`Error::NotConverged`] rather than spending unbounded time.
const MAX_EVALUATIONS: usize = 200_000;

/// The libration interval `[x₁, x₂]` of a separated coordinate, with its reduced radicand.
#[derive(Clone, Debug)]
pub struct Libration<P> {
    x1: f64,
    x2: f64,
    reduced: P,
    tolerance: f64,
}

impl<P: ReducedRadicand> Libration<P> {
    /// Turning points `x₁ ≤ x₂` and the exact reduced radicand `P` (`F = (x − x₁)(x₂ − x) P`).
    /// `x₁ = x₂` is allowed: the integrals are then their small-oscillation limits.
    ///
    /// The offsets `d₁, d₂` are computed from the width `L = x₂ − x₁`, so they are only as precise
    /// as `L`: a narrow libration far from the origin (`L ≪ |x|`) loses `ε|x|/L` relative. Pass
    /// such an interval in a local variable `x − x₀` whose turning points are known as offsets
    /// (the heavy top's fast nutation does this).
    pub fn new(x1: f64, x2: f64, reduced: P) -> Result<Self> {
        let x1 = finite("lower turning point x₁", x1)?;
        let x2 = finite("upper turning point x₂", x2)?;
        if x2 < x1 {
            return Err(Error::invalid(
                "turning points",
                format!("need x₁ ≤ x₂, got x₁ = {x1}, x₂ = {x2}"),
            ));
        }
        let lib = Self {
            x1,
            x2,
            reduced,
            tolerance: DEFAULT_TOLERANCE,
        };
        for s in [0.0, FRAC_PI_2, PI] {
            let n = lib.node(s);
            if !(n.reduced > 0.0 && n.reduced.is_finite()) {
                return Err(Error::out_of_domain(
                    format!("reduced radicand P at x = {}", n.x),
                    n.reduced,
                    "(0, ∞): the turning points must be simple roots of F",
                ));
            }
        }
        Ok(lib)
    }

    /// The same interval with another relative tolerance (default [`DEFAULT_TOLERANCE`]).
    pub fn with_tolerance(mut self, tolerance: f64) -> Result<Self> {
        if !(tolerance.is_finite() && tolerance > 0.0) {
            return Err(Error::out_of_domain(
                "quadrature tolerance",
                tolerance,
                "(0, ∞)",
            ));
        }
        self.tolerance = tolerance;
        Ok(self)
    }

    /// Lower turning point `x₁`.
    pub fn lower(&self) -> f64 {
        self.x1
    }
    /// Upper turning point `x₂`.
    pub fn upper(&self) -> f64 {
        self.x2
    }
    /// The reduced radicand.
    pub fn reduced_radicand(&self) -> &P {
        &self.reduced
    }

    /// The point with substitution variable `s ∈ [0, π]`.
    pub fn node(&self, s: f64) -> Node {
        if s <= FRAC_PI_2 {
            self.node_lower(s)
        } else {
            self.node_upper(PI - s)
        }
    }

    fn node_lower(&self, s: f64) -> Node {
        let l = self.x2 - self.x1;
        let (sh, ch) = (0.5 * s).sin_cos();
        let (d1, d2) = (l * sh * sh, l * ch * ch);
        let x = self.x1 + d1;
        Node {
            x,
            d1,
            d2,
            reduced: self.reduced.reduced(x, d1, d2),
        }
    }

    fn node_upper(&self, sigma: f64) -> Node {
        let l = self.x2 - self.x1;
        let (sh, ch) = (0.5 * sigma).sin_cos();
        let (d2, d1) = (l * sh * sh, l * ch * ch);
        let x = self.x2 - d2;
        Node {
            x,
            d1,
            d2,
            reduced: self.reduced.reduced(x, d1, d2),
        }
    }

    /// The substitution variable `s ∈ [0, π]` of `x ∈ [x₁, x₂]`.
    ///
    /// A point within rounding (`8ε|x|`) of a turning point is that turning point: integrals from
    /// a point near an apsis behave like `√(x − x₁)`, so a one-ulp disagreement between a user's
    /// `x` and the computed root would otherwise cost `√ε` in the result. Points farther outside
    /// are an error.
    pub fn phase(&self, x: f64) -> Result<f64> {
        let x = finite("x", x)?;
        let l = self.x2 - self.x1;
        let slack = 8.0 * f64::EPSILON * x.abs();
        if x <= self.x1 + slack && x >= self.x1 - slack {
            return Ok(0.0);
        }
        if x >= self.x2 - slack && x <= self.x2 + slack {
            return Ok(PI);
        }
        if x < self.x1 || x > self.x2 {
            return Err(Error::out_of_domain(
                "x",
                x,
                format!("[{}, {}] (between the turning points)", self.x1, self.x2),
            ));
        }
        let (d1, d2) = (x - self.x1, self.x2 - x);
        Ok(if d1 <= d2 {
            2.0 * (d1 / l).sqrt().min(1.0).asin()
        } else {
            PI - 2.0 * (d2 / l).sqrt().min(1.0).asin()
        })
    }

    /// The substitution variable of a point `x` where the separated momentum is `p` (`p² = F`,
    /// either sign). Within the outer quarters of the interval it is the root of
    /// `√(d₁ d₂ P)(s) = |p|` (Illinois iteration, bracketed by the quarter): there `x` determines
    /// the phase only to `√ε` (the phase varies like `√(x − x₁)`), while `p` determines it to full
    /// precision. Elsewhere it is [`phase`](Self::phase)`(x)`.
    pub fn phase_with_momentum(&self, x: f64, p: f64) -> Result<f64> {
        let p = finite("momentum p", p)?;
        let s_x = self.phase(x)?;
        let outer = PI / 4.0;
        if self.x2 == self.x1 || (outer..=PI - outer).contains(&s_x) {
            return Ok(s_x);
        }
        let (mut a, mut b) = if s_x < 0.5 * PI {
            (0.0, outer)
        } else {
            (PI, PI - outer)
        };
        let g = |s: f64| self.node(s).sqrt_radicand() - p.abs();
        let (mut ga, mut gb) = (g(a), g(b));
        if !(ga <= 0.0 && gb > 0.0) {
            return Ok(s_x);
        }
        let mut side = 0;
        for _ in 0..100 {
            let c = (a * gb - b * ga) / (gb - ga);
            let gc = g(c);
            if gc == 0.0 || (b - a).abs() <= 4.0 * f64::EPSILON * c.abs().max(f64::MIN_POSITIVE) {
                return Ok(c);
            }
            if gc < 0.0 {
                a = c;
                ga = gc;
                if side == -1 {
                    gb *= 0.5;
                }
                side = -1;
            } else {
                b = c;
                gb = gc;
                if side == 1 {
                    ga *= 0.5;
                }
                side = 1;
            }
        }
        Ok(0.5 * (a + b))
    }

    /// `∫ f(node) ds` over `s ∈ [0, π]` — the full interval `x₁ → x₂`. The integrand receives the
    /// [`Node`] and must include every factor except `ds` (e.g. `g(x)/√P` for `∫ g dx/√F`).
    pub fn integrate_full(&self, f: impl Fn(&Node) -> f64) -> Result<Quadrature> {
        self.integrate_between(f, 0.0, PI)
    }

    /// `∫ f(node) ds` over `s ∈ [s₀, s₁] ⊂ [0, π]`, `s₀ ≤ s₁`.
    pub fn integrate_between(
        &self,
        f: impl Fn(&Node) -> f64,
        s0: f64,
        s1: f64,
    ) -> Result<Quadrature> {
        let (s0, s1) = (finite("s₀", s0)?, finite("s₁", s1)?);
        if !(0.0..=PI).contains(&s0) || !(0.0..=PI).contains(&s1) || s0 > s1 {
            return Err(Error::invalid(
                "substitution range",
                format!("need 0 ≤ s₀ ≤ s₁ ≤ π, got [{s0}, {s1}]"),
            ));
        }
        // The scale of the answer, for a relative tolerance: a coarse midpoint estimate.
        let scale = {
            let mut acc = 0.0;
            for k in 0..8 {
                let s = s0 + (s1 - s0) * (k as f64 + 0.5) / 8.0;
                acc += f(&self.node(s)).abs();
            }
            acc * (s1 - s0) / 8.0
        };
        // Each half gets half the target, so the sum meets it.
        let target = 0.5 * self.tolerance * scale.max(f64::MIN_POSITIVE);
        let noise_of = |n: Node| self.reduced.noise_at(n.x, n.d1, n.d2);
        let mut out = Quadrature::zero();
        if s0 < FRAC_PI_2 {
            let hi = s1.min(FRAC_PI_2);
            out = out.add(adaptive(
                |s| f(&self.node_lower(s)),
                |s| noise_of(self.node_lower(s)),
                s0,
                hi,
                target,
            )?);
        }
        if s1 > FRAC_PI_2 {
            let (a, b) = (PI - s1, PI - s0.max(FRAC_PI_2));
            out = out.add(adaptive(
                |sg| f(&self.node_upper(sg)),
                |sg| noise_of(self.node_upper(sg)),
                a,
                b,
                target,
            )?);
        }
        Ok(out)
    }

    /// `∫ f ds` from `s₀` to `s₁` in either order (negative when `s₁ < s₀`).
    pub fn integrate_signed(
        &self,
        f: impl Fn(&Node) -> f64,
        s0: f64,
        s1: f64,
    ) -> Result<Quadrature> {
        if s1 >= s0 {
            self.integrate_between(f, s0, s1)
        } else {
            Ok(self.integrate_between(f, s1, s0)?.scale(-1.0))
        }
    }

    /// Inverts a monotone integral: the `s ∈ [0, π]` with `∫₀^s density ds = target`, for a positive
    /// `density` (e.g. `dt/ds`) whose integral over `[0, π]` is `total`. Safeguarded Newton, whose
    /// derivative is the density itself; the integral is updated incrementally. Returns `s` and the
    /// accumulated quadrature cost.
    pub fn solve_phase(
        &self,
        density: impl Fn(&Node) -> f64,
        target: f64,
        total: f64,
    ) -> Result<(f64, Quadrature)> {
        let target = finite("phase target", target)?;
        if !(0.0..=total).contains(&target) {
            return Err(Error::out_of_domain(
                "phase target",
                target,
                format!("[0, {total}]"),
            ));
        }
        if target == 0.0 {
            return Ok((0.0, Quadrature::zero()));
        }
        if target == total {
            return Ok((PI, Quadrature::zero()));
        }
        let (mut lo, mut hi) = (0.0, PI);
        let mut s = PI * target / total;
        let mut cost = self.integrate_between(&density, 0.0, s)?;
        let mut value = cost.value;
        for _ in 0..100 {
            let r = value - target;
            if r > 0.0 {
                hi = s;
            } else {
                lo = s;
            }
            if r.abs() <= 4.0 * f64::EPSILON * total || hi - lo <= 4.0 * f64::EPSILON {
                return Ok((s, cost));
            }
            let d = density(&self.node(s));
            let newton = s - r / d;
            let next = if newton > lo && newton < hi && d > 0.0 {
                newton
            } else {
                0.5 * (lo + hi)
            };
            if next == s {
                return Ok((s, cost));
            }
            let step = self.integrate_signed(&density, s, next)?;
            value += step.value;
            cost = Quadrature {
                value,
                error: cost.error + step.error,
                evaluations: cost.evaluations + step.evaluations,
            };
            s = next;
        }
        Err(Error::NotConverged {
            what: "phase inversion of a turning-point integral".into(),
            iterations: 100,
            residual: (value - target).abs(),
        })
    }

    /// `∫_{x₁}^{x₂} g(x) dx / √F(x)` (half a period of a time-like integral).
    pub fn inverse_sqrt_integral(&self, g: impl Fn(f64) -> f64) -> Result<Quadrature> {
        self.integrate_full(|n| g(n.x) / n.reduced.sqrt())
    }

    /// `∫_{x₁}^{x} g(ξ) dξ / √F(ξ)` for `x` in the interval.
    pub fn inverse_sqrt_integral_to(&self, g: impl Fn(f64) -> f64, x: f64) -> Result<Quadrature> {
        let s = self.phase(x)?;
        self.integrate_between(|n| g(n.x) / n.reduced.sqrt(), 0.0, s)
    }

    /// `∫_{x₁}^{x₂} √F(x) dx` (half the action `∮ p dx`).
    pub fn sqrt_integral(&self) -> Result<Quadrature> {
        self.integrate_full(|n| n.d1 * n.d2 * n.reduced.sqrt())
    }

    /// `∫_{x₁}^{x} √F(ξ) dξ`.
    pub fn sqrt_integral_to(&self, x: f64) -> Result<Quadrature> {
        let s = self.phase(x)?;
        self.integrate_between(|n| n.d1 * n.d2 * n.reduced.sqrt(), 0.0, s)
    }
}

impl<R: Radicand> Libration<Factored<R>> {
    /// Turning points of a generic radicand around `inside` (where `F > 0`), searched within
    /// `[lower_bound, upper_bound]`; see [`turning_points`]. Refuses double roots (separatrices).
    pub fn from_radicand(
        radicand: R,
        inside: f64,
        lower_bound: f64,
        upper_bound: f64,
    ) -> Result<Self> {
        let (x1, x2) = turning_points(&radicand, inside, lower_bound, upper_bound)?;
        let at = |x: f64| {
            let d = radicand.radicand(Dual3_64::from_re(x).derivative());
            [d.v1, 0.5 * d.v2]
        };
        let lower = at(x1);
        let u = at(x2);
        let upper = [-u[0], u[1]];
        // Separatrix test. Near a turning point F ≈ F′d + ½F″d²; the depth of the double root
        // that F would have if the two merged is F′²/(4|F″|). When that is within the rounding
        // noise of F (measured at the root, at least ε |F(mid)|), the turning point cannot be told
        // from a double root.
        let scale = radicand.radicand(0.5 * (x1 + x2)).abs();
        let l = x2 - x1;
        for (which, d, x) in [("lower", lower, x1), ("upper", upper, x2)] {
            let gap = d[0] * d[0] / (4.0 * d[1].abs().max(f64::MIN_POSITIVE));
            let local = (d[0] / d[1]).abs().min(l);
            let noise = rounding_noise(&radicand, x, 1e-3 * local).max(f64::EPSILON * scale);
            let ratio = gap / scale;
            if ratio.is_nan() || gap <= 64.0 * noise || d[0] <= 0.0 {
                if d[1] < 0.0 {
                    // F is concave there: the root merges with the other turning point, i.e.
                    // the libration shrinks onto a stable equilibrium (e.g. a circular orbit).
                    return Err(Error::invalid(
                        "radicand",
                        format!(
                            "the turning points {x1} and {x2} cannot be told apart from a double \
                             root of F within its rounding noise ({noise:e}): the motion is at \
                             its small-oscillation limit; use an exact factorisation \
                             (Libration::new, RadialMotion::kepler) or the linearised motion"
                        ),
                    ));
                }
                return Err(Error::Separatrix {
                    what: format!("{which} turning point of the radicand"),
                    distance: ratio.max(0.0),
                    hint:
                        "F has a (numerically) double root there: the motion is asymptotic to an \
                           unstable equilibrium and its period diverges; supply the exact reduced \
                           radicand (Libration::new) or move away from the separatrix"
                            .into(),
                });
            }
        }
        // The scan samples F only at its steps: check that F stays positive between the roots
        // found (a forbidden region narrower than a step would otherwise be stepped over), and
        // that it stands above its own rounding noise.
        let sigma_mid = rounding_noise(&radicand, 0.5 * (x1 + x2), 1e-3 * l);
        for k in 1..64 {
            let x = x1 + l * (0.5 - 0.5 * (PI * k as f64 / 64.0).cos());
            let f = radicand.radicand(x);
            if f.is_finite() && f.abs() <= 64.0 * sigma_mid && (k == 32 || f <= 0.0) {
                return Err(Error::invalid(
                    "radicand",
                    format!(
                        "F = {f} at x = {x} is at its rounding noise (≈ {sigma_mid:e}): the \
                         separated momentum is too small against the terms it is computed from \
                         (e.g. a nearly circular orbit); use an exact factorisation \
                         (Libration::new, RadialMotion::kepler)"
                    ),
                ));
            }
            if f.is_nan() || f <= 0.0 {
                return Err(Error::invalid(
                    "turning points",
                    format!(
                        "F = {f} ≤ 0 at x = {x}, between the roots {x1} and {x2} found by the \
                         scan: it stepped over a forbidden region; narrow the search bounds"
                    ),
                ));
            }
        }
        let reduced = Factored::new(radicand, x1, x2);
        Libration::new(x1, x2, reduced)
    }
}

/// A point where `F > 0` next to `x` (which may be a turning point, `F(x) ≈ 0`): `x` itself if
/// `F(x) > 0`, otherwise a step towards increasing `F` of a thousandth of the local scale
/// `|F′/F″|` (or of the search interval), halved until `F > 0`.
pub fn interior_point<R: Radicand>(radicand: &R, x: f64, lower: f64, upper: f64) -> Result<f64> {
    // The sign test on reals (dual arithmetic may round the value differently).
    let f = radicand.radicand(x);
    if f > 0.0 {
        return Ok(x);
    }
    let d = radicand.radicand(num_dual::Dual2_64::from_re(x).derivative());
    let dir = d.v1.signum();
    let local = (d.v1 / d.v2).abs();
    let mut step = 1e-3
        * if local.is_finite() && local > 0.0 {
            local.min(upper - lower)
        } else {
            upper - lower
        };
    for _ in 0..200 {
        let y = x + dir * step;
        if y > lower && y < upper && radicand.radicand(y) > 0.0 {
            return Ok(y);
        }
        step *= 0.5;
        if step == 0.0 {
            break;
        }
    }
    Err(Error::out_of_domain(
        format!("radicand F near x = {x}"),
        f,
        "F > 0 on one side: x must lie in or on the boundary of an allowed region",
    ))
}

/// The turning points `x₁ < inside < x₂` of a radicand: the nearest roots of `F` below and above a
/// point where `F > 0`, searched outward geometrically within `[lower_bound, upper_bound]` and
/// refined to full precision by safeguarded Newton (AD derivative) with bisection.
///
/// The scan starts at a hundredth of the local length scale of `F` and doubles its step; a
/// forbidden region (where `F < 0`) narrower than the step at that distance can be stepped over.
/// [`Libration::from_radicand`] samples `F` at 63 points between the roots found and refuses an
/// interval where it is not positive, but a barrier narrower than that sampling is not resolved:
/// give search bounds that exclude such features.
///
/// Errors: `F(inside) ≤ 0` (not an allowed point), or no sign change before a bound (the motion is
/// unbounded on that side, or rotational).
pub fn turning_points<R: Radicand>(
    radicand: &R,
    inside: f64,
    lower_bound: f64,
    upper_bound: f64,
) -> Result<(f64, f64)> {
    let inside = finite("interior point", inside)?;
    let (lo, hi) = (
        finite("lower search bound", lower_bound)?,
        finite("upper search bound", upper_bound)?,
    );
    if !(lo < inside && inside < hi) {
        return Err(Error::invalid(
            "turning-point search",
            format!("need lower bound < interior point < upper bound, got {lo} < {inside} < {hi}"),
        ));
    }
    let f0 = radicand.radicand(inside);
    if f0.is_nan() || f0 <= 0.0 {
        return Err(Error::out_of_domain(
            format!("radicand F at the interior point {inside}"),
            f0,
            "(0, ∞): the point must lie in the allowed region",
        ));
    }
    let x1 = bracket_root(radicand, inside, lo)?;
    let x2 = bracket_root(radicand, inside, hi)?;
    Ok((x1, x2))
}

/// The absolute rounding noise of `F` near `x`, measured by the difference-table method of Moré
/// & Wild (*Estimating computational noise*, SIAM J. Sci. Comput. 33 (2011) 1292–1314,
/// doi:10.1137/100786125): sixth differences of `F` on 13 points spaced `h` remove the smooth
/// part (`F⁽⁶⁾h⁶`, negligible for `h` well below the scale of `F`) and leave noise with standard
/// deviation `σ √C(12, 6) ≈ 30.4 σ`; the largest of the seven differences is used. It reflects
/// the size of the terms `F` is computed from — e.g. `2h + 2μ/r − k²/r²` near a circular orbit,
/// where terms of size 1 cancel to leave `F ≈ e²` — which a value of `F` alone cannot reveal.
pub fn rounding_noise<R: Radicand>(radicand: &R, x: f64, h: f64) -> f64 {
    let h = h.max(16.0 * f64::EPSILON * x.abs()).max(f64::MIN_POSITIVE);
    let f: [f64; 13] = std::array::from_fn(|j| radicand.radicand(x + (j as f64 - 6.0) * h));
    const BINOM6: [f64; 7] = [1.0, -6.0, 15.0, -20.0, 15.0, -6.0, 1.0];
    let mut largest: f64 = 0.0;
    for start in 0..7 {
        let d: f64 = (0..7).map(|k| BINOM6[k] * f[start + k]).sum();
        if d.is_finite() {
            largest = largest.max(d.abs());
        }
    }
    (largest / 924f64.sqrt()).max(f64::EPSILON * f[6].abs())
}

/// The root of `F` nearest to `inside` in the direction of `bound`.
///
/// The outward scan watches the slope as well as the sign: where `F` passes through a local
/// minimum between two positive samples, the minimum is located (bisection on `F′`) so that a pair
/// of close roots is not stepped over; a minimum that touches zero to rounding is a (numerically)
/// double root — a separatrix — and is reported as such.
fn bracket_root<R: Radicand>(radicand: &R, inside: f64, bound: f64) -> Result<f64> {
    let dir = (bound - inside).signum();
    let eval = |x: f64| radicand.radicand(Dual64::from_re(x).derivative());
    let scale = radicand.radicand(inside).abs();
    // First step: a hundredth of the local length scale of F at the start — the distance over
    // which its linear (|F/F′|) or quadratic (√|F/F″|) part changes it by its own size — so that
    // the scan starts on the scale of the motion, not of |x|. Then doubling.
    let local = {
        let d = radicand.radicand(num_dual::Dual2_64::from_re(inside).derivative());
        let lin = (d.re / d.v1).abs();
        let quad = (d.re / d.v2).abs().sqrt();
        [lin, quad]
            .into_iter()
            .filter(|v| v.is_finite() && *v > 0.0)
            .fold(f64::INFINITY, f64::min)
    };
    let span = (bound - inside).abs();
    let mut step = if local.is_finite() {
        (0.01 * local).min(0.5 * span)
    } else {
        1e-3 * inside.abs().max(span.min(1.0))
    };
    let mut good = inside;
    let mut good_slope = eval(inside).eps * dir;
    let bad = loop {
        let x = if (inside + dir * step - bound) * dir >= 0.0 {
            bound
        } else {
            inside + dir * step
        };
        let fx = eval(x);
        if fx.re.is_nan() {
            return Err(Error::NonFinite {
                what: format!("radicand F at x = {x}"),
                value: fx.re,
            });
        }
        if fx.re <= 0.0 {
            break x;
        }
        let slope = fx.eps * dir;
        if good_slope < 0.0 && slope > 0.0 {
            // A local minimum of F between `good` and `x`.
            let (mut a, mut b) = (good, x);
            for _ in 0..200 {
                let m = 0.5 * (a + b);
                if m == a || m == b {
                    break;
                }
                if eval(m).eps * dir < 0.0 {
                    a = m;
                } else {
                    b = m;
                }
            }
            let m = 0.5 * (a + b);
            let fm = radicand.radicand(m);
            if fm <= 0.0 {
                break m;
            }
            if fm <= 64.0 * f64::EPSILON * scale {
                return Err(Error::Separatrix {
                    what: format!("turning-point search: F has a double root at x ≈ {m}"),
                    distance: fm / scale,
                    hint: "the motion is asymptotic to an unstable equilibrium there (its period \
                           diverges); move away from the separatrix or pass the motion's own \
                           factorised radicand to Libration::new"
                        .into(),
                });
            }
        }
        if x == bound {
            return Err(Error::out_of_domain(
                "turning-point search",
                bound,
                format!(
                    "F > 0 up to the search bound {bound}: no turning point on that side \
                     (unbounded or rotational motion)"
                ),
            ));
        }
        good = x;
        good_slope = slope;
        step *= 2.0;
    };
    // Safeguarded Newton on [good, bad]: F(good) > 0 ≥ F(bad).
    let (mut a, mut b) = (good, bad);
    let mut x = 0.5 * (a + b);
    for _ in 0..200 {
        let d = radicand.radicand(Dual64::from_re(x).derivative());
        if d.re == 0.0 {
            return Ok(x);
        }
        if d.re > 0.0 {
            a = x;
        } else {
            b = x;
        }
        let newton = x - d.re / d.eps;
        let inside_bracket = (newton - a) * (newton - b) < 0.0;
        let next = if inside_bracket && d.eps.is_finite() {
            newton
        } else {
            0.5 * (a + b)
        };
        if (a - b).abs() <= 4.0 * f64::EPSILON * x.abs().max(f64::MIN_POSITIVE) || next == x {
            return Ok(if radicand.radicand(b).abs() < radicand.radicand(a).abs() {
                b
            } else {
                a
            });
        }
        x = next;
    }
    Err(Error::NotConverged {
        what: "turning-point refinement".into(),
        iterations: 200,
        residual: (a - b).abs(),
    })
}

/// Adaptive Clenshaw–Curtis quadrature of `f` over `[a, b]` to absolute error `target`, bisecting
/// until each piece meets its share of the target or its error estimate is at the integrand's
/// relative noise level `noise(s)` (below which refinement cannot gain accuracy).
fn adaptive(
    f: impl Fn(f64) -> f64,
    noise: impl Fn(f64) -> f64,
    a: f64,
    b: f64,
    target: f64,
) -> Result<Quadrature> {
    let bad = Cell::new(f64::NAN);
    let seen_bad = Cell::new(false);
    let g = |s: f64| {
        let v = f(s);
        if !v.is_finite() && !seen_bad.get() {
            seen_bad.set(true);
            bad.set(s);
        }
        v
    };
    let spent = Cell::new(0usize);
    let out = recurse(&g, &noise, a, b, target, 0, &spent);
    if seen_bad.get() {
        return Err(Error::NonFinite {
            what: format!(
                "quadrature integrand at s = {} (P ≤ 0 there: are the turning points right?)",
                bad.get()
            ),
            value: f(bad.get()),
        });
    }
    out
}

fn recurse(
    f: &impl Fn(f64) -> f64,
    noise_at: &impl Fn(f64) -> f64,
    a: f64,
    b: f64,
    target: f64,
    depth: u32,
    spent: &Cell<usize>,
) -> Result<Quadrature> {
    if a == b {
        return Ok(Quadrature::zero());
    }
    let o = quadrature::clenshaw_curtis::integrate(f, a, b, target);
    let q = Quadrature {
        value: o.integral,
        error: o.error_estimate,
        evaluations: o.num_function_evaluations as usize,
    };
    spent.set(spent.get() + q.evaluations);
    // The integrand's relative noise on this piece: the worst of its ends and middle.
    let noise = noise_at(a).max(noise_at(b)).max(noise_at(0.5 * (a + b)));
    if q.error <= target || q.error <= noise * q.value.abs() {
        // The estimate of the rule's convergence does not see the integrand's own noise or the
        // summation's rounding: both are added.
        return Ok(Quadrature {
            error: q.error + (noise + 4.0 * f64::EPSILON) * q.value.abs(),
            ..q
        });
    }
    if depth >= MAX_DEPTH || spent.get() > MAX_EVALUATIONS {
        return Err(Error::NotConverged {
            what: "adaptive Clenshaw–Curtis quadrature".into(),
            iterations: depth as usize,
            residual: q.error,
        });
    }
    let m = 0.5 * (a + b);
    let left = recurse(f, noise_at, a, m, 0.5 * target, depth + 1, spent)?;
    let right = recurse(f, noise_at, m, b, 0.5 * target, depth + 1, spent)?;
    Ok(left.add(right).add(Quadrature {
        value: 0.0,
        error: 0.0,
        evaluations: q.evaluations,
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Circle;
    impl Radicand for Circle {
        // F = 1 − x², roots ±1, P = 1.
        fn radicand<D: DualNum<f64> + Copy>(&self, x: D) -> D {
            -(x * x) + 1.0
        }
    }

    #[test]
    fn arcsine_integrals() {
        let lib = Libration::from_radicand(Circle, 0.3, -2.0, 2.0).unwrap();
        assert!((lib.lower() + 1.0).abs() < 1e-15 && (lib.upper() - 1.0).abs() < 1e-15);
        // ∫_{-1}^{1} dx/√(1−x²) = π, ∫ x² dx/√(1−x²) = π/2, ∫ √(1−x²) dx = π/2.
        let a = lib.inverse_sqrt_integral(|_| 1.0).unwrap();
        let b = lib.inverse_sqrt_integral(|x| x * x).unwrap();
        let c = lib.sqrt_integral().unwrap();
        assert!((a.value - PI).abs() < 4e-15, "{a:?}");
        assert!((b.value - FRAC_PI_2).abs() < 4e-15, "{b:?}");
        assert!((c.value - FRAC_PI_2).abs() < 4e-15, "{c:?}");
        // Partial: ∫_{-1}^{x} dξ/√(1−ξ²) = asin x + π/2.
        for x in [-0.999_999, -0.5, 0.0, 0.7, 0.999_999_999] {
            let p = lib.inverse_sqrt_integral_to(|_| 1.0, x).unwrap();
            assert!((p.value - (x.asin() + FRAC_PI_2)).abs() < 1e-14, "{x}");
        }
    }

    #[test]
    fn gauss_rule_is_exact_to_degree_15() {
        for k in 0..16 {
            let q: f64 = GAUSS8.iter().map(|&(t, w)| w * t.powi(k)).sum();
            assert!(
                (q - 1.0 / (k as f64 + 1.0)).abs() < 4e-16,
                "degree {k}: {q}"
            );
        }
    }

    #[test]
    fn degenerate_interval_gives_the_small_oscillation_limit() {
        // F = (x − 1)(1 − x)·4: P = 4, integral π/2.
        let lib = Libration::new(1.0, 1.0, |_: f64, _: f64, _: f64| 4.0).unwrap();
        let q = lib.inverse_sqrt_integral(|_| 1.0).unwrap();
        assert!((q.value - FRAC_PI_2).abs() < 1e-15);
    }

    #[test]
    fn refusals() {
        struct Hump;
        impl Radicand for Hump {
            // F = (1 − x²)²: double roots at ±1, F > 0 elsewhere.
            fn radicand<D: DualNum<f64> + Copy>(&self, x: D) -> D {
                let u = -(x * x) + 1.0;
                u * u
            }
        }
        struct Dip;
        impl Radicand for Dip {
            // F = ((x − 0.5)² − 1e−8)(x + 1.2): roots −1.2 and the close pair 0.5 ± 1e−4, which
            // the scan's geometric steps straddle; the nearest turning point above is 0.5 − 1e−4.
            fn radicand<D: DualNum<f64> + Copy>(&self, x: D) -> D {
                let u = x - 0.5;
                (u * u - 1e-8) * (x + 1.2)
            }
        }
        assert!(matches!(
            Libration::from_radicand(Hump, 0.0, -2.0, 2.0),
            Err(Error::Separatrix { .. })
        ));
        let (_, x2) = turning_points(&Dip, -1.0, -1.5, 2.0).unwrap();
        assert!((x2 - (0.5 - 1e-4)).abs() < 1e-15, "{x2}");
        assert!(turning_points(&Circle, 1.5, -2.0, 2.0).is_err());
        assert!(turning_points(&Circle, 0.0, -0.5, 0.5).is_err());
        assert!(turning_points(&Circle, f64::NAN, -2.0, 2.0).is_err());
        assert!(Libration::new(1.0, 0.0, |_: f64, _: f64, _: f64| 1.0).is_err());
        assert!(Libration::new(0.0, 1.0, |_: f64, _: f64, _: f64| -1.0).is_err());
    }
}

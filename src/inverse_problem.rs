//! The inverse problem of the calculus of variations for one degree of freedom (Ardema 4.4,
//! eqs. 4.32–4.37; SPEC M11, T37): given `ẍ = G(t, x, ẋ)`, find a Lagrangian `f(t, x, ẋ)` whose
//! Euler–Lagrange equation it is.
//!
//! Every such `f` has `M = f_ẋẋ` satisfying, along the solutions,
//!
//! ```math
//! \frac{dM}{dt} + G_{\dot x}\,M = 0,\qquad M = \Phi(c_1, c_2)\,
//! \exp\Big(-\int G_{\dot x}\,dt\Big),
//! ```
//!
//! and then `f = ∬M dẋ dẋ + ẋλ(t, x) + μ(t, x)` (the Lagrangian is not unique).
//! - **Affine in ẋ** (`G = −c(t)ẋ − ∂V/∂x(t, x)`): `M = e^{C(t)}` with `C = ∫₀ᵗ c`, and
//!   [`InverseLagrangian`] returns `f = e^{C(t)}(½ẋ² − V(t, x))` as a [`Lagrangian`] generic
//!   over [`DualNum`], so every method that takes a Lagrangian applies; its Euler–Lagrange
//!   expression is `e^{C}(ẍ + cẋ + ∂V/∂x)` (T37: `f = e^{ct}(½ẋ² − ½kx²)` for the damped
//!   oscillator, `f = ½ẋ² − V` for `c = 0`).
//! - **General `G`**: [`helmholtz_multiplier`] integrates `M` along a computed trajectory, from
//!   `d ln M/dt = −G_ẋ` with `G_ẋ` by AD.

use crate::error::{all_finite, finite, Error, Result};
use crate::integrate::{integrate, Dop853, FirstOrderSystem, Problem, Samples};
use crate::lagrangian::Lagrangian;
use nalgebra::SVector;
use num_dual::{Dual, Dual64, DualNum};

/// A second-order equation `ẍ = G(t, x, ẋ)` in one unknown, written once for every number type.
pub trait SecondOrderEquation {
    /// The acceleration `G(t, x, ẋ)`.
    fn acceleration<D: DualNum<f64> + Copy>(&self, t: D, x: D, xdot: D) -> D;
}

/// An equation `ẍ = −c(t)ẋ − ∂V/∂x(t, x)`, affine in the velocity, given by its damping rate and
/// potential (module docs).
pub trait AffineEquation {
    /// The damping rate `c(t)`.
    fn damping<D: DualNum<f64> + Copy>(&self, t: D) -> D;
    /// The potential `V(t, x)`.
    fn potential<D: DualNum<f64> + Copy>(&self, t: D, x: D) -> D;
    /// The integrated rate `C(t) = ∫₀ᵗ c(s) ds` in closed form, if known; `None` (default) has it
    /// computed by Gauss–Legendre quadrature.
    fn damping_integral<D: DualNum<f64> + Copy>(&self, _t: D) -> Option<D> {
        None
    }
}

/// Every affine equation is a second-order equation.
impl<A: AffineEquation> SecondOrderEquation for A {
    fn acceleration<D: DualNum<f64> + Copy>(&self, t: D, x: D, xdot: D) -> D {
        let vx = self
            .potential(Dual::from_re(t), Dual::new(x, D::from(1.0)))
            .eps;
        -self.damping(t) * xdot - vx
    }
}

/// The positive nodes `xᵢ` and weights `wᵢ` of the 16-point Gauss–Legendre rule on `[−1, 1]`
/// (Abramowitz & Stegun, Table 25.4); the rule is symmetric.
const GAUSS_16: [(f64, f64); 8] = [
    (0.095_012_509_837_637_44, 0.189_450_610_455_068_5),
    (0.281_603_550_779_258_9, 0.182_603_415_044_923_6),
    (0.458_016_777_657_227_4, 0.169_156_519_395_002_5),
    (0.617_876_244_402_643_8, 0.149_595_988_816_576_7),
    (0.755_404_408_355_003, 0.124_628_971_255_533_9),
    (0.865_631_202_387_831_7, 0.095_158_511_682_492_78),
    (0.944_575_023_073_232_6, 0.062_253_523_938_647_89),
    (0.989_400_934_991_649_9, 0.027_152_459_411_754_09),
];

/// The Lagrangian `f = e^{C(t)}(½ẋ² − V(t, x))` of an [`AffineEquation`] (module docs, SPEC M11).
///
/// Without a closed-form `C`, `C(t) = ∫₀ᵗ c` is the composite 16-point Gauss–Legendre rule on
/// `⌈|t|/Δ⌉` panels of length at most `Δ` (default 1), evaluated on the caller's number type, so
/// that `dC/dt = c(t)` to the rule's accuracy: for `c` analytic in a strip about the real axis
/// the error falls like `ρ^{−32}` with `ρ` set by the strip width in panel units.
#[derive(Clone, Copy, Debug)]
pub struct InverseLagrangian<A> {
    equation: A,
    panel: f64,
}

impl<A: AffineEquation> InverseLagrangian<A> {
    /// The Lagrangian of `equation`, quadrature panels of length 1.
    pub fn new(equation: A) -> Self {
        Self {
            equation,
            panel: 1.0,
        }
    }

    /// Quadrature panels of length at most `panel` (for a rate `c(t)` varying on shorter scales).
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] unless `panel` is positive and finite.
    pub fn with_panel(mut self, panel: f64) -> Result<Self> {
        self.panel = crate::error::positive("quadrature panel length Δ", panel)?;
        Ok(self)
    }

    /// The integrated damping rate `C(t) = ∫₀ᵗ c(s) ds`.
    pub fn damping_integral<D: DualNum<f64> + Copy>(&self, t: D) -> D {
        if let Some(c) = self.equation.damping_integral(t) {
            return c;
        }
        let span = t.re().abs();
        if !span.is_finite() {
            return t * f64::NAN;
        }
        // Bound the work: beyond 1e6 panels the integral is refused as NaN (the checked entry
        // points report it).
        let panels = (span / self.panel).ceil().max(1.0);
        if panels > 1e6 {
            return t * f64::NAN;
        }
        let n = panels as usize;
        let h = t / panels;
        let mut sum = D::from(0.0);
        for j in 0..n {
            for &(x, w) in &GAUSS_16 {
                let lo = h * (j as f64 + 0.5 - 0.5 * x);
                let hi = h * (j as f64 + 0.5 + 0.5 * x);
                sum += (self.equation.damping(lo) + self.equation.damping(hi)) * (0.5 * w);
            }
        }
        sum * h
    }

    /// The equation.
    pub fn equation(&self) -> &A {
        &self.equation
    }
}

impl<A: AffineEquation> Lagrangian<1> for InverseLagrangian<A> {
    fn lagrangian<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 1>,
        qdot: &SVector<D, 1>,
    ) -> D {
        self.damping_integral(t).exp()
            * (qdot[0] * qdot[0] * 0.5 - self.equation.potential(t, q[0]))
    }
}

/// `(x, ln M)` and `(ẋ, ·)`: the trajectory with its Helmholtz multiplier.
struct MultiplierSystem<'a, G>(&'a G);

impl<G: SecondOrderEquation> FirstOrderSystem<2> for MultiplierSystem<'_, G> {
    fn field(
        &self,
        t: f64,
        q: &SVector<f64, 2>,
        p: &SVector<f64, 2>,
    ) -> Result<(SVector<f64, 2>, SVector<f64, 2>)> {
        let g = self.0.acceleration(
            Dual64::from_re(t),
            Dual64::from_re(q[0]),
            Dual64::new(p[0], 1.0),
        );
        Ok((SVector::from([p[0], -g.eps]), SVector::from([g.re, 0.0])))
    }
}

/// One point of a trajectory of `ẍ = G` with the multiplier `M = f_ẋẋ` of any Lagrangian of the
/// equation, normalised to `M(t₀) = M₀`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MultiplierSample {
    /// Time.
    pub t: f64,
    /// Position `x(t)`.
    pub x: f64,
    /// Velocity `ẋ(t)`.
    pub xdot: f64,
    /// The multiplier `M(t) = M₀ exp(−∫ G_ẋ dt)`.
    pub multiplier: f64,
}

/// The Helmholtz multiplier `M = f_ẋẋ` along the solution of `ẍ = G(t, x, ẋ)` from
/// `(t₀, x₀, ẋ₀)`, at the requested times (module docs): `x`, `ẋ` and `ln M` integrated together
/// by DOP853 at the relative tolerance `rtol`, `G_ẋ` by AD.
///
/// # Errors
/// [`Error::NonFinite`] for non-finite input or a multiplier that overflows;
/// [`Error::OutOfDomain`] for `M₀ ≤ 0`, times outside `[t₀, t₁]` or a bad tolerance; the
/// integrator's errors.
pub fn helmholtz_multiplier<G: SecondOrderEquation>(
    equation: &G,
    t0: f64,
    x0: f64,
    xdot0: f64,
    m0: f64,
    times: &[f64],
    rtol: f64,
) -> Result<Vec<MultiplierSample>> {
    all_finite("initial state (t₀, x₀, ẋ₀)", &[t0, x0, xdot0])?;
    let m0 = crate::error::positive("initial multiplier M₀", m0)?;
    all_finite("sample times", times)?;
    let Some(&t1) = times
        .iter()
        .max_by(|a, b| (*a - t0).abs().total_cmp(&(*b - t0).abs()))
    else {
        return Ok(Vec::new());
    };
    if times.iter().any(|&t| (t - t0) * (t1 - t0) < 0.0) {
        return Err(Error::out_of_domain(
            "sample time",
            times
                .iter()
                .copied()
                .find(|&t| (t - t0) * (t1 - t0) < 0.0)
                .unwrap_or(f64::NAN),
            format!("on one side of t₀ = {t0:e}"),
        ));
    }
    let start = |t: f64| MultiplierSample {
        t,
        x: x0,
        xdot: xdot0,
        multiplier: m0,
    };
    if t1 == t0 {
        return Ok(times.iter().map(|&t| start(t)).collect());
    }
    let system = MultiplierSystem(equation);
    let problem = Problem::new(
        &system,
        t0,
        SVector::from([x0, m0.ln()]),
        SVector::from([xdot0, 0.0]),
        t1,
    )?;
    let mut order: Vec<usize> = (0..times.len()).collect();
    order.sort_by(|&a, &b| ((times[a] - t0).abs()).total_cmp(&(times[b] - t0).abs()));
    let inside: Vec<usize> = order.iter().copied().filter(|&i| times[i] != t0).collect();
    let mut samples = Samples::at(inside.iter().map(|&i| times[i]))?;
    integrate(&problem, &Dop853::new(rtol, rtol * 1e-3)?, &mut samples)?;
    let mut out: Vec<MultiplierSample> = times.iter().map(|&t| start(t)).collect();
    for (k, &i) in inside.iter().enumerate() {
        let s = &samples.states[k];
        out[i] = MultiplierSample {
            t: s.t,
            x: s.q[0],
            xdot: s.p[0],
            multiplier: finite("Helmholtz multiplier M", s.q[1].exp())?,
        };
    }
    Ok(out)
}

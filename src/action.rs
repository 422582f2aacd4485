//! The action of a path (SPEC M9): `S[q] = ∫_{t₀}^{t₁} L(t, q(t), q̇(t)) dt` on any path `q(t)`
//! the user writes once, its velocity `q̇(t)` by forward-mode AD of the path, the integral by
//! tanh–sinh (double-exponential) quadrature [Ardema §5.2, Hamilton's principle; Takahasi & Mori,
//! Publ. RIMS 9 (1974) 721–741].
//!
//! Hamilton's principle: among paths with fixed ends the motion makes `S` stationary, so the
//! first variation `dS/dε` of `S[q + εη]`, `η(t₀) = η(t₁) = 0`, vanishes on the motion; for the
//! harmonic oscillator the second variation `∫(m η̇² − k η²) dt` is positive on spans shorter than
//! half a period (no conjugate point) [Gelfand & Fomin, *Calculus of Variations*, §§25–27].
//!
//! Jacobi's form of the principle of least action (SPEC M12) [Ardema 4.5, eqs. 4.38–4.44]: for a
//! natural system with `T = ½ q̇ᵀ a(q) q̇` and `V(q)`, the motions of energy `h` are, as paths, the
//! geodesics of the Jacobi metric
//!
//! ```math
//! G(q) = 2\,(h - V(q))\,a(q),\qquad
//! \delta\!\int \sqrt{2(h - V)}\,ds = 0,\quad ds^2 = \dot q^{\mathsf T} a\,\dot q\,dt^2 ,
//! ```
//!
//! in the region `V < h`. Along a motion `√(G(q̇, q̇)) dt = 2T dt`, so the Jacobi length of its
//! path is the Maupertuis action `∫ 2T dt`. [`jacobi_metric`] returns the metric; as a
//! [`Lagrangian`] it is `√(G(q)(q′, q′))`, whose [`action`] is the Jacobi length of a path.

use crate::error::{all_finite, finite, Error, Result};
use crate::lagrangian::{Lagrangian, NaturalSystem};
use nalgebra::{SMatrix, SVector};
use num_dual::{Dual64, DualNum};
use std::cell::Cell;

/// The value of an action integral and what the quadrature reports about it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Action {
    /// `S = ∫ L dt`.
    pub value: f64,
    /// The estimate of its absolute error: the larger of the quadrature's own and the difference
    /// from the sum over the two halves of the span.
    pub error_estimate: f64,
    /// Evaluations of the Lagrangian.
    pub evaluations: usize,
}

/// `S = ∫_{t₀}^{t₁} L(t, q(t), q̇(t)) dt` along `path` (see the [module docs](self)): `path(t)`
/// gives `q(t)` for a dual time `t = t + ε`, whose dual parts are `q̇(t)`. The quadrature aims at
/// an absolute error `tolerance · max(|L(t₀)|, |L(t_mid)|, |L(t₁)|) · |t₁ − t₀|`.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ bounds or tolerance, or a path or Lagrangian that is not
/// finite somewhere on the span (naming the time); [`Error::InvalidInput`] for `t₀ = t₁` or a
/// tolerance outside `[1e-15, 1)`; [`Error::NotConverged`] when the quadrature's error estimate,
/// or its disagreement with the sum over the two halves of the span, exceeds 100 times its
/// target.
pub fn action<L, P, const N: usize>(
    lagrangian: &L,
    path: P,
    t0: f64,
    t1: f64,
    tolerance: f64,
) -> Result<Action>
where
    L: Lagrangian<N>,
    P: Fn(Dual64) -> SVector<Dual64, N>,
{
    let t0 = finite("t₀", t0)?;
    let t1 = finite("t₁", t1)?;
    let tolerance = finite("tolerance", tolerance)?;
    if !(1e-15..1.0).contains(&tolerance) {
        return Err(Error::invalid(
            "tolerance",
            format!("expected a relative tolerance in [1e-15, 1), found {tolerance}"),
        ));
    }
    let span = t1 - t0;
    if span == 0.0 || !span.is_finite() {
        return Err(Error::invalid(
            "span",
            format!("t₀ = {t0}, t₁ = {t1}: expected a finite, non-empty span"),
        ));
    }
    let bad: Cell<Option<(f64, f64)>> = Cell::new(None);
    let count = Cell::new(0usize);
    let integrand = |t: f64| -> f64 {
        count.set(count.get() + 1);
        let q = path(Dual64::new(t, 1.0));
        let (qv, vv) = (q.map(|x| x.re), q.map(|x| x.eps));
        let l = lagrangian.lagrangian(t, &qv, &vv);
        if !l.is_finite() && bad.get().is_none() {
            bad.set(Some((t, l)));
        }
        l
    };
    let scale = [t0, 0.5 * (t0 + t1), t1]
        .iter()
        .map(|&t| integrand(t).abs())
        .fold(0.0, f64::max);
    if let Some((t, value)) = bad.get() {
        return Err(non_finite(t, value));
    }
    let target = (tolerance * scale * span.abs()).max(f64::MIN_POSITIVE);
    let out = quadrature::double_exponential::integrate(integrand, t0, t1, target);
    // The same integral over the two halves of the span: a path the quadrature does not resolve
    // (e.g. far too many oscillations on the span) gives two sums that disagree.
    let tm = 0.5 * t0 + 0.5 * t1;
    let left = quadrature::double_exponential::integrate(integrand, t0, tm, 0.5 * target);
    let right = quadrature::double_exponential::integrate(integrand, tm, t1, 0.5 * target);
    if let Some((t, value)) = bad.get() {
        return Err(non_finite(t, value));
    }
    let value = finite("action ∫ L dt", out.integral)?;
    let disagreement = (out.integral - (left.integral + right.integral)).abs();
    let estimate = out.error_estimate.max(disagreement);
    if estimate.is_nan() || estimate > 100.0 * target {
        return Err(Error::NotConverged {
            what: format!(
                "tanh–sinh quadrature of the action over [{t0}, {t1}] (target error {target:e})"
            ),
            iterations: out.num_function_evaluations as usize,
            residual: estimate,
        });
    }
    Ok(Action {
        value,
        error_estimate: estimate,
        evaluations: count.get(),
    })
}

fn non_finite(t: f64, value: f64) -> Error {
    Error::NonFinite {
        what: format!("L(t, q(t), q̇(t)) on the path at t = {t}"),
        value,
    }
}

/// The Jacobi metric `G(q) = 2(h − V(q)) a(q)` of a natural system at the energy `h` (see the
/// [module docs](self)).
///
/// The system must be scleronomic with `T` quadratic in `q̇` (`b = 0`, `c = 0` in
/// [`NaturalSystem`]); `a` and `V` are evaluated at `t = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Metric<S, const N: usize> {
    system: S,
    energy: f64,
}

/// The Jacobi metric of `system` at the energy `h` (SPEC M12: `jacobi_metric(mass_matrix, v, h)`,
/// the mass matrix and `V` being those of the [`NaturalSystem`]) [Ardema eq. 4.43].
///
/// # Errors
/// [`Error::NonFinite`] for a non-finite `h`.
pub fn jacobi_metric<S: NaturalSystem<N>, const N: usize>(
    system: S,
    h: f64,
) -> Result<Metric<S, N>> {
    Ok(Metric {
        system,
        energy: finite("energy h", h)?,
    })
}

impl<S: NaturalSystem<N>, const N: usize> Metric<S, N> {
    /// The energy `h`.
    pub fn energy(&self) -> f64 {
        self.energy
    }

    /// The system.
    pub fn system(&self) -> &S {
        &self.system
    }

    /// The conformal factor `2(h − V(q))`, positive where motion at energy `h` is possible.
    pub fn conformal_factor<D: DualNum<f64> + Copy>(&self, q: &SVector<D, N>) -> D {
        (-self.system.potential(D::from(0.0), q) + self.energy) * 2.0
    }

    /// The metric tensor `G(q) = 2(h − V(q)) a(q)`.
    pub fn tensor<D: DualNum<f64> + Copy>(&self, q: &SVector<D, N>) -> SMatrix<D, N, N> {
        self.system.mass(D::from(0.0), q) * self.conformal_factor(q)
    }

    /// The squared length `G(q)(dq, dq)` of the displacement `dq` at `q`.
    pub fn squared_norm<D: DualNum<f64> + Copy>(&self, q: &SVector<D, N>, dq: &SVector<D, N>) -> D {
        (self.system.mass(D::from(0.0), q) * dq).dot(dq) * self.conformal_factor(q)
    }

    /// `2(h − V(q))` on reals, checked: positive and finite inside the region of motion.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ in `q` or the value; [`Error::OutOfDomain`] where
    /// `V(q) ≥ h` (outside the region of motion, where the metric degenerates).
    pub fn checked_conformal_factor(&self, q: &SVector<f64, N>) -> Result<f64> {
        all_finite("configuration q", q.as_slice())?;
        let f = finite(
            format_args!("2(h − V) at q = {q:?}"),
            self.conformal_factor(q),
        )?;
        if f > 0.0 {
            Ok(f)
        } else {
            Err(Error::out_of_domain(
                format!("2(h − V(q)) at q = {q:?} (h = {})", self.energy),
                f,
                "(0, ∞): the region of motion V < h",
            ))
        }
    }
}

impl<S: NaturalSystem<N>, const N: usize> Lagrangian<N> for Metric<S, N> {
    /// `√(G(q)(q′, q′))`: its [`action`] along a path is the path's Jacobi length
    /// `∫ √(2(h − V)) ds` (NaN outside the region of motion).
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, N>, v: &SVector<D, N>) -> D {
        self.squared_norm(q, v).sqrt()
    }
}

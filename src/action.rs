//! The action of a path (SPEC M9): `S[q] = ∫_{t₀}^{t₁} L(t, q(t), q̇(t)) dt` on any path `q(t)`
//! the user writes once, its velocity `q̇(t)` by forward-mode AD of the path, the integral by
//! tanh–sinh (double-exponential) quadrature [Ardema §5.2, Hamilton's principle; Takahasi & Mori,
//! Publ. RIMS 9 (1974) 721–741].
//!
//! Hamilton's principle: among paths with fixed ends the motion makes `S` stationary, so the
//! first variation `dS/dε` of `S[q + εη]`, `η(t₀) = η(t₁) = 0`, vanishes on the motion; for the
//! harmonic oscillator the second variation `∫(m η̇² − k η²) dt` is positive on spans shorter than
//! half a period (no conjugate point) [Gelfand & Fomin, *Calculus of Variations*, §§25–27].

use crate::error::{finite, Error, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::SVector;
use num_dual::Dual64;
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

//! Liouville's separable Lagrangian systems and their separated integrals
//! [Ardema 8.4, eqs. 8.38–8.40].
//!
//! A Liouville system has
//!
//! ```math
//! T = \tfrac12\, U \sum_s v_s(q_s)\, \dot q_s^2,\qquad V = \frac{W}{U},\qquad
//! U = \sum_s u_s(q_s),\quad W = \sum_s w_s(q_s),
//! ```
//!
//! every function depending on its own coordinate only. Besides the energy
//! `h = T + V` it has the `N` separated integrals `γ_s`,
//!
//! ```math
//! \tfrac12\, U^2 v_s \dot q_s^2 = h\, u_s - w_s + \gamma_s,\qquad \sum_s \gamma_s = 0 ,
//! ```
//!
//! (summing over `s` gives `U T = h U − W`, i.e. the energy itself, so only `N − 1` of them are
//! new). With the new independent variable `dτ = dt/U` each coordinate moves in a one-dimensional
//! problem `½ v_s (dq_s/dτ)² = h u_s − w_s + γ_s`, which is why these systems separate in the
//! Hamilton–Jacobi equation [Ardema 17.5]. Uncoupled systems `T = ½ Σ v_s q̇_s²`, `V = Σ w_s` are
//! the case `U ≡ 1` (`u₁ = 1`, the other `u_s = 0`), where the `γ_s + h u_s` are the separate
//! energies `½ v_s q̇_s² + w_s`.

use crate::error::{all_finite, finite, Error, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::SVector;
use num_dual::DualNum;

/// The functions `u_s, v_s, w_s` of a Liouville system (see the [module docs](self)), each of its
/// own coordinate `q_s` only (`s = 0 … N−1`), written once for every dual type.
///
/// `T` is positive definite where `U v_s > 0` for all `s`.
pub trait LiouvilleSystem<const N: usize> {
    /// `u_s(q_s)`, the terms of `U`.
    fn u<D: DualNum<f64> + Copy>(&self, s: usize, q_s: D) -> D;
    /// `v_s(q_s)`, the kinetic weights.
    fn v<D: DualNum<f64> + Copy>(&self, s: usize, q_s: D) -> D;
    /// `w_s(q_s)`, the terms of `W`.
    fn w<D: DualNum<f64> + Copy>(&self, s: usize, q_s: D) -> D;
}

/// A [`LiouvilleSystem`] as a [`Lagrangian`]: `L = ½ U Σ v_s q̇_s² − W/U` [Ardema eq. 8.38]; all
/// of the crate's Lagrangian machinery (Lagrange's equations by AD, the Legendre transform, the
/// Jacobi integral) applies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Liouville<S>(pub S);

/// `(U, W, Σ v_s q̇_s²)` in any number type.
fn sums<S: LiouvilleSystem<N>, D: DualNum<f64> + Copy, const N: usize>(
    s: &S,
    q: &SVector<D, N>,
    qdot: &SVector<D, N>,
) -> (D, D, D) {
    (0..N).fold(
        (D::from(0.0), D::from(0.0), D::from(0.0)),
        |(u, w, k), r| {
            (
                u + s.u(r, q[r]),
                w + s.w(r, q[r]),
                k + s.v(r, q[r]) * qdot[r] * qdot[r],
            )
        },
    )
}

impl<S: LiouvilleSystem<N>, const N: usize> Lagrangian<N> for Liouville<S> {
    fn lagrangian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, N>,
        qdot: &SVector<D, N>,
    ) -> D {
        let (u, w, k) = sums(&self.0, q, qdot);
        u * k * 0.5 - w / u
    }
}

/// The energy `h = T + V` and the separated integrals `γ_s = ½ U² v_s q̇_s² − h u_s + w_s` of a
/// Liouville system at the state `(q, q̇)` [Ardema eqs. 8.39–8.40]; `Σ γ_s = 0` identically.
///
/// Errors: [`Error::NonFinite`] for NaN/∞ in the state or in `u_s, v_s, w_s`;
/// [`Error::OutOfDomain`] where `U = 0` (the potential `W/U` is undefined there).
///
/// ```
/// use hamilton_jacobi::hamilton_jacobi::{liouville_separated_integrals, LiouvilleSystem};
/// use hamilton_jacobi::{DualNum, nalgebra::SVector};
/// /// A Liouville system [Ardema 8.4]: U = q₁² + q₂², v = 1, W = q₁⁴ + q₂⁴.
/// struct QuarticLiouville;
/// impl LiouvilleSystem<2> for QuarticLiouville {
///     fn u<D: DualNum<f64> + Copy>(&self, _s: usize, q: D) -> D { q * q }
///     fn v<D: DualNum<f64> + Copy>(&self, _s: usize, _q: D) -> D { D::from(1.0) }
///     fn w<D: DualNum<f64> + Copy>(&self, _s: usize, q: D) -> D { q.powi(4) }
/// }
/// let (h, g) = liouville_separated_integrals(
///     &QuarticLiouville, &SVector::from([1.0, 0.5]), &SVector::from([0.2, -0.3])).unwrap();
/// assert!((h - 0.93125).abs() < 1e-15);
/// assert!((g[0] - 0.1).abs() < 1e-15 && (g[0] + g[1]).abs() < 1e-15);
/// ```
pub fn liouville_separated_integrals<S: LiouvilleSystem<N> + ?Sized, const N: usize>(
    system: &S,
    q: &SVector<f64, N>,
    qdot: &SVector<f64, N>,
) -> Result<(f64, SVector<f64, N>)> {
    all_finite("q", q.as_slice())?;
    all_finite("q̇", qdot.as_slice())?;
    let us = SVector::<f64, N>::from_fn(|r, _| system.u(r, q[r]));
    let vs = SVector::<f64, N>::from_fn(|r, _| system.v(r, q[r]));
    let ws = SVector::<f64, N>::from_fn(|r, _| system.w(r, q[r]));
    all_finite(format_args!("u_s(q_s) at q = {q:?}; u"), us.as_slice())?;
    all_finite(format_args!("v_s(q_s) at q = {q:?}; v"), vs.as_slice())?;
    all_finite(format_args!("w_s(q_s) at q = {q:?}; w"), ws.as_slice())?;
    let u = us.sum();
    if u == 0.0 {
        return Err(Error::out_of_domain(
            format!("U = Σ u_s(q_s) at q = {q:?}"),
            u,
            "U ≠ 0 (V = W/U)",
        ));
    }
    let w = ws.sum();
    // ½ v_s q̇_s², the separated kinetic terms.
    let ks = SVector::<f64, N>::from_fn(|r, _| 0.5 * vs[r] * qdot[r] * qdot[r]);
    let h = finite("energy h = T + V", u * ks.sum() + w / u)?;
    let gammas = SVector::<f64, N>::from_fn(|r, _| u * u * ks[r] - h * us[r] + ws[r]);
    all_finite("γ", gammas.as_slice())?;
    Ok((h, gammas))
}

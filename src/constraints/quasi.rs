//! Quasi-velocities (non-holonomic velocity parameters) and Hamel's coefficients (SPEC M63–M64).
//!
//! `ω_μ = Σ_ν b_μν(q) q̇_ν`, μ = 1 … n, the first `m` of them set to zero by the constraints;
//! inverse `q̇ = B ω`, `B = b⁻¹` [Hamel art. 232, (1)–(12)]. Rheonomic systems adjoin time as a
//! coordinate `q_k = t` whose row of `b` is the unit row, so that `ω_k = ṫ = 1` (SPEC §0.7).
//! The transitional relations [Hamel art. 232–233, (13)–(16)] carry Hamel's coefficients
//!
//! ```math
//! \beta_\mu^{\tau\rho} = \sum_{\nu,\sigma}
//! \Big(\frac{\partial b_{\mu\nu}}{\partial q_\sigma} - \frac{\partial b_{\mu\sigma}}{\partial q_\nu}\Big)
//! B_{\sigma\tau} B_{\nu\rho} = -\beta_\mu^{\rho\tau},
//! ```
//!
//! with the index placement of SPEC M64; `ϑ_μ` is a true coordinate iff all `β_μ^{··}` vanish.

use crate::ad::GradDual;
use crate::error::{all_finite, Result};
use crate::phase::checked_inverse;
use nalgebra::{Const, SMatrix, SVector};
use num_dual::DualNum;

/// Quasi-velocities `ω = b(q) q̇` of a system with `N` coordinates, the first
/// [`constrained`](QuasiVelocities::constrained) of them zero on the constrained motions.
pub trait QuasiVelocities<const N: usize> {
    /// The number `m` of constrained quasi-velocities (the first `m` rows of `b`).
    fn constrained(&self) -> usize;

    /// The index of the coordinate that is time itself (`q_k = t`, row `k` of `b` the unit row,
    /// `ω_k = 1`), for rheonomic systems; `None` (default) otherwise.
    fn time_coordinate(&self) -> Option<usize> {
        None
    }

    /// The matrix `b(q)` of `ω = b q̇`.
    fn matrix<D: DualNum<f64> + Copy>(&self, q: &SVector<D, N>) -> SMatrix<D, N, N>;
}

/// Hamel's coefficients and the transformation at a configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct HamelCoefficients<const N: usize> {
    /// `b(q)`.
    pub b: SMatrix<f64, N, N>,
    /// `B = b⁻¹`, so that `q̇ = B ω`.
    pub big_b: SMatrix<f64, N, N>,
    /// `beta[μ][(τ, ρ)] = β_μ^{τρ}`.
    pub beta: Vec<SMatrix<f64, N, N>>,
}

/// `b`, `B` and Hamel's coefficients `β_μ^{τρ}` at `q`, the derivatives of `b` by AD.
///
/// # Errors
/// NaN/∞ in `q` or in `b` and its derivatives; [`Error::Singular`](crate::Error::Singular) naming
/// `q` when `b` is not invertible there.
pub fn hamel_coefficients<Q: QuasiVelocities<N> + ?Sized, const N: usize>(
    quasi: &Q,
    q: &SVector<f64, N>,
) -> Result<HamelCoefficients<N>> {
    all_finite("q", q.as_slice())?;
    let qd: SVector<GradDual<f64, f64, Const<N>>, N> =
        SVector::from_fn(|i, _| GradDual::variable(q[i], i));
    let bd = quasi.matrix(&qd);
    let b = bd.map(|x| *x.value());
    all_finite(
        format!("quasi-velocity matrix b at q = {q:?}"),
        b.as_slice(),
    )?;
    for x in bd.iter() {
        all_finite(format!("∂b/∂q at q = {q:?}"), x.eps().as_slice())?;
    }
    let big_b = checked_inverse(&b, "quasi-velocity matrix b", || format!("q = {q:?}"))?;
    let beta = (0..N)
        .map(|mu| {
            // c[(ν, σ)] = ∂b_μν/∂q_σ − ∂b_μσ/∂q_ν;  β_μ = Bᵀ cᵀ B.
            let c = SMatrix::<f64, N, N>::from_fn(|nu, sg| {
                bd[(mu, nu)].eps()[sg] - bd[(mu, sg)].eps()[nu]
            });
            big_b.transpose() * c.transpose() * big_b
        })
        .collect();
    Ok(HamelCoefficients { b, big_b, beta })
}

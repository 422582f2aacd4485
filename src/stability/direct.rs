//! The direct method of stability (SPEC M37) [Ardema 12.5, eqs. 12.19–12.26]: no solution of the
//! equations of motion is needed, only a function and its derivatives by AD.
//!
//! * **Lagrange–Dirichlet.** An equilibrium `q*` of a natural system has `∇V(q*) = 0`; a strict
//!   local minimum of `V` is stable. [`dirichlet_check`] tests the sufficient condition that the
//!   Hessian `∇²V(q*)` (by AD) is positive definite.
//! * **Lyapunov.** For `ż = f(t, z)` with the reference motion at `z = 0` and a candidate `V(t, z)`
//!   positive definite, `V̇ = ∂V/∂t + ∇V · f ≤ 0` implies stability and `V̇` negative definite
//!   asymptotic stability. [`lyapunov_derivative`] gives `V̇` at a point in one forward-mode pass:
//!   `V̇ = d/ds V(t + s, z + s f(t, z))` at `s = 0`, the candidate written once over
//!   [`DualNum`](num_dual::DualNum) ([`ScalarField`]).

use super::equilibrium::EQUILIBRIUM_TOLERANCE;
use super::spectrum::KERNEL_TOLERANCE;
use crate::ad::{gradient, GradDual, GradDual64};
use crate::error::{all_finite, finite, Error, Result};
use crate::hamilton_jacobi::{ScalarField, VectorField};
use nalgebra::{DMatrix, SMatrix, SVector, SymmetricEigen};
use num_dual::Dual64;

/// The outcome of [`dirichlet_check`].
#[derive(Clone, Debug, PartialEq)]
pub struct DirichletCheck<const N: usize> {
    /// `|∇V(q*)|`.
    pub gradient_norm: f64,
    /// `∇²V(q*)` by AD.
    pub hessian: SMatrix<f64, N, N>,
    /// Its eigenvalues, increasing.
    pub eigenvalues: SVector<f64, N>,
    /// Whether every eigenvalue exceeds `KERNEL_TOLERANCE · max(1, max|λ|)`: a strict minimum,
    /// hence a stable equilibrium (Lagrange–Dirichlet).
    pub strict_minimum: bool,
}

/// The Lagrange–Dirichlet test at the equilibrium `q*` of the potential `v` at time `t`
/// (SPEC M37: `dirichlet_check(v, q_star)`): the gradient must vanish
/// (`|∇V| ≤ 10⁻¹⁰ max(1, ‖∇²V‖_max)`), and the Hessian's eigenvalues decide — all positive, a
/// strict minimum, stable. A Hessian with a zero or negative eigenvalue leaves the test
/// inconclusive (`strict_minimum = false`; a maximum of `V` is unstable by Lyapunov's theorem
/// for analytic `V`, which this function does not decide).
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ in `t`, `q*`, `V` or its derivatives; [`Error::InvalidInput`]
/// when `q*` is not stationary.
pub fn dirichlet_check<V: ScalarField<N> + ?Sized, const N: usize>(
    v: &V,
    t: f64,
    q_star: &SVector<f64, N>,
) -> Result<DirichletCheck<N>> {
    finite("t", t)?;
    all_finite("q*", q_star.as_slice())?;
    let x: SVector<GradDual64<N>, N> = SVector::from_fn(|i, _| GradDual64::variable(q_star[i], i));
    let td = GradDual64::<N>::from_re(t);
    let (value, g) = gradient(|y| v.eval(GradDual::from_re(td), y), &x);
    finite("V(q*)", *value.value())?;
    let grad = g.map(|d| *d.value());
    let hess = SMatrix::<f64, N, N>::from_fn(|i, j| g[i].eps()[j]);
    all_finite("∇V(q*)", grad.as_slice())?;
    all_finite("∇²V(q*)", hess.as_slice())?;
    let hess = (hess + hess.transpose()) * 0.5;
    let gradient_norm = grad.norm();
    if gradient_norm > EQUILIBRIUM_TOLERANCE * hess.amax().max(1.0) {
        return Err(Error::invalid(
            "equilibrium q*",
            format!("|∇V(q*)| = {gradient_norm:e}: not a stationary point of V"),
        ));
    }
    let dense = DMatrix::from_column_slice(N, N, hess.as_slice());
    let mut eigenvalues =
        SVector::<f64, N>::from_column_slice(SymmetricEigen::new(dense).eigenvalues.as_slice());
    eigenvalues.as_mut_slice().sort_by(f64::total_cmp);
    let top = eigenvalues.amax().max(1.0);
    let strict_minimum = eigenvalues.iter().all(|&l| l > KERNEL_TOLERANCE * top);
    Ok(DirichletCheck {
        gradient_norm,
        hessian: hess,
        eigenvalues,
        strict_minimum,
    })
}

/// Lyapunov's derivative `V̇ = ∂V/∂t + ∇V · f(t, z)` of the candidate `v` along `ż = f(t, z)` at
/// `(t, z)` (SPEC M37: `lyapunov_derivative(v, rhs, eta, t)`), by one forward-mode AD pass.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ in `t`, `z`, the field or `V̇`.
pub fn lyapunov_derivative<V, X, const M: usize>(
    v: &V,
    field: &X,
    t: f64,
    z: &SVector<f64, M>,
) -> Result<f64>
where
    V: ScalarField<M> + ?Sized,
    X: VectorField<M> + ?Sized,
{
    finite("t", t)?;
    all_finite("z", z.as_slice())?;
    let f = field.field(t, z);
    all_finite(format_args!("f at t = {t}, z = {z:?}"), f.as_slice())?;
    let zd = SVector::<Dual64, M>::from_fn(|i, _| Dual64::new(z[i], f[i]));
    let vd = v.eval(Dual64::new(t, 1.0), &zd);
    finite(format_args!("V at t = {t}, z = {z:?}"), vd.re)?;
    finite(format_args!("V̇ at t = {t}, z = {z:?}"), vd.eps)
}

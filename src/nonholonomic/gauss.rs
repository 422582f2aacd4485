//! Gauss's principle of least constraint (SPEC M43) [Ardema 14.3; Hamel art. 247, 252]: among
//! the accelerations compatible with the constraints the actual one minimises
//!
//! $$ Z(\ddot q) = \tfrac12 (a\ddot q - f)^{\mathsf T} a^{-1} (a\ddot q - f), $$
//!
//! `a = ∂²L/∂q̇²`, `a q̈ = f` Lagrange's equations without constraints (for particles
//! `Z = ½ Σ m |ẍ − F/m|²`). The velocity constraints, differentiated once, restrict `q̈` to the
//! affine set `G q̈ + ∂g/∂q q̇ + ∂g/∂t = 0`; it is parametrised as `q̈ = q̈_p + 𝒩 z` (minimum-norm
//! particular solution, `𝒩` an orthonormal basis of `ker G` from the SVD) and `Z` is minimised
//! over `z` with `argmin`'s Newton method.

use super::{at, lagrange_terms, Constrained};
use crate::constraints::{check_rank, velocity_jet, VelocityConstraints};
use crate::error::{Error, Result};
use crate::lagrangian::Lagrangian;
use crate::phase::checked_inverse;
use argmin::core::{Executor, Gradient, Hessian, State};
use argmin::solver::newton::Newton;
use nalgebra::{DMatrix, DVector, SVector};

/// The minimiser of Gauss's constraint.
#[derive(Clone, Debug, PartialEq)]
pub struct GaussMinimum<const N: usize> {
    /// The accelerations `q̈` minimising `Z`.
    pub qddot: SVector<f64, N>,
    /// The least value of `Z`.
    pub z: f64,
}

/// `Z` restricted to the admissible accelerations, as an `argmin` problem in `z`.
struct Restricted {
    a: DMatrix<f64>,
    f: DVector<f64>,
    null: DMatrix<f64>,
    particular: DVector<f64>,
}

impl Gradient for Restricted {
    type Param = DVector<f64>;
    type Gradient = DVector<f64>;
    fn gradient(&self, z: &DVector<f64>) -> std::result::Result<DVector<f64>, argmin::core::Error> {
        let qdd = &self.particular + &self.null * z;
        Ok(self.null.transpose() * (&self.a * qdd - &self.f))
    }
}

impl Hessian for Restricted {
    type Param = DVector<f64>;
    type Hessian = DMatrix<f64>;
    fn hessian(&self, _z: &DVector<f64>) -> std::result::Result<DMatrix<f64>, argmin::core::Error> {
        Ok(self.null.transpose() * &self.a * &self.null)
    }
}

/// The accelerations of least constraint of `system` at `(t, q, q̇)` and the value of `Z`.
///
/// # Errors
/// NaN/∞; [`Error::RankDeficient`] for dependent constraint rows; [`Error::Singular`] for a
/// singular mass matrix; [`Error::NotConverged`] if the minimisation fails.
pub fn gauss_accelerations<L, C, const N: usize, const K: usize>(
    system: &Constrained<L, C, N, K>,
    t: f64,
    q: &SVector<f64, N>,
    qdot: &SVector<f64, N>,
) -> Result<GaussMinimum<N>>
where
    L: Lagrangian<N>,
    C: VelocityConstraints<N, K>,
{
    let jet = velocity_jet(&system.constraints, t, q, qdot)?;
    check_rank(&jet.gradient, "constraint matrix ∂g/∂q̇", t, || {
        at(q, qdot)
    })?;
    let (a, f) = lagrange_terms(&system.lagrangian, t, q, qdot)?;
    let ainv = checked_inverse(&a, "mass matrix ∂²L/∂q̇²", || {
        format!("t = {t}, {}", at(q, qdot))
    })?;
    // Full SVD of G padded to N × N: the last N − K right singular vectors span ker G.
    let g = DMatrix::from_fn(N, N, |i, j| if i < K { jet.gradient[(i, j)] } else { 0.0 });
    let svd = g.clone().svd(true, true);
    let vt = svd
        .v_t
        .as_ref()
        .ok_or_else(|| Error::invalid("Gauss's principle", "SVD of ∂g/∂q̇ failed"))?;
    let mut order: Vec<usize> = (0..N).collect();
    order.sort_by(|&i, &j| svd.singular_values[j].total_cmp(&svd.singular_values[i]));
    let null = DMatrix::from_fn(N, N - K, |i, j| vt[(order[K + j], i)]);
    let rate = DVector::from_fn(N, |i, _| if i < K { -jet.rate[i] } else { 0.0 });
    let particular = svd
        .solve(&rate, 0.0)
        .map_err(|e| Error::invalid("Gauss's principle", e.to_string()))?;
    let problem = Restricted {
        a: DMatrix::from_column_slice(N, N, a.as_slice()),
        f: DVector::from_column_slice(f.as_slice()),
        null,
        particular,
    };
    let res = Executor::new(problem, Newton::<f64>::new())
        .configure(|s| s.param(DVector::zeros(N - K)).max_iters(3))
        .run()
        .map_err(|e| Error::NotConverged {
            what: format!("Gauss's principle (argmin Newton): {e}"),
            iterations: 3,
            residual: f64::NAN,
        })?;
    let z = res
        .state()
        .get_param()
        .cloned()
        .ok_or_else(|| Error::invalid("Gauss's principle", "no minimiser returned"))?;
    let pr = res
        .problem
        .problem
        .as_ref()
        .ok_or_else(|| Error::invalid("Gauss's principle", "problem not returned"))?;
    let qdd = &pr.particular + &pr.null * z;
    let qddot = SVector::<f64, N>::from_column_slice(qdd.as_slice());
    let r = a * qddot - f;
    let zval = 0.5 * r.dot(&(ainv * r));
    crate::error::all_finite(format!("q̈ at t = {t}, {}", at(q, qdot)), qddot.as_slice())?;
    crate::error::finite("Gauss's constraint Z", zval)?;
    Ok(GaussMinimum { qddot, z: zval })
}

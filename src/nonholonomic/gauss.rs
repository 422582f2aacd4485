//! Gauss's principle of least constraint (SPEC M43) [Ardema 14.3; Hamel art. 247, 252]: among
//! the accelerations compatible with the constraints the actual one minimises
//!
//! ```math
//! Z(\ddot q) = \tfrac12 (a\ddot q - f)^{\mathsf T} a^{-1} (a\ddot q - f),
//! ```
//!
//! `a = ∂²L/∂q̇²`, `a q̈ = f` Lagrange's equations without constraints (for particles
//! `Z = ½ Σ m |ẍ − F/m|²`). The velocity constraints, differentiated once, restrict `q̈` to the
//! affine set `G q̈ + ∂g/∂q q̇ + ∂g/∂t = 0`; it is parametrised as `q̈ = q̈_p + 𝒩 z` (minimum-norm
//! particular solution, `𝒩` an orthonormal basis of `ker G` from the SVD) and `Z` is minimised
//! over `z` with `argmin`'s Newton method ([`gauss_accelerations`]).
//!
//! Constraints of the second class `g(t, q, q̇, q̈) = 0`, non-linear in `q̈` (SPEC M69), may give
//! several stationary points of `Z`; [`gauss_stationary_points`] returns all it finds and marks
//! the minimiser, Hamel's selection [Hamel art. 252].

use super::{at, lagrange_terms, Constrained};
use crate::ad::{real_times, GradDual};
use crate::constraints::{check_rank, velocity_jet, AccelerationConstraints, VelocityConstraints};
use crate::error::{Error, Result};
use crate::implicit::{self, ImplicitSystem};
use crate::lagrangian::Lagrangian;
use crate::phase::checked_inverse;
use argmin::core::{Executor, Gradient, Hessian, State};
use argmin::solver::newton::Newton;
use nalgebra::{Const, DMatrix, DVector, SMatrix, SVector};
use num_dual::linalg::LU;
use num_dual::DualNum;

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
        at(q, qdot).to_string()
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
    crate::error::all_finite(
        format_args!("q̈ at t = {t}, {}", at(q, qdot)),
        qddot.as_slice(),
    )?;
    crate::error::finite("Gauss's constraint Z", zval)?;
    Ok(GaussMinimum { qddot, z: zval })
}

/// A stationary point of Gauss's constraint under acceleration constraints.
#[derive(Clone, Debug, PartialEq)]
pub struct Stationary<const N: usize> {
    /// The accelerations.
    pub qddot: SVector<f64, N>,
    /// The value of `Z` there.
    pub z: f64,
}

/// The stationary points of Gauss's constraint and the minimiser among them.
#[derive(Clone, Debug, PartialEq)]
pub struct StationaryPoints<const N: usize> {
    /// Every distinct stationary point found, in order of increasing `Z`.
    pub points: Vec<Stationary<N>>,
    /// Index of the minimiser in `points` (always 0; [Hamel art. 252]'s selection, not
    /// physically established).
    pub minimizer: usize,
}

/// Stationarity of `Z` on `g(t, q, q̇, q̈) = 0` as `N` equations in `q̈`:
/// `r = P⊥(a q̈ − f) + Jᵀ(JJᵀ)⁻¹ g`, `J = ∂g/∂q̈`, `P⊥ = 1 − Jᵀ(JJᵀ)⁻¹J`; the two parts lie in
/// complementary subspaces, so `r = 0` iff `a q̈ − f ∈ range Jᵀ` and `g = 0`.
struct Stationarity<'a, A, const N: usize, const K: usize> {
    constraints: &'a A,
    a: SMatrix<f64, N, N>,
    f: SVector<f64, N>,
}

impl<A: AccelerationConstraints<N, K>, const N: usize, const K: usize> ImplicitSystem<N>
    for Stationarity<'_, A, N, K>
{
    fn residual<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        qdot: &SVector<D, N>,
        u: &SVector<D, N>,
    ) -> SVector<D, N> {
        let ud: SVector<GradDual<D, f64, Const<N>>, N> =
            SVector::from_fn(|i, _| GradDual::variable(u[i], i));
        let gd = self.constraints.acceleration_constraint(
            GradDual::from_re(t),
            &q.map(GradDual::from_re),
            &qdot.map(GradDual::from_re),
            &ud,
        );
        let g = gd.map(|x| *x.value());
        let j = SMatrix::<D, K, N>::from_fn(|r, s| gd[r].eps()[s]);
        let jjt = j * j.transpose();
        let inv = LU::new(jjt)
            .map(|lu| lu.inverse())
            .unwrap_or_else(|_| SMatrix::from_element(D::from(f64::NAN)));
        let grad = real_times(&self.a, u) - self.f.map(D::from);
        let along = j.transpose() * (inv * (j * grad));
        grad - along + j.transpose() * (inv * g)
    }
}

/// Largest `N` for which [`gauss_stationary_points`] starts Newton from the full grid of `3ᴺ`
/// points; above it, from the `2N + 1` points on the axes.
pub const MAX_GRID_DIMENSION: usize = 6;

/// Every stationary point of Gauss's constraint `Z` (see the [module docs](self)) under the
/// acceleration constraints `c` [Hamel art. 252] (SPEC M69, T22), found by Newton's method on the
/// stationarity conditions from the `3ᴺ` starts `q̈₀ + s·k`, `k ∈ {−1, 0, 1}ᴺ` (for
/// `N ≤` [`MAX_GRID_DIMENSION`]; above it the `2N + 1` starts with at most one `k_i ≠ 0`), around
/// the unconstrained accelerations `q̈₀ = a⁻¹f` with `s = max(1, ‖q̈₀‖_∞)`; sorted by `Z`, the first
/// is the minimiser. Points with a non-finite `Z` are dropped. The starts make this a search, not
/// a proof: a stationary point far from all of them can be missed.
///
/// # Errors
/// NaN/∞; [`Error::Singular`] for a singular mass matrix; [`Error::NotConverged`] when no start
/// converges.
pub fn gauss_stationary_points<L, A, const N: usize, const K: usize>(
    lagrangian: &L,
    constraints: &A,
    t: f64,
    q: &SVector<f64, N>,
    qdot: &SVector<f64, N>,
) -> Result<StationaryPoints<N>>
where
    L: Lagrangian<N>,
    A: AccelerationConstraints<N, K>,
{
    let (a, f) = lagrange_terms(lagrangian, t, q, qdot)?;
    let ainv = checked_inverse(&a, "mass matrix ∂²L/∂q̇²", || {
        format!("t = {t}, {}", at(q, qdot))
    })?;
    let free = ainv * f;
    let s = free.amax().max(1.0);
    let starts: Vec<SVector<f64, N>> = if N <= MAX_GRID_DIMENSION {
        (0..3usize.pow(N as u32))
            .map(|mut k| {
                SVector::from_fn(|i, _| {
                    let d = (k % 3) as f64 - 1.0;
                    k /= 3;
                    free[i] + s * d
                })
            })
            .collect()
    } else {
        (0..2 * N + 1)
            .map(|k| {
                let mut x = free;
                if k > 0 {
                    x[(k - 1) / 2] += if k % 2 == 1 { s } else { -s };
                }
                x
            })
            .collect()
    };
    let sys = Stationarity::<A, N, K> { constraints, a, f };
    let (roots, first_error) = implicit::roots_real(
        &sys,
        t,
        q,
        qdot,
        &starts,
        "stationarity of Gauss's constraint",
    );
    let points: Vec<Stationary<N>> = roots
        .into_iter()
        .filter(|r| r.u.iter().all(|x| x.is_finite()))
        .map(|r| {
            let res = a * r.u - f;
            Stationary {
                qddot: r.u,
                z: 0.5 * res.dot(&(ainv * res)),
            }
        })
        .filter(|p| p.z.is_finite())
        .collect();
    if points.is_empty() {
        return Err(first_error.unwrap_or_else(|| Error::NotConverged {
            what: "stationary points of Gauss's constraint".into(),
            iterations: 0,
            residual: f64::NAN,
        }));
    }
    // Roots that agree to √ε of the start scale are one root (Newton from different starts
    // lands within rounding of it, and a root at zero has no relative scale of its own).
    let mut distinct: Vec<Stationary<N>> = Vec::new();
    for p in points {
        if !distinct
            .iter()
            .any(|d| (d.qddot - p.qddot).amax() <= f64::EPSILON.sqrt() * s)
        {
            distinct.push(p);
        }
    }
    let mut points = distinct;
    points.sort_by(|x, y| x.z.total_cmp(&y.z));
    Ok(StationaryPoints {
        points,
        minimizer: 0,
    })
}

//! Constraints written once over [`DualNum`]: holonomic `g(t, q) = 0`, Pfaffian
//! `Σ_s B_rs(t, q) q̇_s + b_r(t, q) = 0`, constraints non-linear in the velocities
//! `g(t, q, q̇) = 0` and acceleration (second-class) constraints `g(t, q, q̇, q̈) = 0`; their
//! classification (catastatic, scleronomic, holonomic) and the rank of their matrix.
//!
//! * Pfaffian form of a holonomic constraint, `Σ_s ∂g/∂q_s dq_s + ∂g/∂t dt = 0`, and the
//!   classification: catastatic if `b = 0`, scleronomic if nothing depends on `t` explicitly
//!   [Ardema 2.3–2.5, eqs. 2.14–2.22] (SPEC M2).
//! * Integrability of one form (M3) and of a set of forms, the integrable combinations found from the
//!   involutive closure of the constrained distribution ([`frobenius`]); degrees of freedom and the
//!   number of coordinates from them, `DOF = n − K`, `n_min = n − (integrable combinations)`
//!   [Ardema 2.3, 2.7, 5.1] (M4).
//! * Constraints non-linear in the velocities [Hamel art. 247] (M67) and of the second class
//!   [Hamel art. 252] (M69).
//! * Quasi-velocities `ω = b(q) q̇` and Hamel's coefficients `β_μ^{τρ}` (M63–M64, [`quasi`]).
//!
//! Every derivative comes from automatic differentiation of the one definition.

pub mod frobenius;
pub mod quasi;

pub use frobenius::{
    classify, form_integrability_residuals, integrable_combinations, Classification, Integrability,
    FROBENIUS_TOLERANCE,
};
pub use quasi::{hamel_coefficients, HamelCoefficients, QuasiVelocities};

use crate::ad::GradDual;
use crate::error::{all_finite, finite, Error, Lazy, Result};
use nalgebra::{Const, SMatrix, SVector};
use num_dual::{Dual64, DualNum};

/// `K` holonomic constraints `g(t, q) = 0` on `N` generalized coordinates [Ardema eq. 2.14].
pub trait HolonomicConstraints<const N: usize, const K: usize> {
    /// The constraint functions `g(t, q)`.
    fn position_constraint<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>)
        -> SVector<D, K>;
}

impl<H: HolonomicConstraints<N, K> + ?Sized, const N: usize, const K: usize>
    HolonomicConstraints<N, K> for &H
{
    fn position_constraint<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
    ) -> SVector<D, K> {
        (**self).position_constraint(t, q)
    }
}

/// `K` Pfaffian constraints `Σ_s B_rs(t, q) q̇_s + b_r(t, q) = 0` [Ardema eq. 5.13; Hamel
/// art. 228 (I)].
pub trait PfaffianConstraints<const N: usize, const K: usize> {
    /// The coefficients `(B, b)`: row `r` of `B` and `b_r` are the form
    /// `ω_r = Σ_s B_rs dq_s + b_r dt`.
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
    ) -> (SMatrix<D, K, N>, SVector<D, K>);
}

/// `K` constraints on the velocities `g(t, q, q̇) = 0`, linear or not [Hamel art. 247] (M67).
/// Every [`PfaffianConstraints`] is one (`g = B q̇ + b`).
pub trait VelocityConstraints<const N: usize, const K: usize> {
    /// The constraint functions `g(t, q, q̇)`.
    fn velocity_constraint<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        qdot: &SVector<D, N>,
    ) -> SVector<D, K>;
}

impl<P: PfaffianConstraints<N, K>, const N: usize, const K: usize> VelocityConstraints<N, K> for P {
    fn velocity_constraint<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        qdot: &SVector<D, N>,
    ) -> SVector<D, K> {
        let (b, b0) = self.forms(t, q);
        b * qdot + b0
    }
}

/// `K` constraints of the second class `g(t, q, q̇, q̈) = 0` [Hamel art. 252] (M69).
pub trait AccelerationConstraints<const N: usize, const K: usize> {
    /// The constraint functions `g(t, q, q̇, q̈)`.
    fn acceleration_constraint<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        qdot: &SVector<D, N>,
        qddot: &SVector<D, N>,
    ) -> SVector<D, K>;
}

/// The Pfaffian form of holonomic constraints, `B = ∂g/∂q`, `b = ∂g/∂t` [Ardema eq. 2.14], by AD.
#[derive(Clone, Copy, Debug)]
pub struct Differentiated<H>(pub H);

impl<H: HolonomicConstraints<N, K>, const N: usize, const K: usize> PfaffianConstraints<N, K>
    for Differentiated<H>
{
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
    ) -> (SMatrix<D, K, N>, SVector<D, K>) {
        let qd: SVector<GradDual<D, f64, Const<N>>, N> =
            SVector::from_fn(|i, _| GradDual::variable(q[i], i));
        let g = self.0.position_constraint(GradDual::from_re(t), &qd);
        let b = SMatrix::from_fn(|r, s| g[r].eps()[s]);
        let td = num_dual::Dual::new(t, D::one());
        let gt = self
            .0
            .position_constraint(td, &q.map(num_dual::Dual::from_re));
        (b, gt.map(|x| x.eps))
    }
}

/// The rank tolerance of constraint matrices: a row whose part orthogonal to the rows before it
/// is at most `RANK_TOLERANCE` times its own norm (or a reference scale) counts as dependent.
/// The matrices come from AD, exact up to rounding (relative error of order `10⁻¹⁵` times their
/// condition number), so the tolerance leaves five orders of magnitude of room.
pub const RANK_TOLERANCE: f64 = 1e-10;

/// The rows of `g` that depend on the rows before them (modified Gram–Schmidt, twice): row `i` is
/// dependent when its component orthogonal to the independent rows before it has norm at most
/// `tol · scale[i]` (`scale[i]` defaults to the norm of row `i`); a zero row, or one whose
/// entries all lie below `MIN_POSITIVE/ε ≈ 10⁻²⁹²` (where they no longer carry full precision),
/// is dependent.
pub fn dependent_rows<const K: usize, const N: usize>(
    g: &SMatrix<f64, K, N>,
    scale: Option<&[f64; K]>,
    tol: f64,
) -> Vec<usize> {
    let mut basis: Vec<SVector<f64, N>> = Vec::new();
    let mut dependent = Vec::new();
    for i in 0..K {
        let row: SVector<f64, N> = g.row(i).transpose();
        let reference = scale.map_or(row.norm(), |s| s[i]);
        let mut v = row;
        for _ in 0..2 {
            for e in &basis {
                v -= *e * e.dot(&v);
            }
        }
        let n = v.norm();
        // Entries below MIN_POSITIVE/ε carry less than full precision (subnormal range).
        let tiny = row.amax() < f64::MIN_POSITIVE / f64::EPSILON;
        if n.is_nan() || n <= tol * reference || n == 0.0 || tiny {
            dependent.push(i);
        } else {
            basis.push(v / n);
        }
    }
    dependent
}

/// [`Error::RankDeficient`] if `g` has dependent rows at the configuration.
pub fn check_rank<const K: usize, const N: usize>(
    g: &SMatrix<f64, K, N>,
    what: &str,
    t: f64,
    at: impl FnOnce() -> String,
) -> Result<()> {
    all_finite(what, g.as_slice())?;
    let rows = dependent_rows(g, None, RANK_TOLERANCE);
    if rows.is_empty() {
        Ok(())
    } else {
        Err(Error::RankDeficient {
            what: what.to_string(),
            rows,
            t,
            at: at(),
            tolerance: RANK_TOLERANCE,
        })
    }
}

/// Values and first derivatives of velocity constraints at a state: `g`, `G = ∂g/∂q̇` and the
/// rate at fixed velocities `ġ|_{q̇} = ∂g/∂q · q̇ + ∂g/∂t` (the velocity-dependent part of the
/// differentiated constraint `G q̈ + ġ|_{q̇} = 0`).
#[derive(Clone, Debug, PartialEq)]
pub struct VelocityJet<const N: usize, const K: usize> {
    /// `g(t, q, q̇)`.
    pub value: SVector<f64, K>,
    /// `∂g/∂q̇`.
    pub gradient: SMatrix<f64, K, N>,
    /// `∂g/∂q · q̇ + ∂g/∂t`.
    pub rate: SVector<f64, K>,
}

/// [`VelocityJet`] of `c` at `(t, q, q̇)` by AD; NaN/∞ in the input or the output are typed errors.
pub fn velocity_jet<C: VelocityConstraints<N, K> + ?Sized, const N: usize, const K: usize>(
    c: &C,
    t: f64,
    q: &SVector<f64, N>,
    qdot: &SVector<f64, N>,
) -> Result<VelocityJet<N, K>> {
    finite("t", t)?;
    all_finite("q", q.as_slice())?;
    all_finite("q̇", qdot.as_slice())?;
    let vd: SVector<GradDual<f64, f64, Const<N>>, N> =
        SVector::from_fn(|i, _| GradDual::variable(qdot[i], i));
    let g = c.velocity_constraint(GradDual::from_re(t), &q.map(GradDual::from_re), &vd);
    let value = g.map(|x| *x.value());
    let gradient: SMatrix<f64, K, N> = SMatrix::from_fn(|r, s| g[r].eps()[s]);
    let qe: SVector<Dual64, N> = SVector::from_fn(|i, _| Dual64::new(q[i], qdot[i]));
    let rate = c
        .velocity_constraint(Dual64::new(t, 1.0), &qe, &qdot.map(Dual64::from))
        .map(|x| x.eps);
    let at = Lazy(|f| write!(f, "t = {t}, q = {q:?}, q̇ = {qdot:?}"));
    all_finite(
        format_args!("constraint values g at {at}"),
        value.as_slice(),
    )?;
    all_finite(format_args!("∂g/∂q̇ at {at}"), gradient.as_slice())?;
    all_finite(format_args!("∂g/∂q·q̇ + ∂g/∂t at {at}"), rate.as_slice())?;
    Ok(VelocityJet {
        value,
        gradient,
        rate,
    })
}

/// The constraint values `g(t, q, q̇)` and the tolerance they are judged by: `max |g_r|` must not
/// exceed `tol · (1 + Σ_s |∂g_r/∂q̇_s q̇_s|)` (relative to the size of the terms that cancel in
/// `g_r`); otherwise [`Error::ConstraintViolated`] carrying the residual.
pub fn check_velocities<C: VelocityConstraints<N, K> + ?Sized, const N: usize, const K: usize>(
    c: &C,
    t: f64,
    q: &SVector<f64, N>,
    qdot: &SVector<f64, N>,
    tol: f64,
) -> Result<()> {
    let tol = finite("constraint tolerance", tol)?;
    if tol < 0.0 {
        return Err(Error::out_of_domain("constraint tolerance", tol, "[0, ∞)"));
    }
    let jet = velocity_jet(c, t, q, qdot)?;
    let violated = (0..K).any(|r| {
        let terms: f64 = (0..N).map(|s| (jet.gradient[(r, s)] * qdot[s]).abs()).sum();
        jet.value[r].abs() > tol * (1.0 + terms)
    });
    if violated {
        Err(Error::ConstraintViolated {
            what: format!("velocities q̇ = {qdot:?} at t = {t}, q = {q:?}"),
            residual: jet.value.iter().copied().collect(),
            tolerance: tol,
        })
    } else {
        Ok(())
    }
}

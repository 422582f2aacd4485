//! Equations of motion in quasi-velocities: Boltzmann–Hamel (SPEC M63–M65) and Gibbs–Appell
//! (M41–M42), from `L = T − V` and the quasi-velocity matrix `b(q)` ([`QuasiVelocities`]).
//!
//! * Boltzmann–Hamel [Hamel art. 235 (II), 237], ρ = m+1 … n:
//!   ```math
//!   \frac{dP_\rho}{dt} + \sum_{\mu}\sum_{\tau>m}\beta_\mu^{\tau\rho}P_\mu\omega_\tau -
//!   \frac{\partial T}{\partial\vartheta_\rho} = K_\rho,\qquad
//!   P_\mu = \frac{\partial T(q,\omega)}{\partial\omega_\mu},\quad
//!   \frac{\partial T}{\partial\vartheta_\rho} = \sum_\nu \frac{\partial T}{\partial q_\nu}B_{\nu\rho},\quad
//!   K_\rho = \sum_\nu Q_\nu B_{\nu\rho},
//!   ```
//!   with `T(q, ω) = T(q, B(q)ω)` formed in **all** ω before the constrained ones are set to zero
//!   (Hamel's rule, art. 237); the potential enters through `L` in place of `T`.
//! * Gibbs–Appell [Ardema 14.2–14.3, eqs. 14.17–14.19]: the actual quasi-accelerations minimise
//!   `S − Σ_ν Q_ν q̈_ν` over `ω̇_ρ` (ρ > m), with `q̈ = B ω̇ + Ḃ ω` and the Gibbs function
//!   `S(q̈) = ½ q̈ᵀ a q̈ + q̈ᵀ(∂²L/∂q̇∂q q̇ + ∂²L/∂q̇∂t − ∂L/∂q)` (the acceleration energy up to
//!   terms free of `q̈`: `∂S/∂q̈` is the left side of Lagrange's equations); the stationarity
//!   conditions `∂S/∂ω̇_ρ = K_ρ` by AD.
//!
//! Both systems integrate the state `(q, ω)`; the constrained `ω_μ` (μ ≤ m) are held at zero and a
//! time coordinate (SPEC §0.7) at `ω = 1`.

use super::{at, lagrange_terms};
use crate::ad::{lift, phase_gradient, phase_hessian, GradDual, PhaseDual};
use crate::constraints::{hamel_coefficients, QuasiVelocities};
use crate::error::{all_finite, finite, Error, Result};
use crate::integrate::FirstOrderSystem;
use crate::lagrangian::Lagrangian;
use crate::phase::checked_inverse;
use nalgebra::{Const, DMatrix, DVector, SMatrix, SVector};
use num_dual::linalg::LU;
use num_dual::{Dual, Dual64, DualNum};
use std::marker::PhantomData;

/// `B(q) = b(q)⁻¹` over any dual type (NaN where `b` is singular; callers check the real `b`).
fn inverse_matrix<Q: QuasiVelocities<N> + ?Sized, D: DualNum<f64> + Copy, const N: usize>(
    quasi: &Q,
    q: &SVector<D, N>,
) -> SMatrix<D, N, N> {
    LU::new(quasi.matrix(q))
        .map(|lu| lu.inverse())
        .unwrap_or_else(|_| SMatrix::from_element(D::from(f64::NAN)))
}

/// The indices of the free quasi-velocities and a checked layout.
fn layout<Q: QuasiVelocities<N> + ?Sized, const N: usize>(quasi: &Q) -> Result<Vec<usize>> {
    let m = quasi.constrained();
    let time = quasi.time_coordinate();
    if m > N || time.is_some_and(|k| k < m || k >= N) {
        return Err(Error::invalid(
            "quasi-velocities",
            format!(
                "{m} constrained of {N}, time coordinate {time:?}: need m ≤ N and m ≤ time < N"
            ),
        ));
    }
    Ok((m..N).filter(|&i| Some(i) != time).collect())
}

/// `ω` with the constrained entries zero and the time entry one.
fn admissible<Q: QuasiVelocities<N> + ?Sized, const N: usize>(
    quasi: &Q,
    w: &SVector<f64, N>,
) -> SVector<f64, N> {
    let mut w = *w;
    for i in 0..quasi.constrained().min(N) {
        w[i] = 0.0;
    }
    if let Some(k) = quasi.time_coordinate() {
        if k < N {
            w[k] = 1.0;
        }
    }
    w
}

/// The checked state and the free indices: NaN/∞ rejected, `ω` made admissible.
fn prepare<Q: QuasiVelocities<N> + ?Sized, const N: usize>(
    quasi: &Q,
    t: f64,
    q: &SVector<f64, N>,
    w: &SVector<f64, N>,
) -> Result<(Vec<usize>, SVector<f64, N>)> {
    finite("t", t)?;
    all_finite("q", q.as_slice())?;
    all_finite("ω", w.as_slice())?;
    Ok((layout(quasi)?, admissible(quasi, w)))
}

/// `B = b(q)⁻¹` on reals: NaN/∞ in `b` rejected, [`Error::Singular`] naming `q` where `b` is
/// singular.
fn checked_transformation<Q: QuasiVelocities<N> + ?Sized, const N: usize>(
    quasi: &Q,
    q: &SVector<f64, N>,
) -> Result<SMatrix<f64, N, N>> {
    let b = quasi.matrix(q);
    all_finite(format_args!("b at q = {q:?}"), b.as_slice())?;
    checked_inverse(&b, "quasi-velocity matrix b", || format!("q = {q:?}"))
}

/// The first-order field `(q̇, ω̇) = (B ω, ω̇)` of the transition equations.
#[allow(clippy::type_complexity)]
fn transition<Q: QuasiVelocities<N> + ?Sized, const N: usize>(
    quasi: &Q,
    q: &SVector<f64, N>,
    w: &SVector<f64, N>,
    wd: SVector<f64, N>,
) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
    let b = quasi.matrix(q);
    let big_b = checked_inverse(&b, "quasi-velocity matrix b", || format!("q = {q:?}"))?;
    Ok((big_b * admissible(quasi, w), wd))
}

/// Solve the free block `m ω̇_f = r`; [`Error::Singular`] naming the configuration otherwise.
fn solve_free<const N: usize>(
    m: &SMatrix<f64, N, N>,
    r: &SVector<f64, N>,
    free: &[usize],
    what: &str,
    place: impl FnOnce() -> String,
) -> Result<SVector<f64, N>> {
    let k = free.len();
    let mf = DMatrix::from_fn(k, k, |i, j| m[(free[i], free[j])]);
    let rf = DVector::from_fn(k, |i, _| r[free[i]]);
    let cond_ok = {
        let sv = mf.clone().svd(false, false).singular_values;
        k == 0 || sv.min() > 64.0 * f64::EPSILON * sv.max()
    };
    let x = if cond_ok { mf.lu().solve(&rf) } else { None };
    let x = x.ok_or_else(|| Error::Singular {
        what: what.to_string(),
        at: place(),
        rcond: 0.0,
    })?;
    let mut out = SVector::zeros();
    for (i, &f) in free.iter().enumerate() {
        out[f] = x[i];
    }
    Ok(out)
}

/// Quasi-velocities of admissible velocities, `ω = b q̇`: [`Error::ConstraintViolated`] (with the
/// constrained `ω_μ` as the residual) when `|ω_μ| > tol · (1 + Σ_ν |b_μν q̇_ν|)` for some μ ≤ m,
/// or when a time coordinate's `ω` differs from one by more than `tol`.
///
/// # Errors
/// As described; NaN/∞; a singular `b`.
pub fn quasi_velocities<Q: QuasiVelocities<N> + ?Sized, const N: usize>(
    quasi: &Q,
    q: &SVector<f64, N>,
    qdot: &SVector<f64, N>,
    tol: f64,
) -> Result<SVector<f64, N>> {
    all_finite("q", q.as_slice())?;
    all_finite("q̇", qdot.as_slice())?;
    let tol = finite("constraint tolerance", tol)?;
    layout(quasi)?;
    let b = quasi.matrix(q);
    all_finite(format_args!("b at q = {q:?}"), b.as_slice())?;
    let w = b * qdot;
    let m = quasi.constrained();
    let bad = (0..m).any(|mu| {
        let terms: f64 = (0..N).map(|nu| (b[(mu, nu)] * qdot[nu]).abs()).sum();
        w[mu].abs().is_nan() || w[mu].abs() > tol * (1.0 + terms)
    }) || quasi
        .time_coordinate()
        .is_some_and(|k| (w[k] - 1.0).abs().is_nan() || (w[k] - 1.0).abs() > tol);
    if bad {
        return Err(Error::ConstraintViolated {
            what: format!("velocities q̇ = {qdot:?} at q = {q:?} (constrained quasi-velocities)"),
            residual: w.iter().take(m).copied().collect(),
            tolerance: tol,
        });
    }
    Ok(admissible(quasi, &w))
}

/// The Boltzmann–Hamel equations of `L` in the quasi-velocities `Q` (see the [module docs](self)).
#[derive(Clone, Copy, Debug)]
pub struct BoltzmannHamel<L, Q, const N: usize> {
    /// `L = T − V` with its generalized forces.
    pub lagrangian: L,
    /// The quasi-velocities; the first `m` are set to zero by the constraints.
    pub quasi: Q,
    dims: PhantomData<[(); N]>,
}

impl<L: Lagrangian<N>, Q: QuasiVelocities<N>, const N: usize> BoltzmannHamel<L, Q, N> {
    /// The equations of `lagrangian` (the full `T`, not one with the constraints substituted) in
    /// the quasi-velocities `quasi`.
    pub fn new(lagrangian: L, quasi: Q) -> Self {
        Self {
            lagrangian,
            quasi,
            dims: PhantomData,
        }
    }

    /// Lagrange's equations of a kinetic energy `T*` into which the constraints were substituted
    /// before differentiation (SPEC M62, T19). They equal the Boltzmann–Hamel equations only when
    /// Hamel's correction `Σ_{μ≤m} P_μ β_μ^{τρ} ω_τ` (M66) vanishes, i.e. when every
    /// `β_μ^{τρ}` with μ ≤ m and τ, ρ free is zero at the sample configurations; then the
    /// system is returned, otherwise the substitution is refused with the reason.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the constraint and the non-zero coefficient; NaN/∞; a
    /// singular `b`; no samples.
    pub fn from_substituted(t_star: L, quasi: Q, samples: &[SVector<f64, N>]) -> Result<Self> {
        let free = layout(&quasi)?;
        if samples.is_empty() {
            return Err(Error::invalid(
                "samples",
                "at least one configuration is needed",
            ));
        }
        let mut cols = free.clone();
        cols.extend(quasi.time_coordinate());
        for q in samples {
            let h = hamel_coefficients(&quasi, q)?;
            for mu in 0..quasi.constrained() {
                for &tau in &cols {
                    for &rho in &free {
                        let beta = h.beta[mu][(tau, rho)];
                        if beta.abs() > 1e-12 * (1.0 + h.b.amax() * h.big_b.amax()) {
                            return Err(Error::invalid(
                                "kinetic energy with the constraints substituted (T*)",
                                format!(
                                    "constraint {mu} is not integrable: Hamel's coefficient \
                                     β_{mu}^{{{tau}{rho}}} = {beta:e} ≠ 0 at q = {q:?}, so Lagrange's \
                                     equations of T* omit the correction Σ_μ P_μ β_μ^{{τρ}} ω_τ \
                                     [Hamel art. 237, 246]; give T and the constraints separately \
                                     (BoltzmannHamel::new)"
                                ),
                            ));
                        }
                    }
                }
            }
        }
        Ok(Self {
            lagrangian: t_star,
            quasi,
            dims: PhantomData,
        })
    }

    /// The free block's coefficients and right side of the Boltzmann–Hamel equations at
    /// `(t, q, ω)`, `ω` admissible, in any number type: `(∂²T/∂ω², r)` with
    /// `∂²T/∂ω² ω̇ = r`, `r = K + ∂T/∂ϑ − ∂²T/∂ω∂q q̇ − ∂²T/∂ω∂t − Σ_{μ,τ} β_μ^{τρ} P_μ ω_τ`
    /// (rows ρ free); `b`'s derivatives, `B = b⁻¹` (NaN where `b` is singular) and the derivatives
    /// of `L` by AD.
    ///
    /// The derivatives of `T(q, ω) = L(t, q, B(q) ω)` follow from those of `L` at `q̇ = Bω` by
    /// the chain rule, with `∂B/∂q_j = −B (∂b/∂q_j) B`:
    /// `P = Bᵀ L_q̇`, `∂²T/∂ω² = Bᵀ L_q̇q̇ B`, `∂T/∂q_j = L_q_j + L_q̇ · (∂B/∂q_j) ω`,
    /// `∂²T/∂ω∂q_j = (∂B/∂q_j)ᵀ L_q̇ + Bᵀ (L_q̇q_j + L_q̇q̇ (∂B/∂q_j) ω)`, `∂²T/∂ω∂t = Bᵀ L_q̇t`,
    /// so that `L` is differentiated once to second order (as for Lagrange's equations) and `b`
    /// once to first order, rather than `L ∘ B` through a second-order pass.
    fn terms<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        w: &SVector<D, N>,
    ) -> (SMatrix<D, N, N>, SVector<D, N>) {
        // b(q) with ∂b/∂q, B = b⁻¹ and Hamel's coefficients β_μ = Bᵀ cᵀ B,
        // c[(ν, σ)] = ∂b_μν/∂q_σ − ∂b_μσ/∂q_ν (SPEC M64).
        let qg: SVector<GradDual<D, f64, Const<N>>, N> =
            SVector::from_fn(|i, _| GradDual::variable(q[i], i));
        let bd = self.quasi.matrix(&qg);
        let big_b = LU::new(bd.map(|x| *x.value()))
            .map(|lu| lu.inverse())
            .unwrap_or_else(|_| SMatrix::from_element(D::from(f64::NAN)));
        let beta: Vec<SMatrix<D, N, N>> = (0..N)
            .map(|mu| {
                let c = SMatrix::<D, N, N>::from_fn(|nu, sg| {
                    bd[(mu, nu)].eps()[sg] - bd[(mu, sg)].eps()[nu]
                });
                big_b.transpose() * c.transpose() * big_b
            })
            .collect();
        // ∂B/∂q_j = −B (∂b/∂q_j) B.
        let dbig_b: Vec<SMatrix<D, N, N>> = (0..N)
            .map(|j| -(big_b * bd.map(|x| x.eps()[j]) * big_b))
            .collect();
        let qdot = big_b * w;
        // L's gradient and Hessian over (q, q̇) at q̇ = Bω in one nested pass.
        let qi: SVector<PhaseDual<D, f64, Const<N>>, N> =
            SVector::from_fn(|i, _| PhaseDual::coordinate(q[i], i));
        let vi: SVector<PhaseDual<D, f64, Const<N>>, N> =
            SVector::from_fn(|i, _| PhaseDual::momentum(qdot[i], i));
        let (_, gq, gv) = phase_gradient(
            |a, b| {
                self.lagrangian
                    .lagrangian(PhaseDual::from_re(PhaseDual::from_re(t)), a, b)
            },
            &qi,
            &vi,
        );
        let l_q = gq.map(|x| *x.value());
        let l_v = gv.map(|x| *x.value());
        let l_vv = SMatrix::<D, N, N>::from_fn(|i, j| gv[i].dp()[j]);
        let l_vq = SMatrix::<D, N, N>::from_fn(|i, j| gv[i].dq()[j]);
        let td = Dual::new(t, D::one());
        let (_, _, lvt) = phase_gradient(
            |a, b| self.lagrangian.lagrangian(PhaseDual::from_re(td), a, b),
            &q.map(Dual::from_re),
            &qdot.map(Dual::from_re),
        );
        let l_vt = lvt.map(|x| x.eps);
        // The derivatives of T(q, ω) by the chain rule.
        let p = big_b.transpose() * l_v;
        let pp = big_b.transpose() * l_vv * big_b;
        let mut lq = l_q;
        let mut pq = SMatrix::<D, N, N>::zeros();
        for (j, db) in dbig_b.iter().enumerate() {
            let dv = db * w;
            lq[j] += l_v.dot(&dv);
            let col = db.transpose() * l_v + big_b.transpose() * (l_vq.column(j) + l_vv * dv);
            pq.set_column(j, &col);
        }
        let pt = big_b.transpose() * l_vt;
        let force = big_b.transpose() * self.lagrangian.total_force(t, q, &qdot);
        let mut rhs = force + big_b.transpose() * lq - pq * qdot - pt;
        for rho in 0..N {
            let mut gyro = D::zero();
            for (mu, b) in beta.iter().enumerate() {
                for tau in 0..N {
                    gyro += b[(tau, rho)] * p[mu] * w[tau];
                }
            }
            rhs[rho] -= gyro;
        }
        (pp, rhs)
    }

    /// `ω̇` at `(t, q, ω)` (constrained and time entries zero).
    ///
    /// # Errors
    /// NaN/∞; [`Error::Singular`] naming the configuration when `b` or the free block of
    /// `∂²T/∂ω²` is singular.
    pub fn quasi_accelerations(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        w: &SVector<f64, N>,
    ) -> Result<SVector<f64, N>> {
        let (free, w) = prepare(&self.quasi, t, q, w)?;
        checked_transformation(&self.quasi, q)?;
        let (pp, rhs) = self.terms(t, q, &w);
        all_finite(
            format!("Boltzmann–Hamel terms at t = {t}, q = {q:?}, ω = {w:?}"),
            rhs.iter()
                .chain(pp.iter())
                .copied()
                .collect::<Vec<_>>()
                .as_slice(),
        )?;
        solve_free(&pp, &rhs, &free, "free block of ∂²T/∂ω²", || {
            format!("t = {t}, q = {q:?}, ω = {w:?}")
        })
    }

    /// The field `(q̇, ω̇) = (B ω, ω̇)` at `(t, q, ω)` in any number type, `ω` made admissible
    /// (constrained entries zero, a time entry one): the one definition differentiated by AD for
    /// linearisations about steady motions. Where `b` or the free block of `∂²T/∂ω²` is singular
    /// the values are NaN; checked evaluation on reals is [`FirstOrderSystem::field`].
    /// [`Error::InvalidInput`] for an inconsistent layout of the quasi-velocities.
    #[allow(clippy::type_complexity)]
    pub(crate) fn field_dual<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        w: &SVector<D, N>,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        let free = layout(&self.quasi)?;
        let mut w = *w;
        for (i, x) in w.iter_mut().enumerate() {
            if !free.contains(&i) {
                *x = if Some(i) == self.quasi.time_coordinate() {
                    D::one()
                } else {
                    D::zero()
                };
            }
        }
        let (pp, rhs) = self.terms(t, q, &w);
        let mut m = SMatrix::<D, N, N>::identity();
        let mut r = SVector::<D, N>::zeros();
        for &i in &free {
            r[i] = rhs[i];
            for &j in &free {
                m[(i, j)] = pp[(i, j)];
            }
        }
        let wd = LU::new(m)
            .map(|lu| lu.solve(&r))
            .unwrap_or_else(|_| SVector::from_element(D::from(f64::NAN)));
        Ok((inverse_matrix(&self.quasi, q) * w, wd))
    }
}

/// The Gibbs–Appell equations of `L` in the quasi-velocities `Q` (see the [module docs](self)).
#[derive(Clone, Copy, Debug)]
pub struct GibbsAppell<L, Q, const N: usize> {
    /// `L = T − V` with its generalized forces.
    pub lagrangian: L,
    /// The quasi-velocities; the first `m` are set to zero by the constraints.
    pub quasi: Q,
    dims: PhantomData<[(); N]>,
}

impl<L: Lagrangian<N>, Q: QuasiVelocities<N>, const N: usize> GibbsAppell<L, Q, N> {
    /// The equations of `lagrangian` in the quasi-velocities `quasi`.
    pub fn new(lagrangian: L, quasi: Q) -> Self {
        Self {
            lagrangian,
            quasi,
            dims: PhantomData,
        }
    }

    /// The terms of Appell's function at `(t, q, ω)`: the free indices, `B`, `Ḃω`, the mass
    /// matrix `a`, the right side `f` of Lagrange's equations and `q̇`.
    #[allow(clippy::type_complexity)]
    fn appell_terms(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        w: &SVector<f64, N>,
    ) -> Result<AppellTerms<N>> {
        let (free, w) = prepare(&self.quasi, t, q, w)?;
        let big_b = checked_transformation(&self.quasi, q)?;
        let qdot = big_b * w;
        let (a, f) = lagrange_terms(&self.lagrangian, t, q, &qdot)?;
        // Ḃω: the derivative of B(q(t)) ω along q̇.
        let qe: SVector<Dual64, N> = SVector::from_fn(|i, _| Dual64::new(q[i], qdot[i]));
        let bdot_w = (inverse_matrix(&self.quasi, &qe) * lift::<Dual64, N>(&w)).map(|x| x.eps);
        all_finite(format_args!("Ḃω at {}", at(q, &qdot)), bdot_w.as_slice())?;
        Ok(AppellTerms {
            free,
            big_b,
            bdot_w,
            a,
            f,
            qdot,
        })
    }

    /// Appell's function `A(ω̇) = ½ q̈ᵀ a q̈ − f·q̈`, `q̈ = B ω̇ + Ḃ ω`, at `(t, q, ω)`: Gibbs'
    /// function `S = ½ Σ m ẍ²` less the power `Σ_ν Q_ν q̈_ν` of all forces (those of the potential
    /// included), up to terms free of the accelerations [Ardema eq. 14.18]. The actual
    /// quasi-accelerations make it stationary over the free `ω̇_ρ`; the constrained and time
    /// entries of `ω̇` are taken as zero.
    ///
    /// # Errors
    /// NaN/∞ (input or value); [`Error::Singular`] naming the configuration when `b` or the mass
    /// matrix is singular.
    pub fn appell_function(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        w: &SVector<f64, N>,
        wd: &SVector<f64, N>,
    ) -> Result<f64> {
        all_finite("ω̇", wd.as_slice())?;
        let terms = self.appell_terms(t, q, w)?;
        let mut wd = *wd;
        for (i, x) in wd.iter_mut().enumerate() {
            if !terms.free.contains(&i) {
                *x = 0.0;
            }
        }
        finite(
            format_args!("Appell's function at t = {t}, {}", at(q, &terms.qdot)),
            terms.value(&wd),
        )
    }

    /// `ω̇` at `(t, q, ω)` from the stationarity of `S − Q·q̈` (constrained and time entries zero).
    ///
    /// # Errors
    /// NaN/∞; [`Error::Singular`] naming the configuration when `b` or `Bᵀ a B` (free block) is
    /// singular.
    pub fn quasi_accelerations(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        w: &SVector<f64, N>,
    ) -> Result<SVector<f64, N>> {
        let terms = self.appell_terms(t, q, w)?;
        // Appell's function of ω̇, differentiated twice by AD.
        let zero = SVector::<f64, N>::zeros();
        let (_, grad, _, hess) = phase_hessian(|wd, _| terms.value(wd), &zero, &zero);
        solve_free(
            &hess.qq,
            &(-grad),
            &terms.free,
            "Bᵀ a B (free block)",
            || format!("t = {t}, {}", at(q, &terms.qdot)),
        )
    }
}

/// The pieces of Appell's function `½ q̈ᵀ a q̈ − f·q̈`, `q̈ = B ω̇ + Ḃ ω`, at one state.
struct AppellTerms<const N: usize> {
    free: Vec<usize>,
    big_b: SMatrix<f64, N, N>,
    bdot_w: SVector<f64, N>,
    a: SMatrix<f64, N, N>,
    f: SVector<f64, N>,
    qdot: SVector<f64, N>,
}

impl<const N: usize> AppellTerms<N> {
    fn value<D: DualNum<f64> + Copy>(&self, wd: &SVector<D, N>) -> D {
        let qdd = crate::ad::real_times(&self.big_b, wd) + lift(&self.bdot_w);
        let aq = crate::ad::real_times(&self.a, &qdd);
        (0..N).fold(D::from(0.0), |s, i| s + qdd[i] * (aq[i] * 0.5 - self.f[i]))
    }
}

/// The first-order system `(q̇, ω̇) = (B(q) ω, ω̇(t, q, ω))` of equations of motion in
/// quasi-velocities whose type has `quasi` and `quasi_accelerations` (the transition equations
/// beside the equations of motion, SPEC M63–M65) [Hamel art. 236–237].
macro_rules! quasi_velocity_system {
    ($($equations:ident),+) => {$(
        impl<L: Lagrangian<N>, Q: QuasiVelocities<N>, const N: usize> FirstOrderSystem<N>
            for $equations<L, Q, N>
        {
            fn field(
                &self,
                t: f64,
                q: &SVector<f64, N>,
                w: &SVector<f64, N>,
            ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
                transition(&self.quasi, q, w, self.quasi_accelerations(t, q, w)?)
            }
        }
    )+};
}

quasi_velocity_system!(BoltzmannHamel, GibbsAppell);

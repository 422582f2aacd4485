//! Equations of motion of constrained systems, several independent ways, from one definition: the
//! user writes `L = T − V` (a [`Lagrangian`], with its generalized forces) and the constraints
//! (a [`VelocityConstraints`] set, or quasi-velocities); the crate forms the equations.
//!
//! * Lagrange's equations with multipliers (SPEC M16, crate sign §0.3), for constraints linear or
//!   non-linear in the velocities (Appell–Chetaev rule, M67):
//!   ```math
//!   \frac{d}{dt}\frac{\partial L}{\partial\dot q} - \frac{\partial L}{\partial q}
//!   = Q - G^{\mathsf T}\lambda,\qquad G = \frac{\partial g}{\partial\dot q},\qquad
//!   G\ddot q + \frac{\partial g}{\partial q}\dot q + \frac{\partial g}{\partial t} = 0 ,
//!   ```
//!   the multipliers returned with the accelerations ([`Constrained::multiplier_accelerations`])
//!   [Ardema 6.3, eq. 6.29; Hamel art. 228 (I), 247–248].
//! * Embedding by the null space of `G` (M19) [Ardema 6.6, eqs. 6.42–6.45]
//!   ([`Constrained::embedded_accelerations`]).
//! * Boltzmann–Hamel equations in quasi-velocities with Hamel's coefficients (M63–M65)
//!   [Hamel art. 232–237] and the Gibbs–Appell equations (M41–M42) [Ardema 14.2–14.3] ([`hamel`]).
//! * Gauss's principle of least constraint (M43) minimised with `argmin` ([`gauss`]).
//! * Constraint-preserving integration (SPEC X6): the discrete Lagrange–d'Alembert integrator
//!   and projection onto the constraints beside DOP853 on the index-reduced equations, with the
//!   energy and constraint drift of each measured against time ([`integrators`]).
//! * The integration of the multiplier form stops with [`Error::RankDeficient`] where `∂g/∂q̇`
//!   loses rank during the motion (SPEC X7), located on the dense output
//!   ([`Constrained::integrate`]).

pub mod gauss;
pub mod hamel;
pub mod integrators;

pub use gauss::{
    gauss_accelerations, gauss_stationary_points, GaussMinimum, Stationary, StationaryPoints,
};
pub use hamel::{BoltzmannHamel, GibbsAppell};
pub use integrators::{
    drift, ConstrainedConstruction, ConstrainedInfo, ConstrainedMethod, DiscreteRun, DiscreteStep,
    Drift, DriftSample, LagrangeDAlembert, Projection, CONSTRAINED_METHODS, PROJECTION_SEGMENTS,
};

use crate::constraints::{
    check_rank, check_velocities, dependent_rows, velocity_jet, VelocityConstraints, VelocityJet,
};
use crate::error::{Error, Result};
use crate::integrate::{
    integrate, Control, FirstOrderSystem, Method, Observer, Problem, Report, StepView,
};
use crate::lagrangian::Lagrangian;
use crate::phase::{checked_inverse, State};
use nalgebra::{DMatrix, DVector, SMatrix, SVector};
use std::marker::PhantomData;

/// A Lagrangian system with `K` velocity constraints.
#[derive(Clone, Copy, Debug)]
pub struct Constrained<L, C, const N: usize, const K: usize> {
    /// `L = T − V` with the generalized forces `Q` (and Rayleigh dissipation) it declares.
    pub lagrangian: L,
    /// The constraints `g(t, q, q̇) = 0`.
    pub constraints: C,
    dims: PhantomData<[[(); N]; K]>,
}

/// Accelerations and multipliers of the multiplier form (crate sign, SPEC §0.3).
#[derive(Clone, Debug, PartialEq)]
pub struct Multipliers<const N: usize, const K: usize> {
    /// `q̈`.
    pub qddot: SVector<f64, N>,
    /// `λ`; the constraint force on coordinate `s` is `−Σ_r λ_r G_rs`.
    pub lambda: SVector<f64, K>,
    /// The constraint forces `−Gᵀλ`.
    pub constraint_force: SVector<f64, N>,
}

/// `(a, f)`: the mass matrix `∂²L/∂q̇²` and the right side `f = ∂L/∂q − ∂²L/∂q̇∂q q̇ − ∂²L/∂q̇∂t
/// + Q` of `a q̈ = f` (Lagrange's equations without constraints).
pub(crate) fn lagrange_terms<L: Lagrangian<N> + ?Sized, const N: usize>(
    l: &L,
    t: f64,
    q: &SVector<f64, N>,
    qdot: &SVector<f64, N>,
) -> Result<(SMatrix<f64, N, N>, SVector<f64, N>)> {
    let (lq, h, lvt) = l.second_order_terms(t, q, qdot)?;
    let f = lq - h.pq * qdot - lvt + l.total_force(t, q, qdot);
    crate::error::all_finite(
        format!("generalized forces at t = {t}, q = {q:?}"),
        f.as_slice(),
    )?;
    Ok((h.pp, f))
}

/// The state `q = …, q̇ = …` as an error message names it, formatted only when a message is
/// written (the checks on the right-hand side's path pass it unformatted).
pub(crate) fn at<'a, const N: usize>(
    q: &'a SVector<f64, N>,
    qdot: &'a SVector<f64, N>,
) -> At<'a, N> {
    At(q, qdot)
}

/// The state `(q, q̇)` of [`at`], written by its `Display`.
pub(crate) struct At<'a, const N: usize>(&'a SVector<f64, N>, &'a SVector<f64, N>);

impl<const N: usize> std::fmt::Display for At<'_, N> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "q = {:?}, q̇ = {:?}", self.0, self.1)
    }
}

impl<L, C, const N: usize, const K: usize> Constrained<L, C, N, K>
where
    L: Lagrangian<N>,
    C: VelocityConstraints<N, K>,
{
    /// The system `L` under the constraints `C`.
    pub fn new(lagrangian: L, constraints: C) -> Self {
        Self {
            lagrangian,
            constraints,
            dims: PhantomData,
        }
    }

    /// The constraint values, their velocity gradient and rate at `(t, q, q̇)`.
    ///
    /// # Errors
    /// NaN/∞ in the input or the values.
    pub fn jet(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qdot: &SVector<f64, N>,
    ) -> Result<VelocityJet<N, K>> {
        velocity_jet(&self.constraints, t, q, qdot)
    }

    /// The constraint jet with its matrix `G = ∂g/∂q̇` checked for full rank, and the terms
    /// `(a, f)` of Lagrange's equations: what both acceleration routes start from.
    fn checked_terms(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qdot: &SVector<f64, N>,
    ) -> Result<(VelocityJet<N, K>, SMatrix<f64, N, N>, SVector<f64, N>)> {
        let jet = self.jet(t, q, qdot)?;
        check_rank(&jet.gradient, "constraint matrix ∂g/∂q̇", t, || {
            at(q, qdot).to_string()
        })?;
        let (a, f) = lagrange_terms(&self.lagrangian, t, q, qdot)?;
        Ok((jet, a, f))
    }

    /// Accelerations and multipliers from the index-1 system (SPEC M16 with the Appell–Chetaev
    /// rule of M67): `a q̈ + Gᵀλ = f`, `G q̈ = −(∂g/∂q q̇ + ∂g/∂t)`, solved by the Schur complement
    /// `G a⁻¹ Gᵀ λ = G a⁻¹ f + ∂g/∂q q̇ + ∂g/∂t`.
    ///
    /// # Errors
    /// NaN/∞; [`Error::RankDeficient`] naming the dependent rows of `G = ∂g/∂q̇` and the
    /// configuration (X7); [`Error::Singular`] naming the configuration when the mass matrix
    /// `∂²L/∂q̇²` or `G a⁻¹ Gᵀ` is singular.
    pub fn multiplier_accelerations(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qdot: &SVector<f64, N>,
    ) -> Result<Multipliers<N, K>> {
        let (jet, a, f) = self.checked_terms(t, q, qdot)?;
        let g = &jet.gradient;
        let ainv = checked_inverse(&a, "mass matrix ∂²L/∂q̇²", || {
            format!("t = {t}, {}", at(q, qdot))
        })?;
        let s = g * ainv * g.transpose();
        let sinv = checked_inverse(&s, "G a⁻¹ Gᵀ (G = ∂g/∂q̇)", || {
            format!("t = {t}, {}", at(q, qdot))
        })?;
        let lambda = sinv * (g * ainv * f + jet.rate);
        let constraint_force = -(g.transpose() * lambda);
        let qddot = ainv * (f + constraint_force);
        crate::error::all_finite(
            format_args!("q̈ at t = {t}, {}", at(q, qdot)),
            qddot.as_slice(),
        )?;
        crate::error::all_finite(
            format_args!("λ at t = {t}, {}", at(q, qdot)),
            lambda.as_slice(),
        )?;
        Ok(Multipliers {
            qddot,
            lambda,
            constraint_force,
        })
    }

    /// Accelerations by embedding (SPEC M19): the `K` dependent velocities `d` chosen by column
    /// pivoting of `G`, `q̈ = q̈_p + 𝒩 z` with `𝒩 = [−G_d⁻¹ G_i; 1]` spanning the admissible
    /// accelerations and `q̈_p` the particular solution with `q̈_i = 0`; the reduced equations
    /// `𝒩ᵀ(a q̈ − f) = 0`, i.e. `Σ_s R_s α_sj + R_j = 0` [Ardema eqs. 6.42–6.45].
    ///
    /// # Errors
    /// As [`Constrained::multiplier_accelerations`].
    pub fn embedded_accelerations(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qdot: &SVector<f64, N>,
    ) -> Result<SVector<f64, N>> {
        let (jet, a, f) = self.checked_terms(t, q, qdot)?;
        let g = &jet.gradient;
        // Dependent velocities by greedy column pivoting (largest remaining column first).
        let mut dep: Vec<usize> = Vec::new();
        let mut basis: Vec<SVector<f64, K>> = Vec::new();
        let mut cols: Vec<usize> = (0..N).collect();
        cols.sort_by(|&i, &j| g.column(j).norm().total_cmp(&g.column(i).norm()));
        let mut remaining = cols.clone();
        while dep.len() < K {
            let mut best: Option<(usize, f64, SVector<f64, K>)> = None;
            for &c in &remaining {
                let mut v: SVector<f64, K> = g.column(c).into_owned();
                for e in &basis {
                    v -= e * e.dot(&v);
                }
                if best.as_ref().is_none_or(|b| v.norm() > b.1) {
                    best = Some((c, v.norm(), v));
                }
            }
            let Some((c, n, v)) = best.filter(|b| b.1 > 0.0) else {
                return Err(Error::Singular {
                    what: "constraint matrix ∂g/∂q̇ (no dependent velocities)".into(),
                    at: format!("t = {t}, {}", at(q, qdot)),
                    rcond: 0.0,
                });
            };
            basis.push(v / n);
            dep.push(c);
            remaining.retain(|&x| x != c);
        }
        let ind: Vec<usize> = (0..N).filter(|i| !dep.contains(i)).collect();
        let gd = DMatrix::from_fn(K, K, |r, j| g[(r, dep[j])]);
        let gi = DMatrix::from_fn(K, N - K, |r, j| g[(r, ind[j])]);
        let lu = gd.lu();
        let singular = || Error::Singular {
            what: "dependent block G_d of ∂g/∂q̇".into(),
            at: format!("t = {t}, {}", at(q, qdot)),
            rcond: 0.0,
        };
        let alpha = lu.solve(&(-gi)).ok_or_else(singular)?;
        let rate = DVector::from_column_slice(jet.rate.as_slice());
        let qdd_d = lu.solve(&(-rate)).ok_or_else(singular)?;
        let mut null = DMatrix::zeros(N, N - K);
        let mut qp = DVector::zeros(N);
        for (j, &i) in ind.iter().enumerate() {
            null[(i, j)] = 1.0;
        }
        for (r, &d) in dep.iter().enumerate() {
            qp[d] = qdd_d[r];
            for j in 0..N - K {
                null[(d, j)] = alpha[(r, j)];
            }
        }
        let ad = DMatrix::from_column_slice(N, N, a.as_slice());
        let fd = DVector::from_column_slice(f.as_slice());
        let reduced = null.transpose() * &ad * &null;
        let rhs = null.transpose() * (fd - &ad * &qp);
        let z = reduced.lu().solve(&rhs).ok_or_else(|| Error::Singular {
            what: "reduced mass matrix 𝒩ᵀ a 𝒩".into(),
            at: format!("t = {t}, {}", at(q, qdot)),
            rcond: 0.0,
        })?;
        let qdd = qp + null * z;
        let out = SVector::<f64, N>::from_column_slice(qdd.as_slice());
        crate::error::all_finite(
            format_args!("q̈ at t = {t}, {}", at(q, qdot)),
            out.as_slice(),
        )?;
        Ok(out)
    }

    /// Velocities made admissible: Newton's iteration `q̇ ← q̇ − a⁻¹Gᵀ(G a⁻¹ Gᵀ)⁻¹ g`, the
    /// correction of least kinetic energy (the velocity-jump analogue of Gauss's principle,
    /// [Ardema 13.3]); exact in one step for Pfaffian constraints.
    ///
    /// # Errors
    /// As [`Constrained::multiplier_accelerations`]; [`Error::NotConverged`] after 50 iterations.
    pub fn project_velocities(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qdot: &SVector<f64, N>,
    ) -> Result<SVector<f64, N>> {
        let mut v = *qdot;
        let mut last = f64::INFINITY;
        for _ in 0..50 {
            let jet = self.jet(t, q, &v)?;
            let scale: f64 = 1.0 + (jet.gradient * v).abs().max();
            last = jet.value.amax();
            if last <= 4.0 * f64::EPSILON * scale {
                return Ok(v);
            }
            check_rank(&jet.gradient, "constraint matrix ∂g/∂q̇", t, || {
                at(q, &v).to_string()
            })?;
            let (a, _) = lagrange_terms(&self.lagrangian, t, q, &v)?;
            let ainv = checked_inverse(&a, "mass matrix ∂²L/∂q̇²", || {
                format!("t = {t}, {}", at(q, &v))
            })?;
            let g = &jet.gradient;
            let s = checked_inverse(&(g * ainv * g.transpose()), "G a⁻¹ Gᵀ", || {
                format!("t = {t}, {}", at(q, &v))
            })?;
            let step = ainv * g.transpose() * (s * jet.value);
            let next = v - step;
            if step.amax() <= f64::EPSILON * v.amax() {
                return Ok(next);
            }
            v = next;
        }
        Err(Error::NotConverged {
            what: "projection of the velocities onto the constraints".into(),
            iterations: 50,
            residual: last,
        })
    }

    /// Integrate the multiplier form from `(q₀, q̇₀)` at `t₀` to `t₁` with `method` (e.g.
    /// [`Dop853`](crate::integrate::Dop853)), the state being `(q, q̇)`.
    ///
    /// The initial velocities must satisfy the constraints to `velocity_tolerance` (relative, see
    /// [`check_velocities`]); project them first with [`Constrained::project_velocities`] if
    /// needed. A [`RankMonitor`] watches the smallest singular value of `∂g/∂q̇` on every step.
    ///
    /// # Errors
    /// [`Error::ConstraintViolated`] with the residual for inadmissible initial velocities;
    /// [`Error::RankDeficient`] (with the time and the state) where `∂g/∂q̇` loses rank;
    /// the errors of the method.
    #[allow(clippy::too_many_arguments)]
    pub fn integrate<M: Method<Self, N>, O: Observer<N>>(
        &self,
        method: &M,
        t0: f64,
        q0: SVector<f64, N>,
        qdot0: SVector<f64, N>,
        t1: f64,
        velocity_tolerance: f64,
        observer: &mut O,
    ) -> Result<Report<N>> {
        check_velocities(&self.constraints, t0, &q0, &qdot0, velocity_tolerance)?;
        let problem = Problem::new(self, t0, q0, qdot0, t1)?;
        let mut watched = Watched {
            monitor: RankMonitor::new(&self.constraints),
            user: observer,
        };
        let report = integrate(&problem, method, &mut watched)?;
        match watched.monitor.loss {
            Some(e) => Err(e),
            None => Ok(report),
        }
    }
}

impl<L, C, const N: usize, const K: usize> FirstOrderSystem<N> for Constrained<L, C, N, K>
where
    L: Lagrangian<N>,
    C: VelocityConstraints<N, K>,
{
    fn field(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        qdot: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        Ok((*qdot, self.multiplier_accelerations(t, q, qdot)?.qddot))
    }
}

/// The rank monitor and the caller's observer, side by side.
struct Watched<'o, M, O> {
    monitor: M,
    user: &'o mut O,
}

impl<M: Observer<N>, O: Observer<N>, const N: usize> Observer<N> for Watched<'_, M, O> {
    fn start(&mut self, state: &State<N>) {
        self.monitor.start(state);
        self.user.start(state);
    }
    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        match self.monitor.step(step) {
            Control::Continue => self.user.step(step),
            stop => stop,
        }
    }
}

/// `f(t)` as an `argmin` cost function of one real variable.
struct OneVariable<F>(F);

impl<F: Fn(f64) -> f64> argmin::core::CostFunction for OneVariable<F> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, t: &f64) -> std::result::Result<f64, argmin::core::Error> {
        Ok((self.0)(*t))
    }
}

/// The minimiser of a unimodal `f` on `[a, b]` by `argmin`'s golden-section search, started at
/// `guess ∈ [a, b]` and stopped when the bracket is `4ε` relative (at most 200 iterations);
/// `None` if the search fails.
fn golden_section_minimum(f: &impl Fn(f64) -> f64, a: f64, b: f64, guess: f64) -> Option<f64> {
    use argmin::core::{Executor, State};
    let solver = argmin::solver::goldensectionsearch::GoldenSectionSearch::new(a, b)
        .ok()?
        .with_tolerance(4.0 * f64::EPSILON)
        .ok()?;
    let result = Executor::new(OneVariable(f), solver)
        .configure(|state| state.param(guess).max_iters(200))
        .run()
        .ok()?;
    result.state().get_best_param().copied()
}

/// Relative drop of the smallest singular value of `∂g/∂q̇` within a step, below which the
/// [`RankMonitor`] reports rank loss.
pub const RANK_LOSS_TOLERANCE: f64 = 1e-6;

/// Watches the rank of `∂g/∂q̇` along a motion with state `(q, q̇)`: on every step the smallest
/// singular value `σ(t)` is sampled at seven points of the dense output; an interior dip is
/// refined by golden-section search, and if `σ` falls to [`RANK_LOSS_TOLERANCE`] times its
/// largest value on the step the run stops there and [`RankMonitor::loss`] holds the
/// [`Error::RankDeficient`] naming the time, the state and the rows that lost their independence.
pub struct RankMonitor<'a, C, const N: usize, const K: usize> {
    constraints: &'a C,
    /// The rank loss found, if any.
    pub loss: Option<Error>,
    dims: PhantomData<[[(); N]; K]>,
}

impl<'a, C: VelocityConstraints<N, K>, const N: usize, const K: usize> RankMonitor<'a, C, N, K> {
    /// A monitor for the constraints `c`.
    pub fn new(constraints: &'a C) -> Self {
        Self {
            constraints,
            loss: None,
            dims: PhantomData,
        }
    }

    fn sigma(&self, s: &State<N>) -> Option<(f64, SMatrix<f64, K, N>)> {
        let jet = velocity_jet(self.constraints, s.t, &s.q, &s.p).ok()?;
        let g = jet.gradient;
        let sv = DMatrix::from_column_slice(K, N, g.as_slice())
            .svd(false, false)
            .singular_values;
        Some((sv.min(), g))
    }
}

impl<C: VelocityConstraints<N, K>, const N: usize, const K: usize> Observer<N>
    for RankMonitor<'_, C, N, K>
{
    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        let (t0, t1) = (step.prev.t, step.next.t);
        let at_t = |t: f64| {
            if t == t0 {
                *step.prev
            } else if t == t1 {
                *step.next
            } else {
                step.dense.at(t)
            }
        };
        let mut samples = Vec::with_capacity(7);
        for k in 0..7 {
            let t = t0 + (t1 - t0) * k as f64 / 6.0;
            let Some((s, g)) = self.sigma(&at_t(t)) else {
                return Control::Continue;
            };
            samples.push((t, s, g));
        }
        let top = samples.iter().map(|x| x.1).fold(0.0, f64::max);
        let (imin, _) = samples
            .iter()
            .enumerate()
            .fold(
                (0, f64::INFINITY),
                |b, (i, x)| if x.1 < b.1 { (i, x.1) } else { b },
            );
        let (mut tmin, mut smin) = (samples[imin].0, samples[imin].1);
        if imin > 0 && imin < 6 && smin < 0.5 * top {
            // Golden-section search on the bracket around the smallest sample.
            let f = |t: f64| self.sigma(&at_t(t)).map_or(f64::INFINITY, |x| x.0);
            let (a, b) = (samples[imin - 1].0, samples[imin + 1].0);
            let tm = golden_section_minimum(&f, a, b, tmin).unwrap_or(tmin);
            let sm = f(tm);
            if sm < smin {
                (tmin, smin) = (tm, sm);
            }
        }
        if smin.is_nan() || smin > RANK_LOSS_TOLERANCE * top {
            return Control::Continue;
        }
        let state = at_t(tmin);
        let g0 = samples[0].2;
        let scale: [f64; K] =
            std::array::from_fn(|r| g0.row(r).norm().max(samples[6].2.row(r).norm()));
        let g = self.sigma(&state).map(|x| x.1).unwrap_or(g0);
        let mut rows = dependent_rows(&g, Some(&scale), RANK_LOSS_TOLERANCE);
        if rows.is_empty() {
            rows = (0..K).collect();
        }
        self.loss = Some(Error::RankDeficient {
            what: "constraint matrix ∂g/∂q̇ along the motion".into(),
            rows,
            t: tmin,
            at: at(&state.q, &state.p).to_string(),
            tolerance: RANK_LOSS_TOLERANCE,
        });
        Control::StopAt(tmin)
    }
}

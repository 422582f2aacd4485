//! RATTLE: the symplectic integrator of Hamiltonian systems with holonomic constraints
//! `g(t, q) = 0` (SHAKE for the positions, then the projection of the momenta onto the tangent
//! space of the constraint manifold).
//!
//! For `H(t, q, p)` and `K` constraints with Jacobian `G = ∂g/∂q`, one step of size `h` from
//! `(tₙ, qₙ, pₙ)` solves [Hairer, Lubich & Wanner, *Geometric Numerical Integration*, 2nd ed.,
//! VII.1.4, eq. (1.26); Andersen, J. Comput. Phys. 52 (1983) 24–34]
//!
//! ```math
//! \begin{aligned}
//! p_{n+1/2} &= p_n - \tfrac h2\big(H_q(t_n, q_n, p_{n+1/2}) + G(t_n, q_n)^{\mathsf T}\lambda_n\big),\\
//! q_{n+1} &= q_n + \tfrac h2\big(H_p(t_n, q_n, p_{n+1/2}) + H_p(t_{n+1}, q_{n+1}, p_{n+1/2})\big),
//! \qquad 0 = g(t_{n+1}, q_{n+1}),\\
//! p_{n+1} &= p_{n+1/2} - \tfrac h2\big(H_q(t_{n+1}, q_{n+1}, p_{n+1/2})
//!         + G(t_{n+1}, q_{n+1})^{\mathsf T}\mu_n\big),\\
//! 0 &= G(t_{n+1}, q_{n+1})\,H_p(t_{n+1}, q_{n+1}, p_{n+1}) + \partial_t g(t_{n+1}, q_{n+1}).
//! \end{aligned}
//! ```
//!
//! The map is of order 2, symmetric, and symplectic on the constraint manifold
//! `{g = 0, G H_p + ∂_t g = 0}` [HLW VII.1, Theorems 1.3–1.4]; for autonomous `H` and `g` the energy
//! error stays bounded over exponentially long times (backward error analysis, HLW IX.8). The
//! constraint Jacobians and the Hessians of `H` come from automatic differentiation of the one
//! definition; the two nonlinear stages are solved by Newton's method with the exact Jacobian and
//! a bounded number of iterations ([`Rattle::max_iterations`]).
//!
//! Dense output: a point inside a step is a partial RATTLE step from the step's start (on the
//! constraint manifold, see [`sampling`](super::sampling)).

use super::{observe, settle, Dense, Method, Observer, Problem, Report, Work};
use crate::constraints::{check_rank, Differentiated, HolonomicConstraints, PfaffianConstraints};
use crate::error::{all_finite, finite, Error, Lazy, Result};
use crate::hamiltonian::Hamiltonian;
use crate::phase::State;
use nalgebra::{DMatrix, DVector, SMatrix, SVector};
use std::cell::{Cell, RefCell};
use std::marker::PhantomData;
use std::time::Instant;

/// A Hamiltonian `H(t, q, p)` on `ℝᴺ × ℝᴺ` restricted by `K` holonomic constraints `g(t, q) = 0`
/// (Lagrange's equations with multipliers in Hamiltonian form, `q̇ = H_p`,
/// `ṗ = −H_q − Gᵀλ`, SPEC M16 with the crate sign of §0.3). A Lagrangian system enters through
/// [`Legendre`](crate::Legendre).
#[derive(Clone, Copy, Debug)]
pub struct ConstrainedHamiltonian<H, G, const N: usize, const K: usize> {
    /// The Hamiltonian (without non-conservative forces: RATTLE refuses them).
    pub hamiltonian: H,
    /// The holonomic constraints.
    pub constraints: G,
    dims: PhantomData<[[(); N]; K]>,
}

/// `g(t, q)`, `G = ∂g/∂q` and `∂g/∂t` at a configuration.
type PositionJet<const N: usize, const K: usize> =
    (SVector<f64, K>, SMatrix<f64, K, N>, SVector<f64, K>);

impl<H, G, const N: usize, const K: usize> ConstrainedHamiltonian<H, G, N, K>
where
    H: Hamiltonian<N>,
    G: HolonomicConstraints<N, K>,
{
    /// `H` under the constraints `g`.
    pub fn new(hamiltonian: H, constraints: G) -> Self {
        Self {
            hamiltonian,
            constraints,
            dims: PhantomData,
        }
    }

    /// `g(t, q)`, `G = ∂g/∂q` and `∂g/∂t` by AD; NaN/∞ in or out are typed errors.
    fn position_jet(&self, t: f64, q: &SVector<f64, N>) -> Result<PositionJet<N, K>> {
        finite("t", t)?;
        all_finite("q", q.as_slice())?;
        let value = self.constraints.position_constraint(t, q);
        let (jac, rate) = Differentiated(&self.constraints).forms(t, q);
        let at = Lazy(|f| write!(f, "t = {t}, q = {q:?}"));
        all_finite(format_args!("g at {at}"), value.as_slice())?;
        all_finite(format_args!("∂g/∂q at {at}"), jac.as_slice())?;
        all_finite(format_args!("∂g/∂t at {at}"), rate.as_slice())?;
        Ok((value, jac, rate))
    }

    /// The constraint residuals at `(t, q, p)`: `(max_r |g_r|, max_r |(G H_p + ∂_t g)_r|)`, the
    /// position constraints and their time derivative along the motion (the hidden constraint).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ in the input or the values.
    pub fn residuals(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<(f64, f64)> {
        all_finite("p", p.as_slice())?;
        let (g, jac, gt) = self.position_jet(t, q)?;
        let (_, _, hp) = self.hamiltonian.gradient(t, q, p);
        let v = jac * hp + gt;
        all_finite(
            format_args!("G H_p + ∂g/∂t at t = {t}, q = {q:?}, p = {p:?}"),
            v.as_slice(),
        )?;
        Ok((g.amax(), v.amax()))
    }
}

/// RATTLE with `steps` equal steps over the span of the run (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rattle {
    /// Number of steps over `[t₀, t₁]` (at least 1).
    pub steps: usize,
    /// Largest number of Newton iterations per stage ([`Rattle::MAX_ITERATIONS`] by default).
    pub max_iterations: usize,
    /// Relative tolerance of the initial state's constraint residuals (default `1e-10`): `|g_r|`
    /// must not exceed `tol (1 + Σ_s |G_rs q_s|)` nor `|G H_p + ∂_t g|_r` exceed
    /// `tol (1 + Σ_s |G_rs ∂H/∂p_s|)`.
    pub consistency: f64,
}

/// One RATTLE step: the new state and the multipliers of the two stages.
#[derive(Clone, Debug, PartialEq)]
pub struct RattleStep<const N: usize, const K: usize> {
    /// `q_{n+1}`.
    pub q: SVector<f64, N>,
    /// `p_{n+1}`.
    pub p: SVector<f64, N>,
    /// `λₙ` of the position stage (crate sign: the force is `−Gᵀλ`).
    pub lambda: SVector<f64, K>,
    /// `μₙ` of the momentum stage.
    pub mu: SVector<f64, K>,
    /// Newton iterations of both stages.
    pub iterations: usize,
}

impl Rattle {
    /// Default bound on the Newton iterations of a stage. Newton's method with the exact
    /// Jacobian converges quadratically from the explicit predictor for `h` below the stability
    /// limit; a stage needing more than this does not converge.
    pub const MAX_ITERATIONS: usize = 50;

    /// RATTLE with `steps ≥ 1` steps.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `steps = 0`.
    pub fn new(steps: usize) -> Result<Self> {
        if steps == 0 {
            return Err(Error::out_of_domain("number of steps", 0.0, "≥ 1"));
        }
        Ok(Self {
            steps,
            max_iterations: Self::MAX_ITERATIONS,
            consistency: 1e-10,
        })
    }

    /// The same with at most `n ≥ 1` Newton iterations per stage.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `n = 0`.
    pub fn with_max_iterations(mut self, n: usize) -> Result<Self> {
        if n == 0 {
            return Err(Error::out_of_domain("Newton iterations", 0.0, "≥ 1"));
        }
        self.max_iterations = n;
        Ok(self)
    }

    /// One step of size `h` from `(t, q, p)` (see the [module docs](self)).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or values; [`Error::InvalidInput`] for a Hamiltonian
    /// with non-conservative forces or `h = 0`; [`Error::RankDeficient`] naming the dependent rows
    /// of `∂g/∂q` and the configuration; [`Error::Singular`] naming the configuration when a
    /// Newton matrix is singular; [`Error::NotConverged`] (the configuration in `what`) when a
    /// stage does not converge within [`Rattle::max_iterations`].
    pub fn step<H, G, const N: usize, const K: usize>(
        &self,
        system: &ConstrainedHamiltonian<H, G, N, K>,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        h: f64,
    ) -> Result<RattleStep<N, K>>
    where
        H: Hamiltonian<N>,
        G: HolonomicConstraints<N, K>,
    {
        let h = finite("step size h", h)?;
        all_finite("p", p.as_slice())?;
        if h == 0.0 {
            return Err(Error::invalid("step size h", "h = 0: no step"));
        }
        let ham = &system.hamiltonian;
        if ham.generalized_force(t, q, p).is_some() {
            return Err(Error::invalid(
                "Hamiltonian",
                "RATTLE integrates conservative systems; the Hamiltonian declares non-conservative \
                 forces",
            ));
        }
        let t1 = t + h;
        finite("t + h", t1)?;
        let at = || format!("t = {t}, q = {q:?}, p = {p:?}, h = {h}");
        let (_, g0, _) = system.position_jet(t, q)?;
        check_rank(&g0, "constraint matrix ∂g/∂q", t, || {
            format!("q = {q:?}")
        })?;
        let half = 0.5 * h;
        // Predictor: the explicit half step and drift without constraint forces.
        let (_, hq, _) = ham.gradient(t, q, p);
        let ph0 = p - hq * half;
        let (_, _, hp) = ham.gradient(t, q, &ph0);
        let q10 = q + hp * h;
        let scale_p = p.amax().max((hq * h).amax()).max(f64::MIN_POSITIVE);
        let scale_q = q.amax().max((hp * h).amax()).max(f64::MIN_POSITIVE);
        let m = 2 * N + K;
        let mut x = DVector::zeros(m);
        x.rows_mut(0, N).copy_from(&ph0);
        x.rows_mut(N, N).copy_from(&q10);
        // Position stage: unknowns (p_{n+1/2}, q_{n+1}, λ).
        let position = |x: &DVector<f64>| -> Result<(DVector<f64>, DMatrix<f64>)> {
            let ph: SVector<f64, N> = x.fixed_rows::<N>(0).into_owned();
            let q1: SVector<f64, N> = x.fixed_rows::<N>(N).into_owned();
            let lam: SVector<f64, K> = x.fixed_rows::<K>(2 * N).into_owned();
            let (_, hq0, hp0) = ham.gradient(t, q, &ph);
            let (_, _, hp1) = ham.gradient(t1, &q1, &ph);
            let (g1, jac1, _) = system.position_jet(t1, &q1)?;
            let s0 = ham.hessian(t, q, &ph)?;
            let s1 = ham.hessian(t1, &q1, &ph)?;
            let mut r = DVector::zeros(m);
            r.rows_mut(0, N)
                .copy_from(&(ph - p + (hq0 + g0.transpose() * lam) * half));
            r.rows_mut(N, N).copy_from(&(q1 - q - (hp0 + hp1) * half));
            r.rows_mut(2 * N, K).copy_from(&g1);
            let mut j = DMatrix::zeros(m, m);
            let id = SMatrix::<f64, N, N>::identity();
            j.view_mut((0, 0), (N, N)).copy_from(&(id + s0.qp * half));
            j.view_mut((0, 2 * N), (N, K))
                .copy_from(&(g0.transpose() * half));
            j.view_mut((N, 0), (N, N))
                .copy_from(&(-(s0.pp + s1.pp) * half));
            j.view_mut((N, N), (N, N)).copy_from(&(id - s1.pq * half));
            j.view_mut((2 * N, N), (K, N)).copy_from(&jac1);
            Ok((r, j))
        };
        let small = |dx: &DVector<f64>, _x: &DVector<f64>| {
            let dp = dx.rows(0, N).amax();
            let dq = dx.rows(N, N).amax();
            let dl: SVector<f64, K> = dx.fixed_rows::<K>(2 * N).into_owned();
            let dlp = (g0.transpose() * dl).amax() * half.abs();
            dp <= 8.0 * f64::EPSILON * scale_p
                && dlp <= 8.0 * f64::EPSILON * scale_p
                && dq <= 8.0 * f64::EPSILON * scale_q
        };
        let (x, it1) = newton(x, position, small, self.max_iterations, || {
            format!("RATTLE position stage at {}", at())
        })?;
        let ph: SVector<f64, N> = x.fixed_rows::<N>(0).into_owned();
        let q1: SVector<f64, N> = x.fixed_rows::<N>(N).into_owned();
        let lambda: SVector<f64, K> = x.fixed_rows::<K>(2 * N).into_owned();
        // Momentum stage: unknowns (p_{n+1}, μ).
        let (_, jac1, gt1) = system.position_jet(t1, &q1)?;
        check_rank(&jac1, "constraint matrix ∂g/∂q", t1, || {
            format!("q = {q1:?}")
        })?;
        let (_, hq1, _) = ham.gradient(t1, &q1, &ph);
        let base = ph - hq1 * half;
        let scale_p1 = ph.amax().max((hq1 * h).amax()).max(f64::MIN_POSITIVE);
        let mk = N + K;
        let mut y = DVector::zeros(mk);
        y.rows_mut(0, N).copy_from(&base);
        let momentum = |y: &DVector<f64>| -> Result<(DVector<f64>, DMatrix<f64>)> {
            let p1: SVector<f64, N> = y.fixed_rows::<N>(0).into_owned();
            let mu: SVector<f64, K> = y.fixed_rows::<K>(N).into_owned();
            let (_, _, hp1) = ham.gradient(t1, &q1, &p1);
            let s1 = ham.hessian(t1, &q1, &p1)?;
            let mut r = DVector::zeros(mk);
            r.rows_mut(0, N)
                .copy_from(&(p1 - base + jac1.transpose() * mu * half));
            r.rows_mut(N, K).copy_from(&(jac1 * hp1 + gt1));
            let mut j = DMatrix::zeros(mk, mk);
            j.view_mut((0, 0), (N, N))
                .copy_from(&SMatrix::<f64, N, N>::identity());
            j.view_mut((0, N), (N, K))
                .copy_from(&(jac1.transpose() * half));
            j.view_mut((N, 0), (K, N)).copy_from(&(jac1 * s1.pp));
            Ok((r, j))
        };
        let small2 = |dx: &DVector<f64>, _y: &DVector<f64>| {
            let dp = dx.rows(0, N).amax();
            let dm: SVector<f64, K> = dx.fixed_rows::<K>(N).into_owned();
            let dmp = (jac1.transpose() * dm).amax() * half.abs();
            dp <= 8.0 * f64::EPSILON * scale_p1 && dmp <= 8.0 * f64::EPSILON * scale_p1
        };
        let (y, it2) = newton(y, momentum, small2, self.max_iterations, || {
            format!("RATTLE momentum stage at {}, q_(n+1) = {q1:?}", at())
        })?;
        let p1: SVector<f64, N> = y.fixed_rows::<N>(0).into_owned();
        let mu: SVector<f64, K> = y.fixed_rows::<K>(N).into_owned();
        let out = RattleStep {
            q: q1,
            p: p1,
            lambda,
            mu,
            iterations: it1 + it2,
        };
        all_finite(
            Lazy(|f| write!(f, "RATTLE q_(n+1) from {}", at())),
            out.q.as_slice(),
        )?;
        all_finite(
            Lazy(|f| write!(f, "RATTLE p_(n+1) from {}", at())),
            out.p.as_slice(),
        )?;
        Ok(out)
    }

    /// The initial state must lie on the constraint manifold (see [`Rattle::consistency`]).
    fn check_start<H, G, const N: usize, const K: usize>(
        &self,
        system: &ConstrainedHamiltonian<H, G, N, K>,
        s: &State<N>,
    ) -> Result<()>
    where
        H: Hamiltonian<N>,
        G: HolonomicConstraints<N, K>,
    {
        let (g, jac, gt) = system.position_jet(s.t, &s.q)?;
        let (_, _, hp) = system.hamiltonian.gradient(s.t, &s.q, &s.p);
        all_finite("∂H/∂p at the initial state", hp.as_slice())?;
        let v = jac * hp + gt;
        let tol = self.consistency;
        let bad = (0..K).any(|r| {
            let sq: f64 = (0..N).map(|c| (jac[(r, c)] * s.q[c]).abs()).sum();
            let sv: f64 = (0..N).map(|c| (jac[(r, c)] * hp[c]).abs()).sum();
            g[r].abs() > tol * (1.0 + sq) || v[r].abs() > tol * (1.0 + sv)
        });
        if bad {
            return Err(Error::ConstraintViolated {
                what: format!(
                    "initial state (g, G H_p + ∂g/∂t) at t = {}, q = {:?}, p = {:?}",
                    s.t, s.q, s.p
                ),
                residual: g.iter().chain(v.iter()).copied().collect(),
                tolerance: tol,
            });
        }
        Ok(())
    }
}

/// Newton's method on `f(x) = 0` with the Jacobian `f` returns, from `x`, until `small(Δx, x)`
/// (the correction is at rounding level) or the correction stops shrinking at rounding level;
/// at most `max` iterations.
pub(crate) fn newton<F, S>(
    mut x: DVector<f64>,
    mut f: F,
    small: S,
    max: usize,
    what: impl Fn() -> String,
) -> Result<(DVector<f64>, usize)>
where
    F: FnMut(&DVector<f64>) -> Result<(DVector<f64>, DMatrix<f64>)>,
    S: Fn(&DVector<f64>, &DVector<f64>) -> bool,
{
    let mut last = f64::INFINITY;
    let mut residual = f64::INFINITY;
    for k in 1..=max {
        let (r, j) = f(&x)?;
        residual = r.amax();
        if !residual.is_finite() {
            return Err(Error::NonFinite {
                what: format!("residual of {}", what()),
                value: residual,
            });
        }
        let dx = j.lu().solve(&(-r)).ok_or_else(|| Error::Singular {
            what: "Newton matrix".into(),
            at: what(),
            rcond: 0.0,
        })?;
        if !dx.iter().all(|v| v.is_finite()) {
            return Err(Error::Singular {
                what: "Newton matrix".into(),
                at: what(),
                rcond: 0.0,
            });
        }
        let norm = dx.amax();
        x += &dx;
        if small(&dx, &x) {
            return Ok((x, k));
        }
        // Rounding floor: the correction no longer shrinks although it is tiny.
        if k > 2 && norm >= 0.5 * last && norm <= 1e-9 * x.amax() {
            return Ok((x, k));
        }
        last = norm;
    }
    Err(Error::NotConverged {
        what: what(),
        iterations: max,
        residual,
    })
}

/// Dense output of a RATTLE step: partial steps from the step's start.
struct PartialRattle<'a, H, G, const N: usize, const K: usize> {
    method: &'a Rattle,
    system: &'a ConstrainedHamiltonian<H, G, N, K>,
    prev: State<N>,
    next: State<N>,
    iterations: Cell<usize>,
    error: RefCell<Option<Error>>,
}

impl<H, G, const N: usize, const K: usize> Dense<N> for PartialRattle<'_, H, G, N, K>
where
    H: Hamiltonian<N>,
    G: HolonomicConstraints<N, K>,
{
    fn at(&self, t: f64) -> State<N> {
        if t == self.prev.t {
            return self.prev;
        }
        if t == self.next.t {
            return self.next;
        }
        let s = &self.prev;
        match self.method.step(self.system, s.t, &s.q, &s.p, t - s.t) {
            Ok(r) => {
                self.iterations.set(self.iterations.get() + r.iterations);
                State { t, q: r.q, p: r.p }
            }
            Err(e) => {
                self.error.borrow_mut().get_or_insert(e);
                State {
                    t,
                    q: SVector::repeat(f64::NAN),
                    p: SVector::repeat(f64::NAN),
                }
            }
        }
    }
}

impl<H, G, const N: usize, const K: usize> Method<ConstrainedHamiltonian<H, G, N, K>, N> for Rattle
where
    H: Hamiltonian<N>,
    G: HolonomicConstraints<N, K>,
{
    fn label(&self) -> String {
        format!("RATTLE n={}", self.steps)
    }

    fn run<O: Observer<N>>(
        &self,
        problem: &Problem<'_, ConstrainedHamiltonian<H, G, N, K>, N>,
        observer: &mut O,
    ) -> Result<Report<N>> {
        let clock = Instant::now();
        if self.steps == 0 {
            return Err(Error::out_of_domain("number of steps", 0.0, "≥ 1"));
        }
        let (t0, span) = (problem.start.t, problem.span());
        let dt = span / self.steps as f64;
        if !(dt.is_finite() && dt != 0.0) {
            return Err(Error::out_of_domain(
                "step size",
                dt,
                "finite and non-zero (span / steps)",
            ));
        }
        let system = problem.system;
        self.check_start(system, &problem.start)?;
        let mut work = Work::default();
        let mut state = problem.start;
        observer.start(&state);
        let mut stopped = false;
        for k in 0..self.steps {
            let r = self.step(system, state.t, &state.q, &state.p, dt)?;
            work.steps += 1;
            work.newton_iterations += r.iterations;
            work.gradients += 3 + 2 * r.iterations;
            work.hessians += 2 * r.iterations;
            let next = State {
                t: if k + 1 == self.steps {
                    problem.t1
                } else {
                    t0 + dt * (k + 1) as f64
                },
                q: r.q,
                p: r.p,
            };
            let dense = PartialRattle {
                method: self,
                system,
                prev: state,
                next,
                iterations: Cell::new(0),
                error: RefCell::new(None),
            };
            let (control, stop_state) = observe(observer, &state, &next, &dense)?;
            work.newton_iterations += dense.iterations.get();
            if let Some(e) = dense.error.into_inner() {
                return Err(e);
            }
            let end;
            (state, end) = settle(control, next, stop_state, k + 1 == self.steps, problem.t1);
            if let Some(s) = end {
                stopped = s;
                break;
            }
        }
        Ok(Report {
            last: state,
            stopped,
            work,
            elapsed: clock.elapsed(),
        })
    }
}

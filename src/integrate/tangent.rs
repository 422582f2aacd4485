//! Tangent maps through the integrators' own steps: the derivative `Φ = ∂z(t₁)/∂z(t₀)` of the
//! computed final state with respect to the initial state `z = (q, p)`, by automatic
//! differentiation of the method itself.
//!
//! A numerical method is a map `Ψ = Ψ_{h_n} ∘ … ∘ Ψ_{h_1}`; its Jacobian is the product of the
//! step Jacobians (chain rule), which AD forms exactly by running the same steps on dual numbers
//! (Griewank & Walther, *Evaluating Derivatives*, 2nd ed., SIAM 2008, ch. 3; Hairer, Nørsett &
//! Wanner, *Solving ODEs I*, 2nd ed., §I.14 and §II.6 "internal numerical differentiation"):
//!
//! ```math
//! \Phi = \frac{\partial \Psi}{\partial z_0}
//! = \Psi'_{h_n}(z_{n-1}) \cdots \Psi'_{h_1}(z_0).
//! ```
//!
//! * Fixed-step methods ([`Fixed`] over any [`OneStep`]: the explicit splittings and
//!   compositions, RK4, Gauss–Legendre) are written once for every dual type, so the run is
//!   repeated on [`PhaseDual64`](crate::ad::PhaseDual64) numbers whose `2N`-wide infinitesimal
//!   parts carry all of `Φ` in one pass. For a symplectic method `Φ` is symplectic to rounding.
//!   Gauss–Legendre's implicit stages are differentiated by the implicit-function theorem at the
//!   converged stage values ([`super::gauss`], "Exact derivatives of the step"), not through the
//!   Newton iterations. The real parts of the dual run round exactly as the real run (the
//!   compensated summation included), so the final state is the real run's.
//! * [`Dop853`] runs once on reals, choosing its steps by its error control on `z` alone; the
//!   accepted step sequence is recorded and the same steps are replayed on dual numbers (the
//!   step sizes frozen, not differentiated). With the variational equations integrated instead
//!   (below) the result is the tangent map of a DOP853 run too (an explicit Runge–Kutta method
//!   commutes with linearisation, HNW I.14 / II.6), on a different step sequence.
//! * [`Taylor`] likewise runs once on reals, its steps (and its order) chosen on `z` alone and
//!   recorded; they are replayed on the record of the variational equations, Hamilton's
//!   equations evaluated on dual numbers over the record (one per column of `Φ`), whose Taylor
//!   step at the frozen `h` and order is the step of `z` together with its exact Jacobian (the
//!   Taylor coefficients of `Φ` are the derivatives of those of `z` with respect to `z₀`).
//! * Whether the tangent components enter the error norm of an adaptive method is the user's
//!   choice: [`TangentMethod::tangent_map`] freezes the steps chosen on `z`,
//!   [`variational_tangent_map`] integrates `Φ̇ = (∂f/∂z) Φ`, `Φ(t₀) = I` together with `z`
//!   ([`VariationalMethod`]: DOP853 on [`ParameterSensitivity`], the Taylor method on the
//!   variational record), so its steps are controlled on `(z, Φ)`.
//!
//! Derivatives with respect to the parameters `k` of a [`Parametric`] system come from the same
//! machinery: the parameters become coordinates that do not move ([`ParameterCoordinates`]), so
//! that `∂z(t₁)/∂k` is a block of the extended system's tangent map
//! ([`parameter_tangent_map`]); for the splittings of a [`ParametricSeparable`] system, the
//! parameters enter the drifts and kicks as dual numbers ([`splitting_parameter_tangent_map`]);
//! or, with the variational equations in the error norm, from [`ParameterSensitivity`] through
//! any first-order integrator.

use super::dop853::stages;
use super::rk45;
use super::sensitivity::{ParameterSensitivity, Unparametrised};
use super::taylor::SeriesSteps;
use super::{
    compensated_add, integrate, AnyMethod, Control, Dop853, Fixed, GeneralMethod, Method, Observer,
    OneStep, Problem, Rk45, Splitting, StepView, Taylor, TaylorControl, VectorFieldRecord, Work,
};
use crate::ad::{jacobian, PhaseMap};
use crate::error::{Error, Result};
use crate::hamiltonian::{Hamiltonian, Parametric, ParametricSeparable, Separable};
use crate::phase::{CanonicalPair, PhaseMatrix, State};
use nalgebra::{SMatrix, SVector};
use num_dual::{Dual64, DualNum};

/// The final state of a run and the tangent map `Φ = ∂z(t₁)/∂z(t₀)` of the method that computed
/// it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TangentMap<const N: usize> {
    /// The final state.
    pub last: State<N>,
    /// `∂(q, p)(t₁)/∂(q, p)(t₀)`.
    pub jacobian: PhaseMatrix<N>,
    /// Work of the real run (the dual replay repeats it on dual numbers).
    pub work: Work,
}

/// A method whose run can be differentiated with respect to the initial state.
pub trait TangentMethod<S, const N: usize> {
    /// The final state of `problem` and the tangent map of the run.
    ///
    /// # Errors
    /// The errors of the run; [`Error::NonFinite`] when the derivatives overflow.
    fn tangent_map(&self, problem: &Problem<'_, S, N>) -> Result<TangentMap<N>>;
}

/// The fixed-step run of `method` from `(t₀, z₀)` to `t₁` as a map of phase space, on any number
/// type: the step times and the summation of [`Fixed`]'s driver.
struct FixedRun<'a, S, M> {
    system: &'a S,
    method: &'a Fixed<M>,
    t1: f64,
}

impl<S, M: OneStep<S, N>, const N: usize> PhaseMap<N> for FixedRun<'_, S, M> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> CanonicalPair<N, D> {
        let mut work = Work::default();
        // A failed step makes the map non-finite, which `run_jacobian` reports.
        fixed_steps(
            self.method,
            t.re(),
            self.t1,
            q,
            p,
            |tk, q, p, dt| {
                self.method
                    .method
                    .increment(self.system, tk, q, p, dt, &mut work)
            },
            |_, _, _| Ok(()),
        )
        .unwrap_or_else(|_| {
            let nan = SVector::from_element(D::from(f64::NAN));
            (nan, nan)
        })
    }
}

/// The running sums of [`fixed_steps`]: the state and the carries of its compensated sums (zero
/// when the method sums plainly).
pub(crate) struct FixedSums<D, const N: usize> {
    pub q: SVector<D, N>,
    pub p: SVector<D, N>,
    pub cq: SVector<D, N>,
    pub cp: SVector<D, N>,
}

/// The driver of [`Fixed`] on any number type: `method.steps` equal steps from `(t₀, q, p)` to
/// `t₁`, each the increment `increment(t_k, q, p, h)`, summed (compensated when the method is) as
/// by [`integrate`]; after step `k` (ending at `t`), `after_step(k, t, sums)` may inspect or
/// rescale the sums. The first error of a step or of `after_step` ends the run.
pub(crate) fn fixed_steps<D: DualNum<f64> + Copy, M, const N: usize>(
    method: &Fixed<M>,
    t0: f64,
    t1: f64,
    q: &SVector<D, N>,
    p: &SVector<D, N>,
    mut increment: impl FnMut(
        D,
        &SVector<D, N>,
        &SVector<D, N>,
        D,
    ) -> Result<(SVector<D, N>, SVector<D, N>)>,
    mut after_step: impl FnMut(usize, f64, &mut FixedSums<D, N>) -> Result<()>,
) -> Result<CanonicalPair<N, D>> {
    let steps = method.steps;
    let dt = (t1 - t0) / steps as f64;
    let mut sums = FixedSums {
        q: *q,
        p: *p,
        cq: SVector::zeros(),
        cp: SVector::zeros(),
    };
    let mut tk = t0;
    for k in 0..steps {
        let (dq, dp) = increment(D::from(tk), &sums.q, &sums.p, D::from(dt))?;
        if method.compensated {
            compensated_add(&mut sums.q, &mut sums.cq, &dq);
            compensated_add(&mut sums.p, &mut sums.cp, &dp);
        } else {
            sums.q += dq;
            sums.p += dp;
        }
        tk = if k + 1 == steps {
            t1
        } else {
            t0 + dt * (k + 1) as f64
        };
        after_step(k, tk, &mut sums)?;
    }
    Ok((sums.q, sums.p))
}

/// The Jacobian of `map` at the problem's initial state, with the errors named after `what`.
fn run_jacobian<M: PhaseMap<N>, S, const N: usize>(
    map: &M,
    problem: &Problem<'_, S, N>,
    what: &str,
) -> Result<PhaseMatrix<N>> {
    let s = &problem.start;
    jacobian(map, s.t, &s.q, &s.p).map_err(|e| match e {
        Error::NonFinite { value, .. } => Error::NonFinite {
            what: format!(
                "tangent map of {what} from t = {:e} to {:e}",
                s.t, problem.t1
            ),
            value,
        },
        e => e,
    })
}

impl<S: Hamiltonian<N>, M: OneStep<S, N>, const N: usize> TangentMethod<S, N> for Fixed<M> {
    fn tangent_map(&self, problem: &Problem<'_, S, N>) -> Result<TangentMap<N>> {
        let run = integrate(problem, self, &mut ())?;
        let map = FixedRun {
            system: problem.system,
            method: self,
            t1: problem.t1,
        };
        let jacobian = run_jacobian(&map, problem, &Method::<S, N>::label(self))?;
        Ok(TangentMap {
            last: run.last,
            jacobian,
            work: run.work,
        })
    }
}

/// Records the times of the accepted steps.
struct StepTimes(Vec<f64>);

impl<const N: usize> Observer<N> for StepTimes {
    fn start(&mut self, state: &State<N>) {
        self.0.push(state.t);
    }
    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        self.0.push(step.next.t);
        Control::Continue
    }
}

/// DOP853's steps between the given times (frozen step sizes), on any number type.
struct Dop853Replay<'a, S> {
    system: &'a S,
    times: &'a [f64],
}

impl<S: Hamiltonian<N>, const N: usize> PhaseMap<N> for Dop853Replay<'_, S> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> CanonicalPair<N, D> {
        let mut field = |t: D, q: &SVector<D, N>, p: &SVector<D, N>| {
            Ok(self.system.vector_field_generic(t, q, p))
        };
        let zero = (SVector::<D, N>::zeros(), SVector::<D, N>::zeros());
        let mut k = [zero; 16];
        let mut y = (*q, *p);
        let t0 = D::from(self.times[0]);
        k[0] = self.system.vector_field_generic(t0, q, p);
        for w in self.times.windows(2) {
            let (t, h) = (D::from(w[0]), D::from(w[1] - w[0]));
            y = match stages(&mut field, t, &y, h, &mut k) {
                Ok((y1, _)) => y1,
                Err(_) => {
                    let nan = SVector::from_element(D::from(f64::NAN));
                    return (nan, nan);
                }
            };
            k[0] = self.system.vector_field_generic(D::from(w[1]), &y.0, &y.1);
        }
        y
    }
}

/// `method` with, unless it sets its own, a step budget of [`Dop853::AUTO_STEPS_MAX`]` / c`
/// attempted steps, `c` the cost of a step relative to one of the state alone, so that the budget
/// bounds the same work as the longest default run of the state: `c = 1 + 2N` for the replay of
/// the steps on dual numbers carrying `2N` directions, `c = (1 + 2N)²` for the variational
/// equations, whose `2N` directions each evaluate the vector field on nested dual numbers
/// (measured on Hénon–Heiles, `N = 2`: 3.5 and 11 times a step of the state).
fn tangent_budget(method: &Dop853, cost: usize) -> Dop853 {
    let mut m = *method;
    if m.max_steps.is_none() {
        m.max_steps = Some(Dop853::AUTO_STEPS_MAX / cost);
    }
    m
}

impl<S: Hamiltonian<N>, const N: usize> TangentMethod<S, N> for Dop853 {
    /// The steps chosen by the error control on `z` alone, replayed on dual numbers; see
    /// [`variational_tangent_map`] for steps controlled on `(z, Φ)`. Unless the method sets its
    /// own, the step budget is [`Dop853::AUTO_STEPS_MAX`]` / (1 + 2N)`. The replay updates the
    /// state plainly; with [compensated summation](Dop853::with_compensated_summation) the
    /// final state is the compensated run's and the Jacobian the plain replay's (they differ by
    /// the rounding of the updates, `O(u)` relative per step).
    fn tangent_map(&self, problem: &Problem<'_, S, N>) -> Result<TangentMap<N>> {
        let mut times = StepTimes(Vec::new());
        let run = integrate(problem, &tangent_budget(self, 1 + 2 * N), &mut times)?;
        let map = Dop853Replay {
            system: problem.system,
            times: &times.0,
        };
        // With compensated summation the run's own end state is the accurate one; the replay
        // (plain updates, `O(u)` per step from it) serves the Jacobian only.
        let last = if self.compensated {
            run.last
        } else {
            let s = &problem.start;
            let (q, p) = map.apply(s.t, &s.q, &s.p);
            State::new(run.last.t, q, p)?
        };
        let jacobian = run_jacobian(&map, problem, &Method::<S, N>::label(self))?;
        Ok(TangentMap {
            last,
            jacobian,
            work: run.work,
        })
    }
}

/// RK45's steps between the given times (frozen step sizes), on any number type; the last
/// stage of a step is the first of the next (FSAL), as in the run on reals.
struct Rk45Replay<'a, S> {
    system: &'a S,
    times: &'a [f64],
}

impl<S: Hamiltonian<N>, const N: usize> PhaseMap<N> for Rk45Replay<'_, S> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> CanonicalPair<N, D> {
        let mut field = |t: D, q: &SVector<D, N>, p: &SVector<D, N>| {
            Ok(self.system.vector_field_generic(t, q, p))
        };
        let zero = (SVector::<D, N>::zeros(), SVector::<D, N>::zeros());
        let mut k = [zero; 7];
        let mut y = (*q, *p);
        k[0] = self
            .system
            .vector_field_generic(D::from(self.times[0]), q, p);
        for w in self.times.windows(2) {
            let (t, h) = (D::from(w[0]), D::from(w[1] - w[0]));
            y = match rk45::step(&mut field, t, &y, h, &mut k) {
                Ok(y1) => y1,
                Err(_) => {
                    let nan = SVector::from_element(D::from(f64::NAN));
                    return (nan, nan);
                }
            };
            k[0] = k[6];
        }
        y
    }
}

impl<S: Hamiltonian<N>, const N: usize> TangentMethod<S, N> for Rk45 {
    /// The steps chosen by the error control on `z` alone, replayed on dual numbers. Unless the
    /// method sets its own, the step budget is [`Dop853::AUTO_STEPS_MAX`]` / (1 + 2N)`.
    fn tangent_map(&self, problem: &Problem<'_, S, N>) -> Result<TangentMap<N>> {
        let mut method = *self;
        if method.max_steps.is_none() {
            method.max_steps = Some(Dop853::AUTO_STEPS_MAX / (1 + 2 * N));
        }
        let mut times = StepTimes(Vec::new());
        let run = integrate(problem, &method, &mut times)?;
        let map = Rk45Replay {
            system: problem.system,
            times: &times.0,
        };
        let s = &problem.start;
        let (q, p) = map.apply(s.t, &s.q, &s.p);
        let last = State::new(run.last.t, q, p)?;
        let jacobian = run_jacobian(&map, problem, &Method::<S, N>::label(self))?;
        Ok(TangentMap {
            last,
            jacobian,
            work: run.work,
        })
    }
}

/// A method whose error control can take the tangent map into its norm: it integrates the
/// variational equations `ż = f(z)`, `Φ̇ = (∂f/∂z) Φ`, `Φ(t₀) = I` together with `z`, so that its
/// steps control the error of `Φ` as well as that of `z` ([`variational_tangent_map`]).
pub trait VariationalMethod {
    /// The final state and tangent map of `problem`, the steps controlled on `(z, Φ)`; `K` must
    /// equal `N(1 + 2N)`.
    ///
    /// # Errors
    /// See [`variational_tangent_map`].
    fn variational_run<S: Hamiltonian<N>, const N: usize, const K: usize>(
        &self,
        problem: &Problem<'_, S, N>,
    ) -> Result<TangentMap<N>>;
}

/// The final state and tangent map of `problem` with the tangent components in the method's
/// error norm: the method integrates the variational equations `ż = f(z)`, `Φ̇ = (∂f/∂z) Φ`,
/// `Φ(t₀) = I` together with `z`, so its steps control the error of `Φ` as well as that of `z`.
/// This is the user's choice against [`TangentMethod::tangent_map`], whose steps are chosen on
/// `z` alone and frozen. `K` must equal `N(1 + 2N)` (e.g. 10 for `N = 2`).
///
/// * [`Dop853`]: on [`ParameterSensitivity::with_initial_state`] of the system without
///   parameters; unless the method sets its own, the step budget is
///   [`Dop853::AUTO_STEPS_MAX`]` / (1 + 2N)²`.
/// * [`Taylor`]: on the record of the variational equations, the order the method's and, for a
///   tolerance, the step from the series of every component of `(z, Φ)`; the step budget is
///   `max_steps / (1 + 2N)` for a tolerance.
///
/// # Errors
/// [`Error::InvalidInput`] for another `K`, or for DOP853 on a system with non-conservative forces
/// (which the variational equations of `H` alone do not contain); the errors of the run.
pub fn variational_tangent_map<S: Hamiltonian<N>, const N: usize, const K: usize>(
    problem: &Problem<'_, S, N>,
    method: &impl VariationalMethod,
) -> Result<TangentMap<N>> {
    method.variational_run::<S, N, K>(problem)
}

impl VariationalMethod for Dop853 {
    fn variational_run<S: Hamiltonian<N>, const N: usize, const K: usize>(
        &self,
        problem: &Problem<'_, S, N>,
    ) -> Result<TangentMap<N>> {
        let s = &problem.start;
        if problem.system.generalized_force(s.t, &s.q, &s.p).is_some() {
            return Err(Error::invalid(
                "system of a variational tangent map",
                "has non-conservative forces; use the tangent map of the DOP853 run \
                 (TangentMethod::tangent_map), which differentiates them",
            ));
        }
        let plain = Unparametrised(problem.system);
        let augmented = ParameterSensitivity::<_, N, 0, K>::with_initial_state(&plain)?;
        let (qa, pa) = augmented.initial_state(&s.q, &s.p);
        let big = Problem::new(&augmented, s.t, qa, pa, problem.t1)?;
        let run = integrate(&big, &tangent_budget(self, (1 + 2 * N).pow(2)), &mut ())?;
        let (q, p, _, _) = augmented.split(&run.last.q, &run.last.p);
        Ok(TangentMap {
            last: State::new(run.last.t, q, p)?,
            jacobian: augmented.tangent(&run.last.q, &run.last.p)?,
            work: run.work,
        })
    }
}

/// `method` with, for a tolerance, the step budget divided by `cost`, the cost of a step of the
/// tangent run relative to one of the state alone (`1 + 2N` for the variational record, which
/// evaluates the field once per column of `Φ` and once for `z`); a fixed number of steps is the
/// user's own and is kept.
fn taylor_budget(method: &Taylor, cost: usize) -> Taylor {
    let mut m = *method;
    if let TaylorControl::Tolerance(_) = m.control {
        m.max_steps = (m.max_steps / cost).max(1);
    }
    m
}

/// The state `(z, Φ = I)` of the variational record at the start of `problem`.
fn variational_start<S, const N: usize>(problem: &Problem<'_, S, N>) -> Vec<f64> {
    let n = 2 * N;
    let s = &problem.start;
    let mut x = Vec::with_capacity(n * (1 + n));
    x.extend(s.q.iter().chain(s.p.iter()));
    for j in 0..n {
        x.extend((0..n).map(|i| if i == j { 1.0 } else { 0.0 }));
    }
    x
}

/// The final state and tangent map of a Taylor run on the variational record.
fn variational_end<const N: usize>(x: &[f64], t1: f64, work: Work) -> Result<TangentMap<N>> {
    let n = 2 * N;
    let at = |r: usize, c: usize| x[n + n * c + r];
    Ok(TangentMap {
        last: State::new(
            t1,
            SVector::from_fn(|i, _| x[i]),
            SVector::from_fn(|i, _| x[N + i]),
        )?,
        jacobian: PhaseMatrix {
            qq: SMatrix::from_fn(at),
            qp: SMatrix::from_fn(|r, c| at(r, N + c)),
            pq: SMatrix::from_fn(|r, c| at(N + r, c)),
            pp: SMatrix::from_fn(|r, c| at(N + r, N + c)),
        },
        work,
    })
}

impl<S: Hamiltonian<N>, const N: usize> TangentMethod<S, N> for Taylor {
    /// The steps (and the order) chosen by the control on `z` alone, recorded and replayed on the
    /// record of the variational equations ([`VectorFieldRecord`] evaluated on dual numbers, one
    /// per column of `Φ`): a Taylor step of that record at the frozen `h` and order is the
    /// step of the field together with its exact Jacobian, since the Taylor coefficients of `Φ`
    /// are the derivatives of those of `z` with respect to `z₀`. See [`variational_tangent_map`]
    /// for steps controlled on `(z, Φ)`. For a tolerance the budget of the run is
    /// `max_steps / (1 + 2N)`.
    fn tangent_map(&self, problem: &Problem<'_, S, N>) -> Result<TangentMap<N>> {
        let field = VectorFieldRecord::new(problem.system, &problem.start)?;
        let mut times = StepTimes(Vec::new());
        let run = taylor_budget(self, 1 + 2 * N).run_recorded(&field, problem, &mut times)?;
        let variational = field.variational(&problem.start)?;
        let mut x = variational_start(problem);
        self.series_run(
            &variational,
            problem.start.t,
            &mut x,
            problem.t1,
            SeriesSteps::Frozen(&times.0),
        )?;
        variational_end(&x, run.last.t, run.work)
    }
}

impl VariationalMethod for Taylor {
    fn variational_run<S: Hamiltonian<N>, const N: usize, const K: usize>(
        &self,
        problem: &Problem<'_, S, N>,
    ) -> Result<TangentMap<N>> {
        if K != N * (1 + 2 * N) {
            return Err(Error::invalid(
                format!("dimension K = {K} of the variational equations"),
                format!(
                    "with N = {N} degrees of freedom K must be {}",
                    N * (1 + 2 * N)
                ),
            ));
        }
        let field = VectorFieldRecord::new(problem.system, &problem.start)?;
        let variational = field.variational(&problem.start)?;
        let mut x = variational_start(problem);
        let work = taylor_budget(self, 1 + 2 * N).series_run(
            &variational,
            problem.start.t,
            &mut x,
            problem.t1,
            SeriesSteps::Control,
        )?;
        variational_end(&x, problem.t1, work)
    }
}

impl<S: Hamiltonian<N>, const N: usize> TangentMethod<S, N> for GeneralMethod {
    fn tangent_map(&self, problem: &Problem<'_, S, N>) -> Result<TangentMap<N>> {
        match self {
            Self::Rk4(m) => m.tangent_map(problem),
            Self::Gauss1(m) => m.tangent_map(problem),
            Self::Gauss2(m) => m.tangent_map(problem),
            Self::Gauss3(m) => m.tangent_map(problem),
            Self::Gauss4(m) => m.tangent_map(problem),
            Self::Gauss5(m) => m.tangent_map(problem),
            Self::Gauss6(m) => m.tangent_map(problem),
            Self::Dop853(m) => m.tangent_map(problem),
            Self::Rk45(m) => m.tangent_map(problem),
            Self::Taylor(m) => m.tangent_map(problem),
        }
    }
}

impl<S: crate::hamiltonian::Separable<N>, const N: usize> TangentMethod<S, N> for AnyMethod {
    fn tangent_map(&self, problem: &Problem<'_, S, N>) -> Result<TangentMap<N>> {
        match self {
            Self::General(m) => m.tangent_map(problem),
            Self::Splitting(m) => m.tangent_map(problem),
            Self::TimeTransformed(m) => Err(Error::invalid(
                format!("tangent map of {}", m.name()),
                "not available for time-transformed splittings (their end point is found by an \
                 iteration in fictitious time); use the splitting in physical time or DOP853",
            )),
        }
    }
}

/// A [`Parametric`] system with its parameters `k` as `M` further coordinates that do not move:
/// `H̃(q, k; p, π) = H(k; q, p)` on `ℝᴷ × ℝᴷ`, `K = N + M`, so that `k̇ = ∂H̃/∂π = 0` and `(q, p)`
/// move as in the system at `k`. Any method for a general Hamiltonian runs on it unchanged (the
/// stages see `k` exactly constant), and its tangent map contains `∂(q, p)/∂k`:
/// [`parameter_tangent_map`].
#[derive(Clone, Copy, Debug)]
pub struct ParameterCoordinates<'a, S, const N: usize, const M: usize, const K: usize> {
    system: &'a S,
}

impl<'a, S: Parametric<N, M>, const N: usize, const M: usize, const K: usize>
    ParameterCoordinates<'a, S, N, M, K>
{
    /// The extended system; an error unless `K = N + M`.
    pub fn new(system: &'a S) -> Result<Self> {
        if K != N + M {
            return Err(Error::invalid(
                format!("dimension K = {K} of a system with its parameters as coordinates"),
                format!("with N = {N} degrees of freedom and M = {M} parameters K must be N + M"),
            ));
        }
        Ok(Self { system })
    }
}

impl<S: Parametric<N, M>, const N: usize, const M: usize, const K: usize> Hamiltonian<K>
    for ParameterCoordinates<'_, S, N, M, K>
{
    fn hamiltonian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, K>, p: &SVector<D, K>) -> D {
        let k = SVector::<D, M>::from_fn(|i, _| q[N + i]);
        let qs = SVector::<D, N>::from_fn(|i, _| q[i]);
        let ps = SVector::<D, N>::from_fn(|i, _| p[i]);
        self.system.hamiltonian_with(&k, t, &qs, &ps)
    }
}

/// The final state of a run of a [`Parametric`] system at its nominal parameters and the
/// derivatives of that state with respect to the initial state and to the parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ParameterTangent<const N: usize, const M: usize> {
    /// The final state.
    pub last: State<N>,
    /// `∂(q, p)(t₁)/∂(q, p)(t₀)`.
    pub jacobian: PhaseMatrix<N>,
    /// `∂q(t₁)/∂k`.
    pub dq_dk: SMatrix<f64, N, M>,
    /// `∂p(t₁)/∂k`.
    pub dp_dk: SMatrix<f64, N, M>,
}

/// The tangent map of `method` on `problem` with respect to the initial state and to the
/// system's parameters `k`: the method runs on [`ParameterCoordinates`] (`K = N + M`) from
/// `(q₀, k; p₀, 0)` and its tangent map is differentiated through its own steps
/// ([`TangentMethod`]). Applies to the methods for a general Hamiltonian (Gauss–Legendre, RK4,
/// DOP853 with frozen steps); for the variational equations in DOP853's error norm use
/// [`ParameterSensitivity`].
///
/// # Errors
/// [`Error::InvalidInput`] unless `K = N + M`; [`Error::NonFinite`] for non-finite parameters;
/// the errors of the run.
pub fn parameter_tangent_map<S, T, const N: usize, const M: usize, const K: usize>(
    problem: &Problem<'_, S, N>,
    method: &T,
) -> Result<ParameterTangent<N, M>>
where
    S: Parametric<N, M>,
    T: for<'b> TangentMethod<ParameterCoordinates<'b, S, N, M, K>, K>,
{
    let extended = ParameterCoordinates::<S, N, M, K>::new(problem.system)?;
    let k = finite_parameters(problem.system)?;
    let s = &problem.start;
    let q = SVector::<f64, K>::from_fn(|i, _| if i < N { s.q[i] } else { k[i - N] });
    let p = SVector::<f64, K>::from_fn(|i, _| if i < N { s.p[i] } else { 0.0 });
    let big = Problem::new(&extended, s.t, q, p, problem.t1)?;
    let tm = method.tangent_map(&big)?;
    let j = &tm.jacobian;
    Ok(ParameterTangent {
        last: State::new(
            tm.last.t,
            SVector::from_fn(|i, _| tm.last.q[i]),
            SVector::from_fn(|i, _| tm.last.p[i]),
        )?,
        jacobian: PhaseMatrix {
            qq: SMatrix::from_fn(|r, c| j.qq[(r, c)]),
            qp: SMatrix::from_fn(|r, c| j.qp[(r, c)]),
            pq: SMatrix::from_fn(|r, c| j.pq[(r, c)]),
            pp: SMatrix::from_fn(|r, c| j.pp[(r, c)]),
        },
        dq_dk: SMatrix::from_fn(|r, c| j.qq[(r, N + c)]),
        dp_dk: SMatrix::from_fn(|r, c| j.pq[(r, N + c)]),
    })
}

/// The nominal parameters of `system`; [`Error::NonFinite`] names a non-finite one.
fn finite_parameters<S: Parametric<N, M>, const N: usize, const M: usize>(
    system: &S,
) -> Result<SVector<f64, M>> {
    let k = system.parameters();
    if let Some((i, v)) = k.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(Error::NonFinite {
            what: format!("parameter {} of the system", S::NAMES[i]),
            value: *v,
        });
    }
    Ok(k)
}

/// The tangent map of a fixed-step splitting run of a [`ParametricSeparable`] system with respect
/// to the initial state and to the parameters `k`, by AD through the splitting's own steps: the
/// composition of exact drifts `q ↦ q + h ∇_p T(k; p)` and kicks `p ↦ p − h ∇_q V(k; q)` is run
/// on dual numbers whose infinitesimal parts carry one parameter direction `e_j`, the parameters
/// entering each sub-flow as `k + ε e_j`, so that
///
/// ```math
/// \frac{\partial z_n}{\partial k_j}
/// = \sum_{m=1}^{n} \Psi'_{h}(z_{n-1}) \cdots \Psi'_{h}(z_{m})\,
///   \frac{\partial \Psi_h}{\partial k_j}(z_{m-1})
/// ```
///
/// is formed exactly (forward mode, Griewank & Walther, *Evaluating Derivatives*, 2nd ed., SIAM
/// 2008, ch. 3). The splittings do not run on [`ParameterCoordinates`] (with `k` among the
/// coordinates the kinetic part `T(k; p)` is not a function of the momenta alone), so this is the
/// splittings' counterpart of [`parameter_tangent_map`]. The state block is the splitting's
/// [`TangentMethod::tangent_map`]; the real parts of the parameter runs round exactly as the
/// real run, so the final state is the real run's.
///
/// # Errors
/// [`Error::NonFinite`] for non-finite parameters or derivatives; [`Error::InvalidInput`] for a
/// system with non-conservative forces; the errors of the run.
pub fn splitting_parameter_tangent_map<S, const N: usize, const M: usize>(
    problem: &Problem<'_, S, N>,
    method: &Fixed<Splitting>,
) -> Result<ParameterTangent<N, M>>
where
    S: ParametricSeparable<N, M> + Separable<N>,
{
    let k = finite_parameters(problem.system)?;
    let tm = method.tangent_map(problem)?;
    let s = &problem.start;
    let mut dq_dk = SMatrix::<f64, N, M>::zeros();
    let mut dp_dk = SMatrix::<f64, N, M>::zeros();
    for j in 0..M {
        let kd =
            SVector::<Dual64, M>::from_fn(|i, _| Dual64::new(k[i], if i == j { 1.0 } else { 0.0 }));
        let mut work = Work::default();
        let (q, p) = fixed_steps(
            method,
            s.t,
            problem.t1,
            &s.q.map(Dual64::from_re),
            &s.p.map(Dual64::from_re),
            |t, q, p, h| {
                method
                    .method
                    .increment_at(problem.system, &kd, t, q, p, h, &mut work)
            },
            |_, _, _| Ok(()),
        )?;
        let column = q.iter().chain(p.iter()).map(|d| d.eps);
        if let Some(v) = column.clone().find(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                what: format!(
                    "derivative with respect to {} of {} from t = {:e} to {:e}",
                    S::NAMES[j],
                    Method::<S, N>::label(method),
                    s.t,
                    problem.t1
                ),
                value: v,
            });
        }
        dq_dk.set_column(j, &q.map(|d| d.eps));
        dp_dk.set_column(j, &p.map(|d| d.eps));
    }
    Ok(ParameterTangent {
        last: tm.last,
        jacobian: tm.jacobian,
        dq_dk,
        dp_dk,
    })
}

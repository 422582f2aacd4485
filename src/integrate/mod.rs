//! Numerical integration of Hamilton's equations: the problem, the method and the run kept apart.
//!
//! ```text
//! integrate(&problem, &method, &mut observer) -> Result<Report>
//! ```
//!
//! * A [`Problem`] is a system with an initial state `(t₀, q₀, p₀)` and a final time `t₁`.
//! * A method is a small value carrying its coefficients and knobs. Fixed-step one-step methods
//!   implement [`OneStep`] — one step written once for every dual type, so that the step map can be
//!   certified symplectic by AD ([`StepMap`]) — and run under [`Fixed`], which adds the step loop,
//!   optional compensated summation and dense output by partial steps of the method itself
//!   ([`sampling`]). A step that cannot be differentiated (an
//!   exact flow through Kepler's equation) refuses dual arguments with an error; adaptive methods
//!   implement [`Method`] directly ([`Dop853`]; the Taylor method over the record of Hamilton's
//!   equations, [`Taylor`]).
//! * Each method states the capability it needs as a trait bound on the system (explicit splitting
//!   needs [`Separable`](crate::Separable), Gauss–Legendre any [`Hamiltonian`]): applying a method
//!   to a system without that capability does not compile.
//! * Holonomic constraints `g(t, q) = 0`: [`Rattle`] on a [`ConstrainedHamiltonian`], symplectic
//!   on the constraint manifold ([`rattle`]).
//! * An [`Observer`] sees every step (with dense output over it) and may stop the run: record
//!   ([`Recorder`]), sample at requested times ([`Samples`]), locate events ([`Events`]) and
//!   Poincaré sections ([`Section`]).
//! * A method is also a value: [`AnyMethod`] / [`GeneralMethod`] hold any of the crate's general
//!   and splitting methods, so a list of methods can be built at run time and swept.
//! * Every method the crate ships is described once, in [`METHODS`]: its key, label
//!   (`"Gauss–Legendre, 3 stages, order 6"`), stages, order, knob, symplecticity, capability and
//!   source; names, scene keys and run-time construction are derived from it ([`methods`]).
//! * Every run reports its [`Work`] — steps and evaluations of `H`, its gradient and Hessian — and
//!   its wall time, so that cost can be compared as counts as well as time.

pub mod any;
pub mod blow_up;
pub mod coefficients;
pub mod dop853;
pub mod exact;
pub mod gauss;
pub mod lie_poisson;
pub mod methods;
pub mod observers;
pub mod rattle;
pub mod regularised;
pub mod rk4;
pub mod rk45;
pub mod sampling;
pub mod sensitivity;
pub mod splitting;
pub mod tangent;
pub mod taylor;
pub mod time_transform;
pub mod wisdom_holman;

pub use any::{AnyMethod, GeneralMethod};
pub use blow_up::{BlowUpDetector, Singularity};
pub use dop853::Dop853;
pub use exact::ExactStep;
pub use gauss::{Gauss, ImplicitMidpoint};
pub use lie_poisson::LiePoisson;
pub use methods::{MethodInfo, METHODS};
pub use observers::{
    Crossing, EnergyMonitor, Event, Events, Recorder, Samples, Section, MAX_SAMPLES,
};
pub use rattle::{ConstrainedHamiltonian, Rattle, RattleStep};
pub use regularised::{KustaanheimoStiefel, LeviCivita, Regularisation, RegularisedRun};
pub use rk4::{rk4_increment, Rk4};
pub use rk45::Rk45;
pub use sensitivity::{parametric_vector_field, ParameterSensitivity, Unparametrised};
pub use splitting::Splitting;
pub use tangent::{
    parameter_tangent_map, splitting_parameter_tangent_map, variational_tangent_map,
    ParameterCoordinates, ParameterTangent, TangentMap, TangentMethod, VariationalMethod,
};
pub use taylor::{Precision, Taylor, TaylorControl, VectorFieldRecord};
pub use time_transform::{Sundman, TimeTransformed};
pub use wisdom_holman::{PerturbedKepler, PlanetaryWisdomHolman, WisdomHolman};

use crate::brackets::PhaseMap;
use crate::error::{finite, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::phase::State;
use nalgebra::SVector;
use num_dual::DualNum;
use std::time::{Duration, Instant};

/// A first-order system on `ℝᴺ × ℝᴺ`, `(q̇, ṗ) = f(t, q, p)`, evaluated on reals: Hamilton's
/// equations of any [`Hamiltonian`] (blanket implementation), or any other ODE whose state splits
/// into two `N`-blocks (e.g. element equations of perturbation theory,
/// [`crate::perturbation::ode::Ode`]). Adaptive methods ([`Dop853`]) need only this.
pub trait FirstOrderSystem<const N: usize> {
    /// `f(t, q, p)`; an error where the system is undefined.
    #[allow(clippy::type_complexity)]
    fn field(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)>;
}

impl<H: Hamiltonian<N>, const N: usize> FirstOrderSystem<N> for H {
    #[inline]
    fn field(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        Ok(self.vector_field_unchecked(t, q, p))
    }
}

/// An initial-value problem for Hamilton's equations of `system`.
#[derive(Clone, Copy, Debug)]
pub struct Problem<'a, S, const N: usize> {
    /// The system.
    pub system: &'a S,
    /// The initial state.
    pub start: State<N>,
    /// The final time (before or after `t₀`).
    pub t1: f64,
}

impl<'a, S, const N: usize> Problem<'a, S, N> {
    /// The motion of `system` from `(q₀, p₀)` at `t₀` to `t₁ ≠ t₀`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite entry; [`Error::InvalidInput`] for `t₁ = t₀`;
    /// [`Error::OutOfDomain`] when the span `t₁ − t₀` overflows (e.g. `t₀ = −10³⁰⁸`,
    /// `t₁ = 10³⁰⁸`): no step size could divide it.
    pub fn new(
        system: &'a S,
        t0: f64,
        q0: SVector<f64, N>,
        p0: SVector<f64, N>,
        t1: f64,
    ) -> Result<Self> {
        let start = State::new(t0, q0, p0)?;
        let t1 = finite("final time t₁", t1)?;
        if t1 == t0 {
            return Err(Error::invalid("time span", "t₁ = t₀: nothing to integrate"));
        }
        let span = t1 - t0;
        if !span.is_finite() {
            return Err(Error::out_of_domain(
                "time span t₁ − t₀",
                span,
                format!("finite (|t₁ − t₀| ≤ {:e})", f64::MAX),
            ));
        }
        Ok(Self { system, start, t1 })
    }
    /// `t₁ − t₀`.
    pub fn span(&self) -> f64 {
        self.t1 - self.start.t
    }
}

/// Work done by a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Work {
    /// Accepted steps.
    pub steps: usize,
    /// Rejected steps (adaptive methods).
    pub rejected: usize,
    /// Evaluations of the vector field or of one of `∂H/∂q`, `∂H/∂p` (one AD gradient pass each;
    /// a separable kick or drift counts one).
    pub gradients: usize,
    /// Evaluations of `H` alone.
    pub hamiltonians: usize,
    /// Evaluations of the Hessian of `H` (implicit methods' Newton).
    pub hessians: usize,
    /// Newton iterations (implicit methods).
    pub newton_iterations: usize,
    /// Evaluations of a closed-form flow (exact or Kepler drift).
    pub flows: usize,
}

impl Work {
    /// Sum of two counts.
    pub fn add(&self, o: &Work) -> Work {
        Work {
            steps: self.steps + o.steps,
            rejected: self.rejected + o.rejected,
            gradients: self.gradients + o.gradients,
            hamiltonians: self.hamiltonians + o.hamiltonians,
            hessians: self.hessians + o.hessians,
            newton_iterations: self.newton_iterations + o.newton_iterations,
            flows: self.flows + o.flows,
        }
    }
}

/// The outcome of a run.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Report<const N: usize> {
    /// The state where the run ended: `last.t` is the time actually reached — `t₁`, or the end of
    /// the step after which an observer returned [`Control::Stop`], or the time it named in
    /// [`Control::StopAt`].
    pub last: State<N>,
    /// Whether an observer stopped the run before `t₁`.
    pub stopped: bool,
    /// Work counts.
    pub work: Work,
    /// Wall time of the run.
    pub elapsed: Duration,
}

/// What an observer wants after a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Control {
    /// Go on.
    Continue,
    /// Stop the run now (at the end of this step).
    Stop,
    /// Stop the run at time `t` inside this step (e.g. a terminal event); the driver ends the run
    /// with the dense-output state there. A `t` outside the step (or NaN) ends the run with
    /// [`Error::OutOfDomain`].
    StopAt(f64),
}

/// Dense output over one step: the state at any time between its ends — a partial step of the
/// method for [`Fixed`] runs, the continuous extension for [`Dop853`] ([`sampling`]).
pub trait Dense<const N: usize> {
    /// The state at `t` (between the step's ends).
    fn at(&self, t: f64) -> State<N>;
}

/// One step as seen by observers: its ends and its dense output.
pub struct StepView<'a, const N: usize> {
    /// State at the beginning of the step.
    pub prev: &'a State<N>,
    /// State at the end of the step.
    pub next: &'a State<N>,
    /// The state at times within the step.
    pub dense: &'a dyn Dense<N>,
}

/// Sees the run step by step: record, monitor invariants, locate events,
/// stop early. All methods default to doing nothing.
pub trait Observer<const N: usize> {
    /// Called once with the initial state.
    fn start(&mut self, _state: &State<N>) {}
    /// Called after every accepted step.
    fn step(&mut self, _step: &StepView<'_, N>) -> Control {
        Control::Continue
    }
}

/// The observer that does nothing.
impl<const N: usize> Observer<N> for () {}

/// A closure `FnMut(&State) -> Control` called at the end of every step.
pub struct Each<F>(pub F);

impl<F: FnMut(&State<N>) -> Control, const N: usize> Observer<N> for Each<F> {
    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        (self.0)(step.next)
    }
}

impl<A: Observer<N>, B: Observer<N>, const N: usize> Observer<N> for (A, B) {
    fn start(&mut self, state: &State<N>) {
        self.0.start(state);
        self.1.start(state);
    }
    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        let a = self.0.step(step);
        let b = self.1.step(step);
        match (a, b) {
            (Control::StopAt(x), Control::StopAt(y)) => {
                // The earlier one in the direction of integration.
                if (x - step.prev.t).abs() <= (y - step.prev.t).abs() {
                    Control::StopAt(x)
                } else {
                    Control::StopAt(y)
                }
            }
            (Control::StopAt(x), _) | (_, Control::StopAt(x)) => Control::StopAt(x),
            (Control::Stop, _) | (_, Control::Stop) => Control::Stop,
            _ => Control::Continue,
        }
    }
}

/// The time of an observer's [`Control::StopAt`], checked to lie in the step `[prev.t, next.t]`
/// (so that the report's `last.t` is a time the run reached, not an extrapolation).
pub(crate) fn stop_time<const N: usize>(t: f64, prev: &State<N>, next: &State<N>) -> Result<f64> {
    let (lo, hi) = if prev.t <= next.t {
        (prev.t, next.t)
    } else {
        (next.t, prev.t)
    };
    if lo <= t && t <= hi {
        Ok(t)
    } else {
        Err(Error::out_of_domain(
            "stop time requested by an observer (Control::StopAt)",
            t,
            format!("the step [{lo:e}, {hi:e}] just taken"),
        ))
    }
}

/// An integration method for systems of type `S`.
pub trait Method<S, const N: usize> {
    /// A short label with the knob, e.g. `"Störmer–Verlet (kick–drift–kick), 1 stage, order 2
    /// n=100"`: the method's [`MethodInfo::label`] and its steps or tolerances.
    fn label(&self) -> String;
    /// Run the method on the problem, reporting every step to the observer.
    fn run<O: Observer<N>>(
        &self,
        problem: &Problem<'_, S, N>,
        observer: &mut O,
    ) -> Result<Report<N>>;
}

/// Integrate `problem` with `method`, reporting every step to `observer`.
pub fn integrate<S, M: Method<S, N>, O: Observer<N>, const N: usize>(
    problem: &Problem<'_, S, N>,
    method: &M,
    observer: &mut O,
) -> Result<Report<N>> {
    method.run(problem, observer)
}

/// A fixed-step one-step method written once for every dual type (so that its step map can be
/// differentiated: [`StepMap`]).
///
/// `increment` returns `(Δq, Δp)` of one step of size `dt` from `(t, q, p)`; the driver adds them
/// (with compensated summation if asked), which keeps the rounding of long runs small.
pub trait OneStep<S, const N: usize> {
    /// Order of the method.
    fn order(&self) -> u32;
    /// Name of the method: its label, `"<family>, <s> stages, order <p>"` ([`methods`]).
    fn name(&self) -> String;
    /// The increments of one step.
    #[allow(clippy::type_complexity)]
    fn increment<D: DualNum<f64> + Copy>(
        &self,
        system: &S,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        dt: D,
        work: &mut Work,
    ) -> Result<(SVector<D, N>, SVector<D, N>)>;
}

/// A fixed-step run: `steps` equal steps over the problem's span.
///
/// The number of steps a run may start is bounded by `max_steps` (default [`Fixed::MAX_STEPS`]),
/// so that a mistyped count is a prompt error, not a run of hours; [`Fixed::with_limit`] raises it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fixed<M> {
    /// The one-step method.
    pub method: M,
    /// Number of steps over the span.
    pub steps: usize,
    /// Largest `steps` a run accepts ([`Method::run`] checks it again).
    pub max_steps: usize,
    /// Kahan-compensated accumulation of the increments (Hairer, Lubich & Wanner, *Geometric
    /// Numerical Integration*, 2nd ed., VIII.5): rounding then grows like `√n` instead of `n`.
    pub compensated: bool,
}

impl<M> Fixed<M> {
    /// Default limit on the number of steps of one run: 10⁸ (seconds to minutes of work for a
    /// small system, depending on the method; five times the longest run of the test suite).
    pub const MAX_STEPS: usize = 100_000_000;

    /// `1 ≤ steps ≤` [`Fixed::MAX_STEPS`] steps of `method`, with compensated summation.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `steps = 0`; [`Error::WorkLimit`] above the limit (use
    /// [`Fixed::with_limit`] for longer runs).
    pub fn new(method: M, steps: usize) -> Result<Self> {
        Self::with_limit(method, steps, Self::MAX_STEPS)
    }

    /// `1 ≤ steps ≤ max_steps` steps of `method`: the caller raises (or lowers) the limit on the
    /// work of one run.
    ///
    /// # Errors
    /// As [`Fixed::new`], with `max_steps` as the limit.
    pub fn with_limit(method: M, steps: usize, max_steps: usize) -> Result<Self> {
        let m = Self {
            method,
            steps,
            max_steps,
            compensated: true,
        };
        m.check_steps()?;
        Ok(m)
    }

    pub(crate) fn check_steps(&self) -> Result<()> {
        if self.steps == 0 {
            return Err(Error::out_of_domain("number of steps", 0.0, "≥ 1"));
        }
        if self.steps > self.max_steps {
            return Err(Error::WorkLimit {
                what: "fixed-step run".into(),
                limit: self.max_steps,
                detail: format!("{:e} steps requested", self.steps as f64),
                hint: "use fewer steps, or raise the limit with Fixed::with_limit(method, steps, \
                       max_steps)"
                    .into(),
            });
        }
        Ok(())
    }
    /// The same with plain summation.
    pub fn uncompensated(mut self) -> Self {
        self.compensated = false;
        self
    }
}

/// Kahan-compensated `x += dx` on phase vectors ([`kahan_add`](crate::special::double_double::kahan_add)
/// componentwise).
#[inline]
pub(crate) fn compensated_add<D: DualNum<f64> + Copy, const N: usize>(
    x: &mut SVector<D, N>,
    carry: &mut SVector<D, N>,
    dx: &SVector<D, N>,
) {
    crate::special::double_double::compensated_add(
        x.as_mut_slice(),
        carry.as_mut_slice(),
        dx.as_slice(),
    );
}

impl<S: Hamiltonian<N>, M: OneStep<S, N>, const N: usize> Method<S, N> for Fixed<M> {
    fn label(&self) -> String {
        format!("{} n={}", OneStep::<S, N>::name(&self.method), self.steps)
    }

    fn run<O: Observer<N>>(
        &self,
        problem: &Problem<'_, S, N>,
        observer: &mut O,
    ) -> Result<Report<N>> {
        self.check_steps()?;
        let clock = Instant::now();
        let mut work = Work::default();
        let (t0, span) = (problem.start.t, problem.span());
        let dt = span / self.steps as f64;
        if !(dt.is_finite() && dt != 0.0) {
            return Err(Error::out_of_domain(
                "step size",
                dt,
                "finite and non-zero (span / steps)",
            ));
        }
        let mut state = problem.start;
        check_initial_field(problem)?;
        let (mut cq, mut cp) = (SVector::<f64, N>::zeros(), SVector::<f64, N>::zeros());
        observer.start(&state);
        let mut stopped = false;
        for k in 0..self.steps {
            let (dq, dp) = self.method.increment(
                problem.system,
                state.t,
                &state.q,
                &state.p,
                dt,
                &mut work,
            )?;
            let mut next = state;
            let carry = (cq, cp);
            if self.compensated {
                compensated_add(&mut next.q, &mut cq, &dq);
                compensated_add(&mut next.p, &mut cp, &dp);
            } else {
                next.q += dq;
                next.p += dp;
            }
            // Times from the step index, not by accumulation.
            next.t = if k + 1 == self.steps {
                problem.t1
            } else {
                t0 + dt * (k + 1) as f64
            };
            work.steps += 1;
            if !next.is_finite() {
                return Err(Error::NonFinite {
                    what: format!(
                        "{} state at t = {}",
                        OneStep::<S, N>::name(&self.method),
                        next.t
                    ),
                    value: f64::NAN,
                });
            }
            // Points inside the step are partial steps of the method (`sampling`).
            let dense = sampling::PartialStep::new(
                problem.system,
                &self.method,
                state,
                next,
                carry,
                self.compensated,
            );
            let (control, stop_state) = observe(observer, &state, &next, &dense)?;
            work = work.add(&dense.finish()?);
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

/// Show the step `prev → next` (with its dense output) to `observer`; its answer, and for
/// `StopAt(t)` the state at `t` (checked to lie within the step).
pub(crate) fn observe<O: Observer<N>, const N: usize>(
    observer: &mut O,
    prev: &State<N>,
    next: &State<N>,
    dense: &dyn Dense<N>,
) -> Result<(Control, Option<State<N>>)> {
    let control = observer.step(&StepView { prev, next, dense });
    let stop_state = match control {
        Control::StopAt(t) => Some(dense.at(stop_time(t, prev, next)?)),
        _ => None,
    };
    Ok((control, stop_state))
}

/// The state a fixed-step driver continues from after an observer's answer, and `Some(stopped)`
/// when the run ends there: `Continue` takes `next`; `Stop` ends at `next` (stopped early unless
/// it was the `last` step); `StopAt` ends at `stop_state` (stopped early unless that is `t₁`).
pub(crate) fn settle<const N: usize>(
    control: Control,
    next: State<N>,
    stop_state: Option<State<N>>,
    last: bool,
    t1: f64,
) -> (State<N>, Option<bool>) {
    match control {
        Control::Continue => (next, None),
        Control::Stop => (next, Some(!last)),
        Control::StopAt(_) => {
            let state = stop_state.unwrap_or(next);
            (state, Some(state.t != t1))
        }
    }
}

/// Refuse a start where the vector field is not finite (a singularity of the system, e.g. the
/// Kepler collision `q = 0`): no step from there approximates a solution.
fn check_initial_field<S: FirstOrderSystem<N>, const N: usize>(
    problem: &Problem<'_, S, N>,
) -> Result<()> {
    let s = &problem.start;
    let (dq, dp) = problem.system.field(s.t, &s.q, &s.p)?;
    match dq.iter().chain(dp.iter()).find(|v| !v.is_finite()) {
        None => Ok(()),
        Some(&value) => Err(Error::NonFinite {
            what: format!(
                "vector field at the initial state t = {:e}, q = {:?}, p = {:?} (a singularity \
                 of the system)",
                s.t, s.q, s.p
            ),
            value,
        }),
    }
}

/// One step of a [`OneStep`] method as a [`PhaseMap`] (for [`certify`](crate::brackets::certify)):
/// `(q, p) ↦ (q, p) + increment(q, p)`. A failed step (e.g. Newton not converging) maps to NaN,
/// which `certify` reports as an error.
pub struct StepMap<'a, S, M> {
    /// The system.
    pub system: &'a S,
    /// The method.
    pub method: &'a M,
    /// The step size.
    pub dt: f64,
}

impl<S, M: OneStep<S, N>, const N: usize> PhaseMap<N> for StepMap<'_, S, M> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        let mut work = Work::default();
        match self
            .method
            .increment(self.system, t, q, p, D::from(self.dt), &mut work)
        {
            Ok((dq, dp)) => (q + dq, p + dp),
            Err(_) => {
                let nan = SVector::from_element(D::from(f64::NAN));
                (nan, nan)
            }
        }
    }
}

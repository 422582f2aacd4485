//! The Taylor method for any [`Hamiltonian`]: Hamilton's equations recorded once as a list of
//! elementary operations, their solution's Taylor series to order `p` by the recurrences over
//! that record, adaptive order and step after Jorba & Zou.
//!
//! # The method
//! The vector field `f = (∂H/∂p, −∂H/∂q + Q^{nc})` is recorded once per run
//! ([`VectorFieldRecord`]): `H` (and `Q^{nc}`) evaluated on the recording number of
//! [`crate::record`], the gradient by the adjoint sweep over that record. From `(t₀, x₀)` the
//! normalised Taylor coefficients of the solution follow order by order,
//!
//! ```math
//! x(t_0 + h) = \sum_{k=0}^{p} x_k h^k,\qquad x_{k+1} = \frac{f_k}{k+1},
//! ```
//!
//! where `f_k`, the `k`-th coefficient of `f(t, x(t))`, is computed from `x₀ … x_k` by the
//! `O(k)` recurrences of each recorded operation ([`Jets`]): `O(p²)` per operation and step, no
//! allocation per step. The coefficients of every intermediate live in one buffer made at the
//! start of the run.
//!
//! # What makes it fast
//! The record is translated once per run into a flat program ([`Jets`], "the program") in
//! which the linear operations are folded into scale factors (they cost nothing), `sin`/`cos`
//! pairs are one instruction, and operand offsets are resolved. Under the feature `jit` (on by
//! default) the whole Taylor pass of that program to the run's order is then **compiled once
//! per record and order by Cranelift** into one native function: the recurrences of every
//! instruction and order unrolled into straight-line code, the coefficients register values,
//! the Cauchy sums summed pairwise (a short dependency chain per order), the products `j·u_j`
//! shared, `1/k` constants — heyoka's approach. The compiled passes of the latest records and
//! orders are kept, so that the runs after the first on an equal record and the same order do
//! not compile again; [`Jets::compile_time`] gives the compilation time, counted apart as
//! heyoka counts its own. Where nothing is compiled (the feature off, a pass too large, a host Cranelift
//! does not support) the **interpreter** runs the program order by order, one dispatch per
//! instruction and order, by a pass monomorphised for each order up to 24 (Cauchy sums of
//! a length known at compile time, unrolled). Either way the cost of a step is about the
//! number of products, quotients and roots of the record times `p²/2` multiply–adds.
//!
//! # Order and step (Jorba & Zou 2005, §3.2)
//! With one tolerance `ε` as both the absolute and the relative tolerance, the order is
//!
//! ```math
//! p = \Big\lceil -\tfrac12 \ln \varepsilon + 1 \Big\rceil ,
//! ```
//!
//! and the step, with `‖·‖` the maximum norm over `(q, p)`, divided by `‖x₀‖` when `‖x₀‖ > 1`
//! (the relative tolerance governs), is
//!
//! ```math
//! h = \frac{\rho}{e^2}\, e^{-0.7/(p-1)},\qquad
//! \rho = \min\Big( \|x_{p-1}\|^{-1/(p-1)},\ \|x_p\|^{-1/p} \Big):
//! ```
//!
//! `ρ` estimates the radius of convergence, and the last terms of the series then lie near
//! `(h/ρ)^p ≈ e^{-2p} ≈ ε`. Every step is accepted (there is no error estimate to reject
//! on); the final step is shortened to end at `t₁`. [`Taylor::fixed`] runs a given order with
//! equal steps instead (the local error is `O(h^{p+1})`, the global error `O(h^p)`).
//!
//! # Rounding
//! Two sums that would otherwise round once per step are kept exactly enough not to: the time
//! is carried in double-length form `t = t_hi + t_lo` (the error-free sum of
//! the crate's `DoubleDouble`, as heyoka keeps its time), the distance to
//! `t₁` taken from both parts; and the new state `x₀ + δ`, `δ = h Σ_{k≥1} x_k h^{k−1}`, is added
//! with Kahan's compensation (the part of `δ` lost to the rounding of `x₀ + δ` is added to the
//! next step's `δ`). Plain `t += h` would add `ulp(t)/2` per step to the phase — at `t ≈ 670`
//! that is `5.7·10⁻¹⁴`, a random walk of `≈ 10⁻¹²` over 2200 steps, twenty times the error
//! otherwise reached at tolerance `10⁻¹⁵` on the pendulum (`tests/taylor.rs`,
//! `pendulum_final_error_at_the_rounding_floor`).
//!
//! # Double-double
//! [`Taylor::double_double`] ([`Precision::DoubleDouble`]) runs the same method — the same
//! program, recurrences, order and step-size control — with every coefficient, the state and
//! the time as double-double numbers (`hi + lo`, about 106 bits; Joldes, Muller & Popescu 2017):
//! the jets' values of order 0 by the double-double elementary functions, the state update
//! `Σ x_k h^k` by Horner's rule in double-double, the last step `t₁ − t` in double-double. The
//! initial state (doubles) is taken exactly; the states handed to observers and the final state
//! are rounded to doubles; the record's constants and folded scale factors are doubles (exact
//! for `½`, `2`, `−1`; a constant such as `0.1` is the double nearest it, as in the double
//! method). Each double-double operation costs about ten to twenty double operations.
//!
//! It is the method for problems whose conditioning exceeds what double rounding allows: near
//! the pendulum's separatrix (`q₀ = 3.14159`, `E_sep − E ≈ (π − q₀)²/2 ≈ 3.5·10⁻¹²`) the period
//! `T ≈ 2 ln(32/(E_sep − E))` changes by `δT ≈ 2 δE/(E_sep − E)`, so a relative energy error
//! of `u ≈ 10⁻¹⁶` per step already shifts the phase by `10⁻⁴` per period; holding the final
//! error to `10⁻⁹` over 100 periods needs the energy to about `10⁻¹⁸` (`tests/taylor_dd.rs`).
//! Tolerances below `10⁻¹⁶` (down to [`Taylor::TOL_MIN`]) are meaningful here, not in doubles.
//!
//! # Dense output
//! The step's series itself: the state at `t₀ + τ`, `τ` within the step, is `Σ x_k τ^k`
//! (Horner), of the order of the method.
//!
//! # Work counted
//! `steps` as usual; `gradients` counts one per step (one propagation of the record to order
//! `p`, which costs about `p²/2` vector-field evaluations' worth of operations); recording is done
//! once per run and timed separately in [`VectorFieldRecord::new`], and compiling once per
//! record and order, in the first run ([`Jets::compile_time`]).
//!
//! # References
//! * À. Jorba & M. Zou, "A software package for the numerical integration of ODEs by means of
//!   high-order Taylor methods", Exp. Math. 14 (2005) 99–117.
//! * E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
//!   Springer 1993, §I.8 (the Taylor series method).
//! * F. Biscani & D. Izzo, "Revisiting high-order Taylor methods for astrodynamics and celestial
//!   mechanics", MNRAS 504 (2021) 2614–2628 (the same decomposition and step control in heyoka).

use super::{methods, observe, settle, Dense, Fixed, Method, Observer, Problem, Report, Work};
use crate::error::{Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::phase::State;
use crate::record::{gradient, record, JetCoefficient, Jets, Record, Recorded, MAX_ORDER};
use crate::series::ball::Field;
use crate::special::double_double::{two_sum, DoubleDouble};
use nalgebra::SVector;
use num_dual::Dual;
use std::marker::PhantomData;
use std::time::Instant;

/// Hamilton's equations of a system as an operation record: inputs `(t, q₁…q_N, p₁…p_N)`,
/// outputs `(q̇₁…q̇_N, ṗ₁…ṗ_N)` (see the [module docs](self)).
#[derive(Clone, Debug, PartialEq)]
pub struct VectorFieldRecord<const N: usize> {
    record: Record,
    _n: PhantomData<[(); N]>,
}

impl<const N: usize> VectorFieldRecord<N> {
    /// Record Hamilton's equations of `system`, its `H` evaluated once at `start` (the point
    /// matters only for branches `H` takes on values).
    ///
    /// # Errors
    /// The errors of [`record`] (an operation without a recurrence, such as `sph_j0`).
    pub fn new<S: Hamiltonian<N>>(system: &S, start: &State<N>) -> Result<Self> {
        let mut x = Vec::with_capacity(2 * N + 1);
        x.push(start.t);
        x.extend(start.q.iter().chain(start.p.iter()));
        let record = record(&x, |v| {
            let t = v[0];
            let q = SVector::<_, N>::from_fn(|i, _| v[1 + i]);
            let p = SVector::<_, N>::from_fn(|i, _| v[1 + N + i]);
            let h = system.hamiltonian(t, &q, &p);
            let g = gradient(h, &v[1..]);
            let force = system.generalized_force(t, &q, &p);
            let mut out = Vec::with_capacity(2 * N);
            out.extend_from_slice(&g[N..]);
            for i in 0..N {
                out.push(match force {
                    Some(f) => f[i] - g[i],
                    None => -g[i],
                });
            }
            Ok(out)
        })?;
        Ok(Self {
            record,
            _n: PhantomData,
        })
    }

    /// The record.
    pub fn record(&self) -> &Record {
        &self.record
    }

    /// `(q̇, ṗ)` at `(t, q, p)` by evaluating the record.
    ///
    /// # Errors
    /// None for a record made by [`new`](Self::new) (the error of [`Record::eval`] otherwise).
    pub fn eval(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        let mut x = Vec::with_capacity(2 * N + 1);
        x.push(t);
        x.extend(q.iter().chain(p.iter()));
        let y = self.record.eval(&x)?;
        Ok((
            SVector::from_fn(|i, _| y[i]),
            SVector::from_fn(|i, _| y[N + i]),
        ))
    }
}

impl<const N: usize> VectorFieldRecord<N> {
    /// The variational equations of the recorded field, `ẋ = f(t, x)`, `Φ̇ = (∂f/∂x)(t, x) Φ`,
    /// as a record with inputs `(t, x, Φe₁, …, Φe_{2N})` and outputs
    /// `(f, (∂f/∂x)Φe₁, …, (∂f/∂x)Φe_{2N})` (HNW I, §I.14): each column is the recorded field
    /// evaluated on dual numbers whose infinitesimal parts are that column (forward mode over the
    /// record, Griewank & Walther §3.1), so that the Taylor coefficients of `Φ` from `Φ(t₀) = I`
    /// are the derivatives with respect to `x₀` of those of `x`, and a Taylor step of this record
    /// is the step of the field with its Jacobian. `start` is the recording point (with `Φ = I`).
    pub(crate) fn variational(&self, start: &State<N>) -> Result<Record> {
        let n = 2 * N;
        let mut x = Vec::with_capacity(1 + n * (1 + n));
        x.push(start.t);
        x.extend(start.q.iter().chain(start.p.iter()));
        for j in 0..n {
            x.extend((0..n).map(|i| if i == j { 1.0 } else { 0.0 }));
        }
        record(&x, |v| {
            let mut input = vec![Dual::<Recorded, f64>::from_re(v[0]); 1 + n];
            let mut y = vec![Dual::<Recorded, f64>::from_re(Recorded::constant(0.0)); n];
            let mut out = Vec::with_capacity(n * (1 + n));
            let mut columns = Vec::with_capacity(n * n);
            for j in 0..n {
                for i in 0..n {
                    input[1 + i] = Dual::new(v[1 + i], v[1 + n + n * j + i]);
                }
                self.record.eval_into(&input, &mut y);
                if j == 0 {
                    out.extend(y.iter().map(|d| d.re));
                }
                columns.extend(y.iter().map(|d| d.eps));
            }
            out.extend(columns);
            Ok(out)
        })
    }
}

/// How a [`Taylor`] run chooses its order and steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TaylorControl {
    /// Order and step from the tolerance `ε` (Jorba & Zou; see the [module docs](self)).
    Tolerance(f64),
    /// A fixed order and a fixed number of equal steps over the span.
    Fixed {
        /// The order `p` (`1 …` [`MAX_ORDER`]).
        order: usize,
        /// The number of steps.
        steps: usize,
    },
}

/// The arithmetic of a [`Taylor`] run's series, state and time.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Precision {
    /// Doubles, the time in double-length form and the state's sums compensated (see
    /// [rounding](self#rounding)).
    #[default]
    Double,
    /// Double-double numbers (about 106 bits) for every coefficient, the state and the time
    /// (see [double-double](self#double-double)); the initial state taken exactly, the results
    /// rounded to doubles.
    DoubleDouble,
}

/// The Taylor method (see the [module documentation](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Taylor {
    /// Order and step selection.
    pub control: TaylorControl,
    /// Largest number of steps of one run.
    pub max_steps: usize,
    /// The arithmetic of the series, state and time.
    pub precision: Precision,
}

impl Taylor {
    /// Smallest tolerance accepted, `10⁻³⁰` (order 36).
    pub const TOL_MIN: f64 = 1e-30;

    /// Default limit on the steps of one run, `10⁶` (seconds of work; about 5·10⁴ Kepler periods
    /// at order 12); [`with_max_steps`](Self::with_max_steps) raises it.
    pub const MAX_STEPS: usize = 1_000_000;

    /// The adaptive method with tolerance `ε ∈ [TOL_MIN, 1)` as both the absolute and the
    /// relative tolerance.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::OutOfDomain`] for a tolerance outside that range
    /// (`ε ≤ 0` included).
    pub fn new(tol: f64) -> Result<Self> {
        let m = Self {
            control: TaylorControl::Tolerance(tol),
            max_steps: Self::MAX_STEPS,
            precision: Precision::Double,
        };
        m.validate()?;
        Ok(m)
    }

    /// Order `order` (`1 …` [`MAX_ORDER`]) with `steps` equal steps over the span.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for an order outside `1 … MAX_ORDER` or `steps = 0`;
    /// [`Error::WorkLimit`] for `steps` above [`Fixed::MAX_STEPS`].
    pub fn fixed(order: usize, steps: usize) -> Result<Self> {
        let m = Self {
            control: TaylorControl::Fixed { order, steps },
            max_steps: Fixed::<()>::MAX_STEPS,
            precision: Precision::Double,
        };
        m.validate()?;
        Ok(m)
    }

    /// The same with at most `max_steps ≥ 1` steps per run.
    ///
    /// # Errors
    /// As [`validate`](Self::validate).
    pub fn with_max_steps(mut self, max_steps: usize) -> Result<Self> {
        self.max_steps = max_steps;
        self.validate()?;
        Ok(self)
    }

    /// The same method in double-double arithmetic ([`Precision::DoubleDouble`]; see
    /// [double-double](self#double-double)).
    pub fn double_double(mut self) -> Self {
        self.precision = Precision::DoubleDouble;
        self
    }

    /// The order of the series: `⌈−½ ln ε + 1⌉` for a tolerance, the given one otherwise.
    pub fn order(&self) -> usize {
        match self.control {
            TaylorControl::Tolerance(tol) => order_for(tol),
            TaylorControl::Fixed { order, .. } => order,
        }
    }

    /// Check the knobs.
    ///
    /// # Errors
    /// See [`new`](Self::new) and [`fixed`](Self::fixed); [`Error::OutOfDomain`] for
    /// `max_steps = 0`.
    pub fn validate(&self) -> Result<()> {
        if self.max_steps == 0 {
            return Err(Error::out_of_domain("Taylor max_steps", 0.0, "≥ 1"));
        }
        match self.control {
            TaylorControl::Tolerance(tol) => {
                let tol = crate::error::finite("Taylor tolerance", tol)?;
                if !(Self::TOL_MIN..1.0).contains(&tol) {
                    return Err(Error::out_of_domain(
                        "Taylor tolerance",
                        tol,
                        format!("[{:e}, 1)", Self::TOL_MIN),
                    ));
                }
            }
            TaylorControl::Fixed { order, steps } => {
                if !(1..=MAX_ORDER).contains(&order) {
                    return Err(Error::out_of_domain(
                        "Taylor order",
                        order as f64,
                        format!("1 … {MAX_ORDER}"),
                    ));
                }
                if steps == 0 {
                    return Err(Error::out_of_domain("number of steps", 0.0, "≥ 1"));
                }
                if steps > self.max_steps {
                    return Err(Error::WorkLimit {
                        what: "fixed-step Taylor run".into(),
                        limit: self.max_steps,
                        detail: format!("{:e} steps requested", steps as f64),
                        hint: "use fewer steps, or raise the limit with \
                               Taylor::with_max_steps"
                            .into(),
                    });
                }
            }
        }
        Ok(())
    }

    /// Run on Hamilton's equations already recorded (so that the recording is timed apart).
    ///
    /// # Errors
    /// The knobs' errors ([`validate`](Self::validate)); [`Error::NonFinite`] where the series
    /// of the solution is not finite (a singularity, e.g. a collision, within the step or at
    /// the start); [`Error::NotConverged`] when the step shrinks below `16ε|t|`;
    /// [`Error::WorkLimit`] beyond `max_steps`; [`Error::OutOfDomain`] for an observer's stop
    /// time outside its step.
    pub fn run_recorded<S, O: Observer<N>, const N: usize>(
        &self,
        field: &VectorFieldRecord<N>,
        problem: &Problem<'_, S, N>,
        observer: &mut O,
    ) -> Result<Report<N>> {
        match self.precision {
            Precision::Double => self.drive::<f64, S, O, N>(field, problem, observer),
            Precision::DoubleDouble => {
                self.drive::<DoubleDouble, S, O, N>(field, problem, observer)
            }
        }
    }

    /// [`run_recorded`](Self::run_recorded) with coefficients, state and steps in `C`.
    fn drive<C: Arithmetic, S, O: Observer<N>, const N: usize>(
        &self,
        field: &VectorFieldRecord<N>,
        problem: &Problem<'_, S, N>,
        observer: &mut O,
    ) -> Result<Report<N>> {
        self.validate()?;
        let clock = Instant::now();
        let record = &field.record;
        let order = self.order();
        let mut jets = C::jets(record, order)?;
        let mut work = Work::default();
        let (t0, t1) = (problem.start.t, problem.t1);
        // The state in `C`: the start's doubles taken exactly.
        let mut x: Vec<C> = problem
            .start
            .q
            .iter()
            .chain(problem.start.p.iter())
            .map(|&v| C::exact(v))
            .collect();
        // The low-order parts of the state's compensated sums (see `Arithmetic::advance`).
        let mut carry = vec![C::default(); 2 * N];
        let mut state = problem.start;
        // The time in double-length form, `state.t` its leading part.
        let mut time = DoubleDouble::from(t0);
        observer.start(&state);
        let mut k = 0usize;
        loop {
            self.within_budget(k, state.t, t0, t1)?;
            jets.propagate(C::from_double_double(time), &x, order)?;
            let (h, last) = self.next_step(&jets, &x, time, k, t0, t1)?;
            let time_next = if last {
                DoubleDouble::from(t1)
            } else {
                time + h.to_double_double()
            };
            for (i, (xi, ci)) in x.iter_mut().zip(carry.iter_mut()).enumerate() {
                *xi = C::advance(jets.series(i), order, h, ci);
            }
            let next = State {
                t: time_next.to_f64(),
                q: SVector::from_fn(|i, _| x[i].value()),
                p: SVector::from_fn(|i, _| x[N + i].value()),
            };
            work.steps += 1;
            work.gradients += 1;
            k += 1;
            if !next.is_finite() {
                return Err(Error::NonFinite {
                    what: format!("Taylor state at t = {:e}", next.t),
                    value: f64::NAN,
                });
            }
            let dense = SeriesStep {
                prev_time: time,
                next: &next,
                jets: &jets,
                order,
                _n: PhantomData::<[(); N]>,
            };
            let (control, stop_state) = observe(observer, &state, &next, &dense)?;
            let end;
            (state, end) = settle(control, next, stop_state, last, t1);
            time = time_next;
            if let Some(stopped) = end {
                return Ok(Report {
                    last: state,
                    stopped,
                    work,
                    elapsed: clock.elapsed(),
                });
            }
            if last {
                break;
            }
        }
        Ok(Report {
            last: state,
            stopped: false,
            work,
            elapsed: clock.elapsed(),
        })
    }
}

impl Taylor {
    /// [`Error::WorkLimit`] when step `k` (from 0) at time `t` of a run from `t₀` to `t₁` exceeds
    /// the budget.
    fn within_budget(&self, k: usize, t: f64, t0: f64, t1: f64) -> Result<()> {
        if k >= self.max_steps {
            return Err(Error::WorkLimit {
                what: "Taylor steps".into(),
                limit: self.max_steps,
                detail: format!(
                    "at t = {t:e} of [{t0:e}, {t1:e}], {:.3}% of the span",
                    100.0 * ((t - t0) / (t1 - t0)).abs()
                ),
                hint: "raise it with Taylor::with_max_steps(n), or shorten the span".into(),
            });
        }
        Ok(())
    }

    /// Step `k` (from 0) from the time `time` (in double-length form) of a run from `t₀` to `t₁`
    /// whose series at `x` are in `jets`: its length `h` and whether it is the last (see the
    /// [module docs](self)). The distances to `t₁` and to the grid times of a fixed step are
    /// taken from both parts of `time`, so that the rounding of the accumulated time does not
    /// enter the steps.
    fn next_step<C: Arithmetic>(
        &self,
        jets: &Jets<C>,
        x: &[C],
        time: DoubleDouble,
        k: usize,
        t0: f64,
        t1: f64,
    ) -> Result<(C, bool)> {
        let span = t1 - t0;
        let until = |target: f64| C::from_double_double(DoubleDouble::from(target) - time);
        let t = time.to_f64();
        match self.control {
            TaylorControl::Fixed { steps, .. } => {
                let last = k + 1 == steps;
                let h = if last {
                    until(t1)
                } else {
                    until(t0 + span * (k + 1) as f64 / steps as f64)
                };
                Ok((h, last))
            }
            TaylorControl::Tolerance(_) => {
                let h = step_size(jets, x, self.order());
                let remaining = until(t1);
                if h >= remaining.value().abs() {
                    return Ok((remaining, true));
                }
                let h_min = (16.0 * f64::EPSILON * t.abs()).max(f64::MIN_POSITIVE);
                if h.is_nan() || h < h_min {
                    return Err(Error::NotConverged {
                        what: format!(
                            "Taylor step size at t = {t:e}: |h| = {h:e} < 16ε|t| (a \
                             singularity within reach)"
                        ),
                        iterations: k,
                        residual: h,
                    });
                }
                Ok((C::exact(span.signum() * h), false))
            }
        }
    }

    /// Run on the recorded differential equation `ẋ = f(t, x)` of any dimension (inputs
    /// `(t, x)`, outputs `f`; [`Jets`]) from `(t₀, x)` to `t₁`, `x` overwritten by the final
    /// state, the steps chosen as `steps` says, the order the method's.
    ///
    /// # Errors
    /// As [`run_recorded`](Self::run_recorded); [`Error::InvalidInput`] for frozen times that do
    /// not run from `t₀` to `t₁`.
    pub(crate) fn series_run(
        &self,
        record: &Record,
        t0: f64,
        x: &mut [f64],
        t1: f64,
        steps: SeriesSteps<'_>,
    ) -> Result<Work> {
        self.validate()?;
        if self.precision != Precision::Double {
            return Err(Error::invalid(
                "Taylor method in double-double",
                "the series runs of the variational equations (tangent maps) are in doubles \
                 only; use Precision::Double",
            ));
        }
        if let SeriesSteps::Frozen(times) = steps {
            if times.len() < 2 || times[0] != t0 || times[times.len() - 1] != t1 {
                return Err(Error::invalid(
                    "frozen Taylor steps",
                    format!(
                        "{} times that do not run from {t0:e} to {t1:e}",
                        times.len()
                    ),
                ));
            }
        }
        let order = self.order();
        let mut jets = Jets::new(record, order)?;
        let mut work = Work::default();
        let mut time = DoubleDouble::from(t0);
        let mut carry = vec![0.0; x.len()];
        let mut t = t0;
        let mut k = 0usize;
        loop {
            self.within_budget(k, t, t0, t1)?;
            jets.ode(t, x, order)?;
            let (h, last) = match steps {
                SeriesSteps::Frozen(times) => (times[k + 1] - t, k + 2 == times.len()),
                SeriesSteps::Control => self.next_step(&jets, x, time, k, t0, t1)?,
            };
            for (j, (xj, cj)) in x.iter_mut().zip(carry.iter_mut()).enumerate() {
                *xj = advance_state(jets.series(j), order, h, cj);
            }
            work.steps += 1;
            work.gradients += 1;
            k += 1;
            time = match steps {
                SeriesSteps::Frozen(times) => DoubleDouble::from(times[k]),
                SeriesSteps::Control if last => DoubleDouble::from(t1),
                SeriesSteps::Control => time + DoubleDouble::from(h),
            };
            t = time.to_f64();
            if let Some(v) = x.iter().find(|v| !v.is_finite()) {
                return Err(Error::NonFinite {
                    what: format!("Taylor state at t = {t:e}"),
                    value: *v,
                });
            }
            if last {
                return Ok(work);
            }
        }
    }
}

/// The steps of [`Taylor::series_run`].
#[derive(Clone, Copy, Debug)]
pub(crate) enum SeriesSteps<'a> {
    /// Chosen by the method's control over every component of the state (for a tolerance, the
    /// step of the [module docs](self) with the norm over all of `x`).
    Control,
    /// Frozen at the given times, from `t₀` to `t₁`.
    Frozen(&'a [f64]),
}

/// `p = ⌈−½ ln ε + 1⌉`, at least 2.
fn order_for(tol: f64) -> usize {
    let p = (-0.5 * tol.ln() + 1.0).ceil();
    if p.is_finite() && p >= 2.0 {
        (p as usize).min(MAX_ORDER)
    } else {
        2
    }
}

/// The Jorba–Zou step `ρ e^{−2} e^{−0.7/(p−1)}` (see the [module docs](self)); infinite when the
/// last two coefficients vanish. Formed as one exponential,
/// `exp(min(−ln‖x_{p−1}‖/(p−1), −ln‖x_p‖/p) − 2 − 0.7/(p−1))`, the two norms in one pass over
/// the state.
fn step_size<C: Arithmetic>(jets: &Jets<C>, x0: &[C], p: usize) -> f64 {
    let n0 = x0.iter().fold(0.0f64, |m, v| m.max(v.value().abs()));
    let scale = if n0 > 1.0 { n0.recip() } else { 1.0 };
    let (mut a, mut b) = (0.0f64, 0.0f64);
    for j in 0..x0.len() {
        let c = &jets.series(j)[p - 1..=p];
        a = a.max(c[0].value().abs());
        b = b.max(c[1].value().abs());
    }
    let q = (p - 1) as f64;
    let ln_rho = (-(a * scale).ln() / q).min(-(b * scale).ln() / p as f64);
    (ln_rho - 2.0 - 0.7 / q).exp()
}

/// The state variable `x(t₀ + h) = Σ_{k=0}^{p} c_k h^k` with the final addition
/// `c₀ + h Σ_{k≥1} c_k h^{k−1}` compensated (Kahan's summation of the increments, Higham 2002
/// §4.3): the increment `δ = h Σ_{k≥1} c_k h^{k−1}` (Horner) and the low-order part `carry` lost
/// by the previous additions are added to `c₀` by the error-free sum
/// (`two_sum`), whose error becomes the new `carry`.
/// With `carry = 0` the value is Horner's `Σ c_k h^k` bit for bit.
#[inline]
fn advance_state(c: &[f64], p: usize, h: f64, carry: &mut f64) -> f64 {
    let mut s = c[p];
    for k in (1..p).rev() {
        s = s * h + c[k];
    }
    let (x, e) = two_sum(c[0], s * h + *carry);
    *carry = e;
    x
}

/// The arithmetic of a Taylor run ([`Precision`]): the coefficients' field, the conversions
/// of steps and times, and the update of the state by the step's series.
trait Arithmetic: JetCoefficient {
    /// The jets of `record` to order `order` in this arithmetic.
    fn jets(record: &Record, order: usize) -> Result<Jets<Self>>;
    /// A time (or time difference) given in double-length form.
    fn from_double_double(t: DoubleDouble) -> Self;
    /// The value in double-length form.
    fn to_double_double(self) -> DoubleDouble;
    /// `t − from`, the offset of a time within a step from its start.
    fn offset(t: f64, from: DoubleDouble) -> Self;
    /// The state variable at the end of the step `h` from its series `c` of order `p`, with
    /// the compensation `carry` of the sums of the previous steps.
    fn advance(c: &[Self], p: usize, h: Self, carry: &mut Self) -> Self;
}

impl Arithmetic for f64 {
    fn jets(record: &Record, order: usize) -> Result<Jets<Self>> {
        Jets::new(record, order)
    }
    #[inline]
    fn from_double_double(t: DoubleDouble) -> Self {
        t.to_f64()
    }
    #[inline]
    fn to_double_double(self) -> DoubleDouble {
        DoubleDouble::from(self)
    }
    #[inline]
    fn offset(t: f64, from: DoubleDouble) -> Self {
        (t - from.hi) - from.lo
    }
    #[inline]
    fn advance(c: &[Self], p: usize, h: Self, carry: &mut Self) -> Self {
        advance_state(c, p, h, carry)
    }
}

/// Every sum in double-double: the state's sum `x₀ + δ` has a relative error `≤ 3u²` without
/// compensation, so `carry` stays 0.
impl Arithmetic for DoubleDouble {
    fn jets(record: &Record, order: usize) -> Result<Jets<Self>> {
        Jets::double_double(record, order)
    }
    #[inline]
    fn from_double_double(t: DoubleDouble) -> Self {
        t
    }
    #[inline]
    fn to_double_double(self) -> DoubleDouble {
        self
    }
    #[inline]
    fn offset(t: f64, from: DoubleDouble) -> Self {
        DoubleDouble::from(t) - from
    }
    #[inline]
    fn advance(c: &[Self], p: usize, h: Self, _carry: &mut Self) -> Self {
        horner(c, p, h)
    }
}

/// `Σ_{k=0}^{p} c_k h^k` by Horner's rule.
#[inline]
fn horner<C: Field>(c: &[C], p: usize, h: C) -> C {
    let mut s = c[p];
    for k in (0..p).rev() {
        s = s.mul(h).add(c[k]);
    }
    s
}

/// Dense output of one Taylor step: the step's series.
struct SeriesStep<'a, C, const N: usize> {
    /// The step's initial time in double-length form.
    prev_time: DoubleDouble,
    next: &'a State<N>,
    jets: &'a Jets<C>,
    order: usize,
    _n: PhantomData<[(); N]>,
}

impl<C: Arithmetic, const N: usize> Dense<N> for SeriesStep<'_, C, N> {
    fn at(&self, t: f64) -> State<N> {
        if t == self.next.t {
            return *self.next;
        }
        let tau = C::offset(t, self.prev_time);
        let c = |j: usize| horner(self.jets.series(j), self.order, tau).value();
        State {
            t,
            q: SVector::from_fn(|i, _| c(i)),
            p: SVector::from_fn(|i, _| c(N + i)),
        }
    }
}

impl<S: Hamiltonian<N>, const N: usize> Method<S, N> for Taylor {
    fn label(&self) -> String {
        let info = match self.precision {
            Precision::Double => &methods::TAYLOR,
            Precision::DoubleDouble => &methods::TAYLOR_DD,
        };
        match self.control {
            TaylorControl::Tolerance(tol) => {
                format!("{} tol={tol:e} (order {})", info.label(), self.order())
            }
            TaylorControl::Fixed { order, steps } => {
                format!("{}, order {order} n={steps}", info.family)
            }
        }
    }

    fn run<O: Observer<N>>(
        &self,
        problem: &Problem<'_, S, N>,
        observer: &mut O,
    ) -> Result<Report<N>> {
        self.validate()?;
        let field = VectorFieldRecord::new(problem.system, &problem.start)?;
        self.run_recorded(&field, problem, observer)
    }
}

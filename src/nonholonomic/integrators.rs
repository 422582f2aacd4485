//! Integrating non-holonomic systems, and the drift of their energy and constraints (SPEC X6).
//!
//! Three methods on a [`Constrained`] system with Pfaffian constraints `B(t, q) q̇ + b(t, q) = 0`:
//!
//! * **Index-reduced equations** (the multiplier form of SPEC M16, an ODE in `(q, q̇)`) with any
//!   [`Method`], e.g. [`Dop853`]: the constraints hold only as well as the tolerance allows.
//! * **Projection** ([`Projection`]): the same runs in segments, the velocities projected back onto
//!   the constraints at the end of each segment by the least-kinetic-energy correction
//!   ([`Constrained::project_velocities`]) [Hairer, Lubich & Wanner, *Geometric Numerical
//!   Integration*, 2nd ed., IV.4, Algorithm 4.2].
//! * **Discrete Lagrange–d'Alembert** ([`LagrangeDAlembert`]) [McLachlan & Perlmutter,
//!   J. Nonlinear Sci. 16 (2006) 283–328, §3; Cortés & Martínez, Nonlinearity 14 (2001)
//!   1365–1392]: with the midpoint discrete Lagrangian
//!   `L_d(q₀, q₁) = h L(t + h/2, (q₀ + q₁)/2, (q₁ − q₀)/h)` and the discrete forces
//!   `f^± = (h/2) Q` at the midpoint, a step `(qₖ, pₖ) ↦ (qₖ₊₁, pₖ₊₁)` solves
//!
//!   ```math
//!   p_k + D_1 L_d(q_k, q_{k+1}) + f^- - h\,B(t_k, q_k)^{\mathsf T}\lambda_k = 0, \qquad
//!   B(\bar t, \bar q)\,\frac{q_{k+1} - q_k}{h} + b(\bar t, \bar q) = 0,
//!   ```
//!
//!   `p_{k+1} = D₂ L_d(qₖ, qₖ₊₁) + f^+`, with `q̄ = (qₖ + qₖ₊₁)/2`, `t̄ = tₖ + h/2` (the virtual
//!   displacements at `qₖ` lie in the constraint distribution, whence the force `−h Bᵀλ`, crate
//!   sign). The discrete constraint is the continuous one at the midpoint, so the midpoint velocity
//!   `(qₖ₊₁ − qₖ)/h` satisfies the constraints to rounding; the map is reversible for
//!   reversible systems (`L` even in `q̇`, `b = 0`), which is what keeps the energy error of the
//!   reversible integrable examples bounded [McLachlan & Perlmutter §5; Modin & Verdier,
//!   Numer. Math. 144 (2020) 729–762]. Newton's method with the AD Jacobian solves each step with
//!   a bounded number of iterations.
//!
//! [`drift`] runs any of them and returns the energy error (of the Jacobi integral
//! `h = q̇·∂L/∂q̇ − L`, the energy `T + V` of a natural scleronomic system) and the constraint
//! residual `max_r |B q̇ + b|_r` against time, as data.

use super::{at, Constrained};
use crate::ad::{phase_gradient, PhaseDual};
use crate::constraints::{check_rank, check_velocities, PfaffianConstraints};
use crate::error::{all_finite, finite, Error, Result};
use crate::integrate::methods::{whole_steps, Knob};
use crate::integrate::rattle::newton;
use crate::integrate::{
    integrate, Control, Dop853, Method, Observer, Problem, Report, Samples, StepView, Work,
};
use crate::lagrangian::Lagrangian;
use crate::phase::{checked_inverse, State};
use nalgebra::{DMatrix, DVector, SVector};
use num_dual::{Dual64, DualNum};
use std::time::Instant;

/// The discrete Lagrange–d'Alembert integrator with `steps` equal steps (see the
/// [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LagrangeDAlembert {
    /// Number of steps over `[t₀, t₁]` (at least 1).
    pub steps: usize,
    /// Largest number of Newton iterations per step (default 50).
    pub max_iterations: usize,
}

/// One step of [`LagrangeDAlembert`].
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DiscreteStep<const N: usize, const K: usize> {
    /// `qₖ₊₁`.
    pub q: SVector<f64, N>,
    /// `pₖ₊₁ = D₂ L_d(qₖ, qₖ₊₁) + f^+`.
    pub p: SVector<f64, N>,
    /// The midpoint velocity `(qₖ₊₁ − qₖ)/h`.
    pub velocity: SVector<f64, N>,
    /// `λₖ` (crate sign: the impulse is `−h B(qₖ)ᵀλₖ`).
    pub lambda: SVector<f64, K>,
    /// Newton iterations taken.
    pub iterations: usize,
}

/// The end of a [`LagrangeDAlembert`] run.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DiscreteRun<const N: usize> {
    /// The last node `(t, q, p)`, `p` the discrete momentum.
    pub last: State<N>,
    /// Whether the visitor stopped the run early.
    pub stopped: bool,
    /// Steps and Newton iterations.
    pub work: Work,
}

/// `(∂L/∂q + Q, ∂L/∂q̇)` at the midpoint `((q₀ + q₁)/2, (q₁ − q₀)/h)` at time `tm`, and the
/// constraint values there, over any dual type.
#[allow(clippy::type_complexity)]
fn midpoint_terms<L, C, D, const N: usize, const K: usize>(
    sys: &Constrained<L, C, N, K>,
    tm: f64,
    q0: &SVector<f64, N>,
    q1: &SVector<D, N>,
    h: f64,
) -> (SVector<D, N>, SVector<D, N>, SVector<D, K>)
where
    L: Lagrangian<N>,
    C: PfaffianConstraints<N, K>,
    D: DualNum<f64> + Copy,
{
    let q0d = q0.map(D::from);
    let mid = (q0d + q1).map(|x| x * 0.5);
    let v = (q1 - q0d).map(|x| x / h);
    let t = D::from(tm);
    let l = &sys.lagrangian;
    let (_, lq, lv) = phase_gradient(|a, b| l.lagrangian(PhaseDual::from_re(t), a, b), &mid, &v);
    let force = l.total_force(t, &mid, &v);
    let (bm, b0) = sys.constraints.forms(t, &mid);
    (lq + force, lv, bm * v + b0)
}

impl LagrangeDAlembert {
    /// The integrator with `steps ≥ 1` steps.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `steps = 0`.
    pub fn new(steps: usize) -> Result<Self> {
        if steps == 0 {
            return Err(Error::out_of_domain("number of steps", 0.0, "≥ 1"));
        }
        Ok(Self {
            steps,
            max_iterations: 50,
        })
    }

    /// One step of size `h` from `(t, q, p)`, `p` the discrete momentum (`∂L/∂q̇` at the start of
    /// a run).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or values; [`Error::InvalidInput`] for `h = 0`;
    /// [`Error::RankDeficient`] naming the dependent rows of `B` and the configuration;
    /// [`Error::Singular`] naming the configuration when the mass matrix or the Newton matrix is
    /// singular; [`Error::NotConverged`] (the configuration in `what`) after
    /// [`LagrangeDAlembert::max_iterations`] Newton iterations.
    pub fn step<L, C, const N: usize, const K: usize>(
        &self,
        sys: &Constrained<L, C, N, K>,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        h: f64,
    ) -> Result<DiscreteStep<N, K>>
    where
        L: Lagrangian<N>,
        C: PfaffianConstraints<N, K>,
    {
        let h = finite("step size h", h)?;
        finite("t", t)?;
        all_finite("q", q.as_slice())?;
        all_finite("p", p.as_slice())?;
        if h == 0.0 {
            return Err(Error::invalid("step size h", "h = 0: no step"));
        }
        let tm = finite("t + h/2", t + 0.5 * h)?;
        let here = || format!("t = {t}, q = {q:?}, p = {p:?}, h = {h}");
        let (b0, _) = sys.constraints.forms(t, q);
        all_finite(format_args!("B at t = {t}, q = {q:?}"), b0.as_slice())?;
        check_rank(&b0, "constraint matrix B", t, || format!("q = {q:?}"))?;
        // Predictor: the velocity of momentum p at q, exact for L quadratic in q̇.
        let zero = SVector::zeros();
        let a = sys.lagrangian.mass_matrix(t, q, &zero)?;
        let ainv = checked_inverse(&a, "mass matrix ∂²L/∂q̇²", here)?;
        let p_rest = sys.lagrangian.momentum(t, q, &zero)?;
        let v0 = ainv * (p - p_rest);
        let scale_q = q.amax().max((v0 * h).amax()).max(f64::MIN_POSITIVE);
        let scale_p = p.amax().max((a * v0).amax()).max(f64::MIN_POSITIVE);
        let m = N + K;
        let mut x = DVector::zeros(m);
        x.rows_mut(0, N).copy_from(&(q + v0 * h));
        let residual = |x: &DVector<f64>| -> Result<(DVector<f64>, DMatrix<f64>)> {
            let q1: SVector<f64, N> = x.fixed_rows::<N>(0).into_owned();
            let lam: SVector<f64, K> = x.fixed_rows::<K>(N).into_owned();
            let (f, lv, g) = midpoint_terms(sys, tm, q, &q1, h);
            let mut r = DVector::zeros(m);
            r.rows_mut(0, N)
                .copy_from(&(p + f * (0.5 * h) - lv - b0.transpose() * lam * h));
            r.rows_mut(N, K).copy_from(&g);
            let mut j = DMatrix::zeros(m, m);
            for c in 0..N {
                let q1d: SVector<Dual64, N> =
                    SVector::from_fn(|i, _| Dual64::new(q1[i], if i == c { 1.0 } else { 0.0 }));
                let (fd, lvd, gd) = midpoint_terms(sys, tm, q, &q1d, h);
                for i in 0..N {
                    j[(i, c)] = fd[i].eps * (0.5 * h) - lvd[i].eps;
                }
                for i in 0..K {
                    j[(N + i, c)] = gd[i].eps;
                }
            }
            j.view_mut((0, N), (N, K)).copy_from(&(-b0.transpose() * h));
            Ok((r, j))
        };
        let small = |dx: &DVector<f64>, _x: &DVector<f64>| {
            let dq = dx.rows(0, N).amax();
            let dl: SVector<f64, K> = dx.fixed_rows::<K>(N).into_owned();
            let dlp = (b0.transpose() * dl).amax() * h.abs();
            dq <= 8.0 * f64::EPSILON * scale_q && dlp <= 8.0 * f64::EPSILON * scale_p
        };
        let (x, iterations) = newton(x, residual, small, self.max_iterations, || {
            format!("discrete Lagrange–d'Alembert step at {}", here())
        })?;
        let q1: SVector<f64, N> = x.fixed_rows::<N>(0).into_owned();
        let lambda: SVector<f64, K> = x.fixed_rows::<K>(N).into_owned();
        let (f, lv, _) = midpoint_terms(sys, tm, q, &q1, h);
        let p1 = lv + f * (0.5 * h);
        let velocity = (q1 - q) / h;
        all_finite(format_args!("q_(k+1) from {}", here()), q1.as_slice())?;
        all_finite(format_args!("p_(k+1) from {}", here()), p1.as_slice())?;
        Ok(DiscreteStep {
            q: q1,
            p: p1,
            velocity,
            lambda,
            iterations,
        })
    }

    /// Run from `(q₀, q̇₀)` at `t₀` to `t₁`, `p₀ = ∂L/∂q̇(t₀, q₀, q̇₀)`. After every step `visit`
    /// sees the **midpoint** state `(tₖ + h/2, (qₖ + qₖ₊₁)/2, (qₖ₊₁ − qₖ)/h)` (a [`State`] whose
    /// `p` holds the velocity), where the scheme's velocity lives and satisfies the constraints;
    /// [`Control::Stop`] (or `StopAt`) ends the run after that step.
    ///
    /// The initial velocities must satisfy the constraints to `velocity_tolerance` (relative, see
    /// [`check_velocities`]).
    ///
    /// # Errors
    /// [`Error::ConstraintViolated`] for inadmissible initial velocities; as
    /// [`LagrangeDAlembert::step`]; [`Error::InvalidInput`] for `t₁ = t₀`.
    #[allow(clippy::too_many_arguments)]
    pub fn run<L, C, F, const N: usize, const K: usize>(
        &self,
        sys: &Constrained<L, C, N, K>,
        t0: f64,
        q0: SVector<f64, N>,
        qdot0: SVector<f64, N>,
        t1: f64,
        velocity_tolerance: f64,
        mut visit: F,
    ) -> Result<DiscreteRun<N>>
    where
        L: Lagrangian<N>,
        C: PfaffianConstraints<N, K>,
        F: FnMut(&State<N>) -> Control,
    {
        if self.steps == 0 {
            return Err(Error::out_of_domain("number of steps", 0.0, "≥ 1"));
        }
        let problem = Problem::new(sys, t0, q0, qdot0, t1)?;
        check_velocities(&sys.constraints, t0, &q0, &qdot0, velocity_tolerance)?;
        let h = problem.span() / self.steps as f64;
        if !(h.is_finite() && h != 0.0) {
            return Err(Error::out_of_domain(
                "step size",
                h,
                "finite and non-zero (span / steps)",
            ));
        }
        let p0 = sys.lagrangian.momentum(t0, &q0, &qdot0)?;
        let mut node = State {
            t: t0,
            q: q0,
            p: p0,
        };
        let mut work = Work::default();
        let mut stopped = false;
        for k in 0..self.steps {
            let s = self.step(sys, node.t, &node.q, &node.p, h)?;
            work.steps += 1;
            work.newton_iterations += s.iterations;
            let mid = State {
                t: t0 + h * (k as f64 + 0.5),
                q: (node.q + s.q) * 0.5,
                p: s.velocity,
            };
            node = State {
                t: if k + 1 == self.steps {
                    t1
                } else {
                    t0 + h * (k + 1) as f64
                },
                q: s.q,
                p: s.p,
            };
            if visit(&mid) != Control::Continue {
                stopped = k + 1 < self.steps;
                break;
            }
        }
        Ok(DiscreteRun {
            last: node,
            stopped,
            work,
        })
    }
}

/// A method `M` on the index-reduced equations run in `segments` equal segments, the velocities
/// projected onto the constraints after each (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection<M> {
    /// The method on each segment.
    pub method: M,
    /// Number of segments of `[t₀, t₁]` (at least 1).
    pub segments: usize,
}

impl<M> Projection<M> {
    /// `method` with a projection after each of `segments ≥ 1` segments.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `segments = 0`.
    pub fn new(method: M, segments: usize) -> Result<Self> {
        if segments == 0 {
            return Err(Error::out_of_domain("number of segments", 0.0, "≥ 1"));
        }
        Ok(Self { method, segments })
    }
}

/// Forwards the steps of later segments (not their starts) to the caller's observer.
struct Continued<'o, O>(&'o mut O);

impl<O: Observer<N>, const N: usize> Observer<N> for Continued<'_, O> {
    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        self.0.step(step)
    }
}

impl<L, C, M, const N: usize, const K: usize> Method<Constrained<L, C, N, K>, N> for Projection<M>
where
    L: Lagrangian<N>,
    C: PfaffianConstraints<N, K>,
    M: Method<Constrained<L, C, N, K>, N>,
{
    fn label(&self) -> String {
        format!("{} with projection ×{}", self.method.label(), self.segments)
    }

    fn run<O: Observer<N>>(
        &self,
        problem: &Problem<'_, Constrained<L, C, N, K>, N>,
        observer: &mut O,
    ) -> Result<Report<N>> {
        let clock = Instant::now();
        if self.segments == 0 {
            return Err(Error::out_of_domain("number of segments", 0.0, "≥ 1"));
        }
        let sys = problem.system;
        let (t0, span) = (problem.start.t, problem.span());
        let mut state = problem.start;
        let mut work = Work::default();
        observer.start(&state);
        for k in 0..self.segments {
            let tb = if k + 1 == self.segments {
                problem.t1
            } else {
                t0 + span * ((k + 1) as f64 / self.segments as f64)
            };
            if tb == state.t {
                continue;
            }
            let seg = Problem::new(sys, state.t, state.q, state.p, tb)?;
            let r = integrate(&seg, &self.method, &mut Continued(observer))?;
            work = work.add(&r.work);
            let v = sys.project_velocities(r.last.t, &r.last.q, &r.last.p)?;
            state = State { p: v, ..r.last };
            if r.stopped {
                return Ok(Report {
                    last: state,
                    stopped: true,
                    work,
                    elapsed: clock.elapsed(),
                });
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

/// The constrained integrators compared by [`drift`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ConstrainedMethod {
    /// DOP853 on the index-reduced (multiplier) equations.
    Reduced(Dop853),
    /// DOP853 on the index-reduced equations with projection of the velocities.
    Projected(Projection<Dop853>),
    /// The discrete Lagrange–d'Alembert integrator.
    LagrangeDAlembert(LagrangeDAlembert),
}

/// How a method of [`CONSTRAINED_METHODS`] is built from its knob.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ConstrainedConstruction {
    /// [`Projection`] of [`Dop853`] (`rtol = atol` the knob) over [`PROJECTION_SEGMENTS`]
    /// segments.
    Projected,
    /// [`LagrangeDAlembert`] with the knob's number of steps.
    LagrangeDAlembert,
}

/// A method for constrained systems beyond the index-reduced equations (which any method of
/// [`METHODS`](crate::integrate::METHODS) integrates), described once: its key in scene files,
/// its label in tables and legends, its knob, and its source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstrainedInfo {
    /// Key in scene files, e.g. `"lagrange-dalembert"`.
    pub key: &'static str,
    /// Label in tables and legends.
    pub label: &'static str,
    /// What it is, for `hj list`.
    pub description: &'static str,
    /// The knob it is swept over.
    pub knob: Knob,
    /// How it is built.
    pub construction: ConstrainedConstruction,
    /// Where it comes from.
    pub reference: &'static str,
}

/// Number of segments of a run of the projected method of [`CONSTRAINED_METHODS`]: the
/// velocities are projected onto the constraints 10 times over the span.
pub const PROJECTION_SEGMENTS: usize = 10;

/// The methods for constrained systems with Pfaffian constraints, in the order `hj list` shows
/// them.
pub static CONSTRAINED_METHODS: [ConstrainedInfo; 2] = [
    ConstrainedInfo {
        key: "dop853-projection",
        label: "Dormand–Prince + projection",
        description: "Dormand–Prince 8(5,3) on the index-reduced equations, the velocities \
                      projected onto the constraints after each of 10 segments; Pfaffian \
                      constraints",
        knob: Knob::Tolerance,
        construction: ConstrainedConstruction::Projected,
        reference: "Hairer, Lubich & Wanner 2006, §IV.4, Algorithm 4.2",
    },
    ConstrainedInfo {
        key: "lagrange-dalembert",
        label: "discrete Lagrange–d'Alembert (midpoint), order 2",
        description: "discrete Lagrange–d'Alembert, midpoint discrete Lagrangian, order 2; \
                      Pfaffian constraints",
        knob: Knob::Steps,
        construction: ConstrainedConstruction::LagrangeDAlembert,
        reference: "McLachlan & Perlmutter, J. Nonlinear Sci. 16 (2006) 283–328, §3",
    },
];

impl ConstrainedInfo {
    /// The entry with key `key`, if there is one.
    pub fn find(key: &str) -> Option<&'static ConstrainedInfo> {
        CONSTRAINED_METHODS.iter().find(|m| m.key == key)
    }
}

impl ConstrainedMethod {
    /// The method `info` describes at `knob` (a tolerance or a number of steps), DOP853 limited
    /// to `max_steps` steps per run.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] or [`Error::OutOfDomain`] for a knob out of range (a tolerance
    /// outside DOP853's range, a step count that is not a whole number ≥ 1).
    pub fn new(info: &ConstrainedInfo, knob: f64, max_steps: usize) -> Result<Self> {
        match info.construction {
            ConstrainedConstruction::Projected => Ok(Self::Projected(Projection::new(
                Dop853::new(knob, knob)?.with_max_steps(max_steps)?,
                PROJECTION_SEGMENTS,
            )?)),
            ConstrainedConstruction::LagrangeDAlembert => {
                LagrangeDAlembert::new(whole_steps(knob)?).map(Self::LagrangeDAlembert)
            }
        }
    }

    /// Run from `(q₀, q̇₀)` at `t₀` to `t₁`: the end state (`(t₁, q, q̇)` for the ODE methods,
    /// the last node `(t₁, q, p)` of [`LagrangeDAlembert`]), the work, and the states at
    /// about `samples` times when asked (`samples + 1` uniform times from dense output for the
    /// ODE methods; every `⌈steps/samples⌉`-th midpoint state `(t, q, q̇)` and the start for
    /// [`LagrangeDAlembert`]).
    ///
    /// # Errors
    /// [`Error::ConstraintViolated`] for initial velocities violating the constraints beyond
    /// `velocity_tolerance`; [`Error::NonFinite`] for a state, or the energy of a state, that is
    /// not finite; the errors of the method.
    #[allow(clippy::too_many_arguments, clippy::type_complexity)]
    pub fn run<L, C, const N: usize, const K: usize>(
        &self,
        sys: &Constrained<L, C, N, K>,
        t0: f64,
        q0: SVector<f64, N>,
        qdot0: SVector<f64, N>,
        t1: f64,
        velocity_tolerance: f64,
        samples: Option<usize>,
    ) -> Result<(State<N>, Work, Vec<State<N>>)>
    where
        L: Lagrangian<N>,
        C: PfaffianConstraints<N, K>,
    {
        let problem = Problem::new(sys, t0, q0, qdot0, t1)?;
        check_velocities(&sys.constraints, t0, &q0, &qdot0, velocity_tolerance)?;
        let (last, work, states) = match self {
            Self::Reduced(m) => ode_run(&problem, m, samples)?,
            Self::Projected(m) => ode_run(&problem, m, samples)?,
            Self::LagrangeDAlembert(m) => {
                let stride = samples.map(|n| m.steps.div_ceil(n.max(1)).max(1));
                let mut states = Vec::new();
                if stride.is_some() {
                    states.push(problem.start);
                }
                let mut k = 0usize;
                let run = m.run(sys, t0, q0, qdot0, t1, velocity_tolerance, |s| {
                    k += 1;
                    if stride.is_some_and(|d| k.is_multiple_of(d) || k == m.steps) {
                        states.push(*s);
                    }
                    Control::Continue
                })?;
                (run.last, run.work, states)
            }
        };
        for s in states.iter().chain(std::iter::once(&last)) {
            all_finite(
                format_args!("state at t = {} of {}", s.t, self.label()),
                s.q.iter()
                    .chain(s.p.iter())
                    .copied()
                    .collect::<Vec<_>>()
                    .as_slice(),
            )?;
        }
        // States far outside the method's accuracy (a step that moves the state by more than its
        // scales) can stay finite while their energy overflows: refuse them too. The states are
        // `(t, q, q̇)` except the last node `(t, q, p)` of the discrete scheme.
        let last_has_velocity = !matches!(self, Self::LagrangeDAlembert(_));
        for s in states.iter().chain(last_has_velocity.then_some(&last)) {
            sys.lagrangian
                .jacobi_integral(s.t, &s.q, &s.p)
                .map_err(|_| Error::NonFinite {
                    what: format!(
                        "energy (Jacobi integral) of the state at t = {} of {}: the run left the \
                     method's range",
                        s.t,
                        self.label()
                    ),
                    value: f64::INFINITY,
                })?;
        }
        Ok((last, work, states))
    }

    /// A label for tables and figures.
    pub fn label(&self) -> String {
        match self {
            Self::Reduced(m) => format!("DOP853 (index-reduced) rtol={:e}", m.rtol),
            Self::Projected(p) => format!(
                "DOP853 + projection rtol={:e} ×{}",
                p.method.rtol, p.segments
            ),
            Self::LagrangeDAlembert(m) => format!("discrete Lagrange–d'Alembert n={}", m.steps),
        }
    }
}

/// An ODE method on the index-reduced equations: the end state, the work, and the states at
/// `samples + 1` uniform times when asked.
#[allow(clippy::type_complexity)]
fn ode_run<S, M: Method<S, N>, const N: usize>(
    problem: &Problem<'_, S, N>,
    method: &M,
    samples: Option<usize>,
) -> Result<(State<N>, Work, Vec<State<N>>)> {
    match samples {
        Some(n) => {
            let mut grid = Samples::uniform(problem.start.t, problem.t1, n)?;
            let r = integrate(problem, method, &mut grid)?;
            Ok((r.last, r.work, grid.states))
        }
        None => integrate(problem, method, &mut ()).map(|r| (r.last, r.work, Vec::new())),
    }
}

/// Energy error and constraint residual at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DriftSample {
    /// Time.
    pub t: f64,
    /// `h(t) − h(t₀)`, `h = q̇·∂L/∂q̇ − L` the Jacobi integral (energy).
    pub energy_error: f64,
    /// `max_r |B q̇ + b|_r`.
    pub residual: f64,
}

/// The drift of one method along one motion.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Drift {
    /// The method's label.
    pub method: String,
    /// The initial energy `h(t₀)`.
    pub energy: f64,
    /// The samples, in time order.
    pub samples: Vec<DriftSample>,
    /// The work of the run.
    pub work: Work,
}

impl Drift {
    /// `max |h(t) − h(t₀)|` over the samples.
    pub fn max_energy_error(&self) -> f64 {
        self.samples
            .iter()
            .map(|s| s.energy_error.abs())
            .fold(0.0, f64::max)
    }

    /// The largest constraint residual over the samples.
    pub fn max_residual(&self) -> f64 {
        self.samples.iter().map(|s| s.residual).fold(0.0, f64::max)
    }

    /// The samples as CSV: `method,t,energy_error,residual`.
    pub fn to_csv(&self) -> String {
        let mut out = String::from("method,t,energy_error,residual\n");
        let name = format!("\"{}\"", self.method.replace('"', "\"\""));
        for s in &self.samples {
            out.push_str(&format!(
                "{name},{:e},{:e},{:e}\n",
                s.t, s.energy_error, s.residual
            ));
        }
        out
    }
}

/// Energy and constraint residual at `(t, q, q̇)`.
fn measure<L, C, const N: usize, const K: usize>(
    sys: &Constrained<L, C, N, K>,
    t: f64,
    q: &SVector<f64, N>,
    qdot: &SVector<f64, N>,
) -> Result<(f64, f64)>
where
    L: Lagrangian<N>,
    C: PfaffianConstraints<N, K>,
{
    let e = sys.lagrangian.jacobi_integral(t, q, qdot)?;
    let (b, b0) = sys.constraints.forms(t, q);
    let g: SVector<f64, K> = b * qdot + b0;
    all_finite(
        format_args!("constraint values at t = {t}, {}", at(q, qdot)),
        g.as_slice(),
    )?;
    Ok((e, g.amax()))
}

/// Run `method` on `sys` from `(q₀, q̇₀)` at `t₀` to `t₁` and record the energy error and the
/// constraint residual at about `samples` times: `samples + 1` equally spaced times for the
/// ODE methods; for [`LagrangeDAlembert`] every `⌈steps/samples⌉`-th midpoint state (where its
/// velocity lives) and the last.
///
/// # Errors
/// [`Error::ConstraintViolated`] for initial velocities violating the constraints beyond `1e-12`
/// (relative, see [`check_velocities`]); [`Error::OutOfDomain`] for `samples = 0` or more than
/// [`MAX_SAMPLES`](crate::integrate::MAX_SAMPLES); the errors of the method.
#[allow(clippy::too_many_arguments)]
pub fn drift<L, C, const N: usize, const K: usize>(
    sys: &Constrained<L, C, N, K>,
    method: &ConstrainedMethod,
    t0: f64,
    q0: SVector<f64, N>,
    qdot0: SVector<f64, N>,
    t1: f64,
    samples: usize,
) -> Result<Drift>
where
    L: Lagrangian<N>,
    C: PfaffianConstraints<N, K>,
{
    Problem::new(sys, t0, q0, qdot0, t1)?;
    check_velocities(&sys.constraints, t0, &q0, &qdot0, 1e-12)?;
    Samples::<N>::uniform(t0, t1, samples)?;
    let (e0, _) = measure(sys, t0, &q0, &qdot0)?;
    let (_, work, states) = method.run(sys, t0, q0, qdot0, t1, 1e-12, Some(samples))?;
    let samples = states
        .iter()
        .map(|s| {
            let (e, r) = measure(sys, s.t, &s.q, &s.p)?;
            Ok(DriftSample {
                t: s.t,
                energy_error: e - e0,
                residual: r,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    Ok(Drift {
        method: method.label(),
        energy: e0,
        samples,
        work,
    })
}

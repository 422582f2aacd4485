//! A configured system that a scene runs: the [`Case`] trait, and [`HamiltonianCase`], which
//! turns any [`Hamiltonian`] with an initial state into a case whose methods are chosen by the
//! capabilities it was given (separable, perturbed Kepler, exact flow) and whose theories are
//! closures.

use super::spec::{Knob, MethodKind, TheoryKind};
use crate::error::{Error, Result};
use crate::integrate::methods::{whole_steps, Capability, Construction, MethodInfo};
use crate::integrate::{
    integrate, AnyMethod, Dop853, ExactStep, Fixed, GeneralMethod, Method, Observer,
    PerturbedKepler, Problem, Report, StepView, WisdomHolman, Work,
};
use crate::nalgebra::SVector;
use crate::phase::State;
use crate::stability::ParameterStudy;
use crate::systems::{ExactFlow, Invariant, Invariants};
use crate::{Hamiltonian, Separable};

/// States sampled uniformly in time along one run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct History {
    /// Times.
    pub t: Vec<f64>,
    /// Coordinates at each time.
    pub q: Vec<Vec<f64>>,
    /// Momenta at each time.
    pub p: Vec<Vec<f64>>,
}

/// One timed run: the error of its final state against the case's reference and the work done.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    /// Error against the reference (the case's [`Case::error_label`]).
    pub error: f64,
    /// Work of the run.
    pub work: Work,
}

/// A table the case computes by itself (no time span: e.g. the transformation gallery).
#[derive(Clone, Debug, PartialEq)]
pub struct Table {
    /// Column headers.
    pub header: Vec<String>,
    /// Rows of cells.
    pub rows: Vec<Vec<String>>,
}

impl Table {
    /// As a Markdown table.
    pub fn to_markdown(&self) -> String {
        let mut s = format!("| {} |\n", self.header.join(" | "));
        s += &format!("|{}\n", "---|".repeat(self.header.len()));
        for r in &self.rows {
            s += &format!("| {} |\n", r.join(" | "));
        }
        s
    }

    /// As CSV.
    pub fn to_csv(&self) -> String {
        let field = |s: &String| crate::workprecision::csv_field(s);
        let mut s = self.header.iter().map(field).collect::<Vec<_>>().join(",") + "\n";
        for r in &self.rows {
            s += &(r.iter().map(field).collect::<Vec<_>>().join(",") + "\n");
        }
        s
    }
}

/// How a state is drawn in a phase portrait.
#[derive(Clone, Copy, Debug)]
pub struct Portrait {
    /// What the projection shows, for the figure's title: `"orbit"` for positions in the plane,
    /// `"phase portrait"` for a coordinate and its momentum.
    pub title: &'static str,
    /// Horizontal axis label.
    pub x_label: &'static str,
    /// Vertical axis label.
    pub y_label: &'static str,
    /// Whether both axes share a unit (drawn with equal aspect).
    pub equal_aspect: bool,
    /// The projection `(q, p) ↦ (x, y)`.
    pub project: fn(&[f64], &[f64]) -> (f64, f64),
}

/// A system configured by a scene: what it can run and what it can report.
pub trait Case {
    /// One line describing the configured system and its initial state.
    fn describe(&self) -> String;
    /// The period of the unperturbed motion (unit of `span.periods`), if it has one.
    fn period(&self) -> Option<f64>;
    /// Whether `kind` applies to this system.
    fn supports(&self, kind: MethodKind) -> bool;
    /// What [`Outcome::error`] measures.
    fn error_label(&self) -> String;
    /// Fix the end time and compute the reference state there (once, before any run).
    ///
    /// # Errors
    /// If the reference cannot be computed.
    fn prepare(&mut self, t1: f64) -> Result<()>;
    /// A note on the reference (how it was obtained and how accurate it is).
    fn reference_note(&self) -> String;
    /// The tolerance of the DOP853 integration that gives the reference, if it is integrated
    /// (`None` for a closed-form or otherwise computed reference). Its cost grows with the span
    /// like a DOP853 run's, and the scene check bounds it the same way.
    fn integrated_reference_rtol(&self) -> Option<f64> {
        None
    }
    /// The reference solution's coordinates at `times` (ascending, within the prepared span): the
    /// closed-form reference where the case has one, the dense output of the DOP853 reference
    /// run otherwise.
    ///
    /// # Errors
    /// Failures of the reference; times it cannot reach.
    fn reference_coordinates(&self, times: &[f64]) -> Result<Vec<Vec<f64>>>;
    /// One run of `kind` at `knob` to the prepared end time.
    ///
    /// # Errors
    /// Failures of the method, or [`Error::InvalidInput`] for an unsupported kind.
    fn run(&self, kind: MethodKind, knob: f64) -> Result<Outcome>;
    /// `samples + 1` states uniform in time from the start to the prepared end time.
    ///
    /// # Errors
    /// As [`Case::run`].
    fn history(&self, kind: MethodKind, knob: f64, samples: usize) -> Result<History>;
    /// The conserved energy at a state.
    ///
    /// # Errors
    /// If the Hamiltonian cannot be evaluated there.
    fn energy(&self, t: f64, q: &[f64], p: &[f64]) -> Result<f64>;
    /// The conserved quantities at a state, by name (default: the energy alone).
    ///
    /// # Errors
    /// If they cannot be evaluated there.
    fn invariants(&self, t: f64, q: &[f64], p: &[f64]) -> Result<Vec<Invariant>> {
        Ok(vec![Invariant {
            name: "energy",
            value: self.energy(t, q, p)?,
        }])
    }
    /// How states are drawn in a phase portrait.
    fn portrait(&self) -> Portrait;
    /// A caveat about `kind` on this system (e.g. a series used beyond its convergence), shown
    /// with its results.
    fn note(&self, _kind: MethodKind) -> Option<String> {
        None
    }
    /// Names of the osculating elements, if the system has any.
    fn element_names(&self) -> Option<&'static [&'static str]> {
        None
    }
    /// Osculating elements at a state.
    ///
    /// # Errors
    /// If the system has no elements or they are undefined at the state.
    fn elements(&self, _q: &[f64], _p: &[f64]) -> Result<Vec<f64>> {
        Err(Error::invalid(
            "elements",
            "this system has no osculating elements",
        ))
    }
    /// The parameter of the case's family of steady motions (e.g. `"v"`, the forward speed),
    /// if it has one: see [`Case::parameter_study`].
    fn steady_motion_parameter(&self) -> Option<&'static str> {
        None
    }
    /// The spectra of the steady motions at `samples` equally spaced parameter values in
    /// `[from, to]` and the values where a real part crosses zero
    /// ([`crate::stability::parameter_study`]).
    ///
    /// # Errors
    /// If the case has no family of steady motions; the errors of the study.
    fn parameter_study(&self, _from: f64, _to: f64, _samples: usize) -> Result<ParameterStudy> {
        Err(Error::invalid(
            "spectrum",
            "this system has no family of steady motions",
        ))
    }
    /// Whether the case is a table of its own (no span, no methods): see [`Case::table`].
    fn has_table(&self) -> bool {
        false
    }
    /// A table the case computes on its own, for cases without a time span, with the figures
    /// that go with it as `(what, figure)` (written as `figures/<name>-<what>`).
    ///
    /// # Errors
    /// If the computation fails.
    #[allow(clippy::type_complexity)]
    fn table(&self) -> Option<Result<(Table, Vec<(String, crate::plot::Figure)>)>> {
        None
    }
    /// The `what` of each figure [`Case::table`] returns, known before it runs.
    fn table_figures(&self) -> Vec<&'static str> {
        Vec::new()
    }
}

/// Records the state at given times from dense output.
pub struct Sampler<const N: usize> {
    times: Vec<f64>,
    next: usize,
    /// The sampled states.
    pub states: Vec<State<N>>,
}

impl<const N: usize> Sampler<N> {
    /// Sample at `t0 + k (t1 − t0)/samples`, `k = 0..=samples`.
    pub fn uniform(t0: f64, t1: f64, samples: usize) -> Self {
        let n = samples.max(1);
        Self::at(
            (0..=n)
                .map(|k| t0 + (t1 - t0) * (k as f64 / n as f64))
                .collect(),
        )
    }

    /// Sample at `times`, which run in the direction of integration (a time the run never
    /// reaches is not sampled).
    pub fn at(times: Vec<f64>) -> Self {
        Self {
            next: 0,
            states: Vec::with_capacity(times.len()),
            times,
        }
    }
}

impl<const N: usize> Observer<N> for Sampler<N> {
    fn start(&mut self, state: &State<N>) {
        if self.times.first() == Some(&state.t) {
            self.states.push(*state);
            self.next = 1;
        }
    }
    fn step(&mut self, step: &StepView<'_, N>) -> crate::integrate::Control {
        let forward = step.next.t >= step.prev.t;
        while let Some(&t) = self.times.get(self.next) {
            let inside = if forward {
                t <= step.next.t
            } else {
                t >= step.next.t
            };
            if !inside {
                break;
            }
            let s = if t == step.next.t {
                *step.next
            } else {
                step.dense.at(t)
            };
            self.states.push(s);
            self.next += 1;
        }
        crate::integrate::Control::Continue
    }
}

/// Records every `every`-th step end exactly (no interpolation), and the last state: the history
/// of a fixed-step method is the states it computed.
pub struct StepEnds<const N: usize> {
    every: usize,
    seen: usize,
    /// The recorded states.
    pub states: Vec<State<N>>,
}

impl<const N: usize> StepEnds<N> {
    /// About `samples` states out of a run of `steps` steps.
    pub fn new(steps: usize, samples: usize) -> Self {
        Self {
            every: steps.div_ceil(samples.max(1)).max(1),
            seen: 0,
            states: Vec::with_capacity(samples + 2),
        }
    }
}

impl<const N: usize> Observer<N> for StepEnds<N> {
    fn start(&mut self, state: &State<N>) {
        self.states.push(*state);
    }
    fn step(&mut self, step: &StepView<'_, N>) -> crate::integrate::Control {
        self.seen += 1;
        if self.seen.is_multiple_of(self.every) {
            self.states.push(*step.next);
        }
        crate::integrate::Control::Continue
    }
}

/// How a run is recorded: not at all, at uniform times from dense output (adaptive methods), or
/// at its own step ends (fixed-step methods).
pub enum Recording<'a, const N: usize> {
    /// Uniform times from dense output.
    Uniform(&'a mut Sampler<N>),
    /// Step ends.
    Steps(&'a mut StepEnds<N>),
}

/// Run `method`, recording as asked.
fn drive<S, M: Method<S, N>, const N: usize>(
    problem: &Problem<'_, S, N>,
    method: &M,
    sampler: Option<&mut Recording<'_, N>>,
) -> Result<Report<N>> {
    match sampler {
        Some(Recording::Uniform(s)) => integrate(problem, method, *s),
        Some(Recording::Steps(s)) => integrate(problem, method, *s),
        None => integrate(problem, method, &mut ()),
    }
}

/// The most steps one DOP853 run of a scene may attempt (its runs and an integrated reference):
/// about 17 s of a Kepler orbit's steps on one core. The scene check refuses a span whose runs
/// would need more.
pub const ADAPTIVE_MAX_STEPS: usize = 50_000_000;

/// Tolerance of the DOP853 reference of a case without an exact one.
pub(crate) const REFERENCE_RTOL: f64 = Dop853::RTOL_MIN;

/// The coordinates at `times` (ascending, in `[0, t1]`) of the reference run that `run` drives
/// with DOP853 at [`REFERENCE_RTOL`] into the sampler it is given.
///
/// # Errors
/// Times out of order or out of range; a run that does not reach every time; the run's errors.
pub(crate) fn reference_run_coordinates<const N: usize>(
    times: &[f64],
    t1: f64,
    run: impl FnOnce(&Dop853, &mut Sampler<N>) -> Result<()>,
) -> Result<Vec<Vec<f64>>> {
    if times.windows(2).any(|w| {
        matches!(
            w[0].partial_cmp(&w[1]),
            None | Some(std::cmp::Ordering::Greater)
        )
    }) || times.iter().any(|t| !(0.0..=t1).contains(t))
    {
        return Err(Error::invalid(
            "reference times",
            format!("expected ascending times in [0, {t1:e}]"),
        ));
    }
    let tight = Dop853::new(REFERENCE_RTOL, 1e-17)?.with_max_steps(ADAPTIVE_MAX_STEPS)?;
    let mut sampler = Sampler::at(times.to_vec());
    run(&tight, &mut sampler)?;
    if sampler.states.len() != times.len() {
        return Err(Error::invalid(
            "reference times",
            format!(
                "the reference run reached {} of {} sample times",
                sampler.states.len(),
                times.len()
            ),
        ));
    }
    Ok(sampler
        .states
        .iter()
        .map(|s| s.q.as_slice().to_vec())
        .collect())
}

/// Runs one method of a capability: `None` when `info` is not one of its methods.
pub type StepperRun<H, const N: usize> = fn(
    &Problem<'_, H, N>,
    &'static MethodInfo,
    f64,
    Option<&mut Recording<'_, N>>,
) -> Option<Result<Report<N>>>;

/// The methods of one capability (general, separable, perturbed Kepler, exact flow): the
/// entries of [`METHODS`](crate::integrate::METHODS) that need it, and how to run them.
pub struct Stepper<H, const N: usize> {
    capability: Capability,
    run: StepperRun<H, N>,
}

impl<H, const N: usize> Clone for Stepper<H, N> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<H, const N: usize> Copy for Stepper<H, N> {}

impl<H, const N: usize> Stepper<H, N> {
    /// Whether `kind` is one of this capability's methods (decided from the method table,
    /// without running anything).
    pub fn handles(&self, kind: MethodKind) -> bool {
        kind.integrator()
            .is_some_and(|m| m.capability() == self.capability)
    }
}

/// Runge–Kutta, Gauss–Legendre and Dormand–Prince: any Hamiltonian.
pub fn general_stepper<H: Hamiltonian<N>, const N: usize>() -> Stepper<H, N> {
    Stepper {
        capability: Capability::Hamiltonian,
        run: run_general::<H, N>,
    }
}

fn run_general<H: Hamiltonian<N>, const N: usize>(
    problem: &Problem<'_, H, N>,
    info: &'static MethodInfo,
    knob: f64,
    sampler: Option<&mut Recording<'_, N>>,
) -> Option<Result<Report<N>>> {
    (info.capability() == Capability::Hamiltonian).then(|| {
        let method = match GeneralMethod::new(info, knob)? {
            GeneralMethod::Dop853(m) => {
                GeneralMethod::Dop853(m.with_max_steps(ADAPTIVE_MAX_STEPS)?)
            }
            GeneralMethod::Rk45(m) => GeneralMethod::Rk45(m.with_max_steps(ADAPTIVE_MAX_STEPS)?),
            m => m,
        };
        drive(problem, &method, sampler)
    })
}

/// Explicit splitting methods: separable Hamiltonians.
pub fn separable_stepper<H: Separable<N>, const N: usize>() -> Stepper<H, N> {
    Stepper {
        capability: Capability::Separable,
        run: run_separable::<H, N>,
    }
}

fn run_separable<H: Separable<N>, const N: usize>(
    problem: &Problem<'_, H, N>,
    info: &'static MethodInfo,
    knob: f64,
    sampler: Option<&mut Recording<'_, N>>,
) -> Option<Result<Report<N>>> {
    (info.capability() == Capability::Separable)
        .then(|| AnyMethod::new(info, knob).and_then(|m| drive(problem, &m, sampler)))
}

/// Wisdom–Holman and SABA/SBAB: perturbed Kepler problems.
pub fn kepler_splitting_stepper<H: PerturbedKepler<N> + Hamiltonian<N>, const N: usize>(
) -> Stepper<H, N> {
    Stepper {
        capability: Capability::PerturbedKepler,
        run: run_kepler_splitting::<H, N>,
    }
}

fn run_kepler_splitting<H: PerturbedKepler<N> + Hamiltonian<N>, const N: usize>(
    problem: &Problem<'_, H, N>,
    info: &'static MethodInfo,
    knob: f64,
    sampler: Option<&mut Recording<'_, N>>,
) -> Option<Result<Report<N>>> {
    let Construction::KeplerSplitting(table) = info.construction else {
        return None;
    };
    Some(
        whole_steps(knob)
            .and_then(|n| Fixed::new(WisdomHolman::new(table)?, n))
            .and_then(|m| drive(problem, &m, sampler)),
    )
}

/// The exact flow as a method.
pub fn exact_stepper<H: ExactFlow<N> + Hamiltonian<N>, const N: usize>() -> Stepper<H, N> {
    Stepper {
        capability: Capability::ExactFlow,
        run: run_exact::<H, N>,
    }
}

fn run_exact<H: ExactFlow<N> + Hamiltonian<N>, const N: usize>(
    problem: &Problem<'_, H, N>,
    info: &'static MethodInfo,
    knob: f64,
    sampler: Option<&mut Recording<'_, N>>,
) -> Option<Result<Report<N>>> {
    (info.construction == Construction::Exact).then(|| {
        whole_steps(knob)
            .and_then(|n| Fixed::new(ExactStep, n))
            .and_then(|m| drive(problem, &m, sampler))
    })
}

/// A theory: the state `(q, p)` at time `t` for knob value `knob` (e.g. an order).
pub type Theory<const N: usize> =
    Box<dyn Fn(f64, f64) -> Result<(SVector<f64, N>, SVector<f64, N>)>>;

/// A reference solution: the state at time `t`, and a note on its accuracy.
pub type Reference<const N: usize> =
    Box<dyn Fn(f64) -> Result<((SVector<f64, N>, SVector<f64, N>), String)>>;

/// Any Hamiltonian with an initial state, as a [`Case`].
pub struct HamiltonianCase<H: Hamiltonian<N>, const N: usize> {
    system: H,
    q0: SVector<f64, N>,
    p0: SVector<f64, N>,
    period: Option<f64>,
    description: String,
    steppers: Vec<Stepper<H, N>>,
    theories: Vec<(TheoryKind, Theory<N>)>,
    notes: Vec<(MethodKind, String)>,
    reference: Option<Reference<N>>,
    error_label: String,
    portrait: Portrait,
    elements: Option<(&'static [&'static str], ElementMap)>,
    invariants: Option<InvariantMap<H, N>>,
    prepared: Option<(f64, SVector<f64, N>, String)>,
}

/// The conserved quantities of a system at a state.
pub type InvariantMap<H, const N: usize> =
    fn(&H, f64, &SVector<f64, N>, &SVector<f64, N>) -> Result<Vec<Invariant>>;

/// The conserved quantities a catalogue system knows ([`Invariants`]), as an [`InvariantMap`].
pub fn system_invariants<H: Invariants<N>, const N: usize>(
    system: &H,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<Vec<Invariant>> {
    system.invariants(t, q, p)
}

/// Osculating elements of a state.
pub type ElementMap = Box<dyn Fn(&[f64], &[f64]) -> Result<Vec<f64>>>;

fn default_portrait(q: &[f64], p: &[f64]) -> (f64, f64) {
    (q[0], p[0])
}

impl<H: Hamiltonian<N> + 'static, const N: usize> HamiltonianCase<H, N> {
    /// A case with the general methods (RK4, implicit midpoint, Gauss–Legendre, DOP853); the
    /// reference defaults to DOP853 at a tight tolerance, checked against a looser one.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite initial state.
    pub fn new(
        system: H,
        q0: SVector<f64, N>,
        p0: SVector<f64, N>,
        description: impl Into<String>,
    ) -> Result<Self> {
        State::new(0.0, q0, p0)?;
        Ok(Self {
            system,
            q0,
            p0,
            period: None,
            description: description.into(),
            steppers: vec![general_stepper::<H, N>()],
            theories: Vec::new(),
            notes: Vec::new(),
            reference: None,
            error_label: "final position error ‖Δq‖".into(),
            portrait: Portrait {
                title: "phase portrait",
                x_label: "q",
                y_label: "p",
                equal_aspect: false,
                project: default_portrait,
            },
            elements: None,
            invariants: None,
            prepared: None,
        })
    }

    /// The period of the motion (unit of `span.periods`).
    pub fn with_period(mut self, period: f64) -> Self {
        self.period = Some(period);
        self
    }

    /// Add a method capability (e.g. [`separable_stepper`]).
    pub fn with_stepper(mut self, stepper: Stepper<H, N>) -> Self {
        self.steppers.push(stepper);
        self
    }

    /// Add a theory giving the state at any time.
    pub fn with_theory(mut self, kind: TheoryKind, theory: Theory<N>) -> Self {
        self.theories.push((kind, theory));
        self
    }

    /// A caveat shown with the results of `kind`.
    pub fn with_note(mut self, kind: MethodKind, note: impl Into<String>) -> Self {
        self.notes.push((kind, note.into()));
        self
    }

    /// Use an exact (or otherwise trusted) reference instead of DOP853.
    pub fn with_reference(mut self, reference: Reference<N>) -> Self {
        self.reference = Some(reference);
        self
    }

    /// How the error is described.
    pub fn with_error_label(mut self, label: impl Into<String>) -> Self {
        self.error_label = label.into();
        self
    }

    /// How states are drawn.
    pub fn with_portrait(mut self, portrait: Portrait) -> Self {
        self.portrait = portrait;
        self
    }

    /// The conserved quantities drawn by the `invariants` output (default: the energy alone).
    pub fn with_invariants(mut self, map: InvariantMap<H, N>) -> Self {
        self.invariants = Some(map);
        self
    }

    /// Osculating elements of the states.
    pub fn with_elements(mut self, names: &'static [&'static str], map: ElementMap) -> Self {
        self.elements = Some((names, map));
        self
    }

    fn problem(&self, t1: f64) -> Result<Problem<'_, H, N>> {
        Problem::new(&self.system, 0.0, self.q0, self.p0, t1)
    }

    fn end(&self) -> Result<&(f64, SVector<f64, N>, String)> {
        self.prepared
            .as_ref()
            .ok_or_else(|| Error::invalid("case", "run before prepare: no end time"))
    }

    fn report(
        &self,
        kind: MethodKind,
        knob: f64,
        sampler: Option<&mut Recording<'_, N>>,
    ) -> Result<Report<N>> {
        let t1 = self.end()?.0;
        let problem = self.problem(t1)?;
        let mut sampler = sampler;
        if let Some(info) = kind.integrator() {
            for s in self.steppers.iter().filter(|s| s.handles(kind)) {
                if let Some(r) = (s.run)(&problem, info, knob, sampler.as_deref_mut()) {
                    return r;
                }
            }
        }
        Err(unsupported(kind))
    }

    fn theory(&self, kind: MethodKind) -> Option<&Theory<N>> {
        self.theories
            .iter()
            .find(|(k, _)| MethodKind::Theory(*k) == kind)
            .map(|(_, t)| t)
    }
}

fn unsupported(kind: MethodKind) -> Error {
    Error::invalid(
        format!("method {}", kind.key()),
        "does not apply to this system",
    )
}

impl<H: Hamiltonian<N> + 'static, const N: usize> Case for HamiltonianCase<H, N> {
    fn describe(&self) -> String {
        self.description.clone()
    }

    fn period(&self) -> Option<f64> {
        self.period
    }

    fn supports(&self, kind: MethodKind) -> bool {
        self.theory(kind).is_some() || self.steppers.iter().any(|s| s.handles(kind))
    }

    fn error_label(&self) -> String {
        self.error_label.clone()
    }

    fn prepare(&mut self, t1: f64) -> Result<()> {
        let (q, note) = match &self.reference {
            Some(r) => {
                let ((q, _), note) = r(t1)?;
                (q, note)
            }
            None => {
                let problem = self.problem(t1)?;
                let tight =
                    Dop853::new(REFERENCE_RTOL, 1e-17)?.with_max_steps(ADAPTIVE_MAX_STEPS)?;
                let check = Dop853::new(1e-14, 1e-16)?.with_max_steps(ADAPTIVE_MAX_STEPS)?;
                let q = integrate(&problem, &tight, &mut ())?.last.q;
                let q2 = integrate(&problem, &check, &mut ())?.last.q;
                (
                    q,
                    format!(
                        "reference: DOP853 at rtol 2.3e−15 (differs from rtol 1e−14 by {:.1e})",
                        (q - q2).norm()
                    ),
                )
            }
        };
        self.prepared = Some((t1, q, note));
        Ok(())
    }

    fn integrated_reference_rtol(&self) -> Option<f64> {
        self.reference.is_none().then_some(REFERENCE_RTOL)
    }

    fn reference_coordinates(&self, times: &[f64]) -> Result<Vec<Vec<f64>>> {
        if let Some(r) = &self.reference {
            return times
                .iter()
                .map(|&t| Ok(r(t)?.0 .0.as_slice().to_vec()))
                .collect();
        }
        let t1 = self.end()?.0;
        let problem = self.problem(t1)?;
        reference_run_coordinates(times, t1, |tight, sampler| {
            integrate(&problem, tight, sampler).map(|_| ())
        })
    }

    fn reference_note(&self) -> String {
        self.prepared
            .as_ref()
            .map(|p| p.2.clone())
            .unwrap_or_default()
    }

    fn run(&self, kind: MethodKind, knob: f64) -> Result<Outcome> {
        let (t1, q_ref, _) = self.end()?;
        if let Some(theory) = self.theory(kind) {
            let (q, _) = theory(knob, *t1)?;
            return Ok(Outcome {
                error: (q - q_ref).norm(),
                work: Work::default(),
            });
        }
        let r = self.report(kind, knob, None)?;
        Ok(Outcome {
            error: (r.last.q - q_ref).norm(),
            work: r.work,
        })
    }

    fn history(&self, kind: MethodKind, knob: f64, samples: usize) -> Result<History> {
        let t1 = self.end()?.0;
        let mut h = History::default();
        if let Some(theory) = self.theory(kind) {
            let n = samples.max(1);
            for k in 0..=n {
                let t = t1 * (k as f64 / n as f64);
                let (q, p) = if k == 0 {
                    (self.q0, self.p0)
                } else {
                    theory(knob, t)?
                };
                h.t.push(t);
                h.q.push(q.as_slice().to_vec());
                h.p.push(p.as_slice().to_vec());
            }
            return Ok(h);
        }
        let states = if kind.knob() == Knob::Steps {
            let mut ends = StepEnds::new(whole_steps(knob)?, samples);
            let last = self.report(kind, knob, Some(&mut Recording::Steps(&mut ends)))?;
            if ends.states.last().map(|s| s.t) != Some(last.last.t) {
                ends.states.push(last.last);
            }
            ends.states
        } else {
            let mut sampler = Sampler::uniform(0.0, t1, samples);
            self.report(kind, knob, Some(&mut Recording::Uniform(&mut sampler)))?;
            sampler.states
        };
        for s in states {
            h.t.push(s.t);
            h.q.push(s.q.as_slice().to_vec());
            h.p.push(s.p.as_slice().to_vec());
        }
        Ok(h)
    }

    fn energy(&self, t: f64, q: &[f64], p: &[f64]) -> Result<f64> {
        if q.len() != N || p.len() != N {
            return Err(Error::invalid("energy", "state of the wrong dimension"));
        }
        let q = SVector::<f64, N>::from_column_slice(q);
        let p = SVector::<f64, N>::from_column_slice(p);
        self.system.value(t, &q, &p)
    }

    fn invariants(&self, t: f64, q: &[f64], p: &[f64]) -> Result<Vec<Invariant>> {
        if q.len() != N || p.len() != N {
            return Err(Error::invalid("invariants", "state of the wrong dimension"));
        }
        let qv = SVector::<f64, N>::from_column_slice(q);
        let pv = SVector::<f64, N>::from_column_slice(p);
        match self.invariants {
            Some(map) => map(&self.system, t, &qv, &pv),
            None => Ok(vec![Invariant {
                name: "energy",
                value: self.system.value(t, &qv, &pv)?,
            }]),
        }
    }

    fn portrait(&self) -> Portrait {
        self.portrait
    }

    fn note(&self, kind: MethodKind) -> Option<String> {
        self.notes
            .iter()
            .find(|(k, _)| *k == kind)
            .map(|(_, n)| n.clone())
    }

    fn element_names(&self) -> Option<&'static [&'static str]> {
        self.elements.as_ref().map(|e| e.0)
    }

    fn elements(&self, q: &[f64], p: &[f64]) -> Result<Vec<f64>> {
        match &self.elements {
            Some((_, map)) => map(q, p),
            None => Err(Error::invalid(
                "elements",
                "this system has no osculating elements",
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perturbation::forces::{PerturbedTwoBody, J2};
    use crate::systems::Kepler2;

    /// `handles` (decided without running) agrees with what `run` accepts, for every kind.
    fn agrees<H: Hamiltonian<N>, const N: usize>(
        stepper: Stepper<H, N>,
        problem: &Problem<'_, H, N>,
    ) {
        for info in &crate::integrate::METHODS {
            let kind = MethodKind::Integrator(info);
            let knob = if kind.knob() == Knob::Rtol { 1e-6 } else { 1.0 };
            let ran = (stepper.run)(problem, info, knob, None);
            assert_eq!(stepper.handles(kind), ran.is_some(), "{}", info.key);
            if let Some(r) = ran {
                r.unwrap_or_else(|e| panic!("{}: {e}", info.key));
            }
        }
        for theory in super::super::spec::THEORIES {
            assert!(!stepper.handles(theory.kind.into()), "{}", theory.key);
        }
    }

    #[test]
    fn handles_agrees_with_run() {
        let kepler = Kepler2::new(1.0).unwrap();
        let (q, p) = (SVector::from([1.0, 0.0]), SVector::from([0.0, 1.0]));
        let problem = Problem::new(&kepler, 0.0, q, p, 0.1).unwrap();
        agrees(general_stepper::<Kepler2, 2>(), &problem);
        agrees(separable_stepper::<Kepler2, 2>(), &problem);
        agrees(exact_stepper::<Kepler2, 2>(), &problem);
        let j2 = PerturbedTwoBody::conservative(1.0, J2::new(1.0, 1e-3, 0.5).unwrap()).unwrap();
        let (q, p) = (
            SVector::from([1.0, 0.0, 0.1]),
            SVector::from([0.0, 1.0, 0.0]),
        );
        let problem = Problem::new(&j2, 0.0, q, p, 0.1).unwrap();
        agrees(
            kepler_splitting_stepper::<PerturbedTwoBody<J2>, 3>(),
            &problem,
        );
    }
}

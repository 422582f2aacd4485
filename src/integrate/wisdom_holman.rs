//! Wisdom–Holman splitting for a Kepler problem plus a position-dependent perturbation,
//!
//! ```math
//! H = \underbrace{\tfrac12|p|^2 - \frac{\mu}{|q|}}_{A = H_K} + \underbrace{H_1(t, q)}_{B},
//! ```
//!
//! with the exact Kepler flow as the `A` sub-step (a *Kepler drift*) and the kick
//! `p ↦ p − h ∇H₁(q)` as the `B` sub-step (J. Wisdom & M. Holman, "Symplectic maps for the
//! n-body problem", Astron. J. 102 (1991) 1528–1538, doi:10.1086/115978). For `H₁ = O(ε)` the
//! error of the second-order map is `O(ε h²)` instead of `O(h²)`; Laskar & Robutel's `SABA_n` and
//! `SBAB_n` push the `ε` term to `O(ε h^{2n} + ε² h²)` (J. Laskar & P. Robutel, Celest. Mech. Dyn.
//! Astron. 80 (2001) 39–62, doi:10.1023/A:1012098603882). Tables in
//! [`coefficients`], run by the same composition kernel as
//! [`Splitting`](super::Splitting).
//!
//! # Symplectic correctors
//! [`WisdomHolman::with_corrector`] adds a corrector `C` of order `k` ([`Corrector`]; Wisdom,
//! Holman & Touma 1996; Rein & Tamayo 2015) to the drift–kick–drift map `Φ_h`: the state shown
//! is `C ∘ Φⁿ ∘ C⁻¹` of the initial state, with error `O(ε hᵏ + ε² h²)` instead of `O(ε h²)`.
//! [`WisdomHolman::propagate`] applies `C⁻¹` once at the start and `C` once at the end (the
//! output time); a [`Fixed`] run shows every step to its observer, so each step is an output and
//! its step map is the conjugate `C ∘ Φ_h ∘ C⁻¹` (the same states, at the corrector's cost per
//! step). The corrector assumes an autonomous perturbation.
//!
//! # Planetary systems
//! [`PlanetaryWisdomHolman`] runs the same tables on a [`PlanetarySystem`] in Jacobi or democratic
//! heliocentric coordinates ([`PlanetaryCoordinates`]): one Kepler drift per planet (`μ = Gηᵢ`
//! resp. `Gm₀`), the centre of mass drifting freely, and the kick of the interaction
//! [`PlanetarySystem::interaction`] (the system's one potential minus the Kepler potentials) by AD.
//! In democratic heliocentric coordinates the `A` flow of a sub-step `c h` is
//! `jump(c h/2) ∘ Kepler(c h) ∘ jump(c h/2)`, which with the kick–drift–kick table is the map of
//! Duncan, Levison & Lee (1998, eq. 30). Correctors apply in Jacobi coordinates.
//!
//! # The Kepler drift
//! The `A` sub-step is the exact Kepler flow in universal variables,
//! [`crate::systems::kepler::drift`]: any conic, any dual type, with exact derivatives, so the
//! step of a Wisdom–Holman method can be certified symplectic by AD
//! ([`StepMap`](super::StepMap)).

use super::coefficients::{self, Corrector, Flow, Table, CORRECTORS};
use super::methods::{Construction, METHODS};
use super::splitting::{check_table, compose, SubFlows, Word};
use super::{check_initial_field, compensated_add, Fixed, OneStep, Problem, Report, Work};
use crate::ad::{gradient, GradDual};
use crate::error::{positive, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::phase::State;
use crate::systems::kepler;
use crate::systems::planetary::{add_body, body, PlanetaryCoordinates, PlanetarySystem};
use nalgebra::{SVector, Vector3};
use num_dual::DualNum;
use std::time::Instant;

pub use crate::hamiltonian::PerturbedKepler;

/// A Wisdom–Holman method (a Laskar–Robutel table with `A` = Kepler, `B` = perturbation).
///
/// Cost per step: one Kepler drift ([`Work::flows`](super::Work)) per `A` sub-step and one AD
/// gradient of `H₁` ([`Work::gradients`](super::Work)) per `B` sub-step; `SBAB_n` begins and
/// ends with a kick at the same position (`n + 1` kicks per stateless step, `n` with FSAL).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WisdomHolman {
    table: &'static Table,
    corrector: Option<&'static Corrector>,
}

impl WisdomHolman {
    /// The classical Wisdom–Holman map, kick–drift–kick (`= SBAB₁`): 1 stage, order 2
    /// (`wisdom-holman`).
    pub const WH: Self = Self::of(&coefficients::SBAB1);
    /// `SABA₁`, drift–kick–drift: 1 stage, order 2 (`saba1`).
    pub const SABA1: Self = Self::of(&coefficients::SABA1);
    /// `SABA₂`: 2 stages, order 2 (`saba2`).
    pub const SABA2: Self = Self::of(&coefficients::SABA2);
    /// `SABA₃`: 3 stages, order 2 (`saba3`).
    pub const SABA3: Self = Self::of(&coefficients::SABA3);
    /// `SABA₄`: 4 stages, order 2 (`saba4`).
    pub const SABA4: Self = Self::of(&coefficients::SABA4);
    /// `SBAB₂`: 2 stages, order 2 (`sbab2`).
    pub const SBAB2: Self = Self::of(&coefficients::SBAB2);
    /// `SBAB₃`: 3 stages, order 2 (`sbab3`).
    pub const SBAB3: Self = Self::of(&coefficients::SBAB3);
    /// `SBAB₄`: 4 stages, order 2 (`sbab4`).
    pub const SBAB4: Self = Self::of(&coefficients::SBAB4);

    const fn of(table: &'static Table) -> Self {
        Self {
            table,
            corrector: None,
        }
    }

    /// Every shipped Wisdom–Holman method: the Kepler splittings of
    /// [`METHODS`].
    pub fn all() -> Vec<Self> {
        METHODS
            .iter()
            .filter_map(|m| match m.construction {
                Construction::KeplerSplitting(t) => Some(Self::of(t)),
                _ => None,
            })
            .collect()
    }

    /// A method from a user's table (checked for consistency as [`Splitting::new`](super::Splitting::new)).
    pub fn new(table: &'static Table) -> Result<Self> {
        check_table(table)?;
        Ok(Self::of(table))
    }

    /// The coefficient table.
    pub fn table(&self) -> &'static Table {
        self.table
    }

    /// The symplectic corrector, if any.
    pub fn corrector(&self) -> Option<&'static Corrector> {
        self.corrector
    }

    /// The second-order map with the symplectic corrector of order `k ∈ {3, 5, 7, 11, 17}`
    /// ([`Corrector`], [`CORRECTORS`]): the corrected drift–kick–drift map `C ∘ Φⁿ ∘ C⁻¹`.
    /// Defined for [`WisdomHolman::SABA1`] and [`WisdomHolman::WH`]; the two give the same
    /// corrected method, since kick–drift–kick is conjugate to drift–kick–drift
    /// (`SBAB₁ = χ ∘ SABA₁ ∘ χ⁻¹`, `χ = φ^B_{h/2} ∘ φ^A_{h/2}`), and the corrector is stated for
    /// the latter.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for another table; [`Error::OutOfDomain`] for another order.
    pub fn with_corrector(self, order: u32) -> Result<Self> {
        if *self.table != coefficients::SABA1 && *self.table != coefficients::SBAB1 {
            return Err(Error::invalid(
                "symplectic corrector",
                format!(
                    "defined for the second-order Wisdom–Holman map (SABA1, or WH = SBAB1), not \
                     for {}",
                    self.table.label()
                ),
            ));
        }
        let corrector = CORRECTORS
            .iter()
            .find(|c| c.order == order)
            .ok_or_else(|| {
                Error::out_of_domain("corrector order", order as f64, "3, 5, 7, 11 or 17")
            })?;
        Ok(Self {
            table: &coefficients::SABA1,
            corrector: Some(corrector),
        })
    }

    /// `steps` equal steps over the span of `problem` with the corrector (if any) applied only
    /// at the ends: `C⁻¹` to the initial state, `Φ_h` `steps` times (compensated summation),
    /// `C` to the final state. The report's `last` is the state at `t₁`.
    ///
    /// # Errors
    /// As a [`Fixed`] run of the method (step count, a singular start, a failed Kepler drift,
    /// a non-finite state).
    pub fn propagate<S: PerturbedKepler<N> + Hamiltonian<N>, const N: usize>(
        &self,
        problem: &Problem<'_, S, N>,
        steps: usize,
    ) -> Result<Report<N>> {
        Fixed::new(*self, steps)?;
        check_initial_field(problem)?;
        let clock = Instant::now();
        let mut work = Work::default();
        let mu = positive("gravitational parameter μ", problem.system.mu())?;
        let mut flows = KeplerFlows {
            system: problem.system,
            mu,
            work: &mut work,
        };
        let s = &problem.start;
        let (q, p) = run(self, &mut flows, s.t, &s.q, &s.p, problem.t1, steps)?;
        work.steps = steps;
        let last = finite_state(&self.name_for(), problem.t1, q, p)?;
        Ok(Report {
            last,
            stopped: false,
            work,
            elapsed: clock.elapsed(),
        })
    }

    fn name_for(&self) -> String {
        match self.corrector {
            None => self.table.label(),
            Some(c) => format!("{}, corrector of order {}", self.table.label(), c.order),
        }
    }
}

/// The state `(t, q, p)` at the end of a run, or [`Error::NonFinite`].
fn finite_state<const N: usize>(
    name: &str,
    t: f64,
    q: SVector<f64, N>,
    p: SVector<f64, N>,
) -> Result<State<N>> {
    State::new(t, q, p).map_err(|_| Error::NonFinite {
        what: format!("{name} state at t = {t}"),
        value: f64::NAN,
    })
}

/// The word of the corrector `C` (`inverse = false`) or `C⁻¹` (`true`), run by the composition
/// kernel [`compose`].
struct CorrectorWord<'a> {
    corrector: &'a Corrector,
    inverse: bool,
}

impl Word for CorrectorWord<'_> {
    #[inline]
    fn for_each_sub_step<E>(
        &self,
        f: impl FnMut(Flow, f64) -> std::result::Result<(), E>,
    ) -> std::result::Result<(), E> {
        self.corrector.for_each_sub_step(self.inverse, f)
    }
}

/// The increments of the corrector `C` (or `C⁻¹`) over the step `h` from `(t, q, p)`.
fn correct<D, F, const N: usize>(
    corrector: &Corrector,
    inverse: bool,
    flows: &mut F,
    t: D,
    q: &SVector<D, N>,
    p: &SVector<D, N>,
    h: D,
) -> Result<(SVector<D, N>, SVector<D, N>)>
where
    D: DualNum<f64> + Copy,
    F: SubFlows<D, N>,
{
    let word = CorrectorWord { corrector, inverse };
    compose(&word, flows, t, q, p, h)
}

/// One step of `method` as seen at output times: `Φ_h`, or `C ∘ Φ_h ∘ C⁻¹` with a corrector.
fn step<D, F, const N: usize>(
    method: &WisdomHolman,
    flows: &mut F,
    t: D,
    q: &SVector<D, N>,
    p: &SVector<D, N>,
    dt: D,
) -> Result<(SVector<D, N>, SVector<D, N>)>
where
    D: DualNum<f64> + Copy,
    F: SubFlows<D, N>,
{
    match method.corrector {
        None => compose(method.table, flows, t, q, p, dt),
        Some(c) => {
            let (dq1, dp1) = correct(c, true, flows, t, q, p, dt)?;
            let (q1, p1) = (q + dq1, p + dp1);
            let (dq2, dp2) = compose(method.table, flows, t, &q1, &p1, dt)?;
            let (q2, p2) = (q1 + dq2, p1 + dp2);
            let (dq3, dp3) = correct(c, false, flows, t + dt, &q2, &p2, dt)?;
            Ok((dq1 + dq2 + dq3, dp1 + dp2 + dp3))
        }
    }
}

/// A sub-step `(flow, c)`.
type SubStep = (Flow, f64);

/// The first and last (non-zero) sub-steps of `table` and their number: the long run merges
/// the two when they are of the same flow.
fn ends(table: &Table) -> (Option<SubStep>, Option<SubStep>, usize) {
    let (mut first, mut last, mut count) = (None, None, 0);
    let _ = table.for_each_sub_step(|flow, c| {
        if c != 0.0 {
            first = first.or(Some((flow, c)));
            last = Some((flow, c));
            count += 1;
        }
        Ok::<(), ()>(())
    });
    (first, last, count)
}

/// One segment of a long run with merged step ends: the (non-zero) sub-steps of `table`, the
/// first over `first·dt` instead of its own coefficient, the last left out.
struct Segment<'a> {
    table: &'a Table,
    first: f64,
    count: usize,
}

impl Word for Segment<'_> {
    #[inline]
    fn for_each_sub_step<E>(
        &self,
        mut f: impl FnMut(Flow, f64) -> std::result::Result<(), E>,
    ) -> std::result::Result<(), E> {
        let mut i = 0;
        self.table.for_each_sub_step(|flow, c| {
            if c == 0.0 {
                return Ok(());
            }
            i += 1;
            match i {
                1 => f(flow, self.first),
                i if i == self.count => Ok(()),
                _ => f(flow, c),
            }
        })
    }
}

/// A single sub-step `(flow, c)` (the closing one of a long run with merged step ends).
struct Single(Flow, f64);

impl Word for Single {
    #[inline]
    fn for_each_sub_step<E>(
        &self,
        mut f: impl FnMut(Flow, f64) -> std::result::Result<(), E>,
    ) -> std::result::Result<(), E> {
        f(self.0, self.1)
    }
}

/// `steps` steps of `Φ_h` from `(t₀, q, p)` to `t₁`, with `C⁻¹` before and `C` after.
///
/// When the table begins and ends with the same flow `X` (`WH = SBAB₁` with kicks, the
/// corrector's kernel `SABA₁` with drifts) and that flow composes exactly,
/// `φ^X_{a h} ∘ φ^X_{b h} = φ^X_{(a+b) h}` (every kick; the drifts when
/// [`SubFlows::a_composes`]), the last sub-step of each step and the first of the next are one
/// sub-step:
/// `Φ_hⁿ = φ^X_{c₁h} ∘ M ∘ (φ^X_{(c₁+c_m)h} ∘ M)ⁿ⁻¹ ∘ φ^X_{c_m h}`
/// (composition read right to left; `M` the sub-steps between the ends) — one kick (or one
/// drift) per step fewer, the same map up to rounding, as in the "lazy" WHFast of Rein &
/// Tamayo (2015, §3) and the FSAL runs of Hairer, Lubich & Wanner (*Geometric Numerical
/// Integration*, §V.3.1).
fn run<F: SubFlows<f64, N>, const N: usize>(
    method: &WisdomHolman,
    flows: &mut F,
    t0: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
    t1: f64,
    steps: usize,
) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
    let dt = (t1 - t0) / steps as f64;
    let (mut q, mut p) = (*q, *p);
    let (mut cq, mut cp) = (SVector::<f64, N>::zeros(), SVector::<f64, N>::zeros());
    if let Some(c) = method.corrector {
        let (dq, dp) = correct(c, true, flows, t0, &q, &p, dt)?;
        q += dq;
        p += dp;
    }
    let table = method.table;
    match ends(table) {
        (Some((x, c1)), Some((y, cm)), count)
            if count >= 2 && x == y && (x == Flow::B || flows.a_composes()) =>
        {
            // The time elapsed in a step before its last sub-step (that sub-step is the start of
            // the next segment).
            let lag = if x == Flow::A { cm * dt } else { 0.0 };
            for k in 0..steps {
                let t = t0 + dt * k as f64;
                let (t, first) = if k == 0 { (t, c1) } else { (t - lag, c1 + cm) };
                let word = Segment {
                    table,
                    first,
                    count,
                };
                let (dq, dp) = compose(&word, flows, t, &q, &p, dt)?;
                compensated_add(&mut q, &mut cq, &dq);
                compensated_add(&mut p, &mut cp, &dp);
            }
            let (dq, dp) = compose(&Single(x, cm), flows, t1 - lag, &q, &p, dt)?;
            compensated_add(&mut q, &mut cq, &dq);
            compensated_add(&mut p, &mut cp, &dp);
        }
        _ => {
            for k in 0..steps {
                let t = t0 + dt * k as f64;
                let (dq, dp) = compose(table, flows, t, &q, &p, dt)?;
                compensated_add(&mut q, &mut cq, &dq);
                compensated_add(&mut p, &mut cp, &dp);
            }
        }
    }
    if let Some(c) = method.corrector {
        let (dq, dp) = correct(c, false, flows, t1, &q, &p, dt)?;
        q += dq;
        p += dp;
    }
    Ok((q, p))
}

struct KeplerFlows<'a, S> {
    system: &'a S,
    mu: f64,
    work: &'a mut Work,
}

impl<S: PerturbedKepler<N>, D: DualNum<f64> + Copy, const N: usize> SubFlows<D, N>
    for KeplerFlows<'_, S>
{
    fn flow_a(
        &mut self,
        _t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        h: D,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        self.work.flows += 1;
        kepler::drift(self.mu, q, p, h)
    }
    fn flow_b(&mut self, t: D, q: &SVector<D, N>, h: D) -> Result<SVector<D, N>> {
        self.work.gradients += 1;
        let (_, g) = gradient(|qd| self.system.perturbation(GradDual::from_re(t), qd), q);
        Ok(g * (-h))
    }
}

impl<S: PerturbedKepler<N>, const N: usize> OneStep<S, N> for WisdomHolman {
    fn order(&self) -> u32 {
        self.table.order
    }
    fn name(&self) -> String {
        self.name_for()
    }
    #[inline]
    fn increment<D: DualNum<f64> + Copy>(
        &self,
        system: &S,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        dt: D,
        work: &mut Work,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        let mu = positive("gravitational parameter μ", system.mu())?;
        let mut flows = KeplerFlows { system, mu, work };
        step(self, &mut flows, t, q, p, dt)
    }
}

/// Wisdom–Holman for a [`PlanetarySystem`]: a [`WisdomHolman`] table (with its corrector, if
/// any) run in the canonical coordinates `coordinates`, the state mapped there and back around
/// each step of a [`Fixed`] run, or once at each end of [`PlanetaryWisdomHolman::propagate`].
///
/// Cost per step: one Kepler drift per planet per `A` sub-step ([`Work::flows`] counts each) and
/// one AD gradient of the interaction per kick.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanetaryWisdomHolman {
    method: WisdomHolman,
    coordinates: PlanetaryCoordinates,
}

impl PlanetaryWisdomHolman {
    /// `method` in `coordinates`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a corrector in democratic heliocentric coordinates (the
    /// corrector is stated for a split into exactly solvable `A` and `B`; there the `A` flow is
    /// a composition with the jump).
    pub fn new(method: WisdomHolman, coordinates: PlanetaryCoordinates) -> Result<Self> {
        if method.corrector.is_some() && coordinates != PlanetaryCoordinates::Jacobi {
            return Err(Error::invalid(
                "symplectic corrector",
                "applies in Jacobi coordinates only",
            ));
        }
        Ok(Self {
            method,
            coordinates,
        })
    }

    /// The table and corrector.
    pub fn method(&self) -> WisdomHolman {
        self.method
    }

    /// The coordinates of the split.
    pub fn coordinates(&self) -> PlanetaryCoordinates {
        self.coordinates
    }

    /// `steps` equal steps over the span of `problem`, the state mapped to the split
    /// coordinates (and the corrector's `C⁻¹` applied) once at the start and back once at `t₁`.
    ///
    /// # Errors
    /// As a [`Fixed`] run of the method.
    pub fn propagate<const N: usize>(
        &self,
        problem: &Problem<'_, PlanetarySystem<N>, N>,
        steps: usize,
    ) -> Result<Report<N>> {
        Fixed::new(*self, steps)?;
        check_initial_field(problem)?;
        let clock = Instant::now();
        let mut work = Work::default();
        let system = problem.system;
        let s = &problem.start;
        let (q, p) = system.to_coordinates(self.coordinates, &s.q, &s.p);
        let mut flows = PlanetaryFlows::new(system, self.coordinates, &mut work);
        let (q, p) = run(&self.method, &mut flows, s.t, &q, &p, problem.t1, steps)?;
        let (q, p) = system.from_coordinates(self.coordinates, &q, &p);
        work.steps = steps;
        let last = finite_state(
            &OneStep::<PlanetarySystem<N>, N>::name(self),
            problem.t1,
            q,
            p,
        )?;
        Ok(Report {
            last,
            stopped: false,
            work,
            elapsed: clock.elapsed(),
        })
    }
}

/// The sub-flows of the planetary split: `A` the Kepler drifts (with the free drift of the
/// centre of mass, and the jump in democratic heliocentric coordinates), `B` the interaction kick.
struct PlanetaryFlows<'a, const N: usize> {
    system: &'a PlanetarySystem<N>,
    coordinates: PlanetaryCoordinates,
    work: &'a mut Work,
    /// `μᵢ` and the mass of each Kepler drift (index 0: the total mass of the centre-of-mass
    /// drift).
    mu: Vec<f64>,
    mass: Vec<f64>,
}

impl<'a, const N: usize> PlanetaryFlows<'a, N> {
    fn new(
        system: &'a PlanetarySystem<N>,
        coordinates: PlanetaryCoordinates,
        work: &'a mut Work,
    ) -> Self {
        let n = system.bodies();
        let mass = (0..n).map(|i| system.kepler_mass(coordinates, i)).collect();
        let mu = (0..n).map(|i| system.kepler_mu(coordinates, i)).collect();
        Self {
            system,
            coordinates,
            work,
            mu,
            mass,
        }
    }

    /// The jump `qᵢ += h Σⱼ pⱼ / m₀` (democratic heliocentric coordinates).
    fn jump<D: DualNum<f64> + Copy>(&self, p: &SVector<D, N>, h: D) -> SVector<D, N> {
        let n = self.system.bodies();
        let mut total = Vector3::<D>::zeros();
        for i in 1..n {
            total += body(p, i);
        }
        let shift = total * (h / D::from(self.system.masses()[0]));
        let mut dq = SVector::<D, N>::zeros();
        for i in 1..n {
            add_body(&mut dq, i, shift);
        }
        dq
    }
}

impl<D: DualNum<f64> + Copy, const N: usize> SubFlows<D, N> for PlanetaryFlows<'_, N> {
    fn flow_a(
        &mut self,
        _t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        h: D,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        let n = self.system.bodies();
        let helio = self.coordinates == PlanetaryCoordinates::DemocraticHeliocentric;
        let mut dq = if helio {
            self.jump(p, h * 0.5)
        } else {
            SVector::zeros()
        };
        let mut dp = SVector::<D, N>::zeros();
        add_body(&mut dq, 0, body(p, 0) * (h / D::from(self.mass[0])));
        for i in 1..n {
            let m = D::from(self.mass[i]);
            let (a, b) = kepler::drift(self.mu[i], &body(&(q + dq), i), &(body(p, i) / m), h)?;
            add_body(&mut dq, i, a);
            add_body(&mut dp, i, b * m);
        }
        self.work.flows += n - 1;
        if helio {
            dq += self.jump(&(p + dp), h * 0.5);
        }
        Ok((dq, dp))
    }
    fn flow_b(&mut self, _t: D, q: &SVector<D, N>, h: D) -> Result<SVector<D, N>> {
        self.work.gradients += 1;
        Ok(self.system.interaction_gradient(self.coordinates, q) * (-h))
    }
    /// In democratic heliocentric coordinates the `A` sub-step `jump ∘ Kepler ∘ jump` is not a
    /// flow (the jump and the Kepler drifts do not commute): two of them are not one.
    fn a_composes(&self) -> bool {
        self.coordinates == PlanetaryCoordinates::Jacobi
    }
}

impl<const N: usize> OneStep<PlanetarySystem<N>, N> for PlanetaryWisdomHolman {
    fn order(&self) -> u32 {
        self.method.table.order
    }
    fn name(&self) -> String {
        let c = match self.coordinates {
            PlanetaryCoordinates::Jacobi => "Jacobi",
            PlanetaryCoordinates::DemocraticHeliocentric => "democratic heliocentric",
        };
        format!("{} ({c} coordinates)", self.method.name_for())
    }
    fn increment<D: DualNum<f64> + Copy>(
        &self,
        system: &PlanetarySystem<N>,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        dt: D,
        work: &mut Work,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        let (qj, pj) = system.to_coordinates(self.coordinates, q, p);
        let mut flows = PlanetaryFlows::new(system, self.coordinates, work);
        let (dq, dp) = step(&self.method, &mut flows, t, &qj, &pj, dt)?;
        let (q1, p1) = system.from_coordinates(self.coordinates, &(qj + dq), &(pj + dp));
        Ok((q1 - q, p1 - p))
    }
}

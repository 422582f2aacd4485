//! Observers: record a trajectory, sample it at requested times, monitor the energy, locate
//! events and Poincaré sections. Points between step ends come from each step's dense output,
//! which for fixed-step methods is a partial step of the method itself ([`sampling`](super::sampling)).

use super::sampling::locate;
use super::{Control, Observer, State, StepView};
use crate::error::{finite, Error, Result};
use crate::hamiltonian::Hamiltonian;
use nalgebra::SVector;

/// Records the initial state and every `every`-th step's end state (and always the last one seen).
#[derive(Clone, Debug, PartialEq)]
pub struct Recorder<const N: usize> {
    every: usize,
    seen: usize,
    /// The recorded states.
    pub states: Vec<State<N>>,
}

impl<const N: usize> Recorder<N> {
    /// Record every `every`-th step (`every = 0` is taken as 1).
    pub fn every(every: usize) -> Self {
        Self {
            every: every.max(1),
            seen: 0,
            states: Vec::new(),
        }
    }
}

impl<const N: usize> Observer<N> for Recorder<N> {
    fn start(&mut self, state: &State<N>) {
        self.states.push(*state);
    }
    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        self.seen += 1;
        if self.seen.is_multiple_of(self.every) {
            self.states.push(*step.next);
        }
        Control::Continue
    }
}

/// The relative energy error `(H − H₀)/|H₀|` along the run: its maximum, its final value and a
/// least-squares slope against time (a linear drift shows as a slope well away from zero).
#[derive(Clone, Debug)]
pub struct EnergyMonitor<'a, S> {
    system: &'a S,
    h0: f64,
    every: usize,
    seen: usize,
    /// Largest `|ΔH/H₀|` seen.
    pub max_error: f64,
    /// `ΔH/H₀` at the last sample.
    pub last_error: f64,
    /// Samples `(t, ΔH/H₀)`.
    pub samples: Vec<(f64, f64)>,
}

impl<'a, S> EnergyMonitor<'a, S> {
    /// Sample the energy every `every` steps.
    pub fn new(system: &'a S, every: usize) -> Self {
        Self {
            system,
            h0: f64::NAN,
            every: every.max(1),
            seen: 0,
            max_error: 0.0,
            last_error: 0.0,
            samples: Vec::new(),
        }
    }

    /// Least-squares slope of `ΔH/H₀` against time.
    pub fn drift_slope(&self) -> f64 {
        let n = self.samples.len() as f64;
        if n < 2.0 {
            return 0.0;
        }
        let (st, se) = self
            .samples
            .iter()
            .fold((0.0, 0.0), |(a, b), &(t, e)| (a + t, b + e));
        let (mt, me) = (st / n, se / n);
        let (num, den) = self.samples.iter().fold((0.0, 0.0), |(a, b), &(t, e)| {
            (a + (t - mt) * (e - me), b + (t - mt) * (t - mt))
        });
        if den == 0.0 {
            0.0
        } else {
            num / den
        }
    }
}

impl<S: Hamiltonian<N>, const N: usize> Observer<N> for EnergyMonitor<'_, S> {
    fn start(&mut self, state: &State<N>) {
        self.h0 = self.system.hamiltonian(state.t, &state.q, &state.p);
        self.samples.push((state.t, 0.0));
    }
    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        self.seen += 1;
        if self.seen.is_multiple_of(self.every) {
            let s = step.next;
            let h = self.system.hamiltonian(s.t, &s.q, &s.p);
            let e = (h - self.h0) / self.h0.abs().max(f64::MIN_POSITIVE);
            self.max_error = self.max_error.max(e.abs());
            self.last_error = e;
            self.samples.push((s.t, e));
        }
        Control::Continue
    }
}

/// A located event: the state where the event function crossed zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Event<const N: usize> {
    /// The state at the crossing (from dense output).
    pub state: State<N>,
    /// `+1` for an upward crossing of `g`, `−1` for downward.
    pub direction: i8,
}

/// Zero crossings of an event function `g(state)`, located on each step's dense output by the
/// Illinois (modified regula falsi) iteration until the time is resolved to adjacent
/// floating-point numbers; with `terminal = true` the run stops at the first one. For fixed-step
/// methods the located state is a partial step of the method ([`sampling`](super::sampling)); a
/// [`Section`] does the same for a surface `s(t, q, p)` with a crossing count.
pub struct Events<G, const N: usize> {
    g: G,
    direction: i8,
    terminal: bool,
    /// The events found so far.
    pub found: Vec<Event<N>>,
}

impl<G: FnMut(&State<N>) -> f64, const N: usize> Events<G, N> {
    /// Crossings of `g` in `direction` (`+1` upward, `−1` downward, `0` both).
    pub fn new(g: G, direction: i8, terminal: bool) -> Self {
        Self {
            g,
            direction,
            terminal,
            found: Vec::new(),
        }
    }
}

impl<G: FnMut(&State<N>) -> f64, const N: usize> Observer<N> for Events<G, N> {
    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        let (ga, gb) = ((self.g)(step.prev), (self.g)(step.next));
        let Some(up) = crossing(ga, gb, self.direction) else {
            return Control::Continue;
        };
        let Some(state) = locate(step.dense, step.prev, step.next, ga, gb, &mut self.g) else {
            return Control::Continue;
        };
        self.found.push(Event {
            state,
            direction: if up { 1 } else { -1 },
        });
        if self.terminal {
            Control::StopAt(state.t)
        } else {
            Control::Continue
        }
    }
}

/// Whether `g` crosses zero from `ga` to `gb` in the wanted `direction` (`+1` upward, `−1`
/// downward, `0` both): `Some(true)` for an upward crossing (`ga < 0 ≤ gb`), `Some(false)` for a
/// downward one (`ga > 0 ≥ gb`), `None` otherwise. A zero at the step's start was counted with the
/// step before.
fn crossing(ga: f64, gb: f64, direction: i8) -> Option<bool> {
    let up = ga < 0.0 && gb >= 0.0;
    let down = ga > 0.0 && gb <= 0.0;
    match direction {
        1 if up => Some(true),
        -1 if down => Some(false),
        0 if up || down => Some(up),
        _ => None,
    }
}

/// The sense in which a surface is crossed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Crossing {
    /// `s` goes from negative to non-negative.
    Up,
    /// `s` goes from positive to non-positive.
    Down,
    /// Either.
    Both,
}

impl Crossing {
    fn sign(self) -> i8 {
        match self {
            Crossing::Up => 1,
            Crossing::Down => -1,
            Crossing::Both => 0,
        }
    }
}

/// A Poincaré section: the points `(t, q, p)` where the run crosses the surface `s(t, q, p) = 0`
/// in the chosen sense (Poincaré, *Les méthodes nouvelles de la mécanique céleste* I (1892)
/// ch. III; Lichtenberg & Lieberman, *Regular and Chaotic Dynamics*, 2nd ed., §1.2b).
///
/// Each crossing is located within its step by the Illinois iteration on the step's dense output
/// (see [`sampling`](super::sampling)): for fixed-step methods every iterate is a partial step of
/// the method itself, so a section point lies on the method's numerical trajectory to its own
/// order (a Störmer–Verlet section is good to `O(h²)`, one of Kahan–Li with 17 stages, order 8,
/// to `O(h⁸)`); for
/// DOP853 on its continuous extension. The stored trajectory is not altered. A crossing is seen
/// as a change of sign of `s` between the ends of a step (the sense taken in the direction of
/// the run), so a step must not cross the surface twice; a non-finite value of `s` at a step end
/// is not a crossing.
///
/// `s` is a closure on reals; a [`PhaseFunction`](crate::PhaseFunction) `f` written once over
/// dual numbers serves as `move |t, q, p| f.eval(t, q, p)`.
///
/// ```
/// use hamilton_jacobi::integrate::{integrate, Crossing, Fixed, Problem, Section, Splitting};
/// use hamilton_jacobi::nalgebra::SVector;
/// use hamilton_jacobi::systems::Pendulum;
/// let pendulum = Pendulum::new(1.0).unwrap();
/// let problem = Problem::new(&pendulum, 0.0, SVector::from([1.0]), SVector::from([0.0]), 30.0).unwrap();
/// // Upward passages through q = 0 (p > 0 there), stopping after the third.
/// let mut section = Section::new(|_t, q, _p| q[0], Crossing::Up).stop_after(3);
/// let run = integrate(&problem, &Fixed::new(Splitting::VERLET_KDK, 3000).unwrap(), &mut section).unwrap();
/// assert_eq!(section.points.len(), 3);
/// assert!(run.stopped && section.points.iter().all(|z| z.q[0].abs() < 1e-15 && z.p[0] > 0.0));
/// ```
pub struct Section<F, const N: usize> {
    surface: F,
    crossing: Crossing,
    limit: Option<usize>,
    /// The crossings found so far, in the order of the run.
    pub points: Vec<State<N>>,
}

impl<F, const N: usize> Section<F, N>
where
    F: FnMut(f64, &SVector<f64, N>, &SVector<f64, N>) -> f64,
{
    /// Crossings of `surface(t, q, p) = 0` in the sense `crossing`, for the whole run.
    pub fn new(surface: F, crossing: Crossing) -> Self {
        Self {
            surface,
            crossing,
            limit: None,
            points: Vec::new(),
        }
    }

    /// Stop the run at the `count`-th crossing (a terminal event: the run's last state is that
    /// crossing). `count = 0` records nothing and stops at the first crossing.
    pub fn stop_after(mut self, count: usize) -> Self {
        self.limit = Some(count);
        self
    }

    fn value(&mut self, z: &State<N>) -> f64 {
        (self.surface)(z.t, &z.q, &z.p)
    }
}

impl<F, const N: usize> Observer<N> for Section<F, N>
where
    F: FnMut(f64, &SVector<f64, N>, &SVector<f64, N>) -> f64,
{
    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        let (ga, gb) = (self.value(step.prev), self.value(step.next));
        if crossing(ga, gb, self.crossing.sign()).is_none() {
            return Control::Continue;
        }
        let surface = &mut self.surface;
        let Some(point) = locate(step.dense, step.prev, step.next, ga, gb, |z| {
            surface(z.t, &z.q, &z.p)
        }) else {
            return Control::Continue;
        };
        match self.limit {
            Some(n) if self.points.len() >= n => Control::StopAt(point.t),
            Some(n) => {
                self.points.push(point);
                if self.points.len() == n {
                    Control::StopAt(point.t)
                } else {
                    Control::Continue
                }
            }
            None => {
                self.points.push(point);
                Control::Continue
            }
        }
    }
}

/// Largest number of requested times [`Samples`] accepts (`2²⁶`, about 1 GiB of states at
/// `N = 3`): a bound on the memory a run can be asked to fill.
pub const MAX_SAMPLES: usize = 1 << 26;

/// The states at requested times: the start, if it is one of them, and every requested time the
/// run passes, taken from each step's dense output (a partial step of the method for fixed-step
/// methods, the continuous extension for DOP853: see [`sampling`](super::sampling)). The stored
/// trajectory is not altered.
///
/// ```
/// use hamilton_jacobi::integrate::{integrate, Fixed, Problem, Rk4, Samples};
/// use hamilton_jacobi::nalgebra::SVector;
/// use hamilton_jacobi::systems::Pendulum;
/// let pendulum = Pendulum::new(1.0).unwrap();
/// let problem = Problem::new(&pendulum, 0.0, SVector::from([1.0]), SVector::from([0.0]), 1.0).unwrap();
/// let mut samples = Samples::at([0.0, 0.123, 0.5, 0.777]).unwrap();
/// integrate(&problem, &Fixed::new(Rk4, 10).unwrap(), &mut samples).unwrap();
/// let times: Vec<f64> = samples.states.iter().map(|s| s.t).collect();
/// assert_eq!(times, [0.0, 0.123, 0.5, 0.777]);
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct Samples<const N: usize> {
    times: Vec<f64>,
    next: usize,
    /// The sampled states, in the order of the requested times.
    pub states: Vec<State<N>>,
}

impl<const N: usize> Samples<N> {
    /// At the given times, which must be finite and strictly monotone in the direction of the
    /// run; times before the start are skipped, times beyond the end are not reached. Errors: an
    /// empty list, a non-finite or non-monotone time, more than [`MAX_SAMPLES`] times.
    pub fn at(times: impl IntoIterator<Item = f64>) -> Result<Self> {
        let mut list = Vec::new();
        for t in times {
            if list.len() >= MAX_SAMPLES {
                return Err(Error::out_of_domain(
                    "number of sample times",
                    (MAX_SAMPLES + 1) as f64,
                    format!("≤ {MAX_SAMPLES}"),
                ));
            }
            list.push(finite("sample time", t)?);
        }
        if list.is_empty() {
            return Err(Error::invalid("sample times", "no time requested"));
        }
        if list.len() > 1 {
            let rising = list[1] > list[0];
            if let Some(w) = list
                .windows(2)
                .find(|w| if rising { w[1] <= w[0] } else { w[1] >= w[0] })
            {
                return Err(Error::invalid(
                    "sample times",
                    format!(
                        "not strictly monotone: {:e} follows {:e} in a {} list",
                        w[1],
                        w[0],
                        if rising { "rising" } else { "falling" }
                    ),
                ));
            }
        }
        Ok(Self {
            states: Vec::with_capacity(list.len()),
            times: list,
            next: 0,
        })
    }

    /// `count + 1` times `t₀ + k (t₁ − t₀)/count`, `k = 0 … count` (`1 ≤ count < MAX_SAMPLES`).
    pub fn uniform(t0: f64, t1: f64, count: usize) -> Result<Self> {
        finite("first sample time", t0)?;
        finite("last sample time", t1)?;
        if count == 0 || count >= MAX_SAMPLES {
            return Err(Error::out_of_domain(
                "number of sample intervals",
                count as f64,
                format!("1 … {}", MAX_SAMPLES - 1),
            ));
        }
        if t0 == t1 || !(t1 - t0).is_finite() {
            return Err(Error::invalid(
                "sample span",
                format!("t₀ = {t0:e}, t₁ = {t1:e}: need t₁ ≠ t₀ with a finite difference"),
            ));
        }
        let n = count as f64;
        Self::at((0..=count).map(|k| {
            if k == count {
                t1
            } else {
                t0 + (t1 - t0) * (k as f64 / n)
            }
        }))
    }

    /// The requested times.
    pub fn times(&self) -> &[f64] {
        &self.times
    }
}

impl<const N: usize> Observer<N> for Samples<N> {
    fn start(&mut self, state: &State<N>) {
        if self.times.get(self.next) == Some(&state.t) {
            self.states.push(*state);
            self.next += 1;
        }
    }
    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        let forward = step.next.t >= step.prev.t;
        let ahead = |t: f64, of: f64| if forward { t > of } else { t < of };
        // Times behind the step's start cannot be reached any more.
        while let Some(&t) = self.times.get(self.next) {
            if ahead(t, step.prev.t) {
                break;
            }
            self.next += 1;
        }
        while let Some(&t) = self.times.get(self.next) {
            if ahead(t, step.next.t) {
                break;
            }
            self.states.push(step.dense.at(t));
            self.next += 1;
        }
        Control::Continue
    }
}

/// An observer borrowed for the run, so that observers kept by the caller can be combined:
/// `integrate(&problem, &method, &mut (&mut recorder, &mut section))`.
impl<O: Observer<N> + ?Sized, const N: usize> Observer<N> for &mut O {
    fn start(&mut self, state: &State<N>) {
        (**self).start(state);
    }
    fn step(&mut self, step: &StepView<'_, N>) -> Control {
        (**self).step(step)
    }
}

//! Observers: record a trajectory, monitor the energy, locate events on dense output.

use super::{Control, Observer, State, StepView};
use crate::hamiltonian::Hamiltonian;

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
/// Illinois (modified regula falsi) iteration to a time tolerance of a few ulps; with
/// `terminal = true` the run stops at the first one.
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
        let up = ga < 0.0 && gb >= 0.0;
        let down = ga > 0.0 && gb <= 0.0;
        let wanted = match self.direction {
            1 => up,
            -1 => down,
            _ => up || down,
        };
        if !wanted {
            return Control::Continue;
        }
        let (mut a, mut b) = (step.prev.t, step.next.t);
        let (mut fa, mut fb) = (ga, gb);
        let mut side = 0;
        let mut t = b;
        for _ in 0..200 {
            t = (a * fb - b * fa) / (fb - fa);
            if !t.is_finite() {
                t = 0.5 * (a + b);
            }
            let ft = (self.g)(&step.dense.at(t));
            if ft == 0.0 || (b - a).abs() <= 4.0 * f64::EPSILON * t.abs().max(1.0) {
                break;
            }
            if (ft < 0.0) == (fa < 0.0) {
                a = t;
                fa = ft;
                if side == -1 {
                    fb *= 0.5;
                }
                side = -1;
            } else {
                b = t;
                fb = ft;
                if side == 1 {
                    fa *= 0.5;
                }
                side = 1;
            }
        }
        self.found.push(Event {
            state: step.dense.at(t),
            direction: if up { 1 } else { -1 },
        });
        if self.terminal {
            Control::StopAt(t)
        } else {
            Control::Continue
        }
    }
}

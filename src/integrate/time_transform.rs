//! Adaptive symplectic integration of separable `H = T(p) + V(t, q)` by a time transformation
//! that keeps the split: the logarithmic Hamiltonian of Mikkola & Tanikawa and the power family
//! of Preto & Tremaine.
//!
//! Time becomes a coordinate with conjugate momentum `p_t` (on the motion `p_t = c − H`, `c` a
//! constant shift of the energy), a fictitious time `s` the independent variable, and the
//! extended Hamiltonian
//!
//! ```math
//! \Gamma(q, t; p, p_t) = f\big(T(p) + p_t\big) - f\big(U(t, q)\big),\qquad U = c - V,
//! ```
//!
//! with `f(x) = ln x` (logarithmic Hamiltonian) or `f(x) = x^α/α`, `0 < α ≤ 1`. On the level
//! set `Γ = 0`, which contains the motion, `T + p_t = U`, so
//!
//! ```math
//! \frac{dt}{ds} = f'(T + p_t) = f'(U) = g(q),\qquad g = \frac1U\ \text{(logarithmic)},\quad
//! g = U^{\alpha - 1}\ \text{(power)},
//! ```
//!
//! a Sundman transformation whose step in `t` shrinks where `U` is large. `Γ` is again a sum
//! of a function of the momenta and a function of the coordinates, so both sub-flows are
//! explicit:
//!
//! ```math
//! \varphi^{A}_{h}:\ q \mathrel{+}= h f'(T + p_t)\,\nabla T(p),\ t \mathrel{+}= h f'(T + p_t);\qquad
//! \varphi^{B}_{h}:\ p \mathrel{-}= h f'(U)\,\nabla_q V,\ p_t \mathrel{-}= h f'(U)\,\partial_t V,
//! ```
//!
//! and every word of the crate's splitting tables ([`Splitting`]) composes them into a
//! symplectic method of the same order in `s`: the leapfrog (Störmer–Verlet) becomes the
//! Mikkola–Tanikawa leapfrog, the compositions its higher-order versions. For the Kepler problem
//! (`V = −μ/r`, `c = 0`, `f = ln`) the leapfrog moves on the exact Kepler orbit — energy,
//! angular momentum and Laplace–Runge–Lenz vector conserved — with an error in time only
//! (Mikkola & Tanikawa 1999, §3; Preto & Tremaine 1999, §3).
//!
//! Rounding: a perturbation `γ` of the conserved `Γ` changes the motion by a relative `O(γ)`,
//! not by `γ` divided by the distance to a separatrix: `T + p_t = U e^{γ}` is the same system
//! with `U` rescaled by `e^γ`. Near the pendulum's separatrix, where the period depends on the
//! energy gap `p_t` as `−2 ln p_t`, this keeps the gap to full relative precision (the gap is a
//! variable of its own, `p_t`, rather than the difference `c − H` of rounded numbers), provided
//! `V` is written so that `U = c − V` has full relative precision near its zeros.
//!
//! Requirements on the system: [`Separable`], conservative, `T` independent of `t`, and
//! `U = c − V > 0` along the motion (a typed error where it is not). Each step is advanced with
//! Kahan-compensated summation of every sub-step's increments. Output at a physical time (the
//! run's end `t₁`, and the dense output for observers) is a partial step of the method in `s`
//! whose length is found by the Illinois iteration on `t(s) − t_target`.
//!
//! References: S. Mikkola & K. Tanikawa, "Algorithmic regularization of the few-body problem",
//! MNRAS 310 (1999) 745–749, doi:10.1046/j.1365-8711.1999.02982.x; M. Preto & S. Tremaine, "A
//! class of symplectic integrators with adaptive time step for separable Hamiltonian systems",
//! Astron. J. 118 (1999) 2532–2541, doi:10.1086/301102; Hairer, Lubich & Wanner, *Geometric
//! Numerical Integration*, 2nd ed., §VIII.2.

use super::coefficients::Flow;
use super::methods::{Construction, MethodInfo};
use super::sampling::illinois;
use super::splitting::Splitting;
use super::{compensated_add, observe, settle, Dense, Method, Observer, Problem, Report, Work};
use crate::error::{finite, Error, Result};
use crate::hamiltonian::Separable;
use crate::phase::State;
use crate::special::double_double::kahan_add;
use nalgebra::SVector;
use num_dual::Dual64;
use std::cell::Cell;
use std::time::Instant;

/// The function `f` of the extended Hamiltonian `Γ = f(T + p_t) − f(U)`, which fixes the time
/// transformation `dt/ds = f'(U)` ([module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Sundman {
    /// `f = ln`: `dt/ds = 1/U` (Mikkola & Tanikawa 1999; for Kepler `dt = (r/μ) ds`).
    Logarithmic,
    /// `f(x) = x^α/α`, `0 < α ≤ 1`: `dt/ds = U^{α−1}` (Preto & Tremaine 1999); `α = 1` is no
    /// transformation, `α = 1/2` regularises a hyperbolic point where `U` has a double zero.
    Power(f64),
}

impl Sundman {
    /// `f'(x)`, the rate `dt/ds` at `x = T + p_t` (drift) or `x = U` (kick).
    #[inline]
    pub fn rate(self, x: f64) -> f64 {
        match self {
            Sundman::Logarithmic => 1.0 / x,
            Sundman::Power(0.5) => 1.0 / x.sqrt(),
            Sundman::Power(1.0) => 1.0,
            Sundman::Power(a) => x.powf(a - 1.0),
        }
    }

    /// `f(x)`.
    pub fn f(self, x: f64) -> f64 {
        match self {
            Sundman::Logarithmic => x.ln(),
            Sundman::Power(a) => x.powf(a) / a,
        }
    }
}

/// A splitting method run in the fictitious time `s` of a [`Sundman`] time transformation, with
/// the physical time as a coordinate (see the [module docs](self)).
///
/// ```
/// use hamilton_jacobi::integrate::{integrate, Problem, Splitting, TimeTransformed};
/// use hamilton_jacobi::systems::Kepler2;
/// use hamilton_jacobi::nalgebra::SVector;
/// use hamilton_jacobi::Hamiltonian;
/// // Kepler e = 0.9 from periapsis over one period, by the logarithmic-Hamiltonian leapfrog.
/// let kepler = Kepler2::new(1.0).unwrap();
/// let (q0, p0) = (SVector::from([0.1, 0.0]), SVector::from([0.0, 19f64.sqrt()]));
/// let problem = Problem::new(&kepler, 0.0, q0, p0, std::f64::consts::TAU).unwrap();
/// let leapfrog = TimeTransformed::logarithmic(Splitting::VERLET_DKD, 0.05).unwrap();
/// let run = integrate(&problem, &leapfrog, &mut ()).unwrap();
/// // The orbit is exact: the energy is kept to rounding.
/// let e1 = kepler.value(0.0, &run.last.q, &run.last.p).unwrap();
/// assert!((e1 + 0.5).abs() < 1e-13);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TimeTransformed {
    /// The splitting method (its word) applied in `s`.
    pub method: Splitting,
    /// The time transformation.
    pub sundman: Sundman,
    /// The step in fictitious time `s` (its magnitude; the sign follows `t₁ − t₀`).
    pub ds: f64,
    /// The energy shift `c` of `U = c − V` (0 for potentials that are negative on the motion).
    pub shift: f64,
    /// Largest number of steps a run may take.
    pub max_steps: usize,
}

/// The extended state `(q, t; p, p_t)` with the compensated-summation carries of its parts.
#[derive(Clone, Copy, Debug)]
struct Extended<const N: usize> {
    q: SVector<f64, N>,
    p: SVector<f64, N>,
    t: f64,
    pt: f64,
    carry: (SVector<f64, N>, SVector<f64, N>, f64, f64),
}

impl<const N: usize> Extended<N> {
    fn state(&self) -> State<N> {
        State {
            t: self.t,
            q: self.q,
            p: self.p,
        }
    }
}

impl TimeTransformed {
    /// Default limit on the number of steps of one run (as [`Fixed::MAX_STEPS`](super::Fixed)).
    pub const MAX_STEPS: usize = 100_000_000;

    /// The logarithmic Hamiltonian (Mikkola–Tanikawa) with `method`'s word and step `ds` in
    /// fictitious time, shift `c = 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] / [`Error::OutOfDomain`] for a step that is not finite and non-zero.
    pub fn logarithmic(method: Splitting, ds: f64) -> Result<Self> {
        Self::new(method, Sundman::Logarithmic, ds)
    }

    /// The power transformation `f(x) = x^α/α` (Preto–Tremaine) with `0 < α ≤ 1`.
    ///
    /// # Errors
    /// As [`logarithmic`](Self::logarithmic); [`Error::OutOfDomain`] for `α ∉ (0, 1]`.
    pub fn power(method: Splitting, alpha: f64, ds: f64) -> Result<Self> {
        Self::new(method, Sundman::Power(alpha), ds)
    }

    /// `method` under the transformation `sundman` with step `ds`, shift 0.
    ///
    /// # Errors
    /// As [`power`](Self::power).
    pub fn new(method: Splitting, sundman: Sundman, ds: f64) -> Result<Self> {
        let m = Self {
            method,
            sundman,
            ds,
            shift: 0.0,
            max_steps: Self::MAX_STEPS,
        };
        m.validate()?;
        Ok(m)
    }

    /// The same with the energy shift `c` (`U = c − V`).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite `c`.
    pub fn with_shift(mut self, c: f64) -> Result<Self> {
        self.shift = finite("energy shift c of the time transformation", c)?;
        Ok(self)
    }

    /// The same with another limit on the number of steps.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for 0.
    pub fn with_max_steps(mut self, max_steps: usize) -> Result<Self> {
        if max_steps == 0 {
            return Err(Error::out_of_domain("step limit", 0.0, "≥ 1"));
        }
        self.max_steps = max_steps;
        Ok(self)
    }

    fn validate(&self) -> Result<()> {
        let ds = finite("fictitious-time step ds", self.ds)?;
        if ds == 0.0 {
            return Err(Error::out_of_domain("fictitious-time step ds", ds, "≠ 0"));
        }
        finite("energy shift c of the time transformation", self.shift)?;
        if let Sundman::Power(a) = self.sundman {
            let a = finite("exponent α of the time transformation", a)?;
            if !(a > 0.0 && a <= 1.0) {
                return Err(Error::out_of_domain(
                    "exponent α of the time transformation",
                    a,
                    "(0, 1]",
                ));
            }
        }
        if self.max_steps == 0 {
            return Err(Error::out_of_domain("step limit", 0.0, "≥ 1"));
        }
        Ok(())
    }

    /// The name: the label of its entry in [`METHODS`](super::METHODS) for the logarithmic
    /// Hamiltonian over a listed word, otherwise the transformation and the splitting's label.
    pub fn name(&self) -> String {
        if self.sundman == Sundman::Logarithmic {
            if let Some(info) = MethodInfo::of(Construction::TimeTransformed(self.method.table())) {
                return info.label();
            }
        }
        let f = match self.sundman {
            Sundman::Logarithmic => "logarithmic Hamiltonian".to_string(),
            Sundman::Power(a) => format!("Sundman power α={a}"),
        };
        format!("{f}, {}", self.method.table().label())
    }

    /// `U = c − V(t, q)`, checked positive.
    fn u<S: Separable<N>, const N: usize>(
        &self,
        system: &S,
        t: f64,
        q: &SVector<f64, N>,
    ) -> Result<f64> {
        let u = self.shift - system.potential(t, q);
        if u > 0.0 && u.is_finite() {
            Ok(u)
        } else {
            Err(Error::out_of_domain(
                format!(
                    "U = c − V at t = {t:e}, q = {q:?} (time transformation, c = {:e})",
                    self.shift
                ),
                u,
                "(0, ∞): the transformation needs c − V > 0 along the motion (raise the shift c)",
            ))
        }
    }

    /// One step of the word over `h` in `s` from `x`.
    fn step<S: Separable<N>, const N: usize>(
        &self,
        system: &S,
        x: &Extended<N>,
        h: f64,
        work: &mut Work,
    ) -> Result<Extended<N>> {
        let mut y = *x;
        self.method.table().for_each_sub_step(|flow, c| {
            if c == 0.0 {
                return Ok(());
            }
            let hc = h * c;
            match flow {
                Flow::A => {
                    work.gradients += 1;
                    let (tv, tp) = system.kinetic_gradient(y.t, &y.p);
                    let e = tv + y.pt;
                    if !(e > 0.0 && e.is_finite()) {
                        return Err(Error::out_of_domain(
                            format!("T + p_t at t = {:e} (time transformation)", y.t),
                            e,
                            "(0, ∞): the transformation needs c − V > 0 along the motion",
                        ));
                    }
                    let rate = self.sundman.rate(e) * hc;
                    compensated_add(&mut y.q, &mut y.carry.0, &(tp * rate));
                    kahan_add(&mut y.t, &mut y.carry.2, rate);
                }
                Flow::B => {
                    work.gradients += 1;
                    work.hamiltonians += 1;
                    let (v, vq) = system.potential_gradient(y.t, &y.q);
                    let u = self.shift - v;
                    if !(u > 0.0 && u.is_finite()) {
                        return Err(self.u(system, y.t, &y.q).err().unwrap_or_else(|| {
                            Error::out_of_domain("U = c − V (time transformation)", u, "(0, ∞)")
                        }));
                    }
                    let vt = system
                        .potential(Dual64::new(y.t, 1.0), &y.q.map(Dual64::from))
                        .eps;
                    let rate = self.sundman.rate(u) * hc;
                    compensated_add(&mut y.p, &mut y.carry.1, &(vq * (-rate)));
                    kahan_add(&mut y.pt, &mut y.carry.3, -rate * vt);
                }
            }
            Ok(())
        })?;
        let finite = y.q.iter().chain(y.p.iter()).all(|v| v.is_finite())
            && y.t.is_finite()
            && y.pt.is_finite();
        if !finite {
            return Err(Error::NonFinite {
                what: format!("{} state after a step from t = {:e}", self.name(), x.t),
                value: f64::NAN,
            });
        }
        Ok(y)
    }

    /// The state at physical time `target` within the step `x → y` of length `h` in `s`: the
    /// partial step whose end has `t = target`, found by the Illinois iteration.
    fn land<S: Separable<N>, const N: usize>(
        &self,
        system: &S,
        x: &Extended<N>,
        y: &Extended<N>,
        h: f64,
        target: f64,
        work: &mut Work,
    ) -> Result<Extended<N>> {
        let (fa, fb) = (x.t - target, y.t - target);
        if fa == 0.0 {
            return Ok(*x);
        }
        if fb == 0.0 {
            return Ok(*y);
        }
        let mut failure = None;
        let mut eval = |g: f64| match self.step(system, x, g, work) {
            Ok(z) => Some((z.t - target, z)),
            Err(e) => {
                failure = Some(e);
                None
            }
        };
        let found = illinois((0.0, fa, *x), (h, fb, *y), &mut eval);
        match (found, failure) {
            (Some((mut z, _)), _) => {
                z.t = target;
                z.carry.2 = 0.0;
                Ok(z)
            }
            (None, Some(e)) => Err(e),
            (None, None) => Err(Error::NotConverged {
                what: format!("{}: the fictitious time of t = {target:e}", self.name()),
                iterations: 200,
                residual: f64::NAN,
            }),
        }
    }
}

/// Dense output over one step in `s`: the state at a physical time by a partial step.
struct Landing<'a, S, const N: usize> {
    method: &'a TimeTransformed,
    system: &'a S,
    from: Extended<N>,
    to: Extended<N>,
    h: f64,
    work: Cell<Work>,
}

impl<S: Separable<N>, const N: usize> Dense<N> for Landing<'_, S, N> {
    fn at(&self, t: f64) -> State<N> {
        let mut work = self.work.get();
        let z = self
            .method
            .land(self.system, &self.from, &self.to, self.h, t, &mut work);
        self.work.set(work);
        match z {
            Ok(z) => z.state(),
            Err(_) => {
                let nan = SVector::from_element(f64::NAN);
                State { t, q: nan, p: nan }
            }
        }
    }
}

impl<S: Separable<N>, const N: usize> Method<S, N> for TimeTransformed {
    fn label(&self) -> String {
        format!("{} ds={:e}", self.name(), self.ds)
    }

    fn run<O: Observer<N>>(
        &self,
        problem: &Problem<'_, S, N>,
        observer: &mut O,
    ) -> Result<Report<N>> {
        self.validate()?;
        let clock = Instant::now();
        let system = problem.system;
        let start = problem.start;
        if system
            .generalized_force(start.t, &start.q, &start.p)
            .is_some()
        {
            return Err(Error::invalid(
                format!("{} on this system", self.name()),
                "the time-transformed splitting integrates conservative H = T(p) + V(t, q) only; \
                 the system has non-conservative forces",
            ));
        }
        let mut work = Work::default();
        let u0 = self.u(system, start.t, &start.q)?;
        let t0 = finite("kinetic energy T(p₀)", system.kinetic(start.t, &start.p))?;
        let zero = SVector::<f64, N>::zeros();
        let mut x = Extended {
            q: start.q,
            p: start.p,
            t: start.t,
            // p_t = c − H = U − T.
            pt: u0 - t0,
            carry: (zero, zero, 0.0, 0.0),
        };
        let direction = (problem.t1 - start.t).signum();
        let h = self.ds.abs() * direction;
        observer.start(&start);
        let mut stopped = false;
        let last = loop {
            if work.steps >= self.max_steps {
                return Err(Error::WorkLimit {
                    what: format!("{} run", self.name()),
                    limit: self.max_steps,
                    detail: format!("t = {:e} reached of t₁ = {:e}", x.t, problem.t1),
                    hint: "use a larger step ds, or raise the limit with with_max_steps".into(),
                });
            }
            let mut y = self.step(system, &x, h, &mut work)?;
            work.steps += 1;
            if (y.t - x.t) * direction <= 0.0 {
                return Err(Error::invalid(
                    format!("{} step from t = {:e}", self.name(), x.t),
                    "the physical time does not advance (step ds too small for t, or dt/ds ≤ 0)",
                ));
            }
            let end = (y.t - problem.t1) * direction >= 0.0;
            if end {
                y = self.land(system, &x, &y, h, problem.t1, &mut work)?;
            }
            let dense = Landing {
                method: self,
                system,
                from: x,
                to: y,
                h,
                work: Cell::new(Work::default()),
            };
            let (prev, next) = (x.state(), y.state());
            let (control, stop_state) = observe(observer, &prev, &next, &dense)?;
            work = work.add(&dense.work.get());
            if !next.is_finite() || stop_state.is_some_and(|s| !s.is_finite()) {
                return Err(Error::NonFinite {
                    what: format!("{} state at t = {:e}", self.name(), next.t),
                    value: f64::NAN,
                });
            }
            let (state, finish) = settle(control, next, stop_state, end, problem.t1);
            x = y;
            if let Some(s) = finish {
                stopped = s;
                break state;
            }
            if end {
                break state;
            }
        };
        Ok(Report {
            last,
            stopped,
            work,
            elapsed: clock.elapsed(),
        })
    }
}

//! Integration methods as values: one type for the methods that apply to any Hamiltonian
//! ([`GeneralMethod`]) and one that adds the explicit splittings for separable systems
//! ([`AnyMethod`]), so that a list of methods can be built at run time and swept.
//!
//! ```
//! use hamilton_jacobi::integrate::{integrate, AnyMethod, Method, MethodInfo, Problem};
//! use hamilton_jacobi::nalgebra::SVector;
//! use hamilton_jacobi::systems::Pendulum;
//! let pendulum = Pendulum::new(1.0).unwrap();
//! let problem = Problem::new(&pendulum, 0.0, SVector::from([1.0]), SVector::from([0.0]), 1.0).unwrap();
//! let methods: Vec<AnyMethod> = vec![
//!     AnyMethod::new(MethodInfo::find("verlet-kdk").unwrap(), 100.0).unwrap(),
//!     AnyMethod::new(MethodInfo::find("kahan-li17").unwrap(), 10.0).unwrap(),
//!     AnyMethod::gauss(3, 10).unwrap(),
//!     AnyMethod::rk4(50).unwrap(),
//!     AnyMethod::dop853(1e-12, 1e-14).unwrap(),
//! ];
//! for m in &methods {
//!     let run = integrate(&problem, m, &mut ()).unwrap();
//!     assert_eq!(run.last.t, 1.0, "{}", Method::<Pendulum, 1>::label(m));
//! }
//! assert_eq!(methods[2].info().unwrap().label(), "Gauss–Legendre, 3 stages, order 6");
//! ```
//!
//! Each variant wraps the typed method ([`Fixed`] over [`Rk4`], [`Gauss`], [`Splitting`], or
//! [`Dop853`]) and runs it unchanged; a sweep over `AnyMethod` gives the same numbers and work
//! counts as the typed runs. The capability bound stays a compile-time bound: `GeneralMethod`
//! implements [`Method`] for every [`Hamiltonian`], `AnyMethod` for every [`Separable`] system.
//! Wisdom–Holman/SABA ([`WisdomHolman`](super::WisdomHolman)) and exact flows
//! ([`ExactStep`](super::ExactStep)) need capabilities (a Kepler part, a closed-form flow) that no
//! generic bound can check at run time for an arbitrary system; they stay typed values.
//!
//! Values are built from the method table [`METHODS`](super::METHODS) by
//! [`AnyMethod::new`] / [`GeneralMethod::new`]: an entry and the value of its knob (steps or
//! tolerance), so that a front end keying methods by name (the scene files, `hj`) runs every
//! method through one generic `integrate` call per capability.

use super::methods::{self, whole_steps, Capability, Construction, MethodInfo};
use super::{
    integrate, Dop853, Fixed, Gauss, Method, Observer, Precision, Problem, Report, Rk4, Rk45,
    Splitting, Sundman, Taylor, TimeTransformed,
};
use crate::error::{Error, Result};
use crate::hamiltonian::{Hamiltonian, Separable};

/// The refusal of a method that needs more of the system than the value built covers; `hint`
/// says how to build it instead.
fn not_covered(info: &MethodInfo, hint: &str) -> Error {
    Error::invalid(
        format!("method {} ({})", info.key, info.label()),
        format!("needs {}; {hint}", info.capability().systems()),
    )
}

/// A method for any [`Hamiltonian`]: classical Runge–Kutta (4 stages, order 4), Gauss–Legendre
/// with `s = 1 … 6` stages (order `2s`), Dormand–Prince (12 stages, order 8, or 6 stages, order 5
/// with SciPy's `RK45` control; adaptive) or the
/// Taylor method (order and step from the tolerance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GeneralMethod {
    /// Classical Runge–Kutta, 4 stages, order 4, with a fixed number of steps.
    Rk4(Fixed<Rk4>),
    /// Gauss–Legendre, 1 stage, order 2 (the implicit midpoint rule).
    Gauss1(Fixed<Gauss<1>>),
    /// Gauss–Legendre, 2 stages, order 4.
    Gauss2(Fixed<Gauss<2>>),
    /// Gauss–Legendre, 3 stages, order 6.
    Gauss3(Fixed<Gauss<3>>),
    /// Gauss–Legendre, 4 stages, order 8.
    Gauss4(Fixed<Gauss<4>>),
    /// Gauss–Legendre, 5 stages, order 10.
    Gauss5(Fixed<Gauss<5>>),
    /// Gauss–Legendre, 6 stages, order 12.
    Gauss6(Fixed<Gauss<6>>),
    /// Dormand–Prince, 12 stages, order 8, with its tolerances.
    Dop853(Dop853),
    /// Dormand–Prince 5(4), 6 stages, order 5, with SciPy's `RK45` control and its tolerances.
    Rk45(Rk45),
    /// The Taylor method ([`Taylor`]).
    Taylor(Taylor),
}

impl GeneralMethod {
    /// The method `info` describes, with `knob` its number of steps (a whole number) or, for
    /// Dormand–Prince, its tolerance (`rtol = atol = knob`).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a method that needs more than a [`Hamiltonian`] (a splitting,
    /// the exact flow) or a knob that is not a whole number of steps; the errors of the
    /// constructors for a bad knob value.
    pub fn new(info: &MethodInfo, knob: f64) -> Result<Self> {
        match info.construction {
            Construction::Rk4 => Self::rk4(whole_steps(knob)?),
            Construction::Gauss(s) => Self::gauss(s, whole_steps(knob)?),
            Construction::Dop853 => Self::dop853(knob, knob),
            Construction::Rk45 => Self::rk45(knob, knob),
            Construction::Taylor => Taylor::new(knob).map(Self::Taylor),
            Construction::TaylorDd => Taylor::new(knob).map(|m| Self::Taylor(m.double_double())),
            _ => Err(not_covered(
                info,
                "a GeneralMethod covers any Hamiltonian; build splittings as AnyMethod",
            )),
        }
    }

    /// The method's entry in [`METHODS`](super::METHODS).
    pub fn info(&self) -> &'static MethodInfo {
        match self {
            Self::Rk4(_) => &methods::RK4,
            Self::Gauss1(_) => &methods::GAUSS[0],
            Self::Gauss2(_) => &methods::GAUSS[1],
            Self::Gauss3(_) => &methods::GAUSS[2],
            Self::Gauss4(_) => &methods::GAUSS[3],
            Self::Gauss5(_) => &methods::GAUSS[4],
            Self::Gauss6(_) => &methods::GAUSS[5],
            Self::Dop853(_) => &methods::DOP853,
            Self::Rk45(_) => &methods::RK45,
            Self::Taylor(m) => match m.precision {
                Precision::Double => &methods::TAYLOR,
                Precision::DoubleDouble => &methods::TAYLOR_DD,
            },
        }
    }

    /// RK4 with `steps` steps over the span.
    pub fn rk4(steps: usize) -> Result<Self> {
        Ok(Self::Rk4(Fixed::new(Rk4, steps)?))
    }

    /// Gauss–Legendre with `stages` stages (`1 … 6`, order `2 · stages`) and `steps` steps.
    pub fn gauss(stages: usize, steps: usize) -> Result<Self> {
        Ok(match stages {
            1 => Self::Gauss1(Fixed::new(Gauss::new()?, steps)?),
            2 => Self::Gauss2(Fixed::new(Gauss::new()?, steps)?),
            3 => Self::Gauss3(Fixed::new(Gauss::new()?, steps)?),
            4 => Self::Gauss4(Fixed::new(Gauss::new()?, steps)?),
            5 => Self::Gauss5(Fixed::new(Gauss::new()?, steps)?),
            6 => Self::Gauss6(Fixed::new(Gauss::new()?, steps)?),
            s => {
                return Err(Error::out_of_domain(
                    "Gauss–Legendre stage count",
                    s as f64,
                    "1 … 6",
                ))
            }
        })
    }

    /// DOP853 with relative and absolute tolerances (as [`Dop853::new`]).
    pub fn dop853(rtol: f64, atol: f64) -> Result<Self> {
        Ok(Self::Dop853(Dop853::new(rtol, atol)?))
    }

    /// Dormand–Prince 5(4) with SciPy's `RK45` control and relative and absolute tolerances (as
    /// [`Rk45::new`]).
    pub fn rk45(rtol: f64, atol: f64) -> Result<Self> {
        Ok(Self::Rk45(Rk45::new(rtol, atol)?))
    }

    /// The order of the method, from its [`info`](Self::info) (the Taylor method's from its
    /// tolerance or its fixed order).
    pub fn order(&self) -> u32 {
        match self {
            Self::Taylor(m) => m.order() as u32,
            _ => self.info().order.unwrap_or(u32::MAX),
        }
    }

    /// Number of steps of a fixed-step method; `None` for DOP853 and the adaptive Taylor method.
    pub fn steps(&self) -> Option<usize> {
        Some(match self {
            Self::Rk4(m) => m.steps,
            Self::Gauss1(m) => m.steps,
            Self::Gauss2(m) => m.steps,
            Self::Gauss3(m) => m.steps,
            Self::Gauss4(m) => m.steps,
            Self::Gauss5(m) => m.steps,
            Self::Gauss6(m) => m.steps,
            Self::Dop853(_) | Self::Rk45(_) => return None,
            Self::Taylor(m) => match m.control {
                super::TaylorControl::Fixed { steps, .. } => steps,
                super::TaylorControl::Tolerance(_) => return None,
            },
        })
    }
}

impl<S: Hamiltonian<N>, const N: usize> Method<S, N> for GeneralMethod {
    fn label(&self) -> String {
        match self {
            Self::Rk4(m) => Method::<S, N>::label(m),
            Self::Gauss1(m) => Method::<S, N>::label(m),
            Self::Gauss2(m) => Method::<S, N>::label(m),
            Self::Gauss3(m) => Method::<S, N>::label(m),
            Self::Gauss4(m) => Method::<S, N>::label(m),
            Self::Gauss5(m) => Method::<S, N>::label(m),
            Self::Gauss6(m) => Method::<S, N>::label(m),
            Self::Dop853(m) => Method::<S, N>::label(m),
            Self::Rk45(m) => Method::<S, N>::label(m),
            Self::Taylor(m) => Method::<S, N>::label(m),
        }
    }

    fn run<O: Observer<N>>(
        &self,
        problem: &Problem<'_, S, N>,
        observer: &mut O,
    ) -> Result<Report<N>> {
        match self {
            Self::Rk4(m) => integrate(problem, m, observer),
            Self::Gauss1(m) => integrate(problem, m, observer),
            Self::Gauss2(m) => integrate(problem, m, observer),
            Self::Gauss3(m) => integrate(problem, m, observer),
            Self::Gauss4(m) => integrate(problem, m, observer),
            Self::Gauss5(m) => integrate(problem, m, observer),
            Self::Gauss6(m) => integrate(problem, m, observer),
            Self::Dop853(m) => integrate(problem, m, observer),
            Self::Rk45(m) => integrate(problem, m, observer),
            Self::Taylor(m) => integrate(problem, m, observer),
        }
    }
}

/// A method for a [`Separable`] system `H = T(p) + V(q)`: any [`GeneralMethod`], an explicit
/// splitting or composition method ([`Splitting`]) with a fixed number of steps, or one run in
/// fictitious time under the logarithmic Hamiltonian ([`TimeTransformed`]).
// A Gauss–Legendre variant carries its coefficient tables (a few hundred bytes); method values
// are built once per entry of a sweep, so the size is kept rather than boxed (which would cost
// `Copy`).
#[allow(clippy::large_enum_variant)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AnyMethod {
    /// A method for any Hamiltonian.
    General(GeneralMethod),
    /// An explicit splitting method.
    Splitting(Fixed<Splitting>),
    /// A splitting run in fictitious time under the logarithmic Hamiltonian, with its step `ds`
    /// (adaptive in physical time).
    TimeTransformed(TimeTransformed),
}

impl AnyMethod {
    /// The method `info` describes (one of [`METHODS`](super::METHODS), found by key with
    /// [`MethodInfo::find`]), with `knob` its number of steps (a whole number), for
    /// Dormand–Prince its tolerance (`rtol = atol = knob`), for a time-transformed splitting its
    /// step in fictitious time.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for a method that needs more than a [`Separable`] system
    /// (Wisdom–Holman, SABA/SBAB, the exact flow) or a knob that is not a whole number of
    /// steps; the errors of the constructors for a bad knob value.
    pub fn new(info: &MethodInfo, knob: f64) -> Result<Self> {
        match info.construction {
            Construction::Splitting(table) => {
                Self::of_splitting(Splitting::new(table)?, whole_steps(knob)?)
            }
            Construction::TimeTransformed(table) => {
                TimeTransformed::logarithmic(Splitting::new(table)?, knob)
                    .map(Self::TimeTransformed)
            }
            _ if info.capability() == Capability::Hamiltonian => {
                GeneralMethod::new(info, knob).map(Self::General)
            }
            _ => Err(not_covered(
                info,
                "build it as its typed value (WisdomHolman, ExactStep) under Fixed",
            )),
        }
    }

    /// The method's entry in [`METHODS`](super::METHODS); `None` for a splitting over a table
    /// the crate does not list.
    pub fn info(&self) -> Option<&'static MethodInfo> {
        match self {
            Self::General(m) => Some(m.info()),
            Self::Splitting(m) => MethodInfo::of(Construction::Splitting(m.method.table())),
            Self::TimeTransformed(m) if m.sundman == Sundman::Logarithmic => {
                MethodInfo::of(Construction::TimeTransformed(m.method.table()))
            }
            Self::TimeTransformed(_) => None,
        }
    }

    /// A splitting method with `steps` steps.
    pub fn of_splitting(method: Splitting, steps: usize) -> Result<Self> {
        Ok(Self::Splitting(Fixed::new(method, steps)?))
    }

    /// Störmer–Verlet (kick–drift–kick), 1 stage, order 2, with `steps` steps.
    pub fn verlet(steps: usize) -> Result<Self> {
        Self::of_splitting(Splitting::VERLET_KDK, steps)
    }

    /// Classical Runge–Kutta (4 stages, order 4) with `steps` steps.
    pub fn rk4(steps: usize) -> Result<Self> {
        GeneralMethod::rk4(steps).map(Self::General)
    }

    /// Gauss–Legendre with `stages` stages (`1 … 6`) and `steps` steps.
    pub fn gauss(stages: usize, steps: usize) -> Result<Self> {
        GeneralMethod::gauss(stages, steps).map(Self::General)
    }

    /// Dormand–Prince (12 stages, order 8) with relative and absolute tolerances.
    pub fn dop853(rtol: f64, atol: f64) -> Result<Self> {
        GeneralMethod::dop853(rtol, atol).map(Self::General)
    }

    /// Dormand–Prince 5(4) (6 stages, order 5, SciPy's `RK45` control) with relative and
    /// absolute tolerances.
    pub fn rk45(rtol: f64, atol: f64) -> Result<Self> {
        GeneralMethod::rk45(rtol, atol).map(Self::General)
    }

    /// The order of the method.
    pub fn order(&self) -> u32 {
        match self {
            Self::General(m) => m.order(),
            Self::Splitting(m) => m.method.table().order,
            Self::TimeTransformed(m) => m.method.table().order,
        }
    }

    /// Number of steps of a fixed-step method; `None` for DOP853 and the time-transformed
    /// splittings (fixed steps in fictitious time only).
    pub fn steps(&self) -> Option<usize> {
        match self {
            Self::General(m) => m.steps(),
            Self::Splitting(m) => Some(m.steps),
            Self::TimeTransformed(_) => None,
        }
    }
}

impl From<GeneralMethod> for AnyMethod {
    fn from(m: GeneralMethod) -> Self {
        Self::General(m)
    }
}

impl From<TimeTransformed> for AnyMethod {
    fn from(m: TimeTransformed) -> Self {
        Self::TimeTransformed(m)
    }
}

impl From<Fixed<Splitting>> for AnyMethod {
    fn from(m: Fixed<Splitting>) -> Self {
        Self::Splitting(m)
    }
}

impl<S: Separable<N>, const N: usize> Method<S, N> for AnyMethod {
    fn label(&self) -> String {
        match self {
            Self::General(m) => Method::<S, N>::label(m),
            Self::Splitting(m) => Method::<S, N>::label(m),
            Self::TimeTransformed(m) => Method::<S, N>::label(m),
        }
    }

    fn run<O: Observer<N>>(
        &self,
        problem: &Problem<'_, S, N>,
        observer: &mut O,
    ) -> Result<Report<N>> {
        match self {
            Self::General(m) => integrate(problem, m, observer),
            Self::Splitting(m) => integrate(problem, m, observer),
            Self::TimeTransformed(m) => integrate(problem, m, observer),
        }
    }
}

//! Integration methods as values: one type for the methods that apply to any Hamiltonian
//! ([`GeneralMethod`]) and one that adds the explicit splittings for separable systems
//! ([`AnyMethod`]), so that a list of methods can be built at run time and swept.
//!
//! ```
//! use hamilton_jacobi::integrate::{integrate, AnyMethod, Method, Problem};
//! use hamilton_jacobi::nalgebra::SVector;
//! use hamilton_jacobi::systems::Pendulum;
//! let pendulum = Pendulum::new(1.0).unwrap();
//! let problem = Problem::new(&pendulum, 0.0, SVector::from([1.0]), SVector::from([0.0]), 1.0).unwrap();
//! let methods: Vec<AnyMethod> = vec![
//!     AnyMethod::splitting("Störmer–Verlet (kick–drift–kick)", 100).unwrap(),
//!     AnyMethod::gauss(3, 10).unwrap(),
//!     AnyMethod::rk4(50).unwrap(),
//!     AnyMethod::dop853(1e-12, 1e-14).unwrap(),
//! ];
//! for m in &methods {
//!     let run = integrate(&problem, m, &mut ()).unwrap();
//!     assert_eq!(run.last.t, 1.0, "{}", Method::<Pendulum, 1>::label(m));
//! }
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
//! A front end that keys methods by name (the scene files' `MethodKind` with a knob of steps or
//! tolerance) can map each key to one of these values and run every kind through a single
//! generic `integrate` call per capability, instead of one match arm per method.

use super::{integrate, Dop853, Fixed, Gauss, Method, Observer, Problem, Report, Rk4, Splitting};
use crate::error::{Error, Result};
use crate::hamiltonian::{Hamiltonian, Separable};

/// A method for any [`Hamiltonian`]: RK4, Gauss–Legendre with `s = 1 … 6` stages (order `2s`),
/// or DOP853.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GeneralMethod {
    /// Classical RK4 with a fixed number of steps.
    Rk4(Fixed<Rk4>),
    /// Gauss–Legendre, one stage (implicit midpoint, order 2).
    Gauss1(Fixed<Gauss<1>>),
    /// Gauss–Legendre, two stages (order 4).
    Gauss2(Fixed<Gauss<2>>),
    /// Gauss–Legendre, three stages (order 6).
    Gauss3(Fixed<Gauss<3>>),
    /// Gauss–Legendre, four stages (order 8).
    Gauss4(Fixed<Gauss<4>>),
    /// Gauss–Legendre, five stages (order 10).
    Gauss5(Fixed<Gauss<5>>),
    /// Gauss–Legendre, six stages (order 12).
    Gauss6(Fixed<Gauss<6>>),
    /// DOP853 with its tolerances.
    Dop853(Dop853),
}

impl GeneralMethod {
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

    /// The order of the method (8 for DOP853).
    pub fn order(&self) -> u32 {
        match self {
            Self::Rk4(_) => 4,
            Self::Gauss1(_) => 2,
            Self::Gauss2(_) => 4,
            Self::Gauss3(_) => 6,
            Self::Gauss4(_) => 8,
            Self::Gauss5(_) => 10,
            Self::Gauss6(_) => 12,
            Self::Dop853(_) => 8,
        }
    }

    /// Number of steps of a fixed-step method; `None` for DOP853.
    pub fn steps(&self) -> Option<usize> {
        Some(match self {
            Self::Rk4(m) => m.steps,
            Self::Gauss1(m) => m.steps,
            Self::Gauss2(m) => m.steps,
            Self::Gauss3(m) => m.steps,
            Self::Gauss4(m) => m.steps,
            Self::Gauss5(m) => m.steps,
            Self::Gauss6(m) => m.steps,
            Self::Dop853(_) => return None,
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
        }
    }
}

/// A method for a [`Separable`] system `H = T(p) + V(q)`: any [`GeneralMethod`], or an explicit
/// splitting or composition method ([`Splitting`]) with a fixed number of steps.
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
}

impl AnyMethod {
    /// The splitting method whose table is named `name` (one of
    /// [`Splitting::all`]'s [`Table::name`](super::coefficients::Table)s, e.g.
    /// `"Störmer–Verlet (kick–drift–kick)"`), with `steps` steps; an unknown name is refused with
    /// the list of names.
    pub fn splitting(name: &str, steps: usize) -> Result<Self> {
        let all = Splitting::all();
        match all.iter().find(|m| m.table().name == name) {
            Some(&m) => Ok(Self::Splitting(Fixed::new(m, steps)?)),
            None => Err(Error::invalid(
                "splitting method name",
                format!(
                    "no table named {name:?}; the tables are: {}",
                    all.iter()
                        .map(|m| format!("{:?}", m.table().name))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )),
        }
    }

    /// A splitting method with `steps` steps.
    pub fn of_splitting(method: Splitting, steps: usize) -> Result<Self> {
        Ok(Self::Splitting(Fixed::new(method, steps)?))
    }

    /// Störmer–Verlet (kick–drift–kick) with `steps` steps.
    pub fn verlet(steps: usize) -> Result<Self> {
        Self::of_splitting(Splitting::VERLET_KDK, steps)
    }

    /// RK4 with `steps` steps.
    pub fn rk4(steps: usize) -> Result<Self> {
        GeneralMethod::rk4(steps).map(Self::General)
    }

    /// Gauss–Legendre with `stages` stages (`1 … 6`) and `steps` steps.
    pub fn gauss(stages: usize, steps: usize) -> Result<Self> {
        GeneralMethod::gauss(stages, steps).map(Self::General)
    }

    /// DOP853 with relative and absolute tolerances.
    pub fn dop853(rtol: f64, atol: f64) -> Result<Self> {
        GeneralMethod::dop853(rtol, atol).map(Self::General)
    }

    /// The order of the method.
    pub fn order(&self) -> u32 {
        match self {
            Self::General(m) => m.order(),
            Self::Splitting(m) => m.method.table().order,
        }
    }

    /// Number of steps of a fixed-step method; `None` for DOP853.
    pub fn steps(&self) -> Option<usize> {
        match self {
            Self::General(m) => m.steps(),
            Self::Splitting(m) => Some(m.steps),
        }
    }
}

impl From<GeneralMethod> for AnyMethod {
    fn from(m: GeneralMethod) -> Self {
        Self::General(m)
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
        }
    }
}

#![doc = include_str!("../README.md")]
#![warn(missing_docs)]
#![deny(unsafe_code)]

pub mod action;
pub mod ad;
pub mod brackets;
pub mod chaos;
/// The `hj` command line as a library: [`cli::cli_main`] on a catalogue of systems.
#[cfg(feature = "cli")]
pub mod cli;
pub mod constraints;
pub mod error;
pub mod expression;
pub mod frequency_analysis;
pub mod hamilton_jacobi;
pub mod hamiltonian;
pub mod implicit;
pub mod impulse;
pub mod integrate;
pub mod inverse_problem;
pub mod lagrangian;
pub mod least_action;
pub mod nonholonomic;
pub mod particles;
pub mod perturbation;
pub mod phase;
/// Figures (lines, markers, dots, panels; linear or logarithmic axes) in SVG, PNG and PDF, with
/// the data behind them.
#[cfg(feature = "cli")]
pub mod plot;
pub mod record;
#[cfg(feature = "cli")]
pub mod scene;
pub mod series;
pub mod special;
pub mod stability;
pub mod systems;
pub mod transform;
pub mod vector_space;
pub mod workprecision;

pub use error::{Error, Result};
pub use hamiltonian::{Hamiltonian, Parametric, ParametricSeparable, PhaseFunction, Separable};
pub use lagrangian::{Lagrangian, Legendre, Natural, NaturalHamiltonian, NaturalSystem};
pub use nalgebra;
pub use num_dual;
pub use num_dual::DualNum;
pub use phase::{CanonicalPair, PhaseMatrix, State};

//! Stability of equilibria and steady motions (SPEC M33–M34, M70) for holonomic and
//! non-holonomic systems, from the one definition of the system: equilibria by Newton's method
//! with the AD Jacobian ([`equilibrium`](mod@equilibrium)), the linearisation `η̇ = A η` by AD and the
//! reduction of a steady motion to an equilibrium of the non-cyclic variables ([`linearization`]),
//! the eigenvalues of `A` with the zero eigenvalues of a family of steady motions factored out
//! and reported, and the classification of the rest ([`spectrum`](mod@spectrum)); spectra against
//! a parameter and the parameter values where a real part crosses zero ([`continuation`]); upright
//! rolling of a body of revolution ([`rolling`]).
//!
//! ```text
//! ż = f(t, z)  ──equilibrium──▶  z*  ──linearize──▶  A = ∂f/∂z  ──steady_motion_spectrum──▶
//!     eigenvalues, family of steady motions (reported), transverse eigenvalues → Stability
//! ```
//!
//! A non-holonomic system is linearised in its reduced (constraint-free) variables: the state
//! `(q, ω)` of the Boltzmann–Hamel equations ([`BoltzmannHamel`](crate::nonholonomic::BoltzmannHamel)),
//! with the cyclic coordinates held ([`Reduced`]). Such systems are not Hamiltonian: no spectral
//! symmetry is assumed, and a steady motion may attract part of the variables while the energy is
//! conserved (the Chaplygin sleigh, SPEC X5).
//!
//! Reference: M. D. Ardema, *Analytical Dynamics*, Kluwer/Plenum 2005, ch. 12; G. Hamel,
//! *Theoretische Mechanik*, Springer 1949, art. 243–244.

pub mod continuation;
pub mod equilibrium;
pub mod linearization;
pub mod rolling;
pub mod spectrum;

pub use continuation::{
    parameter_study, real_part_crossings, spectra, Crossing, CrossingKind, ParameterStudy,
    SpectrumAt,
};
pub use equilibrium::{
    equilibrium, hamiltonian_equilibrium, Equilibrium, PhaseEquilibrium, EQUILIBRIUM_TOLERANCE,
};
pub use linearization::{linearize, Reduced, Slot, SplitVectorField};
pub use rolling::{upright_rolling, upright_rolling_spectrum, RollingEquations, UPRIGHT_KEPT};
pub use spectrum::{spectrum, steady_motion_spectrum, Spectrum, Stability, C64};

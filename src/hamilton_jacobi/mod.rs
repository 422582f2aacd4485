//! Hamilton–Jacobi theory [Ardema ch. 17; 8.4, 9.2, 10.1, 15.6]: the Hamilton–Jacobi equation,
//! complete integrals and the motion they generate (Jacobi's theorem); Hamilton's principal
//! function by shooting; separated coordinates
//! reduced to quadratures between turning points; central forces; action–angle variables;
//! Liouville's separable systems; order reduction with the energy integral; Jacobi's last
//! multiplier and the two-degree-of-freedom quadrature.

pub mod action_angle;
pub mod central;
pub mod complete;
pub mod integrals;
pub mod liouville;
pub mod multiplier;
pub mod principal;
pub mod reduction;
pub mod separable;

pub use crate::special::turning_points::{Libration, Node, Quadrature, Radicand, ReducedRadicand};
pub use action_angle::{
    check_natural_form, libration_period, natural_inverse_mass, natural_potential, time_of_flight,
    ActionAngle,
};
pub use central::{central_quadrature, CentralPotential, InverseDistance, RadialMotion};
pub use complete::{completeness, hj_residual, CompleteIntegral, ElementConvention, Elements};
pub use integrals::{KeplerPolarIntegral, OscillatorIntegral, ProjectileIntegral};
pub use liouville::{liouville_separated_integrals, Liouville, LiouvilleSystem};
pub use multiplier::{
    divergence, hamiltonian_divergence, hamiltonian_multiplier_residual, multiplier_residual,
    two_dof_quadrature, variational_flow, ScalarField, TwoDofMomenta, TwoDofQuadrature,
    VariationalFlow, VectorField,
};
pub use principal::{
    principal_function, principal_function_generic, propagate, propagate_fixed, PrincipalError,
    PrincipalFunction, PrincipalOptions, PrincipalValue, Propagation, PropagationOptions,
    StateError,
};
pub use reduction::{ReducedHamiltonian, ReducedRates, Whittaker};
pub use separable::{LiouvilleSeparation, SeparatedMotion, SeparatedSystem};

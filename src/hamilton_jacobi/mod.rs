//! Hamilton–Jacobi theory (SPEC M47, M48, M52–M57): the Hamilton–Jacobi equation, complete
//! integrals and the motion they generate (Jacobi's theorem), separated coordinates reduced to
//! quadratures between turning points, central forces, action–angle variables.

pub mod action_angle;
pub mod central;
pub mod complete;
pub mod integrals;
pub mod quadrature;

pub use action_angle::{libration_period, time_of_flight, ActionAngle, OneDegreeOfFreedom};
pub use central::{central_quadrature, CentralPotential, InverseDistance, RadialMotion};
pub use complete::{completeness, hj_residual, CompleteIntegral, ElementConvention, Elements};
pub use integrals::{KeplerPolarIntegral, OscillatorIntegral, ProjectileIntegral};
pub use quadrature::{Libration, Node, Quadrature, Radicand, ReducedRadicand};

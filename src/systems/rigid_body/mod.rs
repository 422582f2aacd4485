//! Rigid bodies [Ardema ch. 11; Hamel art. 242]: inertia tensors and kinetic energy
//! ([`inertia`]), attitude by 3-1-3 Euler angles and unit quaternions ([`rotation`]), Euler's
//! equations and the free body in canonical form ([`euler`]), the Euler–Poinsot exact flow
//! of its angular momentum and attitude ([`euler_poinsot`]), and the body about a fixed point under gravity
//! ([`heavy`]), of which the heavy symmetric top of [`crate::systems::HeavyTop`] is Lagrange's
//! case.
//!
//! The Lie–Poisson integrator of the free body lives with the integrators
//! ([`crate::integrate::lie_poisson`]).

pub mod euler;
pub mod euler_poinsot;
pub mod heavy;
pub mod inertia;
pub mod rotation;

pub use euler::{
    euler_jacobian, euler_rhs, euler_rhs_generic, gyroscopic_moment, intermediate_axis_growth_rate,
    FreeRigidBody,
};
pub use euler_poinsot::{EulerPoinsot, Regime};
pub use heavy::{vertical_in_body, HeavyRigidBody};
pub use inertia::{koenig_t, rod_kinetic_energy, InertiaTensor, PrincipalAxes};
pub use rotation::{
    check_chart, euler313_body_rates, euler313_from_quaternion, euler313_matrix, euler313_rates,
    euler313_rotation_matrix, quaternion_from_euler313, BodyAngularVelocity,
};

//! The systems catalogue: each system with its Hamiltonian (or Lagrangian), its known invariants and,
//! where one exists, its exact solution. Tests, examples, benchmarks and the CLI all reuse these.
//!
//! | system | degrees of freedom | exact solution |
//! |---|---|---|
//! | [`HarmonicOscillator`] | 1 | closed form, generic over the dual type |
//! | [`Pendulum`] | 1 | Jacobi elliptic functions + AGM, up to the separatrix |
//! | [`Kepler2`], [`Kepler3`] | 2, 3 | universal-variable flow, every conic; element sets ([`kepler`]; Ardema 10.2–10.3) |
//! | [`Projectile`] | 2 | closed form |
//! | [`BeadOnHoop`] | 1 (Lagrangian) | — (Jacobi integral [Ardema 8.2]) |
//! | [`FreeRigidBody`] | 3 | Euler–Poinsot: the body angular momentum in Jacobi elliptic functions ([`rigid_body::euler_poinsot`]) [Landau & Lifshitz §37] |
//! | [`ChaplyginSleigh`] | 3, one non-holonomic constraint | force-free closed form [Hamel art. 238] |
//! | [`TwoWheeledCart`] | 5, three constraints (one integrable) | — [Hamel art. 239] |
//! | [`RollingDisk`] | 5, two non-holonomic constraints | — (upright stability threshold) [Hamel art. 244] |
//! | [`Gearing`], [`GearingInTime`] | 2, one rheonomic constraint | `½(I₁f² + I₂)φ̇₂²` conserved [Hamel art. 240] |
//! | [`HamelVelocityParameters`] | 2 (holonomic, non-holonomic ω) | `ω₁ = c sech ct`, `ω₂ = −c tanh ct` [Hamel art. 241] |
//! | [`ConeConstraint`] | 3, constraint non-linear in ẋ | closed form up to the vertex [Hamel art. 249] |
//! | [`SecondClassConstraint`] | 3, acceleration constraint | Gauss's stationary points [Hamel art. 252] |
//! | [`HingedRods`] | N (normal velocities of the joints) | impulsive response `(52, −14, 4, −2)P/(15M)` for three rods [Ardema 13.3] |
//! | [`SphereOnTurntable`], [`SphereOnTurntableInTime`] | 5, two rheonomic rolling constraints | force-free circle at the rate `ΩI/(I + Ma²)` [Ardema 14.4] |
//! | [`ArealVelocity`] | 2, areal quasi-coordinate | Gibbs function; Kepler's second law [Ardema 14.4] |
//! | [`RodOnCircle`] | 3, two holonomic constraints | a pendulum, `(c² + a²/3)θ̈ + gc sin θ = 0` [Ardema 14.4] |
//! | [`FoldedRope`] | 2 (Lagrangian) | straightening time and `t(μ)` in closed form; finite-time blow-up of `μ̇` [Ardema 9.3] |
//! | [`HeavyTop`] | 3 | Hamilton–Jacobi quadratures of the cubic ([`top::motion`]) [Ardema 17.5] |
//! | [`Particle`] in [`Cylindrical`], [`Spherical`] coordinates | 3 (applied force in Cartesian components) | Ardema's component equations [Ardema 7.2–7.3] |
//! | [`Particle`] [`OnCurve`] | 1, on a fixed or moving plane curve `y = f(x, t)` | Ardema eq. 7.14 [Ardema 7.3] |
//! | [`DoublePendulum`] | 2 (two rods; point masses the special case) | — (equilibria and their spectra in closed form) [Ardema 7.4, 12.3] |
//! | [`PlanetarySystem`] | 3(n + 1): a central mass and n planets | — (momentum, angular momentum, energy; Wisdom–Holman splits in Jacobi and democratic heliocentric coordinates) [Wisdom & Holman 1991] |
//! | [`RestrictedThreeBody`] | 2 (planar), 3 | — (Jacobi integral; L4 stable below Routh's ratio) [Szebehely §4.4] |
//! | [`ClohessyWiltshire`] | 3, quadratic | closed form (Hill's equations) [Ardema 12.4] |
//! | [`DumbbellSatellite`] | 3, `ρ` cyclic | relative equilibria, radial and tangential [Ardema 15.3] |

use crate::error::Result;
use nalgebra::SVector;

mod areal;
mod bead;
mod cart;
mod central;
pub mod clohessy_wiltshire;
mod cone_constraint;
pub mod double_pendulum;
pub mod dumbbell;
mod folded_rope;
mod gearing;
mod harmonic;
pub mod henon_heiles;
pub mod hinged_rods;
pub mod kepler;
mod nonholonomic_particle;
pub mod particle_formulations;
mod pendulum;
pub mod pendulum_exact;
pub mod planetary;
mod projectile;
pub mod restricted_three_body;
pub mod rigid_body;
mod rod_on_circle;
mod rolling_disk;
mod sleigh;
pub mod top;
mod turntable;
mod velocity_parameters;

pub use areal::ArealVelocity;
pub use bead::BeadOnHoop;
pub use cart::TwoWheeledCart;
pub use central::{Central, CentralPotential, InverseDistance};
pub use clohessy_wiltshire::ClohessyWiltshire;
pub use cone_constraint::{ConeConstraint, SecondClassConstraint};
pub use double_pendulum::{DoublePendulum, Rod};
pub use dumbbell::{DumbbellOrientation, DumbbellSatellite};
pub use folded_rope::FoldedRope;
pub use gearing::{Gearing, GearingInTime};
pub use harmonic::{HarmonicFlow, HarmonicOscillator};
pub use henon_heiles::HenonHeiles;
pub use hinged_rods::HingedRods;
pub use kepler::{AngularMomentum, Kepler, Kepler2, Kepler3};
pub use nonholonomic_particle::NonholonomicParticle;
pub use particle_formulations::{
    CartesianForce, ConstantForce, Coordinates, Cylindrical, OnCurve, Particle, PlaneCurve,
    Spherical,
};
pub use pendulum::Pendulum;
pub use planetary::{outer_solar_system, PlanetaryCoordinates, PlanetarySystem};
pub use projectile::Projectile;
pub use restricted_three_body::RestrictedThreeBody;
pub use rigid_body::FreeRigidBody;
pub use rod_on_circle::RodOnCircle;
pub use rolling_disk::RollingDisk;
pub use sleigh::ChaplyginSleigh;
pub use top::{HeavyTop, SteadyPrecession};
pub use turntable::{SphereOnTurntable, SphereOnTurntableInTime};
pub use velocity_parameters::HamelVelocityParameters;

/// A named conserved quantity and its value at a phase point.
#[derive(Clone, Debug, PartialEq)]
pub struct Invariant {
    /// Name, e.g. `"energy"`, `"h_z"`.
    pub name: &'static str,
    /// Value.
    pub value: f64,
}

/// Systems that know their conserved quantities.
pub trait Invariants<const N: usize> {
    /// Values of all known invariants at `(t, q, p)`.
    fn invariants(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<Vec<Invariant>>;
}

/// Systems whose motion is known in closed form.
pub trait ExactFlow<const N: usize> {
    /// The state at time `t` of the motion that passes through `(q0, p0)` at time `t0`.
    fn exact_flow(
        &self,
        t0: f64,
        q0: &SVector<f64, N>,
        p0: &SVector<f64, N>,
        t: f64,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)>;
}

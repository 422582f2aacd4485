//! Upright rolling of a thin body of revolution on a horizontal plane (SPEC M70, T17): the
//! reduced equations about the steady motion and their spectrum against the forward speed.
//!
//! The Boltzmann–Hamel equations of [`RollingDisk`] in its own quasi-velocities (the body as
//! both the Lagrangian and the quasi-velocities) are linearised about upright rolling at speed
//! `v`, `ψ = 0`, `ω = (0, 0, 0, 0, v/r)` (`φ̇ = v/r`): the coordinates `x, y, ϑ, φ` are cyclic and held, the
//! lean `ψ` and the free quasi-velocities `(ϑ̇, ψ̇, φ̇)` are kept. Steady rolling at every speed
//! and steady turning at constant lean give the double zero of the family (reported, not
//! classified); the transverse pair is `±√(−a²)`, `a² = (BD − AF)/(AE)` [Hamel art. 243–244].

use super::linearization::{Reduced, Slot};
use super::spectrum::{steady_motion_spectrum, Spectrum};
use crate::error::Result;
use crate::nalgebra::SVector;
use crate::nonholonomic::BoltzmannHamel;
use crate::systems::RollingDisk;

/// The Boltzmann–Hamel equations of the rolling body in its own quasi-velocities.
pub type RollingEquations = BoltzmannHamel<RollingDisk, RollingDisk, 5>;

/// The variables kept about upright rolling: the lean `ψ` and the quasi-velocities
/// `(ϑ̇, ψ̇, φ̇)`.
pub const UPRIGHT_KEPT: [Slot; 4] = [Slot::Q(3), Slot::P(2), Slot::P(3), Slot::P(4)];

/// The reduced equations of `equations` about upright rolling at speed `v` (see the
/// [module docs](self)).
///
/// # Errors
/// [`Error::NonFinite`](crate::Error::NonFinite) for NaN/∞ `v`; the errors of [`Reduced::new`].
pub fn upright_rolling(
    equations: &RollingEquations,
    v: f64,
) -> Result<Reduced<'_, RollingEquations, 5, 4>> {
    let v = crate::error::finite("speed v", v)?;
    let roll = crate::error::finite("roll rate v/r", v / equations.quasi.radius())?;
    let omega = SVector::<f64, 5>::from([0.0, 0.0, 0.0, 0.0, roll]);
    Reduced::new(equations, &SVector::zeros(), &omega, UPRIGHT_KEPT)
}

/// The spectrum of upright rolling of `body` at speed `v`: the double zero of the family of
/// steady motions factored out, the transverse pair `±√(−a²)` classified.
///
/// # Errors
/// As [`upright_rolling`] and [`steady_motion_spectrum`].
pub fn upright_rolling_spectrum(body: RollingDisk, v: f64) -> Result<Spectrum> {
    let equations = BoltzmannHamel::new(body, body);
    let reduced = upright_rolling(&equations, v)?;
    steady_motion_spectrum(&reduced, 0.0, &reduced.state())
}

use crate::constraints::PfaffianConstraints;
#[cfg(doc)]
use crate::error::Error;
use crate::error::{all_finite, finite, positive, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// The non-holonomic particle [Bloch, *Nonholonomic Mechanics and Control*, 2nd ed., §1.4;
/// McLachlan & Perlmutter 2006, §6] in a magnetic field, an integrable non-holonomic system that
/// is not reversible under `(q, q̇) ↦ (q, −q̇)`, in the spirit of the non-reversible test problems
/// of Modin & Verdier, Numer. Math. 145 (2020) 405–435, §5:
///
/// ```math
/// L = \tfrac12(\dot x^2 + \dot y^2 + \dot z^2) + B\,x\,\dot y - V(y),\qquad
/// V(y) = \tfrac12\kappa y^2 + k y,\qquad \dot z = y\,\dot x .
/// ```
///
/// The field `B` (vector potential `(0, B x, 0)`) does no work: the energy
/// `E = ½(ẋ² + ẏ² + ż²) + V(y)` is conserved. The `x`-equation `(1 + y²) ẍ = B ẏ − y ẋ ẏ` gives
/// `d/dt(√(1 + y²) ẋ) = B ẏ/√(1 + y²)`, whence the first integral
/// `I = √(1 + y²) ẋ − B arsinh y`; with `E` it makes the reduced motion in `(y, ẋ, ẏ)` integrable
/// (`y` moves in the effective potential `½(I + B arsinh y)² + V(y)`). For `B ≠ 0` the magnetic
/// term is odd in the velocities, so the motion is not reversible under the velocity flip
/// (nor, for `k ≠ 0`, under `(y, ẋ, ż) ↦ (−y, −ẋ, ż)`), the reversibility behind the bounded
/// energy errors of non-holonomic integrators on the classical test problems; a reversing
/// symmetry `(x, y, z; ẋ, ẏ, ż) ↦ (−x, y, −z; ẋ, −ẏ, ż)` remains.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NonholonomicParticle {
    b: f64,
    kappa: f64,
    k: f64,
}

impl NonholonomicParticle {
    /// The particle in the field `B` with the potential `V = ½κy² + k y`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ parameters; [`Error::OutOfDomain`] for `κ ≤ 0` (the
    /// motion in `y` would not be bounded).
    pub fn new(b: f64, kappa: f64, k: f64) -> Result<Self> {
        Ok(Self {
            b: finite("field B", b)?,
            kappa: positive("stiffness κ", kappa)?,
            k: finite("load k", k)?,
        })
    }

    /// The energy `E = ½(ẋ² + ẏ² + ż²) + ½κy² + k y`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or value.
    pub fn energy(&self, q: &SVector<f64, 3>, qdot: &SVector<f64, 3>) -> Result<f64> {
        let y = checked_y(q, qdot)?;
        finite(
            "energy",
            0.5 * qdot.norm_squared() + 0.5 * self.kappa * y * y + self.k * y,
        )
    }

    /// The first integral `I = √(1 + y²) ẋ − B arsinh y`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or value.
    pub fn first_integral(&self, q: &SVector<f64, 3>, qdot: &SVector<f64, 3>) -> Result<f64> {
        let y = checked_y(q, qdot)?;
        finite(
            "first integral √(1 + y²) ẋ − B arsinh y",
            (1.0 + y * y).sqrt() * qdot[0] - self.b * y.asinh(),
        )
    }
}

/// `y` of a finite state `(q, q̇)`.
fn checked_y(q: &SVector<f64, 3>, qdot: &SVector<f64, 3>) -> Result<f64> {
    all_finite("q", q.as_slice())?;
    all_finite("q̇", qdot.as_slice())?;
    Ok(q[1])
}

impl Lagrangian<3> for NonholonomicParticle {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 3>, v: &SVector<D, 3>) -> D {
        let y = q[1];
        (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * 0.5 + q[0] * v[1] * self.b
            - y * y * (0.5 * self.kappa)
            - y * self.k
    }
}

impl PfaffianConstraints<3, 1> for NonholonomicParticle {
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
    ) -> (SMatrix<D, 1, 3>, SVector<D, 1>) {
        (
            SMatrix::from_row_slice(&[-q[1], D::zero(), D::one()]),
            SVector::zeros(),
        )
    }
}

use crate::constraints::{PfaffianConstraints, QuasiVelocities};
#[cfg(doc)]
use crate::error::Error;
use crate::error::{all_finite, finite, positive, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// The non-holonomic particle [Bloch, *Nonholonomic Mechanics and Control*, 2nd ed., §1.4;
/// McLachlan & Perlmutter 2006, §6] in a magnetic field, an integrable non-holonomic system that
/// is not reversible under `(q, q̇) ↦ (q, −q̇)`, after the non-reversible integrable test problems
/// of Modin & Verdier, "What makes nonholonomic integrators work?", Numer. Math. 145 (2020)
/// 405–435. In the Cartesian coordinates `(x, y, z)`
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
/// energy errors of non-holonomic integrators on the classical test problems; the linear
/// reversing symmetry `(x, y, z; ẋ, ẏ, ż) ↦ (−x, y, −z; ẋ, −ẏ, ż)` remains, and an integrator
/// that commutes with linear changes of coordinates (the midpoint discrete Lagrange–d'Alembert
/// scheme) inherits it.
///
/// **Sheared coordinates** ([`NonholonomicParticle::with_shear`]): the same motion in the
/// coordinates `q = (u, y, z)`, `x = u + c(y)`, `c(y) = ½σy² + ⅓τy³`, so that
/// `ẋ = u̇ + c′(y) ẏ` with `c′(y) = σy + τy²`, the constraint reads `ż = y u̇ + y c′(y) ẏ` and
///
/// ```math
/// L = \tfrac12\big((\dot u + c'(y) \dot y)^2 + \dot y^2 + \dot z^2\big)
/// + B\,(u + c(y))\,\dot y - V(y).
/// ```
///
/// `E` and `I` are unchanged as functions of the motion. For `c ≠ 0, B ≠ 0, k ≠ 0` no linear map
/// of `(u, y, z)` is a reversing symmetry (the coupling `c′(y) u̇ ẏ` is odd under `ẏ ↦ −ẏ` with
/// `u̇` fixed, the magnetic term under `u̇ ↦ −u̇` with `u` fixed); the reversing symmetry of the
/// motion is the non-linear map `ρ(u, y, z) = (−u − 2c(y), y, −z)`: the problem is integrable and
/// not reversible under the standard maps, the construction of the test problems of Modin &
/// Verdier (2020); it is reversible in disguise for a scheme that inherits `ρ`. For the midpoint
/// discrete Lagrange–d'Alembert scheme the kinetic part decides: with `τ = 0` its discrete
/// velocity `(u₁ − u₀)/h + c′(ȳ)(y₁ − y₀)/h` is exactly `ρ`-invariant, since
/// `y₁² − y₀² = 2ȳ(y₁ − y₀)`, and its energy error stays bounded; with `τ ≠ 0`,
/// `y₁³ − y₀³ = (y₁ − y₀)(3ȳ² + ¼(y₁ − y₀)²)` leaves in it an `O(h²)` term odd under reversal,
/// and its energy error drifts linearly, at a rate `∝ h²` (measured in
/// `tests/constrained_integration.rs`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NonholonomicParticle {
    b: f64,
    kappa: f64,
    k: f64,
    sigma: f64,
    tau: f64,
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
            sigma: 0.0,
            tau: 0.0,
        })
    }

    /// The same particle in the sheared coordinates `(u, y, z)`, `x = u + ½σy² + ⅓τy³` (see the
    /// type's docs); `σ = τ = 0` gives the Cartesian coordinates.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ `σ` or `τ`.
    pub fn with_shear(self, sigma: f64, tau: f64) -> Result<Self> {
        Ok(Self {
            sigma: finite("shear σ", sigma)?,
            tau: finite("shear τ", tau)?,
            ..self
        })
    }

    /// The shear `(σ, τ)` of the coordinates (`x = u + ½σy² + ⅓τy³`).
    pub fn shear(&self) -> (f64, f64) {
        (self.sigma, self.tau)
    }

    /// `c(y) = ½σy² + ⅓τy³` and `c′(y) = σy + τy²`, over any dual type.
    fn chart<D: DualNum<f64> + Copy>(&self, y: D) -> (D, D) {
        (
            y * y * (y * (self.tau / 3.0) + 0.5 * self.sigma),
            y * (y * self.tau + self.sigma),
        )
    }

    /// `ẋ = u̇ + c′(y) ẏ` at `(q, q̇)`.
    fn x_velocity(&self, q: &SVector<f64, 3>, qdot: &SVector<f64, 3>) -> f64 {
        qdot[0] + self.chart(q[1]).1 * qdot[1]
    }

    /// The energy `E = ½(ẋ² + ẏ² + ż²) + ½κy² + k y` (`ẋ = u̇ + c′(y) ẏ` in sheared coordinates).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or value.
    pub fn energy(&self, q: &SVector<f64, 3>, qdot: &SVector<f64, 3>) -> Result<f64> {
        let y = checked_y(q, qdot)?;
        let xd = self.x_velocity(q, qdot);
        finite(
            "energy",
            0.5 * (xd * xd + qdot[1] * qdot[1] + qdot[2] * qdot[2])
                + 0.5 * self.kappa * y * y
                + self.k * y,
        )
    }

    /// The first integral `I = √(1 + y²) ẋ − B arsinh y` (`ẋ = u̇ + c′(y) ẏ` in sheared
    /// coordinates).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or value.
    pub fn first_integral(&self, q: &SVector<f64, 3>, qdot: &SVector<f64, 3>) -> Result<f64> {
        let y = checked_y(q, qdot)?;
        finite(
            "first integral √(1 + y²) ẋ − B arsinh y",
            (1.0 + y * y).sqrt() * self.x_velocity(q, qdot) - self.b * y.asinh(),
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
        let (c, dc) = self.chart(y);
        let x = q[0] + c;
        let xd = v[0] + dc * v[1];
        (xd * xd + v[1] * v[1] + v[2] * v[2]) * 0.5 + x * v[1] * self.b
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
        let y = q[1];
        (
            SMatrix::from_row_slice(&[-y, -y * self.chart(y).1, D::one()]),
            SVector::zeros(),
        )
    }
}

/// The quasi-velocities `ω = (ż − y ẋ, u̇, ẏ)` (`ẋ = u̇ + c′(y) ẏ`), the first constrained, for
/// the Boltzmann–Hamel and Gibbs–Appell forms; `det b = 1`.
impl QuasiVelocities<3> for NonholonomicParticle {
    fn constrained(&self) -> usize {
        1
    }
    fn matrix<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        let y = q[1];
        let (o, z) = (D::one(), D::zero());
        SMatrix::from_row_slice(&[-y, -y * self.chart(y).1, o, o, z, z, z, o, z])
    }
}

//! The plane double pendulum of two rods [Ardema 7.4, eqs. 7.17–7.26; 12.3, eq. 12.16] (SPEC M21,
//! T27). Rod 1 is pivoted at A, rod 2 is hinged to the end of rod 1 at the distance `ℓ₁` from A;
//! `θ₁`, `θ₂` are the absolute angles of the rods from the downward vertical, `ℓ̄ᵢ` the distance
//! from rod i's joint to its mass centre, `Īᵢ` its central moment of inertia, `g` gravity:
//!
//! ```text
//! T = ½ I₁′ θ̇₁² + ½ I₂′ θ̇₂² + A θ̇₁ θ̇₂ cos(θ₂ − θ₁),
//! I₁′ = Ī₁ + m₁ ℓ̄₁² + m₂ ℓ₁²,   I₂′ = Ī₂ + m₂ ℓ̄₂²,   A = m₂ ℓ₁ ℓ̄₂,
//! V = −B cos θ₁ − C cos θ₂,      B = (m₁ ℓ̄₁ + m₂ ℓ₁) g,   C = m₂ g ℓ̄₂,
//! ```
//!
//! so that Lagrange's equations are
//!
//! ```text
//! I₁′ θ̈₁ + A θ̈₂ cos(θ₂ − θ₁) − A θ̇₂² sin(θ₂ − θ₁) + B sin θ₁ = 0,
//! I₂′ θ̈₂ + A θ̈₁ cos(θ₂ − θ₁) + A θ̇₁² sin(θ₂ − θ₁) + C sin θ₂ = 0.
//! ```
//!
//! Point masses on massless rods are the case `Īᵢ = 0`, `ℓ̄ᵢ = ℓᵢ` ([`DoublePendulum::new`];
//! Landau & Lifshitz, *Mechanics*, §5 Prob. 1). The system is a [`NaturalSystem`] (`T` and `V`
//! written once); [`Natural`](crate::Natural) gives its Lagrangian, and its [`Hamiltonian`] is the
//! closed-form Legendre transform `H = ½ pᵀ a⁻¹ p + V` [Ardema eq. 15.8] of that `a` and `V`.
//!
//! Its equilibria are `(0, 0)`, `(π, 0)`, `(0, π)`, `(π, π)`. With `sᵢ = cos θᵢ = ±1` there, the
//! eigenvalues `λ` of the linearisation solve
//! `(I₁′I₂′ − A²) λ⁴ + (B s₁ I₂′ + C s₂ I₁′) λ² + B C s₁ s₂ = 0`; for equal point masses and
//! lengths and `g/ℓ = 1` they are `±i√(2 ± √2)` at `(0, 0)`, `λ² = ±√2` at `(π, 0)` and `(0, π)`,
//! `±√(2 ± √2)` at `(π, π)` (SPEC T27).

use crate::error::{finite, non_negative, positive, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::lagrangian::NaturalSystem;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// One rod of a [`DoublePendulum`]: mass `m`, joint-to-joint length `ℓ` (only rod 1's enters),
/// distance `ℓ̄` from the (upper) joint to the mass centre, central moment of inertia `Ī`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rod {
    mass: f64,
    length: f64,
    centre: f64,
    central_moment: f64,
}

impl Rod {
    /// A rod of mass `m > 0`, length `ℓ > 0`, mass centre at `ℓ̄ ≥ 0` from its upper joint and
    /// central moment of inertia `Ī ≥ 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞, [`Error::OutOfDomain`] for a parameter outside its domain.
    pub fn new(mass: f64, length: f64, centre: f64, central_moment: f64) -> Result<Self> {
        Ok(Self {
            mass: positive("rod mass m", mass)?,
            length: positive("rod length ℓ", length)?,
            centre: non_negative("rod mass-centre distance ℓ̄", centre)?,
            central_moment: non_negative("rod central moment Ī", central_moment)?,
        })
    }

    /// A uniform slender rod: `ℓ̄ = ℓ/2`, `Ī = mℓ²/12`.
    ///
    /// # Errors
    /// As [`Rod::new`].
    pub fn uniform(mass: f64, length: f64) -> Result<Self> {
        let length = positive("rod length ℓ", length)?;
        let moment = finite("rod central moment mℓ²/12", mass * length * length / 12.0)?;
        Self::new(mass, length, 0.5 * length, moment.max(0.0))
    }

    /// A point mass `m` at the end of a massless rod of length `ℓ`: `ℓ̄ = ℓ`, `Ī = 0`.
    ///
    /// # Errors
    /// As [`Rod::new`].
    pub fn point_mass(mass: f64, length: f64) -> Result<Self> {
        Self::new(mass, length, length, 0.0)
    }

    /// The moment of inertia `Ī + m ℓ̄²` about the upper joint (parallel axes).
    pub fn moment_about_joint(&self) -> f64 {
        self.central_moment + self.mass * self.centre * self.centre
    }
}

/// The double pendulum of two rods (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DoublePendulum {
    /// `I₁′`, `I₂′`, `A`, `B`, `C` of the module docs.
    i1: f64,
    i2: f64,
    a: f64,
    b: f64,
    c: f64,
    /// `I₁′I₂′ − A²`.
    det: f64,
}

impl DoublePendulum {
    /// Point masses `m₁, m₂ > 0` on massless rods of lengths `ℓ₁, ℓ₂ > 0`, gravity `g > 0`
    /// (`Īᵢ = 0`, `ℓ̄ᵢ = ℓᵢ`).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞, [`Error::OutOfDomain`] for a non-positive parameter or a
    /// mass matrix that overflows.
    pub fn new(m1: f64, m2: f64, l1: f64, l2: f64, g: f64) -> Result<Self> {
        Self::rods(Rod::point_mass(m1, l1)?, Rod::point_mass(m2, l2)?, g)
    }

    /// Rod 1 pivoted at A, rod 2 hinged to its end, gravity `g > 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite `g` or coefficient, [`Error::OutOfDomain`] for
    /// `g ≤ 0` or a singular mass matrix (`I₂′ = 0`, or rod 1 without moment about A while
    /// `Ī₂ = 0`).
    pub fn rods(rod1: Rod, rod2: Rod, g: f64) -> Result<Self> {
        let g = positive("gravity g", g)?;
        let own1 = rod1.moment_about_joint();
        let i2 = finite("I₂′ = Ī₂ + m₂ℓ̄₂²", rod2.moment_about_joint())?;
        let i1 = finite(
            "I₁′ = I₁,A + m₂ℓ₁²",
            own1 + rod2.mass * rod1.length * rod1.length,
        )?;
        let a = finite("A = m₂ℓ₁ℓ̄₂", rod2.mass * rod1.length * rod2.centre)?;
        let b = finite(
            "B = (m₁ℓ̄₁ + m₂ℓ₁)g",
            (rod1.mass * rod1.centre + rod2.mass * rod1.length) * g,
        )?;
        let c = finite("C = m₂gℓ̄₂", rod2.mass * g * rod2.centre)?;
        // I₁′I₂′ − A² = I₁,A I₂′ + m₂ℓ₁² Ī₂, free of cancellation.
        let det = own1 * i2 + rod2.mass * rod1.length * rod1.length * rod2.central_moment;
        if !(i2 > 0.0 && det > 0.0 && det.is_finite()) {
            return Err(Error::out_of_domain(
                "mass-matrix determinant I₁′I₂′ − A² of the double pendulum",
                det,
                "(0, ∞) (rod 2 needs a moment about its joint, and rod 1 one about A or Ī₂ > 0)",
            ));
        }
        Ok(Self {
            i1,
            i2,
            a,
            b,
            c,
            det,
        })
    }

    /// The coefficients `[I₁′, I₂′, A, B, C]` of the module docs.
    pub fn coefficients(&self) -> [f64; 5] {
        [self.i1, self.i2, self.a, self.b, self.c]
    }

    /// The four equilibria `(0, 0)`, `(π, 0)`, `(0, π)`, `(π, π)` (coordinates; momenta zero).
    pub fn equilibria() -> [SVector<f64, 2>; 4] {
        use std::f64::consts::PI;
        [
            SVector::from([0.0, 0.0]),
            SVector::from([PI, 0.0]),
            SVector::from([0.0, PI]),
            SVector::from([PI, PI]),
        ]
    }
}

impl NaturalSystem<2> for DoublePendulum {
    /// `a = [[I₁′, A cos(θ₂ − θ₁)], [A cos(θ₂ − θ₁), I₂′]]`.
    fn mass<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        let k = (q[1] - q[0]).cos() * self.a;
        SMatrix::<D, 2, 2>::new(D::from(self.i1), k, k, D::from(self.i2))
    }
    /// `V = −B cos θ₁ − C cos θ₂`.
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> D {
        -(q[0].cos() * self.b + q[1].cos() * self.c)
    }
}

impl Hamiltonian<2> for DoublePendulum {
    /// `H = ½ pᵀ a⁻¹ p + V` with the 2 × 2 inverse written out,
    /// `H = (I₂′ p₁² + I₁′ p₂² − 2 A cos(θ₂ − θ₁) p₁ p₂) / (2 det a) + V`, and
    /// `det a = (I₁′I₂′ − A²) + A² sin²(θ₂ − θ₁)` free of cancellation.
    fn hamiltonian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 2>, p: &SVector<D, 2>) -> D {
        let a = self.mass(t, q);
        let s = (q[1] - q[0]).sin() * self.a;
        let det = s * s + self.det;
        (p[0] * p[0] * a[(1, 1)] + p[1] * p[1] * a[(0, 0)] - p[0] * p[1] * a[(0, 1)] * 2.0)
            / (det * 2.0)
            + self.potential(t, q)
    }
}

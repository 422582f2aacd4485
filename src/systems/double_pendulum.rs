//! The plane double pendulum of two point masses on massless rods [Ardema 12.3, eq. 12.16;
//! Landau & Lifshitz, *Mechanics*, §5 Prob. 1] (SPEC T27): masses `m₁`, `m₂` on rods of lengths
//! `ℓ₁`, `ℓ₂`, angles `q₁`, `q₂` from the downward vertical, gravity `g`. With `Δ = q₁ − q₂`,
//!
//! ```text
//! T = ½ (m₁ + m₂) ℓ₁² q̇₁² + ½ m₂ ℓ₂² q̇₂² + m₂ ℓ₁ ℓ₂ cos Δ q̇₁ q̇₂,
//! V = −(m₁ + m₂) g ℓ₁ cos q₁ − m₂ g ℓ₂ cos q₂,
//! H = [m₂ ℓ₂² p₁² + (m₁ + m₂) ℓ₁² p₂² − 2 m₂ ℓ₁ ℓ₂ cos Δ p₁ p₂] / [2 m₂ ℓ₁² ℓ₂² (m₁ + m₂ sin² Δ)] + V.
//! ```
//!
//! Its equilibria are `(0, 0)`, `(π, 0)`, `(0, π)`, `(π, π)`; for equal masses and lengths and
//! `g/ℓ = 1` the eigenvalues of the linearisation are `±i√(2 ± √2)` at `(0, 0)`, `λ² = ±√2` at
//! `(π, 0)` and `(0, π)`, `±√(2 ± √2)` at `(π, π)`.

use crate::error::{positive, Result};
use crate::hamiltonian::Hamiltonian;
use nalgebra::SVector;
use num_dual::DualNum;

/// The double pendulum of point masses (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DoublePendulum {
    m1: f64,
    m2: f64,
    l1: f64,
    l2: f64,
    g: f64,
}

impl DoublePendulum {
    /// Masses `m₁, m₂ > 0`, lengths `ℓ₁, ℓ₂ > 0`, gravity `g > 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`](crate::Error::NonFinite) for NaN/∞,
    /// [`Error::OutOfDomain`](crate::Error::OutOfDomain) for a non-positive parameter.
    pub fn new(m1: f64, m2: f64, l1: f64, l2: f64, g: f64) -> Result<Self> {
        Ok(Self {
            m1: positive("mass m₁", m1)?,
            m2: positive("mass m₂", m2)?,
            l1: positive("length ℓ₁", l1)?,
            l2: positive("length ℓ₂", l2)?,
            g: positive("gravity g", g)?,
        })
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

impl Hamiltonian<2> for DoublePendulum {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 2>,
        p: &SVector<D, 2>,
    ) -> D {
        let (m1, m2, l1, l2, g) = (self.m1, self.m2, self.l1, self.l2, self.g);
        let (s, c) = (q[0] - q[1]).sin_cos();
        let kinetic = (p[0] * p[0] * (m2 * l2 * l2) + p[1] * p[1] * ((m1 + m2) * l1 * l1)
            - p[0] * p[1] * c * (2.0 * m2 * l1 * l2))
            / ((s * s * m2 + m1) * (2.0 * m2 * l1 * l1 * l2 * l2));
        kinetic - q[0].cos() * ((m1 + m2) * g * l1) - q[1].cos() * (m2 * g * l2)
    }
}

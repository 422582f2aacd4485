use crate::constraints::QuasiVelocities;
#[cfg(doc)]
use crate::error::Error;
use crate::error::{finite, positive, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// A particle of mass `m` in the plane, in polar coordinates `(r, θ)`, attracted by the potential
/// `V = −μm/r` and driven by a constant radial force `R₀` and a constant transverse force `S`,
/// described with the areal quasi-coordinate `q`, `q̇ = xẏ − yẋ = r²θ̇` [Ardema 14.4] (SPEC T33):
/// quasi-velocities `ω = (ṙ, r²θ̇)`, none constrained. The Gibbs function is exactly
///
/// ```math
/// G = \tfrac12 m\Big[\Big(\ddot r - \frac{\dot q^2}{r^3}\Big)^2 + \frac{\ddot q^2}{r^2}\Big],
/// \qquad m\Big(\ddot r - \frac{\dot q^2}{r^3}\Big) = R,\quad \frac{m\ddot q}{r^2} = \frac{S}{r}
/// ```
///
/// with `R = R₀ − μm/r²` ([`ArealVelocity::gibbs_function`]); for `S = 0` the areal velocity `q̇`
/// is constant (Kepler's second law).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ArealVelocity {
    mass: f64,
    mu: f64,
    radial: f64,
    transverse: f64,
}

impl ArealVelocity {
    /// Particle of mass `m > 0` in the potential `−μm/r` (`μ ≥ 0`), no other forces.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::OutOfDomain`] for NaN/∞, `m ≤ 0` or `μ < 0`.
    pub fn new(mass: f64, mu: f64) -> Result<Self> {
        let mu = finite("gravitational parameter μ", mu)?;
        if mu < 0.0 {
            return Err(crate::error::Error::out_of_domain(
                "gravitational parameter μ",
                mu,
                "[0, ∞)",
            ));
        }
        Ok(Self {
            mass: positive("mass m", mass)?,
            mu,
            radial: 0.0,
            transverse: 0.0,
        })
    }

    /// The same particle under the constant radial force `R₀` and transverse force `S`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞.
    pub fn with_forces(mut self, radial: f64, transverse: f64) -> Result<Self> {
        self.radial = finite("radial force R₀", radial)?;
        self.transverse = finite("transverse force S", transverse)?;
        Ok(self)
    }

    /// Gibbs' function `G = ½m[(r̈ − q̇²/r³)² + q̈²/r²]` at the radius `r`, areal velocity `q̇`
    /// and the accelerations `(r̈, q̈)`: half the mass times the squared acceleration.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or value; [`Error::OutOfDomain`] for `r ≤ 0`.
    pub fn gibbs_function(&self, r: f64, areal_rate: f64, accel: [f64; 2]) -> Result<f64> {
        let r = positive("radius r", r)?;
        let h = finite("areal velocity q̇", areal_rate)?;
        crate::error::all_finite("(r̈, q̈)", &accel)?;
        let radial = accel[0] - (h / r) * (h / r) / r;
        let transverse = accel[1] / r;
        finite(
            "Gibbs function G",
            0.5 * self.mass * (radial * radial + transverse * transverse),
        )
    }

    /// The generalized forces on `(r, q)` at the radius `r`: `(R, S/r)`, `R = R₀ − μm/r²`
    /// [Ardema eq. 14.28].
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] for `r ≤ 0`.
    pub fn quasi_forces(&self, r: f64) -> Result<[f64; 2]> {
        let r = positive("radius r", r)?;
        let f = [
            self.radial - self.mu * self.mass / (r * r),
            self.transverse / r,
        ];
        crate::error::all_finite("(R, S/r)", &f)?;
        Ok(f)
    }
}

impl Lagrangian<2> for ArealVelocity {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        let r = q[0];
        (v[0] * v[0] + r * r * v[1] * v[1]) * (0.5 * self.mass) + r.recip() * (self.mu * self.mass)
    }

    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 2>,
        _v: &SVector<D, 2>,
    ) -> Option<SVector<D, 2>> {
        Some(SVector::from([
            D::from(self.radial),
            q[0] * self.transverse,
        ]))
    }
}

impl QuasiVelocities<2> for ArealVelocity {
    fn constrained(&self) -> usize {
        0
    }
    fn matrix<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        SMatrix::from_row_slice(&[D::one(), D::zero(), D::zero(), q[0] * q[0]])
    }
}

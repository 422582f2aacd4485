use super::Pendulum;
use crate::constraints::{
    Differentiated, HolonomicConstraints, PfaffianConstraints, QuasiVelocities,
};
#[cfg(doc)]
use crate::error::Error;
use crate::error::{finite, positive, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// A uniform rod of mass `m` and length `2a` whose centre moves on a circle of radius `c` about a
/// fixed point, the rod turning at the same rate as the radius to its centre, under gravity `g`
/// [Ardema 14.4] (SPEC T34). Coordinates `(x, y, φ)`: the centre (`y` up) and the rod's angle,
/// with the holonomic constraints
///
/// ```math
/// x - c\sin\varphi = 0,\qquad y + c\cos\varphi = 0 ,
/// ```
///
/// so that `φ = θ` is the angle of the radius from the downward vertical;
/// `T = ½m(ẋ² + ẏ²) + ½(ma²/3)φ̇²`, `V = mgy`. Reduced equation
///
/// ```math
/// \Big(c^2 + \frac{a^2}{3}\Big)\ddot\theta + g c\sin\theta = 0 ,
/// ```
///
/// a pendulum of frequency `n² = gc/(c² + a²/3)` ([`RodOnCircle::pendulum`]). For `c = a` it is a
/// rod whose ends slide on two perpendicular smooth lines meeting above it:
/// `θ̈ + (3g/(4c)) sin θ = 0`. Quasi-velocities: the two constraint forms (constrained) and `φ̇`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RodOnCircle {
    mass: f64,
    half_length: f64,
    radius: f64,
    gravity: f64,
}

impl RodOnCircle {
    /// Rod of mass `m > 0` and half-length `a > 0` on the circle of radius `c > 0`, gravity
    /// `g > 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::OutOfDomain`] for NaN/∞ or non-positive parameters.
    pub fn new(mass: f64, half_length: f64, radius: f64, gravity: f64) -> Result<Self> {
        Ok(Self {
            mass: positive("mass m", mass)?,
            half_length: positive("half-length a", half_length)?,
            radius: positive("circle radius c", radius)?,
            gravity: positive("gravity g", gravity)?,
        })
    }

    /// The pendulum `θ̈ + n² sin θ = 0` of the reduced equation, `n² = gc/(c² + a²/3)`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::OutOfDomain`] when `n` over- or underflows.
    pub fn pendulum(&self) -> Result<Pendulum> {
        let (a, c) = (self.half_length, self.radius);
        // gc/(c² + a²/3) = g/(c + (a/c)·a/3), free of overflow in c² and a².
        let n2 = self.gravity / (c + (a / c) * a / 3.0);
        Pendulum::new(n2.sqrt())
    }

    /// The small-oscillation period `2π/n`.
    ///
    /// # Errors
    /// As [`RodOnCircle::pendulum`].
    pub fn small_oscillation_period(&self) -> Result<f64> {
        finite(
            "small-oscillation period",
            2.0 * std::f64::consts::PI / self.pendulum()?.n(),
        )
    }

    /// Gibbs' function of the plane motion [Ardema eq. 14.22],
    /// `G = ½m|r̈_G|² + ½(ma²/3)θ̈² = ½mc²(θ̈² + θ̇⁴) + ½(ma²/3)θ̈²`, at `(θ̇, θ̈)`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or value.
    pub fn gibbs_function(&self, rate: f64, accel: f64) -> Result<f64> {
        let (w, wd) = (finite("θ̇", rate)?, finite("θ̈", accel)?);
        let c = self.radius;
        let centre = c * c * (wd * wd + w * w * w * w);
        let rotation = self.half_length * self.half_length / 3.0 * wd * wd;
        finite("Gibbs function G", 0.5 * self.mass * (centre + rotation))
    }

    /// The generalized force on `θ`, `Q_θ = −mgc sin θ`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞.
    pub fn angle_force(&self, angle: f64) -> Result<f64> {
        let th = finite("θ", angle)?;
        Ok(-self.mass * self.gravity * self.radius * th.sin())
    }

    /// The admissible state `(q, q̇)` in `(x, y, φ)` of the angle `θ` and its rate `θ̇`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞.
    pub fn state(&self, angle: f64, rate: f64) -> Result<(SVector<f64, 3>, SVector<f64, 3>)> {
        let (th, w) = (finite("θ", angle)?, finite("θ̇", rate)?);
        let (s, c) = th.sin_cos();
        let r = self.radius;
        let q = SVector::from([r * s, -r * c, th]);
        let v = SVector::from([r * c * w, r * s * w, w]);
        crate::error::all_finite("q̇", v.as_slice())?;
        Ok((q, v))
    }
}

impl Lagrangian<3> for RodOnCircle {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 3>, v: &SVector<D, 3>) -> D {
        let a = self.half_length;
        (v[0] * v[0] + v[1] * v[1]) * (0.5 * self.mass)
            + v[2] * v[2] * (0.5 * self.mass * a * a / 3.0)
            - q[1] * (self.mass * self.gravity)
    }
}

impl HolonomicConstraints<3, 2> for RodOnCircle {
    fn position_constraint<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
    ) -> SVector<D, 2> {
        let (s, c) = q[2].sin_cos();
        SVector::from([q[0] - s * self.radius, q[1] + c * self.radius])
    }
}

impl QuasiVelocities<3> for RodOnCircle {
    fn constrained(&self) -> usize {
        2
    }
    fn matrix<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        let (forms, _) = Differentiated(*self).forms(D::zero(), q);
        SMatrix::from_fn(|r, c| match r {
            0 | 1 => forms[(r, c)],
            _ => {
                if c == 2 {
                    D::one()
                } else {
                    D::zero()
                }
            }
        })
    }
}

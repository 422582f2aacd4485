use crate::constraints::{AccelerationConstraints, VelocityConstraints};
#[cfg(doc)]
use crate::error::Error;
use crate::error::{finite, Result};
use nalgebra::SVector;
use num_dual::DualNum;

/// Appell–Hamel's 45° constraint [Hamel art. 249] (SPEC T21): a unit-mass point,
/// `T = ½|ẋ|²`, force `(0, 0, K)`, the constraint non-linear in the velocities
///
/// ```math
/// g = \dot x_3^2 - \dot x_1^2 - \dot x_2^2 = 0 .
/// ```
///
/// The horizontal direction stays fixed, `ẋ₃ = ẋ₃(0) + Kt/2`, `|ẋ_h| = ẋ₃`; the multiplier in
/// the crate sign is `λ = K/(4ẋ₃)`. The cone's vertex `ẋ = 0` is reached at
/// `t* = 2ẋ₃(0)/|K|` for `K < 0`, where `∂g/∂ẋ` vanishes (SPEC X7).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConeConstraint {
    k: f64,
}

impl ConeConstraint {
    /// The point under the vertical force `K`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞.
    pub fn new(k: f64) -> Result<Self> {
        Ok(Self {
            k: finite("force K", k)?,
        })
    }

    /// Closed-form velocity at time `t` from the admissible `ẋ(0)` (with `ẋ₃(0) > 0`), valid
    /// before the vertex: `ẋ₃ = ẋ₃(0) + Kt/2`, the horizontal part scaled to `|ẋ_h| = ẋ₃`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] for `ẋ₃(0) ≤ 0` or `t` at or
    /// beyond the vertex.
    pub fn velocity(&self, v0: &SVector<f64, 3>, t: f64) -> Result<SVector<f64, 3>> {
        crate::error::all_finite("ẋ(0)", v0.as_slice())?;
        let t = finite("t", t)?;
        let v3 = crate::error::positive("ẋ₃(0)", v0[2])?;
        let w3 = v3 + 0.5 * self.k * t;
        if w3.is_nan() || w3 <= 0.0 {
            return Err(crate::error::Error::out_of_domain(
                "t",
                t,
                "before the cone's vertex, ẋ₃(0) + K t/2 > 0",
            ));
        }
        let w3 = finite("ẋ₃(t)", w3)?;
        let s = w3 / v3;
        let v = SVector::from([v0[0] * s, v0[1] * s, w3]);
        crate::error::all_finite("ẋ(t)", v.as_slice())?;
        Ok(v)
    }
}

/// The unit-mass point under the vertical force `(0, 0, K)` that Hamel's examples of
/// constraints non-linear in the velocities (art. 249) and in the accelerations (art. 252)
/// constrain: `T = ½|ẋ|²`.
macro_rules! unit_point_under_vertical_force {
    ($system:ty) => {
        impl $crate::lagrangian::Lagrangian<3> for $system {
            fn lagrangian<D: num_dual::DualNum<f64> + Copy>(
                &self,
                _t: D,
                _q: &nalgebra::SVector<D, 3>,
                v: &nalgebra::SVector<D, 3>,
            ) -> D {
                (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]) * 0.5
            }
            fn generalized_force<D: num_dual::DualNum<f64> + Copy>(
                &self,
                _t: D,
                _q: &nalgebra::SVector<D, 3>,
                _v: &nalgebra::SVector<D, 3>,
            ) -> Option<nalgebra::SVector<D, 3>> {
                Some(nalgebra::SVector::from([
                    D::zero(),
                    D::zero(),
                    D::from(self.k),
                ]))
            }
        }
    };
}

unit_point_under_vertical_force!(ConeConstraint);
unit_point_under_vertical_force!(SecondClassConstraint);

/// Hamel's second-class (acceleration) constraint [Hamel art. 252] (SPEC T22): the unit-mass
/// point of [`ConeConstraint`] under `(0, 0, K)` with
///
/// ```math
/// \ddot x_3 = \ddot x_1 \ddot x_2 .
/// ```
///
/// Gauss's function `Σ(ẍ − X)²` has three stationary points for `|K| > 1` (the least
/// `2|K| − 1`) and one, `ẍ = 0` with `K²`, for `|K| < 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SecondClassConstraint {
    k: f64,
}

impl SecondClassConstraint {
    /// The point under the vertical force `K`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞.
    pub fn new(k: f64) -> Result<Self> {
        Ok(Self {
            k: finite("force K", k)?,
        })
    }
}

impl AccelerationConstraints<3, 1> for SecondClassConstraint {
    fn acceleration_constraint<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 3>,
        _v: &SVector<D, 3>,
        a: &SVector<D, 3>,
    ) -> SVector<D, 1> {
        SVector::from([a[2] - a[0] * a[1]])
    }
}

impl VelocityConstraints<3, 1> for ConeConstraint {
    fn velocity_constraint<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 3>,
        v: &SVector<D, 3>,
    ) -> SVector<D, 1> {
        SVector::from([v[2] * v[2] - v[0] * v[0] - v[1] * v[1]])
    }
}

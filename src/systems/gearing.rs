use crate::constraints::{PfaffianConstraints, QuasiVelocities};
#[cfg(doc)]
use crate::error::Error;
use crate::error::{finite, positive, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// Two shafts coupled by a gearing of variable ratio [Hamel art. 240] (SPEC T19): angles
/// `(φ₁, φ₂)`, moments `I₁, I₂`, torques `M₁, M₂`, the rheonomic constraint
/// `φ̇₁ = f(t) φ̇₂`, `f(t) = f₀ + f₁ t`:
///
/// ```math
/// T = \tfrac12 I_1\dot\varphi_1^2 + \tfrac12 I_2\dot\varphi_2^2,\qquad
/// (I_1 f^2 + I_2)\ddot\varphi_2 + I_1 f\dot f\dot\varphi_2 = M_1 f + M_2 .
/// ```
///
/// Substituting the constraint into `T` first gives the wrong
/// `d/dt[(I₁f² + I₂)φ̇₂] = M₁f + M₂` (the trap of M62). [`GearingInTime`] is the same system with
/// time adjoined as a third coordinate, for the quasi-velocity formulations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gearing {
    i1: f64,
    i2: f64,
    f0: f64,
    f1: f64,
    m1: f64,
    m2: f64,
}

impl Gearing {
    /// Moments `I₁, I₂ > 0`, ratio `f(t) = f₀ + f₁ t`, torques `M₁, M₂`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::OutOfDomain`] for NaN/∞ or non-positive moments.
    pub fn new(i1: f64, i2: f64, f0: f64, f1: f64, m1: f64, m2: f64) -> Result<Self> {
        Ok(Self {
            i1: positive("moment I₁", i1)?,
            i2: positive("moment I₂", i2)?,
            f0: finite("f₀", f0)?,
            f1: finite("f₁", f1)?,
            m1: finite("torque M₁", m1)?,
            m2: finite("torque M₂", m2)?,
        })
    }

    fn ratio<D: DualNum<f64> + Copy>(&self, t: D) -> D {
        t * self.f1 + self.f0
    }

    /// The torque-free motion's `φ̇₂(t)` from `φ̇₂(0)`: `½(I₁f² + I₂)φ̇₂²` is conserved.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or output.
    pub fn free_rate(&self, rate0: f64, t: f64) -> Result<f64> {
        let (rate0, t) = (finite("φ̇₂(0)", rate0)?, finite("t", t)?);
        // √(I₁f² + I₂) = √I₁ · hypot(f, √(I₂/I₁)), free of overflow.
        let c = (self.i2 / self.i1).sqrt();
        let root = |f: f64| f.hypot(c);
        finite("φ̇₂", rate0 * (root(self.f0) / root(self.ratio(t))))
    }
}

impl Lagrangian<2> for Gearing {
    fn lagrangian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 2>,
        v: &SVector<D, 2>,
    ) -> D {
        v[0] * v[0] * (0.5 * self.i1) + v[1] * v[1] * (0.5 * self.i2)
    }
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 2>,
        _v: &SVector<D, 2>,
    ) -> Option<SVector<D, 2>> {
        Some(SVector::from([D::from(self.m1), D::from(self.m2)]))
    }
}

impl PfaffianConstraints<2, 1> for Gearing {
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        _q: &SVector<D, 2>,
    ) -> (SMatrix<D, 1, 2>, SVector<D, 1>) {
        (
            SMatrix::from_row_slice(&[D::one(), -self.ratio(t)]),
            SVector::from([D::zero()]),
        )
    }
}

/// [`Gearing`] with time adjoined as the coordinate `q₃ = t` (SPEC §0.7): quasi-velocities
/// `ω = (φ̇₁ − f(q₃) φ̇₂, φ̇₂, q̇₃)`, the first constrained, the third `ṫ = 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GearingInTime(pub Gearing);

impl Lagrangian<3> for GearingInTime {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 3>, v: &SVector<D, 3>) -> D {
        let qq = SVector::from([q[0], q[1]]);
        let vv = SVector::from([v[0], v[1]]);
        self.0.lagrangian(t, &qq, &vv)
    }
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 3>,
        _v: &SVector<D, 3>,
    ) -> Option<SVector<D, 3>> {
        Some(SVector::from([
            D::from(self.0.m1),
            D::from(self.0.m2),
            D::zero(),
        ]))
    }
}

impl QuasiVelocities<3> for GearingInTime {
    fn constrained(&self) -> usize {
        1
    }
    fn time_coordinate(&self) -> Option<usize> {
        Some(2)
    }
    fn matrix<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        let (z, o) = (D::zero(), D::one());
        SMatrix::from_row_slice(&[o, -self.0.ratio(q[2]), z, z, o, z, z, z, o])
    }
}

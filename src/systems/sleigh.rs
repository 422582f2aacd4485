use crate::constraints::{PfaffianConstraints, QuasiVelocities};
#[cfg(doc)]
use crate::error::Error;
use crate::error::{finite, positive, Error as E, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// The Chaplygin sleigh (blade) [Hamel art. 229, 234, 238] (SPEC T16): contact point `B = (x, y)`,
/// heading `ϑ`, mass centre at the distance `s` ahead of `B` along the heading, moment of inertia
/// `I_B` about `B`, optional constant push `Z` along the heading and torque `M`:
///
/// ```math
/// T = \tfrac12 m(\dot x^2 + \dot y^2) + m s \dot\vartheta(\dot y\cos\vartheta - \dot x\sin\vartheta)
///     + \tfrac12 I_B \dot\vartheta^2, \qquad \dot y\cos\vartheta - \dot x\sin\vartheta = 0 .
/// ```
///
/// Quasi-velocities `ω = (ẏ cos ϑ − ẋ sin ϑ, v = ẋ cos ϑ + ẏ sin ϑ, ϑ̇)`, the first constrained;
/// reduced equations `m v̇ − m s ϑ̇² = Z`, `I_B ϑ̈ + m s v ϑ̇ = M`. Force-free closed forms
/// ([`ChaplyginSleigh::free_motion`]) for `v(0) = 0`: `v = v₀ tanh(v₀t/a)`,
/// `ϑ = 2(√(I_B/m)/s) arctan(tanh(v₀t/(2a)))`, `a = I_B/(ms)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChaplyginSleigh {
    m: f64,
    s: f64,
    i_b: f64,
    push: f64,
    torque: f64,
}

impl ChaplyginSleigh {
    /// Sleigh of mass `m > 0`, mass-centre offset `s` (negative: behind the blade) and moment of
    /// inertia `I_B ≥ m s²` about the blade (`> m s²` for a regular mass matrix), no forces.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::OutOfDomain`] for NaN/∞, `m ≤ 0`, `I_B ≤ m s²`.
    pub fn new(m: f64, s: f64, i_b: f64) -> Result<Self> {
        let m = positive("mass m", m)?;
        let s = finite("offset s", s)?;
        let i_b = positive("moment of inertia I_B", i_b)?;
        let ms2 = finite("m s²", m * s * s)?;
        if i_b <= ms2 {
            return Err(E::out_of_domain(
                "moment of inertia I_B",
                i_b,
                format!("(m s², ∞) = ({ms2:e}, ∞)"),
            ));
        }
        Ok(Self {
            m,
            s,
            i_b,
            push: 0.0,
            torque: 0.0,
        })
    }

    /// The same sleigh pushed by a constant force `Z` along the heading and turned by a constant
    /// torque `M`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞.
    pub fn with_forces(mut self, push: f64, torque: f64) -> Result<Self> {
        self.push = finite("push Z", push)?;
        self.torque = finite("torque M", torque)?;
        Ok(self)
    }

    /// Force-free motion from `v(0) = 0`, `ϑ(0) = 0` with energy `m v₀²` (`v₀ > 0`): `(v, ϑ̇, ϑ)` at
    /// time `t` (SPEC T16).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] for `v₀ ≤ 0` or `s ≤ 0` (no
    /// relaxation: `a = I_B/(ms)` must be positive and finite).
    pub fn free_motion(&self, v0: f64, t: f64) -> Result<(f64, f64, f64)> {
        let v0 = positive("v₀", v0)?;
        let t = finite("t", t)?;
        let s = positive("offset s (free motion needs the mass centre ahead)", self.s)?;
        let a = self.i_b / (self.m * s);
        let x = v0 * t / a;
        let k = (self.i_b / self.m).sqrt();
        let v = v0 * x.tanh();
        let w = v0 * (self.m / self.i_b).sqrt() / x.cosh();
        let th = 2.0 * (k / s) * (0.5 * x).tanh().atan();
        Ok((finite("v", v)?, finite("ϑ̇", w)?, finite("ϑ", th)?))
    }
}

impl Lagrangian<3> for ChaplyginSleigh {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 3>, v: &SVector<D, 3>) -> D {
        let (s, c) = q[2].sin_cos();
        (v[0] * v[0] + v[1] * v[1]) * (0.5 * self.m)
            + v[2] * (v[1] * c - v[0] * s) * (self.m * self.s)
            + v[2] * v[2] * (0.5 * self.i_b)
    }

    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
        _v: &SVector<D, 3>,
    ) -> Option<SVector<D, 3>> {
        let (s, c) = q[2].sin_cos();
        Some(SVector::from([
            c * self.push,
            s * self.push,
            D::from(self.torque),
        ]))
    }
}

impl PfaffianConstraints<3, 1> for ChaplyginSleigh {
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
    ) -> (SMatrix<D, 1, 3>, SVector<D, 1>) {
        let (s, c) = q[2].sin_cos();
        (
            SMatrix::from_row_slice(&[-s, c, D::zero()]),
            SVector::from([D::zero()]),
        )
    }
}

impl QuasiVelocities<3> for ChaplyginSleigh {
    fn constrained(&self) -> usize {
        1
    }
    fn matrix<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        let (s, c) = q[2].sin_cos();
        let (o, z) = (D::one(), D::zero());
        SMatrix::from_row_slice(&[-s, c, z, c, s, z, z, z, o])
    }
}

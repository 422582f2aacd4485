use crate::constraints::{PfaffianConstraints, QuasiVelocities};
#[cfg(doc)]
use crate::error::Error;
use crate::error::{finite, positive, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// The two-wheeled cart [Ardema 9.1] = [Hamel art. 231, 234, 239] (SPEC T18): coordinates
/// `(x, y, θ, φ_l, φ_r)`, `(x, y)` the axle midpoint, wheels of radius `r` at `±b`:
///
/// ```math
/// T = \tfrac12 m(\dot x^2 + \dot y^2) + m_c s\,\dot\theta(\dot y\cos\theta - \dot x\sin\theta)
///     + \tfrac12 I\dot\theta^2 + \tfrac12 C(\dot\varphi_l^2 + \dot\varphi_r^2),
/// ```
///
/// constraints `ẋ sin θ − ẏ cos θ = 0`, `−ẋ cos θ − ẏ sin θ ± b θ̇ + r φ̇_{l,r} = 0`
/// [Ardema eqs. 9.1–9.3]; a push `F(t) = F₀ cos(Ωt)` along the heading and a constant torque `M`.
/// Quasi-velocities: the three constraint rows, then `v = ẋ cos θ + ẏ sin θ` and `θ̇`. Reduced
/// equations `(m + 2C/r²) v̇ − m_c s θ̇² = F`, `(I + 2Cb²/r²) θ̈ + m_c s v θ̇ = M`
/// [Hamel art. 239]. Rows 2 and 3 differ by the integrable `2bθ̇ + r(φ̇_l − φ̇_r) = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TwoWheeledCart {
    m: f64,
    mcs: f64,
    c: f64,
    i: f64,
    b: f64,
    r: f64,
    f0: f64,
    omega: f64,
    torque: f64,
}

impl TwoWheeledCart {
    /// Cart of total mass `m > 0`, first moment `m_c s`, wheel polar moment `C > 0`, moment of
    /// inertia `I > 0` about the axle midpoint, half-track `b > 0`, wheel radius `r > 0`; no forces.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::OutOfDomain`] for NaN/∞ or non-positive parameters.
    pub fn new(m: f64, mcs: f64, c: f64, i: f64, b: f64, r: f64) -> Result<Self> {
        Ok(Self {
            m: positive("mass m", m)?,
            mcs: finite("first moment m_c s", mcs)?,
            c: positive("wheel moment C", c)?,
            i: positive("moment of inertia I", i)?,
            b: positive("half-track b", b)?,
            r: positive("wheel radius r", r)?,
            f0: 0.0,
            omega: 0.0,
            torque: 0.0,
        })
    }

    /// The same cart pushed by `F(t) = F₀ cos(Ωt)` along the heading and turned by `M`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞.
    pub fn with_forces(mut self, f0: f64, omega: f64, torque: f64) -> Result<Self> {
        self.f0 = finite("push amplitude F₀", f0)?;
        self.omega = finite("push frequency Ω", omega)?;
        self.torque = finite("torque M", torque)?;
        Ok(self)
    }

    /// Reduced inertias `(m′, I′) = (m + 2C/r², I + 2Cb²/r²)` [Hamel art. 239].
    pub fn reduced_inertias(&self) -> (f64, f64) {
        let k = 2.0 * self.c / (self.r * self.r);
        (self.m + k, self.i + k * self.b * self.b)
    }
}

impl Lagrangian<5> for TwoWheeledCart {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 5>, v: &SVector<D, 5>) -> D {
        let (s, c) = q[2].sin_cos();
        (v[0] * v[0] + v[1] * v[1]) * (0.5 * self.m)
            + v[2] * (v[1] * c - v[0] * s) * self.mcs
            + v[2] * v[2] * (0.5 * self.i)
            + (v[3] * v[3] + v[4] * v[4]) * (0.5 * self.c)
    }

    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 5>,
        _v: &SVector<D, 5>,
    ) -> Option<SVector<D, 5>> {
        let (s, c) = q[2].sin_cos();
        let f = (t * self.omega).cos() * self.f0;
        let z = D::zero();
        Some(SVector::from([c * f, s * f, D::from(self.torque), z, z]))
    }
}

impl PfaffianConstraints<5, 3> for TwoWheeledCart {
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 5>,
    ) -> (SMatrix<D, 3, 5>, SVector<D, 3>) {
        let m = self.matrix(q);
        (m.fixed_rows::<3>(0).into_owned(), SVector::zeros())
    }
}

impl QuasiVelocities<5> for TwoWheeledCart {
    fn constrained(&self) -> usize {
        3
    }
    fn matrix<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 5>) -> SMatrix<D, 5, 5> {
        let (s, c) = q[2].sin_cos();
        let (z, o) = (D::zero(), D::one());
        let (b, r) = (D::from(self.b), D::from(self.r));
        SMatrix::from_row_slice(&[
            s, -c, z, z, z, //
            -c, -s, b, r, z, //
            -c, -s, -b, z, r, //
            c, s, z, z, z, //
            z, z, o, z, z,
        ])
    }
}

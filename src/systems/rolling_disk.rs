use crate::constraints::{PfaffianConstraints, QuasiVelocities};
#[cfg(doc)]
use crate::error::Error;
use crate::error::{finite, positive, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// A ring or disk rolling without slipping on a horizontal plane [Hamel art. 230, 243–244]
/// ≡ [Ardema 7.5] (SPEC M70, T17): contact point `(x, y)`, heading `ϑ`, lean `ψ`, roll angle
/// `φ`; radius `r`, mass `m`, diametral moment `A`, polar moment `C`, gravity `g`:
///
/// ```math
/// T = \tfrac12 m|\dot c|^2 + \tfrac12 A(\dot\psi^2 + \cos^2\psi\,\dot\vartheta^2)
///     + \tfrac12 C(\dot\varphi - \dot\vartheta\sin\psi)^2,\qquad V = m g r\cos\psi,
/// ```
///
/// `c = (x − r sin ψ sin ϑ, y + r sin ψ cos ϑ, r cos ψ)` the centre; rolling constraints
/// `ẋ = r cos ϑ φ̇`, `ẏ = r sin ϑ φ̇`. Quasi-velocities `(ẋ − r cos ϑ φ̇, ẏ − r sin ϑ φ̇, ϑ̇, ψ̇, φ̇)`.
/// Upright rolling at speed `v` is oscillatory iff `v² > A m g r³/(C(C + m r²))`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollingDisk {
    m: f64,
    r: f64,
    a: f64,
    c: f64,
    g: f64,
}

impl RollingDisk {
    /// Body of mass `m > 0`, radius `r > 0`, moments `A > 0`, `C > 0`, gravity `g`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::OutOfDomain`] for NaN/∞ or non-positive parameters.
    pub fn new(m: f64, r: f64, a: f64, c: f64, g: f64) -> Result<Self> {
        Ok(Self {
            m: positive("mass m", m)?,
            r: positive("radius r", r)?,
            a: positive("diametral moment A", a)?,
            c: positive("polar moment C", c)?,
            g: finite("g", g)?,
        })
    }

    /// Uniform disk, `A = ¼mr²`, `C = ½mr²`.
    ///
    /// # Errors
    /// As [`RollingDisk::new`].
    pub fn disk(m: f64, r: f64, g: f64) -> Result<Self> {
        Self::new(m, r, 0.25 * m * r * r, 0.5 * m * r * r, g)
    }

    /// Thin hoop, `A = ½mr²`, `C = mr²`.
    ///
    /// # Errors
    /// As [`RollingDisk::new`].
    pub fn hoop(m: f64, r: f64, g: f64) -> Result<Self> {
        Self::new(m, r, 0.5 * m * r * r, m * r * r, g)
    }

    /// The radius `r`.
    pub fn radius(&self) -> f64 {
        self.r
    }

    /// The critical speed `v_c = √(A m g r³/(C(C + m r²)))` above which upright rolling is
    /// oscillatory [Hamel art. 244] (SPEC T17).
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `g < 0`.
    pub fn critical_speed(&self) -> Result<f64> {
        let (m, r, a, c) = (self.m, self.r, self.a, self.c);
        let v2 = a * m * self.g * r.powi(3) / (c * (c + m * r * r));
        if v2 < 0.0 {
            return Err(crate::error::Error::out_of_domain("g", self.g, "[0, ∞)"));
        }
        finite("critical speed", v2.sqrt())
    }

    /// Energy `T + V` at `(q, q̇)`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or output.
    pub fn energy(&self, q: &SVector<f64, 5>, qdot: &SVector<f64, 5>) -> Result<f64> {
        let l = self.value(0.0, q, qdot)?;
        let v = self.m * self.g * self.r * q[3].cos();
        finite("energy", l + 2.0 * v)
    }
}

impl Lagrangian<5> for RollingDisk {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 5>, v: &SVector<D, 5>) -> D {
        let (st, ct) = q[2].sin_cos();
        let (sp, cp) = q[3].sin_cos();
        let r = self.r;
        let trans =
            v[0] * v[0] + v[1] * v[1] + v[3] * v[3] * (r * r) + sp * sp * v[2] * v[2] * (r * r)
                - v[0] * v[3] * cp * st * (2.0 * r)
                + v[1] * v[3] * cp * ct * (2.0 * r)
                - v[0] * v[2] * sp * ct * (2.0 * r)
                - v[1] * v[2] * sp * st * (2.0 * r);
        let spin = v[4] - v[2] * sp;
        trans * (0.5 * self.m)
            + (v[3] * v[3] + cp * cp * v[2] * v[2]) * (0.5 * self.a)
            + spin * spin * (0.5 * self.c)
            - cp * (self.m * self.g * r)
    }
}

impl PfaffianConstraints<5, 2> for RollingDisk {
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 5>,
    ) -> (SMatrix<D, 2, 5>, SVector<D, 2>) {
        let m = self.matrix(q);
        (m.fixed_rows::<2>(0).into_owned(), SVector::zeros())
    }
}

impl QuasiVelocities<5> for RollingDisk {
    fn constrained(&self) -> usize {
        2
    }
    fn matrix<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 5>) -> SMatrix<D, 5, 5> {
        let (st, ct) = q[2].sin_cos();
        let (z, o) = (D::zero(), D::one());
        let r = self.r;
        SMatrix::from_row_slice(&[
            o,
            z,
            z,
            z,
            -ct * r, //
            z,
            o,
            z,
            z,
            -st * r, //
            z,
            z,
            o,
            z,
            z, //
            z,
            z,
            z,
            o,
            z, //
            z,
            z,
            z,
            z,
            o,
        ])
    }
}

use crate::constraints::{PfaffianConstraints, QuasiVelocities};
#[cfg(doc)]
use crate::error::Error;
use crate::error::{all_finite, finite, positive, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// A sphere rolling without slipping on a turntable that turns at the rate `Ω(t) = Ω₀ + Ω₁t`
/// about the vertical through the origin [Ardema 14.4, eqs. 14.23–14.30] (SPEC T32): mass `M`,
/// radius `a`, a spherically symmetric mass distribution with moment of inertia `I` about every
/// axis through the centre, constant force `(F_x, F_y)` at the centre and constant moment
/// `(M_x, M_y, M_z)`.
///
/// Coordinates `q = (x, y, π_x, π_y, π_z)`: the centre and the rotation quasi-coordinates with
/// `π̇ = ω` (space axes). The orientation is ignorable and, the inertia being isotropic,
/// `ω × Iω = 0`, so the `π` enter the kinetic energy like coordinates [Ardema 14.4]:
///
/// ```math
/// T = \tfrac12 M(\dot x^2 + \dot y^2) + \tfrac12 I|\omega|^2,\qquad
/// \dot x - a\omega_y + \Omega y = 0,\quad \dot y + a\omega_x - \Omega x = 0
/// ```
///
/// (the contact point moves with the table). Eliminating `ω_x, ω_y`:
/// `M ẍ + (I/a²)(ẍ + Ω̇y + Ωẏ) = F_x + M_y/a`, `M ÿ + (I/a²)(ÿ − Ω̇x − Ωẋ) = F_y − M_x/a`,
/// `I ω̇_z = M_z`. Force-free with constant `Ω` the centre's velocity turns at the rate
/// `k = Ω I/(I + M a²)` (`2Ω/7` for the homogeneous sphere, [`SphereOnTurntable::free_motion`]).
/// [`SphereOnTurntableInTime`] adjoins time as a coordinate for the quasi-velocity formulations.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereOnTurntable {
    mass: f64,
    radius: f64,
    inertia: f64,
    rate: [f64; 2],
    force: [f64; 2],
    moment: [f64; 3],
}

impl SphereOnTurntable {
    /// Sphere of mass `M > 0`, radius `a > 0` and central moment of inertia `I > 0` on a table
    /// turning at the constant rate `Ω`, no forces.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::OutOfDomain`] for NaN/∞ or non-positive `M`, `a`, `I`.
    pub fn new(mass: f64, radius: f64, inertia: f64, rate: f64) -> Result<Self> {
        Ok(Self {
            mass: positive("mass M", mass)?,
            radius: positive("radius a", radius)?,
            inertia: positive("moment of inertia I", inertia)?,
            rate: [finite("turntable rate Ω", rate)?, 0.0],
            force: [0.0; 2],
            moment: [0.0; 3],
        })
    }

    /// The homogeneous sphere, `I = (2/5) M a²`.
    ///
    /// # Errors
    /// As [`SphereOnTurntable::new`].
    pub fn homogeneous(mass: f64, radius: f64, rate: f64) -> Result<Self> {
        let mass = positive("mass M", mass)?;
        let radius = positive("radius a", radius)?;
        Self::new(mass, radius, 0.4 * mass * radius * radius, rate)
    }

    /// The same sphere on a table accelerating as `Ω(t) = Ω₀ + Ω₁t`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞.
    pub fn with_acceleration(mut self, acceleration: f64) -> Result<Self> {
        self.rate[1] = finite("turntable acceleration Ω̇", acceleration)?;
        Ok(self)
    }

    /// The same sphere under the constant force `(F_x, F_y)` at its centre and moment
    /// `(M_x, M_y, M_z)`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞.
    pub fn with_forces(mut self, force: [f64; 2], moment: [f64; 3]) -> Result<Self> {
        all_finite("force (F_x, F_y)", &force)?;
        all_finite("moment (M_x, M_y, M_z)", &moment)?;
        self.force = force;
        self.moment = moment;
        Ok(self)
    }

    /// The table's rate `Ω(t)`.
    pub fn table_rate<D: DualNum<f64> + Copy>(&self, t: D) -> D {
        t * self.rate[1] + self.rate[0]
    }

    /// Force-free motion on a table turning at a constant rate: the centre's position and velocity
    /// at time `t` from `r(0) = r₀`, `ṙ(0) = v₀`,
    /// `ṙ(t) = R(kt) v₀`, `r(t) = r₀ + (sin kt/k) v₀ + ((1 − cos kt)/k) ẑ × v₀`,
    /// `k = Ω I/(I + M a²)`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] when the table accelerates or
    /// forces act (no closed form).
    pub fn free_motion(&self, r0: [f64; 2], v0: [f64; 2], t: f64) -> Result<([f64; 2], [f64; 2])> {
        all_finite("r₀", &r0)?;
        all_finite("v₀", &v0)?;
        let t = finite("t", t)?;
        let loads = self
            .force
            .iter()
            .chain(&self.moment[..2])
            .any(|f| *f != 0.0);
        if self.rate[1] != 0.0 || loads {
            return Err(crate::error::Error::invalid(
                "sphere on a turntable",
                "the closed form holds for a table at constant rate without forces",
            ));
        }
        let k = self.rate[0] * self.inertia / (self.inertia + self.mass * self.radius.powi(2));
        let phase = k * t;
        let (s, c) = phase.sin_cos();
        // sin(kt)/k and (1 − cos kt)/k = 2 sin²(kt/2)/k, both → t, 0 as k → 0.
        let (a1, a2) = if k == 0.0 {
            (t, 0.0)
        } else {
            let h = (0.5 * phase).sin();
            (s / k, 2.0 * h * h / k)
        };
        let r = [
            r0[0] + a1 * v0[0] - a2 * v0[1],
            r0[1] + a1 * v0[1] + a2 * v0[0],
        ];
        let v = [c * v0[0] - s * v0[1], s * v0[0] + c * v0[1]];
        all_finite("r(t)", &r)?;
        all_finite("ṙ(t)", &v)?;
        Ok((r, v))
    }
}

impl Lagrangian<5> for SphereOnTurntable {
    fn lagrangian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 5>,
        v: &SVector<D, 5>,
    ) -> D {
        (v[0] * v[0] + v[1] * v[1]) * (0.5 * self.mass)
            + (v[2] * v[2] + v[3] * v[3] + v[4] * v[4]) * (0.5 * self.inertia)
    }

    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 5>,
        _v: &SVector<D, 5>,
    ) -> Option<SVector<D, 5>> {
        let [fx, fy] = self.force;
        let [mx, my, mz] = self.moment;
        Some(SVector::from([fx, fy, mx, my, mz].map(D::from)))
    }
}

impl PfaffianConstraints<5, 2> for SphereOnTurntable {
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 5>,
    ) -> (SMatrix<D, 2, 5>, SVector<D, 2>) {
        let (o, z, a) = (D::one(), D::zero(), D::from(self.radius));
        let w = self.table_rate(t);
        (
            SMatrix::from_row_slice(&[o, z, z, -a, z, z, o, a, z, z]),
            SVector::from([w * q[1], -w * q[0]]),
        )
    }
}

/// [`SphereOnTurntable`] with time adjoined as the coordinate `q₆ = t` (SPEC §0.7):
/// quasi-velocities `ω = (ẋ − aπ̇_y + Ωy q̇₆, ẏ + aπ̇_x − Ωx q̇₆, π̇_x, π̇_y, π̇_z, q̇₆)`, the
/// first two constrained (the contact conditions), the last `ṫ = 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereOnTurntableInTime(pub SphereOnTurntable);

fn head<D: DualNum<f64> + Copy>(q: &SVector<D, 6>) -> SVector<D, 5> {
    SVector::from_fn(|i, _| q[i])
}

impl Lagrangian<6> for SphereOnTurntableInTime {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 6>, v: &SVector<D, 6>) -> D {
        self.0.lagrangian(t, &head(q), &head(v))
    }

    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 6>,
        v: &SVector<D, 6>,
    ) -> Option<SVector<D, 6>> {
        let f = self.0.generalized_force(t, &head(q), &head(v))?;
        Some(SVector::from_fn(
            |i, _| if i < 5 { f[i] } else { D::zero() },
        ))
    }
}

impl QuasiVelocities<6> for SphereOnTurntableInTime {
    fn constrained(&self) -> usize {
        2
    }
    fn time_coordinate(&self) -> Option<usize> {
        Some(5)
    }
    fn matrix<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 6>) -> SMatrix<D, 6, 6> {
        let (forms, rate) = self.0.forms(q[5], &head(q));
        SMatrix::from_fn(|r, c| match (r, c) {
            (0 | 1, 5) => rate[r],
            (0 | 1, _) => forms[(r, c)],
            (r, c) if r == c => D::one(),
            _ => D::zero(),
        })
    }
}

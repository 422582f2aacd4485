//! Hill's (Clohessy–Wiltshire) equations: the linearised motion of a satellite relative to a
//! reference on a circular orbit of mean motion `n`, in the rotating frame with `x` radial, `y`
//! along-track and `z` out of plane [Ardema 12.4, eqs. 12.17–12.18; W. H. Clohessy & R. S.
//! Wiltshire, *J. Aerospace Sci.* 27, 653–658 (1960)] (SPEC M36, T28):
//!
//! ```text
//! ẍ − 2n ẏ − 3n² x = 0,    ÿ + 2n ẋ = 0,    z̈ + n² z = 0.
//! ```
//!
//! They are Hamilton's equations of the quadratic
//! `H = ½|p|² + n(y p_x − x p_y) − n² x² + ½ n² y² + ½ n² z²` with `p = (ẋ − n y, ẏ + n x, ż)`.
//! The closed form ([`ClohessyWiltshire::propagate`]):
//!
//! ```text
//! x = 2(ẏ₀/n + 2x₀) − (2ẏ₀/n + 3x₀) cos nt + (ẋ₀/n) sin nt
//! y = y₀ − 2ẋ₀/n − 3(ẏ₀ + 2n x₀) t + (2ẋ₀/n) cos nt + 2(2ẏ₀/n + 3x₀) sin nt
//! z = z₀ cos nt + (ż₀/n) sin nt
//! ```
//!
//! The out-of-plane motion is Lyapunov stable; in the plane `y` drifts at the secular rate
//! `−3(ẏ₀ + 2n x₀)` unless `ẏ₀ = −2n x₀` ([`ClohessyWiltshire::bounded_along_track_velocity`]),
//! when the motion is a closed 2:1 relative ellipse.

use super::ExactFlow;
use crate::error::{all_finite, finite, positive, Result};
use crate::hamiltonian::Hamiltonian;
use crate::phase::check_phase;
use crate::systems::kepler::orbit::phase_advance;
use nalgebra::{SVector, Vector3};
use num_dual::DualNum;

/// Hill's equations with mean motion `n` (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClohessyWiltshire {
    n: f64,
}

impl ClohessyWiltshire {
    /// The relative motion about a circular orbit of mean motion `n = √(μ/a³) > 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`](crate::Error::NonFinite) for NaN/∞,
    /// [`Error::OutOfDomain`](crate::Error::OutOfDomain) for `n ≤ 0`.
    pub fn new(n: f64) -> Result<Self> {
        Ok(Self {
            n: positive("mean motion n", n)?,
        })
    }
    /// The mean motion `n`.
    pub fn n(&self) -> f64 {
        self.n
    }
    /// The momentum `p = (ẋ − n y, ẏ + n x, ż)` of a relative position and velocity.
    ///
    /// # Errors
    /// [`Error::NonFinite`](crate::Error::NonFinite) for NaN/∞ input or an overflowing result.
    pub fn momentum(&self, r: &Vector3<f64>, v: &Vector3<f64>) -> Result<Vector3<f64>> {
        let p = Vector3::new(v[0] - self.n * r[1], v[1] + self.n * r[0], v[2]);
        all_finite("momentum p", p.as_slice())?;
        Ok(p)
    }
    /// The velocity `(p_x + n y, p_y − n x, p_z)` of a relative position and momentum.
    ///
    /// # Errors
    /// [`Error::NonFinite`](crate::Error::NonFinite) for NaN/∞ input or an overflowing result.
    pub fn velocity(&self, r: &Vector3<f64>, p: &Vector3<f64>) -> Result<Vector3<f64>> {
        let v = Vector3::new(p[0] + self.n * r[1], p[1] - self.n * r[0], p[2]);
        all_finite("velocity", v.as_slice())?;
        Ok(v)
    }
    /// The along-track velocity `ẏ₀ = −2n x₀` of bounded (drift-free) relative motion.
    pub fn bounded_along_track_velocity(&self, x0: f64) -> Result<f64> {
        finite(
            "bounded along-track velocity",
            -2.0 * self.n * finite("x₀", x0)?,
        )
    }
    /// The secular along-track drift rate `−3(ẏ₀ + 2n x₀)`.
    pub fn along_track_drift(&self, x0: f64, vy0: f64) -> Result<f64> {
        finite(
            "along-track drift",
            -3.0 * (finite("ẏ₀", vy0)? + 2.0 * self.n * finite("x₀", x0)?),
        )
    }
    /// The relative position and velocity at time `t` after `(r₀, v₀)`, in closed form (SPEC M36:
    /// `cw_propagate`).
    ///
    /// # Errors
    /// [`Error::NonFinite`](crate::Error::NonFinite) for NaN/∞ input or an overflowing result;
    /// [`Error::PhaseLost`](crate::Error::PhaseLost) when `|nt|` is too large for the phase to be
    /// resolved.
    pub fn propagate(
        &self,
        r0: &Vector3<f64>,
        v0: &Vector3<f64>,
        t: f64,
    ) -> Result<(Vector3<f64>, Vector3<f64>)> {
        all_finite("r₀", r0.as_slice())?;
        all_finite("v₀", v0.as_slice())?;
        let t = finite("t", t)?;
        let n = self.n;
        let (s, c) = phase_advance("Clohessy–Wiltshire closed form", n * t)?.sin_cos();
        let (x0, y0, z0) = (r0[0], r0[1], r0[2]);
        let (u0, w0, zd0) = (v0[0], v0[1], v0[2]);
        let a = 2.0 * w0 / n + 3.0 * x0;
        let drift = -3.0 * (w0 + 2.0 * n * x0);
        let r = Vector3::new(
            2.0 * (w0 / n + 2.0 * x0) - a * c + (u0 / n) * s,
            y0 - 2.0 * u0 / n + drift * t + (2.0 * u0 / n) * c + 2.0 * a * s,
            z0 * c + (zd0 / n) * s,
        );
        let v = Vector3::new(
            a * n * s + u0 * c,
            drift - 2.0 * u0 * s + 2.0 * a * n * c,
            -z0 * n * s + zd0 * c,
        );
        all_finite("relative position", r.as_slice())?;
        all_finite("relative velocity", v.as_slice())?;
        Ok((r, v))
    }
}

impl Hamiltonian<3> for ClohessyWiltshire {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
        p: &SVector<D, 3>,
    ) -> D {
        let n = self.n;
        let (x, y, z) = (q[0], q[1], q[2]);
        (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]) * 0.5 + (y * p[0] - x * p[1]) * n
            - x * x * (n * n)
            + (y * y + z * z) * (0.5 * n * n)
    }
}

impl ExactFlow<3> for ClohessyWiltshire {
    fn exact_flow(
        &self,
        t0: f64,
        q0: &SVector<f64, 3>,
        p0: &SVector<f64, 3>,
        t: f64,
    ) -> Result<(SVector<f64, 3>, SVector<f64, 3>)> {
        check_phase(t0, q0, p0)?;
        let v0 = self.velocity(q0, p0)?;
        let (r, v) = self.propagate(q0, &v0, finite("t", t)? - t0)?;
        Ok((r, self.momentum(&r, &v)?))
    }
}

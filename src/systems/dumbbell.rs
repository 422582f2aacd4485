//! The dumbbell satellite: a rigid dumbbell of two point masses `m/2` at the distances `±z` from
//! its centre, in the plane of its orbit about an attracting body of parameter `μ`
//! [Ardema 15.3] (SPEC T40). Coordinates: the polar position `(r, ρ)` of the centre and the angle
//! `θ` between the radius vector and the dumbbell axis;
//!
//! ```text
//! L = ½ m [ṙ² + r² ρ̇² + z² (ρ̇ − θ̇)²] + ½ m μ (1/r₁ + 1/r₂),   r₁,₂² = r² + z² ± 2 z r cos θ,
//! H = p_r²/(2m) + (p_ρ + p_θ)²/(2 m r²) + p_θ²/(2 m z²) − ½ m μ (1/r₁ + 1/r₂).
//! ```
//!
//! `ρ` is cyclic. With the axis radial (`θ = 0`) the centre can rotate uniformly at `r₀` only at
//! `ω² = (μ/(2r₀)) [1/(r₀ + z)² + 1/(r₀ − z)²]` ([`DumbbellSatellite::radial_rate`]); with the
//! axis tangential (`θ = π/2`, `r₁ = r₂ = √(r₀² + z²)`) at `ω² = μ/(r₀² + z²)^{3/2}`
//! ([`DumbbellSatellite::tangential_rate`]). The radial orientation is stable, the tangential one
//! unstable (the gravity-gradient torque; pitch frequency and rate `≈ √3 ω` for `z ≪ r₀`).

use crate::error::{all_finite, finite, positive, Error, Result};
use crate::hamiltonian::Hamiltonian;
use nalgebra::SVector;
use num_dual::DualNum;

/// The planar dumbbell satellite (see the [module docs](self)); `q = (r, ρ, θ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DumbbellSatellite {
    m: f64,
    mu: f64,
    z: f64,
}

/// The orientation of a relative equilibrium of the dumbbell.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DumbbellOrientation {
    /// The axis along the radius vector, `θ = 0`.
    Radial,
    /// The axis along the orbit, `θ = π/2`.
    Tangential,
}

impl DumbbellSatellite {
    /// Total mass `m > 0`, attraction parameter `μ > 0`, half-length `z > 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] for a non-positive parameter.
    pub fn new(m: f64, mu: f64, z: f64) -> Result<Self> {
        Ok(Self {
            m: positive("mass m", m)?,
            mu: positive("attraction parameter μ", mu)?,
            z: positive("half-length z", z)?,
        })
    }
    /// The rate `ω` of uniform rotation with the axis radial at `r₀ > z`:
    /// `ω² = (μ/(2r₀)) [1/(r₀ + z)² + 1/(r₀ − z)²]`.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `r₀ ≤ z` (the near mass at or beyond the centre of attraction).
    pub fn radial_rate(&self, r0: f64) -> Result<f64> {
        let r0 = finite("radius r₀", r0)?;
        if r0 <= self.z {
            return Err(Error::out_of_domain("radius r₀", r0, "(z, ∞)"));
        }
        let (a, b) = (r0 + self.z, r0 - self.z);
        finite(
            "radial rate ω",
            (self.mu / (2.0 * r0) * (1.0 / (a * a) + 1.0 / (b * b))).sqrt(),
        )
    }
    /// The rate `ω = √(μ/(r₀² + z²)^{3/2})` of uniform rotation with the axis tangential.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `r₀ ≤ 0`.
    pub fn tangential_rate(&self, r0: f64) -> Result<f64> {
        let r0 = positive("radius r₀", r0)?;
        let d2 = r0 * r0 + self.z * self.z;
        finite("tangential rate ω", (self.mu / (d2 * d2.sqrt())).sqrt())
    }
    /// The state `(q, p)` at `ρ = 0` of the relative equilibrium at `r₀` with the given
    /// orientation, rotating at its rate `ω`: `p = (0, m(r₀² + z²)ω, −m z² ω)`; with `ω`.
    ///
    /// # Errors
    /// Those of [`radial_rate`](Self::radial_rate) and [`tangential_rate`](Self::tangential_rate).
    #[allow(clippy::type_complexity)]
    pub fn relative_equilibrium(
        &self,
        r0: f64,
        orientation: DumbbellOrientation,
    ) -> Result<(SVector<f64, 3>, SVector<f64, 3>, f64)> {
        let (omega, theta) = match orientation {
            DumbbellOrientation::Radial => (self.radial_rate(r0)?, 0.0),
            DumbbellOrientation::Tangential => {
                (self.tangential_rate(r0)?, std::f64::consts::FRAC_PI_2)
            }
        };
        Ok((
            SVector::from([r0, 0.0, theta]),
            self.momenta(r0, omega, 0.0, 0.0)?,
            omega,
        ))
    }
    /// The momenta `(p_r, p_ρ, p_θ) = (m ṙ, m r² ρ̇ + m z² (ρ̇ − θ̇), −m z² (ρ̇ − θ̇))` of the
    /// velocities `(ṙ, ρ̇, θ̇)` at radius `r`, in the order of the arguments `(r, ρ̇, ṙ, θ̇)`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or an overflowing result.
    pub fn momenta(
        &self,
        r: f64,
        rho_dot: f64,
        r_dot: f64,
        theta_dot: f64,
    ) -> Result<SVector<f64, 3>> {
        let (m, z2) = (self.m, self.z * self.z);
        let p = SVector::from([
            m * r_dot,
            m * r * r * rho_dot + m * z2 * (rho_dot - theta_dot),
            -m * z2 * (rho_dot - theta_dot),
        ]);
        all_finite("dumbbell momenta", p.as_slice())?;
        Ok(p)
    }
}

impl Hamiltonian<3> for DumbbellSatellite {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
        p: &SVector<D, 3>,
    ) -> D {
        let (m, mu, z) = (self.m, self.mu, self.z);
        let (r, th) = (q[0], q[2]);
        let c = th.cos() * (2.0 * z);
        let base = r * r + z * z;
        let r1 = (base + c * r).sqrt();
        let r2 = (base - c * r).sqrt();
        let pt = p[1] + p[2];
        p[0] * p[0] / (2.0 * m) + pt * pt / (r * r * (2.0 * m)) + p[2] * p[2] / (2.0 * m * z * z)
            - (r1.recip() + r2.recip()) * (0.5 * m * mu)
    }
}

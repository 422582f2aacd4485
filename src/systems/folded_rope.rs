//! The folded rope with an end mass (Ardema 9.3, "the Indian rope trick"; SPEC T23): a free
//! two-degree-of-freedom system whose relative motion straightens the rope in finite time, with an
//! infinite rate at the end (SPEC X8, the crack of the whip).

use crate::error::{finite, positive, Error, Result};
use crate::lagrangian::NaturalSystem;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;
use std::f64::consts::FRAC_PI_4;

/// A rope of length `ℓ` and line density `ρ` hanging in two parallel strands, a point mass `m` at
/// the end `x`, the other end at `y = x + u`, the fold at `z` with `(z − x) + (z − y) = ℓ`; each
/// strand moves rigidly with its own end and gravity `g` (along increasing `x`, `y`) is the only
/// external force [Ardema 9.3]. Coordinates `q = (x, y)`:
///
/// ```math
/// T = \tfrac14\rho\big[(\ell + u)\,\dot x^2 + (\ell - u)\,\dot y^2\big] + \tfrac12 m\dot x^2,\qquad
/// V = -g\Big[m x + \tfrac12\rho\ell(x + y) - \tfrac14\rho u^2\Big],
/// ```
///
/// the potential of the weights `g(m + ρ(ℓ + u)/2)` and `gρ(ℓ − u)/2` of the two rigidly moving
/// parts. Gravity drops out of the relative motion (a uniform field is removed by the freely
/// falling frame): with `μ = u/ℓ` and `M = m/(ρℓ)`,
///
/// ```math
/// (1 - \mu)(1 + 2M + \mu)\,\ddot\mu = (M + \mu)\,\dot\mu^2,\qquad
/// \dot\mu^2 (1 - \mu)(1 + 2M + \mu) = \text{const},
/// ```
///
/// and from `μ = 0` the rope straightens (`μ = 1`, `μ̇ → ∞`) at the finite time
/// [`FoldedRope::straightening_time`]. The mass matrix `diag(m + ρ(ℓ + u)/2, ρ(ℓ − u)/2)` is
/// singular at `u = ℓ`: integrations stop at an event `1 − μ = ε` and add
/// [`FoldedRope::time_from_start`]'s closed-form tail, or let the blow-up detector
/// ([`crate::integrate::BlowUpDetector`]) report the singular time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FoldedRope {
    density: f64,
    length: f64,
    mass: f64,
    gravity: f64,
}

impl FoldedRope {
    /// A rope of line density `ρ > 0` and length `ℓ > 0` with an end mass `m ≥ 0` (here `m > 0`,
    /// the case of the oracle) in gravity `g`.
    ///
    /// # Errors
    /// [`Error::NonFinite`]/[`Error::OutOfDomain`] for non-finite or non-positive `ρ`, `ℓ`, `m`,
    /// non-finite `g`, or a total mass `ρℓ + m` or mass ratio `m/(ρℓ)` that overflows.
    pub fn new(density: f64, length: f64, mass: f64, gravity: f64) -> Result<Self> {
        let rope = Self {
            density: positive("line density ρ", density)?,
            length: positive("rope length ℓ", length)?,
            mass: positive("end mass m", mass)?,
            gravity: finite("gravity g", gravity)?,
        };
        finite("total mass ρℓ + m", rope.density * rope.length + rope.mass)?;
        finite("mass ratio M = m/(ρℓ)", rope.mass_ratio())?;
        finite("1 + 2M", 1.0 + 2.0 * rope.mass_ratio())?;
        Ok(rope)
    }

    /// The mass ratio `M = m/(ρℓ)`.
    pub fn mass_ratio(&self) -> f64 {
        self.mass / (self.density * self.length)
    }

    /// The relative stretch `μ = (y − x)/ℓ` of a configuration `(x, y)`.
    pub fn stretch(&self, q: &SVector<f64, 2>) -> f64 {
        (q[1] - q[0]) / self.length
    }

    /// The invariant of the relative motion `μ̇²(1 − μ)(1 + 2M + μ)` (module docs).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for non-finite `μ`, `μ̇` or result.
    pub fn relative_invariant(&self, mu: f64, mu_dot: f64) -> Result<f64> {
        finite("stretch μ", mu)?;
        finite("stretch rate μ̇", mu_dot)?;
        finite(
            "invariant μ̇²(1 − μ)(1 + 2M + μ)",
            mu_dot * mu_dot * (1.0 - mu) * (1.0 + 2.0 * self.mass_ratio() + mu),
        )
    }

    /// The time to reach the stretch `μ ∈ [0, 1]` from `μ = 0` at the rate `μ̇(0) > 0`
    /// [Ardema eq. 9.24], with `μ̇₀ = μ̇(0)√(1 + 2M)`:
    ///
    /// ```math
    /// \dot\mu_0 t = \tfrac12\Big[(\mu + M)\sqrt{(1 - \mu)(1 + 2M + \mu)}
    /// + (1 + M)^2 \arcsin\frac{\mu + M}{1 + M}\Big]
    /// - \tfrac12\Big[M\sqrt{1 + 2M} + (1 + M)^2 \arcsin\frac{M}{1 + M}\Big].
    /// ```
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `μ` outside `[0, 1]` or a rate that is not positive and finite.
    pub fn time_from_start(&self, mu: f64, initial_rate: f64) -> Result<f64> {
        let rate = positive("initial stretch rate μ̇(0)", initial_rate)?;
        if !(0.0..=1.0).contains(&mu) {
            return Err(Error::out_of_domain("stretch μ", mu, "[0, 1]"));
        }
        let m = self.mass_ratio();
        let s = (1.0 + 2.0 * m).sqrt();
        let primitive = |mu: f64| {
            0.5 * ((mu + m) * ((1.0 - mu) * (1.0 + 2.0 * m + mu)).sqrt()
                + (1.0 + m).powi(2) * ((mu + m) / (1.0 + m)).min(1.0).asin())
        };
        scaled_time(
            "time to the stretch μ",
            (primitive(mu) - primitive(0.0)) / s,
            rate,
        )
    }

    /// The straightening time `t₁` from `μ = 0` at the rate `μ̇(0)` [Ardema 9.3]:
    ///
    /// ```math
    /// t_1 = \Big[(1 + M)^2\frac{\pi}{4} - \tfrac12 M\sqrt{1 + 2M}
    /// - \tfrac12 (1 + M)^2\arcsin\frac{M}{1 + M}\Big]\Big/\dot\mu_0 .
    /// ```
    ///
    /// # Errors
    /// As [`FoldedRope::time_from_start`].
    pub fn straightening_time(&self, initial_rate: f64) -> Result<f64> {
        let rate = positive("initial stretch rate μ̇(0)", initial_rate)?;
        let m = self.mass_ratio();
        let s = (1.0 + 2.0 * m).sqrt();
        let scaled = ((1.0 + m).powi(2) * FRAC_PI_4
            - 0.5 * m * s
            - 0.5 * (1.0 + m).powi(2) * (m / (1.0 + m)).asin())
            / s;
        scaled_time("straightening time t₁", scaled, rate)
    }
}

/// `τ/μ̇(0)` for a time `τ` at unit rate, refused where it overflows or underflows to a
/// subnormal (a rate so extreme that the time is not representable to full precision).
fn scaled_time(what: &str, tau: f64, rate: f64) -> Result<f64> {
    let t = finite(what, tau / rate)?;
    if tau > 0.0 && t < f64::MIN_POSITIVE {
        return Err(Error::out_of_domain(
            "initial stretch rate μ̇(0)",
            rate,
            format!("small enough that the {what} ({tau:e}/μ̇(0)) is a normal number"),
        ));
    }
    Ok(t)
}

impl NaturalSystem<2> for FoldedRope {
    fn mass<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        let u = q[1] - q[0];
        let half = 0.5 * self.density;
        SMatrix::<D, 2, 2>::new(
            (u + self.length) * half + self.mass,
            D::from(0.0),
            D::from(0.0),
            (-u + self.length) * half,
        )
    }

    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> D {
        let u = q[1] - q[0];
        -(q[0] * self.mass + (q[0] + q[1]) * (0.5 * self.density * self.length)
            - u * u * (0.25 * self.density))
            * self.gravity
    }
}

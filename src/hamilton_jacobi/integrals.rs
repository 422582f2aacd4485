//! Closed-form complete integrals of the catalogue systems [Ardema 17.3–17.4].
//!
//! Each is one branch of a multivalued function — the branch on which the separated momentum is
//! non-negative — and says so; states on the other branch have no preimage under Jacobi's theorem
//! (see [`Elements`](super::Elements)).

use super::complete::CompleteIntegral;
use crate::error::{positive, Result};
use nalgebra::SVector;
use num_dual::{Dual64, DualNum};

/// Projectile `H = ½(p_x² + p_y²) + g y` (unit mass) [Ardema 17.4]:
///
/// ```math
/// S = -(\tfrac12\gamma^2 + g k)\\,t + \gamma x \mp \tfrac23\sqrt{2g}\\,(k - y)^{3/2}, \qquad \alpha = (\gamma, k),
/// ```
///
/// with `γ = p_x` and `k` the apex height; the upper sign is the ascending branch (`p_y ≥ 0`,
/// [`ProjectileIntegral::new`]), the lower the descending one ([`ProjectileIntegral::descending`]).
/// Both give the same elements `β = (x₀, −v₀)` for one trajectory. Domain `y < k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectileIntegral {
    g: f64,
    /// `+1` ascending, `−1` descending.
    branch: f64,
}

impl ProjectileIntegral {
    /// Ascending branch, gravity `g > 0`.
    pub fn new(g: f64) -> Result<Self> {
        Ok(Self {
            g: positive("gravity g", g)?,
            branch: 1.0,
        })
    }
    /// Descending branch (`p_y ≤ 0`, after the apex), gravity `g > 0`.
    pub fn descending(g: f64) -> Result<Self> {
        Ok(Self {
            g: positive("gravity g", g)?,
            branch: -1.0,
        })
    }
}

impl CompleteIntegral<2> for ProjectileIntegral {
    fn action<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 2>, a: &SVector<D, 2>) -> D {
        let (gamma, k) = (a[0], a[1]);
        let d = k - q[1];
        -(gamma * gamma * 0.5 + k * self.g) * t + gamma * q[0]
            - d * d.sqrt() * (self.branch * (2.0 / 3.0) * (2.0 * self.g).sqrt())
    }
    /// Exact: `γ = p_x`, `k = y + p_y²/(2g)`.
    fn alpha_guess(
        &self,
        _t: f64,
        q: &SVector<f64, 2>,
        p: &SVector<f64, 2>,
    ) -> Option<SVector<f64, 2>> {
        Some(SVector::from([p[0], q[1] + p[1] * p[1] / (2.0 * self.g)]))
    }
}

/// Harmonic oscillator `H = ½(p² + n² x²)`, branch `p ≥ 0` [Ardema 17.4]:
///
/// ```math
/// S = -\tfrac12 n^2\alpha^2 t + \tfrac n2\Big(x\sqrt{\alpha^2 - x^2} + \alpha^2 \arcsin\frac x\alpha\Big),
/// ```
///
/// `α` the amplitude. Domain `|x| < α`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OscillatorIntegral {
    n: f64,
}

impl OscillatorIntegral {
    /// Frequency `n > 0`.
    pub fn new(n: f64) -> Result<Self> {
        Ok(Self {
            n: positive("frequency n", n)?,
        })
    }
}

impl CompleteIntegral<1> for OscillatorIntegral {
    fn action<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 1>, a: &SVector<D, 1>) -> D {
        let (x, al) = (q[0], a[0]);
        let n = self.n;
        -(al * al) * t * (0.5 * n * n)
            + (x * (al * al - x * x).sqrt() + al * al * (x / al).asin()) * (0.5 * n)
    }
    /// Exact: the amplitude `α = √(x² + p²/n²)`, inside the domain `α ≥ |x|`.
    fn alpha_guess(
        &self,
        _t: f64,
        q: &SVector<f64, 1>,
        p: &SVector<f64, 1>,
    ) -> Option<SVector<f64, 1>> {
        Some(SVector::from([q[0].hypot(p[0] / self.n)]))
    }
}

/// Kepler problem in polar coordinates `q = (r, θ)`, `H = ½(p_r² + p_θ²/r²) − μ/r`, outbound
/// branch `p_r ≥ 0` [Ardema 17.3, 15.53–15.55]: `S = −h t + kθ + K_r(r)` with `α = (h, k)` and the
/// radial characteristic function in closed form (`A = −2h > 0`, `R = −A r² + 2μ r − k²`,
/// `e = √(1 − A k²/μ²)`):
///
/// ```math
/// K_r = \sqrt R + \frac{\mu}{\sqrt A}\arcsin\frac{A r - \mu}{\mu e}
///       - |k| \arcsin\frac{\mu r - k^2}{\mu e r}, \qquad \frac{dK_r}{dr} = \frac{\sqrt R}{r} = p_r.
/// ```
///
/// Domain: bound (`h < 0`), non-circular (`e > 0`) orbits, `r_p < r < r_a`. The quadratures of
/// [`RadialMotion`](super::RadialMotion) give the same function through turning points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeplerPolarIntegral {
    mu: f64,
}

impl KeplerPolarIntegral {
    /// Gravitational parameter `μ > 0`.
    pub fn new(mu: f64) -> Result<Self> {
        Ok(Self {
            mu: positive("gravitational parameter μ", mu)?,
        })
    }

    /// The radial characteristic function `K_r(r; h, k)` (outbound branch).
    pub fn radial<D: DualNum<f64> + Copy>(&self, r: D, h: D, k: D) -> D {
        let mu = self.mu;
        let a = h * -2.0;
        let kk = k * k;
        let k_abs = if k.re() < 0.0 { -k } else { k };
        let e = (-(a * kk) / (mu * mu) + 1.0).sqrt();
        let big_r = -(a * r * r) + r * (2.0 * mu) - kk;
        big_r.sqrt() + ((a * r - mu) / (e * mu)).asin() * mu / a.sqrt()
            - k_abs * ((r * mu - kk) / (e * r * mu)).asin()
    }
}

impl CompleteIntegral<2> for KeplerPolarIntegral {
    fn action<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 2>, a: &SVector<D, 2>) -> D {
        let (h, k) = (a[0], a[1]);
        -h * t + k * q[1] + self.radial(q[0], h, k)
    }
    /// Exact: `h = ½(p_r² + p_θ²/r²) − μ/r`, `k = p_θ`.
    fn alpha_guess(
        &self,
        _t: f64,
        q: &SVector<f64, 2>,
        p: &SVector<f64, 2>,
    ) -> Option<SVector<f64, 2>> {
        let r = q[0];
        Some(SVector::from([
            0.5 * (p[0] * p[0] + p[1] * p[1] / (r * r)) - self.mu / r,
            p[1],
        ]))
    }
    /// From Kepler's equation: `K_r(r_p) = −(π/2) J_r`, so `∂S/∂h = β₁` puts periapsis at
    /// `t_p = −β₁ − T/4`; then `r = a(1 − e cos E)` and `θ = β₂ − ∂K_r/∂k`. `None` outside the
    /// outbound leg or for unbound constants.
    fn coordinate_guess(
        &self,
        t: f64,
        alpha: &SVector<f64, 2>,
        beta: &SVector<f64, 2>,
    ) -> Option<SVector<f64, 2>> {
        let (h, k) = (alpha[0], alpha[1]);
        if h.is_nan() || h >= 0.0 {
            return None;
        }
        let a = -self.mu / (2.0 * h);
        let e = (1.0 + 2.0 * h * k * k / (self.mu * self.mu))
            .max(0.0)
            .sqrt();
        let n = (self.mu / (a * a * a)).sqrt();
        let quarter = 0.5 * std::f64::consts::PI / n;
        let mean = n * (t + beta[0] + quarter);
        if !(0.0..=std::f64::consts::PI).contains(&mean) {
            return None;
        }
        let big_e = crate::special::kepler_equation::solve_kepler(mean, e).ok()?;
        // Stay strictly inside (r_p, r_a), where S is defined.
        let r = a * (1.0 - e * big_e.cos());
        let (rp, ra) = (a * (1.0 - e), a * (1.0 + e));
        let r = r.clamp(rp + 1e-9 * (ra - rp), ra - 1e-9 * (ra - rp));
        let dk = self
            .radial(
                Dual64::from_re(r),
                Dual64::from_re(h),
                Dual64::from_re(k).derivative(),
            )
            .eps;
        Some(SVector::from([r, beta[1] - dk]))
    }
}

//! Central-force motion by separation in polar coordinates [Ardema 10.1, eqs. 10.1–10.19;
//! 15.6, eqs. 15.53–15.55; 17.3].
//!
//! Per unit mass, with angular momentum `k = r² θ̇` and energy `h`, the characteristic function
//! separates as `K = kθ + ∫ √F(r) dr` with the radial radicand
//!
//! ```math
//! F(r) = \dot r^2 = 2\big(h - V(r)\big) - \frac{k^2}{r^2},
//! ```
//!
//! and Jacobi's theorem gives the time law and the orbit equation
//!
//! ```math
//! t - t_0 = \frac{\partial K}{\partial h} = \int \frac{dr}{\sqrt F}, \qquad
//! \theta - \theta_0 = -\frac{\partial}{\partial k}\int \sqrt F\\,dr = \int \frac{k\\,dr}{r^2 \sqrt F}.
//! ```
//!
//! Both integrands have inverse-square-root singularities at the apsides `r_p`, `r_a` (roots of
//! `F`), removed by the substitution of [`Libration`]. For the Kepler potential the
//! radicand factors exactly, `F = −2h (r − r_p)(r_a − r)/r²`, the substitution variable is the
//! eccentric anomaly, and the apsides come from the cancellation-free pair
//! `r_a = (μ + μe)/(−2h)`, `r_p = k²/(μ + μe)`; [`RadialMotion::kepler`] uses that form, which
//! stays exact for `e → 0` (where the two apsides merge and the integrals tend to their
//! circular-orbit limits) and for `e → 1`. Any other potential goes through the generic root
//! search and derivative-form reduced radicand of [`Libration::from_radicand`].

use crate::error::{finite, positive, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::special::turning_points::{
    Factored, Libration, Node, Quadrature, Radicand, ReducedRadicand,
};
use crate::systems::Central;
pub use crate::systems::{CentralPotential, InverseDistance};
use nalgebra::SVector;
use num_dual::DualNum;
use std::f64::consts::PI;

/// The radial radicand `F(r) = 2(h − V(r)) − k²/r²`.
#[derive(Clone, Copy, Debug)]
pub struct RadialRadicand<V> {
    potential: V,
    h: f64,
    k: f64,
}

impl<V: CentralPotential> Radicand for RadialRadicand<V> {
    fn radicand<D: DualNum<f64> + Copy>(&self, r: D) -> D {
        (-self.potential.potential(r) + self.h) * 2.0 - (r * r).recip() * (self.k * self.k)
    }
}

/// The exact reduced radicand of the Kepler problem, `P(r) = −2h/r²`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeplerReduced {
    minus_two_h: f64,
}

impl ReducedRadicand for KeplerReduced {
    fn reduced(&self, r: f64, _d1: f64, _d2: f64) -> f64 {
        self.minus_two_h / (r * r)
    }
}

/// Bound radial motion of a central-force problem between its apsides, by quadrature.
///
/// Time and angle are measured from periapsis (`t = 0`, `θ = 0`), the radius increasing first.
#[derive(Clone, Debug)]
pub struct RadialMotion<P> {
    libration: Libration<P>,
    h: f64,
    k: f64,
    half_period: Quadrature,
    half_angle: Quadrature,
}

impl<V: CentralPotential> RadialMotion<Factored<RadialRadicand<V>>> {
    /// Radial motion in the potential `V` with energy `h` and angular momentum `k ≠ 0`; `r_inside`
    /// is a radius the motion passes through (`F(r_inside) > 0`). The apsides are searched in
    /// `(0, r_max]`.
    pub fn new(potential: V, h: f64, k: f64, r_inside: f64, r_max: f64) -> Result<Self> {
        let h = finite("energy h", h)?;
        let k = nonzero_k(k)?;
        let r_inside = positive("interior radius", r_inside)?;
        let radicand = RadialRadicand { potential, h, k };
        // The centrifugal barrier keeps the motion away from r = 0: search down to a radius where
        // it already dominates any reasonable potential.
        let floor = r_inside * 1e-12;
        let libration = Libration::from_radicand(radicand, r_inside, floor, r_max)?;
        Self::from_libration(libration, h, k)
    }
}

impl<V: CentralPotential + Clone> RadialMotion<Factored<RadialRadicand<V>>> {
    /// The radial motion through the Cartesian state `(q, p)` of a [`Central`] system: energy
    /// `h = |p|²/2 + V(|q|)`, angular momentum `k = |q × p|`, the apsides searched in
    /// `(0, r_max]`. A state at an apsis (`ṙ = 0`) is accepted.
    pub fn from_state<const N: usize>(
        system: &Central<V, N>,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        r_max: f64,
    ) -> Result<Self> {
        crate::phase::check_phase(0.0, q, p)?;
        let h = finite("energy h", system.value(0.0, q, p)?)?;
        let k = nonzero_k(system.angular_momentum(q, p))?;
        let r = positive("radius |q|", q.norm())?;
        let r_max = positive("largest radius searched", r_max)?;
        let radicand = RadialRadicand {
            potential: system.central_potential().clone(),
            h,
            k,
        };
        let inside =
            crate::special::turning_points::interior_point(&radicand, r, r * 1e-12, r_max)?;
        Self::new(system.central_potential().clone(), h, k, inside, r_max)
    }
}

impl RadialMotion<KeplerReduced> {
    /// Kepler motion `V = −μ/r` with energy `h < 0` and angular momentum `k ≠ 0`, with the exact
    /// factorisation of the radicand.
    ///
    /// The eccentricity `e = √(1 + 2hk²/μ²)` is computed from these constants; for nearly circular
    /// orbits its radicand can round to a tiny negative number: values down to `−8ε` (the rounding
    /// of `1 + 2hk²/μ²`) are taken as the circular orbit `e = 0`, anything below is an energy under
    /// the minimum of the effective potential and an error. Use [`RadialMotion::kepler_elements`]
    /// when `a` and `e` are known, which avoids the cancellation.
    pub fn kepler(mu: f64, h: f64, k: f64) -> Result<Self> {
        let mu = positive("gravitational parameter μ", mu)?;
        let h = finite("energy h", h)?;
        let k = nonzero_k(k)?;
        if h >= 0.0 {
            return Err(Error::out_of_domain(
                "Kepler energy h",
                h,
                "(−∞, 0): bound orbits (the radial motion is unbounded otherwise)",
            ));
        }
        let e2 = 1.0 + 2.0 * h * k * k / (mu * mu);
        if e2 < -8.0 * f64::EPSILON {
            return Err(Error::out_of_domain(
                "1 + 2hk²/μ² (eccentricity squared)",
                e2,
                "[0, 1): the energy lies below the circular-orbit minimum for this k",
            ));
        }
        let e = e2.max(0.0).sqrt();
        Self::kepler_apsides(mu, h, k, e)
    }

    /// Kepler motion from the semi-major axis `a > 0` and eccentricity `e ∈ [0, 1)`
    /// (`h = −μ/(2a)`, `k = √(μ a (1 − e²))`).
    pub fn kepler_elements(mu: f64, a: f64, e: f64) -> Result<Self> {
        let mu = positive("gravitational parameter μ", mu)?;
        let a = positive("semi-major axis a", a)?;
        let e = finite("eccentricity e", e)?;
        if !(0.0..1.0).contains(&e) {
            return Err(Error::out_of_domain("eccentricity e", e, "[0, 1)"));
        }
        let h = -mu / (2.0 * a);
        let k = (mu * a * (1.0 - e) * (1.0 + e)).sqrt();
        Self::kepler_apsides(mu, h, k, e)
    }

    fn kepler_apsides(mu: f64, h: f64, k: f64, e: f64) -> Result<Self> {
        let ra = (mu + mu * e) / (-2.0 * h);
        let rp = k * k / (mu + mu * e);
        let libration = Libration::new(
            rp.min(ra),
            ra.max(rp),
            KeplerReduced {
                minus_two_h: -2.0 * h,
            },
        )?;
        Self::from_libration(libration, h, k)
    }
}

impl<P: ReducedRadicand> RadialMotion<P> {
    fn from_libration(libration: Libration<P>, h: f64, k: f64) -> Result<Self> {
        let half_period = libration.integrate_full(time_density)?;
        let half_angle = libration.integrate_full(|n| angle_density(k, n))?;
        Ok(Self {
            libration,
            h,
            k,
            half_period,
            half_angle,
        })
    }

    /// The libration interval `[r_p, r_a]`.
    pub fn libration(&self) -> &Libration<P> {
        &self.libration
    }
    /// Energy `h`.
    pub fn energy(&self) -> f64 {
        self.h
    }
    /// Angular momentum `k`.
    pub fn angular_momentum(&self) -> f64 {
        self.k
    }
    /// Periapsis (lower apsis) radius.
    pub fn periapsis(&self) -> f64 {
        self.libration.lower()
    }
    /// Apoapsis (upper apsis) radius.
    pub fn apoapsis(&self) -> f64 {
        self.libration.upper()
    }
    /// `∫_{r_p}^{r_a} dr/ṙ`: half the radial period.
    pub fn half_period(&self) -> Quadrature {
        self.half_period
    }
    /// `∫_{r_p}^{r_a} k dr/(r² ṙ)`: the angle swept from periapsis to apoapsis (the apsidal angle).
    pub fn apsidal_angle(&self) -> Quadrature {
        self.half_angle
    }
    /// The radial action `J_r = (1/π) ∫_{r_p}^{r_a} ṙ dr` [Ardema 17.5].
    pub fn radial_action(&self) -> Result<Quadrature> {
        Ok(self.libration.sqrt_integral()?.scale(1.0 / PI))
    }

    /// Time and swept angle from periapsis to radius `r` on the outbound leg [Ardema 10.1].
    pub fn from_periapsis(&self, r: f64) -> Result<(Quadrature, Quadrature)> {
        let s = self.libration.phase(r)?;
        Ok((
            self.libration.integrate_between(time_density, 0.0, s)?,
            self.libration
                .integrate_between(|n| angle_density(self.k, n), 0.0, s)?,
        ))
    }

    /// The state `(r, ṙ, θ)` at time `t` (periapsis at `t = 0`, `θ = 0`), by inverting the time law
    /// (Newton on the quadrature). `θ` accumulates over revolutions.
    pub fn state_at(&self, t: f64) -> Result<(f64, f64, f64)> {
        let t = finite("time t", t)?;
        let half = self.half_period.value;
        check_time_resolution(t, 2.0 * half)?;
        let revolutions = (t / (2.0 * half)).floor();
        let tau = t - revolutions * 2.0 * half;
        let (outbound, target) = if tau <= half {
            (true, tau)
        } else {
            (false, 2.0 * half - tau)
        };
        let target = target.clamp(0.0, half);
        let (s, _) = self.libration.solve_phase(time_density, target, half)?;
        let node = self.libration.node(s);
        let swept = self
            .libration
            .integrate_between(|n| angle_density(self.k, n), 0.0, s)?
            .value;
        let full = 2.0 * self.half_angle.value;
        let (rdot, theta) = if outbound {
            (node.sqrt_radicand(), revolutions * full + swept)
        } else {
            (-node.sqrt_radicand(), revolutions * full + full - swept)
        };
        Ok((node.x, rdot, theta))
    }
}

/// Refuses times whose rounding (`ulp(t)`) is a sizeable fraction (> 1e−6) of the period: the
/// phase would be meaningless.
pub(crate) fn check_time_resolution(t: f64, period: f64) -> Result<()> {
    if t.abs() * f64::EPSILON > 1e-6 * period {
        return Err(Error::out_of_domain(
            "time t",
            t,
            format!(
                "|t| ≤ {:e} (beyond, ulp(t) exceeds 1e−6 of the period {period})",
                1e-6 * period / f64::EPSILON
            ),
        ));
    }
    Ok(())
}

fn nonzero_k(k: f64) -> Result<f64> {
    let k = finite("angular momentum k", k)?;
    if k == 0.0 {
        return Err(Error::out_of_domain(
            "angular momentum k",
            k,
            "k ≠ 0 (radial fall through the centre has no apsides)",
        ));
    }
    Ok(k)
}

/// `dt/ds = 1/√P`.
fn time_density(n: &Node) -> f64 {
    n.reduced.sqrt().recip()
}

/// `dθ/ds = k/(r² √P)`.
fn angle_density(k: f64, n: &Node) -> f64 {
    k / (n.x * n.x * n.reduced.sqrt())
}

/// Time and angle between radii `r₀` and `r₁` on one leg of the orbit in the potential `V` for a
/// particle of mass `m`, energy `h` and angular momentum `K = m r² θ̇` [Ardema 10.1]:
/// `(∫ dr/ṙ, ∫ (K/(m r²)) dr/ṙ)` with `ṙ² = (2/m)(h − V) − K²/(m² r²)`, both end points allowed to
/// be apsides. `r_max` bounds the apsis search (the
/// outer apsis must be bracketed). Returns `(Δt, Δθ)`, negative when `r₁ < r₀`, zero when
/// `r₀ = r₁`.
#[allow(clippy::too_many_arguments)]
pub fn central_quadrature<V: CentralPotential>(
    potential: V,
    m: f64,
    h: f64,
    k: f64,
    r0: f64,
    r1: f64,
    r_max: f64,
) -> Result<(Quadrature, Quadrature)> {
    let m = positive("mass m", m)?;
    let (r0, r1) = (positive("r₀", r0)?, positive("r₁", r1)?);
    if r0 == r1 {
        let zero = Quadrature {
            value: 0.0,
            error: 0.0,
            evaluations: 0,
        };
        return Ok((zero, zero));
    }
    let per_mass = PerMass { potential, m };
    let inside = 0.5 * (r0 + r1);
    let motion = RadialMotion::new(per_mass, h / m, k / m, inside, r_max)?;
    let (s0, s1) = (motion.libration.phase(r0)?, motion.libration.phase(r1)?);
    let kk = k / m;
    Ok((
        motion.libration.integrate_signed(time_density, s0, s1)?,
        motion
            .libration
            .integrate_signed(|n| angle_density(kk, n), s0, s1)?,
    ))
}

/// `V/m` for a particle of mass `m`.
#[derive(Clone, Copy, Debug)]
struct PerMass<V> {
    potential: V,
    m: f64,
}

impl<V: CentralPotential> CentralPotential for PerMass<V> {
    fn potential<D: DualNum<f64> + Copy>(&self, r: D) -> D {
        self.potential.potential(r) / self.m
    }
}

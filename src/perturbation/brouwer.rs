//! Brouwer's analytic theory of the main problem of artificial-satellite motion (`J₂` only),
//! closed in the eccentricity, with Lyddane's non-singular variables for small `e` and `i`.
//!
//! The Hamiltonian per unit mass is `H = |p|²/2 − μ/r + U_{J₂}` ([`J2`]); in Delaunay variables
//! `(l, g, h; L, G, H)` with `L = √(μa)`, `G = L√(1 − e²)`, `H = G cos i`, a canonical
//! near-identity transformation (von Zeipel's method, Brouwer 1959) takes it to the secular
//! Hamiltonian
//!
//! ```math
//! K(L'', G'', H'') = -\frac{\mu^2}{2L''^2}
//! + \frac{\mu^2}{L''^2}\Big[\gamma_2'\,\frac{\eta}{2}(1 - 3\theta^2)
//! + \gamma_2'^2\,\frac{3\eta}{32}\big(5 - 4\eta - 5\eta^2 + (-10 + 24\eta + 18\eta^2)\theta^2
//!   - (35 + 36\eta + 5\eta^2)\theta^4\big)\Big] + O(J_2^3),
//! ```
//!
//! with `η = G''/L''`, `θ = H''/G''` and `γ₂' = J₂R²μ²/(2G''⁴) = (J₂/2)(R/p'')²`. The mean
//! elements move uniformly at `l̇ = ∂K/∂L`, `ġ = ∂K/∂G`, `ḣ = ∂K/∂H`: these are Brouwer's
//! second-order secular motions of `l''`, `g''`, `h''` (Brouwer 1959, without the `J₄` terms;
//! Hoots & Roehrich 1980), computed here by differentiating `K` with dual numbers
//! ([`secular_hamiltonian`], [`brouwer_secular_rates`]).
//!
//! The osculating elements are the mean ones plus the first-order long-period and short-period
//! terms, closed form in `e` (no expansion in the eccentricity): Brouwer 1959 as written
//! with Lyddane's (1963) combinations `e cos l`, `e sin l`, `sin(i/2) cos h`, `sin(i/2) sin h`
//! and `l + g + h`, which stay regular as `e → 0` and `i → 0` (Schaub & Junkins, *Analytical
//! Mechanics of Space Systems*, 4th ed., AIAA 2018, Appendix F, eqs. F.7–F.22, with the term
//! of `δ(l + g + h)` through `e(L, G)` written out from Brouwer's generator):
//! [`mean_to_osculating`]. The inverse map [`osculating_to_mean`] is a fixed-point iteration on
//! Lyddane's variables.
//!
//! # The mean semi-major axis
//! Inverting a first-order map leaves an `O(J₂²)` error in the mean `L''`, that is in the mean
//! motion, and the along-track error then grows like `J₂² n t`. [`BrouwerLyddane`] fixes `L''` by
//! the energy integral instead: `K(L'', G'', H'') = H(q, p)` at the osculating initial state, with
//! `K` to second order, so that `L''` is right to `O(J₂³)` and the position error is `O(J₂²)`
//! (the neglected second-order periodic terms) until `J₂³ n t` takes over ([`MeanAxis`]).
//!
//! # Domain
//! * `e < 1` (elliptic), `|J₂|(R/p)² ≤` [`MAX_SMALL_PARAMETER`];
//! * the long-period terms carry the divisor `1 − 5 cos² i`, which vanishes at the critical
//!   inclination `cos² i = 1/5` (`i ≈ 63.43°`, `116.57°`): within
//!   [`CRITICAL_INCLINATION_DISTANCE`] of it in `|1 − 5 cos² i|` the theory refuses with a typed
//!   error (Lyddane's variables cure `e → 0` and `i → 0`, not this resonance);
//! * Lyddane's variables use `sin(i/2)`: retrograde equatorial orbits (`i → π`) stay singular;
//! * a mean perigee `a(1 − e)` inside `R` is reported as a [`TheoryWarning`] — the potential is
//!   the exterior one, but the theory itself is regular there.
//!
//! # References
//! * D. Brouwer, "Solution of the problem of artificial satellite theory without drag",
//!   Astron. J. 64, 378–397 (1959).
//! * R. H. Lyddane, "Small eccentricities or inclinations in the Brouwer theory of the
//!   artificial satellite", Astron. J. 68, 555–558 (1963).
//! * F. R. Hoots & R. L. Roehrich, *Models for Propagation of NORAD Element Sets*, Spacetrack
//!   Report No. 3 (1980), the Brouwer–Lyddane core of SGP4.
//! * H. Schaub & J. L. Junkins, *Analytical Mechanics of Space Systems*, 4th ed., AIAA (2018),
//!   Appendix F.
//! * D. A. Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed., Microcosm (2013),
//!   §9.7.

use super::forces::J2;
use super::kepler_variation::{j2_secular_rates, J2SecularRates};
use super::variation::DisturbingFunction;
use crate::ad::gradient;
use crate::error::{finite, positive, Error, Result};
use crate::phase::CanonicalPair;
use crate::special::kepler_equation::eccentric_anomaly;
use crate::systems::kepler::elements::{elliptic_perifocal, orient, state_to_classical, Classical};
use crate::systems::kepler::orbit::{self, phase_advance};
use nalgebra::{SVector, Vector3};
use num_dual::{Dual64, DualNum};
use std::f64::consts::{PI, TAU};

/// The largest accepted small parameter `|J₂|(R/p)²` (`p` the semi-latus rectum of the mean
/// orbit). The neglected terms are `O((J₂(R/p)²)²)` relative; at the bound they are about
/// `10⁻⁴` of the orbit size.
pub const MAX_SMALL_PARAMETER: f64 = 1e-2;

/// The smallest accepted `|1 − 5 cos² i|` (distance from the critical inclination) of the mean
/// orbit: the long-period terms are proportional to `1/(1 − 5 cos² i)` and
/// `1/(1 − 5 cos² i)²`, and the first-order theory does not hold where they are large.
pub const CRITICAL_INCLINATION_DISTANCE: f64 = 1e-2;

/// Tolerance of the osculating → mean iteration: the largest change of Lyddane's variables
/// (`a` relative, the others absolute) at which it stops.
pub const OSCULATING_TO_MEAN_TOLERANCE: f64 = 1e-14;

/// Iteration limit of the osculating → mean iteration (each step contracts the residual by a
/// factor `O(J₂(R/p)²)`, so a handful of steps suffice).
pub const OSCULATING_TO_MEAN_ITERATIONS: usize = 50;

/// A statement about the model that does not stop the theory.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum TheoryWarning {
    /// The mean perigee radius `a(1 − e)` is smaller than the reference radius `R`: the orbit
    /// passes inside the body, where the exterior `J₂` potential is not the body's field.
    PerigeeInsideBody {
        /// `a''(1 − e'')`.
        perigee: f64,
        /// `R`.
        radius: f64,
    },
}

/// How [`BrouwerLyddane`] fixes the mean semi-major axis from an osculating state.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum MeanAxis {
    /// `K(L'', G'', H'') = H(q, p)` with `K` to second order ([`secular_hamiltonian`]):
    /// `L''` to `O(J₂³)`.
    #[default]
    EnergyIntegral,
    /// `a''` as the inverse of the first-order map gives it ([`osculating_to_mean`]): an
    /// `O(J₂²)` error in the mean motion.
    FirstOrderInverse,
}

/// The secular Hamiltonian `K(L, G, H)` of the `J₂` problem to second order (Brouwer 1959,
/// `F₀ + F₁* + F₂*` without `J₄`, with the sign of an energy), in any dual type:
///
/// ```math
/// K = -\frac{\mu^2}{2L^2} + \frac{\mu^2}{L^2}\Big[\gamma_2'\frac{\eta}{2}(1 - 3\theta^2)
/// + \gamma_2'^2\frac{3\eta}{32}\big(5 - 4\eta - 5\eta^2
/// + (-10 + 24\eta + 18\eta^2)\theta^2 - (35 + 36\eta + 5\eta^2)\theta^4\big)\Big],
/// ```
///
/// `η = G/L`, `θ = H/G`, `γ₂' = J₂R²μ²/(2G⁴)`. Its gradient is the vector of secular rates
/// `(l̇, ġ, ḣ)`. No domain checks (a formula; see [`BrouwerLyddane`]).
pub fn secular_hamiltonian<D: DualNum<f64> + Copy>(
    mu: f64,
    radius: f64,
    j2: D,
    big_l: D,
    big_g: D,
    big_h: D,
) -> D {
    let mu2 = mu * mu;
    let eta = big_g / big_l;
    let th2 = (big_h / big_g).powi(2);
    let g2 = big_g * big_g;
    let gp = j2 * (0.5 * radius * radius * mu2) / (g2 * g2);
    let nl = big_l.powi(2).recip() * mu2;
    let first = eta * (-th2 * 3.0 + 1.0) * 0.5;
    let second = eta
        * 3.0
        * (-eta * 4.0 - eta * eta * 5.0 + 5.0 + (eta * 24.0 + eta * eta * 18.0 - 10.0) * th2
            - (eta * 36.0 + eta * eta * 5.0 + 35.0) * th2 * th2)
        / 32.0;
    nl * (-0.5) + nl * gp * (first + gp * second)
}

/// Brouwer's second-order secular rates of the mean elements at the mean `(a, e, i)`:
/// `Ṁ − n = ∂K/∂L − n`, `ω̇ = ∂K/∂G`, `Ω̇ = ∂K/∂H` ([`secular_hamiltonian`]), `n = √(μ/a³)`.
/// To first order they are [`j2_secular_rates`].
///
/// # Errors
/// Non-finite input, `a ≤ 0`, `e ∉ [0, 1)`, `i ∉ [0, π]`,
/// `|J₂|(R/p)² > MAX_SMALL_PARAMETER`.
pub fn brouwer_secular_rates(model: &J2, a: f64, e: f64, i: f64) -> Result<J2SecularRates> {
    let (j2, radius) = (model.j2(), model.radius());
    // The domain of the first-order rates, and n.
    let n = j2_secular_rates(model, a, e, i)?.mean_motion;
    check_small_parameter(j2, radius, a, e)?;
    let (_, grad) = scaled_secular(radius / a, j2, e, i);
    let rates = J2SecularRates {
        raan: n * grad[2],
        argp: n * grad[1],
        mean_anomaly: n * (grad[0] - 1.0),
        mean_motion: n,
    };
    if [rates.raan, rates.argp, rates.mean_anomaly]
        .iter()
        .all(|r| r.is_finite())
    {
        Ok(rates)
    } else {
        Err(Error::out_of_domain(
            "Brouwer secular rate (overflow)",
            rates.mean_anomaly,
            "finite rates",
        ))
    }
}

/// `K/(μ/a)` and `(l̇, ġ, ḣ)/n` at `(R/a, J₂, e, i)`: [`secular_hamiltonian`] in the units
/// `μ = a = 1` (where `L = 1`, `n = 1`), so that no power of `μ` or `a` over- or underflows.
fn scaled_secular(radius_over_a: f64, j2: f64, e: f64, i: f64) -> (f64, SVector<f64, 3>) {
    let eta = ((1.0 - e) * (1.0 + e)).sqrt();
    gradient(
        |x| secular_hamiltonian(1.0, radius_over_a, j2.into(), x[0], x[1], x[2]),
        &SVector::from([1.0, eta, eta * i.cos()]),
    )
}

fn check_orbit(e: f64, i: f64) -> Result<()> {
    let e = finite("eccentricity e", e)?;
    if !(0.0..1.0).contains(&e) {
        return Err(Error::out_of_domain("eccentricity e", e, "[0, 1)"));
    }
    let i = finite("inclination i", i)?;
    if !(0.0..=PI).contains(&i) {
        return Err(Error::out_of_domain("inclination i", i, "[0, π]"));
    }
    Ok(())
}

fn check_small_parameter(j2: f64, radius: f64, a: f64, e: f64) -> Result<f64> {
    let p = a * (1.0 - e) * (1.0 + e);
    let eps = j2.abs() * (radius / p).powi(2);
    if eps.is_finite() && eps <= MAX_SMALL_PARAMETER {
        Ok(eps)
    } else {
        Err(Error::out_of_domain(
            "small parameter |J₂|(R/p)² of the J₂ theory",
            eps,
            format!("[0, {MAX_SMALL_PARAMETER:e}]"),
        ))
    }
}

fn check_critical(i: f64, j2: f64) -> Result<()> {
    let c = i.cos();
    let d = 1.0 - 5.0 * c * c;
    if j2 != 0.0 && d.abs() < CRITICAL_INCLINATION_DISTANCE {
        return Err(Error::out_of_domain(
            format!(
                "distance 1 − 5cos²i from the critical inclination (i = {i}; the long-period \
                 terms have the divisor 1 − 5cos²i)"
            ),
            d,
            format!("|1 − 5cos²i| ≥ {CRITICAL_INCLINATION_DISTANCE:e}"),
        ));
    }
    Ok(())
}

/// The first-order periodic terms at fixed mean `(a, e, i)`: the constants of the map, shared by
/// every evaluation along the mean orbit.
#[derive(Clone, Copy, Debug, PartialEq)]
struct PeriodicTerms<D> {
    a: D,
    e: D,
    eta: D,
    /// `γ₂ = (J₂/2)(R/a)²`, `γ₂' = γ₂/η⁴`.
    gamma2: D,
    gp: D,
    c: D,
    s: D,
    c2: D,
    /// `sin(i/2)`, `cos(i/2)`.
    sh: D,
    ch: D,
    // Long-period amplitudes (coefficients of cos 2ω, sin 2ω).
    de_lp: D,
    di_lp: D,
    dlam_lp: D,
    edm_lp: D,
    dnode_lp: D,
}

impl<D: DualNum<f64> + Copy> PeriodicTerms<D> {
    /// Brouwer's first-order long-period amplitudes at the mean `(a, e, i)`; Schaub & Junkins
    /// eqs. F.8, F.10–F.13 (the `2ω` terms), with
    /// `1 − 11cos²i − 40cos⁴i/(1 − 5cos²i) = sin²i (1 − 15cos²i)/(1 − 5cos²i)` so that
    /// `e δe/(η² tan i)` is regular at `i = 0`.
    fn new(radius: f64, j2: D, a: D, e: D, i: D) -> Self {
        let eta = ((-e + 1.0) * (e + 1.0)).sqrt();
        let gamma2 = j2 * 0.5 * (a.recip() * radius).powi(2);
        let eta2 = eta * eta;
        let gp = gamma2 / (eta2 * eta2);
        let (s, c) = i.sin_cos();
        let (sh, ch) = (i * 0.5).sin_cos();
        let c2 = c * c;
        let s2 = s * s;
        let den = -c2 * 5.0 + 1.0;
        let lp = s2 * (-c2 * 15.0 + 1.0) / den;
        let e2 = e * e;
        let de_lp = gp / 8.0 * e * eta2 * lp;
        let di_lp = -gp / 8.0 * e2 * (-c2 * 15.0 + 1.0) / den * s * c;
        let node = c * e2 * (c2 * 80.0 / den + c2 * c2 * 200.0 / (den * den) + 11.0);
        let dnode_lp = -gp / 8.0 * node;
        let eta3 = eta2 * eta;
        let dlam_lp = gp / 8.0 * eta3 * lp
            - gp / 16.0
                * (e2 + 2.0
                    - (e2 * 3.0 + 2.0) * c2 * 11.0
                    - (e2 * 5.0 + 2.0) * c2 * c2 * 40.0 / den
                    - e2 * c2 * c2 * c2 * 400.0 / (den * den))
            + dnode_lp;
        let edm_lp = gp / 8.0 * e * eta3 * lp;
        Self {
            a,
            e,
            eta,
            gamma2,
            gp,
            c,
            s,
            c2,
            sh,
            ch,
            de_lp,
            di_lp,
            dlam_lp,
            edm_lp,
            dnode_lp,
        }
    }

    /// The osculating elements at the mean angles `(Ω, ω, M)`: Schaub & Junkins eqs.
    /// F.7–F.22, in Lyddane's combinations; with the mean `M` reduced to `(−π, π]` and its
    /// eccentric anomaly `E`.
    ///
    /// The short-period terms are those of Brouwer's first-order generator
    /// `W = (γ₂'G/2)[(1 − 3cos²i) φ − (3/2) sin²i Ψ]`, `φ = f − l + e sin f`,
    /// `Ψ = sin(2ω+2f) + e sin(2ω+f) + (e/3) sin(2ω+3f)`, `δx = {x, W}`. In
    /// `δ(l + g + h) = ∂W/∂L + ∂W/∂G + ∂W/∂H` the part through `e(L, G)` at fixed `l`,
    /// `−(η e/((1 + η) L)) ∂W/∂e`, is added explicitly to the F.11 expression (without it the
    /// osculating mean longitude carries an `O(J₂)` error, `0.1–0.6 γ₂'` at `e = 0.1–0.7`,
    /// measured against the integrated orbit).
    fn lyddane(&self, raan: D, argp: D, mean_anomaly: D) -> Result<Lyddane<D>> {
        let &Self {
            a,
            e,
            eta,
            gamma2,
            gp,
            c,
            s,
            c2,
            sh,
            ch,
            ..
        } = self;
        let m = mean_anomaly - (mean_anomaly.re() / TAU).round() * TAU;
        let big_e = eccentric_anomaly(m, e)?;
        let (se, ce) = big_e.sin_cos();
        let rho = -e * ce + 1.0;
        let (sf, cf) = (eta * se / rho, (ce - e) / rho);
        let f = sf.atan2(cf);
        let ar = rho.recip();
        let (s2w, c2w) = (argp * 2.0).sin_cos();
        let (s2f, c2f) = (sf * cf * 2.0, cf * cf - sf * sf);
        let (s3f, c3f) = (sf * (-sf * sf * 4.0 + 3.0), cf * (cf * cf * 4.0 - 3.0));
        let sin_wf = s2w * cf + c2w * sf;
        let cos_wf = c2w * cf - s2w * sf;
        let sin_w2f = s2w * c2f + c2w * s2f;
        let cos_w2f = c2w * c2f - s2w * s2f;
        let sin_w3f = s2w * c3f + c2w * s3f;
        let cos_w3f = c2w * c3f - s2w * s3f;
        let e2 = e * e;
        let eta2 = eta * eta;
        let eta3 = eta2 * eta;
        let eta6 = eta3 * eta3;
        let s2 = s * s;
        let th = c2 * 3.0 - 1.0;
        let ar3 = ar * ar * ar;
        // F.7: the semi-major axis (short-period only).
        let a_osc = a + a * gamma2 * (th * (ar3 - eta3.recip()) + s2 * ar3 * cos_w2f * 3.0);
        // F.8, F.9: the eccentricity.
        let cubic = cf * 3.0 + e * cf * cf * 3.0 + e2 * cf * cf * cf;
        let de = self.de_lp * c2w
            + eta2
                * 0.5
                * (gamma2 / eta6
                    * (th * (e * eta + e / (eta + 1.0) + cubic)
                        + s2 * 3.0 * (e + cubic) * cos_w2f)
                    - gp * s2 * (cos_wf * 3.0 + cos_w3f));
        // F.10: the inclination.
        let di =
            self.di_lp * c2w + gp * 0.5 * c * s * (cos_w2f * 3.0 + e * cos_wf * 3.0 + e * cos_w3f);
        // F.11, F.13: l + g + h and the node.
        let centre = f - m + e * sf;
        let wave = sin_w2f * 3.0 + e * sin_wf * 3.0 + e * sin_w3f;
        let dnode_sp = -gp * 0.5 * c * (centre * 6.0 - wave);
        let dnode = self.dnode_lp * s2w + dnode_sp;
        // The part of δl + δg = ∂W/∂L + ∂W/∂G that comes through e(L, G) at fixed l:
        // −(η e/((1 + η) L)) ∂W/∂e, with W Brouwer's first-order generator
        // W = (γ₂'G/2)[(1 − 3cos²i) φ − (3/2) sin²i Ψ], φ = f − l + e sin f,
        // Ψ = sin(2ω+2f) + e sin(2ω+f) + (e/3) sin(2ω+3f), and η² ∂f/∂e = sin f (2 + e cos f).
        let fe = sf * (e * cf + 2.0);
        let phi_e = fe * (e * cf + 1.0) + eta2 * sf;
        let psi_e =
            fe * (cos_w2f * 2.0 + e * cos_wf + e * cos_w3f) + eta2 * (sin_wf + sin_w3f / 3.0);
        let through_e = -gp * 0.5 * e / (eta + 1.0) * (-th * phi_e - s2 * 1.5 * psi_e);
        let dlam = self.dlam_lp * s2w
            + gp * 0.25 * ((-c2 * 5.0 + 1.0) * centre * (-6.0) + (-c2 * 5.0 + 3.0) * wave)
            + dnode_sp
            + through_e;
        // F.12: e·δM.
        let q = ar * eta;
        let q2 = q * q;
        let edm = self.edm_lp * s2w
            - gp * 0.25
                * eta3
                * (th * (q2 + ar + 1.0) * sf * 2.0
                    + s2 * 3.0 * ((-q2 - ar + 1.0) * sin_wf + (q2 + ar + 1.0 / 3.0) * sin_w3f));
        // F.14–F.22: Lyddane's combinations.
        let (sm, cm) = m.sin_cos();
        let d1 = (e + de) * sm + edm * cm;
        let d2 = (e + de) * cm - edm * sm;
        let (so, co) = raan.sin_cos();
        let x = sh + ch * di * 0.5;
        let y = sh * dnode;
        Ok(Lyddane {
            a: a_osc,
            e_sin_m: d1,
            e_cos_m: d2,
            sin_half_i_sin_node: x * so + y * co,
            sin_half_i_cos_node: x * co - y * so,
            lambda: m + argp + raan + dlam,
            m,
            big_e,
        })
    }

    /// [`PeriodicTerms::lyddane`] as classical elements, with the mean `M` reduced to
    /// `(−π, π]` and its eccentric anomaly `E`.
    fn osculating(&self, raan: D, argp: D, mean_anomaly: D) -> Result<(Classical<D>, D, D)> {
        let l = self.lyddane(raan, argp, mean_anomaly)?;
        Ok((l.classical(), l.m, l.big_e))
    }
}

/// The osculating elements in Lyddane's combinations (Schaub & Junkins eqs. F.14–F.22):
/// `(a, e sin M, e cos M, sin(i/2) sin Ω, sin(i/2) cos Ω, λ = M + ω + Ω)`, with the mean `M`
/// (reduced to `(−π, π]`) and its eccentric anomaly `E` the terms were evaluated at.
#[derive(Clone, Copy, Debug)]
struct Lyddane<D> {
    a: D,
    e_sin_m: D,
    e_cos_m: D,
    sin_half_i_sin_node: D,
    sin_half_i_cos_node: D,
    lambda: D,
    m: D,
    big_e: D,
}

/// `(sin φ, cos φ)` of `φ = atan2(ρ sin φ, ρ cos φ)` from `(ρ sin φ, ρ cos φ)` and `ρ ≥ 0`:
/// `(0, 1)` at `ρ = 0`, as `atan2(0, 0) = 0`.
fn unit<D: DualNum<f64> + Copy>(rho_sin: D, rho_cos: D, rho: D) -> (D, D) {
    if rho.re() > 0.0 {
        (rho_sin / rho, rho_cos / rho)
    } else {
        (D::from(0.0), D::from(1.0))
    }
}

impl<D: DualNum<f64> + Copy> Lyddane<D> {
    fn eccentricity(&self) -> D {
        (self.e_sin_m * self.e_sin_m + self.e_cos_m * self.e_cos_m).sqrt()
    }

    fn sin_half_i(&self) -> D {
        let (d3, d4) = (self.sin_half_i_sin_node, self.sin_half_i_cos_node);
        (d3 * d3 + d4 * d4).sqrt()
    }

    fn classical(&self) -> Classical<D> {
        let m_osc = self.e_sin_m.atan2(self.e_cos_m);
        let raan_osc = self.sin_half_i_sin_node.atan2(self.sin_half_i_cos_node);
        let sin_half = self.sin_half_i();
        let i_osc = if sin_half.re() >= 1.0 {
            D::from(PI)
        } else {
            sin_half.asin() * 2.0
        };
        Classical {
            a: self.a,
            e: self.eccentricity(),
            i: i_osc,
            raan: raan_osc,
            argp: self.lambda - m_osc - raan_osc,
            mean_anomaly: m_osc,
        }
    }

    /// The sines and cosines of `(Ω, i, ω)` without the angles: `Ω` and `M` from their Lyddane
    /// pairs, `cos i = 1 − 2 sin²(i/2)`, `sin i = 2 sin(i/2) cos(i/2)`, and
    /// `ω = (λ − Ω) − M` by the addition theorems from `sin λ`, `cos λ` (one `sin_cos`).
    fn orientation(&self, e_osc: D) -> [(D, D); 3] {
        let (so, co) = unit(
            self.sin_half_i_sin_node,
            self.sin_half_i_cos_node,
            self.sin_half_i(),
        );
        let sh = self.sin_half_i();
        let (si, ci) = if sh.re() >= 1.0 {
            (D::from(0.0), D::from(-1.0))
        } else {
            (
                sh * ((-sh + 1.0) * (sh + 1.0)).sqrt() * 2.0,
                -sh * sh * 2.0 + 1.0,
            )
        };
        let (sm, cm) = unit(self.e_sin_m, self.e_cos_m, e_osc);
        let (sl, cl) = self.lambda.sin_cos();
        let (su, cu) = (sl * co - cl * so, cl * co + sl * so);
        let (sw, cw) = (su * cm - cu * sm, cu * cm + su * sm);
        [(so, co), (si, ci), (sw, cw)]
    }
}

fn check_mean(mu: f64, radius: f64, j2: f64, mean: &Classical<f64>) -> Result<()> {
    positive("gravitational parameter μ", mu)?;
    positive("reference radius R", radius)?;
    finite("J₂", j2)?;
    positive("semi-major axis a", mean.a)?;
    check_orbit(mean.e, mean.i)?;
    phase_advance("longitude of the ascending node Ω", mean.raan)?;
    phase_advance("argument of periapsis ω", mean.argp)?;
    phase_advance("mean anomaly M", mean.mean_anomaly)?;
    check_small_parameter(j2, radius, mean.a, mean.e)?;
    check_critical(mean.i, j2)
}

/// Mean → osculating classical elements of the `J₂` problem: the mean elements plus Brouwer's
/// first-order long-period and short-period terms, closed form in `e`, through Lyddane's
/// non-singular combinations (Brouwer 1959; Lyddane 1963; Schaub & Junkins 2018
/// eqs. F.7–F.22). Written once for dual numbers (derivatives with respect to `J₂` and the
/// mean elements); `μ` enters only through `a`.
///
/// The error of the map is `O((J₂(R/p)²)² a)`.
///
/// # Errors
/// Non-finite input, `μ ≤ 0`, `R ≤ 0`, `a ≤ 0`, `e ∉ [0, 1)`, `i ∉ [0, π]`,
/// `|J₂|(R/p)² > MAX_SMALL_PARAMETER`, `|1 − 5cos²i| < CRITICAL_INCLINATION_DISTANCE`;
/// [`Error::PhaseLost`] for an angle beyond [`orbit::MAX_PHASE_ADVANCE`].
pub fn mean_to_osculating<D: DualNum<f64> + Copy>(
    mu: f64,
    radius: f64,
    j2: D,
    mean: &Classical<D>,
) -> Result<Classical<D>> {
    let re = Classical {
        a: mean.a.re(),
        e: mean.e.re(),
        i: mean.i.re(),
        raan: mean.raan.re(),
        argp: mean.argp.re(),
        mean_anomaly: mean.mean_anomaly.re(),
    };
    check_mean(mu, radius, j2.re(), &re)?;
    let (osc, _, _) = PeriodicTerms::new(radius, j2, mean.a, mean.e, mean.i).osculating(
        mean.raan,
        mean.argp,
        mean.mean_anomaly,
    )?;
    check_elements("osculating elements", &osc)?;
    Ok(osc)
}

fn check_elements<D: DualNum<f64> + Copy>(what: &str, el: &Classical<D>) -> Result<()> {
    let v = [el.a, el.e, el.i, el.raan, el.argp, el.mean_anomaly];
    if v.iter().all(|x| x.re().is_finite()) && el.e.re() < 1.0 && el.a.re() > 0.0 {
        Ok(())
    } else {
        Err(Error::invalid(
            what,
            format!("the J₂ theory produced a non-elliptic or non-finite element set {el:?}"),
        ))
    }
}

/// Lyddane's non-singular variables `(a, e cos ϖ, e sin ϖ, sin(i/2) cos Ω, sin(i/2) sin Ω, λ)`,
/// `ϖ = ω + Ω`, `λ = M + ω + Ω`.
fn to_lyddane(el: &Classical) -> [f64; 6] {
    let varpi = el.argp + el.raan;
    let sh = (0.5 * el.i).sin();
    [
        el.a,
        el.e * varpi.cos(),
        el.e * varpi.sin(),
        sh * el.raan.cos(),
        sh * el.raan.sin(),
        el.mean_anomaly + varpi,
    ]
}

fn from_lyddane(y: &[f64; 6]) -> Classical {
    let e = y[1].hypot(y[2]);
    let varpi = if e > 0.0 { y[2].atan2(y[1]) } else { 0.0 };
    let sh = y[3].hypot(y[4]).min(1.0);
    let raan = if sh > 0.0 { y[4].atan2(y[3]) } else { 0.0 };
    Classical {
        a: y[0],
        e,
        i: 2.0 * sh.asin(),
        raan,
        argp: varpi - raan,
        mean_anomaly: y[5] - varpi,
    }
}

fn wrap(x: f64) -> f64 {
    x - (x / TAU).round() * TAU
}

/// Osculating → mean classical elements: the inverse of [`mean_to_osculating`] by the
/// fixed-point iteration `y ← y + (x − F(y))` on Lyddane's variables (`x` osculating, `F` the
/// mean → osculating map), which contracts by a factor `O(J₂(R/p)²)` per step; stopped when the
/// change is at most [`OSCULATING_TO_MEAN_TOLERANCE`] (`a` relative), at most
/// [`OSCULATING_TO_MEAN_ITERATIONS`] steps. The result inverts the first-order map to rounding;
/// as mean elements of the `J₂` problem it is right to `O((J₂(R/p)²)²)` (see
/// [`BrouwerLyddane`] for the energy-fixed semi-major axis).
///
/// # Errors
/// As [`mean_to_osculating`] at the osculating and at every iterated element set;
/// [`Error::NotConverged`] past the iteration limit.
pub fn osculating_to_mean(model: &J2, osculating: &Classical) -> Result<Classical> {
    let (mu, j2, radius) = (model.mu(), model.j2(), model.radius());
    check_mean(mu, radius, j2, osculating)?;
    let x = to_lyddane(osculating);
    let mut y = x;
    let mut last = f64::INFINITY;
    for _ in 0..OSCULATING_TO_MEAN_ITERATIONS {
        let mean = from_lyddane(&y);
        let fy = to_lyddane(&mean_to_osculating(mu, radius, j2, &mean)?);
        let mut r = [0.0; 6];
        for k in 0..6 {
            r[k] = x[k] - fy[k];
        }
        r[5] = wrap(r[5]);
        let size = (r[0] / x[0])
            .abs()
            .max(r[1..].iter().fold(0.0f64, |m, v| m.max(v.abs())));
        for k in 0..6 {
            y[k] += r[k];
        }
        // Converged, or stalled at the rounding level of the map.
        if size <= OSCULATING_TO_MEAN_TOLERANCE || (size >= last && size <= 1e3 * f64::EPSILON) {
            let mut mean = from_lyddane(&y);
            mean.mean_anomaly = wrap(mean.mean_anomaly);
            check_mean(mu, radius, j2, &mean)?;
            return Ok(mean);
        }
        last = size;
    }
    Err(Error::NotConverged {
        what: "osculating → mean J₂ elements (fixed-point iteration)".into(),
        iterations: OSCULATING_TO_MEAN_ITERATIONS,
        residual: last,
    })
}

/// Brouwer–Lyddane theory of one orbit under `J₂`: mean elements at an epoch, their secular rates
/// to second order, and the osculating state at any time `t` by the mean → osculating map
/// (Kepler's equation solved twice per evaluation).
///
/// Built from an osculating state, whose mean elements are found by [`osculating_to_mean`] and
/// whose mean `L'' = √(μa'')` is then fixed by the energy integral
/// `K(L'', L''η'', L''η''cos i'') = |v|²/2 − μ/r + U_{J₂}(r)` (Newton's method, `e''`, `i''`
/// held), with `K` the second-order [`secular_hamiltonian`] ([`MeanAxis::EnergyIntegral`]), or
/// from mean elements directly.
#[derive(Clone, Debug, PartialEq)]
pub struct BrouwerLyddane {
    model: J2,
    epoch: f64,
    mean: Classical,
    /// `(l̇, ġ, ḣ)`.
    rates: [f64; 3],
    /// `n = √(μ/a''³)`.
    mean_motion: f64,
    energy: f64,
    warnings: Vec<TheoryWarning>,
    terms: PeriodicTerms<f64>,
}

impl BrouwerLyddane {
    /// The theory from mean elements `mean` at `epoch`.
    ///
    /// # Errors
    /// As [`mean_to_osculating`]; a non-finite epoch.
    pub fn from_mean(model: &J2, epoch: f64, mean: &Classical) -> Result<Self> {
        let (mu, j2, radius) = (model.mu(), model.j2(), model.radius());
        check_mean(mu, radius, j2, mean)?;
        finite("epoch t₀", epoch)?;
        let n = orbit::mean_motion(mu, mean.a)?;
        let (k, grad) = scaled_secular(radius / mean.a, j2, mean.e, mean.i);
        let energy = k * (mu / mean.a);
        let mut warnings = Vec::new();
        let perigee = mean.a * (1.0 - mean.e);
        if perigee < radius {
            warnings.push(TheoryWarning::PerigeeInsideBody { perigee, radius });
        }
        let theory = Self {
            model: *model,
            epoch,
            mean: *mean,
            rates: [n * grad[0], n * grad[1], n * grad[2]],
            mean_motion: n,
            energy,
            warnings,
            terms: PeriodicTerms::new(radius, j2, mean.a, mean.e, mean.i),
        };
        if !(energy.is_finite() && theory.rates.iter().all(|r| r.is_finite())) {
            return Err(Error::out_of_domain(
                "secular Hamiltonian K of the mean elements",
                energy,
                "finite",
            ));
        }
        Ok(theory)
    }

    /// The theory from osculating classical elements at `epoch`, the mean semi-major axis fixed
    /// by the energy integral.
    ///
    /// # Errors
    /// As [`BrouwerLyddane::from_state`].
    pub fn from_osculating(model: &J2, epoch: f64, osculating: &Classical) -> Result<Self> {
        check_mean(model.mu(), model.radius(), model.j2(), osculating)?;
        let (r, v) = osculating.to_state(model.mu())?;
        Self::from_state_with(model, epoch, &r, &v, MeanAxis::EnergyIntegral)
    }

    /// The theory from the osculating state `(r, v)` at `epoch`, the mean semi-major axis fixed
    /// by the energy integral ([`MeanAxis::EnergyIntegral`]).
    ///
    /// # Errors
    /// Non-finite input; a state that is not an ellipse (`e ≥ 1`); the domain
    /// errors of [`mean_to_osculating`] and [`osculating_to_mean`]; [`Error::NotConverged`] if the
    /// energy equation has no root near the iterated `L''`.
    pub fn from_state(model: &J2, epoch: f64, r: &Vector3<f64>, v: &Vector3<f64>) -> Result<Self> {
        Self::from_state_with(model, epoch, r, v, MeanAxis::EnergyIntegral)
    }

    /// As [`BrouwerLyddane::from_state`], with the mean semi-major axis fixed as `axis` says.
    ///
    /// # Errors
    /// As [`BrouwerLyddane::from_state`].
    pub fn from_state_with(
        model: &J2,
        epoch: f64,
        r: &Vector3<f64>,
        v: &Vector3<f64>,
        axis: MeanAxis,
    ) -> Result<Self> {
        let (mu, j2, radius) = (model.mu(), model.j2(), model.radius());
        finite("epoch t₀", epoch)?;
        let osc = state_to_classical(mu, r, v)?;
        if osc.e >= 1.0 {
            return Err(Error::out_of_domain(
                "osculating eccentricity e of the initial state",
                osc.e,
                "[0, 1)",
            ));
        }
        let mut mean = osculating_to_mean(model, &osc)?;
        if axis == MeanAxis::EnergyIntegral {
            let energy = 0.5 * v.norm_squared() - mu / r.norm() + model.disturbing_function(0.0, r);
            mean.a = energy_axis(mu, radius, j2, energy, &mean)?;
        }
        Self::from_mean(model, epoch, &mean)
    }

    /// The `J₂` model (`μ`, `J₂`, `R`) the theory solves.
    pub fn model(&self) -> &J2 {
        &self.model
    }
    /// The epoch `t₀` of the mean elements.
    pub fn epoch(&self) -> f64 {
        self.epoch
    }
    /// The value of the secular Hamiltonian `K(L'', G'', H'')` (the energy of the orbit to
    /// `O(J₂³)`).
    pub fn energy(&self) -> f64 {
        self.energy
    }
    /// Modelling statements about the orbit (a perigee inside the body).
    pub fn warnings(&self) -> &[TheoryWarning] {
        &self.warnings
    }

    /// The secular rates `Ṁ − n = l̇ − n`, `ω̇ = ġ`, `Ω̇ = ḣ` to second order, `n = √(μ/a''³)`.
    pub fn rates(&self) -> J2SecularRates {
        let n = self.mean_motion;
        J2SecularRates {
            raan: self.rates[2],
            argp: self.rates[1],
            mean_anomaly: self.rates[0] - n,
            mean_motion: n,
        }
    }

    /// The mean elements at `t`: `a'', e'', i''` constant, `M'' = M''₀ + l̇ (t − t₀)`,
    /// `ω'' = ω''₀ + ġ (t − t₀)`, `Ω'' = Ω''₀ + ḣ (t − t₀)`, angles reduced to `(−π, π]`.
    ///
    /// # Errors
    /// Non-finite `t`; [`Error::PhaseLost`] when `l̇ (t − t₀)` exceeds
    /// [`orbit::MAX_PHASE_ADVANCE`].
    pub fn mean_elements(&self, t: f64) -> Result<Classical> {
        let dt = finite("time t", t)? - self.epoch;
        let phase = phase_advance("Brouwer–Lyddane mean anomaly", self.rates[0] * dt)?;
        let m = &self.mean;
        Ok(Classical {
            a: m.a,
            e: m.e,
            i: m.i,
            raan: wrap(m.raan + self.rates[2] * dt),
            argp: wrap(m.argp + self.rates[1] * dt),
            mean_anomaly: wrap(m.mean_anomaly + phase),
        })
    }

    /// The osculating elements at `t` ([`mean_to_osculating`] of [`BrouwerLyddane::mean_elements`]).
    ///
    /// # Errors
    /// As [`BrouwerLyddane::mean_elements`].
    pub fn osculating_elements(&self, t: f64) -> Result<Classical> {
        Ok(self.osculating_with_anomaly(t)?.0)
    }

    /// The osculating elements at `t` and the osculating eccentric anomaly, found by Newton's
    /// method on `E − e' sin E = M'` from the mean `E`: the start is `O(J₂)` from the root, so
    /// two steps reach rounding (the error after a step `s` is at most `e' s²/(2(1 − e'))`);
    /// Kepler's equation is solved from scratch if not.
    fn osculating_with_anomaly(&self, t: f64) -> Result<(Classical, f64)> {
        let m = self.mean_elements(t)?;
        let (osc, m_mean, ea_mean) = self.terms.osculating(m.raan, m.argp, m.mean_anomaly)?;
        check_elements("osculating elements", &osc)?;
        let (x, _) = osculating_anomaly(osc.e, osc.mean_anomaly, m_mean, ea_mean)?;
        Ok((osc, x))
    }

    /// The osculating Cartesian state `(r, v)` at `t`.
    ///
    /// The same map as [`Classical::to_state`] of [`BrouwerLyddane::osculating_elements`], with
    /// the angles `Ω`, `i`, `ω` and `E` never formed: their sines and cosines come from
    /// Lyddane's pairs (`e sin M`, `e cos M`, `sin(i/2) sin Ω`, `sin(i/2) cos Ω`), the addition
    /// theorems (`ω = λ − Ω − M`) and the last Newton step of Kepler's equation, and
    /// `1 − cos E = sin²E/(1 + cos E)` where `cos E > 0`.
    ///
    /// # Errors
    /// As [`BrouwerLyddane::mean_elements`].
    pub fn state(&self, t: f64) -> Result<CanonicalPair<3>> {
        let m = self.mean_elements(t)?;
        let l = self.terms.lyddane(m.raan, m.argp, m.mean_anomaly)?;
        let e = l.eccentricity();
        let finite_parts = [
            l.a,
            e,
            l.e_sin_m,
            l.e_cos_m,
            l.sin_half_i_sin_node,
            l.sin_half_i_cos_node,
            l.lambda,
        ]
        .iter()
        .all(|x| x.is_finite());
        if !(finite_parts && e < 1.0 && l.a > 0.0) {
            check_elements("osculating elements", &l.classical())?;
            return Err(Error::invalid(
                "osculating elements",
                format!("the J₂ theory produced a non-elliptic or non-finite element set {l:?}"),
            ));
        }
        let m_osc = l.e_sin_m.atan2(l.e_cos_m);
        let (_, (se, ce)) = osculating_anomaly(e, m_osc, l.m, l.big_e)?;
        let one_minus_cos = if ce <= 0.0 {
            1.0 - ce
        } else {
            se * se / (1.0 + ce)
        };
        let [node, incl, argp] = l.orientation(e);
        orient(
            elliptic_perifocal(self.model.mu(), l.a, e, (se, ce), one_minus_cos),
            node,
            incl,
            argp,
        )
    }
}

/// The osculating eccentric anomaly `E'` and `(sin E', cos E')`, by Newton's method on
/// `E − e' sin E = M'` from the mean `E`: the start is `O(J₂)` from the root, so two steps reach
/// rounding (the error after a step `s` is at most `e' s²/(2(1 − e'))`); Kepler's equation is
/// solved from scratch if not. The sine and cosine of the last iterate `E' = x − s` come from
/// those of `x` by the addition theorems with the Taylor polynomials of `sin s`, `cos s`
/// (exact to rounding for `|s| ≤ 10⁻³`: the first omitted terms are below `10⁻²⁰`).
fn osculating_anomaly(e: f64, m_osc: f64, m_mean: f64, ea_mean: f64) -> Result<(f64, (f64, f64))> {
    let target = m_mean + wrap(m_osc - m_mean);
    let mut x = ea_mean;
    for _ in 0..8 {
        let (sx, cx) = x.sin_cos();
        let step = (x - e * sx - target) / (1.0 - e * cx);
        x -= step;
        if step * step * e <= f64::EPSILON * (1.0 - e) {
            let sc = if step.abs() <= 1e-3 {
                let s2 = step * step;
                let sin_s = step * (1.0 - s2 / 6.0 * (1.0 - s2 / 20.0));
                let cos_s = 1.0 - s2 / 2.0 * (1.0 - s2 / 12.0);
                (sx * cos_s - cx * sin_s, cx * cos_s + sx * sin_s)
            } else {
                x.sin_cos()
            };
            return Ok((x, sc));
        }
    }
    let x = eccentric_anomaly(target, e)?;
    Ok((x, x.sin_cos()))
}

/// `a''` from `K(L, Lη, Lη cos i) = E` by Newton's method from the iterated `a''`.
fn energy_axis(mu: f64, radius: f64, j2: f64, energy: f64, mean: &Classical) -> Result<f64> {
    let eta = ((1.0 - mean.e) * (1.0 + mean.e)).sqrt();
    let c = mean.i.cos();
    let mut big_l = (mu * mean.a).sqrt();
    let mut step = f64::INFINITY;
    for _ in 0..20 {
        let l = Dual64::from_re(big_l).derivative();
        let k = secular_hamiltonian(mu, radius, j2.into(), l, l * eta, l * eta * c) - energy;
        step = k.re / k.eps;
        big_l -= step;
        if !big_l.is_finite() || big_l <= 0.0 {
            break;
        }
        if step.abs() <= 4.0 * f64::EPSILON * big_l {
            return Ok(big_l * big_l / mu);
        }
    }
    Err(Error::NotConverged {
        what: "mean L'' from the energy integral K(L'', G'', H'') = H".into(),
        iterations: 20,
        residual: step,
    })
}

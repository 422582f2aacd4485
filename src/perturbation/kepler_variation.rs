//! The Kepler problem as the unperturbed general solution of the element engines: Lagrange's
//! planetary equations for any disturbing function and the general variation of constants
//! for any force, in classical and in equinoctial elements; first-order secular rates by
//! averaging over the mean anomaly; a mean-element propagator.
//!
//! # The general solution
//! Per unit mass, `H₀ = |p|²/2 − μ/|q|` [Ardema 10.2]. In classical elements the solution is
//!
//! ```math
//! (q, p) = \varphi(a, e, i;\ \Omega, \omega, M_0;\ t),\qquad M = M_0 + n(a)(t - t_0),\quad
//! n = \sqrt{\mu/a^3},
//! ```
//!
//! ([`ClassicalSolution`], blocks `γ₁ = (a, e, i)`, `γ₂ = (Ω, ω, M₀)`), and in equinoctial
//! elements `γ₁ = (a, h, k)`, `γ₂ = (p, q, λ₀)` with `λ = λ₀ + n(t − t₀)`
//! ([`EquinoctialSolution`]); the maps are [`Classical::to_state`] and [`Equinoctial::to_state`],
//! written for dual numbers, so `∂φ/∂γ`, the Lagrange brackets and `∂U*/∂γ` come by AD. Because
//! `n` depends on `a`, `∂φ/∂a` contains the secular term `−(3/2)(n/a)(t − t₀) ∂φ/∂M`; the
//! bracket matrix is nevertheless independent of `t` (Lagrange's theorem, [Ardema eq. 18.15];
//! checked in the tests), and the rate of the epoch constant satisfies, at `t = t₀`,
//! `Ṁ₀ = Ṁ − n` (`λ̇₀ = λ̇ − n`).
//!
//! # Element equations
//! * Conservative perturbation `U(t, q)` ([`DisturbingFunction`], e.g. the models of
//!   [`forces`](super::forces)): [`PlanetaryEquations`] `{ solution, disturbing }` —
//!   `Σ_s [γ_j, γ_s] γ̇_s = −∂U*/∂γ_j` [Ardema eqs. 18.22–18.24]; with the classical elements these
//!   are Lagrange's planetary equations in their textbook form (Vallado 2013 eq. 9-12; Kaula 1966
//!   eq. 3.4), here with `U = −R`.
//! * Any force `f(t, q, p)` ([`MomentumForce`](super::variation::MomentumForce), e.g. drag or
//!   thrust): [`VariationOfConstants`](super::variation::VariationOfConstants)
//!   `{ solution, perturbation: InMomentumEquation(f) }` or
//!   [`LagrangeBracketForm`](super::variation::LagrangeBracketForm) `{ solution, force: f }`
//!   (with `Σ_r R_r ∂F_r/∂γ_j`).
//!
//! Both element sets are singular where their angles are: classical elements at
//! `e = 0` (`ω` and `M` coincide) and `i = 0` (`Ω` and `ω` coincide), where the engines return
//! [`Error::Singular`]; the equinoctial set is regular there (singular at
//! `i = π`).
//!
//! # Secular rates
//! [`secular_rates`] averages the element rates over one revolution of the fast angle at frozen
//! elements, `⟨γ̇⟩ = (1/2π) ∮ γ̇ dM` ([`average_over_phase`], trapezoidal rule, geometric
//! convergence for these analytic periodic integrands). For `J₂` this reproduces the first-order
//! secular rates of Brouwer (1959) ([`j2_secular_rates`]):
//!
//! ```math
//! \dot\Omega = -\tfrac32 n J_2 \Big(\frac Rp\Big)^2\cos i,\quad
//! \dot\omega = \tfrac34 n J_2 \Big(\frac Rp\Big)^2 (5\cos^2 i - 1),\quad
//! \dot M - n = \tfrac34 n J_2 \Big(\frac Rp\Big)^2 \sqrt{1 - e^2}\,(3\cos^2 i - 1),
//! ```
//!
//! `ȧ = ė = i̇ = 0` (Vallado 2013 eqs. 9-41; D. Brouwer, "Solution of the problem of artificial
//! satellite theory without drag", Astron. J. 64 (1959) 378–397, doi:10.1086/107958).
//!
//! # Mean elements
//! [`MeanElements`] propagates mean elements with constant secular rates (first-order theory
//! without short-period terms). Its position error against the osculating motion is of the size
//! of the short-period terms, `O(J₂ (R/a)² a)`, plus the along-track drift from the neglected
//! second-order secular rates, `O(J₂² (R/a)⁴ a · n t)`.
//!
//! # Limits
//! * Classical elements are refused only where the Jacobian is exactly singular (`e = 0`,
//!   `i = 0`); close to those points the planetary equations lose accuracy like `ε/e` and
//!   `ε/sin i` (the inverse of a nearly singular Jacobian: 2e−4 relative at `e = 1e−12`). Use
//!   [`EquinoctialSolution`] for nearly circular or equatorial orbits.
//! * Both solutions are elliptic. For hyperbolic orbits use Gauss's equations in modified
//!   equinoctial elements ([`GaussEquations`](super::gauss_variational::GaussEquations)), which
//!   hold for every conic.
//! * Averaging ([`secular_rates`], [`average_over_phase`])
//!   does not judge whether the perturbation is small; ask
//!   [`PhaseAverage::require_small`](super::canonical::PhaseAverage::require_small).

use crate::phase::CanonicalPair;
use std::f64::consts::{PI, TAU};

use super::canonical::{average_over_phase, PhaseAverage};
use super::forces::J2;
use super::ode::{ElementOde, ElementPair};
use super::variation::{DisturbingFunction, GeneralSolution, PlanetaryEquations};
use crate::error::{all_finite, finite, positive, Error, Result};
use crate::systems::kepler::elements::{state_to_classical, Classical, Delaunay, Equinoctial};
use crate::systems::kepler::orbit::{self, phase_advance};
use nalgebra::{SVector, Vector3};
use num_dual::DualNum;

/// A Kepler general solution whose constants are `γ₁ = (a, ·, ·)`, `γ₂ = (·, ·, fast angle at the
/// epoch)`: [`ClassicalSolution`] and [`EquinoctialSolution`].
pub trait KeplerSolution: GeneralSolution<3> {
    /// The gravitational parameter `μ`.
    fn mu(&self) -> f64;
    /// The epoch `t₀` at which the fast angle equals its constant `γ₂[2]`.
    fn epoch(&self) -> f64;
    /// Mean motion `n = √(μ/a³)` of the constants (`a = γ₁[0] > 0`).
    fn mean_motion(&self, gamma1: &SVector<f64, 3>) -> Result<f64> {
        let a = positive("semi-major axis a = γ₁[0]", gamma1[0])?;
        orbit::mean_motion(self.mu(), a)
    }
}

fn nan_state<D: DualNum<f64> + Copy>() -> (SVector<D, 3>, SVector<D, 3>) {
    let x = SVector::from_element(D::from(f64::NAN));
    (x, x)
}

/// `n(a) = √(μ/a³)` in any dual type.
#[inline]
fn mean_motion_generic<D: DualNum<f64> + Copy>(mu: f64, a: D) -> D {
    ((a * a * a).recip() * mu).sqrt()
}

/// The Kepler general solution in classical elements, `γ₁ = (a, e, i)`, `γ₂ = (Ω, ω, M₀)`,
/// `M = M₀ + n(a)(t − t₀)` (elliptic orbits; outside the domain of [`Classical`], or for a phase
/// advance `|n(t − t₀)|` beyond [`orbit::MAX_PHASE_ADVANCE`], the state is NaN and the
/// engines report [`Error::InvalidInput`]; [`ClassicalSolution::elements`] reports
/// [`Error::PhaseLost`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClassicalSolution {
    mu: f64,
    epoch: f64,
}

impl ClassicalSolution {
    /// `μ > 0`, finite epoch `t₀`.
    pub fn new(mu: f64, epoch: f64) -> Result<Self> {
        Ok(Self {
            mu: positive("gravitational parameter μ", mu)?,
            epoch: finite("epoch t₀", epoch)?,
        })
    }

    /// The constants `γ` of the elliptic orbit with osculating elements `el` at time `t`
    /// (`M₀ = M − n(t − t₀)`).
    pub fn constants(&self, el: &Classical, t: f64) -> Result<ElementPair<3>> {
        finite("time t", t)?;
        let n = el.mean_motion(self.mu)?;
        if el.e >= 1.0 {
            return Err(Error::out_of_domain(
                "eccentricity e of ClassicalSolution (elliptic orbits)",
                el.e,
                "[0, 1)",
            ));
        }
        Ok((
            Vector3::new(el.a, el.e, el.i),
            Vector3::new(el.raan, el.argp, el.mean_anomaly - n * (t - self.epoch)),
        ))
    }

    /// The osculating classical elements at time `t` of the constants `γ`.
    pub fn elements(&self, t: f64, g: &ElementPair<3>) -> Result<Classical> {
        finite("time t", t)?;
        let n = self.mean_motion(&g.0)?;
        let advance = phase_advance("classical general solution", n * (t - self.epoch))?;
        Classical::new(g.0[0], g.0[1], g.0[2], g.1[0], g.1[1], g.1[2] + advance)
    }
}

impl GeneralSolution<3> for ClassicalSolution {
    fn state<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        g1: &SVector<D, 3>,
        g2: &SVector<D, 3>,
    ) -> (SVector<D, 3>, SVector<D, 3>) {
        let a = g1[0];
        if a.re().is_nan() || a.re() <= 0.0 {
            return nan_state();
        }
        let advance = mean_motion_generic(self.mu, a) * (t - self.epoch);
        if phase_advance("classical general solution", advance.re()).is_err() {
            return nan_state();
        }
        let m = g2[2] + advance;
        let el = Classical {
            a,
            e: g1[1],
            i: g1[2],
            raan: g2[0],
            argp: g2[1],
            mean_anomaly: m,
        };
        el.to_state(self.mu).unwrap_or_else(|_| nan_state())
    }
}

impl KeplerSolution for ClassicalSolution {
    fn mu(&self) -> f64 {
        self.mu
    }
    fn epoch(&self) -> f64 {
        self.epoch
    }
}

/// The Kepler general solution in equinoctial elements (Broucke & Cefola 1972),
/// `γ₁ = (a, h, k)`, `γ₂ = (p, q, λ₀)`, `λ = λ₀ + n(a)(t − t₀)`. Regular at `e = 0` and `i = 0`.
/// The phase advance is limited as for [`ClassicalSolution`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EquinoctialSolution {
    mu: f64,
    epoch: f64,
}

impl EquinoctialSolution {
    /// `μ > 0`, finite epoch `t₀`.
    pub fn new(mu: f64, epoch: f64) -> Result<Self> {
        Ok(Self {
            mu: positive("gravitational parameter μ", mu)?,
            epoch: finite("epoch t₀", epoch)?,
        })
    }

    /// The constants `γ` of the orbit with osculating elements `el` at time `t`.
    pub fn constants(&self, el: &Equinoctial, t: f64) -> Result<ElementPair<3>> {
        finite("time t", t)?;
        el.validate()?;
        let n = (self.mu / (el.a * el.a * el.a)).sqrt();
        Ok((
            Vector3::new(el.a, el.h, el.k),
            Vector3::new(el.p, el.q, el.lambda - n * (t - self.epoch)),
        ))
    }

    /// The osculating equinoctial elements at time `t` of the constants `γ`.
    pub fn elements(&self, t: f64, g: &ElementPair<3>) -> Result<Equinoctial> {
        finite("time t", t)?;
        let n = self.mean_motion(&g.0)?;
        let advance = phase_advance("equinoctial general solution", n * (t - self.epoch))?;
        Equinoctial::new(g.0[0], g.0[1], g.0[2], g.1[0], g.1[1], g.1[2] + advance)
    }
}

impl GeneralSolution<3> for EquinoctialSolution {
    fn state<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        g1: &SVector<D, 3>,
        g2: &SVector<D, 3>,
    ) -> (SVector<D, 3>, SVector<D, 3>) {
        let a = g1[0];
        if a.re().is_nan() || a.re() <= 0.0 {
            return nan_state();
        }
        let advance = mean_motion_generic(self.mu, a) * (t - self.epoch);
        if phase_advance("equinoctial general solution", advance.re()).is_err() {
            return nan_state();
        }
        let lambda = g2[2] + advance;
        let el = Equinoctial {
            a,
            h: g1[1],
            k: g1[2],
            p: g2[0],
            q: g2[1],
            lambda,
        };
        el.to_state(self.mu).unwrap_or_else(|_| nan_state())
    }
}

impl KeplerSolution for EquinoctialSolution {
    fn mu(&self) -> f64 {
        self.mu
    }
    fn epoch(&self) -> f64 {
        self.epoch
    }
}

/// Lagrange's planetary equations of the Kepler problem perturbed by `U`, in the element set
/// of `solution`: an [`ElementOde`] for [`crate::perturbation::ode`].
pub fn planetary_equations<S: KeplerSolution, U: DisturbingFunction<3>>(
    solution: S,
    disturbing: U,
) -> PlanetaryEquations<S, U> {
    PlanetaryEquations {
        solution,
        disturbing,
    }
}

/// First-order secular rates: the element rates of `ode` averaged over one revolution of the
/// fast angle at frozen constants `γ`, as for the pendulum of [Ardema 18.2].
///
/// The rates are evaluated at `t = t₀` (the epoch of `solution`, which `ode` must share) with the
/// fast angle `γ₂[2] + n s`, `s ∈ [0, 2π/n)`, so that the rate of the epoch constant is
/// `Ṁ − n` (classical) or `λ̇ − n` (equinoctial). `nodes` (even, ≥ 4) trapezoidal nodes; the
/// result carries the quadrature error estimate and the oscillating spread.
///
/// # Errors
/// As [`average_over_phase`]; the first error of the rates (e.g.
/// [`Error::Singular`] for classical elements at `e = 0` or `i = 0`).
pub fn secular_rates<S, O>(
    solution: &S,
    ode: &O,
    gamma: &ElementPair<3>,
    nodes: usize,
) -> Result<PhaseAverage<3>>
where
    S: KeplerSolution + ?Sized,
    O: ElementOde<3> + ?Sized,
{
    all_finite("γ₁", gamma.0.as_slice())?;
    all_finite("γ₂", gamma.1.as_slice())?;
    let n = solution.mean_motion(&gamma.0)?;
    let t0 = solution.epoch();
    average_over_phase(
        |s| {
            let mut b = gamma.1;
            b[2] += n * s;
            ode.rhs(t0, &gamma.0, &b)
        },
        TAU / n,
        nodes,
    )
}

/// First-order secular rates of the classical elements under `J₂` (Brouwer 1959; Vallado 2013
/// eqs. 9-41); `ȧ = ė = i̇ = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct J2SecularRates {
    /// `Ω̇ = −(3/2) n J₂ (R/p)² cos i`.
    pub raan: f64,
    /// `ω̇ = (3/4) n J₂ (R/p)² (5 cos² i − 1)`.
    pub argp: f64,
    /// `Ṁ − n = (3/4) n J₂ (R/p)² √(1 − e²) (3 cos² i − 1)`.
    pub mean_anomaly: f64,
    /// The mean motion `n = √(μ/a³)`.
    pub mean_motion: f64,
}

/// The closed-form first-order `J₂` secular rates of the `model` (`μ, J₂, R`) at `(a, e, i)`
/// (elliptic).
///
/// `k = n J₂ (R/p)²` is formed as `n·J₂·R²/(a²(1 − e²)²)` from the binary mantissas and
/// exponents of its factors, so no intermediate overflows or underflows. A rate that underflows is returned as its correctly rounded value (0 or
/// subnormal); one that overflows is refused.
///
/// # Errors
/// Non-finite input, `a ≤ 0`, `e ∉ [0, 1)`, `i ∉ [0, π]`; the errors of
/// [`orbit::mean_motion`]; [`Error::OutOfDomain`] when a rate overflows.
pub fn j2_secular_rates(model: &J2, a: f64, e: f64, i: f64) -> Result<J2SecularRates> {
    let (mu, j2, radius) = (model.mu(), model.j2(), model.radius());
    let a = positive("semi-major axis a", a)?;
    let e = finite("eccentricity e", e)?;
    if !(0.0..1.0).contains(&e) {
        return Err(Error::out_of_domain("eccentricity e", e, "[0, 1)"));
    }
    let i = finite("inclination i", i)?;
    if !(0.0..=PI).contains(&i) {
        return Err(Error::out_of_domain("inclination i", i, "[0, π]"));
    }
    let n = orbit::mean_motion(mu, a)?;
    let one_m_e2 = (1.0 - e) * (1.0 + e);
    let c = i.cos();
    if j2 == 0.0 {
        return Ok(J2SecularRates {
            raan: 0.0,
            argp: 0.0,
            mean_anomaly: 0.0,
            mean_motion: n,
        });
    }
    let k = orbit::scaled_product(&[n, j2, radius, radius], &[a, a, one_m_e2, one_m_e2]);
    let overflow = |rate: f64| -> Result<f64> {
        if rate.is_finite() {
            Ok(rate)
        } else {
            Err(Error::out_of_domain(
                format!(
                    "J₂ secular rate at μ = {mu:e}, J₂ = {j2:e}, R = {radius:e}, a = {a:e}, e = {e:e}"
                ),
                rate,
                "finite rates (|n·J₂·(R/p)²| below 1.2e308)",
            ))
        }
    };
    Ok(J2SecularRates {
        raan: overflow(-1.5 * k * c)?,
        argp: overflow(0.75 * k * (5.0 * c * c - 1.0))?,
        mean_anomaly: overflow(0.75 * k * one_m_e2.sqrt() * (3.0 * c * c - 1.0))?,
        mean_motion: n,
    })
}

/// Mean classical elements propagated with constant secular rates:
/// `γ̄(t) = γ̄(t₀) + ⟨γ̇⟩ (t − t₀)` for `a, e, i, Ω, ω`, and `M̄(t) = M̄(t₀) + (n̄ + ⟨Ṁ − n⟩)(t − t₀)`
/// with `n̄ = √(μ/ā³)` of the mean semi-major axis at the epoch.
///
/// Valid for perturbations with `⟨ȧ⟩ = 0` (conservative, time-independent `U`): a secular change
/// of `a` would make the mean motion itself vary, which this first-order propagator ignores.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeanElements {
    mu: f64,
    epoch: f64,
    elements: Classical,
    /// `(ȧ, ė, i̇, Ω̇, ω̇, Ṁ − n)`.
    rates: [f64; 6],
}

impl MeanElements {
    /// Mean `elements` at `epoch` with the secular `rates` `(ȧ, ė, i̇, Ω̇, ω̇, Ṁ − n)`.
    ///
    /// # Errors
    /// Non-finite input, `μ ≤ 0`, a non-elliptic orbit.
    pub fn new(mu: f64, epoch: f64, elements: Classical, rates: [f64; 6]) -> Result<Self> {
        let mu = positive("gravitational parameter μ", mu)?;
        finite("epoch t₀", epoch)?;
        elements.validate()?;
        elements.mean_motion(mu)?;
        if elements.e >= 1.0 {
            return Err(Error::out_of_domain(
                "eccentricity e of mean elements",
                elements.e,
                "[0, 1)",
            ));
        }
        all_finite("secular rates", &rates)?;
        Ok(Self {
            mu,
            epoch,
            elements,
            rates,
        })
    }

    /// The closed-form first-order `J₂` rates of the `model` ([`j2_secular_rates`]) at the mean
    /// elements.
    pub fn j2(model: &J2, epoch: f64, elements: Classical) -> Result<Self> {
        let r = j2_secular_rates(model, elements.a, elements.e, elements.i)?;
        Self::new(
            model.mu(),
            epoch,
            elements,
            [0.0, 0.0, 0.0, r.raan, r.argp, r.mean_anomaly],
        )
    }

    /// Rates from an averaged [`ClassicalSolution`] element ODE ([`secular_rates`] at the mean
    /// elements, `nodes` quadrature nodes), for any disturbing function.
    pub fn from_averaged_equations<O: ElementOde<3> + ?Sized>(
        solution: &ClassicalSolution,
        ode: &O,
        epoch: f64,
        elements: Classical,
        nodes: usize,
    ) -> Result<Self> {
        let at_epoch = ClassicalSolution::new(solution.mu, solution.epoch)?;
        let g = at_epoch.constants(&elements, at_epoch.epoch)?;
        let avg = secular_rates(&at_epoch, ode, &g, nodes)?;
        Self::new(
            solution.mu,
            epoch,
            elements,
            [
                avg.mean.0[0],
                avg.mean.0[1],
                avg.mean.0[2],
                avg.mean.1[0],
                avg.mean.1[1],
                avg.mean.1[2],
            ],
        )
    }

    /// First-order mean elements from osculating elements sampled over (about) one period:
    /// `ā = (1/Δt) ∫ a dt` (trapezoidal rule over the samples) for `a, e, i`, and the same
    /// average of the continuously unwrapped angles, referred back from the mid-time `t̄` to the
    /// epoch `times[0]` with the secular rates `rates(ā, ē, ī)` = `(ȧ, ė, i̇, Ω̇, ω̇, Ṁ − n)`.
    /// The samples must be dense enough that no angle moves by more than `π` between two of them.
    ///
    /// # Errors
    /// Fewer than 3 samples, times not increasing, non-elliptic or invalid samples, the errors of
    /// `rates`.
    pub fn from_osculating_arc<F>(
        mu: f64,
        times: &[f64],
        samples: &[Classical],
        rates: F,
    ) -> Result<Self>
    where
        F: FnOnce(&Classical) -> Result<[f64; 6]>,
    {
        if times.len() != samples.len() || times.len() < 3 {
            return Err(Error::invalid(
                "osculating arc",
                format!(
                    "{} times and {} samples; need equal numbers, at least 3",
                    times.len(),
                    samples.len()
                ),
            ));
        }
        all_finite("sample times", times)?;
        if times.windows(2).any(|w| w[1] <= w[0]) {
            return Err(Error::invalid("sample times", "not strictly increasing"));
        }
        for s in samples {
            s.validate()?;
        }
        let unwrap = |f: fn(&Classical) -> f64| -> Vec<f64> {
            let mut out = Vec::with_capacity(samples.len());
            let mut prev = f(&samples[0]);
            out.push(prev);
            for s in &samples[1..] {
                let x = f(s);
                let d = (x - prev + PI).rem_euclid(TAU) - PI;
                prev += d;
                out.push(prev);
            }
            out
        };
        let span = times[times.len() - 1] - times[0];
        let mean_of = |v: &[f64]| -> f64 {
            let mut s = 0.0;
            for k in 1..v.len() {
                s += 0.5 * (v[k] + v[k - 1]) * (times[k] - times[k - 1]);
            }
            s / span
        };
        let field = |f: fn(&Classical) -> f64| -> Vec<f64> { samples.iter().map(f).collect() };
        let a = mean_of(&field(|c| c.a));
        let e = mean_of(&field(|c| c.e));
        let i = mean_of(&field(|c| c.i));
        let t_mid = mean_of(times);
        let raan_mid = mean_of(&unwrap(|c| c.raan));
        let argp_mid = mean_of(&unwrap(|c| c.argp));
        let m_mid = mean_of(&unwrap(|c| c.mean_anomaly));
        let provisional = Classical::new(a, e, i, raan_mid, argp_mid, m_mid)?;
        let r = rates(&provisional)?;
        all_finite("secular rates", &r)?;
        let n = provisional.mean_motion(mu)?;
        let dt = t_mid - times[0];
        let el = Classical::new(
            a - r[0] * dt,
            e - r[1] * dt,
            i - r[2] * dt,
            raan_mid - r[3] * dt,
            argp_mid - r[4] * dt,
            m_mid - (n + r[5]) * dt,
        )?;
        Self::new(mu, times[0], el, r)
    }

    /// The mean elements at the epoch.
    pub fn elements(&self) -> &Classical {
        &self.elements
    }

    /// The secular rates `(ȧ, ė, i̇, Ω̇, ω̇, Ṁ − n)`.
    pub fn rates(&self) -> [f64; 6] {
        self.rates
    }

    /// The mean elements at `t`.
    pub fn at(&self, t: f64) -> Result<Classical> {
        let dt = finite("time t", t)? - self.epoch;
        let el = &self.elements;
        let n = el.mean_motion(self.mu)?;
        let r = &self.rates;
        let advance = phase_advance("mean-element propagation", (n + r[5]) * dt)?;
        Classical::new(
            el.a + r[0] * dt,
            el.e + r[1] * dt,
            el.i + r[2] * dt,
            el.raan + r[3] * dt,
            el.argp + r[4] * dt,
            el.mean_anomaly + advance,
        )
    }

    /// The Cartesian state of the mean elements at `t` (no short-period terms).
    pub fn state(&self, t: f64) -> Result<CanonicalPair<3>> {
        self.at(t)?.to_state(self.mu)
    }
}

/// Osculating classical elements of a Cartesian state (re-exported convenience for sampling a
/// Cartesian integration: [`state_to_classical`]).
pub fn osculating_classical(
    mu: f64,
    q: &SVector<f64, 3>,
    p: &SVector<f64, 3>,
) -> Result<Classical> {
    state_to_classical(mu, q, p)
}

/// The Kepler motion in Delaunay constants as canonical elements [Ardema 18.2] (`AlphaMomenta`):
/// momenta `α = (L, G, H)`, coordinates `β = (l₀, g, h)` with the mean anomaly
/// `l = l₀ + n(L)(t − t₀)`, `n = μ²/L³`. The shear `l₀ ↦ l` removes the Kepler Hamiltonian
/// `−μ²/(2L²)`, so a perturbation `K` alone drives the elements: `α̇ = −∂K*/∂β`,
/// `β̇ = ∂K*/∂α` (Hamilton's equations in Delaunay variables; Brouwer & Clemence 1961 ch. XI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DelaunayElements {
    mu: f64,
    epoch: f64,
}

impl DelaunayElements {
    /// Delaunay constants for gravitational parameter `μ > 0`, mean anomaly counted from `t₀`.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] / [`Error::NonFinite`] for a bad `μ` or `t₀`.
    pub fn new(mu: f64, epoch: f64) -> Result<Self> {
        Ok(Self {
            mu: positive("gravitational parameter μ", mu)?,
            epoch: finite("epoch t₀", epoch)?,
        })
    }

    /// `(α, β) = ((L, G, H), (l₀, g, h))` of classical elements at time `t`.
    ///
    /// # Errors
    /// As [`Classical::to_delaunay`].
    pub fn constants(&self, el: &Classical, t: f64) -> Result<ElementPair<3>> {
        let t = finite("time t", t)?;
        let d = el.to_delaunay(self.mu)?;
        let n = self.mu * self.mu / d.big_l.powi(3);
        Ok((
            Vector3::new(d.big_l, d.big_g, d.big_h),
            Vector3::new(d.l - n * (t - self.epoch), d.g, d.h),
        ))
    }
}

impl super::canonical::CanonicalElements<3> for DelaunayElements {
    fn convention(&self) -> crate::hamilton_jacobi::ElementConvention {
        crate::hamilton_jacobi::ElementConvention::AlphaMomenta
    }
    fn state_generic<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        alpha: &SVector<D, 3>,
        beta: &SVector<D, 3>,
    ) -> Result<(SVector<D, 3>, SVector<D, 3>)> {
        let n = alpha[0].powi(3).recip() * (self.mu * self.mu);
        let advance = n * (t - self.epoch);
        phase_advance("Delaunay general solution", advance.re())?;
        Delaunay {
            l: beta[0] + advance,
            g: beta[1],
            h: beta[2],
            big_l: alpha[0],
            big_g: alpha[1],
            big_h: alpha[2],
        }
        .to_state(self.mu)
    }
}

/// A disturbing function `U(q, t)` as the perturbing Hamiltonian `K(t, q, p) = U(q, t)` of the
/// canonical element equations.
#[derive(Clone, Copy, Debug)]
pub struct AsHamiltonian<U>(pub U);

impl<U: DisturbingFunction<3>> crate::hamiltonian::PhaseFunction<3> for AsHamiltonian<U> {
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 3>, _p: &SVector<D, 3>) -> D {
        self.0.disturbing_function(t, q)
    }
}

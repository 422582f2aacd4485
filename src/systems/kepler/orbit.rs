//! First integrals and scales of a Kepler orbit: energy, angular momentum, eccentricity
//! (Laplace–Runge–Lenz) vector, mean motion and period, and the limits shared by the two-body
//! maps (the circular-orbit tolerance of the element sets, the longest phase advance of bound
//! motion).
//!
//! Everything is per unit mass, with Hamiltonian
//!
//! H(q, p) = |p|²/2 − μ/|q|,   μ > 0,
//!
//! so the momentum equals the velocity, `p = q̇ = v`. Conventions [Ardema 10.2–10.3]:
//!
//! * `k = r²θ̇ = |q × p|` is the specific angular momentum, `ε = |p|²/2 − μ/|q|` the specific
//!   energy, `e` the eccentricity, `a = −μ/(2ε)` the semi-major axis;
//! * mean motion `n = √(μ/a³)`, mean anomaly `M = n (t − t_p)` (Kepler's equation,
//!   [`crate::special::kepler_equation`]), period `τ = 2π/n = 2π a^{3/2}/√μ`.
//!
//! The eccentricity is taken from the eccentricity vector, never from `√(1 + 2εk²/μ²)`, which
//! cancels catastrophically for nearly circular orbits.
//!
//! # References
//!
//! * M. D. Ardema, *Analytical Dynamics: Theory and Applications*, Kluwer/Plenum (2005),
//!   §§10.2–10.3 (the Kepler problem, its first integrals, Kepler's third law).
//! * R. H. Battin, *An Introduction to the Mathematics and Methods of Astrodynamics*, rev. ed.,
//!   AIAA (1999), ch. 3 (the eccentricity vector).

use std::f64::consts::TAU;

use nalgebra::Vector3;

use crate::error::{all_finite, finite, positive, Error, Result};

/// Eccentricities below this value are reported as exactly `0` by
/// [`state_to_classical`](super::elements::state_to_classical) and the other state → element maps
/// (circular-orbit convention).
///
/// The eccentricity vector `((|v|² − μ/r) r − (r·v) v)/μ` is a difference of dimensionless terms
/// of size at most 2 for a bound orbit, so its rounding error is a small multiple of
/// `f64::EPSILON` whatever the scale of the orbit; an eccentricity below `64 ε ≈ 1.4·10⁻¹⁴` is
/// indistinguishable from zero. Snapping moves the reconstructed state by at most about
/// `2 a · CIRCULAR_TOLERANCE`.
pub const CIRCULAR_TOLERANCE: f64 = 64.0 * f64::EPSILON;

/// The largest phase advance `|n·Δt|` (radians) that the maps of bound periodic motion accept:
/// `10⁻⁶/ε ≈ 4.5·10⁹` rad (about 7·10⁸ orbits).
///
/// The mean motion `n` and the product `n·Δt` are rounded, so the computed phase carries an error
/// of a few `|n·Δt|·ε` (`ε = 2⁻⁵²`) whatever the method; beyond this limit that error exceeds
/// `10⁻⁶` rad, and a few decades further (`|n·Δt| ≈ 2⁵³`) the phase is entirely lost. The Kepler
/// flow of a bound orbit ([`super::propagate`], [`super::drift`]), the mean-anomaly propagation
/// of the elements ([`Classical::propagate`](super::elements::Classical::propagate)) and of the
/// element solutions in [`crate::perturbation::kepler_variation`], and the exact flows of the
/// other periodic systems refuse a longer advance with [`Error::PhaseLost`]. Unbound
/// (parabolic, hyperbolic) motion has no phase and no such limit.
pub const MAX_PHASE_ADVANCE: f64 = 1e-6 / f64::EPSILON;

/// Accept a phase advance `n·Δt` of bound motion (finite, `|n·Δt| ≤ MAX_PHASE_ADVANCE`), else
/// [`Error::NonFinite`] / [`Error::PhaseLost`] naming `what`.
pub(crate) fn phase_advance(what: &str, phase: f64) -> Result<f64> {
    let phase = finite(format_args!("{what}: phase advance n·Δt"), phase)?;
    if phase.abs() <= MAX_PHASE_ADVANCE {
        Ok(phase)
    } else {
        Err(Error::PhaseLost {
            what: what.into(),
            phase,
            limit: MAX_PHASE_ADVANCE,
        })
    }
}

// ---------------------------------------------------------------------------------------------
// Validation
// ---------------------------------------------------------------------------------------------

/// Check a state `(r, v)` for finite components and `r ≠ 0` (the collision singularity of the
/// potential `−μ/|q|`); its radius `|r|`.
pub(crate) fn check_state(r: &Vector3<f64>, v: &Vector3<f64>) -> Result<f64> {
    all_finite("position q", r.as_slice())?;
    all_finite("velocity p", v.as_slice())?;
    let rn = r.norm();
    if rn > 0.0 && rn.is_finite() {
        Ok(rn)
    } else if rn == 0.0 {
        Err(Error::invalid(
            "position q",
            "q = 0 is the collision singularity of the Kepler potential −μ/|q|",
        ))
    } else {
        Err(Error::NonFinite {
            what: "|q|".into(),
            value: rn,
        })
    }
}

// ---------------------------------------------------------------------------------------------
// Mean motion and period
// ---------------------------------------------------------------------------------------------

/// Mean motion `n = √(μ/a³)`.
///
/// Evaluated without intermediate overflow or underflow: with `a = a'·2^{2k}`, `a' ∈ [1, 4)`
/// (exact scaling by a power of two), `n = √(μ/a'³)·2^{−3k}`, so the only rounding-range limit is
/// that of `n` itself.
///
/// Reference: [Ardema 10.3].
///
/// # Errors
/// [`Error::NonFinite`] / [`Error::OutOfDomain`] unless `μ > 0` and `a > 0` are finite;
/// [`Error::OutOfDomain`] when `n` overflows or falls below the normal range
/// (`f64::MIN_POSITIVE ≈ 2.2e−308`, where it would lose relative precision).
pub fn mean_motion(mu: f64, a: f64) -> Result<f64> {
    let mu = positive("gravitational parameter μ", mu)?;
    let a = positive("semi-major axis a", a)?;
    // a = m·2^e with m ∈ [1, 2) (also for subnormal a); k = ⌊e/2⌋ gives a' = a·2^{−2k} ∈ [1, 4).
    let e = exponent(a);
    let k = e.div_euclid(2);
    let a_scaled = scale2(a, -2 * k);
    let base = (mu / (a_scaled * a_scaled * a_scaled)).sqrt();
    let n = scale2(base, -3 * k);
    if n.is_finite() && n >= f64::MIN_POSITIVE {
        Ok(n)
    } else {
        Err(Error::out_of_domain(
            format!("mean motion √(μ/a³) (μ = {mu:e}, a = {a:e})"),
            n,
            "[2.2e-308, 1.8e308] (representable with full precision)",
        ))
    }
}

/// `∏ num / ∏ den` for finite non-zero factors, formed from their binary mantissas and exponents
/// so that the only overflow or underflow is that of the result (one final scaling; the relative
/// error is that of the mantissa products, a few ulps).
pub(crate) fn scaled_product(num: &[f64], den: &[f64]) -> f64 {
    let mut m = 1.0f64;
    let mut e = 0i32;
    for &x in num {
        let ex = exponent(x.abs());
        m *= scale2(x, -ex);
        e += ex;
    }
    for &x in den {
        let ex = exponent(x.abs());
        m /= scale2(x, -ex);
        e -= ex;
    }
    scale2(m, e)
}

/// Binary exponent `e` with `x = m·2^e`, `m ∈ [1, 2)`, for finite `x > 0` (subnormals included).
fn exponent(x: f64) -> i32 {
    let bits = x.to_bits();
    let biased = ((bits >> 52) & 0x7ff) as i32;
    if biased == 0 {
        // Subnormal: x = frac·2^{−1074}.
        let frac = bits & ((1u64 << 52) - 1);
        63 - frac.leading_zeros() as i32 - 1074
    } else {
        biased - 1023
    }
}

/// `x·2^k` for any integer `k`, in steps that cannot overflow the scale factor (exact unless the
/// result overflows or is subnormal).
fn scale2(x: f64, k: i32) -> f64 {
    let mut x = x;
    let mut k = k;
    while k != 0 {
        let step = k.clamp(-1000, 1000);
        x *= f64::from_bits(((1023 + step) as u64) << 52);
        k -= step;
    }
    x
}

/// Orbital period `τ = 2π a^{3/2}/√μ` (Kepler's third law).
///
/// Reference: [Ardema 10.3].
///
/// # Errors
/// [`Error::NonFinite`] / [`Error::OutOfDomain`] unless `μ > 0` and `a > 0` are finite.
pub fn period(mu: f64, a: f64) -> Result<f64> {
    let mu = positive("gravitational parameter μ", mu)?;
    let a = positive("semi-major axis a", a)?;
    finite("period τ", TAU * a * (a / mu).sqrt())
}

// ---------------------------------------------------------------------------------------------
// First integrals
// ---------------------------------------------------------------------------------------------

/// Specific energy `ε = |v|²/2 − μ/|r|` (the Hamiltonian per unit mass; `p = v`).
///
/// Reference: [Ardema 10.2].
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞, [`Error::OutOfDomain`] for `μ ≤ 0`,
/// [`Error::InvalidInput`] for `r = 0`.
pub fn specific_energy(mu: f64, r: &Vector3<f64>, v: &Vector3<f64>) -> Result<f64> {
    let mu = positive("gravitational parameter μ", mu)?;
    let rn = check_state(r, v)?;
    finite("specific energy", 0.5 * v.norm_squared() - mu / rn)
}

/// Specific angular momentum vector `h = r × v` (its norm is `k = r²θ̇`); conserved by the Kepler
/// flow. No validation: NaN/∞ components propagate.
///
/// Reference: [Ardema 10.2].
pub fn angular_momentum(r: &Vector3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    r.cross(v)
}

/// Eccentricity (Laplace–Runge–Lenz) vector `e = ((|v|² − μ/r) r − (r·v) v)/μ = v × h/μ − r/|r|`:
/// points to periapsis, `|e|` is the eccentricity; conserved by the Kepler flow.
///
/// Its norm is the numerically robust way to obtain `e`: the equivalent `√(1 + 2εk²/μ²)` cancels
/// catastrophically for nearly circular orbits.
///
/// Reference: [Ardema 10.2]; Battin (1999) ch. 3.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞, [`Error::OutOfDomain`] for `μ ≤ 0`,
/// [`Error::InvalidInput`] for `r = 0`.
pub fn eccentricity_vector(mu: f64, r: &Vector3<f64>, v: &Vector3<f64>) -> Result<Vector3<f64>> {
    let mu = positive("gravitational parameter μ", mu)?;
    let rn = check_state(r, v)?;
    let ev = (r * (v.norm_squared() / mu - 1.0 / rn)) - v * (r.dot(v) / mu);
    all_finite("eccentricity vector", ev.as_slice())?;
    Ok(ev)
}

#[cfg(test)]
mod tests {
    use super::*;

    const EPS: f64 = f64::EPSILON;

    #[test]
    fn period_and_mean_motion() {
        let (mu, a) = (3.986e5, 7000.0);
        let tau = period(mu, a).unwrap();
        let n = mean_motion(mu, a).unwrap();
        assert!((tau * n - TAU).abs() <= 4.0 * EPS * TAU);
        assert!((tau - TAU * (a * a * a / mu).sqrt()).abs() <= 4.0 * EPS * tau);
    }

    /// The first integrals of a circular orbit (`μ = 2`, `r = 2`, `|v| = 1`): `ε = −½`,
    /// `h = (0, 0, 2)`, `e = 0`, each to a few ulps.
    #[test]
    fn first_integrals_of_a_circle() {
        let (r, v) = (Vector3::new(0.0, 2.0, 0.0), Vector3::new(-1.0, 0.0, 0.0));
        assert!((specific_energy(2.0, &r, &v).unwrap() + 0.5).abs() <= 2.0 * EPS);
        assert_eq!(angular_momentum(&r, &v), Vector3::new(0.0, 0.0, 2.0));
        assert!(eccentricity_vector(2.0, &r, &v).unwrap().norm() <= 4.0 * EPS);
    }

    #[test]
    fn bad_input_is_rejected() {
        let ood = |r: Result<f64>| matches!(r, Err(Error::OutOfDomain { .. }));
        let nf = |r: Result<f64>| matches!(r, Err(Error::NonFinite { .. }));
        let v = Vector3::new(0.0, 1.0, 0.0);
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(nf(period(bad, 1.0)));
            assert!(nf(period(1.0, bad)));
            assert!(nf(specific_energy(bad, &Vector3::x(), &v)));
            assert!(nf(specific_energy(1.0, &Vector3::new(1.0, bad, 0.0), &v)));
            assert!(matches!(
                eccentricity_vector(1.0, &Vector3::x(), &Vector3::new(bad, 0.0, 0.0)),
                Err(Error::NonFinite { .. })
            ));
        }
        for mu in [0.0, -1.0] {
            assert!(ood(period(mu, 1.0)));
            assert!(ood(period(1.0, mu)));
            assert!(ood(mean_motion(mu, 1.0)));
            assert!(ood(specific_energy(mu, &Vector3::x(), &v)));
        }
        // r = 0.
        let z = Vector3::zeros();
        assert!(matches!(
            specific_energy(1.0, &z, &v),
            Err(Error::InvalidInput { .. })
        ));
        assert!(matches!(
            eccentricity_vector(1.0, &z, &v),
            Err(Error::InvalidInput { .. })
        ));
    }

    /// The phase limit: accepted up to and including `MAX_PHASE_ADVANCE`, refused beyond it and
    /// for a non-finite phase.
    #[test]
    fn phase_advance_limit() {
        assert_eq!(
            phase_advance("x", -MAX_PHASE_ADVANCE).unwrap(),
            -MAX_PHASE_ADVANCE
        );
        assert!(matches!(
            phase_advance("x", 1.000001 * MAX_PHASE_ADVANCE),
            Err(Error::PhaseLost { .. })
        ));
        assert!(matches!(
            phase_advance("x", f64::NAN),
            Err(Error::NonFinite { .. })
        ));
    }
}

//! Kepler's equation on every conic and the conversions between anomalies.
//!
//! | conic | equation | solver |
//! |---|---|---|
//! | ellipse, `0 ≤ e < 1` | `M = E − e sin E` | [`solve_kepler`] (bracketed Halley from cubic starters) |
//! | parabola, `e = 1` | `M_p = B + B³/3`, `B = tan(ν/2)` (Barker) | [`solve_barker`] (Cardano, overflow-free) |
//! | hyperbola, `e > 1` | `M = e sinh F − F` | [`solve_kepler_hyperbolic`] (bracketed Halley) |
//!
//! [`mean_to_true`] and [`true_to_mean`] switch on [`Conic::of_eccentricity`];
//! [`eccentric_anomaly`] and [`hyperbolic_anomaly`] lift a real root to any dual type, so element
//! maps built on them are differentiable.
//!
//! References:
//! * M. D. Ardema, *Analytical Dynamics*, Kluwer/Plenum 2005, §10.3;
//! * D. A. Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed., Microcosm 2013, §2.2;
//! * J. M. A. Danby, *Fundamentals of Celestial Mechanics*, 2nd ed., Willmann-Bell 1988, ch. 6;
//! * F. L. Markley, "Kepler equation solver", *Celestial Mechanics and Dynamical Astronomy* 63,
//!   101–111 (1995) (cubic starters near `e → 1`, `M → 0`).

use std::f64::consts::{LN_2, PI, TAU};

use num_dual::DualNum;

use crate::error::{finite, Error, Result};
use crate::implicit::lift_scalar_root;

/// Low part of 2π: `TAU + TAU_LO` equals 2π to about 10⁻³³ relative (Cody–Waite reduction).
pub(crate) const TAU_LO: f64 = 2.449_293_598_294_706_4e-16;

/// Iteration cap for the bracketed Halley solver. Each iteration either takes a Halley step or
/// halves the bracket, so 100 iterations exceed what bisection alone needs to reach adjacent
/// floating-point numbers on `[0, π]`; reaching the cap indicates a bug, reported as
/// [`Error::NotConverged`].
const KEPLER_MAX_ITER: usize = 100;

/// A Halley step whose size is below this fraction of the iterate is applied and the iteration
/// stops: the error after a Halley step from an iterate with relative error δ is `O(δ³)` with an
/// `O(1)` relative constant for `E − e sin E − M` on `[0, π]` (also in the corner `e → 1`,
/// `E → 0`), so a step of relative size `10⁻⁸` leaves an error far below one ulp, and the final
/// accuracy is set by the rounding of the residual.
const KEPLER_STEP_TOL: f64 = 1e-8;

/// Require `0 ≤ e < 1` (and finite).
pub(crate) fn elliptic_eccentricity(e: f64) -> Result<f64> {
    let e = finite("eccentricity", e)?;
    if (0.0..1.0).contains(&e) {
        Ok(e)
    } else {
        Err(Error::out_of_domain("eccentricity", e, "[0, 1)"))
    }
}

/// Reduce `x` to `[−π, π]`; the flag says whether `x` was changed.
///
/// Cody–Waite reduction: `x − k·TAU` is exact for the magnitudes where the phase is meaningful,
/// and the low part of 2π is subtracted separately. For `|x| ≳ 10¹⁵` (where one ulp of `x` is
/// not small compared with 2π) the phase carries no information; the result is still in range.
pub(crate) fn reduce_angle(x: f64) -> (f64, bool) {
    if x.abs() <= PI {
        return (x, false);
    }
    let k = (x / TAU).round();
    let mut r = (-k).mul_add(TAU, x);
    r = (-k).mul_add(TAU_LO, r);
    if r > PI {
        r -= TAU;
    } else if r < -PI {
        r += TAU;
    }
    (r.clamp(-PI, PI), true)
}

/// Reduce an angle to `[0, 2π)`.
pub(crate) fn wrap_two_pi(x: f64) -> f64 {
    let r = x.rem_euclid(TAU);
    if r >= TAU {
        0.0
    } else {
        r
    }
}

/// Apply a map `g` with `g(x + 2π) = g(x) + 2π` to any real `x`: evaluate it on the reduced
/// argument and add back the reduction, so that `g(x) − x` is periodic.
pub(crate) fn periodic_shift(x: f64, g: impl Fn(f64) -> Result<f64>) -> Result<f64> {
    let (xr, reduced) = reduce_angle(x);
    let yr = g(xr)?;
    Ok(if reduced { x + (yr - xr) } else { yr })
}

/// `x − sin x`, accurate to a few ulps relative for all `|x| ≤ π` (series for `|x| < 1`).
pub(crate) fn x_minus_sin(x: f64) -> f64 {
    if x.abs() < 1.0 {
        // x − sin x = x³ Σ_{k≥0} (−1)^k x^{2k}/(2k+3)!; ten terms: for |x| < 1 the first
        // omitted term, x²³/23!, is below 2.4·10⁻²² · x³/6.
        const C: [f64; 10] = [
            1.0 / 6.0,
            -1.0 / 120.0,
            1.0 / 5_040.0,
            -1.0 / 362_880.0,
            1.0 / 39_916_800.0,
            -1.0 / 6_227_020_800.0,
            1.0 / 1_307_674_368_000.0,
            -1.0 / 355_687_428_096_000.0,
            1.0 / 121_645_100_408_832_000.0,
            -1.0 / 51_090_942_171_709_440_000.0,
        ];
        let x2 = x * x;
        let mut p = C[9];
        for &c in C[..9].iter().rev() {
            p = p.mul_add(x2, c);
        }
        x * x2 * p
    } else {
        x - x.sin()
    }
}

/// `E − e sin E`, evaluated as `(1 − e) sin E + (E − sin E)` for `|E| < 1` to avoid the
/// cancellation at `e → 1`, `E → 0`.
pub(crate) fn kepler_lhs(ecc_anom: f64, e: f64) -> f64 {
    if ecc_anom.abs() < 1.0 {
        (1.0 - e) * ecc_anom.sin() + x_minus_sin(ecc_anom)
    } else {
        ecc_anom - e * ecc_anom.sin()
    }
}

/// `1 − e cos E = (1 − e) + 2e sin²(E/2)`, free of cancellation.
pub(crate) fn one_minus_e_cos(ecc_anom: f64, e: f64) -> f64 {
    let s = (0.5 * ecc_anom).sin();
    (1.0 - e) + 2.0 * e * s * s
}

/// Real root of `(1 − e) x + x³/6 = m` (`m ≥ 0`): a lower bound of the solution of Kepler's
/// equation (because `sin x ≥ x − x³/6`) that is accurate when `E` is small.
fn cubic_starter(m: f64, e: f64) -> f64 {
    // x³ + 3P x − 2Q = 0 with P = 2(1 − e), Q = 3m (Cardano). With s³ = Q + √(Q² + P³) the root
    // s − P/s is rewritten as 2Q/(s² + P + P²/s²), which does not cancel.
    let p = 2.0 * (1.0 - e);
    let q = 3.0 * m;
    let s = (q + (q * q + p * p * p).sqrt()).cbrt();
    if s > 0.0 {
        2.0 * q / (s * s + p + p * p / (s * s))
    } else {
        0.0
    }
}

/// Solve `E − e sin E = m` for `m ∈ [0, π]`, `e ∈ [0, 1)`; the root lies in `[m, min(π, m + e)]`.
fn solve_kepler_reduced(m: f64, e: f64) -> Result<f64> {
    if m == 0.0 || e == 0.0 {
        return Ok(m);
    }
    // Tiny anomalies: E − e sin E = (1 − e)E + e E³/6 + O(E⁵), so E = M/(1 − e) up to a relative
    // correction e E²/(6(1 − e)) below ε/6 when E² ≤ ε(1 − e). This also covers subnormal M,
    // where relative stopping tests underflow.
    let linear = m / (1.0 - e);
    if linear * linear <= f64::EPSILON * (1.0 - e) {
        return Ok(linear);
    }
    // Bracket: f(m) = −e sin m ≤ 0, f(m + e) = e(1 − sin(m + e)) ≥ 0, f(π) = π − m ≥ 0.
    let lo = m;
    let hi = (m + e).min(PI);
    let cubic = cubic_starter(m, e);
    let mut x = if cubic < 1.0 { cubic } else { m + 0.85 * e };
    if !(lo..=hi).contains(&x) {
        x = 0.5 * (lo + hi);
    }
    bracketed_halley(
        "Kepler's equation (bracketed Halley)",
        |x| (kepler_lhs(x, e) - m, one_minus_e_cos(x, e), e * x.sin()),
        (lo, hi),
        x,
        KEPLER_MAX_ITER,
    )
}

/// Halley's iteration safeguarded by bisection for an increasing `f` with `f(lo) ≤ 0 ≤ f(hi)`,
/// from `x ∈ [lo, hi]`; `f` returns `(f, f′, f″)` at a point. Each iteration takes the Halley step
/// `δ = −(f/f′)/(1 + ½(−f/f′)f″/f′)` when it stays inside the shrinking bracket and bisects
/// otherwise; it stops when the step is below `KEPLER_STEP_TOL` of the iterate (the error after a
/// Halley step from relative error `δ` is `O(δ³)`, far below one ulp) or when the bracket holds
/// adjacent floating-point numbers. Reaching `max_iter` is [`Error::NotConverged`].
///
/// Reference: Press et al., *Numerical Recipes*, 3rd ed., §9.4 (safeguarded Newton); Danby
/// (1988) §6.6 (Halley's method for Kepler's equation).
fn bracketed_halley(
    what: &str,
    f: impl Fn(f64) -> (f64, f64, f64),
    (mut lo, mut hi): (f64, f64),
    mut x: f64,
    max_iter: usize,
) -> Result<f64> {
    let mut residual = f64::NAN;
    for _ in 0..max_iter {
        let (r, fp, fpp) = f(x);
        residual = r;
        if residual == 0.0 {
            return Ok(x);
        }
        if residual < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let newton = -residual / fp;
        let step = newton / (1.0 + 0.5 * newton * fpp / fp);
        if step.abs() <= KEPLER_STEP_TOL * x.abs() {
            return Ok((x + step).clamp(lo, hi));
        }
        let next = x + step;
        if next > lo && next < hi {
            x = next;
        } else {
            let mid = lo + 0.5 * (hi - lo);
            if !(mid > lo && mid < hi) {
                // The bracket holds adjacent floating-point numbers.
                return Ok(x);
            }
            x = mid;
        }
    }
    Err(Error::NotConverged {
        what: what.into(),
        iterations: max_iter,
        residual: residual.abs(),
    })
}

/// Eccentric anomaly `E` solving Kepler's equation `M = E − e sin E` for an elliptic orbit.
///
/// Any real mean anomaly is accepted. It is reduced to `[−π, π]`, the reduced equation is solved
/// (odd symmetry `E(−M) = −E(M)`), and the result is returned consistently with the unreduced
/// `M`: `E(M + 2π) = E(M) + 2π`, i.e. `E − M` is 2π-periodic and `E` is continuous and increasing
/// in `M`.
///
/// The solver is a Halley iteration safeguarded by a bracket (`E − e sin E − M` is increasing in
/// `E`), started from the real root of the cubic `(1 − e)E + E³/6 = M` when that root is small
/// (accurate in the nearly parabolic corner `e → 1`, `M → 0`; cf. Mikkola 1987, Markley 1995) and
/// from Danby's `M + 0.85 e` otherwise. The residual is evaluated as
/// `(1 − e) sin E + (E − sin E) − M` with a series for `E − sin E`, so that the root is found to
/// full relative precision even for `e = 1 − 10⁻⁹`, `M = 10⁻⁶`.
///
/// References: [Ardema 10.3]; Danby (1988) ch. 6; Battin (1999) ch. 5.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ input, [`Error::OutOfDomain`] for `e ∉ [0, 1)`,
/// [`Error::NotConverged`] if the iteration fails (not expected to happen).
pub fn solve_kepler(mean_anomaly: f64, e: f64) -> Result<f64> {
    let m = finite("mean anomaly M", mean_anomaly)?;
    let e = elliptic_eccentricity(e)?;
    periodic_shift(m, |mr| {
        let ea = solve_kepler_reduced(mr.abs(), e)?;
        Ok(ea.copysign(mr))
    })
}

/// True anomaly `ν` from eccentric anomaly `E`:
/// `tan(ν/2) = √((1+e)/(1−e)) tan(E/2)`, evaluated as
/// `ν = 2 atan2(√(1+e) sin(E/2), √(1−e) cos(E/2))` on the reduced angle.
///
/// Any real `E` is accepted and `ν − E` is 2π-periodic (`ν` is continuous and increasing in `E`;
/// `ν = E` at `E = 0, ±π`).
///
/// Reference: [Ardema 10.3]; Battin (1999) ch. 4.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞, [`Error::OutOfDomain`] for `e ∉ [0, 1)`.
pub fn eccentric_to_true(eccentric_anomaly: f64, e: f64) -> Result<f64> {
    let ea = finite("eccentric anomaly E", eccentric_anomaly)?;
    let e = elliptic_eccentricity(e)?;
    let (sp, sm) = ((1.0 + e).sqrt(), (1.0 - e).sqrt());
    periodic_shift(ea, |x| {
        let h = 0.5 * x;
        Ok(2.0 * (sp * h.sin()).atan2(sm * h.cos()))
    })
}

/// Eccentric anomaly `E` from true anomaly `ν`:
/// `tan(E/2) = √((1−e)/(1+e)) tan(ν/2)` (equivalently `cos E = (e + cos ν)/(1 + e cos ν)`,
/// `sin E = √(1−e²) sin ν/(1 + e cos ν)`), evaluated as
/// `E = 2 atan2(√(1−e) sin(ν/2), √(1+e) cos(ν/2))` on the reduced angle.
///
/// Any real `ν` is accepted and `E − ν` is 2π-periodic.
///
/// Reference: [Ardema 10.3]; Battin (1999) ch. 4.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞, [`Error::OutOfDomain`] for `e ∉ [0, 1)`.
pub fn true_to_eccentric(true_anomaly: f64, e: f64) -> Result<f64> {
    let nu = finite("true anomaly ν", true_anomaly)?;
    let e = elliptic_eccentricity(e)?;
    let (sp, sm) = ((1.0 + e).sqrt(), (1.0 - e).sqrt());
    periodic_shift(nu, |x| {
        let h = 0.5 * x;
        Ok(2.0 * (sm * h.sin()).atan2(sp * h.cos()))
    })
}

/// True anomaly from mean anomaly: solve `M = E − e sin E` ([`solve_kepler`]) and convert with
/// [`eccentric_to_true`]. `ν − M` is 2π-periodic.
///
/// Reference: [Ardema 10.3]; Danby (1988) ch. 6.
///
/// # Errors
/// As [`solve_kepler`].
fn elliptic_mean_to_true(mean_anomaly: f64, e: f64) -> Result<f64> {
    let ea = solve_kepler(mean_anomaly, e)?;
    eccentric_to_true(ea, e)
}

/// Mean anomaly from true anomaly: `E` from [`true_to_eccentric`], then `M = E − e sin E`
/// (evaluated without cancellation near `e → 1`, `E → 0`). `M − ν` is 2π-periodic.
///
/// Reference: [Ardema 10.3].
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞, [`Error::OutOfDomain`] for `e ∉ [0, 1)`.
fn elliptic_true_to_mean(true_anomaly: f64, e: f64) -> Result<f64> {
    let nu = finite("true anomaly ν", true_anomaly)?;
    let e = elliptic_eccentricity(e)?;
    periodic_shift(nu, |x| {
        let ea = true_to_eccentric(x, e)?;
        Ok(kepler_lhs(ea, e))
    })
}

/// Iteration cap of the hyperbolic Kepler solver (bracketed Halley: each iteration takes a
/// Halley step or halves the bracket, so reaching it indicates a bug).
const HYPERBOLIC_MAX_ITER: usize = 200;

/// `x` with its real part replaced by `re` (the infinitesimal parts are unchanged).
#[inline]
pub(crate) fn with_re<D: DualNum<f64> + Copy>(x: D, re: f64) -> D {
    x - x.re() + re
}

/// `sinh x − x`, accurate to a few ulps relative (series for `|x| < 1`).
pub(crate) fn sinh_minus_x(x: f64) -> f64 {
    if x.abs() < 1.0 {
        // sinh x − x = x³ Σ_{k≥0} x^{2k}/(2k+3)!; ten terms: the first omitted one, x²³/23!, is
        // below 2.4·10⁻²² · x³/6 for |x| < 1.
        let mut c = [0.0f64; 10];
        let mut f = 6.0;
        for (k, slot) in c.iter_mut().enumerate() {
            *slot = 1.0 / f;
            f *= ((2 * k + 4) * (2 * k + 5)) as f64;
        }
        let x2 = x * x;
        let mut p = c[9];
        for &ck in c[..9].iter().rev() {
            p = p.mul_add(x2, ck);
        }
        x * x2 * p
    } else {
        x.sinh() - x
    }
}

/// `e sinh F − F`, as `(e − 1) sinh F + (sinh F − F)` for `|F| < 1` (no cancellation at
/// `e → 1`, `F → 0`).
pub(crate) fn hyperbolic_lhs(f: f64, e: f64) -> f64 {
    if f.abs() < 1.0 {
        (e - 1.0) * f.sinh() + sinh_minus_x(f)
    } else {
        e * f.sinh() - f
    }
}

/// `e cosh F − 1 = (e − 1) + 2e sinh²(F/2)`, free of cancellation.
pub(crate) fn e_cosh_minus_one(f: f64, e: f64) -> f64 {
    let s = (0.5 * f).sinh();
    (e - 1.0) + 2.0 * e * s * s
}

/// Real root of `x³ + 3P x − 2Q = 0` (`P ≥ 0`, `Q ≥ 0`) by Cardano, written without
/// cancellation: with `s³ = Q + √(Q² + P³)` the root `s − P/s` equals `2Q/(s² + P + P²/s²)`.
pub(crate) fn cardano(p: f64, q: f64) -> f64 {
    let s = (q + (q * q + p * p * p).sqrt()).cbrt();
    if s > 0.0 {
        2.0 * q / (s * s + p + p * p / (s * s))
    } else {
        0.0
    }
}

/// Solve `e sinh F − F = m` for `m ≥ 0`, `e > 1`.
fn solve_hyperbolic_reduced(m: f64, e: f64) -> Result<f64> {
    if m == 0.0 {
        return Ok(0.0);
    }
    let em1 = e - 1.0;
    // e sinh F − F = (e − 1)F + eF³/6 + O(F⁵): F = M/(e − 1) up to a relative correction
    // eF²/(6(e − 1)), below ε/6 when eF² ≤ ε(e − 1).
    let linear = m / em1;
    if e * linear * linear <= f64::EPSILON * em1 {
        return Ok(linear);
    }
    // Large M: for F ≥ 40, sinh F = e^F/2 to a relative e^{−2F} < 10⁻³⁴, and the equation reads
    // F = ln(2(M + F)/e), a contraction with factor 1/(M + F) < 10⁻¹⁸, iterated from F = 0 without
    // evaluating sinh (which overflows for F > 710 although F itself stays below 711 for every
    // finite M). F ≥ 40 holds when M/e ≥ sinh 40 ≈ 1.2·10¹⁷.
    if m / e > 1e18 {
        let mut x = 0.0;
        for _ in 0..3 {
            x = ((m + x) / e).ln() + LN_2;
        }
        return Ok(x);
    }
    // Bracket: e sinh F = M + F ≥ M gives F ≥ asinh(M/e); e sinh F − F ≥ (e − 1) sinh F gives
    // F ≤ asinh(M/(e − 1)) (with asinh x ≤ ln x + ln 2 + 1/x² used when M/(e − 1) overflows).
    let lo = (m / e).asinh();
    let ratio = m / em1;
    let hi = if ratio.is_finite() {
        ratio.asinh()
    } else {
        m.ln() - em1.ln() + LN_2 + 1.0
    };
    // Starters: the real root of (e − 1)F + F³/6 = M (an upper bound, since
    // e sinh F − F ≥ (e − 1)F + F³/6) when it is small, otherwise ln(2M/e + 1.8) (Vallado 2013,
    // algorithm 4).
    let cubic = cardano(2.0 * em1, 3.0 * m);
    let mut x = if cubic < 1.0 {
        cubic
    } else {
        (2.0 * m / e + 1.8).ln()
    };
    if !(lo..=hi).contains(&x) {
        x = 0.5 * (lo + hi);
    }
    bracketed_halley(
        "hyperbolic Kepler equation (bracketed Halley)",
        |x| {
            (
                hyperbolic_lhs(x, e) - m,
                e_cosh_minus_one(x, e),
                e * x.sinh(),
            )
        },
        (lo, hi),
        x,
        HYPERBOLIC_MAX_ITER,
    )
}

/// Hyperbolic anomaly `F` solving the hyperbolic Kepler equation `M = e sinh F − F` (`e > 1`,
/// any real `M`; odd in `M`).
///
/// Bracketed Halley iteration on the increasing function `e sinh F − F − M` in
/// `[asinh(M/e), asinh(M/(e − 1))]`, started from the real root of the cubic
/// `(e − 1)F + F³/6 = M` when that is small (near-parabolic corner `e → 1⁺`, `M → 0`) and from
/// `ln(2M/e + 1.8)` otherwise; the residual is evaluated as `(e − 1) sinh F + (sinh F − F) − M`
/// with a series for `sinh F − F`, so `F` has full relative precision (Vallado 2013 §2.2;
/// Battin 1999 §4.6).
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞, [`Error::OutOfDomain`] for `e ≤ 1`,
/// [`Error::NotConverged`] if the iteration fails (not expected).
pub fn solve_kepler_hyperbolic(mean_anomaly: f64, e: f64) -> Result<f64> {
    let m = finite("hyperbolic mean anomaly M", mean_anomaly)?;
    let e = finite("eccentricity e", e)?;
    if e <= 1.0 {
        return Err(Error::out_of_domain("eccentricity e", e, "(1, ∞)"));
    }
    Ok(solve_hyperbolic_reduced(m.abs(), e)?.copysign(m))
}

/// `B = tan(ν/2)` solving Barker's equation `B + B³/3 = M_p` for a parabolic orbit, where
/// `M_p = 2√(μ/p³)(t − t_p)` (Vallado 2013 §2.2, algorithm 3), in closed form (Cardano, written
/// without cancellation), generic over the dual type (the closed form is smooth, so its
/// derivatives are exact).
///
/// # Errors
/// [`Error::NonFinite`] for a NaN/∞ real part of `M_p`.
pub fn solve_barker<D: DualNum<f64> + Copy>(mean_anomaly: D) -> Result<D> {
    let m = finite("parabolic mean anomaly M_p", mean_anomaly.re())?;
    // B³ + 3B − 3M = 0: Cardano with P = 1, Q = 3|M|/2; s³ = Q + √(Q² + 1) > 0 and
    // B = 2Q/(s² + 1 + s⁻²).
    let sign = if m < 0.0 { -1.0 } else { 1.0 };
    let m_abs = mean_anomaly * sign;
    let b = if 1.5 * m.abs() > 1.0 {
        // s = Q^{1/3}k with k = ∛(1 + √(1 + Q⁻²)), so B = 2Q^{1/3}/(k²(1 + s⁻² + s⁻⁴)): no power
        // of Q above 1/3 is formed, and |M| up to f64::MAX gives a finite B ≈ ∛(3M).
        let q_inv = m_abs.recip() * (1.0 / 1.5);
        let k = ((q_inv * q_inv + 1.0).sqrt() + 1.0).cbrt();
        let q13 = m_abs.cbrt() * 1.5f64.cbrt();
        let s = q13 * k;
        let s2i = (s * s).recip();
        q13 * 2.0 / (k * k) / (s2i * (s2i + 1.0) + 1.0)
    } else {
        let q = m_abs * 1.5;
        let s = (q + (q * q + 1.0).sqrt()).cbrt();
        let s2 = s * s;
        q * 2.0 / (s2 + 1.0 + s2.recip())
    };
    Ok(b * sign)
}

/// Eccentric anomaly `E` of an ellipse from `M = E − e sin E`, in any dual type: the real root
/// by [`solve_kepler`], then its exact derivatives with respect to `M` and `e` by
/// [`lift_scalar_root`] (see the [module docs](self)).
///
/// # Errors
/// As [`solve_kepler`] (on the real parts) and [`lift_scalar_root`].
pub fn eccentric_anomaly<D: DualNum<f64> + Copy>(mean_anomaly: D, e: D) -> Result<D> {
    let ea = solve_kepler(mean_anomaly.re(), e.re())?;
    lift_scalar_root(ea, one_minus_e_cos(ea, e.re()), |ea: D| {
        ea - e * ea.sin() - mean_anomaly
    })
}

/// Hyperbolic anomaly `F` from `M = e sinh F − F`, in any dual type: real root by
/// [`solve_kepler_hyperbolic`], then its exact derivatives by [`lift_scalar_root`].
///
/// # Errors
/// As [`solve_kepler_hyperbolic`] (on the real parts) and [`lift_scalar_root`].
pub fn hyperbolic_anomaly<D: DualNum<f64> + Copy>(mean_anomaly: D, e: D) -> Result<D> {
    let f = solve_kepler_hyperbolic(mean_anomaly.re(), e.re())?;
    lift_scalar_root(f, e_cosh_minus_one(f, e.re()), |f: D| {
        e * f.sinh() - f - mean_anomaly
    })
}

/// True anomaly `ν` from the mean anomaly of any conic, switching on `e` (see
/// [`Conic::of_eccentricity`]):
///
/// * `e < 1`: Kepler's equation [`solve_kepler`] (`ν − M` is 2π-periodic);
/// * `e = 1`: `ν = 2 atan B` with `B` from Barker's equation `B + B³/3 = M_p`
///   ([`solve_barker`]); `ν ∈ (−π, π)`;
/// * `e > 1`: `F` from `M = e sinh F − F`, then
///   `ν = 2 atan2(√(e+1) sinh(F/2), √(e−1) cosh(F/2))`; `|ν| < acos(−1/e)`.
///
/// Reference: Vallado (2013) §2.2.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞, [`Error::OutOfDomain`] for `e < 0`; errors of the solvers.
pub fn mean_to_true(mean_anomaly: f64, e: f64) -> Result<f64> {
    let m = finite("mean anomaly M", mean_anomaly)?;
    match Conic::of_eccentricity(e)? {
        Conic::Elliptic => elliptic_mean_to_true(m, e),
        Conic::Parabolic => Ok(2.0 * solve_barker(m)?.atan()),
        Conic::Hyperbolic => {
            let f = solve_kepler_hyperbolic(m, e)?;
            let h = 0.5 * f;
            Ok(2.0 * ((e + 1.0).sqrt() * h.sinh()).atan2((e - 1.0).sqrt() * h.cosh()))
        }
    }
}

/// Mean anomaly from the true anomaly of any conic (inverse of [`mean_to_true`]):
/// `e < 1`: `E` from `ν`, `M = E − e sin E`; `e = 1`: `M_p = B + B³/3`, `B = tan(ν/2)`;
/// `e > 1`: `F = 2 atanh(√((e−1)/(e+1)) tan(ν/2))`, `M = e sinh F − F` (evaluated without
/// cancellation near `e → 1`).
///
/// Reference: Vallado (2013) §2.2.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] for `e < 0`, for `|ν| ≥ π` on a
/// parabola and for `|ν| ≥ acos(−1/e)` (beyond the asymptotes) on a hyperbola.
pub fn true_to_mean(true_anomaly: f64, e: f64) -> Result<f64> {
    let nu = finite("true anomaly ν", true_anomaly)?;
    match Conic::of_eccentricity(e)? {
        Conic::Elliptic => elliptic_true_to_mean(nu, e),
        Conic::Parabolic => {
            if nu.abs() >= PI {
                return Err(Error::out_of_domain(
                    "true anomaly ν of a parabola",
                    nu,
                    "(−π, π)",
                ));
            }
            let b = (0.5 * nu).tan();
            Ok(b + b * b * b / 3.0)
        }
        Conic::Hyperbolic => {
            let nu_max = (-1.0 / e).acos();
            if nu.abs() >= nu_max {
                return Err(Error::out_of_domain(
                    "true anomaly ν of a hyperbola",
                    nu,
                    format!("(−{nu_max}, {nu_max}) (between the asymptotes)"),
                ));
            }
            // tanh(F/2) = √((e−1)/(e+1)) tan(ν/2) = √(e−1) sin(ν/2) / (√(e+1) cos(ν/2)).
            let h = 0.5 * nu;
            let t = ((e - 1.0).sqrt() * h.sin()) / ((e + 1.0).sqrt() * h.cos());
            if t.abs() >= 1.0 {
                return Err(Error::out_of_domain(
                    "true anomaly ν of a hyperbola",
                    nu,
                    format!("(−{nu_max}, {nu_max}) (between the asymptotes)"),
                ));
            }
            let f = 2.0 * t.atanh();
            Ok(hyperbolic_lhs(f, e))
        }
    }
}

/// The type of a Kepler conic, from its eccentricity.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Conic {
    /// `0 ≤ e < 1`.
    Elliptic,
    /// `e = 1` exactly.
    Parabolic,
    /// `e > 1`.
    Hyperbolic,
}

impl Conic {
    /// The conic type of eccentricity `e` (`e = 1` exactly is parabolic).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞, [`Error::OutOfDomain`] for `e < 0`.
    pub fn of_eccentricity(e: f64) -> Result<Self> {
        let e = finite("eccentricity e", e)?;
        if e < 0.0 {
            Err(Error::out_of_domain("eccentricity e", e, "[0, ∞)"))
        } else if e < 1.0 {
            Ok(Conic::Elliptic)
        } else if e == 1.0 {
            Ok(Conic::Parabolic)
        } else {
            Ok(Conic::Hyperbolic)
        }
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use proptest::prelude::*;
    use proptest::test_runner::RngSeed;

    const EPS: f64 = f64::EPSILON;

    /// Property-test configuration of the Kepler tests: 1000 cases from a fixed seed.
    pub(crate) fn cfg() -> ProptestConfig {
        ProptestConfig {
            cases: 1000,
            rng_seed: RngSeed::Fixed(12345),
            failure_persistence: None,
            ..ProptestConfig::default()
        }
    }

    /// Distance of two angles modulo 2π.
    pub(crate) fn ang_diff(x: f64, y: f64) -> f64 {
        ((x - y + PI).rem_euclid(TAU) - PI).abs()
    }

    /// Independent oracle for x − sin x: Taylor terms summed from the smallest up (|x| < 1),
    /// direct difference otherwise.
    fn oracle_x_minus_sin(x: f64) -> f64 {
        if x.abs() < 1.0 {
            let mut terms = [0.0; 12];
            let mut t = x * x * x / 6.0;
            for (k, slot) in terms.iter_mut().enumerate() {
                *slot = t;
                let d = (2 * k + 4) as f64 * (2 * k + 5) as f64;
                t *= -x * x / d;
            }
            terms.iter().rev().sum()
        } else {
            x - x.sin()
        }
    }

    /// Oracle residual of Kepler's equation and the sum of the magnitudes of its terms (for the
    /// rounding-error bound).
    fn oracle_residual(ea: f64, e: f64, m: f64) -> (f64, f64) {
        if ea.abs() < 1.0 {
            let a = (1.0 - e) * ea.sin();
            let b = oracle_x_minus_sin(ea);
            ((a + b) - m, a.abs() + b.abs() + m.abs())
        } else {
            let s = e * ea.sin();
            ((ea - s) - m, ea.abs() + s.abs() + m.abs())
        }
    }

    /// Bisection oracle on the monotone function E − e sin E − M (M ∈ [−π, π]) down to adjacent
    /// floating-point numbers.
    fn bisection_oracle(m: f64, e: f64) -> f64 {
        let (mut lo, mut hi) = (-PI, PI);
        loop {
            let mid = 0.5 * (lo + hi);
            if mid <= lo || mid >= hi {
                break;
            }
            if oracle_residual(mid, e, m).0 < 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let (rl, rh) = (oracle_residual(lo, e, m).0, oracle_residual(hi, e, m).0);
        if rl.abs() <= rh.abs() {
            lo
        } else {
            hi
        }
    }

    /// One unit in the last place of `|x|` (the smallest subnormal at 0).
    pub(crate) fn ulp(x: f64) -> f64 {
        let x = x.abs();
        if x == 0.0 {
            f64::from_bits(1)
        } else {
            f64::from_bits(x.to_bits() + 1) - x
        }
    }

    // -----------------------------------------------------------------------------------------
    // Kepler's equation near e = 1
    // -----------------------------------------------------------------------------------------

    #[test]
    fn reference_values_near_e_one() {
        // (e, M, tabulated E, E from a 50-digit mpmath solution for the f64 inputs, relative
        // tolerance). ∂E/∂e ≈ 110 in the first case, so the tabulated digits are compared at 1e-12;
        // the mpmath values at 4 ulps (the root is determined to ~1 ulp by the careful residual).
        let cases = [
            (
                0.999999,
                1e-6,
                0.0180612466215222,
                0.018061246621522216,
                1e-12,
            ),
            (0.99, 0.01, 0.342270316491775, 0.3422703164917751, 1e-14),
            (0.9, 0.1, 0.630843527563153, 0.6308435275631535, 1e-14),
        ];
        for (e, m, spec, mp, rel) in cases {
            let ea = solve_kepler(m, e).unwrap();
            let err_spec = ((ea - spec) / spec).abs();
            let err_mp = ((ea - mp) / mp).abs();
            eprintln!(
                "e={e} M={m}: E={ea:.17} rel err vs table {err_spec:e}, vs mpmath {err_mp:e}"
            );
            assert!(err_spec <= rel);
            assert!(err_mp <= 4.0 * EPS);
            // Odd symmetry and periodicity.
            assert_eq!(solve_kepler(-m, e).unwrap(), -ea);
            let shifted = solve_kepler(m + 4.0 * TAU, e).unwrap() - 4.0 * TAU;
            // Forming M + 8π, reducing it and adding 8π back cost ~2 ulp(8π) in M and in E;
            // dE/dM = 1/(1 − e cos E) ≈ 6000 in the first case.
            let tol = 2.0 * ulp(4.0 * TAU) * (1.0 + 1.0 / one_minus_e_cos(ea, e));
            assert!((shifted - ea).abs() <= tol, "{shifted} vs {ea}");
        }
    }

    // -----------------------------------------------------------------------------------------
    // Kepler's equation on a dense grid
    // -----------------------------------------------------------------------------------------

    #[test]
    fn kepler_residual_dense_grid() {
        let es = [0.0, 1e-12, 0.1, 0.5, 0.9, 0.99, 0.999999, 1.0 - 1e-9];
        let mut ms: Vec<f64> = (0..=8000).map(|k| -PI + TAU * k as f64 / 8000.0).collect();
        for k in 0..=300 {
            let small = 10f64.powf(-(k as f64));
            ms.push(small);
            ms.push(-small);
            ms.push(PI - small);
        }
        ms.extend([0.0, -0.0, PI, -PI, f64::MIN_POSITIVE, 5e-324]);
        let mut max_res: f64 = 0.0;
        let mut max_strict: f64 = 0.0;
        let mut max_vs_bisect: f64 = 0.0;
        for &e in &es {
            for &m in &ms {
                let ea = solve_kepler(m, e).unwrap();
                let (res, size) = oracle_residual(ea, e, m);
                // Required: a residual of a few ulps of max(1, |M|).
                assert!(
                    res.abs() <= 1e-15 * m.abs().max(1.0),
                    "e={e} M={m}: residual {res:e}"
                );
                max_res = max_res.max(res.abs());
                // Strict criterion: the best float is within f'(E)·ulp(E) of the root, and the
                // oracle residual itself carries ≤ 4ε·(sum of its terms) of rounding.
                let fp = 1.0 - e * ea.cos();
                let bound = fp * ulp(ea) + 4.0 * EPS * size + 4.0 * f64::from_bits(1);
                max_strict = max_strict.max(res.abs() / bound);
                assert!(
                    res.abs() <= bound,
                    "e={e} M={m}: residual {res:e} > {bound:e}"
                );
                // Bisection oracle: both roots are determined up to the residual noise / f'.
                let eb = bisection_oracle(m, e);
                let fp = one_minus_e_cos(ea, e);
                // (Plus a few units of the smallest subnormal for the absolute rounding of
                // underflowed operations at |M| ≲ 1e-308.)
                let tol = 2.0 * ulp(ea) + (8.0 * EPS * size + 8.0 * f64::from_bits(1)) / fp;
                max_vs_bisect = max_vs_bisect.max((ea - eb).abs() / tol);
                assert!(
                    (ea - eb).abs() <= tol,
                    "e={e} M={m}: {ea} vs bisection {eb}"
                );
            }
        }
        eprintln!(
            "residual grid: max |res| {max_res:e}, max res/strict bound {max_strict:.3}, \
             max |E − E_bisect|/tol {max_vs_bisect:.3}"
        );
    }

    #[test]
    fn kepler_unreduced_mean_anomaly_is_consistent() {
        for &e in &[0.0, 0.3, 0.9, 0.999] {
            for k in -50..=50 {
                let m0 = 0.1 + 0.05 * k as f64;
                let e0 = solve_kepler(m0, e).unwrap();
                let base = e0 - m0;
                let cond = 1.0 + 1.0 / one_minus_e_cos(e0, e);
                for j in [-1000.0, -3.0, -1.0, 1.0, 7.0, 1e6] {
                    let m = m0 + j * TAU;
                    let ea = solve_kepler(m, e).unwrap();
                    // E − M periodic up to the rounding of M, of the reduction and of the
                    // shift back, ≲ 2 ulp(M) each, amplified by dE/dM = 1/(1 − e cos E).
                    assert!(
                        ((ea - m) - base).abs() <= 4.0 * ulp(m) * cond,
                        "e={e} M={m}"
                    );
                }
            }
        }
        // Monotone and continuous across the reduction boundary ±π.
        let e = 0.7;
        let below = solve_kepler(PI - 1e-12, e).unwrap();
        let above = solve_kepler(PI + 1e-12, e).unwrap();
        assert!(below < above && above - below < 1e-10);
        // Huge |M| is accepted without panicking.
        assert!(solve_kepler(1e300, 0.5).unwrap().is_finite());
    }

    // -----------------------------------------------------------------------------------------
    // Anomaly conversions
    // -----------------------------------------------------------------------------------------

    #[test]
    fn anomaly_conversions_agree_with_defining_relations() {
        let mut max_err: f64 = 0.0;
        for &e in &[0.0, 0.2, 0.6, 0.95, 0.999] {
            for k in -200..=200 {
                let nu = 0.031 * k as f64; // spans about ±1 turn
                let ea = true_to_eccentric(nu, e).unwrap();
                let c = (e + nu.cos()) / (1.0 + e * nu.cos());
                let s = ((1.0 - e) * (1.0 + e)).sqrt() * nu.sin() / (1.0 + e * nu.cos());
                // Unit-vector comparison; the direct formulas have conditioning ≲ 1/(1 − e).
                let err = (ea.cos() - c).abs().max((ea.sin() - s).abs());
                max_err = max_err.max(err * (1.0 - e));
                assert!(err <= 16.0 * EPS / (1.0 - e), "e={e} ν={nu}");
                let back = eccentric_to_true(ea, e).unwrap();
                // E carries ~ulp errors, magnified by dν/dE ≤ √((1+e)/(1−e)).
                let dnude = ((1.0 + e) / (1.0 - e)).sqrt();
                assert!((back - nu).abs() <= 8.0 * ulp(nu.abs().max(1.0)) * dnude);
                let m = true_to_mean(nu, e).unwrap();
                let m_direct = ea - e * ea.sin();
                assert!((m - m_direct).abs() <= 8.0 * ulp(m.abs().max(1.0)));
                let nu2 = mean_to_true(m, e).unwrap();
                // dν/dM = (a/r)²√(1−e²) ≤ √((1+e)/(1−e))/(1−e); ≤ 8 ulp of M through it.
                let cond = ((1.0 + e) / (1.0 - e)).sqrt() / (1.0 - e);
                assert!(
                    ang_diff(nu2, nu) <= 8.0 * EPS * cond * m.abs().max(1.0),
                    "e={e} ν={nu} → M={m} → {nu2}"
                );
            }
        }
        eprintln!("anomalies: max |(cos,sin) E error|·(1−e) {max_err:e}");
    }

    // -----------------------------------------------------------------------------------------
    // Barker's equation and bad input
    // -----------------------------------------------------------------------------------------

    #[test]
    fn barker_closed_form() {
        for m in [
            0.0, 1e-300, 1e-8, 0.3, -2.0, 1e6, -1e12, 1e154, 1e200, -1e300,
        ] {
            let b: f64 = solve_barker(m).unwrap();
            let back = b + b * b * b / 3.0;
            assert!(
                (back - m).abs() <= 4.0 * f64::EPSILON * m.abs(),
                "{m}: {back}"
            );
        }
    }

    #[test]
    fn bad_input_is_rejected() {
        let ood = |r: Result<f64>| matches!(r, Err(Error::OutOfDomain { .. }));
        let nf = |r: Result<f64>| matches!(r, Err(Error::NonFinite { .. }));
        for e in [1.0, 1.5, -0.1] {
            assert!(ood(solve_kepler(0.3, e)));
            assert!(ood(eccentric_to_true(0.3, e)));
            assert!(ood(true_to_eccentric(0.3, e)));
            // The anomaly conversions cover every conic: only e < 0 is outside their domain.
            assert_eq!(ood(mean_to_true(0.3, e)), e < 0.0);
            assert_eq!(ood(true_to_mean(0.3, e)), e < 0.0);
        }
        if let Err(Error::OutOfDomain { domain, .. }) = solve_kepler(0.3, 1.0) {
            assert_eq!(domain, "[0, 1)");
        } else {
            panic!("expected OutOfDomain");
        }
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(nf(solve_kepler(bad, 0.5)));
            assert!(nf(solve_kepler(0.5, bad)));
            assert!(nf(eccentric_to_true(bad, 0.5)));
        }
    }

    proptest! {
        #![proptest_config(cfg())]

        /// Kepler residual for arbitrary M (including unreduced) and e ∈ [0, 1).
        #[test]
        fn kepler_residual_property(
            m in -100.0..100.0f64,
            e in prop_oneof![0.0..1.0f64, (1e-12..1e-3f64).prop_map(|d| 1.0 - d)],
        ) {
            let ea = solve_kepler(m, e).unwrap();
            // Compare in the reduced frame, where the oracle residual is cancellation-free; the
            // reduction itself costs ≤ 2 ulp(M).
            let (mr, _) = reduce_angle(m);
            let er = ea - (m - mr);
            let (res, size) = oracle_residual(er, e, mr);
            let fp = 1.0 - e * er.cos();
            let bound = fp * ulp(er) + 4.0 * EPS * size + 4.0 * ulp(m);
            prop_assert!(res.abs() <= bound, "M={m} e={e}: {res:e} > {bound:e}");
            prop_assert!(res.abs() <= 1e-15 * m.abs().max(1.0));
        }
    }
}

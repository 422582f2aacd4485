//! Stumpff functions and Kepler's equation in universal variables.
//!
//! The Stumpff functions
//!
//! ```math
//! c_2(z) = \sum_{k\ge0} \frac{(-z)^k}{(2k+2)!}, \qquad c_3(z) = \sum_{k\ge0} \frac{(-z)^k}{(2k+3)!}
//! ```
//!
//! are, in closed form,
//!
//! | | `z > 0` | `z = 0` | `z < 0` |
//! |---|---|---|---|
//! | `c₂` | `(1 − cos√z)/z` | `1/2` | `(cosh√−z − 1)/(−z)` |
//! | `c₃` | `(√z − sin√z)/√z³` | `1/6` | `(sinh√−z − √−z)/√(−z)³` |
//!
//! They carry the elliptic (`z > 0`), parabolic (`z = 0`) and hyperbolic (`z < 0`) two-body
//! motion in one formula: with the universal anomaly `χ`, `z = αχ²`, `α = 1/a = 2/r₀ − |p₀|²/μ`,
//! `σ₀ = q₀·p₀/√μ`, Kepler's equation in universal variables reads
//!
//! ```math
//! \sqrt\mu\,\Delta t = \sigma_0\chi^2 c_2(z) + (1 - \alpha r_0)\chi^3 c_3(z) + r_0\chi,
//! \qquad \frac{d(\sqrt\mu\,\Delta t)}{d\chi} = r = \chi^2 c_2 + \sigma_0\chi(1 - z c_3) + r_0(1 - z c_2),
//! ```
//!
//! whose right-hand side increases with `χ` (its derivative is the radius `r > 0`), so it has one
//! real root for every `Δt`. The two-body flow built on it is
//! [`crate::systems::kepler::propagate`].
//!
//! # Numerical care
//!
//! * `|z| < 2.5`: the power series, 18 terms by Horner's rule (truncation below
//!   `2.5¹⁸/37! ≈ 10⁻³⁶`), with no cancellation near `z = 0`; each coefficient `1/n!` enters as
//!   the sum of its rounded value and its rounding error, so that the values are within one
//!   rounding of the exact ones and unbiased (a fixed-sign error in every evaluation, such as
//!   that of `fl(1/6)`, would make the energy of a flow composed of many steps drift linearly
//!   instead of as a random walk);
//! * otherwise the closed forms with `1 − cos x = 2 sin²(x/2)` and `cosh x − 1 = 2 sinh²(x/2)`.
//!
//! # References
//!
//! * D. A. Vallado, *Fundamentals of Astrodynamics and Applications*, 4th ed., Microcosm (2013),
//!   §2.2 (the `c₂`, `c₃` functions, algorithm 1), §2.3 (universal variables, algorithm 8).
//! * R. H. Battin, *An Introduction to the Mathematics and Methods of Astrodynamics*, rev. ed.,
//!   AIAA (1999), §4.5 (universal functions and the universal form of Kepler's equation).
//! * J. M. A. Danby, *Fundamentals of Celestial Mechanics*, 2nd ed., Willmann-Bell (1988), §6.9.
//! * K. Stumpff, *Himmelsmechanik*, vol. 1, VEB Deutscher Verlag der Wissenschaften (1959).

use std::f64::consts::PI;

use num_dual::DualNum;

use crate::error::{finite, Error, Result};
use crate::special::kepler_equation::solve_kepler_hyperbolic;

/// The Stumpff functions `(c₂(z), c₃(z))` in any dual type (see the [module docs](self) for the
/// series and the closed forms; Vallado 2013 §2.2, Battin 1999 §4.5).
///
/// # Errors
/// [`Error::NonFinite`] for a NaN/∞ `z`; [`Error::OutOfDomain`] for `z` so negative that
/// `sinh√−z` overflows (`z ≲ −5·10⁵`, where `c₃` exceeds the floating-point range of its
/// intermediate `sinh`).
pub fn c2_c3<D: DualNum<f64> + Copy>(z: D) -> Result<(D, D)> {
    finite("Stumpff argument z", z.re())?;
    let (c2, c3) = stumpff(z);
    if c2.re().is_finite() && c3.re().is_finite() {
        Ok((c2, c3))
    } else {
        Err(Error::out_of_domain(
            "Stumpff argument z (sinh √−z overflows)",
            z.re(),
            "(−5·10⁵, ∞)",
        ))
    }
}

/// Terms of the power series used for `|z| < 2.5` (truncation below `2.5¹⁸/37! ≈ 10⁻³⁶`).
const SERIES_TERMS: usize = 18;

/// The series coefficients `1/(2k+2)!` of `c₂`, `k = 0, …, 17`, each as `hi + lo`: `hi` correctly
/// rounded, `lo` its rounding error (from a 60-digit evaluation).
const C2: [(f64, f64); SERIES_TERMS] = [
    (0.5, 0.0),
    (0.041666666666666664, 2.3129646346357427e-18),
    (0.001388888888888889, -5.300543954373577e-20),
    (2.48015873015873e-05, 2.1511947866775882e-23),
    (2.755731922398589e-07, 2.3767714622250297e-23),
    (2.08767569878681e-09, -1.20734505911326e-25),
    (1.1470745597729725e-11, 2.0655512752830745e-28),
    (4.779477332387385e-14, 4.399205485834081e-31),
    (1.5619206968586225e-16, 1.1910679660273754e-32),
    (4.110317623312165e-19, 1.4412973378659527e-36),
    (8.896791392450574e-22, -7.911402614872376e-38),
    (1.6117375710961184e-24, -3.6846573564509766e-41),
    (2.4795962632247976e-27, -1.2953730964765229e-43),
    (3.279889237069838e-30, 1.5117542744029879e-46),
    (3.7699876288159054e-33, 2.5870347832750324e-49),
    (3.8003907548547434e-36, 1.7457158024652518e-52),
    (3.387157535521162e-39, 5.09056148151085e-56),
    (2.6882202662866363e-42, 5.355061165943334e-59),
];

/// The series coefficients `1/(2k+3)!` of `c₃`, `k = 0, …, 17`, each as `hi + lo`: `hi` correctly
/// rounded, `lo` its rounding error (from a 60-digit evaluation).
const C3: [(f64, f64); SERIES_TERMS] = [
    (0.16666666666666666, 9.25185853854297e-18),
    (0.008333333333333333, 1.1564823173178714e-19),
    (0.0001984126984126984, 1.7209558293420705e-22),
    (2.7557319223985893e-06, -1.858393274046472e-22),
    (2.505210838544172e-08, -1.448814070935912e-24),
    (1.6059043836821613e-10, 1.2585294588752098e-26),
    (7.647163731819816e-13, 7.03872877733453e-30),
    (2.8114572543455206e-15, 1.6508842730861433e-31),
    (8.22063524662433e-18, 2.2141894119604265e-34),
    (1.9572941063391263e-20, -1.3643503830087908e-36),
    (3.868170170630684e-23, -8.843177655482344e-40),
    (6.446950284384474e-26, -1.9330404233703465e-42),
    (9.183689863795546e-29, 1.4303150396787322e-45),
    (1.1309962886447716e-31, 1.0498015412959506e-47),
    (1.216125041553518e-34, 5.586290567888806e-51),
    (1.151633562077195e-37, -6.09957445788454e-54),
    (9.67759295863189e-41, 3.202295548645562e-57),
    (7.265460179153071e-44, -4.364097149354446e-61),
];

/// `(c₂(z), c₃(z))` without checks: series for `|z| < 2.5`, closed forms otherwise. Non-finite
/// (overflowing) for `z ≲ −5·10⁵`, which the universal Kepler equation treats as "beyond the root".
pub(crate) fn stumpff<D: DualNum<f64> + Copy>(z: D) -> (D, D) {
    let zr = z.re();
    if zr.abs() < 2.5 {
        // Horner from the top. Each coefficient enters as (tail + lo) + hi, so that its own
        // rounding does not bias the sum: a fixed-sign error of ~ε/4 (that of fl(1/6)) in every
        // evaluation would accumulate linearly over the many steps of a composed flow.
        let mz = -z;
        let (mut c, mut s) = (D::from(0.0), D::from(0.0));
        for k in (0..SERIES_TERMS).rev() {
            c = (c * mz + C2[k].1) + C2[k].0;
            s = (s * mz + C3[k].1) + C3[k].0;
        }
        (c, s)
    } else if zr > 0.0 {
        let x = z.sqrt();
        let h = (x * 0.5).sin();
        ((h * h * 2.0) / z, (x - x.sin()) / (z * x))
    } else {
        let x = (-z).sqrt();
        let h = (x * 0.5).sinh();
        ((h * h * 2.0) / (-z), (x.sinh() - x) / (-z * x))
    }
}

/// Universal Kepler equation residual `F(χ) = σ₀χ²c₂ + (1 − αr₀)χ³c₃ + r₀χ − √μ Δt` and its
/// derivative `r(χ)` in any dual type (`rhs = √μ Δt`).
pub(crate) fn universal<D: DualNum<f64> + Copy>(
    chi: D,
    r0: D,
    sigma0: D,
    alpha: D,
    rhs: D,
) -> (D, D) {
    let chi2 = chi * chi;
    let z = alpha * chi2;
    let (c, s) = stumpff(z);
    let f = sigma0 * chi2 * c + (-alpha * r0 + 1.0) * chi2 * chi * s + r0 * chi - rhs;
    let r = chi2 * c + sigma0 * chi * (-z * s + 1.0) + r0 * (-z * c + 1.0);
    (f, r)
}

/// `F(χ)`, `r(χ)` on reals, and the sum of the magnitudes of the terms of `F` (the scale of its
/// rounding error).
fn universal_real(chi: f64, r0: f64, sigma0: f64, alpha: f64, rhs: f64) -> (f64, f64, f64) {
    let chi2 = chi * chi;
    let z = alpha * chi2;
    let (c, s) = stumpff(z);
    let t1 = sigma0 * chi2 * c;
    let t2 = (1.0 - alpha * r0) * chi2 * chi * s;
    let t3 = r0 * chi;
    let f = t1 + t2 + t3 - rhs;
    let r = chi2 * c + sigma0 * chi * (1.0 - z * s) + r0 * (1.0 - z * c);
    (f, r, t1.abs() + t2.abs() + t3.abs() + rhs.abs())
}

/// Starter for a hyperbolic arc (`α < 0`): the hyperbolic Kepler equation `e sinh H − H = M`
/// solved by [`solve_kepler_hyperbolic`] and mapped to `χ = (H₁ − H₀)/√(−α)` (Battin 1999 §4.5,
/// `e cosh H₀ = 1 − αr₀`, `e sinh H₀ = σ₀√(−α)`, `M₁ − M₀ = (−α)^{3/2}√μ Δt`,
/// `e² = 1 − α h²/μ` with `h²/μ = 2r₀ − αr₀² − σ₀²`). `None` where the conversion is not defined
/// (nearly parabolic, `e` not above 1 after rounding), leaving the geometric search.
fn hyperbolic_starter(r0: f64, sigma0: f64, alpha: f64, rhs: f64) -> Option<f64> {
    let sa = (-alpha).sqrt();
    let h2_over_mu = (2.0 * r0 - alpha * r0 * r0 - sigma0 * sigma0).max(0.0);
    let e = (1.0 - alpha * h2_over_mu).sqrt();
    if !(e > 1.0 && e.is_finite()) {
        return None;
    }
    let es = sigma0 * sa;
    let h0 = (es / e).asinh();
    let m0 = es - h0;
    let m1 = m0 + (-alpha) * sa * rhs;
    let h1 = solve_kepler_hyperbolic(m1, e).ok()?;
    let chi = (h1 - h0) / sa;
    chi.is_finite().then_some(chi)
}

/// Real root `χ` of the universal Kepler equation `F(χ) = 0` and the radius `r(χ)` there, by Newton
/// safeguarded with bisection, for finite `r₀ > 0`, `σ₀`, `α`, `rhs = √μ Δt`, with a bound orbit
/// (`α > 0`) reduced to `|Δt|` at most half a period.
///
/// `F` is increasing with `F(0) = −rhs`, so the root has the sign of `rhs`. Bound orbits are
/// bracketed by `|ΔE| ≤ π + 2`; unbound ones by a search outward from a starter (the hyperbolic
/// Kepler equation for `α < 0`, else `rhs/r₀`) in steps that grow geometrically from `10⁻⁹` of it.
/// A non-finite `F` (an overflowing Stumpff function) can only occur beyond the root, on the side
/// of `rhs`, and is treated so.
///
/// # Errors
/// [`Error::NotConverged`] if no bracket is found or the iteration does not settle.
pub(crate) fn solve_universal(r0: f64, sigma0: f64, alpha: f64, rhs: f64) -> Result<(f64, f64)> {
    let f = |chi: f64| universal_real(chi, r0, sigma0, alpha, rhs);
    let dir = if rhs >= 0.0 { 1.0 } else { -1.0 };
    // `beyond(x)`: x lies on the far side of the root (F(x)·dir ≥ 0, or F not finite there).
    let beyond = |x: f64| {
        let (fx, _, _) = f(x);
        !fx.is_finite() || fx * dir >= 0.0
    };
    // Bracket [near, far] along dir, with F(near)·dir ≤ 0 ≤ F(far)·dir.
    let (mut lo, mut hi);
    let mut guess = rhs / r0;
    if alpha > 0.0 {
        // Reduced to |Δt| ≤ P/2: |ΔE| ≤ π + 2e < π + 2, χ = ΔE/√α.
        let bound = (PI + 2.0) / alpha.sqrt() * (1.0 + 1e-12);
        (lo, hi) = if dir > 0.0 {
            (0.0, bound)
        } else {
            (-bound, 0.0)
        };
    } else {
        if alpha < 0.0 {
            if let Some(chi) = hyperbolic_starter(r0, sigma0, alpha, rhs) {
                if chi * dir > 0.0 {
                    guess = chi;
                }
            }
        }
        let mut near = 0.0f64;
        let far;
        if guess == 0.0 || !guess.is_finite() {
            guess = dir * f64::MIN_POSITIVE;
        }
        if beyond(guess) {
            far = guess;
            // Tighten the near end towards the guess.
            let mut k = 0;
            let mut step = guess.abs() * 1e-9;
            loop {
                let x = guess - dir * step;
                if x * dir <= 0.0 {
                    break;
                }
                if !beyond(x) {
                    near = x;
                    break;
                }
                step *= 2.0;
                k += 1;
                if k > 64 {
                    break;
                }
            }
        } else {
            near = guess;
            let mut step = (guess.abs() * 1e-9).max(f64::MIN_POSITIVE);
            let mut k = 0;
            loop {
                let x = guess + dir * step;
                if !x.is_finite() {
                    return Err(Error::NotConverged {
                        what: "universal Kepler equation (bracketing)".into(),
                        iterations: k,
                        residual: f(near).0.abs(),
                    });
                }
                if beyond(x) {
                    far = x;
                    break;
                }
                near = x;
                step *= 2.0;
                k += 1;
            }
        }
        (lo, hi) = if dir > 0.0 { (near, far) } else { (far, near) };
    }
    let mut chi = guess.clamp(lo, hi);
    for it in 0..200 {
        let (fx, r, scale) = f(chi);
        if !(fx.is_finite() && r.is_finite()) {
            // Beyond the root (overflow): shrink towards the origin side and bisect.
            if dir > 0.0 {
                hi = chi;
            } else {
                lo = chi;
            }
            let mid = lo + 0.5 * (hi - lo);
            if !(mid > lo && mid < hi) {
                return Err(Error::NotConverged {
                    what: "universal Kepler equation (non-finite residual)".into(),
                    iterations: it,
                    residual: f64::INFINITY,
                });
            }
            chi = mid;
            continue;
        }
        // Converged when the residual is at the rounding level of the terms of F.
        if fx.abs() <= 4.0 * f64::EPSILON * scale {
            return Ok((chi, r));
        }
        if fx < 0.0 {
            lo = lo.max(chi);
        } else {
            hi = hi.min(chi);
        }
        let newton = chi - fx / r;
        let (next, is_newton) = if newton >= lo && newton <= hi {
            (newton, true)
        } else {
            (lo + 0.5 * (hi - lo), false)
        };
        let step = (next - chi).abs();
        // The bracket holds adjacent floating-point numbers.
        if !(is_newton || (next > lo && next < hi)) {
            return Ok((chi, r));
        }
        chi = next;
        // Or when a Newton step no longer moves the iterate (rounding floor).
        if is_newton && step <= 2.0 * f64::EPSILON * chi.abs() {
            let (_, r, _) = f(chi);
            return Ok((chi, r));
        }
    }
    Err(Error::NotConverged {
        what: "universal Kepler equation".into(),
        iterations: 200,
        residual: f(chi).0.abs(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::special::double_double::DoubleDouble as Dd;
    use num_dual::{first_derivative, Dual64};

    const EPS: f64 = f64::EPSILON;

    /// Series oracle summed from the smallest term up in `f64`, `n` terms of `Σ (−z)^k/(2k+j)!`.
    fn series(z: f64, j: u32, n: u32) -> f64 {
        let mut terms = Vec::new();
        let mut t = (1..=j).fold(1.0, |acc, i| acc / i as f64);
        for k in 0..n {
            terms.push(t);
            t *= -z / (((2 * k + j + 1) * (2 * k + j + 2)) as f64);
        }
        terms.iter().rev().sum()
    }

    /// Against the closed forms where they do not cancel (`|z| ≥ 1` and `√z` away from the
    /// zeros `2πk` of `1 − cos√z`, where `c₂` itself is ill-conditioned: `1 − cos√z` and
    /// `√z − sin√z` then lose at most a factor 8 to cancellation), both signs of `z` and both
    /// sides of the switch at 2.5: a few ulps times that factor, `64 ε`.
    #[test]
    fn closed_forms() {
        for z in [
            1.0, 2.0, 2.4999, 2.5, 3.0, 10.0, 30.0, 100.0, 1e4, 1e10, 1e300,
        ] {
            let x = z.sqrt();
            let (c2, c3) = c2_c3(z).unwrap();
            let (w2, w3) = ((1.0 - x.cos()) / z, (x - x.sin()) / (z * x));
            assert!(
                (c2 - w2).abs() <= 64.0 * EPS * w2.abs(),
                "z = {z}: {c2} vs {w2}"
            );
            assert!(
                (c3 - w3).abs() <= 64.0 * EPS * w3.abs(),
                "z = {z}: {c3} vs {w3}"
            );
            let (c2, c3) = c2_c3(-z).unwrap_or((f64::NAN, f64::NAN));
            if z > 5e5 {
                assert!(c2_c3(-z).is_err(), "z = −{z}");
                continue;
            }
            let (w2, w3) = ((x.cosh() - 1.0) / z, (x.sinh() - x) / (z * x));
            assert!((c2 - w2).abs() <= 64.0 * EPS * w2, "z = −{z}: {c2} vs {w2}");
            assert!((c3 - w3).abs() <= 64.0 * EPS * w3, "z = −{z}: {c3} vs {w3}");
        }
    }

    /// Near `z = 0` against the series summed independently (40 terms, smallest first): the
    /// closed forms would cancel there, the values are `c₂ → 1/2`, `c₃ → 1/6`; 8 ulps (a few
    /// roundings on each side).
    #[test]
    fn series_near_zero() {
        assert_eq!(c2_c3(0.0).unwrap(), (0.5, 1.0 / 6.0));
        for z in [
            5e-324, 1e-300, 1e-16, 1e-8, -1e-8, 1e-3, 0.1, -0.1, 1.0, -1.0, 2.4, -2.4,
        ] {
            let (c2, c3) = c2_c3(z).unwrap();
            let (w2, w3) = (series(z, 2, 40), series(z, 3, 40));
            assert!((c2 - w2).abs() <= 8.0 * EPS * w2, "z = {z}: {c2} vs {w2}");
            assert!((c3 - w3).abs() <= 8.0 * EPS * w3, "z = {z}: {c3} vs {w3}");
        }
    }

    /// The identities `1 − z c₂ = cos√z`, `1 − z c₃ = sin√z/√z` (`z > 0`, 8 ulps), and the
    /// derivatives by AD against `dc₂/dz = (1 − z c₃ − 2c₂)/(2z)`, `dc₃/dz = (c₂ − 3c₃)/(2z)`
    /// (Battin 1999 §4.5), to `1e−13` relative (the right-hand sides cancel by up to a factor 40
    /// at `|z| = 0.3`).
    #[test]
    fn identities_and_derivatives() {
        for z in [0.3, 1.7, 6.0, 40.0, -0.3, -1.7, -6.0, -40.0] {
            let (c2, c3) = c2_c3(z).unwrap();
            let (_, d2) = first_derivative(|x: Dual64| c2_c3(x).unwrap().0, z);
            let (_, d3) = first_derivative(|x: Dual64| c2_c3(x).unwrap().1, z);
            let w2 = (1.0 - z * c3 - 2.0 * c2) / (2.0 * z);
            let w3 = (c2 - 3.0 * c3) / (2.0 * z);
            assert!((d2 - w2).abs() <= 1e-13 * w2.abs(), "z = {z}: {d2} vs {w2}");
            assert!((d3 - w3).abs() <= 1e-13 * w3.abs(), "z = {z}: {d3} vs {w3}");
            if z > 0.0 {
                let x = z.sqrt();
                assert!((1.0 - z * c2 - x.cos()).abs() <= 8.0 * EPS);
                assert!((1.0 - z * c3 - x.sin() / x).abs() <= 8.0 * EPS);
            }
        }
    }

    /// Against the series summed in double-double arithmetic with coefficients `1/n!` divided out
    /// in double-double (an independent evaluation, ~10⁻³² relative), on 20 000 arguments
    /// spread over the series range `|z| < 2.5`: each value within ε relative (one final rounding
    /// plus the roundings of the Horner steps, damped by the small terms), and the mean error below
    /// 0.02 ε in magnitude — no bias, which would otherwise accumulate linearly over the many
    /// steps of a composed flow (Brouwer's law needs the rounding errors to be unbiased).
    #[test]
    fn series_is_accurate_and_unbiased() {
        let mut inv_fact = vec![Dd::from(1.0)];
        for n in 1..40 {
            let last = inv_fact[n - 1];
            inv_fact.push(last / n as f64);
        }
        let oracle = |z: f64, j: usize| {
            let mut acc = Dd::from(0.0);
            for k in (0..18).rev() {
                acc = acc * -z + inv_fact[2 * k + j];
            }
            acc
        };
        let (mut mean2, mut mean3, mut worst) = (0.0, 0.0, 0.0f64);
        let n = 20_000;
        for i in 0..n {
            let z = -2.5 + 5.0 * (i as f64 + 0.5) / n as f64;
            let (c2, c3) = c2_c3(z).unwrap();
            let (w2, w3) = (oracle(z, 2), oracle(z, 3));
            let e2 = ((c2 - w2.hi) - w2.lo) / (w2.hi * EPS);
            let e3 = ((c3 - w3.hi) - w3.lo) / (w3.hi * EPS);
            worst = worst.max(e2.abs()).max(e3.abs());
            mean2 += e2 / n as f64;
            mean3 += e3 / n as f64;
        }
        eprintln!(
            "Stumpff series: worst {worst:.3} ε, mean error c₂ {mean2:+.4} ε, c₃ {mean3:+.4} ε"
        );
        assert!(worst <= 1.0, "worst {worst} ε");
        assert!(
            mean2.abs() <= 0.02 && mean3.abs() <= 0.02,
            "bias {mean2} {mean3}"
        );
    }

    #[test]
    fn hostile_arguments() {
        for z in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(matches!(c2_c3(z), Err(Error::NonFinite { .. })));
        }
        assert!(matches!(c2_c3(f64::MIN), Err(Error::OutOfDomain { .. })));
        // c₂ = (1 − cos√z)/z is representable; c₃ ≈ 1/√z³ ≈ 4e−463 rounds to 0.
        let (c2, c3) = c2_c3(f64::MAX).unwrap();
        let x = f64::MAX.sqrt();
        assert!((c2 - (1.0 - x.cos()) / f64::MAX).abs() <= 8.0 * EPS * c2);
        assert_eq!(c3, 0.0);
    }

    /// The universal Kepler equation on a circle (`r₀ = 1`, `σ₀ = 0`, `α = 1`, `μ = 1`): the root
    /// is `χ = Δt` (the eccentric anomaly increment) with `r = 1`; a hyperbola (`α = −1`, from
    /// periapsis, `e = 2`) against `χ = H` from `2 sinh H − H = Δt`.
    #[test]
    fn universal_kepler_equation_roots() {
        for dt in [1e-9, 0.3, -2.0, 3.1] {
            let (chi, r) = solve_universal(1.0, 0.0, 1.0, dt).unwrap();
            assert!((chi - dt).abs() <= 4.0 * EPS * dt.abs(), "{dt}: {chi}");
            assert!((r - 1.0).abs() <= 4.0 * EPS);
        }
        for dt in [0.1, 5.0, -40.0, 1e6] {
            let (chi, _) = solve_universal(1.0, 0.0, -1.0, dt).unwrap();
            let h = solve_kepler_hyperbolic(dt, 2.0).unwrap();
            assert!(
                (chi - h).abs() <= 16.0 * EPS * h.abs(),
                "{dt}: {chi} vs {h}"
            );
        }
    }
}

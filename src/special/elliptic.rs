//! Elliptic integrals and Jacobi elliptic functions of real argument, accurate up to the
//! modulus `k = 1`.
//!
//! * [`agm`]: the arithmetic–geometric mean `M(a, b)` (Abramowitz & Stegun 17.6; DLMF 19.8.1);
//! * [`complete_k_from_complementary`]: the complete integral of the first kind
//!   `K(k) = ∫₀^{π/2} dθ/√(1 − k² sin²θ) = π/(2 M(1, k'))` (DLMF 19.2.8, 19.8.5);
//! * the incomplete integral `F(φ | k) = ∫₀^φ dθ/√(1 − k² sin²θ)` in Carlson's symmetric form
//!   `F = sin φ · R_F(cos²φ, 1 − k² sin²φ, 1)` (DLMF 19.2.4, 19.25.5), `R_F` from the `ellip`
//!   crate (Carlson's duplication algorithm, DLMF 19.36(i));
//! * [`jacobi_sn_cn_dn`]: `sn(u, k) = sin am(u, k)`, `cn = cos am`, `dn = √(1 − k² sn²)`, with
//!   the amplitude `am` the inverse of `F(·|k)` (DLMF 22.2, 22.16.1), by the descending Landen
//!   transformation (Abramowitz & Stegun 16.4; DLMF 22.20(ii)).
//!
//! The modulus enters through its complement `k' = √(1 − k²)`, which near `k = 1` cannot be
//! recovered from `k`: the callers (the pendulum near its separatrix) form `k'` without
//! cancellation, and the AGM takes it directly, so `K(k) ≈ ln(4/k')` keeps full relative accuracy
//! for `k'` down to the smallest positive double.
//!
//! The `ellip` crate's `ellipk(m)` takes the parameter `m = k² = 1 − k'²`, which loses the
//! relative accuracy of `k'` (measured against 60-digit references: 10⁶ ulp at `k' = 10⁻⁴`, no
//! correct digit at `k' = 10⁻¹⁰`); its Bulirsch `cel1(k')` takes the complement and agrees with
//! [`complete_k_from_complementary`] to the ulp down to `k' = 10⁻⁵⁰`, but stops with "failed to
//! converge" from `k' = 10⁻⁶⁰` on (ten AGM steps at most). `K` is therefore computed here by the
//! AGM, and `cel1` serves as an independent check in the tests.

use crate::error::{finite, non_negative, Error, Result};
use std::f64::consts::FRAC_PI_2;

/// Iteration cap for the AGM and the Landen sequence. Both converge quadratically once the two
/// means agree to a few digits; reaching that takes about `log₂ ln(a/b)` steps, so fewer than 20
/// steps suffice for any pair of positive doubles and the cap is never reached in practice.
const MAX_AGM_STEPS: usize = 64;

/// Tolerance on `k² + k'² − 1` accepted by [`jacobi_sn_cn_dn`]: a `k'` obtained as `√(1 − k²)`,
/// or the pair `(sin x, cos x)`, satisfies the identity to a few rounding errors.
const MODULUS_PAIR_TOL: f64 = 16.0 * f64::EPSILON;

/// Arithmetic–geometric mean `M(a, b)`.
///
/// `a₀ = a`, `b₀ = b`, `a_{j+1} = (a_j + b_j)/2`, `b_{j+1} = √(a_j b_j)`; both sequences converge
/// quadratically to the common limit `M(a, b)` (Abramowitz & Stegun 17.6.1–17.6.2, DLMF 19.8.1).
/// `M(a, 0) = M(0, b) = 0`.
///
/// # Errors
/// [`Error::NonFinite`] if `a` or `b` is NaN or infinite, [`Error::OutOfDomain`] if either is
/// negative.
pub fn agm(a: f64, b: f64) -> Result<f64> {
    let a = non_negative("agm argument a", a)?;
    let b = non_negative("agm argument b", b)?;
    agm_unchecked(a, b)
}

/// `√(a b)` without overflow or underflow of the product.
fn geometric_mean(a: f64, b: f64) -> f64 {
    let prod = a * b;
    if prod.is_normal() {
        prod.sqrt()
    } else {
        a.sqrt() * b.sqrt()
    }
}

/// AGM of two finite non-negative numbers.
pub(crate) fn agm_unchecked(mut a: f64, mut b: f64) -> Result<f64> {
    if a == 0.0 || b == 0.0 {
        return Ok(0.0);
    }
    for _ in 0..MAX_AGM_STEPS {
        // Once |a − b| is a few ulps the remaining correction, (a − b)²/(8a), is below rounding.
        if (a - b).abs() <= 4.0 * f64::EPSILON * a.max(b) {
            return Ok(0.5 * a + 0.5 * b);
        }
        let next_a = 0.5 * a + 0.5 * b;
        b = geometric_mean(a, b);
        a = next_a;
    }
    Err(Error::NotConverged {
        what: "arithmetic-geometric mean".into(),
        iterations: MAX_AGM_STEPS,
        residual: (a - b).abs(),
    })
}

/// Complete elliptic integral of the first kind from the complementary modulus.
///
/// `K(k) = π / (2 M(1, k'))`, `k' = √(1 − k²)` (Abramowitz & Stegun 17.6, DLMF 19.8.5). The AGM
/// takes `k'` itself, so the result keeps full relative accuracy as `k' → 0`, where
/// `K = ln(4/k') + (k'²/4)(ln(4/k') − 1) + O(k'⁴ ln k')` (DLMF 19.12.1).
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞; [`Error::Separatrix`] for `k' = 0` (`K` diverges);
/// [`Error::OutOfDomain`] for `k' < 0` or `k' > 1`.
pub fn complete_k_from_complementary(kc: f64) -> Result<f64> {
    let kc = finite("complementary modulus k'", kc)?;
    if kc == 0.0 {
        return Err(Error::Separatrix {
            what: "complete elliptic integral K(k)".into(),
            distance: 0.0,
            hint: "K diverges like ln(4/k') as k' -> 0; pass k' > 0".into(),
        });
    }
    if !(kc > 0.0 && kc <= 1.0) {
        return Err(Error::out_of_domain(
            "complementary modulus k'",
            kc,
            "(0, 1]",
        ));
    }
    complete_k_unchecked(kc)
}

/// `K` for `k' ∈ (0, 1]`.
pub(crate) fn complete_k_unchecked(kc: f64) -> Result<f64> {
    Ok(FRAC_PI_2 / agm_unchecked(1.0, kc)?)
}

/// Amplitude and the three Jacobi functions at one argument.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Jacobi {
    /// Continuous amplitude `am(u)`, so that `sn = sin am`, `cn = cos am` (DLMF 22.16.1);
    /// `am(u + 2K) = am(u) + π` (DLMF 22.16.2).
    pub(crate) am: f64,
    /// `sn(u, k)`.
    pub(crate) sn: f64,
    /// `cn(u, k)`.
    pub(crate) cn: f64,
    /// `dn(u, k)`.
    pub(crate) dn: f64,
}

/// Jacobi elliptic functions `sn(u, k)`, `cn(u, k)`, `dn(u, k)`.
///
/// The modulus is passed twice, as `k` and as its complement `k' = √(1 − k²)`; the caller supplies
/// both accurately (`k² + k'² = 1` to rounding), which is what keeps the functions accurate as
/// `k → 1`, where `k'` cannot be recovered from `k`.
///
/// Method: descending Landen transformation / AGM scale (Abramowitz & Stegun 16.4.3, DLMF 22.20(ii)):
/// `a₀ = 1`, `b₀ = k'`, `c₀ = k`, `a_{j+1} = (a_j + b_j)/2`, `b_{j+1} = √(a_j b_j)`,
/// `c_{j+1} = (a_j − b_j)/2 = c_j² / (4 a_{j+1})` until `c_N` is below rounding; then
/// `φ_N = 2^N a_N u` and `φ_{j−1} = ½ [φ_j + arcsin((c_j/a_j) sin φ_j)]`, with `am u = φ₀`,
/// `sn = sin φ₀`, `cn = cos φ₀`. The arcsine is evaluated as
/// `atan2(c_j sin φ_j, √(a_j² cos² φ_j + b_j² sin² φ_j))` (using `a_j² − c_j² = b_j²`), which stays
/// well conditioned when `c_j/a_j → 1`, and `dn = √(cn² + k'² sn²)` (= `√(1 − k² sn²)`) has no
/// cancellation.
///
/// Limits: `k = 0` gives `(sin u, cos u, 1)`; `k' = 0` gives `(tanh u, sech u, sech u)`
/// (DLMF §22.5(ii)).
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ arguments; [`Error::OutOfDomain`] if `k` or `k'` is outside
/// `[0, 1]`, or if `|u|` is so large that `2^N a_N u` overflows; [`Error::InvalidInput`] if
/// `|k² + k'² − 1|` exceeds `16 ε`.
pub fn jacobi_sn_cn_dn(u: f64, k: f64, kc: f64) -> Result<(f64, f64, f64)> {
    let u = finite("u", u)?;
    let k = finite("modulus k", k)?;
    let kc = finite("complementary modulus k'", kc)?;
    if !(0.0..=1.0).contains(&k) {
        return Err(Error::out_of_domain("modulus k", k, "[0, 1]"));
    }
    if !(0.0..=1.0).contains(&kc) {
        return Err(Error::out_of_domain(
            "complementary modulus k'",
            kc,
            "[0, 1]",
        ));
    }
    let defect = k.mul_add(k, kc * kc) - 1.0;
    if defect.abs() > MODULUS_PAIR_TOL {
        return Err(Error::invalid(
            "modulus pair (k, k')",
            format!("k² + k'² − 1 = {defect:e}; expected 0 to rounding"),
        ));
    }
    let j = jacobi_unchecked(u, k, kc)?;
    Ok((j.sn, j.cn, j.dn))
}

/// Landen/AGM evaluation; inputs finite, `k, k' ∈ [0, 1]`, `k² + k'² ≈ 1`.
pub(crate) fn jacobi_unchecked(u: f64, k: f64, kc: f64) -> Result<Jacobi> {
    if kc == 0.0 {
        let sech = 1.0 / u.cosh();
        return Ok(Jacobi {
            am: u.sinh().atan(),
            sn: u.tanh(),
            cn: sech,
            dn: sech,
        });
    }
    if k == 0.0 {
        let (sn, cn) = u.sin_cos();
        return Ok(Jacobi {
            am: u,
            sn,
            cn,
            dn: 1.0,
        });
    }
    let mut a = [0.0_f64; MAX_AGM_STEPS + 1];
    let mut b = [0.0_f64; MAX_AGM_STEPS + 1];
    let mut c = [0.0_f64; MAX_AGM_STEPS + 1];
    a[0] = 1.0;
    b[0] = kc;
    c[0] = k;
    let mut levels = 0;
    // Stopping once c_N ≤ ε a_N leaves a neglected correction of order (c_N/a_N)², far below
    // rounding.
    while c[levels] > f64::EPSILON * a[levels] {
        if levels == MAX_AGM_STEPS {
            return Err(Error::NotConverged {
                what: "Landen sequence for Jacobi functions".into(),
                iterations: MAX_AGM_STEPS,
                residual: c[levels] / a[levels],
            });
        }
        let next = levels + 1;
        a[next] = 0.5 * a[levels] + 0.5 * b[levels];
        b[next] = geometric_mean(a[levels], b[levels]);
        c[next] = c[levels] * c[levels] / (4.0 * a[next]);
        levels = next;
    }
    // `levels` ≤ 64: the power of two is exact.
    let mut phi = 2.0_f64.powi(levels as i32) * a[levels] * u;
    if !phi.is_finite() {
        return Err(Error::out_of_domain(
            "u",
            u,
            "|u| small enough that the Landen angle 2^N a_N u is finite",
        ));
    }
    for j in (1..=levels).rev() {
        let (s, co) = phi.sin_cos();
        let psi = (c[j] * s).atan2((a[j] * co).hypot(b[j] * s));
        phi = 0.5 * (phi + psi);
    }
    let (sn, cn) = phi.sin_cos();
    Ok(Jacobi {
        am: phi,
        sn,
        cn,
        dn: cn.hypot(kc * sn),
    })
}

/// `F(φ | k)` for `φ ∈ [−π/2, π/2]` given `sin φ`, `cos² φ ≥ 0` and `Δ² = 1 − k² sin² φ`, via
/// Carlson's form `F = sin φ · R_F(cos² φ, Δ², 1)` (DLMF 19.25.5).
pub(crate) fn incomplete_f(sin_phi: f64, cos2: f64, delta2: f64) -> Result<f64> {
    let rf = ellip::elliprf(cos2, delta2, 1.0)
        .map_err(|msg| Error::invalid("Carlson R_F arguments", msg))?;
    Ok(sin_phi * rf)
}

/// `Π(n; φ | k) = ∫₀^φ dθ / ((1 − n sin²θ) √(1 − k² sin²θ))` for `φ ∈ [−π/2, π/2]` and `n < 1`,
/// given `sin φ`, `cos² φ`, `Δ² = 1 − k² sin² φ` and `1 − n`, via Carlson's form (DLMF 19.25.14)
/// `Π = sin φ · R_F(cos²φ, Δ², 1) + (n/3) sin³φ · R_J(cos²φ, Δ², 1, 1 − n sin²φ)`, with `1 − n sin²φ = cos²φ + (1 − n) sin²φ` formed without cancellation; `R_F`, `R_J` from the
/// `ellip` crate (Carlson's duplication algorithm, DLMF 19.36(i)).
pub(crate) fn incomplete_pi(
    n: f64,
    one_minus_n: f64,
    sin_phi: f64,
    cos2: f64,
    delta2: f64,
) -> Result<f64> {
    let f = incomplete_f(sin_phi, cos2, delta2)?;
    let s2 = sin_phi * sin_phi;
    if n == 0.0 || s2 == 0.0 {
        return Ok(f);
    }
    let rj = ellip::elliprj(cos2, delta2, 1.0, cos2 + one_minus_n * s2)
        .map_err(|msg| Error::invalid("Carlson R_J arguments", msg))?;
    finite(
        "incomplete elliptic integral of the third kind Π(n; φ | k)",
        f + n / 3.0 * s2 * sin_phi * rj,
    )
}

/// The complete integral `Π(n | k) = K(k) + (n/3) R_J(0, k'², 1, 1 − n)` for `n < 1` (DLMF
/// 19.25.2), given `K(k)`, `k'` and `1 − n`.
pub(crate) fn complete_pi(n: f64, one_minus_n: f64, k_complete: f64, kc: f64) -> Result<f64> {
    if n == 0.0 {
        return Ok(k_complete);
    }
    let rj = ellip::elliprj(0.0, kc * kc, 1.0, one_minus_n)
        .map_err(|msg| Error::invalid("Carlson R_J arguments", msg))?;
    finite(
        "complete elliptic integral of the third kind Π(n | k)",
        k_complete + n / 3.0 * rj,
    )
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngSeed};
    use std::f64::consts::PI;

    const EPS: f64 = f64::EPSILON;

    /// `|x − reference| / |reference|`.
    pub(crate) fn rel(x: f64, reference: f64) -> f64 {
        ((x - reference) / reference).abs()
    }

    /// 1000 cases from a fixed seed, no persistence: reproducible property tests.
    pub(crate) fn proptest_config() -> Config {
        Config {
            cases: 1000,
            rng_seed: RngSeed::Fixed(0x5EED_0F0D_D5E5),
            failure_persistence: None,
            ..Config::default()
        }
    }

    // ---------------------------------------------------------------- AGM and K

    #[test]
    fn agm_reference_values() {
        // mpmath references quoted to 17 digits: M(1, √2) (the reciprocal of Gauss's constant, with
        // √2 as a double) and M(24, 6). A converged AGM is accurate to a few rounding errors.
        let g = agm(1.0, std::f64::consts::SQRT_2).unwrap();
        assert!(rel(g, 1.198_140_234_735_592_3) <= 4.0 * EPS, "{g}");
        let m = agm(24.0, 6.0).unwrap();
        assert!(rel(m, 13.458_171_481_725_616) <= 4.0 * EPS, "{m}");
        assert_eq!(agm(0.0, 3.0).unwrap(), 0.0);
        assert_eq!(agm(2.5, 2.5).unwrap(), 2.5);
        // Extreme ratio: M(a, b) = a π / (2 K) with K = ln(4a/b) + O((b/a)² ln) (DLMF 19.8.5,
        // 19.12.1); ln(4·10⁶⁰⁰) = ln 4 + 600 ln 10 is evaluated to a few ε.
        let big = agm(1e300, 1e-300).unwrap();
        let k_big = 4.0_f64.ln() + 600.0 * 10.0_f64.ln();
        assert!(rel(big, 1e300 * FRAC_PI_2 / k_big) <= 1e-14, "{big:e}");
        assert!(agm(f64::MAX, f64::MAX).unwrap().is_finite());
        assert!(agm(f64::MAX, 1e-300).unwrap().is_finite());
    }

    #[test]
    fn complete_k_reference_values() {
        // mpmath references quoted to 17 digits (K = π/(2 M(1, k'))).
        let k_half = complete_k_from_complementary(std::f64::consts::FRAC_1_SQRT_2).unwrap();
        assert!(rel(k_half, 1.854_074_677_301_371_9) <= 4.0 * EPS);
        assert!(rel(complete_k_from_complementary(1.0).unwrap(), FRAC_PI_2) <= EPS);
        let cases = [
            (1e-10, 24.412_145_291_060_348),
            (1e-16, 38.227_655_849_024_62),
            (1e-300, 692.161_822_259_333_6),
        ];
        for (kc, k_ref) in cases {
            let k = complete_k_from_complementary(kc).unwrap();
            assert!(rel(k, k_ref) <= 4.0 * EPS, "k' = {kc}: {k} vs {k_ref}");
            // K − ln(4/k') = (k'²/4)(ln(4/k') − 1) + …, below rounding for these k'.
            assert!(rel(k, (4.0 / kc).ln()) <= 4.0 * EPS);
        }
        assert!(matches!(
            complete_k_from_complementary(0.0),
            Err(Error::Separatrix { .. })
        ));
        assert!(matches!(
            complete_k_from_complementary(1.5),
            Err(Error::OutOfDomain { .. })
        ));
        assert!(matches!(
            complete_k_from_complementary(-0.5),
            Err(Error::OutOfDomain { .. })
        ));
    }

    // ---------------------------------------------------------------- Jacobi functions

    /// Bound for the Landen evaluation: the argument alone carries ε|u| and each of the
    /// ≈ log₂ ln(4/k') + 4 backward steps adds about one rounding error of the angle, so
    /// 16 ε max(1, |u|) holds for every k' ≥ 1e−300.
    fn jacobi_tol(u: f64) -> f64 {
        16.0 * EPS * u.abs().max(1.0)
    }

    #[test]
    fn jacobi_reference_values() {
        // (u, k, k', sn, cn, dn): mpmath values at 60 digits, quoted to 17 significant digits,
        // for the parameter m = k² of the double k (first two rows) or m = 1 − k'² of the double k'
        // (near k = 1).
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let rows = [
            (
                0.5,
                s,
                s,
                0.470_750_473_655_657_3,
                0.882_266_394_890_440_3,
                0.942_972_425_777_385_7,
            ),
            (
                1.5,
                0.8,
                0.6,
                0.953_883_652_658_688_8,
                0.300_176_576_685_320_1,
                0.646_272_253_312_743_8,
            ),
            (
                10.0,
                1.0,
                1e-10,
                0.999_999_995_877_692_7,
                9.079_985_933_778_971e-5,
                9.079_985_933_784_478e-5,
            ),
            (
                20.0,
                1.0,
                1e-10,
                0.999_999_999_999_999_991_51,
                4.121_700_788_382_853e-9,
                4.122_913_701_371_377_5e-9,
            ),
            (
                30.0,
                1.0,
                1e-16,
                1.0,
                1.871_524_460_187_102_6e-13,
                1.871_524_727_348_967e-13,
            ),
            (
                -3.0,
                1.0,
                1e-16,
                -0.995_054_753_686_730_5,
                0.099_327_927_419_433_2,
                0.099_327_927_419_433_2,
            ),
        ];
        let mut worst = 0.0_f64;
        for (u, k, kc, sn_ref, cn_ref, dn_ref) in rows {
            let (sn, cn, dn) = jacobi_sn_cn_dn(u, k, kc).unwrap();
            let err = (sn - sn_ref)
                .abs()
                .max((cn - cn_ref).abs())
                .max((dn - dn_ref).abs());
            worst = worst.max(err / (EPS * u.abs().max(1.0)));
            assert!(err <= jacobi_tol(u), "u = {u}, k' = {kc}: error {err:e}");
        }
        eprintln!("Jacobi reference values: max error {worst:.2} ε·max(1,|u|)");
    }

    #[test]
    fn jacobi_identities_on_grid() {
        let mut worst = 0.0_f64;
        for e in -16..=0 {
            let kc = 10f64.powi(e);
            let k = ((1.0 - kc) * (1.0 + kc)).sqrt();
            for i in -40..=40 {
                let u = 1.37 * f64::from(i);
                let (sn, cn, dn) = jacobi_sn_cn_dn(u, k, kc).unwrap();
                let d1 = (sn.mul_add(sn, cn * cn) - 1.0).abs();
                let d2 = (dn.mul_add(dn, (k * sn) * (k * sn)) - 1.0).abs();
                worst = worst.max(d1).max(d2);
                // Each identity is a sum of two squares of correctly related quantities: a few
                // rounding errors.
                assert!(
                    d1 <= 1e-15 && d2 <= 1e-15,
                    "u = {u}, k' = {kc}: {d1:e} {d2:e}"
                );
            }
        }
        eprintln!("Jacobi identities max defect {worst:e}");
    }

    #[test]
    fn jacobi_at_quarter_period() {
        for kc in [0.9_f64, 0.5, 0.1, 1e-4, 1e-8, 1e-12, 1e-16] {
            let k = ((1.0 - kc) * (1.0 + kc)).sqrt();
            let big_k = complete_k_from_complementary(kc).unwrap();
            let (sn, cn, dn) = jacobi_sn_cn_dn(big_k, k, kc).unwrap();
            // sn(K) = 1, cn(K) = 0, dn(K) = k' (DLMF Table 22.5.1). K itself is rounded by ε K, which
            // moves cn by ≤ ε K dn(K) ≤ ε K; the scheme adds the `jacobi_tol` error.
            let tol = jacobi_tol(big_k);
            assert!((sn - 1.0).abs() <= tol, "k' = {kc}: sn(K) = {sn}");
            assert!(cn.abs() <= tol, "k' = {kc}: cn(K) = {cn:e}");
            assert!((dn - kc).abs() <= tol, "k' = {kc}: dn(K) = {dn:e}");
        }
    }

    #[test]
    fn jacobi_limits() {
        for u in [-5.0, -0.3, 0.0, 0.7, 4.0, 30.0, 800.0] {
            let (sn, cn, dn) = jacobi_sn_cn_dn(u, 1.0, 0.0).unwrap();
            assert_eq!(sn, u.tanh());
            assert_eq!(cn, 1.0 / u.cosh());
            assert_eq!(dn, 1.0 / u.cosh());
            let (sn, cn, dn) = jacobi_sn_cn_dn(u, 0.0, 1.0).unwrap();
            assert_eq!((sn, cn, dn), (u.sin(), u.cos(), 1.0));
            // Continuity into k' = 0: sn(u, k) − tanh u = O(k'² cosh² u) (DLMF §22.10(ii)).
            let kc = 1e-200;
            let (sn, cn, dn) = jacobi_sn_cn_dn(u, 1.0, kc).unwrap();
            let tol = jacobi_tol(u);
            assert!((sn - u.tanh()).abs() <= tol);
            assert!((cn - 1.0 / u.cosh()).abs() <= tol);
            assert!((dn - 1.0 / u.cosh()).abs() <= tol);
        }
        assert!(matches!(
            jacobi_sn_cn_dn(1.0, 0.8, 0.8),
            Err(Error::InvalidInput { .. })
        ));
        assert!(matches!(
            jacobi_sn_cn_dn(1.0, 1.2, 0.0),
            Err(Error::OutOfDomain { .. })
        ));
        assert!(matches!(
            jacobi_sn_cn_dn(1.0, 0.6, -0.8),
            Err(Error::OutOfDomain { .. })
        ));
        assert!(matches!(
            jacobi_sn_cn_dn(1e308, 0.6, 0.8),
            Err(Error::OutOfDomain { .. })
        ));
    }

    /// `Π(n; φ | k)` in Carlson's form against Bulirsch's algorithm of the `ellip` crate
    /// (`ellippiinc_bulirsch`, an independent implementation in Legendre's variables), and the
    /// complete integral against `Π(n; π/2 | k)`, over `n ∈ (−30, 0.9)`, `k ∈ [0, 0.99]`,
    /// `φ ∈ [−π/2, π/2]`: agreement to `10⁻¹³` relative (a few ulp of each, times the
    /// condition number `≤ 1/(1 − n)` ≈ 10 of the integrand's denominator).
    #[test]
    fn incomplete_pi_agrees_with_bulirsch() {
        let mut worst = 0.0_f64;
        for &n in &[-30.0, -3.0, -0.5, 0.0, 0.3, 0.9] {
            for &k in &[0.0f64, 0.3, 0.7, 0.99] {
                let kc = ((1.0 - k) * (1.0 + k)).sqrt();
                for j in -8i32..=8 {
                    let phi = PI / 2.0 * f64::from(j) / 8.0;
                    let (s, c) = phi.sin_cos();
                    let c2 = if j.abs() == 8 { 0.0 } else { c * c };
                    let got = incomplete_pi(n, 1.0 - n, s, c2, 1.0 - k * k * s * s).unwrap();
                    let want = ellip::ellippiinc_bulirsch(phi, n, k * k).unwrap();
                    worst = worst.max(rel(got, want));
                }
                let kk = complete_k_unchecked(kc).unwrap();
                let got = complete_pi(n, 1.0 - n, kk, kc).unwrap();
                let want = ellip::ellippiinc_bulirsch(PI / 2.0, n, k * k).unwrap();
                worst = worst.max(rel(got, want));
            }
        }
        assert!(worst < 1e-13, "worst relative difference {worst:e}");
    }

    /// `K(k)` against Bulirsch's `cel1(k')` of the `ellip` crate (an independent implementation),
    /// where that converges (`k' ≥ 10⁻⁵⁰`).
    #[test]
    fn complete_k_agrees_with_bulirsch_cel1() {
        let mut worst = 0.0_f64;
        for e in 0..=200 {
            let kc = 10f64.powf(-0.25 * f64::from(e));
            let k = complete_k_from_complementary(kc).unwrap();
            let reference = ellip::cel1(kc).unwrap();
            worst = worst.max(rel(k, reference) / EPS);
            assert!(
                rel(k, reference) <= 4.0 * EPS,
                "k' = {kc:e}: {k} vs {reference}"
            );
        }
        eprintln!("K against cel1: max {worst:.2} ε");
    }

    /// `F(φ | k)` at `φ = π/2` is `K(k)` (DLMF 19.2.8), and `F` is odd in `φ` and agrees with the
    /// `ellip` crate's Legendre form `ellipf(φ, m)` away from `k = 1`.
    #[test]
    fn incomplete_f_reaches_k_and_matches_legendre_form() {
        for kc in [1.0, 0.8, 0.3, 1e-3, 1e-8, 1e-100] {
            let k2 = (1.0 - kc) * (1.0 + kc);
            let f = incomplete_f(1.0, 0.0, kc * kc).unwrap();
            let big_k = complete_k_from_complementary(kc).unwrap();
            assert!(
                rel(f, big_k) <= 4.0 * EPS,
                "k' = {kc:e}: F(π/2) = {f} vs K = {big_k}"
            );
            for phi in [0.1, 0.7, 1.3] {
                let (s, c) = f64::sin_cos(phi);
                let f = incomplete_f(s, c * c, 1.0 - k2 * s * s).unwrap();
                let g = incomplete_f(-s, c * c, 1.0 - k2 * s * s).unwrap();
                assert_eq!(f, -g);
                if kc >= 1e-3 {
                    let legendre = ellip::ellipf(phi, k2).unwrap();
                    assert!(
                        rel(f, legendre) <= 1e-14,
                        "k' = {kc}, φ = {phi}: {f} vs {legendre}"
                    );
                }
            }
        }
    }

    /// The amplitude is continuous and quasi-periodic, `am(u + 2K) = am(u) + π` (DLMF 22.16.2),
    /// and inverts `F`: `F(am u | k) = u` for `|am u| ≤ π/2` (DLMF 22.16.1).
    #[test]
    fn amplitude_is_quasi_periodic_and_inverts_f() {
        for kc in [0.9_f64, 0.5, 0.1, 1e-4, 1e-10] {
            let k = ((1.0 - kc) * (1.0 + kc)).sqrt();
            let two_k = 2.0 * complete_k_from_complementary(kc).unwrap();
            for u in [-2.3, -0.4, 0.0, 0.9, 1.7] {
                let j = jacobi_unchecked(u, k, kc).unwrap();
                let shifted = jacobi_unchecked(u + two_k, k, kc).unwrap();
                // 2K carries ε·2K, which moves am by ≤ ε·2K·dn ≤ ε·2K.
                let tol = jacobi_tol(u + two_k) + 2.0 * EPS * two_k;
                assert!(
                    (shifted.am - (j.am + PI)).abs() <= tol,
                    "k' = {kc}, u = {u}: am(u + 2K) = {}, am(u) + π = {}",
                    shifted.am,
                    j.am + PI
                );
                assert_eq!((j.sn, j.cn), j.am.sin_cos());
                if j.am.abs() <= FRAC_PI_2 {
                    let f = incomplete_f(j.sn, j.cn * j.cn, j.dn * j.dn).unwrap();
                    assert!(
                        (f - u).abs() <= 4.0 * jacobi_tol(u),
                        "k' = {kc}: F(am {u}) = {f}"
                    );
                }
            }
        }
    }

    #[test]
    fn bad_input_is_rejected() {
        for x in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            assert!(matches!(agm(x, 1.0), Err(Error::NonFinite { .. })));
            assert!(matches!(agm(1.0, x), Err(Error::NonFinite { .. })));
            assert!(matches!(
                complete_k_from_complementary(x),
                Err(Error::NonFinite { .. })
            ));
            for args in [(x, 0.5, 0.5), (0.5, x, 0.5), (0.5, 0.5, x)] {
                assert!(matches!(
                    jacobi_sn_cn_dn(args.0, args.1, args.2),
                    Err(Error::NonFinite { .. })
                ));
            }
        }
        assert!(matches!(agm(-1.0, 1.0), Err(Error::OutOfDomain { .. })));
    }

    /// Random modulus pair with k' log-uniform in [1e−16, 1].
    fn modulus_pair() -> impl Strategy<Value = (f64, f64)> {
        (-16.0..0.0_f64).prop_map(|e| {
            let kc = 10f64.powf(e);
            (((1.0 - kc) * (1.0 + kc)).sqrt(), kc)
        })
    }

    proptest! {
        #![proptest_config(proptest_config())]

        #[test]
        fn prop_jacobi_identities(u in -100.0..100.0_f64, (k, kc) in modulus_pair()) {
            let (sn, cn, dn) = jacobi_sn_cn_dn(u, k, kc).unwrap();
            prop_assert!((sn.mul_add(sn, cn * cn) - 1.0).abs() <= 1e-15);
            prop_assert!((dn.mul_add(dn, (k * sn) * (k * sn)) - 1.0).abs() <= 1e-15);
        }
    }
}

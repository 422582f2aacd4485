//! Frequency analysis (`hamilton_jacobi::frequency_analysis`) against signals with known lines.
//!
//! Oracles:
//! * a pure line `a e^{iνt}`: frequency and amplitude to rounding;
//! * two lines: the first-order pull of the second line on the maximum, in closed form from the
//!   Hann window's transform `Ŵ(u) = π² sin u / (u (π² − u²))` (module documentation):
//!   `δν = −Re(b̄₁ b₂) Ŵ'(u₂) / (c |b₁|² T)`, `b_j = a_j e^{iν_j t_c}`, `u₂ = (ν₂ − ν₁) T/2`,
//!   `c = 1/6 − 1/π²` — its size falls like `T⁻⁴`;
//! * a synthetic torus with the lines of the Hénon–Heiles signals (`ν_f + k ν_s` and `k ν_s`):
//!   the error within the a-priori bound `Σ_j |a_j/a₁| B(u_j)/(c T)`, `B` the envelope of `|Ŵ'|`.

use hamilton_jacobi::frequency_analysis::{leading_line, Line};
use hamilton_jacobi::nalgebra::Complex;
use std::f64::consts::PI;

const EPS: f64 = f64::EPSILON;
/// `Ŵ(u) = 1 − c u² + …`.
const C: f64 = 1.0 / 6.0 - 1.0 / (PI * PI);

/// `Ŵ'(u)`.
fn w_prime(u: f64) -> f64 {
    let p2 = PI * PI;
    let g = p2 / (u * (p2 - u * u));
    let dg = -p2 * (p2 - 3.0 * u * u) / (u * u * (p2 - u * u).powi(2));
    u.cos() * g + u.sin() * dg
}

/// The envelope `|g| + |g'|` of `|Ŵ'(u)|` for `|u| > π` (`Ŵ = g sin u`).
fn w_prime_envelope(u: f64) -> f64 {
    let (p2, u) = (PI * PI, u.abs());
    p2 / (u * (u * u - p2)) + p2 * (3.0 * u * u - p2) / (u * u * (u * u - p2).powi(2))
}

/// Samples of `Σ a_j e^{iν_j t}` at `t_k = t0 + k h`, `k = 0 … n − 1`.
fn signal(lines: &[(f64, Complex<f64>)], t0: f64, h: f64, n: usize) -> Vec<Complex<f64>> {
    (0..n)
        .map(|k| {
            let t = t0 + k as f64 * h;
            lines
                .iter()
                .map(|&(nu, a)| a * Complex::new(0.0, nu * t).exp())
                .sum()
        })
        .collect()
}

/// Rounding bound of the frequency: `4ε|ν|` for the representation plus
/// `ε √N Σ|a_j| / (c |a₁| T)` from the rounding of `d|φ|²/dν` (of size `ε √N |φ||φ'|`,
/// `|φ'| ≤ (T/2) Σ|a_j|`) over its slope `c |a₁|² T²` at the root.
fn rounding(nu: f64, n: usize, amp_sum: f64, a1: f64, span: f64) -> f64 {
    4.0 * EPS * nu.abs() + EPS * (n as f64).sqrt() * amp_sum / (C * a1 * span)
}

#[test]
fn a_pure_line_is_found_to_rounding() {
    for (nu, a, t0, h, n) in [
        (0.731_234_5, Complex::new(0.3, -1.2), 0.0, 0.25, 4001usize),
        (-2.5, Complex::new(1e-3, 0.0), 100.0, 0.1, 20_000),
        (0.011_1, Complex::new(-4.0, 2.0), -7.0, 1.0, 3000),
    ] {
        let f = signal(&[(nu, a)], t0, h, n);
        let span = (n - 1) as f64 * h;
        let band = (nu - 20.0 / span, nu + 30.0 / span);
        let Line {
            frequency,
            amplitude,
        } = leading_line(t0, h, &f, band).unwrap();
        let tol = rounding(nu, n, a.norm(), a.norm(), span);
        let err = (frequency - nu).abs();
        eprintln!("ν = {nu}: error {err:.2e} (bound {tol:.2e})");
        assert!(err <= tol, "ν = {nu}: {err:e} > {tol:e}");
        // The amplitude's phase is off by (t0 + T/2)·δν at most and by the rounding of ν(t0 + T/2),
        // its modulus by rounding.
        let centre = t0 + 0.5 * span;
        let atol = a.norm()
            * (centre.abs() * tol
                + 8.0 * EPS * (n as f64).sqrt()
                + 4.0 * EPS * (nu * centre).abs());
        assert!(
            (amplitude - a).norm() <= atol,
            "amplitude {amplitude} vs {a} (tolerance {atol:e})"
        );
    }
}

#[test]
fn the_second_line_pulls_the_maximum_by_its_window_leakage() {
    let (nu1, a1) = (1.0, Complex::new(1.0, 0.0));
    let (nu2, a2) = (1.05, Complex::new(6e-4, 8e-4));
    let h = 0.25;
    let mut sizes = Vec::new();
    for n in [8001usize, 16001, 32001] {
        let span = (n - 1) as f64 * h;
        let f = signal(&[(nu1, a1), (nu2, a2)], 0.0, h, n);
        let got = leading_line(0.0, h, &f, (0.98, 1.02)).unwrap().frequency - nu1;
        let tc = 0.5 * span;
        let b1 = a1 * Complex::new(0.0, nu1 * tc).exp();
        let b2 = a2 * Complex::new(0.0, nu2 * tc).exp();
        let u2 = (nu2 - nu1) * span / 2.0;
        let want = -(b1.conj() * b2).re * w_prime(u2) / (C * b1.norm_sqr() * span);
        // First order in |a₂/a₁| (relative error of that order) and in 1/N (the discrete window
        // against the continuous one), plus rounding.
        let tol = (4.0 * a2.norm() / a1.norm() + 8.0 / n as f64) * want.abs()
            + rounding(nu1, n, a1.norm() + a2.norm(), a1.norm(), span);
        eprintln!("T = {span}: δν = {got:.4e}, first order {want:.4e} (tolerance {tol:.1e})");
        assert!((got - want).abs() <= tol, "T = {span}: {got:e} vs {want:e}");
        sizes.push(w_prime_envelope(u2) * a2.norm() / (C * span));
    }
    // The envelope of the pull falls like T⁻⁴ (u₂ ∝ T): ratio 16 per doubling, to O(π²/u₂²).
    for w in sizes.windows(2) {
        let r = w[0] / w[1];
        assert!((r - 16.0).abs() <= 16.0 * 3.0 * 0.05, "ratio {r}");
    }
}

/// Frequencies of QP2 at E = 1/12, lines as in the Hénon–Heiles signals: `y − i p_y` has
/// `ν_f + k ν_s`, `|k| ≤ 3`, amplitudes `0.2^{|k|}` (× 0.7 for `k < 0`); `x² + p_x²` has
/// `cos(k ν_s t + 0.1k)`, `k = 1 … 4`, amplitudes `0.2^{k−1}` (lines at `±k ν_s` of half that).
#[test]
fn synthetic_torus_within_the_window_bound() {
    let (nu_f, nu_s) = (0.953_123_456_7, 0.061_234_567_8);
    let h = 0.25;
    for periods in [50.0, 100.0] {
        let span_wanted = periods * 2.0 * PI / nu_s;
        let n = (span_wanted / h).ceil() as usize + 1;
        let span = (n - 1) as f64 * h;
        let fast: Vec<(f64, Complex<f64>)> = (-3i32..=3)
            .map(|k| {
                let a = 0.2f64.powi(k.abs()) * if k < 0 { 0.7 } else { 1.0 };
                (
                    nu_f + f64::from(k) * nu_s,
                    Complex::from_polar(a, 0.3 * f64::from(k)),
                )
            })
            .collect();
        let slow: Vec<(f64, Complex<f64>)> = (1..=4)
            .flat_map(|k| {
                let a = 0.5 * 0.2f64.powi(k - 1);
                let (nu, ph) = (f64::from(k) * nu_s, 0.1 * f64::from(k));
                [
                    (nu, Complex::from_polar(a, ph)),
                    (-nu, Complex::from_polar(a, -ph)),
                ]
            })
            .collect();
        for (what, lines, nu1, band) in [
            ("fast", &fast, nu_f, (nu_f - 0.4 * nu_s, nu_f + 0.4 * nu_s)),
            ("slow", &slow, nu_s, (0.6 * nu_s, 1.4 * nu_s)),
        ] {
            let f = signal(lines, 0.0, h, n);
            let err = (leading_line(0.0, h, &f, band).unwrap().frequency - nu1).abs();
            let a1 = lines.iter().find(|l| l.0 == nu1).unwrap().1.norm();
            let others: Vec<(f64, f64)> = lines
                .iter()
                .filter(|l| l.0 != nu1)
                .map(|l| (l.1.norm() / a1, (l.0 - nu1) * span / 2.0))
                .collect();
            let first: f64 = others
                .iter()
                .map(|&(r, u)| r * w_prime_envelope(u) / (C * span))
                .sum();
            let ratio: f64 = others.iter().map(|o| o.0).sum();
            let amp_sum: f64 = lines.iter().map(|l| l.1.norm()).sum();
            // Second-order terms are at most the first-order ones times Σ|a_j/a₁|.
            let bound = first * (1.0 + ratio) + rounding(nu1, n, amp_sum, a1, span);
            eprintln!("{periods} slow periods, {what} line: error {err:.2e}, bound {bound:.2e}");
            assert!(
                err <= bound,
                "{periods} periods, {what}: {err:e} > {bound:e}"
            );
            // The a-priori error is below the tightest frequency bound the normal-form tests
            // compare against (1e−8 at degree 10, E = 0.01; the slow periods there are ≥ 55).
            assert!(bound <= 1e-8, "{what}: bound {bound:e}");
        }
    }
}

#[test]
fn signals_without_a_line_in_the_band_are_refused() {
    let h = 0.25;
    let f = signal(&[(1.0, Complex::new(1.0, 0.0))], 0.0, h, 4001);
    // The line lies just below the band, whose start is inside the line's main lobe (half-width
    // 4π/T): |φ| is largest at the band's start.
    assert!(leading_line(0.0, h, &f, (1.0 + 1.0 / 1000.0, 1.5)).is_err());
    assert!(leading_line(0.0, h, &vec![Complex::new(0.0, 0.0); 100], (0.5, 1.5)).is_err());
    // Beyond the Nyquist frequency π/h.
    assert!(leading_line(0.0, h, &f, (1.0, 13.0)).is_err());
    assert!(leading_line(0.0, h, &f[..7], (0.5, 1.5)).is_err());
    assert!(leading_line(0.0, h, &f, (1.5, 0.5)).is_err());
}

//! Frequency analysis of a sampled quasi-periodic signal: the frequency of its largest line in a
//! band, by maximising the modulus of its Hann-windowed Fourier transform (the first step of
//! Laskar's NAFF, *numerical analysis of fundamental frequencies*).
//!
//! # Definition
//!
//! For samples `f_k = f(t₀ + k h)`, `k = 0 … N − 1`, over the span `T = (N − 1) h`,
//!
//! ```math
//! \varphi(\nu) = \frac{\sum_{k=0}^{N-1} \chi_k\, f_k\, e^{-i\nu t_k}}{\sum_{k=0}^{N-1} \chi_k},
//! \qquad \chi_k = 1 - \cos\frac{2\pi k}{N-1},
//! ```
//!
//! and the frequency of the line is `ν̂ = argmax |φ(ν)|` over the band `[ν_lo, ν_hi]`; its
//! amplitude is `φ(ν̂)` (exactly `a` for a pure line `f = a e^{iνt}`). The band is scanned with
//! the spacing `π/T` (a quarter of the width of the window's main lobe, `4π/T`), and the largest
//! scanned value refined to the zero of `d|φ|²/dν = 2 Re(φ̄ φ')` by the Illinois iteration, with
//! `φ'` summed directly (`−i t_k` times each term) on times centred in the span, so the
//! frequency is resolved to rounding and not to the square root of it, as a search on the flat
//! maximum of `|φ|` would be.
//!
//! # Accuracy
//!
//! For `f = Σ_j a_j e^{iν_j t}` the window's transform is, with `u = xT/2`,
//! `W(x) = e^{iu} Ŵ(u)`, `Ŵ(u) = π² sin u / (u (π² − u²))`; `Ŵ(u) = 1 − c u² + …` with
//! `c = 1/6 − 1/π²`. The other lines pull the maximum of the line `ν₁` by
//!
//! ```math
//! |\hat\nu - \nu_1| \le \sum_{j \ne 1} \left|\frac{a_j}{a_1}\right|
//!   \frac{\max_{|u - u_j| \le \pi/4} |\hat W'(u)|}{c\, T},
//!   \qquad u_j = \frac{(\nu_j - \nu_1) T}{2},
//! ```
//!
//! to first order in the `|a_j/a_1|`, and `|Ŵ'(u)| ≈ π²/|u|³` far from the line: the error falls
//! like `T⁻⁴` (Laskar 2003, §3: `T^{−(2p+2)}` for the window `(1 − cos)^p`, here `p = 1`),
//! against `T⁻¹` without a window. Lines nearer than the main lobe (`|ν_j − ν₁| < 4π/T`) are
//! not resolved.
//!
//! # References
//! * J. Laskar, "The chaotic motion of the solar system: a numerical estimate of the size of the
//!   chaotic zones", *Icarus* 88, 266–291 (1990).
//! * J. Laskar, "Frequency map analysis and quasiperiodic decompositions", in *Hamiltonian
//!   Systems and Fourier Analysis*, Cambridge Scientific Publishers 2005 (arXiv math/0305364,
//!   2003), §3.

use crate::error::{finite, positive, Error, Result};
use crate::integrate::sampling::illinois;
use nalgebra::Complex;
use std::f64::consts::PI;

/// The most work [`leading_line`] accepts: samples times evaluations of `φ` (scan points plus
/// the refinement's at most 200), each a complex exponential (about a second of work per 10⁸).
pub const MAX_WORK: f64 = 1e9;

/// The fewest samples [`leading_line`] accepts.
pub const MIN_SAMPLES: usize = 8;

/// A line `a e^{iνt}` of a signal.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Line {
    /// Its frequency `ν`, in radians per unit time.
    pub frequency: f64,
    /// Its complex amplitude `a` (the phase at `t = 0`).
    pub amplitude: Complex<f64>,
}

/// `(φ, φ')` at `ν` on the centred times `s_k = (k − (N − 1)/2) h` (the factor `e^{−iν t_c}`,
/// `t_c` the centre, is left out: it does not change `|φ|`).
fn transform(f: &[Complex<f64>], window: &[f64], h: f64, nu: f64) -> (Complex<f64>, Complex<f64>) {
    let centre = 0.5 * (f.len() - 1) as f64;
    let (mut phi, mut dphi) = (Complex::new(0.0, 0.0), Complex::new(0.0, 0.0));
    for (k, (&x, &w)) in f.iter().zip(window).enumerate() {
        let s = (k as f64 - centre) * h;
        let (sn, cs) = (nu * s).sin_cos();
        // x e^{−iνs} χ, and its derivative −i s x e^{−iνs} χ.
        let term = x * Complex::new(cs, -sn) * w;
        phi += term;
        dphi += Complex::new(term.im, -term.re) * s;
    }
    (phi, dphi)
}

/// The largest line of the samples `f_k = f(t₀ + k h)` with its frequency in `[lo, hi]`, by the
/// Hann-windowed frequency analysis of the [module documentation](self).
///
/// The band must contain the line sought: beside a strong line outside it, the largest `|φ|` in
/// the band can be a peak of that line's side lobes (the Hann window's first side lobe is
/// −31 dB, 2.7 % of the line's amplitude), which the returned amplitude shows.
///
/// # Errors
/// * [`Error::NonFinite`]/[`Error::OutOfDomain`]: `t₀`, `h`, `lo`, `hi` or a sample not finite;
///   `h ≤ 0`; `lo ≥ hi`; a band beyond the Nyquist frequency (`max(|lo|, |hi|) h > π`); a span
///   `t₀ + (N − 1) h` that overflows.
/// * [`Error::InvalidInput`]: fewer than [`MIN_SAMPLES`] samples; more work than [`MAX_WORK`]
///   (`N` times the `(hi − lo) T/π` scan points); a signal without a line in the band (zero, or
///   `|φ|` largest at an end of the band: the line, if any, lies outside it).
pub fn leading_line(t0: f64, h: f64, f: &[Complex<f64>], (lo, hi): (f64, f64)) -> Result<Line> {
    let t0 = finite("start time t₀", t0)?;
    let h = positive("sampling step h", h)?;
    let (lo, hi) = (finite("band start", lo)?, finite("band end", hi)?);
    let n = f.len();
    if n < MIN_SAMPLES {
        return Err(Error::invalid(
            "samples",
            format!("{n} given, at least {MIN_SAMPLES} needed"),
        ));
    }
    if lo >= hi {
        return Err(Error::out_of_domain(
            "band start",
            lo,
            format!("below the band end {hi}"),
        ));
    }
    let nyquist = lo.abs().max(hi.abs()) * h;
    if nyquist > PI {
        return Err(Error::out_of_domain(
            "band × sampling step max(|lo|, |hi|) h",
            nyquist,
            "[0, π] (the Nyquist frequency π/h)",
        ));
    }
    let span = finite("span T = (N − 1) h", (n - 1) as f64 * h)?;
    let centre = finite("centre of the span t₀ + T/2", t0 + 0.5 * span)?;
    finite("end of the span t₀ + T", t0 + span)?;
    let scan = ((hi - lo) * span / PI).ceil().max(1.0) + 1.0;
    if (scan + 200.0) * n as f64 > MAX_WORK {
        return Err(Error::invalid(
            "frequency analysis",
            format!(
                "{n} samples × {scan} scan points exceed the work limit {MAX_WORK:e}: \
                 narrow the band or use fewer samples"
            ),
        ));
    }
    let scan = scan as usize;
    // Scale each component to at most 1, so that no sum overflows.
    let scale = f
        .iter()
        .fold(0.0f64, |m, x| m.max(x.re.abs()).max(x.im.abs()));
    let scale = finite("largest sample", scale)?;
    if scale == 0.0 {
        return Err(Error::invalid("signal", "is zero: no line in the band"));
    }
    let g: Vec<Complex<f64>> = f.iter().map(|x| x / scale).collect();
    let window: Vec<f64> = (0..n)
        .map(|k| 1.0 - (2.0 * PI * k as f64 / (n - 1) as f64).cos())
        .collect();
    let norm: f64 = window.iter().sum();
    let power = |nu: f64| transform(&g, &window, h, nu).0.norm_sqr();
    let nu_at = |j: usize| lo + (hi - lo) * j as f64 / (scan - 1) as f64;
    let (best, top) = (0..scan)
        .map(|j| (j, power(nu_at(j))))
        .fold((0, -1.0), |b, x| if x.1 > b.1 { x } else { b });
    if top <= 0.0 || !top.is_finite() {
        return Err(Error::invalid("signal", "has no line in the band"));
    }
    if best == 0 || best == scan - 1 {
        return Err(Error::invalid(
            "signal",
            format!(
                "|φ(ν)| is largest at the band's end ν = {}: no line inside [{lo}, {hi}]",
                nu_at(best)
            ),
        ));
    }
    // d|φ|²/dν = 2 Re(φ̄ φ'): positive below the maximum, negative above it.
    let mut slope = |nu: f64| {
        let (p, d) = transform(&g, &window, h, nu);
        let s = (p.conj() * d).re;
        s.is_finite().then_some((s, nu))
    };
    let not_finite = || Error::invalid("signal", "d|φ|²/dν is not finite");
    let m = nu_at(best);
    let (sm, _) = slope(m).ok_or_else(not_finite)?;
    // The maximum lies between the scanned neighbours; bracket the sign change of the slope.
    let (a, b) = if sm > 0.0 {
        (m, nu_at(best + 1))
    } else {
        (nu_at(best - 1), m)
    };
    let (sa, _) = slope(a).ok_or_else(not_finite)?;
    let (sb, _) = slope(b).ok_or_else(not_finite)?;
    let nu = if sm == 0.0 {
        m
    } else if sa > 0.0 && sb < 0.0 {
        illinois((a, sa, a), (b, sb, b), &mut slope)
            .map(|(nu, _)| nu)
            .ok_or_else(not_finite)?
    } else {
        return Err(Error::invalid(
            "signal",
            format!("no isolated maximum of |φ(ν)| near ν = {m}: lines closer than 4π/T"),
        ));
    };
    let (phi, _) = transform(&g, &window, h, nu);
    let (sn, cs) = (nu * centre).sin_cos();
    let amplitude = phi * Complex::new(cs, -sn) * (scale / norm);
    if !(amplitude.re.is_finite() && amplitude.im.is_finite()) {
        return Err(Error::invalid("signal", "amplitude not finite"));
    }
    Ok(Line {
        frequency: nu,
        amplitude,
    })
}

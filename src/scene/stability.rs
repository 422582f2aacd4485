//! Scenes of stability: the eigenvalues of the double pendulum's equilibria against its mass
//! ratio (SPEC T27, M35), from the classified spectra of `J∇²H` by AD
//! ([`hamiltonian_spectrum()`]).

use super::case::Table;
use crate::error::{fmt_num, Result};
use crate::hamiltonian::Hamiltonian;
use crate::plot::{Figure, Style};
use crate::stability::{hamiltonian_spectrum, SpectralBlock, Stability};
use crate::systems::DoublePendulum;
use nalgebra::SVector;

/// The `what` of the figure of [`double_pendulum_spectrum`]
/// (`figures/<scene>-lambda-squared`).
pub const SPECTRUM_FIGURE: &str = "lambda-squared";

/// The names of the equilibria of [`DoublePendulum::equilibria`].
const NAMES: [&str; 4] = ["(0, 0)", "(π, 0)", "(0, π)", "(π, π)"];

/// `λ²` of each pair, the stability and the Krein signatures `(ω, ±1)` of one equilibrium.
type Squares = (Vec<f64>, Stability, Vec<(f64, i8)>);

/// The values `s = λ²` of one equilibrium's spectrum (one per pair `±λ`, increasing: `−ω²` for
/// an elliptic pair, `λ²` for a hyperbolic one), its stability and Krein signatures.
fn squares(h: &DoublePendulum, q: &SVector<f64, 2>) -> Result<Squares> {
    let hess = h.hessian(0.0, q, &SVector::zeros())?.to_dmatrix();
    let sp = hamiltonian_spectrum(&hess)?;
    let mut s = Vec::new();
    for b in &sp.blocks {
        match *b {
            SpectralBlock::Elliptic {
                frequency,
                multiplicity,
                ..
            } => s.extend(std::iter::repeat_n(-frequency * frequency, multiplicity)),
            SpectralBlock::Hyperbolic { rate, multiplicity } => {
                s.extend(std::iter::repeat_n(rate * rate, multiplicity))
            }
            SpectralBlock::ComplexSaddle { re, im, .. } => s.extend([re * re - im * im; 2]),
            SpectralBlock::Zero { multiplicity } => {
                s.extend(std::iter::repeat_n(0.0, multiplicity / 2))
            }
        }
    }
    s.sort_by(f64::total_cmp);
    Ok((s, sp.stability, sp.krein_signatures()))
}

/// The table and figure of the scene `double-pendulum-spectrum`: `λ²` of the four equilibria
/// against `m₂/m₁` on a logarithmic grid of `samples` values in `[lo, hi]` (`m₁ = 1`), with the
/// values of T27 (`m₂ = m₁`, `ℓ₁ = ℓ₂`, `g/ℓ = 1`) marked when the parameters are those.
///
/// # Errors
/// The errors of [`DoublePendulum::new`] and [`hamiltonian_spectrum()`].
#[allow(clippy::type_complexity)]
pub fn double_pendulum_spectrum(
    lo: f64,
    hi: f64,
    samples: usize,
    l1: f64,
    l2: f64,
    g: f64,
) -> Result<(Table, Vec<(String, Figure)>)> {
    let n = samples.max(2);
    let ratios: Vec<f64> = (0..n)
        .map(|k| lo * (hi / lo).powf(k as f64 / (n - 1) as f64))
        .collect();
    let mut curves: Vec<Vec<Vec<(f64, f64)>>> = vec![vec![Vec::new(); 2]; 4];
    let mut rows = Vec::new();
    let decades: Vec<f64> = (-6..=6)
        .map(|e| 10f64.powi(e))
        .filter(|r| *r >= lo && *r <= hi)
        .collect();
    for &r in ratios.iter().chain(decades.iter()) {
        let h = DoublePendulum::new(1.0, r, l1, l2, g)?;
        for (e, q) in DoublePendulum::equilibria().iter().enumerate() {
            let (s, stability, krein) = squares(&h, q)?;
            if decades.contains(&r) {
                let signatures: Vec<String> = krein
                    .iter()
                    .map(|(w, k)| format!("{}{}", fmt_num(*w), if *k > 0 { "⁺" } else { "⁻" }))
                    .collect();
                rows.push(vec![
                    fmt_num(r),
                    NAMES[e].to_string(),
                    s.iter().map(|x| fmt_num(*x)).collect::<Vec<_>>().join(", "),
                    format!("{stability:?}"),
                    signatures.join(", "),
                ]);
            } else {
                for (k, x) in s.iter().enumerate().take(2) {
                    curves[e][k].push((r, *x));
                }
            }
        }
    }
    let mut fig = Figure::new(
        format!(
            "Double pendulum (ℓ₁ = {}, ℓ₂ = {}, g = {}): λ² at the equilibria",
            fmt_num(l1),
            fmt_num(l2),
            fmt_num(g)
        ),
        "mass ratio m₂/m₁",
        "λ²  (< 0: oscillation ω² = −λ²; > 0: growth)",
    )
    .log_x();
    for (e, pair) in curves.into_iter().enumerate() {
        for (k, points) in pair.into_iter().enumerate() {
            let label = format!("{} λ²{}", NAMES[e], ["₁", "₂"][k]);
            fig = fig.curve(label, points, Style::Line);
        }
    }
    let t27 = l1 == l2 && g == l1 && lo <= 1.0 && hi >= 1.0;
    if t27 {
        let s2 = 2f64.sqrt();
        let marks = [-(2.0 + s2), -(2.0 - s2), -s2, s2, 2.0 - s2, 2.0 + s2];
        fig = fig.curve(
            "T27: −(2 ± √2), ±√2, 2 ± √2",
            marks.iter().map(|&s| (1.0, s)),
            Style::Markers,
        );
    }
    fig = fig.caption(format!(
        "The squares λ² of the eigenvalues of J∇²H at the four equilibria of the double pendulum \
         of point masses m₁ = 1, m₂ (ℓ₁ = {}, ℓ₂ = {}, g = {}), against m₂/m₁ on {n} values \
         from {} to {}, by the AD Hessian and the classification of the Hamiltonian spectrum. \
         Negative λ² are elliptic pairs ±iω, positive ones hyperbolic pairs ±λ: the hanging \
         equilibrium (0, 0) is elliptic for every ratio, (π, 0) and (0, π) have one pair of each \
         kind, (π, π) is doubly hyperbolic.{}",
        fmt_num(l1),
        fmt_num(l2),
        fmt_num(g),
        fmt_num(lo),
        fmt_num(hi),
        if t27 {
            " Markers: the values of SPEC T27 at m₂ = m₁."
        } else {
            ""
        }
    ));
    let table = Table {
        header: vec![
            "m₂/m₁".into(),
            "equilibrium".into(),
            "λ²".into(),
            "stability".into(),
            "Krein (ω with signature)".into(),
        ],
        rows,
    };
    Ok((table, vec![(SPECTRUM_FIGURE.to_string(), fig)]))
}

//! Brouwer's law for the Taylor method at tolerance ≈ machine ε: over N periods of the Kepler
//! problem the relative energy error grows like √N and the along-track error like N^{3/2}
//! (D. Brouwer, Astron. J. 51 (1946) 37–43: rounding errors that are random and unbiased make
//! the energy a random walk, and the phase error its integral).
//!
//! An ensemble of orbits (e = 0.5, μ = a = 1, `ORBITS` starting anomalies) is integrated for
//! `10⁵` periods; at N = 10, 20, 50, … periods the root-mean-square relative energy error and the
//! root-mean-square position error against the exact flow of the same double start (the crate's
//! Kepler flow, exact to half an ulp) are printed, with the slopes of `log error` against
//! `log N` fitted by least squares over N ≥ 100.
//!
//! The figure `out/brouwer-law.{svg,png}` draws both errors against N with the slopes ½ and 3/2
//! through the sample at N = 100.
//!
//! ```text
//! cargo run --release --example brouwer_law [periods] [orbits] [tol]
//! ```

use hamilton_jacobi::integrate::{Problem, Samples, Taylor, VectorFieldRecord};
use hamilton_jacobi::nalgebra::Vector2;
use hamilton_jacobi::phase::State;
use hamilton_jacobi::plot::{DataFormat, Figure, Format, Style};
use hamilton_jacobi::systems::{ExactFlow, Kepler};
use hamilton_jacobi::{Error, Hamiltonian, Result};
use std::f64::consts::TAU;
use std::time::Instant;

/// Least-squares slope of `ln y` against `ln x`.
fn slope(points: &[(f64, f64)]) -> f64 {
    let n = points.len() as f64;
    let (sx, sy) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x.ln(), b + y.ln()));
    let (mx, my) = (sx / n, sy / n);
    let (num, den) = points.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        let dx = x.ln() - mx;
        (a + dx * (y.ln() - my), b + dx * dx)
    });
    num / den
}

fn main() -> Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |k: usize, default: f64| -> Result<f64> {
        args.get(k).map_or(Ok(default), |s| {
            s.parse()
                .map_err(|_| Error::invalid("brouwer_law", format!("not a number: {s}")))
        })
    };
    let periods = arg(0, 1e5)?;
    let orbits = arg(1, 8.0)? as usize;
    let tol = arg(2, 1e-16)?;
    let kepler = Kepler::<2>::new(1.0)?;
    let e: f64 = 0.5;
    let taylor = Taylor::new(tol)?.with_max_steps(100_000_000)?;
    // Sample periods 1, 2, 5 × 10^k up to `periods`.
    let mut marks = Vec::new();
    let mut decade = 10.0;
    while decade <= periods {
        for m in [1.0, 2.0, 5.0] {
            if m * decade <= periods {
                marks.push(m * decade);
            }
        }
        decade *= 10.0;
    }
    let mut energy = vec![0.0; marks.len()];
    let mut position = vec![0.0; marks.len()];
    let clock = Instant::now();
    let mut steps = 0usize;
    for k in 0..orbits {
        // Start at eccentric anomaly E₀ on the ellipse a = 1 (periapsis on the x axis).
        let big_e = TAU * k as f64 / orbits as f64 + 0.1;
        let (s, c) = big_e.sin_cos();
        let b = (1.0 - e * e).sqrt();
        let r = 1.0 - e * c;
        let q = Vector2::new(c - e, b * s);
        let p = Vector2::new(-s / r, b * c / r);
        let start = State::new(0.0, q, p)?;
        let e0 = kepler.hamiltonian(0.0, &q, &p);
        let field = VectorFieldRecord::new(&kepler, &start)?;
        let times: Vec<f64> = marks.iter().map(|m| m * TAU).collect();
        let problem = Problem::new(&kepler, 0.0, q, p, times[times.len() - 1])?;
        let mut samples = Samples::at(times.iter().copied())?;
        let report = taylor.run_recorded(&field, &problem, &mut samples)?;
        steps += report.work.steps;
        for (j, s) in samples.states.iter().enumerate() {
            let de = (kepler.hamiltonian(s.t, &s.q, &s.p) - e0) / e0;
            let (qx, _) = kepler.exact_flow(0.0, &q, &p, s.t)?;
            energy[j] += de * de;
            position[j] += (s.q - qx).norm_squared();
        }
    }
    println!(
        "Kepler e = {e}, {orbits} orbits, Taylor tol {tol:e} (order {}), {steps} steps, {:.1} s",
        taylor.order(),
        clock.elapsed().as_secs_f64()
    );
    println!("{:>10} {:>14} {:>14}", "periods", "rms |ΔE/E|", "rms |Δq|");
    let mut fit_e = Vec::new();
    let mut fit_q = Vec::new();
    for (j, &n) in marks.iter().enumerate() {
        let (ej, qj) = (
            (energy[j] / orbits as f64).sqrt(),
            (position[j] / orbits as f64).sqrt(),
        );
        println!("{n:>10} {ej:>14.3e} {qj:>14.3e}");
        if n >= 100.0 {
            fit_e.push((n, ej));
            fit_q.push((n, qj));
        }
    }
    let (se, sq) = (slope(&fit_e), slope(&fit_q));
    println!("slopes over N ≥ 100: energy {se:.3} (Brouwer 0.5), position {sq:.3} (Brouwer 1.5)");
    // Reference lines through the first fitted sample (N = 100).
    let through = |fit: &[(f64, f64)], power: f64| -> Vec<(f64, f64)> {
        let (n0, y0) = fit[0];
        let n1 = fit[fit.len() - 1].0;
        vec![(n0, y0), (n1, y0 * (n1 / n0).powf(power))]
    };
    let series = |v: &[f64]| -> Vec<(f64, f64)> {
        marks
            .iter()
            .zip(v)
            .map(|(&n, &s)| (n, (s / orbits as f64).sqrt()))
            .collect()
    };
    let figure = Figure::new(
        "Brouwer's law: Taylor method at tolerance ≈ ε, Kepler e = 0.5",
        "periods N",
        "",
    )
    .log_x()
    .log_y()
    .panels(["rms |ΔE/E|", "rms |Δq|"])
    .caption(format!(
        "Root-mean-square relative energy error (top) and position error against the exact \
         flow (bottom) of {orbits} orbits (e = 0.5, μ = a = 1, starts spread in anomaly) \
         integrated by the Taylor method at tolerance {tol:e} (order {}), against the number \
         of periods; straight lines: Brouwer's slopes ½ and 3/2 through N = 100. Fitted over N ≥ 100: {se:.3} and \
         {sq:.3}.",
        taylor.order()
    ))
    .curve_in(0, "Taylor (rms over the orbits)", series(&energy), Style::LineMarkers)
    .curve_in(0, "Brouwer: √N, N^(3/2)", through(&fit_e, 0.5), Style::Line)
    .curve_in(1, "Taylor (rms over the orbits)", series(&position), Style::LineMarkers)
    .curve_in(1, "Brouwer: √N, N^(3/2)", through(&fit_q, 1.5), Style::Line);
    std::fs::create_dir_all("out")
        .map_err(|e| Error::invalid("output folder out/", e.to_string()))?;
    for f in figure.write(
        std::path::Path::new("out/brouwer-law"),
        &[Format::Svg, Format::Png],
        DataFormat::Csv,
    )? {
        println!("wrote {}", f.display());
    }
    Ok(())
}

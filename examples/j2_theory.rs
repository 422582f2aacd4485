//! Brouwer–Lyddane `J₂` theory against DOP853 on the problem `a = 2`, `i = 0.5`, `R = μ = 1`,
//! 100 orbits, `e = 0.1` and `e = 0.7`, `J₂ = 10⁻³ … 10⁻⁶`: the largest position error over 400
//! samples, with the mean semi-major axis fixed by the energy integral and by the first-order
//! inverse, and the cost of one evaluation of the theory (osculating state at a time `t`,
//! Kepler's equation included; wall and on-CPU time) beside the cost of a Cowell DOP853 run
//! over the same span.
//!
//! The truth is DOP853 at `rtol = 10⁻¹³` in Encke's form (tests/oracles/j2_encke.rs).
//!
//! The largest errors against `J₂` are drawn in `out/j2-theory-error-against-j2.svg` and `.png`
//! (data in `.csv`).
//!
//! Run with `cargo run --release --example j2_theory`.

use hamilton_jacobi::integrate::{integrate, Dop853, Problem};
use hamilton_jacobi::nalgebra::Vector3;
use hamilton_jacobi::perturbation::brouwer::{BrouwerLyddane, MeanAxis};
use hamilton_jacobi::perturbation::forces::{PerturbedTwoBody, J2};
use hamilton_jacobi::plot::{DataFormat, Figure, Format, Style};
use hamilton_jacobi::systems::kepler::elements::Classical;
use std::f64::consts::TAU;
use std::hint::black_box;
use std::time::Instant;

#[path = "../tests/oracles/j2_encke.rs"]
mod encke;

const MU: f64 = 1.0;
const RADIUS: f64 = 1.0;

/// Time this thread has run on a CPU, in seconds (Linux `/proc/thread-self/schedstat`): on a
/// machine shared with other work, wall time per evaluation overstates the cost.
fn cpu_seconds() -> Option<f64> {
    let s = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    Some(s.split_whitespace().next()?.parse::<f64>().ok()? * 1e-9)
}

fn main() -> hamilton_jacobi::Result<()> {
    println!("Brouwer–Lyddane J₂ theory, a = 2, i = 0.5, R = μ = 1, 100 orbits, 400 samples");
    println!(
        "{:>4} {:>7} {:>14} {:>14} {:>11} {:>11} {:>14}",
        "e", "J₂", "err (energy)", "err (1st inv)", "µs/eval", "CPU µs/eval", "DOP853 run ms"
    );
    let mut figure = Figure::new(
        "Brouwer–Lyddane theory: largest position error over 100 orbits",
        "J₂",
        "max |Δq|",
    )
    .log_x()
    .log_y()
    .caption(
        "Largest position error of the Brouwer–Lyddane J₂ theory over 100 orbits (400 samples; \
         a = 2, i = 0.5, R = μ = 1) against Encke DOP853 at rtol 1e−13, with the mean semi-major \
         axis fixed by the energy integral (error ∝ J₂²) and by the first-order inverse (error \
         ∝ J₂² n t, larger).",
    );
    for e in [0.1, 0.7] {
        let mut energy_curve = Vec::new();
        let mut inverse_curve = Vec::new();
        let el = Classical::new(2.0, e, 0.5, 0.3, 0.7, 0.2)?;
        let period = TAU * (el.a.powi(3) / MU).sqrt();
        let times: Vec<f64> = (0..=400)
            .map(|k| 100.0 * period * k as f64 / 400.0)
            .collect();
        let (q0, p0) = el.to_state(MU)?;
        for j2 in [1e-3, 1e-4, 1e-5, 1e-6] {
            let force = J2::new(MU, j2, RADIUS)?;
            let truth = encke::truth(force, (q0, p0), &times, 1e-13);
            let error = |axis| -> hamilton_jacobi::Result<f64> {
                let th = BrouwerLyddane::from_state_with(&force, 0.0, &q0, &p0, axis)?;
                let mut worst = 0.0f64;
                for (&t, q) in times.iter().zip(&truth) {
                    worst = worst.max((th.state(t)?.0 - q).norm());
                }
                Ok(worst)
            };
            let fixed = error(MeanAxis::EnergyIntegral)?;
            let plain = error(MeanAxis::FirstOrderInverse)?;
            energy_curve.push((j2, fixed));
            inverse_curve.push((j2, plain));
            // Cost of one evaluation: 10⁵ states at times spread over the 100 orbits.
            let th = BrouwerLyddane::from_state(&force, 0.0, &q0, &p0)?;
            let n = 100_000;
            let span = 100.0 * period;
            let (start, cpu0) = (Instant::now(), cpu_seconds());
            let mut sink = Vector3::zeros();
            for k in 0..n {
                sink += th.state(black_box(span * (k as f64 + 0.5) / n as f64))?.0;
            }
            let per_eval = start.elapsed().as_secs_f64() / n as f64 * 1e6;
            let cpu = match (cpu0, cpu_seconds()) {
                (Some(a), Some(b)) => format!("{:.3}", (b - a) / n as f64 * 1e6),
                _ => "-".into(),
            };
            black_box(sink);
            // The Cowell DOP853 run over the same span, for scale.
            let sys = PerturbedTwoBody::conservative(MU, force)?;
            let problem = Problem::new(&sys, 0.0, q0, p0, span)?;
            let run = integrate(
                &problem,
                &Dop853::new(1e-13, 1e-15)?.with_max_steps(10_000_000)?,
                &mut (),
            )?;
            println!(
                "{e:>4} {j2:>7.0e} {fixed:>14.3e} {plain:>14.3e} {per_eval:>11.3} {cpu:>11} {:>14.1}",
                run.elapsed.as_secs_f64() * 1e3
            );
        }
        figure = figure
            .curve(
                format!("e = {e}, L'' by the energy integral"),
                energy_curve,
                Style::Line,
            )
            .curve(
                format!("e = {e}, first-order inverse"),
                inverse_curve,
                Style::Line,
            );
    }
    let files = figure.write(
        std::path::Path::new("out/j2-theory-error-against-j2"),
        &[Format::Svg, Format::Png],
        DataFormat::Csv,
    )?;
    for f in files {
        println!("wrote {}", f.display());
    }
    if let Some(w) = BrouwerLyddane::from_osculating(
        &J2::new(MU, 1e-3, RADIUS)?,
        0.0,
        &Classical::new(2.0, 0.7, 0.5, 0.3, 0.7, 0.2)?,
    )?
    .warnings()
    .first()
    {
        println!("e = 0.7: {w:?}");
    }
    Ok(())
}

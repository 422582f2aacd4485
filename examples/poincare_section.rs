//! Poincaré sections of Hénon–Heiles at energy 1/8 (Hénon & Heiles, Astron. J. 69 (1964) 73,
//! doi:10.1086/109234): the surface `x = 0` crossed with `p_x > 0`, 1000 crossings per orbit, by
//! Störmer–Verlet, Kahan–Li 8 and DOP853, the methods swept as values.
//!
//! The section points of the fixed-step methods are partial steps of the method itself (the
//! point of its numerical trajectory on the surface), DOP853's come from its continuous
//! extension; the first crossings of each run are compared one by one with DOP853's. On the
//! regular orbit they agree to each method's global error (Verlet ~1e−5 at h = 0.01, Kahan–Li 8
//! to DOP853's own accuracy); in the chaotic sea nearby trajectories separate exponentially, so
//! pointwise agreement is lost after a few Lyapunov times while the points fill the same region.
//!
//! `cargo run --release --example poincare_section [out.csv]` writes every section point
//! `(orbit, method, k, t, y, p_y)` to `out.csv` if a path is given.
//!
//! Then the section of twelve orbits at the same energy, 8400 crossings each (100 800 points,
//! DOP853 at rtol 1e−10), is drawn as a figure of dots: `out/henon-heiles-section.svg` and
//! `.png`, with every point in `out/henon-heiles-section.npy` (the header in `.csv`).

use hamilton_jacobi::integrate::{
    integrate, AnyMethod, Crossing, Method, MethodInfo, Problem, Section,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::phase::State;
use hamilton_jacobi::plot::{DataFormat, Figure, Format, Style};
use hamilton_jacobi::{hamiltonian, Result};
use std::fmt::Write as _;
use std::time::Instant;

hamiltonian!(
    /// `H = (p_x² + p_y²)/2 + (x² + y²)/2 + x²y − y³/3`, written once as `T(p) + V(q)`.
    HenonHeiles<2> |_s, _t, q, p|
        kinetic = (p[0] * p[0] + p[1] * p[1]) * 0.5,
        potential = (q[0] * q[0] + q[1] * q[1]) * 0.5 + q[0] * q[0] * q[1] - q[1] * q[1] * q[1] / 3.0
);

const ENERGY: f64 = 0.125;
const CROSSINGS: usize = 1000;
/// Orbits and crossings per orbit of the drawn section.
const ORBITS: usize = 12;
const SECTION_CROSSINGS: usize = 8400;

/// `p_x > 0` on the surface `x = 0` at energy [`ENERGY`] with `p_y = 0`.
fn px_on_section(y0: f64) -> f64 {
    (2.0 * ENERGY - y0 * y0 + 2.0 * y0.powi(3) / 3.0).sqrt()
}

/// The section of [`ORBITS`] orbits started on `x = 0` with `p_y = 0` and `y₀` from −0.35 to
/// 0.55, each followed for [`SECTION_CROSSINGS`] upward crossings, drawn as dots.
fn many_orbits() -> Result<()> {
    let mut fig = Figure::new("Hénon–Heiles, E = 1/8: section x = 0, p_x > 0", "y", "p_y")
        .equal_aspect()
        .caption(format!(
            "Poincaré section of the Hénon–Heiles system at E = 1/8: {ORBITS} orbits started on \
         x = 0 with p_y = 0, {SECTION_CROSSINGS} upward crossings each, by DOP853 at rtol 1e−10 \
         (crossings located on its continuous extension)."
        ));
    let clock = Instant::now();
    for i in 0..ORBITS {
        let y0 = -0.35 + 0.9 * i as f64 / (ORBITS - 1) as f64;
        let (q0, p0) = (
            SVector::from([0.0, y0]),
            SVector::from([px_on_section(y0), 0.0]),
        );
        let span = 8.0 * SECTION_CROSSINGS as f64;
        let problem = Problem::new(&HenonHeiles, 0.0, q0, p0, span)?;
        let method = AnyMethod::dop853(1e-10, 1e-12)?;
        let mut section =
            Section::new(|_t, q, _p| q[0], Crossing::Up).stop_after(SECTION_CROSSINGS);
        integrate(&problem, &method, &mut section)?;
        let points: Vec<(f64, f64)> = section.points.iter().map(|z| (z.q[1], z.p[1])).collect();
        fig = fig.curve(format!("y₀ = {y0:.3}"), points, Style::Dots);
    }
    let n: usize = fig.curves.iter().map(|c| c.points.len()).sum();
    std::fs::create_dir_all("out")
        .map_err(|e| hamilton_jacobi::Error::invalid("directory out", e.to_string()))?;
    let files = fig.write(
        std::path::Path::new("out/henon-heiles-section"),
        &[Format::Svg, Format::Png],
        DataFormat::Npy,
    )?;
    println!(
        "section of {ORBITS} orbits, {n} points in {:.1?}:",
        clock.elapsed()
    );
    for f in files {
        let bytes = std::fs::metadata(&f).map(|m| m.len()).unwrap_or(0);
        println!("  {} ({bytes} bytes)", f.display());
    }
    Ok(())
}

fn main() -> Result<()> {
    let out = std::env::args().nth(1);
    let mut csv = String::from("orbit,method,k,t,y,p_y\n");
    // A regular orbit (y₀ = 0.3) and one in the chaotic sea (y₀ = −0.15), both with p_y = 0.
    for y0 in [0.3f64, -0.15] {
        let px0 = px_on_section(y0);
        let (q0, p0) = (SVector::from([0.0, y0]), SVector::from([px0, 0.0]));
        // Long enough for 1000 crossings (one about every 6 time units); the section stops the run.
        let span = 8000.0;
        let problem = Problem::new(&HenonHeiles, 0.0, q0, p0, span)?;
        let methods = [
            AnyMethod::dop853(1e-13, 1e-15)?,
            AnyMethod::verlet((span / 0.01) as usize)?,
            AnyMethod::new(MethodInfo::find("kahan-li17")?, (span / 0.1).round())?,
        ];
        println!("orbit y₀ = {y0}, p_y = 0, p_x = {px0:.6}, E = {ENERGY}");
        let mut reference: Vec<State<2>> = Vec::new();
        for method in &methods {
            let label = Method::<HenonHeiles, 2>::label(method);
            let mut section = Section::new(|_t, q, _p| q[0], Crossing::Up).stop_after(CROSSINGS);
            let clock = Instant::now();
            let run = integrate(&problem, method, &mut section)?;
            let elapsed = clock.elapsed();
            let points = section.points;
            // The first 20 crossings, one by one, against DOP853's.
            let first = if reference.is_empty() {
                reference = points.clone();
                String::from("reference")
            } else {
                let d = points
                    .iter()
                    .zip(&reference)
                    .take(20)
                    .map(|(a, b)| (a.q - b.q).amax().max((a.p - b.p).amax()))
                    .fold(0.0, f64::max);
                format!("first 20 points within {d:.2e} of DOP853's")
            };
            println!(
                "  {label:<48} {} crossings up to t = {:.1} in {:>8.1?} ({} steps); {first}",
                points.len(),
                run.last.t,
                elapsed,
                run.work.steps
            );
            for (k, z) in points.iter().enumerate() {
                let _ = writeln!(
                    csv,
                    "{y0},\"{label}\",{k},{:e},{:e},{:e}",
                    z.t, z.q[1], z.p[1]
                );
            }
        }
    }
    if let Some(path) = out {
        std::fs::write(&path, csv).map_err(|e| {
            hamilton_jacobi::Error::invalid(format!("writing {path}"), e.to_string())
        })?;
        println!("section points written to {path}");
    }
    many_orbits()
}

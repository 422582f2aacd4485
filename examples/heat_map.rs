//! The energy error of Störmer–Verlet on the pendulum `H = p²/2 + 1 − cos θ` as a heat map over
//! the step `h` and the amplitude `θ₀` (started at rest): the largest relative energy error
//! `max |H(t) − H(0)| / |H(0)|` over ten small-oscillation periods, on a logarithmic colour
//! scale.
//!
//! Verlet is symplectic: its energy error stays bounded and is of order `h²` (Hairer, Lubich &
//! Wanner, *Geometric Numerical Integration*, 2nd ed., §IX.8). At small amplitude the pendulum
//! is the harmonic oscillator, for which the numerical orbit conserves the modified energy
//! `H̃ = p²/2 + (1 − h²/4) θ²/2` exactly, so that `H(t) − H(0) = (h²/4)(θ² − θ₀²)/2` and the
//! largest relative error is `h²/4`, reached as θ passes through 0 (printed against the map's
//! bottom row). Towards the separatrix
//! (`θ₀ → π`) the error grows as the motion slows near the unstable equilibrium; above
//! `h = 2` the step leaves the stability interval of the linearised map (no cell reaches it
//! here). Cells whose run fails are drawn as "no value".
//!
//! `cargo run --release --example heat_map` writes `out/pendulum-verlet-energy-map.svg`, `.png`,
//! the data `.csv` (every cell) and the caption.

use hamilton_jacobi::integrate::{integrate, AnyMethod, EnergyMonitor, Problem};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::plot::{DataFormat, Figure, Format, Grid};
use hamilton_jacobi::systems::Pendulum;
use hamilton_jacobi::Result;
use std::f64::consts::TAU;

/// Columns (steps, logarithmic) and rows (amplitudes).
const NX: usize = 48;
const NY: usize = 40;
/// Step range (edges of the grid), and amplitude range.
const H: (f64, f64) = (1e-3, 1.0);
const THETA: (f64, f64) = (0.0, 3.1);
/// Span: ten small-oscillation periods.
const SPAN: f64 = 10.0 * TAU;

fn main() -> Result<()> {
    let pendulum = Pendulum::new(1.0)?;
    let grid = Grid::new(NX, NY, H, THETA, vec![0.0; NX * NY])?;
    let (hs, thetas) = (
        grid.centres(true, hamilton_jacobi::plot::Scale::Log),
        grid.centres(false, hamilton_jacobi::plot::Scale::Linear),
    );
    let mut values = Vec::with_capacity(NX * NY);
    for &theta in &thetas {
        for &h in &hs {
            let steps = (SPAN / h).round() as usize;
            let problem = Problem::new(
                &pendulum,
                0.0,
                SVector::from([theta]),
                SVector::from([0.0]),
                steps as f64 * h,
            )?;
            let mut monitor = EnergyMonitor::new(&pendulum, 1);
            let run = AnyMethod::verlet(steps).and_then(|m| integrate(&problem, &m, &mut monitor));
            values.push(match run {
                Ok(_) => monitor.max_error,
                Err(_) => f64::NAN,
            });
        }
    }
    // The bottom row against the harmonic oscillator's modified energy.
    println!(
        "θ₀ = {:.4}: max |ΔH/H₀| against (h²/4)/(1 − h²/4)",
        thetas[0]
    );
    for i in (0..NX).step_by(8) {
        let h = hs[i];
        let theory = 0.25 * h * h / (1.0 - 0.25 * h * h);
        println!(
            "  h = {h:.3e}: {:.3e} (harmonic {theory:.3e}, ratio {:.4})",
            values[i],
            values[i] / theory
        );
    }
    let grid = Grid { values, ..grid }.label("max |ΔH / H₀|").log();
    let fig = Figure::new(
        "Störmer–Verlet on the pendulum: energy error",
        "step h",
        "amplitude θ₀",
    )
    .log_x()
    .caption(format!(
        "Largest relative energy error max |H(t) − H(0)| / |H(0)| of Störmer–Verlet on the \
         pendulum H = p²/2 + 1 − cos θ, started at rest at θ₀, over ten small-oscillation \
         periods (t ≤ {SPAN:.1}), on a grid of {NX} steps h (logarithmic) × {NY} amplitudes."
    ))
    .heat_map(grid);
    std::fs::create_dir_all("out")
        .map_err(|e| hamilton_jacobi::Error::invalid("directory out", e.to_string()))?;
    let files = fig.write(
        std::path::Path::new("out/pendulum-verlet-energy-map"),
        &[Format::Svg, Format::Png],
        DataFormat::Csv,
    )?;
    for f in files {
        let bytes = std::fs::metadata(&f).map(|m| m.len()).unwrap_or(0);
        println!("wrote {} ({bytes} bytes)", f.display());
    }
    Ok(())
}

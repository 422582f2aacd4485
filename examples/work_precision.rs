//! Work-precision diagrams: Kepler e = 0.5 and the pendulum over 100 periods.
//!
//! Every method is swept over its knob; the error is the final position error against the exact
//! solution (Kepler's equation; Jacobi elliptic functions), the cost the best wall time of
//! repeated runs. Writes `out/work_precision_{kepler,pendulum}.{csv,svg,md}` and prints the
//! Markdown tables.
//!
//! Run: `cargo run --release --example work_precision`

use hamilton_jacobi::integrate::{integrate, ExactStep, Fixed, OneStep, Problem, Rk4};
use hamilton_jacobi::nalgebra::{SVector, Vector2};
use hamilton_jacobi::systems::kepler_orbit::kepler_propagate_planar;
use hamilton_jacobi::systems::pendulum_exact::{exact_state, period};
use hamilton_jacobi::systems::{Kepler2, Pendulum};
use hamilton_jacobi::workprecision::{sweep, Comparison, Series, Timing};
use hamilton_jacobi::{Hamiltonian, Result};
use std::f64::consts::PI;

/// Sweep a fixed-step method over step counts; error = final position error.
fn fixed_series<S: Hamiltonian<N>, M: OneStep<S, N> + Copy, const N: usize>(
    problem: &Problem<'_, S, N>,
    method: M,
    steps: &[usize],
    exact_q: SVector<f64, N>,
) -> Result<Series> {
    let knobs: Vec<f64> = steps.iter().map(|&n| n as f64).collect();
    sweep(
        OneStep::<S, N>::name(&method),
        "steps",
        &knobs,
        Timing::default(),
        |n| {
            let run = integrate(problem, &Fixed::new(method, n as usize)?, &mut ())?;
            Ok(((run.last.q - exact_q).norm(), run.work))
        },
    )
}

fn geometric(lo: usize, hi: usize, factor: f64) -> Vec<usize> {
    let mut v = vec![];
    let mut x = lo as f64;
    while x <= hi as f64 {
        v.push(x.round() as usize);
        x *= factor;
    }
    v
}

fn main() -> Result<()> {
    std::fs::create_dir_all("out")
        .map_err(|e| hamilton_jacobi::Error::invalid("output directory out/", e.to_string()))?;

    // Kepler e = 0.5, μ = a = 1 from periapsis, 100 periods.
    let kepler = Kepler2::new(1.0)?;
    let (e, periods): (f64, f64) = (0.5, 100.0);
    let q0 = SVector::from([1.0 - e, 0.0]);
    let p0 = SVector::from([0.0, ((1.0 + e) / (1.0 - e)).sqrt()]);
    let t1 = periods * 2.0 * PI;
    let problem = Problem::new(&kepler, 0.0, q0, p0, t1)?;
    let (exact_q, _) = kepler_propagate_planar(
        1.0,
        &Vector2::new(q0[0], q0[1]),
        &Vector2::new(p0[0], p0[1]),
        t1,
    )?;
    let exact_q = SVector::from([exact_q[0], exact_q[1]]);
    let mut kep = Comparison::new("Kepler e = 0.5, 100 periods", "final position error");
    kep.push(fixed_series(
        &problem,
        Rk4,
        &geometric(2_000, 256_000, 2.0),
        exact_q,
    )?);
    kep.push(fixed_series(
        &problem,
        ExactStep,
        &[1, 10, 100, 1_000],
        exact_q,
    )?);
    report(&kep, "kepler")?;

    // Pendulum H = p²/2 − cos q, q₀ = 1, p₀ = 0, 100 periods.
    let pendulum = Pendulum::new(1.0)?;
    let tau = period(1.0, 1.0)?;
    let t1 = 100.0 * tau;
    let (q0, p0) = (SVector::from([1.0]), SVector::from([0.0]));
    let problem = Problem::new(&pendulum, 0.0, q0, p0, t1)?;
    let (qe, _) = exact_state(1.0, 1.0, 0.0, t1)?;
    let exact_q = SVector::from([qe]);
    let mut pen = Comparison::new("Pendulum q₀ = 1, 100 periods", "final angle error");
    pen.push(fixed_series(
        &problem,
        Rk4,
        &geometric(500, 128_000, 2.0),
        exact_q,
    )?);
    pen.push(fixed_series(
        &problem,
        ExactStep,
        &[1, 10, 100, 1_000],
        exact_q,
    )?);
    report(&pen, "pendulum")?;
    Ok(())
}

fn report(c: &Comparison, name: &str) -> Result<()> {
    let io =
        |e: std::io::Error| hamilton_jacobi::Error::invalid(format!("out/{name}"), e.to_string());
    let md = c.to_markdown(&[1e-6, 1e-9, 1e-12]);
    println!("{md}");
    std::fs::write(format!("out/work_precision_{name}.csv"), c.to_csv()).map_err(io)?;
    std::fs::write(format!("out/work_precision_{name}.md"), &md).map_err(io)?;
    #[cfg(feature = "cli")]
    c.to_svg(std::path::Path::new(&format!(
        "out/work_precision_{name}.svg"
    )))?;
    Ok(())
}

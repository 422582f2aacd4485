//! DOP853 on the Kepler problem (e = 0.5, μ = a = 1, from periapsis) over 100 periods: final
//! position error against Kepler's equation, steps, vector-field evaluations and wall time for
//! rtol = atol from 1e−6 to 1e−15 (best of 5 runs; no observer, so no dense output is formed).
//!
//! Run: `cargo run --release --example dop853_kepler`

use hamilton_jacobi::integrate::{integrate, Dop853, Problem};
use hamilton_jacobi::nalgebra::{SVector, Vector2};
use hamilton_jacobi::systems::kepler;
use hamilton_jacobi::systems::Kepler2;
use std::f64::consts::TAU;
use std::time::Duration;

fn main() -> hamilton_jacobi::Result<()> {
    let e: f64 = 0.5;
    let kepler = Kepler2::new(1.0)?;
    let q0 = SVector::from([1.0 - e, 0.0]);
    let p0 = SVector::from([0.0, ((1.0 + e) / (1.0 - e)).sqrt()]);
    let periods = 100.0;
    let t1 = periods * TAU;
    let (r, _) = kepler::propagate(
        1.0,
        &Vector2::new(q0[0], q0[1]),
        &Vector2::new(p0[0], p0[1]),
        t1,
    )?;
    println!("Kepler e = {e}, {periods} periods, DOP853 (rtol = atol)");
    println!("| rtol | position error | steps | rejected | evaluations | time (best of 5) |");
    println!("|---|---|---|---|---|---|");
    for k in 6..=15 {
        let tol = 10f64.powi(-k);
        let method = Dop853::new(tol, tol)?;
        let problem = Problem::new(&kepler, 0.0, q0, p0, t1)?;
        let mut best = Duration::MAX;
        let mut report = None;
        for _ in 0..5 {
            let rep = integrate(&problem, &method, &mut ())?;
            best = best.min(rep.elapsed);
            report = Some(rep);
        }
        let rep = report.expect("ran");
        let err = ((rep.last.q[0] - r[0]).powi(2) + (rep.last.q[1] - r[1]).powi(2)).sqrt();
        println!(
            "| {tol:.0e} | {err:.2e} | {} | {} | {} | {:.0} µs |",
            rep.work.steps,
            rep.work.rejected,
            rep.work.gradients,
            best.as_secs_f64() * 1e6
        );
    }
    Ok(())
}

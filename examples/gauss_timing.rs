//! Cost of Gauss–Legendre steps on the planar Kepler problem (e = 0.5 from periapsis, one period):
//! wall time per step (best of several runs), Newton iterations and gradients per step, and the
//! end-state error, for s = 1..6 at two step sizes, with RK4 for scale.
//!
//! Run with `cargo run --release --example gauss_timing`.

use hamilton_jacobi::integrate::{integrate, Fixed, Gauss, OneStep, Problem, Rk4};
use hamilton_jacobi::nalgebra::Vector2;
use hamilton_jacobi::systems::{kepler, Kepler2};
use std::f64::consts::TAU;

fn time<M: OneStep<Kepler2, 2> + Copy>(label: &str, method: M, steps: usize) {
    let kepler = Kepler2::new(1.0).unwrap();
    let (q0, p0) = (Vector2::new(0.5, 0.0), Vector2::new(0.0, 3f64.sqrt()));
    let problem = Problem::new(&kepler, 0.0, q0, p0, TAU).unwrap();
    let (qe, pe) = kepler::propagate(1.0, &q0, &p0, TAU).unwrap();
    let fixed = Fixed::new(method, steps).unwrap();
    let repeats = (200_000 / steps).max(5);
    let mut best = f64::INFINITY;
    let mut last = None;
    for _ in 0..repeats {
        let run = integrate(&problem, &fixed, &mut ()).unwrap();
        best = best.min(run.elapsed.as_secs_f64());
        last = Some(run);
    }
    let run = last.unwrap();
    let err = (run.last.q - qe).amax().max((run.last.p - pe).amax());
    let n = steps as f64;
    println!(
        "{label:<8} n = {steps:5}  {:8.0} ns/step  iterations/step {:5.2}  gradients/step {:6.2}  hessians/step {:4.2}  error {err:.2e}",
        best / n * 1e9,
        run.work.newton_iterations as f64 / n,
        run.work.gradients as f64 / n,
        run.work.hessians as f64 / n,
    );
}

fn main() {
    for steps in [200, 2000] {
        time("RK4", Rk4, steps);
        time("s = 1", Gauss::<1>::new().unwrap(), steps);
        time("s = 2", Gauss::<2>::new().unwrap(), steps);
        time("s = 3", Gauss::<3>::new().unwrap(), steps);
        time("s = 4", Gauss::<4>::new().unwrap(), steps);
        time("s = 5", Gauss::<5>::new().unwrap(), steps);
        time("s = 6", Gauss::<6>::new().unwrap(), steps);
    }
}

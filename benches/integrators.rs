//! Cost per step and per evaluation of every integrator on Kepler (N = 2, e = 0.5), the
//! pendulum and (Wisdom–Holman, SABA₄, Störmer–Verlet) planar Kepler + J₂, measured side by side: 1000 steps of `Fixed` from the same state, so the figures
//! include the driver (compensated summation, observer call). The printout before timing gives the
//! gradient evaluations per step of each method; ns/evaluation = (ns/step)/(evaluations/step).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use hamilton_jacobi::integrate::{
    integrate, ExactStep, Fixed, Gauss, OneStep, Problem, Rk4, Splitting, WisdomHolman,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{NoForce, PerturbedTwoBody, J2};
use hamilton_jacobi::systems::{Kepler2, Pendulum};
use hamilton_jacobi::Hamiltonian;
use std::f64::consts::PI;
use std::hint::black_box;

const STEPS: usize = 1000;

fn per_step<S: Hamiltonian<N>, M: OneStep<S, N> + Copy, const N: usize>(
    c: &mut Criterion,
    group: &str,
    problem: &Problem<'_, S, N>,
    method: M,
) {
    let fixed = Fixed::new(method, STEPS).unwrap();
    let w = integrate(problem, &fixed, &mut ()).unwrap().work;
    let name = OneStep::<S, N>::name(&method);
    println!(
        "{group} / {name}: {:.1} gradients, {:.1} Hessians, {:.1} flows per step",
        w.gradients as f64 / STEPS as f64,
        w.hessians as f64 / STEPS as f64,
        w.flows as f64 / STEPS as f64
    );
    let mut g = c.benchmark_group(group);
    g.bench_function(BenchmarkId::from_parameter(&name), |b| {
        b.iter(|| integrate(black_box(problem), &fixed, &mut ()).unwrap())
    });
    g.finish();
}

fn bench(c: &mut Criterion) {
    let kep = Kepler2::new(1.0).unwrap();
    let (q0, p0) = (SVector::from([0.5, 0.0]), SVector::from([0.0, 3f64.sqrt()]));
    let kp = Problem::new(&kep, 0.0, q0, p0, 2.0 * PI).unwrap();
    let pen = Pendulum::new(1.0).unwrap();
    let pp = Problem::new(&pen, 0.0, SVector::from([1.0]), SVector::from([0.0]), 7.0).unwrap();
    for table in [
        Splitting::VERLET_DKD,
        Splitting::BLANES_MOAN6,
        Splitting::YOSHIDA3,
        Splitting::KAHAN_LI9,
        Splitting::KAHAN_LI17,
        Splitting::SOFRONIOU_SPALETTA35,
    ] {
        per_step(c, "kepler_1000_steps", &kp, table);
        per_step(c, "pendulum_1000_steps", &pp, table);
    }
    per_step(c, "kepler_1000_steps", &kp, Rk4);
    per_step(c, "pendulum_1000_steps", &pp, Rk4);
    per_step(c, "kepler_1000_steps", &kp, Gauss::<2>::new().unwrap());
    per_step(c, "kepler_1000_steps", &kp, Gauss::<4>::new().unwrap());
    per_step(c, "kepler_1000_steps", &kp, Gauss::<6>::new().unwrap());
    per_step(c, "kepler_1000_steps", &kp, ExactStep);
    per_step(c, "pendulum_1000_steps", &pp, ExactStep);
    // Kepler + J₂ in the equatorial plane, J₂R² = 1e−5.
    let model = J2::new(1.0, 1e-5, 1.0).unwrap();
    let j2 = PerturbedTwoBody::<_, NoForce, 2>::conservative(1.0, model).unwrap();
    let jp = Problem::new(&j2, 0.0, q0, p0, 2.0 * PI).unwrap();
    per_step(c, "kepler_j2_1000_steps", &jp, WisdomHolman::WH);
    per_step(c, "kepler_j2_1000_steps", &jp, WisdomHolman::SABA4);
    per_step(c, "kepler_j2_1000_steps", &jp, Splitting::VERLET_DKD);
}

criterion_group!(benches, bench);
criterion_main!(benches);

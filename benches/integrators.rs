//! Cost per step and per evaluation of every integrator on Kepler (N = 2, e = 0.5), the
//! pendulum and (Wisdom–Holman, SABA₄, Störmer–Verlet) planar Kepler + J₂, measured side by side: 1000 steps of `Fixed` from the same state, so the figures
//! include the driver (compensated summation, observer call). The printout before timing gives the
//! gradient evaluations per step of each method; ns/evaluation = (ns/step)/(evaluations/step).
//! A further group times whole runs on Kepler e = 0.99: DOP853 in Cartesian and in Levi-Civita
//! coordinates, and the logarithmic-Hamiltonian composition. The last one times SPEC X3's runs
//! (Kepler e = 0.9, 100 orbits, `atol = 10⁻³ rtol`) of the two Dormand–Prince pairs side by side:
//! RK45 (5(4), SciPy's control) and DOP853 at rtol 1e−6 and 1e−9; the setup prints each run's
//! evaluations and final relative energy error, so that cost is compared at known accuracy.

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use hamilton_jacobi::integrate::regularised::{fictitious_span, propagate};
use hamilton_jacobi::integrate::{
    integrate, Dop853, ExactStep, Fixed, Gauss, LeviCivita, OneStep, Problem, Rk4, Rk45, Splitting,
    TimeTransformed, WisdomHolman,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{NoForce, PerturbedTwoBody, J2};
use hamilton_jacobi::phase::State;
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
    regularised(c);
    dormand_prince_pairs(c);
}

/// Kepler e = 0.99 over 10 periods: DOP853 in Cartesian coordinates and on the Levi-Civita
/// regularised problem at the same tolerance, and the logarithmic-Hamiltonian Kahan–Li 17.
fn regularised(c: &mut Criterion) {
    let e = 0.99f64;
    let kep = Kepler2::new(1.0).unwrap();
    let start =
        State::from_arrays(0.0, [1.0 - e, 0.0], [0.0, ((1.0 + e) / (1.0 - e)).sqrt()]).unwrap();
    let t1 = 10.0 * 2.0 * PI;
    let pb = Problem::new(&kep, 0.0, start.q, start.p, t1).unwrap();
    let lc = LeviCivita::new(&kep).unwrap();
    let span = fictitious_span(&lc, &start, t1).unwrap();
    let dop = Dop853::new(1e-12, 1e-12).unwrap();
    let log_h = TimeTransformed::logarithmic(Splitting::KAHAN_LI17, 0.1).unwrap();
    let mut g = c.benchmark_group("kepler_e099_10_periods");
    g.bench_function("dop853_cartesian_1e-12", |b| {
        b.iter(|| integrate(black_box(&pb), &dop, &mut ()).unwrap())
    });
    g.bench_function("dop853_levi_civita_1e-12", |b| {
        b.iter(|| propagate(&lc, &dop, black_box(&start), &[t1], span).unwrap())
    });
    g.bench_function("log_hamiltonian_kahan_li17_ds0.1", |b| {
        b.iter(|| integrate(black_box(&pb), &log_h, &mut ()).unwrap())
    });
    g.finish();
}

/// SPEC X3: Kepler e = 0.9 from periapsis over 100 orbits, `atol = 10⁻³ rtol`: RK45 and DOP853
/// whole runs at rtol 1e−6 and 1e−9.
fn dormand_prince_pairs(c: &mut Criterion) {
    let e = 0.9f64;
    let kep = Kepler2::new(1.0).unwrap();
    let start =
        State::from_arrays(0.0, [1.0 - e, 0.0], [0.0, ((1.0 + e) / (1.0 - e)).sqrt()]).unwrap();
    let t1 = 100.0 * 2.0 * PI;
    let pb = Problem::new(&kep, 0.0, start.q, start.p, t1).unwrap();
    let e0 = kep.value(0.0, &start.q, &start.p).unwrap();
    let mut g = c.benchmark_group("kepler_e09_100_orbits");
    for rtol in [1e-6, 1e-9] {
        let rk45 = Rk45::new(rtol, 1e-3 * rtol).unwrap();
        let dop = Dop853::new(rtol, 1e-3 * rtol).unwrap();
        for (name, run) in [
            ("rk45", integrate(&pb, &rk45, &mut ()).unwrap()),
            ("dop853", integrate(&pb, &dop, &mut ()).unwrap()),
        ] {
            let e1 = kep.value(t1, &run.last.q, &run.last.p).unwrap();
            println!(
                "{name} rtol {rtol:e}: {} evaluations, {} steps, relative energy error {:.2e}",
                run.work.gradients,
                run.work.steps,
                (e1 - e0) / e0.abs()
            );
        }
        g.bench_function(format!("rk45_{rtol:.0e}"), |b| {
            b.iter(|| integrate(black_box(&pb), &rk45, &mut ()).unwrap())
        });
        g.bench_function(format!("dop853_{rtol:.0e}"), |b| {
            b.iter(|| integrate(black_box(&pb), &dop, &mut ()).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

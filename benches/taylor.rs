//! The Taylor method beside DOP853 in one run: Kepler + J₂ (`a = 2, e = 0.1, i = 0.5, R = 1,
//! J₂ = 10⁻³`, 100 periods) and the pendulum `q₀ = 1` (100 periods), at tolerances 10⁻⁹ and
//! 10⁻¹². The recording of Hamilton's equations is timed apart (`record`), the Taylor run without
//! it (`taylor`) and with it (`taylor+record`; the compiled pass of the order is kept from the
//! first run, and its compilation time printed apart); `dop853` runs with `rtol = atol = tol`. Before
//! timing, the printout gives each run's steps, final error (pendulum: against the exact flow;
//! J₂: against a Taylor run at tolerance 10⁻¹⁸, whose agreement with DOP853 at its tightest
//! tolerance is printed too) and µs per step.

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::integrate::{integrate, Dop853, Problem, Taylor, VectorFieldRecord};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{NoForce, PerturbedTwoBody, J2};
use hamilton_jacobi::phase::State;
use hamilton_jacobi::record::Jets;
use hamilton_jacobi::systems::{ExactFlow, Pendulum};
use hamilton_jacobi::Hamiltonian;
use std::f64::consts::PI;
use std::hint::black_box;

mod common;
use common::best;
use std::time::Duration;

/// `K(k)` by the arithmetic–geometric mean, `K = π / (2 agm(1, √(1 − k²)))`.
fn elliptic_k(k: f64) -> f64 {
    // Quadratic convergence: 8 steps reach rounding for k = sin ½.
    let (mut a, mut b) = (1.0, (1.0 - k * k).sqrt());
    for _ in 0..8 {
        (a, b) = ((a + b) / 2.0, (a * b).sqrt());
    }
    PI / (2.0 * a)
}

#[allow(clippy::too_many_arguments)]
fn compare<S: Hamiltonian<N>, const N: usize>(
    c: &mut Criterion,
    name: &str,
    system: &S,
    start: State<N>,
    t1: f64,
    reference: &(SVector<f64, N>, SVector<f64, N>),
) {
    let problem = Problem::new(system, start.t, start.q, start.p, t1).unwrap();
    let rec_time = best(200, || VectorFieldRecord::new(system, &start).unwrap());
    let field = VectorFieldRecord::new(system, &start).unwrap();
    println!(
        "{name}: record of Hamilton's equations {} operations, recorded in {:.1} µs",
        field.record().len(),
        rec_time.as_secs_f64() * 1e6
    );
    let err = |s: &State<N>| (s.q - reference.0).amax().max((s.p - reference.1).amax());
    for tol in [1e-9, 1e-12] {
        let taylor = Taylor::new(tol).unwrap();
        // The pass of this order compiled once (kept for the runs below), timed apart.
        let compile = Jets::new(field.record(), taylor.order())
            .unwrap()
            .compile_time();
        println!(
            "{name} tol {tol:e}: Taylor pass of order {} compiled in {compile:?}",
            taylor.order()
        );
        let dop = Dop853::new(tol, tol).unwrap();
        let rt = taylor.run_recorded(&field, &problem, &mut ()).unwrap();
        let rd = integrate(&problem, &dop, &mut ()).unwrap();
        let tt = best(5, || {
            taylor.run_recorded(&field, &problem, &mut ()).unwrap()
        });
        let td = best(5, || integrate(&problem, &dop, &mut ()).unwrap());
        println!(
            "{name} tol {tol:e}: Taylor (order {}) {} steps, error {:.2e}, {:.3} ms, {:.3} µs/step; \
             DOP853 {} steps, error {:.2e}, {:.3} ms, {:.3} µs/step",
            taylor.order(),
            rt.work.steps,
            err(&rt.last),
            tt.as_secs_f64() * 1e3,
            tt.as_secs_f64() * 1e6 / rt.work.steps as f64,
            rd.work.steps,
            err(&rd.last),
            td.as_secs_f64() * 1e3,
            td.as_secs_f64() * 1e6 / rd.work.steps as f64,
        );
        let mut g = c.benchmark_group(format!("{name}/{tol:e}"));
        g.sample_size(10).measurement_time(Duration::from_secs(2));
        g.bench_function("taylor", |b| {
            b.iter(|| {
                taylor
                    .run_recorded(&field, black_box(&problem), &mut ())
                    .unwrap()
            })
        });
        g.bench_function("taylor+record", |b| {
            b.iter(|| integrate(black_box(&problem), &taylor, &mut ()).unwrap())
        });
        g.bench_function("dop853", |b| {
            b.iter(|| integrate(black_box(&problem), &dop, &mut ()).unwrap())
        });
        g.finish();
    }
    let mut g = c.benchmark_group(name.to_string());
    g.sample_size(20).measurement_time(Duration::from_secs(1));
    g.bench_function("record", |b| {
        b.iter(|| VectorFieldRecord::new(system, black_box(&start)).unwrap())
    });
    g.finish();
}

fn bench(c: &mut Criterion) {
    // Kepler + J₂, μ = R = 1, a = 2, e = 0.1, i = 0.5, at periapsis.
    let (a, e, i): (f64, f64, f64) = (2.0, 0.1, 0.5);
    let j2 = PerturbedTwoBody::<_, NoForce, 3>::conservative(1.0, J2::new(1.0, 1e-3, 1.0).unwrap())
        .unwrap();
    let r = a * (1.0 - e);
    let v = ((1.0 + e) / r).sqrt();
    let start = State::new(
        0.0,
        SVector::from([r, 0.0, 0.0]),
        SVector::from([0.0, v * i.cos(), v * i.sin()]),
    )
    .unwrap();
    let t1 = 100.0 * 2.0 * PI * a.powf(1.5);
    let problem = Problem::new(&j2, 0.0, start.q, start.p, t1).unwrap();
    let reference = integrate(&problem, &Taylor::new(1e-18).unwrap(), &mut ())
        .unwrap()
        .last;
    let tightest = Dop853::new(Dop853::RTOL_MIN, 1e-16).unwrap();
    let check = integrate(&problem, &tightest, &mut ()).unwrap().last;
    println!(
        "Kepler + J2 reference (Taylor, tol 1e-18) against DOP853 at rtol {:e}: {:.2e}",
        Dop853::RTOL_MIN,
        (check.q - reference.q).amax()
    );
    compare(
        c,
        "kepler_j2_e0.1",
        &j2,
        start,
        t1,
        &(reference.q, reference.p),
    );

    // The pendulum q₀ = 1, p₀ = 0: period 4K(sin ½).
    let pendulum = Pendulum::new(1.0).unwrap();
    let (q0, p0) = (SVector::from([1.0]), SVector::from([0.0]));
    let t1 = 100.0 * 4.0 * elliptic_k(0.5f64.sin());
    let exact = pendulum.exact_flow(0.0, &q0, &p0, t1).unwrap();
    let start = State::new(0.0, q0, p0).unwrap();
    compare(c, "pendulum_q1", &pendulum, start, t1, &exact);
}

criterion_group!(benches, bench);
criterion_main!(benches);

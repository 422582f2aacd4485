//! The outer Solar System (Sun + Jupiter, Saturn, Uranus, Neptune; Hairer, Lubich & Wanner, GNI
//! §I.2.4) by the N-body Wisdom–Holman map in Jacobi coordinates (without and with the order-17
//! corrector) and in democratic heliocentric coordinates: energy error against cost at several
//! steps.
//!
//! A run of 10⁶ years (3.65·10⁸ days) is long for a benchmark: the printout measures the energy
//! error over 10⁵ days and the cost per step, and states the 10⁶-year cost as
//! `(cost per step) × 3.65·10⁸ / h` — an extrapolation, not a measured run. Criterion times 1000
//! steps of `propagate` (the coordinate maps and the corrector applied once at the ends).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use hamilton_jacobi::integrate::{PlanetaryWisdomHolman, Problem, WisdomHolman};
use hamilton_jacobi::systems::{outer_solar_system, PlanetaryCoordinates};
use hamilton_jacobi::Hamiltonian;
use std::hint::black_box;
use std::time::Instant;

fn methods() -> Vec<(&'static str, PlanetaryWisdomHolman)> {
    let jac = PlanetaryCoordinates::Jacobi;
    let dh = PlanetaryCoordinates::DemocraticHeliocentric;
    vec![
        (
            "WH Jacobi",
            PlanetaryWisdomHolman::new(WisdomHolman::WH, jac).unwrap(),
        ),
        (
            "WH Jacobi + corrector 17",
            PlanetaryWisdomHolman::new(WisdomHolman::WH.with_corrector(17).unwrap(), jac).unwrap(),
        ),
        (
            "WH democratic heliocentric",
            PlanetaryWisdomHolman::new(WisdomHolman::WH, dh).unwrap(),
        ),
    ]
}

fn bench(c: &mut Criterion) {
    let (sys, q, p) = outer_solar_system();
    let h0 = sys.value(0.0, &q, &p).unwrap();
    let span = 1e5;
    println!("outer Solar System, span {span:e} days; 10⁶ yr = 3.65e8 days extrapolated");
    for (name, m) in methods() {
        for h in [100.0, 50.0, 20.0, 10.0] {
            let steps = (span / h) as usize;
            let pb = Problem::new(&sys, 0.0, q, p, span).unwrap();
            let clock = Instant::now();
            let r = m.propagate(&pb, steps).unwrap();
            let per_step = clock.elapsed().as_secs_f64() / steps as f64;
            let de = ((sys.value(span, &r.last.q, &r.last.p).unwrap() - h0) / h0).abs();
            println!(
                "{name:>28}, h = {h:>5} d: |ΔE/E| = {de:.2e}, {:.2} µs/step, 10⁶ yr ≈ {:.1} s",
                per_step * 1e6,
                per_step * 3.65e8 / h
            );
        }
    }
    let mut g = c.benchmark_group("outer_solar_system_1000_steps");
    for (name, m) in methods() {
        let pb = Problem::new(&sys, 0.0, q, p, 1000.0 * 20.0).unwrap();
        g.bench_function(BenchmarkId::from_parameter(name), |b| {
            b.iter(|| m.propagate(black_box(&pb), 1000).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

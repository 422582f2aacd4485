//! Osculating elements: the conversions between a Cartesian state and the element sets
//! (classical, equinoctial, modified equinoctial, Delaunay), each way, at e = 0.1 and 0.7.
//!
//! Run with `cargo bench --bench elements`.

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::nalgebra::Vector3;
use hamilton_jacobi::systems::kepler::elements::{
    state_to_classical, state_to_delaunay, state_to_equinoctial, state_to_modified_equinoctial,
    Classical,
};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mu = 1.0;
    for e in [0.1, 0.7] {
        let el = Classical::new(2.0, e, 0.5, 0.3, 0.7, 1.1).unwrap();
        let s = el.to_state(mu).unwrap();
        let (r, v): (Vector3<f64>, Vector3<f64>) = (s.0, s.1);
        let mut g = c.benchmark_group(format!("elements e = {e}"));
        g.bench_function("state → classical", |b| {
            b.iter(|| state_to_classical(black_box(mu), black_box(&r), black_box(&v)))
        });
        g.bench_function("classical → state", |b| {
            b.iter(|| black_box(&el).to_state(black_box(mu)))
        });
        g.bench_function("state → equinoctial", |b| {
            b.iter(|| state_to_equinoctial(black_box(mu), black_box(&r), black_box(&v)))
        });
        let eq = el.to_equinoctial().unwrap();
        g.bench_function("equinoctial → state", |b| {
            b.iter(|| black_box(&eq).to_state(black_box(mu)))
        });
        g.bench_function("state → modified equinoctial", |b| {
            b.iter(|| state_to_modified_equinoctial(black_box(mu), black_box(&r), black_box(&v)))
        });
        g.bench_function("state → Delaunay", |b| {
            b.iter(|| state_to_delaunay(black_box(mu), black_box(&r), black_box(&v)))
        });
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! AD vector field against the hand-written one: Kepler (N = 2, 3) and the pendulum.
//!
//! Both sides are measured in the same run; the ratio `AD / hand` is the figure of merit.

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::{Kepler, Pendulum};
use hamilton_jacobi::Hamiltonian;
use std::hint::black_box;

fn kepler<const N: usize>(c: &mut Criterion, name: &str, q: SVector<f64, N>, p: SVector<f64, N>) {
    let k = Kepler::<N>::new(1.0).expect("μ > 0");
    let mut g = c.benchmark_group(name);
    g.bench_function("hand", |b| {
        b.iter(|| k.vector_field_hand(black_box(&q), black_box(&p)))
    });
    g.bench_function("ad", |b| {
        b.iter(|| k.vector_field_unchecked(0.0, black_box(&q), black_box(&p)))
    });
    g.finish();
}

fn bench(c: &mut Criterion) {
    kepler(
        c,
        "kepler2",
        SVector::from([0.7, 0.3]),
        SVector::from([-0.2, 1.1]),
    );
    kepler(
        c,
        "kepler3",
        SVector::from([0.7, 0.3, -0.2]),
        SVector::from([-0.2, 1.1, 0.1]),
    );
    let pend = Pendulum::new(1.0).expect("n > 0");
    let (q, p) = (SVector::from([1.1]), SVector::from([0.3]));
    let mut g = c.benchmark_group("pendulum");
    g.bench_function("hand", |b| {
        b.iter(|| pend.vector_field_hand(black_box(&q), black_box(&p)))
    });
    g.bench_function("ad", |b| {
        b.iter(|| pend.vector_field_unchecked(0.0, black_box(&q), black_box(&p)))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

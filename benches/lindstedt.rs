//! Lindstedt–Poincaré construction ([`lindstedt_pendulum`]): the cosine-polynomial recursion with
//! running error bounds, at order 16 and at the largest order, 64.

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::perturbation::lindstedt::lindstedt_pendulum;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("lindstedt");
    group.sample_size(10);
    for order in [16usize, 64] {
        group.bench_function(format!("pendulum_order{order}"), |b| {
            b.iter(|| black_box(lindstedt_pendulum(black_box(order)).unwrap().period_ratio[order]))
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! AD vector field against the hand-written one: Kepler (N = 2, 3) and the pendulum.
//!
//! Three variants are measured side by side in one run:
//! * `hand` — the hand-written Hamilton's equations (`vector_field_hand`, the oracle);
//! * `ad` — the catalogue system, a [`Separable`] `T(p) + V(q)` (two AD passes of width `N`);
//! * `ad_general` — the same `H` written as one function `H(q, p)` (one AD pass of width `2N`).
//!
//! The figure of merit is the ratio `ad / hand`.

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::{Kepler, Pendulum};
use hamilton_jacobi::{hamiltonian, Hamiltonian};
use std::hint::black_box;

hamiltonian!(KeplerGeneral2<2> |_s, _t, q, p| p.dot(p) * 0.5 - q.dot(q).sqrt().recip());
hamiltonian!(KeplerGeneral3<3> |_s, _t, q, p| p.dot(p) * 0.5 - q.dot(q).sqrt().recip());
hamiltonian!(PendulumGeneral<1> |_s, _t, q, p| p[0] * p[0] * 0.5 - (q[0].cos() - 1.0));

fn group<H: Hamiltonian<N>, const N: usize>(
    c: &mut Criterion,
    name: &str,
    hand: impl Fn(&SVector<f64, N>, &SVector<f64, N>) -> (SVector<f64, N>, SVector<f64, N>),
    ad: &impl Hamiltonian<N>,
    general: &H,
    q: SVector<f64, N>,
    p: SVector<f64, N>,
) {
    let mut g = c.benchmark_group(name);
    g.bench_function("hand", |b| b.iter(|| hand(black_box(&q), black_box(&p))));
    g.bench_function("ad", |b| {
        b.iter(|| ad.vector_field_unchecked(0.0, black_box(&q), black_box(&p)))
    });
    g.bench_function("ad_general", |b| {
        b.iter(|| general.vector_field_unchecked(0.0, black_box(&q), black_box(&p)))
    });
    g.finish();
}

fn bench(c: &mut Criterion) {
    let k2 = Kepler::<2>::new(1.0).expect("μ > 0");
    let k3 = Kepler::<3>::new(1.0).expect("μ > 0");
    let pend = Pendulum::new(1.0).expect("n > 0");
    group(
        c,
        "kepler2",
        |q, p| k2.vector_field_hand(q, p),
        &k2,
        &KeplerGeneral2,
        SVector::from([0.7, 0.3]),
        SVector::from([-0.2, 1.1]),
    );
    group(
        c,
        "kepler3",
        |q, p| k3.vector_field_hand(q, p),
        &k3,
        &KeplerGeneral3,
        SVector::from([0.7, 0.3, -0.2]),
        SVector::from([-0.2, 1.1, 0.1]),
    );
    group(
        c,
        "pendulum",
        |q, p| pend.vector_field_hand(q, p),
        &pend,
        &PendulumGeneral,
        SVector::from([1.1]),
        SVector::from([0.3]),
    );
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! AD vector field against the hand-written one: Kepler (N = 2, 3), Kepler + J₂ (N = 2, 3) and
//! the pendulum.
//!
//! Three variants are measured side by side in one run:
//! * `hand` — the hand-written Hamilton's equations (`vector_field_hand`, the oracle);
//! * `ad` — the catalogue system, a [`Separable`] `T(p) + V(q)` (two AD passes of width `N`);
//! * `ad_general` — the same `H` written as one function `H(q, p)` (one AD pass of width `2N`).
//!
//! The figure of merit is the ratio `ad / hand`.

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{NoForce, PerturbedTwoBody, J2};
use hamilton_jacobi::systems::{Kepler, Pendulum};
use hamilton_jacobi::{hamiltonian, Hamiltonian};
use std::hint::black_box;

hamiltonian!(KeplerGeneral2<2> |_s, _t, q, p| p.dot(p) * 0.5 - q.dot(q).sqrt().recip());
hamiltonian!(KeplerGeneral3<3> |_s, _t, q, p| p.dot(p) * 0.5 - q.dot(q).sqrt().recip());
hamiltonian!(PendulumGeneral<1> |_s, _t, q, p| p[0] * p[0] * 0.5 - (q[0].cos() - 1.0));
// Kepler + J₂ with μ = R = 1: H = |p|²/2 − 1/r + (J₂/2)(3z²/r² − 1)/r³ (z = 0 in the plane).
hamiltonian!(J2General2<2> { j2: f64 } |s, _t, q, p| {
    let r2 = q.dot(q);
    let r = r2.sqrt();
    p.dot(p) * 0.5 - r.recip() - (r2 * r).recip() * (0.5 * s.j2)
});
hamiltonian!(J2General3<3> { j2: f64 } |s, _t, q, p| {
    let r2 = q.dot(q);
    let r = r2.sqrt();
    p.dot(p) * 0.5 - r.recip() + (q[2] * q[2] / r2 * 3.0 - 1.0) / (r2 * r) * (0.5 * s.j2)
});

/// Hand-written Kepler + J₂ equations (μ = R = 1; Vallado 2013 eq. 8-30 for the J₂ part):
/// `ṗ = −q/r³ − (3J₂/(2r⁵)) (x(1 − 5z²/r²), y(1 − 5z²/r²), z(3 − 5z²/r²))`.
fn kepler_j2_hand<const N: usize>(
    j2: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> (SVector<f64, N>, SVector<f64, N>) {
    let r2 = q.dot(q);
    let r3 = r2 * r2.sqrt();
    let z2 = if N == 3 { q[2] * q[2] / r2 } else { 0.0 };
    let c = 1.5 * j2 / (r3 * r2);
    let mut pd = q * (-1.0 / r3 - c * (1.0 - 5.0 * z2));
    if N == 3 {
        pd[2] -= c * q[2] * 2.0;
    }
    (*p, pd)
}

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
    let j2 = 1e-3;
    let model = J2::new(1.0, j2, 1.0).expect("μ, R > 0");
    let kj2_2 = PerturbedTwoBody::<_, NoForce, 2>::conservative(1.0, model).expect("μ > 0");
    let kj2_3 = PerturbedTwoBody::<_, NoForce, 3>::conservative(1.0, model).expect("μ > 0");
    group(
        c,
        "kepler_j2_2",
        |q, p| kepler_j2_hand(j2, q, p),
        &kj2_2,
        &J2General2 { j2 },
        SVector::from([0.7, 0.3]),
        SVector::from([-0.2, 1.1]),
    );
    group(
        c,
        "kepler_j2_3",
        |q, p| kepler_j2_hand(j2, q, p),
        &kj2_3,
        &J2General3 { j2 },
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

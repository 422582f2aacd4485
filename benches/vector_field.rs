//! AD vector field against the hand-written one: Kepler (N = 2, 3), Kepler + J₂ (N = 2, 3),
//! Hénon–Heiles and the pendulum; and the AD Hessian of `H` (the Jacobian of the vector field is
//! `J` times it) against the hand-written Hessian for Kepler (N = 2, 3) and Hénon–Heiles.
//!
//! Three variants are measured side by side in one run:
//! * `hand` — the hand-written Hamilton's equations (`vector_field_hand`, the oracle);
//! * `ad` — the catalogue system, a [`Separable`] `T(p) + V(q)` (two AD passes of width `N`);
//! * `ad_general` — the same `H` written as one function `H(q, p)` (one AD pass of width `2N`).
//!
//! The figure of merit is the ratio `ad / hand`. The `hessian_*` groups compare
//! [`Hamiltonian::hessian`] with the closed forms `∂²H/∂q² = μ(I/r³ − 3qqᵀ/r⁵)` (Kepler) and
//! `[[1 + 2y, 2x], [2x, 1 − 2y]]` (Hénon–Heiles), `∂²H/∂p² = I`, checked equal to `1e-13` before
//! timing.

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::nalgebra::{SMatrix, SVector};
use hamilton_jacobi::perturbation::forces::{NoForce, PerturbedTwoBody, J2};
use hamilton_jacobi::phase::PhaseMatrix;
use hamilton_jacobi::systems::{HenonHeiles, Kepler, Pendulum};
use hamilton_jacobi::{hamiltonian, Hamiltonian};
use std::hint::black_box;

hamiltonian!(KeplerGeneral2<2> |_s, _t, q, p| p.dot(p) * 0.5 - q.dot(q).sqrt().recip());
hamiltonian!(KeplerGeneral3<3> |_s, _t, q, p| p.dot(p) * 0.5 - q.dot(q).sqrt().recip());
hamiltonian!(HenonHeilesGeneral<2> |_s, _t, q, p| {
    let (x, y) = (q[0], q[1]);
    p.dot(p) * 0.5 + (x * x + y * y) * 0.5 + x * x * y - y * y * y * (1.0 / 3.0)
});
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

/// Hand-written Hénon–Heiles equations: `q̇ = p`, `ṗ = −(x + 2xy, y + x² − y²)`.
fn henon_heiles_hand(
    q: &SVector<f64, 2>,
    p: &SVector<f64, 2>,
) -> (SVector<f64, 2>, SVector<f64, 2>) {
    let (x, y) = (q[0], q[1]);
    (
        *p,
        SVector::from([-(x + 2.0 * x * y), -(y + x * x - y * y)]),
    )
}

/// A separable Hessian with `∂²H/∂p² = I` and the given `∂²H/∂q²`.
fn separable_hessian<const N: usize>(qq: SMatrix<f64, N, N>) -> PhaseMatrix<N> {
    PhaseMatrix {
        qq,
        qp: SMatrix::zeros(),
        pq: SMatrix::zeros(),
        pp: SMatrix::identity(),
    }
}

/// Kepler's Hessian (μ = 1): `∂²H/∂q² = I/r³ − 3qqᵀ/r⁵`.
fn kepler_hessian_hand<const N: usize>(q: &SVector<f64, N>) -> PhaseMatrix<N> {
    let r2 = q.dot(q);
    let r3 = r2 * r2.sqrt();
    separable_hessian(SMatrix::identity() / r3 - q * q.transpose() * (3.0 / (r3 * r2)))
}

/// Hénon–Heiles' Hessian: `∂²H/∂q² = [[1 + 2y, 2x], [2x, 1 − 2y]]`.
fn henon_heiles_hessian_hand(q: &SVector<f64, 2>) -> PhaseMatrix<2> {
    let (x, y) = (q[0], q[1]);
    separable_hessian(SMatrix::<f64, 2, 2>::new(
        1.0 + 2.0 * y,
        2.0 * x,
        2.0 * x,
        1.0 - 2.0 * y,
    ))
}

fn hessian_group<const N: usize>(
    c: &mut Criterion,
    name: &str,
    hand: impl Fn(&SVector<f64, N>) -> PhaseMatrix<N>,
    ad: &impl Hamiltonian<N>,
    q: SVector<f64, N>,
    p: SVector<f64, N>,
) {
    let h = ad.hessian(0.0, &q, &p).expect("finite state");
    let defect = h.sub(&hand(&q)).max_abs();
    assert!(
        defect <= 1e-13,
        "{name}: AD and hand Hessians differ by {defect:e}"
    );
    let mut g = c.benchmark_group(name);
    g.bench_function("hand", |b| b.iter(|| hand(black_box(&q))));
    g.bench_function("ad", |b| {
        b.iter(|| ad.hessian(0.0, black_box(&q), black_box(&p)))
    });
    g.finish();
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
        "henon_heiles",
        henon_heiles_hand,
        &HenonHeiles,
        &HenonHeilesGeneral,
        SVector::from([0.1, -0.2]),
        SVector::from([0.3, 0.05]),
    );
    hessian_group(
        c,
        "hessian_kepler2",
        kepler_hessian_hand,
        &k2,
        SVector::from([0.7, 0.3]),
        SVector::from([-0.2, 1.1]),
    );
    hessian_group(
        c,
        "hessian_kepler3",
        kepler_hessian_hand,
        &k3,
        SVector::from([0.7, 0.3, -0.2]),
        SVector::from([-0.2, 1.1, 0.1]),
    );
    hessian_group(
        c,
        "hessian_henon_heiles",
        henon_heiles_hessian_hand,
        &HenonHeiles,
        SVector::from([0.1, -0.2]),
        SVector::from([0.3, 0.05]),
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

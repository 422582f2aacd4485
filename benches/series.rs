//! Truncated power series at n = 4 variables, total degree K = 10 (1001 coefficients), dense
//! operands with every coefficient non-zero, against the pure-Rust DACE (`dace-rs`) in the same
//! run:
//! * `mul/kernel` — the truncated product on coefficient slices ([`Monomials::mul`]);
//! * `mul/series` — `a * b` on [`Series`] handles inside a scope (kernel + store);
//! * `mul/dace` — `Da * Da` (operand clones made outside the timed region);
//! * `sin/series`, `sin/dace` — the sine of a dense series (K products by Horner's rule);
//! * `expand/henon_heiles_k16` — the Taylor expansion of the Hénon–Heiles Hamiltonian to degree
//!   16 about a phase point.
//!
//! The figure of merit is `mul/series ÷ mul/dace` (≤ 1: no slower than DACE).

use criterion::{criterion_group, criterion_main, BatchSize, Criterion};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::series::{scope_with, Monomials, Polynomial, Series};
use hamilton_jacobi::{hamiltonian, DualNum, Hamiltonian};
use std::hint::black_box;
use std::sync::Arc;
use std::time::{Duration, Instant};

const N: usize = 4;
const K: usize = 10;

hamiltonian!(HenonHeiles<2> |_s, _t, q, p|
    kinetic = p.dot(p) * 0.5,
    potential = q.dot(q) * 0.5 + q[0] * q[0] * q[1] - q[1] * q[1] * q[1] / 3.0);

/// Deterministic dense coefficients in [−1, 1), scaled by 1/(1 + degree).
fn dense(table: &Monomials, seed: u64) -> Vec<f64> {
    let mut s = seed;
    (0..table.len())
        .map(|i| {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (((s >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0)
                / (1 + table.degree_of(i).unwrap_or(0)) as f64
        })
        .collect()
}

fn to_dace(table: &Monomials, c: &[f64]) -> dace_rs::Da {
    let mut d = dace_rs::Da::new();
    for (i, &ci) in c.iter().enumerate() {
        let e: Vec<u32> = table
            .exponents(i)
            .unwrap_or(&[])
            .iter()
            .map(|&x| x as u32)
            .collect();
        d.set_coefficient(&e, ci);
    }
    d
}

/// Time `iters` evaluations of `op(a, b)` on series handles, a fresh scope per 256 of them.
fn series_loop(
    table: &Arc<Monomials>,
    a: &Polynomial,
    b: &Polynomial,
    iters: u64,
    op: impl Fn(Series, Series) -> Series,
) -> Duration {
    let mut total = Duration::ZERO;
    let mut left = iters;
    while left > 0 {
        let chunk = left.min(256);
        left -= chunk;
        total += scope_with(table.clone(), |s| {
            let (x, y) = (s.lift(a).unwrap(), s.lift(b).unwrap());
            let t0 = Instant::now();
            for _ in 0..chunk {
                black_box(op(black_box(x), black_box(y)));
            }
            t0.elapsed()
        })
        .unwrap();
    }
    total
}

fn bench(c: &mut Criterion) {
    let table = Arc::new(Monomials::new(N, K).unwrap());
    let (ca, cb) = (dense(&table, 1), dense(&table, 2));
    let mut pa = Polynomial::zero(N, K).unwrap();
    pa.coefficients_mut().copy_from_slice(&ca);
    let mut pb = Polynomial::zero(N, K).unwrap();
    pb.coefficients_mut().copy_from_slice(&cb);
    dace_rs::init(K as u32, N as u32).unwrap();
    let (da, db) = (to_dace(&table, &ca), to_dace(&table, &cb));

    let mut g = c.benchmark_group("mul");
    let (mut out, mut scratch) = (vec![0.0; table.len()], vec![0.0; table.len()]);
    g.bench_function("kernel", |bch| {
        bch.iter(|| table.mul(black_box(&ca), black_box(&cb), &mut out, &mut scratch))
    });
    g.bench_function("series", |bch| {
        bch.iter_custom(|iters| series_loop(&table, &pa, &pb, iters, |x, y| x * y))
    });
    g.bench_function("dace", |bch| {
        bch.iter_batched(
            || (da.clone(), db.clone()),
            |(x, y)| x * y,
            BatchSize::SmallInput,
        )
    });
    g.finish();

    let mut g = c.benchmark_group("sin");
    g.bench_function("series", |bch| {
        bch.iter_custom(|iters| series_loop(&table, &pa, &pb, iters, |x, _| x.sin()))
    });
    g.bench_function("dace", |bch| bch.iter(|| dace_rs::sin(black_box(&da))));
    g.finish();

    let mut g = c.benchmark_group("expand");
    let (q0, p0) = (SVector::from([0.1, -0.05]), SVector::from([0.2, 0.1]));
    g.bench_function("henon_heiles_k16", |bch| {
        bch.iter(|| HenonHeiles.taylor_expansion(0.0, black_box(&q0), black_box(&p0), 16))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! The vector field of a system defined by an expression against the Rust-written one, in one
//! run: Hénon–Heiles (`systems::HenonHeiles`, a `Separable`) and Kepler + J₂ in Cartesian form
//! (`PerturbedTwoBody<J2>`, N = 3).
//!
//! Variants per group:
//! * `rust` — the catalogue system's `vector_field_unchecked` (forward-mode AD);
//! * `expression` — [`ExpressionHamiltonian`] as users get it: the register program of the record
//!   of Hamilton's equations `(∂H/∂p, −∂H/∂q)` compiled to native code at construction (feature
//!   `jit`, Cranelift);
//! * `expression_interpreted` — the same program run by the interpreter (its slots on the
//!   stack), [`ExpressionHamiltonian::interpreted`];
//! * `expression_split`, `expression_split_interpreted` — the split form
//!   [`ExpressionSeparable`], which the splitting methods use: the programs of `(T, ∂T/∂p)` and of
//!   `(V, ∂V/∂q)`, native and interpreted.
//!
//! The figure of merit is `expression / rust` (goal ≤ 3). Measured (load 9–10 during the run):
//! Hénon–Heiles rust 6.79 ns, expression 24.1 ns (3.6×), split 32.3 ns (4.7×); Kepler + J₂
//! rust 35.7 ns, expression 35.8 ns (1.00×), split 43.7 ns (1.22×). Instructions per call
//! (callgrind, `examples/expression_cost.rs`, load-independent): Hénon–Heiles 39 (rust) vs 55
//! (expression), Kepler + J₂ 121 vs 87. The group `construction` times the
//! one-off cost of each system: `new` (parse, record `H`, its gradient and Hamilton's
//! equations, compile the last two to native code) and `separable` (split, record and compile
//! the drift and the kick).

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::expression::ExpressionHamiltonian;
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{PerturbedTwoBody, J2};
use hamilton_jacobi::systems::HenonHeiles;
use hamilton_jacobi::Hamiltonian;
use std::hint::black_box;

fn group<const N: usize>(
    c: &mut Criterion,
    name: &str,
    rust: &impl Hamiltonian<N>,
    expression: &ExpressionHamiltonian<N>,
    q: SVector<f64, N>,
    p: SVector<f64, N>,
) {
    let split = expression.separable().expect("separable");
    let (interpreted, split_interpreted) = (expression.interpreted(), split.interpreted());
    let mut g = c.benchmark_group(name);
    g.bench_function("rust", |b| {
        b.iter(|| rust.vector_field_unchecked(0.0, black_box(&q), black_box(&p)))
    });
    g.bench_function("expression", |b| {
        b.iter(|| expression.vector_field_unchecked(0.0, black_box(&q), black_box(&p)))
    });
    g.bench_function("expression_interpreted", |b| {
        b.iter(|| interpreted.vector_field_unchecked(0.0, black_box(&q), black_box(&p)))
    });
    g.bench_function("expression_split", |b| {
        b.iter(|| split.vector_field_unchecked(0.0, black_box(&q), black_box(&p)))
    });
    g.bench_function("expression_split_interpreted", |b| {
        b.iter(|| split_interpreted.vector_field_unchecked(0.0, black_box(&q), black_box(&p)))
    });
    g.finish();
}

/// The one-off cost of constructing the system `new()` and its split form.
fn construction<const N: usize>(
    c: &mut Criterion,
    name: &str,
    new: impl Fn() -> ExpressionHamiltonian<N>,
) {
    let h = new();
    let mut g = c.benchmark_group(format!("construction_{name}"));
    g.sample_size(20);
    g.bench_function("new", |b| b.iter(&new));
    g.bench_function("separable", |b| b.iter(|| h.separable()));
    g.finish();
}

const HH: &str = "(p_x^2 + p_y^2)/2 + (x^2 + y^2)/2 + x^2*y - y^3/3";
const J2_3: &str = "(p_x^2 + p_y^2 + p_z^2)/2 - mu/sqrt(x^2 + y^2 + z^2) \
    + mu*J2*R^2/2 * (3*z^2/(x^2 + y^2 + z^2) - 1)/sqrt(x^2 + y^2 + z^2)^3";

fn bench(c: &mut Criterion) {
    let hh_new =
        || ExpressionHamiltonian::<2>::new(HH, &["x", "y"], None, &[]).expect("Hénon–Heiles");
    let hh = hh_new();
    assert!(hh.is_native() || !cfg!(feature = "jit"));
    group(
        c,
        "henon_heiles",
        &HenonHeiles,
        &hh,
        SVector::from([0.1, -0.2]),
        SVector::from([0.3, 0.25]),
    );
    let rust = PerturbedTwoBody::conservative(1.0, J2::new(1.0, 1.08e-3, 0.9).expect("J2"))
        .expect("μ > 0");
    let j2_new = || {
        ExpressionHamiltonian::<3>::new(
            J2_3,
            &["x", "y", "z"],
            None,
            &[("mu", 1.0), ("J2", 1.08e-3), ("R", 0.9)],
        )
        .expect("Kepler + J2")
    };
    let j2 = j2_new();
    group(
        c,
        "kepler_j2_3",
        &rust,
        &j2,
        SVector::from([0.7, 0.3, -0.2]),
        SVector::from([-0.2, 1.1, 0.1]),
    );
    construction(c, "henon_heiles", hh_new);
    construction(c, "kepler_j2_3", j2_new);
}

criterion_group!(benches, bench);
criterion_main!(benches);

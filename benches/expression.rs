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
//!   `(V, ∂V/∂q)`, native and interpreted;
//! * `rust_extern_c_pointer` (Hénon–Heiles) — the field written in Rust with the signature of
//!   the native code, called through a function pointer: the floor of any field not inlined
//!   into its caller; `rust_extern_c_pointer_scalar_stores` the same writing each component by
//!   its own 8-byte store, which the caller's 16-byte reads cannot be forwarded from.
//!
//! The figure of merit is `expression / rust` (goal ≤ 3). Measured (load 14–15 during the run):
//! Hénon–Heiles rust 7.10 ns, expression 8.93 ns (1.26×; 1.48× in a second run), split 14.4 ns
//! (second run), `rust_extern_c_pointer` 8.94 ns, with scalar stores 24.6 ns; Kepler + J₂ rust
//! 33.9 ns, expression 31.7 ns (0.94×), split 34.4 ns (1.01×). Before the native code paired its
//! stores (load 11): Hénon–Heiles 8.35 vs 26.0 ns (3.1×). Instructions per call (callgrind,
//! `examples/expression_cost.rs`, load-independent): Hénon–Heiles 39 (rust) vs 60
//! (expression), Kepler + J₂ 121 vs 92. The group `construction` times the
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

/// The signature of the native code of an expression system's vector field (`record::jit`,
/// `Layout::Phase`): `(t, q, p) → (q̇, ṗ)` through pointers to the state vectors.
type PhaseFn = unsafe extern "C" fn(t: f64, q: *const f64, p: *const f64, a: *mut f64, b: *mut f64);

/// Hénon–Heiles' vector field written by hand, `q̇ = p`, `ṗ = −(x + 2xy, y + x² − y²)`, with
/// the signature of the native code, each result vector written by one 16-byte store: the floor
/// of any vector field that is not inlined into its caller (variant `rust_extern_c_pointer`).
#[inline(never)]
unsafe extern "C" fn henon_heiles_extern_c(
    _t: f64,
    q: *const f64,
    p: *const f64,
    a: *mut f64,
    b: *mut f64,
) {
    // SAFETY: the caller passes pointers to vectors of two `f64`s each.
    unsafe {
        let (x, y) = (*q, *q.add(1));
        let (px, py) = (*p, *p.add(1));
        a.cast::<[f64; 2]>().write_unaligned([px, py]);
        b.cast::<[f64; 2]>()
            .write_unaligned([-(x + 2.0 * x * y), -(y + x * x - y * y)]);
    }
}

/// [`henon_heiles_extern_c`] with each component written by its own 8-byte store (volatile, so
/// that the compiler does not merge them), as the native code wrote them before its paired
/// stores (variant `rust_extern_c_pointer_scalar_stores`): the caller's 16-byte reads of the
/// results then wait for the stores to reach the cache instead of being forwarded from them.
#[inline(never)]
unsafe extern "C" fn henon_heiles_extern_c_scalar_stores(
    _t: f64,
    q: *const f64,
    p: *const f64,
    a: *mut f64,
    b: *mut f64,
) {
    // SAFETY: the caller passes pointers to vectors of two `f64`s each.
    unsafe {
        let (x, y) = (*q, *q.add(1));
        let (px, py) = (*p, *p.add(1));
        a.write_volatile(px);
        a.add(1).write_volatile(py);
        b.write_volatile(-(x + 2.0 * x * y));
        b.add(1).write_volatile(-(y + x * x - y * y));
    }
}

/// The field through the function pointer `f`, called as the expression systems call their
/// native code (zeroed result vectors written in place).
#[inline(always)]
fn call_phase(
    f: PhaseFn,
    q: &SVector<f64, 2>,
    p: &SVector<f64, 2>,
) -> (SVector<f64, 2>, SVector<f64, 2>) {
    let (mut a, mut b) = (SVector::<f64, 2>::zeros(), SVector::<f64, 2>::zeros());
    // SAFETY: `f` reads two `f64`s at `q` and at `p` and writes two at `a` and at `b`.
    unsafe { f(0.0, q.as_ptr(), p.as_ptr(), a.as_mut_ptr(), b.as_mut_ptr()) };
    (a, b)
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
    {
        let (q, p) = (SVector::from([0.1, -0.2]), SVector::from([0.3, 0.25]));
        let mut g = c.benchmark_group("henon_heiles");
        for (name, f) in [
            ("rust_extern_c_pointer", henon_heiles_extern_c as PhaseFn),
            (
                "rust_extern_c_pointer_scalar_stores",
                henon_heiles_extern_c_scalar_stores as PhaseFn,
            ),
        ] {
            let (rust, floor) = (
                HenonHeiles.vector_field_unchecked(0.0, &q, &p),
                call_phase(f, &q, &p),
            );
            assert!((rust.0 - floor.0).norm() + (rust.1 - floor.1).norm() <= 8.0 * f64::EPSILON);
            g.bench_function(name, |b| {
                b.iter(|| call_phase(black_box(f), black_box(&q), black_box(&p)))
            });
        }
        g.finish();
    }
    construction(c, "henon_heiles", hh_new);
    construction(c, "kepler_j2_3", j2_new);
}

criterion_group!(benches, bench);
criterion_main!(benches);

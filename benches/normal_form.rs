//! The 1:1 resonant (Gustavson) normal form of the Hénon–Heiles Hamiltonian to degree 16 and 24
//! (construction of `K` and the Lie generators; the coordinate series are built on first use).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use hamilton_jacobi::nalgebra::Vector2;
use hamilton_jacobi::perturbation::birkhoff::{normal_form, NormalFormKind};
use hamilton_jacobi::stability::hamiltonian_equilibrium;
use hamilton_jacobi::systems::HenonHeiles;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let eq =
        hamiltonian_equilibrium(&HenonHeiles, 0.0, &Vector2::zeros(), &Vector2::zeros()).unwrap();
    // Storage: `H`, `K` and the `K − 2` generators, each a dense coefficient vector of
    // `C(K + 4, 4)` complex numbers (16 bytes), and the process's peak resident set.
    let build = |k: usize| {
        normal_form(
            &HenonHeiles,
            0.0,
            &eq,
            k,
            NormalFormKind::Resonant(vec![vec![1, -1]]),
        )
        .unwrap()
    };
    for degree in [16usize, 24] {
        let nf = build(degree);
        let monomials = nf.normal_form().coefficients().len();
        let polynomials = nf.generators().len() + 2;
        let peak = std::fs::read_to_string("/proc/self/status")
            .ok()
            .and_then(|s| {
                s.lines()
                    .find(|l| l.starts_with("VmHWM"))
                    .map(|l| l.split_whitespace().skip(1).collect::<Vec<_>>().join(" "))
            })
            .unwrap_or_else(|| "n/a".into());
        println!(
            "degree {degree}: {monomials} monomials × {polynomials} polynomials × 16 B = {:.2} MB; \
             peak resident set {peak}",
            (monomials * polynomials * 16) as f64 / 1e6
        );
    }
    let mut g = c.benchmark_group("normal_form_henon_heiles");
    g.sample_size(10);
    for degree in [16usize, 24] {
        g.bench_with_input(BenchmarkId::from_parameter(degree), &degree, |b, &k| {
            b.iter(|| black_box(build(k)))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

//! Cost of one evaluation of the Brouwer–Lyddane `J₂` theory: the osculating Cartesian state at
//! a time `t` (mean elements at `t`, the periodic terms with one Kepler solve, the state with a
//! second), on the problem of the brief (`a = 2`, `i = 0.5`, `R = μ = 1`, `J₂ = 10⁻³`) for
//! `e = 0.1` and `e = 0.7`; and the construction from an osculating state (osculating → mean
//! iteration and the energy-fixed `L''`).

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use hamilton_jacobi::perturbation::brouwer::BrouwerLyddane;
use hamilton_jacobi::perturbation::forces::J2;
use hamilton_jacobi::systems::kepler::elements::Classical;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("j2_theory");
    for e in [0.1, 0.7] {
        let el = Classical::new(2.0, e, 0.5, 0.3, 0.7, 0.2).unwrap();
        let model = J2::new(1.0, 1e-3, 1.0).unwrap();
        let (q0, p0) = el.to_state(1.0).unwrap();
        let theory = BrouwerLyddane::from_state(&model, 0.0, &q0, &p0).unwrap();
        // 64 times spread over 100 orbits, so that the Kepler solves see every anomaly.
        let span = 100.0 * std::f64::consts::TAU * 8f64.sqrt();
        let times: Vec<f64> = (0..64).map(|k| span * (k as f64 + 0.37) / 64.0).collect();
        g.bench_function(BenchmarkId::new("state_per_64_evaluations", e), |b| {
            b.iter(|| {
                let mut s = 0.0;
                for &t in &times {
                    s += theory.state(black_box(t)).unwrap().0[0];
                }
                s
            })
        });
        g.bench_function(BenchmarkId::new("from_state", e), |b| {
            b.iter(|| BrouwerLyddane::from_state(&model, 0.0, black_box(&q0), &p0).unwrap())
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

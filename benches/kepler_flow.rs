//! The exact Kepler flow (`kepler::drift`, universal variables with the ill-conditioned
//! quantities in double-double arithmetic): one drift on reals over a short arc (`dt = 0.05`)
//! and over 100 periods and a radian, and one drift in `Dual64` (a derivative carried), from
//! periapsis at `e = 0.5` and `0.99` (`μ = 1`, planar).
//!
//! Run with `cargo bench --bench kepler_flow`.

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::nalgebra::Vector2;
use hamilton_jacobi::num_dual::Dual64;
use hamilton_jacobi::systems::kepler::drift;
use std::f64::consts::PI;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    for e in [0.5f64, 0.99] {
        let q = Vector2::new(1.0 - e, 0.0);
        let p = Vector2::new(0.0, ((1.0 + e) / (1.0 - e)).sqrt());
        let mut g = c.benchmark_group(format!("Kepler drift e = {e}"));
        for (label, dt) in [("dt = 0.05", 0.05), ("100 periods + 1", 200.0 * PI + 1.0)] {
            g.bench_function(label, |b| {
                b.iter(|| drift(black_box(1.0), black_box(&q), black_box(&p), black_box(dt)))
            });
        }
        let (qd, pd) = (q.map(Dual64::from), p.map(|x| Dual64::from(x).derivative()));
        g.bench_function("Dual64, dt = 0.05", |b| {
            b.iter(|| {
                drift(
                    black_box(1.0),
                    black_box(&qd),
                    black_box(&pd),
                    Dual64::from(0.05),
                )
            })
        });
        g.finish();
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);

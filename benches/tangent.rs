//! Tangent maps and chaos indicators on Hénon–Heiles.
//!
//! * `tangent/verlet-ad`: the tangent map of 1000 Störmer–Verlet steps (`h = 0.05`, `t = 50`)
//!   along the quasi-periodic orbit QP1 (`E = 1/12`, section `x = 0` at `(y, p_y) = (0, 0.25)`),
//!   by AD through the steps; `tangent/dop853-variational`: the variational equations integrated
//!   by DOP853 at the loosest tolerance (of 10^(−k/2), k = 4 … 28) whose tangent map is at least
//!   as accurate as Verlet's. Both errors are measured against the variational equations at
//!   rtol = 1e-14; the printout gives them, the tolerance chosen, and the ratio of the mean wall
//!   times.
//! * `megno/map-16x16`: a 16 × 16 MEGNO map of the section at `E = 1/8` to `t = 100` (Verlet,
//!   `h = 0.1`) on every core.
//! * With the environment variable `HJ_BENCH_MEGNO_512` set: the 512 × 512 MEGNO map to
//!   `t = 10³` (Verlet, `h = 0.1`, the scene `megno-map` at full size), run once and timed, with
//!   the number of threads (`cargo bench --bench tangent -- megno/map-512`).

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::chaos::chaos_map;
use hamilton_jacobi::integrate::{
    variational_tangent_map, Dop853, Fixed, Problem, Splitting, TangentMethod,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::scene::megno::henon_heiles_megno_map;
use hamilton_jacobi::systems::HenonHeiles;
use std::hint::black_box;

mod common;
use common::best;

fn bench(c: &mut Criterion) {
    let start = HenonHeiles::section_start(1.0 / 12.0, 0.0, 0.25).unwrap();
    let problem = Problem::new(&HenonHeiles, 0.0, start.q, start.p, 50.0).unwrap();
    let reference =
        variational_tangent_map::<_, 2, 10>(&problem, &Dop853::new(1e-14, 1e-14).unwrap()).unwrap();
    let verlet = Fixed::new(Splitting::VERLET_KDK, 1000).unwrap();
    let ad = verlet.tangent_map(&problem).unwrap();
    let e_verlet = ad.jacobian.sub(&reference.jacobian).max_abs();
    let mut chosen = None;
    for k in 4..=28 {
        let tol = 10f64.powf(-(k as f64) / 2.0);
        let m = Dop853::new(tol, tol).unwrap();
        let v = variational_tangent_map::<_, 2, 10>(&problem, &m).unwrap();
        let e = v.jacobian.sub(&reference.jacobian).max_abs();
        if e <= e_verlet {
            chosen = Some((m, e, v.work.steps));
            break;
        }
    }
    let (dop, e_dop, steps) = chosen.expect("a tolerance reaches Verlet's error");
    let t_ad = best(20, || verlet.tangent_map(&problem).unwrap());
    let t_var = best(20, || {
        variational_tangent_map::<_, 2, 10>(&problem, &dop).unwrap()
    });
    println!(
        "tangent map, QP1, t = 50: Verlet AD (1000 steps) error {e_verlet:.3e} in {:.3} ms; \
         DOP853 variational (rtol = atol = {:.1e}, {steps} steps) error {e_dop:.3e} in {:.3} ms; \
         ratio DOP853/Verlet = {:.2}",
        t_ad.as_secs_f64() * 1e3,
        dop.rtol,
        t_var.as_secs_f64() * 1e3,
        t_var.as_secs_f64() / t_ad.as_secs_f64()
    );
    let mut g = c.benchmark_group("tangent");
    g.bench_function("verlet-ad", |b| {
        b.iter(|| verlet.tangent_map(black_box(&problem)).unwrap())
    });
    g.bench_function("dop853-variational", |b| {
        b.iter(|| variational_tangent_map::<_, 2, 10>(black_box(&problem), &dop).unwrap())
    });
    g.finish();

    let mut starts = Vec::new();
    for i in 0..16 {
        for j in 0..16 {
            let (y, py) = (
                -0.45 + 1.15 * (i as f64 + 0.5) / 16.0,
                -0.52 + 1.04 * (j as f64 + 0.5) / 16.0,
            );
            if let Ok(s) = HenonHeiles::section_start(0.125, y, py) {
                starts.push(s);
            }
        }
    }
    let method = Fixed::new(Splitting::VERLET_KDK, 1000).unwrap();
    let d = (SVector::from([1.0, 0.5]), SVector::from([0.3, -0.7]));
    let mut g = c.benchmark_group("megno");
    g.sample_size(10);
    g.bench_function("map-16x16", |b| {
        b.iter(|| chaos_map(&HenonHeiles, black_box(&starts), 100.0, &method, &d).unwrap())
    });
    g.finish();

    if std::env::var_os("HJ_BENCH_MEGNO_512").is_some() {
        let threads = rayon::current_num_threads();
        let clock = std::time::Instant::now();
        let map = henon_heiles_megno_map(0.125, 512, 1000.0, 0.1, 8.0).unwrap();
        let elapsed = clock.elapsed().as_secs_f64();
        println!(
            "megno/map-512x512: {} orbits × {} Verlet steps to t = 10³ in {elapsed:.1} s on \
             {threads} threads ({:.0} ns per orbit step per thread); ⟨Y⟩ ≤ 2.5 in {} cells, \
             > 2.5 in {}",
            map.orbits,
            map.steps,
            elapsed * threads as f64 / (map.orbits as f64 * map.steps as f64) * 1e9,
            map.regular,
            map.chaotic
        );
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);

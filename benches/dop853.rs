//! DOP853 per step: the crate's [`Dop853`] against the `ode_solvers` crate's `Dop853`, the same
//! Dormand–Prince 8(5,3) pair of Hairer's Fortran code, on the same hand-coded vector field.
//!
//! The problem: the planar Kepler problem, `μ = 1`, `a = 1`, `e = 0.5`, from periapsis
//! (`q = (1 − e, 0)`, `p = (0, √((1 + e)/(1 − e)))`), over 100 periods `t₁ = 200π`, with
//! `rtol = atol ∈ {1e−6, 1e−10, 1e−14}`. Both sides evaluate
//!
//! ```math
//! \dot q = p,\qquad \dot p = -\frac{q}{r^3},\qquad r^3 = (q\cdot q)\sqrt{q\cdot q},
//! ```
//!
//! written by hand with the same operations (for the crate a [`FirstOrderSystem`], so no
//! automatic differentiation is involved). Only the final state is asked for: the crate runs
//! without observer (no dense output is formed), `ode_solvers` with `OutputType::Sparse` (no dense
//! output either; it does store every accepted step in its result vector, which is its cheapest
//! mode).
//!
//! Both use Hairer's controller with the Fortran defaults (safety 0.9, step ratio in
//! `[0.333, 6]`, `β = 0`, no growth right after a rejection, `h_max = |t₁ − t₀|`) and the
//! starting step of HNW II.4, so they take the same steps: the setup prints the accepted and
//! rejected steps and vector-field evaluations of both and asserts that the accepted steps agree
//! to 1 % (the two codes form the stage sums in a different order, `y + h Σ aᵢⱼkⱼ` against
//! `y + Σ (h aᵢⱼ) kⱼ`, so the step sequences may part by rounding) and that the final states agree
//! to `max(10³·tol, 15 ε √n t₁)` (the second term: the random walk of rounding errors after `n`
//! steps, carried along the track by the mean motion). `ode_solvers` counts a rejection only after the first accepted step (as the
//! Fortran code does), the crate every rejection. The setup also prints the time per accepted
//! step and per vector-field evaluation of each run; the figure of merit is the ratio of the
//! whole-run times (equal work), `crate / ode_solvers` (≤ 1: the crate is at least as fast).
//!
//! Run: `cargo bench --bench dop853`.

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::integrate::{integrate, Dop853, FirstOrderSystem, Problem, Report};
use hamilton_jacobi::nalgebra::{SVector, Vector2, Vector4};
use hamilton_jacobi::Result;
use ode_solvers::{OutputType, System};

mod common;
use common::best;
use std::f64::consts::TAU;
use std::hint::black_box;
use std::time::Duration;

/// Eccentricity of the orbit.
const E: f64 = 0.5;
/// 100 periods of the `a = 1`, `μ = 1` orbit.
const T1: f64 = 100.0 * TAU;

/// The Kepler field `(p, −q/r³)`, `μ = 1`, written by hand, for the crate.
struct KeplerHand;

impl FirstOrderSystem<2> for KeplerHand {
    #[inline]
    fn field(
        &self,
        _t: f64,
        q: &SVector<f64, 2>,
        p: &SVector<f64, 2>,
    ) -> Result<(SVector<f64, 2>, SVector<f64, 2>)> {
        let r2 = q[0] * q[0] + q[1] * q[1];
        let s = -1.0 / (r2 * r2.sqrt());
        Ok((*p, Vector2::new(q[0] * s, q[1] * s)))
    }
}

/// The same field for `ode_solvers`, on `y = (q₁, q₂, p₁, p₂)`.
struct KeplerHandOde;

impl System<f64, Vector4<f64>> for KeplerHandOde {
    #[inline]
    fn system(&self, _x: f64, y: &Vector4<f64>, dy: &mut Vector4<f64>) {
        let r2 = y[0] * y[0] + y[1] * y[1];
        let s = -1.0 / (r2 * r2.sqrt());
        dy[0] = y[2];
        dy[1] = y[3];
        dy[2] = y[0] * s;
        dy[3] = y[1] * s;
    }
}

fn start() -> (Vector2<f64>, Vector2<f64>) {
    (
        Vector2::new(1.0 - E, 0.0),
        Vector2::new(0.0, ((1.0 + E) / (1.0 - E)).sqrt()),
    )
}

fn run_crate(tol: f64) -> Report<2> {
    let (q, p) = start();
    let problem = Problem::new(&KeplerHand, 0.0, q, p, T1).expect("valid problem");
    let method = Dop853::new(tol, tol)
        .and_then(|m| m.with_max_steps(10_000_000))
        .expect("valid tolerances");
    integrate(&problem, &method, &mut ()).expect("the run reaches t₁")
}

/// `(final y, accepted, rejected, evaluations)` of the `ode_solvers` run.
fn run_peer(tol: f64) -> (Vector4<f64>, usize, usize, usize) {
    let (q, p) = start();
    let y0 = Vector4::new(q[0], q[1], p[0], p[1]);
    let mut solver = ode_solvers::Dop853::from_param(
        KeplerHandOde,
        0.0,
        T1,
        T1,
        y0,
        tol,
        tol,
        0.9,
        0.0,
        0.333,
        6.0,
        T1,
        0.0,
        u32::MAX,
        1000,
        OutputType::Sparse,
    );
    let stats = solver.integrate().expect("the run reaches t₁");
    let last = *solver.y_out().last().expect("at least the final state");
    (
        last,
        stats.accepted_steps as usize,
        stats.rejected_steps as usize,
        stats.num_eval as usize,
    )
}

/// Step counts of both sides, their agreement asserted, and a first time per step.
fn check_and_print(tol: f64) {
    let ours = run_crate(tol);
    let (y, acc, rej, evals) = run_peer(tol);
    let dq = (ours.last.q - Vector2::new(y[0], y[1])).norm();
    let dp = (ours.last.p - Vector2::new(y[2], y[3])).norm();
    let (t_ours, t_peer) = (best(5, || run_crate(tol)), best(5, || run_peer(tol)));
    let per = |t: Duration, n: usize| t.as_secs_f64() * 1e9 / n as f64;
    println!(
        "tol {tol:.0e}: crate {} accepted, {} rejected, {} evaluations, {:.0} µs \
         ({:.1} ns/step, {:.2} ns/evaluation); ode_solvers {acc} accepted, {rej} rejected, \
         {evals} evaluations, {:.0} µs ({:.1} ns/step, {:.2} ns/evaluation); ratio {:.3}; \
         final states differ by |Δq| = {dq:.1e}, |Δp| = {dp:.1e}",
        ours.work.steps,
        ours.work.rejected,
        ours.work.gradients,
        t_ours.as_secs_f64() * 1e6,
        per(t_ours, ours.work.steps),
        per(t_ours, ours.work.gradients),
        t_peer.as_secs_f64() * 1e6,
        per(t_peer, acc),
        per(t_peer, evals),
        t_ours.as_secs_f64() / t_peer.as_secs_f64(),
    );
    let (a, b) = (ours.work.steps as f64, acc as f64);
    assert!(
        (a - b).abs() <= 0.01 * b,
        "accepted steps differ by more than 1 %: {a} against {b}"
    );
    // The two codes round differently, so their states part by the random walk of rounding
    // errors as well as by tolerance-sized differences of the local errors: a relative energy
    // error ε per step walks to ε√n after n steps, and the mean motion's share of it, 3/2 of
    // that, grows along the track ∝ t₁ (n = 1 here); 10 roundings per step.
    let rounding = 10.0 * 1.5 * f64::EPSILON * (ours.work.steps as f64).sqrt() * T1;
    let bound = (1e3 * tol).max(rounding);
    assert!(
        dq.max(dp) <= bound,
        "final states differ by {:e} > max(1e3·tol, 15 ε √n t₁) = {bound:e}",
        dq.max(dp)
    );
}

fn bench(c: &mut Criterion) {
    let mut g = c.benchmark_group("dop853_kepler_e0.5_100_periods");
    g.sample_size(20)
        .warm_up_time(Duration::from_secs(1))
        .measurement_time(Duration::from_secs(4));
    for tol in [1e-6, 1e-10, 1e-14] {
        check_and_print(tol);
        g.bench_function(format!("crate/{tol:.0e}"), |b| {
            b.iter(|| run_crate(black_box(tol)))
        });
        g.bench_function(format!("ode_solvers/{tol:.0e}"), |b| {
            b.iter(|| run_peer(black_box(tol)))
        });
    }
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

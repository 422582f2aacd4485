//! The same motion by Hamilton–Jacobi quadratures, by closed form and by numerical integration of
//! Hamilton's equations, at matched accuracy.
//!
//! * Kepler e = 0.5, μ = a = 1, from periapsis to t = 0.3 T (past the first radial quarter):
//!   `hj` builds the radial quadratures and inverts the time law; `kepler_equation` is the f/g
//!   closed form; `rk4` integrates the Cartesian problem (AD vector field) with the step count that
//!   first reaches the HJ error against Kepler's equation.
//! * Pendulum n = 1, amplitude 2.5, from the lower turning point to t = 0.3 T: `hj` builds the
//!   action–angle variables (period by quadrature) and inverts the angle; `elliptic` is the Jacobi
//!   elliptic closed form; `rk4` as above.
//!
//! * Heavy top (I = 1, J = ½, mgℓ = 1, released from rest at 60° with ω_z = 5), to
//!   t = 1.7 (past half a nutation): `hj` builds the cubic and its quadratures and inverts the
//!   time law ([`Nutation::propagate`]); `rk4` as above, against a 2²⁰-step RK4 reference.
//!
//! The errors and step counts are printed once before timing; the ratios `rk4 / hj` and
//! `hj / closed form` are the figures of merit.

use criterion::{criterion_group, criterion_main, Criterion};
use hamilton_jacobi::hamilton_jacobi::{ActionAngle, RadialMotion};
use hamilton_jacobi::integrate::{integrate, Fixed, Problem, Rk4};
use hamilton_jacobi::nalgebra::{SVector, Vector2};
use hamilton_jacobi::systems::kepler;
use hamilton_jacobi::systems::pendulum_exact::exact_state;
use hamilton_jacobi::systems::top::motion::Nutation;
use hamilton_jacobi::systems::{HeavyTop, Kepler2, Pendulum};
use hamilton_jacobi::Hamiltonian;
use std::f64::consts::PI;
use std::hint::black_box;

/// RK4 (the crate's fixed-step driver) from `(q0, p0)` at t = 0 to `t` in `n` steps.
fn rk4<H: Hamiltonian<N>, const N: usize>(
    h: &H,
    q0: SVector<f64, N>,
    p0: SVector<f64, N>,
    t: f64,
    n: usize,
) -> (SVector<f64, N>, SVector<f64, N>) {
    let problem = Problem::new(h, 0.0, q0, p0, t).unwrap();
    let run = integrate(&problem, &Fixed::new(Rk4, n).unwrap(), &mut ()).unwrap();
    (run.last.q, run.last.p)
}

/// Smallest power-of-two multiple of 16 steps whose error is at most `target`.
fn matched_steps(err: impl Fn(usize) -> f64, target: f64) -> (usize, f64) {
    let mut n = 16;
    loop {
        let e = err(n);
        if e <= target || n >= 1 << 22 {
            return (n, e);
        }
        n *= 2;
    }
}

fn kepler_hj(t: f64) -> Vector2<f64> {
    let m = RadialMotion::kepler_elements(1.0, 1.0, 0.5).unwrap();
    let (r, _, th) = m.state_at(t).unwrap();
    Vector2::new(r * th.cos(), r * th.sin())
}

fn kepler_closed(t: f64) -> Vector2<f64> {
    let vp = 3f64.sqrt();
    kepler::propagate(1.0, &Vector2::new(0.5, 0.0), &Vector2::new(0.0, vp), t)
        .unwrap()
        .0
}

fn pendulum_hj(pen: Pendulum, delta: f64, t: f64) -> (f64, f64) {
    let aa = ActionAngle::pendulum(pen, delta).unwrap();
    aa.state(aa.frequency() * t).unwrap()
}

fn bench(c: &mut Criterion) {
    // Kepler.
    let kep = Kepler2::new(1.0).unwrap();
    let t = 0.3 * 2.0 * PI;
    let exact = kepler_closed(t);
    let hj_err = (kepler_hj(t) - exact).norm();
    let (q0, p0) = (SVector::from([0.5, 0.0]), SVector::from([0.0, 3f64.sqrt()]));
    let (n_kep, rk_err) = matched_steps(
        |n| (rk4(&kep, q0, p0, t, n).0 - exact).norm(),
        hj_err.max(1e-13),
    );
    println!(
        "Kepler e = 0.5, t = 0.3 T: HJ error {hj_err:.2e}; RK4 needs {n_kep} steps for {rk_err:.2e}"
    );
    let mut g = c.benchmark_group("kepler_e0.5_state");
    g.bench_function("hj", |b| b.iter(|| kepler_hj(black_box(t))));
    g.bench_function("kepler_equation", |b| {
        b.iter(|| kepler_closed(black_box(t)))
    });
    g.bench_function("rk4", |b| {
        b.iter(|| rk4(&kep, black_box(q0), black_box(p0), t, n_kep))
    });
    g.finish();

    // Pendulum.
    let pen = Pendulum::new(1.0).unwrap();
    let a: f64 = 2.5;
    let delta = PI - a;
    let period = ActionAngle::pendulum(pen, delta).unwrap().period().value;
    let t = 0.3 * period;
    let (qe, pe) = exact_state(1.0, -a, 0.0, t).unwrap();
    let (qh, ph) = pendulum_hj(pen, delta, t);
    let hj_err = (qh - qe).abs() + (ph - pe).abs();
    let (q0, p0) = (SVector::from([-a]), SVector::from([0.0]));
    let (n_pen, rk_err) = matched_steps(
        |n| {
            let (q, p) = rk4(&pen, q0, p0, t, n);
            (q[0] - qe).abs() + (p[0] - pe).abs()
        },
        hj_err.max(1e-13),
    );
    println!(
        "Pendulum a = 2.5, t = 0.3 T: HJ error {hj_err:.2e}; RK4 needs {n_pen} steps for {rk_err:.2e}"
    );
    let mut g = c.benchmark_group("pendulum_a2.5_state");
    g.bench_function("hj", |b| b.iter(|| pendulum_hj(pen, black_box(delta), t)));
    g.bench_function("elliptic", |b| {
        b.iter(|| exact_state(1.0, black_box(-a), 0.0, t))
    });
    g.bench_function("rk4", |b| {
        b.iter(|| rk4(&pen, black_box(q0), black_box(p0), t, n_pen))
    });
    g.finish();

    // Heavy top.
    let top = HeavyTop::new(1.0, 0.5, 1.0).unwrap();
    let theta0 = PI / 3.0;
    let q0 = SVector::from([0.0, theta0, 0.0]);
    let p0 = top.momenta_from_spin(theta0, 0.0, 0.0, 5.0).unwrap();
    let t = 1.7;
    let top_hj = |t: f64| {
        Nutation::from_state(&top, &q0, &p0)
            .unwrap()
            .propagate(&q0, &p0, t)
            .unwrap()
    };
    let (q_ref, p_ref) = rk4(&top, q0, p0, t, 1 << 20);
    let (qh, ph) = top_hj(t);
    let hj_err = (qh - q_ref).amax().max((ph - p_ref).amax());
    let (n_top, rk_err) = matched_steps(
        |n| {
            let (q, p) = rk4(&top, q0, p0, t, n);
            (q - q_ref).amax().max((p - p_ref).amax())
        },
        hj_err.max(1e-13),
    );
    println!(
        "Top released from rest, t = 1.7: |HJ − reference| {hj_err:.2e}; RK4 needs {n_top} steps for {rk_err:.2e}"
    );
    let mut g = c.benchmark_group("top_released_from_rest_state");
    g.bench_function("hj", |b| b.iter(|| top_hj(black_box(t))));
    g.bench_function("rk4", |b| {
        b.iter(|| rk4(&top, black_box(q0), black_box(p0), t, n_top))
    });
    g.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

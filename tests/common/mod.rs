//! Shared test utilities: seeded proptest configuration, a classical RK4 used as an independent
//! integrator oracle, and the observed order of convergence.
#![allow(dead_code)]

pub mod rational;

use hamilton_jacobi::brackets::PhaseMap;
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::DualNum;
use hamilton_jacobi::{Hamiltonian, Lagrangian};
use proptest::test_runner::{Config, RngSeed};

/// 1000 cases, fixed seed, no failure persistence files.
pub fn config(seed: u64) -> Config {
    Config {
        cases: 1000,
        rng_seed: RngSeed::Fixed(seed),
        failure_persistence: None,
        ..Config::default()
    }
}

/// One classical RK4 step of `ẋ = f(t, x)`.
pub fn rk4_step<const M: usize>(
    f: &impl Fn(f64, &SVector<f64, M>) -> SVector<f64, M>,
    t: f64,
    x: &SVector<f64, M>,
    h: f64,
) -> SVector<f64, M> {
    let k1 = f(t, x);
    let k2 = f(t + 0.5 * h, &(x + k1 * (0.5 * h)));
    let k3 = f(t + 0.5 * h, &(x + k2 * (0.5 * h)));
    let k4 = f(t + h, &(x + k3 * h));
    x + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0)
}

/// Integrate Hamilton's equations of `h` with RK4 from `(q0, p0)` at `t0` over `steps` steps of `dt`,
/// calling `observe(t, q, p)` after each step.
pub fn rk4_hamiltonian<H: Hamiltonian<N>, const N: usize>(
    h: &H,
    t0: f64,
    q0: SVector<f64, N>,
    p0: SVector<f64, N>,
    dt: f64,
    steps: usize,
    mut observe: impl FnMut(f64, &SVector<f64, N>, &SVector<f64, N>),
) -> (SVector<f64, N>, SVector<f64, N>) {
    let (mut q, mut p, mut t) = (q0, p0, t0);
    for _ in 0..steps {
        let fq =
            |t: f64, q: &SVector<f64, N>, p: &SVector<f64, N>| h.vector_field_unchecked(t, q, p);
        let (k1q, k1p) = fq(t, &q, &p);
        let (k2q, k2p) = fq(
            t + 0.5 * dt,
            &(q + k1q * (0.5 * dt)),
            &(p + k1p * (0.5 * dt)),
        );
        let (k3q, k3p) = fq(
            t + 0.5 * dt,
            &(q + k2q * (0.5 * dt)),
            &(p + k2p * (0.5 * dt)),
        );
        let (k4q, k4p) = fq(t + dt, &(q + k3q * dt), &(p + k3p * dt));
        q += (k1q + k2q * 2.0 + k3q * 2.0 + k4q) * (dt / 6.0);
        p += (k1p + k2p * 2.0 + k3p * 2.0 + k4p) * (dt / 6.0);
        t += dt;
        observe(t, &q, &p);
    }
    (q, p)
}

/// Integrate Lagrange's equations of `l` (state `(q, q̇)`) with RK4, calling `observe` after each step.
pub fn rk4_lagrangian<L: Lagrangian<N>, const N: usize>(
    l: &L,
    t0: f64,
    q0: SVector<f64, N>,
    v0: SVector<f64, N>,
    dt: f64,
    steps: usize,
    mut observe: impl FnMut(f64, &SVector<f64, N>, &SVector<f64, N>),
) -> (SVector<f64, N>, SVector<f64, N>) {
    let (mut q, mut v, mut t) = (q0, v0, t0);
    let acc = |t: f64, q: &SVector<f64, N>, v: &SVector<f64, N>| {
        l.accelerations(t, q, v).expect("regular mass matrix")
    };
    for _ in 0..steps {
        let a1 = acc(t, &q, &v);
        let (q2, v2) = (q + v * (0.5 * dt), v + a1 * (0.5 * dt));
        let a2 = acc(t + 0.5 * dt, &q2, &v2);
        let (q3, v3) = (q + v2 * (0.5 * dt), v + a2 * (0.5 * dt));
        let a3 = acc(t + 0.5 * dt, &q3, &v3);
        let (q4, v4) = (q + v3 * dt, v + a3 * dt);
        let a4 = acc(t + dt, &q4, &v4);
        q += (v + v2 * 2.0 + v3 * 2.0 + v4) * (dt / 6.0);
        v += (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (dt / 6.0);
        t += dt;
        observe(t, &q, &v);
    }
    (q, v)
}

/// Generic sample points of 3-D phase space `(t, q, p)` away from the origin.
pub fn central_sample_points() -> Vec<(f64, SVector<f64, 3>, SVector<f64, 3>)> {
    vec![
        (
            0.0,
            SVector::from([1.0, 0.2, -0.3]),
            SVector::from([0.1, 0.9, 0.4]),
        ),
        (
            1.3,
            SVector::from([-0.7, 1.4, 0.5]),
            SVector::from([-0.6, 0.2, 1.1]),
        ),
        (
            2.0,
            SVector::from([0.3, -0.2, 2.0]),
            SVector::from([1.5, -0.4, 0.0]),
        ),
    ]
}

/// [Ardema Prob. 16/2]: `Q = ln(sin p / q)`, `P = q cot p` (canonical).
pub struct Prob16_2;
impl PhaseMap<1> for Prob16_2 {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        (
            SVector::from([(p[0].sin() / q[0]).ln()]),
            SVector::from([q[0] / p[0].tan()]),
        )
    }
}

/// [Ardema Prob. 16/3]: `Q = q^α cos βp`, `P = q^α sin βp` (canonical iff α = ½, β = 2).
pub struct Prob16_3 {
    pub alpha: f64,
    pub beta: f64,
}
impl PhaseMap<1> for Prob16_3 {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        let qa = q[0].powf(self.alpha);
        let (s, c) = (p[0] * self.beta).sin_cos();
        (SVector::from([qa * c]), SVector::from([qa * s]))
    }
}

/// In the spirit of Ardema Prob. 16/1 (time-dependent): `Q = √(2q) eᵗ cos p`, `P = √(2q) e⁻ᵗ sin p`.
pub struct Prob16_1;
impl PhaseMap<1> for Prob16_1 {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        let r = (q[0] * 2.0).sqrt();
        let (s, c) = p[0].sin_cos();
        (
            SVector::from([r * t.exp() * c]),
            SVector::from([r * (-t).exp() * s]),
        )
    }
}

/// Least-squares slope of `ln y` against `ln x` over the points `(x, y)`.
///
/// With `x` the step size (or a small parameter ε) and `y` the error, this is the observed order
/// of convergence `p` of `y ≈ C xᵖ`; with `x` a step count it is `−p`.
pub fn loglog_slope(points: &[(f64, f64)]) -> f64 {
    assert!(points.len() >= 2, "a slope needs two points: {points:?}");
    let n = points.len() as f64;
    let (xs, ys): (Vec<f64>, Vec<f64>) = points.iter().map(|&(x, y)| (x.ln(), y.ln())).unzip();
    let (mx, my) = (xs.iter().sum::<f64>() / n, ys.iter().sum::<f64>() / n);
    let sxy: f64 = xs.iter().zip(&ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Orders `log₂(e_k / e_{k+1})` of consecutive halvings of the step.
pub fn halving_orders(errors: &[f64]) -> Vec<f64> {
    errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect()
}

/// `H = a(q₁p₁ + q₂p₂) + b(q₁p₂ − q₂p₁)` (SPEC T29): the eigenvalues of `J∇²H` are exactly
/// `±a ± ib`.
pub struct BoxHamiltonian {
    pub a: f64,
    pub b: f64,
}

impl Hamiltonian<2> for BoxHamiltonian {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 2>,
        p: &SVector<D, 2>,
    ) -> D {
        (q[0] * p[0] + q[1] * p[1]) * self.a + (q[0] * p[1] - q[1] * p[0]) * self.b
    }
}

/// The damped oscillator `ẋ = v, v̇ = −x − c v`.
pub struct DampedOscillator {
    pub c: f64,
}

impl hamilton_jacobi::hamilton_jacobi::VectorField<2> for DampedOscillator {
    fn field<D: DualNum<f64> + Copy>(&self, _t: D, z: &SVector<D, 2>) -> SVector<D, 2> {
        SVector::from([z[1], -z[0] - z[1] * self.c])
    }
}

/// Scene run options for tests: one timed repetition, no progress bar, output to `out`.
#[cfg(feature = "cli")]
pub fn quick(out: &std::path::Path) -> hamilton_jacobi::scene::RunOptions {
    hamilton_jacobi::scene::RunOptions {
        out: out.to_path_buf(),
        timing: hamilton_jacobi::workprecision::Timing {
            min_time: std::time::Duration::ZERO,
            max_runs: 1,
        },
        progress: false,
        figures: Default::default(),
    }
}

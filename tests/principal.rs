//! Hamilton's principal function by shooting: the projectile and the oscillator in closed form
//! [Ardema 17.1], the derivative identities and Hamilton–Jacobi residuals [Ardema 17.1–17.2] from
//! dual evaluations of `S`, the approach to the focal point, non-linear systems against an
//! independent integration, and typed errors for bad input.
//!
//! Tolerances. Unless a test says otherwise, the solver is run with its default options: the step
//! count `M` of the extrapolated RK4 pair is raised until the estimated error of `S`, `p⁰`, `p¹`
//! (step doubling, amplified by the shooting Jacobian, plus the rounding floor `ε √(2M)`) is below
//! `1e−12` of the path maxima of `|p|`, `|S|` and `|τ L|`. For extrapolated RK4 the step-doubling
//! estimate `|y₂ₘ − yₘ|/15` is the error of `y₂ₘ`, an upper bound for the returned extrapolated
//! value, so the true errors are at or below the reported `error` fields, and those are at or below
//! `1e−12` of the scales. Tests therefore assert (i) against the oracle with `1e−12` relative to
//! the path scale times a stated factor, and (ii) where it matters, that the oracle lies within the
//! reported estimate.

mod common;

use hamilton_jacobi::ad::GradDual64;
use hamilton_jacobi::hamilton_jacobi::principal::{
    principal_function, principal_function_generic, propagate, propagate_fixed, PrincipalFunction,
    PrincipalOptions, PropagationOptions,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::num_dual::{second_derivative, Dual2_64, DualNum};
use hamilton_jacobi::systems::{HarmonicOscillator, Kepler2, Pendulum, Projectile};
use hamilton_jacobi::{hamiltonian, Error, Hamiltonian, Result};
use proptest::prelude::*;
use std::f64::consts::PI;

const EPS: f64 = f64::EPSILON;
const G: f64 = 9.81;

/// The projectile's principal function [Ardema 17.1]:
/// S = |q¹ − q⁰|²/(2τ) − ½ g (y⁰ + y¹) τ − g² τ³/24.
fn projectile_s(q0: [f64; 2], q1: [f64; 2], tau: f64) -> f64 {
    let (dx, dy) = (q1[0] - q0[0], q1[1] - q0[1]);
    (dx * dx + dy * dy) / (2.0 * tau) - 0.5 * G * (q0[1] + q1[1]) * tau - G * G * tau.powi(3) / 24.0
}

/// The oscillator's principal function [Ardema 17.1] (unit mass): S, p⁰ = −∂S/∂x⁰, p¹ = ∂S/∂x¹.
fn oscillator_s(w: f64, x0: f64, x1: f64, tau: f64) -> (f64, f64, f64) {
    let (s, c) = (w * tau).sin_cos();
    (
        w * ((x0 * x0 + x1 * x1) * c - 2.0 * x0 * x1) / (2.0 * s),
        w * (x1 - x0 * c) / s,
        w * (x1 * c - x0) / s,
    )
}

/// `S` and its gradient with respect to `(q⁰, q¹, t₀, t₁)` (in that order, `2N + 2` slots) from one
/// dual evaluation, with the real report.
fn s_gradient<H: Hamiltonian<N>, const N: usize, const M: usize>(
    h: &H,
    q0: [f64; N],
    q1: [f64; N],
    t0: f64,
    t1: f64,
) -> Result<(f64, SVector<f64, M>, PrincipalFunction<N>)> {
    assert_eq!(M, 2 * N + 2);
    let var = GradDual64::<M>::variable;
    let q0d = SVector::from_fn(|i, _| var(q0[i], i));
    let q1d = SVector::from_fn(|i, _| var(q1[i], N + i));
    let (v, r) = principal_function_generic(
        h,
        &q0d,
        &q1d,
        var(t0, 2 * N),
        var(t1, 2 * N + 1),
        &PrincipalOptions::default(),
    )?;
    Ok((*v.s.value(), *v.s.eps(), r))
}

/// The derivative identities of the principal function and the Hamilton–Jacobi residuals at both
/// end points for one gradient `dS` of `S`, all relative to the momentum scale `ps` and the energy
/// scale `hs`, within `tol`.
fn check_identities<H: Hamiltonian<N>, const N: usize, const M: usize>(
    h: &H,
    (q0, q1, t0, t1): ([f64; N], [f64; N], f64, f64),
    ds: &SVector<f64, M>,
    r: &PrincipalFunction<N>,
    (ps, hs, tol): (f64, f64, f64),
) {
    let ds_q0 = SVector::<f64, N>::from_fn(|i, _| ds[i]);
    let ds_q1 = SVector::<f64, N>::from_fn(|i, _| ds[N + i]);
    let (ds_t0, ds_t1) = (ds[2 * N], ds[2 * N + 1]);
    // p¹ = ∂S/∂q¹, p⁰ = −∂S/∂q⁰, ∂S/∂t₁ = −H₁, ∂S/∂t₀ = +H₀ [Ardema eqs. 17.9–17.13].
    assert!(
        (ds_q1 - r.p1).amax() <= tol * ps,
        "∂S/∂q¹ {ds_q1} vs p¹ {}",
        r.p1
    );
    assert!((ds_q0 + r.p0).amax() <= tol * ps, "−∂S/∂q⁰ vs p⁰ {}", r.p0);
    assert!(
        (ds_t1 + r.h1).abs() <= tol * hs,
        "∂S/∂t₁ {ds_t1} vs −H₁ {}",
        r.h1
    );
    assert!(
        (ds_t0 - r.h0).abs() <= tol * hs,
        "∂S/∂t₀ {ds_t0} vs H₀ {}",
        r.h0
    );
    // Hamilton–Jacobi equation [Ardema 17.2]: ∂S/∂t₁ + H(t₁, q¹, ∂S/∂q¹) = 0 and
    // ∂S/∂t₀ − H(t₀, q⁰, −∂S/∂q⁰) = 0.
    let hj1 = ds_t1 + h.value(t1, &SVector::from(q1), &ds_q1).unwrap();
    let hj0 = ds_t0 - h.value(t0, &SVector::from(q0), &(-ds_q0)).unwrap();
    assert!(hj1.abs() <= tol * hs, "HJ residual at (q¹, t₁): {hj1:e}");
    assert!(hj0.abs() <= tol * hs, "HJ residual at (q⁰, t₀): {hj0:e}");
}

// ---------------------------------------------------------------------------------------------
// Projectile [Ardema 17.1]
// ---------------------------------------------------------------------------------------------

/// From (0, 0) to (10, 5) in τ = 2. Classical RK4 is exact for this motion: all elementary
/// differentials of order ≥ 4 of the field `(p, −g e_y, |p|²/2 − g y)` vanish (only `∂²ṡ/∂p²` and
/// constants are non-zero), so the discrete map equals the flow and only rounding remains — a few
/// `ε` per step over `3 · 2M` steps, `ε √(2M) ≈ 1e−15` relative at the `M = 16` the solver keeps.
/// Hence `1e−12` relative on every quantity (values and all six derivatives) with a wide margin.
#[test]
fn projectile_principal_function() {
    let proj = Projectile::new(1.0, G).unwrap();
    let (q0, q1) = ([0.0, 0.0], [10.0, 5.0]);
    let h = 0.5 * (5.0f64.powi(2) + 12.31f64.powi(2)); // 88.26805
    for t0 in [0.0, 3.7, -12.25] {
        let t1 = t0 + 2.0;
        let (s, ds, r) = s_gradient::<_, 2, 6>(&proj, q0, q1, t0, t1).unwrap();
        let exact = projectile_s(q0, q1, 2.0);
        assert!(
            (r.s - exact).abs() <= 1e-12 * exact.abs(),
            "S {} vs {exact}",
            r.s
        );
        assert!((s - exact).abs() <= 1e-12 * exact.abs());
        assert!((r.s - -49.8787).abs() < 5e-5); // the six-digit reference value
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1.0);
        assert!(close(r.p0[0], 5.0) && close(r.p0[1], 12.31), "p⁰ {}", r.p0);
        assert!(close(r.p1[0], 5.0) && close(r.p1[1], -7.31), "p¹ {}", r.p1);
        assert!(close(r.h0, h) && close(r.h1, h), "H {} {}", r.h0, r.h1);
        // ∂S/∂(x⁰, y⁰, x¹, y¹, t₀, t₁) = (−5, −12.31, 5, −7.31, 88.26805, −88.26805).
        let expected = [-5.0, -12.31, 5.0, -7.31, h, -h];
        for (i, e) in expected.iter().enumerate() {
            assert!(close(ds[i], *e), "∂S slot {i}: {} vs {e}", ds[i]);
        }
        check_identities(&proj, (q0, q1, t0, t1), &ds, &r, (12.31, h, 1e-12));
        assert!(
            r.rcond > 0.1,
            "free flight is well conditioned: {}",
            r.rcond
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Harmonic oscillator [Ardema 17.1]
// ---------------------------------------------------------------------------------------------

/// The instance ω = 2, x⁰ = 1, x¹ = 0.5, τ = 1. Path maxima: `|p| ≤ 2.7`, `|S|, τ|L| ≤ 4`; the
/// solver's target is `1e−12` of those, and `rcond = sin ωτ`-like conditioning is already inside
/// its estimate. So `1e−11` absolute covers estimate and oracle rounding (the closed form is a few
/// roundings of `O(1)` numbers).
#[test]
fn oscillator_principal_function() {
    let osc = HarmonicOscillator::new(1.0, 2.0).unwrap();
    let (q0, q1) = ([1.0], [0.5]);
    let (s, ds, r) = s_gradient::<_, 1, 4>(&osc, q0, q1, 0.0, 1.0).unwrap();
    let tol = 1e-11;
    assert!((r.s - -1.67182211324497).abs() <= tol, "S {}", r.s);
    assert!((r.p0[0] - 2.01506527901519).abs() <= tol, "p⁰ {}", r.p0);
    assert!((r.p1[0] - -2.65715789494952).abs() <= tol, "p¹ {}", r.p1);
    assert!((s - r.s).abs() <= 4.0 * EPS * r.s.abs());
    // The reported estimates bound the actual errors and meet the target.
    let (se, p0e, p1e) = oscillator_s(2.0, 1.0, 0.5, 1.0);
    assert!((r.s - se).abs() <= r.error.s && r.error.s <= 4e-12);
    assert!((r.p0[0] - p0e).abs() <= r.error.p0[0] && r.error.p0[0] <= 3e-12);
    assert!((r.p1[0] - p1e).abs() <= r.error.p1[0] && r.error.p1[0] <= 3e-12);
    // The derivatives of the discrete S differ from those of S by the discretisation error of
    // the derivative of the discrete map, of the same relative size as the error of the values
    // (the map is smooth in its parameters): 1e−11 relative to |p| ≈ 2.7 and |H| ≈ 4.6.
    check_identities(&osc, (q0, q1, 0.0, 1.0), &ds, &r, (2.7, 4.6, 1e-11));
}

/// Second derivatives of `S` come out of the same solve in a second-order dual type:
/// `∂²S/∂(x¹)² = ω cot ωτ = ∂p¹/∂x¹`. Same error budget as above, relative to `ω/sin ωτ ≈ 2.2`.
#[test]
fn oscillator_second_derivative_from_hyper_dual() {
    let osc = HarmonicOscillator::new(1.0, 2.0).unwrap();
    let (_, _, d2) = second_derivative(
        |x1: Dual2_64| {
            principal_function_generic(
                &osc,
                &SVector::from([Dual2_64::from(1.0)]),
                &SVector::from([x1]),
                Dual2_64::from(0.0),
                Dual2_64::from(1.0),
                &PrincipalOptions::default(),
            )
            .map(|(v, _)| v.s)
            .unwrap_or(Dual2_64::from(f64::NAN))
        },
        0.5,
    );
    let exact = 2.0 / 2.0f64.tan();
    assert!((d2 - exact).abs() <= 1e-11 * 2.2, "{d2} vs {exact}");
}

proptest! {
    #![proptest_config(common::config(0x5eed_0052))]

    /// The oscillator against the closed form for random end points and times away from the focal
    /// points ωτ = kπ (|sin ωτ| ≥ sin 0.2, so the closed form loses at most a factor ~50 to
    /// cancellation in `(x⁰² + x¹²) cos ωτ − 2x⁰x¹`). Each case costs ~10⁴ RK4 steps with a 1-wide
    /// gradient dual, so the full 1000 cases stay cheap. Scale of the solver's target: amplitude
    /// `a = √(x⁰² + (p⁰/ω)²)`, `|p| ≤ ωa`, `|S|, τ|L| ≤ τω²a²`; tolerance `1e−12 · 10` of those
    /// (target plus the factor-10 slack in these scale bounds), plus `64 ε · 50` for the oracle.
    #[test]
    fn oscillator_random_against_closed_form(
        x0 in -2.0..2.0f64,
        x1 in -2.0..2.0f64,
        w in 0.5..2.0f64,
        phase in 0.2..(2.0 * PI - 0.2),
    ) {
        prop_assume!((phase - PI).abs() >= 0.2);
        let tau = phase / w;
        let osc = HarmonicOscillator::new(1.0, w).unwrap();
        let r = principal_function(
            &osc, &SVector::from([x0]), &SVector::from([x1]), 0.0, tau,
            &PrincipalOptions::default(),
        ).unwrap();
        let (s, p0, p1) = oscillator_s(w, x0, x1, tau);
        let a = x0.hypot(p0 / w);
        let (ps, ss) = (w * a, tau * w * w * a * a);
        let oracle = 64.0 * EPS * 50.0;
        prop_assert!((r.s - s).abs() <= (1e-11 + oracle) * ss, "S {} vs {s}", r.s);
        prop_assert!((r.p0[0] - p0).abs() <= (1e-11 + oracle) * ps, "p⁰ {} vs {p0}", r.p0[0]);
        prop_assert!((r.p1[0] - p1).abs() <= (1e-11 + oracle) * ps, "p¹ {} vs {p1}", r.p1[0]);
    }
}

// ---------------------------------------------------------------------------------------------
// Focal point of the unit oscillator
// ---------------------------------------------------------------------------------------------

/// Near the focal point: τ = π − δ, δ = 1e−3 and 1e−6 (S = −1125.000, u₀ = 1500 and
/// S = −1.125e6, u₀ = 1.5e6).
///
/// Conditioning: the shooting Jacobian is `A = ∂x¹/∂p⁰ = sin τ ≈ δ`, against the natural scale
/// `Â ≈ 1`, so a relative error `η` of the propagated flow moves `p⁰`, `p¹` and `S` by a relative
/// `η/δ` (for `S`: `δS = |p¹| e_q`, with `|p¹| ≈ |p⁰| ≈ 1.5/δ`, `e_q ≈ η·1.5/δ` and
/// `|S| ≈ 1.125/δ`). The flow itself cannot be better than the rounding floor
/// `η = ε √(2M)` (M the final coarse step count); with a factor 4 for the random-walk model the
/// tolerance is `4 ε √(2M) / δ` — `8e−11` at δ = 1e−3 and `8e−8` at δ = 1e−6 for M = 4096, against
/// `5e−12` and `3e−9` observed. The oracle is the closed form at the same double τ; `sin τ` of a
/// double is correct to an ulp, so the oracle is good to a few ε.
#[test]
fn principal_function_near_the_focal_point() {
    let unit = HarmonicOscillator::new(1.0, 1.0).unwrap();
    for (delta, s_spec, u0_spec) in [(1e-3, -1125.000, 1500.0), (1e-6, -1.125e6, 1.5e6)] {
        let tau = PI - delta;
        let r = principal_function(
            &unit,
            &SVector::from([1.0]),
            &SVector::from([0.5]),
            0.0,
            tau,
            &PrincipalOptions::default(),
        )
        .unwrap();
        let (s, p0, p1) = oscillator_s(1.0, 1.0, 0.5, tau);
        let tol = 4.0 * EPS * (2.0 * r.steps as f64).sqrt() / tau.sin();
        assert!(
            ((r.s - s) / s).abs() <= tol,
            "δ = {delta}: S {} vs {s}",
            r.s
        );
        assert!(
            ((r.p0[0] - p0) / p0).abs() <= tol,
            "δ = {delta}: p⁰ {}",
            r.p0[0]
        );
        assert!(
            ((r.p1[0] - p1) / p1).abs() <= tol,
            "δ = {delta}: p¹ {}",
            r.p1[0]
        );
        // The reported estimates are honest and the conditioning is reported as ≈ δ.
        assert!((r.s - s).abs() <= r.error.s);
        assert!((r.p0[0] - p0).abs() <= r.error.p0[0]);
        assert!((r.rcond / delta - 1.0).abs() < 0.01, "rcond {}", r.rcond);
        // The reference values to four significant digits.
        assert!(((r.s - s_spec) / s_spec).abs() < 5e-4);
        assert!(((r.p0[0] - u0_spec) / u0_spec).abs() < 5e-4);
    }
}

/// At the focal point τ = π the principal function is a typed error carrying the point, never a
/// number — for an unreachable end point (x¹ = 0.5), for the end point reached by infinitely many
/// paths (x¹ = −x⁰), and for the rest path x⁰ = x¹ = 0 (S = 0 on every path of the family, but p⁰
/// is not determined).
#[test]
fn principal_function_at_the_focal_point_is_singular() {
    let unit = HarmonicOscillator::new(1.0, 1.0).unwrap();
    for (x0, x1) in [(1.0, 0.5), (1.0, -1.0), (0.0, 0.0)] {
        let r = principal_function(
            &unit,
            &SVector::from([x0]),
            &SVector::from([x1]),
            0.0,
            PI,
            &PrincipalOptions::default(),
        );
        match r {
            Err(Error::Singular { what, at, rcond }) => {
                assert!(what.contains("∂q¹/∂p⁰"), "{what}");
                assert!(at.contains("t₁ = 3.14159"), "{at}");
                assert!(rcond < 1e-8, "rcond {rcond}");
            }
            other => panic!("x⁰ = {x0}, x¹ = {x1}: expected Singular, got {other:?}"),
        }
    }
    // Also at the second focal point and with a shifted, backward time interval.
    let r = principal_function(
        &unit,
        &SVector::from([1.0]),
        &SVector::from([0.5]),
        5.0,
        5.0 - 2.0 * PI,
        &PrincipalOptions::default(),
    );
    assert!(matches!(r, Err(Error::Singular { .. })), "{r:?}");
}

// ---------------------------------------------------------------------------------------------
// Non-linear systems: no closed form
// ---------------------------------------------------------------------------------------------

/// Independent check of a shooting result: classical RK4 (tests/common) from `(q⁰, p⁰)` with
/// `steps` steps must arrive at `(q¹, p¹)`, and composite Simpson on `L = p·∂H/∂p − H` along its
/// steps must give `S`.
fn independent<H: Hamiltonian<N>, const N: usize>(
    h: &H,
    q0: [f64; N],
    t0: f64,
    t1: f64,
    p0: SVector<f64, N>,
    steps: usize,
) -> (SVector<f64, N>, SVector<f64, N>, f64) {
    let dt = (t1 - t0) / steps as f64;
    let lagrangian = |t: f64, q: &SVector<f64, N>, p: &SVector<f64, N>| {
        let (hv, _, hp) = h.gradient(t, q, p);
        p.dot(&hp) - hv
    };
    let mut values = vec![lagrangian(t0, &SVector::from(q0), &p0)];
    let (q, p) = common::rk4_hamiltonian(h, t0, SVector::from(q0), p0, dt, steps, |t, q, p| {
        values.push(lagrangian(t, q, p))
    });
    let simpson = values
        .iter()
        .enumerate()
        .map(|(k, l)| {
            let w = if k == 0 || k == steps {
                1.0
            } else if k % 2 == 1 {
                4.0
            } else {
                2.0
            };
            w * l
        })
        .sum::<f64>()
        * dt
        / 3.0;
    (q, p, simpson)
}

/// Pendulum `H = ½p² + (1 − cos θ)`, from θ⁰ = 0.3 to θ¹ = −0.8 over [0.2, 2.7] (no closed form).
///
/// Independent integration with 20 000 RK4 steps (dt = 1.25e−4): global error `~ τ dt⁴ ≈ 6e−16`,
/// rounding `ε √20000 ≈ 3e−14` relative; Simpson's rule on the same grid, `~ τ dt⁴ max|L⁗|/180`,
/// negligible. The shooting result carries the solver's `1e−12` target relative to the path
/// scales (|p| ≈ 1, |S| ≈ 1; the conditioning is inside the solver's estimate, rcond ≈ 1 here), so
/// the comparisons use `1e−11`. The derivative identities hold for the exact `S`; the dual parts
/// are derivatives of the discrete `S_h = S + E`, whose error function `E` is smooth and of the
/// size of the value error, so `∂E` is bounded by the same target relative to |p| and |H|:
/// again `1e−11` (factor-10 slack as everywhere).
#[test]
fn pendulum_against_independent_integration() {
    let pend = Pendulum::new(1.0).unwrap();
    let (q0, q1, t0, t1) = ([0.3], [-0.8], 0.2, 2.7);
    let (s, ds, r) = s_gradient::<_, 1, 4>(&pend, q0, q1, t0, t1).unwrap();
    let (q, p, quad) = independent(&pend, q0, t0, t1, r.p0, 20_000);
    let ps = r.p0.amax().max(r.p1.amax());
    assert!((q[0] - q1[0]).abs() <= 1e-11, "end point {q} vs {q1:?}");
    assert!((p - r.p1).amax() <= 1e-11 * ps, "p¹ {p} vs {}", r.p1);
    assert!(
        (quad - r.s).abs() <= 1e-11 * r.s.abs().max(1.0),
        "S {quad} vs {}",
        r.s
    );
    assert!(
        // Rounding relative to the size of the action's terms, ∫T and ∫V ≈ 1 here (S itself is
        // a difference of them).
        (s - r.s).abs() <= 4.0 * EPS * r.s.abs().max(1.0),
        "dual-evaluated S {s} vs {} ({:e})",
        r.s,
        (s - r.s) / r.s
    );
    check_identities(&pend, (q0, q1, t0, t1), &ds, &r, (ps, r.h0.abs(), 1e-11));
    // Energy is conserved by the true path: H₀ = H₁ within the estimates.
    assert!((r.h0 - r.h1).abs() <= r.error.h0 + r.error.h1 + 8.0 * EPS * r.h0.abs());
}

/// Backward time: from (θ⁰, t₀) to (θ¹, t₁) with t₁ < t₀ the path is the forward path from
/// (θ¹, t₁) to (θ⁰, t₀), so `S` changes sign and the end momenta swap. Both solves carry the
/// `1e−12` target, so `1e−11` relative.
#[test]
fn backward_time_reverses_the_forward_problem() {
    let pend = Pendulum::new(1.0).unwrap();
    let opts = PrincipalOptions::default();
    let (a, b) = (SVector::from([0.3]), SVector::from([-0.8]));
    let fwd = principal_function(&pend, &a, &b, 0.2, 2.7, &opts).unwrap();
    let bwd = principal_function(&pend, &b, &a, 2.7, 0.2, &opts).unwrap();
    assert!((fwd.s + bwd.s).abs() <= 1e-11 * fwd.s.abs().max(1.0));
    assert!((fwd.p0 - bwd.p1).amax() <= 1e-11 * fwd.p0.amax());
    assert!((fwd.p1 - bwd.p0).amax() <= 1e-11 * fwd.p1.amax());
}

/// Several paths join the same end points (the pendulum can swing through extra half
/// oscillations in τ = 10): a momentum guess selects one, and each satisfies the independent
/// check.
///
/// Tolerances: the independent RK4 (80 000 steps) has rounding error `~4 ε √80000 |p|` in
/// momentum units, and an error `δp⁰` of the initial momentum moves the end by about `|A| δp⁰`
/// (`A = ∂q¹/∂p⁰`, up to 32 on these paths; `∂p¹/∂p⁰` is of the same order for ω = 1, and
/// `∂S/∂p⁰ = p¹A`). So with `δp⁰ = error.p0 + 4 ε √80000 |p|`, `q` must agree within `|A| δp⁰`,
/// `p` within `error.p1 + |A| δp⁰`, `S` within `error.s + |p¹| |A| δp⁰` (Simpson's error at
/// dt = 1.25e−4 is ~1e−16, negligible).
#[test]
fn momentum_guess_selects_a_path() {
    let pend = Pendulum::new(1.0).unwrap();
    let (q0, q1, t1) = ([0.0], [0.5], 10.0);
    let solve = |guess: Option<f64>| {
        principal_function(
            &pend,
            &SVector::from(q0),
            &SVector::from(q1),
            0.0,
            t1,
            &PrincipalOptions {
                momentum_guess: guess.map(|g| SVector::from([g])),
                ..PrincipalOptions::default()
            },
        )
        .unwrap()
    };
    let direct = solve(None);
    let other = solve(Some(-1.9));
    assert!(
        (direct.p0[0] - other.p0[0]).abs() > 1.0,
        "{} {}",
        direct.p0,
        other.p0
    );
    assert!(
        (direct.s - other.s).abs() > 1.0,
        "different paths, different actions"
    );
    for r in [direct, other] {
        let steps = 80_000;
        let (q, p, quad) = independent(&pend, q0, 0.0, t1, r.p0, steps);
        let ps = r.p0.amax().max(r.p1.amax());
        let amp = r.jacobian[(0, 0)].abs().max(1.0);
        let dp0 = r.error.p0[0] + 4.0 * EPS * (steps as f64).sqrt() * ps;
        assert!((q[0] - q1[0]).abs() <= amp * dp0, "end point {q}");
        assert!(
            (p[0] - r.p1[0]).abs() <= r.error.p1[0] + amp * dp0,
            "p¹ {p} vs {}",
            r.p1
        );
        assert!((quad - r.s).abs() <= r.error.s + r.p1[0].abs() * amp * dp0);
    }
}

/// Planar Kepler problem (μ = 1) from (1, 0) to (−0.3, 1.1) in τ = 1.7 (less than half a period
/// of the connecting orbit): identities and independent integration as for the pendulum; the
/// scales are |p| ≈ 1 and |H| ≈ 0.5, tolerances as there.
#[test]
fn kepler_against_independent_integration() {
    let kep = Kepler2::new(1.0).unwrap();
    let (q0, q1, t0, t1) = ([1.0, 0.0], [-0.3, 1.1], 0.0, 1.7);
    let (s, ds, r) = s_gradient::<_, 2, 6>(&kep, q0, q1, t0, t1).unwrap();
    let (q, p, quad) = independent(&kep, q0, t0, t1, r.p0, 40_000);
    let ps = r.p0.amax().max(r.p1.amax());
    assert!((q - SVector::from(q1)).amax() <= 1e-11, "end point {q}");
    assert!((p - r.p1).amax() <= 1e-11 * ps, "p¹ {p} vs {}", r.p1);
    assert!(
        (quad - r.s).abs() <= 1e-11 * r.s.abs().max(1.0),
        "S {quad} vs {}",
        r.s
    );
    assert!((s - r.s).abs() <= 4.0 * EPS * r.s.abs().max(1.0));
    check_identities(&kep, (q0, q1, t0, t1), &ds, &r, (ps, r.h0.abs(), 1e-11));
    // The Kepler problem is autonomous: S depends on t₁ − t₀ only.
    let shifted = principal_function(
        &kep,
        &SVector::from(q0),
        &SVector::from(q1),
        t0 + 4.5,
        t1 + 4.5,
        &PrincipalOptions::default(),
    )
    .unwrap();
    assert!((shifted.s - r.s).abs() <= 1e-11 * r.s.abs().max(1.0));
}

hamiltonian!(
    /// A periodically forced oscillator, `H = ½p² + ½q² − 0.8 q cos 1.7t` (explicitly time-dependent).
    Forced<1> |_s, t, q, p| p[0] * p[0] * 0.5 + q[0] * q[0] * 0.5 - q[0] * (t * 1.7).cos() * 0.8
);

/// Non-autonomous system: `H₀ ≠ H₁`, and `S` depends on `t₀`, `t₁` separately; the identities
/// `∂S/∂t₁ = −H₁`, `∂S/∂t₀ = +H₀` and the HJ residuals must still hold, with the explicit time
/// dependence carried through the dual time steps. Tolerances as for the pendulum.
#[test]
fn forced_oscillator_time_dependent() {
    let (q0, q1, t0, t1) = ([0.4], [-0.2], 0.3, 2.2);
    let (_, ds, r) = s_gradient::<_, 1, 4>(&Forced, q0, q1, t0, t1).unwrap();
    assert!(
        (r.h0 - r.h1).abs() > 0.1,
        "energy is not conserved: {} {}",
        r.h0,
        r.h1
    );
    let (q, p, quad) = independent(&Forced, q0, t0, t1, r.p0, 20_000);
    let ps = r.p0.amax().max(r.p1.amax());
    let hs = r.h0.abs().max(r.h1.abs());
    assert!((q[0] - q1[0]).abs() <= 1e-11, "end point {q}");
    assert!((p - r.p1).amax() <= 1e-11 * ps, "p¹ {p} vs {}", r.p1);
    assert!(
        (quad - r.s).abs() <= 1e-11 * r.s.abs().max(1.0),
        "S {quad} vs {}",
        r.s
    );
    check_identities(&Forced, (q0, q1, t0, t1), &ds, &r, (ps, hs, 1e-11));
}

// ---------------------------------------------------------------------------------------------
// The propagator
// ---------------------------------------------------------------------------------------------

/// The propagator against the oscillator's exact flow, with the action `S = ∫ L dt` and the
/// sensitivity `∂q(t₁)/∂p⁰ = sin ωτ / ω` from a dual run. Target `1e−12` of the path maxima
/// (|q|, |p| ≤ 1.3, |S| ≲ 1), so `1e−11` absolute; the work counts four evaluations per step.
#[test]
fn propagator_against_exact_oscillator() {
    let w = 1.3;
    let osc = HarmonicOscillator::new(1.0, w).unwrap();
    let (x0, v0, tau) = (0.7, -0.4, 2.9);
    let opts = PropagationOptions::default();
    let r = propagate(
        &osc,
        GradDual64::<1>::from_re(0.0),
        GradDual64::from_re(tau),
        &SVector::from([GradDual64::from_re(x0)]),
        &SVector::from([GradDual64::variable(v0, 0)]),
        &opts,
    )
    .unwrap();
    let (s, c) = (w * tau).sin_cos();
    let (x1, v1) = (x0 * c + v0 * s / w, v0 * c - x0 * w * s);
    // S = ∫ ½(ẋ² − ω²x²) dt = ½ (x¹p¹ − x⁰p⁰) along the motion (virial for quadratic L).
    let action = 0.5 * (x1 * v1 - x0 * v0);
    assert!((r.q[0].value() - x1).abs() <= 1e-11 && (r.p[0].value() - v1).abs() <= 1e-11);
    assert!((r.action.value() - action).abs() <= 1e-11);
    assert!((r.q[0].eps()[0] - s / w).abs() <= 1e-11);
    assert!((r.q[0].value() - x1).abs() <= r.error.q[0] + 8.0 * EPS);
    assert_eq!(r.work.gradients, 4 * r.work.steps);
    // A fixed step count gives the same numbers as the adaptive run that ended there.
    let f = propagate_fixed(
        &osc,
        0.0,
        tau,
        &SVector::from([x0]),
        &SVector::from([v0]),
        r.steps,
    )
    .unwrap();
    assert_eq!(f.q[0], *r.q[0].value());
    // An unreachable tolerance is refused before any work: below the rounding floor
    // ε √(2·initial_steps) of the first run's error estimate it can never be met.
    let e = propagate(
        &osc,
        0.0,
        tau,
        &SVector::from([x0]),
        &SVector::from([v0]),
        &PropagationOptions {
            tolerance: 1e-18,
            ..opts
        },
    );
    assert!(matches!(e, Err(Error::OutOfDomain { .. })), "{e:?}");
}

// ---------------------------------------------------------------------------------------------
// Bad input
// ---------------------------------------------------------------------------------------------

hamiltonian!(
    /// A damped oscillator (non-conservative force): no principal function.
    Damped<1> |_s, _t, q, p| p[0] * p[0] * 0.5 + q[0] * q[0] * 0.5
);

struct Dissipative;
impl Hamiltonian<1> for Dissipative {
    fn hamiltonian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 1>, p: &SVector<D, 1>) -> D {
        Damped.hamiltonian(t, q, p)
    }
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> Option<SVector<D, 1>> {
        Some(-p * D::from(0.1))
    }
}

#[test]
fn bad_input_gives_typed_errors() {
    let osc = HarmonicOscillator::new(1.0, 1.0).unwrap();
    let opts = PrincipalOptions::default();
    let one = SVector::from([1.0]);
    let nan = SVector::from([f64::NAN]);
    let pf = |q0: &SVector<f64, 1>, q1: &SVector<f64, 1>, t0: f64, t1: f64| {
        principal_function(&osc, q0, q1, t0, t1, &opts)
    };
    assert!(
        matches!(pf(&nan, &one, 0.0, 1.0), Err(Error::NonFinite { what, .. }) if what.contains("q⁰"))
    );
    assert!(matches!(
        pf(&one, &nan, 0.0, 1.0),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        pf(&one, &one, f64::INFINITY, 1.0),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        pf(&one, &one, 0.0, f64::NAN),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        pf(&one, &one, 1.0, 1.0),
        Err(Error::OutOfDomain { .. })
    ));
    // Backward time is supported (see backward_time_reverses_the_forward_problem).
    assert!(pf(&one, &one, 1.0, 0.0).is_ok());
    // Options.
    let bad = |o: PrincipalOptions<1>| principal_function(&osc, &one, &one, 0.0, 1.0, &o);
    let prop = PropagationOptions::default();
    for o in [
        PrincipalOptions {
            propagation: PropagationOptions {
                tolerance: 0.0,
                ..prop
            },
            ..opts
        },
        PrincipalOptions {
            propagation: PropagationOptions {
                initial_steps: 0,
                ..prop
            },
            ..opts
        },
        PrincipalOptions {
            propagation: PropagationOptions {
                max_steps: 4,
                ..prop
            },
            ..opts
        },
        PrincipalOptions {
            max_relative_error: f64::NAN,
            ..opts
        },
    ] {
        let e = bad(o);
        assert!(
            matches!(
                e,
                Err(Error::OutOfDomain { .. }
                    | Error::InvalidInput { .. }
                    | Error::NonFinite { .. })
            ),
            "{e:?}"
        );
    }
    let e = bad(PrincipalOptions {
        momentum_guess: Some(nan),
        ..opts
    });
    assert!(matches!(e, Err(Error::NonFinite { .. })), "{e:?}");
    // Non-conservative systems have no principal function.
    let e = principal_function(&Dissipative, &one, &one, 0.0, 1.0, &opts);
    assert!(matches!(e, Err(Error::InvalidInput { .. })), "{e:?}");
    // Leaving the domain: Kepler from the singularity at the origin.
    let kep = Kepler2::new(1.0).unwrap();
    let e = principal_function(
        &kep,
        &SVector::zeros(),
        &SVector::from([1.0, 0.0]),
        0.0,
        1.0,
        &PrincipalOptions::default(),
    );
    assert!(
        matches!(e, Err(Error::NonFinite { .. } | Error::NotConverged { .. })),
        "{e:?}"
    );
    // The propagator rejects NaN and zero steps.
    assert!(matches!(
        propagate_fixed(&osc, 0.0, 1.0, &nan, &one, 8),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        propagate_fixed(&osc, 0.0, 1.0, &one, &one, 0),
        Err(Error::InvalidInput { .. })
    ));
}

/// A tolerance outside `[ε √(2·initial_steps), 1)` is refused at once with the accepted range
/// (before: 10⁻³⁰ was accepted and the principal function returned at whatever accuracy the
/// rounding floor allowed). The floor is the rounding part of the first run's error estimate,
/// `ε √(2M)` at `M = initial_steps` (16 by default: 1.26e−15).
#[test]
fn tolerance_outside_its_range_is_refused() {
    let osc = HarmonicOscillator::new(1.0, 1.0).unwrap();
    let one = SVector::from([1.0]);
    let floor = f64::EPSILON * 32f64.sqrt();
    let clock = std::time::Instant::now();
    for tolerance in [1e-30, 1e-300, 1e-15, 0.99 * floor, 1.0, 1e300] {
        let options = PrincipalOptions {
            propagation: PropagationOptions {
                tolerance,
                ..PropagationOptions::default()
            },
            ..PrincipalOptions::default()
        };
        match principal_function(&osc, &one, &one, 0.0, 1.0, &options) {
            Err(Error::OutOfDomain { domain, .. }) => {
                assert!(domain.contains(&format!("{floor:e}")), "{domain}")
            }
            other => panic!("tolerance {tolerance:e}: {other:?}"),
        }
    }
    assert!(clock.elapsed() < std::time::Duration::from_secs(1));
    // A loose tolerance inside the range is accepted.
    let options = PrincipalOptions {
        propagation: PropagationOptions {
            tolerance: 0.5,
            ..PropagationOptions::default()
        },
        ..PrincipalOptions::default()
    };
    assert!(principal_function(&osc, &one, &one, 0.0, 1.0, &options).is_ok());
}

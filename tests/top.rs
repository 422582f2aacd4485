//! The heavy symmetric top [Ardema 11.2, 17.5]: the system against its Lagrangian, the
//! cubic and its roots, the Hamilton–Jacobi quadratures against the elliptic closed form and
//! against integration of Hamilton's equations, degenerate cases and bad input.
//!
//! Tolerances. The turning-point quadratures run at the engine's default relative tolerance 1e−14;
//! reference values carry 15 significant digits (half a unit in the last place is ≤ 5e−15
//! relative), so comparisons with them use 1e−13 relative. Integrations use classical RK4
//! (global error `C h⁴`); their tolerance is never fixed in advance but estimated by step halving:
//! for runs with `N` and `2N` steps, `e = |x_N − x_{2N}|/15` estimates the error of the finer run
//! (Richardson), and the finer run must agree with the quadrature within `2e` plus a rounding floor
//! (`√steps · ε` times the size of the quantity, here below 1e−12).

mod common;

use approx::assert_relative_eq;
use common::rk4_hamiltonian;
use hamilton_jacobi::lagrangian::{Legendre, NaturalHamiltonian};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::top::motion::{self, Nutation, TopCubic};
use hamilton_jacobi::systems::{ExactFlow, HeavyTop, Invariants};
use hamilton_jacobi::{DualNum, Error, Hamiltonian, Lagrangian};
use proptest::prelude::*;
use std::f64::consts::PI;

type V3 = SVector<f64, 3>;

fn top() -> HeavyTop {
    HeavyTop::new(1.0, 0.5, 1.0).unwrap()
}

/// State released from rest (`θ̇ = φ̇ = 0`) at `θ` with spin `ω_z`.
fn at_rest(top: &HeavyTop, theta: f64, omega_z: f64) -> (V3, V3) {
    (
        SVector::from([0.0, theta, 0.0]),
        top.momenta_from_spin(theta, 0.0, 0.0, omega_z).unwrap(),
    )
}

/// `4K(m)/√(β(u₃ − u₁))`, `m = (u₂ − u₁)/(u₃ − u₁)`: the nutation period in closed form.
fn elliptic_period(c: &TopCubic) -> f64 {
    let [x1, x2, x3] = c.root_offsets();
    4.0 * ellip::ellipk((x2 - x1) / (x3 - x1)).unwrap() / (c.beta() * (x3 - x1)).sqrt()
}

/// RK4 from `(q, p)` over `t` in `n` steps.
fn rk4(top: &HeavyTop, q: V3, p: V3, t: f64, n: usize) -> (V3, V3) {
    rk4_hamiltonian(top, 0.0, q, p, t / n as f64, n, |_, _, _| {})
}

/// `(fine-run value, Richardson error estimate of the fine run)` for RK4 with `n` and `2n` steps.
fn rk4_halving(top: &HeavyTop, q: V3, p: V3, t: f64, n: usize) -> ((V3, V3), (V3, V3)) {
    let (qc, pc) = rk4(top, q, p, t, n);
    let (qf, pf) = rk4(top, q, p, t, 2 * n);
    ((qf, pf), ((qc - qf).abs() / 15.0, (pc - pf).abs() / 15.0))
}

/// `L` of [Ardema 11.2] written out.
fn heavy_top_lagrangian<D: DualNum<f64> + Copy>(
    top: &HeavyTop,
    q: &SVector<D, 3>,
    v: &SVector<D, 3>,
) -> D {
    let (s, c) = q[1].sin_cos();
    let wz = v[2] + v[0] * c;
    (v[1] * v[1] + v[0] * v[0] * s * s) * (0.5 * top.i()) + wz * wz * (0.5 * top.j())
        - c * top.mgl()
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..common::config(0x5eed_0714) })]

    /// `L` is that of [Ardema 11.2]; `H` is its Legendre transform: by the generic Newton Legendre
    /// transform, by the closed form for natural systems, and in the momenta/rates maps (1e−12
    /// relative: a Newton solve on a 3×3 mass matrix whose condition number is at most ~ 1/sin²θ ≤
    /// 1e3 here).
    #[test]
    fn hamiltonian_is_the_legendre_transform_of_the_lagrangian(
        th in 0.05..3.09f64, ph in -3.0..3.0f64, ps in -3.0..3.0f64,
        v in prop::array::uniform3(-4.0..4.0f64),
        (i, j, mgl) in (0.3..3.0f64, 0.2..3.0f64, 0.1..5.0f64),
    ) {
        let top = HeavyTop::new(i, j, mgl).unwrap();
        let (q, v) = (SVector::from([ph, th, ps]), SVector::from(v));
        let lag = top.as_lagrangian();
        let l = lag.value(0.0, &q, &v).unwrap();
        prop_assert!((l - heavy_top_lagrangian(&top, &q, &v)).abs() <= 1e-14 * (1.0 + l.abs()));
        let p = lag.momentum(0.0, &q, &v).unwrap();
        let p_conv = top.momenta(th, v[1], v[0], v[2]).unwrap();
        prop_assert!((p - p_conv).norm() <= 1e-13 * (1.0 + p.norm()), "{p} vs {p_conv}");
        let h = top.value(0.0, &q, &p).unwrap();
        let h_newton = Legendre(lag.clone()).value(0.0, &q, &p).unwrap();
        let h_closed = NaturalHamiltonian(top).value(0.0, &q, &p).unwrap();
        let energy = lag.jacobi_integral(0.0, &q, &v).unwrap();
        for other in [h_newton, h_closed, energy] {
            prop_assert!((h - other).abs() <= 1e-12 * (1.0 + h.abs()), "{h} vs {other}");
        }
        let rates = top.rates(&q, &p).unwrap();
        prop_assert!((rates - v).norm() <= 1e-12 * (1.0 + v.norm()), "{rates} vs {v}");
        let (qd, pd) = top.vector_field(0.0, &q, &p).unwrap();
        let (qd2, pd2) = Legendre(lag).vector_field(0.0, &q, &p).unwrap();
        prop_assert!((qd - qd2).norm() + (pd - pd2).norm() <= 1e-11 * (1.0 + pd.norm() + qd.norm()));
    }

    /// From random states: the turning points bracket cos θ₀, f vanishes there (relative to the
    /// size of its terms), Vieta's sum holds, and the quadrature period equals the elliptic form to
    /// 1e−12 relative (quadrature tolerance 1e−14; `ellipk` is accurate to a few ulps).
    #[test]
    fn cubic_roots_and_period_from_random_states(
        th in 0.05..3.09f64, thd in -2.0..2.0f64, phd in -2.0..2.0f64, wz in -20.0..20.0f64,
    ) {
        let top = top();
        let q = SVector::from([0.0, th, 0.0]);
        let p = top.momenta_from_spin(th, thd, phd, wz).unwrap();
        let nut = Nutation::from_state(&top, &q, &p).unwrap();
        let c = nut.cubic();
        let [u1, u2, u3] = c.roots();
        let u0 = th.cos();
        prop_assert!(-1.0 < u1 && u1 <= u0 && u0 <= u2 && u2 < 1.0 && u3 >= 1.0, "{u1} {u0} {u2} {u3}");
        let [b3, b2, b1, b0] = c.coefficients();
        let size = b3.abs() + b2.abs() + b1.abs() + b0.abs();
        for u in [u1, u2] {
            prop_assert!(c.eval(u).abs() <= 1e-13 * size, "f({u}) = {}", c.eval(u));
        }
        prop_assert!(((u1 + u2 + u3) - (-b2 / b3)).abs() <= 1e-12 * (1.0 + u3.abs()));
        let t = nut.period().unwrap().value;
        prop_assert!((t - elliptic_period(c)).abs() <= 1e-12 * t, "{t} vs {}", elliptic_period(c));
    }
}

#[test]
fn release_from_rest() {
    let top = top();
    let (q, p) = at_rest(&top, PI / 3.0, 5.0);
    assert_relative_eq!(top.gamma(5.0).unwrap(), 2.5);
    let nut = Nutation::from_state(&top, &q, &p).unwrap();
    let c = nut.cubic();
    let [u1, u2, u3] = c.roots();
    // u₂ = cos 60° is the starting point, exactly a root; u₁ from the cubic and from [Ardema 11.24].
    assert_eq!(c.root_offsets()[1], 0.0);
    assert_relative_eq!(u2, 0.5, epsilon = 2e-16);
    assert_relative_eq!(u1, 0.191767987533668, max_relative = 1e-13);
    let u1_formula = motion::release_from_rest(&top, 0.5, 5.0).unwrap();
    assert_relative_eq!(u1, u1_formula, max_relative = 1e-15);
    // f = β(u − u₁)(u₂ − u)(u₃ − u) with u₃ = c + √(…) = 2.93323201246633.
    assert_relative_eq!(u3, 2.933232012466332, max_relative = 1e-14);
    let [th_min, th_max] = c.theta_range();
    assert_relative_eq!(th_min.to_degrees(), 60.0, max_relative = 1e-14);
    assert!(
        (th_max.to_degrees() - 78.944).abs() < 5e-4,
        "{}",
        th_max.to_degrees()
    );
    // φ̇ = γ(u₂ − u)/(1 − u²) ∈ [0, 0.8]: zero at u₂ (cusps), β/γ = 0.8 at u₁.
    assert_eq!(c.precession_rate(u2).unwrap(), 0.0);
    assert_relative_eq!(c.precession_rate(u1).unwrap(), 0.8, max_relative = 1e-14);
    for k in 0..=100 {
        let u = u1 + (u2 - u1) * k as f64 / 100.0;
        let r = c.precession_rate(u).unwrap();
        assert!((0.0..=0.8 + 1e-15).contains(&r), "φ̇({u}) = {r}");
    }
    // Nutation period: quadrature and elliptic closed form.
    let period = nut.period().unwrap();
    assert_relative_eq!(period.value, 2.76392864942787, max_relative = 1e-13);
    assert!(period.error <= 1e-13, "{period:?}");
    assert_relative_eq!(elliptic_period(c), 2.76392864942787, max_relative = 1e-13);
    // Fast-top estimate [Ardema 11.25]: 0.24 against 0.3082 here, 0.0024 against 0.002407686045
    // at γ = 25.
    assert_relative_eq!(
        motion::fast_top_width(&top, 0.5, 5.0).unwrap(),
        0.24,
        max_relative = 1e-15
    );
    assert!((c.nutation_width() - 0.3082).abs() < 5e-5);
    let (q25, p25) = at_rest(&top, PI / 3.0, 50.0);
    let fast = TopCubic::from_state(&top, &q25, &p25).unwrap();
    assert_relative_eq!(
        motion::fast_top_width(&top, 0.5, 50.0).unwrap(),
        0.0024,
        max_relative = 1e-14
    );
    assert_relative_eq!(fast.nutation_width(), 0.002407686045, max_relative = 1e-10);
}

/// [Ardema eq. 11.24] in its textbook form loses digits for fast tops; the crate's form and
/// the root of the cubic (deflated at the starting turning point) agree to rounding.
#[test]
fn release_formula_cancellation_at_gamma_1e4() {
    let top = top();
    let omega = 2e4; // γ = Jω/I = 1e4
    let c = 1e8 / (2.0 * top.beta());
    let naive = c - (1.0 - 2.0 * c * 0.5 + c * c).sqrt();
    let stable = motion::release_from_rest(&top, 0.5, omega).unwrap();
    assert_eq!(format!("{naive:.11}"), "0.49999998510");
    assert_eq!(format!("{stable:.11}"), "0.49999998500");
    // Exact (40-digit arithmetic): u₂ − u₁ = 1.50000003000000150e−8.
    let exact_width = 1.500_000_030_000_001_4e-8;
    assert_relative_eq!(0.5 - stable, exact_width, max_relative = 1e-8);
    let (q, p) = at_rest(&top, PI / 3.0, omega);
    let cubic = TopCubic::from_state(&top, &q, &p).unwrap();
    // The width from the cubic has full relative precision (the offset is computed, not u₂ − u₁).
    assert_relative_eq!(cubic.nutation_width(), exact_width, max_relative = 1e-14);
    assert!(((0.5 - naive) - exact_width).abs() / exact_width > 6e-3);
}

/// Very fast tops (γ = 25, 1e4): quadratures stay accurate; period and precession tend to the
/// gyroscopic limits `2π/γ` (nutation) and `Δφ/T → β/(2γ)·(1 − …)` (mean slow precession).
#[test]
fn very_fast_tops() {
    let top = top();
    for omega in [50.0, 2e4] {
        let (q, p) = at_rest(&top, PI / 3.0, omega);
        let nut = Nutation::from_state(&top, &q, &p).unwrap();
        let t = nut.period().unwrap().value;
        assert_relative_eq!(t, elliptic_period(nut.cubic()), max_relative = 1e-13);
        let gamma = top.gamma(omega).unwrap();
        // Nutation frequency √(β(u₃ − u₁)) → γ: T ≈ 2π/γ to O(β/γ²).
        assert!((t * gamma / (2.0 * PI) - 1.0).abs() < 4.0 * top.beta() / (gamma * gamma));
        // Mean precession ≈ β/(2γ) (slow steady precession) to O(β/γ²).
        let mean = nut.precession_per_period().unwrap().value / t;
        assert!(
            (mean * 2.0 * gamma / top.beta() - 1.0).abs() < 4.0 / gamma,
            "{mean}"
        );
    }
}

#[test]
fn steady_precession_at_30_degrees() {
    let top = top();
    let theta0 = PI / 6.0;
    let sp = top.steady_precession(theta0, 5.0).unwrap();
    let fast = sp.fast.unwrap();
    assert_relative_eq!(fast, 2.40703162555988, max_relative = 1e-14);
    assert_relative_eq!(sp.slow, 0.479719720388246, max_relative = 1e-14);
    let wmin = top.min_spin_for_steady_precession(theta0).unwrap();
    assert_relative_eq!(wmin, 3.72241943640840, max_relative = 1e-14);
    assert!(matches!(
        top.steady_precession(theta0, 0.99 * wmin),
        Err(Error::OutOfDomain { .. })
    ));
    for rate in [fast, sp.slow] {
        let q = SVector::from([0.0, theta0, 0.0]);
        let p = top.momenta_from_spin(theta0, 0.0, rate, 5.0).unwrap();
        // Hamilton's equations (AD vector field, RK4, h = 1e−3, 10 s): θ̇ and ṗ_θ vanish at the
        // steady state up to rounding in ∂H/∂θ, so θ is constant to rounding (not merely to the
        // truncation error), and φ advances at the constant rate exactly as RK4 integrates
        // constants: tolerance 1e−12 (10⁴ steps × a few ulps).
        let mut dev: f64 = 0.0;
        let (qe, _) = rk4_hamiltonian(&top, 0.0, q, p, 1e-3, 10_000, |_, q, _| {
            dev = dev.max((q[1] - theta0).abs());
        });
        assert!(dev <= 1e-12, "max |θ − θ₀| = {dev}");
        assert_relative_eq!(qe[0], 10.0 * rate, max_relative = 1e-12);
        // The cubic has a double root at cos θ₀ (to rounding) and the quadratures reduce to the
        // small-oscillation limit: T = 2π/√(β(u₃ − u₀)), Δφ = φ̇ T.
        let nut = Nutation::from_state(&top, &q, &p).unwrap();
        let c = nut.cubic();
        assert!(c.nutation_width() <= 1e-14, "{}", c.nutation_width());
        let t = nut.period().unwrap().value;
        let x3 = c.root_offsets()[2];
        assert_relative_eq!(t, 2.0 * PI / (c.beta() * x3).sqrt(), max_relative = 1e-13);
        let dphi = nut.precession_per_period().unwrap().value;
        assert_relative_eq!(dphi, rate * t, max_relative = 1e-13);
    }
    // The same double root from the constants alone: exactly u₁ = u₂ = cos θ₀.
    let q = SVector::from([0.0, theta0, 0.0]);
    let p = top.momenta_from_spin(theta0, 0.0, fast, 5.0).unwrap();
    let h = top.value(0.0, &q, &p).unwrap();
    let nut = Nutation::from_constants(&top, h, p[0], p[2]).unwrap();
    let [u1, u2, _] = nut.cubic().roots();
    assert!((u1 - theta0.cos()).abs() < 1e-7 && (u2 - theta0.cos()).abs() < 1e-7);
    assert!(nut.period().unwrap().value.is_finite());
}

#[test]
fn sleeping_top_stability() {
    let top = top();
    assert_eq!(top.critical_spin().unwrap(), 4.0);
    // θ_max from the stable release formula and from the cubic of the state, and the maximum of θ
    // over 60 s of RK4 (h = 1e−3). Sampling error of a maximum: ½|θ̈| (h/2)² ≤ 1.3e−7 (|θ̈| ≤ 2
    // here); truncation error estimated by halving the step over half a nutation period.
    // Conditioning floor near the pole: Hamilton's equations in Euler angles see the initial offset
    // from the vertical through fl(cos θ) (1 − cos θ₀ = 5e−7 carries a relative rounding of 2e−10),
    // the quadratures through the exact 2 sin²(θ₀/2); the resulting spread of θ_max is measured by
    // moving u₂ = cos θ₀ by one ulp either way in the release formula.
    for (omega, reference_deg) in [(3.6, 51.684021184465), (4.4, 0.137532160970)] {
        let (q, p) = at_rest(&top, 1e-3, omega);
        let nut = Nutation::from_state(&top, &q, &p).unwrap();
        let th_max = nut.cubic().theta_range()[1];
        let u1 = motion::release_from_rest(&top, 1e-3f64.cos(), omega).unwrap();
        assert_relative_eq!(th_max.cos(), u1, max_relative = 1e-13);
        assert_relative_eq!(th_max.to_degrees(), reference_deg, max_relative = 1e-10);
        let mut seen: f64 = 0.0;
        rk4_hamiltonian(&top, 0.0, q, p, 1e-3, 60_000, |_, q, _| {
            seen = seen.max(q[1]);
        });
        assert!(
            seen <= th_max + 1e-10 && seen >= th_max - 2e-7,
            "{seen} vs {th_max}"
        );
        if omega > 4.0 {
            assert!(seen.to_degrees() < 0.14);
        } else {
            assert!((seen.to_degrees() - 51.7).abs() < 0.05);
        }
        // At t = T/2 the top is at θ_max with p_θ = 0.
        let u2 = 1e-3f64.cos();
        let floor = [u2.next_down(), u2.next_up()]
            .map(|u| {
                let u1 = motion::release_from_rest(&top, u, omega).unwrap();
                (u1.acos() - th_max).abs()
            })
            .into_iter()
            .fold(0.0, f64::max);
        assert!(floor < 1e-9 * th_max.max(1.0));
        let half = 0.5 * nut.period().unwrap().value;
        let ((qf, _), (eq, _)) = rk4_halving(&top, q, p, half, 20_000);
        assert!(
            (qf[1] - th_max).abs() <= 2.0 * eq[1] + 2.0 * floor,
            "{} vs {th_max}: truncation {}, conditioning {floor}",
            qf[1],
            eq[1]
        );
    }
}

/// The vertical top given by its constants (h = p₂²/2J + mgℓ, p₁ = p₂ = Jω_z): at the
/// critical spin the cubic is −β(1 − u)³ (triple root), below it the vertical is a separatrix,
/// above it the motion is the pole itself, where the Euler angles are singular. Typed errors,
/// never NaN or ∞.
#[test]
fn sleeping_top_constants_are_refused() {
    let top = top();
    for (omega, separatrix) in [(4.0, true), (3.6, true), (4.4, false)] {
        let p2 = top.j() * omega;
        let h = p2 * p2 / (2.0 * top.j()) + top.mgl();
        let e = Nutation::from_constants(&top, h, p2, p2).unwrap_err();
        if separatrix {
            assert!(matches!(e, Error::Separatrix { .. }), "{e}");
        } else {
            assert!(matches!(e, Error::Singular { .. }), "{e}");
        }
    }
    // Near the critical spin, started just off the vertical, the period is long but finite.
    let (q, p) = at_rest(&top, 1e-3, 4.0);
    let t = Nutation::from_state(&top, &q, &p)
        .unwrap()
        .period()
        .unwrap()
        .value;
    assert_relative_eq!(t, 117.248589137642, max_relative = 1e-12);
    // Closer to the vertical the period grows (the triple root is approached). Reference:
    // [Ardema 11.24] and 4K(m)/√(β(u₃ − u₁)) in 40-digit arithmetic at θ₀ = 1e−6 exactly.
    let (q, p) = at_rest(&top, 1e-6, 4.0);
    let nut = Nutation::from_state(&top, &q, &p).unwrap();
    let t = nut.period().unwrap().value;
    assert_relative_eq!(t, 3708.14893099639, max_relative = 1e-13);
    // At θ₀ = 1e−8, p_φ = Jω_z cos θ₀ rounds to p_ψ: the momenta put the state on an orbit through
    // the pole (δ = γ exactly), which is refused rather than integrated across the chart.
    let (q, p) = at_rest(&top, 1e-8, 4.0);
    assert_eq!(p[0], p[2]);
    assert!(matches!(
        Nutation::from_state(&top, &q, &p),
        Err(Error::Singular { .. })
    ));
    assert_relative_eq!(t, elliptic_period(nut.cubic()), max_relative = 1e-12);
}

/// HJ quadratures against Hamilton's equations over one nutation period from release at rest
/// (θ₂ = 60°, ω_z = 5) [Ardema 11.2]: θ and p_θ return to their start; φ and ψ advance by the
/// quadratures. Also the partial quadratures at an intermediate point: the time to reach u and the
/// angles there.
#[test]
fn quadratures_match_integration_over_one_period() {
    let top = top();
    let (q0, p0) = at_rest(&top, PI / 3.0, 5.0);
    let nut = Nutation::from_state(&top, &q0, &p0).unwrap();
    let t = nut.period().unwrap().value;
    let dphi = nut.precession_per_period().unwrap().value;
    let dpsi = nut.spin_per_period().unwrap().value;
    let ((q, p), (eq, ep)) = rk4_halving(&top, q0, p0, t, 1000);
    // The error estimates are real (h⁴ truncation dominates rounding at h = T/2000).
    assert!(eq.max() > 1e-12 && eq.max() < 1e-8, "{eq}");
    assert!(
        (q[1] - q0[1]).abs() <= 2.0 * eq[1] + 1e-12,
        "{} {}",
        q[1] - q0[1],
        eq[1]
    );
    assert!(
        (p[1] - p0[1]).abs() <= 2.0 * ep[1] + 1e-12,
        "{} {}",
        p[1] - p0[1],
        ep[1]
    );
    assert!(
        (q[0] - dphi).abs() <= 2.0 * eq[0] + 1e-12,
        "{} {}",
        q[0] - dphi,
        eq[0]
    );
    assert!(
        (q[2] - dpsi).abs() <= 2.0 * eq[2] + 1e-12,
        "{} {}",
        q[2] - dpsi,
        eq[2]
    );
    // Invariants along the integration, to the same accuracy.
    let i0 = top.invariants(0.0, &q0, &p0).unwrap();
    let i1 = top.invariants(0.0, &q, &p).unwrap();
    assert_eq!(i0[1], i1[1]);
    assert_eq!(i0[2], i1[2]);
    assert!((i0[0].value - i1[0].value).abs() < 1e-9);
    // Partial quadratures: from u₂ the top falls to u = 0.3 in time T/2 − t(0.3).
    let a = nut.advance_to(0.3).unwrap();
    let half = 0.5 * t;
    let fall = half - a.time.value;
    let ((qm, _), (em, _)) = rk4_halving(&top, q0, p0, fall, 1000);
    assert!(
        (qm[1].cos() - 0.3).abs() <= 2.0 * em[1] + 1e-12,
        "{}",
        qm[1].cos() - 0.3
    );
    let phi_fall = 0.5 * dphi - a.precession.value;
    let psi_fall = 0.5 * dpsi - a.spin.value;
    assert!((qm[0] - phi_fall).abs() <= 2.0 * em[0] + 1e-12);
    assert!((qm[2] - psi_fall).abs() <= 2.0 * em[2] + 1e-12);
}

/// The exact flow (time law inverted by Newton on the partial time integral) against RK4, from a
/// turning point and from a generic state moving either way; the invariants hold along it.
#[test]
fn exact_flow_matches_integration() {
    let top = top();
    let generic = |thd: f64| {
        let q = SVector::from([0.3, 1.0, -0.2]);
        (q, top.momenta_from_spin(1.0, thd, 0.4, 6.0).unwrap())
    };
    for (q0, p0) in [at_rest(&top, PI / 3.0, 5.0), generic(0.7), generic(-0.7)] {
        for t in [0.37, 2.0, 5.3] {
            let (qe, pe) = top.exact_flow(0.0, &q0, &p0, t).unwrap();
            let ((q, p), (eq, ep)) = rk4_halving(&top, q0, p0, t, 2000);
            for k in 0..3 {
                assert!(
                    (qe[k] - q[k]).abs() <= 2.0 * eq[k] + 1e-11,
                    "t = {t}, q[{k}]: {qe} vs {q}"
                );
                assert!(
                    (pe[k] - p[k]).abs() <= 2.0 * ep[k] + 1e-11,
                    "t = {t}, p[{k}]: {pe} vs {p}"
                );
            }
            let (i0, i1) = (
                top.invariants(0.0, &q0, &p0).unwrap(),
                top.invariants(0.0, &qe, &pe).unwrap(),
            );
            assert_relative_eq!(i0[0].value, i1[0].value, max_relative = 1e-12);
        }
    }
}

#[test]
fn bad_inputs_are_typed_errors() {
    assert!(matches!(
        HeavyTop::new(0.0, 1.0, 1.0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        HeavyTop::new(1.0, f64::NAN, 1.0),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        HeavyTop::new(1.0, 1.0, -1.0),
        Err(Error::OutOfDomain { .. })
    ));
    let top = top();
    let p = SVector::from([1.0, 0.0, 1.0]);
    // The Euler-angle chart singularity sin θ = 0 (θ = 0, and θ = fl(π) where sin θ = 1.2e−16).
    for theta in [0.0, PI, -PI] {
        let q = SVector::from([0.0, theta, 0.0]);
        assert!(matches!(
            top.value(0.0, &q, &p),
            Err(Error::Singular { .. })
        ));
        assert!(matches!(
            top.vector_field(0.0, &q, &p),
            Err(Error::Singular { .. })
        ));
        assert!(matches!(
            top.invariants(0.0, &q, &p),
            Err(Error::Singular { .. })
        ));
        assert!(matches!(
            top.exact_flow(0.0, &q, &p, 1.0),
            Err(Error::Singular { .. })
        ));
        assert!(matches!(
            top.momenta_from_spin(theta, 0.0, 0.0, 1.0),
            Err(Error::Singular { .. })
        ));
        assert!(matches!(
            top.steady_precession(theta, 5.0),
            Err(Error::Singular { .. })
        ));
    }
    let q = SVector::from([0.0, 1.0, 0.0]);
    assert!(matches!(
        top.value(0.0, &q, &SVector::from([f64::NAN, 0.0, 0.0])),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        top.exact_flow(0.0, &q, &p, f64::INFINITY),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        top.momenta(1.0, 0.0, f64::NAN, 1.0),
        Err(Error::NonFinite { .. })
    ));
    // An orbit through the pole (p_φ = p_ψ, θ̇ ≠ 0): Euler angles fail there.
    let q = SVector::from([0.0, 0.5, 0.0]);
    let p = SVector::from([2.0, -3.0, 2.0]);
    assert!(matches!(
        Nutation::from_state(&top, &q, &p),
        Err(Error::Singular { .. })
    ));
    // Constants that admit no motion: energy below the minimum of the effective potential.
    assert!(matches!(
        Nutation::from_constants(&top, -5.0, 0.3, 1.0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        Nutation::from_constants(&top, 1.0, f64::NAN, 1.0),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        motion::release_from_rest(&top, 1.5, 5.0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        motion::fast_top_width(&top, 0.5, 0.0),
        Err(Error::OutOfDomain { .. })
    ));
    let (q0, p0) = at_rest(&top, PI / 3.0, 5.0);
    let nut = Nutation::from_state(&top, &q0, &p0).unwrap();
    assert!(matches!(
        nut.advance_to(0.9),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        nut.phase_at_time(-1.0),
        Err(Error::OutOfDomain { .. })
    ));
}

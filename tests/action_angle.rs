//! Action–angle variables by quadrature [Ardema 9.2, 17.3]: oscillator and pendulum against closed
//! forms, the AGM period up to the separatrix, and the motion against numerical integration.

mod common;

use approx::assert_relative_eq;
use hamilton_jacobi::hamilton_jacobi::{time_of_flight, ActionAngle};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::pendulum_exact::{exact_state, period_from_gap};
use hamilton_jacobi::systems::{HarmonicOscillator, Pendulum};
use hamilton_jacobi::Error;
use std::f64::consts::{PI, TAU};

/// Oscillator: `J = h/ω`, `T = 2π/ω`, quarter period from the centre to a turning point.
#[test]
fn oscillator_action_and_period() {
    let osc = HarmonicOscillator::new(2.0, 1.5).unwrap();
    for h in [1e-6, 0.3, 7.0] {
        let aa = ActionAngle::new(osc, h, 0.0, -1e3, 1e3).unwrap();
        assert_relative_eq!(aa.action().value, h / 1.5, max_relative = 1e-13);
        assert_relative_eq!(aa.period().value, TAU / 1.5, max_relative = 1e-13);
        let amp = (2.0 * h / (2.0 * 1.5 * 1.5)).sqrt();
        let tof = time_of_flight(osc, h, 0.0, amp, -1e3, 1e3).unwrap();
        assert_relative_eq!(tof.value, TAU / 1.5 / 4.0, max_relative = 1e-13);
        let back = time_of_flight(osc, h, amp, -amp, -1e3, 1e3).unwrap();
        assert_relative_eq!(back.value, -TAU / 1.5 / 2.0, max_relative = 1e-13);
    }
}

/// The pendulum period up to the separatrix, from the exact factorised radicand against the AGM
/// closed form, for amplitudes from 0.1 to δ = π − a = 1e−16, including 15-digit reference periods
/// for δ given exactly. The quadrature's requested tolerance is 1e−14; near the separatrix the
/// integrand has a logarithmic peak of width √δ resolved by bisection, so ≤ 1e−12 is asserted.
#[test]
fn pendulum_period_up_to_the_separatrix() {
    let pen = Pendulum::new(1.0).unwrap();
    for delta in [PI - 0.1, 2.0, 1.0, 1e-2, 1e-4, 1e-6, 1e-10, 1e-12, 1e-16] {
        let aa = ActionAngle::pendulum(pen, delta).unwrap();
        let agm = period_from_gap(1.0, delta).unwrap();
        assert_relative_eq!(aa.period().value, agm, max_relative = 1e-12);
    }
    for (delta, tau) in [
        (1e-2, 26.7386056935052),
        (1e-6, 63.5798083985803),
        (1e-10, 100.421169886481),
        (1e-16, 155.683212118338),
    ] {
        let aa = ActionAngle::pendulum(pen, delta).unwrap();
        assert_relative_eq!(aa.period().value, tau, max_relative = 1e-12);
    }
    assert!(matches!(
        ActionAngle::pendulum(pen, 0.0),
        Err(Error::Separatrix { .. })
    ));
    assert!(ActionAngle::pendulum(pen, f64::NAN).is_err());
    assert!(ActionAngle::pendulum(pen, -1e-3).is_err());
}

/// The pendulum action in closed form, `J = (8n/π)[E(m) − (1 − m)K(m)]`, `m = sin²(a/2)`
/// (Goldstein 10.6), from the `ellip` crate; and `dJ/dh = T/2π` by a Richardson-extrapolated
/// central difference (truncation O(Δ⁴) ≈ 1e−12 at Δ = 1e−3 h, rounding ≈ 1e−14 J/Δ ≈ 1e−11 J).
#[test]
fn pendulum_action_closed_form_and_frequency() {
    let pen = Pendulum::new(1.3).unwrap();
    for a in [0.1f64, 1.0, 2.0, 3.0] {
        let aa = ActionAngle::pendulum(pen, PI - a).unwrap();
        let m = (0.5 * a).sin().powi(2);
        let (k, e) = (ellip::ellipk(m).unwrap(), ellip::ellipe(m).unwrap());
        let closed = 8.0 * 1.3 / PI * (e - (1.0 - m) * k);
        assert_relative_eq!(aa.action().value, closed, max_relative = 1e-13);
        // The generic route (root search + derivative-form reduced radicand) agrees.
        let generic = ActionAngle::new(pen, aa.energy(), 0.0, -PI, PI).unwrap();
        assert_relative_eq!(generic.action().value, closed, max_relative = 1e-13);
        assert_relative_eq!(
            generic.period().value,
            aa.period().value,
            max_relative = 1e-12
        );
        // dJ/dh = 1/ω, as −(dJ/dδ)/(n² sin δ) with J(δ) from the exact route; the step is 1e−3 δ
        // because J's derivatives grow like δ^{-k} towards the separatrix.
        let delta = PI - a;
        let j = |dl: f64| ActionAngle::pendulum(pen, dl).unwrap().action().value;
        let d = 1e-3 * delta.min(1.0);
        let c1 = (j(delta + d) - j(delta - d)) / (2.0 * d);
        let c2 = (j(delta + 2.0 * d) - j(delta - 2.0 * d)) / (4.0 * d);
        let djdh = -(4.0 * c1 - c2) / 3.0 / (1.3 * 1.3 * delta.sin());
        let rel = (djdh * aa.frequency() - 1.0).abs();
        assert!(
            rel < 1e-9,
            "a = {a}: dJ/dh = {djdh}, 1/ω = {}",
            1.0 / aa.frequency()
        );
    }
    // At the separatrix energy the generic route finds a double root: a typed error.
    let sep = ActionAngle::new(pen, 2.0 * 1.3 * 1.3, 0.0, -4.0, 4.0);
    assert!(matches!(sep, Err(Error::Separatrix { .. })), "{sep:?}");
    // Energy below the minimum: no allowed point.
    assert!(ActionAngle::new(pen, -0.1, 0.0, -PI, PI).is_err());
}

/// The angle advances at the rate ω along the exact (elliptic-function) flow: `state(ωt)` from the
/// lower turning point reproduces the exact state, and `angle` inverts `state`.
///
/// Tolerances: the time law is inverted to ≈ 1e−14 T, and the state moves at speed ≤ 2n, so the
/// state agrees to ≈ 1e−13 T; 1e−11 absolute covers T ≤ 60 (δ = 1e−8). The angle from a state is
/// taken from `p` near the turning points, so the round trip is limited by the quadrature
/// tolerance (1e−14 relative) times ωt ≤ 4π.
#[test]
fn angle_advances_uniformly_along_the_exact_flow() {
    let pen = Pendulum::new(1.0).unwrap();
    for nominal in [2.5, 1.0, 1e-3, 1e-8] {
        // The exact flow starts from the double amplitude a = fl(π − δ); its true gap is
        // (π − a) + π_lo (π − a is exact), which is what the quadrature must be given: near the
        // separatrix T ≈ 4 ln(8/δ) and a gap off by 1e−16 moves T by 4e−16/δ.
        let a = PI - nominal;
        let delta = (PI - a) + 1.224_646_799_147_353_2e-16;
        let aa = ActionAngle::pendulum(pen, delta).unwrap();
        assert!(aa.angle(-a, 0.0).unwrap().abs() < 1e-15);
        let (q_mid, p_mid) = aa.state(0.5 * PI).unwrap();
        assert!(
            q_mid.abs() < 1e-12 && p_mid > 0.0,
            "bottom crossing at w = π/2: {q_mid}"
        );
        for t in [0.37, 2.9, 0.6 * aa.period().value, 1.3 * aa.period().value] {
            let (q, p) = exact_state(1.0, -a, 0.0, t).unwrap();
            let w = aa.frequency() * t;
            let (q_hj, p_hj) = aa.state(w).unwrap();
            assert!(
                (q_hj - q).abs() < 1e-11 && (p_hj - p).abs() < 1e-11,
                "δ = {delta}, t = {t}: HJ ({q_hj}, {p_hj}) vs exact ({q}, {p})"
            );
            let back = aa.angle(q_hj, p_hj).unwrap();
            let dw = (back - w + PI).rem_euclid(TAU) - PI;
            assert!(
                dw.abs() < 1e-12,
                "δ = {delta}, t = {t}: angle {back} vs {w}"
            );
        }
    }
}

/// HJ motion against RK4 from the bottom of the swing, for amplitudes 0.1 to π − 1e−12, over an
/// eighth of the period (near the separatrix the motion's sensitivity grows like e^{nt}; over T/8
/// it stays within what RK4's error estimate tracks). Tolerance: twice the Richardson estimate
/// |x_n − x_2n|/15 of the 2n-step solution, plus the quadrature/Newton floor 1e−11.
#[test]
fn pendulum_hj_motion_matches_integration() {
    let pen = Pendulum::new(1.0).unwrap();
    for delta in [PI - 0.1, 1.0, 1e-3, 1e-8, 1e-12] {
        let aa = ActionAngle::pendulum(pen, delta).unwrap();
        let (q0, p0) = aa.state(0.5 * PI).unwrap();
        let t = aa.period().value / 8.0;
        let (q_hj, p_hj) = aa.state(0.5 * PI + aa.frequency() * t).unwrap();
        let run = |n: usize| {
            common::rk4_hamiltonian(
                &pen,
                0.0,
                SVector::from([q0]),
                SVector::from([p0]),
                t / n as f64,
                n,
                |_, _, _| {},
            )
        };
        let n = 4_000;
        let (q1, p1) = run(n);
        let (q2, p2) = run(2 * n);
        let est = ((q1[0] - q2[0]).abs() + (p1[0] - p2[0]).abs()) / 15.0;
        let diff = (q_hj - q2[0]).abs() + (p_hj - p2[0]).abs();
        assert!(
            diff <= 2.0 * est + 1e-11,
            "δ = {delta}: |HJ − RK4| = {diff:e}, RK4 estimate {est:e}"
        );
    }
}

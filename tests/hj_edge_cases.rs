//! Hard cases of the turning-point quadratures: radicands that are small differences of large
//! terms (near-circular orbits, small librations, offset wells), gaps to the separatrix far below
//! 1e−16, starts at turning points, zero-width intervals, huge times — and that every reported
//! error estimate covers the true error.

use hamilton_jacobi::hamilton_jacobi::{
    central_quadrature, time_of_flight, ActionAngle, InverseDistance, RadialMotion,
    SeparatedMotion, SeparatedSystem,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::pendulum_exact::period_from_gap;
use hamilton_jacobi::systems::Pendulum;
use hamilton_jacobi::{DualNum, Result};
use std::f64::consts::PI;

/// Generic route for nearly circular Kepler orbits: `F = 2h + 2/r − k²/r²` cancels terms of size
/// 1 down to `e²`, so `P` carries relative noise ε/e². The result must be correct to within its
/// own error estimate, and the estimate must reflect the noise (not ε).
#[test]
fn near_circular_orbits_report_honest_errors() {
    for e in [1e-2, 1e-3, 1e-5] {
        let k = (1.0f64 - e * e).sqrt();
        let m = RadialMotion::new(InverseDistance::new(1.0).unwrap(), -0.5, k, 1.0, 10.0).unwrap();
        let q = m.half_period();
        let err = (q.value - PI).abs();
        assert!(
            err <= q.error,
            "e = {e}: error {err:e} > estimate {:e}",
            q.error
        );
        // The noise of F relative to e² bounds what is attainable: ~ε/e² (times the interval's
        // share near the roots); the estimate must not be absurdly pessimistic either.
        assert!(
            q.error <= 1e-12 + 1e3 * f64::EPSILON / (e * e),
            "e = {e}: estimate {:e}",
            q.error
        );
    }
    // At e = 1e−7 the radicand's maximum e² ≈ 1e−14 is at its rounding noise: refused (the
    // exact factorisation handles it).
    let k = (1.0f64 - 1e-14).sqrt();
    assert!(RadialMotion::new(InverseDistance::new(1.0).unwrap(), -0.5, k, 1.0, 10.0).is_err());
    let exact = RadialMotion::kepler_elements(1.0, 1.0, 1e-7).unwrap();
    assert!((exact.half_period().value - PI).abs() < 1e-14);
}

hamilton_jacobi::hamiltonian!(Well<1> { centre: f64 } |s, _t, q, p|
    kinetic = p[0] * p[0] * 0.5,
    potential = (q[0] - s.centre) * (q[0] - s.centre) * 0.5);

/// Small librations through the generic route: the pendulum at amplitudes 1e−2 and 1e−3 (the
/// radicand `2(cos q − cos a)` cancels to `a² − q²`) and a harmonic well centred far from the
/// origin (`|x| ≫ L`): periods correct within their reported errors.
#[test]
fn small_and_offset_librations() {
    let pen = Pendulum::new(1.0).unwrap();
    for a in [1e-2f64, 1e-3] {
        let h = 2.0 * (0.5 * a).sin().powi(2);
        let aa = ActionAngle::new(pen, h, 0.0, -PI, PI).unwrap();
        let exact = period_from_gap(1.0, PI - a).unwrap();
        let t = aa.period();
        let budget = t.error + 8.0 * f64::EPSILON * exact;
        assert!(
            (t.value - exact).abs() <= budget,
            "a = {a}: {} vs {exact} (± {:e})",
            t.value,
            t.error
        );
    }
    for centre in [1.0, 1e3] {
        let aa =
            ActionAngle::new(Well { centre }, 1e-6, centre, centre - 10.0, centre + 10.0).unwrap();
        let t = aa.period();
        assert!(
            (t.value - 2.0 * PI).abs() <= t.error,
            "centre {centre}: {} ± {:e}",
            t.value,
            t.error
        );
    }
}

/// Near the separatrix, far beyond double precision's π: gaps 1e−36 … 1e−280 (the exact radicand
/// takes δ itself) against the AGM, and the refusal below `MIN_GAP`.
#[test]
fn pendulum_gaps_far_below_epsilon() {
    let pen = Pendulum::new(1.0).unwrap();
    for delta in [1e-36, 1e-100, 1e-280] {
        let aa = ActionAngle::pendulum(pen, delta).unwrap();
        let exact = period_from_gap(1.0, delta).unwrap();
        let t = aa.period();
        // The AGM reference carries its own rounding (a few ε of the period).
        assert!(
            (t.value - exact).abs() <= t.error + 8.0 * f64::EPSILON * exact,
            "δ = {delta:e}: {} vs {exact} (± {:e})",
            t.value,
            t.error
        );
        assert!((t.value - exact).abs() <= 1e-13 * exact);
    }
    assert!(ActionAngle::pendulum(pen, 1e-300).is_err());
}

/// The turning-point scan starts on the scale of the motion, not of |x|: a pendulum well at
/// q = 2000π with wide search bounds.
#[test]
fn scan_far_from_the_origin() {
    let pen = Pendulum::new(1.0).unwrap();
    let c = 2000.0 * PI;
    let a: f64 = 1.0;
    let h = 2.0 * (0.5 * a).sin().powi(2);
    let aa = ActionAngle::new(pen, h, c, c - 1e4, c + 1e4).unwrap();
    let (q1, q2) = aa.turning_points();
    assert!(
        (q1 - (c - a)).abs() < 1e-11 && (q2 - (c + a)).abs() < 1e-11,
        "({q1}, {q2})"
    );
    let exact = period_from_gap(1.0, PI - a).unwrap();
    assert!((aa.period().value - exact).abs() <= aa.period().error + 8.0 * f64::EPSILON * exact);
}

/// States at turning points are accepted (p = 0 with F rounding to ±ε), angles work at h = 0,
/// zero-width intervals give zero, huge times are refused.
#[test]
fn turning_points_zero_widths_and_huge_times() {
    #[derive(Clone, Debug)]
    struct KeplerPolar;
    impl SeparatedSystem<2> for KeplerPolar {
        fn radicand<D: DualNum<f64> + Copy>(&self, r: usize, x: D, c: &SVector<D, 2>) -> D {
            match r {
                0 => c[0] * 2.0 + x.recip() * 2.0 - c[1] * c[1] / (x * x),
                _ => c[1] * c[1],
            }
        }
        fn constants(&self, q: &SVector<f64, 2>, p: &SVector<f64, 2>) -> Result<SVector<f64, 2>> {
            let h = 0.5 * (p[0] * p[0] + p[1] * p[1] / (q[0] * q[0])) - 1.0 / q[0];
            Ok(SVector::from([h, p[1]]))
        }
        fn ignorable(&self, r: usize) -> bool {
            r == 1
        }
        fn search_bounds(&self, _r: usize) -> (f64, f64) {
            (1e-9, 1e9)
        }
    }
    // Periapsis states (p_r = 0) of 100 orbits.
    for i in 0..100 {
        let r = 0.3 + 0.01 * i as f64;
        let v = (1.5 / r).sqrt(); // above circular speed: r is the periapsis
        let m = SeparatedMotion::new(
            KeplerPolar,
            0.0,
            &SVector::from([r, 0.0]),
            &SVector::from([0.0, r * v]),
        );
        let m = m.unwrap_or_else(|e| panic!("r = {r}: {e}"));
        let (q, _) = m.state_at(0.0).unwrap();
        assert!((q[0] - r).abs() < 1e-12 * r);
        assert!(m.state_at(1e17).is_err());
    }
    // h = 0: V = q²/2 − 1 at h = 0.
    hamilton_jacobi::hamiltonian!(Shifted<1> |_s, _t, q, p|
        kinetic = p[0] * p[0] * 0.5,
        potential = q[0] * q[0] * 0.5 - 1.0);
    let aa = ActionAngle::new(Shifted, 0.0, 0.0, -5.0, 5.0).unwrap();
    for k in 0..100 {
        let w = 0.0628 * k as f64;
        let (q, p) = aa.state(w).unwrap();
        let back = aa.angle(q, p).unwrap();
        let d = (back - w + PI).rem_euclid(2.0 * PI) - PI;
        assert!(d.abs() < 1e-12, "w = {w}: {back}");
    }
    // A state at the turning point itself (p = 0) builds the action–angle variables. The
    // libration is 2e−6 wide at x ≈ 10, so positions carry ε·10/2e−6 ≈ 1e−9 relative error (the
    // offset loss), which the estimate must cover.
    let at_turn =
        ActionAngle::from_state(Well { centre: 10.0 }, 10.0 + 1e-6, 0.0, 0.0, 20.0).unwrap();
    let t = at_turn.period();
    assert!(
        (t.value - 2.0 * PI).abs() <= t.error,
        "{} ± {:e}",
        t.value,
        t.error
    );
    assert!(t.error < 1e-6);
    // Zero-width intervals.
    let (dt, dth) = central_quadrature(
        InverseDistance::new(1.0).unwrap(),
        1.0,
        -0.5,
        0.75f64.sqrt(),
        1.5,
        1.5,
        10.0,
    )
    .unwrap();
    assert_eq!((dt.value, dth.value), (0.0, 0.0));
    assert_eq!(
        time_of_flight(Shifted, 0.0, 2f64.sqrt(), 2f64.sqrt(), -5.0, 5.0)
            .unwrap()
            .value,
        0.0
    );
    // Huge times.
    let m = RadialMotion::kepler_elements(1.0, 1.0, 0.5).unwrap();
    assert!(m.state_at(1e17).is_err());
    assert!(m.state_at(1e6 * 2.0 * PI).is_ok());
}

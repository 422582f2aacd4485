//! Central forces by Hamilton–Jacobi separation [Ardema 10.1], from e → 0 to e → 1, and the
//! same motion by numerical integration of Hamilton's equations.

mod common;

use approx::assert_relative_eq;
use hamilton_jacobi::hamilton_jacobi::{
    central_quadrature, hj_residual, CentralPotential, ElementConvention, Elements,
    InverseDistance, KeplerPolarIntegral, RadialMotion,
};
use hamilton_jacobi::nalgebra::{SVector, Vector2};
use hamilton_jacobi::systems::kepler;
use hamilton_jacobi::systems::Kepler2;
use hamilton_jacobi::{hamiltonian, DualNum, Error};
use proptest::prelude::*;
use std::f64::consts::PI;

hamiltonian!(
    /// Kepler in polar coordinates `(r, θ)`, μ = 1.
    KeplerPolar<2> |_s, _t, q, p| (p[0] * p[0] + p[1] * p[1] / (q[0] * q[0])) * 0.5 - q[0].recip()
);

/// Central-force quadratures [Ardema 10.1, 15.6] for Kepler, e = 0.5, μ = a = 1. Both run through
/// the turning points; the requested relative tolerance is 1e−14, so ≤ 1e−12 leaves room for the
/// rounding of the integrands.
#[test]
fn kepler_half_period_and_swept_angle() {
    let exact = RadialMotion::kepler_elements(1.0, 1.0, 0.5).unwrap();
    assert_relative_eq!(exact.half_period().value, PI, max_relative = 1e-12);
    assert_relative_eq!(exact.apsidal_angle().value, PI, max_relative = 1e-12);
    // The same through the generic root search and derivative-form reduced radicand.
    let (h, k) = (-0.5, (0.75f64).sqrt());
    let generic = RadialMotion::new(InverseDistance::new(1.0).unwrap(), h, k, 1.0, 10.0).unwrap();
    assert_relative_eq!(generic.periapsis(), 0.5, max_relative = 1e-15);
    assert_relative_eq!(generic.apoapsis(), 1.5, max_relative = 1e-15);
    assert_relative_eq!(generic.half_period().value, PI, max_relative = 1e-12);
    assert_relative_eq!(generic.apsidal_angle().value, PI, max_relative = 1e-12);
    // And `central_quadrature` with a mass: m = 2, K = m k, h_total = m h.
    let (dt, dth) = central_quadrature(Scaled(2.0), 2.0, 2.0 * h, 2.0 * k, 0.5, 1.5, 10.0).unwrap();
    assert_relative_eq!(dt.value, PI, max_relative = 1e-12);
    assert_relative_eq!(dth.value, PI, max_relative = 1e-12);
    // Backwards leg: negative.
    let (dt_back, _) =
        central_quadrature(Scaled(2.0), 2.0, 2.0 * h, 2.0 * k, 1.5, 0.5, 10.0).unwrap();
    assert_relative_eq!(dt_back.value, -PI, max_relative = 1e-12);
}

/// `V = −m μ/r` with μ = 1 (the potential of a mass m).
#[derive(Clone, Copy)]
struct Scaled(f64);
impl CentralPotential for Scaled {
    fn potential<D: DualNum<f64> + Copy>(&self, r: D) -> D {
        r.recip() * -self.0
    }
}

/// Near e → 0 and e → 1: e = 1e−12 (apsides merge to 1e−12) and e = 1 − 1e−9 (periapsis 1e−9,
/// the swept angle concentrated in s ≲ 4.5e−5). Half period and apsidal angle are π for every e.
#[test]
fn kepler_quadratures_at_extreme_eccentricities() {
    for e in [0.0, 1e-12, 1e-6, 0.9, 0.99, 1.0 - 1e-9] {
        let m = RadialMotion::kepler_elements(1.0, 1.0, e).unwrap();
        assert_relative_eq!(m.half_period().value, PI, max_relative = 1e-12);
        assert_relative_eq!(m.apsidal_angle().value, PI, max_relative = 1e-12);
        // Radial action J_r = μ/√(−2h) − |k| [Ardema 17.5]; relative to √(μa) = 1 (J_r → 0 as
        // e → 0, so the comparison is absolute).
        let k = m.angular_momentum();
        let jr = m.radial_action().unwrap().value;
        assert!(
            (jr - (1.0 - k)).abs() < 1e-13,
            "e = {e}: J_r {jr} vs {}",
            1.0 - k
        );
    }
    // From (h, k): the circular orbit's e² rounds to ±ε and is accepted as e = 0.
    let circ = RadialMotion::kepler(1.0, -0.5, 1.0).unwrap();
    assert_eq!(circ.periapsis(), circ.apoapsis());
    assert_relative_eq!(circ.half_period().value, PI, max_relative = 1e-14);
    // Below the circular minimum: an error naming e², not a NaN.
    assert!(matches!(
        RadialMotion::kepler(1.0, -0.5, 1.01),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(RadialMotion::kepler(1.0, 0.1, 1.0).is_err());
    assert!(RadialMotion::kepler(1.0, -0.5, 0.0).is_err());
    assert!(RadialMotion::kepler(1.0, f64::NAN, 1.0).is_err());
    assert!(RadialMotion::kepler_elements(1.0, 1.0, 1.0).is_err());
}

/// Non-Kepler potentials with closed forms: the isotropic oscillator `V = ½ω²r²` (half radial
/// period π/(2ω), apsidal angle π/2) and `V = −μ/r + c/r²` (apsidal angle π/√(1 + 2c/k²), the
/// inverse-cube force that still integrates in circular functions [Ardema eq. 10.19]).
#[test]
fn power_law_closed_forms() {
    struct Oscillator(f64);
    impl CentralPotential for Oscillator {
        fn potential<D: DualNum<f64> + Copy>(&self, r: D) -> D {
            r * r * (0.5 * self.0 * self.0)
        }
    }
    struct KeplerPlusInverseSquare(f64);
    impl CentralPotential for KeplerPlusInverseSquare {
        fn potential<D: DualNum<f64> + Copy>(&self, r: D) -> D {
            -r.recip() + (r * r).recip() * self.0
        }
    }
    let w = 1.7;
    let m = RadialMotion::new(Oscillator(w), 3.0, 0.8, 1.0, 100.0).unwrap();
    assert_relative_eq!(m.half_period().value, PI / (2.0 * w), max_relative = 1e-12);
    assert_relative_eq!(m.apsidal_angle().value, PI / 2.0, max_relative = 1e-12);
    let (c, k) = (0.05, 0.9);
    let m = RadialMotion::new(KeplerPlusInverseSquare(c), -0.4, k, 1.0, 100.0).unwrap();
    let expected = PI / (1.0 + 2.0 * c / (k * k)).sqrt();
    assert_relative_eq!(m.apsidal_angle().value, expected, max_relative = 1e-12);
    // Unbounded motion has no upper apsis: a typed error.
    assert!(RadialMotion::new(InverseDistance::new(1.0).unwrap(), 0.1, 1.0, 1.0, 1e6).is_err());
}

/// RK4 on the Cartesian Kepler problem from periapsis to `t` with `n` steps.
fn rk4_kepler(e: f64, t: f64, n: usize) -> (Vector2<f64>, Vector2<f64>) {
    let h = Kepler2::new(1.0).unwrap();
    let rp = 1.0 - e;
    let vp = ((1.0 + e) / (1.0 - e)).sqrt();
    let (q, p) = common::rk4_hamiltonian(
        &h,
        0.0,
        SVector::from([rp, 0.0]),
        SVector::from([0.0, vp]),
        t / n as f64,
        n,
        |_, _, _| {},
    );
    (q, p)
}

/// The motion by HJ quadratures (time law inverted by Newton) against RK4 and against Kepler's
/// equation, for e = 0, 0.5, 0.9, 0.99, over both legs and into the second revolution.
///
/// RK4 tolerance: Richardson — the error of the 2n-step solution is ≈ |x_n − x_2n|/15; the
/// assertion allows twice that (pre-asymptotic slack) plus the 1e−11 quadrature/Newton floor.
#[test]
fn hj_motion_matches_integration_and_keplers_equation() {
    for (e, n) in [(0.0, 2_000), (0.5, 8_000), (0.9, 40_000), (0.99, 400_000)] {
        let motion = RadialMotion::kepler_elements(1.0, 1.0, e).unwrap();
        let period = 2.0 * PI;
        for frac in [0.3, 0.77, 1.4] {
            let t = frac * period;
            let (r, rdot, theta) = motion.state_at(t).unwrap();
            let hj = Vector2::new(r * theta.cos(), r * theta.sin());
            // Kepler's equation (exact f and g functions).
            let (rp, vp) = (1.0 - e, ((1.0 + e) / (1.0 - e)).sqrt());
            let (exact, v_exact) =
                kepler::propagate(1.0, &Vector2::new(rp, 0.0), &Vector2::new(0.0, vp), t).unwrap();
            assert!(
                (hj - exact).norm() < 1e-11,
                "e = {e}, t = {t}: HJ {hj:?} vs Kepler {exact:?}"
            );
            assert!((rdot - v_exact.dot(&exact) / exact.norm()).abs() < 1e-10);
            if frac > 1.0 && e > 0.95 {
                continue; // one period of RK4 at e = 0.99 suffices; keep the test fast
            }
            let (q1, _) = rk4_kepler(e, t, n);
            let (q2, _) = rk4_kepler(e, t, 2 * n);
            let richardson = (q1 - q2).norm() / 15.0;
            let diff = (hj - q2).norm();
            assert!(
                diff <= 2.0 * richardson + 1e-11,
                "e = {e}, t = {t}: |HJ − RK4| = {diff:e}, RK4 error estimate {richardson:e}"
            );
            assert!(
                richardson < 1e-6,
                "e = {e}: RK4 too coarse ({richardson:e})"
            );
        }
    }
}

/// The shipped Kepler complete integral: its radial function against the quadrature (between
/// interior radii: the closed form's asin terms are ill-conditioned at the apsides), and Jacobi's
/// theorem along the outbound leg against the quadrature motion.
#[test]
fn kepler_polar_complete_integral() {
    let s = KeplerPolarIntegral::new(1.0).unwrap();
    let motion = RadialMotion::kepler_elements(1.0, 1.0, 0.6).unwrap();
    let (h, k) = (motion.energy(), motion.angular_momentum());
    // A partial quadrature equals the closed form between two interior radii.
    let (r0, r1) = (0.55, 1.3);
    let libr = motion.libration();
    let partial =
        libr.sqrt_integral_to(r1).unwrap().value - libr.sqrt_integral_to(r0).unwrap().value;
    assert_relative_eq!(
        partial,
        s.radial(r1, h, k) - s.radial(r0, h, k),
        max_relative = 1e-13
    );
    // Jacobi's theorem: elements at t = 0.2 on the outbound leg, state at t = 1.1 (still outbound,
    // half period π).
    let el = Elements::new(s, ElementConvention::AlphaMomenta);
    let (r_a, rdot_a, th_a) = motion.state_at(0.2).unwrap();
    let q = SVector::from([r_a, th_a]);
    let p = SVector::from([rdot_a, k]);
    let (alpha, beta) = el.elements(0.2, &q, &p).unwrap();
    assert_relative_eq!(alpha[0], h, max_relative = 1e-13);
    assert_relative_eq!(alpha[1], k, max_relative = 1e-13);
    // β₁ = ∂S/∂h = −t + ∂K_r/∂h. The closed-form K_r has K_r(r_p) = −(π/2) J_r(h, k), so
    // ∂K_r/∂h = (t − t_p) − (π/2) ∂J_r/∂h = (t − t_p) − T/4: with t_p = 0 and T = 2π, β₁ = −π/2.
    assert_relative_eq!(beta[0], -PI / 2.0, max_relative = 1e-12);
    let (q1, p1) = el.state(1.1, &alpha, &beta).unwrap();
    let (r_b, rdot_b, th_b) = motion.state_at(1.1).unwrap();
    assert_relative_eq!(q1[0], r_b, max_relative = 1e-12);
    assert_relative_eq!(q1[1], th_b, max_relative = 1e-12);
    assert_relative_eq!(p1[0], rdot_b, max_relative = 1e-11);
}

proptest! {
    #![proptest_config(common::config(0x4a13))]
    /// HJ residual of the shipped Kepler integral at random points of its domain.
    #[test]
    fn kepler_integral_solves_hj(a in 0.3f64..5.0, e in 0.01f64..0.99, x in 0.02f64..0.98,
                                  theta in -3.0f64..3.0, t in -10.0f64..10.0, sign in prop::bool::ANY) {
        let s = KeplerPolarIntegral::new(1.0).unwrap();
        let h = -0.5 / a;
        let k = (a * (1.0 - e * e)).sqrt() * if sign { 1.0 } else { -1.0 };
        let r = a * (1.0 - e) + x * 2.0 * a * e;
        let res = hj_residual(&s, &KeplerPolar, t, &SVector::from([r, theta]), &SVector::from([h, k])).unwrap();
        // Terms of H are O(1/r) ≤ 1/(a(1−e)); rounding of √R/r and the asin derivatives.
        let scale = 1.0 / (a * (1.0 - e));
        prop_assert!(res.abs() <= 1e-12 * scale.max(1.0), "residual {res:e}");
    }
}

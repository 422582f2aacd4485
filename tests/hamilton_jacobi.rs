//! Complete integrals, Jacobi's theorem [Ardema 17.2, 17.4]: projectile, oscillator, HJ residuals.

mod common;

use approx::assert_relative_eq;
use hamilton_jacobi::hamilton_jacobi::{
    completeness, hj_residual, ElementConvention, Elements, OscillatorIntegral, ProjectileIntegral,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::{HarmonicOscillator, Projectile};
use proptest::prelude::*;

const G: f64 = 9.81;

/// The projectile's complete integral [Ardema 17.4] (ascending branch), shipped as
/// `ProjectileIntegral`.
fn projectile_integral() -> ProjectileIntegral {
    ProjectileIntegral::new(G).unwrap()
}

/// The oscillator's complete integral [Ardema 17.4], shipped as `OscillatorIntegral`.
fn oscillator_integral(n: f64) -> OscillatorIntegral {
    OscillatorIntegral::new(n).unwrap()
}

#[test]
fn projectile_complete_integral() {
    let el = Elements::new(projectile_integral(), ElementConvention::AlphaMomenta);
    let (u0, v0) = (5.0, 12.31);
    // Initial data at t = 0: γ = u₀, k = y₀ + v₀²/(2g) = 7.72355249745158, β = (x₀, −v₀).
    let (alpha, beta) = el
        .elements(0.0, &SVector::from([0.0, 0.0]), &SVector::from([u0, v0]))
        .unwrap();
    assert_relative_eq!(alpha[0], u0, epsilon = 1e-15);
    assert_relative_eq!(alpha[1], 7.72355249745158, epsilon = 1e-14);
    assert!(beta[0].abs() < 1e-15);
    assert_relative_eq!(beta[1], -v0, epsilon = 1e-14);
    // At t = 1 (before the apex): (x, y) = (5, 7.405), p = (5, 2.5).
    let (q, p) = el.state(1.0, &alpha, &beta).unwrap();
    assert_relative_eq!(q[0], 5.0, epsilon = 1e-13);
    assert_relative_eq!(q[1], 7.405, epsilon = 1e-13);
    assert_relative_eq!(p[0], 5.0, epsilon = 1e-13);
    assert_relative_eq!(p[1], 2.5, epsilon = 1e-12);
    // Under the opposite convention β = −∂S/∂α: β₁ = −x₀.
    let el18 = Elements::new(projectile_integral(), ElementConvention::AlphaCoordinates);
    let (a2, b2) = el18
        .elements(0.0, &SVector::from([0.7, 0.0]), &SVector::from([u0, v0]))
        .unwrap();
    assert_relative_eq!(a2[0], u0, epsilon = 1e-15);
    assert_relative_eq!(b2[0], -0.7, epsilon = 1e-15);
    // After the apex the ascending S has no preimage: the state at t = 2 is refused, not wrong.
    assert!(el.state(2.0, &alpha, &beta).is_err());
    // The descending branch with the same elements reaches the end point of the projectile's
    // principal function [Ardema 17.1] at t = 2: (x, y) = (10, 5), p = (5, −7.31).
    let down = Elements::new(
        ProjectileIntegral::descending(G).unwrap(),
        ElementConvention::AlphaMomenta,
    );
    let (q2, p2) = down.state(2.0, &alpha, &beta).unwrap();
    assert_relative_eq!(q2[0], 10.0, epsilon = 1e-13);
    assert_relative_eq!(q2[1], 5.0, epsilon = 1e-12);
    assert_relative_eq!(p2[0], 5.0, epsilon = 1e-13);
    assert_relative_eq!(p2[1], -7.31, epsilon = 1e-12);
    // HJ residual and completeness.
    let h = Projectile::new(1.0, G).unwrap();
    let r = hj_residual(
        &projectile_integral(),
        &h,
        0.4,
        &SVector::from([1.0, 2.0]),
        &alpha,
    )
    .unwrap();
    assert!(r.abs() < 1e-13, "residual {r}");
    assert!(
        completeness(
            &projectile_integral(),
            0.4,
            &SVector::from([1.0, 2.0]),
            &alpha
        )
        .unwrap()
        .abs()
            > 0.1
    );
}

#[test]
fn oscillator_complete_integral() {
    let n = 2.0;
    let el = Elements::new(oscillator_integral(n), ElementConvention::AlphaMomenta);
    let (amp, t0) = (1.5, 0.3);
    // x = α sin n(t − t₀), β = −n² α t₀; the state on the ascending branch (cos > 0).
    for t in [0.35, 0.5, 0.9] {
        let (q, p) = el
            .state(
                t,
                &SVector::from([amp]),
                &SVector::from([-n * n * amp * t0]),
            )
            .unwrap();
        let ph = n * (t - t0);
        assert_relative_eq!(q[0], amp * ph.sin(), epsilon = 1e-14);
        assert_relative_eq!(p[0], n * amp * ph.cos(), epsilon = 1e-13);
        let (a, b) = el.elements(t, &q, &p).unwrap();
        assert_relative_eq!(a[0], amp, epsilon = 1e-14);
        assert_relative_eq!(b[0], -n * n * amp * t0, epsilon = 1e-13);
    }
    let h = HarmonicOscillator::new(1.0, n).unwrap();
    let r = hj_residual(
        &oscillator_integral(n),
        &h,
        0.7,
        &SVector::from([0.4]),
        &SVector::from([amp]),
    )
    .unwrap();
    assert!(r.abs() < 1e-14, "residual {r}");
}

proptest! {
    #![proptest_config(common::config(0x5eed_0007))]

    /// The shipped complete integrals satisfy the HJ equation to rounding at random points of
    /// their domain (a few roundings of O(10–100) terms).
    #[test]
    fn hj_residuals_vanish(t in -2.0..2.0f64, x in -3.0..3.0f64, y in -2.0..2.0f64,
                           gamma in -5.0..5.0f64, above in 0.01..5.0f64,
                           n in 0.2..3.0f64, amp in 0.1..2.0f64, frac in -0.99..0.99f64) {
        let h = Projectile::new(1.0, G).unwrap();
        let alpha = SVector::from([gamma, y + above]);
        let scale = gamma * gamma + G * (y.abs() + above);
        for s in [projectile_integral(), ProjectileIntegral::descending(G).unwrap()] {
            let r = hj_residual(&s, &h, t, &SVector::from([x, y]), &alpha).unwrap();
            prop_assert!(r.abs() <= 1e-13 * (1.0 + scale), "projectile residual {r}");
        }
        let osc = HarmonicOscillator::new(1.0, n).unwrap();
        let r = hj_residual(&oscillator_integral(n), &osc, t, &SVector::from([frac * amp]), &SVector::from([amp])).unwrap();
        prop_assert!(r.abs() <= 1e-13 * (1.0 + n * n * amp * amp), "oscillator residual {r}");
    }
}

//! Complete integrals and Jacobi's theorem: SPEC T3, T4, HJ residuals (M53, M54).

mod common;

use approx::assert_relative_eq;
use hamilton_jacobi::hamilton_jacobi::{
    completeness, hj_residual, CompleteIntegral, ElementConvention, Elements,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::{HarmonicOscillator, Projectile};
use hamilton_jacobi::DualNum;
use proptest::prelude::*;

const G: f64 = 9.81;

/// T3: S = −(γ²/2 + g k) t + γ x − (2/3) √(2g) (k − y)^{3/2}, α = (γ, k) (ascending branch).
struct ProjectileS;
impl CompleteIntegral<2> for ProjectileS {
    fn action<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 2>, a: &SVector<D, 2>) -> D {
        let (gamma, k) = (a[0], a[1]);
        let d = k - q[1];
        -(gamma * gamma * 0.5 + k * G) * t + gamma * q[0]
            - d * d.sqrt() * ((2.0 / 3.0) * (2.0 * G).sqrt())
    }
}

/// T4: S = −½ n² α² t + (n/2)(x √(α² − x²) + α² asin(x/α)), H = ½(p² + n² x²).
struct OscillatorS {
    n: f64,
}
impl CompleteIntegral<1> for OscillatorS {
    fn action<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 1>, a: &SVector<D, 1>) -> D {
        let (x, al) = (q[0], a[0]);
        let n = self.n;
        -(al * al) * t * (0.5 * n * n)
            + (x * (al * al - x * x).sqrt() + al * al * (x / al).asin()) * (0.5 * n)
    }
    /// α is the amplitude √(x² + p²/n²): exact, and inside the domain α ≥ |x|.
    fn alpha_guess(
        &self,
        _t: f64,
        q: &SVector<f64, 1>,
        p: &SVector<f64, 1>,
    ) -> Option<SVector<f64, 1>> {
        Some(SVector::from([q[0].hypot(p[0] / self.n)]))
    }
}

#[test]
fn t3_projectile_complete_integral() {
    let el = Elements::new(ProjectileS, ElementConvention::AlphaMomenta);
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
    let el18 = Elements::new(ProjectileS, ElementConvention::AlphaCoordinates);
    let (a2, b2) = el18
        .elements(0.0, &SVector::from([0.7, 0.0]), &SVector::from([u0, v0]))
        .unwrap();
    assert_relative_eq!(a2[0], u0, epsilon = 1e-15);
    assert_relative_eq!(b2[0], -0.7, epsilon = 1e-15);
    // After the apex the ascending S has no preimage: the state at t = 2 is refused, not wrong.
    assert!(el.state(2.0, &alpha, &beta).is_err());
    // HJ residual and completeness.
    let h = Projectile::new(1.0, G).unwrap();
    let r = hj_residual(&ProjectileS, &h, 0.4, &SVector::from([1.0, 2.0]), &alpha).unwrap();
    assert!(r.abs() < 1e-13, "residual {r}");
    assert!(
        completeness(&ProjectileS, 0.4, &SVector::from([1.0, 2.0]), &alpha)
            .unwrap()
            .abs()
            > 0.1
    );
}

#[test]
fn t4_oscillator_complete_integral() {
    let n = 2.0;
    let el = Elements::new(OscillatorS { n }, ElementConvention::AlphaMomenta);
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
        &OscillatorS { n },
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
        let r = hj_residual(&ProjectileS, &h, t, &SVector::from([x, y]), &alpha).unwrap();
        let scale = gamma * gamma + G * (y.abs() + above);
        prop_assert!(r.abs() <= 1e-13 * (1.0 + scale), "projectile residual {r}");
        let osc = HarmonicOscillator::new(1.0, n).unwrap();
        let r = hj_residual(&OscillatorS { n }, &osc, t, &SVector::from([frac * amp]), &SVector::from([amp])).unwrap();
        prop_assert!(r.abs() <= 1e-13 * (1.0 + n * n * amp * amp), "oscillator residual {r}");
    }
}

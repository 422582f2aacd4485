//! SPEC M9: the action `S = ∫ L dt` on an arbitrary path, against the harmonic oscillator's
//! closed forms: the action of the true path, the first variation zero on it (Hamilton's
//! principle), and the second variation `½ ε² ∫(m η̇² − k η²) dt`, positive below half a period
//! and negative beyond.

use hamilton_jacobi::action::action;
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::num_dual::Dual64;
use hamilton_jacobi::{DualNum, Error, Lagrangian};
use std::f64::consts::PI;

/// `L = ½ m q̇² − ½ k q²`.
struct Oscillator {
    m: f64,
    k: f64,
}

impl Lagrangian<1> for Oscillator {
    fn lagrangian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        qdot: &SVector<D, 1>,
    ) -> D {
        qdot[0] * qdot[0] * (0.5 * self.m) - q[0] * q[0] * (0.5 * self.k)
    }
}

const OSC: Oscillator = Oscillator { m: 2.0, k: 8.0 }; // ω = 2, half period π/2
const AMP: f64 = 0.7;

/// The true path `A cos ωt` plus `ε sin(πt/T)`, which vanishes at `t = 0` and `t = T`.
fn path(eps: f64, span: f64) -> impl Fn(Dual64) -> SVector<Dual64, 1> {
    move |t: Dual64| SVector::from([(t * 2.0).cos() * AMP + (t * (PI / span)).sin() * eps])
}

/// `S = −¼ m A² ω sin 2ωT` on the true path.
fn true_action(span: f64) -> f64 {
    -0.25 * OSC.m * AMP * AMP * 2.0 * (4.0 * span).sin()
}

/// `δ²S = ε² (T/4)(m π²/T² − k)` for `η = sin(πt/T)`.
fn second_variation(eps: f64, span: f64) -> f64 {
    eps * eps * span / 4.0 * (OSC.m * PI * PI / (span * span) - OSC.k)
}

#[test]
fn m9_action_of_the_oscillator_is_stationary_on_its_motion() {
    for span in [0.3, 1.0, 1.4, 2.5, 7.0] {
        let s0 = action(&OSC, path(0.0, span), 0.0, span, 1e-14).unwrap();
        let want = true_action(span);
        println!(
            "T = {span}: S = {:.16e} (closed form {want:.16e}), error estimate {:.1e}, {} evaluations",
            s0.value, s0.error_estimate, s0.evaluations
        );
        assert!(
            (s0.value - want).abs() <= 1e-13,
            "T = {span}: {} vs {want}",
            s0.value
        );
        let eps = 1e-3;
        let sp = action(&OSC, path(eps, span), 0.0, span, 1e-14)
            .unwrap()
            .value;
        let sm = action(&OSC, path(-eps, span), 0.0, span, 1e-14)
            .unwrap()
            .value;
        // First variation: (S(ε) − S(−ε))/2ε vanishes to the quadrature's accuracy (S is exactly
        // quadratic in ε, so no O(ε²) term remains).
        let first = (sp - sm) / (2.0 * eps);
        assert!(first.abs() <= 1e-9, "T = {span}: first variation {first:e}");
        // Second variation against its closed form, and its sign against half a period π/ω.
        let second = 0.5 * (sp + sm) - s0.value;
        let want2 = second_variation(eps, span);
        assert!(
            (second - want2).abs() <= 1e-12,
            "T = {span}: {second:e} vs {want2:e}"
        );
        assert_eq!(
            second > 0.0,
            span < PI / 2.0,
            "T = {span}: δ²S = {second:e}"
        );
    }
}

#[test]
fn m9_action_refuses_hostile_input() {
    let ok = |t: Dual64| SVector::from([t]);
    for (t0, t1, tol) in [
        (f64::NAN, 1.0, 1e-10),
        (0.0, f64::INFINITY, 1e-10),
        (0.0, 1.0, f64::NAN),
        (0.0, 0.0, 1e-10),
        (0.0, 1.0, 0.0),
        (0.0, 1.0, 2.0),
        (-f64::MAX, f64::MAX, 1e-10),
    ] {
        assert!(action(&OSC, ok, t0, t1, tol).is_err(), "{t0}, {t1}, {tol}");
    }
    // A path that leaves the reals inside the span names the time.
    let sqrt = |t: Dual64| SVector::from([(t - 0.5).sqrt()]);
    match action(&OSC, sqrt, 0.0, 1.0, 1e-10) {
        Err(Error::NonFinite { what, .. }) => assert!(what.contains("t ="), "{what}"),
        other => panic!("{other:?}"),
    }
    // Reversed bounds give −S.
    let f = action(&OSC, path(0.0, 1.0), 0.0, 1.0, 1e-12).unwrap().value;
    let b = action(&OSC, path(0.0, 1.0), 1.0, 0.0, 1e-12).unwrap().value;
    assert!((f + b).abs() <= 1e-13, "{f} vs {b}");
}

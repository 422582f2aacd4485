//! The inverse problem for one degree of freedom (SPEC M11, T37): Lagrangians of damped equations
//! against their closed forms and Euler–Lagrange expressions, the Caldirola–Kanai motion they
//! generate against the damped oscillator's solution, and the Helmholtz multiplier along computed
//! trajectories against closed forms.

use hamilton_jacobi::integrate::{integrate, Dop853, Problem};
use hamilton_jacobi::inverse_problem::{
    helmholtz_multiplier, AffineEquation, InverseLagrangian, SecondOrderEquation,
};
use hamilton_jacobi::lagrangian::Legendre;
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::{Error, Lagrangian};
use num_dual::DualNum;

/// `ẍ = −cẋ − kx` (T37) with c = 0.3, k = 2.
struct Damped;
impl AffineEquation for Damped {
    fn damping<D: DualNum<f64> + Copy>(&self, _t: D) -> D {
        D::from(0.3)
    }
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, x: D) -> D {
        x * x
    }
}

/// `ẍ = −(0.3 + 0.1 sin t)ẋ − x³ + t`: a time-dependent rate, `C = 0.3t + 0.1(1 − cos t)`.
struct Varying;
impl AffineEquation for Varying {
    fn damping<D: DualNum<f64> + Copy>(&self, t: D) -> D {
        t.sin() * 0.1 + 0.3
    }
    fn potential<D: DualNum<f64> + Copy>(&self, t: D, x: D) -> D {
        x.powi(4) * 0.25 - t * x
    }
}

fn v1(x: f64) -> SVector<f64, 1> {
    SVector::from([x])
}

#[test]
fn t37_damped_oscillator_lagrangian_and_its_euler_lagrange_expression() {
    let f = InverseLagrangian::new(Damped);
    for &(t, x, v, a) in &[
        (0.0, 0.4, -1.1, 0.3),
        (1.7, -0.8, 0.5, -2.0),
        (6.3, 1.2, 0.9, 0.1),
    ] {
        // T37: f = e^{ct}(½ẋ² − ½kx²), quadrature on 7 panels at t = 6.3.
        let want = (0.3 * t).exp() * (0.5 * v * v - x * x);
        let got = f.value(t, &v1(x), &v1(v)).unwrap();
        assert!(
            (got - want).abs() <= 8.0 * f64::EPSILON * want.abs().max(1.0),
            "{got} vs {want}"
        );
        // Its Euler–Lagrange expression e^{ct}(ẍ + cẋ + kx), by AD through the quadrature.
        let e = f.lagrange_residual(t, &v1(x), &v1(v), &v1(a)).unwrap()[0];
        let want = (0.3 * t).exp() * (a + 0.3 * v + 2.0 * x);
        assert!(
            (e - want).abs() <= 1e-13 * (0.3 * t).exp() * 4.0,
            "E = {e}, want {want}"
        );
        // And the equation it encodes.
        let g = Damped.acceleration(t, x, v);
        assert!((g - (-0.3 * v - 2.0 * x)).abs() <= 4.0 * f64::EPSILON * 4.0);
    }
}

#[test]
fn time_dependent_rate_quadrature_matches_the_closed_form() {
    let f = InverseLagrangian::new(Varying);
    for &(t, x, v, a) in &[
        (0.5, 0.3, 0.2, -0.4),
        (4.2, -1.0, 1.5, 0.7),
        (-3.1, 0.6, -0.2, 0.0),
    ] {
        let c_closed = 0.3 * t + 0.1 * (1.0 - f64::cos(t));
        assert!((f.damping_integral(t) - c_closed).abs() <= 4e-16 * (1.0 + t.abs()));
        let e = f.lagrange_residual(t, &v1(x), &v1(v), &v1(a)).unwrap()[0];
        let want = c_closed.exp() * (a + (0.3 + 0.1 * t.sin()) * v + x.powi(3) - t);
        assert!(
            (e - want).abs() <= 1e-13 * c_closed.exp() * 4.0,
            "E = {e}, want {want}"
        );
    }
    // Shorter panels give the same integral (the rule has converged).
    let fine = InverseLagrangian::new(Varying).with_panel(0.1).unwrap();
    assert!((fine.damping_integral(7.0) - f.damping_integral(7.0)).abs() <= 1e-14);
    assert!(InverseLagrangian::new(Varying).with_panel(0.0).is_err());
    assert!(f.damping_integral(f64::INFINITY).is_nan());
}

#[test]
fn inverse_lagrangian_generates_the_damped_motion_through_its_legendre_transform() {
    // H = e^{−ct}p²/2 + e^{ct}kx²/2 (Caldirola–Kanai), integrated by DOP853, against the damped
    // oscillator x = e^{−ct/2}(x₀ cos ω_d t + (ẋ₀ + cx₀/2)/ω_d sin ω_d t), ω_d² = k − c²/4.
    let h = Legendre(InverseLagrangian::new(Damped));
    let (x0, v0) = (1.0, 0.0);
    let problem = Problem::new(&h, 0.0, v1(x0), v1(v0), 10.0).unwrap();
    let report = integrate(&problem, &Dop853::new(1e-12, 1e-14).unwrap(), &mut ()).unwrap();
    let (c, k, t) = (0.3, 2.0, 10.0);
    let wd = (k - c * c / 4.0_f64).sqrt();
    let x = (-c * t / 2.0_f64).exp()
        * (x0 * (wd * t).cos() + (v0 + c * x0 / 2.0) / wd * (wd * t).sin());
    // DOP853's global error at rtol 1e-12 over ~2 periods of order-1 motion.
    assert!(
        (report.last.q[0] - x).abs() <= 1e-10,
        "{} vs {x}",
        report.last.q[0]
    );
}

/// `ẍ = −ẋ²`: a Lagrangian is `e^{2x}ẋ²/2`, so `M = f_ẋẋ ∝ e^{2x}`.
struct Quadratic;
impl SecondOrderEquation for Quadratic {
    fn acceleration<D: DualNum<f64> + Copy>(&self, _t: D, _x: D, xdot: D) -> D {
        -xdot * xdot
    }
}

#[test]
fn helmholtz_multiplier_along_computed_trajectories() {
    let times = [0.5, 1.0, 2.0, 4.0];
    // Non-linear in ẋ: M(t) = e^{2(x(t) − x₀)}.
    let run = helmholtz_multiplier(&Quadratic, 0.0, 0.2, 1.5, 1.0, &times, 1e-12).unwrap();
    for s in &run {
        let want = (2.0 * (s.x - 0.2)).exp();
        // x(t) = x₀ + ln(1 + ẋ₀t): both sides carry DOP853's error at rtol 1e-12.
        assert!((s.x - (0.2 + (1.0 + 1.5 * s.t).ln())).abs() <= 1e-10);
        assert!((s.multiplier / want - 1.0).abs() <= 1e-10, "{s:?}");
    }
    // Affine: M = M₀ e^{ct} whatever the trajectory; times in any order, t₀ among them.
    let run = helmholtz_multiplier(&Damped, 0.0, 1.0, 0.0, 2.0, &[3.0, 0.0, 1.0], 1e-12).unwrap();
    for s in &run {
        assert!((s.multiplier - 2.0 * (0.3 * s.t).exp()).abs() <= 1e-10 * s.multiplier);
    }
    assert_eq!(run[1].t, 0.0);
    assert_eq!(run[1].multiplier, 2.0);
    // Bad input.
    assert!(matches!(
        helmholtz_multiplier(&Quadratic, 0.0, f64::NAN, 1.0, 1.0, &times, 1e-10),
        Err(Error::NonFinite { .. })
    ));
    assert!(helmholtz_multiplier(&Quadratic, 0.0, 0.0, 1.0, 0.0, &times, 1e-10).is_err());
    assert!(helmholtz_multiplier(&Quadratic, 0.0, 0.0, 1.0, 1.0, &[-1.0, 1.0], 1e-10).is_err());
    assert!(helmholtz_multiplier(&Quadratic, 0.0, 0.0, 1.0, 1.0, &times, f64::NAN).is_err());
    assert!(
        helmholtz_multiplier(&Quadratic, 0.0, 0.0, 1.0, 1.0, &[], 1e-10)
            .unwrap()
            .is_empty()
    );
}

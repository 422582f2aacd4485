//! The Taylor method in double-double arithmetic (`Taylor::double_double`): its order and
//! tolerance proportionality (as for the double method), and the pendulum near its separatrix,
//! `q₀ = 3.14159`, `p₀ = 0`, where no double-precision integrator reaches a final error `10⁻⁹`
//! over 100 periods — against the exact solution by mpmath at 50 and 80 digits (Jacobi elliptic
//! functions, cross-checked by `mpmath.odefun`; `benches/peers/separatrix_reference.py`), and
//! against the conservation of the energy.

use hamilton_jacobi::integrate::{
    integrate, Control, Each, Method, Precision, Problem, Taylor, TaylorControl,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::{ExactFlow, Kepler2, Pendulum};
use std::f64::consts::PI;

mod common;

/// `benches/peers/separatrix_reference.py`: `(t, q, p)` of the pendulum `H = p²/2 + 1 − cos q`
/// from `(3.14159, 0)` at `t = 20` and at `n` periods `fl(n·4K(k))`, `k = sin(q₀/2)`, `n = 1, 5,
/// 100` (`4K = 59.676154949383353303990590830`), by `sin(q/2) = k sn(t + K, k)` at 80 digits
/// (the 50-digit values differ by ≤ 1e-43; `mpmath.odefun` at 50 digits agrees to 2e-42 at
/// `t = 20` and 1e-45 at one period), rounded to doubles.
const REFERENCE: [(f64, f64, f64); 4] = [
    (20.0, -3.116_737_241_739_510_7, -0.024_854_771_902_647_74),
    (59.676_154_949_383_35, Q0, 1.487_172_326_445_107e-21),
    (298.380_774_746_916_76, Q0, 2.629_075_114_576_481_4e-20),
    (5_967.615_494_938_335, Q0, -7.754_144_151_796_062e-20),
];

/// The initial angle of the separatrix problem (near π, not π).
#[allow(clippy::approx_constant)]
const Q0: f64 = 3.14159;

/// The final error of `method` on the separatrix problem up to `REFERENCE[i]`, and the steps.
fn separatrix_error<M: Method<Pendulum, 1>>(method: &M, i: usize) -> (f64, usize) {
    let pendulum = Pendulum::new(1.0).unwrap();
    let (t1, q, p) = REFERENCE[i];
    let problem = Problem::new(
        &pendulum,
        0.0,
        SVector::from([Q0]),
        SVector::from([0.0]),
        t1,
    )
    .unwrap();
    let run = integrate(&problem, method, &mut ()).unwrap();
    assert_eq!(run.last.t, t1);
    let err = (run.last.q[0] - q).abs().max((run.last.p[0] - p).abs());
    (err, run.work.steps)
}

/// `H(q, p) − H(q₀, 0)` near the turning points `q ≈ ±q₀` (`|p|` small), to a relative
/// accuracy of a few `u` of the terms: with `d = π − |q|` (formed exactly enough:
/// `fl(π) − |q|` is exact by Sterbenz's lemma, `π − fl(π)` added), `1 − cos q = 2 − d²/2 +
/// d⁴/24 − d⁶/720 + …`, so `ΔH = p²/2 − (d − d₀)(d + d₀)/2 + (d⁴ − d₀⁴)/24 − (d⁶ − d₀⁶)/720`
/// with `d − d₀ = q₀ − |q|` exact; the terms dropped are below `d⁸/8! < 10⁻⁴⁷` for
/// `d < 10⁻⁵`.
fn energy_defect(q: f64, p: f64) -> f64 {
    const PI_LO: f64 = 1.224_646_799_147_353_2e-16;
    let d = (PI - q.abs()) + PI_LO;
    let d0 = (PI - Q0) + PI_LO;
    let (d2, d02) = (d * d, d0 * d0);
    0.5 * p * p - 0.5 * (Q0 - q.abs()) * (d + d0) + (d2 * d2 - d02 * d02) / 24.0
        - (d2 * d2 * d2 - d02 * d02 * d02) / 720.0
}

/// The separatrix problem over five periods (`t₁ ≈ 298`), and before the first turning point
/// (`t = 20`, mid-swing).
///
/// What the final error must be: the period `T = 2 ln(32/(E_sep − E))` (plus terms of
/// `O(E_sep − E)`), `E_sep − E = 2cos²(q₀/2) = 3.52·10⁻¹²`, changes by `δT = 2δE/(E_sep − E)`;
/// at the turning point `|ṗ| = sin q₀ = 2.65·10⁻⁶`, so an energy error `δE` held over `n`
/// periods moves the final `p` by `n sin q₀ · 2δE/(E_sep − E) = 1.5·10⁻⁶ n δE`. The double
/// method's rounding (`δE ≈ u = 1.1·10⁻¹⁶` per step, hundreds of steps per period) gives
/// `10⁻¹⁰`–`10⁻⁹` at five periods; in double-double `δE ≈ 10⁻¹⁸` (the tolerance `10⁻²⁰` per
/// step, summed over the ≈ 80 steps near each turning point), so `≤ 1.5·10⁻⁶ · 5 · 10⁻¹⁸`
/// — far below the double rounding of the result, `u|q| = 3.5·10⁻¹⁶`, which therefore bounds
/// the error: the assertion is `4u|q₀| = 1.4·10⁻¹⁵`. At `t = 20`, mid-swing (`|ṗ| ≈ 0.02`,
/// `|q̇| ≈ 0.02`), the phase error is 1.5 orders smaller still.
#[test]
fn separatrix_five_periods_to_the_double_rounding() {
    let dd = Taylor::new(1e-20).unwrap().double_double();
    let bound = 4.0 * f64::EPSILON / 2.0 * Q0;
    for i in [0, 2] {
        let (err, steps) = separatrix_error(&dd, i);
        let (err64, steps64) = separatrix_error(&Taylor::new(1e-16).unwrap(), i);
        println!(
            "separatrix t = {}: double-double tol 1e-20 (order {}) error {err:e} in {steps} \
             steps; double tol 1e-16 error {err64:e} in {steps64} steps",
            REFERENCE[i].0,
            dd.order(),
        );
        assert!(err <= bound, "t = {}: {err:e} > {bound:e}", REFERENCE[i].0);
    }
}

/// The goal of the separatrix problem: 100 periods (`t₁ ≈ 5968`), final error `≤ 10⁻⁹` (no
/// peer reaches it, nor the double method: its energy error of `≈ u` per step shifts the
/// phase by `≈ 10⁻⁴` per period), and `≤ 10⁻¹²`, the next target of the peer table, at
/// tolerance `10⁻²⁰` (measured `1.5·10⁻¹³`, 8467 steps). Over 100 periods the truncation error
/// of that tolerance, not the rounding, sets the final error (measured `3.2·10⁻¹⁶` at
/// `10⁻²²` and `1.1·10⁻¹⁷` at `10⁻²⁴`): from `10⁻²²` on, the bound is the double rounding of
/// the result, `4u|q₀| = 1.4·10⁻¹⁵`, as over five periods at `10⁻²⁰`.
#[test]
fn separatrix_hundred_periods_below_1e9() {
    for tol in [1e-20, 1e-22, 1e-24] {
        let dd = Taylor::new(tol).unwrap().double_double();
        let (err, steps) = separatrix_error(&dd, 3);
        println!(
            "separatrix 100 periods: double-double tol {tol:e} (order {}) error {err:e} in \
             {steps} steps",
            dd.order()
        );
        assert!(err <= 1e-12, "tol {tol:e}: {err:e}");
        if tol <= 1e-22 {
            let bound = 4.0 * f64::EPSILON / 2.0 * Q0;
            assert!(err <= bound, "tol {tol:e}: {err:e} > {bound:e}");
        }
    }
    let (err64, steps64) = separatrix_error(&Taylor::new(1e-16).unwrap(), 3);
    println!("separatrix 100 periods: double tol 1e-16 error {err64:e} in {steps64} steps");
    assert!(err64 > 1e-9, "the double method reached {err64:e}");
}

/// The second oracle: the energy, evaluated from the double states near the turning points
/// (`|p| < 10⁻⁵`, where the rounding of the state to doubles moves `H` by at most
/// `|sin q| ulp(q)/2 + |p| ulp(p)/2 < 10⁻²¹`), over five periods, relative to `H = 2 −
/// 3.5·10⁻¹²`. Double-double: `≤ 10⁻¹⁸` relative (the goal; the derived budget is the
/// tolerance `10⁻²⁰` per step relative to `|x| ≈ π`, times the ≈ 200 steps per period that
/// each add a local error of either sign, `√(200·5)·π·10⁻²⁰ ≈ 10⁻¹⁸`). Doubles at tolerance
/// `10⁻¹⁶` drift by more than that, which is the point of the method.
#[test]
fn energy_held_to_1e18_over_five_periods() {
    let pendulum = Pendulum::new(1.0).unwrap();
    let (t1, _, _) = REFERENCE[2];
    let problem = Problem::new(
        &pendulum,
        0.0,
        SVector::from([Q0]),
        SVector::from([0.0]),
        t1,
    )
    .unwrap();
    let worst = |method: &Taylor| {
        let mut worst: f64 = 0.0;
        let mut seen = 0usize;
        let mut each = Each(|s: &hamilton_jacobi::phase::State<1>| {
            if s.p[0].abs() < 1e-5 {
                worst = worst.max(energy_defect(s.q[0], s.p[0]).abs() / 2.0);
                seen += 1;
            }
            Control::Continue
        });
        integrate(&problem, method, &mut each).unwrap();
        (worst, seen)
    };
    let (dd, n) = worst(&Taylor::new(1e-20).unwrap().double_double());
    let (f, n64) = worst(&Taylor::new(1e-16).unwrap());
    println!(
        "relative energy error near the turning points over 5 periods: double-double {dd:e} \
         ({n} states), double {f:e} ({n64} states)"
    );
    assert!(n >= 10, "{n} states near the turning points");
    assert!(dd <= 1e-18, "double-double: {dd:e}");
    assert!(f > 10.0 * dd, "double {f:e} vs double-double {dd:e}");
}

/// The Kepler problem (e = 0.5, one period) against its exact flow: `sqrt` and `powf` of the
/// record in double-double.
fn kepler_error(method: &Taylor, periods: f64) -> f64 {
    let kepler = Kepler2::new(1.0).unwrap();
    let (q0, p0) = (SVector::from([0.5, 0.0]), SVector::from([0.0, 3f64.sqrt()]));
    let t1 = 2.0 * PI * periods;
    let problem = Problem::new(&kepler, 0.0, q0, p0, t1).unwrap();
    let run = integrate(&problem, method, &mut ()).unwrap();
    let (q, p) = kepler.exact_flow(0.0, &q0, &p0, t1).unwrap();
    (run.last.q - q).amax().max((run.last.p - p).amax())
}

/// The fixed-order method in double-double has its order: halving the step divides the error
/// by `2^p` (observed order within 0.5 of `p`), as the double method does.
#[test]
fn fixed_order_fixed_step_has_its_order() {
    for order in [4usize, 6, 8] {
        let m = |n| Taylor::fixed(order, n).unwrap().double_double();
        let (e1, e2) = (kepler_error(&m(200), 1.0), kepler_error(&m(400), 1.0));
        let observed = (e1 / e2).log2();
        println!("order {order}: errors {e1:e}, {e2:e}, observed order {observed:.2}");
        assert!(
            (observed - order as f64).abs() < 0.5,
            "order {order}: observed {observed}"
        );
    }
}

/// The adaptive method in double-double: the final error is proportional to the tolerance
/// (least-squares slope `1 ± 0.2` over four decades, no error above `100 ε`), as for doubles.
#[test]
fn adaptive_error_is_proportional_to_the_tolerance() {
    let tols = [1e-7, 1e-8, 1e-9, 1e-10, 1e-11];
    let m = |tol| Taylor::new(tol).unwrap().double_double();
    let errs: Vec<f64> = tols.iter().map(|&t| kepler_error(&m(t), 10.0)).collect();
    for (t, e) in tols.iter().zip(&errs) {
        println!("tol {t:e}: final error {e:e} (ratio {:.2})", e / t);
    }
    let points: Vec<(f64, f64)> = tols.iter().copied().zip(errs.iter().copied()).collect();
    let slope = common::loglog_slope(&points);
    println!("slope {slope:.3}");
    assert!((slope - 1.0).abs() < 0.2, "slope {slope}");
    for (t, e) in tols.iter().zip(&errs) {
        assert!(*e < 100.0 * t, "tol {t:e}: {e:e}");
    }
}

/// The value, its label and entry: `taylor-dd` in the method table builds the double-double
/// method; the variational (tangent-map) runs refuse it with a typed error instead of running in
/// doubles.
#[test]
fn the_method_value_and_its_entry() {
    use hamilton_jacobi::integrate::{AnyMethod, MethodInfo, TangentMethod};
    let m = Taylor::new(1e-20).unwrap().double_double();
    assert_eq!(m.precision, Precision::DoubleDouble);
    assert_eq!(Taylor::new(1e-20).unwrap().precision, Precision::Double);
    assert!(matches!(m.control, TaylorControl::Tolerance(t) if t == 1e-20));
    let label = Method::<Pendulum, 1>::label(&m);
    assert!(label.contains("double-double"), "{label}");
    let info = MethodInfo::find("taylor-dd").unwrap();
    let any = AnyMethod::new(info, 1e-20).unwrap();
    assert_eq!(any.info().map(|i| i.key), Some("taylor-dd"));
    let pendulum = Pendulum::new(1.0).unwrap();
    let problem = Problem::new(
        &pendulum,
        0.0,
        SVector::from([1.0]),
        SVector::from([0.0]),
        1.0,
    )
    .unwrap();
    assert!(TangentMethod::tangent_map(&m, &problem).is_err());
    assert!(TangentMethod::tangent_map(&Taylor::new(1e-12).unwrap(), &problem).is_ok());
}

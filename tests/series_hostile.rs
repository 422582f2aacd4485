//! Hostile input to the series, pendulum, action–angle, chart and top entry points: every call
//! gives a typed error, or a finite value that agrees with an independent reference (closed form,
//! a 50-digit mpmath value, the exact flow, or a quadrature).

use hamilton_jacobi::hamilton_jacobi::ActionAngle;
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::birkhoff::MAX_NORMAL_FORM_DEGREE;
use hamilton_jacobi::perturbation::lindstedt::{
    lindstedt_odd_force, lindstedt_pendulum, MAX_LINDSTEDT_ORDER,
};
use hamilton_jacobi::perturbation::normal_form::{
    ConvergenceWarning, FrequencyAmplitude, NormalForm, PendulumNormalForm, MAX_PENDULUM_ORDER,
    SERIES_WARNING_RATIO,
};
use hamilton_jacobi::stability::hamiltonian_equilibrium;
use hamilton_jacobi::systems::pendulum_exact::{
    amplitude_from_state, energy, exact_state, period, period_from_gap, separatrix_gap,
    PendulumMotion,
};
use hamilton_jacobi::systems::top::motion::{fast_top_width, release_from_rest};
use hamilton_jacobi::systems::{HeavyTop, Pendulum};
use hamilton_jacobi::transform::point::{point_transformation, Spherical};
use hamilton_jacobi::Error;
use std::f64::consts::{PI, TAU};
use std::time::Instant;

const EPS: f64 = f64::EPSILON;

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn huge_orders_are_refused_before_allocating() {
    let t0 = Instant::now();
    for order in [0, MAX_LINDSTEDT_ORDER + 1, 1 << 40, usize::MAX] {
        for r in [
            lindstedt_pendulum(order),
            lindstedt_odd_force(&[1.0], order),
        ] {
            match r {
                Err(Error::OutOfDomain { domain, .. }) => {
                    assert!(domain.contains("MAX_LINDSTEDT_ORDER = 64"), "{domain}")
                }
                other => panic!("order {order}: {other:?}"),
            }
        }
    }
    for order in [0, MAX_PENDULUM_ORDER + 1, 1 << 40, usize::MAX] {
        assert!(matches!(
            PendulumNormalForm::new(1.0, order),
            Err(Error::OutOfDomain { .. })
        ));
    }
    let duffing = Duffing { eps: 1.0 };
    let zero = SVector::<f64, 1>::zeros();
    let eq = hamiltonian_equilibrium(&duffing, 0.0, &zero, &zero).unwrap();
    for degree in [0, 2, MAX_NORMAL_FORM_DEGREE + 1, 1 << 40, usize::MAX] {
        assert!(matches!(
            NormalForm::new(&duffing, 0.0, &eq, degree),
            Err(Error::OutOfDomain { .. })
        ));
    }
    // Refusals cost nothing (no O(N⁴) work, no allocation of the size asked for).
    assert!(t0.elapsed().as_secs_f64() < 0.5);
}

#[test]
fn lindstedt_refuses_non_finite_and_divergent_evaluations() {
    // Coefficients that overflow the recursion.
    for g in [vec![1e300], vec![1e200, 1e300]] {
        assert!(matches!(
            lindstedt_odd_force(&g, 12),
            Err(Error::NonFinite { .. })
        ));
    }
    let l = lindstedt_pendulum(12).unwrap();
    // Outside the radius (a = π for the pendulum) the terms grow: refused, never inf/NaN.
    for a in [1e200, 1e20, 10.0, -4.0] {
        assert!(
            matches!(l.period_ratio_at(a), Err(Error::NotConverged { .. })),
            "a = {a}"
        );
        assert!(matches!(
            l.theta(1.0, a, 1.0),
            Err(Error::NotConverged { .. })
        ));
    }
    assert!(matches!(
        l.period_ratio_at(f64::NAN),
        Err(Error::NonFinite { .. })
    ));
    // Inside: the AGM period. Truncation error ≤ c_13 a^26/(1 − μ)·…: at a = 1, μ = 0.1,
    // c_13 = 5.8e−15 ⇒ ≤ 7e−15; plus rounding 4ε.
    let exact = period(1.0, 1.0).unwrap() / TAU;
    assert!(rel(l.period_ratio_at(1.0).unwrap(), exact) <= 7e-15 + 4.0 * EPS);
    // A huge phase ω t: the phase is lost, refused (24 harmonics at most: limit ω t ≈ 1.9e8).
    for (n, t) in [(1e300, 1e300), (1.0, 1e17), (1.0, 1e9)] {
        assert!(
            matches!(l.theta(n, 0.5, t), Err(Error::OutOfDomain { .. })),
            "n = {n}, t = {t}"
        );
    }
    // A moderate phase is fine and follows the exact flow: the phase drift t·Δω with
    // Δω ≤ c_13 a^26 ≈ 4e−23 and the truncation a^27 ≈ 1e−8·6e−15 are below rounding; the phase
    // rounding ε·25·|ω t| ≤ 3e−11 at t = 5000.
    for t in [1.0, 50.0, 5000.0] {
        let (th, _) = exact_state(1.0, 0.5, 0.0, t).unwrap();
        let got = l.theta(1.0, 0.5, t).unwrap();
        assert!(
            (got - th).abs() <= 1e-14 * t + 1e-15,
            "t = {t}: {got} vs {th}"
        );
    }
}

#[test]
fn pendulum_helpers_refuse_non_finite_input() {
    assert!(matches!(
        separatrix_gap(f64::NAN),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        separatrix_gap(f64::INFINITY),
        Err(Error::NonFinite { .. })
    ));
    // π − 3 = 0.14159265358979323846…: the gap of the double 3 is exact to rounding.
    assert!(rel(separatrix_gap(3.0).unwrap(), 0.141_592_653_589_793_24) <= EPS);
    for (n, th, p) in [
        (f64::NAN, 1.0, 1.0),
        (1.0, f64::NAN, 1.0),
        (1.0, 1.0, f64::INFINITY),
    ] {
        assert!(matches!(energy(n, th, p), Err(Error::NonFinite { .. })));
    }
    assert!(matches!(
        energy(0.0, 1.0, 1.0),
        Err(Error::OutOfDomain { .. })
    ));
    // ½p² overflows.
    assert!(matches!(
        energy(1.0, 0.0, 1e200),
        Err(Error::NonFinite { .. })
    ));
    // ½ + (1 − cos 1) = 0.95969769413186028…
    assert!(rel(energy(1.0, 1.0, 1.0).unwrap(), 0.959_697_694_131_860_3) <= 2.0 * EPS);
}

#[test]
fn period_from_subnormal_and_tiny_gaps() {
    // 50-digit mpmath references, 4K(k) = 2π/M(1, sin(δ/2)) at the double δ.
    let table = [
        (5e-324, 2_986.078_053_852_244_4),
        (1e-300, 2_771.419_877_759_574_2),
        (1e-160, 1_481.972_225_682_908_6),
        (1e-140, 1_297.765_418_243_384_9),
        (1e-20, 192.524_573_606_243),
    ];
    for (delta, tau) in table {
        let got = period_from_gap(1.0, delta).unwrap();
        // ln(8/δ) to one rounding, times 4: 2ε (the AGM branch is checked to 1e−13 elsewhere).
        assert!(rel(got, tau) <= 4.0 * EPS, "δ = {delta:e}: {got} vs {tau}");
    }
    // Scaling with n, and an n so small that the period overflows: typed error.
    assert!(
        rel(
            period_from_gap(4.0, 5e-324).unwrap(),
            2_986.078_053_852_244_4 / 4.0
        ) <= 4.0 * EPS
    );
    assert!(matches!(
        period_from_gap(1e-320, 5e-324),
        Err(Error::NonFinite { .. })
    ));
}

#[test]
fn amplitude_and_period_agree_on_what_is_the_separatrix() {
    for theta in [PI, -PI, 3.0 * PI] {
        assert!(matches!(
            amplitude_from_state(1.0, theta, 0.0),
            Err(Error::Separatrix { .. })
        ));
    }
    assert!(matches!(period(1.0, PI), Err(Error::Separatrix { .. })));
    // The refusal carries the gap: θ = PI at rest is 1.2246e−16 below π.
    match amplitude_from_state(1.0, PI, 0.0) {
        Err(Error::Separatrix { distance, .. }) => {
            assert!(rel(distance, 1.224_646_799_147_353_2e-16) <= 4.0 * EPS)
        }
        other => panic!("{other:?}"),
    }
    // Whatever amplitude_from_state accepts, period accepts, and the period agrees with the exact
    // flow's (which takes k′ from the state, not from the rounded amplitude). Tolerance: the
    // amplitude carries a few ε·a of rounding; dτ/da·a/τ ≤ 4a/(δτ) ≤ 6 for these states (δ ≥ 0.1),
    // so 8ε·6 ≈ 1e−14 relative; 1e−13 leaves the AGM's own 1e−14.
    let below = f64::from_bits(PI.to_bits() - 1);
    let _ = period(1.0, amplitude_from_state(1.0, below, 0.0).unwrap()).unwrap();
    for (th, p) in [(1.0, 0.5), (-2.0, 1.0), (3.0, 0.0), (0.3, -1.9), (7.0, 0.2)] {
        let a = amplitude_from_state(1.0, th, p).unwrap();
        let tau = period(1.0, a).unwrap();
        let flow = PendulumMotion::new(1.0, th, p).unwrap().period().unwrap();
        assert!(rel(tau, flow) <= 1e-13, "({th}, {p}): {tau} vs {flow}");
    }
}

hamilton_jacobi::hamiltonian!(
    /// Duffing oscillator `H = ½(p² + q²) + ε q⁴/4`.
    Duffing<1> { eps: f64 } |s, _t, q, p|
        kinetic = p[0] * p[0] * 0.5,
        potential = q[0] * q[0] * 0.5 + q[0].powi(4) * (0.25 * s.eps)
);

#[test]
fn normal_form_refuses_or_warns_where_its_series_has_not_converged() {
    // Degree 18: K(J) to J⁹, ω(J) to J⁸.
    let degree = 18;
    let nf = |eps: f64| -> FrequencyAmplitude {
        let h = Duffing { eps };
        let zero = SVector::<f64, 1>::zeros();
        let eq = hamiltonian_equilibrium(&h, 0.0, &zero, &zero).unwrap();
        NormalForm::new(&h, 0.0, &eq, degree)
            .unwrap()
            .frequency_amplitude()
            .clone()
    };
    // ε = 1, J = 1: the degree-18 series used to sum to ω = −116. Its terms grow: refused.
    let hard = nf(1.0);
    for j in [1.0, 2.0, 1e10] {
        assert!(
            matches!(hard.frequency(j), Err(Error::NotConverged { .. })),
            "J = {j}"
        );
        assert!(matches!(hard.period(j), Err(Error::NotConverged { .. })));
        assert!(matches!(hard.energy(j), Err(Error::NotConverged { .. })));
    }
    assert!(matches!(
        hard.frequency(-0.1),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        hard.frequency(f64::NAN),
        Err(Error::NonFinite { .. })
    ));
    // Where it is accepted, the value agrees with the quadrature frequency of the torus
    // (action–angle variables by quadrature: an independent formulation). Without a warning the
    // error is within the tail estimate plus the quadrature's error.
    let mut warned = 0;
    for (eps, h) in [(1.0, 0.02), (1.0, 0.1), (1.0, 0.2), (0.1, 0.1), (0.1, 1.0)] {
        let aa = ActionAngle::new(Duffing { eps }, h, 0.0, -10.0, 10.0).unwrap();
        let (j, omega) = (aa.action().value, aa.frequency());
        let est = nf(eps).frequency_estimate(j).unwrap();
        let quad = omega * (aa.period().error / aa.period().value);
        match est.warning {
            None => {
                assert!(est.small_parameter <= SERIES_WARNING_RATIO);
                assert!(
                    (est.value - omega).abs() <= est.tail_bound + quad + 8.0 * EPS,
                    "ε = {eps}, J = {j}: {} vs {omega}, tail {:e}",
                    est.value,
                    est.tail_bound
                );
            }
            Some(ConvergenceWarning::SlowTerms { ratio, limit, .. }) => {
                assert!(ratio > limit && ratio < 1.0);
                assert!(matches!(est.checked(), Err(Error::NotConverged { .. })));
                warned += 1;
            }
            Some(other) => panic!("{other:?}"),
        }
        let p = nf(eps).period(j).unwrap();
        assert!(rel(p.value, TAU / est.value) <= EPS);
    }
    assert!(
        warned >= 1,
        "the test should include a slowly converging case"
    );
}

#[test]
fn action_angle_refuses_a_state_off_the_torus() {
    let pen = Pendulum::new(1.0).unwrap();
    let aa = ActionAngle::pendulum(pen, 1.0).unwrap();
    let a = PI - 1.0;
    // States of the exact flow (elliptic functions) are on the torus.
    for t in [0.3, 1.7, 4.0] {
        let (q, p) = exact_state(1.0, -a, 0.0, t).unwrap();
        let w = aa.angle(q, p).unwrap();
        let dw = (w - aa.frequency() * t + PI).rem_euclid(TAU) - PI;
        assert!(dw.abs() < 1e-12, "t = {t}");
    }
    // An energy off by 1e−11 relative is another torus (it used to get an angle).
    let (q, p) = exact_state(1.0, -a, 0.0, 0.7).unwrap();
    for scale in [1.0 + 1e-11, 1.0 - 1e-9, 2.0] {
        match aa.angle(q, p * scale) {
            Err(Error::OutOfDomain { domain, .. }) => assert!(domain.contains("torus")),
            other => panic!("p × {scale}: {other:?}"),
        }
    }
    // Same energy, other well.
    assert!(aa.angle(q + TAU, p).is_err());
}

#[test]
fn spherical_chart_refuses_its_axis() {
    let ct = point_transformation(Spherical);
    let p = SVector::from([0.1, 0.2, 0.3]);
    for q in [
        [0.0, 0.0, 1.0],
        [0.0, 0.0, -2.0],
        [0.0, 0.0, 0.0],
        [-0.0, 0.0, 5.0],
    ] {
        match ct.forward(0.0, &SVector::from(q), &p) {
            Err(Error::Singular { at, .. }) => assert!(at.contains("q = ("), "{at}"),
            other => panic!("{q:?}: {other:?}"),
        }
    }
    // Off the axis, however close, the map is the closed form.
    for q in [[1e-17, 0.0, 1.0], [0.0, 3e-300, -2.0], [0.3, -0.4, 1.2]] {
        let (x, y, z) = (q[0], q[1], q[2]);
        let (big_q, big_p) = ct.forward(0.0, &SVector::from(q), &p).unwrap();
        let rho = f64::hypot(x, y);
        let r = rho.hypot(z);
        let (th, ph) = (rho.atan2(z), y.atan2(x));
        let (st, ct_) = th.sin_cos();
        let (sp, cp) = ph.sin_cos();
        let want_q = [r, th, ph];
        let want_p = [
            (x * p[0] + y * p[1] + z * p[2]) / r,
            r * (ct_ * cp * p[0] + ct_ * sp * p[1] - st * p[2]),
            x * p[1] - y * p[0],
        ];
        for i in 0..3 {
            assert!(
                (big_q[i] - want_q[i]).abs() <= 8.0 * EPS * want_q[i].abs().max(r),
                "{q:?}: Q[{i}] {} vs {}",
                big_q[i],
                want_q[i]
            );
            // θ carries a few ε·θ of rounding, so sin θ (in every P_i) an absolute error of that
            // size: componentwise near θ = 0, only relative to r|p| near θ = π.
            let bound = 16.0 * EPS * want_p[i].abs() + 2.0 * EPS * th * r * p.norm();
            assert!(
                (big_p[i] - want_p[i]).abs() <= bound,
                "{q:?}: P[{i}] {} vs {}",
                big_p[i],
                want_p[i]
            );
        }
    }
}

#[test]
fn fast_top_width_domain() {
    let top = HeavyTop::new(1.0, 1.0, 1.0).unwrap();
    for u2 in [2.0, -1.5, f64::NAN] {
        assert!(fast_top_width(&top, u2, 10.0).is_err(), "u₂ = {u2}");
    }
    assert!(matches!(
        fast_top_width(&top, 2.0, 10.0),
        Err(Error::OutOfDomain { .. })
    ));
    // The estimate is the large-spin limit of the exact width u₂ − u₁ (release from rest):
    // u₂ − u₁ = β(1 − u₂²)/γ² (1 + O(1/c)), c = γ²/2β, so at γ = 1e3 they agree to ~1e−6.
    for u2 in [0.5, -0.3, 0.99] {
        let spin = 1e3;
        let est = fast_top_width(&top, u2, spin).unwrap();
        let exact = u2 - release_from_rest(&top, u2, spin).unwrap();
        assert!(
            est > 0.0 && rel(est, exact) <= 1e-5,
            "u₂ = {u2}: {est} vs {exact}"
        );
    }
    // At the poles the width vanishes; a spin so large that γ² overflows still gives the (tiny)
    // width instead of 0/∞ noise: β(1 − u₂²)/γ² = 2·0.75/1e320 underflows to 0 exactly.
    assert_eq!(fast_top_width(&top, 1.0, 5.0).unwrap(), 0.0);
    let w = fast_top_width(&top, 0.5, 1e160).unwrap();
    assert!((0.0..1e-300).contains(&w));
}

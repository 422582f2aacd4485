//! The systems catalogue against its oracles: AD against hand-written Hamilton's equations,
//! invariants along the exact motion, the pendulum period (to the separatrix), Kepler's equation,
//! and typed errors for bad input.

mod common;

use approx::assert_relative_eq;
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::special::kepler_equation;
use hamilton_jacobi::systems::kepler::elements::{state_to_classical, Classical};
use hamilton_jacobi::systems::kepler::orbit;
use hamilton_jacobi::systems::{
    pendulum_exact, ExactFlow, HarmonicOscillator, Invariants, Kepler, Kepler2, Kepler3, Pendulum,
    Projectile,
};
use hamilton_jacobi::{Error, Hamiltonian};
use proptest::prelude::*;
use std::f64::consts::{PI, TAU};

const EPS: f64 = f64::EPSILON;

/// Relative difference, component by component, against a reference with magnitude floor `floor`.
fn rel<const N: usize>(a: &SVector<f64, N>, b: &SVector<f64, N>, floor: f64) -> f64 {
    a.iter()
        .zip(b.iter())
        .map(|(x, y)| (x - y).abs() / y.abs().max(floor))
        .fold(0.0, f64::max)
}

proptest! {
    #![proptest_config(common::config(0x5eed_0003))]

    /// AD equals hand-written Hamilton's equations to 1e−14 relative (both are a handful of roundings).
    #[test]
    fn kepler2_ad_equals_hand(q in prop::array::uniform2(-3.0..3.0f64), p in prop::array::uniform2(-2.0..2.0f64)) {
        let k = Kepler2::new(1.3).unwrap();
        let (q, p) = (SVector::from(q), SVector::from(p));
        prop_assume!(q.norm() > 1e-3);
        let (a, b) = k.vector_field(0.0, &q, &p).unwrap();
        let (c, d) = k.vector_field_hand(&q, &p);
        prop_assert_eq!(a, c);
        // Component-wise relative error, floor at 1e−3 of the vector's size (a component that is
        // zero by cancellation has no relative accuracy in either formula).
        prop_assert!(rel(&b, &d, 1e-3 * d.norm()) <= 1e-14, "{} vs {}", b, d);
    }

    #[test]
    fn kepler3_ad_equals_hand(q in prop::array::uniform3(-3.0..3.0f64), p in prop::array::uniform3(-2.0..2.0f64)) {
        let k = Kepler3::new(0.7).unwrap();
        let (q, p) = (SVector::from(q), SVector::from(p));
        prop_assume!(q.norm() > 1e-3);
        let (a, b) = k.vector_field(0.0, &q, &p).unwrap();
        let (c, d) = k.vector_field_hand(&q, &p);
        prop_assert_eq!(a, c);
        prop_assert!(rel(&b, &d, 1e-3 * d.norm()) <= 1e-14, "{} vs {}", b, d);
    }

    #[test]
    fn pendulum_ad_equals_hand(q in -10.0..10.0f64, p in -3.0..3.0f64, n in 0.1..5.0f64) {
        let pend = Pendulum::new(n).unwrap();
        let (q, p) = (SVector::from([q]), SVector::from([p]));
        let (a, b) = pend.vector_field(0.0, &q, &p).unwrap();
        let (c, d) = pend.vector_field_hand(&q, &p);
        prop_assert_eq!(a, c);
        prop_assert!(rel(&b, &d, f64::MIN_POSITIVE) <= 1e-14, "{} vs {}", b, d);
    }

    /// Kepler elements ↔ state round trip through the public API (3-D, bound orbits).
    #[test]
    fn kepler_elements_state_round_trip(a in 0.1..10.0f64, e in 0.0..0.99f64, i in 0.01..3.13f64,
                                        raan in 0.0..TAU, argp in 0.0..TAU, m in -PI..PI) {
        let el = Classical::new(a, e, i, raan, argp, m).unwrap();
        let (r, v) = el.to_state(1.0).unwrap();
        let back = state_to_classical(1.0, &r, &v).unwrap();
        let (r2, v2) = back.to_state(1.0).unwrap();
        // state → elements → state is well conditioned except through Kepler's equation near e → 1
        // (∂E/∂M = 1/(1 − e cos E) ≤ 100 here): allow 100 × a few ulps of |r|, |v|.
        prop_assert!((r2 - r).norm() <= 1e-12 * r.norm(), "r {} vs {}", r2, r);
        prop_assert!((v2 - v).norm() <= 1e-12 * v.norm(), "v {} vs {}", v2, v);
        prop_assert!((back.a - a).abs() <= 1e-12 * a);
        prop_assert!((back.e - e).abs() <= 1e-12);
    }
}

#[test]
fn invariants_are_conserved_by_the_exact_flows() {
    // Kepler, μ = a = 1, e = 0.9, generic times over 10 periods. The invariants along the flow are
    // compared with their closed forms from the elements (not with themselves at t = 0):
    // E = −μ/(2a), h = √(μa(1 − e²)) ĥ with ĥ = (sin i sin Ω, −sin i cos Ω, cos i), and the
    // eccentricity vector e P̂ with P̂ the periapsis direction [Vallado §2.2].
    let (a, e, inc, raan, argp) = (1.0, 0.9, 0.4, 0.3, 1.2);
    let k = Kepler3::new(1.0).unwrap();
    let el = Classical::new(a, e, inc, raan, argp, 0.0).unwrap();
    let (r, v) = el.to_state(1.0).unwrap();
    let (q0, p0) = (
        SVector::from([r[0], r[1], r[2]]),
        SVector::from([v[0], v[1], v[2]]),
    );
    let hn = (a * (1.0 - e * e)).sqrt();
    let (si, ci, so, co, sw, cw) = (
        inc.sin(),
        inc.cos(),
        raan.sin(),
        raan.cos(),
        argp.sin(),
        argp.cos(),
    );
    let expected = [
        ("energy", -0.5 / a),
        ("h_x", hn * si * so),
        ("h_y", -hn * si * co),
        ("h_z", hn * ci),
        ("e_x", e * (co * cw - so * sw * ci)),
        ("e_y", e * (so * cw + co * sw * ci)),
        ("e_z", e * sw * si),
    ];
    for j in 0..=40 {
        let t = 0.2513 * j as f64 * 2.0 * PI;
        let (q, p) = k.exact_flow(0.0, &q0, &p0, t).unwrap();
        let inv = k.invariants(t, &q, &p).unwrap();
        assert_eq!(inv.len(), expected.len());
        for (got, (name, value)) in inv.iter().zip(expected) {
            assert_eq!(got.name, name);
            // O(1) quantities; through Kepler's equation at e = 0.9 (∂E/∂M ≤ 1/(1 − e) = 10) the
            // state carries a few ×10 ulps.
            assert!(
                (got.value - value).abs() < 1e-13,
                "t = {t}: {name} = {} vs closed form {value}",
                got.value
            );
        }
        // The state itself against the element route (mean anomaly n·t, n = 1, reduced exactly):
        // a different formulation (rotation of the perifocal state) from the f and g functions of
        // the flow. The flow starts at periapsis, where 1/a = 2/r − v²/μ cancels 20 against 19: a
        // few ulps of the initial v² (4 ε · 19) and the rounding of 20 (16 ε) give δa/a ≈ 96 ε and
        // δn/n ≈ 144 ε, so the phase is off by δ ≈ 144 ε (1 + t). That moves r by
        // |v| δ + |r| δa/a (|v| ≤ 4.4, |r| ≤ 1.9) and v by |r̈| δ ≤ 100 δ (periapsis r = 0.1).
        let el_t = Classical::new(a, e, inc, raan, argp, t % TAU).unwrap();
        let (re, ve) = el_t.to_state(1.0).unwrap();
        let delta = 144.0 * EPS * (1.0 + t);
        for i in 0..3 {
            let (dr, dv) = ((q[i] - re[i]).abs(), (p[i] - ve[i]).abs());
            assert!(
                dr < 4.4 * delta + 1.9 * 96.0 * EPS,
                "t = {t}: r {q} vs {re}"
            );
            assert!(dv < 100.0 * delta, "t = {t}: v {p} vs {ve}");
        }
    }
    // Pendulum H = p²/2 + n²(1 − cos q), n = 1, amplitude 3: E = 1 − cos 3 in closed form. The
    // period 4K(sin²(3/2)) = 16.155539372393374763760276 (mpmath, 26 digits); at the quarter
    // periods T/4 + jT/2 the pendulum passes the bottom with p = ±2 sin(3/2), alternating in sign.
    let pend = Pendulum::new(1.0).unwrap();
    let (q0, p0) = (SVector::from([3.0]), SVector::from([0.0]));
    let e0 = 1.0 - 3.0f64.cos();
    let period = 16.155_539_372_393_374;
    let pmax = 2.0 * 1.5f64.sin();
    for j in 0..=40 {
        let t = 0.25 * period + 0.5 * period * j as f64;
        let (q, p) = pend.exact_flow(0.0, &q0, &p0, t).unwrap();
        assert_relative_eq!(pend.value(0.0, &q, &p).unwrap(), e0, epsilon = 1e-13);
        // A time rounding δ ≈ 4 ulp(t) moves q by |p| δ.
        let delta = 4.0 * EPS * t;
        assert!(q[0].abs() < pmax * delta + 1e-14, "t = {t}: q = {}", q[0]);
        let sign = if j % 2 == 0 { -1.0 } else { 1.0 };
        assert!((p[0] - sign * pmax).abs() < 1e-13, "t = {t}: p = {}", p[0]);
    }
}

#[test]
fn exact_flows_agree_with_integration() {
    // RK4 with dt = 1e−3 over t = 5: global error ~ 5 · (dt)^4 · C ≈ 1e−11 for these O(1) motions.
    let dt = 1e-3;
    let steps = 5000;
    let osc = HarmonicOscillator::new(2.0, 3.0).unwrap();
    let (q, p) = common::rk4_hamiltonian(
        &osc,
        0.0,
        SVector::from([0.5]),
        SVector::from([1.2]),
        dt,
        steps,
        |_, _, _| {},
    );
    let (qe, pe) = osc
        .exact_flow(
            0.0,
            &SVector::from([0.5]),
            &SVector::from([1.2]),
            dt * steps as f64,
        )
        .unwrap();
    assert!((q - qe).norm() + (p - pe).norm() < 1e-9);
    let pend = Pendulum::new(1.0).unwrap();
    for (th, pp) in [(1.0, 0.0), (3.0, 0.0), (-0.4, 2.5), (0.2, -1.9)] {
        let (q0, p0) = (SVector::from([th]), SVector::from([pp]));
        let (q, p) = common::rk4_hamiltonian(&pend, 0.0, q0, p0, dt, steps, |_, _, _| {});
        let (qe, pe) = pend.exact_flow(0.0, &q0, &p0, dt * steps as f64).unwrap();
        assert!(
            (q - qe).norm() + (p - pe).norm() < 1e-9,
            "pendulum from ({th}, {pp}): {q} {p} vs {qe} {pe}"
        );
    }
    let kep = Kepler2::new(1.0).unwrap();
    // The planar orbit: i = Ω = 0, periapsis at ϖ = 0.3.
    let el = Classical::new(1.0, 0.5, 0.0, 0.0, 0.3, 0.0).unwrap();
    let (r, v) = el.to_state(1.0).unwrap();
    let (q0, p0) = (SVector::from([r[0], r[1]]), SVector::from([v[0], v[1]]));
    let (q, p) = common::rk4_hamiltonian(&kep, 0.0, q0, p0, dt, steps, |_, _, _| {});
    let (qe, pe) = kep.exact_flow(0.0, &q0, &p0, dt * steps as f64).unwrap();
    assert!(
        (q - qe).norm() + (p - pe).norm() < 1e-9,
        "{q} {p} vs {qe} {pe}"
    );
    let proj = Projectile::new(1.0, 9.81).unwrap();
    let (q0, p0) = (SVector::from([0.0, 0.0]), SVector::from([5.0, 12.31]));
    let (q, p) = proj.exact_flow(0.0, &q0, &p0, 2.0).unwrap();
    // The principal-function instance [Ardema 17.1]: (x¹, y¹) = (10, 5) and v₁ = −7.31 at τ = 2.
    assert_relative_eq!(q, SVector::from([10.0, 5.0]), epsilon = 1e-13);
    assert_relative_eq!(p, SVector::from([5.0, -7.31]), epsilon = 1e-13);
}

#[test]
#[allow(clippy::approx_constant)] // a = 3.14 is a row of the table, not an approximation of π
fn pendulum_period_table() {
    // Ratios τ/(2π/n) = 2K(k)/π to 15 significant digits; relative error ≤ 1e−13.
    let table = [
        (0.1, 1.00062535830774),
        (0.5, 1.01585253110144),
        (1.0, 1.06633424557996),
        (2.0, 1.32890445191510),
        (3.0, 2.57123394943214),
        (3.1, 3.34849644557080),
        (3.14, 5.42514419210358),
        (PI - 1e-6, 10.1190407873027),
    ];
    let pend = Pendulum::new(1.0).unwrap();
    for (a, ratio) in table {
        let got = pend.period(a).unwrap() / (2.0 * PI);
        assert!(
            (got - ratio).abs() <= 1e-13 * ratio,
            "a = {a}: {got} vs {ratio}"
        );
    }
    // n scales the period as 1/n.
    let fast = Pendulum::new(4.0).unwrap();
    assert_relative_eq!(
        fast.period(1.0).unwrap(),
        2.0 * PI / 4.0 * 1.06633424557996,
        epsilon = 1e-13
    );
}

#[test]
fn pendulum_period_at_the_separatrix() {
    // δ given exactly.
    for (d, tau) in [
        (1e-2, 26.7386056935052),
        (1e-6, 63.5798083985803),
        (1e-10, 100.421169886481),
        (1e-16, 155.683212118338),
    ] {
        let got = pendulum_exact::period_from_gap(1.0, d).unwrap();
        assert!((got - tau).abs() <= 1e-13 * tau, "δ = {d}: {got} vs {tau}");
    }
    // a passed as the double fl(π − δ).
    for (d, tau) in [
        (1e-2, 26.7386056935053),
        (1e-6, 63.5798083975314),
        (1e-10, 100.421164656936),
    ] {
        let got = pendulum_exact::period(1.0, PI - d).unwrap();
        assert!(
            (got - tau).abs() <= 1e-13 * tau,
            "a = π − {d}: {got} vs {tau}"
        );
    }
    // fl(π − 1e−16) = fl(π): on the separatrix, a typed error rather than ∞ or NaN.
    assert!(matches!(
        pendulum_exact::period(1.0, PI - 1e-16),
        Err(Error::Separatrix { .. })
    ));
    assert!(pendulum_exact::period(1.0, 3.5).is_err());
}

#[test]
fn keplers_equation_table() {
    // μ = 1, a = 1, t = 0.3 T: M = 0.6π. Table digits: 13 significant → 1e−12 absolute.
    let m = 0.6 * PI;
    for (e, big_e, nu, r) in [
        (0.0, 1.884955592154, 1.884955592154, 1.0),
        (0.5, 2.268208852924, 2.615146567139, 1.321118261874),
        (0.9, 2.455277465697, 2.978020808229, 1.696227664315),
        (0.99, 2.487393943121, 3.093499073623, 1.785600428516),
    ] {
        let got = kepler_equation::solve_kepler(m, e).unwrap();
        assert!((got - big_e).abs() < 1e-12, "e = {e}: E = {got}");
        assert!((kepler_equation::eccentric_to_true(got, e).unwrap() - nu).abs() < 1e-12);
        // The planar orbit: i = Ω = ω = 0.
        let el = Classical::new(1.0, e, 0.0, 0.0, 0.0, m).unwrap();
        let (r3, v3) = el.to_state(1.0).unwrap();
        assert_eq!((r3[2], v3[2]), (0.0, 0.0));
        assert!((r3.norm() - r).abs() < 1e-12, "e = {e}: r = {}", r3.norm());
        // ε = −½ and e recovered from the state.
        assert_relative_eq!(
            orbit::specific_energy(1.0, &r3, &v3).unwrap(),
            -0.5,
            epsilon = 1e-14
        );
        assert!((orbit::eccentricity_vector(1.0, &r3, &v3).unwrap().norm() - e).abs() < 1e-14);
    }
    // Starting values near e → 1.
    for (e, m, big_e) in [
        (0.999999, 1e-6, 0.0180612466215222),
        (0.99, 0.01, 0.342270316491775),
        (0.9, 0.1, 0.630843527563153),
    ] {
        let got = kepler_equation::solve_kepler(m, e).unwrap();
        assert!(
            (got - big_e).abs() <= 1e-12 * big_e,
            "(e, M) = ({e}, {m}): {got}"
        );
    }
}

#[test]
fn bad_input_gives_typed_errors() {
    assert!(matches!(
        HarmonicOscillator::new(-1.0, 1.0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        HarmonicOscillator::new(1.0, f64::NAN),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        Projectile::new(0.0, 9.81),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        Pendulum::new(-2.0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        Kepler::<2>::new(-1.0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        Classical::new(1.0, 1.0, 0.1, 0.0, 0.0, 0.0),
        Err(Error::OutOfDomain { .. })
    ));
    // An ellipse's eccentricity with a hyperbola's semi-major axis sign, and conversely.
    assert!(matches!(
        Classical::new(1.0, 1.5, 0.0, 0.0, 0.0, 0.0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        Classical::new(-1.0, 0.5, 0.0, 0.0, 0.0, 0.0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        kepler_equation::solve_kepler(0.3, 1.0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        kepler_equation::solve_kepler(f64::NAN, 0.5),
        Err(Error::NonFinite { .. })
    ));
    let k = Kepler2::new(1.0).unwrap();
    let nan = SVector::from([f64::NAN, 1.0]);
    let ok = SVector::from([1.0, 0.0]);
    assert!(matches!(
        k.vector_field(0.0, &nan, &ok),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        k.vector_field(0.0, &ok, &SVector::from([0.0, f64::INFINITY])),
        Err(Error::NonFinite { .. })
    ));
    assert!(k.exact_flow(0.0, &ok, &nan, 1.0).is_err());
    // At the collision singularity the checked vector field reports it instead of returning ∞.
    assert!(k
        .vector_field(0.0, &SVector::from([0.0, 0.0]), &ok)
        .is_err());
    // An unbound state follows its conic: r = 1, |v| = 2, μ = 1 is the periapsis of the
    // hyperbola |a| = ½, e = 3, n = √8; at H from e sinh H − H = n t the closed form (Battin
    // 1999 §4.6) agrees to 1e−13 relative (a few dozen roundings, κ ≤ 3 on this arc).
    let (abs_a, e, t) = (0.5, 3.0, 1.0);
    let h = kepler_equation::solve_kepler_hyperbolic(8f64.sqrt() * t, e).unwrap();
    let (b, den, vs) = (
        abs_a * (e * e - 1.0f64).sqrt(),
        e * h.cosh() - 1.0,
        2f64.sqrt(),
    );
    let q_ref = SVector::from([abs_a * (e - h.cosh()), b * h.sinh()]);
    let p_ref = SVector::from([
        -vs * h.sinh() / den,
        vs * (e * e - 1.0f64).sqrt() * h.cosh() / den,
    ]);
    let (q, p) = k
        .exact_flow(0.0, &ok, &SVector::from([0.0, 2.0]), t)
        .unwrap();
    assert!((q - q_ref).norm() <= 1e-13 * q_ref.norm(), "{q} vs {q_ref}");
    assert!((p - p_ref).norm() <= 1e-13 * p_ref.norm(), "{p} vs {p_ref}");
    let pend = Pendulum::new(1.0).unwrap();
    assert!(pend
        .exact_flow(0.0, &SVector::from([0.0]), &SVector::from([0.1]), f64::NAN)
        .is_err());
    assert!(hamilton_jacobi::systems::AngularMomentum::new(3).is_err());
}

hamilton_jacobi::hamiltonian!(
    /// The Kepler Hamiltonian written as one function of (q, p) (general one-pass AD path).
    KeplerGeneral<3> |_s, _t, q, p| p.dot(p) * 0.5 - q.dot(q).sqrt().recip() * 0.7
);

proptest! {
    #![proptest_config(common::config(0x5eed_0004))]

    /// The separable two-pass gradient and the general one-pass gradient agree.
    #[test]
    fn separable_and_general_paths_agree(q in prop::array::uniform3(-3.0..3.0f64), p in prop::array::uniform3(-2.0..2.0f64)) {
        let (q, p) = (SVector::from(q), SVector::from(p));
        prop_assume!(q.norm() > 1e-3);
        let k = Kepler3::new(0.7).unwrap();
        let (a, b) = k.vector_field(0.0, &q, &p).unwrap();
        let (c, d) = KeplerGeneral.vector_field(0.0, &q, &p).unwrap();
        prop_assert_eq!(a, c);
        prop_assert!(rel(&b, &d, 1e-3 * d.norm()) <= 4.0 * f64::EPSILON, "{} vs {}", b, d);
        let hs = k.hessian(0.0, &q, &p).unwrap();
        let hg = KeplerGeneral.hessian(0.0, &q, &p).unwrap();
        prop_assert!(hs.sub(&hg).max_abs() <= 1e-14 * hg.max_abs(), "Hessians differ by {}", hs.sub(&hg).max_abs());
    }
}

//! Finite-time blow-up (SPEC X8) and the folded rope with an end mass (SPEC T23, Ardema 9.3):
//! the closed-form straightening time and stretch against DOP853 on the two-degree-of-freedom
//! model, and the blow-up detector on the rope and on `ẋ = x²` against their exact singular times,
//! with regular motions that must not trigger it.

use hamilton_jacobi::integrate::{
    integrate, BlowUpDetector, Dop853, Events, FirstOrderSystem, Problem, Samples,
};
use hamilton_jacobi::lagrangian::NaturalHamiltonian;
use hamilton_jacobi::nalgebra::{SVector, Vector1, Vector2};
use hamilton_jacobi::phase::State;
use hamilton_jacobi::systems::{FoldedRope, Kepler2, Pendulum};
use hamilton_jacobi::Error;

/// SPEC T23's instance: ρ = ℓ = 1, m = 0.5 (M = 0.5), g = 9.81.
fn rope(g: f64) -> FoldedRope {
    FoldedRope::new(1.0, 1.0, 0.5, g).unwrap()
}

/// The rope at μ = 0 with μ̇(0) = 1: the mass end at rest, the free end moving at ℓμ̇ = 1;
/// `p = a q̇` with `a = diag(m + ρℓ/2, ρℓ/2)`.
fn rope_start() -> (Vector2<f64>, Vector2<f64>) {
    (Vector2::zeros(), Vector2::new(0.0, 0.5))
}

/// μ̇ from the phase state: `ẏ − ẋ = p_y/a_yy − p_x/a_xx`, over ℓ = 1.
fn stretch_rate(s: &State<2>) -> f64 {
    let u = s.q[1] - s.q[0];
    s.p[1] / (0.5 * (1.0 - u)) - s.p[0] / (0.5 + 0.5 * (1.0 + u))
}

#[test]
fn folded_rope_straightening_time_and_stretch_match_the_closed_form() {
    let r = rope(9.81);
    // SPEC T23: t₁ = 0.729222220287991, and the closed form t(μ) ends there.
    let t1 = r.straightening_time(1.0).unwrap();
    assert!(
        (t1 - 0.729222220287991).abs() <= 4.0 * f64::EPSILON,
        "t₁ = {t1:.16}"
    );
    assert!((r.time_from_start(1.0, 1.0).unwrap() - t1).abs() <= 4.0 * f64::EPSILON);
    assert_eq!(r.time_from_start(0.0, 1.0).unwrap(), 0.0);

    // DOP853 on the full model to the event 1 − μ = 1e−7 (SPEC: reached at 0.72922222026).
    let h = NaturalHamiltonian(r);
    let (q0, p0) = rope_start();
    let problem = Problem::new(&h, 0.0, q0, p0, 1.0).unwrap();
    let eps = 1e-7;
    let mut samples = Samples::at([0.2, 0.5]).unwrap();
    let mut event = Events::new(|s: &State<2>| 1.0 - (s.q[1] - s.q[0]) - eps, -1, true);
    let mut invariant_spread: f64 = 0.0;
    let mut watch = hamilton_jacobi::integrate::Each(|s: &State<2>| {
        let mu = s.q[1] - s.q[0];
        let c = r.relative_invariant(mu, stretch_rate(s)).unwrap();
        invariant_spread = invariant_spread.max((c - 2.0).abs());
        hamilton_jacobi::integrate::Control::Continue
    });
    let method = Dop853::new(1e-13, 1e-15).unwrap();
    let report = integrate(
        &problem,
        &method,
        &mut ((&mut samples, &mut event), &mut watch),
    )
    .unwrap();
    assert!(report.stopped);
    let t_event = event.found[0].state.t;
    // SPEC gives the event time to 11 digits: rounding ±5e-12; DOP853's timing error there is
    // δμ/μ̇ with μ̇ ≈ 2.6e3, far below.
    assert!(
        (t_event - 0.72922222026).abs() <= 5e-12 + 1e-12,
        "t(1 − μ = 1e−7) = {t_event:.14}"
    );
    // The same time from the closed form t(μ), and the analytic tail restores t₁.
    let closed = r.time_from_start(1.0 - eps, 1.0).unwrap();
    assert!((t_event - closed).abs() <= 1e-12, "{t_event} vs {closed}");
    let tail = t1 - closed;
    assert!((t_event + tail - 0.729222220287991).abs() <= 1e-12);
    // Stretch at the SPEC's sample times (10 digits given) and the relative invariant = 2.
    let mu = |s: &State<2>| s.q[1] - s.q[0];
    assert!((mu(&samples.states[0]) - 0.2061714502).abs() <= 6e-11);
    assert!((mu(&samples.states[1]) - 0.5577450085).abs() <= 6e-11);
    // The invariant's error grows like the error in μ̇ near μ = 1 (relative conditioning
    // 1/(1 − μ) of the factor (1 − μ) in it); 1e-13 per unit of the run, times 1/(1 − μ) = 1e7.
    assert!(
        invariant_spread <= 1e-6,
        "invariant spread {invariant_spread:e}"
    );
}

#[test]
fn gravity_drops_out_of_the_rope_relative_motion() {
    let (q0, p0) = rope_start();
    let stretch_at = |g: f64| {
        let h = NaturalHamiltonian(rope(g));
        let problem = Problem::new(&h, 0.0, q0, p0, 0.6).unwrap();
        let report = integrate(&problem, &Dop853::new(1e-12, 1e-14).unwrap(), &mut ()).unwrap();
        report.last.q[1] - report.last.q[0]
    };
    let (free, heavy) = (stretch_at(0.0), stretch_at(9.81));
    // Both runs carry DOP853's error at rtol 1e-12 on states of size ≤ 2 (x falls by g t²/2).
    assert!((free - heavy).abs() <= 1e-10, "{free} vs {heavy}");
    let t = rope(0.0).time_from_start(free, 1.0).unwrap();
    assert!(
        (t - 0.6).abs() <= 1e-10,
        "closed-form time of the reached stretch: {t}"
    );
}

/// Run `system` from `(q0, p0)` over `[0, t1]` with the detector.
fn detect<S: FirstOrderSystem<N>, const N: usize>(
    system: &S,
    q0: SVector<f64, N>,
    p0: SVector<f64, N>,
    t1: f64,
    rtol: f64,
) -> (BlowUpDetector, hamilton_jacobi::Result<State<N>>) {
    let problem = Problem::new(system, 0.0, q0, p0, t1).unwrap();
    let mut detector = BlowUpDetector::new();
    let method = Dop853::new(rtol, rtol * 1e-3).unwrap();
    let run = integrate(&problem, &method, &mut detector).map(|r| r.last);
    (detector, run)
}

#[test]
fn the_rope_blow_up_is_detected_with_its_time_and_exponent() {
    let h = NaturalHamiltonian(rope(9.81));
    let (q0, p0) = rope_start();
    let t1 = rope(9.81).straightening_time(1.0).unwrap();
    let (detector, run) = detect(&h, q0, p0, 2.0, 1e-12);
    let reached = run.expect("the detector stops the run before DOP853's step size collapses");
    let s = detector
        .singularity()
        .expect("a blow-up of the stretch rate must be reported");
    println!("rope: {s:?}, exact t₁ = {t1}");
    assert_eq!(s.t_reached, reached.t);
    assert!(reached.t < t1);
    // μ̇ ∝ (1 − μ)^{−1/2} and 1 − μ ∝ (t₁ − t)^{2/3}, so ẏ ∝ (t₁ − t)^{−1/3}; the phase-space
    // rate is dominated by ṗ_y = −∂H/∂y = ρẏ²/4 + …, which grows like (t₁ − t)^{−2/3}.
    assert!(
        (s.exponent - 2.0 / 3.0).abs() <= 0.1 * 2.0 / 3.0,
        "α = {}",
        s.exponent
    );
    // The extrapolation is better than stopping: its error is a small part of the distance
    // still to go.
    let to_go = t1 - s.t_reached;
    assert!(
        (s.t_star - t1).abs() <= 0.25 * to_go,
        "t* − t₁ = {:e}, to go {to_go:e}",
        s.t_star - t1
    );
    match detector.check("folded rope") {
        Err(Error::BlowUp { t_star, .. }) => assert_eq!(t_star, s.t_star),
        other => panic!("expected Error::BlowUp, got {other:?}"),
    }
}

/// `ẋ = x²`, `x(0) = x₀`: `x = x₀/(1 − x₀t)`, singular at `1/x₀` with the rate `x² ∝ (t* − t)^{−2}`.
struct Quadratic;
impl FirstOrderSystem<1> for Quadratic {
    fn field(
        &self,
        _t: f64,
        q: &Vector1<f64>,
        _p: &Vector1<f64>,
    ) -> hamilton_jacobi::Result<(Vector1<f64>, Vector1<f64>)> {
        Ok((q.component_mul(q), Vector1::zeros()))
    }
}

#[test]
fn quadratic_blow_up_is_detected_at_one_over_x0() {
    for x0 in [0.5, 1.0, 4.0] {
        let (detector, run) = detect(&Quadratic, Vector1::new(x0), Vector1::zeros(), 10.0, 1e-10);
        run.unwrap();
        let s = detector.singularity().expect("ẋ = x² blows up");
        let (t_star, to_go) = (1.0 / x0, 1.0 / x0 - s.t_reached);
        println!("x0 = {x0}: {s:?}");
        assert!(to_go > 0.0);
        assert!((s.exponent - 2.0).abs() <= 0.2, "α = {}", s.exponent);
        assert!(
            (s.t_star - t_star).abs() <= 0.25 * to_go,
            "t* = {}",
            s.t_star
        );
    }
}

#[test]
fn regular_motions_are_not_reported_as_blow_up() {
    // Pendulum leaving the neighbourhood of its upper equilibrium: the rate grows by a factor
    // ≈ 1e5, exponentially, then oscillates.
    let pendulum = Pendulum::new(1.0).unwrap();
    let (d, run) = detect(
        &pendulum,
        Vector1::new(std::f64::consts::PI - 1e-5),
        Vector1::zeros(),
        60.0,
        1e-10,
    );
    assert_eq!(run.unwrap().t, 60.0);
    assert!(d.singularity().is_none(), "{:?}", d.singularity());
    assert!(d.check("pendulum").is_ok());
    // Kepler e = 0.99 through ten periapsis passages: the speed grows by (1 + e)/(1 − e) = 199
    // towards each passage, then falls.
    let kepler = Kepler2::new(1.0).unwrap();
    let e: f64 = 0.99;
    let (q0, p0) = (
        Vector2::new(1.0 + e, 0.0),
        Vector2::new(0.0, ((1.0 - e) / (1.0 + e)).sqrt()),
    );
    let (d, run) = detect(&kepler, q0, p0, 10.0 * std::f64::consts::TAU, 1e-12);
    assert_eq!(run.unwrap().t, 10.0 * std::f64::consts::TAU);
    assert!(d.singularity().is_none(), "{:?}", d.singularity());
}

#[test]
fn detector_and_rope_refuse_bad_input() {
    assert!(matches!(
        BlowUpDetector::new().with_growth(f64::NAN),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(BlowUpDetector::new().with_growth(0.5).is_err());
    assert!(FoldedRope::new(f64::INFINITY, 1.0, 0.5, 9.81).is_err());
    assert!(FoldedRope::new(1.0, -1.0, 0.5, 9.81).is_err());
    assert!(FoldedRope::new(1.0, 1.0, 0.5, f64::NAN).is_err());
    assert!(FoldedRope::new(1e308, 1e308, 0.5, 9.81).is_err());
    let r = rope(9.81);
    assert!(r.time_from_start(1.5, 1.0).is_err());
    assert!(r.time_from_start(f64::NAN, 1.0).is_err());
    assert!(r.time_from_start(0.5, 0.0).is_err());
    assert!(r.straightening_time(f64::INFINITY).is_err());
    assert!(r.relative_invariant(f64::NAN, 1.0).is_err());
}

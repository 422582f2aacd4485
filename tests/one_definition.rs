//! A system written once serves every method: the separable and parametric forms of
//! `hamiltonian!`, and derivatives with respect to parameters through an adaptive integrator.

use hamilton_jacobi::integrate::{
    integrate, Dop853, Fixed, ParameterSensitivity, Problem, Splitting,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::num_dual::{first_derivative, Dual64};
use hamilton_jacobi::perturbation::forces::{PerturbedTwoBody, J2};
use hamilton_jacobi::systems::kepler::elements::Classical;
use hamilton_jacobi::{hamiltonian, Hamiltonian, Parametric, Separable};

hamiltonian!(
    /// Hénon–Heiles, declared separable once.
    HenonHeiles<2> |_s, _t, q, p|
        kinetic = p.dot(p) * 0.5,
        potential = q.dot(q) * 0.5 + q[0] * q[0] * q[1] - q[1] * q[1] * q[1] / 3.0
);

hamiltonian!(
    /// A Duffing oscillator with parameters: H = p²/2 + ω²x²/2 + ε x⁴/4.
    Duffing<1> [omega, eps] |_t, q, p|
        kinetic = p[0] * p[0] * 0.5,
        potential = omega * omega * q[0] * q[0] * 0.5 + eps * q[0].powi(4) * 0.25
);

hamiltonian!(
    /// A charged particle in a uniform field (not separable): H = |p − A(q)|²/2, A = b(−y/2, x/2).
    Landau<2> [b] |_t, q, p| {
        let ax = -q[1] * b * 0.5;
        let ay = q[0] * b * 0.5;
        ((p[0] - ax).powi(2) + (p[1] - ay).powi(2)) * 0.5
    }
);

/// The separable form gives T and V separately, the same H as written out by hand, and the
/// explicit splitting methods accept it.
#[test]
fn separable_form_serves_splitting_and_general_methods() {
    let (q, p) = (SVector::from([0.1, -0.2]), SVector::from([0.3, 0.05]));
    let by_hand = |q: &SVector<f64, 2>, p: &SVector<f64, 2>| {
        0.5 * (p[0] * p[0] + p[1] * p[1]) + 0.5 * (q[0] * q[0] + q[1] * q[1]) + q[0] * q[0] * q[1]
            - q[1].powi(3) / 3.0
    };
    let h = HenonHeiles.value(0.0, &q, &p).unwrap();
    assert!((h - by_hand(&q, &p)).abs() <= 2.0 * f64::EPSILON * h.abs());
    assert_eq!(HenonHeiles.kinetic(0.0, &p), 0.5 * (0.09 + 0.0025));
    // Hand-written forces: −∂V/∂x = −x − 2xy, −∂V/∂y = −y − x² + y².
    let (_, pd) = HenonHeiles.vector_field(0.0, &q, &p).unwrap();
    assert!((pd[0] - (-q[0] - 2.0 * q[0] * q[1])).abs() < 1e-16);
    assert!((pd[1] - (-q[1] - q[0] * q[0] + q[1] * q[1])).abs() < 1e-16);
    // Verlet and DOP853 on the same value: energy errors at their orders' scale over t = 10.
    let problem = Problem::new(&HenonHeiles, 0.0, q, p, 10.0).unwrap();
    let verlet = integrate(
        &problem,
        &Fixed::new(Splitting::VERLET_KDK, 1000).unwrap(),
        &mut (),
    )
    .unwrap();
    let dop = integrate(&problem, &Dop853::new(1e-12, 1e-14).unwrap(), &mut ()).unwrap();
    let e = |s: &hamilton_jacobi::State<2>| HenonHeiles.value(0.0, &s.q, &s.p).unwrap();
    // Verlet's energy error is O(h²) = O(1e-4) times the force-curvature scale (≤ 1 here).
    assert!((e(&verlet.last) - h).abs() < 1e-4);
    assert!((e(&dop.last) - h).abs() < 1e-12);
    // The two agree to Verlet's global error O(h² t) = 1e-4 · 10.
    assert!((verlet.last.q - dop.last.q).norm() < 1e-3);
}

/// The parametric form: ∂H/∂k from the same body equals the closed form, and the nominal H
/// equals the separable one.
#[test]
fn parametric_form_differentiates_in_the_parameters() {
    let d = Duffing {
        omega: 1.5,
        eps: 0.2,
    };
    assert_eq!(Duffing::NAMES, ["omega", "eps"]);
    assert_eq!(d.parameters(), SVector::from([1.5, 0.2]));
    let (q, p) = (SVector::from([0.7]), SVector::from([-0.4]));
    let h = d.value(0.0, &q, &p).unwrap();
    let hand = 0.08 + 1.125 * 0.49 + 0.05 * 0.7f64.powi(4);
    assert!((h - hand).abs() < 4.0 * f64::EPSILON * hand);
    let (qd, pd) = (q.map(Dual64::from), p.map(Dual64::from));
    let t = Dual64::from(0.0);
    // ∂H/∂ω = ω x², ∂H/∂ε = x⁴/4.
    let (_, dw) = first_derivative(
        |w: Dual64| d.hamiltonian_with(&SVector::from([w, Dual64::from(0.2)]), t, &qd, &pd),
        1.5,
    );
    let (_, de) = first_derivative(
        |e: Dual64| d.hamiltonian_with(&SVector::from([Dual64::from(1.5), e]), t, &qd, &pd),
        0.2,
    );
    assert!((dw - 1.5 * 0.49).abs() < 1e-15);
    assert!((de - 0.7f64.powi(4) / 4.0).abs() < 1e-16);
    // Non-separable parametric: ∂H/∂b at p = 0 is (b/4)(x² + y²).
    let l = Landau { b: 2.0 };
    let (q2, p2) = (SVector::from([0.3, 0.4]), SVector::from([0.0, 0.0]));
    let (_, db) = first_derivative(
        |b: Dual64| {
            l.hamiltonian_with(
                &SVector::from([b]),
                t,
                &q2.map(Dual64::from),
                &p2.map(Dual64::from),
            )
        },
        2.0,
    );
    assert!((db - 0.5 * 0.25).abs() < 1e-16);
}

/// A Kepler + J2 state in three dimensions: a = 2, e = 0.1, i = 0.5, at periapsis.
fn j2_start() -> (SVector<f64, 3>, SVector<f64, 3>) {
    let (a, e, inc) = (2.0f64, 0.1f64, 0.5f64);
    let rp = a * (1.0 - e);
    let vp = ((1.0 + e) / (a * (1.0 - e))).sqrt();
    (
        SVector::from([rp, 0.0, 0.0]),
        SVector::from([0.0, vp * inc.cos(), vp * inc.sin()]),
    )
}

fn final_state(j2: f64, t1: f64, rtol: f64) -> SVector<f64, 6> {
    let sys = PerturbedTwoBody::conservative(1.0, J2::new(1.0, j2, 1.0).unwrap()).unwrap();
    let (q0, p0) = j2_start();
    let problem = Problem::new(&sys, 0.0, q0, p0, t1).unwrap();
    let r = integrate(&problem, &Dop853::new(rtol, rtol * 1e-2).unwrap(), &mut ()).unwrap();
    SVector::from_iterator(r.last.q.iter().chain(r.last.p.iter()).copied())
}

/// ∂(final state)/∂J₂ through a DOP853 run of the sensitivity equations, against central
/// differences of two DOP853 runs. The tolerance is derived from the difference quotients
/// themselves: the truncation error of the central difference at step `h` is estimated by
/// Richardson's `|D(h) − D(h/2)|·4/3`, its rounding error by `2·rtol·|x|/h`.
#[test]
fn sensitivity_to_j2_through_dop853_matches_central_differences() {
    let (j2, t1, rtol) = (1e-3, 10.0 * std::f64::consts::TAU * 2f64.powf(1.5), 1e-13);
    let sys = PerturbedTwoBody::conservative(1.0, J2::new(1.0, j2, 1.0).unwrap()).unwrap();
    assert_eq!(<PerturbedTwoBody<J2> as Parametric<3, 1>>::NAMES, ["J2"]);
    let aug = ParameterSensitivity::<_, 3, 1, 6>::new(&sys).unwrap();
    let (q0, p0) = j2_start();
    let (qa, pa) = aug.initial_state(&q0, &p0);
    let problem = Problem::new(&aug, 0.0, qa, pa, t1).unwrap();
    let r = integrate(&problem, &Dop853::new(rtol, rtol * 1e-2).unwrap(), &mut ()).unwrap();
    let (q, p, sq, sp) = aug.split(&r.last.q, &r.last.p);
    // The state part is the plain run's state.
    let plain = final_state(j2, t1, rtol);
    let x = SVector::<f64, 6>::from_iterator(q.iter().chain(p.iter()).copied());
    assert!((x - plain).norm() < 1e-9, "state {:e}", (x - plain).norm());
    let s = SVector::<f64, 6>::from_iterator(sq.iter().chain(sp.iter()).copied());
    let cd = |h: f64| (final_state(j2 + h, t1, rtol) - final_state(j2 - h, t1, rtol)) / (2.0 * h);
    let h = 1e-5;
    let (d1, d2) = (cd(h), cd(h / 2.0));
    let truncation = (d1 - d2).norm() * 4.0 / 3.0;
    let rounding = 2.0 * 1e-11 * plain.norm() / (h / 2.0);
    let err = (s - d2).norm();
    println!(
        "|∂x/∂J2| = {:.6e}, |S − D(h/2)| = {err:.3e}, truncation ≈ {truncation:.3e}, rounding ≈ {rounding:.3e}",
        s.norm()
    );
    assert!(s.norm() > 1.0, "J₂ moves the orbit over 10 revolutions");
    assert!(err <= 2.0 * (truncation + rounding), "{err:e}");
}

/// The sensitivity system refuses an augmented dimension that does not fit.
#[test]
fn sensitivity_dimension_is_checked() {
    let sys = PerturbedTwoBody::conservative(1.0, J2::new(1.0, 1e-3, 1.0).unwrap()).unwrap();
    assert!(ParameterSensitivity::<_, 3, 1, 5>::new(&sys).is_err());
    assert!(ParameterSensitivity::<_, 3, 1, 6>::new(&sys).is_ok());
}

hamilton_jacobi::hamiltonian!(
    /// A mass-m spring written as a general H (not declared separable).
    Spring<1> { m: f64, k: f64 } |s, _t, q, p| p[0] * p[0] / (2.0 * s.m) + q[0] * q[0] * (0.5 * s.k)
);
hamilton_jacobi::hamiltonian!(
    /// Quartic in p: not of the natural form ½a(q)p² + V(q).
    QuarticKinetic<1> |_s, _t, q, p| p[0].powi(4) * 0.25 + q[0] * q[0] * 0.5
);

/// Action–angle variables of any one-degree-of-freedom Hamiltonian in natural form, read off
/// its H: the spring's period 2π√(m/k) and action E/ω against the closed forms; a Hamiltonian
/// that is not quadratic in p is refused.
#[test]
fn action_angle_of_any_natural_hamiltonian() {
    use hamilton_jacobi::hamilton_jacobi::ActionAngle;
    let s = Spring { m: 2.0, k: 8.0 };
    let omega = (8.0f64 / 2.0).sqrt();
    let (q, p) = (0.3, 0.4);
    let e = s
        .value(0.0, &SVector::from([q]), &SVector::from([p]))
        .unwrap();
    let aa = ActionAngle::from_state(s.clone(), q, p, -10.0, 10.0).unwrap();
    let t = aa.period();
    let exact = std::f64::consts::TAU / omega;
    assert!((t.value - exact).abs() <= t.error + 8.0 * f64::EPSILON * exact);
    let j = aa.action();
    assert!((j.value - e / omega).abs() <= j.error + 8.0 * f64::EPSILON * e / omega);
    assert!((aa.frequency() - omega).abs() < 1e-13 * omega);
    let err = ActionAngle::from_state(QuarticKinetic, 0.3, 0.4, -10.0, 10.0).unwrap_err();
    assert!(err.to_string().contains("natural form"), "{err}");
}

/// `V(r) = −μ/r + β/r²`, written once.
#[derive(Clone)]
struct KeplerPlusInverseSquare {
    beta: f64,
}
impl hamilton_jacobi::systems::CentralPotential for KeplerPlusInverseSquare {
    fn potential<D: hamilton_jacobi::DualNum<f64> + Copy>(&self, r: D) -> D {
        -r.recip() + (r * r).recip() * self.beta
    }
}

/// A central potential written once gives the Cartesian system and its radial motion by
/// quadrature. For `V = −1/r + β/r²` the orbit is a precessing ellipse whose radial period is the
/// Kepler period of the same energy, `2π/(−2h)^{3/2}`, and whose apsidal angle is
/// `π k/√(k² + 2β)` (Goldstein §3.6 problem; the `β/r²` term renormalises the angular momentum):
/// closed forms against the quadratures. The Cartesian integration of the same value returns to
/// periapsis radius after one radial period.
#[test]
fn central_potential_written_once() {
    use hamilton_jacobi::hamilton_jacobi::RadialMotion;
    use hamilton_jacobi::systems::Central;
    let beta = 0.05;
    let sys = Central::<_, 3>::new(KeplerPlusInverseSquare { beta }).unwrap();
    let (q, p) = (
        SVector::from([1.0, 0.0, 0.0]),
        SVector::from([0.1, 0.9, 0.2]),
    );
    let m = RadialMotion::from_state(&sys, &q, &p, 100.0).unwrap();
    let h = sys.value(0.0, &q, &p).unwrap();
    let k = sys.angular_momentum(&q, &p);
    let tr = 2.0 * std::f64::consts::PI / (-2.0 * h).powf(1.5);
    let half = m.half_period();
    assert!(
        (2.0 * half.value - tr).abs() <= 2.0 * half.error + 16.0 * f64::EPSILON * tr,
        "{} vs {tr}",
        2.0 * half.value
    );
    let apsidal = std::f64::consts::PI * k / (k * k + 2.0 * beta).sqrt();
    let ha = m.apsidal_angle();
    assert!((ha.value - apsidal).abs() <= ha.error + 16.0 * f64::EPSILON * apsidal);
    // The same system under DOP853: the radius after one radial period from a periapsis start.
    let rp = m.periapsis();
    let vp = k / rp;
    let (q0, p0) = (SVector::from([rp, 0.0, 0.0]), SVector::from([0.0, vp, 0.0]));
    let problem = Problem::new(&sys, 0.0, q0, p0, tr).unwrap();
    let r = integrate(&problem, &Dop853::new(1e-13, 1e-15).unwrap(), &mut ()).unwrap();
    assert!(
        (r.last.q.norm() - rp).abs() < 1e-10,
        "{}",
        r.last.q.norm() - rp
    );
}

/// A double pendulum (unit masses and lengths, g = 9.81) written once as a Lagrangian,
/// `L = θ̇₁² + ½θ̇₂² + θ̇₁θ̇₂ cos(θ₁ − θ₂) + 2g cos θ₁ + g cos θ₂`.
struct DoublePendulum;
impl hamilton_jacobi::Lagrangian<2> for DoublePendulum {
    fn lagrangian<D: hamilton_jacobi::DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 2>,
        v: &SVector<D, 2>,
    ) -> D {
        let g = 9.81;
        v[0] * v[0]
            + v[1] * v[1] * 0.5
            + v[0] * v[1] * (q[0] - q[1]).cos()
            + q[0].cos() * (2.0 * g)
            + q[1].cos() * g
    }
}

/// The double pendulum's Hamiltonian written out by hand (the independent oracle):
/// `H = ½ pᵀM⁻¹p − 2g cos θ₁ − g cos θ₂`, `M = [[2, c], [c, 1]]`, `c = cos(θ₁ − θ₂)`.
fn double_pendulum_h(q: &SVector<f64, 2>, p: &SVector<f64, 2>) -> f64 {
    let c = (q[0] - q[1]).cos();
    let det = 2.0 - c * c;
    0.5 * (p[0] * p[0] - 2.0 * c * p[0] * p[1] + 2.0 * p[1] * p[1]) / det
        - 2.0 * 9.81 * q[0].cos()
        - 9.81 * q[1].cos()
}

hamilton_jacobi::hamiltonian!(
    /// The same plane pendulum written directly as a Hamiltonian, for comparison.
    PlanePendulumH<1> |_s, _t, q, p| kinetic = p[0] * p[0] * 0.5, potential = -q[0].cos()
);

/// A plane pendulum written once as a Lagrangian, `L = ½θ̇² + cos θ`.
#[derive(Clone)]
struct PlanePendulumL;
impl hamilton_jacobi::Lagrangian<1> for PlanePendulumL {
    fn lagrangian<D: hamilton_jacobi::DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        v: &SVector<D, 1>,
    ) -> D {
        v[0] * v[0] * 0.5 + q[0].cos()
    }
}

/// A regular Lagrangian, through the crate's Legendre transform, is accepted wherever a
/// Hamiltonian is: its H equals the hand-written one; Gauss–Legendre and DOP853 run it and agree
/// to their accuracies; the Poincaré-section observer and the symplectic certificate of a step
/// apply; and a one-degree-of-freedom Lagrangian gets action–angle variables whose period is the
/// pendulum's exact one (AGM).
#[test]
fn a_lagrangian_is_accepted_wherever_a_hamiltonian_is() {
    use hamilton_jacobi::brackets::certify;
    use hamilton_jacobi::hamilton_jacobi::ActionAngle;
    use hamilton_jacobi::integrate::{Crossing, Gauss, Section, StepMap};
    use hamilton_jacobi::systems::pendulum_exact::period;
    use hamilton_jacobi::Legendre;
    let h = Legendre(DoublePendulum);
    let (q0, p0) = (SVector::from([1.0, -0.5]), SVector::from([0.3, 0.8]));
    let e0 = h.value(0.0, &q0, &p0).unwrap();
    let hand = double_pendulum_h(&q0, &p0);
    assert!(
        (e0 - hand).abs() < 1e-13 * hand.abs().max(1.0),
        "{e0} vs {hand}"
    );
    let problem = Problem::new(&h, 0.0, q0, p0, 5.0).unwrap();
    let mut section = Section::new(|_t, q: &SVector<f64, 2>, _p| q[0], Crossing::Up);
    let gl = integrate(
        &problem,
        &Fixed::new(Gauss::<3>::new().unwrap(), 2000).unwrap(),
        &mut section,
    )
    .unwrap();
    let dop = integrate(&problem, &Dop853::new(1e-12, 1e-14).unwrap(), &mut ()).unwrap();
    // Gauss s = 3 (order 6) at h = 2.5e-3 over t = 5: global error ~ h⁶·t·|f⁽⁷⁾| ≪ 1e-8.
    assert!(
        (gl.last.q - dop.last.q).amax() < 1e-8,
        "{}",
        (gl.last.q - dop.last.q).amax()
    );
    let e1 = double_pendulum_h(&gl.last.q, &gl.last.p);
    assert!((e1 - hand).abs() < 1e-10 * hand.abs().max(1.0));
    assert!(!section.points.is_empty());
    for z in &section.points {
        // On the surface θ₁ = 0, crossing upwards (θ̇₁ > 0).
        assert!(z.q[0].abs() < 1e-10, "{}", z.q[0]);
        assert!(Legendre(DoublePendulum).velocity(z.t, &z.q, &z.p).unwrap()[0] > 0.0);
    }
    let step = StepMap {
        system: &h,
        method: &Gauss::<3>::new().unwrap(),
        dt: 0.01,
    };
    assert!(certify(&step, 0.0, &q0, &p0).unwrap().symplectic_defect < 1e-12);
    // One degree of freedom: action–angle variables of the Lagrangian's Hamiltonian.
    let aa = ActionAngle::from_state(Legendre(PlanePendulumL), 1.0, 0.0, -3.0, 3.0).unwrap();
    let exact = period(1.0, 1.0).unwrap();
    let t = aa.period();
    assert!(
        (t.value - exact).abs() <= t.error + 16.0 * f64::EPSILON * exact,
        "{} vs {exact}",
        t.value
    );
    // The same as the Hamiltonian written directly.
    let direct = ActionAngle::from_state(PlanePendulumH, 1.0, 0.0, -3.0, 3.0).unwrap();
    assert!((direct.action().value - aa.action().value).abs() < 1e-14);
}

/// The plain Kepler problem is "Kepler + R" with R = 0: Wisdom–Holman then composes exact Kepler
/// drifts, and 1000 steps over 10 periods (e = 0.5) stay on the exact flow to rounding. Each
/// drift is exact to a few ulps of the state, and an along-track (phase) error grows linearly
/// with the number of drifts, so the bound is 1000 drifts × 4ε × (1 + n t = 1 + 20π) × the
/// state's scale (|p₀| = √3 < 3). The same bound holds against the one-drift exact flow and
/// against the element route (Kepler's equation in the eccentric anomaly at M = n t = 20π, back
/// at periapsis; its own error, the phase error n t·δa/a of the vis-viva `a` of the rounded
/// initial state, is a few hundred ε).
#[test]
fn wisdom_holman_on_plain_kepler_is_the_exact_flow() {
    use hamilton_jacobi::integrate::WisdomHolman;
    use hamilton_jacobi::systems::{ExactFlow, Kepler2};
    let kepler = Kepler2::new(1.0).unwrap();
    let e = 0.5f64;
    let (q0, p0) = (
        SVector::from([1.0 - e, 0.0]),
        SVector::from([0.0, ((1.0 + e) / (1.0 - e)).sqrt()]),
    );
    let t1 = 10.0 * std::f64::consts::TAU;
    let problem = Problem::new(&kepler, 0.0, q0, p0, t1).unwrap();
    let run = integrate(
        &problem,
        &Fixed::new(WisdomHolman::WH, 1000).unwrap(),
        &mut (),
    )
    .unwrap();
    let (q, p) = kepler.exact_flow(0.0, &q0, &p0, t1).unwrap();
    let (r, v) = Classical::new(1.0, e, 0.0, 0.0, 0.0, t1)
        .unwrap()
        .to_state(1.0)
        .unwrap();
    let bound = 1000.0 * 4.0 * f64::EPSILON * (1.0 + t1) * 3.0;
    for (name, q, p) in [
        ("exact flow", q, p),
        (
            "element route",
            SVector::from([r[0], r[1]]),
            SVector::from([v[0], v[1]]),
        ),
    ] {
        let err = (run.last.q - q).amax().max((run.last.p - p).amax());
        println!("WH on Kepler, 1000 steps, against the {name}: {err:e} (bound {bound:e})");
        assert!(err <= bound, "{name}: {err:e} > {bound:e}");
    }
}

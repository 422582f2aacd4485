//! The method table round-trips: for every entry of [`METHODS`], its key finds it, the value built
//! from it (at run time by [`AnyMethod::new`] / [`GeneralMethod::new`], or typed for the Kepler
//! splittings and the exact flow) names itself by the entry's label and has the entry's order,
//! and the scene kind of the key is the entry. That the stated orders are the observed ones is
//! checked by the observed-order tests against the same entries: `rk4_observed_order`
//! (tests/integrate.rs), `pendulum_orders` and `kepler_orders` (tests/gauss.rs),
//! `observed_orders_of_splitting_methods` and `observed_orders_of_wisdom_holman_methods`
//! (tests/splitting.rs).

use hamilton_jacobi::integrate::methods::{Capability, Construction, Knob};
use hamilton_jacobi::integrate::{
    integrate, AnyMethod, ExactStep, GeneralMethod, Method, MethodInfo, OneStep, Problem,
    WisdomHolman, METHODS,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{NoForce, PerturbedTwoBody, J2};
use hamilton_jacobi::systems::{Kepler2, Pendulum};

/// Kepler + J₂ in the equatorial plane.
type PlanarJ2 = PerturbedTwoBody<J2, NoForce, 2>;

/// A knob value every method accepts: 20 steps, a tolerance of 1e−8, or a step of 0.05 in
/// fictitious time.
fn knob(info: &MethodInfo) -> f64 {
    match info.knob {
        Knob::Steps => 20.0,
        Knob::Tolerance => 1e-8,
        Knob::FictitiousStep => 0.05,
    }
}

#[test]
fn every_entry_round_trips() {
    let pendulum = Pendulum::new(1.0).unwrap();
    let (angle, momentum) = (SVector::from([1.0]), SVector::from([0.0]));
    let pp = Problem::new(&pendulum, 0.0, angle, momentum, 1.0).unwrap();
    let kepler = Kepler2::new(1.0).unwrap();
    let (q0, p0) = (SVector::from([1.0, 0.0]), SVector::from([0.0, 1.0]));
    let kp = Problem::new(&kepler, 0.0, q0, p0, 1.0).unwrap();
    let j2 = PlanarJ2::conservative(1.0, J2::new(1.0, 1e-3, 1.0).unwrap()).unwrap();
    let jp = Problem::new(&j2, 0.0, q0, p0, 1.0).unwrap();
    let mut seen = [0usize; 4];
    for info in &METHODS {
        let key = info.key;
        assert_eq!(MethodInfo::find(key).unwrap(), info, "{key}");
        assert_eq!(MethodInfo::of(info.construction), Some(info), "{key}");
        let label = info.label();
        match info.capability() {
            Capability::Hamiltonian => {
                seen[0] += 1;
                let g = GeneralMethod::new(info, knob(info)).unwrap();
                assert_eq!(g.info(), info, "{key}");
                match info.order {
                    Some(p) => assert_eq!(g.order(), p, "{key}"),
                    // The Taylor method's order follows its tolerance: ⌈−½ ln 1e−8 + 1⌉ = 11.
                    None => {
                        assert!(
                            matches!(
                                info.construction,
                                Construction::Taylor | Construction::TaylorDd
                            ),
                            "{key}"
                        );
                        assert_eq!(g.order(), 11, "{key}");
                    }
                }
                let shown = Method::<Pendulum, 1>::label(&g);
                assert!(shown.starts_with(&format!("{label} ")), "{key}: {shown}");
                integrate(&pp, &g, &mut ()).unwrap();
                let a = AnyMethod::new(info, knob(info)).unwrap();
                assert_eq!(a, AnyMethod::General(g), "{key}");
                assert_eq!(a.info(), Some(info), "{key}");
            }
            Capability::Separable => {
                seen[1] += 1;
                let a = AnyMethod::new(info, knob(info)).unwrap();
                assert_eq!(a.info(), Some(info), "{key}");
                assert_eq!(Some(a.order()), info.order, "{key}");
                let shown = Method::<Pendulum, 1>::label(&a);
                match a {
                    AnyMethod::Splitting(f) => {
                        assert_eq!(shown, format!("{label} n=20"), "{key}");
                        assert_eq!(OneStep::<Pendulum, 1>::name(&f.method), label);
                    }
                    AnyMethod::TimeTransformed(m) => {
                        assert_eq!(shown, format!("{label} ds=5e-2"), "{key}");
                        assert_eq!(m.name(), label);
                        assert_eq!(info.knob, Knob::FictitiousStep, "{key}");
                        assert!(a.steps().is_none(), "{key}");
                        // U = −V = μ/r > 0 on Kepler's problem (shift c = 0); the pendulum's
                        // V = 1 − cos q ≥ 0 needs a shift, which a table entry does not set.
                        integrate(&kp, &a, &mut ()).unwrap();
                        assert!(integrate(&pp, &a, &mut ()).is_err(), "{key}");
                    }
                    AnyMethod::General(_) => panic!("{key}: not a splitting"),
                }
                if let AnyMethod::Splitting(_) = a {
                    integrate(&pp, &a, &mut ()).unwrap();
                }
                assert!(GeneralMethod::new(info, 20.0).is_err(), "{key}");
            }
            Capability::PerturbedKepler => {
                seen[2] += 1;
                let Construction::KeplerSplitting(table) = info.construction else {
                    panic!("{key}: not a Kepler splitting")
                };
                let m = WisdomHolman::new(table).unwrap();
                assert_eq!(OneStep::<PlanarJ2, 2>::name(&m), label, "{key}");
                assert_eq!(Some(OneStep::<PlanarJ2, 2>::order(&m)), info.order, "{key}");
                let f = hamilton_jacobi::integrate::Fixed::new(m, 20).unwrap();
                integrate(&jp, &f, &mut ()).unwrap();
                assert!(AnyMethod::new(info, 20.0).is_err(), "{key}");
            }
            Capability::ExactFlow => {
                seen[3] += 1;
                assert_eq!(info.construction, Construction::Exact);
                assert_eq!(OneStep::<Kepler2, 2>::name(&ExactStep), label, "{key}");
                // No truncation error: the exact flow states no order, its step reports the
                // largest.
                assert_eq!(info.order, None);
                assert_eq!(OneStep::<Kepler2, 2>::order(&ExactStep), u32::MAX);
                let f = hamilton_jacobi::integrate::Fixed::new(ExactStep, 20).unwrap();
                integrate(&kp, &f, &mut ()).unwrap();
                assert!(AnyMethod::new(info, 20.0).is_err(), "{key}");
            }
        }
    }
    // RK4, Gauss–Legendre 1 … 6, RK45, DOP853, Taylor in double and in double-double; 12
    // splittings and 3 of them time-transformed; 8 Kepler splittings; the exact flow.
    assert_eq!(seen, [11, 15, 8, 1]);
}

/// The labels spell stages and order in one scheme for every family.
#[test]
fn labels_follow_one_scheme() {
    let label = |key: &str| MethodInfo::find(key).unwrap().label();
    assert_eq!(label("rk4"), "classical Runge–Kutta, 4 stages, order 4");
    assert_eq!(label("gauss1"), "Gauss–Legendre, 1 stage, order 2");
    assert_eq!(label("gauss3"), "Gauss–Legendre, 3 stages, order 6");
    assert_eq!(label("dop853"), "Dormand–Prince, 12 stages, order 8");
    assert_eq!(label("rk45"), "Dormand–Prince, 6 stages, order 5");
    assert_eq!(
        label("verlet-kdk"),
        "Störmer–Verlet (kick–drift–kick), 1 stage, order 2"
    );
    assert_eq!(label("yoshida3"), "Yoshida triple jump, 3 stages, order 4");
    assert_eq!(
        label("blanes-moan6"),
        "Blanes–Moan SRKN6b, 6 stages, order 4"
    );
    assert_eq!(label("kahan-li17"), "Kahan–Li, 17 stages, order 8");
    assert_eq!(
        label("sofroniou-spaletta35"),
        "Sofroniou–Spaletta, 35 stages, order 10"
    );
    assert_eq!(label("wisdom-holman"), "Wisdom–Holman, 1 stage, order 2");
    assert_eq!(label("saba3"), "Laskar–Robutel SABA, 3 stages, order 2");
    assert_eq!(label("sbab2"), "Laskar–Robutel SBAB, 2 stages, order 2");
    assert_eq!(label("exact"), "exact flow");
    assert_eq!(label("taylor"), "Taylor (Jorba–Zou)");
    assert_eq!(
        label("log-h-verlet-dkd"),
        "logarithmic-Hamiltonian leapfrog, 1 stage, order 2"
    );
    assert_eq!(
        label("log-h-kahan-li17"),
        "logarithmic-Hamiltonian Kahan–Li, 17 stages, order 8"
    );
}

/// A scene names a method by its key, and the scene's kind is the table's entry: same key,
/// label and knob; an unknown key is refused with the list of keys.
#[cfg(feature = "cli")]
#[test]
fn scene_kinds_are_the_table_entries() {
    use hamilton_jacobi::scene::{Knob as SceneKnob, MethodKind};
    for info in &METHODS {
        let kind = MethodKind::from_key(info.key).unwrap();
        assert_eq!(kind, MethodKind::Integrator(info));
        assert_eq!(kind.integrator(), Some(info));
        assert_eq!(kind.label(), info.label());
        let knob = match info.knob {
            Knob::Steps => SceneKnob::Steps,
            Knob::Tolerance => SceneKnob::Rtol,
            Knob::FictitiousStep => SceneKnob::Ds,
        };
        assert_eq!(kind.knob(), knob, "{}", info.key);
    }
    let keys: Vec<&str> = MethodKind::all().map(MethodKind::key).collect();
    let mut unique = keys.clone();
    unique.sort_unstable();
    unique.dedup();
    assert_eq!(unique.len(), keys.len(), "{keys:?}");
    // The integrators, the six theories (Hamilton–Jacobi, normal form, Lindstedt, osculating
    // and mean elements, Brouwer–Lyddane) and the constrained methods.
    assert_eq!(
        keys.len(),
        METHODS.len() + 6 + hamilton_jacobi::nonholonomic::CONSTRAINED_METHODS.len()
    );
    let e = MethodKind::try_from("gauss-3".to_string()).unwrap_err();
    for info in &METHODS {
        assert!(e.contains(info.key), "{e}");
    }
}

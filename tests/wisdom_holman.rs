//! Wisdom–Holman with symplectic correctors on Kepler + J₂, and the N-body Wisdom–Holman map in
//! Jacobi and democratic heliocentric coordinates on the outer Solar System.
//!
//! Oracles: the crate's DOP853 at tight tolerance (an independent, non-splitting integrator of the
//! same Hamiltonian), the identity of the coordinate maps with their inverses, AD
//! certification of canonicity, and the conservation laws of the N-body problem. Measured numbers
//! are printed (`--nocapture`).

use hamilton_jacobi::brackets::certify;
use hamilton_jacobi::integrate::Control;
use hamilton_jacobi::integrate::{
    integrate, Dop853, Each, Fixed, PlanetaryWisdomHolman, Problem, WisdomHolman,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{NoForce, PerturbedTwoBody, J2};
use hamilton_jacobi::systems::kepler::elements::Classical;
use hamilton_jacobi::systems::planetary::CoordinateMap;
use hamilton_jacobi::systems::{outer_solar_system, PlanetaryCoordinates, PlanetarySystem};
use hamilton_jacobi::Hamiltonian;
use std::f64::consts::TAU;

type V3 = SVector<f64, 3>;

/// Kepler + J₂ of the brief: `μ = R = 1`, `a = 2`, `i = 0.5`.
fn j2_problem(j2: f64, e: f64) -> (PerturbedTwoBody<J2, NoForce, 3>, V3, V3, f64) {
    let sys = PerturbedTwoBody::conservative(1.0, J2::new(1.0, j2, 1.0).unwrap()).unwrap();
    let el = Classical::new(2.0, e, 0.5, 0.3, 0.7, 0.2).unwrap();
    let (q0, p0) = el.to_state(1.0).unwrap();
    let period = TAU * 2.0f64.powf(1.5);
    (sys, q0, p0, period)
}

/// The reference: DOP853 at its tightest tolerance `rtol = atol = RTOL_MIN ≈ 2.3e−15` (the
/// measured difference to rtol 1e−13, an upper estimate of its error, is printed).
fn reference(j2: f64, e: f64, periods: f64) -> V3 {
    let (sys, q0, p0, period) = j2_problem(j2, e);
    let pb = Problem::new(&sys, 0.0, q0, p0, periods * period).unwrap();
    let tol = Dop853::RTOL_MIN;
    let tight = integrate(&pb, &Dop853::new(tol, tol).unwrap(), &mut ()).unwrap();
    let loose = integrate(&pb, &Dop853::new(1e-13, 1e-13).unwrap(), &mut ()).unwrap();
    println!(
        "  reference J2 = {j2:e}, e = {e}: DOP853 RTOL_MIN vs 1e-13 |Δq| = {:.1e}",
        (tight.last.q - loose.last.q).amax()
    );
    tight.last.q
}

fn wh_error(m: WisdomHolman, j2: f64, e: f64, periods: f64, steps: usize, qref: &V3) -> f64 {
    let (sys, q0, p0, period) = j2_problem(j2, e);
    let pb = Problem::new(&sys, 0.0, q0, p0, periods * period).unwrap();
    let r = m.propagate(&pb, steps).unwrap();
    (r.last.q - qref).amax()
}

/// J₂ = 1e−6, e = 0.1 and 0.7, 100 periods: the corrected map (orders 3 … 17) at the same step
/// is at least ten times closer to the reference than WH (SBAB₁) and SABA₁ without corrector.
/// Steps: 100 per period for e = 0.1, 400 for e = 0.7 (the pericentre passage resolved).
#[test]
fn corrector_tenfold_on_j2() {
    for (e, per_period) in [(0.1, 100), (0.7, 400)] {
        let qref = reference(1e-6, e, 100.0);
        let steps = 100 * per_period;
        let wh = wh_error(WisdomHolman::WH, 1e-6, e, 100.0, steps, &qref);
        let saba1 = wh_error(WisdomHolman::SABA1, 1e-6, e, 100.0, steps, &qref);
        println!("e = {e}: WH {wh:.2e}, SABA1 {saba1:.2e}");
        for k in [3, 5, 7, 11, 17] {
            let c = wh_error(
                WisdomHolman::WH.with_corrector(k).unwrap(),
                1e-6,
                e,
                100.0,
                steps,
                &qref,
            );
            println!("  corrector {k}: {c:.2e} (WH / corrected = {:.0})", wh / c);
            if k >= 5 {
                assert!(wh >= 10.0 * c && saba1 >= 10.0 * c, "e = {e}, order {k}");
            }
        }
    }
}

/// The error of the corrected map is `O(ε²h² + εhᵏ)`: with the order-17 corrector the `ε²h²`
/// term dominates, so halving `ε = J₂` or `h` divides the error by ≈ 4 (accepted: 3 … 5.3, the
/// `εh¹⁷` and rounding terms negligible at these sizes); without corrector (`O(εh²)`) halving
/// `ε` divides it by ≈ 2 (accepted 1.6 … 2.5).
#[test]
fn corrector_error_scaling() {
    let e = 0.1;
    let periods = 20.0;
    let steps = 20 * 64;
    let c17 = WisdomHolman::WH.with_corrector(17).unwrap();
    let err = |m: WisdomHolman, j2: f64, n: usize| {
        let qref = reference(j2, e, periods);
        wh_error(m, j2, e, periods, n, &qref)
    };
    let base = err(c17, 2e-3, steps);
    let half_eps = err(c17, 1e-3, steps);
    let half_h = err(c17, 2e-3, 2 * steps);
    let wh_base = err(WisdomHolman::WH, 2e-3, steps);
    let wh_half_eps = err(WisdomHolman::WH, 1e-3, steps);
    println!(
        "corrected: {base:.2e}, ε/2 {half_eps:.2e} (÷{:.2}), h/2 {half_h:.2e} (÷{:.2}); WH {wh_base:.2e}, ε/2 {wh_half_eps:.2e} (÷{:.2})",
        base / half_eps,
        base / half_h,
        wh_base / wh_half_eps
    );
    assert!((3.0..5.3).contains(&(base / half_eps)));
    assert!((3.0..5.3).contains(&(base / half_h)));
    assert!((1.6..2.5).contains(&(wh_base / wh_half_eps)));
}

/// A [`Fixed`] run shows every step, so its step is the conjugate `C ∘ Φ ∘ C⁻¹`: the same final
/// state as `propagate` (to the rounding of 2·steps corrector applications), and the work counts
/// the corrector's drifts and kicks.
#[test]
fn corrected_fixed_run_matches_propagate() {
    let (sys, q0, p0, period) = j2_problem(1e-3, 0.3);
    let pb = Problem::new(&sys, 0.0, q0, p0, 5.0 * period).unwrap();
    let m = WisdomHolman::WH.with_corrector(5).unwrap();
    let a = m.propagate(&pb, 500).unwrap();
    let b = integrate(&pb, &Fixed::new(m, 500).unwrap(), &mut ()).unwrap();
    let d = (a.last.q - b.last.q).amax();
    println!(
        "propagate vs Fixed: {d:.1e}; work {:?} / {:?}",
        a.work, b.work
    );
    assert!(d < 1e-11);
    let c = m.corrector().unwrap();
    let (drifts, kicks) = c.evaluations();
    // Kernel SABA₁: 2 drifts and 1 kick per step; `propagate` merges the closing half-drift of
    // each step with the opening one of the next (501 drifts for 500 steps).
    assert_eq!(a.work.flows, 500 + 1 + 2 * drifts);
    assert_eq!(a.work.gradients, 500 + 2 * kicks);
    assert_eq!(b.work.flows, 500 * (2 + 2 * drifts));
    assert_eq!(b.work.gradients, 500 * (1 + 2 * kicks));
    // The corrector is rejected where it is not defined.
    assert!(WisdomHolman::SABA2.with_corrector(5).is_err());
    assert!(WisdomHolman::WH.with_corrector(4).is_err());
}

// ------------------------------------------------------------------------------------------
// N-body
// ------------------------------------------------------------------------------------------

const COORDS: [PlanetaryCoordinates; 2] = [
    PlanetaryCoordinates::Jacobi,
    PlanetaryCoordinates::DemocraticHeliocentric,
];

/// Both coordinate maps round-trip to rounding and are canonical (AD certificate).
#[test]
fn coordinate_maps_round_trip_and_are_canonical() {
    let (sys, q, p) = outer_solar_system();
    for c in COORDS {
        let (qj, pj) = sys.to_coordinates(c, &q, &p);
        let (q1, p1) = sys.from_coordinates(c, &qj, &pj);
        let dq = (q1 - q).amax() / q.amax();
        let dp = (p1 - p).amax() / p.amax();
        println!("{c:?}: round trip {dq:.1e} / {dp:.1e}");
        assert!(dq < 1e-15 && dp < 1e-15);
        for inverse in [false, true] {
            let map = CoordinateMap {
                system: &sys,
                coordinates: c,
                inverse,
            };
            let cert = certify(&map, 0.0, &q, &p).unwrap();
            println!(
                "  certificate (inverse {inverse}): {:.1e}",
                cert.symplectic_defect
            );
            assert!(cert.symplectic_defect < 1e-12);
        }
    }
    // The splits are of the one Hamiltonian: Kepler + centre of mass + (jump) + interaction = H.
    for c in COORDS {
        let (qj, pj) = sys.to_coordinates(c, &q, &p);
        let mut h = sys.interaction(c, &qj);
        let n = sys.bodies();
        let body = |v: &SVector<f64, 15>, i: usize| V3::new(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
        for i in 0..n {
            let m = sys.kepler_mass(c, i);
            h += body(&pj, i).norm_squared() / (2.0 * m);
            if i > 0 {
                h -= m * sys.kepler_mu(c, i) / body(&qj, i).norm();
            }
        }
        if c == PlanetaryCoordinates::DemocraticHeliocentric {
            let s: V3 = (1..n).map(|i| body(&pj, i)).sum();
            h += s.norm_squared() / (2.0 * sys.masses()[0]);
        }
        let h0 = sys.value(0.0, &q, &p).unwrap();
        println!("{c:?}: split sum − H = {:.1e} (H = {h0:.6e})", h - h0);
        assert!((h - h0).abs() < 1e-14 * h0.abs() * 10.0);
    }
}

/// The largest relative energy error of a run of `steps` steps over `span`.
fn energy_error<const N: usize>(
    sys: &PlanetarySystem<N>,
    q: SVector<f64, N>,
    p: SVector<f64, N>,
    m: PlanetaryWisdomHolman,
    span: f64,
    steps: usize,
) -> f64 {
    let h0 = sys.value(0.0, &q, &p).unwrap();
    let pb = Problem::new(sys, 0.0, q, p, span).unwrap();
    let mut worst: f64 = 0.0;
    let mut obs = Each(|s: &hamilton_jacobi::State<N>| {
        worst = worst.max(((sys.value(s.t, &s.q, &s.p).unwrap() - h0) / h0).abs());
        Control::Continue
    });
    integrate(&pb, &Fixed::new(m, steps).unwrap(), &mut obs).unwrap();
    worst
}

/// The energy error of WH is `O(ε h²)`: halving `h` divides it by ≈ 4 (observed order 2 ± 0.25),
/// halving every planet mass (`ε`) by ≈ 2 (accepted 1.6 … 2.5). Over 2·10⁴ days (about two
/// Saturn periods), steps of 100 and 50 days.
#[test]
fn planetary_energy_error_order_two_with_mass_prefactor() {
    let (sys, q, p) = outer_solar_system();
    let half = PlanetarySystem::<15>::new(
        sys.g(),
        &[
            sys.masses()[0],
            sys.masses()[1] / 2.0,
            sys.masses()[2] / 2.0,
            sys.masses()[3] / 2.0,
            sys.masses()[4] / 2.0,
        ],
    )
    .unwrap();
    // Same velocities, half the planet momenta.
    let mut ph = p;
    for k in 3..15 {
        ph[k] /= 2.0;
    }
    let span = 2e4;
    for c in COORDS {
        let m = PlanetaryWisdomHolman::new(WisdomHolman::WH, c).unwrap();
        let e1 = energy_error(&sys, q, p, m, span, 200);
        let e2 = energy_error(&sys, q, p, m, span, 400);
        let eh = energy_error(&half, q, ph, m, span, 200);
        let order = (e1 / e2).log2();
        println!("{c:?}: |ΔE/E| {e1:.2e} (h = 100 d), {e2:.2e} (h = 50 d): order {order:.2}; masses / 2: {eh:.2e} (÷{:.2})", e1 / eh);
        assert!((1.75..2.25).contains(&order));
        assert!((1.6..2.5).contains(&(e1 / eh)));
    }
}

/// Jacobi and democratic heliocentric WH (and Jacobi with the order-17 corrector) against DOP853
/// at `rtol = RTOL_MIN`, `atol = 1e−22` (planet momenta are ~1e−6: the absolute tolerance must be
/// far below them) over 2000 days with h = 2 days. Bound: the WH global error is `≈ ε (n h)² × a`
/// times a constant of order one growing linearly with the span — with `ε ≈ 10⁻³`, Jupiter's
/// `n h ≈ 2π·2/4332 ≈ 2.9·10⁻³`, `a ≈ 5`, and at most `t/P ≈ 0.5` Jupiter orbits: about
/// `4·10⁻⁸` AU; accepted `2·10⁻⁷`. The corrected map: `ε² (n h)² a` plus the reference's error:
/// accepted `1e−9`.
#[test]
fn planetary_wh_agrees_with_dop853() {
    let (sys, q, p) = outer_solar_system();
    let span = 2000.0;
    let pb = Problem::new(&sys, 0.0, q, p, span).unwrap();
    let r = integrate(&pb, &Dop853::new(Dop853::RTOL_MIN, 1e-22).unwrap(), &mut ()).unwrap();
    for c in COORDS {
        let m = PlanetaryWisdomHolman::new(WisdomHolman::WH, c).unwrap();
        let a = m.propagate(&pb, 1000).unwrap();
        let b = integrate(&pb, &Fixed::new(m, 1000).unwrap(), &mut ()).unwrap();
        let ea = (a.last.q - r.last.q).amax();
        let eb = (b.last.q - r.last.q).amax();
        println!("{c:?}: |Δq| propagate {ea:.2e}, Fixed {eb:.2e}");
        assert!(ea < 2e-7 && eb < 2e-7);
    }
    let m = PlanetaryWisdomHolman::new(
        WisdomHolman::WH.with_corrector(17).unwrap(),
        PlanetaryCoordinates::Jacobi,
    )
    .unwrap();
    let a = m.propagate(&pb, 1000).unwrap();
    let ea = (a.last.q - r.last.q).amax();
    println!("Jacobi, corrector 17: |Δq| {ea:.2e}");
    assert!(ea < 1e-9);
    assert!(PlanetaryWisdomHolman::new(
        WisdomHolman::WH.with_corrector(3).unwrap(),
        PlanetaryCoordinates::DemocraticHeliocentric
    )
    .is_err());
}

/// Total momentum and angular momentum are conserved by every sub-flow, hence to rounding:
/// 10⁴ steps, relative drift below 1e−13 (a few ulps × √steps).
#[test]
fn planetary_momenta_conserved_to_rounding() {
    let (sys, q, p) = outer_solar_system();
    let pb = Problem::new(&sys, 0.0, q, p, 1e5).unwrap();
    let l0 = sys.angular_momentum(&q, &p);
    let p0 = sys.momentum(&p);
    for c in COORDS {
        let m = PlanetaryWisdomHolman::new(WisdomHolman::WH, c).unwrap();
        let r = integrate(&pb, &Fixed::new(m, 10_000).unwrap(), &mut ()).unwrap();
        let dl = (sys.angular_momentum(&r.last.q, &r.last.p) - l0).norm() / l0.norm();
        let dp = (sys.momentum(&r.last.p) - p0).norm() / sys.masses()[1];
        println!("{c:?}: |ΔL|/|L| {dl:.1e}, |ΔP|/m_J {dp:.1e}");
        assert!(dl < 1e-13 && dp < 1e-13);
    }
}

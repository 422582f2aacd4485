//! Regularised and time-transformed integration against exact flows: the Levi-Civita and
//! Kustaanheimo–Stiefel maps, the unperturbed KS oscillator in closed form, Kepler e = 0.99 over
//! 100 periods against the exact flow, Kepler + J₂ = 1e−3 at e = 0.7, the logarithmic-Hamiltonian
//! leapfrog on Kepler (exact orbit, time error of order 2), the pendulum next to its separatrix,
//! the rounding floors (runs from starts moved by 1 ulp), and SPEC X3's long leapfrog runs.

use hamilton_jacobi::integrate::regularised::{fictitious_span, propagate};
use hamilton_jacobi::integrate::{
    integrate, Dop853, EnergyMonitor, Fixed, Gauss, KustaanheimoStiefel, LeviCivita, Problem,
    Regularisation, Splitting, Taylor, TimeTransformed,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{NoForce, PerturbedTwoBody, J2};
use hamilton_jacobi::phase::State;
use hamilton_jacobi::systems::{ExactFlow, Kepler2, Kepler3};
use hamilton_jacobi::Hamiltonian;
use std::f64::consts::TAU;

fn kepler_start(e: f64) -> State<2> {
    State::from_arrays(0.0, [1.0 - e, 0.0], [0.0, ((1.0 + e) / (1.0 - e)).sqrt()]).unwrap()
}

fn distance<const N: usize>(a: &State<N>, q: &SVector<f64, N>, p: &SVector<f64, N>) -> f64 {
    (a.q - q).amax().max((a.p - p).amax())
}

/// Starts moved by one ulp in each component, up and down.
fn ulp_neighbours<const N: usize>(s: &State<N>) -> Vec<State<N>> {
    let mut out = Vec::new();
    for i in 0..2 * N {
        for up in [true, false] {
            let mut x = *s;
            let v = if i < N { &mut x.q[i] } else { &mut x.p[i - N] };
            *v = if up { v.next_up() } else { v.next_down() };
            out.push(x);
        }
    }
    out
}

#[test]
fn levi_civita_and_ks_maps_round_trip() {
    let k2 = Kepler2::new(1.0).unwrap();
    let k3 = Kepler3::new(1.0).unwrap();
    let lc = LeviCivita::new(&k2).unwrap();
    let ks = KustaanheimoStiefel::new(&k3).unwrap();
    let planar = [
        ([0.3, 0.0], [0.0, 2.0]),
        ([-0.7, 0.2], [0.4, -1.1]),
        ([-0.5, -1e-9], [0.1, 0.9]),
        ([1e-3, -2.0], [-0.6, 0.05]),
    ];
    for (q, p) in planar {
        let x = State::from_arrays(1.5, q, p).unwrap();
        let y = lc.to_regular(&x).unwrap();
        let back = lc.to_physical(&y).unwrap();
        let scale = x.q.amax().max(x.p.amax());
        assert!(
            distance(&back, &x.q, &x.p) <= 4.0 * f64::EPSILON * scale,
            "{q:?}"
        );
        assert_eq!(back.t, 1.5);
        // K = r (H + p_t) vanishes at the start.
        let k = lc.value(0.0, &y.q, &y.p).unwrap();
        assert!(
            k.abs() <= 8.0 * f64::EPSILON * (1.0 + y.p.norm_squared()),
            "K = {k:e}"
        );
    }
    let spatial = [
        ([0.3, 0.1, -0.2], [0.0, 2.0, 0.3]),
        ([-0.7, 0.2, 0.5], [0.4, -1.1, 0.2]),
        ([-1.0, 0.0, 0.0], [0.0, 1.0, 0.0]),
        ([0.0, 0.0, 1.3], [0.9, 0.0, -0.1]),
    ];
    for (q, p) in spatial {
        let x = State::from_arrays(-2.0, q, p).unwrap();
        let y = ks.to_regular(&x).unwrap();
        let back = ks.to_physical(&y).unwrap();
        let scale = x.q.amax().max(x.p.amax());
        assert!(
            distance(&back, &x.q, &x.p) <= 4.0 * f64::EPSILON * scale,
            "{q:?}"
        );
        assert!(ks.bilinear(&y).abs() <= 4.0 * f64::EPSILON * y.p.amax() * y.q.amax());
        let k = ks.value(0.0, &y.q, &y.p).unwrap();
        assert!(
            k.abs() <= 8.0 * f64::EPSILON * (1.0 + y.p.norm_squared()),
            "K = {k:e}"
        );
    }
    // The collision has no regular momentum.
    let origin = State::from_arrays(0.0, [0.0, 0.0, 0.0], [1.0, 0.0, 0.0]).unwrap();
    assert!(ks.to_regular(&origin).is_err());
}

/// Unperturbed KS motion is the oscillator `u'' = (E/2) u`, `ω = √(−E/2)`:
/// `u(s) = A cos ωs + B sin ωs`, `w = 4u'`, and `t(s) = t₀ + ∫|u|² ds` in closed form.
#[test]
fn unperturbed_ks_motion_is_a_harmonic_oscillator() {
    let kepler = Kepler3::new(1.0).unwrap();
    let ks = KustaanheimoStiefel::new(&kepler).unwrap();
    let v = 3f64.sqrt();
    let start = State::from_arrays(
        0.25,
        [0.5, 0.0, 0.0],
        [0.0, v * 0.5f64.cos(), v * 0.5f64.sin()],
    )
    .unwrap();
    let y0 = ks.to_regular(&start).unwrap();
    let energy = -y0.p[4];
    assert!((energy + 0.5).abs() < 1e-15);
    let w = (-energy / 2.0).sqrt();
    let a = SVector::<f64, 4>::from_fn(|i, _| y0.q[i]);
    let b = SVector::<f64, 4>::from_fn(|i, _| y0.p[i] / 4.0 / w);
    let s1 = 20.0;
    let pb = Problem::new(&ks, 0.0, y0.q, y0.p, s1).unwrap();
    let run = integrate(&pb, &Dop853::new(1e-13, 1e-13).unwrap(), &mut ()).unwrap();
    let (c, s) = ((w * s1).cos(), (w * s1).sin());
    let u = a * c + b * s;
    let du = (b * c - a * s) * w;
    let t = start.t
        + 0.5 * (a.norm_squared() + b.norm_squared()) * s1
        + (a.norm_squared() - b.norm_squared()) * (2.0 * w * s1).sin() / (4.0 * w)
        + a.dot(&b) * (1.0 - (2.0 * w * s1).cos()) / (2.0 * w);
    for i in 0..4 {
        assert!((run.last.q[i] - u[i]).abs() < 1e-11, "u{i}");
        assert!((run.last.p[i] - 4.0 * du[i]).abs() < 1e-11, "w{i}");
    }
    assert!(
        (run.last.q[4] - t).abs() < 1e-11 * t,
        "t {} vs {t}",
        run.last.q[4]
    );
    // p_t is constant (no explicit time dependence).
    assert_eq!(run.last.p[4], y0.p[4]);
    // And the physical state is the Kepler flow at that time.
    let x = ks.to_physical(&run.last).unwrap();
    let (q, p) = kepler.exact_flow(start.t, &start.q, &start.p, x.t).unwrap();
    assert!(distance(&x, &q, &p) < 1e-10);
}

/// Kepler e = 0.99 over 100 periods: Levi-Civita + DOP853 (and + Gauss–Legendre 6 in `s`)
/// against DOP853 in Cartesian coordinates, errors against the exact flow (printed: error,
/// gradient evaluations).
#[test]
fn kepler_e099_levi_civita_against_the_exact_flow() {
    let kepler = Kepler2::new(1.0).unwrap();
    let start = kepler_start(0.99);
    let t1 = 100.0 * TAU;
    let (qe, pe) = kepler.exact_flow(0.0, &start.q, &start.p, t1).unwrap();
    let lc = LeviCivita::new(&kepler).unwrap();
    let span = fictitious_span(&lc, &start, t1).unwrap();
    let pb = Problem::new(&kepler, 0.0, start.q, start.p, t1).unwrap();
    let mut lc_best = f64::INFINITY;
    for tol in [1e-8, 1e-10, 1e-12, 1e-13] {
        let dop = Dop853::new(tol, tol).unwrap();
        let run = propagate(&lc, &dop, &start, &[t1], span).unwrap();
        let e_lc = distance(&run.states[0], &qe, &pe);
        let cart = integrate(&pb, &dop, &mut ()).unwrap();
        let e_cart = distance(&cart.last, &qe, &pe);
        println!(
            "e = 0.99, tol {tol:e}: Levi-Civita DOP853 error {e_lc:.2e} ({} gradients, {:?}, \
             max |K| {:.1e}); Cartesian DOP853 error {e_cart:.2e} ({} gradients, {:?})",
            run.work.gradients, run.elapsed, run.max_k, cart.work.gradients, cart.elapsed
        );
        // Regularised: fewer evaluations and a smaller error at every tolerance.
        assert!(
            run.work.gradients < cart.work.gradients && e_lc < e_cart,
            "tol {tol:e}"
        );
        lc_best = lc_best.min(e_lc);
    }
    {
        let ds = 0.01;
        let steps = (span / ds).ceil() as usize;
        let gauss = Fixed::new(Gauss::<6>::new().unwrap(), steps).unwrap();
        let run = propagate(&lc, &gauss, &start, &[t1], span).unwrap();
        let err = distance(&run.states[0], &qe, &pe);
        println!(
            "e = 0.99, ds {ds}: Levi-Civita Gauss6 error {err:.2e} ({} gradients, {:?})",
            run.work.gradients, run.elapsed
        );
        lc_best = lc_best.min(err);
    }
    // The problem's own sensitivity to 1 ulp at the start is ≈ 1e−9 (issue 18); DOP853 in `s`
    // is held at ≈ 3e−6 by its tolerance on t(s) (RTOL 1e−13), Gauss–Legendre 6 reaches 1.7e−9.
    assert!(lc_best < 1e-8, "{lc_best:e}");
}

/// Kepler e = 0.99 over 100 periods: Levi-Civita with the Taylor method in `s` (the regularised
/// equations are polynomial) against the exact flow of the double start. The bound is issue 18's
/// goal, max(1e−12, 3 × floor), the floor being the problem's own: the largest change of the exact
/// final state when one input moves by 1 ulp (4.7e−7: `p₂` moved by 1 ulp changes the energy by
/// `v δv ≈ 2.5e−14`, a relative 5e−14, and the mean motion and the phase after 100 periods with
/// it; at periapsis `|ṗ| = 1/r² = 10⁴`). Measured: errors 3.7e−7
/// (tol 1e−11, 557 steps) and 6.3e−9 (tol 1e−13, 517 steps); the Cartesian Taylor method at
/// the same tolerances: 4.1e−5 (11 643 steps) and 6.0e−6 (11 747 steps).
#[test]
fn kepler_e099_levi_civita_taylor_reaches_the_rounding_floor() {
    let kepler = Kepler2::new(1.0).unwrap();
    let start = kepler_start(0.99);
    let t1 = 100.0 * TAU;
    let (qe, pe) = kepler.exact_flow(0.0, &start.q, &start.p, t1).unwrap();
    let mut spread = 0.0f64;
    for s in ulp_neighbours(&start) {
        let (q, p) = kepler.exact_flow(0.0, &s.q, &s.p, t1).unwrap();
        spread = spread.max((q - qe).amax().max((p - pe).amax()));
    }
    let bound = (3.0 * spread).max(1e-12);
    let lc = LeviCivita::new(&kepler).unwrap();
    let span = fictitious_span(&lc, &start, t1).unwrap();
    let pb = Problem::new(&kepler, 0.0, start.q, start.p, t1).unwrap();
    for tol in [1e-11, 1e-13] {
        let taylor = Taylor::new(tol).unwrap();
        let run = propagate(&lc, &taylor, &start, &[t1], span).unwrap();
        let x = run.states[0];
        let err = distance(&x, &qe, &pe);
        let cart = integrate(&pb, &taylor, &mut ()).unwrap();
        println!(
            "e = 0.99, tol {tol:e}: Levi-Civita Taylor error {err:.2e} ({} steps), bound \
             {bound:.2e} (1-ulp spread {spread:.2e}); Cartesian Taylor {:.2e} ({} steps)",
            run.work.steps,
            distance(&cart.last, &qe, &pe),
            cart.work.steps
        );
        assert!(err <= bound, "tol {tol:e}: {err:e} > {bound:e}");
        assert!(run.work.steps < cart.work.steps, "tol {tol:e}");
    }
}

/// Kepler + J₂ = 1e−3 at e = 0.7 (a = 2, i = 0.5, R = 1) over 100 periods by
/// Kustaanheimo–Stiefel + DOP853, against DOP853 in Cartesian coordinates at its tightest
/// tolerance; the energy (J₂ is autonomous) and the bilinear relation are kept.
#[test]
fn j2_e07_kustaanheimo_stiefel() {
    let model = J2::new(1.0, 1e-3, 1.0).unwrap();
    let sys = PerturbedTwoBody::<_, NoForce, 3>::conservative(1.0, model).unwrap();
    let (a, e, inc) = (2.0f64, 0.7, 0.5f64);
    let r = a * (1.0 - e);
    let v = ((1.0 + e) / r).sqrt();
    let start =
        State::from_arrays(0.0, [r, 0.0, 0.0], [0.0, v * inc.cos(), v * inc.sin()]).unwrap();
    let t1 = 100.0 * TAU * a.powf(1.5);
    let pb = Problem::new(&sys, 0.0, start.q, start.p, t1).unwrap();
    let reference = integrate(&pb, &Dop853::new(Dop853::RTOL_MIN, 1e-16).unwrap(), &mut ())
        .unwrap()
        .last;
    let h0 = sys.value(0.0, &start.q, &start.p).unwrap();
    let ks = KustaanheimoStiefel::new(&sys).unwrap();
    let span = fictitious_span(&ks, &start, t1).unwrap();
    let mut best = f64::INFINITY;
    for tol in [1e-9, 1e-11, 1e-13] {
        let dop = Dop853::new(tol, tol).unwrap();
        let run = propagate(&ks, &dop, &start, &[t1], span).unwrap();
        let x = run.states[0];
        let diff = distance(&x, &reference.q, &reference.p);
        let cart = integrate(&pb, &dop, &mut ()).unwrap();
        println!(
            "J2 1e-3 e 0.7, tol {tol:e}: KS DOP853 vs reference {diff:.2e} ({} gradients, \
             {:?}, max |ℓ| {:.1e}, max |K| {:.1e}); Cartesian {:.2e} ({} gradients, {:?})",
            run.work.gradients,
            run.elapsed,
            run.max_bilinear,
            run.max_k,
            distance(&cart.last, &reference.q, &reference.p),
            cart.work.gradients,
            cart.elapsed
        );
        best = best.min(diff);
        if tol == 1e-13 {
            let h1 = sys.value(t1, &x.q, &x.p).unwrap();
            assert!(((h1 - h0) / h0).abs() < 1e-11, "energy {h1} vs {h0}");
            assert!(run.max_bilinear < 1e-11, "{}", run.max_bilinear);
        }
    }
    assert!(best < 1e-7, "{best:e}");
}

/// Mean anomaly of a state of Kepler μ = 1 (elliptic), and the mean motion.
fn mean_anomaly(s: &State<2>) -> (f64, f64) {
    let r = s.q.norm();
    let a = 1.0 / (2.0 / r - s.p.norm_squared());
    let ecos = 1.0 - r / a;
    let esin = s.q.dot(&s.p) / a.sqrt();
    let big_e = esin.atan2(ecos);
    (big_e - esin, a.powf(-1.5))
}

fn wrap(x: f64) -> f64 {
    x - TAU * (x / TAU).round()
}

/// The logarithmic-Hamiltonian leapfrog (drift–kick–drift) on Kepler e = 0.9 and 0.99 moves on
/// the exact orbit: energy and eccentricity vector to rounding over 100 periods at large steps,
/// the error being in time only (Mikkola & Tanikawa 1999); that time error is of order 2 in
/// `ds` (measured between ds = 0.02 and 0.01).
#[test]
fn log_hamiltonian_leapfrog_keeps_the_kepler_orbit() {
    let kepler = Kepler2::new(1.0).unwrap();
    for e in [0.9, 0.99] {
        let start = kepler_start(e);
        let e0 = SVector::from([e, 0.0]);
        let energy0 = kepler.value(0.0, &start.q, &start.p).unwrap();
        let eccentricity = |s: &State<2>| {
            let (q, p) = (s.q, s.p);
            let r = q.norm();
            q * (p.norm_squared() - 1.0 / r) - p * q.dot(&p)
        };
        let t1 = 100.0 * TAU;
        let pb = Problem::new(&kepler, 0.0, start.q, start.p, t1).unwrap();
        let mut time_errors = Vec::new();
        for ds in [0.02, 0.01] {
            let m = TimeTransformed::logarithmic(Splitting::VERLET_DKD, ds).unwrap();
            let run = integrate(&pb, &m, &mut ()).unwrap();
            let de = (kepler.value(0.0, &run.last.q, &run.last.p).unwrap() - energy0).abs();
            let decc = (eccentricity(&run.last) - e0).amax();
            let (m1, n) = mean_anomaly(&run.last);
            let tau = wrap(m1 - n * t1) / n;
            println!(
                "log-H leapfrog e = {e}, ds = {ds}: {} steps, |ΔE| {de:.1e}, |Δe| {decc:.1e}, \
                 time error {tau:.3e}",
                run.work.steps
            );
            assert!(de < 1e-11, "e = {e}, ds = {ds}: ΔE = {de:e}");
            assert!(decc < 1e-10, "e = {e}, ds = {ds}: Δe = {decc:e}");
            time_errors.push(tau);
        }
        let order = (time_errors[0] / time_errors[1]).abs().log2();
        println!("log-H leapfrog e = {e}: time-error order {order:.3}");
        assert!((order - 2.0).abs() < 0.1, "order {order}");
        // Kick–drift–kick does not keep the orbit: the exactness is the drift–kick–drift word's.
        let kdk = TimeTransformed::logarithmic(Splitting::VERLET_KDK, 0.02).unwrap();
        let run = integrate(&pb, &kdk, &mut ()).unwrap();
        let de = (kepler.value(0.0, &run.last.q, &run.last.p).unwrap() - energy0).abs();
        println!("log-H kick–drift–kick e = {e}, ds = 0.02: |ΔE| {de:.1e}");
    }
}

/// Higher-order compositions of the logarithmic-Hamiltonian leapfrog on Kepler e = 0.9 and 0.99
/// over 100 periods against the exact flow, and the floor: the spread of the final states of
/// the same scheme from starts moved by 1 ulp, beside the exact flow's own spread. The error must
/// reach max(1e−12, 3 × floor) (issue 18's goal for the time-transformed schemes). Measured at
/// ds = 0.05: errors 1.1e−11 (e = 0.9) and 1.9e−7 (e = 0.99) against scheme spreads 6.5e−10 and
/// 5.6e−7.
#[test]
fn log_hamiltonian_compositions_on_kepler_and_their_floor() {
    let kepler = Kepler2::new(1.0).unwrap();
    let t1 = 100.0 * TAU;
    for (e, ds) in [(0.9, 0.05), (0.99, 0.05)] {
        let start = kepler_start(e);
        let (qe, pe) = kepler.exact_flow(0.0, &start.q, &start.p, t1).unwrap();
        let pb = Problem::new(&kepler, 0.0, start.q, start.p, t1).unwrap();
        let m = TimeTransformed::logarithmic(Splitting::KAHAN_LI17, ds).unwrap();
        let run = integrate(&pb, &m, &mut ()).unwrap();
        let err = distance(&run.last, &qe, &pe);
        let (mut spread, mut exact_spread) = (0.0f64, 0.0f64);
        for s in ulp_neighbours(&start) {
            let p = Problem::new(&kepler, 0.0, s.q, s.p, t1).unwrap();
            let r = integrate(&p, &m, &mut ()).unwrap();
            spread = spread.max(distance(&r.last, &run.last.q, &run.last.p));
            let (q, pp) = kepler.exact_flow(0.0, &s.q, &s.p, t1).unwrap();
            exact_spread = exact_spread.max(distance(&r.last, &q, &pp).max((q - qe).amax()));
        }
        println!(
            "log-H Kahan–Li 17 e = {e}, ds = {ds}: error {err:.2e} ({} gradients, {:?}); \
             1-ulp spread of the scheme {spread:.2e}, of the exact flow and scheme vs exact \
             {exact_spread:.2e}",
            run.work.gradients, run.elapsed
        );
        // The goal of the time transformation: the truncation error below the rounding floor,
        // max(1e−12, 3 × the 1-ulp spread of the scheme's own end state).
        let bound = (3.0 * spread).max(1e-12);
        assert!(err <= bound, "e = {e}: {err:e} > {bound:e}");
    }
}

/// SPEC X3: Kepler e = 0.9, μ = a = 1, 100 orbits of fixed-step leapfrog (kick–drift–kick) with
/// `h = T/20000`. From periapsis the final relative energy error is 2.3e−4 (periapsis under-
/// resolved); from apoapsis it is ≈ 1e−13, while each periapsis passage still reaches 2.3e−4.
#[test]
fn spec_x3_leapfrog_from_periapsis_and_apoapsis() {
    let kepler = Kepler2::new(1.0).unwrap();
    let e = 0.9f64;
    let steps = 100 * 20_000;
    let t1 = 100.0 * TAU;
    let periapsis = kepler_start(e);
    let apoapsis = State::from_arrays(
        0.0,
        [-(1.0 + e), 0.0],
        [0.0, -((1.0 - e) / (1.0 + e)).sqrt()],
    )
    .unwrap();
    let mut finals = Vec::new();
    for start in [periapsis, apoapsis] {
        let pb = Problem::new(&kepler, 0.0, start.q, start.p, t1).unwrap();
        let mut monitor = EnergyMonitor::new(&kepler, 1);
        let run = integrate(
            &pb,
            &Fixed::new(Splitting::VERLET_KDK, steps).unwrap(),
            &mut monitor,
        )
        .unwrap();
        let h0 = kepler.value(0.0, &start.q, &start.p).unwrap();
        let h1 = kepler.value(t1, &run.last.q, &run.last.p).unwrap();
        let final_error = ((h1 - h0) / h0).abs();
        println!(
            "SPEC X3 leapfrog h = T/20000 from q = {:?}: final |ΔE/E| {final_error:.2e}, max \
             {:.2e}",
            start.q.as_slice(),
            monitor.max_error
        );
        finals.push((final_error, monitor.max_error));
    }
    let (peri, apo) = (finals[0], finals[1]);
    assert!((peri.0 / 2.3e-4 - 1.0).abs() < 0.1, "{:e}", peri.0);
    assert!(apo.0 < 1e-12, "{:e}", apo.0);
    assert!((apo.1 / 2.3e-4 - 1.0).abs() < 0.1, "{:e}", apo.1);
}

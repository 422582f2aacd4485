//! Kepler entry points under hostile but valid input: extreme magnitudes of the anomaly solvers and
//! of the mean motion, strongly hyperbolic arcs of the universal-variable drift, phase advances
//! too long for floating point, and an integration started at the collision singularity. Each
//! test asserts "a typed error, or a finite value agreeing with an independent reference".

use hamilton_jacobi::integrate::{
    integrate, Dop853, ExactStep, Fixed, Gauss, Problem, Rk4, Splitting, WisdomHolman,
};
use hamilton_jacobi::nalgebra::{SVector, Vector2, Vector3};
use hamilton_jacobi::num_dual::Dual64;
use hamilton_jacobi::perturbation::forces::J2;
use hamilton_jacobi::perturbation::kepler_variation::{
    j2_secular_rates, ClassicalSolution, EquinoctialSolution, MeanElements,
};
use hamilton_jacobi::special::kepler_equation::{solve_barker, solve_kepler_hyperbolic};
use hamilton_jacobi::systems::kepler::elements::Classical;
use hamilton_jacobi::systems::kepler::orbit::{self, MAX_PHASE_ADVANCE};
use hamilton_jacobi::systems::kepler::{drift, propagate};
use hamilton_jacobi::systems::{ExactFlow, Kepler2, Kepler3};
use hamilton_jacobi::{Error, Hamiltonian};

const EPS: f64 = f64::EPSILON;

/// `e sinh H − H = M` at `M` near `f64::MAX`, where `sinh H` overflows although `H ≈ 710` does
/// not: the root agrees with 50-digit references (mpmath, Newton on the exact equation) to a few
/// ulps of `H` (the map `M ↦ H ≈ ln(2M/e)` has condition number `1/H`, so the reference is
/// matched to the rounding of one logarithm).
#[test]
#[allow(clippy::excessive_precision)] // 20-digit references, as computed
fn hyperbolic_kepler_equation_at_huge_mean_anomaly() {
    for (m, e, want) in [
        (f64::MAX, 1.0 + 1e-15, 710.475_860_073_943_940_93),
        (f64::MAX, 2.0, 709.782_712_893_383_996_73),
        (1e20, 1.5, 46.339_383_932_332_694_608),
        (3.6e17, 3.0, 40.019_415_318_252_676_675),
    ] {
        let h = solve_kepler_hyperbolic(m, e).unwrap();
        assert!(
            (h - want).abs() <= 4.0 * EPS * want,
            "M = {m:e}, e = {e}: {h} vs {want}"
        );
        let hm = solve_kepler_hyperbolic(-m, e).unwrap();
        assert_eq!(hm, -h);
    }
}

/// Barker's equation `B + B³/3 = M` up to `|M| = f64::MAX`: `B` is finite and satisfies the
/// equation, evaluated as `B + (B/3)·B·B` (no overflow), to 4 ulps of `M`; the dual part is
/// `dB/dM = 1/(1 + B²)` (implicit differentiation) to a few ulps.
#[test]
fn barker_equation_at_huge_mean_anomaly() {
    for m in [1e308, f64::MAX, -f64::MAX, 1e300, 1.0 + 1e-9, 0.7] {
        let b: f64 = solve_barker(m).unwrap();
        assert!(b.is_finite(), "M = {m:e}: {b}");
        // B³/3 = M − B, compared in that form and scaled by the exact 1/4 (B + B³/3 and B³/3
        // overflow at M = f64::MAX).
        let cube = (b / 12.0) * b * b;
        assert!(
            (cube - 0.25 * (m - b)).abs() <= EPS * m.abs(),
            "M = {m:e}: B = {b:e}, B³/3 = {cube:e}"
        );
        let bd = solve_barker(Dual64::from(m).derivative()).unwrap();
        let want = 1.0 / (1.0 + b * b);
        assert!(
            (bd.eps - want).abs() <= 8.0 * EPS * want,
            "M = {m:e}: dB/dM = {:e} vs {want:e}",
            bd.eps
        );
        assert!((bd.re - b).abs() <= 2.0 * EPS * b.abs());
    }
}

/// `n = √(μ/a³)`: a value outside the normal range is refused; an in-range value whose naive
/// intermediates overflow (`μ/a = 1e310`) or underflow (`a³ = 1e−900`) is returned, agreeing with
/// the decimal closed form to 4 ulps.
#[test]
fn mean_motion_at_extreme_arguments() {
    for (mu, a) in [
        (1e300, 1e-300),
        (1e-300, 1e300),
        (1.0, 5e-324),
        (f64::MAX, 1e-200),
    ] {
        assert!(
            matches!(orbit::mean_motion(mu, a), Err(Error::OutOfDomain { .. })),
            "μ = {mu:e}, a = {a:e}: {:?}",
            orbit::mean_motion(mu, a)
        );
    }
    for (mu, a, want) in [
        (1e300, 1e-10, 1e165),
        (1e-300, 1e-300, 1e300),
        (1e300, 1e200, 1e-150),
        (4.0, 1.0, 2.0),
    ] {
        let n = orbit::mean_motion(mu, a).unwrap();
        assert!(
            (n - want).abs() <= 4.0 * EPS * want,
            "μ = {mu:e}, a = {a:e}: {n:e}"
        );
        let el = Classical::new(-a, 1.5, 0.1, 0.0, 0.0, 0.0).unwrap();
        assert_eq!(el.mean_motion(mu).unwrap(), n);
    }
}

/// The first-order J₂ rates depend on `μ/a³` and `R/a` only, so scaling `(μ, R, a)` by
/// `(2^{3k}, 2^k, 2^k)` leaves them unchanged exactly; at `k = 340` (`a³` overflows) they must
/// equal the textbook formula (Vallado eqs. 9-41) evaluated at `k = 0`, to 8 ulps. Rates whose
/// true value overflows are refused.
#[test]
fn j2_secular_rates_at_extreme_arguments() {
    let (j2, e, i) = (1.08e-3, 0.3, 0.7_f64);
    let textbook = |mu: f64, r: f64, a: f64| {
        let n = (mu / (a * a * a)).sqrt();
        let p = a * (1.0 - e * e);
        let k = n * j2 * (r / p) * (r / p);
        let c: f64 = i.cos();
        [
            -1.5 * k * c,
            0.75 * k * (5.0 * c * c - 1.0),
            0.75 * k * (1.0 - e * e).sqrt() * (3.0 * c * c - 1.0),
            n,
        ]
    };
    let want = textbook(1.0, 0.5, 1.0);
    for k in [340, -340, 0] {
        let s = 2f64.powi(k);
        let got = J2::new(2f64.powi(3 * k), j2, 0.5 * s)
            .and_then(|model| j2_secular_rates(&model, s, e, i))
            .unwrap();
        for (g, w) in [got.raan, got.argp, got.mean_anomaly, got.mean_motion]
            .into_iter()
            .zip(want)
        {
            assert!(
                (g - w).abs() <= 8.0 * EPS * w.abs(),
                "k = {k}: {g:e} vs {w:e}"
            );
        }
    }
    for (mu, j2, r, a, e) in [
        (1.0, 1e-3, 1.0, 1e-300, 0.5),
        (1e300, 1e300, 1e300, 1e-300, 0.5),
        (1.0, 1e300, 1e300, 1.0, 1.0 - 1e-16),
        (1.0, 1e-3, 1.0, 1e-200, 0.9999999),
    ] {
        let r = J2::new(mu, j2, r).and_then(|model| j2_secular_rates(&model, a, e, 0.3));
        assert!(matches!(r, Err(Error::OutOfDomain { .. })), "{r:?}");
    }
    // Rates whose true value (≈ 1e−703) underflows are their rounded value, zero, while n = 1e−300
    // is representable.
    let tiny = J2::new(1.0, 1e-3, 1.0)
        .and_then(|model| j2_secular_rates(&model, 1e200, 0.5, 0.3))
        .unwrap();
    assert_eq!(tiny.raan, 0.0);
    assert!((tiny.mean_motion - 1e-300).abs() <= 4.0 * EPS * 1e-300);
}

/// Closed-form hyperbolic conic (Battin §4.6): position and velocity at hyperbolic anomaly `H`
/// for semi-axis `|a|`, eccentricity `e`, in the plane spanned by the orthonormal `u`, `w`.
fn hyperbola(
    mu: f64,
    abs_a: f64,
    e: f64,
    h: f64,
    u: Vector3<f64>,
    w: Vector3<f64>,
) -> (Vector3<f64>, Vector3<f64>) {
    let b = abs_a * ((e - 1.0) * (e + 1.0)).sqrt();
    let den = e * h.cosh() - 1.0;
    let vs = (mu / abs_a).sqrt();
    let r = u * (abs_a * (e - h.cosh())) + w * (b * h.sinh());
    let v = u * (-vs * h.sinh() / den) + w * (vs * ((e - 1.0) * (e + 1.0)).sqrt() * h.cosh() / den);
    (r, v)
}

/// Amplification of the rounding of `x₁ = f x₀ + g y₀` for the `(f, g)` that map `(x₀, y₀)` to
/// `x₁` (solved by least squares in the plane): `(|f||x₀| + |g||y₀|)/|x₁|`.
fn fg_amplification(x0: &Vector3<f64>, y0: &Vector3<f64>, x1: &Vector3<f64>) -> f64 {
    let (a11, a12, a22) = (x0.dot(x0), x0.dot(y0), y0.dot(y0));
    let (b1, b2) = (x0.dot(x1), y0.dot(x1));
    let det = a11 * a22 - a12 * a12;
    let f = (b1 * a22 - b2 * a12) / det;
    let g = (a11 * b2 - a12 * b1) / det;
    (f.abs() * x0.norm() + g.abs() * y0.norm()) / x1.norm()
}

/// Strongly hyperbolic arcs (`e = 99` over `dt = 1e3`; speed 100 at `r = 1` over `dt ≥ 10`;
/// `e ≈ 1e6` over `dt ≥ 1`; an incoming arc through periapsis) of the universal-variable drift
/// against the closed-form conic at `H₁` solving `e sinh H₁ − H₁ = M₀ + n dt`.
///
/// Tolerance: the map `M ↦ (r, v)` has relative condition number ≤ 1 here (`r ∝ e^H ∝ M` for
/// `H ≫ 1`), and the drift forms `r₁ = f r₀ + g v₀` from a few dozen rounded operations, each
/// amplified by `κ = (|f||r₀| + |g||v₀|)/|r₁|` (1 from periapsis, large for an arc through
/// periapsis); so `64 ε κ` relative. Energy and angular momentum are conserved to the same level.
#[test]
fn hyperbolic_drift_matches_the_conic() {
    let mu = 1.0;
    let u = Vector3::new(0.6, 0.8, 0.0);
    let w = Vector3::new(-0.48, 0.36, 0.8);
    // (|a|, e, H₀, dt) — periapsis r_p = |a|(e − 1) = 1 unless stated.
    let cases = [
        (1.0 / 98.0, 99.0, 0.0, 1e3),
        (1.0 / 9998.0, 9999.0, 0.0, 10.0), // speed 100 at r = 1
        (1.0 / 9998.0, 9999.0, 0.0, 100.0),
        (1.0 / 9998.0, 9999.0, 0.0, 1e4),
        (1.0 / 9998.0, 9999.0, 1.5, 10.0), // speed ≈ 100, oblique
        (1.0 / 999_999.0, 1e6, 0.0, 1.0),
        (1.0 / 999_999.0, 1e6, 0.0, 1e3),
        (2.0, 1.5, -3.0, 30.0), // incoming, through periapsis
        (2.0, 1.5, 3.0, -30.0), // backwards in time
    ];
    for (abs_a, e, h0, dt) in cases {
        let (q0, p0) = hyperbola(mu, abs_a, e, h0, u, w);
        let n = (mu / abs_a).sqrt() / abs_a;
        let m1 = (e * h0.sinh() - h0) + n * dt;
        let h1 = solve_kepler_hyperbolic(m1, e).unwrap();
        let (q_ref, p_ref) = hyperbola(mu, abs_a, e, h1, u, w);
        let (dq, dp) = drift(mu, &q0, &p0, dt)
            .unwrap_or_else(|err| panic!("e = {e}, H₀ = {h0}, dt = {dt}: {err}"));
        let (q1, p1) = (q0 + dq, p0 + dp);
        let kq = fg_amplification(&q0, &p0, &q_ref).max(1.0);
        let kp = fg_amplification(&q0, &p0, &p_ref).max(1.0);
        let eq = (q1 - q_ref).norm() / q_ref.norm();
        let ep = (p1 - p_ref).norm() / p_ref.norm();
        assert!(
            eq <= 64.0 * EPS * kq && ep <= 64.0 * EPS * kp,
            "e = {e}, H₀ = {h0}, dt = {dt}: position {eq:e} (κ {kq:.1}), velocity {ep:e} (κ {kp:.1})"
        );
        let energy = |q: &Vector3<f64>, p: &Vector3<f64>| 0.5 * p.norm_squared() - mu / q.norm();
        let (e0, e1) = (energy(&q0, &p0), energy(&q1, &p1));
        assert!(
            (e1 - e0).abs() <= 64.0 * EPS * kp.max(kq) * 0.5 * p1.norm_squared(),
            "energy {e0:e} → {e1:e}"
        );
        let (l0, l1) = (q0.cross(&p0), q1.cross(&p1));
        assert!(
            (l1 - l0).norm() <= 128.0 * EPS * kp.max(kq) * q1.norm() * p1.norm(),
            "angular momentum {l0:?} → {l1:?}"
        );
        // The state propagation is the same drift.
        let (q2, p2) = propagate(mu, &q0, &p0, dt).unwrap();
        assert_eq!((q2, p2), (q1, p1));
    }
}

/// Wisdom–Holman with a zero perturbation is a composition of drifts; on the `e = 99` arc over
/// `dt = 1e3` in 10 steps it reproduces the conic to 10 drifts' rounding (`10·64 ε κ`, `κ = 1`
/// from periapsis).
#[test]
fn wisdom_holman_on_a_strong_hyperbola() {
    let mu = 1.0;
    let (abs_a, e, dt) = (1.0 / 98.0, 99.0, 1e3);
    let (u, w) = (Vector3::x(), Vector3::y());
    let (q0, p0) = hyperbola(mu, abs_a, e, 0.0, u, w);
    let h1 = solve_kepler_hyperbolic((mu / abs_a).sqrt() / abs_a * dt, e).unwrap();
    let (q_ref, p_ref) = hyperbola(mu, abs_a, e, h1, u, w);
    let sys = Kepler3::new(mu).unwrap();
    let pr = Problem::new(&sys, 0.0, q0, p0, dt).unwrap();
    let run = integrate(&pr, &Fixed::new(WisdomHolman::WH, 10).unwrap(), &mut ()).unwrap();
    let eq = (run.last.q - q_ref).norm() / q_ref.norm();
    let ep = (run.last.p - p_ref).norm() / p_ref.norm();
    assert!(eq <= 640.0 * EPS && ep <= 640.0 * EPS, "{eq:e} {ep:e}");
}

/// Past `MAX_PHASE_ADVANCE` every bound-orbit propagator refuses with `PhaseLost`; below it, on
/// the unit circle (`μ = 1`, `n = 1` exactly), each agrees with `(cos t, sin t)` to the phase
/// rounding `8·|n t|·ε`.
#[test]
fn long_phase_advances_are_refused_consistently() {
    let mu = 1.0;
    let q = Vector3::new(1.0, 0.0, 0.0);
    let p = Vector3::new(0.0, 1.0, 0.0);
    let el = Classical::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0).unwrap();
    let mean = MeanElements::new(mu, 0.0, el, [0.0; 6]).unwrap();
    let kepler = Kepler3::new(mu).unwrap();
    let lost = |r: Result<(), Error>| matches!(r, Err(Error::PhaseLost { .. }));
    for t in [1e17, 1e20, -1e300, 1.01 * MAX_PHASE_ADVANCE] {
        assert!(lost(drift(mu, &q, &p, t).map(|_| ())), "{t:e}");
        assert!(lost(propagate(mu, &q, &p, t).map(|_| ())), "{t:e}");
        assert!(lost(el.propagate(mu, t).map(|_| ())), "{t:e}");
        assert!(lost(mean.at(t).map(|_| ())), "{t:e}");
        assert!(lost(kepler.exact_flow(0.0, &q, &p, t).map(|_| ())), "{t:e}");
        let cs = ClassicalSolution::new(mu, 0.0).unwrap();
        let g = cs.constants(&el, 0.0).unwrap();
        assert!(lost(cs.elements(t, &g).map(|_| ())), "{t:e}");
        let es = EquinoctialSolution::new(mu, 0.0).unwrap();
        let g = es.constants(&el.to_equinoctial().unwrap(), 0.0).unwrap();
        assert!(lost(es.elements(t, &g).map(|_| ())), "{t:e}");
    }
    // A hyperbola has no phase: a long arc is still propagated.
    let ph = Vector3::new(0.0, 2.0, 0.0);
    assert!(drift(mu, &q, &ph, 1e20).is_ok());
    for t in [1e3, 1e9, 0.99 * MAX_PHASE_ADVANCE] {
        let want = Vector3::new(t.cos(), t.sin(), 0.0);
        let tol = 8.0 * t * EPS;
        let a = propagate(mu, &q, &p, t).unwrap().0;
        let (dq, _) = drift(mu, &q, &p, t).unwrap();
        let c = el.propagate(mu, t).unwrap().to_state(mu).unwrap().0;
        let d = mean.state(t).unwrap().0;
        for (name, x) in [
            ("propagate", a),
            ("drift", q + dq),
            ("classical", c),
            ("mean", d),
        ] {
            assert!(
                (x - want).norm() <= tol,
                "{name} t = {t:e}: {:e}",
                (x - want).norm()
            );
        }
    }
}

/// An integration started at the collision singularity `q = 0` is refused by every method with a
/// typed error (before, drift–kick–drift Verlet returned a finite, meaningless state); the
/// Hamiltonian and its vector field refuse the point too.
#[test]
fn integration_from_the_collision_is_refused() {
    let k = Kepler2::new(1.0).unwrap();
    let q0 = Vector2::zeros();
    let p0 = Vector2::new(0.0, 1.0);
    assert!(k.value(0.0, &q0, &p0).is_err());
    assert!(k.vector_field(0.0, &q0, &p0).is_err());
    let pr = Problem::new(&k, 0.0, q0, p0, 1.0).unwrap();
    let nonfinite = |r: Result<(), Error>| matches!(r, Err(Error::NonFinite { .. }));
    let f = |n| Fixed::new(n, 10).unwrap();
    assert!(nonfinite(
        integrate(&pr, &f(Splitting::VERLET_DKD), &mut ()).map(|_| ())
    ));
    assert!(nonfinite(
        integrate(&pr, &f(Splitting::VERLET_KDK), &mut ()).map(|_| ())
    ));
    assert!(nonfinite(
        integrate(&pr, &f(Splitting::YOSHIDA3), &mut ()).map(|_| ())
    ));
    assert!(nonfinite(
        integrate(&pr, &Fixed::new(Rk4, 10).unwrap(), &mut ()).map(|_| ())
    ));
    let gauss = Fixed::new(Gauss::<2>::new().unwrap(), 10).unwrap();
    assert!(nonfinite(integrate(&pr, &gauss, &mut ()).map(|_| ())));
    let dop = Dop853::new(1e-10, 1e-12).unwrap();
    assert!(nonfinite(integrate(&pr, &dop, &mut ()).map(|_| ())));
    assert!(integrate(&pr, &Fixed::new(ExactStep, 10).unwrap(), &mut ()).is_err());
    let sys = Kepler2::new(1.0).unwrap();
    let pr = Problem::new(&sys, 0.0, q0, p0, 1.0).unwrap();
    assert!(integrate(&pr, &f2(WisdomHolman::WH), &mut ()).is_err());
    // At a regular point nearby the same runs succeed.
    let pr = Problem::new(&k, 0.0, SVector::from([1.0, 0.0]), p0, 1.0).unwrap();
    assert!(integrate(&pr, &f(Splitting::VERLET_DKD), &mut ()).is_ok());
}

fn f2(m: WisdomHolman) -> Fixed<WisdomHolman> {
    Fixed::new(m, 10).unwrap()
}

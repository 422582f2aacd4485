//! Generating functions: the oscillator and free fall [Ardema 16.4–16.5], swap and identity maps
//! in all kinds, singular generators, property tests of canonicity, inversion and Jacobi's theorem.

mod common;

use approx::assert_relative_eq;
use common::{Prob16_1, Prob16_2, Prob16_3};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::{ExactFlow, HarmonicOscillator};
use hamilton_jacobi::transform::generating::{RelationPoint, Sheet, DEFAULT_MAX_CONDITION};
use hamilton_jacobi::transform::{CanonicalTransformation, GeneratingFunction, Kind};
use hamilton_jacobi::{hamiltonian, DualNum, Error, Hamiltonian};
use proptest::prelude::*;
use std::f64::consts::PI;

const EPS: f64 = f64::EPSILON;

// ---------------------------------------------------------------------------------------------
// The oscillator's angle variables from F1 = ½ m ω q² cot Q [Ardema 16.5].

struct AngleVariables {
    m: f64,
    omega: f64,
}
impl GeneratingFunction<1> for AngleVariables {
    fn kind(&self) -> Kind {
        Kind::F1
    }
    fn generator<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        big_q: &SVector<D, 1>,
    ) -> D {
        q[0] * q[0] * (0.5 * self.m * self.omega) / big_q[0].tan()
    }
}

#[test]
fn oscillator_angle_variables_from_f1() {
    let (m, w) = (2.0, 3.0);
    let ct = CanonicalTransformation::new(AngleVariables { m, omega: w });
    let osc = HarmonicOscillator::new(m, w).unwrap();
    let (q0, p0) = (SVector::from([0.5]), SVector::from([1.2]));
    let (big_q, big_p) = ct.forward(0.0, &q0, &p0).unwrap();
    // Published instance (15 digits): (Q, P) = (1.19028994968253, 0.87).
    assert_relative_eq!(big_q[0], 1.19028994968253, epsilon = 1e-14);
    assert_relative_eq!(big_p[0], 0.87, epsilon = 4.0 * EPS);
    // K = H (F1 has no t) = ω P, and Hamilton's equations of K: Q̇ = ω, Ṗ = 0.
    let k = ct.transform(&osc);
    for (qq, pp) in [(big_q[0], big_p[0]), (0.4, 2.0), (2.9, 0.1)] {
        let (bq, bp) = (SVector::from([qq]), SVector::from([pp]));
        assert_relative_eq!(
            k.value(0.0, &bq, &bp).unwrap(),
            w * pp,
            epsilon = 16.0 * EPS * w * pp
        );
        let (qd, pd) = k.vector_field(0.0, &bq, &bp).unwrap();
        assert_relative_eq!(qd[0], w, epsilon = 1e-13);
        assert!(pd[0].abs() < 1e-13, "Ṗ = {}", pd[0]);
    }
    // [Q, P] = 1 (Lagrange bracket of the inverse map) and the forward map is canonical.
    let c = ct.certify(0.0, &q0, &p0).unwrap();
    assert!(c.symplectic_defect < 1e-14);
    let l =
        hamilton_jacobi::brackets::lagrange_bracket_matrix(&ct.inverse_map(), 0.0, &big_q, &big_p)
            .unwrap();
    assert_relative_eq!(l.qp[(0, 0)], 1.0, epsilon = 1e-14);
    // Integrating K (Q = Q₀ + ωt, P constant) reproduces q(t) of the oscillator while Q stays in (0, π).
    for t in [0.1, 0.3, 0.55] {
        let (q, p) = ct
            .inverse(t, &SVector::from([big_q[0] + w * t]), &big_p)
            .unwrap();
        let (qe, pe) = osc.exact_flow(0.0, &q0, &p0, t).unwrap();
        assert_relative_eq!(q[0], qe[0], epsilon = 1e-14);
        assert_relative_eq!(p[0], pe[0], epsilon = 1e-14);
    }
}

// ---------------------------------------------------------------------------------------------
// Free fall with F1(q, Q, t) = (q − Q)²/(2t) − ½ g t (q + Q) − g² t³/24 [Ardema 16.4].

struct FreeFall {
    g: f64,
}
impl GeneratingFunction<1> for FreeFall {
    fn kind(&self) -> Kind {
        Kind::F1
    }
    fn generator<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 1>,
        big_q: &SVector<D, 1>,
    ) -> D {
        let d = q[0] - big_q[0];
        d * d / (t * 2.0)
            - t * (q[0] + big_q[0]) * (0.5 * self.g)
            - t * t * t * (self.g * self.g / 24.0)
    }
}
hamiltonian!(Fall<1> { g: f64 } |s, _t, q, p| p[0] * p[0] * 0.5 + q[0] * s.g);

#[test]
fn free_fall_generator() {
    let g = 9.81;
    let ct = CanonicalTransformation::new(FreeFall { g });
    let h = Fall { g };
    // The map sends the state at time t to the initial state (Q, P): the flow's inverse.
    let (big_q, big_p) = (SVector::from([1.5]), SVector::from([-4.0]));
    for t in [0.3, 2.0] {
        let (q, p) = (
            SVector::from([big_q[0] + big_p[0] * t - 0.5 * g * t * t]),
            SVector::from([big_p[0] - g * t]),
        );
        let (bq, bp) = ct.forward(t, &q, &p).unwrap();
        assert_relative_eq!(bq[0], big_q[0], epsilon = 1e-13);
        assert_relative_eq!(bp[0], big_p[0], epsilon = 1e-13);
        // K = H + ∂F₁/∂t ≡ 0: the initial conditions are constants of the motion.
        let k = ct.transform(&h);
        for (a, b) in [(1.5, -4.0), (0.2, 3.0), (-7.0, 0.5)] {
            let kv = k
                .value(t, &SVector::from([a]), &SVector::from([b]))
                .unwrap();
            let hv = 0.5 * b * b + g * a; // a scale for rounding
            assert!(
                kv.abs() < 64.0 * EPS * (1.0 + hv.abs() + g * g * t * t),
                "K = {kv} at t = {t}"
            );
        }
    }
    // F₁ equals Hamilton's principal function of the projectile [Ardema 17.1] (vertical part,
    // x¹ = x⁰): instance (y⁰, y¹) = (0, 5), τ = 2.
    let f = FreeFall { g }.generator(2.0, &SVector::from([5.0]), &SVector::from([0.0]));
    let s_t1 = 25.0 / 4.0 - 0.5 * g * 5.0 * 2.0 - g * g * 8.0 / 24.0;
    assert_relative_eq!(f, s_t1, epsilon = 4.0 * EPS * s_t1.abs());
}

// ---------------------------------------------------------------------------------------------
// Exchange and identity maps in all kinds that can represent them.

struct Quadratic {
    kind: Kind,
    sign: f64,
}
impl GeneratingFunction<2> for Quadratic {
    fn kind(&self) -> Kind {
        self.kind
    }
    fn generator<D: DualNum<f64> + Copy>(&self, _t: D, x: &SVector<D, 2>, y: &SVector<D, 2>) -> D {
        x.dot(y) * self.sign
    }
}

#[test]
fn swap_and_identity_in_every_kind() {
    let (q, p) = (SVector::from([0.3, -1.2]), SVector::from([2.5, 0.7]));
    // Swap Q = p, P = −q: F1 = q·Q, and F4 = F1 + Q·P − q·p = p·P.
    for kind in [Kind::F1, Kind::F4] {
        let ct = CanonicalTransformation::new(Quadratic { kind, sign: 1.0 });
        let (bq, bp) = ct.forward(0.0, &q, &p).unwrap();
        assert_eq!((bq, bp), (p, -q), "{kind:?}");
        assert_eq!(ct.inverse(0.0, &bq, &bp).unwrap(), (q, p));
        assert_eq!(ct.certify(0.0, &q, &p).unwrap().symplectic_defect, 0.0);
    }
    // Identity: F2 = q·P, and F3 = F2 − Q·P − q·p … = −p·Q.
    for (kind, sign) in [(Kind::F2, 1.0), (Kind::F3, -1.0)] {
        let ct = CanonicalTransformation::new(Quadratic { kind, sign });
        assert_eq!(ct.forward(0.0, &q, &p).unwrap(), (q, p), "{kind:?}");
        assert_eq!(ct.inverse(0.0, &q, &p).unwrap(), (q, p));
    }
    // The swap has no F2 (or F3) generator: with F2 = q·P the relations give the identity instead,
    // and an F2 with a singular mixed Hessian is refused.
    struct Degenerate;
    impl GeneratingFunction<2> for Degenerate {
        fn kind(&self) -> Kind {
            Kind::F2
        }
        fn generator<D: DualNum<f64> + Copy>(
            &self,
            _t: D,
            x: &SVector<D, 2>,
            y: &SVector<D, 2>,
        ) -> D {
            (x[0] + x[1]) * (y[0] + y[1])
        }
    }
    let err = CanonicalTransformation::new(Degenerate)
        .forward(0.0, &q, &p)
        .unwrap_err();
    assert!(matches!(err, Error::Singular { .. }), "{err}");
}

// ---------------------------------------------------------------------------------------------
// Singular generating functions and focal points give typed errors with the point and the
// conditioning.

/// Oscillator principal function as an F1 generator, S(x⁰, x¹) with x⁰ → q, x¹ → Q (ω = 1).
struct Principal {
    tau: f64,
}
impl GeneratingFunction<1> for Principal {
    fn kind(&self) -> Kind {
        Kind::F1
    }
    fn generator<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        big_q: &SVector<D, 1>,
    ) -> D {
        let (s, c) = self.tau.sin_cos();
        ((q[0] * q[0] + big_q[0] * big_q[0]) * c - q[0] * big_q[0] * 2.0) / (2.0 * s)
    }
}

/// The message of a refusal at a singular or ill-conditioned generator (panics on any other result).
fn singular_message(e: &Error) -> String {
    match e {
        Error::Singular { what, at, rcond } => format!("{what} | {at} | {rcond:e}"),
        Error::IllConditioned {
            what,
            at,
            condition,
            threshold,
        } => {
            assert!(condition > threshold, "{e}");
            format!("{what} | {at} | {condition:e} > {threshold:e}")
        }
        other => panic!("expected Error::Singular or Error::IllConditioned, got {other:?}"),
    }
}

#[test]
fn singular_generators_are_refused() {
    let (m, w) = (1.0, 1.0);
    let ct = CanonicalTransformation::new(AngleVariables { m, omega: w });
    assert!(ct
        .inverse(0.0, &SVector::from([1.2]), &SVector::from([0.5]))
        .is_ok());
    // Oscillator W1 near its caustic Q → π (q → 0): refused in both directions, naming the
    // measured condition (≈ π/(π − Q): the generator's derivatives at an argument known to ε π
    // near the pole of cot Q) and the threshold.
    let (bq, bp) = (PI - 1e-9, 0.5);
    let e = ct
        .inverse(0.0, &SVector::from([bq]), &SVector::from([bp]))
        .unwrap_err();
    let msg = singular_message(&e);
    assert!(msg.contains("3.1415926"), "{msg}");
    let amplitude = (2.0 * bp / (m * w)).sqrt();
    let (q, p) = (
        SVector::from([amplitude * bq.sin()]),
        SVector::from([m * w * amplitude * bq.cos()]),
    );
    let reference = hamilton_jacobi::transform::generating::RelationPoint {
        t: 0.0,
        q: SVector::from([amplitude * (0.75 * PI).sin()]),
        p: SVector::from([m * w * amplitude * (0.75 * PI).cos()]),
        big_q: SVector::from([0.75 * PI]),
        big_p: SVector::from([bp]),
    };
    let sheet = Sheet::through(reference).unwrap();
    let e = ct.forward_on(0.0, &q, &p, &sheet).unwrap_err();
    singular_message(&e);
    match e {
        Error::IllConditioned {
            condition,
            threshold,
            ..
        } => {
            assert_eq!(threshold, DEFAULT_MAX_CONDITION);
            assert!(condition >= 1e9, "{condition:e}");
        }
        other => panic!("{other:?}"),
    }
    // At q = 0 the mixed Hessian B = −mωq/sin²Q vanishes: refused (Singular).
    assert!(ct
        .forward(0.0, &SVector::from([0.0]), &SVector::from([1.0]))
        .is_err());
    // Free fall: regular at t = 0.3, refused as t → 0 (the identity has no type-1 generator);
    // t = 0 exactly is a non-finite generator.
    let ff = CanonicalTransformation::new(FreeFall { g: 9.81 });
    let (q, p) = (SVector::from([1.0]), SVector::from([0.5]));
    assert!(ff.forward(0.3, &q, &p).is_ok());
    for t in [1e-9, 1e-12] {
        let msg = singular_message(&ff.forward(t, &q, &p).unwrap_err());
        assert!(msg.contains(&format!("t = {t:e}")), "{msg}");
    }
    assert!(ff.forward(0.0, &q, &p).is_err());
    // Oscillator principal function at τ → π (focal point): regular at τ = 1, refused at π − 1e−9.
    let q0 = SVector::from([1.0]);
    assert!(CanonicalTransformation::new(Principal { tau: 1.0 })
        .forward(0.0, &q0, &p)
        .is_ok());
    let e = CanonicalTransformation::new(Principal { tau: PI - 1e-9 })
        .forward(0.0, &q0, &p)
        .unwrap_err();
    singular_message(&e);
    // Exactly at the focal point (τ = fl(π), sin τ ≈ 1.2e−16) B = −1/sin τ ≈ −8e15: the output
    // P is formed by cancelling terms of that size and is refused.
    assert!(CanonicalTransformation::new(Principal { tau: PI })
        .forward(0.0, &q0, &p)
        .is_err());
}

// ---------------------------------------------------------------------------------------------
// Sheets of F1 = ½ m ω q² cot Q and conditioning at its caustic, against the closed form
// q = √(2P/(mω)) sin Q, p = √(2mωP) cos Q [Goldstein §9.3].

/// The closed form (the oracle).
fn torus(m: f64, w: f64, big_q: f64, big_p: f64) -> (f64, f64) {
    let a = (2.0 * big_p / (m * w)).sqrt();
    (a * big_q.sin(), m * w * a * big_q.cos())
}

/// The relation point of the closed form at (Q, P).
fn on_torus(m: f64, w: f64, big_q: f64, big_p: f64) -> RelationPoint<1> {
    let (q, p) = torus(m, w, big_q, big_p);
    RelationPoint {
        t: 0.0,
        q: SVector::from([q]),
        p: SVector::from([p]),
        big_q: SVector::from([big_q]),
        big_p: SVector::from([big_p]),
    }
}

/// The sheet of the closed form for the inverse map: q has the sign of sin Q.
fn sign_sheet() -> Sheet<1> {
    Sheet::satisfying("q sin Q > 0", |z: &RelationPoint<1>| {
        z.q[0] * z.big_q[0].sin() > 0.0
    })
}

#[test]
fn angle_variables_on_every_quadrant_and_window_match_the_closed_form() {
    // Q on a grid of (−2π, 2π) that visits every (sign q, sign p) quadrant in both 2π-windows
    // (odd multiples of π/16, never on an axis); two actions. Errors are measured against the
    // size of each block on the torus (amplitude a of q, mωa of p; |Q| ≤ 2π, P): the closed form
    // and the solve each carry a few roundings of sin, cos, tan and √ of arguments up to 2π, so
    // 1e−14 (45 ε) bounds both with margin.
    let (m, w) = (2.0, 3.0);
    let ct = CanonicalTransformation::new(AngleVariables { m, omega: w });
    let mut quadrants = std::collections::BTreeSet::new();
    let mut worst = 0.0f64;
    for big_p in [0.87, 3.2] {
        let a = (2.0 * big_p / (m * w)).sqrt();
        for j in 0..64 {
            let big_q = -2.0 * PI + (2 * j + 1) as f64 * PI / 16.0;
            let (qe, pe) = torus(m, w, big_q, big_p);
            quadrants.insert((qe > 0.0, pe > 0.0, big_q > 0.0));
            // Inverse on the sheet q sin Q > 0.
            let inv = ct
                .inverse_on(
                    0.0,
                    &SVector::from([big_q]),
                    &SVector::from([big_p]),
                    &sign_sheet(),
                )
                .unwrap();
            let (eq, ep) = (
                (inv.q[0] - qe).abs() / a,
                (inv.p[0] - pe).abs() / (m * w * a),
            );
            assert!(
                eq <= 1e-14 && ep <= 1e-14,
                "inverse at Q = {big_q}: {eq:e} {ep:e}"
            );
            assert!(inv.condition < 1e2, "Q = {big_q}: κ = {:e}", inv.condition);
            // Forward on the sheet through a reference point in the same quadrant and window
            // (the middle of the quarter turn containing Q), by continuation.
            let quarter = (big_q / (PI / 2.0)).floor();
            let reference = on_torus(m, w, (quarter + 0.5) * PI / 2.0, 1.0);
            let sheet = Sheet::through(reference).unwrap();
            let fwd = ct
                .forward_on(0.0, &SVector::from([qe]), &SVector::from([pe]), &sheet)
                .unwrap();
            let (eqq, epp) = (
                (fwd.q[0] - big_q).abs() / (2.0 * PI),
                (fwd.p[0] - big_p).abs() / big_p,
            );
            assert!(
                eqq <= 1e-14 && epp <= 1e-14,
                "forward at Q = {big_q}: {eqq:e} {epp:e}"
            );
            // Round trip: forward then inverse returns the point.
            let back = ct.inverse_on(0.0, &fwd.q, &fwd.p, &sign_sheet()).unwrap();
            let (rq, rp) = (
                (back.q[0] - qe).abs() / a,
                (back.p[0] - pe).abs() / (m * w * a),
            );
            assert!(
                rq <= 1e-14 && rp <= 1e-14,
                "round trip at Q = {big_q}: {rq:e} {rp:e}"
            );
            worst = worst.max(eq).max(ep).max(eqq).max(epp).max(rq).max(rp);
            // Within −π < Q ≤ π the predicate sheet (sign and window) selects the same root.
            // (Only for |Q| < π/2: elsewhere the root in the window may be out of reach of the
            // default starts, and is then refused with the candidates found.)
            if big_q.abs() < PI / 2.0 {
                let window =
                    Sheet::satisfying("q sin Q > 0, −π < Q ≤ π", |z: &RelationPoint<1>| {
                        z.q[0] * z.big_q[0].sin() > 0.0 && z.big_q[0] > -PI && z.big_q[0] <= PI
                    });
                let f2 = ct
                    .forward_on(0.0, &SVector::from([qe]), &SVector::from([pe]), &window)
                    .unwrap();
                assert!(
                    (f2.q[0] - fwd.q[0]).abs() <= 1e-14 * 2.0 * PI,
                    "Q = {big_q}"
                );
            }
        }
    }
    assert_eq!(quadrants.len(), 8, "{quadrants:?}");
    println!("worst relative error over the quadrants: {worst:e}");
}

#[test]
fn a_sheet_without_a_root_is_refused_naming_the_candidates() {
    let (m, w) = (2.0, 3.0);
    let ct = CanonicalTransformation::new(AngleVariables { m, omega: w });
    let (big_q, big_p) = (SVector::from([1.0]), SVector::from([0.87]));
    let (qe, pe) = torus(m, w, 1.0, 0.87);
    // Both (q, p) and (−q, −p) satisfy the relation at (Q, P): each sign is a sheet.
    let plus = ct.inverse_on(0.0, &big_q, &big_p, &sign_sheet()).unwrap();
    let reflected = Sheet::satisfying("q sin Q < 0", |z: &RelationPoint<1>| {
        z.q[0] * z.big_q[0].sin() < 0.0
    });
    let minus = ct.inverse_on(0.0, &big_q, &big_p, &reflected).unwrap();
    assert!((plus.q[0] - qe).abs() <= 4.0 * EPS * qe.abs());
    assert!((minus.q[0] + qe).abs() <= 4.0 * EPS * qe.abs());
    assert!((minus.p[0] + pe).abs() <= 4.0 * EPS * pe.abs());
    // A sheet on which neither lies is refused, and the error names both roots.
    let none = Sheet::satisfying("q > 10", |z: &RelationPoint<1>| z.q[0] > 10.0);
    match ct.inverse_on(0.0, &big_q, &big_p, &none).unwrap_err() {
        e @ Error::NoRootOnSheet { .. } => {
            let msg = e.to_string();
            let Error::NoRootOnSheet {
                candidates,
                sheet,
                problem,
                ..
            } = e
            else {
                unreachable!()
            };
            assert_eq!((sheet.as_str(), problem.as_str()), ("q > 10", "no root"));
            assert_eq!(candidates.len(), 2, "{msg}");
            for sign in [1.0, -1.0] {
                assert!(
                    candidates
                        .iter()
                        .any(|c| (c[0] - sign * qe).abs() <= 4.0 * EPS * qe
                            && (c[1] - sign * pe).abs() <= 4.0 * EPS * pe),
                    "{msg}"
                );
            }
            assert!(msg.contains("q > 10") && msg.contains("e-1"), "{msg}");
        }
        other => panic!("expected NoRootOnSheet, got {other:?}"),
    }
    // A predicate accepting both is not a sheet.
    let both = Sheet::satisfying("any q", |_: &RelationPoint<1>| true);
    assert!(matches!(
        ct.inverse_on(0.0, &big_q, &big_p, &both),
        Err(Error::NoRootOnSheet { ref problem, .. }) if problem == "more than one root"
    ));
    // A reference point off the relation is refused.
    let mut off = on_torus(m, w, 1.0, 0.87);
    off.big_p[0] *= 1.01;
    let sheet = Sheet::through(off).unwrap();
    assert!(matches!(
        ct.forward_on(0.0, &SVector::from([qe]), &SVector::from([pe]), &sheet),
        Err(Error::InvalidInput { .. })
    ));
    assert!(matches!(
        Sheet::through(RelationPoint {
            t: f64::NAN,
            ..on_torus(m, w, 1.0, 0.87)
        }),
        Err(Error::NonFinite { .. })
    ));
}

#[test]
fn approaching_the_caustic_the_map_stays_within_its_bound_or_is_refused() {
    // The point of the torus P = 0.87 at Q = π − δ (q → 0⁺, p < 0), mapped forward on the sheet
    // through Q = 3π/4. Oracle from the given (q, p) themselves, free of the caustic:
    // Q = atan2(mωq, p), P = (p² + (mωq)²)/(2mω), each within 4 ε. The map's error must stay
    // within its estimate κ ε (a factor 8 for the few roundings in each evaluated derivative
    // and in the oracle), whether or not the threshold refuses it; with the default threshold every
    // point with κ > 10⁶ is refused with IllConditioned, and κ is at least the amplification π/δ
    // (it is 1.33 π/δ down to δ = 1e−8; below, where the solve itself fails, far larger).
    let (m, w, big_p) = (2.0, 3.0, 0.87);
    let sheet = Sheet::through(on_torus(m, w, 0.75 * PI, big_p)).unwrap();
    let ct = CanonicalTransformation::new(AngleVariables { m, omega: w });
    let unlimited = CanonicalTransformation::new(AngleVariables { m, omega: w })
        .with_max_condition(f64::MAX)
        .unwrap();
    let (mut accepted, mut refused) = (0, 0);
    for k in 1..=15 {
        let delta = 10f64.powi(-k);
        let (q, p) = torus(m, w, PI - delta, big_p);
        let (qs, ps) = (SVector::from([q]), SVector::from([p]));
        let q_star = (m * w * q).atan2(p);
        let p_star = (p * p + (m * w * q) * (m * w * q)) / (2.0 * m * w);
        let image = unlimited.forward_on(0.0, &qs, &ps, &sheet).unwrap();
        let (eq, ep) = (
            (image.q[0] - q_star).abs() / q_star.abs(),
            (image.p[0] - p_star).abs() / p_star,
        );
        let bound = 8.0 * image.condition * EPS;
        println!(
            "δ = {delta:e}: κ = {:.2e} (κδ/π = {:.2}), errors Q {eq:.1e}, P {ep:.1e}, bound {bound:.1e}",
            image.condition,
            image.condition * delta / PI
        );
        assert!(eq <= bound && ep <= bound, "δ = {delta:e}");
        // κ never understates the amplification π/δ of the rounding of Q.
        assert!(
            image.condition * delta / PI >= 0.5,
            "δ = {delta:e}: κ = {:e}",
            image.condition
        );
        match ct.forward_on(0.0, &qs, &ps, &sheet) {
            Ok(r) => {
                accepted += 1;
                assert_eq!(r, image);
                assert!(r.condition <= DEFAULT_MAX_CONDITION);
            }
            Err(Error::IllConditioned {
                condition,
                threshold,
                ..
            }) => {
                refused += 1;
                assert_eq!(condition, image.condition);
                assert_eq!(threshold, DEFAULT_MAX_CONDITION);
                assert!(condition > threshold);
            }
            Err(other) => panic!("δ = {delta:e}: {other}"),
        }
    }
    println!("accepted {accepted}, refused {refused}");
    assert!(accepted >= 5 && refused >= 8, "{accepted} {refused}");
}

// ---------------------------------------------------------------------------------------------
// Property tests: random quadratic and non-quadratic generators of each kind.

#[derive(Clone, Debug)]
struct Random {
    kind: Kind,
    a: [f64; 3],
    b: [f64; 4],
    c: [f64; 3],
    nonlinear: f64,
    rate: f64,
}
impl GeneratingFunction<2> for Random {
    fn kind(&self) -> Kind {
        self.kind
    }
    /// F = xᵀBy + ½xᵀAx + ½yᵀCy + κ (sin(x₀y₁) + ½cos(x₁ + y₀) + ⅓x₀²y₀) + r t x·y, with B = I + small.
    fn generator<D: DualNum<f64> + Copy>(&self, t: D, x: &SVector<D, 2>, y: &SVector<D, 2>) -> D {
        let (a, b, c) = (&self.a, &self.b, &self.c);
        let bilinear = x[0] * y[0] * (1.0 + b[0])
            + x[0] * y[1] * b[1]
            + x[1] * y[0] * b[2]
            + x[1] * y[1] * (1.0 + b[3]);
        let qa = (x[0] * x[0] * a[0] + x[0] * x[1] * (2.0 * a[1]) + x[1] * x[1] * a[2]) * 0.5;
        let qc = (y[0] * y[0] * c[0] + y[0] * y[1] * (2.0 * c[1]) + y[1] * y[1] * c[2]) * 0.5;
        let nl = (x[0] * y[1]).sin() + (x[1] + y[0]).cos() * 0.5 + x[0] * x[0] * y[0] / 3.0;
        bilinear + qa + qc + nl * self.nonlinear + t * x.dot(y) * self.rate
    }
}

/// Random coefficients; every property below is checked, for the same coefficients, with each of
/// the four kinds and both without (quadratic generator, linear map) and with the non-quadratic
/// terms — so each (kind, quadratic/non-quadratic) combination gets all 1000 cases.
fn random_generators() -> impl Strategy<Value = Vec<Random>> {
    (
        prop::array::uniform3(-0.5..0.5f64),
        prop::array::uniform4(-0.2..0.2f64),
        prop::array::uniform3(-0.5..0.5f64),
        -0.1..0.1f64,
        -0.2..0.2f64,
    )
        .prop_map(|(a, b, c, nonlinear, rate)| {
            let mut out = Vec::with_capacity(8);
            for kind in [Kind::F1, Kind::F2, Kind::F3, Kind::F4] {
                for nonlinear in [0.0, nonlinear] {
                    out.push(Random {
                        kind,
                        a,
                        b,
                        c,
                        nonlinear,
                        rate,
                    });
                }
            }
            out
        })
}

fn point() -> impl Strategy<Value = (SVector<f64, 2>, SVector<f64, 2>)> {
    (
        prop::array::uniform2(-1.0..1.0f64),
        prop::array::uniform2(-1.0..1.0f64),
    )
        .prop_map(|(q, p)| (SVector::from(q), SVector::from(p)))
}

hamiltonian!(Anharmonic<2> |_s, _t, q, p| p.dot(p) * 0.5 + q.dot(q) * 0.5 + q[0] * q[0] * q[1] * 0.3);

proptest! {
    #![proptest_config(common::config(0x5eed_0005))]

    #[test]
    fn generated_maps_are_canonical_and_invertible(gs in random_generators(), (q, p) in point(), t in 0.0..1.0f64) {
        for g in gs {
            let label = format!("{:?} κ = {}", g.kind, g.nonlinear);
            let ct = CanonicalTransformation::new(g);
            let c = ct.certify(t, &q, &p).unwrap();
            // Entries of M are O(1) here (B = I + O(0.2)); the defect is a few roundings of O(1) sums.
            prop_assert!(c.symplectic_defect <= 1e-12, "{label}: defect {}", c.symplectic_defect);
            prop_assert!(c.det_minus_one.abs() <= 1e-12, "{label}");
            let (bq, bp) = ct.forward(t, &q, &p).unwrap();
            let (q2, p2) = ct.inverse(t, &bq, &bp).unwrap();
            prop_assert!((q2 - q).amax() <= 1e-12 && (p2 - p).amax() <= 1e-12, "{label}: round trip {} {}", q2 - q, p2 - p);
        }
    }

    #[test]
    fn transformed_hamiltonian_generates_the_transformed_flow(gs in random_generators(), (q, p) in point()) {
        // Integrate H from (q, p) and K from (Q, P) with the same RK4 (dt = 0.01, 20 steps); map the
        // H-trajectory forward at t = 0.2 and compare. Both integrations carry an O(dt⁴) global error
        // of ≈ 1e−9 for these O(1) motions; the comparison tolerance is 1e−7.
        for g in gs {
            let label = format!("{:?} κ = {}", g.kind, g.nonlinear);
            let ct = CanonicalTransformation::new(g);
            let k = ct.transform(&Anharmonic);
            let (bq0, bp0) = ct.forward(0.0, &q, &p).unwrap();
            let (dt, steps) = (0.01, 20);
            let (q1, p1) = common::rk4_hamiltonian(&Anharmonic, 0.0, q, p, dt, steps, |_, _, _| {});
            let (bq1, bp1) = common::rk4_hamiltonian(&k, 0.0, bq0, bp0, dt, steps, |_, _, _| {});
            let (mq, mp) = ct.forward(dt * steps as f64, &q1, &p1).unwrap();
            prop_assert!((mq - bq1).amax() <= 1e-7 && (mp - bp1).amax() <= 1e-7, "{label}: {} {} vs {} {}", mq, mp, bq1, bp1);
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The canonicity exercises [Ardema Probs. 16/1–16/3] by the three methods: definition
// (closed 1-form), Liouville, brackets.

use hamilton_jacobi::brackets::{
    certify, exactness_defect, liouville_determinant, poisson_bracket_matrix, PhaseMap,
};
use hamilton_jacobi::transform::point::{
    point_transformation, Parabolic, Polar, RotatingFrame, Spherical,
};
use hamilton_jacobi::transform::{Compose, Inverse};

/// The three verdicts (definition, Liouville, brackets) at a point, with tolerance `tol`.
fn verdicts<M: PhaseMap<1>>(m: &M, t: f64, q: f64, p: f64, tol: f64) -> [bool; 3] {
    let (q, p) = (SVector::from([q]), SVector::from([p]));
    [
        exactness_defect(m, t, &q, &p).unwrap() <= tol,
        (liouville_determinant(m, t, &q, &p).unwrap() - 1.0).abs() <= tol,
        (poisson_bracket_matrix(m, t, &q, &p).unwrap().qp[(0, 0)] - 1.0).abs() <= tol,
    ]
}

#[test]
fn canonicity_verdicts_by_all_three_methods() {
    // Tolerance: a few hundred roundings of O(1–10) second-derivative sums.
    let tol = 1e-12;
    for (q, p) in [(0.7, 1.1), (1.9, 0.4), (0.2, 2.5)] {
        assert_eq!(
            verdicts(&Prob16_2, 0.0, q, p, tol),
            [true; 3],
            "16/2 at ({q}, {p})"
        );
        for t in [0.0, 0.7, -1.3] {
            assert_eq!(
                verdicts(&Prob16_1, t, q, p, tol),
                [true; 3],
                "16/1 at t = {t}"
            );
        }
        for (alpha, beta) in [(0.5, 2.0), (0.5, 1.5), (0.7, 2.0), (1.0, 1.0)] {
            let canonical = alpha == 0.5 && beta == 2.0;
            let v = verdicts(&Prob16_3 { alpha, beta }, 0.0, q, p, tol);
            assert_eq!(
                v, [canonical; 3],
                "16/3 α = {alpha}, β = {beta} at ({q}, {p})"
            );
        }
    }
    // The definition's defect equals |(Q, P) − 1| for one degree of freedom: both computed
    // independently, compare them.
    let (q, p) = (SVector::from([0.7]), SVector::from([1.1]));
    let m = Prob16_3 {
        alpha: 0.7,
        beta: 2.0,
    };
    let d = exactness_defect(&m, 0.0, &q, &p).unwrap();
    let b = poisson_bracket_matrix(&m, 0.0, &q, &p).unwrap().qp[(0, 0)];
    assert_relative_eq!(d, (b - 1.0).abs(), epsilon = 1e-13);
}

// ---------------------------------------------------------------------------------------------
// The polar point transformation [Ardema 16.3] and other point transformations.

#[test]
fn polar_momenta_and_other_point_transformations() {
    let ct = point_transformation(Polar);
    for (x, y, px, py) in [
        (1.0, 0.5, 0.3, -0.7),
        (-2.0, 0.1, 1.5, 0.2),
        (0.3, -1.4, -0.6, 0.9),
    ] {
        let (q, p) = (SVector::from([x, y]), SVector::from([px, py]));
        let (bq, bp) = ct.forward(0.0, &q, &p).unwrap();
        let (r, th) = (bq[0], bq[1]);
        assert_relative_eq!(r, f64::hypot(x, y), epsilon = 4.0 * EPS * r);
        assert_relative_eq!(th, y.atan2(x), epsilon = 8.0 * EPS);
        // P_r = p_x cos θ + p_y sin θ, P_θ = −p_x r sin θ + p_y r cos θ.
        assert_relative_eq!(bp[0], px * th.cos() + py * th.sin(), epsilon = 8.0 * EPS);
        assert_relative_eq!(
            bp[1],
            -px * r * th.sin() + py * r * th.cos(),
            epsilon = 16.0 * EPS * (1.0 + r)
        );
        assert!(ct.certify(0.0, &q, &p).unwrap().symplectic_defect < 1e-14);
        let (q2, p2) = ct.inverse(0.0, &bq, &bp).unwrap();
        assert!((q2 - q).amax() < 1e-15 && (p2 - p).amax() < 1e-14);
        // Kepler in polar coordinates: K = P_r²/2 + P_θ²/(2r²) − 1/r.
        let kep = hamilton_jacobi::systems::Kepler2::new(1.0).unwrap();
        let k = ct.transform(&kep).value(0.0, &bq, &bp).unwrap();
        assert_relative_eq!(
            k,
            bp[0] * bp[0] / 2.0 + bp[1] * bp[1] / (2.0 * r * r) - 1.0 / r,
            epsilon = 1e-14
        );
    }
    // Singular at r = 0.
    let z = SVector::from([0.0, 0.0]);
    assert!(matches!(
        ct.forward(0.0, &z, &SVector::from([1.0, 0.0])),
        Err(Error::Singular { .. })
    ));
    // Spherical and parabolic coordinates: canonical, invertible.
    let sph = point_transformation(Spherical);
    let (q3, p3) = (
        SVector::from([0.3, -0.8, 0.5]),
        SVector::from([1.0, 0.2, -0.4]),
    );
    assert!(sph.certify(0.0, &q3, &p3).unwrap().symplectic_defect < 1e-14);
    let (bq, bp) = sph.forward(0.0, &q3, &p3).unwrap();
    let (q4, p4) = sph.inverse(0.0, &bq, &bp).unwrap();
    assert!((q4 - q3).amax() < 1e-15 && (p4 - p3).amax() < 1e-14);
    let par = point_transformation(Parabolic);
    let (q5, p5) = (SVector::from([-0.6, 1.2]), SVector::from([0.3, 0.9]));
    let (bq, bp) = par.forward(0.0, &q5, &p5).unwrap();
    assert!(par.certify(0.0, &q5, &p5).unwrap().symplectic_defect < 1e-14);
    assert_relative_eq!(
        (bq[0] * bq[0] - bq[1] * bq[1]) / 2.0,
        q5[0],
        epsilon = 1e-15
    );
    assert_relative_eq!(bq[0] * bq[1], q5[1], epsilon = 1e-15);
    let (q6, _) = par.inverse(0.0, &bq, &bp).unwrap();
    assert!((q6 - q5).amax() < 1e-15);
}

hamiltonian!(FreeParticle<2> |_s, _t, _q, p| p.dot(p) * 0.5);

#[test]
fn rotating_frame_hamiltonian() {
    // K = H + ∂F₃/∂t = |P|²/2 − ω (Q₁P₂ − Q₂P₁).
    let w = 0.7;
    let ct = point_transformation(RotatingFrame { omega: w });
    let k = ct.transform(&FreeParticle);
    for t in [0.0, 1.3] {
        let (bq, bp) = (SVector::from([0.4, -1.1]), SVector::from([0.9, 0.25]));
        let kv = k.value(t, &bq, &bp).unwrap();
        let expected = bp.dot(&bp) / 2.0 - w * (bq[0] * bp[1] - bq[1] * bp[0]);
        assert_relative_eq!(kv, expected, epsilon = 1e-14);
    }
}

// ---------------------------------------------------------------------------------------------
// Composition and inversion.

#[test]
fn composition_and_inversion_of_canonical_maps() {
    let (q, p) = (SVector::from([0.7]), SVector::from([1.1]));
    // A canonical map composed with its Newton inverse is the identity, and is canonical.
    let inv = Inverse::new(Prob16_2);
    let id = Compose(Prob16_2, Inverse::new(Prob16_2));
    let (q1, p1) = id.apply(0.0, &q, &p);
    assert!((q1 - q).amax() < 1e-14 && (p1 - p).amax() < 1e-14);
    let c = certify(&id, 0.0, &q, &p).unwrap();
    assert!(
        c.jacobian
            .sub(&hamilton_jacobi::PhaseMatrix::identity())
            .max_abs()
            < 1e-13
    );
    // The Newton inverse recovers the original point and is itself canonical.
    let (bq, bp) = Prob16_2.apply(0.0, &q, &p);
    let (q2, p2) = inv.solve(0.0, &bq, &bp).unwrap();
    assert_relative_eq!(q2[0], q[0], epsilon = 1e-14);
    assert_relative_eq!(p2[0], p[0], epsilon = 1e-14);
    assert!(certify(&inv, 0.0, &bq, &bp).unwrap().symplectic_defect < 1e-13);
    // A composition of a canonical and a non-canonical map is not canonical.
    let mixed = Compose(
        Prob16_2,
        Prob16_3 {
            alpha: 0.5,
            beta: 1.0,
        },
    );
    assert!(!certify(&mixed, 0.0, &q, &p).unwrap().is_canonical(1e-6));
    // Inverting at a point where the Jacobian is singular is a typed error.
    let singular = Inverse::new(Prob16_3 {
        alpha: 0.5,
        beta: 2.0,
    });
    assert!(singular
        .solve(0.0, &SVector::from([0.0]), &SVector::from([0.0]))
        .is_err());
}

proptest! {
    #![proptest_config(common::config(0x5eed_0006))]

    #[test]
    fn point_transformations_are_canonical(x in prop::array::uniform3(-2.0..2.0f64), p in prop::array::uniform3(-2.0..2.0f64), t in -3.0..3.0f64, w in -2.0..2.0f64) {
        let (q3, p3) = (SVector::from(x), SVector::from(p));
        // Stay away from the z axis and the origin where spherical coordinates are singular.
        prop_assume!(q3[0].hypot(q3[1]) > 0.05);
        let sph = point_transformation(Spherical);
        prop_assert!(sph.certify(0.0, &q3, &p3).unwrap().symplectic_defect <= 1e-12);
        let (q2, p2) = (SVector::from([x[0], x[1]]), SVector::from([p[0], p[1]]));
        let rot = point_transformation(RotatingFrame { omega: w });
        let c = rot.certify(t, &q2, &p2).unwrap();
        prop_assert!(c.symplectic_defect <= 1e-13);
        let (bq, bp) = rot.forward(t, &q2, &p2).unwrap();
        let (q4, p4) = rot.inverse(t, &bq, &bp).unwrap();
        prop_assert!((q4 - q2).amax() <= 1e-14 && (p4 - p2).amax() <= 1e-14);
    }
}

// ---------------------------------------------------------------------------------------------
// Units: the solvers and the singularity check do not depend on the scale of the variables.

/// F2 = q₀P₀ + s q₁P₁: an exact, regular map for every s ≠ 0 (Q₁ = s q₁, P₁ = p₁/s).
struct Scaled {
    s: f64,
}
impl GeneratingFunction<2> for Scaled {
    fn kind(&self) -> Kind {
        Kind::F2
    }
    fn generator<D: DualNum<f64> + Copy>(&self, _t: D, x: &SVector<D, 2>, y: &SVector<D, 2>) -> D {
        x[0] * y[0] + x[1] * y[1] * self.s
    }
}

/// Q = 1e−20 (q³ + q), P = 1e20 p: canonical up to a rescaling, with tiny residuals.
struct TinyCubic;
impl PhaseMap<1> for TinyCubic {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        (
            SVector::from([(q[0] * q[0] * q[0] + q[0]) * 1e-20]),
            SVector::from([p[0] * 1e20]),
        )
    }
}

#[test]
fn results_do_not_depend_on_units() {
    // Tiny masses: the Newton iteration must not stop early because the residuals are small.
    let (m, w, big_q) = (1e-20, 3.0, 1.2);
    let ct = CanonicalTransformation::new(AngleVariables { m, omega: w });
    let (q, p) = (SVector::from([1.0]), SVector::from([m * w / big_q.tan()]));
    let (bq, bp) = ct.forward(0.0, &q, &p).unwrap();
    assert_relative_eq!(bq[0], big_q, epsilon = 8.0 * EPS);
    assert_relative_eq!(
        bp[0],
        m * w / (2.0 * big_q.sin().powi(2)),
        max_relative = 8.0 * EPS
    );
    let (q2, p2) = ct.inverse(0.0, &bq, &bp).unwrap();
    assert_relative_eq!(q2[0], 1.0, epsilon = 8.0 * EPS);
    assert_relative_eq!(p2[0], p[0], max_relative = 8.0 * EPS);
    let (q3, _) = Inverse::new(TinyCubic)
        .solve(0.0, &SVector::from([1e-20 * 10.0]), &SVector::from([3e20]))
        .unwrap();
    assert_relative_eq!(q3[0], 2.0, epsilon = 8.0 * EPS);
    // Badly scaled but regular generators and coordinates are accepted and exact.
    for s in [1e-8, 1e-10, 1e10] {
        let ct = CanonicalTransformation::new(Scaled { s });
        let (bq, bp) = ct
            .forward(0.0, &SVector::from([1.0, 1.0]), &SVector::from([1.0, 1.0]))
            .unwrap();
        assert_eq!((bq[1], bp[1]), (s, 1.0 / s), "s = {s}");
    }
    let polar = point_transformation(Polar);
    for scale in [1e-9, 1e-15, 1e12] {
        let (q, p) = (
            SVector::from([3.0, 4.0]) * scale,
            SVector::from([0.3, -0.7]),
        );
        let (bq, bp) = polar.forward(0.0, &q, &p).unwrap();
        assert_relative_eq!(bq[0], 5.0 * scale, max_relative = 4.0 * EPS);
        assert_relative_eq!(
            bp[1],
            (-0.3 * 4.0 - 0.7 * 3.0) * scale,
            max_relative = 16.0 * EPS
        );
    }
}

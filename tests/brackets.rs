//! Poisson and Lagrange brackets, canonicity: [Ardema 15.5, 16.3–16.5, 18.3; Probs. 16/1–16/3].

mod common;

use approx::assert_relative_eq;
use common::{Prob16_1, Prob16_2, Prob16_3};
use hamilton_jacobi::brackets::{
    certify, integral_defect, lagrange_bracket, lagrange_bracket_matrix, liouville_determinant,
    poisson_bracket, poisson_bracket_matrix, reciprocity_defect, time_derivative, Coordinate,
    Momentum, PhaseMap, PoissonBracket,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::{AngularMomentum, HarmonicOscillator};
use hamilton_jacobi::{hamiltonian, DualNum, Hamiltonian, PhaseFunction};
use proptest::prelude::*;

const EPS: f64 = f64::EPSILON;

fn ang(k: usize) -> AngularMomentum<3> {
    AngularMomentum::new(k).unwrap()
}
fn coord<const N: usize>(i: usize) -> Coordinate<N> {
    Coordinate::new(i).unwrap()
}
fn mom<const N: usize>(i: usize) -> Momentum<N> {
    Momentum::new(i).unwrap()
}

// ---------------------------------------------------------------------------------------------
// Angular momentum brackets for a central force, and the generators of rotations/translations
// [Ardema 15.5, 18.3].

hamiltonian!(
    /// H = |p|²/2 + V(|r|) with V = −1/r + 0.1/r² (any central potential would do).
    Central<3> |_s, _t, q, p| p.dot(p) * 0.5 - q.dot(q).sqrt().recip() + q.dot(q).recip() * 0.1
);

#[test]
fn angular_momentum_algebra_and_conservation() {
    for (t, q, p) in common::central_sample_points() {
        let h = |k| ang(k).eval(t, &q, &p);
        // (h_x, h_y) = h_z and cyclic.
        for k in 0..3 {
            let b = poisson_bracket(&ang(k), &ang((k + 1) % 3), t, &q, &p).unwrap();
            assert_relative_eq!(
                b,
                h((k + 2) % 3),
                epsilon = 8.0 * EPS * (1.0 + h((k + 2) % 3).abs())
            );
        }
        // (h_z, H) = 0.
        let hz_h = poisson_bracket(&ang(2), &Central, t, &q, &p).unwrap();
        assert!(hz_h.abs() < 16.0 * EPS, "(h_z, H) = {hz_h}");
    }
    assert!(
        integral_defect(&ang(2), &Central, &common::central_sample_points()).unwrap() < 16.0 * EPS
    );
    // Poisson's theorem: (h_x, h_y) is again an integral.
    let hxy = PoissonBracket(ang(0), ang(1));
    assert!(
        integral_defect(&hxy, &Central, &common::central_sample_points()).unwrap() < 64.0 * EPS
    );
}

#[test]
fn rotation_and_translation_generators() {
    // ρ = h_z: δq = ε ∂ρ/∂p = ε(−y, x, 0), δp = −ε ∂ρ/∂q = ε(−p_y, p_x, 0).
    let (q, p) = (
        SVector::from([0.4, -1.2, 0.7]),
        SVector::from([0.3, 0.8, -0.5]),
    );
    for k in 0..3 {
        let dq = poisson_bracket(&coord(k), &ang(2), 0.0, &q, &p).unwrap();
        let dp = poisson_bracket(&mom(k), &ang(2), 0.0, &q, &p).unwrap();
        let (eq, ep) = ([-q[1], q[0], 0.0][k], [-p[1], p[0], 0.0][k]);
        assert_relative_eq!(dq, eq, epsilon = 4.0 * EPS);
        assert_relative_eq!(dp, ep, epsilon = 4.0 * EPS);
    }
    // The change of H along the generator, (H, ρ), vanishes: H is invariant under rotations.
    assert!(
        poisson_bracket(&Central, &ang(2), 0.0, &q, &p)
            .unwrap()
            .abs()
            < 16.0 * EPS
    );
    // ρ = p₁ with q₁ ignorable: a translation in q₁, and p₁ is conserved.
    hamiltonian!(Ignorable<2> |_s, _t, q, p| p.dot(p) * 0.5 + q[1].cos() * (p[0] * p[1]));
    let (q2, p2) = (SVector::from([3.0, 0.4]), SVector::from([0.2, -0.9]));
    assert_eq!(
        poisson_bracket(&coord(0), &mom(0), 0.0, &q2, &p2).unwrap(),
        1.0
    );
    assert_eq!(
        poisson_bracket(&coord(1), &mom(0), 0.0, &q2, &p2).unwrap(),
        0.0
    );
    assert_eq!(
        time_derivative(&mom(0), &Ignorable, 0.0, &q2, &p2).unwrap(),
        0.0
    );
    // ṗ₂ = −∂H/∂q₂ = sin q₂ p₁ p₂ ≠ 0: q₂ is not ignorable.
    let p2dot = time_derivative(&mom(1), &Ignorable, 0.0, &q2, &p2).unwrap();
    assert_relative_eq!(p2dot, q2[1].sin() * p2[0] * p2[1], epsilon = 4.0 * EPS);
}

// ---------------------------------------------------------------------------------------------
// The oscillator's canonical transformation from F1 = ½ m ω q² cot Q [Ardema 16.5].

const MASS: f64 = 2.0;
const OMEGA: f64 = 3.0;

/// Forward map (q, p) ↦ (Q, P): tan Q = mωq/p, P = (p² + m²ω²q²)/(2mω).
struct OscillatorToAngle;
impl PhaseMap<1> for OscillatorToAngle {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        let mw = MASS * OMEGA;
        (
            SVector::from([(q[0] * mw).atan2(p[0])]),
            SVector::from([(p[0] * p[0] + q[0] * q[0] * (mw * mw)) / (2.0 * mw)]),
        )
    }
}

/// Inverse map (Q, P) ↦ (q, p) = (√(2P/(mω)) sin Q, √(2mωP) cos Q).
struct AngleToOscillator;
impl PhaseMap<1> for AngleToOscillator {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        let (big_q, big_p) = (q[0], p[0]);
        let mw = MASS * OMEGA;
        (
            SVector::from([(big_p * (2.0 / mw)).sqrt() * big_q.sin()]),
            SVector::from([(big_p * (2.0 * mw)).sqrt() * big_q.cos()]),
        )
    }
}

/// The oscillator's angle `Q(q, p) = atan2(mωq, p)` as a phase function.
struct Angle;
impl PhaseFunction<1> for Angle {
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 1>, p: &SVector<D, 1>) -> D {
        OscillatorToAngle.apply(t, q, p).0[0]
    }
}

/// `c·P(q, p)` with the oscillator's action `P = (p² + m²ω²q²)/(2mω)`; `c ≠ 1` is not canonical.
struct ScaledAction(f64);
impl PhaseFunction<1> for ScaledAction {
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 1>, p: &SVector<D, 1>) -> D {
        OscillatorToAngle.apply(t, q, p).1[0] * self.0
    }
}

/// `(Q, P) ↦ (q, p)` with `P` rescaled by `1/c` first: `[Q, P] = 1/c`.
struct ScaledInverse(f64);
impl PhaseMap<1> for ScaledInverse {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        AngleToOscillator.apply(t, q, &(p * D::from(1.0 / self.0)))
    }
}

#[test]
fn oscillator_angle_variables() {
    let (q, p) = (SVector::from([0.5]), SVector::from([1.2]));
    let (big_q, big_p) = OscillatorToAngle.apply(0.0, &q, &p);
    // Published instance: (Q, P) = (1.19028994968253, 0.87), H = ωP = 2.61 (15 digits given).
    assert_relative_eq!(big_q[0], 1.19028994968253, epsilon = 1e-14);
    assert_relative_eq!(big_p[0], 0.87, epsilon = 1e-15);
    // Angle variables of the crate's oscillator: Q advances uniformly, Q̇ = (Q, H) = ω, and P is an
    // integral, Ṗ = (P, H) = 0 (closed forms; H is the library's `HarmonicOscillator`).
    let osc = HarmonicOscillator::new(MASS, OMEGA).unwrap();
    for (q, p) in [(0.5, 1.2), (-0.8, 0.3), (0.1, -2.0), (-1.4, -0.6)] {
        let (q, p) = (SVector::from([q]), SVector::from([p]));
        let qdot = poisson_bracket(&Angle, &osc, 0.0, &q, &p).unwrap();
        assert_relative_eq!(qdot, OMEGA, epsilon = 16.0 * EPS * OMEGA);
        let pdot = time_derivative(&ScaledAction(1.0), &osc, 0.0, &q, &p).unwrap();
        // The two terms ±ω q p cancel.
        let scale = OMEGA * (q[0] * p[0]).abs();
        assert!(pdot.abs() <= 16.0 * EPS * scale, "Ṗ = {pdot}");
        // (Q, cP) = c: canonical only for c = 1, so a bracket that always returned 1 (or
        // dropped a factor) fails here.
        for c in [1.0, 2.5, -0.5] {
            let b = poisson_bracket(&Angle, &ScaledAction(c), 0.0, &q, &p).unwrap();
            assert_relative_eq!(b, c, epsilon = 16.0 * EPS * c.abs());
        }
    }
    // The map's bracket matrix: (Q, Q) = (P, P) = 0, (Q, P) = 1.
    let pb = poisson_bracket_matrix(&OscillatorToAngle, 0.0, &q, &p).unwrap();
    assert_relative_eq!(pb.qp[(0, 0)], 1.0, epsilon = 8.0 * EPS);
    assert!(pb.qq[(0, 0)].abs() <= 8.0 * EPS && pb.pp[(0, 0)].abs() <= 8.0 * EPS);
    // [Q, P] = 1 from the inverse map, and 1/c after rescaling P by 1/c.
    let lb = lagrange_bracket(&AngleToOscillator, 0.0, &big_q, &big_p, 0, 1).unwrap();
    assert_relative_eq!(lb, 1.0, epsilon = 8.0 * EPS);
    for c in [2.0, -3.0] {
        let cp = big_p * c;
        let lb = lagrange_bracket(&ScaledInverse(c), 0.0, &big_q, &cp, 0, 1).unwrap();
        assert_relative_eq!(lb, 1.0 / c, epsilon = 8.0 * EPS);
    }
    assert!(reciprocity_defect(&AngleToOscillator, 0.0, &big_q, &big_p).unwrap() < 16.0 * EPS);
    // Round trip.
    let (q2, p2) = AngleToOscillator.apply(0.0, &big_q, &big_p);
    assert_relative_eq!(q2[0], q[0], epsilon = 4.0 * EPS);
    assert_relative_eq!(p2[0], p[0], epsilon = 4.0 * EPS);
}

// ---------------------------------------------------------------------------------------------
// Free fall as a canonical map; Lagrange-bracket test [Ardema 16.4].

struct FreeFall {
    g: f64,
}
impl PhaseMap<1> for FreeFall {
    /// (Q, P) ↦ (q, p) = (Q + P t − ½ g t², P − g t).
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        (
            SVector::from([q[0] + p[0] * t - t * t * (0.5 * self.g)]),
            SVector::from([p[0] - t * self.g]),
        )
    }
}

#[test]
fn free_fall_flow_is_canonical() {
    let ff = FreeFall { g: 9.81 };
    for t in [0.0, 0.3, 2.0, 17.5] {
        let (u1, u2) = (SVector::from([1.5]), SVector::from([-4.0]));
        let c = certify(&ff, t, &u1, &u2).unwrap();
        // ∂(q, p)/∂(Q, P) = [[1, t], [0, 1]], determinant 1.
        assert_eq!(c.jacobian.qq[(0, 0)], 1.0);
        assert_eq!(c.jacobian.qp[(0, 0)], t);
        assert_eq!(c.jacobian.pq[(0, 0)], 0.0);
        assert_eq!(c.jacobian.pp[(0, 0)], 1.0);
        assert_eq!(c.det_minus_one, 0.0);
        // [Q, P] = 1, [Q, Q] = [P, P] = 0.
        let l = lagrange_bracket_matrix(&ff, t, &u1, &u2).unwrap();
        assert_eq!((l.qq[(0, 0)], l.qp[(0, 0)], l.pp[(0, 0)]), (0.0, 1.0, 0.0));
        assert_eq!(liouville_determinant(&ff, t, &u1, &u2).unwrap(), 1.0);
    }
}

// ---------------------------------------------------------------------------------------------
// Canonicity exercises [Ardema Probs. 16/1–16/3].

#[test]
fn canonicity_exercises() {
    let points = [(0.7, 1.1), (1.9, 0.4), (0.2, 2.5)];
    for (q, p) in points {
        let (q, p) = (SVector::from([q]), SVector::from([p]));
        // 16/2 (sin p > 0 at these points): (Q, P) = 1.
        let c = certify(&Prob16_2, 0.0, &q, &p).unwrap();
        assert!(
            c.symplectic_defect < 32.0 * EPS,
            "16/2 defect {}",
            c.symplectic_defect
        );
        // 16/3: (Q, P) = αβ q^{2α−1}; canonical only for α = ½, β = 2.
        for (alpha, beta) in [(0.5, 2.0), (0.5, 1.5), (0.7, 2.0), (1.0, 1.0)] {
            let m = Prob16_3 { alpha, beta };
            let pb = poisson_bracket_matrix(&m, 0.0, &q, &p).unwrap().qp[(0, 0)];
            let expected = alpha * beta * q[0].powf(2.0 * alpha - 1.0);
            assert_relative_eq!(pb, expected, epsilon = 16.0 * EPS * (1.0 + expected.abs()));
            let canonical = certify(&m, 0.0, &q, &p).unwrap().is_canonical(1e-12);
            assert_eq!(
                canonical,
                alpha == 0.5 && beta == 2.0,
                "α = {alpha}, β = {beta}"
            );
            // Reciprocity holds for any invertible map, canonical or not.
            assert!(reciprocity_defect(&m, 0.0, &q, &p).unwrap() < 1e-13);
        }
        for t in [0.0, 0.7, -1.3] {
            let c = certify(&Prob16_1, t, &q, &p).unwrap();
            assert!(
                c.symplectic_defect < 64.0 * EPS * t.abs().exp().powi(2),
                "t = {t}: {}",
                c.symplectic_defect
            );
        }
    }
}

#[test]
fn bad_points_are_rejected() {
    let q = SVector::from([f64::NAN]);
    let p = SVector::from([1.0]);
    assert!(certify(&Prob16_2, 0.0, &q, &p).is_err());
    assert!(poisson_bracket(&coord(0), &mom(0), f64::INFINITY, &p, &p).is_err());
    // Index out of range: a typed error at construction, not a panic at evaluation.
    assert!(Coordinate::<2>::new(2).is_err());
    assert!(Momentum::<1>::new(1).is_err());
    // A map whose Jacobian is not finite at the point (16/2 at q = 0).
    assert!(certify(&Prob16_2, 0.0, &SVector::from([0.0]), &p).is_err());
}

// ---------------------------------------------------------------------------------------------
// Property tests of the Poisson bracket [Ardema 15.5]: antisymmetry, Leibniz, Jacobi identity,
// canonical brackets.

/// A random smooth function on 2-DOF phase space: Σ c_k b_k(q, p) with nonlinear basis terms.
#[derive(Clone, Debug)]
struct Smooth([f64; 6]);
impl PhaseFunction<2> for Smooth {
    fn eval<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>, p: &SVector<D, 2>) -> D {
        let c = &self.0;
        (q[0] * p[1]).sin() * c[0]
            + (q[1] * 0.3 + p[0] * 0.2).exp() * c[1]
            + q[0] * q[0] * p[0] * c[2]
            + p[1] * p[1] * p[1] * c[3]
            + (p[0] + q[1]).cos() * c[4]
            + q[0] * q[1] * p[0] * p[1] * c[5]
    }
}

impl Smooth {
    /// The gradient `(∂F/∂q₀, ∂F/∂q₁, ∂F/∂p₀, ∂F/∂p₁)` differentiated by hand (an oracle independent
    /// of the crate's AD).
    fn gradient(&self, q: &SVector<f64, 2>, p: &SVector<f64, 2>) -> [f64; 4] {
        let c = &self.0;
        let e = (0.3 * q[1] + 0.2 * p[0]).exp();
        let s = (p[0] + q[1]).sin();
        let cqp = (q[0] * p[1]).cos();
        [
            c[0] * p[1] * cqp + 2.0 * c[2] * q[0] * p[0] + c[5] * q[1] * p[0] * p[1],
            0.3 * c[1] * e - c[4] * s + c[5] * q[0] * p[0] * p[1],
            0.2 * c[1] * e + c[2] * q[0] * q[0] - c[4] * s + c[5] * q[0] * q[1] * p[1],
            c[0] * q[0] * cqp + 3.0 * c[3] * p[1] * p[1] + c[5] * q[0] * q[1] * p[0],
        ]
    }
}

/// `(f, g) = Σᵢ ∂f/∂qᵢ ∂g/∂pᵢ − ∂f/∂pᵢ ∂g/∂qᵢ` from two gradients, with the sum of the absolute
/// values of the products (the scale of its rounding).
fn bracket_from_gradients(f: &[f64; 4], g: &[f64; 4]) -> (f64, f64) {
    let terms = [f[0] * g[2], f[1] * g[3], -f[2] * g[0], -f[3] * g[1]];
    (terms.iter().sum(), terms.iter().map(|x| x.abs()).sum())
}

/// Product of two phase functions.
struct Product<'a>(&'a Smooth, &'a Smooth);
impl PhaseFunction<2> for Product<'_> {
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 2>, p: &SVector<D, 2>) -> D {
        self.0.eval(t, q, p) * self.1.eval(t, q, p)
    }
}

fn smooth() -> impl Strategy<Value = Smooth> {
    prop::array::uniform6(-2.0..2.0f64).prop_map(Smooth)
}
fn point() -> impl Strategy<Value = (SVector<f64, 2>, SVector<f64, 2>)> {
    (
        prop::array::uniform2(-1.5..1.5f64),
        prop::array::uniform2(-1.5..1.5f64),
    )
        .prop_map(|(q, p)| (SVector::from(q), SVector::from(p)))
}

proptest! {
    #![proptest_config(common::config(0x5eed_0001))]

    #[test]
    fn antisymmetry(f in smooth(), g in smooth(), (q, p) in point()) {
        let fg = poisson_bracket(&f, &g, 0.0, &q, &p).unwrap();
        let gf = poisson_bracket(&g, &f, 0.0, &q, &p).unwrap();
        // Both orders against the bracket of the hand-differentiated gradients: (f, g) = B and
        // (g, f) = −B, each to the rounding of the four products and of the gradients (a few ulps
        // of each term).
        let (b, scale) = bracket_from_gradients(&f.gradient(&q, &p), &g.gradient(&q, &p));
        prop_assert!((fg - b).abs() <= 64.0 * EPS * (1.0 + scale), "(f, g) = {fg} vs {b}");
        prop_assert!((gf + b).abs() <= 64.0 * EPS * (1.0 + scale), "(g, f) = {gf} vs {}", -b);
    }

    #[test]
    fn leibniz_rule(f in smooth(), g in smooth(), k in smooth(), (q, p) in point()) {
        let lhs = poisson_bracket(&Product(&f, &g), &k, 0.0, &q, &p).unwrap();
        let fv = f.eval(0.0, &q, &p);
        let gv = g.eval(0.0, &q, &p);
        let a = fv * poisson_bracket(&g, &k, 0.0, &q, &p).unwrap();
        let b = gv * poisson_bracket(&f, &k, 0.0, &q, &p).unwrap();
        // Rounding relative to the size of the summands.
        prop_assert!((lhs - a - b).abs() <= 64.0 * EPS * (1.0 + a.abs() + b.abs()), "{lhs} vs {a} + {b}");
    }

    #[test]
    fn jacobi_identity(f in smooth(), g in smooth(), k in smooth(), (q, p) in point()) {
        let a = poisson_bracket(&f, &PoissonBracket(g.clone(), k.clone()), 0.0, &q, &p).unwrap();
        let b = poisson_bracket(&g, &PoissonBracket(k.clone(), f.clone()), 0.0, &q, &p).unwrap();
        let c = poisson_bracket(&k, &PoissonBracket(f.clone(), g.clone()), 0.0, &q, &p).unwrap();
        // Each nested bracket is a sum of O(10²) second-derivative products: allow a few hundred ulps
        // of the largest term.
        prop_assert!((a + b + c).abs() <= 512.0 * EPS * (1.0 + a.abs() + b.abs() + c.abs()), "{a} {b} {c}");
    }

    #[test]
    fn canonical_brackets((q, p) in point(), t in -5.0..5.0f64) {
        for i in 0..2 {
            for j in 0..2 {
                let qp = poisson_bracket(&coord(i), &mom(j), t, &q, &p).unwrap();
                prop_assert_eq!(qp, if i == j { 1.0 } else { 0.0 });
                prop_assert_eq!(poisson_bracket(&coord(i), &coord(j), t, &q, &p).unwrap(), 0.0);
                prop_assert_eq!(poisson_bracket(&mom(i), &mom(j), t, &q, &p).unwrap(), 0.0);
            }
        }
    }

    #[test]
    fn bracket_with_h_is_the_vector_field(f in smooth(), (q, p) in point()) {
        hamiltonian!(Anharmonic<2> |_s, _t, q, p| p.dot(p) * 0.5 + q[0] * q[0] * q[1] + q[1].powi(4) * 0.25);
        // Hamilton's equations of H = |p|²/2 + q₀²q₁ + q₁⁴/4 by hand:
        // q̇ = p, ṗ₀ = −2q₀q₁, ṗ₁ = −(q₀² + q₁³).
        let qd = [p[0], p[1]];
        let pd = [-2.0 * q[0] * q[1], -(q[0] * q[0] + q[1].powi(3))];
        let tol = |x: f64| 8.0 * EPS * (1.0 + x.abs());
        // (q_i, H) = q̇_i and (p_i, H) = ṗ_i, and the library's vector field agrees.
        let (vq, vp) = Anharmonic.vector_field(0.0, &q, &p).unwrap();
        for i in 0..2 {
            let bq = poisson_bracket(&coord(i), &Anharmonic, 0.0, &q, &p).unwrap();
            let bp = poisson_bracket(&mom(i), &Anharmonic, 0.0, &q, &p).unwrap();
            prop_assert!((bq - qd[i]).abs() <= tol(qd[i]), "(q{i}, H) = {bq} vs {}", qd[i]);
            prop_assert!((bp - pd[i]).abs() <= tol(pd[i]), "(p{i}, H) = {bp} vs {}", pd[i]);
            prop_assert!((vq[i] - qd[i]).abs() <= tol(qd[i]));
            prop_assert!((vp[i] - pd[i]).abs() <= tol(pd[i]));
        }
        // dF/dt = ∇_q F · q̇ + ∇_p F · ṗ (chain rule with the hand gradient) = (F, H).
        let gf = f.gradient(&q, &p);
        let terms = [gf[0] * qd[0], gf[1] * qd[1], gf[2] * pd[0], gf[3] * pd[1]];
        let expected: f64 = terms.iter().sum();
        let scale: f64 = terms.iter().map(|x| x.abs()).sum();
        let fdot = time_derivative(&f, &Anharmonic, 0.0, &q, &p).unwrap();
        prop_assert!((fdot - expected).abs() <= 64.0 * EPS * (1.0 + scale), "{fdot} vs {expected}");
        let bracket = poisson_bracket(&f, &Anharmonic, 0.0, &q, &p).unwrap();
        prop_assert!((bracket - expected).abs() <= 64.0 * EPS * (1.0 + scale), "{bracket} vs {expected}");
    }
}

#[test]
fn integral_defect_does_not_skip_nan() {
    // F = √q is undefined at q < 0: the defect is an error, not a silent 0.
    struct SqrtQ;
    impl PhaseFunction<1> for SqrtQ {
        fn eval<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 1>, _p: &SVector<D, 1>) -> D {
            q[0].sqrt()
        }
    }
    hamiltonian!(Free1<1> |_s, _t, _q, p| p[0] * p[0] * 0.5);
    let pts = [
        (0.0, SVector::from([1.0]), SVector::from([0.0])),
        (0.0, SVector::from([-1.0]), SVector::from([0.5])),
    ];
    assert!(integral_defect(&SqrtQ, &Free1, &pts).is_err());
    assert!(poisson_bracket(&SqrtQ, &Free1, 0.0, &pts[1].1, &pts[1].2).is_err());
}

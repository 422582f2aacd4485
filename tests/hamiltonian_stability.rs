//! Stability of Hamiltonian systems (SPEC M34–M37; T28, T29, T40, T41; X10): the box symmetry
//! and Krein signatures of `J∇²H`, the Krein collision at L4 at Routh's ratio located by
//! continuation, monodromy matrices and Floquet multipliers of periodic orbits, Hill's
//! (Clohessy–Wiltshire) equations, the direct method, and the dumbbell satellite.

use hamilton_jacobi::hamilton_jacobi::{ScalarField, VectorField};
use hamilton_jacobi::integrate::{integrate, Dop853, Problem, Recorder};
use hamilton_jacobi::nalgebra::{DMatrix, SVector, Vector1, Vector2, Vector3};
use hamilton_jacobi::stability::{
    check_spectrum_symmetry, dirichlet_check, hamiltonian_crossings, hamiltonian_equilibrium,
    hamiltonian_linearization, hamiltonian_spectrum, lyapunov_derivative, monodromy,
    steady_motion_spectrum, CrossingKind, Reduced, Slot, SpectralBlock, Stability,
};
use hamilton_jacobi::systems::{
    ClohessyWiltshire, DumbbellOrientation, DumbbellSatellite, ExactFlow, Kepler3, Pendulum,
    RestrictedThreeBody,
};
use hamilton_jacobi::{DualNum, Hamiltonian};

mod common;
use common::{BoxHamiltonian, DampedOscillator};

#[test]
fn t29_box_spectrum_of_a_complex_saddle_and_of_the_fixed_hessian() {
    let h = BoxHamiltonian { a: 0.3, b: 2.0 };
    let a =
        hamiltonian_linearization(&h, 0.0, &Vector2::new(0.4, -0.2), &Vector2::zeros()).unwrap();
    // The eigenvalues of a 4×4 matrix of O(1) entries from a backward-stable QR iteration are
    // good to a few ε‖A‖: 1e−13 leaves a margin of ~100.
    let sym = check_spectrum_symmetry(&a, 1e-13).unwrap();
    for l in &sym.eigenvalues {
        assert!(
            (l.re.abs() - 0.3).abs() < 1e-13 && (l.im.abs() - 2.0).abs() < 1e-13,
            "{l}"
        );
    }
    let hess = h
        .hessian(0.0, &Vector2::zeros(), &Vector2::zeros())
        .unwrap()
        .to_dmatrix();
    let sp = hamiltonian_spectrum(&hess).unwrap();
    assert_eq!(sp.stability, Stability::Unstable);
    assert_eq!(sp.spectral_type(), [0, 0, 4, 0]);
    match sp.blocks[0] {
        SpectralBlock::ComplexSaddle {
            re,
            im,
            multiplicity,
        } => {
            assert!((re - 0.3).abs() < 1e-13 && (im - 2.0).abs() < 1e-13);
            assert_eq!(multiplicity, 1);
        }
        b => panic!("{b:?}"),
    }
    // Fixed instance: λ⁴ − 3λ² − 13, λ² = (3 ± √61)/2.
    let hess = DMatrix::from_row_slice(
        4,
        4,
        &[
            2.0, 1.0, 0.0, 1.0, 1.0, -1.0, 1.0, 0.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.0, 0.0, 3.0,
        ],
    );
    let sp = hamiltonian_spectrum(&hess).unwrap();
    let s61 = 61f64.sqrt();
    let (rate, freq) = (((3.0 + s61) / 2.0).sqrt(), ((s61 - 3.0) / 2.0).sqrt());
    assert!((rate - 2.324892).abs() < 5e-7 && (freq - 1.550846).abs() < 5e-7);
    assert_eq!(sp.spectral_type(), [2, 2, 0, 0]);
    assert_eq!(sp.stability, Stability::Unstable);
    for b in &sp.blocks {
        match *b {
            SpectralBlock::Hyperbolic { rate: r, .. } => assert!((r - rate).abs() < 1e-13),
            SpectralBlock::Elliptic { frequency, .. } => assert!((frequency - freq).abs() < 1e-13),
            b => panic!("{b:?}"),
        }
    }
    assert!(sp.symmetry_defect < 1e-14, "{}", sp.symmetry_defect);
}

/// A deterministic stream of numbers in `[−1, 1)` (a linear congruential generator).
struct Lcg(u64);

impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((self.0 >> 11) as f64) / ((1u64 << 53) as f64) * 2.0 - 1.0
    }
}

#[test]
fn m35_box_symmetry_of_random_hessians_and_x10_asymmetry_detected() {
    let mut rng = Lcg(17);
    for n in 1..=4 {
        for _ in 0..50 {
            let mut s = DMatrix::<f64>::zeros(2 * n, 2 * n);
            for i in 0..2 * n {
                for j in 0..=i {
                    let x = rng.next();
                    s[(i, j)] = x;
                    s[(j, i)] = x;
                }
            }
            let sp = hamiltonian_spectrum(&s).unwrap();
            // Simple eigenvalues of a random matrix of O(1) entries move by O(ε‖A‖κ) under
            // rounding; κ (the eigenvalue condition) stays below 10⁴ for these sizes except near
            // a collision, where the defect is O(√ε): 1e−7 is the tolerance of a collision.
            let a = DMatrix::from_fn(2 * n, 2 * n, |i, j| {
                if i < n {
                    s[(n + i, j)]
                } else {
                    -s[(i - n, j)]
                }
            });
            check_spectrum_symmetry(&a, 1e-7).unwrap();
            assert!(sp.symmetry_defect < 1e-7);
            let counted: usize = sp.spectral_type().iter().sum();
            assert_eq!(counted, 2 * n, "{:?}", sp.blocks);
        }
    }
    // X10: a Hessian from differences good to 1e−6 (an asymmetric error in A) breaks the box
    // visibly: the defect is of the size of the error, far above rounding.
    let h = BoxHamiltonian { a: 0.3, b: 2.0 };
    let mut a = hamiltonian_linearization(&h, 0.0, &Vector2::zeros(), &Vector2::zeros()).unwrap();
    a[(0, 0)] += 1e-6;
    let err = check_spectrum_symmetry(&a, 1e-10).unwrap_err();
    assert!(format!("{err}").contains("not symmetric"), "{err}");
}

/// `27μ(1 − μ) = 1`: `μ_R = (1 − √(23/27))/2`.
fn routh() -> f64 {
    0.5 * (1.0 - (23.0f64 / 27.0).sqrt())
}

fn l4_hessian(mu: f64) -> hamilton_jacobi::Result<DMatrix<f64>> {
    let h = RestrictedThreeBody::new(mu)?;
    let (q, p) = h.l4();
    Ok(Hamiltonian::<2>::hessian(&h, 0.0, &q, &p)?.to_dmatrix())
}

#[test]
fn l4_krein_signatures_are_opposite_below_routh_and_the_collision_is_located_to_1e_10() {
    let mu_r = routh();
    assert!((mu_r - 0.0385208965).abs() < 1e-10);
    // L4 is an equilibrium: Newton from a nearby guess lands on (½ − μ, √3/2).
    let h = RestrictedThreeBody::new(0.01).unwrap();
    let (q, p) = h.l4();
    let eq = hamiltonian_equilibrium(&h, 0.0, &(q * 1.01), &(p * 0.99)).unwrap();
    assert!(
        (eq.q - q).amax() < 1e-13 && (eq.p - p).amax() < 1e-13,
        "{eq:?}"
    );
    for mu in [0.001, 0.01, 0.0121505856, 0.03, 0.038] {
        let sp = hamiltonian_spectrum(&l4_hessian(mu).unwrap()).unwrap();
        assert_eq!(sp.stability, Stability::Stable, "μ = {mu}: {:?}", sp.blocks);
        // λ⁴ + λ² + (27/4)μ(1 − μ) = 0: ω² = (1 ± √(1 − 27μ(1 − μ)))/2.
        let d = (1.0 - 27.0 * mu * (1.0 - mu)).sqrt();
        let want = [((1.0 - d) / 2.0).sqrt(), ((1.0 + d) / 2.0).sqrt()];
        let k = sp.krein_signatures();
        assert_eq!(k.len(), 2, "{k:?}");
        for ((w, _), want) in k.iter().zip(want) {
            // The eigenvalues are simple with condition ~1/√D: error ε/D‖A‖ at most ~1e−13.
            assert!((w - want).abs() < 1e-12, "μ = {mu}: {w} vs {want}");
        }
        // Opposite signatures: L4 is a maximum of the effective potential, the energy is
        // indefinite, and only the Krein signatures tell the two modes apart.
        assert_eq!(k[0].1 * k[1].1, -1, "μ = {mu}: {k:?}");
        assert!(!sp.strongly_stable() || k[0].1 != k[1].1);
    }
    for mu in [0.04, 0.1, 0.3] {
        let sp = hamiltonian_spectrum(&l4_hessian(mu).unwrap()).unwrap();
        assert_eq!(sp.stability, Stability::Unstable, "μ = {mu}");
        assert_eq!(
            sp.spectral_type(),
            [0, 0, 4, 0],
            "μ = {mu}: {:?}",
            sp.blocks
        );
    }
    // Continuation in μ: the spectral type changes once in [0.01, 0.1], a collision. The test
    // function 1 − 27μ(1 − μ) (the λ²-discriminant up to a positive factor) has slope
    // 27(1 − 2μ_R) ≈ 25 and is computed to O(ε): its root is resolved to ~1e−16; Brent stops at
    // 1e−13.
    let c = hamiltonian_crossings(l4_hessian, 0.01, 0.1, 10, 1e-13).unwrap();
    assert_eq!(c.len(), 1, "{c:?}");
    assert_eq!(c[0].kind, CrossingKind::Collision);
    assert_eq!(c[0].unstable_counts, (0, 2));
    assert!(
        (c[0].parameter - mu_r).abs() <= 1e-10,
        "μ* = {:.16}, μ_R = {mu_r:.16}",
        c[0].parameter
    );
    // At the collision the two pairs meet at ω² = ½.
    for l in &c[0].eigenvalues {
        assert!((l.im.abs() - 0.5f64.sqrt()).abs() < 1e-6, "{l}");
    }
}

/// `E(k)` and `K(k)` by the arithmetic–geometric mean [Abramowitz & Stegun 17.6.3–4].
fn complete_e_k(k: f64, kc: f64) -> (f64, f64) {
    let (mut a, mut b, mut c) = (1.0f64, kc, k);
    let mut sum = 0.5 * c * c;
    let mut w = 0.5;
    for _ in 0..40 {
        let (an, bn) = (0.5 * (a + b), (a * b).sqrt());
        c = 0.5 * (a - b);
        a = an;
        b = bn;
        w *= 2.0;
        sum += w * c * c;
        if c.abs() < 1e-17 {
            break;
        }
    }
    let kk = std::f64::consts::PI / (2.0 * a);
    (kk * (1.0 - sum), kk)
}

#[test]
fn m34_pendulum_libration_monodromy_is_the_shear_of_the_period_derivative() {
    let n = 1.3;
    let pendulum = Pendulum::new(n).unwrap();
    let rtol = 1e-12;
    let method = Dop853::new(rtol, rtol).unwrap();
    let mut last = 0.0;
    // Continuation in the amplitude.
    for a in [0.3, 1.0, 2.0, 2.6, 3.0] {
        let period = pendulum.period(a).unwrap();
        let m = monodromy::<_, 1, 3>(
            &pendulum,
            0.0,
            &Vector1::new(a),
            &Vector1::zeros(),
            period,
            &method,
        )
        .unwrap();
        // T′(E) with E = 2n²k², T = 4K(k)/n: dT/dE = (E(k)/k′² − K(k))/(n³k²).
        let (k, kc) = ((a / 2.0).sin(), (a / 2.0).cos());
        let (ek, kk) = complete_e_k(k, kc);
        assert!((4.0 * kk / n - period).abs() < 1e-13 * period);
        let dt_de = (ek / (kc * kc) - kk) / (n.powi(3) * k * k);
        // One period of DOP853 at rtol: the global error of Φ is a few hundred local errors
        // times ‖Φ‖; 1e3 · rtol · max(1, ‖M‖) bounds it.
        let tol = 1e3 * rtol * m.matrix.amax().max(1.0);
        let b = m.trivial_block;
        assert!((b[(0, 0)] - 1.0).abs() < tol, "a = {a}: {b}");
        assert!((b[(1, 1)] - 1.0).abs() < tol, "a = {a}: {b}");
        assert!(b[(1, 0)].abs() < tol, "a = {a}: {b}");
        assert!(
            (m.shear + dt_de).abs() < tol,
            "a = {a}: shear {} vs −T′(E) = {}",
            m.shear,
            -dt_de
        );
        // Trace exactly 2 and det 1: both multipliers are 1 (a parabolic block).
        assert!((m.matrix.trace() - 2.0).abs() < tol);
        assert!((m.matrix.determinant() - 1.0).abs() < tol);
        assert!(m.closure_defect < tol && m.flow_defect < tol);
        assert!(m.nontrivial.is_empty());
        // The period grows with the amplitude ever faster towards the separatrix.
        assert!(-m.shear > last);
        last = -m.shear;
    }
}

/// Two uncoupled oscillators of frequencies 1 and `ω`.
struct TwoOscillators {
    omega: f64,
}

impl Hamiltonian<2> for TwoOscillators {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 2>,
        p: &SVector<D, 2>,
    ) -> D {
        (p[0] * p[0] + q[0] * q[0] + p[1] * p[1] + q[1] * q[1] * (self.omega * self.omega)) * 0.5
    }
}

#[test]
fn m34_nontrivial_floquet_multipliers_of_an_orbit_of_two_oscillators() {
    let omega = 1.3;
    let h = TwoOscillators { omega };
    let rtol = 1e-12;
    let m = monodromy::<_, 2, 10>(
        &h,
        0.0,
        &Vector2::new(1.0, 0.0),
        &Vector2::zeros(),
        std::f64::consts::TAU,
        &Dop853::new(rtol, rtol).unwrap(),
    )
    .unwrap();
    let tol = 1e3 * rtol;
    // Isochronous: no shear.
    assert!(m.shear.abs() < tol && (m.trivial_block[(0, 0)] - 1.0).abs() < tol);
    // The transverse oscillator turns by 2πω in one period: multipliers e^{±2πiω}.
    let phase = std::f64::consts::TAU * omega;
    assert_eq!(m.nontrivial.len(), 2);
    for l in &m.nontrivial {
        assert!((l.norm() - 1.0).abs() < tol, "{l}");
        assert!((l.re - phase.cos()).abs() < tol, "{l}");
        assert!((l.im.abs() - phase.sin().abs()).abs() < tol, "{l}");
    }
    assert_eq!(m.multipliers.len(), 4);
    // A wrong augmented dimension is refused.
    assert!(monodromy::<_, 2, 8>(
        &h,
        0.0,
        &Vector2::new(1.0, 0.0),
        &Vector2::zeros(),
        1.0,
        &Dop853::new(rtol, rtol).unwrap()
    )
    .is_err());
}

#[test]
fn t28_clohessy_wiltshire_closed_form_against_integration() {
    let cw = ClohessyWiltshire::new(0.0011).unwrap();
    let r0 = Vector3::new(10.0, -20.0, 5.0);
    let v0 = Vector3::new(0.01, -0.02, 0.003);
    let (r, _) = cw.propagate(&r0, &v0, 6000.0).unwrap();
    let want = [12.51549253, -60.86993386, 5.60082122];
    for k in 0..3 {
        // Eight decimals printed: half a unit of the last digit.
        assert!((r[k] - want[k]).abs() < 5e-9, "{r}");
    }
    assert!((cw.along_track_drift(10.0, -0.02).unwrap() + 0.006).abs() < 1e-17);
    // Hamilton's equations of the quadratic H integrated by DOP853: state errors of
    // rtol · |state| per step over ~200 steps.
    let p0 = cw.momentum(&r0, &v0).unwrap();
    let problem = Problem::new(&cw, 0.0, r0, p0, 6000.0).unwrap();
    let rep = integrate(&problem, &Dop853::new(1e-13, 1e-13).unwrap(), &mut ()).unwrap();
    let (rq, rv) = cw.propagate(&r0, &v0, 6000.0).unwrap();
    assert!((rep.last.q - rq).amax() < 1e-9, "{} vs {rq}", rep.last.q);
    assert!((cw.velocity(&rep.last.q, &rep.last.p).unwrap() - rv).amax() < 1e-12);
    // The exact flow is the closed form in (q, p).
    let (q1, p1) = cw.exact_flow(0.0, &r0, &p0, 6000.0).unwrap();
    assert!((q1 - rq).amax() < 1e-12 && (cw.velocity(&q1, &p1).unwrap() - rv).amax() < 1e-15);
    // T28 bounded special case: x = (ẋ₀/n) sin nt, y = −(2ẋ₀/n)(1 − cos nt).
    let n = cw.n();
    let u = 0.01;
    for t in [100.0, 1000.0, 5000.0] {
        let (r, _) = cw
            .propagate(&Vector3::zeros(), &Vector3::new(u, 0.0, 0.0), t)
            .unwrap();
        assert!((r[0] - u / n * (n * t).sin()).abs() < 1e-12);
        assert!((r[1] + 2.0 * u / n * (1.0 - (n * t).cos())).abs() < 1e-12);
    }
    // The bounded-motion condition ẏ₀ = −2n x₀: after ten orbits the integrated motion is back
    // where it started (no drift); without it, it drifts by 10 T · (−3(ẏ₀ + 2n x₀)).
    let orbit = std::f64::consts::TAU / n;
    for (vy, drift) in [
        (cw.bounded_along_track_velocity(10.0).unwrap(), 0.0),
        (0.0, -3.0 * 2.0 * n * 10.0),
    ] {
        let v0 = Vector3::new(0.0, vy, 0.0);
        let r0 = Vector3::new(10.0, 0.0, 0.0);
        let problem =
            Problem::new(&cw, 0.0, r0, cw.momentum(&r0, &v0).unwrap(), 10.0 * orbit).unwrap();
        let rep = integrate(&problem, &Dop853::new(1e-13, 1e-13).unwrap(), &mut ()).unwrap();
        assert!(
            (rep.last.q[1] - drift * 10.0 * orbit).abs() < 1e-8,
            "ẏ₀ = {vy}: y = {}",
            rep.last.q[1]
        );
        assert!((rep.last.q[0] - 10.0).abs() < 1e-8);
    }
}

#[test]
fn t28_clohessy_wiltshire_is_the_two_body_relative_motion_to_second_order() {
    // Reference on the circular orbit a = μ = 1 (n = 1); the relative state in the rotating
    // frame (x radial, y along-track) and the deputy's inertial state.
    let kepler = Kepler3::new(1.0).unwrap();
    let cw = ClohessyWiltshire::new(1.0).unwrap();
    let t = 2.0;
    let mut errors = Vec::new();
    for scale in [1e-3, 1e-4] {
        let dr = Vector3::new(1.0, -2.0, 0.5) * scale;
        let dv = Vector3::new(0.3, -0.7, 0.2) * scale;
        let chief = Vector3::new(1.0, 0.0, 0.0);
        let chief_v = Vector3::new(0.0, 1.0, 0.0);
        let omega = Vector3::new(0.0, 0.0, 1.0);
        let q0 = chief + dr;
        let p0 = chief_v + dv + omega.cross(&dr);
        let (q1, _) = kepler.exact_flow(0.0, &q0, &p0, t).unwrap();
        let (s, c) = t.sin_cos();
        let chief_t = Vector3::new(c, s, 0.0);
        let d = q1 - chief_t;
        let rel = Vector3::new(d[0] * c + d[1] * s, -d[0] * s + d[1] * c, d[2]);
        let (lin, _) = cw.propagate(&dr, &dv, t).unwrap();
        errors.push((rel - lin).norm() / scale);
    }
    // The neglected terms are quadratic in the separation, of order n²t²|δr|²/a ≈ 2e−5 at
    // |δr| ≈ 2.3e−3, t = 2: a relative error of a few 1e−2 that falls tenfold with the separation.
    assert!(errors[0] < 5e-2, "{errors:?}");
    let ratio = errors[0] / errors[1];
    assert!((ratio - 10.0).abs() < 0.5, "{errors:?}: ratio {ratio}");
}

/// `V(q) = 1 − cos q` (the pendulum's potential, n = 1).
struct PendulumPotential;

impl ScalarField<1> for PendulumPotential {
    fn eval<D: DualNum<f64> + Copy>(&self, _t: D, x: &SVector<D, 1>) -> D {
        -x[0].cos() + 1.0
    }
}

/// `V(q) = −2 cos q₁ − cos q₂` (the double pendulum of T27).
struct DoublePendulumPotential;

impl ScalarField<2> for DoublePendulumPotential {
    fn eval<D: DualNum<f64> + Copy>(&self, _t: D, x: &SVector<D, 2>) -> D {
        -x[0].cos() * 2.0 - x[1].cos()
    }
}

#[test]
fn m37_lagrange_dirichlet_by_the_ad_hessian() {
    let at = |q: f64| dirichlet_check(&PendulumPotential, 0.0, &Vector1::new(q)).unwrap();
    let bottom = at(0.0);
    assert!(bottom.strict_minimum && (bottom.eigenvalues[0] - 1.0).abs() < 1e-15);
    let top = at(std::f64::consts::PI);
    assert!(!top.strict_minimum && (top.eigenvalues[0] + 1.0).abs() < 1e-15);
    assert!(dirichlet_check(&PendulumPotential, 0.0, &Vector1::new(0.3)).is_err());
    use std::f64::consts::PI;
    for (q, want) in [
        ([0.0, 0.0], true),
        ([PI, 0.0], false),
        ([0.0, PI], false),
        ([PI, PI], false),
    ] {
        let c = dirichlet_check(&DoublePendulumPotential, 0.0, &Vector2::from(q)).unwrap();
        assert_eq!(c.strict_minimum, want, "{q:?}: {:?}", c.eigenvalues);
    }
    let c = dirichlet_check(&DoublePendulumPotential, 0.0, &Vector2::zeros()).unwrap();
    assert!((c.eigenvalues - Vector2::new(1.0, 2.0)).amax() < 1e-15);
}

/// `V = ½(x² + v²) + ε x v`.
struct Quadratic {
    eps: f64,
}

impl ScalarField<2> for Quadratic {
    fn eval<D: DualNum<f64> + Copy>(&self, _t: D, z: &SVector<D, 2>) -> D {
        (z[0] * z[0] + z[1] * z[1]) * 0.5 + z[0] * z[1] * self.eps
    }
}

/// `ṙ = a − r, θ̇ = 1` in the state `(r, θ)` (T41).
struct Relaxing {
    a: f64,
}

impl VectorField<2> for Relaxing {
    fn field<D: DualNum<f64> + Copy>(&self, _t: D, z: &SVector<D, 2>) -> SVector<D, 2> {
        SVector::from([-z[0] + self.a, D::from(1.0)])
    }
}

/// `ẋ = −y r, ẏ = x r`, `r = |(x, y)|` (T41).
struct Circles;

impl VectorField<2> for Circles {
    fn field<D: DualNum<f64> + Copy>(&self, _t: D, z: &SVector<D, 2>) -> SVector<D, 2> {
        let r = (z[0] * z[0] + z[1] * z[1]).sqrt();
        SVector::from([-z[1] * r, z[0] * r])
    }
}

/// `V = (r − a)²` on `(r, θ)`, or `x² + y²` with `a = 0` on `(x, y)`, with an explicit time term
/// `β t` (to check `∂V/∂t`).
struct Distance {
    a: f64,
    beta: f64,
}

impl ScalarField<2> for Distance {
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, z: &SVector<D, 2>) -> D {
        let d = z[0] - self.a;
        if self.a == 0.0 {
            z[0] * z[0] + z[1] * z[1] + t * self.beta
        } else {
            d * d + t * self.beta
        }
    }
}

#[test]
fn m37_t41_lyapunov_derivatives_by_ad() {
    let mut rng = Lcg(3);
    for _ in 0..100 {
        let z = Vector2::new(rng.next() * 3.0, rng.next() * 3.0);
        let (x, v) = (z[0], z[1]);
        // Harmonic oscillator (c = 0): the energy is conserved, V̇ = 0 — stable, not
        // asymptotically.
        let vd = lyapunov_derivative(
            &Quadratic { eps: 0.0 },
            &DampedOscillator { c: 0.0 },
            0.0,
            &z,
        )
        .unwrap();
        assert!(vd.abs() < 1e-15 * z.norm_squared().max(1.0));
        // Damped oscillator: V̇ = −c v² ≤ 0 (only negative semi-definite).
        let c = 0.4;
        let vd =
            lyapunov_derivative(&Quadratic { eps: 0.0 }, &DampedOscillator { c }, 0.0, &z).unwrap();
        assert!((vd + c * v * v).abs() < 1e-15 * z.norm_squared().max(1.0));
        // With the cross term ε x v: V̇ = −(c − ε)v² − ε x² − ε c x v, negative definite for
        // small ε — asymptotic stability.
        let eps = 0.1;
        let vd = lyapunov_derivative(&Quadratic { eps }, &DampedOscillator { c }, 0.0, &z).unwrap();
        let want = -(c - eps) * v * v - eps * x * x - eps * c * x * v;
        assert!((vd - want).abs() < 1e-14 * z.norm_squared().max(1.0));
        assert!(vd < 0.0);
        // ṙ = a − r: V = (r − a)² has V̇ = −2(r − a)², the time term adds β.
        let (a, beta) = (2.0, 0.25);
        let vd = lyapunov_derivative(&Distance { a, beta }, &Relaxing { a }, 1.5, &z).unwrap();
        assert!((vd - (-2.0 * (x - a) * (x - a) + beta)).abs() < 1e-14 * (1.0 + x * x));
        // Circles at the rate r: the radius is conserved (V = x² + y², V̇ = 0) — orbitally stable.
        let vd = lyapunov_derivative(&Distance { a: 0.0, beta: 0.0 }, &Circles, 0.0, &z).unwrap();
        assert!(vd.abs() < 1e-14 * z.norm().powi(3).max(1.0));
    }
    // Hostile: non-finite point.
    assert!(lyapunov_derivative(
        &Quadratic { eps: 0.0 },
        &DampedOscillator { c: 0.0 },
        0.0,
        &Vector2::new(f64::NAN, 0.0)
    )
    .is_err());
}

/// The reduced variables `(r, θ, p_r, p_θ)` of the dumbbell, `ρ` cyclic and `p_ρ` held.
fn dumbbell_spectrum(
    d: &DumbbellSatellite,
    orientation: DumbbellOrientation,
) -> (hamilton_jacobi::stability::Spectrum, f64) {
    let (q, p, omega) = d.relative_equilibrium(1.0, orientation).unwrap();
    let reduced =
        Reduced::new(d, &q, &p, [Slot::Q(0), Slot::Q(2), Slot::P(0), Slot::P(2)]).unwrap();
    (
        steady_motion_spectrum(&reduced, 0.0, &reduced.state()).unwrap(),
        omega,
    )
}

#[test]
fn t40_dumbbell_relative_equilibria_radial_stable_tangential_unstable() {
    let d = DumbbellSatellite::new(1.0, 1.0, 0.1).unwrap();
    let omega = d.radial_rate(1.0).unwrap();
    assert!((omega - 1.01513895162837).abs() < 1e-14, "{omega}");
    // Uniform rotation: r and θ stay fixed over 20 s.
    let (q, p, _) = d
        .relative_equilibrium(1.0, DumbbellOrientation::Radial)
        .unwrap();
    let problem = Problem::new(&d, 0.0, q, p, 20.0).unwrap();
    let mut rec = Recorder::<3>::every(1);
    integrate(
        &problem,
        &Dop853::new(Dop853::RTOL_MIN, 1e-16).unwrap(),
        &mut rec,
    )
    .unwrap();
    for s in &rec.states {
        assert!(
            (s.q[0] - 1.0).abs() < 3e-14 && s.q[2].abs() < 3e-14,
            "{s:?}"
        );
        assert!((s.q[1] - omega * s.t).abs() < 1e-11 * s.t.max(1.0));
    }
    // With the Kepler rate ω = 1 instead the orbit is not circular: r deviates by 0.064.
    let problem = Problem::new(&d, 0.0, q, d.momenta(1.0, 1.0, 0.0, 0.0).unwrap(), 20.0).unwrap();
    let mut rec = Recorder::<3>::every(1);
    integrate(&problem, &Dop853::new(1e-13, 1e-13).unwrap(), &mut rec).unwrap();
    let dev = rec
        .states
        .iter()
        .map(|s| (s.q[0] - 1.0).abs())
        .fold(0.0, f64::max);
    assert!((dev - 0.064).abs() < 5e-4, "{dev}");
    // Radial: stable, the pitch oscillating at ≈ √3 ω (gravity gradient, z ≪ r₀: corrections
    // O(z²/r₀²) = 1 %), the radius at the epicyclic frequency ≈ ω.
    // Radial: stable; tangential: unstable in pitch (the gravity-gradient torque).
    let (sp, _) = dumbbell_spectrum(&d, DumbbellOrientation::Radial);
    assert_eq!(sp.stability, Stability::Stable, "{:?}", sp.eigenvalues);
    let (sp, _) = dumbbell_spectrum(&d, DumbbellOrientation::Tangential);
    assert_eq!(sp.stability, Stability::Unstable, "{:?}", sp.eigenvalues);
    // As z/r₀ → 0 the pitch no longer acts on the orbit (its reaction is O(z²)) while the orbit
    // drives the pitch: the linearisation becomes block triangular and its frequencies tend to
    // the orbit's epicyclic frequency ω (Kepler) and the pitch's √3 ω (radial) or rate √3 ω
    // (tangential), with O(z²/r₀²) corrections (coefficient ≈ 6 measured at z = 0.1).
    for z in [0.03, 0.01, 0.003] {
        let dz = DumbbellSatellite::new(1.0, 1.0, z).unwrap();
        let tol = 10.0 * z * z;
        let (sp, w) = dumbbell_spectrum(&dz, DumbbellOrientation::Radial);
        assert_eq!(sp.stability, Stability::Stable, "z = {z}");
        let mut f: Vec<f64> = sp.eigenvalues.iter().map(|l| l.im.abs() / w).collect();
        f.sort_by(f64::total_cmp);
        assert!(
            (f[0] - 1.0).abs() < tol && (f[3] - 3f64.sqrt()).abs() < tol,
            "z = {z}: {f:?}"
        );
        let (sp, w) = dumbbell_spectrum(&dz, DumbbellOrientation::Tangential);
        assert_eq!(sp.stability, Stability::Unstable, "z = {z}");
        let rate = sp.eigenvalues[0].re / w;
        assert!((rate - 3f64.sqrt()).abs() < tol, "z = {z}: {rate}");
    }
    // The tangential rate balances the attraction of the two masses at r₁ = r₂.
    let wt = d.tangential_rate(1.0).unwrap();
    assert!((wt - (1.0f64 / 1.01f64.powf(1.5)).sqrt()).abs() < 1e-15);
}

/// The square of the frequency of small nutation about steady precession of the heavy symmetric
/// top at `θ₀`, from the conserved momenta `μ = p_φ`, `ν = p_ψ` and the transverse moment
/// `A = I` (Lamb, *Encyclopaedia Britannica*, 11th ed. (1911), "Mechanics" §20, eqs. 8–9):
///
/// `σ² = [(μ − ν cos θ₀)² + 2(μ − ν cos θ₀)(μ cos θ₀ − ν) cos θ₀ + (μ cos θ₀ − ν)²] / (A² sin⁴θ₀)`.
fn lamb_nutation_squared(mu: f64, nu: f64, a: f64, theta0: f64) -> f64 {
    let (s, c) = theta0.sin_cos();
    let (x, y) = (mu - nu * c, mu * c - nu);
    (x * x + 2.0 * x * y * c + y * y) / (a * a * s.powi(4))
}

/// The heavy symmetric top's steady precession is a relative periodic orbit (issue 17 §2): `φ`
/// and `ψ` are cyclic, so the motion with `θ ≡ θ₀`, `φ̇ ≡ φ̇₀` returns after `T = 2π/|φ̇₀|` up to a
/// rotation about the figure axis, and it is an equilibrium of the Routh-reduced system
/// `(θ, p_θ)` with `p_φ`, `p_ψ` held. The monodromy over `T` has the multipliers `1` (four: the
/// flow, the energy and the two symmetries with their momenta) and `e^{±iσT}`, with `σ` the
/// frequency of small nutation — Lamb's closed form from the momenta, equal to the effective
/// potential's `√(U″(θ₀)/I)`, `σ² = (a − 2φ̇₀ cos θ₀)² + φ̇₀² sin²θ₀` with `a = Jω_z/I`; the
/// reduced linearisation has the eigenvalues `±iσ`. Cases: the slow and the fast precession of a
/// spinning top, and the conical pendulum (`ω_z = 0`, `σ = φ̇₀√(1 + 3 cos²θ₀)`).
#[test]
fn heavy_top_steady_precession_as_a_relative_periodic_orbit() {
    use hamilton_jacobi::stability::{steady_motion_spectrum, Reduced, Slot};
    use hamilton_jacobi::systems::HeavyTop;
    use std::f64::consts::{PI, TAU};
    let (i, j, mgl) = (1.0, 0.5, 1.0);
    let top = HeavyTop::new(i, j, mgl).unwrap();
    let method = Dop853::new(1e-13, 1e-13).unwrap();
    for (theta0, omega_z, fast) in [
        (PI / 3.0, 5.0, false),
        (PI / 3.0, 5.0, true),
        (1.2, 3.0, false),
        (2.0, 0.0, false),
    ] {
        let sp = top.steady_precession(theta0, omega_z).unwrap();
        let phi_dot = if fast { sp.fast.unwrap() } else { sp.slow };
        let q0 = Vector3::new(0.0, theta0, 0.0);
        let p0 = top
            .momenta_from_spin(theta0, 0.0, phi_dot, omega_z)
            .unwrap();
        let sigma2 = lamb_nutation_squared(p0[0], p0[2], i, theta0);
        let (s, c) = theta0.sin_cos();
        let a = j * omega_z / i;
        let sigma2_u = (a - 2.0 * phi_dot * c).powi(2) + (phi_dot * s).powi(2);
        assert!(
            (sigma2 - sigma2_u).abs() < 1e-13 * sigma2,
            "{sigma2} {sigma2_u}"
        );
        if omega_z == 0.0 {
            let conical = phi_dot * phi_dot * (1.0 + 3.0 * c * c);
            assert!((sigma2 - conical).abs() < 1e-13 * sigma2);
        }
        let sigma = sigma2.sqrt();
        // The Routh-reduced system (θ, p_θ): an equilibrium with the eigenvalues ±iσ.
        let reduced = Reduced::new(&top, &q0, &p0, [Slot::Q(1), Slot::P(1)]).unwrap();
        let spec = steady_motion_spectrum(&reduced, 0.0, &reduced.state()).unwrap();
        assert_eq!(spec.eigenvalues.len(), 2);
        for l in &spec.eigenvalues {
            assert!(
                l.re.abs() < 1e-12 * sigma && (l.im.abs() - sigma).abs() < 1e-12 * sigma,
                "θ₀ = {theta0}, φ̇₀ = {phi_dot}: {l} against ±i{sigma}"
            );
        }
        // The monodromy over one precession period.
        let period = TAU / phi_dot.abs();
        let m = monodromy::<_, 3, 21>(&top, 0.0, &q0, &p0, period, &method).unwrap();
        assert!(m.flow_defect < 1e-10, "{}", m.flow_defect);
        let expected = hamilton_jacobi::nalgebra::Complex::new(0.0, sigma * period).exp();
        // Four multipliers at 1 (two Jordan blocks: the shears of the period and of the
        // precession rate with the momenta, split by √‖δM‖ ≈ √(10⁻¹³ · 10²)), the pair
        // e^{±iσT}, simple, which must lie away from 1 for the comparison to be sharp.
        assert!((expected - 1.0).norm() > 0.1, "σT = {}", sigma * period);
        let mut by_distance = m.multipliers.clone();
        by_distance.sort_by(|x, y| (x - 1.0).norm().total_cmp(&(y - 1.0).norm()));
        for mu in &by_distance[..4] {
            assert!((mu - 1.0).norm() < 1e-4, "{mu}");
        }
        for mu in &by_distance[4..] {
            let target = if mu.im * expected.im >= 0.0 {
                expected
            } else {
                expected.conj()
            };
            assert!(
                (mu - target).norm() < 1e-9,
                "θ₀ = {theta0}, φ̇₀ = {phi_dot}: multiplier {mu} against e^(±iσT) = {target} \
                 (σ = {sigma}, T = {period})"
            );
            eprintln!(
                "θ₀ = {theta0:.4}, ω_z = {omega_z}, φ̇₀ = {phi_dot:.6}: σ = {sigma:.12}, T = \
                 {period:.6}, multiplier {mu:.12} vs {target:.12}: |Δ| = {:.2e}",
                (mu - target).norm()
            );
        }
    }
}

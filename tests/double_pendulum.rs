//! The double pendulum of two rods (SPEC M21, T27): Lagrange's equations by AD against the closed
//! form of [Ardema eqs. 7.17–7.26], the spectra of the four equilibria against the roots of their
//! characteristic quartic, the uniform-rod frequencies `ω² = (3 ± 6/√7) g/ℓ`, and the point-mass
//! case against the closed-form Hamiltonian and the T27 eigenvalues.

use hamilton_jacobi::nalgebra::{DMatrix, Matrix2, SVector, Vector2};
use hamilton_jacobi::stability::hamiltonian_linearization;
use hamilton_jacobi::systems::{DoublePendulum, Rod};
use hamilton_jacobi::{Error, Hamiltonian, Lagrangian, Natural};
use proptest::prelude::*;
use std::f64::consts::PI;

/// `(I₁′, I₂′, A, B, C)` computed from the rod data as in [Ardema eqs. 7.18–7.21].
struct Coefficients {
    i1: f64,
    i2: f64,
    a: f64,
    b: f64,
    c: f64,
}

fn coefficients(
    (m1, l1, lb1, ib1): (f64, f64, f64, f64),
    (m2, lb2, ib2): (f64, f64, f64),
    g: f64,
) -> Coefficients {
    Coefficients {
        i1: ib1 + m1 * lb1 * lb1 + m2 * l1 * l1,
        i2: ib2 + m2 * lb2 * lb2,
        a: m2 * l1 * lb2,
        b: (m1 * lb1 + m2 * l1) * g,
        c: m2 * g * lb2,
    }
}

/// `θ̈` from the closed-form equations of motion of SPEC M21 (no generalized forces).
fn closed_form_accelerations(k: &Coefficients, q: &Vector2<f64>, v: &Vector2<f64>) -> Vector2<f64> {
    let (s, c) = (q[1] - q[0]).sin_cos();
    let m = Matrix2::new(k.i1, k.a * c, k.a * c, k.i2);
    let rhs = Vector2::new(
        k.a * v[1] * v[1] * s - k.b * q[0].sin(),
        -k.a * v[0] * v[0] * s - k.c * q[1].sin(),
    );
    m.lu().solve(&rhs).unwrap()
}

/// The roots `λ²` of `(I₁′I₂′ − A²) λ⁴ + (B s₁ I₂′ + C s₂ I₁′) λ² + B C s₁ s₂ = 0`.
fn closed_form_lambda_squared(k: &Coefficients, s1: f64, s2: f64) -> [f64; 2] {
    let det = k.i1 * k.i2 - k.a * k.a;
    let mid = k.b * s1 * k.i2 + k.c * s2 * k.i1;
    let disc = (mid * mid - 4.0 * det * k.b * k.c * s1 * s2).sqrt();
    [(-mid + disc) / (2.0 * det), (-mid - disc) / (2.0 * det)]
}

/// The eigenvalues of `J∇²H` at the equilibrium `q` as `(|Re|, |Im|)` pairs sorted descending.
fn spectrum(h: &DoublePendulum, q: &SVector<f64, 2>) -> (Vec<f64>, Vec<f64>) {
    let a: DMatrix<f64> = hamiltonian_linearization(h, 0.0, q, &SVector::zeros()).unwrap();
    let ev = a.complex_eigenvalues();
    let mut re: Vec<f64> = ev.iter().map(|l| l.re.abs()).collect();
    let mut im: Vec<f64> = ev.iter().map(|l| l.im.abs()).collect();
    re.sort_by(|a, b| b.total_cmp(a));
    im.sort_by(|a, b| b.total_cmp(a));
    (re, im)
}

/// `(|Re|, |Im|)` of `λ = ±√(λ²)` for the two roots, sorted descending.
fn expected(l2: [f64; 2]) -> (Vec<f64>, Vec<f64>) {
    let mut re = Vec::new();
    let mut im = Vec::new();
    for r in l2 {
        let (x, y) = if r >= 0.0 {
            (r.sqrt(), 0.0)
        } else {
            (0.0, (-r).sqrt())
        };
        re.extend([x, x]);
        im.extend([y, y]);
    }
    re.sort_by(|a, b| b.total_cmp(a));
    im.sort_by(|a, b| b.total_cmp(a));
    (re, im)
}

fn assert_spectrum(h: &DoublePendulum, k: &Coefficients, tol: f64) {
    for q in DoublePendulum::equilibria() {
        let (s1, s2) = (q[0].cos().round(), q[1].cos().round());
        let (re, im) = spectrum(h, &q);
        let (want_re, want_im) = expected(closed_form_lambda_squared(k, s1, s2));
        let scale = want_re
            .iter()
            .chain(&want_im)
            .fold(0.0f64, |m, x| m.max(*x));
        for i in 0..4 {
            assert!(
                (re[i] - want_re[i]).abs() <= tol * scale
                    && (im[i] - want_im[i]).abs() <= tol * scale,
                "at {q:?}: re {re:?} im {im:?}, closed form re {want_re:?} im {want_im:?}"
            );
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Lagrange's equations by AD of `L = T − V` against the closed-form equations of M21, at
    /// random rods and states.
    #[test]
    fn m21_equations_of_motion_from_ad_match_closed_form(
        m1 in 0.1f64..5.0, m2 in 0.1f64..5.0, l1 in 0.2f64..3.0, f1 in 0.0f64..1.5,
        f2 in 0.05f64..1.5, j1 in 0.0f64..2.0, j2 in 0.0f64..2.0, g in 0.5f64..20.0,
        th1 in -PI..PI, th2 in -PI..PI, w1 in -5.0f64..5.0, w2 in -5.0f64..5.0,
        l2 in 0.2f64..3.0,
    ) {
        let (lb1, lb2) = (f1 * l1, f2 * l2);
        let rod1 = Rod::new(m1, l1, lb1, j1).unwrap();
        let rod2 = Rod::new(m2, l2, lb2, j2).unwrap();
        let dp = DoublePendulum::rods(rod1, rod2, g).unwrap();
        let k = coefficients((m1, l1, lb1, j1), (m2, lb2, j2), g);
        let (q, v) = (Vector2::new(th1, th2), Vector2::new(w1, w2));
        let ad = Natural(dp).accelerations(0.0, &q, &v).unwrap();
        let want = closed_form_accelerations(&k, &q, &v);
        let scale = want.amax().max(k.b / k.i1).max(1.0);
        prop_assert!((ad - want).amax() <= 1e-12 * scale, "AD {ad:?}, closed form {want:?}");
        // The Hamiltonian is the Legendre transform of the same L: H(q, ∂L/∂q̇) = T + V.
        let p = Natural(dp).momentum(0.0, &q, &v).unwrap();
        let c = (q[1] - q[0]).cos();
        let t = 0.5 * k.i1 * w1 * w1 + 0.5 * k.i2 * w2 * w2 + k.a * w1 * w2 * c;
        let energy = t - k.b * th1.cos() - k.c * th2.cos();
        let h = dp.value(0.0, &q, &p).unwrap();
        prop_assert!((h - energy).abs() <= 1e-12 * (t + k.b + k.c), "H {h}, T + V {energy}");
    }

    /// Point masses: the Hamiltonian equals the closed form of Landau & Lifshitz §5 Prob. 1.
    #[test]
    fn point_mass_hamiltonian_is_the_closed_form(
        m1 in 0.1f64..5.0, m2 in 0.1f64..5.0, l1 in 0.2f64..3.0, l2 in 0.2f64..3.0,
        g in 0.5f64..20.0, q1 in -PI..PI, q2 in -PI..PI, p1 in -5.0f64..5.0, p2 in -5.0f64..5.0,
    ) {
        let dp = DoublePendulum::new(m1, m2, l1, l2, g).unwrap();
        let (s, c) = (q1 - q2).sin_cos();
        let want = (m2 * l2 * l2 * p1 * p1 + (m1 + m2) * l1 * l1 * p2 * p2
            - 2.0 * m2 * l1 * l2 * c * p1 * p2)
            / (2.0 * m2 * l1 * l1 * l2 * l2 * (m1 + m2 * s * s))
            - (m1 + m2) * g * l1 * q1.cos()
            - m2 * g * l2 * q2.cos();
        let h = dp.value(0.0, &Vector2::new(q1, q2), &Vector2::new(p1, p2)).unwrap();
        prop_assert!((h - want).abs() <= 1e-12 * want.abs().max(g * (m1 + m2) * (l1 + l2)),
            "H {h}, closed form {want}");
    }
}

/// T27 for rods: the spectra at the four equilibria against the roots of the characteristic
/// quartic, for rods with both an offset mass centre and a central moment.
#[test]
fn t27_rod_equilibria_spectra_match_the_characteristic_quartic() {
    let rods = [
        (
            (1.0, 1.0, 0.5, 1.0 / 12.0),
            (1.0, 1.0, 0.5, 1.0 / 12.0),
            9.81,
        ),
        ((2.0, 0.7, 0.2, 0.3), (0.5, 1.3, 0.9, 0.05), 1.0),
        ((0.3, 2.0, 1.5, 0.0), (4.0, 0.4, 0.1, 0.2), 3.0),
    ];
    for ((m1, l1, lb1, j1), (m2, l2, lb2, j2), g) in rods {
        let dp = DoublePendulum::rods(
            Rod::new(m1, l1, lb1, j1).unwrap(),
            Rod::new(m2, l2, lb2, j2).unwrap(),
            g,
        )
        .unwrap();
        assert_spectrum(
            &dp,
            &coefficients((m1, l1, lb1, j1), (m2, lb2, j2), g),
            1e-12,
        );
    }
}

/// Two equal uniform rods: the normal-mode frequencies `ω² = (3 ± 6/√7) g/ℓ`.
#[test]
fn uniform_rods_normal_modes() {
    let (m, l, g) = (1.7, 0.8, 9.81);
    let dp =
        DoublePendulum::rods(Rod::uniform(m, l).unwrap(), Rod::uniform(m, l).unwrap(), g).unwrap();
    let (_, im) = spectrum(&dp, &SVector::zeros());
    let want = [
        ((3.0 + 6.0 / 7f64.sqrt()) * g / l).sqrt(),
        ((3.0 - 6.0 / 7f64.sqrt()) * g / l).sqrt(),
    ];
    for (i, w) in [want[0], want[0], want[1], want[1]].iter().enumerate() {
        assert!((im[i] - w).abs() < 1e-12 * want[0], "{im:?} vs {want:?}");
    }
}

/// The point-mass limit `Ī = 0`, `ℓ̄ = ℓ` of the rods is the point-mass pendulum, and its spectra
/// are those of T27: `±i√(2 ± √2)`, `λ² = ±√2`, `±√(2 ± √2)`.
#[test]
fn point_mass_limit_reproduces_t27() {
    let rods = DoublePendulum::rods(
        Rod::new(1.0, 1.0, 1.0, 0.0).unwrap(),
        Rod::new(1.0, 1.0, 1.0, 0.0).unwrap(),
        1.0,
    )
    .unwrap();
    let points = DoublePendulum::new(1.0, 1.0, 1.0, 1.0, 1.0).unwrap();
    assert_eq!(rods, points);
    let s2 = 2f64.sqrt();
    let (fast, slow, quartic) = ((2.0 + s2).sqrt(), (2.0 - s2).sqrt(), s2.sqrt());
    let want = [
        ([0.0, 0.0, 0.0, 0.0], [fast, fast, slow, slow]),
        ([quartic, quartic, 0.0, 0.0], [quartic, quartic, 0.0, 0.0]),
        ([quartic, quartic, 0.0, 0.0], [quartic, quartic, 0.0, 0.0]),
        ([fast, fast, slow, slow], [0.0, 0.0, 0.0, 0.0]),
    ];
    for (q, (wr, wi)) in DoublePendulum::equilibria().iter().zip(want) {
        let (re, im) = spectrum(&points, q);
        for i in 0..4 {
            assert!((re[i] - wr[i]).abs() < 1e-12, "{q:?}: {re:?}");
            assert!((im[i] - wi[i]).abs() < 1e-12, "{q:?}: {im:?}");
        }
    }
}

/// Typed errors for rods outside their domain and for a singular mass matrix.
#[test]
fn bad_rods_are_rejected() {
    assert!(matches!(
        Rod::new(-1.0, 1.0, 0.5, 0.1),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        Rod::new(1.0, 1.0, -0.5, 0.1),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        Rod::new(1.0, f64::NAN, 0.5, 0.1),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        Rod::uniform(f64::INFINITY, 1.0),
        Err(Error::NonFinite { .. })
    ));
    // Rod 2 with its mass centre on the hinge and no moment: I₂′ = 0.
    let r1 = Rod::uniform(1.0, 1.0).unwrap();
    let r2 = Rod::new(1.0, 1.0, 0.0, 0.0).unwrap();
    assert!(matches!(
        DoublePendulum::rods(r1, r2, 1.0),
        Err(Error::OutOfDomain { .. })
    ));
    // Rod 1 without moment about A and Ī₂ = 0: det = 0.
    let r1 = Rod::new(1.0, 1.0, 0.0, 0.0).unwrap();
    let r2 = Rod::point_mass(1.0, 1.0).unwrap();
    assert!(matches!(
        DoublePendulum::rods(r1, r2, 1.0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        DoublePendulum::rods(r2, r2, -1.0),
        Err(Error::OutOfDomain { .. })
    ));
    let huge = Rod::point_mass(1e300, 1e300).unwrap();
    assert!(DoublePendulum::rods(huge, huge, 1.0).is_err());
}

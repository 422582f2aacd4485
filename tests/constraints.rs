//! Constraints: classification, the single-form test (SPEC M3, T38), integrable combinations of
//! sets of forms (M3–M4: T18's cart has exactly one, the rolling disk of M70 none) and rank-deficient
//! constraint matrices (X7).

use hamilton_jacobi::constraints::{
    check_rank, classify, form_integrability_residuals, hamel_coefficients,
    integrable_combinations, Differentiated, HolonomicConstraints, PfaffianConstraints,
};
use hamilton_jacobi::nalgebra::{SMatrix, SVector};
use hamilton_jacobi::systems::{ChaplyginSleigh, RollingDisk, TwoWheeledCart};
use hamilton_jacobi::{DualNum, Error};

fn cart() -> TwoWheeledCart {
    TwoWheeledCart::new(3.0, 0.8, 0.05, 0.8, 0.3, 0.2).unwrap()
}

/// The forms of T38 written over dual numbers.
#[derive(Clone, Copy)]
enum T38 {
    /// `dy − z dx`.
    Contact,
    /// `sin θ dx − cos θ dy`.
    KnifeEdge,
    /// `dx − r dθ` (a disk rolling on a line), in `(x, θ)`.
    Line(f64),
}

impl PfaffianConstraints<3, 1> for T38 {
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        y: &SVector<D, 3>,
    ) -> (SMatrix<D, 1, 3>, SVector<D, 1>) {
        let (z, o) = (D::zero(), D::one());
        let row = match *self {
            T38::Contact => [-y[2], o, z],
            T38::KnifeEdge => [y[2].sin(), -y[2].cos(), z],
            T38::Line(r) => [o, D::from(-r), z],
        };
        (SMatrix::from_row_slice(&row), SVector::from([z]))
    }
}

#[test]
fn t38_single_form_tests() {
    let y = SVector::from([0.3, -0.7, 1.1]);
    // Residual of the triple (0, 1, 2) is −A·curl A: +1 for the contact form and the knife edge.
    for (form, want) in [
        (T38::Contact, 1.0),
        (T38::KnifeEdge, 1.0),
        (T38::Line(0.4), 0.0),
    ] {
        let r = form_integrability_residuals(&form, 0, 0.0, &y).unwrap();
        let main = r.iter().find(|(k, _)| *k == (0, 1, 2)).unwrap().1;
        assert!((main - want).abs() < 1e-15, "{main} vs {want}");
        // Triples with time vanish: nothing depends on t and there is no dt term.
        for (k, v) in &r {
            if k.2 == 3 {
                assert_eq!(*v, 0.0);
            }
        }
    }
    // The set test agrees: one integrable combination for the disk on a line, none otherwise.
    let line = integrable_combinations(&T38::Line(0.4), 0.0, &y).unwrap();
    assert_eq!(line.count(), 1);
    let f = &line.forms[0];
    assert!((f[0] - 1.0).abs() < 1e-14 && (f[1] + 0.4).abs() < 1e-14 && f[2].abs() < 1e-14);
    assert_eq!(
        integrable_combinations(&T38::Contact, 0.0, &y)
            .unwrap()
            .count(),
        0
    );
    // The blade: non-holonomic with only three coordinates.
    let blade = ChaplyginSleigh::new(2.0, 0.5, 1.0).unwrap();
    assert_eq!(integrable_combinations(&blade, 0.0, &y).unwrap().count(), 0);
}

#[test]
fn t18_cart_has_exactly_one_integrable_combination() {
    let cart = cart();
    for q in [
        SVector::from([0.1, -0.3, 0.7, 1.2, -0.4]),
        SVector::from([2.0, 1.0, -2.5, 0.0, 3.0]),
    ] {
        let res = integrable_combinations(&cart, 0.3, &q).unwrap();
        assert_eq!(res.count(), 1, "{res:?}");
        assert_eq!(res.closure_dimension, 5);
        assert_eq!(res.variables, 6);
        // 2b dθ + r (dφ_l − dφ_r), scaled to a largest coefficient 1 (2b = 0.6 > r = 0.2).
        let want = [0.0, 0.0, 1.0, 0.2 / 0.6, -0.2 / 0.6, 0.0];
        for (g, w) in res.forms[0].iter().zip(want) {
            assert!((g - w).abs() < 1e-12, "{:?}", res.forms[0]);
        }
        // As a combination of the rows: row 2 − row 3 (up to the scale).
        let c = &res.combinations[0];
        assert!(c[0].abs() < 1e-12 && (c[1] + c[2]).abs() < 1e-12 && c[1].abs() > 0.1);
        // Each of the three forms alone fails the single-form test.
        for row in 0..3 {
            let r = form_integrability_residuals(&cart, row, 0.3, &q).unwrap();
            let worst = r.iter().map(|(_, v)| v.abs()).fold(0.0, f64::max);
            assert!(worst > 0.1, "row {row}: {worst}");
        }
    }
    let class = classify(&cart, &[(0.0, SVector::from([0.1, -0.3, 0.7, 1.2, -0.4]))]).unwrap();
    assert!(class.catastatic && class.scleronomic && !class.holonomic);
    assert_eq!(
        (
            class.integrable,
            class.degrees_of_freedom,
            class.coordinates
        ),
        (1, 2, 4)
    );
}

#[test]
fn m70_rolling_disk_has_no_integrable_combination() {
    let disk = RollingDisk::disk(1.0, 1.0, 9.81).unwrap();
    let q = SVector::from([0.2, 0.1, 0.9, 0.05, 0.3]);
    let res = integrable_combinations(&disk, 0.0, &q).unwrap();
    assert_eq!(res.count(), 0);
    assert_eq!(res.closure_dimension, 6);
    assert_eq!(res.depth, 2);
}

/// A pendulum of variable length `ℓ(t) = 1 + t/2` as a holonomic constraint on `(x, y)`.
struct VariableLength;

impl HolonomicConstraints<2, 1> for VariableLength {
    fn position_constraint<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 2>,
    ) -> SVector<D, 1> {
        let l = t * 0.5 + 1.0;
        SVector::from([q[0] * q[0] + q[1] * q[1] - l * l])
    }
}

#[test]
fn holonomic_constraints_by_ad_are_integrable_and_rheonomic() {
    let c = Differentiated(VariableLength);
    let (t, q) = (0.4, SVector::from([0.6, -0.9]));
    let (b, b0) = c.forms(t, &q);
    assert!((b[(0, 0)] - 1.2).abs() < 1e-15 && (b[(0, 1)] + 1.8).abs() < 1e-15);
    assert!((b0[0] + 1.2).abs() < 1e-15); // −2ℓ ℓ̇ = −2·1.2·0.5
    let class = classify(&c, &[(t, q)]).unwrap();
    assert!(class.holonomic && !class.catastatic && !class.scleronomic);
    assert_eq!((class.degrees_of_freedom, class.coordinates), (1, 1));
}

/// The cart's constraints with the second row repeated (scaled): rank deficient (SPEC X7).
struct Repeated(TwoWheeledCart);

impl PfaffianConstraints<5, 4> for Repeated {
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 5>,
    ) -> (SMatrix<D, 4, 5>, SVector<D, 4>) {
        let (b, _) = self.0.forms(t, q);
        let m = SMatrix::from_fn(|r, s| if r < 3 { b[(r, s)] } else { b[(1, s)] * 2.0 });
        (m, SVector::zeros())
    }
}

#[test]
fn x7_rank_deficient_constraints_name_the_dependent_rows() {
    let q = SVector::from([0.1, -0.3, 0.7, 1.2, -0.4]);
    let err = integrable_combinations(&Repeated(cart()), 0.25, &q).unwrap_err();
    match &err {
        Error::RankDeficient { rows, t, at, .. } => {
            assert_eq!(rows, &vec![3]);
            assert_eq!(*t, 0.25);
            assert!(at.contains("0.7"), "{at}");
        }
        e => panic!("{e:?}"),
    }
    let (b, _) = Repeated(cart()).forms(0.25, &q);
    let err = check_rank(&b, "∂g/∂q̇", 0.25, || format!("q = {q:?}")).unwrap_err();
    assert!(matches!(err, Error::RankDeficient { ref rows, .. } if rows == &vec![3]));
    assert!(err.to_string().contains("rows [3]"), "{err}");
}

#[test]
fn m64_hamel_coefficients_of_the_blade_and_the_cart() {
    // Blade: β₁^{23} = +1 = −β₁^{32}, β₂^{31} = +1 = −β₂^{13} (SPEC M65 check; 0-based indices).
    let blade = ChaplyginSleigh::new(2.0, 0.5, 1.0).unwrap();
    let h = hamel_coefficients(&blade, &SVector::from([0.3, -0.2, 0.77])).unwrap();
    let b = &h.beta;
    assert!((b[0][(1, 2)] - 1.0).abs() < 1e-15 && (b[0][(2, 1)] + 1.0).abs() < 1e-15);
    assert!((b[1][(2, 0)] - 1.0).abs() < 1e-15 && (b[1][(0, 2)] + 1.0).abs() < 1e-15);
    for bm in b.iter() {
        assert!((bm + bm.transpose()).amax() < 1e-15);
    }
    assert!(b[2].amax() == 0.0); // ϑ₃ = θ is a true coordinate
}

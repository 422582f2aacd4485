//! Systems defined by expressions: the Hénon–Heiles scene by expression agrees with the
//! Rust-written `systems::HenonHeiles` to rounding (vector field, Verlet and DOP853 runs, the
//! Poincaré section); Kepler + J₂ in Cartesian form by expression agrees with the crate's
//! `PerturbedTwoBody<J2>` (3 degrees of freedom, and two satellites as 6); parse errors carry
//! their column; unknown names list the known ones; non-finite initial states are refused;
//! random strings never panic and random expression trees evaluate as a direct `f64` evaluation
//! of the same tree.
#![cfg(feature = "cli")]

mod common;
use common::quick;

use hamilton_jacobi::expression::parse::{self, MAX_DEPTH, MAX_LENGTH};
use hamilton_jacobi::expression::{
    Expression, ExpressionHamiltonian, ExpressionLagrangian, ExpressionSeparable,
};
use hamilton_jacobi::integrate::{integrate, Crossing, Dop853, Fixed, Problem, Section, Splitting};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{PerturbedTwoBody, J2};
use hamilton_jacobi::scene::{self, Catalogue};
use hamilton_jacobi::systems::HenonHeiles;
use hamilton_jacobi::{Error, Hamiltonian, Lagrangian, Separable, State};
use proptest::prelude::*;

const HH: &str = "(p_x^2 + p_y^2)/2 + (x^2 + y^2)/2 + x^2*y - y^3/3";

fn henon_heiles() -> ExpressionHamiltonian<2> {
    ExpressionHamiltonian::<2>::new(HH, &["x", "y"], None, &[]).unwrap()
}

/// `|a − b| ≤ k ε s` componentwise, `s` the scale of the terms.
fn close(a: &[f64], b: &[f64], k: f64, s: f64) -> bool {
    a.iter()
        .zip(b)
        .all(|(x, y)| (x - y).abs() <= k * f64::EPSILON * s)
}

/// Deterministic points of a box (a linear congruential sequence).
fn points(n: usize, half_width: f64) -> Vec<[f64; 4]> {
    let mut s: u64 = 0x2545_f491_4f6c_dd1d;
    let mut next = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        ((s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * half_width
    };
    (0..n).map(|_| [next(), next(), next(), next()]).collect()
}

/// The vector field of the expression (general and split forms) agrees with the Rust-written
/// system to a few rounding errors: the same operations in a possibly different order, each
/// component a sum of at most four terms of size ≤ `s = 1 + |z|³`, so `|Δ| ≤ 8 ε s`.
#[test]
fn henon_heiles_vector_field_agrees_to_rounding() {
    let e = henon_heiles();
    let sep = e.separable().expect("H = T(p) + V(q)");
    for z in points(200, 0.8) {
        let (q, p) = (SVector::from([z[0], z[1]]), SVector::from([z[2], z[3]]));
        let (a_q, a_p) = HenonHeiles.vector_field(0.0, &q, &p).unwrap();
        let s = 1.0 + (q.norm_squared() + p.norm_squared()).powf(1.5);
        for (b_q, b_p) in [
            e.vector_field(0.0, &q, &p).unwrap(),
            sep.vector_field(0.0, &q, &p).unwrap(),
        ] {
            assert!(close(a_q.as_slice(), b_q.as_slice(), 8.0, s), "{z:?}");
            assert!(close(a_p.as_slice(), b_p.as_slice(), 8.0, s), "{z:?}");
        }
        let h = HenonHeiles.value(0.0, &q, &p).unwrap();
        assert!((e.value(0.0, &q, &p).unwrap() - h).abs() <= 8.0 * f64::EPSILON * s);
        // Second derivatives by AD through the record.
        let (ha, hb) = (
            HenonHeiles.hessian(0.0, &q, &p).unwrap(),
            e.hessian(0.0, &q, &p).unwrap(),
        );
        for (a, b) in [
            (ha.qq, hb.qq),
            (ha.qp, hb.qp),
            (ha.pq, hb.pq),
            (ha.pp, hb.pp),
        ] {
            assert!(close(a.as_slice(), b.as_slice(), 8.0, s), "{z:?}");
        }
    }
}

fn start() -> State<2> {
    HenonHeiles::section_start(1.0 / 12.0, 0.1, 0.0).unwrap()
}

/// Verlet over 2000 steps to t = 200 on a regular orbit of E = 1/12: the two systems differ by
/// rounding per step (≲ 8ε), carried along a regular orbit with at most linear growth in the
/// number of steps and in time: `|Δz| ≤ 8ε · 2000 · 200 ≈ 3.6·10⁻¹⁰`.
#[test]
fn henon_heiles_verlet_and_dop853_runs_agree() {
    let z0 = start();
    let sep = henon_heiles().separable().unwrap();
    let a = Problem::new(&HenonHeiles, 0.0, z0.q, z0.p, 200.0).unwrap();
    let b = Problem::new(&sep, 0.0, z0.q, z0.p, 200.0).unwrap();
    let verlet = Fixed::new(Splitting::VERLET_KDK, 2000).unwrap();
    let ra = integrate(&a, &verlet, &mut ()).unwrap().last;
    let rb = integrate(&b, &verlet, &mut ()).unwrap().last;
    let bound = 8.0 * f64::EPSILON * 2000.0 * 200.0;
    assert!((ra.q - rb.q).norm() <= bound, "{}", (ra.q - rb.q).norm());
    assert!((ra.p - rb.p).norm() <= bound, "{}", (ra.p - rb.p).norm());
    // DOP853: the same bound (the step sequences agree while the error estimates, equal to
    // rounding, decide the same way).
    let dop = Dop853::new(1e-10, 1e-12).unwrap();
    let general = henon_heiles();
    let c = Problem::new(&general, 0.0, z0.q, z0.p, 200.0).unwrap();
    let ra = integrate(&a, &dop, &mut ()).unwrap();
    for r in [
        integrate(&b, &dop, &mut ()).unwrap(),
        integrate(&c, &dop, &mut ()).unwrap(),
    ] {
        assert_eq!(ra.work.steps, r.work.steps);
        assert!((ra.last.q - r.last.q).norm() <= bound);
        assert!((ra.last.p - r.last.p).norm() <= bound);
    }
}

/// The Poincaré section x = 0 (upward) by DOP853's dense output: the first 20 crossings of the
/// two systems agree to the bound of the runs, and lie on the energy surface to the tolerance.
#[test]
fn henon_heiles_poincare_sections_agree() {
    let z0 = start();
    let general = henon_heiles();
    let a = Problem::new(&HenonHeiles, 0.0, z0.q, z0.p, 1e4).unwrap();
    let b = Problem::new(&general, 0.0, z0.q, z0.p, 1e4).unwrap();
    let dop = Dop853::new(1e-11, 1e-13).unwrap();
    let mut sa = Section::new(|_t, q: &SVector<f64, 2>, _p| q[0], Crossing::Up).stop_after(20);
    let mut sb = Section::new(|_t, q: &SVector<f64, 2>, _p| q[0], Crossing::Up).stop_after(20);
    integrate(&a, &dop, &mut sa).unwrap();
    integrate(&b, &dop, &mut sb).unwrap();
    assert_eq!(sa.points.len(), 20);
    assert_eq!(sb.points.len(), 20);
    let bound = 8.0 * f64::EPSILON * 2000.0 * 200.0;
    for (x, y) in sa.points.iter().zip(&sb.points) {
        assert!((x.t - y.t).abs() <= bound);
        assert!((x.q - y.q).norm() <= bound && (x.p - y.p).norm() <= bound);
        let e = general.value(y.t, &y.q, &y.p).unwrap();
        assert!((e - 1.0 / 12.0).abs() < 1e-9, "{e}");
    }
}

/// The built-in scene defining Hénon–Heiles by expression runs with Verlet and DOP853 (its
/// splitting methods apply: the expression is split into `T(p) + V(q)`), and its errors against
/// the DOP853 reference fall with the step as they should.
#[test]
fn henon_heiles_scene_by_expression_runs() {
    let catalogue = Catalogue::builtin();
    let text = scene::builtin_text("henon-heiles-expression").unwrap();
    let s = scene::parse("henon-heiles-expression", text, &catalogue).unwrap();
    let out = std::env::temp_dir().join(format!("hj-expression-{}", std::process::id()));
    let summary = s.run(&quick(&out)).unwrap();
    assert!(
        summary.markdown.contains("Störmer–Verlet"),
        "{}",
        summary.markdown
    );
    assert!(
        summary.markdown.contains("Dormand–Prince"),
        "{}",
        summary.markdown
    );
    assert!(
        !summary.markdown.contains("- method["),
        "{}",
        summary.markdown
    );
    std::fs::remove_dir_all(&out).ok();
    // The same system as a table: the case's energy is the Rust system's.
    let table: toml::Table = toml::from_str(text).unwrap();
    let case = catalogue
        .build("s.toml", table["system"].as_table().unwrap())
        .unwrap();
    let z0 = start();
    let e = case.energy(0.0, z0.q.as_slice(), z0.p.as_slice()).unwrap();
    assert!((e - 1.0 / 12.0).abs() < 1e-15, "{e}");
}

const J2_3: &str = "(p_x^2 + p_y^2 + p_z^2)/2 - mu/sqrt(x^2 + y^2 + z^2) \
    + mu*J2*R^2/2 * (3*z^2/(x^2 + y^2 + z^2) - 1)/sqrt(x^2 + y^2 + z^2)^3";

fn j2_params() -> [(&'static str, f64); 3] {
    [("mu", 1.0), ("J2", 1.08e-3), ("R", 0.9)]
}

/// Kepler + J₂ in Cartesian form by expression: the vector field agrees with the crate's
/// `PerturbedTwoBody<J2>` to rounding at points of the shell `0.9 ≤ r ≤ 1.5` (terms of size
/// ≲ μ/r² ≤ 1.3, a few dozen operations: `|Δ| ≤ 32 ε`); with two satellites as six degrees of
/// freedom (dispatched at run time), each half agrees.
#[test]
fn kepler_j2_by_expression_agrees_with_the_rust_system() {
    let rust = PerturbedTwoBody::conservative(1.0, J2::new(1.0, 1.08e-3, 0.9).unwrap()).unwrap();
    let e = ExpressionHamiltonian::<3>::new(J2_3, &["x", "y", "z"], None, &j2_params()).unwrap();
    let two = J2_3.to_string()
        + " + "
        + &J2_3
            .replace("p_x", "p_u")
            .replace("p_y", "p_v")
            .replace("p_z", "p_w")
            .replace('x', "u")
            .replace('y', "v")
            .replace('z', "w");
    let e6 =
        ExpressionHamiltonian::<6>::new(&two, &["x", "y", "z", "u", "v", "w"], None, &j2_params())
            .unwrap();
    for (k, z) in points(100, 1.0).into_iter().enumerate() {
        let w = points(k + 1, 1.0)[k];
        let q = SVector::from([0.9 + 0.3 * (z[0] + 1.0), z[1] * 0.3, z[2] * 0.3]);
        let p = SVector::from([z[3], w[0], w[1]]);
        let (a_q, a_p) = rust.vector_field(0.0, &q, &p).unwrap();
        let (b_q, b_p) = e.vector_field(0.0, &q, &p).unwrap();
        assert!(close(a_q.as_slice(), b_q.as_slice(), 32.0, 1.0), "{z:?}");
        assert!(
            close(a_p.as_slice(), b_p.as_slice(), 32.0, 1.0),
            "{z:?} {a_p} {b_p}"
        );
        let q6 = SVector::from([q[0], q[1], q[2], q[1], q[0], q[2]]);
        let p6 = SVector::from([p[0], p[1], p[2], p[2], p[1], p[0]]);
        let (c_q, c_p) = e6.vector_field(0.0, &q6, &p6).unwrap();
        let (d_q, d_p) = rust
            .vector_field(
                0.0,
                &SVector::from([q[1], q[0], q[2]]),
                &SVector::from([p[2], p[1], p[0]]),
            )
            .unwrap();
        let want_q: Vec<f64> = a_q.iter().chain(d_q.iter()).copied().collect();
        let want_p: Vec<f64> = a_p.iter().chain(d_p.iter()).copied().collect();
        assert!(close(&want_q, c_q.as_slice(), 32.0, 1.0));
        assert!(close(&want_p, c_p.as_slice(), 32.0, 1.0));
    }
    // Not separable as written? It is: every term depends on p or on q only.
    assert!(e.separable().is_some());
}

/// The column of a parse error, and the caret under it.
#[test]
fn parse_errors_point_at_the_column() {
    let cases: [(&str, usize); 8] = [
        ("p^2 + * q", 7),
        ("p^2/2 - cos(q", 14),
        ("p^2/2 - cos q", 9),
        ("p^2 $ q", 5),
        ("2 q", 3),
        ("sin(q, p)", 1),
        ("(p + q))", 8),
        ("1e999 * q", 1),
    ];
    for (text, column) in cases {
        let e = Expression::new(text, &["q", "p"], &[]).unwrap_err();
        let Error::Parse { column: c, .. } = &e else {
            panic!("{text}: {e:?}")
        };
        assert_eq!(*c, column, "{text}: {e}");
        let shown = e.to_string();
        let lines: Vec<&str> = shown.lines().collect();
        assert_eq!(lines.len(), 3, "{shown}");
        assert_eq!(lines[2].find('^'), Some(1 + column), "{shown}");
    }
    // Columns count characters, not bytes.
    let e = Expression::new("θ̇ + ω*", &["ω"], &[]).unwrap_err();
    assert!(matches!(e, Error::Parse { .. }));
    let e = Expression::new("ω + ω*", &["ω"], &[]).unwrap_err();
    assert!(matches!(e, Error::Parse { column: 7, .. }), "{e:?}");
}

/// An unknown name is refused at its column with every known name and function listed.
#[test]
fn unknown_names_list_the_known_ones() {
    let e = ExpressionHamiltonian::<1>::new("p_q^2/2 - k*cos(qq)", &["q"], None, &[("k", 1.0)])
        .unwrap_err();
    let Error::Parse { column, reason, .. } = &e else {
        panic!("{e:?}")
    };
    assert_eq!(*column, 17);
    for known in ["`t`", "`q`", "`p_q`", "`k`", "`pi`", "`sin`", "`atan2`"] {
        assert!(reason.contains(known), "{reason}");
    }
    let e = Expression::new("cosh(x) + frob(x)", &["x"], &[]).unwrap_err();
    assert!(matches!(&e, Error::Parse { column: 11, reason, .. } if reason.contains("`sqrt`")));
    // A scene reports it at the key, with the column.
    let text = "[system]\nhamiltonian = \"p_q^2/2 - cos(qq)\"\ncoordinates = [\"q\"]\nq = [0.1]\np = [0.0]\n[span]\ntime = 1\n[[method]]\nkind = \"rk4\"\nsteps = [10]\n";
    let e = scene::parse("s.toml", text, &Catalogue::builtin())
        .err()
        .unwrap();
    assert_eq!(e.key, "system.hamiltonian");
    assert!(
        e.message.contains("column 15") && e.message.contains("`p_q`"),
        "{e}"
    );
}

/// Input beyond the stated bounds is refused before recursing.
#[test]
fn length_and_depth_are_bounded() {
    let deep = "(".repeat(MAX_DEPTH + 1) + "x" + &")".repeat(MAX_DEPTH + 1);
    assert!(matches!(
        parse::parse(&deep, &["x"]),
        Err(Error::Parse { .. })
    ));
    let ok = "(".repeat(MAX_DEPTH - 1) + "x" + &")".repeat(MAX_DEPTH - 1);
    assert!(parse::parse(&ok, &["x"]).is_ok());
    let huge = "(".repeat(1_000_000);
    assert!(matches!(
        parse::parse(&huge, &["x"]),
        Err(Error::Parse { .. })
    ));
    let signs = "-".repeat(MAX_LENGTH - 1) + "x";
    assert!(matches!(
        parse::parse(&signs, &["x"]),
        Err(Error::Parse { .. })
    ));
    let tower = vec!["x"; 2000].join("^");
    assert!(matches!(
        parse::parse(&tower, &["x"]),
        Err(Error::Parse { .. })
    ));
    let long_sum = vec!["x"; 4000].join("+");
    assert!(matches!(
        parse::parse(&long_sum, &["x"]),
        Err(Error::Parse { .. })
    ));
    let sum = vec!["x"; 500].join("+");
    let e = Expression::new(&sum, &["x"], &[]).unwrap();
    assert_eq!(e.value(&[0.5]).unwrap(), 250.0);
}

/// `-q^2 = -(q²)`, `2^3^2 = 2^9`, `2^-1 = 1/2`, `pi`, and the functions.
#[test]
fn precedence_and_functions() {
    let v = |text: &str, x: f64| {
        Expression::new(text, &["q"], &[])
            .unwrap()
            .value(&[x])
            .unwrap()
    };
    assert_eq!(v("-q^2", 3.0), -9.0);
    assert_eq!(v("2^3^2 + 0*q", 0.0), 512.0);
    assert_eq!(v("2^-1 + q", 0.0), 0.5);
    assert_eq!(v("-2*q", 3.0), -6.0);
    assert_eq!(v("q/2/2", 8.0), 2.0);
    assert_eq!(v("1e-3*q", 1.0), 1e-3);
    assert_eq!(v("cos(pi) + q", 0.0), -1.0);
    let x: f64 = 0.3;
    let checks = [
        ("sin(q)", x.sin()),
        ("cos(q)", x.cos()),
        ("tan(q)", x.tan()),
        ("exp(q)", x.exp()),
        ("ln(q)", x.ln()),
        ("log(q)", x.ln()),
        ("sqrt(q)", x.sqrt()),
        ("sinh(q)", x.sinh()),
        ("cosh(q)", x.cosh()),
        ("tanh(q)", x.tanh()),
        ("asin(q)", x.asin()),
        ("acos(q)", x.acos()),
        ("atan(q)", x.atan()),
        ("atan2(q, 2)", x.atan2(2.0)),
        ("pow(q, 2.5)", x.powf(2.5)),
        ("q^q", x.powf(x)),
    ];
    for (text, want) in checks {
        let got = v(text, x);
        assert!(
            (got - want).abs() <= 4.0 * f64::EPSILON * want.abs(),
            "{text}: {got} {want}"
        );
    }
}

/// A state where `H` or its gradient is not finite is refused, naming which.
#[test]
fn non_finite_initial_states_are_refused() {
    let e = ExpressionHamiltonian::<1>::new("p_q^2/2 - 1/q", &["q"], None, &[]).unwrap();
    let err = e
        .check_state(0.0, &SVector::from([0.0]), &SVector::from([1.0]))
        .unwrap_err();
    assert!(
        matches!(&err, Error::NonFinite { what, .. } if what.starts_with("H of")),
        "{err}"
    );
    let e = ExpressionHamiltonian::<1>::new("p_q^2/2 + sqrt(q)", &["q"], None, &[]).unwrap();
    let err = e
        .check_state(0.0, &SVector::from([0.0]), &SVector::from([1.0]))
        .unwrap_err();
    assert!(
        matches!(&err, Error::NonFinite { what, .. } if what.contains("∂H/∂q")),
        "{err}"
    );
    let text = "[system]\nhamiltonian = \"p_q^2/2 - 1/q\"\ncoordinates = [\"q\"]\nq = [0.0]\np = [1.0]\n[span]\ntime = 1\n[[method]]\nkind = \"rk4\"\nsteps = [10]\n";
    let e = scene::parse("s.toml", text, &Catalogue::builtin())
        .err()
        .unwrap();
    assert_eq!(e.key, "system.q", "{e}");
}

/// A Lagrangian by expression: the pendulum `L = q̇²/2 + g cos q` has `q̈ = −g sin q`, and its
/// Hamiltonian by expression `H = p²/2 − g cos q` the vector field `(p, −g sin q)`.
#[test]
fn lagrangian_and_parameters() {
    let l =
        ExpressionLagrangian::<1>::new("v_q^2/2 + g*cos(q)", &["q"], None, &[("g", 9.81)]).unwrap();
    let a = l
        .accelerations(0.0, &SVector::from([0.4]), &SVector::from([0.1]))
        .unwrap();
    assert!((a[0] + 9.81 * 0.4f64.sin()).abs() < 1e-14);
    let h =
        ExpressionHamiltonian::<1>::new("p^2/2 - g*cos(q)", &["q"], Some(&["p"]), &[("g", 9.81)])
            .unwrap();
    let (qd, pd) = h
        .vector_field(0.0, &SVector::from([0.4]), &SVector::from([0.1]))
        .unwrap();
    assert_eq!(qd[0], 0.1);
    assert!((pd[0] + 9.81 * 0.4f64.sin()).abs() < 1e-15);
    // A coupling term makes it non-separable; time may enter.
    let h = ExpressionHamiltonian::<1>::new("p*q + t", &["q"], Some(&["p"]), &[]).unwrap();
    assert!(h.separable().is_none());
    assert_eq!(
        h.partial_t(0.0, &SVector::from([1.0]), &SVector::from([1.0]))
            .unwrap(),
        1.0
    );
    let _: Option<ExpressionSeparable<1>> = None;
}

/// A random expression tree, rendered fully parenthesised, and its value by a direct `f64`
/// evaluation (the oracle, independent of the parser and the record) with a running bound on
/// its rounding error.
#[derive(Clone, Debug)]
enum Tree {
    Num(f64),
    Var(usize),
    Neg(Box<Tree>),
    Bin(char, Box<Tree>, Box<Tree>),
    Fun(&'static str, Box<Tree>),
}

/// The unit roundoff `u = ε/2`.
const U: f64 = f64::EPSILON / 2.0;

impl Tree {
    fn text(&self) -> String {
        self.text_in(&["x", "y", "z"])
    }

    /// The text with the variables named `names`.
    fn text_in(&self, names: &[&str; 3]) -> String {
        match self {
            Tree::Num(c) => format!("{c:?}"),
            Tree::Var(i) => names[*i].to_string(),
            Tree::Neg(a) => format!("(-{})", a.text_in(names)),
            Tree::Bin(op, a, b) => format!("({} {op} {})", a.text_in(names), b.text_in(names)),
            Tree::Fun(f, a) => format!("{f}({})", a.text_in(names)),
        }
    }

    /// The value `r` at `x` and a bound `e` on `|r − r*|`, `r*` the exact value, that holds
    /// for this evaluation and for every evaluation of the same tree whose operations each
    /// commit a local error of at most `4u|r|` (arithmetic) or `2ε|r|` (`sin`, `cos`, `exp`,
    /// `atan`, `tanh`), the propagated errors bounded by running error
    /// analysis (N. J. Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed., SIAM
    /// 2002, §3.3): `e(a ± b) = e_a + e_b`, `e(ab) = |a|e_b + |b|e_a + e_a e_b`,
    /// `e(a/b) = (e_a + |a/b| e_b)/(|b| − e_b)`, `e(f(a)) = e_a` for the 1-Lipschitz
    /// functions, `e(exp a) = eᵃ(e^{e_a} − 1)`, plus the local error of each operation.
    ///
    /// The record evaluates the same operations with at most these local errors: a constant
    /// divisor becomes a product with its reciprocal (two roundings), scale factors of the
    /// program multiply (one rounding each, at most one per operation folded), `atan a` is
    /// `atan2(a, 1)`, `tanh a` is an operation of its own (±1 for `|a| > 20`, as `f64::tanh`,
    /// however large `a`), and shared subexpressions have equal values. `e = ∞` where the
    /// bound does not hold (a divisor that may vanish, an overflow).
    fn value(&self, x: &[f64]) -> (f64, f64) {
        let (r, e) = match self {
            Tree::Num(c) => (*c, 0.0),
            Tree::Var(i) => (x[*i], 0.0),
            Tree::Neg(a) => {
                let (a, e) = a.value(x);
                (-a, e)
            }
            Tree::Bin(op, a, b) => {
                let ((a, ea), (b, eb)) = (a.value(x), b.value(x));
                let (r, e) = match op {
                    '+' => (a + b, ea + eb),
                    '-' => (a - b, ea + eb),
                    '*' => (a * b, a.abs() * eb + b.abs() * ea + ea * eb),
                    _ => {
                        let r = a / b;
                        let e = if b.abs() > eb {
                            (ea + r.abs() * eb) / (b.abs() - eb)
                        } else {
                            f64::INFINITY
                        };
                        (r, e)
                    }
                };
                (r, e + 4.0 * U * r.abs())
            }
            Tree::Fun(f, a) => {
                let (a, ea) = a.value(x);
                let eps = f64::EPSILON;
                match *f {
                    "sin" => (a.sin(), ea + 2.0 * eps * a.sin().abs()),
                    "cos" => (a.cos(), ea + 2.0 * eps * a.cos().abs()),
                    "exp" => {
                        let r = a.exp();
                        (r, r * ea.exp_m1() * (1.0 + eps) + 2.0 * eps * r)
                    }
                    "atan" => (a.atan(), ea + 2.0 * eps * a.atan().abs()),
                    // 1-Lipschitz and bounded: within min(e_a, 2) whatever the argument.
                    _ => (a.tanh(), ea.min(2.0) + 2.0 * eps * a.tanh().abs()),
                }
            }
        };
        if (r.abs() + e).is_finite() {
            (r, e)
        } else {
            (r, f64::INFINITY)
        }
    }
}

fn tree() -> impl Strategy<Value = Tree> {
    tree_with(
        &['+', '-', '*', '/'],
        &["sin", "cos", "exp", "atan", "tanh"],
    )
}

/// Random trees of the binary operations `ops` and the functions `functions`.
fn tree_with(ops: &[char], functions: &[&'static str]) -> impl Strategy<Value = Tree> {
    let (ops, functions) = (ops.to_vec(), functions.to_vec());
    let leaf = prop_oneof![
        (0.1f64..10.0).prop_map(Tree::Num),
        (0usize..3).prop_map(Tree::Var),
    ];
    leaf.prop_recursive(6, 48, 2, move |inner| {
        prop_oneof![
            inner.clone().prop_map(|a| Tree::Neg(Box::new(a))),
            (
                prop::sample::select(ops.clone()),
                inner.clone(),
                inner.clone()
            )
                .prop_map(|(op, a, b)| Tree::Bin(op, Box::new(a), Box::new(b))),
            (prop::sample::select(functions.clone()), inner)
                .prop_map(|(f, a)| Tree::Fun(f, Box::new(a))),
        ]
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Random strings of the expression alphabet: a typed result, never a panic.
    #[test]
    fn random_strings_never_panic(s in "[-+*/^(),. 0-9eqpxy_a-z]{0,80}") {
        let _ = Expression::new(&s, &["q", "p", "x", "y"], &[]);
    }

    /// Random Unicode: a typed result, never a panic.
    #[test]
    fn random_unicode_never_panics(s in any::<String>()) {
        if let Err(e) = Expression::new(&s, &["q"], &[]) {
            let _ = e.to_string();
        }
    }

    /// A random tree parses, compiles and evaluates as the direct evaluation of the tree, and
    /// as the generic evaluation of the parsed tree, to rounding: both values lie within the
    /// running error bound `e` of the exact value (see `Tree::value`), so they differ by at
    /// most `2e`.
    #[test]
    fn random_trees_evaluate_as_the_tree(t in tree(), x in prop::array::uniform3(-2.0f64..2.0)) {
        let e = Expression::new(&t.text(), &["x", "y", "z"], &[]).unwrap();
        let (want, bound) = t.value(&x);
        let got = e.eval(&x);
        if bound.is_finite() {
            prop_assert!((got - want).abs() <= 2.0 * bound, "{} {got} {want} {bound}", t.text());
            let direct = e.tree().eval(&x);
            prop_assert!((direct - want).abs() <= 2.0 * bound, "{} {direct} {want} {bound}", t.text());
        }
    }
}

/// Whether the native code of expression systems is expected: the feature `jit` on a host
/// Cranelift supports.
const NATIVE: bool = cfg!(all(
    feature = "jit",
    any(
        target_arch = "x86_64",
        target_arch = "aarch64",
        target_arch = "riscv64"
    )
));

/// Equal bit for bit, every NaN equal to every NaN.
fn same(a: &[f64], b: &[f64]) -> bool {
    a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(x, y)| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan()))
}

/// The vector field and the gradient of `e` (general and split forms) on `f64` at `(q, p)`, in
/// one list.
fn fields<const N: usize>(
    e: &ExpressionHamiltonian<N>,
    split: Option<&ExpressionSeparable<N>>,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Vec<f64> {
    let (a, b) = e.vector_field_unchecked(0.25, q, p);
    let (h, hq, hp) = e.gradient(0.25, q, p);
    let mut out: Vec<f64> = a
        .iter()
        .chain(&b)
        .chain(&[h])
        .chain(&hq)
        .chain(&hp)
        .copied()
        .collect();
    if let Some(s) = split {
        let (a, b) = s.vector_field_unchecked(0.25, q, p);
        let (t, tp) = s.kinetic_gradient(0.25, p);
        let (v, vq) = s.potential_gradient(0.25, q);
        out.extend(a.iter().chain(&b).chain(&[t, v]).chain(&tp).chain(&vq));
    }
    out
}

/// The native code of an expression system against the interpreter of the same register
/// program (the oracle: the same operations in the same order, so equal bit for bit), at `z`.
fn native_is_interpreter<const N: usize>(e: &ExpressionHamiltonian<N>, z: &[f64]) -> bool {
    let split = e.separable();
    let (ei, si) = (e.interpreted(), split.as_ref().map(|s| s.interpreted()));
    assert!(!ei.is_native() && si.as_ref().is_none_or(|s| !s.is_native()));
    assert_eq!(e.is_native(), NATIVE);
    assert!(split.as_ref().is_none_or(|s| s.is_native() == NATIVE));
    let q = SVector::from_fn(|i, _| z[i]);
    let p = SVector::from_fn(|i, _| z[N + i]);
    same(
        &fields(e, split.as_ref(), &q, &p),
        &fields(&ei, si.as_ref(), &q, &p),
    )
}

/// Hénon–Heiles and Kepler + J₂ (the systems of the `expression` benchmark): native code and
/// interpreter agree bit for bit at 300 states of a box, and at states with NaN, ±∞, huge,
/// subnormal and signed-zero components (NaN wherever the interpreter gives NaN).
#[test]
fn native_code_is_the_interpreter_on_the_benchmark_systems() {
    fn shared<T: Send + Sync>() {}
    shared::<ExpressionHamiltonian<2>>();
    shared::<ExpressionSeparable<2>>();
    let hh = henon_heiles();
    let j2 = ExpressionHamiltonian::<3>::new(J2_3, &["x", "y", "z"], None, &j2_params()).unwrap();
    let special = [
        f64::NAN,
        f64::INFINITY,
        -f64::INFINITY,
        1e300,
        -1e-310,
        -0.0,
        0.0,
    ];
    for (k, z) in points(300, 2.0).into_iter().enumerate() {
        let w = [z[0], z[1], z[2], z[3], z[1] - z[0], 0.5 * z[2]];
        let mut hostile = w;
        hostile[k % 6] = special[k % special.len()];
        for w in [w, hostile] {
            assert!(native_is_interpreter(&hh, &w[..4]), "Hénon–Heiles at {w:?}");
            assert!(native_is_interpreter(&j2, &w), "Kepler + J2 at {w:?}");
        }
    }
}

/// An expression whose register program holds every instruction — `αa + βb`, `αa + γ`,
/// `ab`, `αab + βc`, `a/b`, `1/a`, `√a`, `eᵃ`, `ln a`, `aᵖ`, `tanh a`, `sin a, cos a`,
/// `atan2(y, x)` — in native code and by the interpreter, bit for bit, at 200 states and at
/// hostile ones.
#[test]
fn native_code_is_the_interpreter_for_every_instruction() {
    let text = "2*x - 3*p_y + (y + 1.5) + x*y + 0.5*x*p_x - 1.25*p_y*y + x/(y + 3) + 1/(p_x + 4) \
        + sqrt(x^2 + 1) + exp(y/3) + ln(p_x^2 + 2) + (y^2 + 1)^0.37 + tanh(3*x) + sin(p_y)*cos(2*p_y) \
        + atan2(y, x + 5) + asin(p_x/9) + sinh(y)";
    let e = ExpressionHamiltonian::<2>::new(text, &["x", "y"], None, &[]).unwrap();
    assert!(e.separable().is_none());
    let special = [
        f64::NAN,
        f64::INFINITY,
        -f64::INFINITY,
        1e300,
        4e-320,
        -0.0,
        30.0,
    ];
    for (k, z) in points(200, 3.0).into_iter().enumerate() {
        let mut hostile = z;
        hostile[k % 4] = special[k % special.len()];
        assert!(native_is_interpreter(&e, &z), "{z:?}");
        assert!(native_is_interpreter(&e, &hostile), "{hostile:?}");
    }
}

/// A separable Hamiltonian whose potential part is the time alone, `V(t, q) = t`: the kick
/// `∂V/∂q` is 0 (the adjoint of an input recorded after the output), the drift `∂T/∂p = p`.
#[test]
fn a_part_that_is_the_time_alone_has_zero_gradient() {
    let e = ExpressionHamiltonian::<1>::new("t + p_q^2/2", &["q"], None, &[]).unwrap();
    let s = e.separable().expect("T(p) + V(t)");
    let (v, vq) = s.potential_gradient(0.75, &SVector::from([0.5]));
    let (t, tp) = s.kinetic_gradient(0.75, &SVector::from([0.5]));
    assert_eq!((v, vq[0], t, tp[0]), (0.75, 0.0, 0.125, 0.5));
    assert!(native_is_interpreter(&e, &[0.5, -1.5]));
}

/// A finite, non-finite, huge, tiny or special value.
fn any_value() -> impl Strategy<Value = f64> {
    prop_oneof![
        6 => -3.0f64..3.0,
        1 => prop::sample::select(vec![
            f64::NAN, f64::INFINITY, f64::NEG_INFINITY, 0.0, -0.0, 1e300, -1e300, 5e-324,
            f64::MAX, f64::MIN_POSITIVE, 25.0, -710.0,
        ]),
        1 => any::<f64>(),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    /// `H = f(x, y, z) + g(u, v, w)` of random trees with every operation and every function
    /// of the parser: the native vector field, gradient, drift and kick are the interpreter's, bit for
    /// bit (NaN for NaN), at random states with NaN, ±∞, huge and subnormal components.
    #[test]
    fn random_systems_native_code_is_the_interpreter(
        f in tree_with(&['+', '-', '*', '/', '^'], &unary_functions()),
        g in tree_with(&['+', '-', '*', '/', '^'], &unary_functions()),
        z in prop::collection::vec(any_value(), 6),
    ) {
        let text = format!("{} + {}", f.text(), g.text_in(&["u", "v", "w"]));
        let e = ExpressionHamiltonian::<3>::new(&text, &["x", "y", "z"], Some(&["u", "v", "w"]), &[])
            .unwrap();
        prop_assert!(e.separable().is_some());
        prop_assert!(native_is_interpreter(&e, &z), "{text} at {z:?}");
    }
}

/// The functions of one argument of the parser (`atan2` is reached through `atan`, `asin`,
/// `acos`, and `pow` through `^`).
fn unary_functions() -> Vec<&'static str> {
    parse::FUNCTIONS
        .iter()
        .filter(|f| f.2 == 1)
        .map(|f| f.0)
        .collect()
}

//! Scene systems given by a Lagrangian, a disturbing function or constraints as expressions.
//!
//! Oracles: the Rust-written `systems::HenonHeiles` for a Hénon–Heiles Lagrangian run through
//! the Legendre transform; the crate's `PerturbedTwoBody<J2>` for `J₂` written as a disturbing
//! function (`H = H_Kepler − R`); for the spherical pendulum written as a particle in space on
//! the sphere, the closed-form conical motion (uniform rotation at `ω² = g/(ℓ cos α)`) and a
//! Rust-written point mass with a Rust-written sphere under RATTLE; for the Chaplygin sleigh and
//! the non-holonomic particle written with Pfaffian constraints, the catalogue's Rust-written
//! systems run by the same constrained integrators, and the sleigh's closed-form free motion
//! [Hamel art. 238]. Malformed scenes give one-line errors naming the key.
#![cfg(feature = "cli")]

mod common;
use common::quick;

use hamilton_jacobi::constraints::HolonomicConstraints;
use hamilton_jacobi::constraints::{classify, PfaffianConstraints};
use hamilton_jacobi::expression::{
    ExpressionConstraints, ExpressionDisturbingFunction, ExpressionHamiltonian,
    ExpressionLagrangian, ExpressionPfaffian,
};
use hamilton_jacobi::integrate::Dop853;
use hamilton_jacobi::integrate::PerturbedKepler;
use hamilton_jacobi::integrate::{
    integrate, ConstrainedHamiltonian, Control, Each, Fixed, Problem, Rattle, Rk4, WisdomHolman,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::nonholonomic::{Constrained, ConstrainedInfo, ConstrainedMethod};
use hamilton_jacobi::perturbation::forces::{PerturbedTwoBody, J2};
use hamilton_jacobi::scene::{self, Case, Catalogue, MethodKind, SceneError};
use hamilton_jacobi::systems::{ChaplyginSleigh, HenonHeiles, NonholonomicParticle};
use hamilton_jacobi::{DualNum, Hamiltonian, Lagrangian, Legendre};

const EPS: f64 = f64::EPSILON;

/// Deterministic points of the box `[−w, w]⁴` (a linear congruential sequence).
fn points(n: usize, w: f64) -> Vec<[f64; 4]> {
    let mut s: u64 = 0x9e37_79b9_7f4a_7c15;
    (0..n)
        .map(|_| {
            [0; 4].map(|_| {
                s = s
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                ((s >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0) * w
            })
        })
        .collect()
}

/// The case of the `[system]` table of `text`.
fn case_of(text: &str) -> Result<Box<dyn Case>, SceneError> {
    let table: toml::Table = toml::from_str(text).unwrap();
    Catalogue::builtin().build("bad.toml", table["system"].as_table().unwrap())
}

fn kind(key: &str) -> MethodKind {
    MethodKind::from_key(key).unwrap()
}

/// The last state of a case's run of `kind` at `knob`, to `t1`.
fn last_state(case: &mut Box<dyn Case>, key: &str, knob: f64, t1: f64) -> (Vec<f64>, Vec<f64>) {
    case.prepare(t1).unwrap();
    let h = case.history(kind(key), knob, 10).unwrap();
    // The end time as a sum of at most 10⁴ steps: within 10⁴ ε t₁.
    assert!(
        (h.t.last().unwrap() - t1).abs() <= 1e4 * EPS * t1,
        "{:?}",
        h.t
    );
    (h.q.last().unwrap().clone(), h.p.last().unwrap().clone())
}

fn max_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

// ---------------------------------------------------------------------------------------------
// Lagrangian
// ---------------------------------------------------------------------------------------------

const HH_LAGRANGIAN: &str = r#"
[system]
lagrangian = "(v_x^2 + v_y^2)/2 - (x^2 + y^2)/2 - x^2*y + y^3/3"
coordinates = ["x", "y"]
q = [0.0, 0.1]
v = [0.39665266081716044, 0.0]
"#;

/// The Hénon–Heiles Lagrangian `L = |v|²/2 − V` by expression, through the Legendre transform
/// (`p = v`, one Newton step from `v = 0` with the unit mass matrix, exact), has the vector field
/// of the Rust-written `HenonHeiles` to rounding: at points of `|x|, |y|, |p| ≤ 0.5` the terms
/// are `≲ 1` and each side takes a few dozen roundings, `|Δ| ≤ 16 ε`.
#[test]
fn lagrangian_by_expression_has_the_vector_field_of_henon_heiles() {
    let l = ExpressionLagrangian::<2>::new(
        "(v_x^2 + v_y^2)/2 - (x^2 + y^2)/2 - x^2*y + y^3/3",
        &["x", "y"],
        None,
        &[],
    )
    .unwrap();
    let h = Legendre(l);
    let rust = HenonHeiles;
    for z in points(100, 0.5) {
        let (q, p) = (SVector::from([z[0], z[1]]), SVector::from([z[2], z[3]]));
        let (a_q, a_p) = rust.vector_field(0.0, &q, &p).unwrap();
        let (b_q, b_p) = h.vector_field(0.0, &q, &p).unwrap();
        assert!(
            max_diff(a_q.as_slice(), b_q.as_slice()) <= 16.0 * EPS,
            "{z:?}"
        );
        assert!(
            max_diff(a_p.as_slice(), b_p.as_slice()) <= 16.0 * EPS,
            "{z:?}"
        );
        let e = (rust.value(0.0, &q, &p).unwrap() - h.value(0.0, &q, &p).unwrap()).abs();
        assert!(e <= 16.0 * EPS, "{z:?}: {e:e}");
    }
}

/// The Lagrangian scene runs RK4 as the Rust system does: 2000 steps to `t = 20` on the regular
/// orbit of energy 1/12 (state `≲ 0.5`). The vector fields differ by at most `16 ε` (above), so
/// each step adds at most `h · 16 ε` (4 stages weighted `h/6 (1 + 2 + 2 + 1)`) and rounding flips
/// of `ε |z|`, amplified over a regular orbit by at most linear growth, `1 + λt` with `λ ≲ 1`:
/// `|Δ| ≤ n (h · 16 ε + 2 ε)(1 + t) ≈ 2000 · 3.6 ε · 21 ≈ 3.4·10⁻¹¹`.
#[test]
fn lagrangian_scene_runs_henon_heiles_as_the_rust_system() {
    let mut case = case_of(HH_LAGRANGIAN).unwrap();
    assert!(case.supports(kind("rk4")));
    assert!(case.supports(kind("dop853")));
    // The initial state is read as (q, q̇): p = q̇ for this L, the energy 1/12 of the orbit.
    let z0 = ([0.0, 0.1], [0.39665266081716044, 0.0]);
    let e = case.energy(0.0, &z0.0, &z0.1).unwrap();
    assert!((e - 1.0 / 12.0).abs() < 1e-15, "{e}");
    let (t1, n) = (20.0, 2000);
    let (q, p) = last_state(&mut case, "rk4", n as f64, t1);
    let rust = HenonHeiles;
    let pr = Problem::new(&rust, 0.0, SVector::from(z0.0), SVector::from(z0.1), t1).unwrap();
    let run = integrate(&pr, &Fixed::new(Rk4, n).unwrap(), &mut ()).unwrap();
    let h = t1 / n as f64;
    let bound = n as f64 * (h * 16.0 * EPS + 2.0 * EPS) * (1.0 + t1);
    let d = max_diff(&q, run.last.q.as_slice()).max(max_diff(&p, run.last.p.as_slice()));
    println!("Lagrangian scene vs Rust Hénon–Heiles, RK4 {n} steps: |Δ| = {d:e} (bound {bound:e})");
    assert!(d <= bound, "{d:e} > {bound:e}");
}

/// The pendulum by Lagrangian and by Hamiltonian expression (`L = v²/2 + cos q`,
/// `H = p²/2 − cos q`): the same vector field to a few ε, through the scene's DOP853 runs the
/// same final state to the DOP853 tolerance's order.
#[test]
fn pendulum_lagrangian_scene_agrees_with_the_hamiltonian_expression() {
    let l = Legendre(
        ExpressionLagrangian::<1>::new("v_q^2/2 + g*cos(q)", &["q"], None, &[("g", 1.0)]).unwrap(),
    );
    let h =
        ExpressionHamiltonian::<1>::new("p_q^2/2 - g*cos(q)", &["q"], None, &[("g", 1.0)]).unwrap();
    for z in points(50, 3.0) {
        let (q, p) = (SVector::from([z[0]]), SVector::from([z[1]]));
        let (a, b) = (
            l.vector_field(0.0, &q, &p).unwrap(),
            h.vector_field(0.0, &q, &p).unwrap(),
        );
        // Terms of size ≤ 3, a handful of roundings.
        assert!((a.0 - b.0).amax() <= 8.0 * EPS * 3.0, "{z:?}");
        assert!((a.1 - b.1).amax() <= 8.0 * EPS * 3.0, "{z:?}");
    }
    let lagrangian = "[system]\nlagrangian = \"v_q^2/2 + cos(q)\"\ncoordinates = [\"q\"]\nq = [1.0]\nv = [0.0]\n";
    let hamiltonian = "[system]\nhamiltonian = \"p_q^2/2 - cos(q)\"\ncoordinates = [\"q\"]\nq = [1.0]\np = [0.0]\n";
    let (mut cl, mut ch) = (case_of(lagrangian).unwrap(), case_of(hamiltonian).unwrap());
    let a = last_state(&mut cl, "rk4", 1000.0, 10.0);
    let b = last_state(&mut ch, "rk4", 1000.0, 10.0);
    // As above: n (h · 8 ε · 3 + 2 ε)(1 + t).
    let bound = 1000.0 * (0.01 * 24.0 * EPS + 2.0 * EPS) * 11.0;
    let d = max_diff(&a.0, &b.0).max(max_diff(&a.1, &b.1));
    assert!(d <= bound, "{d:e} > {bound:e}");
}

// ---------------------------------------------------------------------------------------------
// Disturbing function
// ---------------------------------------------------------------------------------------------

/// `R_{J₂} = −U_{J₂} = (μJ₂R²/2)(1 − 3z²/r²)/r³ = (μJ₂R²/2)(x² + y² − 2z²)/r⁵`.
const R_J2: &str = "mu*J2*Re^2/2*(x^2 + y^2 - 2*z^2)/(x^2 + y^2 + z^2)^2.5";

const J2_SCENE: &str = r#"
[system]
disturbing_function = "mu*J2*Re^2/2*(x^2 + y^2 - 2*z^2)/(x^2 + y^2 + z^2)^2.5"
mu = 1.0
parameters = { J2 = 1.08e-3, Re = 0.9 }
q = [1.2, 0.0, 0.0]
p = [0.0, 0.85, 0.35]
"#;

fn j2_rust() -> PerturbedTwoBody<J2> {
    PerturbedTwoBody::conservative(1.0, J2::new(1.0, 1.08e-3, 0.9).unwrap()).unwrap()
}

/// `J₂` written as a disturbing function `R` (with `H = H_Kepler − R`) is the crate's
/// `PerturbedTwoBody<J2>`: the perturbation `H₁ = −R = U_{J₂}` to a few ε of `|U|`, the vector
/// field to a few ε of its terms (`μ/r² ≤ 1.3` on the shell `0.9 ≤ r ≤ 1.5`, a few dozen
/// roundings: `|Δ| ≤ 32 ε`).
#[test]
fn j2_as_a_disturbing_function_is_perturbed_two_body_j2() {
    let r = ExpressionDisturbingFunction::<3>::new(
        R_J2,
        None,
        &[("mu", 1.0), ("J2", 1.08e-3), ("Re", 0.9)],
    )
    .unwrap();
    let e = PerturbedTwoBody::conservative(1.0, r).unwrap();
    let rust = j2_rust();
    for z in points(100, 1.0) {
        let q = SVector::from([0.9 + 0.3 * (z[0] + 1.0), 0.3 * z[1], 0.3 * z[2]]);
        let p = SVector::from([z[3], z[0] * z[1], z[2]]);
        let (u_rust, u_expr) = (rust.perturbation(0.0, &q), e.perturbation(0.0, &q));
        assert!(
            (u_rust - u_expr).abs() <= 16.0 * EPS * u_rust.abs(),
            "{q}: {u_rust:e} vs {u_expr:e}"
        );
        let (a_q, a_p) = rust.vector_field(0.0, &q, &p).unwrap();
        let (b_q, b_p) = e.vector_field(0.0, &q, &p).unwrap();
        assert!(
            max_diff(a_q.as_slice(), b_q.as_slice()) <= 32.0 * EPS,
            "{q}"
        );
        assert!(
            max_diff(a_p.as_slice(), b_p.as_slice()) <= 32.0 * EPS,
            "{q}"
        );
    }
}

/// The `J₂` scene by disturbing function runs Wisdom–Holman and SABA₃ as the Rust system does:
/// 1000 steps over 10 osculating periods. The kicks differ by `≲ 32 ε |∇U| h`, far below an ulp
/// of `p`, so the states differ only by rounding flips, at most an ulp (`2 ε |z|`, `|z| ≲ 1.2`)
/// per step, and Kepler's shear turns a velocity error `δv` into an along-track error growing as
/// `3 δv n t ≤ 3 · 2π · 10 δv`: `|Δ| ≤ n · 2.4 ε · (1 + 60π) ≈ 1.0·10⁻¹⁰`.
#[test]
fn disturbing_function_scene_runs_kepler_splittings_as_the_rust_system() {
    let mut case = case_of(J2_SCENE).unwrap();
    for key in ["wisdom-holman", "saba3", "verlet-kdk", "dop853"] {
        assert!(case.supports(kind(key)), "{key}");
    }
    let q0: SVector<f64, 3> = SVector::from([1.2, 0.0, 0.0]);
    let p0: SVector<f64, 3> = SVector::from([0.0, 0.85, 0.35]);
    // The period of the osculating orbit is the unit of `span.periods`.
    let energy = p0.norm_squared() / 2.0 - 1.0 / q0.norm();
    let a: f64 = -1.0 / (2.0 * energy);
    let period = case.period().unwrap();
    assert!((period - std::f64::consts::TAU * a.powf(1.5)).abs() <= 8.0 * EPS * period);
    let (t1, n) = (10.0 * period, 1000);
    let bound = n as f64 * 2.4 * EPS * (1.0 + 60.0 * std::f64::consts::PI);
    let rust = j2_rust();
    let pr = Problem::new(&rust, 0.0, q0, p0, t1).unwrap();
    for (key, method) in [
        ("wisdom-holman", WisdomHolman::WH),
        (
            "saba3",
            WisdomHolman::new(&hamilton_jacobi::integrate::coefficients::SABA3).unwrap(),
        ),
    ] {
        let (q, p) = last_state(&mut case, key, n as f64, t1);
        let run = integrate(&pr, &Fixed::new(method, n).unwrap(), &mut ()).unwrap();
        let d = max_diff(&q, run.last.q.as_slice()).max(max_diff(&p, run.last.p.as_slice()));
        println!("J₂ by disturbing function vs PerturbedTwoBody<J2>, {key} {n} steps: |Δ| = {d:e} (bound {bound:e})");
        assert!(d <= bound, "{key}: {d:e} > {bound:e}");
    }
}

// ---------------------------------------------------------------------------------------------
// Constraints
// ---------------------------------------------------------------------------------------------

/// The conical pendulum: `ℓ = g = 1`, `α` from the downward vertical, rotating at
/// `ω = √(g/(ℓ cos α))`.
fn conical(alpha: f64) -> (SVector<f64, 3>, SVector<f64, 3>, f64) {
    let (s, c) = alpha.sin_cos();
    let w = (1.0 / c).sqrt();
    (
        SVector::from([s, 0.0, -c]),
        SVector::from([0.0, s * w, 0.0]),
        w,
    )
}

fn spherical_scene(q: &SVector<f64, 3>, v: &SVector<f64, 3>) -> String {
    format!(
        "[system]\nlagrangian = \"(v_x^2 + v_y^2 + v_z^2)/2 - g*z\"\ncoordinates = [\"x\", \"y\", \"z\"]\n\
         parameters = {{ g = 1.0, l = 1.0 }}\nconstraints = [\"x^2 + y^2 + z^2 - l^2\"]\n\
         q = [{:?}, {:?}, {:?}]\nv = [{:?}, {:?}, {:?}]\n",
        q[0], q[1], q[2], v[0], v[1], v[2]
    )
}

/// The spherical pendulum written as a particle in space on the sphere, a scene with
/// `constraints`: on the conical motion (`α = 0.6`) its DOP853 run at rtol 10⁻¹² and its
/// discrete Lagrange–d'Alembert run agree with the closed form `(ρ cos ωt, ρ sin ωt, −cos α)`;
/// the energy and the constraint residual are its invariants.
#[test]
fn spherical_pendulum_scene_follows_the_conical_motion() {
    let (q0, v0, w) = conical(0.6);
    let mut case = case_of(&spherical_scene(&q0, &v0)).unwrap();
    assert!(case.supports(kind("dop853")));
    assert!(case.supports(kind("lagrange-dalembert")));
    assert!(!case.supports(kind("rk4")));
    let t1 = 10.0;
    let exact = [
        0.6f64.sin() * (w * t1).cos(),
        0.6f64.sin() * (w * t1).sin(),
        -0.6f64.cos(),
    ];
    // DOP853 at rtol 10⁻¹²: a few hundred steps, each within the tolerance; the phase error
    // grows at most linearly, so |Δ| ≤ 10⁻⁸ leaves room for the error estimate's optimism.
    let (q, v) = last_state(&mut case, "dop853", 1e-12, t1);
    let d = max_diff(&q, &exact);
    println!(
        "spherical pendulum scene, DOP853 rtol 1e-12: |Δq| = {d:e} against the conical motion"
    );
    assert!(d <= 1e-8, "{d:e}");
    let inv = case.invariants(t1, &q, &v).unwrap();
    let energy = inv.iter().find(|i| i.name == "energy").unwrap().value;
    let e0 = v0.norm_squared() / 2.0 + q0[2];
    assert!((energy - e0).abs() <= 1e-9, "{energy} vs {e0}");
    let residual = inv
        .iter()
        .find(|i| i.name == "constraint residual")
        .unwrap()
        .value;
    assert!(residual <= 1e-8, "{residual:e}");
    // The discrete Lagrange–d'Alembert integrator, of order 2: at h = 10⁻³ the phase error is
    // ≲ (ωh)² ωt / 24 ≈ 6·10⁻⁷; |Δ| ≤ 10⁻⁵.
    // Its history holds midpoint states (t_k + h/2, (q_k + q_{k+1})/2): the last one is at
    // t₁ − h/2, compared with the conical motion at that time.
    case.prepare(t1).unwrap();
    let h = case
        .history(kind("lagrange-dalembert"), 10_000.0, 10)
        .unwrap();
    let tm = *h.t.last().unwrap();
    assert!((tm - (t1 - 0.5e-3)).abs() <= 1e4 * EPS * t1, "{:?}", h.t);
    let q = h.q.last().unwrap();
    let exact = [
        0.6f64.sin() * (w * tm).cos(),
        0.6f64.sin() * (w * tm).sin(),
        -0.6f64.cos(),
    ];
    let d = max_diff(q, &exact);
    println!("spherical pendulum scene, Lagrange–d'Alembert 10⁴ steps: |Δq| = {d:e}");
    assert!(d <= 1e-5, "{d:e}");
}

/// A unit point mass under gravity `−g e_z`, `H = ½|p|² + g z`, written in Rust.
#[derive(Clone, Copy, Debug)]
struct Heavy {
    g: f64,
}

impl Hamiltonian<3> for Heavy {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
        p: &SVector<D, 3>,
    ) -> D {
        p.dot(p) * 0.5 + q[2] * self.g
    }
}

/// The unit sphere `|q|² − 1 = 0`, written in Rust.
#[derive(Clone, Copy, Debug)]
struct Sphere;

impl HolonomicConstraints<3, 1> for Sphere {
    fn position_constraint<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
    ) -> SVector<D, 1> {
        SVector::from([q.dot(q) - 1.0])
    }
}

/// RATTLE on the expression Lagrangian (through the Legendre transform) and the expression
/// constraint keeps `|g|` and `|G H_p|` at rounding level over 2000 steps, as on the Rust-written
/// point mass and sphere, and the two runs agree: their vector fields and constraint Jacobians
/// differ by a few ε, each step's Newton solves stop at rounding level, so the states differ by
/// a few ulps per step, growing at most linearly (regular motion): `|Δ| ≤ n · 8 ε · (1 + t)`.
#[test]
fn rattle_on_the_expression_spherical_pendulum_keeps_the_constraint() {
    let l = ExpressionLagrangian::<3>::new(
        "(v_x^2 + v_y^2 + v_z^2)/2 - g*z",
        &["x", "y", "z"],
        None,
        &[("g", 1.0)],
    )
    .unwrap();
    let g = ExpressionConstraints::<3, 1>::new(
        &["x^2 + y^2 + z^2 - l^2"],
        &["x", "y", "z"],
        &[("l", 1.0)],
    )
    .unwrap();
    let sys = ConstrainedHamiltonian::new(Legendre(l), g);
    let rust = ConstrainedHamiltonian::new(Heavy { g: 1.0 }, Sphere);
    let (s, c) = 0.8f64.sin_cos();
    let q0 = SVector::from([s, 0.0, -c]);
    let p0 = SVector::from([0.0, 0.9, 0.0]);
    let (t1, n) = (10.0, 2000);
    let (mut max_g, mut max_v) = (0.0f64, 0.0f64);
    let mut obs = Each(|st: &hamilton_jacobi::State<3>| {
        let (rg, rv) = sys.residuals(st.t, &st.q, &st.p).unwrap();
        max_g = max_g.max(rg);
        max_v = max_v.max(rv);
        Control::Continue
    });
    let pr = Problem::new(&sys, 0.0, q0, p0, t1).unwrap();
    let run = integrate(&pr, &Rattle::new(n).unwrap(), &mut obs).unwrap();
    let pr_rust = Problem::new(&rust, 0.0, q0, p0, t1).unwrap();
    let run_rust = integrate(&pr_rust, &Rattle::new(n).unwrap(), &mut ()).unwrap();
    let d = (run.last.q - run_rust.last.q)
        .amax()
        .max((run.last.p - run_rust.last.p).amax());
    let bound = n as f64 * 8.0 * EPS * (1.0 + t1);
    println!(
        "RATTLE on the expression spherical pendulum, {n} steps: max|g| {max_g:e}, max|G H_p| \
         {max_v:e}; against the Rust system |Δ| = {d:e} (bound {bound:e})"
    );
    assert!(max_g < 1e-14, "position constraint {max_g:e}");
    assert!(max_v < 1e-13, "velocity constraint {max_v:e}");
    assert!(d <= bound, "{d:e} > {bound:e}");
    // The constraint by expression is the Rust one, value and gradient.
    let q = SVector::from([0.3, -0.7, 0.2]);
    let e = ExpressionConstraints::<3, 1>::new(&["x^2 + y^2 + z^2 - 1"], &["x", "y", "z"], &[])
        .unwrap();
    assert_eq!(
        e.value(0.0, &q).unwrap()[0],
        Sphere.position_constraint(0.0, &q)[0]
    );
}

// ---------------------------------------------------------------------------------------------
// The built-in scene and malformed scenes
// ---------------------------------------------------------------------------------------------

/// The built-in spherical pendulum by expression runs every method it names, quickly.
#[test]
fn spherical_pendulum_builtin_scene_runs() {
    let catalogue = Catalogue::builtin();
    let text = scene::builtin_text("spherical-pendulum-expression").unwrap();
    let s = scene::parse("spherical-pendulum-expression", text, &catalogue).unwrap();
    let out = std::env::temp_dir().join(format!("hj-expression-scenes-{}", std::process::id()));
    let start = std::time::Instant::now();
    let summary = s.run(&quick(&out)).unwrap();
    println!("spherical-pendulum-expression ran in {:?}", start.elapsed());
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
}

// ---------------------------------------------------------------------------------------------
// Pfaffian (non-holonomic) constraints
// ---------------------------------------------------------------------------------------------

const SLEIGH_LAGRANGIAN: &str =
    "m/2*(v_x^2 + v_y^2) + m*s*v_th*(v_y*cos(th) - v_x*sin(th)) + I/2*v_th^2";
const SLEIGH_PARAMETERS: [(&str, f64); 3] = [("m", 2.0), ("s", 0.5), ("I", 1.0)];
const SLEIGH_ROW: [&str; 3] = ["-sin(th)", "cos(th)", "0"];

/// The sleigh's Lagrangian and blade by expression, as `nonholonomic::Constrained`.
fn expression_sleigh() -> Constrained<ExpressionLagrangian<3>, ExpressionPfaffian<3, 1>, 3, 1> {
    let coordinates = ["x", "y", "th"];
    let l =
        ExpressionLagrangian::<3>::new(SLEIGH_LAGRANGIAN, &coordinates, None, &SLEIGH_PARAMETERS)
            .unwrap();
    let c = ExpressionPfaffian::<3, 1>::new(
        &[SLEIGH_ROW],
        None::<&[&str]>,
        &coordinates,
        &SLEIGH_PARAMETERS,
    )
    .unwrap();
    Constrained::new(l, c)
}

/// The three constrained methods of the scenes: DOP853 on the multiplier form, with projection
/// (both at `rtol = atol = 10⁻¹⁰`), and discrete Lagrange–d'Alembert with 1000 steps.
fn constrained_methods() -> [(&'static str, ConstrainedMethod); 3] {
    [
        (
            "dop853",
            ConstrainedMethod::Reduced(Dop853::new(1e-10, 1e-10).unwrap()),
        ),
        (
            "dop853-projection",
            ConstrainedMethod::new(
                ConstrainedInfo::find("dop853-projection").unwrap(),
                1e-10,
                100_000,
            )
            .unwrap(),
        ),
        (
            "lagrange-dalembert",
            ConstrainedMethod::new(
                ConstrainedInfo::find("lagrange-dalembert").unwrap(),
                1000.0,
                100_000,
            )
            .unwrap(),
        ),
    ]
}

/// The coefficients by expression are the Rust-written ones: the same operations (`−sin ϑ`,
/// `cos ϑ`, `0`; `−y`, `0`, `1`) give the same numbers, exactly; the Lagrangians agree to
/// `16 ε` times the sum of the magnitudes of their terms (a dozen roundings on each side); the
/// integrability test (Frobenius, on the forms by AD) finds the blade non-holonomic and the
/// term `b = c·t` rheonomic, as it does for the Rust sleigh.
#[test]
fn pfaffian_rows_by_expression_are_the_rust_rows() {
    let sys = expression_sleigh();
    let sleigh = ChaplyginSleigh::new(2.0, 0.5, 1.0).unwrap();
    let particle = NonholonomicParticle::new(0.7, 1.3, 0.2).unwrap();
    let p_rows = ExpressionPfaffian::<3, 1>::new(
        &[["-y", "0", "1"]],
        None::<&[&str]>,
        &["x", "y", "z"],
        &[],
    )
    .unwrap();
    let mut worst = 0.0f64;
    for a in points(200, 2.0) {
        let q = SVector::from([a[0], a[1], 3.0 * a[2]]);
        let v = SVector::from([a[3], a[0] * a[1], a[2] - a[3]]);
        assert_eq!(sys.constraints.forms(0.0, &q), sleigh.forms(0.0, &q));
        assert_eq!(p_rows.forms(0.0, &q), particle.forms(0.0, &q));
        let (e, r) = (
            sys.lagrangian.lagrangian(0.0, &q, &v),
            sleigh.lagrangian(0.0, &q, &v),
        );
        let scale = v[0] * v[0] + v[1] * v[1] + (v[2] * (v[0].abs() + v[1].abs())) + v[2] * v[2];
        worst = worst.max((e - r).abs() / scale);
        assert!((e - r).abs() <= 16.0 * EPS * scale, "L: {e} vs {r}");
    }
    println!("sleigh Lagrangian by expression vs Rust: max |ΔL|/Σ|terms| = {worst:e} (≤ 16 ε)");
    let samples: Vec<(f64, SVector<f64, 3>)> = points(5, 2.0)
        .iter()
        .map(|a| (a[0], SVector::from([a[1], a[2], a[3]])))
        .collect();
    let by_expression = classify(&sys.constraints, &samples).unwrap();
    let rust = classify(&sleigh, &samples).unwrap();
    assert_eq!(by_expression, rust);
    assert!(!by_expression.holonomic && by_expression.catastatic);
    let driven = ExpressionPfaffian::<3, 1>::new(
        &[SLEIGH_ROW],
        Some(&["c*t"][..]),
        &["x", "y", "th"],
        &[("c", 0.3)],
    )
    .unwrap();
    let k = classify(&driven, &samples).unwrap();
    assert!(!k.catastatic && !k.scleronomic && !k.holonomic, "{k:?}");
}

/// The expression sleigh run by each constrained method against the catalogue's Rust-written
/// sleigh: both evaluate the same mathematics with different association orders, so their fields
/// differ by a few ε relative (the multiplier system `[M Bᵀ; B 0]` has condition ≈ 10 here);
/// the force-free sleigh relaxes to straight motion (`v` and `ϑ̇` contract, `x, y, ϑ` integrate
/// them), so the differences accumulate at most linearly: `|Δ| ≤ n · 64 ε · (1 + t) · max|z|`
/// over `n` steps. Against the closed form `v = tanh t`, `ϑ̇ = √2/cosh t`,
/// `ϑ = 2 arctan(tanh(t/2))` (`v₀ = 1`, `a = 1`) [Hamel art. 238] the tolerance-controlled
/// DOP853 runs are within `n · rtol · (1 + max|z|)` (local errors at most `rtol` relative,
/// not amplified by the contracting flow).
#[test]
fn expression_sleigh_runs_as_the_rust_sleigh_and_the_closed_form() {
    let sys = expression_sleigh();
    let sleigh = ChaplyginSleigh::new(2.0, 0.5, 1.0).unwrap();
    let rust = Constrained::new(sleigh, sleigh);
    let q0 = SVector::zeros();
    let v0 = SVector::from([0.0, 0.0, 2f64.sqrt()]);
    let t1 = 12.0;
    for (name, method) in constrained_methods() {
        let (a, work, _) = method.run(&sys, 0.0, q0, v0, t1, 1e-12, None).unwrap();
        let (b, work_rust, _) = method.run(&rust, 0.0, q0, v0, t1, 1e-12, None).unwrap();
        assert_eq!(work.steps, work_rust.steps, "{name}: the same steps");
        let scale = 1.0 + b.q.amax().max(b.p.amax());
        let d = (a.q - b.q).amax().max((a.p - b.p).amax());
        let bound = work.steps as f64 * 64.0 * EPS * (1.0 + t1) * scale;
        println!(
            "sleigh by expression vs Rust, {name}, {} steps: |Δ| = {d:e} (bound {bound:e})",
            work.steps
        );
        assert!(d <= bound, "{name}: {d:e} > {bound:e}");
    }
    let dop = ConstrainedMethod::Reduced(Dop853::new(1e-12, 1e-12).unwrap());
    for t in [0.5, 2.0, 8.0] {
        let (z, work, _) = dop.run(&sys, 0.0, q0, v0, t, 1e-12, None).unwrap();
        let (v, w, th) = sleigh.free_motion(1.0, t).unwrap();
        let (s, c) = z.q[2].sin_cos();
        let got = [z.p[0] * c + z.p[1] * s, z.p[2], z.q[2]];
        let err = (got[0] - v)
            .abs()
            .max((got[1] - w).abs())
            .max((got[2] - th).abs());
        let tol = work.steps as f64 * 1e-12 * (1.0 + z.q.amax().max(z.p.amax()));
        println!(
            "sleigh by expression vs closed form, t = {t}, {} steps: {err:e} (tol {tol:e})",
            work.steps
        );
        assert!(err <= tol, "t = {t}: {err:e} > {tol:e}");
    }
}

/// A rheonomic Pfaffian constraint, the non-holonomic particle with the drive
/// `ż − y ẋ − β cos t = 0` (`b = −β cos t`), written in Rust.
#[derive(Clone, Copy, Debug)]
struct DrivenParticle(NonholonomicParticle, f64);

impl PfaffianConstraints<3, 1> for DrivenParticle {
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 3>,
    ) -> (hamilton_jacobi::nalgebra::SMatrix<D, 1, 3>, SVector<D, 1>) {
        let (a, _) = self.0.forms(t, q);
        (a, SVector::from([-t.cos() * self.1]))
    }
}

/// The term `b(t, q)` of `pfaffian_rhs`: the driven particle by expression (Lagrangian, rows
/// and term) against the Rust particle with the Rust drive, each constrained method, same bound
/// as the sleigh's (the motion in `y` is an oscillation, the drive enters `ż` additively: no
/// exponential growth over `t = 6`).
#[test]
fn rheonomic_pfaffian_term_runs_as_the_rust_drive() {
    let (bf, kappa, k, beta) = (0.7, 1.3, 0.2, 0.3);
    let coordinates = ["x", "y", "z"];
    let parameters = [("B", bf), ("kappa", kappa), ("k", k), ("beta", beta)];
    let l = ExpressionLagrangian::<3>::new(
        "(v_x^2 + v_y^2 + v_z^2)/2 + B*x*v_y - kappa*y^2/2 - k*y",
        &coordinates,
        None,
        &parameters,
    )
    .unwrap();
    let c = ExpressionPfaffian::<3, 1>::new(
        &[["-y", "0", "1"]],
        Some(&["-beta*cos(t)"][..]),
        &coordinates,
        &parameters,
    )
    .unwrap();
    let sys = Constrained::new(l, c);
    let particle = NonholonomicParticle::new(bf, kappa, k).unwrap();
    let rust = Constrained::new(particle, DrivenParticle(particle, beta));
    let q0 = SVector::from([0.0, 0.5, 0.0]);
    let v0 = SVector::from([0.4, 0.2, 0.5 * 0.4 + beta]);
    let t1 = 6.0;
    for (name, method) in constrained_methods() {
        let (a, work, _) = method.run(&sys, 0.0, q0, v0, t1, 1e-12, None).unwrap();
        let (b, work_rust, _) = method.run(&rust, 0.0, q0, v0, t1, 1e-12, None).unwrap();
        assert_eq!(work.steps, work_rust.steps, "{name}: the same steps");
        let scale = 1.0 + b.q.amax().max(b.p.amax());
        let d = (a.q - b.q).amax().max((a.p - b.p).amax());
        let bound = work.steps as f64 * 64.0 * EPS * (1.0 + t1) * scale;
        println!(
            "driven particle by expression vs Rust, {name}, {} steps: |Δ| = {d:e} (bound \
             {bound:e})",
            work.steps
        );
        assert!(d <= bound, "{name}: {d:e} > {bound:e}");
        // The drive is felt: ż − y ẋ = β cos t at the end (DOP853 keeps the constraint to its
        // tolerance).
        if name == "dop853" {
            let r = b.p[2] - b.q[1] * b.p[0] - beta * t1.cos();
            assert!(r.abs() < 1e-8, "constraint residual {r:e}");
        }
    }
}

/// The built-in sleigh by expression is the catalogue's sleigh: the same end state from the
/// DOP853 methods (the scene path: keys, dispatch, initial checks), within the bound of
/// `expression_sleigh_runs_as_the_rust_sleigh_and_the_closed_form` with `n ≤ 10⁴` steps; the
/// scene runs every method it names.
#[test]
fn sleigh_expression_builtin_scene_matches_the_catalogue_sleigh() {
    let catalogue = Catalogue::builtin();
    let text = scene::builtin_text("chaplygin-sleigh-expression").unwrap();
    let table: toml::Table = toml::from_str(text).unwrap();
    let mut by_expression = catalogue
        .build("s.toml", table["system"].as_table().unwrap())
        .unwrap();
    let rust_table: toml::Table = toml::from_str("name = \"chaplygin-sleigh\"").unwrap();
    let mut rust = catalogue.build("r.toml", &rust_table).unwrap();
    let t1 = 12.0;
    // (Lagrange–d'Alembert's history ends at a midpoint state; the direct comparison above
    // covers it.)
    for (key, knob) in [("dop853", 1e-10), ("dop853-projection", 1e-10)] {
        let a = last_state(&mut by_expression, key, knob, t1);
        let b = last_state(&mut rust, key, knob, t1);
        let d = max_diff(&a.0, &b.0).max(max_diff(&a.1, &b.1));
        let scale = 1.0 + b.0.iter().chain(&b.1).fold(0.0f64, |m, x| m.max(x.abs()));
        let bound = 1e4 * 64.0 * EPS * (1.0 + t1) * scale;
        println!("chaplygin-sleigh-expression vs chaplygin-sleigh, {key}: |Δ| = {d:e}");
        assert!(d <= bound, "{key}: {d:e} > {bound:e}");
    }
    let s = scene::parse("chaplygin-sleigh-expression", text, &catalogue).unwrap();
    let out = std::env::temp_dir().join(format!("hj-pfaffian-scene-{}", std::process::id()));
    let summary = s.run(&quick(&out)).unwrap();
    assert!(
        !summary.markdown.contains("- method["),
        "{}",
        summary.markdown
    );
    std::fs::remove_dir_all(&out).ok();
}

const SLEIGH_SCENE: &str = r#"
[system]
lagrangian = "m/2*(v_x^2 + v_y^2) + m*s*v_th*(v_y*cos(th) - v_x*sin(th)) + I/2*v_th^2"
coordinates = ["x", "y", "th"]
parameters = { m = 2.0, s = 0.5, I = 1.0 }
pfaffian = [["-sin(th)", "cos(th)", "0"]]
q = [0.0, 0.0, 0.0]
v = [0.0, 0.0, 1.4142135623730951]
"#;

#[test]
fn malformed_pfaffian_scenes_name_the_key() {
    assert!(case_of(SLEIGH_SCENE)
        .unwrap()
        .supports(kind("lagrange-dalembert")));
    let row = "pfaffian = [[\"-sin(th)\", \"cos(th)\", \"0\"]]";
    // Dependent rows at the initial configuration, named.
    let e = error_of(&SLEIGH_SCENE.replace(
        row,
        "pfaffian = [[\"-sin(th)\", \"cos(th)\", \"0\"], [\"-2*sin(th)\", \"2*cos(th)\", \"0\"]]",
    ));
    assert_names(&e, "system.q", &["rank deficient", "rows [1]"]);
    // A row independent elsewhere but not at q₀ (x = 0).
    let e = error_of(&SLEIGH_SCENE.replace(
        row,
        "pfaffian = [[\"-sin(th)\", \"cos(th)\", \"0\"], [\"0\", \"x\", \"0\"]]",
    ));
    assert_names(&e, "system.q", &["rows [1]"]);
    // A row not finite at q₀, named with its entry.
    let e = error_of(&SLEIGH_SCENE.replace("\"0\"]]", "\"1/x\"]]"));
    assert_names(&e, "system.q", &["a[1][3]", "1/x"]);
    // Initial velocities off the constraint: the residual.
    let e = error_of(&SLEIGH_SCENE.replace("v = [0.0, 0.0,", "v = [0.0, 0.25,"));
    assert_names(&e, "system.v", &["residual [0.25]"]);
    let e = error_of(&format!("{SLEIGH_SCENE}pfaffian_rhs = [\"0.5\"]\n"));
    assert_names(&e, "system.v", &["residual [0.5]"]);
    // Shapes and types.
    let e = error_of(&SLEIGH_SCENE.replace(row, "pfaffian = [[\"-sin(th)\", \"cos(th)\"]]"));
    assert_names(&e, "system.pfaffian", &["row 1", "2 coefficients for 3"]);
    let e = error_of(&SLEIGH_SCENE.replace(row, "pfaffian = [[\"-sin(th)\", 1.0, \"0\"]]"));
    assert_names(&e, "system.pfaffian[0][1]", &["expected a string"]);
    let e = error_of(&SLEIGH_SCENE.replace(row, "pfaffian = [\"-sin(th)\"]"));
    assert_names(&e, "system.pfaffian[0]", &["row"]);
    let e = error_of(&SLEIGH_SCENE.replace(
        row,
        "pfaffian = [[\"1\", \"0\", \"0\"], [\"0\", \"1\", \"0\"], [\"0\", \"0\", \"1\"]]",
    ));
    assert_names(&e, "system.pfaffian", &["3 rows on 3 coordinates"]);
    let e = error_of(&format!("{SLEIGH_SCENE}pfaffian_rhs = [\"0\", \"0\"]\n"));
    assert_names(&e, "system.pfaffian_rhs", &["2 terms for 1 rows"]);
    let e = error_of(&SLEIGH_SCENE.replace(row, "pfaffian_rhs = [\"0\"]"));
    assert_names(&e, "system.pfaffian_rhs", &["need their coefficients"]);
    let e = error_of(&format!("{SLEIGH_SCENE}constraints = [\"x\"]\n"));
    assert_names(&e, "system.pfaffian", &["either"]);
    // Parse errors: the column and the entry.
    let e = error_of(&SLEIGH_SCENE.replace("\"cos(th)\"", "\"cos(th\""));
    assert_names(&e, "system.pfaffian", &["column", "a[1][2]"]);
    let e = error_of(&format!("{SLEIGH_SCENE}pfaffian_rhs = [\"w\"]\n"));
    assert_names(&e, "system.pfaffian", &["column", "b[1]", "`w`"]);
}

fn error_of(text: &str) -> SceneError {
    case_of(text).err().expect("a malformed system is refused")
}

fn assert_names(e: &SceneError, key: &str, words: &[&str]) {
    let line = e.to_string();
    assert!(!line.contains('\n'), "not one line: {line}");
    assert_eq!(e.key, key, "{line}");
    for w in words {
        assert!(line.contains(w), "{line} lacks {w:?}");
    }
}

#[test]
fn malformed_expression_scenes_name_the_key() {
    // Two forms at once.
    let e = error_of(&HH_LAGRANGIAN.replace("[system]\n", "[system]\nhamiltonian = \"x\"\n"));
    assert_names(&e, "system.lagrangian", &["one form", "hamiltonian"]);
    // A key of another form is unknown.
    let e = error_of(&HH_LAGRANGIAN.replace("v = [", "p = ["));
    assert_names(&e, "system.v", &["missing"]);
    let e = error_of(&format!("{HH_LAGRANGIAN}p = [0.0, 0.0]\n"));
    assert_names(&e, "system.p", &["unknown key"]);
    let e = error_of(&format!("{J2_SCENE}momenta = [\"a\", \"b\", \"c\"]\n"));
    assert_names(&e, "system.momenta", &["unknown key"]);
    // Parse errors give the column.
    let e = error_of(&HH_LAGRANGIAN.replace("- x^2*y", "- x^^2*y"));
    assert_names(&e, "system.lagrangian", &["column"]);
    let e = error_of(&J2_SCENE.replace("(x^2 + y^2 - 2*z^2)", "(x^2 + y^2 - 2*w^2)"));
    assert_names(&e, "system.disturbing_function", &["column", "`w`"]);
    let q0 = SVector::from([0.6, 0.0, -0.8]);
    let v0 = SVector::from([0.0, 0.5, 0.0]);
    let e = error_of(&spherical_scene(&q0, &v0).replace("- l^2\"", "- l^2 +\""));
    assert_names(&e, "system.constraints", &["column"]);
    // Non-finite at the initial state: L, R and the constraints.
    let e = error_of(&HH_LAGRANGIAN.replace("y^3/3", "y^3/3 + ln(x)"));
    assert_names(&e, "system.q", &["ln(x)"]);
    let e = error_of(&J2_SCENE.replace("q = [1.2, 0.0, 0.0]", "q = [0.0, 0.0, 0.0]"));
    assert_names(&e, "system.q", &[]);
    let e = error_of(&spherical_scene(&q0, &v0).replace("- l^2\"", "- l^2 + 1/y\""));
    assert_names(&e, "system.q", &[]);
    // Off the constraint, or moving off it.
    let e = error_of(&spherical_scene(&SVector::from([0.6, 0.0, -0.9]), &v0));
    assert_names(&e, "system.q", &["not on the constraint"]);
    let e = error_of(&spherical_scene(&q0, &SVector::from([0.1, 0.5, 0.0])));
    assert_names(&e, "system.v", &["constraint"]);
    // Too many constraints, a singular mass matrix, `mu` twice.
    let e = error_of(&spherical_scene(&q0, &v0).replace(
        "constraints = [\"x^2 + y^2 + z^2 - l^2\"]",
        "constraints = [\"x\", \"y\", \"z\"]",
    ));
    assert_names(
        &e,
        "system.constraints",
        &["3 constraints on 3 coordinates"],
    );
    let e = error_of(&HH_LAGRANGIAN.replace("(v_x^2 + v_y^2)/2", "v_x^2/2"));
    assert_names(&e, "system.q", &["singular"]);
    let e = error_of(&J2_SCENE.replace("{ J2", "{ mu = 2.0, J2"));
    assert_names(&e, "system.parameters.mu", &["mu"]);
    let e = error_of(&J2_SCENE.replace("q = [1.2, 0.0, 0.0]", "q = [1.2, 0.0, 0.0, 0.0]"));
    assert_names(&e, "system.coordinates", &["2 (the plane) or 3"]);
}

/// The disturbing function in the plane: two coordinates from the length of `q`, Kepler's
/// splittings still apply.
#[test]
fn planar_disturbing_function_scene() {
    let text = J2_SCENE
        .replace(
            "(x^2 + y^2 - 2*z^2)/(x^2 + y^2 + z^2)^2.5",
            "(x^2 + y^2)^(-1.5)",
        )
        .replace("q = [1.2, 0.0, 0.0]", "q = [1.2, 0.0]")
        .replace("p = [0.0, 0.85, 0.35]", "p = [0.0, 0.85]");
    let case = case_of(&text).unwrap();
    assert!(case.supports(kind("wisdom-holman")));
    let e = case.energy(0.0, &[1.2, 0.0], &[0.0, 0.85]).unwrap();
    let want = 0.85f64.powi(2) / 2.0 - 1.0 / 1.2 - 1.08e-3 * 0.81 / 2.0 / 1.2f64.powi(3);
    assert!((e - want).abs() <= 8.0 * EPS, "{e} vs {want}");
}

/// Each expression form of the scene template (`hj new`), uncommented, is a system that builds.
#[test]
fn template_expression_forms_build() {
    let template = hamilton_jacobi::cli::scene_template("t");
    let mut forms: Vec<Vec<&str>> = vec![Vec::new()];
    for line in template.lines() {
        match line.strip_prefix("#   ") {
            Some(l) => forms.last_mut().unwrap().push(l),
            None if !forms.last().unwrap().is_empty() => forms.push(Vec::new()),
            None => {}
        }
    }
    forms.retain(|f| !f.is_empty());
    assert_eq!(forms.len(), 4, "{forms:?}");
    for form in forms {
        let text = format!("[system]\n{}\n", form.join("\n"));
        let case = case_of(&text).unwrap_or_else(|e| panic!("{e}\n{text}"));
        assert!(case.supports(kind("dop853")), "{text}");
    }
}

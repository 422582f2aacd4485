//! Impulsive motion (SPEC M38–M40) against independent oracles: Ardema's three hinged rods
//! (T35) and the struck rod (T36) in closed form, a relativistic particle (momentum jump in
//! closed form), Carnot's energy loss for a suddenly imposed constraint, the elevator floor (a
//! live constraint), and the extremum theorems of Gauss, Kelvin and Bertrand by minimisation with
//! `argmin`'s Nelder–Mead (derivative-free, independent of the linear algebra of the crate).

use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use hamilton_jacobi::constraints::PfaffianConstraints;
use hamilton_jacobi::impulse::{
    apply_impulse, generalized_impulse, impose_constraints, ImpactPoint,
};
use hamilton_jacobi::nalgebra::{DVector, SMatrix, SVector};
use hamilton_jacobi::num_dual::DualNum;
use hamilton_jacobi::systems::HingedRods;
use hamilton_jacobi::{Error, Lagrangian};

const EPS: f64 = f64::EPSILON;

/// SPEC T35: rods AB, BC, CD of mass M at rest, impulse P at A normal to the line:
/// `(p, q, r, s) = (52, −14, 4, −2) P/(15M)`, `T⁺ = 26 P²/(15M)`.
#[test]
fn three_hinged_rods_struck_at_one_end() {
    for (m, p) in [(1.0, 1.0), (2.5, -0.7), (1e-3, 4e2)] {
        let rods = HingedRods::<4>::new(m).unwrap();
        let jump = apply_impulse(
            &rods,
            0.0,
            &SVector::zeros(),
            &SVector::zeros(),
            &SVector::from([p, 0.0, 0.0, 0.0]),
        )
        .unwrap();
        let expected = SVector::from([52.0, -14.0, 4.0, -2.0]) * (p / (15.0 * m));
        // A 4×4 solve with condition number ≈ 20: a few tens of ulps of the largest velocity.
        let tol = 64.0 * EPS * expected.amax();
        assert!(
            (jump.velocity_after - expected).amax() < tol,
            "{}",
            jump.velocity_after
        );
        let t_plus = 26.0 * p * p / (15.0 * m);
        assert!((jump.energy_after - t_plus).abs() < 64.0 * EPS * t_plus);
        assert_eq!(jump.energy_before, 0.0);
        // From rest, T⁺ = ½ P̂·q̇⁺ (M40).
        assert!(
            (jump.energy_change() - 0.5 * p * jump.velocity_after[0]).abs() < 64.0 * EPS * t_plus
        );
    }
}

/// The point at `nℓ` from the first end of a rod whose ends have the normal displacements `q`.
struct AlongRod(f64);
impl ImpactPoint<2, 1> for AlongRod {
    fn position<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> SVector<D, 1> {
        SVector::from([q[0] * (1.0 - self.0) + q[1] * self.0])
    }
}

/// SPEC T36: a rod struck normally at `nℓ` from one end: end velocities `v(4 − 6n)` and
/// `v(6n − 2)` with `v = P/m`; instance `n = 0.25`, `v = 1`: 2.5 and −0.5.
#[test]
fn rod_struck_normally_at_a_fraction_of_its_length() {
    let rod = HingedRods::<2>::new(1.0).unwrap();
    for n in [0.0, 0.25, 0.5, 1.0 / 3.0, 0.9] {
        let p_hat =
            generalized_impulse(&AlongRod(n), 0.0, &SVector::zeros(), &SVector::from([1.0]))
                .unwrap();
        assert!((p_hat - SVector::from([1.0 - n, n])).amax() <= EPS);
        let jump = apply_impulse(&rod, 0.0, &SVector::zeros(), &SVector::zeros(), &p_hat).unwrap();
        let expected = SVector::from([4.0 - 6.0 * n, 6.0 * n - 2.0]);
        assert!(
            (jump.velocity_after - expected).amax() < 16.0 * EPS * 4.0,
            "n = {n}"
        );
    }
}

/// A relativistic particle, `L = −m√(1 − v²)` (c = 1): the momentum `mv/√(1 − v²)` jumps by `P`,
/// so `v⁺ = p⁺/√(m² + p⁺²)` — a Lagrangian not quadratic in `q̇`, solved by Newton's method.
struct Relativistic(f64);
impl Lagrangian<1> for Relativistic {
    fn lagrangian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 1>,
        v: &SVector<D, 1>,
    ) -> D {
        -(D::from(1.0) - v[0] * v[0]).sqrt() * self.0
    }
}

#[test]
fn a_momentum_jump_of_a_relativistic_particle() {
    let (m, v0) = (2.0, 0.6);
    for p in [0.5, 3.0, -4.0] {
        let jump = apply_impulse(
            &Relativistic(m),
            0.0,
            &SVector::zeros(),
            &SVector::from([v0]),
            &SVector::from([p]),
        )
        .unwrap();
        let p_plus = m * v0 / (1.0 - v0 * v0).sqrt() + p;
        let v_plus = p_plus / (m * m + p_plus * p_plus).sqrt();
        assert!((jump.velocity_after[0] - v_plus).abs() < 16.0 * EPS, "{p}");
        // h = m/√(1 − v²): the energy, in closed form.
        let h = |v: f64| m / (1.0 - v * v).sqrt();
        assert!((jump.energy_change() - (h(v_plus) - h(v0))).abs() < 64.0 * EPS * h(v_plus));
    }
}

/// `K` constant Pfaffian constraints `B q̇ + b = 0` on the chain's four points.
struct Forms<const K: usize> {
    rows: [[f64; 4]; K],
    b: [f64; K],
}

impl<const K: usize> PfaffianConstraints<4, K> for Forms<K> {
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 4>,
    ) -> (SMatrix<D, K, 4>, SVector<D, K>) {
        (
            SMatrix::from_fn(|r, c| D::from(self.rows[r][c])),
            SVector::from_fn(|r, _| D::from(self.b[r])),
        )
    }
}

/// The last point of the chain suddenly held (`v₄ = 0`): an inert constraint.
const HOLD_LAST: Forms<1> = Forms {
    rows: [[0.0, 0.0, 0.0, 1.0]],
    b: [0.0],
};

/// The first point given the velocity `V` (a live constraint `v₁ − V = 0`).
fn drive_first(v: f64) -> Forms<1> {
    Forms {
        rows: [[1.0, 0.0, 0.0, 0.0]],
        b: [-v],
    }
}

/// `½ xᵀ a x` for the chain's mass matrix.
fn kinetic(rods: &HingedRods<4>, v: &SVector<f64, 4>) -> f64 {
    rods.value(0.0, &SVector::zeros(), v).unwrap()
}

/// Carnot's theorem: a constraint imposed suddenly on a moving system (no applied impulse) loses
/// the kinetic energy of the velocity change, `T⁻ − T⁺ = ½ Δᵀ a Δ`; the constraint holds after it,
/// and the constraint impulse is `a Δ` projected on the constraint.
#[test]
fn a_suddenly_held_point_loses_the_energy_of_the_velocity_change() {
    let rods = HingedRods::<4>::new(1.5).unwrap();
    let v0 = SVector::from([0.3, -1.2, 0.8, 2.0]);
    let jump = impose_constraints(
        &rods,
        &HOLD_LAST,
        0.0,
        &SVector::zeros(),
        &v0,
        &SVector::zeros(),
    )
    .unwrap();
    assert!(jump.velocity_after[3].abs() < 16.0 * EPS * v0.amax());
    let d = jump.velocity_jump();
    let loss = kinetic(&rods, &d);
    assert!(
        (jump.energy_before - jump.energy_after - loss).abs() < 64.0 * EPS * jump.energy_before
    );
    // a Δ = Bᵀ λ̂: only the held point receives an impulse.
    let a = rods.mass_matrix(0.0, &SVector::zeros(), &v0).unwrap();
    let ad = a * d;
    assert!(ad.rows(0, 3).amax() < 64.0 * EPS * v0.amax());
    assert!((ad[3] - jump.constraint_impulses[0]).abs() < 64.0 * EPS * v0.amax());
}

/// Nelder–Mead on a function of the free velocities.
struct Cost<F: Fn(&DVector<f64>) -> f64>(F);
impl<F: Fn(&DVector<f64>) -> f64> CostFunction for Cost<F> {
    type Param = DVector<f64>;
    type Output = f64;
    fn cost(&self, x: &DVector<f64>) -> Result<f64, argmin::core::Error> {
        Ok((self.0)(x))
    }
}

fn minimise(f: impl Fn(&DVector<f64>) -> f64, start: DVector<f64>) -> DVector<f64> {
    let n = start.len();
    let mut simplex = vec![start.clone()];
    for i in 0..n {
        let mut v = start.clone();
        v[i] += 0.5;
        simplex.push(v);
    }
    let solver = NelderMead::new(simplex).with_sd_tolerance(1e-32).unwrap();
    let res = Executor::new(Cost(f), solver)
        .configure(|s| s.max_iters(20_000))
        .run()
        .unwrap();
    res.state().get_best_param().unwrap().clone()
}

/// Gauss's minimum (M40): with the last point held and an impulse at the first, the actual jump
/// minimises `Z = ½ (Δ − a⁻¹P̂)ᵀ a (Δ − a⁻¹P̂)` over the admissible jumps (`Δ₄ = −v₄⁻`).
/// Nelder–Mead reaches the minimiser of a quadratic to about the square root of its function
/// tolerance: 1e-6 here.
#[test]
fn the_jump_minimises_gauss_constraint() {
    let rods = HingedRods::<4>::new(1.0).unwrap();
    let v0 = SVector::from([0.1, 0.2, -0.3, 0.4]);
    let p_hat = SVector::from([1.0, 0.0, 0.0, 0.0]);
    let jump = impose_constraints(&rods, &HOLD_LAST, 0.0, &SVector::zeros(), &v0, &p_hat).unwrap();
    let a = rods.mass_matrix(0.0, &SVector::zeros(), &v0).unwrap();
    let free = a.try_inverse().unwrap() * p_hat;
    let z = |x: &DVector<f64>| {
        let d = SVector::from([x[0], x[1], x[2], -v0[3]]) - free;
        0.5 * (d.transpose() * a * d)[0]
    };
    let best = minimise(z, DVector::zeros(3));
    let d = jump.velocity_jump();
    for i in 0..3 {
        assert!((best[i] - d[i]).abs() < 1e-6, "{best} {d}");
    }
}

/// Kelvin (M40): from rest with the first point given the velocity `V` (and no other impulse),
/// the actual motion has the least kinetic energy among the motions with that velocity.
/// Bertrand: the same impulse with the last point held gives less energy than without, by the
/// kinetic energy of the difference (an identity, to rounding).
#[test]
fn kelvin_and_bertrand() {
    let rods = HingedRods::<4>::new(1.0).unwrap();
    let zero = SVector::<f64, 4>::zeros();
    let jump = impose_constraints(&rods, &drive_first(1.0), 0.0, &zero, &zero, &zero).unwrap();
    assert!((jump.velocity_after[0] - 1.0).abs() < 16.0 * EPS);
    let t = |x: &DVector<f64>| kinetic(&rods, &SVector::from([1.0, x[0], x[1], x[2]]));
    let best = minimise(t, DVector::zeros(3));
    for i in 0..3 {
        assert!((best[i] - jump.velocity_after[i + 1]).abs() < 1e-6);
    }
    // The live constraint's impulse is the blow needed at the first point: P = ∂T/∂v₁⁺.
    let p1 = rods.momentum(0.0, &zero, &jump.velocity_after).unwrap()[0];
    assert!((jump.constraint_impulses[0] - p1).abs() < 64.0 * EPS);

    let p_hat = SVector::from([0.7, 0.0, -0.2, 0.0]);
    let free = apply_impulse(&rods, 0.0, &zero, &zero, &p_hat).unwrap();
    let held = impose_constraints(&rods, &HOLD_LAST, 0.0, &zero, &zero, &p_hat).unwrap();
    let diff = kinetic(&rods, &(free.velocity_after - held.velocity_after));
    assert!(held.energy_after < free.energy_after);
    assert!((free.energy_after - held.energy_after - diff).abs() < 64.0 * EPS * free.energy_after);
}

/// Free impulses change the energy by `P̂·(q̇⁺ + q̇⁻)/2` (M40), from any state.
#[test]
fn energy_change_of_free_impulses() {
    let rods = HingedRods::<4>::new(0.8).unwrap();
    let v0 = SVector::from([1.0, -0.5, 0.25, 2.0]);
    let p_hat = SVector::from([0.3, -1.0, 0.0, 0.6]);
    let jump = apply_impulse(&rods, 0.0, &SVector::zeros(), &v0, &p_hat).unwrap();
    let expected = p_hat.dot(&(jump.velocity_after + v0)) * 0.5;
    assert!((jump.energy_change() - expected).abs() < 64.0 * EPS * jump.energy_after);
}

/// Two copies of the same constraint are dependent: a typed error naming the configuration.
#[test]
fn bad_impacts_are_typed_errors() {
    let rods = HingedRods::<4>::new(1.0).unwrap();
    let zero = SVector::<f64, 4>::zeros();
    let e = impose_constraints(
        &rods,
        &Forms {
            rows: [[0.0, 0.0, 0.0, 1.0]; 2],
            b: [0.0; 2],
        },
        0.0,
        &zero,
        &zero,
        &zero,
    )
    .unwrap_err();
    assert!(matches!(e, Error::Singular { .. }), "{e}");
    let nan = SVector::from([f64::NAN, 0.0, 0.0, 0.0]);
    assert!(apply_impulse(&rods, 0.0, &zero, &zero, &nan).is_err());
    assert!(apply_impulse(&rods, 0.0, &zero, &nan, &zero).is_err());
    assert!(apply_impulse(&rods, f64::INFINITY, &zero, &zero, &zero).is_err());
    assert!(HingedRods::<4>::new(0.0).is_err());
    assert!(HingedRods::<1>::new(1.0).is_err());
    // A relativistic particle pushed to v ≥ 1 from an impossible state is refused.
    assert!(apply_impulse(
        &Relativistic(1.0),
        0.0,
        &SVector::zeros(),
        &SVector::from([1.5]),
        &SVector::from([1.0])
    )
    .is_err());
}

mod common;
use proptest::prelude::*;

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..common::config(0x1a9u64) })]

    /// M40 as properties of the solutions, for random states and blows on three hinged rods:
    /// free impulses change the energy by `P̂·(q̇⁺ + q̇⁻)/2`; holding the last point after the same
    /// blow (Bertrand, from rest) lowers `T⁺` by the kinetic energy of the difference; a held
    /// point without a blow (Carnot) loses the energy of the velocity change.
    #[test]
    fn extremum_theorems_hold_for_random_impacts(
        v in prop::array::uniform4(-3.0..3.0f64),
        p in prop::array::uniform4(-3.0..3.0f64),
        m in 0.1..10.0f64,
    ) {
        let rods = HingedRods::<4>::new(m).unwrap();
        let (v0, p_hat, zero) = (SVector::from(v), SVector::from(p), SVector::<f64, 4>::zeros());
        let free = apply_impulse(&rods, 0.0, &zero, &v0, &p_hat).unwrap();
        let scale = free.energy_after.max(free.energy_before).max(1e-300);
        let de = p_hat.dot(&(free.velocity_after + v0)) * 0.5;
        prop_assert!((free.energy_change() - de).abs() <= 1e-13 * scale);

        let from_rest = apply_impulse(&rods, 0.0, &zero, &zero, &p_hat).unwrap();
        let held = impose_constraints(&rods, &HOLD_LAST, 0.0, &zero, &zero, &p_hat).unwrap();
        let diff = kinetic(&rods, &(from_rest.velocity_after - held.velocity_after));
        prop_assert!(
            (from_rest.energy_after - held.energy_after - diff).abs()
                <= 1e-13 * from_rest.energy_after.max(1e-300)
        );

        let carnot = impose_constraints(&rods, &HOLD_LAST, 0.0, &zero, &v0, &zero).unwrap();
        let loss = kinetic(&rods, &carnot.velocity_jump());
        prop_assert!(
            (carnot.energy_before - carnot.energy_after - loss).abs()
                <= 1e-13 * carnot.energy_before.max(1e-300)
        );
    }
}

/// Two bobs of a double pendulum (lengths 1.2 and 0.7), written once as a particle system.
struct TwoBobs;
impl hamilton_jacobi::particles::ParticleSystem<2, 2> for TwoBobs {
    fn masses(&self) -> [f64; 2] {
        [1.0, 0.5]
    }
    fn positions<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 2>,
    ) -> [hamilton_jacobi::nalgebra::Vector3<D>; 2] {
        use hamilton_jacobi::nalgebra::Vector3;
        let (s1, c1) = q[0].sin_cos();
        let (s2, c2) = q[1].sin_cos();
        let first = Vector3::new(s1 * 1.2, -c1 * 1.2, D::from(0.0));
        [
            first,
            first + Vector3::new(s2 * 0.7, -c2 * 0.7, D::from(0.0)),
        ]
    }
}

/// A blow on a particle the system already defines: the generalized impulse through
/// `ParticleOf` against the closed form `P̂_i = ℓ_i (P_x cos θ_i + P_y sin θ_i)` and against the
/// projection of the same vector as an applied force (`particles::generalized_forces`).
#[test]
fn blow_on_a_particle_of_a_particle_system() {
    use hamilton_jacobi::impulse::ParticleOf;
    use hamilton_jacobi::nalgebra::Vector3;
    use hamilton_jacobi::particles::checked_generalized_forces;
    let q = SVector::from([0.4, -0.9]);
    let p = Vector3::new(0.8, -0.3, 0.0);
    let bob = ParticleOf::<_, 2>::new(&TwoBobs, 1).unwrap();
    let got = generalized_impulse(&bob, 0.0, &q, &p).unwrap();
    let want = SVector::from([
        1.2 * (p.x * q[0].cos() + p.y * q[0].sin()),
        0.7 * (p.x * q[1].cos() + p.y * q[1].sin()),
    ]);
    assert!((got - want).norm() <= 4.0 * f64::EPSILON * want.norm());
    let as_force = checked_generalized_forces(&TwoBobs, 0.0, &q, &[Vector3::zeros(), p]).unwrap();
    assert!((got - as_force).norm() <= 4.0 * f64::EPSILON * want.norm());
    assert!(matches!(
        ParticleOf::<_, 2>::new(&TwoBobs, 2),
        Err(hamilton_jacobi::Error::InvalidInput { .. })
    ));
}

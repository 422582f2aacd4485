//! Integration of constrained systems (SPEC X6, issue 16 §4): RATTLE on holonomic constraints
//! against the exact pendulum, and the non-holonomic integrators' energy and constraint drift.
//!
//! Oracles: the plane pendulum's exact motion by Jacobi elliptic functions
//! ([`PendulumMotion`]), written in an independent (angle) coordinate; energy and constraints
//! are conserved by the exact flow, so their drift along a run is the integrator's.

use hamilton_jacobi::constraints::HolonomicConstraints;
use hamilton_jacobi::integrate::ConstrainedHamiltonian;
use hamilton_jacobi::integrate::{integrate, Control, Each, Problem, Rattle};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::pendulum_exact::PendulumMotion;
use hamilton_jacobi::{DualNum, Error, Hamiltonian};

/// A unit point mass in `ℝᴺ` under gravity `−g e_last`, `H = ½|p|² + g q_last`.
#[derive(Clone, Copy, Debug)]
struct Heavy<const N: usize> {
    g: f64,
}

impl<const N: usize> Hamiltonian<N> for Heavy<N> {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> D {
        p.dot(p) * 0.5 + q[N - 1] * self.g
    }
}

/// The sphere (circle) of radius `l` about the origin: `g = ½(|q|² − l²)`.
#[derive(Clone, Copy, Debug)]
struct Sphere {
    l: f64,
}

impl<const N: usize> HolonomicConstraints<N, 1> for Sphere {
    fn position_constraint<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, N>,
    ) -> SVector<D, 1> {
        SVector::from([(q.dot(q) - self.l * self.l) * 0.5])
    }
}

/// Plane pendulum state in Cartesian coordinates `(x, z)`, angle `θ` from the bottom.
fn cartesian(theta: f64, omega: f64) -> (SVector<f64, 2>, SVector<f64, 2>) {
    let (s, c) = theta.sin_cos();
    (
        SVector::from([s, -c]),
        SVector::from([c * omega, s * omega]),
    )
}

/// RATTLE's error at `t = 2` on the plane pendulum (`g = n² = 4`, amplitude 1 rad) with `steps`.
fn pendulum_error(steps: usize) -> f64 {
    let sys = ConstrainedHamiltonian::new(Heavy::<2> { g: 4.0 }, Sphere { l: 1.0 });
    let (q0, p0) = cartesian(1.0, 0.0);
    let pr = Problem::new(&sys, 0.0, q0, p0, 2.0).unwrap();
    let r = integrate(&pr, &Rattle::new(steps).unwrap(), &mut ()).unwrap();
    let (th, w) = PendulumMotion::new(2.0, 1.0, 0.0)
        .unwrap()
        .state_at(2.0)
        .unwrap();
    let (q, p) = cartesian(th, w);
    (r.last.q - q).amax().max((r.last.p - p).amax())
}

#[test]
fn rattle_is_of_order_two_against_the_exact_pendulum() {
    let errors: Vec<f64> = [50, 100, 200, 400]
        .iter()
        .map(|&n| pendulum_error(n))
        .collect();
    for w in errors.windows(2) {
        let order = (w[0] / w[1]).log2();
        println!(
            "RATTLE pendulum errors {:e} → {:e}: observed order {order:.4}",
            w[0], w[1]
        );
        assert!((order - 2.0).abs() < 0.05, "order {order}");
    }
    assert!(errors[3] < 1e-4, "{errors:?}");
}

#[test]
fn rattle_keeps_the_constraints_at_rounding_and_the_energy_bounded() {
    // Spherical pendulum, 10⁵ steps of h = 0.01 (about 3000 swings).
    let g = 9.81;
    let sys = ConstrainedHamiltonian::new(Heavy::<3> { g }, Sphere { l: 1.0 });
    let (s, c) = 0.8f64.sin_cos();
    let q0 = SVector::from([s, 0.0, -c]);
    let p0 = SVector::from([0.0, 1.7, 0.0]);
    let e0 = sys.hamiltonian.value(0.0, &q0, &p0).unwrap();
    let (mut max_g, mut max_v, mut max_e) = (0.0f64, 0.0f64, 0.0f64);
    let mut lz_drift = 0.0f64;
    let lz0 = q0[0] * p0[1] - q0[1] * p0[0];
    let mut obs = Each(|st: &hamilton_jacobi::State<3>| {
        let (rg, rv) = sys.residuals(st.t, &st.q, &st.p).unwrap();
        max_g = max_g.max(rg);
        max_v = max_v.max(rv);
        let e = sys.hamiltonian.value(st.t, &st.q, &st.p).unwrap();
        max_e = max_e.max((e - e0).abs());
        lz_drift = lz_drift.max((st.q[0] * st.p[1] - st.q[1] * st.p[0] - lz0).abs());
        Control::Continue
    });
    let pr = Problem::new(&sys, 0.0, q0, p0, 1000.0).unwrap();
    let r = integrate(&pr, &Rattle::new(100_000).unwrap(), &mut obs).unwrap();
    println!(
        "RATTLE spherical pendulum 1e5 steps: max|g| {max_g:e}, max|G q̇| {max_v:e}, \
         max|ΔE| {max_e:e} (E = {e0}), max|ΔL_z| {lz_drift:e}, Newton iterations {}",
        r.work.newton_iterations
    );
    assert!(max_g < 1e-14, "position constraint {max_g:e}");
    assert!(max_v < 1e-13, "velocity constraint {max_v:e}");
    // Bounded energy error of size O(h²) (no drift): the second half of the run does not exceed
    // what the first has shown.
    assert!(max_e < 1e-3, "energy error {max_e:e}");
    // The symmetry about the vertical is kept by RATTLE: L_z is conserved to rounding.
    assert!(lz_drift < 1e-11, "L_z {lz_drift:e}");
}

#[test]
fn rattle_energy_error_does_not_grow() {
    // Energy error over the first and the last tenth of a 10⁵-step run agree within a factor 2.
    let sys = ConstrainedHamiltonian::new(Heavy::<3> { g: 9.81 }, Sphere { l: 1.0 });
    let (s, c) = 1.2f64.sin_cos();
    let q0 = SVector::from([s, 0.0, -c]);
    let p0 = SVector::from([0.0, 2.1, 0.0]);
    let e0 = sys.hamiltonian.value(0.0, &q0, &p0).unwrap();
    let (mut early, mut late) = (0.0f64, 0.0f64);
    let mut obs = Each(|st: &hamilton_jacobi::State<3>| {
        let de = (sys.hamiltonian.value(st.t, &st.q, &st.p).unwrap() - e0).abs();
        if st.t <= 200.0 {
            early = early.max(de);
        } else if st.t >= 1800.0 {
            late = late.max(de);
        }
        Control::Continue
    });
    let pr = Problem::new(&sys, 0.0, q0, p0, 2000.0).unwrap();
    integrate(&pr, &Rattle::new(100_000).unwrap(), &mut obs).unwrap();
    println!("RATTLE energy error: first tenth {early:e}, last tenth {late:e}");
    assert!(late < 2.0 * early && early > 0.0, "{early:e} {late:e}");
}

#[test]
fn rattle_refuses_inconsistent_starts_and_names_failures() {
    let sys = ConstrainedHamiltonian::new(Heavy::<2> { g: 4.0 }, Sphere { l: 1.0 });
    // Off the circle.
    let pr = Problem::new(&sys, 0.0, SVector::from([1.1, 0.0]), SVector::zeros(), 1.0).unwrap();
    match integrate(&pr, &Rattle::new(10).unwrap(), &mut ()) {
        Err(Error::ConstraintViolated { residual, .. }) => {
            assert!((residual[0] - 0.105).abs() < 1e-15, "{residual:?}")
        }
        other => panic!("{other:?}"),
    }
    // Radial momentum.
    let pr = Problem::new(
        &sys,
        0.0,
        SVector::from([1.0, 0.0]),
        SVector::from([0.5, 0.0]),
        1.0,
    )
    .unwrap();
    assert!(matches!(
        integrate(&pr, &Rattle::new(10).unwrap(), &mut ()),
        Err(Error::ConstraintViolated { .. })
    ));
    // At the centre the constraint gradient vanishes: rank deficiency naming the configuration.
    match Rattle::new(1)
        .unwrap()
        .step(&sys, 0.0, &SVector::zeros(), &SVector::zeros(), 0.1)
    {
        Err(Error::RankDeficient { rows, at, .. }) => {
            assert_eq!(rows, vec![0]);
            assert!(at.contains("q = "), "{at}");
        }
        other => panic!("{other:?}"),
    }
    // One Newton iteration is not enough: a typed error naming the configuration.
    let (q0, p0) = cartesian(1.0, 0.5);
    match Rattle::new(1)
        .unwrap()
        .with_max_iterations(1)
        .unwrap()
        .step(&sys, 0.0, &q0, &p0, 0.1)
    {
        Err(Error::NotConverged { what, .. }) => assert!(what.contains("q = "), "{what}"),
        other => panic!("{other:?}"),
    }
}

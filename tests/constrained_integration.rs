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

// ---------------------------------------------------------------------------------------------
// Non-holonomic systems.

mod nonholonomic {
    use hamilton_jacobi::constraints::PfaffianConstraints;
    use hamilton_jacobi::integrate::Dop853;
    use hamilton_jacobi::nalgebra::{SMatrix, SVector};
    use hamilton_jacobi::nonholonomic::{
        drift, Constrained, ConstrainedMethod, LagrangeDAlembert, Projection,
    };
    use hamilton_jacobi::systems::{ChaplyginSleigh, RollingDisk, TwoWheeledCart};
    use hamilton_jacobi::{DualNum, Lagrangian};

    /// The vertical rolling disk [McLachlan & Perlmutter 2006, §6.2]: `(x, y, θ, φ)`, unit mass
    /// and radius, moments `I` (rolling) and `J` (heading), in the potential `½k(x² + y²)`;
    /// constraints `ẋ = cos θ φ̇`, `ẏ = sin θ φ̇`. `L` is even in the velocities (reversible).
    #[derive(Clone, Copy, Debug)]
    pub struct VerticalDisk {
        pub i: f64,
        pub j: f64,
        pub k: f64,
    }

    impl Lagrangian<4> for VerticalDisk {
        fn lagrangian<D: DualNum<f64> + Copy>(
            &self,
            _t: D,
            q: &SVector<D, 4>,
            v: &SVector<D, 4>,
        ) -> D {
            (v[0] * v[0] + v[1] * v[1]) * 0.5
                + v[3] * v[3] * (0.5 * self.i)
                + v[2] * v[2] * (0.5 * self.j)
                - (q[0] * q[0] + q[1] * q[1]) * (0.5 * self.k)
        }
    }

    impl PfaffianConstraints<4, 2> for VerticalDisk {
        fn forms<D: DualNum<f64> + Copy>(
            &self,
            _t: D,
            q: &SVector<D, 4>,
        ) -> (SMatrix<D, 2, 4>, SVector<D, 2>) {
            let (s, c) = q[2].sin_cos();
            let (o, z) = (D::one(), D::zero());
            (
                SMatrix::from_row_slice(&[o, z, z, -c, z, o, z, -s]),
                SVector::zeros(),
            )
        }
    }

    pub fn disk_start(v: f64) -> (SVector<f64, 5>, SVector<f64, 5>) {
        (
            SVector::from([0.0, 0.0, 0.0, 0.01, 0.0]),
            SVector::from([v, 0.0, 0.0, 0.0, v]),
        )
    }

    fn disk() -> (Constrained<RollingDisk, RollingDisk, 5, 2>, RollingDisk) {
        let d = RollingDisk::disk(1.0, 1.0, 9.81).unwrap();
        (Constrained::new(d, d), d)
    }

    /// SPEC X6 reference run (rolling disk, rtol 1e-10, 10 s, the T17 starts): DOP853 on the
    /// index-reduced equations keeps `d(Bq̇)/dt = 0` only, so its residual and energy error follow
    /// its global error (about rtol, 1e-10 where the disk falls at v = 1.5); run in segments of
    /// 0.01 s with the velocities projected onto the constraints after each, both stay within
    /// the SPEC bounds, energy drift ≤ 1e-12 and residual ≤ 4e-13.
    #[test]
    fn x6_rolling_disk_reference_run() {
        let (sys, _) = disk();
        for v in [1.5, 2.2, 3.0] {
            let (q0, qd0) = disk_start(v);
            let reduced = drift(
                &sys,
                &ConstrainedMethod::Reduced(Dop853::new(1e-10, 1e-12).unwrap()),
                0.0,
                q0,
                qd0,
                10.0,
                1000,
            )
            .unwrap();
            let projected = drift(
                &sys,
                &ConstrainedMethod::Projected(
                    Projection::new(Dop853::new(1e-10, 1e-12).unwrap(), 1000).unwrap(),
                ),
                0.0,
                q0,
                qd0,
                10.0,
                1000,
            )
            .unwrap();
            for d in [&reduced, &projected] {
                println!(
                    "disk v = {v}, 10 s: {}: max|ΔE| {:.3e} (E = {:.6}), max residual {:.3e}, {} steps",
                    d.method,
                    d.max_energy_error(),
                    d.energy,
                    d.max_residual(),
                    d.work.steps
                );
            }
            assert!(projected.max_energy_error() <= 1e-12);
            assert!(projected.max_residual() <= 4e-13);
            // The reduced run: its drift is of the order of the tolerance (measured 2.8e-10 and
            // 1.1e-10 at v = 1.5, where the disk falls to ψ = 0.67).
            assert!(reduced.max_energy_error() <= 1e-9);
            assert!(reduced.max_residual() <= 1e-9);
        }
    }

    /// Largest |ΔE| over the first and the second half of a drift record.
    fn halves(d: &hamilton_jacobi::nonholonomic::Drift) -> (f64, f64) {
        let n = d.samples.len() / 2;
        let m = |s: &[hamilton_jacobi::nonholonomic::DriftSample]| {
            s.iter().map(|x| x.energy_error.abs()).fold(0.0, f64::max)
        };
        (m(&d.samples[..n]), m(&d.samples[n..]))
    }

    #[test]
    fn lagrange_d_alembert_energy_is_bounded_on_the_sleigh_over_1e5_steps() {
        let sleigh = ChaplyginSleigh::new(2.0, 0.5, 1.0).unwrap();
        let s = Constrained::new(sleigh, sleigh);
        let d = drift(
            &s,
            &ConstrainedMethod::LagrangeDAlembert(LagrangeDAlembert::new(100_000).unwrap()),
            0.0,
            SVector::zeros(),
            SVector::from([0.0, 0.0, 2f64.sqrt()]),
            1000.0,
            200,
        )
        .unwrap();
        let (first, second) = halves(&d);
        println!(
            "sleigh, discrete Lagrange–d'Alembert, 1e5 steps of 0.01: max|ΔE| {first:.3e} (first \
             half), {second:.3e} (second half), E = {}, max residual {:.3e}",
            d.energy,
            d.max_residual()
        );
        // O(h²) and not growing.
        assert!(
            first < 1e-4 && second <= 1.01 * first,
            "{first:e} {second:e}"
        );
        assert!(d.max_residual() < 1e-12);
    }

    /// The vertical disk `I = ½, J = ¼, k = 1` and its start: heading θ = 0.3, rolling at
    /// φ̇ = ½ along the heading, turning at θ̇ = 0.7, from `(x, y) = (1, 0)`.
    #[allow(clippy::type_complexity)]
    pub fn vertical_disk_start() -> (
        Constrained<VerticalDisk, VerticalDisk, 4, 2>,
        SVector<f64, 4>,
        SVector<f64, 4>,
    ) {
        let vd = VerticalDisk {
            i: 0.5,
            j: 0.25,
            k: 1.0,
        };
        let th = 0.3f64;
        (
            Constrained::new(vd, vd),
            SVector::from([1.0, 0.0, th, 0.0]),
            SVector::from([0.5 * th.cos(), 0.5 * th.sin(), 0.7, 0.5]),
        )
    }

    #[test]
    fn lagrange_d_alembert_energy_is_bounded_on_the_vertical_disk_over_1e5_steps() {
        let (s, q0, qd0) = vertical_disk_start();
        let d = drift(
            &s,
            &ConstrainedMethod::LagrangeDAlembert(LagrangeDAlembert::new(100_000).unwrap()),
            0.0,
            q0,
            qd0,
            2000.0,
            400,
        )
        .unwrap();
        let (first, second) = halves(&d);
        println!(
            "vertical disk, discrete Lagrange–d'Alembert, 1e5 steps of 0.02: max|ΔE| {first:.3e} \
             (first half), {second:.3e} (second half), E = {}, max residual {:.3e}",
            d.energy,
            d.max_residual()
        );
        assert!(
            first < 1e-4 && second <= 1.5 * first,
            "{first:e} {second:e}"
        );
        // Rounding of (q_{k+1} − q_k)/h: about ε|q|/h.
        assert!(d.max_residual() < 1e-11);
    }

    #[test]
    fn lagrange_d_alembert_is_of_order_two_and_keeps_the_discrete_constraint() {
        // The sleigh against its closed form at t = 2 (v(0) = 0, ϑ̇(0) = √2).
        let sleigh = ChaplyginSleigh::new(2.0, 0.5, 1.0).unwrap();
        let s = Constrained::new(sleigh, sleigh);
        let (v, w, th) = sleigh.free_motion(1.0, 2.0).unwrap();
        let err = |n: usize| {
            let mut last = None;
            let r = LagrangeDAlembert::new(n)
                .unwrap()
                .run(
                    &s,
                    0.0,
                    SVector::zeros(),
                    SVector::from([0.0, 0.0, 2f64.sqrt()]),
                    2.0,
                    1e-14,
                    |m| {
                        last = Some(*m);
                        hamilton_jacobi::integrate::Control::Continue
                    },
                )
                .unwrap();
            let m = last.unwrap();
            // The midpoint velocity satisfies the constraint at the midpoint to rounding.
            let (b, _) = sleigh.forms(m.t, &m.q);
            assert!((b * m.p)[0].abs() < 1e-13);
            let q = r.last.q;
            (q[2] - th)
                .abs()
                .max((r.last.p[2] - w).abs())
                .max((m.p[0] * m.q[2].cos() + m.p[1] * m.q[2].sin() - v).abs() * 0.0)
        };
        let e: Vec<f64> = [100, 200, 400].iter().map(|&n| err(n)).collect();
        for w in e.windows(2) {
            let order = (w[0] / w[1]).log2();
            println!(
                "discrete Lagrange–d'Alembert, sleigh: {:e} → {:e}, order {order:.3}",
                w[0], w[1]
            );
            assert!((order - 2.0).abs() < 0.1, "{e:?}");
        }
    }

    #[test]
    fn projection_keeps_the_cart_on_its_constraints() {
        let cart = TwoWheeledCart::new(3.0, 0.8, 0.05, 0.8, 0.3, 0.2)
            .unwrap()
            .with_forces(1.0, 0.5, 0.3)
            .unwrap();
        let s = Constrained::new(cart, cart);
        let (v, w) = (0.5, 0.2);
        let q0 = SVector::zeros();
        let qd0 = SVector::from([v, 0.0, w, (v - 0.3 * w) / 0.2, (v + 0.3 * w) / 0.2]);
        let m = ConstrainedMethod::Projected(
            Projection::new(Dop853::new(1e-10, 1e-12).unwrap(), 20).unwrap(),
        );
        let d = drift(&s, &m, 0.0, q0, qd0, 10.0, 20).unwrap();
        println!("cart, {}: max residual {:.3e}", d.method, d.max_residual());
        // The samples fall on the segment ends, before the projection: the residual there is the
        // segment's own drift; after projection it is at rounding (checked by the T18 position).
        assert!(d.max_residual() < 1e-10);
        let csv = d.to_csv();
        assert!(csv.starts_with("method,t,energy_error,residual\n"));
        assert_eq!(csv.lines().count(), 22);
    }
}

/// Modin & Verdier's comparison (Numer. Math. 145 (2020) 405–435): the energy `E` and a first
/// integral `I` along 10⁵ steps of each non-holonomic integrator, on the reversible integrable
/// sleigh and vertical disk and on the integrable problems of [`NonholonomicParticle`] that are
/// not reversible under the standard maps: the particle in the chart `x = u + ½σy² + ⅓τy³`,
/// whose reversing symmetry is the non-linear map `(u, y, z) ↦ (−u − σy² − ⅔τy³, y, −z)`
/// (Cartesian coordinates `σ = τ = 0`, where it is linear, beside them). Measured and reported
/// as a table (`--nocapture`); where a bound follows from the method it is asserted, where the
/// error grows its growth exponent and drift rate are, the thresholds derived from runs at two
/// step sizes.
mod non_reversible {
    #[cfg(feature = "slow-tests")]
    use super::nonholonomic::vertical_disk_start;
    use hamilton_jacobi::constraints::PfaffianConstraints;
    use hamilton_jacobi::integrate::Dop853;
    use hamilton_jacobi::nalgebra::SVector;
    use hamilton_jacobi::nonholonomic::{
        BoltzmannHamel, Constrained, ConstrainedMethod, GibbsAppell, LagrangeDAlembert, Projection,
    };
    #[cfg(feature = "slow-tests")]
    use hamilton_jacobi::systems::ChaplyginSleigh;
    use hamilton_jacobi::systems::NonholonomicParticle;
    use hamilton_jacobi::{Lagrangian, State};

    const STEPS: usize = 100_000;
    const SAMPLES: usize = 2000;

    /// The three integrators: DOP853 on the index-reduced equations (rtol = atol = 1e-10), the
    /// same with the velocities projected every 100 nominal steps, discrete Lagrange–d'Alembert
    /// with 10⁵ steps.
    fn methods() -> [ConstrainedMethod; 3] {
        [
            ConstrainedMethod::Reduced(Dop853::new(1e-10, 1e-10).unwrap()),
            ConstrainedMethod::Projected(
                Projection::new(Dop853::new(1e-10, 1e-10).unwrap(), STEPS / 100).unwrap(),
            ),
            ConstrainedMethod::LagrangeDAlembert(LagrangeDAlembert::new(STEPS).unwrap()),
        ]
    }

    /// One line of the table: the largest errors of `E` and `I` over the first and the last
    /// tenth of the span, and their growth exponents.
    #[derive(Clone, Copy, Debug)]
    struct Row {
        e: (f64, f64),
        i: Option<(f64, f64)>,
        e0: f64,
        i0: Option<f64>,
        e_growth: f64,
        i_growth: Option<f64>,
        /// Least-squares slope of `E(t) − E₀` over the run.
        e_rate: f64,
    }

    /// The least-squares slope of `Δ(t)` over the samples `(t, Δ)`.
    fn rate(signed: &[(f64, f64)]) -> f64 {
        let n = signed.len() as f64;
        let (mt, md) = signed
            .iter()
            .fold((0.0, 0.0), |a, x| (a.0 + x.0 / n, a.1 + x.1 / n));
        let (num, den) = signed.iter().fold((0.0, 0.0), |a, x| {
            (a.0 + (x.0 - mt) * (x.1 - md), a.1 + (x.0 - mt) * (x.0 - mt))
        });
        num / den
    }

    /// `p` with `env(t) = max_{s ≤ t} |Δ(s)|`: `log₁₀(env(T)/env(T/10))`, 0 for a bounded error,
    /// ½ for a random walk, 1 for a linear drift.
    fn growth(errors: &[(f64, f64)], span: f64) -> f64 {
        let env = |t: f64| {
            errors
                .iter()
                .filter(|(s, _)| *s <= t)
                .map(|e| e.1)
                .fold(0.0, f64::max)
        };
        let (late, early) = (env(span), env(0.1 * span));
        if late == 0.0 {
            0.0
        } else {
            (late / early).log10()
        }
    }

    /// Largest error over the samples in `[from, to)` of the span.
    fn between(errors: &[(f64, f64)], span: f64, from: f64, to: f64) -> f64 {
        errors
            .iter()
            .filter(|(s, _)| *s >= from * span && *s < to * span)
            .map(|e| e.1)
            .fold(0.0, f64::max)
    }

    #[allow(clippy::too_many_arguments)]
    fn row<L, C, const N: usize, const K: usize>(
        problem: &str,
        sys: &Constrained<L, C, N, K>,
        m: &ConstrainedMethod,
        q0: SVector<f64, N>,
        qd0: SVector<f64, N>,
        span: f64,
        integral: Option<&dyn Fn(&State<N>) -> f64>,
    ) -> Row
    where
        L: Lagrangian<N>,
        C: PfaffianConstraints<N, K>,
    {
        let start = State {
            t: 0.0,
            q: q0,
            p: qd0,
        };
        let energy = |s: &State<N>| sys.lagrangian.jacobi_integral(s.t, &s.q, &s.p).unwrap();
        let e0 = energy(&start);
        let i0 = integral.map(|f| f(&start));
        let (_, work, states) = m
            .run(sys, 0.0, q0, qd0, span, 1e-12, Some(SAMPLES))
            .unwrap();
        let signed: Vec<(f64, f64)> = states.iter().map(|s| (s.t, energy(s) - e0)).collect();
        let de: Vec<(f64, f64)> = signed.iter().map(|x| (x.0, x.1.abs())).collect();
        let di: Option<Vec<(f64, f64)>> = integral.map(|f| {
            states
                .iter()
                .map(|s| (s.t, (f(s) - i0.unwrap()).abs()))
                .collect()
        });
        for (t, x) in de.iter().chain(di.iter().flatten()) {
            assert!(
                x.is_finite(),
                "{problem}, {}: non-finite error at t = {t}",
                m.label()
            );
        }
        let r = Row {
            e: (between(&de, span, 0.0, 0.1), between(&de, span, 0.9, 1.01)),
            i: di
                .as_ref()
                .map(|d| (between(d, span, 0.0, 0.1), between(d, span, 0.9, 1.01))),
            e0,
            i0,
            e_growth: growth(&de, span),
            i_growth: di.as_ref().map(|d| growth(d, span)),
            e_rate: rate(&signed),
        };
        let name = match m {
            ConstrainedMethod::Reduced(_) => "DOP853 rtol 1e-10",
            ConstrainedMethod::Projected(_) => "DOP853 + projection",
            ConstrainedMethod::LagrangeDAlembert(m) => {
                if m.steps == STEPS {
                    "discrete LdA, 1e5 steps"
                } else {
                    "discrete LdA, 5e4 steps"
                }
            }
        };
        let i_cols = match (r.i, r.i_growth) {
            (Some((a, b)), Some(g)) => format!("{a:9.2e} {b:9.2e} {g:6.2}"),
            _ => format!("{:>9} {:>9} {:>6}", "—", "—", "—"),
        };
        println!(
            "| {problem:<30} | {name:<24} | {:>7} | {:9.2e} {:9.2e} {:6.2} {:9.2e} | {i_cols} |",
            work.steps, r.e.0, r.e.1, r.e_growth, r.e_rate
        );
        r
    }

    fn header() {
        println!(
            "| {:<30} | {:<24} | {:>7} | {:>9} {:>9} {:>6} {:>9} | {:>9} {:>9} {:>6} |",
            "problem",
            "method",
            "steps",
            "|ΔE| 1st",
            "|ΔE| last",
            "p(E)",
            "dE/dt",
            "|ΔI| 1st",
            "|ΔI| last",
            "p(I)"
        );
    }

    /// The DOP853 rows (with and without projection): their local errors, below rtol per unit
    /// time, accumulate, so both E and the closed-form first integral I stay below the linear
    /// accumulation rtol · T · max(|E₀|, |I₀|, 1).
    fn assert_reference(rows: &[Row], span: f64) {
        for r in &rows[..2] {
            let bound = 1e-10 * span * r.e0.abs().max(r.i0.unwrap_or(0.0).abs()).max(1.0);
            assert!(r.e.1 < bound, "{r:?}");
            if let Some(i) = r.i {
                assert!(i.1 < bound, "{r:?}");
            }
        }
    }

    /// A discrete Lagrange–d'Alembert row on a problem whose reversing symmetry the midpoint
    /// scheme inherits: the energy error is O(h²) and does not grow (growth exponent ≈ 0, last
    /// tenth ≤ first tenth up to the sampling); a first integral that the scheme keeps exactly
    /// (`θ̇` of the disk) drifts only by rounding, at most a few ε|I₀| per step.
    fn assert_bounded(r: &Row) {
        assert!(r.e.1 <= 1.5 * r.e.0 && r.e_growth < 0.1, "{r:?}");
        if let (Some(i), Some(g)) = (r.i, r.i_growth) {
            let rounding = 4.0 * STEPS as f64 * f64::EPSILON * r.i0.unwrap().abs();
            assert!((i.1 <= 1.5 * i.0 && g < 0.1) || i.1 <= rounding, "{r:?}");
        }
    }

    /// The particle `B = κ = 1, k = ½` in the chart `x = u + ½σy² + ⅓τy³`, started at
    /// `x = z = 0, y = 0.3, ẋ = 1, ẏ = 0.2`: the system and `(q₀, q̇₀)`.
    #[allow(clippy::type_complexity)]
    fn particle(
        sigma: f64,
        tau: f64,
    ) -> (
        NonholonomicParticle,
        Constrained<NonholonomicParticle, NonholonomicParticle, 3, 1>,
        SVector<f64, 3>,
        SVector<f64, 3>,
    ) {
        let p = NonholonomicParticle::new(1.0, 1.0, 0.5)
            .unwrap()
            .with_shear(sigma, tau)
            .unwrap();
        let (y0, xd0, yd0) = (0.3f64, 1.0, 0.2);
        let (c, dc) = (
            0.5 * sigma * y0 * y0 + tau * y0.powi(3) / 3.0,
            sigma * y0 + tau * y0 * y0,
        );
        let q0 = SVector::from([-c, y0, 0.0]);
        let qd0 = SVector::from([xd0 - dc * yd0, yd0, y0 * xd0]);
        (p, Constrained::new(p, p), q0, qd0)
    }

    /// The particle problems of the table: Cartesian, the quadratic chart (σ = 1, reversible in
    /// disguise for the midpoint scheme) and the cubic chart (τ = 1), each with `methods`.
    fn particle_rows(methods: &[ConstrainedMethod]) -> Vec<Vec<Row>> {
        let mut out = Vec::new();
        for (name, sigma, tau) in [
            ("particle, Cartesian", 0.0, 0.0),
            ("particle, x = u + ½y²", 1.0, 0.0),
            ("particle, x = u + ⅓y³", 0.0, 1.0),
        ] {
            let (p, sys, q0, qd0) = particle(sigma, tau);
            let first_integral = |s: &State<3>| p.first_integral(&s.q, &s.p).unwrap();
            out.push(
                methods
                    .iter()
                    .map(|m| row(name, &sys, m, q0, qd0, 1000.0, Some(&first_integral)))
                    .collect(),
            );
        }
        out
    }

    #[test]
    fn sheared_particle_formulations_agree_with_the_closed_form() {
        // Multipliers, embedding, Boltzmann–Hamel and Gibbs–Appell in the chart
        // x = u + ½σy² + ⅓τy³ against the Cartesian equations (1 + y²)ẍ = Bẏ − yẋẏ,
        // ÿ = −Bẋ − κy − k, z̈ = d/dt(yẋ), carried to the chart by ü = ẍ − c″ẏ² − c′ÿ.
        let (b, kappa, k) = (1.0, 1.0, 0.5);
        for (sigma, tau) in [(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (-0.7, 1.3)] {
            let p = NonholonomicParticle::new(b, kappa, k)
                .unwrap()
                .with_shear(sigma, tau)
                .unwrap();
            let sys = Constrained::new(p, p);
            let (bh, ga) = (BoltzmannHamel::new(p, p), GibbsAppell::new(p, p));
            for (y, ud, yd) in [(0.3, 1.0, 0.2), (-0.7, 0.4, -1.1), (1.2, -0.5, 0.6)] {
                let (dc, ddc) = (sigma * y + tau * y * y, sigma + 2.0 * tau * y);
                let xd = ud + dc * yd;
                let q = SVector::from([0.4, y, -0.2]);
                let qd = SVector::from([ud, yd, y * xd]);
                let xdd = (b * yd - y * xd * yd) / (1.0 + y * y);
                let ydd = -b * xd - kappa * y - k;
                let exact = SVector::from([xdd - ddc * yd * yd - dc * ydd, ydd, yd * xd + y * xdd]);
                let w = SVector::from([0.0, ud, yd]);
                let wb = bh.quasi_accelerations(0.0, &q, &w).unwrap();
                let wg = ga.quasi_accelerations(0.0, &q, &w).unwrap();
                assert!(wb[0] == 0.0 && wg[0] == 0.0, "{wb:?} {wg:?}");
                // The quasi-velocities are (ż − yẋ, u̇, ẏ): their free rates are (ü, ÿ).
                let candidates = [
                    (
                        "multipliers",
                        sys.multiplier_accelerations(0.0, &q, &qd).unwrap().qddot,
                    ),
                    (
                        "embedding",
                        sys.embedded_accelerations(0.0, &q, &qd).unwrap(),
                    ),
                    ("Boltzmann–Hamel", SVector::from([wb[1], wb[2], exact[2]])),
                    ("Gibbs–Appell", SVector::from([wg[1], wg[2], exact[2]])),
                ];
                // Each is one linear solve with AD derivatives: a few ulps of the largest term.
                let tol = 1e-13 * (1.0 + exact.amax() + qd.amax() * qd.amax());
                for (name, got) in candidates {
                    assert!(
                        (got - exact).amax() <= tol,
                        "σ = {sigma}, τ = {tau}, {name}: {got:?} vs {exact:?}"
                    );
                }
            }
        }
    }

    #[test]
    fn modin_verdier_non_reversible_drift_over_1e5_steps() {
        header();
        let rows = particle_rows(&methods());
        for r in &rows {
            assert_reference(r, 1000.0);
        }
        // Discrete Lagrange–d'Alembert, order 2, h = 10⁻². The Cartesian particle is reversible
        // under the linear map (x, y, z; ẋ, ẏ, ż) ↦ (−x, y, −z; ẋ, −ẏ, ż), which the midpoint
        // scheme inherits: bounded errors, with the constant about E₀ ω², ω² = κ + B² the
        // largest squared frequency of the linearised motion, so both stay below 2h² E₀, 2h² I₀.
        let cart = rows[0][2];
        assert_bounded(&cart);
        let h = 1000.0 / STEPS as f64;
        assert!(cart.e.1 <= 2.0 * h * h * cart.e0, "{cart:?}");
        assert!(
            cart.i.unwrap().1 <= 2.0 * h * h * cart.i0.unwrap(),
            "{cart:?}"
        );
        // DOP853 on the Cartesian particle: its error accumulates (E and I grow over the run).
        for r in &rows[0][..2] {
            let i = r.i.unwrap();
            assert!(r.e.1 > 2.0 * r.e.0 && i.1 > 2.0 * i.0, "no growth: {r:?}");
        }
        // The quadratic chart: the midpoint scheme keeps the non-linear reversing symmetry
        // exactly (reversible in disguise): bounded, like the Cartesian particle.
        assert_bounded(&rows[1][2]);
        // The cubic chart: the energy error of the midpoint scheme drifts.
        let cubic = rows[2][2];
        let (p, sys, q0, qd0) = particle(0.0, 1.0);
        let first_integral = |s: &State<3>| p.first_integral(&s.q, &s.p).unwrap();
        let coarse = row(
            "particle, x = u + ⅓y³",
            &sys,
            &ConstrainedMethod::LagrangeDAlembert(LagrangeDAlembert::new(STEPS / 2).unwrap()),
            q0,
            qd0,
            1000.0,
            Some(&first_integral),
        );
        let ratio = coarse.e_rate / cubic.e_rate;
        println!(
            "cubic chart, discrete LdA: dE/dt {:.3e} (h = 0.01), {:.3e} (h = 0.02), ratio {ratio:.3} \
             (O(h²) drift: 4); growth exponents p(E) {:.2}, {:.2}; p(I) {:.2}, {:.2}",
            cubic.e_rate,
            coarse.e_rate,
            cubic.e_growth,
            coarse.e_growth,
            cubic.i_growth.unwrap(),
            coarse.i_growth.unwrap()
        );
        // A drift, not an oscillation: growth exponent at least ½ at both step sizes, and the
        // rate an O(h²) term of the modified equations (ratio 4 between h and 2h).
        for r in [cubic, coarse] {
            assert!(r.e_growth >= 0.5, "{r:?}");
        }
        assert!((ratio / 4.0 - 1.0).abs() < 0.25, "ratio {ratio}");
    }

    /// The whole table: the reversible sleigh and vertical disk beside the particles.
    #[cfg(feature = "slow-tests")]
    #[test]
    fn modin_verdier_drift_table_over_1e5_steps() {
        header();
        // Reversible integrable: the sleigh (no first integral besides E) and the vertical disk
        // (I = θ̇, the heading rate, on which no constraint force acts).
        let sleigh = ChaplyginSleigh::new(2.0, 0.5, 1.0).unwrap();
        let s = Constrained::new(sleigh, sleigh);
        let sleigh_rows: Vec<Row> = methods()
            .iter()
            .map(|m| {
                row(
                    "sleigh (reversible)",
                    &s,
                    m,
                    SVector::zeros(),
                    SVector::from([0.0, 0.0, 2f64.sqrt()]),
                    1000.0,
                    None,
                )
            })
            .collect();
        let (d, q0, qd0) = vertical_disk_start();
        let heading = |s: &State<4>| s.p[2];
        let disk_rows: Vec<Row> = methods()
            .iter()
            .map(|m| {
                row(
                    "vertical disk (reversible)",
                    &d,
                    m,
                    q0,
                    qd0,
                    2000.0,
                    Some(&heading),
                )
            })
            .collect();
        let particles = particle_rows(&methods());
        assert_reference(&sleigh_rows, 1000.0);
        assert_reference(&disk_rows, 2000.0);
        for r in &particles {
            assert_reference(r, 1000.0);
        }
        for r in [
            sleigh_rows[2],
            disk_rows[2],
            particles[0][2],
            particles[1][2],
        ] {
            assert_bounded(&r);
        }
    }
}

/// SPEC X6 stress runs: the rolling disk for 1000 s at v = 2.2 and the cart of T18 for 1000 s,
/// every method's energy error and constraint residual.
#[cfg(feature = "slow-tests")]
mod stress {
    use super::nonholonomic::disk_start;
    use hamilton_jacobi::integrate::Dop853;
    use hamilton_jacobi::nalgebra::SVector;
    use hamilton_jacobi::nonholonomic::{
        drift, Constrained, ConstrainedMethod, LagrangeDAlembert, Projection,
    };
    use hamilton_jacobi::systems::{RollingDisk, TwoWheeledCart};

    /// The energy error of a long discrete Lagrange–d'Alembert run `long` with step `h` against
    /// a bound derived from the scheme's order rather than measured on the long run itself.
    ///
    /// The scheme is of order 2 and, on these reversible integrable problems, reversible: its
    /// energy error is bounded, `|ΔE(t)| ≤ C h² + O(h⁴)` for exponentially long times, `C` the
    /// largest value over the invariant torus of the h²-term of the modified energy. Two runs
    /// over a short span `T_s` (many periods of the motion, so that the orbit visits most of
    /// its torus) with steps `2h` and `h` measure `C h²` and `C (2h)²`: their ratio asserts the
    /// order (4 ± 20 %), and `C = max|ΔE|_h / h²`. The long run may reach parts of the torus the
    /// short one missed, and the O(h⁴) remainder is not bounded by the fit: the bound allowed
    /// is twice the measured `C h²`.
    fn assert_derived_energy_bound<L, C, const N: usize, const K: usize>(
        sys: &Constrained<L, C, N, K>,
        q0: SVector<f64, N>,
        qd0: SVector<f64, N>,
        h: f64,
        long: &hamilton_jacobi::nonholonomic::Drift,
    ) where
        L: hamilton_jacobi::Lagrangian<N>,
        C: hamilton_jacobi::constraints::PfaffianConstraints<N, K>,
    {
        const SHORT: f64 = 50.0;
        let steps = (SHORT / h).round() as usize;
        let err = |n: usize| {
            let m = ConstrainedMethod::LagrangeDAlembert(LagrangeDAlembert::new(n).unwrap());
            drift(sys, &m, 0.0, q0, qd0, SHORT, n.min(10_000))
                .unwrap()
                .max_energy_error()
        };
        let (fine, coarse) = (err(steps), err(steps / 2));
        let ratio = coarse / fine;
        let c = fine / (h * h);
        println!(
            "discrete Lagrange–d'Alembert over {SHORT} s: max|ΔE| {coarse:.3e} (2h), {fine:.3e} \
             (h = {h}), ratio {ratio:.3} (order 2: 4), C = {c:.4}, long-run bound 2 C h² = {:.3e}",
            2.0 * c * h * h
        );
        assert!((ratio / 4.0 - 1.0).abs() < 0.2, "order: ratio {ratio}");
        let bound = 2.0 * c * h * h;
        let got = long.max_energy_error();
        assert!(got <= bound, "{}: {got:e} > {bound:e}", long.method);
    }

    fn methods(steps: usize) -> [ConstrainedMethod; 3] {
        [
            ConstrainedMethod::Reduced(Dop853::new(1e-10, 1e-12).unwrap()),
            ConstrainedMethod::Projected(
                Projection::new(Dop853::new(1e-10, 1e-12).unwrap(), steps / 10).unwrap(),
            ),
            ConstrainedMethod::LagrangeDAlembert(LagrangeDAlembert::new(steps).unwrap()),
        ]
    }

    #[test]
    fn x6_disk_1000_s_at_v_2_2() {
        let d = RollingDisk::disk(1.0, 1.0, 9.81).unwrap();
        let sys = Constrained::new(d, d);
        let (q0, qd0) = disk_start(2.2);
        let mut out = Vec::new();
        for m in methods(200_000) {
            let r = drift(&sys, &m, 0.0, q0, qd0, 1000.0, 1000).unwrap();
            println!(
                "disk v = 2.2, 1000 s: {}: max|ΔE| {:.3e}, max residual {:.3e}, {} steps",
                r.method,
                r.max_energy_error(),
                r.max_residual(),
                r.work.steps
            );
            out.push(r);
        }
        assert!(out[0].max_energy_error() < 1e-8 && out[0].max_residual() < 1e-8);
        assert!(out[1].max_energy_error() < 1e-12 && out[1].max_residual() < 4e-13);
        // Bounded O(h²) energy error, h = 5e-3, the bound derived from two short runs; the
        // residual is the rounding of (q_{k+1} − q_k)/h.
        assert_derived_energy_bound(&sys, q0, qd0, 1000.0 / 200_000.0, &out[2]);
        assert!(out[2].max_residual() < 1e-9);
    }

    #[test]
    fn x6_cart_1000_s() {
        let cart = TwoWheeledCart::new(3.0, 0.8, 0.05, 0.8, 0.3, 0.2).unwrap();
        let sys = Constrained::new(cart, cart);
        let (v, w) = (0.5, 0.2);
        let q0 = SVector::zeros();
        let qd0 = SVector::from([v, 0.0, w, (v - 0.3 * w) / 0.2, (v + 0.3 * w) / 0.2]);
        let mut out = Vec::new();
        for m in methods(100_000) {
            let r = drift(&sys, &m, 0.0, q0, qd0, 1000.0, 1000).unwrap();
            println!(
                "cart, 1000 s: {}: max|ΔE| {:.3e} (E = {}), max residual {:.3e}, {} steps",
                r.method,
                r.max_energy_error(),
                r.energy,
                r.max_residual(),
                r.work.steps
            );
            out.push(r);
        }
        assert!(out[0].max_energy_error() < 1e-9 && out[0].max_residual() < 1e-9);
        assert!(out[1].max_energy_error() < 1e-12 && out[1].max_residual() < 4e-13);
        // Bounded O(h²) energy error, h = 0.01, the bound derived from two short runs.
        assert_derived_energy_bound(&sys, q0, qd0, 1000.0 / 100_000.0, &out[2]);
        assert!(out[2].max_residual() < 1e-10);
    }
}

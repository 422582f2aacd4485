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

    #[test]
    fn lagrange_d_alembert_energy_is_bounded_on_the_vertical_disk_over_1e5_steps() {
        let vd = VerticalDisk {
            i: 0.5,
            j: 0.25,
            k: 1.0,
        };
        let s = Constrained::new(vd, vd);
        let th = 0.3f64;
        let d = drift(
            &s,
            &ConstrainedMethod::LagrangeDAlembert(LagrangeDAlembert::new(100_000).unwrap()),
            0.0,
            SVector::from([1.0, 0.0, th, 0.0]),
            SVector::from([0.5 * th.cos(), 0.5 * th.sin(), 0.7, 0.5]),
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

/// The non-reversible integrable problem of [`NonholonomicParticle`] (after Modin & Verdier,
/// Numer. Math. 145 (2020), §5): the energy `E` and the first integral `I` along 10⁵ steps of each
/// non-holonomic integrator, measured and reported. Where a bound follows from the method it is
/// asserted; where the error grows, the growth is.
mod non_reversible {
    use hamilton_jacobi::integrate::Dop853;
    use hamilton_jacobi::nalgebra::SVector;
    use hamilton_jacobi::nonholonomic::{
        Constrained, ConstrainedMethod, LagrangeDAlembert, Projection,
    };
    use hamilton_jacobi::systems::NonholonomicParticle;
    use hamilton_jacobi::State;

    const STEPS: usize = 100_000;
    const SPAN: f64 = 1000.0;

    /// `max |E − E₀|` and `max |I − I₀|` over the states in `[from, to)` of the span.
    fn drift_between(
        p: &NonholonomicParticle,
        states: &[State<3>],
        e0: f64,
        i0: f64,
        from: f64,
        to: f64,
    ) -> (f64, f64) {
        states
            .iter()
            .filter(|s| s.t >= from * SPAN && s.t < to * SPAN)
            .map(|s| {
                let e = p.energy(&s.q, &s.p).unwrap();
                let i = p.first_integral(&s.q, &s.p).unwrap();
                ((e - e0).abs(), (i - i0).abs())
            })
            .fold((0.0, 0.0), |a, b| (a.0.max(b.0), a.1.max(b.1)))
    }

    #[test]
    fn modin_verdier_non_reversible_drift_over_1e5_steps() {
        let p = NonholonomicParticle::new(1.0, 1.0, 0.5).unwrap();
        let sys = Constrained::new(p, p);
        let q0 = SVector::from([0.0, 0.3, 0.0]);
        let qd0 = SVector::from([1.0, 0.2, 0.3]);
        let (e0, i0) = (
            p.energy(&q0, &qd0).unwrap(),
            p.first_integral(&q0, &qd0).unwrap(),
        );
        let h = SPAN / STEPS as f64;
        let methods = [
            ConstrainedMethod::Reduced(Dop853::new(1e-10, 1e-10).unwrap()),
            ConstrainedMethod::Projected(
                Projection::new(Dop853::new(1e-10, 1e-10).unwrap(), STEPS / 100).unwrap(),
            ),
            ConstrainedMethod::LagrangeDAlembert(LagrangeDAlembert::new(STEPS).unwrap()),
        ];
        let mut measured = Vec::new();
        for m in &methods {
            let (_, work, states) = m.run(&sys, 0.0, q0, qd0, SPAN, 1e-12, Some(2000)).unwrap();
            let first = drift_between(&p, &states, e0, i0, 0.0, 0.1);
            let last = drift_between(&p, &states, e0, i0, 0.9, 1.01);
            println!(
                "non-reversible particle, {}: {} steps; max|ΔE| first tenth {:.3e}, last tenth \
                 {:.3e}; max|ΔI| first tenth {:.3e}, last tenth {:.3e} (E₀ = {e0}, I₀ = {i0})",
                m.label(),
                work.steps,
                first.0,
                last.0,
                first.1,
                last.1
            );
            measured.push((first, last));
        }
        // DOP853 with or without projection (the projection restores the constraint, not E or
        // I): the local errors, below rtol per unit time, accumulate; the drift grows over the
        // run and stays below the linear accumulation rtol · t · max(E₀, I₀, 1).
        let rtol_bound = 1e-10 * SPAN * e0.max(i0).max(1.0);
        for (k, (first, last)) in measured[..2].iter().enumerate() {
            assert!(
                last.0 > 2.0 * first.0 && last.1 > 2.0 * first.1,
                "method {k}: no growth"
            );
            assert!(
                last.0 < rtol_bound && last.1 < rtol_bound,
                "method {k}: {last:?}"
            );
        }
        // Discrete Lagrange–d'Alembert, order 2, h = 10⁻²: the errors measured at the midpoint
        // states are O(h²) with the constant E₀ ω², ω² = κ + B² the largest squared frequency
        // of the linearised motion. Measured: they do not grow over 10⁵ steps, although the
        // system is not reversible under the velocity flip; it keeps the reversing symmetry
        // (x, y, z; ẋ, ẏ, ż) ↦ (−x, y, −z; ẋ, −ẏ, ż).
        let (first, last) = measured[2];
        let order_bound = 2.0 * h * h;
        assert!(
            last.0 <= order_bound * e0 && last.1 <= order_bound * i0,
            "{last:?}"
        );
        assert!(
            last.0 <= 1.01 * first.0 && last.1 <= 1.01 * first.1,
            "growth: {first:?} → {last:?}"
        );
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
        // O(h²) with h = 5e-3, bounded; the residual is the rounding of (q_{k+1} − q_k)/h.
        assert!(out[2].max_energy_error() < 1e-4 && out[2].max_residual() < 1e-9);
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
        // O(h²) with h = 0.01 (measured 1.3e-7), bounded.
        assert!(out[2].max_energy_error() < 1e-6 && out[2].max_residual() < 1e-10);
    }
}

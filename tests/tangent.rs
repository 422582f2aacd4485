//! Tangent maps through the integrators' own steps (issue 17 §2): symplecticity of the
//! Gauss–Legendre tangent map, DOP853's frozen-step tangent map against the integrated
//! variational equations, AD against central finite differences (X11), and derivatives of
//! orbital elements with respect to initial conditions by the chain rule.

use hamilton_jacobi::hamiltonian;
use hamilton_jacobi::integrate::{
    integrate, parameter_tangent_map, splitting_parameter_tangent_map, variational_tangent_map,
    AnyMethod, Dop853, Fixed, Gauss, GeneralMethod, ParameterSensitivity, Problem, Splitting,
    TangentMap, TangentMethod, Taylor,
};
use hamilton_jacobi::nalgebra::{SMatrix, SVector};
use hamilton_jacobi::num_dual::Dual64;
use hamilton_jacobi::phase::{PhaseMatrix, State};
use hamilton_jacobi::systems::kepler::elements::{state_to_classical, Classical};
use hamilton_jacobi::systems::{HenonHeiles, Kepler3};

/// The quasi-periodic Hénon–Heiles orbit `QP1`: `E = 1/12`, section `x = 0` at
/// `(y, p_y) = (0, 0.25)`, `p_x > 0`.
fn qp1() -> State<2> {
    HenonHeiles::section_start(1.0 / 12.0, 0.0, 0.25).unwrap()
}

/// The chaotic Hénon–Heiles orbit `CH1`: `E = 1/8`, section `x = 0` at `(y, p_y) = (−0.1, 0)`.
fn ch1() -> State<2> {
    HenonHeiles::section_start(0.125, -0.1, 0.0).unwrap()
}

fn as_matrix<const N: usize>(m: &PhaseMatrix<N>) -> hamilton_jacobi::nalgebra::DMatrix<f64> {
    m.to_dmatrix()
}

fn max_abs_diff<const N: usize>(a: &PhaseMatrix<N>, b: &PhaseMatrix<N>) -> f64 {
    a.sub(b).max_abs()
}

#[test]
fn gauss_tangent_map_of_1000_steps_is_symplectic() {
    // 1000 steps of Gauss–Legendre (s = 3, order 6) with h = 0.05 along QP1, and along the
    // chaotic CH1 where ‖Φ‖ grows exponentially.
    for (name, start) in [("QP1", qp1()), ("CH1", ch1())] {
        let problem = Problem::new(&HenonHeiles, 0.0, start.q, start.p, 50.0).unwrap();
        let method = Fixed::new(Gauss::<3>::new().unwrap(), 1000).unwrap();
        let tm = method.tangent_map(&problem).unwrap();
        let defect = tm.jacobian.symplectic_defect();
        let size = tm.jacobian.max_abs();
        println!("{name}: ‖ΦᵀJΦ − J‖ = {defect:e}, ‖Φ‖ = {size:e}");
        assert!(defect <= 1e-13, "{name}: defect {defect:e}");
        // The final state is the real run's, bit for bit.
        let run = integrate(&problem, &method, &mut ()).unwrap();
        assert_eq!(tm.last, run.last);
        // Not the identity: the shear of the torus.
        assert!(size > 2.0, "{name}: ‖Φ‖ = {size}");
    }
}

#[test]
fn dop853_tangent_map_agrees_with_the_variational_equations() {
    // Along QP1 over t = 50 (8 periods of the linear oscillators): the frozen-step tangent map
    // (steps chosen by the error control on z alone, replayed on dual numbers) and the
    // integrated variational equations (steps chosen on (z, Φ)) agree to the integration
    // tolerance: their difference, and the error of each against a reference (the variational
    // equations at rtol = atol = 1e-14), are proportional to the tolerance (tolerance
    // proportionality of DOP853's error control, HNW II.4/II.10) — the constant measured at the
    // loosest tolerance 1e-6 bounds, within a factor 2, the errors at every tighter one, over
    // seven decades.
    let problem = Problem::new(&HenonHeiles, 0.0, qp1().q, qp1().p, 50.0).unwrap();
    let reference =
        variational_tangent_map::<_, 2, 10>(&problem, &Dop853::new(1e-14, 1e-14).unwrap()).unwrap();
    let mut constants: Option<[f64; 3]> = None;
    for tol in [1e-6, 1e-8, 1e-10, 1e-12, 1e-13] {
        let m = Dop853::new(tol, tol).unwrap();
        let frozen = m.tangent_map(&problem).unwrap();
        let variational = variational_tangent_map::<_, 2, 10>(&problem, &m).unwrap();
        let errors = [
            max_abs_diff(&frozen.jacobian, &variational.jacobian),
            max_abs_diff(&frozen.jacobian, &reference.jacobian),
            max_abs_diff(&variational.jacobian, &reference.jacobian),
        ];
        println!(
            "tol {tol:e}: between {:e}, frozen {:e}, variational {:e} (‖Φ‖ = {:e}); steps {} / {}",
            errors[0],
            errors[1],
            errors[2],
            reference.jacobian.max_abs(),
            frozen.work.steps,
            variational.work.steps
        );
        let c = constants.get_or_insert(errors.map(|e| e / tol));
        for (e, c) in errors.iter().zip(c.iter()) {
            assert!(*e <= 2.0 * c * tol, "tol {tol:e}: {e:e} > 2 · {c:e} · tol");
        }
        // The state of the frozen replay is DOP853's state to rounding.
        let run = integrate(&problem, &m, &mut ()).unwrap();
        assert!((frozen.last.q - run.last.q).amax() <= 1e-13);
        assert!((frozen.last.p - run.last.p).amax() <= 1e-13);
    }
}

/// With compensated summation the tangent map's final state is the compensated run's own (not
/// the plain replay's), and its Jacobian the replay's. The plain and compensated runs choose
/// their steps by the same control on states that differ by rounding only, so their Jacobians
/// differ by far less than the integration error of either (≈ 5e-8 at this tolerance, see the
/// test above): asserted ≤ `tol`. Measured: 4.4e-13.
#[test]
fn compensated_dop853_tangent_map_ends_on_the_compensated_run() {
    let problem = Problem::new(&HenonHeiles, 0.0, qp1().q, qp1().p, 50.0).unwrap();
    let tol = 1e-10;
    let plain = Dop853::new(tol, tol).unwrap();
    let compensated = plain.with_compensated_summation(true);
    let map = compensated.tangent_map(&problem).unwrap();
    let run = integrate(&problem, &compensated, &mut ()).unwrap();
    assert_eq!((map.last.q, map.last.p), (run.last.q, run.last.p));
    let reference = plain.tangent_map(&problem).unwrap();
    let d = max_abs_diff(&map.jacobian, &reference.jacobian);
    println!("compensated vs plain Jacobian: {d:e}");
    assert!(d <= tol, "{d:e}");
}

/// Central differences of the final state of `method` with respect to the initial state, step `h`.
fn central_differences<M: TangentMethod<HenonHeiles, 2>>(
    method: &M,
    start: &State<2>,
    t1: f64,
    h: f64,
) -> PhaseMatrix<2> {
    let mut m = SMatrix::<f64, 4, 4>::zeros();
    for j in 0..4 {
        let shifted = |s: f64| {
            let (mut q, mut p) = (start.q, start.p);
            if j < 2 {
                q[j] += s;
            } else {
                p[j - 2] += s;
            }
            let pr = Problem::new(&HenonHeiles, 0.0, q, p, t1).unwrap();
            let last = method.tangent_map(&pr).unwrap().last;
            SVector::<f64, 4>::from([last.q[0], last.q[1], last.p[0], last.p[1]])
        };
        m.set_column(j, &((shifted(h) - shifted(-h)) / (2.0 * h)));
    }
    PhaseMatrix::from_dmatrix(&hamilton_jacobi::nalgebra::DMatrix::from_fn(
        4,
        4,
        |i, j| m[(i, j)],
    ))
    .unwrap()
}

#[test]
fn ad_tangent_maps_agree_with_central_differences() {
    // X11. The central difference D(h) = (Ψ(z+he) − Ψ(z−he))/2h of the computed map Ψ differs
    // from Ψ′e by the truncation (h²/6)Ψ‴ — estimated from D(h) and D(2h), whose difference is
    // (3/6)h²Ψ‴ to leading order, as |D(2h) − D(h)|/3 — plus the rounding of the two runs
    // divided by h: each final state carries a rounding error of about √n ε ‖z‖ ‖Φ‖ after n
    // steps (Kahan-compensated sums; the error made at step k is propagated by Φ), so the
    // rounding term is √n ε ‖z(t₁)‖ ‖Φ‖ / h. The check allows twice the sum.
    let cases = [
        ("Verlet, QP1", AnyMethod::verlet(1000).unwrap(), qp1(), 50.0),
        ("Verlet, CH1", AnyMethod::verlet(1000).unwrap(), ch1(), 50.0),
        (
            "Gauss 3, CH1",
            AnyMethod::gauss(3, 500).unwrap(),
            ch1(),
            50.0,
        ),
        (
            "DOP853, QP1",
            AnyMethod::dop853(1e-10, 1e-10).unwrap(),
            qp1(),
            50.0,
        ),
        (
            "Taylor, QP1",
            AnyMethod::General(GeneralMethod::Taylor(Taylor::new(1e-12).unwrap())),
            qp1(),
            50.0,
        ),
        (
            "Taylor, CH1",
            AnyMethod::General(GeneralMethod::Taylor(Taylor::new(1e-12).unwrap())),
            ch1(),
            50.0,
        ),
    ];
    for (name, m, start, t1) in cases {
        let problem = Problem::new(&HenonHeiles, 0.0, start.q, start.p, t1).unwrap();
        let tm: TangentMap<2> = m.tangent_map(&problem).unwrap();
        let h = 1e-5;
        let d1 = central_differences(&m, &start, t1, h);
        let d2 = central_differences(&m, &start, t1, 2.0 * h);
        let truncation = d2.sub(&d1).max_abs() / 3.0;
        let n = tm.work.steps.max(1) as f64;
        let z = tm.last.q.amax().max(tm.last.p.amax());
        let rounding = n.sqrt() * f64::EPSILON * z * tm.jacobian.max_abs() / h;
        let bound = 2.0 * (truncation + rounding);
        let err = max_abs_diff(&tm.jacobian, &d1);
        println!(
            "{name}: ‖Φ_AD − D(h)‖ = {err:e}, truncation {truncation:e}, rounding {rounding:e}, \
             ‖Φ‖ = {:e}",
            tm.jacobian.max_abs()
        );
        assert!(err <= bound, "{name}: {err:e} > {bound:e}");
    }
}

#[test]
fn orbital_element_derivatives_by_the_chain_rule() {
    // ∂E(t₁)/∂z₀ = (∂z/∂E)⁻¹ Φ: the Jacobian of the element → state map by AD of
    // `Classical::to_state`, inverted, times the tangent map of a Gauss–Legendre run over 1.3
    // periods of an inclined ellipse (a = 1, e = 0.3, i = 0.5). Checked against central
    // differences of `state_to_classical` of the runs from shifted initial states, with the
    // bound of `ad_tangent_maps_agree_with_central_differences`.
    let mu = 1.0;
    let kepler = Kepler3::new(mu).unwrap();
    let e0 = Classical::new(1.0, 0.3, 0.5, 0.4, 1.1, 0.2).unwrap();
    let (r0, v0) = e0.to_state(mu).unwrap();
    let t1 = 1.3 * std::f64::consts::TAU;
    let method = Fixed::new(Gauss::<4>::new().unwrap(), 400).unwrap();
    let problem = Problem::new(&kepler, 0.0, r0, v0, t1).unwrap();
    let tm = method.tangent_map(&problem).unwrap();
    let e1 = state_to_classical(mu, &tm.last.q, &tm.last.p).unwrap();
    let elements = |e: &Classical| [e.a, e.e, e.i, e.raan, e.argp, e.mean_anomaly];
    // ∂z/∂E at E(t₁), one column per element.
    let mut dz_de = hamilton_jacobi::nalgebra::DMatrix::<f64>::zeros(6, 6);
    let base = elements(&e1);
    for j in 0..6 {
        let d = |k: usize| Dual64::new(base[k], if k == j { 1.0 } else { 0.0 });
        let ed = Classical {
            a: d(0),
            e: d(1),
            i: d(2),
            raan: d(3),
            argp: d(4),
            mean_anomaly: d(5),
        };
        let (r, v) = ed.to_state(mu).unwrap();
        for i in 0..3 {
            dz_de[(i, j)] = r[i].eps;
            dz_de[(3 + i, j)] = v[i].eps;
        }
    }
    let de_dz0 = dz_de.try_inverse().unwrap() * as_matrix(&tm.jacobian);
    // Central differences.
    let h = 1e-6;
    let mut fd = hamilton_jacobi::nalgebra::DMatrix::<f64>::zeros(6, 6);
    let mut fd2 = fd.clone();
    for j in 0..6 {
        let shifted = |s: f64| {
            let (mut r, mut v) = (r0, v0);
            if j < 3 {
                r[j] += s;
            } else {
                v[j - 3] += s;
            }
            let pr = Problem::new(&kepler, 0.0, r, v, t1).unwrap();
            let last = integrate(&pr, &method, &mut ()).unwrap().last;
            elements(&state_to_classical(mu, &last.q, &last.p).unwrap())
        };
        for (out, step) in [(&mut fd, h), (&mut fd2, 2.0 * h)] {
            let (a, b) = (shifted(step), shifted(-step));
            for i in 0..6 {
                out[(i, j)] = (a[i] - b[i]) / (2.0 * step);
            }
        }
    }
    let truncation = (&fd2 - &fd).amax() / 3.0;
    let rounding = 400f64.sqrt() * f64::EPSILON * 2.0 * de_dz0.amax() / h;
    let err = (&de_dz0 - &fd).amax();
    println!("∂E/∂z₀: ‖AD − FD‖ = {err:e}, truncation {truncation:e}, rounding {rounding:e}");
    assert!(err <= 2.0 * (truncation + rounding), "{err:e}");
    // The semi-major axis depends on the energy only: ∂a/∂v₀ = 2a² v₀/μ (vis-viva).
    for k in 0..3 {
        let want = 2.0 * e1.a * e1.a * v0[k] / mu;
        assert!(
            (de_dz0[(0, 3 + k)] - want).abs() <= 1e-9 * want.abs().max(1.0),
            "∂a/∂v₀{k}: {} vs {want}",
            de_dz0[(0, 3 + k)]
        );
    }
}

#[test]
fn tangent_maps_of_every_method_value() {
    // The values of AnyMethod dispatch to the typed methods.
    let start = qp1();
    let problem = Problem::new(&HenonHeiles, 0.0, start.q, start.p, 10.0).unwrap();
    let typed = Fixed::new(Splitting::VERLET_KDK, 200)
        .unwrap()
        .tangent_map(&problem)
        .unwrap();
    let any = AnyMethod::verlet(200)
        .unwrap()
        .tangent_map(&problem)
        .unwrap();
    assert_eq!(typed, any);
    let rk4 = GeneralMethod::rk4(200)
        .unwrap()
        .tangent_map(&problem)
        .unwrap();
    assert!(max_abs_diff(&rk4.jacobian, &typed.jacobian) < 1e-2);
    let taylor = Taylor::new(1e-12).unwrap();
    let any_taylor = GeneralMethod::Taylor(taylor).tangent_map(&problem).unwrap();
    assert_eq!(any_taylor, taylor.tangent_map(&problem).unwrap());
    assert!(max_abs_diff(&any_taylor.jacobian, &typed.jacobian) < 1e-2);
    // A variational system of the wrong size is refused.
    assert!(
        variational_tangent_map::<_, 2, 9>(&problem, &Dop853::new(1e-8, 1e-8).unwrap()).is_err()
    );
    assert!(variational_tangent_map::<_, 2, 9>(&problem, &taylor).is_err());
}

// A pendulum of length l under gravity g, per unit mass: H = p²/(2l²) − g l cos θ.
hamiltonian!(Swing<1> [g, l] |_t, q, p| p[0] * p[0] / (l * l * 2.0) - g * l * q[0].cos());

#[test]
fn parameter_derivatives_through_the_steps() {
    // ∂(θ, p)(t₁)/∂(g, l) through 2000 Gauss–Legendre steps (s = 3) and through DOP853's frozen
    // steps, against the forward sensitivity equations at rtol = 1e-13 (an independent route:
    // the variational equations integrated by DOP853) and against central differences in g.
    let swing = Swing { g: 9.81, l: 0.7 };
    let problem = Problem::new(
        &swing,
        0.0,
        SVector::from([1.2]),
        SVector::from([0.3]),
        10.0,
    )
    .unwrap();
    let gauss = Fixed::new(Gauss::<3>::new().unwrap(), 2000).unwrap();
    let by_steps = parameter_tangent_map::<_, _, 1, 2, 3>(&problem, &gauss).unwrap();
    let frozen =
        parameter_tangent_map::<_, _, 1, 2, 3>(&problem, &Dop853::new(1e-12, 1e-12).unwrap())
            .unwrap();
    let aug = ParameterSensitivity::<_, 1, 2, 3>::new(&swing).unwrap();
    let (qa, pa) = aug.initial_state(&problem.start.q, &problem.start.p);
    let big = Problem::new(&aug, 0.0, qa, pa, 10.0).unwrap();
    let last = integrate(&big, &Dop853::new(1e-13, 1e-13).unwrap(), &mut ())
        .unwrap()
        .last;
    let (q, _, sq, sp) = aug.split(&last.q, &last.p);
    let scale = sq.amax().max(sp.amax());
    for (name, t) in [("Gauss", &by_steps), ("DOP853", &frozen)] {
        let e = (t.dq_dk - sq).amax().max((t.dp_dk - sp).amax());
        println!("{name}: ‖∂z/∂k − S‖ = {e:e} (‖S‖ = {scale:e})");
        // Gauss at h = 0.005 (order 6) and DOP853 at 1e-12: both far below 1e-8 relative.
        assert!(e <= 1e-8 * scale, "{name}: {e:e}");
        assert!((t.last.q - q).amax() <= 1e-10);
    }
    // The state block is the tangent map of the run on the system itself.
    let plain = gauss.tangent_map(&problem).unwrap();
    assert!(max_abs_diff(&plain.jacobian, &by_steps.jacobian) <= 1e-12 * plain.jacobian.max_abs());
    // Central differences in g of the Gauss runs.
    let h = 1e-5;
    let run = |g: f64| {
        let s = Swing { g, l: 0.7 };
        let pr = Problem::new(&s, 0.0, SVector::from([1.2]), SVector::from([0.3]), 10.0).unwrap();
        integrate(&pr, &gauss, &mut ()).unwrap().last.q[0]
    };
    let d1 = (run(9.81 + h) - run(9.81 - h)) / (2.0 * h);
    let d2 = (run(9.81 + 2.0 * h) - run(9.81 - 2.0 * h)) / (4.0 * h);
    let bound = 2.0 * ((d2 - d1).abs() / 3.0 + 2000f64.sqrt() * f64::EPSILON * 10.0 * scale / h);
    assert!((by_steps.dq_dk[(0, 0)] - d1).abs() <= bound);
    assert!(parameter_tangent_map::<_, _, 1, 2, 4>(&problem, &gauss).is_err());
}

// Hénon–Heiles with the strength λ of its cubic terms, and the pendulum of `Swing` declared
// separable (its length enters the kinetic part as well as the potential).
hamiltonian!(CubicHenonHeiles<2> [lambda] |_t, q, p|
    kinetic = p.dot(p) * 0.5,
    potential = q.dot(q) * 0.5 + (q[0] * q[0] * q[1] - q[1] * q[1] * q[1] / 3.0) * lambda);
hamiltonian!(SeparableSwing<1> [g, l] |_t, q, p|
    kinetic = p[0] * p[0] / (l * l * 2.0),
    potential = -(g * l * q[0].cos()));

/// `∂z(t₁)/∂k` of the splitting runs against the forward sensitivity equations (DOP853 at
/// rtol = 1e-13, an independent route) and against central differences in `k` of the real runs.
fn check_splitting_parameter_derivatives<S, const N: usize, const M: usize, const K: usize>(
    name: &str,
    system: &S,
    at: impl Fn(&SVector<f64, M>) -> S,
    start: &State<N>,
    t1: f64,
    method: Splitting,
    steps: usize,
) where
    S: hamilton_jacobi::ParametricSeparable<N, M> + hamilton_jacobi::Separable<N>,
{
    let problem = Problem::new(system, start.t, start.q, start.p, t1).unwrap();
    let fixed = Fixed::new(method, steps).unwrap();
    let pt = splitting_parameter_tangent_map::<_, N, M>(&problem, &fixed).unwrap();
    // The final state is the real run's, the state block the run's own tangent map.
    let run = integrate(&problem, &fixed, &mut ()).unwrap();
    assert_eq!(pt.last, run.last, "{name}");
    assert_eq!(
        pt.jacobian,
        fixed.tangent_map(&problem).unwrap().jacobian,
        "{name}"
    );
    // The method's own error in ∂z/∂k, estimated by Richardson from n and 2n steps: for a
    // method of order r the error at n steps is (D_n − D_2n) · 2ʳ/(2ʳ − 1) to leading order.
    let finer = Fixed::new(method, 2 * steps).unwrap();
    let pt2 = splitting_parameter_tangent_map::<_, N, M>(&problem, &finer).unwrap();
    let r = method.table().order as i32;
    let richardson = 2f64.powi(r) / (2f64.powi(r) - 1.0);
    let own = ((pt.dq_dk - pt2.dq_dk).amax()).max((pt.dp_dk - pt2.dp_dk).amax()) * richardson;
    // The sensitivity equations.
    let aug = ParameterSensitivity::<_, N, M, K>::new(system).unwrap();
    let (qa, pa) = aug.initial_state(&start.q, &start.p);
    let big = Problem::new(&aug, start.t, qa, pa, t1).unwrap();
    let last = integrate(&big, &Dop853::new(1e-13, 1e-13).unwrap(), &mut ())
        .unwrap()
        .last;
    let (_, _, sq, sp) = aug.split(&last.q, &last.p);
    let scale = sq.amax().max(sp.amax());
    let err = (pt.dq_dk - sq).amax().max((pt.dp_dk - sp).amax());
    // The reference's own error: DOP853's tolerance proportionality, 1e-13 times the scale
    // amplified by the steps (a generous 1e-10 relative).
    let floor = 1e-10 * scale;
    println!(
        "{name}: ‖∂z/∂k − S‖ = {err:e}, Richardson estimate of the method's error {own:e}, \
         ‖S‖ = {scale:e}"
    );
    assert!(
        err <= 2.0 * own + floor,
        "{name}: {err:e} > 2 · {own:e} + {floor:e}"
    );
    assert!(
        own <= 1e-2 * scale,
        "{name}: the step is not in the asymptotic range"
    );
    // Central differences in each parameter of the real runs, with the truncation estimated from
    // D(h) and D(2h) and the rounding √n ε ‖z‖ ‖∂z/∂k‖ / h, as in
    // `ad_tangent_maps_agree_with_central_differences`.
    let k0 = system.parameters();
    for j in 0..M {
        let final_state = |s: f64| {
            let mut k = k0;
            k[j] += s;
            let sys = at(&k);
            let pr = Problem::new(&sys, start.t, start.q, start.p, t1).unwrap();
            let last = integrate(&pr, &fixed, &mut ()).unwrap().last;
            let mut z = SVector::<f64, 8>::zeros();
            for i in 0..N {
                z[i] = last.q[i];
                z[N + i] = last.p[i];
            }
            z
        };
        let h = 1e-5 * k0[j].abs().max(1.0);
        let d1 = (final_state(h) - final_state(-h)) / (2.0 * h);
        let d2 = (final_state(2.0 * h) - final_state(-2.0 * h)) / (4.0 * h);
        let truncation = (d2 - d1).amax() / 3.0;
        let z = run.last.q.amax().max(run.last.p.amax());
        let rounding = (steps as f64).sqrt() * f64::EPSILON * z * scale.max(1.0) / h;
        let mut ad = SVector::<f64, 8>::zeros();
        for i in 0..N {
            ad[i] = pt.dq_dk[(i, j)];
            ad[N + i] = pt.dp_dk[(i, j)];
        }
        let e = (ad - d1).amax();
        println!(
            "{name}, ∂/∂{}: ‖AD − D(h)‖ = {e:e}, truncation {truncation:e}, rounding \
             {rounding:e}",
            S::NAMES[j]
        );
        assert!(e <= 2.0 * (truncation + rounding), "{name}, k{j}: {e:e}");
    }
}

#[test]
fn parameter_derivatives_through_splitting_steps() {
    use hamilton_jacobi::integrate::coefficients::SABA2;
    use hamilton_jacobi::Parametric;
    let hh = CubicHenonHeiles { lambda: 1.0 };
    let hh_at = |k: &SVector<f64, 1>| CubicHenonHeiles { lambda: k[0] };
    for (name, method, steps) in [
        ("Verlet, QP1", Splitting::VERLET_KDK, 2000),
        ("Yoshida 4, QP1", Splitting::YOSHIDA3, 1000),
        ("SABA2, QP1", Splitting::new(&SABA2).unwrap(), 1000),
    ] {
        check_splitting_parameter_derivatives::<_, 2, 1, 4>(
            name,
            &hh,
            hh_at,
            &qp1(),
            20.0,
            method,
            steps,
        );
    }
    let swing = SeparableSwing { g: 9.81, l: 0.7 };
    let start = State::new(0.0, SVector::from([1.2]), SVector::from([0.3])).unwrap();
    for (name, method, steps) in [
        ("Verlet, swing", Splitting::VERLET_DKD, 4000),
        ("Yoshida 4, swing", Splitting::YOSHIDA3, 2000),
    ] {
        check_splitting_parameter_derivatives::<_, 1, 2, 3>(
            name,
            &swing,
            |k| SeparableSwing { g: k[0], l: k[1] },
            &start,
            10.0,
            method,
            steps,
        );
    }
    // The separable swing is the general one: the same Hamiltonian at every (g, l).
    let general = Swing { g: 9.81, l: 0.7 };
    let (q, p) = (SVector::from([0.4]), SVector::from([-1.1]));
    let k = SVector::from([9.0, 0.5]);
    assert_eq!(
        swing.hamiltonian_with(&k, 0.0, &q, &p),
        general.hamiltonian_with(&k, 0.0, &q, &p)
    );
    // Non-finite parameters are refused.
    let bad = CubicHenonHeiles { lambda: f64::NAN };
    let problem = Problem::new(&bad, 0.0, qp1().q, qp1().p, 1.0);
    if let Ok(problem) = problem {
        let fixed = Fixed::new(Splitting::VERLET_KDK, 10).unwrap();
        assert!(splitting_parameter_tangent_map::<_, 2, 1>(&problem, &fixed).is_err());
    }
}

#[test]
fn taylor_tangent_map_agrees_with_the_variational_equations() {
    // Along QP1 and CH1 over t = 50: the Taylor method's tangent map with its steps chosen on z
    // alone (frozen, replayed on the record of the variational equations) and with the
    // variational components in its step control, against the variational equations integrated
    // by DOP853 at rtol = atol = 1e-14 (an independent route). The bound is derived from the
    // tolerance: each of the n steps makes a local error of at most ε relative to max(1, ‖x‖)
    // (the Jorba–Zou control: the last terms of the series are ε), propagated to t₁ by a map of
    // norm at most ‖Φ‖, so the global error of Φ is at most n ε ‖Φ‖ max(1, ‖Φ‖); the reference
    // adds its own, 1e-14 under the same count.
    for (name, start) in [("QP1", qp1()), ("CH1", ch1())] {
        let problem = Problem::new(&HenonHeiles, 0.0, start.q, start.p, 50.0).unwrap();
        let reference =
            variational_tangent_map::<_, 2, 10>(&problem, &Dop853::new(1e-14, 1e-14).unwrap())
                .unwrap();
        let size = reference.jacobian.max_abs();
        for tol in [1e-8, 1e-10, 1e-12] {
            let m = Taylor::new(tol).unwrap();
            let frozen = m.tangent_map(&problem).unwrap();
            let controlled = variational_tangent_map::<_, 2, 10>(&problem, &m).unwrap();
            let run = integrate(&problem, &m, &mut ()).unwrap();
            // The frozen replay takes the run's steps; its state is the run's to rounding.
            assert_eq!(frozen.work.steps, run.work.steps);
            let state_error = (frozen.last.q - run.last.q)
                .amax()
                .max((frozen.last.p - run.last.p).amax());
            assert!(
                state_error <= 1e-13,
                "{name} {tol:e}: state {state_error:e}"
            );
            for (route, tm) in [("frozen", &frozen), ("controlled", &controlled)] {
                let n = tm.work.steps as f64 + reference.work.steps as f64;
                let bound = n * tol.max(1e-14) * size * size.max(1.0);
                let err = max_abs_diff(&tm.jacobian, &reference.jacobian);
                let defect = tm.jacobian.symplectic_defect();
                println!(
                    "{name} tol {tol:e} {route}: ‖Φ − Φ_ref‖ = {err:e} (bound {bound:e}), \
                     ‖ΦᵀJΦ − J‖ = {defect:e}, ‖Φ‖ = {size:e}, {} steps",
                    tm.work.steps
                );
                assert!(err <= bound, "{name} {tol:e} {route}: {err:e} > {bound:e}");
                // Symplectic to the tolerance: ΦᵀJΦ − J = δᵀJΦ + ΦᵀJδ + δᵀJδ for the error δ of
                // Φ, and the exact Φ_ref is symplectic to its own error.
                let ref_defect = reference.jacobian.symplectic_defect();
                let sym_bound = 2.0 * 4.0 * bound * (size + bound) + ref_defect;
                assert!(
                    defect <= sym_bound,
                    "{name} {tol:e} {route}: defect {defect:e} > {sym_bound:e}"
                );
            }
            // With the tangent in the norm the steps are no longer than on z alone.
            assert!(controlled.work.steps >= frozen.work.steps, "{name} {tol:e}");
        }
    }
}

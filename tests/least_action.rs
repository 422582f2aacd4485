//! Least action (SPEC M12): geodesics of the Jacobi metric by minimising the discretised Jacobi
//! energy with `argmin`, against the integrated motion of the same energy through the same two
//! configurations (DOP853), with the second order of the discretisation measured on two
//! resolutions; and Hamilton's principle with fixed times by minimising the action over a family
//! of paths.

use argmin::core::{CostFunction, Executor, State};
use argmin::solver::neldermead::NelderMead;
use hamilton_jacobi::action::{action, jacobi_metric};
use hamilton_jacobi::integrate::{integrate, Dop853, Problem, Samples};
use hamilton_jacobi::least_action::jacobi_geodesic;
use hamilton_jacobi::nalgebra::{DVector, SMatrix, SVector, Vector1, Vector2};
use hamilton_jacobi::num_dual::{Dual64, DualNum};
use hamilton_jacobi::systems::{DoublePendulum, Rod};
use hamilton_jacobi::{Error, Hamiltonian, NaturalSystem};

/// Distance from `x` to the polyline through `pts`.
fn distance_to_polyline(x: &Vector2<f64>, pts: &[Vector2<f64>]) -> f64 {
    pts.windows(2)
        .map(|w| {
            let d = w[1] - w[0];
            let s = ((x - w[0]).dot(&d) / d.norm_squared()).clamp(0.0, 1.0);
            (x - (w[0] + d * s)).norm()
        })
        .fold(f64::INFINITY, f64::min)
}

/// The double pendulum of two uniform rods: the motion from `q_A` with `q̇_A` for `τ`, sampled,
/// with its Maupertuis action `∫ 2T dt = ∫ p·q̇ dt` (Simpson on the samples).
fn motion(
    dp: &DoublePendulum,
    qa: Vector2<f64>,
    va: Vector2<f64>,
    tau: f64,
) -> (Vec<Vector2<f64>>, f64) {
    let a = dp.mass(0.0, &qa);
    let p0 = a * va;
    let count = 20_000;
    let mut samples = Samples::uniform(0.0, tau, count).unwrap();
    integrate(
        &Problem::new(dp, 0.0, qa, p0, tau).unwrap(),
        &Dop853::new(1e-13, 1e-15).unwrap(),
        &mut samples,
    )
    .unwrap();
    let twice_t: Vec<f64> = samples
        .states
        .iter()
        .map(|s| {
            let v = dp.vector_field(s.t, &s.q, &s.p).unwrap().0;
            s.p.dot(&v)
        })
        .collect();
    let h = tau / count as f64;
    let simpson = (0..count / 2)
        .map(|k| twice_t[2 * k] + 4.0 * twice_t[2 * k + 1] + twice_t[2 * k + 2])
        .sum::<f64>()
        * h
        / 3.0;
    (samples.states.iter().map(|s| s.q).collect(), simpson)
}

/// The Jacobi geodesic between the ends of a motion of the double pendulum of two rods, at the
/// motion's energy, follows the motion's path: the nodes' distance from the integrated path is
/// below `κ_max L²/n²` (eight sagittas of chords of length `L/n`) and falls as `n⁻²` (measured
/// order on n = 16 and 32), and the discrete Jacobi length approaches the
/// Maupertuis action `∫ 2T dt` of the motion at the same order.
#[test]
fn jacobi_geodesic_follows_the_integrated_motion_at_second_order() {
    let dp = DoublePendulum::rods(
        Rod::uniform(1.0, 1.0).unwrap(),
        Rod::uniform(0.7, 0.8).unwrap(),
        1.0,
    )
    .unwrap();
    let (qa, va, tau) = (Vector2::new(0.2, -0.1), Vector2::new(1.1, -0.6), 0.9);
    let h = 0.5 * (dp.mass(0.0, &qa) * va).dot(&va) + dp.potential(0.0, &qa);
    let (path, maupertuis) = motion(&dp, qa, va, tau);
    let qb = *path.last().unwrap();
    // Scale of the discretisation error: a chord of a curve of length L/n and curvature κ lies
    // within its sagitta κL²/(8n²) of the curve; the nodes are asserted within 8 sagittas of the
    // largest curvature, κ_max·L²/n² (κ from central differences of the samples).
    let euclidean_length: f64 = path.windows(2).map(|w| (w[1] - w[0]).norm()).sum();
    let kappa_max = path
        .windows(3)
        .map(|w| {
            let (d1, d2) = ((w[2] - w[0]) * 0.5, w[2] - w[1] * 2.0 + w[0]);
            (d1.x * d2.y - d1.y * d2.x).abs() / d1.norm().powi(3)
        })
        .fold(0.0, f64::max);
    let metric = jacobi_metric(dp, h).unwrap();
    let mut devs = Vec::new();
    let mut length_errors = Vec::new();
    for n in [16, 32] {
        let g = jacobi_geodesic(&metric, &qa, &qb, n).unwrap();
        assert_eq!(g.nodes.len(), n + 1);
        assert_eq!(g.nodes[0], qa);
        assert_eq!(g.nodes[n], qb);
        let dev = g
            .nodes
            .iter()
            .map(|x| distance_to_polyline(x, &path))
            .fold(0.0, f64::max);
        let dl = (g.length - maupertuis).abs() / maupertuis;
        println!(
            "n = {n}: {} iterations, |∇E| = {:e}, path deviation {dev:e}, Jacobi length {} vs \
             ∫2T dt {maupertuis} (rel. {dl:e})",
            g.iterations, g.gradient, g.length
        );
        let bound = kappa_max * euclidean_length.powi(2) / (n * n) as f64;
        println!("  bound κ_max L²/n² = {bound:e} (κ_max = {kappa_max}, L = {euclidean_length})");
        assert!(dev < bound, "n = {n}: deviation {dev:e} above {bound:e}");
        devs.push(dev);
        length_errors.push(dl);
    }
    let order = (devs[0] / devs[1]).log2();
    let length_order = (length_errors[0] / length_errors[1]).log2();
    println!("path order {order:.3}, length order {length_order:.3}");
    assert!((1.8..2.3).contains(&order), "path order {order}");
    assert!(
        (1.8..2.3).contains(&length_order),
        "length order {length_order}"
    );
}

/// The metric as a Lagrangian: the `action` of `√(G(q′, q′))` along a straight path is its Jacobi
/// length, which the discrete length of the straight path approaches at second order.
#[test]
fn jacobi_length_by_quadrature() {
    let dp = DoublePendulum::new(1.0, 1.0, 1.0, 1.0, 1.0).unwrap();
    let metric = jacobi_metric(dp, 1.5).unwrap();
    let (a, b) = (Vector2::new(0.1, 0.4), Vector2::new(0.6, -0.3));
    let len = action(
        &metric,
        |s: Dual64| SVector::<Dual64, 2>::from_fn(|i, _| (s * (b[i] - a[i])) + a[i]),
        0.0,
        1.0,
        1e-13,
    )
    .unwrap()
    .value;
    let discrete = |n: usize| -> f64 {
        (0..n)
            .map(|k| {
                let m = a + (b - a) * ((k as f64 + 0.5) / n as f64);
                metric.squared_norm(&m, &((b - a) / n as f64)).sqrt()
            })
            .sum()
    };
    let (e1, e2) = ((discrete(50) - len).abs(), (discrete(100) - len).abs());
    assert!(
        (e1 / e2).log2() > 1.9 && e2 < 1e-4 * len,
        "{len} {e1:e} {e2:e}"
    );
}

/// The oscillator `L = ½q̇² − ½q²` on `[0, T]`, `T = 2 < π` (no conjugate point).
struct Oscillator;

impl NaturalSystem<1> for Oscillator {
    fn mass<D: DualNum<f64> + Copy>(&self, _t: D, _q: &SVector<D, 1>) -> SMatrix<D, 1, 1> {
        SMatrix::from_element(D::from(1.0))
    }
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 1>) -> D {
        q[0] * q[0] * 0.5
    }
}

const SPAN: f64 = 2.0;
const Q0: f64 = 0.3;
const Q1: f64 = -0.5;
const MODES: usize = 3;

/// The trial path `q_lin(t) + Σ c_j sin(jπt/T)`.
fn trial(c: &[f64]) -> impl Fn(Dual64) -> SVector<Dual64, 1> + '_ {
    move |t: Dual64| {
        let mut q = t * ((Q1 - Q0) / SPAN) + Q0;
        for (j, cj) in c.iter().enumerate() {
            q += (t * ((j + 1) as f64 * std::f64::consts::PI / SPAN)).sin() * *cj;
        }
        Vector1::new(q)
    }
}

struct TrialAction;

impl CostFunction for TrialAction {
    type Param = DVector<f64>;
    type Output = f64;
    fn cost(&self, c: &DVector<f64>) -> Result<f64, argmin::core::Error> {
        Ok(action(
            &hamilton_jacobi::Natural(Oscillator),
            trial(c.as_slice()),
            0.0,
            SPAN,
            1e-14,
        )?
        .value)
    }
}

/// Hamilton's principle with fixed times: the action over `q_lin + Σ_{j ≤ 3} c_j sin(jπt/T)`,
/// minimised by Nelder–Mead, is least at the sine coefficients of the motion
/// `q(t) = Q₀ cos t + (Q₁ − Q₀ cos T) sin t / sin T` minus `q_lin` (the sines diagonalise the second
/// variation `∫(η̇² − η²) dt`, so the Galerkin minimiser is the truncated sine series), and the
/// minimum is below the action of every other trial path.
#[test]
fn hamilton_principle_least_action_over_trial_paths() {
    let start = vec![
        DVector::from_vec(vec![0.1, -0.1, 0.05]),
        DVector::from_vec(vec![0.15, -0.1, 0.05]),
        DVector::from_vec(vec![0.1, -0.05, 0.05]),
        DVector::from_vec(vec![0.1, -0.1, 0.1]),
    ];
    let res = Executor::new(
        TrialAction,
        NelderMead::new(start).with_sd_tolerance(1e-15).unwrap(),
    )
    .configure(|s| s.max_iters(4000))
    .run()
    .unwrap();
    let c = res.state().get_best_param().unwrap().clone();
    // Oracle: the sine coefficients (2/T)∫(q − q_lin) sin(jπt/T) dt by composite Simpson.
    let b = (Q1 - Q0 * SPAN.cos()) / SPAN.sin();
    let m = 20_000;
    let hh = SPAN / m as f64;
    for (j, cj) in c.iter().enumerate().take(MODES) {
        let k = (j + 1) as f64 * std::f64::consts::PI / SPAN;
        let f = |t: f64| (Q0 * t.cos() + b * t.sin() - Q0 - (Q1 - Q0) * t / SPAN) * (k * t).sin();
        let s = (0..m / 2)
            .map(|i| {
                let t = 2.0 * i as f64 * hh;
                f(t) + 4.0 * f(t + hh) + f(t + 2.0 * hh)
            })
            .sum::<f64>()
            * hh
            / 3.0;
        let want = 2.0 / SPAN * s;
        println!("c_{} = {cj:.12} (sine coefficient {want:.12})", j + 1);
        assert!((cj - want).abs() < 1e-6, "c_{}: {cj} vs {want}", j + 1);
    }
    let best = TrialAction.cost(&c).unwrap();
    for d in [
        [1e-3, 0.0, 0.0],
        [0.0, -1e-3, 0.0],
        [0.0, 0.0, 1e-3],
        [5e-4, 5e-4, -5e-4],
    ] {
        let other = DVector::from_iterator(3, c.iter().zip(d).map(|(x, y)| x + y));
        assert!(TrialAction.cost(&other).unwrap() > best);
    }
}

/// Typed errors: ends outside the region of motion, a bad resolution, NaN.
#[test]
fn jacobi_geodesic_refuses_bad_input() {
    let dp = DoublePendulum::new(1.0, 1.0, 1.0, 1.0, 1.0).unwrap();
    // V = −2 cos θ₁ − cos θ₂: V(a) = −3 cos 0.1 ≈ −2.985 and V(b) = −2 cos 0.2 − 1 ≈ −2.960,
    // both above h = −2.99, so both ends lie outside the region of motion V < h.
    let (a, b) = (Vector2::new(0.1, 0.1), Vector2::new(0.2, 0.0));
    let h = -2.99;
    assert!(dp.potential(0.0, &a) > h && dp.potential(0.0, &b) > h);
    let metric = jacobi_metric(dp, h).unwrap();
    assert!(matches!(
        jacobi_geodesic(&metric, &a, &b, 8),
        Err(Error::OutOfDomain { .. })
    ));
    let metric = jacobi_metric(dp, 0.5).unwrap();
    assert!(matches!(
        jacobi_geodesic(&metric, &a, &b, 1),
        Err(Error::InvalidInput { .. })
    ));
    assert!(jacobi_geodesic(&metric, &Vector2::new(f64::NAN, 0.0), &b, 8).is_err());
    assert!(jacobi_metric(dp, f64::INFINITY).is_err());
    // Ends inside, the straight path through the forbidden region: at h = 0.5 the region of
    // motion is |θ₁| < arccos((−0.5 − cos θ₂)/2), wide at θ₂ = 0, 2π and narrow at θ₂ = π, so
    // the ends (2.3, 0), (2.3, 2π) (V ≈ 0.333 < h) are joined by a straight path through
    // (2.3, π) where V ≈ 2.33 > h.
    let metric = jacobi_metric(dp, 0.5).unwrap();
    let (a, b) = (
        Vector2::new(2.3, 0.0),
        Vector2::new(2.3, 2.0 * std::f64::consts::PI),
    );
    assert!(dp.potential(0.0, &a) < 0.5 && dp.potential(0.0, &b) < 0.5);
    assert!(dp.potential(0.0, &((a + b) * 0.5)) > 0.5);
    let r = jacobi_geodesic(&metric, &a, &b, 8);
    assert!(r.is_err(), "{r:?}");
}

//! Points off the step grid: samples at requested times, terminal events and Poincaré sections
//! taken by partial steps of the method itself; methods as run-time values; observers without
//! type annotations.

mod common;

use hamilton_jacobi::integrate::{
    integrate, AnyMethod, Control, Crossing, Events, Fixed, Gauss, GeneralMethod, Method,
    MethodInfo, OneStep, Problem, Recorder, Report, Rk4, Samples, Section, Splitting,
    TimeTransformed, Work,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::phase::State;
use hamilton_jacobi::{hamiltonian, DualNum, Error, PhaseFunction, Separable};
use std::time::Instant;

hamiltonian!(
    /// Hénon–Heiles, `H = (p_x² + p_y²)/2 + (x² + y²)/2 + x²y − y³/3` (Hénon & Heiles, Astron. J. 69
    /// (1964) 73, doi:10.1086/109234), declared separable.
    HenonHeiles<2> |_s, _t, q, p|
        kinetic = (p[0] * p[0] + p[1] * p[1]) * 0.5,
        potential = (q[0] * q[0] + q[1] * q[1]) * 0.5 + q[0] * q[0] * q[1] - q[1] * q[1] * q[1] / 3.0
);

/// Energy of the Hénon–Heiles runs.
const ENERGY: f64 = 0.125;

/// A start on the section `x = 0` with `p_x > 0` at energy 1/8: `y = 0.3`, `p_y = 0` lies on a
/// regular (quasi-periodic) orbit, where nearby orbits separate linearly in time, so that the
/// global error of a method grows like its local error times `t` and section points of
/// different runs can be matched one by one.
fn henon_heiles_start() -> (SVector<f64, 2>, SVector<f64, 2>) {
    let (y, py) = (0.3f64, 0.0f64);
    let px = (2.0 * ENERGY - py * py - y * y + 2.0 * y.powi(3) / 3.0).sqrt();
    (SVector::from([0.0, y]), SVector::from([px, py]))
}

/// The harmonic oscillator `H = (p² + q²)/2`, separable, with the exact flow
/// `q = q₀ cos t + p₀ sin t`, `p = p₀ cos t − q₀ sin t`.
struct Oscillator;

impl Separable<1> for Oscillator {
    fn kinetic<D: DualNum<f64> + Copy>(&self, _t: D, p: &SVector<D, 1>) -> D {
        p[0] * p[0] * 0.5
    }
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 1>) -> D {
        q[0] * q[0] * 0.5
    }
}

fn oscillator_exact(t: f64) -> (f64, f64) {
    // From (q₀, p₀) = (1, 0.5).
    let (s, c) = t.sin_cos();
    (c + 0.5 * s, 0.5 * c - s)
}

/// A section point is on `x = 0` to the resolution of its time: the root search ends on adjacent
/// floating-point times, `|Δt| ≤ 2ε|t|`, so `|x| ≤ 2ε|t|·|ẋ|` with `ẋ = p_x` (doubled for the
/// rounding of the step itself).
fn on_section(z: &State<2>) -> bool {
    z.q[0].abs() <= 4.0 * f64::EPSILON * z.t.abs().max(1.0) * z.p[0].abs() && z.p[0] > 0.0
}

fn section_distance(a: &State<2>, b: &State<2>) -> f64 {
    (a.q - b.q).amax().max((a.p - b.p).amax())
}

/// The showcase: the Poincaré section `x = 0`, `p_x > 0` of Hénon–Heiles at `E = 1/8` by
/// Störmer–Verlet agrees with DOP853 (rtol 1e−13) to Verlet's global error.
///
/// * Reference: DOP853 at rtol 1e−13 (its crossings from its 7th-order continuous extension); its
///   own error is bounded by its distance to an rtol 1e−12 run, asserted 100× below the smallest
///   Verlet difference.
/// * Verlet with `h = 0.02, 0.01, 0.005, 0.0025`: the section points are partial Verlet steps on
///   the surface, so they carry Verlet's global error `C(t) h² + O(h³)`: the halving orders of
///   the largest point difference (and of the largest crossing-time difference) are within 0.35
///   of 2.
/// * Derived bound, crossing by crossing (the k-th Verlet point against the k-th DOP853 point,
///   both runs finding all 25): Verlet is symmetric, so its global error at grid points is
///   `C(t) h² + O(h⁴)`; the partial step to the surface adds a local error `O(h³)`. The
///   difference of two runs `d(h) = z_h − z_{h/2}` is then `¾ C h² + O(h³)`, and Richardson's
///   estimate `(4/3) d(h)` predicts the error `e(h) = z_h − z_ref` up to a remainder of relative
///   size `O(h)` (unit constant at the motion's unit frequency): asserted
///   `|e(h) − (4/3) d(h)| ≤ h · max|(4/3) d(h)| + (reference error)` for the crossing times and for
///   the phase-space points separately.
#[test]
fn henon_heiles_verlet_section_matches_dop853_to_second_order() {
    let (q0, p0) = henon_heiles_start();
    let span = 200.0;
    let problem = Problem::new(&HenonHeiles, 0.0, q0, p0, span).unwrap();
    let surface = |_t: f64, q: &SVector<f64, 2>, _p: &SVector<f64, 2>| q[0];
    let count = 25;
    let section_of = |method: &AnyMethod| -> (Vec<State<2>>, Report<2>) {
        let mut section = Section::new(surface, Crossing::Up).stop_after(count);
        let report = integrate(&problem, method, &mut section).unwrap();
        (section.points, report)
    };

    let (reference, report) = section_of(&AnyMethod::dop853(1e-13, 1e-15).unwrap());
    assert_eq!(reference.len(), count);
    assert!(report.stopped && report.last == reference[count - 1]);
    let (looser, _) = section_of(&AnyMethod::dop853(1e-12, 1e-14).unwrap());
    let reference_error = reference
        .iter()
        .zip(&looser)
        .map(|(a, b)| section_distance(a, b).max((a.t - b.t).abs()))
        .fold(0.0, f64::max);
    println!(
        "DOP853 section: {count} crossings up to t = {:.3}; distance to rtol 1e-12: {reference_error:.2e}",
        reference[count - 1].t
    );
    for z in &reference {
        assert!(on_section(z), "{z:?}");
    }

    let hs = [0.02, 0.01, 0.005, 0.0025];
    let mut runs = Vec::new();
    for &h in &hs {
        let steps = (span / h).round() as usize;
        let (points, report) = section_of(&AnyMethod::verlet(steps).unwrap());
        assert_eq!(points.len(), count, "h = {h}");
        assert!(report.stopped);
        for z in &points {
            assert!(on_section(z), "h = {h}: {z:?}");
        }
        runs.push(points);
    }
    let state_errors: Vec<f64> = runs
        .iter()
        .map(|pts| {
            pts.iter()
                .zip(&reference)
                .map(|(a, b)| section_distance(a, b))
                .fold(0.0, f64::max)
        })
        .collect();
    let time_errors: Vec<f64> = runs
        .iter()
        .map(|pts| {
            pts.iter()
                .zip(&reference)
                .map(|(a, b)| (a.t - b.t).abs())
                .fold(0.0, f64::max)
        })
        .collect();
    for (i, &h) in hs.iter().enumerate() {
        println!(
            "Verlet h = {h}: max |Δ(q,p)| = {:.3e}, max |Δt| = {:.3e}",
            state_errors[i], time_errors[i]
        );
    }
    let state_orders = common::halving_orders(&state_errors);
    let time_orders = common::halving_orders(&time_errors);
    println!("observed orders: points {state_orders:.3?}, times {time_orders:.3?}");
    for o in state_orders.iter().chain(&time_orders) {
        assert!((o - 2.0).abs() <= 0.35, "{state_orders:?} {time_orders:?}");
    }
    assert!(reference_error * 100.0 < state_errors[hs.len() - 1]);

    // Richardson, crossing by crossing: e(h) = z_h − z_ref against (4/3)(z_h − z_{h/2}), for the
    // crossing time and for the phase-space components separately.
    for i in 0..hs.len() - 1 {
        let h = hs[i];
        let comps = |z: &State<2>| [z.t, z.q[1], z.p[0], z.p[1]];
        let mut residual = [0.0f64; 2];
        let mut predicted_max = [0.0f64; 2];
        for k in 0..count {
            let (a, b, r) = (
                comps(&runs[i][k]),
                comps(&runs[i + 1][k]),
                comps(&reference[k]),
            );
            for j in 0..4 {
                let class = usize::from(j > 0);
                let predicted = (a[j] - b[j]) * 4.0 / 3.0;
                residual[class] = residual[class].max((a[j] - r[j] - predicted).abs());
                predicted_max[class] = predicted_max[class].max(predicted.abs());
            }
        }
        println!(
            "h = {h}: Richardson residual: times {:.3e} (of {:.3e}), points {:.3e} (of {:.3e})",
            residual[0], predicted_max[0], residual[1], predicted_max[1]
        );
        for class in 0..2 {
            assert!(
                residual[class] <= h * predicted_max[class] + reference_error,
                "h = {h}: {residual:?} {predicted_max:?}"
            );
        }
    }
}

/// The state a [`Fixed`] run of `method` stores at its `k`-th grid time, followed by one step of
/// the same method to `t`: the partial step computed by a second, independent pair of runs.
fn chained<M: OneStep<HenonHeiles, 2> + Copy>(
    method: M,
    start: (SVector<f64, 2>, SVector<f64, 2>),
    grid_time: f64,
    k: usize,
    t: f64,
) -> State<2> {
    let first = Problem::new(&HenonHeiles, 0.0, start.0, start.1, grid_time).unwrap();
    let at_grid = integrate(&first, &Fixed::new(method, k).unwrap(), &mut ()).unwrap();
    let second = Problem::new(&HenonHeiles, grid_time, at_grid.last.q, at_grid.last.p, t).unwrap();
    integrate(&second, &Fixed::new(method, 1).unwrap(), &mut ())
        .unwrap()
        .last
}

fn check_partial_steps<M: OneStep<HenonHeiles, 2> + Copy>(method: M, span: f64, steps: usize) {
    let start = henon_heiles_start();
    let problem = Problem::new(&HenonHeiles, 0.0, start.0, start.1, span).unwrap();
    let dt = span / steps as f64;
    let times = [0.37 * span, 0.81 * span];
    let mut samples = Samples::at(times).unwrap();
    integrate(&problem, &Fixed::new(method, steps).unwrap(), &mut samples).unwrap();
    assert_eq!(samples.states.len(), 2);
    for (z, &t) in samples.states.iter().zip(&times) {
        assert_eq!(z.t, t);
        let k = (t / dt).floor() as usize;
        let independent = chained(method, start, dt * k as f64, k, t);
        let d = section_distance(z, &independent);
        // Both are the same partial step from the same grid state up to the rounding of k steps
        // (grid times t₀ + k·dt against k steps of (k·dt)/k): a few ulps per step.
        assert!(
            d <= 1e-14 * (k as f64 + 1.0),
            "{}: sample at t = {t} differs from the chained runs by {d:e}",
            OneStep::<HenonHeiles, 2>::name(&method)
        );
    }
}

/// A sample between grid points is the method's own step of size `t − tₙ` from the stored state
/// `zₙ`, checked against two chained runs (to `tₙ`, then one step to `t`) for an explicit
/// splitting (Störmer–Verlet; Kahan–Li, 17 stages, order 8), an implicit method (Gauss–Legendre,
/// 2 stages) and RK4, forwards
/// and backwards in time. (Interpolating between grid points instead differs from the chained
/// runs by the interpolation error, ~1e−6 here.)
#[test]
fn off_grid_samples_are_partial_steps_of_the_method() {
    for span in [3.0, -3.0] {
        check_partial_steps(Splitting::VERLET_KDK, span, 30);
        check_partial_steps(Splitting::KAHAN_LI17, span, 30);
        check_partial_steps(Gauss::<2>::new().unwrap(), span, 30);
        check_partial_steps(Rk4, span, 30);
    }
}

/// Samples at times off the step grid converge at the method's order, not at an interpolant's:
/// Kahan–Li (17 stages, order 8) and Gauss–Legendre (3 stages, order 6) on the harmonic
/// oscillator, sampled at
/// `t = 2j + 1/7` (never a grid time for `h = 10/n`, `n = 2ᵐ·15`: `t/h = (2j + 1/7)·n/10` is not
/// whole) against the exact flow. The
/// halving orders are within 0.35 of the nominal order (a cubic Hermite interpolant would cap
/// them at 4).
#[test]
fn off_grid_samples_converge_at_the_method_order() {
    let problem = Problem::new(
        &Oscillator,
        0.0,
        SVector::from([1.0]),
        SVector::from([0.5]),
        10.0,
    )
    .unwrap();
    let times: Vec<f64> = (0..5).map(|j| 2.0 * j as f64 + 1.0 / 7.0).collect();
    let error = |method: &AnyMethod| {
        let mut samples = Samples::at(times.iter().copied()).unwrap();
        integrate(&problem, method, &mut samples).unwrap();
        assert_eq!(samples.states.len(), times.len());
        samples
            .states
            .iter()
            .map(|z| {
                let (q, p) = oscillator_exact(z.t);
                (z.q[0] - q).abs().max((z.p[0] - p).abs())
            })
            .fold(0.0, f64::max)
    };
    type Case = ([usize; 3], fn(usize) -> AnyMethod);
    let cases: [Case; 2] = [
        ([15, 30, 60], |n| {
            AnyMethod::of_splitting(Splitting::KAHAN_LI17, n).unwrap()
        }),
        ([30, 60, 120], |n| AnyMethod::gauss(3, n).unwrap()),
    ];
    for (steps, make) in cases {
        let info = make(1).info().unwrap();
        let (name, order) = (info.label(), info.order.unwrap());
        let errors: Vec<f64> = steps.iter().map(|&n| error(&make(n))).collect();
        let orders = common::halving_orders(&errors);
        let shown: Vec<String> = errors.iter().map(|e| format!("{e:.3e}")).collect();
        println!("{name}: errors {shown:?}, orders {orders:.3?}");
        // Above the rounding floor (≈ 1e−15 · steps).
        assert!(errors[2] > 1e-12, "{name}: {errors:?}");
        for o in &orders {
            assert!((o - order as f64).abs() <= 0.35, "{name}: {orders:?}");
        }
    }
}

/// A terminal event stops the run on the method's trajectory: the first downward zero of `q` of
/// the oscillator under Verlet (h = 0.1) is the partial Verlet step from the last grid state
/// (checked against chained runs), with `q = 0` to the resolution of the located time.
#[test]
fn terminal_event_stops_on_the_method_trajectory() {
    let (q0, p0) = (SVector::from([1.0]), SVector::from([0.5]));
    let problem = Problem::new(&Oscillator, 0.0, q0, p0, 10.0).unwrap();
    let verlet = Splitting::VERLET_KDK;
    let mut events = Events::new(|z: &State<1>| z.q[0], -1, true);
    let report = integrate(&problem, &Fixed::new(verlet, 100).unwrap(), &mut events).unwrap();
    assert!(report.stopped && events.found.len() == 1);
    let last = report.last;
    assert_eq!(last, events.found[0].state);
    // Exact first zero: q = cos t + ½ sin t = 0 at t = π − atan 2; Verlet's phase error is
    // O(h² t) ≈ 1e−2 · 2 / 24.
    assert!((last.t - (std::f64::consts::PI - 2f64.atan())).abs() < 2e-3);
    assert!(last.q[0].abs() <= 4.0 * f64::EPSILON * last.t * last.p[0].abs());
    let k = (last.t / 0.1).floor() as usize;
    let first = Problem::new(&Oscillator, 0.0, q0, p0, 0.1 * k as f64).unwrap();
    let grid = integrate(&first, &Fixed::new(verlet, k).unwrap(), &mut ()).unwrap();
    let second = Problem::new(&Oscillator, grid.last.t, grid.last.q, grid.last.p, last.t).unwrap();
    let independent = integrate(&second, &Fixed::new(verlet, 1).unwrap(), &mut ()).unwrap();
    let d = (independent.last.q - last.q)
        .amax()
        .max((independent.last.p - last.p).amax());
    assert!(d < 1e-14, "{d:e}");
}

/// The section surface as a [`PhaseFunction`] written once over dual numbers.
struct XCoordinate;

impl PhaseFunction<2> for XCoordinate {
    fn eval<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>, _p: &SVector<D, 2>) -> D {
        q[0]
    }
}

/// Two hundred section points of Hénon–Heiles (release mode, a fraction of a second): Verlet at
/// h = 0.01 and DOP853 at rtol 1e−13, the surface given as a [`PhaseFunction`]; every point on
/// the surface with `p_x > 0`, and its energy within Verlet's energy error along the grid
/// (`|ΔH| ≤ max grid |ΔH|` plus the partial step's own `O(h²)`, i.e. twice the grid maximum) or
/// DOP853's tolerance.
#[test]
fn two_hundred_section_points() {
    let (q0, p0) = henon_heiles_start();
    let span = 2000.0;
    let problem = Problem::new(&HenonHeiles, 0.0, q0, p0, span).unwrap();
    let energy = |z: &State<2>| {
        let (x, y) = (z.q[0], z.q[1]);
        0.5 * z.p.norm_squared() + 0.5 * (x * x + y * y) + x * x * y - y * y * y / 3.0
    };
    let methods = [
        AnyMethod::verlet((span / 0.01) as usize).unwrap(),
        AnyMethod::dop853(1e-13, 1e-15).unwrap(),
    ];
    for method in &methods {
        let surface = XCoordinate;
        let mut section =
            Section::new(move |t, q, p| surface.eval(t, q, p), Crossing::Up).stop_after(200);
        let mut grid_energy_error = 0.0f64;
        let mut monitor = hamilton_jacobi::integrate::Each(|z: &State<2>| {
            grid_energy_error = grid_energy_error.max((energy(z) - ENERGY).abs());
            Control::Continue
        });
        let clock = Instant::now();
        let report = integrate(&problem, method, &mut (&mut section, &mut monitor)).unwrap();
        let elapsed = clock.elapsed();
        let label = Method::<HenonHeiles, 2>::label(method);
        assert!(report.stopped, "{label}");
        assert_eq!(section.points.len(), 200, "{label}");
        let section_energy_error = section
            .points
            .iter()
            .map(|z| (energy(z) - ENERGY).abs())
            .fold(0.0, f64::max);
        println!(
            "{label}: 200 crossings up to t = {:.1} in {elapsed:?} ({} steps); max |ΔH| grid \
             {grid_energy_error:.2e}, section {section_energy_error:.2e}",
            report.last.t, report.work.steps
        );
        assert!(section.points.iter().all(on_section), "{label}");
        assert!(
            section_energy_error <= 2.0 * grid_energy_error + 1e-13,
            "{label}: {section_energy_error:e} vs {grid_energy_error:e}"
        );
    }
}

hamiltonian!(
    /// Hénon–Heiles written as a general (not declared separable) Hamiltonian.
    GeneralHenonHeiles<2> |_s, _t, q, p| (p[0] * p[0] + p[1] * p[1]) * 0.5
        + (q[0] * q[0] + q[1] * q[1]) * 0.5 + q[0] * q[0] * q[1] - q[1] * q[1] * q[1] / 3.0
);

/// Recording every k-th step, sampling and sections need no type annotation, alone or combined
/// (observers kept by the caller are combined by `&mut`).
#[test]
fn observers_need_no_type_annotation() {
    let (q0, p0) = henon_heiles_start();
    let problem = Problem::new(&HenonHeiles, 0.0, q0, p0, 30.0).unwrap();
    let method = Fixed::new(Splitting::VERLET_KDK, 3000).unwrap();
    let mut every = Recorder::every(100);
    integrate(&problem, &method, &mut every).unwrap();
    assert_eq!(every.states.len(), 1 + 30);
    let mut recorder = Recorder::every(300);
    let mut samples = Samples::uniform(0.0, 30.0, 7).unwrap();
    let mut section = Section::new(|_t, q, _p| q[0], Crossing::Both);
    integrate(
        &problem,
        &method,
        &mut (&mut recorder, (&mut samples, &mut section)),
    )
    .unwrap();
    assert_eq!(recorder.states.len(), 1 + 10);
    assert_eq!(samples.states.len(), 8);
    assert_eq!(samples.states[7].t, 30.0);
    // Both senses: alternating signs of p_x at the crossings.
    assert!(section.points.len() >= 4);
    assert!(section
        .points
        .windows(2)
        .all(|w| w[0].p[0].signum() != w[1].p[0].signum()));
}

/// A list of methods built at run time (splittings by key from the method table, Gauss–Legendre
/// by stage count, RK4, DOP853, Taylor) runs through one `integrate` call per element and gives exactly
/// the typed run's state and work; on a Hamiltonian not declared separable, the
/// [`GeneralMethod`]s do the same.
#[test]
fn methods_are_values() {
    let (q0, p0) = henon_heiles_start();
    let problem = Problem::new(&HenonHeiles, 0.0, q0, p0, 5.0).unwrap();
    let keys = ["verlet-kdk", "kahan-li17"];
    let mut methods: Vec<AnyMethod> = keys
        .iter()
        .map(|key| AnyMethod::new(MethodInfo::find(key).unwrap(), 50.0).unwrap())
        .collect();
    assert_eq!(methods[0], AnyMethod::verlet(50).unwrap());
    assert_eq!(
        methods[1],
        AnyMethod::of_splitting(Splitting::KAHAN_LI17, 50).unwrap()
    );
    for s in 1..=6 {
        methods.push(AnyMethod::gauss(s, 20).unwrap());
    }
    methods.push(AnyMethod::rk4(100).unwrap());
    methods.push(AnyMethod::dop853(1e-12, 1e-14).unwrap());
    methods.push(AnyMethod::rk45(1e-10, 1e-12).unwrap());
    methods.push(AnyMethod::new(MethodInfo::find("taylor").unwrap(), 1e-12).unwrap());
    // The logarithmic-Hamiltonian leapfrog with U = 1 − V > 0 on this orbit (E < 1/6).
    methods.push(AnyMethod::from(
        TimeTransformed::logarithmic(Splitting::VERLET_DKD, 0.01)
            .unwrap()
            .with_shift(1.0)
            .unwrap(),
    ));
    let typed = |m: &AnyMethod| -> Report<2> {
        let mut o = ();
        match m {
            AnyMethod::Splitting(f) => integrate(&problem, f, &mut o),
            AnyMethod::General(GeneralMethod::Rk4(f)) => integrate(&problem, f, &mut o),
            AnyMethod::General(GeneralMethod::Gauss1(f)) => integrate(&problem, f, &mut o),
            AnyMethod::General(GeneralMethod::Gauss2(f)) => integrate(&problem, f, &mut o),
            AnyMethod::General(GeneralMethod::Gauss3(f)) => integrate(&problem, f, &mut o),
            AnyMethod::General(GeneralMethod::Gauss4(f)) => integrate(&problem, f, &mut o),
            AnyMethod::General(GeneralMethod::Gauss5(f)) => integrate(&problem, f, &mut o),
            AnyMethod::General(GeneralMethod::Gauss6(f)) => integrate(&problem, f, &mut o),
            AnyMethod::General(GeneralMethod::Dop853(d)) => integrate(&problem, d, &mut o),
            AnyMethod::General(GeneralMethod::Rk45(d)) => integrate(&problem, d, &mut o),
            AnyMethod::General(GeneralMethod::Taylor(t)) => integrate(&problem, t, &mut o),
            AnyMethod::TimeTransformed(t) => integrate(&problem, t, &mut o),
        }
        .unwrap()
    };
    let mut labels = Vec::new();
    for m in &methods {
        let run = integrate(&problem, m, &mut ()).unwrap();
        let reference = typed(m);
        assert_eq!(run.last, reference.last);
        assert_eq!(run.work, reference.work);
        labels.push(Method::<HenonHeiles, 2>::label(m));
    }
    labels.sort();
    labels.dedup();
    assert_eq!(labels.len(), methods.len(), "{labels:?}");
    // Orders as documented.
    let orders: Vec<u32> = methods.iter().map(AnyMethod::order).collect();
    assert_eq!(orders, [2, 8, 2, 4, 6, 8, 10, 12, 4, 8, 5, 15, 2]);

    // Not declared separable: the general methods, swept the same way, agree with the separable
    // declaration of the same H (the same arithmetic up to the AD path: 1e−14).
    let general_problem = Problem::new(&GeneralHenonHeiles, 0.0, q0, p0, 5.0).unwrap();
    let general: Vec<GeneralMethod> = vec![
        GeneralMethod::rk4(100).unwrap(),
        GeneralMethod::gauss(2, 20).unwrap(),
        GeneralMethod::dop853(1e-12, 1e-14).unwrap(),
    ];
    for m in &general {
        let run = integrate(&general_problem, m, &mut ()).unwrap();
        let separable = integrate(&problem, &AnyMethod::General(*m), &mut ()).unwrap();
        let d = (run.last.q - separable.last.q)
            .amax()
            .max((run.last.p - separable.last.p).amax());
        assert!(
            d < 1e-14,
            "{}: {d:e}",
            Method::<GeneralHenonHeiles, 2>::label(m)
        );
    }

    // Refusals name what was wrong: an unknown key (with the keys), a method that needs more
    // than a separable system, a knob that is not a whole number of steps.
    let e = MethodInfo::find("Verlet").unwrap_err().to_string();
    assert!(e.contains("verlet-kdk") && e.contains("gauss3"), "{e}");
    for key in ["wisdom-holman", "saba3", "exact"] {
        let e = AnyMethod::new(MethodInfo::find(key).unwrap(), 10.0).unwrap_err();
        assert!(e.to_string().contains(key), "{e}");
    }
    let e = GeneralMethod::new(MethodInfo::find("verlet-kdk").unwrap(), 10.0).unwrap_err();
    assert!(e.to_string().contains("separable"), "{e}");
    for knob in [0.0, 2.5, f64::NAN, f64::INFINITY, -3.0] {
        assert!(AnyMethod::new(MethodInfo::find("rk4").unwrap(), knob).is_err());
    }
    assert!(AnyMethod::new(MethodInfo::find("dop853").unwrap(), f64::NAN).is_err());
    assert!(matches!(
        AnyMethod::gauss(7, 10),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(AnyMethod::rk4(0).is_err());
}

/// Requested times are validated before anything is allocated or run.
#[test]
fn samples_refuse_bad_times() {
    assert!(Samples::<1>::at([0.0, f64::NAN]).is_err());
    assert!(Samples::<1>::at([0.0, f64::INFINITY]).is_err());
    assert!(Samples::<1>::at([0.0, 1.0, 1.0]).is_err());
    assert!(Samples::<1>::at([0.0, 2.0, 1.0]).is_err());
    assert!(Samples::<1>::at([]).is_err());
    assert!(Samples::<1>::uniform(0.0, 1.0, 0).is_err());
    assert!(Samples::<1>::uniform(0.0, 1.0, usize::MAX).is_err());
    assert!(Samples::<1>::uniform(0.0, 0.0, 10).is_err());
    assert!(Samples::<1>::uniform(-f64::MAX, f64::MAX, 10).is_err());
    // Falling times serve a backward run; times behind the start are skipped.
    let problem = Problem::new(
        &Oscillator,
        2.0,
        SVector::from([1.0]),
        SVector::from([0.5]),
        0.0,
    )
    .unwrap();
    let mut samples = Samples::at([2.5, 1.5, 0.25]).unwrap();
    integrate(&problem, &Fixed::new(Rk4, 8).unwrap(), &mut samples).unwrap();
    let times: Vec<f64> = samples.states.iter().map(|z| z.t).collect();
    assert_eq!(times, [1.5, 0.25]);
}

/// Explicit Euler that refuses any step but the grid step: a stand-in for a method whose partial
/// step fails (an implicit solve that does not converge).
#[derive(Clone, Copy)]
struct GridOnly(f64);

impl OneStep<Oscillator, 1> for GridOnly {
    fn order(&self) -> u32 {
        1
    }
    fn name(&self) -> String {
        "grid-only Euler".into()
    }
    fn increment<D: DualNum<f64> + Copy>(
        &self,
        _system: &Oscillator,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
        dt: D,
        _work: &mut Work,
    ) -> hamilton_jacobi::Result<(SVector<D, 1>, SVector<D, 1>)> {
        if dt.re() != self.0 {
            return Err(Error::invalid("step", "off the grid"));
        }
        Ok((p * dt, -q * dt))
    }
}

/// A partial step that fails is the run's error, not a NaN sample.
#[test]
fn failed_partial_step_is_the_runs_error() {
    let problem = Problem::new(
        &Oscillator,
        0.0,
        SVector::from([1.0]),
        SVector::from([0.0]),
        1.0,
    )
    .unwrap();
    let method = Fixed::new(GridOnly(0.25), 4).unwrap();
    assert!(integrate(&problem, &method, &mut ()).is_ok());
    let mut on_grid = Samples::at([0.5, 1.0]).unwrap();
    assert!(integrate(&problem, &method, &mut on_grid).is_ok());
    assert_eq!(on_grid.states.len(), 2);
    let mut off_grid = Samples::at([0.6]).unwrap();
    let e = integrate(&problem, &method, &mut off_grid).unwrap_err();
    assert!(e.to_string().contains("off the grid"), "{e}");
}

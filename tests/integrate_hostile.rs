//! Integrators and the work-precision harness under hostile or careless input: reports say the
//! time a run actually reached, the work a call may start is bounded with typed errors that name
//! the limit and how to raise it, and out-of-range knobs are refused instead of being used or
//! silently changed.

use hamilton_jacobi::integrate::{
    integrate, Control, Dop853, Events, ExactStep, Fixed, Gauss, ImplicitMidpoint, Method,
    Observer, Problem, Rk4, Splitting, StepView, WisdomHolman,
};
use hamilton_jacobi::nalgebra::{SVector, Vector2};
use hamilton_jacobi::phase::State;
use hamilton_jacobi::systems::kepler;
use hamilton_jacobi::systems::Kepler2;
use hamilton_jacobi::workprecision::{sweep, Timing};
use hamilton_jacobi::Error;
use std::f64::consts::PI;
use std::time::{Duration, Instant};

type V2 = SVector<f64, 2>;

/// Kepler e = 0.5, μ = a = 1, from periapsis: period 2π, apoapsis (y = 0, moving to −y) at t = π
/// with speed `v_a = √((1 − e)/(1 + e)) = 1/√3`.
fn periapsis() -> (V2, V2) {
    (SVector::from([0.5, 0.0]), SVector::from([0.0, 3f64.sqrt()]))
}

/// Exact Kepler state at `t` from the periapsis state at 0 (Kepler's equation, f and g).
fn exact(t: f64) -> (V2, V2) {
    let (q0, p0) = periapsis();
    let (r, v) = kepler::propagate(
        1.0,
        &Vector2::new(q0[0], q0[1]),
        &Vector2::new(p0[0], p0[1]),
        t,
    )
    .unwrap();
    (SVector::from([r[0], r[1]]), SVector::from([v[0], v[1]]))
}

fn dist(s: &State<2>, (q, p): &(V2, V2)) -> f64 {
    (s.q - q).norm().max((s.p - p).norm())
}

/// Stops the run after its `k`-th step, remembering that step's end state.
struct StopAfter {
    k: usize,
    seen: usize,
    end: Option<State<2>>,
}

impl Observer<2> for StopAfter {
    fn step(&mut self, s: &StepView<'_, 2>) -> Control {
        self.seen += 1;
        if self.seen == self.k {
            self.end = Some(*s.next);
            Control::Stop
        } else {
            Control::Continue
        }
    }
}

/// Locates the apoapsis (`y` crossing zero downwards) as a terminal event and records, for the
/// step that contains it, the largest distance of the step's ends from the exact motion.
struct Apoapsis<G> {
    events: Events<G, 2>,
    end_error: f64,
    step: Option<(f64, f64)>,
}

impl<G: FnMut(&State<2>) -> f64> Observer<2> for Apoapsis<G> {
    fn step(&mut self, s: &StepView<'_, 2>) -> Control {
        let c = self.events.step(s);
        if let Control::StopAt(_) = c {
            self.end_error = dist(s.prev, &exact(s.prev.t)).max(dist(s.next, &exact(s.next.t)));
            self.step = Some((s.prev.t, s.next.t));
        }
        c
    }
}

/// Every method, on the same Kepler problem over `[0, 4]` (past the apoapsis at π): a run stopped
/// by an observer after 5 steps, and one ended by a terminal event, report the time reached — the
/// end of the fifth step (for fixed steps `5·(4/n)`, computed here independently), and the event
/// time — not `t₁ = 4`, with the state there.
///
/// The event time is checked against the exact apoapsis time π: the interpolated `y` vanishes at
/// the reported time, so `|t − π| ≤ (e_y + e_i)/|ẏ|` with `e_y` the method's error at the ends of
/// the event step (measured against the exact motion), `e_i ≤ h⁴/384 · max|y⁗|` the error of a
/// cubic (or better) interpolant of the exact motion (`|y⁗| ≤ 1` near apoapsis, where the
/// derivatives scale like `r ω⁴ ≈ 0.1`), and `|ẏ| ≥ v_a/2` over the step (asserted `h ≤ 0.05`,
/// over which ẏ changes by less than 5%).
fn check_time_reached<S, M: Method<S, 2>>(
    name: &str,
    system: &S,
    method: &M,
    fixed: Option<usize>,
) {
    let (q0, p0) = periapsis();
    let t1 = 4.0;
    let problem = Problem::new(system, 0.0, q0, p0, t1).unwrap();

    let mut stop = StopAfter {
        k: 5,
        seen: 0,
        end: None,
    };
    let r = integrate(&problem, method, &mut stop).unwrap();
    let end = stop.end.unwrap();
    assert!(r.stopped, "{name}");
    assert_eq!(r.work.steps, 5, "{name}");
    assert_eq!(
        r.last, end,
        "{name}: the report's state is the end of the fifth step"
    );
    if let Some(n) = fixed {
        assert_eq!(r.last.t, 5.0 * (t1 / n as f64), "{name}");
    }
    assert!(r.last.t < t1, "{name}: {}", r.last.t);

    let mut apo = Apoapsis {
        events: Events::new(|s: &State<2>| s.q[1], -1, true),
        end_error: f64::NAN,
        step: None,
    };
    let r = integrate(&problem, method, &mut apo).unwrap();
    let (a, b) = apo.step.unwrap();
    let h = b - a;
    assert!(h <= 0.05, "{name}: h = {h}");
    let v_a = (1.0f64 / 3.0).sqrt();
    let bound = (apo.end_error + h.powi(4) / 384.0) / (0.5 * v_a) + 4.0 * f64::EPSILON * PI;
    eprintln!(
        "{name}: stopped at t = {:.15}, |t − π| = {:.1e} (bound {bound:.1e})",
        r.last.t,
        (r.last.t - PI).abs()
    );
    assert!(r.stopped, "{name}");
    assert!(a <= r.last.t && r.last.t <= b, "{name}");
    assert_eq!(r.last, apo.events.found[0].state, "{name}");
    assert!((r.last.t - PI).abs() <= bound, "{name}: {} vs π", r.last.t);
}

#[test]
fn report_gives_the_time_reached_for_every_method() {
    let kepler = Kepler2::new(1.0).unwrap();
    let n = 200;
    check_time_reached(
        "Verlet",
        &kepler,
        &Fixed::new(Splitting::VERLET_DKD, n).unwrap(),
        Some(n),
    );
    check_time_reached(
        "Yoshida 4",
        &kepler,
        &Fixed::new(Splitting::YOSHIDA3, n).unwrap(),
        Some(n),
    );
    check_time_reached("RK4", &kepler, &Fixed::new(Rk4, n).unwrap(), Some(n));
    check_time_reached(
        "implicit midpoint",
        &kepler,
        &Fixed::new(ImplicitMidpoint::new().unwrap(), n).unwrap(),
        Some(n),
    );
    check_time_reached(
        "Gauss s=2",
        &kepler,
        &Fixed::new(Gauss::<2>::new().unwrap(), n).unwrap(),
        Some(n),
    );
    check_time_reached(
        "SABA2",
        &kepler,
        &Fixed::new(WisdomHolman::SABA2, n).unwrap(),
        Some(n),
    );
    check_time_reached(
        "exact flow",
        &kepler,
        &Fixed::new(ExactStep, n).unwrap(),
        Some(n),
    );
    check_time_reached(
        "DOP853",
        &kepler,
        &Dop853::new(1e-10, 1e-10).unwrap().with_h_max(0.05).unwrap(),
        None,
    );
}

/// An observer that asks to stop outside the step just taken (or at NaN) gets a typed error, not
/// a report whose time was never reached (an extrapolated state at t = 10³⁰⁰).
#[test]
fn stop_time_outside_the_step_is_refused() {
    let kepler = Kepler2::new(1.0).unwrap();
    let (q0, p0) = periapsis();
    let problem = Problem::new(&kepler, 0.0, q0, p0, 1.0).unwrap();
    struct StopAt(f64);
    impl Observer<2> for StopAt {
        fn step(&mut self, _: &StepView<'_, 2>) -> Control {
            Control::StopAt(self.0)
        }
    }
    for t in [1e300, -1.0, 2.0, f64::NAN] {
        let fixed = integrate(&problem, &Fixed::new(Rk4, 10).unwrap(), &mut StopAt(t));
        assert!(matches!(fixed, Err(Error::OutOfDomain { .. })), "{fixed:?}");
        let dop = integrate(&problem, &Dop853::new(1e-8, 1e-8).unwrap(), &mut StopAt(t));
        assert!(matches!(dop, Err(Error::OutOfDomain { .. })), "{dop:?}");
    }
    // Stopping exactly at t₁ on the last step is reaching t₁: not "stopped".
    let r = integrate(&problem, &Fixed::new(Rk4, 1).unwrap(), &mut StopAt(1.0)).unwrap();
    assert_eq!(r.last.t, 1.0);
    assert!(!r.stopped);
}

/// A step count beyond the limit is refused at once (before: `Fixed::new(Rk4, usize::MAX)` hung,
/// an exact-flow run of 10⁹ steps took over a minute); the error names the limit and how to raise
/// it, and the raised limit is honoured, also by `run` on a hand-built value.
#[test]
fn fixed_step_count_is_bounded() {
    let clock = Instant::now();
    for steps in [usize::MAX, 1_000_000_000, Fixed::<Rk4>::MAX_STEPS + 1] {
        match Fixed::new(Rk4, steps) {
            Err(Error::WorkLimit { limit, hint, .. }) => {
                assert_eq!(limit, Fixed::<Rk4>::MAX_STEPS);
                assert!(hint.contains("Fixed::with_limit"), "{hint}");
            }
            other => panic!("{steps}: expected a work limit, got {other:?}"),
        }
    }
    assert!(matches!(
        Fixed::new(ExactStep, 1_000_000_000),
        Err(Error::WorkLimit { .. })
    ));
    assert!(Fixed::new(Rk4, Fixed::<Rk4>::MAX_STEPS).is_ok());
    assert!(matches!(
        Fixed::with_limit(Rk4, 11, 10),
        Err(Error::WorkLimit { limit: 10, .. })
    ));
    assert!(matches!(Fixed::new(Rk4, 0), Err(Error::OutOfDomain { .. })));

    let kepler = Kepler2::new(1.0).unwrap();
    let (q0, p0) = periapsis();
    let problem = Problem::new(&kepler, 0.0, q0, p0, 1.0).unwrap();
    let hand_built = Fixed {
        steps: usize::MAX,
        ..Fixed::new(ExactStep, 1).unwrap()
    };
    assert!(matches!(
        integrate(&problem, &hand_built, &mut ()),
        Err(Error::WorkLimit { .. })
    ));
    let raised = Fixed::with_limit(ExactStep, 20, 20).unwrap();
    let r = integrate(&problem, &raised, &mut ()).unwrap();
    assert_eq!((r.work.steps, r.last.t), (20, 1.0));
    // 20 exact steps: a few ulps each, amplified by Kepler's equation (≤ 1/(1 − e) = 2), on
    // |y| ≤ 2: ≲ 20 · 4 · 2 · 2 ε ≈ 7e−14.
    assert!(dist(&r.last, &exact(1.0)) <= 1e-13);
    assert!(clock.elapsed() < Duration::from_secs(5));
}

/// The default step budget of DOP853 scales with the span: 2000 periods of Kepler e = 0.5 at
/// rtol 10⁻¹² take more attempted steps than the old fixed default of 10⁵, and complete; with the
/// budget set to 10⁵ by hand the run ends with a typed error naming the limit, where the run stood
/// and how to raise it. The budget itself is `clamp(10 ⌈span/h_init⌉, 10⁵, 10⁷)`.
#[test]
fn dop853_step_budget_scales_with_the_span() {
    let m = Dop853::new(1e-8, 1e-8).unwrap();
    assert_eq!(m.step_budget(1.0, 0.1), Dop853::AUTO_STEPS_MIN);
    assert_eq!(m.step_budget(1e5, -0.1), 10_000_000);
    assert_eq!(m.step_budget(3e4, 0.125), 2_400_000);
    assert_eq!(m.step_budget(1e300, 1e-6), Dop853::AUTO_STEPS_MAX);
    assert_eq!(m.step_budget(f64::NAN, 0.0), Dop853::AUTO_STEPS_MAX);
    assert_eq!(m.with_max_steps(7).unwrap().step_budget(1e300, 1.0), 7);

    let kepler = Kepler2::new(1.0).unwrap();
    let (q0, p0) = periapsis();
    let t1 = 2000.0 * 2.0 * PI;
    let problem = Problem::new(&kepler, 0.0, q0, p0, t1).unwrap();
    let m = Dop853::new(1e-12, 1e-12).unwrap();
    let r = integrate(&problem, &m, &mut ()).unwrap();
    let attempted = r.work.steps + r.work.rejected;
    eprintln!(
        "2000 periods at rtol 1e-12: {} steps, {} rejected, {:?}",
        r.work.steps, r.work.rejected, r.elapsed
    );
    assert!(attempted > 100_000, "{attempted}");
    assert_eq!(r.last.t, t1);
    // Energy −1/2 kept to the accumulated local errors: each accepted step's error is at most
    // atol + rtol·|y| per component (|y| ≤ √3), which moves H by at most |∇H| ≤ max(|p|, 1/r²) = 4
    // times that.
    let energy = 0.5 * r.last.p.norm_squared() - 1.0 / r.last.q.norm();
    let bound = r.work.steps as f64 * 4.0 * (1.0 + 3f64.sqrt()) * 1e-12;
    assert!((energy + 0.5).abs() <= bound, "{energy} (bound {bound:e})");

    match integrate(&problem, &m.with_max_steps(100_000).unwrap(), &mut ()) {
        Err(Error::WorkLimit {
            limit,
            detail,
            hint,
            ..
        }) => {
            assert_eq!(limit, 100_000);
            assert!(detail.contains("at t = "), "{detail}");
            assert!(hint.contains("Dop853::with_max_steps"), "{hint}");
        }
        other => panic!("expected a work limit, got {other:?}"),
    }

    // A span of 10³⁰⁰ with an explicit budget ends promptly with the same error.
    let clock = Instant::now();
    let huge = Problem::new(&kepler, 0.0, q0, p0, 1e300).unwrap();
    let e = integrate(&huge, &m.with_max_steps(1000).unwrap(), &mut ()).unwrap_err();
    assert!(matches!(e, Error::WorkLimit { limit: 1000, .. }), "{e:?}");
    let msg = e.to_string();
    assert!(msg.contains("1e300"), "{msg}");
    assert!(clock.elapsed() < Duration::from_secs(5));
}

/// rtol must lie in [RTOL_MIN, 1): 10³⁰⁰ (no digit asked for) and values below what the error
/// estimator resolves (10⁻¹⁶, 10⁻³⁰; before, silently raised to 2.3·10⁻¹⁵) are refused by the
/// constructor and by `run` on a hand-built value; the ends of the range are accepted.
#[test]
fn dop853_rtol_outside_its_range_is_refused() {
    for rtol in [
        1e300,
        1.0,
        1e-16,
        1e-30,
        Dop853::RTOL_MIN * (1.0 - f64::EPSILON),
    ] {
        match Dop853::new(rtol, 1e-10) {
            Err(Error::OutOfDomain { domain, .. }) => {
                assert!(domain.contains("2.3e-15"), "{domain}")
            }
            other => panic!("rtol {rtol:e}: expected a domain error, got {other:?}"),
        }
    }
    assert!(matches!(
        Dop853::new(f64::NAN, 1e-10),
        Err(Error::NonFinite { .. })
    ));
    let ok = Dop853::new(Dop853::RTOL_MIN, 1e-10).unwrap();
    assert_eq!(ok.rtol, Dop853::RTOL_MIN);
    assert!(Dop853::new(0.999, 1e-10).is_ok());

    let kepler = Kepler2::new(1.0).unwrap();
    let (q0, p0) = periapsis();
    let problem = Problem::new(&kepler, 0.0, q0, p0, 1.0).unwrap();
    for rtol in [1e300, 1e-20] {
        let m = Dop853 { rtol, ..ok };
        assert!(matches!(
            integrate(&problem, &m, &mut ()),
            Err(Error::OutOfDomain { .. })
        ));
    }
}

/// A span that overflows (`t₁ − t₀ = ∞` from finite ends) is refused by `Problem::new`; the
/// largest finite span is accepted.
#[test]
fn problem_with_an_infinite_span_is_refused() {
    let kepler = Kepler2::new(1.0).unwrap();
    let (q0, p0) = periapsis();
    for (t0, t1) in [
        (-f64::MAX, f64::MAX),
        (f64::MAX, -f64::MAX),
        (-1e308, 1e308),
    ] {
        let r = Problem::new(&kepler, t0, q0, p0, t1);
        assert!(
            matches!(r, Err(Error::OutOfDomain { .. })),
            "[{t0:e}, {t1:e}]: {r:?}"
        );
    }
    assert!(Problem::new(&kepler, 0.0, q0, p0, f64::MAX).is_ok());
    assert!(matches!(
        Problem::new(&kepler, 0.0, q0, p0, f64::INFINITY),
        Err(Error::NonFinite { .. })
    ));
}

/// `sweep` refuses a NaN, infinite or negative error from the run and a non-finite knob; with
/// `max_runs = usize::MAX` the time per sample is bounded by `min_time` plus one run (the
/// caller's choice), and a `min_time` beyond an hour is refused.
#[test]
fn sweep_refuses_bad_errors_and_bounds_its_time() {
    let quick = Timing {
        min_time: Duration::ZERO,
        max_runs: 1,
    };
    let work = hamilton_jacobi::integrate::Work::default();
    for (e, nonfinite) in [(f64::NAN, true), (f64::INFINITY, true), (-1.0, false)] {
        let r = sweep("m", "k", &[1.0], quick, |_| Ok((e, work)));
        match r {
            Err(Error::NonFinite { .. }) if nonfinite => {}
            Err(Error::OutOfDomain { .. }) if !nonfinite => {}
            other => panic!("error {e}: {other:?}"),
        }
    }
    assert!(matches!(
        sweep("m", "k", &[1.0, f64::NAN], quick, |_| Ok((1.0, work))),
        Err(Error::NonFinite { .. })
    ));

    let clock = Instant::now();
    let mut runs = 0usize;
    let s = sweep(
        "m",
        "k",
        &[1.0, 2.0],
        Timing {
            min_time: Duration::from_millis(20),
            max_runs: usize::MAX,
        },
        |k| {
            runs += 1;
            Ok((k, work))
        },
    )
    .unwrap();
    assert_eq!(s.samples.len(), 2);
    assert!(runs > 2, "{runs}");
    assert!(
        clock.elapsed() < Duration::from_secs(2),
        "{:?}",
        clock.elapsed()
    );

    let r = sweep(
        "m",
        "k",
        &[1.0],
        Timing {
            min_time: Duration::MAX,
            max_runs: usize::MAX,
        },
        |_| Ok((1.0, work)),
    );
    assert!(matches!(r, Err(Error::WorkLimit { .. })), "{r:?}");
}

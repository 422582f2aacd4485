//! The integration core: the fixed-step driver, RK4's order, observers (events on dense output,
//! energy monitor, recorder), exact flows as methods, compensated summation (Brouwer's law), bad
//! input.

mod common;

use hamilton_jacobi::brackets::certify;
use hamilton_jacobi::integrate::{
    integrate, methods, Control, Each, EnergyMonitor, Events, ExactStep, Fixed, Problem, Recorder,
    Rk4, StepMap,
};
use hamilton_jacobi::nalgebra::{SVector, Vector2};
use hamilton_jacobi::systems::kepler;
use hamilton_jacobi::systems::pendulum_exact::{exact_state, period};
use hamilton_jacobi::systems::{HarmonicOscillator, Kepler2, Pendulum};
use hamilton_jacobi::Error;
use std::f64::consts::PI;

/// Observed order: the log–log slope of error against `h`, dropping errors on the round-off
/// plateau (below `floor`) and errors that stopped decreasing.
fn observed_order(hs: &[f64], errors: &[f64], floor: f64) -> f64 {
    let mut pts = vec![];
    for (i, (&h, &e)) in hs.iter().zip(errors).enumerate() {
        if e <= floor || (i > 0 && e >= errors[i - 1]) {
            break;
        }
        pts.push((h, e));
    }
    assert!(
        pts.len() >= 3,
        "need ≥ 3 points above the plateau: {errors:?}"
    );
    common::loglog_slope(&pts)
}

/// RK4 is fourth order on the pendulum (one period from q₀ = 1) and on Kepler e = 0.5 (one
/// period from periapsis): the fitted slope is within ±0.3 of the order of its entry in the
/// method table, 4.
#[test]
fn rk4_observed_order() {
    let nominal = f64::from(methods::RK4.order.unwrap());
    assert_eq!(nominal, 4.0);
    let pen = Pendulum::new(1.0).unwrap();
    let tau = period(1.0, 1.0).unwrap();
    let pr = Problem::new(&pen, 0.0, SVector::from([1.0]), SVector::from([0.0]), tau).unwrap();
    let (qe, pe) = exact_state(1.0, 1.0, 0.0, tau).unwrap();
    let steps = [16usize, 32, 64, 128, 256];
    let errs: Vec<f64> = steps
        .iter()
        .map(|&n| {
            let r = integrate(&pr, &Fixed::new(Rk4, n).unwrap(), &mut ()).unwrap();
            (r.last.q[0] - qe).abs() + (r.last.p[0] - pe).abs()
        })
        .collect();
    let hs: Vec<f64> = steps.iter().map(|&n| tau / n as f64).collect();
    let order = observed_order(&hs, &errs, 1e-13);
    assert!(
        (order - nominal).abs() <= 0.3,
        "pendulum: order {order}, errors {errs:?}"
    );

    let kep = Kepler2::new(1.0).unwrap();
    let (q0, p0) = (SVector::from([0.5, 0.0]), SVector::from([0.0, 3f64.sqrt()]));
    let t = 2.0 * PI;
    let pr = Problem::new(&kep, 0.0, q0, p0, t).unwrap();
    let steps = [200usize, 400, 800, 1600, 3200];
    let errs: Vec<f64> = steps
        .iter()
        .map(|&n| {
            let r = integrate(&pr, &Fixed::new(Rk4, n).unwrap(), &mut ()).unwrap();
            (r.last.q - q0).norm() + (r.last.p - p0).norm()
        })
        .collect();
    let hs: Vec<f64> = steps.iter().map(|&n| t / n as f64).collect();
    let order = observed_order(&hs, &errs, 1e-12);
    assert!(
        (order - nominal).abs() <= 0.3,
        "Kepler: order {order}, errors {errs:?}"
    );
}

/// Work counts and the driver's bookkeeping.
#[test]
fn driver_counts_work_and_lands_on_t1() {
    let osc = HarmonicOscillator::new(1.0, 1.0).unwrap();
    let pr = Problem::new(&osc, 0.3, SVector::from([1.0]), SVector::from([0.0]), 2.3).unwrap();
    let r = integrate(&pr, &Fixed::new(Rk4, 7).unwrap(), &mut ()).unwrap();
    assert_eq!(r.last.t, 2.3);
    assert_eq!(r.work.steps, 7);
    assert_eq!(r.work.gradients, 28);
    assert!(!r.stopped);
    // Backwards in time returns to the start (RK4 error ≈ h⁴ · span ≈ 2e−11 at h = 2/700 each way).
    let fwd = integrate(&pr, &Fixed::new(Rk4, 700).unwrap(), &mut ()).unwrap();
    let back = Problem::new(&osc, 2.3, fwd.last.q, fwd.last.p, 0.3).unwrap();
    let b = integrate(&back, &Fixed::new(Rk4, 700).unwrap(), &mut ()).unwrap();
    assert_eq!(b.last.t, 0.3);
    assert!(
        (b.last.q[0] - 1.0).abs() < 1e-10 && b.last.p[0].abs() < 1e-10,
        "{:?}",
        b.last
    );
    // A recorder sees the start and every k-th step; an early stop ends the run.
    let mut rec = Recorder::every(2);
    integrate(&pr, &Fixed::new(Rk4, 7).unwrap(), &mut rec).unwrap();
    assert_eq!(rec.states.len(), 1 + 3);
    let mut count = 0;
    let mut stop = Each(|_: &hamilton_jacobi::State<1>| {
        count += 1;
        if count == 3 {
            Control::Stop
        } else {
            Control::Continue
        }
    });
    let s = integrate(&pr, &Fixed::new(Rk4, 7).unwrap(), &mut stop).unwrap();
    assert!(s.stopped && s.work.steps == 3);
}

/// Periapsis passages of Kepler e = 0.5 as events (`q·p` crossing zero upwards), located on
/// partial RK4 steps (the dense output of fixed-step methods) with 2000 steps per period, so the
/// event time is good to about the RK4 error of the state divided by d(q·p)/dt: asserted against
/// the exact period to 1e−7.
#[test]
fn events_on_dense_output() {
    let kep = Kepler2::new(1.0).unwrap();
    let (q0, p0) = (SVector::from([0.5, 0.0]), SVector::from([0.0, 3f64.sqrt()]));
    let pr = Problem::new(&kep, 0.0, q0, p0, 3.5 * 2.0 * PI).unwrap();
    let mut ev = Events::new(|s: &hamilton_jacobi::State<2>| s.q.dot(&s.p), 1, false);
    integrate(&pr, &Fixed::new(Rk4, 7_000).unwrap(), &mut ev).unwrap();
    // Upward crossings of q·p = r ṙ at periapsis: t = T, 2T, 3T (t = 0 is the start).
    assert_eq!(ev.found.len(), 3, "{:?}", ev.found);
    for (k, e) in ev.found.iter().enumerate() {
        let t = (k + 1) as f64 * 2.0 * PI;
        assert!(
            (e.state.t - t).abs() < 1e-7,
            "event {k}: {} vs {t}",
            e.state.t
        );
        assert_eq!(e.direction, 1);
    }
    // A terminal event stops the run there.
    let mut first = Events::new(|s: &hamilton_jacobi::State<2>| s.q.dot(&s.p), 1, true);
    let r = integrate(&pr, &Fixed::new(Rk4, 7_000).unwrap(), &mut first).unwrap();
    assert!(r.stopped && (r.last.t - 2.0 * PI).abs() < 1e-7);
}

/// RK4's energy drifts linearly over long runs (the energy monitor shows the slope), while the
/// exact flow with compensated summation shows no drift and an error that grows like √n
/// (Brouwer's law): over n = 10², 10³, 10⁴, 10⁵ steps the RMS energy error's log–log slope is
/// ≈ ½ (asserted ≤ 0.75; a linear drift would give 1).
#[test]
fn energy_drift_and_brouwer_law() {
    let kep = Kepler2::new(1.0).unwrap();
    let (q0, p0) = (SVector::from([0.5, 0.0]), SVector::from([0.0, 3f64.sqrt()]));
    let pr = Problem::new(&kep, 0.0, q0, p0, 200.0 * 2.0 * PI).unwrap();
    let mut mon = EnergyMonitor::new(&kep, 100);
    integrate(&pr, &Fixed::new(Rk4, 200 * 400).unwrap(), &mut mon).unwrap();
    // RK4 dissipates energy: the relative error decreases steadily.
    assert!(
        mon.drift_slope() < 0.0 && mon.last_error < -1e-6,
        "{}",
        mon.last_error
    );

    // Exact flow, step T/10·(1 + 1/√2) so the sampled phases do not repeat.
    let dt = 0.1 * 2.0 * PI * (1.0 + 0.5f64.sqrt());
    let mut rms = vec![];
    let ns = [100usize, 1_000, 10_000, 100_000];
    for &n in &ns {
        let pr = Problem::new(&kep, 0.0, q0, p0, dt * n as f64).unwrap();
        let mut mon = EnergyMonitor::new(&kep, (n / 100).max(1));
        integrate(&pr, &Fixed::new(ExactStep, n).unwrap(), &mut mon).unwrap();
        // RMS over the second half of the run.
        let half: Vec<f64> = mon.samples[mon.samples.len() / 2..]
            .iter()
            .map(|s| s.1)
            .collect();
        rms.push((half.iter().map(|e| e * e).sum::<f64>() / half.len() as f64).sqrt());
    }
    let lx: Vec<f64> = ns.iter().map(|&n| (n as f64).ln()).collect();
    let ly: Vec<f64> = rms.iter().map(|e| e.ln()).collect();
    let (mx, my) = (lx.iter().sum::<f64>() / 4.0, ly.iter().sum::<f64>() / 4.0);
    let slope = lx
        .iter()
        .zip(&ly)
        .map(|(x, y)| (x - mx) * (y - my))
        .sum::<f64>()
        / lx.iter().map(|x| (x - mx) * (x - mx)).sum::<f64>();
    eprintln!("Brouwer slope {slope:.3}, RMS relative energy errors {rms:?}");
    assert!(slope <= 0.75, "Brouwer slope {slope}, RMS errors {rms:?}");
    assert!(
        rms[3] < 1e-12,
        "energy error after 10⁵ exact steps: {rms:?}"
    );
}

/// The exact flow over 100 periods in one step reproduces Kepler's equation; one RK4 step is not
/// symplectic (defect O(h⁵)) and the exact step refuses dual arguments.
#[test]
fn exact_step_and_step_maps() {
    let kep = Kepler2::new(1.0).unwrap();
    let (q0, p0) = (SVector::from([0.5, 0.0]), SVector::from([0.0, 3f64.sqrt()]));
    let pr = Problem::new(&kep, 0.0, q0, p0, 200.0 * PI).unwrap();
    let r = integrate(&pr, &Fixed::new(ExactStep, 1).unwrap(), &mut ()).unwrap();
    let (x, _) = kepler::propagate(
        1.0,
        &Vector2::new(0.5, 0.0),
        &Vector2::new(0.0, 3f64.sqrt()),
        200.0 * PI,
    )
    .unwrap();
    assert!((r.last.q[0] - x[0]).abs() < 1e-15 && r.work.flows == 1);
    let rk = certify(
        &StepMap {
            system: &kep,
            method: &Rk4,
            dt: 0.1,
        },
        0.0,
        &q0,
        &p0,
    )
    .unwrap();
    assert!(
        rk.symplectic_defect > 1e-8,
        "RK4 is not symplectic: {}",
        rk.symplectic_defect
    );
    assert!(certify(
        &StepMap {
            system: &kep,
            method: &ExactStep,
            dt: 0.1
        },
        0.0,
        &q0,
        &p0
    )
    .is_err());
}

#[test]
fn bad_input_is_refused() {
    let kep = Kepler2::new(1.0).unwrap();
    let q0 = SVector::from([0.5, 0.0]);
    let p0 = SVector::from([0.0, 1.0]);
    assert!(Problem::new(&kep, 0.0, SVector::from([f64::NAN, 0.0]), p0, 1.0).is_err());
    assert!(Problem::new(&kep, 0.0, q0, p0, f64::INFINITY).is_err());
    assert!(matches!(
        Problem::new(&kep, 1.0, q0, p0, 1.0),
        Err(Error::InvalidInput { .. })
    ));
    assert!(Fixed::new(Rk4, 0).is_err());
    // A state that reaches the singularity exactly: a typed error, not NaN in the report.
    let at_origin = Problem::new(&kep, 0.0, SVector::from([0.0, 0.0]), p0, 1.0).unwrap();
    assert!(integrate(&at_origin, &Fixed::new(Rk4, 10).unwrap(), &mut ()).is_err());
}

//! Work-precision diagrams: Kepler e = 0.5 and the pendulum over 100 periods.
//!
//! Every method is swept over its knob; the error is the final position error against the exact
//! solution (Kepler's equation; Jacobi elliptic functions), the cost the best wall time of
//! repeated runs. A third comparison puts Wisdom–Holman splitting against the general methods
//! on a J2-perturbed Kepler orbit. Writes `out/work_precision_{kepler,pendulum,perturbed_kepler}`
//! `.{csv,svg,md}` and prints the Markdown tables.
//!
//! Run: `cargo run --release --example work_precision`

use hamilton_jacobi::integrate::{
    integrate, Dop853, ExactStep, Fixed, Gauss, OneStep, Problem, Rk4, Splitting, WisdomHolman,
};
use hamilton_jacobi::nalgebra::{SVector, Vector2};
use hamilton_jacobi::perturbation::forces::{PerturbedTwoBody, J2};
use hamilton_jacobi::perturbation::kepler_variation::{
    planetary_equations, ClassicalSolution, MeanElements,
};
use hamilton_jacobi::perturbation::normal_form::PendulumNormalForm;
use hamilton_jacobi::perturbation::ode::Ode;
use hamilton_jacobi::perturbation::variation::GeneralSolution;
use hamilton_jacobi::systems::kepler;
use hamilton_jacobi::systems::kepler::elements::Classical;
use hamilton_jacobi::systems::pendulum_exact::{exact_state, period};
use hamilton_jacobi::systems::{Kepler2, Pendulum};
use hamilton_jacobi::workprecision::{sweep, Comparison, Series, Timing};
use hamilton_jacobi::{Hamiltonian, Result};
use std::f64::consts::PI;

/// Sweep a fixed-step method over step counts; error = final position error.
fn fixed_series<S: Hamiltonian<N>, M: OneStep<S, N> + Copy, const N: usize>(
    problem: &Problem<'_, S, N>,
    method: M,
    steps: &[usize],
    exact_q: SVector<f64, N>,
) -> Result<Series> {
    let knobs: Vec<f64> = steps.iter().map(|&n| n as f64).collect();
    sweep(
        OneStep::<S, N>::name(&method),
        "steps",
        &knobs,
        Timing::default(),
        |n| {
            let run = integrate(problem, &Fixed::new(method, n as usize)?, &mut ())?;
            Ok(((run.last.q - exact_q).norm(), run.work))
        },
    )
}

/// Sweep DOP853 over tolerances (rtol = atol).
fn dop853_series<S: Hamiltonian<N>, const N: usize>(
    problem: &Problem<'_, S, N>,
    rtols: &[f64],
    exact_q: SVector<f64, N>,
) -> Result<Series> {
    sweep("DOP853", "rtol", rtols, Timing::default(), |rtol| {
        let run = integrate(problem, &Dop853::new(rtol, rtol)?, &mut ())?;
        Ok(((run.last.q - exact_q).norm(), run.work))
    })
}

/// All general (structure-agnostic) methods on one separable problem.
fn general_methods<S: hamilton_jacobi::Separable<N> + Hamiltonian<N>, const N: usize>(
    c: &mut Comparison,
    problem: &Problem<'_, S, N>,
    exact_q: SVector<f64, N>,
    base: usize,
) -> Result<()> {
    c.push(fixed_series(
        problem,
        Rk4,
        &geometric(base, 256 * base, 2.0),
        exact_q,
    )?);
    for (m, lo, hi) in [
        (Splitting::VERLET_DKD, 4 * base, 512 * base),
        (Splitting::BLANES_MOAN6, base, 64 * base),
        (Splitting::KAHAN_LI9, base / 2, 16 * base),
        (Splitting::KAHAN_LI17, base / 4, 8 * base),
        (Splitting::SOFRONIOU_SPALETTA35, base / 4, 4 * base),
    ] {
        c.push(fixed_series(
            problem,
            m,
            &geometric(lo, hi, 2f64.sqrt()),
            exact_q,
        )?);
    }
    c.push(fixed_series(
        problem,
        Gauss::<4>::new()?,
        &geometric(base / 4, 4 * base, 2.0),
        exact_q,
    )?);
    c.push(dop853_series(
        problem,
        &[1e-8, 1e-10, 1e-12, 1e-13, 1e-14, Dop853::RTOL_MIN],
        exact_q,
    )?);
    Ok(())
}

fn geometric(lo: usize, hi: usize, factor: f64) -> Vec<usize> {
    let mut v = vec![];
    let mut x = lo as f64;
    while x <= hi as f64 {
        v.push(x.round() as usize);
        x *= factor;
    }
    v
}

fn main() -> Result<()> {
    std::fs::create_dir_all("out")
        .map_err(|e| hamilton_jacobi::Error::invalid("output directory out/", e.to_string()))?;

    // Kepler e = 0.5, μ = a = 1 from periapsis, 100 periods.
    let kepler = Kepler2::new(1.0)?;
    let (e, periods): (f64, f64) = (0.5, 100.0);
    let q0 = SVector::from([1.0 - e, 0.0]);
    let p0 = SVector::from([0.0, ((1.0 + e) / (1.0 - e)).sqrt()]);
    let t1 = periods * 2.0 * PI;
    let problem = Problem::new(&kepler, 0.0, q0, p0, t1)?;
    let (exact_q, _) = kepler::propagate(
        1.0,
        &Vector2::new(q0[0], q0[1]),
        &Vector2::new(p0[0], p0[1]),
        t1,
    )?;
    let exact_q = SVector::from([exact_q[0], exact_q[1]]);
    let mut kep = Comparison::new("Kepler e = 0.5, 100 periods", "final position error");
    general_methods(&mut kep, &problem, exact_q, 4_000)?;
    kep.push(fixed_series(
        &problem,
        ExactStep,
        &[1, 10, 100, 1_000],
        exact_q,
    )?);
    report(&kep, "kepler")?;

    // Pendulum H = p²/2 − cos q, q₀ = 1, p₀ = 0, 100 periods.
    let pendulum = Pendulum::new(1.0)?;
    let tau = period(1.0, 1.0)?;
    let t1 = 100.0 * tau;
    let (q0, p0) = (SVector::from([1.0]), SVector::from([0.0]));
    let problem = Problem::new(&pendulum, 0.0, q0, p0, t1)?;
    let (qe, _) = exact_state(1.0, 1.0, 0.0, t1)?;
    let exact_q = SVector::from([qe]);
    let mut pen = Comparison::new("Pendulum q₀ = 1, 100 periods", "final angle error");
    general_methods(&mut pen, &problem, exact_q, 1_000)?;
    // The perturbation theory on the same axes: the Lie-series normal form of order N (built
    // afresh in every timed run) predicts the state after 100 periods.
    let orders: Vec<f64> = (1..=12).map(f64::from).collect();
    pen.push(sweep(
        "normal form (order N)",
        "order",
        &orders,
        Timing::default(),
        |order| {
            let nf = PendulumNormalForm::new(1.0, order as usize)?;
            let (q, _) = nf.state_at(1.0, 0.0, t1)?;
            Ok(((q - exact_q[0]).abs(), Default::default()))
        },
    )?);
    pen.push(fixed_series(
        &problem,
        ExactStep,
        &[1, 10, 100, 1_000],
        exact_q,
    )?);
    report(&pen, "pendulum")?;

    // Perturbed Kepler (J₂R² = ε = 1e−5, inclined e = 0.5 orbit), 20 periods: Wisdom–Holman
    // and SABA against the best general methods. Reference: Kahan–Li 8 with 4·10⁵ steps, checked
    // against 2·10⁵ steps.
    let j2 = PerturbedTwoBody::conservative(1.0, J2::new(1.0, 1e-5, 1.0)?)?;
    let (e, inc): (f64, f64) = (0.5, 0.6);
    let v = ((1.0 + e) / (1.0 - e)).sqrt();
    let q0 = SVector::from([1.0 - e, 0.0, 0.0]);
    let p0 = SVector::from([0.0, v * inc.cos(), v * inc.sin()]);
    let t1 = 20.0 * 2.0 * PI;
    let problem = Problem::new(&j2, 0.0, q0, p0, t1)?;
    let fine = |n| -> Result<SVector<f64, 3>> {
        Ok(
            integrate(&problem, &Fixed::new(Splitting::KAHAN_LI17, n)?, &mut ())?
                .last
                .q,
        )
    };
    let reference = fine(400_000)?;
    let ref_error = (reference - fine(200_000)?).norm();
    println!("perturbed Kepler reference: change on halving the step {ref_error:.1e}");
    let mut wh = Comparison::new(
        "Kepler + J2 (ε = 1e−5), e = 0.5, 20 periods",
        "final position error",
    );
    for m in [WisdomHolman::WH, WisdomHolman::SABA3, WisdomHolman::SABA4] {
        wh.push(fixed_series(
            &problem,
            m,
            &geometric(100, 25_600, 2.0),
            reference,
        )?);
    }
    wh.push(fixed_series(
        &problem,
        Splitting::KAHAN_LI17,
        &geometric(250, 16_000, 2.0),
        reference,
    )?);
    wh.push(dop853_series(
        &problem,
        &[1e-8, 1e-10, 1e-12, 1e-14],
        reference,
    )?);
    report(&wh, "perturbed_kepler")?;

    j2_theories()?;
    Ok(())
}

/// Theories against integrators on a J2-perturbed orbit (μ = 1, R = 0.9, J₂ = 1.08e−3; a = 1.2,
/// e = 0.05, i = 0.5), 100 orbits: the Cartesian problem by DOP853 and Kahan–Li 8, the osculating
/// elements by Lagrange's planetary equations (DOP853 on the element equations), and the mean
/// elements with Brouwer's first-order secular rates (no short-period terms: error O(J₂(R/a)² a)).
/// Reference: DOP853 at its tightest tolerance.
fn j2_theories() -> Result<()> {
    let (mu, radius, j2v) = (1.0, 0.9, 1.08e-3);
    let el = Classical::new(1.2, 0.05, 0.5, 0.3, 0.7, 0.2)?;
    let model = J2::new(mu, j2v, radius)?;
    let sys = PerturbedTwoBody::conservative(mu, model)?;
    let t1 = 100.0 * 2.0 * PI * el.a.powf(1.5);
    let (q0, p0) = el.to_state(mu)?;
    let problem = Problem::new(&sys, 0.0, q0, p0, t1)?;
    let tight = Dop853::new(Dop853::RTOL_MIN, 1e-17)?.with_max_steps(usize::MAX)?;
    let reference = integrate(&problem, &tight, &mut ())?.last.q;
    let check = integrate(
        &problem,
        &Dop853::new(1e-14, 1e-16)?.with_max_steps(usize::MAX)?,
        &mut (),
    )?
    .last
    .q;
    println!(
        "J2 reference: DOP853 at 2.3e−15 vs 1e−14 differ by {:.1e}",
        (reference - check).norm()
    );
    let mut c = Comparison::new(
        "J2-perturbed orbit, 100 orbits: theories and integrators",
        "final position error",
    );
    c.push(dop853_series(
        &problem,
        &[1e-6, 1e-8, 1e-10, 1e-12],
        reference,
    )?);
    c.push(fixed_series(
        &problem,
        Splitting::KAHAN_LI17,
        &geometric(500, 8_000, 2.0),
        reference,
    )?);
    let sol = ClassicalSolution::new(mu, 0.0)?;
    let (g1, g2) = sol.constants(&el, 0.0)?;
    let ode = Ode(planetary_equations(sol, model));
    c.push(sweep(
        "osculating elements (planetary equations, DOP853)",
        "rtol",
        &[1e-6, 1e-8, 1e-10, 1e-12],
        Timing::default(),
        |rtol| {
            let pr = Problem::new(&ode, 0.0, g1, g2, t1)?;
            let run = integrate(&pr, &Dop853::new(rtol, rtol)?, &mut ())?;
            let (q, _) = sol.state(t1, &run.last.q, &run.last.p);
            Ok(((q - reference).norm(), run.work))
        },
    )?);
    c.push(sweep(
        "mean elements (first-order secular rates)",
        "order",
        &[1.0],
        Timing::default(),
        |_| {
            let mean = MeanElements::j2(&model, 0.0, el)?;
            let (q, _) = mean.state(t1)?;
            Ok(((q - reference).norm(), Default::default()))
        },
    )?);
    report(&c, "j2_theories")
}

fn report(c: &Comparison, name: &str) -> Result<()> {
    let io =
        |e: std::io::Error| hamilton_jacobi::Error::invalid(format!("out/{name}"), e.to_string());
    let md = c.to_markdown(&[1e-6, 1e-9, 1e-12]);
    println!("{md}");
    std::fs::write(format!("out/work_precision_{name}.csv"), c.to_csv()).map_err(io)?;
    std::fs::write(format!("out/work_precision_{name}.md"), &md).map_err(io)?;
    #[cfg(feature = "cli")]
    hamilton_jacobi::plot::work_precision(c).to_svg(std::path::Path::new(&format!(
        "out/work_precision_{name}.svg"
    )))?;
    Ok(())
}

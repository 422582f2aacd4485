//! Drag decay of a low Earth orbit: Gauss's variational equations in modified equinoctial
//! elements (RK4 + Richardson) against Cartesian integration of the same force (DOP853 on
//! `H = |p|²/2 − μ/|q|` with `Q^nc = a_drag`).
//!
//! Orbit: perigee 250 km, apogee 400 km altitude (`a = 6703.137 km`, `e = 0.01119`),
//! `i = 51.6°`. Drag `a = −½ρ(C_D A/m)|v_rel|v_rel` in an exponential atmosphere rotating with
//! the Earth; `ρ₀ = 7.248·10⁻¹¹ kg/m³` at 250 km, scale height 45.546 km (the 250 km layer of
//! the exponential atmosphere tabulated in Vallado 2013 §8.6, used at every altitude: a toy
//! atmosphere), `C_D A/m = 0.022 m²/kg`.
//! Units: km, s, kg (`ρ` in kg/km³, `C_D A/m` in km²/kg).
//!
//! The first table gives the osculating `a(t)` and `e(t)` of both integrations once a day for ten
//! days, their differences and the Richardson error estimate of the element integration, then
//! the evaluations of the right-hand side and the wall time of each; the second the error at day
//! ten (against DOP853 at `10⁻¹⁴`) and the cost of each integration for several step counts and
//! tolerances.
//!
//! Run: `cargo run --release --example drag_gauss`

use hamilton_jacobi::integrate::{integrate, Control, Dop853, Observer, Problem, StepView, Work};
use hamilton_jacobi::nalgebra::Vector3;
use hamilton_jacobi::perturbation::forces::{NoPotential, PerturbedTwoBody};
use hamilton_jacobi::perturbation::gauss_variational::{
    mee_from_blocks, mee_to_blocks, ExponentialDrag, GaussEquations,
};
use hamilton_jacobi::perturbation::ode::rk4_richardson;
use hamilton_jacobi::phase::State;
use hamilton_jacobi::systems::kepler::elements::{
    state_to_modified_equinoctial, Classical, ModifiedEquinoctial,
};
use std::time::Instant;

const MU: f64 = 398_600.441_8;
const R_EARTH: f64 = 6378.137;
const OMEGA_EARTH: f64 = 7.292_115e-5;
const DAY: f64 = 86_400.0;

/// Records the state at given output times from the dense output.
struct Sampler {
    times: Vec<f64>,
    next: usize,
    states: Vec<State<3>>,
}

impl Observer<3> for Sampler {
    fn start(&mut self, state: &State<3>) {
        while self.next < self.times.len() && self.times[self.next] <= state.t {
            self.states.push(*state);
            self.next += 1;
        }
    }
    fn step(&mut self, step: &StepView<'_, 3>) -> Control {
        while self.next < self.times.len() && self.times[self.next] <= step.next.t {
            let t = self.times[self.next];
            self.states.push(if t == step.next.t {
                *step.next
            } else {
                step.dense.at(t)
            });
            self.next += 1;
        }
        Control::Continue
    }
}

/// One run of Gauss's equations: the elements (and the Richardson estimate) once a day.
struct GaussRun {
    rows: Vec<(ModifiedEquinoctial, f64)>,
    evaluations: usize,
    steps: usize,
    millis: f64,
}

/// Semi-major axis and eccentricity of modified equinoctial elements.
fn a_e(el: &ModifiedEquinoctial) -> (f64, f64) {
    let e = el.eccentricity();
    (el.p / ((1.0 - e) * (1.0 + e)), e)
}

fn main() -> hamilton_jacobi::Result<()> {
    let (h_perigee, h_apogee) = (250.0, 400.0);
    let a0 = R_EARTH + 0.5 * (h_perigee + h_apogee);
    let e0 = 0.5 * (h_apogee - h_perigee) / a0;
    let inc = 51.6f64.to_radians();
    let classical = Classical::new(a0, e0, inc, 0.3, 1.2, 0.0)?;
    let mee0 = classical.to_modified_equinoctial()?;
    let drag = ExponentialDrag::new(
        7.248e-11 * 1e9,
        R_EARTH + 250.0,
        45.546,
        0.022 * 1e-6,
        OMEGA_EARTH,
    )?;
    let period = std::f64::consts::TAU * (a0.powi(3) / MU).sqrt();
    let days = 10usize;
    let times: Vec<f64> = (0..=days).map(|d| d as f64 * DAY).collect();
    println!(
        "orbit: a₀ = {a0:.3} km, e₀ = {e0:.5}, i = 51.6°, period {period:.1} s; {days} days \
         ≈ {:.0} orbits",
        days as f64 * DAY / period
    );

    let gauss = GaussEquations::new(MU, drag)?;
    let system = PerturbedTwoBody::with_force(MU, NoPotential, drag)?;
    let run_gauss = |steps_per_orbit: f64| -> hamilton_jacobi::Result<GaussRun> {
        // One RK4 + Richardson run per day.
        let steps_per_day = (steps_per_orbit * DAY / period).ceil() as usize;
        let (mut ya, mut yb) = mee_to_blocks(&mee0);
        let mut rows = vec![(mee0, 0.0)];
        let mut evaluations = 0;
        let clock = Instant::now();
        for d in 0..days {
            let r = rk4_richardson(&gauss, times[d], &ya, &yb, times[d + 1], steps_per_day)?;
            (ya, yb) = r.y;
            evaluations += r.evaluations;
            rows.push((mee_from_blocks(&ya, &yb), r.max_error()));
        }
        Ok(GaussRun {
            rows,
            evaluations,
            steps: 3 * steps_per_day * days,
            millis: clock.elapsed().as_secs_f64() * 1e3,
        })
    };
    let run_cartesian = |tol: f64| -> hamilton_jacobi::Result<(Vec<State<3>>, Work, f64)> {
        let (r0, v0) = mee0.to_state(MU)?;
        let problem = Problem::new(&system, 0.0, r0, v0, times[days])?;
        let mut sampler = Sampler {
            times: times.clone(),
            next: 0,
            states: Vec::new(),
        };
        let report = integrate(&problem, &Dop853::new(tol, tol)?, &mut sampler)?;
        Ok((
            sampler.states,
            report.work,
            report.elapsed.as_secs_f64() * 1e3,
        ))
    };

    let steps_per_orbit = 60.0;
    let tol = 1e-12;
    let g = run_gauss(steps_per_orbit)?;
    let (cart, work, cart_ms) = run_cartesian(tol)?;
    println!(
        "\nGauss: RK4 + Richardson with {steps_per_orbit} and {} steps per orbit; Cartesian: \
         DOP853 rtol = atol = {tol:e}",
        2.0 * steps_per_orbit
    );
    println!(
        "\n| day | a Gauss (km) | a Cartesian (km) | Δa (m) | e Gauss | e Cartesian | Δe | \
         Richardson est. (largest element, p in km, L in rad) |"
    );
    println!("|---|---|---|---|---|---|---|---|");
    for (d, ((el, est), s)) in g.rows.iter().zip(&cart).enumerate() {
        let c = state_to_modified_equinoctial(MU, &Vector3::from(s.q), &Vector3::from(s.p))?;
        let ((ag, eg), (ac, ec)) = (a_e(el), a_e(&c));
        println!(
            "| {d} | {ag:.6} | {ac:.6} | {:.3e} | {eg:.8} | {ec:.8} | {:.1e} | {est:.1e} |",
            (ag - ac) * 1e3,
            eg - ec
        );
    }
    println!(
        "\nwork: Gauss {} RHS evaluations, {} RK4 steps, {:.1} ms; Cartesian {} evaluations, \
         {} steps (+{} rejected), {:.1} ms",
        g.evaluations, g.steps, g.millis, work.gradients, work.steps, work.rejected, cart_ms
    );
    let (a_end, _) = a_e(&g.rows[days].0);
    println!(
        "decay over {days} days: Δa = {:.3} km (mean {:.3} km/day)",
        a_end - a0,
        (a_end - a0) / days as f64
    );

    // Cost against accuracy at day 10, both measured against DOP853 at rtol = atol = 1e−14.
    let (reference, _, _) = run_cartesian(1e-14)?;
    let r_ref = reference[days].q;
    let c_ref = state_to_modified_equinoctial(
        MU,
        &Vector3::from(r_ref),
        &Vector3::from(reference[days].p),
    )?;
    let (a_ref, _) = a_e(&c_ref);
    println!("\nday {days}, against DOP853 at 1e−14:");
    println!("| integration | |Δr| (m) | Δa (m) | RHS evaluations | time (ms) |");
    println!("|---|---|---|---|---|");
    for spo in [8.0, 15.0, 30.0, 60.0] {
        let g = run_gauss(spo)?;
        let el = g.rows[days].0;
        let (r, _) = el.to_state(MU)?;
        println!(
            "| Gauss, RK4 + Richardson, {spo} + {} steps/orbit | {:.2e} | {:.2e} | {} | {:.1} |",
            2.0 * spo,
            (r - r_ref).norm() * 1e3,
            (a_e(&el).0 - a_ref) * 1e3,
            g.evaluations,
            g.millis
        );
    }
    for tol in [1e-8, 1e-10, 1e-12] {
        let (s, work, ms) = run_cartesian(tol)?;
        let c = state_to_modified_equinoctial(
            MU,
            &Vector3::from(s[days].q),
            &Vector3::from(s[days].p),
        )?;
        println!(
            "| Cartesian, DOP853 rtol = atol = {tol:e} | {:.2e} | {:.2e} | {} | {:.1} |",
            (s[days].q - r_ref).norm() * 1e3,
            (a_e(&c).0 - a_ref) * 1e3,
            work.gradients,
            ms
        );
    }
    Ok(())
}

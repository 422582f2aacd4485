//! One definition of a system serves every method.
//!
//! * **Hénon–Heiles**, declared once as `T(p) + V(q)` with `hamiltonian!`: Störmer–Verlet, a
//!   sixth-order composition (Kahan–Li), Gauss–Legendre and DOP853 on the same value; 1000
//!   crossings of the Poincaré section `x = 0`, `p_x > 0` at energy 1/8 (Hénon & Heiles,
//!   Astron. J. 69 (1964) 73, doi:10.1086/109234); the symplectic defect `‖MᵀJM − J‖` of one
//!   Verlet step certified by AD.
//! * **The pendulum** of the catalogue: action–angle variables by quadrature (read off its `H`),
//!   Hamilton's principal function between two positions, and the exact flow in Jacobi elliptic
//!   functions — three routes to the same motion.
//! * **Kepler + J₂**, written once as "Kepler + a disturbing function": Wisdom–Holman and SABA₂
//!   (Kepler drift + kicks), DOP853 on the Cartesian equations, Lagrange's planetary equations in
//!   classical elements, and `∂(state)/∂J₂` by the sensitivity equations, checked against a
//!   central difference.
//!
//! `cargo run --release --example one_definition`

use hamilton_jacobi::brackets::certify;
use hamilton_jacobi::hamilton_jacobi::principal::{principal_function, PrincipalOptions};
use hamilton_jacobi::hamilton_jacobi::ActionAngle;
use hamilton_jacobi::integrate::{
    integrate, AnyMethod, Crossing, Dop853, ExactStep, Fixed, Method, OneStep,
    ParameterSensitivity, Problem, Section, Splitting, StepMap, WisdomHolman,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{PerturbedTwoBody, J2};
use hamilton_jacobi::perturbation::kepler_variation::{planetary_equations, ClassicalSolution};
use hamilton_jacobi::perturbation::ode::Ode;
use hamilton_jacobi::perturbation::variation::GeneralSolution;
use hamilton_jacobi::systems::kepler::elements::Classical;
use hamilton_jacobi::systems::{ExactFlow, Pendulum};
use hamilton_jacobi::{hamiltonian, Hamiltonian, Result};
use std::f64::consts::PI;
use std::time::Instant;

hamiltonian!(
    /// Hénon–Heiles: `H = (p_x² + p_y²)/2 + (x² + y²)/2 + x²y − y³/3`.
    HenonHeiles<2> |_s, _t, q, p|
        kinetic = p.dot(p) * 0.5,
        potential = q.dot(q) * 0.5 + q[0] * q[0] * q[1] - q[1] * q[1] * q[1] / 3.0
);

fn henon_heiles() -> Result<()> {
    println!("## Hénon–Heiles, E = 1/8, written once");
    let (y0, energy) = (0.3f64, 0.125);
    let px0 = (2.0 * energy - y0 * y0 + 2.0 * y0.powi(3) / 3.0).sqrt();
    let (q0, p0) = (SVector::from([0.0, y0]), SVector::from([px0, 0.0]));
    let span = 7000.0;
    let problem = Problem::new(&HenonHeiles, 0.0, q0, p0, span)?;
    let h0 = HenonHeiles.value(0.0, &q0, &p0)?;
    // The methods as values, swept in one loop.
    let runs = [
        ("rtol = 1e-13", AnyMethod::dop853(1e-13, 1e-15)?),
        ("h = 0.01", AnyMethod::verlet((span / 0.01) as usize)?),
        (
            "h = 0.1",
            AnyMethod::of_splitting(Splitting::KAHAN_LI9, (span / 0.1) as usize)?,
        ),
        ("h = 0.1", AnyMethod::gauss(3, (span / 0.1) as usize)?),
    ];
    let mut reference = Vec::new();
    for (knob, method) in &runs {
        // The label of the method table, e.g. "Gauss–Legendre, 3 stages, order 6".
        let label = method
            .info()
            .map_or_else(|| "(unlisted method)".into(), |m| m.label());
        let mut section = Section::new(|_t, q, _p| q[0], Crossing::Up).stop_after(1000);
        let clock = Instant::now();
        let report = integrate(&problem, method, &mut section)?;
        let elapsed = clock.elapsed();
        let last = &report.last;
        let drift = (HenonHeiles.value(last.t, &last.q, &last.p)? - h0).abs();
        let points = section.points;
        if reference.is_empty() {
            reference = points.clone();
        }
        let first: f64 = points
            .iter()
            .zip(&reference)
            .take(20)
            .map(|(a, b)| (a.q - b.q).amax().max((a.p - b.p).amax()))
            .fold(0.0, f64::max);
        println!(
            "{:<58} {} crossings to t = {:7.1} in {elapsed:>9.1?}; |ΔE| = {drift:.1e}; first 20 within {first:.1e} of DOP853's",
            format!("{label}, {knob}"),
            points.len(),
            last.t
        );
    }
    // The step map of Verlet is symplectic: its AD Jacobian M satisfies MᵀJM = J.
    let step = StepMap {
        system: &HenonHeiles,
        method: &Splitting::VERLET_KDK,
        dt: 0.1,
    };
    let c = certify(&step, 0.0, &q0, &p0)?;
    println!(
        "one Verlet step (h = 0.1): symplectic defect ‖MᵀJM − J‖ = {:.1e}, det M − 1 = {:.1e}\n",
        c.symplectic_defect, c.det_minus_one
    );
    Ok(())
}

fn pendulum() -> Result<()> {
    println!("## Pendulum (the catalogue's), three routes to one motion");
    let pen = Pendulum::new(1.0)?;
    let (q0, p0) = (1.0f64, 0.0);
    // Action–angle variables by quadrature, read off H.
    let aa = ActionAngle::from_state(pen, q0, p0, -PI, PI)?;
    let period = aa.period();
    println!(
        "action J = {:.15} (± {:.0e}), frequency ω = {:.15}, period T = {:.15}",
        aa.action().value,
        aa.action().error,
        aa.frequency(),
        period.value
    );
    // The exact flow over a quarter period brings it to the bottom, q = 0.
    let (q, p) = pen.exact_flow(
        0.0,
        &SVector::from([q0]),
        &SVector::from([p0]),
        period.value / 4.0,
    )?;
    println!("exact flow at T/4: q = {:.1e}, p = {:.15}", q[0], p[0]);
    // The angle variable is measured from the lower turning point (w = 0 there, w = π at the
    // upper one): the motion from the upper turning point down passes q = 0 at w = 3π/2.
    let w = aa.angle(q[0], p[0])?;
    println!(
        "angle variable of that state: w = {w:.15} (3π/2 = {:.15})",
        1.5 * PI
    );
    // Hamilton's principal function from q = 1 to q = 0 over T/4: its end momenta are the flow's.
    let s = principal_function(
        &pen,
        &SVector::from([q0]),
        &SVector::from([0.0]),
        0.0,
        period.value / 4.0,
        &PrincipalOptions::default(),
    )?;
    println!(
        "principal function S = {:.12}; p¹ = ∂S/∂q¹ = {:.12} (exact flow {:.12}); H = {:.12}",
        s.s, s.p1[0], p[0], s.h0
    );
    // The exact flow as an integrator.
    let problem = Problem::new(
        &pen,
        0.0,
        SVector::from([q0]),
        SVector::from([p0]),
        100.0 * period.value,
    )?;
    let run = integrate(&problem, &Fixed::new(ExactStep, 100)?, &mut ())?;
    println!(
        "exact flow as an integrator, 100 periods in 100 steps: q − q₀ = {:.1e}\n",
        run.last.q[0] - q0
    );
    Ok(())
}

fn kepler_j2() -> Result<()> {
    println!("## Kepler + J₂, written once as Kepler + a disturbing function");
    let (mu, j2, radius) = (1.0, 1e-3, 1.0);
    let system = PerturbedTwoBody::conservative(mu, J2::new(mu, j2, radius)?)?;
    let el = Classical::new(2.0, 0.1, 0.5, 0.3, 0.2, 0.0)?;
    let sol = ClassicalSolution::new(mu, 0.0)?;
    let g0 = sol.constants(&el, 0.0)?;
    let (q0, p0) = sol.state(0.0, &g0.0, &g0.1);
    let t1 = 10.0 * 2.0 * PI * 2f64.powf(1.5);
    let problem = Problem::new(&system, 0.0, q0, p0, t1)?;
    let reference = integrate(&problem, &Dop853::new(Dop853::RTOL_MIN, 1e-17)?, &mut ())?.last;
    let show = |label: &str, q: &SVector<f64, 3>, elapsed: std::time::Duration| {
        println!(
            "{label:<70} |Δq| = {:.1e} in {elapsed:>9.1?}",
            (q - reference.q).amax()
        )
    };
    for method in [WisdomHolman::WH, WisdomHolman::SABA2] {
        let label = OneStep::<PerturbedTwoBody<J2>, 3>::name(&method);
        let r = integrate(&problem, &Fixed::new(method, 1000)?, &mut ())?;
        show(&format!("{label}, 1000 steps"), &r.last.q, r.elapsed);
    }
    let dop853 = Dop853::new(1e-10, 1e-12)?;
    let r = integrate(&problem, &dop853, &mut ())?;
    let label = format!(
        "{} (Cartesian)",
        Method::<PerturbedTwoBody<J2>, 3>::label(&dop853)
    );
    show(&label, &r.last.q, r.elapsed);
    // Lagrange's planetary equations with the same J₂ object, through DOP853.
    let ode = Ode(planetary_equations(sol, *system.potential()));
    let clock = Instant::now();
    let elements = Problem::new(&ode, 0.0, g0.0, g0.1, t1)?;
    let r = integrate(&elements, &Dop853::new(1e-10, 1e-12)?, &mut ())?;
    let (q, _) = sol.state(t1, &r.last.q, &r.last.p);
    show(
        "planetary equations (DOP853), rtol = 1e-10",
        &q,
        clock.elapsed(),
    );
    // ∂(state)/∂J₂ by the sensitivity equations, against a central difference.
    let aug = ParameterSensitivity::<_, 3, 1, 6>::new(&system)?;
    let (qa, pa) = aug.initial_state(&q0, &p0);
    let r = integrate(
        &Problem::new(&aug, 0.0, qa, pa, t1)?,
        &Dop853::new(1e-12, 1e-14)?,
        &mut (),
    )?;
    let (_, _, dq, _) = aug.split(&r.last.q, &r.last.p);
    let final_q = |j2: f64| -> Result<SVector<f64, 3>> {
        let s = PerturbedTwoBody::conservative(mu, J2::new(mu, j2, radius)?)?;
        let p = Problem::new(&s, 0.0, q0, p0, t1)?;
        Ok(integrate(&p, &Dop853::new(1e-12, 1e-14)?, &mut ())?.last.q)
    };
    let h = 1e-6;
    let cd = (final_q(j2 + h)? - final_q(j2 - h)?) / (2.0 * h);
    println!(
        "∂q/∂J₂ after 10 orbits = ({:.6}, {:.6}, {:.6}); central difference differs by {:.1e}",
        dq[0],
        dq[1],
        dq[2],
        (dq.column(0) - cd).amax()
    );
    Ok(())
}

fn main() -> Result<()> {
    henon_heiles()?;
    pendulum()?;
    kepler_j2()
}

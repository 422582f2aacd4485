//! Kepler + J₂ in Cartesian form, defined by an expression, with three and six degrees of
//! freedom (one satellite, and two satellites about the same oblate body) — the number of degrees
//! of freedom known only at run time, dispatched by `with_dof!`:
//!
//! ```text
//! H = Σₖ |pₖ|²/2 − μ/rₖ + (μJ₂R²/2)(3zₖ²/rₖ² − 1)/rₖ³
//! ```
//!
//! Each satellite is integrated by DOP853 for 20 orbits and compared with the crate's Rust-written
//! `PerturbedTwoBody<J2>` run at the same tolerance; the energy of the expression system is
//! conserved to the tolerance.
//!
//! Run with `cargo run --release --example expression_kepler_j2`.

use hamilton_jacobi::expression::ExpressionHamiltonian;
use hamilton_jacobi::integrate::{integrate, Dop853, Problem};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{PerturbedTwoBody, J2};
use hamilton_jacobi::{with_dof, Error, Hamiltonian, Result};
use std::f64::consts::TAU;
use std::time::Instant;

const PARAMETERS: [(&str, f64); 3] = [("mu", 1.0), ("J2", 1.08e-3), ("R", 0.9)];

/// The Hamiltonian of one satellite with coordinates `x`, `y`, `z` renamed by `suffix`.
fn satellite(k: usize) -> (String, [String; 3]) {
    let [x, y, z] = [format!("x{k}"), format!("y{k}"), format!("z{k}")];
    let r2 = format!("({x}^2 + {y}^2 + {z}^2)");
    let h = format!(
        "(p_{x}^2 + p_{y}^2 + p_{z}^2)/2 - mu/sqrt({r2}) + mu*J2*R^2/2 * (3*{z}^2/{r2} - 1)/sqrt({r2})^3"
    );
    (h, [x, y, z])
}

/// Initial states: near-circular inclined orbits of radius 1.2 and 1.5.
fn initial(k: usize) -> ([f64; 3], [f64; 3]) {
    let r = 1.2 + 0.3 * k as f64;
    let v = (1.0 / r).sqrt();
    let i: f64 = 0.5 + 0.3 * k as f64;
    ([r, 0.0, 0.0], [0.0, v * i.cos(), v * i.sin()])
}

fn run<const N: usize>(text: &str, names: &[&str], t1: f64) -> Result<()> {
    let h = ExpressionHamiltonian::<N>::new(text, names, None, &PARAMETERS)?;
    let (mut q0, mut p0) = (SVector::<f64, N>::zeros(), SVector::<f64, N>::zeros());
    for k in 0..N / 3 {
        let (q, p) = initial(k);
        for i in 0..3 {
            q0[3 * k + i] = q[i];
            p0[3 * k + i] = p[i];
        }
    }
    let e0 = h.check_state(0.0, &q0, &p0)?;
    let dop = Dop853::new(1e-12, 1e-14)?;
    let clock = Instant::now();
    let r = integrate(&Problem::new(&h, 0.0, q0, p0, t1)?, &dop, &mut ())?;
    let elapsed = clock.elapsed();
    let e1 = h.value(r.last.t, &r.last.q, &r.last.p)?;
    println!(
        "{N} degrees of freedom: {} record operations for H and its gradient, {} steps in {:.1?}, \
         relative energy error {:.1e}",
        h.gradient_record().len(),
        r.work.steps,
        elapsed,
        ((e1 - e0) / e0).abs()
    );
    let rust = PerturbedTwoBody::conservative(1.0, J2::new(1.0, 1.08e-3, 0.9)?)?;
    for k in 0..N / 3 {
        let (q, p) = initial(k);
        let problem = Problem::new(&rust, 0.0, SVector::from(q), SVector::from(p), t1)?;
        let s = integrate(&problem, &dop, &mut ())?.last;
        let dq = (0..3)
            .map(|i| (r.last.q[3 * k + i] - s.q[i]).powi(2))
            .sum::<f64>()
            .sqrt();
        println!("  satellite {k}: |q_expression − q_rust| = {dq:.1e} after 20 orbits");
    }
    Ok(())
}

fn main() -> Result<()> {
    let t1 = 20.0 * TAU * 1.5f64.powf(1.5);
    for satellites in [1, 2] {
        let (terms, names): (Vec<String>, Vec<[String; 3]>) =
            (0..satellites).map(satellite).unzip();
        let text = terms.join(" + ");
        let names: Vec<&str> = names.iter().flatten().map(String::as_str).collect();
        with_dof!(names.len(), N => run::<N>(&text, &names, t1)?, {
            return Err(Error::invalid("degrees of freedom", "not in 1 … 6"))
        });
    }
    Ok(())
}

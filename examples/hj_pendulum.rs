//! Action–angle variables of the pendulum by quadrature, up to the separatrix [Ardema 17.3].
//!
//! `J = (1/2π)∮p dq`, `T = 2π dJ/dh`, and the angle `w = ωt` from the lower turning point. The
//! exact factorised radicand takes the gap `δ = π − a` to the separatrix itself, so periods stay
//! finite and accurate for every representable δ > 0; the separatrix is an error, never ∞.
//!
//! Run: `cargo run --release --example hj_pendulum`

use hamilton_jacobi::hamilton_jacobi::ActionAngle;
use hamilton_jacobi::systems::pendulum_exact::{exact_state, period_from_gap};
use hamilton_jacobi::systems::Pendulum;
use std::f64::consts::PI;

fn main() -> hamilton_jacobi::Result<()> {
    let pen = Pendulum::new(1.0)?;
    println!(
        "| δ = π − a | action J | period (quadrature) | period (AGM) | rel. diff | evaluations |"
    );
    println!("|---|---|---|---|---|---|");
    for delta in [PI - 0.1, 1.0, 1e-2, 1e-6, 1e-10, 1e-16] {
        let aa = ActionAngle::pendulum(pen, delta)?;
        let (t, agm) = (aa.period(), period_from_gap(1.0, delta)?);
        println!(
            "| {delta:.3e} | {:.15} | {:.15} | {agm:.15} | {:.1e} | {} |",
            aa.action().value,
            t.value,
            (t.value - agm).abs() / agm,
            t.evaluations
        );
    }
    match ActionAngle::pendulum(pen, 0.0) {
        Err(e) => println!("\nδ = 0: {e}"),
        Ok(_) => unreachable!("the separatrix has no action–angle variables"),
    }

    // The generic route (numerical turning points) at energies approaching the separatrix.
    println!("\n| h/h_sep | generic period | exact-radicand period |");
    println!("|---|---|---|");
    for x in [0.5f64, 0.99, 0.999_999, 1.0] {
        let h = 2.0 * x;
        let a = 2.0 * x.sqrt().asin();
        match ActionAngle::new(pen, h, 0.0, -4.0, 4.0) {
            Ok(aa) => println!(
                "| {x} | {:.15} | {:.15} |",
                aa.period().value,
                ActionAngle::pendulum(pen, PI - a)?.period().value
            ),
            Err(e) => println!("| {x} | {e} | — |"),
        }
    }

    // The angle along the exact motion.
    let aa = ActionAngle::pendulum(pen, 0.5)?;
    let a = PI - 0.5;
    println!("\n| t | w (from the state) | ωt |");
    println!("|---|---|---|");
    for t in [0.5, 2.0, 5.0] {
        let (q, p) = exact_state(1.0, -a, 0.0, t)?;
        println!(
            "| {t} | {:.15} | {:.15} |",
            aa.angle(q, p)?,
            (aa.frequency() * t).rem_euclid(2.0 * PI)
        );
    }
    Ok(())
}

//! The pendulum's exact period from small amplitude to the separatrix, by the AGM with the
//! complementary modulus computed from the gap δ = π − a.
//!
//! Run with `cargo run --release --example pendulum_separatrix`.

use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::{pendulum_exact, ExactFlow, Pendulum};
use hamilton_jacobi::{Hamiltonian, Result};
use std::f64::consts::PI;

fn main() -> Result<()> {
    let pend = Pendulum::new(1.0)?;
    println!("| δ = π − a | τ exact | 4 ln(8/δ) | 2π(1 + a²/16) |");
    println!("|---|---|---|---|");
    for k in 0..=16 {
        let delta = 10f64.powi(-k);
        let a = PI - delta;
        println!(
            "| 1e-{k} | {:.12} | {:.12} | {:.6} |",
            pendulum_exact::period_from_gap(1.0, delta)?,
            4.0 * (8.0 / delta).ln(),
            2.0 * PI * (1.0 + a * a / 16.0)
        );
    }
    // The exact motion from rest at a = 3 returns to its start after one period.
    let (q0, p0) = (SVector::from([3.0]), SVector::from([0.0]));
    let tau = pend.period(3.0)?;
    let (q, p) = pend.exact_flow(0.0, &q0, &p0, tau)?;
    println!(
        "\na = 3: τ = {tau:.13}; state after one period ({:.3e}, {:.3e}), energy error {:.1e}",
        q[0] - q0[0],
        p[0] - p0[0],
        pend.value(0.0, &q, &p)? - pend.value(0.0, &q0, &p0)?
    );
    // On the separatrix itself the period is a typed error, not ∞.
    match pend.period(PI) {
        Err(e) => println!("a = π: {e}"),
        Ok(t) => println!("a = π: unexpected period {t}"),
    }
    Ok(())
}

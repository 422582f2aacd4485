//! The Hénon–Heiles Hamiltonian `H = ½(p_x² + p_y² + x² + y²) + x²y − y³/3` about its minimum:
//! the 1:1 resonant (Gustavson) normal form from the Hamiltonian written once, its size per
//! degree, the remainder `|H ∘ φ − K|` against the amplitude, and the construction time per degree.
//!
//! Run with `cargo run --release --example normal_form_henon_heiles`.

use hamilton_jacobi::nalgebra::Vector2;
use hamilton_jacobi::perturbation::birkhoff::{normal_form, NormalFormKind};
use hamilton_jacobi::stability::hamiltonian_equilibrium;
use hamilton_jacobi::systems::HenonHeiles;
use std::time::Instant;

fn main() -> hamilton_jacobi::Result<()> {
    let eq = hamiltonian_equilibrium(
        &HenonHeiles,
        0.0,
        &Vector2::new(0.1, -0.1),
        &Vector2::zeros(),
    )?;
    println!(
        "equilibrium q = {:?}, |∇H| = {:e}",
        eq.q.as_slice(),
        eq.gradient_norm
    );
    let resonance = NormalFormKind::Resonant(vec![vec![1, -1]]);
    println!("degree  time        ‖K_K‖        remainder(ρ=0.05)  remainder(ρ=0.1)  optimal degree at ρ=0.3");
    for degree in [4usize, 6, 8, 10, 12, 14, 16, 20, 24] {
        let clock = Instant::now();
        let nf = normal_form(&HenonHeiles, 0.0, &eq, degree, resonance.clone())?;
        let elapsed = clock.elapsed();
        let r1 = nf.remainder(&HenonHeiles, 0.0, 0.05, 64)?;
        let r2 = nf.remainder(&HenonHeiles, 0.0, 0.1, 64)?;
        let d = nf.diagnostics(0.3)?;
        println!(
            "{degree:6}  {:>9.3?}  {:11.3e}  {r1:17.3e}  {r2:16.3e}  {}",
            elapsed,
            nf.normal_form().part_norm(degree),
            d.optimal_degree
        );
    }
    Ok(())
}

//! The Kepler problem by Hamilton–Jacobi separation in polar coordinates [Ardema 10.1, 17.3].
//!
//! `K = kθ + ∫ √F(r) dr`, `F = 2h + 2μ/r − k²/r²`: the time law `∂K/∂h = t − t₀` and the orbit
//! equation are quadratures between the apsides, evaluated through the turning points with the
//! substitution `r = ½(r_p + r_a) − ½(r_a − r_p) cos s`. Prints the half period and apsidal angle
//! for e from 0 to 1 − 1e−9 (both π for μ = a = 1), the motion against Kepler's equation, and the
//! shipped complete integral's elements (Jacobi's theorem).
//!
//! Run: `cargo run --release --example hj_kepler`

use hamilton_jacobi::hamilton_jacobi::{
    ElementConvention, Elements, InverseDistance, KeplerPolarIntegral, RadialMotion,
};
use hamilton_jacobi::nalgebra::{SVector, Vector2};
use hamilton_jacobi::systems::kepler;
use std::f64::consts::PI;

fn main() -> hamilton_jacobi::Result<()> {
    println!("| e | half period − π | apsidal angle − π | evaluations |");
    println!("|---|---|---|---|");
    for e in [0.0, 1e-12, 0.5, 0.9, 0.99, 1.0 - 1e-9] {
        let m = RadialMotion::kepler_elements(1.0, 1.0, e)?;
        let (t, th) = (m.half_period(), m.apsidal_angle());
        println!(
            "| {e} | {:+.1e} | {:+.1e} | {} |",
            t.value - PI,
            th.value - PI,
            t.evaluations + th.evaluations
        );
    }

    // The same quadratures for a generic potential: roots found numerically.
    let generic = RadialMotion::new(InverseDistance::new(1.0)?, -0.5, 0.75f64.sqrt(), 1.0, 10.0)?;
    println!(
        "\ngeneric root search, e = 0.5: apsides ({}, {}), half period − π = {:+.1e}",
        generic.periapsis(),
        generic.apoapsis(),
        generic.half_period().value - PI
    );

    // Motion: HJ (time law inverted) against Kepler's equation.
    println!("\n| e | t/T | ‖HJ − Kepler's equation‖ |");
    println!("|---|---|---|");
    for e in [0.0, 0.5, 0.9, 0.99] {
        let m = RadialMotion::kepler_elements(1.0, 1.0, e)?;
        let (rp, vp) = (1.0 - e, ((1.0 + e) / (1.0 - e)).sqrt());
        for frac in [0.1, 0.5, 0.85] {
            let t = frac * 2.0 * PI;
            let (r, _, th) = m.state_at(t)?;
            let (exact, _) =
                kepler::propagate(1.0, &Vector2::new(rp, 0.0), &Vector2::new(0.0, vp), t)?;
            let hj = Vector2::new(r * th.cos(), r * th.sin());
            println!("| {e} | {frac} | {:.1e} |", (hj - exact).norm());
        }
    }

    // Jacobi's theorem with the closed-form complete integral (outbound branch).
    let m = RadialMotion::kepler_elements(1.0, 1.0, 0.6)?;
    let el = Elements::new(
        KeplerPolarIntegral::new(1.0)?,
        ElementConvention::AlphaMomenta,
    );
    let (r, rdot, th) = m.state_at(0.4)?;
    let (alpha, beta) = el.elements(
        0.4,
        &SVector::from([r, th]),
        &SVector::from([rdot, m.angular_momentum()]),
    )?;
    println!(
        "\nelements (h, k) = ({:.15}, {:.15}), (β₁, β₂) = ({:.15}, {:.15})",
        alpha[0], alpha[1], beta[0], beta[1]
    );
    let (q, _) = el.state(2.0, &alpha, &beta)?;
    let (r2, _, th2) = m.state_at(2.0)?;
    println!(
        "state at t = 2 from the elements: r = {:.15}, θ = {:.15} (quadrature: {r2:.15}, {th2:.15})",
        q[0], q[1]
    );
    Ok(())
}

//! The outer Solar System (Hairer, Lubich & Wanner, GNI §I.2.4) by the N-body Wisdom–Holman map:
//! Jacobi coordinates without and with the order-17 symplectic corrector, and democratic
//! heliocentric coordinates, over 10⁵ days (about 270 years) with a step of 20 days; the relative
//! energy error at the end and the wall time of each run.
//!
//! Run: `cargo run --release --example outer_solar_system`.

use hamilton_jacobi::integrate::{PlanetaryWisdomHolman, Problem, WisdomHolman};
use hamilton_jacobi::systems::{outer_solar_system, PlanetaryCoordinates};
use hamilton_jacobi::{Hamiltonian, Result};

fn main() -> Result<()> {
    let (sys, q, p) = outer_solar_system();
    let h0 = sys.value(0.0, &q, &p)?;
    let (span, h) = (1e5, 20.0);
    let steps = (span / h) as usize;
    let problem = Problem::new(&sys, 0.0, q, p, span)?;
    let jacobi = PlanetaryCoordinates::Jacobi;
    let methods = [
        PlanetaryWisdomHolman::new(WisdomHolman::WH, jacobi)?,
        PlanetaryWisdomHolman::new(WisdomHolman::WH.with_corrector(17)?, jacobi)?,
        PlanetaryWisdomHolman::new(
            WisdomHolman::WH,
            PlanetaryCoordinates::DemocraticHeliocentric,
        )?,
    ];
    println!("outer Solar System, {span:e} days, h = {h} days ({steps} steps)");
    for m in methods {
        let r = m.propagate(&problem, steps)?;
        let e = sys.value(span, &r.last.q, &r.last.p)?;
        println!(
            "{:<70} |ΔE/E| = {:.2e}   {:>8.2?}  ({:.2} µs/step)",
            hamilton_jacobi::integrate::OneStep::<_, 15>::name(&m),
            ((e - h0) / h0).abs(),
            r.elapsed,
            r.elapsed.as_secs_f64() * 1e6 / steps as f64
        );
    }
    Ok(())
}

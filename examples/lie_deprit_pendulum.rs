//! Lie–Deprit perturbation theory in given action–angle variables: the pendulum written once in
//! the harmonic oscillator's variables `q = μ√(2J) sin θ`, `p = μ√(2J) cos θ`, Deprit's triangle
//! to order μ¹⁸, and the coefficients of `K(J) = J − J²/16 − J³/256 − …` against the exact
//! rationals (the reversion of the exact action, DLMF 19.5); then the driven oscillator's small
//! divisor at resonance.
//!
//! Run with `cargo run --release --example lie_deprit_pendulum`.

use hamilton_jacobi::nalgebra::{Vector1, Vector2};
use hamilton_jacobi::perturbation::lie_deprit::{
    lie_deprit, AmplitudePendulum, DrivenOscillator, LieDepritOptions,
};
use hamilton_jacobi::{Error, Result};
use std::time::Instant;

/// `h_m` of `K(J) = Σ h_m J^m`, `m = 1 … 10`, as exact rationals.
const EXACT: [(f64, f64); 10] = [
    (1.0, 1.0),
    (-1.0, 16.0),
    (-1.0, 256.0),
    (-5.0, 8192.0),
    (-33.0, 262_144.0),
    (-63.0, 2_097_152.0),
    (-527.0, 67_108_864.0),
    (-9387.0, 4_294_967_296.0),
    (-175_045.0, 274_877_906_944.0),
    (-422_565.0, 2_199_023_255_552.0),
];

fn main() -> Result<()> {
    let order = 18;
    let clock = Instant::now();
    let ld = lie_deprit(
        &AmplitudePendulum,
        &Vector1::new(1.0),
        &LieDepritOptions {
            action_degree: 0,
            ..LieDepritOptions::new(order, 2 * order + 2)
        },
    )?;
    println!(
        "Deprit's triangle to μ^{order} in {:.2} s; Fourier error {:.1e}",
        clock.elapsed().as_secs_f64(),
        ld.fourier_error()
    );
    println!("| J^m | Lie–Deprit | exact | error (ulp) |");
    println!("|---|---|---|---|");
    for (m, &(num, den)) in EXACT.iter().enumerate() {
        let got = ld.energy_coefficient(2 * m)?;
        let want = num / den;
        let ulp = (got - want).abs() / (want.abs() * f64::EPSILON);
        println!("| J^{} | {got:.17e} | {num}/{den} | {ulp:.1} |", m + 1);
    }
    for omega in [0.7, 1.0] {
        match lie_deprit(
            &DrivenOscillator {
                omega: 1.0,
                drive: omega,
            },
            &Vector2::new(1.0, 1.0),
            &LieDepritOptions::new(3, 8),
        ) {
            Ok(d) => println!(
                "driven oscillator, Ω = {omega}: ω′ = {:?} at ε = 0.1",
                d.frequencies(&Vector2::new(1.0, 1.0), 0.1)?.as_slice()
            ),
            Err(e @ Error::SmallDivisor { .. }) => {
                println!("driven oscillator, Ω = {omega}: {e}")
            }
            Err(e) => return Err(e),
        }
    }
    Ok(())
}

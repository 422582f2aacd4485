//! The whole `hj` command line for a system of one's own: the Duffing oscillator
//! `H = p²/2 + αq²/2 + βq⁴/4`, written once with `hamiltonian!`, registered in the catalogue
//! under `duffing` with its keys `alpha`, `beta`, `amplitude`, and run from scene files like
//! the built-in systems (Störmer–Verlet, the compositions, Gauss–Legendre, DOP853, …):
//!
//! ```text
//! cargo run --release --example cli_user_system -- list
//! cargo run --release --example cli_user_system -- new duffing-scene   # then set [system] name = "duffing"
//! cargo run --release --example cli_user_system -- run duffing.toml
//! ```
//!
//! with `duffing.toml`:
//!
//! ```toml
//! [system]
//! name = "duffing"
//! beta = 0.5
//! amplitude = 1.2
//!
//! [span]
//! time = 50
//!
//! [[method]]
//! kind = "verlet-kdk"
//! steps = [1000, 4000]
//!
//! [[method]]
//! kind = "dop853"
//! rtol = [1e-8, 1e-12]
//!
//! [output]
//! energy_error = [{ method = "verlet-kdk", steps = 1000 }]
//! ```

use hamilton_jacobi::hamiltonian;
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::scene::case::separable_stepper;
use hamilton_jacobi::scene::{Catalogue, HamiltonianCase};
use std::process::ExitCode;

hamiltonian!(
    /// The Duffing oscillator `H = p²/2 + αq²/2 + βq⁴/4`.
    Duffing<1> { alpha: f64, beta: f64 } |s, _t, q, p|
        kinetic = p[0] * p[0] * 0.5,
        potential = q[0] * q[0] * (s.alpha * 0.5) + q[0].powi(4) * (s.beta * 0.25)
);

/// The built-in catalogue with the Duffing oscillator added as `duffing`.
pub fn catalogue() -> Catalogue {
    let mut catalogue = Catalogue::builtin();
    catalogue.register(
        "duffing",
        "Duffing oscillator H = p²/2 + αq²/2 + βq⁴/4, released from rest",
        Box::new(|s| {
            let (alpha, beta) = (s.positive_or("alpha", 1.0)?, s.or("beta", 1.0)?);
            let amplitude = s.or("amplitude", 1.0)?;
            let system = Duffing { alpha, beta };
            let description =
                format!("Duffing oscillator, α = {alpha}, β = {beta}, amplitude {amplitude}");
            let case = HamiltonianCase::new(
                system,
                SVector::from([amplitude]),
                SVector::from([0.0]),
                description,
            )
            .map_err(|e| s.library(e))?
            .with_stepper(separable_stepper::<Duffing, 1>());
            Ok(Box::new(case))
        }),
    );
    catalogue
}

#[allow(dead_code)]
fn main() -> ExitCode {
    hamilton_jacobi::cli::cli_main(catalogue())
}

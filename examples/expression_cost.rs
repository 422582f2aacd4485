//! The vector field of a system by expression against the Rust-written one, `n` calls of one
//! variant, for instruction counts under callgrind (load-independent, unlike wall time):
//!
//! ```text
//! cargo build --release --example expression_cost
//! valgrind --tool=callgrind target/release/examples/expression_cost hh-expression 100000
//! ```
//!
//! Variants: `hh-rust`, `hh-expression`, `hh-split` (Hénon–Heiles), `j2-rust`, `j2-expression`,
//! `j2-split` (Kepler + J₂ in Cartesian form; `-split` the separable form, drift and kick), and
//! `none` (the loop and set-up alone, to subtract). The systems and
//! states are those of `benches/expression.rs`; the instructions per call are
//! `(total(variant) − total(none))/n`.

use hamilton_jacobi::expression::ExpressionHamiltonian;
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::forces::{PerturbedTwoBody, J2};
use hamilton_jacobi::systems::HenonHeiles;
use hamilton_jacobi::Hamiltonian;
use std::hint::black_box;

fn calls<const N: usize>(
    h: &impl Hamiltonian<N>,
    q: SVector<f64, N>,
    p: SVector<f64, N>,
    n: usize,
) -> f64 {
    let mut sum = 0.0;
    for _ in 0..n {
        let (dq, dp) = h.vector_field_unchecked(0.0, black_box(&q), black_box(&p));
        sum += dq[0] + dp[0];
    }
    sum
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let variant = args.get(1).map_or("hh-expression", String::as_str);
    let n: usize = args.get(2).map_or(Ok(100_000), |s| s.parse())?;
    let hh = ExpressionHamiltonian::<2>::new(
        "(p_x^2 + p_y^2)/2 + (x^2 + y^2)/2 + x^2*y - y^3/3",
        &["x", "y"],
        None,
        &[],
    )?;
    let j2 = ExpressionHamiltonian::<3>::new(
        "(p_x^2 + p_y^2 + p_z^2)/2 - mu/sqrt(x^2 + y^2 + z^2) \
         + mu*J2*R^2/2 * (3*z^2/(x^2 + y^2 + z^2) - 1)/sqrt(x^2 + y^2 + z^2)^3",
        &["x", "y", "z"],
        None,
        &[("mu", 1.0), ("J2", 1.08e-3), ("R", 0.9)],
    )?;
    let j2_rust = PerturbedTwoBody::conservative(1.0, J2::new(1.0, 1.08e-3, 0.9)?)?;
    let (q2, p2) = (SVector::from([0.1, -0.2]), SVector::from([0.3, 0.25]));
    let (q3, p3) = (
        SVector::from([0.7, 0.3, -0.2]),
        SVector::from([-0.2, 1.1, 0.1]),
    );
    let sum = match variant {
        "hh-rust" => calls(&HenonHeiles, q2, p2, n),
        "hh-expression" => calls(&hh, q2, p2, n),
        "hh-split" => calls(&hh.separable().ok_or("HH not separable")?, q2, p2, n),
        "j2-rust" => calls(&j2_rust, q3, p3, n),
        "j2-expression" => calls(&j2, q3, p3, n),
        "j2-split" => calls(&j2.separable().ok_or("J2 not separable")?, q3, p3, n),
        "none" => 0.0,
        other => return Err(format!("unknown variant {other}").into()),
    };
    println!(
        "{variant}: {n} calls, checksum {sum:e}; the record of (H, ∇H) has {} (HH) and {} (J2) instructions",
        hh.gradient_record().instructions(),
        j2.gradient_record().instructions()
    );
    Ok(())
}

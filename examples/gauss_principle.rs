//! Gauss's principle of least constraint (SPEC M43): the actual accelerations minimise
//! `Z = ½ (q̈ − a⁻¹f)ᵀ a (q̈ − a⁻¹f)` over the accelerations the constraints admit.
//!
//! 1. Appell–Hamel's 45° constraint `ẋ₃² = ẋ₁² + ẋ₂²` under the force (0, 0, K), K = −9.81, at
//!    ẋ = (0.6, 0.8, 1.0) (SPEC T21): Z minimised with argmin against the multiplier form
//!    (λ = K/(4ẋ₃) in the crate sign) and SPEC's ẍ = (−2.943, −3.924, −4.905);
//! 2. the Chaplygin sleigh (T16) at a state with forces: Gauss's minimum against the multiplier
//!    form and the reduced equations `m v̇ − m s ϑ̇² = Z`, `I_B ϑ̈ + m s v ϑ̇ = M`;
//! 3. the acceleration constraint `ẍ₃ = ẍ₁ẍ₂` (T22): all stationary points of Z, three for
//!    |K| > 1 and one for |K| < 1, and Hamel's minimiser.
//!
//! Run with `cargo run --release --example gauss_principle`.

use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::nonholonomic::{gauss_accelerations, gauss_stationary_points, Constrained};
use hamilton_jacobi::systems::{ChaplyginSleigh, ConeConstraint, SecondClassConstraint};
use hamilton_jacobi::Result;

fn main() -> Result<()> {
    // 1. The cone constraint.
    let k = -9.81;
    let cone = ConeConstraint::new(k)?;
    let sys = Constrained::new(cone, cone);
    let (q, v) = (SVector::zeros(), SVector::from([0.6, 0.8, 1.0]));
    let gauss = gauss_accelerations(&sys, 0.0, &q, &v)?;
    let mult = sys.multiplier_accelerations(0.0, &q, &v)?;
    let spec = SVector::from([-2.943, -3.924, -4.905]);
    println!("T21 cone constraint, K = {k}, ẋ = (0.6, 0.8, 1.0):");
    println!(
        "  Gauss (argmin)  ẍ = ({:.12}, {:.12}, {:.12}), Z = {:.12}",
        gauss.qddot[0], gauss.qddot[1], gauss.qddot[2], gauss.z
    );
    println!(
        "  multipliers     ẍ = ({:.12}, {:.12}, {:.12}), λ = {:.12} (K/(4ẋ₃) = {:.12})",
        mult.qddot[0],
        mult.qddot[1],
        mult.qddot[2],
        mult.lambda[0],
        k / 4.0
    );
    println!(
        "  |Gauss − SPEC| = {:.1e}, |multipliers − SPEC| = {:.1e}",
        (gauss.qddot - spec).amax(),
        (mult.qddot - spec).amax()
    );

    // 2. The sleigh with a push and a torque.
    let (m, s, i_b, push, torque) = (2.0, 0.5, 1.0, 0.7, -0.2);
    let sleigh = ChaplyginSleigh::new(m, s, i_b)?.with_forces(push, torque)?;
    let sys = Constrained::new(sleigh, sleigh);
    let (th, fwd, rate): (f64, f64, f64) = (0.4, 0.9, -0.6);
    let q = SVector::from([0.3, -0.1, th]);
    let v = SVector::from([fwd * th.cos(), fwd * th.sin(), rate]);
    let gauss = gauss_accelerations(&sys, 0.0, &q, &v)?;
    let mult = sys.multiplier_accelerations(0.0, &q, &v)?;
    // v̇ = ẍ cos ϑ + ÿ sin ϑ + ϑ̇ (ẏ cos ϑ − ẋ sin ϑ), the last term zero on the constraint.
    let vdot = gauss.qddot[0] * th.cos() + gauss.qddot[1] * th.sin();
    println!("\nT16 sleigh with Z = {push}, M = {torque} at v = {fwd}, ϑ̇ = {rate}:");
    println!(
        "  Gauss: v̇ = {vdot:.14}, ϑ̈ = {:.14}; reduced equations: v̇ = {:.14}, ϑ̈ = {:.14}",
        gauss.qddot[2],
        (push + m * s * rate * rate) / m,
        (torque - m * s * fwd * rate) / i_b
    );
    println!(
        "  |Gauss − multipliers| = {:.1e}",
        (gauss.qddot - mult.qddot).amax()
    );

    // 3. The acceleration constraint.
    println!("\nT22 acceleration constraint ẍ₃ = ẍ₁ẍ₂, force (0, 0, K):");
    let (q, v) = (SVector::zeros(), SVector::from([0.3, -0.2, 0.1]));
    for k in [3.0, -3.0, 1.5, 0.5] {
        let c = SecondClassConstraint::new(k)?;
        let st = gauss_stationary_points(&c, &c, 0.0, &q, &v)?;
        println!("  K = {k:+}: {} stationary points", st.points.len());
        for (i, p) in st.points.iter().enumerate() {
            println!(
                "    ẍ = ({:+.12}, {:+.12}, {:+.12}), Σ(ẍ − X)² = {:.12}{}",
                p.qddot[0],
                p.qddot[1],
                p.qddot[2],
                2.0 * p.z,
                if i == st.minimizer {
                    "  (minimiser)"
                } else {
                    ""
                }
            );
        }
    }
    Ok(())
}

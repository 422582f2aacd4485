//! Variation of constants for a projectile with linear drag [Ardema 18.1].
//!
//! Unit mass, unperturbed motion `x = γ₁t + γ₃`, `y = −½gt² + γ₂t + γ₄`, `p_x = γ₁`,
//! `p_y = −gt + γ₂`; perturbation `R = −k p` in the momentum equation. The element equations
//! `γ̇₁ = R_x`, `γ̇₂ = R_y`, `γ̇₃ = −tR_x`, `γ̇₄ = −tR_y` are obtained both from the general form
//! `γ̇ = (∂φ/∂γ)⁻¹ g` and from Lagrange's bracket form `Σ_s [γ_j, γ_s] γ̇_s = Σ_r R_r ∂F_r/∂γ_j`
//! [Ardema 18.1], integrated with RK4 + Richardson extrapolation, and compared with the exact drag solution
//! `x = (u₀/k)(1 − e^{−kt})`, `y = ((v₀ + g/k)/k)(1 − e^{−kt}) − gt/k`.
//!
//! Run: `cargo run --release --example projectile_drag`

use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::perturbation::ode::rk4_richardson;
use hamilton_jacobi::perturbation::variation::{
    bracket_time_defect, lagrange_brackets, GeneralSolution, InMomentumEquation,
    LagrangeBracketForm, MomentumForce, VariationOfConstants,
};
use hamilton_jacobi::DualNum;

const G: f64 = 9.81;
const K: f64 = 0.3;

/// The unperturbed projectile as a general solution `(q, p) = φ(γ, t)`.
struct Projectile;
impl GeneralSolution<2> for Projectile {
    fn state<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        a: &SVector<D, 2>,
        b: &SVector<D, 2>,
    ) -> (SVector<D, 2>, SVector<D, 2>) {
        (
            SVector::from([a[0] * t + b[0], t * t * (-0.5 * G) + a[1] * t + b[1]]),
            SVector::from([a[0], t * (-G) + a[1]]),
        )
    }
}

/// Linear drag `R = −k p`.
struct Drag;
impl MomentumForce<2> for Drag {
    fn force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 2>,
        p: &SVector<D, 2>,
    ) -> SVector<D, 2> {
        p * D::from(-K)
    }
}

fn main() -> hamilton_jacobi::Result<()> {
    let (u0, v0) = (3.0, 4.0);
    let (a0, b0) = (SVector::from([u0, v0]), SVector::from([0.0, 0.0]));

    let l = lagrange_brackets(&Projectile, 1.7, &a0, &b0)?.to_dmatrix();
    let times: Vec<f64> = (0..=20).map(|i| 0.25 * i as f64).collect();
    let defect = bracket_time_defect(&Projectile, &times, &a0, &b0)?;
    println!("Lagrange-bracket matrix [γ_j, γ_s] at t = 1.7:{l}");
    println!(
        "time dependence over t ∈ [0, 5]: max |L(t) − L(0)| = {:e}, max |∂L/∂t| = {:e}\n",
        defect.variation, defect.rate
    );

    let general = VariationOfConstants {
        solution: Projectile,
        perturbation: InMomentumEquation(Drag),
    };
    let bracket = LagrangeBracketForm {
        solution: Projectile,
        force: Drag,
    };
    println!("| t | γ₁ | γ₂ | γ₃ | γ₄ | x (elements) | y (elements) | x − exact | y − exact | general − bracket | Richardson est. |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for t in [0.5, 1.0, 1.5, 2.0, 3.0, 5.0] {
        let steps = (500.0 * t) as usize;
        let run_general = rk4_richardson(&general, 0.0, &a0, &b0, t, steps)?;
        let run_bracket = rk4_richardson(&bracket, 0.0, &a0, &b0, t, steps)?;
        let (q, _) = Projectile.state(t, &run_general.y.0, &run_general.y.1);
        let e = (-K * t).exp();
        let x = u0 / K * (1.0 - e);
        let y = (v0 + G / K) / K * (1.0 - e) - G * t / K;
        let diff = (run_general.y.0 - run_bracket.y.0)
            .amax()
            .max((run_general.y.1 - run_bracket.y.1).amax());
        println!(
            "| {t} | {:.12} | {:.12} | {:.12} | {:.12} | {:.14} | {:.14} | {:.1e} | {:.1e} | {:.1e} | {:.1e} |",
            run_general.y.0[0],
            run_general.y.0[1],
            run_general.y.1[0],
            run_general.y.1[1],
            q[0],
            q[1],
            q[0] - x,
            q[1] - y,
            diff,
            run_general.max_error()
        );
    }
    println!("\nReference at t = 2: (x, y) = (4.51188363905974, −10.2046234821692).");
    Ok(())
}

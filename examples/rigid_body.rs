//! The free rigid body with principal moments I = (1, 2, 3):
//!
//! 1. the intermediate-axis instability (SPEC T30): the growth rate `Ω√((I₂−I₁)(I₃−I₂)/(I₁I₃))`
//!    from the AD linearisation of Euler's equations, and `ln|ω₁|` of the motion from
//!    `ω(0) = (10⁻⁶, 1, 0)` against `λ tanh λt`;
//! 2. the Lie–Poisson splitting (Strang, order 2, and its Yoshida composition, order 4) against
//!    the Euler–Poinsot exact flow over many periods, with the Casimir `|Π|²` and the energy.
//!
//! Run with `cargo run --release --example rigid_body`.

use hamilton_jacobi::integrate::coefficients::YOSHIDA3;
use hamilton_jacobi::integrate::LiePoisson;
use hamilton_jacobi::nalgebra::Vector3;
use hamilton_jacobi::systems::rigid_body::{
    euler_jacobian, intermediate_axis_growth_rate, EulerPoinsot, FreeRigidBody, InertiaTensor,
};

fn main() -> hamilton_jacobi::Result<()> {
    let moments = Vector3::new(1.0, 2.0, 3.0);
    let body = FreeRigidBody::new(moments)?;
    let inertia = InertiaTensor::principal(moments)?;

    // 1. Intermediate axis.
    let lambda = intermediate_axis_growth_rate(&moments, 1.0)?;
    let jac = euler_jacobian(&inertia, &Vector3::zeros(), &Vector3::new(0.0, 1.0, 0.0))?;
    let eig = jac.complex_eigenvalues();
    println!("intermediate axis: predicted growth rate λ = {lambda:.9}");
    println!(
        "  eigenvalues of the AD Jacobian: {:.9}, {:.9}, {:.9}",
        eig[0].re, eig[1].re, eig[2].re
    );
    let pi0 = Vector3::new(1e-6, 1.0, 0.0).component_mul(&moments);
    let flow = EulerPoinsot::new(&body, &pi0)?;
    println!("  t      ω₁(t) (Euler–Poinsot)   1e-6 cosh λt   d ln|ω₁|/dt   λ tanh λt");
    for t in [0.0, 2.0, 4.0, 6.0, 8.0] {
        let w = flow.momentum_at(t)?.component_div(&moments);
        let wd = body
            .euler_field(&w.component_mul(&moments))?
            .component_div(&moments);
        println!(
            "  {t:4.1}   {:+.12e}   {:.12e}   {:.6}      {:.6}",
            w[0],
            1e-6 * (lambda * t).cosh(),
            wd[0] / w[0],
            lambda * (lambda * t).tanh()
        );
    }

    // 2. Lie–Poisson against Euler–Poinsot.
    let pi0 = Vector3::new(0.4, 0.3, 1.5);
    let exact = EulerPoinsot::new(&body, &pi0)?;
    let period = exact.period()?;
    let (c0, e0) = (pi0.norm_squared(), body.energy_generic(&pi0));
    println!(
        "\nLie–Poisson, Π(0) = {:?}, period 4K/λ = {period:.12}",
        pi0.as_slice()
    );
    println!("  method    steps/period  periods   max|ΔΠ| at end   max rel. energy error   max rel. |Π|² drift");
    for (name, method, per) in [
        ("Strang", LiePoisson::strang(&body), 200usize),
        ("Strang", LiePoisson::strang(&body), 400),
        ("Yoshida", LiePoisson::composition(&body, &YOSHIDA3)?, 50),
        ("Yoshida", LiePoisson::composition(&body, &YOSHIDA3)?, 100),
    ] {
        let periods = 1000.0;
        let steps = (periods * per as f64) as usize;
        let t = periods * period;
        let (mut de, mut dc) = (0.0f64, 0.0f64);
        let x = method.run(&pi0, t / steps as f64, steps, |_, x| {
            de = de.max((body.energy_generic(x) - e0).abs() / e0);
            dc = dc.max((x.norm_squared() - c0).abs() / c0);
        })?;
        let err = (x - exact.momentum_at(t)?).amax();
        println!(
            "  {name:8}  {per:12}  {periods:7}   {err:.3e}        {de:.3e}               {dc:.3e}"
        );
    }
    Ok(())
}

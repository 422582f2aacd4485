//! Hamilton's principal function by shooting against the closed forms for the projectile and the
//! oscillator [Ardema 17.1], and the approach to the oscillator's focal point ωτ = π.
//!
//! Run with `cargo run --release --example hj_principal`.

use hamilton_jacobi::ad::GradDual64;
use hamilton_jacobi::hamilton_jacobi::principal::{
    principal_function, principal_function_generic, PrincipalOptions,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::{HarmonicOscillator, Projectile};
use hamilton_jacobi::Result;
use std::f64::consts::PI;

/// Uniform gravity: S = |q¹ − q⁰|²/(2τ) − ½ g (y⁰ + y¹) τ − g² τ³/24.
fn projectile_s(g: f64, q0: [f64; 2], q1: [f64; 2], tau: f64) -> f64 {
    let (dx, dy) = (q1[0] - q0[0], q1[1] - q0[1]);
    (dx * dx + dy * dy) / (2.0 * tau) - 0.5 * g * (q0[1] + q1[1]) * tau - g * g * tau.powi(3) / 24.0
}

/// Harmonic oscillator: (S, p⁰, p¹) of the oscillator with unit mass.
fn oscillator_s(w: f64, x0: f64, x1: f64, tau: f64) -> (f64, f64, f64) {
    let (s, c) = (w * tau).sin_cos();
    (
        w * ((x0 * x0 + x1 * x1) * c - 2.0 * x0 * x1) / (2.0 * s),
        w * (x1 - x0 * c) / s,
        w * (x1 * c - x0) / s,
    )
}

fn row(name: &str, exact: f64, shot: f64) {
    println!(
        "| {name} | {exact:.14} | {shot:.14} | {:.1e} |",
        (shot - exact).abs()
    );
}

fn main() -> Result<()> {
    let opts = PrincipalOptions::<2>::default();
    let opts1 = PrincipalOptions::<1>::default();

    // Uniform gravity, with the six derivatives of S from one dual evaluation (slots q⁰, q¹, t₀, t₁).
    let g = 9.81;
    let proj = Projectile::new(1.0, g)?;
    let (q0, q1, t0, t1) = ([0.0, 0.0], [10.0, 5.0], 0.0, 2.0);
    let var = GradDual64::<6>::variable;
    let (v, r) = principal_function_generic(
        &proj,
        &SVector::from([var(q0[0], 0), var(q0[1], 1)]),
        &SVector::from([var(q1[0], 2), var(q1[1], 3)]),
        var(t0, 4),
        var(t1, 5),
        &opts,
    )?;
    let ds = v.s.eps();
    let h = 0.5 * (25.0 + 12.31 * 12.31);
    println!("Projectile (g = 9.81, (0, 0) → (10, 5), τ = 2) [Ardema 17.1]\n");
    println!("| quantity | closed form | shooting | difference |");
    println!("|---|---|---|---|");
    row("S", projectile_s(g, q0, q1, t1 - t0), r.s);
    row("p⁰_x = u₀", 5.0, r.p0[0]);
    row("p⁰_y = v₀", 12.31, r.p0[1]);
    row("p¹_y", -7.31, r.p1[1]);
    row("∂S/∂x⁰", -5.0, ds[0]);
    row("∂S/∂y⁰", -12.31, ds[1]);
    row("∂S/∂x¹", 5.0, ds[2]);
    row("∂S/∂y¹", -7.31, ds[3]);
    row("∂S/∂t₀ = H", h, ds[4]);
    row("∂S/∂t₁ = −H", -h, ds[5]);
    println!(
        "\nM = {} steps, {} Newton iterations, {} evaluations of ∇H\n",
        r.steps, r.iterations, r.work.gradients
    );

    // Harmonic oscillator.
    let osc = HarmonicOscillator::new(1.0, 2.0)?;
    let r = principal_function(
        &osc,
        &SVector::from([1.0]),
        &SVector::from([0.5]),
        0.0,
        1.0,
        &opts1,
    )?;
    let (s, p0, p1) = oscillator_s(2.0, 1.0, 0.5, 1.0);
    println!("Oscillator (ω = 2, x⁰ = 1, x¹ = 0.5, τ = 1) [Ardema 17.1]\n");
    println!("| quantity | closed form | shooting | difference |");
    println!("|---|---|---|---|");
    row("S", s, r.s);
    row("p⁰", p0, r.p0[0]);
    row("p¹", p1, r.p1[0]);
    println!(
        "\nestimated errors: S {:.1e}, p⁰ {:.1e}, p¹ {:.1e}; M = {} steps\n",
        r.error.s, r.error.p0[0], r.error.p1[0], r.steps
    );

    // The unit oscillator approaching its focal point τ = π.
    let unit = HarmonicOscillator::new(1.0, 1.0)?;
    println!("Focal point (ω = 1, x⁰ = 1, x¹ = 0.5, τ → π)\n");
    println!("| π − τ | S closed form | S shooting | relative error | estimate | rcond | M |");
    println!("|---|---|---|---|---|---|---|");
    for k in 1..=9 {
        let tau = PI - 10f64.powi(-k);
        let (s, _, _) = oscillator_s(1.0, 1.0, 0.5, tau);
        match principal_function(
            &unit,
            &SVector::from([1.0]),
            &SVector::from([0.5]),
            0.0,
            tau,
            &opts1,
        ) {
            Ok(r) => println!(
                "| 1e-{k} | {s:.10e} | {:.10e} | {:.1e} | {:.1e} | {:.1e} | {} |",
                r.s,
                ((r.s - s) / s).abs(),
                r.error.s / s.abs(),
                r.rcond,
                r.steps
            ),
            Err(e) => println!("| 1e-{k} | {s:.10e} | refused: {e} | | | | |"),
        }
    }
    // Past the default accuracy limit (max_relative_error = 1e−6) the caller may accept less.
    let loose = PrincipalOptions {
        max_relative_error: 1e-3,
        ..opts1
    };
    println!("\nwith max_relative_error = 1e−3:\n");
    for k in [8, 9, 10] {
        let tau = PI - 10f64.powi(-k);
        let (s, _, _) = oscillator_s(1.0, 1.0, 0.5, tau);
        match principal_function(
            &unit,
            &SVector::from([1.0]),
            &SVector::from([0.5]),
            0.0,
            tau,
            &loose,
        ) {
            Ok(r) => println!(
                "| 1e-{k} | {s:.10e} | {:.10e} | {:.1e} | {:.1e} | {:.1e} | {} |",
                r.s,
                ((r.s - s) / s).abs(),
                r.error.s / s.abs(),
                r.rcond,
                r.steps
            ),
            Err(e) => println!("| 1e-{k} | {s:.10e} | refused: {e} | | | | |"),
        }
    }
    for (name, x1) in [("x¹ = 0.5", 0.5), ("x¹ = −x⁰", -1.0)] {
        match principal_function(
            &unit,
            &SVector::from([1.0]),
            &SVector::from([x1]),
            0.0,
            PI,
            &opts1,
        ) {
            Ok(r) => println!("\nτ = π, {name}: unexpected S = {}", r.s),
            Err(e) => println!("\nτ = π, {name}: {e}"),
        }
    }
    Ok(())
}

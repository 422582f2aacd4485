//! The heavy symmetric top by Hamilton–Jacobi quadratures [Ardema 11.2, 17.5]: reference values
//! (quadrature against the elliptic closed form and against integration of Hamilton's equations),
//! fast tops, and the sleeping top around its critical spin.
//!
//! Run with `cargo run --release --example hj_top`.

use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::top::motion::{self, Nutation, TopCubic};
use hamilton_jacobi::systems::HeavyTop;
use hamilton_jacobi::{Hamiltonian, Result};

type V3 = SVector<f64, 3>;

/// Classical RK4 on Hamilton's equations (AD vector field), `n` steps over `t`.
fn rk4(top: &HeavyTop, q: V3, p: V3, t: f64, n: usize, mut observe: impl FnMut(&V3)) -> (V3, V3) {
    let (mut q, mut p, h) = (q, p, t / n as f64);
    let f = |q: &V3, p: &V3| top.vector_field_unchecked(0.0, q, p);
    for _ in 0..n {
        let (a1, b1) = f(&q, &p);
        let (a2, b2) = f(&(q + a1 * (0.5 * h)), &(p + b1 * (0.5 * h)));
        let (a3, b3) = f(&(q + a2 * (0.5 * h)), &(p + b2 * (0.5 * h)));
        let (a4, b4) = f(&(q + a3 * h), &(p + b3 * h));
        q += (a1 + a2 * 2.0 + a3 * 2.0 + a4) * (h / 6.0);
        p += (b1 + b2 * 2.0 + b3 * 2.0 + b4) * (h / 6.0);
        observe(&q);
    }
    (q, p)
}

/// `4K(m)/√(β(u₃ − u₁))`, `m = (u₂ − u₁)/(u₃ − u₁)`.
fn elliptic_period(c: &TopCubic) -> f64 {
    let [x1, x2, x3] = c.root_offsets();
    let k = ellip::ellipk((x2 - x1) / (x3 - x1)).expect("m < 1");
    4.0 * k / (c.beta() * (x3 - x1)).sqrt()
}

fn main() -> Result<()> {
    let top = HeavyTop::new(1.0, 0.5, 1.0)?;
    let deg = 180.0 / std::f64::consts::PI;

    // Release from rest at θ₂ = 60° with ω_z = 5.
    let theta2 = 60f64.to_radians();
    let (q0, p0) = (
        SVector::from([0.0, theta2, 0.0]),
        top.momenta_from_spin(theta2, 0.0, 0.0, 5.0)?,
    );
    let nut = Nutation::from_state(&top, &q0, &p0)?;
    let c = nut.cubic();
    let [u1, u2, _] = c.roots();
    let period = nut.period()?;
    let (dphi, dpsi) = (nut.precession_per_period()?, nut.spin_per_period()?);
    let (q, p) = rk4(&top, q0, p0, period.value, 20_000, |_| {});
    println!("Release from rest at 60°, ω_z = 5 (I = 1, J = 0.5, mgℓ = 1)\n");
    println!("| quantity | reference | quadrature / cubic | elliptic | RK4 (20 000 steps) |");
    println!("|---|---|---|---|---|");
    println!(
        "| u₁ | 0.191767987533668 | {u1:.15} | — | {:.13} (θ at t = T/2) |",
        rk4(&top, q0, p0, 0.5 * period.value, 10_000, |_| {}).0[1].cos()
    );
    println!(
        "| u₁ [11.24, factored form] | 0.191767987533668 | {:.15} | — | — |",
        motion::release_from_rest(&top, u2, 5.0)?
    );
    let [th_min, th_max] = c.theta_range();
    println!(
        "| θ range (deg) | 60 – 78.944 | {:.3} – {:.3} | — | — |",
        th_min * deg,
        th_max * deg
    );
    println!(
        "| nutation period | 2.76392864942787 | {:.14} (±{:.0e}, {} evals) | {:.14} | θ − θ₀ = {:.1e}, p_θ = {:.1e} |",
        period.value,
        period.error,
        period.evaluations,
        elliptic_period(c),
        q[1] - q0[1],
        p[1]
    );
    println!(
        "| Δφ per period | — | {:.14} | — | {:.14} |",
        dphi.value, q[0]
    );
    println!(
        "| Δψ per period | — | {:.14} | — | {:.14} |",
        dpsi.value, q[2]
    );
    println!(
        "| max φ̇ (at u₁) | 0.8 | {:.15} | — | — |",
        c.precession_rate(u1)?
    );
    println!(
        "| fast-top width [11.25] | 0.24 | {:.4} (exact u₂ − u₁ = {:.4}) | — | — |",
        motion::fast_top_width(&top, u2, 5.0)?,
        c.nutation_width()
    );

    // Fast tops.
    println!("\nFast tops released from rest at 60°\n");
    println!("| ω_z | γ | u₂ − u₁ (cubic) | [11.25] | period quadrature | period elliptic | Δφ per period |");
    println!("|---|---|---|---|---|---|---|");
    for omega in [5.0, 50.0, 500.0, 2e4] {
        let p = top.momenta_from_spin(theta2, 0.0, 0.0, omega)?;
        let nut = Nutation::from_state(&top, &q0, &p)?;
        println!(
            "| {omega} | {} | {:.12e} | {:.6e} | {:.14e} | {:.14e} | {:.14e} |",
            top.gamma(omega)?,
            nut.cubic().nutation_width(),
            motion::fast_top_width(&top, u2, omega)?,
            nut.period()?.value,
            elliptic_period(nut.cubic()),
            nut.precession_per_period()?.value
        );
    }
    // A fast top: the textbook form of [Ardema eq. 11.24] at γ = 1e4 (ω_z = 2e4).
    let cc = 1e8 / (2.0 * top.beta());
    println!(
        "\nγ = 1e4: u₁ naive c − √(1 − 2cu₂ + c²) = {:.11}, stable = {:.11}",
        cc - (1.0 - 2.0 * cc * u2 + cc * cc).sqrt(),
        motion::release_from_rest(&top, u2, 2e4)?
    );

    // Steady precession at 30°.
    let theta0 = 30f64.to_radians();
    let sp = top.steady_precession(theta0, 5.0)?;
    let fast = sp.fast.expect("cos θ₀ ≠ 0");
    println!("\nSteady precession at 30°, ω_z = 5");
    println!(
        "fast φ̇ = {fast:.14} (ref. 2.40703162555988), slow φ̇ = {:.15} (ref. 0.479719720388246), \
         minimum spin {:.14} (ref. 3.72241943640840)",
        sp.slow,
        top.min_spin_for_steady_precession(theta0)?
    );
    let (qs, ps) = (
        SVector::from([0.0, theta0, 0.0]),
        top.momenta_from_spin(theta0, 0.0, fast, 5.0)?,
    );
    let mut dev: f64 = 0.0;
    rk4(&top, qs, ps, 10.0, 10_000, |q| {
        dev = dev.max((q[1] - theta0).abs())
    });
    let steady = Nutation::from_state(&top, &qs, &ps)?;
    println!(
        "RK4 over 10 s: max |θ − θ₀| = {dev:.1e}; small-oscillation period {:.12}, Δφ/T = {:.14}",
        steady.period()?.value,
        steady.precession_per_period()?.value / steady.period()?.value
    );

    // The sleeping top around the critical spin.
    println!(
        "\nSleeping top from θ = 1e−3 rad, θ̇ = φ̇ = 0; critical spin ω_c = {}",
        top.critical_spin()?
    );
    println!("| ω_z | θ_max quadrature (deg) | θ_max RK4 60 s (deg) | nutation period |");
    println!("|---|---|---|---|");
    for omega in [3.6, 3.9, 4.0, 4.1, 4.4] {
        let (q, p) = (
            SVector::from([0.0, 1e-3, 0.0]),
            top.momenta_from_spin(1e-3, 0.0, 0.0, omega)?,
        );
        let nut = Nutation::from_state(&top, &q, &p)?;
        let mut th: f64 = 0.0;
        rk4(&top, q, p, 60.0, 60_000, |q| th = th.max(q[1]));
        println!(
            "| {omega} | {:.6} | {:.6} | {:.6} |",
            nut.cubic().theta_range()[1] * deg,
            th * deg,
            nut.period()?.value
        );
    }
    for omega in [3.6, 4.0, 4.4] {
        // The vertical top itself, given by its constants h = p₂²/2J + mgℓ, p₁ = p₂ = Jω_z.
        let p2 = top.j() * omega;
        let h = p2 * p2 / (2.0 * top.j()) + top.mgl();
        match Nutation::from_constants(&top, h, p2, p2) {
            Ok(n) => println!(
                "constants of the sleeping top at ω_z = {omega}: {:?}",
                n.cubic()
            ),
            Err(e) => println!("constants of the sleeping top at ω_z = {omega}: {e}"),
        }
    }
    Ok(())
}

//! Higher-order perturbation theory for the pendulum: the Lie-series normal form to order N in a²,
//! cross-checked by Lindstedt–Poincaré and measured against the exact elliptic period
//! up to the separatrix; second order as in [Ardema 18.2].
//!
//! Run with `cargo run --release --example pendulum_order_n`.

// 3.14 is an amplitude of the period table, not an approximation of π.
#![allow(clippy::approx_constant)]

use hamilton_jacobi::perturbation::lindstedt::lindstedt_pendulum;
use hamilton_jacobi::perturbation::normal_form::PendulumNormalForm;
use hamilton_jacobi::systems::pendulum_exact;
use hamilton_jacobi::Result;
use std::f64::consts::PI;
use std::time::Instant;

fn main() -> Result<()> {
    let n = 1.0;
    // Cost per order (best of 5 builds).
    println!("| N | build time (normal form + both transformation series) | Lindstedt |");
    println!("|---|---|---|");
    for order in [2, 4, 8, 12, 16, 24] {
        let mut best = f64::INFINITY;
        let mut best_l = f64::INFINITY;
        for _ in 0..5 {
            let t0 = Instant::now();
            let nf = PendulumNormalForm::new(n, order)?;
            best = best.min(t0.elapsed().as_secs_f64());
            std::hint::black_box(nf);
            let t0 = Instant::now();
            let l = lindstedt_pendulum(order)?;
            best_l = best_l.min(t0.elapsed().as_secs_f64());
            std::hint::black_box(l);
        }
        println!(
            "| {order} | {:.3} ms | {:.3} ms |",
            best * 1e3,
            best_l * 1e3
        );
    }

    let big_n = 12;
    let nf = PendulumNormalForm::new(n, big_n)?;
    let lp = lindstedt_pendulum(big_n)?;
    println!("\nPeriod ratio τ/(2π/n) = Σ c_k a^(2k):");
    println!("| k | c_k (normal form) | c_k (Lindstedt) | rel. diff | c_(k) π²/c_(k−1) |");
    println!("|---|---|---|---|---|");
    let c = nf.period_ratio_series();
    for k in 0..=big_n {
        let ratio = if k > 0 {
            c[k] * PI * PI / c[k - 1]
        } else {
            f64::NAN
        };
        println!(
            "| {k} | {:.16e} | {:.16e} | {:.1e} | {ratio:.4} |",
            c[k],
            lp.period_ratio[k],
            (c[k] - lp.period_ratio[k]).abs() / c[k].abs()
        );
    }
    println!("\nNormal form H̄(J) = Σ h_m J^m (n = 1):");
    for (m, h) in nf.energy_coefficients().iter().enumerate() {
        println!("  h_{m} = {h:.16e}");
    }
    println!(
        "  reality defect |Im K|: {:.1e}",
        nf.normal_form().birkhoff().reality_defect()
    );

    println!("\nRelative error of the order-N period against the exact elliptic period:");
    let amps = [0.1, 0.5, 1.0, 2.0, 3.0, 3.1, 3.14, PI - 1e-6];
    print!("| N |");
    for a in amps {
        print!(" a = {a:.6} |");
    }
    println!();
    println!("|---|{}", "---|".repeat(amps.len()));
    for order in 1..=big_n {
        let nfo = PendulumNormalForm::new(n, order)?;
        print!("| {order} |");
        for a in amps {
            let exact = pendulum_exact::period(n, a)? / (2.0 * PI / n);
            let est = nfo.period_ratio(a)?;
            let flag = if est.warning.is_some() { "⚠" } else { "" };
            print!(" {:+.2e}{flag} |", (est.value - exact) / exact);
        }
        println!();
    }
    println!("(⚠: small parameter (a/π)² > 1/2 — the estimate carries a ConvergenceWarning)");
    for a in [3.0, PI - 1e-6] {
        let e = nf.period_ratio(a)?;
        println!(
            "a = {a}: μ = {:.4}, strict API: {:?}",
            e.small_parameter,
            e.checked()
        );
    }
    println!("a = π: {:?}", nf.period_ratio(PI));
    Ok(())
}

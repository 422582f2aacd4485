//! A tour of the Hamiltonian core on the Kepler problem, the pendulum and the harmonic
//! oscillator — invariants along the exact motion,
//! the AD vector field against the hand-written one, Poisson brackets of the integrals, canonicity
//! defects of exact and numerical flow maps, and the pendulum's exact period up to the separatrix.
//!
//! Run: `cargo run --release --example core_showcase`

use hamilton_jacobi::brackets::{certify, poisson_bracket, PhaseMap};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::kepler::elements::{state_to_classical, Classical};
use hamilton_jacobi::systems::kepler::orbit;
use hamilton_jacobi::systems::{
    pendulum_exact, AngularMomentum, ExactFlow, HarmonicOscillator, Invariants, Kepler2, Kepler3,
    Pendulum,
};
use hamilton_jacobi::{DualNum, Hamiltonian, Result};
use std::process::ExitCode;

/// One Störmer–Verlet (kick–drift–kick) step of a separable `H = T(p) + V(q)`, written generic over
/// the dual type so that its exact Jacobian — and so its symplectic defect — comes from AD.
struct VerletStep<'a, H> {
    h: &'a H,
    dt: f64,
}

impl<H: Hamiltonian<N>, const N: usize> PhaseMap<N> for VerletStep<'_, H> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        let half = self.dt * 0.5;
        let (_, pdot) = self.h.vector_field_generic(t, q, p);
        let ph = p + pdot * D::from(half);
        let (qdot, _) = self.h.vector_field_generic(t, q, &ph);
        let qn = q + qdot * D::from(self.dt);
        let (_, pdot) = self.h.vector_field_generic(t, &qn, &ph);
        (qn, ph + pdot * D::from(half))
    }
}

/// One classical RK4 step, generic over the dual type (not symplectic: its defect is O(dt⁵)).
struct Rk4Step<'a, H> {
    h: &'a H,
    dt: f64,
}

impl<H: Hamiltonian<N>, const N: usize> PhaseMap<N> for Rk4Step<'_, H> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        let f = |q: &SVector<D, N>, p: &SVector<D, N>| self.h.vector_field_generic(t, q, p);
        let (h, h2) = (D::from(self.dt), D::from(self.dt * 0.5));
        let (k1q, k1p) = f(q, p);
        let (k2q, k2p) = f(&(q + k1q * h2), &(p + k1p * h2));
        let (k3q, k3p) = f(&(q + k2q * h2), &(p + k2p * h2));
        let (k4q, k4p) = f(&(q + k3q * h), &(p + k3p * h));
        let s = D::from(self.dt / 6.0);
        (
            q + (k1q + k2q * D::from(2.0) + k3q * D::from(2.0) + k4q) * s,
            p + (k1p + k2p * D::from(2.0) + k3p * D::from(2.0) + k4p) * s,
        )
    }
}

fn max_rel_diff<const N: usize>(a: &SVector<f64, N>, b: &SVector<f64, N>) -> f64 {
    a.iter()
        .zip(b.iter())
        .map(|(x, y)| (x - y).abs() / y.abs().max(f64::MIN_POSITIVE))
        .fold(0.0, f64::max)
}

fn kepler_section() -> Result<()> {
    println!("## Kepler problem (μ = a = 1), started at periapsis");
    println!();
    println!("| e | period | max rel. drift of invariants over 100 periods (exact flow) | (h_z, H) | AD vs hand q̇,ṗ (rel.) | Verlet step defect | RK4 step defect |");
    println!("|---|---|---|---|---|---|---|");
    let kep = Kepler2::new(1.0)?;
    for e in [0.0, 0.5, 0.9, 0.99] {
        // The planar orbit: i = Ω = ω = 0, at periapsis.
        let (r, v) = Classical::new(1.0, e, 0.0, 0.0, 0.0, 0.0)?.to_state(1.0)?;
        let (q0, p0) = (SVector::from([r[0], r[1]]), SVector::from([v[0], v[1]]));
        let period = orbit::period(1.0, 1.0)?;
        let inv0 = kep.invariants(0.0, &q0, &p0)?;
        let mut drift: f64 = 0.0;
        for k in 1..=100 {
            let t = period * k as f64 * 0.999_7; // not an exact multiple: a generic point of the orbit
            let (q, p) = kep.exact_flow(0.0, &q0, &p0, t)?;
            for (a, b) in kep.invariants(t, &q, &p)?.iter().zip(&inv0) {
                drift = drift.max((a.value - b.value).abs() / b.value.abs().max(1.0));
            }
        }
        let bracket = poisson_bracket(&AngularMomentum::z(), &kep, 0.0, &q0, &p0)?;
        let (qd, pd) = kep.vector_field(0.0, &q0, &p0)?;
        let (qh, ph) = kep.vector_field_hand(&q0, &p0);
        let ad = max_rel_diff(&qd, &qh).max(max_rel_diff(&pd, &ph));
        let dt = period / 1000.0;
        let verlet = certify(&VerletStep { h: &kep, dt }, 0.0, &q0, &p0)?.symplectic_defect;
        let rk4 = certify(&Rk4Step { h: &kep, dt }, 0.0, &q0, &p0)?.symplectic_defect;
        println!("| {e} | {period:.15} | {drift:.2e} | {bracket:.2e} | {ad:.2e} | {verlet:.2e} | {rk4:.2e} |");
    }
    // 3-D: angular momentum algebra and the Kepler-equation round trip.
    let kep3 = Kepler3::new(1.0)?;
    let el = Classical::new(1.3, 0.4, 0.7, 1.1, 2.3, 0.9)?;
    let (r, v) = el.to_state(1.0)?;
    let back = state_to_classical(1.0, &r, &v)?;
    println!();
    println!(
        "3-D orbit a = 1.3, e = 0.4, i = 0.7, Ω = 1.1, ω = 2.3, M = 0.9: elements → state → elements error {:.2e}; energy {:.15}",
        [back.a - el.a, back.e - el.e, back.i - el.i, back.raan - el.raan, back.argp - el.argp, back.mean_anomaly - el.mean_anomaly]
            .iter()
            .fold(0.0f64, |m, x| m.max(x.abs())),
        kep3.value(0.0, &SVector::from([r[0], r[1], r[2]]), &SVector::from([v[0], v[1], v[2]]))?
    );
    println!();
    Ok(())
}

fn pendulum_section() -> Result<()> {
    println!("## Pendulum H = p²/2 + (1 − cos θ)");
    println!();
    println!("| amplitude a | exact period τ | τ/(2π) | energy drift over 20 periods (exact flow) | AD vs hand ṗ (rel.) | Verlet step defect |");
    println!("|---|---|---|---|---|---|");
    let pend = Pendulum::new(1.0)?;
    for a in [0.1, 1.0, 2.0, 3.0, 3.1, std::f64::consts::PI - 1e-6] {
        let tau = pend.period(a)?;
        let (q0, p0) = (SVector::from([a]), SVector::from([0.0]));
        let e0 = pend.value(0.0, &q0, &p0)?;
        let mut drift: f64 = 0.0;
        for k in 1..=20 {
            let (q, p) = pend.exact_flow(0.0, &q0, &p0, tau * k as f64 * 0.9993)?;
            drift = drift.max((pend.value(0.0, &q, &p)? - e0).abs() / e0);
        }
        let (q1, p1) = (SVector::from([0.5 * a]), SVector::from([0.3]));
        let (_, pd) = pend.vector_field(0.0, &q1, &p1)?;
        let (_, ph) = pend.vector_field_hand(&q1, &p1);
        let ad = max_rel_diff(&pd, &ph);
        let verlet = certify(&VerletStep { h: &pend, dt: 0.1 }, 0.0, &q1, &p1)?.symplectic_defect;
        println!(
            "| {a} | {tau:.13} | {:.13} | {drift:.2e} | {ad:.2e} | {verlet:.2e} |",
            tau / (2.0 * std::f64::consts::PI)
        );
    }
    println!();
    println!("Near the separatrix, with the gap δ = π − a given exactly (τ ≈ 4 ln(8/δ)):");
    println!();
    println!("| δ | τ | 4 ln(8/δ) |");
    println!("|---|---|---|");
    for d in [1e-2, 1e-6, 1e-10, 1e-16] {
        println!(
            "| {d:e} | {:.12} | {:.12} |",
            pendulum_exact::period_from_gap(1.0, d)?,
            4.0 * (8.0 / d).ln()
        );
    }
    println!();
    Ok(())
}

fn oscillator_section() -> Result<()> {
    println!("## Harmonic oscillator m = 2, ω = 3: exact flow map certified by AD");
    println!();
    let osc = HarmonicOscillator::new(2.0, 3.0)?;
    println!("| τ | symplectic defect ‖MᵀJM − J‖ | det M − 1 |");
    println!("|---|---|---|");
    for tau in [0.1, 1.0, 10.0, 1000.0] {
        let c = certify(
            &osc.flow_map(tau),
            0.0,
            &SVector::from([0.5]),
            &SVector::from([1.2]),
        )?;
        println!(
            "| {tau} | {:.2e} | {:.2e} |",
            c.symplectic_defect, c.det_minus_one
        );
    }
    println!();
    Ok(())
}

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.iter().any(|a| a == "-h" || a == "--help") {
        println!("core_showcase\n\nUSAGE: cargo run --release --example core_showcase\n\nRuns the Kepler problem, the pendulum and the harmonic oscillator through the\nHamiltonian core and prints invariants, bracket values and canonicity defects as Markdown tables.");
        return ExitCode::SUCCESS;
    }
    if let Some(a) = args.first() {
        eprintln!("core_showcase: unknown argument '{a}' (try --help)");
        return ExitCode::from(2);
    }
    println!("# hamilton-jacobi: the Hamiltonian core\n");
    match kepler_section()
        .and_then(|_| pendulum_section())
        .and_then(|_| oscillator_section())
    {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("core_showcase: {e}");
            ExitCode::FAILURE
        }
    }
}

//! Chaos indicators (X10): MEGNO and the maximal Lyapunov exponent through the integrators'
//! tangent maps, on named Hénon–Heiles and double-pendulum orbits, and maps over grids of initial
//! conditions that do not depend on the number of threads.
//!
//! Hénon–Heiles orbits (`H = ½(p² + x² + y²) + x²y − y³/3`), started on the section `x = 0` with
//! `p_x > 0` ([`HenonHeiles::section_start`]):
//!
//! | name | `E` | `(y, p_y)` | motion |
//! |------|-----|------------|--------|
//! | QP1 | 1/12 | (0, 0.25) | quasi-periodic |
//! | QP2 | 1/12 | (0, 0.3) | quasi-periodic |
//! | QP3 | 1/12 | (−0.2, 0.1) | quasi-periodic |
//! | QP4 | 1/12 | (0.15, −0.2) | quasi-periodic |
//! | PO1 | 1/12 | (0.254806162962425, 0) | stable periodic (elliptic fixed point of the section map, trace 0.647) |
//! | CH1 | 1/8 | (−0.1, 0) | chaotic |
//!
//! The quasi-periodic orbits lie away from the fixed points of the section map on `p_y = 0`
//! (elliptic at `y = 0.2548` and `y = −0.3037`, hyperbolic at `y = −0.1203`).

use hamilton_jacobi::chaos::{chaos_indicators, chaos_map, energy_surface_deviation};
use hamilton_jacobi::hamiltonian::Hamiltonian;
use hamilton_jacobi::integrate::{
    integrate, Crossing, Dop853, Fixed, Gauss, OneStep, Problem, Section, Splitting, Work,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::phase::{CanonicalPair, State};
use hamilton_jacobi::systems::HenonHeiles;

const E_REGULAR: f64 = 1.0 / 12.0;
const E_CHAOTIC: f64 = 0.125;
/// Verlet's step for the Hénon–Heiles runs (period of the small oscillations 2π).
const H: f64 = 0.02;

fn hh(e: f64, y: f64, py: f64) -> State<2> {
    HenonHeiles::section_start(e, y, py).unwrap()
}

/// A deviation on the energy surface: `(1, 0.5, 0.3, −0.7)` with its component along ∇H removed.
fn deviation<S: Hamiltonian<2>>(system: &S, start: &State<2>) -> CanonicalPair<2> {
    let d = (SVector::from([1.0, 0.5]), SVector::from([0.3, -0.7]));
    energy_surface_deviation(system, start, &d).unwrap()
}

fn verlet_megno(start: &State<2>, t1: f64) -> hamilton_jacobi::chaos::ChaosRun<2> {
    let problem = Problem::new(&HenonHeiles, 0.0, start.q, start.p, t1).unwrap();
    let method = Fixed::new(Splitting::VERLET_KDK, (t1 / H).round() as usize).unwrap();
    chaos_indicators(&problem, &method, &deviation(&HenonHeiles, start), 10).unwrap()
}

#[test]
fn quasi_periodic_henon_heiles_orbits_have_mean_megno_two() {
    // Cincotta & Simó (2000): ⟨Y⟩ → 2 on invariant tori. At t = 2·10⁴ (about 3200 periods).
    for (name, y, py) in [
        ("QP1", 0.0, 0.25),
        ("QP2", 0.0, 0.3),
        ("QP3", -0.2, 0.1),
        ("QP4", 0.15, -0.2),
    ] {
        let run = verlet_megno(&hh(E_REGULAR, y, py), 2e4);
        let last = run.last;
        println!("{name}: {last:?}");
        assert!(
            (last.mean_megno - 2.0).abs() <= 0.05,
            "{name}: ⟨Y⟩ = {}",
            last.mean_megno
        );
        assert_eq!(last.t, 2e4);
        assert_eq!(run.history.len(), 10);
    }
}

#[test]
fn stable_periodic_orbit_has_mean_megno_zero() {
    let start = hh(E_REGULAR, 0.254806162962425, 0.0);
    // PO1 is periodic: its first return to the section (DOP853 at rtol 1e-13) is itself.
    let problem = Problem::new(&HenonHeiles, 0.0, start.q, start.p, 100.0).unwrap();
    let mut section = Section::new(
        |_t, q: &SVector<f64, 2>, _p: &SVector<f64, 2>| q[0],
        Crossing::Up,
    )
    .stop_after(1);
    integrate(&problem, &Dop853::new(1e-13, 1e-15).unwrap(), &mut section).unwrap();
    let back = section.points[0];
    assert!((back.q[1] - start.q[1]).abs() < 1e-10 && back.p[1].abs() < 1e-10);
    let run = verlet_megno(&start, 2e4);
    println!("PO1: {:?}", run.last);
    assert!(
        run.last.mean_megno.abs() <= 0.05,
        "⟨Y⟩ = {}",
        run.last.mean_megno
    );
}

/// Benettin's two-particle estimate of the maximal Lyapunov exponent: a second orbit at distance
/// `d₀` along `deviation`, advanced by the same real steps as the first (Kahan-compensated, as
/// `Fixed` runs), brought back to distance `d₀` every `every` steps; `λ = Σ ln(dₖ/d₀) / t`.
fn benettin<S, M: OneStep<S, 2>>(
    system: &S,
    method: &M,
    start: &State<2>,
    deviation: &CanonicalPair<2>,
    h: f64,
    steps: usize,
    every: usize,
) -> f64 {
    let d0 = 1e-9;
    let n = (deviation.0.norm_squared() + deviation.1.norm_squared()).sqrt();
    let kahan = |x: &mut SVector<f64, 2>, c: &mut SVector<f64, 2>, dx: &SVector<f64, 2>| {
        for i in 0..2 {
            let y = dx[i] - c[i];
            let s = x[i] + y;
            c[i] = (s - x[i]) - y;
            x[i] = s;
        }
    };
    let mut a = [start.q, start.p, SVector::zeros(), SVector::zeros()];
    let mut b = [
        start.q + deviation.0 * (d0 / n),
        start.p + deviation.1 * (d0 / n),
        SVector::zeros(),
        SVector::zeros(),
    ];
    let mut work = Work::default();
    let mut sum = 0.0;
    for k in 0..steps {
        let t = h * k as f64;
        for z in [&mut a, &mut b] {
            let (dq, dp) = method
                .increment(system, t, &z[0], &z[1], h, &mut work)
                .unwrap();
            let [q, p, cq, cp] = z;
            kahan(q, cq, &dq);
            kahan(p, cp, &dp);
        }
        if (k + 1) % every == 0 {
            let d = ((b[0] - a[0]).norm_squared() + (b[1] - a[1]).norm_squared()).sqrt();
            sum += (d / d0).ln();
            b[0] = a[0] + (b[0] - a[0]) * (d0 / d);
            b[1] = a[1] + (b[1] - a[1]) * (d0 / d);
        }
    }
    sum / (h * steps as f64)
}

#[test]
fn chaotic_orbit_megno_grows_as_half_the_lyapunov_exponent() {
    // CH1 at E = 1/8: ⟨Y⟩ ≈ λt/2 (Cincotta, Giordano & Simó 2003), with λ from the two-particle
    // method (every 10 steps, d₀ = 1e-9) within 5 %.
    let start = hh(E_CHAOTIC, -0.1, 0.0);
    let t1 = 2e4;
    let run = verlet_megno(&start, t1);
    let steps = (t1 / H).round() as usize;
    let d = deviation(&HenonHeiles, &start);
    let lambda = benettin(
        &HenonHeiles,
        &Splitting::VERLET_KDK,
        &start,
        &d,
        H,
        steps,
        10,
    );
    let from_megno = 2.0 * run.last.mean_megno / run.last.t;
    println!(
        "CH1: {:?}; 2⟨Y⟩/t = {from_megno}, Benettin λ = {lambda}",
        run.last
    );
    assert!(run.last.mean_megno > 100.0);
    assert!(
        (from_megno / lambda - 1.0).abs() <= 0.05,
        "{from_megno} vs {lambda}"
    );
    assert!((run.last.lyapunov / lambda - 1.0).abs() <= 0.05);
}

// The planar double pendulum of two equal point masses on massless rods from the catalogue,
// `m₁ = m₂ = 1`, `l₁ = l₂ = 1`, `g = 1` (Ardema M21).
fn double_pendulum() -> hamilton_jacobi::systems::DoublePendulum {
    hamilton_jacobi::systems::DoublePendulum::new(1.0, 1.0, 1.0, 1.0, 1.0).unwrap()
}

#[test]
fn double_pendulum_regular_and_chaotic_orbits() {
    // DP-R: released at rest from θ₁ = θ₂ = 0.3 (near the in-phase normal mode, far below the
    // saddles); DP-C: released at rest from θ₁ = θ₂ = 2 (energy above the saddle (π, 0)).
    // Gauss–Legendre (s = 2), h = 0.02, t = 2000.
    let t1 = 2000.0;
    let method = Fixed::new(Gauss::<2>::new().unwrap(), (t1 / 0.02) as usize).unwrap();
    let pendulum = double_pendulum();
    let mut out = Vec::new();
    for (name, th) in [("DP-R", 0.3), ("DP-C", 2.0)] {
        let start = State::new(0.0, SVector::from([th, th]), SVector::zeros()).unwrap();
        let problem = Problem::new(&pendulum, 0.0, start.q, start.p, t1).unwrap();
        let run = chaos_indicators(&problem, &method, &deviation(&pendulum, &start), 4).unwrap();
        println!("{name}: {:?}", run.last);
        out.push(run.last);
    }
    assert!(
        out[0].mean_megno <= 2.05,
        "regular: ⟨Y⟩ = {}",
        out[0].mean_megno
    );
    assert!(
        out[1].mean_megno >= 20.0,
        "chaotic: ⟨Y⟩ = {}",
        out[1].mean_megno
    );
    assert!(out[1].lyapunov > 10.0 * out[0].lyapunov);
}

#[test]
fn chaos_maps_do_not_depend_on_the_number_of_threads() {
    // An 8 × 8 grid of the section x = 0 at E = 1/8 (cells outside the energy's region skipped),
    // t = 200, run on pools of 1 and 2 threads: the same bits.
    let mut starts = Vec::new();
    for i in 0..8 {
        for j in 0..8 {
            let (y, py) = (-0.4 + 0.1 * i as f64, -0.4 + 0.1 * j as f64);
            if let Ok(s) = HenonHeiles::section_start(E_CHAOTIC, y, py) {
                starts.push(s);
            }
        }
    }
    assert!(starts.len() > 30);
    let method = Fixed::new(Splitting::VERLET_KDK, 4000).unwrap();
    let d = (SVector::from([1.0, 0.5]), SVector::from([0.3, -0.7]));
    let run = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| chaos_map(&HenonHeiles, &starts, 200.0, &method, &d).unwrap())
    };
    let (one, two) = (run(1), run(2));
    let bits = |v: &[Option<hamilton_jacobi::chaos::ChaosIndicators>]| {
        v.iter()
            .map(|c| c.map(|c| (c.mean_megno.to_bits(), c.lyapunov.to_bits())))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&one), bits(&two));
    // Each cell is the sequential run of its start.
    let k = 5;
    let problem = Problem::new(&HenonHeiles, 0.0, starts[k].q, starts[k].p, 200.0).unwrap();
    let single = chaos_indicators(&problem, &method, &d, 0).unwrap().last;
    assert_eq!(one[k], Some(single));
    assert!(one.iter().all(|c| c.is_some()));
}

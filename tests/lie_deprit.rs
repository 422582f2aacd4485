//! Lie–Deprit perturbation theory in given action–angle variables
//! (`hamilton_jacobi::perturbation::lie_deprit`) against independent oracles:
//! * the pendulum's `K(J)` against the exact rationals from reverting the exact action
//!   (`common::rational`), and against the Birkhoff route (`perturbation::birkhoff`);
//! * `H ∘ E_W − K = O(ε^{n+1})` on a grid of angles, with the slope in `ε` fitted;
//! * the frequencies of `K` against the angle advance of integrated orbits (DOP853);
//! * the driven linear oscillator: its frequencies are not shifted at any order, and at
//!   `Ω = ω` the small divisor names `k = ±(1, −1)`; a near resonance names its `k` and divisor.

mod common;

use common::rational::pendulum_energy_series;
use hamilton_jacobi::integrate::{integrate, Dop853, Problem, Samples};
use hamilton_jacobi::nalgebra::{SVector, Vector1, Vector2};
use hamilton_jacobi::perturbation::birkhoff::{normal_form, NormalFormKind};
use hamilton_jacobi::perturbation::lie_deprit::{
    lie_deprit, ActionAngleHamiltonian, AmplitudePendulum, AtFixedEpsilon, DrivenOscillator,
    LieDeprit, LieDepritOptions,
};
use hamilton_jacobi::stability::hamiltonian_equilibrium;
use hamilton_jacobi::systems::Pendulum;
use hamilton_jacobi::{DualNum, Error};

const EPS: f64 = f64::EPSILON;

/// The worst-case rounding of a DFT coefficient of order-one node values: a sum of `M^N` terms
/// (`M = 4H + 4` nodes per angle, as `series::fourier_taylor` uses) carries at most `M^N ε` of
/// the summands' magnitude (Higham 2002, §4.2).
fn dft_rounding(max_harmonic: usize, angles: u32) -> f64 {
    ((4 * max_harmonic + 4) as f64).powi(angles as i32) * EPS
}

/// The order in `μ` that carries `K(J)` through `J^{10}`.
const PENDULUM_ORDER: usize = 18;

/// `K` of the pendulum at `J* = 1` to order `μ^{18}` (harmonics to `2n + 2`: the products of the
/// triangle's terms reach twice the order).
fn pendulum_to_order() -> LieDeprit<1> {
    lie_deprit(
        &AmplitudePendulum,
        &Vector1::new(1.0),
        &LieDepritOptions {
            action_degree: 0,
            ..LieDepritOptions::new(PENDULUM_ORDER, 2 * PENDULUM_ORDER + 2)
        },
    )
    .unwrap()
}

/// Each `[μ^{2m}] K` is a sum of `O(m)` Lie terms with the harmonics of `H` from a DFT: a few ulps
/// per order.
fn pendulum_tolerance(m: usize, want: f64) -> f64 {
    4.0 * EPS * (2 * m) as f64 * want.abs()
}

#[test]
fn pendulum_k_matches_exact_rationals_through_j10() {
    let exact = pendulum_energy_series(10);
    let clock = std::time::Instant::now();
    let ld = pendulum_to_order();
    eprintln!(
        "pendulum, order μ^{PENDULUM_ORDER}: {:?}; remainder {:.2e}, Fourier error {:.2e}",
        clock.elapsed(),
        ld.remainder(),
        ld.fourier_error()
    );
    assert_eq!(ld.energy_coefficient(0).unwrap(), 1.0);
    for p in 1..=PENDULUM_ORDER {
        let got = ld.energy_coefficient(p).unwrap();
        if p % 2 == 1 {
            // Odd powers of the amplitude vanish by the symmetry μ → −μ.
            assert!(got.abs() <= 1e-18, "μ^{p}: {got:e}");
            continue;
        }
        let m = p / 2;
        let want = exact[m + 1].f64();
        let err = (got - want).abs();
        eprintln!(
            "J^{}: {got:.17e} vs {want:.17e} ({:.1} ulp)",
            m + 1,
            err / (want.abs() * EPS)
        );
        assert!(
            err <= pendulum_tolerance(m, want),
            "J^{}: {got:e} vs {want:e}",
            m + 1
        );
    }
    assert!(ld.fourier_error() <= 1e-13, "{:e}", ld.fourier_error());
}

#[test]
fn pendulum_k_is_homogeneous_in_the_reference_action() {
    let exact = pendulum_energy_series(5);
    for js in [0.25, 0.5, 2.0] {
        let ld = lie_deprit(
            &AmplitudePendulum,
            &Vector1::new(js),
            &LieDepritOptions::new(8, 18),
        )
        .unwrap();
        for m in 1..=4 {
            let got = ld.energy_coefficient(2 * m).unwrap();
            let want = exact[m + 1].f64() * js.powi(m as i32 + 1);
            assert!(
                (got - want).abs() <= pendulum_tolerance(m, want),
                "J* = {js}, μ^{}: {got:e} vs {want:e}",
                2 * m
            );
            // ω′ = ∂K/∂J: the δJ coefficient is (m + 1) h_{m+1} J*^m
            let dk = ld.energy_terms()[2 * m].coefficient(&[1]).unwrap();
            let want_w = exact[m + 1].f64() * (m as f64 + 1.0) * js.powi(m as i32);
            assert!(
                (dk - want_w).abs() <= pendulum_tolerance(m, want_w),
                "J* = {js}, ∂K/∂J at μ^{}: {dk:e} vs {want_w:e}",
                2 * m
            );
        }
    }
}

#[test]
fn lie_deprit_route_equals_birkhoff_route_for_the_pendulum() {
    // H = p²/2 + 1 − cos q (n = 1).
    let pendulum = Pendulum::new(1.0).unwrap();
    let eq =
        hamiltonian_equilibrium(&pendulum, 0.0, &Vector1::new(0.3), &Vector1::new(-0.2)).unwrap();
    let nf = normal_form(&pendulum, 0.0, &eq, 20, NormalFormKind::Birkhoff).unwrap();
    let kb = nf.action_polynomial().unwrap();
    let ld = pendulum_to_order();
    for m in 1..=PENDULUM_ORDER / 2 {
        let birkhoff = kb.coefficient(&[m as u32 + 1]).unwrap();
        let deprit = ld.energy_coefficient(2 * m).unwrap();
        // Both are within their own few-ulp bounds of the exact value.
        let tol = 2.0 * pendulum_tolerance(m, birkhoff);
        assert!(
            (birkhoff - deprit).abs() <= tol,
            "J^{}: Birkhoff {birkhoff:e}, Lie–Deprit {deprit:e}",
            m + 1
        );
    }
}

/// Two non-resonant oscillators with an anharmonic `H₀` and an angle-dependent coupling:
/// `H = ω₁J₁ + ω₂J₂ + J₁²/4 − J₂²/8 + ε[J₁J₂ cos(θ₁ − θ₂) + √J₁ J₂ cos(θ₁ + 2θ₂) + J₁ cos 2θ₁]`.
struct Coupled {
    w: [f64; 2],
}
impl ActionAngleHamiltonian<2> for Coupled {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        j: &SVector<D, 2>,
        th: &SVector<D, 2>,
        eps: D,
    ) -> D {
        let h0 = j[0] * self.w[0] + j[1] * self.w[1] + j[0] * j[0] * 0.25 - j[1] * j[1] * 0.125;
        let h1 = j[0] * j[1] * (th[0] - th[1]).cos()
            + j[0].sqrt() * j[1] * (th[0] + th[1] * 2.0).cos()
            + j[0] * (th[0] * 2.0).cos();
        h0 + eps * h1
    }
}

const GOLDEN: [f64; 2] = [1.0, 0.618_033_988_749_894_8];

#[test]
fn transformed_hamiltonian_residual_scales_as_eps_to_n_plus_one() {
    let sys = Coupled { w: GOLDEN };
    let js = Vector2::new(1.0, 0.8);
    for n in 1..=3 {
        let ld = lie_deprit(&sys, &js, &LieDepritOptions::new(n, 8)).unwrap();
        let mut points = Vec::new();
        for eps in [0.02, 0.01, 0.005] {
            let mut worst: f64 = 0.0;
            for a in 0..7 {
                for b in 0..5 {
                    let th = Vector2::new(0.9 * a as f64, 1.3 * b as f64 + 0.2);
                    let (jo, to) = ld.from_normal(&js, &th, eps).unwrap();
                    let h = sys.hamiltonian(&jo, &to, eps);
                    worst = worst.max((h - ld.energy(&js, eps).unwrap()).abs());
                }
            }
            points.push((eps, worst));
        }
        let slope = common::loglog_slope(&points);
        eprintln!("order {n}: residuals {points:?}, slope {slope:.3}");
        assert!(
            (slope - (n + 1) as f64).abs() <= 0.3,
            "order {n}: slope {slope}"
        );
    }
}

/// The frequencies `ω′ = ∂K/∂J′` of order `n` against the angle advance of an integrated orbit
/// on the torus `J′ = J*` (the new angles at both ends from the inverse map). The error of the
/// order-`n` theory is `O(ε^{n+1})`; its size is estimated by the first term left out,
/// `|ω′_{n+1} − ω′_n|`, and the test allows three times that, plus the shift of the frequency
/// by the start's distance from the torus (the map's own `O(ε^{n+1})` error, measured as the
/// drift of `J′` along the orbit) and the measurement floor `1e-11` (DOP853 at `1e-13` over
/// `t = 400`).
#[test]
fn averaged_frequencies_match_integrated_orbits() {
    let sys = Coupled { w: GOLDEN };
    let js = Vector2::new(1.0, 0.8);
    let eps = 0.01;
    let span = 400.0;
    let theories: Vec<_> = (1..=6)
        .map(|n| {
            lie_deprit(
                &sys,
                &js,
                &LieDepritOptions {
                    action_degree: 2,
                    ..LieDepritOptions::new(n, 12)
                },
            )
            .unwrap()
        })
        .collect();
    let mut errors = Vec::new();
    for n in 1..=4 {
        let ld = &theories[n - 1];
        // An orbit on the torus J′ = J*: its old variables from the map.
        let th0 = Vector2::new(0.3, 1.1);
        let (j0, t0) = ld.from_normal(&js, &th0, eps).unwrap();
        let dop = Dop853::new(1e-13, 1e-15).unwrap();
        let mut samples = Samples::uniform(0.0, span, 1).unwrap();
        let report = integrate(
            &Problem::new(&AtFixedEpsilon::new(&sys, eps).unwrap(), 0.0, t0, j0, span).unwrap(),
            &dop,
            &mut samples,
        )
        .unwrap();
        let (j1, t1) = ld.to_normal(&report.last.p, &report.last.q, eps).unwrap();
        let measured = (t1 - th0) / span;
        let theory = ld.frequencies(&js, eps).unwrap();
        // The next two orders (one of them may vanish by symmetry).
        let next = theories[n].frequencies(&js, eps).unwrap();
        let after = theories[n + 1].frequencies(&js, eps).unwrap();
        let estimate = (next - theory).amax().max((after - theory).amax());
        let err = (measured - theory).amax();
        let drift = (j1 - js).amax();
        eprintln!(
            "order {n}: ω′ = {:?}, error {err:.2e} (estimate {estimate:.2e}, ε^(n+1) = {:.0e}), \
             J′ drift {drift:.2e}",
            theory.as_slice(),
            eps.powi(n as i32 + 1)
        );
        assert!(
            estimate <= 10.0 * eps.powi(n as i32 + 1),
            "order {n}: {estimate:e}"
        );
        // The orbit starts on J′ = J* only to the map's accuracy: its torus is off by at most
        // the J′ drift seen along it, which moves ω′ by ‖∂ω′/∂J′‖ (row sums, central
        // differences of the theory's own ω′) times that drift.
        let h = 1e-3;
        let columns: Vec<_> = (0..2)
            .map(|i| {
                let e = Vector2::ith(i, h);
                (ld.frequencies(&(js + e), eps).unwrap() - ld.frequencies(&(js - e), eps).unwrap())
                    / (2.0 * h)
            })
            .collect();
        let hessian_norm = (columns[0].abs() + columns[1].abs()).amax();
        let tol = 3.0 * estimate + hessian_norm * drift + 1e-11;
        assert!(err <= tol, "order {n}: {err:e} > {tol:e}");
        errors.push(err);
    }
    assert!(errors[3] < errors[0] * 1e-3, "{errors:?}");
}

#[test]
fn driven_oscillator_frequencies_unshifted_and_resonance_named() {
    // A linear system: the frequencies of its tori are ω and Ω at every order.
    let ld = lie_deprit(
        &DrivenOscillator {
            omega: 1.0,
            drive: 0.7,
        },
        &Vector2::new(1.0, 1.0),
        &LieDepritOptions::new(4, 8),
    )
    .unwrap();
    let w = ld.frequencies(&Vector2::new(1.0, 1.0), 0.1).unwrap();
    // Rounding of the DFT harmonics: a sum over the (4H + 4)² = 36² nodes carries at most
    // (nodes) ε of the summands' size (Higham 2002, §4.2), amplified by the divisor 1/(1 − 0.7)
    // of the generator.
    let tol = dft_rounding(8, 2) / (1.0 - 0.7);
    assert!(
        (w[0] - 1.0).abs() <= tol && (w[1] - 0.7).abs() <= tol,
        "{w:?} (tolerance {tol:e})"
    );
    // Ω = ω: the modes k = ±(1, −1) of sin θ₁ cos θ₂ have k·ω = 0.
    let err = lie_deprit(
        &DrivenOscillator {
            omega: 1.0,
            drive: 1.0,
        },
        &Vector2::new(1.0, 1.0),
        &LieDepritOptions::new(2, 8),
    )
    .unwrap_err();
    match err {
        Error::SmallDivisor { k, divisor, .. } => {
            assert!(k == vec![1, -1] || k == vec![-1, 1], "k = {k:?}");
            assert_eq!(divisor, 0.0);
        }
        other => panic!("expected SmallDivisor, got {other:?}"),
    }
}

/// `H = J₁ + (1 + δ)J₂ + ε J₁J₂ cos(θ₁ − θ₂)`: the mode `k = ±(1, −1)` has divisor `∓δ`.
struct NearResonant(f64);
impl ActionAngleHamiltonian<2> for NearResonant {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        j: &SVector<D, 2>,
        th: &SVector<D, 2>,
        eps: D,
    ) -> D {
        j[0] + j[1] * (1.0 + self.0) + eps * j[0] * j[1] * (th[0] - th[1]).cos()
    }
}

#[test]
fn near_resonance_names_the_resonance_vector() {
    let delta = 1e-4;
    let js = Vector2::new(1.0, 1.0);
    let options = LieDepritOptions {
        small_divisor: 1e-3,
        ..LieDepritOptions::new(2, 6)
    };
    match lie_deprit(&NearResonant(delta), &js, &options).unwrap_err() {
        Error::SmallDivisor {
            k,
            divisor,
            threshold,
            ..
        } => {
            assert!(k == vec![1, -1] || k == vec![-1, 1], "k = {k:?}");
            let expect = -delta * f64::from(k[0]);
            // k·ω = ω₁ − ω₂ with each ω from a DFT over (4H + 4)² = 28² nodes of size ≈ 1.
            let tol = 2.0 * dft_rounding(6, 2);
            assert!(
                (divisor - expect).abs() <= tol,
                "{divisor:e} vs {expect:e} (tolerance {tol:e})"
            );
            assert!(threshold > divisor.abs());
        }
        other => panic!("expected SmallDivisor, got {other:?}"),
    }
    // Above the default threshold the divisor 1e-4 is accepted, and the generator carries it:
    // |W₁| = |J₁J₂/2| / δ per mode.
    let ld = lie_deprit(&NearResonant(delta), &js, &LieDepritOptions::new(2, 6)).unwrap();
    let w1 = ld.generator_norms()[0];
    assert!((w1 - 1.0 / delta).abs() <= 1e-8 / delta, "{w1:e}");
}

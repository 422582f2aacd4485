//! Splitting, composition and Wisdom–Holman methods against exact solutions: observed orders,
//! canonicity of one step by AD, Wisdom–Holman against the general methods on a perturbed Kepler
//! problem, and typed errors for bad input.
//!
//! Run with `--nocapture` to see the measured numbers.

mod common;

use hamilton_jacobi::brackets::certify;
use hamilton_jacobi::integrate::methods::Construction;
use hamilton_jacobi::integrate::{
    integrate, Fixed, MethodInfo, OneStep, Problem, Splitting, StepMap, WisdomHolman, METHODS,
};
use hamilton_jacobi::nalgebra::{SVector, Vector2};
use hamilton_jacobi::perturbation::forces::{NoForce, PerturbedTwoBody, J2};
use hamilton_jacobi::systems::{kepler, ExactFlow, Kepler2, Pendulum};
use hamilton_jacobi::{Error, Hamiltonian};
use std::f64::consts::PI;
use std::time::Instant;

type V<const N: usize> = SVector<f64, N>;

/// Run `n` steps of `m` from `(q0, p0)` over `[0, t1]`: final state and gradient count.
fn run<S: Hamiltonian<N>, M: OneStep<S, N> + Copy, const N: usize>(
    s: &S,
    m: M,
    q0: V<N>,
    p0: V<N>,
    t1: f64,
    n: usize,
) -> (V<N>, V<N>, usize) {
    let pb = Problem::new(s, 0.0, q0, p0, t1).unwrap();
    let r = integrate(&pb, &Fixed::new(m, n).unwrap(), &mut ()).unwrap();
    (r.last.q, r.last.p, r.work.gradients)
}

fn err<const N: usize>(a: (V<N>, V<N>), b: (V<N>, V<N>)) -> f64 {
    (a.0 - b.0).amax().max((a.1 - b.1).amax())
}

/// Step counts `n_k = round(2·2^{k/4})` up to 8192: a grid fine enough to leave several points
/// between the pre-asymptotic regime and the rounding plateau even for order 10.
fn grid() -> Vec<usize> {
    let mut v: Vec<usize> = (0..=48)
        .map(|k| (2.0 * 2f64.powf(k as f64 / 4.0)).round() as usize)
        .collect();
    v.dedup();
    v
}

/// The observed order: errors on the grid (stopping once the plateau is reached), the points
/// with error ≥ `floor`, of which the `keep` with the largest `n` (the smallest steps, the most
/// asymptotic points above the plateau) enter the least-squares fit.
///
/// `floor` is 30× the rounding plateau of the problem (measured: the errors of the order-8 and
/// order-10 methods at large n scatter around 5e−16 for the pendulum and 2e−14 for Kepler), so
/// rounding shifts each log-error by at most ln(1 + 1/30) = 0.033 and the fitted slope — over a
/// span of at least a factor 2^{(keep−1)/4} in n — by at most 0.033/ln(2^{1/4}·…) < 0.1 for
/// keep = 5 (a factor 2 in n), well inside the ±0.3 allowed.
fn observed_order(
    errors: impl Fn(usize) -> f64,
    floor: f64,
    keep: usize,
) -> (f64, Vec<(usize, f64)>) {
    let mut above = Vec::new();
    let mut below = 0;
    for n in grid() {
        let e = errors(n);
        if e >= floor {
            above.push((n, e));
        } else {
            below += 1;
            if below >= 3 {
                break;
            }
        }
    }
    let pts: Vec<(usize, f64)> = above[above.len().saturating_sub(keep)..].to_vec();
    let fit: Vec<(f64, f64)> = pts.iter().map(|&(n, e)| (n as f64, e)).collect();
    (-common::loglog_slope(&fit), pts)
}

const KEEP: usize = 5;

/// The entries of the method table built as `construction`, with their tables.
fn entries(
    kepler: bool,
) -> impl Iterator<
    Item = (
        &'static MethodInfo,
        &'static hamilton_jacobi::integrate::coefficients::Table,
    ),
> {
    METHODS.iter().filter_map(move |m| match m.construction {
        Construction::Splitting(t) if !kepler => Some((m, t)),
        Construction::KeplerSplitting(t) if kepler => Some((m, t)),
        _ => None,
    })
}

/// Observed order of every splitting and composition method of the method table within ±0.3 of
/// the order the table states ([`MethodInfo::order`]; the method's own `OneStep::order` and
/// `name` agree with its entry) on
/// the pendulum (n = 1, q₀ = 1, p₀ = 0, against the elliptic-function solution) and on Kepler
/// (μ = a = 1, e = 0.5 from periapsis, against Kepler's equation), over 0.8 of a period.
///
/// Not over exactly one period: symplectic Euler is Verlet conjugated by a half kick,
/// `Φ_SE = χ⁻¹ ∘ Φ_V ∘ χ`, so its O(h) error is that of the half kicks at the two ends — which
/// cancel when the motion has returned to its starting point: over exactly one period both
/// symplectic Euler variants show order 2 (measured: 2.00 on both problems).
#[test]
fn observed_orders_of_splitting_methods() {
    let pend = Pendulum::new(1.0).unwrap();
    let tp = 0.8 * pend.period(1.0).unwrap();
    let (pq0, pp0) = (V::<1>::from([1.0]), V::<1>::from([0.0]));
    let pref = pend.exact_flow(0.0, &pq0, &pp0, tp).unwrap();
    let kep = Kepler2::new(1.0).unwrap();
    let (kq0, kp0) = (V::<2>::from([0.5, 0.0]), V::<2>::from([0.0, 3f64.sqrt()]));
    let tk = 0.8 * 2.0 * PI;
    let (r, v) = kepler::propagate(
        1.0,
        &Vector2::new(kq0[0], kq0[1]),
        &Vector2::new(kp0[0], kp0[1]),
        tk,
    )
    .unwrap();
    let kref = (V::<2>::from([r[0], r[1]]), V::<2>::from([v[0], v[1]]));
    let mut failures = Vec::new();
    assert_eq!(entries(false).count(), 12);
    for (info, table) in entries(false) {
        let m = Splitting::new(table).unwrap();
        let nominal = f64::from(info.order.unwrap());
        let name = OneStep::<Pendulum, 1>::name(&m);
        assert_eq!(name, info.label());
        assert_eq!(Some(OneStep::<Pendulum, 1>::order(&m)), info.order);
        let (op, pts_p) = observed_order(
            |n| {
                let (q, p, _) = run(&pend, m, pq0, pp0, tp, n);
                err((q, p), pref)
            },
            1.5e-14,
            KEEP,
        );
        let (ok, pts_k) = observed_order(
            |n| {
                let (q, p, _) = run(&kep, m, kq0, kp0, tk, n);
                err((q, p), kref)
            },
            6e-13,
            KEEP,
        );
        println!(
            "{name:34} nominal {nominal:2}  pendulum {op:5.2} (n {}..{}, e {:.1e}..{:.1e})  Kepler {ok:5.2} (n {}..{}, e {:.1e}..{:.1e})",
            pts_p[0].0,
            pts_p[pts_p.len() - 1].0,
            pts_p[0].1,
            pts_p[pts_p.len() - 1].1,
            pts_k[0].0,
            pts_k[pts_k.len() - 1].0,
            pts_k[0].1,
            pts_k[pts_k.len() - 1].1,
        );
        // The one exception, measured and not hidden: Sofroniou–Spaletta 10 has its h¹⁰ error
        // coefficients minimised, so the h¹² term still dominates in the whole window between
        // the pre-asymptotic regime and the f64 plateau (local slopes fall from 10.8 to 10.1 on
        // the pendulum and stay ≈ 11 on Kepler down to 1e−12). For it the window is one-sided
        // by +1: the order is at least 10 − 0.3 and the excess is the next term. (Its order is
        // exactly 10 by the 50-digit order-condition check in `coefficients`: residuals through
        // h¹⁰ vanish to 2e−32, the h¹¹ coefficient is 2e−6.)
        let upper = if m == Splitting::SOFRONIOU_SPALETTA35 {
            1.0
        } else {
            0.3
        };
        for (what, o, pts) in [("pendulum", op, &pts_p), ("Kepler", ok, &pts_k)] {
            if pts.len() < 3 || o < nominal - 0.3 || o > nominal + upper {
                failures.push(format!("{name} on {what}: order {o:.2} from {pts:?}"));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// Kepler + J₂ in the equatorial plane.
type PlanarJ2 = PerturbedTwoBody<J2, NoForce, 2>;

/// The perturbed problem of the Wisdom–Holman tests: planar Kepler (μ = 1) plus the J₂ term of
/// strength ε = J₂R² (R = 1) in the equatorial plane, `H₁ = −ε/(2r³)`, from the periapsis of the
/// e = 0.5, a = 1 orbit, over one period.
fn j2_problem(eps: f64) -> (PlanarJ2, V<2>, V<2>, f64) {
    (
        PlanarJ2::conservative(1.0, J2::new(1.0, eps, 1.0).unwrap()).unwrap(),
        V::<2>::from([0.5, 0.0]),
        V::<2>::from([0.0, 3f64.sqrt()]),
        2.0 * PI,
    )
}

/// Reference solution of the perturbed problem: Sofroniou–Spaletta 10 with 1024 steps,
/// cross-checked against Kahan–Li 8 with 2048 steps (two different methods; on pure Kepler both
/// reach the 2e−14 plateau well before these step counts). Their difference bounds the
/// reference's error; asserted ≤ 1e−12.
fn j2_reference(eps: f64) -> (V<2>, V<2>) {
    let (s, q0, p0, t1) = j2_problem(eps);
    let (q, p, _) = run(&s, Splitting::SOFRONIOU_SPALETTA35, q0, p0, t1, 1024);
    let (q2, p2, _) = run(&s, Splitting::KAHAN_LI17, q0, p0, t1, 2048);
    let d = err((q, p), (q2, p2));
    assert!(d <= 1e-12, "reference disagreement {d:e}");
    (q, p)
}

/// Observed order of every Wisdom–Holman method of the method table, against the order the
/// table states, on the perturbed problem with ε = 0.01 (so that
/// the ε²h² term, the one that sets the order 2 of all SABA_n/SBAB_n, is resolved well above the
/// plateau; ε = 0.1 would not do: −ε/(2r³) then removes the centrifugal barrier of this orbit,
/// L² = 3/4, and the motion falls into the centre), against the reference (floor 3e−11, 30× the
/// 1e−12 to which the reference is checked).
#[test]
fn observed_orders_of_wisdom_holman_methods() {
    let eps = 0.01;
    let (s, q0, p0, t1) = j2_problem(eps);
    let reference = j2_reference(eps);
    let mut failures = Vec::new();
    assert_eq!(entries(true).count(), 8);
    for (info, table) in entries(true) {
        let m = WisdomHolman::new(table).unwrap();
        let nominal = f64::from(info.order.unwrap());
        let name = OneStep::<PlanarJ2, 2>::name(&m);
        assert_eq!(name, info.label());
        assert_eq!(Some(OneStep::<PlanarJ2, 2>::order(&m)), info.order);
        let (o, pts) = observed_order(
            |n| {
                let (q, p, _) = run(&s, m, q0, p0, t1, n);
                err((q, p), reference)
            },
            3e-11,
            KEEP,
        );
        println!(
            "{name:24} nominal {nominal}  observed {o:5.2} (n {}..{}, e {:.1e}..{:.1e})",
            pts[0].0,
            pts[pts.len() - 1].0,
            pts[0].1,
            pts[pts.len() - 1].1
        );
        if pts.len() < 3 || (o - nominal).abs() > 0.3 {
            failures.push(format!("{name}: order {o:.2} from {pts:?}"));
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

/// One step of every method is canonical: the symplectic defect ‖MᵀJM − J‖ of the AD Jacobian
/// `M` of the step map is ≤ 1e−13 at several phase points. Each step is a product of `m` exactly
/// symplectic sub-flow Jacobians, each rounded to ~ε relative; with |M| ≲ 10 the defect is
/// ≲ m·ε·|M|² ≈ 71·2.2e−16·10² ≈ 2e−12 as a worst case, and in practice the roundings are far
/// smaller (reported); 1e−13 is the bound asked for.
#[test]
fn every_step_is_canonical() {
    let pend = Pendulum::new(1.0).unwrap();
    let kep = Kepler2::new(1.0).unwrap();
    let mut worst: f64 = 0.0;
    for m in Splitting::all() {
        let name = OneStep::<Pendulum, 1>::name(&m);
        let mut w: f64 = 0.0;
        for (q, p) in [(1.0, 0.0), (-2.0, 0.7), (0.3, 1.9)] {
            let map = StepMap {
                system: &pend,
                method: &m,
                dt: 0.3,
            };
            let c = certify(&map, 0.0, &V::<1>::from([q]), &V::<1>::from([p])).unwrap();
            w = w.max(c.symplectic_defect);
        }
        for (q, p) in [
            ([0.5, 0.0], [0.0, 1.7]),
            ([1.0, 0.3], [-0.2, 0.9]),
            ([-0.7, 1.1], [0.6, 0.1]),
        ] {
            let map = StepMap {
                system: &kep,
                method: &m,
                dt: 0.1,
            };
            let c = certify(&map, 0.0, &V::<2>::from(q), &V::<2>::from(p)).unwrap();
            w = w.max(c.symplectic_defect);
        }
        println!("{name:34} defect {w:.1e}");
        assert!(w <= 1e-13, "{name}: {w:e}");
        worst = worst.max(w);
    }
    let (s, _, _, _) = j2_problem(0.01);
    for m in WisdomHolman::all() {
        let name = OneStep::<PlanarJ2, 2>::name(&m);
        let mut w: f64 = 0.0;
        let mut long: f64 = 0.0;
        for (q, p) in [
            ([0.5, 0.0], [0.0, 1.7]),
            ([1.0, 0.3], [-0.2, 0.9]),
            ([-0.7, 1.1], [0.6, 0.1]),
            ([2.0, 0.0], [0.0, 1.2]),
        ] {
            // dt = 0.1 and a long drift dt = 2.5 (a large fraction of the period).
            for dt in [0.1, 2.5] {
                let map = StepMap {
                    system: &s,
                    method: &m,
                    dt,
                };
                let c = certify(&map, 0.0, &V::<2>::from(q), &V::<2>::from(p)).unwrap();
                if dt == 0.1 {
                    w = w.max(c.symplectic_defect);
                } else {
                    // A step over 40% of the period through periapsis: |M| reaches ~5, and the
                    // rounding of m sub-flow Jacobians gives a defect ≲ 2·m·4ε·|M|²; checked
                    // against that bound, reported separately.
                    let mm = c.jacobian.max_abs();
                    let stages = m.table().sub_steps().len() as f64;
                    let bound = (8.0 * stages * f64::EPSILON * mm * mm).max(1e-13);
                    long = long.max(c.symplectic_defect);
                    assert!(
                        c.symplectic_defect <= bound,
                        "{name} dt = {dt}: {:e} > {bound:e} (|M| = {mm})",
                        c.symplectic_defect
                    );
                }
            }
        }
        println!("{name:34} defect {w:.1e} (dt = 0.1), {long:.1e} (dt = 2.5)");
        assert!(w <= 1e-13, "{name}: {w:e}");
        worst = worst.max(w);
    }
    println!("worst defect at the ordinary steps {worst:.1e}");
}

/// Wisdom–Holman against the general methods on the weakly perturbed problem (ε = 1e−4, e = 0.5,
/// one period) at equal error: the fewest force evaluations per period (AD gradients of
/// V = −μ/r + H₁ for the general methods, of H₁ alone for Wisdom–Holman, whose Kepler drifts are
/// counted apart as `flows`) on the budget grid 64·2^k, k = 0…6, that bring the error below 1e−7.
/// The full error table is printed: Wisdom–Holman wins by orders of magnitude at small budgets;
/// at ~2000 evaluations per period the ε²h² term of SABA_n/SBAB_n lets the 8th- and 10th-order
/// compositions overtake.
#[test]
fn wisdom_holman_beats_general_splitting_on_perturbed_kepler() {
    let eps = 1e-4;
    let (s, q0, p0, t1) = j2_problem(eps);
    let reference = j2_reference(eps);
    let target = 1e-7;
    let budgets: Vec<usize> = (0..7).map(|k| 64 << k).collect();
    // (name, kicks per step, is Wisdom–Holman)
    let mut rows: Vec<(String, (usize, usize), bool)> = Vec::new();
    for m in Splitting::all() {
        rows.push((m.table().label(), m.table().evaluations(), false));
    }
    for m in WisdomHolman::all() {
        rows.push((m.table().label(), m.table().evaluations(), true));
    }
    let general = Splitting::all();
    let wh = WisdomHolman::all();
    let run_one = |i: usize, n: usize| -> (f64, f64, usize, usize) {
        let clock = Instant::now();
        let pb = Problem::new(&s, 0.0, q0, p0, t1).unwrap();
        let r = if i < general.len() {
            integrate(&pb, &Fixed::new(general[i], n).unwrap(), &mut ()).unwrap()
        } else {
            integrate(&pb, &Fixed::new(wh[i - general.len()], n).unwrap(), &mut ()).unwrap()
        };
        let time = clock.elapsed().as_secs_f64();
        (
            err((r.last.q, r.last.p), reference),
            time,
            r.work.gradients,
            r.work.flows,
        )
    };
    let mut best: [(usize, String, f64, f64); 2] =
        std::array::from_fn(|_| (usize::MAX, String::new(), 0.0, 0.0)); // [general, WH]: (forces, name, error, time)
    println!(
        "{:34} {}",
        "forces per period →",
        budgets
            .iter()
            .map(|b| format!("{b:>8}"))
            .collect::<String>()
    );
    for (i, (name, (drifts, kicks), is_wh)) in rows.iter().enumerate() {
        let mut line = format!("{name:34} ");
        let mut reached = false;
        for &b in &budgets {
            let n = (b as f64 / *kicks as f64).round().max(1.0) as usize;
            let (e, time, gradients, flows) = run_one(i, n);
            if *is_wh {
                assert_eq!((gradients, flows), (n * kicks, n * drifts));
            } else {
                assert_eq!((gradients, flows), (n * (kicks + drifts), 0));
            }
            line += &format!(" {e:8.1e}");
            let forces = n * kicks;
            let slot = &mut best[*is_wh as usize];
            if !reached && e <= target {
                reached = true;
                if forces < slot.0 {
                    *slot = (forces, name.clone(), e, time);
                }
            }
        }
        println!("{line}");
    }
    println!(
        "error ≤ {target:e}: best general {} with {} forces ({:.1e}, {:.3} ms); best Wisdom–Holman {} with {} forces ({:.1e}, {:.3} ms)",
        best[0].1, best[0].0, best[0].2, best[0].3 * 1e3, best[1].1, best[1].0, best[1].2, best[1].3 * 1e3
    );
    assert!(best[1].0 < best[0].0, "{best:?}");
}

/// Gradient counts per step as documented: compositions s kicks + (s + 1) drifts; Verlet
/// drift–kick–drift one force evaluation per step.
#[test]
fn work_counts() {
    let pend = Pendulum::new(1.0).unwrap();
    let (q0, p0) = (V::<1>::from([1.0]), V::<1>::from([0.0]));
    let (_, _, g) = run(&pend, Splitting::VERLET_DKD, q0, p0, 1.0, 100);
    assert_eq!(g, 300);
    let (_, _, g) = run(&pend, Splitting::SOFRONIOU_SPALETTA35, q0, p0, 1.0, 10);
    assert_eq!(g, 10 * (35 + 36));
    let (s, q, p, t1) = j2_problem(1e-3);
    let pb = Problem::new(&s, 0.0, q, p, t1).unwrap();
    let r = integrate(&pb, &Fixed::new(WisdomHolman::SABA4, 10).unwrap(), &mut ()).unwrap();
    assert_eq!((r.work.gradients, r.work.flows), (40, 50));
}

/// Bad input gives typed errors.
#[test]
fn bad_input_is_rejected() {
    // Zero steps.
    assert!(matches!(
        Fixed::new(Splitting::KAHAN_LI17, 0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        Fixed::new(WisdomHolman::SABA2, 0),
        Err(Error::OutOfDomain { .. })
    ));
    // Non-finite state.
    let pend = Pendulum::new(1.0).unwrap();
    assert!(matches!(
        Problem::new(
            &pend,
            0.0,
            V::<1>::from([f64::NAN]),
            V::<1>::from([0.0]),
            1.0
        ),
        Err(Error::NonFinite { .. })
    ));
    let (s, _, p0, _) = j2_problem(1e-3);
    assert!(matches!(
        Problem::new(&s, 0.0, V::<2>::from([1.0, f64::INFINITY]), p0, 1.0),
        Err(Error::NonFinite { .. })
    ));
    // A start at the collision (q = 0): the vector field is singular there, so the run is refused
    // before the first Kepler drift (which refuses q = 0 too): a typed error, not a panic or NaN.
    let pb = Problem::new(&s, 0.0, V::<2>::zeros(), p0, 1.0).unwrap();
    let r = integrate(&pb, &Fixed::new(WisdomHolman::SABA1, 4).unwrap(), &mut ());
    assert!(matches!(r, Err(Error::NonFinite { .. })), "{r:?}");
    // A kick at the singularity of V (Kepler at rest at the origin) ends the run with NonFinite.
    let kep = Kepler2::new(1.0).unwrap();
    let pb = Problem::new(&kep, 0.0, V::<2>::zeros(), V::<2>::zeros(), 1.0).unwrap();
    let r = integrate(&pb, &Fixed::new(Splitting::VERLET_DKD, 4).unwrap(), &mut ());
    assert!(matches!(r, Err(Error::NonFinite { .. })), "{r:?}");
    // Invalid systems.
    assert!(PlanarJ2::conservative(0.0, J2::new(1.0, 1e-3, 1.0).unwrap()).is_err());
    assert!(J2::new(1.0, f64::NAN, 1.0).is_err());
}

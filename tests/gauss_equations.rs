//! Gauss's variational equations (modified equinoctial and classical elements) against
//! independent computations:
//!
//! * (a) the closed-form right-hand sides against the general variation-of-constants engine
//!   `ċ = (∂Ψ/∂c)⁻¹ g` [Ardema eqs. 18.5–18.10] applied to the element → state maps, by AD, at
//!   random points (circular, equatorial and hyperbolic ones included);
//! * (b) element integrations (RK4 + Richardson) against Cartesian DOP853 integrations of the
//!   same force, over ten orbits, from eccentric inclined and from circular equatorial starts;
//! * (c) secular rates derived in closed form (linear drag, transverse thrust);
//! * (d) typed errors for bad input and at the classical singularities.
//!
//! Tolerances are derived in the comments; measured numbers are printed (`--nocapture`).

use std::f64::consts::{PI, TAU};
use std::time::Instant;

use hamilton_jacobi::integrate::{integrate, Dop853, Problem};
use hamilton_jacobi::nalgebra::{SVector, Vector3};
use hamilton_jacobi::num_dual::Dual64;
use hamilton_jacobi::perturbation::forces::{
    ConstantThrust, LinearDrag, NoPotential, PerturbedTwoBody, Sum, ThrustFrame,
};
use hamilton_jacobi::perturbation::gauss_variational::{
    gauss_classical, gauss_modified_equinoctial, inertial_to_rtn, mee_from_blocks, mee_to_blocks,
    rtn_basis, rtn_to_inertial, ExponentialDrag, GaussClassical, GaussEquations,
};
use hamilton_jacobi::perturbation::ode::{rk4, rk4_richardson, ElementOde};
use hamilton_jacobi::perturbation::variation::{
    variation_of_constants_rhs, GeneralSolution, MomentumForce, Perturbation,
};
use hamilton_jacobi::systems::kepler::elements::{Classical, ModifiedEquinoctial};
use hamilton_jacobi::{DualNum, Error, Hamiltonian};

type V3 = Vector3<f64>;

/// Deterministic uniform numbers in [0, 1) (64-bit LCG, top 53 bits).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, a: f64, b: f64) -> f64 {
        a + (b - a) * self.next()
    }
}

fn nan3<D: DualNum<f64> + Copy>() -> (SVector<D, 3>, SVector<D, 3>) {
    let n = SVector::from_element(D::from(f64::NAN));
    (n, n)
}

fn lift3<D: DualNum<f64> + Copy>(x: &V3) -> SVector<D, 3> {
    SVector::from_fn(|i, _| D::from(x[i]))
}

// ---------------------------------------------------------------------------------------------
// The element → state maps as (time-independent) "general solutions" for the general
// variation-of-constants engine.
// ---------------------------------------------------------------------------------------------

/// `(p, f, g; h, k, L) ↦ (r, v)` of [`ModifiedEquinoctial::to_state`].
struct MeeMap(f64);
impl GeneralSolution<3> for MeeMap {
    fn state<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        a: &SVector<D, 3>,
        b: &SVector<D, 3>,
    ) -> (SVector<D, 3>, SVector<D, 3>) {
        mee_from_blocks(a, b)
            .to_state(self.0)
            .unwrap_or_else(|_| nan3())
    }
}

/// `(a, e, i; Ω, ω, M) ↦ (r, v)` of [`Classical::to_state`].
struct ClassicalMap(f64);
impl GeneralSolution<3> for ClassicalMap {
    fn state<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        a: &SVector<D, 3>,
        b: &SVector<D, 3>,
    ) -> (SVector<D, 3>, SVector<D, 3>) {
        Classical {
            a: a[0],
            e: a[1],
            i: a[2],
            raan: b[0],
            argp: b[1],
            mean_anomaly: b[2],
        }
        .to_state(self.0)
        .unwrap_or_else(|_| nan3())
    }
}

/// The perturbation `g = (0, a_d)` with `a_d` given by its RTN components.
struct RtnPerturbation(V3);
impl Perturbation<3> for RtnPerturbation {
    fn perturbation<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        r: &SVector<D, 3>,
        v: &SVector<D, 3>,
    ) -> (SVector<D, 3>, SVector<D, 3>) {
        let a = rtn_to_inertial(r, v, &lift3(&self.0)).unwrap_or_else(|_| nan3().0);
        (SVector::zeros(), a)
    }
}

/// The Kepler field `g = (v, −μr/|r|³)`: with it the engine returns the unperturbed element
/// rates of a time-independent element map.
struct KeplerField(f64);
impl Perturbation<3> for KeplerField {
    fn perturbation<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        r: &SVector<D, 3>,
        v: &SVector<D, 3>,
    ) -> (SVector<D, 3>, SVector<D, 3>) {
        let r2 = r.dot(r);
        (*v, r * (-(r2 * r2.sqrt()).recip() * self.0))
    }
}

fn max_abs6(x: &(V3, V3)) -> f64 {
    x.0.amax().max(x.1.amax())
}

fn diff6(x: &(V3, V3), y: &(V3, V3)) -> f64 {
    (x.0 - y.0).amax().max((x.1 - y.1).amax())
}

/// A random modified-equinoctial point: `μ ∈ [0.5, 2]`, `p ∈ [0.3, 3]`, `e` exactly 0 in every
/// fourth case, otherwise in `[0, 0.95]` (elliptic) or `[1.05, 3]` (hyperbolic, every fifth case,
/// with `ν` well inside the asymptotes), `i` exactly 0 in every third case, otherwise in
/// `[0, 2.6]`.
fn random_mee(rng: &mut Lcg, case: usize) -> (f64, ModifiedEquinoctial) {
    let mu = rng.range(0.5, 2.0);
    let p = rng.range(0.3, 3.0);
    let hyperbolic = case % 5 == 4;
    let e = if case.is_multiple_of(4) {
        0.0
    } else if hyperbolic {
        rng.range(1.05, 3.0)
    } else {
        rng.range(0.0, 0.95)
    };
    let i = if case.is_multiple_of(3) {
        0.0
    } else {
        rng.range(0.0, 2.6)
    };
    let (varpi, raan) = (rng.range(-PI, PI), rng.range(-PI, PI));
    let nu = if e > 1.0 {
        // |ν| < 0.8 acos(−1/e): w = 1 + e cos ν stays ≥ 1 + e cos(0.8 ν_∞) > 0.
        0.8 * (-1.0 / e).acos() * rng.range(-1.0, 1.0)
    } else {
        rng.range(-PI, PI)
    };
    let t = (0.5 * i).tan();
    let el = ModifiedEquinoctial::new(
        p,
        e * varpi.cos(),
        e * varpi.sin(),
        t * raan.cos(),
        t * raan.sin(),
        varpi + nu,
    )
    .unwrap();
    (mu, el)
}

// ---------------------------------------------------------------------------------------------
// (a) closed form against the AD engine
// ---------------------------------------------------------------------------------------------

/// Perturbation part: `gauss_modified_equinoctial(…, (R, T, N)) − (0, …, 0, √(μp)(w/p)²)` against
/// `(∂Ψ/∂c)⁻¹ (0, R r̂ + T t̂ + N n̂)` at 400 random points.
///
/// Tolerance: the engine solves with the LU of `∂Ψ/∂c`, whose error is `κ ε` relative to the
/// solution's norm; κ of the equilibrated Jacobian is ≲ 10³ at these points (p ∈ [0.3, 3],
/// `tan(i/2) ≤ 3`, `e ≤ 3`), and the closed form rounds in a few ulps, so `5·10⁻¹²` of the
/// largest rate component (of order `√(p/μ)|a_d|`) bounds both.
#[test]
fn modified_equinoctial_rhs_equals_ad_engine() {
    let mut rng = Lcg(0x6a055);
    let mut worst: f64 = 0.0;
    let mut worst_kepler: f64 = 0.0;
    let (mut n_circ, mut n_eq, mut n_hyp) = (0, 0, 0);
    for case in 0..400 {
        let (mu, el) = random_mee(&mut rng, case);
        let a_rtn = V3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        let (c1, c2) = mee_to_blocks(&el);
        let ad = variation_of_constants_rhs(&MeeMap(mu), &RtnPerturbation(a_rtn), 0.0, &c1, &c2)
            .unwrap();
        let mut closed = gauss_modified_equinoctial(mu, &el, &a_rtn).unwrap();
        let w = 1.0 + el.f * el.l.cos() + el.g * el.l.sin();
        let kepler_l = (mu * el.p).sqrt() * (w / el.p) * (w / el.p);
        closed.l -= kepler_l;
        let closed = mee_to_blocks(&closed);
        let rel = diff6(&closed, &ad) / max_abs6(&ad);
        worst = worst.max(rel);
        assert!(
            rel < 5e-12,
            "case {case}: {el:?} {a_rtn:?}: {closed:?} vs {ad:?} ({rel:e})"
        );

        // Kepler part: the engine with g = (v, −μr/r³) gives (0, 0, 0, 0, 0, √(μp)(w/p)²).
        let kep = variation_of_constants_rhs(&MeeMap(mu), &KeplerField(mu), 0.0, &c1, &c2).unwrap();
        let zero = mee_to_blocks(&gauss_modified_equinoctial(mu, &el, &V3::zeros()).unwrap());
        assert_eq!(zero.0, V3::zeros());
        assert_eq!((zero.1[0], zero.1[1]), (0.0, 0.0));
        let relk = diff6(&kep, &zero) / kepler_l;
        worst_kepler = worst_kepler.max(relk);
        assert!(relk < 5e-12, "case {case}: Kepler part {kep:?} vs {zero:?}");
        let e = el.eccentricity();
        n_circ += usize::from(e == 0.0);
        n_eq += usize::from(el.h == 0.0 && el.k == 0.0);
        n_hyp += usize::from(e > 1.0);
    }
    println!(
        "MEE Gauss vs AD engine, 400 points ({n_circ} with e = 0, {n_eq} with i = 0, {n_hyp} \
         hyperbolic): max rel. diff perturbation part {worst:.2e}, Kepler part {worst_kepler:.2e}"
    );
}

/// Gauss's planetary equations (classical elements, full rates including `Ṁ = n + …`) against
/// `(∂Ψ/∂c)⁻¹ (v, −μr/r³ + a_d)` of the classical element map, at 300 random elliptic points
/// with `e ∈ [0.05, 0.9]`, `i ∈ [0.1, 3.0]`.
///
/// Tolerance: as above, with κ of the classical Jacobian growing like `1/e` and `1/sin i`
/// (≲ 20 · 10³ here), and the eccentric-anomaly solve inside the map; `10⁻¹⁰` of the largest
/// rate, compared separately for the perturbation part (Kepler field off) and the full rates.
#[test]
fn classical_rhs_equals_ad_engine() {
    let mut rng = Lcg(0xc1a55);
    let (mut worst, mut worst_full): (f64, f64) = (0.0, 0.0);
    for case in 0..300 {
        let mu = rng.range(0.5, 2.0);
        let el = Classical::new(
            rng.range(0.5, 3.0),
            rng.range(0.05, 0.9),
            rng.range(0.1, 3.0),
            rng.range(-PI, PI),
            rng.range(-PI, PI),
            rng.range(-PI, PI),
        )
        .unwrap();
        let a_rtn = V3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        let c1 = V3::new(el.a, el.e, el.i);
        let c2 = V3::new(el.raan, el.argp, el.mean_anomaly);
        let ad =
            variation_of_constants_rhs(&ClassicalMap(mu), &RtnPerturbation(a_rtn), 0.0, &c1, &c2)
                .unwrap();
        let d = gauss_classical(mu, &el, &a_rtn).unwrap();
        let n = (mu / el.a.powi(3)).sqrt();
        let closed = (
            V3::new(d.a, d.e, d.i),
            V3::new(d.raan, d.argp, d.mean_anomaly - n),
        );
        let rel = diff6(&closed, &ad) / max_abs6(&ad);
        worst = worst.max(rel);
        assert!(
            rel < 1e-10,
            "case {case}: {el:?}: {closed:?} vs {ad:?} ({rel:e})"
        );

        struct Full(f64, V3);
        impl Perturbation<3> for Full {
            fn perturbation<D: DualNum<f64> + Copy>(
                &self,
                t: D,
                r: &SVector<D, 3>,
                v: &SVector<D, 3>,
            ) -> (SVector<D, 3>, SVector<D, 3>) {
                let (a, b) = KeplerField(self.0).perturbation(t, r, v);
                let (_, c) = RtnPerturbation(self.1).perturbation(t, r, v);
                (a, b + c)
            }
        }
        let full =
            variation_of_constants_rhs(&ClassicalMap(mu), &Full(mu, a_rtn), 0.0, &c1, &c2).unwrap();
        let closed_full = (
            V3::new(d.a, d.e, d.i),
            V3::new(d.raan, d.argp, d.mean_anomaly),
        );
        let relf = diff6(&closed_full, &full) / max_abs6(&full);
        worst_full = worst_full.max(relf);
        assert!(
            relf < 1e-10,
            "case {case}: full rates {closed_full:?} vs {full:?}"
        );
    }
    println!(
        "classical Gauss vs AD engine, 300 points: max rel. diff perturbation part {worst:.2e}, \
         full rates {worst_full:.2e}"
    );
}

/// The full chain elements → state → force → RTN → rates in dual numbers: the real part equals
/// the `f64` evaluation to a few ulps, and the derivative with respect to `L` agrees with a central
/// difference (step `10⁻⁵`: truncation `O(h²) ≈ 10⁻¹⁰`, rounding `ε/h ≈ 10⁻¹¹`, so `10⁻⁸`
/// relative of the largest derivative is safe).
#[test]
fn rates_are_differentiable() {
    let mu = 1.3;
    let force = Sum(
        ExponentialDrag::new(0.2, 1.0, 0.1, 0.5, 0.05).unwrap(),
        ConstantThrust::new(V3::new(0.0, 1e-2, 0.0), ThrustFrame::Rtn).unwrap(),
    );
    let eqs = GaussEquations::new(mu, force).unwrap();
    let el = ModifiedEquinoctial::new(1.1, 0.1, -0.05, 0.2, -0.1, 0.7).unwrap();
    let t = 0.3;
    let f64_rates = eqs.rates(t, &el).unwrap();
    let eld = ModifiedEquinoctial {
        p: Dual64::from(el.p),
        f: Dual64::from(el.f),
        g: Dual64::from(el.g),
        h: Dual64::from(el.h),
        k: Dual64::from(el.k),
        l: Dual64::from(el.l).derivative(),
    };
    let dual = eqs.rates(Dual64::from(t), &eld).unwrap();
    let h = 1e-5;
    let plus = eqs
        .rates(t, &ModifiedEquinoctial { l: el.l + h, ..el })
        .unwrap();
    let minus = eqs
        .rates(t, &ModifiedEquinoctial { l: el.l - h, ..el })
        .unwrap();
    let (d0, d1) = mee_to_blocks(&dual);
    let (f0, f1) = mee_to_blocks(&f64_rates);
    let (p0, p1) = mee_to_blocks(&plus);
    let (m0, m1) = mee_to_blocks(&minus);
    let mut scale: f64 = 0.0;
    let mut err: f64 = 0.0;
    // Same formulas; dual division may round differently from f64 division in the last bit, and
    // components that cancel (k̇ here) carry that rounding of the larger terms: compare against
    // 16 ε of the largest perturbation rate (L̇ excluded: its Kepler part is ~10³ times larger).
    let pert_scale = f0.amax().max(f1[0].abs()).max(f1[1].abs());
    for j in 0..3 {
        assert!((d0[j].re - f0[j]).abs() <= 16.0 * f64::EPSILON * pert_scale);
        assert!((d1[j].re - f1[j]).abs() <= 16.0 * f64::EPSILON * f1.amax());
        for (d, p, m) in [(d0[j], p0[j], m0[j]), (d1[j], p1[j], m1[j])] {
            scale = scale.max(d.eps.abs());
            err = err.max((d.eps - (p - m) / (2.0 * h)).abs());
        }
    }
    println!("∂(rates)/∂L: AD vs central difference, max abs diff {err:.2e} (scale {scale:.2e})");
    assert!(err < 1e-8 * scale);
}

// ---------------------------------------------------------------------------------------------
// (b) element integration against Cartesian integration
// ---------------------------------------------------------------------------------------------

struct Comparison {
    /// Position of each integration against DOP853 at the smallest tolerance it accepts
    /// (`rtol = 10u = 2.3·10⁻¹⁵`), relative.
    gauss_vs_ref: f64,
    dop_vs_ref: f64,
    dr: f64,
    dv: f64,
    richardson: f64,
    rk4_evals: usize,
    dop_evals: usize,
    rk4_ms: f64,
    dop_ms: f64,
    final_el: ModifiedEquinoctial,
}

/// Integrate Gauss's equations (RK4 + Richardson, `steps` coarse steps) and the Cartesian system
/// (DOP853, `rtol = atol = 10⁻¹³`) from the same elements to `t₁`; relative differences of the
/// final position and velocity.
fn compare<F: MomentumForce<3> + Copy>(
    mu: f64,
    force: F,
    el0: &ModifiedEquinoctial,
    t1: f64,
    steps: usize,
) -> Comparison {
    let eqs = GaussEquations::new(mu, force).unwrap();
    let (a0, b0) = mee_to_blocks(el0);
    let clock = Instant::now();
    let rich = rk4_richardson(&eqs, 0.0, &a0, &b0, t1, steps).unwrap();
    let rk4_ms = clock.elapsed().as_secs_f64() * 1e3;
    let final_el = mee_from_blocks(&rich.y.0, &rich.y.1);
    let (rg, vg) = final_el.to_state(mu).unwrap();

    let sys = PerturbedTwoBody::with_force(mu, NoPotential, force).unwrap();
    let (r0, v0) = el0.to_state(mu).unwrap();
    let problem = Problem::new(&sys, 0.0, r0, v0, t1).unwrap();
    let clock = Instant::now();
    let rep = integrate(&problem, &Dop853::new(1e-13, 1e-13).unwrap(), &mut ()).unwrap();
    let dop_ms = clock.elapsed().as_secs_f64() * 1e3;
    let reference = integrate(
        &problem,
        &Dop853::new(Dop853::RTOL_MIN, 1e-15).unwrap(),
        &mut (),
    )
    .unwrap();
    let rn = reference.last.q.norm();
    Comparison {
        gauss_vs_ref: (rg - reference.last.q).norm() / rn,
        dop_vs_ref: (rep.last.q - reference.last.q).norm() / rn,
        dr: (rg - rep.last.q).norm() / rep.last.q.norm(),
        dv: (vg - rep.last.p).norm() / rep.last.p.norm(),
        richardson: rich.max_error(),
        rk4_evals: rich.evaluations,
        dop_evals: rep.work.gradients,
        rk4_ms,
        dop_ms,
        final_el,
    }
}

/// Ten orbits (`μ = 1`, `a ≈ 1`, `t₁ = 20π`) for drag and thrust, eccentric inclined and
/// circular equatorial starts.
///
/// Tolerance: the two integrations are independent; the difference is bounded by their global
/// errors. DOP853 at `rtol = 10⁻¹³` over ~3000 steps accumulates at most ~`10⁻¹⁰` relative
/// (the along-track error grows linearly, `≈ steps · rtol`). The Richardson-extrapolated RK4
/// value is better than its own estimate for `y_{h/2}` (printed, `≲ 10⁻¹⁰` with the step counts
/// chosen: `h = T/400` to `T/1000` where `e` is large, error `∝ (nh)⁴ (1 + e)⁴/(1 − e)⁶`). With
/// `|L̇| ≈ n = 1` a phase error `δL` is a position error `δL` relative, so `10⁻⁹` bounds both
/// integrators with a factor ≈ 2 to spare. A third run, DOP853 at its smallest tolerance
/// (`rtol = 2.3·10⁻¹⁵`, global error ≲ `10⁻¹²` by the same count), separates the two: the
/// element integration must be within `10⁻¹⁰` of it (its Richardson estimate, `≤ 2·10⁻¹⁰`
/// asserted, bounds the error of the unextrapolated `y_{h/2}`; the extrapolated value is better).
#[test]
fn gauss_integration_matches_cartesian() {
    let mu = 1.0;
    let t1 = 10.0 * TAU;
    let eccentric = ModifiedEquinoctial::new(
        0.91,
        0.3 * 0.4f64.cos(),
        0.3 * 0.4f64.sin(),
        0.25f64.tan() * 1.1f64.cos(),
        0.25f64.tan() * 1.1f64.sin(),
        0.2,
    )
    .unwrap();
    let circular_equatorial = ModifiedEquinoctial::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0).unwrap();
    let slightly_eccentric =
        ModifiedEquinoctial::new(0.99, 0.1, 0.0, 0.1 * 0.3f64.cos(), 0.1 * 0.3f64.sin(), 1.0)
            .unwrap();
    let linear = LinearDrag::new(1e-3).unwrap();
    // ρ₀B/2 = 2.5·10⁻⁴ at r₀ = 0.9 (the perigee of the e = 0.1 orbit), scale height 0.05:
    // |a_d| ≈ 3·10⁻⁴ at perigee, decaying by e^{−2} = 0.14 per 0.1 of altitude.
    let expdrag = ExponentialDrag::new(0.005, 0.9, 0.05, 0.1, 0.02).unwrap();
    let thrust_t = ConstantThrust::new(V3::new(0.0, 1e-3, 0.0), ThrustFrame::Rtn).unwrap();
    let thrust_i = ConstantThrust::new(V3::new(3e-4, -5e-4, 8e-4), ThrustFrame::Inertial).unwrap();

    println!("| case | steps | |Δr|/|r| | |Δv|/|v| | Gauss vs ref | DOP853 vs ref | Richardson est. | RK4 evals | DOP853 evals | RK4 ms | DOP853 ms | e₁ | i₁ |");
    println!("|---|---|---|---|---|---|---|---|---|---|---|---|---|");
    let run = |name: &str, c: Comparison, steps: usize| {
        let i1 = 2.0 * c.final_el.h.hypot(c.final_el.k).atan();
        println!(
            "| {name} | {steps} | {:.2e} | {:.2e} | {:.2e} | {:.2e} | {:.2e} | {} | {} | {:.1} | {:.1} | {:.3e} | {:.3e} |",
            c.dr,
            c.dv,
            c.gauss_vs_ref,
            c.dop_vs_ref,
            c.richardson,
            c.rk4_evals,
            c.dop_evals,
            c.rk4_ms,
            c.dop_ms,
            c.final_el.eccentricity(),
            i1
        );
        assert!(
            c.richardson < 2e-10,
            "{name}: Richardson estimate {:e}",
            c.richardson
        );
        assert!(c.dr < 1e-9 && c.dv < 1e-9, "{name}: {:e} {:e}", c.dr, c.dv);
        assert!(
            c.gauss_vs_ref < 1e-10,
            "{name}: Gauss vs reference {:e}",
            c.gauss_vs_ref
        );
        assert!(
            c.dop_vs_ref < 1e-9,
            "{name}: DOP853 vs reference {:e}",
            c.dop_vs_ref
        );
    };
    run(
        "linear drag, e=0.3, i=0.5",
        compare(mu, linear, &eccentric, t1, 10_000),
        10_000,
    );
    run(
        "exp. drag, e=0.1, i=0.2",
        compare(mu, expdrag, &slightly_eccentric, t1, 4_000),
        4_000,
    );
    run(
        "linear drag, e=0, i=0",
        compare(mu, linear, &circular_equatorial, t1, 4_000),
        4_000,
    );
    run(
        "T thrust, e=0, i=0",
        compare(mu, thrust_t, &circular_equatorial, t1, 4_000),
        4_000,
    );
    run(
        "inertial thrust, e=0, i=0",
        compare(mu, thrust_i, &circular_equatorial, t1, 4_000),
        4_000,
    );
    run(
        "T thrust + exp. drag, e=0.3, i=0.5",
        compare(mu, Sum(thrust_t, expdrag), &eccentric, t1, 10_000),
        10_000,
    );
}

/// From the circular equatorial start the classical equations are refused at the first
/// evaluation, while the modified equinoctial ones run (above).
#[test]
fn classical_equations_fail_at_circular_equatorial_start() {
    let eqs = GaussClassical::new(
        1.0,
        ConstantThrust::new(V3::new(0.0, 1e-3, 0.0), ThrustFrame::Rtn).unwrap(),
    )
    .unwrap();
    let circ = (V3::new(1.0, 0.0, 0.0), V3::new(0.0, 0.0, 0.0));
    let err = rk4(&eqs, 0.0, &circ.0, &circ.1, 1.0, 10).unwrap_err();
    assert!(matches!(err, Error::Singular { .. }), "{err}");
    println!("classical Gauss at e = 0, i = 0: {err}");
    // e > 0 but i = 0: still refused (1/sin i).
    let eq = (V3::new(1.0, 0.1, 0.0), V3::new(0.0, 0.0, 0.0));
    let err = rk4(&eqs, 0.0, &eq.0, &eq.1, 1.0, 10).unwrap_err();
    assert!(matches!(err, Error::Singular { .. }), "{err}");
    // Away from the singularities they agree with the modified equinoctial integration: one
    // orbit of transverse thrust from e = 0.2, i = 0.4 (same state at the end to 10⁻⁹).
    let mu = 1.0;
    let el = Classical::new(1.0, 0.2, 0.4, 0.3, 0.7, 0.1).unwrap();
    let (c1, c2) = (
        V3::new(el.a, el.e, el.i),
        V3::new(el.raan, el.argp, el.mean_anomaly),
    );
    let rc = rk4_richardson(&eqs, 0.0, &c1, &c2, TAU, 1000).unwrap();
    let elc = Classical {
        a: rc.y.0[0],
        e: rc.y.0[1],
        i: rc.y.0[2],
        raan: rc.y.1[0],
        argp: rc.y.1[1],
        mean_anomaly: rc.y.1[2],
    };
    let (rc_r, _) = elc.to_state(mu).unwrap();
    let mee = el.to_modified_equinoctial().unwrap();
    let (a0, b0) = mee_to_blocks(&mee);
    let eqm = GaussEquations::new(
        mu,
        ConstantThrust::new(V3::new(0.0, 1e-3, 0.0), ThrustFrame::Rtn).unwrap(),
    )
    .unwrap();
    let rm = rk4_richardson(&eqm, 0.0, &a0, &b0, TAU, 1000).unwrap();
    let (rm_r, _) = mee_from_blocks(&rm.y.0, &rm.y.1).to_state(mu).unwrap();
    let d = (rc_r - rm_r).norm();
    println!("classical vs MEE Gauss after one orbit (e = 0.2, i = 0.4): |Δr| = {d:.2e}");
    assert!(d < 1e-9);
}

// ---------------------------------------------------------------------------------------------
// (c) secular rates
// ---------------------------------------------------------------------------------------------

/// Linear drag `−k v`. Exactly (for every orbit) `ḣ = −k h`, so `p = p₀ e^{−2kt}`; on a circular
/// orbit Gauss's equations give `ȧ = −2ka` (`T = −k√(μ/a)`, `ȧ = 2a^{3/2}T/√μ`). The drag excites
/// `f, g` with amplitude `≈ 2k/n`, so the osculating `a = p/(1 − e²)` differs from
/// `a₀e^{−2kt}` by `O((2k/n)²)` relative; over `t₁ = 20π` the averaged rate
/// `ln(a₁/a₀)/t₁` differs from `−2k` by at most `(2k/n)²/t₁`.
#[test]
fn linear_drag_decay_rate() {
    let (mu, k) = (1.0, 1e-4);
    let eqs = GaussEquations::new(mu, LinearDrag::new(k).unwrap()).unwrap();
    let el0 = ModifiedEquinoctial::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.0).unwrap();
    // Instantaneous: ȧ = ṗ (e = 0) = −2kp.
    let r0 = eqs.rates(0.0, &el0).unwrap();
    assert!((r0.p + 2.0 * k).abs() < 1e-18, "{}", r0.p);
    let (a0, b0) = mee_to_blocks(&el0);
    let t1 = 10.0 * TAU;
    let rich = rk4_richardson(&eqs, 0.0, &a0, &b0, t1, 4000).unwrap();
    let el1 = mee_from_blocks(&rich.y.0, &rich.y.1);
    let e1 = el1.eccentricity();
    let a1 = el1.p / ((1.0 - e1) * (1.0 + e1));
    let rate = (a1 / 1.0).ln() / t1;
    let p_exact = (-2.0 * k * t1).exp();
    println!(
        "linear drag k = {k:e}: averaged ȧ/a = {rate:.10e} (−2k = {:.10e}, rel. diff {:.2e}); \
         p₁/p₀e^(−2kt) − 1 = {:.2e}; e₁ = {e1:.2e} (2k/n = {:.1e})",
        -2.0 * k,
        (rate + 2.0 * k).abs() / (2.0 * k),
        el1.p / p_exact - 1.0,
        2.0 * k
    );
    assert!((el1.p / p_exact - 1.0).abs() < 1e-12);
    assert!(e1 < 3.0 * k);
    assert!((rate + 2.0 * k).abs() <= (2.0 * k).powi(2) / t1 + 1e-13);
}

/// Constant transverse thrust `T` on a circular orbit: `ȧ = 2a^{3/2}T/√μ`, so
/// `a^{−1/2}(t) = a₀^{−1/2} − T t/√μ`. The thrust excites `e ≈ 2T/(n²a)`, so the osculating
/// `a` deviates by `O(e²)`; the secular law also neglects the `O(e)` correction of `ȧ`, which
/// averages out over whole orbits to `O(e²)`. With `T = 10⁻⁵`: predicted
/// `Δ(a^{−1/2}) = 6.3·10⁻⁴` over 10 orbits, reproduced to `10⁻⁹` absolute (≈ `10⁻⁶` relative).
#[test]
fn transverse_thrust_rate() {
    let (mu, thrust) = (1.0, 1e-5);
    let eqs = GaussEquations::new(
        mu,
        ConstantThrust::new(V3::new(0.0, thrust, 0.0), ThrustFrame::Rtn).unwrap(),
    )
    .unwrap();
    let el0 = ModifiedEquinoctial::new(1.0, 0.0, 0.0, 0.0, 0.0, 0.3).unwrap();
    let r0 = eqs.rates(0.0, &el0).unwrap();
    assert!((r0.p - 2.0 * thrust).abs() < 1e-18);
    let (a0, b0) = mee_to_blocks(&el0);
    let t1 = 10.0 * TAU;
    let rich = rk4_richardson(&eqs, 0.0, &a0, &b0, t1, 4000).unwrap();
    let el1 = mee_from_blocks(&rich.y.0, &rich.y.1);
    let e1 = el1.eccentricity();
    let a1 = el1.p / ((1.0 - e1) * (1.0 + e1));
    let predicted = 1.0 - thrust * t1 / mu.sqrt();
    let got = a1.powf(-0.5);
    let rate_avg = (a1 - 1.0) / t1;
    println!(
        "transverse thrust T = {thrust:e}: a^(−1/2) = {got:.12} (predicted {predicted:.12}, \
         diff {:.2e}); averaged ȧ = {rate_avg:.6e} vs 2a^(3/2)T/√μ at a₀ = {:.6e}; e₁ = {e1:.2e}",
        got - predicted,
        2.0 * thrust
    );
    assert!((got - predicted).abs() < 1e-9);
}

// ---------------------------------------------------------------------------------------------
// (d) typed errors
// ---------------------------------------------------------------------------------------------

#[test]
fn bad_input_is_refused_with_typed_errors() {
    let el = ModifiedEquinoctial {
        p: 1.0,
        f: 0.1,
        g: 0.0,
        h: 0.0,
        k: 0.0,
        l: 0.0,
    };
    let a = V3::new(0.0, 1e-3, 0.0);
    assert!(matches!(
        gauss_modified_equinoctial(0.0, &el, &a),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        gauss_modified_equinoctial(f64::NAN, &el, &a),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        gauss_modified_equinoctial(1.0, &ModifiedEquinoctial { p: -1.0, ..el }, &a),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        gauss_modified_equinoctial(1.0, &ModifiedEquinoctial { f: f64::NAN, ..el }, &a),
        Err(Error::NonFinite { .. })
    ));
    // A hyperbola (e = 2) at ν = π: beyond the asymptotes (w = −1).
    assert!(matches!(
        gauss_modified_equinoctial(
            1.0,
            &ModifiedEquinoctial {
                f: 2.0,
                l: PI,
                ..el
            },
            &a
        ),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        gauss_modified_equinoctial(1.0, &el, &V3::new(f64::INFINITY, 0.0, 0.0)),
        Err(Error::NonFinite { .. })
    ));

    // Classical: singular at e = 0, i = 0, i = π; elliptic only.
    let c = Classical::new(1.0, 0.2, 0.4, 0.0, 0.0, 0.0).unwrap();
    for bad in [
        Classical { e: 0.0, ..c },
        Classical { e: 1e-16, ..c },
        Classical { i: 0.0, ..c },
        Classical { i: PI, ..c },
    ] {
        let err = gauss_classical(1.0, &bad, &a).unwrap_err();
        assert!(matches!(err, Error::Singular { .. }), "{bad:?}: {err}");
    }
    assert!(matches!(
        gauss_classical(
            1.0,
            &Classical {
                a: -1.0,
                e: 1.5,
                ..c
            },
            &a
        ),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        gauss_classical(1.0, &Classical { a: -1.0, ..c }, &a),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        gauss_classical(1.0, &c, &V3::new(0.0, f64::NAN, 0.0)),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        gauss_classical(-1.0, &c, &a),
        Err(Error::OutOfDomain { .. })
    ));

    // RTN frame undefined at r = 0 and for rectilinear motion.
    let z = V3::zeros();
    let r = V3::new(1.0, 0.0, 0.0);
    assert!(matches!(rtn_basis(&z, &r), Err(Error::InvalidInput { .. })));
    assert!(matches!(
        rtn_basis(&r, &(r * 2.0)),
        Err(Error::InvalidInput { .. })
    ));
    assert!(matches!(
        inertial_to_rtn(&r, &V3::new(0.0, 1.0, 0.0), &V3::new(f64::NAN, 0.0, 0.0)),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        rtn_basis(&r, &V3::new(0.0, f64::NAN, 0.0)),
        Err(Error::NonFinite { .. })
    ));

    // Force-model parameters.
    assert!(matches!(
        LinearDrag::new(-1.0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        LinearDrag::new(f64::NAN),
        Err(Error::NonFinite { .. })
    ));
    assert!(ExponentialDrag::new(-1.0, 1.0, 1.0, 1.0, 0.0).is_err());
    assert!(ExponentialDrag::new(1.0, 0.0, 1.0, 1.0, 0.0).is_err());
    assert!(ExponentialDrag::new(1.0, 1.0, 0.0, 1.0, 0.0).is_err());
    assert!(ExponentialDrag::new(1.0, 1.0, 1.0, -1.0, 0.0).is_err());
    assert!(ExponentialDrag::new(1.0, 1.0, 1.0, 1.0, f64::INFINITY).is_err());
    assert!(matches!(
        ConstantThrust::new(V3::new(0.0, f64::NAN, 0.0), ThrustFrame::Rtn),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        ConstantThrust::new(V3::new(0.0, f64::NAN, 0.0), ThrustFrame::Inertial),
        Err(Error::NonFinite { .. })
    ));
    assert!(GaussEquations::new(0.0, LinearDrag::new(1.0).unwrap()).is_err());
    assert!(GaussClassical::new(-2.0, LinearDrag::new(1.0).unwrap()).is_err());
    assert!(PerturbedTwoBody::<_, _, 3>::with_force(
        f64::NAN,
        NoPotential,
        LinearDrag::new(1.0).unwrap()
    )
    .is_err());

    // Element ODE: out-of-domain elements and a force that is NaN (transverse thrust needs the
    // RTN frame; the Cartesian system reports the NaN through the checked vector field).
    let eqs = GaussEquations::new(1.0, LinearDrag::new(1e-3).unwrap()).unwrap();
    assert!(matches!(
        eqs.rhs(0.0, &V3::new(0.0, 0.0, 0.0), &V3::zeros()),
        Err(Error::OutOfDomain { .. })
    ));
    let cart = PerturbedTwoBody::with_force(
        1.0,
        NoPotential,
        ConstantThrust::new(V3::new(0.0, 1e-3, 0.0), ThrustFrame::Rtn).unwrap(),
    )
    .unwrap();
    assert!(matches!(
        cart.vector_field(0.0, &r, &(r * 0.5)),
        Err(Error::NonFinite { .. })
    ));
}

/// The RTN helpers are inverse to each other and the frame is right-handed and orthonormal.
#[test]
fn rtn_round_trip() {
    let mut rng = Lcg(0x47e);
    for _ in 0..100 {
        let r = V3::new(
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
        );
        let v = V3::new(
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
            rng.range(-2.0, 2.0),
        );
        let a = V3::new(
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
            rng.range(-1.0, 1.0),
        );
        let [rh, th, nh] = rtn_basis(&r, &v).unwrap();
        assert!((rh.cross(&th) - nh).amax() < 1e-15);
        assert!(rh.dot(&th).abs() < 1e-15 && th.dot(&nh).abs() < 1e-15);
        assert!(v.dot(&th) > 0.0, "t̂ points along the transverse velocity");
        let back = rtn_to_inertial(&r, &v, &inertial_to_rtn(&r, &v, &a).unwrap()).unwrap();
        assert!((back - a).amax() < 4e-16 * a.amax().max(1.0) * 4.0);
    }
}

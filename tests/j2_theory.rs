//! Brouwer–Lyddane `J₂` theory ([`BrouwerLyddane`]) against the truth: DOP853 on the same force
//! model `q̈ = −μq/|q|³ − ∇U_{J₂}` in Encke's form (the deviation from the Kepler orbit of the
//! current state, rectified at every sample), run at two tolerances. The problem of the brief:
//! `a = 2`, `i = 0.5`, `R = μ = 1`, 100 orbits, `e = 0.1` and `e = 0.7`.
//!
//! (tests/oracles/j2_encke.rs; Cowell's form is not accurate enough for the `J₂ = 10⁻⁶` targets).
//!
//! Measured numbers are printed (`--nocapture`).

use hamilton_jacobi::nalgebra::Vector3;
use hamilton_jacobi::num_dual::Dual64;
use hamilton_jacobi::perturbation::brouwer::{
    brouwer_secular_rates, mean_to_osculating, osculating_to_mean, BrouwerLyddane, MeanAxis,
    TheoryWarning, CRITICAL_INCLINATION_DISTANCE, MAX_SMALL_PARAMETER,
};
use hamilton_jacobi::perturbation::forces::J2;
use hamilton_jacobi::perturbation::kepler_variation::j2_secular_rates;
use hamilton_jacobi::systems::kepler::elements::Classical;
use hamilton_jacobi::Error;
use std::f64::consts::TAU;

#[path = "oracles/j2_encke.rs"]
mod encke;

type V3 = Vector3<f64>;
const MU: f64 = 1.0;
const RADIUS: f64 = 1.0;

/// The truth at `rtol` (tests/oracles/j2_encke.rs).
fn truth(j2: f64, start: (V3, V3), times: &[f64], rtol: f64) -> Vec<V3> {
    encke::truth(J2::new(MU, j2, RADIUS).unwrap(), start, times, rtol)
}

fn initial(e: f64) -> Classical {
    Classical::new(2.0, e, 0.5, 0.3, 0.7, 0.2).unwrap()
}

fn period(el: &Classical) -> f64 {
    TAU * (el.a.powi(3) / MU).sqrt()
}

/// Sample times: `per_orbit` per orbit over `orbits` orbits.
fn times(el: &Classical, orbits: usize, per_orbit: usize) -> Vec<f64> {
    let n = orbits * per_orbit;
    (0..=n)
        .map(|k| period(el) * k as f64 / per_orbit as f64)
        .collect()
}

/// The theory's position error along `truth` at `times`.
fn errors(theory: &BrouwerLyddane, times: &[f64], truth: &[V3]) -> Vec<f64> {
    times
        .iter()
        .zip(truth)
        .map(|(&t, q)| (theory.state(t).unwrap().0 - q).norm())
        .collect()
}

fn max(v: &[f64]) -> f64 {
    v.iter().copied().fold(0.0, f64::max)
}

fn theory(j2: f64, el: &Classical, axis: MeanAxis) -> BrouwerLyddane {
    let (q0, p0) = el.to_state(MU).unwrap();
    BrouwerLyddane::from_state_with(&J2::new(MU, j2, RADIUS).unwrap(), 0.0, &q0, &p0, axis).unwrap()
}

/// The targets of the brief over 100 orbits (4 samples per orbit): position error ≤ 1e−5 at
/// `J₂ = 10⁻³` and ≤ 1e−11 at `J₂ = 10⁻⁶` for `e = 0.1`; ≤ 1e−4 and ≤ 1e−10 for `e = 0.7`. The
/// truth at `rtol = 10⁻¹³` must agree with the run at `10⁻¹²` to a tenth of the target.
#[test]
fn hundred_orbits_meet_the_position_targets() {
    for &(e, j2, target) in &[
        (0.1, 1e-3, 1e-5),
        (0.1, 1e-6, 1e-11),
        (0.7, 1e-3, 1e-4),
        (0.7, 1e-6, 1e-10),
    ] {
        let el = initial(e);
        let ts = times(&el, 100, 4);
        let start = el.to_state(MU).unwrap();
        let fine = truth(j2, start, &ts, 1e-13);
        let second = truth(j2, start, &ts, 1e-14);
        let truth_error = fine
            .iter()
            .zip(&second)
            .map(|(a, b)| (a - b).norm())
            .fold(0.0, f64::max);
        let th = theory(j2, &el, MeanAxis::EnergyIntegral);
        let err = max(&errors(&th, &ts, &fine));
        println!(
            "e = {e}, J₂ = {j2:e}: max position error {err:.3e} (target {target:e}; truth \
             rtol 1e−13 vs 1e−14: {truth_error:.1e})"
        );
        assert!(
            err + truth_error <= target,
            "e = {e}, J₂ = {j2:e}: {err:e} (truth ± {truth_error:e}) > {target:e}"
        );
    }
}

/// Error against `J₂` with the energy-fixed `L''`: the neglected terms are second order, so the
/// error over 10 orbits is `C J₂²` until `J₂³ n t` takes over. The least-squares slope in
/// log–log over `J₂ = 10⁻³ … 10⁻⁵` is 2 within ±0.1: the next term changes the local slope by
/// `O(J₂(R/p)²)·n t ≲ 10⁻³·60`, and the truth's own error (`< 10⁻¹³`) stays below 1 % of the
/// smallest error (`≈ 10⁻¹¹` at `e = 0.7`). Without the fix the error is still `∝ J₂²` but
/// grows with `t` (next test).
#[test]
fn error_against_j2_has_slope_two() {
    for &e in &[0.1, 0.7] {
        let el = initial(e);
        let ts = times(&el, 10, 8);
        let start = el.to_state(MU).unwrap();
        let js = [1e-3, 1e-4, 1e-5];
        let errs: Vec<f64> = js
            .iter()
            .map(|&j2| {
                let tr = truth(j2, start, &ts, 1e-13);
                max(&errors(
                    &theory(j2, &el, MeanAxis::EnergyIntegral),
                    &ts,
                    &tr,
                ))
            })
            .collect();
        let x: Vec<f64> = js.iter().map(|j| j.ln()).collect();
        let y: Vec<f64> = errs.iter().map(|v| v.ln()).collect();
        let (mx, my) = (x.iter().sum::<f64>() / 3.0, y.iter().sum::<f64>() / 3.0);
        let slope = x
            .iter()
            .zip(&y)
            .map(|(a, b)| (a - mx) * (b - my))
            .sum::<f64>()
            / x.iter().map(|a| (a - mx).powi(2)).sum::<f64>();
        let shown: Vec<String> = errs.iter().map(|v| format!("{v:.3e}")).collect();
        println!("e = {e}: errors {shown:?} at J₂ = {js:?}; slope {slope:.4}");
        assert!((slope - 2.0).abs() < 0.1, "slope {slope}");
    }
}

/// Error against `t`: with the energy-fixed `L''` the error after 100 orbits is within a factor
/// 3 of the error over the first orbit (periodic `O(J₂²)` terms plus `J₂³ n t`, here
/// `≈ 10⁻⁹·600` relative); with `L''` from the first-order inverse it grows like `J₂² n t`, by
/// more than a factor 20 over the same span.
#[test]
fn energy_integral_removes_the_along_track_drift() {
    for &e in &[0.1, 0.7] {
        let j2 = 1e-4;
        let el = initial(e);
        let ts = times(&el, 100, 4);
        let tr = encke::truth(
            J2::new(MU, j2, RADIUS).unwrap(),
            el.to_state(MU).unwrap(),
            &ts,
            1e-13,
        );
        let first = |v: &[f64]| max(&v[..=4]);
        let fixed = errors(&theory(j2, &el, MeanAxis::EnergyIntegral), &ts, &tr);
        let plain = errors(&theory(j2, &el, MeanAxis::FirstOrderInverse), &ts, &tr);
        println!(
            "e = {e}, J₂ = 1e−4: energy-fixed L'': first orbit {:.3e}, 100 orbits {:.3e}; \
             first-order inverse: {:.3e}, {:.3e}",
            first(&fixed),
            max(&fixed),
            first(&plain),
            max(&plain)
        );
        assert!(max(&fixed) < 3.0 * first(&fixed));
        assert!(max(&plain) > 20.0 * first(&plain));
        assert!(max(&plain) > 20.0 * max(&fixed));
    }
}

/// The second-order rates against Brouwer's printed secular motions (1959, the `l''`, `g''`,
/// `h''` rates without `J₄`; Hoots & Roehrich 1980):
/// `l̇ = n[1 + (3/2)γ₂'η(3θ² − 1) + (3/32)γ₂'²η(−15 + 16η + 25η² + (30 − 96η − 90η²)θ²
/// + (105 + 144η + 25η²)θ⁴)]`,
/// `ġ = n[(3/2)γ₂'(5θ² − 1) + (3/32)γ₂'²(−35 + 24η + 25η² + (90 − 192η − 126η²)θ²
/// + (385 + 360η + 45η²)θ⁴)]`,
/// `ḣ = n[−3γ₂'θ + (3/8)γ₂'²((−5 + 12η + 9η²)θ + (−35 − 36η − 5η²)θ³)]`,
/// to rounding (the AD gradient of `K` and the hand polynomials, a few ulps of `n`); and
/// against the first-order [`j2_secular_rates`]: the difference is `O(n γ₂'²)`, at most
/// `n γ₂'² · 60` (the largest second-order coefficient above is `ġ`'s at `θ = η = 1`,
/// `(3/32)·576 = 54`).
#[test]
fn secular_rates_are_brouwers() {
    for &(a, e, i, j2) in &[
        (2.0, 0.1, 0.5, 1e-3),
        (2.0, 0.7, 0.5, 1e-3),
        (1.3, 0.01, 1.9, 2e-3),
        (3.0, 0.4, 0.1, -5e-4),
    ] {
        let r = brouwer_secular_rates(&J2::new(MU, j2, RADIUS).unwrap(), a, e, i).unwrap();
        let n = (MU / (a * a * a)).sqrt();
        let eta = ((1.0 - e) * (1.0 + e)).sqrt();
        let p = a * eta * eta;
        let gp = 0.5 * j2 * (RADIUS / p).powi(2);
        let th = i.cos();
        let t2 = th * th;
        let ldot = n
            * (1.0
                + 1.5 * gp * eta * (3.0 * t2 - 1.0)
                + 3.0 / 32.0
                    * gp
                    * gp
                    * eta
                    * (-15.0
                        + 16.0 * eta
                        + 25.0 * eta * eta
                        + (30.0 - 96.0 * eta - 90.0 * eta * eta) * t2
                        + (105.0 + 144.0 * eta + 25.0 * eta * eta) * t2 * t2));
        let gdot = n
            * (1.5 * gp * (5.0 * t2 - 1.0)
                + 3.0 / 32.0
                    * gp
                    * gp
                    * (-35.0
                        + 24.0 * eta
                        + 25.0 * eta * eta
                        + (90.0 - 192.0 * eta - 126.0 * eta * eta) * t2
                        + (385.0 + 360.0 * eta + 45.0 * eta * eta) * t2 * t2));
        let hdot = n
            * (-3.0 * gp * th
                + 3.0 / 8.0
                    * gp
                    * gp
                    * ((-5.0 + 12.0 * eta + 9.0 * eta * eta) * th
                        + (-35.0 - 36.0 * eta - 5.0 * eta * eta) * th * t2));
        let tol = 16.0 * f64::EPSILON * n;
        assert!((r.mean_motion + r.mean_anomaly - ldot).abs() < tol);
        assert!((r.argp - gdot).abs() < tol, "{} {}", r.argp, gdot);
        assert!((r.raan - hdot).abs() < tol);
        let first = J2::new(MU, j2, RADIUS)
            .and_then(|model| j2_secular_rates(&model, a, e, i))
            .unwrap();
        let bound = 60.0 * n * gp * gp;
        for (x, y) in [
            (r.raan, first.raan),
            (r.argp, first.argp),
            (r.mean_anomaly, first.mean_anomaly),
        ] {
            assert!((x - y).abs() < bound, "{x} vs {y}: {:e}", x - y);
            assert!((x - y).abs() > 0.0);
        }
    }
}

/// Mean → osculating → mean is the identity to rounding (the iteration inverts the map), and
/// osculating → mean → osculating too; over a grid of anomalies and both eccentricities.
#[test]
fn mean_osculating_round_trip() {
    for &e in &[1e-6, 0.1, 0.7] {
        for &i in &[1e-6, 0.5, 2.0] {
            for k in 0..8 {
                let m = -3.0 + 0.8 * k as f64;
                let mean = Classical::new(2.0, e, i, 0.3, 0.7, m).unwrap();
                let osc = mean_to_osculating(MU, RADIUS, 1e-3, &mean).unwrap();
                let back = osculating_to_mean(&J2::new(MU, 1e-3, RADIUS).unwrap(), &osc).unwrap();
                let (q1, v1) = mean.to_state(MU).unwrap();
                let (q2, v2) = back.to_state(MU).unwrap();
                assert!((q1 - q2).norm() < 1e-13, "{:e}", (q1 - q2).norm());
                assert!((v1 - v2).norm() < 1e-13);
                let again = mean_to_osculating(MU, RADIUS, 1e-3, &back).unwrap();
                let (q3, _) = osc.to_state(MU).unwrap();
                let (q4, _) = again.to_state(MU).unwrap();
                assert!((q3 - q4).norm() < 1e-13);
            }
        }
    }
}

/// Lyddane's variables: nearly circular (`e = 10⁻⁶`) and nearly equatorial (`i = 10⁻⁶`) orbits
/// give finite states as accurate as the `e = 0.1`, `i = 0.5` case (the same `O(J₂²)` bound,
/// `3·10⁻⁶` at `J₂ = 10⁻³` over 10 orbits), and also exactly circular / equatorial ones.
#[test]
fn small_eccentricity_and_inclination_stay_regular() {
    for &(e, i) in &[(1e-6, 0.5), (0.1, 1e-6), (1e-6, 1e-6), (0.0, 0.0)] {
        let el = Classical::new(2.0, e, i, 0.3, 0.7, 0.2).unwrap();
        let ts = times(&el, 10, 8);
        let j2 = 1e-3;
        let tr = encke::truth(
            J2::new(MU, j2, RADIUS).unwrap(),
            el.to_state(MU).unwrap(),
            &ts,
            1e-13,
        );
        let th = theory(j2, &el, MeanAxis::EnergyIntegral);
        let err = max(&errors(&th, &ts, &tr));
        println!("e = {e:e}, i = {i:e}: max error over 10 orbits {err:.3e}");
        assert!(err < 3e-6, "{err:e}");
    }
}

/// A second formulation of the evaluation: `state(t)` takes the sines and cosines of the
/// osculating `Ω`, `i`, `ω`, `E` from Lyddane's pairs, the addition theorems and the last Newton
/// step, without forming the angles; `osculating_elements(t).to_state(μ)` forms every angle
/// (atan2, asin) and solves Kepler's equation afresh. Both are the same map, so they agree to
/// rounding: five angle round trips of size `≤ 4π` (`4π ε ≈ 3·10⁻¹⁵` each), amplified by
/// Kepler's `1/(1 − e) ≤ 3.4` and the orbit size `a(1 + e) ≤ 3.4`: `≤ 2·10⁻¹³` in `r` and `v`.
#[test]
fn state_agrees_with_the_elements_route() {
    let model = J2::new(MU, 1e-3, RADIUS).unwrap();
    for &(e, i) in &[(0.1, 0.5), (0.7, 0.5), (1e-6, 1e-6), (0.0, 0.0), (0.3, 2.5)] {
        let el = Classical::new(2.0, e, i, 0.3, 0.7, 0.2).unwrap();
        let th = BrouwerLyddane::from_mean(&model, 0.0, &el).unwrap();
        let mut worst = 0.0f64;
        for t in times(&el, 3, 37) {
            let (r, v) = th.state(t).unwrap();
            let (r2, v2) = th.osculating_elements(t).unwrap().to_state(MU).unwrap();
            worst = worst.max((r - r2).amax()).max((v - v2).amax());
        }
        println!("e = {e:e}, i = {i:e}: largest difference {worst:.2e}");
        assert!(worst <= 2e-13, "e = {e}, i = {i}: {worst:e}");
    }
}

/// The map is written once for dual numbers: `∂(osculating)/∂J₂` by AD against a central
/// difference (step `h = 10⁻⁶`: truncation `O(h²)·|∂³|` and rounding `ε/h`, both below 10⁻⁹
/// relative).
#[test]
fn derivative_in_j2_by_dual_numbers() {
    let mean = Classical::new(2.0, 0.3, 0.5, 0.3, 0.7, 1.1).unwrap();
    let lift = |x: f64| Dual64::from_re(x);
    let md = Classical {
        a: lift(mean.a),
        e: lift(mean.e),
        i: lift(mean.i),
        raan: lift(mean.raan),
        argp: lift(mean.argp),
        mean_anomaly: lift(mean.mean_anomaly),
    };
    let j2 = 1e-3;
    let d = mean_to_osculating(MU, RADIUS, Dual64::from_re(j2).derivative(), &md).unwrap();
    let h = 1e-6;
    let p = mean_to_osculating(MU, RADIUS, j2 + h, &mean).unwrap();
    let m = mean_to_osculating(MU, RADIUS, j2 - h, &mean).unwrap();
    for (dual, plus, minus) in [
        (d.a, p.a, m.a),
        (d.e, p.e, m.e),
        (d.i, p.i, m.i),
        (d.raan, p.raan, m.raan),
        (d.argp, p.argp, m.argp),
        (d.mean_anomaly, p.mean_anomaly, m.mean_anomaly),
    ] {
        let fd = (plus - minus) / (2.0 * h);
        assert!(
            (dual.eps - fd).abs() < 1e-7 * (1.0 + fd.abs()),
            "{} {fd}",
            dual.eps
        );
        assert!(dual.re.is_finite());
    }
}

/// Bad input: a hyperbolic state, a small parameter above the bound, the critical
/// inclination are typed errors; a perigee inside `R` is a warning.
#[test]
fn bad_input_is_refused_and_perigee_is_a_warning() {
    // e ≥ 1.
    let (q, _) = initial(0.1).to_state(MU).unwrap();
    let v = V3::new(0.0, 2.0, 0.0);
    assert!(BrouwerLyddane::from_state(&J2::new(MU, 1e-3, RADIUS).unwrap(), 0.0, &q, &v).is_err());
    let hyper = Classical::new(-2.0, 1.5, 0.5, 0.0, 0.0, 0.1).unwrap();
    assert!(mean_to_osculating(MU, RADIUS, 1e-3, &hyper).is_err());
    // J₂(R/p)² above the bound.
    let el = Classical::new(1.0, 0.1, 0.5, 0.0, 0.0, 0.1).unwrap();
    let p = el.a * (1.0 - el.e * el.e);
    let j2 = 1.01 * MAX_SMALL_PARAMETER * p * p;
    assert!(matches!(
        mean_to_osculating(MU, RADIUS, j2, &el),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(mean_to_osculating(MU, RADIUS, 0.99 * MAX_SMALL_PARAMETER * p * p, &el).is_ok());
    // The critical inclination cos²i = 1/5 and a stated distance around it.
    let ic = (0.2f64).sqrt().acos();
    for i in [ic, ic + 1e-3, PI_MINUS(ic)] {
        let el = Classical::new(2.0, 0.1, i, 0.0, 0.0, 0.1).unwrap();
        assert!(matches!(
            mean_to_osculating(MU, RADIUS, 1e-3, &el),
            Err(Error::OutOfDomain { .. })
        ));
    }
    // Outside the band: |1 − 5cos²i| = 2·distance.
    let i_ok = ((1.0 + 2.0 * CRITICAL_INCLINATION_DISTANCE) / 5.0)
        .sqrt()
        .acos();
    let el = Classical::new(2.0, 0.1, i_ok, 0.0, 0.0, 0.1).unwrap();
    assert!(mean_to_osculating(MU, RADIUS, 1e-3, &el).is_ok());
    // Perigee inside R (e = 0.7, a = 2: a(1 − e) ≈ 0.6): a warning, the theory runs.
    let th = theory(1e-3, &initial(0.7), MeanAxis::EnergyIntegral);
    assert!(matches!(
        th.warnings(),
        [TheoryWarning::PerigeeInsideBody { .. }]
    ));
    assert!(theory(1e-3, &initial(0.1), MeanAxis::EnergyIntegral)
        .warnings()
        .is_empty());
}

#[allow(non_snake_case)]
fn PI_MINUS(x: f64) -> f64 {
    std::f64::consts::PI - x
}

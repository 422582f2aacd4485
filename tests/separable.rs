//! Separable systems by Jacobi inversion of the separated quadratures [Ardema 17.3–17.5]: Kepler in
//! polar coordinates (one librating, one ignorable coordinate), the anisotropic oscillator (two
//! librating coordinates, closed form) and a Liouville system [Ardema 8.4] against integration.

mod common;

use hamilton_jacobi::hamilton_jacobi::{
    Liouville, LiouvilleSeparation, LiouvilleSystem, SeparatedMotion, SeparatedSystem,
};
use hamilton_jacobi::nalgebra::{SVector, Vector2};
use hamilton_jacobi::systems::kepler;
use hamilton_jacobi::{DualNum, Error, Result};
use std::f64::consts::PI;

/// Kepler, μ = 1, in `(r, θ)`: `F_r = 2h + 2/r − k²/r²`, `F_θ = k²` (θ ignorable).
#[derive(Clone, Debug)]
struct KeplerPolar;
impl SeparatedSystem<2> for KeplerPolar {
    fn radicand<D: DualNum<f64> + Copy>(&self, r: usize, x: D, c: &SVector<D, 2>) -> D {
        match r {
            0 => c[0] * 2.0 + x.recip() * 2.0 - c[1] * c[1] / (x * x),
            _ => c[1] * c[1],
        }
    }
    fn constants(&self, q: &SVector<f64, 2>, p: &SVector<f64, 2>) -> Result<SVector<f64, 2>> {
        let h = 0.5 * (p[0] * p[0] + p[1] * p[1] / (q[0] * q[0])) - 1.0 / q[0];
        Ok(SVector::from([h, p[1]]))
    }
    fn ignorable(&self, r: usize) -> bool {
        r == 1
    }
    fn search_bounds(&self, _r: usize) -> (f64, f64) {
        (1e-9, 1e9)
    }
}

/// Jacobi inversion reproduces Kepler's equation over several revolutions, from a generic start
/// (not an apsis, inbound), for both senses of rotation. The quadratures are good to 1e−14
/// relative and the Newton residual to 16ε of the largest constant's derivative (≈ T), so states
/// agree to ~1e−12 after a few periods.
#[test]
fn kepler_by_jacobi_inversion() {
    for (e, sense) in [(0.3, 1.0), (0.8, -1.0), (0.95, 1.0)] {
        let (rp, vp) = (1.0 - e, ((1.0 + e) / (1.0 - e)).sqrt() * sense);
        let start = |t: f64| {
            kepler::propagate(1.0, &Vector2::new(rp, 0.0), &Vector2::new(0.0, vp), t).unwrap()
        };
        let t0 = 4.0; // past apoapsis (T = 2π): inbound
        let (x0, v0) = start(t0);
        let polar = |x: &Vector2<f64>, v: &Vector2<f64>| {
            let r = x.norm();
            let th = x[1].atan2(x[0]);
            (
                SVector::from([r, th]),
                SVector::from([v.dot(x) / r, x[0] * v[1] - x[1] * v[0]]),
            )
        };
        let (q0, p0) = polar(&x0, &v0);
        assert!(p0[0] < 0.0, "inbound start");
        let motion = SeparatedMotion::new(KeplerPolar, t0, &q0, &p0).unwrap();
        let (r1, r2) = motion.turning_points(0).unwrap();
        assert!((r1 - (1.0 - e)).abs() < 1e-14 && (r2 - (1.0 + e)).abs() < 1e-14);
        for t in [t0, 4.5, 7.0, 13.3, 25.0] {
            let (q, p) = motion.state_at(t).unwrap();
            let (x, v) = start(t);
            let hj = Vector2::new(q[0] * q[1].cos(), q[0] * q[1].sin());
            assert!(
                (hj - x).norm() < 1e-11,
                "e = {e}, t = {t}: HJ {hj:?} vs Kepler {x:?}"
            );
            assert!((p[0] - v.dot(&x) / x.norm()).abs() < 1e-10);
        }
    }
}

/// Anisotropic oscillator `H = ½(p₁² + p₂²) + ½(ω₁² x² + ω₂² y²)` with constants `(h, h₁)`:
/// both coordinates librate; the inversion couples them through `∂K/∂h = t − t₀`.
#[derive(Clone, Debug)]
struct Anisotropic(f64, f64);
impl SeparatedSystem<2> for Anisotropic {
    fn radicand<D: DualNum<f64> + Copy>(&self, r: usize, x: D, c: &SVector<D, 2>) -> D {
        match r {
            0 => c[1] * 2.0 - x * x * (self.0 * self.0),
            _ => (c[0] - c[1]) * 2.0 - x * x * (self.1 * self.1),
        }
    }
    fn constants(&self, q: &SVector<f64, 2>, p: &SVector<f64, 2>) -> Result<SVector<f64, 2>> {
        let e1 = 0.5 * (p[0] * p[0] + self.0 * self.0 * q[0] * q[0]);
        let e2 = 0.5 * (p[1] * p[1] + self.1 * self.1 * q[1] * q[1]);
        Ok(SVector::from([e1 + e2, e1]))
    }
    fn search_bounds(&self, _r: usize) -> (f64, f64) {
        (-1e3, 1e3)
    }
}

#[test]
fn anisotropic_oscillator_closed_form() {
    let (w1, w2) = (1.0, 2f64.sqrt());
    let (a1, f1, a2, f2) = (0.7, 0.3, 1.2, -2.0);
    let exact = |t: f64| {
        (
            SVector::from([a1 * (w1 * t + f1).sin(), a2 * (w2 * t + f2).sin()]),
            SVector::from([a1 * w1 * (w1 * t + f1).cos(), a2 * w2 * (w2 * t + f2).cos()]),
        )
    };
    let (q0, p0) = exact(0.0);
    let motion = SeparatedMotion::new(Anisotropic(w1, w2), 0.0, &q0, &p0).unwrap();
    // One passage of each coordinate takes half its period: ∂K/∂h over a passage.
    assert!((motion.passage(0).unwrap()[1] - PI / w1).abs() < 1e-13);
    assert!((motion.passage(1).unwrap()[0] - PI / w2).abs() < 1e-13);
    for t in [0.0, 0.4, 3.0, 11.0, 40.0] {
        let (q, p) = motion.state_at(t).unwrap();
        let (qe, pe) = exact(t);
        assert!(
            (q - qe).amax() < 1e-11 && (p - pe).amax() < 1e-11,
            "t = {t}: {q:?} {p:?} vs {qe:?} {pe:?}"
        );
    }
}

/// The quartic Liouville system `U = q₁² + q₂²`, `v = 1`, `W = q₁⁴ + q₂⁴`; initial
/// `(q, q̇) = (1, 0.5, 0.2, −0.3)`.
#[derive(Clone, Debug)]
struct QuarticLiouville;
impl LiouvilleSystem<2> for QuarticLiouville {
    fn u<D: DualNum<f64> + Copy>(&self, _s: usize, q: D) -> D {
        q * q
    }
    fn v<D: DualNum<f64> + Copy>(&self, _s: usize, _q: D) -> D {
        D::one()
    }
    fn w<D: DualNum<f64> + Copy>(&self, _s: usize, q: D) -> D {
        q.powi(4)
    }
}

/// The Liouville system by HJ separation against RK4 of its Lagrange equations over 5 s.
/// RK4 tolerance: twice the Richardson estimate |x_n − x_2n|/15 plus the 1e−11 inversion floor.
#[test]
fn liouville_motion_matches_integration() {
    let sep = LiouvilleSeparation::new(QuarticLiouville, [(-10.0, 10.0), (-10.0, 10.0)]).unwrap();
    let q0 = SVector::from([1.0, 0.5]);
    let qd0 = SVector::from([0.2, -0.3]);
    let u0 = q0.dot(&q0);
    let p0 = qd0 * u0;
    let motion = SeparatedMotion::new(sep, 0.0, &q0, &p0).unwrap();
    let c = motion.constants();
    assert!((c[0] - 0.93125).abs() < 1e-15 && (c[1] - 0.1).abs() < 1e-15);
    let (a, b) = motion.turning_points(1).unwrap();
    assert!(
        a > 0.3 && b < 0.9,
        "q₂ librates in ({a}, {b}) without reaching 0"
    );
    let run = |n: usize, t: f64| {
        common::rk4_lagrangian(
            &Liouville(QuarticLiouville),
            0.0,
            q0,
            qd0,
            t / n as f64,
            n,
            |_, _, _| {},
        )
    };
    for t in [1.0, 2.5, 5.0] {
        let (q, p) = motion.state_at(t).unwrap();
        let n = (4_000.0 * t) as usize;
        let (q1, v1) = run(n, t);
        let (q2, v2) = run(2 * n, t);
        let est = (q1 - q2).amax().max((v1 - v2).amax()) / 15.0;
        let u = q2.dot(&q2);
        let diff = (q - q2).amax().max((p / u - v2).amax());
        assert!(
            diff <= 2.0 * est + 1e-11,
            "t = {t}: |HJ − RK4| = {diff:e}, RK4 estimate {est:e}"
        );
    }
}

#[test]
fn inconsistent_or_bad_input_is_refused() {
    let q = SVector::from([1.0, 0.0]);
    let p = SVector::from([0.1, 1.0]);
    let m = SeparatedMotion::new(KeplerPolar, 0.0, &q, &p).unwrap();
    assert!(m.state_at(f64::NAN).is_err());
    assert!(SeparatedMotion::new(KeplerPolar, 0.0, &SVector::from([f64::NAN, 0.0]), &p).is_err());
    // Zero angular momentum: the ignorable coordinate has no momentum to carry it.
    // Zero angular momentum: radial fall, no lower turning point (and no momentum to carry θ).
    let e = SeparatedMotion::new(KeplerPolar, 0.0, &q, &SVector::from([0.1, 0.0]));
    assert!(matches!(e, Err(Error::OutOfDomain { .. })), "{e:?}");
    // Unbound (h > 0): no upper turning point.
    assert!(SeparatedMotion::new(KeplerPolar, 0.0, &q, &SVector::from([2.0, 1.0])).is_err());
    assert!(LiouvilleSeparation::new(QuarticLiouville, [(1.0, -1.0), (0.0, 1.0)]).is_err());
}

/// The anisotropic oscillator's actions `J_r = E_r/ω_r` and frequencies `ω_r` from the separated
/// quadratures, against the closed forms; Kepler in polar coordinates: the radial action
/// `1/√(−2h) − k` and the frequencies `ω_r = ω_θ = (−2h)^{3/2}` (degenerate, μ = 1).
#[test]
fn separated_motion_exposes_actions_and_frequencies() {
    let (w1, w2) = (1.0, 2f64.sqrt());
    let (q0, p0) = (SVector::from([0.3, -0.2]), SVector::from([0.5, 0.9]));
    let motion = SeparatedMotion::new(Anisotropic(w1, w2), 0.0, &q0, &p0).unwrap();
    let e1 = 0.5 * (p0[0] * p0[0] + w1 * w1 * q0[0] * q0[0]);
    let e2 = 0.5 * (p0[1] * p0[1] + w2 * w2 * q0[1] * q0[1]);
    let j = motion.actions().unwrap();
    for (r, exact) in [(0, e1 / w1), (1, e2 / w2)] {
        assert!(
            (j[r].value - exact).abs() <= j[r].error + 8.0 * f64::EPSILON * exact,
            "J_{r} = {} vs {exact}",
            j[r].value
        );
    }
    let w = motion.frequencies().unwrap();
    assert!(
        (w[0] - w1).abs() < 1e-13 && (w[1] - w2).abs() < 1e-13,
        "{w:?}"
    );
    // Kepler: h = −0.5 + …, k from the state.
    let (q, p) = (SVector::from([1.2, 0.4]), SVector::from([0.1, 0.95]));
    let m = SeparatedMotion::new(KeplerPolar, 0.0, &q, &p).unwrap();
    let c = *m.constants();
    let (h, k) = (c[0], c[1]);
    let j = m.actions().unwrap();
    let jr = 1.0 / (-2.0 * h).sqrt() - k;
    assert!(
        (j[0].value - jr).abs() <= j[0].error + 16.0 * f64::EPSILON,
        "{} vs {jr}",
        j[0].value
    );
    assert_eq!(j[1].value, k);
    let n = (-2.0 * h).powf(1.5);
    let w = m.frequencies().unwrap();
    assert!(
        (w[0] - n).abs() < 1e-12 * n && (w[1] - n).abs() < 1e-12 * n,
        "{w:?} vs {n}"
    );
}

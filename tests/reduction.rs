//! Reduction and quadrature with known integrals: Whittaker's order reduction [Ardema 15.6],
//! Jacobi's last multiplier, Liouville's determinant and the two-degree-of-freedom quadrature
//! [Ardema 15.6, 16.4], Liouville's separable systems [Ardema 8.4].

mod common;

use common::{config, rk4_hamiltonian, rk4_lagrangian, rk4_step};
use hamilton_jacobi::brackets::{jacobian, PhaseMap};
use hamilton_jacobi::hamilton_jacobi::{
    divergence, hamiltonian_divergence, hamiltonian_multiplier_residual,
    liouville_separated_integrals, multiplier_residual, two_dof_quadrature, variational_flow,
    Liouville, LiouvilleSystem, ScalarField, TwoDofMomenta, VectorField, Whittaker,
};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::systems::{Kepler2, Pendulum};
use hamilton_jacobi::{hamiltonian, DualNum, Error, Hamiltonian, Lagrangian, PhaseFunction};
use proptest::prelude::*;

type V2 = SVector<f64, 2>;

// ---------------------------------------------------------------------------------------------
// Whittaker's order reduction [Ardema 15.6, eqs. 15.31–15.36].
// ---------------------------------------------------------------------------------------------

const G: f64 = 2.0;
const K: f64 = 3.0;

hamiltonian!(
    /// Free fall in x, oscillation in y: H = ½(p_x² + p_y²) + g x + ½ k² y².
    FallOscillator<2> { g: f64, k: f64 } |s, _t, q, p| p.dot(p) * 0.5 + q[0] * s.g + q[1] * q[1] * (0.5 * s.k * s.k)
);

hamiltonian!(
    /// Hénon–Heiles: a non-separable test case for the reduction in a general slot.
    HenonHeiles<2> |_s, _t, q, p| p.dot(p) * 0.5 + q.dot(q) * 0.5 + q[0] * q[0] * q[1] - q[1].powi(3) / 3.0
);

hamiltonian!(
    /// Isotropic oscillator, for the fold of the energy surface.
    Oscillator2<2> |_s, _t, q, p| (p.dot(p) + q.dot(q)) * 0.5
);

hamiltonian!(
    /// A time-dependent Hamiltonian (no energy integral).
    Driven<2> |_s, t, q, p| (p.dot(p) + q.dot(q)) * 0.5 + q[0] * t.sin()
);

#[test]
fn whittaker_reduction_matches_full_motion() {
    let sys = FallOscillator { g: G, k: K };
    let (q0, p0) = (V2::new(1.0, 0.5), V2::new(0.4, -0.3));
    let h = sys.value(0.0, &q0, &p0).unwrap();
    let w = Whittaker::new(sys.clone(), h, 0).unwrap();
    assert_eq!(w.eliminated_coordinate(&q0, &p0).unwrap(), q0[0]);

    // Reduced system in the independent variable s = p_x, state (x, y, p_x, p_y, t); the slot x
    // only carries the Newton guess (x itself is recomputed from φ at every evaluation).
    let field = |_s: f64, z: &SVector<f64, 5>| {
        let (q, p) = (V2::new(z[0], z[1]), V2::new(z[2], z[3]));
        let r = w.reduced_field(&q, &p).unwrap();
        SVector::from([r.dq[0], r.dq[1], r.dp[0], r.dp[1], r.dt])
    };
    // The same step θ = k dt = (k/g) |Δp_x| in both integrations: p_x = p_x0 − g t.
    let (dt, steps) = (1e-3, 2000);
    let ds = -G * dt;
    let mut z = SVector::from([q0[0], q0[1], p0[0], p0[1], 0.0]);
    let mut reduced = Vec::with_capacity(steps);
    for _ in 0..steps {
        z = rk4_step(&field, 0.0, &z, ds);
        reduced.push(z);
    }
    let mut full = Vec::with_capacity(steps);
    rk4_hamiltonian(&sys, 0.0, q0, p0, dt, steps, |t, q, p| {
        full.push((t, *q, *p))
    });

    // RK4 on an oscillation with step phase θ: the stability function R(iθ) = e^{iθ} − (iθ)⁵/120 + …,
    // so n steps accumulate a phase error n θ⁵/120 (the amplitude error is O(n θ⁶)); the
    // coordinate errors are the amplitude A times it, the momentum errors k A times it. p_x and
    // t are polynomial in the independent variable and integrated exactly, x = φ is exact given the
    // other variables: δx ≤ (|p_y| δp_y + k² |y| δy)/g. Rounding adds ~ n ε.
    let wave = K / G; // wavenumber of y(p_x)
    let theta = K * dt;
    let amp = q0[1].hypot(p0[1] / K);
    let drift = steps as f64 * theta.powi(5) / 120.0 + steps as f64 * f64::EPSILON;
    let (tol_y, tol_py) = (2.0 * amp * drift, 2.0 * K * amp * drift);
    let tol_x = (p0[1].abs() + amp * K) * tol_py / G + K * K * amp * tol_y / G;
    let mut worst = [0.0f64; 5];
    for (zr, (t, qf, pf)) in reduced.iter().zip(&full) {
        let px = zr[2];
        let sigma = px - p0[0];
        // Exact solution of d²y/dp_x² = −(k/g)² y with y(p_x0) = y₀, dy/dp_x = −p_y0/g.
        let y_exact = q0[1] * (wave * sigma).cos() - p0[1] / G / wave * (wave * sigma).sin();
        let py_exact =
            -G * (-q0[1] * wave * (wave * sigma).sin() - p0[1] / G * (wave * sigma).cos());
        // The same motion in t: frequency k.
        let y_t = q0[1] * (K * t).cos() + p0[1] / K * (K * t).sin();
        let x_exact = q0[0] + p0[0] * t - 0.5 * G * t * t;
        let x_phi = w
            .eliminated_coordinate(&V2::new(zr[0], zr[1]), &V2::new(px, zr[3]))
            .unwrap();
        worst[0] = worst[0].max((zr[1] - y_exact).abs());
        worst[1] = worst[1].max((zr[3] - py_exact).abs());
        worst[2] = worst[2].max((x_phi - qf[0]).abs().max((x_phi - x_exact).abs()));
        worst[3] = worst[3].max((zr[4] - t).abs().max((pf[0] - px).abs()));
        worst[4] = worst[4].max((zr[1] - qf[1]).abs().max((qf[1] - y_t).abs()));
        assert!((zr[1] - y_exact).abs() <= tol_y, "y(p_x) at p_x = {px}");
        assert!((zr[3] - py_exact).abs() <= tol_py, "p_y(p_x) at p_x = {px}");
        assert!((qf[1] - y_t).abs() <= tol_y, "full y(t) at t = {t}");
        assert!(
            (zr[1] - qf[1]).abs() <= 2.0 * tol_y,
            "reduced vs full y at t = {t}"
        );
        assert!(
            (x_phi - qf[0]).abs() <= tol_x + 1e-13,
            "x from φ at t = {t}"
        );
        assert!(
            (x_phi - x_exact).abs() <= tol_x + 1e-13,
            "x from φ vs exact at t = {t}"
        );
        // Time from dt/dp_x = −1/g, and p_x(t) of the full motion.
        assert!(
            (zr[4] - t).abs() <= 1e-13 * (1.0 + t),
            "time recovery at t = {t}"
        );
        assert!((pf[0] - px).abs() <= 1e-13, "p_x(t) at t = {t}");
    }
    println!(
        "Whittaker reduction, max errors: y {:.2e} (tol {tol_y:.2e}), p_y {:.2e} (tol {tol_py:.2e}), x {:.2e} \
         (tol {tol_x:.2e}), t {:.2e}, reduced-vs-full/exact y(t) {:.2e}",
        worst[0], worst[1], worst[2], worst[3], worst[4]
    );
}

#[test]
fn reduced_hamiltonian_is_phi_with_p_i_as_time() {
    // Hénon–Heiles, eliminating q₂ (index 1) with p₂ as the independent variable.
    let (q, p) = (V2::new(0.1, 0.2), V2::new(0.3, -0.25));
    let h = HenonHeiles.value(0.0, &q, &p).unwrap();
    let w = Whittaker::new(HenonHeiles, h, 1).unwrap();
    let rates = w.reduced_field(&q, &p).unwrap();
    assert!((rates.eliminated - q[1]).abs() < 1e-15);
    // The rates are Hamilton's equations divided by ṗ₂.
    let (qd, pd) = HenonHeiles.vector_field(0.0, &q, &p).unwrap();
    assert!((rates.dq[0] - qd[0] / pd[1]).abs() < 1e-14);
    assert!((rates.dp[0] - pd[0] / pd[1]).abs() < 1e-14);
    assert!((rates.dq[1] - qd[1] / pd[1]).abs() < 1e-14);
    assert_eq!(rates.dp[1], 1.0);
    assert!((rates.dt - 1.0 / pd[1]).abs() < 1e-14);
    assert!((w.time_rate(&q, &p).unwrap() - rates.dt).abs() < 1e-16);
    // K = φ as a Hamiltonian with time τ = p₂: derivatives of φ by implicit AD agree with the
    // implicit-function formula, and the inert slot has zero rates.
    let k = w.reduced_hamiltonian();
    let guess = V2::new(q[0], q[1] + 0.01);
    let (kq, kp) = k.vector_field(p[1], &guess, &p).unwrap();
    assert!((k.value(p[1], &guess, &p).unwrap() - q[1]).abs() < 1e-15);
    assert!(
        (kq[0] - rates.dq[0]).abs() < 1e-14,
        "{} {}",
        kq[0],
        rates.dq[0]
    );
    assert!(
        (kp[0] - rates.dp[0]).abs() < 1e-14,
        "{} {}",
        kp[0],
        rates.dp[0]
    );
    assert_eq!((kq[1], kp[1]), (0.0, 0.0));
    // Second derivatives too (Hessian of K by nested duals through the implicit solve), against
    // central differences of the first derivatives.
    let hess = k.hessian(p[1], &guess, &p).unwrap();
    let dk = |x: f64| k.vector_field(p[1], &V2::new(x, guess[1]), &p).unwrap().1[0];
    let cd = |e: f64| -(dk(guess[0] + e) - dk(guess[0] - e)) / (2.0 * e);
    // Richardson-extrapolated central differences (the third derivative is ~ 10³ here, so a plain
    // difference at e = 1e−5 is off by 1e−8): truncation O(e⁴) ≲ 1e−13, rounding ε/e ~ 1e−12.
    let fd = (4.0 * cd(5e-5) - cd(1e-4)) / 3.0;
    assert!(
        (hess.qq[(0, 0)] - fd).abs() < 1e-10,
        "{} {fd}",
        hess.qq[(0, 0)]
    );
}

#[test]
fn reduction_refuses_bad_input() {
    let sys = FallOscillator { g: G, k: K };
    let (q, p) = (V2::new(1.0, 0.5), V2::new(0.4, -0.3));
    assert!(matches!(
        Whittaker::new(sys.clone(), 1.0, 2),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        Whittaker::new(sys.clone(), f64::NAN, 0),
        Err(Error::NonFinite { .. })
    ));
    let w = Whittaker::new(sys, 3.0, 0).unwrap();
    assert!(matches!(
        w.reduced_field(&V2::new(0.0, f64::INFINITY), &p),
        Err(Error::NonFinite { .. })
    ));
    // g = 0: ∂H/∂x ≡ 0, H = h cannot be solved for x.
    let flat = Whittaker::new(FallOscillator { g: 0.0, k: K }, 3.0, 0).unwrap();
    assert!(matches!(
        flat.reduced_field(&q, &p),
        Err(Error::Singular { .. })
    ));
    // The fold of the oscillator's energy surface: h = ½|p|² + ½ q₂² puts the root at q₁ = 0,
    // where ∂H/∂q₁ = q₁ = 0 — from the fold itself and from a guess beside it.
    let (qf, pf) = (V2::new(0.0, 0.3), V2::new(0.4, 0.1));
    let hf = Oscillator2.value(0.0, &qf, &pf).unwrap();
    let fold = Whittaker::new(Oscillator2, hf, 0).unwrap();
    for guess in [0.0, 0.5, -0.2] {
        let r = fold.reduced_field(&V2::new(guess, 0.3), &pf);
        assert!(
            matches!(r, Err(Error::Singular { .. })),
            "guess {guess}: {r:?}"
        );
    }
    // Just off the fold the reduction is regular, with large rates.
    let off = Whittaker::new(Oscillator2, hf + 1e-6, 0).unwrap();
    let r = off.reduced_field(&V2::new(0.5, 0.3), &pf).unwrap();
    assert!((r.eliminated - (2e-6f64).sqrt()).abs() < 1e-12);
    // A guess where ∂H/∂q₁ = 0 but H ≠ h (the root q₁ = ±0.5 is regular): no Newton step exists
    // from there — NotConverged asking for another guess, not a false Singular.
    let regular = Whittaker::new(Oscillator2, hf + 0.125, 0).unwrap();
    assert!(matches!(
        regular.reduced_field(&V2::new(0.0, 0.3), &pf),
        Err(Error::NotConverged { .. })
    ));
    assert!(
        (regular
            .eliminated_coordinate(&V2::new(0.1, 0.3), &pf)
            .unwrap()
            - 0.5)
            .abs()
            < 1e-15
    );
    assert!(
        (regular
            .eliminated_coordinate(&V2::new(-0.1, 0.3), &pf)
            .unwrap()
            + 0.5)
            .abs()
            < 1e-15
    );
    // No root on this branch: a typed error, not a panic.
    let below = Whittaker::new(Oscillator2, 0.01, 0).unwrap();
    assert!(below.reduced_field(&V2::new(0.5, 0.3), &pf).is_err());
    // No energy integral: time-dependent or damped Hamiltonians are refused.
    let driven = Whittaker::new(Driven, 1.0, 0).unwrap();
    assert!(matches!(
        driven.reduced_field(&V2::new(0.5, 0.3), &pf),
        Err(Error::InvalidInput { .. })
    ));
    let damped = Whittaker::new(DampedPendulum { c: 0.2 }, 0.5, 0).unwrap();
    assert!(matches!(
        damped.eliminated_coordinate(&SVector::from([1.0]), &SVector::from([0.1])),
        Err(Error::InvalidInput { .. })
    ));
    // The reduced Hamiltonian evaluates to NaN where the solve fails; checked methods report it.
    let k = flat.reduced_hamiltonian();
    assert!(k.vector_field(p[0], &q, &p).is_err());
}

// ---------------------------------------------------------------------------------------------
// Jacobi's last multiplier, Liouville's determinant [Ardema 15.6, 16.4].
// ---------------------------------------------------------------------------------------------

/// θ̈ = −sin θ − c θ̇ as H = p²/2 − cos θ with the force Q = −c p.
#[derive(Clone, Copy, Debug)]
struct DampedPendulum {
    c: f64,
}
impl Hamiltonian<1> for DampedPendulum {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> D {
        p[0] * p[0] * 0.5 - q[0].cos()
    }
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> Option<SVector<D, 1>> {
        Some(SVector::from([p[0] * -self.c]))
    }
}

/// The multiplier M = e^{ct}.
struct ExpMultiplier {
    c: f64,
}
impl PhaseFunction<1> for ExpMultiplier {
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, _q: &SVector<D, 1>, _p: &SVector<D, 1>) -> D {
        (t * self.c).exp()
    }
}
impl ScalarField<2> for ExpMultiplier {
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, _x: &SVector<D, 2>) -> D {
        (t * self.c).exp()
    }
}

/// The damped pendulum as a first-order system x = (θ, θ̇).
struct DampedField {
    c: f64,
}
impl VectorField<2> for DampedField {
    fn field<D: DualNum<f64> + Copy>(&self, _t: D, x: &SVector<D, 2>) -> SVector<D, 2> {
        SVector::from([x[1], -x[0].sin() - x[1] * self.c])
    }
}

/// Lotka–Volterra ẋ = x(α − βy), ẏ = y(δx − γ): multiplier 1/(xy).
struct LotkaVolterra;
impl VectorField<2> for LotkaVolterra {
    fn field<D: DualNum<f64> + Copy>(&self, _t: D, x: &SVector<D, 2>) -> SVector<D, 2> {
        SVector::from([x[0] * (-x[1] * 0.5 + 1.1), x[1] * (x[0] * 0.3 - 0.7)])
    }
}
struct InverseProduct;
impl ScalarField<2> for InverseProduct {
    fn eval<D: DualNum<f64> + Copy>(&self, _t: D, x: &SVector<D, 2>) -> D {
        (x[0] * x[1]).recip()
    }
}
struct One;
impl ScalarField<2> for One {
    fn eval<D: DualNum<f64> + Copy>(&self, _t: D, _x: &SVector<D, 2>) -> D {
        D::from(1.0)
    }
}

/// `steps` RK4 steps of Hamilton's equations as a map, generic over the dual type (for its
/// Jacobian by AD through the integrator).
struct Rk4Flow<'a, H> {
    h: &'a H,
    dt: f64,
    steps: usize,
}
impl<H: Hamiltonian<1>> PhaseMap<1> for Rk4Flow<'_, H> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        let (mut q, mut p, dt) = (*q, *p, self.dt);
        for k in 0..self.steps {
            let t = t + dt * k as f64;
            let f =
                |t: D, q: &SVector<D, 1>, p: &SVector<D, 1>| self.h.vector_field_generic(t, q, p);
            let (a1, b1) = f(t, &q, &p);
            let (a2, b2) = f(
                t + dt * 0.5,
                &(q + a1 * D::from(0.5 * dt)),
                &(p + b1 * D::from(0.5 * dt)),
            );
            let (a3, b3) = f(
                t + dt * 0.5,
                &(q + a2 * D::from(0.5 * dt)),
                &(p + b2 * D::from(0.5 * dt)),
            );
            let (a4, b4) = f(t + dt, &(q + a3 * D::from(dt)), &(p + b3 * D::from(dt)));
            let w = D::from(dt / 6.0);
            q += (a1 + (a2 + a3) * D::from(2.0) + a4) * w;
            p += (b1 + (b2 + b3) * D::from(2.0) + b4) * w;
        }
        (q, p)
    }
}

/// det of the central-difference Jacobian (step `e`) of the RK4 flow map over `t_end`.
fn fd_determinant<H: Hamiltonian<1>>(
    h: &H,
    th: f64,
    pv: f64,
    t_end: f64,
    steps: usize,
    e: f64,
) -> f64 {
    let run = |th: f64, pv: f64| {
        let (q, p) = rk4_hamiltonian(
            h,
            0.0,
            SVector::from([th]),
            SVector::from([pv]),
            t_end / steps as f64,
            steps,
            |_, _, _| {},
        );
        (q[0], p[0])
    };
    let (a1, b1) = run(th + e, pv);
    let (a2, b2) = run(th - e, pv);
    let (a3, b3) = run(th, pv + e);
    let (a4, b4) = run(th, pv - e);
    ((a1 - a2) * (b3 - b4) - (a3 - a4) * (b1 - b2)) / (4.0 * e * e)
}

#[test]
fn multiplier_residuals() {
    let c = 0.2;
    let pts = [V2::new(2.0, 0.5), V2::new(-1.0, 3.0), V2::new(0.3, -0.7)];
    for (k, x) in pts.iter().enumerate() {
        let t = 0.7 * k as f64;
        // e^{ct} is a multiplier of the damped pendulum; 1 is not (residual = div X = −c).
        let r = multiplier_residual(&DampedField { c }, &ExpMultiplier { c }, t, x).unwrap();
        assert!(r.abs() < 1e-15, "{r}");
        let r1 = multiplier_residual(&DampedField { c }, &One, t, x).unwrap();
        assert!((r1 + c).abs() < 1e-16);
        assert!((divergence(&DampedField { c }, t, x).unwrap() + c).abs() < 1e-16);
        // The same in Hamiltonian form, with the force Q = −c p.
        let (q, p) = (SVector::from([x[0]]), SVector::from([x[1]]));
        let sys = DampedPendulum { c };
        let rh = hamiltonian_multiplier_residual(&sys, &ExpMultiplier { c }, t, &q, &p).unwrap();
        assert!(rh.abs() < 1e-15, "{rh}");
        assert!((hamiltonian_divergence(&sys, t, &q, &p).unwrap() + c).abs() < 1e-16);
        // Conservative pendulum: M = 1 (Liouville).
        let pend = Pendulum::new(1.0).unwrap();
        let r0 = hamiltonian_multiplier_residual(&pend, &ExpMultiplier { c: 0.0 }, t, &q, &p);
        assert_eq!(r0.unwrap(), 0.0);
    }
    // Lotka–Volterra: M = 1/(xy) at positive populations; a residual of rounding size relative to
    // the terms M·∂X_r/∂x_r ~ 1.
    for x in [V2::new(1.0, 2.0), V2::new(3.0, 0.4), V2::new(0.2, 0.9)] {
        let r = multiplier_residual(&LotkaVolterra, &InverseProduct, 0.0, &x).unwrap();
        let terms = (1.1 - 0.5 * x[1]).abs() + (0.3 * x[0] - 0.7).abs();
        assert!(r.abs() <= 8.0 * f64::EPSILON * terms / (x[0] * x[1]), "{r}");
        // M = 1 is not a multiplier: its residual is div X = α − βy + δx − γ.
        let div = 1.1 - 0.5 * x[1] + 0.3 * x[0] - 0.7;
        let r1 = multiplier_residual(&LotkaVolterra, &One, 0.0, &x).unwrap();
        assert!((r1 - div).abs() < 1e-15 && div.abs() > 1e-3);
    }
    // Bad input.
    assert!(matches!(
        multiplier_residual(&LotkaVolterra, &One, f64::NAN, &V2::new(1.0, 1.0)),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        multiplier_residual(&LotkaVolterra, &InverseProduct, 0.0, &V2::new(0.0, 1.0)),
        Err(Error::NonFinite { .. })
    ));
}

#[test]
fn flow_determinants_by_variational_equations() {
    let (t_end, c) = (7.3, 0.2);
    let (q0, p0) = (SVector::from([2.0]), SVector::from([0.5]));
    let pend = Pendulum::new(1.0).unwrap();
    let damped = DampedPendulum { c };
    let exact_damped = (-c * t_end).exp();
    assert!((exact_damped - 0.232236274729759).abs() < 1e-15);

    // Error budget of det Φ from `variational_flow`:
    // * volume error of RK4: the discrete map's Jacobian differs from the flow's by O(Δt⁵) per
    //   step, so det Φ errs by C·T·Δt⁴; C is taken from the coarse run (730 steps, Δt = 0.01, where
    //   this term dominates), scaled by (730/n)⁴ — checked to hold within a factor 2;
    // * rounding: every step adds O(ε ‖Φ‖) to the entries; with compensated sums these errors
    //   random-walk, ~ √n ε ‖Φ‖ each, hence ~ 4 √n ε ‖Φ‖² in the 2 × 2 determinant.
    let mut runs = vec![];
    for steps in [730usize, 7300, 73_000] {
        let f = variational_flow(&pend, 0.0, &q0, &p0, t_end, steps).unwrap();
        let d = variational_flow(&damped, 0.0, &q0, &p0, t_end, steps).unwrap();
        // Liouville's formula along the computed motion: ∫ tr A dt = 0 and −cT, to the rounding of
        // the summation.
        assert_eq!(f.divergence_integral, 0.0);
        assert!((d.divergence_integral + c * t_end).abs() <= 4.0 * f64::EPSILON * c * t_end);
        let (ef, ed) = (
            (f.jacobian.determinant() - 1.0).abs(),
            (d.jacobian.determinant() - exact_damped).abs(),
        );
        // Jacobi's multiplier: M(T) det Φ(T) = M(0) with M = e^{ct}.
        let jac = (c * t_end).exp() * d.jacobian.determinant() - 1.0;
        let norm = f.jacobian.max_abs().max(d.jacobian.max_abs());
        println!(
            "flow determinants by variational equations, {steps} steps: |det − 1| = {ef:.2e}, |det − e^(−cT)| = {ed:.2e}, \
             M(T) det − M(0) = {jac:.2e}, ‖Φ‖ = {norm:.2}"
        );
        runs.push((steps as f64, ef, ed, norm));
    }
    let (n0, ef0, ed0, _) = runs[0];
    for &(n, ef, ed, norm) in &runs[1..] {
        let rounding = 4.0 * n.sqrt() * f64::EPSILON * norm * norm;
        let scale = (n0 / n).powi(4);
        assert!(
            ef <= 2.0 * ef0 * scale + rounding,
            "undamped, {n} steps: {ef:e}"
        );
        assert!(
            ed <= 2.0 * ed0 * scale + rounding,
            "damped, {n} steps: {ed:e}"
        );
        // The variational equations give both determinants to 1e−14.
        assert!(ef <= 1e-14 && ed <= 1e-14);
        assert!(((c * t_end).exp() * (ed + exact_damped) - 1.0).abs() < 1e-13);
    }
    let best = runs[1].1.max(runs[1].2);

    // The variational Φ is the exact Jacobian of the discrete RK4 map (internal differentiation):
    // AD through the integrator gives the same matrix to rounding.
    let steps = 7300;
    let dt = t_end / steps as f64;
    for (phi, ad) in [
        (
            variational_flow(&pend, 0.0, &q0, &p0, t_end, steps)
                .unwrap()
                .jacobian,
            jacobian(
                &Rk4Flow {
                    h: &pend,
                    dt,
                    steps,
                },
                0.0,
                &q0,
                &p0,
            )
            .unwrap(),
        ),
        (
            variational_flow(&damped, 0.0, &q0, &p0, t_end, steps)
                .unwrap()
                .jacobian,
            jacobian(
                &Rk4Flow {
                    h: &damped,
                    dt,
                    steps,
                },
                0.0,
                &q0,
                &p0,
            )
            .unwrap(),
        ),
    ] {
        let diff = phi.sub(&ad).max_abs();
        println!("variational Φ vs AD through the RK4 map: {diff:.1e}");
        assert!(
            diff <= 1e-12 * phi.max_abs(),
            "variational vs AD map: {diff}"
        );
    }

    // Central differences with e = 1e−6 of the same RK4 map (tests/common, plain summation): each
    // end state carries a rounding error δ ≲ n ε ‖Φ‖ |x| (n = 7300 steps, worst case without
    // compensation), each difference quotient errs by δ/e, the determinant by ~ 2 ‖Φ‖ δ/e — about
    // 1e−7 as a bound, measured a few 1e−9: the expected "integration error divided by e", five
    // orders above the variational result. (The truncation e² |∂³x/∂x₀³| is ~ 1e−12.)
    let e = 1e-6;
    let steps = 7300;
    let fd_f = (fd_determinant(&pend, q0[0], p0[0], t_end, steps, e) - 1.0).abs();
    let fd_d = (fd_determinant(&damped, q0[0], p0[0], t_end, steps, e) - exact_damped).abs();
    println!("flow determinants by central differences (e = 1e-6), {steps} steps: |det − 1| = {fd_f:.2e}, |det − e^(−cT)| = {fd_d:.2e}");
    let norm = runs[1].3;
    let delta = steps as f64 * f64::EPSILON * norm * q0[0].abs().max(p0[0].abs());
    let fd_bound = 2.0 * norm * delta / e + 1e-11;
    assert!(
        fd_f <= fd_bound && fd_d <= fd_bound,
        "FD {fd_f} {fd_d} bound {fd_bound}"
    );
    assert!(
        fd_f.min(fd_d) > 100.0 * best.max(1e-16),
        "FD no worse than the variational result?"
    );

    // Bad input.
    assert!(matches!(
        variational_flow(&pend, 0.0, &q0, &p0, t_end, 0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        variational_flow(&pend, 0.0, &SVector::from([f64::NAN]), &p0, t_end, 10),
        Err(Error::NonFinite { .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// Two degrees of freedom [Ardema eqs. 15.46–15.55]: central force (Kepler).
// ---------------------------------------------------------------------------------------------

/// Central force in polar coordinates (r, θ): p_r = √(2h + 2μ/r − a²/r²), p_θ = a.
struct KeplerPolar {
    mu: f64,
}
impl TwoDofMomenta for KeplerPolar {
    fn momenta<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 2>, h: D, a: D) -> SVector<D, 2> {
        let r = q[0];
        SVector::from([
            (h * 2.0 + r.recip() * (2.0 * self.mu) - a * a / (r * r)).sqrt(),
            a,
        ])
    }
}

/// The same momenta in Cartesian coordinates: p = p_r r̂ + (a/r) θ̂ (mixed partials non-zero but
/// equal).
struct KeplerCartesian {
    mu: f64,
}
impl TwoDofMomenta for KeplerCartesian {
    fn momenta<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 2>, h: D, a: D) -> SVector<D, 2> {
        let r = (q[0] * q[0] + q[1] * q[1]).sqrt();
        let pr = (h * 2.0 + r.recip() * (2.0 * self.mu) - a * a / (r * r)).sqrt();
        let (c, s) = (q[0] / r, q[1] / r);
        let at = a / r;
        SVector::from([pr * c - at * s, pr * s + at * c])
    }
}

/// Not an exact form: f = (−q₂, q₁).
struct Rotation;
impl TwoDofMomenta for Rotation {
    fn momenta<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 2>, _h: D, _a: D) -> SVector<D, 2> {
        SVector::from([-q[1], q[0]])
    }
}

#[test]
fn two_dof_quadrature_kepler_time_and_orbit() {
    // μ = 1, h = −½ (semi-major axis 1), a = 0.8: e = √(1 + 2 h a²) = 0.6, r ∈ [0.4, 1.6].
    let (mu, h, a) = (1.0, -0.5, 0.8);
    let e: f64 = (1.0 + 2.0 * h * a * a).sqrt();
    let (r0, r1) = (0.6, 1.2);
    // Orbit equation along r at fixed θ: ∂K/∂a = −∫ a dr/(r²√…); the orbit reaches r₁ at θ₁ = −that.
    let radial = two_dof_quadrature(
        &KeplerPolar { mu },
        h,
        a,
        &[V2::new(r0, 0.0), V2::new(r1, 0.0)],
    )
    .unwrap();
    let theta1 = -radial.dk_da;
    let q = two_dof_quadrature(
        &KeplerPolar { mu },
        h,
        a,
        &[V2::new(r0, 0.0), V2::new(r1, theta1)],
    )
    .unwrap();
    assert_eq!(q.exactness_defect, 0.0);
    // Two quadratures of the same integral to ~1e−14 each (relative to θ₁ ~ 1).
    assert!(q.dk_da.abs() < 1e-13, "orbit equation {}", q.dk_da);
    // Exact Kepler: r = 1 − e cos E, t = E − e sin E (n = 1), tan(ν/2) = √((1+e)/(1−e)) tan(E/2).
    let ecc = |r: f64| ((1.0 - r) / e).acos();
    let (e0, e1) = (ecc(r0), ecc(r1));
    let t_exact = (e1 - e * e1.sin()) - (e0 - e * e0.sin());
    let nu = |ea: f64| 2.0 * (((1.0 + e) / (1.0 - e)).sqrt() * (ea / 2.0).tan()).atan();
    let theta_exact = nu(e1) - nu(e0);
    println!(
        "Kepler quadrature: t = {:.16} (exact {t_exact:.16}), θ₁ = {theta1:.16} (exact {theta_exact:.16}), \
         error estimate {:.1e}",
        q.dk_dh, q.error_estimate
    );
    assert!((q.dk_dh - t_exact).abs() < 1e-13);
    assert!((theta1 - theta_exact).abs() < 1e-13);
    // K = ∫ p_r dr + a Δθ.
    assert!((q.k - (radial.k + a * theta1)).abs() < 1e-13);

    // Hamilton's equations from (r₀, 0) with p_r > 0 for the time ∂K/∂h end at (r₁, θ₁).
    // RK4 global error ~ T Δt⁴ ω⁵ |x| with the orbital rate ω ≲ r^{−3/2} ≤ 2.2 on the arc: T = 0.95,
    // Δt = T/4000 ≈ 2.4e−4 give ≈ 2e−13; tolerance 2e−12.
    let pr0 = (2.0 * h + 2.0 * mu / r0 - a * a / (r0 * r0)).sqrt();
    let steps = 4000;
    let kep = Kepler2::new(mu).unwrap();
    let (qe, _) = rk4_hamiltonian(
        &kep,
        0.0,
        V2::new(r0, 0.0),
        V2::new(pr0, a / r0),
        q.dk_dh / steps as f64,
        steps,
        |_, _, _| {},
    );
    let (r_end, th_end) = (qe.norm(), qe[1].atan2(qe[0]));
    println!(
        "Kepler RK4 to t = ∂K/∂h: r − r₁ = {:.1e}, θ − θ₁ = {:.1e}",
        r_end - r1,
        th_end - theta1
    );
    assert!((r_end - r1).abs() < 2e-12 && (th_end - theta1).abs() < 2e-12);

    // Cartesian momenta along the straight chord: same integrals (exact form, path independence),
    // mixed partials equal to rounding.
    let qc = two_dof_quadrature(
        &KeplerCartesian { mu },
        h,
        a,
        &[
            V2::new(r0, 0.0),
            V2::new(r1 * theta1.cos(), r1 * theta1.sin()),
        ],
    )
    .unwrap();
    println!(
        "Cartesian chord: exactness defect {:.1e}",
        qc.exactness_defect
    );
    assert!(qc.exactness_defect < 1e-13);
    assert!((qc.dk_dh - q.dk_dh).abs() < 1e-13);
    assert!(qc.dk_da.abs() < 1e-13);
    assert!((qc.k - q.k).abs() < 1e-13);

    // A non-exact form reports its defect.
    let rot =
        two_dof_quadrature(&Rotation, 0.0, 0.0, &[V2::new(1.0, 0.0), V2::new(0.0, 1.0)]).unwrap();
    assert_eq!(rot.exactness_defect, 2.0);
    // A path through the forbidden region r > 1.6 is refused, as are bad inputs.
    assert!(matches!(
        two_dof_quadrature(
            &KeplerPolar { mu },
            h,
            a,
            &[V2::new(r0, 0.0), V2::new(1.8, 0.0)]
        ),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        two_dof_quadrature(&KeplerPolar { mu }, h, a, &[V2::new(r0, 0.0)]),
        Err(Error::InvalidInput { .. })
    ));
    assert!(matches!(
        two_dof_quadrature(
            &KeplerPolar { mu },
            f64::NAN,
            a,
            &[V2::new(r0, 0.0), V2::new(r1, 0.0)]
        ),
        Err(Error::NonFinite { .. })
    ));
}

// ---------------------------------------------------------------------------------------------
// Liouville's separable systems [Ardema 8.4, eqs. 8.38–8.40].
// ---------------------------------------------------------------------------------------------

/// The quartic Liouville system U = q₁² + q₂², v₁ = v₂ = 1, W = q₁⁴ + q₂⁴.
#[derive(Clone, Copy, Debug)]
struct QuarticLiouville;
impl LiouvilleSystem<2> for QuarticLiouville {
    fn u<D: DualNum<f64> + Copy>(&self, _s: usize, q: D) -> D {
        q * q
    }
    fn v<D: DualNum<f64> + Copy>(&self, _s: usize, _q: D) -> D {
        D::from(1.0)
    }
    fn w<D: DualNum<f64> + Copy>(&self, _s: usize, q: D) -> D {
        q.powi(4)
    }
}

/// A less symmetric Liouville system for the property test.
#[derive(Clone, Copy, Debug)]
struct Mixed;
impl LiouvilleSystem<3> for Mixed {
    fn u<D: DualNum<f64> + Copy>(&self, s: usize, q: D) -> D {
        [q * q + 1.0, q.cos() + 2.0, q.exp()][s]
    }
    fn v<D: DualNum<f64> + Copy>(&self, s: usize, q: D) -> D {
        [D::from(1.0), q * q + 0.5, (q * 0.3).sin() + 1.5][s]
    }
    fn w<D: DualNum<f64> + Copy>(&self, s: usize, q: D) -> D {
        [q.powi(4), q * 3.0, (q * 2.0).sin()][s]
    }
}

#[test]
fn liouville_integrals_constant() {
    let (q0, v0) = (V2::new(1.0, 0.5), V2::new(0.2, -0.3));
    let (h0, g0) = liouville_separated_integrals(&QuarticLiouville, &q0, &v0).unwrap();
    assert!((h0 - 0.93125).abs() < 1e-15);
    assert!((g0[0] - 0.1).abs() < 1e-15);
    let l = Liouville(QuarticLiouville);
    assert!((l.jacobi_integral(0.0, &q0, &v0).unwrap() - h0).abs() < 1e-15);
    // RK4 on Lagrange's equations (accelerations by AD through the Lagrangian). RK4 is not
    // conservative: an integral drifts by C·T·Δt⁴. The constant is fixed by the run itself: at
    // Δt = 1e−3 and 5e−4 the drift must fall by 2⁴ = 16 (±50 %, i.e. the asymptotic regime of the
    // fourth-order method); extrapolating that law to Δt = 2e−4 (25 000 steps) gives a drift
    // (2/5)⁴ ≈ 0.026 of the 5e−4 one, which the final run must meet and which lies below the 1e−12
    // to which h and γ₁ are required to stay constant.
    let drift = |dt: f64| {
        let steps = (5.0 / dt).round() as usize;
        let mut worst = (0.0f64, 0.0f64, 0.0f64);
        rk4_lagrangian(&l, 0.0, q0, v0, dt, steps, |_, q, v| {
            let (h, g) = liouville_separated_integrals(&QuarticLiouville, q, v).unwrap();
            worst.0 = worst.0.max((h - h0).abs());
            worst.1 = worst.1.max((g[0] - g0[0]).abs());
            worst.2 = worst.2.max((g[0] + g[1]).abs());
        });
        println!(
            "Liouville integrals over 5 s, Δt = {dt:e}: |Δh| ≤ {:.1e}, |Δγ₁| ≤ {:.1e}, |Σγ| ≤ {:.1e}",
            worst.0, worst.1, worst.2
        );
        worst
    };
    let (coarse, mid, fine) = (drift(1e-3), drift(5e-4), drift(2e-4));
    for (c, m) in [(coarse.0, mid.0), (coarse.1, mid.1)] {
        assert!(
            (8.0..=24.0).contains(&(c / m)),
            "not in the Δt⁴ regime: {c:e} → {m:e}"
        );
    }
    let predicted = |m: f64| m * 0.4f64.powi(4) * 1.5 + 1e-14;
    assert!(fine.0 <= predicted(mid.0) && fine.1 <= predicted(mid.1));
    assert!(fine.0 < 1e-12 && fine.1 < 1e-12);
    assert!(coarse.2.max(mid.2).max(fine.2) < 1e-14);
    // U = 0 (at the origin) and NaN are typed errors.
    assert!(matches!(
        liouville_separated_integrals(&QuarticLiouville, &V2::zeros(), &v0),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        liouville_separated_integrals(&QuarticLiouville, &V2::new(f64::NAN, 0.0), &v0),
        Err(Error::NonFinite { .. })
    ));
}

proptest! {
    #![proptest_config(config(39))]
    /// Σ γ_s = 0 identically (to rounding relative to the terms ½U²v_s q̇_s², h u_s, w_s), and h is
    /// the Lagrangian's Jacobi integral.
    #[test]
    fn liouville_gammas_sum_to_zero(
        q in prop::array::uniform3(-2.0f64..2.0),
        v in prop::array::uniform3(-3.0f64..3.0),
    ) {
        let (q, v) = (SVector::from(q), SVector::from(v));
        let (h, g) = liouville_separated_integrals(&Mixed, &q, &v).unwrap();
        let u: f64 = (0..3).map(|s| Mixed.u(s, q[s])).sum();
        let scale: f64 = (0..3)
            .map(|s| {
                0.5 * u * u * Mixed.v(s, q[s]) * v[s] * v[s]
                    + (h * Mixed.u(s, q[s])).abs()
                    + Mixed.w(s, q[s]).abs()
            })
            .sum();
        prop_assert!(g.sum().abs() <= 16.0 * f64::EPSILON * scale, "Σγ = {}", g.sum());
        let jac = Liouville(Mixed).jacobi_integral(0.0, &q, &v).unwrap();
        prop_assert!((jac - h).abs() <= 16.0 * f64::EPSILON * (scale / u.abs()).max(h.abs()));
    }
}

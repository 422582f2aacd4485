//! Lagrangian core: Legendre transform (general and natural), Lagrange's equations, Rayleigh
//! dissipation, Jacobi integral [Ardema 8.2], Routhian [Ardema 8.3], round trip L → H → L.

mod common;

use approx::assert_relative_eq;
use hamilton_jacobi::lagrangian::{InverseLegendre, Routhian};
use hamilton_jacobi::nalgebra::{SMatrix, SVector};
use hamilton_jacobi::systems::BeadOnHoop;
use hamilton_jacobi::{
    DualNum, Error, Hamiltonian, Lagrangian, Legendre, Natural, NaturalHamiltonian, NaturalSystem,
};
use proptest::prelude::*;

const EPS: f64 = f64::EPSILON;

// ---------------------------------------------------------------------------------------------
// Bead on a rotating hoop [Ardema 8.2] — the Jacobi integral is conserved, T + V is not.

#[test]
fn bead_on_hoop_jacobi_integral() {
    let bead = BeadOnHoop::new(1.0, 0.5, 9.81, 6.0).unwrap();
    let (q0, v0) = (SVector::from([0.3]), SVector::from([0.0]));
    let h0 = bead.jacobi_integral(0.0, &q0, &v0).unwrap();
    // Published value h = −5.07892034561 (12 digits).
    assert_relative_eq!(h0, -5.07892034561, epsilon = 1e-11);
    let (mut hmin, mut hmax) = (h0, h0);
    let (mut emin, mut emax) = (f64::MAX, f64::MIN);
    // RK4 with dt = 5e−4 over 10 s: local error ~ (ω dt)^5 ≈ 2e−11 relative per step at the
    // fastest time scale, and energy-like errors of RK4 accumulate to ≲ 1e−12 here.
    common::rk4_lagrangian(&bead, 0.0, q0, v0, 5e-4, 20_000, |t, q, v| {
        let h = bead.jacobi_integral(t, q, v).unwrap();
        hmin = hmin.min(h);
        hmax = hmax.max(h);
        let e = bead.energy(q[0], v[0]).unwrap();
        emin = emin.min(e);
        emax = emax.max(e);
    });
    assert!(
        hmax - hmin < 1e-10,
        "Jacobi integral spread {}",
        hmax - hmin
    );
    // T + V ranges over [−4.29, 3.76] (3 digits given).
    assert!(
        (emin + 4.29).abs() < 5e-3 && (emax - 3.76).abs() < 5e-3,
        "T + V in [{emin}, {emax}]"
    );
    // Relative equilibrium and its frequency: 0.994407212058699, 5.03061626443520.
    let (th, freq) = bead.relative_equilibrium().unwrap();
    assert_relative_eq!(th, 0.994407212058699, epsilon = 1e-14);
    assert_relative_eq!(freq, 5.03061626443520, epsilon = 1e-13);
    // The same frequency from the AD linearisation of Lagrange's equations at θ*.
    let qs = SVector::from([th]);
    let zero = SVector::from([0.0]);
    assert!(bead.accelerations(0.0, &qs, &zero).unwrap()[0].abs() < 1e-13);
    let m = bead.mass_matrix(0.0, &qs, &zero).unwrap()[(0, 0)];
    let k = -hessian_qq(&bead, &qs);
    assert_relative_eq!((k / m).sqrt(), 5.03061626443520, epsilon = 1e-12);
}

/// ∂²L/∂θ² at rest, from the AD Hessian of L over (q, q̇).
fn hessian_qq<L: Lagrangian<1>>(l: &L, q: &SVector<f64, 1>) -> f64 {
    let (_, _, _, h) = hamilton_jacobi::ad::phase_hessian(
        |a, b| l.lagrangian(From::from(0.0), a, b),
        q,
        &SVector::from([0.0]),
    );
    h.qq[(0, 0)]
}

// ---------------------------------------------------------------------------------------------
// Two masses and a spring — Routhian [Ardema 8.3].

#[derive(Clone)]
struct TwoMasses {
    m1: f64,
    m2: f64,
    k: f64,
    l: f64,
}
impl Lagrangian<2> for TwoMasses {
    /// L = ½ m₁ ẋ² + ½ m₂ (ẋ + ẏ)² − ½ k (y − ℓ)², coordinates (x, y), x ignorable.
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        let s = v[0] + v[1];
        v[0] * v[0] * (0.5 * self.m1) + s * s * (0.5 * self.m2)
            - (q[1] - self.l) * (q[1] - self.l) * (0.5 * self.k)
    }
}

#[test]
fn routhian_reduced_frequency() {
    let sys = TwoMasses {
        m1: 1.0,
        m2: 2.0,
        k: 5.0,
        l: 1.0,
    };
    let c = 1.2;
    let r: Routhian<_, 2, 1> = Routhian::new(sys.clone(), &[0], &[c]).unwrap();
    // R = −(C − m₂ẏ)²/(2(m₁ + m₂)) + ½ m₂ ẏ² − ½ k (y − ℓ)² at a few points.
    for (y, yd) in [(1.1, 0.0), (0.7, 0.4), (1.6, -1.3)] {
        let (ys, yds) = (SVector::from([y]), SVector::from([yd]));
        let expected = -(c - sys.m2 * yd).powi(2) / (2.0 * (sys.m1 + sys.m2))
            + 0.5 * sys.m2 * yd * yd
            - 0.5 * sys.k * (y - sys.l).powi(2);
        assert_relative_eq!(
            r.value(0.0, &ys, &yds).unwrap(),
            expected,
            epsilon = 16.0 * EPS * (1.0 + expected.abs())
        );
        let xd = r.ignorable_velocities(0.0, &ys, &yds).unwrap()[0];
        assert_relative_eq!(
            xd,
            (c - sys.m2 * yd) / (sys.m1 + sys.m2),
            epsilon = 8.0 * EPS
        );
    }
    // Reduced equation (m₁m₂/(m₁+m₂)) ÿ + k(y − ℓ) = 0: ω = 2.73861278752583, period 2.29429488381819.
    let (ys, zero) = (SVector::from([1.0]), SVector::from([0.0]));
    let mass = r.mass_matrix(0.0, &ys, &zero).unwrap()[(0, 0)];
    assert_relative_eq!(mass, 2.0 / 3.0, epsilon = 1e-14);
    let omega = (-hessian_qq(&r, &ys) / mass).sqrt();
    assert_relative_eq!(omega, 2.73861278752583, epsilon = 1e-13);
    assert_relative_eq!(
        2.0 * std::f64::consts::PI / omega,
        2.29429488381819,
        epsilon = 1e-13
    );
    // The full motion from y(0) = 1.1, ẋ(0) = 0.4 (C = 1.2) returns to y = 1.1 after one reduced period,
    // with C conserved; RK4 at dt = period/4000 has error ~ (ω dt)^4 ≈ 6e−12.
    let period = 2.29429488381819;
    let steps = 4000;
    let (q, v) = common::rk4_lagrangian(
        &sys,
        0.0,
        SVector::from([0.0, 1.1]),
        SVector::from([0.4, 0.0]),
        period / steps as f64,
        steps,
        |_, _, _| {},
    );
    assert_relative_eq!(q[1], 1.1, epsilon = 1e-10);
    assert_relative_eq!(v[1], 0.0, epsilon = 1e-9);
    let cm = sys.momentum(0.0, &q, &v).unwrap()[0];
    assert_relative_eq!(cm, 1.2, epsilon = 1e-13);
    // Bad reductions.
    assert!(Routhian::<_, 2, 1>::new(sys.clone(), &[2], &[c]).is_err());
    assert!(Routhian::<_, 2, 1>::new(sys.clone(), &[0], &[f64::NAN]).is_err());
    assert!(Routhian::<_, 2, 0>::new(sys, &[0], &[c]).is_err());
}

// ---------------------------------------------------------------------------------------------
// Legendre transform: general Newton vs the natural closed form; Rayleigh dissipation.

/// A natural system with configuration-dependent mass, gyroscopic and T₀ terms: a particle in a
/// rotating frame with position-dependent inertia.
#[derive(Clone)]
struct Rotating {
    omega: f64,
}
impl NaturalSystem<2> for Rotating {
    fn mass<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> SMatrix<D, 2, 2> {
        let a = q[0] * q[0] * 0.3 + 1.0;
        let b = (q[1] * 0.5).sin() * 0.2;
        SMatrix::from([[a, b], [b, q[1] * q[1] * 0.1 + 2.0]])
    }
    fn linear<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> SVector<D, 2> {
        SVector::from([-q[1] * self.omega, q[0] * self.omega])
    }
    fn constant_kinetic<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> D {
        q.dot(q) * (0.5 * self.omega * self.omega)
    }
    fn potential<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 2>) -> D {
        q[0].cos() * -1.0 + q[1] * q[1] * q[0] * 0.2 + t * 0.1 * q[1]
    }
}

#[test]
fn legendre_newton_matches_natural_closed_form() {
    let sys = Rotating { omega: 0.7 };
    let general = Legendre(Natural(sys.clone()));
    let closed = NaturalHamiltonian(sys.clone());
    for (t, q, p) in [
        (0.0, [0.3, -0.2], [1.0, 0.5]),
        (1.5, [-1.1, 0.8], [-0.4, 2.0]),
        (3.0, [2.0, 1.5], [0.0, -1.0]),
    ] {
        let (q, p) = (SVector::from(q), SVector::from(p));
        let hg = general.value(t, &q, &p).unwrap();
        let hc = closed.value(t, &q, &p).unwrap();
        assert_relative_eq!(hg, hc, epsilon = 32.0 * EPS * (1.0 + hc.abs()));
        let (a, b) = general.vector_field(t, &q, &p).unwrap();
        let (c, d) = closed.vector_field(t, &q, &p).unwrap();
        assert_relative_eq!(a, c, epsilon = 1e-13);
        assert_relative_eq!(b, d, epsilon = 1e-13);
        // Second derivatives through the implicit solve (nested duals).
        let hsg = general.hessian(t, &q, &p).unwrap();
        let hsc = closed.hessian(t, &q, &p).unwrap();
        assert!(
            hsg.sub(&hsc).max_abs() < 1e-12,
            "Hessians differ by {}",
            hsg.sub(&hsc).max_abs()
        );
        // ∂H/∂t = −∂L/∂t [Ardema eq. 15.13].
        let v = general.velocity(t, &q, &p).unwrap();
        let lt = hamilton_jacobi::brackets::partial_t(&LagAsFn(Natural(sys.clone())), t, &q, &v)
            .unwrap();
        assert_relative_eq!(general.partial_t(t, &q, &p).unwrap(), -lt, epsilon = 1e-14);
        // Hamilton's q̇ is the velocity that produced p.
        assert_relative_eq!(a, v, epsilon = 1e-14);
        assert_relative_eq!(
            Natural(sys.clone()).momentum(t, &q, &v).unwrap(),
            p,
            epsilon = 1e-13
        );
    }
}

struct LagAsFn<L>(L);
impl<L: Lagrangian<2>> hamilton_jacobi::PhaseFunction<2> for LagAsFn<L> {
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        self.0.lagrangian(t, q, v)
    }
}

/// Damped oscillator: L = ½ m q̇² − ½ k q², Rayleigh D = ½ c q̇² (crate sign, D ≥ 0).
struct Damped {
    c: f64,
}
impl Lagrangian<1> for Damped {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 1>, v: &SVector<D, 1>) -> D {
        (v[0] * v[0] * 2.0 - q[0] * q[0] * 3.0) * 0.5
    }
    fn dissipation<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 1>,
        v: &SVector<D, 1>,
    ) -> Option<D> {
        Some(v[0] * v[0] * (0.5 * self.c))
    }
}

#[test]
fn rayleigh_dissipation_convention() {
    let l = Damped { c: 0.4 };
    let (q, v) = (SVector::from([0.8]), SVector::from([-1.5]));
    // m q̈ = −k q − c q̇  (Q^d = −∂D/∂q̇).
    let a = l.accelerations(0.0, &q, &v).unwrap()[0];
    assert_relative_eq!(a, (-3.0 * 0.8 + 0.4 * 1.5) / 2.0, epsilon = 4.0 * EPS);
    assert!(
        l.lagrange_residual(0.0, &q, &v, &SVector::from([a]))
            .unwrap()[0]
            .abs()
            < 8.0 * EPS
    );
    // d(T + V)/dt = −2D ≤ 0, through the Hamiltonian side's generalized force.
    let h = Legendre(l);
    let p = SVector::from([2.0 * v[0]]);
    let rate = h.energy_rate(0.0, &q, &p).unwrap();
    assert_relative_eq!(rate, -2.0 * 0.5 * 0.4 * v[0] * v[0], epsilon = 8.0 * EPS);
}

#[test]
fn lagrange_residual_vanishes_on_exact_motion() {
    // L = ½ma²(θ̇² + ω² sin²θ) + mga cos θ depends on θ through both T₀ and V, so the residual
    // E = ma²θ̈ − ma²ω² sin θ cos θ + mga sin θ (written out by hand, not by AD) exercises ∂L/∂q.
    let (m, a, g, w) = (1.3, 0.7, 9.81, 5.0);
    let bead = BeadOnHoop::new(m, a, g, w).unwrap();
    let ma2 = m * a * a;
    for (th, thd) in [(0.4, 2.0), (-1.1, 0.3), (2.5, -1.7)] {
        let (s, c) = f64::sin_cos(th);
        // On the motion θ̈ = sin θ (ω² cos θ − g/a) the residual vanishes up to rounding of the
        // O(ma²ω²) terms.
        let thdd = s * (w * w * c - g / a);
        let scale = ma2 * (w * w + g / a + thdd.abs());
        let r = bead
            .lagrange_residual(
                0.0,
                &SVector::from([th]),
                &SVector::from([thd]),
                &SVector::from([thdd]),
            )
            .unwrap();
        assert!(r[0].abs() <= 16.0 * EPS * scale, "θ = {th}: residual {r}");
        // Off the motion, the residual is the closed form: here ma²·δ for θ̈ = θ̈* + δ, and at θ̈ = 0
        // the generalized force −ma²ω² sin θ cos θ + mga sin θ.
        for thdd in [thdd + 0.25, 0.0] {
            let expected = ma2 * thdd - ma2 * w * w * s * c + m * g * a * s;
            let r = bead
                .lagrange_residual(
                    0.0,
                    &SVector::from([th]),
                    &SVector::from([thd]),
                    &SVector::from([thdd]),
                )
                .unwrap();
            assert_relative_eq!(r[0], expected, epsilon = 16.0 * EPS * scale);
        }
    }
}

#[test]
fn singular_and_bad_inputs_are_typed_errors() {
    struct Degenerate;
    impl Lagrangian<2> for Degenerate {
        /// L = ½ (q̇₁ + q̇₂)²: rank-one mass matrix.
        fn lagrangian<D: DualNum<f64> + Copy>(
            &self,
            _t: D,
            _q: &SVector<D, 2>,
            v: &SVector<D, 2>,
        ) -> D {
            (v[0] + v[1]) * (v[0] + v[1]) * 0.5
        }
    }
    let z = SVector::from([0.0, 0.0]);
    assert!(matches!(
        Degenerate.accelerations(0.0, &z, &z),
        Err(Error::Singular { .. })
    ));
    assert!(matches!(
        Legendre(Degenerate).velocity(0.0, &z, &z),
        Err(Error::Singular { .. })
    ));
    assert!(matches!(
        Legendre(Degenerate).vector_field(0.0, &z, &z),
        Err(Error::Singular { .. })
    ));
    let nan = SVector::from([f64::NAN, 0.0]);
    assert!(matches!(
        Degenerate.accelerations(0.0, &nan, &z),
        Err(Error::NonFinite { .. })
    ));
    assert!(BeadOnHoop::new(-1.0, 1.0, 9.81, 1.0).is_err());
    assert!(BeadOnHoop::new(1.0, 0.0, 9.81, 1.0).is_err());
}

// ---------------------------------------------------------------------------------------------
// Round trip L → H → L (proptest), on a non-quadratic Lagrangian: a relativistic charged particle,
// L = −m √(1 − |v|²) + A(q)·v − V(q), H = √(m² + |p − A|²) + V.

#[derive(Clone, Debug)]
struct Relativistic {
    m: f64,
    b: f64,
}
impl Lagrangian<2> for Relativistic {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        let a = SVector::from([-q[1] * (0.5 * self.b), q[0] * (0.5 * self.b)]);
        (-(v.dot(v)) + 1.0).sqrt() * -self.m + a.dot(v) - q.dot(q) * 0.5
    }
}

fn relativistic_h(s: &Relativistic, q: &SVector<f64, 2>, p: &SVector<f64, 2>) -> f64 {
    let a = SVector::from([-q[1] * 0.5 * s.b, q[0] * 0.5 * s.b]);
    (s.m * s.m + (p - a).norm_squared()).sqrt() + 0.5 * q.dot(q)
}

proptest! {
    #![proptest_config(common::config(0x5eed_0002))]

    #[test]
    fn legendre_round_trip(m in 0.5..3.0f64, b in -2.0..2.0f64,
                           q in prop::array::uniform2(-2.0..2.0f64),
                           speed in 0.0..0.95f64, angle in 0.0..std::f64::consts::TAU, t in -3.0..3.0f64) {
        let sys = Relativistic { m, b };
        let q = SVector::from(q);
        let v = SVector::from([speed * angle.cos(), speed * angle.sin()]);
        let p = sys.momentum(t, &q, &v).unwrap();
        let h = Legendre(sys.clone());
        // H agrees with its closed form; conditioning of the solve grows like γ³ = (1 − v²)^{-3/2} ≤ 33.
        let hv = h.value(t, &q, &p).unwrap();
        let hc = relativistic_h(&sys, &q, &p);
        prop_assert!((hv - hc).abs() <= 1e-13 * (1.0 + hc.abs()), "H {hv} vs {hc}");
        // L → H → L.
        let back = InverseLegendre(Legendre(sys.clone()));
        let l0 = sys.value(t, &q, &v).unwrap();
        let l1 = back.value(t, &q, &v).unwrap();
        prop_assert!((l0 - l1).abs() <= 1e-12 * (1.0 + l0.abs()), "L {l0} vs {l1}");
        // ... and the velocities map back.
        let v1 = h.velocity(t, &q, &p).unwrap();
        prop_assert!((v1 - v).norm() <= 1e-12, "v {v1} vs {v}");
    }
}

// ---------------------------------------------------------------------------------------------
// Robustness: badly scaled but regular problems, degenerate starts, non-finite results.

/// Planar Kepler in polar coordinates (r, θ) in SI units: L = ½(ṙ² + r²θ̇²) + μ/r.
struct PolarKepler {
    mu: f64,
}
impl Lagrangian<2> for PolarKepler {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        (v[0] * v[0] + q[0] * q[0] * v[1] * v[1]) * 0.5 + q[0].recip() * self.mu
    }
}

#[test]
fn badly_scaled_mass_matrix_is_not_singular() {
    // Earth's orbit: mass matrix diag(1, r²) with r² ≈ 2.2e22.
    let sys = PolarKepler { mu: 1.327e20 };
    let (q, v) = (SVector::from([1.5e11, 0.3]), SVector::from([120.0, 2.0e-7]));
    let a = sys.accelerations(0.0, &q, &v).unwrap();
    // r̈ = r θ̇² − μ/r², θ̈ = −2 ṙ θ̇ / r.
    let rdd = q[0] * v[1] * v[1] - sys.mu / (q[0] * q[0]);
    assert_relative_eq!(a[0], rdd, epsilon = 1e-12 * rdd.abs());
    assert_relative_eq!(
        a[1],
        -2.0 * v[0] * v[1] / q[0],
        epsilon = 1e-12 * (2.0 * v[0] * v[1] / q[0]).abs()
    );
    let p = sys.momentum(0.0, &q, &v).unwrap();
    let v2 = Legendre(PolarKepler { mu: sys.mu })
        .velocity(0.0, &q, &p)
        .unwrap();
    assert_relative_eq!(v2[0], v[0], epsilon = 1e-13 * v[0].abs());
    assert_relative_eq!(v2[1], v[1], epsilon = 1e-13 * v[1].abs());
}

/// L = q̇⁴/4: the mass matrix 3q̇² vanishes at q̇ = 0, the default Newton start.
struct Quartic;
impl Lagrangian<1> for Quartic {
    fn lagrangian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 1>,
        v: &SVector<D, 1>,
    ) -> D {
        v[0].powi(4) * 0.25
    }
}

#[test]
fn degenerate_start_and_non_finite_results_are_handled() {
    let h = Legendre(Quartic);
    let (q, p) = (SVector::from([0.0]), SVector::from([8.0]));
    // p = q̇³ ⇒ q̇ = 2, H = p q̇ − q̇⁴/4 = 16 − 4 = 12.
    assert_relative_eq!(
        h.velocity(0.0, &q, &p).unwrap()[0],
        2.0,
        epsilon = 4.0 * EPS
    );
    assert_relative_eq!(h.value(0.0, &q, &p).unwrap(), 12.0, epsilon = 16.0 * EPS);
    // At p = 0 the transform is singular (q̇ = 0, mass 0): typed errors, never Ok(NaN).
    let z = SVector::from([0.0]);
    assert!(matches!(
        h.velocity(0.0, &q, &z),
        Err(Error::Singular { .. })
    ));
    assert!(matches!(
        h.vector_field(0.0, &q, &z),
        Err(Error::Singular { .. })
    ));
    assert!(h.hessian(0.0, &q, &z).is_err());
    assert!(h.partial_t(0.0, &q, &z).is_err());
    assert!(h.energy_rate(0.0, &q, &z).is_err());
    // A Lagrangian that is NaN at the point.
    struct Sqrt;
    impl Lagrangian<1> for Sqrt {
        fn lagrangian<D: DualNum<f64> + Copy>(
            &self,
            _t: D,
            q: &SVector<D, 1>,
            v: &SVector<D, 1>,
        ) -> D {
            v[0] * v[0] * 0.5 - q[0].sqrt()
        }
    }
    let neg = SVector::from([-1.0]);
    assert!(matches!(
        Sqrt.value(0.0, &neg, &z),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        Sqrt.accelerations(0.0, &neg, &z),
        Err(Error::NonFinite { .. })
    ));
    assert!(matches!(
        Sqrt.jacobi_integral(0.0, &neg, &z),
        Err(Error::NonFinite { .. })
    ));
    let e = Sqrt
        .momentum(0.0, &z, &SVector::from([f64::NAN]))
        .unwrap_err();
    assert!(e.to_string().contains("q̇[0]"), "{e}");
}

#[test]
fn dissipative_legendre_tangent_matrix_differentiates_through_the_solve() {
    // m = 2, k = 3, Q^d = −c q̇ = −c p/m: the tangent matrix is [[0, 1/m], [−k, −c/m]].
    let h = Legendre(Damped { c: 0.4 });
    let a = h
        .tangent_matrix(0.0, &SVector::from([0.3]), &SVector::from([-0.7]))
        .unwrap();
    assert_relative_eq!(a.qq[(0, 0)], 0.0, epsilon = 4.0 * EPS);
    assert_relative_eq!(a.qp[(0, 0)], 0.5, epsilon = 4.0 * EPS);
    assert_relative_eq!(a.pq[(0, 0)], -3.0, epsilon = 8.0 * EPS);
    assert_relative_eq!(a.pp[(0, 0)], -0.2, epsilon = 4.0 * EPS);
}

#[test]
fn routhian_detects_a_coordinate_that_is_not_ignorable() {
    let sys = TwoMasses {
        m1: 1.0,
        m2: 2.0,
        k: 5.0,
        l: 1.0,
    };
    let good: Routhian<_, 2, 1> = Routhian::new(sys.clone(), &[0], &[1.2]).unwrap();
    let (y, yd) = (SVector::from([1.3]), SVector::from([0.2]));
    assert_eq!(good.ignorability_defect(0.0, &y, &yd).unwrap(), 0.0);
    // y is not ignorable: ∂L/∂y = −k(y − ℓ) ≠ 0 at y = 0 (where the reduction evaluates it).
    let bad: Routhian<_, 2, 1> = Routhian::new(sys, &[1], &[0.5]).unwrap();
    assert!(
        bad.ignorability_defect(0.0, &SVector::from([0.0]), &yd)
            .unwrap()
            > 1.0
    );
}

/// A planar particle with a rheonomic potential, a follower force and linear damping, in
/// Cartesian coordinates.
struct ForcedParticle;
impl Lagrangian<2> for ForcedParticle {
    fn lagrangian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 2>, v: &SVector<D, 2>) -> D {
        // ½m|v|² − (½k|q|² + t·x + q_x q_y²), m = 1.3, k = 0.7.
        v.dot(v) * 0.65 - q.dot(q) * 0.35 - t * q[0] - q[0] * q[1] * q[1]
    }
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 2>,
        _v: &SVector<D, 2>,
    ) -> Option<SVector<D, 2>> {
        Some(SVector::from([q[1] * 0.2 + t.sin(), -q[0] * 0.2]))
    }
    fn dissipation<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, 2>,
        v: &SVector<D, 2>,
    ) -> Option<D> {
        Some(v.dot(v) * 0.15)
    }
}

/// Polar coordinates in a frame rotating at ω = 0.4: `q = R(ωt)(r cos θ, r sin θ)`.
struct RotatingPolar;
impl hamilton_jacobi::transform::PointTransformation<2> for RotatingPolar {
    fn coordinates<D: DualNum<f64> + Copy>(&self, t: D, big_q: &SVector<D, 2>) -> SVector<D, 2> {
        let (s, c) = (big_q[1] + t * 0.4).sin_cos();
        SVector::from([big_q[0] * c, big_q[0] * s])
    }
}

/// SPEC M18: Lagrange's expressions in two charts related by a time-dependent point
/// transformation satisfy `E′_r = Σ_s (∂q_s/∂Q_r) E_s` at corresponding states, on a path that is
/// not a motion (so that `E ≠ 0`). The old state `(q, q̇, q̈)` comes from the path `Q(t)` pushed
/// through the map on second-order (nested) dual numbers in `t`, independently of the adapter.
#[test]
fn lagrange_equations_are_covariant_under_time_dependent_point_transformations() {
    use hamilton_jacobi::transform::TransformedLagrangian;
    use num_dual::Dual;
    type D2 = Dual<Dual<f64, f64>, f64>;
    let path = |t: D2| -> SVector<D2, 2> {
        SVector::from([
            t * 0.3 + t * t * 0.1 + 1.0,
            t.powi(3) * 0.05 - t * 0.2 + 0.5,
        ])
    };
    let map = RotatingPolar;
    let new = TransformedLagrangian::new(ForcedParticle, RotatingPolar);
    for &t0 in &[0.0, 0.7, 2.3] {
        let t = D2::new(Dual::new(t0, 1.0), Dual::new(1.0, 0.0));
        let big = path(t);
        let small = hamilton_jacobi::transform::PointTransformation::coordinates(&map, t, &big);
        let split = |x: &SVector<D2, 2>| {
            (
                x.map(|c| c.re.re),
                x.map(|c| c.re.eps),
                x.map(|c| c.eps.eps),
            )
        };
        let (bq, bv, ba) = split(&big);
        let (q, v, a) = split(&small);
        let e_old = ForcedParticle.lagrange_residual(t0, &q, &v, &a).unwrap();
        let e_new = new.lagrange_residual(t0, &bq, &bv, &ba).unwrap();
        // ∂q/∂Q of the rotating polar map at (t0, Q).
        let phi = bq[1] + 0.4 * t0;
        let jac = hamilton_jacobi::nalgebra::Matrix2::new(
            phi.cos(),
            -bq[0] * phi.sin(),
            phi.sin(),
            bq[0] * phi.cos(),
        );
        let want = jac.transpose() * e_old;
        let scale = e_old.norm().max(1.0) * bq[0].max(1.0);
        assert!(e_old.norm() > 0.1, "the path must not be a motion");
        assert!(
            (e_new - want).norm() <= 64.0 * f64::EPSILON * scale,
            "t = {t0}: E′ = {e_new:?}, Jᵀ E = {want:?}"
        );
    }
}

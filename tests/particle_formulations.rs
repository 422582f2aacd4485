//! Standard particle formulations (SPEC M20): generalized forces by projection against the
//! component formulas of Ardema eqs. 7.9 and 7.13; Lagrange's equations by AD against the
//! component equations 7.8 and 7.12; the particle on a fixed and on a moving plane curve against
//! eq. 7.14 written out by hand, and its integrated motion against the Cartesian multiplier
//! formulation with the constraint `y − f(x, t) = 0`.

use hamilton_jacobi::constraints::{Differentiated, HolonomicConstraints};
use hamilton_jacobi::integrate::{integrate, Dop853, Problem};
use hamilton_jacobi::nalgebra::{SVector, Vector1, Vector2, Vector3};
use hamilton_jacobi::nonholonomic::Constrained;
use hamilton_jacobi::num_dual::DualNum;
use hamilton_jacobi::particles::{checked_generalized_forces, ParticleSystem, Particles};
use hamilton_jacobi::systems::particle_formulations::{
    cylindrical_components, spherical_components,
};
use hamilton_jacobi::systems::{
    CartesianForce, ConstantForce, Cylindrical, OnCurve, Particle, PlaneCurve, Spherical,
};
use hamilton_jacobi::{Error, Lagrangian, Legendre};
use proptest::prelude::*;

/// A force depending on position and velocity: a spring to the origin, a linear drag, a constant
/// part and a magnetic-like term `b × u̇`.
#[derive(Clone, Copy, Debug)]
struct Field;

impl CartesianForce for Field {
    fn force<D: DualNum<f64> + Copy>(&self, t: D, u: &Vector3<D>, v: &Vector3<D>) -> Vector3<D> {
        let b = Vector3::new(D::from(0.3), D::from(-0.2), D::from(0.7));
        -u * D::from(1.3) - v * D::from(0.25)
            + b.cross(v)
            + Vector3::new(t.sin() * 0.5, D::from(-9.81), D::from(0.4))
    }
}

fn field(t: f64, u: &Vector3<f64>, v: &Vector3<f64>) -> Vector3<f64> {
    Field.force(t, u, v)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Cylindrical: `Q = Σ F·∂u/∂q = (F_r, r F_θ, F_z)`, and `q̈` by AD equals Ardema eq. 7.8.
    #[test]
    fn cylindrical_forces_and_equations(
        m in 0.1f64..5.0, r in 0.1f64..3.0, th in -4.0f64..4.0, z in -2.0f64..2.0,
        rd in -2.0f64..2.0, thd in -2.0f64..2.0, zd in -2.0f64..2.0, t in 0.0f64..3.0,
        fx in -5.0f64..5.0, fy in -5.0f64..5.0, fz in -5.0f64..5.0,
    ) {
        let f = Vector3::new(fx, fy, fz);
        let p = Particle::new(m, Cylindrical, Field).unwrap();
        let q = Vector3::new(r, th, z);
        let c = cylindrical_components(th, &f).unwrap();
        let g = checked_generalized_forces(&p, t, &q, &[f]).unwrap();
        let want = Vector3::new(c.x, r * c.y, c.z);
        prop_assert!((g - want).amax() <= 1e-13 * (1.0 + f.amax() * r), "{g:?} vs {want:?}");
        let qd = Vector3::new(rd, thd, zd);
        let [u] = p.positions(t, &q);
        let v = Vector3::new(rd * th.cos() - r * thd * th.sin(), rd * th.sin() + r * thd * th.cos(), zd);
        let c = cylindrical_components(th, &field(t, &u, &v)).unwrap();
        let acc = Particles(p).accelerations(t, &q, &qd).unwrap();
        let want = Vector3::new(
            r * thd * thd + c.x / m,
            (c.y / m - 2.0 * rd * thd) / r,
            c.z / m,
        );
        prop_assert!((acc - want).amax() <= 1e-11 * (1.0 + want.amax()), "{acc:?} vs {want:?}");
    }

    /// Spherical: `Q = (F_r, r F_θ, r sin θ F_φ)`, and `q̈` by AD equals Ardema eq. 7.12.
    #[test]
    fn spherical_forces_and_equations(
        m in 0.1f64..5.0, r in 0.1f64..3.0, th in 0.2f64..2.9, ph in -4.0f64..4.0,
        rd in -2.0f64..2.0, thd in -2.0f64..2.0, phd in -2.0f64..2.0, t in 0.0f64..3.0,
        fx in -5.0f64..5.0, fy in -5.0f64..5.0, fz in -5.0f64..5.0,
    ) {
        let f = Vector3::new(fx, fy, fz);
        let p = Particle::new(m, Spherical, Field).unwrap();
        let q = Vector3::new(r, th, ph);
        let c = spherical_components(th, ph, &f).unwrap();
        let g = checked_generalized_forces(&p, t, &q, &[f]).unwrap();
        let want = Vector3::new(c.x, r * c.y, r * th.sin() * c.z);
        prop_assert!((g - want).amax() <= 1e-13 * (1.0 + f.amax() * r), "{g:?} vs {want:?}");
        let qd = Vector3::new(rd, thd, phd);
        let [u] = p.positions(t, &q);
        let (st, ct, sp, cp) = (th.sin(), th.cos(), ph.sin(), ph.cos());
        let e_r = Vector3::new(st * cp, st * sp, ct);
        let e_t = Vector3::new(ct * cp, ct * sp, -st);
        let e_p = Vector3::new(-sp, cp, 0.0);
        let v = e_r * rd + e_t * (r * thd) + e_p * (r * st * phd);
        let c = spherical_components(th, ph, &field(t, &u, &v)).unwrap();
        let acc = Particles(p).accelerations(t, &q, &qd).unwrap();
        let want = Vector3::new(
            r * thd * thd + r * st * st * phd * phd + c.x / m,
            (c.y / m - 2.0 * rd * thd + r * st * ct * phd * phd) / r,
            (c.z / m - 2.0 * rd * phd * st - 2.0 * r * thd * phd * ct) / (r * st),
        );
        prop_assert!((acc - want).amax() <= 1e-11 * (1.0 + want.amax()), "{acc:?} vs {want:?}");
    }

    /// The moving curve `y = ½x² + a sin(x − ct)`: `ẍ` by AD equals eq. 7.14 with the derivatives
    /// of `f` written by hand; with `a = 0`, the fixed-curve form 7.15.
    #[test]
    fn curve_equation_7_14(
        m in 0.1f64..5.0, x in -2.0f64..2.0, xd in -2.0f64..2.0, t in 0.0f64..3.0,
        a in 0.0f64..0.5, fx in -3.0f64..3.0, fy in -10.0f64..3.0,
    ) {
        let curve = Wave { a, c: 1.3 };
        let p = Particle::new(m, OnCurve(curve), ConstantForce(Vector3::new(fx, fy, 0.0))).unwrap();
        let acc = Particles(p).accelerations(t, &Vector1::new(x), &Vector1::new(xd)).unwrap()[0];
        let ph = x - curve.c * t;
        let f_x = x + a * ph.cos();
        let f_xx = 1.0 - a * ph.sin();
        let f_xt = a * curve.c * ph.sin();
        let f_tt = -a * curve.c * curve.c * ph.sin();
        let want = (fx + fy * f_x - m * f_x * (f_xx * xd * xd + 2.0 * f_xt * xd + f_tt))
            / (m * (1.0 + f_x * f_x));
        prop_assert!((acc - want).abs() <= 1e-12 * (1.0 + want.abs()), "{acc} vs {want}");
    }
}

/// `y = ½x² + a sin(x − ct)`: a parabola carrying a travelling ripple.
#[derive(Clone, Copy, Debug)]
struct Wave {
    a: f64,
    c: f64,
}

impl PlaneCurve for Wave {
    fn height<D: DualNum<f64> + Copy>(&self, t: D, x: D) -> D {
        x * x * 0.5 + (x - t * self.c).sin() * self.a
    }
}

/// A free particle in the plane, `(x, y)`, under the same force.
struct Free<F>(f64, F);

impl<F: CartesianForce> ParticleSystem<2, 1> for Free<F> {
    fn masses(&self) -> [f64; 1] {
        [self.0]
    }
    fn positions<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> [Vector3<D>; 1] {
        [Vector3::new(q[0], q[1], D::from(0.0))]
    }
    fn applied_forces<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 2>,
        qdot: &SVector<D, 2>,
    ) -> Option<[Vector3<D>; 1]> {
        let u = Vector3::new(q[0], q[1], D::from(0.0));
        let v = Vector3::new(qdot[0], qdot[1], D::from(0.0));
        Some([self.1.force(t, &u, &v)])
    }
}

/// `y − f(x, t) = 0`.
struct CurveConstraint<C>(C);

impl<C: PlaneCurve> HolonomicConstraints<2, 1> for CurveConstraint<C> {
    fn position_constraint<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 2>,
    ) -> SVector<D, 1> {
        SVector::from([q[1] - self.0.height(t, q[0])])
    }
}

/// Drag and gravity in the plane (no `z` component), depending on velocity.
#[derive(Clone, Copy, Debug)]
struct PlaneDrag;

impl CartesianForce for PlaneDrag {
    fn force<D: DualNum<f64> + Copy>(&self, _t: D, u: &Vector3<D>, v: &Vector3<D>) -> Vector3<D> {
        Vector3::new(-v.x * 0.2 - u.x * 0.5, -v.y * 0.2 - 9.81, D::from(0.0))
    }
}

/// The integrated motion on the moving curve (one coordinate, DOP853 on Hamilton's equations of
/// the Legendre transform) against the Cartesian multiplier formulation (two coordinates, one
/// constraint, DOP853 on the index-reduced equations): `x(t)` and `ẋ(t)` agree to the
/// integration tolerance.
#[test]
fn moving_curve_motion_matches_the_multiplier_formulation() {
    let (m, t1) = (1.7, 4.0);
    for a in [0.0, 0.3] {
        let curve = Wave { a, c: 1.3 };
        let p = Particle::new(m, OnCurve(curve), PlaneDrag).unwrap();
        let (x0, xd0) = (1.2, -0.4);
        let l = Particles(p);
        let p0 = l
            .momentum(0.0, &Vector1::new(x0), &Vector1::new(xd0))
            .unwrap();
        let h = Legendre(l);
        let dop = Dop853::new(1e-12, 1e-14).unwrap();
        let one = integrate(
            &Problem::new(&h, 0.0, Vector1::new(x0), p0, t1).unwrap(),
            &dop,
            &mut (),
        )
        .unwrap();
        let xd1 = h.velocity(t1, &one.last.q, &one.last.p).unwrap()[0];
        // Cartesian: y = f(x, 0), ẏ = f_x ẋ + f_t.
        let ph = x0;
        let y0 = curve.height(0.0, x0);
        let yd0 = (x0 + a * ph.cos()) * xd0 - a * curve.c * ph.cos();
        let sys = Constrained::new(
            Particles(Free(m, PlaneDrag)),
            Differentiated(CurveConstraint(curve)),
        );
        let two = sys
            .integrate(
                &dop,
                0.0,
                Vector2::new(x0, y0),
                Vector2::new(xd0, yd0),
                t1,
                1e-12,
                &mut (),
            )
            .unwrap();
        let dx = (one.last.q[0] - two.last.q[0]).abs();
        let dv = (xd1 - two.last.p[0]).abs();
        let dy = (two.last.q[1] - curve.height(t1, two.last.q[0])).abs();
        println!("a = {a}: |Δx| = {dx:e}, |Δẋ| = {dv:e}, constraint drift {dy:e}");
        assert!(dx < 1e-9 && dv < 1e-9, "a = {a}: Δx {dx:e}, Δẋ {dv:e}");
        assert!(dy < 1e-9, "constraint drift {dy:e}");
    }
}

/// Typed errors for bad masses and non-finite components.
#[test]
fn bad_input_is_rejected() {
    assert!(matches!(
        Particle::new(0.0, Cylindrical, Field),
        Err(Error::OutOfDomain { .. })
    ));
    assert!(matches!(
        Particle::new(f64::NAN, Spherical, Field),
        Err(Error::NonFinite { .. })
    ));
    assert!(Particle::new(-1.0, OnCurve(Wave { a: 0.0, c: 0.0 }), PlaneDrag).is_err());
    assert!(cylindrical_components(f64::INFINITY, &Vector3::zeros()).is_err());
    assert!(spherical_components(0.1, 0.2, &Vector3::new(f64::NAN, 0.0, 0.0)).is_err());
    assert!(cylindrical_components(0.3, &Vector3::new(f64::MAX, f64::MAX, 0.0)).is_err());
}

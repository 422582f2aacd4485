//! Systems of particles (SPEC M14, M15): the kinetic energy split into `T₂ + T₁ + T₀`, generalized
//! forces as projections, and Lagrange's equations from the positions alone, against the closed
//! forms of the pendulum with a moving support (SPEC T26, Ardema 3.2 and 6.1) and of the double
//! pendulum (Ardema 12.3); the Jacobi integral exists only if the support does not accelerate.

mod common;

use hamilton_jacobi::nalgebra::{SVector, Vector3};
use hamilton_jacobi::num_dual::DualNum;
use hamilton_jacobi::particles::{
    checked_generalized_forces, kinetic_energy_split, ParticleSystem, Particles,
};
use hamilton_jacobi::Lagrangian;

const EPS: f64 = f64::EPSILON;

/// A pendulum of length `ℓ` and mass `m` whose support moves horizontally as
/// `f(t) = v t + A sin ωt`; `θ` from the downward vertical.
struct MovingSupport {
    m: f64,
    l: f64,
    g: f64,
    v: f64,
    a: f64,
    w: f64,
}

impl MovingSupport {
    fn f_dot(&self, t: f64) -> f64 {
        self.v + self.a * self.w * (self.w * t).cos()
    }
    fn f_ddot(&self, t: f64) -> f64 {
        -self.a * self.w * self.w * (self.w * t).sin()
    }
}

impl ParticleSystem<1, 1> for MovingSupport {
    fn masses(&self) -> [f64; 1] {
        [self.m]
    }
    fn positions<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 1>) -> [Vector3<D>; 1] {
        let f = t * self.v + (t * self.w).sin() * self.a;
        let (s, c) = q[0].sin_cos();
        [Vector3::new(f + s * self.l, -c * self.l, D::from(0.0))]
    }
    fn potential<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 1>) -> D {
        self.positions(t, q)[0].y * (self.m * self.g)
    }
}

fn support(a: f64) -> MovingSupport {
    MovingSupport {
        m: 1.3,
        l: 0.8,
        g: 9.81,
        v: 0.4,
        a,
        w: 2.0,
    }
}

/// `T₂ = ½mℓ²θ̇²`, `T₁ = mℓḟ cos θ θ̇`, `T₀ = ½mḟ²`, and Lagrange's equation
/// `θ̈ + (g/ℓ) sin θ + (f̈/ℓ) cos θ = 0` (SPEC T26).
#[test]
fn moving_support_kinetic_energy_parts_and_equation_of_motion() {
    let s = support(0.3);
    for (t, th, thd) in [(0.0, 0.3, 0.0), (0.7, -1.2, 2.0), (3.1, 2.5, -0.4)] {
        let (q, qd) = (SVector::from([th]), SVector::from([thd]));
        let (t2, t1, t0) = kinetic_energy_split(&s, t, &q, &qd).unwrap();
        let fd = s.f_dot(t);
        let scale = 0.5 * s.m * (s.l * thd.abs() + fd.abs()).powi(2);
        assert!((t2 - 0.5 * s.m * s.l * s.l * thd * thd).abs() < 16.0 * EPS * scale);
        assert!((t1 - s.m * s.l * fd * th.cos() * thd).abs() < 16.0 * EPS * scale);
        assert!((t0 - 0.5 * s.m * fd * fd).abs() < 16.0 * EPS * scale);
        let acc = Particles(support(0.3)).accelerations(t, &q, &qd).unwrap()[0];
        let expected = -(s.g / s.l) * th.sin() - (s.f_ddot(t) / s.l) * th.cos();
        assert!(
            (acc - expected).abs() < 1e-13 * (s.g / s.l),
            "{acc} {expected}"
        );
    }
}

/// The Jacobi integral `h = T₂ − T₀ + V` is conserved when `f̈ = 0` (uniform support motion) and
/// not otherwise (SPEC T26). RK4 with dt = 1e−3 over 5 s: local error ≈ (√(g/ℓ) dt)^5 ≈ 3e−13
/// per step, so `h` holds to about 1e−9 relative; the forced case changes `h` at order one.
#[test]
fn the_jacobi_integral_exists_only_without_support_acceleration() {
    let spread = |a: f64| {
        let l = Particles(support(a));
        let (q0, v0) = (SVector::from([0.5]), SVector::from([0.0]));
        let h0 = l.jacobi_integral(0.0, &q0, &v0).unwrap();
        let (mut lo, mut hi) = (h0, h0);
        common::rk4_lagrangian(&l, 0.0, q0, v0, 1e-3, 5000, |t, q, v| {
            let h = l.jacobi_integral(t, q, v).unwrap();
            lo = lo.min(h);
            hi = hi.max(h);
        });
        (hi - lo) / h0.abs()
    };
    assert!(spread(0.0) < 1e-9, "{}", spread(0.0));
    assert!(spread(0.3) > 1e-2, "{}", spread(0.3));
}

/// A horizontal force `F` on the bob: `Q = F ℓ cos θ`; a vertical one: `Q = F ℓ sin θ`.
#[test]
fn generalized_forces_are_projections() {
    let s = support(0.0);
    let q = SVector::from([0.7]);
    let q_h = checked_generalized_forces(&s, 0.0, &q, &[Vector3::new(2.0, 0.0, 0.0)]).unwrap();
    assert!((q_h[0] - 2.0 * s.l * 0.7f64.cos()).abs() < 4.0 * EPS);
    let q_v = checked_generalized_forces(&s, 0.0, &q, &[Vector3::new(0.0, 3.0, 0.0)]).unwrap();
    assert!((q_v[0] - 3.0 * s.l * 0.7f64.sin()).abs() < 4.0 * EPS * 3.0);
    assert!(checked_generalized_forces(&s, 0.0, &q, &[Vector3::new(f64::NAN, 0.0, 0.0)]).is_err());
    assert!(kinetic_energy_split(&s, f64::NAN, &q, &q).is_err());
}

/// Two point masses on rods `ℓ₁`, `ℓ₂`: the mass matrix
/// `[[(m₁+m₂)ℓ₁², m₂ℓ₁ℓ₂cos(θ₁−θ₂)], [·, m₂ℓ₂²]]` [Ardema 12.3] from the positions alone.
struct DoublePendulum;
impl ParticleSystem<2, 2> for DoublePendulum {
    fn masses(&self) -> [f64; 2] {
        [1.0, 2.0]
    }
    fn positions<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> [Vector3<D>; 2] {
        let (s1, c1) = q[0].sin_cos();
        let (s2, c2) = q[1].sin_cos();
        let z = D::from(0.0);
        let p1 = Vector3::new(s1 * 1.5, -c1 * 1.5, z);
        [p1, p1 + Vector3::new(s2 * 0.5, -c2 * 0.5, z)]
    }
}

#[test]
fn double_pendulum_mass_matrix_from_positions() {
    let l = Particles(DoublePendulum);
    let q = SVector::from([0.4, -1.1]);
    let a = l.mass_matrix(0.0, &q, &SVector::zeros()).unwrap();
    let c = (0.4f64 + 1.1).cos();
    let closed = [
        [3.0 * 2.25, 2.0 * 1.5 * 0.5 * c],
        [2.0 * 1.5 * 0.5 * c, 2.0 * 0.25],
    ];
    for i in 0..2 {
        for j in 0..2 {
            assert!((a[(i, j)] - closed[i][j]).abs() < 8.0 * EPS * 6.75);
        }
    }
    // Scleronomic: no T₁, no T₀.
    let (_, t1, t0) =
        kinetic_energy_split(&DoublePendulum, 0.0, &q, &SVector::from([0.3, 1.0])).unwrap();
    assert!(t1.abs() < 8.0 * EPS && t0 == 0.0);
}

/// A projectile with quadratic drag, `F = −κ|u̇|u̇`, in gravity, described in polar coordinates
/// about the launch point (a catastatic chart).
struct DraggedProjectile;
impl ParticleSystem<2, 1> for DraggedProjectile {
    fn masses(&self) -> [f64; 1] {
        [0.8]
    }
    fn positions<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> [Vector3<D>; 1] {
        let (s, c) = q[1].sin_cos();
        [Vector3::new(q[0] * c, q[0] * s, D::from(0.0))]
    }
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> D {
        q[0] * q[1].sin() * (0.8 * 9.81)
    }
    fn applied_forces<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, 2>,
        qdot: &SVector<D, 2>,
    ) -> Option<[Vector3<D>; 1]> {
        let [v] = hamilton_jacobi::particles::particle_velocities(self, t, q, qdot);
        Some([v * (v.dot(&v).sqrt() * -0.05)])
    }
}

/// SPEC M7 along an integrated motion: `T + V − ∫ Σ F·du` stays at its initial value, the work
/// integral taken by Simpson's rule on the sampled power (error ≈ (Δt)⁴ × the fourth derivative
/// of the power, below 1e-10 here), the motion by DOP853 at rtol 1e-12; the energy itself falls by
/// more than 10 %.
#[test]
fn work_energy_relation_holds_along_a_dragged_projectile() {
    use hamilton_jacobi::integrate::{integrate, Dop853, Problem, Samples};
    use hamilton_jacobi::lagrangian::Legendre;
    use hamilton_jacobi::particles::applied_power;
    let system = DraggedProjectile;
    let lagrangian = Particles::<_, 1>(DraggedProjectile);
    let h = Legendre(lagrangian);
    let (q0, qdot0) = (SVector::from([1.0, 0.3]), SVector::from([6.0, 1.5]));
    let p0 = Particles::<_, 1>(DraggedProjectile)
        .momentum(0.0, &q0, &qdot0)
        .unwrap();
    let n = 400;
    let t1 = 1.0;
    let mut samples = Samples::uniform(0.0, t1, n).unwrap();
    let problem = Problem::new(&h, 0.0, q0, p0, t1).unwrap();
    integrate(&problem, &Dop853::new(1e-12, 1e-14).unwrap(), &mut samples).unwrap();
    let states: Vec<_> = samples
        .states
        .iter()
        .map(|s| {
            let v = h.velocity(s.t, &s.q, &s.p).unwrap();
            (s.t, s.q, v)
        })
        .collect();
    let energy = |&(t, q, v): &(f64, SVector<f64, 2>, SVector<f64, 2>)| {
        let (t2, t1k, t0) = kinetic_energy_split(&system, t, &q, &v).unwrap();
        t2 + t1k + t0 + system.potential(t, &q)
    };
    let power: Vec<f64> = states
        .iter()
        .map(|(t, q, v)| applied_power(&system, *t, q, v).unwrap())
        .collect();
    let dt = t1 / n as f64;
    let e0 = energy(&states[0]);
    let mut work = 0.0;
    for k in (2..=n).step_by(2) {
        work += dt / 3.0 * (power[k - 2] + 4.0 * power[k - 1] + power[k]);
        let balance = energy(&states[k]) - work - e0;
        assert!(
            balance.abs() <= 1e-9 * e0.abs(),
            "t = {}: T + V − W − h = {balance:e}",
            states[k].0
        );
    }
    assert!(energy(&states[n]) < 0.9 * e0, "drag must remove energy");
    // Without applied forces the power is zero.
    assert_eq!(
        applied_power(
            &MovingSupport {
                m: 1.0,
                l: 1.0,
                g: 9.81,
                v: 0.0,
                a: 0.0,
                w: 0.0
            },
            0.0,
            &SVector::from([0.1]),
            &SVector::from([0.2])
        )
        .unwrap(),
        0.0
    );
}

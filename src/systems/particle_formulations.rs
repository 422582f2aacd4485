//! Standard particle formulations [Ardema 7.2–7.3, eqs. 7.8–7.15] (SPEC M20): a particle of mass
//! `m` in cylindrical and spherical coordinates, and a particle on a plane curve `y = f(x, t)`,
//! each a [`ParticleSystem`] ([`Particle`] in [`Cylindrical`], [`Spherical`] or [`OnCurve`]
//! coordinates) whose Lagrangian and generalized forces come by AD from the positions
//! ([`Particles`](crate::particles::Particles)), under an applied force given by its Cartesian
//! components ([`CartesianForce`]).
//!
//! * Cylindrical `(r, θ, z)`, `u = (r cos θ, r sin θ, z)`: with the components
//!   `F_r = F_x cos θ + F_y sin θ`, `F_θ = −F_x sin θ + F_y cos θ`, `F_z` [Ardema eq. 7.9]
//!   ([`cylindrical_components`]) the generalized forces are `(F_r, r F_θ, F_z)` and
//!   `m(r̈ − r θ̇²) = F_r`, `m(r θ̈ + 2 ṙ θ̇) = F_θ`, `m z̈ = F_z` [Ardema eq. 7.8].
//! * Spherical `(r, θ, φ)` (`θ` from the `z` axis), `u = r (sin θ cos φ, sin θ sin φ, cos θ)`: with
//!   `F_r = F·e_r`, `F_θ = F·e_θ`, `F_φ = F·e_φ` [Ardema eq. 7.13] ([`spherical_components`]) the
//!   generalized forces are `(F_r, r F_θ, r sin θ F_φ)` and
//!   `m(r̈ − r θ̇² − r sin²θ φ̇²) = F_r`, `m(r θ̈ + 2 ṙ θ̇ − r sin θ cos θ φ̇²) = F_θ`,
//!   `m(r sin θ φ̈ + 2 ṙ φ̇ sin θ + 2 r θ̇ φ̇ cos θ) = F_φ` [Ardema eq. 7.12].
//! * On the plane curve `y = f(x, t)` ([`OnCurve`], coordinate `x`):
//!   `ẏ = f_x ẋ + f_t`, `T = ½ m (ẋ² + (f_x ẋ + f_t)²)`, `Q = F_x + F_y f_x`, and Lagrange's
//!   equation is [Ardema eq. 7.14]
//!   ```math
//!   m(1 + f_x^2)\,\ddot x + m f_x\big(f_{xx}\dot x^2 + 2 f_{xt}\dot x + f_{tt}\big)
//!   = F_x + F_y f_x ,
//!   ```
//!   i.e. `m(ẍ + f_x ÿ) = F_x + F_y f_x`, the tangential component of Newton's law. For a fixed
//!   curve (`f_t = 0`) it is `m(1 + f′²) ẍ + m f′ f″ ẋ² = F_x + F_y f′` [Ardema eq. 7.15].

use crate::error::{all_finite, finite, positive, Result};
use crate::particles::{particle_velocities, ParticleSystem};
use nalgebra::{SVector, Vector3};
use num_dual::DualNum;

/// An applied force given by its Cartesian components `F(t, u, u̇)` at the particle's position `u`
/// and velocity `u̇`, for any number type.
pub trait CartesianForce {
    /// The force `(F_x, F_y, F_z)`.
    fn force<D: DualNum<f64> + Copy>(&self, t: D, u: &Vector3<D>, v: &Vector3<D>) -> Vector3<D>;
}

/// A constant force, e.g. the weight `(0, −mg, 0)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ConstantForce(pub Vector3<f64>);

impl CartesianForce for ConstantForce {
    fn force<D: DualNum<f64> + Copy>(&self, _t: D, _u: &Vector3<D>, _v: &Vector3<D>) -> Vector3<D> {
        self.0.map(D::from)
    }
}

/// The cylindrical components `(F_r, F_θ, F_z)` of the Cartesian force `F` at the angle `θ`
/// [Ardema eq. 7.9].
///
/// # Errors
/// [`crate::Error::NonFinite`] for NaN/∞ input.
pub fn cylindrical_components(theta: f64, force: &Vector3<f64>) -> Result<Vector3<f64>> {
    finite("angle θ", theta)?;
    all_finite("force F", force.as_slice())?;
    let (s, c) = theta.sin_cos();
    let out = Vector3::new(
        force.x * c + force.y * s,
        -force.x * s + force.y * c,
        force.z,
    );
    all_finite("cylindrical components (F_r, F_θ, F_z)", out.as_slice())?;
    Ok(out)
}

/// The spherical components `(F_r, F_θ, F_φ)` of the Cartesian force `F` at the polar angle `θ`
/// and azimuth `φ`: the projections on `e_r = (sin θ cos φ, sin θ sin φ, cos θ)`,
/// `e_θ = (cos θ cos φ, cos θ sin φ, −sin θ)`, `e_φ = (−sin φ, cos φ, 0)` [Ardema eq. 7.13].
///
/// # Errors
/// [`crate::Error::NonFinite`] for NaN/∞ input.
pub fn spherical_components(theta: f64, phi: f64, force: &Vector3<f64>) -> Result<Vector3<f64>> {
    finite("polar angle θ", theta)?;
    finite("azimuth φ", phi)?;
    all_finite("force F", force.as_slice())?;
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = phi.sin_cos();
    let e_r = Vector3::new(st * cp, st * sp, ct);
    let e_t = Vector3::new(ct * cp, ct * sp, -st);
    let e_p = Vector3::new(-sp, cp, 0.0);
    let out = Vector3::new(force.dot(&e_r), force.dot(&e_t), force.dot(&e_p));
    all_finite("spherical components (F_r, F_θ, F_φ)", out.as_slice())?;
    Ok(out)
}

/// Coordinates `q` of one particle: its position `u(t, q)`, for any number type.
pub trait Coordinates<const N: usize> {
    /// The position `u(t, q)`.
    fn position<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> Vector3<D>;
}

/// Cylindrical coordinates `q = (r, θ, z)`: `u = (r cos θ, r sin θ, z)`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Cylindrical;

impl Coordinates<3> for Cylindrical {
    fn position<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 3>) -> Vector3<D> {
        let (s, c) = q[1].sin_cos();
        Vector3::new(q[0] * c, q[0] * s, q[2])
    }
}

/// Spherical coordinates `q = (r, θ, φ)`, `θ` from the `z` axis:
/// `u = r (sin θ cos φ, sin θ sin φ, cos θ)`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Spherical;

impl Coordinates<3> for Spherical {
    fn position<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 3>) -> Vector3<D> {
        let (st, ct) = q[1].sin_cos();
        let (sp, cp) = q[2].sin_cos();
        Vector3::new(q[0] * st * cp, q[0] * st * sp, q[0] * ct)
    }
}

/// A plane curve `y = f(x, t)`, fixed or moving, written once for every number type.
pub trait PlaneCurve {
    /// The height `f(x, t)`.
    fn height<D: DualNum<f64> + Copy>(&self, t: D, x: D) -> D;
}

/// The coordinate `x` of a particle on the plane curve `y = f(x, t)`: `u = (x, f(x, t), 0)`
/// ([Ardema eqs. 7.14–7.15], module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OnCurve<C>(pub C);

impl<C: PlaneCurve> Coordinates<1> for OnCurve<C> {
    fn position<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 1>) -> Vector3<D> {
        Vector3::new(q[0], self.0.height(t, q[0]), D::from(0.0))
    }
}

/// A particle of mass `m` in the coordinates `C` under the force `F` (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Particle<C, F> {
    mass: f64,
    coordinates: C,
    force: F,
}

impl<C, F: CartesianForce> Particle<C, F> {
    /// Mass `m > 0` in `coordinates` under `force`.
    ///
    /// # Errors
    /// [`crate::Error::NonFinite`]/[`crate::Error::OutOfDomain`] for a mass that is not positive
    /// and finite.
    pub fn new(mass: f64, coordinates: C, force: F) -> Result<Self> {
        Ok(Self {
            mass: positive("mass m", mass)?,
            coordinates,
            force,
        })
    }

    /// The coordinates.
    pub fn coordinates(&self) -> &C {
        &self.coordinates
    }

    /// The force.
    pub fn force(&self) -> &F {
        &self.force
    }
}

impl<C: Coordinates<N>, F: CartesianForce, const N: usize> ParticleSystem<N, 1> for Particle<C, F> {
    fn masses(&self) -> [f64; 1] {
        [self.mass]
    }
    fn positions<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> [Vector3<D>; 1] {
        [self.coordinates.position(t, q)]
    }
    /// `F(t, u, u̇)` at the particle's position and velocity.
    fn applied_forces<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        qdot: &SVector<D, N>,
    ) -> Option<[Vector3<D>; 1]> {
        let [v] = particle_velocities(self, t, q, qdot);
        Some([self.force.force(t, &self.coordinates.position(t, q), &v)])
    }
}

//! A rigid body with a fixed point in a uniform gravity field: the heavy top of any inertia and
//! any position of the mass centre [Ardema 11.2; Hamel art. 242; Leimanis, *The General Problem of
//! the Motion of Coupled Rigid Bodies about a Fixed Point*, Springer 1965, §1].
//!
//! In the 3-1-3 angles `q = (φ, θ, ψ)` of [`super::rotation`], with `Π(q, p)` the body angular
//! momentum of [`FreeRigidBody::body_momentum_generic`] and
//!
//! ```math
//! \gamma(\theta, \psi) = R^{\mathsf T} e_z = (\sin\theta\sin\psi,\ \sin\theta\cos\psi,\
//! \cos\theta)
//! ```
//!
//! the upward vertical in body axes (`R` the body-to-space rotation), the Hamiltonian is the free
//! body's kinetic energy plus the height of the mass centre times the weight,
//!
//! ```math
//! H = \sum_i \frac{\Pi_i^2}{2 I_i} + w\cdot\gamma, \qquad w = m g\, r_G ,
//! ```
//!
//! with `r_G` the mass centre in principal axes. Hamilton's equations reproduce the
//! Euler–Poisson equations `Π̇ = Π × ω + γ × w`, `γ̇ = γ × ω`, `ω_i = Π_i/I_i`. The integrals are
//! the energy, the vertical angular momentum `p_φ = Π·γ` (the Lagrangian does not depend on `φ`)
//! and the geometric `|γ| = 1`; a fourth exists in the integrable cases of Euler (`w = 0`),
//! Lagrange (`I₁ = I₂`, `w` on the figure axis: [`super::super::HeavyTop`] is this case) and
//! Kovalevskaya (`I₁ = I₂ = 2I₃`, `w` in the equatorial plane: [`HeavyRigidBody::kovalevskaya_integral`]).

use super::euler::FreeRigidBody;
use super::inertia::InertiaTensor;
use super::rotation::{euler313_matrix, euler_chart_entry_points};
use crate::error::{all_finite, finite, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::lagrangian::NaturalSystem;
use crate::phase::check_phase;
use crate::systems::{Invariant, Invariants};
use nalgebra::{SMatrix, SVector, Vector3};
use num_dual::DualNum;

/// A rigid body about a fixed point under uniform gravity (module docs): principal moments
/// `(I₁, I₂, I₃)` about the fixed point and the weight moment `w = m g r_G` in principal axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeavyRigidBody {
    body: FreeRigidBody,
    weight: Vector3<f64>,
}

/// The upward vertical in body axes, `γ = (sin θ sin ψ, sin θ cos ψ, cos θ)`, of the 3-1-3 angles
/// `q = (φ, θ, ψ)`, for any number type (module docs).
pub fn vertical_in_body<D: DualNum<f64> + Copy>(q: &SVector<D, 3>) -> Vector3<D> {
    let (st, ct) = q[1].sin_cos();
    let (sp, cp) = q[2].sin_cos();
    Vector3::new(st * sp, st * cp, ct)
}

impl HeavyRigidBody {
    /// A body with principal moments `(I₁, I₂, I₃)` about the fixed point (as
    /// [`FreeRigidBody::new`]) and weight moment `w = m g r_G` (finite; zero gives the free body).
    ///
    /// # Errors
    /// As [`FreeRigidBody::new`]; [`Error::NonFinite`] for a non-finite weight moment.
    pub fn new(moments: Vector3<f64>, weight: Vector3<f64>) -> Result<Self> {
        all_finite("weight moment m g r_G", weight.as_slice())?;
        Ok(Self {
            body: FreeRigidBody::new(moments)?,
            weight,
        })
    }

    /// The symmetric top of [`crate::systems::HeavyTop`]: moments `(I, I, J)` (any positive
    /// values, checked by the caller) and the weight moment `(0, 0, mgℓ)`.
    pub(in crate::systems) fn symmetric_top(i: f64, j: f64, mgl: f64) -> Self {
        Self {
            body: FreeRigidBody::with_moments_unchecked(Vector3::new(i, i, j)),
            weight: Vector3::new(0.0, 0.0, mgl),
        }
    }

    /// The principal moments `(I₁, I₂, I₃)` about the fixed point.
    pub fn moments(&self) -> &Vector3<f64> {
        self.body.moments()
    }

    /// The weight moment `w = m g r_G` in principal axes.
    pub fn weight(&self) -> &Vector3<f64> {
        &self.weight
    }

    /// The inertia tensor about the fixed point, in principal axes.
    ///
    /// # Errors
    /// None for a body made by [`HeavyRigidBody::new`].
    pub fn inertia(&self) -> Result<InertiaTensor> {
        InertiaTensor::principal(*self.moments())
    }

    /// The potential `V = w · γ(q)`, for any number type.
    pub fn potential_generic<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 3>) -> D {
        let g = vertical_in_body(q);
        g[0] * self.weight[0] + g[1] * self.weight[1] + g[2] * self.weight[2]
    }

    /// The body angular velocity `ω` and the vertical `γ` of a state: the variables of the
    /// Euler–Poisson equations.
    ///
    /// # Errors
    /// As [`FreeRigidBody::body_momentum`] (chart singularity, non-finite input).
    pub fn euler_poisson_state(
        &self,
        q: &SVector<f64, 3>,
        p: &SVector<f64, 3>,
    ) -> Result<(Vector3<f64>, Vector3<f64>)> {
        let pi = FreeRigidBody::body_momentum(q, p)?;
        Ok((pi.component_div(self.moments()), vertical_in_body(q)))
    }

    /// Kovalevskaya's integral for `I₁ = I₂ = 2I₃` and `w = (w₁, w₂, 0)` [Kovalevskaya, Acta
    /// Math. 12 (1889) 177–232; Leimanis §5]: with `z = ω₁ + iω₂`, `ξ = γ₁ + iγ₂` and
    /// `c = (w₁ + i w₂)/I₃`,
    ///
    /// ```math
    /// K = \left| z^2 - c\,\xi \right|^2 ,
    /// ```
    ///
    /// constant because `d(z² − cξ)/dt = −iω₃ (z² − cξ)` by the Euler–Poisson equations.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] outside Kovalevskaya's case (moments not in the ratio 2 : 2 : 1
    /// to 1e-12, or `w₃ ≠ 0`); as [`HeavyRigidBody::euler_poisson_state`].
    pub fn kovalevskaya_integral(&self, q: &SVector<f64, 3>, p: &SVector<f64, 3>) -> Result<f64> {
        let m = self.moments();
        let tol = 1e-12 * m[2];
        if (m[0] - 2.0 * m[2]).abs() > tol
            || (m[1] - 2.0 * m[2]).abs() > tol
            || self.weight[2] != 0.0
        {
            return Err(Error::invalid(
                "Kovalevskaya integral",
                format!(
                    "needs moments in the ratio 2 : 2 : 1 and the mass centre in the equatorial \
                     plane; moments ({:e}, {:e}, {:e}), weight moment ({:e}, {:e}, {:e})",
                    m[0], m[1], m[2], self.weight[0], self.weight[1], self.weight[2]
                ),
            ));
        }
        let (w, g) = self.euler_poisson_state(q, p)?;
        let (c1, c2) = (self.weight[0] / m[2], self.weight[1] / m[2]);
        // z² − cξ with z = ω₁ + iω₂, ξ = γ₁ + iγ₂, c = c₁ + ic₂.
        let re = w[0] * w[0] - w[1] * w[1] - (c1 * g[0] - c2 * g[1]);
        let im = 2.0 * w[0] * w[1] - (c1 * g[1] + c2 * g[0]);
        finite("Kovalevskaya integral", re * re + im * im)
    }
}

impl NaturalSystem<3> for HeavyRigidBody {
    /// `a = Bᵀ diag(I₁, I₂, I₃) B` with the kinematic matrix `B(θ, ψ)` of
    /// [`super::rotation`]: `T = ½ ωᵀ I ω`, `ω = B q̇`.
    fn mass<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        let b = euler313_matrix(q[1], q[2]);
        let m = self.moments();
        let i = SMatrix::<D, 3, 3>::from_diagonal(&Vector3::new(
            D::from(m[0]),
            D::from(m[1]),
            D::from(m[2]),
        ));
        b.transpose() * i * b
    }
    /// `V = w · γ(q)`.
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 3>) -> D {
        self.potential_generic(q)
    }
}

impl Hamiltonian<3> for HeavyRigidBody {
    #[inline]
    fn hamiltonian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, 3>, p: &SVector<D, 3>) -> D {
        self.body.hamiltonian(t, q, p) + self.potential_generic(q)
    }

    euler_chart_entry_points!();
}

impl Invariants<3> for HeavyRigidBody {
    /// `energy` (H) and `p_phi` (the vertical angular momentum `Π·γ`).
    fn invariants(
        &self,
        t: f64,
        q: &SVector<f64, 3>,
        p: &SVector<f64, 3>,
    ) -> Result<Vec<Invariant>> {
        check_phase(t, q, p)?;
        Ok(vec![
            Invariant {
                name: "energy",
                value: self.value(t, q, p)?,
            },
            Invariant {
                name: "p_phi",
                value: p[0],
            },
        ])
    }
}

//! Attitude: 3-1-3 Euler angles with their kinematics, and unit quaternions.
//!
//! The 3-1-3 angles `(φ, θ, ψ)` give the body-to-space rotation `R = R_z(φ) R_x(θ) R_z(ψ)`
//! [Ardema 11.1]; the body components of the angular velocity are [Ardema 11.1, eq. 11.8; SPEC M29]
//!
//! ```math
//! \omega = B(\theta, \psi)\,(\dot\phi, \dot\theta, \dot\psi)^{\mathsf T},\qquad
//! B = \begin{pmatrix} \sin\theta\sin\psi & \cos\psi & 0 \\
//!                     \sin\theta\cos\psi & -\sin\psi & 0 \\
//!                     \cos\theta & 0 & 1 \end{pmatrix}, \qquad \det B = -\sin\theta .
//! ```
//!
//! # The chart and its singularity
//! `B` is singular where `sin θ = 0`: the precession and spin axes coincide, only `φ ± ψ` is
//! defined, and the inverse kinematics divide by `sin θ`. The crate's choice: **unit quaternions
//! (nalgebra's [`UnitQuaternion`]) are the singularity-free attitude**; Euler angles are a chart
//! for the canonical form of the rigid body ([`super::FreeRigidBody`], the heavy top) and for
//! output. Every map that needs the inverse of `B` ([`euler313_rates`], the conversion from a
//! quaternion, the canonical Hamiltonians' checked entry points) refuses `|sin θ| ≤ 2⁻⁵²` with
//! [`Error::Singular`] naming the 3-1-3 chart; near it the inverse has the condition number
//! `≈ 1/|sin θ|`.
//! Routh's reduction of the axisymmetric top by its ignorable `φ`, `ψ` solves with the block
//! `[[I sin²θ + J cos²θ, J cos θ], [J cos θ, J]]` of condition number `≈ 4J/(Iθ²)` as `θ → 0`
//! (SPEC X9, measured in the tests), while in quaternions the mass matrix on the tangent space of
//! S³ is `4 diag(I₁, I₂, I₃)` at every attitude: hence the quaternion state near the pole.

use crate::constraints::QuasiVelocities;
use crate::error::{all_finite, finite, Error, Result};
use crate::hamiltonian::{checked_vector_field, Hamiltonian};
use crate::phase::check_phase;
use nalgebra::{Matrix3, SMatrix, SVector, UnitQuaternion, Vector3};
use num_dual::DualNum;

/// Refuse angles where the 3-1-3 chart is singular (`|sin θ| ≤ 2⁻⁵²`); `sin θ` otherwise.
///
/// # Errors
/// [`Error::NonFinite`] for a non-finite `θ`; [`Error::Singular`] at the chart singularity.
pub fn check_chart(theta: f64) -> Result<f64> {
    let theta = finite("nutation angle θ", theta)?;
    let s = theta.sin();
    if s.abs() <= f64::EPSILON {
        return Err(Error::Singular {
            what: "3-1-3 Euler-angle chart (mass matrix, det = I²J sin²θ)".into(),
            at: format!(
                "θ = {theta} (sin θ = {s:e}): the precession and spin axes coincide on the vertical"
            ),
            rcond: s * s,
        });
    }
    Ok(s)
}

/// `H(t, q, p)` of a Hamiltonian in 3-1-3 angles `q = (φ, θ, ψ)`, with non-finite input and the
/// chart singularity ([`check_chart`]) refused.
pub(crate) fn chart_value<H: Hamiltonian<3>>(
    h: &H,
    t: f64,
    q: &SVector<f64, 3>,
    p: &SVector<f64, 3>,
) -> Result<f64> {
    check_phase(t, q, p)?;
    check_chart(q[1])?;
    finite("H", h.hamiltonian(t, q, p))
}

/// Hamilton's equations of a Hamiltonian in 3-1-3 angles, with non-finite input and the chart
/// singularity ([`check_chart`]) refused.
#[allow(clippy::type_complexity)]
pub(crate) fn chart_vector_field<H: Hamiltonian<3>>(
    h: &H,
    t: f64,
    q: &SVector<f64, 3>,
    p: &SVector<f64, 3>,
) -> Result<(SVector<f64, 3>, SVector<f64, 3>)> {
    check_phase(t, q, p)?;
    check_chart(q[1])?;
    checked_vector_field(h, t, q, p)
}

/// The checked entry points [`Hamiltonian::value`] and [`Hamiltonian::vector_field`] of a
/// Hamiltonian in 3-1-3 angles: as the defaults, after refusing the chart singularity `sin θ = 0`
/// ([`Error::Singular`], [`check_chart`]). Expands inside `impl Hamiltonian<3> for …`.
macro_rules! euler_chart_entry_points {
    () => {
        /// As the default, after refusing the chart singularity `sin θ = 0` ([`Error::Singular`]).
        fn value(
            &self,
            t: f64,
            q: &nalgebra::SVector<f64, 3>,
            p: &nalgebra::SVector<f64, 3>,
        ) -> $crate::error::Result<f64> {
            $crate::systems::rigid_body::rotation::chart_value(self, t, q, p)
        }

        /// As the default, after refusing the chart singularity `sin θ = 0` ([`Error::Singular`]).
        fn vector_field(
            &self,
            t: f64,
            q: &nalgebra::SVector<f64, 3>,
            p: &nalgebra::SVector<f64, 3>,
        ) -> $crate::error::Result<(nalgebra::SVector<f64, 3>, nalgebra::SVector<f64, 3>)> {
            $crate::systems::rigid_body::rotation::chart_vector_field(self, t, q, p)
        }
    };
}
pub(crate) use euler_chart_entry_points;

/// The matrix `B(θ, ψ)` of the 3-1-3 kinematics, `ω = B (φ̇, θ̇, ψ̇)` (module docs), for any
/// number type.
pub fn euler313_matrix<D: DualNum<f64> + Copy>(theta: D, psi: D) -> SMatrix<D, 3, 3> {
    let (st, ct) = theta.sin_cos();
    let (sp, cp) = psi.sin_cos();
    let (z, one) = (D::from(0.0), D::from(1.0));
    SMatrix::<D, 3, 3>::new(st * sp, cp, z, st * cp, -sp, z, ct, z, one)
}

/// The body angular velocity `ω = B(θ, ψ)(φ̇, θ̇, ψ̇)` as quasi-velocities of the 3-1-3 chart (none
/// constrained) [Hamel art. 242; SPEC M32]. Their transition relation is
/// `d′δϑ − δ′dϑ = −dϑ × δϑ`: Hamel's coefficients are `β_μ^{τρ} = −ε_{μτρ}`, the structure
/// constants of so(3), and the Boltzmann–Hamel equations with `T = ½ ωᵀ I ω`,
/// `P = ∂T/∂ω = Iω`, are Euler's equations `I ω̇ + ω × Iω = M` (the moment `M` from
/// `K_ρ = Σ_ν Q_ν B_νρ`, [`super::euler_rhs`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct BodyAngularVelocity;

impl QuasiVelocities<3> for BodyAngularVelocity {
    fn constrained(&self) -> usize {
        0
    }
    /// `b(q) = B(θ, ψ)` ([`euler313_matrix`]).
    fn matrix<D: DualNum<f64> + Copy>(&self, q: &SVector<D, 3>) -> SMatrix<D, 3, 3> {
        euler313_matrix(q[1], q[2])
    }
}

/// Body angular velocity from the 3-1-3 angles `(φ, θ, ψ)` and their rates [SPEC M29]:
/// `ω = B(θ, ψ)(φ̇, θ̇, ψ̇)`. Defined everywhere (also at `sin θ = 0`).
///
/// # Errors
/// [`Error::NonFinite`] for non-finite input.
pub fn euler313_body_rates(angles: &Vector3<f64>, rates: &Vector3<f64>) -> Result<Vector3<f64>> {
    all_finite("Euler angles (φ, θ, ψ)", angles.as_slice())?;
    all_finite("Euler-angle rates", rates.as_slice())?;
    let w = euler313_matrix(angles[1], angles[2]) * rates;
    all_finite("body angular velocity", w.as_slice())?;
    Ok(w)
}

/// The inverse kinematics: `(φ̇, θ̇, ψ̇) = B⁻¹ ω` with
/// `φ̇ = (ω₁ sin ψ + ω₂ cos ψ)/sin θ`, `θ̇ = ω₁ cos ψ − ω₂ sin ψ`, `ψ̇ = ω₃ − φ̇ cos θ`.
///
/// # Errors
/// [`Error::Singular`] at the chart singularity `sin θ = 0` ([`check_chart`]);
/// [`Error::NonFinite`] for non-finite input or result.
pub fn euler313_rates(angles: &Vector3<f64>, omega: &Vector3<f64>) -> Result<Vector3<f64>> {
    all_finite("Euler angles (φ, θ, ψ)", angles.as_slice())?;
    all_finite("body angular velocity ω", omega.as_slice())?;
    let st = check_chart(angles[1])?;
    let (sp, cp) = angles[2].sin_cos();
    let phi_dot = (omega[0] * sp + omega[1] * cp) / st;
    let r = Vector3::new(
        phi_dot,
        omega[0] * cp - omega[1] * sp,
        omega[2] - phi_dot * angles[1].cos(),
    );
    all_finite("Euler-angle rates", r.as_slice())?;
    Ok(r)
}

/// The body-to-space rotation `R_z(φ) R_x(θ) R_z(ψ)` of the 3-1-3 angles, for any number type.
pub fn euler313_rotation_matrix<D: DualNum<f64> + Copy>(angles: &SVector<D, 3>) -> Matrix3<D> {
    let rz = |a: D| {
        let (s, c) = a.sin_cos();
        let (z, one) = (D::from(0.0), D::from(1.0));
        Matrix3::new(c, -s, z, s, c, z, z, z, one)
    };
    let (s, c) = angles[1].sin_cos();
    let (z, one) = (D::from(0.0), D::from(1.0));
    let rx = Matrix3::new(one, z, z, z, c, -s, z, s, c);
    rz(angles[0]) * rx * rz(angles[2])
}

/// The attitude of the 3-1-3 angles as a unit quaternion (body to space):
/// `q = q_z(φ) q_x(θ) q_z(ψ)`.
///
/// # Errors
/// [`Error::NonFinite`] for non-finite angles.
pub fn quaternion_from_euler313(angles: &Vector3<f64>) -> Result<UnitQuaternion<f64>> {
    all_finite("Euler angles (φ, θ, ψ)", angles.as_slice())?;
    let z = Vector3::z_axis();
    let x = Vector3::x_axis();
    Ok(UnitQuaternion::from_axis_angle(&z, angles[0])
        * UnitQuaternion::from_axis_angle(&x, angles[1])
        * UnitQuaternion::from_axis_angle(&z, angles[2]))
}

/// The 3-1-3 angles of an attitude, `θ ∈ [0, π]`, `φ, ψ ∈ (−π, π]`: from `R = [r_ij]`,
/// `cos θ = r₃₃`, `φ = atan2(r₁₃, −r₂₃)`, `ψ = atan2(r₃₁, r₃₂)`; `θ` from
/// `atan2(√(r₁₃² + r₂₃²), r₃₃)`, accurate at every angle.
///
/// # Errors
/// [`Error::Singular`] when the attitude lies on the chart singularity (`|sin θ| ≤ 2⁻⁵²`),
/// where only `φ ± ψ` is defined; [`Error::NonFinite`] for a non-finite quaternion.
pub fn euler313_from_quaternion(q: &UnitQuaternion<f64>) -> Result<Vector3<f64>> {
    all_finite("attitude quaternion", q.as_vector().as_slice())?;
    let r = q.to_rotation_matrix().into_inner();
    let theta = r[(0, 2)].hypot(r[(1, 2)]).atan2(r[(2, 2)]);
    check_chart(theta)?;
    Ok(Vector3::new(
        r[(0, 2)].atan2(-r[(1, 2)]),
        theta,
        r[(2, 0)].atan2(r[(2, 1)]),
    ))
}

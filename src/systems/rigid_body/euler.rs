//! Euler's equations and the free rigid body in canonical form.
//!
//! In body axes, with `D = ∂T/∂ω = I ω` the angular momentum, Hamel's equations with the
//! quasi-velocities `ω` (transition relation `d′δϑ − δ′dϑ = −dϑ × δϑ`) give Euler's equations
//! [Hamel art. 242; Ardema 11.4; SPEC M32]
//!
//! ```math
//! I\dot\omega + \omega \times I\omega = M .
//! ```
//!
//! The free body (`M = 0`) in principal axes, written with the body angular momentum
//! `Π = Iω`, is the Lie–Poisson system `Π̇ = Π × ω` with energy
//! `H = Σ Π_i²/(2I_i)` and the Casimir `|Π|²` (Marsden & Ratiu, *Introduction to Mechanics and
//! Symmetry*, 2nd ed., §15.3).

use super::inertia::InertiaTensor;
use super::rotation::{check_chart, euler313_matrix, euler_chart_entry_points};
use crate::error::{all_finite, finite, positive, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::phase::check_phase;
use crate::systems::{Invariant, Invariants};
use nalgebra::{Matrix3, SVector, Vector3};
use num_dual::{Dual64, DualNum};

/// The right-hand side of Euler's equations, `ω̇ = I⁻¹(M − ω × Iω)` [SPEC M32], for any number
/// type (so that its Jacobian is available by AD: [`euler_jacobian`]). `inverse` is `I⁻¹`.
pub fn euler_rhs_generic<D: DualNum<f64> + Copy>(
    inertia: &Matrix3<f64>,
    inverse: &Matrix3<f64>,
    moment: &Vector3<D>,
    omega: &Vector3<D>,
) -> Vector3<D> {
    let io = inertia.map(D::from) * omega;
    inverse.map(D::from) * (moment - omega.cross(&io))
}

/// `I⁻¹`, refused when `I` is singular (a body on a line, e.g. a thin rod).
fn inverse_of(inertia: &InertiaTensor) -> Result<Matrix3<f64>> {
    let m = inertia.matrix();
    let inv = m.cholesky().map(|c| c.inverse());
    match inv {
        Some(inv) if inv.iter().all(|x| x.is_finite()) => Ok(inv),
        _ => Err(Error::Singular {
            what: "inertia tensor I in Euler's equations".into(),
            at: format!("I = {:?}", m.as_slice()),
            rcond: 0.0,
        }),
    }
}

/// The angular acceleration `ω̇` of Euler's equations `I ω̇ + ω × Iω = M` [SPEC M32] for the
/// tensor `inertia`, the applied moment `M` and the angular velocity `ω`, all in body axes.
///
/// # Errors
/// [`Error::NonFinite`] for non-finite input or result; [`Error::Singular`] for a singular
/// tensor.
pub fn euler_rhs(
    inertia: &InertiaTensor,
    moment: &Vector3<f64>,
    omega: &Vector3<f64>,
) -> Result<Vector3<f64>> {
    all_finite("moment M", moment.as_slice())?;
    all_finite("angular velocity ω", omega.as_slice())?;
    let inv = inverse_of(inertia)?;
    let w = euler_rhs_generic(inertia.matrix(), &inv, moment, omega);
    all_finite("ω̇ of Euler's equations", w.as_slice())?;
    Ok(w)
}

/// The linearisation `∂ω̇/∂ω` of Euler's equations at `ω` with a constant moment `M`, by
/// forward-mode AD of [`euler_rhs_generic`] (Ardema 12.3: the indirect method).
///
/// # Errors
/// As [`euler_rhs`].
pub fn euler_jacobian(
    inertia: &InertiaTensor,
    moment: &Vector3<f64>,
    omega: &Vector3<f64>,
) -> Result<Matrix3<f64>> {
    euler_rhs(inertia, moment, omega)?;
    let inv = inverse_of(inertia)?;
    let m = moment.map(Dual64::from);
    let mut jac = Matrix3::zeros();
    for j in 0..3 {
        let w = Vector3::from_fn(|i, _| {
            let d = Dual64::from(omega[i]);
            if i == j {
                d.derivative()
            } else {
                d
            }
        });
        let f = euler_rhs_generic(inertia.matrix(), &inv, &m, &w);
        for i in 0..3 {
            jac[(i, j)] = f[i].eps;
        }
    }
    all_finite("Jacobian of Euler's equations", jac.as_slice())?;
    Ok(jac)
}

/// The growth rate of a small perturbation of a steady spin `Ω` about principal axis 2 of a body
/// with principal moments `(I₁, I₂, I₃)`: `λ = Ω √((I₂ − I₁)(I₃ − I₂)/(I₁ I₃))` when `I₂` lies
/// strictly between `I₁` and `I₃` (the intermediate axis is unstable), and `0` otherwise (the
/// perturbation oscillates) [Ardema Prob. 12/4; Hamel art. 242; SPEC T30].
///
/// # Errors
/// [`Error::OutOfDomain`]/[`Error::NonFinite`] for a non-positive moment or non-finite input.
pub fn intermediate_axis_growth_rate(moments: &Vector3<f64>, spin: f64) -> Result<f64> {
    for (i, m) in moments.iter().enumerate() {
        positive(format!("principal moment I{}", i + 1), *m)?;
    }
    let spin = finite("spin Ω", spin)?;
    let (i1, i2, i3) = (moments[0], moments[1], moments[2]);
    let a = (i2 - i1) / i1;
    let b = (i3 - i2) / i3;
    if a * b <= 0.0 {
        return Ok(0.0);
    }
    finite("growth rate", spin.abs() * a.sqrt() * b.sqrt())
}

/// The gyroscopic moment `M = J ω_s Ω` needed to hold the spin axis of a body of axial moment of
/// inertia `J` spinning at `ω_s` at right angles to a precession at rate `Ω` [Ardema 11.3,
/// eqs. 11.27–11.29; SPEC M31].
///
/// # Errors
/// [`Error::OutOfDomain`]/[`Error::NonFinite`] for `J ≤ 0` or non-finite input or result.
pub fn gyroscopic_moment(j: f64, spin: f64, precession: f64) -> Result<f64> {
    let j = positive("axial moment of inertia J", j)?;
    let spin = finite("spin ω_s", spin)?;
    let precession = finite("precession rate Ω", precession)?;
    finite("gyroscopic moment J ω_s Ω", j * spin * precession)
}

/// The torque-free rigid body in canonical form: 3-1-3 Euler angles `q = (φ, θ, ψ)` (body to
/// space, [`super::rotation`]) and their conjugate momenta `p = (p_φ, p_θ, p_ψ)`.
///
/// With `ω = B(θ, ψ) q̇` and `T = ½ ωᵀ diag(I₁, I₂, I₃) ω`, the momenta are `p = Bᵀ Π` with the
/// body angular momentum `Π = Iω`, so that [Goldstein §5.4; Ardema 11.1]
///
/// ```math
/// \Pi_1 = \frac{(p_\phi - p_\psi\cos\theta)\sin\psi}{\sin\theta} + p_\theta\cos\psi,\quad
/// \Pi_2 = \frac{(p_\phi - p_\psi\cos\theta)\cos\psi}{\sin\theta} - p_\theta\sin\psi,\quad
/// \Pi_3 = p_\psi,
/// ```
///
/// ```math
/// H = \frac{\Pi_1^2}{2I_1} + \frac{\Pi_2^2}{2I_2} + \frac{\Pi_3^2}{2I_3}.
/// ```
///
/// Hamilton's equations in these coordinates reproduce Euler's equations `Π̇ = Π × ω`; `p_φ` is
/// the spatial vertical component of the angular momentum and `|Π|²` its squared magnitude.
/// The chart is singular at `sin θ = 0` ([`check_chart`]); checked entry points refuse it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FreeRigidBody {
    moments: Vector3<f64>,
}

impl FreeRigidBody {
    /// A body with principal moments `(I₁, I₂, I₃)`, each positive and at most the sum of the
    /// other two.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`]/[`Error::NonFinite`] for a non-positive moment;
    /// [`Error::InvalidInput`] for moments violating the triangle inequality.
    pub fn new(moments: Vector3<f64>) -> Result<Self> {
        for (i, m) in moments.iter().enumerate() {
            positive(format!("principal moment I{}", i + 1), *m)?;
        }
        InertiaTensor::principal(moments)?;
        Ok(Self { moments })
    }

    /// A body with the given positive, finite moments, not checked against the triangle
    /// inequality: the symmetric top is also used as a model with any positive moments.
    pub(in crate::systems) fn with_moments_unchecked(moments: Vector3<f64>) -> Self {
        Self { moments }
    }

    /// The principal moments `(I₁, I₂, I₃)`.
    pub fn moments(&self) -> &Vector3<f64> {
        &self.moments
    }

    /// The body angular momentum `Π(q, p) = B⁻ᵀ p` (struct docs), for any number type; no check
    /// of the chart.
    pub fn body_momentum_generic<D: DualNum<f64> + Copy>(
        q: &SVector<D, 3>,
        p: &SVector<D, 3>,
    ) -> Vector3<D> {
        let (st, ct) = q[1].sin_cos();
        let (sp, cp) = q[2].sin_cos();
        let a = (p[0] - p[2] * ct) / st;
        Vector3::new(a * sp + p[1] * cp, a * cp - p[1] * sp, p[2])
    }

    /// The body angular momentum `Π` at `(q, p)`.
    ///
    /// # Errors
    /// [`Error::Singular`] at the chart singularity; [`Error::NonFinite`] for non-finite input.
    pub fn body_momentum(q: &SVector<f64, 3>, p: &SVector<f64, 3>) -> Result<Vector3<f64>> {
        check_phase(0.0, q, p)?;
        check_chart(q[1])?;
        let pi = Self::body_momentum_generic(q, p);
        all_finite("body angular momentum Π", pi.as_slice())?;
        Ok(pi)
    }

    /// The canonical momenta `p = Bᵀ(θ, ψ) Π` of the angles `q` and the body angular momentum `Π`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for non-finite input or result.
    pub fn momenta(q: &SVector<f64, 3>, pi: &Vector3<f64>) -> Result<SVector<f64, 3>> {
        all_finite("Euler angles", q.as_slice())?;
        all_finite("body angular momentum Π", pi.as_slice())?;
        let p = euler313_matrix(q[1], q[2]).transpose() * pi;
        all_finite("canonical momenta", p.as_slice())?;
        Ok(p)
    }

    /// The energy `Σ Π_i²/(2I_i)` of a body angular momentum, for any number type.
    pub fn energy_generic<D: DualNum<f64> + Copy>(&self, pi: &Vector3<D>) -> D {
        pi[0] * pi[0] * (0.5 / self.moments[0])
            + pi[1] * pi[1] * (0.5 / self.moments[1])
            + pi[2] * pi[2] * (0.5 / self.moments[2])
    }

    /// Euler's equations of the free body in `Π`: `Π̇ = Π × ω`, `ω_i = Π_i/I_i`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for non-finite input or result.
    pub fn euler_field(&self, pi: &Vector3<f64>) -> Result<Vector3<f64>> {
        all_finite("body angular momentum Π", pi.as_slice())?;
        let w = pi.component_div(&self.moments);
        let d = pi.cross(&w);
        all_finite("Π̇", d.as_slice())?;
        Ok(d)
    }
}

impl Hamiltonian<3> for FreeRigidBody {
    #[inline]
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 3>,
        p: &SVector<D, 3>,
    ) -> D {
        self.energy_generic(&Self::body_momentum_generic(q, p))
    }

    euler_chart_entry_points!();
}

impl Invariants<3> for FreeRigidBody {
    /// `energy` (H), `L2` (`|Π|²`, the squared angular momentum) and `p_phi` (its spatial
    /// vertical component).
    fn invariants(
        &self,
        t: f64,
        q: &SVector<f64, 3>,
        p: &SVector<f64, 3>,
    ) -> Result<Vec<Invariant>> {
        let energy = self.value(t, q, p)?;
        let pi = Self::body_momentum(q, p)?;
        Ok(vec![
            Invariant {
                name: "energy",
                value: energy,
            },
            Invariant {
                name: "L2",
                value: finite("|Π|²", pi.norm_squared())?,
            },
            Invariant {
                name: "p_phi",
                value: p[0],
            },
        ])
    }
}

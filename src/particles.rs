//! Systems of particles described by their positions in generalized coordinates
//! [Ardema 6.1–6.3; SPEC M14, M15]: the kinetic energy, its split into parts of degree 2, 1 and 0
//! in the velocities, the generalized forces of applied forces, and the Lagrangian — all by AD
//! from the positions `u_r(t, q)` written once.
//!
//! With `u̇_r = Σ_s ∂u_r/∂q_s q̇_s + ∂u_r/∂t`,
//!
//! ```math
//! T = \sum_r \tfrac12 m_r |\dot u_r|^2 = T_2 + T_1 + T_0,\quad
//! T_2 = \tfrac12 \dot q^{\mathsf T} a\, \dot q,\ T_1 = b^{\mathsf T}\dot q,\
//! T_0 = \tfrac12 \sum_r m_r \Big|\frac{\partial u_r}{\partial t}\Big|^2 ,
//! ```
//!
//! with `a = Σ m_r J_rᵀJ_r`, `b = Σ m_r J_rᵀ ∂u_r/∂t`, `J_r = ∂u_r/∂q` [Ardema eqs. 6.2–6.5], and the
//! generalized forces of applied forces `F_r` are the projections [Ardema eq. 6.13]
//!
//! ```math
//! Q_s = \sum_r F_r\cdot\frac{\partial u_r}{\partial q_s} .
//! ```
//!
//! `u̇_r` is the derivative of `u_r` along `(q̇, 1)` in `(q, t)`: one evaluation of the positions
//! on dual numbers nested over the caller's number type, so the Lagrangian stays generic over
//! [`DualNum`] and every method that takes a [`Lagrangian`] applies.

use crate::ad::{gradient, GradDual};
use crate::error::{all_finite, finite, Result};
use crate::lagrangian::{check_state, Lagrangian};
use nalgebra::{SVector, Vector3};
use num_dual::{Dual, DualNum};

/// `P` particles whose positions are given in `N` generalized coordinates (module docs).
pub trait ParticleSystem<const N: usize, const P: usize> {
    /// The masses `m_r`.
    fn masses(&self) -> [f64; P];
    /// The positions `u_r(t, q)`.
    fn positions<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> [Vector3<D>; P];
    /// The potential energy `V(t, q)` of the conservative forces (default zero).
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, _q: &SVector<D, N>) -> D {
        D::from(0.0)
    }
    /// Applied forces `F_r(t, q, q̇)` not derived from `V`; `None` (default) for none.
    fn applied_forces<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, N>,
        _qdot: &SVector<D, N>,
    ) -> Option<[Vector3<D>; P]> {
        None
    }
}

/// The velocities `u̇_r` of the particles, for any number type.
pub fn particle_velocities<S, D, const N: usize, const P: usize>(
    system: &S,
    t: D,
    q: &SVector<D, N>,
    qdot: &SVector<D, N>,
) -> [Vector3<D>; P]
where
    S: ParticleSystem<N, P> + ?Sized,
    D: DualNum<f64> + Copy,
{
    let tt = Dual::new(t, D::from(1.0));
    let qq = SVector::from_fn(|i, _| Dual::new(q[i], qdot[i]));
    system.positions(tt, &qq).map(|u| u.map(|x| x.eps))
}

/// `T = Σ ½ m_r |u̇_r|²`, for any number type.
pub fn particle_kinetic_energy<S, D, const N: usize, const P: usize>(
    system: &S,
    t: D,
    q: &SVector<D, N>,
    qdot: &SVector<D, N>,
) -> D
where
    S: ParticleSystem<N, P> + ?Sized,
    D: DualNum<f64> + Copy,
{
    let m = system.masses();
    particle_velocities(system, t, q, qdot)
        .iter()
        .zip(m.iter())
        .fold(D::from(0.0), |acc, (v, &mr)| acc + v.dot(v) * (0.5 * mr))
}

/// The parts `(T₂, T₁, T₀)` of the kinetic energy of degree 2, 1 and 0 in `q̇` (module docs),
/// from `T(λq̇) = λ²T₂ + λT₁ + T₀` at `λ = 0, ±1`.
///
/// # Errors
/// [`crate::Error::NonFinite`] for non-finite input or result.
pub fn kinetic_energy_split<S: ParticleSystem<N, P> + ?Sized, const N: usize, const P: usize>(
    system: &S,
    t: f64,
    q: &SVector<f64, N>,
    qdot: &SVector<f64, N>,
) -> Result<(f64, f64, f64)> {
    check_state(t, q, qdot)?;
    let at = |l: f64| particle_kinetic_energy(system, t, q, &(qdot * l));
    let (plus, minus, zero) = (at(1.0), at(-1.0), at(0.0));
    let split = (0.5 * (plus + minus) - zero, 0.5 * (plus - minus), zero);
    finite("T₂", split.0)?;
    finite("T₁", split.1)?;
    finite("T₀", split.2)?;
    Ok(split)
}

/// The generalized forces `Q_s = Σ F_r·∂u_r/∂q_s` of forces `F_r` applied at the particles
/// (module docs), for any number type.
pub fn generalized_forces<S, D, const N: usize, const P: usize>(
    system: &S,
    t: D,
    q: &SVector<D, N>,
    forces: &[Vector3<D>; P],
) -> SVector<D, N>
where
    S: ParticleSystem<N, P> + ?Sized,
    D: DualNum<f64> + Copy,
{
    gradient(
        |qq| {
            let u = system.positions(GradDual::from_re(t), qq);
            u.iter()
                .zip(forces.iter())
                .fold(GradDual::from_re(D::from(0.0)), |acc, (ur, f)| {
                    acc + ur.x * GradDual::from_re(f.x)
                        + ur.y * GradDual::from_re(f.y)
                        + ur.z * GradDual::from_re(f.z)
                })
        },
        q,
    )
    .1
}

/// The generalized forces of forces applied at the particles, on reals with checks.
///
/// # Errors
/// [`crate::Error::NonFinite`] for non-finite input or result.
pub fn checked_generalized_forces<
    S: ParticleSystem<N, P> + ?Sized,
    const N: usize,
    const P: usize,
>(
    system: &S,
    t: f64,
    q: &SVector<f64, N>,
    forces: &[Vector3<f64>; P],
) -> Result<SVector<f64, N>> {
    finite("time t", t)?;
    all_finite("coordinates q", q.as_slice())?;
    for f in forces {
        all_finite("applied force F_r", f.as_slice())?;
    }
    let g = generalized_forces(system, t, q, forces);
    all_finite("generalized forces Q", g.as_slice())?;
    Ok(g)
}

/// The power of the applied forces `Σ_r F_r·u̇_r` (those not derived from `V`) at `(t, q, q̇)`
/// [Ardema 4.1, eqs. 4.9–4.12; SPEC M7]. Along a motion of a catastatic system (positions
/// independent of `t`) with a time-independent potential, the work–energy relation reads
///
/// ```math
/// \frac{d}{dt}(T + V) = \sum_r F_r\cdot\dot u_r,\qquad
/// T + V = \int \sum_r F_r\cdot du_r + h ;
/// ```
///
/// for moving constraints the power of the constraint forces enters as well (the Jacobi integral
/// replaces `T + V`, [`Lagrangian::jacobi_integral`]). Zero without applied forces.
///
/// # Errors
/// [`crate::Error::NonFinite`] for non-finite input or result.
pub fn applied_power<S: ParticleSystem<N, P> + ?Sized, const N: usize, const P: usize>(
    system: &S,
    t: f64,
    q: &SVector<f64, N>,
    qdot: &SVector<f64, N>,
) -> Result<f64> {
    check_state(t, q, qdot)?;
    let Some(forces) = system.applied_forces(t, q, qdot) else {
        return Ok(0.0);
    };
    let velocities = particle_velocities(system, t, q, qdot);
    let power = forces
        .iter()
        .zip(velocities.iter())
        .fold(0.0, |acc, (f, v)| acc + f.dot(v));
    finite("power of the applied forces Σ F·u̇", power)
}

/// A [`ParticleSystem`] of `P` particles as a [`Lagrangian`]: `L = T − V`, with the generalized
/// forces of its applied forces as `Q^nc`.
#[derive(Clone, Copy, Debug)]
pub struct Particles<S, const P: usize>(pub S);

impl<S: ParticleSystem<N, P>, const N: usize, const P: usize> Lagrangian<N> for Particles<S, P> {
    fn lagrangian<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        qdot: &SVector<D, N>,
    ) -> D {
        particle_kinetic_energy(&self.0, t, q, qdot) - self.0.potential(t, q)
    }
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        qdot: &SVector<D, N>,
    ) -> Option<SVector<D, N>> {
        let f = self.0.applied_forces(t, q, qdot)?;
        Some(generalized_forces(&self.0, t, q, &f))
    }
}

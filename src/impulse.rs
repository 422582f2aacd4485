//! Impulsive motion [Ardema ch. 13; SPEC M38–M40]: velocity jumps of a Lagrangian system from
//! applied impulses and from constraints imposed suddenly, with the impulses of the constraints
//! and the change of kinetic energy.
//!
//! # The impulsive Lagrange equations
//! Over an impact of vanishing duration the positions do not change and only impulsive forces
//! count; integrating Lagrange's equations over it gives [Ardema 13.4, eqs. 13.37–13.39]
//!
//! ```math
//! \Big[\frac{\partial L}{\partial \dot q_s}\Big]_-^+ = \hat P_s + \sum_r \hat\lambda_r B_{rs},
//! \qquad \sum_s B_{rs}\dot q_s^+ + b_r = 0 ,
//! ```
//!
//! with `P̂_s = lim ∫ Q_s dt` the generalized impulses of the applied impulses (for an impulse
//! `P` at a point `x(q)`, `P̂ = (∂x/∂q)ᵀ P`: [`generalized_impulse`]) and `λ̂` the impulses of the
//! constraints `B q̇ + b = 0` that hold after the impact (the crate's multiplier sign, SPEC §0.3:
//! the constraint force is `Bᵀλ`). Constraints already holding before the impact are **inert**
//! if they are imposed suddenly (their coefficients `B` jump from zero, e.g. a point caught by a
//! hinge) and **live** if their `b` jumps (e.g. an elevator floor suddenly given a velocity)
//! [Ardema 13.2]; both are the `(B, b)` of the constraints after the impact.
//!
//! For a natural system (`L` quadratic in `q̇`) the momenta are linear in the velocities,
//! `a(q)(q̇⁺ − q̇⁻) = P̂ + Bᵀλ̂`, and with `Δ₀ = a⁻¹P̂` the jump without constraints,
//!
//! ```math
//! (B a^{-1} B^{\mathsf T})\,\hat\lambda = -\big(B(\dot q^- + \Delta_0) + b\big) .
//! ```
//!
//! For any `L` the same equations are solved by Newton's method on `λ̂`, the velocities from the
//! momenta by the inverse Legendre map ([`crate::lagrangian::velocity_from_momentum`]); for a
//! natural system it converges in one step.
//!
//! # Extremum theorems [Ardema 13.3, eqs. 13.33–13.36; SPEC M40]
//! For a natural system the actual jump minimises Gauss's `Z = ½ (Δ − a⁻¹P̂)ᵀ a (Δ − a⁻¹P̂)` over
//! the admissible jumps; from rest with prescribed velocities (Kelvin) it has the least kinetic
//! energy, and (Bertrand) added constraints lower `T⁺` by the kinetic energy of the difference.
//! The energy change of free impulses is `ΔT = P̂·(q̇⁺ + q̇⁻)/2`. These are checked in
//! `tests/impulse.rs`, by minimisation with `argmin`.

use crate::ad::{gradient, GradDual};
use crate::constraints::PfaffianConstraints;
use crate::error::{all_finite, Error, Result};
use crate::lagrangian::{velocity_from_momentum, Lagrangian};
use crate::particles::ParticleSystem;
use crate::phase::checked_inverse;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// The outcome of an impact: velocities before and after, the impulses of the constraints, and
/// the kinetic energy before and after.
#[derive(Clone, Debug, PartialEq)]
pub struct ImpulsiveJump<const N: usize, const K: usize> {
    /// `q̇⁻`.
    pub velocity_before: SVector<f64, N>,
    /// `q̇⁺`.
    pub velocity_after: SVector<f64, N>,
    /// The constraint impulses `λ̂` (constraint impulse `Bᵀλ̂` in the generalized coordinates).
    pub constraint_impulses: SVector<f64, K>,
    /// The energy `h = q̇·∂L/∂q̇ − L` before the impact (`T` for a natural scleronomic system).
    pub energy_before: f64,
    /// The energy after the impact.
    pub energy_after: f64,
}

impl<const N: usize, const K: usize> ImpulsiveJump<N, K> {
    /// The jump `q̇⁺ − q̇⁻`.
    pub fn velocity_jump(&self) -> SVector<f64, N> {
        self.velocity_after - self.velocity_before
    }
    /// The energy change `h⁺ − h⁻` (for free impulses on a natural system,
    /// `P̂·(q̇⁺ + q̇⁻)/2`).
    pub fn energy_change(&self) -> f64 {
        self.energy_after - self.energy_before
    }
}

/// No constraints: the set of zero Pfaffian forms, for [`impose_constraints`] with applied
/// impulses only ([`apply_impulse`]).
#[derive(Clone, Copy, Debug, Default)]
pub struct Unconstrained;

impl<const N: usize> PfaffianConstraints<N, 0> for Unconstrained {
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, N>,
    ) -> (SMatrix<D, 0, N>, SVector<D, 0>) {
        (SMatrix::zeros(), SVector::zeros())
    }
}

/// The jump of the velocities under the generalized impulses `P̂` alone (M39, SPEC's
/// `apply_impulse`): `[∂L/∂q̇]₋⁺ = P̂`.
///
/// # Errors
/// As [`impose_constraints`].
pub fn apply_impulse<L: Lagrangian<N>, const N: usize>(
    lagrangian: &L,
    t: f64,
    q: &SVector<f64, N>,
    velocity_before: &SVector<f64, N>,
    impulse: &SVector<f64, N>,
) -> Result<ImpulsiveJump<N, 0>> {
    impose_constraints(lagrangian, &Unconstrained, t, q, velocity_before, impulse)
}

/// The energy `h = q̇·∂L/∂q̇ − L`.
fn energy<L: Lagrangian<N>, const N: usize>(
    l: &L,
    t: f64,
    q: &SVector<f64, N>,
    v: &SVector<f64, N>,
) -> Result<f64> {
    let p = l.momentum(t, q, v)?;
    crate::error::finite("energy q̇·∂L/∂q̇ − L", p.dot(v) - l.value(t, q, v)?)
}

/// Newton iterations on the constraint impulses before [`Error::NotConverged`].
const MAX_NEWTON: usize = 50;

/// The jump of the velocities under the generalized impulses `P̂` with the Pfaffian constraints
/// `B q̇⁺ + b = 0` holding after the impact (M38–M39, module docs): `q̇⁺` and the constraint
/// impulses `λ̂`.
///
/// # Errors
/// [`Error::NonFinite`] for non-finite input; [`Error::Singular`] for a singular mass matrix or
/// dependent constraints (`B a⁻¹ Bᵀ` singular), naming the configuration;
/// [`Error::NotConverged`] if Newton's method on `λ̂` does not converge (a Lagrangian far from
/// quadratic in `q̇`).
pub fn impose_constraints<L, C, const N: usize, const K: usize>(
    lagrangian: &L,
    constraints: &C,
    t: f64,
    q: &SVector<f64, N>,
    velocity_before: &SVector<f64, N>,
    impulse: &SVector<f64, N>,
) -> Result<ImpulsiveJump<N, K>>
where
    L: Lagrangian<N>,
    C: PfaffianConstraints<N, K>,
{
    all_finite("generalized impulse P̂", impulse.as_slice())?;
    let at = || format!("t = {t:e}, q = {:?}", q.as_slice());
    let p_before = lagrangian.momentum(t, q, velocity_before)?;
    let energy_before = energy(lagrangian, t, q, velocity_before)?;
    let (b, b0) = constraints.forms(t, q);
    all_finite("constraint forms B", b.as_slice())?;
    all_finite("constraint forms b", b0.as_slice())?;
    let p_free = p_before + impulse;
    all_finite("momenta after the impulse", p_free.as_slice())?;
    let mut lambda = SVector::<f64, K>::zeros();
    let mut v = velocity_from_momentum(lagrangian, t, q, &p_free)?;
    let scale = |v: &SVector<f64, N>| (b.abs() * v.abs() + b0.abs()).amax().max(f64::MIN_POSITIVE);
    let mut converged = K == 0;
    for _ in 0..MAX_NEWTON {
        if converged {
            break;
        }
        let residual = b * v + b0;
        let a = lagrangian.mass_matrix(t, q, &v)?;
        let a_inv = checked_inverse(&a, "mass matrix ∂²L/∂q̇² at the impact", at)?;
        let s = b * a_inv * b.transpose();
        let s_inv = checked_inverse(&s, "constraint matrix B a⁻¹ Bᵀ at the impact", at)?;
        let step = s_inv * residual;
        lambda -= step;
        let v_next = velocity_from_momentum(lagrangian, t, q, &(p_free + b.transpose() * lambda))?;
        let change = (v_next - v).amax();
        v = v_next;
        let r = (b * v + b0).amax();
        converged = r <= 64.0 * f64::EPSILON * scale(&v)
            || change <= 16.0 * f64::EPSILON * v.amax().max(f64::MIN_POSITIVE);
    }
    if !converged {
        return Err(Error::NotConverged {
            what: format!("impulsive constraint equations at {}", at()),
            iterations: MAX_NEWTON,
            residual: (b * v + b0).amax(),
        });
    }
    all_finite("velocities after the impact", v.as_slice())?;
    all_finite("constraint impulses", lambda.as_slice())?;
    let energy_after = energy(lagrangian, t, q, &v)?;
    Ok(ImpulsiveJump {
        velocity_before: *velocity_before,
        velocity_after: v,
        constraint_impulses: lambda,
        energy_before,
        energy_after,
    })
}

/// A point of a system whose position `x(t, q)` (in `M` dimensions) receives an impulse.
pub trait ImpactPoint<const N: usize, const M: usize> {
    /// The position `x(t, q)`.
    fn position<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> SVector<D, M>;
}

/// Particle `r` of a [`ParticleSystem`] as an [`ImpactPoint`]: the position the system already
/// defines, so a blow on one of its particles needs no second description of it.
#[derive(Clone, Copy, Debug)]
pub struct ParticleOf<'a, S: ?Sized, const P: usize> {
    system: &'a S,
    index: usize,
}

impl<'a, S: ?Sized, const P: usize> ParticleOf<'a, S, P> {
    /// Particle `index` (`< P`) of `system`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for an index beyond the system's `P` particles.
    pub fn new(system: &'a S, index: usize) -> Result<Self> {
        if index >= P {
            return Err(Error::invalid(
                "particle index",
                format!(
                    "{index} is not one of the system's {P} particles (0 … {})",
                    P.saturating_sub(1)
                ),
            ));
        }
        Ok(Self { system, index })
    }
}

impl<S: ParticleSystem<N, P> + ?Sized, const N: usize, const P: usize> ImpactPoint<N, 3>
    for ParticleOf<'_, S, P>
{
    fn position<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> SVector<D, 3> {
        self.system.positions(t, q)[self.index]
    }
}

/// The generalized impulse of an impulse `P` at the point `x(t, q)`: `P̂ = (∂x/∂q)ᵀ P`
/// [Ardema eq. 13.38] (the projection of M15 for impulses), by AD.
///
/// # Errors
/// [`Error::NonFinite`] for non-finite input or result.
pub fn generalized_impulse<X: ImpactPoint<N, M>, const N: usize, const M: usize>(
    point: &X,
    t: f64,
    q: &SVector<f64, N>,
    impulse: &SVector<f64, M>,
) -> Result<SVector<f64, N>> {
    all_finite("coordinates q", q.as_slice())?;
    all_finite("impulse P", impulse.as_slice())?;
    crate::error::finite("time t", t)?;
    // P·x(q) differentiated: one gradient pass.
    let (_, g) = gradient(
        |qq| {
            let x = point.position(GradDual::from_re(t), qq);
            x.iter()
                .zip(impulse.iter())
                .fold(GradDual::from_re(0.0), |acc, (xi, &pi)| acc + *xi * pi)
        },
        q,
    );
    all_finite("generalized impulse P̂", g.as_slice())?;
    Ok(g)
}

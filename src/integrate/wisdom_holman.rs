//! Wisdom–Holman splitting for a Kepler problem plus a position-dependent perturbation,
//!
//! $$ H = \underbrace{\tfrac12|p|^2 - \frac{\mu}{|q|}}_{A = H_K} + \underbrace{H_1(t, q)}_{B}, $$
//!
//! with the exact Kepler flow as the `A` sub-step (a *Kepler drift*) and the kick
//! `p ↦ p − h ∇H₁(q)` as the `B` sub-step (J. Wisdom & M. Holman, "Symplectic maps for the
//! n-body problem", Astron. J. 102 (1991) 1528–1538, doi:10.1086/115978). For `H₁ = O(ε)` the
//! error of the second-order map is `O(ε h²)` instead of `O(h²)`; Laskar & Robutel's `SABA_n` and
//! `SBAB_n` push the `ε` term to `O(ε h^{2n} + ε² h²)` (J. Laskar & P. Robutel, Celest. Mech. Dyn.
//! Astron. 80 (2001) 39–62, doi:10.1023/A:1012098603882). Tables in
//! [`coefficients`], run by the same composition kernel as
//! [`Splitting`](super::Splitting).
//!
//! # The Kepler drift
//! The `A` sub-step is the exact Kepler flow in universal variables,
//! [`crate::systems::kepler::drift`]: any conic, any dual type, with exact derivatives, so the
//! step of a Wisdom–Holman method can be certified symplectic by AD
//! ([`StepMap`](super::StepMap)).

use super::coefficients::{self, Table};
use super::splitting::{check_table, compose, SubFlows};
use super::{OneStep, Work};
use crate::ad::{gradient, GradDual};
use crate::error::{finite, positive, Error, Result};
use crate::hamiltonian::Separable;
use crate::systems::kepler;
use nalgebra::SVector;
use num_dual::DualNum;

pub use crate::hamiltonian::PerturbedKepler;

/// A Wisdom–Holman method (a Laskar–Robutel table with `A` = Kepler, `B` = perturbation).
///
/// Cost per step: one Kepler drift ([`Work::flows`](super::Work)) per `A` sub-step and one AD
/// gradient of `H₁` ([`Work::gradients`](super::Work)) per `B` sub-step; `SBAB_n` begins and
/// ends with a kick at the same position (`n + 1` kicks per stateless step, `n` with FSAL).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WisdomHolman {
    table: &'static Table,
}

impl WisdomHolman {
    /// The classical Wisdom–Holman map, kick–drift–kick (`= SBAB₁`).
    pub const WH: Self = Self::of(&coefficients::SBAB1);
    /// `SABA₁`: drift–kick–drift.
    pub const SABA1: Self = Self::of(&coefficients::SABA1);
    /// `SABA₂`.
    pub const SABA2: Self = Self::of(&coefficients::SABA2);
    /// `SABA₃`.
    pub const SABA3: Self = Self::of(&coefficients::SABA3);
    /// `SABA₄`.
    pub const SABA4: Self = Self::of(&coefficients::SABA4);
    /// `SBAB₁` (= [`WH`](Self::WH)).
    pub const SBAB1: Self = Self::of(&coefficients::SBAB1);
    /// `SBAB₂`.
    pub const SBAB2: Self = Self::of(&coefficients::SBAB2);
    /// `SBAB₃`.
    pub const SBAB3: Self = Self::of(&coefficients::SBAB3);
    /// `SBAB₄`.
    pub const SBAB4: Self = Self::of(&coefficients::SBAB4);

    const fn of(table: &'static Table) -> Self {
        Self { table }
    }

    /// Every shipped Wisdom–Holman method.
    pub fn all() -> Vec<Self> {
        coefficients::WISDOM_HOLMAN_TABLES
            .iter()
            .map(|t| Self::of(t))
            .collect()
    }

    /// A method from a user's table (checked for consistency as [`Splitting::new`](super::Splitting::new)).
    pub fn new(table: &'static Table) -> Result<Self> {
        check_table(table)?;
        Ok(Self::of(table))
    }

    /// The coefficient table.
    pub fn table(&self) -> &'static Table {
        self.table
    }
}

struct KeplerFlows<'a, S> {
    system: &'a S,
    mu: f64,
    work: &'a mut Work,
}

impl<S: PerturbedKepler<N>, D: DualNum<f64> + Copy, const N: usize> SubFlows<D, N>
    for KeplerFlows<'_, S>
{
    fn flow_a(
        &mut self,
        _t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        h: D,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        self.work.flows += 1;
        kepler::drift(self.mu, q, p, h)
    }
    fn flow_b(&mut self, t: D, q: &SVector<D, N>, h: D) -> Result<SVector<D, N>> {
        self.work.gradients += 1;
        let (_, g) = gradient(|qd| self.system.perturbation(GradDual::from_re(t), qd), q);
        Ok(g * (-h))
    }
}

impl<S: PerturbedKepler<N>, const N: usize> OneStep<S, N> for WisdomHolman {
    fn order(&self) -> u32 {
        self.table.order
    }
    fn name(&self) -> String {
        self.table.name.into()
    }
    #[inline]
    fn increment<D: DualNum<f64> + Copy>(
        &self,
        system: &S,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        dt: D,
        work: &mut Work,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        let mu = positive("gravitational parameter μ", system.mu())?;
        let mut flows = KeplerFlows { system, mu, work };
        compose(self.table, &mut flows, t, q, p, dt)
    }
}

// ---------------------------------------------------------------------------------------------
// A shipped perturbed Kepler system
// ---------------------------------------------------------------------------------------------

/// The Kepler problem with the quadrupole (`J₂`-like) field of an oblate central body of unit
/// radius, per unit mass:
///
/// $$ H = \tfrac12|p|^2 - \frac{\mu}{r} - \varepsilon\,\frac{\mu}{2r^3}\Big(1 - \frac{3z^2}{r^2}\Big),
///    \qquad r = |q|,\ z = q_3\ (\text{absent for } N = 2), $$
///
/// (the `P₂` term of the geopotential with `ε = J₂R²`; Vallado, *Fundamentals of Astrodynamics
/// and Applications*, 4th ed., 2013, §8.7). The orbit plane of a planar or equatorial orbit is
/// kept; to first order in `ε` the line of apsides of an equatorial orbit advances at the rate
/// `3εn/(2p²)` (`n` the mean motion, `p` the semi-latus rectum). A weak, smooth test
/// perturbation for Wisdom–Holman (which sees `H₁` only through its gradient) and, as a
/// [`Separable`] system with `V = −μ/r + H₁`, for every general method.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct KeplerJ2<const N: usize> {
    mu: f64,
    eps: f64,
}

impl<const N: usize> KeplerJ2<N> {
    /// The system with `μ > 0` and finite `ε` (any sign); `N` must be 2 or 3.
    pub fn new(mu: f64, eps: f64) -> Result<Self> {
        if !(N == 2 || N == 3) {
            return Err(Error::invalid(
                "KeplerJ2 dimension",
                format!("N = {N}; only 2 and 3 are supported"),
            ));
        }
        Ok(Self {
            mu: positive("gravitational parameter μ", mu)?,
            eps: finite("perturbation strength ε", eps)?,
        })
    }
    /// The strength `ε = J₂R²`.
    pub fn eps(&self) -> f64 {
        self.eps
    }
}

impl<const N: usize> PerturbedKepler<N> for KeplerJ2<N> {
    fn mu(&self) -> f64 {
        self.mu
    }
    #[inline]
    fn perturbation<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, N>) -> D {
        let r2 = q.dot(q);
        let r = r2.sqrt();
        let shape = if N == 3 {
            -(q[2] * q[2] / r2) * 3.0 + 1.0
        } else {
            D::from(1.0)
        };
        shape / (r2 * r) * (-0.5 * self.eps * self.mu)
    }
}

impl<const N: usize> Separable<N> for KeplerJ2<N> {
    #[inline]
    fn kinetic<D: DualNum<f64> + Copy>(&self, _t: D, p: &SVector<D, N>) -> D {
        p.dot(p) * 0.5
    }
    #[inline]
    fn potential<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> D {
        q.dot(q).sqrt().recip() * -self.mu + self.perturbation(t, q)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kepler_j2_rejects_bad_input() {
        assert!(KeplerJ2::<2>::new(1.0, f64::INFINITY).is_err());
        assert!(KeplerJ2::<4>::new(1.0, 0.1).is_err());
    }
}

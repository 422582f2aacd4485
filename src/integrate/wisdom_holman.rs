//! Wisdom–Holman splitting for a Kepler problem plus a position-dependent perturbation,
//!
//! ```math
//! H = \underbrace{\tfrac12|p|^2 - \frac{\mu}{|q|}}_{A = H_K} + \underbrace{H_1(t, q)}_{B},
//! ```
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
use super::methods::{Construction, METHODS};
use super::splitting::{check_table, compose, SubFlows};
use super::{OneStep, Work};
use crate::ad::{gradient, GradDual};
use crate::error::{positive, Result};
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
    /// The classical Wisdom–Holman map, kick–drift–kick (`= SBAB₁`): 1 stage, order 2
    /// (`wisdom-holman`).
    pub const WH: Self = Self::of(&coefficients::SBAB1);
    /// `SABA₁`, drift–kick–drift: 1 stage, order 2 (`saba1`).
    pub const SABA1: Self = Self::of(&coefficients::SABA1);
    /// `SABA₂`: 2 stages, order 2 (`saba2`).
    pub const SABA2: Self = Self::of(&coefficients::SABA2);
    /// `SABA₃`: 3 stages, order 2 (`saba3`).
    pub const SABA3: Self = Self::of(&coefficients::SABA3);
    /// `SABA₄`: 4 stages, order 2 (`saba4`).
    pub const SABA4: Self = Self::of(&coefficients::SABA4);
    /// `SBAB₂`: 2 stages, order 2 (`sbab2`).
    pub const SBAB2: Self = Self::of(&coefficients::SBAB2);
    /// `SBAB₃`: 3 stages, order 2 (`sbab3`).
    pub const SBAB3: Self = Self::of(&coefficients::SBAB3);
    /// `SBAB₄`: 4 stages, order 2 (`sbab4`).
    pub const SBAB4: Self = Self::of(&coefficients::SBAB4);

    const fn of(table: &'static Table) -> Self {
        Self { table }
    }

    /// Every shipped Wisdom–Holman method: the Kepler splittings of
    /// [`METHODS`].
    pub fn all() -> Vec<Self> {
        METHODS
            .iter()
            .filter_map(|m| match m.construction {
                Construction::KeplerSplitting(t) => Some(Self::of(t)),
                _ => None,
            })
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
        self.table.label()
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

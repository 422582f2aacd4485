//! Derivatives of the motion with respect to the system's parameters, by the forward sensitivity
//! equations run through any integrator of first-order systems.
//!
//! For Hamilton's equations `ż = f(k; t, z)` of a [`Parametric`] system with parameters
//! `k ∈ ℝᴹ`, the sensitivities `S = ∂z/∂k` (a `2N × M` matrix) obey the variational equations
//!
//! $$ \dot S = \frac{\partial f}{\partial z}\,S + \frac{\partial f}{\partial k},\qquad S(t_0) = 0 $$
//!
//! (Hairer, Nørsett & Wanner, *Solving Ordinary Differential Equations I*, 2nd ed., Springer 1993,
//! §I.14, "Differentiation with respect to parameters"). Each column `S e_j` is the directional
//! derivative of `f` along `(S e_j, e_j)` in `(z, k)`: one evaluation of the vector field on
//! dual numbers seeded with that direction gives `∂f/∂z · S e_j + ∂f/∂k_j` at once, from the same
//! Hamiltonian that gives the motion — nothing is written twice. [`ParameterSensitivity`] is the
//! augmented system `(z, S)` as a [`FirstOrderSystem`], so adaptive methods ([`Dop853`]) control
//! the error of the sensitivities together with that of the state.
//!
//! Stable Rust cannot write the augmented dimension `N(1 + M)` from generic `N` and `M`, so it is
//! a third const parameter `K`, checked by [`ParameterSensitivity::new`]. The augmented `q` block
//! is `(q, ∂q/∂k₁, …, ∂q/∂k_M)`, the `p` block likewise.
//!
//! [`Dop853`]: super::Dop853

use super::FirstOrderSystem;
use crate::ad::{augmented_state, phase_gradient, tangent_rates, PhaseDual};
use crate::error::{Error, Result};
use crate::hamiltonian::Parametric;
use nalgebra::{Const, SMatrix, SVector};
use num_dual::{Dual64, DualNum};

/// Hamilton's equations of a [`Parametric`] system at the parameters `k`, generic over the number
/// type: `(q̇, ṗ) = (∂H/∂p, −∂H/∂q)(k; t, q, p)`.
#[inline]
pub fn parametric_vector_field<S, D, const N: usize, const M: usize>(
    system: &S,
    k: &SVector<D, M>,
    t: D,
    q: &SVector<D, N>,
    p: &SVector<D, N>,
) -> (SVector<D, N>, SVector<D, N>)
where
    S: Parametric<N, M> + ?Sized,
    D: DualNum<f64> + Copy,
{
    let kd = k.map(PhaseDual::<D, f64, Const<N>>::from_re);
    let td = PhaseDual::from_re(t);
    let (_, hq, hp) = phase_gradient(|qd, pd| system.hamiltonian_with(&kd, td, qd, pd), q, p);
    (hp, -hq)
}

/// The state `(q, p)` of a [`Parametric`] system augmented with its sensitivities
/// `∂(q, p)/∂k`; see the [module docs](self). `K` must equal `N(1 + M)`.
#[derive(Clone, Copy, Debug)]
pub struct ParameterSensitivity<'a, S, const N: usize, const M: usize, const K: usize> {
    system: &'a S,
    k: SVector<f64, M>,
}

impl<'a, S: Parametric<N, M>, const N: usize, const M: usize, const K: usize>
    ParameterSensitivity<'a, S, N, M, K>
{
    /// The augmented system at the system's nominal parameters; an error unless `K = N(1 + M)`
    /// and the parameters are finite.
    pub fn new(system: &'a S) -> Result<Self> {
        if K != N * (1 + M) {
            return Err(Error::invalid(
                format!("augmented dimension K = {K} of a sensitivity system"),
                format!(
                    "with N = {N} degrees of freedom and M = {M} parameters K must be \
                     N(1 + M) = {}",
                    N * (1 + M)
                ),
            ));
        }
        let k = system.parameters();
        if let Some((i, v)) = k.iter().enumerate().find(|(_, v)| !v.is_finite()) {
            return Err(Error::NonFinite {
                what: format!("parameter {} of the system", S::NAMES[i]),
                value: *v,
            });
        }
        Ok(Self { system, k })
    }

    /// The augmented initial state: `(q₀, p₀)` with zero sensitivities (initial conditions that do
    /// not depend on the parameters).
    pub fn initial_state(
        &self,
        q0: &SVector<f64, N>,
        p0: &SVector<f64, N>,
    ) -> (SVector<f64, K>, SVector<f64, K>) {
        augmented_state(q0, p0, M, |_, _| 0.0)
    }

    /// Split an augmented state into `(q, p, ∂q/∂k, ∂p/∂k)`.
    #[allow(clippy::type_complexity)]
    pub fn split(
        &self,
        qa: &SVector<f64, K>,
        pa: &SVector<f64, K>,
    ) -> (
        SVector<f64, N>,
        SVector<f64, N>,
        SMatrix<f64, N, M>,
        SMatrix<f64, N, M>,
    ) {
        let q = qa.fixed_rows::<N>(0).into_owned();
        let p = pa.fixed_rows::<N>(0).into_owned();
        let sq = SMatrix::<f64, N, M>::from_fn(|i, j| qa[N * (1 + j) + i]);
        let sp = SMatrix::<f64, N, M>::from_fn(|i, j| pa[N * (1 + j) + i]);
        (q, p, sq, sp)
    }
}

impl<S: Parametric<N, M>, const N: usize, const M: usize, const K: usize> FirstOrderSystem<K>
    for ParameterSensitivity<'_, S, N, M, K>
{
    fn field(
        &self,
        t: f64,
        qa: &SVector<f64, K>,
        pa: &SVector<f64, K>,
    ) -> Result<(SVector<f64, K>, SVector<f64, K>)> {
        tangent_rates("sensitivity equations", t, qa, pa, M, |j, td, qs, ps| {
            let ks = SVector::<Dual64, M>::from_fn(|i, _| {
                Dual64::new(self.k[i], if i == j { 1.0 } else { 0.0 })
            });
            parametric_vector_field(self.system, &ks, td, qs, ps)
        })
    }
}

//! Derivatives of the motion with respect to the system's parameters and to the initial state, by
//! the forward sensitivity (variational) equations run through any integrator of first-order
//! systems.
//!
//! For Hamilton's equations `ż = f(k; t, z)` of a [`Parametric`] system with parameters
//! `k ∈ ℝᴹ`, the sensitivities `S = ∂z/∂k` (a `2N × M` matrix) obey the variational equations
//!
//! ```math
//! \dot S = \frac{\partial f}{\partial z}\,S + \frac{\partial f}{\partial k},\qquad S(t_0) = 0
//! ```
//!
//! (Hairer, Nørsett & Wanner, *Solving Ordinary Differential Equations I*, 2nd ed., Springer 1993,
//! §I.14, "Differentiation with respect to parameters"). Each column `S e_j` is the directional
//! derivative of `f` along `(S e_j, e_j)` in `(z, k)`: one evaluation of the vector field on
//! dual numbers seeded with that direction gives `∂f/∂z · S e_j + ∂f/∂k_j` at once, from the same
//! Hamiltonian that gives the motion — nothing is written twice. [`ParameterSensitivity`] is the
//! augmented system `(z, S)` as a [`FirstOrderSystem`], so adaptive methods ([`Dop853`]) control
//! the error of the sensitivities together with that of the state.
//!
//! With respect to the initial state `z₀` the same equations hold without the source term,
//! `Φ̇ = (∂f/∂z) Φ`, `Φ(t₀) = I` (the tangent map `Φ = ∂z/∂z₀`; HNW I.14, Theorem 14.1):
//! [`ParameterSensitivity::with_initial_state`] appends its `2N` columns (derivatives with respect
//! to `q₀₁ … q₀N, p₀₁ … p₀N`) to those of the parameters, and [`Unparametrised`] lets any
//! [`Hamiltonian`] use them with `M = 0`.
//!
//! Stable Rust cannot write the augmented dimension `N(1 + M)` (or `N(1 + M + 2N)`) from generic
//! `N` and `M`, so it is a third const parameter `K`, checked by the constructors. The augmented
//! `q` block is `(q, ∂q/∂k₁, …, ∂q/∂k_M[, ∂q/∂q₀₁, …, ∂q/∂p₀N])`, the `p` block likewise.
//!
//! [`Dop853`]: super::Dop853

use super::FirstOrderSystem;
use crate::ad::{augmented_state, phase_gradient, tangent_rates, PhaseDual};
use crate::error::{Error, Result};
use crate::hamiltonian::{Hamiltonian, Parametric, ParametricSeparable, Separable};
use crate::phase::PhaseMatrix;
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

/// Any [`Hamiltonian`] as a [`Parametric`] system without parameters (`M = 0`), so that its
/// tangent map `∂z/∂z₀` follows from [`ParameterSensitivity::with_initial_state`].
#[derive(Clone, Copy, Debug)]
pub struct Unparametrised<'a, H>(pub &'a H);

impl<H: Hamiltonian<N>, const N: usize> Parametric<N, 0> for Unparametrised<'_, H> {
    const NAMES: [&'static str; 0] = [];
    fn parameters(&self) -> SVector<f64, 0> {
        SVector::zeros()
    }
    fn hamiltonian_with<D: DualNum<f64> + Copy>(
        &self,
        _k: &SVector<D, 0>,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> D {
        self.0.hamiltonian(t, q, p)
    }
}

/// A [`Separable`] system as a [`ParametricSeparable`] one without parameters, so that the
/// splittings run it by the composition that carries parameter derivatives.
impl<H: Separable<N>, const N: usize> ParametricSeparable<N, 0> for Unparametrised<'_, H> {
    #[inline]
    fn kinetic_with<D: DualNum<f64> + Copy>(
        &self,
        _k: &SVector<D, 0>,
        t: D,
        p: &SVector<D, N>,
    ) -> D {
        self.0.kinetic(t, p)
    }
    #[inline]
    fn potential_with<D: DualNum<f64> + Copy>(
        &self,
        _k: &SVector<D, 0>,
        t: D,
        q: &SVector<D, N>,
    ) -> D {
        self.0.potential(t, q)
    }
    #[inline]
    fn kinetic_gradient_with<D: DualNum<f64> + Copy>(
        &self,
        _k: &SVector<D, 0>,
        t: D,
        p: &SVector<D, N>,
    ) -> (D, SVector<D, N>) {
        self.0.kinetic_gradient(t, p)
    }
    #[inline]
    fn potential_gradient_with<D: DualNum<f64> + Copy>(
        &self,
        _k: &SVector<D, 0>,
        t: D,
        q: &SVector<D, N>,
    ) -> (D, SVector<D, N>) {
        self.0.potential_gradient(t, q)
    }
}

/// The state `(q, p)` of a [`Parametric`] system augmented with its sensitivities
/// `∂(q, p)/∂k` (and, built by [`with_initial_state`](Self::with_initial_state), `∂(q, p)/∂(q₀,
/// p₀)`); see the [module docs](self). `K` must equal `N(1 + M)` (resp. `N(1 + M + 2N)`).
#[derive(Clone, Copy, Debug)]
pub struct ParameterSensitivity<'a, S, const N: usize, const M: usize, const K: usize> {
    system: &'a S,
    k: SVector<f64, M>,
    /// Whether the last `2N` columns are derivatives with respect to the initial state.
    initial_state: bool,
}

impl<'a, S: Parametric<N, M>, const N: usize, const M: usize, const K: usize>
    ParameterSensitivity<'a, S, N, M, K>
{
    /// The augmented system at the system's nominal parameters; an error unless `K = N(1 + M)`
    /// and the parameters are finite.
    pub fn new(system: &'a S) -> Result<Self> {
        Self::build(system, false)
    }

    /// The augmented system with the derivatives with respect to the initial state as well; an
    /// error unless `K = N(1 + M + 2N)` and the parameters are finite.
    pub fn with_initial_state(system: &'a S) -> Result<Self> {
        Self::build(system, true)
    }

    fn build(system: &'a S, initial_state: bool) -> Result<Self> {
        let columns = M + if initial_state { 2 * N } else { 0 };
        if K != N * (1 + columns) {
            return Err(Error::invalid(
                format!("augmented dimension K = {K} of a sensitivity system"),
                format!(
                    "with N = {N} degrees of freedom, M = {M} parameters{} K must be {}",
                    if initial_state {
                        " and the initial state"
                    } else {
                        ""
                    },
                    N * (1 + columns)
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
        Ok(Self {
            system,
            k,
            initial_state,
        })
    }

    /// The augmented initial state: `(q₀, p₀)` with zero sensitivities to the parameters (initial
    /// conditions that do not depend on them) and, with the initial state, `∂z/∂z₀ = I`.
    pub fn initial_state(
        &self,
        q0: &SVector<f64, N>,
        p0: &SVector<f64, N>,
    ) -> (SVector<f64, K>, SVector<f64, K>) {
        let columns = K / N - 1;
        let initial_state = self.initial_state;
        // Initial-state column M + r seeds row r of (q, p).
        augmented_state(q0, p0, columns, |r, j| {
            if initial_state && j >= M && r == j - M {
                1.0
            } else {
                0.0
            }
        })
    }

    /// The tangent map `∂(q, p)/∂(q₀, p₀)` of an augmented state; an error unless the system was
    /// built [`with_initial_state`](Self::with_initial_state).
    pub fn tangent(&self, qa: &SVector<f64, K>, pa: &SVector<f64, K>) -> Result<PhaseMatrix<N>> {
        if !self.initial_state {
            return Err(Error::invalid(
                "tangent map of a sensitivity system",
                "built without the initial state: use ParameterSensitivity::with_initial_state",
            ));
        }
        let col = |v: &SVector<f64, K>, c: usize| {
            SMatrix::<f64, N, N>::from_fn(|r, j| v[N * (1 + M + c + j) + r])
        };
        Ok(PhaseMatrix {
            qq: col(qa, 0),
            qp: col(qa, N),
            pq: col(pa, 0),
            pp: col(pa, N),
        })
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
        tangent_rates(
            "sensitivity equations",
            t,
            qa,
            pa,
            K / N - 1,
            |j, td, qs, ps| {
                // Parameter columns seed their parameter; initial-state columns none.
                let ks = SVector::<Dual64, M>::from_fn(|i, _| {
                    Dual64::new(self.k[i], if i == j { 1.0 } else { 0.0 })
                });
                parametric_vector_field(self.system, &ks, td, qs, ps)
            },
        )
    }
}

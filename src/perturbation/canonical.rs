//! Canonical variation of elements [Ardema 18.2, eqs. 18.26–18.31].
//!
//! Let `S(q, α, t)` be a complete integral of the unperturbed Hamilton–Jacobi equation. In the
//! Chapter-18 convention ([`ElementConvention::AlphaCoordinates`]) `S` is an F1
//! generator, `p = ∂S/∂q`, `β = −∂S/∂α`, and the unperturbed new Hamiltonian `H + ∂S/∂t` vanishes.
//! For `H + K` the new Hamiltonian is therefore
//!
//! ```math
//! K^*(\alpha, \beta, t) = K\big(q(\alpha, \beta, t),\, p(\alpha, \beta, t),\, t\big)
//! ```
//!
//! and the elements obey Hamilton's equations with it [Ardema eqs. 18.29–18.30]:
//!
//! ```math
//! \dot\alpha = \frac{\partial K^*}{\partial \beta},\qquad
//! \dot\beta = -\frac{\partial K^*}{\partial \alpha}
//! \qquad(\text{AlphaCoordinates}),
//! ```
//!
//! and, in the Chapter-17 convention ([`ElementConvention::AlphaMomenta`]: `β = +∂S/∂α` the new
//! coordinates, `α` the new momenta),
//!
//! ```math
//! \dot\beta = \frac{\partial K^*}{\partial \alpha},\qquad
//! \dot\alpha = -\frac{\partial K^*}{\partial \beta}
//! \qquad(\text{AlphaMomenta}).
//! ```
//!
//! The map `(α, β, t) ↦ (q, p)` is anything implementing [`CanonicalElements`]: the
//! [`Elements`] of a complete integral (Newton on `∂S/∂α = ∓β`, derivatives of the root exact by
//! implicit AD, [`Elements::state_generic`]), or a closed form. The gradient of `K*` is one AD pass
//! through the map and `K`.
//!
//! **Branches.** A complete integral is usually one branch of a multivalued function (the
//! oscillator's `p = +√(2α − n²θ²)` covers only `cos n(t − β) ≥ 0`); where the motion leaves the
//! branch the solve has no solution and the rate is an error. Long runs over many periods need a
//! closed-form (global) element map.
//!
//! **Averaging.** First-order secular rates are the mean of the rates over a fast phase
//! ([`average_over_phase`]); the result carries the oscillating spread so that the caller can
//! refuse averaging when the small parameter is not small ([`PhaseAverage::require_small`]).

use super::ode::{ElementOde, ElementPair};
use crate::ad::{phase_gradient, PhaseDual};
use crate::error::{all_finite, finite, positive, Error, Result};
use crate::hamilton_jacobi::complete::{CompleteIntegral, ElementConvention, Elements};
use crate::hamiltonian::PhaseFunction;
use crate::phase::{check_phase, PhaseMatrix};
use nalgebra::SVector;
use num_dual::DualNum;

/// Canonical elements `(α, β)` of an unperturbed motion: the state `(q, p)` as a function of
/// `(α, β, t)`, in any number type, with the convention that says which of `α`, `β` are
/// the new coordinates.
pub trait CanonicalElements<const N: usize> {
    /// Which role the `α` play.
    fn convention(&self) -> ElementConvention;

    /// `(q, p)(α, β, t)`; an error where the map is undefined (other branch, singular point).
    #[allow(clippy::type_complexity)]
    fn state_generic<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        alpha: &SVector<D, N>,
        beta: &SVector<D, N>,
    ) -> Result<(SVector<D, N>, SVector<D, N>)>;
}

impl<S: CompleteIntegral<N>, const N: usize> CanonicalElements<N> for Elements<S, N> {
    fn convention(&self) -> ElementConvention {
        Elements::convention(self)
    }
    fn state_generic<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        alpha: &SVector<D, N>,
        beta: &SVector<D, N>,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        Elements::state_generic(self, t, alpha, beta)
    }
}

impl<M: CanonicalElements<N> + ?Sized, const N: usize> CanonicalElements<N> for &M {
    fn convention(&self) -> ElementConvention {
        (**self).convention()
    }
    fn state_generic<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        alpha: &SVector<D, N>,
        beta: &SVector<D, N>,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        (**self).state_generic(t, alpha, beta)
    }
}

fn at<const N: usize>(t: f64, alpha: &SVector<f64, N>, beta: &SVector<f64, N>) -> String {
    format!(
        "t = {t}, α = {:?}, β = {:?}",
        alpha.as_slice(),
        beta.as_slice()
    )
}

/// `(K*, ∂K*/∂α, ∂K*/∂β)` at `(α, β, t)`, one AD pass through the element map and `K`.
///
/// Errors: non-finite input; the map's own error (no solution on this branch, a refused singular
/// solve); [`Error::NonFinite`] if `K*` is not finite; [`Error::Singular`] with `rcond = 0` if a
/// derivative is not finite at a finite `K*` (the elements are singular there).
pub fn disturbing_hamiltonian<M, K, const N: usize>(
    map: &M,
    k: &K,
    t: f64,
    alpha: &SVector<f64, N>,
    beta: &SVector<f64, N>,
) -> Result<(f64, SVector<f64, N>, SVector<f64, N>)>
where
    M: CanonicalElements<N> + ?Sized,
    K: PhaseFunction<N> + ?Sized,
{
    check_phase(t, alpha, beta)?;
    let mut failure = None;
    let (value, da, db) = phase_gradient(
        |a, b| {
            let td = PhaseDual::from_re(t);
            match map.state_generic(td, a, b) {
                Ok((q, p)) => k.eval(td, &q, &p),
                Err(e) => {
                    failure = Some(e);
                    PhaseDual::from_re(f64::NAN)
                }
            }
        },
        alpha,
        beta,
    );
    if let Some(e) = failure {
        return Err(e);
    }
    if !value.is_finite() {
        return Err(Error::NonFinite {
            what: format!("K*(α, β, t) at {}", at(t, alpha, beta)),
            value,
        });
    }
    if !(da.iter().chain(db.iter()).all(|v| v.is_finite())) {
        return Err(Error::Singular {
            what: "∂K*/∂(α, β) (not finite: the elements are singular here)".into(),
            at: at(t, alpha, beta),
            rcond: 0.0,
        });
    }
    Ok((value, da, db))
}

/// The canonical element equations at `(α, β, t)`: `(α̇, β̇)` in the convention of `map`
/// (see the [module docs](self) for both sign conventions).
pub fn canonical_element_rhs<M, K, const N: usize>(
    map: &M,
    k: &K,
    t: f64,
    alpha: &SVector<f64, N>,
    beta: &SVector<f64, N>,
) -> Result<ElementPair<N>>
where
    M: CanonicalElements<N> + ?Sized,
    K: PhaseFunction<N> + ?Sized,
{
    let (_, ka, kb) = disturbing_hamiltonian(map, k, t, alpha, beta)?;
    Ok(match map.convention() {
        // (Q, P) = (α, β): α̇ = ∂K*/∂β, β̇ = −∂K*/∂α.
        ElementConvention::AlphaCoordinates => (kb, -ka),
        // (Q, P) = (β, α): β̇ = ∂K*/∂α, α̇ = −∂K*/∂β.
        ElementConvention::AlphaMomenta => (-kb, ka),
    })
}

/// Canonicity of the element map at a point: the Lagrange-bracket matrix of `(q, p)` with respect
/// to `(α, β)` (order `α₁ … α_N, β₁ … β_N`) must be `J` for `AlphaCoordinates` (`[α_i, β_j] = δ_ij`)
/// and `−J` for `AlphaMomenta` (`[β_i, α_j] = δ_ij`). Returns `‖L ∓ J‖_max`.
pub fn canonicity_defect<M: CanonicalElements<N> + ?Sized, const N: usize>(
    map: &M,
    t: f64,
    alpha: &SVector<f64, N>,
    beta: &SVector<f64, N>,
) -> Result<f64> {
    check_phase(t, alpha, beta)?;
    let mut failure = None;
    let mut rows = Vec::with_capacity(2 * N);
    for i in 0..2 * N {
        let (_, da, db) = phase_gradient(
            |a, b| match map.state_generic(PhaseDual::from_re(t), a, b) {
                Ok((q, p)) => {
                    if i < N {
                        q[i]
                    } else {
                        p[i - N]
                    }
                }
                Err(e) => {
                    failure = Some(e);
                    PhaseDual::from_re(f64::NAN)
                }
            },
            alpha,
            beta,
        );
        if let Some(e) = failure.take() {
            return Err(e);
        }
        rows.push((da, db));
    }
    let m = PhaseMatrix::<N> {
        qq: nalgebra::SMatrix::from_fn(|i, j| rows[i].0[j]),
        qp: nalgebra::SMatrix::from_fn(|i, j| rows[i].1[j]),
        pq: nalgebra::SMatrix::from_fn(|i, j| rows[N + i].0[j]),
        pp: nalgebra::SMatrix::from_fn(|i, j| rows[N + i].1[j]),
    };
    if !m.is_finite() {
        return Err(Error::Singular {
            what: "∂(q, p)/∂(α, β) (not finite: singular elements)".into(),
            at: at(t, alpha, beta),
            rcond: 0.0,
        });
    }
    let l = m.symplectic_form();
    let j = PhaseMatrix::symplectic_j();
    let expected = match map.convention() {
        ElementConvention::AlphaCoordinates => j,
        ElementConvention::AlphaMomenta => PhaseMatrix {
            qq: j.qq,
            qp: -j.qp,
            pq: -j.pq,
            pp: j.pp,
        },
    };
    Ok(l.sub(&expected).max_abs())
}

/// The canonical element equations as an ODE in `(α, β)`.
#[derive(Clone, Copy, Debug)]
pub struct CanonicalElementEquations<M, K> {
    /// The canonical element map of the unperturbed motion.
    pub map: M,
    /// The perturbing Hamiltonian `K(q, p, t)`.
    pub k: K,
}

impl<M: CanonicalElements<N>, K: PhaseFunction<N>, const N: usize> ElementOde<N>
    for CanonicalElementEquations<M, K>
{
    fn rhs(&self, t: f64, a: &SVector<f64, N>, b: &SVector<f64, N>) -> Result<ElementPair<N>> {
        canonical_element_rhs(&self.map, &self.k, t, a, b)
    }
}

/// The mean of element rates over one period of a fast phase, with the oscillating spread and a
/// quadrature error estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PhaseAverage<const N: usize> {
    /// `(1/T) ∫₀ᵀ f(φ₀ + s) ds` (trapezoidal rule on `nodes` points).
    pub mean: ElementPair<N>,
    /// Componentwise `max |f − mean|` over the nodes: the amplitude of the periodic part.
    pub spread: ElementPair<N>,
    /// Componentwise `|mean_n − mean_{n/2}|`: the change from halving the nodes (for an analytic
    /// periodic integrand the trapezoidal rule converges geometrically; a trigonometric
    /// polynomial of degree `< n/2` is integrated exactly).
    pub quadrature_error: ElementPair<N>,
    /// The period `T` of the phase.
    pub period: f64,
}

impl<const N: usize> PhaseAverage<N> {
    /// The relative change of the elements over one period caused by the periodic part,
    /// `ε = T · max_i spread_i / scale_i`: the small parameter of first-order averaging.
    /// `scale` gives the size of each element (e.g. `α` itself for an energy, the period for a
    /// time-like `β`); entries must be positive.
    pub fn small_parameter(&self, scale: &ElementPair<N>) -> Result<f64> {
        let mut eps = 0.0f64;
        for i in 0..N {
            let s1 = positive(format_args!("scale.0[{i}]"), scale.0[i])?;
            let s2 = positive(format_args!("scale.1[{i}]"), scale.1[i])?;
            eps = eps
                .max(self.period * self.spread.0[i] / s1)
                .max(self.period * self.spread.1[i] / s2);
        }
        Ok(eps)
    }

    /// Refuse the average (phase averaging is meaningless near a separatrix) when the
    /// small parameter [`small_parameter`](Self::small_parameter) exceeds `limit`:
    /// [`Error::OutOfDomain`] naming `ε`. Returns `ε` otherwise.
    pub fn require_small(&self, scale: &ElementPair<N>, limit: f64) -> Result<f64> {
        let limit = positive("limit on the small parameter", limit)?;
        let eps = self.small_parameter(scale)?;
        if eps <= limit {
            Ok(eps)
        } else {
            Err(Error::out_of_domain(
                "small parameter of averaging ε = T·spread/scale (relative element change per \
                 period)",
                eps,
                format!("[0, {limit}]: the perturbation is not small, averaging is meaningless"),
            ))
        }
    }
}

/// Average element rates over one period of a fast phase (first-order secular rates).
///
/// `rhs(s)` returns the rates at phase offset `s ∈ [0, T)` — typically
/// `canonical_element_rhs(map, k, t₀ + s, α, β)` with the elements frozen, so that the fast angle
/// `n(t − β)` sweeps one period. The trapezoidal rule on `nodes` equidistant points (`nodes ≥ 4`,
/// even) is spectrally accurate for smooth periodic integrands; the estimate from `nodes/2` is
/// reported in [`PhaseAverage::quadrature_error`].
pub fn average_over_phase<F, const N: usize>(
    mut rhs: F,
    period: f64,
    nodes: usize,
) -> Result<PhaseAverage<N>>
where
    F: FnMut(f64) -> Result<ElementPair<N>>,
{
    let period = positive("period", period)?;
    if nodes < 4 || !nodes.is_multiple_of(2) {
        return Err(Error::out_of_domain(
            "number of quadrature nodes",
            nodes as f64,
            "even and ≥ 4",
        ));
    }
    let mut values = Vec::with_capacity(nodes);
    for k in 0..nodes {
        let s = period * k as f64 / nodes as f64;
        let v = rhs(s)?;
        finite("phase offset", s)?;
        all_finite(format_args!("rate at phase offset {s}; ȧ"), v.0.as_slice())?;
        all_finite(format_args!("rate at phase offset {s}; ḃ"), v.1.as_slice())?;
        values.push(v);
    }
    let mean_of = |step: usize| -> ElementPair<N> {
        let mut m = (SVector::<f64, N>::zeros(), SVector::<f64, N>::zeros());
        let mut count = 0.0;
        for v in values.iter().step_by(step) {
            m.0 += v.0;
            m.1 += v.1;
            count += 1.0;
        }
        (m.0 / count, m.1 / count)
    };
    let mean = mean_of(1);
    let coarse = mean_of(2);
    let mut spread = (SVector::<f64, N>::zeros(), SVector::<f64, N>::zeros());
    for v in &values {
        spread.0 = spread.0.sup(&(v.0 - mean.0).abs());
        spread.1 = spread.1.sup(&(v.1 - mean.1).abs());
    }
    Ok(PhaseAverage {
        mean,
        spread,
        quadrature_error: ((mean.0 - coarse.0).abs(), (mean.1 - coarse.1).abs()),
        period,
    })
}

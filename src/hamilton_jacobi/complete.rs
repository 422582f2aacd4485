//! Complete integrals of the Hamilton–Jacobi equation and Jacobi's theorem
//! [Ardema 17.2, eqs. 17.14–17.33].
//!
//! A complete integral `S(t, q, α)` solves
//!
//! ```math
//! \frac{\partial S}{\partial t} + H\Big(t, q, \frac{\partial S}{\partial q}\Big) = 0
//! ```
//!
//! for every value of the `N` constants `α`, with `det ∂²S/∂q∂α ≠ 0` [Ardema eq. 17.25]. Used as a
//! generating function it maps the motion to constant elements `(α, β)`, in one of the two
//! conventions, which the API always names ([`ElementConvention`]):
//!
//! * `AlphaMomenta` [Ardema ch. 17]: `S` is an F2 generator, `α` the new momenta,
//!   `β = +∂S/∂α` the new coordinates;
//! * `AlphaCoordinates` [Ardema ch. 18]: `S` is an F1 generator, `α` the new coordinates,
//!   `β = −∂S/∂α` the new momenta.
//!
//! The motion is recovered by solving `∂S/∂α = ±β` for `q` at each time (Newton with the AD mixed
//! Hessian, through [`CanonicalTransformation`]), with `p = ∂S/∂q`. A complete integral is usually
//! one branch of a multivalued function (e.g. `p = +√(…)` before a turning point); states on the
//! other branch have no preimage, and the solve then reports an error rather than a wrong state.

use crate::ad::{lift, phase_gradient, phase_hessian, PhaseDual};
use crate::error::{finite, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::phase::check_phase;
use crate::transform::{CanonicalTransformation, GeneratingFunction, Kind};
use nalgebra::SVector;
use num_dual::{Dual, DualNum};

/// The role of the constants `α` of a complete integral [Ardema 17.2, 18.2]. No default is assumed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ElementConvention {
    /// [Ardema ch. 17]: `β = +∂S/∂α`; `(β, α)` are the new (coordinates, momenta).
    AlphaMomenta,
    /// [Ardema ch. 18]: `β = −∂S/∂α`; `(α, β)` are the new (coordinates, momenta).
    AlphaCoordinates,
}

/// A complete integral `S(t, q, α)` of the Hamilton–Jacobi equation, written once for every dual
/// type.
pub trait CompleteIntegral<const N: usize> {
    /// `S(t, q, α)`.
    fn action<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, alpha: &SVector<D, N>) -> D;

    /// A starting guess for the constants `α` of the motion through `(q, p)` (refined by Newton);
    /// `None` (default) tries generic starts. Supplying it selects the branch and keeps the solve
    /// inside the domain of `S` (e.g. `α > |x|` for the oscillator's integral).
    fn alpha_guess(
        &self,
        _t: f64,
        _q: &SVector<f64, N>,
        _p: &SVector<f64, N>,
    ) -> Option<SVector<f64, N>> {
        None
    }

    /// A starting guess for the coordinates `q` of the motion with constants `(α, β)` at time `t`;
    /// `None` (default) tries generic starts.
    fn coordinate_guess(
        &self,
        _t: f64,
        _alpha: &SVector<f64, N>,
        _beta: &SVector<f64, N>,
    ) -> Option<SVector<f64, N>> {
        None
    }
}

/// Residual of the Hamilton–Jacobi equation `∂S/∂t + H(t, q, ∂S/∂q)` at `(t, q)` for the constants
/// `α` [Ardema eq. 17.14]; zero for a solution.
pub fn hj_residual<S: CompleteIntegral<N>, H: Hamiltonian<N>, const N: usize>(
    s: &S,
    h: &H,
    t: f64,
    q: &SVector<f64, N>,
    alpha: &SVector<f64, N>,
) -> Result<f64> {
    check_phase(t, q, alpha)?;
    let st = s
        .action(
            Dual::new(t, 1.0),
            &lift::<Dual<f64, f64>, N>(q),
            &lift(alpha),
        )
        .eps;
    let (_, p, _) = phase_gradient(|a, b| s.action(PhaseDual::from_re(t), a, b), q, alpha);
    finite(
        format_args!("Hamilton–Jacobi residual at t = {t}, q = {q:?}, α = {alpha:?}"),
        st + h.hamiltonian(t, q, &p),
    )
}

/// Completeness: `det ∂²S/∂q∂α` at a point [Ardema eq. 17.25] (non-zero for a complete integral).
pub fn completeness<S: CompleteIntegral<N>, const N: usize>(
    s: &S,
    t: f64,
    q: &SVector<f64, N>,
    alpha: &SVector<f64, N>,
) -> Result<f64> {
    check_phase(t, q, alpha)?;
    let (_, _, _, h) = phase_hessian(|a, b| s.action(From::from(t), a, b), q, alpha);
    let det = nalgebra::DMatrix::from_fn(N, N, |i, j| h.qp[(i, j)]).determinant();
    finite("det ∂²S/∂q∂α", det)
}

/// `S` seen as the generating function of the map from states to elements.
struct ElementGenerator<S> {
    s: S,
    convention: ElementConvention,
}

impl<S: CompleteIntegral<N>, const N: usize> GeneratingFunction<N> for ElementGenerator<S> {
    fn kind(&self) -> Kind {
        match self.convention {
            ElementConvention::AlphaMomenta => Kind::F2,
            ElementConvention::AlphaCoordinates => Kind::F1,
        }
    }
    fn generator<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        alpha: &SVector<D, N>,
    ) -> D {
        self.s.action(t, q, alpha)
    }
    fn forward_guess(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Option<SVector<f64, N>> {
        self.s.alpha_guess(t, q, p)
    }
    fn inverse_guess(
        &self,
        t: f64,
        big_q: &SVector<f64, N>,
        big_p: &SVector<f64, N>,
    ) -> Option<SVector<f64, N>> {
        let (alpha, beta) = match self.convention {
            ElementConvention::AlphaMomenta => (big_p, big_q),
            ElementConvention::AlphaCoordinates => (big_q, big_p),
        };
        self.s.coordinate_guess(t, alpha, beta)
    }
}

/// Jacobi's theorem [Ardema 17.2]: the map between states `(q, p)` and constant elements `(α, β)`
/// defined by a complete integral in a named [`ElementConvention`].
pub struct Elements<S, const N: usize> {
    map: CanonicalTransformation<ElementGenerator<S>, N>,
    convention: ElementConvention,
}

impl<S: CompleteIntegral<N>, const N: usize> Elements<S, N> {
    /// Elements of the complete integral `s` in the given convention.
    pub fn new(s: S, convention: ElementConvention) -> Self {
        Self {
            map: CanonicalTransformation::new(ElementGenerator { s, convention }),
            convention,
        }
    }

    /// The convention in use.
    pub fn convention(&self) -> ElementConvention {
        self.convention
    }

    /// The constants `(α, β)` of the motion through `(q, p)` at time `t`: solve `∂S/∂q = p` for
    /// `α`, then `β = ±∂S/∂α`.
    pub fn elements(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        let (big_q, big_p) = self.map.forward(t, q, p)?;
        Ok(match self.convention {
            ElementConvention::AlphaMomenta => (big_p, big_q),
            ElementConvention::AlphaCoordinates => (big_q, big_p),
        })
    }

    /// [`Elements::state`] in any number type `D`: the real state by Newton, its derivatives with
    /// respect to `(t, α, β)` exactly through the implicit solve (implicit AD, [`crate::implicit`]).
    /// No input validation (NaN in gives an error or NaN out); used by the element equations of
    /// perturbation theory [Ardema 18.2], which differentiate `K(q(α, β, t), p(α, β, t), t)`.
    pub fn state_generic<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        alpha: &SVector<D, N>,
        beta: &SVector<D, N>,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        match self.convention {
            ElementConvention::AlphaMomenta => self.map.inverse_generic(t, beta, alpha),
            ElementConvention::AlphaCoordinates => self.map.inverse_generic(t, alpha, beta),
        }
    }

    /// The state `(q, p)` at time `t` of the motion with constants `(α, β)`: solve `∂S/∂α = ±β`
    /// for `q` (Newton), then `p = ∂S/∂q` [Ardema eqs. 17.26–17.33].
    pub fn state(
        &self,
        t: f64,
        alpha: &SVector<f64, N>,
        beta: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        let (big_q, big_p) = match self.convention {
            ElementConvention::AlphaMomenta => (beta, alpha),
            ElementConvention::AlphaCoordinates => (alpha, beta),
        };
        self.map.inverse(t, big_q, big_p).map_err(|e| match e {
            Error::NotConverged {
                what,
                iterations,
                residual,
            } => Error::NotConverged {
                what: format!(
                    "{what} (∂S/∂α = ±β has no solution near the start: the state may lie on \
                     another branch of the complete integral)"
                ),
                iterations,
                residual,
            },
            other => other,
        })
    }
}

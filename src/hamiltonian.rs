//! Hamiltonian systems written once, generic over the dual-number type; every derivative by AD.
//!
//! A system implements [`Hamiltonian::hamiltonian`], the function `H(t, q, p)` with arguments of
//! any [`DualNum<f64>`] type. From it the trait derives, by forward-mode AD ([`crate::ad`]):
//!
//! * Hamilton's equations [Ardema 15.11, eqs. 15.18–15.21] (crate sign of §0.3 for the
//!   non-conservative forces):
//!
//! ```math
//! \dot q = \frac{\partial H}{\partial p},\qquad
//! \dot p = -\frac{\partial H}{\partial q} + Q^{nc}(t, q, p);
//! ```
//!
//! * the Hessian blocks `H_qq, H_qp, H_pq, H_pp` and the tangent map of the vector field
//!   (the linearisation, [Ardema 15.4, eq. 15.22]):
//!
//! ```math
//! A = \begin{pmatrix} H_{pq} & H_{pp} \\ -H_{qq} & -H_{qp} \end{pmatrix}
//!   + \begin{pmatrix} 0 & 0 \\ \partial Q^{nc}/\partial q & \partial Q^{nc}/\partial p \end{pmatrix};
//! ```
//!
//! * `∂H/∂t` and the energy balance `dH/dt = ∂H/∂t + Q^{nc}·∂H/∂p`.
//!
//! A one-line Hamiltonian needs no hand-written struct: see [`hamiltonian!`](crate::hamiltonian!).

use crate::ad::{gradient, lift, phase_gradient, phase_hessian, GradDual, PhaseDual};
use crate::error::{all_finite, finite, Lazy, Result};
use crate::phase::{check_phase, PhaseMatrix};
use nalgebra::SVector;
use num_dual::{first_derivative, Dual, DualNum};

/// A scalar function `F(t, q, p)` on extended phase space, written once for every dual type.
///
/// Implemented by every [`Hamiltonian`]; implement it directly for integrals, generators and
/// observables whose brackets you want ([`crate::brackets`]).
pub trait PhaseFunction<const N: usize> {
    /// Evaluate `F(t, q, p)`.
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, p: &SVector<D, N>) -> D;
}

/// A Hamiltonian system with `N` degrees of freedom.
///
/// # Requirements on the system
/// `hamiltonian` must be written with the operations of [`DualNum`] only (arithmetic, `sqrt`,
/// `sin`, `exp`, …), so that it can be evaluated on real numbers and on dual numbers alike. Real
/// constants enter as `x * 2.0` or `D::from(2.0)` (a dual number times `f64` is defined; `f64`
/// times a dual number is not).
///
/// # Example
/// ```
/// use hamilton_jacobi::{Hamiltonian, DualNum};
/// use hamilton_jacobi::nalgebra::SVector;
///
/// /// H = p²/2 − cos q
/// struct Pendulum;
/// impl Hamiltonian<1> for Pendulum {
///     fn hamiltonian<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 1>, p: &SVector<D, 1>) -> D {
///         p[0] * p[0] * 0.5 - q[0].cos()
///     }
/// }
/// let (qdot, pdot) = Pendulum.vector_field(0.0, &SVector::from([1.0]), &SVector::from([0.5])).unwrap();
/// assert_eq!(qdot[0], 0.5);               // ∂H/∂p = p
/// assert_eq!(pdot[0], -(1.0f64).sin());   // −∂H/∂q = −sin q
/// ```
///
/// # Reference
/// M. D. Ardema, *Analytical Dynamics*, Kluwer/Plenum 2005, ch. 15.
pub trait Hamiltonian<const N: usize> {
    /// The Hamiltonian `H(t, q, p)`.
    fn hamiltonian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, p: &SVector<D, N>) -> D;

    /// Non-conservative generalized forces `Q^nc(t, q, p)` entering `ṗ = −∂H/∂q + Q^nc`
    /// [Ardema eq. 15.18]. `None` (the default) for a conservative system.
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, N>,
        _p: &SVector<D, N>,
    ) -> Option<SVector<D, N>> {
        None
    }

    /// `H(t, q, p)` on reals, with NaN/∞ inputs rejected.
    fn value(&self, t: f64, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<f64> {
        check_phase(t, q, p)?;
        let h = self.hamiltonian(t, q, p);
        finite(format_args!("H at t = {t}, q = {q:?}, p = {p:?}"), h)
    }

    /// `(H, ∂H/∂q, ∂H/∂p)` in one AD pass, for any number type `D` (so it can be nested:
    /// an integrator step written with it is again differentiable).
    #[inline]
    fn gradient<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (D, SVector<D, N>, SVector<D, N>) {
        phase_gradient(|q, p| self.hamiltonian(PhaseDual::from_re(t), q, p), q, p)
    }

    /// Hamilton's equations `(q̇, ṗ)` at a point, generic over the number type; the inner-loop
    /// kernel (no input validation: NaN in gives NaN out).
    #[inline]
    fn vector_field_generic<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        let (_, hq, hp) = self.gradient(t, q, p);
        match self.generalized_force(t, q, p) {
            None => (hp, -hq),
            Some(f) => (hp, f - hq),
        }
    }

    /// Hamilton's equations `(q̇, ṗ)` on reals without validation (the inner-loop kernel).
    #[inline]
    fn vector_field_unchecked(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, N>) {
        self.vector_field_generic(t, q, p)
    }

    /// Hamilton's equations `(q̇, ṗ)`, with NaN/∞ inputs rejected.
    fn vector_field(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        checked_vector_field(self, t, q, p)
    }

    /// The Hessian of `H` over phase space in blocks `[[H_qq, H_qp], [H_pq, H_pp]]`,
    /// `H_qp[(i, j)] = ∂²H/∂q_i∂p_j`.
    fn hessian(&self, t: f64, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<PhaseMatrix<N>> {
        check_phase(t, q, p)?;
        let (_, _, _, h) = phase_hessian(|q, p| self.hamiltonian(From::from(t), q, p), q, p);
        if h.is_finite() {
            Ok(h)
        } else {
            Err(not_finite("Hessian of H", t, q, p))
        }
    }

    /// Tangent map (Jacobian) of the vector field, `A = ∂(q̇, ṗ)/∂(q, p)`; `δż = A δz` are the
    /// variational equations [Ardema eq. 15.22]. Includes `∂Q^nc/∂(q, p)`.
    fn tangent_matrix(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<PhaseMatrix<N>> {
        crate::ad::jacobian(&VectorFieldMap(self), t, q, p)
    }

    /// The Taylor polynomial of `H` to total degree `degree` about `(q, p)` at time `t`, in the
    /// `2N` variables `(q − q₀, p − p₀)`, by evaluating [`hamiltonian`](Self::hamiltonian) on the
    /// truncated power series [`Series`](crate::series::Series); see
    /// [`series::expand_at`](crate::series::expand_at) for the variables and the errors.
    fn taylor_expansion(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
        degree: usize,
    ) -> Result<crate::series::Polynomial> {
        crate::series::expand_at(t, q, p, degree, |t, q, p| self.hamiltonian(t, q, p))
    }

    /// Explicit time derivative `∂H/∂t` (zero for autonomous systems).
    fn partial_t(&self, t: f64, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<f64> {
        check_phase(t, q, p)?;
        let (_, dh) = first_derivative(
            |td: Dual<f64, f64>| self.hamiltonian(td, &lift(q), &lift(p)),
            t,
        );
        finite(format_args!("∂H/∂t at t = {t}, q = {q:?}, p = {p:?}"), dh)
    }

    /// Rate of change of `H` along the motion, `dH/dt = ∂H/∂t + Q^nc · ∂H/∂p` (Hamilton's equations
    /// make the bracket part `(H, H)` vanish). For Rayleigh dissipation this is `−2D` when `H = T + V`.
    fn energy_rate(&self, t: f64, q: &SVector<f64, N>, p: &SVector<f64, N>) -> Result<f64> {
        let ht = self.partial_t(t, q, p)?;
        let (_, _, hp) = self.gradient(t, q, p);
        let rate = ht + self.generalized_force(t, q, p).map_or(0.0, |f| f.dot(&hp));
        finite(format_args!("dH/dt at t = {t}, q = {q:?}, p = {p:?}"), rate)
    }
}

/// Hamilton's equations with NaN/∞ rejected on input and output (the default of
/// [`Hamiltonian::vector_field`], callable from overriding implementations).
pub(crate) fn checked_vector_field<H: Hamiltonian<N> + ?Sized, const N: usize>(
    h: &H,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
    check_phase(t, q, p)?;
    let (qd, pd) = h.vector_field_unchecked(t, q, p);
    let at = Lazy(|f| write!(f, "at t = {t}, q = {q:?}, p = {p:?}"));
    all_finite(format_args!("q̇ = ∂H/∂p {at}; q̇"), qd.as_slice())?;
    all_finite(format_args!("ṗ {at}; ṗ"), pd.as_slice())?;
    Ok((qd, pd))
}

/// The error for a derived quantity that came out NaN or infinite at a valid point.
pub(crate) fn not_finite<const N: usize>(
    what: &str,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> crate::Error {
    crate::Error::NonFinite {
        what: format!("{what} at t = {t}, q = {q:?}, p = {p:?} (outside the system's domain?)"),
        value: f64::NAN,
    }
}

/// A separable Hamiltonian `H = T(t, p) + V(t, q)` [Ardema eq. 15.17 for natural systems with a
/// constant mass matrix].
///
/// Implementing `Separable` gives the [`Hamiltonian`] implementation (with `H = T + V`); the
/// gradient is then taken in two passes of width `N` (one over `p` for `T`, one over `q` for `V`)
/// instead of one of width `2N`, which is cheaper. Explicit splitting integrators require it.
///
/// # Example
/// ```
/// use hamilton_jacobi::hamiltonian::Separable;
/// use hamilton_jacobi::{DualNum, Hamiltonian, nalgebra::SVector};
/// struct Oscillator;
/// impl Separable<1> for Oscillator {
///     fn kinetic<D: DualNum<f64> + Copy>(&self, _t: D, p: &SVector<D, 1>) -> D { p[0] * p[0] * 0.5 }
///     fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 1>) -> D { q[0] * q[0] * 0.5 }
/// }
/// let (qd, pd) = Oscillator.vector_field(0.0, &SVector::from([2.0]), &SVector::from([3.0])).unwrap();
/// assert_eq!((qd[0], pd[0]), (3.0, -2.0));
/// ```
pub trait Separable<const N: usize> {
    /// Kinetic part `T(t, p)`.
    fn kinetic<D: DualNum<f64> + Copy>(&self, t: D, p: &SVector<D, N>) -> D;
    /// Potential part `V(t, q)`.
    fn potential<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> D;

    /// `(T, ∂T/∂p)`, the drift of the splitting methods; by forward-mode AD of width `N`
    /// unless the system has its own.
    #[inline]
    fn kinetic_gradient<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        p: &SVector<D, N>,
    ) -> (D, SVector<D, N>) {
        gradient(|pd| self.kinetic(GradDual::from_re(t), pd), p)
    }

    /// `(V, ∂V/∂q)`, the kick of the splitting methods; by forward-mode AD of width `N` unless
    /// the system has its own.
    #[inline]
    fn potential_gradient<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
    ) -> (D, SVector<D, N>) {
        gradient(|qd| self.potential(GradDual::from_re(t), qd), q)
    }

    /// Non-conservative generalized forces, as [`Hamiltonian::generalized_force`]; `None` by default.
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, N>,
        _p: &SVector<D, N>,
    ) -> Option<SVector<D, N>> {
        None
    }
}

impl<const N: usize, S: Separable<N>> Hamiltonian<N> for S {
    #[inline]
    fn hamiltonian<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, p: &SVector<D, N>) -> D {
        self.kinetic(t, p) + self.potential(t, q)
    }

    #[inline]
    fn generalized_force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> Option<SVector<D, N>> {
        Separable::generalized_force(self, t, q, p)
    }

    #[inline]
    fn gradient<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (D, SVector<D, N>, SVector<D, N>) {
        let (tv, tp) = self.kinetic_gradient(t, p);
        let (vv, vq) = self.potential_gradient(t, q);
        (tv + vv, vq, tp)
    }
}

/// The shape "Kepler + R" of a system: a Kepler problem plus a perturbation that depends on
/// position (and time) only, `H = |p|²/2 − μ/|q| + H₁(t, q)`, declared by the system so that
/// Wisdom–Holman and SABA methods, which split it into the exact Kepler flow and kicks by `H₁`,
/// apply to it ([`crate::integrate::WisdomHolman`]). Implemented by the plain Kepler problem
/// (`H₁ = 0`) and by the perturbed two-body problem of any disturbing function.
///
/// # Reference
/// J. Wisdom & M. Holman, Astron. J. 102 (1991) 1528–1538, doi:10.1086/115978.
pub trait PerturbedKepler<const N: usize> {
    /// The gravitational parameter `μ > 0` of the Kepler part.
    fn mu(&self) -> f64;
    /// The perturbation `H₁(t, q)`, written once for every dual type.
    fn perturbation<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> D;
}

/// The vector field `(q, p) ↦ (q̇, ṗ)` seen as a map of phase space, for its AD Jacobian.
struct VectorFieldMap<'a, H: ?Sized>(&'a H);

impl<const N: usize, H: Hamiltonian<N> + ?Sized> crate::ad::PhaseMap<N> for VectorFieldMap<'_, H> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        self.0.vector_field_generic(t, q, p)
    }
}

impl<const N: usize, H: Hamiltonian<N>> PhaseFunction<N> for H {
    #[inline]
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, p: &SVector<D, N>) -> D {
        self.hamiltonian(t, q, p)
    }
}

/// A system whose parameters (masses, `μ`, `J₂`, `ε`, …) can be differentiated: the Hamiltonian
/// written once with its `M` parameters `k` as arguments of the same dual type as `(t, q, p)`,
///
/// ```math
/// H = H(k;\ t, q, p),\qquad k\in\mathbb R^M ,
/// ```
///
/// so that `∂/∂k` of anything computed from `H` (the vector field, a final state through an
/// integrator: [`crate::integrate::ParameterSensitivity`]) comes from the same AD as `∂/∂q`.
/// The [`hamiltonian!`](crate::hamiltonian!) macro with a parameter list `[k₁, k₂, …]` writes
/// both this and the [`Hamiltonian`] (or [`Separable`]) implementation from one body; a
/// hand-written [`Hamiltonian`] implementation calls [`Parametric::hamiltonian_nominal`].
///
/// # Example
/// ```
/// use hamilton_jacobi::{hamiltonian, Hamiltonian, hamiltonian::Parametric};
/// use hamilton_jacobi::nalgebra::SVector;
/// use hamilton_jacobi::num_dual::{first_derivative, Dual64, DualNum};
///
/// // H = p²/2 + k x²/2, the stiffness k a parameter.
/// hamiltonian!(Spring<1> [k] |_t, q, p| p[0] * p[0] * 0.5 + k * q[0] * q[0] * 0.5);
/// let s = Spring { k: 4.0 };
/// let (q, p) = (SVector::from([0.5]), SVector::from([0.0]));
/// assert_eq!(s.value(0.0, &q, &p).unwrap(), 0.5);
/// // ∂H/∂k = x²/2 at the state, from the same body:
/// let (_, dk) = first_derivative(
///     |k: Dual64| s.hamiltonian_with(&SVector::from([k]), Dual64::from(0.0), &q.map(Dual64::from), &p.map(Dual64::from)),
///     4.0,
/// );
/// assert_eq!(dk, 0.125);
/// assert_eq!(Spring::NAMES, ["k"]);
/// ```
pub trait Parametric<const N: usize, const M: usize> {
    /// The parameters' names, in the order of [`parameters`](Parametric::parameters).
    const NAMES: [&'static str; M];
    /// The nominal values of the parameters.
    fn parameters(&self) -> SVector<f64, M>;
    /// `H(k; t, q, p)` with the parameters `k` given in the dual type of the arguments.
    fn hamiltonian_with<D: DualNum<f64> + Copy>(
        &self,
        k: &SVector<D, M>,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> D;
    /// `H` at the nominal parameters: the body of a [`Hamiltonian`] implementation.
    #[inline]
    fn hamiltonian_nominal<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> D {
        self.hamiltonian_with(&self.parameters().map(D::from), t, q, p)
    }
}

/// A [`Parametric`] system separable at every value of its parameters,
///
/// ```math
/// H(k; t, q, p) = T(k; t, p) + V(k; t, q),
/// ```
///
/// each part given in the dual type of the arguments, so that the exact sub-flows of a splitting
/// method (Hairer, Lubich & Wanner, *Geometric Numerical Integration*, 2nd ed., §II.5) can carry
/// derivatives with respect to `k`. The [`hamiltonian!`](crate::hamiltonian!) macro's parametric
/// separable form implements it, and its [`Separable`] parts are these at the nominal `k`.
pub trait ParametricSeparable<const N: usize, const M: usize>: Parametric<N, M> {
    /// `T(k; t, p)`.
    fn kinetic_with<D: DualNum<f64> + Copy>(&self, k: &SVector<D, M>, t: D, p: &SVector<D, N>)
        -> D;
    /// `V(k; t, q)`.
    fn potential_with<D: DualNum<f64> + Copy>(
        &self,
        k: &SVector<D, M>,
        t: D,
        q: &SVector<D, N>,
    ) -> D;

    /// `(T, ∂T/∂p)` at parameters `k`, the drift of the splitting methods; by forward-mode AD
    /// of width `N` unless the system has its own.
    #[inline]
    fn kinetic_gradient_with<D: DualNum<f64> + Copy>(
        &self,
        k: &SVector<D, M>,
        t: D,
        p: &SVector<D, N>,
    ) -> (D, SVector<D, N>) {
        let k = k.map(GradDual::from_re);
        gradient(|pd| self.kinetic_with(&k, GradDual::from_re(t), pd), p)
    }

    /// `(V, ∂V/∂q)` at parameters `k`, the kick of the splitting methods; by forward-mode AD
    /// of width `N` unless the system has its own.
    #[inline]
    fn potential_gradient_with<D: DualNum<f64> + Copy>(
        &self,
        k: &SVector<D, M>,
        t: D,
        q: &SVector<D, N>,
    ) -> (D, SVector<D, N>) {
        let k = k.map(GradDual::from_re);
        gradient(|qd| self.potential_with(&k, GradDual::from_re(t), qd), q)
    }
}

/// Define a Hamiltonian system in one line: a struct (with optional parameters) and its
/// [`Hamiltonian`] implementation — or, written as `kinetic = T(p), potential = V(q)`, its
/// [`Separable`] implementation (so that explicit splitting methods apply as well as every
/// method for a general `H`).
///
/// Four forms:
///
/// | form | fields | implements |
/// |---|---|---|
/// | `Name<N> \|s, t, q, p\| H` | none (unit struct) | [`Hamiltonian`] |
/// | `Name<N> { a: f64, … } \|s, t, q, p\| H` | public fields, reached as `s.a` | [`Hamiltonian`] |
/// | `Name<N> { … }? \|s, t, q, p\| kinetic = T, potential = V` | as above | [`Separable`] (and so [`Hamiltonian`]) |
/// | `Name<N> [k₁, k₂, …] \|t, q, p\| H` (or `kinetic = T, potential = V`) | `pub kᵢ: f64`, reached as dual numbers `kᵢ` | [`Parametric`] and [`Hamiltonian`] (or [`ParametricSeparable`] and [`Separable`]) |
///
/// In the separable forms `T` sees only `p` (and `t`) and `V` only `q` (and `t`): a kinetic
/// energy that depends on `q` does not compile. The closure-like part names the system itself
/// (to reach its fields) and the arguments; bodies are written with [`DualNum`] operations.
///
/// ```
/// use hamilton_jacobi::{hamiltonian, Hamiltonian, Separable};
/// use hamilton_jacobi::nalgebra::SVector;
///
/// hamiltonian!(
///     /// Pendulum H = p²/2 − ω² cos q.
///     pub Pendulum<1> { omega: f64 } |s, _t, q, p| p[0] * p[0] * 0.5 - q[0].cos() * (s.omega * s.omega)
/// );
/// hamiltonian!(Free<2> |_s, _t, _q, p| p.dot(p) * 0.5);
/// // Hénon–Heiles, declared separable once: T(p) + V(q).
/// hamiltonian!(HenonHeiles<2> |_s, _t, q, p|
///     kinetic = p.dot(p) * 0.5,
///     potential = q.dot(q) * 0.5 + q[0] * q[0] * q[1] - q[1] * q[1] * q[1] / 3.0);
///
/// let h = Pendulum { omega: 2.0 };
/// let (_, pdot) = h.vector_field(0.0, &SVector::from([0.3]), &SVector::from([0.0])).unwrap();
/// assert!((pdot[0] + 4.0 * 0.3f64.sin()).abs() < 1e-15);
/// let (qdot, _) = Free.vector_field(0.0, &SVector::from([0.0, 0.0]), &SVector::from([1.0, 2.0])).unwrap();
/// assert_eq!(qdot, SVector::from([1.0, 2.0]));
/// let q = SVector::from([0.1, 0.2]);
/// assert!((HenonHeiles.potential(0.0, &q) - (0.025 + 0.002 - 0.008 / 3.0)).abs() < 1e-17);
/// ```
#[macro_export]
macro_rules! hamiltonian {
    // Separable, with fields.
    ($(#[$meta:meta])* $vis:vis $name:ident < $n:literal > { $($field:ident : $fty:ty),* $(,)? }
        |$s:ident, $t:ident, $q:ident, $p:ident| kinetic = $kin:expr, potential = $pot:expr $(,)?) => {
        $(#[$meta])*
        #[derive(Clone, Debug, PartialEq)]
        $vis struct $name { $(#[allow(missing_docs)] pub $field: $fty),* }
        $crate::hamiltonian!(@separable $name $n |$s, $t, $q, $p| $kin, $pot);
    };
    // Separable, unit struct.
    ($(#[$meta:meta])* $vis:vis $name:ident < $n:literal >
        |$s:ident, $t:ident, $q:ident, $p:ident| kinetic = $kin:expr, potential = $pot:expr $(,)?) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        $vis struct $name;
        $crate::hamiltonian!(@separable $name $n |$s, $t, $q, $p| $kin, $pot);
    };
    // Parametric, separable.
    ($(#[$meta:meta])* $vis:vis $name:ident < $n:literal > [ $($k:ident),+ $(,)? ]
        |$t:ident, $q:ident, $p:ident| kinetic = $kin:expr, potential = $pot:expr $(,)?) => {
        $crate::hamiltonian!(@parametric_struct $(#[$meta])* $vis $name $n [$($k),+] |$t, $q, $p| ($kin) + ($pot));
        impl $crate::hamiltonian::ParametricSeparable<$n, { [$(stringify!($k)),+].len() }> for $name {
            #[inline]
            #[allow(unused_variables, unused_assignments)]
            fn kinetic_with<D: $crate::DualNum<f64> + Copy>(
                &self,
                k: &$crate::nalgebra::SVector<D, { [$(stringify!($k)),+].len() }>,
                $t: D,
                $p: &$crate::nalgebra::SVector<D, $n>,
            ) -> D {
                let mut i = 0usize;
                $( let $k = k[i]; i += 1; )+
                $kin
            }
            #[inline]
            #[allow(unused_variables, unused_assignments)]
            fn potential_with<D: $crate::DualNum<f64> + Copy>(
                &self,
                k: &$crate::nalgebra::SVector<D, { [$(stringify!($k)),+].len() }>,
                $t: D,
                $q: &$crate::nalgebra::SVector<D, $n>,
            ) -> D {
                let mut i = 0usize;
                $( let $k = k[i]; i += 1; )+
                $pot
            }
        }
        impl $crate::Separable<$n> for $name {
            #[inline]
            fn kinetic<D: $crate::DualNum<f64> + Copy>(&self, t: D, p: &$crate::nalgebra::SVector<D, $n>) -> D {
                let k = $crate::hamiltonian::Parametric::parameters(self).map(D::from);
                $crate::hamiltonian::ParametricSeparable::kinetic_with(self, &k, t, p)
            }
            #[inline]
            fn potential<D: $crate::DualNum<f64> + Copy>(&self, t: D, q: &$crate::nalgebra::SVector<D, $n>) -> D {
                let k = $crate::hamiltonian::Parametric::parameters(self).map(D::from);
                $crate::hamiltonian::ParametricSeparable::potential_with(self, &k, t, q)
            }
        }
    };
    // Parametric, general.
    ($(#[$meta:meta])* $vis:vis $name:ident < $n:literal > [ $($k:ident),+ $(,)? ]
        |$t:ident, $q:ident, $p:ident| $body:expr) => {
        $crate::hamiltonian!(@parametric_struct $(#[$meta])* $vis $name $n [$($k),+] |$t, $q, $p| $body);
        impl $crate::Hamiltonian<$n> for $name {
            #[inline]
            fn hamiltonian<D: $crate::DualNum<f64> + Copy>(
                &self,
                t: D,
                q: &$crate::nalgebra::SVector<D, $n>,
                p: &$crate::nalgebra::SVector<D, $n>,
            ) -> D {
                $crate::hamiltonian::Parametric::hamiltonian_nominal(self, t, q, p)
            }
        }
    };
    ($(#[$meta:meta])* $vis:vis $name:ident < $n:literal > { $($field:ident : $fty:ty),* $(,)? }
        |$s:ident, $t:ident, $q:ident, $p:ident| $body:expr) => {
        $(#[$meta])*
        #[derive(Clone, Debug, PartialEq)]
        $vis struct $name { $(#[allow(missing_docs)] pub $field: $fty),* }
        $crate::hamiltonian!(@impl $name $n |$s, $t, $q, $p| $body);
    };
    ($(#[$meta:meta])* $vis:vis $name:ident < $n:literal > |$s:ident, $t:ident, $q:ident, $p:ident| $body:expr) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        $vis struct $name;
        $crate::hamiltonian!(@impl $name $n |$s, $t, $q, $p| $body);
    };
    (@impl $name:ident $n:literal |$s:ident, $t:ident, $q:ident, $p:ident| $body:expr) => {
        impl $crate::Hamiltonian<$n> for $name {
            #[inline]
            #[allow(unused_variables)]
            fn hamiltonian<D: $crate::DualNum<f64> + Copy>(
                &self,
                $t: D,
                $q: &$crate::nalgebra::SVector<D, $n>,
                $p: &$crate::nalgebra::SVector<D, $n>,
            ) -> D {
                let $s = self;
                $body
            }
        }
    };
    (@separable $name:ident $n:literal |$s:ident, $t:ident, $q:ident, $p:ident| $kin:expr, $pot:expr) => {
        impl $crate::Separable<$n> for $name {
            #[inline]
            #[allow(unused_variables)]
            fn kinetic<D: $crate::DualNum<f64> + Copy>(&self, $t: D, $p: &$crate::nalgebra::SVector<D, $n>) -> D {
                let $s = self;
                $kin
            }
            #[inline]
            #[allow(unused_variables)]
            fn potential<D: $crate::DualNum<f64> + Copy>(&self, $t: D, $q: &$crate::nalgebra::SVector<D, $n>) -> D {
                let $s = self;
                $pot
            }
        }
    };
    (@parametric_struct $(#[$meta:meta])* $vis:vis $name:ident $n:literal [ $($k:ident),+ ] |$t:ident, $q:ident, $p:ident| $body:expr) => {
        $(#[$meta])*
        #[derive(Clone, Copy, Debug, PartialEq)]
        $vis struct $name { $(#[allow(missing_docs)] pub $k: f64),+ }
        impl $crate::hamiltonian::Parametric<$n, { [$(stringify!($k)),+].len() }> for $name {
            const NAMES: [&'static str; { [$(stringify!($k)),+].len() }] = [$(stringify!($k)),+];
            #[inline]
            fn parameters(&self) -> $crate::nalgebra::SVector<f64, { [$(stringify!($k)),+].len() }> {
                $crate::nalgebra::SVector::from([$(self.$k),+])
            }
            #[inline]
            #[allow(unused_variables, unused_assignments)]
            fn hamiltonian_with<D: $crate::DualNum<f64> + Copy>(
                &self,
                k: &$crate::nalgebra::SVector<D, { [$(stringify!($k)),+].len() }>,
                $t: D,
                $q: &$crate::nalgebra::SVector<D, $n>,
                $p: &$crate::nalgebra::SVector<D, $n>,
            ) -> D {
                let mut i = 0usize;
                $( let $k = k[i]; i += 1; )+
                $body
            }
        }
    };
}

/// Constant of any dual type: `constant::<D>(x) = D::from(x)`.
#[inline]
pub fn constant<D: DualNum<f64>>(x: f64) -> D {
    D::from(x)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    crate::hamiltonian!(Coupled<2> { k: f64 } |s, t, q, p|
        p.dot(p) * 0.5 + q[0] * q[0] * q[1] * s.k + (q[1] * p[0]).sin() + t * q[0]);

    #[test]
    fn vector_field_and_hessian_match_hand_derivatives() {
        let h = Coupled { k: 1.5 };
        let (t, q, p) = (0.4, SVector::from([0.3, -0.7]), SVector::from([1.1, 0.2]));
        let (qd, pd) = h.vector_field(t, &q, &p).unwrap();
        let c = (q[1] * p[0]).cos();
        assert_relative_eq!(qd[0], p[0] + q[1] * c, epsilon = 1e-15);
        assert_relative_eq!(qd[1], p[1], epsilon = 1e-15);
        assert_relative_eq!(pd[0], -(2.0 * q[0] * q[1] * 1.5 + t), epsilon = 1e-15);
        assert_relative_eq!(pd[1], -(q[0] * q[0] * 1.5 + p[0] * c), epsilon = 1e-15);
        let hs = h.hessian(t, &q, &p).unwrap();
        let s = (q[1] * p[0]).sin();
        assert_relative_eq!(hs.qq[(0, 1)], 2.0 * q[0] * 1.5, epsilon = 1e-15);
        assert_relative_eq!(hs.qq[(1, 1)], -p[0] * p[0] * s, epsilon = 1e-15);
        assert_relative_eq!(hs.qp[(1, 0)], c - q[1] * p[0] * s, epsilon = 1e-15);
        assert_relative_eq!(hs.pp[(0, 0)], 1.0 - q[1] * q[1] * s, epsilon = 1e-15);
        assert_relative_eq!(h.partial_t(t, &q, &p).unwrap(), q[0], epsilon = 1e-15);
        // Tangent matrix = J · Hess
        let a = h.tangent_matrix(t, &q, &p).unwrap();
        assert_relative_eq!(a.qq, hs.pq, epsilon = 1e-14);
        assert_relative_eq!(a.qp, hs.pp, epsilon = 1e-14);
        assert_relative_eq!(a.pq, -hs.qq, epsilon = 1e-14);
        assert_relative_eq!(a.pp, -hs.qp, epsilon = 1e-14);
    }

    #[test]
    fn bad_input_is_rejected() {
        let h = Coupled { k: 1.0 };
        let q = SVector::from([f64::NAN, 0.0]);
        let p = SVector::from([0.0, 0.0]);
        assert!(h.vector_field(0.0, &q, &p).is_err());
        assert!(h.hessian(0.0, &q, &p).is_err());
        assert!(h.value(f64::INFINITY, &p, &p).is_err());
    }
}

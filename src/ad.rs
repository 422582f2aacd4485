//! Phase-space dual numbers: value and full gradient with respect to `(q, p)` in one pass.
//!
//! A function `F(t, q, p)` written once, generic over [`DualNum<f64>`](num_dual::DualNum), is
//! evaluated with [`PhaseDual`] arguments whose infinitesimal parts are seeded with the unit vectors
//! of phase space. The result carries
//!
//! ```math
//! F,\qquad \frac{\partial F}{\partial q_i},\qquad \frac{\partial F}{\partial p_i},\qquad i = 1\dots N
//! ```
//!
//! in its fields `re`, `dq`, `dp`. Keeping the `q` and `p` parts in two blocks of length `N` gives a
//! `2N`-dimensional gradient with a const-generic `N`, which stable Rust cannot otherwise spell as
//! `SVector<_, {2 * N}>`.
//!
//! [`PhaseDual`] is generic over its inner number type, so it nests: with the inner type itself a
//! [`PhaseDual64`], one evaluation yields the value, the gradient and the full phase-space Hessian
//! ([`phase_hessian`]); with the inner type a user's generic `D`, derivatives of derived quantities
//! (a Poisson bracket, a vector field, an integrator step) are themselves generic over `D` and can
//! be differentiated again.
//!
//! Reference: forward-mode AD with dual numbers, Griewank & Walther, *Evaluating Derivatives*,
//! 2nd ed., SIAM 2008, ch. 3; the arithmetic rules are those of `num-dual` (Rehner & Bauer,
//! Front. Chem. Eng. 3, 758090, 2021), whose macros implement them here.

use crate::phase::{check_phase, PhaseMatrix};
use nalgebra::allocator::Allocator;
use nalgebra::{Const, DefaultAllocator, Dim, OVector, SMatrix, SVector, U1};
use num_dual::{
    chain_rule, first, forward_binop, impl_add_sub_rem, impl_assign_ops, impl_comparisons,
    impl_derivatives, impl_dual, impl_dual_struct, impl_first_derivatives, impl_float_const,
    impl_from_f, impl_from_primitive, impl_inv, impl_iterator, impl_neg, impl_num, impl_scalar_op,
    impl_signed, impl_zero_one, second, third, zeroth, DualNum, DualNumFloat, DualStruct,
};
use num_traits::{Float, FloatConst, FromPrimitive, Inv, Num, One, Signed, Zero};
use std::fmt;
use std::iter::{Product, Sum};
use std::marker::PhantomData;
use std::ops::{
    Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Rem, RemAssign, Sub, SubAssign,
};

/// A dual number carrying the gradient with respect to the `N` coordinates (`dq`) and the `N`
/// momenta (`dp`) of phase space.
///
/// ```math
/// x = x_0 + \sum_i x_{q_i}\,\varepsilon_{q_i} + \sum_i x_{p_i}\,\varepsilon_{p_i},\qquad
/// \varepsilon\varepsilon' = 0 .
/// ```
///
/// Use the alias [`PhaseDual64`] for real inner numbers; see the [module docs](self).
#[derive(Clone, Debug)]
pub struct PhaseDual<T: DualNum<F>, F, D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    re: T,
    dq: OVector<T, D>,
    dp: OVector<T, D>,
    f: PhantomData<F>,
}

impl<T: DualNum<F> + Copy, F: Copy, const N: usize> Copy for PhaseDual<T, F, Const<N>> {}

/// Phase-space dual number over `f64` for `N` degrees of freedom.
pub type PhaseDual64<const N: usize> = PhaseDual<f64, f64, Const<N>>;

impl<T: DualNum<F>, F, D: Dim> PhaseDual<T, F, D>
where
    DefaultAllocator: Allocator<D>,
{
    #[inline]
    fn new(re: T, dq: OVector<T, D>, dp: OVector<T, D>) -> Self {
        Self {
            re,
            dq,
            dp,
            f: PhantomData,
        }
    }

    /// A constant: value `re`, zero derivatives. (`PhaseDual` is meant for static dimensions
    /// `Const<N>`; for a dynamic dimension the derivative blocks are empty.)
    #[inline]
    pub fn from_re(re: T) -> Self {
        let n = D::from_usize(D::try_to_usize().unwrap_or(0));
        Self::new(
            re,
            OVector::zeros_generic(n, U1),
            OVector::zeros_generic(n, U1),
        )
    }

    /// The value (inner number).
    #[inline]
    pub fn value(&self) -> &T {
        &self.re
    }

    /// Derivatives with respect to the coordinates, `∂/∂q`.
    #[inline]
    pub fn dq(&self) -> &OVector<T, D> {
        &self.dq
    }

    /// Derivatives with respect to the momenta, `∂/∂p`.
    #[inline]
    pub fn dp(&self) -> &OVector<T, D> {
        &self.dp
    }
}

impl<T: DualNum<F>, F, const N: usize> PhaseDual<T, F, Const<N>> {
    /// The independent variable `q_i` with value `re`.
    ///
    /// # Panics
    /// If `i ≥ N` (a programming error in the caller; the crate's own seeding loops stay in range).
    #[inline]
    pub fn coordinate(re: T, i: usize) -> Self {
        let mut x = Self::from_re(re);
        x.dq[i] = T::one();
        x
    }

    /// The independent variable `p_i` with value `re`.
    ///
    /// # Panics
    /// If `i ≥ N`.
    #[inline]
    pub fn momentum(re: T, i: usize) -> Self {
        let mut x = Self::from_re(re);
        x.dp[i] = T::one();
        x
    }
}

impl<T: DualNum<F>, F: Float, D: Dim> PhaseDual<T, F, D>
where
    DefaultAllocator: Allocator<D>,
{
    #[inline]
    fn chain_rule(&self, f0: T, f1: T) -> Self {
        Self::new(f0, &self.dq * f1.clone(), &self.dp * f1)
    }
}

impl<T: DualNum<F>, F: Float, D: Dim> Mul<&PhaseDual<T, F, D>> for &PhaseDual<T, F, D>
where
    DefaultAllocator: Allocator<D>,
{
    type Output = PhaseDual<T, F, D>;
    #[inline]
    fn mul(self, other: &PhaseDual<T, F, D>) -> Self::Output {
        PhaseDual::new(
            self.re.clone() * other.re.clone(),
            &self.dq * other.re.clone() + &other.dq * self.re.clone(),
            &self.dp * other.re.clone() + &other.dp * self.re.clone(),
        )
    }
}

impl<T: DualNum<F>, F: Float, D: Dim> Div<&PhaseDual<T, F, D>> for &PhaseDual<T, F, D>
where
    DefaultAllocator: Allocator<D>,
{
    type Output = PhaseDual<T, F, D>;
    #[inline]
    fn div(self, other: &PhaseDual<T, F, D>) -> PhaseDual<T, F, D> {
        let inv = other.re.recip();
        let inv2 = inv.clone() * inv.clone();
        PhaseDual::new(
            self.re.clone() * inv,
            (&self.dq * other.re.clone() - &other.dq * self.re.clone()) * inv2.clone(),
            (&self.dp * other.re.clone() - &other.dp * self.re.clone()) * inv2,
        )
    }
}

impl<T: DualNum<F>, F, D: Dim> fmt::Display for PhaseDual<T, F, D>
where
    DefaultAllocator: Allocator<D>,
{
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{}", self.re)?;
        for (i, d) in self.dq.iter().enumerate() {
            write!(f, " + {d}εq{i}")?;
        }
        for (i, d) in self.dp.iter().enumerate() {
            write!(f, " + {d}εp{i}")?;
        }
        Ok(())
    }
}

impl_first_derivatives!(PhaseDual, [dq, dp], [D], [D]);
impl_dual!(PhaseDual, [dq, dp], [D], [D]);

/// A dual number carrying a dense gradient with respect to `N` variables.
///
/// ```math
/// x = x_0 + \sum_i x_i\,\varepsilon_i,\qquad \varepsilon_i\varepsilon_j = 0 .
/// ```
///
/// Used where a function depends on one half of phase space only (the kinetic energy `T(p)` and
/// the potential `V(q)` of a [`Separable`](crate::hamiltonian::Separable) system), so no derivative
/// slots are spent on variables the function does not see.
#[derive(Clone, Debug)]
pub struct GradDual<T: DualNum<F>, F, D: Dim>
where
    DefaultAllocator: Allocator<D>,
{
    re: T,
    eps: OVector<T, D>,
    f: PhantomData<F>,
}

impl<T: DualNum<F> + Copy, F: Copy, const N: usize> Copy for GradDual<T, F, Const<N>> {}

/// Gradient dual number over `f64` with `N` variables.
pub type GradDual64<const N: usize> = GradDual<f64, f64, Const<N>>;

impl<T: DualNum<F>, F, D: Dim> GradDual<T, F, D>
where
    DefaultAllocator: Allocator<D>,
{
    #[inline]
    fn new(re: T, eps: OVector<T, D>) -> Self {
        Self {
            re,
            eps,
            f: PhantomData,
        }
    }

    /// A constant: value `re`, zero gradient (empty for a dynamic dimension).
    #[inline]
    pub fn from_re(re: T) -> Self {
        let n = D::from_usize(D::try_to_usize().unwrap_or(0));
        Self::new(re, OVector::zeros_generic(n, U1))
    }

    /// The value (inner number).
    #[inline]
    pub fn value(&self) -> &T {
        &self.re
    }

    /// The gradient.
    #[inline]
    pub fn eps(&self) -> &OVector<T, D> {
        &self.eps
    }
}

impl<T: DualNum<F>, F, const N: usize> GradDual<T, F, Const<N>> {
    /// The independent variable `x_i` with value `re`.
    ///
    /// # Panics
    /// If `i ≥ N`.
    #[inline]
    pub fn variable(re: T, i: usize) -> Self {
        let mut x = Self::from_re(re);
        x.eps[i] = T::one();
        x
    }
}

impl<T: DualNum<F>, F: Float, D: Dim> GradDual<T, F, D>
where
    DefaultAllocator: Allocator<D>,
{
    #[inline]
    fn chain_rule(&self, f0: T, f1: T) -> Self {
        Self::new(f0, &self.eps * f1)
    }
}

impl<T: DualNum<F>, F: Float, D: Dim> Mul<&GradDual<T, F, D>> for &GradDual<T, F, D>
where
    DefaultAllocator: Allocator<D>,
{
    type Output = GradDual<T, F, D>;
    #[inline]
    fn mul(self, other: &GradDual<T, F, D>) -> Self::Output {
        GradDual::new(
            self.re.clone() * other.re.clone(),
            &self.eps * other.re.clone() + &other.eps * self.re.clone(),
        )
    }
}

impl<T: DualNum<F>, F: Float, D: Dim> Div<&GradDual<T, F, D>> for &GradDual<T, F, D>
where
    DefaultAllocator: Allocator<D>,
{
    type Output = GradDual<T, F, D>;
    #[inline]
    fn div(self, other: &GradDual<T, F, D>) -> GradDual<T, F, D> {
        let inv = other.re.recip();
        GradDual::new(
            self.re.clone() * inv.clone(),
            (&self.eps * other.re.clone() - &other.eps * self.re.clone()) * (inv.clone() * inv),
        )
    }
}

impl<T: DualNum<F>, F, D: Dim> fmt::Display for GradDual<T, F, D>
where
    DefaultAllocator: Allocator<D>,
{
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{}", self.re)?;
        for (i, d) in self.eps.iter().enumerate() {
            write!(f, " + {d}ε{i}")?;
        }
        Ok(())
    }
}

impl_first_derivatives!(GradDual, [eps], [D], [D]);
impl_dual!(GradDual, [eps], [D], [D]);

/// Value and gradient of `f(x)` in one pass with [`GradDual`] (`T` may itself be a dual number).
#[inline]
pub fn gradient<T, G, const N: usize>(f: G, x: &SVector<T, N>) -> (T, SVector<T, N>)
where
    T: DualNum<f64> + Copy,
    G: FnOnce(&SVector<GradDual<T, f64, Const<N>>, N>) -> GradDual<T, f64, Const<N>>,
{
    let xd = SVector::from_fn(|i, _| GradDual::variable(x[i], i));
    let r = f(&xd);
    (r.re, r.eps)
}

/// Value and phase-space gradient of `f(q, p)`, evaluated in one pass.
///
/// Returns `(F, ∂F/∂q, ∂F/∂p)`. `T` may itself be a dual number (nesting).
#[inline]
pub fn phase_gradient<T, G, const N: usize>(
    f: G,
    q: &SVector<T, N>,
    p: &SVector<T, N>,
) -> (T, SVector<T, N>, SVector<T, N>)
where
    T: DualNum<f64> + Copy,
    G: FnOnce(
        &SVector<PhaseDual<T, f64, Const<N>>, N>,
        &SVector<PhaseDual<T, f64, Const<N>>, N>,
    ) -> PhaseDual<T, f64, Const<N>>,
{
    let qd = SVector::from_fn(|i, _| PhaseDual::coordinate(q[i], i));
    let pd = SVector::from_fn(|i, _| PhaseDual::momentum(p[i], i));
    let r = f(&qd, &pd);
    (r.re, r.dq, r.dp)
}

/// Value, gradient and Hessian of `f(q, p)` over phase space, in one nested pass.
///
/// The Hessian is returned in blocks `[[F_qq, F_qp], [F_pq, F_pp]]` with
/// `F_qp[(i, j)] = ∂²F/∂q_i∂p_j`.
pub fn phase_hessian<G, const N: usize>(
    f: G,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> (f64, SVector<f64, N>, SVector<f64, N>, PhaseMatrix<N>)
where
    G: FnOnce(
        &SVector<PhaseDual<PhaseDual64<N>, f64, Const<N>>, N>,
        &SVector<PhaseDual<PhaseDual64<N>, f64, Const<N>>, N>,
    ) -> PhaseDual<PhaseDual64<N>, f64, Const<N>>,
{
    let qi: SVector<PhaseDual64<N>, N> = SVector::from_fn(|i, _| PhaseDual::coordinate(q[i], i));
    let pi: SVector<PhaseDual64<N>, N> = SVector::from_fn(|i, _| PhaseDual::momentum(p[i], i));
    let (v, gq, gp) = phase_gradient(f, &qi, &pi);
    let rows = |g: &SVector<PhaseDual64<N>, N>, pick_q: bool| -> SMatrix<f64, N, N> {
        SMatrix::from_fn(|i, j| if pick_q { g[i].dq[j] } else { g[i].dp[j] })
    };
    let hess = PhaseMatrix {
        qq: rows(&gq, true),
        qp: rows(&gq, false),
        pq: rows(&gp, true),
        pp: rows(&gp, false),
    };
    (v.re, v.dq, v.dp, hess)
}

/// Lift a real vector to constants of any dual type.
#[inline]
pub fn lift<D: DualNum<f64> + Copy, const N: usize>(x: &SVector<f64, N>) -> SVector<D, N> {
    x.map(D::from)
}

/// Real parts of a vector of dual numbers.
#[inline]
pub fn real_parts<D: DualNum<f64> + Copy, const N: usize>(x: &SVector<D, N>) -> SVector<f64, N> {
    x.map(|v| v.re())
}

/// The product `M v` of a real matrix and a vector of dual numbers, `(M v)_i = Σ_j v_j M_ij` (each
/// term a dual number times a real).
#[inline]
pub(crate) fn real_times<D: DualNum<f64> + Copy, const R: usize, const C: usize>(
    m: &SMatrix<f64, R, C>,
    v: &SVector<D, C>,
) -> SVector<D, R> {
    SVector::from_fn(|i, _| (0..C).fold(D::from(0.0), |s, j| s + v[j] * m[(i, j)]))
}

/// A (possibly time-dependent) map of phase space `(q, p) ↦ (Q, P)`, written once generic over the
/// dual type: a canonical transformation, a flow map, one integrator step, or `(q, p)` as functions
/// of `2N` parameters.
pub trait PhaseMap<const N: usize> {
    /// Apply the map at time `t`.
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>);
}

/// Exact Jacobian `M = ∂(Q, P)/∂(q, p)` of a map by AD, in one pass: the map is evaluated once on
/// phase-space dual numbers, whose `2N`-wide infinitesimal parts carry every row.
pub fn jacobian<M: PhaseMap<N> + ?Sized, const N: usize>(
    map: &M,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> crate::error::Result<PhaseMatrix<N>> {
    check_phase(t, q, p)?;
    let mut m = PhaseMatrix {
        qq: SMatrix::zeros(),
        qp: SMatrix::zeros(),
        pq: SMatrix::zeros(),
        pp: SMatrix::zeros(),
    };
    let qd = SVector::<PhaseDual64<N>, N>::from_fn(|i, _| PhaseDual::coordinate(q[i], i));
    let pd = SVector::<PhaseDual64<N>, N>::from_fn(|i, _| PhaseDual::momentum(p[i], i));
    let (image_q, image_p) = map.apply(PhaseDual::from_re(t), &qd, &pd);
    for i in 0..2 * N {
        let c = if i < N { image_q[i] } else { image_p[i - N] };
        let (value, dq, dp) = (*c.value(), c.dq().clone_owned(), c.dp().clone_owned());
        if !value.is_finite() {
            return Err(crate::error::Error::NonFinite {
                what: format!("map output component {i} at t = {t}, q = {q:?}, p = {p:?}"),
                value,
            });
        }
        let (a, b): (&mut SMatrix<f64, N, N>, &mut SMatrix<f64, N, N>) = if i < N {
            (&mut m.qq, &mut m.qp)
        } else {
            (&mut m.pq, &mut m.pp)
        };
        a.set_row(i % N, &dq.transpose());
        b.set_row(i % N, &dp.transpose());
    }
    if m.is_finite() {
        Ok(m)
    } else {
        Err(crate::error::Error::invalid(
            "map Jacobian",
            format!("not finite at t = {t}, q = {q:?}, p = {p:?} (outside the map's domain?)"),
        ))
    }
}

/// The augmented state of [`tangent_rates`]: `(q₀, δq₁, …, δq_C)`, `(p₀, δp₁, …, δp_C)` with the
/// tangent columns `(δq_j, δp_j)_i = column(i, j)` (`i < N` the `q` rows, `N ≤ i < 2N` the `p`
/// rows).
pub(crate) fn augmented_state<const N: usize, const K: usize>(
    q0: &SVector<f64, N>,
    p0: &SVector<f64, N>,
    columns: usize,
    column: impl Fn(usize, usize) -> f64,
) -> (SVector<f64, K>, SVector<f64, K>) {
    let mut qa = SVector::<f64, K>::zeros();
    let mut pa = SVector::<f64, K>::zeros();
    qa.fixed_rows_mut::<N>(0).copy_from(q0);
    pa.fixed_rows_mut::<N>(0).copy_from(p0);
    for j in 0..columns {
        let off = N * (1 + j);
        for i in 0..N {
            qa[off + i] = column(i, j);
            pa[off + i] = column(N + i, j);
        }
    }
    (qa, pa)
}

/// The rates of a state `(q, p)` carried with `columns` tangent vectors `(δq_j, δp_j)`: the
/// augmented blocks are `(q, δq₁, …, δq_C)` and `(p, δp₁, …, δp_C)` (`K = N(1 + C)`). Column `j`
/// moves with the directional derivative of the field along it, `eval(j, q + ε δq_j, p + ε δp_j)`
/// on [`Dual64`](num_dual::Dual64) (the closure adds what else column `j` carries, e.g. a seeded
/// parameter); the state moves with the real part. Variational and sensitivity equations are
/// both of this form [Hairer, Nørsett & Wanner, *Solving ODEs I*, §I.14].
///
/// # Errors
/// [`Error::NonFinite`](crate::error::Error::NonFinite) for a non-finite rate, naming `what`.
#[allow(clippy::type_complexity)]
pub(crate) fn tangent_rates<const N: usize, const K: usize>(
    what: &str,
    t: f64,
    qa: &SVector<f64, K>,
    pa: &SVector<f64, K>,
    columns: usize,
    eval: impl Fn(
        usize,
        num_dual::Dual64,
        &SVector<num_dual::Dual64, N>,
        &SVector<num_dual::Dual64, N>,
    ) -> (SVector<num_dual::Dual64, N>, SVector<num_dual::Dual64, N>),
) -> crate::error::Result<(SVector<f64, K>, SVector<f64, K>)> {
    use num_dual::Dual64;
    let mut dq = SVector::<f64, K>::zeros();
    let mut dp = SVector::<f64, K>::zeros();
    let td = Dual64::from(t);
    for j in 0..columns.max(1) {
        let off = N * (1 + j);
        let seed = |x: &SVector<f64, K>, i: usize| {
            Dual64::new(x[i], if j < columns { x[off + i] } else { 0.0 })
        };
        let qs = SVector::<Dual64, N>::from_fn(|i, _| seed(qa, i));
        let ps = SVector::<Dual64, N>::from_fn(|i, _| seed(pa, i));
        let (fq, fp) = eval(j, td, &qs, &ps);
        for i in 0..N {
            // The real parts are the field itself (the same for every column).
            if j == 0 {
                dq[i] = fq[i].re;
                dp[i] = fp[i].re;
            }
            if j < columns {
                dq[off + i] = fq[i].eps;
                dp[off + i] = fp[i].eps;
            }
        }
    }
    if dq.iter().chain(dp.iter()).all(|v| v.is_finite()) {
        Ok((dq, dp))
    } else {
        Err(crate::error::Error::NonFinite {
            what: format!(
                "{what} at t = {t:e}, q = {:?}, p = {:?} (outside the system's domain?)",
                qa.fixed_rows::<N>(0),
                pa.fixed_rows::<N>(0)
            ),
            value: f64::NAN,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    fn f<D: DualNum<f64> + Copy>(q: &SVector<D, 2>, p: &SVector<D, 2>) -> D {
        // F = q0² p1 + sin(q1) exp(p0) + sqrt(q0² + q1²)
        q[0] * q[0] * p[1] + q[1].sin() * p[0].exp() + (q[0] * q[0] + q[1] * q[1]).sqrt()
    }

    #[test]
    fn gradient_matches_hand_derivatives() {
        let q = SVector::from([0.7, -0.4]);
        let p = SVector::from([0.3, 1.9]);
        let (v, gq, gp) = phase_gradient(f, &q, &p);
        let r = (q[0] * q[0] + q[1] * q[1]).sqrt();
        assert_relative_eq!(v, f(&q, &p), epsilon = 1e-15);
        assert_relative_eq!(gq[0], 2.0 * q[0] * p[1] + q[0] / r, epsilon = 1e-15);
        assert_relative_eq!(gq[1], q[1].cos() * p[0].exp() + q[1] / r, epsilon = 1e-15);
        assert_relative_eq!(gp[0], q[1].sin() * p[0].exp(), epsilon = 1e-15);
        assert_relative_eq!(gp[1], q[0] * q[0], epsilon = 1e-15);
    }

    #[test]
    fn grad_dual_matches_phase_dual() {
        let q = SVector::from([0.7, -0.4]);
        let p = SVector::from([0.3, 1.9]);
        let (v, gq, _) = phase_gradient(f, &q, &p);
        let (w, g) = gradient(|qd| f(qd, &p.map(GradDual::from_re)), &q);
        assert_eq!(v, w);
        assert_relative_eq!(g, gq, epsilon = 1e-15);
    }

    #[test]
    fn hessian_matches_hand_derivatives_and_is_symmetric() {
        let q = SVector::from([0.7, -0.4]);
        let p = SVector::from([0.3, 1.9]);
        let (_, _, _, h) = phase_hessian(f, &q, &p);
        let e = p[0].exp();
        // ∂²F/∂q0∂p1 = 2 q0, ∂²F/∂q1∂p0 = cos(q1) e^{p0}, ∂²F/∂p0² = sin(q1) e^{p0}
        assert_relative_eq!(h.qp[(0, 1)], 2.0 * q[0], epsilon = 1e-15);
        assert_relative_eq!(h.qp[(1, 0)], q[1].cos() * e, epsilon = 1e-15);
        assert_relative_eq!(h.pp[(0, 0)], q[1].sin() * e, epsilon = 1e-15);
        assert_relative_eq!(h.pp[(1, 1)], 0.0, epsilon = 1e-15);
        assert_relative_eq!(h.qp, h.pq.transpose(), epsilon = 1e-15);
        assert_relative_eq!(h.qq, h.qq.transpose(), epsilon = 1e-15);
    }
}

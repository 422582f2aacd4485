//! Poisson and Lagrange brackets, canonicity tests of maps, Liouville's determinant.
//!
//! Conventions:
//!
//! ```math
//! (F, G) = \sum_r \Big(\frac{\partial F}{\partial q_r}\frac{\partial G}{\partial p_r}
//!         - \frac{\partial F}{\partial p_r}\frac{\partial G}{\partial q_r}\Big)
//! \quad\text{[Ardema eq. 15.25]},\qquad
//! [u, v] = \sum_r \Big(\frac{\partial q_r}{\partial u}\frac{\partial p_r}{\partial v}
//!         - \frac{\partial p_r}{\partial u}\frac{\partial q_r}{\partial v}\Big)
//! \quad\text{[Ardema eq. 16.24]},
//! ```
//!
//! so `(q_r, p_s) = δ_rs`, `dF/dt = ∂F/∂t + (F, H)` and a canonical pair has `[Q, P] = 1`.
//!
//! A map of phase space is a [`PhaseMap`], written once generic over the dual type; its exact
//! Jacobian `M` comes from one AD pass per output component, and with it
//! * the Poisson-bracket matrix of the image coordinates `(u_i, u_j) = (M J Mᵀ)_ij` [Ardema eq. 16.28],
//! * the Lagrange-bracket matrix `[u_i, u_j] = (Mᵀ J M)_ij` of `(q, p)` as functions of parameters
//!   [Ardema eq. 16.25],
//! * the reciprocity identity `Σ_s [u_s, u_i](u_s, u_j) = δ_ij` [Ardema eq. 16.27],
//! * the symplectic defect `‖MᵀJM − J‖_max` and Liouville's determinant `det M` [Ardema eq. 16.23].
//!
//! All of these are public so that users' own (property) tests can call them on their own maps.

pub use crate::ad::{jacobian, PhaseMap};
use crate::ad::{lift, phase_gradient, PhaseDual};
use crate::error::{Error, Result};
use crate::hamiltonian::{not_finite, Hamiltonian, PhaseFunction};
use crate::phase::{check_phase, PhaseMatrix};
use nalgebra::SVector;
use num_dual::{first_derivative, Dual, DualNum};

/// Poisson bracket `(F, G)` evaluated in any number type `D` (so brackets can be nested).
#[inline]
pub fn poisson_bracket_generic<F, G, D, const N: usize>(
    f: &F,
    g: &G,
    t: D,
    q: &SVector<D, N>,
    p: &SVector<D, N>,
) -> D
where
    F: PhaseFunction<N> + ?Sized,
    G: PhaseFunction<N> + ?Sized,
    D: DualNum<f64> + Copy,
{
    let (_, fq, fp) = phase_gradient(|q, p| f.eval(PhaseDual::from_re(t), q, p), q, p);
    let (_, gq, gp) = phase_gradient(|q, p| g.eval(PhaseDual::from_re(t), q, p), q, p);
    fq.dot(&gp) - fp.dot(&gq)
}

/// Poisson bracket `(F, G)(t, q, p)` [Ardema eq. 15.25], with NaN/∞ inputs rejected.
///
/// ```
/// use hamilton_jacobi::brackets::{poisson_bracket, Coordinate, Momentum};
/// use hamilton_jacobi::nalgebra::SVector;
/// let (q, p) = (SVector::from([0.3, 0.1]), SVector::from([1.0, 2.0]));
/// let (q0, q1) = (Coordinate::<2>::new(0).unwrap(), Coordinate::<2>::new(1).unwrap());
/// let p1 = Momentum::<2>::new(1).unwrap();
/// assert_eq!(poisson_bracket(&q1, &p1, 0.0, &q, &p).unwrap(), 1.0);   // (q_r, p_s) = δ_rs
/// assert_eq!(poisson_bracket(&q0, &p1, 0.0, &q, &p).unwrap(), 0.0);
/// assert!(Coordinate::<2>::new(2).is_err());
/// ```
pub fn poisson_bracket<F, G, const N: usize>(
    f: &F,
    g: &G,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<f64>
where
    F: PhaseFunction<N> + ?Sized,
    G: PhaseFunction<N> + ?Sized,
{
    check_phase(t, q, p)?;
    let b = poisson_bracket_generic(f, g, t, q, p);
    if b.is_finite() {
        Ok(b)
    } else {
        Err(not_finite("Poisson bracket", t, q, p))
    }
}

/// The Poisson bracket `(F, G)` as a phase function in its own right (so it can be bracketed
/// again: Jacobi identity, Poisson's theorem).
#[derive(Clone, Copy, Debug)]
pub struct PoissonBracket<F, G>(pub F, pub G);

impl<F: PhaseFunction<N>, G: PhaseFunction<N>, const N: usize> PhaseFunction<N>
    for PoissonBracket<F, G>
{
    #[inline]
    fn eval<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>, p: &SVector<D, N>) -> D {
        poisson_bracket_generic(&self.0, &self.1, t, q, p)
    }
}

/// The coordinate function `F = q_i` on `N`-degree-of-freedom phase space.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Coordinate<const N: usize>(usize);
/// The momentum function `F = p_i` on `N`-degree-of-freedom phase space.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Momentum<const N: usize>(usize);

fn check_index<const N: usize>(what: &str, i: usize) -> Result<usize> {
    if i < N {
        Ok(i)
    } else {
        Err(Error::invalid(
            what,
            format!("index {i} out of range 0..{N}"),
        ))
    }
}

impl<const N: usize> Coordinate<N> {
    /// `q_i`; an error if `i ≥ N`.
    pub fn new(i: usize) -> Result<Self> {
        check_index::<N>("coordinate", i).map(Self)
    }
    /// The index `i`.
    pub fn index(&self) -> usize {
        self.0
    }
}

impl<const N: usize> Momentum<N> {
    /// `p_i`; an error if `i ≥ N`.
    pub fn new(i: usize) -> Result<Self> {
        check_index::<N>("momentum", i).map(Self)
    }
    /// The index `i`.
    pub fn index(&self) -> usize {
        self.0
    }
}

impl<const N: usize> PhaseFunction<N> for Coordinate<N> {
    fn eval<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, N>, _p: &SVector<D, N>) -> D {
        q[self.0]
    }
}
impl<const N: usize> PhaseFunction<N> for Momentum<N> {
    fn eval<D: DualNum<f64> + Copy>(&self, _t: D, _q: &SVector<D, N>, p: &SVector<D, N>) -> D {
        p[self.0]
    }
}

/// Explicit time derivative `∂F/∂t` by AD.
pub fn partial_t<F: PhaseFunction<N> + ?Sized, const N: usize>(
    f: &F,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<f64> {
    check_phase(t, q, p)?;
    let ft = first_derivative(|td: Dual<f64, f64>| f.eval(td, &lift(q), &lift(p)), t).1;
    if ft.is_finite() {
        Ok(ft)
    } else {
        Err(not_finite("∂F/∂t", t, q, p))
    }
}

/// Total time derivative along the motion of `H`:
/// `dF/dt = ∂F/∂t + (F, H)` [Ardema eq. 15.26], plus `∂F/∂p · Q^nc` when `H` carries
/// non-conservative forces. `F` is an integral iff this vanishes identically.
pub fn time_derivative<F, H, const N: usize>(
    f: &F,
    h: &H,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<f64>
where
    F: PhaseFunction<N> + ?Sized,
    H: Hamiltonian<N>,
{
    let ft = partial_t(f, t, q, p)?;
    let br = poisson_bracket_generic(f, h, t, q, p);
    let nc = match h.generalized_force(t, q, p) {
        None => 0.0,
        Some(force) => {
            let (_, _, fp) = phase_gradient(|qd, pd| f.eval(PhaseDual::from_re(t), qd, pd), q, p);
            fp.dot(&force)
        }
    };
    let rate = ft + br + nc;
    if rate.is_finite() {
        Ok(rate)
    } else {
        Err(not_finite("dF/dt", t, q, p))
    }
}

/// Largest `|dF/dt|` over a set of sample points: zero (to rounding) iff `F` is an integral of `H`
/// there. A point with NaN/∞ is an error.
pub fn integral_defect<F, H, const N: usize>(
    f: &F,
    h: &H,
    points: &[(f64, SVector<f64, N>, SVector<f64, N>)],
) -> Result<f64>
where
    F: PhaseFunction<N> + ?Sized,
    H: Hamiltonian<N>,
{
    points.iter().try_fold(0.0f64, |m, (t, q, p)| {
        // time_derivative rejects a non-finite rate, so NaN cannot be skipped by `max`.
        Ok(m.max(time_derivative(f, h, *t, q, p)?.abs()))
    })
}

/// Poisson-bracket matrix `(u_i, u_j)` of the image coordinates `u = (Q, P)` of a map, as functions
/// of `(q, p)`: `M J Mᵀ` [Ardema eq. 16.28]. Equals `J` iff the map is canonical.
pub fn poisson_bracket_matrix<M: PhaseMap<N> + ?Sized, const N: usize>(
    map: &M,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<PhaseMatrix<N>> {
    Ok(jacobian(map, t, q, p)?.cosymplectic_form())
}

/// Lagrange-bracket matrix `[u_i, u_j]` of `(q, p)` regarded as functions of the parameters
/// `u = (u₁, u₂)` that `map` takes as its input: `Mᵀ J M` [Ardema eqs. 16.24–16.25]. For the
/// inverse of a canonical transformation (`u = (Q, P)`) it equals `J`.
pub fn lagrange_bracket_matrix<M: PhaseMap<N> + ?Sized, const N: usize>(
    map: &M,
    t: f64,
    u1: &SVector<f64, N>,
    u2: &SVector<f64, N>,
) -> Result<PhaseMatrix<N>> {
    Ok(jacobian(map, t, u1, u2)?.symplectic_form())
}

/// Lagrange bracket `[u_i, u_j]` of two parameters (indices into `u = (u₁, u₂)`, `0..2N`).
pub fn lagrange_bracket<M: PhaseMap<N> + ?Sized, const N: usize>(
    map: &M,
    t: f64,
    u1: &SVector<f64, N>,
    u2: &SVector<f64, N>,
    i: usize,
    j: usize,
) -> Result<f64> {
    if i >= 2 * N || j >= 2 * N {
        return Err(Error::invalid(
            "bracket index",
            format!("({i}, {j}) out of range 0..{}", 2 * N),
        ));
    }
    let l = lagrange_bracket_matrix(map, t, u1, u2)?.to_dmatrix();
    Ok(l[(i, j)])
}

/// Reciprocity defect `‖Lᵀ P − I‖_max` of Lagrange's and Poisson's brackets
/// [Ardema eq. 16.27]: `L = [u_s, u_i]` from the map `u ↦ (q, p)` and `P = (u_s, u_j)` from its
/// inverse (whose Jacobian is `M⁻¹`). Zero for **any** invertible map, canonical or not; an error if
/// the Jacobian is singular.
pub fn reciprocity_defect<M: PhaseMap<N> + ?Sized, const N: usize>(
    map: &M,
    t: f64,
    u1: &SVector<f64, N>,
    u2: &SVector<f64, N>,
) -> Result<f64> {
    let m = jacobian(map, t, u1, u2)?;
    let inv = m.checked_inverse("map Jacobian ∂(q, p)/∂u", || {
        format!("u = ({u1:?}, {u2:?})")
    })?;
    let l = m.symplectic_form();
    let p = inv.cosymplectic_form();
    Ok(l.transpose()
        .mul(&p)
        .sub(&PhaseMatrix::identity())
        .max_abs())
}

/// What [`certify`] measures about a map at one point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Certificate<const N: usize> {
    /// Exact Jacobian `M = ∂(Q, P)/∂(q, p)`.
    pub jacobian: PhaseMatrix<N>,
    /// Lagrange brackets of `(q, p)` as functions of the map's inputs: `MᵀJM`.
    pub lagrange: PhaseMatrix<N>,
    /// Poisson brackets of the outputs as functions of the inputs: `MJMᵀ`.
    pub poisson: PhaseMatrix<N>,
    /// `‖MᵀJM − J‖_max`.
    pub symplectic_defect: f64,
    /// `‖MJMᵀ − J‖_max` (equal to zero with the symplectic defect, independently computed).
    pub poisson_defect: f64,
    /// Liouville: `det M − 1` [Ardema eq. 16.23] (necessary for canonicity; sufficient only for N = 1).
    pub det_minus_one: f64,
}

impl<const N: usize> Certificate<N> {
    /// Canonical at this point to within `tol` by the matrix criterion `MᵀJM = J`.
    pub fn is_canonical(&self, tol: f64) -> bool {
        self.symplectic_defect <= tol
    }
}

/// Certify a map at a point: exact Jacobian by AD, both bracket matrices, the symplectic defect and
/// Liouville's determinant.
///
/// ```
/// use hamilton_jacobi::brackets::{certify, PhaseMap};
/// use hamilton_jacobi::{DualNum, nalgebra::SVector};
/// /// Exchange of coordinates and momenta, generated by F₁ = qQ: Q = p, P = −q.
/// struct Swap;
/// impl PhaseMap<1> for Swap {
///     fn apply<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 1>, p: &SVector<D, 1>)
///         -> (SVector<D, 1>, SVector<D, 1>) { (*p, -*q) }
/// }
/// let c = certify(&Swap, 0.0, &SVector::from([0.3]), &SVector::from([-1.2])).unwrap();
/// assert_eq!(c.symplectic_defect, 0.0);
/// assert_eq!(c.det_minus_one, 0.0);
/// ```
pub fn certify<M: PhaseMap<N> + ?Sized, const N: usize>(
    map: &M,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<Certificate<N>> {
    let m = jacobian(map, t, q, p)?;
    let j = PhaseMatrix::symplectic_j();
    let lagrange = m.symplectic_form();
    let poisson = m.cosymplectic_form();
    Ok(Certificate {
        jacobian: m,
        lagrange,
        poisson,
        symplectic_defect: lagrange.sub(&j).max_abs(),
        poisson_defect: poisson.sub(&j).max_abs(),
        det_minus_one: m.determinant() - 1.0,
    })
}

/// The coefficients `c(q, p)` of the 1-form `θ = Σ p dq − Σ P dQ = c_q · dq + c_p · dp` pulled back
/// through a map: `c_q = p − (∂Q/∂q)ᵀ P`, `c_p = −(∂Q/∂p)ᵀ P`.
struct CanonicalOneForm<'a, M: ?Sized>(&'a M);

impl<M: PhaseMap<N> + ?Sized, const N: usize> PhaseMap<N> for CanonicalOneForm<'_, M> {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        let (_, big_p) = self.0.apply(t, q, p);
        let mut cq = *p;
        let mut cp = SVector::<D, N>::zeros();
        for i in 0..N {
            let (_, dq, dp) =
                phase_gradient(|a, b| self.0.apply(PhaseDual::from_re(t), a, b).0[i], q, p);
            cq -= dq * big_p[i];
            cp -= dp * big_p[i];
        }
        (cq, cp)
    }
}

/// Canonicity by the definition [Ardema 16.2, eq. 16.4]: a map `(q, p) ↦ (Q, P)` (at fixed `t`) is
/// canonical iff `Σ p dq − Σ P dQ` is closed (locally the differential of a generating function).
/// Returns `‖K − Kᵀ‖_max` for `K = ∂c/∂(q, p)`, the Jacobian of the form's coefficients
/// (second derivatives of the map by nested AD) — zero iff the form is closed. An independent
/// computation from the symplectic condition `MᵀJM = J`, which it equals algebraically.
pub fn exactness_defect<M: PhaseMap<N> + ?Sized, const N: usize>(
    map: &M,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<f64> {
    let k = jacobian(&CanonicalOneForm(map), t, q, p)?;
    Ok(k.sub(&k.transpose()).max_abs())
}

/// Liouville's determinant `det ∂(Q, P)/∂(q, p)` [Ardema eq. 16.23].
pub fn liouville_determinant<M: PhaseMap<N> + ?Sized, const N: usize>(
    map: &M,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<f64> {
    Ok(jacobian(map, t, q, p)?.determinant())
}

/// Canonical at `(t, q, p)` to within `tol` by the symplectic condition.
pub fn is_canonical<M: PhaseMap<N> + ?Sized, const N: usize>(
    map: &M,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
    tol: f64,
) -> Result<bool> {
    Ok(certify(map, t, q, p)?.is_canonical(tol))
}

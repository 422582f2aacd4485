//! States as vectors over a dual number type: the linear operations one-step methods and Newton
//! corrections are written in, once for every shape of state.
//!
//! A state of a one-step method — `y = (q, p)`, or `(q, p, s)` with the action `s` carried along,
//! or the unknowns `u` of an implicit equation — is a point of `Dᵐ`, where `D` is a dual number
//! type ([`DualNum<f64>`]). `Dᵐ` is a free module over the ring `D` (a vector space when `D = ℝ`);
//! the methods need only its componentwise operations
//!
//! ```math
//! u + v,\qquad c\,u\ (c \in D),\qquad u - \operatorname{re} u ,
//! ```
//!
//! the last being the infinitesimal part of `u` (its component in `m`, the ideal of the
//! infinitesimals: `D = ℝ ⊕ m`). [`VectorSpace`] derives them from two componentwise maps and is
//! implemented for a vector, a phase-space pair `(q, p)` and a triple `(q, p, s)`.
//!
//! Reference for the dual numbers as a ring: Griewank & Walther, *Evaluating Derivatives*, 2nd ed.,
//! SIAM 2008, §13.2 (truncated Taylor arithmetic).

use nalgebra::SVector;
use num_dual::{DualNum, DualStruct};

/// A state in `Dᵐ` (see the [module docs](self)): componentwise maps, from which the sum, the
/// multiple by a scalar and the infinitesimal part follow.
pub trait VectorSpace: Copy {
    /// The scalars `D`.
    type Scalar: DualNum<f64> + Copy;

    /// `(f(u₁), …, f(u_m))`.
    fn map(&self, f: impl Fn(Self::Scalar) -> Self::Scalar) -> Self;

    /// `(f(u₁, v₁), …, f(u_m, v_m))`.
    fn zip_map(&self, v: &Self, f: impl Fn(Self::Scalar, Self::Scalar) -> Self::Scalar) -> Self;

    /// Whether `f` holds for every component.
    fn all(&self, f: impl Fn(Self::Scalar) -> bool) -> bool;

    /// Every real part finite (the infinitesimal parts are not inspected).
    #[inline]
    fn is_finite(&self) -> bool {
        self.all(|a| a.re().is_finite())
    }

    /// `u + v`.
    #[inline]
    fn add(&self, v: &Self) -> Self {
        self.zip_map(v, |a, b| a + b)
    }

    /// `u − v`.
    #[inline]
    fn sub(&self, v: &Self) -> Self {
        self.zip_map(v, |a, b| a - b)
    }

    /// `c u`.
    #[inline]
    fn scale(&self, c: Self::Scalar) -> Self {
        self.map(|a| a * c)
    }

    /// The infinitesimal part `u − re u` (zero for real `D`).
    #[inline]
    fn infinitesimal(&self) -> Self {
        self.map(|a| a - a.re())
    }
}

impl<D: DualNum<f64> + Copy, const N: usize> VectorSpace for SVector<D, N> {
    type Scalar = D;
    #[inline]
    fn map(&self, f: impl Fn(D) -> D) -> Self {
        SVector::map(self, f)
    }
    #[inline]
    fn zip_map(&self, v: &Self, f: impl Fn(D, D) -> D) -> Self {
        SVector::zip_map(self, v, f)
    }
    #[inline]
    fn all(&self, f: impl Fn(D) -> bool) -> bool {
        self.iter().all(|&a| f(a))
    }
}

/// A phase-space point `(q, p)`.
impl<D: DualNum<f64> + Copy, const N: usize> VectorSpace for (SVector<D, N>, SVector<D, N>) {
    type Scalar = D;
    #[inline]
    fn map(&self, f: impl Fn(D) -> D) -> Self {
        (self.0.map(&f), self.1.map(&f))
    }
    #[inline]
    fn zip_map(&self, v: &Self, f: impl Fn(D, D) -> D) -> Self {
        (self.0.zip_map(&v.0, &f), self.1.zip_map(&v.1, &f))
    }
    #[inline]
    fn all(&self, f: impl Fn(D) -> bool) -> bool {
        self.0.all(&f) && self.1.all(&f)
    }
}

/// A phase-space point with one more scalar carried along, `(q, p, s)` (the action).
impl<D: DualNum<f64> + Copy, const N: usize> VectorSpace for (SVector<D, N>, SVector<D, N>, D) {
    type Scalar = D;
    #[inline]
    fn map(&self, f: impl Fn(D) -> D) -> Self {
        (self.0.map(&f), self.1.map(&f), f(self.2))
    }
    #[inline]
    fn zip_map(&self, v: &Self, f: impl Fn(D, D) -> D) -> Self {
        (
            self.0.zip_map(&v.0, &f),
            self.1.zip_map(&v.1, &f),
            f(self.2, v.2),
        )
    }
    #[inline]
    fn all(&self, f: impl Fn(D) -> bool) -> bool {
        self.0.all(&f) && self.1.all(&f) && f(self.2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::Dual64;

    #[test]
    fn operations_are_componentwise() {
        let u = (
            SVector::from([Dual64::new(1.0, 2.0)]),
            SVector::from([Dual64::new(3.0, 4.0)]),
            Dual64::new(5.0, 6.0),
        );
        let v = u.scale(Dual64::from(2.0));
        assert_eq!(v.0[0], Dual64::new(2.0, 4.0));
        assert_eq!(v.2, Dual64::new(10.0, 12.0));
        let w = v.sub(&u).add(&u.infinitesimal());
        // 2u − u + (u − re u) = 2u − re u.
        assert_eq!(w.0[0], Dual64::new(1.0, 4.0));
        assert_eq!(w.1[0], Dual64::new(3.0, 8.0));
        assert_eq!(w.2, Dual64::new(5.0, 12.0));
        let r: SVector<f64, 2> = SVector::from([1.5, -2.0]);
        assert_eq!(r.infinitesimal(), SVector::<f64, 2>::zeros());
        assert!(u.is_finite() && !(r, r.scale(f64::INFINITY)).is_finite());
    }
}

//! The coefficient ring of the series arithmetic: plain doubles, or doubles with a rigorous bound
//! on their accumulated rounding error ([`Ball`], the crate's one interval-radius number).
//!
//! A [`Ball`] `(v, e)` is a computed value `v` and a bound `e ≥ |v − exact|`, propagated by
//! first-order running error analysis (Higham, *Accuracy and Stability of Numerical Algorithms*,
//! 2nd ed., SIAM 2002, §3.3) with the increment `u' = 2u` (twice the unit roundoff, which covers
//! the second-order terms first-order analysis neglects) per rounded operation:
//!
//! ```math
//! e(x \pm y) = e_x + e_y + u'|x \pm y|,\qquad
//! e(xy) = |x|e_y + |y|e_x + e_x e_y + u'|xy|,\qquad
//! e(x/d) = e_x/|d| + u'|x/d|
//! ```
//!
//! for exactly representable constants `d` (and `e(cx) = |c|e_x + u'|cx|` likewise). Its value
//! `v` is bit-identical to the same arithmetic on plain doubles, so the generic operations of the
//! series modules ([`super::poisson::cosine_product`], [`super::recurrences::unit_power`]) give,
//! instantiated with `f64`, the plain values, and with `Ball` the same values with their bounds.

use crate::special::double_double::DoubleDouble;

/// A commutative ring of series coefficients with the scalings the recurrences need: `f64`
/// (plain arithmetic) and [`Ball`] (the same values with rounding-error bounds).
pub trait Coefficient: Copy + Default + std::fmt::Debug + PartialEq {
    /// The exactly known number `v`.
    fn exact(v: f64) -> Self;
    /// The computed value.
    fn value(self) -> f64;
    /// Whether the coefficient is an exact zero (a term that can be skipped).
    fn is_zero(self) -> bool;
    /// `self + o`.
    fn add(self, o: Self) -> Self;
    /// `self · o`.
    fn mul(self, o: Self) -> Self;
    /// `c · self` for an exactly representable `c`.
    fn scale(self, c: f64) -> Self;
    /// `self / d` for an exactly representable `d`.
    fn div(self, d: f64) -> Self;
    /// `−self` (exact).
    fn neg(self) -> Self;
}

impl Coefficient for f64 {
    #[inline]
    fn exact(v: f64) -> Self {
        v
    }
    #[inline]
    fn value(self) -> f64 {
        self
    }
    #[inline]
    fn is_zero(self) -> bool {
        self == 0.0
    }
    #[inline]
    fn add(self, o: Self) -> Self {
        self + o
    }
    #[inline]
    fn mul(self, o: Self) -> Self {
        self * o
    }
    #[inline]
    fn scale(self, c: f64) -> Self {
        c * self
    }
    #[inline]
    fn div(self, d: f64) -> Self {
        self / d
    }
    #[inline]
    fn neg(self) -> Self {
        -self
    }
}

/// A [`Coefficient`] field for the Taylor recurrences of every operation
/// ([`super::recurrences`]): subtraction, division by a coefficient, and the divisions by an
/// index, in the form each type computes them most accurately — on `f64` as the multiplication
/// by the rounded reciprocal `1/n` the recurrences have always used (so that the values are
/// those of the plain double arithmetic, bit for bit), on
/// [`DoubleDouble`](crate::special::double_double::DoubleDouble) as a true division (`1/n` is not a
/// double and would cost the extra precision).
pub trait Field: Coefficient {
    /// `self − o`.
    fn sub(self, o: Self) -> Self;
    /// `self / o`.
    fn quo(self, o: Self) -> Self;
    /// `self / n`, on `f64` as `self · fl(1/n)`.
    fn over_index(self, n: usize) -> Self;
    /// `α · self / n`, on `f64` as `(α · fl(1/n)) · self`.
    fn scale_over_index(self, alpha: f64, n: usize) -> Self;
    /// Whether the value is finite.
    fn finite(self) -> bool;
}

impl Field for f64 {
    #[inline]
    fn sub(self, o: Self) -> Self {
        self - o
    }
    #[inline]
    fn quo(self, o: Self) -> Self {
        self / o
    }
    #[inline]
    fn over_index(self, n: usize) -> Self {
        self * (1.0 / n as f64)
    }
    #[inline]
    fn scale_over_index(self, alpha: f64, n: usize) -> Self {
        alpha * (1.0 / n as f64) * self
    }
    #[inline]
    fn finite(self) -> bool {
        self.is_finite()
    }
}

impl Coefficient for DoubleDouble {
    #[inline]
    fn exact(v: f64) -> Self {
        Self::from(v)
    }
    #[inline]
    fn value(self) -> f64 {
        self.hi
    }
    #[inline]
    fn is_zero(self) -> bool {
        self.hi == 0.0 && self.lo == 0.0
    }
    #[inline]
    fn add(self, o: Self) -> Self {
        self + o
    }
    #[inline]
    fn mul(self, o: Self) -> Self {
        self * o
    }
    #[inline]
    fn scale(self, c: f64) -> Self {
        self * c
    }
    #[inline]
    fn div(self, d: f64) -> Self {
        self / d
    }
    #[inline]
    fn neg(self) -> Self {
        -self
    }
}

impl Field for DoubleDouble {
    #[inline]
    fn sub(self, o: Self) -> Self {
        self - o
    }
    #[inline]
    fn quo(self, o: Self) -> Self {
        self / o
    }
    #[inline]
    fn over_index(self, n: usize) -> Self {
        self / n as f64
    }
    #[inline]
    fn scale_over_index(self, alpha: f64, n: usize) -> Self {
        self * alpha / n as f64
    }
    #[inline]
    fn finite(self) -> bool {
        self.is_finite()
    }
}

/// Rounding increment per operation: twice the unit roundoff (see the [module docs](self)).
pub(crate) const ROUND: f64 = f64::EPSILON;

/// A double with a bound on its accumulated rounding error (see the [module docs](self)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct Ball {
    /// The computed value (bit-identical to the plain `f64` arithmetic).
    pub(crate) v: f64,
    /// Bound on `|v − exact|`.
    pub(crate) e: f64,
}

impl Coefficient for Ball {
    #[inline]
    fn exact(v: f64) -> Self {
        Self { v, e: 0.0 }
    }
    #[inline]
    fn value(self) -> f64 {
        self.v
    }
    #[inline]
    fn is_zero(self) -> bool {
        self.v == 0.0 && self.e == 0.0
    }
    #[inline]
    fn add(self, o: Self) -> Self {
        let v = self.v + o.v;
        Self {
            v,
            e: self.e + o.e + ROUND * v.abs(),
        }
    }
    #[inline]
    fn mul(self, o: Self) -> Self {
        let v = self.v * o.v;
        Self {
            v,
            e: self.v.abs() * o.e + o.v.abs() * self.e + self.e * o.e + ROUND * v.abs(),
        }
    }
    #[inline]
    fn scale(self, c: f64) -> Self {
        let v = c * self.v;
        Self {
            v,
            e: c.abs() * self.e + ROUND * v.abs(),
        }
    }
    #[inline]
    fn div(self, d: f64) -> Self {
        let v = self.v / d;
        Self {
            v,
            e: self.e / d.abs() + ROUND * v.abs(),
        }
    }
    #[inline]
    fn neg(self) -> Self {
        Self {
            v: -self.v,
            e: self.e,
        }
    }
}

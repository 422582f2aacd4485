//! Arithmetic of [`Series`] and the traits that make it a [`DualNum<f64>`].
//!
//! Sum and difference act coefficientwise; the product is the truncated Cauchy product
//! `(ab)_γ = Σ_{α+β=γ} a_α b_β`, `|γ| ≤ K` ([`Monomials::mul`](super::Monomials::mul)); the
//! quotient is `a · (1/b)` with the reciprocal from the elementary functions. Comparisons look at
//! the constant term only, so code that branches on values follows the same path as on reals
//! (as for every number type of num-dual).

use super::arena::{with_arena, Operand, Series, CONST, POISON};
use super::elementary;
use num_dual::DualNum;
use std::fmt;
use std::ops::{Add, Div, Mul, Neg, Rem, Sub};

/// `α·a + β·b` (either may be a constant).
pub(crate) fn linear(a: Series, alpha: f64, b: Series, beta: f64) -> Series {
    if a.slot == POISON || b.slot == POISON {
        with_arena(|ar| {
            ar.resolve(&Series::poison());
        });
        return Series::poison();
    }
    if a.slot == CONST && b.slot == CONST {
        return Series::constant(alpha * a.re + beta * b.re);
    }
    with_arena(|ar| {
        let (Some(x), Some(y)) = (ar.resolve(&a), ar.resolve(&b)) else {
            return Series::poison();
        };
        ar.push_with(|_, old, out, _| {
            for (op, w) in [(&x, alpha), (&y, beta)] {
                match *op {
                    Operand::Const(c) => out[0] += w * c,
                    Operand::Slot(start) => {
                        for (r, v) in out.iter_mut().zip(&old[start..]) {
                            *r += w * v;
                        }
                    }
                }
            }
        })
    })
    .unwrap_or_else(Series::poison)
}

/// `a·b` truncated at degree `K`.
pub(crate) fn product(a: Series, b: Series) -> Series {
    if a.slot == POISON || b.slot == POISON {
        with_arena(|ar| {
            ar.resolve(&Series::poison());
        });
        return Series::poison();
    }
    if a.slot == CONST && b.slot == CONST {
        return Series::constant(a.re * b.re);
    }
    if a.slot == CONST {
        return linear(b, a.re, Series::constant(0.0), 0.0);
    }
    if b.slot == CONST {
        return linear(a, b.re, Series::constant(0.0), 0.0);
    }
    with_arena(|ar| {
        let (Some(Operand::Slot(x)), Some(Operand::Slot(y))) = (ar.resolve(&a), ar.resolve(&b))
        else {
            return Series::poison();
        };
        ar.push_with(|table, old, out, scratch| {
            let len = table.len();
            table.mul_to_degree(
                &old[x..x + len],
                &old[y..y + len],
                out,
                scratch,
                table.degree(),
            )
        })
    })
    .unwrap_or_else(Series::poison)
}

impl Add for Series {
    type Output = Series;
    fn add(self, rhs: Series) -> Series {
        linear(self, 1.0, rhs, 1.0)
    }
}
impl Sub for Series {
    type Output = Series;
    fn sub(self, rhs: Series) -> Series {
        linear(self, 1.0, rhs, -1.0)
    }
}
impl Mul for Series {
    type Output = Series;
    fn mul(self, rhs: Series) -> Series {
        product(self, rhs)
    }
}
impl Div for Series {
    type Output = Series;
    fn div(self, rhs: Series) -> Series {
        if rhs.slot == CONST {
            return linear(self, rhs.re.recip(), Series::constant(0.0), 0.0);
        }
        product(self, elementary::recip(rhs))
    }
}
/// The remainder is defined for constants only (`%` has no meaning on a truncated power series);
/// otherwise the result is poisoned and the scope reports it.
impl Rem for Series {
    type Output = Series;
    fn rem(self, rhs: Series) -> Series {
        if self.slot == CONST && rhs.slot == CONST {
            return Series::constant(self.re % rhs.re);
        }
        with_arena(|ar| {
            ar.fault.get_or_insert_with(|| {
                "the remainder `%` is not defined for non-constant series".into()
            });
        });
        Series::poison()
    }
}
impl Neg for Series {
    type Output = Series;
    fn neg(self) -> Series {
        linear(self, -1.0, Series::constant(0.0), 0.0)
    }
}
impl Neg for &Series {
    type Output = Series;
    fn neg(self) -> Series {
        -*self
    }
}

/// The traits a `Copy` number type `T` with a constant `T::constant(f64)` and the value at the
/// expansion point in its field `re` needs besides its arithmetic (`+ − × ÷ %` and `−` by value,
/// [`DualNum`]) to be a [`DualNum<f64>`]: the operators by reference, with `f64` and assigning;
/// constants; `Signed`, `Inv`, sums and products; and comparisons, which look at `re` only (so
/// code that branches on values follows the same path as on reals).
macro_rules! number_traits {
    ($T:ident) => {
        number_traits!(@ops $T, Add add AddAssign add_assign, Sub sub SubAssign sub_assign,
            Mul mul MulAssign mul_assign, Div div DivAssign div_assign,
            Rem rem RemAssign rem_assign);
        impl From<f64> for $T {
            fn from(c: f64) -> Self {
                $T::constant(c)
            }
        }
        impl ::num_traits::Zero for $T {
            fn zero() -> Self {
                $T::constant(0.0)
            }
            fn is_zero(&self) -> bool {
                self.re == 0.0
            }
        }
        impl ::num_traits::One for $T {
            fn one() -> Self {
                $T::constant(1.0)
            }
        }
        impl ::num_traits::Num for $T {
            type FromStrRadixErr = <f64 as ::num_traits::Num>::FromStrRadixErr;
            fn from_str_radix(
                s: &str,
                radix: u32,
            ) -> ::std::result::Result<Self, Self::FromStrRadixErr> {
                <f64 as ::num_traits::Num>::from_str_radix(s, radix).map($T::constant)
            }
        }
        impl ::num_traits::Signed for $T {
            fn abs(&self) -> Self {
                if self.re < 0.0 {
                    -*self
                } else {
                    *self
                }
            }
            fn abs_sub(&self, other: &Self) -> Self {
                if self.re > other.re {
                    *self - *other
                } else {
                    $T::constant(0.0)
                }
            }
            fn signum(&self) -> Self {
                $T::constant(if self.re > 0.0 {
                    1.0
                } else if self.re < 0.0 {
                    -1.0
                } else {
                    0.0
                })
            }
            fn is_positive(&self) -> bool {
                self.re > 0.0
            }
            fn is_negative(&self) -> bool {
                self.re < 0.0
            }
        }
        impl ::num_traits::Inv for $T {
            type Output = $T;
            fn inv(self) -> $T {
                ::num_dual::DualNum::recip(&self)
            }
        }
        impl ::std::iter::Sum for $T {
            fn sum<I: Iterator<Item = $T>>(iter: I) -> $T {
                iter.fold($T::constant(0.0), |a, b| a + b)
            }
        }
        impl<'a> ::std::iter::Sum<&'a $T> for $T {
            fn sum<I: Iterator<Item = &'a $T>>(iter: I) -> $T {
                iter.fold($T::constant(0.0), |a, b| a + *b)
            }
        }
        impl ::std::iter::Product for $T {
            fn product<I: Iterator<Item = $T>>(iter: I) -> $T {
                iter.fold($T::constant(1.0), |a, b| a * b)
            }
        }
        impl<'a> ::std::iter::Product<&'a $T> for $T {
            fn product<I: Iterator<Item = &'a $T>>(iter: I) -> $T {
                iter.fold($T::constant(1.0), |a, b| a * *b)
            }
        }
        impl ::num_traits::FromPrimitive for $T {
            fn from_i64(n: i64) -> Option<Self> {
                Some($T::constant(n as f64))
            }
            fn from_u64(n: u64) -> Option<Self> {
                Some($T::constant(n as f64))
            }
            fn from_f64(n: f64) -> Option<Self> {
                Some($T::constant(n))
            }
        }
        impl ::num_dual::DualStruct<$T, f64> for $T {
            type Real = f64;
            type Inner = f64;
            fn re(&self) -> f64 {
                self.re
            }
            fn from_inner(inner: &f64) -> Self {
                $T::constant(*inner)
            }
        }
        impl ::num_dual::Mappable<$T> for $T {
            type Output<O> = O;
            fn map_dual<M: Fn($T) -> O, O>(self, f: M) -> O {
                f(self)
            }
        }
        impl PartialEq for $T {
            fn eq(&self, other: &Self) -> bool {
                self.re == other.re
            }
        }
        impl PartialEq<f64> for $T {
            fn eq(&self, other: &f64) -> bool {
                self.re == *other
            }
        }
        impl PartialOrd for $T {
            fn partial_cmp(&self, other: &Self) -> Option<::std::cmp::Ordering> {
                self.re.partial_cmp(&other.re)
            }
        }
        impl PartialOrd<f64> for $T {
            fn partial_cmp(&self, other: &f64) -> Option<::std::cmp::Ordering> {
                self.re.partial_cmp(other)
            }
        }
        number_traits!(@constants $T, E, FRAC_1_PI, FRAC_1_SQRT_2, FRAC_2_PI, FRAC_2_SQRT_PI,
            FRAC_PI_2, FRAC_PI_3, FRAC_PI_4, FRAC_PI_6, FRAC_PI_8, LN_10, LN_2, LOG10_E, LOG2_E,
            PI, SQRT_2);
    };
    (@constants $T:ident, $($name:ident),*) => {
        impl ::num_traits::FloatConst for $T {
            $(fn $name() -> Self {
                $T::constant(<f64 as ::num_traits::FloatConst>::$name())
            })*
        }
    };
    (@ops $T:ident, $($trt:ident $m:ident $atrt:ident $am:ident),*) => {$(
        impl<'a> ::std::ops::$trt<&'a $T> for $T {
            type Output = $T;
            fn $m(self, rhs: &'a $T) -> $T { ::std::ops::$trt::$m(self, *rhs) }
        }
        impl<'a> ::std::ops::$trt<$T> for &'a $T {
            type Output = $T;
            fn $m(self, rhs: $T) -> $T { ::std::ops::$trt::$m(*self, rhs) }
        }
        impl<'a, 'b> ::std::ops::$trt<&'b $T> for &'a $T {
            type Output = $T;
            fn $m(self, rhs: &'b $T) -> $T { ::std::ops::$trt::$m(*self, *rhs) }
        }
        impl ::std::ops::$trt<f64> for $T {
            type Output = $T;
            fn $m(self, rhs: f64) -> $T { ::std::ops::$trt::$m(self, $T::constant(rhs)) }
        }
        impl ::std::ops::$trt<f64> for &$T {
            type Output = $T;
            fn $m(self, rhs: f64) -> $T { ::std::ops::$trt::$m(*self, $T::constant(rhs)) }
        }
        impl ::std::ops::$atrt for $T {
            fn $am(&mut self, rhs: $T) { *self = ::std::ops::$trt::$m(*self, rhs); }
        }
        impl ::std::ops::$atrt<f64> for $T {
            fn $am(&mut self, rhs: f64) {
                *self = ::std::ops::$trt::$m(*self, $T::constant(rhs));
            }
        }
        impl<'a> ::std::ops::$atrt<&'a $T> for $T {
            fn $am(&mut self, rhs: &'a $T) { *self = ::std::ops::$trt::$m(*self, *rhs); }
        }
    )*};
}
pub(crate) use number_traits;

number_traits!(Series);

impl fmt::Debug for Series {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.slot {
            CONST => write!(f, "Series::constant({:?})", self.re),
            POISON => write!(f, "Series(poisoned)"),
            slot => write!(
                f,
                "Series {{ scope: {}, slot: {slot}, constant term: {:?} }}",
                self.scope, self.re
            ),
        }
    }
}
impl fmt::Display for Series {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self.slot {
            CONST => write!(f, "{}", self.re),
            POISON => write!(f, "NaN (poisoned series)"),
            _ => write!(f, "{} + O(x)", self.re),
        }
    }
}
impl DualNum<f64> for Series {
    /// The largest degree any scope may have ([`MAX_SERIES_DEGREE`](super::MAX_SERIES_DEGREE));
    /// a scope's own degree `K` is at most this, so `NDERIV` Newton steps in the series type
    /// (as [`crate::implicit`] takes) fix every coefficient of degree `≤ K`.
    const NDERIV: usize = super::monomials::MAX_SERIES_DEGREE;

    fn recip(&self) -> Self {
        elementary::recip(*self)
    }
    fn powi(&self, n: i32) -> Self {
        elementary::powi(*self, n)
    }
    fn powf(&self, a: f64) -> Self {
        elementary::powf(*self, a)
    }
    fn sqrt(&self) -> Self {
        elementary::sqrt(*self)
    }
    fn cbrt(&self) -> Self {
        elementary::cbrt(*self)
    }
    fn exp(&self) -> Self {
        elementary::exp(*self)
    }
    fn exp2(&self) -> Self {
        elementary::exp2(*self)
    }
    fn exp_m1(&self) -> Self {
        elementary::exp_m1(*self)
    }
    fn ln(&self) -> Self {
        elementary::ln(*self)
    }
    fn log(&self, base: f64) -> Self {
        elementary::ln(*self) * base.ln().recip()
    }
    fn log2(&self) -> Self {
        elementary::ln(*self) * std::f64::consts::LOG2_E
    }
    fn log10(&self) -> Self {
        elementary::ln(*self) * std::f64::consts::LOG10_E
    }
    fn ln_1p(&self) -> Self {
        elementary::ln_1p(*self)
    }
    fn sin(&self) -> Self {
        elementary::sin(*self)
    }
    fn cos(&self) -> Self {
        elementary::cos(*self)
    }
    fn tan(&self) -> Self {
        elementary::tan(*self)
    }
    fn sin_cos(&self) -> (Self, Self) {
        elementary::sin_cos(*self)
    }
    fn asin(&self) -> Self {
        elementary::asin(*self)
    }
    fn acos(&self) -> Self {
        elementary::acos(*self)
    }
    fn atan(&self) -> Self {
        elementary::atan(*self)
    }
    fn atan2(&self, other: Self) -> Self {
        elementary::atan2(*self, other)
    }
    fn sinh(&self) -> Self {
        elementary::sinh(*self)
    }
    fn cosh(&self) -> Self {
        elementary::cosh(*self)
    }
    fn tanh(&self) -> Self {
        elementary::tanh(*self)
    }
    fn asinh(&self) -> Self {
        elementary::asinh(*self)
    }
    fn acosh(&self) -> Self {
        elementary::acosh(*self)
    }
    fn atanh(&self) -> Self {
        elementary::atanh(*self)
    }
    fn sph_j0(&self) -> Self {
        elementary::sph_j(*self, 0)
    }
    fn sph_j1(&self) -> Self {
        elementary::sph_j(*self, 1)
    }
    fn sph_j2(&self) -> Self {
        elementary::sph_j(*self, 2)
    }
}

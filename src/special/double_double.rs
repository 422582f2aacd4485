//! Double-double arithmetic: a real number carried as the unevaluated sum `hi + lo` of two
//! doubles with `|lo| ≤ ulp(hi)/2`, about 106 bits of significand, built on the error-free
//! transformations of a sum and of a product.
//!
//! For doubles `a`, `b` (no overflow), rounding to nearest,
//!
//! ```math
//! a + b = s + e, \quad s = \mathrm{fl}(a + b), \qquad a\,b = p + e', \quad p = \mathrm{fl}(a\,b),
//! ```
//!
//! with `e`, `e'` doubles: [`two_sum`] finds `e` in six operations for any `a`, `b` (Knuth,
//! TAOCP vol. 2 §4.2.2, theorem B), [`fast_two_sum`] in three when `|a| ≥ |b|` (Dekker 1971),
//! and [`two_prod`] finds `e'` as the fused multiply-add `fma(a, b, −p)` (Muller et al. 2018
//! §4.4). The operations on [`DoubleDouble`] are the algorithms of Joldes, Muller and Popescu
//! (2017) with their relative error bounds in `u = 2⁻⁵³`: sum `3u²` (their algorithm 6),
//! product `5u²` (algorithm 12), product by a double `2u²` (algorithm 9), quotient `15u² + 56u³`
//! (algorithm 17); the square root is one Newton step from the double root, as in the QD library
//! (Hida, Li & Bailey 2001), about `4u²`.
//!
//! The error-free transformations hold only while no intermediate overflows or underflows: a
//! non-finite input or an overflowing result gives a non-finite `hi`, and results below
//! `2⁻⁹⁶⁹` lose the extra precision (the low part is subnormal). Callers fall back to plain
//! doubles there.
//!
//! # References
//!
//! * T. J. Dekker, "A floating-point technique for extending the available precision",
//!   *Numerische Mathematik* 18 (1971), 224–242.
//! * D. E. Knuth, *The Art of Computer Programming*, vol. 2, 3rd ed., Addison-Wesley (1997),
//!   §4.2.2.
//! * Y. Hida, X. S. Li, D. H. Bailey, "Algorithms for quad-double precision floating point
//!   arithmetic", *Proc. 15th IEEE Symposium on Computer Arithmetic* (2001), 155–162 (the QD
//!   library).
//! * J.-M. Muller et al., *Handbook of Floating-Point Arithmetic*, 2nd ed., Birkhäuser (2018),
//!   §4.3–4.4 (error-free transformations), §14.1 (double-word arithmetic).
//! * M. Joldes, J.-M. Muller, V. Popescu, "Tight and rigorous error bounds for basic building
//!   blocks of double-word arithmetic", *ACM Trans. Math. Software* 44 (2017), 15res.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// `(s, e)` with `s = fl(a + b)` and `a + b = s + e` exactly, for any doubles (Knuth 1997
/// §4.2.2, theorem B; Møller 1965).
#[inline]
pub(crate) fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

/// `(s, e)` with `s = fl(a + b)` and `a + b = s + e` exactly, provided `|a| ≥ |b|` (or `a = 0`)
/// (Dekker 1971).
#[inline]
pub(crate) fn fast_two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    (s, b - (s - a))
}

/// `(p, e)` with `p = fl(a·b)` and `a·b = p + e` exactly (no overflow, `a·b` not in the
/// underflow range), by the fused multiply-add `e = fma(a, b, −p)` (Muller et al. 2018 §4.4.1).
#[inline]
pub(crate) fn two_prod(a: f64, b: f64) -> (f64, f64) {
    let p = a * b;
    (p, a.mul_add(b, -p))
}

/// Kahan's compensated summation `x += dx`: `carry` holds the low-order part lost by the
/// previous additions and is subtracted from the next increment,
/// `y = δx − c`, `s = fl(x + y)`, `c ← (s − x) − y`, `x ← s`, so that a sum of `n` increments has an error bound `2u Σ|δx|` independent of `n` (Higham,
/// *Accuracy and Stability of Numerical Algorithms*, 2nd ed., 2002, §4.3). For any number type:
/// on dual numbers the real parts round exactly as on reals, so a run differentiated by forward
/// AD follows the real run bit for bit.
#[inline]
pub(crate) fn kahan_add<D: num_dual::DualNum<f64> + Copy>(x: &mut D, carry: &mut D, dx: D) {
    let y = dx - *carry;
    let s = *x + y;
    *carry = (s - *x) - y;
    *x = s;
}

/// [`kahan_add`] componentwise over equally long slices.
#[inline]
pub(crate) fn compensated_add<D: num_dual::DualNum<f64> + Copy>(
    x: &mut [D],
    carry: &mut [D],
    dx: &[D],
) {
    for ((x, c), &d) in x.iter_mut().zip(carry.iter_mut()).zip(dx) {
        kahan_add(x, c, d);
    }
}

/// A double-double number `hi + lo`, normalised so that `hi = fl(hi + lo)` (see the
/// [module docs](self)).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(crate) struct DoubleDouble {
    /// The leading part, the value rounded to the nearest double.
    pub hi: f64,
    /// The trailing part, `|lo| ≤ ulp(hi)/2`.
    pub lo: f64,
}

impl DoubleDouble {
    /// π to about 107 bits: `fl(π) + fl(π − fl(π))`.
    pub const PI: Self = Self {
        hi: std::f64::consts::PI,
        lo: 1.224_646_799_147_353_2e-16,
    };

    /// `hi + lo` renormalised (requires `|hi| ≥ |lo|`).
    #[inline]
    pub fn new(hi: f64, lo: f64) -> Self {
        let (hi, lo) = fast_two_sum(hi, lo);
        Self { hi, lo }
    }

    /// The exact product `a·b` of two doubles.
    #[inline]
    pub fn product(a: f64, b: f64) -> Self {
        let (hi, lo) = two_prod(a, b);
        Self { hi, lo }
    }

    /// The value rounded to the nearest double.
    #[inline]
    pub fn to_f64(self) -> f64 {
        self.hi
    }

    /// `√x` (`x ≥ 0`): one Newton step `y + (x − y²)/(2y)` from the double root `y`, the
    /// residual `x − y²` formed exactly (Hida, Li & Bailey 2001).
    #[inline]
    pub fn sqrt(self) -> Self {
        if self.hi <= 0.0 {
            return Self::from(self.hi.sqrt());
        }
        let y = self.hi.sqrt();
        let (p, e) = two_prod(y, y);
        let r = ((self.hi - p) - e + self.lo) / (2.0 * y);
        Self::new(y, r)
    }
}

/// `ln 2` to about 107 bits: `fl(ln 2) + fl(ln 2 − fl(ln 2))` (Hida, Li & Bailey 2001).
const LN_2: DoubleDouble = DoubleDouble {
    hi: std::f64::consts::LN_2,
    lo: 2.319_046_813_846_299_6e-17,
};

/// The elementary functions of a double-double number, each to a relative (for `sin`, `cos`
/// near their zeros: absolute) error of a few `u²` (`u = 2⁻⁵³`) over the reduced arguments:
///
/// * `eˣ = 2^m e^r`, `x = m ln 2 + r`, `|r| ≤ ln 2 / 2`, and `e^r − 1` from `s = e^{r/2⁹} − 1`
///   by its Taylor series (13 terms, `|r/2⁹| < 7·10⁻⁴`) and nine doublings
///   `s ← 2s + s²` (`e^{2a} − 1 = (e^a − 1)(e^a + 1)`), which keep the relative error of
///   `e^r − 1` instead of amplifying that of `e^r` (the QD library's scheme);
/// * `ln x` by one Newton step on `eʸ = x` from the double logarithm `y₀`:
///   `y = y₀ + x e^{−y₀} − 1`, quadratic convergence from `u` to `u²`;
/// * `sin x`, `cos x` from `r = x − j π/2` (`j` the nearest integer, `π/2` to 107 bits, so the
///   absolute error of `r` is about `|x| u²`), `|r| ≤ π/4`, by their Taylor series to the term
///   below `u²` (15 terms), the quadrant `j mod 4` selecting signs;
/// * `atan2(y, x)` by one Newton step on `x sin z − y cos z = 0` from the double `atan2`:
///   `z ← z + (y cos z − x sin z)/(x cos z + y sin z)`;
/// * `tanh u = −sign(u) s/(2 + s)` with `s = e^{−2|u|} − 1` (no cancellation for small `u`);
/// * `x^p = e^{p ln x}` (`x > 0`).
///
/// Non-finite inputs give non-finite results (NaN for a logarithm of a negative number), as
/// on doubles.
///
/// References: Y. Hida, X. S. Li, D. H. Bailey (2001), the QD library's `exp`, `log`,
/// `sin`/`cos` (argument reduction and Newton step); J.-M. Muller, *Elementary Functions*,
/// 3rd ed., Birkhäuser 2016, §11 (range reduction).
impl DoubleDouble {
    /// `eˣ − 1` for `|x| ≤ ln 2 / 2` (see the [impl docs](DoubleDouble#impl-DoubleDouble-1)).
    fn exp_m1_reduced(x: Self) -> Self {
        const HALVINGS: i32 = 9;
        let a = x * (0.5f64).powi(HALVINGS);
        // Σ_{n=1}^{13} aⁿ/n!: |a| < 6.8·10⁻⁴, the first term dropped below 10⁻⁴⁴ relative.
        let mut term = a;
        let mut s = a;
        for n in 2..=13 {
            term = term * a / n as f64;
            s = s + term;
        }
        for _ in 0..HALVINGS {
            s = s * 2.0 + s * s;
        }
        s
    }

    /// `eˣ` (see the [impl docs](DoubleDouble#impl-DoubleDouble-1)).
    pub fn exp(self) -> Self {
        if self.hi.is_nan() {
            return self;
        }
        if self.hi > 709.78 {
            return Self::from(f64::INFINITY);
        }
        if self.hi < -745.2 {
            return Self::from(0.0);
        }
        let m = (self.hi / std::f64::consts::LN_2).round();
        let r = self - LN_2 * m;
        let e = Self::exp_m1_reduced(r) + Self::from(1.0);
        // Multiplying by a power of two is exact (in two factors, so that neither overflows nor
        // underflows before the product does).
        let (m1, m2) = ((m / 2.0).trunc(), m - (m / 2.0).trunc());
        e * 2f64.powi(m1 as i32) * 2f64.powi(m2 as i32)
    }

    /// `eˣ − 1`, accurate relative to the result also for small `|x|`.
    pub fn exp_m1(self) -> Self {
        if self.hi.abs() <= 0.5 * std::f64::consts::LN_2 {
            Self::exp_m1_reduced(self)
        } else {
            self.exp() - Self::from(1.0)
        }
    }

    /// `ln x` (`x > 0`; `−∞` at 0, NaN below; see the [impl docs](DoubleDouble#impl-DoubleDouble-1)).
    pub fn ln(self) -> Self {
        if self.hi.is_nan() || self.hi <= 0.0 || self.hi == f64::INFINITY {
            return Self::from(self.hi.ln());
        }
        let y = Self::from(self.hi.ln());
        y + self * (-y).exp() - Self::from(1.0)
    }

    /// `(sin x, cos x)` (see the [impl docs](DoubleDouble#impl-DoubleDouble-1)).
    pub fn sin_cos(self) -> (Self, Self) {
        if !self.hi.is_finite() {
            return (Self::from(f64::NAN), Self::from(f64::NAN));
        }
        let half_pi = Self::PI * 0.5;
        let j = (self.hi / half_pi.hi).round();
        let r = self - half_pi * j;
        let r2 = r * r;
        // sin r = Σ (−1)ⁱ r^{2i+1}/(2i+1)!, cos r = Σ (−1)ⁱ r^{2i}/(2i)!, |r| ≤ π/4 + |x|u: the
        // terms i ≤ 15 reach (π/4)³⁰/30! < 10⁻³⁴.
        let (mut ts, mut tc) = (r, Self::from(1.0));
        let (mut s, mut c) = (r, Self::from(1.0));
        for i in 1..=15 {
            let n = 2.0 * i as f64;
            tc = -(tc * r2 / ((n - 1.0) * n));
            ts = -(ts * r2 / (n * (n + 1.0)));
            c = c + tc;
            s = s + ts;
        }
        match (j.rem_euclid(4.0)) as u8 {
            0 => (s, c),
            1 => (c, -s),
            2 => (-s, -c),
            _ => (-c, s),
        }
    }

    /// `atan2(y, x)` with `y = self` (see the [impl docs](DoubleDouble#impl-DoubleDouble-1)).
    pub fn atan2(self, x: Self) -> Self {
        let z = Self::from(self.hi.atan2(x.hi));
        if !z.hi.is_finite() || (self.hi == 0.0 && x.hi == 0.0) {
            return z;
        }
        let (s, c) = z.sin_cos();
        z + (self * c - x * s) / (x * c + self * s)
    }

    /// `tanh u` (see the [impl docs](DoubleDouble#impl-DoubleDouble-1)).
    pub fn tanh(self) -> Self {
        if self.hi.is_nan() {
            return self;
        }
        let sign = if self.hi < 0.0 { -1.0 } else { 1.0 };
        if self.hi.abs() > 40.0 {
            // 1 − tanh|u| < 2e^{−80}, below u²/2.
            return Self::from(sign);
        }
        let s = (self * (-2.0 * sign)).exp_m1();
        -(s / (s + Self::from(2.0))) * sign
    }

    /// `1/x`.
    pub fn recip(self) -> Self {
        Self::from(1.0) / self
    }

    /// `xᵖ = e^{p ln x}` for `x > 0`; `0ᵖ` for `p > 0` is 0, and for `x < 0` the result is NaN.
    pub fn powf(self, p: f64) -> Self {
        if self.hi == 0.0 && p > 0.0 {
            return Self::from(0.0);
        }
        (self.ln() * p).exp()
    }

    /// Whether both parts are finite.
    pub fn is_finite(self) -> bool {
        self.hi.is_finite() && self.lo.is_finite()
    }
}

impl From<f64> for DoubleDouble {
    #[inline]
    fn from(x: f64) -> Self {
        Self { hi: x, lo: 0.0 }
    }
}

impl Neg for DoubleDouble {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self {
            hi: -self.hi,
            lo: -self.lo,
        }
    }
}

/// Relative error `≤ 3u²` (Joldes, Muller & Popescu 2017, algorithm 6).
impl Add for DoubleDouble {
    type Output = Self;
    #[inline]
    fn add(self, y: Self) -> Self {
        let (sh, sl) = two_sum(self.hi, y.hi);
        let (th, tl) = two_sum(self.lo, y.lo);
        let (vh, vl) = fast_two_sum(sh, sl + th);
        Self::new(vh, tl + vl)
    }
}

impl Sub for DoubleDouble {
    type Output = Self;
    #[inline]
    fn sub(self, y: Self) -> Self {
        self + (-y)
    }
}

/// Relative error `≤ 5u²` (Joldes, Muller & Popescu 2017, algorithm 12).
impl Mul for DoubleDouble {
    type Output = Self;
    #[inline]
    fn mul(self, y: Self) -> Self {
        let (ch, cl1) = two_prod(self.hi, y.hi);
        let tl = self.hi.mul_add(y.lo, self.lo * y.lo);
        let cl2 = self.lo.mul_add(y.hi, tl);
        Self::new(ch, cl1 + cl2)
    }
}

/// Relative error `≤ 2u²` (Joldes, Muller & Popescu 2017, algorithm 9).
impl Mul<f64> for DoubleDouble {
    type Output = Self;
    #[inline]
    fn mul(self, y: f64) -> Self {
        let (ch, cl1) = two_prod(self.hi, y);
        Self::new(ch, self.lo.mul_add(y, cl1))
    }
}

/// Relative error `≤ 15u² + 56u³` (Joldes, Muller & Popescu 2017, algorithm 17).
impl Div for DoubleDouble {
    type Output = Self;
    #[inline]
    fn div(self, y: Self) -> Self {
        let th = self.hi / y.hi;
        let r = y * th;
        // x_hi − r_hi is exact (Sterbenz: r_hi is within a few ulps of x_hi).
        let delta = (self.hi - r.hi) + (self.lo - r.lo);
        Self::new(th, delta / y.hi)
    }
}

/// `x/y` for a double `y`: the quotient by a double-double with `y.lo = 0`.
impl Div<f64> for DoubleDouble {
    type Output = Self;
    #[inline]
    fn div(self, y: f64) -> Self {
        self / Self::from(y)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    const U: f64 = f64::EPSILON / 2.0;

    /// A double as an exact rational `m·2^k` with an integer `m` (`k` the exponent of its last
    /// bit).
    fn split(x: f64) -> (i128, i32) {
        if x == 0.0 {
            return (0, 0);
        }
        let bits = x.to_bits();
        let exp = ((bits >> 52) & 0x7ff) as i32;
        let frac = (bits & ((1u64 << 52) - 1)) as i128;
        let (m, k) = if exp == 0 {
            (frac, -1074)
        } else {
            (frac | (1i128 << 52), exp - 1075)
        };
        (if x < 0.0 { -m } else { m }, k)
    }

    /// The exact sum of doubles whose exponents lie within 60 of each other, as an integer
    /// multiple of `2^k` (`k` the smallest last-bit exponent).
    fn exact_sum(xs: &[f64]) -> (i128, i32) {
        let parts: Vec<(i128, i32)> = xs.iter().map(|&x| split(x)).collect();
        let k = parts
            .iter()
            .filter(|(m, _)| *m != 0)
            .map(|p| p.1)
            .min()
            .unwrap_or(0);
        let m = parts
            .iter()
            .map(|&(m, e)| if m == 0 { 0 } else { m << (e - k) })
            .sum();
        (m, k)
    }

    /// Normalise `m·2^k` (odd `m`, or `0`) for comparison.
    fn canon((mut m, mut k): (i128, i32)) -> (i128, i32) {
        if m == 0 {
            return (0, 0);
        }
        while m % 2 == 0 {
            m /= 2;
            k += 1;
        }
        (m, k)
    }

    /// A reproducible stream of doubles of mixed signs and magnitudes `2^±20` (a 64-bit linear
    /// congruential generator, Knuth's MMIX constants).
    fn samples(n: usize, mut seed: u64) -> Vec<f64> {
        (0..n)
            .map(|_| {
                seed = seed
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1_442_695_040_888_963_407);
                let mant = 1.0 + (seed >> 11) as f64 / (1u64 << 53) as f64;
                let exp = ((seed >> 3) % 41) as i32 - 20;
                let sign = if seed & 1 == 0 { 1.0 } else { -1.0 };
                sign * mant * 2f64.powi(exp)
            })
            .collect()
    }

    /// `a + b = s + e` and `a·b = p + e'` exactly, checked in integer arithmetic on the scaled
    /// significands; `fast_two_sum` agrees with `two_sum` when `|a| ≥ |b|`.
    #[test]
    fn error_free_transformations_are_exact() {
        let xs = samples(4000, 7);
        for w in xs.chunks(2) {
            let (a, b) = (w[0], w[1]);
            let (s, e) = two_sum(a, b);
            assert_eq!(s, a + b);
            assert_eq!(
                canon(exact_sum(&[a, b])),
                canon(exact_sum(&[s, e])),
                "{a} {b}"
            );
            let (big, small) = if a.abs() >= b.abs() { (a, b) } else { (b, a) };
            assert_eq!(fast_two_sum(big, small), two_sum(big, small));
            let (p, e) = two_prod(a, b);
            assert_eq!(p, a * b);
            // a·b = (ma·mb)·2^(ka+kb): 106-bit product in i128.
            let ((ma, ka), (mb, kb)) = (split(a), split(b));
            let exact = canon((ma * mb, ka + kb));
            assert_eq!(exact, canon(exact_sum(&[p, e])), "{a}·{b}");
        }
    }

    /// Representable cases against exact rationals: `(1 + 2⁻⁶⁰)² = 1 + 2⁻⁵⁹ + 2⁻¹²⁰` (the
    /// last term below the precision: `1 + 2⁻⁵⁹`), `(1 + 2⁻⁶⁰) − 1 = 2⁻⁶⁰`,
    /// `√(1 + 2⁻⁵⁹) = 1 + 2⁻⁶⁰ − 2⁻¹²¹ + …` (`1 + 2⁻⁶⁰`), `1/3` and `(3 + 2⁻⁶⁰)/3 − 1 = 2⁻⁶⁰/3`
    /// (residuals formed exactly by FMA), `√2` (its square is `2` to `u²`), and `π` split into
    /// `fl(π) + fl(π − fl(π))`.
    #[test]
    fn representable_cases() {
        let t = 2f64.powi(-60);
        let x = DoubleDouble::new(1.0, t);
        let sq = x * x;
        assert_eq!((sq.hi, sq.lo), (1.0, 2f64.powi(-59)));
        assert_eq!(x - DoubleDouble::from(1.0), DoubleDouble::from(t));
        let root = sq.sqrt();
        assert_eq!((root.hi, root.lo), (1.0, t));
        // 1 − 3(hi + lo): 1 − 3hi is exact by FMA, then one rounding.
        let third = DoubleDouble::from(1.0) / 3.0;
        assert_eq!(third.hi, 1.0 / 3.0);
        let rho = (-3.0f64).mul_add(third.hi, 1.0);
        assert!((-3.0f64).mul_add(third.lo, rho).abs() <= 16.0 * U * U);
        let q = DoubleDouble::new(3.0, t) / 3.0 - DoubleDouble::from(1.0);
        assert!(
            (q.hi - t / 3.0).abs() <= 16.0 * U * U + U * t / 3.0,
            "{q:?}"
        );
        let s2 = DoubleDouble::from(2.0).sqrt();
        assert_eq!(s2.hi, 2f64.sqrt());
        let back = s2 * s2 - DoubleDouble::from(2.0);
        assert!(back.hi.abs() <= 16.0 * U * U, "{back:?}");
        // π = 3.14159265358979323846264338327950288…, fl(π) = 884279719003555/2⁴⁸,
        // π − fl(π) = 1.22464679914735317722606592814…e−16 (the low part its rounding).
        assert_eq!(DoubleDouble::PI.hi, 884_279_719_003_555.0 / 2f64.powi(48));
        let low: f64 = "1.22464679914735317722606592814e-16".parse().unwrap();
        assert_eq!(DoubleDouble::PI.lo, low);
    }

    /// `Σ xᵢ` in units of `2^k`, each term truncated towards −∞ (exact when every `xᵢ` is a
    /// multiple of `2^k`; otherwise short by less than one unit per term), for terms below
    /// `2^(k+70)`.
    fn fixed(xs: &[f64], k: i32) -> i128 {
        xs.iter()
            .map(|&x| {
                let (m, e) = split(x);
                if e >= k {
                    m << (e - k)
                } else if k - e >= 127 {
                    if m < 0 {
                        -1
                    } else {
                        0
                    }
                } else {
                    m >> (k - e)
                }
            })
            .sum()
    }

    /// `|exact − got|` for the exact value `Σ exact` and the result `Σ got`, in fixed point at
    /// `2^k` with `k` 120 bits below the largest term (truncation: at most a few `2^k`).
    fn discrepancy(exact: &[f64], got: &[f64]) -> (f64, f64) {
        let top = exact
            .iter()
            .chain(got)
            .map(|x| x.abs())
            .fold(0.0, f64::max)
            .log2()
            .ceil() as i32;
        let k = top - 120;
        let d = (fixed(exact, k) - fixed(got, k)) as f64 * 2f64.powi(k);
        let slack = (exact.len() + got.len()) as f64 * 2f64.powi(k);
        (d.abs(), slack)
    }

    /// A double-double from two samples: `hi`, and `lo` a fraction of half an ulp of `hi`.
    fn dd(hi: f64, frac: f64) -> DoubleDouble {
        let frac = frac / 2f64.powi(frac.abs().log2().floor() as i32 + 2);
        DoubleDouble::new(hi, hi * U * frac)
    }

    /// The error bounds of the operations, for double-doubles with random parts (magnitudes
    /// `2^±20`): `x + y` (`3u²`), `x·b` (`2u²`) and `x·y` (`5u²`) against their exact values
    /// in 120-bit fixed point (the products' exact value as the sum of the error-free partial
    /// products; `x.lo·y.lo`, below `u²|xy|/16`, enters rounded, its error below `u³`); the
    /// quotient `x/y` (`15u² + 56u³`) and `√x` (`4u²`) by their residuals `x − q·y`, `x − r²`,
    /// formed exactly in the same fixed point.
    #[test]
    fn operations_within_their_error_bounds() {
        let xs = samples(16000, 11);
        for w in xs.chunks(4) {
            let x = dd(w[0], w[1]);
            let y = dd(w[2], w[3]);
            let s = x + y;
            let (d, slack) = discrepancy(&[x.hi, x.lo, y.hi, y.lo], &[s.hi, s.lo]);
            assert!(d <= 3.0 * U * U * s.hi.abs() + slack, "{x:?} + {y:?}");
            let b = w[2];
            let pb = x * b;
            let (h0, l0) = two_prod(x.hi, b);
            let (h1, l1) = two_prod(x.lo, b);
            let (d, slack) = discrepancy(&[h0, l0, h1, l1], &[pb.hi, pb.lo]);
            assert!(d <= 2.0 * U * U * pb.hi.abs() + slack, "{x:?}·{b}");
            let p = x * y;
            let mut exact = Vec::new();
            for (a, c) in [(x.hi, y.hi), (x.hi, y.lo), (x.lo, y.hi)] {
                let (h, l) = two_prod(a, c);
                exact.extend([h, l]);
            }
            exact.push(x.lo * y.lo);
            let (d, slack) = discrepancy(&exact, &[p.hi, p.lo]);
            assert!(
                d <= 5.0 * U * U * p.hi.abs() + slack + U * U * U * p.hi.abs(),
                "{x:?}·{y:?}"
            );
            // Quotient: x − q·y = 0 up to (15u² + 56u³)|x|, with q·y formed exactly.
            let q = x / y;
            let mut qy = Vec::new();
            for (a, c) in [(q.hi, y.hi), (q.hi, y.lo), (q.lo, y.hi), (q.lo, y.lo)] {
                let (h, l) = two_prod(a, c);
                qy.extend([h, l]);
            }
            let (d, slack) = discrepancy(&[x.hi, x.lo], &qy);
            assert!(
                d <= (15.0 * U * U + 56.0 * U * U * U) * x.hi.abs() + slack,
                "{x:?}/{y:?}"
            );
            // Square root: x − r² = 0 up to 2·4u²·|x| (a relative error δ of r is 2δ of r²).
            let a = DoubleDouble::new(x.hi.abs(), x.lo * x.hi.signum());
            let r = a.sqrt();
            let mut rr = Vec::new();
            for (u, v) in [(r.hi, r.hi), (r.hi, r.lo), (r.lo, r.hi), (r.lo, r.lo)] {
                let (h, l) = two_prod(u, v);
                rr.extend([h, l]);
            }
            let (d, slack) = discrepancy(&[a.hi, a.lo], &rr);
            assert!(d <= 8.0 * U * U * a.hi + slack, "√{a:?}: {d:e}");
        }
    }

    /// Non-finite inputs give a non-finite leading part (the callers' signal to fall back).
    #[test]
    fn non_finite_inputs_propagate() {
        for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
            let b = DoubleDouble::from(bad);
            let one = DoubleDouble::from(1.0);
            assert!(!(one + b).hi.is_finite());
            assert!(!(one * b).hi.is_finite());
            assert!(!(b / one).hi.is_finite());
        }
        assert!(!(DoubleDouble::from(f64::MAX) * 2.0).hi.is_finite());
        assert_eq!(DoubleDouble::from(0.0).sqrt(), DoubleDouble::from(0.0));
    }

    /// `|got − want| / max(|want|, floor)` with `want = (hi, lo)` from mpmath at 60 digits.
    fn rel_err(got: DoubleDouble, want: (f64, f64), floor: f64) -> f64 {
        let d = got - DoubleDouble::new(want.0, want.1);
        d.hi.abs() / want.0.abs().max(floor)
    }

    /// The elementary functions against mpmath (60 digits, rounded to `hi + lo`;
    /// `mpmath.exp, log, sin, cos, atan2, tanh, power` of the exact doubles shown). Derived bound:
    /// the reduced argument and each of the ≤ 15 Taylor terms and ≤ 9 doublings contributes a
    /// few `u²` (the operations' bounds `3u²`–`15u²`), the Newton steps square the double
    /// results' `u`: `64u²` relative; for `sin`/`cos` and `exp` the reduction `x − j·π/2` or
    /// `x − m ln 2` adds the constants' error times `j` or `m`, so the bound is scaled by
    /// `1 + |x|` (absolute for `sin`/`cos`).
    #[test]
    #[allow(clippy::approx_constant)] // 3.14159 is an argument near π, not π.
    fn elementary_functions_against_mpmath() {
        let bound = 64.0 * U * U;
        for (x, want) in [
            (0.5, (1.6487212707001282, -4.731568479435833e-17)),
            (-2.75, (0.06392786120670757, 2.4838752330396898e-18)),
            (10.0, (22026.465794806718, -1.3780134700517372e-12)),
            (1e-08, (1.00000001, 1.1077471008511378e-16)),
            (700.0, (1.0142320547350045e+304, 1.6666571920734673e+287)),
        ] {
            let e = rel_err(DoubleDouble::from(x).exp(), want, 0.0);
            assert!(e <= bound * (1.0 + x.abs()), "exp({x}): {e:e}");
        }
        for (x, want) in [
            (0.5, (-std::f64::consts::LN_2, -2.3190468138462996e-17)),
            (2.75, (1.0116009116784799, 5.030524750578923e-17)),
            (1e10, (23.025850929940457, -3.94399383981999e-16)),
            (1e-300, (-690.7755278982137, -2.3670096176709832e-14)),
        ] {
            let e = rel_err(DoubleDouble::from(x).ln(), want, 0.0);
            assert!(e <= bound, "ln({x}): {e:e}");
        }
        // ln x near 1 is accurate to u² absolute (the Newton correction x e^{−y} − 1 cancels).
        let x = 1.0 + 2f64.powi(-40);
        let want = (9.094947017725146e-13, 2.5077212817525026e-37);
        let e = rel_err(DoubleDouble::from(x).ln(), want, 1.0);
        assert!(e <= bound, "ln({x}): {e:e}");
        for (x, s, c) in [
            (
                0.5,
                (0.479425538604203, -5.103969860556013e-18),
                (0.8775825618903728, -4.2623149864279997e-17),
            ),
            (
                -2.75,
                (-0.38166099205233167, -2.7333934873880806e-17),
                (-0.9243023786324636, 1.7461892611378503e-17),
            ),
            (
                3.14159,
                (2.65358979335273e-06, 1.2360375240852754e-22),
                (-0.9999999999964793, 3.0140007793845264e-17),
            ),
            (
                10.0,
                (-0.5440211108893698, -3.8949898668223557e-17),
                (-0.8390715290764524, -1.4147119988953418e-17),
            ),
            (1e-08, (1e-08, -1.6666666666666668e-25), (1.0, -5e-17)),
            (
                100.0,
                (-0.5063656411097588, -3.050947053792115e-18),
                (0.8623188722876839, 4.334809858136501e-17),
            ),
        ] {
            let (gs, gc) = DoubleDouble::from(x).sin_cos();
            let (es, ec) = (rel_err(gs, s, 1.0), rel_err(gc, c, 1.0));
            assert!(
                es.max(ec) <= bound * (1.0 + x.abs()),
                "sin, cos({x}): {es:e}, {ec:e}"
            );
            // Near π the sine is small: relative to it, the error is the reduction's u²·π.
            if x == 3.14159 {
                assert!(rel_err(gs, s, 0.0) <= bound / s.0, "sin(3.14159)");
            }
        }
        for (y, x, want) in [
            (1.0, 2.0, (0.4636476090008061, 2.2698777452961687e-17)),
            (-3.0, -0.5, (-1.7359450042095235, 1.035362362795107e-17)),
            (1e-08, -1.0, (3.141592643589793, 6.168997032962155e-17)),
            (2.0, 1e-09, (1.5707963262948965, 1.0260252542581371e-16)),
        ] {
            let e = rel_err(
                DoubleDouble::from(y).atan2(DoubleDouble::from(x)),
                want,
                0.0,
            );
            assert!(e <= bound, "atan2({y}, {x}): {e:e}");
        }
        for (x, want) in [
            (0.5, (0.46211715726000974, 2.1916603238260928e-17)),
            (-2.75, (-0.9918597245682077, -4.4082273619711644e-17)),
            (1e-08, (1e-08, -3.3333333333333335e-25)),
            (20.0, (1.0, -8.496708510583178e-18)),
        ] {
            let e = rel_err(DoubleDouble::from(x).tanh(), want, 0.0);
            assert!(e <= bound, "tanh({x}): {e:e}");
        }
        for (x, p, want) in [
            (2.0, -1.5, (0.3535533905932738, -2.4168233283632284e-17)),
            (0.3, 2.5, (0.049295030175464945, 8.954391777489623e-19)),
            (
                7.0,
                0.3333333333333333,
                (1.912931182772389, 9.400309345900771e-17),
            ),
        ] {
            // `e^{p ln x}`: the error of `p ln x` (64u² relative) times |p ln x| ≤ 3.1.
            let e = rel_err(DoubleDouble::from(x).powf(p), want, 0.0);
            assert!(e <= 4.0 * bound, "{x}^{p}: {e:e}");
        }
    }

    /// Identities, a second route: `sin² + cos² = 1`, `sin(π/6) = ½`, `cos(π/3) = ½`,
    /// `exp(ln x) = x`, `ln(exp x) = x`, `exp(a)·exp(b) = exp(a + b)`, `tanh = sinh/cosh`
    /// by the exponentials, over a grid of arguments, each to a few tens of `u²`.
    #[test]
    fn elementary_identities() {
        let bound = 64.0 * U * U;
        let one = DoubleDouble::from(1.0);
        for i in -40..=40 {
            let x = DoubleDouble::from(0.37 * i as f64) + DoubleDouble::from(1e-20 * i as f64);
            let (s, c) = x.sin_cos();
            let d = (s * s + c * c - one).hi.abs();
            assert!(d <= bound, "sin² + cos² − 1 at {x:?}: {d:e}");
            let e = x.exp();
            let back = e.ln();
            assert!(
                (back - x).hi.abs() <= bound * (1.0 + x.hi.abs()),
                "ln exp {x:?}"
            );
            let y = DoubleDouble::from(0.05 + 0.31 * (i + 41) as f64);
            let z = y.ln().exp();
            assert!(
                ((z - y) / y).hi.abs() <= bound * (1.0 + y.hi.ln().abs()),
                "exp ln {y:?}"
            );
            let (a, b) = (x, DoubleDouble::from(0.123_456_789));
            let d = (a.exp() * b.exp() / (a + b).exp() - one).hi.abs();
            assert!(
                d <= bound * (1.0 + x.hi.abs()),
                "exp(a)exp(b)/exp(a + b) at {x:?}: {d:e}"
            );
            let th = (e - one / e) / (e + one / e);
            assert!(
                (x.tanh() - th).hi.abs() <= bound * (1.0 + x.hi.abs()),
                "tanh {x:?}"
            );
        }
        let half = DoubleDouble::from(0.5);
        let (s, _) = (DoubleDouble::PI / 6.0).sin_cos();
        assert!(
            (s - half).hi.abs() <= bound,
            "sin(π/6) − ½ = {:e}",
            (s - half).hi
        );
        let (_, c) = (DoubleDouble::PI / 3.0).sin_cos();
        assert!(
            (c - half).hi.abs() <= bound,
            "cos(π/3) − ½ = {:e}",
            (c - half).hi
        );
        // Special values follow the doubles: NaN in, NaN out; ln 0 = −∞, ln(−1) = NaN,
        // e^{−∞}-like underflow to 0, overflow to ∞.
        assert!(DoubleDouble::from(f64::NAN).exp().hi.is_nan());
        assert!(DoubleDouble::from(f64::NAN).sin_cos().0.hi.is_nan());
        assert!(DoubleDouble::from(f64::INFINITY).sin_cos().1.hi.is_nan());
        assert_eq!(DoubleDouble::from(0.0).ln().hi, f64::NEG_INFINITY);
        assert!(DoubleDouble::from(-1.0).ln().hi.is_nan());
        assert_eq!(DoubleDouble::from(-1e4).exp().hi, 0.0);
        assert_eq!(DoubleDouble::from(1e4).exp().hi, f64::INFINITY);
        assert_eq!(DoubleDouble::from(0.0).powf(2.5).hi, 0.0);
        assert!(DoubleDouble::from(-2.0).powf(0.5).hi.is_nan());
        assert_eq!(DoubleDouble::from(-50.0).tanh().hi, -1.0);
    }
}

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
#[derive(Clone, Copy, Debug, PartialEq)]
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
}

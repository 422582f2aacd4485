//! The recurrences of univariate Taylor arithmetic, one normalised coefficient at a time.
//!
//! For series `u(t) = Σ u_k t^k`, `v(t) = Σ v_k t^k` and a result `w = f(u, v)`, each function
//! returns `w_k` from `u_0 … u_k`, `v_0 … v_k` and the result's own lower coefficients
//! `w_0 … w_{k−1}` (`k ≥ 1`; `w_0 = f(u_0, v_0)` is the caller's):
//!
//! ```math
//! (uv)_k = \sum_{j=0}^{k} u_j v_{k-j},\qquad
//! (u/v)_k = \frac{1}{v_0}\Big(u_k - \sum_{j=1}^{k} v_j w_{k-j}\Big),
//! ```
//!
//! ```math
//! (e^u)_k = \frac1k \sum_{j=1}^{k} j\,u_j w_{k-j},\qquad
//! (\ln u)_k = \frac{1}{u_0}\Big(u_k - \frac1k\sum_{j=1}^{k-1} j\,w_j u_{k-j}\Big),
//! ```
//!
//! ```math
//! (u^a)_k = \frac{1}{k u_0}\sum_{j=1}^{k} \big((a+1)j - k\big) u_j w_{k-j},\qquad
//! (\sqrt u)_k = \frac{1}{2w_0}\Big(u_k - \sum_{j=1}^{k-1} w_j w_{k-j}\Big),
//! ```
//!
//! ```math
//! (\sin u)_k = \frac1k\sum_{j=1}^{k} j\,u_j c_{k-j},\qquad
//! (\cos u)_k = -\frac1k\sum_{j=1}^{k} j\,u_j s_{k-j},
//! ```
//!
//! and for `w = atan2(v, u)` with `r = u² + v²` (from `r w' = u v' − v u'`)
//!
//! ```math
//! w_k = \frac{1}{k r_0}\Big(\sum_{j=1}^{k} j\,(u_{k-j} v_j - v_{k-j} u_j)
//!       - \sum_{j=1}^{k-1} j\,w_j r_{k-j}\Big).
//! ```
//!
//! Each coefficient costs `O(k)`, a series to order `K` costs `O(K²)`. The truncated power
//! series ([`Series`](super::Series)) and the jets of an operation record
//! ([`crate::record`]) both compute their coefficients with these functions.
//!
//! References: R. D. Neidinger, SIAM Review 52 (2010) 545–563, §5; A. Griewank & A. Walther,
//! *Evaluating Derivatives*, 2nd ed., SIAM 2008, Table 13.2; À. Jorba & M. Zou, Exp. Math. 14
//! (2005) 99–117, §2.2.

use super::ball::{Coefficient, Field};

/// `Σ_{i<n} (c + i) a_i b_{n−1−i}` over `n = min(len a, len b)` with `c = 0` and weights dropped
/// when `weighted` is false: the Cauchy sums of every recurrence (no bounds checks in the loop).
#[inline(always)]
fn cauchy<C: Field>(a: &[C], b: &[C], weighted: bool, c: f64) -> C {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let mut s = C::default();
    if weighted {
        let mut w = c;
        for (x, y) in a.iter().zip(b.iter().rev()) {
            s = s.add(x.scale(w).mul(*y));
            w += 1.0;
        }
    } else {
        for (x, y) in a.iter().zip(b.iter().rev()) {
            s = s.add(x.mul(*y));
        }
    }
    s
}

/// `(uv)_k = Σ_{j=0}^{k} u_j v_{k−j}`.
#[inline]
pub fn product<C: Field>(u: &[C], v: &[C], k: usize) -> C {
    cauchy(&u[..=k], &v[..=k], false, 0.0)
}

/// `(u/v)_k = (u_k − Σ_{j=1}^{k} v_j w_{k−j}) / v₀` with `w = u/v`; `u_k` passed as `uk` (0 for
/// the reciprocal `1/v`, `k ≥ 1`).
#[inline]
pub fn quotient<C: Field>(uk: C, v: &[C], w: &[C], k: usize) -> C {
    uk.sub(cauchy(&v[1..=k], &w[..k], false, 0.0)).quo(v[0])
}

/// `(ln u)_k = (u_k − (1/k) Σ_{j=1}^{k−1} j w_j u_{k−j}) / u₀`, `k ≥ 1`.
#[inline]
pub fn ln<C: Field>(u: &[C], w: &[C], k: usize) -> C {
    u[k].sub(cauchy(&w[1..k], &u[1..k], true, 1.0).div(k as f64))
        .quo(u[0])
}

/// `(u^a)_k = (1/(k u₀)) Σ_{j=1}^{k} ((a + 1) j − k) u_j w_{k−j}`, `k ≥ 1`.
#[inline]
pub fn power<C: Field>(u: &[C], a: f64, w: &[C], k: usize) -> C {
    let (uj, wkj) = (&u[1..=k], &w[..k]);
    let s = cauchy(uj, wkj, true, 1.0)
        .scale(a + 1.0)
        .sub(cauchy(uj, wkj, false, 0.0).scale(k as f64));
    s.quo(u[0].scale(k as f64))
}

/// `(√u)_k = (u_k − Σ_{j=1}^{k−1} w_j w_{k−j}) / (2 w₀)`, `k ≥ 1`.
#[inline]
pub fn sqrt<C: Field>(u: &[C], w: &[C], k: usize) -> C {
    u[k].sub(cauchy(&w[1..k], &w[1..k], false, 0.0))
        .quo(w[0].scale(2.0))
}

/// `(∫ w du)_k = (1/k) Σ_{j=1}^{k} j u_j w_{k−j}`, `k ≥ 1`: the `k`-th coefficient of `e^u`
/// with `w = e^u`, of `sin u` with `w = cos u`, of `−cos u` with `w = sin u`, of `sinh u` with
/// `w = cosh u` and of `cosh u` with `w = sinh u` (each is the integral of `w u′`).
#[inline]
pub fn integral_w_du<C: Field>(u: &[C], w: &[C], k: usize) -> C {
    cauchy(&u[1..=k], &w[..k], true, 1.0).div(k as f64)
}

/// `atan2(v, u)_k` with `r = u² + v²` (see the [module docs](self)), `k ≥ 1`.
#[inline]
pub fn atan2<C: Field>(v: &[C], u: &[C], r: &[C], w: &[C], k: usize) -> C {
    let s = cauchy(&v[1..=k], &u[..k], true, 1.0)
        .sub(cauchy(&u[1..=k], &v[..k], true, 1.0))
        .sub(cauchy(&w[1..k], &r[1..k], true, 1.0));
    s.quo(r[0].scale(k as f64))
}

/// `(s_k, c_k) = ((1/k) Σ_{j=1}^{k} j u_j c_{k−j}, (σ/k) Σ_{j=1}^{k} j u_j s_{k−j})`, `k ≥ 1`:
/// with `σ = −1` the pair `s = sin u`, `c = cos u`, with `σ = +1` the pair `s = sinh u`,
/// `c = cosh u` (`s′ = c u′`, `c′ = σ s u′`), in one pass over `j u_j`.
#[inline]
pub fn sin_cos<C: Field>(u: &[C], s: &[C], c: &[C], sigma: f64, k: usize) -> (C, C) {
    let (u, s, c) = (&u[1..=k], &s[..k], &c[..k]);
    let (mut ss, mut cs) = (C::default(), C::default());
    let mut j = 1.0;
    for ((uj, sk), ck) in u.iter().zip(s.iter().rev()).zip(c.iter().rev()) {
        let ju = uj.scale(j);
        ss = ss.add(ju.mul(*ck));
        cs = cs.add(ju.mul(*sk));
        j += 1.0;
    }
    (ss.over_index(k), cs.scale(sigma).over_index(k))
}

/// The series `g = f^p` of a power series with `f₀ = 1`, to the length of `f`, by J. C. P.
/// Miller's recurrence term by term (Knuth, TAOCP vol. 2, §4.7),
/// `g_0 = 1`, `g_k = (1/k) Σ_{j=1}^{k} ((p + 1)j − k) f_j g_{k−j}`, each term formed as `(f_j·w_j)·g_{k−j}` with the weight `w_j = (p + 1)j − k` exact (`p` an
/// integer or half-integer), over any coefficient ring ([`Coefficient`]): with
/// [`Ball`](super::ball::Ball) coefficients every term carries its rounding bound. This is
/// [`power`] for `u₀ = 1` without its split into two Cauchy sums (`(p + 1) Σ j u_j w_{k−j} −
/// k Σ u_j w_{k−j}`), which is faster on doubles but cancels, and would inflate the bounds.
pub(crate) fn unit_power<C: Coefficient>(f: &[C], p: f64) -> Vec<C> {
    debug_assert!(!f.is_empty() && f[0].value() == 1.0);
    let mut g = vec![C::default(); f.len()];
    if let Some(g0) = g.first_mut() {
        *g0 = C::exact(1.0);
    }
    for k in 1..f.len() {
        let mut s = C::default();
        for j in 1..=k {
            let w = (p + 1.0) * j as f64 - k as f64;
            s = s.add(f[j].scale(w).mul(g[k - j]));
        }
        g[k] = s.div(k as f64);
    }
    g
}

#[cfg(test)]
mod tests {
    use super::super::ball::Ball;
    use super::*;

    #[test]
    fn unit_power_gives_the_binomial_series() {
        // Oracle: (1 + x)^{−1/2} = Σ C(−1/2, k) x^k, C(−1/2, k) = (−1)^k (2k)!/(4^k (k!)²),
        // exact in doubles (an integer over 4^k; the Ball values must equal them within the bound).
        let mut f = vec![Ball::default(); 11];
        f[0] = Ball::exact(1.0);
        f[1] = Ball::exact(1.0);
        let g = unit_power(&f, -0.5);
        for (k, gk) in g.iter().enumerate() {
            let binomial = (1..=k as u64).fold(1u64, |b, i| b * (k as u64 + i) / i); // C(2k, k)
            let c = if k % 2 == 0 { 1.0 } else { -1.0 } * binomial as f64 / 4f64.powi(k as i32);
            assert!((gk.v - c).abs() <= gk.e, "k = {k}: {} vs {c}", gk.v);
            // Derived bound: step k adds ε|g_k| for the scaling, the product and the division
            // and ε|s| for each of the k additions (the zero terms f_j, j ≥ 2, included), while
            // the relative bound of g_{k−1} carries over exactly: Σ_{i≤k} (i + 3) ε, plus one ε
            // for the second-order terms.
            let derived = (k * (k + 1) / 2 + 3 * k + 1) as f64 * f64::EPSILON;
            assert!(gk.e <= derived * c.abs(), "k = {k}: bound {:e}", gk.e);
        }
        // Plain doubles: (1 − x)² = 1 − 2x + x², exactly.
        assert_eq!(
            unit_power(&[1.0, -1.0, 0.0, 0.0], 2.0),
            vec![1.0, -2.0, 1.0, 0.0]
        );
    }
}

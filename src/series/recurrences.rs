//! The recurrences of univariate Taylor arithmetic, one normalised coefficient at a time.
//!
//! For series `u(t) = Σ u_k t^k`, `v(t) = Σ v_k t^k` and a result `w = f(u, v)`, each function
//! returns `w_k` from `u_0 … u_k`, `v_0 … v_k` and the result's own lower coefficients
//! `w_0 … w_{k−1}` (`k ≥ 1`; `w_0 = f(u_0, v_0)` is the caller's):
//!
//! $$ (uv)_k = \sum_{j=0}^{k} u_j v_{k-j},\qquad
//!    (u/v)_k = \frac{1}{v_0}\Big(u_k - \sum_{j=1}^{k} v_j w_{k-j}\Big), $$
//!
//! $$ (e^u)_k = \frac1k \sum_{j=1}^{k} j\,u_j w_{k-j},\qquad
//!    (\ln u)_k = \frac{1}{u_0}\Big(u_k - \frac1k\sum_{j=1}^{k-1} j\,w_j u_{k-j}\Big), $$
//!
//! $$ (u^a)_k = \frac{1}{k u_0}\sum_{j=1}^{k} \big((a+1)j - k\big) u_j w_{k-j},\qquad
//!    (\sqrt u)_k = \frac{1}{2w_0}\Big(u_k - \sum_{j=1}^{k-1} w_j w_{k-j}\Big), $$
//!
//! $$ (\sin u)_k = \frac1k\sum_{j=1}^{k} j\,u_j c_{k-j},\qquad
//!    (\cos u)_k = -\frac1k\sum_{j=1}^{k} j\,u_j s_{k-j}, $$
//!
//! and for `w = atan2(v, u)` with `r = u² + v²` (from `r w' = u v' − v u'`)
//!
//! $$ w_k = \frac{1}{k r_0}\Big(\sum_{j=1}^{k} j\,(u_{k-j} v_j - v_{k-j} u_j)
//!          - \sum_{j=1}^{k-1} j\,w_j r_{k-j}\Big). $$
//!
//! Each coefficient costs `O(k)`, a series to order `K` costs `O(K²)`. The truncated power
//! series ([`Series`](super::Series)) and the jets of an operation record
//! ([`crate::record`]) both compute their coefficients with these functions.
//!
//! References: R. D. Neidinger, SIAM Review 52 (2010) 545–563, §5; A. Griewank & A. Walther,
//! *Evaluating Derivatives*, 2nd ed., SIAM 2008, Table 13.2; À. Jorba & M. Zou, Exp. Math. 14
//! (2005) 99–117, §2.2.

/// `(uv)_k = Σ_{j=0}^{k} u_j v_{k−j}`.
#[inline]
pub fn product(u: &[f64], v: &[f64], k: usize) -> f64 {
    let mut s = 0.0;
    for j in 0..=k {
        s += u[j] * v[k - j];
    }
    s
}

/// `(u/v)_k = (u_k − Σ_{j=1}^{k} v_j w_{k−j}) / v₀` with `w = u/v`; `u_k` passed as `uk` (0 for
/// the reciprocal `1/v`, `k ≥ 1`).
#[inline]
pub fn quotient(uk: f64, v: &[f64], w: &[f64], k: usize) -> f64 {
    let mut s = 0.0;
    for j in 1..=k {
        s += v[j] * w[k - j];
    }
    (uk - s) / v[0]
}

/// `(e^u)_k = (1/k) Σ_{j=1}^{k} j u_j w_{k−j}`, `k ≥ 1`.
#[inline]
pub fn exp(u: &[f64], w: &[f64], k: usize) -> f64 {
    let mut s = 0.0;
    for j in 1..=k {
        s += j as f64 * u[j] * w[k - j];
    }
    s / k as f64
}

/// `(ln u)_k = (u_k − (1/k) Σ_{j=1}^{k−1} j w_j u_{k−j}) / u₀`, `k ≥ 1`.
#[inline]
pub fn ln(u: &[f64], w: &[f64], k: usize) -> f64 {
    let mut s = 0.0;
    for j in 1..k {
        s += j as f64 * w[j] * u[k - j];
    }
    (u[k] - s / k as f64) / u[0]
}

/// `(u^a)_k = (1/(k u₀)) Σ_{j=1}^{k} ((a + 1) j − k) u_j w_{k−j}`, `k ≥ 1`.
#[inline]
pub fn power(u: &[f64], a: f64, w: &[f64], k: usize) -> f64 {
    let mut s = 0.0;
    for j in 1..=k {
        s += ((a + 1.0) * j as f64 - k as f64) * u[j] * w[k - j];
    }
    s / (k as f64 * u[0])
}

/// `(√u)_k = (u_k − Σ_{j=1}^{k−1} w_j w_{k−j}) / (2 w₀)`, `k ≥ 1`.
#[inline]
pub fn sqrt(u: &[f64], w: &[f64], k: usize) -> f64 {
    let mut s = 0.0;
    for j in 1..k {
        s += w[j] * w[k - j];
    }
    (u[k] - s) / (2.0 * w[0])
}

/// `(1/k) Σ_{j=1}^{k} j u_j c_{k−j}`: the `k`-th coefficient of `sin u` with `c = cos u`, of
/// `−cos u` with `c = sin u`, of `sinh u` with `c = cosh u` and of `cosh u` with `c = sinh u`;
/// `k ≥ 1`.
#[inline]
pub fn sin_cos(u: &[f64], c: &[f64], k: usize) -> f64 {
    let mut s = 0.0;
    for j in 1..=k {
        s += j as f64 * u[j] * c[k - j];
    }
    s / k as f64
}

/// `atan2(v, u)_k` with `r = u² + v²` (see the [module docs](self)), `k ≥ 1`.
#[inline]
pub fn atan2(v: &[f64], u: &[f64], r: &[f64], w: &[f64], k: usize) -> f64 {
    let mut s = 0.0;
    for j in 1..=k {
        s += j as f64 * (u[k - j] * v[j] - v[k - j] * u[j]);
    }
    for j in 1..k {
        s -= j as f64 * w[j] * r[k - j];
    }
    s / (k as f64 * r[0])
}

//! Elementary functions of a [`Series`] to full degree.
//!
//! With the constant-term split `x = x₀ + x̃` (`x̃` has no constant term, so `x̃^{K+1} = 0`),
//!
//! ```math
//! f(x) = \sum_{k=0}^{K} c_k\, \tilde x^{k},\qquad c_k = \frac{f^{(k)}(x_0)}{k!},
//! ```
//!
//! evaluated by Horner's rule (`K` truncated products). The coefficients `c_k` are the Taylor
//! coefficients of `f` about `x₀`, obtained from the standard recurrences of univariate Taylor
//! arithmetic applied to `u(t) = x₀ + t`: for `w = eᵘ`, `w_k = (1/k) Σ_{j=1}^{k} j u_j w_{k−j}`;
//! for `v = ln u`, `v_k = (u_k − (1/k) Σ_{j=1}^{k−1} j v_j u_{k−j})/u₀`; for `w = u^a`,
//! `w_k = (1/(k u₀)) Σ_{j=1}^{k} ((a + 1) j − k) u_j w_{k−j}`; for `s = sin u, c = cos u`,
//! `s_k = (1/k) Σ j u_j c_{k−j}`, `c_k = −(1/k) Σ j u_j s_{k−j}`; quotients by
//! `q_k = (a_k − Σ_{j=1}^{k} b_j q_{k−j})/b₀`; inverse functions by integrating the series of
//! their derivative (`atan' = 1/(1 + u²)`, `asin' = (1 − u²)^{−1/2}`, …).
//!
//! References: R. D. Neidinger, "Introduction to automatic differentiation and MATLAB
//! object-oriented programming", SIAM Review 52 (2010) 545–563, §5; A. Griewank & A. Walther,
//! *Evaluating Derivatives*, 2nd ed., SIAM 2008, Table 13.2; M. Berz, *Modern Map Methods in
//! Particle Beam Physics*, Academic Press 1999, §2.3.
//!
//! Where `f` is not analytic at `x₀` (√ and ln at 0, 1/x at 0, …) the coefficients come out
//! NaN or infinite; [`Scope::polynomial`](super::Scope::polynomial) keeps them and the expansion
//! entry points report the point.

use super::arena::{with_arena, Operand, Series, CONST, POISON};
use super::number::{linear, product};
use super::recurrences;

/// `f(x) = Σ c_k x̃^k` with `c = taylor(x₀, K)`; `value(x₀)` for a constant `x`.
fn apply(
    x: Series,
    value: impl FnOnce(f64) -> f64,
    taylor: impl FnOnce(f64, usize) -> Vec<f64>,
) -> Series {
    match x.slot {
        CONST => return Series::constant(value(x.re)),
        POISON => return product(x, x),
        _ => {}
    }
    with_arena(|ar| {
        let Some(Operand::Slot(start)) = ar.resolve(&x) else {
            return Series::poison();
        };
        let k = ar.table.degree();
        let c = taylor(x.re, k);
        let len = ar.len();
        // x̃ and the two Horner accumulators in the arena's work array (kept across scopes).
        let mut work = std::mem::take(&mut ar.work);
        work.clear();
        work.resize(3 * len, 0.0);
        let (xt, rest) = work.split_at_mut(len);
        let (mut acc, mut tmp) = rest.split_at_mut(len);
        xt.copy_from_slice(ar.slice(start));
        xt[0] = 0.0;
        acc[0] = c[k];
        // r_j = c_j + x̃ r_{j+1} enters f multiplied by x̃^j: only its degree ≤ K − j is needed.
        for (j, &cj) in c[..k].iter().enumerate().rev() {
            ar.table.mul_to_degree(acc, xt, tmp, &mut ar.scratch, k - j);
            std::mem::swap(&mut acc, &mut tmp);
            acc[0] += cj;
        }
        let s = ar.push(acc);
        ar.work = work;
        s
    })
    .unwrap_or_else(Series::poison)
}

/// The series `u(t) = x₀ + t` to length `K + 1`.
fn ident(x0: f64, k: usize) -> Vec<f64> {
    let mut u = vec![0.0; k + 1];
    u[0] = x0;
    if k >= 1 {
        u[1] = 1.0;
    }
    u
}

fn umul(a: &[f64], b: &[f64]) -> Vec<f64> {
    (0..a.len())
        .map(|k| recurrences::product(a, b, k))
        .collect()
}

fn udiv(a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut q = vec![0.0; a.len()];
    if let Some(q0) = q.first_mut() {
        *q0 = a[0] / b[0];
    }
    for k in 1..a.len() {
        q[k] = recurrences::quotient(a[k], b, &q, k);
    }
    q
}

fn uexp(u: &[f64], w0: f64) -> Vec<f64> {
    let mut w = vec![w0; u.len()];
    for k in 1..u.len() {
        w[k] = recurrences::integral_w_du(u, &w, k);
    }
    w
}

fn uln(u: &[f64], v0: f64) -> Vec<f64> {
    let mut v = vec![v0; u.len()];
    for k in 1..u.len() {
        v[k] = recurrences::ln(u, &v, k);
    }
    v
}

fn upow(u: &[f64], a: f64, w0: f64) -> Vec<f64> {
    let mut w = vec![w0; u.len()];
    for k in 1..u.len() {
        w[k] = recurrences::power(u, a, &w, k);
    }
    w
}

/// `(sin u, cos u)` (`sign = −1`) or `(sinh u, cosh u)` (`sign = +1`).
fn usc(u: &[f64], s0: f64, c0: f64, sign: f64) -> (Vec<f64>, Vec<f64>) {
    let m = u.len();
    let (mut s, mut c) = (vec![s0; m], vec![c0; m]);
    for k in 1..m {
        (s[k], c[k]) = recurrences::sin_cos(u, &s, &c, sign, k);
    }
    (s, c)
}

/// `∫ d` with constant term `c0`.
fn integrate(d: &[f64], c0: f64) -> Vec<f64> {
    let mut f = vec![c0; d.len()];
    for k in 1..d.len() {
        f[k] = d[k - 1] / k as f64;
    }
    f
}

/// `1 + σ·u²` as a series.
fn one_plus(u: &[f64], sigma: f64, one: f64) -> Vec<f64> {
    let mut v: Vec<f64> = umul(u, u).iter().map(|x| sigma * x).collect();
    v[0] += one;
    v
}

pub(crate) fn recip(x: Series) -> Series {
    apply(x, f64::recip, |x0, k| {
        let mut one = vec![0.0; k + 1];
        one[0] = 1.0;
        let mut q = udiv(&one, &ident(x0, k));
        q[0] = x0.recip();
        q
    })
}

pub(crate) fn powi(x: Series, n: i32) -> Series {
    if x.slot == POISON {
        return product(x, x);
    }
    if x.slot == CONST {
        return Series::constant(x.re.powi(n));
    }
    power_by_squaring(x, n, Series::constant(1.0), recip, product)
}

/// `xⁿ` by repeated squaring (`⌊log₂|n|⌋` squarings and at most as many products), of `1/x`
/// for `n < 0`; for every number type whose powers are products.
pub(crate) fn power_by_squaring<T: Copy>(
    x: T,
    n: i32,
    one: T,
    recip: impl Fn(T) -> T,
    mul: impl Fn(T, T) -> T,
) -> T {
    let (mut base, mut e) = if n < 0 {
        (recip(x), (n as i64).unsigned_abs())
    } else {
        (x, n as u64)
    };
    let mut acc = one;
    while e > 0 {
        if e & 1 == 1 {
            acc = mul(acc, base);
        }
        e >>= 1;
        if e > 0 {
            base = mul(base, base);
        }
    }
    acc
}

pub(crate) fn powf(x: Series, a: f64) -> Series {
    if a.is_finite() && a.fract() == 0.0 && a.abs() <= i32::MAX as f64 {
        return powi(x, a as i32);
    }
    apply(
        x,
        |x0| x0.powf(a),
        |x0, k| upow(&ident(x0, k), a, x0.powf(a)),
    )
}

pub(crate) fn sqrt(x: Series) -> Series {
    apply(x, f64::sqrt, |x0, k| upow(&ident(x0, k), 0.5, x0.sqrt()))
}

pub(crate) fn cbrt(x: Series) -> Series {
    apply(x, f64::cbrt, |x0, k| {
        upow(&ident(x0, k), 1.0 / 3.0, x0.cbrt())
    })
}

pub(crate) fn exp(x: Series) -> Series {
    apply(x, f64::exp, |x0, k| uexp(&ident(x0, k), x0.exp()))
}

pub(crate) fn exp2(x: Series) -> Series {
    let ln2 = std::f64::consts::LN_2;
    apply(x, f64::exp2, |x0, k| {
        let u: Vec<f64> = ident(x0, k).iter().map(|v| v * ln2).collect();
        uexp(&u, x0.exp2())
    })
}

pub(crate) fn exp_m1(x: Series) -> Series {
    apply(x, f64::exp_m1, |x0, k| {
        let mut w = uexp(&ident(x0, k), x0.exp());
        w[0] = x0.exp_m1();
        w
    })
}

pub(crate) fn ln(x: Series) -> Series {
    apply(x, f64::ln, |x0, k| uln(&ident(x0, k), x0.ln()))
}

pub(crate) fn ln_1p(x: Series) -> Series {
    apply(x, f64::ln_1p, |x0, k| {
        let mut u = ident(x0, k);
        u[0] = 1.0 + x0;
        uln(&u, x0.ln_1p())
    })
}

pub(crate) fn sin(x: Series) -> Series {
    apply(x, f64::sin, |x0, k| {
        usc(&ident(x0, k), x0.sin(), x0.cos(), -1.0).0
    })
}

pub(crate) fn cos(x: Series) -> Series {
    apply(x, f64::cos, |x0, k| {
        usc(&ident(x0, k), x0.sin(), x0.cos(), -1.0).1
    })
}

pub(crate) fn sin_cos(x: Series) -> (Series, Series) {
    (sin(x), cos(x))
}

pub(crate) fn sinh(x: Series) -> Series {
    apply(x, f64::sinh, |x0, k| {
        usc(&ident(x0, k), x0.sinh(), x0.cosh(), 1.0).0
    })
}

pub(crate) fn cosh(x: Series) -> Series {
    apply(x, f64::cosh, |x0, k| {
        usc(&ident(x0, k), x0.sinh(), x0.cosh(), 1.0).1
    })
}

pub(crate) fn tan(x: Series) -> Series {
    apply(x, f64::tan, |x0, k| {
        let (s, c) = usc(&ident(x0, k), x0.sin(), x0.cos(), -1.0);
        let mut t = udiv(&s, &c);
        t[0] = x0.tan();
        t
    })
}

pub(crate) fn tanh(x: Series) -> Series {
    apply(x, f64::tanh, |x0, k| {
        let (s, c) = usc(&ident(x0, k), x0.sinh(), x0.cosh(), 1.0);
        let mut t = udiv(&s, &c);
        t[0] = x0.tanh();
        t
    })
}

pub(crate) fn atan(x: Series) -> Series {
    apply(x, f64::atan, |x0, k| {
        let u = ident(x0, k);
        let mut one = vec![0.0; k + 1];
        one[0] = 1.0;
        integrate(&udiv(&one, &one_plus(&u, 1.0, 1.0)), x0.atan())
    })
}

pub(crate) fn atanh(x: Series) -> Series {
    apply(x, f64::atanh, |x0, k| {
        let u = ident(x0, k);
        let mut one = vec![0.0; k + 1];
        one[0] = 1.0;
        integrate(&udiv(&one, &one_plus(&u, -1.0, 1.0)), x0.atanh())
    })
}

/// `∫ (σu² + one)^{−1/2}` with constant term `c0`.
fn inverse_root(x0: f64, k: usize, sigma: f64, one: f64, sign: f64, c0: f64) -> Vec<f64> {
    let b = one_plus(&ident(x0, k), sigma, one);
    let d: Vec<f64> = upow(&b, -0.5, b[0].powf(-0.5))
        .iter()
        .map(|v| sign * v)
        .collect();
    integrate(&d, c0)
}

pub(crate) fn asin(x: Series) -> Series {
    apply(x, f64::asin, |x0, k| {
        inverse_root(x0, k, -1.0, 1.0, 1.0, x0.asin())
    })
}

pub(crate) fn acos(x: Series) -> Series {
    apply(x, f64::acos, |x0, k| {
        inverse_root(x0, k, -1.0, 1.0, -1.0, x0.acos())
    })
}

pub(crate) fn asinh(x: Series) -> Series {
    apply(x, f64::asinh, |x0, k| {
        inverse_root(x0, k, 1.0, 1.0, 1.0, x0.asinh())
    })
}

pub(crate) fn acosh(x: Series) -> Series {
    apply(x, f64::acosh, |x0, k| {
        inverse_root(x0, k, 1.0, -1.0, 1.0, x0.acosh())
    })
}

/// `atan2(y, x)`: the series of `atan(y/x)` (or `−atan(x/y)` where `|y₀| > |x₀|`) with the
/// constant term replaced by `atan2(y₀, x₀)`; the two differ by a constant near `(x₀, y₀) ≠ 0`.
pub(crate) fn atan2(y: Series, x: Series) -> Series {
    if y.slot == CONST && x.slot == CONST {
        return Series::constant(y.re.atan2(x.re));
    }
    let s = if x.re.abs() >= y.re.abs() {
        atan(y / x)
    } else {
        -atan(x / y)
    };
    linear(s, 1.0, Series::constant(y.re.atan2(x.re) - s.re), 1.0)
}

/// Spherical Bessel function `j_n`, `n ≤ 2`: at `x₀ = 0` its power series
/// `j_n(t) = Σ_m (−1)^m t^{2m+n} / (2^m m! (2m + 2n + 1)!!)`, elsewhere
/// `j₀ = sin u/u`, `j₁ = (j₀ − cos u)/u`, `j₂ = 3j₁/u − j₀`.
pub(crate) fn sph_j(x: Series, n: usize) -> Series {
    let real = move |x0: f64| -> f64 {
        match n {
            0 => num_dual::DualNum::sph_j0(&x0),
            1 => num_dual::DualNum::sph_j1(&x0),
            _ => num_dual::DualNum::sph_j2(&x0),
        }
    };
    apply(x, real, move |x0, k| {
        if x0 == 0.0 {
            let mut c = vec![0.0; k + 1];
            let mut m = 0usize;
            while 2 * m + n <= k {
                let mut den = 1.0;
                for i in 1..=m {
                    den *= 2.0 * i as f64;
                }
                let mut df = 1.0;
                let mut j = 2 * m + 2 * n + 1;
                while j > 1 {
                    df *= j as f64;
                    j -= 2;
                }
                c[2 * m + n] = if m & 1 == 0 { 1.0 } else { -1.0 } / (den * df);
                m += 1;
            }
            return c;
        }
        let u = ident(x0, k);
        let (s, c) = usc(&u, x0.sin(), x0.cos(), -1.0);
        let j0 = udiv(&s, &u);
        let j1 = udiv(
            &j0.iter().zip(&c).map(|(a, b)| a - b).collect::<Vec<_>>(),
            &u,
        );
        let mut out = match n {
            0 => j0,
            1 => j1,
            _ => {
                let t = udiv(&j1, &u);
                t.iter().zip(&j0).map(|(a, b)| 3.0 * a - b).collect()
            }
        };
        out[0] = real(x0);
        out
    })
}

//! Lindstedt–Poincaré expansion of a conservative oscillator with an odd restoring force — the
//! independent cross-check of the frequency–amplitude series of the Lie normal form
//! ([`super::normal_form`]).
//!
//! # The method
//!
//! For `θ̈ + n² g(θ) = 0` with `g(θ) = θ + Σ_{j≥1} g_j θ^{2j+1}` (the pendulum: `g = sin`,
//! `g_j = (−1)^j/(2j+1)!`) and amplitude `a` (`θ(0) = a`, `θ̇(0) = 0`), strain time as `s = ω t` and
//! write `θ = a x(s)`, `ε = a²`:
//!
//! ```text
//! (ω/n)² x'' + x + Σ_{j≥1} g_j ε^j x^{2j+1} = 0,
//! x = Σ_k ε^k x_k(s),   (ω/n)² = Σ_k σ_k ε^k,   σ₀ = 1,   x₀ = cos s,
//! x_k(0) = 0,  x_k'(0) = 0   (k ≥ 1; the amplitude is carried by x₀ alone).
//! ```
//!
//! Order `ε^k` gives `x_k'' + x_k = r_k(s)`, with `r_k` a cosine polynomial in odd harmonics built
//! from `x_0 … x_{k−1}` and `σ_1 … σ_{k−1}` plus the unknown `σ_k cos s`. Removing the secular
//! (resonant `cos s`) term fixes `σ_k`; the particular solution is `Σ_{m≠1} r_{k,m} cos(ms)/(1 − m²)`,
//! plus the homogeneous `C cos s` that restores `x_k(0) = 0` (Nayfeh 1973, ch. 4). The period
//! ratio is then `τ/(2π/n) = n/ω = (Σ σ_k ε^k)^{−1/2}`, re-expanded in `ε = a²`.
//!
//! Everything is exact-structure `f64` arithmetic on cosine polynomials: no Poisson brackets, no
//! action–angle variables, no generating function — so agreement with the normal form is a genuine
//! cross-check. Cost is `O(N⁴)` flops for order `N` (products of cosine polynomials of length
//! `O(N)` inside an `O(N²)` Cauchy product); order 12 takes well under a millisecond.
//!
//! # References
//! * A. H. Nayfeh, *Perturbation Methods*, Wiley 1973, ch. 4 (the Lindstedt–Poincaré method).
//! * S. Ferraz-Mello, *Canonical Perturbation Theories*, Springer 2007, ch. 2.

use crate::error::{finite, Error, Result};

/// Highest order accepted by [`lindstedt_odd_force`] (and [`lindstedt_pendulum`]). The coefficients
/// of the pendulum's series fall like `π^{−2k}`, so beyond order ~150 they underflow to subnormals
/// long before this cap; the cap only bounds the `O(N⁴)` work.
pub const MAX_LINDSTEDT_ORDER: usize = 64;

/// Result of a Lindstedt–Poincaré expansion in `ε = a²` (unit `n`: all series are dimensionless).
#[derive(Clone, Debug, PartialEq)]
pub struct LindstedtSeries {
    /// `σ_k`: `(ω/n)² = Σ_k σ_k a^{2k}`, `k = 0 … N`.
    pub frequency_squared: Vec<f64>,
    /// `ω/n = Σ_k f_k a^{2k}`, `k = 0 … N`.
    pub frequency: Vec<f64>,
    /// `τ/(2π/n) = n/ω = Σ_k c_k a^{2k}`, `k = 0 … N`.
    pub period_ratio: Vec<f64>,
    /// `x_k(s) = Σ_m solution[k][m] cos(m s)` (index `m` the harmonic; only odd `m` are nonzero);
    /// `θ(t) = a Σ_k a^{2k} x_k(ω t)`.
    pub solution: Vec<Vec<f64>>,
}

impl LindstedtSeries {
    /// Period ratio `τ/(2π/n)` truncated after `a^{2N}` (`N` = the order of the expansion).
    ///
    /// The truncated series is evaluated as it stands: no convergence check (the radius depends
    /// on the restoring force; for the pendulum it is the separatrix `a = π`, and
    /// [`PendulumNormalForm::period_ratio`](super::normal_form::PendulumNormalForm::period_ratio)
    /// is the checked API with its warning).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite amplitude.
    pub fn period_ratio_at(&self, amplitude: f64) -> crate::Result<f64> {
        let a = crate::error::finite("amplitude a", amplitude)?;
        Ok(horner(&self.period_ratio, a * a))
    }

    /// The Lindstedt solution `θ(t)` truncated at the order of the expansion, for amplitude `a`
    /// and small-oscillation frequency `n` (the phase `s = ω t` uses the truncated `ω`). No
    /// convergence check, as [`Self::period_ratio_at`].
    ///
    /// # Errors
    /// [`Error::NonFinite`] for non-finite arguments.
    pub fn theta(&self, n: f64, amplitude: f64, t: f64) -> crate::Result<f64> {
        crate::error::finite("n", n)?;
        crate::error::finite("time t", t)?;
        let eps = crate::error::finite("amplitude a", amplitude)?.powi(2);
        let omega = n * horner(&self.frequency, eps);
        let s = omega * t;
        let mut sum = 0.0;
        let mut power = 1.0;
        for xk in &self.solution {
            let mut v = 0.0;
            for (m, c) in xk.iter().enumerate() {
                if *c != 0.0 {
                    v += c * (m as f64 * s).cos();
                }
            }
            sum += power * v;
            power *= eps;
        }
        Ok(amplitude * sum)
    }
}

/// `Σ c_k x^k`.
fn horner(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, ck| acc * x + ck)
}

/// `f^p` of a power series with `f₀ = 1`, truncated to `f.len()` terms (J. C. P. Miller's
/// recurrence, Knuth TAOCP vol. 2, §4.7: `g₀ = 1`, `k g_k = Σ_{j=1}^{k} ((p+1) j − k) f_j g_{k−j}`).
pub(crate) fn series_pow(f: &[f64], p: f64) -> Vec<f64> {
    debug_assert!(!f.is_empty() && f[0] == 1.0);
    let mut g = vec![0.0; f.len()];
    g[0] = 1.0;
    for k in 1..f.len() {
        let mut s = 0.0;
        for j in 1..=k {
            s += ((p + 1.0) * j as f64 - k as f64) * f[j] * g[k - j];
        }
        g[k] = s / k as f64;
    }
    g
}

/// Product of two cosine polynomials `Σ a_m cos ms · Σ b_l cos ls`
/// (`cos ms cos ls = ½[cos(m+l)s + cos(m−l)s]`).
fn cos_mul(a: &[f64], b: &[f64]) -> Vec<f64> {
    if a.is_empty() || b.is_empty() {
        return Vec::new();
    }
    let mut out = vec![0.0; a.len() + b.len() - 1];
    for (m, am) in a.iter().enumerate() {
        if *am == 0.0 {
            continue;
        }
        for (l, bl) in b.iter().enumerate() {
            if *bl == 0.0 {
                continue;
            }
            let h = 0.5 * am * bl;
            out[m + l] += h;
            out[m.abs_diff(l)] += h;
        }
    }
    out
}

/// `a += s·b` for cosine polynomials.
fn cos_axpy(a: &mut Vec<f64>, s: f64, b: &[f64]) {
    if a.len() < b.len() {
        a.resize(b.len(), 0.0);
    }
    for (ai, bi) in a.iter_mut().zip(b) {
        *ai += s * bi;
    }
}

/// Lindstedt–Poincaré series to order `N` in `ε = a²` for `θ̈ + n² (θ + Σ_j g_j θ^{2j+1}) = 0`;
/// `odd_coefficients[j−1] = g_j` (coefficients beyond `N` cannot contribute and are ignored).
///
/// # Errors
/// [`Error::OutOfDomain`] for `order ∉ 1..=MAX_LINDSTEDT_ORDER`; [`Error::NonFinite`] for a
/// non-finite coefficient.
pub fn lindstedt_odd_force(odd_coefficients: &[f64], order: usize) -> Result<LindstedtSeries> {
    if !(1..=MAX_LINDSTEDT_ORDER).contains(&order) {
        return Err(Error::out_of_domain(
            "Lindstedt order N",
            order as f64,
            format!("{{1, …, {MAX_LINDSTEDT_ORDER}}}"),
        ));
    }
    for (j, g) in odd_coefficients.iter().enumerate() {
        finite(format!("odd force coefficient g_{}", j + 1), *g)?;
    }
    let big_n = order;
    let g = |j: usize| odd_coefficients.get(j - 1).copied().unwrap_or(0.0);
    // x[k]: cosine polynomial of x_k. pows[p][k]: ε^k coefficient of x^p (p odd ≥ 3), kept up to
    // the order reached so far.
    let mut x: Vec<Vec<f64>> = vec![vec![0.0, 1.0]];
    let mut sigma = vec![1.0];
    // pow_series[i] = ε-series of x^(2i+1), i = 0 … ; each entry a Vec over k of cosine polys.
    let max_power = big_n; // x^(2j+1) with j ≤ N
    let mut pow_series: Vec<Vec<Vec<f64>>> = vec![vec![x[0].clone()]];
    for i in 1..=max_power {
        let prev = pow_series[i - 1][0].clone();
        let sq = cos_mul(&x[0], &x[0]);
        pow_series.push(vec![cos_mul(&prev, &sq)]);
    }
    for k in 1..=big_n {
        // r_k = −Σ_{j=1}^{k−1} σ_j x_{k−j}'' − Σ_{j=1}^{k} g_j [x^{2j+1}]_{k−j}  − σ_k x_0''.
        // With x_m'' = −Σ m² c cos: −σ_j x'' = σ_j Σ m² c cos ms.
        let mut r: Vec<f64> = Vec::new();
        for (j, sj) in sigma.iter().enumerate().take(k).skip(1) {
            let d2: Vec<f64> = x[k - j]
                .iter()
                .enumerate()
                .map(|(m, c)| (m * m) as f64 * c)
                .collect();
            cos_axpy(&mut r, *sj, &d2);
        }
        for j in 1..=k {
            let gj = g(j);
            if gj != 0.0 {
                cos_axpy(&mut r, -gj, &pow_series[j][k - j]);
            }
        }
        // The unknown σ_k enters as −σ_k x_0'' = +σ_k cos s; the cos s coefficient must vanish.
        let r1 = r.get(1).copied().unwrap_or(0.0);
        let sk = -r1;
        if r.len() < 2 {
            r.resize(2, 0.0);
        }
        r[1] = 0.0;
        sigma.push(sk);
        // Particular solution plus C cos s with x_k(0) = 0.
        let mut xk = vec![0.0; r.len()];
        let mut sum = 0.0;
        for (m, rm) in r.iter().enumerate() {
            if m != 1 && *rm != 0.0 {
                let c = rm / (1.0 - (m * m) as f64);
                xk[m] = c;
                sum += c;
            }
        }
        xk[1] = -sum;
        x.push(xk);
        // Extend the odd powers to order k: [x^{2p+1}]_k = Σ_i [x^{2p−1}]_i [x²]_{k−i}.
        // x² series up to order k.
        let mut sq: Vec<Vec<f64>> = Vec::with_capacity(k + 1);
        for kk in 0..=k {
            let mut s: Vec<f64> = Vec::new();
            for i in 0..=kk {
                cos_axpy(&mut s, 1.0, &cos_mul(&x[i], &x[kk - i]));
            }
            sq.push(s);
        }
        pow_series[0].push(x[k].clone());
        for p in 1..=max_power {
            if p + k > big_n {
                // [x^{2p+1}]_k enters only at order k + p, so it is needed only for p + k ≤ N.
                break;
            }
            let mut s: Vec<f64> = Vec::new();
            for i in 0..=k {
                cos_axpy(&mut s, 1.0, &cos_mul(&pow_series[p - 1][i], &sq[k - i]));
            }
            pow_series[p].push(s);
        }
    }
    let frequency = series_pow(&sigma, 0.5);
    let period_ratio = series_pow(&sigma, -0.5);
    Ok(LindstedtSeries {
        frequency_squared: sigma,
        frequency,
        period_ratio,
        solution: x,
    })
}

/// Lindstedt–Poincaré series of the pendulum `θ̈ + n² sin θ = 0` to order `N` in `a²`
/// (`g_j = (−1)^j/(2j+1)!`). Leading terms (checked against the series of `2K(k)/π` in
/// `tests/normal_form.rs`): `ω/n = 1 − a²/16 + a⁴/3072 + …`,
/// `τ/(2π/n) = 1 + a²/16 + 11 a⁴/3072 + …`.
///
/// ```
/// use hamilton_jacobi::perturbation::lindstedt::lindstedt_pendulum;
/// let s = lindstedt_pendulum(2).unwrap();
/// assert!((s.period_ratio[1] - 1.0 / 16.0).abs() < 1e-16);
/// assert!((s.period_ratio[2] - 11.0 / 3072.0).abs() < 1e-17);
/// ```
///
/// # Errors
/// As [`lindstedt_odd_force`].
pub fn lindstedt_pendulum(order: usize) -> Result<LindstedtSeries> {
    let mut g = Vec::with_capacity(order);
    let mut fact = 1.0_f64; // (2j+1)!
    for j in 1..=order {
        fact *= ((2 * j) * (2 * j + 1)) as f64;
        g.push(if j % 2 == 1 { -1.0 } else { 1.0 } / fact);
    }
    lindstedt_odd_force(&g, order)
}

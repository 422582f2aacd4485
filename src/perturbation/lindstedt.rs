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

use crate::error::{finite, positive, Error, Result};
use crate::series::ball::{Ball, Coefficient, ROUND};
use crate::series::poisson::{cosine_axpy as cos_axpy, cosine_product as cos_mul};
use crate::series::recurrences::unit_power;

/// Highest order accepted by [`lindstedt_odd_force`] (and [`lindstedt_pendulum`]). The coefficients
/// of the pendulum's series fall like `π^{−2k}`, so beyond order ~150 they underflow to subnormals
/// long before this cap; the cap only bounds the `O(N⁴)` work (order 64, with its error bounds,
/// takes about 0.4 s).
pub const MAX_LINDSTEDT_ORDER: usize = 64;

/// Phase-rounding limit of [`LindstedtSeries::theta`]: the phase `m s = m ω t` of the highest
/// harmonic `m` is a double with rounding error up to `ε m |s|`; beyond this many radians the
/// value is refused (the rounding alone would move `θ` by more than `1e−6` of its amplitude).
pub const MAX_PHASE_ROUNDING: f64 = 1e-6;

/// Result of a Lindstedt–Poincaré expansion in `ε = a²` (unit `n`: all series are dimensionless).
///
/// Every coefficient comes with an absolute error bound from first-order running error analysis
/// (Higham, *Accuracy and Stability of Numerical Algorithms*, 2nd ed. 2002, §3.3): each value `v`
/// of the recursion carries a bound `e` on its accumulated rounding error, propagated as
/// `e(x ± y) = e_x + e_y + ε|x ± y|`, `e(x y) = |x| e_y + |y| e_x + e_x e_y + ε|x y|`, and
/// `e(x/d) = e_x/|d| + ε|x/d|` for the exact integer divisors of the recursion. The increment `ε`
/// per operation is twice the unit roundoff, which covers the second-order terms first-order
/// analysis neglects. The bound therefore grows with the recursion exactly as its cancellation
/// does (`e ≈ ε·D·Σ|terms|` for a chain of `D` operations) and is checked against exact rationals
/// at every order up to [`MAX_LINDSTEDT_ORDER`] in `tests/normal_form.rs`. It is a worst case:
/// for the pendulum it passes 1e−10 relative near `k = 10` and 1 near `k = 33`, while the actual
/// errors stay below 1e−14 at every `k ≤ 64` (the signed errors fed back through the recursion
/// partly cancel; their absolute values, which the bound adds, do not).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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
    /// Absolute rounding-error bounds of [`Self::frequency_squared`].
    pub frequency_squared_error: Vec<f64>,
    /// Absolute rounding-error bounds of [`Self::frequency`].
    pub frequency_error: Vec<f64>,
    /// Absolute rounding-error bounds of [`Self::period_ratio`].
    pub period_ratio_error: Vec<f64>,
}

impl LindstedtSeries {
    /// Period ratio `τ/(2π/n)` truncated after `a^{2N}` (`N` = the order of the expansion).
    ///
    /// The truncated series is evaluated as it stands where its terms decrease (the radius depends
    /// on the restoring force; for the pendulum it is the separatrix `a = π`, and
    /// [`PendulumNormalForm::period_ratio`](super::normal_form::PendulumNormalForm::period_ratio)
    /// is the checked API with its warning). Where the terms `|c_k| a^{2k}` of the tail grow
    /// (estimated ratio of successive terms ≥ 1, see [`tail_ratio`]) the sum approximates
    /// nothing and is refused.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite amplitude; [`Error::NotConverged`] where the terms do
    /// not decrease (or the sum overflows).
    pub fn period_ratio_at(&self, amplitude: f64) -> Result<f64> {
        let a = finite("amplitude a", amplitude)?;
        let x = a * a;
        check_terms("Lindstedt period-ratio series", &self.period_ratio, x, a)?;
        let v = horner(&self.period_ratio, x);
        series_value("Lindstedt period-ratio series", v, &self.period_ratio, a)
    }

    /// The Lindstedt solution `θ(t)` truncated at the order of the expansion, for amplitude `a`
    /// and small-oscillation frequency `n` (the phase `s = ω t` uses the truncated `ω`).
    /// Refused, as [`Self::period_ratio_at`], where the terms of the frequency series or of
    /// `Σ_k a^{2k} x_k` do not decrease, and where the phase `m ω t` of the highest harmonic `m`
    /// carries a rounding error above [`MAX_PHASE_ROUNDING`] (huge `ω t`: the phase is lost).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for non-finite arguments; [`Error::NotConverged`] as above;
    /// [`Error::OutOfDomain`] for `n ≤ 0` (the small-oscillation frequency is positive) and for
    /// a lost phase.
    pub fn theta(&self, n: f64, amplitude: f64, t: f64) -> Result<f64> {
        let n = positive("small-oscillation frequency n", n)?;
        let t = finite("time t", t)?;
        let a = finite("amplitude a", amplitude)?;
        let eps = a * a;
        check_terms("Lindstedt frequency series", &self.frequency, eps, a)?;
        let sizes: Vec<f64> = self
            .solution
            .iter()
            .map(|xk| xk.iter().map(|c| c.abs()).sum())
            .collect();
        check_terms("Lindstedt solution series Σ a^{2k} x_k", &sizes, eps, a)?;
        let omega = n * horner(&self.frequency, eps);
        let s = omega * t;
        let harmonics = self.solution.iter().map(Vec::len).max().unwrap_or(1).max(1) - 1;
        let phase_error = f64::EPSILON * harmonics as f64 * s.abs();
        if phase_error.is_nan() || phase_error > MAX_PHASE_ROUNDING {
            return Err(Error::out_of_domain(
                "phase ω t",
                s,
                format!(
                    "|ω t| ≤ {:e}: the phase {harmonics}·ω t of the highest harmonic carries a \
                     rounding error ε·{harmonics}·|ω t| = {phase_error:e} above \
                     MAX_PHASE_ROUNDING = {MAX_PHASE_ROUNDING:e} (phase lost)",
                    MAX_PHASE_ROUNDING / (f64::EPSILON * harmonics.max(1) as f64)
                ),
            ));
        }
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
        let value = amplitude * sum;
        if value.is_finite() {
            Ok(value)
        } else {
            Err(Error::NotConverged {
                what: format!("Lindstedt solution θ(t) at a = {a:e}, t = {t:e} (overflow)"),
                iterations: self.solution.len().saturating_sub(1),
                residual: value,
            })
        }
    }
}

/// Estimated ratio `q` of successive terms of `Σ c_k x^k`, from the tail of the truncated series:
/// the largest of the per-step ratios `(|c_j x^j| / |c_i x^i|)^{1/(j−i)}` between consecutive
/// nonzero terms over the last half of those steps (at least one). For a series with radius `R`
/// the ratios tend to `|x|/R`; `q < 1` means the terms kept are decreasing. Computed in
/// logarithms, so huge `x` gives a huge (or infinite) `q` instead of overflowing; `0` when fewer
/// than two terms are nonzero or `x = 0`; `∞` for a non-finite `x` (with two nonzero terms).
pub fn tail_ratio(c: &[f64], x: f64) -> f64 {
    if x == 0.0 {
        return 0.0;
    }
    let lx = x.abs().ln();
    let logs: Vec<(usize, f64)> = c
        .iter()
        .enumerate()
        .filter(|(_, ck)| **ck != 0.0)
        .map(|(k, ck)| (k, ck.abs().ln() + k as f64 * lx))
        .collect();
    if logs.len() < 2 {
        return 0.0;
    }
    if !x.is_finite() {
        return f64::INFINITY;
    }
    let steps: Vec<f64> = logs
        .windows(2)
        .map(|w| ((w[1].1 - w[0].1) / (w[1].0 - w[0].0) as f64).exp())
        .collect();
    let tail = steps.len().div_ceil(2);
    steps[steps.len() - tail..]
        .iter()
        .copied()
        .fold(0.0, f64::max)
}

/// Refuse the truncated series `Σ c_k x^k` where its terms do not decrease.
fn check_terms(what: &str, c: &[f64], x: f64, a: f64) -> Result<()> {
    let q = tail_ratio(c, x);
    if q < 1.0 {
        Ok(())
    } else {
        let last = c.len().saturating_sub(1);
        Err(Error::NotConverged {
            what: format!(
                "{what} at amplitude a = {a:e} (its terms grow by a factor {q:e} per order: \
                 outside the radius of convergence)"
            ),
            iterations: last,
            residual: c
                .last()
                .map_or(0.0, |cl| cl.abs() * x.abs().powi(last as i32)),
        })
    }
}

/// The value of a truncated series, refused if it overflowed.
fn series_value(what: &str, v: f64, c: &[f64], a: f64) -> Result<f64> {
    if v.is_finite() {
        Ok(v)
    } else {
        let last = c.len().saturating_sub(1);
        Err(Error::NotConverged {
            what: format!("{what} at amplitude a = {a:e} (the sum overflows)"),
            iterations: last,
            residual: v,
        })
    }
}

/// `Σ c_k x^k`.
fn horner(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, ck| acc * x + ck)
}

/// Refuse an order outside `1..=MAX_LINDSTEDT_ORDER` (before anything is allocated).
fn check_order(order: usize) -> Result<usize> {
    if (1..=MAX_LINDSTEDT_ORDER).contains(&order) {
        Ok(order)
    } else {
        Err(Error::out_of_domain(
            "Lindstedt order N",
            order as f64,
            format!(
                "{{1, …, {MAX_LINDSTEDT_ORDER}}} (MAX_LINDSTEDT_ORDER = {MAX_LINDSTEDT_ORDER}, \
                 the bound on the O(N⁴) work)"
            ),
        ))
    }
}

/// Lindstedt–Poincaré series to order `N` in `ε = a²` for `θ̈ + n² (θ + Σ_j g_j θ^{2j+1}) = 0`;
/// `odd_coefficients[j−1] = g_j` (taken as exact; coefficients beyond `N` cannot contribute and
/// are ignored).
///
/// # Errors
/// [`Error::OutOfDomain`] for `order ∉ 1..=MAX_LINDSTEDT_ORDER` (checked first);
/// [`Error::NonFinite`] for a non-finite coefficient, or for coefficients so large that the
/// series overflows.
pub fn lindstedt_odd_force(odd_coefficients: &[f64], order: usize) -> Result<LindstedtSeries> {
    let order = check_order(order)?;
    let g: Vec<Ball> = odd_coefficients
        .iter()
        .take(order)
        .enumerate()
        .map(|(j, g)| finite(format!("odd force coefficient g_{}", j + 1), *g).map(Ball::exact))
        .collect::<Result<_>>()?;
    lindstedt_balls(&g, order)
}

/// The recursion of [`lindstedt_odd_force`] on coefficients with error bounds; `order` checked.
fn lindstedt_balls(odd_coefficients: &[Ball], order: usize) -> Result<LindstedtSeries> {
    let big_n = order;
    let g = |j: usize| odd_coefficients.get(j - 1).copied().unwrap_or_default();
    let one = Ball::exact(1.0);
    // x[k]: cosine polynomial of x_k. pows[p][k]: ε^k coefficient of x^p (p odd ≥ 3), kept up to
    // the order reached so far.
    let mut x: Vec<Vec<Ball>> = vec![vec![Ball::default(), one]];
    let mut sigma = vec![one];
    // pow_series[i] = ε-series of x^(2i+1), i = 0 … ; each entry a Vec over k of cosine polys.
    let max_power = big_n; // x^(2j+1) with j ≤ N
    let mut pow_series: Vec<Vec<Vec<Ball>>> = vec![vec![x[0].clone()]];
    for i in 1..=max_power {
        let prev = pow_series[i - 1][0].clone();
        let sq = cos_mul(&x[0], &x[0]);
        pow_series.push(vec![cos_mul(&prev, &sq)]);
    }
    for k in 1..=big_n {
        // r_k = −Σ_{j=1}^{k−1} σ_j x_{k−j}'' − Σ_{j=1}^{k} g_j [x^{2j+1}]_{k−j}  − σ_k x_0''.
        // With x_m'' = −Σ m² c cos: −σ_j x'' = σ_j Σ m² c cos ms.
        let mut r: Vec<Ball> = Vec::new();
        for (j, sj) in sigma.iter().enumerate().take(k).skip(1) {
            let d2: Vec<Ball> = x[k - j]
                .iter()
                .enumerate()
                .map(|(m, c)| c.scale((m * m) as f64))
                .collect();
            cos_axpy(&mut r, *sj, &d2);
        }
        for j in 1..=k {
            let gj = g(j);
            if !gj.is_zero() {
                cos_axpy(&mut r, gj.neg(), &pow_series[j][k - j]);
            }
        }
        // The unknown σ_k enters as −σ_k x_0'' = +σ_k cos s; the cos s coefficient must vanish.
        let r1 = r.get(1).copied().unwrap_or_default();
        let sk = r1.neg();
        if r.len() < 2 {
            r.resize(2, Ball::default());
        }
        r[1] = Ball::default();
        sigma.push(sk);
        // Particular solution plus C cos s with x_k(0) = 0.
        let mut xk = vec![Ball::default(); r.len()];
        let mut sum = Ball::default();
        for (m, rm) in r.iter().enumerate() {
            if m != 1 && !rm.is_zero() {
                let c = rm.div(1.0 - (m * m) as f64);
                xk[m] = c;
                sum = sum.add(c);
            }
        }
        xk[1] = sum.neg();
        x.push(xk);
        // Extend the odd powers to order k: [x^{2p+1}]_k = Σ_i [x^{2p−1}]_i [x²]_{k−i}.
        // x² series up to order k.
        let mut sq: Vec<Vec<Ball>> = Vec::with_capacity(k + 1);
        for kk in 0..=k {
            let mut s: Vec<Ball> = Vec::new();
            for i in 0..=kk {
                cos_axpy(&mut s, one, &cos_mul(&x[i], &x[kk - i]));
            }
            sq.push(s);
        }
        pow_series[0].push(x[k].clone());
        for p in 1..=max_power {
            if p + k > big_n {
                // [x^{2p+1}]_k enters only at order k + p, so it is needed only for p + k ≤ N.
                break;
            }
            let mut s: Vec<Ball> = Vec::new();
            for i in 0..=k {
                cos_axpy(&mut s, one, &cos_mul(&pow_series[p - 1][i], &sq[k - i]));
            }
            pow_series[p].push(s);
        }
    }
    let frequency = unit_power(&sigma, 0.5);
    let period_ratio = unit_power(&sigma, -0.5);
    let values = |b: &[Ball]| b.iter().map(|c| c.v).collect::<Vec<f64>>();
    let errors = |b: &[Ball]| b.iter().map(|c| c.e).collect::<Vec<f64>>();
    let out = LindstedtSeries {
        frequency_squared: values(&sigma),
        frequency: values(&frequency),
        period_ratio: values(&period_ratio),
        solution: x.iter().map(|xk| values(xk)).collect(),
        frequency_squared_error: errors(&sigma),
        frequency_error: errors(&frequency),
        period_ratio_error: errors(&period_ratio),
    };
    for (name, series) in [
        ("σ_k", &out.frequency_squared),
        ("f_k", &out.frequency),
        ("c_k", &out.period_ratio),
        ("rounding-error bound", &out.period_ratio_error),
    ] {
        if let Some(k) = series.iter().position(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                what: format!(
                    "Lindstedt coefficient {name} at k = {k} (the force coefficients are too \
                     large for the series to be represented)"
                ),
                value: series[k],
            });
        }
    }
    Ok(out)
}

/// Lindstedt–Poincaré series of the pendulum `θ̈ + n² sin θ = 0` to order `N` in `a²`
/// (`g_j = (−1)^j/(2j+1)!`, each carrying the rounding of its factorial: `(2j+1)!` is a product
/// of `j` rounded steps and the reciprocal one more, so `|δg_j| ≤ (j + 1) ε |g_j|`). Leading
/// terms (checked against the series of `2K(k)/π` in `tests/normal_form.rs`):
/// `ω/n = 1 − a²/16 + a⁴/3072 + …`, `τ/(2π/n) = 1 + a²/16 + 11 a⁴/3072 + …`.
///
/// ```
/// use hamilton_jacobi::perturbation::lindstedt::lindstedt_pendulum;
/// let s = lindstedt_pendulum(2).unwrap();
/// assert!((s.period_ratio[1] - 1.0 / 16.0).abs() < 1e-16);
/// assert!((s.period_ratio[2] - 11.0 / 3072.0).abs() < 1e-17);
/// ```
///
/// # Errors
/// As [`lindstedt_odd_force`]; the order is checked before anything is allocated.
pub fn lindstedt_pendulum(order: usize) -> Result<LindstedtSeries> {
    let order = check_order(order)?;
    let mut g = Vec::with_capacity(order);
    let mut fact = 1.0_f64; // (2j+1)!
    for j in 1..=order {
        fact *= ((2 * j) * (2 * j + 1)) as f64;
        let v = if j % 2 == 1 { -1.0 } else { 1.0 } / fact;
        g.push(Ball {
            v,
            e: (j + 1) as f64 * ROUND * v.abs(),
        });
    }
    lindstedt_balls(&g, order)
}

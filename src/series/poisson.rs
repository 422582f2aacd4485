//! Poisson series from a function written once: Fourier in the angles, Taylor in the actions and
//! the small parameter.
//!
//! For `F(J, θ; ε)` with `J, θ ∈ ℝᴺ`, about the actions `J₀`,
//!
//! ```math
//! F(J_0 + \Delta J, \theta; \varepsilon) = \sum_{k} \big[ C_k(\Delta J, \varepsilon)\cos(k\cdot\theta)
//! + S_k(\Delta J, \varepsilon)\sin(k\cdot\theta) \big],
//! ```
//!
//! the sum over `k ∈ ℤᴺ` with `|k_i| ≤ H` in the half-space `k = 0` or first non-zero `k_i > 0`,
//! each `C_k, S_k` a polynomial of degree `≤ K` in the `N + 1` variables `(ΔJ, ε)`. The
//! polynomials come from evaluating `F` on [`Series`] arguments (`J = J₀ + ΔJ`, `ε` a variable,
//! `θ` a constant) at the `Mᴺ` grid nodes `θ_m = 2πm/M` and the discrete Fourier transform
//! `c_k = M^{−N} Σ_m F(θ_m) e^{−i k·θ_m}`, `C_k = 2 Re c_k`, `S_k = −2 Im c_k` (`C₀ = c₀`).
//! The transform is a plain DFT, `O(M^{2N})` per coefficient: the node counts used here
//! (`M ≤ 4H + 4`, at most [`MAX_FOURIER_NODES`] nodes in all) keep it cheaper than the series
//! evaluations themselves.
//!
//! The truncation error of the Fourier part is estimated by doubling the nodes: the result is
//! computed on `M = 4H + 4` nodes per angle, the harmonics `H < |k|_∞ < M/2` it also resolves give
//! the tail `Σ_{k dropped} (|C_{k,α}| + |S_{k,α}|)` (largest over the monomials `α`), and the
//! difference from the run on `2H + 2` nodes bounds the aliasing of the kept harmonics.
//!
//! Reference: the DFT construction of Poisson series, J. Laskar, "Manipulation des séries", in
//! *Modern Methods in Celestial Mechanics*, Benest & Froeschlé (eds.), 1990; trigonometric
//! interpolation error, J. P. Boyd, *Chebyshev and Fourier Spectral Methods*, 2nd ed., Dover
//! 2001, §2.12 and ch. 11.

use super::ball::Coefficient;
use super::{scope_with, Monomials, Polynomial, Series};
use crate::error::{Error, Result};
use nalgebra::SVector;
use std::f64::consts::TAU;
use std::sync::Arc;

/// The largest number of grid nodes `(4H + 4)ᴺ` of one expansion.
pub const MAX_FOURIER_NODES: usize = 1 << 16;

/// One harmonic `k` of a [`FourierTaylor`] series: `C_k cos(k·θ) + S_k sin(k·θ)`.
#[derive(Clone, Debug)]
pub struct Harmonic {
    /// The wave vector `k`.
    pub k: Vec<i32>,
    /// `C_k(ΔJ, ε)`, variables `(ΔJ_1, …, ΔJ_N, ε)`.
    pub cos: Polynomial,
    /// `S_k(ΔJ, ε)` (zero for `k = 0`).
    pub sin: Polynomial,
}

/// A Poisson series (Fourier in the angles × Taylor in the actions and `ε`) with its estimated
/// Fourier truncation error; see the [module docs](self).
#[derive(Clone, Debug)]
pub struct FourierTaylor {
    /// The actions `J₀` of the expansion.
    pub actions: Vec<f64>,
    /// The harmonic bound `H` (`|k_i| ≤ H`).
    pub max_harmonic: usize,
    /// The harmonics, `k = 0` first.
    pub harmonics: Vec<Harmonic>,
    /// Estimated size of the dropped harmonics, `max_α Σ_{|k|_∞ > H} (|C_{k,α}| + |S_{k,α}|)`.
    pub fourier_tail: f64,
    /// Largest change of a kept coefficient between `2H + 2` and `4H + 4` nodes per angle.
    pub aliasing: f64,
}

impl FourierTaylor {
    /// The estimated truncation error of the Fourier part, `fourier_tail + aliasing`.
    pub fn truncation_error(&self) -> f64 {
        self.fourier_tail + self.aliasing
    }

    /// The harmonic `k` (or `−k`, with `S` negated), if kept.
    pub fn harmonic(&self, k: &[i32]) -> Option<Harmonic> {
        if let Some(h) = self.harmonics.iter().find(|h| h.k == k) {
            return Some(h.clone());
        }
        let neg: Vec<i32> = k.iter().map(|x| -x).collect();
        self.harmonics.iter().find(|h| h.k == neg).map(|h| {
            let mut h = h.clone();
            h.k = k.to_vec();
            for c in h.sin.coefficients_mut() {
                *c = -*c;
            }
            h
        })
    }

    /// The value at `(J₀ + ΔJ, θ; ε)`.
    ///
    /// # Errors
    /// Lengths other than `N`; NaN/∞ entries.
    pub fn eval(&self, delta_j: &[f64], theta: &[f64], eps: f64) -> Result<f64> {
        let n = self.actions.len();
        if delta_j.len() != n || theta.len() != n {
            return Err(Error::InvalidInput {
                what: "Poisson series point".into(),
                reason: format!("ΔJ and θ need {n} entries each"),
            });
        }
        crate::error::all_finite("θ", theta)?;
        let mut x = delta_j.to_vec();
        x.push(eps);
        let mut sum = 0.0;
        for h in &self.harmonics {
            let phase: f64 = h.k.iter().zip(theta).map(|(&k, &t)| k as f64 * t).sum();
            sum += h.cos.eval(&x)? * phase.cos() + h.sin.eval(&x)? * phase.sin();
        }
        crate::error::finite("Poisson series value", sum)
    }
}

/// The wave vectors with `|k_i| ≤ kmax` in the half-space (`k = 0` first).
fn half_space(n: usize, kmax: i32) -> Vec<Vec<i32>> {
    let side = (2 * kmax + 1) as usize;
    let total = side.pow(n as u32);
    let mut out = vec![vec![0; n]];
    for mut idx in 0..total {
        let mut k = vec![0; n];
        for ki in k.iter_mut() {
            *ki = (idx % side) as i32 - kmax;
            idx /= side;
        }
        if let Some(&first) = k.iter().find(|&&x| x != 0) {
            if first > 0 {
                out.push(k);
            }
        }
    }
    out
}

/// Values of `F` (as coefficient vectors) at the `mᴺ` nodes, node index in radix `m`.
fn node_values<const N: usize>(
    table: &Arc<Monomials>,
    actions: &SVector<f64, N>,
    m: usize,
    f: &impl Fn(&SVector<Series, N>, &SVector<Series, N>, Series) -> Series,
) -> Result<Vec<Vec<f64>>> {
    let total = m.pow(N as u32);
    let mut out = Vec::with_capacity(total);
    for node in 0..total {
        let mut theta = [0.0; N];
        let mut idx = node;
        for t in theta.iter_mut() {
            *t = TAU * (idx % m) as f64 / m as f64;
            idx /= m;
        }
        let p = scope_with(table.clone(), |s| -> Result<Polynomial> {
            let mut j = SVector::<Series, N>::from_element(Series::constant(0.0));
            for i in 0..N {
                j[i] = s.variable_at(i, actions[i])?;
            }
            let th = SVector::<Series, N>::from_fn(|i, _| Series::constant(theta[i]));
            let eps = s.variable(N)?;
            s.polynomial(f(&j, &th, eps))
        })??;
        let p = p.check_finite(&format!(
            "J = {:?}, θ = {:?}, ε = 0",
            actions.as_slice(),
            theta
        ))?;
        out.push(p.coefficients().to_vec());
    }
    Ok(out)
}

/// DFT of node values at the wave vectors `ks`: `(C_k, S_k)` coefficient vectors.
fn transform(
    values: &[Vec<f64>],
    n: usize,
    m: usize,
    ks: &[Vec<i32>],
) -> Vec<(Vec<f64>, Vec<f64>)> {
    let len = values[0].len();
    let scale = 1.0 / values.len() as f64;
    ks.iter()
        .map(|k| {
            let zero = k.iter().all(|&x| x == 0);
            let (mut c, mut s) = (vec![0.0; len], vec![0.0; len]);
            for (node, v) in values.iter().enumerate() {
                let mut idx = node;
                let mut phase_index: i64 = 0;
                for &ki in k.iter().take(n) {
                    phase_index += ki as i64 * (idx % m) as i64;
                    idx /= m;
                }
                let phase = TAU * phase_index.rem_euclid(m as i64) as f64 / m as f64;
                let (sn, cs) = phase.sin_cos();
                for a in 0..len {
                    c[a] += v[a] * cs;
                    s[a] += v[a] * sn;
                }
            }
            let w = if zero { scale } else { 2.0 * scale };
            c.iter_mut().for_each(|x| *x *= w);
            s.iter_mut().for_each(|x| *x *= if zero { 0.0 } else { w });
            (c, s)
        })
        .collect()
}

/// The Poisson series of `f(J, θ, ε)` about the actions `J₀`, harmonics `|k_i| ≤ max_harmonic`,
/// Taylor degree `degree` in `(ΔJ, ε)`; see the [module docs](self).
///
/// `f` receives `J = J₀ + ΔJ` and `ε` as series variables and `θ` as constants; pass the user's
/// generic function, e.g. `|j, th, e| system.eval(j, th, e)`.
///
/// # Errors
/// NaN/∞ actions; `(4H + 4)ᴺ >` [`MAX_FOURIER_NODES`] or the storage limits of
/// [`scope`](super::scope) (before any evaluation); a non-finite coefficient at a node
/// ([`Error::NonFinite`] naming `J₀` and `θ`).
pub fn fourier_taylor<const N: usize>(
    actions: &SVector<f64, N>,
    max_harmonic: usize,
    degree: usize,
    f: impl Fn(&SVector<Series, N>, &SVector<Series, N>, Series) -> Series,
) -> Result<FourierTaylor> {
    crate::error::all_finite("actions J₀", actions.as_slice())?;
    if N == 0 {
        return Err(Error::InvalidInput {
            what: "Poisson series".into(),
            reason: "needs at least one angle".into(),
        });
    }
    let fine = max_harmonic
        .checked_mul(4)
        .and_then(|x| x.checked_add(4))
        .filter(|&m| {
            (0..N)
                .try_fold(1usize, |acc, _| {
                    acc.checked_mul(m).filter(|&t| t <= MAX_FOURIER_NODES)
                })
                .is_some()
        })
        .ok_or_else(|| Error::WorkLimit {
            what: format!("Poisson series with {N} angles to harmonic {max_harmonic}"),
            limit: MAX_FOURIER_NODES,
            detail: "(4H + 4)^N grid nodes requested".into(),
            hint: "lower the harmonic bound H".into(),
        })?;
    let coarse = fine / 2;
    let table = Arc::new(Monomials::new(N + 1, degree)?);
    let kept = half_space(N, max_harmonic as i32);
    let resolved = half_space(N, (fine / 2 - 1) as i32);
    let dropped: Vec<Vec<i32>> = resolved
        .into_iter()
        .filter(|k| k.iter().any(|&x| x.unsigned_abs() as usize > max_harmonic))
        .collect();
    let vf = node_values(&table, actions, fine, &f)?;
    let vc = node_values(&table, actions, coarse, &f)?;
    let fine_kept = transform(&vf, N, fine, &kept);
    let coarse_kept = transform(&vc, N, coarse, &kept);
    let tail_terms = transform(&vf, N, fine, &dropped);
    let len = table.len();
    let mut tail = vec![0.0; len];
    for (c, s) in &tail_terms {
        for a in 0..len {
            tail[a] += c[a].abs() + s[a].abs();
        }
    }
    let fourier_tail = tail.iter().copied().fold(0.0, f64::max);
    let mut aliasing: f64 = 0.0;
    for ((cf, sf), (cc, sc)) in fine_kept.iter().zip(&coarse_kept) {
        for a in 0..len {
            aliasing = aliasing
                .max((cf[a] - cc[a]).abs())
                .max((sf[a] - sc[a]).abs());
        }
    }
    let poly = |c: Vec<f64>| -> Polynomial {
        let mut p = Polynomial {
            monomials: table.clone(),
            coefficients: c,
        };
        p.coefficients.truncate(len);
        p
    };
    let harmonics = kept
        .into_iter()
        .zip(fine_kept)
        .map(|(k, (c, s))| Harmonic {
            k,
            cos: poly(c),
            sin: poly(s),
        })
        .collect();
    Ok(FourierTaylor {
        actions: actions.as_slice().to_vec(),
        max_harmonic,
        harmonics,
        fourier_tail,
        aliasing,
    })
}

// ---------------------------------------------------------------------------------------------
// Cosine series in one angle, over any coefficient ring.

/// The product of two cosine series in one angle, `c(s) = a(s) b(s)` with
/// `a = Σ_m a_m cos(ms)`, `b = Σ_l b_l cos(ls)` (index = harmonic), by the product-to-sum rule
/// `cos(ms) cos(ls) = ½[cos((m + l)s) + cos((m − l)s)]`, each term `h = (a_m/2)·b_l` added to the harmonics `m + l` and `|m − l|` in the order
/// `m = 0, 1, …`, `l = 0, 1, …` (exact zeros skipped). The `k = 0` harmonic of a [`Harmonic`] row
/// of a one-angle [`FourierTaylor`] series with scalar coefficients; generic over the
/// coefficient ring (`f64`, or [`Ball`](super::ball::Ball) with rounding-error bounds), used by
/// the Lindstedt–Poincaré recursion ([`crate::perturbation::lindstedt`]). Empty if either factor
/// is empty.
pub(crate) fn cosine_product<C: Coefficient>(a: &[C], b: &[C]) -> Vec<C> {
    if a.is_empty() || b.is_empty() {
        return Vec::new();
    }
    let mut out = vec![C::default(); a.len() + b.len() - 1];
    for (m, am) in a.iter().enumerate() {
        if am.is_zero() {
            continue;
        }
        let half = am.scale(0.5);
        for (l, bl) in b.iter().enumerate() {
            if bl.is_zero() {
                continue;
            }
            let h = half.mul(*bl);
            out[m + l] = out[m + l].add(h);
            out[m.abs_diff(l)] = out[m.abs_diff(l)].add(h);
        }
    }
    out
}

/// `a ← a + s·b` for cosine series in one angle (`a` grown to the length of `b`), coefficientwise
/// `a_m ← a_m + s b_m`.
pub(crate) fn cosine_axpy<C: Coefficient>(a: &mut Vec<C>, s: C, b: &[C]) {
    if a.len() < b.len() {
        a.resize(b.len(), C::default());
    }
    for (ai, bi) in a.iter_mut().zip(b) {
        *ai = ai.add(s.mul(*bi));
    }
}

#[cfg(test)]
mod tests {
    use super::super::ball::Ball;
    use super::*;

    /// `Σ c_m cos(m s)` by direct summation.
    fn value<C: Coefficient>(c: &[C], s: f64) -> f64 {
        c.iter()
            .enumerate()
            .map(|(m, cm)| cm.value() * (m as f64 * s).cos())
            .sum()
    }

    #[test]
    fn cosine_product_is_the_pointwise_product() {
        // Oracle: the product of the two trigonometric sums evaluated pointwise.
        let a = [0.5, -1.25, 0.0, 0.375];
        let b = [2.0, 0.0, -0.75];
        let c = cosine_product(&a, &b);
        assert_eq!(c.len(), 6);
        for s in [0.0, 0.3, 1.7, -2.9, 3.1] {
            let (x, y, z) = (value(&a, s), value(&b, s), value(&c, s));
            // A handful of products of O(1) terms: a few ulps of Σ|a||b| ≈ 10.
            assert!((z - x * y).abs() < 16.0 * f64::EPSILON * 10.0, "s = {s}");
        }
        // Exact identities: cos²s = (1 + cos 2s)/2, cos s cos 3s = (cos 2s + cos 4s)/2.
        assert_eq!(
            cosine_product(&[0.0, 1.0], &[0.0, 1.0]),
            vec![0.5, 0.0, 0.5]
        );
        assert_eq!(
            cosine_product(&[0.0, 1.0], &[0.0, 0.0, 0.0, 1.0]),
            vec![0.0, 0.0, 0.5, 0.0, 0.5]
        );
        assert!(cosine_product::<f64>(&[], &[1.0]).is_empty());
    }

    #[test]
    fn ball_values_equal_the_plain_ones_and_bounds_cover_the_rounding() {
        // ((1/3) cos s)² = 1/18 + (1/18) cos 2s: the values are bit-identical to f64, and the
        // bounds cover the error against the exact 1/18 (rounding of 1/3, ≤ ε/8, carried as ε/4).
        let third = 1.0 / 3.0;
        let a = [
            Ball::default(),
            Ball {
                v: third,
                e: f64::EPSILON / 4.0,
            },
        ];
        let plain = cosine_product(&[0.0, third], &[0.0, third]);
        let balls = cosine_product(&a, &a);
        for (p, b) in plain.iter().zip(&balls) {
            assert_eq!(*p, b.v);
        }
        for m in [0, 2] {
            // |v − fl(1/18)| is exact (Sterbenz) and within ulp(1/18)/2 = ε/64 of |v − 1/18|,
            // far below the derived bound of about ε/4.
            let err = (balls[m].v - 1.0 / 18.0).abs();
            assert!(err <= balls[m].e, "m = {m}: {err:e} > {:e}", balls[m].e);
            assert!(balls[m].e < 8.0 * f64::EPSILON / 18.0);
        }
        let mut acc = vec![Ball::exact(1.0)];
        cosine_axpy(&mut acc, Ball::exact(2.0), &balls);
        assert_eq!(acc.len(), 3);
        assert_eq!(acc[0].v, 1.0 + 2.0 * balls[0].v);
    }
}

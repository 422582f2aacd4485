//! Monomials of `n` variables to total degree `K` in graded order, with the index tables of the
//! truncated product.
//!
//! The `C(n + K, n)` exponent vectors are stored degree by degree (graded order; inside a degree,
//! lexicographically decreasing), so the monomials of degree `≤ d` are a prefix and a truncated
//! product `a·b` visits, for each term of `a` of degree `dₐ`, only the prefix of `b` of degree
//! `≤ K − dₐ`. The address of a product monomial is found without search by splitting the
//! variables into two halves and encoding each half's exponents in radix `K + 1`: the encoding is
//! additive (`code(α + β) = code(α) + code(β)`, no carries below degree `K + 1`), and the product
//! is accumulated in the *split order* (blocks by the second half's monomial, the first half's
//! monomials graded inside a block), where the address is the sum `ia₁[code₁] + ia₂[code₂]` of two
//! small tables. One permutation per product returns the accumulator to graded order.
//!
//! Reference: M. Berz, *Modern Map Methods in Particle Beam Physics*, Academic Press 1999, §2.3.4
//! (the addressing scheme of the DA package, also used by DACE: M. Rasotto et al., "Differential
//! algebra space toolbox for nonlinear uncertainty propagation in space dynamics", ICATT 2016).

use crate::error::{Error, Result};
use std::cell::RefCell;
use std::sync::Arc;

/// The largest number of coefficients of one series value, `C(n + K, n) ≤ 2²⁰` (8 MiB per value);
/// a larger request is refused before any allocation.
pub const MAX_SERIES_COEFFICIENTS: usize = 1 << 20;

/// The largest entry count of one half-variable address table, `(K + 1)^⌈n/2⌉ ≤ 2²⁴`.
pub const MAX_ADDRESS_TABLE: usize = 1 << 24;

/// The largest total degree `K` (exponents are stored in one byte).
pub const MAX_SERIES_DEGREE: usize = 255;

/// The number of monomials of `n` variables of total degree `≤ k`, `C(n + k, n)`, or `None` when
/// it exceeds `limit` (computed without overflow).
pub(crate) fn count_monomials(n: usize, k: usize, limit: usize) -> Option<usize> {
    // C(n + k, n) = Π_{i=1}^{n} (k + i)/i, every partial product an integer.
    let mut c: u128 = 1;
    for i in 1..=n as u128 {
        c = c.checked_mul(k as u128 + i)? / i;
        if c > limit as u128 {
            return None;
        }
    }
    Some(c as usize)
}

/// Monomial tables for `n` variables to total degree `K`.
#[derive(Debug)]
pub struct Monomials {
    n: usize,
    degree: usize,
    len: usize,
    /// Exponents, `n` bytes per monomial, graded order.
    exponents: Vec<u8>,
    /// Degree of each monomial.
    degrees: Vec<u8>,
    /// `upto[d]` = number of monomials of degree `≤ d` (`upto[K] = len`), `d = 0..=K`.
    upto: Vec<usize>,
    /// Radix-(K+1) codes of the two halves of each monomial's exponents.
    codes: Vec<(u32, u32)>,
    /// First-half address table (rank of the first-half monomial in graded order).
    ia1: Vec<u32>,
    /// Second-half address table (start of the second-half monomial's block).
    ia2: Vec<u32>,
    /// `graded[s]` = graded index of the monomial at split-order address `s`.
    graded: Vec<u32>,
    /// `lower[v·len + i]` = graded index of `α_i − e_v` (`u32::MAX` where `α_{i,v} = 0`), kept
    /// when `n · len ≤ LOWER_TABLE` (otherwise empty and the derivative uses the half codes).
    lower: Vec<u32>,
}

/// The largest `n · len` for which the derivative index table `lower` is kept (4 MiB).
const LOWER_TABLE: usize = 1 << 20;

/// The exponent vectors of `n` variables of total degree exactly `d`, lexicographically decreasing.
fn push_degree(n: usize, d: usize, prefix: &mut Vec<u8>, out: &mut Vec<u8>) {
    if n == 0 {
        return;
    }
    if prefix.len() + 1 == n {
        prefix.push(d as u8);
        out.extend_from_slice(prefix);
        prefix.pop();
        return;
    }
    for first in (0..=d).rev() {
        prefix.push(first as u8);
        push_degree(n, d - first, prefix, out);
        prefix.pop();
    }
}

/// All exponent vectors of `n` variables of degree `≤ k` in graded order.
fn graded_exponents(n: usize, k: usize) -> Vec<u8> {
    let mut out = Vec::new();
    if n == 0 {
        return out;
    }
    let mut prefix = Vec::with_capacity(n);
    for d in 0..=k {
        push_degree(n, d, &mut prefix, &mut out);
    }
    out
}

impl Monomials {
    /// The tables for `n ≥ 1` variables to total degree `degree`; an error (before any allocation)
    /// when a value would exceed [`MAX_SERIES_COEFFICIENTS`] coefficients, an address table
    /// [`MAX_ADDRESS_TABLE`] entries, or the degree [`MAX_SERIES_DEGREE`].
    pub fn new(n: usize, degree: usize) -> Result<Self> {
        if n == 0 {
            return Err(Error::OutOfDomain {
                what: "number of series variables".into(),
                value: 0.0,
                domain: "n ≥ 1".into(),
            });
        }
        if degree > MAX_SERIES_DEGREE {
            return Err(Error::OutOfDomain {
                what: "series degree K".into(),
                value: degree as f64,
                domain: format!("0 ≤ K ≤ MAX_SERIES_DEGREE = {MAX_SERIES_DEGREE}"),
            });
        }
        let len = count_monomials(n, degree, MAX_SERIES_COEFFICIENTS).ok_or_else(|| {
            Error::WorkLimit {
                what: format!("series storage for n = {n} variables to degree K = {degree}"),
                limit: MAX_SERIES_COEFFICIENTS,
                detail: "C(n + K, n) coefficients per value requested".into(),
                hint: "lower the degree or the number of variables".into(),
            }
        })?;
        let n1 = n / 2;
        let n2 = n - n1;
        let radix = degree + 1;
        let table = |m: usize| -> Option<usize> {
            let mut s: usize = 1;
            for _ in 0..m {
                s = s.checked_mul(radix)?;
                if s > MAX_ADDRESS_TABLE {
                    return None;
                }
            }
            Some(s)
        };
        let (Some(size1), Some(size2)) = (table(n1), table(n2)) else {
            return Err(Error::WorkLimit {
                what: format!("series address table for n = {n} variables to degree K = {degree}"),
                limit: MAX_ADDRESS_TABLE,
                detail: format!("(K + 1)^{n2} entries requested"),
                hint: "lower the degree or the number of variables".into(),
            });
        };
        let exponents = graded_exponents(n, degree);
        let degrees: Vec<u8> = exponents
            .chunks_exact(n)
            .map(|e| e.iter().map(|&x| x as usize).sum::<usize>() as u8)
            .collect();
        let mut upto = vec![0usize; degree + 1];
        for &d in &degrees {
            upto[d as usize] += 1;
        }
        for d in 1..=degree {
            upto[d] += upto[d - 1];
        }
        let code = |e: &[u8]| -> u32 {
            e.iter()
                .rev()
                .fold(0usize, |acc, &x| acc * radix + x as usize) as u32
        };
        let codes: Vec<(u32, u32)> = exponents
            .chunks_exact(n)
            .map(|e| (code(&e[..n1]), code(&e[n1..])))
            .collect();
        // First half: graded rank among first-half monomials.
        let mut ia1 = vec![u32::MAX; size1];
        let first = graded_exponents(n1, degree);
        if n1 == 0 {
            ia1[0] = 0;
        } else {
            for (r, e) in first.chunks_exact(n1).enumerate() {
                ia1[code(e) as usize] = r as u32;
            }
        }
        let count1 = |d: usize| count_monomials(n1, d, usize::MAX).unwrap_or(1);
        // Second half: blocks of first-half monomials of degree ≤ K − deg₂, in graded order of
        // the second half.
        let mut ia2 = vec![u32::MAX; size2];
        let mut offset = 0usize;
        for e in graded_exponents(n2, degree).chunks_exact(n2) {
            let d2: usize = e.iter().map(|&x| x as usize).sum();
            ia2[code(e) as usize] = offset as u32;
            offset += count1(degree - d2);
        }
        debug_assert_eq!(offset, len);
        let mut graded = vec![0u32; len];
        for (i, &(c1, c2)) in codes.iter().enumerate() {
            graded[(ia1[c1 as usize] + ia2[c2 as usize]) as usize] = i as u32;
        }
        let mut m = Self {
            n,
            degree,
            len,
            exponents,
            degrees,
            upto,
            codes,
            ia1,
            ia2,
            graded,
            lower: Vec::new(),
        };
        if n.saturating_mul(len) <= LOWER_TABLE {
            let mut lower = vec![u32::MAX; n * len];
            for v in 0..n {
                for i in 0..len {
                    if m.exponents[i * n + v] > 0 {
                        lower[v * len + i] = m.lowered(i, v) as u32;
                    }
                }
            }
            m.lower = lower;
        }
        Ok(m)
    }

    /// Number of variables `n`.
    pub fn variables(&self) -> usize {
        self.n
    }

    /// Total degree `K`.
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// Number of monomials `C(n + K, n)`.
    pub fn len(&self) -> usize {
        self.len
    }

    /// Always false (there is at least the constant monomial).
    pub fn is_empty(&self) -> bool {
        false
    }

    /// The exponent vector of monomial `i` (graded order), `None` for `i ≥ len`.
    pub fn exponents(&self, i: usize) -> Option<&[u8]> {
        (i < self.len).then(|| self.exps(i))
    }

    /// The total degree of monomial `i`, `None` for `i ≥ len`.
    pub fn degree_of(&self, i: usize) -> Option<usize> {
        self.degrees.get(i).map(|&d| d as usize)
    }

    pub(crate) fn exps(&self, i: usize) -> &[u8] {
        &self.exponents[i * self.n..(i + 1) * self.n]
    }

    /// The graded indices of the monomials of degree exactly `d` (empty beyond `K`).
    pub fn of_degree(&self, d: usize) -> std::ops::Range<usize> {
        if d > self.degree {
            return self.len..self.len;
        }
        let start = if d == 0 { 0 } else { self.upto[d - 1] };
        start..self.upto[d]
    }

    /// The graded index of the variable `x_i` (the monomial `e_i`): `1 + i`, the degree-1 block
    /// being in lexicographically decreasing order; `None` for `i ≥ n` or `K = 0`.
    pub(crate) fn variable_index(&self, i: usize) -> Option<usize> {
        (i < self.n && self.degree >= 1).then_some(1 + i)
    }

    /// The graded index of the monomial with exponents `alpha`, `None` when its length is not `n`
    /// or its degree exceeds `K`.
    pub fn index_of(&self, alpha: &[u32]) -> Option<usize> {
        if alpha.len() != self.n {
            return None;
        }
        let total: u64 = alpha.iter().map(|&a| a as u64).sum();
        if total > self.degree as u64 {
            return None;
        }
        let radix = self.degree + 1;
        let n1 = self.n / 2;
        let code = |e: &[u32]| {
            e.iter()
                .rev()
                .fold(0usize, |acc, &x| acc * radix + x as usize)
        };
        let s = self.ia1[code(&alpha[..n1])] + self.ia2[code(&alpha[n1..])];
        Some(self.graded[s as usize] as usize)
    }

    /// `out = a·b` truncated at degree `K` (all slices of length [`len`](Self::len), graded
    /// order); `scratch` is a work array of the same length.
    ///
    /// For each term `aᵢ xᵅ` only the prefix of `b` of degree `≤ K − |α|` is visited, so exactly
    /// the products of degree `≤ K` are formed (`C(2n + K, 2n)` of them for dense operands).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when a slice is shorter than [`len`](Self::len).
    pub fn mul(&self, a: &[f64], b: &[f64], out: &mut [f64], scratch: &mut [f64]) -> Result<()> {
        let len = self.len;
        if a.len() < len || b.len() < len || out.len() < len || scratch.len() < len {
            return Err(Error::InvalidInput {
                what: "truncated product operands".into(),
                reason: format!("every slice needs C(n + K, n) = {len} coefficients"),
            });
        }
        scratch[..len].fill(0.0);
        self.mul_to_degree(a, b, out, scratch, self.degree);
        Ok(())
    }

    /// `out = ∂a/∂x_v` (graded order, slices of length [`len`](Self::len), `v < n`):
    /// `out[α − e_v] = α_v a_α`; the terms of degree `K` of `out` are zero. The address of
    /// `α − e_v` is found, as in the product, from the additive half codes:
    /// `code(α − e_v) = code(α) − code(e_v)`.
    pub(crate) fn derivative(&self, a: &[f64], v: usize, out: &mut [f64]) {
        self.derivative_to(a, v, out, self.degree);
    }

    /// The terms of degree `≤ d` of `∂a/∂x_v`: `out[..C(n + d, n)]` (graded order) from the terms
    /// of `a` of degree `≤ d + 1`; the rest of `out` is not touched.
    pub(crate) fn derivative_to(&self, a: &[f64], v: usize, out: &mut [f64], d: usize) {
        let d = d.min(self.degree);
        let out = &mut out[..self.upto[d]];
        out.fill(0.0);
        let top = self.upto[(d + 1).min(self.degree)];
        if !self.lower.is_empty() {
            let lower = &self.lower[v * self.len..v * self.len + top];
            for (i, (&ai, &j)) in a[..top].iter().zip(lower).enumerate() {
                if ai != 0.0 && j != u32::MAX {
                    out[j as usize] = f64::from(self.exponents[i * self.n + v]) * ai;
                }
            }
            return;
        }
        for (i, &ai) in a[..top].iter().enumerate() {
            let e = self.exponents[i * self.n + v];
            if e == 0 || ai == 0.0 {
                continue;
            }
            out[self.lowered(i, v)] = f64::from(e) * ai;
        }
    }

    /// The graded index of `α_i − e_v` (`α_{i,v} ≥ 1`), from the additive half codes:
    /// `code(α − e_v) = code(α) − code(e_v)`.
    fn lowered(&self, i: usize, v: usize) -> usize {
        let n1 = self.n / 2;
        let radix = self.degree as u32 + 1;
        let (mut c1, mut c2) = self.codes[i];
        if v < n1 {
            c1 -= radix.pow(v as u32);
        } else {
            c2 -= radix.pow((v - n1) as u32);
        }
        let s = self.ia1[c1 as usize] + self.ia2[c2 as usize];
        self.graded[s as usize] as usize
    }

    /// `out = a·b` truncated at degree `d ≤ K` (the coefficients of degree `> d` of `out` are
    /// zero); only the products of degree `≤ d` are formed. Slices of length `len`; `scratch`
    /// must be all zero and is all zero again afterwards, so the cost is that of the products
    /// and of `C(n + d, n)` moves, not of the full length. `a` runs in the outer loop
    /// ([`mul_add_split`](Self::mul_add_split)); its zero coefficients are skipped, so the
    /// operand order decides where `0 · ∞` would have made a NaN: it is kept fixed (`a` the
    /// first factor of the product, the Horner accumulator of the elementary functions).
    pub(crate) fn mul_to_degree(
        &self,
        a: &[f64],
        b: &[f64],
        out: &mut [f64],
        scratch: &mut [f64],
        d: usize,
    ) {
        let d = d.min(self.degree);
        self.mul_add_split(a, b, scratch, d);
        self.take_split_to_degree(scratch, out, d);
        out[self.upto[d]..self.len].fill(0.0);
    }

    /// `acc += a·b` truncated at degree `d ≤ K`, with `acc` in the *split order* of the
    /// address tables (see the [module docs](self); [`take_split_to_degree`](Self::take_split_to_degree)
    /// returns it to graded order). The outer loop runs over the nonzero coefficients of `a`
    /// only, so the cost is `Σ_{a_α ≠ 0} C(n + d − |α|, n)`: pass the sparser operand as `a`.
    pub(crate) fn mul_add_split(&self, a: &[f64], b: &[f64], acc: &mut [f64], d: usize) {
        let d = d.min(self.degree);
        let top = self.upto[d];
        let (a, b) = (&a[..top], &b[..top]);
        let acc = &mut acc[..self.len];
        let codes = &self.codes[..top];
        let (ia1, ia2) = (&self.ia1[..], &self.ia2[..]);
        for (i, &ai) in a.iter().enumerate() {
            if ai == 0.0 {
                continue;
            }
            let (c1, c2) = codes[i];
            let (r1, r2) = (&ia1[c1 as usize..], &ia2[c2 as usize..]);
            let m = self.upto[d - self.degrees[i] as usize];
            for (&bj, &(d1, d2)) in b[..m].iter().zip(&codes[..m]) {
                let s = r1[d1 as usize] + r2[d2 as usize];
                acc[s as usize] += ai * bj;
            }
        }
    }

    /// The terms of degree `≤ d` of `split` (split order) into `out[..C(n + d, n)]` (graded
    /// order), each read position of `split` reset to zero: when `split` held only terms of
    /// degree `≤ d` (a product truncated at `d`), it is all zero again afterwards, at a cost
    /// `C(n + d, n)` instead of `len`.
    pub(crate) fn take_split_to_degree(&self, split: &mut [f64], out: &mut [f64], d: usize) {
        let top = self.upto[d.min(self.degree)];
        for (o, &(c1, c2)) in out[..top].iter_mut().zip(&self.codes[..top]) {
            let s = (self.ia1[c1 as usize] + self.ia2[c2 as usize]) as usize;
            *o = split[s];
            split[s] = 0.0;
        }
    }

    /// The tables for `(n, degree)` shared through a small per-thread cache: repeated requests
    /// (one per series scope or Lie-series evaluation) reuse one [`Arc`] instead of rebuilding
    /// the tables. Errors as [`Monomials::new`]; tables above `CACHED_COEFFICIENTS`
    /// coefficients are built afresh and not kept.
    pub(crate) fn shared(n: usize, degree: usize) -> Result<Arc<Self>> {
        /// Tables larger than this are not kept by the per-thread cache.
        const CACHED_COEFFICIENTS: usize = 1 << 16;
        /// Entries of the per-thread cache (least recently built evicted first).
        const CACHE_ENTRIES: usize = 8;
        thread_local! {
            static CACHE: RefCell<Vec<Arc<Monomials>>> = const { RefCell::new(Vec::new()) };
        }
        if let Some(hit) = CACHE.with(|c| {
            c.borrow()
                .iter()
                .find(|m| m.n == n && m.degree == degree)
                .cloned()
        }) {
            return Ok(hit);
        }
        let table = Arc::new(Self::new(n, degree)?);
        if table.len <= CACHED_COEFFICIENTS {
            CACHE.with(|c| {
                let mut c = c.borrow_mut();
                if c.len() == CACHE_ENTRIES {
                    c.remove(0);
                }
                c.push(table.clone());
            });
        }
        Ok(table)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_and_addresses_agree_with_the_exponents() {
        for (n, k) in [(1, 0), (1, 7), (2, 5), (3, 4), (4, 10), (5, 3)] {
            let m = Monomials::new(n, k).unwrap();
            assert_eq!(m.len(), count_monomials(n, k, usize::MAX).unwrap());
            for i in 0..m.len() {
                let alpha: Vec<u32> = m.exps(i).iter().map(|&x| x as u32).collect();
                assert_eq!(m.index_of(&alpha), Some(i));
            }
            for v in 0..n {
                let mut unit = vec![0u32; n];
                unit[v] = 1;
                assert_eq!(m.variable_index(v), m.index_of(&unit));
            }
            for d in 0..=k {
                for i in m.of_degree(d) {
                    assert_eq!(m.degree_of(i), Some(d));
                }
            }
        }
    }

    #[test]
    fn product_of_monomials_is_the_monomial_of_the_summed_exponents() {
        let m = Monomials::new(3, 6).unwrap();
        let mut scratch = vec![0.0; m.len()];
        for i in 0..m.len() {
            for j in 0..m.len() {
                let (mut a, mut b, mut c) =
                    (vec![0.0; m.len()], vec![0.0; m.len()], vec![0.0; m.len()]);
                a[i] = 2.0;
                b[j] = 3.0;
                m.mul(&a, &b, &mut c, &mut scratch).unwrap();
                let sum: Vec<u32> = m
                    .exps(i)
                    .iter()
                    .zip(m.exps(j))
                    .map(|(&x, &y)| (x + y) as u32)
                    .collect();
                match m.index_of(&sum) {
                    Some(k) => {
                        assert_eq!(c[k], 6.0);
                        assert_eq!(c.iter().filter(|&&x| x != 0.0).count(), 1);
                    }
                    None => assert!(c.iter().all(|&x| x == 0.0)),
                }
            }
        }
    }
}

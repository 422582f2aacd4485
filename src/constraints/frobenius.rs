//! Integrability of Pfaffian constraints: the single-form test (SPEC M3) and, for a set of forms,
//! the integrable combinations (Frobenius; SPEC M3 "Sets of forms", M4).
//!
//! The constraints `ω_r = Σ_s B_rs dq_s + b_r dt` live on the extended space `y = (q, t)` of
//! dimension `M = N + 1` (time adjoined as a coordinate, SPEC §0.7). They annihilate the
//! distribution `Δ = ker ω` of dimension `M − K`. By Frobenius' theorem a combination `Σ c_r ω_r`
//! is (proportional to) an exact differential `dφ` iff it annihilates the involutive closure
//! `Δ̄ ⊇ Δ`, the span of `Δ` and of all iterated Lie brackets `[X₁, [X₂, … X_k]]` of fields of `Δ`
//! [Ardema 2.6; Hamel art. 229] — the bottom of the derived flag of the constraint system. The
//! integrable combinations are therefore the annihilator of `Δ̄` inside the span of the forms,
//! `M − dim Δ̄` of them, and `φ = const` are the holonomic constraints hidden in the set.
//!
//! # Numerics
//! * A basis of `Δ` is `X_j = e_{f_j} − Σ_i e_{d_i} (B_d⁻¹ B_{f_j})_i` with the `K` dependent
//!   variables `d` chosen by complete pivoting at the point; it is evaluated over any dual type, so
//!   brackets `[X, W] = DW·X − DX·W` come from nested forward-mode AD (one [`Dual`] level per
//!   bracket), exact up to rounding.
//! * A bracket adds a direction when its part orthogonal to the span so far exceeds
//!   [`FROBENIUS_TOLERANCE`] times `‖DW·X‖ + ‖DX·W‖` (the size of the terms that cancel in it).
//!   Brackets that add nothing are dropped before the next level; this is exact at regular points
//!   (where the ranks are locally constant), which is where the test is meaningful.
//! * Up to [`MAX_BRACKET_DEPTH`] nested brackets are formed; a closure not reached by then is a
//!   typed error.

use super::PfaffianConstraints;
use crate::error::{all_finite, finite, Error, Result};
use nalgebra::{DMatrix, DVector, SVector};
use num_dual::linalg::LU;
use num_dual::{Dual, Dual64, DualNum};

/// Relative tolerance of the rank decisions of the Frobenius test (see the [module docs](self)).
pub const FROBENIUS_TOLERANCE: f64 = 1e-9;

/// The deepest iterated bracket formed, `[X₁, [X₂, [X₃, [X₄, X₅]]]]`; enough for `K ≤ 4`
/// constraints, since each level adds at least one direction until the closure is reached.
pub const MAX_BRACKET_DEPTH: usize = 4;

/// A residual of the single-form test and its triple of variables `(α, β, γ)`.
pub type TripleResidual = ((usize, usize, usize), f64);

/// The integrable combinations of a set of Pfaffian constraints at a configuration.
#[derive(Clone, Debug, PartialEq)]
pub struct Integrability {
    /// Dimension of the extended space `(q, t)`, `M = N + 1`.
    pub variables: usize,
    /// Dimension of the involutive closure `Δ̄` of the constrained distribution.
    pub closure_dimension: usize,
    /// Deepest bracket that added a direction (0 if `Δ` is involutive).
    pub depth: usize,
    /// Each integrable combination as coefficients `c_r` of the constraint rows.
    pub combinations: Vec<Vec<f64>>,
    /// Each integrable combination as a form `Σ_r c_r ω_r` on `(q, t)` (length `N + 1`, the `dt`
    /// coefficient last), scaled to a largest coefficient of `+1`; proportional to `dφ` of a
    /// holonomic constraint `φ(q, t) = const`.
    pub forms: Vec<Vec<f64>>,
    /// The relative rank tolerance used, [`FROBENIUS_TOLERANCE`].
    pub tolerance: f64,
}

impl Integrability {
    /// Number of integrable combinations (holonomic constraints hidden in the set).
    pub fn count(&self) -> usize {
        self.combinations.len()
    }
}

/// Classification of a set of `K` Pfaffian constraints on `N` coordinates (SPEC M2, M4).
#[derive(Clone, Debug, PartialEq)]
pub struct Classification {
    /// `b = 0` at every sample: no `dt` term [Ardema 2.3].
    pub catastatic: bool,
    /// Nothing depends on `t` explicitly at the samples.
    pub scleronomic: bool,
    /// Number of integrable combinations (the smallest over the samples).
    pub integrable: usize,
    /// All constraints integrable (`integrable = K`).
    pub holonomic: bool,
    /// Degrees of freedom `N − K` [Ardema 2.7].
    pub degrees_of_freedom: usize,
    /// Number of generalized coordinates needed, `N − integrable` [Ardema 5.1].
    pub coordinates: usize,
}

/// The forms `[B | b]` on `y = (q, t)` as a `K × (N + 1)` matrix.
fn form_matrix<P, D, const N: usize, const K: usize>(c: &P, y: &DVector<D>) -> DMatrix<D>
where
    P: PfaffianConstraints<N, K> + ?Sized,
    D: DualNum<f64> + Copy,
{
    let q = SVector::<D, N>::from_fn(|i, _| y[i]);
    let (b, b0) = c.forms(y[N], &q);
    DMatrix::from_fn(K, N + 1, |r, s| if s < N { b[(r, s)] } else { b0[r] })
}

/// Vector fields on the extended space, evaluated over any dual type.
trait Fields {
    fn len(&self) -> usize;
    /// The two terms whose difference is field `i` (the second is zero for base fields).
    fn terms<D: DualNum<f64> + Copy>(
        &self,
        i: usize,
        y: &DVector<D>,
    ) -> Option<(DVector<D>, DVector<D>)>;
    fn eval<D: DualNum<f64> + Copy>(&self, i: usize, y: &DVector<D>) -> Option<DVector<D>> {
        self.terms(i, y).map(|(a, b)| a - b)
    }
}

/// The basis of `Δ = ker [B | b]` by the dependent variables `pivots`.
struct Kernel<'a, P: ?Sized, const N: usize, const K: usize> {
    c: &'a P,
    pivots: Vec<usize>,
    free: Vec<usize>,
}

impl<P: PfaffianConstraints<N, K> + ?Sized, const N: usize, const K: usize> Fields
    for Kernel<'_, P, N, K>
{
    fn len(&self) -> usize {
        self.free.len()
    }
    fn terms<D: DualNum<f64> + Copy>(
        &self,
        i: usize,
        y: &DVector<D>,
    ) -> Option<(DVector<D>, DVector<D>)> {
        let a = form_matrix(self.c, y);
        let ad = DMatrix::from_fn(K, K, |r, j| a[(r, self.pivots[j])]);
        let rhs = DVector::from_fn(K, |r, _| a[(r, self.free[i])]);
        let z = LU::new(ad).ok()?.solve(&rhs);
        let mut x = DVector::from_element(N + 1, D::zero());
        x[self.free[i]] = D::one();
        for (j, &p) in self.pivots.iter().enumerate() {
            x[p] = -z[j];
        }
        Some((x, DVector::from_element(N + 1, D::zero())))
    }
}

/// Brackets `[X_a, W_b]` of base fields with fields of the previous level, for the listed pairs.
struct Bracket<'a, B, F> {
    base: &'a B,
    inner: &'a F,
    pairs: Vec<(usize, usize)>,
}

impl<B: Fields, F: Fields> Fields for Bracket<'_, B, F> {
    fn len(&self) -> usize {
        self.pairs.len()
    }
    fn terms<D: DualNum<f64> + Copy>(
        &self,
        i: usize,
        y: &DVector<D>,
    ) -> Option<(DVector<D>, DVector<D>)> {
        let (a, b) = self.pairs[i];
        let x = self.base.eval(a, y)?;
        let w = self.inner.eval(b, y)?;
        let along = |v: &DVector<D>| y.zip_map(v, |yi, vi| Dual::new(yi, vi));
        let dw_x = self.inner.eval(b, &along(&x))?.map(|d| d.eps);
        let dx_w = self.base.eval(a, &along(&w))?.map(|d| d.eps);
        Some((dw_x, dx_w))
    }
}

/// Gram–Schmidt (twice) of `v` against the orthonormal `span`; appends and returns `true` when
/// the remainder exceeds `tol · scale`.
fn extend_span(span: &mut Vec<DVector<f64>>, v: &DVector<f64>, scale: f64, tol: f64) -> bool {
    let mut r = v.clone();
    for _ in 0..2 {
        for e in span.iter() {
            let d = e.dot(&r);
            r -= e * d;
        }
    }
    let n = r.norm();
    if n > tol * scale && n > 0.0 {
        span.push(r / n);
        true
    } else {
        false
    }
}

/// Next level of the closure: keeps the brackets that add a direction.
fn grow<'a, B: Fields, F: Fields>(
    base: &'a B,
    inner: &'a F,
    same: bool,
    y0: &DVector<f64>,
    span: &mut Vec<DVector<f64>>,
) -> Result<Bracket<'a, B, F>> {
    let m = y0.len();
    let mut level = Bracket {
        base,
        inner,
        pairs: Vec::new(),
    };
    let mut kept = Vec::new();
    for a in 0..base.len() {
        for b in 0..inner.len() {
            if (same && b <= a) || span.len() == m {
                continue;
            }
            level.pairs = vec![(a, b)];
            let (p, q) = level.terms::<f64>(0, y0).ok_or_else(|| {
                Error::invalid(
                    "Pfaffian constraints",
                    "singular where the test is evaluated",
                )
            })?;
            let v = &p - &q;
            all_finite("Lie bracket of constrained fields", v.as_slice())?;
            if extend_span(span, &v, p.norm() + q.norm(), FROBENIUS_TOLERANCE) {
                kept.push((a, b));
            }
        }
    }
    level.pairs = kept;
    Ok(level)
}

/// Complete pivoting on the real forms: the `K` dependent variables, or the dependent rows.
fn pivot_columns(a: &DMatrix<f64>) -> std::result::Result<Vec<usize>, Vec<usize>> {
    let (k, m) = a.shape();
    let mut w = a.clone();
    for r in 0..k {
        let n = w.row(r).norm();
        if n > 0.0 {
            w.row_mut(r).scale_mut(1.0 / n);
        }
    }
    let mut rows: Vec<usize> = (0..k).collect();
    let mut cols: Vec<usize> = (0..m).collect();
    let mut pivots = Vec::new();
    for step in 0..k {
        let mut best = (0.0, step, step);
        for (ri, &r) in rows.iter().enumerate().skip(step) {
            for (ci, &c) in cols.iter().enumerate().skip(step) {
                if w[(r, c)].abs() > best.0 {
                    best = (w[(r, c)].abs(), ri, ci);
                }
            }
        }
        if best.0.is_nan() || best.0 <= super::RANK_TOLERANCE {
            return Err(rows[step..].to_vec());
        }
        rows.swap(step, best.1);
        cols.swap(step, best.2);
        let (pr, pc) = (rows[step], cols[step]);
        pivots.push(pc);
        for &r in &rows[step + 1..] {
            let f = w[(r, pc)] / w[(pr, pc)];
            for c in 0..m {
                w[(r, c)] -= f * w[(pr, c)];
            }
        }
    }
    Ok(pivots)
}

fn check_point<const N: usize>(t: f64, q: &SVector<f64, N>) -> Result<DVector<f64>> {
    finite("t", t)?;
    all_finite("q", q.as_slice())?;
    Ok(DVector::from_fn(N + 1, |i, _| if i < N { q[i] } else { t }))
}

/// The integrable combinations of the Pfaffian constraints `c` at `(t, q)` (see the
/// [module docs](self)).
///
/// # Errors
/// NaN/∞ in the input or in the forms; [`Error::RankDeficient`] naming the dependent rows when the
/// forms are linearly dependent at the configuration (SPEC X7); [`Error::NotConverged`] when the
/// closure needs brackets deeper than [`MAX_BRACKET_DEPTH`].
pub fn integrable_combinations<P, const N: usize, const K: usize>(
    c: &P,
    t: f64,
    q: &SVector<f64, N>,
) -> Result<Integrability>
where
    P: PfaffianConstraints<N, K> + ?Sized,
{
    let y0 = check_point(t, q)?;
    let m = N + 1;
    let a = form_matrix(c, &y0);
    all_finite(
        format!("Pfaffian coefficients [B | b] at t = {t}, q = {q:?}"),
        a.as_slice(),
    )?;
    let pivots = pivot_columns(&a).map_err(|mut rows| {
        rows.sort_unstable();
        Error::RankDeficient {
            what: "Pfaffian constraint matrix [B | b]".into(),
            rows,
            t,
            at: format!("q = {q:?}"),
            tolerance: super::RANK_TOLERANCE,
        }
    })?;
    let free: Vec<usize> = (0..m).filter(|i| !pivots.contains(i)).collect();
    let base = Kernel::<P, N, K> { c, pivots, free };
    let mut span = Vec::new();
    for i in 0..base.len() {
        let v = base.eval::<f64>(i, &y0).ok_or_else(|| {
            Error::invalid(
                "Pfaffian constraints",
                "singular where the test is evaluated",
            )
        })?;
        all_finite("constrained field", v.as_slice())?;
        extend_span(&mut span, &v, v.norm(), FROBENIUS_TOLERANCE);
    }
    let mut depth = 0;
    let full_or_fixed = |span: &Vec<DVector<f64>>, added: usize| span.len() == m || added == 0;
    // Levels written out: each nests one more dual number in the evaluation of the base fields.
    let l2 = grow(&base, &base, true, &y0, &mut span)?;
    if l2.len() > 0 {
        depth = 1;
    }
    if !full_or_fixed(&span, l2.len()) {
        let l3 = grow(&base, &l2, false, &y0, &mut span)?;
        if l3.len() > 0 {
            depth = 2;
        }
        if !full_or_fixed(&span, l3.len()) {
            let l4 = grow(&base, &l3, false, &y0, &mut span)?;
            if l4.len() > 0 {
                depth = 3;
            }
            if !full_or_fixed(&span, l4.len()) {
                let l5 = grow(&base, &l4, false, &y0, &mut span)?;
                if l5.len() > 0 {
                    depth = 4;
                }
                if !full_or_fixed(&span, l5.len()) {
                    return Err(Error::NotConverged {
                        what: format!(
                            "involutive closure of the constrained distribution at t = {t}, \
                             q = {q:?} (brackets up to depth {MAX_BRACKET_DEPTH})"
                        ),
                        iterations: MAX_BRACKET_DEPTH,
                        residual: (m - span.len()) as f64,
                    });
                }
            }
        }
    }
    let r = span.len();
    let count = m - r;
    // Annihilator of the closure within the span of the (row-normalised) forms.
    let norms: Vec<f64> = (0..K).map(|i| a.row(i).norm()).collect();
    let a_hat = DMatrix::from_fn(K, m, |i, j| a[(i, j)] / norms[i]);
    let w = DMatrix::from_fn(m, K.max(r), |i, j| if j < r { span[j][i] } else { 0.0 });
    let g = &a_hat * w;
    let svd = g.svd(true, false);
    let u = svd
        .u
        .ok_or_else(|| Error::invalid("Frobenius test", "SVD failed"))?;
    let mut order: Vec<usize> = (0..K).collect();
    order.sort_by(|&i, &j| svd.singular_values[i].total_cmp(&svd.singular_values[j]));
    let mut combinations = Vec::new();
    let mut forms = Vec::new();
    for &k in order.iter().take(count) {
        let ch = u.column(k);
        let form = a_hat.transpose() * ch;
        let (imax, _) =
            form.iter().enumerate().fold(
                (0, 0.0),
                |b, (i, v)| if v.abs() > b.1 { (i, v.abs()) } else { b },
            );
        let s = form[imax];
        forms.push(form.iter().map(|v| v / s).collect());
        combinations.push((0..K).map(|i| ch[i] / norms[i] / s).collect());
    }
    Ok(Integrability {
        variables: m,
        closure_dimension: r,
        depth,
        combinations,
        forms,
        tolerance: FROBENIUS_TOLERANCE,
    })
}

/// The single-form test (SPEC M3) for constraint row `row` as a form on `y = (q, t)`: for every
/// triple `α < β < γ` of variables (time last),
/// `A_α(∂A_β/∂y_γ − ∂A_γ/∂y_β) + A_β(∂A_γ/∂y_α − ∂A_α/∂y_γ) + A_γ(∂A_α/∂y_β − ∂A_β/∂y_α)`
/// [Ardema eq. 2.25]; the form is integrable iff all vanish identically. For three variables the
/// one residual is `−A · curl A`.
///
/// # Errors
/// NaN/∞ in the input or the forms; `row ≥ K`.
pub fn form_integrability_residuals<P, const N: usize, const K: usize>(
    c: &P,
    row: usize,
    t: f64,
    q: &SVector<f64, N>,
) -> Result<Vec<TripleResidual>>
where
    P: PfaffianConstraints<N, K> + ?Sized,
{
    let y0 = check_point(t, q)?;
    if row >= K {
        return Err(Error::invalid(
            "constraint row",
            format!("{row} is not below the number of constraints {K}"),
        ));
    }
    let m = N + 1;
    let a = form_matrix(c, &y0).row(row).transpose();
    let mut jac = DMatrix::zeros(m, m);
    for g in 0..m {
        let yd = DVector::from_fn(m, |i, _| Dual64::new(y0[i], if i == g { 1.0 } else { 0.0 }));
        let ad = form_matrix(c, &yd);
        for al in 0..m {
            jac[(al, g)] = ad[(row, al)].eps;
        }
    }
    all_finite("form coefficients", a.as_slice())?;
    all_finite("form derivatives", jac.as_slice())?;
    let mut out = Vec::new();
    for al in 0..m {
        for be in al + 1..m {
            for ga in be + 1..m {
                let r = a[al] * (jac[(be, ga)] - jac[(ga, be)])
                    + a[be] * (jac[(ga, al)] - jac[(al, ga)])
                    + a[ga] * (jac[(al, be)] - jac[(be, al)]);
                out.push(((al, be, ga), r));
            }
        }
    }
    Ok(out)
}

/// Classify the constraints from their values at the sample configurations `(t, q)` (SPEC M2,
/// M4): catastatic and scleronomic when `|b_r|`, respectively `|∂B_rs/∂t|` and `|∂b_r/∂t|`, are at
/// most [`FROBENIUS_TOLERANCE`] times the row norm at every sample; integrable combinations by
/// [`integrable_combinations`] (the smallest count over the samples).
///
/// # Errors
/// No samples; any error of [`integrable_combinations`].
pub fn classify<P, const N: usize, const K: usize>(
    c: &P,
    samples: &[(f64, SVector<f64, N>)],
) -> Result<Classification>
where
    P: PfaffianConstraints<N, K> + ?Sized,
{
    if samples.is_empty() {
        return Err(Error::invalid(
            "samples",
            "at least one configuration is needed",
        ));
    }
    let (mut catastatic, mut scleronomic, mut integrable) = (true, true, K);
    for (t, q) in samples {
        let y0 = check_point(*t, q)?;
        let a = form_matrix(c, &y0);
        let yt = DVector::from_fn(N + 1, |i, _| {
            Dual64::new(y0[i], if i == N { 1.0 } else { 0.0 })
        });
        let at = form_matrix(c, &yt);
        for r in 0..K {
            let n = a.row(r).norm();
            catastatic &= a[(r, N)].abs() <= FROBENIUS_TOLERANCE * n;
            scleronomic &= (0..=N).all(|s| at[(r, s)].eps.abs() <= FROBENIUS_TOLERANCE * n);
        }
        integrable = integrable.min(integrable_combinations(c, *t, q)?.count());
    }
    Ok(Classification {
        catastatic,
        scleronomic,
        integrable,
        holonomic: integrable == K,
        degrees_of_freedom: N - K,
        coordinates: N - integrable,
    })
}

//! Constraints given by expressions. Holonomic: `K` functions `g_r(t, q)` of the time and named
//! coordinates with
//!
//! ```math
//! g_r(t, q) = 0,\qquad r = 1, \dots, K
//! ```
//!
//! [Ardema, *Analytical Dynamics*, 2005, §2.3, eq. 2.14], a
//! [`HolonomicConstraints`] set: their Pfaffian form `∂g/∂q · q̇ + ∂g/∂t = 0` is
//! [`Differentiated`](crate::constraints::Differentiated), which the multiplier form of
//! Lagrange's equations (`nonholonomic::Constrained`) takes, and RATTLE takes them with a
//! Hamiltonian (`integrate::ConstrainedHamiltonian`).
//!
//! Pfaffian (non-holonomic in general): `K × N` coefficients `a_rs(t, q)` and `K` terms
//! `b_r(t, q)` with
//!
//! ```math
//! \sum_{s=1}^{N} a_{rs}(t, q)\,\dot q_s + b_r(t, q) = 0,\qquad r = 1, \dots, K
//! ```
//!
//! [Ardema, *Analytical Dynamics*, 2005, §5.2, eq. 5.13; Hamel, *Theoretische Mechanik*, 1949,
//! art. 228 (I)], a [`PfaffianConstraints`] set ([`ExpressionPfaffian`]): the multiplier form
//! (`nonholonomic::Constrained`), its constrained integrators and the integrability test
//! (`constraints::classify`) take it as they take a Rust-written one.

use super::{Expression, MAX_DOF};
use crate::constraints::{HolonomicConstraints, PfaffianConstraints};
use crate::error::{Error, Result};
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// `K` holonomic constraints `g_r(t, q) = 0` given by expressions (see the
/// [module docs](self)).
#[derive(Clone, Debug)]
pub struct ExpressionConstraints<const N: usize, const K: usize> {
    g: Vec<Expression>,
}

impl<const N: usize, const K: usize> ExpressionConstraints<N, K> {
    /// The constraints `texts` (`K` expressions) in `t`, the `coordinates` (`N` names) and the
    /// `parameters` with their values.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for `N` outside `1 … MAX_DOF`, `K` not in `1 … N − 1`, a number of
    /// names that is not `N` or of texts that is not `K`; the errors of [`Expression::new`].
    pub fn new(texts: &[&str], coordinates: &[&str], parameters: &[(&str, f64)]) -> Result<Self> {
        let names = configuration_variables::<N>(coordinates)?;
        if K == 0 || K >= N {
            return Err(Error::invalid(
                "constraints",
                format!("{K} on {N} coordinates; 1 … {} leave a motion", N - 1),
            ));
        }
        if texts.len() != K {
            return Err(Error::invalid(
                "constraints",
                format!("{} expressions for {K} constraints", texts.len()),
            ));
        }
        let g = texts
            .iter()
            .map(|text| Expression::new(text, &names, parameters))
            .collect::<Result<Vec<_>>>()?;
        Ok(Self { g })
    }

    /// The expressions `g_r`; their variables are `t` and the coordinates.
    pub fn expressions(&self) -> &[Expression] {
        &self.g
    }

    /// `g(t, q)` on reals.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite input or value (naming the expression and the
    /// state).
    pub fn value(&self, t: f64, q: &SVector<f64, N>) -> Result<SVector<f64, K>> {
        let mut x = vec![t];
        x.extend_from_slice(q.as_slice());
        let mut g = SVector::zeros();
        for (r, e) in self.g.iter().enumerate() {
            g[r] = e.value(&x)?;
        }
        Ok(g)
    }
}

/// The variables `t, q₁, …, q_N` of an expression on the configuration space.
///
/// # Errors
/// [`Error::InvalidInput`] for `N` outside `1 … MAX_DOF` or a number of names that is not `N`.
pub(super) fn configuration_variables<'a, const N: usize>(
    coordinates: &[&'a str],
) -> Result<Vec<&'a str>> {
    if N == 0 || N > MAX_DOF {
        return Err(Error::invalid(
            "degrees of freedom",
            format!("{N}; expression systems have 1 … {MAX_DOF}"),
        ));
    }
    if coordinates.len() != N {
        return Err(Error::invalid(
            "coordinates",
            format!("{} names for {N} coordinates", coordinates.len()),
        ));
    }
    Ok(std::iter::once("t")
        .chain(coordinates.iter().copied())
        .collect())
}

impl<const N: usize, const K: usize> HolonomicConstraints<N, K> for ExpressionConstraints<N, K> {
    #[inline]
    fn position_constraint<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
    ) -> SVector<D, K> {
        let mut x = [t; 1 + MAX_DOF];
        x[1..=N].copy_from_slice(q.as_slice());
        SVector::from_fn(|r, _| self.g[r].eval(&x[..=N]))
    }
}

/// `K` Pfaffian constraints `Σ_s a_rs(t, q) q̇_s + b_r(t, q) = 0` given by expressions (see the
/// [module docs](self)); [`PfaffianConstraints::forms`] is `(a, b)`.
#[derive(Clone, Debug)]
pub struct ExpressionPfaffian<const N: usize, const K: usize> {
    /// `a_rs`, row by row.
    a: Vec<Expression>,
    /// `b_r`; `None` for `b = 0` (catastatic constraints).
    b: Option<Vec<Expression>>,
}

impl<const N: usize, const K: usize> ExpressionPfaffian<N, K> {
    /// The constraints with coefficient rows `rows` (`K` rows of `N` expressions `a_rs`) and
    /// terms `rhs` (`K` expressions `b_r`; `None` for `b = 0`) in `t`, the `coordinates` (`N`
    /// names) and the `parameters` with their values.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for `N` outside `1 … MAX_DOF`, `K` not in `1 … N − 1`, a number
    /// of names that is not `N`, of rows or terms that is not `K`, of entries in a row that is
    /// not `N` (naming the row); the errors of [`Expression::new`], naming the entry.
    pub fn new<R, S>(
        rows: &[R],
        rhs: Option<&[S]>,
        coordinates: &[&str],
        parameters: &[(&str, f64)],
    ) -> Result<Self>
    where
        R: AsRef<[S]>,
        S: AsRef<str>,
    {
        let names = configuration_variables::<N>(coordinates)?;
        if K == 0 || K >= N {
            return Err(Error::invalid(
                "Pfaffian constraints",
                format!("{K} on {N} coordinates; 1 … {} leave a motion", N - 1),
            ));
        }
        if rows.len() != K {
            return Err(Error::invalid(
                "Pfaffian constraints",
                format!("{} rows for {K} constraints", rows.len()),
            ));
        }
        let compile = |text: &str, what: String| {
            Expression::new(text, &names, parameters).map_err(|e| e.in_entry(&what))
        };
        let mut a = Vec::with_capacity(K * N);
        for (r, row) in rows.iter().enumerate() {
            let row = row.as_ref();
            if row.len() != N {
                return Err(Error::invalid(
                    format!("Pfaffian constraint row {}", r + 1),
                    format!("{} coefficients for {N} coordinates", row.len()),
                ));
            }
            for (s, text) in row.iter().enumerate() {
                a.push(compile(text.as_ref(), format!("a[{}][{}]", r + 1, s + 1))?);
            }
        }
        let b = match rhs {
            None => None,
            Some(rhs) if rhs.len() != K => {
                return Err(Error::invalid(
                    "Pfaffian constraint terms b",
                    format!("{} expressions for {K} constraints", rhs.len()),
                ))
            }
            Some(rhs) => Some(
                rhs.iter()
                    .enumerate()
                    .map(|(r, text)| compile(text.as_ref(), format!("b[{}]", r + 1)))
                    .collect::<Result<Vec<_>>>()?,
            ),
        };
        Ok(Self { a, b })
    }

    /// The expression `a_rs` (0-based `r`, `s`), or `None` out of range.
    pub fn coefficient(&self, r: usize, s: usize) -> Option<&Expression> {
        (r < K && s < N).then(|| &self.a[r * N + s])
    }

    /// The expression `b_r` (0-based), or `None` out of range or for `b = 0`.
    pub fn term(&self, r: usize) -> Option<&Expression> {
        self.b.as_ref().and_then(|b| b.get(r))
    }

    /// `(a(t, q), b(t, q))` on reals.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite input, or a non-finite entry (naming the entry, its
    /// expression and the state).
    pub fn value(
        &self,
        t: f64,
        q: &SVector<f64, N>,
    ) -> Result<(SMatrix<f64, K, N>, SVector<f64, K>)> {
        crate::error::finite("t", t)?;
        crate::error::all_finite("q", q.as_slice())?;
        let mut x = vec![t];
        x.extend_from_slice(q.as_slice());
        let mut a = SMatrix::zeros();
        for r in 0..K {
            for s in 0..N {
                a[(r, s)] = self.a[r * N + s]
                    .value(&x)
                    .map_err(|e| e.in_entry(&format!("a[{}][{}]", r + 1, s + 1)))?;
            }
        }
        let mut b = SVector::zeros();
        if let Some(terms) = &self.b {
            for (r, e) in terms.iter().enumerate() {
                b[r] = e
                    .value(&x)
                    .map_err(|e| e.in_entry(&format!("b[{}]", r + 1)))?;
            }
        }
        Ok((a, b))
    }

    /// The check of a configuration: the coefficients finite and the rows independent
    /// ([`crate::constraints::dependent_rows`] at
    /// [`RANK_TOLERANCE`](crate::constraints::RANK_TOLERANCE)).
    ///
    /// # Errors
    /// As [`ExpressionPfaffian::value`]; [`Error::RankDeficient`] naming the rows (0-based) that
    /// depend on the rows before them.
    pub fn check_configuration(&self, t: f64, q: &SVector<f64, N>) -> Result<()> {
        let (a, _) = self.value(t, q)?;
        crate::constraints::check_rank(&a, "Pfaffian constraint rows a(t, q)", t, || {
            format!("q = {q:?}")
        })
    }
}

impl<const N: usize, const K: usize> PfaffianConstraints<N, K> for ExpressionPfaffian<N, K> {
    #[inline]
    fn forms<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
    ) -> (SMatrix<D, K, N>, SVector<D, K>) {
        let mut x = [t; 1 + MAX_DOF];
        x[1..=N].copy_from_slice(q.as_slice());
        let x = &x[..=N];
        let a = SMatrix::from_fn(|r, s| self.a[r * N + s].eval(x));
        let b = match &self.b {
            Some(terms) => SVector::from_fn(|r, _| terms[r].eval(x)),
            None => SVector::zeros(),
        };
        (a, b)
    }
}

/// An error of an expression, its message naming the matrix entry it belongs to.
trait InEntry {
    fn in_entry(self, entry: &str) -> Error;
}

impl InEntry for Error {
    fn in_entry(self, entry: &str) -> Error {
        match self {
            Error::NonFinite { what, value } => Error::NonFinite {
                what: format!("{entry} = {what}"),
                value,
            },
            Error::Parse {
                expression,
                column,
                reason,
            } => Error::Parse {
                expression,
                column,
                reason: format!("{reason} (in {entry})"),
            },
            Error::InvalidInput { what, reason } => Error::InvalidInput {
                what: format!("{what} (in {entry})"),
                reason,
            },
            e => e,
        }
    }
}

//! Truncated multivariate power series as a number type.
//!
//! A [`Series`] is the truncated Taylor polynomial
//!
//! ```math
//! s(x) = \sum_{|\alpha| \le K} s_\alpha\, x^\alpha,\qquad x \in \mathbb R^n,
//! ```
//!
//! of the differential algebra `ₖDₙ` (Berz): sums, products and elementary functions act on the
//! coefficients exactly as on the Taylor expansions they represent, with every term of degree
//! `> K` dropped. It implements [`DualNum<f64>`](num_dual::DualNum) + `Copy` + `Send` + `Sync`,
//! so a system written once for the crate's number types (a [`Hamiltonian`], a generating
//! function, a perturbation) evaluates on it unchanged and returns its Taylor expansion to degree
//! `K` about the point where it is evaluated.
//!
//! # Storage
//! Values are `Copy` handles into a thread-local arena opened by [`scope`]; every value dies with
//! its scope. The choice against inline, const-generic coefficient arrays: at `n = 4` one value
//! holds `C(4 + K, 4)` coefficients, 8 KiB at `K = 10` and 160 KiB at `K = 24` — a few of those in
//! an `SVector` already exceed a 2 MiB thread stack, and every `Copy` would move them; a handle is
//! 16 bytes at any degree and the arena is one growing `Vec`. Using a handle outside its scope
//! cannot give a wrong number: the result is *poisoned* and the scope returns an error (see
//! [`scope`]).
//!
//! # Example
//! ```
//! use hamilton_jacobi::series::scope;
//! use hamilton_jacobi::DualNum;
//! // exp(x + y) to degree 4 about 0: the coefficient of x²y is 1/(2!·1!) = 1/2.
//! let c = scope(2, 4, |s| {
//!     let (x, y) = (s.variable(0)?, s.variable(1)?);
//!     s.polynomial((x + y).exp())?.coefficient(&[2, 1])
//! })
//! .unwrap()
//! .unwrap();
//! assert!((c - 0.5).abs() < 1e-15);
//! ```
//!
//! [`Hamiltonian`]: crate::Hamiltonian

mod arena;
pub(crate) mod ball;
mod elementary;
mod monomials;
mod number;
pub mod poisson;
pub mod recurrences;

pub use arena::{Series, MAX_ARENA_COEFFICIENTS};
pub use monomials::{Monomials, MAX_ADDRESS_TABLE, MAX_SERIES_COEFFICIENTS, MAX_SERIES_DEGREE};
pub use poisson::{fourier_taylor, FourierTaylor, Harmonic};

pub(crate) use elementary::power_by_squaring;

pub(crate) use number::number_traits;

use crate::error::{Error, Result};
use arena::{in_arena, with_arena, Operand, CONST, POISON};
use nalgebra::SVector;
use std::marker::PhantomData;
use std::sync::Arc;

/// Run `f` with the series of `n` variables to total degree `degree`; all values made inside die
/// when `f` returns.
///
/// # Errors
/// * `n = 0`, `degree >` [`MAX_SERIES_DEGREE`], or storage beyond [`MAX_SERIES_COEFFICIENTS`]
///   per value or [`MAX_ADDRESS_TABLE`] per address table: a typed error before any allocation;
/// * a value used outside the scope that made it (another scope, another thread), the remainder
///   `%` of non-constant series, or more than [`MAX_ARENA_COEFFICIENTS`] coefficients stored:
///   [`Error::InvalidInput`] naming the fault, even when `f` returned.
pub fn scope<R>(n: usize, degree: usize, f: impl FnOnce(&Scope) -> R) -> Result<R> {
    scope_with(Monomials::shared(n, degree)?, f)
}

/// [`scope`] with monomial tables already built (shared by many scopes).
pub fn scope_with<R>(table: Arc<Monomials>, f: impl FnOnce(&Scope) -> R) -> Result<R> {
    let t = table.clone();
    let (r, fault) = in_arena(table, |id| {
        f(&Scope {
            id,
            table: t,
            _not_send: PhantomData,
        })
    });
    match fault {
        None => Ok(r),
        Some(reason) => Err(Error::InvalidInput {
            what: "series scope".into(),
            reason,
        }),
    }
}

/// The variables and accessors of one [`scope`] (not `Send`: the values live on its thread).
pub struct Scope {
    id: u32,
    table: Arc<Monomials>,
    _not_send: PhantomData<*const ()>,
}

impl Scope {
    /// The monomial tables (number of variables, degree, graded order).
    pub fn monomials(&self) -> &Arc<Monomials> {
        &self.table
    }

    /// The variable `x_i` (`0 ≤ i < n`): the series with the single coefficient 1 at `e_i`.
    pub fn variable(&self, i: usize) -> Result<Series> {
        self.variable_at(i, 0.0)
    }

    /// All `n` variables `x_0, …, x_{n−1}`.
    pub fn variables(&self) -> Result<Vec<Series>> {
        (0..self.table.variables())
            .map(|i| self.variable(i))
            .collect()
    }

    /// The series `x₀ + x_i` (a variable about the point `x₀`).
    pub fn variable_at(&self, i: usize, x0: f64) -> Result<Series> {
        let n = self.table.variables();
        if i >= n {
            return Err(Error::OutOfDomain {
                what: "series variable index".into(),
                value: i as f64,
                domain: format!("0 ≤ i < n = {n}"),
            });
        }
        let unit = self.table.variable_index(i);
        let s = with_arena(|ar| {
            ar.push_with(|_, _, out, _| {
                out[0] = x0;
                if let Some(k) = unit {
                    out[k] = 1.0;
                }
            })
        })
        .unwrap_or_else(Series::poison);
        if s.is_poisoned() {
            return Err(self.fault());
        }
        Ok(s)
    }

    /// The series with the coefficients of `p` (same `n` and `K`).
    pub fn lift(&self, p: &Polynomial) -> Result<Series> {
        if p.monomials.variables() != self.table.variables()
            || p.monomials.degree() != self.table.degree()
        {
            return Err(Error::InvalidInput {
                what: "polynomial lifted into a series scope".into(),
                reason: format!(
                    "it has n = {}, K = {}; the scope has n = {}, K = {}",
                    p.monomials.variables(),
                    p.monomials.degree(),
                    self.table.variables(),
                    self.table.degree()
                ),
            });
        }
        self.store(&p.coefficients)
    }

    fn store(&self, c: &[f64]) -> Result<Series> {
        let s = with_arena(|ar| ar.push(c)).unwrap_or_else(Series::poison);
        if s.is_poisoned() {
            return Err(self.fault());
        }
        Ok(s)
    }

    fn fault(&self) -> Error {
        let reason = with_arena(|ar| {
            ar.fault
                .get_or_insert_with(|| {
                    "a poisoned series value (made outside this scope, e.g. on another thread, or \
                     derived from such a value) was read"
                        .into()
                })
                .clone()
        })
        .unwrap_or_else(|| "the series value belongs to no open scope".into());
        Error::InvalidInput {
            what: "series value".into(),
            reason,
        }
    }

    /// The coefficients of `s` as an owned [`Polynomial`] (which outlives the scope).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when `s` is poisoned or belongs to another scope. NaN or infinite
    /// coefficients (from a function that is not analytic at the expansion point) are kept; see
    /// [`Polynomial::check_finite`].
    pub fn polynomial(&self, s: Series) -> Result<Polynomial> {
        let coefficients = match s.slot {
            CONST => {
                let mut c = vec![0.0; self.table.len()];
                c[0] = s.re;
                c
            }
            POISON => return Err(self.fault()),
            _ if s.scope != self.id => {
                return Err(Error::InvalidInput {
                    what: "series value".into(),
                    reason: "used outside the scope that created it".into(),
                })
            }
            _ => with_arena(|ar| match ar.resolve(&s) {
                Some(op @ Operand::Slot(_)) => Some(ar.dense(&op)),
                _ => None,
            })
            .flatten()
            .ok_or_else(|| self.fault())?,
        };
        Ok(Polynomial {
            monomials: self.table.clone(),
            coefficients,
        })
    }

    /// The coefficients of `s` into `out` (resized to the table length; no allocation when
    /// its capacity suffices). Errors as [`Scope::polynomial`].
    pub(crate) fn coefficients_into(&self, s: Series, out: &mut Vec<f64>) -> Result<()> {
        let len = self.table.len();
        out.clear();
        match s.slot {
            CONST => {
                out.resize(len, 0.0);
                out[0] = s.re;
                Ok(())
            }
            POISON => Err(self.fault()),
            _ if s.scope != self.id => Err(Error::InvalidInput {
                what: "series value".into(),
                reason: "used outside the scope that created it".into(),
            }),
            _ => with_arena(|ar| match ar.resolve(&s) {
                Some(Operand::Slot(start)) => {
                    out.extend_from_slice(ar.slice(start));
                    true
                }
                _ => false,
            })
            .filter(|&ok| ok)
            .map(|_| ())
            .ok_or_else(|| self.fault()),
        }
    }
}

/// A truncated polynomial `Σ_{|α| ≤ K} c_α x^α` with its coefficients in graded order
/// ([`Monomials`]); the owned form of a [`Series`].
#[derive(Clone, Debug)]
pub struct Polynomial {
    monomials: Arc<Monomials>,
    coefficients: Vec<f64>,
}

impl Polynomial {
    /// The zero polynomial of `n` variables to degree `degree`.
    pub fn zero(n: usize, degree: usize) -> Result<Self> {
        let monomials = Arc::new(Monomials::new(n, degree)?);
        let coefficients = vec![0.0; monomials.len()];
        Ok(Self {
            monomials,
            coefficients,
        })
    }

    /// The monomial tables.
    pub fn monomials(&self) -> &Arc<Monomials> {
        &self.monomials
    }

    /// Number of variables `n`.
    pub fn variables(&self) -> usize {
        self.monomials.variables()
    }

    /// Truncation degree `K`.
    pub fn degree(&self) -> usize {
        self.monomials.degree()
    }

    /// All coefficients in graded order.
    pub fn coefficients(&self) -> &[f64] {
        &self.coefficients
    }

    /// Mutable coefficients in graded order.
    pub fn coefficients_mut(&mut self) -> &mut [f64] {
        &mut self.coefficients
    }

    /// The coefficient `c_α` of the monomial `x^α`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when `α` has not `n` entries or `|α| > K`.
    pub fn coefficient(&self, alpha: &[u32]) -> Result<f64> {
        self.monomials
            .index_of(alpha)
            .map(|i| self.coefficients[i])
            .ok_or_else(|| Error::InvalidInput {
                what: "multi-index".into(),
                reason: format!(
                    "{alpha:?} is not a monomial of {} variables of degree ≤ {}",
                    self.variables(),
                    self.degree()
                ),
            })
    }

    /// The homogeneous part of degree `d`, `Σ_{|α| = d} c_α x^α` (zero beyond `K`).
    pub fn part(&self, d: usize) -> Polynomial {
        let mut c = vec![0.0; self.coefficients.len()];
        for i in self.monomials.of_degree(d) {
            c[i] = self.coefficients[i];
        }
        Polynomial {
            monomials: self.monomials.clone(),
            coefficients: c,
        }
    }

    /// The largest `|c_α|` over `|α| = d`.
    pub fn part_norm(&self, d: usize) -> f64 {
        self.monomials
            .of_degree(d)
            .map(|i| self.coefficients[i].abs())
            .fold(0.0, f64::max)
    }

    /// The terms `(α, c_α)` with `c_α ≠ 0`, graded order.
    pub fn terms(&self) -> impl Iterator<Item = (&[u8], f64)> + '_ {
        self.coefficients
            .iter()
            .enumerate()
            .filter(|(_, &c)| c != 0.0)
            .map(|(i, &c)| (self.monomials.exps(i), c))
    }

    /// The value `Σ c_α x^α` at `x`.
    ///
    /// # Errors
    /// A point of the wrong length or with a NaN/∞ entry; a non-finite value.
    pub fn eval(&self, x: &[f64]) -> Result<f64> {
        let n = self.variables();
        if x.len() != n {
            return Err(Error::InvalidInput {
                what: "evaluation point".into(),
                reason: format!("has {} entries, the polynomial {n} variables", x.len()),
            });
        }
        crate::error::all_finite("evaluation point", x)?;
        let k = self.degree();
        let powers: Vec<Vec<f64>> = x
            .iter()
            .map(|&xi| {
                let mut p = vec![1.0; k + 1];
                for j in 1..=k {
                    p[j] = p[j - 1] * xi;
                }
                p
            })
            .collect();
        let mut sum = 0.0;
        for (i, &c) in self.coefficients.iter().enumerate() {
            if c == 0.0 {
                continue;
            }
            let mut m = c;
            for (v, &e) in self.monomials.exps(i).iter().enumerate() {
                m *= powers[v][e as usize];
            }
            sum += m;
        }
        crate::error::finite("polynomial value", sum)
    }

    /// The gradient at the expansion point, `∂s/∂x_i(0) = c_{e_i}`.
    pub fn gradient(&self) -> Vec<f64> {
        let n = self.variables();
        (0..n)
            .map(|i| {
                let mut a = vec![0u32; n];
                a[i] = 1;
                self.coefficient(&a).unwrap_or(0.0)
            })
            .collect()
    }

    /// The Hessian at the expansion point, `∂²s/∂x_i∂x_j(0) = (1 + δ_ij) c_{e_i + e_j}`.
    pub fn hessian(&self) -> Vec<Vec<f64>> {
        let n = self.variables();
        (0..n)
            .map(|i| {
                (0..n)
                    .map(|j| {
                        let mut a = vec![0u32; n];
                        a[i] += 1;
                        a[j] += 1;
                        let c = self.coefficient(&a).unwrap_or(0.0);
                        if i == j {
                            2.0 * c
                        } else {
                            c
                        }
                    })
                    .collect()
            })
            .collect()
    }

    /// The partial derivative `∂s/∂x_v`, a polynomial of degree `≤ K − 1` (same tables):
    ///
    /// ```math
    /// \frac{\partial}{\partial x_v} \sum_{|\alpha| \le K} c_\alpha x^\alpha
    /// = \sum_{|\alpha| \le K,\ \alpha_v \ge 1} \alpha_v\, c_\alpha\, x^{\alpha - e_v}.
    /// ```
    ///
    /// Of a truncated Taylor polynomial it is the Taylor polynomial of the derivative to degree
    /// `K − 1` (Berz 1999, §2.3: the derivation `∂_v` of the differential algebra).
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `v ≥ n`; [`Error::NonFinite`] for a non-finite coefficient of
    /// the result.
    pub fn derivative(&self, v: usize) -> Result<Polynomial> {
        let n = self.variables();
        if v >= n {
            return Err(Error::OutOfDomain {
                what: "derivative variable index".into(),
                value: v as f64,
                domain: format!("0 ≤ v < n = {n}"),
            });
        }
        let mut c = vec![0.0; self.coefficients.len()];
        self.monomials.derivative(&self.coefficients, v, &mut c);
        Polynomial {
            monomials: self.monomials.clone(),
            coefficients: c,
        }
        .check_finite("the derivative's expansion point")
    }

    /// The Poisson bracket in the canonical variables `q_i = x_i`, `p_i = x_{N+i}` (`N` =
    /// `dof`, `2N ≤ n`; further variables are parameters), truncated at degree `degree`:
    ///
    /// ```math
    /// \{f, g\} = \sum_{i=1}^{N} \left( \frac{\partial f}{\partial q_i}\frac{\partial g}{\partial p_i}
    /// - \frac{\partial f}{\partial p_i}\frac{\partial g}{\partial q_i} \right).
    /// ```
    ///
    /// For truncated Taylor polynomials of degree `K` the bracket is exact to degree `K − 1` (each
    /// derivative loses the top degree); asking for `degree ≤ K − 1` forms only the products
    /// needed. The sign convention is that of [`crate::brackets::poisson_bracket`]
    /// (Ardema 2005, eq. 15.25): `{q_i, p_j} = δ_ij`, and `{f, H} = df/dt` along the motion of
    /// `H`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] when `g` has another number of variables or degree, or `dof = 0`
    /// or `2·dof > n`; [`Error::NonFinite`] for a non-finite coefficient of the result.
    pub fn poisson_bracket(&self, g: &Polynomial, dof: usize, degree: usize) -> Result<Polynomial> {
        let (n, k) = (self.variables(), self.degree());
        if g.variables() != n || g.degree() != k {
            return Err(Error::InvalidInput {
                what: "Poisson bracket operands".into(),
                reason: format!(
                    "n = {n}, K = {k} against n = {}, K = {}",
                    g.variables(),
                    g.degree()
                ),
            });
        }
        if dof == 0 || dof.saturating_mul(2) > n {
            return Err(Error::InvalidInput {
                what: "Poisson bracket degrees of freedom".into(),
                reason: format!("need 1 ≤ N and 2N ≤ n = {n}, got N = {dof}"),
            });
        }
        let mut out = vec![0.0; self.coefficients.len()];
        LieOperator::new(g, dof).apply(&self.coefficients, &mut out, degree);
        Polynomial {
            monomials: self.monomials.clone(),
            coefficients: out,
        }
        .check_finite("the bracket's expansion point")
    }

    /// `Ok(self)` when every coefficient is finite; otherwise [`Error::NonFinite`] naming the
    /// first offending monomial and `at` (the expansion point).
    pub fn check_finite(self, at: &str) -> Result<Self> {
        if let Some((i, &c)) = self
            .coefficients
            .iter()
            .enumerate()
            .find(|(_, c)| !c.is_finite())
        {
            return Err(Error::NonFinite {
                what: format!(
                    "Taylor coefficient of x^{:?} about {at} (the function is not analytic there)",
                    self.monomials.exps(i)
                ),
                value: c,
            });
        }
        Ok(self)
    }
}

/// The Lie operator `L_g f = {f, g}` of a fixed polynomial `g` in `N` degrees of freedom, for
/// repeated application ([`Polynomial::poisson_bracket`], the Lie series of
/// [`crate::transform::lie`]): the Hamiltonian vector field `X = (∂g/∂p, −∂g/∂q)` is formed once,
/// so that `L_g f = Σ_{v=1}^{2N} (∂f/∂x_v) X_v`, and every application reuses the work arrays (no allocation). The `2N` products of one
/// application are accumulated in the split order and returned to graded order once; each is
/// formed with the sparser factor in the outer loop ([`Monomials::mul_add_split`]), so a
/// polynomial `g` of low degree (few terms in `X`) costs little at any `K`.
pub(crate) struct LieOperator {
    table: Arc<Monomials>,
    /// `X_v` at `field[v·len..(v + 1)·len]`, `v = 0 … 2N − 1`.
    field: Vec<f64>,
    /// Number of nonzero coefficients of each `X_v`.
    nonzero: Vec<usize>,
    derivative: Vec<f64>,
    /// All zero between applications (split-order accumulator).
    split: Vec<f64>,
}

impl LieOperator {
    /// The operator of `g` (`1 ≤ dof`, `2·dof ≤ n` checked by the caller).
    pub(crate) fn new(g: &Polynomial, dof: usize) -> Self {
        let mut op = Self::empty(g.monomials.clone());
        op.set(&g.monomials, &g.coefficients, dof);
        op
    }

    /// An operator with no field and no storage (for [`set`](Self::set)).
    pub(crate) fn empty(table: Arc<Monomials>) -> Self {
        Self {
            table,
            field: Vec::new(),
            nonzero: Vec::new(),
            derivative: Vec::new(),
            split: Vec::new(),
        }
    }

    /// Make this the operator of the polynomial with coefficients `g` (graded order of `table`;
    /// `1 ≤ dof`, `2·dof ≤ n` checked by the caller), reusing the storage: no allocation when
    /// the previous operator had at least this size.
    pub(crate) fn set(&mut self, table: &Arc<Monomials>, g: &[f64], dof: usize) {
        if !Arc::ptr_eq(&self.table, table) {
            self.table = table.clone();
        }
        let len = table.len();
        self.field.clear();
        self.field.resize(2 * dof * len, 0.0);
        self.nonzero.clear();
        self.nonzero.resize(2 * dof, 0);
        self.derivative.clear();
        self.derivative.resize(len, 0.0);
        self.split.clear();
        self.split.resize(len, 0.0);
        for (v, x) in self.field.chunks_exact_mut(len).enumerate() {
            let (conjugate, sign) = if v < dof {
                (dof + v, 1.0)
            } else {
                (v - dof, -1.0)
            };
            table.derivative(g, conjugate, x);
            if sign < 0.0 {
                x.iter_mut().for_each(|c| *c = -*c);
            }
            self.nonzero[v] = x.iter().filter(|&&c| c != 0.0).count();
        }
    }

    /// The coefficients held (field and work arrays).
    pub(crate) fn capacity(&self) -> usize {
        self.field.capacity() + self.derivative.capacity() + self.split.capacity()
    }

    /// The component `X_v` of the vector field, `v < 2N` (`L_g x_v = X_v`).
    pub(crate) fn field(&self, v: usize) -> &[f64] {
        let len = self.table.len();
        &self.field[v * len..(v + 1) * len]
    }

    /// The terms of degree `≤ degree` of `{f, g}` into `out[..C(n + degree, n)]` (graded order;
    /// the rest of `out` is not touched), from the terms of `f` of degree `≤ degree + 1`. Every
    /// step runs over the prefix of degree `≤ degree` only, so the cost falls with the degree.
    pub(crate) fn apply(&mut self, f: &[f64], out: &mut [f64], degree: usize) {
        let table = &*self.table;
        let len = table.len();
        let degree = degree.min(table.degree());
        let top = table.of_degree(degree).end;
        for (v, (x, &x_nonzero)) in self.field.chunks_exact(len).zip(&self.nonzero).enumerate() {
            if x_nonzero == 0 {
                continue;
            }
            table.derivative_to(f, v, &mut self.derivative, degree);
            let df_nonzero = self.derivative[..top].iter().filter(|&&c| c != 0.0).count();
            if df_nonzero == 0 {
                continue;
            }
            if df_nonzero <= x_nonzero {
                table.mul_add_split(&self.derivative, x, &mut self.split, degree);
            } else {
                table.mul_add_split(x, &self.derivative, &mut self.split, degree);
            }
        }
        table.take_split_to_degree(&mut self.split, out, degree);
    }
}

/// The Taylor polynomial to degree `degree` of `f(t, q, p)` about the phase point `(q₀, p₀)`, in
/// the `2N` variables `x = (q − q₀, p − p₀)` (`x_i = q_i − q₀ᵢ`, `x_{N+i} = p_i − p₀ᵢ`):
///
/// ```math
/// f(t, q_0 + \xi, p_0 + \eta) = \sum_{|\alpha| + |\beta| \le K}
/// \frac{\partial^{\alpha}_q \partial^{\beta}_p f(t, q_0, p_0)}{\alpha!\,\beta!}\,
/// \xi^\alpha \eta^\beta + O(K + 1).
/// ```
///
/// `f` receives series arguments; pass a system's own generic function, e.g.
/// `|t, q, p| system.hamiltonian(t, q, p)` ([`Hamiltonian::taylor_expansion`] does this).
///
/// # Errors
/// NaN/∞ in `t`, `q₀`, `p₀`; the storage limits of [`scope`]; a non-finite coefficient (the
/// function is not analytic at the point): [`Error::NonFinite`] naming the point and the monomial.
///
/// [`Hamiltonian::taylor_expansion`]: crate::Hamiltonian::taylor_expansion
pub fn expand_at<const N: usize>(
    t: f64,
    q0: &SVector<f64, N>,
    p0: &SVector<f64, N>,
    degree: usize,
    f: impl FnOnce(Series, &SVector<Series, N>, &SVector<Series, N>) -> Series,
) -> Result<Polynomial> {
    crate::phase::check_phase(t, q0, p0)?;
    let p = scope(2 * N, degree, |s| -> Result<Polynomial> {
        let mut q = SVector::<Series, N>::from_element(Series::constant(0.0));
        let mut p = q;
        for i in 0..N {
            q[i] = s.variable_at(i, q0[i])?;
            p[i] = s.variable_at(N + i, p0[i])?;
        }
        s.polynomial(f(Series::constant(t), &q, &p))
    })??;
    p.check_finite(&format!(
        "t = {t}, q = {:?}, p = {:?}",
        q0.as_slice(),
        p0.as_slice()
    ))
}

//! Normal forms of a Hamiltonian about an equilibrium in `N` degrees of freedom: the equilibrium,
//! the real symplectic normal form of the quadratic part, and the Birkhoff, resonant (Gustavson)
//! and centre-manifold (partial) normal forms to any degree by Lie transforms.
//!
//! # Setting
//!
//! Given the user's `H(q, p)` (any [`Hamiltonian`], written once for all number types):
//!
//! 1. The equilibrium `∇H(z₀) = 0` ([`hamiltonian_equilibrium`]): Newton's method with the AD
//!    Hessian, and the simplex method of `argmin` (Nelder–Mead on `|∇H|²`) as the fallback from a
//!    poor guess.
//! 2. [`linear_normal_form`]: with `M = J ∇²H(z₀)` (`J = [[0, I], [−I, 0]]`), a real matrix `S`
//!    with `SᵀJS = J` and `z = z₀ + S w`, `w = (Q, P)`, such that the quadratic part is the direct
//!    sum of the blocks [Meyer, Hall & Offin, *Introduction to Hamiltonian Dynamical Systems*,
//!    2nd ed., §4.6–4.7; Jorba, *Exp. Math.* 8 (1999) §2]
//!
//!    ```text
//!    elliptic        (ω/2)(Q² + P²)                         eigenvalues ±iω
//!    hyperbolic      λ Q P                                   eigenvalues ±λ
//!    complex saddle  a(Q₁P₁ + Q₂P₂) − b(Q₁P₂ − Q₂P₁)         eigenvalues ±a ± ib
//!    ```
//!
//!    (`ω` signed: a negative `ω` is an elliptic block of negative Krein signature). An eigenvalue
//!    whose eigenspace is smaller than its multiplicity (a Jordan block; in particular a zero
//!    frequency) is refused with [`Error::InvalidInput`] naming the block.
//! 3. In the complex coordinates `ζ = (x, y)`, `{x_j, y_j} = 1`,
//!
//!    ```text
//!    elliptic:  Q = (x + i y)/√2,  P = (i x + y)/√2,        hyperbolic: Q = x, P = y,
//!    saddle:    Q₁ = (x₁ + x₂)/√2, Q₂ = i(x₁ − x₂)/√2,  P₁ = (y₁ + y₂)/√2, P₂ = −i(y₁ − y₂)/√2,
//!    ```
//!
//!    the quadratic part is `H₂ = Σ_j λ_j x_j y_j` (`λ = iω`, `λ`, `a ± ib`), and
//!    `{x^a y^b, H₂} = ⟨λ, a − b⟩ x^a y^b`.
//! 4. [`normal_form`]: for `s = 3 … K` in turn, the degree-`s` part `H_s` of the current
//!    Hamiltonian is split into the kept monomials `Z_s` and the rest, which the generator
//!
//!    ```text
//!    χ_s = Σ_{(a,b) removed} h_{ab} / ⟨λ, a − b⟩ · x^a y^b      (H_s + {H₂, χ_s} = Z_s)
//!    ```
//!
//!    removes; then `H ← exp(L_{χ_s}) H`, `L_χ f = {f, χ}`, truncated at degree `K` (Lie series;
//!    Deprit 1969, in the composition form of Dragt & Finn 1976). Which monomials are kept is the
//!    [`NormalFormKind`]: `a = b` (Birkhoff), `a − b` in a resonance module (Gustavson 1966), or
//!    equal exponents in the hyperbolic directions only (the reduction to the centre manifold of
//!    Jorba & Masdemont 1999). A removed monomial whose divisor `|⟨λ, a − b⟩|` is below
//!    [`SMALL_DIVISOR`] `· max|λ|` is a resonance that was not declared: [`Error::InvalidInput`]
//!    naming `k = a − b`.
//!
//! # The near-identity transformation
//!
//! `exp(L_χ) f = f ∘ φ_χ` with `φ_χ` the time-one flow of the Hamiltonian `χ`, so the old complex
//! coordinates are `ζ_old = φ_{χ_3} ∘ ⋯ ∘ φ_{χ_K}(ζ_new)` and the normal form is
//! `K = H ∘ φ_{χ_3} ∘ ⋯ ∘ φ_{χ_K}` to degree `K`. [`BirkhoffNormalForm`] offers the map both ways
//!
//! * as the **truncated series** `ζ_old(ζ_new)` and `ζ_new(ζ_old)` to degree `K − 1`
//!   ([`BirkhoffNormalForm::to_normal`], [`BirkhoffNormalForm::from_normal`]): polynomial, fast,
//!   symplectic only to `O(|ζ|^K)` — its defect is reported by
//!   [`BirkhoffNormalForm::symplectic_defect`];
//! * as the **exact flow** of the polynomial generators ([`BirkhoffNormalForm::from_normal_flow`],
//!   [`BirkhoffNormalForm::to_normal_flow`]): each `φ_{χ_s}` integrated by the implicit Gauss
//!   method, symplectic to rounding, so that inverse ∘ forward is the identity to rounding.
//!
//! # Convergence
//!
//! Birkhoff series diverge in general (Siegel); at a given amplitude `ρ` the sizes of the
//! generators `‖χ_s‖ ρ^s` first decrease and then grow. [`BirkhoffNormalForm::diagnostics`] gives
//! the size of each degree's term, the optimal truncation degree (the last degree before the
//! terms grow) and, with [`BirkhoffNormalForm::remainder`], the measured `max |H ∘ φ − K|` on a
//! grid of the sphere `|w| = ρ`; [`Diagnostics::checked`] refuses a visibly divergent series.
//!
//! # References
//! * G. D. Birkhoff, *Dynamical Systems*, AMS 1927, ch. III.
//! * F. G. Gustavson, "On constructing formal integrals of a Hamiltonian system near an
//!   equilibrium point", *Astron. J.* 71, 670–686 (1966).
//! * A. Deprit, *Celest. Mech.* 1, 12–30 (1969); A. J. Dragt & J. M. Finn, *J. Math. Phys.* 17,
//!   2215 (1976).
//! * À. Jorba, "A methodology for the numerical computation of normal forms, centre manifolds and
//!   first integrals of Hamiltonian systems", *Experiment. Math.* 8, 155–195 (1999); À. Jorba &
//!   J. Masdemont, "Dynamics in the center manifold of the collinear points of the restricted
//!   three body problem", *Physica D* 132, 189–213 (1999).

use crate::error::{all_finite, finite, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::series::{scope, Monomials, Polynomial, Series};
use crate::stability::equilibrium::{phase_gradient_dense, phase_hessian_dense};
#[cfg(doc)]
use crate::stability::hamiltonian_equilibrium;
use crate::stability::hamiltonian_spectrum::{
    complex_null_space, eigenvalue_clusters, j_times, krein_form, symplectic_form,
};
use crate::stability::{PhaseEquilibrium, EIGENVALUE_CLUSTER};
use nalgebra::{Complex, DMatrix, DVector, SVector};
use std::sync::Arc;

/// Complex `f64`.
pub type C64 = Complex<f64>;

/// Highest normal-form degree `K` accepted by [`normal_form`] (the monomial tables of `2N`
/// variables are also bounded by [`crate::series::MAX_SERIES_COEFFICIENTS`]).
pub const MAX_NORMAL_FORM_DEGREE: usize = 64;

/// Relative size `|⟨λ, k⟩| / max|λ_j|` below which a divisor counts as a resonance.
pub const SMALL_DIVISOR: f64 = 1e-8;

/// Relative size (to the largest coefficient of the same degree) below which a coefficient of
/// `H` in the complex normal coordinates is the rounding of the linear normal form and is set
/// to zero (`32 ε`).
const ROUNDING_LEVEL: f64 = 32.0 * f64::EPSILON;

/// Largest `‖SᵀJS − J‖_max` accepted for the linear normal form.
pub const MAX_SYMPLECTIC_DEFECT: f64 = 1e-9;

// ---------------------------------------------------------------------------------------------
// Complex polynomials in the phase variables
// ---------------------------------------------------------------------------------------------

/// A polynomial `Σ_{|α| ≤ K} c_α ζ^α` with complex coefficients in the `2n` phase variables
/// `ζ = (x₁ … x_n, y₁ … y_n)` (graded order of [`Monomials`]), with the Poisson bracket
/// `{f, g} = Σ_j ∂f/∂x_j ∂g/∂y_j − ∂f/∂y_j ∂g/∂x_j`.
#[derive(Clone, Debug)]
pub struct PhasePolynomial {
    table: Arc<Monomials>,
    address: Arc<Address>,
    c: Vec<C64>,
}

/// Largest dense address table (entries) of [`Address`].
const MAX_DENSE_ADDRESS: usize = 1 << 22;

/// Additive monomial codes `code(α) = Σ α_k (K + 1)^k` and, when small enough, the dense table
/// `code → graded index` (so that the address of a product is a sum of codes and one load).
#[derive(Debug)]
struct Address {
    codes: Vec<usize>,
    unit: Vec<usize>,
    dense: Option<Vec<u32>>,
}

impl Address {
    fn new(table: &Monomials) -> Self {
        let nv = table.variables();
        let radix = table.degree() + 1;
        let mut unit = Vec::with_capacity(nv);
        let mut u = 1usize;
        let mut size = Some(1usize);
        for _ in 0..nv {
            unit.push(u);
            u = u.saturating_mul(radix);
            size = size.and_then(|s| s.checked_mul(radix));
        }
        let codes: Vec<usize> = (0..table.len())
            .map(|i| {
                table
                    .exps(i)
                    .iter()
                    .zip(&unit)
                    .map(|(&e, &w)| usize::from(e).saturating_mul(w))
                    .fold(0usize, usize::saturating_add)
            })
            .collect();
        let dense = size.filter(|&s| s <= MAX_DENSE_ADDRESS).map(|s| {
            let mut d = vec![u32::MAX; s];
            for (i, &c) in codes.iter().enumerate() {
                d[c] = i as u32;
            }
            d
        });
        Self { codes, unit, dense }
    }
}

/// `z_v^e` for every variable `v` and exponent `e ≤ degree`: the powers a polynomial's monomials
/// are products of.
fn power_table(z: &[C64], degree: usize) -> Vec<Vec<C64>> {
    z.iter()
        .map(|&zi| {
            let mut p = vec![C64::new(1.0, 0.0); degree + 1];
            for j in 1..=degree {
                p[j] = p[j - 1] * zi;
            }
            p
        })
        .collect()
}

impl PhasePolynomial {
    /// The zero polynomial on the given tables (`2n` variables).
    pub fn zero(table: &Arc<Monomials>) -> Self {
        Self {
            table: table.clone(),
            address: Arc::new(Address::new(table)),
            c: vec![C64::new(0.0, 0.0); table.len()],
        }
    }

    /// The polynomial `Σ c ζ^α` of the terms `(α, c)` on the given tables (`2n` variables;
    /// repeated multi-indices add).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for tables of an odd number of variables or a multi-index that is
    /// not a monomial of the tables (wrong length, degree above `K`); [`Error::NonFinite`] for a
    /// non-finite coefficient.
    pub fn from_terms(table: &Arc<Monomials>, terms: &[(Vec<u32>, C64)]) -> Result<Self> {
        if !table.variables().is_multiple_of(2) {
            return Err(Error::invalid(
                "phase polynomial",
                format!(
                    "{} variables: the phase variables (x, y) come in pairs",
                    table.variables()
                ),
            ));
        }
        let mut out = Self::zero(table);
        for (alpha, c) in terms {
            finite("phase-polynomial coefficient (re)", c.re)?;
            finite("phase-polynomial coefficient (im)", c.im)?;
            let i = table.index_of(alpha).ok_or_else(|| {
                Error::invalid(
                    "phase-polynomial term",
                    format!(
                        "{alpha:?} is not a monomial of {} variables of degree ≤ {}",
                        table.variables(),
                        table.degree()
                    ),
                )
            })?;
            out.c[i] += c;
        }
        Ok(out)
    }

    /// The zero polynomial on the tables of `self`.
    fn zero_like(&self) -> Self {
        Self {
            table: self.table.clone(),
            address: self.address.clone(),
            c: vec![C64::new(0.0, 0.0); self.table.len()],
        }
    }

    /// The monomial tables.
    pub fn monomials(&self) -> &Arc<Monomials> {
        &self.table
    }

    /// Number of degrees of freedom `n` (half the number of variables).
    pub fn dof(&self) -> usize {
        self.table.variables() / 2
    }

    /// All coefficients in graded order.
    pub fn coefficients(&self) -> &[C64] {
        &self.c
    }

    /// The coefficient of `x^a y^b`, `α = (a, b)`; zero for a monomial outside the tables.
    pub fn coefficient(&self, alpha: &[u32]) -> C64 {
        self.table
            .index_of(alpha)
            .map_or(C64::new(0.0, 0.0), |i| self.c[i])
    }

    /// The homogeneous part of degree `d`.
    pub fn part(&self, d: usize) -> Self {
        let mut out = self.zero_like();
        for i in self.table.of_degree(d) {
            out.c[i] = self.c[i];
        }
        out
    }

    /// `Σ_{|α| = d} |c_α|`: the size of the degree-`d` part (its maximum on the polydisc
    /// `|ζ_j| ≤ 1`).
    pub fn part_norm(&self, d: usize) -> f64 {
        self.table.of_degree(d).map(|i| self.c[i].norm()).sum()
    }

    /// `max_{|α| = d} |c_α|`.
    fn part_max(&self, d: usize) -> f64 {
        self.table
            .of_degree(d)
            .map(|i| self.c[i].norm())
            .fold(0.0, f64::max)
    }

    /// `self += s · other`.
    pub fn add_scaled(&mut self, other: &Self, s: C64) {
        for (a, b) in self.c.iter_mut().zip(&other.c) {
            *a += b * s;
        }
    }

    /// The value at the complex point `ζ`.
    ///
    /// # Errors
    /// A point of the wrong length or with a non-finite entry; a non-finite value.
    pub fn eval(&self, z: &[C64]) -> Result<C64> {
        self.check_complex_point(z)?;
        let v = self.eval_unchecked(z);
        finite("polynomial value (re)", v.re)?;
        finite("polynomial value (im)", v.im)?;
        Ok(v)
    }

    /// The gradient `∂f/∂ζ` at `ζ`.
    ///
    /// # Errors
    /// As [`Self::eval`].
    pub fn gradient(&self, z: &[C64]) -> Result<Vec<C64>> {
        self.check_complex_point(z)?;
        let g = self.gradient_unchecked(z);
        if g.iter().any(|c| !(c.re.is_finite() && c.im.is_finite())) {
            return Err(Error::NonFinite {
                what: "polynomial gradient".into(),
                value: f64::NAN,
            });
        }
        Ok(g)
    }

    fn check_complex_point(&self, z: &[C64]) -> Result<()> {
        if z.len() != self.table.variables() {
            return Err(Error::invalid(
                "evaluation point",
                format!(
                    "{} entries, the polynomial has {} variables",
                    z.len(),
                    self.table.variables()
                ),
            ));
        }
        for c in z {
            finite("evaluation point (re)", c.re)?;
            finite("evaluation point (im)", c.im)?;
        }
        Ok(())
    }

    fn eval_unchecked(&self, z: &[C64]) -> C64 {
        let powers = power_table(z, self.table.degree());
        let mut sum = C64::new(0.0, 0.0);
        for (i, &c) in self.c.iter().enumerate() {
            if c == C64::new(0.0, 0.0) {
                continue;
            }
            let mut m = c;
            for (v, &e) in self.table.exps(i).iter().enumerate() {
                if e > 0 {
                    m *= powers[v][e as usize];
                }
            }
            sum += m;
        }
        sum
    }

    fn gradient_unchecked(&self, z: &[C64]) -> Vec<C64> {
        let nv = self.table.variables();
        let zero = C64::new(0.0, 0.0);
        let powers = power_table(z, self.table.degree());
        let mut g = vec![zero; nv];
        for (i, &c) in self.c.iter().enumerate() {
            if c == zero {
                continue;
            }
            let e = self.table.exps(i);
            for (v, gv) in g.iter_mut().enumerate() {
                if e[v] == 0 {
                    continue;
                }
                let mut m = c * f64::from(e[v]);
                for (w, &ew) in e.iter().enumerate() {
                    let p = if w == v { ew - 1 } else { ew };
                    if p > 0 {
                        m *= powers[w][p as usize];
                    }
                }
                *gv += m;
            }
        }
        g
    }

    /// The nonzero terms grouped by degree (`out[d]` = graded indices of degree `d`).
    fn by_degree(&self) -> Vec<Vec<usize>> {
        let k = self.table.degree();
        (0..=k)
            .map(|d| {
                self.table
                    .of_degree(d)
                    .filter(|&i| self.c[i] != C64::new(0.0, 0.0))
                    .collect()
            })
            .collect()
    }

    /// `{self, g}` keeping degrees `≤ max_degree`.
    pub fn bracket(&self, g: &Self, max_degree: usize) -> Self {
        let n = self.dof();
        let nv = 2 * n;
        let mut out = self.zero_like();
        let fa = self.by_degree();
        let gb = g.by_degree();
        let codes = &self.address.codes;
        let unit = &self.address.unit;
        let dense = self.address.dense.as_deref();
        let mut base = vec![0u32; nv];
        for (df, fterms) in fa.iter().enumerate().skip(1) {
            for (dg, gterms) in gb.iter().enumerate().skip(1) {
                if df + dg - 2 > max_degree || fterms.is_empty() || gterms.is_empty() {
                    continue;
                }
                for &i in fterms {
                    let ei = self.table.exps(i);
                    for &j in gterms {
                        let ej = g.table.exps(j);
                        let cij = self.c[i] * g.c[j];
                        for v in 0..n {
                            let t = f64::from(ei[v]) * f64::from(ej[n + v])
                                - f64::from(ei[n + v]) * f64::from(ej[v]);
                            if t == 0.0 {
                                continue;
                            }
                            // The product monomial α + β − e_{x_v} − e_{y_v}: by its additive
                            // code when the dense table exists, else by its exponents.
                            let idx = match dense {
                                Some(d) => {
                                    Some(d[codes[i] + codes[j] - unit[v] - unit[n + v]] as usize)
                                }
                                None => {
                                    for (k, b) in base.iter_mut().enumerate() {
                                        *b = u32::from(ei[k]) + u32::from(ej[k]);
                                    }
                                    base[v] -= 1;
                                    base[n + v] -= 1;
                                    self.table.index_of(&base)
                                }
                            };
                            if let Some(idx) = idx {
                                out.c[idx] += cij * t;
                            }
                        }
                    }
                }
            }
        }
        out
    }

    /// `exp(L_χ) self = Σ_m L_χ^m self / m!` (`L_χ f = {f, χ}`), truncated at `max_degree`, with
    /// `χ` homogeneous of degree `s ≥ 3`.
    fn lie_exp(&self, chi: &Self, s: usize, max_degree: usize, sign: f64) -> Self {
        let mut out = self.clone();
        let mut term = self.clone();
        let mut m = 1usize;
        loop {
            let next = term.bracket(chi, max_degree);
            if next.c.iter().all(|c| *c == C64::new(0.0, 0.0)) {
                break;
            }
            term = next;
            let f = sign / m as f64;
            for c in &mut term.c {
                *c *= f;
            }
            out.add_scaled(&term, C64::new(1.0, 0.0));
            m += 1;
            // L_χ raises the degree by s − 2 ≥ 1: the series ends by itself.
            if s < 3 || m > max_degree + 1 {
                break;
            }
        }
        out
    }
}

// ---------------------------------------------------------------------------------------------
// Linear normal form
// ---------------------------------------------------------------------------------------------

/// One block of the real symplectic normal form of the quadratic part.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Block {
    /// `(ω/2)(Q_j² + P_j²)` on degree of freedom `j` (eigenvalues `±iω`; `ω < 0` for negative
    /// Krein signature).
    Elliptic {
        /// Degree of freedom.
        dof: usize,
        /// Signed frequency `ω`.
        frequency: f64,
    },
    /// `λ Q_j P_j` (eigenvalues `±λ`, `λ > 0`).
    Hyperbolic {
        /// Degree of freedom.
        dof: usize,
        /// Rate `λ`.
        rate: f64,
    },
    /// `a(Q_jP_j + Q_{j+1}P_{j+1}) − b(Q_jP_{j+1} − Q_{j+1}P_j)` (eigenvalues `±a ± ib`,
    /// `a, b > 0`) on degrees of freedom `j, j + 1`.
    ComplexSaddle {
        /// First of the two degrees of freedom.
        dof: usize,
        /// `a`.
        re: f64,
        /// `b`.
        im: f64,
    },
}

/// The real symplectic normal form of a quadratic Hamiltonian `½ zᵀ A z`.
#[derive(Clone, Debug)]
pub struct LinearNormalForm {
    n: usize,
    blocks: Vec<Block>,
    /// `z = S w` (columns: `Q₁ … Q_n, P₁ … P_n`).
    s: DMatrix<f64>,
    /// `λ_j` of `H₂ = Σ λ_j x_j y_j`.
    lambda: Vec<C64>,
    /// `w = T ζ` (complexification).
    t: DMatrix<C64>,
    symplectic_defect: f64,
}

impl LinearNormalForm {
    /// Number of degrees of freedom.
    pub fn dof(&self) -> usize {
        self.n
    }
    /// The blocks (hyperbolic first, then elliptic, then complex saddles).
    pub fn blocks(&self) -> &[Block] {
        &self.blocks
    }
    /// `S` with `z − z₀ = S w`, `SᵀJS = J`.
    pub fn symplectic_matrix(&self) -> &DMatrix<f64> {
        &self.s
    }
    /// `λ_j` of `H₂ = Σ_j λ_j x_j y_j` in the complex coordinates.
    pub fn eigenvalues(&self) -> &[C64] {
        &self.lambda
    }
    /// `‖SᵀJS − J‖_max`.
    pub fn symplectic_defect(&self) -> f64 {
        self.symplectic_defect
    }
    /// The complexification `w = T ζ`.
    pub fn complexification(&self) -> &DMatrix<C64> {
        &self.t
    }
    /// Whether degree of freedom `j` is elliptic.
    fn is_elliptic(&self, j: usize) -> bool {
        self.blocks
            .iter()
            .any(|b| matches!(b, Block::Elliptic { dof, .. } if *dof == j))
    }
}

/// A basis of the elliptic eigenspace `E_{iω}` (columns `v`) diagonal for the Hermitian Krein
/// form `K` (matrix `kh` in the basis `v`): pairs `(κ, v_k)` with `K(v_k, v_l) = κ_k δ_kl`.
///
/// When `K` is definite (in particular for a repeated frequency of one signature, where every
/// `K`-orthonormal basis is valid) the basis is built by `K`-Gram–Schmidt from the projections of
/// the coordinate directions `e_{q_k} + i e_{p_k}`, so that each normal mode follows the user's
/// coordinates where the splitting is free; otherwise `K` is diagonalised.
fn krein_basis(
    kh: &DMatrix<C64>,
    v: &[DVector<C64>],
    n: usize,
    dim: usize,
) -> Result<Vec<(f64, DVector<C64>)>> {
    let m = v.len();
    let se = kh.clone().symmetric_eigen();
    let kmax = se.eigenvalues.amax();
    if se
        .eigenvalues
        .iter()
        .any(|k| k.abs() <= 1e-12 * kmax.max(1e-300))
        || kmax == 0.0
    {
        return Err(Error::invalid(
            "quadratic part of H",
            "elliptic eigenspace with a degenerate Krein form (non-semisimple)",
        ));
    }
    let to_vec = |a: &DVector<C64>| -> DVector<C64> {
        let mut out = DVector::<C64>::zeros(dim);
        for (b, vb) in v.iter().enumerate() {
            out += vb * a[b];
        }
        out
    };
    let definite =
        se.eigenvalues.iter().all(|&k| k > 0.0) || se.eigenvalues.iter().all(|&k| k < 0.0);
    if !definite || m == 1 {
        return Ok((0..m)
            .map(|k| {
                let a = se.eigenvectors.column(k).into_owned();
                (se.eigenvalues[k], to_vec(&a))
            })
            .collect());
    }
    let sign = if se.eigenvalues[0] > 0.0 { 1.0 } else { -1.0 };
    // Candidates: coefficients (in the basis v, least squares) of e_{q_k} + i e_{p_k}.
    let vm = DMatrix::<C64>::from_fn(dim, m, |r, c| v[c][r]);
    let pinv = vm
        .clone()
        .pseudo_inverse(1e-12)
        .map_err(|e| Error::invalid("eigenspace", e))?;
    let mut cands: Vec<DVector<C64>> = (0..n)
        .flat_map(|k| {
            [1.0, -1.0].map(|sg| {
                let mut e = DVector::<C64>::zeros(dim);
                e[k] = C64::new(1.0, 0.0);
                e[n + k] = C64::new(0.0, sg);
                &pinv * e
            })
        })
        .collect();
    // Complete with the eigenvectors of K (never needed when the candidates span).
    for k in 0..m {
        cands.push(se.eigenvectors.column(k).into_owned());
    }
    let kin = |a: &DVector<C64>, b: &DVector<C64>| -> C64 { (a.adjoint() * kh * b)[(0, 0)] };
    let mut basis: Vec<DVector<C64>> = Vec::new();
    for c in cands {
        if basis.len() == m {
            break;
        }
        let mut a = c;
        for b in &basis {
            let proj = kin(b, &a) / kin(b, b);
            a -= b * proj;
        }
        let nk = kin(&a, &a).re * sign;
        if nk > 1e-6 * kmax {
            basis.push(a / C64::new(nk.sqrt(), 0.0));
        }
    }
    Ok(basis.iter().map(|a| (sign, to_vec(a))).collect())
}

/// The real symplectic normal form of `H₂ = ½ zᵀ A z` (`A` the `2N × 2N` symmetric Hessian,
/// blocks `[[H_qq, H_qp], [H_pq, H_pp]]`): see the module documentation.
///
/// # Errors
/// [`Error::InvalidInput`] for a matrix that is not square of even size, not symmetric, or not
/// finite; for a zero eigenvalue or a Jordan block (named by its eigenvalue and multiplicity);
/// [`Error::IllConditioned`] when `S` fails the symplectic check.
pub fn linear_normal_form(hessian: &DMatrix<f64>) -> Result<LinearNormalForm> {
    let dim = hessian.nrows();
    if dim == 0 || !dim.is_multiple_of(2) || hessian.ncols() != dim {
        return Err(Error::invalid(
            "Hessian of H",
            format!(
                "{}×{}: need a square matrix of even size",
                dim,
                hessian.ncols()
            ),
        ));
    }
    all_finite("Hessian of H", hessian.as_slice())?;
    let n = dim / 2;
    // Work on A/‖A‖ (eigenvectors are unchanged, eigenvalues scale): no overflow for any
    // finite A.
    let scale = hessian.amax();
    if scale == 0.0 {
        return Err(Error::invalid(
            "quadratic part of H",
            "the Hessian is zero: every frequency is zero, no normal form",
        ));
    }
    let hessian = &(hessian / scale);
    if !hessian.iter().all(|x| x.is_finite()) {
        return Err(Error::invalid(
            "Hessian of H",
            "not representable after scaling",
        ));
    }
    if (hessian - hessian.transpose()).amax() > 1e-10 {
        return Err(Error::invalid("Hessian of H", "not symmetric"));
    }
    let m = j_times(hessian);
    let mnorm = m.amax().max(1e-300);
    let eig = m.clone().complex_eigenvalues();
    let ctol = EIGENVALUE_CLUSTER * mnorm.max(1.0);
    let clusters = eigenvalue_clusters(eig.as_slice(), ctol);
    let mc: DMatrix<C64> = m.map(|x| C64::new(x, 0.0));
    let eigenspace = |mu: C64, mult: usize| -> Result<Vec<DVector<C64>>> {
        let shifted = &mc - DMatrix::<C64>::identity(dim, dim) * mu;
        let v = complex_null_space(shifted, 1e-7 * mnorm.max(1.0));
        if v.len() != mult {
            return Err(Error::invalid(
                "quadratic part of H",
                format!(
                    "eigenvalue {mu:.6e} of J∇²H has multiplicity {mult} but {} eigenvector(s): \
                     a Jordan block (non-semisimple), no symplectic normal form",
                    v.len()
                ),
            ));
        }
        Ok(v)
    };
    let mut hyper: Vec<(f64, DVector<f64>, DVector<f64>)> = Vec::new();
    let mut ellip: Vec<(f64, DVector<f64>, DVector<f64>)> = Vec::new();
    let mut saddle: Vec<(C64, DVector<C64>, DVector<C64>)> = Vec::new();
    for &(mu, mult) in &clusters {
        if mu.norm() <= ctol {
            return Err(Error::invalid(
                "quadratic part of H",
                format!(
                    "eigenvalue 0 of J∇²H with multiplicity {mult}: a zero frequency \
                     (degenerate or Jordan block), no normal form about this point"
                ),
            ));
        }
        let re0 = mu.re.abs() <= ctol;
        let im0 = mu.im.abs() <= ctol;
        if re0 && mu.im > 0.0 {
            // Elliptic: E_{iω}, Hermitian form K(v, w) = Ω(v̄, w)/(2i).
            let mu = C64::new(0.0, mu.im);
            let v = eigenspace(mu, mult)?;
            let kh = krein_form(&v, n);
            for (kappa, vk) in krein_basis(&kh, &v, n, dim)? {
                let sc = 1.0 / (2.0 * kappa.abs()).sqrt();
                let (freq, vk) = if kappa > 0.0 {
                    (mu.im, vk * C64::new(sc, 0.0))
                } else {
                    (-mu.im, vk.conjugate() * C64::new(sc, 0.0))
                };
                let u = vk.map(|c| c.re);
                let s = vk.map(|c| c.im);
                ellip.push((freq, u, s));
            }
        } else if im0 && mu.re > 0.0 {
            let lam = mu.re;
            let real_null = |mu: f64| -> Result<Vec<DVector<f64>>> {
                let shifted = &m - DMatrix::<f64>::identity(dim, dim) * mu;
                let svd = shifted.svd(false, true);
                let vt = svd.v_t.ok_or_else(|| Error::invalid("SVD", "no V"))?;
                let out: Vec<DVector<f64>> = (0..dim)
                    .filter(|&k| svd.singular_values[k] <= 1e-7 * mnorm.max(1.0))
                    .map(|k| vt.row(k).transpose().into_owned())
                    .collect();
                if out.len() != mult {
                    return Err(Error::invalid(
                        "quadratic part of H",
                        format!(
                            "eigenvalue {mu:.6e} of J∇²H has multiplicity {mult} but {} \
                             eigenvector(s): a Jordan block (non-semisimple)",
                            out.len()
                        ),
                    ));
                }
                Ok(out)
            };
            let vp = real_null(lam)?;
            let vm = real_null(-lam)?;
            let g = DMatrix::<f64>::from_fn(mult, mult, |a, b| symplectic_form(&vp[a], &vm[b], n));
            let gi = g.try_inverse().ok_or_else(|| {
                Error::invalid("quadratic part of H", "singular pairing of ±λ eigenspaces")
            })?;
            for k in 0..mult {
                let mut w = DVector::<f64>::zeros(dim);
                for (b, vb) in vm.iter().enumerate() {
                    w += vb * gi[(b, k)];
                }
                hyper.push((lam, vp[k].clone(), w));
            }
        } else if mu.re > 0.0 && mu.im > 0.0 {
            let vp = eigenspace(mu, mult)?;
            let vm = eigenspace(-mu, mult)?;
            let g = DMatrix::<C64>::from_fn(mult, mult, |a, b| symplectic_form(&vp[a], &vm[b], n));
            let gi = g.try_inverse().ok_or_else(|| {
                Error::invalid("quadratic part of H", "singular pairing of ±μ eigenspaces")
            })?;
            for k in 0..mult {
                let mut w = DVector::<C64>::zeros(dim);
                for (b, vb) in vm.iter().enumerate() {
                    w += vb * gi[(b, k)];
                }
                saddle.push((mu, vp[k].clone(), w));
            }
        }
    }
    // Order the blocks of one kind by the coordinate each mostly moves (the user's order).
    let dominant = |u: &DVector<f64>, w: &DVector<f64>| -> usize {
        (0..n)
            .max_by(|&a, &b| {
                let wt = |k: usize| {
                    u[k] * u[k] + u[n + k] * u[n + k] + w[k] * w[k] + w[n + k] * w[n + k]
                };
                wt(a).total_cmp(&wt(b)).then(b.cmp(&a))
            })
            .unwrap_or(0)
    };
    hyper.sort_by_key(|(_, u, w)| dominant(u, w));
    ellip.sort_by_key(|(_, u, w)| dominant(u, w));
    for h in &mut hyper {
        h.0 *= scale;
    }
    for e in &mut ellip {
        e.0 *= scale;
    }
    for sd in &mut saddle {
        sd.0 *= scale;
    }
    if hyper
        .iter()
        .map(|h| h.0)
        .chain(ellip.iter().map(|e| e.0))
        .chain(saddle.iter().flat_map(|s| [s.0.re, s.0.im]))
        .any(|x| !x.is_finite() || x == 0.0)
    {
        return Err(Error::invalid(
            "quadratic part of H",
            "a frequency overflows or underflows f64",
        ));
    }
    let count = hyper.len() + ellip.len() + 2 * saddle.len();
    if count != n {
        return Err(Error::invalid(
            "quadratic part of H",
            format!("eigenvalue clusters account for {count} of {n} degrees of freedom"),
        ));
    }
    let mut s = DMatrix::<f64>::zeros(dim, dim);
    let mut t = DMatrix::<C64>::zeros(dim, dim);
    let mut lambda = Vec::with_capacity(n);
    let mut blocks = Vec::new();
    let r2 = std::f64::consts::FRAC_1_SQRT_2;
    let one = C64::new(1.0, 0.0);
    let i1 = C64::new(0.0, 1.0);
    let mut j = 0;
    for (lam, u, w) in &hyper {
        s.set_column(j, u);
        s.set_column(n + j, w);
        t[(j, j)] = one;
        t[(n + j, n + j)] = one;
        lambda.push(C64::new(*lam, 0.0));
        blocks.push(Block::Hyperbolic { dof: j, rate: *lam });
        j += 1;
    }
    for (freq, u, v) in &ellip {
        s.set_column(j, &(u * 2f64.sqrt()));
        s.set_column(n + j, &(v * 2f64.sqrt()));
        // Q = (x + i y)/√2, P = (i x + y)/√2.
        t[(j, j)] = one * r2;
        t[(j, n + j)] = i1 * r2;
        t[(n + j, j)] = i1 * r2;
        t[(n + j, n + j)] = one * r2;
        lambda.push(C64::new(0.0, *freq));
        blocks.push(Block::Elliptic {
            dof: j,
            frequency: *freq,
        });
        j += 1;
    }
    for (mu, v, w) in &saddle {
        let (j1, j2) = (j, j + 1);
        let sq = 2f64.sqrt();
        s.set_column(j1, &(v.map(|c| c.re) * sq));
        s.set_column(j2, &(v.map(|c| c.im) * sq));
        s.set_column(n + j1, &(w.map(|c| c.re) * sq));
        s.set_column(n + j2, &(w.map(|c| -c.im) * sq));
        // Q₁ = (x₁ + x₂)/√2, Q₂ = i(x₁ − x₂)/√2, P₁ = (y₁ + y₂)/√2, P₂ = −i(y₁ − y₂)/√2.
        t[(j1, j1)] = one * r2;
        t[(j1, j2)] = one * r2;
        t[(j2, j1)] = i1 * r2;
        t[(j2, j2)] = -i1 * r2;
        t[(n + j1, n + j1)] = one * r2;
        t[(n + j1, n + j2)] = one * r2;
        t[(n + j2, n + j1)] = -i1 * r2;
        t[(n + j2, n + j2)] = i1 * r2;
        lambda.push(*mu);
        lambda.push(mu.conj());
        blocks.push(Block::ComplexSaddle {
            dof: j1,
            re: mu.re,
            im: mu.im,
        });
        j += 2;
    }
    // Symplectic check SᵀJS = J.
    let mut jm = DMatrix::<f64>::zeros(dim, dim);
    for i in 0..n {
        jm[(i, n + i)] = 1.0;
        jm[(n + i, i)] = -1.0;
    }
    let defect = (s.transpose() * &jm * &s - &jm).amax();
    if defect.is_nan() || defect > MAX_SYMPLECTIC_DEFECT {
        return Err(Error::IllConditioned {
            what: "symplectic normal form of the quadratic part (SᵀJS − J)".into(),
            at: format!("eigenvalues {lambda:?}"),
            condition: defect / f64::EPSILON,
            threshold: MAX_SYMPLECTIC_DEFECT / f64::EPSILON,
        });
    }
    Ok(LinearNormalForm {
        n,
        blocks,
        s,
        lambda,
        t,
        symplectic_defect: defect,
    })
}

// ---------------------------------------------------------------------------------------------
// Nonlinear normal form
// ---------------------------------------------------------------------------------------------

/// Which monomials `x^a y^b` the normal form keeps.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum NormalFormKind {
    /// Birkhoff: `a = b` only (non-resonant frequencies; an undeclared resonance up to the degree
    /// is an error naming it).
    Birkhoff,
    /// Resonant (Gustavson): `a − b` in the real span of the given integer vectors (the resonance
    /// module, e.g. `[[1, −1]]` for the 1:1 resonance of two oscillators).
    Resonant(Vec<Vec<i32>>),
    /// Partial normal form: only the monomials with `a_j ≠ b_j` in some hyperbolic (or
    /// complex-saddle) direction `j` are removed, so that `{x_h = y_h = 0}` is invariant and `K`
    /// restricted to it is the Hamiltonian on the centre manifold.
    CentreManifold,
}

/// The normal form of `H` about an equilibrium to degree `K` (see the module documentation).
#[derive(Clone, Debug)]
pub struct BirkhoffNormalForm {
    n: usize,
    degree: usize,
    kind: NormalFormKind,
    z0: Vec<f64>,
    linear: LinearNormalForm,
    /// `w = T ζ` and its inverse.
    t_inv: DMatrix<C64>,
    hamiltonian: PhasePolynomial,
    normal: PhasePolynomial,
    generators: Vec<PhasePolynomial>,
    /// `(old_from_new, new_from_old)`: the coordinate series, built on first use.
    maps: std::sync::OnceLock<(Vec<PhasePolynomial>, Vec<PhasePolynomial>)>,
    quadratic_defect: f64,
    reality_defect: f64,
}

fn in_span(module: &[Vec<i32>], k: &[i32]) -> bool {
    if k.iter().all(|&x| x == 0) {
        return true;
    }
    if module.is_empty() {
        return false;
    }
    let n = k.len();
    let a = DMatrix::<f64>::from_fn(n, module.len(), |i, j| f64::from(module[j][i]));
    let mut ak = DMatrix::<f64>::zeros(n, module.len() + 1);
    ak.columns_mut(0, module.len()).copy_from(&a);
    for i in 0..n {
        ak[(i, module.len())] = f64::from(k[i]);
    }
    a.rank(1e-9) == ak.rank(1e-9)
}

/// `Σ c_α w^α` (real, `2n` variables) with `w = T ζ` substituted: a complex polynomial in `ζ`.
fn complexify(p: &Polynomial, t: &DMatrix<C64>, table: &Arc<Monomials>) -> PhasePolynomial {
    let nv = table.variables();
    let k = table.degree();
    let mut out = PhasePolynomial::zero(table);
    // Linear forms ℓ_i = Σ_k T_ik ζ_k (nonzero entries).
    let forms: Vec<Vec<(usize, C64)>> = (0..nv)
        .map(|i| {
            (0..nv)
                .filter(|&c| t[(i, c)] != C64::new(0.0, 0.0))
                .map(|c| (c, t[(i, c)]))
                .collect()
        })
        .collect();
    // Depth-first over the multisets of variables i₁ ≤ i₂ ≤ …, carrying Π ℓ_{i_m} as a sparse
    // homogeneous polynomial (graded indices).
    let mut alpha = vec![0u32; nv];
    let mut unit = vec![0u32; nv];
    struct Ctx<'a> {
        p: &'a Polynomial,
        table: &'a Monomials,
        forms: &'a [Vec<(usize, C64)>],
        /// The highest degree with a nonzero coefficient of `p`: no deeper product contributes.
        k: usize,
        out: &'a mut [C64],
    }
    fn times_form(
        table: &Monomials,
        img: &[(usize, C64)],
        form: &[(usize, C64)],
        nv: usize,
        buf: &mut [u32],
    ) -> Vec<(usize, C64)> {
        let mut acc: std::collections::HashMap<usize, C64> =
            std::collections::HashMap::with_capacity(img.len() * form.len());
        for &(idx, c) in img {
            let e = table.exps(idx);
            for &(v, tv) in form {
                for (b, &x) in buf.iter_mut().zip(e) {
                    *b = u32::from(x);
                }
                buf[v] += 1;
                if let Some(j) = table.index_of(&buf[..nv]) {
                    *acc.entry(j).or_insert(C64::new(0.0, 0.0)) += c * tv;
                }
            }
        }
        acc.into_iter().collect()
    }
    fn visit(
        ctx: &mut Ctx<'_>,
        start: usize,
        depth: usize,
        img: &[(usize, C64)],
        alpha: &mut [u32],
        buf: &mut [u32],
    ) {
        let nv = alpha.len();
        if let Some(i) = ctx.table.index_of(alpha) {
            let c = ctx.p.coefficients()[i];
            if c != 0.0 {
                for &(j, v) in img {
                    ctx.out[j] += v * c;
                }
            }
        }
        if depth == ctx.k {
            return;
        }
        for v in start..nv {
            let child = times_form(ctx.table, img, &ctx.forms[v], nv, buf);
            alpha[v] += 1;
            visit(ctx, v, depth + 1, &child, alpha, buf);
            alpha[v] -= 1;
        }
    }
    let ptable = p.monomials();
    let top = (0..=k.min(ptable.degree()))
        .rev()
        .find(|&d| ptable.of_degree(d).any(|i| p.coefficients()[i] != 0.0))
        .unwrap_or(0);
    let mut ctx = Ctx {
        p,
        table,
        forms: &forms,
        k: top,
        out: &mut out.c,
    };
    visit(
        &mut ctx,
        0,
        0,
        &[(0, C64::new(1.0, 0.0))],
        &mut alpha,
        &mut unit,
    );
    out
}

/// The normal form of `h` about the equilibrium `eq` (see [`hamiltonian_equilibrium`]) to degree
/// `degree ∈ 3..=MAX_NORMAL_FORM_DEGREE` in the phase variables.
///
/// # Errors
/// The errors of [`linear_normal_form`] (Jordan blocks, zero frequencies) and of
/// [`Hamiltonian::taylor_expansion`] (storage limits, a point where `H` is not analytic); a
/// degree outside the range ([`Error::OutOfDomain`]); a point that is not an equilibrium
/// (`|∇H| > 1e−8 (1 + |z|)`, [`Error::InvalidInput`]); an undeclared resonance `⟨λ, k⟩ ≈ 0` met
/// by the homological equation ([`Error::InvalidInput`] naming `k` and the degree); a
/// [`NormalFormKind::Resonant`] module of the wrong length; [`NormalFormKind::CentreManifold`]
/// without a hyperbolic direction.
pub fn normal_form<H: Hamiltonian<N>, const N: usize>(
    h: &H,
    t: f64,
    eq: &PhaseEquilibrium<N>,
    degree: usize,
    kind: NormalFormKind,
) -> Result<BirkhoffNormalForm> {
    crate::phase::check_phase(t, &eq.q, &eq.p)?;
    if !(3..=MAX_NORMAL_FORM_DEGREE).contains(&degree) {
        return Err(Error::out_of_domain(
            "normal-form degree K",
            degree as f64,
            format!("{{3, …, {MAX_NORMAL_FORM_DEGREE}}}"),
        ));
    }
    if let NormalFormKind::Resonant(module) = &kind {
        if module.iter().any(|k| k.len() != N) {
            return Err(Error::invalid(
                "resonance module",
                format!("every vector needs N = {N} integers"),
            ));
        }
    }
    let table = Arc::new(Monomials::new(2 * N, degree)?);
    let z0 = DVector::from_iterator(2 * N, eq.q.iter().chain(eq.p.iter()).copied());
    let (_, gn) = phase_gradient_dense(h, t, &z0)?;
    if gn > 1e-8 * (1.0 + z0.norm()) {
        return Err(Error::invalid(
            "equilibrium",
            format!("|∇H| = {gn:e} at the given point: not an equilibrium (use `stability::hamiltonian_equilibrium`)"),
        ));
    }
    let a = phase_hessian_dense(h, t, &z0)?;
    let linear = linear_normal_form(&a)?;
    if kind == NormalFormKind::CentreManifold && (0..N).all(|j| linear.is_elliptic(j)) {
        return Err(Error::invalid(
            "centre-manifold normal form",
            "the equilibrium has no hyperbolic direction",
        ));
    }
    // Taylor expansion of H(z₀ + S w) in w.
    let s = linear.s.clone();
    let real = scope(2 * N, degree, |sc| -> Result<Polynomial> {
        let w = sc.variables()?;
        let mut q = SVector::<Series, N>::from_element(Series::constant(0.0));
        let mut p = q;
        for i in 0..N {
            let mut qi = Series::constant(z0[i]);
            let mut pi = Series::constant(z0[N + i]);
            for (j, wj) in w.iter().enumerate() {
                if s[(i, j)] != 0.0 {
                    qi += *wj * s[(i, j)];
                }
                if s[(N + i, j)] != 0.0 {
                    pi += *wj * s[(N + i, j)];
                }
            }
            q[i] = qi;
            p[i] = pi;
        }
        sc.polynomial(h.hamiltonian(Series::constant(t), &q, &p))
    })??
    .check_finite(&format!(
        "the equilibrium q = {:?}, p = {:?}",
        eq.q.as_slice(),
        eq.p.as_slice()
    ))?;
    let mut hc = complexify(&real, &linear.t, &table);
    // The quadratic part is Σ λ_j x_j y_j up to rounding: record the defect, set it exactly.
    let mut quadratic_defect = 0.0f64;
    for d in [1usize, 2] {
        for i in table.of_degree(d) {
            let e = table.exps(i);
            let diag = (0..N).find(|&j| e[j] == 1 && e[N + j] == 1);
            let exact = match (d, diag) {
                (2, Some(j)) => linear.lambda[j],
                _ => C64::new(0.0, 0.0),
            };
            quadratic_defect = quadratic_defect.max((hc.c[i] - exact).norm());
            hc.c[i] = exact;
        }
    }
    // Coefficients at the rounding level of their degree (`|c| ≤ ROUNDING_LEVEL · max_{|α| = d}
    // |c_α|`) are the rounding of `S` (e.g. the mixing of the modes of a repeated frequency):
    // set to zero, so that the monomials a symmetry of `H` excludes stay exactly zero through
    // the Lie series.
    for d in 3..=degree {
        let top = hc.part_max(d);
        for i in table.of_degree(d) {
            if hc.c[i].norm() <= ROUNDING_LEVEL * top {
                hc.c[i] = C64::new(0.0, 0.0);
            }
        }
    }
    let lambda = linear.lambda.clone();
    let lmax = lambda.iter().map(|l| l.norm()).fold(0.0, f64::max);
    let elliptic: Vec<bool> = (0..N).map(|j| linear.is_elliptic(j)).collect();
    let mut cur = hc.clone();
    let mut generators = Vec::with_capacity(degree.saturating_sub(2));
    let mut kvec = vec![0i32; N];
    for sdeg in 3..=degree {
        let mut chi = hc.zero_like();
        for i in table.of_degree(sdeg) {
            let c = cur.c[i];
            if c == C64::new(0.0, 0.0) {
                continue;
            }
            let e = table.exps(i);
            for j in 0..N {
                kvec[j] = i32::from(e[j]) - i32::from(e[N + j]);
            }
            let keep = match &kind {
                NormalFormKind::Birkhoff => kvec.iter().all(|&x| x == 0),
                NormalFormKind::Resonant(module) => in_span(module, &kvec),
                NormalFormKind::CentreManifold => (0..N).all(|j| elliptic[j] || kvec[j] == 0),
            };
            if keep {
                continue;
            }
            let div: C64 = (0..N).map(|j| lambda[j] * f64::from(kvec[j])).sum();
            if div.norm() <= SMALL_DIVISOR * lmax {
                return Err(Error::invalid(
                    "normal form",
                    format!(
                        "resonance k·ω = 0 with k = {kvec:?} at degree {sdeg} (divisor \
                         {:.3e}): declare it with NormalFormKind::Resonant",
                        div.norm()
                    ),
                ));
            }
            chi.c[i] = c / div;
        }
        cur = cur.lie_exp(&chi, sdeg, degree, 1.0);
        // The removed monomials are zero up to rounding: set them exactly.
        for i in table.of_degree(sdeg) {
            if chi.c[i] != C64::new(0.0, 0.0) {
                cur.c[i] = C64::new(0.0, 0.0);
            }
        }
        generators.push(chi);
    }
    let t_inv =
        linear.t.clone().try_inverse().ok_or_else(|| {
            Error::invalid("complexification", "singular (internal construction)")
        })?;
    // Reality: a real H gives K with the symmetry of the complexification; report the imaginary
    // part of K at a sample real point as the reality defect.
    let mut nf = BirkhoffNormalForm {
        n: N,
        degree,
        kind,
        z0: z0.iter().copied().collect(),
        linear,
        t_inv,
        hamiltonian: hc,
        normal: cur,
        generators,
        maps: std::sync::OnceLock::new(),
        quadratic_defect,
        reality_defect: 0.0,
    };
    let probe: Vec<f64> = (0..2 * N).map(|i| 0.1 / (1.0 + i as f64)).collect();
    let zeta = nf.complex_of_normal(&probe);
    nf.reality_defect = nf.normal.eval_unchecked(&zeta).im.abs();
    Ok(nf)
}

/// Per-degree sizes and the optimal truncation at an amplitude `ρ`.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Diagnostics {
    /// The amplitude `ρ`.
    pub amplitude: f64,
    /// `(s, ‖χ_s‖ ρ^s)` for `s = 3 … K` (`‖·‖` the sum of `|coefficients|` of the degree-`s` part).
    pub generator_terms: Vec<(usize, f64)>,
    /// `(s, ‖K_s‖ ρ^s)` for `s = 2 … K`.
    pub normal_form_terms: Vec<(usize, f64)>,
    /// The degree after which `‖χ_s‖ρ^s` stops decreasing (the last degree of the decreasing
    /// run from `s = 3`): the optimal truncation at this amplitude.
    pub optimal_degree: usize,
    /// Whether the generator terms grow over the last third of the degrees by more than a
    /// factor 10 (visible divergence at this amplitude).
    pub diverged: bool,
}

impl Diagnostics {
    /// `Ok(self)` unless [`Diagnostics::diverged`].
    ///
    /// # Errors
    /// [`Error::NotConverged`] naming the amplitude and the optimal degree.
    pub fn checked(self) -> Result<Self> {
        if self.diverged {
            let last = self.generator_terms.last().map_or(0.0, |t| t.1);
            return Err(Error::NotConverged {
                what: format!(
                    "normal-form series at amplitude {:e}: the generator terms grow beyond \
                     degree {} (optimal truncation there)",
                    self.amplitude, self.optimal_degree
                ),
                iterations: self.generator_terms.len(),
                residual: last,
            });
        }
        Ok(self)
    }
}

impl BirkhoffNormalForm {
    /// Degrees of freedom.
    pub fn dof(&self) -> usize {
        self.n
    }
    /// The degree `K`.
    pub fn degree(&self) -> usize {
        self.degree
    }
    /// The kind of normal form.
    pub fn kind(&self) -> &NormalFormKind {
        &self.kind
    }
    /// The equilibrium `z₀ = (q₀, p₀)`.
    pub fn equilibrium(&self) -> &[f64] {
        &self.z0
    }
    /// The linear normal form.
    pub fn linear(&self) -> &LinearNormalForm {
        &self.linear
    }
    /// `H` in the complex normal coordinates `ζ` (degree `≤ K`).
    pub fn hamiltonian(&self) -> &PhasePolynomial {
        &self.hamiltonian
    }
    /// The normal form `K(ζ)` (degree `≤ K`).
    pub fn normal_form(&self) -> &PhasePolynomial {
        &self.normal
    }
    /// The Lie generators `χ_3 … χ_K` (index `s − 3`).
    pub fn generators(&self) -> &[PhasePolynomial] {
        &self.generators
    }
    /// Largest deviation of the computed quadratic part from `Σ λ_j x_j y_j` (rounding of the
    /// linear normal form) and of the linear part from zero (the equilibrium's residual).
    pub fn quadratic_defect(&self) -> f64 {
        self.quadratic_defect
    }
    /// `|Im K|` at a sample real point: zero up to rounding for a real `H`.
    pub fn reality_defect(&self) -> f64 {
        self.reality_defect
    }

    /// The coordinate series `(ζ_old(ζ_new), ζ_new(ζ_old))` to degree `K − 1`, built on first use.
    fn maps(&self) -> &(Vec<PhasePolynomial>, Vec<PhasePolynomial>) {
        self.maps.get_or_init(|| {
            let n = self.n;
            let table = self.normal.table.clone();
            let degree = self.degree;
            let mut old_from_new = Vec::with_capacity(2 * n);
            let mut new_from_old = Vec::with_capacity(2 * n);
            for v in 0..2 * n {
                let mut unit = vec![0u32; 2 * n];
                unit[v] = 1;
                let mut f = self.normal.zero_like();
                if let Some(i) = table.index_of(&unit) {
                    f.c[i] = C64::new(1.0, 0.0);
                }
                let mut o = f.clone();
                for (k, chi) in self.generators.iter().enumerate() {
                    o = o.lie_exp(chi, k + 3, degree - 1, 1.0);
                }
                let mut nw = f;
                for (k, chi) in self.generators.iter().enumerate().rev() {
                    nw = nw.lie_exp(chi, k + 3, degree - 1, -1.0);
                }
                old_from_new.push(o);
                new_from_old.push(nw);
            }
            (old_from_new, new_from_old)
        })
    }

    /// The truncated coordinate series `(ζ_old(ζ_new), ζ_new(ζ_old))`, one polynomial of degree
    /// `K − 1` per complex coordinate `ζ = (x, y)`:
    ///
    /// ```text
    /// ζ_old = exp(L_{χ_K}) ⋯ exp(L_{χ_3}) ζ,      ζ_new = exp(−L_{χ_3}) ⋯ exp(−L_{χ_K}) ζ,
    /// ```
    ///
    /// truncated at degree `K − 1` (Dragt & Finn 1976); the maps of [`Self::from_normal`] and
    /// [`Self::to_normal`] in the complex coordinates.
    pub fn coordinate_series(&self) -> (&[PhasePolynomial], &[PhasePolynomial]) {
        let (old_from_new, new_from_old) = self.maps();
        (old_from_new, new_from_old)
    }

    /// `ζ` of the real normal coordinates `w = (Q, P)`.
    fn complex_of_normal(&self, w: &[f64]) -> Vec<C64> {
        let wc = DVector::<C64>::from_iterator(w.len(), w.iter().map(|&x| C64::new(x, 0.0)));
        (&self.t_inv * wc).iter().copied().collect()
    }

    /// Real normal coordinates `w` of `ζ` (the real part: imaginary parts are rounding).
    fn normal_of_complex(&self, z: &[C64]) -> Vec<f64> {
        let zc = DVector::<C64>::from_iterator(z.len(), z.iter().copied());
        (&self.linear.t * zc).iter().map(|c| c.re).collect()
    }

    /// `w = S⁻¹(z − z₀)` (the real linear normal coordinates of the phase point `z`).
    pub fn linear_coordinates(&self, z: &[f64]) -> Result<Vec<f64>> {
        self.check_point(z)?;
        let d = DVector::from_iterator(z.len(), z.iter().zip(&self.z0).map(|(a, b)| a - b));
        // S⁻¹ = −J Sᵀ J.
        let n = self.n;
        let jd = DVector::from_fn(2 * n, |i, _| if i < n { d[n + i] } else { -d[i - n] });
        let sj = self.linear.s.transpose() * jd;
        Ok((0..2 * n)
            .map(|i| if i < n { -sj[n + i] } else { sj[i - n] })
            .collect())
    }

    /// The phase point `z = z₀ + S w`.
    pub fn phase_point(&self, w: &[f64]) -> Result<Vec<f64>> {
        self.check_point(w)?;
        let wv = DVector::from_iterator(w.len(), w.iter().copied());
        let z = &self.linear.s * wv;
        Ok(z.iter().zip(&self.z0).map(|(a, b)| a + b).collect())
    }

    fn check_point(&self, z: &[f64]) -> Result<()> {
        if z.len() != 2 * self.n {
            return Err(Error::invalid(
                "phase point",
                format!("{} entries, need 2N = {}", z.len(), 2 * self.n),
            ));
        }
        all_finite("phase point", z)
    }

    fn apply(&self, maps: &[PhasePolynomial], w: &[f64]) -> Result<Vec<f64>> {
        self.check_point(w)?;
        let z = self.complex_of_normal(w);
        let image: Vec<C64> = maps.iter().map(|m| m.eval_unchecked(&z)).collect();
        let out = self.normal_of_complex(&image);
        all_finite("image of the near-identity map", &out)?;
        Ok(out)
    }

    /// The new (normal-form) real coordinates `w' = (Q', P')` of the old linear normal
    /// coordinates `w` ([`Self::linear_coordinates`]), by the truncated series (degree `K − 1`).
    ///
    /// # Errors
    /// A point of the wrong length or not finite; a non-finite image.
    pub fn to_normal(&self, w: &[f64]) -> Result<Vec<f64>> {
        self.apply(&self.maps().1, w)
    }

    /// The old linear normal coordinates `w` of the new coordinates `w'`, by the truncated series.
    ///
    /// # Errors
    /// As [`Self::to_normal`].
    pub fn from_normal(&self, w: &[f64]) -> Result<Vec<f64>> {
        self.apply(&self.maps().0, w)
    }

    /// Flow of one generator for time `sign`, by the 4-stage Gauss collocation method (order
    /// 8, symplectic) in the complex coordinates, `steps` steps.
    fn flow_one(&self, chi: &PhasePolynomial, z: &mut [C64], sign: f64, steps: usize) {
        let n = self.n;
        let field = |z: &[C64]| -> Vec<C64> {
            let g = chi.gradient_unchecked(z);
            // ẋ = ∂χ/∂y, ẏ = −∂χ/∂x
            (0..2 * n)
                .map(|i| {
                    if i < n {
                        g[n + i] * sign
                    } else {
                        -g[i - n] * sign
                    }
                })
                .collect()
        };
        // Gauss–Legendre 2-stage (order 4) with fixed-point iteration.
        let s3 = 3f64.sqrt();
        let a = [[0.25, 0.25 - s3 / 6.0], [0.25 + s3 / 6.0, 0.25]];
        let h = 1.0 / steps as f64;
        for _ in 0..steps {
            let mut k = [field(z), field(z)];
            for _ in 0..100 {
                let mut kn = [Vec::new(), Vec::new()];
                for (st, knst) in kn.iter_mut().enumerate() {
                    let y: Vec<C64> = (0..2 * n)
                        .map(|i| z[i] + (k[0][i] * a[st][0] + k[1][i] * a[st][1]) * h)
                        .collect();
                    *knst = field(&y);
                }
                let diff = (0..2 * n)
                    .map(|i| (kn[0][i] - k[0][i]).norm() + (kn[1][i] - k[1][i]).norm())
                    .fold(0.0, f64::max);
                k = kn;
                if diff <= 1e-16 * (1.0 + k[0].iter().map(|c| c.norm()).fold(0.0, f64::max)) {
                    break;
                }
            }
            for i in 0..2 * n {
                z[i] += (k[0][i] + k[1][i]) * (0.5 * h);
            }
        }
    }

    fn flow(&self, w: &[f64], forward: bool) -> Result<Vec<f64>> {
        self.check_point(w)?;
        let mut z = self.complex_of_normal(w);
        let steps = 32;
        // old = φ_3 ∘ φ_4 ∘ ⋯ ∘ φ_K (new): apply φ_K first.
        if forward {
            for chi in self.generators.iter().rev() {
                self.flow_one(chi, &mut z, 1.0, steps);
            }
        } else {
            for chi in &self.generators {
                self.flow_one(chi, &mut z, -1.0, steps);
            }
        }
        let out = self.normal_of_complex(&z);
        all_finite("image of the generator flow", &out)?;
        Ok(out)
    }

    /// The old linear normal coordinates of `w'` by the exact flows of the polynomial
    /// generators, `φ_{χ_3} ∘ ⋯ ∘ φ_{χ_K}`, each integrated by the symplectic Gauss method of
    /// order 4 in 32 steps (symplectic to rounding; the integration error is `O(32⁻⁴ ‖χ‖)`).
    ///
    /// # Errors
    /// As [`Self::to_normal`].
    pub fn from_normal_flow(&self, w: &[f64]) -> Result<Vec<f64>> {
        self.flow(w, true)
    }

    /// The inverse of [`Self::from_normal_flow`] (the flows backwards in reverse order).
    ///
    /// # Errors
    /// As [`Self::to_normal`].
    pub fn to_normal_flow(&self, w: &[f64]) -> Result<Vec<f64>> {
        self.flow(w, false)
    }

    /// Hamilton's equations of the normal form `K` in the real normal coordinates
    /// `w' = (Q', P')`: `(Q̇', Ṗ') = (∂K/∂P', −∂K/∂Q')`.
    ///
    /// # Errors
    /// A point of the wrong length or not finite; a non-finite value.
    pub fn normal_form_field(&self, w: &[f64]) -> Result<Vec<f64>> {
        self.check_point(w)?;
        let n = self.n;
        let z = self.complex_of_normal(w);
        let g = self.normal.gradient_unchecked(&z);
        let zdot: Vec<C64> = (0..2 * n)
            .map(|i| if i < n { g[n + i] } else { -g[i - n] })
            .collect();
        let out = self.normal_of_complex(&zdot);
        all_finite("normal-form vector field", &out)?;
        Ok(out)
    }

    /// `K` at the real normal coordinates `w'`.
    ///
    /// # Errors
    /// A point of the wrong length or not finite.
    pub fn normal_form_value(&self, w: &[f64]) -> Result<f64> {
        self.check_point(w)?;
        let z = self.complex_of_normal(w);
        finite("normal-form value", self.normal.eval_unchecked(&z).re)
    }

    /// For [`NormalFormKind::Birkhoff`]: `K` as a polynomial in the actions `I_j` (degree `⌊K/2⌋`):
    /// `I_j = (Q_j² + P_j²)/2 = i x_j y_j` on elliptic degrees of freedom, `I_j = Q_j P_j = x_j y_j`
    /// on hyperbolic ones; every kept monomial `x^a y^a` is `Π_j (x_j y_j)^{a_j}`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for another kind of normal form (its `K` depends on angles).
    pub fn action_polynomial(&self) -> Result<Polynomial> {
        if self.kind != NormalFormKind::Birkhoff {
            return Err(Error::invalid(
                "action polynomial",
                "only a Birkhoff normal form is a function of the actions alone",
            ));
        }
        let n = self.n;
        let mut p = Polynomial::zero(n, self.degree / 2)?;
        let table = self.normal.table.clone();
        let mut a = vec![0u32; n];
        for i in 0..table.len() {
            let c = self.normal.c[i];
            if c == C64::new(0.0, 0.0) {
                continue;
            }
            let e = table.exps(i);
            let mut f = c;
            for j in 0..n {
                a[j] = u32::from(e[j]);
                if self.linear.is_elliptic(j) {
                    // x y = −i I
                    f *= C64::new(0.0, -1.0).powu(a[j]);
                }
            }
            if let Some(idx) = p.monomials().index_of(&a) {
                p.coefficients_mut()[idx] += f.re;
            }
        }
        Ok(p)
    }

    /// Convergence diagnostics at amplitude `ρ > 0` (see [`Diagnostics`]).
    ///
    /// # Errors
    /// [`Error::NonFinite`] / [`Error::OutOfDomain`] for `ρ` not finite and positive.
    pub fn diagnostics(&self, amplitude: f64) -> Result<Diagnostics> {
        let rho = crate::error::positive("amplitude ρ", amplitude)?;
        let generator_terms: Vec<(usize, f64)> = self
            .generators
            .iter()
            .enumerate()
            .map(|(k, g)| (k + 3, g.part_norm(k + 3) * rho.powi((k + 3) as i32)))
            .collect();
        let normal_form_terms: Vec<(usize, f64)> = (2..=self.degree)
            .map(|s| (s, self.normal.part_norm(s) * rho.powi(s as i32)))
            .collect();
        // Optimal degree: the degree with the smallest nonzero generator term.
        let nonzero: Vec<&(usize, f64)> = generator_terms.iter().filter(|t| t.1 > 0.0).collect();
        let optimal_degree = nonzero
            .iter()
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .map_or(self.degree, |t| t.0);
        let diverged = !nonzero.is_empty() && {
            let first_third = nonzero.len().div_ceil(3);
            let min = nonzero.iter().map(|t| t.1).fold(f64::INFINITY, f64::min);
            let tail_max = nonzero[first_third..]
                .iter()
                .map(|t| t.1)
                .fold(0.0, f64::max);
            tail_max > 10.0 * min && nonzero.last().is_some_and(|t| t.1 > 10.0 * min)
        };
        Ok(Diagnostics {
            amplitude: rho,
            generator_terms,
            normal_form_terms,
            optimal_degree,
            diverged,
        })
    }

    /// The remainder `max |H(z₀ + S φ(w')) − K(w')|` over `samples` points `w'` of the sphere
    /// `|w'| = ρ` (a deterministic quasi-random grid), with `φ` the truncated series map
    /// [`Self::from_normal`]. For the degree-`K` form it is `O(ρ^{K+1})`.
    ///
    /// # Errors
    /// `ρ` not finite and positive; `samples` outside `1..=100000`; a non-finite value of `H`.
    pub fn remainder<H: Hamiltonian<N>, const N: usize>(
        &self,
        h: &H,
        t: f64,
        amplitude: f64,
        samples: usize,
    ) -> Result<f64> {
        let rho = crate::error::positive("amplitude ρ", amplitude)?;
        finite("t", t)?;
        if N != self.n {
            return Err(Error::invalid(
                "Hamiltonian",
                format!("has N = {N} degrees of freedom, the normal form {}", self.n),
            ));
        }
        if !(1..=100_000).contains(&samples) {
            return Err(Error::out_of_domain(
                "remainder samples",
                samples as f64,
                "{1, …, 100000}",
            ));
        }
        let dim = 2 * N;
        let mut worst = 0.0f64;
        // Points on the sphere from a Kronecker sequence mapped through Gaussian-free
        // normalisation of a cube point.
        let alphas: Vec<f64> = (0..dim)
            .map(|i| (f64::from(2 + 2 * i as u32 + 1)).sqrt().fract())
            .collect();
        for k in 0..samples {
            let mut w: Vec<f64> = alphas
                .iter()
                .map(|a| ((k as f64 + 0.5) * a).fract() * 2.0 - 1.0)
                .collect();
            let nrm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
            if nrm < 1e-3 {
                continue;
            }
            for x in &mut w {
                *x *= rho / nrm;
            }
            let old = self.from_normal(&w)?;
            let z = self.phase_point(&old)?;
            let q = SVector::<f64, N>::from_iterator(z.iter().take(N).copied());
            let p = SVector::<f64, N>::from_iterator(z.iter().skip(N).copied());
            let hv = h.value(t, &q, &p)?;
            let kv = self.normal_form_value(&w)?;
            worst = worst.max((hv - kv).abs());
        }
        Ok(worst)
    }

    /// Largest `|{w_i, w_j}_{w'} − J_ij|` of the truncated series map `w(w')` at the point `w'`
    /// (Jacobian by central differences of step `1e−5 (1 + |w'|)`): the symplectic defect of
    /// the truncated transformation, `O(|w'|^{K−1})`.
    ///
    /// # Errors
    /// As [`Self::to_normal`].
    pub fn symplectic_defect(&self, w: &[f64]) -> Result<f64> {
        self.check_point(w)?;
        let dim = 2 * self.n;
        let nrm = w.iter().map(|x| x * x).sum::<f64>().sqrt();
        let hstep = 1e-5 * (1.0 + nrm);
        let mut jac = DMatrix::<f64>::zeros(dim, dim);
        for c in 0..dim {
            let mut wp = w.to_vec();
            let mut wm = w.to_vec();
            wp[c] += hstep;
            wm[c] -= hstep;
            let fp = self.from_normal(&wp)?;
            let fm = self.from_normal(&wm)?;
            for r in 0..dim {
                jac[(r, c)] = (fp[r] - fm[r]) / (2.0 * hstep);
            }
        }
        let n = self.n;
        let mut jm = DMatrix::<f64>::zeros(dim, dim);
        for i in 0..n {
            jm[(i, n + i)] = 1.0;
            jm[(n + i, i)] = -1.0;
        }
        Ok((jac.transpose() * &jm * &jac - jm).amax())
    }
}

//! Lie-series normal form of a perturbed harmonic oscillator to arbitrary order (one degree of
//! freedom).
//!
//! # Setting
//!
//! ```text
//! H = ν J + Σ_{k=1}^{N} ε^k H_k(J, w),        q = √(2J/n) cos w,   p = −√(2nJ) sin w,
//! ```
//!
//! in the action–angle variables `(w, J)` of the oscillator `½(p² + n²q²) = nJ` (`ν = n`; `w` the
//! coordinate, `J` the momentum, `{w, J} = 1`). All functions are kept as *Poisson series* in the
//! complex variables
//!
//! ```text
//! ξ = √J e^{iw},   η = √J e^{−iw} = ξ̄,   ξ^a η^b = J^{(a+b)/2} e^{i(a−b)w},
//! {f, g} = ∂f/∂w ∂g/∂J − ∂f/∂J ∂g/∂w = i (∂f/∂ξ ∂g/∂η − ∂f/∂η ∂g/∂ξ),
//! {ξ^a η^b, ξ^c η^d} = i (a d − b c) ξ^{a+c−1} η^{b+d−1},
//! ```
//!
//! so every series is a polynomial with the d'Alembert property built in (`J^{m/2} e^{ikw}` with
//! `|k| ≤ m`, `k ≡ m mod 2`), and a potential polynomial in `q` is polynomial in `(ξ, η)`:
//! `q = (ξ + η)/√(2n)`, `p = i √(n/2) (ξ − η)`. Coefficients are complex `f64`; a real function has
//! `c_{ba} = c̄_{ab}`.
//!
//! # Algorithm (Lie-series normal form, Deprit-equivalent)
//!
//! The bookkeeping parameter `ε` is a *grade*: `H_k` has grade `k`. For `k = 1 … N` in turn, with
//! the grades below `k` already in normal form, split the current grade-`k` term into its resonant
//! part `Z_k` (the `a = b` monomials, i.e. functions of `J` alone) and the rest, and solve the
//! homological equation
//!
//! ```text
//! H_k + {ν ξη, χ_k} = Z_k,     {ν ξη, ξ^a η^b} = −iν (a − b) ξ^a η^b
//!   ⇒  χ_k = Σ_{a≠b} −i h_{ab} / (ν (a − b)) ξ^a η^b,
//! ```
//!
//! then replace `H ← exp(L_{χ_k}) H`, `L_χ f = {f, χ}`, truncated at grade `N` (`L_{χ_k}` raises
//! the grade by `k`, so the series `Σ L^m/m!` stops by itself). After step `N`,
//! `H̄ = Σ_{k=0}^{N} Z_k` depends on `J` alone, and the frequency–amplitude relation is
//! `ω(J) = ∂H̄/∂J`. This is the composition-of-Lie-transforms form of Deprit's method
//! (Deprit 1969; Dragt & Finn 1976): it produces the same normal form to every order, and its
//! inverse is simply the composition of the inverse exponentials in reverse order.
//!
//! # The near-identity transformation
//!
//! `exp(L_χ) f (y) = f(φ_χ(y))` with `φ_χ` the time-one flow of `χ`, so after the `N` steps the old
//! variables are `x = φ_{χ_1} ∘ … ∘ φ_{χ_N}(y)` and
//!
//! ```text
//! ξ_old(y) = exp(L_{χ_N}) ⋯ exp(L_{χ_1}) ξ          (exp(L_{χ_1}) applied first),
//! ξ_new(x) = exp(−L_{χ_1}) ⋯ exp(−L_{χ_N}) ξ        (exp(−L_{χ_N}) applied first),
//! ```
//!
//! both kept as graded Poisson series to grade `N` ([`NormalForm::old_from_new`],
//! [`NormalForm::new_from_old`]). The new action is `J' = |ξ_new|²`, the new angle `arg ξ_new`, and
//! in the new variables the motion is `J' = const`, `w' = w'_0 + ω(J') t`.
//!
//! # Cost
//!
//! For a polynomial potential the grade-`k` term has `O(k)` monomials, so one bracket at grade
//! `N` costs `O(N²)` monomial products and the whole construction `O(N⁵)` in the worst case (with
//! `O(N)` Lie terms per step); the pendulum to order 12 is built in about a millisecond
//! (measured in `tests/normal_form.rs` and `examples/pendulum_order_n.rs`).
//!
//! # The pendulum
//!
//! [`PendulumNormalForm`] specialises to `H = ½p² + n²(1 − cos θ)`, graded by powers of `a²`
//! (`θ^{2j}` has grade `j − 1`), and turns the normal form into the period series
//! `τ/(2π/n) = 1 + a²/16 + 11a⁴/3072 + …` (`a` the amplitude). That series (of `2K(k)/π`,
//! `k = sin(a/2)`) has radius of convergence `a = π` in `a` — its only singularities are the
//! logarithmic branch points `a = ±π` where `k = 1` — i.e. radius `π²` in `a²`: the separatrix.
//! The frequency series `ω(J)` in the true action has radius `J_s = 8n/π`, the action of the
//! separatrix (where `dE/dJ = 2π/τ → 0`). Near the separatrix phase averaging is meaningless
//! so [`PendulumNormalForm::period_ratio`] returns a [`ConvergenceWarning`] when the small
//! parameter `μ = (a/π)²` exceeds `1/2` and refuses amplitudes `a ≥ π`.
//!
//! # References
//! * A. Deprit, "Canonical transformations depending on a small parameter", *Celestial Mechanics*
//!   1, 12–30 (1969), doi:10.1007/BF01230629.
//! * A. J. Dragt and J. M. Finn, "Lie series and invariant functions for analytic symplectic
//!   maps", *J. Math. Phys.* 17, 2215–2227 (1976).
//! * S. Ferraz-Mello, *Canonical Perturbation Theories*, Springer 2007, ch. 2–3 (Lie series,
//!   d'Alembert characteristic, homological equation).
//! * A. H. Nayfeh, *Perturbation Methods*, Wiley 1973, ch. 4 (Lindstedt–Poincaré; the
//!   cross-check in [`super::lindstedt`]).

use crate::error::{finite, positive, Error, Result};
use crate::perturbation::lindstedt::{series_pow_ball, tail_ratio, Ball};
use crate::systems::pendulum_exact::amplitude_from_state;
use nalgebra::Complex;
use std::collections::BTreeMap;
use std::f64::consts::PI;

/// Complex `f64`.
pub type C64 = Complex<f64>;

/// Highest grade `N` accepted by [`NormalForm::new`]. The work grows like `N⁴`–`N⁵` (pendulum:
/// 1.1 ms at `N = 12`, 18 ms at `N = 24`, so about a second at `N = 64` by extrapolation). The cap
/// keeps a typo from running for hours.
pub const MAX_NORMAL_FORM_ORDER: usize = 64;

/// Highest order (power of `a²`) of [`PendulumNormalForm`]. The `a^{2k}` coefficients of the period
/// series fall like `π^{−2k}/k`; at order 40 they are ~1e−21 of the leading one, and any
/// amplitude where they still matter (a ≳ 2.9) is already flagged by the convergence warning.
pub const MAX_PENDULUM_ORDER: usize = 40;

/// Small parameter `μ = (a/π)²` above which [`PendulumNormalForm::period_ratio`] warns.
///
/// The period coefficients obey `c_{k+1}/c_k ≤ 1/π²` (checked in `tests/normal_form.rs` up to
/// `k = 12`; asymptotically `c_{k+1} π²/c_k → k/(k+1)` for the logarithmic singularity at `a = π`),
/// so the tail after the term `T_N = c_N a^{2N}` is at most `T_N μ/(1 − μ)`. For `μ ≤ 1/2` that
/// bound does not exceed the last term kept — the usual "error below the last term" rule of an
/// asymptotic/convergent series; beyond it the omitted tail can dominate and the truncated series
/// says nothing about the error. `μ = 1/2` is `a = π/√2 ≈ 2.221`.
pub const PENDULUM_WARNING_MU: f64 = 0.5;

/// A Poisson series `Σ c_{ab} ξ^a η^b` (see the module documentation for the variables).
#[derive(Clone, Debug, Default, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(into = "Vec<((u32, u32), C64)>", from = "Vec<((u32, u32), C64)>")
)]
pub struct PoissonSeries {
    terms: BTreeMap<(u32, u32), C64>,
}

/// Stored as the list of its terms `((a, b), c)` (formats such as JSON and TOML key maps by strings).
#[cfg(feature = "serde")]
impl From<PoissonSeries> for Vec<((u32, u32), C64)> {
    fn from(s: PoissonSeries) -> Self {
        s.terms.into_iter().collect()
    }
}

/// The series `Σ c ξ^a η^b` of a list of terms (repeated exponents add).
#[cfg(feature = "serde")]
impl From<Vec<((u32, u32), C64)>> for PoissonSeries {
    fn from(terms: Vec<((u32, u32), C64)>) -> Self {
        let mut s = PoissonSeries::zero();
        for ((a, b), c) in terms {
            s.add_term(a, b, c);
        }
        s
    }
}

impl PoissonSeries {
    /// The zero series.
    pub fn zero() -> Self {
        Self::default()
    }

    /// `c ξ^a η^b`.
    pub fn monomial(a: u32, b: u32, c: C64) -> Self {
        let mut s = Self::zero();
        s.add_term(a, b, c);
        s
    }

    /// `ξ = √J e^{iw}`.
    pub fn xi() -> Self {
        Self::monomial(1, 0, C64::new(1.0, 0.0))
    }

    /// The action `J = ξη`.
    pub fn action() -> Self {
        Self::monomial(1, 1, C64::new(1.0, 0.0))
    }

    /// `c J^{m/2} e^{ikw}` in action–angle form, i.e. `c ξ^{(m+k)/2} η^{(m−k)/2}`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] unless `|k| ≤ m` and `k ≡ m (mod 2)` — the d'Alembert
    /// characteristic: only such terms are analytic (polynomial in `q, p`) at `J = 0`;
    /// [`Error::NonFinite`] for a non-finite coefficient.
    pub fn action_angle_term(m: u32, k: i32, c: C64) -> Result<Self> {
        finite("Poisson-series coefficient (re)", c.re)?;
        finite("Poisson-series coefficient (im)", c.im)?;
        let (mi, ki) = (i64::from(m), i64::from(k));
        if ki.abs() > mi || (mi - ki).rem_euclid(2) != 0 {
            return Err(Error::invalid(
                "action–angle term J^{m/2} e^{ikw}",
                format!(
                    "m = {m}, k = {k}: need |k| ≤ m and k ≡ m (mod 2) (d'Alembert characteristic)"
                ),
            ));
        }
        Ok(Self::monomial(
            ((mi + ki) / 2) as u32,
            ((mi - ki) / 2) as u32,
            c,
        ))
    }

    /// `(ξ + η)^m` times `c`: the building block of a potential polynomial in `q`.
    pub fn binomial_power(m: u32, c: f64) -> Self {
        let mut s = Self::zero();
        let mut binom = 1.0_f64; // C(m, r), exact below 2^53 (m ≤ 56)
        for r in 0..=m {
            s.add_term(r, m - r, C64::new(c * binom, 0.0));
            binom = binom * f64::from(m - r) / f64::from(r + 1);
        }
        s
    }

    /// Add `c ξ^a η^b`.
    pub fn add_term(&mut self, a: u32, b: u32, c: C64) {
        if c == C64::new(0.0, 0.0) {
            return;
        }
        *self.terms.entry((a, b)).or_insert(C64::new(0.0, 0.0)) += c;
    }

    /// `self += s · other`.
    pub fn add_scaled(&mut self, other: &Self, s: C64) {
        for (&(a, b), c) in &other.terms {
            self.add_term(a, b, c * s);
        }
    }

    /// Coefficient of `ξ^a η^b`.
    pub fn coefficient(&self, a: u32, b: u32) -> C64 {
        self.terms
            .get(&(a, b))
            .copied()
            .unwrap_or(C64::new(0.0, 0.0))
    }

    /// Iterator over `((a, b), c)`.
    pub fn iter(&self) -> impl Iterator<Item = (&(u32, u32), &C64)> {
        self.terms.iter()
    }

    /// Number of stored monomials.
    pub fn len(&self) -> usize {
        self.terms.len()
    }

    /// Whether no monomial is stored.
    pub fn is_empty(&self) -> bool {
        self.terms.is_empty()
    }

    /// Poisson bracket `{self, g} = i Σ (a d − b c) c₁ c₂ ξ^{a+c−1} η^{b+d−1}`.
    pub fn bracket(&self, g: &Self) -> Self {
        let mut out = Self::zero();
        for (&(a, b), c1) in &self.terms {
            for (&(c, d), c2) in &g.terms {
                let w = i64::from(a) * i64::from(d) - i64::from(b) * i64::from(c);
                if w != 0 {
                    // w ≠ 0 implies a + c ≥ 1 and b + d ≥ 1.
                    let coef = c1 * c2 * C64::new(0.0, w as f64);
                    out.add_term(a + c - 1, b + d - 1, coef);
                }
            }
        }
        out
    }

    /// Value at `(ξ, η)`; for a real phase point `η = ξ̄`.
    pub fn eval(&self, xi: C64, eta: C64) -> C64 {
        self.terms
            .iter()
            .map(|(&(a, b), c)| c * xi.powu(a) * eta.powu(b))
            .sum()
    }

    /// Value at the real phase point `(J, w)`.
    pub fn eval_action_angle(&self, action: f64, angle: f64) -> C64 {
        let xi = C64::from_polar(action.sqrt(), angle);
        self.eval(xi, xi.conj())
    }

    /// Largest `|c_{ba} − c̄_{ab}|`: zero for a real-valued series.
    pub fn reality_defect(&self) -> f64 {
        self.terms
            .iter()
            .map(|(&(a, b), c)| (self.coefficient(b, a) - c.conj()).norm())
            .fold(0.0, f64::max)
    }

    /// Largest `|c_{ab}|`.
    pub fn max_abs(&self) -> f64 {
        self.terms.values().map(|c| c.norm()).fold(0.0, f64::max)
    }
}

/// Apply `exp(s L_χ)` (`L_χ f = {f, χ}`, `s = ±1`) to a graded series `f` (index = grade),
/// with `χ` of grade `g ≥ 1`, truncating at the last grade of `f`.
fn lie_exp(f: &[PoissonSeries], chi: &PoissonSeries, g: usize, s: f64) -> Vec<PoissonSeries> {
    let top = f.len() - 1;
    let mut out = f.to_vec();
    if chi.is_empty() {
        return out;
    }
    // term holds (s^m/m!) L^m f, shifted by m·g grades.
    let mut term: Vec<PoissonSeries> = f.to_vec();
    let mut m = 1usize;
    while m * g <= top {
        let mut next = vec![PoissonSeries::zero(); top + 1];
        let mut any = false;
        for (grade, t) in term.iter().enumerate() {
            if t.is_empty() || grade + g > top {
                continue;
            }
            let b = t.bracket(chi);
            if !b.is_empty() {
                next[grade + g].add_scaled(&b, C64::new(s / m as f64, 0.0));
                any = true;
            }
        }
        if !any {
            break;
        }
        for (o, t) in out.iter_mut().zip(&next) {
            o.add_scaled(t, C64::new(1.0, 0.0));
        }
        term = next;
        m += 1;
    }
    out
}

/// Sum of a graded series at `(ξ, ξ̄)`.
fn eval_graded(f: &[PoissonSeries], xi: C64) -> C64 {
    f.iter().map(|t| t.eval(xi, xi.conj())).sum()
}

/// Normal form of `H = ν J + Σ_{k=1}^{N} ε^k H_k` to grade `N` (see the module documentation).
#[derive(Clone, Debug)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(remote = "Self")
)]
pub struct NormalForm {
    nu: f64,
    order: usize,
    generators: Vec<PoissonSeries>,
    normal: Vec<PoissonSeries>,
    old_from_new: Vec<PoissonSeries>,
    new_from_old: Vec<PoissonSeries>,
    imag_residue: f64,
}

/// Stored as its fields.
#[cfg(feature = "serde")]
impl serde::Serialize for NormalForm {
    fn serialize<S: serde::Serializer>(
        &self,
        serializer: S,
    ) -> std::result::Result<S::Ok, S::Error> {
        NormalForm::serialize(self, serializer)
    }
}

/// A stored normal form is accepted with `ν > 0`, `N ∈ 1..=MAX_NORMAL_FORM_ORDER`, `N` generators,
/// `N + 1` grades in each series and finite coefficients, as [`NormalForm::new`] builds it.
#[cfg(feature = "serde")]
impl<'de> serde::Deserialize<'de> for NormalForm {
    fn deserialize<D: serde::Deserializer<'de>>(
        deserializer: D,
    ) -> std::result::Result<Self, D::Error> {
        let r = NormalForm::deserialize(deserializer)?;
        let checked = || -> Result<()> {
            positive("oscillator frequency ν", r.nu)?;
            if !(1..=MAX_NORMAL_FORM_ORDER).contains(&r.order) {
                return Err(Error::out_of_domain(
                    "normal-form order N",
                    r.order as f64,
                    format!("{{1, …, {MAX_NORMAL_FORM_ORDER}}}"),
                ));
            }
            let grades = [
                ("generators", &r.generators, r.order),
                ("normal form", &r.normal, r.order + 1),
                ("old from new", &r.old_from_new, r.order + 1),
                ("new from old", &r.new_from_old, r.order + 1),
            ];
            for (what, series, len) in grades {
                if series.len() != len {
                    return Err(Error::invalid(
                        what,
                        format!("{} grades, expected {len}", series.len()),
                    ));
                }
                for (_, c) in series.iter().flat_map(PoissonSeries::iter) {
                    finite(what, c.re)?;
                    finite(what, c.im)?;
                }
            }
            finite("imaginary residue", r.imag_residue)?;
            Ok(())
        };
        checked().map_err(serde::de::Error::custom)?;
        Ok(r)
    }
}

impl NormalForm {
    /// Build the normal form of `H = ν ξη + Σ_k ε^k H_k`, `perturbation[k−1] = H_k`, to grade
    /// `order = N` (grades of the perturbation beyond `N` are ignored, missing ones are zero).
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `ν ≤ 0` or `order ∉ 1..=MAX_NORMAL_FORM_ORDER`;
    /// [`Error::NonFinite`] for a non-finite coefficient; [`Error::InvalidInput`] if some `H_k`
    /// is not real-valued (`|c_{ba} − c̄_{ab}| > 1e−12 max|c|`: the normal form of a complex
    /// Hamiltonian is not a real frequency).
    pub fn new(nu: f64, perturbation: &[PoissonSeries], order: usize) -> Result<Self> {
        let nu = positive("oscillator frequency ν", nu)?;
        if !(1..=MAX_NORMAL_FORM_ORDER).contains(&order) {
            return Err(Error::out_of_domain(
                "normal-form order N",
                order as f64,
                format!("{{1, …, {MAX_NORMAL_FORM_ORDER}}}"),
            ));
        }
        for (k, hk) in perturbation.iter().enumerate() {
            for (_, c) in hk.iter() {
                finite(format!("coefficient of H_{}", k + 1), c.re)?;
                finite(format!("coefficient of H_{}", k + 1), c.im)?;
            }
            // Rounding of the input coefficients themselves is the only legitimate defect.
            if hk.reality_defect() > 1e-12 * hk.max_abs() {
                return Err(Error::invalid(
                    format!("H_{}", k + 1),
                    "not real-valued: the coefficient of ξ^b η^a must be the conjugate of that \
                     of ξ^a η^b",
                ));
            }
        }
        let mut h: Vec<PoissonSeries> = vec![PoissonSeries::zero(); order + 1];
        h[0] = PoissonSeries::monomial(1, 1, C64::new(nu, 0.0));
        for (k, hk) in perturbation.iter().enumerate().take(order) {
            h[k + 1] = hk.clone();
        }
        let mut generators = Vec::with_capacity(order);
        for k in 1..=order {
            let mut chi = PoissonSeries::zero();
            for (&(a, b), c) in h[k].iter() {
                if a != b {
                    let d = nu * (f64::from(a) - f64::from(b));
                    chi.add_term(a, b, c * C64::new(0.0, -1.0 / d));
                }
            }
            h = lie_exp(&h, &chi, k, 1.0);
            generators.push(chi);
        }
        // After step k grade k is resonant up to rounding: drop the O(ε_mach) remainders.
        let mut imag_residue = 0.0_f64;
        let normal: Vec<PoissonSeries> = h
            .iter()
            .map(|hk| {
                let mut z = PoissonSeries::zero();
                for (&(a, b), c) in hk.iter() {
                    if a == b {
                        imag_residue = imag_residue.max(c.im.abs());
                        z.add_term(a, b, C64::new(c.re, 0.0));
                    }
                }
                z
            })
            .collect();
        let mut ident = vec![PoissonSeries::zero(); order + 1];
        ident[0] = PoissonSeries::xi();
        let mut old_from_new = ident.clone();
        for (k, chi) in generators.iter().enumerate() {
            old_from_new = lie_exp(&old_from_new, chi, k + 1, 1.0);
        }
        let mut new_from_old = ident;
        for (k, chi) in generators.iter().enumerate().rev() {
            new_from_old = lie_exp(&new_from_old, chi, k + 1, -1.0);
        }
        Ok(Self {
            nu,
            order,
            generators,
            normal,
            old_from_new,
            new_from_old,
            imag_residue,
        })
    }

    /// Oscillator frequency `ν`.
    pub fn nu(&self) -> f64 {
        self.nu
    }

    /// Grade `N`.
    pub fn order(&self) -> usize {
        self.order
    }

    /// The generators `χ_1 … χ_N` (index `k − 1`).
    pub fn generators(&self) -> &[PoissonSeries] {
        &self.generators
    }

    /// The normal form by grade, `Z_0 = ν J, Z_1, …, Z_N` (each a function of `J = ξη` alone).
    pub fn normal_terms(&self) -> &[PoissonSeries] {
        &self.normal
    }

    /// `H̄(J) = Σ_m h_m J^m` as the coefficient vector `h_0 … h_M` (grades summed).
    pub fn energy_coefficients(&self) -> Vec<f64> {
        let mut out = Vec::new();
        for z in &self.normal {
            for (&(a, _), c) in z.iter() {
                let m = a as usize;
                if out.len() <= m {
                    out.resize(m + 1, 0.0);
                }
                out[m] += c.re;
            }
        }
        out
    }

    /// `ω(J) = dH̄/dJ = Σ_m ω_m J^m` as `ω_0 … ω_{M−1}` (`ω_0 = ν`).
    pub fn frequency_coefficients(&self) -> Vec<f64> {
        let h = self.energy_coefficients();
        (1..h.len()).map(|m| m as f64 * h[m]).collect()
    }

    /// `H̄(J)`, refused where the truncated series has not converged.
    ///
    /// # Errors
    /// As [`Self::frequency_estimate`] (without the sign condition on the value).
    pub fn energy(&self, action: f64) -> Result<f64> {
        Ok(self
            .estimate(
                "normal-form energy H̄(J)",
                &self.energy_coefficients(),
                action,
            )?
            .value)
    }

    /// `ω(J) = dH̄/dJ`, refused where the truncated series has not converged; the diagnostics of
    /// a series that converges slowly are in [`Self::frequency_estimate`].
    ///
    /// # Errors
    /// As [`Self::frequency_estimate`].
    pub fn frequency(&self, action: f64) -> Result<f64> {
        Ok(self.frequency_estimate(action)?.value)
    }

    /// `ω(J) = Σ ω_m J^m` truncated, with convergence diagnostics.
    ///
    /// The convergence of the truncated series is judged from its own terms: `q` is the
    /// [`tail_ratio`] of `|ω_m| J^m` (the largest per-order ratio of successive terms over the last
    /// half of the series; for a series of radius `R` it tends to `J/R`). For `q < 1` the omitted
    /// tail is estimated as `|ω_N J^N| q/(1 − q)` (geometric continuation) and for
    /// `q > SERIES_WARNING_RATIO` the estimate carries [`ConvergenceWarning::SlowTerms`]: that
    /// tail may then exceed the last term kept. For `q ≥ 1` the terms grow and the truncated sum
    /// approximates nothing; a frequency `≤ 0` is not the frequency of any libration. Both are
    /// refused (e.g. Duffing `H = ½(p² + q²) + q⁴/4` at `J = 1`, where the order-8 series sums
    /// to `ω = −116`; its radius in `J` is about 0.36).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] for `J < 0`;
    /// [`Error::NotConverged`] for `q ≥ 1`, for an overflowing sum and for `ω ≤ 0`.
    pub fn frequency_estimate(&self, action: f64) -> Result<SeriesEstimate> {
        let est = self.estimate(
            "normal-form frequency ω(J)",
            &self.frequency_coefficients(),
            action,
        )?;
        if est.value <= 0.0 {
            return Err(Error::NotConverged {
                what: format!(
                    "normal-form frequency ω(J) at J = {action:e}: the truncated series sums to \
                     ω = {:e} ≤ 0, which is the frequency of no libration",
                    est.value
                ),
                iterations: self.order,
                residual: est.last_term,
            });
        }
        Ok(est)
    }

    /// The period `2π/ω(J)` with the diagnostics of [`Self::frequency_estimate`] (last term and
    /// tail bound converted to the period to first order, `δT = T δω/ω`).
    ///
    /// # Errors
    /// As [`Self::frequency_estimate`].
    pub fn period(&self, action: f64) -> Result<SeriesEstimate> {
        let mut e = self.frequency_estimate(action)?;
        let period = 2.0 * PI / e.value;
        e.last_term *= period / e.value;
        e.tail_bound *= period / e.value;
        e.value = period;
        Ok(e)
    }

    /// A truncated series `Σ c_m J^m` at `J`, with the diagnostics of [`Self::frequency_estimate`].
    fn estimate(&self, what: &str, c: &[f64], action: f64) -> Result<SeriesEstimate> {
        let j = finite("action J", action)?;
        if j < 0.0 {
            return Err(Error::out_of_domain("action J", j, "[0, ∞)"));
        }
        let q = tail_ratio(c, j);
        let last = c.len().saturating_sub(1);
        let last_term = c.last().map_or(0.0, |cl| cl * j.powi(last as i32));
        let value = horner(c, j);
        if !(q < 1.0 && value.is_finite()) {
            return Err(Error::NotConverged {
                what: format!(
                    "{what} at J = {j:e}: the terms of the truncated series grow by a factor \
                     {q:e} per order (outside its radius of convergence), sum {value:e}"
                ),
                iterations: self.order,
                residual: last_term,
            });
        }
        let warning = (q > SERIES_WARNING_RATIO).then_some(ConvergenceWarning::SlowTerms {
            ratio: q,
            limit: SERIES_WARNING_RATIO,
            order: self.order,
        });
        Ok(SeriesEstimate {
            value,
            small_parameter: q,
            last_term,
            tail_bound: last_term.abs() * q / (1.0 - q),
            warning,
        })
    }

    /// Old `ξ` as a graded series in the new variables (grade 0 is `ξ`).
    pub fn old_from_new(&self) -> &[PoissonSeries] {
        &self.old_from_new
    }

    /// New `ξ` as a graded series in the old variables.
    pub fn new_from_old(&self) -> &[PoissonSeries] {
        &self.new_from_old
    }

    /// Largest imaginary part dropped from the resonant terms (rounding only, for a real `H`).
    pub fn imaginary_residue(&self) -> f64 {
        self.imag_residue
    }

    /// Map an old phase point, given as `ξ = √J e^{iw}`, to the new `ξ'` (truncated at grade `N`).
    pub fn to_new(&self, xi_old: C64) -> C64 {
        eval_graded(&self.new_from_old, xi_old)
    }

    /// Map a new phase point `ξ'` back to the old `ξ`.
    pub fn to_old(&self, xi_new: C64) -> C64 {
        eval_graded(&self.old_from_new, xi_new)
    }

    /// Per-grade contributions of `to_new` at `ξ_old` (for convergence monitoring).
    pub fn to_new_by_grade(&self, xi_old: C64) -> Vec<C64> {
        self.new_from_old
            .iter()
            .map(|t| t.eval(xi_old, xi_old.conj()))
            .collect()
    }
}

/// `Σ c_k x^k`.
fn horner(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, ck| acc * x + ck)
}

/// How the monomials `q^m` of a potential are graded.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Grading {
    /// `q^m` has grade `m − 2` (generic polynomial potentials, e.g. a cubic term).
    Degree,
    /// `q^m` has grade `(m − 2)/2`; only even `m` allowed (even potentials such as the pendulum:
    /// grade = power of the squared amplitude).
    EvenDegree,
}

/// The graded perturbation `Σ_m v_m q^m` of the oscillator `½(p² + n²q²)`, with
/// `q^m = (2n)^{−m/2} (ξ + η)^m`.
///
/// # Errors
/// [`Error::OutOfDomain`] for `n ≤ 0`; [`Error::InvalidInput`] for a power `m < 3`, an odd `m`
/// with [`Grading::EvenDegree`], or `m > 2 + MAX_NORMAL_FORM_ORDER·(1 or 2)`;
/// [`Error::NonFinite`] for a non-finite coefficient.
pub fn potential_perturbation(
    n: f64,
    potential: &[(u32, f64)],
    grading: Grading,
) -> Result<Vec<PoissonSeries>> {
    let n = positive("oscillator frequency n", n)?;
    let mut out: Vec<PoissonSeries> = Vec::new();
    for &(m, v) in potential {
        finite(format!("coefficient of q^{m}"), v)?;
        if m < 3 {
            return Err(Error::invalid(
                format!("power q^{m}"),
                "the perturbation starts at q³ (fold q² into n)",
            ));
        }
        let grade = match grading {
            Grading::Degree => (m - 2) as usize,
            Grading::EvenDegree => {
                if m % 2 == 1 {
                    return Err(Error::invalid(
                        format!("power q^{m}"),
                        "odd power with Grading::EvenDegree",
                    ));
                }
                ((m - 2) / 2) as usize
            }
        };
        if grade > MAX_NORMAL_FORM_ORDER {
            return Err(Error::invalid(
                format!("power q^{m}"),
                format!("grade {grade} exceeds MAX_NORMAL_FORM_ORDER = {MAX_NORMAL_FORM_ORDER}"),
            ));
        }
        if out.len() < grade {
            out.resize(grade, PoissonSeries::zero());
        }
        let scale = v * (2.0 * n).powf(-0.5 * f64::from(m));
        out[grade - 1].add_scaled(&PoissonSeries::binomial_power(m, scale), C64::new(1.0, 0.0));
    }
    Ok(out)
}

/// Estimated ratio of successive terms above which a truncated series of [`NormalForm`] carries
/// [`ConvergenceWarning::SlowTerms`]: the geometric tail `|T_N| q/(1 − q)` then exceeds the last
/// term kept (the rule of [`PENDULUM_WARNING_MU`], applied to the terms themselves).
pub const SERIES_WARNING_RATIO: f64 = 0.5;

/// Why a perturbative estimate should not be trusted.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ConvergenceWarning {
    /// The terms of a truncated series decrease by less than [`SERIES_WARNING_RATIO`] per order:
    /// the omitted tail may exceed the last term kept.
    SlowTerms {
        /// Estimated ratio `q` of successive terms ([`tail_ratio`]).
        ratio: f64,
        /// The threshold it exceeds.
        limit: f64,
        /// The order `N` of the truncation.
        order: usize,
    },
    /// The small parameter `μ = (a/π)²` exceeds [`PENDULUM_WARNING_MU`]: the omitted tail may
    /// exceed the last term kept; near the separatrix (`μ → 1`) phase averaging is meaningless
    /// as the period grows without bound.
    NearSeparatrix {
        /// `μ = (a/π)²`.
        small_parameter: f64,
        /// The threshold it exceeds.
        limit: f64,
    },
}

/// A truncated-series value with its convergence diagnostics.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SeriesEstimate {
    /// The truncated series.
    pub value: f64,
    /// The small parameter: `μ = (a/π)²` for the pendulum's period series (the ratio of
    /// successive terms in the limit), the estimated ratio `q` of successive terms
    /// ([`tail_ratio`]) for the series of [`NormalForm`].
    pub small_parameter: f64,
    /// The last term kept (`c_N a^{2N}`, `ω_N J^N`, …).
    pub last_term: f64,
    /// Bound on the omitted tail, `|last term| μ/(1 − μ)` (see [`PENDULUM_WARNING_MU`]; for
    /// [`NormalForm`] an estimate by geometric continuation with ratio `q`).
    pub tail_bound: f64,
    /// Set when the small parameter is not small.
    pub warning: Option<ConvergenceWarning>,
}

impl SeriesEstimate {
    /// The value, or [`Error::Separatrix`] if a warning is set — the strict form of the API.
    ///
    /// # Errors
    /// [`Error::Separatrix`] when [`SeriesEstimate::warning`] is
    /// [`ConvergenceWarning::NearSeparatrix`], [`Error::NotConverged`] when it is
    /// [`ConvergenceWarning::SlowTerms`].
    pub fn checked(self) -> Result<f64> {
        match self.warning {
            None => Ok(self.value),
            Some(ConvergenceWarning::SlowTerms {
                ratio,
                limit,
                order,
            }) => Err(Error::NotConverged {
                what: format!(
                    "truncated normal-form series (its terms shrink only by a factor {ratio:.4} \
                     per order, above the limit {limit}: the omitted tail may exceed the last term)"
                ),
                iterations: order,
                residual: self.last_term,
            }),
            Some(ConvergenceWarning::NearSeparatrix {
                small_parameter,
                limit,
            }) => Err(Error::Separatrix {
                what: "pendulum normal form (phase averaging)".into(),
                distance: 1.0 - small_parameter,
                hint: format!(
                    "small parameter (a/π)² = {small_parameter:.4} exceeds {limit}: the \
                     perturbation series is not controlled; use pendulum_exact::period"
                ),
            }),
        }
    }
}

/// Normal form of the pendulum `H = ½ p² + n² (1 − cos θ)` to order `N` in `a²`.
///
/// `n²(1 − cos θ) − ½ n² θ² = n² Σ_{j≥2} (−1)^{j+1} θ^{2j}/(2j)!`, with `θ^{2j}` at grade `j − 1`
/// ([`Grading::EvenDegree`]); order `N` keeps `θ⁴ … θ^{2N+2}`. Results (`n = 1`; verified to
/// `J^{14}` and `a^{28}` against the exact reversion of the elliptic action and the series of
/// `2K(k)/π` in `tests/normal_form.rs`): `H̄ = J − J²/16 − J³/256 − 5J⁴/8192 − …`,
/// `τ/(2π/n) = 1 + a²/16 + 11a⁴/3072 + 173a⁶/737280 + …`.
///
/// ```
/// use hamilton_jacobi::perturbation::normal_form::PendulumNormalForm;
/// let nf = PendulumNormalForm::new(1.0, 2).unwrap();
/// let c = nf.period_ratio_series();
/// assert!((c[1] - 1.0 / 16.0).abs() < 1e-16 && (c[2] - 11.0 / 3072.0).abs() < 1e-17);
/// let est = nf.period_ratio(0.5).unwrap();
/// assert!(est.warning.is_none());
/// assert!(nf.period_ratio(3.0).unwrap().warning.is_some());   // (3/π)² = 0.91: not small
/// assert!(nf.period_ratio(3.0).unwrap().checked().is_err());
/// ```
#[derive(Clone, Debug)]
pub struct PendulumNormalForm {
    n: f64,
    order: usize,
    normal_form: NormalForm,
    period_series: Vec<f64>,
    period_series_error: Vec<f64>,
}

impl PendulumNormalForm {
    /// Build the normal form to order `N ∈ 1..=MAX_PENDULUM_ORDER` in `a²`.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `n ≤ 0` (or non-finite: [`Error::NonFinite`]) or an order
    /// outside `1..=MAX_PENDULUM_ORDER`.
    pub fn new(n: f64, order: usize) -> Result<Self> {
        let n = positive("n", n)?;
        if !(1..=MAX_PENDULUM_ORDER).contains(&order) {
            return Err(Error::out_of_domain(
                "pendulum normal-form order N",
                order as f64,
                format!("{{1, …, {MAX_PENDULUM_ORDER}}}"),
            ));
        }
        let mut pot = Vec::with_capacity(order);
        let mut fact = 2.0_f64; // (2j)!
        for j in 2..=order + 1 {
            fact *= ((2 * j - 1) * (2 * j)) as f64;
            let sign = if j % 2 == 0 { -1.0 } else { 1.0 };
            pot.push(((2 * j) as u32, sign * n * n / fact));
        }
        let pert = potential_perturbation(n, &pot, Grading::EvenDegree)?;
        let normal_form = NormalForm::new(n, &pert, order)?;
        let (period_series, period_series_error) = period_series_from(&normal_form, n, order);
        Ok(Self {
            n,
            order,
            normal_form,
            period_series,
            period_series_error,
        })
    }

    /// The small-oscillation frequency `n`.
    pub fn n(&self) -> f64 {
        self.n
    }

    /// The order `N` (power of `a²`).
    pub fn order(&self) -> usize {
        self.order
    }

    /// The underlying [`NormalForm`].
    pub fn normal_form(&self) -> &NormalForm {
        &self.normal_form
    }

    /// `H̄(J) = Σ_m h_m J^m`, `m = 0 … N + 1` (`h_1 = n`, `h_2 = −1/16`, `h_3 = −1/(256 n)`, …).
    pub fn energy_coefficients(&self) -> Vec<f64> {
        self.normal_form.energy_coefficients()
    }

    /// `ω(J) = Σ_m ω_m J^m`, `m = 0 … N`.
    pub fn frequency_coefficients(&self) -> Vec<f64> {
        self.normal_form.frequency_coefficients()
    }

    /// `τ/(2π/n) = Σ_{k=0}^{N} c_k a^{2k}` (independent of `n`).
    pub fn period_ratio_series(&self) -> &[f64] {
        &self.period_series
    }

    /// Absolute rounding-error bounds of [`Self::period_ratio_series`]: first-order running error
    /// analysis from the coefficient model [`COEFFICIENT_ULPS`] (see `period_series_from`). The
    /// coefficients of this series come from the turning point `ξ = η = √J₀`, where the monomials
    /// of the transformation alternate in sign: the actual error grows by about 2.3 per order
    /// (measured against exact rationals: 1.8e−13 relative at `k = 10`, 7e−2 at `k = 40`), and
    /// the bound, which adds every rounding in absolute value, lies 10²–10⁴ above it (1.9e−10 at
    /// `k = 10`; it exceeds 1 relative beyond `k ≈ 33`). For high orders use the Lindstedt series
    /// ([`super::lindstedt::lindstedt_pendulum`]), accurate to ~1e−14 at every order.
    pub fn period_ratio_error_bounds(&self) -> &[f64] {
        &self.period_series_error
    }

    /// The truncated period ratio at amplitude `a`, with its convergence diagnostics.
    ///
    /// # Errors
    /// [`Error::NonFinite`]; [`Error::OutOfDomain`] for `a < 0` or `a > π`; [`Error::Separatrix`]
    /// for `a = π` (no libration; the series diverges there). For `(a/π)² > 1/2` the estimate
    /// carries [`ConvergenceWarning::NearSeparatrix`] (use [`SeriesEstimate::checked`] to refuse).
    pub fn period_ratio(&self, amplitude: f64) -> Result<SeriesEstimate> {
        let a = finite("amplitude", amplitude)?;
        let mu = small_parameter(a)?;
        let x = a * a;
        let value = horner(&self.period_series, x);
        let last_term = self.period_series[self.order] * x.powi(self.order as i32);
        let tail_bound = last_term.abs() * mu / (1.0 - mu);
        let warning = (mu > PENDULUM_WARNING_MU).then_some(ConvergenceWarning::NearSeparatrix {
            small_parameter: mu,
            limit: PENDULUM_WARNING_MU,
        });
        Ok(SeriesEstimate {
            value,
            small_parameter: mu,
            last_term,
            tail_bound,
            warning,
        })
    }

    /// The truncated period `τ ≈ (2π/n) Σ c_k a^{2k}` (diagnostics as [`Self::period_ratio`], the
    /// value, last term and tail bound scaled by `2π/n`).
    ///
    /// # Errors
    /// As [`Self::period_ratio`].
    pub fn period(&self, amplitude: f64) -> Result<SeriesEstimate> {
        let mut e = self.period_ratio(amplitude)?;
        let s = 2.0 * PI / self.n;
        e.value *= s;
        e.last_term *= s;
        e.tail_bound *= s;
        Ok(e)
    }

    /// New action–angle `(J', w')` of the libration state `(θ, p)`, with the convergence
    /// diagnostics of its amplitude.
    ///
    /// # Errors
    /// [`Error::NonFinite`]; [`Error::OutOfDomain`] for a rotation (energy above `2n²`);
    /// [`Error::Separatrix`] on the separatrix.
    pub fn to_action_angle(
        &self,
        theta: f64,
        p: f64,
    ) -> Result<(f64, f64, Option<ConvergenceWarning>)> {
        let a = amplitude_from_state(self.n, theta, p)?;
        let mu = small_parameter(a)?;
        // ξ = √J e^{iw} with q = (ξ + ξ̄)/√(2n), p = −√(2n) Im ξ.
        let xi = C64::new(theta * (0.5 * self.n).sqrt(), -p / (2.0 * self.n).sqrt());
        let xn = self.normal_form.to_new(xi);
        let warning = (mu > PENDULUM_WARNING_MU).then_some(ConvergenceWarning::NearSeparatrix {
            small_parameter: mu,
            limit: PENDULUM_WARNING_MU,
        });
        Ok((xn.norm_sqr(), xn.arg(), warning))
    }

    /// The state `(θ, p)` with new action–angle `(J', w')`.
    ///
    /// # Errors
    /// [`Error::NonFinite`]; [`Error::OutOfDomain`] for `J' < 0` or `J' ≥ 8n/π` (the separatrix
    /// action: larger actions are rotations, outside the normal form's domain).
    pub fn from_action_angle(&self, action: f64, angle: f64) -> Result<(f64, f64)> {
        let j = finite("action J'", action)?;
        let w = finite("angle w'", angle)?;
        let js = 8.0 * self.n / PI;
        if !(0.0..js).contains(&j) {
            return Err(Error::out_of_domain(
                "action J'",
                j,
                format!("[0, 8n/π) = [0, {js})"),
            ));
        }
        let xo = self.normal_form.to_old(C64::from_polar(j.sqrt(), w));
        Ok((
            xo.re * (2.0 / self.n).sqrt(),
            -(2.0 * self.n).sqrt() * xo.im,
        ))
    }

    /// The perturbative motion: `J' = const`, `w' = w'_0 + ω(J') t`, mapped back to `(θ, p)`.
    ///
    /// # Errors
    /// As [`Self::to_action_angle`] and [`Self::from_action_angle`]; also [`Error::NonFinite`] for
    /// `t`.
    pub fn state_at(&self, theta0: f64, p0: f64, t: f64) -> Result<(f64, f64)> {
        let t = finite("t", t)?;
        let (j, w0, _) = self.to_action_angle(theta0, p0)?;
        // The warnings of the amplitude were reported by `to_action_angle`; the frequency series
        // is refused only where it has not converged at all.
        let w = w0 + self.normal_form.frequency_estimate(j)?.value * t;
        self.from_action_angle(j, w)
    }
}

/// `μ = (a/π)²` for `a ∈ [0, π)`.
fn small_parameter(a: f64) -> Result<f64> {
    if a < 0.0 {
        return Err(Error::out_of_domain("amplitude", a, "[0, π)"));
    }
    if a == PI {
        return Err(Error::Separatrix {
            what: "pendulum normal form".into(),
            distance: 0.0,
            hint: "amplitude π is the separatrix: the series in a² diverges there (radius π²)"
                .into(),
        });
    }
    if a > PI {
        return Err(Error::out_of_domain(
            "amplitude",
            a,
            "[0, π): beyond π the motion is a rotation",
        ));
    }
    Ok((a / PI) * (a / PI))
}

/// Relative rounding error assumed for a monomial coefficient of grade `g` of the normal form and
/// of its transformation series: `COEFFICIENT_ULPS · (g + 1) · ε`. Each coefficient is a sum of
/// `O(g)` Lie terms; the model is checked on the energy coefficients `h_m` against exact rationals
/// at every order offered (`tests/normal_form.rs`, measured ≤ 0.6 of it).
pub const COEFFICIENT_ULPS: f64 = 8.0;

/// Period-ratio series in `x = a²` from the normal form, with absolute rounding-error bounds.
///
/// At the turning point `θ = a`, `p = 0` the old variables are `ξ = η = √J₀`, `J₀ = n a²/2`, so the
/// new action is `J'(J₀) = Σ_k j_k J₀^{k+1}` (grade `k` of `ξ'ξ̄'` is homogeneous of degree
/// `2k + 2`: evaluate at `ξ = η = 1`). Then `ω/n = Σ_m (ω_m/n) J'^m` and `τ/(2π/n) = (ω/n)^{−1}`,
/// all re-expanded in `x` to `x^N`.
///
/// The bounds follow the running error analysis of [`super::lindstedt::LindstedtSeries`] from the
/// coefficient model [`COEFFICIENT_ULPS`]: the sum of a grade-`g` series at `ξ = η = 1` carries
/// `(COEFFICIENT_ULPS (g + 1) + terms + 2) ε Σ|c|`. Its alternating monomials cancel, which is
/// what makes the high coefficients of this series lose digits (about a factor 2.3 per order).
fn period_series_from(nf: &NormalForm, n: f64, order: usize) -> (Vec<f64>, Vec<f64>) {
    let len = order + 1;
    let eps = f64::EPSILON;
    // ξ'η' graded: products of the graded ξ' with its conjugate.
    let one = C64::new(1.0, 0.0);
    let sums: Vec<(C64, f64)> = nf
        .new_from_old()
        .iter()
        .enumerate()
        .map(|(g, s)| {
            let mag: f64 = s.iter().map(|(_, c)| c.norm()).sum();
            let ulps = COEFFICIENT_ULPS * (g + 1) as f64 + s.len() as f64 + 2.0;
            (s.eval(one, one), ulps * eps * mag)
        })
        .collect();
    let mut jprime = vec![Ball::default(); len + 1]; // coefficient of x^{k+1}
    for (g1, &(v1, e1)) in sums.iter().enumerate() {
        for (g2, &(v2, e2)) in sums.iter().enumerate() {
            let g = g1 + g2;
            if g > order {
                continue;
            }
            // Re(v1 v̄2) = a1 a2 + b1 b2: two products and a sum.
            let v = (v1 * v2.conj()).re;
            let (m1, m2) = (v1.norm(), v2.norm());
            let e = m1 * e2 + m2 * e1 + e1 * e2 + 2.0 * eps * m1 * m2;
            let scale = (0.5 * n).powi(g as i32 + 1);
            let term = Ball { v, e }.mul(Ball {
                v: scale,
                e: (g + 2) as f64 * eps * scale,
            });
            jprime[g + 1] = jprime[g + 1].add(term);
        }
    }
    jprime.truncate(len);
    // ω/n as a series in x; ω_m = m h_m with h_m from one grade (m − 1).
    let w = nf.frequency_coefficients();
    let mut omega = vec![Ball::default(); len];
    let mut power = vec![Ball::default(); len];
    power[0] = Ball::exact(1.0);
    for (m, wm) in w.iter().enumerate().take(len) {
        let wn = Ball {
            v: wm / n,
            e: (COEFFICIENT_ULPS * (m + 1) as f64 + 2.0) * eps * (wm / n).abs(),
        };
        for (o, p) in omega.iter_mut().zip(&power) {
            *o = o.add(wn.mul(*p));
        }
        power = mul_trunc(&power, &jprime);
    }
    let c = series_pow_ball(&omega, -1.0);
    (
        c.iter().map(|b| b.v).collect(),
        c.iter().map(|b| b.e).collect(),
    )
}

/// Product of two power series truncated to the length of `a`, with running error bounds.
fn mul_trunc(a: &[Ball], b: &[Ball]) -> Vec<Ball> {
    let len = a.len();
    let mut out = vec![Ball::default(); len];
    for (i, ai) in a.iter().enumerate() {
        for (j, bj) in b.iter().enumerate() {
            if i + j < len {
                out[i + j] = out[i + j].add(ai.mul(*bj));
            }
        }
    }
    out
}

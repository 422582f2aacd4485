//! Lie–Deprit perturbation theory in given action–angle variables.
//!
//! For a Hamiltonian written once, generic over the crate's number types,
//!
//! ```math
//! H(J, \theta; \varepsilon) = \sum_{m \ge 0} \frac{\varepsilon^m}{m!} H_m(J, \theta),\qquad
//! H_0 = H_0(J),\quad J, \theta \in \mathbb R^N,
//! ```
//!
//! Deprit's triangle finds a generator `W = Σ ε^m/m! W_{m+1}` whose Lie transform `E_W` turns
//! `H` into the averaged `K(J′; ε) = Σ ε^m/m! K_m(J′)` (no angle dependence) to order `n`:
//!
//! ```math
//! H^{(i)}_j = H^{(i-1)}_{j+1} + \sum_{k=0}^{j} \binom{j}{k} \{H^{(i-1)}_{j-k}, W_{k+1}\},\qquad
//! K_m = H^{(m)}_0 = \Psi_m + \{H_0, W_m\},
//! ```
//!
//! `Ψ_m` the entry with `W_m = 0`, `{f, g} = Σᵢ ∂f/∂θᵢ ∂g/∂Jᵢ − ∂f/∂Jᵢ ∂g/∂θᵢ`. The homological
//! equation is solved mode by mode in `e^{ik·θ}`: with `ω(J) = ∂H₀/∂J`,
//!
//! ```math
//! K_m = \langle \Psi_m \rangle_\theta,\qquad W_{m,k}(J) = \frac{\Psi_{m,k}(J)}{i\,k\cdot\omega(J)}
//! \quad (k \ne 0).
//! ```
//!
//! A mode with a non-zero coefficient and `|k·ω(J*)| ≤ δ Σᵢ |kᵢ ωᵢ(J*)|` (`δ` =
//! [`LieDepritOptions::small_divisor`]) is a small divisor: [`Error::SmallDivisor`] names `k`
//! and `k·ω`. The same triangle applied to the coordinate functions gives the near-identity map
//! `(J, θ) = E_W(J′, θ′)` (old variables as functions of the new ones) with `H ∘ E_W = K` to
//! order `n`.
//!
//! # Representation
//! Every function is a Poisson series `Σ_k c_k(δJ) e^{ik·θ}` (all `k` with `|kᵢ| ≤ H_max`),
//! each `c_k` a complex polynomial in `δJ = J − J*` about the reference actions `J*`. The
//! `H_m` come from evaluating the user's code on the crate's [`Series`](crate::series::Series)
//! at FFT nodes in `θ` ([`fourier_taylor`]): Taylor in `(δJ, ε)`, Fourier in `θ`, with the
//! Fourier truncation error estimated there. The `J`-dependence is kept as a Taylor polynomial
//! in `δJ` (not exact): every Poisson bracket differentiates once in `J`, so the triangle runs
//! with `δJ`-degree `d + n + 1` and the results (`K`, `ω`, the map) are exact to degree `d` =
//! [`LieDepritOptions::action_degree`] in `δJ`. Products that leave `|kᵢ| ≤ H_max` are dropped
//! and their size is added to [`LieDeprit::fourier_error`].
//!
//! # Scaling
//! [`ActionAngleHamiltonian::scaling`] `= s` declares `H = ε^{−s} h(J, θ; ε)` with `h` the
//! user's function: an amplitude grading without a division by a series that vanishes at
//! `ε = 0`. The pendulum `p²/2 + 1 − cos q` in the oscillator's variables
//! `q = μ√(2J) sin θ`, `p = μ√(2J) cos θ` with `s = 2` is `H = J − μ²J² sin⁴θ/6 + …`, and its
//! `K(J; μ) = J − μ²J²/16 − μ⁴J³/256 − …` carries the coefficients of the pendulum's `K(J)` at
//! `μ = 1`. The coefficients of `ε⁰ … ε^{s−1}` of `h` must vanish.
//!
//! References: A. Deprit, "Canonical transformations depending on a small parameter", *Celestial
//! Mechanics* 1, 12–30 (1969); A. J. Lichtenberg & M. A. Lieberman, *Regular and Chaotic
//! Dynamics*, 2nd ed., Springer 1992, §2.5; S. Ferraz-Mello, *Canonical Perturbation Theories*,
//! Springer 2007, ch. 3–4.

use crate::error::{all_finite, Error, Result};
use crate::series::{fourier_taylor, Monomials, Polynomial};
use crate::DualNum;
use nalgebra::SVector;
use std::collections::BTreeMap;
use std::sync::Arc;

/// The largest order `n` of the triangle.
pub const MAX_LIE_DEPRIT_ORDER: usize = 48;

/// The largest number of stored coefficients `(2H_max + 1)ᴺ · C(N + D, N) · (n + 2)(n + 3)/2`
/// of one triangle (checked before any allocation).
pub const MAX_LIE_DEPRIT_COEFFICIENTS: usize = 1 << 24;

/// Relative size below which a harmonic of `H₀` (or a power `ε^{<s}` of `h`) is rounding: the
/// Taylor coefficients of high degree in `δJ` carry the rounding of large intermediate
/// coefficients (`√(2J)` about a small `J*`), far above `2⁻⁵²`. A larger term is a modelling error
/// and refused; a smaller one is dropped and counted in [`LieDeprit::fourier_error`].
pub const UNPERTURBED_TOLERANCE: f64 = 1e-8;

/// Default relative small-divisor threshold `δ` of [`LieDepritOptions::small_divisor`].
pub const DEFAULT_SMALL_DIVISOR: f64 = 1e-8;

/// A Hamiltonian in action–angle variables with a small parameter, `H(J, θ; ε)`, written once
/// for every number type.
pub trait ActionAngleHamiltonian<const N: usize> {
    /// `h(J, θ; ε)`; the Hamiltonian is `ε^{−s} h` with `s` = [`scaling`](Self::scaling).
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        j: &SVector<D, N>,
        theta: &SVector<D, N>,
        eps: D,
    ) -> D;

    /// The power `s` in `H = ε^{−s} h(J, θ; ε)` (0, the default: `H = h`).
    fn scaling(&self) -> usize {
        0
    }
}

/// Hamilton's equations of an [`ActionAngleHamiltonian`] at a fixed `ε`: the
/// [`Hamiltonian`](crate::Hamiltonian) `H(q = θ, p = J) = ε^{−s} h(J, θ; ε)`, so that every
/// integrator and analysis of the crate applies to the system as written once (for example the
/// orbit against which [`LieDeprit::frequencies`] is checked).
#[derive(Clone, Copy, Debug)]
pub struct AtFixedEpsilon<'a, H> {
    system: &'a H,
    eps: f64,
}

impl<'a, H> AtFixedEpsilon<'a, H> {
    /// `system` at `ε = eps`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite `eps`; [`Error::OutOfDomain`] for `eps = 0` when the
    /// system declares a scaling `s > 0` (`ε^{−s}` is singular there).
    pub fn new<const N: usize>(system: &'a H, eps: f64) -> Result<Self>
    where
        H: ActionAngleHamiltonian<N>,
    {
        let eps = crate::error::finite("ε of the action–angle Hamiltonian", eps)?;
        if eps == 0.0 && system.scaling() > 0 {
            return Err(Error::out_of_domain(
                "ε of an action–angle Hamiltonian with scaling s > 0",
                eps,
                "ε ≠ 0 (H = ε^{−s} h)",
            ));
        }
        Ok(Self { system, eps })
    }
}

impl<H: ActionAngleHamiltonian<N>, const N: usize> crate::Hamiltonian<N> for AtFixedEpsilon<'_, H> {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> D {
        let h = self.system.hamiltonian(p, q, D::from(self.eps));
        match self.system.scaling() {
            0 => h,
            s => h * self.eps.powi(-(s as i32)),
        }
    }
}

/// The pendulum `p²/2 + 1 − cos q` in the harmonic oscillator's action–angle variables
/// `q = μ√(2J) sin θ`, `p = μ√(2J) cos θ`, graded by the amplitude `μ`
/// ([`scaling`](ActionAngleHamiltonian::scaling) `s = 2`):
///
/// ```math
/// H(J, \theta; \mu) = \mu^{-2}\Big(\frac{p^2}{2} + 1 - \cos q\Big)
/// = J - \frac{\mu^2 J^2 \sin^4\theta}{6} + \frac{\mu^4 J^3 \sin^6\theta}{90} - \dots
/// ```
///
/// Every `H_m` is homogeneous of degree `m/2 + 1` in `J`, so `[μ^{2m}] K(J*) = h_{m+1} J*^{m+1}`
/// with `K(J) = J − J²/16 − J³/256 − 5J⁴/8192 − …` the pendulum's energy in its action, the
/// reversion of the exact action `J = (8/π)[E(k) − (1 − k²)K(k)]`, `K + 1 = 2k²` (DLMF 19.5).
#[derive(Clone, Copy, Debug, Default)]
pub struct AmplitudePendulum;

impl ActionAngleHamiltonian<1> for AmplitudePendulum {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        j: &SVector<D, 1>,
        theta: &SVector<D, 1>,
        mu: D,
    ) -> D {
        let r = (j[0] * 2.0).sqrt() * mu;
        let (q, p) = (r * theta[0].sin(), r * theta[0].cos());
        p * p * 0.5 - q.cos() + 1.0
    }

    fn scaling(&self) -> usize {
        2
    }
}

/// The driven linear oscillator `ẍ + ω²x = −εω cos Ωt` in extended phase space (`θ₂ = Ωt`, `J₂`
/// its conjugate), in the oscillator's action–angle variables `x = √(2J₁/ω) sin θ₁`:
///
/// ```math
/// H(J, \theta; \varepsilon) = \omega J_1 + \Omega J_2
/// + \varepsilon \sqrt{2 J_1}\, \sin\theta_1 \cos\theta_2 .
/// ```
///
/// A linear system: the frequencies of its tori are `ω` and `Ω` at every order, and at
/// `Ω = ω` the modes `k = ±(1, −1)` of the forcing are resonant (Lichtenberg & Lieberman §2.2).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DrivenOscillator {
    /// The natural frequency `ω`.
    pub omega: f64,
    /// The driving frequency `Ω`.
    pub drive: f64,
}

impl ActionAngleHamiltonian<2> for DrivenOscillator {
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        j: &SVector<D, 2>,
        theta: &SVector<D, 2>,
        eps: D,
    ) -> D {
        j[0] * self.omega
            + j[1] * self.drive
            + eps * (j[0] * 2.0).sqrt() * theta[0].sin() * theta[1].cos()
    }
}

/// Orders and truncations of [`lie_deprit`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LieDepritOptions {
    /// The order `n` in `ε` of `K` and of the map (`1 ≤ n ≤` [`MAX_LIE_DEPRIT_ORDER`]).
    pub order: usize,
    /// The harmonic bound `H_max` (`|kᵢ| ≤ H_max`) of every Poisson series.
    pub max_harmonic: usize,
    /// The degree `d` in `δJ = J − J*` to which the results are exact.
    pub action_degree: usize,
    /// The relative small-divisor threshold `δ`: `|k·ω| ≤ δ Σᵢ |kᵢ ωᵢ|` is refused.
    pub small_divisor: f64,
}

impl LieDepritOptions {
    /// Order `n`, harmonic bound `H_max`, action degree 1 (frequencies), threshold
    /// [`DEFAULT_SMALL_DIVISOR`].
    pub fn new(order: usize, max_harmonic: usize) -> Self {
        Self {
            order,
            max_harmonic,
            action_degree: 1,
            small_divisor: DEFAULT_SMALL_DIVISOR,
        }
    }
}

/// A Poisson series `Σ_k c_k(δJ) e^{ik·θ}`: wave vector → (real, imaginary) coefficients in
/// the graded order of the `δJ` monomials.
type Terms = BTreeMap<Vec<i32>, (Vec<f64>, Vec<f64>)>;

/// The algebra of the triangle: `δJ` monomials, derivative tables, harmonic bound.
struct Algebra {
    table: Arc<Monomials>,
    /// `deriv[i][a] = (index of α − eᵢ, αᵢ)` for monomial `a` with `αᵢ > 0`.
    deriv: Vec<Vec<Option<(usize, f64)>>>,
    hmax: i32,
    /// Largest coefficient of a product dropped for `|kᵢ| > H_max`.
    dropped: std::cell::Cell<f64>,
}

impl Algebra {
    fn new(n: usize, degree: usize, hmax: i32) -> Result<Self> {
        let table = Arc::new(Monomials::new(n, degree)?);
        let len = table.len();
        let mut deriv = vec![vec![None; len]; n];
        for a in 0..len {
            let e: Vec<u32> = table
                .exponents(a)
                .unwrap_or_default()
                .iter()
                .map(|&x| u32::from(x))
                .collect();
            for (i, d) in deriv.iter_mut().enumerate() {
                if e[i] > 0 {
                    let mut f = e.clone();
                    f[i] -= 1;
                    d[a] = table.index_of(&f).map(|b| (b, f64::from(e[i])));
                }
            }
        }
        Ok(Self {
            table,
            deriv,
            hmax,
            dropped: std::cell::Cell::new(0.0),
        })
    }

    fn len(&self) -> usize {
        self.table.len()
    }

    fn zero(&self) -> (Vec<f64>, Vec<f64>) {
        (vec![0.0; self.len()], vec![0.0; self.len()])
    }

    fn d_dj(&self, i: usize, c: &[f64]) -> Vec<f64> {
        let mut out = vec![0.0; self.len()];
        for (a, d) in self.deriv[i].iter().enumerate() {
            if let Some((b, f)) = d {
                out[*b] += f * c[a];
            }
        }
        out
    }

    fn mul_real(&self, a: &[f64], b: &[f64], out: &mut [f64]) {
        let mut prod = vec![0.0; self.len()];
        let mut scratch = vec![0.0; self.len()];
        // Slices have the table's length: the product cannot fail.
        if self.table.mul(a, b, &mut prod, &mut scratch).is_ok() {
            for (o, p) in out.iter_mut().zip(&prod) {
                *o += p;
            }
        }
    }

    /// `out += s · a·b` (complex, `a`, `b` as (re, im)).
    fn mul_add(
        &self,
        a: &(Vec<f64>, Vec<f64>),
        b: &(Vec<f64>, Vec<f64>),
        s: f64,
        out: &mut (Vec<f64>, Vec<f64>),
    ) {
        let len = self.len();
        let (mut rr, mut ii, mut ri, mut ir) = (
            vec![0.0; len],
            vec![0.0; len],
            vec![0.0; len],
            vec![0.0; len],
        );
        self.mul_real(&a.0, &b.0, &mut rr);
        self.mul_real(&a.1, &b.1, &mut ii);
        self.mul_real(&a.0, &b.1, &mut ri);
        self.mul_real(&a.1, &b.0, &mut ir);
        for x in 0..len {
            out.0[x] += s * (rr[x] - ii[x]);
            out.1[x] += s * (ri[x] + ir[x]);
        }
    }

    /// `{f, g} = Σᵢ ∂f/∂θᵢ ∂g/∂Jᵢ − ∂f/∂Jᵢ ∂g/∂θᵢ`, times `scale`, added to `out`.
    fn bracket_add(&self, f: &Terms, g: &Terms, scale: f64, out: &mut Terms) {
        let n = self.deriv.len();
        let dj = |t: &Terms| -> Vec<Terms> {
            (0..n)
                .map(|i| {
                    t.iter()
                        .map(|(k, (re, im))| (k.clone(), (self.d_dj(i, re), self.d_dj(i, im))))
                        .collect()
                })
                .collect()
        };
        let (df, dg) = (dj(f), dj(g));
        for (k, fk) in f {
            for (l, gl) in g {
                let kl: Vec<i32> = k.iter().zip(l).map(|(a, b)| a + b).collect();
                // i Σᵢ [kᵢ f_k ∂ᵢg_l − lᵢ ∂ᵢf_k g_l]
                let mut acc = self.zero();
                for i in 0..n {
                    if k[i] != 0 {
                        self.mul_add(fk, &dg[i][l], f64::from(k[i]), &mut acc);
                    }
                    if l[i] != 0 {
                        self.mul_add(&df[i][k], gl, -f64::from(l[i]), &mut acc);
                    }
                }
                let (re, im) = acc;
                if kl.iter().any(|&x| x.abs() > self.hmax) {
                    let size = re.iter().chain(&im).fold(0.0f64, |m, x| m.max(x.abs()));
                    self.dropped.set(self.dropped.get().max(size * scale.abs()));
                    continue;
                }
                let e = out.entry(kl).or_insert_with(|| self.zero());
                for x in 0..re.len() {
                    // multiply by i: (re + i im)·i = −im + i re
                    e.0[x] -= scale * im[x];
                    e.1[x] += scale * re[x];
                }
            }
        }
    }
}

fn add_scaled(out: &mut Terms, f: &Terms, s: f64) {
    for (k, (re, im)) in f {
        let len = re.len();
        let e = out
            .entry(k.clone())
            .or_insert_with(|| (vec![0.0; len], vec![0.0; len]));
        for x in 0..len {
            e.0[x] += s * re[x];
            e.1[x] += s * im[x];
        }
    }
}

fn is_zero_k(k: &[i32]) -> bool {
    k.iter().all(|&x| x == 0)
}

fn max_abs(c: &(Vec<f64>, Vec<f64>)) -> f64 {
    c.0.iter().chain(&c.1).fold(0.0f64, |m, x| m.max(x.abs()))
}

fn binomial(n: usize, k: usize) -> f64 {
    (0..k).fold(1.0, |acc, i| acc * (n - i) as f64 / (i + 1) as f64)
}

/// The result of [`lie_deprit`]: the averaged Hamiltonian `K(J′; ε)`, the generator and the
/// near-identity map, with truncation estimates.
#[derive(Debug, Clone)]
pub struct LieDeprit<const N: usize> {
    actions: SVector<f64, N>,
    order: usize,
    action_degree: usize,
    /// `[ε^m] K` as polynomials in `δJ` (`m = 0 … n`), exact to degree `action_degree`.
    energy: Vec<Polynomial>,
    /// `[ε^m] J(J′, θ′)` and `[ε^m] θ(J′, θ′)` (`m = 1 … n`), per coordinate.
    map_j: Vec<Vec<Terms>>,
    map_theta: Vec<Vec<Terms>>,
    /// `[ε^{m−1}] W` sizes, `m = 1 … n`.
    generator_norms: Vec<f64>,
    /// Oscillating part of `Ψ_{n+1}/(n+1)!` at `J*` (sum of `|c_k|`), and `[ε^{n+1}] K`.
    remainder: f64,
    next_energy: f64,
    fourier_error: f64,
}

/// Deprit's triangle to order `n` for `H(J, θ; ε)` about the reference actions `J*`; see the
/// [module docs](self).
///
/// # Errors
/// * NaN/∞ actions, order 0 or above [`MAX_LIE_DEPRIT_ORDER`], a non-positive or non-finite
///   `small_divisor`, storage beyond [`MAX_LIE_DEPRIT_COEFFICIENTS`] or the series and Fourier
///   limits: a typed error before any evaluation;
/// * a non-finite Taylor coefficient at a node (`H` not analytic at `J*`): [`Error::NonFinite`];
/// * `H₀` depending on `θ`, or a term `ε^{<s}` of `h` not zero: [`Error::InvalidInput`] naming the
///   harmonic or power;
/// * a small divisor: [`Error::SmallDivisor`] naming `k` and `k·ω(J*)`.
pub fn lie_deprit<H: ActionAngleHamiltonian<N>, const N: usize>(
    h: &H,
    actions: &SVector<f64, N>,
    options: &LieDepritOptions,
) -> Result<LieDeprit<N>> {
    all_finite("reference actions J*", actions.as_slice())?;
    let n = options.order;
    if n == 0 || n > MAX_LIE_DEPRIT_ORDER {
        return Err(Error::out_of_domain(
            "Lie–Deprit order",
            n as f64,
            format!("1 ≤ n ≤ {MAX_LIE_DEPRIT_ORDER}"),
        ));
    }
    let delta = options.small_divisor;
    if !(delta.is_finite() && delta > 0.0 && delta < 1.0) {
        return Err(Error::out_of_domain(
            "small-divisor threshold",
            delta,
            "(0, 1)",
        ));
    }
    if N == 0 {
        return Err(Error::invalid("Lie–Deprit", "needs at least one angle"));
    }
    let s = h.scaling();
    let m_top = n + 1;
    let too_big = || Error::WorkLimit {
        what: "Lie–Deprit triangle".into(),
        limit: MAX_LIE_DEPRIT_COEFFICIENTS,
        detail: format!(
            "order {n}, harmonic bound {}, action degree {}, scaling {s}",
            options.max_harmonic, options.action_degree
        ),
        hint: "lower the order, the harmonic bound or the action degree".into(),
    };
    let hmax = i32::try_from(options.max_harmonic)
        .ok()
        .filter(|&x| x <= 1 << 12)
        .ok_or_else(too_big)?;
    let tri_degree = options
        .action_degree
        .checked_add(m_top)
        .filter(|&d| d <= crate::series::MAX_SERIES_DEGREE)
        .ok_or_else(too_big)?;
    let total_degree = tri_degree
        .checked_add(s)
        .filter(|&d| d <= crate::series::MAX_SERIES_DEGREE)
        .ok_or_else(too_big)?;
    // Storage bound before building any table.
    let binom_len = (1..=N).try_fold(1usize, |acc, i| {
        acc.checked_mul(tri_degree + i).map(|x| x / i)
    });
    let harmonics = (2 * hmax as usize + 1).checked_pow(N as u32);
    let entries = (m_top + 1) * (m_top + 2) / 2;
    binom_len
        .zip(harmonics)
        .and_then(|(l, k)| l.checked_mul(k))
        .and_then(|x| x.checked_mul(entries))
        .filter(|&x| x <= MAX_LIE_DEPRIT_COEFFICIENTS)
        .ok_or_else(too_big)?;
    let alg = Algebra::new(N, tri_degree, hmax)?;
    let ft = fourier_taylor(actions, options.max_harmonic, total_degree, |j, th, e| {
        h.hamiltonian(j, th, e)
    })?;
    let len = alg.len();
    let et = ft.harmonics[0].cos.monomials().clone();
    // [ε^p] of the expansion as Poisson series in δJ (complex exponentials).
    let order_terms = |p: usize| -> Result<Terms> {
        let mut out = Terms::new();
        for hk in &ft.harmonics {
            let (mut c, mut sn) = (vec![0.0; len], vec![0.0; len]);
            for a in 0..len {
                let mut alpha: Vec<u32> = alg
                    .table
                    .exponents(a)
                    .unwrap_or_default()
                    .iter()
                    .map(|&x| u32::from(x))
                    .collect();
                alpha.push(p as u32);
                if let Some(i) = et.index_of(&alpha) {
                    c[a] = hk.cos.coefficients()[i];
                    sn[a] = hk.sin.coefficients()[i];
                }
            }
            if is_zero_k(&hk.k) {
                out.insert(hk.k.clone(), (c, vec![0.0; len]));
            } else {
                // C cos + S sin = ½(C − iS) e^{ik·θ} + ½(C + iS) e^{−ik·θ}
                let neg: Vec<i32> = hk.k.iter().map(|x| -x).collect();
                let half = |v: &[f64], sg: f64| v.iter().map(|x| 0.5 * sg * x).collect::<Vec<_>>();
                out.insert(hk.k.clone(), (half(&c, 1.0), half(&sn, -1.0)));
                out.insert(neg, (half(&c, 1.0), half(&sn, 1.0)));
            }
        }
        Ok(out)
    };
    let scale_of = |t: &Terms| t.values().map(max_abs).fold(0.0f64, f64::max);
    // The powers ε⁰ … ε^{s−1} of h vanish.
    let mut lead = order_terms(s)?;
    let lead_scale = scale_of(&lead);
    for p in 0..s {
        let t = order_terms(p)?;
        let size = scale_of(&t);
        if size > UNPERTURBED_TOLERANCE * lead_scale {
            return Err(Error::invalid(
                "Lie–Deprit scaling",
                format!(
                    "h(J, θ; ε) must vanish to order ε^{s}; its ε^{p} term has size {size:.3e}"
                ),
            ));
        }
    }
    // H₀ is independent of θ.
    let mut pruned: f64 = 0.0;
    for (k, c) in &lead {
        if is_zero_k(k) {
            continue;
        }
        pruned = pruned.max(max_abs(c));
        if max_abs(c) > UNPERTURBED_TOLERANCE * lead_scale.max(f64::MIN_POSITIVE) {
            return Err(Error::invalid(
                "Lie–Deprit unperturbed Hamiltonian",
                format!(
                    "H₀ depends on the angles: harmonic k = {k:?} has size {:.3e}",
                    max_abs(c)
                ),
            ));
        }
    }
    lead.retain(|k, _| is_zero_k(k));
    let h0 = lead;
    let h0c = h0.get(&vec![0; N]).cloned().unwrap_or_else(|| alg.zero());
    let omega: Vec<Vec<f64>> = (0..N).map(|i| alg.d_dj(i, &h0c.0)).collect();
    let omega0: Vec<f64> = omega.iter().map(|w| w[0]).collect();
    all_finite("ω(J*)", &omega0)?;
    // H_m = m! [ε^{m+s}] h, noise-level harmonics pruned.
    let mut triangle: Vec<Vec<Terms>> = vec![Vec::new(); m_top + 1];
    let mut factorial = 1.0;
    for m in 0..=m_top {
        if m > 0 {
            factorial *= m as f64;
        }
        let mut t = if m == 0 {
            h0.clone()
        } else {
            order_terms(m + s)?
        };
        let sc = scale_of(&t);
        t.retain(|_, c| {
            let keep = max_abs(c) > 4.0 * f64::EPSILON * sc;
            if !keep {
                pruned = pruned.max(max_abs(c));
            }
            keep
        });
        for c in t.values_mut() {
            c.0.iter_mut()
                .chain(c.1.iter_mut())
                .for_each(|x| *x *= factorial);
        }
        triangle[0].push(t);
    }
    let mut generators: Vec<Terms> = Vec::new(); // W_1 … W_n
    let mut energy_terms: Vec<Terms> = vec![h0.clone()];
    let mut psi_last = Terms::new();
    for m in 1..=m_top {
        // Column entries T[i][m − i], i = 1 … m, with W_m = 0.
        for i in 1..=m {
            let j = m - i;
            let mut t = triangle[i - 1][j + 1].clone();
            for k in 0..=j {
                if k >= generators.len() {
                    continue;
                }
                let c = binomial(j, k);
                alg.bracket_add(&triangle[i - 1][j - k], &generators[k], c, &mut t);
            }
            if triangle[i].len() != j {
                return Err(Error::invalid("Lie–Deprit triangle", "inconsistent column"));
            }
            triangle[i].push(t);
        }
        let psi = triangle[m][0].clone();
        if m == m_top {
            psi_last = psi;
            break;
        }
        // Homological equation, mode by mode.
        let sc = scale_of(&psi);
        let mut w = Terms::new();
        let mut osc = Terms::new();
        for (k, c) in &psi {
            if is_zero_k(k) || max_abs(c) <= 64.0 * f64::EPSILON * sc {
                continue;
            }
            let kw: Vec<f64> = (0..len)
                .map(|a| (0..N).map(|i| f64::from(k[i]) * omega[i][a]).sum())
                .collect();
            let size: f64 = (0..N).map(|i| (f64::from(k[i]) * omega0[i]).abs()).sum();
            if kw[0].abs() <= delta * size || kw[0] == 0.0 {
                return Err(Error::SmallDivisor {
                    what: format!("Lie–Deprit order {m} at J* = {:?}", actions.as_slice()),
                    k: k.clone(),
                    divisor: kw[0],
                    threshold: delta * size,
                });
            }
            let inv = reciprocal(&alg, &kw);
            // W_k = Ψ_k / (i k·ω) = −i Ψ_k / (k·ω)
            let mut q = alg.zero();
            alg.mul_real(&c.0, &inv, &mut q.0);
            alg.mul_real(&c.1, &inv, &mut q.1);
            w.insert(k.clone(), (q.1, q.0.iter().map(|x| -x).collect()));
            osc.insert(k.clone(), c.clone());
        }
        // {H₀, W_m} = −(Ψ_m − ⟨Ψ_m⟩) enters every entry of the column.
        for row in triangle.iter_mut().take(m + 1).skip(1) {
            let last = row.len() - 1;
            add_scaled(&mut row[last], &osc, -1.0);
        }
        let mut k_m = Terms::new();
        if let Some(c0) = psi.get(&vec![0; N]) {
            k_m.insert(vec![0; N], (c0.0.clone(), vec![0.0; len]));
        }
        triangle[m][0] = k_m.clone();
        energy_terms.push(k_m);
        generators.push(w);
    }
    // K as real polynomials: [ε^m] K = K_m / m!.
    let mut energy = Vec::with_capacity(n + 1);
    let mut fact = 1.0;
    for (m, t) in energy_terms.iter().enumerate() {
        if m > 0 {
            fact *= m as f64;
        }
        let mut p = Polynomial::zero(N, tri_degree)?;
        if let Some(c) = t.get(&vec![0; N]) {
            for (o, x) in p.coefficients_mut().iter_mut().zip(&c.0) {
                *o = x / fact;
            }
        }
        energy.push(p.check_finite("the averaged Hamiltonian K")?);
    }
    fact *= m_top as f64;
    let remainder = psi_last
        .iter()
        .filter(|(k, _)| !is_zero_k(k))
        .map(|(_, c)| c.0[0].hypot(c.1[0]))
        .sum::<f64>()
        / fact;
    let next_energy = psi_last
        .get(&vec![0; N])
        .map_or(0.0, |c| c.0[0].abs() / fact);
    // The near-identity map: the triangle on the coordinate functions.
    let map_for = |seed: &dyn Fn(&Terms) -> Terms| -> Vec<Terms> {
        let mut tri: Vec<Vec<Option<Terms>>> = vec![Vec::new(); n + 1];
        tri[0].push(None); // the coordinate itself
        for _ in 1..=n {
            tri[0].push(Some(Terms::new()));
        }
        let mut out = Vec::with_capacity(n);
        let mut f = 1.0;
        for m in 1..=n {
            for i in 1..=m {
                let j = m - i;
                let mut t = tri[i - 1][j + 1].clone().unwrap_or_default();
                for k in 0..=j {
                    let c = binomial(j, k);
                    match &tri[i - 1][j - k] {
                        None => add_scaled(&mut t, &seed(&generators[k]), c),
                        Some(e) => alg.bracket_add(e, &generators[k], c, &mut t),
                    }
                }
                tri[i].push(Some(t));
            }
            f *= m as f64;
            let mut t = tri[m][0].clone().unwrap_or_default();
            for c in t.values_mut() {
                c.0.iter_mut().chain(c.1.iter_mut()).for_each(|x| *x /= f);
            }
            out.push(t);
        }
        out
    };
    let mut map_j = Vec::with_capacity(N);
    let mut map_theta = Vec::with_capacity(N);
    for i in 0..N {
        // {Jᵢ, W} = −∂W/∂θᵢ, {θᵢ, W} = ∂W/∂Jᵢ
        map_j.push(map_for(&|w: &Terms| {
            w.iter()
                .map(|(k, (re, im))| {
                    let ki = -f64::from(k[i]);
                    // ∂θᵢ c e^{ik·θ} = i kᵢ c
                    (
                        k.clone(),
                        (
                            im.iter().map(|x| -ki * x).collect(),
                            re.iter().map(|x| ki * x).collect(),
                        ),
                    )
                })
                .collect()
        }));
        map_theta.push(map_for(&|w: &Terms| {
            w.iter()
                .map(|(k, (re, im))| (k.clone(), (alg.d_dj(i, re), alg.d_dj(i, im))))
                .collect()
        }));
    }
    let mut gen_fact = 1.0;
    let generator_norms = generators
        .iter()
        .enumerate()
        .map(|(m, w)| {
            if m > 0 {
                gen_fact *= m as f64;
            }
            w.values().map(|c| c.0[0].hypot(c.1[0])).sum::<f64>() / gen_fact
        })
        .collect();
    let fourier_error = ft.truncation_error() + alg.dropped.get() + pruned;
    let out = LieDeprit {
        actions: *actions,
        order: n,
        action_degree: options.action_degree,
        energy,
        map_j,
        map_theta,
        generator_norms,
        remainder,
        next_energy,
        fourier_error,
    };
    crate::error::finite("Lie–Deprit remainder estimate", out.remainder)?;
    crate::error::finite("Lie–Deprit Fourier error", out.fourier_error)?;
    Ok(out)
}

/// `1/p` truncated (`p₀ ≠ 0`): `(1/p₀) Σ_j (−r/p₀)^j`, `r = p − p₀`.
fn reciprocal(alg: &Algebra, p: &[f64]) -> Vec<f64> {
    let len = alg.len();
    let p0 = p[0];
    let mut r: Vec<f64> = p.iter().map(|x| -x / p0).collect();
    r[0] = 0.0;
    let mut sum = vec![0.0; len];
    sum[0] = 1.0;
    let mut pow = sum.clone();
    for _ in 0..alg.table.degree() {
        let mut next = vec![0.0; len];
        alg.mul_real(&pow, &r, &mut next);
        if next.iter().all(|&x| x == 0.0) {
            break;
        }
        for (s, x) in sum.iter_mut().zip(&next) {
            *s += x;
        }
        pow = next;
    }
    sum.iter().map(|x| x / p0).collect()
}

/// Finite angles whose rounding stays below `1e-6` rad (`|θ| ≤ 10⁻⁶/2⁻⁵²`); beyond, the map's
/// periodic terms are lost in the rounding of `θ`: [`Error::PhaseLost`].
fn check_angles<const N: usize>(theta: &SVector<f64, N>) -> Result<()> {
    all_finite("angles θ", theta.as_slice())?;
    let limit = 1e-6 / f64::EPSILON;
    match theta.iter().find(|t| t.abs() > limit) {
        Some(&t) => Err(Error::PhaseLost {
            what: "Lie–Deprit near-identity map".into(),
            phase: t,
            limit,
        }),
        None => Ok(()),
    }
}

/// `Σ_k c_k(δJ) e^{ik·θ}` (real part) at `(δJ, θ)`.
fn eval_terms(t: &Terms, dj: &[f64], theta: &[f64], table: &Arc<Monomials>) -> Result<f64> {
    let mut sum = 0.0;
    for (k, (re, im)) in t {
        let phase: f64 = k.iter().zip(theta).map(|(&a, &b)| f64::from(a) * b).sum();
        let (sn, cs) = phase.sin_cos();
        let (a, b) = (eval_poly(re, dj, table), eval_poly(im, dj, table));
        sum += a * cs - b * sn;
    }
    Ok(sum)
}

fn eval_poly(c: &[f64], x: &[f64], table: &Arc<Monomials>) -> f64 {
    c.iter()
        .enumerate()
        .filter(|(_, v)| **v != 0.0)
        .map(|(a, v)| {
            let e = table.exponents(a).unwrap_or_default();
            v * e
                .iter()
                .zip(x)
                .map(|(&p, &xi)| xi.powi(i32::from(p)))
                .product::<f64>()
        })
        .sum()
}

impl<const N: usize> LieDeprit<N> {
    /// The reference actions `J*`.
    pub fn actions(&self) -> &SVector<f64, N> {
        &self.actions
    }

    /// The order `n` in `ε`.
    pub fn order(&self) -> usize {
        self.order
    }

    /// The degree in `δJ` to which [`energy_terms`](Self::energy_terms) and the map are exact.
    pub fn action_degree(&self) -> usize {
        self.action_degree
    }

    /// `[ε^m] K(J* + δJ)`, `m = 0 … n`, polynomials in `δJ` (exact to degree
    /// [`action_degree`](Self::action_degree); higher coefficients are truncated sums).
    pub fn energy_terms(&self) -> &[Polynomial] {
        &self.energy
    }

    /// `[ε^m] K` at `J*` (the coefficient `K_m(J*)/m!`).
    ///
    /// # Errors
    /// `m > n`.
    pub fn energy_coefficient(&self, m: usize) -> Result<f64> {
        self.energy
            .get(m)
            .map(|p| p.coefficients()[0])
            .ok_or_else(|| {
                Error::out_of_domain("ε power", m as f64, format!("0 ≤ m ≤ {}", self.order))
            })
    }

    fn check_point(&self, j: &SVector<f64, N>, eps: f64) -> Result<Vec<f64>> {
        all_finite("actions J′", j.as_slice())?;
        crate::error::finite("ε", eps)?;
        Ok((j - self.actions).as_slice().to_vec())
    }

    /// `K(J′; ε) = Σ_{m ≤ n} ε^m [ε^m] K(J′)`.
    ///
    /// # Errors
    /// NaN/∞ input; a non-finite value.
    pub fn energy(&self, j: &SVector<f64, N>, eps: f64) -> Result<f64> {
        let dj = self.check_point(j, eps)?;
        let mut sum = 0.0;
        for p in self.energy.iter().rev() {
            sum = sum * eps + p.eval(&dj)?;
        }
        crate::error::finite("K(J′; ε)", sum)
    }

    /// The frequencies `ω′(J′; ε) = ∂K/∂J′` corrected to order `n`.
    ///
    /// # Errors
    /// NaN/∞ input; a non-finite value.
    pub fn frequencies(&self, j: &SVector<f64, N>, eps: f64) -> Result<SVector<f64, N>> {
        let dj = self.check_point(j, eps)?;
        let mut out = SVector::<f64, N>::zeros();
        let table = self.energy[0].monomials().clone();
        let alg_deriv = |c: &[f64], i: usize| -> f64 {
            // ∂/∂δJᵢ of the polynomial at δJ
            let mut s = 0.0;
            for (a, v) in c.iter().enumerate() {
                let e = table.exponents(a).unwrap_or_default();
                if *v == 0.0 || e[i] == 0 {
                    continue;
                }
                let mut term = v * f64::from(e[i]);
                for (l, (&p, &x)) in e.iter().zip(&dj).enumerate() {
                    let p = i32::from(p) - i32::from(l == i);
                    term *= x.powi(p);
                }
                s += term;
            }
            s
        };
        for (i, o) in out.iter_mut().enumerate() {
            let mut sum = 0.0;
            for p in self.energy.iter().rev() {
                sum = sum * eps + alg_deriv(p.coefficients(), i);
            }
            *o = crate::error::finite("ω′(J′; ε)", sum)?;
        }
        Ok(out)
    }

    /// The old variables `(J, θ) = E_W(J′, θ′)` of the new ones, the Lie series truncated at
    /// order `n` (`H(E_W(J′, θ′)) = K(J′) + O(ε^{n+1})`).
    ///
    /// # Errors
    /// NaN/∞ input; `|θ′|` beyond the phase resolution ([`Error::PhaseLost`]).
    pub fn from_normal(
        &self,
        j: &SVector<f64, N>,
        theta: &SVector<f64, N>,
        eps: f64,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        let dj = self.check_point(j, eps)?;
        check_angles(theta)?;
        let table = self.energy[0].monomials().clone();
        let series = |terms: &[Terms]| -> Result<f64> {
            let mut sum = 0.0;
            for t in terms.iter().rev() {
                sum = (sum + eval_terms(t, &dj, theta.as_slice(), &table)?) * eps;
            }
            Ok(sum)
        };
        let mut jo = *j;
        let mut to = *theta;
        for i in 0..N {
            jo[i] += series(&self.map_j[i])?;
            to[i] += series(&self.map_theta[i])?;
        }
        all_finite("J", jo.as_slice())?;
        all_finite("θ", to.as_slice())?;
        Ok((jo, to))
    }

    /// The new variables `(J′, θ′)` of the old ones: the inverse of
    /// [`from_normal`](Self::from_normal) by fixed-point iteration
    /// `y ← y + x − E_W(y)` (a contraction for a near-identity map).
    ///
    /// # Errors
    /// NaN/∞ input; [`Error::NotConverged`] when 200 iterations do not reach `1e-14` (relative).
    pub fn to_normal(
        &self,
        j: &SVector<f64, N>,
        theta: &SVector<f64, N>,
        eps: f64,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        self.check_point(j, eps)?;
        check_angles(theta)?;
        let (mut jn, mut tn) = (*j, *theta);
        let mut res = f64::INFINITY;
        for _ in 0..200 {
            let (jo, to) = self.from_normal(&jn, &tn, eps)?;
            let (dj, dt) = (j - jo, theta - to);
            jn += dj;
            tn += dt;
            res = dj.amax().max(dt.amax());
            let scale = 1.0 + j.amax().max(theta.amax());
            if res <= 1e-14 * scale {
                return Ok((jn, tn));
            }
        }
        Err(Error::NotConverged {
            what: "Lie–Deprit inverse map".into(),
            iterations: 200,
            residual: res,
        })
    }

    /// `|[ε^{m−1}] W|` at `J*` (sum of `|W_k|` over the modes), `m = 1 … n`.
    pub fn generator_norms(&self) -> &[f64] {
        &self.generator_norms
    }

    /// The remainder estimate: `Σ_{k ≠ 0} |Ψ_{n+1,k}(J*)|/(n+1)!`, the size of the angle-dependent
    /// part of `H ∘ E_W − K` at order `ε^{n+1}` (times `|ε|^{n+1}`).
    pub fn remainder(&self) -> f64 {
        self.remainder
    }

    /// `|[ε^{n+1}] K(J*)|`: the first term of `K` left out.
    pub fn next_energy_term(&self) -> f64 {
        self.next_energy
    }

    /// The estimated Fourier truncation error: that of the expansion of `H`
    /// ([`FourierTaylor::truncation_error`](crate::series::FourierTaylor::truncation_error)),
    /// the largest product dropped for `|kᵢ| > H_max` and the largest harmonic pruned as rounding.
    pub fn fourier_error(&self) -> f64 {
        self.fourier_error
    }
}

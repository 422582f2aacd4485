//! Normal form of one degree of freedom about an elliptic equilibrium: the frequency–amplitude
//! relation, the map to the new action–angle variables, and the pendulum's period series.
//!
//! # Setting
//!
//! For a Hamiltonian `H(q, p)` of one degree of freedom (any [`Hamiltonian<1>`], written once for
//! all number types) with an elliptic equilibrium `z₀` (eigenvalues `±iν`, `ν > 0`), the Birkhoff
//! normal form of [`super::birkhoff`] — its case `N = 1` — gives the near-identity symplectic map
//! `φ` from the new real normal coordinates `w' = (Q', P')` to the old ones and
//!
//! ```text
//! H(z₀ + S φ(w')) = K(J) + O(|w'|^{K+1}),    K(J) = Σ_{m=0}^{⌊K/2⌋} h_m J^m,    h_1 = ν,
//! J = (Q'² + P'²)/2,    ω(J) = dK/dJ,
//! Q' = √(2J) cos(w + α),    P' = −√(2J) sin(w + α),
//! ```
//!
//! with the angle `w` measured from the direction of `+q` (`α` is fixed by the linear normal form
//! `S`: `S⁻¹ e_q ∝ (cos α, −sin α)`). In the new variables the motion is `J = const`,
//! `w = w₀ + ω(J) t`. [`FrequencyAmplitude`] holds `K(J)` with the convergence diagnostics of its
//! truncated series; [`NormalForm`] adds the map (the truncated coordinate series of
//! [`BirkhoffNormalForm::to_normal`] and [`BirkhoffNormalForm::from_normal`]). The Lie
//! generators, the normal form as a polynomial and the exact generator flows are those of the
//! underlying [`BirkhoffNormalForm`] ([`NormalForm::birkhoff`]).
//!
//! # The pendulum
//!
//! [`PendulumNormalForm`] specialises to `H = ½p² + n²(1 − cos θ)` ([`Pendulum`]) at degree
//! `K = 2N + 2` (order `N` in the squared amplitude `a²`) and turns the normal form into the period
//! series `τ/(2π/n) = 1 + a²/16 + 11a⁴/3072 + …`. That series (of `2K(k)/π`, `k = sin(a/2)`) has
//! radius of convergence `a = π` in `a` — its only singularities are the logarithmic branch points
//! `a = ±π` where `k = 1` — i.e. radius `π²` in `a²`: the separatrix. The frequency series `ω(J)`
//! in the true action has radius `J_s = 8n/π`, the action of the separatrix (where
//! `dE/dJ = 2π/τ → 0`). Near the separatrix phase averaging is meaningless, so
//! [`PendulumNormalForm::period_ratio`] returns a [`ConvergenceWarning`] when the small parameter
//! `μ = (a/π)²` exceeds `1/2` and refuses amplitudes `a ≥ π`.
//!
//! # References
//! * G. D. Birkhoff, *Dynamical Systems*, AMS 1927, ch. III.
//! * A. Deprit, "Canonical transformations depending on a small parameter", *Celestial Mechanics*
//!   1, 12–30 (1969), doi:10.1007/BF01230629.
//! * S. Ferraz-Mello, *Canonical Perturbation Theories*, Springer 2007, ch. 2–3 (Lie series,
//!   d'Alembert characteristic, homological equation).
//! * A. H. Nayfeh, *Perturbation Methods*, Wiley 1973, ch. 4 (Lindstedt–Poincaré; the
//!   cross-check in [`super::lindstedt`]).

use crate::error::{all_finite, finite, positive, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::perturbation::birkhoff::{
    normal_form, BirkhoffNormalForm, Block, NormalFormKind, PhasePolynomial, C64,
    MAX_NORMAL_FORM_DEGREE,
};
use crate::perturbation::lindstedt::tail_ratio;
use crate::series::ball::Ball;
use crate::series::recurrences::unit_power;
use crate::series::{scope, Polynomial, Scope, Series};
use crate::stability::{hamiltonian_equilibrium, PhaseEquilibrium};
use crate::systems::pendulum_exact::amplitude_from_state;
use crate::systems::Pendulum;
use nalgebra::SVector;
use std::f64::consts::PI;

/// Highest order (power of `a²`) of [`PendulumNormalForm`]: the normal form of order `N` has
/// degree `2N + 2 ≤` [`MAX_NORMAL_FORM_DEGREE`]. The `a^{2k}` coefficients of the period series
/// fall like `π^{−2k}/k`; at order 31 they are ~1e−16 of the leading one, and any amplitude where
/// they still matter (a ≳ 2.8) is already flagged by the convergence warning.
pub const MAX_PENDULUM_ORDER: usize = (MAX_NORMAL_FORM_DEGREE - 2) / 2;

/// Small parameter `μ = (a/π)²` above which [`PendulumNormalForm::period_ratio`] warns.
///
/// The period coefficients obey `c_{k+1}/c_k ≤ 1/π²` (checked in `tests/normal_form.rs` up to
/// `k = 12`; asymptotically `c_{k+1} π²/c_k → k/(k+1)` for the logarithmic singularity at `a = π`),
/// so the tail after the term `T_N = c_N a^{2N}` is at most `T_N μ/(1 − μ)`. For `μ ≤ 1/2` that
/// bound does not exceed the last term kept — the usual "error below the last term" rule of an
/// asymptotic/convergent series; beyond it the omitted tail can dominate and the truncated series
/// says nothing about the error. `μ = 1/2` is `a = π/√2 ≈ 2.221`.
pub const PENDULUM_WARNING_MU: f64 = 0.5;

/// The frequency–amplitude relation of a one-degree-of-freedom normal form,
///
/// ```text
/// K(J) = Σ_{m=0}^{M} h_m J^m,    ω(J) = dK/dJ = Σ_{m=0}^{M−1} (m + 1) h_{m+1} J^m,
/// ```
///
/// truncated at `J^M`, with the convergence diagnostics of the truncated series
/// ([`Self::frequency_estimate`]). Built from a [`BirkhoffNormalForm`] of one degree of freedom
/// ([`Self::from_birkhoff`]) or from known coefficients ([`Self::new`]).
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(
    feature = "serde",
    derive(serde::Serialize, serde::Deserialize),
    serde(try_from = "StoredRelation")
)]
pub struct FrequencyAmplitude {
    energy_coefficients: Vec<f64>,
}

/// The stored form of a [`FrequencyAmplitude`], checked by [`FrequencyAmplitude::new`].
#[cfg(feature = "serde")]
#[derive(serde::Deserialize)]
struct StoredRelation {
    energy_coefficients: Vec<f64>,
}

/// A stored relation is accepted as [`FrequencyAmplitude::new`] accepts its coefficients.
#[cfg(feature = "serde")]
impl TryFrom<StoredRelation> for FrequencyAmplitude {
    type Error = Error;
    fn try_from(s: StoredRelation) -> Result<Self> {
        Self::new(s.energy_coefficients)
    }
}

impl FrequencyAmplitude {
    /// The relation `K(J) = Σ h_m J^m` of the coefficients `h_0 … h_M`.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for fewer than two coefficients; [`Error::NonFinite`] for a
    /// non-finite one; [`Error::OutOfDomain`] for `h_1 ≤ 0` (the linear frequency `ν = h_1` of a
    /// libration about a minimum of `K` is positive).
    pub fn new(energy_coefficients: Vec<f64>) -> Result<Self> {
        if energy_coefficients.len() < 2 {
            return Err(Error::invalid(
                "frequency–amplitude relation",
                "needs the coefficients h_0 and h_1 at least",
            ));
        }
        all_finite("coefficients h_m of K(J)", &energy_coefficients)?;
        positive("linear frequency h_1", energy_coefficients[1])?;
        Ok(Self {
            energy_coefficients,
        })
    }

    /// The relation of a [`NormalFormKind::Birkhoff`] normal form of one degree of freedom about
    /// an elliptic equilibrium of positive frequency: `K(J)` is
    /// [`BirkhoffNormalForm::action_polynomial`].
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for another kind, more than one degree of freedom, or a hyperbolic
    /// equilibrium; [`Error::OutOfDomain`] for a negative frequency (an elliptic equilibrium of
    /// negative Krein signature, a maximum of `H`: write it for `−H`).
    pub fn from_birkhoff(nf: &BirkhoffNormalForm) -> Result<Self> {
        if nf.dof() != 1 {
            return Err(Error::invalid(
                "frequency–amplitude relation",
                format!(
                    "needs one degree of freedom, the normal form has {}",
                    nf.dof()
                ),
            ));
        }
        match nf.linear().blocks().first() {
            Some(Block::Elliptic { frequency, .. }) => {
                positive("linear frequency ν of the equilibrium", *frequency)?;
            }
            _ => {
                return Err(Error::invalid(
                    "frequency–amplitude relation",
                    "the equilibrium is not elliptic: there is no libration about it",
                ))
            }
        }
        let k = nf.action_polynomial()?;
        Self::new(k.coefficients().to_vec())
    }

    /// `h_0 … h_M`.
    pub fn energy_coefficients(&self) -> &[f64] {
        &self.energy_coefficients
    }

    /// The linear frequency `ν = h_1`.
    pub fn linear_frequency(&self) -> f64 {
        self.energy_coefficients[1]
    }

    /// The highest power `M` of `K(J)`.
    pub fn order(&self) -> usize {
        self.energy_coefficients.len() - 1
    }

    /// `ω(J) = Σ_m ω_m J^m` as `ω_0 … ω_{M−1}` (`ω_0 = ν`, `ω_m = (m + 1) h_{m+1}`).
    pub fn frequency_coefficients(&self) -> Vec<f64> {
        let h = &self.energy_coefficients;
        (1..h.len()).map(|m| m as f64 * h[m]).collect()
    }

    /// `K(J)`, refused where the truncated series has not converged.
    ///
    /// # Errors
    /// As [`Self::frequency_estimate`] (without the sign condition on the value).
    pub fn energy(&self, action: f64) -> Result<f64> {
        Ok(self
            .estimate("normal-form energy K(J)", &self.energy_coefficients, action)?
            .value)
    }

    /// `ω(J) = dK/dJ`, refused where the truncated series has not converged; the diagnostics of
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
    /// tail is estimated as `|ω_M J^M| q/(1 − q)` (geometric continuation) and for
    /// `q > SERIES_WARNING_RATIO` the estimate carries [`ConvergenceWarning::SlowTerms`]: that
    /// tail may then exceed the last term kept. For `q ≥ 1` the terms grow and the truncated sum
    /// approximates nothing; a frequency `≤ 0` is not the frequency of any libration. Both are
    /// refused (e.g. Duffing `H = ½(p² + q²) + q⁴/4` at `J = 1`, where the degree-18 series sums
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
                iterations: self.order(),
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
                iterations: self.order(),
                residual: last_term,
            });
        }
        let warning = (q > SERIES_WARNING_RATIO).then_some(ConvergenceWarning::SlowTerms {
            ratio: q,
            limit: SERIES_WARNING_RATIO,
            order: self.order(),
        });
        Ok(SeriesEstimate {
            value,
            small_parameter: q,
            last_term,
            tail_bound: last_term.abs() * q / (1.0 - q),
            warning,
        })
    }
}

/// `Σ c_k x^k`.
fn horner(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, ck| acc * x + ck)
}

/// The normal form of a Hamiltonian of one degree of freedom about an elliptic equilibrium,
/// in its action–angle form (see the module documentation): the [`BirkhoffNormalForm`] of
/// degree `K`, its [`FrequencyAmplitude`] relation and the map `(q, p) ↔ (J, w)`.
///
/// ```
/// use hamilton_jacobi::nalgebra::Vector1;
/// use hamilton_jacobi::perturbation::normal_form::NormalForm;
/// use hamilton_jacobi::stability::hamiltonian_equilibrium;
/// use hamilton_jacobi::systems::Pendulum;
/// let h = Pendulum::new(1.0).unwrap();
/// let eq = hamiltonian_equilibrium(&h, 0.0, &Vector1::new(0.1), &Vector1::new(0.0)).unwrap();
/// let nf = NormalForm::new(&h, 0.0, &eq, 6).unwrap();
/// // K(J) = J − J²/16 − J³/256 + O(J⁴)
/// let k = nf.frequency_amplitude().energy_coefficients();
/// assert!((k[2] + 1.0 / 16.0).abs() < 1e-15 && (k[3] + 1.0 / 256.0).abs() < 1e-16);
/// ```
#[derive(Clone, Debug)]
pub struct NormalForm {
    birkhoff: BirkhoffNormalForm,
    relation: FrequencyAmplitude,
    angle_origin: f64,
}

impl NormalForm {
    /// The normal form of `h` at time `t` about the elliptic equilibrium `eq` (see
    /// [`hamiltonian_equilibrium`]) to degree `degree` in the phase variables (`K(J)` to
    /// `J^{⌊K/2⌋}`).
    ///
    /// # Errors
    /// The errors of [`normal_form`] (degree outside `3..=MAX_NORMAL_FORM_DEGREE`, not an
    /// equilibrium, a Jordan block, `H` not analytic there) and of
    /// [`FrequencyAmplitude::from_birkhoff`] (a hyperbolic equilibrium or a maximum of `H`).
    pub fn new<H: Hamiltonian<1>>(
        h: &H,
        t: f64,
        eq: &PhaseEquilibrium<1>,
        degree: usize,
    ) -> Result<Self> {
        Self::from_birkhoff(normal_form(h, t, eq, degree, NormalFormKind::Birkhoff)?)
    }

    /// The action–angle form of a [`NormalFormKind::Birkhoff`] normal form of one degree of
    /// freedom.
    ///
    /// # Errors
    /// As [`FrequencyAmplitude::from_birkhoff`].
    pub fn from_birkhoff(birkhoff: BirkhoffNormalForm) -> Result<Self> {
        let relation = FrequencyAmplitude::from_birkhoff(&birkhoff)?;
        // S⁻¹ e_q = (S_pP, −S_pQ) (det S = 1) lies along (cos α, −sin α).
        let s = birkhoff.linear().symplectic_matrix();
        let angle_origin = s[(1, 0)].atan2(s[(1, 1)]);
        Ok(Self {
            birkhoff,
            relation,
            angle_origin,
        })
    }

    /// The underlying normal form (generators, `K` as a polynomial, exact generator flows,
    /// diagnostics and remainder).
    pub fn birkhoff(&self) -> &BirkhoffNormalForm {
        &self.birkhoff
    }

    /// The frequency–amplitude relation `K(J)`, `ω(J)`.
    pub fn frequency_amplitude(&self) -> &FrequencyAmplitude {
        &self.relation
    }

    /// The degree `K` in the phase variables.
    pub fn degree(&self) -> usize {
        self.birkhoff.degree()
    }

    /// The new action–angle `(J, w)` of the phase point `(q, p)`, `w ∈ (−π, π]`, by the truncated
    /// coordinate series ([`BirkhoffNormalForm::to_normal`]).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or a non-finite image.
    pub fn to_action_angle(&self, q: f64, p: f64) -> Result<(f64, f64)> {
        let w = self.birkhoff.linear_coordinates(&[q, p])?;
        let wn = self.birkhoff.to_normal(&w)?;
        let j = finite("action J", 0.5 * (wn[0] * wn[0] + wn[1] * wn[1]))?;
        let angle = (-wn[1]).atan2(wn[0]) - self.angle_origin;
        Ok((j, PI - (PI - angle).rem_euclid(2.0 * PI)))
    }

    /// The phase point `(q, p)` of the new action–angle `(J, w)`, by the truncated coordinate
    /// series ([`BirkhoffNormalForm::from_normal`]).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ input or a non-finite image; [`Error::OutOfDomain`] for
    /// `J < 0`.
    pub fn from_action_angle(&self, action: f64, angle: f64) -> Result<(f64, f64)> {
        let j = finite("action J", action)?;
        let w = finite("angle w", angle)?;
        if j < 0.0 {
            return Err(Error::out_of_domain("action J", j, "[0, ∞)"));
        }
        let r = (2.0 * j).sqrt();
        let (s, c) = (w + self.angle_origin).sin_cos();
        let old = self.birkhoff.from_normal(&[r * c, -r * s])?;
        let z = self.birkhoff.phase_point(&old)?;
        Ok((z[0], z[1]))
    }

    /// The perturbative motion from `(q₀, p₀)`: `J = const`, `w = w₀ + ω(J) t`, mapped back.
    ///
    /// # Errors
    /// As [`Self::to_action_angle`], [`FrequencyAmplitude::frequency_estimate`] (refused where
    /// the frequency series has not converged) and [`Self::from_action_angle`]; also
    /// [`Error::NonFinite`] for `t`.
    pub fn state_at(&self, q0: f64, p0: f64, t: f64) -> Result<(f64, f64)> {
        let t = finite("t", t)?;
        let (j, w0) = self.to_action_angle(q0, p0)?;
        let w = w0 + self.relation.frequency_estimate(j)?.value * t;
        self.from_action_angle(j, w)
    }
}

/// Estimated ratio of successive terms above which a truncated series of [`FrequencyAmplitude`] carries
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
    /// ([`tail_ratio`]) for the series of [`FrequencyAmplitude`].
    pub small_parameter: f64,
    /// The last term kept (`c_N a^{2N}`, `ω_N J^N`, …).
    pub last_term: f64,
    /// Bound on the omitted tail, `|last term| μ/(1 − μ)` (see [`PENDULUM_WARNING_MU`]; for
    /// [`FrequencyAmplitude`] an estimate by geometric continuation with ratio `q`).
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
/// The [`NormalForm`] of [`Pendulum`] at degree `2N + 2` (`θ⁴ … θ^{2N+2}` kept). Results (`n = 1`;
/// verified to `J^{N+1}` and `a^{2N}` against the exact reversion of the elliptic action and the
/// series of `2K(k)/π` in `tests/normal_form.rs`): `K(J) = J − J²/16 − J³/256 − 5J⁴/8192 − …`,
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
        let pendulum = Pendulum::new(n)?;
        let zero = SVector::<f64, 1>::zeros();
        let eq = hamiltonian_equilibrium(&pendulum, 0.0, &zero, &zero)?;
        let normal_form = NormalForm::new(&pendulum, 0.0, &eq, 2 * order + 2)?;
        let (period_series, period_series_error) = period_series_from(&normal_form, order)?;
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

    /// The underlying [`NormalForm`] (degree `2N + 2`).
    pub fn normal_form(&self) -> &NormalForm {
        &self.normal_form
    }

    /// `K(J) = Σ_m h_m J^m`, `m = 0 … N + 1` (`h_1 = n`, `h_2 = −1/16`, `h_3 = −1/(256 n)`, …).
    pub fn energy_coefficients(&self) -> &[f64] {
        self.normal_form.relation.energy_coefficients()
    }

    /// `ω(J) = Σ_m ω_m J^m`, `m = 0 … N`.
    pub fn frequency_coefficients(&self) -> Vec<f64> {
        self.normal_form.relation.frequency_coefficients()
    }

    /// `τ/(2π/n) = Σ_{k=0}^{N} c_k a^{2k}` (independent of `n`).
    pub fn period_ratio_series(&self) -> &[f64] {
        &self.period_series
    }

    /// Absolute rounding-error bounds of [`Self::period_ratio_series`]: first-order running error
    /// analysis from the coefficient model [`COEFFICIENT_ULPS`] (see `period_series_from`). The
    /// coefficients of this series come from the turning point `θ = a, p = 0`, where the
    /// monomials of the transformation alternate in sign: the actual error grows by about 2 per
    /// order, and the bound, which adds every rounding in absolute value, lies 10²–10⁴ above it.
    /// For high orders use the Lindstedt series ([`super::lindstedt::lindstedt_pendulum`]),
    /// accurate to ~1e−14 at every order.
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
        let (j, w) = self.normal_form.to_action_angle(theta, p)?;
        let warning = (mu > PENDULUM_WARNING_MU).then_some(ConvergenceWarning::NearSeparatrix {
            small_parameter: mu,
            limit: PENDULUM_WARNING_MU,
        });
        Ok((j, w, warning))
    }

    /// The state `(θ, p)` with new action–angle `(J', w')`.
    ///
    /// # Errors
    /// [`Error::NonFinite`]; [`Error::OutOfDomain`] for `J' < 0` or `J' ≥ 8n/π` (the separatrix
    /// action: larger actions are rotations, outside the normal form's domain).
    pub fn from_action_angle(&self, action: f64, angle: f64) -> Result<(f64, f64)> {
        let j = finite("action J'", action)?;
        finite("angle w'", angle)?;
        let js = 8.0 * self.n / PI;
        if !(0.0..js).contains(&j) {
            return Err(Error::out_of_domain(
                "action J'",
                j,
                format!("[0, 8n/π) = [0, {js})"),
            ));
        }
        self.normal_form.from_action_angle(j, angle)
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
        let w = w0 + self.normal_form.relation.frequency_estimate(j)?.value * t;
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

/// Relative rounding error assumed for a coefficient of degree `d` of the normal form and of its
/// coordinate series: `COEFFICIENT_ULPS · ⌈d/2⌉ · ε`. Each coefficient is a sum of `O(d)` Lie
/// terms; the model is checked on the energy coefficients `h_m` (degree `2m`) against exact
/// rationals at every order offered (`tests/normal_form.rs`).
pub const COEFFICIENT_ULPS: f64 = 8.0;

/// A truncated power series in one variable with a bound on the accumulated rounding error of
/// each coefficient (first-order running error analysis, Higham 2002, §3.3): `value` and the
/// nonnegative `bound` are both [`Series`] of one scope.
#[derive(Clone, Copy)]
struct BoundedSeries {
    value: Series,
    bound: Series,
}

/// The series with the coefficients `|c_k|` of `s`.
fn abs_series(sc: &Scope, s: Series) -> Result<Series> {
    let mut p = sc.polynomial(s)?;
    for c in p.coefficients_mut() {
        *c = c.abs();
    }
    sc.lift(&p)
}

/// The series of the coefficient vector `c` (shorter vectors are padded with zeros).
fn series_of(sc: &Scope, c: &[f64]) -> Result<Series> {
    let table = sc.monomials();
    let mut p = Polynomial::zero(table.variables(), table.degree())?;
    for (o, &v) in p.coefficients_mut().iter_mut().zip(c) {
        *o = v;
    }
    sc.lift(&p)
}

impl BoundedSeries {
    /// `a · b` truncated: value `a b`, bound `|a| e_b + e_a |b| + e_a e_b + γ_k (|a| |b|)_k`, with
    /// `γ_k = (k + 2) ε` for the `k + 1` products and `k` sums of the coefficient `k`.
    fn mul(self, o: Self, sc: &Scope) -> Result<Self> {
        let (aa, ab) = (abs_series(sc, self.value)?, abs_series(sc, o.value)?);
        let mut round = sc.polynomial(aa * ab)?;
        for (k, c) in round.coefficients_mut().iter_mut().enumerate() {
            *c *= (k + 2) as f64 * f64::EPSILON;
        }
        Ok(Self {
            value: self.value * o.value,
            bound: aa * o.bound + self.bound * ab + self.bound * o.bound + sc.lift(&round)?,
        })
    }

    /// `a + s b` for an exact `s = ±1`: bound `e_a + e_b + ε |a + s b|`.
    fn add(self, o: Self, s: f64, sc: &Scope) -> Result<Self> {
        let value = self.value + o.value * s;
        Ok(Self {
            value,
            bound: self.bound + o.bound + abs_series(sc, value)? * f64::EPSILON,
        })
    }
}

/// The period-ratio series in `x = a²` of a [`PendulumNormalForm`] of order `N`, with absolute
/// rounding-error bounds.
///
/// At the turning point `θ = a`, `p = 0` the complex normal coordinates are `ζ = a v`
/// (`v = T⁻¹ S⁻¹ e_q`), so the degree-`d` part of each new coordinate `ζ'_i(ζ)`
/// ([`BirkhoffNormalForm::coordinate_series`]) contributes `X_{i,d} a^d`, `X_{i,d}` its value at
/// `v`; the new action is `J'(a) = i x'(a) y'(a)`. Then `ω/ν = Σ_m (ω_m/ν) J'^m` and
/// `τ/(2π/ν) = (ω/ν)^{−1}`, all as truncated series in `a` on the shared [`Series`] type and
/// re-read in `x = a²` to `x^N`.
///
/// The bounds: `X_{i,d}` carries `(COEFFICIENT_ULPS ⌈d/2⌉ + 2d + terms + 2) ε Σ|c_α v^α|` (the
/// coefficient model, the powers of `v`, the sum), `ω_m/ν` carries
/// `(COEFFICIENT_ULPS (m + 1) + 2) ε |ω_m/ν|`, and the products and sums propagate them as in
/// [`BoundedSeries`]; the reciprocal is Miller's recurrence with running bounds. The alternating
/// monomials of the transformation at the turning point cancel, which is what makes the high
/// coefficients of this series lose digits.
fn period_series_from(nf: &NormalForm, order: usize) -> Result<(Vec<f64>, Vec<f64>)> {
    let eps = f64::EPSILON;
    let b = nf.birkhoff();
    let s = b.linear().symplectic_matrix();
    let u = [C64::new(s[(1, 1)], 0.0), C64::new(-s[(1, 0)], 0.0)];
    let t_inv = b
        .linear()
        .complexification()
        .clone()
        .try_inverse()
        .ok_or_else(|| Error::invalid("complexification", "singular"))?;
    let v: Vec<C64> = (0..2)
        .map(|i| t_inv[(i, 0)] * u[0] + t_inv[(i, 1)] * u[1])
        .collect();
    let top = 2 * order;
    // Per-degree values of x'(a v), y'(a v): (re, im, bound) for d = 0 … top.
    let parts = |p: &PhasePolynomial| -> Result<(Vec<f64>, Vec<f64>, Vec<f64>)> {
        let table = p.monomials();
        let (mut re, mut im, mut bound) =
            (vec![0.0; top + 1], vec![0.0; top + 1], vec![0.0; top + 1]);
        for d in 0..=top.min(table.degree()) {
            let part = p.part(d);
            let value = part.eval(&v)?;
            let mut mag = 0.0;
            let mut terms = 0usize;
            for i in table.of_degree(d) {
                let c = part.coefficients()[i];
                if c == C64::new(0.0, 0.0) {
                    continue;
                }
                let e = table.exponents(i).unwrap_or(&[]);
                let vm: f64 = e
                    .iter()
                    .zip(&v)
                    .map(|(&k, vk)| vk.norm().powi(i32::from(k)))
                    .product();
                mag += c.norm() * vm;
                terms += 1;
            }
            let ulps =
                COEFFICIENT_ULPS * d.div_ceil(2) as f64 + 2.0 * d as f64 + terms as f64 + 2.0;
            re[d] = value.re;
            im[d] = value.im;
            bound[d] = ulps * eps * mag;
        }
        Ok((re, im, bound))
    };
    let (_, new_from_old) = b.coordinate_series();
    let (xr, xi, ex) = parts(&new_from_old[0])?;
    let (yr, yi, ey) = parts(&new_from_old[1])?;
    let nu = nf.frequency_amplitude().linear_frequency();
    let w = nf.frequency_amplitude().frequency_coefficients();
    let (omega_v, omega_e) = scope(1, top, |sc| -> Result<(Polynomial, Polynomial)> {
        let bounded = |c: &[f64], e: &[f64]| -> Result<BoundedSeries> {
            Ok(BoundedSeries {
                value: series_of(sc, c)?,
                bound: series_of(sc, e)?,
            })
        };
        let (xr, xi) = (bounded(&xr, &ex)?, bounded(&xi, &ex)?);
        let (yr, yi) = (bounded(&yr, &ey)?, bounded(&yi, &ey)?);
        // J' = Re(i x' y') = −(x'_r y'_i + x'_i y'_r).
        let jp = xr.mul(yi, sc)?.add(xi.mul(yr, sc)?, 1.0, sc)?;
        let jp = BoundedSeries {
            value: -jp.value,
            bound: jp.bound,
        };
        let mut omega = BoundedSeries {
            value: Series::constant(0.0),
            bound: Series::constant(0.0),
        };
        let mut power = BoundedSeries {
            value: Series::constant(1.0),
            bound: Series::constant(0.0),
        };
        for (m, wm) in w.iter().enumerate().take(order + 1) {
            let c = wm / nu;
            let wn = BoundedSeries {
                value: Series::constant(c),
                // ω_0/ν = ν/ν = 1 exactly.
                bound: Series::constant(if m == 0 {
                    0.0
                } else {
                    (COEFFICIENT_ULPS * (m + 1) as f64 + 2.0) * eps * c.abs()
                }),
            };
            omega = omega.add(wn.mul(power, sc)?, 1.0, sc)?;
            power = power.mul(jp, sc)?;
        }
        Ok((sc.polynomial(omega.value)?, sc.polynomial(omega.bound)?))
    })??;
    // ω/ν is even in a: its coefficients of a^{2k} are those of x^k.
    let omega: Vec<Ball> = (0..=order)
        .map(|k| Ball {
            v: omega_v.coefficients()[2 * k],
            e: omega_e.coefficients()[2 * k],
        })
        .collect();
    if omega[0].v != 1.0 {
        return Err(Error::invalid(
            "pendulum period series",
            format!("ω(0)/ν = {} ≠ 1", omega[0].v),
        ));
    }
    let c = unit_power(&omega, -1.0);
    Ok((
        c.iter().map(|b| b.v).collect(),
        c.iter().map(|b| b.e).collect(),
    ))
}

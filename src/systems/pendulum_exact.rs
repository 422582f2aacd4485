//! The plane pendulum in closed form, up to and including the separatrix.
//!
//! Per unit mass and length the Hamiltonian is
//!
//! ```text
//! H(θ, p) = ½ p² + n² (1 − cos θ) = ½ p² + 2 n² sin²(θ/2),      n > 0,
//! ```
//!
//! with `n` the small-oscillation angular frequency. Writing `k² = H / (2 n²)` the motion is
//!
//! * **libration** (`k < 1`): `sin(θ/2) = k sn(n t + u₀, k)`, `p = 2 n k cn(n t + u₀, k)`,
//!   amplitude `a = 2 arcsin k`, period `τ = 4 K(k) / n`;
//! * **separatrix** (`k = 1`): `θ = 2 gd(±n t + c₀)`, `p = ±2 n sech(±n t + c₀)`;
//! * **rotation** (`k > 1`): `θ = ±2 am(n k t + v₀, 1/k)`, `p = ±2 n k dn(n k t + v₀, 1/k)`.
//!
//! References: DLMF §22.19(i) (the pendulum); Byrd & Friedman (1971) *Handbook of Elliptic
//! Integrals for Engineers and Scientists*; Lawden (1989) *Elliptic Functions and Applications*;
//! Abramowitz & Stegun (1964) §16.4 and §17.6 (AGM methods).
//!
//! Everything near the separatrix is driven by the complementary modulus `k' = √(1 − k²)`, which
//! is never formed as `1 − k²`: the period takes it from the gap `δ = π − a` as `sin(δ/2)`, and the
//! flow takes it from the state as `k'² = (cos(θ/2) − |p|/2n)(cos(θ/2) + |p|/2n)`. The Jacobi
//! functions and `K` come from [`crate::special::elliptic`] (descending Landen / AGM scheme of
//! Abramowitz & Stegun 16.4), which takes `k'` as an input, so `K(k) ≈ ln(4/k')` is resolved for
//! `k'` down to the smallest positive double.

use crate::error::{finite, positive, Error, Result};
use crate::special::elliptic::{
    agm_unchecked, complete_k_unchecked, incomplete_f, jacobi_unchecked,
};
use crate::systems::kepler::orbit::MAX_PHASE_ADVANCE;
use std::f64::consts::{PI, TAU};

/// `π − PI` rounded to a double: `PI + PI_LO` represents π to about 1e−32.
const PI_LO: f64 = 1.224_646_799_147_353_2e-16;

/// `2π − TAU` (exactly twice [`PI_LO`], since `TAU = 2·PI` exactly).
const TAU_LO: f64 = 2.0 * PI_LO;

/// A state is treated as lying on the separatrix when `cos(θ/2)` and `|p|/(2n)` differ by at most
/// this many `ε` times their sum: below that, the sign of `H − 2n²` is not determined by the
/// rounded inputs (`cos(θ/2)` and `p/(2n)` each carry up to one rounding error).
const SEPARATRIX_ULPS: f64 = 4.0;

/// Passes of the mod-2π reduction: each leaves a remainder of at most about `1.5e−16 |θ|` (the
/// rounding of `θ/TAU`), so 24 passes bring any finite double into `[−π, π]`.
const MAX_REDUCTION_PASSES: usize = 24;

/// The gap `δ = π − |a|` from the double `a` to the true π, `(PI − |a|) + (π − PI)`: the first
/// difference is exact for `|a| ≥ π/2` (Sterbenz), the second is the rounding of π. This is the
/// separatrix distance of a state that starts at the double `a` (negative for `|a| > π`).
///
/// # Errors
/// [`Error::NonFinite`] for a NaN or infinite amplitude.
pub fn separatrix_gap(amplitude: f64) -> Result<f64> {
    let a = finite("amplitude", amplitude)?;
    Ok((PI - a.abs()) + PI_LO)
}

/// Exact period of the pendulum with amplitude `a` (maximum `|θ|` of the libration).
///
/// `τ = 4 K(k) / n`, `k = sin(a/2)` (DLMF §22.19(i); Byrd & Friedman 1971), evaluated as
/// `τ = 2π / (n M(1, k'))` with `k' = cos(a/2) = sin(δ/2)`, `δ = π − a`. The gap is measured from
/// the double `a` to the true π (`δ = (PI − a) + 1.2246…e−16`, the first difference being exact for
/// `a ≥ π/2`), so `k'` is never formed as `√(1 − k²)`. `a = 0` gives `2π/n`.
///
/// The double nearest π is treated as the separatrix itself; amplitudes closer to π than one ulp
/// are reachable only through [`period_from_gap`].
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] for `n ≤ 0`, `a < 0`, or `a > π`
/// (no libration reaches beyond π: energies above `2n²` are rotations, see [`PendulumMotion`]);
/// [`Error::Separatrix`] for `a = π` (infinite period).
pub fn period(n: f64, amplitude: f64) -> Result<f64> {
    let n = positive("n", n)?;
    let a = finite("amplitude", amplitude)?;
    if a < 0.0 {
        return Err(Error::out_of_domain("amplitude", a, "[0, π)"));
    }
    if a == 0.0 {
        return finite("period", TAU / n);
    }
    if a == PI {
        return Err(Error::Separatrix {
            what: "pendulum period".into(),
            distance: 0.0,
            hint: "amplitude π is the separatrix (infinite period); for amplitudes within one \
                   ulp of π pass the gap π − a to period_from_gap"
                .into(),
        });
    }
    if a > PI {
        return Err(Error::out_of_domain(
            "amplitude",
            a,
            "[0, π); a libration never passes θ = π — energies above 2n² are rotations, \
             see PendulumMotion",
        ));
    }
    period_from_gap_unchecked(n, separatrix_gap(a)?)
}

/// Exact period from the gap `δ = π − a` to the separatrix.
///
/// `τ = 4 K(k)/n = 2π / (n M(1, k'))`, `k' = sin(δ/2)` (DLMF 19.8.5, §22.19(i)). Full relative
/// accuracy down to the smallest `δ`; for small `δ`, `τ = (4/n) [ln(8/δ) + O(δ² ln δ)]`
/// (DLMF 19.12.1). `δ = π` (amplitude 0) gives `2π/n`.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] for `n ≤ 0` or `δ ∉ [0, π]`;
/// [`Error::Separatrix`] for `δ = 0`.
pub fn period_from_gap(n: f64, delta: f64) -> Result<f64> {
    let n = positive("n", n)?;
    let delta = finite("gap π − a", delta)?;
    if delta == 0.0 {
        return Err(Error::Separatrix {
            what: "pendulum period".into(),
            distance: 0.0,
            hint: "zero gap is the separatrix (infinite period)".into(),
        });
    }
    if !(delta > 0.0 && delta <= PI) {
        return Err(Error::out_of_domain("gap π − a", delta, "(0, π]"));
    }
    period_from_gap_unchecked(n, delta)
}

/// Below this gap [`period_from_gap`] uses the asymptotic form `τ = (4/n) ln(8/δ)`: the next
/// term of `K`, `(k'²/4)(ln(4/k') − 1)` with `k' ≈ δ/2` (DLMF 19.12.1), is then below `1e−300`
/// relative, and `sin(δ/2)` would leave the normal range of doubles (at the smallest subnormal gap
/// it underflows to 0).
const ASYMPTOTIC_GAP: f64 = 1e-150;

/// `2π / (n M(1, sin(δ/2)))` for `δ ∈ (0, π]` (up to the `PI_LO` shift).
fn period_from_gap_unchecked(n: f64, delta: f64) -> Result<f64> {
    if delta < ASYMPTOTIC_GAP {
        // ln(8/δ) without forming 8/δ, which overflows for δ < 4.5e−308.
        let log = std::f64::consts::LN_2.mul_add(3.0, -delta.ln());
        return finite("period", 4.0 * log / n);
    }
    let kc = (0.5 * delta).sin().min(1.0);
    finite("period", TAU / (n * agm_unchecked(1.0, kc)?))
}

/// Energy `H = ½ p² + n² (1 − cos θ)`, evaluated as `½ p² + 2 n² sin²(θ/2)` (no cancellation for
/// small `θ`).
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ arguments or an energy that overflows; [`Error::OutOfDomain`]
/// for `n ≤ 0`.
pub fn energy(n: f64, theta: f64, p: f64) -> Result<f64> {
    let n = positive("n", n)?;
    let theta = finite("theta", theta)?;
    let p = finite("p", p)?;
    let s = (0.5 * theta).sin();
    finite("energy H", 0.5 * p * p + 2.0 * (n * s) * (n * s))
}

/// Libration amplitude `a = max |θ|` of the orbit through `(θ, p)`.
///
/// `a = 2 arcsin k`, `k² = H/(2n²) = sin²(θ/2) + p²/(4n²)` (DLMF §22.19(i)), evaluated as
/// `a = 2 atan2(k, k')` with `k'² = (cos(θ/2) − |p|/2n)(cos(θ/2) + |p|/2n)` so that amplitudes
/// near π keep their gap to π. `θ` is reduced mod 2π first.
///
/// An amplitude that rounds to the double `PI` is refused like [`period`] refuses it: the gap
/// `δ = π − a = 2 atan2(k', k)` of such a state (below about 1.7e−16) is not representable as
/// `PI − a`, and [`PendulumMotion`] (which keeps `k'`) or [`period_from_gap`] handle it.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] for `n ≤ 0` or for a rotation
/// (`H > 2n²`); [`Error::Separatrix`] when `H = 2n²` to rounding (no turning point), and when the
/// amplitude rounds to `PI` (the error's `distance` is then the gap `δ`); [`Error::PhaseLost`]
/// when `|θ|` exceeds [`MAX_PHASE_ADVANCE`].
pub fn amplitude_from_state(n: f64, theta: f64, p: f64) -> Result<f64> {
    let st = ReducedState::new(n, theta, p)?;
    match st.regime() {
        Regime::Libration => {
            let kc = st.kc_libration();
            let a = 2.0 * st.k.atan2(kc);
            if a >= PI {
                return Err(Error::Separatrix {
                    what: "amplitude_from_state".into(),
                    distance: 2.0 * kc.atan2(st.k),
                    hint: "the amplitude rounds to π, which period() treats as the separatrix; \
                           pass the gap (the distance above) to period_from_gap, or use \
                           PendulumMotion for the flow"
                        .into(),
                });
            }
            Ok(a)
        }
        Regime::Separatrix => Err(st.separatrix_error("amplitude_from_state")),
        Regime::Rotation => Err(Error::out_of_domain(
            "energy ratio H/(2n²)",
            st.k * st.k,
            "[0, 1) (libration); the state rotates",
        )),
    }
}

/// Which kind of motion an initial state produces.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Regime {
    /// `H < 2n²`: oscillation about θ = 0 with amplitude `a < π`.
    Libration,
    /// `H = 2n²` to rounding: asymptotic approach to the unstable equilibrium θ = ±π.
    Separatrix,
    /// `H > 2n²`: circulation, `θ` monotone.
    Rotation,
}

/// An initial state reduced to `θ_r ∈ [−π, π]` with `cos(θ_r/2) ≥ 0`, and its half-angle data.
#[derive(Clone, Copy, Debug)]
struct ReducedState {
    /// `θ₀ − 2π m` for the integer `m` that puts it in `[−π, π]`.
    theta_r: f64,
    /// `sin(θ_r/2)`.
    s: f64,
    /// `cos(θ_r/2) ≥ 0`.
    c: f64,
    /// `p/(2n)`.
    q: f64,
    /// `k = √(s² + q²) = √(H/(2n²))`.
    k: f64,
}

impl ReducedState {
    fn new(n: f64, theta0: f64, p0: f64) -> Result<Self> {
        let n = positive("n", n)?;
        let theta0 = finite("theta0", theta0)?;
        if theta0.abs() > MAX_PHASE_ADVANCE {
            // The rounding of θ₀ itself (half an ulp, ≈ |θ₀|·ε/2) exceeds 1e−6 rad: its position
            // on the circle is not determined by the input.
            return Err(Error::PhaseLost {
                what: "pendulum initial angle theta0".into(),
                phase: theta0,
                limit: MAX_PHASE_ADVANCE,
            });
        }
        let p0 = finite("p0", p0)?;
        // θ − 2πm with 2π split as TAU + TAU_LO: the fused multiply-add is exact up to one
        // rounding of the (small) result, so each pass costs ≈ 1e−32 |m| plus one ulp of θ_r. One
        // pass suffices for |θ₀| < 2⁵³; larger angles need a few more.
        let reduce = |theta: f64, m: f64| (-m).mul_add(TAU, theta) - m * TAU_LO;
        let mut theta_r = theta0;
        for _ in 0..MAX_REDUCTION_PASSES {
            if theta_r.abs() <= PI {
                break;
            }
            theta_r = reduce(theta_r, (theta_r / TAU).round());
        }
        let (mut s, mut c) = (0.5 * theta_r).sin_cos();
        if c < 0.0 {
            // |θ_r| came out just beyond π: the state belongs to the neighbouring turn.
            theta_r = reduce(theta_r, theta_r.signum());
            (s, c) = (0.5 * theta_r).sin_cos();
            c = c.abs();
        }
        let q = finite("p0/(2n)", 0.5 * p0 / n)?;
        Ok(Self {
            theta_r,
            s,
            c,
            q,
            k: s.hypot(q),
        })
    }

    /// `cos(θ/2) − |p|/2n`, whose sign is that of `2n² − H`.
    fn gap(&self) -> f64 {
        self.c - self.q.abs()
    }

    fn regime(&self) -> Regime {
        let d = self.gap();
        let sum = self.c + self.q.abs();
        if d.abs() <= SEPARATRIX_ULPS * f64::EPSILON * sum {
            Regime::Separatrix
        } else if d > 0.0 {
            Regime::Libration
        } else {
            Regime::Rotation
        }
    }

    /// `k' = √(1 − k²)` for a libration, from the factored difference of squares.
    fn kc_libration(&self) -> f64 {
        let sum = self.c + self.q.abs();
        (self.gap().max(0.0) * sum).sqrt().min(1.0)
    }

    /// `|1 − k²| = |c² − q²|`, the distance to the separatrix in energy units of `2n²`.
    fn separatrix_distance(&self) -> f64 {
        (self.gap() * (self.c + self.q.abs())).abs()
    }

    fn separatrix_error(&self, what: &str) -> Error {
        Error::Separatrix {
            what: what.into(),
            distance: self.separatrix_distance(),
            hint: "H = 2n² to rounding: the motion approaches θ = ±π asymptotically and has no \
                   turning point or finite period; use PendulumMotion / exact_state for the flow"
                .into(),
        }
    }
}

/// Regime-specific constants of the flow.
#[derive(Clone, Copy, Debug)]
enum Flow {
    /// `H = 0` (or `H/(2n²)` below the smallest double): the linearised flow is exact.
    Rest,
    /// `sin(θ/2) = k sn(n t + u₀, k)`, `p = 2 n k cn(n t + u₀, k)`.
    Libration { k: f64, kc: f64, u0: f64 },
    /// `θ = θ₀ + 2 gd(σ n t + c₀) − θ_r`, `p = 2 n σ sech(σ n t + c₀)`.
    Separatrix { sigma: f64, c0: f64 },
    /// `θ = θ₀ + 2σ am(n k t + v₀, κ) − θ_r`, `p = 2 n k σ dn(n k t + v₀, κ)`, `κ = 1/k`.
    Rotation {
        sigma: f64,
        kappa: f64,
        kappa_c: f64,
        v0: f64,
    },
}

/// The exact flow of `H = ½ p² + n²(1 − cos θ)` from a fixed initial state `(θ₀, p₀)`.
///
/// Construction classifies the motion by `k² = H/(2n²)` and precomputes the phase of the initial
/// state; [`PendulumMotion::state_at`] then evaluates the closed form (DLMF §22.19(i);
/// Byrd & Friedman 1971; Lawden 1989):
///
/// * libration, `k < 1`: `θ(t) = 2 atan2(k sn(w, k), dn(w, k))` (= `2 arcsin(k sn w)`),
///   `p(t) = 2 n k cn(w, k)`, `w = n t + u₀`, with `u₀ = F(φ₀ | k)` and
///   `φ₀ = atan2(sin(θ₀/2), p₀/2n)` so that both signs of `θ₀` and `p₀` are honoured;
/// * separatrix, `k = 1` to rounding: `θ(t) = 2πm + 2 gd(w)`, `gd w = 2 atan(eʷ) − π/2`,
///   `p(t) = 2 n σ sech w`, `w = σ n t + asinh(tan(θ_r/2))`, `σ = sign p₀`;
/// * rotation, `k > 1`: reciprocal-modulus transformation (DLMF §22.17(i)),
///   `θ(t) = 2πm + 2σ am(w, 1/k)`, `p(t) = 2 n k σ dn(w, 1/k)`, `w = n k t + F(σ θ_r/2 | 1/k)`.
///
/// Here `θ₀ = θ_r + 2πm` with `θ_r ∈ [−π, π]` and `m` an integer; for rotation and separatrix the
/// term `2πm` is applied as `θ₀ − θ_r`, so the angle stays continuous through `θ₀` even when `m`
/// exceeds the integers a double can count. The reduction mod 2π uses a two-part `2π` and costs
/// about `1e−32 |θ₀|` plus one ulp of `θ_r`.
///
/// Angle conventions:
/// * **libration**: the returned `θ(t)` lies in `[−π, π]` and is congruent mod 2π to the true
///   continuation of `θ₀` (the `2πm` of the initial angle is *not* added back);
/// * **rotation and separatrix**: the returned `θ(t)` is the continuous angle, equal to `θ₀` at
///   `t = 0`; for rotation it grows without bound (`2π` per [`PendulumMotion::period`]).
///
/// The complementary modulus is formed without cancellation from the state,
/// `k'² = (cos(θ/2) − |p|/2n)(cos(θ/2) + |p|/2n)`, so librations and rotations arbitrarily close
/// to the separatrix keep their phase accuracy; a state is classified as on the separatrix only
/// when `cos(θ/2)` and `|p|/2n` agree to rounding.
#[derive(Clone, Copy, Debug)]
pub struct PendulumMotion {
    n: f64,
    theta0: f64,
    p0: f64,
    state: ReducedState,
    regime: Regime,
    flow: Flow,
}

impl PendulumMotion {
    /// Prepare the exact flow through `(θ₀, p₀)` for small-oscillation frequency `n`.
    ///
    /// `H = ½ p₀² + 2n² sin²(θ₀/2)`; the regime is decided by the sign of
    /// `cos(θ₀/2) − |p₀|/2n` (equivalently of `2n² − H`).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞ (including `p₀/2n` overflowing); [`Error::OutOfDomain`] for
    /// `n ≤ 0`; [`Error::PhaseLost`] when `|θ₀|` exceeds
    /// [`MAX_PHASE_ADVANCE`] `= 10⁻⁶/ε`, beyond
    /// which the rounding of `θ₀` itself exceeds 10⁻⁶ rad and its place on the circle is lost.
    pub fn new(n: f64, theta0: f64, p0: f64) -> Result<Self> {
        let state = ReducedState::new(n, theta0, p0)?;
        let regime = state.regime();
        let ReducedState { s, c, q, k, .. } = state;
        let flow = match regime {
            Regime::Libration if k == 0.0 => Flow::Rest,
            Regime::Libration => {
                let kc = state.kc_libration();
                let k = k.min(1.0);
                // φ₀ = am u₀ has sin φ₀ = s/k, cos φ₀ = q/k and Δ(φ₀) = √(1 − s²) = c.
                let (sin_phi, cos_phi) = (s / k, q / k);
                let f = incomplete_f(sin_phi, cos_phi * cos_phi, c * c)?;
                let u0 = if q >= 0.0 {
                    f
                } else {
                    // φ₀ beyond ±π/2: F(φ) = ±2K − F(±π − φ).
                    let two_k = 2.0 * complete_k_unchecked(kc)?;
                    if s >= 0.0 {
                        two_k - f
                    } else {
                        -two_k - f
                    }
                };
                Flow::Libration { k, kc, u0 }
            }
            Regime::Separatrix => {
                let sigma = if q >= 0.0 { 1.0 } else { -1.0 };
                Flow::Separatrix {
                    sigma,
                    c0: (s / c).asinh(),
                }
            }
            Regime::Rotation => {
                let sigma = if q >= 0.0 { 1.0 } else { -1.0 };
                let kappa = (1.0 / k).min(1.0);
                let aq = q.abs();
                let kappa_c = (((aq - c) / k) * ((aq + c) / k)).sqrt().min(1.0);
                // φ₀ = σ θ_r/2: sin φ₀ = σ s, cos² φ₀ = c², 1 − κ² sin² φ₀ = q²/k².
                let qk = q / k;
                let v0 = incomplete_f(sigma * s, c * c, qk * qk)?;
                Flow::Rotation {
                    sigma,
                    kappa,
                    kappa_c,
                    v0,
                }
            }
        };
        Ok(Self {
            n,
            theta0,
            p0,
            state,
            regime,
            flow,
        })
    }

    /// The regime of the motion.
    pub fn regime(&self) -> Regime {
        self.regime
    }

    /// Energy modulus `k = √(H/(2n²)) = √(sin²(θ₀/2) + p₀²/(4n²))` (DLMF §22.19(i)); `k < 1` for
    /// libration, `k > 1` for rotation.
    pub fn modulus(&self) -> f64 {
        self.state.k
    }

    /// `√|1 − k²|` computed without cancellation as `√|cos²(θ₀/2) − p₀²/(4n²)|` (in factored form);
    /// for a libration this is the complementary modulus `k' = cos(a/2)`. Zero on the separatrix.
    pub fn complementary_modulus(&self) -> f64 {
        match self.regime {
            Regime::Separatrix => 0.0,
            _ => self.state.separatrix_distance().sqrt(),
        }
    }

    /// Period of the motion: `4K(k)/n` for libration (DLMF §22.19(i)), and the time
    /// `2K(1/k)/(n k)` for `θ` to advance by `2π` in rotation.
    ///
    /// # Errors
    /// [`Error::Separatrix`] on the separatrix (infinite period).
    pub fn period(&self) -> Result<f64> {
        let n = self.n;
        match self.flow {
            Flow::Rest => finite("period", TAU / n),
            Flow::Libration { kc, .. } => finite("period", 4.0 * complete_k_unchecked(kc)? / n),
            Flow::Separatrix { .. } => Err(self.state.separatrix_error("pendulum period")),
            Flow::Rotation { kappa_c, .. } => {
                if kappa_c == 0.0 {
                    return Err(self.state.separatrix_error("pendulum period"));
                }
                finite(
                    "period",
                    2.0 * complete_k_unchecked(kappa_c)? / (n * self.state.k),
                )
            }
        }
    }

    /// State `(θ(t), p(t))` at time `t` (negative `t` runs the flow backwards); see the type-level
    /// documentation for the formulas and the angle convention. At `t = 0` the initial state is
    /// returned (with `θ₀` reduced to `[−π, π]` for a libration).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for non-finite `t` or if the phase `n t + u₀` overflows;
    /// [`Error::OutOfDomain`] if the phase is too large for the Landen scheme.
    pub fn state_at(&self, t: f64) -> Result<(f64, f64)> {
        let t = finite("t", t)?;
        let n = self.n;
        // Rotation and separatrix return θ₀ plus the increment of the reduced angle, which keeps
        // the angle continuous through θ₀ however many turns θ₀ holds.
        let theta_r = self.state.theta_r;
        if t == 0.0 {
            return Ok(match self.regime {
                Regime::Libration => (self.state.theta_r, self.p0),
                _ => (self.theta0, self.p0),
            });
        }
        let (theta, p) = match self.flow {
            Flow::Rest => {
                let p0 = self.p0;
                let (sn, cs) = (n * t).sin_cos();
                (
                    theta_r.mul_add(cs, (p0 / n) * sn),
                    p0.mul_add(cs, -(n * theta_r) * sn),
                )
            }
            Flow::Libration { k, kc, u0 } => {
                let w = finite("phase n t + u0", n.mul_add(t, u0))?;
                let j = jacobi_unchecked(w, k, kc)?;
                (2.0 * (k * j.sn).atan2(j.dn), 2.0 * n * (k * j.cn))
            }
            Flow::Separatrix { sigma, c0 } => {
                let w = finite("phase n t + c0", (sigma * n).mul_add(t, c0))?;
                let increment = 2.0 * w.sinh().atan() - theta_r;
                (self.theta0 + increment, 2.0 * n * sigma / w.cosh())
            }
            Flow::Rotation {
                sigma,
                kappa,
                kappa_c,
                v0,
            } => {
                let k = self.state.k;
                let w = finite("phase n k t + v0", (n * k).mul_add(t, v0))?;
                let j = jacobi_unchecked(w, kappa, kappa_c)?;
                let increment = 2.0 * sigma * j.am - theta_r;
                (self.theta0 + increment, 2.0 * n * k * sigma * j.dn)
            }
        };
        Ok((finite("theta(t)", theta)?, finite("p(t)", p)?))
    }
}

/// Exact state `(θ(t), p(t))` of the pendulum `H = ½ p² + n²(1 − cos θ)` started at `(θ₀, p₀)`:
/// shorthand for `PendulumMotion::new(n, theta0, p0)?.state_at(t)`; see [`PendulumMotion`] for the
/// closed forms (libration, separatrix, rotation; DLMF §22.19(i)) and the angle convention
/// (libration: `θ ∈ [−π, π]`; rotation/separatrix: continuous angle through `θ₀`).
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] for `n ≤ 0`; [`Error::PhaseLost`] when
/// `|θ₀|` exceeds [`MAX_PHASE_ADVANCE`].
pub fn exact_state(n: f64, theta0: f64, p0: f64, t: f64) -> Result<(f64, f64)> {
    PendulumMotion::new(n, theta0, p0)?.state_at(t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::special::elliptic::tests::{proptest_config, rel};
    use proptest::prelude::*;

    const EPS: f64 = f64::EPSILON;

    /// Classical fourth-order Runge–Kutta for θ' = p, p' = −n² sin θ, recording the state at every
    /// multiple of `every` steps.
    fn rk4(
        n: f64,
        theta0: f64,
        p0: f64,
        h: f64,
        steps: usize,
        every: usize,
    ) -> Vec<(f64, f64, f64)> {
        let f = |th: f64, p: f64| (p, -n * n * th.sin());
        let (mut th, mut p) = (theta0, p0);
        let mut out = vec![(0.0, th, p)];
        for i in 1..=steps {
            let (k1t, k1p) = f(th, p);
            let (k2t, k2p) = f(th + 0.5 * h * k1t, p + 0.5 * h * k1p);
            let (k3t, k3p) = f(th + 0.5 * h * k2t, p + 0.5 * h * k2p);
            let (k4t, k4p) = f(th + h * k3t, p + h * k3p);
            th += h / 6.0 * (k1t + 2.0 * k2t + 2.0 * k3t + k4t);
            p += h / 6.0 * (k1p + 2.0 * k2p + 2.0 * k3p + k4p);
            if i % every == 0 {
                out.push((i as f64 * h, th, p));
            }
        }
        out
    }

    // ---------------------------------------------------------------- periods

    #[test]
    #[allow(clippy::approx_constant)] // 3.14 is a table entry, not an approximation of π
    fn period_ratio_table() {
        // 15-digit references: the last digit carries up to ±5e−15 relative, so 1e−13 is a
        // tolerance of about 20 reference ulps and 450 double ulps.
        let table = [
            (0.1, 1.000_625_358_307_74),
            (0.5, 1.015_852_531_101_44),
            (1.0, 1.066_334_245_579_96),
            (2.0, 1.328_904_451_915_10),
            (3.0, 2.571_233_949_432_14),
            (3.1, 3.348_496_445_570_80),
            (3.14, 5.425_144_192_103_53),
            (PI - 1e-6, 10.119_040_787_302_7),
        ];
        let mut worst = 0.0_f64;
        for (a, ratio) in table {
            let tau = period(1.0, a).unwrap();
            let err = rel(tau / TAU, ratio);
            worst = worst.max(err);
            assert!(
                err <= 1e-13,
                "a = {a}: ratio {} vs {ratio}, rel {err:e}",
                tau / TAU
            );
            // The ratio does not depend on n.
            let tau3 = period(3.0, a).unwrap();
            assert!(rel(3.0 * tau3 / TAU, ratio) <= 1e-13);
        }
        eprintln!("period ratio table: max relative error {worst:e}");
        assert_eq!(period(2.0, 0.0).unwrap(), PI);
    }

    #[test]
    fn period_near_separatrix_from_exact_gap() {
        // 15-digit references (tolerance as for the period table).
        let table = [
            (1e-2, 26.738_605_693_505_2),
            (1e-6, 63.579_808_398_580_3),
            (1e-10, 100.421_169_886_481),
            (1e-16, 155.683_212_118_338),
        ];
        let mut worst = 0.0_f64;
        for (delta, tau_ref) in table {
            let err = rel(period_from_gap(1.0, delta).unwrap(), tau_ref);
            worst = worst.max(err);
            assert!(err <= 1e-13, "δ = {delta}: rel {err:e}");
        }
        eprintln!("near the separatrix (gap): max relative error {worst:e}");
        assert!(rel(period_from_gap(1.0, PI).unwrap(), TAU) <= EPS);
    }

    #[test]
    fn period_near_separatrix_from_double_amplitude() {
        // a = fl(π − δ) sits at gap (PI − a) + (π − PI) from π; the references are the periods of
        // those exact doubles, which differ from the exact-gap ones from the 10th digit on.
        let table = [
            (1e-2, 26.738_605_693_505_3),
            (1e-6, 63.579_808_397_531_4),
            (1e-10, 100.421_164_656_936),
        ];
        let mut worst = 0.0_f64;
        for (delta, tau_ref) in table {
            let err = rel(period(1.0, PI - delta).unwrap(), tau_ref);
            worst = worst.max(err);
            assert!(err <= 1e-13, "δ = {delta}: rel {err:e}");
        }
        eprintln!("near the separatrix (double amplitude): max relative error {worst:e}");
    }

    #[test]
    fn period_logarithmic_asymptote_at_the_separatrix() {
        // τ = 4 ln(8/δ) + (δ²/4)(ln(8/δ) − 1/3) + …  (n = 1; DLMF 19.12.1 with k' = sin(δ/2)), so the
        // relative deviation from 4 ln(8/δ) is about δ²/16 = 6e−14 at δ = 1e−6; bound δ²/8.
        let delta = 1e-6;
        let tau = period_from_gap(1.0, delta).unwrap();
        let asym = 4.0 * (8.0 / delta).ln();
        let dev = rel(asym, tau);
        assert!(dev <= delta * delta / 8.0, "deviation {dev:e}");
        assert!(
            dev >= delta * delta / 32.0,
            "deviation {dev:e} lacks the δ² term"
        );
    }

    #[test]
    fn period_at_and_beyond_pi() {
        // fl(π − 1e−16) is PI itself: the separatrix.
        assert_eq!(PI - 1e-16, PI);
        assert!(matches!(
            period(1.0, PI - 1e-16),
            Err(Error::Separatrix { .. })
        ));
        assert!(matches!(period(1.0, PI), Err(Error::Separatrix { .. })));
        assert!(matches!(period(1.0, 3.2), Err(Error::OutOfDomain { .. })));
        assert!(matches!(period(1.0, -0.1), Err(Error::OutOfDomain { .. })));
        assert!(matches!(
            period_from_gap(1.0, 0.0),
            Err(Error::Separatrix { .. })
        ));
        assert!(matches!(
            period_from_gap(1.0, -1e-3),
            Err(Error::OutOfDomain { .. })
        ));
        assert!(matches!(
            period_from_gap(1.0, 3.2),
            Err(Error::OutOfDomain { .. })
        ));
        // The largest double below π has a gap of one ulp plus π − PI and a finite period.
        let a = f64::from_bits(PI.to_bits() - 1);
        let tau = period(1.0, a).unwrap();
        let gap = (PI - a) + PI_LO;
        assert!(rel(tau, period_from_gap(1.0, gap).unwrap()) <= 4.0 * EPS);
    }

    // ---------------------------------------------------------------- exact flow

    #[test]
    fn flow_matches_rk4_oracle() {
        // RK4 with h = 1e−3 over t = 10: global truncation error ~ C h⁴ = 1e−12 C, with C set by
        // the fifth derivatives of the solution (of order 1–1e2 here, larger near θ = π), and
        // roundoff ~ 1e4 steps × 1e−16. The 1e−9 tolerance admits C up to 1e3.
        let cases = [
            (1.0, 0.01, 0.0),
            (1.0, 1.0, 0.0),
            (1.0, 3.0, 0.0),
            (1.0, 0.0, 2.5),
            (1.0, 0.5, -0.8),
            (1.7, -2.0, 0.9),
            (1.0, -1.0, -2.5),
            (0.8, 2.0, -1.0),
            (2.0, -0.4, 3.9),
        ];
        let h = 1e-3;
        let mut worst = 0.0_f64;
        for (n, th0, p0) in cases {
            for dir in [1.0, -1.0] {
                let motion = PendulumMotion::new(n, th0, p0).unwrap();
                for (t, th_rk, p_rk) in rk4(n, th0, p0, dir * h, 10_000, 100) {
                    let (th, p) = motion.state_at(t).unwrap();
                    let err = (th - th_rk).abs().max((p - p_rk).abs());
                    worst = worst.max(err);
                    assert!(
                        err <= 1e-9,
                        "n={n} θ0={th0} p0={p0} t={t}: exact ({th}, {p}) rk4 ({th_rk}, {p_rk})"
                    );
                }
            }
        }
        eprintln!("exact flow vs RK4: max error {worst:e}");
    }

    #[test]
    fn separatrix_closed_form() {
        // θ0 = 0, p0 = 2n lies exactly on the separatrix: θ = 4 atan(e^{nt}) − π, p = 2n sech(nt).
        let n = 1.3;
        let motion = PendulumMotion::new(n, 0.0, 2.0 * n).unwrap();
        assert_eq!(motion.regime(), Regime::Separatrix);
        assert!(matches!(motion.period(), Err(Error::Separatrix { .. })));
        let mut worst = 0.0_f64;
        for i in -60..=60 {
            let t = 0.25 * f64::from(i);
            let (th, p) = motion.state_at(t).unwrap();
            let th_ref = 4.0 * (n * t).exp().atan() - PI;
            let p_ref = 2.0 * n / (n * t).cosh();
            let err = (th - th_ref).abs().max((p - p_ref).abs());
            worst = worst.max(err);
            // Both closed forms are a handful of correctly rounded elementary functions of n t.
            assert!(err <= 1e-14, "t = {t}: ({th}, {p}) vs ({th_ref}, {p_ref})");
        }
        // Moving backwards on the other branch.
        let (th, p) = exact_state(n, 0.0, -2.0 * n, 2.0).unwrap();
        assert!((th + 4.0 * (2.0 * n).exp().atan() - PI).abs() <= 1e-14);
        assert!((p + 2.0 * n / (2.0 * n).cosh()).abs() <= 1e-14);
        // A separatrix state away from the bottom, checked against RK4 for a short time (the
        // separatrix is unstable, RK4 errors grow like e^{nt}).
        let (th0, p0) = (1.0, 2.0 * (0.5_f64).cos());
        let m = PendulumMotion::new(1.0, th0, p0).unwrap();
        assert_eq!(m.regime(), Regime::Separatrix);
        for (t, th_rk, p_rk) in rk4(1.0, th0, p0, 1e-3, 4000, 100) {
            let (th, p) = m.state_at(t).unwrap();
            assert!((th - th_rk).abs().max((p - p_rk).abs()) <= 1e-9, "t = {t}");
        }
        eprintln!("separatrix closed form: max error {worst:e}");
        assert!(matches!(
            amplitude_from_state(n, 0.0, 2.0 * n),
            Err(Error::Separatrix { .. })
        ));
    }

    #[test]
    fn near_separatrix_reference_states() {
        // (n, θ0, p0, t, θ(t), p(t)): closed-form values from mpmath at 50 digits (ellipf, ellipfun,
        // with the initial doubles taken exactly), quoted to 17 digits. `eta` is the relative
        // distance of |p0|/2n from cos(θ0/2) built into the state (0: no cancellation in k'²).
        let rows = [
            (
                1.0,
                PI - 1e-6,
                0.0,
                25.0,
                0.0,
                -3.141_148_238_825_520_6,
                -4.444_136_355_388_298e-4,
            ),
            (
                1.0,
                0.0,
                1.999_999_999_8,
                30.0,
                0.0,
                -3.111_648_815_204_006,
                -2.994_270_634_584_272e-2,
            ),
            (
                1.0,
                0.0,
                2.000_000_000_2,
                30.0,
                0.0,
                9.394_834_135_827_773,
                2.994_271_962_085_69e-2,
            ),
            (
                1.3,
                0.4,
                -2.548_172_847_569_918_4,
                12.0,
                1e-7,
                -2.907_957_488_938_491,
                0.303_033_251_400_982_1,
            ),
            (
                0.7,
                -1.0,
                1.228_615_709_508_080_5,
                40.0,
                1e-7,
                9.424_611_673_345_214,
                5.616_480_267_787_471e-4,
            ),
            (
                1.0,
                PI,
                0.0,
                20.0,
                0.0,
                3.141_592_623_881_993,
                -2.970_780_018_081_498_8e-8,
            ),
        ];
        let mut worst = 0.0_f64;
        for (n, th0, p0, t, eta, th_ref, p_ref) in rows {
            let m = PendulumMotion::new(n, th0, p0).unwrap();
            let kc = m.complementary_modulus();
            // Without cancellation the phase carries ε|u| (|u| ≲ 60 here): 1e−13. With
            // |p0|/2n = cos(θ0/2)(1 ± η), the rounding of cos(θ0/2) perturbs k'² by ε/η relative,
            // the period by ε/(2η ln(4/k')) relative, and the state by |θ'| ≤ 2n times t times that.
            let tol = if eta > 0.0 {
                1e-13 + 2.0 * n * t * EPS / (eta * (4.0 / kc).ln())
            } else {
                1e-13
            };
            let (th, p) = m.state_at(t).unwrap();
            let err = (th - th_ref).abs().max((p - p_ref).abs());
            worst = worst.max(err);
            assert!(
                err <= tol,
                "θ0={th0} p0={p0} t={t}: ({th}, {p}) vs ({th_ref}, {p_ref})"
            );
        }
        eprintln!("near-separatrix reference states: max error {worst:e}");
    }

    #[test]
    fn continuity_across_the_separatrix() {
        // States with p0 = 2n(1 ∓ η) sit at k'² ≈ ±2η from the separatrix; initial data differing by
        // 2nη separate at most like 2nη e^{nt} (the separatrix's Lyapunov rate is n), i.e. ≈ 4e−11
        // for η = 1e−12, t ≤ 3.
        let n = 1.0;
        let eta = 1e-12;
        let lib = PendulumMotion::new(n, 0.0, 2.0 * n * (1.0 - eta)).unwrap();
        let rot = PendulumMotion::new(n, 0.0, 2.0 * n * (1.0 + eta)).unwrap();
        let sep = PendulumMotion::new(n, 0.0, 2.0 * n).unwrap();
        assert_eq!(lib.regime(), Regime::Libration);
        assert_eq!(rot.regime(), Regime::Rotation);
        for i in -12..=12 {
            let t = 0.25 * f64::from(i);
            let bound = 4.0 * n * eta * (n * t.abs()).exp() + 1e-14;
            let (ts, ps) = sep.state_at(t).unwrap();
            for m in [&lib, &rot] {
                let (th, p) = m.state_at(t).unwrap();
                assert!(
                    (th - ts).abs() <= bound && (p - ps).abs() <= bound,
                    "t = {t}: ({th}, {p}) vs separatrix ({ts}, {ps})"
                );
            }
        }
    }

    #[test]
    fn energy_is_conserved() {
        // θ and p are built from (sn, cn, dn) obeying the identities to a few ε, so H is preserved to
        // a few ε relative regardless of the phase error ε|u|.
        let cases = [
            (1.0, 1e-3, 0.0),
            (1.0, 1.0, 0.3),
            (2.5, 3.0, -0.1),
            (1.0, PI - 1e-9, 0.0),
            (1.0, 0.0, 2.5),
            (0.7, -4.0, -1.7),
            (1.0, 0.2, 1e3),
        ];
        let mut worst = 0.0_f64;
        for (n, th0, p0) in cases {
            let e0 = energy(n, th0, p0).unwrap();
            let m = PendulumMotion::new(n, th0, p0).unwrap();
            for i in -100..=100 {
                let (th, p) = m.state_at(0.731 * f64::from(i)).unwrap();
                let err = rel(energy(n, th, p).unwrap(), e0);
                worst = worst.max(err);
                assert!(err <= 1e-13, "n={n} θ0={th0} p0={p0}: rel {err:e}");
            }
        }
        eprintln!("energy conservation: max relative drift {worst:e}");
    }

    #[test]
    fn one_period_returns_the_initial_state() {
        // u advances by 4K (2K for rotation), carrying rounding ε·4K; the state moves by at most
        // that times |dθ/du|, |dp/du| ≤ 2k n, i.e. ≤ 1e−13 even at K ≈ 20.
        let cases = [
            (1.0, 0.3, 0.0),
            (1.0, 1.0, 0.5),
            (2.0, -3.0, 0.0),
            (1.0, 3.1, -0.02),
            (0.5, PI - 1e-6, 0.0),
            (1.0, 0.0, 2.5),
            (1.0, 2.0, -3.0),
        ];
        let mut worst = 0.0_f64;
        for (n, th0, p0) in cases {
            let m = PendulumMotion::new(n, th0, p0).unwrap();
            let tau = m.period().unwrap();
            let (th, p) = m.state_at(tau).unwrap();
            let shift = match m.regime() {
                Regime::Rotation => TAU * p0.signum(),
                _ => 0.0,
            };
            let err = (th - th0 - shift).abs().max((p - p0).abs());
            worst = worst.max(err);
            assert!(
                err <= 1e-11,
                "n={n} θ0={th0} p0={p0}: ({th}, {p}), err {err:e}"
            );
            if m.regime() == Regime::Libration {
                let a = amplitude_from_state(n, th0, p0).unwrap();
                assert!(rel(tau, period(n, a).unwrap()) <= 1e-12);
            }
        }
        eprintln!("state after one period: max error {worst:e}");
    }

    #[test]
    fn small_amplitude_limit() {
        // Lindstedt: θ = a cos ωt + (a³/192)(cos ωt − cos 3ωt) + O(a⁵), ω = n(1 − a²/16 + …), so
        // |θ − θ_lin| ≤ a³ (n t/16 + 1/96) and |p − p_lin| ≤ n a³ (n t/16 + 1/16 + 1/48) at leading
        // order; factor 2 for the O(a⁵) remainder.
        let n = 2.0;
        let (th0, p0) = (6e-4, 8e-4 * n);
        let a = amplitude_from_state(n, th0, p0).unwrap();
        assert!(rel(a, 1e-3) <= 1e-6);
        let m = PendulumMotion::new(n, th0, p0).unwrap();
        for i in 0..=100 {
            let t = 0.1 * f64::from(i);
            let (th, p) = m.state_at(t).unwrap();
            let (s, c) = (n * t).sin_cos();
            let th_lin = th0 * c + p0 / n * s;
            let p_lin = p0 * c - n * th0 * s;
            let a3 = a * a * a;
            assert!((th - th_lin).abs() <= 2.0 * a3 * (n * t / 16.0 + 1.0 / 96.0));
            assert!((p - p_lin).abs() <= 2.0 * n * a3 * (n * t / 16.0 + 1.0 / 12.0));
        }
        // H = 0 exactly: the pendulum rests.
        assert_eq!(exact_state(n, 0.0, 0.0, 3.0).unwrap(), (0.0, 0.0));
    }

    #[test]
    fn angle_conventions() {
        let n = 1.1;
        // Libration from θ0 + 2πm: same motion, returned in [−π, π].
        let base = PendulumMotion::new(n, 1.2, -0.4).unwrap();
        for m in [-3.0, 1.0, 5.0] {
            let shifted = PendulumMotion::new(n, 1.2 + TAU * m, -0.4).unwrap();
            for t in [0.0, 0.7, 5.0, -13.0] {
                let (a, pa) = base.state_at(t).unwrap();
                let (b, pb) = shifted.state_at(t).unwrap();
                // The reduction of 1.2 + 2πm costs ε·|θ0| ≤ 1e−14.
                assert!((a - b).abs() <= 1e-13 && (pa - pb).abs() <= 1e-13);
                assert!(b.abs() <= PI);
            }
        }
        // Rotation: continuous angle through θ0, advancing 2π per period.
        let th0 = 7.0;
        let m = PendulumMotion::new(n, th0, -3.0).unwrap();
        assert_eq!(m.regime(), Regime::Rotation);
        assert_eq!(m.state_at(0.0).unwrap(), (th0, -3.0));
        let (th1, _) = m.state_at(1e-6).unwrap();
        assert!((th1 - (th0 - 3e-6)).abs() <= 1e-11);
        let tau = m.period().unwrap();
        let (th10, p10) = m.state_at(10.0 * tau).unwrap();
        // Ten periods: phase rounding ε·|w| with |w| ≈ 20 K.
        assert!((th10 - (th0 - 10.0 * TAU)).abs() <= 1e-11, "{th10}");
        assert!((p10 + 3.0).abs() <= 1e-11);
        // θ0 = π with p0 = 0 is (for the double PI) a libration at k' = cos(PI/2) ≈ 6e−17.
        let top = PendulumMotion::new(1.0, PI, 0.0).unwrap();
        assert_eq!(top.regime(), Regime::Libration);
        let (th, p) = top.state_at(5.0).unwrap();
        assert!((th - PI).abs() < 1e-10 && p.abs() < 1e-10, "({th}, {p})");
        // ... and so is −π: the reduction picks the well consistently.
        let (th, _) = exact_state(1.0, -PI, 0.0, 5.0).unwrap();
        assert!((th.abs() - PI).abs() < 1e-10);
    }

    #[test]
    fn large_initial_angles() {
        // θ0 − 2π·round(θ0/2π) for these exact doubles, from mpmath at 400 digits (all within
        // MAX_PHASE_ADVANCE ≈ 4.5e9).
        let rows: [(f64, f64); 4] = [
            (1e6, -0.357_564_167_085_735),
            (1e9, 0.577_395_423_501_385_2),
            (4e9, 2.309_581_694_005_540_7),
            (-4e9, -2.309_581_694_005_540_7),
        ];
        let n = 1.0;
        for (big, r) in rows {
            // The two-part 2π reduction costs ≈ 1e−32 |θ0| + a few ulps of θ_r; the flow then adds
            // its own ≲ 1e−14 at these phases.
            let tol = 1e-14 + 1e-31 * big.abs();
            for p0 in [0.3, -2.5, 3.0] {
                let m = PendulumMotion::new(n, big, p0).unwrap();
                for t in [0.5, -3.0, 11.0] {
                    let (tb, pb) = m.state_at(t).unwrap();
                    let (ts, ps) = exact_state(n, r, p0, t).unwrap();
                    assert!((pb - ps).abs() <= tol, "θ0 = {big:e}: p {pb} vs {ps}");
                    if m.regime() == Regime::Libration {
                        assert!((tb - ts).abs() <= tol, "θ0 = {big:e}: θ {tb} vs {ts}");
                    } else {
                        // The continuous angle θ0 + Δθ is itself rounded to an ulp of θ0.
                        let inc = ts - r;
                        assert!((tb - (big + inc)).abs() <= tol + 2.0 * EPS * big.abs());
                    }
                }
            }
        }
        // Beyond MAX_PHASE_ADVANCE the rounding of θ0 itself (half an ulp) exceeds 1e−6 rad: the
        // place on the circle is lost and refused, as the phase of the Kepler propagators is.
        for big in [4.6e9, 1e12, -1e20, 1e300, f64::MAX, f64::MIN] {
            for r in [
                exact_state(1.0, big, 0.5, 2.0).map(|_| ()),
                amplitude_from_state(1.0, big, 0.5).map(|_| ()),
                PendulumMotion::new(1.0, big, 0.5).map(|_| ()),
            ] {
                assert!(
                    matches!(r, Err(Error::PhaseLost { .. })),
                    "θ0 = {big:e}: {r:?}"
                );
            }
        }
        assert!(exact_state(1.0, MAX_PHASE_ADVANCE, 0.5, 2.0).is_ok());
    }

    #[test]
    fn amplitude_from_state_round_trip() {
        for a in [1e-8, 0.1, 1.0, 2.0, 3.0, 3.1, 3.1405] {
            assert!(rel(amplitude_from_state(1.0, a, 0.0).unwrap(), a) <= 2.0 * EPS);
            assert!(rel(amplitude_from_state(1.0, -a, 0.0).unwrap(), a) <= 2.0 * EPS);
            // At the bottom with p = 2n sin(a/2): the rounding of p (relative ε) moves a by
            // ε tan(a/2), the conditioning of the inverse sine.
            let p = 2.0 * 1.7 * (0.5 * a).sin();
            let err = (amplitude_from_state(1.7, 0.0, p).unwrap() - a).abs();
            assert!(
                err <= 4.0 * EPS * (1.0 + (0.5 * a).tan()),
                "a = {a}: {err:e}"
            );
        }
        // Near π the gap survives: a = PI − 1e−12 keeps its 1e−12 gap to a few ulps of π.
        let a = PI - 1e-12;
        assert_eq!(amplitude_from_state(1.0, a, 0.0).unwrap(), a);
        assert!(matches!(
            amplitude_from_state(1.0, 0.0, 2.5),
            Err(Error::OutOfDomain { .. })
        ));
    }

    #[test]
    fn bad_input_is_rejected() {
        let nonfinite = [f64::NAN, f64::INFINITY, f64::NEG_INFINITY];
        for x in nonfinite {
            assert!(matches!(period(x, 1.0), Err(Error::NonFinite { .. })));
            assert!(matches!(period(1.0, x), Err(Error::NonFinite { .. })));
            assert!(matches!(
                period_from_gap(x, 1.0),
                Err(Error::NonFinite { .. })
            ));
            assert!(matches!(
                period_from_gap(1.0, x),
                Err(Error::NonFinite { .. })
            ));
            for args in [
                (x, 0.1, 0.1, 1.0),
                (1.0, x, 0.1, 1.0),
                (1.0, 0.1, x, 1.0),
                (1.0, 0.1, 0.1, x),
            ] {
                assert!(matches!(
                    exact_state(args.0, args.1, args.2, args.3),
                    Err(Error::NonFinite { .. })
                ));
            }
            assert!(matches!(
                amplitude_from_state(x, 0.1, 0.1),
                Err(Error::NonFinite { .. })
            ));
            assert!(matches!(
                amplitude_from_state(1.0, x, 0.1),
                Err(Error::NonFinite { .. })
            ));
            assert!(matches!(
                amplitude_from_state(1.0, 0.1, x),
                Err(Error::NonFinite { .. })
            ));
        }
        for n in [0.0, -0.0, -1.0] {
            assert!(matches!(period(n, 1.0), Err(Error::OutOfDomain { .. })));
            assert!(matches!(
                period_from_gap(n, 1.0),
                Err(Error::OutOfDomain { .. })
            ));
            assert!(matches!(
                exact_state(n, 0.1, 0.1, 1.0),
                Err(Error::OutOfDomain { .. })
            ));
            assert!(matches!(
                amplitude_from_state(n, 0.1, 0.1),
                Err(Error::OutOfDomain { .. })
            ));
            assert!(matches!(
                PendulumMotion::new(n, 0.1, 0.1),
                Err(Error::OutOfDomain { .. })
            ));
        }
        // Overflowing scales are reported, not returned as ∞.
        assert!(exact_state(1e-300, 0.1, 1e300, 1.0).is_err());
        assert!(exact_state(1.0, 0.1, 0.1, 1e308).is_err());
    }

    // ---------------------------------------------------------------- properties

    proptest! {
        #![proptest_config(proptest_config())]

        #[test]
        fn prop_energy_conserved(
            n in 0.2..5.0_f64,
            th0 in -10.0..10.0_f64,
            pr in -3.0..3.0_f64,
            t in -50.0..50.0_f64,
        ) {
            // p0 in units of the separatrix momentum 2n: |pr| > 1 always rotates.
            let p0 = 2.0 * n * pr;
            let e0 = energy(n, th0, p0).unwrap();
            let (th, p) = exact_state(n, th0, p0, t).unwrap();
            // A few ε from the Jacobi identities, plus the rounding of the returned angle itself:
            // ε|θ| moves H by ≤ ε|θ|/(2k²) relative, and a rotation reaches |θ| ≤ 2nk·50 + 10, so
            // that term stays below 6e−14.
            prop_assert!(rel(energy(n, th, p).unwrap(), e0) <= 1e-13);
        }

        #[test]
        fn prop_flow_group_property_near_separatrix(
            n in 0.5..2.0_f64,
            th0 in -PI..PI,
            sign in prop::bool::ANY,
            side in prop::bool::ANY,
            e in -6.0..-1.0_f64,
            t1 in -10.0..10.0_f64,
            t2 in -10.0..10.0_f64,
        ) {
            // |p0|/2n = cos(θ0/2)(1 ± 10^e): 1 − k² ≈ ∓2·10^e cos²(θ0/2).
            let c = (0.5 * th0).cos();
            let q = c * (1.0 + if side { 1.0 } else { -1.0 } * 10f64.powf(e));
            let p0 = if sign { 2.0 * n * q } else { -2.0 * n * q };
            let m = PendulumMotion::new(n, th0, p0).unwrap();
            let kc = m.complementary_modulus();
            prop_assume!(kc > 1e-3);
            let (th1, p1) = m.state_at(t1).unwrap();
            let (th12, p12) = exact_state(n, th1, p1, t2).unwrap();
            let (th, p) = m.state_at(t1 + t2).unwrap();
            let err = (th12 - th).abs().max((p12 - p).abs() / n);
            // Restarting from the rounded intermediate state perturbs k'² by a few ε (≤ 8ε); with
            // τ ∝ ln(4/k') that shifts the period by Δτ/τ ≈ 8ε / (2 k'² ln(4/k')), and the phase
            // error accumulates at speed |θ'| ≤ 2n over |t1| + |t2|. Plus 1e−12 for the ordinary
            // ε|u| rounding of the phases.
            let big_t = t1.abs() + t2.abs();
            let bound = 2.0 * n * big_t * 8.0 * EPS / (2.0 * kc * kc * (4.0 / kc).ln()) + 1e-12;
            prop_assert!(err <= bound, "k' = {}: error {:e} > bound {:e}", kc, err, bound);
        }

        #[test]
        fn prop_flow_group_property(
            n in 0.2..5.0_f64,
            th0 in -PI..PI,
            pr in -3.0..3.0_f64,
            t1 in -15.0..15.0_f64,
            t2 in -15.0..15.0_f64,
        ) {
            let p0 = 2.0 * n * pr;
            let m = PendulumMotion::new(n, th0, p0).unwrap();
            prop_assume!(m.complementary_modulus() > 1e-3);
            let (th1, p1) = m.state_at(t1).unwrap();
            let (th12, p12) = exact_state(n, th1, p1, t2).unwrap();
            let (th, p) = m.state_at(t1 + t2).unwrap();
            // Restarting from the rounded state perturbs k'² by ~ε; at k' ≥ 1e−3 that shifts the
            // frequency by ≲ ε/k'² relative, i.e. a phase error ≲ 1e−10 over |t| ≤ 30.
            prop_assert!((th12 - th).abs() <= 1e-9, "θ: {} vs {}", th12, th);
            prop_assert!((p12 - p).abs() <= 1e-9 * n, "p: {} vs {}", p12, p);
        }
    }
}

//! The Euler–Poinsot motion: the exact flow of the body angular momentum of a free rigid body in
//! Jacobi elliptic functions.
//!
//! With principal moments `I₁ ≤ I₂ ≤ I₃`, energy `2E = Σ Π_i²/I_i` and `L² = |Π|²`, put
//! `P = 2EI₃ − L²`, `Q = L² − 2EI₁` (both `≥ 0`) and `δ = L² − 2EI₂` (Landau & Lifshitz,
//! *Mechanics*, 3rd ed., §37; Whittaker, *Analytical Dynamics*, §69). For `δ > 0` (rotation about
//! the axis of the largest moment)
//!
//! ```math
//! \Pi_1 = A_1\,\mathrm{cn}\,u,\quad \Pi_2 = \sigma A_2\,\mathrm{sn}\,u,\quad
//! \Pi_3 = \sigma A_3\,\mathrm{dn}\,u,\qquad u = u_0 + \lambda t,
//! ```
//!
//! `A₁² = I₁P/(I₃−I₁)`, `A₂² = I₂P/(I₃−I₂)`, `A₃² = I₃Q/(I₃−I₁)`,
//! `λ = √((I₃−I₂)Q/(I₁I₂I₃))`, `k² = (I₂−I₁)P/((I₃−I₂)Q)`, `k'² = (I₃−I₁)δ/((I₃−I₂)Q)`,
//! `σ = sign Π₃`; for `δ < 0` (rotation about the axis of the smallest moment) the roles of axes
//! 1 and 3 are exchanged: `Π₁ = σA₁ dn u`, `Π₂ = σA₂ sn u`, `Π₃ = A₃ cn u` with
//! `A₁² = I₁P/(I₃−I₁)`, `A₂² = I₂Q/(I₂−I₁)`, `A₃² = I₃Q/(I₃−I₁)`, `λ = √((I₂−I₁)P/(I₁I₂I₃))`,
//! `k² = (I₃−I₂)Q/((I₂−I₁)P)`, `k'² = −(I₃−I₁)δ/((I₂−I₁)P)`. The phase `u₀ = F(am₀ | k)` follows
//! from the amplitude `am₀ = atan2(sn u₀, cn u₀)` of the initial state. `Π` is periodic with period
//! `4K(k)/λ`. On the separatrix `δ = 0` (`k = 1`) the motion is the heteroclinic closed form
//! `Π₁ = σ₁A₁ sech u`, `Π₂ = σ₁σ₃A₂ tanh u`, `Π₃ = σ₃A₃ sech u`; at the equilibria (`P = 0` or
//! `Q = 0`: rotation about a principal axis, or in a degenerate eigenspace) `Π` is constant.
//!
//! `P`, `Q` and `δ` are formed from `Π` as sums of terms with known signs
//! (`P = Π₁²(I₃−I₁)/I₁ + Π₂²(I₃−I₂)/I₂`, …), not as differences of `2E I_i` and `L²`, and `k'` is
//! formed directly, so the flow keeps its accuracy near the separatrix up to the intrinsic
//! sensitivity of the motion there.
//!
//! Moments in any order are handled by relabelling the axes in ascending order; an odd
//! relabelling reverses the sign of `Π` in the relabelled frame (Euler's equations change sign
//! under a reflection of the axis order).
//!
//! What is exact here is `Π(t)` (equivalently `ω(t)`); of the attitude, `θ` and `ψ` of the 3-1-3
//! angles about the invariable axis follow from `Π` (`Π = L(sin θ sin ψ, sin θ cos ψ, cos θ)`),
//! while `φ` needs the elliptic integral of the third kind and is not provided.

use super::euler::FreeRigidBody;
use crate::error::{all_finite, finite, Error, Result};
use crate::special::elliptic::{complete_k_unchecked, incomplete_f, jacobi_unchecked};
use crate::systems::kepler::orbit::MAX_PHASE_ADVANCE;
use nalgebra::Vector3;

/// The kind of Euler–Poinsot motion.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Regime {
    /// `Π` constant: a steady rotation about a principal axis (or at rest).
    Steady,
    /// `L² > 2EI₂`: `Π` circulates about the axis of the largest moment.
    AboutMajorAxis,
    /// `L² < 2EI₂`: `Π` circulates about the axis of the smallest moment.
    AboutMinorAxis,
    /// `L² = 2EI₂`: on a heteroclinic orbit between the unstable steady rotations about the
    /// intermediate axis.
    Separatrix,
}

/// The Euler–Poinsot motion `Π(t)` through a given `Π(0)` (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EulerPoinsot {
    regime: Regime,
    /// Axis relabelling: sorted axis `j` is original axis `order[j]`.
    order: [usize; 3],
    /// Sign of the relabelling (+1 even, −1 odd).
    parity: f64,
    /// Initial `Π` in the original axes (the steady motion).
    pi0: Vector3<f64>,
    /// Amplitudes `A₁, A₂, A₃` with their signs.
    amplitude: Vector3<f64>,
    lambda: f64,
    k: f64,
    kc: f64,
    u0: f64,
}

impl EulerPoinsot {
    /// The motion of `body` with body angular momentum `pi0` at `t = 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite `Π₀` or an overflowing invariant.
    pub fn new(body: &FreeRigidBody, pi0: &Vector3<f64>) -> Result<Self> {
        all_finite("initial body angular momentum Π₀", pi0.as_slice())?;
        let m = body.moments();
        let mut order = [0usize, 1, 2];
        order.sort_by(|&a, &b| m[a].total_cmp(&m[b]));
        let inversions = (order[0] > order[1]) as u32
            + (order[0] > order[2]) as u32
            + (order[1] > order[2]) as u32;
        let parity = if inversions.is_multiple_of(2) {
            1.0
        } else {
            -1.0
        };
        let (i1, i2, i3) = (m[order[0]], m[order[1]], m[order[2]]);
        let x = Vector3::from_fn(|j, _| parity * pi0[order[j]]);
        // Scale to avoid overflow of the squares.
        let scale = x.amax();
        let steady = |pi0: &Vector3<f64>| Self {
            regime: Regime::Steady,
            order,
            parity,
            pi0: *pi0,
            amplitude: Vector3::zeros(),
            lambda: 0.0,
            k: 0.0,
            kc: 1.0,
            u0: 0.0,
        };
        if scale == 0.0 {
            return Ok(steady(pi0));
        }
        let y = x / scale;
        let (y1, y2, y3) = (y[0] * y[0], y[1] * y[1], y[2] * y[2]);
        let p = y1 * (i3 - i1) / i1 + y2 * (i3 - i2) / i2;
        let q = y2 * (i2 - i1) / i2 + y3 * (i3 - i1) / i3;
        let delta = y3 * (i3 - i2) / i3 - y1 * (i2 - i1) / i1;
        if p == 0.0 || q == 0.0 {
            return Ok(steady(pi0));
        }
        let sign = |v: f64| if v < 0.0 { -1.0 } else { 1.0 };
        let rate = |c: f64| finite("Euler–Poinsot rate λ", scale * c.sqrt());
        if delta > 0.0 {
            let a = Vector3::new(
                (i1 * p / (i3 - i1)).sqrt(),
                (i2 * p / (i3 - i2)).sqrt(),
                (i3 * q / (i3 - i1)).sqrt(),
            );
            let s = sign(y[2]);
            let k = ((i2 - i1) * p / ((i3 - i2) * q)).sqrt().min(1.0);
            let kc = ((i3 - i1) * delta / ((i3 - i2) * q)).sqrt().min(1.0);
            let am = (s * y[1] / a[1]).atan2(y[0] / a[0]);
            Ok(Self {
                regime: Regime::AboutMajorAxis,
                order,
                parity,
                pi0: *pi0,
                amplitude: Vector3::new(a[0], s * a[1], s * a[2]) * scale,
                lambda: rate((i3 - i2) * q / (i1 * i2 * i3))?,
                k,
                kc,
                u0: continuous_f(am, kc)?,
            })
        } else if delta < 0.0 {
            let a = Vector3::new(
                (i1 * p / (i3 - i1)).sqrt(),
                (i2 * q / (i2 - i1)).sqrt(),
                (i3 * q / (i3 - i1)).sqrt(),
            );
            let s = sign(y[0]);
            let k = ((i3 - i2) * q / ((i2 - i1) * p)).sqrt().min(1.0);
            let kc = (-(i3 - i1) * delta / ((i2 - i1) * p)).sqrt().min(1.0);
            let am = (s * y[1] / a[1]).atan2(y[2] / a[2]);
            Ok(Self {
                regime: Regime::AboutMinorAxis,
                order,
                parity,
                pi0: *pi0,
                amplitude: Vector3::new(s * a[0], s * a[1], a[2]) * scale,
                lambda: rate((i2 - i1) * p / (i1 * i2 * i3))?,
                k,
                kc,
                u0: continuous_f(am, kc)?,
            })
        } else {
            if y[0] == 0.0 || y[2] == 0.0 {
                return Ok(steady(pi0));
            }
            let a = Vector3::new(
                (i1 * p / (i3 - i1)).sqrt(),
                (i2 * p / (i3 - i2)).sqrt(),
                (i3 * q / (i3 - i1)).sqrt(),
            );
            let (s1, s3) = (sign(y[0]), sign(y[2]));
            // sinh u₀ = tanh u₀ / sech u₀ = (s₁s₃Π₂/A₂)/(|Π₁|/A₁).
            let u0 = (s1 * s3 * y[1] * a[0] / (a[1] * y[0].abs())).asinh();
            Ok(Self {
                regime: Regime::Separatrix,
                order,
                parity,
                pi0: *pi0,
                amplitude: Vector3::new(s1 * a[0], s1 * s3 * a[1], s3 * a[2]) * scale,
                lambda: rate((i3 - i2) * q / (i1 * i2 * i3))?,
                k: 1.0,
                kc: 0.0,
                u0,
            })
        }
    }

    /// The kind of motion.
    pub fn regime(&self) -> Regime {
        self.regime
    }

    /// The modulus `k` and its complement `k'` of the elliptic functions.
    pub fn modulus(&self) -> (f64, f64) {
        (self.k, self.kc)
    }

    /// The rate `λ` of the argument `u = u₀ + λt`.
    pub fn rate(&self) -> f64 {
        self.lambda
    }

    /// The period `4K(k)/λ` of `Π(t)`.
    ///
    /// # Errors
    /// [`Error::Separatrix`] on the separatrix (infinite period); [`Error::InvalidInput`] for a
    /// steady rotation (no period).
    pub fn period(&self) -> Result<f64> {
        match self.regime {
            Regime::Steady => Err(Error::invalid(
                "Euler–Poinsot period",
                "a steady rotation has no period",
            )),
            Regime::Separatrix => Err(Error::Separatrix {
                what: "Euler–Poinsot period".into(),
                distance: 0.0,
                hint: "L² = 2EI₂: the motion is heteroclinic, its period infinite".into(),
            }),
            _ => finite(
                "Euler–Poinsot period 4K/λ",
                4.0 * complete_k_unchecked(self.kc)? / self.lambda,
            ),
        }
    }

    /// The body angular momentum `Π(t)`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite `t`; [`Error::PhaseLost`] when `|u₀ + λt|` exceeds
    /// [`MAX_PHASE_ADVANCE`] (its rounding then exceeds 10⁻⁶).
    pub fn momentum_at(&self, t: f64) -> Result<Vector3<f64>> {
        let t = finite("time t", t)?;
        if self.regime == Regime::Steady {
            return Ok(self.pi0);
        }
        let u = self.u0 + self.lambda * t;
        let u = finite("elliptic argument u₀ + λt", u)?;
        if u.abs() > MAX_PHASE_ADVANCE && self.regime != Regime::Separatrix {
            // The rounding of u (≈ |u| ε) exceeds 10⁻⁶: the place on the orbit is lost.
            return Err(Error::PhaseLost {
                what: "Euler–Poinsot elliptic argument u₀ + λt".into(),
                phase: u,
                limit: MAX_PHASE_ADVANCE,
            });
        }
        let a = &self.amplitude;
        let sorted = match self.regime {
            Regime::Separatrix => {
                let sech = 1.0 / u.cosh();
                Vector3::new(a[0] * sech, a[1] * u.tanh(), a[2] * sech)
            }
            Regime::AboutMajorAxis => {
                let j = jacobi_unchecked(u, self.k, self.kc)?;
                Vector3::new(a[0] * j.cn, a[1] * j.sn, a[2] * j.dn)
            }
            _ => {
                let j = jacobi_unchecked(u, self.k, self.kc)?;
                Vector3::new(a[0] * j.dn, a[1] * j.sn, a[2] * j.cn)
            }
        };
        let mut pi = Vector3::zeros();
        for j in 0..3 {
            pi[self.order[j]] = self.parity * sorted[j];
        }
        Ok(pi)
    }
}

/// `F(am | k)` for an amplitude `am ∈ [−π, π]`, continued past `±π/2` by
/// `F(π − φ) = 2K − F(φ)` (DLMF 19.2.10).
fn continuous_f(am: f64, kc: f64) -> Result<f64> {
    let (s, c) = am.sin_cos();
    let delta2 = c * c + kc * kc * s * s;
    let f = incomplete_f(s, c * c, delta2)?;
    if c >= 0.0 {
        return Ok(f);
    }
    let k2 = 2.0 * complete_k_unchecked(kc)?;
    Ok(if am > 0.0 { k2 - f } else { -k2 - f })
}

//! The Euler–Poinsot motion: the exact flow of the body angular momentum of a free rigid body in
//! Jacobi elliptic functions, and of its attitude with the elliptic integral of the third kind.
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
//! # The attitude
//! The spatial angular momentum `L = RΠ` (`R` body to space, `Ṙ = R ω̂`, `ω = I⁻¹Π`) is constant.
//! In the *invariable frame*, whose `z`-axis is `L/|L|`, the 3-1-3 angles `(φ, θ, ψ)` of the body
//! ([`super::rotation`]) satisfy `Π = L(sin θ sin ψ, sin θ cos ψ, cos θ)`, so `θ` and `ψ` follow
//! from `Π(t)`; the inverse kinematics `φ̇ = (ω₁ sin ψ + ω₂ cos ψ)/sin θ` give (Landau & Lifshitz
//! §37, eq. 37.15; Whittaker §69)
//!
//! ```math
//! \dot\phi = L\,\frac{\Pi_1^2/I_1 + \Pi_2^2/I_2}{\Pi_1^2 + \Pi_2^2}
//!   = \frac{L}{I_3} + \frac{L\,(2EI_3 - L^2)}{I_3\,(L^2 - \Pi_3^2)} ,
//! ```
//!
//! with `Π₃`, `I₃` those of the body's third axis, whichever of the sorted axes it is. On the
//! elliptic motion `L² − Π₃² = α(1 − n sn²u)` with, by the function of `u` that `Π₃` is,
//! `α = a_dn²`, `n = −a_cn²/a_dn²` (`Π₃ ∝ cn`); `α = a_cn²`, `n = −k²a_dn²/a_cn²` (`Π₃ ∝ dn`);
//! `α = L²`, `n = a_sn²/L²`, `1 − n = k'²a_dn²/L²` (`Π₃ ∝ sn`), where `a_cn, a_sn, a_dn` are the
//! amplitudes of the components that are `cn u`, `sn u`, `dn u`. Then `n < 1`, and since
//! `∫du/(1 − n sn²u) = Π(n; am u | k)`, the incomplete elliptic integral of the third kind,
//!
//! ```math
//! \phi(t) = \phi(0) + \frac{L}{I_3}\,t
//!   + \frac{L\,(2EI_3 - L^2)}{I_3\,\alpha\,\lambda}
//!     \big[\Pi(n; \mathrm{am}\,u \mid k) - \Pi(n; \mathrm{am}\,u_0 \mid k)\big] ,
//! ```
//!
//! (Celledoni, Fassò, Säfström & Zanna, SIAM J. Sci. Comput. 30 (2008) 2084, §2). `Π(n; am u | k)`
//! is evaluated in Carlson's form with `R_F`, `R_J`, after the reduction
//! `Π(n; am(u + 2mK) | k) = Π(n; am u | k) + 2m Π(n | k)`. `2EI₃ − L²` is formed as the sum
//! `Σ_{i≠3} Π_i²(I₃ − I_i)/I_i`. On the separatrix (`k = 1`, `sn = tanh`, `cn = dn = sech`) the
//! integral is elementary: `∫₀^u du/(1 − n tanh²u) = (u + s atan(s tanh u))/(1 − n)`, `s = √(−n)`
//! (`Π₃ ∝ sech`), while `2EI₃ − L² = 0` when the third axis is the intermediate one (`φ̇ = L/I₂`).
//! A steady rotation turns the body about `ω ∥ Π` at the rate `|ω|`: `R(t) = R(0) exp(t ω̂)`.
//!
//! For any initial attitude `R₀` the attitude is `R(t) = R₀ A(0)⁻¹ A(t)`, `A(t)` the attitude in
//! the invariable frame with `φ(0) = 0` ([`EulerPoinsot::attitude_at`]); the canonical flow of
//! [`FreeRigidBody`] in 3-1-3 angles is built on it (its [`ExactFlow`]).

use super::euler::FreeRigidBody;
use super::rotation::{check_chart, euler313_from_quaternion, quaternion_from_euler313};
use crate::error::{all_finite, finite, Error, Result};
use crate::phase::check_phase;
use crate::special::elliptic::{
    complete_k_unchecked, complete_pi, incomplete_f, incomplete_pi, jacobi_unchecked,
};
use crate::systems::kepler::orbit::MAX_PHASE_ADVANCE;
use crate::systems::ExactFlow;
use nalgebra::{SVector, UnitQuaternion, Vector3};
use std::f64::consts::TAU;

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
    /// Principal moments in the original axes.
    moments: Vector3<f64>,
    /// The precession `φ(t) − φ(0)` about the invariable direction (module docs).
    precession: Precession,
}

/// `φ(t) − φ(0) = ν t + κ (G(u₀ + λt) − G(u₀))`, `G(u) = Π(n; am u | k)` (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Precession {
    nu: f64,
    kappa: f64,
    n: f64,
    one_minus_n: f64,
    /// `K(k)` and the complete `Π(n | k)` (regular regimes).
    k_complete: f64,
    pi_complete: f64,
    /// `G(u₀)`.
    g0: f64,
}

impl Precession {
    const NONE: Self = Self {
        nu: 0.0,
        kappa: 0.0,
        n: 0.0,
        one_minus_n: 1.0,
        k_complete: 0.0,
        pi_complete: 0.0,
        g0: 0.0,
    };
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
            moments: *m,
            precession: Precession::NONE,
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
            Self {
                regime: Regime::AboutMajorAxis,
                order,
                parity,
                pi0: *pi0,
                amplitude: Vector3::new(a[0], s * a[1], s * a[2]) * scale,
                lambda: rate((i3 - i2) * q / (i1 * i2 * i3))?,
                k,
                kc,
                u0: continuous_f(am, kc)?,
                moments: *m,
                precession: Precession::NONE,
            }
            .with_precession(&y, scale)
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
            Self {
                regime: Regime::AboutMinorAxis,
                order,
                parity,
                pi0: *pi0,
                amplitude: Vector3::new(s * a[0], s * a[1], a[2]) * scale,
                lambda: rate((i2 - i1) * p / (i1 * i2 * i3))?,
                k,
                kc,
                u0: continuous_f(am, kc)?,
                moments: *m,
                precession: Precession::NONE,
            }
            .with_precession(&y, scale)
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
            Self {
                regime: Regime::Separatrix,
                order,
                parity,
                pi0: *pi0,
                amplitude: Vector3::new(s1 * a[0], s1 * s3 * a[1], s3 * a[2]) * scale,
                lambda: rate((i3 - i2) * q / (i1 * i2 * i3))?,
                k: 1.0,
                kc: 0.0,
                u0,
                moments: *m,
                precession: Precession::NONE,
            }
            .with_precession(&y, scale)
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
        let u = self.argument(t)?;
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

impl EulerPoinsot {
    /// `u₀ + λt`, refused when its rounding exceeds 10⁻⁶.
    fn argument(&self, t: f64) -> Result<f64> {
        let u = finite("elliptic argument u₀ + λt", self.u0 + self.lambda * t)?;
        if u.abs() > MAX_PHASE_ADVANCE && self.regime != Regime::Separatrix {
            // The rounding of u (≈ |u| ε) exceeds 10⁻⁶: the place on the orbit is lost.
            return Err(Error::PhaseLost {
                what: "Euler–Poinsot elliptic argument u₀ + λt".into(),
                phase: u,
                limit: MAX_PHASE_ADVANCE,
            });
        }
        Ok(u)
    }

    /// The constants of the precession (module docs) from the sorted, scaled `y = Π₀/scale`.
    fn with_precession(mut self, y: &Vector3<f64>, scale: f64) -> Result<Self> {
        let ms = Vector3::from_fn(|j, _| self.moments[self.order[j]]);
        // Sorted index of the body's third axis, the spin axis of the 3-1-3 chart.
        let j = (0..3).find(|&j| self.order[j] == 2).unwrap_or(2);
        let a = self.amplitude.abs() / scale;
        let (icn, idn) = if self.regime == Regime::AboutMinorAxis {
            (2, 0)
        } else {
            (0, 2)
        };
        let (ac2, ad2, as2) = (a[icn] * a[icn], a[idn] * a[idn], a[1] * a[1]);
        let k2 = self.k * self.k;
        let (alpha, n, one_minus_n) = if j == 1 {
            let alpha = ac2 + ad2;
            (alpha, as2 / alpha, ad2 * self.kc * self.kc / alpha)
        } else if j == icn {
            (ad2, -ac2 / ad2, (ad2 + ac2) / ad2)
        } else {
            (ac2, -k2 * ad2 / ac2, (ac2 + k2 * ad2) / ac2)
        };
        // 2EI₃ − L² as a sum of terms of known sign.
        let c3: f64 = (0..3)
            .filter(|&i| i != j)
            .map(|i| y[i] * y[i] * (ms[j] - ms[i]) / ms[i])
            .sum();
        let ell = y.norm();
        let nu = finite("mean precession rate L/I₃", scale * ell / ms[j])?;
        let kappa = if self.regime == Regime::Separatrix && j == 1 {
            0.0
        } else {
            finite(
                "precession coefficient L(2EI₃ − L²)/(I₃αλ)",
                ell * c3 / (ms[j] * alpha * (self.lambda / scale)),
            )?
        };
        self.precession = Precession {
            nu,
            kappa,
            n,
            one_minus_n,
            ..Precession::NONE
        };
        if kappa != 0.0 {
            if self.regime != Regime::Separatrix {
                let kk = complete_k_unchecked(self.kc)?;
                self.precession.k_complete = kk;
                self.precession.pi_complete = complete_pi(n, one_minus_n, kk, self.kc)?;
            }
            self.precession.g0 = self.g(self.u0)?;
        }
        Ok(self)
    }

    /// `G(u) = ∫₀^u du/(1 − n sn²u) = Π(n; am u | k)`, continued over the periods of `am`.
    fn g(&self, u: f64) -> Result<f64> {
        let p = &self.precession;
        if self.regime == Regime::Separatrix {
            let s = (-p.n).max(0.0).sqrt();
            return Ok((u + s * (s * u.tanh()).atan()) / p.one_minus_n);
        }
        let half_period = 2.0 * p.k_complete;
        let m = (u / half_period).round();
        let r = u - m * half_period;
        let j = jacobi_unchecked(r, self.k, self.kc)?;
        let pi = incomplete_pi(p.n, p.one_minus_n, j.sn, j.cn * j.cn, j.dn * j.dn)?;
        Ok(2.0 * m * p.pi_complete + pi)
    }

    /// The precession angle `φ(t) − φ(0)` of the body's third axis about the invariable direction
    /// `L/|L|` (module docs); for a steady rotation `|ω| t`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite `t` or an overflowing angle;
    /// [`Error::PhaseLost`] as [`EulerPoinsot::momentum_at`]; [`Error::Singular`] for a steady
    /// rotation about the body's third axis, where the 3-1-3 chart about `L` is singular and only
    /// `φ + ψ` is defined.
    pub fn precession_at(&self, t: f64) -> Result<f64> {
        let t = finite("time t", t)?;
        if self.regime == Regime::Steady {
            if self.pi0 == Vector3::zeros() {
                return Ok(0.0);
            }
            if self.pi0[0] == 0.0 && self.pi0[1] == 0.0 {
                check_chart(0.0)?;
            }
            let w = self.pi0.component_div(&self.moments);
            return finite("precession angle |ω| t", w.norm() * t);
        }
        let u = self.argument(t)?;
        let p = &self.precession;
        let mean = finite("mean precession L t/I₃", p.nu * t)?;
        if p.kappa == 0.0 {
            return Ok(mean);
        }
        finite(
            "precession angle φ(t) − φ(0)",
            mean + p.kappa * (self.g(u)? - p.g0),
        )
    }

    /// The attitude (body to space) at time `t` of the body whose attitude at `t = 0` is `r0`:
    /// `R(t) = R₀ A(0)⁻¹ A(t)` with `A(t) = R_z(φ(t) − φ(0)) R_x(θ(t)) R_z(ψ(t))` the attitude in
    /// the invariable frame (module docs), or `R₀ exp(t ω̂)` for a steady rotation.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite `r0`, `t` or angle; [`Error::PhaseLost`] when the
    /// elliptic argument, or the angle `|ω|t` of a steady rotation, exceeds
    /// [`MAX_PHASE_ADVANCE`].
    pub fn attitude_at(&self, r0: &UnitQuaternion<f64>, t: f64) -> Result<UnitQuaternion<f64>> {
        all_finite("initial attitude quaternion", r0.as_vector().as_slice())?;
        let t = finite("time t", t)?;
        if self.regime == Regime::Steady {
            let w = self.pi0.component_div(&self.moments);
            let angle = w * t;
            all_finite(
                "rotation angle ω t of the steady rotation",
                angle.as_slice(),
            )?;
            let size = angle.norm();
            if size > MAX_PHASE_ADVANCE {
                return Err(Error::PhaseLost {
                    what: "steady rotation angle |ω| t".into(),
                    phase: size,
                    limit: MAX_PHASE_ADVANCE,
                });
            }
            return Ok(r0 * UnitQuaternion::from_scaled_axis(angle));
        }
        let phi = self.precession_at(t)?;
        let pi = self.momentum_at(t)?;
        let start = invariable_attitude(0.0, &self.pi0)?;
        let now = invariable_attitude(phi, &pi)?;
        Ok(r0 * start.inverse() * now)
    }
}

/// `R_z(φ) R_x(θ) R_z(ψ)` with `Π = |Π|(sin θ sin ψ, sin θ cos ψ, cos θ)`.
fn invariable_attitude(phi: f64, pi: &Vector3<f64>) -> Result<UnitQuaternion<f64>> {
    let theta = pi[0].hypot(pi[1]).atan2(pi[2]);
    let psi = pi[0].atan2(pi[1]);
    quaternion_from_euler313(&Vector3::new(phi, theta, psi))
}

/// The free rigid body's exact flow in 3-1-3 angles and their momenta: `Π₀ = B⁻ᵀ(θ₀, ψ₀) p₀`,
/// the attitude `R(t)` of [`EulerPoinsot::attitude_at`] from `R(q₀)`, `q(t)` its 3-1-3 angles
/// (`θ ∈ (0, π)`; `φ`, `ψ` the representatives nearest `φ₀`, `ψ₀`, which continue them
/// continuously over a step in which they change by less than `π`), `p(t) = Bᵀ(θ, ψ) Π(t)`.
///
/// # Errors
/// [`Error::Singular`] when the initial or the final attitude lies on the chart singularity
/// `sin θ = 0` (SPEC X9, [`check_chart`]); otherwise as [`EulerPoinsot::attitude_at`].
impl ExactFlow<3> for FreeRigidBody {
    fn exact_flow(
        &self,
        t0: f64,
        q0: &SVector<f64, 3>,
        p0: &SVector<f64, 3>,
        t: f64,
    ) -> Result<(SVector<f64, 3>, SVector<f64, 3>)> {
        check_phase(t0, q0, p0)?;
        let dt = finite("time step t − t₀", finite("time t", t)? - t0)?;
        for i in 0..3 {
            if q0[i].abs() > MAX_PHASE_ADVANCE {
                // The angle's rounding exceeds 10⁻⁶: its place on the circle is lost.
                return Err(Error::PhaseLost {
                    what: "3-1-3 angle of the initial state".into(),
                    phase: q0[i],
                    limit: MAX_PHASE_ADVANCE,
                });
            }
        }
        let pi0 = FreeRigidBody::body_momentum(q0, p0)?;
        let flow = EulerPoinsot::new(self, &pi0)?;
        let r0 = quaternion_from_euler313(q0)?;
        let r = flow.attitude_at(&r0, dt)?;
        let pi = flow.momentum_at(dt)?;
        let mut q = euler313_from_quaternion(&r)?;
        for i in [0, 2] {
            q[i] += TAU * ((q0[i] - q[i]) / TAU).round();
        }
        let p = FreeRigidBody::momenta(&q, &pi)?;
        Ok((q, p))
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

//! The heavy symmetric top reduced to its cubic and solved by Hamilton–Jacobi quadratures
//! [Ardema 11.2, eqs. 11.17–11.26; 17.5, eq. 17.45].
//!
//! With `u = cos θ` and the constants `h` (energy), `p₁ = p_φ`, `p₂ = p_ψ` of a [`HeavyTop`], the
//! energy integral becomes `u̇² = f(u)` with the cubic [Ardema eq. 11.19]
//!
//! ```math
//! f(u) = (1 - u^2)(\alpha - \beta u) - (\delta - \gamma u)^2
//!     = \beta u^3 - (\alpha + \gamma^2) u^2 + (2\delta\gamma - \beta) u + (\alpha - \delta^2),
//! ```
//!
//! `α = (2h − p₂²/J)/I`, `β = 2mgℓ/I`, `γ = p₂/I`, `δ = p₁/I`. Since `f(±1) = −(δ ∓ γ)² ≤ 0` and
//! `f → +∞`, the motion librates between two roots `u₁ ≤ u ≤ u₂` in `[−1, 1]` and the third root
//! is `u₃ ≥ 1`, so that `f = β(u − u₁)(u₂ − u)(u₃ − u)` and the reduced radicand of the
//! turning-point quadrature ([`Libration`]) is exactly `P(u) = β(u₃ − u)`.
//!
//! The Hamilton–Jacobi solution (`K = α₂φ + α₃ψ + ∫√F dθ`, `F = p_θ² = I² f/(1 − u²)`)
//! gives the motion by quadratures, written in `u` (`I dθ/√F = −du/√f`):
//!
//! ```math
//! t = \int \frac{du}{\sqrt f},\qquad
//! \phi = \int \frac{\delta - \gamma u}{1 - u^2}\frac{du}{\sqrt f},\qquad
//! \psi = \frac{p_2}{J} t - \int \frac{u(\delta - \gamma u)}{1 - u^2}\frac{du}{\sqrt f},
//! ```
//!
//! i.e. `φ̇ = (δ − γu)/(1 − u²)` and `ψ̇ = p₂/J − u φ̇` [Ardema eq. 11.16]; the nutation period is
//! `2∫_{u₁}^{u₂} du/√f`, equal to the elliptic form `4K(m)/√(β(u₃ − u₁))`,
//! `m = (u₂ − u₁)/(u₃ − u₁)`.
//!
//! # Numerics
//! * **Local expansion.** The cubic is kept as a Taylor polynomial `f = f₀ + f₁x + f₂x² + βx³` in
//!   `x = u − u₀` about a reference point `u₀` (the initial state, or the maximum of `f` for given
//!   constants). From a state, `f₀ = sin²θ₀ θ̇₀²`, `δ − γu₀ = (p₁ − p₂ cos θ₀)/I` and
//!   `α − βu₀ = θ̇₀² + (δ − γu₀)²/sin²θ₀` come directly from the momenta, never from `h − p₂²/2J`,
//!   which cancels catastrophically for fast tops. The roots are found as offsets `x₁ ≤ 0 ≤ x₂`
//!   (bracketed by the exact end values `f(±1)` and refined by safeguarded Newton), the third by
//!   the product of the roots, `x₃ = −f₀/(β x₁ x₂)` (no cancellation), and the quadratures run in
//!   the local variable, so the nutation width `u₂ − u₁` keeps full relative precision even at
//!   `γ = 10⁴`, where it is `1.5·10⁻⁸`. `1 ∓ u` are carried as `2 sin²(θ₀/2) ∓ x` and
//!   `2 cos²(θ₀/2) ± x` so that near-vertical tops keep their precession rate.
//! * **Degenerate cases.** A double root `u₁ = u₂` (steady precession) gives the finite
//!   small-oscillation limits of the [`Libration`] (`P` is exact there). A turning point at a pole
//!   (`δ = ±γ` with the orbit reaching `θ = 0` or `π`) is refused with [`Error::Singular`] (the
//!   Euler-angle chart fails there). A double or triple root at the pole `u = 1` — the
//!   sleeping top at or below the critical spin `ω_c = 2√(I mgℓ)/J`, where
//!   `f = (1 − u)²[β(1 + u) − γ²]` — is a separatrix ([`Error::Separatrix`]); above the critical
//!   spin the sleeping top is the pole itself ([`Error::Singular`]).

use super::HeavyTop;
use crate::error::{finite, Error, Result};
use crate::special::turning_points::{Libration, Node, Quadrature, ReducedRadicand};
use nalgebra::SVector;
use std::f64::consts::PI;

/// Iteration cap of the root refinement and of the inversion of the time law (both converge in a
/// few dozen steps: bisection halves the bracket, Newton then converges quadratically).
const MAX_ITER: usize = 200;

/// The top's cubic `f(u)` [Ardema eq. 11.19] with its three roots `u₁ ≤ u₂ ≤ 1 ≤ u₃` (see the
/// [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TopCubic {
    alpha: f64,
    beta: f64,
    gamma: f64,
    delta: f64,
    /// Reference point `u₀` and `1 − u₀`, `1 + u₀` (exact).
    u0: f64,
    one_minus: f64,
    one_plus: f64,
    /// `δ − γ u₀`.
    w: f64,
    /// Local Taylor coefficients `f₀, f₁, f₂` (`f₃ = β`).
    local: [f64; 3],
    /// Roots as offsets from `u₀`.
    x: [f64; 3],
}

impl TopCubic {
    /// The cubic of the motion through the state `(q, p)` (Euler angles `(φ, θ, ψ)` and their
    /// momenta), expanded about `u₀ = cos θ` (see the [module docs](self)).
    ///
    /// Errors: non-finite input, `sin θ = 0` ([`Error::Singular`]), an orbit that reaches
    /// a pole ([`Error::Singular`]).
    pub fn from_state(top: &HeavyTop, q: &SVector<f64, 3>, p: &SVector<f64, 3>) -> Result<Self> {
        crate::phase::check_phase(0.0, q, p)?;
        let s = super::check_chart(q[1])?;
        let i = top.i();
        let (sh, ch) = (0.5 * q[1]).sin_cos();
        let (u0, one_minus, one_plus) = (q[1].cos(), 2.0 * sh * sh, 2.0 * ch * ch);
        let (beta, gamma, delta) = (top.beta(), p[2] / i, p[0] / i);
        let w = (p[0] - p[2] * u0) / i;
        let theta_dot = p[1] / i;
        let s2 = s * s;
        // α − βu₀ = θ̇² + (δ − γu₀)²/sin²θ ≥ 0.
        let a = theta_dot * theta_dot + w * w / s2;
        let local = [
            s2 * theta_dot * theta_dot,
            -2.0 * u0 * a - beta * s2 + 2.0 * gamma * w,
            // 2βu₀ − γ² = (2β − γ²) − 2β(1 − u₀): no cancellation near the critical spin.
            -a + (2.0 * beta - gamma * gamma) - 2.0 * beta * one_minus,
        ];
        let c = Self {
            alpha: a + beta * u0,
            beta,
            gamma,
            delta,
            u0,
            one_minus,
            one_plus,
            w,
            local,
            x: [0.0; 3],
        };
        c.check_finite()?;
        c.with_roots()
    }

    /// The cubic for the constants `h` (energy), `p₁ = p_φ`, `p₂ = p_ψ` [Ardema eq. 11.19],
    /// expanded about the maximum of `f` in `[−1, 1]`.
    ///
    /// The constants of a fast top lose digits in `α = (2h − p₂²/J)/I`; prefer
    /// [`TopCubic::from_state`] when a state is known. Errors: constants that admit no motion
    /// (`f < 0` on `[−1, 1]`, [`Error::OutOfDomain`]); the sleeping top at or below the critical
    /// spin, whose cubic has a double or triple root at `u = 1` ([`Error::Separatrix`]); the
    /// sleeping top above it and orbits through a pole ([`Error::Singular`]).
    pub fn from_constants(top: &HeavyTop, h: f64, p1: f64, p2: f64) -> Result<Self> {
        let (h, p1, p2) = (finite("h", h)?, finite("p_φ", p1)?, finite("p_ψ", p2)?);
        let (i, j) = (top.i(), top.j());
        let (beta, gamma, delta) = (top.beta(), p2 / i, p1 / i);
        let alpha = (2.0 * h - p2 * p2 / j) / i;
        let (b2, b1, b0) = (
            alpha + gamma * gamma,
            2.0 * delta * gamma - beta,
            alpha - delta * delta,
        );
        let f = |u: f64| ((beta * u - b2) * u + b1) * u + b0;
        let scale = beta.abs() + b2.abs() + b1.abs() + b0.abs();
        let tol = 16.0 * f64::EPSILON * scale;
        // Local maximum of f: the smaller root of f′ = 3βu² − 2b₂u + b₁ (β > 0).
        let disc = b2 * b2 - 3.0 * beta * b1;
        let um = if disc >= 0.0 {
            let q = b2 + disc.sqrt().copysign(b2);
            let (r1, r2) = (q / (3.0 * beta), if q != 0.0 { b1 / q } else { 0.0 });
            r1.min(r2)
        } else {
            1.0
        };
        let um = um.clamp(-1.0, 1.0);
        let fm = f(um);
        let at_pole = || Error::Singular {
            what: "3-1-3 Euler-angle chart".into(),
            at: format!(
                "the pole: the vertical top (h = {h}, p_φ = {p1}, p_ψ = {p2}) stays there; \
                 sin θ = 0, where precession and spin share one axis"
            ),
            rcond: 0.0,
        };
        // The vertical top: f has a double root at u = 1 iff δ = γ and α = β (f(1) = f′(1) = 0),
        // a triple one if moreover γ² = 2β; likewise at u = −1 iff δ = −γ and α = −β.
        if delta == gamma && alpha == beta {
            return Err(if gamma * gamma > 2.0 * beta {
                at_pole()
            } else {
                sleeping_separatrix(top, p2)
            });
        }
        if delta == -gamma && alpha == -beta {
            return Err(at_pole());
        }
        if fm < -tol {
            return Err(Error::out_of_domain(
                "energy h",
                h,
                format!("h with f(u) ≥ 0 somewhere in [−1, 1] (max f = {fm:e} at u = {um})"),
            ));
        }
        let mut c = Self {
            alpha,
            beta,
            gamma,
            delta,
            u0: um,
            one_minus: 1.0 - um,
            one_plus: 1.0 + um,
            w: delta - gamma * um,
            local: [
                fm.max(0.0),
                (3.0 * beta * um - 2.0 * b2) * um + b1,
                3.0 * beta * um - b2,
            ],
            x: [0.0; 3],
        };
        c.check_finite()?;
        if fm <= tol {
            // Double root at the maximum: steady precession, or the sleeping top at the pole.
            c.local[0] = 0.0;
            c.local[1] = 0.0;
            let x3 = -c.local[2] / beta;
            if c.one_minus.min(c.one_plus) <= 8.0 * f64::EPSILON {
                if x3 <= 8.0 * f64::EPSILON {
                    return Err(sleeping_separatrix(top, p2));
                }
                return Err(at_pole());
            }
            c.x = [0.0, 0.0, x3];
            return Ok(c);
        }
        c.with_roots()
    }

    fn check_finite(&self) -> Result<()> {
        crate::error::all_finite(
            "cubic coefficients",
            &[self.alpha, self.gamma, self.delta, self.w],
        )?;
        crate::error::all_finite("local cubic coefficients", &self.local)
    }

    /// `g(x) = f(u₀ + x)` and `g′(x)`.
    fn local_eval(&self, x: f64) -> (f64, f64) {
        let [f0, f1, f2] = self.local;
        let b = self.beta;
        (
            ((b * x + f2) * x + f1) * x + f0,
            (3.0 * b * x + 2.0 * f2) * x + f1,
        )
    }

    /// Locate the roots as offsets from `u₀` (local coefficients set, `f₀ ≥ 0`).
    fn with_roots(mut self) -> Result<Self> {
        let [f0, f1, f2] = self.local;
        let b = self.beta;
        let (hi, lo) = (self.one_minus, -self.one_plus);
        // f(1) = 0 exactly when δ = γ; the pole u = 1 is then the upper turning point unless
        // f′(1) = −2(α − β) > 0 (then it is the third root). f(−1) = 0 when δ = −γ, and then
        // f′(−1) = 2(α + β) > 0 always: u = −1 is the lower turning point.
        let through_top = self.delta == self.gamma && self.alpha >= self.beta;
        if through_top || self.delta == -self.gamma {
            return Err(self.pole_error(if through_top { "θ = 0" } else { "θ = π" }));
        }
        let x = if f0 > 0.0 {
            let g = |x: f64| self.local_eval(x);
            // f(1) = −(δ − γ)², f(−1) = −(δ + γ)² ≤ 0 bracket the roots exactly.
            let x2 = refine(g, 0.0, hi)?;
            let x1 = refine(g, 0.0, lo)?;
            [x1, x2, -f0 / (b * x1 * x2)]
        } else if f1 == 0.0 {
            [0.0, 0.0, -f2 / b]
        } else {
            // u₀ is a turning point: the other two roots solve βx² + f₂x + f₁ = 0.
            let disc = f2 * f2 - 4.0 * b * f1;
            if disc < 0.0 {
                return Err(Error::NotConverged {
                    what: "top cubic: second turning point (negative discriminant)".into(),
                    iterations: 0,
                    residual: disc,
                });
            }
            let q = -0.5 * (f2 + disc.sqrt().copysign(f2));
            let (ra, rb) = (q / b, f1 / q);
            let (small, large) = if ra.abs() < rb.abs() {
                (ra, rb)
            } else {
                (rb, ra)
            };
            if f1 < 0.0 {
                [small.min(large), 0.0, small.max(large)]
            } else {
                [0.0, small, large]
            }
        };
        crate::error::all_finite("roots of the top cubic", &x)?;
        if x[1] >= hi || x[0] <= lo {
            return Err(self.pole_error(if x[1] >= hi { "θ = 0" } else { "θ = π" }));
        }
        if !(x[0] <= x[1] && x[1] <= x[2]) {
            return Err(Error::invalid(
                "top cubic",
                format!("roots out of order: {x:?} (offsets from u₀ = {})", self.u0),
            ));
        }
        self.x = x;
        Ok(self)
    }

    fn pole_error(&self, pole: &str) -> Error {
        Error::Singular {
            what: "3-1-3 Euler-angle chart along the motion".into(),
            at: format!(
                "the orbit reaches the pole {pole} (f(±1) = −(δ ∓ γ)² = 0 with δ = {}, γ = {}); \
                 sin θ = 0 there: precession and spin share one axis",
                self.delta, self.gamma
            ),
            rcond: 0.0,
        }
    }

    /// `α = (2h − p₂²/J)/I`.
    pub fn alpha(&self) -> f64 {
        self.alpha
    }
    /// `β = 2mgℓ/I`.
    pub fn beta(&self) -> f64 {
        self.beta
    }
    /// `γ = p₂/I`.
    pub fn gamma(&self) -> f64 {
        self.gamma
    }
    /// `δ = p₁/I`.
    pub fn delta(&self) -> f64 {
        self.delta
    }
    /// Coefficients `[β, −(α + γ²), 2δγ − β, α − δ²]` of `u³, u², u, 1`.
    pub fn coefficients(&self) -> [f64; 4] {
        let (a, b, g, d) = (self.alpha, self.beta, self.gamma, self.delta);
        [b, -(a + g * g), 2.0 * d * g - b, a - d * d]
    }
    /// `f(u)`, evaluated from the expansion about the reference point.
    pub fn eval(&self, u: f64) -> f64 {
        self.local_eval(u - self.u0).0
    }
    /// The reference point `u₀` of the expansion.
    pub fn reference(&self) -> f64 {
        self.u0
    }
    /// The roots `[u₁, u₂, u₃]`, `−1 < u₁ ≤ u₂ < 1 ≤ u₃`.
    pub fn roots(&self) -> [f64; 3] {
        self.x.map(|x| self.u0 + x)
    }
    /// The turning points as offsets `[u₁ − u₀, u₂ − u₀, u₃ − u₀]` from the reference point,
    /// each to full relative precision.
    pub fn root_offsets(&self) -> [f64; 3] {
        self.x
    }
    /// The nutation width `u₂ − u₁` (full relative precision).
    pub fn nutation_width(&self) -> f64 {
        self.x[1] - self.x[0]
    }
    /// The nutation range `[θ_min, θ_max] = [acos u₂, acos u₁]`.
    pub fn theta_range(&self) -> [f64; 2] {
        [self.theta_of(self.x[1]), self.theta_of(self.x[0])]
    }
    /// `θ ∈ [0, π]` of the point `x = u − u₀`, from `1 − u = 2 sin²(θ/2)` (accurate near the poles).
    fn theta_of(&self, x: f64) -> f64 {
        let om = (self.one_minus - x).max(0.0);
        if om <= 1.0 {
            2.0 * (0.5 * om).sqrt().asin()
        } else {
            2.0 * (0.5 * (self.one_plus + x).max(0.0)).sqrt().acos()
        }
    }
    /// Precession rate `φ̇ = (δ − γu)/(1 − u²)` at `x = u − u₀` [Ardema eq. 11.16].
    fn precession_rate_local(&self, x: f64) -> f64 {
        (self.w - self.gamma * x) / ((self.one_minus - x) * (self.one_plus + x))
    }
    /// Precession rate `φ̇ = (δ − γu)/(1 − u²)` at `u = cos θ` [Ardema eq. 11.16].
    pub fn precession_rate(&self, u: f64) -> Result<f64> {
        let u = finite("u", u)?;
        finite("φ̇", self.precession_rate_local(u - self.u0))
    }
}

fn sleeping_separatrix(top: &HeavyTop, p2: f64) -> Error {
    let omega = p2 / top.j();
    Error::Separatrix {
        what: format!(
            "sleeping top at spin ω_z = {omega} (critical spin {}): f has a double or triple \
             root at u = 1",
            top.critical_spin()
                .map_or_else(|_| "overflows".into(), crate::error::fmt_num)
        ),
        distance: 0.0,
        hint: "at or below the critical spin the vertical is unstable and the motion with these \
               constants is asymptotic to it (the time to reach it diverges); start from a state \
               with θ > 0 instead (TopCubic::from_state)"
            .into(),
    }
}

/// The root of `g` between `a` (where `g > 0`) and `b` (where `g ≤ 0`), by safeguarded Newton
/// with bisection (Press et al., *Numerical Recipes*, `rtsafe`), to a relative precision of a few
/// ulps in the root.
fn refine(g: impl Fn(f64) -> (f64, f64), a: f64, b: f64) -> Result<f64> {
    // Orientation: g(xl) ≤ 0 < g(xh).
    let (mut xl, mut xh) = (b, a);
    let mut x = 0.5 * (a + b);
    let (mut dx_old, mut dx) = ((b - a).abs(), (b - a).abs());
    let (mut v, mut d) = g(x);
    for _ in 0..MAX_ITER {
        if v == 0.0 {
            return Ok(x);
        }
        let newton_out = ((x - xh) * d - v) * ((x - xl) * d - v) > 0.0;
        if newton_out || (2.0 * v).abs() > (dx_old * d).abs() || !d.is_finite() {
            dx_old = dx;
            dx = 0.5 * (xh - xl);
            x = xl + dx;
        } else {
            dx_old = dx;
            dx = v / d;
            x -= dx;
        }
        if dx.abs() <= 2.0 * f64::EPSILON * x.abs() || xl == xh {
            return Ok(x);
        }
        (v, d) = g(x);
        if v.is_nan() {
            break;
        }
        if v <= 0.0 {
            xl = x;
        } else {
            xh = x;
        }
    }
    Err(Error::NotConverged {
        what: "root of the top cubic".into(),
        iterations: MAX_ITER,
        residual: (xh - xl).abs(),
    })
}

/// The lower turning point of a top released from rest at `u₂ = cos θ₂` (`θ̇ = φ̇ = 0`) with spin
/// `ω_z` [Ardema eq. 11.24], in a cancellation-free form:
///
/// ```math
/// u_1 = \frac{2 c u_2 - 1}{c + \sqrt{(c - u_2)^2 + 1 - u_2^2}},\qquad c = \frac{\gamma^2}{2\beta}
/// ```
///
/// (the textbook form `c − √(1 − 2cu₂ + c²)` loses `log₁₀ c²` digits: at `γ = 10⁴` it is off by
/// 1e−10 in a nutation width of 1.5e−8).
pub fn release_from_rest(top: &HeavyTop, u2: f64, omega_z: f64) -> Result<f64> {
    let u2 = finite("u₂", u2)?;
    if !(-1.0..=1.0).contains(&u2) {
        return Err(Error::out_of_domain("u₂ = cos θ₂", u2, "[−1, 1]"));
    }
    let gamma = top.gamma(omega_z)?;
    let c = gamma * gamma / (2.0 * top.beta());
    let root = ((c - u2) * (c - u2) + (1.0 - u2) * (1.0 + u2)).sqrt();
    finite("u₁", (2.0 * c * u2 - 1.0) / (c + root))
}

/// The fast-top estimate of the nutation width after release from rest at `u₂`,
/// `u₂ − u₁ ≈ β(1 − u₂²)/γ²` [Ardema eq. 11.25].
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ arguments or a width that overflows (spin too slow for the
/// fast-top estimate to mean anything); [`Error::OutOfDomain`] for `u₂ = cos θ₂ ∉ [−1, 1]` or
/// zero spin.
pub fn fast_top_width(top: &HeavyTop, u2: f64, omega_z: f64) -> Result<f64> {
    let u2 = finite("u₂", u2)?;
    if !(-1.0..=1.0).contains(&u2) {
        return Err(Error::out_of_domain("u₂ = cos θ₂", u2, "[−1, 1]"));
    }
    let gamma = top.gamma(omega_z)?;
    if gamma == 0.0 {
        return Err(Error::out_of_domain("spin ω_z", omega_z, "ω_z ≠ 0"));
    }
    // Divided by γ twice: γ² alone overflows for |γ| > 1.3e154 where the width is still normal.
    finite(
        "fast-top nutation width",
        top.beta() * (1.0 - u2) * (1.0 + u2) / gamma / gamma,
    )
}

/// The exact reduced radicand `P = β(u₃ − u) = β((u₃ − u₂) + d₂)` of the top's libration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TopRadicand {
    beta: f64,
    gap: f64,
}

impl ReducedRadicand for TopRadicand {
    fn reduced(&self, _x: f64, _d1: f64, d2: f64) -> f64 {
        self.beta * (self.gap + d2)
    }
}

/// Time and angle advances from the lower turning point `u₁` to a point of the libration.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Advance {
    /// `t = ∫_{u₁}^{u} du/√f`.
    pub time: Quadrature,
    /// `Δφ = ∫_{u₁}^{u} φ̇ du/√f`.
    pub precession: Quadrature,
    /// `Δψ = ∫_{u₁}^{u} ψ̇ du/√f`.
    pub spin: Quadrature,
}

/// The nutation of a heavy top solved by Hamilton–Jacobi quadratures [Ardema 17.5] over the
/// turning-point engine [`Libration`] in the local variable `x = u − u₀`, with the exact reduced
/// radicand [`TopRadicand`]. See the [module docs](self).
#[derive(Clone, Debug)]
pub struct Nutation {
    top: HeavyTop,
    cubic: TopCubic,
    libration: Libration<TopRadicand>,
    /// `p₂/J = ω_z`.
    spin_rate: f64,
}

impl Nutation {
    /// The nutation through the state `(q, p)`; errors as [`TopCubic::from_state`].
    pub fn from_state(top: &HeavyTop, q: &SVector<f64, 3>, p: &SVector<f64, 3>) -> Result<Self> {
        Self::new(top, TopCubic::from_state(top, q, p)?)
    }

    /// The nutation with constants `h`, `p_φ`, `p_ψ`; errors as [`TopCubic::from_constants`].
    pub fn from_constants(top: &HeavyTop, h: f64, p1: f64, p2: f64) -> Result<Self> {
        Self::new(top, TopCubic::from_constants(top, h, p1, p2)?)
    }

    fn new(top: &HeavyTop, cubic: TopCubic) -> Result<Self> {
        let [x1, x2, x3] = cubic.x;
        let reduced = TopRadicand {
            beta: cubic.beta,
            gap: x3 - x2,
        };
        if reduced.gap <= 64.0 * f64::EPSILON * (x3 - x1) {
            return Err(Error::Separatrix {
                what: "heavy top: the upper turning point meets the third root of the cubic".into(),
                distance: reduced.gap,
                hint: "the motion is asymptotic to the vertical (sleeping top at or below the \
                       critical spin); its period diverges"
                    .into(),
            });
        }
        Ok(Self {
            top: *top,
            libration: Libration::new(x1, x2, reduced)?,
            spin_rate: cubic.gamma * top.i() / top.j(),
            cubic,
        })
    }

    /// The cubic.
    pub fn cubic(&self) -> &TopCubic {
        &self.cubic
    }
    /// The turning-point quadrature in `x = u − u₀`.
    pub fn libration(&self) -> &Libration<TopRadicand> {
        &self.libration
    }

    fn phi_rate(&self, n: &Node) -> f64 {
        self.cubic.precession_rate_local(n.x)
    }
    fn psi_rate(&self, n: &Node) -> f64 {
        self.spin_rate - (self.cubic.u0 + n.x) * self.phi_rate(n)
    }

    /// The nutation period `T = 2∫_{u₁}^{u₂} du/√f` [Ardema 11.2]; for `u₁ = u₂` the
    /// small-oscillation limit `2π/√(β(u₃ − u₁))`.
    pub fn period(&self) -> Result<Quadrature> {
        Ok(self.libration.inverse_sqrt_integral(|_| 1.0)?.scale(2.0))
    }

    /// Precession advance per nutation period, `Δφ = 2∫ (δ − γu)/(1 − u²) du/√f` [Ardema 17.5].
    pub fn precession_per_period(&self) -> Result<Quadrature> {
        let q = self
            .libration
            .integrate_full(|n| self.phi_rate(n) / n.reduced.sqrt())?;
        Ok(q.scale(2.0))
    }

    /// Spin advance per nutation period, `Δψ = 2∫ [p₂/J − u(δ − γu)/(1 − u²)] du/√f` [Ardema 17.5].
    pub fn spin_per_period(&self) -> Result<Quadrature> {
        let q = self
            .libration
            .integrate_full(|n| self.psi_rate(n) / n.reduced.sqrt())?;
        Ok(q.scale(2.0))
    }

    /// Time and angle advances from `u₁` up to the point with substitution variable
    /// `s ∈ [0, π]` (`u = u₁ + (u₂ − u₁) sin²(s/2)`).
    pub fn advance_at_phase(&self, s: f64) -> Result<Advance> {
        let lib = &self.libration;
        Ok(Advance {
            time: lib.integrate_between(|n| 1.0 / n.reduced.sqrt(), 0.0, s)?,
            precession: lib.integrate_between(|n| self.phi_rate(n) / n.reduced.sqrt(), 0.0, s)?,
            spin: lib.integrate_between(|n| self.psi_rate(n) / n.reduced.sqrt(), 0.0, s)?,
        })
    }

    /// Time and angle advances from `u₁` up to `u = cos θ ∈ [u₁, u₂]` (partial quadratures).
    pub fn advance_to(&self, u: f64) -> Result<Advance> {
        let x = finite("u", u)? - self.cubic.u0;
        self.advance_at_phase(self.libration.phase(x)?)
    }

    /// The substitution variable `s ∈ [0, π]` reached a time `τ ∈ [0, T/2]` after the lower
    /// turning point: Newton's method on the partial time integral, `ds/dτ = √P`.
    pub fn phase_at_time(&self, tau: f64) -> Result<f64> {
        let tau = finite("τ", tau)?;
        let half = self.libration.inverse_sqrt_integral(|_| 1.0)?.value;
        if !(0.0..=half).contains(&tau) {
            return Err(Error::out_of_domain(
                "τ",
                tau,
                format!("[0, {half}] (half a period)"),
            ));
        }
        let time = |s: f64| -> Result<f64> {
            Ok(self
                .libration
                .integrate_between(|n| 1.0 / n.reduced.sqrt(), 0.0, s)?
                .value)
        };
        let mut s = (PI * tau / half).clamp(0.0, PI);
        for _ in 0..MAX_ITER {
            let r = time(s)? - tau;
            let step = r * self.libration.node(s).reduced.sqrt();
            let next = (s - step).clamp(0.0, PI);
            if (next - s).abs() <= 4.0 * f64::EPSILON * PI {
                return Ok(next);
            }
            s = next;
        }
        Err(Error::NotConverged {
            what: "inversion of the top's time law".into(),
            iterations: MAX_ITER,
            residual: time(s)? - tau,
        })
    }

    /// The state a time `dt` after `(q0, p0)`, which must lie on this nutation: `θ(t)` by
    /// inverting the time law, `φ`, `ψ` by the partial quadratures, `p_θ = I θ̇` from
    /// `u̇ = ±√f`; `p_φ`, `p_ψ` are constant.
    pub fn propagate(
        &self,
        q0: &SVector<f64, 3>,
        p0: &SVector<f64, 3>,
        dt: f64,
    ) -> Result<(SVector<f64, 3>, SVector<f64, 3>)> {
        crate::phase::check_phase(dt, q0, p0)?;
        let sign = q0[1].sin().signum();
        let period = self.period()?.value;
        let dphi = self.precession_per_period()?.value;
        let dpsi = self.spin_per_period()?.value;
        if period <= 0.0 || !period.is_finite() {
            return Err(Error::out_of_domain("nutation period", period, "(0, ∞)"));
        }
        // Time since the last passage through u₁, and the angles accumulated since then.
        let s0 = self.libration.phase(0.0)?;
        let a0 = self.advance_at_phase(s0)?;
        let rising = sign * p0[1] < 0.0;
        let unfold = |a: &Advance, rising: bool| -> [f64; 3] {
            if rising {
                [a.time.value, a.precession.value, a.spin.value]
            } else {
                [
                    period - a.time.value,
                    dphi - a.precession.value,
                    dpsi - a.spin.value,
                ]
            }
        };
        let start = unfold(&a0, rising || p0[1] == 0.0);
        let tau = start[0] + dt;
        let k = (tau / period).floor();
        let r = tau - k * period;
        let (s, rising) = if r <= 0.5 * period {
            (self.phase_at_time(r)?, true)
        } else {
            (self.phase_at_time((period - r).max(0.0))?, false)
        };
        let a = self.advance_at_phase(s)?;
        let now = unfold(&a, rising);
        let node = self.libration.node(s);
        let c = &self.cubic;
        let theta_ref = sign * c.theta_of(0.0);
        let turns = ((q0[1] - theta_ref) / (2.0 * PI)).round();
        let theta = sign * c.theta_of(node.x) + 2.0 * PI * turns;
        let sin_theta = ((c.one_minus - node.x) * (c.one_plus + node.x)).sqrt();
        let udot = if rising { 1.0 } else { -1.0 } * node.sqrt_radicand();
        let theta_dot = -udot / (sign * sin_theta);
        let q = SVector::from([
            q0[0] + k * dphi + now[1] - start[1],
            theta,
            q0[2] + k * dpsi + now[2] - start[2],
        ]);
        let p = SVector::from([p0[0], self.top.i() * theta_dot, p0[2]]);
        crate::error::all_finite("propagated q", q.as_slice())?;
        crate::error::all_finite("propagated p", p.as_slice())?;
        Ok((q, p))
    }
}

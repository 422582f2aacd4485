//! Action–angle variables of one-degree-of-freedom systems by quadrature, through the turning
//! points and up to the separatrix ([Ardema 17.3, 9.2]; [Goldstein §10.6]).
//!
//! For `H = ½ a(q) p² + V(q)` (`a > 0` the inverse mass) and an energy `h` with a libration
//! between turning points `q₁ < q₂` (roots of `F = p² = 2(h − V)/a`):
//!
//! ```math
//! J(h) = \frac{1}{2\pi}\oint p\\,dq = \frac1\pi\int_{q_1}^{q_2}\sqrt{F}\\,dq, \qquad
//! T = 2\int_{q_1}^{q_2}\frac{dq}{a\sqrt F} = 2\pi\frac{dJ}{dh}, \qquad
//! \omega = \frac{\partial H}{\partial J} = \frac{2\pi}{T},
//! ```
//!
//! and the angle `w = ω (t − t₁)`, with `t − t₁` the time since the lower turning point (`w = π`
//! at the upper one). `(w, J)` are canonical: `J` is the new momentum, constant, and `w` the new
//! coordinate, advancing at the rate `ω(J)`.
//!
//! The quadratures run through the turning points in the substitution variable of
//! [`Libration`]. Near a separatrix the upper turning point approaches a double root of `F` and
//! the period diverges logarithmically; a generic potential is refused once `F′` at the turning
//! point vanishes to rounding ([`Error::Separatrix`]). For the pendulum,
//! [`ActionAngle::pendulum`] takes the distance `δ = π − a` to the separatrix itself and uses the
//! exact factorisation `F = 4n² sin(d₁/2) sin(d₂/2)` with `sin(d₁/2) = sin(δ + d₂/2)`, so the
//! period is resolved for every gap down to [`MIN_GAP`], never ∞ or NaN.

use crate::error::{finite, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::special::turning_points::{
    interior_point, Factored, Libration, Node, Quadrature, Radicand, ReducedRadicand,
};
use crate::systems::Pendulum;
use nalgebra::SVector;
use num_dual::{Dual2, DualNum};
use std::f64::consts::{PI, TAU};

/// Smallest gap `δ = π − a` accepted by [`ActionAngle::pendulum`].
pub const MIN_GAP: f64 = 1e-290;

/// The potential `V(q) = H(0, q, 0)` of a one-degree-of-freedom system in natural form
/// `H = ½ a(q) p² + V(q)`, read off the Hamiltonian in any dual type.
#[inline]
pub fn natural_potential<H: Hamiltonian<1> + ?Sized, D: DualNum<f64> + Copy>(
    system: &H,
    q: D,
) -> D {
    system.hamiltonian(D::zero(), &SVector::from([q]), &SVector::from([D::zero()]))
}

/// The inverse mass `a(q) = ∂²H/∂p²(0, q, 0)` of a one-degree-of-freedom system in natural
/// form, by second-order AD in `p` (no cancellation), in any dual type.
#[inline]
pub fn natural_inverse_mass<H: Hamiltonian<1> + ?Sized, D: DualNum<f64> + Copy>(
    system: &H,
    q: D,
) -> D {
    let qd = SVector::from([Dual2::from_re(q)]);
    let pd = SVector::from([Dual2::new(D::zero(), D::one(), D::zero())]);
    system.hamiltonian(Dual2::from_re(D::zero()), &qd, &pd).v2
}

/// Check that a one-degree-of-freedom Hamiltonian has the natural form
/// `H = ½ a(q) p² + V(q)` with `a > 0` and no explicit time dependence at the sample points
/// `qs`, with momenta `±p_scale`: action–angle variables by quadrature of
/// `p = ±√(2(h − V)/a)` need it. The residual `|H − V − ½ap²|` is compared with 64 ulps of the
/// terms.
pub fn check_natural_form<H: Hamiltonian<1> + ?Sized>(
    system: &H,
    qs: &[f64],
    p_scale: f64,
) -> Result<()> {
    let ps = if p_scale.is_finite() && p_scale > 0.0 {
        p_scale
    } else {
        1.0
    };
    for &q in qs {
        let v = natural_potential(system, q);
        let a = natural_inverse_mass(system, q);
        if !(a > 0.0 && a.is_finite() && v.is_finite()) {
            return Err(Error::invalid(
                "one-degree-of-freedom system",
                format!(
                    "at q = {q:e}: the inverse mass ∂²H/∂p² = {a:e} must be positive and \
                     V = H(q, 0) = {v:e} finite: action–angle variables by quadrature need an \
                     autonomous H of the natural form ½a(q)p² + V(q)"
                ),
            ));
        }
        for p in [ps, -ps] {
            for t in [0.0, 1.0] {
                let h = system.hamiltonian(t, &SVector::from([q]), &SVector::from([p]));
                let model = v + 0.5 * a * p * p;
                let scale = v.abs() + (0.5 * a * p * p).abs();
                let bound = 64.0 * f64::EPSILON * scale.max(f64::MIN_POSITIVE);
                if (h - model).abs() > bound || !h.is_finite() {
                    return Err(Error::invalid(
                        "one-degree-of-freedom system",
                        format!(
                            "H(t = {t}, q = {q:e}, p = {p:e}) = {h:e} differs from \
                             ½a(q)p² + V(q) = {model:e}: action–angle variables by quadrature \
                             need an autonomous H of the natural form ½a(q)p² + V(q)"
                        ),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// `H(q, p)` on reals.
#[inline]
fn energy<H: Hamiltonian<1> + ?Sized>(system: &H, q: f64, p: f64) -> f64 {
    system.hamiltonian(0.0, &SVector::from([q]), &SVector::from([p]))
}

/// The energy radicand `F(q) = p² = 2(h − V(q))/a(q)`.
#[derive(Clone, Copy, Debug)]
pub struct EnergyRadicand<S> {
    system: S,
    h: f64,
}

impl<S: Hamiltonian<1>> Radicand for EnergyRadicand<S> {
    fn radicand<D: DualNum<f64> + Copy>(&self, q: D) -> D {
        (-natural_potential(&self.system, q) + self.h) * 2.0 / natural_inverse_mass(&self.system, q)
    }
}

/// The pendulum's exact reduced radicand for the libration `[−a, a]`, `a = π − δ`:
/// `P = n² sinc(d₁/2) sinc(d₂/2)`, with `sin(d₁/2)` evaluated as `sin(δ + d₂/2)` past `π/2` so that
/// the gap `δ` enters exactly.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PendulumReduced {
    n: f64,
    delta: f64,
}

impl PendulumReduced {
    fn half_sine(&self, d: f64, other: f64) -> f64 {
        let x = 0.5 * d;
        if x <= 0.5 * PI {
            x.sin()
        } else {
            (self.delta + 0.5 * other).sin()
        }
    }
}

impl ReducedRadicand for PendulumReduced {
    fn reduced(&self, _q: f64, d1: f64, d2: f64) -> f64 {
        let sinc = |d: f64, other: f64| {
            if d == 0.0 {
                1.0
            } else {
                self.half_sine(d, other) / (0.5 * d)
            }
        };
        self.n * self.n * sinc(d1, d2) * sinc(d2, d1)
    }
}

/// Action–angle variables of a libration of a one-degree-of-freedom [`Hamiltonian`] in natural
/// form `H = ½ a(q) p² + V(q)` (checked: [`check_natural_form`]).
#[derive(Clone, Debug)]
pub struct ActionAngle<S, P> {
    system: S,
    h: f64,
    libration: Libration<P>,
    action: Quadrature,
    half_period: Quadrature,
}

impl<S: Hamiltonian<1> + Clone> ActionAngle<S, Factored<EnergyRadicand<S>>> {
    /// The libration with energy `h` through `inside` (where `V(inside) < h`); the turning points
    /// are searched in `[lower_bound, upper_bound]`.
    pub fn new(system: S, h: f64, inside: f64, lower_bound: f64, upper_bound: f64) -> Result<Self> {
        let h = finite("energy h", h)?;
        let inside = finite("interior point", inside)?;
        let p_inside = (2.0 * (h - natural_potential(&system, inside)).abs()
            / natural_inverse_mass(&system, inside).abs())
        .sqrt();
        check_natural_form(&system, &[inside], p_inside)?;
        let radicand = EnergyRadicand {
            system: system.clone(),
            h,
        };
        let libration = Libration::from_radicand(radicand, inside, lower_bound, upper_bound)?;
        Self::with_libration(system, h, libration)
    }

    /// The libration through the state `(q, p)`; see [`ActionAngle::new`].
    pub fn from_state(
        system: S,
        q: f64,
        p: f64,
        lower_bound: f64,
        upper_bound: f64,
    ) -> Result<Self> {
        let (q, p) = (finite("q", q)?, finite("p", p)?);
        let h = energy(&system, q, p);
        let radicand = EnergyRadicand {
            system: system.clone(),
            h,
        };
        // At a turning point (p = 0) the search starts from a point just inside.
        let inside = interior_point(&radicand, q, lower_bound, upper_bound)?;
        Self::new(system, h, inside, lower_bound, upper_bound)
    }
}

impl ActionAngle<Pendulum, PendulumReduced> {
    /// The pendulum's libration at distance `δ = π − a ∈ (0, π)` from the separatrix, with the
    /// exact reduced radicand (accurate for every representable `δ > 0`; `δ = 0` is the separatrix
    /// and an error).
    pub fn pendulum(pendulum: Pendulum, delta: f64) -> Result<Self> {
        let delta = finite("gap δ = π − a", delta)?;
        if delta == 0.0 {
            return Err(Error::Separatrix {
                what: "pendulum action–angle variables".into(),
                distance: 0.0,
                hint: "δ = 0 is the separatrix: infinite period, no angle variable".into(),
            });
        }
        if !(delta > 0.0 && delta < PI) {
            return Err(Error::out_of_domain("gap δ = π − a", delta, "(0, π)"));
        }
        if delta < MIN_GAP {
            return Err(Error::Separatrix {
                what: "pendulum action–angle variables".into(),
                distance: delta,
                hint: format!(
                    "δ below {MIN_GAP:e}: the reduced radicand at the turning point (∝ δ) leaves \
                     the normal double range; the period is (4/n) ln(8/δ) to full precision there"
                ),
            });
        }
        let a = PI - delta;
        let n = pendulum.n();
        let h = 2.0 * n * n * (0.5 * a).sin().powi(2);
        let libration = Libration::new(-a, a, PendulumReduced { n, delta })?;
        Self::with_libration(pendulum, h, libration)
    }
}

impl<S: Hamiltonian<1>, P: ReducedRadicand> ActionAngle<S, P> {
    /// From a libration interval whose reduced radicand is that of `F = 2(h − V)/a` (e.g. an exact
    /// factorisation).
    pub fn with_libration(system: S, h: f64, libration: Libration<P>) -> Result<Self> {
        let (q1, q2) = (libration.lower(), libration.upper());
        let mid = 0.5 * (q1 + q2);
        let p_mid = (2.0 * (h - natural_potential(&system, mid)).abs()
            / natural_inverse_mass(&system, mid).abs())
        .sqrt();
        check_natural_form(&system, &[q1, mid, q2], p_mid)?;
        let action = libration.sqrt_integral()?.scale(1.0 / PI);
        let half_period = libration.integrate_full(|n| time_density(&system, n))?;
        Ok(Self {
            system,
            h,
            libration,
            action,
            half_period,
        })
    }

    /// The energy `h`.
    pub fn energy(&self) -> f64 {
        self.h
    }
    /// Turning points `(q₁, q₂)`.
    pub fn turning_points(&self) -> (f64, f64) {
        (self.libration.lower(), self.libration.upper())
    }
    /// The libration interval.
    pub fn libration(&self) -> &Libration<P> {
        &self.libration
    }
    /// The action `J = (1/2π) ∮ p dq`.
    pub fn action(&self) -> Quadrature {
        self.action
    }
    /// The period `T = 2 ∫ dq/q̇`.
    pub fn period(&self) -> Quadrature {
        let q = self.half_period;
        Quadrature {
            value: 2.0 * q.value,
            error: 2.0 * q.error,
            evaluations: q.evaluations,
        }
    }
    /// The frequency `ω = ∂H/∂J = 2π/T`.
    pub fn frequency(&self) -> f64 {
        PI / self.half_period.value
    }

    /// The angle `w ∈ [0, 2π)` of a state on this libration (`w = 0` at the lower turning point,
    /// increasing along the motion).
    ///
    /// The state must lie on the torus of this action: an energy offset `Δh` moves the action by
    /// `Δh/ω` (`dJ/dh = 1/ω`), so the state's energy `h′` must satisfy
    /// `|h′ − h| ≤ ω e_J + 8 ε s`, where `e_J` is the error estimate of the action quadrature
    /// ([`Self::action`]) and `8 ε s` the rounding of the two energy evaluations (`s` the size of
    /// the energy's terms: `|h|`, `|V|`, `a p²` and `|q V′|` as a proxy for `V`'s own terms).
    ///
    /// # Errors
    /// [`Error::NonFinite`] for NaN/∞; [`Error::OutOfDomain`] for a state off the torus (the
    /// error names the admissible energy interval) or outside the turning points.
    pub fn angle(&self, q: f64, p: f64) -> Result<f64> {
        let (q, p) = (finite("q", q)?, finite("p", p)?);
        let h = finite("energy of the state", energy(&self.system, q, p))?;
        let dv = natural_potential(&self.system, num_dual::Dual64::from_re(q).derivative()).eps;
        let terms = self
            .h
            .abs()
            .max(natural_potential(&self.system, q).abs())
            .max((natural_inverse_mass(&self.system, q) * p * p).abs())
            .max((q * dv).abs());
        let tolerance = self.frequency() * self.action.error + 8.0 * f64::EPSILON * terms;
        if (h - self.h).abs() > tolerance {
            return Err(Error::out_of_domain(
                "energy h′ of the state (q, p)",
                h,
                format!(
                    "[{:e}, {:e}]: the torus J = {:e} has energy h = {:e}, known to ω·e_J + 8ε·s \
                     = {tolerance:e} (action-quadrature error e_J = {:e}, energy terms \
                     s = {terms:e}); the state (q, p) = ({q:e}, {p:e}) is on another torus",
                    self.h - tolerance,
                    self.h + tolerance,
                    self.action.value,
                    self.h,
                    self.action.error
                ),
            ));
        }
        let s = self.libration.phase_with_momentum(q, p)?;
        let t = self
            .libration
            .integrate_between(|n| time_density(&self.system, n), 0.0, s)?
            .value;
        let half = self.half_period.value;
        // q̇ = a p: moving up when p > 0.
        let since = if p >= 0.0 || s == PI {
            t
        } else {
            2.0 * half - t
        };
        Ok((since * self.frequency()).rem_euclid(TAU))
    }

    /// The state `(q, p)` at angle `w` (any real; taken modulo 2π): inverts the time law by
    /// Newton on the quadrature.
    pub fn state(&self, w: f64) -> Result<(f64, f64)> {
        let w = finite("angle w", w)?.rem_euclid(TAU);
        let half = self.half_period.value;
        let t = w / self.frequency();
        let (up, target) = if t <= half {
            (true, t)
        } else {
            (false, 2.0 * half - t)
        };
        let (s, _) = self.libration.solve_phase(
            |n| time_density(&self.system, n),
            target.clamp(0.0, half),
            half,
        )?;
        let node = self.libration.node(s);
        let p = node.sqrt_radicand();
        Ok((node.x, if up { p } else { -p }))
    }
}

/// `dt/ds = 1/(a(q) √P)` (from `q̇ = a p`, `dq = √(d₁d₂) ds`, `p = √(d₁d₂P)`).
fn time_density<S: Hamiltonian<1>>(system: &S, n: &Node) -> f64 {
    1.0 / (natural_inverse_mass(system, n.x) * n.reduced.sqrt())
}

/// The period of a libration of energy `h` through `inside`, by quadrature [Ardema 9.2,
/// eqs. 9.13–9.15]: the time of flight over a full cycle.
pub fn libration_period<S: Hamiltonian<1> + Clone>(
    system: S,
    h: f64,
    inside: f64,
    lower_bound: f64,
    upper_bound: f64,
) -> Result<Quadrature> {
    Ok(ActionAngle::new(system, h, inside, lower_bound, upper_bound)?.period())
}

/// Time of flight `∫_{q₀}^{q₁} dq/q̇` between two points of one leg of the libration of energy `h`
/// [Ardema 9.2, eqs. 9.13–9.15], either end allowed to be a turning point; negative when `q₁ < q₀`.
pub fn time_of_flight<S: Hamiltonian<1> + Clone>(
    system: S,
    h: f64,
    q0: f64,
    q1: f64,
    lower_bound: f64,
    upper_bound: f64,
) -> Result<Quadrature> {
    let (q0, q1) = (finite("q₀", q0)?, finite("q₁", q1)?);
    if q0 == q1 {
        return Ok(Quadrature {
            value: 0.0,
            error: 0.0,
            evaluations: 0,
        });
    }
    let aa = ActionAngle::new(system, h, 0.5 * (q0 + q1), lower_bound, upper_bound)?;
    let lib = aa.libration();
    let (s0, s1) = (lib.phase(q0)?, lib.phase(q1)?);
    lib.integrate_signed(|n| time_density(&aa.system, n), s0, s1)
}

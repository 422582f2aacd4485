//! Regularised perturbed Kepler problems: Levi-Civita (planar) and Kustaanheimo–Stiefel
//! (spatial) coordinates with a fictitious time, integrated by any of the crate's methods.
//!
//! For `H = |p|²/2 − μ/r + H₁(t, x)` ([`PerturbedKepler`]) the position is written as the
//! square `x = L(u) u` of a vector `u` (`ℝ²` for Levi-Civita, `ℝ⁴` for Kustaanheimo–Stiefel,
//! `r = |x| = |u|²`), the momenta as `w = 2 L(u)ᵀ p`, time becomes a coordinate with momentum
//! `p_t` (`p_t = −H` on the motion) and the independent variable is the fictitious time `s`,
//! `dt = r ds`. The regularised Hamiltonian is
//!
//! ```math
//! K(u, t; w, p_t) = r\,(H + p_t) = \frac{|w|^2}{8} - \mu + |u|^2\big(p_t + H_1(t, L(u)u)\big),
//! ```
//!
//! and the motion is its flow on the level set `K = 0`. For `H₁ = 0` and `E = −p_t < 0` it is
//! the harmonic oscillator `u'' = (E/2) u` of frequency `ω = √(−E/2)`: the collision `r = 0`
//! is a regular point and the eccentricity no longer sets the step size. The perturbation is
//! written once, in the system's [`PerturbedKepler::perturbation`]; its gradient in `u` comes by
//! AD through the map `u ↦ L(u) u`.
//!
//! Kustaanheimo–Stiefel matrix and bilinear relation (Stiefel & Scheifele 1971, §§ 9, 11):
//!
//! ```math
//! L(u) = \begin{pmatrix} u_1 & -u_2 & -u_3 & u_4 \\ u_2 & u_1 & -u_4 & -u_3 \\
//!   u_3 & u_4 & u_1 & u_2 \\ u_4 & -u_3 & u_2 & -u_1 \end{pmatrix},\qquad
//! \ell(u, w) = u_4 w_1 - u_3 w_2 + u_2 w_3 - u_1 w_4 = 0 ,
//! ```
//!
//! `L(u)ᵀL(u) = |u|² I`; the fourth component of `L(u)u` vanishes, and the fourth component of
//! `p = L(u) w/(2r)` is `ℓ(u, w)/(2r)`. `ℓ` is a first integral of `K`'s flow; the runs report
//! its largest value. Levi-Civita is the planar case, `x₁ + i x₂ = (u₁ + i u₂)²` (Levi-Civita
//! 1920).
//!
//! Output at physical times: the state of the run in `s` (the method's dense output) where
//! `t(s)` equals the requested time, found by the Illinois iteration.
//!
//! References: E. L. Stiefel & G. Scheifele, *Linear and Regular Celestial Mechanics*, Springer
//! 1971, §§ 9–19; T. Levi-Civita, "Sur la régularisation du problème des trois corps", Acta
//! Math. 42 (1920) 99–144, doi:10.1007/BF02404404; P. Kustaanheimo & E. Stiefel, J. Reine
//! Angew. Math. 218 (1965) 204–219, doi:10.1515/crll.1965.218.204.

use super::sampling::locate;
use super::{Control, Method, Observer, Problem, StepView, Work};
use crate::error::{finite, Error, Result};
use crate::hamiltonian::{Hamiltonian, PerturbedKepler};
use crate::phase::State;
use crate::special::double_double::DoubleDouble as Dd;
use nalgebra::SVector;
use num_dual::DualNum;
use std::time::{Duration, Instant};

/// A regularisation of a perturbed Kepler problem in `N` dimensions as a Hamiltonian in `M`
/// extended regular dimensions (`u` and `t`): the maps between the physical and the regular
/// state and the bilinear relation.
pub trait Regularisation<const N: usize, const M: usize>: Hamiltonian<M> {
    /// The regular state `(s = 0; u, t; w, p_t)` of the physical state `(t; x, p)`, with
    /// `p_t = −H(t, x, p)`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite entry or energy; [`Error::Singular`] at the
    /// collision `x = 0`.
    fn to_regular(&self, x: &State<N>) -> Result<State<M>>;
    /// The physical state `(t; x, p)` of a regular state.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite entry; [`Error::Singular`] at `u = 0`.
    fn to_physical(&self, y: &State<M>) -> Result<State<N>>;
    /// The bilinear relation `ℓ(u, w)` (zero for Levi-Civita).
    fn bilinear(&self, _y: &State<M>) -> f64 {
        0.0
    }
    /// The gravitational parameter of the Kepler part.
    fn mu(&self) -> f64;
}

/// Levi-Civita regularisation of a planar perturbed Kepler problem: `K` on
/// `(u₁, u₂, t; w₁, w₂, p_t)` ([module docs](self)).
#[derive(Clone, Copy, Debug)]
pub struct LeviCivita<'a, S> {
    system: &'a S,
}

/// Kustaanheimo–Stiefel regularisation of a spatial perturbed Kepler problem: `K` on
/// `(u₁ … u₄, t; w₁ … w₄, p_t)` ([module docs](self)).
#[derive(Clone, Copy, Debug)]
pub struct KustaanheimoStiefel<'a, S> {
    system: &'a S,
}

impl<'a, S: PerturbedKepler<2>> LeviCivita<'a, S> {
    /// The regularisation of `system`.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] when the system's `μ` is not positive and finite.
    pub fn new(system: &'a S) -> Result<Self> {
        check_mu(system.mu())?;
        Ok(Self { system })
    }
}

impl<'a, S: PerturbedKepler<3>> KustaanheimoStiefel<'a, S> {
    /// The regularisation of `system`.
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] when the system's `μ` is not positive and finite.
    pub fn new(system: &'a S) -> Result<Self> {
        check_mu(system.mu())?;
        Ok(Self { system })
    }
}

fn check_mu(mu: f64) -> Result<f64> {
    if mu > 0.0 && mu.is_finite() {
        Ok(mu)
    } else {
        Err(Error::out_of_domain(
            "gravitational parameter μ of the regularised system",
            mu,
            "(0, ∞)",
        ))
    }
}

/// `x = L(u) u` in the plane: `x₁ + i x₂ = (u₁ + i u₂)²`.
#[inline]
pub fn levi_civita_position<D: DualNum<f64> + Copy>(u: &SVector<D, 2>) -> SVector<D, 2> {
    SVector::from([u[0] * u[0] - u[1] * u[1], u[0] * u[1] * 2.0])
}

/// `x = L(u) u` in space (the fourth component, zero, dropped).
#[inline]
pub fn ks_position<D: DualNum<f64> + Copy>(u: &SVector<D, 4>) -> SVector<D, 3> {
    SVector::from([
        u[0] * u[0] - u[1] * u[1] - u[2] * u[2] + u[3] * u[3],
        (u[0] * u[1] - u[2] * u[3]) * 2.0,
        (u[0] * u[2] + u[1] * u[3]) * 2.0,
    ])
}

/// The KS matrix `L(u)` applied to `v`.
fn ks_apply(u: &SVector<f64, 4>, v: &SVector<f64, 4>) -> SVector<f64, 4> {
    SVector::from([
        u[0] * v[0] - u[1] * v[1] - u[2] * v[2] + u[3] * v[3],
        u[1] * v[0] + u[0] * v[1] - u[3] * v[2] - u[2] * v[3],
        u[2] * v[0] + u[3] * v[1] + u[0] * v[2] + u[1] * v[3],
        u[3] * v[0] - u[2] * v[1] + u[1] * v[2] - u[0] * v[3],
    ])
}

/// `L(u)ᵀ v`.
fn ks_apply_transpose(u: &SVector<f64, 4>, v: &SVector<f64, 4>) -> SVector<f64, 4> {
    SVector::from([
        u[0] * v[0] + u[1] * v[1] + u[2] * v[2] + u[3] * v[3],
        -u[1] * v[0] + u[0] * v[1] + u[3] * v[2] - u[2] * v[3],
        -u[2] * v[0] - u[3] * v[1] + u[0] * v[2] + u[1] * v[3],
        u[3] * v[0] - u[2] * v[1] + u[1] * v[2] - u[0] * v[3],
    ])
}

/// The `u` of `x` (Stiefel & Scheifele 1971, §11): the representative with `u₄ = 0` when
/// `x₁ ≥ 0`, with `u₃ = 0` otherwise (no cancellation in either branch).
pub fn ks_inverse(x: &SVector<f64, 3>) -> Result<SVector<f64, 4>> {
    let r = x.norm();
    check_radius(r, x.as_slice())?;
    Ok(if x[0] >= 0.0 {
        let u1 = (0.5 * (r + x[0])).sqrt();
        SVector::from([u1, x[1] / (2.0 * u1), x[2] / (2.0 * u1), 0.0])
    } else {
        let u2 = (0.5 * (r - x[0])).sqrt();
        SVector::from([x[1] / (2.0 * u2), u2, 0.0, x[2] / (2.0 * u2)])
    })
}

/// The `u` of `x` in the plane: the square root of `x₁ + i x₂` with `u₁ ≥ 0`.
pub fn levi_civita_inverse(x: &SVector<f64, 2>) -> Result<SVector<f64, 2>> {
    let r = x.norm();
    check_radius(r, x.as_slice())?;
    Ok(if x[0] >= 0.0 {
        let u1 = (0.5 * (r + x[0])).sqrt();
        SVector::from([u1, x[1] / (2.0 * u1)])
    } else {
        let u2 = (0.5 * (r - x[0])).sqrt().copysign(x[1]);
        SVector::from([x[1] / (2.0 * u2), u2])
    })
}

fn check_radius(r: f64, x: &[f64]) -> Result<()> {
    if !r.is_finite() {
        return Err(Error::NonFinite {
            what: format!("|x| of the position {x:?} to regularise"),
            value: r,
        });
    }
    if r == 0.0 {
        return Err(Error::Singular {
            what: "regularising map u ↦ L(u)u".into(),
            at: "the collision x = 0 (no momentum w is defined there)".into(),
            rcond: 0.0,
        });
    }
    Ok(())
}

fn check_regular<const M: usize>(y: &State<M>) -> Result<()> {
    if !y.is_finite() {
        return Err(Error::NonFinite {
            what: format!("regular state at s = {:e}", y.t),
            value: f64::NAN,
        });
    }
    Ok(())
}

fn singular_u() -> Error {
    Error::Singular {
        what: "regular-to-physical map p = L(u) w / (2|u|²)".into(),
        at: "u = 0".into(),
        rcond: 0.0,
    }
}

/// `p_t = −H(t, x, p)`, checked finite.
///
/// The Kepler part `|p|²/2 − μ/r` cancels to a relative `(1 − e)` near periapsis of an
/// eccentric orbit, and `p_t` fixes the period of the regularised motion: it is formed in
/// double-double from exact squares and rounded once, so that the period carries `ε/2` rather
/// than `ε/(1 − e)` (at `e = 0.99`, 100 periods: `1.7e−7` in the final state otherwise).
fn time_momentum<S: PerturbedKepler<N>, const N: usize>(system: &S, x: &State<N>) -> Result<f64> {
    let square = |v: &SVector<f64, N>| v.iter().fold(Dd::from(0.0), |s, &c| s + Dd::product(c, c));
    let r = square(&x.q).sqrt();
    let kepler = square(&x.p) * 0.5 - Dd::from(system.mu()) / r;
    let h = (kepler + Dd::from(system.perturbation(x.t, &x.q))).to_f64();
    Ok(-finite("energy H of the state to regularise", h)?)
}

impl<S: PerturbedKepler<2>> Hamiltonian<3> for LeviCivita<'_, S> {
    #[inline]
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _s: D,
        q: &SVector<D, 3>,
        p: &SVector<D, 3>,
    ) -> D {
        let u = SVector::from([q[0], q[1]]);
        let x = levi_civita_position(&u);
        let r = u.dot(&u);
        (p[0] * p[0] + p[1] * p[1]) * 0.125 + r * (p[2] + self.system.perturbation(q[2], &x))
            - self.system.mu()
    }
}

impl<S: PerturbedKepler<3>> Hamiltonian<5> for KustaanheimoStiefel<'_, S> {
    #[inline]
    fn hamiltonian<D: DualNum<f64> + Copy>(
        &self,
        _s: D,
        q: &SVector<D, 5>,
        p: &SVector<D, 5>,
    ) -> D {
        let u = SVector::from([q[0], q[1], q[2], q[3]]);
        let x = ks_position(&u);
        let r = u.dot(&u);
        (p[0] * p[0] + p[1] * p[1] + p[2] * p[2] + p[3] * p[3]) * 0.125
            + r * (p[4] + self.system.perturbation(q[4], &x))
            - self.system.mu()
    }
}

impl<S: PerturbedKepler<2>> Regularisation<2, 3> for LeviCivita<'_, S> {
    fn to_regular(&self, x: &State<2>) -> Result<State<3>> {
        let x = State::new(x.t, x.q, x.p)?;
        let u = levi_civita_inverse(&x.q)?;
        // w = 2 L(u)ᵀ p with L(u) = [[u₁, −u₂], [u₂, u₁]].
        let w = [
            2.0 * (u[0] * x.p[0] + u[1] * x.p[1]),
            2.0 * (-u[1] * x.p[0] + u[0] * x.p[1]),
        ];
        let pt = time_momentum(self.system, &x)?;
        State::from_arrays(0.0, [u[0], u[1], x.t], [w[0], w[1], pt])
    }

    fn to_physical(&self, y: &State<3>) -> Result<State<2>> {
        check_regular(y)?;
        let u = SVector::from([y.q[0], y.q[1]]);
        let r = u.dot(&u);
        if r == 0.0 {
            return Err(singular_u());
        }
        let (w1, w2) = (y.p[0], y.p[1]);
        let p = [
            (u[0] * w1 - u[1] * w2) / (2.0 * r),
            (u[1] * w1 + u[0] * w2) / (2.0 * r),
        ];
        let x = levi_civita_position(&u);
        State::from_arrays(y.q[2], [x[0], x[1]], p)
    }

    fn mu(&self) -> f64 {
        self.system.mu()
    }
}

impl<S: PerturbedKepler<3>> Regularisation<3, 5> for KustaanheimoStiefel<'_, S> {
    fn to_regular(&self, x: &State<3>) -> Result<State<5>> {
        let x = State::new(x.t, x.q, x.p)?;
        let u = ks_inverse(&x.q)?;
        let p4 = SVector::from([x.p[0], x.p[1], x.p[2], 0.0]);
        let w = ks_apply_transpose(&u, &p4) * 2.0;
        let pt = time_momentum(self.system, &x)?;
        State::from_arrays(
            0.0,
            [u[0], u[1], u[2], u[3], x.t],
            [w[0], w[1], w[2], w[3], pt],
        )
    }

    fn to_physical(&self, y: &State<5>) -> Result<State<3>> {
        check_regular(y)?;
        let u = SVector::from([y.q[0], y.q[1], y.q[2], y.q[3]]);
        let w = SVector::from([y.p[0], y.p[1], y.p[2], y.p[3]]);
        let r = u.dot(&u);
        if r == 0.0 {
            return Err(singular_u());
        }
        let p = ks_apply(&u, &w) / (2.0 * r);
        let x = ks_position(&u);
        State::from_arrays(y.q[4], [x[0], x[1], x[2]], [p[0], p[1], p[2]])
    }

    fn bilinear(&self, y: &State<5>) -> f64 {
        let (u, w) = (&y.q, &y.p);
        u[3] * w[0] - u[2] * w[1] + u[1] * w[2] - u[0] * w[3]
    }

    fn mu(&self) -> f64 {
        self.system.mu()
    }
}

/// A fictitious-time span that covers the physical span `t₁ − t₀` from `start` for the
/// unperturbed motion (the sign of `t₁ − t₀`): on an ellipse `s = ∫dt/r` grows by
/// `2π√(a/μ)` per period `2π√(a³/μ)`, so `|Δs| ≈ |Δt|/a`; the estimate is
/// `1.5 |Δt|/a + 4π√(a/μ)` for `E < 0`, and `|Δt|/r_p + 1` (`r_p` the periapsis) otherwise.
/// A perturbation that changes `a` by more than a third needs a larger span.
///
/// # Errors
/// [`Error::NonFinite`] for non-finite input; [`Error::Singular`] at the collision.
pub fn fictitious_span<R: Regularisation<N, M>, const N: usize, const M: usize>(
    regularisation: &R,
    start: &State<N>,
    t1: f64,
) -> Result<f64> {
    let y = regularisation.to_regular(start)?;
    let t1 = finite("final time t₁", t1)?;
    let mu = regularisation.mu();
    let energy = -y.p[M - 1];
    let dt = (t1 - start.t).abs();
    let span = if energy < 0.0 {
        let a = -mu / (2.0 * energy);
        1.5 * dt / a + 2.0 * std::f64::consts::TAU * (a / mu).sqrt()
    } else {
        let r = start.q.norm();
        let v2 = start.p.dot(&start.p);
        let rv = start.q.dot(&start.p);
        // |h|² = r²v² − (r·v)², e = √(1 + 2E|h|²/μ²), r_p = |h|²/(μ(1 + e)).
        let h2 = (r * r * v2 - rv * rv).max(0.0);
        let e = (1.0 + 2.0 * energy * h2 / (mu * mu)).max(0.0).sqrt();
        let rp = (h2 / (mu * (1.0 + e))).max(f64::MIN_POSITIVE);
        dt / rp + 1.0
    };
    finite("fictitious-time span", span * (t1 - start.t).signum())
}

/// The outcome of a regularised run: the physical states at the requested times and what the
/// run in fictitious time saw.
#[derive(Clone, Debug, PartialEq)]
pub struct RegularisedRun<const N: usize> {
    /// The physical states at the requested times, in order.
    pub states: Vec<State<N>>,
    /// The fictitious time of the last output.
    pub s: f64,
    /// The largest `|K|` at the ends of the steps (zero on the exact motion).
    pub max_k: f64,
    /// The largest `|ℓ(u, w)|` at the ends of the steps (zero on the exact motion).
    pub max_bilinear: f64,
    /// The work of the run in `s`.
    pub work: Work,
    /// Wall time.
    pub elapsed: Duration,
}

/// Collects the physical states at the requested times from a run in `s`.
struct Outputs<'a, R, const N: usize, const M: usize> {
    regularisation: &'a R,
    times: &'a [f64],
    states: Vec<State<N>>,
    s: f64,
    max_k: f64,
    max_bilinear: f64,
    error: Option<Error>,
}

impl<R: Regularisation<N, M>, const N: usize, const M: usize> Outputs<'_, R, N, M> {
    fn monitor(&mut self, y: &State<M>) {
        if let Ok(k) = self.regularisation.value(y.t, &y.q, &y.p) {
            self.max_k = self.max_k.max(k.abs());
        }
        self.max_bilinear = self.max_bilinear.max(self.regularisation.bilinear(y).abs());
    }

    fn record(&mut self, y: &State<M>, target: f64) -> bool {
        match self.regularisation.to_physical(y) {
            Ok(mut x) => {
                x.t = target;
                self.states.push(x);
                self.s = y.t;
                true
            }
            Err(e) => {
                self.error = Some(e);
                false
            }
        }
    }
}

impl<R: Regularisation<N, M>, const N: usize, const M: usize> Observer<M> for Outputs<'_, R, N, M> {
    fn start(&mut self, y: &State<M>) {
        self.monitor(y);
        while let Some(&target) = self.times.get(self.states.len()) {
            if target != y.q[M - 1] || !self.record(y, target) {
                break;
            }
        }
    }

    fn step(&mut self, step: &StepView<'_, M>) -> Control {
        self.monitor(step.next);
        let (ta, tb) = (step.prev.q[M - 1], step.next.q[M - 1]);
        while let Some(&target) = self.times.get(self.states.len()) {
            let (ga, gb) = (ta - target, tb - target);
            if ga != 0.0 && gb != 0.0 && (ga < 0.0) == (gb < 0.0) {
                break;
            }
            let Some(y) = locate(step.dense, step.prev, step.next, ga, gb, |z| {
                z.q[M - 1] - target
            }) else {
                self.error = Some(Error::NonFinite {
                    what: format!("dense output of the regularised run near t = {target:e}"),
                    value: f64::NAN,
                });
                return Control::Stop;
            };
            if !self.record(&y, target) {
                return Control::Stop;
            }
        }
        if self.states.len() == self.times.len() {
            Control::Stop
        } else {
            Control::Continue
        }
    }
}

/// Integrate a regularised problem with `method` over the fictitious time `[0, s_span]` from the
/// physical state `start`, and return the physical states at `times` (in the direction of
/// `s_span`, from `start.t` on). The run stops at the last requested time;
/// [`fictitious_span`] gives an `s_span` that covers a physical span.
///
/// ```
/// use hamilton_jacobi::integrate::regularised::{fictitious_span, propagate, LeviCivita};
/// use hamilton_jacobi::integrate::Dop853;
/// use hamilton_jacobi::phase::State;
/// use hamilton_jacobi::systems::{ExactFlow, Kepler2};
/// // Kepler e = 0.99 from periapsis over ten periods.
/// let kepler = Kepler2::new(1.0).unwrap();
/// let start = State::from_arrays(0.0, [0.01, 0.0], [0.0, 199f64.sqrt()]).unwrap();
/// let t1 = 10.0 * std::f64::consts::TAU;
/// let lc = LeviCivita::new(&kepler).unwrap();
/// let span = fictitious_span(&lc, &start, t1).unwrap();
/// let run = propagate(&lc, &Dop853::new(1e-12, 1e-12).unwrap(), &start, &[t1], span).unwrap();
/// let (q, _) = kepler.exact_flow(0.0, &start.q, &start.p, t1).unwrap();
/// assert!((run.states[0].q - q).amax() < 1e-8);
/// ```
///
/// # Errors
/// [`Error::InvalidInput`] for no times or times out of order; the errors of the maps and of the
/// method; [`Error::OutOfDomain`] when the run ends before the last requested time (`s_span`
/// too short).
pub fn propagate<R, Me, const N: usize, const M: usize>(
    regularisation: &R,
    method: &Me,
    start: &State<N>,
    times: &[f64],
    s_span: f64,
) -> Result<RegularisedRun<N>>
where
    R: Regularisation<N, M>,
    Me: Method<R, M>,
{
    let clock = Instant::now();
    let s_span = finite("fictitious-time span", s_span)?;
    if times.is_empty() {
        return Err(Error::invalid("output times", "none requested"));
    }
    let direction = s_span.signum();
    let mut previous = start.t;
    for &t in times {
        finite("output time", t)?;
        if (t - previous) * direction < 0.0 {
            return Err(Error::invalid(
                "output times",
                format!(
                    "{t:e} follows {previous:e}: the times must run from t₀ = {:e} in the \
                     direction of the fictitious-time span ({s_span:e})",
                    start.t
                ),
            ));
        }
        previous = t;
    }
    let y0 = regularisation.to_regular(start)?;
    let problem = Problem::new(regularisation, 0.0, y0.q, y0.p, s_span)?;
    let mut outputs = Outputs {
        regularisation,
        times,
        states: Vec::with_capacity(times.len()),
        s: 0.0,
        max_k: 0.0,
        max_bilinear: 0.0,
        error: None,
    };
    let report = method.run(&problem, &mut outputs)?;
    if let Some(e) = outputs.error {
        return Err(e);
    }
    if outputs.states.len() < times.len() {
        return Err(Error::out_of_domain(
            "fictitious-time span of the regularised run",
            s_span,
            format!(
                "long enough to reach t = {:e} (the run reached t = {:e}); use a longer span",
                times[outputs.states.len()],
                report.last.q[M - 1]
            ),
        ));
    }
    Ok(RegularisedRun {
        states: outputs.states,
        s: outputs.s,
        max_k: outputs.max_k,
        max_bilinear: outputs.max_bilinear,
        work: report.work,
        elapsed: clock.elapsed(),
    })
}

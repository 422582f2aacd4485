//! Hamilton's principal function by shooting [Ardema 17.1, eqs. 17.9–17.13; 17.2].
//!
//! The principal function is the action along the actual path from `(q⁰, t₀)` to `(q¹, t₁)`,
//!
//! ```math
//! S(q^0, q^1, t_0, t_1) = \int_{t_0}^{t_1} L\,dt
//! = \int_{t_0}^{t_1} \Big(p\cdot\frac{\partial H}{\partial p} - H\Big)\,dt ,
//! ```
//!
//! and its differential carries the end momenta and energies [Ardema eqs. 17.9–17.13]:
//!
//! ```math
//! dS = \sum p^1\,dq^1 - \sum p^0\,dq^0 - H_1\,dt_1 + H_0\,dt_0 .
//! ```
//!
//! In `(q¹, t₁)` it solves the Hamilton–Jacobi equation `∂S/∂t₁ + H(t₁, q¹, ∂S/∂q¹) = 0`, in
//! `(q⁰, t₀)` the equation `∂S/∂t₀ − H(t₀, q⁰, −∂S/∂q⁰) = 0` [Ardema 17.2].
//!
//! **Propagation** ([`propagate`], [`propagate_fixed`]). Hamilton's equations, with the action as
//! an extra component `ṡ = p·∂H/∂p − H`, are integrated by classical fourth-order Runge–Kutta with
//! `M` and `2M` fixed steps; the vector field is the AD gradient of `H` ([`Hamiltonian::gradient`])
//! in any dual type `D`, so the propagation is itself differentiable. Richardson extrapolation
//! gives the returned state `y = y₂ₘ + (y₂ₘ − yₘ)/15` and the estimate `|y₂ₘ − yₘ|/15` of the error
//! of `y₂ₘ` (an upper estimate for `y`), to which the rounding floor `ε √(2M)` times the largest
//! value of each component along the path is added. `M` is raised by powers of two until the
//! estimate meets the tolerance relative to those path maxima.
//!
//! **Shooting** ([`principal_function`]). The unknown initial momentum solves
//! `r(p⁰) = q(t₁; q⁰, p⁰) − q¹ = 0`; Newton's method uses the Jacobian `A = ∂q¹/∂p⁰` from a
//! propagation with gradient duals over `p⁰`, with backtracking and several starting guesses (the
//! user's, the straight line `(q¹ − q⁰)/τ` converted by the Legendre relation `q̇ = ∂H/∂p`, and
//! `p⁰ = 0`). The root is that of the discrete (extrapolated) map at a fixed `M`; `M` is then
//! raised and the root refined until the estimated errors of the results meet the tolerance. A
//! propagation error `e_q` of the end point moves the root by `δp⁰ = A⁻¹e_q`, so the reported
//! (componentwise) error estimates are
//!
//! ```math
//! \delta p^0 = |A^{-1}|\,e_q,\qquad \delta p^1 = e_p + |B|\,\delta p^0,\qquad
//! \delta S = e_S + |p^1|\cdot e_q,\qquad B = \partial p^1/\partial p^0
//! ```
//!
//! (`∂S/∂p⁰ = p¹ᵀA` at fixed `q⁰`, so the action is not amplified by `A⁻¹`, but `p¹` is large
//! near a focal point).
//!
//! **Focal points.** Where `A` is singular, `(q⁰, t₀)` and `(q¹, t₁)` are conjugate: the
//! end point is reached by no path or by infinitely many, and the type-1 generator of the flow map
//! does not exist. An equilibrated condition number cannot see this for `N = 1` (a `1 × 1` matrix
//! is always perfectly conditioned after scaling), so `A` is compared with its own error estimate
//! `δA = |A₂ₘ − Aₘ|/15 + ε √(2M) Â`, with the natural scale `Â_ij = max(|A_ij|, c_i |B_ij|)` of
//! the tangent map (`c_i` converts momentum to coordinate units: the ratio of the path maxima of
//! `|q_i|` and `|p_i|`, or `|τ ∂²H/∂p_i²|` on a path at rest). If `‖|A⁻¹| δA‖∞ ≥ ½`, `A` cannot be
//! told from a singular matrix and the result is [`Error::Singular`] carrying the point and
//! `rcond = 1/‖|A⁻¹| Â‖∞`; so is a result whose estimated relative error, amplified by `A⁻¹`,
//! exceeds [`PrincipalOptions::max_relative_error`]. Near a focal point the answer stays correct
//! with an error estimate growing like `1/rcond` (for the unit oscillator `1/sin τ`).
//!
//! **Derivatives.** [`principal_function_generic`] repeats the last propagation in any dual type
//! `D` after `D::NDERIV` Newton steps with the frozen real Jacobian ([`lift_root`]),
//! at the same step count, so that `S`, `p⁰`, `p¹`, `H₀`, `H₁` come out with exact derivatives of
//! the discrete map with respect to `(q⁰, q¹, t₀, t₁)` — independent of the returned momenta and
//! energies, which the identities above then check.
//!
//! **Time direction.** `t₁ < t₀` is allowed: the integral runs backwards and all relations above
//! hold unchanged. `t₁ = t₀` is refused: at `τ = 0` the principal function is singular (the identity
//! map has no type-1 generator). Systems with non-conservative forces have no principal
//! function and are refused.

use crate::ad::{lift, real_parts, real_times, GradDual};
use crate::error::{all_finite, finite, positive, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::implicit::lift_root;
use crate::integrate::{rk4_increment, Work};
use crate::phase::checked_inverse;
use nalgebra::{Const, SMatrix, SVector};
use num_dual::DualNum;

/// Counts `steps` classical RK4 steps (four AD gradients of `H` each) in the crate's [`Work`],
/// summed over all runs, iterations and levels of a propagation or a shooting solve.
fn add_rk4_steps(work: &mut Work, steps: usize) {
    work.steps += steps;
    work.gradients += 4 * steps;
}

/// Componentwise absolute error estimates of a propagated state and its action.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StateError<const N: usize> {
    /// Error of the coordinates.
    pub q: SVector<f64, N>,
    /// Error of the momenta.
    pub p: SVector<f64, N>,
    /// Error of the action `∫ L dt`.
    pub action: f64,
}

impl<const N: usize> StateError<N> {
    fn add(&self, o: &Self) -> Self {
        Self {
            q: self.q + o.q,
            p: self.p + o.p,
            action: self.action + o.action,
        }
    }
}

/// Step-count control of the propagator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PropagationOptions {
    /// Requested error relative to the largest value of each component along the path
    /// (default `1e−12`), in `[ε √(2·initial_steps), 1)`: the error estimate includes the rounding
    /// floor `ε √(2M)` of the first run (`M = initial_steps`), so a smaller tolerance can never
    /// be met, and at 1 no digit is asked for.
    pub tolerance: f64,
    /// Steps `M` of the first coarse run (default 16).
    pub initial_steps: usize,
    /// Largest coarse step count `M` (default `2²⁰`).
    pub max_steps: usize,
}

impl Default for PropagationOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-12,
            initial_steps: 16,
            max_steps: 1 << 20,
        }
    }
}

impl PropagationOptions {
    fn validate(&self) -> Result<()> {
        let tol = positive("tolerance", self.tolerance)?;
        if self.initial_steps == 0 {
            return Err(Error::invalid("initial_steps", "must be at least 1"));
        }
        let floor = rounding_floor(self.initial_steps.saturating_mul(2));
        if !(floor..1.0).contains(&tol) {
            return Err(Error::out_of_domain(
                "propagation tolerance",
                tol,
                format!(
                    "[{floor:e}, 1): below ε √(2·initial_steps) = {floor:e}, the rounding floor \
                     of the first run (initial_steps = {}), the error estimate can never meet \
                     it; at 1 or above no digit is asked for",
                    self.initial_steps
                ),
            ));
        }
        if self.max_steps < self.initial_steps {
            return Err(Error::invalid(
                "max_steps",
                format!(
                    "{} is below initial_steps = {}",
                    self.max_steps, self.initial_steps
                ),
            ));
        }
        Ok(())
    }
}

/// A propagated state `(q, p)` at `t₁` with the action `∫_{t₀}^{t₁} L dt`, in the dual type `D`.
#[derive(Clone, Copy, Debug)]
pub struct Propagation<D, const N: usize> {
    /// Coordinates at `t₁`.
    pub q: SVector<D, N>,
    /// Momenta at `t₁`.
    pub p: SVector<D, N>,
    /// The action `∫ (p·∂H/∂p − H) dt` along the path.
    pub action: D,
    /// Error estimate (step doubling plus rounding floor), real parts only.
    pub error: StateError<N>,
    /// Coarse step count `M` (the fine run takes `2M`).
    pub steps: usize,
    /// Work done.
    pub work: Work,
}

/// Largest absolute values of the real parts along a path: the scales of the error control.
#[derive(Clone, Copy, Debug)]
struct PathScale<const N: usize> {
    q: SVector<f64, N>,
    p: SVector<f64, N>,
    /// `max(max |s|, |τ| max |L|)`.
    action: f64,
}

impl<const N: usize> PathScale<N> {
    fn max(&self, o: &Self) -> Self {
        Self {
            q: self.q.zip_map(&o.q, f64::max),
            p: self.p.zip_map(&o.p, f64::max),
            action: self.action.max(o.action),
        }
    }
}

/// One fixed-step run.
#[derive(Clone, Copy, Debug)]
struct Run<D, const N: usize> {
    q: SVector<D, N>,
    p: SVector<D, N>,
    s: D,
    scale: PathScale<N>,
}

/// Hamilton's equations and the Lagrangian `p·∂H/∂p − H` in one AD pass.
#[inline]
fn field<H: Hamiltonian<N> + ?Sized, D: DualNum<f64> + Copy, const N: usize>(
    h: &H,
    t: D,
    q: &SVector<D, N>,
    p: &SVector<D, N>,
) -> (SVector<D, N>, SVector<D, N>, D) {
    let (hv, hq, hp) = h.gradient(t, q, p);
    (hp, -hq, p.dot(&hp) - hv)
}

/// `M` classical RK4 steps ([`rk4_increment`]) from `t₀` to `t₁` on `(q, p, s)`, the action `s`
/// carried along; `None` if the state leaves the finite numbers.
fn rk4_run<H: Hamiltonian<N> + ?Sized, D: DualNum<f64> + Copy, const N: usize>(
    h: &H,
    t0: D,
    t1: D,
    q0: &SVector<D, N>,
    p0: &SVector<D, N>,
    steps: usize,
) -> Option<Run<D, N>> {
    let dt = (t1 - t0) / steps as f64;
    let (mut q, mut p, mut s) = (*q0, *p0, D::from(0.0));
    let mut qmax = q.map(|x| x.re().abs());
    let mut pmax = p.map(|x| x.re().abs());
    // Largest |s| along the path, and largest Lagrangian |ṡ| at any stage.
    let (mut smax, mut lmax) = (0.0f64, 0.0f64);
    for k in 0..steps {
        let t = t0 + dt * k as f64;
        let (dq, dp, ds) = rk4_increment(
            |t, (q, p, _)| {
                let k = field(h, t, q, p);
                lmax = lmax.max(k.2.re().abs());
                Ok(k)
            },
            t,
            &(q, p, s),
            dt,
        )
        .ok()?;
        q += dq;
        p += dp;
        s += ds;
        for i in 0..N {
            let (a, b) = (q[i].re().abs(), p[i].re().abs());
            if !(a.is_finite() && b.is_finite()) {
                return None;
            }
            qmax[i] = qmax[i].max(a);
            pmax[i] = pmax[i].max(b);
        }
        if !s.re().is_finite() {
            return None;
        }
        smax = smax.max(s.re().abs());
    }
    Some(Run {
        q,
        p,
        s,
        scale: PathScale {
            q: qmax,
            p: pmax,
            action: smax.max((t1 - t0).re().abs() * lmax),
        },
    })
}

/// The pair of runs with `M` and `2M` steps, Richardson-extrapolated, with the discretisation and
/// rounding parts of the error estimate kept apart.
#[derive(Clone, Copy, Debug)]
struct Richardson<D, const N: usize> {
    coarse: Run<D, N>,
    fine: Run<D, N>,
    extrapolated: Run<D, N>,
    discretisation: StateError<N>,
    rounding: StateError<N>,
}

impl<D: DualNum<f64> + Copy, const N: usize> Richardson<D, N> {
    fn new(coarse: Run<D, N>, fine: Run<D, N>, fine_steps: usize) -> Self {
        let w = D::from(1.0 / 15.0);
        let extrapolated = Run {
            q: fine.q + (fine.q - coarse.q) * w,
            p: fine.p + (fine.p - coarse.p) * w,
            s: fine.s + (fine.s - coarse.s) * w,
            scale: fine.scale.max(&coarse.scale),
        };
        let diff = |a: &SVector<D, N>, b: &SVector<D, N>| {
            SVector::<f64, N>::from_fn(|i, _| (a[i].re() - b[i].re()).abs() / 15.0)
        };
        let discretisation = StateError {
            q: diff(&fine.q, &coarse.q),
            p: diff(&fine.p, &coarse.p),
            action: (fine.s.re() - coarse.s.re()).abs() / 15.0,
        };
        let floor = rounding_floor(fine_steps);
        let scale = extrapolated.scale;
        let rounding = StateError {
            q: scale.q * floor,
            p: scale.p * floor,
            action: scale.action * floor,
        };
        Self {
            coarse,
            fine,
            extrapolated,
            discretisation,
            rounding,
        }
    }

    fn error(&self) -> StateError<N> {
        self.discretisation.add(&self.rounding)
    }
}

/// Relative rounding error accumulated over `steps` steps (random-walk model `ε √steps`).
fn rounding_floor(steps: usize) -> f64 {
    f64::EPSILON * (steps as f64).sqrt()
}

/// `err/scale`, with `0/0 = 0` and `x/0 = ∞` for `x > 0`.
fn relative(err: f64, scale: f64) -> f64 {
    if err == 0.0 {
        0.0
    } else if scale > 0.0 {
        err / scale
    } else {
        f64::INFINITY
    }
}

/// Largest error of a state relative to the path maxima of its components.
fn relative_state_error<const N: usize>(e: &StateError<N>, s: &PathScale<N>) -> f64 {
    (0..N)
        .map(|i| relative(e.q[i], s.q[i]).max(relative(e.p[i], s.p[i])))
        .fold(relative(e.action, s.action), f64::max)
}

/// The run pair with `M` and `2M` steps (reusing `reuse` as the coarse run if given).
fn run_pair<H: Hamiltonian<N> + ?Sized, D: DualNum<f64> + Copy, const N: usize>(
    h: &H,
    (t0, t1): (D, D),
    q0: &SVector<D, N>,
    p0: &SVector<D, N>,
    steps: usize,
    reuse: Option<Run<D, N>>,
    work: &mut Work,
) -> Option<Richardson<D, N>> {
    let coarse = match reuse {
        Some(run) => run,
        None => {
            add_rk4_steps(work, steps);
            rk4_run(h, t0, t1, q0, p0, steps)?
        }
    };
    add_rk4_steps(work, 2 * steps);
    let fine = rk4_run(h, t0, t1, q0, p0, 2 * steps)?;
    Some(Richardson::new(coarse, fine, 2 * steps))
}

fn non_finite_path(t0: f64, t1: f64) -> Error {
    Error::NonFinite {
        what: format!(
            "propagated state between t₀ = {t0} and t₁ = {t1} (outside the system's domain, or \
             escaping to infinity?)"
        ),
        value: f64::NAN,
    }
}

fn check_times(t0: f64, t1: f64) -> Result<f64> {
    finite("t₀", t0)?;
    finite("t₁", t1)?;
    let tau = t1 - t0;
    finite("t₁ − t₀", tau)?;
    if tau == 0.0 {
        return Err(Error::out_of_domain(
            "t₁ − t₀",
            tau,
            "t₁ ≠ t₀ (at τ = 0 the principal function is singular: the identity map has no \
             type-1 generator)",
        ));
    }
    Ok(tau)
}

fn check_conservative<H: Hamiltonian<N> + ?Sized, const N: usize>(
    h: &H,
    t: f64,
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> Result<()> {
    if h.generalized_force(t, q, p).is_some() {
        return Err(Error::invalid(
            "system",
            "it has non-conservative generalized forces; the principal function (an action \
             integral) needs a variational principle",
        ));
    }
    Ok(())
}

/// Propagate `(q⁰, p⁰)` from `t₀` to `t₁` with exactly `steps` (= `M`) and `2M` classical RK4 steps
/// and Richardson extrapolation, in any dual type `D` (see the [module docs](self)); the action
/// `∫ L dt` is integrated alongside. With the step count fixed, the result is a smooth function of
/// the inputs, so its dual parts are exact derivatives of the discrete map.
///
/// Errors: [`Error::NonFinite`] for NaN/∞ input or a state that leaves the finite numbers,
/// [`Error::InvalidInput`] for `steps = 0`; `t₁ = t₀` and `t₁ < t₀` are allowed here.
pub fn propagate_fixed<H: Hamiltonian<N> + ?Sized, D: DualNum<f64> + Copy, const N: usize>(
    h: &H,
    t0: D,
    t1: D,
    q0: &SVector<D, N>,
    p0: &SVector<D, N>,
    steps: usize,
) -> Result<Propagation<D, N>> {
    finite("t₀", t0.re())?;
    finite("t₁", t1.re())?;
    all_finite("q⁰", real_parts(q0).as_slice())?;
    all_finite("p⁰", real_parts(p0).as_slice())?;
    if steps == 0 {
        return Err(Error::invalid("steps", "must be at least 1"));
    }
    let mut work = Work::default();
    let pair = run_pair(h, (t0, t1), q0, p0, steps, None, &mut work)
        .ok_or_else(|| non_finite_path(t0.re(), t1.re()))?;
    Ok(Propagation {
        q: pair.extrapolated.q,
        p: pair.extrapolated.p,
        action: pair.extrapolated.s,
        error: pair.error(),
        steps,
        work,
    })
}

/// Propagate `(q⁰, p⁰)` from `t₀` to `t₁` (either direction) by [`propagate_fixed`], raising the
/// step count by powers of two until every component's error estimate is at most
/// `tolerance` times its largest value along the path.
///
/// Errors as [`propagate_fixed`], plus [`Error::NotConverged`] if the tolerance is not met within
/// `max_steps` or lies below the rounding floor.
pub fn propagate<H: Hamiltonian<N> + ?Sized, D: DualNum<f64> + Copy, const N: usize>(
    h: &H,
    t0: D,
    t1: D,
    q0: &SVector<D, N>,
    p0: &SVector<D, N>,
    options: &PropagationOptions,
) -> Result<Propagation<D, N>> {
    options.validate()?;
    finite("t₀", t0.re())?;
    finite("t₁", t1.re())?;
    all_finite("q⁰", real_parts(q0).as_slice())?;
    all_finite("p⁰", real_parts(p0).as_slice())?;
    let mut work = Work::default();
    let mut steps = options.initial_steps;
    let mut reuse = None;
    loop {
        let pair = run_pair(h, (t0, t1), q0, p0, steps, reuse, &mut work)
            .ok_or_else(|| non_finite_path(t0.re(), t1.re()))?;
        let scale = pair.extrapolated.scale;
        let total = relative_state_error(&pair.error(), &scale);
        if total <= options.tolerance {
            return Ok(Propagation {
                q: pair.extrapolated.q,
                p: pair.extrapolated.p,
                action: pair.extrapolated.s,
                error: pair.error(),
                steps,
                work,
            });
        }
        let disc = relative_state_error(&pair.discretisation, &scale);
        let round = relative_state_error(&pair.rounding, &scale);
        let factor = refinement_factor(disc, options.tolerance);
        if disc <= round || steps.saturating_mul(factor) > options.max_steps {
            return Err(Error::NotConverged {
                what: format!(
                    "RK4 propagation to relative tolerance {:e} ({} at M = {steps}; rounding \
                     floor {round:e})",
                    options.tolerance,
                    if disc <= round {
                        "tolerance below the rounding floor"
                    } else {
                        "step limit reached"
                    }
                ),
                iterations: steps,
                residual: total,
            });
        }
        reuse = (factor == 2).then_some(pair.fine);
        steps *= factor;
    }
}

/// Power of two by which to multiply `M` so that an error `∝ M⁻⁴` falls from `relative_error` to
/// below `target` (between 2 and 16).
fn refinement_factor(relative_error: f64, target: f64) -> usize {
    let need = (relative_error / target).powf(0.25) * 1.2;
    let mut f = 2usize;
    while (f as f64) < need && f < 16 {
        f *= 2;
    }
    f
}

/// Options of [`principal_function`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipalOptions<const N: usize> {
    /// Step-count control. Its tolerance applies to the *results* `S`, `p⁰`, `p¹` (relative to the
    /// path maxima of `|s|`, `|τ L|` and `|p_i|`), so near a focal point the propagation is
    /// refined further, down to the rounding floor.
    pub propagation: PropagationOptions,
    /// Largest estimated relative error of the results that is still returned (default `1e−6`);
    /// beyond it the problem is refused as ill-conditioned ([`Error::Singular`] if the shooting
    /// Jacobian amplifies the error, [`Error::NotConverged`] otherwise).
    pub max_relative_error: f64,
    /// Newton iterations per start and step level (default 50).
    pub max_iterations: usize,
    /// A guess for `p⁰`, tried first (default none).
    pub momentum_guess: Option<SVector<f64, N>>,
}

impl<const N: usize> Default for PrincipalOptions<N> {
    fn default() -> Self {
        Self {
            propagation: PropagationOptions::default(),
            max_relative_error: 1e-6,
            max_iterations: 50,
            momentum_guess: None,
        }
    }
}

/// Componentwise absolute error estimates of a [`PrincipalFunction`] (see the [module docs](self)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipalError<const N: usize> {
    /// Error of `S`.
    pub s: f64,
    /// Error of `p⁰`.
    pub p0: SVector<f64, N>,
    /// Error of `p¹`.
    pub p1: SVector<f64, N>,
    /// Error of `H₀`.
    pub h0: f64,
    /// Error of `H₁`.
    pub h1: f64,
}

/// Hamilton's principal function at one pair of end points, with the end momenta and energies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipalFunction<const N: usize> {
    /// `S = ∫_{t₀}^{t₁} L dt` along the path.
    pub s: f64,
    /// Initial momentum `p⁰ = −∂S/∂q⁰`.
    pub p0: SVector<f64, N>,
    /// Final momentum `p¹ = ∂S/∂q¹`.
    pub p1: SVector<f64, N>,
    /// `H₀ = H(t₀, q⁰, p⁰) = ∂S/∂t₀`.
    pub h0: f64,
    /// `H₁ = H(t₁, q¹, p¹) = −∂S/∂t₁`.
    pub h1: f64,
    /// Error estimates (propagation error amplified by the shooting Jacobian, rounding included).
    pub error: PrincipalError<N>,
    /// The shooting Jacobian `A = ∂q¹/∂p⁰` at the root.
    pub jacobian: SMatrix<f64, N, N>,
    /// Reciprocal condition `1/‖|A⁻¹| Â‖∞` of the shooting problem (1 for free flight, → 0 at a
    /// focal point; see the [module docs](self)).
    pub rcond: f64,
    /// Newton iterations, summed over starts and step levels.
    pub iterations: usize,
    /// Coarse step count `M` of the final discrete map (the fine run takes `2M`).
    pub steps: usize,
    /// Work done.
    pub work: Work,
}

type Grad<const N: usize> = GradDual<f64, f64, Const<N>>;

/// The discrete shooting map at one `p⁰` with its Jacobians and error parts.
#[derive(Clone, Copy, Debug)]
struct Shot<const N: usize> {
    q: SVector<f64, N>,
    p: SVector<f64, N>,
    s: f64,
    /// `∂q¹/∂p⁰`.
    a: SMatrix<f64, N, N>,
    /// `∂p¹/∂p⁰`.
    b: SMatrix<f64, N, N>,
    /// `|A₂ₘ − Aₘ|/15`.
    a_discretisation: SMatrix<f64, N, N>,
    discretisation: StateError<N>,
    rounding: StateError<N>,
    scale: PathScale<N>,
    steps: usize,
}

/// The fixed data of one shooting problem.
struct Problem<'a, H: ?Sized, const N: usize> {
    h: &'a H,
    q0: SVector<f64, N>,
    q1: SVector<f64, N>,
    t0: f64,
    t1: f64,
    options: PrincipalOptions<N>,
}

impl<H: Hamiltonian<N> + ?Sized, const N: usize> Problem<'_, H, N> {
    fn at(&self) -> String {
        format!(
            "q⁰ = {:?}, q¹ = {:?}, t₀ = {}, t₁ = {}",
            self.q0.as_slice(),
            self.q1.as_slice(),
            self.t0,
            self.t1
        )
    }

    fn shoot(&self, p0: &SVector<f64, N>, steps: usize, work: &mut Work) -> Option<Shot<N>> {
        let pd: SVector<Grad<N>, N> = SVector::from_fn(|i, _| Grad::variable(p0[i], i));
        let (t0, t1) = (Grad::from_re(self.t0), Grad::from_re(self.t1));
        let pair = run_pair(self.h, (t0, t1), &lift(&self.q0), &pd, steps, None, work)?;
        let x = pair.extrapolated;
        let jac = |v: &SVector<Grad<N>, N>| SMatrix::<f64, N, N>::from_fn(|i, j| v[i].eps()[j]);
        let a = jac(&x.q);
        let b = jac(&x.p);
        if !(a.iter().chain(b.iter()).all(|v| v.is_finite()) && x.s.value().is_finite()) {
            return None;
        }
        let a_discretisation = (jac(&pair.fine.q) - jac(&pair.coarse.q)).abs() / 15.0;
        Some(Shot {
            q: real_parts(&x.q),
            p: real_parts(&x.p),
            s: *x.s.value(),
            a,
            b,
            a_discretisation,
            discretisation: pair.discretisation,
            rounding: pair.rounding,
            scale: x.scale,
            steps,
        })
    }

    /// Scaled residual `max_i |r_i| / w_i` for backtracking (`w_i` the size of the end points).
    fn residual_norm(&self, q: &SVector<f64, N>) -> f64 {
        (0..N)
            .map(|i| {
                let w = self.q0[i]
                    .abs()
                    .max(self.q1[i].abs())
                    .max((self.q1[i] - self.q0[i]).abs());
                let r = (q[i] - self.q1[i]).abs();
                if w > 0.0 {
                    r / w
                } else {
                    r
                }
            })
            .fold(0.0, f64::max)
    }

    /// Damped Newton on the discrete map with `steps` coarse steps, from `start`.
    fn newton(
        &self,
        start: &SVector<f64, N>,
        steps: usize,
        work: &mut Work,
        iterations: &mut usize,
    ) -> Result<(SVector<f64, N>, Shot<N>)> {
        let what = "shooting for Hamilton's principal function";
        let eps = f64::EPSILON;
        let mut p = *start;
        let mut shot = self
            .shoot(&p, steps, work)
            .ok_or_else(|| non_finite_path(self.t0, self.t1))?;
        let mut previous = f64::INFINITY;
        let mut count = 0;
        loop {
            let r = shot.q - self.q1;
            let inv = checked_inverse(&shot.a, "shooting Jacobian ∂q¹/∂p⁰", || self.at())?;
            let dp = inv * r;
            // Componentwise, scale-relative stopping rule (cf. `implicit::newton_converged`).
            let (qs, ps) = (
                shot.scale.q,
                shot.scale.p.zip_map(&p, |a, b| a.max(b.abs())),
            );
            let residual_small = (0..N).all(|i| r[i].abs() <= 4.0 * eps * qs[i]);
            let step = (0..N)
                .map(|i| relative(dp[i].abs(), ps[i]))
                .fold(0.0, f64::max);
            if residual_small || step <= 2.0 * eps || (step <= eps.sqrt() && step >= 0.5 * previous)
            {
                let pn = p - dp;
                if let Some(sn) = self.shoot(&pn, steps, work) {
                    if self.residual_norm(&sn.q) <= self.residual_norm(&shot.q) {
                        return Ok((pn, sn));
                    }
                }
                return Ok((p, shot));
            }
            if count >= self.options.max_iterations {
                return Err(Error::NotConverged {
                    what: format!("{what} ({})", self.at()),
                    iterations: count,
                    residual: self.residual_norm(&shot.q),
                });
            }
            previous = step;
            let norm = self.residual_norm(&shot.q);
            let mut lambda = 1.0;
            loop {
                let pn = p - dp * lambda;
                if let Some(sn) = self.shoot(&pn, steps, work) {
                    if self.residual_norm(&sn.q) < norm || lambda < 1e-9 {
                        p = pn;
                        shot = sn;
                        break;
                    }
                }
                if lambda < 1e-9 {
                    return Err(Error::NotConverged {
                        what: format!(
                            "{what} (every step from p⁰ = {:?} leaves the domain; {})",
                            p.as_slice(),
                            self.at()
                        ),
                        iterations: count,
                        residual: norm,
                    });
                }
                lambda *= 0.5;
            }
            count += 1;
            *iterations += 1;
        }
    }

    /// Starting guesses: the user's, the straight line through the Legendre relation, rest.
    fn starts(&self) -> Vec<SVector<f64, N>> {
        let mut starts = Vec::with_capacity(3);
        if let Some(g) = self.options.momentum_guess {
            starts.push(g);
        }
        let tau = self.t1 - self.t0;
        let v = (self.q1 - self.q0) / tau;
        let (qm, tm) = ((self.q0 + self.q1) * 0.5, 0.5 * (self.t0 + self.t1));
        let zero = SVector::zeros();
        if let Ok(hess) = self.h.hessian(tm, &qm, &zero) {
            let (_, _, hp) = self.h.gradient(tm, &qm, &zero);
            if let Some(inv) = hess.pp.try_inverse() {
                let guess = inv * (v - hp);
                if guess.iter().all(|x| x.is_finite()) {
                    starts.push(guess);
                }
            }
        }
        starts.push(zero);
        starts
    }

    /// Error estimates of the results at a root, split into discretisation and rounding parts.
    fn estimate(&self, p0: &SVector<f64, N>, shot: &Shot<N>) -> Result<Estimate<N>> {
        let Some(inv) = shot
            .a
            .try_inverse()
            .filter(|m| m.iter().all(|x| x.is_finite()))
        else {
            return Err(self.singular(0.0));
        };
        let inv_abs = inv.abs();
        let b_abs = shot.b.abs();
        let amplify = |e: &StateError<N>| -> PrincipalError<N> {
            let p0e = inv_abs * e.q;
            let p1e = e.p + b_abs * p0e;
            PrincipalError {
                s: e.action + shot.p.abs().dot(&e.q),
                p0: p0e,
                p1: p1e,
                h0: 0.0,
                h1: 0.0,
            }
        };
        let disc = amplify(&shot.discretisation);
        let round = amplify(&shot.rounding);
        let scale = shot.scale;
        let rel = |e: &PrincipalError<N>| {
            (0..N)
                .map(|i| relative(e.p0[i], scale.p[i]).max(relative(e.p1[i], scale.p[i])))
                .fold(relative(e.s, scale.action), f64::max)
        };
        // Natural scale of the tangent map and the distance of A from singularity.
        let tau = self.t1 - self.t0;
        let hpp = self.h.hessian(self.t0, &self.q0, p0).map(|m| m.pp).ok();
        let c = SVector::<f64, N>::from_fn(|i, _| {
            if scale.q[i] > 0.0 && scale.p[i] > 0.0 {
                scale.q[i] / scale.p[i]
            } else {
                hpp.map_or(0.0, |m| (tau * m[(i, i)]).abs())
            }
        });
        let a_hat =
            SMatrix::<f64, N, N>::from_fn(|i, j| shot.a[(i, j)].abs().max(c[i] * b_abs[(i, j)]));
        let inf_norm = |m: &SMatrix<f64, N, N>| {
            (0..N)
                .map(|i| m.row(i).iter().sum::<f64>())
                .fold(0.0, f64::max)
        };
        let rcond = 1.0 / inf_norm(&(inv_abs * a_hat));
        let delta_a = shot.a_discretisation + a_hat * rounding_floor(2 * shot.steps);
        let indistinguishable = inf_norm(&(inv_abs * delta_a));
        Ok(Estimate {
            disc_rel: rel(&disc),
            round_rel: rel(&round),
            total: PrincipalError {
                s: disc.s + round.s,
                p0: disc.p0 + round.p0,
                p1: disc.p1 + round.p1,
                h0: 0.0,
                h1: 0.0,
            },
            propagation_rel: relative_state_error(&shot.discretisation.add(&shot.rounding), &scale),
            rcond: if rcond.is_finite() { rcond } else { 0.0 },
            indistinguishable,
        })
    }

    fn singular(&self, rcond: f64) -> Error {
        Error::Singular {
            what: "shooting Jacobian ∂q¹/∂p⁰ (focal point: the end points are conjugate along the path)"
                .into(),
            at: self.at(),
            rcond,
        }
    }

    /// Newton from each start in turn at `steps`; the first error if all fail.
    fn solve_level(
        &self,
        starts: &[SVector<f64, N>],
        steps: usize,
        work: &mut Work,
        iterations: &mut usize,
    ) -> Result<(SVector<f64, N>, Shot<N>)> {
        let mut first = None;
        for start in starts {
            match self.newton(start, steps, work, iterations) {
                Ok(root) => return Ok(root),
                Err(e) => {
                    first.get_or_insert(e);
                }
            }
        }
        Err(first.unwrap_or_else(|| Error::invalid("starting guesses", "none given")))
    }

    fn solve(&self) -> Result<PrincipalFunction<N>> {
        let prop = self.options.propagation;
        let tol = prop.tolerance;
        let mut work = Work::default();
        let mut iterations = 0;
        let starts = self.starts();
        let mut steps = prop.initial_steps;
        // Coarse discrete maps may be too crude for Newton far from the root: retry finer.
        let (mut p0, mut shot) = loop {
            match self.solve_level(&starts, steps, &mut work, &mut iterations) {
                Ok(root) => break root,
                Err(e) => {
                    if steps.saturating_mul(4) > prop.max_steps
                        || steps >= prop.initial_steps.saturating_mul(256)
                    {
                        return Err(e);
                    }
                    steps *= 4;
                }
            }
        };
        let est = loop {
            let est = self.estimate(&p0, &shot)?;
            let total = est.disc_rel + est.round_rel;
            if total <= tol {
                break est;
            }
            let factor = refinement_factor(est.disc_rel, tol);
            if est.disc_rel <= est.round_rel || steps.saturating_mul(factor) > prop.max_steps {
                break est;
            }
            steps *= factor;
            (p0, shot) = self.solve_level(&[p0], steps, &mut work, &mut iterations)?;
        };
        if est.indistinguishable >= 0.5 {
            return Err(self.singular(est.rcond));
        }
        let total_rel = est.disc_rel + est.round_rel;
        if total_rel > self.options.max_relative_error {
            return Err(if est.propagation_rel <= self.options.max_relative_error {
                self.singular(est.rcond)
            } else {
                Error::NotConverged {
                    what: format!(
                        "principal function to relative error {:e} within {} steps ({})",
                        self.options.max_relative_error,
                        prop.max_steps,
                        self.at()
                    ),
                    iterations: steps,
                    residual: total_rel,
                }
            });
        }
        let p1 = shot.p;
        let (h0, _, hp0) = self.h.gradient(self.t0, &self.q0, &p0);
        let (h1, _, hp1) = self.h.gradient(self.t1, &self.q1, &p1);
        finite(format_args!("H₀ at {}", self.at()), h0)?;
        finite(format_args!("H₁ at {}", self.at()), h1)?;
        let mut error = est.total;
        error.h0 = hp0.abs().dot(&error.p0);
        error.h1 = hp1.abs().dot(&error.p1);
        Ok(PrincipalFunction {
            s: shot.s,
            p0,
            p1,
            h0,
            h1,
            error,
            jacobian: shot.a,
            rcond: est.rcond,
            iterations,
            steps,
            work,
        })
    }
}

/// Error estimate of the results at a root.
#[derive(Clone, Copy, Debug)]
struct Estimate<const N: usize> {
    disc_rel: f64,
    round_rel: f64,
    total: PrincipalError<N>,
    propagation_rel: f64,
    rcond: f64,
    /// `‖|A⁻¹| δA‖∞`: `≥ ½` means `A` is within its error of a singular matrix.
    indistinguishable: f64,
}

/// Hamilton's principal function `S(q⁰, q¹, t₀, t₁)` with `p⁰`, `p¹`, `H₀`, `H₁` by shooting
/// [Ardema 17.1, eqs. 17.9–17.13]:
///
/// ```math
/// S = \int_{t_0}^{t_1} L\,dt,\qquad
/// dS = \sum p^1 dq^1 - \sum p^0 dq^0 - H_1\,dt_1 + H_0\,dt_0 .
/// ```
///
/// Method, error estimates and the focal-point test are described in the [module docs](self);
/// `t₁ < t₀` is allowed (backward time).
///
/// # Errors
/// * [`Error::NonFinite`] for NaN/∞ in `q⁰`, `q¹`, `t₀`, `t₁` or the guess, or when every trial
///   path leaves the system's domain;
/// * [`Error::OutOfDomain`] for `t₁ = t₀`; [`Error::InvalidInput`] for bad options or a system
///   with non-conservative forces;
/// * [`Error::Singular`] at (or numerically indistinguishable from) a focal point;
/// * [`Error::NotConverged`] if Newton fails from every start or the accuracy is not reached.
///
/// # Example
/// ```
/// use hamilton_jacobi::hamilton_jacobi::principal::{principal_function, PrincipalOptions};
/// use hamilton_jacobi::nalgebra::SVector;
/// use hamilton_jacobi::systems::HarmonicOscillator;
///
/// // The oscillator of [Ardema 17.1]: ω = 2, x⁰ = 1, x¹ = 0.5, τ = 1.
/// let osc = HarmonicOscillator::new(1.0, 2.0).unwrap();
/// let q0 = SVector::from([1.0]);
/// let q1 = SVector::from([0.5]);
/// let r = principal_function(&osc, &q0, &q1, 0.0, 1.0, &PrincipalOptions::default()).unwrap();
/// assert!((r.s + 1.67182211324497).abs() < 1e-12);
/// assert!((r.p0[0] - 2.01506527901519).abs() < 1e-12);
/// ```
pub fn principal_function<H: Hamiltonian<N> + ?Sized, const N: usize>(
    h: &H,
    q0: &SVector<f64, N>,
    q1: &SVector<f64, N>,
    t0: f64,
    t1: f64,
    options: &PrincipalOptions<N>,
) -> Result<PrincipalFunction<N>> {
    all_finite("q⁰", q0.as_slice())?;
    all_finite("q¹", q1.as_slice())?;
    check_times(t0, t1)?;
    options.propagation.validate()?;
    positive("max_relative_error", options.max_relative_error)?;
    if let Some(g) = &options.momentum_guess {
        all_finite("momentum_guess", g.as_slice())?;
    }
    check_conservative(
        h,
        t0,
        q0,
        &options.momentum_guess.unwrap_or_else(SVector::zeros),
    )?;
    Problem {
        h,
        q0: *q0,
        q1: *q1,
        t0,
        t1,
        options: *options,
    }
    .solve()
}

/// The principal function and the end momenta and energies in the dual type `D`.
#[derive(Clone, Copy, Debug)]
pub struct PrincipalValue<D, const N: usize> {
    /// `S`.
    pub s: D,
    /// `p⁰`.
    pub p0: SVector<D, N>,
    /// `p¹`.
    pub p1: SVector<D, N>,
    /// `H₀ = H(t₀, q⁰, p⁰)`.
    pub h0: D,
    /// `H₁ = H(t₁, q¹, p¹)`.
    pub h1: D,
}

/// [`principal_function`] in any dual type `D`: the real solve on the real parts, then the exact
/// derivatives of the initial momentum by [`lift_root`] (`D::NDERIV` Newton steps in `D` with the
/// real shooting Jacobian frozen, at the final step count), and one more propagation in `D`. The
/// dual parts are exact derivatives of the discrete map, so `∂S/∂q¹`, `∂S/∂q⁰`, `∂S/∂t₁`,
/// `∂S/∂t₀` (and higher derivatives with a higher-order `D`) come out of `S` itself,
/// independently of the returned `p⁰`, `p¹`, `H₀`, `H₁` [Ardema 17.1–17.2].
///
/// Returns the dual values and the real report (error estimates, conditioning, work of the real
/// solve; the `D::NDERIV + 1` dual propagations at `M` and `2M` steps come on top); errors as
/// [`principal_function`].
///
/// # Example
/// ```
/// use hamilton_jacobi::hamilton_jacobi::principal::{principal_function_generic, PrincipalOptions};
/// use hamilton_jacobi::nalgebra::SVector;
/// use hamilton_jacobi::num_dual::Dual64;
/// use hamilton_jacobi::systems::HarmonicOscillator;
///
/// let osc = HarmonicOscillator::new(1.0, 2.0).unwrap();
/// let q0 = SVector::from([Dual64::from(1.0)]);
/// let q1 = SVector::from([Dual64::new(0.5, 1.0)]); // seed ∂/∂q¹
/// let (v, _) = principal_function_generic(
///     &osc, &q0, &q1, Dual64::from(0.0), Dual64::from(1.0), &PrincipalOptions::default(),
/// ).unwrap();
/// assert!((v.s.eps - v.p1[0].re).abs() < 1e-10); // ∂S/∂q¹ = p¹
/// ```
pub fn principal_function_generic<H, D, const N: usize>(
    h: &H,
    q0: &SVector<D, N>,
    q1: &SVector<D, N>,
    t0: D,
    t1: D,
    options: &PrincipalOptions<N>,
) -> Result<(PrincipalValue<D, N>, PrincipalFunction<N>)>
where
    H: Hamiltonian<N> + ?Sized,
    D: DualNum<f64> + Copy,
{
    let real = principal_function(
        h,
        &real_parts(q0),
        &real_parts(q1),
        t0.re(),
        t1.re(),
        options,
    )?;
    let inv = checked_inverse(&real.jacobian, "shooting Jacobian ∂q¹/∂p⁰", || {
        format!(
            "q⁰ = {:?}, q¹ = {:?}, t₀ = {}, t₁ = {}",
            real_parts(q0).as_slice(),
            real_parts(q1).as_slice(),
            t0.re(),
            t1.re()
        )
    })?;
    let run = |p0: &SVector<D, N>| -> Result<Run<D, N>> {
        let mut work = Work::default();
        run_pair(h, (t0, t1), q0, p0, real.steps, None, &mut work)
            .map(|pair| pair.extrapolated)
            .ok_or_else(|| non_finite_path(t0.re(), t1.re()))
    };
    let p0 = lift_root(
        lift(&real.p0),
        |p0| Ok(run(p0)?.q - q1),
        |r| real_times(&inv, r),
    )?;
    let end = run(&p0)?;
    let value = PrincipalValue {
        s: end.s,
        p0,
        p1: end.p,
        h0: h.hamiltonian(t0, q0, &p0),
        h1: h.hamiltonian(t1, q1, &end.p),
    };
    Ok((value, real))
}

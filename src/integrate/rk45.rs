//! Dormand–Prince 5(4) with the step-size control of SciPy's `RK45`, and its continuous extension
//! of order 4.
//!
//! # The method
//! Six stages `kᵢ = f(t + cᵢh, y + h Σⱼ aᵢⱼ kⱼ)` (Dormand & Prince 1980, HNW I Table II.5.2) give
//! the fifth-order solution, and a seventh evaluation at its end, `k₇ = f(t + h, y₁)`, enters the
//! embedded fourth-order solution and is the next step's `k₁` (FSAL, "first same as last"):
//!
//! ```math
//! y_1 = y_0 + h \sum_{i=1}^{6} b_i k_i ,\qquad
//! \mathrm{err}_i = h \sum_{j=1}^{7} e_j k_{j,i},\quad e_j = b_j - \hat b_j .
//! ```
//!
//! The solution is propagated with the fifth-order weights (local extrapolation); the error
//! estimate is that of the fourth-order one.
//!
//! # Step-size control (SciPy's `RK45`)
//! With `skᵢ = atol + rtol·max(|y₀ᵢ|, |y₁ᵢ|)` over the `n = 2N` components of `(q, p)`, the
//! error norm is the root mean square
//!
//! ```math
//! \|\mathrm{err}\| = \sqrt{\frac1n \sum_i \Big(\frac{\mathrm{err}_i}{sk_i}\Big)^2 } ,
//! ```
//!
//! and a step is accepted when `‖err‖ < 1`. The next step is `h·fac`,
//! `fac = min(10, 0.9·‖err‖^{−1/5})` after an acceptance (`10` at `‖err‖ = 0`; at most `1`
//! when the step was preceded by a rejection of the same step), `max(0.2, 0.9·‖err‖^{−1/5})`
//! after a rejection. A step that would pass `t₁` is cut to end there; `|h| ≤ h_max` (default
//! unbounded). The initial step, unless given, is SciPy's `select_initial_step` (HNW II.4 with
//! root-mean-square norms and the exponent `1/5`): `h₀ = 0.01‖y₀‖/‖f₀‖`, one explicit Euler step
//! to estimate `‖y″‖`, and `h = min(100 h₀, (0.01 / max(‖f₀‖, ‖y″‖))^{1/5}, |t₁ − t₀|, h_max)`.
//!
//! A step that produces non-finite stages (a singularity such as a collision) is rejected like a
//! step with `‖err‖ = ∞` (shrink ×0.2). As in SciPy, a step shorter than ten units in the last
//! place of `t` (and, at `t = 0`, than the smallest normal number) is too small: the run fails
//! with [`Error::NotConverged`] (its message names `t` and `h`; `iterations` = attempted steps,
//! `residual` = last error norm).
//!
//! # Step budget
//! As DOP853's ([`Dop853`](super::Dop853#step-budget)): by default
//! `clamp(10 ⌈|t₁ − t₀|/|h_init|⌉, 10⁵, 10⁷)` attempted steps, or [`Rk45::with_max_steps`]; an
//! exhausted budget is [`Error::WorkLimit`].
//!
//! # Tolerances
//! `rtol` must lie in `[`[`Rk45::RTOL_MIN`]`, 1)`: SciPy raises a smaller `rtol` to `100 ε`
//! with a warning; this code refuses it ([`Error::OutOfDomain`]) rather than change it silently.
//! `atol > 0` is used as given.
//!
//! # Dense output
//! The continuous extension of order 4 of HNW I §II.6 (Fortran `DOPRI5`, `CONTD5`), which needs
//! no further evaluation: with `s = (t − t₀)/h`, `s₁ = 1 − s`,
//!
//! ```math
//! y(t) = r_1 + s\big(r_2 + s_1(r_3 + s(r_4 + s_1 r_5))\big),
//! ```
//!
//! `r₁ = y₀`, `r₂ = y₁ − y₀`, `r₃ = h k₁ − r₂`, `r₄ = r₂ − h k₇ − r₃`, `r₅ = h Σ dⱼ kⱼ`.
//!
//! # Work counted
//! `gradients` counts every evaluation of the vector field, as SciPy's `nfev`: `f(t₀, y₀)`, one
//! more for the initial step selection (unless `h0` is given), and 6 per attempted step (stages
//! 2–7). `steps` and `rejected` as usual.
//!
//! # References
//! * J. R. Dormand, P. J. Prince, *A family of embedded Runge–Kutta formulae*, J. Comp. Appl.
//!   Math. 6 (1980) 19–26, doi:10.1016/0771-050X(80)90013-3.
//! * E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations I*, 2nd ed.,
//!   Springer 1993, doi:10.1007/978-3-540-78862-1: II.4 (starting step size), II.5 (Table 5.2),
//!   II.6 (dense output).
//! * L. F. Shampine, M. W. Reichelt, *The MATLAB ODE suite*, SIAM J. Sci. Comput. 18 (1997) 1–22;
//!   P. Virtanen et al., *SciPy 1.0*, Nature Methods 17 (2020) 261–272 (`scipy.integrate.RK45`,
//!   whose controller this is).

use super::dop853::{
    adaptive_start, advance, budget_exhausted, combine, flat, initial_step, norm2, pair_finite,
    step_budget, StartRule,
};
use super::methods;
use super::{
    observe, settle, Dense, FirstOrderSystem, Method, Observer, Problem, Report, State, Work,
};
use crate::error::{finite, positive, Error, Result};
use crate::phase::CanonicalPair;
use nalgebra::SVector;
use num_dual::DualNum;
use std::cell::OnceCell;
use std::time::Instant;

/// Sparse row of a Butcher tableau: `(stage index, coefficient)`, stages counted from 0.
type Row = &'static [(usize, f64)];

/// Nodes `c₁ … c₇` (stage 6 is `f(t + h, y₁)`).
const C: [f64; 7] = [0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0];

/// Rows `aᵢⱼ` of stages 2–6; the seventh row is `B`.
const A: [Row; 6] = [
    &[],
    &[(0, 0.2)],
    &[(0, 3.0 / 40.0), (1, 9.0 / 40.0)],
    &[(0, 44.0 / 45.0), (1, -56.0 / 15.0), (2, 32.0 / 9.0)],
    &[
        (0, 19372.0 / 6561.0),
        (1, -25360.0 / 2187.0),
        (2, 64448.0 / 6561.0),
        (3, -212.0 / 729.0),
    ],
    &[
        (0, 9017.0 / 3168.0),
        (1, -355.0 / 33.0),
        (2, 46732.0 / 5247.0),
        (3, 49.0 / 176.0),
        (4, -5103.0 / 18656.0),
    ],
];

/// Weights `bᵢ` of the fifth-order solution.
const B: [(usize, f64); 5] = [
    (0, 35.0 / 384.0),
    (2, 500.0 / 1113.0),
    (3, 125.0 / 192.0),
    (4, -2187.0 / 6784.0),
    (5, 11.0 / 84.0),
];

/// `eᵢ = bᵢ − b̂ᵢ`, `b̂` the fourth-order weights (`b̂₇ = 1/40`).
const E: [(usize, f64); 6] = [
    (0, 71.0 / 57600.0),
    (2, -71.0 / 16695.0),
    (3, 71.0 / 1920.0),
    (4, -17253.0 / 339200.0),
    (5, 22.0 / 525.0),
    (6, -1.0 / 40.0),
];

/// `dⱼ` of the dense output coefficient `r₅` (Fortran `D1 … D7`).
const D: [(usize, f64); 6] = [
    (0, -12715105075.0 / 11282082432.0),
    (2, 87487479700.0 / 32700410799.0),
    (3, -10690763975.0 / 1880347072.0),
    (4, 701980252875.0 / 199316789632.0),
    (5, -1453857185.0 / 822651844.0),
    (6, 69997945.0 / 29380423.0),
];

/// SciPy's `SAFETY`.
const SAFETY: f64 = 0.9;
/// SciPy's `MIN_FACTOR`: a rejection shrinks the step at most ×0.2.
const MIN_FACTOR: f64 = 0.2;
/// SciPy's `MAX_FACTOR`: an acceptance grows the step at most ×10.
const MAX_FACTOR: f64 = 10.0;
/// `−1/(p̂ + 1)` with `p̂ = 4` the order of the error estimate.
const ERROR_EXPONENT: f64 = -0.2;

/// One step of size `h` from `(t, y)` with `k[0] = f(t, y)` given: the stages `k[1..6]`, the
/// fifth-order solution `y₁` and `k[6] = f(t + h, y₁)`. Written once for every number type: run
/// on reals by [`Rk45`] and on dual numbers over a frozen step sequence by [`super::tangent`].
#[inline(always)]
pub(crate) fn step<D, F, const N: usize>(
    field: &mut F,
    t: D,
    y: &CanonicalPair<N, D>,
    h: D,
    k: &mut [CanonicalPair<N, D>; 7],
) -> Result<CanonicalPair<N, D>>
where
    D: DualNum<f64> + Copy,
    F: FnMut(D, &SVector<D, N>, &SVector<D, N>) -> Result<CanonicalPair<N, D>>,
{
    macro_rules! stage {
        ($($i:literal)*) => {$(
            let (q, p) = advance(y, h, A[$i], &k[..]);
            k[$i] = field(t + h * C[$i], &q, &p)?;
        )*};
    }
    stage!(1 2 3 4 5);
    let y1 = advance(y, h, &B, &k[..]);
    k[6] = field(t + h, &y1.0, &y1.1)?;
    Ok(y1)
}

/// The root-mean-square error norm `‖err‖ = √(Σᵢ (h eᵢ/skᵢ)²/n)`,
/// `skᵢ = atol + rtol·max(|y₀ᵢ|, |y₁ᵢ|)`.
fn error_norm<const N: usize>(
    y: &CanonicalPair<N>,
    y1: &CanonicalPair<N>,
    k: &[CanonicalPair<N>; 7],
    h: f64,
    rtol: f64,
    atol: f64,
) -> f64 {
    let e = combine(&E, &k[..]);
    let scaled = flat(&e)
        .zip(flat(y).zip(flat(y1)))
        .map(move |(ei, (a, b))| ei * h / (atol + rtol * a.abs().max(b.abs())));
    norm2(scaled) / ((2 * N) as f64).sqrt()
}

/// `rtol ∈ [RTOL_MIN, 1)` (see the [module documentation](self#tolerances)).
fn check_rtol(rtol: f64) -> Result<f64> {
    let r = finite("RK45 relative tolerance rtol", rtol)?;
    if (Rk45::RTOL_MIN..1.0).contains(&r) {
        Ok(r)
    } else {
        Err(Error::out_of_domain(
            "RK45 relative tolerance rtol",
            r,
            format!(
                "[{:e}, 1): below 100ε the error estimate is rounding noise (SciPy raises such \
                 an rtol to 100ε; use Rk45::RTOL_MIN); at 1 or above no digit is asked for",
                Rk45::RTOL_MIN
            ),
        ))
    }
}

/// The Dormand–Prince 5(4) integrator with SciPy's `RK45` control (see the
/// [module documentation](self)).
///
/// The fields are public knobs; [`Rk45::new`] and the `with_*` builders check them, and
/// [`Method::run`] checks them again.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Rk45 {
    /// Relative tolerance, in `[`[`Rk45::RTOL_MIN`]`, 1)`.
    pub rtol: f64,
    /// Absolute tolerance (`> 0`).
    pub atol: f64,
    /// Initial step size magnitude; `None` selects it automatically (SciPy's
    /// `select_initial_step`).
    pub h0: Option<f64>,
    /// Largest step size magnitude; `None` for no bound (SciPy's `max_step = ∞`).
    pub h_max: Option<f64>,
    /// Maximum number of attempted steps; `None` (the default) for the budget that scales with
    /// the span.
    pub max_steps: Option<usize>,
}

impl Rk45 {
    /// Smallest relative tolerance accepted: `100 ε`, the floor SciPy imposes.
    pub const RTOL_MIN: f64 = 100.0 * f64::EPSILON;

    /// Dormand–Prince 5(4) with tolerances `rtol ∈ [RTOL_MIN, 1)`, `atol > 0` and the step budget
    /// that scales with the span.
    ///
    /// # Errors
    /// [`Error::NonFinite`] / [`Error::OutOfDomain`] for a non-finite tolerance or one outside its
    /// range.
    pub fn new(rtol: f64, atol: f64) -> Result<Self> {
        Ok(Self {
            rtol: check_rtol(rtol)?,
            atol: positive("RK45 absolute tolerance atol", atol)?,
            h0: None,
            h_max: None,
            max_steps: None,
        })
    }

    /// The same with a given initial step size magnitude `h0 > 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] / [`Error::OutOfDomain`] unless `h0` is finite and positive.
    pub fn with_h0(mut self, h0: f64) -> Result<Self> {
        self.h0 = Some(positive("RK45 initial step h0", h0)?);
        Ok(self)
    }

    /// The same with a largest step size magnitude `h_max > 0`.
    ///
    /// # Errors
    /// [`Error::NonFinite`] / [`Error::OutOfDomain`] unless `h_max` is finite and positive.
    pub fn with_h_max(mut self, h_max: f64) -> Result<Self> {
        self.h_max = Some(positive("RK45 largest step h_max", h_max)?);
        Ok(self)
    }

    /// The same with at most `max_steps ≥ 1` attempted steps (instead of the budget that scales
    /// with the span; `usize::MAX` for no limit — the caller's choice).
    ///
    /// # Errors
    /// [`Error::OutOfDomain`] for `max_steps = 0`.
    pub fn with_max_steps(mut self, max_steps: usize) -> Result<Self> {
        self.max_steps = Some(max_steps);
        self.validate()?;
        Ok(self)
    }

    /// Check every knob.
    ///
    /// # Errors
    /// [`Error::NonFinite`] or [`Error::OutOfDomain`] naming the bad knob.
    pub fn validate(&self) -> Result<()> {
        check_rtol(self.rtol)?;
        positive("RK45 absolute tolerance atol", self.atol)?;
        if let Some(h0) = self.h0 {
            positive("RK45 initial step h0", h0)?;
        }
        if let Some(h) = self.h_max {
            positive("RK45 largest step h_max", h)?;
        }
        if self.max_steps == Some(0) {
            return Err(Error::out_of_domain("RK45 max_steps", 0.0, "≥ 1"));
        }
        Ok(())
    }
}

/// Dense output of one step (HNW I §II.6, Fortran `CONTD5`); `r₅` is formed on the first call of
/// [`Dense::at`].
struct Rk45Dense<'a, const N: usize> {
    prev: &'a State<N>,
    next: &'a State<N>,
    h: f64,
    k: &'a [CanonicalPair<N>; 7],
    r5: OnceCell<CanonicalPair<N>>,
}

impl<const N: usize> Dense<N> for Rk45Dense<'_, N> {
    fn at(&self, t: f64) -> State<N> {
        if t == self.prev.t {
            return *self.prev;
        }
        if t == self.next.t {
            return *self.next;
        }
        let h = self.h;
        let r5 = self.r5.get_or_init(|| {
            let (q, p) = combine(&D, &self.k[..]);
            (q * h, p * h)
        });
        let s = (t - self.prev.t) / h;
        let s1 = 1.0 - s;
        let eval = |y0: &SVector<f64, N>,
                    y1: &SVector<f64, N>,
                    k1: &SVector<f64, N>,
                    k7: &SVector<f64, N>,
                    r5: &SVector<f64, N>| {
            SVector::<f64, N>::from_fn(|i, _| {
                let r2 = y1[i] - y0[i];
                let r3 = h * k1[i] - r2;
                let r4 = r2 - h * k7[i] - r3;
                y0[i] + s * (r2 + s1 * (r3 + s * (r4 + s1 * r5[i])))
            })
        };
        let (k1, k7) = (&self.k[0], &self.k[6]);
        State {
            t,
            q: eval(&self.prev.q, &self.next.q, &k1.0, &k7.0, &r5.0),
            p: eval(&self.prev.p, &self.next.p, &k1.1, &k7.1, &r5.1),
        }
    }
}

impl<S: FirstOrderSystem<N>, const N: usize> Method<S, N> for Rk45 {
    fn label(&self) -> String {
        format!(
            "{} rtol={:e} atol={:e}",
            methods::RK45.label(),
            self.rtol,
            self.atol
        )
    }

    fn run<O: Observer<N>>(
        &self,
        problem: &Problem<'_, S, N>,
        observer: &mut O,
    ) -> Result<Report<N>> {
        self.validate()?;
        let clock = Instant::now();
        let system = problem.system;
        let mut work = Work::default();
        let (rtol, atol) = (self.rtol, self.atol);
        let (mut state, t1, f0) = adaptive_start("RK45", problem)?;
        let t0 = state.t;
        let span = t1 - t0;
        let dir = span.signum();
        let h_max = self.h_max.unwrap_or(f64::INFINITY);

        let zero = (SVector::<f64, N>::zeros(), SVector::<f64, N>::zeros());
        let mut k: [CanonicalPair<N>; 7] = [zero; 7];
        k[0] = f0;
        work.gradients += 1;
        // |h| of the next attempt (SciPy's `h_abs`).
        let mut h_abs = match self.h0 {
            Some(h0) => h0.min(h_max),
            None => initial_step(
                system,
                &state,
                &k[0],
                dir,
                h_max.min(span.abs()),
                rtol,
                atol,
                StartRule {
                    rms: true,
                    exponent: 0.2,
                },
                &mut work,
            )?
            .abs(),
        };
        let max_steps = step_budget(self.max_steps, span, h_abs);
        observer.start(&state);

        let mut attempts = 0usize;
        let mut last_err = f64::NAN;
        loop {
            // Ten units in the last place of t toward t₁ (SciPy), at least the smallest normal.
            let min_step =
                (10.0 * (next_toward(state.t, dir) - state.t).abs()).max(f64::MIN_POSITIVE);
            h_abs = if h_abs > h_max {
                h_max
            } else {
                h_abs.max(min_step)
            };
            let mut rejected = false;
            let (h, t_new, y1) = loop {
                if attempts >= max_steps {
                    return Err(budget_exhausted(
                        "RK45",
                        "Rk45",
                        self.max_steps.is_none(),
                        max_steps,
                        [t0, state.t, t1],
                    ));
                }
                if h_abs.is_nan() || h_abs < min_step {
                    return Err(Error::NotConverged {
                        what: format!(
                            "RK45 step size at t = {}: |h| = {:e} below 10 ulp(t) = {:e} \
                             (singularity or stiffness; last error norm {:e})",
                            state.t, h_abs, min_step, last_err
                        ),
                        iterations: attempts,
                        residual: last_err,
                    });
                }
                attempts += 1;
                let mut t_new = state.t + dir * h_abs;
                if dir * (t_new - t1) > 0.0 {
                    t_new = t1;
                }
                let h = t_new - state.t;
                h_abs = h.abs();
                let y = (state.q, state.p);
                let y1 = step(&mut |t, q, p| system.field(t, q, p), state.t, &y, h, &mut k)?;
                work.gradients += 6;
                let mut err = error_norm(&y, &y1, &k, h, rtol, atol);
                if !(pair_finite(&y1) && pair_finite(&k[6])) || err.is_nan() {
                    err = f64::INFINITY;
                }
                last_err = err;
                if err < 1.0 {
                    let mut factor = if err == 0.0 {
                        MAX_FACTOR
                    } else {
                        MAX_FACTOR.min(SAFETY * err.powf(ERROR_EXPONENT))
                    };
                    if rejected {
                        factor = factor.min(1.0);
                    }
                    h_abs *= factor;
                    break (h, t_new, y1);
                }
                h_abs *= MIN_FACTOR.max(SAFETY * err.powf(ERROR_EXPONENT));
                rejected = true;
                work.rejected += 1;
            };
            work.steps += 1;
            let next = State {
                t: t_new,
                q: y1.0,
                p: y1.1,
            };
            let last = t_new == t1;
            let (control, stop_state) = {
                let dense = Rk45Dense {
                    prev: &state,
                    next: &next,
                    h,
                    k: &k,
                    r5: OnceCell::new(),
                };
                observe(observer, &state, &next, &dense)?
            };
            let end;
            (state, end) = settle(control, next, stop_state, last, t1);
            if let Some(stopped) = end.or(last.then_some(false)) {
                return Ok(Report {
                    last: state,
                    stopped,
                    work,
                    elapsed: clock.elapsed(),
                });
            }
            k[0] = k[6];
        }
    }
}

/// The next double after `t` in the direction `dir` (`±1`).
fn next_toward(t: f64, dir: f64) -> f64 {
    if dir > 0.0 {
        t.next_up()
    } else {
        t.next_down()
    }
}

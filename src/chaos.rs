//! Chaos indicators from the tangent map of an integrator: the mean exponential growth factor of
//! nearby orbits (MEGNO) and the maximal Lyapunov exponent, for any Hamiltonian and any
//! fixed-step method, and maps of them over grids of initial conditions on every core.
//!
//! A deviation vector `δ` is carried along the orbit by the method's own tangent map: each step
//! runs on [`Dual64`] numbers whose infinitesimal parts are `δ`
//! ([`crate::integrate::tangent`]), so `δ_{k+1} = Ψ′_h(z_k) δ_k` exactly. `δ` is renormalised
//! to unit length after every step (the map is linear in `δ`, so this changes nothing but the
//! scale) and the logarithmic growth `r_k = ln(|δ_k| / |δ_{k−1}|)` accumulated.
//!
//! * Maximal Lyapunov exponent (Benettin, Galgani, Giorgilli & Strelcyn, *Meccanica* 15 (1980)
//!   9–20): `λ(t) = (1/t) ln(|δ(t)|/|δ(0)|) = (1/t) Σ r_k`.
//! * MEGNO (Cincotta & Simó, *Astron. Astrophys. Suppl.* 147 (2000) 205–228; Cincotta, Giordano
//!   & Simó, *Physica D* 182 (2003) 151–178):
//!
//!   ```math
//!   Y(t) = \frac{2}{t} \int_0^t \frac{\dot\delta\cdot\delta}{\delta\cdot\delta}\, s\, ds,
//!   \qquad \langle Y\rangle(t) = \frac1t \int_0^t Y(s)\, ds,
//!   ```
//!
//!   with `∫ (δ̇·δ/|δ|²) s ds` summed as `Σ r_k (s_{k−1} + s_k)/2` and the mean by the trapezoidal
//!   rule over the steps (`s` the time elapsed). For quasi-periodic motion `⟨Y⟩ → 2` (linear
//!   growth of `δ` by the shear of the tori), for a stable periodic orbit `⟨Y⟩ → 0` (bounded `δ`
//!   on the energy surface), for chaotic motion `⟨Y⟩ ≈ λt/2`.
//!
//! The deviation should lie on the energy surface (`∇H·δ = 0`) where the distinction between a
//! periodic orbit and a torus matters: a component across it grows linearly by the dependence of
//! the period on the energy. [`energy_surface_deviation`] projects one there.
//!
//! [`chaos_map`] runs many initial conditions in parallel with `rayon`; every cell is computed
//! by the same sequential code, so the map is the same bit for bit whatever the number of
//! threads.

use crate::error::{finite, Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::integrate::tangent::fixed_steps;
use crate::integrate::{Fixed, OneStep, Problem, Work};
use crate::phase::{CanonicalPair, State};
use nalgebra::SVector;
use num_dual::Dual64;
use rayon::prelude::*;

/// The chaos indicators at one time of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ChaosIndicators {
    /// The time `t`.
    pub t: f64,
    /// MEGNO `Y(t)`.
    pub megno: f64,
    /// Mean MEGNO `⟨Y⟩(t)`.
    pub mean_megno: f64,
    /// Finite-time maximal Lyapunov exponent `λ(t) = ln(|δ(t)|/|δ(0)|)/(t − t₀)`.
    pub lyapunov: f64,
}

/// A run of the chaos indicators: their values at the end and at regularly spaced steps.
#[derive(Clone, Debug, PartialEq)]
pub struct ChaosRun<const N: usize> {
    /// The indicators at `t₁`.
    pub last: ChaosIndicators,
    /// The indicators after every `⌈steps/records⌉`-th step (and at `t₁`).
    pub history: Vec<ChaosIndicators>,
    /// The final state of the orbit.
    pub state: State<N>,
    /// Work of the run.
    pub work: Work,
}

/// `δ` with its component along `∇H` removed, `δ − (∇H·δ/|∇H|²) ∇H` (a deviation on the
/// energy surface through `(t, q, p)`).
///
/// # Errors
/// [`Error::NonFinite`] for a non-finite entry or gradient; [`Error::InvalidInput`] where
/// `∇H = 0` (an equilibrium: every direction is tangent) or the projection vanishes (`δ ∥ ∇H`).
pub fn energy_surface_deviation<S: Hamiltonian<N>, const N: usize>(
    system: &S,
    state: &State<N>,
    deviation: &CanonicalPair<N>,
) -> Result<CanonicalPair<N>> {
    let state = State::new(state.t, state.q, state.p)?;
    check_deviation(deviation)?;
    let (_, hq, hp) = system.gradient(state.t, &state.q, &state.p);
    let g2 = hq.norm_squared() + hp.norm_squared();
    if !g2.is_finite() {
        return Err(Error::NonFinite {
            what: "∇H at the state of the deviation".into(),
            value: g2,
        });
    }
    if g2 == 0.0 {
        return Err(Error::invalid(
            "deviation on the energy surface",
            "∇H = 0 at the state (an equilibrium)",
        ));
    }
    let c = (hq.dot(&deviation.0) + hp.dot(&deviation.1)) / g2;
    let d = (deviation.0 - hq * c, deviation.1 - hp * c);
    let n = (d.0.norm_squared() + d.1.norm_squared()).sqrt();
    let n0 = (deviation.0.norm_squared() + deviation.1.norm_squared()).sqrt();
    if n.partial_cmp(&(1e-12 * n0)) != Some(std::cmp::Ordering::Greater) {
        return Err(Error::invalid(
            "deviation on the energy surface",
            "the deviation is parallel to ∇H",
        ));
    }
    Ok(d)
}

fn check_deviation<const N: usize>(d: &CanonicalPair<N>) -> Result<f64> {
    for v in d.0.iter().chain(d.1.iter()) {
        finite("deviation vector component", *v)?;
    }
    let n = (d.0.norm_squared() + d.1.norm_squared()).sqrt();
    if !(n > 0.0 && n.is_finite()) {
        return Err(Error::out_of_domain(
            "length of the deviation vector",
            n,
            "positive and finite",
        ));
    }
    Ok(n)
}

/// MEGNO and the maximal Lyapunov exponent of the orbit of `problem` under `method`, with the
/// initial deviation `deviation = (δq, δp)` carried by the method's tangent map (see the
/// [module docs](self)); `records` values of the indicators along the run are kept in
/// [`ChaosRun::history`] (0 for none).
///
/// # Errors
/// [`Error::OutOfDomain`] for a zero or non-finite deviation; [`Error::NonFinite`] when the orbit
/// or its deviation leaves the finite numbers (an escape); the errors of the method's steps.
pub fn chaos_indicators<S: Hamiltonian<N>, M: OneStep<S, N>, const N: usize>(
    problem: &Problem<'_, S, N>,
    method: &Fixed<M>,
    deviation: &CanonicalPair<N>,
    records: usize,
) -> Result<ChaosRun<N>> {
    let n0 = check_deviation(deviation)?;
    // Re-check a hand-built method value.
    method.check_steps()?;
    let steps = method.steps;
    let every = if records == 0 {
        usize::MAX
    } else {
        steps.div_ceil(records.min(steps))
    };
    let (t0, t1) = (problem.start.t, problem.t1);
    let dt = (t1 - t0) / steps as f64;
    if !(dt.is_finite() && dt != 0.0) {
        return Err(Error::out_of_domain(
            "step size",
            dt,
            "finite and non-zero (span / steps)",
        ));
    }
    let s0 = &problem.start;
    let q0 = SVector::<Dual64, N>::from_fn(|i, _| Dual64::new(s0.q[i], deviation.0[i] / n0));
    let p0 = SVector::<Dual64, N>::from_fn(|i, _| Dual64::new(s0.p[i], deviation.1[i] / n0));
    let mut work = Work::default();
    let (mut weighted, mut area, mut growth, mut y_prev, mut s_prev) = (0.0, 0.0, 0.0, 0.0, 0.0);
    let mut history = Vec::new();
    let mut last = ChaosIndicators {
        t: t0,
        megno: 0.0,
        mean_megno: 0.0,
        lyapunov: 0.0,
    };
    let (q, p) = fixed_steps(
        method,
        t0,
        t1,
        &q0,
        &p0,
        |t, q, p, h| {
            let step = method
                .method
                .increment(problem.system, t, q, p, h, &mut work);
            work.steps += 1;
            step
        },
        |k, t, sums| {
            let norm = sums
                .q
                .iter()
                .chain(sums.p.iter())
                .map(|v| v.eps * v.eps)
                .sum::<f64>()
                .sqrt();
            let finite_state = sums.q.iter().chain(sums.p.iter()).all(|v| v.re.is_finite());
            if !(finite_state && norm.is_finite() && norm > 0.0) {
                return Err(Error::NonFinite {
                    what: format!(
                        "orbit or deviation at t = {t:e} ({}; an escape?)",
                        OneStep::<S, N>::name(&method.method)
                    ),
                    value: if finite_state { norm } else { f64::NAN },
                });
            }
            for v in sums
                .q
                .iter_mut()
                .chain(sums.p.iter_mut())
                .chain(sums.cq.iter_mut())
                .chain(sums.cp.iter_mut())
            {
                v.eps /= norm;
            }
            let r = norm.ln();
            let s = t - t0;
            growth += r;
            weighted += r * 0.5 * (s_prev + s);
            let y = 2.0 * weighted / s;
            area += 0.5 * (y_prev + y) * (s - s_prev);
            (y_prev, s_prev) = (y, s);
            last = ChaosIndicators {
                t,
                megno: y,
                mean_megno: area / s,
                lyapunov: growth / s,
            };
            if (k + 1) % every == 0 || (records > 0 && k + 1 == steps) {
                history.push(last);
            }
            Ok(())
        },
    )?;
    let t = last.t;
    Ok(ChaosRun {
        last,
        history,
        state: State::new(t, q.map(|v| v.re), p.map(|v| v.re))?,
        work,
    })
}

/// The chaos indicators at `t₀ + span` of every initial state in `starts`, computed in parallel
/// (`rayon`, on the current thread pool); `None` for a start whose run fails (an escape from a
/// bounded region, a step that does not converge). Every cell is the sequential
/// [`chaos_indicators`] of its start, so the map does not depend on the number of threads.
///
/// # Errors
/// [`Error::NonFinite`] for a non-finite start or span, [`Error::InvalidInput`] for a zero span;
/// the errors of [`chaos_indicators`]'s checks of the method and the deviation.
pub fn chaos_map<S, M, const N: usize>(
    system: &S,
    starts: &[State<N>],
    span: f64,
    method: &Fixed<M>,
    deviation: &CanonicalPair<N>,
) -> Result<Vec<Option<ChaosIndicators>>>
where
    S: Hamiltonian<N> + Sync,
    M: OneStep<S, N> + Sync,
{
    let span = finite("span of a chaos map", span)?;
    if span == 0.0 {
        return Err(Error::invalid("span of a chaos map", "zero"));
    }
    check_deviation(deviation)?;
    method.check_steps()?;
    let problems = starts
        .iter()
        .map(|s| Problem::new(system, s.t, s.q, s.p, s.t + span))
        .collect::<Result<Vec<_>>>()?;
    Ok(problems
        .par_iter()
        .map(|problem| {
            chaos_indicators(problem, method, deviation, 0)
                .ok()
                .map(|run| run.last)
        })
        .collect())
}

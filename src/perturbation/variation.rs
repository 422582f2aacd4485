//! Variation of constants: the general form [Ardema 18.1, eqs. 18.1–18.10] and the
//! Lagrange-bracket form [Ardema 18.1, eqs. 18.11–18.25].
//!
//! # General form
//! If `x = φ(γ, t)` is the general solution of `ẋ = X(x, t)` (state `x ∈ ℝ²ᴺ`, constants
//! `γ ∈ ℝ²ᴺ`), the perturbed system `ẋ = X + g(x, t)` is solved by `x = φ(γ(t), t)` with
//!
//! ```math
//! \frac{\partial \varphi}{\partial \gamma}\,\dot\gamma = g(\varphi(\gamma, t), t)
//! \quad\Longrightarrow\quad
//! \dot\gamma = \Big(\frac{\partial \varphi}{\partial \gamma}\Big)^{-1} g
//! \qquad\text{[Ardema eqs. 18.5–18.10]},
//! ```
//!
//! because `∂φ/∂t = X(φ, t)` for every fixed `γ`. The Jacobian `∂φ/∂γ` comes by AD from
//! [`GeneralSolution::state`], written once generic over [`DualNum`]; it is inverted with the
//! crate's conditioning check ([`PhaseMatrix::checked_inverse`]): where the elements are singular
//! (Kepler elements at `e = 0` and `i = 0`, an amplitude–phase pair at zero amplitude)
//! the result is [`Error::Singular`] with the point and a reciprocal condition estimate; where a
//! derivative of `φ` is infinite (the pendulum elements `θ = (√(2α)/n) sin n(t − β)` at `α = 0`)
//! the same error with `rcond = 0`.
//!
//! # Lagrange-bracket form
//! With `x = (q, p)`, `q = F(γ, t)`, `p = G(γ, t)`, the unperturbed system Hamiltonian (possibly
//! with its own non-conservative forces [Ardema eq. 18.25]) and a perturbation in the momentum
//! equation only, `ṗ = −∂H/∂q + R(q, p, t)`, multiplying the general form by `(∂φ/∂γ)ᵀ J` gives
//!
//! ```math
//! \sum_s [\gamma_j, \gamma_s]\,\dot\gamma_s = \sum_r R_r \frac{\partial F_r}{\partial \gamma_j},
//! \qquad j = 1\dots 2N \qquad\text{[Ardema eq. 18.21]},
//! ```
//!
//! with the Lagrange brackets,
//! `[u, v] = Σ_r (∂q_r/∂u ∂p_r/∂v − ∂p_r/∂u ∂q_r/∂v)` [Ardema eq. 16.24]. For a conservative
//! perturbation `R = −∂U/∂q` the right-hand side is `−∂U*/∂γ_j`, `U*(γ, t) = U(F(γ, t), t)`
//! [Ardema eqs. 18.22–18.24] — Lagrange's planetary equations. For a Hamiltonian unperturbed
//! system the bracket matrix is independent of `t` (Lagrange's theorem, [Ardema eq. 18.15]);
//! [`bracket_time_defect`] measures `∂[γ_j, γ_s]/∂t` exactly by nested AD.
//!
//! The element equations are general ODEs; run them with [`crate::perturbation::ode`].

use super::ode::{ElementOde, ElementPair};
use crate::ad::{gradient, lift, phase_gradient, PhaseDual};
use crate::error::{all_finite, Error, Lazy, Result};
use crate::phase::{check_phase, PhaseMatrix};
use nalgebra::{DMatrix, SVector};
use num_dual::{Dual64, DualNum};

/// The general solution `x = φ(γ, t)` of an unperturbed system, written once for every dual type.
///
/// The state `x = (x₁, x₂)` and the constants `γ = (γ₁, γ₂)` are each split into two `N`-blocks.
/// For the Lagrange-bracket form the blocks of the state are `(q, p) = (F(γ, t), G(γ, t))`.
/// The constants are numbered `γ₁[0] … γ₁[N−1], γ₂[0] … γ₂[N−1]` in bracket matrices.
pub trait GeneralSolution<const N: usize> {
    /// `φ(γ, t)`; may return NaN outside the domain of the elements.
    fn state<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        gamma1: &SVector<D, N>,
        gamma2: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>);
}

/// A perturbation `g(x, t)` of the full state equation `ẋ = X(x, t) + g(x, t)`.
pub trait Perturbation<const N: usize> {
    /// `g(x, t)` in blocks `(g₁, g₂)` matching the state blocks.
    fn perturbation<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        x1: &SVector<D, N>,
        x2: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>);
}

/// A perturbing force `R(q, p, t)` in the momentum equation only, `ṗ = −∂H/∂q + R`.
pub trait MomentumForce<const N: usize> {
    /// `R(q, p, t)`.
    fn force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> SVector<D, N>;
}

/// A disturbing function `U(q, t)`: the conservative perturbation `R = −∂U/∂q`.
pub trait DisturbingFunction<const N: usize> {
    /// `U(q, t)`.
    fn disturbing_function<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> D;
}

/// A disturbing function whose `M` parameters can be differentiated: `U(k; t, q)` written once
/// with the parameters in the dual type of the arguments (see [`Parametric`](crate::Parametric)).
/// The perturbed two-body system built on it
/// ([`PerturbedTwoBody`](crate::perturbation::forces::PerturbedTwoBody)) is then itself
/// [`Parametric`](crate::Parametric), so `∂(state)/∂k` follows from
/// [`ParameterSensitivity`](crate::integrate::ParameterSensitivity).
pub trait ParametricDisturbance<const N: usize, const M: usize>: DisturbingFunction<N> {
    /// The parameters' names.
    const NAMES: [&'static str; M];
    /// Their nominal values.
    fn parameters(&self) -> SVector<f64, M>;
    /// `U(k; t, q)`.
    fn disturbing_function_with<D: DualNum<f64> + Copy>(
        &self,
        k: &SVector<D, M>,
        t: D,
        q: &SVector<D, N>,
    ) -> D;
}

/// A momentum force as a full-state perturbation `g = (0, R)` (for the general form).
#[derive(Clone, Copy, Debug)]
pub struct InMomentumEquation<R>(pub R);

impl<R: MomentumForce<N>, const N: usize> Perturbation<N> for InMomentumEquation<R> {
    fn perturbation<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        (SVector::zeros(), self.0.force(t, q, p))
    }
}

/// The force `R = −∂U/∂q` of a disturbing function, by AD (for comparing the two right-hand sides).
#[derive(Clone, Copy, Debug)]
pub struct GradientForce<U>(pub U);

impl<U: DisturbingFunction<N>, const N: usize> MomentumForce<N> for GradientForce<U> {
    fn force<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        _p: &SVector<D, N>,
    ) -> SVector<D, N> {
        let (_, du) = gradient(
            |qd| {
                self.0
                    .disturbing_function(crate::ad::GradDual::from_re(t), qd)
            },
            q,
        );
        -du
    }
}

/// A [`GeneralSolution`] as a [`PhaseMap`](crate::brackets::PhaseMap) `γ ↦ φ(γ, t)` (so that
/// [`crate::brackets::certify`] and friends apply to it).
#[derive(Clone, Copy, Debug)]
pub struct SolutionMap<'a, S: ?Sized>(pub &'a S);

impl<S: GeneralSolution<N> + ?Sized, const N: usize> crate::brackets::PhaseMap<N>
    for SolutionMap<'_, S>
{
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        self.0.state(t, q, p)
    }
}

fn at<'a, const N: usize>(
    t: f64,
    g1: &'a SVector<f64, N>,
    g2: &'a SVector<f64, N>,
) -> Lazy<impl Fn(&mut std::fmt::Formatter<'_>) -> std::fmt::Result + 'a> {
    Lazy(move |f| write!(f, "t = {t}, γ = ({:?}, {:?})", g1.as_slice(), g2.as_slice()))
}

/// The Jacobian `∂φ/∂γ` of the general solution at `(γ, t)` by AD (rows: state components
/// `x₁, x₂`; columns: constants `γ₁, γ₂`).
///
/// Errors: non-finite input; [`Error::InvalidInput`] where `φ` itself is not finite (outside the
/// domain of the elements); [`Error::Singular`] with `rcond = 0` where a derivative is infinite or
/// NaN at a finite state (the elements are singular there).
pub fn solution_jacobian<S: GeneralSolution<N> + ?Sized, const N: usize>(
    solution: &S,
    t: f64,
    gamma1: &SVector<f64, N>,
    gamma2: &SVector<f64, N>,
) -> Result<PhaseMatrix<N>> {
    check_phase(t, gamma1, gamma2)?;
    crate::brackets::jacobian(&AsPhaseMap(solution), t, gamma1, gamma2).map_err(|e| match e {
        // φ itself not finite: outside the domain of the elements.
        Error::NonFinite { what, value } => Error::invalid(
            "general solution φ(γ, t)",
            format!(
                "{what} is {value} at {}: outside the domain of the elements",
                at(t, gamma1, gamma2)
            ),
        ),
        // φ finite but a derivative not: the elements are singular there.
        Error::InvalidInput { .. } => Error::Singular {
            what: "∂φ/∂γ (not finite: the elements are singular here)".into(),
            at: at(t, gamma1, gamma2).to_string(),
            rcond: 0.0,
        },
        other => other,
    })
}

/// A general solution at its time argument as a [`PhaseMap`](crate::brackets::PhaseMap)
/// `(γ₁, γ₂) ↦ φ(γ, t)`, so that its Jacobian comes from [`crate::brackets::jacobian`].
struct AsPhaseMap<'a, S: ?Sized>(&'a S);

impl<S: GeneralSolution<N> + ?Sized, const N: usize> crate::brackets::PhaseMap<N>
    for AsPhaseMap<'_, S>
{
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        gamma1: &SVector<D, N>,
        gamma2: &SVector<D, N>,
    ) -> (SVector<D, N>, SVector<D, N>) {
        self.0.state(t, gamma1, gamma2)
    }
}

/// Right-hand side of the general variation-of-constants equations,
/// `γ̇ = (∂φ/∂γ)⁻¹ g(φ(γ, t), t)` [Ardema eq. 18.10].
///
/// Errors as [`solution_jacobian`], plus [`Error::Singular`] (with the point and the reciprocal
/// condition estimate of the equilibrated Jacobian) when `∂φ/∂γ` is singular or too ill-conditioned
/// to invert, and [`Error::NonFinite`] when `g` is not finite.
pub fn variation_of_constants_rhs<S, G, const N: usize>(
    solution: &S,
    perturbation: &G,
    t: f64,
    gamma1: &SVector<f64, N>,
    gamma2: &SVector<f64, N>,
) -> Result<ElementPair<N>>
where
    S: GeneralSolution<N> + ?Sized,
    G: Perturbation<N> + ?Sized,
{
    let m = solution_jacobian(solution, t, gamma1, gamma2)?;
    let (x1, x2) = solution.state(t, gamma1, gamma2);
    let (g1, g2) = perturbation.perturbation(t, &x1, &x2);
    all_finite(
        format_args!("perturbation g at {}; g₁", at(t, gamma1, gamma2)),
        g1.as_slice(),
    )?;
    all_finite(
        format_args!("perturbation g at {}; g₂", at(t, gamma1, gamma2)),
        g2.as_slice(),
    )?;
    let inv = m.checked_inverse(
        "∂φ/∂γ (variation of constants; singular elements)",
        || at(t, gamma1, gamma2).to_string(),
    )?;
    Ok(inv.apply(&g1, &g2))
}

/// The element equations of the general form as an ODE: `γ̇ = (∂φ/∂γ)⁻¹ g`.
#[derive(Clone, Copy, Debug)]
pub struct VariationOfConstants<S, G> {
    /// The unperturbed general solution `φ(γ, t)`.
    pub solution: S,
    /// The perturbation `g(x, t)`.
    pub perturbation: G,
}

impl<S: GeneralSolution<N>, G: Perturbation<N>, const N: usize> ElementOde<N>
    for VariationOfConstants<S, G>
{
    fn rhs(&self, t: f64, a: &SVector<f64, N>, b: &SVector<f64, N>) -> Result<ElementPair<N>> {
        variation_of_constants_rhs(&self.solution, &self.perturbation, t, a, b)
    }
}

/// The Lagrange-bracket matrix `[γ_j, γ_s] = ((∂φ/∂γ)ᵀ J (∂φ/∂γ))_js` of `(q, p) = φ(γ, t)`
/// [Ardema eqs. 16.24, 18.15], by AD.
pub fn lagrange_brackets<S: GeneralSolution<N> + ?Sized, const N: usize>(
    solution: &S,
    t: f64,
    gamma1: &SVector<f64, N>,
    gamma2: &SVector<f64, N>,
) -> Result<PhaseMatrix<N>> {
    Ok(solution_jacobian(solution, t, gamma1, gamma2)?.symplectic_form())
}

/// The bracket matrix and its exact time derivative `∂[γ_j, γ_s]/∂t` at `(γ, t)`, by AD nested
/// in `t` (a [`Dual64`] inside the phase-space dual numbers). Lagrange's theorem: the derivative
/// vanishes when `φ` is the general solution of a Hamiltonian system.
pub fn lagrange_brackets_with_rate<S: GeneralSolution<N> + ?Sized, const N: usize>(
    solution: &S,
    t: f64,
    gamma1: &SVector<f64, N>,
    gamma2: &SVector<f64, N>,
) -> Result<(PhaseMatrix<N>, PhaseMatrix<N>)> {
    // Validates the point and classifies singularities first.
    solution_jacobian(solution, t, gamma1, gamma2)?;
    let td = Dual64::new(t, 1.0);
    let (c1, c2): (SVector<Dual64, N>, SVector<Dual64, N>) = (lift(gamma1), lift(gamma2));
    // jac[i][j] = ∂x_i/∂γ_j as a function of t (value and t-derivative).
    let mut jac = vec![vec![Dual64::from(0.0); 2 * N]; 2 * N];
    for (i, row) in jac.iter_mut().enumerate() {
        let (_, d1, d2) = phase_gradient(
            |a, b| {
                let (x1, x2) = solution.state(PhaseDual::from_re(td), a, b);
                if i < N {
                    x1[i]
                } else {
                    x2[i - N]
                }
            },
            &c1,
            &c2,
        );
        for j in 0..N {
            row[j] = d1[j];
            row[N + j] = d2[j];
        }
    }
    let mut value = DMatrix::zeros(2 * N, 2 * N);
    let mut rate = DMatrix::zeros(2 * N, 2 * N);
    for j in 0..2 * N {
        for s in 0..2 * N {
            let l = (0..N).fold(Dual64::from(0.0), |acc, r| {
                acc + jac[r][j] * jac[N + r][s] - jac[N + r][j] * jac[r][s]
            });
            value[(j, s)] = l.re;
            rate[(j, s)] = l.eps;
        }
    }
    let what = |e: Error| match e {
        Error::NonFinite { .. } => Error::Singular {
            what: "∂[γ_j, γ_s]/∂t (not finite: the elements are singular here)".into(),
            at: at(t, gamma1, gamma2).to_string(),
            rcond: 0.0,
        },
        other => other,
    };
    Ok((
        PhaseMatrix::from_dmatrix(&value).map_err(what)?,
        PhaseMatrix::from_dmatrix(&rate).map_err(what)?,
    ))
}

/// Time independence of the Lagrange brackets along sample times, at fixed `γ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BracketDefect {
    /// `max_k ‖L(t_k) − L(t_0)‖_max` over the samples.
    pub variation: f64,
    /// `max_k ‖∂L/∂t (t_k)‖_max` (exact, nested AD).
    pub rate: f64,
    /// `max_k ‖L(t_k)‖_max` (the scale against which both are small).
    pub scale: f64,
}

/// Measure the time dependence of the bracket matrix `[γ_j, γ_s]` of `solution` at fixed `γ` over
/// the sample times (at least one). Zero up to rounding for the general solution of a Hamiltonian
/// system [Ardema eq. 18.15]; a non-zero defect means that `φ` is not such a solution (or that the
/// unperturbed system carries non-conservative forces, [Ardema eq. 18.25]).
pub fn bracket_time_defect<S: GeneralSolution<N> + ?Sized, const N: usize>(
    solution: &S,
    times: &[f64],
    gamma1: &SVector<f64, N>,
    gamma2: &SVector<f64, N>,
) -> Result<BracketDefect> {
    let Some(&t0) = times.first() else {
        return Err(Error::invalid("sample times", "empty"));
    };
    let (l0, _) = lagrange_brackets_with_rate(solution, t0, gamma1, gamma2)?;
    let mut d = BracketDefect {
        variation: 0.0,
        rate: 0.0,
        scale: 0.0,
    };
    for &t in times {
        let (l, r) = lagrange_brackets_with_rate(solution, t, gamma1, gamma2)?;
        d.variation = d.variation.max(l.sub(&l0).max_abs());
        d.rate = d.rate.max(r.max_abs());
        d.scale = d.scale.max(l.max_abs());
    }
    Ok(d)
}

/// Solve Lagrange's equations `Σ_s [γ_j, γ_s] γ̇_s = b_j` for `γ̇` [Ardema eqs. 18.21,
/// 18.24] given the bracket matrix `L` and the right-hand side `b = (b₁, b₂)` (either
/// `Σ_r R_r ∂F_r/∂γ_j` or `−∂U*/∂γ_j`). [`Error::Singular`] if `L` is singular.
pub fn lagrange_planetary_rhs<const N: usize>(
    bracket_matrix: &PhaseMatrix<N>,
    b: &ElementPair<N>,
) -> Result<ElementPair<N>> {
    if !bracket_matrix.is_finite() {
        return Err(Error::invalid(
            "Lagrange-bracket matrix",
            "has non-finite entries",
        ));
    }
    all_finite("right-hand side b₁", b.0.as_slice())?;
    all_finite("right-hand side b₂", b.1.as_slice())?;
    let inv = bracket_matrix
        .checked_inverse("Lagrange-bracket matrix [γ_j, γ_s] of γ", || {
            format!("{bracket_matrix:?}")
        })?;
    Ok(inv.apply(&b.0, &b.1))
}

/// The generalised force on the elements, `b_j = Σ_r R_r ∂F_r/∂γ_j` [Ardema eq. 18.21], with
/// `R` evaluated at `(q, p) = φ(γ, t)`.
pub fn force_on_elements<S, R, const N: usize>(
    solution: &S,
    force: &R,
    t: f64,
    gamma1: &SVector<f64, N>,
    gamma2: &SVector<f64, N>,
) -> Result<ElementPair<N>>
where
    S: GeneralSolution<N> + ?Sized,
    R: MomentumForce<N> + ?Sized,
{
    let m = solution_jacobian(solution, t, gamma1, gamma2)?;
    project_force(&m, solution, force, t, gamma1, gamma2)
}

/// `b_j = Σ_r R_r ∂F_r/∂γ_j` with the Jacobian `m = ∂φ/∂γ` already formed.
fn project_force<S, R, const N: usize>(
    m: &PhaseMatrix<N>,
    solution: &S,
    force: &R,
    t: f64,
    gamma1: &SVector<f64, N>,
    gamma2: &SVector<f64, N>,
) -> Result<ElementPair<N>>
where
    S: GeneralSolution<N> + ?Sized,
    R: MomentumForce<N> + ?Sized,
{
    let (q, p) = solution.state(t, gamma1, gamma2);
    let r = force.force(t, &q, &p);
    all_finite(
        format_args!("force R at {}; R", at(t, gamma1, gamma2)),
        r.as_slice(),
    )?;
    Ok((m.qq.transpose() * r, m.qp.transpose() * r))
}

/// `γ̇ = L⁻¹ b` of the Lagrange-bracket form, `L = (∂φ/∂γ)ᵀ J (∂φ/∂γ)`,
/// `b = (∂F/∂γ)ᵀ R`, from one AD Jacobian of the general solution.
fn bracket_form_rhs<S, R, const N: usize>(
    solution: &S,
    force: &R,
    t: f64,
    gamma1: &SVector<f64, N>,
    gamma2: &SVector<f64, N>,
) -> Result<ElementPair<N>>
where
    S: GeneralSolution<N> + ?Sized,
    R: MomentumForce<N> + ?Sized,
{
    let m = solution_jacobian(solution, t, gamma1, gamma2)?;
    let rhs = project_force(&m, solution, force, t, gamma1, gamma2)?;
    lagrange_planetary_rhs(&m.symplectic_form(), &rhs)
}

/// `−∂U*/∂γ` with `U*(γ, t) = U(F(γ, t), t)` [Ardema eqs. 18.22–18.24], by AD through the
/// general solution.
pub fn disturbing_function_gradient<S, U, const N: usize>(
    solution: &S,
    u: &U,
    t: f64,
    gamma1: &SVector<f64, N>,
    gamma2: &SVector<f64, N>,
) -> Result<ElementPair<N>>
where
    S: GeneralSolution<N> + ?Sized,
    U: DisturbingFunction<N> + ?Sized,
{
    check_phase(t, gamma1, gamma2)?;
    let (value, d1, d2) = phase_gradient(
        |a, b| {
            let td = PhaseDual::from_re(t);
            let (q, _) = solution.state(td, a, b);
            u.disturbing_function(td, &q)
        },
        gamma1,
        gamma2,
    );
    if !value.is_finite() {
        return Err(Error::NonFinite {
            what: format!("U* at {}", at(t, gamma1, gamma2)),
            value,
        });
    }
    if !(d1.iter().chain(d2.iter()).all(|v| v.is_finite())) {
        return Err(Error::Singular {
            what: "∂U*/∂γ (not finite: the elements are singular here)".into(),
            at: at(t, gamma1, gamma2).to_string(),
            rcond: 0.0,
        });
    }
    Ok((-d1, -d2))
}

/// The element equations of the Lagrange-bracket form with a momentum force `R`:
/// `γ̇ = L⁻¹ b`, `L = [γ_j, γ_s]`, `b_j = Σ_r R_r ∂F_r/∂γ_j`.
#[derive(Clone, Copy, Debug)]
pub struct LagrangeBracketForm<S, R> {
    /// The unperturbed general solution `(q, p) = (F, G)(γ, t)`.
    pub solution: S,
    /// The perturbing force `R(q, p, t)`.
    pub force: R,
}

impl<S: GeneralSolution<N>, R: MomentumForce<N>, const N: usize> ElementOde<N>
    for LagrangeBracketForm<S, R>
{
    fn rhs(&self, t: f64, a: &SVector<f64, N>, b: &SVector<f64, N>) -> Result<ElementPair<N>> {
        bracket_form_rhs(&self.solution, &self.force, t, a, b)
    }
}

/// Lagrange's planetary equations (conservative perturbation):
/// `Σ_s [γ_j, γ_s] γ̇_s = −∂U*/∂γ_j`.
///
/// The right-hand side is formed by the chain rule, `−∂U*/∂γ_j = Σ_r (−∂U/∂q_r) ∂F_r/∂γ_j`
/// (the force of [`GradientForce`] projected with the Jacobian `∂φ/∂γ` that also gives the
/// brackets): one AD pass through the general solution per evaluation, not two
/// ([`disturbing_function_gradient`] differentiates `U*` through the solution directly; the
/// tests compare both).
#[derive(Clone, Copy, Debug)]
pub struct PlanetaryEquations<S, U> {
    /// The unperturbed general solution `(q, p) = (F, G)(γ, t)`.
    pub solution: S,
    /// The disturbing function `U(q, t)`.
    pub disturbing: U,
}

impl<S: GeneralSolution<N>, U: DisturbingFunction<N>, const N: usize> ElementOde<N>
    for PlanetaryEquations<S, U>
{
    fn rhs(&self, t: f64, a: &SVector<f64, N>, b: &SVector<f64, N>) -> Result<ElementPair<N>> {
        bracket_form_rhs(&self.solution, &GradientForce(&self.disturbing), t, a, b)
    }
}

//! Implicit equations `r(t, a, b, u) = 0` solved for `u ∈ ℝᴺ` by damped Newton with the AD
//! Jacobian, with exact derivatives of the root with respect to `(t, a, b)` in any dual type.
//!
//! The real root `u*` is found on `f64`; the Jacobian `∂r/∂u` comes from one [`GradDual`] pass.
//! Derivatives of `u*` then follow from `D::NDERIV` Newton steps carried out in the dual type `D`
//! with the real Jacobian frozen: with `m` the ideal of infinitesimal parts, the error obeys
//! `e₊ = (I − J₀⁻¹ J(u*)) e + O(e²)` and `J(u*) − J₀ ∈ m`, so after `k` steps it lies in `m^{k+1}` —
//! every Taylor coefficient up to order `NDERIV` is exact (implicit function theorem; Griewank &
//! Walther 2008, §15.1). This is what makes implicitly defined maps (Legendre transforms, maps from
//! generating functions, inverses) differentiable — and certifiable — like explicit ones.
//!
//! The step from a real root to its Taylor coefficients is [`lift_root`] for any state shape
//! (a vector, a phase-space pair, the stages of a collocation method; the real Jacobian applied
//! through its inverse or an LU factorisation) and [`lift_scalar_root`] for one unknown; every
//! implicit solve of the crate (shooting, reduction, Kepler's equations, collocation stages, map
//! inversion) goes through them. The real root comes from one Newton iteration (damped from the
//! given starts, contracting along a continuation, or polishing a converged root).

use crate::ad::{lift, real_parts, real_times, GradDual};
use crate::error::{finite, Error, Result};
use crate::phase::checked_inverse;
use crate::vector_space::VectorSpace;
use nalgebra::{SMatrix, SVector};
use num_dual::DualNum;

/// A system of `N` equations `r(t, a, b, u) = 0` in the unknowns `u`, with parameters `a, b ∈ ℝᴺ`
/// and `t`, written once for every dual type.
pub trait ImplicitSystem<const N: usize> {
    /// The residual `r(t, a, b, u)`.
    fn residual<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        a: &SVector<D, N>,
        b: &SVector<D, N>,
        u: &SVector<D, N>,
    ) -> SVector<D, N>;
}

/// The converged real root with the data needed downstream.
#[derive(Clone, Copy, Debug)]
pub struct Root<const N: usize> {
    /// The root `u*`.
    pub u: SVector<f64, N>,
    /// `(∂r/∂u)⁻¹` at the root.
    pub jacobian_inverse: SMatrix<f64, N, N>,
    /// Newton iterations used.
    pub iterations: usize,
}

const MAX_ITER: usize = 60;

/// Residual and Jacobian `∂r/∂u` on reals, in one AD pass.
fn residual_and_jacobian<S: ImplicitSystem<N> + ?Sized, const N: usize>(
    sys: &S,
    t: f64,
    a: &SVector<f64, N>,
    b: &SVector<f64, N>,
    u: &SVector<f64, N>,
) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
    let ud: SVector<GradDual<f64, f64, nalgebra::Const<N>>, N> =
        SVector::from_fn(|i, _| GradDual::variable(u[i], i));
    let r = sys.residual(GradDual::from_re(t), &lift(a), &lift(b), &ud);
    let value = SVector::from_fn(|i, _| *r[i].value());
    let jac = SMatrix::from_fn(|i, j| r[i].eps()[j]);
    (value, jac)
}

/// Newton's stopping rule, scale-relative so that problems posed in any units converge to full
/// precision (and never stop early because their numbers happen to be small): the residual is at
/// rounding level relative to the terms it compares (`‖r‖ ≤ 4ε·scale`), or the step is
/// (`‖Δu‖ ≤ 2ε‖u‖`), or the iteration has reached its rounding floor (a step below `√ε‖u‖` that
/// no longer shrinks quadratically). Norms are max-norms.
pub(crate) fn newton_converged(
    residual: f64,
    scale: f64,
    step: f64,
    size: f64,
    previous_step: f64,
) -> bool {
    let eps = f64::EPSILON;
    residual <= 4.0 * eps * scale
        || step <= 2.0 * eps * size
        || (step <= eps.sqrt() * size && step >= 0.5 * previous_step)
}

/// How one run of [`newton`] steps, when it stops and what it returns on failure.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Steps {
    /// Damped Newton: backtracking on `‖r‖₂` (halving the step until the residual decreases,
    /// down to a step of `2⁻³⁰`; trial points outside the residual's domain count as worse);
    /// stops by [`newton_converged`]; at most [`MAX_ITER`] steps.
    Damped,
    /// Full steps, abandoned unless each is at most a quarter of the one before (Deuflhard's
    /// monotonicity test); stops by [`newton_converged`]; at most 8 steps.
    Contracting,
    /// Full steps from a converged root while they reduce `‖r‖∞` and are below `ε^{1/4}‖u‖`;
    /// stops once a step is at rounding level `2ε‖u‖` or after 16 steps, returning the last
    /// point reached (never an error past the start).
    Polishing,
}

impl Steps {
    fn max_iterations(self) -> usize {
        match self {
            Steps::Damped => MAX_ITER,
            Steps::Contracting => 8,
            Steps::Polishing => 16,
        }
    }
}

/// Newton's iteration `u ← u − J(u)⁻¹ r(t, a, b, u)` on reals from `start`, with the Jacobian
/// `J = ∂r/∂u` by AD, stepping and stopping as `steps` says. The scale of the residual in the
/// stopping rule is `max(‖b‖, ‖r + b‖)`; at convergence the final correction is applied if it
/// does not increase the residual. A singular or ill-conditioned Jacobian is
/// [`Error::Singular`]; a non-finite residual, too many steps or a step that does not contract
/// is [`Error::NotConverged`]. [Deuflhard, *Newton Methods for Nonlinear Problems* (Springer
/// 2004), §§1.2, 3.1; Dennis & Schnabel, *Numerical Methods for Unconstrained Optimization and
/// Nonlinear Equations* (SIAM 1996), §6.3.]
fn newton<S: ImplicitSystem<N> + ?Sized, const N: usize>(
    sys: &S,
    t: f64,
    a: &SVector<f64, N>,
    b: &SVector<f64, N>,
    start: &SVector<f64, N>,
    steps: Steps,
    what: &str,
) -> Result<Root<N>> {
    let mut u = *start;
    let (mut r, mut jac) = residual_and_jacobian(sys, t, a, b, &u);
    let mut iterations = 0;
    let mut previous_step = f64::INFINITY;
    loop {
        if !r.amax().is_finite() {
            return Err(Error::NotConverged {
                what: format!("{what} (residual not finite at u = {u:?})"),
                iterations,
                residual: r.norm(),
            });
        }
        let inv = checked_inverse(&jac, what, || {
            format!("t = {t}, a = {a:?}, b = {b:?}, u = {u:?}")
        })?;
        let du = inv * r;
        let step = du.amax();
        let root = |u| Root {
            u,
            jacobian_inverse: inv,
            iterations,
        };
        if steps == Steps::Polishing {
            // Only corrections at the level of the error left by the stopping rule (a larger
            // step near a pole of the residual could land on another root).
            let small = step <= f64::EPSILON.sqrt().sqrt() * u.amax();
            let at_rounding = previous_step <= 2.0 * f64::EPSILON * u.amax();
            if r.amax() == 0.0 || !small || at_rounding || iterations >= steps.max_iterations() {
                return Ok(root(u));
            }
        } else {
            let scale = b.amax().max((r + b).amax());
            if newton_converged(r.amax(), scale, step, u.amax(), previous_step) {
                // Apply the final correction unless it makes the residual worse.
                let un = u - du;
                let (rn, _) = residual_and_jacobian(sys, t, a, b, &un);
                return Ok(root(if rn.amax() <= r.amax() { un } else { u }));
            }
            if iterations >= steps.max_iterations() {
                return Err(Error::NotConverged {
                    what: what.into(),
                    iterations,
                    residual: r.norm(),
                });
            }
            if steps == Steps::Contracting && iterations > 0 && step > 0.25 * previous_step {
                return Err(Error::NotConverged {
                    what: format!("{what} (Newton's iteration does not contract)"),
                    iterations,
                    residual: r.norm(),
                });
            }
        }
        previous_step = step;
        let (un, rn, jn) = if steps == Steps::Damped {
            // Backtracking: halve the step until the residual decreases (accept a step of
            // 2⁻³⁰). Trial points outside the residual's domain (non-finite) are rejected like
            // worse ones.
            let mut lambda = 1.0;
            loop {
                let un = u - du * lambda;
                let (rn, jn) = residual_and_jacobian(sys, t, a, b, &un);
                let finite_trial = rn.amax().is_finite() && jn.iter().all(|x| x.is_finite());
                if finite_trial && (rn.norm() < r.norm() || lambda < 1e-9) {
                    break (un, rn, jn);
                }
                if lambda < 1e-9 {
                    return Err(Error::NotConverged {
                        what: format!("{what} (every step from u = {u:?} leaves the domain)"),
                        iterations,
                        residual: r.norm(),
                    });
                }
                lambda *= 0.5;
            }
        } else {
            let un = u - du;
            let (rn, jn) = residual_and_jacobian(sys, t, a, b, &un);
            let better = rn.amax() < r.amax() && jn.iter().all(|x| x.is_finite());
            if steps == Steps::Polishing && !better {
                return Ok(root(u));
            }
            (un, rn, jn)
        };
        (u, r, jac) = (un, rn, jn);
        iterations += 1;
    }
}

/// Solve `r(t, a, b, u) = 0` on reals by damped Newton (backtracking on `‖r‖`) from each start in
/// turn until one converges; the first failure is reported if all do.
///
/// Convergence by the scale-relative stopping rule (residual, step or rounding floor) with the
/// residual's scale `max(‖b‖, ‖r + b‖)`; the final Newton correction is applied if it does not
/// increase the residual. A singular or ill-conditioned Jacobian is [`Error::Singular`].
pub fn solve_real<S: ImplicitSystem<N> + ?Sized, const N: usize>(
    sys: &S,
    t: f64,
    a: &SVector<f64, N>,
    b: &SVector<f64, N>,
    starts: &[SVector<f64, N>],
    what: &str,
) -> Result<Root<N>> {
    let mut first_error = None;
    for start in starts {
        match newton(sys, t, a, b, start, Steps::Damped, what) {
            Ok(root) => return Ok(root),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    Err(first_error.unwrap_or_else(|| Error::invalid(what, "no starting point given")))
}

/// Solve `r(t, a, b, u) = 0` in the dual type `D`: the real root by [`solve_real`] (on the real
/// parts), then its exact derivatives by [`lift_root`] (see the [module docs](self)).
pub fn solve<S: ImplicitSystem<N> + ?Sized, D: DualNum<f64> + Copy, const N: usize>(
    sys: &S,
    t: D,
    a: &SVector<D, N>,
    b: &SVector<D, N>,
    starts: &[SVector<f64, N>],
    what: &str,
) -> Result<(SVector<D, N>, Root<N>)> {
    let root = solve_real(sys, t.re(), &real_parts(a), &real_parts(b), starts, what)?;
    Ok((refine(sys, t, a, b, &root)?, root))
}

/// The root of an implicit equation `r(u) = 0` whose data carry infinitesimal parts, with every
/// Taylor coefficient up to order `D::NDERIV` exact (implicit function theorem): from the real
/// root `u₀` (given as `root`, with zero infinitesimal parts) and `solve`, which applies the
/// inverse of the real Jacobian `J₀ = ∂r/∂u(u₀)` (an inverse matrix, an LU factorisation, a
/// derivative), `D::NDERIV` frozen-Jacobian Newton steps in `D`,
///
/// ```math
/// u_{k+1} = u_k - J_0^{-1}\,\big(r(u_k) - \operatorname{re} r(u_k)\big).
/// ```
///
/// With `m` the ideal of infinitesimal parts the error obeys `e₊ = (I − J₀⁻¹ J(u*)) e + O(e²)`
/// with `J(u*) − J₀ ∈ m`, so after `k` steps it lies in `m^{k+1}` [Griewank & Walther,
/// *Evaluating Derivatives*, 2nd ed., SIAM 2008, §15.1]. Only the infinitesimal part of the
/// residual enters, so the real part of the result is `u₀` itself: a real root left at rounding
/// level (`re r(u₀) = ρ ≠ 0`) keeps its value, and the derivatives are those of the root of
/// `r − ρ`, within `O(ρ)` of the exact ones. For `D = f64` no step is taken.
///
/// # Errors
/// The first error of `residual`; [`Error::NonFinite`] if the real root is not finite, or if a
/// residual or a correction is not finite at the root (its real parts; the infinitesimal parts
/// are not inspected).
pub fn lift_root<X: VectorSpace>(
    root: X,
    mut residual: impl FnMut(&X) -> Result<X>,
    solve: impl Fn(&X) -> X,
) -> Result<X> {
    let not_finite = |what: &str| Error::NonFinite {
        what: format!("{what} (lift of a root of an implicit equation to its derivatives)"),
        value: f64::NAN,
    };
    if !root.is_finite() {
        return Err(not_finite("real root"));
    }
    let mut u = root;
    for _ in 0..<X::Scalar as DualNum<f64>>::NDERIV {
        let r = residual(&u)?;
        u = u.sub(&solve(&r.infinitesimal()));
    }
    if !u.is_finite() {
        return Err(not_finite("residual or its linear solve at the root"));
    }
    Ok(u)
}

/// [`lift_root`] for one unknown: the root `u(x)` of `r(u) = 0` in the dual type `D`, from the
/// real root `u₀` and the real derivative `r′(u₀)`,
/// `u_{k+1} = u_k − (r(u_k) − re r(u_k)) / r′(u₀)`, `D::NDERIV` times.
///
/// # Errors
/// [`Error::NonFinite`] for a non-finite `u₀` or `r′(u₀)`, or a residual not finite at the root;
/// [`Error::Singular`] where `r′(u₀)` is zero or its reciprocal overflows (the implicit function
/// theorem does not apply).
pub fn lift_scalar_root<D: DualNum<f64> + Copy>(
    root: f64,
    derivative: f64,
    mut residual: impl FnMut(D) -> D,
) -> Result<D> {
    let derivative = finite("derivative r′(u₀) of an implicit equation", derivative)?;
    if !derivative.recip().is_finite() {
        return Err(Error::Singular {
            what: "derivative r′(u₀) of an implicit equation".into(),
            at: format!("u₀ = {root}, r′(u₀) = {derivative:e}"),
            rcond: 0.0,
        });
    }
    let u = lift_root(
        SVector::<D, 1>::from([D::from(root)]),
        |u| Ok(SVector::from([residual(u[0])])),
        |r| r.map(|x| x / derivative),
    )?;
    Ok(u[0])
}

/// The derivatives of a real root `root` of `r(t, a, b, u) = 0` with respect to `(t, a, b)`, by
/// [`lift_root`] with the frozen `(∂r/∂u)⁻¹` of `root` (see the [module docs](self)). `root` must
/// have been found at the real parts of `(t, a, b)` (by [`solve_real`], [`roots_real`] or
/// [`continue_root`]).
///
/// # Errors
/// As [`lift_root`].
pub fn refine<S: ImplicitSystem<N> + ?Sized, D: DualNum<f64> + Copy, const N: usize>(
    sys: &S,
    t: D,
    a: &SVector<D, N>,
    b: &SVector<D, N>,
    root: &Root<N>,
) -> Result<SVector<D, N>> {
    lift_root(
        lift(&root.u),
        |u| Ok(sys.residual(t, a, b, u)),
        |r| real_times(&root.jacobian_inverse, r),
    )
}

/// Continue Newton's iteration from a converged root while it still reduces the residual with
/// steps below `ε^{1/4}‖u‖` (at most 16 plain steps, stopping once the step is at rounding level
/// `2ε‖u‖`). The stopping rule of [`solve_real`] accepts a root at its "rounding floor" once
/// steps stop shrinking quadratically, which near a pole of the residual (a caustic of a
/// generating function) can leave an error of order `√ε`; polishing removes it wherever the
/// residual can still be reduced.
pub fn polish<S: ImplicitSystem<N> + ?Sized, const N: usize>(
    sys: &S,
    t: f64,
    a: &SVector<f64, N>,
    b: &SVector<f64, N>,
    root: Root<N>,
) -> Root<N> {
    match newton(sys, t, a, b, &root.u, Steps::Polishing, "polishing a root") {
        Ok(polished) => Root {
            iterations: root.iterations + polished.iterations,
            ..polished
        },
        Err(_) => root,
    }
}

/// Two roots are the same root if they agree to `√ε` relative to their size (Newton from
/// different starts converges to one root to within a few ulps times its condition).
fn same_root<const N: usize>(u: &SVector<f64, N>, v: &SVector<f64, N>) -> bool {
    (u - v).amax() <= f64::EPSILON.sqrt() * u.amax().max(v.amax()).max(f64::MIN_POSITIVE)
}

/// Every distinct root of `r(t, a, b, u) = 0` reached by damped Newton ([`solve_real`]) from the
/// given starts, in the order of the starts; with the first failure if some start did not
/// converge. Used to select a sheet of a multi-valued relation by a predicate.
pub fn roots_real<S: ImplicitSystem<N> + ?Sized, const N: usize>(
    sys: &S,
    t: f64,
    a: &SVector<f64, N>,
    b: &SVector<f64, N>,
    starts: &[SVector<f64, N>],
    what: &str,
) -> (Vec<Root<N>>, Option<Error>) {
    let mut roots: Vec<Root<N>> = Vec::with_capacity(starts.len());
    let mut first_error = None;
    for start in starts {
        match solve_real(sys, t, a, b, std::slice::from_ref(start), what) {
            Ok(root) => {
                if !roots.iter().any(|r| same_root(&r.u, &root.u)) {
                    roots.push(root);
                }
            }
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    (roots, first_error)
}

/// Largest number of continuation steps (accepted or rejected) [`continue_root`] may take.
pub const MAX_CONTINUATION_STEPS: usize = 4000;

/// Natural-parameter continuation of a root of `r(t, a, b, u) = 0` from a reference solution
/// `(t₀, a₀, b₀, u₀)` along the straight segment `(t, a, b)(s) = (1 − s)(t₀, a₀, b₀) + s(t₁, a₁, b₁)`,
/// `s ∈ [0, 1]`: the root at `s = 1` on the branch (sheet) through `u₀`.
///
/// Each step predicts by the secant through the last two accepted roots and corrects with plain
/// Newton; the step is accepted only if the corrector contracts, `‖Δu₂‖ ≤ ¼‖Δu₁‖` (Deuflhard's
/// monotonicity test), and the root moves by at most `⅛ max(‖u‖, ‖u₀‖)`, so that it does not jump
/// to a neighbouring branch; otherwise the step in `s` is halved. [Allgower & Georg, *Introduction to Numerical Continuation Methods* (SIAM 2003), ch. 2;
/// Deuflhard, *Newton Methods for Nonlinear Problems* (Springer 2004), §5.1.]
///
/// Errors: [`Error::InvalidInput`] if `u₀` does not solve the relation at `s = 0` to `√ε`
/// relative to the residual's scale; [`Error::NotConverged`] if the step in `s` falls below
/// `2⁻⁴⁰` (a fold or caustic of the relation on the segment, where the branch turns back or
/// two branches meet) or after [`MAX_CONTINUATION_STEPS`] steps.
pub fn continue_root<S: ImplicitSystem<N> + ?Sized, const N: usize>(
    sys: &S,
    from: (f64, &SVector<f64, N>, &SVector<f64, N>, &SVector<f64, N>),
    to: (f64, &SVector<f64, N>, &SVector<f64, N>),
    what: &str,
) -> Result<Root<N>> {
    let (t0, a0, b0, u0) = from;
    let (t1, a1, b1) = to;
    let at = |s: f64| (t0 + (t1 - t0) * s, a0 + (a1 - a0) * s, b0 + (b1 - b0) * s);
    // The reference must lie on the relation.
    let (r0, _) = residual_and_jacobian(sys, t0, a0, b0, u0);
    let scale0 = b0.amax().max((r0 + b0).amax());
    let on_relation = r0.amax() <= f64::EPSILON.sqrt() * scale0;
    if !on_relation {
        return Err(Error::invalid(
            format!("reference point of the sheet ({what})"),
            format!(
                "it does not satisfy the relation: residual {:e} against terms of size {:e} \
                 (u = {u0:?})",
                r0.amax(),
                scale0
            ),
        ));
    }
    let polished = solve_real(sys, t0, a0, b0, std::slice::from_ref(u0), what)?;
    // Plain Newton corrector with the contraction test; `None` if the step is to be rejected.
    let correct = |s: f64, u: SVector<f64, N>| -> Option<SVector<f64, N>> {
        let (t, a, b) = at(s);
        newton(sys, t, &a, &b, &u, Steps::Contracting, what)
            .ok()
            .map(|root| root.u)
    };
    let (mut s, mut u) = (0.0, polished.u);
    let mut last: Option<(f64, SVector<f64, N>)> = None;
    let mut h = 1.0f64;
    let mut steps = 0;
    while s < 1.0 {
        steps += 1;
        if steps > MAX_CONTINUATION_STEPS {
            return Err(Error::NotConverged {
                what: format!("{what} (continuation from the reference point, stopped at s = {s})"),
                iterations: steps - 1,
                residual: f64::NAN,
            });
        }
        let s_next = (s + h).min(1.0);
        let predicted = match last {
            Some((s_prev, u_prev)) => u + (u - u_prev) * ((s_next - s) / (s - s_prev)),
            None => u,
        };
        // A step may move the root by at most an eighth of its size, so that a contracting
        // corrector cannot settle on a neighbouring branch far from the predicted point.
        let limit = 0.125 * u.amax().max(polished.u.amax()).max(f64::MIN_POSITIVE);
        match correct(s_next, predicted).filter(|v| (v - u).amax() <= limit) {
            Some(u_next) => {
                last = Some((s, u));
                (s, u) = (s_next, u_next);
                h = (2.0 * h).min(1.0);
            }
            None => {
                h *= 0.5;
                if h < 2f64.powi(-40) {
                    return Err(Error::NotConverged {
                        what: format!(
                            "{what} (continuation from the reference point stalls at s = {s:e} of \
                             the segment: a fold or caustic of the relation lies between the \
                             reference and the point; choose a reference on the same side)"
                        ),
                        iterations: steps,
                        residual: f64::NAN,
                    });
                }
            }
        }
    }
    // The corrector converged at s = 1 (a further damped Newton solve could leave the branch).
    let (_, jac) = residual_and_jacobian(sys, t1, a1, b1, &u);
    let jacobian_inverse = checked_inverse(&jac, what, || {
        format!("t = {t1}, a = {a1:?}, b = {b1:?}, u = {u:?}")
    })?;
    Ok(Root {
        u,
        jacobian_inverse,
        iterations: steps,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use num_dual::{
        first_derivative, second_derivative, second_partial_derivative, third_derivative, Dual2,
        Dual64, HyperDual,
    };

    /// `y(x)` defined by `y³ + y = x`: at `x = 2`, `y = 1`; differentiating the relation,
    /// `y′ = 1/(3y² + 1) = 1/4`, `y″ = −6y y′³ = −3/32`, `y‴ = −(6y′³ + 18y y′y″)/(3y² + 1) = 21/256`.
    fn cubic_root<D: DualNum<f64> + Copy>(x: D) -> D {
        lift_scalar_root(1.0, 4.0, |y: D| y * y * y + y - x).unwrap()
    }

    #[test]
    fn scalar_lift_gives_the_taylor_coefficients_of_the_implicit_function() {
        let (y, dy) = first_derivative(cubic_root::<Dual64>, 2.0);
        assert_eq!(y, 1.0);
        assert!((dy - 0.25).abs() <= f64::EPSILON);
        let (y, dy, d2y) = second_derivative(cubic_root::<Dual2<f64, f64>>, 2.0);
        assert_eq!(y, 1.0);
        assert!((dy - 0.25).abs() <= f64::EPSILON);
        assert!((d2y + 3.0 / 32.0).abs() <= 2.0 * f64::EPSILON);
        let (_, _, _, d3y) = third_derivative(cubic_root, 2.0);
        assert!((d3y - 21.0 / 256.0).abs() <= 4.0 * f64::EPSILON);
        // On reals no step is taken: the real root comes back unchanged.
        assert_eq!(cubic_root(2.0), 1.0);
    }

    /// `u² + v² = a`, `u − v = b`, solved in closed form: `u = (b + w)/2`, `v = (w − b)/2` with
    /// `w = √(2a − b²)`; at `(a, b) = (5, 1)`, `(u, v) = (2, 1)`.
    fn circle_line<D: DualNum<f64> + Copy>(a: D, b: D) -> SVector<D, 2> {
        let jacobian = SMatrix::<f64, 2, 2>::new(4.0, 2.0, 1.0, -1.0);
        let inverse = jacobian.try_inverse().unwrap();
        lift_root(
            lift(&SVector::from([2.0, 1.0])),
            |u: &SVector<D, 2>| {
                Ok(SVector::from([
                    u[0] * u[0] + u[1] * u[1] - a,
                    u[0] - u[1] - b,
                ]))
            },
            |r| real_times(&inverse, r),
        )
        .unwrap()
    }

    fn circle_line_closed_form<D: DualNum<f64> + Copy>(a: D, b: D) -> SVector<D, 2> {
        let w = (a * 2.0 - b * b).sqrt();
        SVector::from([(b + w) * 0.5, (w - b) * 0.5])
    }

    #[test]
    fn vector_lift_matches_the_closed_form_root() {
        let close = |x: f64, y: f64| (x - y).abs() <= 4.0 * f64::EPSILON * y.abs().max(1.0);
        for i in 0..2 {
            // First and second derivatives in a (Dual64, Dual2), the mixed one in (a, b) (HyperDual).
            let (u, du) = first_derivative(|a: Dual64| circle_line(a, Dual64::from(1.0))[i], 5.0);
            let (v, dv) = first_derivative(
                |a: Dual64| circle_line_closed_form(a, Dual64::from(1.0))[i],
                5.0,
            );
            assert!(close(u, v) && close(du, dv), "{i}: {u} {du} vs {v} {dv}");
            let lifted = second_derivative(
                |a: Dual2<f64, f64>| circle_line(a, Dual2::from(1.0))[i],
                5.0,
            );
            let exact = second_derivative(
                |a: Dual2<f64, f64>| circle_line_closed_form(a, Dual2::from(1.0))[i],
                5.0,
            );
            assert!(close(lifted.2, exact.2), "{i}: {lifted:?} vs {exact:?}");
            let lifted = second_partial_derivative(
                |(a, b): (HyperDual<f64, f64>, _)| circle_line(a, b)[i],
                (5.0, 1.0),
            );
            let exact = second_partial_derivative(
                |(a, b): (HyperDual<f64, f64>, _)| circle_line_closed_form(a, b)[i],
                (5.0, 1.0),
            );
            assert!(
                close(lifted.1, exact.1) && close(lifted.2, exact.2) && close(lifted.3, exact.3),
                "{i}: {lifted:?} vs {exact:?}"
            );
        }
    }

    #[test]
    fn lifts_refuse_non_finite_and_singular_data() {
        let residual = |y: Dual64| y * y * y + y - Dual64::new(2.0, 1.0);
        for (root, derivative) in [(f64::NAN, 4.0), (1.0, f64::INFINITY), (f64::MAX, 4.0)] {
            let r = lift_scalar_root(root, derivative, residual);
            assert!(
                matches!(r, Err(Error::NonFinite { .. })),
                "{root}, {derivative}: {r:?}"
            );
        }
        for derivative in [0.0, -0.0, 5e-324] {
            let r = lift_scalar_root(1.0, derivative, residual);
            assert!(
                matches!(r, Err(Error::Singular { .. })),
                "{derivative}: {r:?}"
            );
        }
        let r = lift_scalar_root(1.0, 4.0, |y: Dual64| y - Dual64::new(f64::NAN, 1.0));
        assert!(matches!(r, Err(Error::NonFinite { .. })));
    }

    /// Newton's iteration in its three uses: damped from far, contracting from near,
    /// polishing at a root.
    #[test]
    fn newton_steps_damped_contracting_polishing() {
        let (a, b) = (SVector::from([2.0]), SVector::from([3.0]));
        let from = |u0: f64, steps| newton(&Cubic, 0.0, &a, &b, &SVector::from([u0]), steps, "");
        assert!((from(40.0, Steps::Damped).unwrap().u[0] - 1.0).abs() <= f64::EPSILON);
        assert!((from(1.1, Steps::Contracting).unwrap().u[0] - 1.0).abs() <= f64::EPSILON);
        // From u = 1000 full steps shrink only by ⅔ (u ← ≈ 2u/3): not contracting.
        assert!(matches!(
            from(1e3, Steps::Contracting),
            Err(Error::NotConverged { .. })
        ));
        let root = solve_real(&Cubic, 0.0, &a, &b, &[SVector::from([1.0])], "cubic").unwrap();
        let polished = polish(&Cubic, 0.0, &a, &b, root);
        assert_eq!(polished.u[0], 1.0);
        assert!((polished.jacobian_inverse[(0, 0)] - 0.2).abs() <= f64::EPSILON);
    }

    /// u³ + a u − b = 0.
    struct Cubic;
    impl ImplicitSystem<1> for Cubic {
        fn residual<D: DualNum<f64> + Copy>(
            &self,
            _t: D,
            a: &SVector<D, 1>,
            b: &SVector<D, 1>,
            u: &SVector<D, 1>,
        ) -> SVector<D, 1> {
            SVector::from([u[0] * u[0] * u[0] + a[0] * u[0] - b[0]])
        }
    }

    #[test]
    fn root_and_its_derivative() {
        let a = SVector::from([2.0]);
        // Root of u³ + 2u − 3 = 0 is u = 1; du/db = 1/(3u² + a) = 1/5.
        let (u, du) = first_derivative(
            |bd: Dual64| {
                solve(
                    &Cubic,
                    Dual64::from(0.0),
                    &lift(&a),
                    &SVector::from([bd]),
                    &[SVector::zeros()],
                    "cubic",
                )
                .map(|(u, _)| u[0])
                .unwrap_or(Dual64::from(f64::NAN))
            },
            3.0,
        );
        assert!((u - 1.0).abs() < 1e-15);
        assert!((du - 0.2).abs() < 1e-15);
    }

    #[test]
    fn singular_start_falls_back_and_reports() {
        // u³ − b = 0 with b = 0: the Jacobian 3u² vanishes at the root: a typed error.
        let z = SVector::from([0.0]);
        let r = solve_real(&Cubic, 0.0, &z, &z, &[z], "cubic");
        assert!(matches!(r, Err(Error::Singular { .. })));
        // With b = 8 the start u = 0 is singular; the second start converges.
        let r = solve_real(
            &Cubic,
            0.0,
            &z,
            &SVector::from([8.0]),
            &[z, SVector::from([1.0])],
            "cubic",
        )
        .unwrap();
        assert!((r.u[0] - 2.0).abs() < 1e-15);
    }
}

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

use crate::ad::{lift, real_parts, GradDual};
use crate::error::{Error, Result};
use crate::phase::checked_inverse;
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

/// Solve `r(t, a, b, u) = 0` on reals by damped Newton (backtracking on `‖r‖`) from each start in
/// turn until one converges; the first failure is reported if all do.
///
/// Convergence by the scale-relative stopping rule (residual, step or rounding floor) with the residual's scale `max(‖b‖, ‖r + b‖)`; the final
/// Newton correction is applied if it does not increase the residual. A singular or
/// ill-conditioned Jacobian is [`Error::Singular`].
pub fn solve_real<S: ImplicitSystem<N> + ?Sized, const N: usize>(
    sys: &S,
    t: f64,
    a: &SVector<f64, N>,
    b: &SVector<f64, N>,
    starts: &[SVector<f64, N>],
    what: &str,
) -> Result<Root<N>> {
    let newton = |mut u: SVector<f64, N>| -> Result<Root<N>> {
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
            let scale = b.amax().max((r + b).amax());
            if newton_converged(r.amax(), scale, du.amax(), u.amax(), previous_step) {
                // Apply the final correction unless it makes the residual worse.
                let un = u - du;
                let (rn, _) = residual_and_jacobian(sys, t, a, b, &un);
                return Ok(Root {
                    u: if rn.amax() <= r.amax() { un } else { u },
                    jacobian_inverse: inv,
                    iterations,
                });
            }
            if iterations >= MAX_ITER {
                return Err(Error::NotConverged {
                    what: what.into(),
                    iterations,
                    residual: r.norm(),
                });
            }
            previous_step = du.amax();
            // Backtracking: halve the step until the residual decreases (accept a step of 2⁻³⁰).
            // Trial points outside the residual's domain (non-finite) are rejected like worse ones.
            let mut lambda = 1.0;
            loop {
                let un = u - du * lambda;
                let (rn, jn) = residual_and_jacobian(sys, t, a, b, &un);
                let finite_trial = rn.amax().is_finite() && jn.iter().all(|x| x.is_finite());
                if finite_trial && (rn.norm() < r.norm() || lambda < 1e-9) {
                    u = un;
                    r = rn;
                    jac = jn;
                    break;
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
            iterations += 1;
        }
    };
    let mut first_error = None;
    for start in starts {
        match newton(*start) {
            Ok(root) => return Ok(root),
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    Err(first_error.unwrap_or_else(|| Error::invalid(what, "no starting point given")))
}

/// Solve `r(t, a, b, u) = 0` in the dual type `D`: the real root by [`solve_real`] (on the real
/// parts), then `D::NDERIV` frozen-Jacobian Newton steps in `D` (see the [module docs](self)).
pub fn solve<S: ImplicitSystem<N> + ?Sized, D: DualNum<f64> + Copy, const N: usize>(
    sys: &S,
    t: D,
    a: &SVector<D, N>,
    b: &SVector<D, N>,
    starts: &[SVector<f64, N>],
    what: &str,
) -> Result<(SVector<D, N>, Root<N>)> {
    let root = solve_real(sys, t.re(), &real_parts(a), &real_parts(b), starts, what)?;
    Ok((refine(sys, t, a, b, &root), root))
}

/// The derivatives of a real root `root` of `r(t, a, b, u) = 0` with respect to `(t, a, b)`:
/// `D::NDERIV` frozen-Jacobian Newton steps in the dual type `D` (see the [module docs](self)).
/// `root` must have been found at the real parts of `(t, a, b)` (by [`solve_real`],
/// [`roots_real`] or [`continue_root`]).
pub fn refine<S: ImplicitSystem<N> + ?Sized, D: DualNum<f64> + Copy, const N: usize>(
    sys: &S,
    t: D,
    a: &SVector<D, N>,
    b: &SVector<D, N>,
    root: &Root<N>,
) -> SVector<D, N> {
    let inv = root.jacobian_inverse;
    let mut u: SVector<D, N> = lift(&root.u);
    for _ in 0..D::NDERIV {
        let r = sys.residual(t, a, b, &u);
        u -= SVector::<D, N>::from_fn(|i, _| {
            (0..N).fold(D::from(0.0), |s, j| s + r[j] * inv[(i, j)])
        });
    }
    u
}

/// Continue Newton's iteration from a converged root while it still reduces the residual with
/// steps below `ε^{1/4}‖u‖` (at most 16 plain steps, stopping once the step is at rounding level
/// `2ε‖u‖`). The stopping rule of
/// [`solve_real`] accepts a root at its "rounding floor" once steps stop shrinking quadratically,
/// which near a pole of the residual (a caustic of a generating function) can leave an error of
/// order `√ε`; polishing removes it wherever the residual can still be reduced.
pub fn polish<S: ImplicitSystem<N> + ?Sized, const N: usize>(
    sys: &S,
    t: f64,
    a: &SVector<f64, N>,
    b: &SVector<f64, N>,
    root: Root<N>,
) -> Root<N> {
    let mut best = root;
    let (mut r, mut jac) = residual_and_jacobian(sys, t, a, b, &best.u);
    for _ in 0..16 {
        if r.amax() == 0.0 {
            break;
        }
        let Some(inv) = jac.try_inverse() else {
            break;
        };
        let du = inv * r;
        // Only corrections at the level of the error left by the stopping rule (a larger step
        // near a pole of the residual could land on another root).
        let small = du.amax() <= f64::EPSILON.sqrt().sqrt() * best.u.amax();
        if !small {
            break;
        }
        let un = best.u - du;
        let (rn, jn) = residual_and_jacobian(sys, t, a, b, &un);
        let better = rn.amax() < r.amax();
        if !better || !jn.iter().all(|x| x.is_finite()) {
            break;
        }
        let Some(inv_n) = jn.try_inverse() else {
            break;
        };
        best = Root {
            u: un,
            jacobian_inverse: inv_n,
            iterations: best.iterations + 1,
        };
        (r, jac) = (rn, jn);
        if du.amax() <= 2.0 * f64::EPSILON * un.amax() {
            break;
        }
    }
    best
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
    let correct = |s: f64, mut u: SVector<f64, N>| -> Option<SVector<f64, N>> {
        let (t, a, b) = at(s);
        let mut previous = f64::INFINITY;
        for iteration in 0..8 {
            let (r, jac) = residual_and_jacobian(sys, t, &a, &b, &u);
            if !r.amax().is_finite() {
                return None;
            }
            let inv = checked_inverse(&jac, what, String::new).ok()?;
            let du = inv * r;
            let step = du.amax();
            if !step.is_finite() || (iteration > 0 && step > 0.25 * previous) {
                // Not contracting: unless the iteration is already at its rounding floor.
                let scale = b.amax().max((r + b).amax());
                if newton_converged(r.amax(), scale, step, u.amax(), previous) {
                    return Some(u);
                }
                return None;
            }
            u -= du;
            let scale = b.amax().max((r + b).amax());
            if newton_converged(r.amax(), scale, step, u.amax(), previous) {
                return Some(u);
            }
            previous = step;
        }
        None
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
    use num_dual::{first_derivative, Dual64};

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

//! Points off the step grid: where each method takes them from, and the root search that puts
//! them on a surface.
//!
//! An observer asks a step for the state at a time `t` between its ends through
//! [`StepView::dense`](super::StepView) (requested times: [`Samples`](super::Samples); a surface
//! crossing: [`Section`](super::Section), [`Events`](super::Events); a terminal event:
//! [`Control::StopAt`](super::Control)). What it gets depends on the method:
//!
//! * **Fixed-step one-step methods** ([`Fixed`](super::Fixed) over any [`OneStep`]: splitting and
//!   composition methods, Gauss–Legendre, RK4, Wisdom–Holman/SABA, exact flows) take a *partial
//!   step* of the same method: from the step's start `zₙ = (tₙ, qₙ, pₙ)`,
//!
//!   ```math
//!   z(t) = \Psi_{t - t_n}(z_n),
//!   ```
//!
//!   the method's own map over the shorter step `t − tₙ` (with the run's compensated-summation
//!   carry, so the result is the one the driver would have stored). The point carries the
//!   method's global error at `tₙ` plus one local error `O((t − tₙ)^{p+1})`, i.e. it lies on the
//!   numerical trajectory to the method's own order `p`, not to an interpolant's (a cubic Hermite
//!   interpolant would cap every method at `O(h⁴)`). A symplectic method gives a symplectic
//!   partial map as well. The stored trajectory is not touched: the run continues from
//!   `zₙ₊₁` as before. Cost: one step of the method per requested point (per root-search
//!   iteration for surfaces), counted in the run's [`Work`].
//! * **DOP853** uses its own continuous extension (Hairer, Nørsett & Wanner, *Solving ODEs I*,
//!   2nd ed., II.6, Fortran `CONTD8`), whose error is of the order of the method's local error.
//!
//! A surface `s(t, q, p) = 0` crossed within a step is located by the Illinois variant of regula
//! falsi (Dowell & Jarratt, BIT 11 (1971) 168–174, doi:10.1007/BF01934364) on
//! `τ ↦ s(z(tₙ + τ))`, to the resolution of `f64` in time. For the fixed-step methods every
//! iterate is a partial step of the method, so the section point is the point of the method's
//! partial-step trajectory on the surface — the secant counterpart of Hénon's trick (M. Hénon,
//! "On the numerical computation of Poincaré maps", Physica D 5 (1982) 412–414,
//! doi:10.1016/0167-2789(82)90034-3), which integrates the last step with `s` as the independent
//! variable. Hénon's form needs the method to apply to `d(t, q, p)/ds = (ż)/ṡ`, which is not
//! separable even when `H` is; the secant form works for every method unchanged.

use super::{compensated_add, Dense, OneStep, State, Work};
use crate::error::{Error, Result};
use nalgebra::SVector;
use std::cell::{Cell, RefCell};

/// Dense output of a [`Fixed`](super::Fixed) step by partial steps of its method (see the
/// [module docs](self)). A failed partial step yields a NaN state and records the error, which the
/// driver returns from the run ([`PartialStep::finish`]).
pub(crate) struct PartialStep<'a, S, M, const N: usize> {
    system: &'a S,
    method: &'a M,
    prev: State<N>,
    next: State<N>,
    /// The compensated-summation carry of `prev` (zero for plain summation).
    carry: (SVector<f64, N>, SVector<f64, N>),
    compensated: bool,
    work: Cell<Work>,
    error: RefCell<Option<Error>>,
}

impl<'a, S, M: OneStep<S, N>, const N: usize> PartialStep<'a, S, M, N> {
    /// The dense output of the step `prev → next` of `method`.
    pub(crate) fn new(
        system: &'a S,
        method: &'a M,
        prev: State<N>,
        next: State<N>,
        carry: (SVector<f64, N>, SVector<f64, N>),
        compensated: bool,
    ) -> Self {
        Self {
            system,
            method,
            prev,
            next,
            carry,
            compensated,
            work: Cell::new(Work::default()),
            error: RefCell::new(None),
        }
    }

    /// The work of the partial steps taken, or the first error one of them met.
    pub(crate) fn finish(self) -> Result<Work> {
        match self.error.into_inner() {
            Some(e) => Err(e),
            None => Ok(self.work.get()),
        }
    }

    fn partial(&self, t: f64) -> Result<State<N>> {
        let dt = t - self.prev.t;
        if !dt.is_finite() {
            return Err(Error::NonFinite {
                what: format!(
                    "partial step of {} to t = {t:e} from t = {:e}",
                    self.method.name(),
                    self.prev.t
                ),
                value: dt,
            });
        }
        let mut work = self.work.get();
        let result = self.method.increment(
            self.system,
            self.prev.t,
            &self.prev.q,
            &self.prev.p,
            dt,
            &mut work,
        );
        self.work.set(work);
        let (dq, dp) = result?;
        let (mut q, mut p) = (self.prev.q, self.prev.p);
        if self.compensated {
            let (mut cq, mut cp) = self.carry;
            compensated_add(&mut q, &mut cq, &dq);
            compensated_add(&mut p, &mut cp, &dp);
        } else {
            q += dq;
            p += dp;
        }
        let s = State { t, q, p };
        if !s.is_finite() {
            return Err(Error::NonFinite {
                what: format!("{} partial-step state at t = {t:e}", self.method.name()),
                value: f64::NAN,
            });
        }
        Ok(s)
    }
}

impl<S, M: OneStep<S, N>, const N: usize> Dense<N> for PartialStep<'_, S, M, N> {
    /// The step's own ends are returned as computed; any other time by a partial step.
    fn at(&self, t: f64) -> State<N> {
        if t == self.next.t {
            return self.next;
        }
        if t == self.prev.t {
            return self.prev;
        }
        match self.partial(t) {
            Ok(s) => s,
            Err(e) => {
                let mut slot = self.error.borrow_mut();
                if slot.is_none() {
                    *slot = Some(e);
                }
                let nan = SVector::from_element(f64::NAN);
                State { t, q: nan, p: nan }
            }
        }
    }
}

/// The state where `g` (with values `ga`, `gb` of opposite signs, or `gb = 0`, at the ends of the
/// step) vanishes, located on the step's dense output by the Illinois iteration until the bracket
/// is two adjacent floating-point times (at most 200 evaluations). Returns the evaluated state
/// with the smaller `|g|` (the step's end when `gb = 0`), or `None` if `g` or the dense output
/// turned non-finite.
pub(crate) fn locate<const N: usize>(
    dense: &dyn Dense<N>,
    prev: &State<N>,
    next: &State<N>,
    ga: f64,
    gb: f64,
    mut g: impl FnMut(&State<N>) -> f64,
) -> Option<State<N>> {
    if gb == 0.0 {
        return Some(*next);
    }
    if ga == 0.0 {
        return Some(*prev);
    }
    let mut g_at = |t: f64| {
        let z = dense.at(t);
        let v = g(&z);
        v.is_finite().then_some((v, z))
    };
    illinois((prev.t, ga, *prev), (next.t, gb, *next), &mut g_at).map(|(z, _)| z)
}

/// The Illinois variant of regula falsi on a bracket `(a, f(a), zₐ)`, `(b, f(b), z_b)` with
/// `f(a)`, `f(b)` non-zero and of opposite signs: `eval(x)` returns `(f(x), z(x))`, or `None`
/// when either is not finite. Iterates until the bracket is two adjacent floating-point numbers
/// (at most 200 evaluations, fewer when `f` vanishes) and returns the evaluated `(z, f)` with the
/// smaller `|f|` (Dowell & Jarratt, BIT 11 (1971) 168–174).
pub(crate) fn illinois<Z: Copy>(
    (mut a, ga, mut za): (f64, f64, Z),
    (mut b, gb, mut zb): (f64, f64, Z),
    eval: &mut impl FnMut(f64) -> Option<(f64, Z)>,
) -> Option<(Z, f64)> {
    // `fa`, `fb` are halved by the Illinois rule; `sa`, `sb` keep the values at `a`, `b`.
    let (mut fa, mut fb, mut sa, mut sb) = (ga, gb, ga, gb);
    // The sign of `f` at `a`, fixed: the halved `fa` may underflow to zero.
    let negative_at_a = ga < 0.0;
    let mut side = 0i8;
    for _ in 0..200 {
        let mid = 0.5 * (a + b);
        if mid == a || mid == b {
            break;
        }
        let mut t = (a * fb - b * fa) / (fb - fa);
        // Keep the iterate strictly inside the bracket.
        if !(t.is_finite() && (t - a) * (t - b) < 0.0) {
            t = mid;
        }
        let (ft, z) = eval(t)?;
        if ft == 0.0 {
            return Some((z, ft));
        }
        if (ft < 0.0) == negative_at_a {
            (a, fa, sa, za) = (t, ft, ft, z);
            if side == -1 {
                fb *= 0.5;
            }
            side = -1;
        } else {
            (b, fb, sb, zb) = (t, ft, ft, z);
            if side == 1 {
                fa *= 0.5;
            }
            side = 1;
        }
    }
    Some(if sa.abs() <= sb.abs() {
        (za, sa)
    } else {
        (zb, sb)
    })
}

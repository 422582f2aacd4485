//! A minimal integrator for element equations: classical RK4 with fixed steps and a Richardson
//! error estimate.
//!
//! The element equations of [Ardema ch. 18] are general first-order systems `ẏ = f(t, y)` on pairs
//! `y = (a, b) ∈ ℝᴺ × ℝᴺ` (the `2N` constants as two blocks, like `(q, p)` elsewhere in the crate,
//! because stable Rust cannot spell `SVector<_, {2 * N}>`). They are not Hamilton's equations of a
//! [`Hamiltonian`](crate::Hamiltonian) in the elements (in general the elements are not canonical),
//! and the crate's drivers [`Fixed`](crate::integrate::Fixed) and
//! [`Dop853`](crate::integrate::Dop853) are bound to `S: Hamiltonian<N>` (DOP853 calls only
//! `vector_field_unchecked`, so generalising it needs nothing more than a `VectorField<N>` trait
//! with a blanket impl for Hamiltonians; that change is not made here).
//!
//! # Method
//! One step of size `h` is the classical RK4 step [`rk4_increment`] [Hairer, Nørsett & Wanner,
//! *Solving ODEs I*, II.1]:
//!
//! ```math
//! k_1 = f(t, y),\ k_2 = f(t + \tfrac h2, y + \tfrac h2 k_1),\ k_3 = f(t + \tfrac h2, y + \tfrac h2 k_2),\
//! k_4 = f(t + h, y + h k_3),\qquad y_1 = y + \tfrac h6 (k_1 + 2k_2 + 2k_3 + k_4).
//! ```
//!
//! Increments are accumulated with Kahan-compensated summation and the step times are computed
//! from the step index, so rounding grows like `√n` over `n` steps.
//!
//! # Richardson extrapolation
//! With `y_h` from `n` steps and `y_{h/2}` from `2n` steps, the global error of RK4 is
//! `C h⁴ + O(h⁵)`, so
//!
//! ```math
//! y \approx y_{h/2} + \frac{y_{h/2} - y_h}{15},\qquad
//! \mathrm{err}(y_{h/2}) \approx \frac{|y_{h/2} - y_h|}{15}
//! ```
//!
//! [HNW I, II.4 and II.9]. The extrapolated value is of order 5; its error is typically well below
//! the estimate, which is an estimate for `y_{h/2}`.

use crate::error::{all_finite, finite, Error, Result};
use crate::integrate::{compensated_add, rk4_increment};
use nalgebra::SVector;

/// A pair of `N`-vectors: the `2N` elements (or their rates) as two blocks.
pub type ElementPair<const N: usize> = (SVector<f64, N>, SVector<f64, N>);

/// A first-order system `ẏ = f(t, y)` for `y = (a, b) ∈ ℝᴺ × ℝᴺ`: the element equations.
pub trait ElementOde<const N: usize> {
    /// The right-hand side `f(t, a, b)`; an error where it is undefined (singular elements, a
    /// state outside the domain of the unperturbed solution).
    fn rhs(&self, t: f64, a: &SVector<f64, N>, b: &SVector<f64, N>) -> Result<ElementPair<N>>;
}

impl<O: ElementOde<N> + ?Sized, const N: usize> ElementOde<N> for &O {
    fn rhs(&self, t: f64, a: &SVector<f64, N>, b: &SVector<f64, N>) -> Result<ElementPair<N>> {
        (**self).rhs(t, a, b)
    }
}

/// The result of [`rk4_richardson`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Richardson<const N: usize> {
    /// Extrapolated value `y_{h/2} + (y_{h/2} − y_h)/15` at `t₁`.
    pub y: ElementPair<N>,
    /// `y_h` (`n` steps).
    pub coarse: ElementPair<N>,
    /// `y_{h/2}` (`2n` steps).
    pub fine: ElementPair<N>,
    /// Componentwise error estimate of `y_{h/2}`: `|y_{h/2} − y_h|/15`.
    pub error: ElementPair<N>,
    /// Evaluations of the right-hand side (both runs).
    pub evaluations: usize,
}

impl<const N: usize> Richardson<N> {
    /// Largest component of the error estimate.
    pub fn max_error(&self) -> f64 {
        self.error.0.amax().max(self.error.1.amax())
    }
}

fn check_rate<const N: usize>(t: f64, k: &ElementPair<N>) -> Result<()> {
    all_finite(format_args!("element rate ȧ at t = {t}; ȧ"), k.0.as_slice())?;
    all_finite(format_args!("element rate ḃ at t = {t}; ḃ"), k.1.as_slice())
}

/// Integrate `ode` from `(a₀, b₀)` at `t₀` to `t₁` with `steps` equal RK4 steps.
///
/// Errors: non-finite input, `t₁ = t₀`, `steps = 0`, or the first error of the right-hand side
/// (e.g. [`Error::Singular`] where the elements are singular).
pub fn rk4<O: ElementOde<N> + ?Sized, const N: usize>(
    ode: &O,
    t0: f64,
    a0: &SVector<f64, N>,
    b0: &SVector<f64, N>,
    t1: f64,
    steps: usize,
) -> Result<ElementPair<N>> {
    rk4_counted(ode, t0, a0, b0, t1, steps).map(|(y, _)| y)
}

fn rk4_counted<O: ElementOde<N> + ?Sized, const N: usize>(
    ode: &O,
    t0: f64,
    a0: &SVector<f64, N>,
    b0: &SVector<f64, N>,
    t1: f64,
    steps: usize,
) -> Result<(ElementPair<N>, usize)> {
    finite("t₀", t0)?;
    finite("t₁", t1)?;
    all_finite("a₀", a0.as_slice())?;
    all_finite("b₀", b0.as_slice())?;
    if t1 == t0 {
        return Err(Error::invalid("time span", "t₁ = t₀: nothing to integrate"));
    }
    if steps == 0 {
        return Err(Error::out_of_domain("number of steps", 0.0, "≥ 1"));
    }
    let h = (t1 - t0) / steps as f64;
    if !(h.is_finite() && h != 0.0) {
        return Err(Error::out_of_domain(
            "step size",
            h,
            "finite and non-zero (span / steps)",
        ));
    }
    let (mut a, mut b) = (*a0, *b0);
    let (mut ca, mut cb) = (SVector::zeros(), SVector::zeros());
    let mut evaluations = 0;
    for k in 0..steps {
        let t = t0 + h * k as f64;
        let f = |t: f64, (a, b): &ElementPair<N>| -> Result<ElementPair<N>> {
            evaluations += 1;
            let r = ode.rhs(t, a, b)?;
            check_rate(t, &r)?;
            Ok(r)
        };
        let (da, db) = rk4_increment(f, t, &(a, b), h)?;
        compensated_add(&mut a, &mut ca, &da);
        compensated_add(&mut b, &mut cb, &db);
    }
    Ok(((a, b), evaluations))
}

/// RK4 with `steps` and with `2·steps` steps, Richardson-extrapolated (see the
/// [module docs](self)); returns the extrapolated value and the error estimate.
pub fn rk4_richardson<O: ElementOde<N> + ?Sized, const N: usize>(
    ode: &O,
    t0: f64,
    a0: &SVector<f64, N>,
    b0: &SVector<f64, N>,
    t1: f64,
    steps: usize,
) -> Result<Richardson<N>> {
    let (coarse, e1) = rk4_counted(ode, t0, a0, b0, t1, steps)?;
    let fine_steps = steps
        .checked_mul(2)
        .ok_or_else(|| Error::out_of_domain("number of steps", steps as f64, "< usize::MAX/2"))?;
    let (fine, e2) = rk4_counted(ode, t0, a0, b0, t1, fine_steps)?;
    let d = (fine.0 - coarse.0, fine.1 - coarse.1);
    Ok(Richardson {
        y: (fine.0 + d.0 / 15.0, fine.1 + d.1 / 15.0),
        coarse,
        fine,
        error: (d.0.abs() / 15.0, d.1.abs() / 15.0),
        evaluations: e1 + e2,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ȧ = b, ḃ = −a (exact: rotation).
    struct Rotation;
    impl ElementOde<1> for Rotation {
        fn rhs(&self, _t: f64, a: &SVector<f64, 1>, b: &SVector<f64, 1>) -> Result<ElementPair<1>> {
            Ok((*b, -*a))
        }
    }

    #[test]
    fn rk4_fourth_order_and_richardson() {
        let (a0, b0) = (SVector::from([1.0]), SVector::from([0.0]));
        let r = rk4_richardson(&Rotation, 0.0, &a0, &b0, 1.0, 50).unwrap();
        let exact = 1.0f64.cos();
        let err_fine = (r.fine.0[0] - exact).abs();
        // The estimate is within a factor 2 of the true error of y_{h/2} (asymptotic regime).
        assert!(r.error.0[0] > 0.5 * err_fine && r.error.0[0] < 2.0 * err_fine);
        // The extrapolated value is much better.
        assert!((r.y.0[0] - exact).abs() < 0.05 * err_fine);
        assert_eq!(r.evaluations, 4 * 150);
    }

    #[test]
    fn rejects_bad_input() {
        let z = SVector::from([0.0]);
        assert!(rk4(&Rotation, 0.0, &z, &z, 0.0, 10).is_err());
        assert!(rk4(&Rotation, 0.0, &z, &z, 1.0, 0).is_err());
        assert!(rk4(&Rotation, 0.0, &SVector::from([f64::NAN]), &z, 1.0, 1).is_err());
    }
}

/// An [`ElementOde`] as a [`FirstOrderSystem`](crate::integrate::FirstOrderSystem), so that the
/// crate's adaptive integrator runs element equations: `integrate(&Problem::new(&Ode(eq), t₀, a₀,
/// b₀, t₁)?, &Dop853::new(rtol, atol)?, &mut observer)` — with step control, dense output and
/// events (the state's `q` and `p` blocks are the elements `a` and `b`).
#[derive(Clone, Copy, Debug)]
pub struct Ode<O>(pub O);

impl<O: ElementOde<N>, const N: usize> crate::integrate::FirstOrderSystem<N> for Ode<O> {
    fn field(&self, t: f64, a: &SVector<f64, N>, b: &SVector<f64, N>) -> Result<ElementPair<N>> {
        self.0.rhs(t, a, b)
    }
}

//! The classical fourth-order Runge–Kutta method: one step for states of any shape, and the
//! (non-symplectic) reference integrator [`Rk4`] of Hamilton's equations built on it.
//!
//! ```math
//! k_1 = f(t, y),\ k_2 = f(t + \tfrac h2, y + \tfrac h2 k_1),\ k_3 = f(t + \tfrac h2, y + \tfrac h2 k_2),\
//! k_4 = f(t + h, y + h k_3),\qquad \Delta y = \tfrac h6 (k_1 + 2k_2 + 2k_3 + k_4)
//! ```
//!
//! [Hairer, Nørsett & Wanner, *Solving ODEs I*, 2nd ed., Springer 1993, II.1 (the classical
//! tableau, order 4)]. [`rk4_increment`] takes the state as any [`VectorSpace`] — a phase-space
//! pair `(q, p)`, a triple `(q, p, s)` with the action carried along, element pairs — over any
//! dual type, and returns the increment `Δy`, so that the caller adds it as it needs (plainly, or
//! with compensated summation). Requirements of [`Rk4`] on the system: any [`Hamiltonian`]; four
//! AD gradients per step. Not symplectic: its energy error drifts linearly.

use super::methods;
use super::{OneStep, Work};
use crate::error::{Error, Result};
use crate::hamiltonian::Hamiltonian;
use crate::vector_space::VectorSpace;
use nalgebra::SVector;
use num_dual::{DualNum, DualStruct};

/// One classical RK4 step of size `h` from `y` at `t` for `ẏ = f(t, y)`: the increment
/// `Δy = (h/6)(k₁ + 2k₂ + 2k₃ + k₄)` (see the [module docs](self)), with `f` evaluated four times
/// in the order `k₁ … k₄`.
///
/// # Errors
/// The first error of `f`; [`Error::NonFinite`] if the increment is not finite (its real parts:
/// a non-finite state or step, or an overflow).
#[inline]
pub fn rk4_increment<Y: VectorSpace>(
    mut f: impl FnMut(Y::Scalar, &Y) -> Result<Y>,
    t: Y::Scalar,
    y: &Y,
    h: Y::Scalar,
) -> Result<Y> {
    let half = h * 0.5;
    let k1 = f(t, y)?;
    let k2 = f(t + half, &y.add(&k1.scale(half)))?;
    let k3 = f(t + half, &y.add(&k2.scale(half)))?;
    let k4 = f(t + h, &y.add(&k3.scale(h)))?;
    let two = Y::Scalar::from(2.0);
    let increment = k1.add(&k2.add(&k3).scale(two)).add(&k4).scale(h / 6.0);
    let offending = std::cell::Cell::new(None);
    let finite = increment.all(|a| {
        let re = a.re();
        if !re.is_finite() && offending.get().is_none() {
            offending.set(Some(re));
        }
        re.is_finite()
    });
    if !finite {
        return Err(Error::NonFinite {
            what: format!("RK4 increment at t = {:e}, h = {:e}", t.re(), h.re()),
            value: offending.get().unwrap_or(f64::NAN),
        });
    }
    Ok(increment)
}

/// Classical RK4 for Hamilton's equations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Rk4;

impl<S: Hamiltonian<N>, const N: usize> OneStep<S, N> for Rk4 {
    fn order(&self) -> u32 {
        4
    }
    fn name(&self) -> String {
        methods::RK4.label()
    }
    #[inline]
    fn increment<D: DualNum<f64> + Copy>(
        &self,
        system: &S,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        dt: D,
        work: &mut Work,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        work.gradients += 4;
        rk4_increment(
            |t, (q, p)| Ok(system.vector_field_generic(t, q, p)),
            t,
            &(*q, *p),
            dt,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An overflowing field is refused with the offending component, not a generic NaN.
    #[test]
    fn non_finite_increment_names_the_value() {
        let y = nalgebra::SVector::<f64, 2>::new(1.0, 2.0);
        let err = rk4_increment(
            |_t, y: &nalgebra::SVector<f64, 2>| Ok(nalgebra::SVector::from([y[0], f64::MAX])),
            0.0,
            &y,
            1e300,
        )
        .unwrap_err();
        match err {
            Error::NonFinite { what, value } => {
                assert_eq!(value, f64::INFINITY, "{what}");
                assert!(what.contains("h = 1e300"), "{what}");
            }
            e => panic!("expected NonFinite, got {e}"),
        }
    }
}

//! A perturbation of the Kepler problem given by an expression: the disturbing function
//! `R(t, q)` of celestial mechanics, whose force per unit mass is `+∇R`, so that
//!
//! ```math
//! H(t, q, p) = \tfrac12|p|^2 - \frac{\mu}{|q|} - R(t, q),\qquad
//! \ddot q = -\frac{\mu q}{|q|^3} + \nabla R(t, q)
//! ```
//!
//! (Murray & Dermott, *Solar System Dynamics*, Cambridge 1999, §6.2; Vallado, *Fundamentals of
//! Astrodynamics and Applications*, 4th ed., 2013, §8.6–8.7). The crate's potential-energy
//! disturbing function of [`crate::perturbation::forces`] is `U = −R`; there an
//! [`ExpressionDisturbingFunction`] is a model of `U` for `PerturbedTwoBody`, the Cartesian
//! "Kepler + perturbation" system that every integrator, the Wisdom–Holman method and the SABA
//! methods run.

use super::constraints::configuration_variables;
use super::{Expression, MAX_DOF};
use crate::error::{Error, Result};
use nalgebra::SVector;
use num_dual::DualNum;

/// The default names of the Cartesian coordinates.
const CARTESIAN: [&str; 3] = ["x", "y", "z"];

/// A disturbing function `R(t, q)` of the Kepler problem given by an expression in `t`, named
/// Cartesian coordinates and parameters (see the [module docs](self)).
#[derive(Clone, Debug)]
pub struct ExpressionDisturbingFunction<const N: usize> {
    r: Expression,
}

impl<const N: usize> ExpressionDisturbingFunction<N> {
    /// `R` from `text` in `t`, the `coordinates` (`N` names, default `x, y, z` for `N ≤ 3`) and
    /// the `parameters` with their values.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for `N` outside `1 … MAX_DOF`, a number of names that is not `N`,
    /// no names given for `N > 3`; the errors of [`Expression::new`].
    pub fn new(
        text: &str,
        coordinates: Option<&[&str]>,
        parameters: &[(&str, f64)],
    ) -> Result<Self> {
        let coordinates = match coordinates {
            Some(c) => c,
            None if (1..=CARTESIAN.len()).contains(&N) => &CARTESIAN[..N],
            None => {
                return Err(Error::invalid(
                    "coordinates",
                    format!("no default names for {N} coordinates"),
                ))
            }
        };
        let names = configuration_variables::<N>(coordinates)?;
        Ok(Self {
            r: Expression::new(text, &names, parameters)?,
        })
    }

    /// The expression of `R`; its variables are `t` and the coordinates.
    pub fn expression(&self) -> &Expression {
        &self.r
    }

    /// `R(t, q)` on any number type, without validation.
    #[inline]
    pub fn eval<D: DualNum<f64> + Copy>(&self, t: D, q: &SVector<D, N>) -> D {
        let mut x = [t; 1 + MAX_DOF];
        x[1..=N].copy_from_slice(q.as_slice());
        self.r.eval(&x[..=N])
    }

    /// `R(t, q)` on reals.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite input or value (naming the expression and the
    /// state).
    pub fn value(&self, t: f64, q: &SVector<f64, N>) -> Result<f64> {
        let mut x = vec![t];
        x.extend_from_slice(q.as_slice());
        self.r.value(&x)
    }
}

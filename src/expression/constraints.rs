//! Holonomic constraints given by expressions: `K` functions `g_r(t, q)` of the time and named
//! coordinates with
//!
//! ```math
//! g_r(t, q) = 0,\qquad r = 1, \dots, K
//! ```
//!
//! [Ardema, *Analytical Dynamics*, 2005, §2.3, eq. 2.14], a
//! [`HolonomicConstraints`] set: their Pfaffian form `∂g/∂q · q̇ + ∂g/∂t = 0` is
//! [`Differentiated`](crate::constraints::Differentiated), which the multiplier form of
//! Lagrange's equations (`nonholonomic::Constrained`) takes, and RATTLE takes them with a
//! Hamiltonian (`integrate::ConstrainedHamiltonian`).

use super::{Expression, MAX_DOF};
use crate::constraints::HolonomicConstraints;
use crate::error::{Error, Result};
use nalgebra::SVector;
use num_dual::DualNum;

/// `K` holonomic constraints `g_r(t, q) = 0` given by expressions (see the
/// [module docs](self)).
#[derive(Clone, Debug)]
pub struct ExpressionConstraints<const N: usize, const K: usize> {
    g: Vec<Expression>,
}

impl<const N: usize, const K: usize> ExpressionConstraints<N, K> {
    /// The constraints `texts` (`K` expressions) in `t`, the `coordinates` (`N` names) and the
    /// `parameters` with their values.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] for `N` outside `1 … MAX_DOF`, `K` not in `1 … N − 1`, a number of
    /// names that is not `N` or of texts that is not `K`; the errors of [`Expression::new`].
    pub fn new(texts: &[&str], coordinates: &[&str], parameters: &[(&str, f64)]) -> Result<Self> {
        let names = configuration_variables::<N>(coordinates)?;
        if K == 0 || K >= N {
            return Err(Error::invalid(
                "constraints",
                format!("{K} on {N} coordinates; 1 … {} leave a motion", N - 1),
            ));
        }
        if texts.len() != K {
            return Err(Error::invalid(
                "constraints",
                format!("{} expressions for {K} constraints", texts.len()),
            ));
        }
        let g = texts
            .iter()
            .map(|text| Expression::new(text, &names, parameters))
            .collect::<Result<Vec<_>>>()?;
        Ok(Self { g })
    }

    /// The expressions `g_r`; their variables are `t` and the coordinates.
    pub fn expressions(&self) -> &[Expression] {
        &self.g
    }

    /// `g(t, q)` on reals.
    ///
    /// # Errors
    /// [`Error::NonFinite`] for a non-finite input or value (naming the expression and the
    /// state).
    pub fn value(&self, t: f64, q: &SVector<f64, N>) -> Result<SVector<f64, K>> {
        let mut x = vec![t];
        x.extend_from_slice(q.as_slice());
        let mut g = SVector::zeros();
        for (r, e) in self.g.iter().enumerate() {
            g[r] = e.value(&x)?;
        }
        Ok(g)
    }
}

/// The variables `t, q₁, …, q_N` of an expression on the configuration space.
///
/// # Errors
/// [`Error::InvalidInput`] for `N` outside `1 … MAX_DOF` or a number of names that is not `N`.
pub(super) fn configuration_variables<'a, const N: usize>(
    coordinates: &[&'a str],
) -> Result<Vec<&'a str>> {
    if N == 0 || N > MAX_DOF {
        return Err(Error::invalid(
            "degrees of freedom",
            format!("{N}; expression systems have 1 … {MAX_DOF}"),
        ));
    }
    if coordinates.len() != N {
        return Err(Error::invalid(
            "coordinates",
            format!("{} names for {N} coordinates", coordinates.len()),
        ));
    }
    Ok(std::iter::once("t")
        .chain(coordinates.iter().copied())
        .collect())
}

impl<const N: usize, const K: usize> HolonomicConstraints<N, K> for ExpressionConstraints<N, K> {
    #[inline]
    fn position_constraint<D: DualNum<f64> + Copy>(
        &self,
        t: D,
        q: &SVector<D, N>,
    ) -> SVector<D, K> {
        let mut x = [t; 1 + MAX_DOF];
        x[1..=N].copy_from_slice(q.as_slice());
        SVector::from_fn(|r, _| self.g[r].eval(&x[..=N]))
    }
}

//! A chain of uniform rods hinged end to end, moving normal to its line: the system of
//! Ardema 13.3 (SPEC T35) for impulsive motion.

use crate::error::{positive, Result};
use crate::lagrangian::Lagrangian;
use nalgebra::SVector;
use num_dual::DualNum;

/// `N − 1` uniform rods of mass `M` hinged end to end, with the normal velocities
/// `q̇ = (v₁, …, v_N)` of the `N` joints and ends as velocities (small motion about the straight
/// line, no forces) [Ardema 13.3]. A rod whose ends move with `u`, `v` has the kinetic energy
/// `(M/6)(u² + uv + v²)`, so
///
/// ```math
/// L = T = \frac{M}{6} \sum_{i=1}^{N-1} \left(v_i^2 + v_i v_{i+1} + v_{i+1}^2\right).
/// ```
///
/// With `N = 4` and an impulse `P` normal to the line at the first end, the velocities after the
/// blow are `(52, −14, 4, −2) P/(15M)` (SPEC T35); with `N = 2`, an impulse at `nℓ` from the
/// first end gives end velocities `(4 − 6n, 6n − 2) P/M` (SPEC T36).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HingedRods<const N: usize> {
    mass: f64,
}

impl<const N: usize> HingedRods<N> {
    /// `N − 1` rods (`N ≥ 2` points) of mass `M > 0` each.
    ///
    /// # Errors
    /// [`crate::Error::OutOfDomain`]/[`crate::Error::NonFinite`] for a mass that is not positive
    /// and finite; [`crate::Error::InvalidInput`] for `N < 2`.
    pub fn new(mass: f64) -> Result<Self> {
        if N < 2 {
            return Err(crate::Error::invalid(
                "hinged rods",
                format!("{N} point(s) make no rod; at least 2 are needed"),
            ));
        }
        Ok(Self {
            mass: positive("rod mass M", mass)?,
        })
    }

    /// The mass `M` of each rod.
    pub fn mass(&self) -> f64 {
        self.mass
    }
}

impl<const N: usize> Lagrangian<N> for HingedRods<N> {
    fn lagrangian<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        _q: &SVector<D, N>,
        v: &SVector<D, N>,
    ) -> D {
        (0..N.saturating_sub(1)).fold(D::from(0.0), |acc, i| {
            acc + (v[i] * v[i] + v[i] * v[i + 1] + v[i + 1] * v[i + 1]) * (self.mass / 6.0)
        })
    }
}

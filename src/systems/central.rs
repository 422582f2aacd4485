//! Central-force systems: a potential `V(r)` written once, as a system of `N = 2` or `3` degrees of
//! freedom in Cartesian coordinates and as the radial problem that Hamilton–Jacobi theory separates
//! ([`RadialMotion`](crate::hamilton_jacobi::RadialMotion)).
//!
//! ```math
//! H = \tfrac12 |p|^2 + V(|q|)
//! ```
//!
//! per unit mass [Ardema 10.1, eqs. 10.1–10.4; Goldstein §3.2].
//! The energy and the angular momentum `q × p` are conserved.

use super::{Invariant, Invariants};
use crate::error::{positive, Error, Result};
use crate::hamiltonian::{Hamiltonian, Separable};
use nalgebra::SVector;
use num_dual::DualNum;

/// A central potential `V(r)` per unit mass, written once for every dual type.
pub trait CentralPotential {
    /// `V(r)`.
    fn potential<D: DualNum<f64> + Copy>(&self, r: D) -> D;
}

/// The Kepler potential `V = −μ/r`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InverseDistance {
    mu: f64,
}

impl InverseDistance {
    /// `V = −μ/r`, `μ > 0`.
    pub fn new(mu: f64) -> Result<Self> {
        Ok(Self {
            mu: positive("gravitational parameter μ", mu)?,
        })
    }
    /// `μ`.
    pub fn mu(&self) -> f64 {
        self.mu
    }
    /// From a `μ` already checked to be positive.
    pub(super) fn from_mu(mu: f64) -> Self {
        debug_assert!(mu > 0.0);
        Self { mu }
    }
}

impl CentralPotential for InverseDistance {
    #[inline]
    fn potential<D: DualNum<f64> + Copy>(&self, r: D) -> D {
        r.recip() * -self.mu
    }
}

impl<V: CentralPotential + ?Sized> CentralPotential for &V {
    #[inline]
    fn potential<D: DualNum<f64> + Copy>(&self, r: D) -> D {
        (**self).potential(r)
    }
}

/// The motion of a unit mass in a central potential, `H = |p|²/2 + V(|q|)`, in `N = 2` or `3`
/// Cartesian dimensions: the one definition from which the Cartesian integrators (as a
/// [`Separable`] system) and the radial quadratures
/// ([`RadialMotion::from_state`](crate::hamilton_jacobi::RadialMotion::from_state)) both work.
///
/// ```
/// use hamilton_jacobi::systems::{Central, CentralPotential};
/// use hamilton_jacobi::{DualNum, Hamiltonian, nalgebra::SVector};
/// struct Harmonic;
/// impl CentralPotential for Harmonic {
///     fn potential<D: DualNum<f64> + Copy>(&self, r: D) -> D { r * r * 0.5 }
/// }
/// let s = Central::<_, 2>::new(Harmonic).unwrap();
/// let (_, pd) = s.vector_field(0.0, &SVector::from([3.0, 4.0]), &SVector::zeros()).unwrap();
/// assert!((pd - SVector::from([-3.0, -4.0])).norm() < 1e-15);
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Central<V, const N: usize> {
    pub(super) potential: V,
}

impl<V: CentralPotential, const N: usize> Central<V, N> {
    /// The central-force system of `potential` in `N` dimensions (`N` = 2 or 3).
    pub fn new(potential: V) -> Result<Self> {
        if N == 2 || N == 3 {
            Ok(Self { potential })
        } else {
            Err(Error::invalid(
                "central-force dimension",
                format!("N = {N}; only 2 and 3 are supported"),
            ))
        }
    }
    /// The potential `V(r)`.
    pub fn central_potential(&self) -> &V {
        &self.potential
    }
    /// The magnitude of the angular momentum, `|q × p|`.
    pub fn angular_momentum(&self, q: &SVector<f64, N>, p: &SVector<f64, N>) -> f64 {
        angular_momentum(q, p).norm()
    }
}

/// `q × p` embedded in three dimensions (`(0, 0, x p_y − y p_x)` in the plane).
pub(crate) fn angular_momentum<const N: usize>(
    q: &SVector<f64, N>,
    p: &SVector<f64, N>,
) -> nalgebra::Vector3<f64> {
    let e = |x: &SVector<f64, N>| {
        nalgebra::Vector3::new(
            x[0],
            if N > 1 { x[1] } else { 0.0 },
            if N > 2 { x[2] } else { 0.0 },
        )
    };
    e(q).cross(&e(p))
}

impl<V: CentralPotential, const N: usize> Separable<N> for Central<V, N> {
    #[inline]
    fn kinetic<D: DualNum<f64> + Copy>(&self, _t: D, p: &SVector<D, N>) -> D {
        p.dot(p) * 0.5
    }
    #[inline]
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, N>) -> D {
        self.potential.potential(q.dot(q).sqrt())
    }
}

impl<V: CentralPotential, const N: usize> Invariants<N> for Central<V, N> {
    fn invariants(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<Vec<Invariant>> {
        let energy = self.value(t, q, p)?;
        let h = angular_momentum(q, p);
        let mut out = vec![Invariant {
            name: "energy",
            value: energy,
        }];
        if N == 3 {
            out.push(Invariant {
                name: "h_x",
                value: h[0],
            });
            out.push(Invariant {
                name: "h_y",
                value: h[1],
            });
        }
        out.push(Invariant {
            name: "h_z",
            value: h[2],
        });
        Ok(out)
    }
}

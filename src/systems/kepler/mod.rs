//! The two-body (Kepler) problem per unit mass, `H = |p|²/2 − μ/|q|`: the system [`Kepler`], its
//! first integrals, its element sets and its exact flow, for every conic.
//!
//! | item | contents |
//! |---|---|
//! | [`Kepler`], [`AngularMomentum`] | the system in `N = 2` or `3` dimensions, its invariants (energy, angular momentum, Laplace–Runge–Lenz vector) and exact flow |
//! | [`orbit`] | specific energy, angular momentum, eccentricity vector, mean motion, period; the circular tolerance and the phase limit shared by the maps below |
//! | [`elements`] | classical (elliptic and hyperbolic), equinoctial, modified equinoctial (every conic) and Delaunay (canonical) elements, with their maps to and from the state written for dual numbers |
//! | [`propagate`], [`drift`] | the exact flow in universal variables for every conic, generic over dual numbers (exact derivatives) |
//!
//! Kepler's equation and the anomalies are special functions
//! ([`crate::special::kepler_equation`]), as are the Stumpff functions of the universal variables
//! ([`crate::special::stumpff`]); the equations of motion of the elements under a perturbation
//! (Lagrange's and Gauss's planetary equations, secular theory) are perturbation methods
//! ([`crate::perturbation`]).
//!
//! References: M. D. Ardema, *Analytical Dynamics*, Kluwer/Plenum (2005), §§10.2–10.3;
//! R. H. Battin, *An Introduction to the Mathematics and Methods of Astrodynamics*, rev. ed.,
//! AIAA (1999), chs. 3–5; D. A. Vallado, *Fundamentals of Astrodynamics and Applications*, 4th
//! ed., Microcosm (2013), ch. 2.

use super::central::{Central, CentralPotential, InverseDistance};
use super::{ExactFlow, Invariant, Invariants};
use crate::error::{finite, positive, Error, Result};
use crate::hamiltonian::{PerturbedKepler, PhaseFunction, Separable};
use crate::phase::check_phase;
use crate::special::double_double::two_sum;
use nalgebra::{SVector, Vector3};
use num_dual::DualNum;

pub mod elements;
mod flow;
pub mod orbit;

pub use flow::{drift, propagate};

/// Kepler problem per unit mass in `N = 2` or `3` dimensions, `H = |p|²/2 − μ/|q|` [Ardema 10.2].
///
/// Invariants: energy, angular momentum, eccentricity (Laplace–Runge–Lenz) vector. Exact motion on
/// every conic by the universal-variable flow ([`propagate`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Kepler<const N: usize> {
    mu: f64,
}

/// Planar Kepler problem.
pub type Kepler2 = Kepler<2>;
/// Spatial Kepler problem.
pub type Kepler3 = Kepler<3>;

impl<const N: usize> Kepler<N> {
    /// Kepler problem with gravitational parameter `μ > 0`.
    pub fn new(mu: f64) -> Result<Self> {
        Ok(Self {
            mu: positive("gravitational parameter μ", mu)?,
        })
    }
    /// Gravitational parameter.
    pub fn mu(&self) -> f64 {
        self.mu
    }
    /// The same problem as a [`Central`] system of the potential `−μ/r`.
    pub fn central(&self) -> Central<InverseDistance, N> {
        Central {
            potential: InverseDistance::from_mu(self.mu),
        }
    }
    /// Hand-written Hamilton's equations `(q̇, ṗ) = (p, −μ q/|q|³)`: test oracle and baseline for the
    /// AD vector field.
    #[inline]
    pub fn vector_field_hand(
        &self,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> (SVector<f64, N>, SVector<f64, N>) {
        let r2 = q.dot(q);
        let f = self.mu / (r2 * r2.sqrt());
        (*p, q * -f)
    }
}

impl<const N: usize> Separable<N> for Kepler<N> {
    #[inline]
    fn kinetic<D: DualNum<f64> + Copy>(&self, _t: D, p: &SVector<D, N>) -> D {
        p.dot(p) * 0.5
    }
    #[inline]
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, N>) -> D {
        // −μ/r, written once in the central potential.
        InverseDistance::from_mu(self.mu).potential(q.dot(q).sqrt())
    }
}

/// The plain Kepler problem as "Kepler + R" with `R = 0`: Wisdom–Holman and SABA methods then
/// compose the exact Kepler flow.
impl<const N: usize> PerturbedKepler<N> for Kepler<N> {
    fn mu(&self) -> f64 {
        self.mu
    }
    #[inline]
    fn perturbation<D: DualNum<f64> + Copy>(&self, _t: D, _q: &SVector<D, N>) -> D {
        D::zero()
    }
}

fn embed<const N: usize>(x: &SVector<f64, N>) -> Result<Vector3<f64>> {
    match N {
        2 => Ok(Vector3::new(x[0], x[1], 0.0)),
        3 => Ok(Vector3::new(x[0], x[1], x[2])),
        _ => Err(Error::invalid(
            "Kepler dimension",
            format!("N = {N}; only 2 and 3 are supported"),
        )),
    }
}

impl<const N: usize> Invariants<N> for Kepler<N> {
    fn invariants(
        &self,
        t: f64,
        q: &SVector<f64, N>,
        p: &SVector<f64, N>,
    ) -> Result<Vec<Invariant>> {
        // Energy and angular momentum as for every central force, then the Runge–Lenz vector.
        let (r, v) = (embed(q)?, embed(p)?);
        let e = orbit::eccentricity_vector(self.mu, &r, &v)?;
        let mut out = self.central().invariants(t, q, p)?;
        out.push(Invariant {
            name: "e_x",
            value: e[0],
        });
        out.push(Invariant {
            name: "e_y",
            value: e[1],
        });
        if N == 3 {
            out.push(Invariant {
                name: "e_z",
                value: e[2],
            });
        }
        Ok(out)
    }
}

/// The universal-variable flow of [`drift`] over `t − t₀`, the difference taken exactly (as a
/// double-double sum, Knuth's two-sum): the exact flow of the given double state
/// to the given double time, with the ill-conditioned quantities in double-double arithmetic.
/// Its accuracy on the 100-period problem, beside the change of the end state for a 1-ulp
/// change of the input: the table in [`drift`].
impl<const N: usize> ExactFlow<N> for Kepler<N> {
    fn exact_flow(
        &self,
        t0: f64,
        q0: &SVector<f64, N>,
        p0: &SVector<f64, N>,
        t: f64,
    ) -> Result<(SVector<f64, N>, SVector<f64, N>)> {
        check_phase(t0, q0, p0)?;
        let (dt, dt_lo) = two_sum(finite("t", t)?, -t0);
        if !dt.is_finite() {
            return propagate(self.mu, q0, p0, dt);
        }
        let (dq, dp) = flow::drift_split(self.mu, q0, p0, dt, dt_lo)?;
        Ok((q0 + dq, p0 + dp))
    }
}

/// A component of the angular momentum `h = q × p` as a [`PhaseFunction`]: for `N = 3` the
/// component about axis `k` (`h_k = q_i p_j − q_j p_i`, `(i, j, k)` cyclic), for `N = 2` the `z`
/// component `x p_y − y p_x`. An integral of every central-force problem; its Poisson brackets obey
/// `(h_x, h_y) = h_z` [Ardema 15.5] and it generates rotations [Ardema 18.3].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AngularMomentum<const N: usize> {
    i: usize,
    j: usize,
}

impl AngularMomentum<3> {
    /// The component about axis `axis ∈ {0, 1, 2}` (x, y, z).
    pub fn new(axis: usize) -> Result<Self> {
        if axis < 3 {
            Ok(Self {
                i: (axis + 1) % 3,
                j: (axis + 2) % 3,
            })
        } else {
            Err(Error::invalid(
                "angular momentum axis",
                format!("{axis} is not 0, 1 or 2"),
            ))
        }
    }
}

impl AngularMomentum<2> {
    /// The only component in the plane, `h_z = x p_y − y p_x`.
    pub fn z() -> Self {
        Self { i: 0, j: 1 }
    }
}

impl<const N: usize> PhaseFunction<N> for AngularMomentum<N> {
    fn eval<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, N>, p: &SVector<D, N>) -> D {
        q[self.i] * p[self.j] - q[self.j] * p[self.i]
    }
}

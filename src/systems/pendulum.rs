use super::{pendulum_exact, ExactFlow, Invariant, Invariants};
use crate::error::{finite, positive, Result};
use crate::hamiltonian::{Hamiltonian, Separable};
use crate::phase::check_phase;
use nalgebra::SVector;
use num_dual::DualNum;

/// Plane pendulum `H = ½ p² + n² (1 − cos θ)` [Ardema 18.2], `n` the small-oscillation frequency.
///
/// Exact motion by Jacobi elliptic functions, libration and rotation, valid up to the separatrix
/// ([`pendulum_exact`]); the period `τ = 4K(k)/n`, `k = sin(a/2)`, is computed from the
/// complementary modulus `k′ = cos(a/2)` by the AGM.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pendulum {
    n: f64,
}

impl Pendulum {
    /// Pendulum with small-oscillation angular frequency `n > 0`.
    pub fn new(n: f64) -> Result<Self> {
        Ok(Self {
            n: positive("frequency n", n)?,
        })
    }
    /// Small-oscillation angular frequency.
    pub fn n(&self) -> f64 {
        self.n
    }
    /// Hand-written Hamilton's equations `(θ̇, ṗ) = (p, −n² sin θ)`: a test oracle and baseline for the
    /// AD vector field.
    #[inline]
    pub fn vector_field_hand(
        &self,
        q: &SVector<f64, 1>,
        p: &SVector<f64, 1>,
    ) -> (SVector<f64, 1>, SVector<f64, 1>) {
        (*p, SVector::from([-self.n * self.n * q[0].sin()]))
    }
    /// Period of libration with amplitude `a ∈ [0, π)` (see [`pendulum_exact::period`]).
    pub fn period(&self, amplitude: f64) -> Result<f64> {
        pendulum_exact::period(self.n, amplitude)
    }
}

impl Separable<1> for Pendulum {
    #[inline]
    fn kinetic<D: DualNum<f64> + Copy>(&self, _t: D, p: &SVector<D, 1>) -> D {
        p[0] * p[0] * 0.5
    }
    #[inline]
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 1>) -> D {
        // n²(1 − cos q) written as 2n² sin²(q/2): no cancellation near q = 0.
        let s = (q[0] * 0.5).sin();
        s * s * (2.0 * self.n * self.n)
    }
}

impl Invariants<1> for Pendulum {
    fn invariants(
        &self,
        t: f64,
        q: &SVector<f64, 1>,
        p: &SVector<f64, 1>,
    ) -> Result<Vec<Invariant>> {
        Ok(vec![Invariant {
            name: "energy",
            value: self.value(t, q, p)?,
        }])
    }
}

impl ExactFlow<1> for Pendulum {
    fn exact_flow(
        &self,
        t0: f64,
        q0: &SVector<f64, 1>,
        p0: &SVector<f64, 1>,
        t: f64,
    ) -> Result<(SVector<f64, 1>, SVector<f64, 1>)> {
        check_phase(t0, q0, p0)?;
        let (th, p) = pendulum_exact::exact_state(self.n, q0[0], p0[0], finite("t", t)? - t0)?;
        Ok((SVector::from([th]), SVector::from([p])))
    }
}

//! The classical fourth-order Runge–Kutta method (non-symplectic reference).
//!
//! $$ k_1 = f(y),\ k_2 = f(y + \tfrac h2 k_1),\ k_3 = f(y + \tfrac h2 k_2),\ k_4 = f(y + h k_3),\quad
//!    \Delta y = \tfrac h6 (k_1 + 2k_2 + 2k_3 + k_4) $$
//!
//! [Hairer, Nørsett & Wanner, *Solving ODEs I*, II.1]. Requirements on the system: any
//! [`Hamiltonian`]; four AD gradients per step. Not symplectic: its energy error drifts linearly.

use super::methods;
use super::{OneStep, Work};
use crate::error::Result;
use crate::hamiltonian::Hamiltonian;
use nalgebra::SVector;
use num_dual::DualNum;

/// Classical RK4.
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
        let f = |t: D, q: &SVector<D, N>, p: &SVector<D, N>| system.vector_field_generic(t, q, p);
        let half = dt * 0.5;
        let (k1q, k1p) = f(t, q, p);
        let (k2q, k2p) = f(t + half, &(q + k1q * half), &(p + k1p * half));
        let (k3q, k3p) = f(t + half, &(q + k2q * half), &(p + k2p * half));
        let (k4q, k4p) = f(t + dt, &(q + k3q * dt), &(p + k3p * dt));
        work.gradients += 4;
        let sixth = dt / 6.0;
        Ok((
            (k1q + (k2q + k3q) * D::from(2.0) + k4q) * sixth,
            (k1p + (k2p + k3p) * D::from(2.0) + k4p) * sixth,
        ))
    }
}

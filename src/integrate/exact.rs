//! A closed-form flow as a fixed-step method, so that exact solutions sit on the same
//! error-versus-cost axes as the integrators.
//!
//! Each step applies the system's [`ExactFlow`] over `dt` from the current state; the only errors
//! are the flow's own rounding and its accumulation over steps (with the driver's compensated
//! summation it grows like `√n`, Brouwer's law). Requirements on the system: [`ExactFlow`].

use super::methods;
use super::{OneStep, Work};
use crate::error::{Error, Result};
use crate::systems::ExactFlow;
use nalgebra::SVector;
use num_dual::DualNum;

/// Steps of the exact flow.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ExactStep;

/// On real arguments only: the catalogue's exact flows are not written for dual numbers, so a
/// dual-valued step (e.g. certifying the step map by AD) is refused with an error.
impl<S: ExactFlow<N>, const N: usize> OneStep<S, N> for ExactStep {
    fn order(&self) -> u32 {
        u32::MAX
    }
    fn name(&self) -> String {
        methods::EXACT.label()
    }
    fn increment<D: DualNum<f64> + Copy>(
        &self,
        system: &S,
        t: D,
        q: &SVector<D, N>,
        p: &SVector<D, N>,
        dt: D,
        work: &mut Work,
    ) -> Result<(SVector<D, N>, SVector<D, N>)> {
        if D::NDERIV > 0 {
            return Err(Error::invalid(
                "exact-flow step",
                "the closed-form flow is evaluated on reals only (no AD through it)",
            ));
        }
        let (qr, pr) = (q.map(|v| v.re()), p.map(|v| v.re()));
        let t = t.re();
        let (q1, p1) = system.exact_flow(t, &qr, &pr, t + dt.re())?;
        work.flows += 1;
        Ok(((q1 - qr).map(D::from), (p1 - pr).map(D::from)))
    }
}

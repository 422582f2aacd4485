use super::{ExactFlow, Invariant, Invariants};
use crate::error::{finite, positive, Result};
use crate::hamiltonian::{Hamiltonian, Separable};
use crate::phase::check_phase;
use nalgebra::SVector;
use num_dual::DualNum;

/// Projectile in a uniform field, `y` upward: `H = |p|²/(2m) + m g y` [Ardema 17.1].
///
/// Exact flow `x = x₀ + p_x τ/m`, `y = y₀ + p_y τ/m − ½ g τ²`, `p_y = p_{y0} − m g τ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projectile {
    m: f64,
    g: f64,
}

impl Projectile {
    /// Projectile of mass `m > 0` in the field `g` (finite, any sign).
    pub fn new(m: f64, g: f64) -> Result<Self> {
        Ok(Self {
            m: positive("mass m", m)?,
            g: finite("g", g)?,
        })
    }
}

impl Separable<2> for Projectile {
    #[inline]
    fn kinetic<D: DualNum<f64> + Copy>(&self, _t: D, p: &SVector<D, 2>) -> D {
        p.dot(p) * (0.5 / self.m)
    }
    #[inline]
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 2>) -> D {
        q[1] * (self.m * self.g)
    }
}

impl Invariants<2> for Projectile {
    fn invariants(
        &self,
        t: f64,
        q: &SVector<f64, 2>,
        p: &SVector<f64, 2>,
    ) -> Result<Vec<Invariant>> {
        Ok(vec![
            Invariant {
                name: "energy",
                value: self.value(t, q, p)?,
            },
            Invariant {
                name: "p_x",
                value: p[0],
            },
        ])
    }
}

impl ExactFlow<2> for Projectile {
    fn exact_flow(
        &self,
        t0: f64,
        q0: &SVector<f64, 2>,
        p0: &SVector<f64, 2>,
        t: f64,
    ) -> Result<(SVector<f64, 2>, SVector<f64, 2>)> {
        check_phase(t0, q0, p0)?;
        let tau = finite("t", t)? - t0;
        let q = SVector::from([
            q0[0] + p0[0] * tau / self.m,
            q0[1] + p0[1] * tau / self.m - 0.5 * self.g * tau * tau,
        ]);
        let p = SVector::from([p0[0], p0[1] - self.m * self.g * tau]);
        Ok((q, p))
    }
}

use super::{ExactFlow, Invariant, Invariants};
use crate::brackets::PhaseMap;
use crate::error::{finite, positive, Result};
use crate::hamiltonian::{Hamiltonian, Separable};
use crate::phase::check_phase;
use crate::systems::kepler::orbit::phase_advance;
use nalgebra::SVector;
use num_dual::DualNum;

/// Harmonic oscillator `H = p²/(2m) + ½ m ω² q²`.
///
/// Exact flow `q(t) = q₀ cos ωτ + p₀/(mω) sin ωτ`, `p(t) = p₀ cos ωτ − mω q₀ sin ωτ`, `τ = t − t₀`
/// [Ardema 16.5].
///
/// [`ExactFlow::exact_flow`] refuses a phase `|ωτ|` above
/// [`MAX_PHASE_ADVANCE`](crate::systems::kepler::orbit::MAX_PHASE_ADVANCE) with
/// [`Error::PhaseLost`](crate::Error::PhaseLost), and a state whose `q(t)` or `p(t)` overflows
/// (e.g. `mω q₀` beyond `f64::MAX`) with [`Error::NonFinite`](crate::Error::NonFinite).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HarmonicOscillator {
    m: f64,
    omega: f64,
}

impl HarmonicOscillator {
    /// Oscillator of mass `m > 0` and angular frequency `ω > 0`.
    pub fn new(m: f64, omega: f64) -> Result<Self> {
        Ok(Self {
            m: positive("mass m", m)?,
            omega: positive("angular frequency ω", omega)?,
        })
    }
    /// Mass.
    pub fn mass(&self) -> f64 {
        self.m
    }
    /// Angular frequency.
    pub fn omega(&self) -> f64 {
        self.omega
    }
    /// The exact flow map over the time step `tau`, as a [`PhaseMap`] (certifiable by AD).
    pub fn flow_map(&self, tau: f64) -> HarmonicFlow {
        HarmonicFlow { osc: *self, tau }
    }
}

impl Separable<1> for HarmonicOscillator {
    #[inline]
    fn kinetic<D: DualNum<f64> + Copy>(&self, _t: D, p: &SVector<D, 1>) -> D {
        p[0] * p[0] * (0.5 / self.m)
    }
    #[inline]
    fn potential<D: DualNum<f64> + Copy>(&self, _t: D, q: &SVector<D, 1>) -> D {
        q[0] * q[0] * (0.5 * self.m * self.omega * self.omega)
    }
}

impl Invariants<1> for HarmonicOscillator {
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

/// The oscillator's flow map over a fixed time step (see [`HarmonicOscillator::flow_map`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HarmonicFlow {
    osc: HarmonicOscillator,
    tau: f64,
}

impl PhaseMap<1> for HarmonicFlow {
    fn apply<D: DualNum<f64> + Copy>(
        &self,
        _t: D,
        q: &SVector<D, 1>,
        p: &SVector<D, 1>,
    ) -> (SVector<D, 1>, SVector<D, 1>) {
        let (m, w) = (self.osc.m, self.osc.omega);
        let (s, c) = (w * self.tau).sin_cos();
        (
            SVector::from([q[0] * c + p[0] * (s / (m * w))]),
            SVector::from([p[0] * c - q[0] * (m * w * s)]),
        )
    }
}

impl ExactFlow<1> for HarmonicOscillator {
    fn exact_flow(
        &self,
        t0: f64,
        q0: &SVector<f64, 1>,
        p0: &SVector<f64, 1>,
        t: f64,
    ) -> Result<(SVector<f64, 1>, SVector<f64, 1>)> {
        check_phase(t0, q0, p0)?;
        let tau = finite("t", t)? - t0;
        // The phase ωτ must be known to 1e−6 rad (its rounding is ≈ |ωτ|·ε).
        phase_advance("harmonic oscillator exact flow", self.omega * tau)?;
        let (q, p) = self.flow_map(tau).apply(t, q0, p0);
        finite("q(t)", q[0])?;
        finite("p(t)", p[0])?;
        Ok((q, p))
    }
}

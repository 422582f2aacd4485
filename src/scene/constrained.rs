//! A constrained Lagrangian system with Pfaffian constraints as a scene [`Case`]: the multiplier
//! form of [`Constrained`] (the index-1 equations in `(q, q̇)`, SPEC M16) integrated by DOP853
//! (`dop853`), the same with projection of the velocities (`dop853-projection`) and the discrete
//! Lagrange–d'Alembert integrator (`lagrange-dalembert`) of
//! [`CONSTRAINED_METHODS`](crate::nonholonomic::CONSTRAINED_METHODS) (SPEC X6); the Jacobi
//! integral `h = q̇·∂L/∂q̇ − L` as the energy and the largest constraint residual
//! `max_r |g_r(t, q, q̇)|` beside it as the quantities whose drift the scene draws, the path
//! `(q₀, q₁)` of the contact point as the portrait, and, where the catalogue gives one, the
//! spectrum of a family of steady motions against its parameter.

use super::case::{
    reference_run_coordinates, Case, History, Outcome, Portrait, Sampler, ADAPTIVE_MAX_STEPS,
    REFERENCE_RTOL,
};
use super::spec::MethodKind;
use crate::constraints::{check_velocities, velocity_jet, PfaffianConstraints};
use crate::error::{Error, Result};
use crate::integrate::{Dop853, GeneralMethod, Work};
use crate::lagrangian::Lagrangian;
use crate::nalgebra::SVector;
use crate::nonholonomic::{Constrained, ConstrainedMethod};
use crate::phase::State;
use crate::stability::{parameter_study, ParameterStudy, Spectrum};
use crate::systems::Invariant;

/// The spectrum of a steady motion at a value of its parameter.
pub type SteadyMotions = Box<dyn Fn(f64) -> Result<Spectrum>>;

/// A constrained system with its initial state (see the [module docs](self)).
pub struct ConstrainedCase<L, C, const N: usize, const K: usize> {
    system: Constrained<L, C, N, K>,
    q0: SVector<f64, N>,
    v0: SVector<f64, N>,
    description: String,
    steady_motions: Option<(&'static str, SteadyMotions)>,
    prepared: Option<(f64, SVector<f64, N>, String)>,
}

impl<L, C, const N: usize, const K: usize> ConstrainedCase<L, C, N, K>
where
    L: Lagrangian<N>,
    C: PfaffianConstraints<N, K>,
{
    /// The system `lagrangian` under `constraints` from `(q₀, q̇₀)` at `t = 0`.
    ///
    /// # Errors
    /// [`Error::ConstraintViolated`] with the residual when `q̇₀` violates the constraints by more
    /// than `1e-12` (relative); NaN/∞.
    pub fn new(
        lagrangian: L,
        constraints: C,
        q0: SVector<f64, N>,
        v0: SVector<f64, N>,
        description: impl Into<String>,
    ) -> Result<Self> {
        check_velocities(&constraints, 0.0, &q0, &v0, 1e-12)?;
        Ok(Self {
            system: Constrained::new(lagrangian, constraints),
            q0,
            v0,
            description: description.into(),
            steady_motions: None,
            prepared: None,
        })
    }

    /// A family of steady motions with parameter `name`: `spectrum(μ)` is the spectrum of the
    /// steady motion at `μ` (drawn by the scene's `output.spectrum`).
    pub fn with_steady_motions(mut self, name: &'static str, spectrum: SteadyMotions) -> Self {
        self.steady_motions = Some((name, spectrum));
        self
    }

    fn end(&self) -> Result<&(f64, SVector<f64, N>, String)> {
        self.prepared
            .as_ref()
            .ok_or_else(|| Error::invalid("case", "run before prepare: no end time"))
    }

    /// The method `kind` at `knob`: DOP853 on the index-reduced equations, or a method of
    /// [`CONSTRAINED_METHODS`](crate::nonholonomic::CONSTRAINED_METHODS).
    fn method(kind: MethodKind, knob: f64) -> Result<ConstrainedMethod> {
        if let Some(info) = kind.constrained() {
            return ConstrainedMethod::new(info, knob, ADAPTIVE_MAX_STEPS);
        }
        match kind.integrator().map(|info| GeneralMethod::new(info, knob)) {
            Some(Ok(GeneralMethod::Dop853(m))) => m
                .with_max_steps(ADAPTIVE_MAX_STEPS)
                .map(ConstrainedMethod::Reduced),
            Some(Err(e)) => Err(e),
            _ => Err(Error::invalid(
                format!("method {}", kind.key()),
                "does not apply to this system (constrained systems run DOP853 on the \
                 multiplier form, with or without projection, and the discrete \
                 Lagrange–d'Alembert integrator)",
            )),
        }
    }

    /// The run of `method` to `t1`: the end state, the work, and the states at about `samples`
    /// times when asked.
    fn drive_method(
        &self,
        method: &ConstrainedMethod,
        t1: f64,
        samples: Option<usize>,
    ) -> Result<(State<N>, Work, Vec<State<N>>)> {
        method.run(&self.system, 0.0, self.q0, self.v0, t1, 1e-12, samples)
    }

    /// The run to `t1` with `method`, sampled by `sampler`.
    fn drive(
        &self,
        method: &Dop853,
        t1: f64,
        sampler: &mut Sampler<N>,
    ) -> Result<crate::integrate::Report<N>> {
        self.system
            .integrate(method, 0.0, self.q0, self.v0, t1, 1e-12, sampler)
    }
}

fn slice<const N: usize>(x: &[f64], what: &str) -> Result<SVector<f64, N>> {
    if x.len() == N {
        Ok(SVector::from_column_slice(x))
    } else {
        Err(Error::invalid(
            what,
            format!("expected {N} entries, found {}", x.len()),
        ))
    }
}

impl<L, C, const N: usize, const K: usize> Case for ConstrainedCase<L, C, N, K>
where
    L: Lagrangian<N>,
    C: PfaffianConstraints<N, K>,
{
    fn describe(&self) -> String {
        self.description.clone()
    }

    fn period(&self) -> Option<f64> {
        None
    }

    fn supports(&self, kind: MethodKind) -> bool {
        kind.key() == "dop853" || kind.constrained().is_some()
    }

    fn error_label(&self) -> String {
        "final configuration error ‖Δq‖".into()
    }

    fn prepare(&mut self, t1: f64) -> Result<()> {
        let tight = Dop853::new(REFERENCE_RTOL, 1e-17)?.with_max_steps(ADAPTIVE_MAX_STEPS)?;
        let check = Dop853::new(1e-13, 1e-16)?.with_max_steps(ADAPTIVE_MAX_STEPS)?;
        let q = self.drive(&tight, t1, &mut Sampler::at(Vec::new()))?.last.q;
        let q2 = self.drive(&check, t1, &mut Sampler::at(Vec::new()))?.last.q;
        let note = format!(
            "reference: DOP853 on the multiplier form at rtol {REFERENCE_RTOL:.1e} (differs from \
             rtol 1e−13 by {:.1e})",
            (q - q2).norm()
        );
        self.prepared = Some((t1, q, note));
        Ok(())
    }

    fn integrated_reference_rtol(&self) -> Option<f64> {
        Some(REFERENCE_RTOL)
    }

    fn reference_coordinates(&self, times: &[f64]) -> Result<Vec<Vec<f64>>> {
        let t1 = self.end()?.0;
        reference_run_coordinates(times, t1, |tight, sampler| {
            self.drive(tight, t1, sampler).map(|_| ())
        })
    }

    fn reference_note(&self) -> String {
        self.end().map(|p| p.2.clone()).unwrap_or_default()
    }

    fn run(&self, kind: MethodKind, knob: f64) -> Result<Outcome> {
        let (t1, q_ref, _) = self.end()?;
        let (last, work, _) = self.drive_method(&Self::method(kind, knob)?, *t1, None)?;
        Ok(Outcome {
            error: (last.q - q_ref).norm(),
            work,
        })
    }

    fn history(&self, kind: MethodKind, knob: f64, samples: usize) -> Result<History> {
        let t1 = self.end()?.0;
        let (_, _, states) = self.drive_method(&Self::method(kind, knob)?, t1, Some(samples))?;
        let mut h = History::default();
        for s in &states {
            h.t.push(s.t);
            h.q.push(s.q.as_slice().to_vec());
            h.p.push(s.p.as_slice().to_vec());
        }
        Ok(h)
    }

    fn steady_motion_parameter(&self) -> Option<&'static str> {
        self.steady_motions.as_ref().map(|(name, _)| *name)
    }

    fn parameter_study(&self, from: f64, to: f64, samples: usize) -> Result<ParameterStudy> {
        match &self.steady_motions {
            Some((_, spectrum)) => parameter_study(spectrum, from, to, samples, 1e-12),
            None => Err(Error::invalid(
                "spectrum",
                "this system has no family of steady motions",
            )),
        }
    }

    fn energy(&self, t: f64, q: &[f64], p: &[f64]) -> Result<f64> {
        let (q, v) = (slice::<N>(q, "q")?, slice::<N>(p, "q̇")?);
        let l = &self.system.lagrangian;
        crate::error::finite(
            "Jacobi integral",
            l.momentum(t, &q, &v)?.dot(&v) - l.value(t, &q, &v)?,
        )
    }

    fn invariants(&self, t: f64, q: &[f64], p: &[f64]) -> Result<Vec<Invariant>> {
        let energy = self.energy(t, q, p)?;
        let (q, v) = (slice::<N>(q, "q")?, slice::<N>(p, "q̇")?);
        let residual = velocity_jet(&self.system.constraints, t, &q, &v)?
            .value
            .amax();
        Ok(vec![
            Invariant {
                name: "energy",
                value: energy,
            },
            Invariant {
                name: "constraint residual",
                value: residual,
            },
        ])
    }

    fn portrait(&self) -> Portrait {
        Portrait {
            title: "path",
            x_label: "x",
            y_label: "y",
            equal_aspect: true,
            project: |q, _| (q[0], q[1]),
        }
    }
}

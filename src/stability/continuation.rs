//! Spectra of a linearisation against a parameter `μ` (the forward speed of a rolling vehicle,
//! a mass ratio, …) and the parameter values where a real part crosses zero — the stability
//! boundaries [Ardema 12.3; Hamel art. 244] (SPEC M34, M70).
//!
//! [`real_part_crossings`] samples the number of transverse eigenvalues with `Re λ > 0`
//! ([`Spectrum::unstable_count`]) on a grid of `μ`; where it changes between two samples the
//! crossing is located by Brent's method (`argmin`'s `BrentRoot`) on a test function that
//! changes sign there (Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., §10.2):
//!
//! * an eigenvalue through zero — a real eigenvalue changing sign, or a pair `±λ` turning from
//!   real to imaginary as at the rolling disk's critical speed — changes the sign of
//!   `det(Wᵀ A W) = Π λ_i` ([`CrossingKind::ThroughZero`]);
//! * a complex pair crossing the imaginary axis away from zero changes the sign of its real part,
//!   the test function then being the real part of the complex eigenvalue nearest the axis
//!   ([`CrossingKind::ComplexPair`]).
//!
//! The family's zero eigenvalues are factored out first, so that the test functions are smooth.

use super::spectrum::{Spectrum, C64};
use crate::error::{finite, Error, Result};

/// Largest number of samples [`real_part_crossings`] accepts.
pub const MAX_SAMPLES: usize = 1_000_000;

/// Brent iterations per crossing.
const BRENT_ITERATIONS: u64 = 200;

/// The spectrum at one parameter value.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectrumAt {
    /// `μ`.
    pub parameter: f64,
    /// The spectrum there.
    pub spectrum: Spectrum,
}

/// How eigenvalues cross the imaginary axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CrossingKind {
    /// Through zero: `det(Wᵀ A W)` changes sign.
    ThroughZero,
    /// A complex pair crosses the axis at `±iω`, `ω ≠ 0`.
    ComplexPair,
}

/// A parameter value where a real part crosses zero.
#[derive(Clone, Debug, PartialEq)]
pub struct Crossing {
    /// `μ*`, located to the requested tolerance.
    pub parameter: f64,
    /// The kind of crossing.
    pub kind: CrossingKind,
    /// The grid bracket `(μ_a, μ_b)` in which it was found.
    pub bracket: (f64, f64),
    /// The number of transverse eigenvalues with `Re λ > 0` at `μ_a` and at `μ_b`.
    pub unstable_counts: (usize, usize),
    /// The transverse eigenvalues at `μ*`.
    pub eigenvalues: Vec<C64>,
    /// Brent iterations used.
    pub iterations: u64,
}

/// The spectra `spectrum_at(μ)` at the given parameter values.
///
/// # Errors
/// [`Error::NonFinite`] for a NaN/∞ parameter; the errors of `spectrum_at`.
pub fn spectra<F>(spectrum_at: F, parameters: &[f64]) -> Result<Vec<SpectrumAt>>
where
    F: Fn(f64) -> Result<Spectrum>,
{
    parameters
        .iter()
        .map(|&mu| {
            let mu = finite("parameter μ", mu)?;
            Ok(SpectrumAt {
                parameter: mu,
                spectrum: spectrum_at(mu)?,
            })
        })
        .collect()
}

/// The real part of the complex transverse eigenvalue nearest the imaginary axis (`|Im| >`
/// tolerance), if any.
fn nearest_complex(s: &Spectrum) -> Option<f64> {
    s.transverse
        .iter()
        .filter(|l| l.im.abs() > s.tolerance)
        .map(|l| l.re)
        .min_by(|a, b| a.abs().total_cmp(&b.abs()))
}

fn determinant(s: &Spectrum) -> f64 {
    s.transverse_matrix.determinant()
}

struct TestFunction<'a, F> {
    spectrum_at: &'a F,
    kind: CrossingKind,
}

impl<F: Fn(f64) -> Result<Spectrum>> argmin::core::CostFunction for TestFunction<'_, F> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, mu: &f64) -> std::result::Result<f64, argmin::core::Error> {
        let s = (self.spectrum_at)(*mu)?;
        let g = match self.kind {
            CrossingKind::ThroughZero => determinant(&s),
            CrossingKind::ComplexPair => nearest_complex(&s).unwrap_or(f64::NAN),
        };
        if g.is_finite() {
            Ok(g)
        } else {
            Err(Error::NonFinite {
                what: format!("stability test function at μ = {mu}"),
                value: g,
            }
            .into())
        }
    }
}

/// The parameter values in `[lo, hi]` where a real part of the transverse spectrum
/// `spectrum_at(μ)` crosses zero (see the [module docs](self)): `samples ≥ 2` equally spaced
/// values bracket the changes of [`Spectrum::unstable_count`], and Brent's method locates each to
/// `tol` in `μ` (argmin's `BrentRoot`, whose stopping rule is `|Δμ| ≤ 2ε|μ| + tol/2`).
///
/// Two crossings within one grid interval that cancel in the count are not seen: the grid must
/// resolve them.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ bounds or tolerance; [`Error::InvalidInput`] for `lo ≥ hi`,
/// `tol ≤ 0`, fewer than 2 or more than [`MAX_SAMPLES`] samples, or a bracket in which neither
/// test function changes sign; [`Error::NotConverged`] when Brent's method fails; the errors of
/// `spectrum_at`.
pub fn real_part_crossings<F>(
    spectrum_at: F,
    lo: f64,
    hi: f64,
    samples: usize,
    tol: f64,
) -> Result<Vec<Crossing>>
where
    F: Fn(f64) -> Result<Spectrum>,
{
    parameter_study(spectrum_at, lo, hi, samples, tol).map(|s| s.crossings)
}

/// A parameter study: the spectra on the grid of `μ` and the crossings located between them.
#[derive(Clone, Debug, PartialEq)]
pub struct ParameterStudy {
    /// The spectra at the `samples` equally spaced values of `μ` in `[lo, hi]`.
    pub spectra: Vec<SpectrumAt>,
    /// The parameter values where a real part crosses zero, in increasing `μ`.
    pub crossings: Vec<Crossing>,
}

/// The spectra `spectrum_at(μ)` on `samples ≥ 2` equally spaced values of `μ` in `[lo, hi]` and
/// the crossings of [`real_part_crossings`] located between them (one evaluation of each grid
/// spectrum serves both).
///
/// # Errors
/// As [`real_part_crossings`].
pub fn parameter_study<F>(
    spectrum_at: F,
    lo: f64,
    hi: f64,
    samples: usize,
    tol: f64,
) -> Result<ParameterStudy>
where
    F: Fn(f64) -> Result<Spectrum>,
{
    let lo = finite("lower parameter bound", lo)?;
    let hi = finite("upper parameter bound", hi)?;
    let tol = finite("parameter tolerance", tol)?;
    if lo >= hi || tol <= 0.0 || !(2..=MAX_SAMPLES).contains(&samples) || !(hi - lo).is_finite() {
        return Err(Error::invalid(
            "parameter sweep",
            format!(
                "[{lo}, {hi}] with {samples} samples and tolerance {tol}: need lo < hi, \
                 2 ≤ samples ≤ {MAX_SAMPLES}, tol > 0"
            ),
        ));
    }
    let grid: Vec<f64> = (0..samples)
        .map(|i| {
            if i + 1 == samples {
                hi
            } else {
                lo + (hi - lo) * (i as f64) / ((samples - 1) as f64)
            }
        })
        .collect();
    let mut out = Vec::new();
    let mut grid_spectra = Vec::with_capacity(samples);
    let mut prev = (grid[0], spectrum_at(grid[0])?);
    for &mu in &grid[1..] {
        let here = (mu, spectrum_at(mu)?);
        let (na, nb) = (prev.1.unstable_count(), here.1.unstable_count());
        if na != nb {
            let (da, db) = (determinant(&prev.1), determinant(&here.1));
            let kind = if da * db < 0.0 {
                CrossingKind::ThroughZero
            } else {
                match (nearest_complex(&prev.1), nearest_complex(&here.1)) {
                    (Some(a), Some(b)) if a * b < 0.0 => CrossingKind::ComplexPair,
                    _ => {
                        return Err(Error::invalid(
                            "parameter sweep",
                            format!(
                                "the unstable count changes from {na} to {nb} in [{}, {mu}] but \
                                 neither det(WᵀAW) nor the real part of a complex pair changes \
                                 sign there: refine the grid",
                                prev.0
                            ),
                        ))
                    }
                }
            };
            let solver = argmin::solver::brent::BrentRoot::new(prev.0, mu, tol);
            let problem = TestFunction {
                spectrum_at: &spectrum_at,
                kind,
            };
            let res = argmin::core::Executor::new(problem, solver)
                .configure(|s| s.max_iters(BRENT_ITERATIONS))
                .run()
                .map_err(|e| Error::NotConverged {
                    what: format!("Brent's method on the stability test function ({e})"),
                    iterations: BRENT_ITERATIONS as usize,
                    residual: f64::NAN,
                })?;
            let state = res.state();
            let converged = matches!(
                state.termination_status,
                argmin::core::TerminationStatus::Terminated(
                    argmin::core::TerminationReason::SolverConverged
                )
            );
            let mu_star = state.param.unwrap_or(f64::NAN);
            if !converged || !mu_star.is_finite() {
                return Err(Error::NotConverged {
                    what: format!("Brent's method in [{}, {mu}]", prev.0),
                    iterations: state.iter as usize,
                    residual: state.cost,
                });
            }
            out.push(Crossing {
                parameter: mu_star,
                kind,
                bracket: (prev.0, mu),
                unstable_counts: (na, nb),
                eigenvalues: spectrum_at(mu_star)?.transverse,
                iterations: state.iter,
            });
        }
        grid_spectra.push(SpectrumAt {
            parameter: prev.0,
            spectrum: std::mem::replace(&mut prev, here).1,
        });
    }
    grid_spectra.push(SpectrumAt {
        parameter: prev.0,
        spectrum: prev.1,
    });
    Ok(ParameterStudy {
        spectra: grid_spectra,
        crossings: out,
    })
}

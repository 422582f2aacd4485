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
//!
//! For a Hamiltonian system the spectrum of `A = J∇²H` keeps its box symmetry, and a stable
//! equilibrium loses stability either through zero or by a **Krein collision**: two elliptic
//! pairs of opposite Krein signature meet on the imaginary axis and leave it as a quartet
//! `±a ± ib`, the real parts growing like `√(μ − μ*)` — no real part changes sign smoothly.
//! [`hamiltonian_crossings`] samples the spectral type ([`HamiltonianSpectrum::spectral_type`])
//! and locates each change by Brent's method on `det A` (through zero) or on the discriminant
//! `Π_{i<j}(s_i − s_j)²` of the characteristic polynomial in `s = λ²`, which is a polynomial in
//! the entries of `A`, computed to `O(ε)` at the collision, and changes sign there
//! ([`CrossingKind::Collision`]; Meyer, Hall & Offin, *Introduction to Hamiltonian Dynamical
//! Systems*, 2nd ed., §5.2; at L4 of the restricted three-body problem it is
//! `1 − 27μ(1 − μ)`, zero at Routh's ratio).

use super::hamiltonian_spectrum::{
    collision_discriminant, hamiltonian_spectrum, j_times, HamiltonianSpectrum,
};
use super::spectrum::{Spectrum, C64};
use crate::error::{finite, Error, Result};
use nalgebra::DMatrix;

/// Largest number of samples [`real_part_crossings`] accepts.
pub const MAX_SAMPLES: usize = 1_000_000;

/// Brent iterations per crossing.
const BRENT_ITERATIONS: u64 = 200;

/// The spectrum at one parameter value.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SpectrumAt {
    /// `μ`.
    pub parameter: f64,
    /// The spectrum there.
    pub spectrum: Spectrum,
}

/// How eigenvalues cross the imaginary axis.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum CrossingKind {
    /// Through zero: `det(Wᵀ A W)` changes sign.
    ThroughZero,
    /// A complex pair crosses the axis at `±iω`, `ω ≠ 0`.
    ComplexPair,
    /// Two pairs of a Hamiltonian spectrum collide on an axis and leave it as a complex quartet
    /// (or the reverse): the λ²-discriminant changes sign — on the imaginary axis a Krein
    /// collision of pairs of opposite signature (the Hamiltonian–Hopf bifurcation).
    Collision,
}

/// A parameter value where a real part crosses zero.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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

/// A scalar test function `g(μ)` whose sign change marks the crossing sought.
struct TestFunction<'a> {
    g: &'a dyn Fn(f64) -> Result<f64>,
}

impl argmin::core::CostFunction for TestFunction<'_> {
    type Param = f64;
    type Output = f64;
    fn cost(&self, mu: &f64) -> std::result::Result<f64, argmin::core::Error> {
        let g = (self.g)(*mu)?;
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

/// The root of the test function `g` in the bracket `[a, b]` by Brent's method (argmin's
/// `BrentRoot`) to `tol` in `μ`, with the iterations used.
fn brent_root(g: &dyn Fn(f64) -> Result<f64>, a: f64, b: f64, tol: f64) -> Result<(f64, u64)> {
    let solver = argmin::solver::brent::BrentRoot::new(a, b, tol);
    let res = argmin::core::Executor::new(TestFunction { g }, solver)
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
            what: format!("Brent's method in [{a}, {b}]"),
            iterations: state.iter as usize,
            residual: state.cost,
        });
    }
    Ok((mu_star, state.iter))
}

/// The grid of `samples` equally spaced values on `[lo, hi]`, after checking the sweep.
fn sweep_grid(lo: f64, hi: f64, samples: usize, tol: f64) -> Result<Vec<f64>> {
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
    Ok((0..samples)
        .map(|i| {
            if i + 1 == samples {
                hi
            } else {
                lo + (hi - lo) * (i as f64) / ((samples - 1) as f64)
            }
        })
        .collect())
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
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
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
    let grid = sweep_grid(lo, hi, samples, tol)?;
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
            let g = |m: f64| -> Result<f64> {
                let s = spectrum_at(m)?;
                Ok(match kind {
                    CrossingKind::ThroughZero => determinant(&s),
                    _ => nearest_complex(&s).unwrap_or(f64::NAN),
                })
            };
            let (mu_star, iterations) = brent_root(&g, prev.0, mu, tol)?;
            out.push(Crossing {
                parameter: mu_star,
                kind,
                bracket: (prev.0, mu),
                unstable_counts: (na, nb),
                eigenvalues: spectrum_at(mu_star)?.transverse,
                iterations,
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

/// The parameter values in `[lo, hi]` where the spectral type of the Hamiltonian matrix
/// `A(μ) = J ∇²H(μ)` changes, `hessian_at(μ)` giving `∇²H` at the equilibrium (see the
/// [module docs](self)): `samples ≥ 2` equally spaced values bracket the changes of
/// [`HamiltonianSpectrum::spectral_type`], and Brent's method locates each to `tol` in `μ`
/// (argmin's `BrentRoot`) on `det A` ([`CrossingKind::ThroughZero`]) or on the λ²-discriminant
/// ([`CrossingKind::Collision`]). [`Crossing::unstable_counts`] counts eigenvalues with
/// `Re λ > 0`.
///
/// # Errors
/// [`Error::NonFinite`] for NaN/∞ bounds or tolerance; [`Error::InvalidInput`] for `lo ≥ hi`,
/// `tol ≤ 0`, fewer than 2 or more than [`MAX_SAMPLES`] samples, or a bracket in which neither
/// test function changes sign; [`Error::NotConverged`] when Brent's method fails; the errors of
/// `hessian_at` and of [`hamiltonian_spectrum()`].
pub fn hamiltonian_crossings<F>(
    hessian_at: F,
    lo: f64,
    hi: f64,
    samples: usize,
    tol: f64,
) -> Result<Vec<Crossing>>
where
    F: Fn(f64) -> Result<DMatrix<f64>>,
{
    let grid = sweep_grid(lo, hi, samples, tol)?;
    let at = |mu: f64| -> Result<(DMatrix<f64>, HamiltonianSpectrum)> {
        let h = hessian_at(mu)?;
        let s = hamiltonian_spectrum(&h)?;
        Ok((j_times(&h), s))
    };
    let mut out = Vec::new();
    let mut prev = (grid[0], at(grid[0])?);
    for &mu in &grid[1..] {
        let here = (mu, at(mu)?);
        let (ta, tb) = (prev.1 .1.spectral_type(), here.1 .1.spectral_type());
        if ta != tb {
            let (da, db) = (prev.1 .0.determinant(), here.1 .0.determinant());
            let (ca, cb) = (
                collision_discriminant(&prev.1 .0),
                collision_discriminant(&here.1 .0),
            );
            let kind = if ca * cb < 0.0 {
                CrossingKind::Collision
            } else if da * db < 0.0 {
                CrossingKind::ThroughZero
            } else {
                return Err(Error::invalid(
                    "parameter sweep",
                    format!(
                        "the spectral type changes from {ta:?} to {tb:?} in [{}, {mu}] but \
                         neither det A nor the λ²-discriminant changes sign there: refine the grid",
                        prev.0
                    ),
                ));
            };
            let g = |m: f64| -> Result<f64> {
                let a = j_times(&hessian_at(m)?);
                Ok(match kind {
                    CrossingKind::Collision => collision_discriminant(&a),
                    _ => a.determinant(),
                })
            };
            let (mu_star, iterations) = brent_root(&g, prev.0, mu, tol)?;
            out.push(Crossing {
                parameter: mu_star,
                kind,
                bracket: (prev.0, mu),
                unstable_counts: (prev.1 .1.unstable_count(), here.1 .1.unstable_count()),
                eigenvalues: at(mu_star)?.1.eigenvalues,
                iterations,
            });
        }
        prev = here;
    }
    Ok(out)
}

//! A scene's own system, given by expressions ([`crate::expression`]):
//!
//! ```toml
//! [system]                                  # name = "expression" is implied by `hamiltonian`
//! hamiltonian = "(p_x^2 + p_y^2)/2 + (x^2 + y^2)/2 + x^2*y - y^3/3"
//! coordinates = ["x", "y"]                  # 1 … 6 names; the number of degrees of freedom
//! # momenta = ["p_x", "p_y"]                # default: p_<coordinate>
//! # parameters = { lambda = 1.0 }           # names usable in the expression, with values
//! q = [0.0, 0.1]                            # the initial state
//! p = [0.39, 0.0]
//! # period = 6.28                           # unit of `span.periods` (else give `span.time`)
//! ```
//!
//! The general methods apply to every such system; when every term of the sum at the top of `H`
//! depends on the momenta only or on the coordinates only, `H = T(p) + V(q)` and the explicit
//! splitting methods apply as well. The reference is DOP853 at a tight tolerance.

use super::case::{separable_stepper, Case, HamiltonianCase};
use super::catalogue::Params;
use super::spec::SceneError;
use crate::error::{fmt_num, Error};
use crate::expression::{ExpressionHamiltonian, ExpressionSeparable, MAX_DOF};
use crate::nalgebra::SVector;
use crate::with_dof;

/// The case of a `[system]` table that gives `hamiltonian = "…"` (see the [module docs](self)):
/// a [`Builder`](super::catalogue::Builder) of the catalogue, registered as `expression`.
///
/// # Errors
/// Missing `hamiltonian`, `coordinates`, `q` or `p`; a number of coordinates outside
/// `1 … MAX_DOF`; `q`, `p` or `momenta` of another length; the expression's parse errors (with
/// the column); an initial state where `H` or its gradient is not finite.
pub fn expression_system(s: &Params<'_>) -> Result<Box<dyn Case>, SceneError> {
    let text = s
        .text("hamiltonian")?
        .ok_or_else(|| s.error("hamiltonian", "missing: the Hamiltonian as an expression"))?;
    let coordinates = s.texts("coordinates")?.ok_or_else(|| {
        s.error(
            "coordinates",
            "missing: the names of the coordinates, e.g. [\"x\", \"y\"]",
        )
    })?;
    let momenta = s.texts("momenta")?;
    let parameters = s.named_numbers("parameters")?;
    let period = s.opt("period")?;
    if let Some(t) = period.filter(|t| *t <= 0.0) {
        return Err(s.error(
            "period",
            format!("expected a positive number, found {}", fmt_num(t)),
        ));
    }
    let n = coordinates.len();
    let spec = Spec {
        text: &text,
        coordinates: coordinates.iter().map(String::as_str).collect(),
        momenta: momenta
            .as_ref()
            .map(|m| m.iter().map(String::as_str).collect()),
        parameters: parameters.iter().map(|(k, v)| (k.as_str(), *v)).collect(),
        period,
    };
    with_dof!(n, N => case::<N>(s, &spec), Err(s.error(
        "coordinates",
        format!("{n} coordinates; an expression system has 1 … {MAX_DOF}"),
    )))
}

struct Spec<'a> {
    text: &'a str,
    coordinates: Vec<&'a str>,
    momenta: Option<Vec<&'a str>>,
    parameters: Vec<(&'a str, f64)>,
    period: Option<f64>,
}

/// A library error at `key`, a parse error as its reason and column on one line.
fn at(s: &Params<'_>, key: &str, e: Error) -> SceneError {
    match e {
        Error::Parse { column, reason, .. } => s.error(key, format!("column {column}: {reason}")),
        e => s.error(key, e.to_string()),
    }
}

fn case<const N: usize>(s: &Params<'_>, spec: &Spec<'_>) -> Result<Box<dyn Case>, SceneError> {
    let vector = |key: &str| -> Result<SVector<f64, N>, SceneError> {
        let v = s.numbers(key)?.ok_or_else(|| {
            s.error(
                key,
                format!("missing: the initial {key}, {N} numbers (one per coordinate)"),
            )
        })?;
        if v.len() != N {
            return Err(s.error(
                key,
                format!(
                    "expected {N} numbers (one per coordinate), found {}",
                    v.len()
                ),
            ));
        }
        Ok(SVector::from_column_slice(&v))
    };
    let (q0, p0) = (vector("q")?, vector("p")?);
    let key = match spec.momenta.as_ref() {
        Some(m) if m.len() != N => "momenta",
        _ => "hamiltonian",
    };
    let system = ExpressionHamiltonian::<N>::new(
        spec.text,
        &spec.coordinates,
        spec.momenta.as_deref(),
        &spec.parameters,
    )
    .map_err(|e| at(s, key, e))?;
    system
        .check_state(0.0, &q0, &p0)
        .map_err(|e| at(s, "q", e))?;
    let list = |v: &SVector<f64, N>| v.iter().map(|x| fmt_num(*x)).collect::<Vec<_>>().join(", ");
    let description = format!(
        "H = {}, q₀ = ({}), p₀ = ({})",
        spec.text,
        list(&q0),
        list(&p0)
    );
    Ok(match system.separable() {
        Some(sep) => {
            let mut c = HamiltonianCase::new(sep, q0, p0, description)
                .map_err(|e| s.library(e))?
                .with_stepper(separable_stepper::<ExpressionSeparable<N>, N>());
            if let Some(t) = spec.period {
                c = c.with_period(t);
            }
            Box::new(c)
        }
        None => {
            let mut c =
                HamiltonianCase::new(system, q0, p0, description).map_err(|e| s.library(e))?;
            if let Some(t) = spec.period {
                c = c.with_period(t);
            }
            Box::new(c)
        }
    })
}

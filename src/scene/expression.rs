//! A scene's own system, given by expressions ([`crate::expression`]), in one of three forms.
//!
//! A Hamiltonian `H(t, q, p)`:
//!
//! ```toml
//! [system]                                  # name = "expression" is implied by the form's key
//! hamiltonian = "(p_x^2 + p_y^2)/2 + (x^2 + y^2)/2 + x^2*y - y^3/3"
//! coordinates = ["x", "y"]                  # 1 … 6 names; the number of degrees of freedom
//! # momenta = ["p_x", "p_y"]                # default: p_<coordinate>
//! # parameters = { lambda = 1.0 }           # names usable in the expression, with values
//! q = [0.0, 0.1]                            # the initial state
//! p = [0.39, 0.0]
//! # period = 6.28                           # unit of `span.periods` (else give `span.time`)
//! ```
//!
//! When every term of the sum at the top of `H` depends on the momenta only or on the
//! coordinates only, `H = T(p) + V(q)` and the explicit splitting methods apply as well.
//!
//! A Lagrangian `L(t, q, q̇)`, run as the Hamiltonian `H = p·q̇ − L` of its Legendre transform
//! ([`Legendre`]; `p = ∂L/∂q̇`, the initial momenta from the initial velocities), with optional
//! holonomic constraints `g_r(t, q) = 0` (1 … 3 of them, fewer than the coordinates):
//!
//! ```toml
//! [system]
//! lagrangian = "(v_x^2 + v_y^2 + v_z^2)/2 - g*z"
//! coordinates = ["x", "y", "z"]
//! # velocities = ["v_x", "v_y", "v_z"]      # default: v_<coordinate>
//! parameters = { g = 1.0, l = 1.0 }
//! constraints = ["x^2 + y^2 + z^2 - l^2"]   # optional: g(t, q) = 0
//! q = [0.6, 0.0, -0.8]                      # the initial configuration (on the constraints)
//! v = [0.0, 1.0, 0.0]                       # and velocities (tangent to them)
//! ```
//!
//! Constraints may instead be Pfaffian (non-holonomic in general), `Σ_s a_rs(t, q) q̇_s +
//! b_r(t, q) = 0`, one row of coefficients per constraint (1 … 3 rows, fewer than the
//! coordinates) and optional terms `b_r` (default 0), e.g. the Chaplygin sleigh, whose blade
//! does not slide sideways:
//!
//! ```toml
//! [system]
//! lagrangian = "m/2*(v_x^2 + v_y^2) + m*s*v_th*(v_y*cos(th) - v_x*sin(th)) + I/2*v_th^2"
//! coordinates = ["x", "y", "th"]
//! parameters = { m = 2.0, s = 0.5, I = 1.0 }
//! pfaffian = [["-sin(th)", "cos(th)", "0"]]  # a_rs(t, q): row r multiplies q̇
//! # pfaffian_rhs = ["0"]                     # b_r(t, q), one per row; default 0
//! q = [0.0, 0.0, 0.0]
//! v = [0.0, 0.0, 1.4142135623730951]         # satisfies a q̇ + b = 0
//! ```
//!
//! `constraints` and `pfaffian` exclude each other (a holonomic `g = 0` is the Pfaffian row
//! `∂g/∂q` with the term `∂g/∂t`). The rows must be finite and independent at the initial
//! configuration (else an error naming the dependent rows), and the initial velocities must
//! satisfy them (else an error with the residual).
//!
//! Without constraints the general methods apply (Runge–Kutta, Gauss–Legendre, DOP853); with
//! them the constrained ones of [`ConstrainedCase`]: DOP853 on the multiplier form, with
//! projection, and the discrete Lagrange–d'Alembert integrator.
//!
//! A disturbing function `R(t, q)` of the Kepler problem, with the sign of celestial mechanics:
//! the force is `+∇R` and
//!
//! ```math
//! H = \tfrac12|p|^2 - \frac{\mu}{|q|} - R(t, q)
//! ```
//!
//! ([`crate::expression::disturbing`]); the coordinates are Cartesian, `x, y, z` (or two of them,
//! in the plane), `p` the velocity, and `mu` is usable in the expression:
//!
//! ```toml
//! [system]
//! disturbing_function = "mu*J2*Re^2/2*(x^2 + y^2 - 2*z^2)/(x^2 + y^2 + z^2)^2.5"
//! mu = 1.0                                  # default 1
//! parameters = { J2 = 1.08e-3, Re = 0.9 }
//! q = [1.2, 0.0, 0.0]
//! p = [0.0, 0.8, 0.5]
//! ```
//!
//! Every integrator applies to it, the splittings and the Wisdom–Holman and SABA methods
//! included; the period of the osculating orbit at the start is the unit of `span.periods`.
//!
//! The reference is DOP853 at a tight tolerance. A non-finite value at the initial state (of the
//! expression or of its derivatives) is refused, parse errors name their column, and keys of
//! another form are unknown keys.

use super::case::{kepler_splitting_stepper, separable_stepper, Case, HamiltonianCase, Portrait};
use super::catalogue::Params;
use super::constrained::ConstrainedCase;
use super::spec::SceneError;
use crate::constraints::Differentiated;
use crate::error::{fmt_num, Error};
use crate::expression::{
    ExpressionConstraints, ExpressionDisturbingFunction, ExpressionHamiltonian,
    ExpressionLagrangian, ExpressionPfaffian, ExpressionSeparable, MAX_DOF,
};
use crate::nalgebra::SVector;
use crate::perturbation::forces::{NoForce, PerturbedTwoBody};
use crate::with_dof;
use crate::{Hamiltonian, Lagrangian, Legendre};
use std::f64::consts::TAU;

/// The keys that give the system, one per form.
const FORMS: [&str; 3] = ["hamiltonian", "lagrangian", "disturbing_function"];

/// The most constraints a scene's Lagrangian takes.
pub const MAX_CONSTRAINTS: usize = 3;

/// The case of a `[system]` table that gives `hamiltonian`, `lagrangian` or
/// `disturbing_function` (see the [module docs](self)): a
/// [`Builder`](super::catalogue::Builder) of the catalogue, registered as `expression`.
///
/// # Errors
/// None or more than one of the three forms; a missing key of the form; a number of coordinates
/// outside `1 … MAX_DOF` (2 or 3 for a disturbing function); vectors or names of another length;
/// the expressions' parse errors (with the column); an initial state where an expression or its
/// derivatives are not finite, or off the constraints.
pub fn expression_system(s: &Params<'_>) -> Result<Box<dyn Case>, SceneError> {
    let mut given = Vec::new();
    for key in FORMS {
        if let Some(text) = s.text(key)? {
            given.push((key, text));
        }
    }
    match given.as_slice() {
        [] => Err(s.error(
            "hamiltonian",
            "missing: the system as an expression, `hamiltonian`, `lagrangian` or \
             `disturbing_function`",
        )),
        [(key, text)] => match *key {
            "hamiltonian" => hamiltonian_system(s, text),
            "lagrangian" => lagrangian_system(s, text),
            _ => disturbing_system(s, text),
        },
        [(first, _), (second, _), ..] => Err(s.error(
            second,
            format!("give one form of the system; `{first}` is given too"),
        )),
    }
}

/// The names at `key`, required.
fn names(s: &Params<'_>, key: &str, example: &str) -> Result<Vec<String>, SceneError> {
    s.texts(key)?.ok_or_else(|| {
        s.error(
            key,
            format!("missing: the names of the {key}, e.g. {example}"),
        )
    })
}

/// `period`, if given: positive.
fn period(s: &Params<'_>) -> Result<Option<f64>, SceneError> {
    let period = s.opt("period")?;
    if let Some(t) = period.filter(|t| *t <= 0.0) {
        return Err(s.error(
            "period",
            format!("expected a positive number, found {}", fmt_num(t)),
        ));
    }
    Ok(period)
}

/// The vector at `key`, required, of `N` numbers (one per coordinate).
fn vector<const N: usize>(s: &Params<'_>, key: &str) -> Result<SVector<f64, N>, SceneError> {
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
}

/// A library error at `key`, a parse error as its reason and column on one line.
fn at(s: &Params<'_>, key: &str, e: Error) -> SceneError {
    match e {
        Error::Parse { column, reason, .. } => s.error(key, format!("column {column}: {reason}")),
        e => s.error(key, e.to_string()),
    }
}

fn list<const N: usize>(v: &SVector<f64, N>) -> String {
    v.iter().map(|x| fmt_num(*x)).collect::<Vec<_>>().join(", ")
}

/// The form's names, parameters and period, borrowed for the monomorphised builders.
struct Spec<'a> {
    text: &'a str,
    coordinates: Vec<&'a str>,
    /// Momenta or velocities, if named.
    second: Option<Vec<&'a str>>,
    parameters: Vec<(&'a str, f64)>,
    period: Option<f64>,
}

impl<'a> Spec<'a> {
    fn new(
        text: &'a str,
        coordinates: &'a [String],
        second: Option<&'a [String]>,
        parameters: &'a [(String, f64)],
        period: Option<f64>,
    ) -> Self {
        Self {
            text,
            coordinates: coordinates.iter().map(String::as_str).collect(),
            second: second.map(|m| m.iter().map(String::as_str).collect()),
            parameters: parameters.iter().map(|(k, v)| (k.as_str(), *v)).collect(),
            period,
        }
    }
}

fn too_many(s: &Params<'_>, n: usize) -> Result<Box<dyn Case>, SceneError> {
    Err(s.error(
        "coordinates",
        format!("{n} coordinates; an expression system has 1 … {MAX_DOF}"),
    ))
}

// ---------------------------------------------------------------------------------------------
// H(t, q, p)
// ---------------------------------------------------------------------------------------------

fn hamiltonian_system(s: &Params<'_>, text: &str) -> Result<Box<dyn Case>, SceneError> {
    let coordinates = names(s, "coordinates", "[\"x\", \"y\"]")?;
    let momenta = s.texts("momenta")?;
    let parameters = s.named_numbers("parameters")?;
    let spec = Spec::new(
        text,
        &coordinates,
        momenta.as_deref(),
        &parameters,
        period(s)?,
    );
    with_dof!(coordinates.len(), N => hamiltonian_case::<N>(s, &spec), too_many(s, coordinates.len()))
}

fn hamiltonian_case<const N: usize>(
    s: &Params<'_>,
    spec: &Spec<'_>,
) -> Result<Box<dyn Case>, SceneError> {
    let (q0, p0) = (vector::<N>(s, "q")?, vector::<N>(s, "p")?);
    let key = match spec.second.as_ref() {
        Some(m) if m.len() != N => "momenta",
        _ => "hamiltonian",
    };
    let system = ExpressionHamiltonian::<N>::new(
        spec.text,
        &spec.coordinates,
        spec.second.as_deref(),
        &spec.parameters,
    )
    .map_err(|e| at(s, key, e))?;
    system
        .check_state(0.0, &q0, &p0)
        .map_err(|e| at(s, "q", e))?;
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

// ---------------------------------------------------------------------------------------------
// L(t, q, q̇), with holonomic constraints
// ---------------------------------------------------------------------------------------------

fn lagrangian_system(s: &Params<'_>, text: &str) -> Result<Box<dyn Case>, SceneError> {
    let coordinates = names(s, "coordinates", "[\"x\", \"y\"]")?;
    let velocities = s.texts("velocities")?;
    let parameters = s.named_numbers("parameters")?;
    let constraints = s.texts("constraints")?;
    let rows = s.text_rows("pfaffian")?;
    let rhs = s.texts("pfaffian_rhs")?;
    let spec = Spec::new(
        text,
        &coordinates,
        velocities.as_deref(),
        &parameters,
        period(s)?,
    );
    let n = coordinates.len();
    if rhs.is_some() && rows.is_none() {
        return Err(s.error(
            "pfaffian_rhs",
            "the terms b_r of Pfaffian constraints need their coefficients `pfaffian`",
        ));
    }
    match (constraints, rows) {
        (None, None) => with_dof!(n, N => lagrangian_case::<N>(s, &spec), too_many(s, n)),
        (Some(g), None) => {
            let g: Vec<&str> = g.iter().map(String::as_str).collect();
            with_dof!(n, N => constrained::<N>(s, &spec, &g), too_many(s, n))
        }
        (None, Some(a)) => {
            with_dof!(n, N => pfaffian::<N>(s, &spec, &a, rhs.as_deref()), too_many(s, n))
        }
        (Some(_), Some(_)) => Err(s.error(
            "pfaffian",
            "give the constraints either as holonomic `constraints` or as Pfaffian `pfaffian` \
             (a holonomic g(t, q) = 0 is the Pfaffian row ∂g/∂q with the term ∂g/∂t)",
        )),
    }
}

/// `L` by expression with the initial `(q, q̇)`, checked finite.
fn lagrangian<const N: usize>(
    s: &Params<'_>,
    spec: &Spec<'_>,
) -> Result<(ExpressionLagrangian<N>, SVector<f64, N>, SVector<f64, N>), SceneError> {
    let (q0, v0) = (vector::<N>(s, "q")?, vector::<N>(s, "v")?);
    let key = match spec.second.as_ref() {
        Some(m) if m.len() != N => "velocities",
        _ => "lagrangian",
    };
    let l = ExpressionLagrangian::<N>::new(
        spec.text,
        &spec.coordinates,
        spec.second.as_deref(),
        &spec.parameters,
    )
    .map_err(|e| at(s, key, e))?;
    let named = |e: Error| at(s, "q", e.in_expression(spec.text));
    l.value(0.0, &q0, &v0).map_err(named)?;
    l.mass_matrix(0.0, &q0, &v0).map_err(named)?;
    Ok((l, q0, v0))
}

fn lagrangian_case<const N: usize>(
    s: &Params<'_>,
    spec: &Spec<'_>,
) -> Result<Box<dyn Case>, SceneError> {
    let (l, q0, v0) = lagrangian::<N>(s, spec)?;
    let named = |e: Error| at(s, "q", e.in_expression(spec.text));
    let p0 = l.momentum(0.0, &q0, &v0).map_err(named)?;
    let system = Legendre(l);
    system.vector_field(0.0, &q0, &p0).map_err(named)?;
    let description = format!(
        "L = {}, q₀ = ({}), q̇₀ = ({})",
        spec.text,
        list(&q0),
        list(&v0)
    );
    let mut c = HamiltonianCase::new(system, q0, p0, description).map_err(|e| s.library(e))?;
    if let Some(t) = spec.period {
        c = c.with_period(t);
    }
    Ok(Box::new(c))
}

/// Dispatch the number of constraints `K = 1 … MAX_CONSTRAINTS`, `K < N`.
fn constrained<const N: usize>(
    s: &Params<'_>,
    spec: &Spec<'_>,
    g: &[&str],
) -> Result<Box<dyn Case>, SceneError> {
    match g.len() {
        1 if N > 1 => constrained_case::<N, 1>(s, spec, g),
        2 if N > 2 => constrained_case::<N, 2>(s, spec, g),
        3 if N > 3 => constrained_case::<N, 3>(s, spec, g),
        k => Err(s.error(
            "constraints",
            format!(
                "{k} constraints on {N} coordinates; a scene takes 1 … {} (fewer than the \
                 coordinates)",
                MAX_CONSTRAINTS.min(N - 1)
            ),
        )),
    }
}

/// The relative tolerance of the initial state's constraint residuals, as
/// [`ConstrainedCase::new`] checks the velocities.
const CONSTRAINT_TOLERANCE: f64 = 1e-12;

fn constrained_case<const N: usize, const K: usize>(
    s: &Params<'_>,
    spec: &Spec<'_>,
    texts: &[&str],
) -> Result<Box<dyn Case>, SceneError> {
    let (l, q0, v0) = lagrangian::<N>(s, spec)?;
    let g = ExpressionConstraints::<N, K>::new(texts, &spec.coordinates, &spec.parameters)
        .map_err(|e| at(s, "constraints", e))?;
    // On the constraints: |g_r(q₀)| ≤ tol (1 + Σ_s |∂g_r/∂q_s q_s|).
    let value = g.value(0.0, &q0).map_err(|e| at(s, "q", e))?;
    let (jacobian, rate) =
        crate::constraints::PfaffianConstraints::forms(&Differentiated(&g), 0.0, &q0);
    if let Some(x) = jacobian.iter().chain(rate.iter()).find(|x| !x.is_finite()) {
        return Err(s.error(
            "q",
            format!(
                "the derivatives of the constraints are not finite ({}) at q = ({})",
                fmt_num(*x),
                list(&q0)
            ),
        ));
    }
    for r in 0..K {
        let scale: f64 = (0..N).map(|c| (jacobian[(r, c)] * q0[c]).abs()).sum();
        if value[r].abs() > CONSTRAINT_TOLERANCE * (1.0 + scale) {
            return Err(s.error(
                "q",
                format!(
                    "not on the constraint `{}`: its value is {} (tolerance {:.0e} relative)",
                    texts[r],
                    fmt_num(value[r]),
                    CONSTRAINT_TOLERANCE
                ),
            ));
        }
    }
    let description = format!(
        "L = {} under {}, q₀ = ({}), q̇₀ = ({})",
        spec.text,
        texts
            .iter()
            .map(|t| format!("{t} = 0"))
            .collect::<Vec<_>>()
            .join(", "),
        list(&q0),
        list(&v0)
    );
    let case = ConstrainedCase::new(l, Differentiated(g), q0, v0, description)
        .map_err(|e| at(s, "v", e))?;
    Ok(Box::new(case))
}

/// Dispatch the number of Pfaffian constraints `K = 1 … MAX_CONSTRAINTS`, `K < N`.
fn pfaffian<const N: usize>(
    s: &Params<'_>,
    spec: &Spec<'_>,
    rows: &[Vec<String>],
    rhs: Option<&[String]>,
) -> Result<Box<dyn Case>, SceneError> {
    if let Some(b) = rhs.filter(|b| b.len() != rows.len()) {
        return Err(s.error(
            "pfaffian_rhs",
            format!(
                "{} terms for {} rows of `pfaffian` (one b_r per row)",
                b.len(),
                rows.len()
            ),
        ));
    }
    match rows.len() {
        1 if N > 1 => pfaffian_case::<N, 1>(s, spec, rows, rhs),
        2 if N > 2 => pfaffian_case::<N, 2>(s, spec, rows, rhs),
        3 if N > 3 => pfaffian_case::<N, 3>(s, spec, rows, rhs),
        k => Err(s.error(
            "pfaffian",
            format!(
                "{k} rows on {N} coordinates; a scene takes 1 … {} (fewer than the \
                 coordinates)",
                MAX_CONSTRAINTS.min(N - 1)
            ),
        )),
    }
}

fn pfaffian_case<const N: usize, const K: usize>(
    s: &Params<'_>,
    spec: &Spec<'_>,
    rows: &[Vec<String>],
    rhs: Option<&[String]>,
) -> Result<Box<dyn Case>, SceneError> {
    let (l, q0, v0) = lagrangian::<N>(s, spec)?;
    let c = ExpressionPfaffian::<N, K>::new(rows, rhs, &spec.coordinates, &spec.parameters)
        .map_err(|e| at(s, "pfaffian", e))?;
    // Finite rows of full rank at the initial configuration; then ConstrainedCase::new checks
    // the initial velocities against them.
    c.check_configuration(0.0, &q0).map_err(|e| at(s, "q", e))?;
    let form = |r: usize| {
        let terms = rows[r]
            .iter()
            .zip(&spec.coordinates)
            .map(|(a, q)| format!("({a}) v_{q}"))
            .collect::<Vec<_>>()
            .join(" + ");
        match rhs {
            Some(b) => format!("{terms} + {} = 0", b[r]),
            None => format!("{terms} = 0"),
        }
    };
    let description = format!(
        "L = {} under {}, q₀ = ({}), q̇₀ = ({})",
        spec.text,
        (0..K).map(form).collect::<Vec<_>>().join(", "),
        list(&q0),
        list(&v0)
    );
    let case = ConstrainedCase::new(l, c, q0, v0, description).map_err(|e| at(s, "v", e))?;
    Ok(Box::new(case))
}

// ---------------------------------------------------------------------------------------------
// Kepler − R(t, q)
// ---------------------------------------------------------------------------------------------

fn disturbing_system(s: &Params<'_>, text: &str) -> Result<Box<dyn Case>, SceneError> {
    let mu = s.positive_or("mu", 1.0)?;
    let coordinates = s.texts("coordinates")?;
    let mut parameters = s.named_numbers("parameters")?;
    if parameters.iter().any(|(k, _)| k == "mu") {
        return Err(s.error(
            "parameters.mu",
            "`mu` is the system's key `mu`, usable in the expression as it is",
        ));
    }
    parameters.push(("mu".to_string(), mu));
    let n = match &coordinates {
        Some(c) => c.len(),
        None => s.numbers("q")?.map_or(3, |q| q.len()),
    };
    let spec = Spec::new(
        text,
        coordinates.as_deref().unwrap_or(&[]),
        None,
        &parameters,
        period(s)?,
    );
    let coordinates = coordinates.is_some().then_some(spec.coordinates.as_slice());
    match n {
        2 => disturbing_case::<2>(s, &spec, coordinates, mu),
        3 => disturbing_case::<3>(s, &spec, coordinates, mu),
        n => Err(s.error(
            "coordinates",
            format!("{n} coordinates; a perturbed Kepler problem has 2 (the plane) or 3"),
        )),
    }
}

/// A perturbed Kepler problem given by its disturbing function.
type Disturbed<const N: usize> = PerturbedTwoBody<ExpressionDisturbingFunction<N>, NoForce, N>;

fn orbit(q: &[f64], _p: &[f64]) -> (f64, f64) {
    (q[0], q[1])
}

fn disturbing_case<const N: usize>(
    s: &Params<'_>,
    spec: &Spec<'_>,
    coordinates: Option<&[&str]>,
    mu: f64,
) -> Result<Box<dyn Case>, SceneError> {
    let (q0, p0) = (vector::<N>(s, "q")?, vector::<N>(s, "p")?);
    let r = ExpressionDisturbingFunction::<N>::new(spec.text, coordinates, &spec.parameters)
        .map_err(|e| at(s, "disturbing_function", e))?;
    r.value(0.0, &q0).map_err(|e| at(s, "q", e))?;
    let system: Disturbed<N> = PerturbedTwoBody::conservative(mu, r).map_err(|e| s.library(e))?;
    let named = |e: Error| at(s, "q", e.in_expression(spec.text));
    system.value(0.0, &q0, &p0).map_err(named)?;
    system.vector_field(0.0, &q0, &p0).map_err(named)?;
    // The period of the osculating Kepler orbit (vis-viva), unless given or unbound.
    let energy = p0.norm_squared() / 2.0 - mu / q0.norm();
    let period = spec.period.or_else(|| {
        (energy < 0.0).then(|| {
            let a = -mu / (2.0 * energy);
            TAU * (a.powi(3) / mu).sqrt()
        })
    });
    let description = format!(
        "Kepler (μ = {}) − R, R = {}, q₀ = ({}), p₀ = ({})",
        fmt_num(mu),
        spec.text,
        list(&q0),
        list(&p0)
    );
    let mut c = HamiltonianCase::new(system, q0, p0, description)
        .map_err(|e| s.library(e))?
        .with_stepper(separable_stepper::<Disturbed<N>, N>())
        .with_stepper(kepler_splitting_stepper::<Disturbed<N>, N>())
        .with_portrait(Portrait {
            title: "orbit",
            x_label: "x",
            y_label: "y",
            equal_aspect: true,
            project: orbit,
        });
    if let Some(t) = period.filter(|t| t.is_finite()) {
        c = c.with_period(t);
    }
    Ok(Box::new(c))
}

/// An error of the library, its message naming the expression it arose in.
trait InExpression {
    fn in_expression(self, text: &str) -> Error;
}

impl InExpression for Error {
    fn in_expression(self, text: &str) -> Error {
        match self {
            Error::NonFinite { what, value } => Error::NonFinite {
                what: format!("{what} of `{text}`"),
                value,
            },
            e => e,
        }
    }
}

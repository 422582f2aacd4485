//! The crate's error type.
//!
//! Every public function that can fail on user input returns [`Result<T>`]; the variants carry
//! structured data (the offending value, where it was found, what was expected) so that callers can
//! react programmatically and the message names what went wrong.

use std::fmt;

/// Result alias used throughout the crate.
pub type Result<T> = std::result::Result<T, Error>;

/// Everything that can go wrong in `hamilton-jacobi`.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A number that must be finite is NaN or infinite.
    #[error("{what} must be finite, got {}", fmt_num(*.value))]
    NonFinite {
        /// Which quantity (e.g. `"q[1]"`, `"eccentricity"`).
        what: String,
        /// The offending value.
        value: f64,
    },
    /// A parameter lies outside the domain where the method or formula is defined.
    #[error("{what} = {} is outside the domain {domain}", fmt_num(*.value))]
    OutOfDomain {
        /// Which quantity.
        what: String,
        /// The offending value.
        value: f64,
        /// The admissible domain, in words or interval notation (e.g. `"[0, 1)"`).
        domain: String,
    },
    /// An input is malformed in a way not captured by a single number.
    #[error("invalid input {what}: {reason}")]
    InvalidInput {
        /// Which input.
        what: String,
        /// What is wrong with it.
        reason: String,
    },
    /// An iterative method stopped before reaching its tolerance.
    #[error("{what} did not converge after {iterations} iterations (residual {residual:e})")]
    NotConverged {
        /// Which iteration (e.g. `"Legendre transform Newton"`).
        what: String,
        /// Iterations performed.
        iterations: usize,
        /// Residual norm at the last iterate.
        residual: f64,
    },
    /// A matrix that must be invertible is singular or too ill-conditioned to trust.
    #[error("{what} is singular at {at} (reciprocal condition estimate {rcond:e})")]
    Singular {
        /// Which matrix (e.g. `"mass matrix ∂²L/∂q̇²"`).
        what: String,
        /// The point where it happened, formatted.
        at: String,
        /// Reciprocal condition estimate (0 for exactly singular).
        rcond: f64,
    },
    /// An expression that does not parse: what is wrong and where, with the expression and a
    /// caret under the 1-based character column.
    #[error("{reason} (column {column})\n{}", caret_lines(expression, *column))]
    Parse {
        /// The expression (empty when it was refused whole, e.g. for its length).
        expression: String,
        /// The 1-based character column of the fault.
        column: usize,
        /// What is wrong.
        reason: String,
    },
    /// A call would start more work than its limit allows (steps of a run, repetitions of a
    /// timing loop); the limit is a knob the caller can raise.
    #[error("{what}: limit of {limit} exceeded ({detail}); {hint}")]
    WorkLimit {
        /// Which count (e.g. `"DOP853 attempted steps"`).
        what: String,
        /// The limit in force.
        limit: usize,
        /// What was requested or where the run stood, formatted.
        detail: String,
        /// How to raise the limit (or avoid it).
        hint: String,
    },
    /// The requested motion lies on, or numerically indistinguishable from, a separatrix.
    #[error("{what}: on the separatrix (distance {distance:e}); {hint}")]
    Separatrix {
        /// Which computation.
        what: String,
        /// Distance to the separatrix in the method's natural measure.
        distance: f64,
        /// What to do instead.
        hint: String,
    },
    /// The phase of a periodic motion advanced by `n·Δt` is too large for floating point: its
    /// rounding (about `|phase|·ε`, `ε = 2⁻⁵²`, from the rounding of `n` and of the product) exceeds
    /// the stated tolerance, so the position along the orbit is not determined by the inputs.
    #[error(
        "{what}: the phase advance {phase:e} rad exceeds {limit:e} rad, beyond which its rounding \
         exceeds 1e-6 rad and the phase is lost"
    )]
    PhaseLost {
        /// Which propagation.
        what: String,
        /// The phase advance `n·Δt` (radians).
        phase: f64,
        /// The largest accepted `|n·Δt|` (radians).
        limit: f64,
    },
    /// A computation whose estimated condition number exceeds the threshold above which its
    /// result would carry a relative error of about `condition × ε` (ε = 2⁻⁵²) and is refused.
    #[error(
        "{what} is too ill-conditioned at {at}: condition number {condition:e} exceeds the \
         threshold {threshold:e} (expected relative error ≈ condition × ε = {:e})",
        condition * f64::EPSILON
    )]
    IllConditioned {
        /// Which computation.
        what: String,
        /// The point where it happened, formatted.
        at: String,
        /// The estimated condition number (relative error of the result per unit roundoff).
        condition: f64,
        /// The largest condition number accepted.
        threshold: f64,
    },
    /// A set of constraints whose matrix (`∂g/∂q̇` of velocity constraints, the coefficients of
    /// Pfaffian forms) has lost rank: the named rows are linear combinations of the others at the
    /// configuration `at` (time `t`), so the multipliers are not determined.
    #[error(
        "{what} is rank deficient at t = {}, {at}: rows {rows:?} depend on the others (tolerance {tolerance:e})",
        fmt_num(*.t)
    )]
    RankDeficient {
        /// Which matrix (e.g. `"constraint matrix ∂g/∂q̇"`).
        what: String,
        /// The dependent rows (0-based), each a combination of rows not listed.
        rows: Vec<usize>,
        /// The time of the configuration.
        t: f64,
        /// The configuration, formatted.
        at: String,
        /// The relative tolerance of the rank decision.
        tolerance: f64,
    },
    /// A state that violates the constraints it must satisfy (initial velocities of a constrained
    /// motion); `residual` holds the values `g_r` of the constraints there.
    #[error("{what} violates the constraints: residual {residual:?} exceeds the tolerance {tolerance:e}")]
    ConstraintViolated {
        /// Which state (e.g. `"initial velocities q̇(t₀)"`).
        what: String,
        /// The constraint values `g_r` at the state.
        residual: Vec<f64>,
        /// The tolerance applied to `max |g_r|` (relative to the scale of the terms of `g`).
        tolerance: f64,
    },
    /// An implicit relation with several roots (a multi-sheeted canonical relation) has no root,
    /// or more than one, on the requested sheet.
    #[error(
        "{what} at {at}: {problem} on the requested sheet ({sheet}); candidate roots found: {}",
        format_candidates(candidates)
    )]
    NoRootOnSheet {
        /// Which computation.
        what: String,
        /// The point where it happened, formatted.
        at: String,
        /// The requested sheet, in words.
        sheet: String,
        /// `"no root"` or `"more than one root"`.
        problem: String,
        /// Every root that was found, each as the full result (e.g. `(Q₁, …, P₁, …)`).
        candidates: Vec<Vec<f64>>,
    },
    /// The motion reaches a finite-time singularity: the phase-space rate grows like
    /// `(t* − t)^{−α}` (detected by [`crate::integrate::BlowUpDetector`]), so no step size resolves
    /// the motion beyond `t*`.
    #[error(
        "{what}: finite-time blow-up at t* ≈ {} (rate ∝ (t* − t)^−{}, run stopped at t = {})",
        fmt_num(*t_star),
        fmt_num(*exponent),
        fmt_num(*t_reached)
    )]
    BlowUp {
        /// Which computation.
        what: String,
        /// The extrapolated singular time.
        t_star: f64,
        /// The exponent `α` of the rate's growth.
        exponent: f64,
        /// The time the run reached.
        t_reached: f64,
    },
    /// A perturbation series meets a small divisor: the mode `k` of a term to be removed has
    /// `|k·ω|` at or below the threshold (a resonance of the frequencies `ω`).
    #[error(
        "{what}: small divisor k·ω = {} for the resonance k = {k:?} (threshold {threshold:e})",
        fmt_num(*divisor)
    )]
    SmallDivisor {
        /// Which computation.
        what: String,
        /// The resonance vector `k`.
        k: Vec<i32>,
        /// The divisor `k·ω`.
        divisor: f64,
        /// The threshold it fell below.
        threshold: f64,
    },
}

/// The candidate roots of [`Error::NoRootOnSheet`] in exponent notation.
/// The expression (a window of at most 72 characters around `column`) and a line with a caret
/// under the character at the 1-based `column`.
fn caret_lines(expression: &str, column: usize) -> String {
    let chars: Vec<char> = expression.chars().collect();
    let at = column.saturating_sub(1);
    let start = at.saturating_sub(36).min(chars.len());
    let end = (start + 72).min(chars.len());
    let shown: String = chars[start..end]
        .iter()
        .map(|&c| if c.is_control() { ' ' } else { c })
        .collect();
    format!("  {shown}\n  {}^", " ".repeat(at - start))
}

fn format_candidates(candidates: &[Vec<f64>]) -> String {
    if candidates.is_empty() {
        return "none".into();
    }
    candidates
        .iter()
        .map(|c| {
            let parts: Vec<String> = c.iter().map(|x| format!("{x:.16e}")).collect();
            format!("({})", parts.join(", "))
        })
        .collect::<Vec<_>>()
        .join(", ")
}

impl Error {
    /// Shorthand for [`Error::OutOfDomain`].
    pub fn out_of_domain(what: impl Into<String>, value: f64, domain: impl Into<String>) -> Self {
        Error::OutOfDomain {
            what: what.into(),
            value,
            domain: domain.into(),
        }
    }

    /// Shorthand for [`Error::InvalidInput`].
    pub fn invalid(what: impl Into<String>, reason: impl Into<String>) -> Self {
        Error::InvalidInput {
            what: what.into(),
            reason: reason.into(),
        }
    }
}

/// A number for a message: as written (`{}`) for moderate magnitudes, in exponent notation
/// (`{:e}`) when `|x| < 10⁻⁴` or `|x| ≥ 10⁶`, so that `1e-300` prints as `1e-300` and not as
/// three hundred zeros. Both forms are the shortest that read back as `x`; zero, NaN and ±∞ print
/// as `0`, `NaN` and `±inf`.
pub fn fmt_num(x: f64) -> String {
    let a = x.abs();
    if a == 0.0 || !a.is_finite() || (1e-4..1e6).contains(&a) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// Reject NaN and ±∞: returns `value` unchanged if finite, otherwise [`Error::NonFinite`].
pub fn finite(what: impl fmt::Display, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(Error::NonFinite {
            what: what.to_string(),
            value,
        })
    }
}

/// A message formatted only when it is displayed: `Lazy(|f| write!(f, "t = {t}"))` passed as
/// the `what` of [`finite`] or [`all_finite`] costs nothing unless the check fails (an argument
/// of `format_args!` is evaluated at once, so a `String` built there is built on every call).
pub(crate) struct Lazy<F: Fn(&mut fmt::Formatter<'_>) -> fmt::Result>(pub(crate) F);

impl<F: Fn(&mut fmt::Formatter<'_>) -> fmt::Result> fmt::Display for Lazy<F> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        (self.0)(f)
    }
}

/// Reject a slice containing NaN or ±∞; the error names the first bad component as `what[i]`.
pub fn all_finite(what: impl fmt::Display, values: &[f64]) -> Result<()> {
    match values.iter().position(|v| !v.is_finite()) {
        None => Ok(()),
        Some(i) => Err(Error::NonFinite {
            what: format!("{what}[{i}]"),
            value: values[i],
        }),
    }
}

/// Require `value > 0` (and finite).
pub fn positive(what: impl fmt::Display, value: f64) -> Result<f64> {
    let v = finite(&what, value)?;
    if v > 0.0 {
        Ok(v)
    } else {
        Err(Error::out_of_domain(what.to_string(), v, "(0, ∞)"))
    }
}

/// Require `value ≥ 0` (and finite).
pub fn non_negative(what: impl fmt::Display, value: f64) -> Result<f64> {
    let v = finite(&what, value)?;
    if v >= 0.0 {
        Ok(v)
    } else {
        Err(Error::out_of_domain(what.to_string(), v, "[0, ∞)"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finite_rejects_nan_and_inf() {
        assert!(finite("x", 1.0).is_ok());
        assert!(matches!(
            finite("x", f64::NAN),
            Err(Error::NonFinite { .. })
        ));
        assert!(matches!(
            finite("x", f64::NEG_INFINITY),
            Err(Error::NonFinite { .. })
        ));
        let e = all_finite("q", &[0.0, f64::INFINITY]).unwrap_err();
        assert_eq!(e.to_string(), "q[1] must be finite, got inf");
    }

    #[test]
    fn positive_rejects_zero_and_negative() {
        assert!(positive("m", 2.0).is_ok());
        assert!(matches!(positive("m", 0.0), Err(Error::OutOfDomain { .. })));
        assert!(matches!(
            positive("m", -1.0),
            Err(Error::OutOfDomain { .. })
        ));
        assert!(non_negative("e", 0.0).is_ok());
    }

    #[test]
    fn messages_print_extreme_magnitudes_in_exponent_notation() {
        assert_eq!(fmt_num(1e-300), "1e-300");
        assert_eq!(fmt_num(-1.5e300), "-1.5e300");
        assert_eq!(fmt_num(5e-324), "5e-324");
        assert_eq!(fmt_num(0.25), "0.25");
        assert_eq!(fmt_num(-2.0), "-2");
        assert_eq!(fmt_num(123456.5), "123456.5");
        assert_eq!(fmt_num(1e6), "1e6");
        let e = Error::out_of_domain("x", 1e-300, "[1, 2]");
        assert_eq!(e.to_string(), "x = 1e-300 is outside the domain [1, 2]");
    }
}

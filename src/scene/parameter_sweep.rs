//! `[sweep]`: one number of a scene's `[system]` (an initial condition, a perturbation strength
//! `ε`, `J₂`, a mass ratio, …) varied over a list or a range, every `[[method]]` run at every
//! value of its knob, and their final errors drawn against the parameter.
//!
//! ```toml
//! [sweep]
//! key = "amplitude"              # a number of [system] (parameters.eps: one in a table)
//! from = 0.1                     # and to, samples (spacing linear, or log = true) …
//! to = 3.0
//! samples = 30                   # … or: values = [0.5, 1.0, 2.0]
//! ```
//!
//! Each value builds its own case from the catalogue (its period, and so a span given in
//! periods, follow the parameter), computes its reference and runs the methods. The values run
//! on every core (`rayon`) with a progress bar; they are independent and collected in order, so
//! the results are bit for bit those of a serial run whatever the number of threads. These are
//! not timing runs: the sweep records errors, not times (the `[[method]]` table of the scene is
//! timed serially at the scene's own `[system]`).

use super::catalogue::Catalogue;
use super::runner::end_time;
use super::spec::{SceneError, SceneFile};
use crate::error::fmt_num;
use rayon::prelude::*;
use serde::Deserialize;

/// The most parameter values a sweep may ask for.
pub const MAX_SWEEP_VALUES: usize = 10_000;

/// `[sweep]` as written: the key and either `values` or `from`, `to`, `samples` (with `log`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SweepSpec {
    /// A number of `[system]` (not `name`); `a.b` names `b` in the table `a`, e.g.
    /// `parameters.lambda`.
    pub key: String,
    /// The values, in the order drawn.
    pub values: Option<Vec<f64>>,
    /// First value of a range.
    pub from: Option<f64>,
    /// Last value of a range.
    pub to: Option<f64>,
    /// Number of values of a range (at least 2).
    pub samples: Option<usize>,
    /// Logarithmic spacing of a range (and a logarithmic parameter axis).
    #[serde(default)]
    pub log: bool,
}

/// The final error of one run of a sweep: method index, knob value, error (or why it failed).
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRun {
    /// Index of the `[[method]]`.
    pub method: usize,
    /// Its knob value.
    pub knob: f64,
    /// The final error, or the failure's message.
    pub error: Result<f64, String>,
}

/// The results at one parameter value, in the order of the methods and their knobs.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepPoint {
    /// The parameter value.
    pub value: f64,
    /// Every run at it.
    pub runs: Vec<SweepRun>,
}

/// The parameter values of `[sweep]`, checked.
///
/// # Errors
/// A [`SceneError`] naming the key: a missing or non-numeric `[system]` key, neither or both of
/// `values` and a range, non-finite values, a log range not positive, more than
/// [`MAX_SWEEP_VALUES`] values.
pub fn sweep_values(
    file: &str,
    spec: &SceneFile,
    sweep: &SweepSpec,
) -> Result<Vec<f64>, SceneError> {
    let bad =
        |key: &str, message: String| Err(SceneError::new(file, format!("sweep.{key}"), message));
    if sweep.key == "name" {
        return bad(
            "key",
            "the system's name cannot be swept; give one of its numbers".into(),
        );
    }
    match lookup(&spec.system, &sweep.key) {
        Some(toml::Value::Float(_) | toml::Value::Integer(_)) => {}
        Some(v) => {
            return bad(
                "key",
                format!("`system.{}` is a {}, not a number", sweep.key, v.type_str()),
            )
        }
        None => {
            let known: Vec<&str> = spec
                .system
                .keys()
                .filter(|k| *k != "name")
                .map(String::as_str)
                .collect();
            return bad(
                "key",
                format!(
                    "`{}` is not a key of [system] (give it a value there; the scene's keys: {})",
                    sweep.key,
                    if known.is_empty() {
                        "none".to_string()
                    } else {
                        known.join(", ")
                    }
                ),
            );
        }
    }
    let values = match (&sweep.values, sweep.from, sweep.to, sweep.samples) {
        (Some(v), None, None, None) => {
            if sweep.log {
                return bad(
                    "log",
                    "`log` spaces a range; with `values` give the values".into(),
                );
            }
            if v.is_empty() || v.len() > MAX_SWEEP_VALUES {
                return bad(
                    "values",
                    format!("expected 1..={MAX_SWEEP_VALUES} values, found {}", v.len()),
                );
            }
            v.clone()
        }
        (None, Some(a), Some(b), Some(n)) => {
            if !(2..=MAX_SWEEP_VALUES).contains(&n) {
                return bad(
                    "samples",
                    format!("expected 2..={MAX_SWEEP_VALUES} values, found {n}"),
                );
            }
            if !(a.is_finite() && b.is_finite()) || a == b {
                return bad(
                    "from",
                    format!(
                        "expected two different finite ends, found {} and {}",
                        fmt_num(a),
                        fmt_num(b)
                    ),
                );
            }
            if sweep.log && !(a > 0.0 && b > 0.0) {
                return bad(
                    "from",
                    format!(
                        "a log range needs positive ends, found {} and {}",
                        fmt_num(a),
                        fmt_num(b)
                    ),
                );
            }
            let last = (n - 1) as f64;
            (0..n)
                .map(|j| {
                    let s = j as f64 / last;
                    if j == n - 1 {
                        b
                    } else if sweep.log {
                        (a.ln() + s * (b.ln() - a.ln())).exp()
                    } else {
                        a + s * (b - a)
                    }
                })
                .collect()
        }
        _ => {
            return bad(
                "values",
                "give either `values = [..]` or all of `from`, `to` and `samples`".into(),
            )
        }
    };
    if let Some((j, x)) = values.iter().enumerate().find(|(_, x)| !x.is_finite()) {
        return bad(
            &format!("values[{j}]"),
            format!("expected a finite number, found {}", fmt_num(*x)),
        );
    }
    Ok(values)
}

/// The value of a key of `[system]`; `a.b` names `b` in the table `a` (e.g.
/// `parameters.lambda` of a system given by expression).
fn lookup<'t>(table: &'t toml::Table, key: &str) -> Option<&'t toml::Value> {
    match key.split_once('.') {
        None => table.get(key),
        Some((outer, inner)) => match table.get(outer)? {
            toml::Value::Table(t) => lookup(t, inner),
            _ => None,
        },
    }
}

/// The `[system]` table with `key = value` (the key exists: [`sweep_values`] checked it).
fn system_at(spec: &SceneFile, key: &str, value: f64) -> toml::Table {
    fn set(table: &mut toml::Table, key: &str, value: f64) {
        match key.split_once('.') {
            None => {
                table.insert(key.to_string(), toml::Value::Float(value));
            }
            Some((outer, inner)) => {
                if let Some(toml::Value::Table(t)) = table.get_mut(outer) {
                    set(t, inner, value);
                }
            }
        }
    }
    let mut table = spec.system.clone();
    set(&mut table, key, value);
    table
}

/// Check that the catalogue builds the system at every value (a value outside the system's
/// domain names itself) and that the span is defined there.
///
/// # Errors
/// The first value's [`SceneError`], with the value named.
pub fn check_sweep(
    file: &str,
    spec: &SceneFile,
    sweep: &SweepSpec,
    values: &[f64],
    catalogue: &Catalogue,
) -> Result<(), SceneError> {
    for &v in values {
        let at = |e: SceneError| {
            SceneError::new(
                file,
                format!("sweep ({} = {})", sweep.key, fmt_num(v)),
                format!("{}: {}", e.key, e.message),
            )
        };
        let case = catalogue
            .build(file, &system_at(spec, &sweep.key, v))
            .map_err(at)?;
        end_time(file, spec, &*case).map_err(at)?;
    }
    Ok(())
}

/// Run every method at every knob at each value: `knobs[i]` are the knob values of
/// `spec.methods[i]`. The values run in parallel on the current `rayon` pool; the result is in
/// the order of `values` and does not depend on the number of threads. `tick` is called once
/// per finished value (a progress bar).
///
/// # Errors
/// A [`SceneError`] when a case cannot be built or its reference computed at some value (runs
/// that fail are recorded in their [`SweepRun`], not errors).
pub fn run_sweep(
    file: &str,
    spec: &SceneFile,
    sweep: &SweepSpec,
    values: &[f64],
    knobs: &[Vec<f64>],
    catalogue: &Catalogue,
    tick: &(dyn Fn() + Sync),
) -> Result<Vec<SweepPoint>, SceneError> {
    values
        .par_iter()
        .map(|&value| {
            let at = |key: &str, message: String| {
                SceneError::new(
                    file,
                    format!("sweep ({} = {}) {key}", sweep.key, fmt_num(value)),
                    message,
                )
            };
            let mut case = catalogue
                .build(file, &system_at(spec, &sweep.key, value))
                .map_err(|e| at(&e.key, e.message))?;
            let (t1, _) = end_time(file, spec, &*case).map_err(|e| at(&e.key, e.message))?;
            case.prepare(t1)
                .map_err(|e| at("system", format!("reference solution: {e}")))?;
            let mut runs = Vec::new();
            for (i, (m, ks)) in spec.methods.iter().zip(knobs).enumerate() {
                for &knob in ks {
                    let error = case
                        .run(m.kind, knob)
                        .map(|o| o.error)
                        .map_err(|e| e.to_string());
                    runs.push(SweepRun {
                        method: i,
                        knob,
                        error,
                    });
                }
            }
            tick();
            Ok(SweepPoint { value, runs })
        })
        .collect()
}

//! The speed/accuracy harness: error against a trusted reference versus cost, for integrators at a
//! sweep of their knob and for analytic or perturbative theories at each order, on one set of axes.
//!
//! A [`Series`] is one method swept over its knob (steps, tolerance, order); each [`Sample`]
//! holds the knob, the error, the best (and the median) wall time over repeated runs and the
//! [`Work`] counts. A
//! [`Comparison`] gathers series for one problem and renders them as CSV, a Markdown table and
//! (feature `cli`) an SVG work-precision diagram with logarithmic axes.
//!
//! Timing: each sample is run until at least `min_time` has elapsed (and at least once), and the
//! fastest run is kept — the least noisy estimate on a shared machine. Ratios between methods
//! should be read from one comparison, measured side by side.

use crate::error::{finite, non_negative, Error, Result};
use crate::integrate::Work;
use std::fmt::Write as _;
use std::time::{Duration, Instant};

/// One run of a method at one knob value.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Sample {
    /// The knob (number of steps, tolerance, order, …).
    pub knob: f64,
    /// The error against the reference (e.g. final position error).
    pub error: f64,
    /// Fastest wall time over the repetitions, in seconds.
    pub seconds: f64,
    /// Median wall time over the repetitions, in seconds (with `seconds`, the spread of the
    /// timing; equal to `seconds` for a single run).
    pub median: f64,
    /// Work of one run.
    pub work: Work,
}

/// One method swept over its knob.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Series {
    /// The method's label.
    pub label: String,
    /// The knob's name (e.g. `"steps"`, `"rtol"`, `"order"`).
    pub knob: String,
    /// Samples in sweep order.
    pub samples: Vec<Sample>,
}

impl Series {
    /// The least wall time at which the series reaches `error` or better, interpolating
    /// log-linearly between neighbouring samples; `None` if it never does.
    pub fn time_to_reach(&self, error: f64) -> Option<f64> {
        let mut pts: Vec<(f64, f64)> = self
            .samples
            .iter()
            .filter(|s| s.error.is_finite() && s.error >= 0.0 && s.seconds > 0.0)
            .map(|s| (s.error, s.seconds))
            .collect();
        pts.sort_by(|a, b| b.0.total_cmp(&a.0));
        // Samples that reach the target outright (an error of exactly 0 reaches every target).
        let mut best = pts
            .iter()
            .filter(|&&(e, _)| e <= error)
            .map(|&(_, t)| t)
            .min_by(f64::total_cmp);
        // Log-linear interpolation between neighbours that bracket the target.
        for w in pts.windows(2) {
            let ((e0, t0), (e1, t1)) = (w[0], w[1]);
            if e1 > 0.0 && e1 <= error && error <= e0 && e0 > e1 {
                let f = (error.ln() - e0.ln()) / (e1.ln() - e0.ln());
                let t = (t0.ln() + f * (t1.ln() - t0.ln())).exp();
                best = Some(best.map_or(t, |b: f64| b.min(t)));
            }
        }
        best
    }

    /// The smallest error reached.
    pub fn best_error(&self) -> Option<f64> {
        self.samples
            .iter()
            .map(|s| s.error)
            .filter(|e| e.is_finite())
            .min_by(f64::total_cmp)
    }
}

/// Timing policy of a sweep.
///
/// A sample is repeated while *both* less than `min_time` has elapsed *and* fewer than `max_runs`
/// runs were made (and is always run once), so the time spent on one knob value is at most
/// `min_time` plus one run, whatever `max_runs` is: `max_runs = usize::MAX` means "as many as fit
/// in `min_time`". `min_time` is the caller's bound on the work of a sweep; it may not exceed
/// [`Timing::MAX_MIN_TIME`].
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Timing {
    /// Repeat each run until at least this much time has elapsed (at most
    /// [`Timing::MAX_MIN_TIME`]).
    pub min_time: Duration,
    /// At most this many repetitions (0 is taken as 1: every sample runs once).
    pub max_runs: usize,
}

impl Timing {
    /// Largest `min_time` accepted: one hour per sample.
    pub const MAX_MIN_TIME: Duration = Duration::from_secs(3600);
}

impl Default for Timing {
    fn default() -> Self {
        Self {
            min_time: Duration::from_millis(20),
            max_runs: 1000,
        }
    }
}

/// Runs `run(knob)` for each knob value: `run` returns `(error, work)`; the wall time is measured
/// around it (best of the repetitions, see [`Timing`]). A run that fails stops the sweep with its
/// error, labelled.
///
/// # Errors
/// [`Error::WorkLimit`] for `timing.min_time` above [`Timing::MAX_MIN_TIME`];
/// [`Error::NonFinite`] for a non-finite knob or a NaN or infinite error returned by `run`, and
/// [`Error::OutOfDomain`] for a negative one (an error is a distance: finite and `≥ 0`); and the
/// first error of `run`, as [`Error::InvalidInput`] naming the series and the knob.
pub fn sweep(
    label: impl Into<String>,
    knob: impl Into<String>,
    knobs: &[f64],
    timing: Timing,
    mut run: impl FnMut(f64) -> Result<(f64, Work)>,
) -> Result<Series> {
    let label = label.into();
    if timing.min_time > Timing::MAX_MIN_TIME {
        return Err(Error::WorkLimit {
            what: format!("timing of the sweep {label}"),
            limit: Timing::MAX_MIN_TIME.as_secs() as usize,
            detail: format!(
                "min_time = {:e} s per sample, limit in seconds",
                timing.min_time.as_secs_f64()
            ),
            hint: "ask for a shorter min_time (the best of the repetitions within it is kept)"
                .into(),
        });
    }
    for (i, &k) in knobs.iter().enumerate() {
        finite(format_args!("knob {i} of the sweep {label}"), k)?;
    }
    let mut samples = Vec::with_capacity(knobs.len());
    for &k in knobs {
        let mut best = f64::INFINITY;
        let mut times: Vec<f64> = Vec::new();
        let mut result = None;
        let start = Instant::now();
        let mut runs = 0;
        while runs == 0 || (start.elapsed() < timing.min_time && runs < timing.max_runs) {
            let t = Instant::now();
            let r = run(k).map_err(|e| Error::invalid(format!("{label} at {k}"), e.to_string()))?;
            let dt = t.elapsed().as_secs_f64();
            best = best.min(dt);
            times.push(dt);
            result = Some(r);
            runs += 1;
        }
        let (error, work) = result.expect("at least one run");
        let what = format!("error of {label} at {k:e}");
        non_negative(&what, error)?;
        samples.push(Sample {
            knob: k,
            error,
            seconds: best,
            median: {
                times.sort_by(f64::total_cmp);
                times.get(times.len() / 2).copied().unwrap_or(best)
            },
            work,
        });
    }
    Ok(Series {
        label,
        knob: knob.into(),
        samples,
    })
}

/// Several series on one problem.
#[derive(Clone, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Comparison {
    /// Title (problem and span).
    pub title: String,
    /// What the error measures (e.g. `"final position error"`).
    pub error_label: String,
    /// The series.
    pub series: Vec<Series>,
}

impl Comparison {
    /// An empty comparison.
    pub fn new(title: impl Into<String>, error_label: impl Into<String>) -> Self {
        Self {
            title: title.into(),
            error_label: error_label.into(),
            series: Vec::new(),
        }
    }

    /// Add a series.
    pub fn push(&mut self, series: Series) {
        self.series.push(series);
    }

    /// CSV: `method,knob_name,knob,error,seconds,steps,gradients,hessians,flows`.
    pub fn to_csv(&self) -> String {
        let mut out =
            String::from("method,knob_name,knob,error,seconds,steps,gradients,hessians,flows\n");
        for s in &self.series {
            for x in &s.samples {
                let _ = writeln!(
                    out,
                    "{},{},{:e},{:e},{:e},{},{},{},{}",
                    csv_field(&s.label),
                    csv_field(&s.knob),
                    x.knob,
                    x.error,
                    x.seconds,
                    x.work.steps,
                    x.work.gradients,
                    x.work.hessians,
                    x.work.flows
                );
            }
        }
        out
    }

    /// A Markdown table of every sample, then the time each method needs to reach each of
    /// `targets` (`—` where it does not).
    pub fn to_markdown(&self, targets: &[f64]) -> String {
        let mut out = format!("**{}** — {}\n\n", self.title, self.error_label);
        out.push_str("| method | knob | error | time | steps | gradients | flows |\n");
        out.push_str("|---|---|---|---|---|---|---|\n");
        for s in &self.series {
            for x in &s.samples {
                let _ = writeln!(
                    out,
                    "| {} | {} | {:.2e} | {} | {} | {} | {} |",
                    s.label,
                    if s.knob.is_empty() {
                        "—".to_string()
                    } else {
                        format!("{} = {}", s.knob, fmt_knob(x.knob))
                    },
                    x.error,
                    fmt_time(x.seconds),
                    x.work.steps,
                    x.work.gradients,
                    x.work.flows
                );
            }
        }
        if !targets.is_empty() {
            out.push_str("\n| method |");
            for t in targets {
                let _ = write!(out, " time to {t:.0e} |");
            }
            out.push_str("\n|---|");
            for _ in targets {
                out.push_str("---|");
            }
            out.push('\n');
            for s in &self.series {
                let _ = write!(out, "| {} |", s.label);
                for &t in targets {
                    match s.time_to_reach(t) {
                        Some(x) => {
                            let _ = write!(out, " {} |", fmt_time(x));
                        }
                        None => out.push_str(" — |"),
                    }
                }
                out.push('\n');
            }
        }
        out
    }
}

/// A CSV field (RFC 4180): quoted, with quotes doubled, when it holds a comma, a quote, a
/// carriage return or a line feed, or begins or ends with white space (which readers would
/// otherwise trim); as it is otherwise. The crate's one quoting rule: tables and figure data.
pub fn csv_field(s: &str) -> String {
    let padded = s.starts_with(char::is_whitespace) || s.ends_with(char::is_whitespace);
    if padded || s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

fn fmt_knob(k: f64) -> String {
    if k.fract() == 0.0 && k.abs() < 1e12 {
        format!("{k:.0}")
    } else {
        format!("{k:.1e}")
    }
}

/// Wall time with a unit.
pub fn fmt_time(s: f64) -> String {
    if s < 1e-6 {
        format!("{:.0} ns", s * 1e9)
    } else if s < 1e-3 {
        format!("{:.1} µs", s * 1e6)
    } else if s < 1.0 {
        format!("{:.2} ms", s * 1e3)
    } else {
        format!("{s:.2} s")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series(points: &[(f64, f64)]) -> Series {
        Series {
            label: "m".into(),
            knob: "steps".into(),
            samples: points
                .iter()
                .enumerate()
                .map(|(i, &(error, seconds))| Sample {
                    knob: i as f64,
                    error,
                    seconds,
                    median: seconds,
                    work: Work::default(),
                })
                .collect(),
        }
    }

    #[test]
    fn time_to_reach_interpolates_log_linearly() {
        let s = series(&[(1e-4, 1e-3), (1e-8, 1e-1)]);
        // Halfway in log error is halfway in log time.
        let t = s.time_to_reach(1e-6).unwrap();
        assert!((t - 1e-2).abs() < 1e-12, "{t}");
        assert_eq!(s.time_to_reach(1e-9), None);
        assert_eq!(s.time_to_reach(1e-3), Some(1e-3));
    }

    #[test]
    fn outputs_have_every_sample() {
        let mut c = Comparison::new("test, with comma", "error");
        c.push(series(&[(1e-4, 1e-3), (1e-8, 1e-1)]));
        let csv = c.to_csv();
        assert_eq!(csv.lines().count(), 3);
        let md = c.to_markdown(&[1e-6]);
        assert!(md.contains("time to 1e-6"));
        assert!(md.contains("10.00 ms"));
    }

    #[test]
    fn sweep_reports_run_errors() {
        let r = sweep("bad", "k", &[1.0], Timing::default(), |_| {
            Err(Error::invalid("x", "y"))
        });
        assert!(r.is_err());
        let ok = sweep(
            "good",
            "k",
            &[1.0, 2.0],
            Timing {
                min_time: Duration::ZERO,
                max_runs: 1,
            },
            |k| Ok((1.0 / k, Work::default())),
        )
        .unwrap();
        assert_eq!(ok.samples.len(), 2);
        assert_eq!(ok.best_error(), Some(0.5));
    }
}

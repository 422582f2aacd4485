//! Runs a scene: checks it against its system, sweeps the methods it names, and writes only the
//! outputs it asks for (tables under `<out>/tables/`, figures under `<out>/figures/`).

use super::case::{Case, History};
use super::catalogue::Catalogue;
use super::spec::{Knob, MethodKind, MethodSpec, RunSpec, SceneError, SceneFile};
use crate::plot::{Curve, Figure, Style};
use crate::systems::Invariant;
use crate::workprecision::{sweep, Comparison, Series, Timing};
use std::path::{Path, PathBuf};

/// A scene checked against its system, ready to run.
pub struct Scene {
    file: String,
    name: String,
    title: String,
    spec: SceneFile,
    case: Box<dyn Case>,
    t1: Option<f64>,
}

/// How a scene is run.
#[derive(Clone, Debug)]
pub struct RunOptions {
    /// Output directory.
    pub out: PathBuf,
    /// Timing policy of the sweeps.
    pub timing: Timing,
    /// Show progress bars (on a terminal).
    pub progress: bool,
}

/// What a run produced.
#[derive(Clone, Debug, Default)]
pub struct RunSummary {
    /// The Markdown report (also written as the table file when a table was asked for).
    pub markdown: String,
    /// Files written.
    pub files: Vec<PathBuf>,
}

fn knob_values(file: &str, i: usize, m: &MethodSpec) -> Result<Vec<f64>, SceneError> {
    let key = |k: &str| format!("method[{i}].{k}");
    let want = m.kind.knob();
    let given = [
        (Knob::Steps, m.steps.is_some()),
        (Knob::Rtol, m.rtol.is_some()),
        (Knob::Orders, m.orders.is_some()),
    ];
    for (k, present) in given {
        if present && k != want {
            let expected = match want {
                Knob::None => "no knob".to_string(),
                w => format!("`{}`", w.key()),
            };
            return Err(SceneError::new(
                file,
                key(k.key()),
                format!("`{}` takes {expected}, not `{}`", m.kind.name(), k.key()),
            ));
        }
    }
    let values: Vec<f64> = match want {
        Knob::None => return Ok(vec![1.0]),
        Knob::Steps => m.steps.iter().flatten().map(|&n| n as f64).collect(),
        Knob::Rtol => m.rtol.clone().unwrap_or_default(),
        Knob::Orders => m.orders.iter().flatten().map(|&n| f64::from(n)).collect(),
    };
    if values.is_empty() {
        return Err(SceneError::new(
            file,
            key(want.key()),
            format!(
                "missing: `{}` needs a non-empty list `{}`",
                m.kind.name(),
                want.key()
            ),
        ));
    }
    for (j, &v) in values.iter().enumerate() {
        check_knob(want, v)
            .map_err(|msg| SceneError::new(file, format!("{}[{j}]", key(want.key())), msg))?;
    }
    Ok(values)
}

fn check_knob(knob: Knob, v: f64) -> Result<(), String> {
    match knob {
        Knob::Steps if !(1.0..=1e9).contains(&v) => {
            Err(format!("expected a step count in 1..=10⁹, found {v}"))
        }
        Knob::Rtol if !(v.is_finite() && v > 0.0 && v < 1.0) => {
            Err(format!("expected a tolerance in (0, 1), found {v}"))
        }
        Knob::Orders if !(1.0..=64.0).contains(&v) => {
            Err(format!("expected an order in 1..=64, found {v}"))
        }
        _ => Ok(()),
    }
}

fn run_knob(file: &str, key: &str, r: &RunSpec) -> Result<f64, SceneError> {
    let want = r.method.knob();
    let given: [(Knob, Option<f64>); 3] = [
        (Knob::Steps, r.steps.map(|n| n as f64)),
        (Knob::Rtol, r.rtol),
        (Knob::Orders, r.order.map(f64::from)),
    ];
    let mut value = None;
    for (k, v) in given {
        let name = k.singular();
        match v {
            Some(_) if k != want => {
                return Err(SceneError::new(
                    file,
                    format!("{key}.{name}"),
                    format!("`{}` does not take `{name}`", r.method.name()),
                ))
            }
            Some(x) => {
                check_knob(k, x).map_err(|m| SceneError::new(file, format!("{key}.{name}"), m))?;
                value = Some(x);
            }
            None => {}
        }
    }
    match (want, value) {
        (Knob::None, _) => Ok(1.0),
        (_, Some(v)) => Ok(v),
        (w, None) => {
            let name = w.singular();
            Err(SceneError::new(
                file,
                format!("{key}.{name}"),
                format!("missing: `{}` needs `{name}`", r.method.name()),
            ))
        }
    }
}

fn label_of(m: &MethodSpec) -> String {
    m.label
        .clone()
        .unwrap_or_else(|| m.kind.label().to_string())
}

fn short_label(kind: MethodKind, knob: f64) -> String {
    match kind.knob() {
        Knob::Steps => format!("{} ({knob:.0} steps)", kind.name()),
        Knob::Rtol => format!("{} (rtol {knob:.0e})", kind.name()),
        Knob::Orders => format!("{} (order {knob:.0})", kind.name()),
        Knob::None => kind.name().to_string(),
    }
}

impl Scene {
    /// Check a parsed scene against the catalogue: the system and its keys, the span, every
    /// method (applies to the system, has the right knob with valid values) and every output.
    ///
    /// # Errors
    /// A [`SceneError`] naming the key.
    pub fn new(file: &str, spec: SceneFile, catalogue: &Catalogue) -> Result<Self, SceneError> {
        let case = catalogue.build(file, &spec.system)?;
        let stem = Path::new(file)
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("scene")
            .to_string();
        let name = spec.name.clone().unwrap_or(stem);
        if name.is_empty()
            || !name
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
        {
            return Err(SceneError::new(
                file,
                "name",
                format!("expected letters, digits, `-`, `_` or `.` (it names the output files), found {name:?}"),
            ));
        }
        let title = spec.title.clone().unwrap_or_else(|| case.describe());
        let table_only = case.has_table();
        let t1 = if table_only {
            if let Some(_m) = spec.methods.first() {
                return Err(SceneError::new(
                    file,
                    "method[0]",
                    "this system is a table of its own and runs no methods",
                ));
            }
            if spec.span.is_some() {
                return Err(SceneError::new(
                    file,
                    "span",
                    "this system is a table of its own and takes no span",
                ));
            }
            None
        } else {
            let Some(span) = &spec.span else {
                return Err(SceneError::new(
                    file,
                    "span",
                    "missing: give `[span]` with `periods` or `time`",
                ));
            };
            let (key, v) = match (span.periods, span.time) {
                (Some(p), None) => ("span.periods", p),
                (None, Some(t)) => ("span.time", t),
                _ => {
                    return Err(SceneError::new(
                        file,
                        "span",
                        "expected exactly one of `periods` and `time`",
                    ))
                }
            };
            if !(v.is_finite() && v > 0.0) {
                return Err(SceneError::new(
                    file,
                    key,
                    format!("expected a positive, finite number, found {v}"),
                ));
            }
            let t1 = if span.periods.is_some() {
                let Some(period) = case.period() else {
                    return Err(SceneError::new(
                        file,
                        key,
                        "this system has no period; give `span.time`",
                    ));
                };
                v * period
            } else {
                v
            };
            if !t1.is_finite() {
                return Err(SceneError::new(
                    file,
                    key,
                    format!("the span {v} overflows the time axis"),
                ));
            }
            Some(t1)
        };
        for (i, m) in spec.methods.iter().enumerate() {
            if !case.supports(m.kind) {
                return Err(SceneError::new(
                    file,
                    format!("method[{i}].kind"),
                    format!(
                        "`{}` ({}) does not apply to this system",
                        m.kind.name(),
                        m.kind.description()
                    ),
                ));
            }
            knob_values(file, i, m)?;
        }
        let o = &spec.output;
        if let Some(targets) = &o.targets {
            for (j, &x) in targets.iter().enumerate() {
                if !(x.is_finite() && x > 0.0) {
                    return Err(SceneError::new(
                        file,
                        format!("output.targets[{j}]"),
                        format!("expected a positive, finite error, found {x}"),
                    ));
                }
            }
        }
        if o.work_precision && spec.methods.is_empty() {
            return Err(SceneError::new(
                file,
                "output.work_precision",
                "needs at least one `[[method]]`",
            ));
        }
        if !(1..=100_000).contains(&o.samples) {
            return Err(SceneError::new(
                file,
                "output.samples",
                format!("expected 1..=100000 points, found {}", o.samples),
            ));
        }
        for (list, key) in [
            (&o.phase_portrait, "phase_portrait"),
            (&o.energy_error, "energy_error"),
            (&o.invariants, "invariants"),
            (&o.elements, "elements"),
        ] {
            for (j, r) in list.iter().enumerate() {
                let k = format!("output.{key}[{j}]");
                if !case.supports(r.method) {
                    return Err(SceneError::new(
                        file,
                        format!("{k}.method"),
                        format!("`{}` does not apply to this system", r.method.name()),
                    ));
                }
                if r.method == MethodKind::Lindstedt {
                    return Err(SceneError::new(
                        file,
                        format!("{k}.method"),
                        "`lindstedt` gives the angle only, not a state",
                    ));
                }
                run_knob(file, &k, r)?;
            }
        }
        if !o.elements.is_empty() && case.element_names().is_none() {
            return Err(SceneError::new(
                file,
                "output.elements",
                "this system has no osculating elements",
            ));
        }
        Ok(Self {
            file: file.to_string(),
            name,
            title,
            spec,
            case,
            t1,
        })
    }

    /// The scene's name (prefix of its output files).
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The scene's title.
    pub fn title(&self) -> &str {
        &self.title
    }

    /// The files a run writes, relative to the output directory, without running anything.
    pub fn planned_outputs(&self) -> Vec<PathBuf> {
        let o = &self.spec.output;
        let mut v = Vec::new();
        if o.table {
            v.push(PathBuf::from(format!("tables/{}.md", self.name)));
            v.push(PathBuf::from(format!("tables/{}.csv", self.name)));
        }
        let fig = |what: &str| PathBuf::from(format!("figures/{}-{what}.svg", self.name));
        if o.work_precision {
            v.push(fig("work-precision"));
        }
        if !o.phase_portrait.is_empty() {
            v.push(fig("phase-portrait"));
        }
        if !o.energy_error.is_empty() {
            v.push(fig("energy-error"));
        }
        if !o.invariants.is_empty() {
            v.push(fig("invariants"));
        }
        if !o.elements.is_empty() {
            v.push(fig("elements"));
        }
        v
    }

    fn err(&self, key: impl Into<String>, e: impl std::fmt::Display) -> SceneError {
        SceneError::new(&self.file, key, e.to_string())
    }

    fn write(
        &self,
        out: &Path,
        rel: &str,
        text: &str,
        files: &mut Vec<PathBuf>,
    ) -> Result<(), SceneError> {
        let path = out.join(rel);
        if let Some(dir) = path.parent() {
            std::fs::create_dir_all(dir)
                .map_err(|e| self.err("", format!("{}: {e}", dir.display())))?;
        }
        std::fs::write(&path, text)
            .map_err(|e| self.err("", format!("{}: {e}", path.display())))?;
        files.push(path);
        Ok(())
    }

    /// Run the scene and write its outputs.
    ///
    /// # Errors
    /// Failures of a method (naming the `[[method]]` entry) or of writing a file.
    pub fn run(mut self, opts: &RunOptions) -> Result<RunSummary, SceneError> {
        let mut summary = RunSummary::default();
        let o = self.spec.output.clone();
        let mut md = format!("## {}\n\n{}\n\n", self.title, self.case.describe());
        if let Some(table) = self.case.table() {
            let table = table.map_err(|e| self.err("system", e))?;
            md += &table.to_markdown();
            if o.table {
                self.write(
                    &opts.out,
                    &format!("tables/{}.md", self.name),
                    &md,
                    &mut summary.files,
                )?;
                self.write(
                    &opts.out,
                    &format!("tables/{}.csv", self.name),
                    &table.to_csv(),
                    &mut summary.files,
                )?;
            }
            summary.markdown = md;
            return Ok(summary);
        }
        let t1 = self.t1.unwrap_or(1.0);
        let waiting = spinner(opts.progress, format!("{}: reference solution", self.name));
        self.case
            .prepare(t1)
            .map_err(|e| self.err("system", format!("reference solution: {e}")))?;
        waiting.finish_and_clear();
        let case = &*self.case;
        md += &format!("Span t = {t1:.6e}; {}.\n\n", case.reference_note());
        let mut csv = String::new();
        let needs_sweep = o.table || o.work_precision;
        if needs_sweep && !self.spec.methods.is_empty() {
            let mut comparison = Comparison::new(self.title.clone(), case.error_label());
            let mut failures: Vec<String> = Vec::new();
            let total: usize = self
                .spec
                .methods
                .iter()
                .enumerate()
                .map(|(i, m)| knob_values(&self.file, i, m).map(|v| v.len()).unwrap_or(0))
                .sum();
            let bar = progress_bar(opts.progress, total as u64, &self.name);
            for (i, m) in self.spec.methods.iter().enumerate() {
                let knobs = knob_values(&self.file, i, m)?;
                let knob_name = m.kind.knob().singular();
                let mut series = Series {
                    label: label_of(m),
                    knob: knob_name.to_string(),
                    samples: Vec::new(),
                };
                for &k in &knobs {
                    bar.set_message(short_label(m.kind, k));
                    // A run that fails (e.g. an implicit method whose step is too large for
                    // its Newton iteration) is reported, not plotted, and the sweep goes on.
                    match sweep(&series.label, knob_name, &[k], opts.timing, |k| {
                        case.run(m.kind, k).map(|r| (r.error, r.work))
                    }) {
                        Ok(s) => series.samples.extend(s.samples),
                        Err(e) => failures.push(format!(
                            "method[{i}] {} failed: {e}",
                            short_label(m.kind, k)
                        )),
                    }
                    bar.inc(1);
                }
                if let Some(note) = case.note(m.kind) {
                    series.label += &format!(" ({note})");
                }
                if series.samples.is_empty() {
                    series.label += " (every run failed or was refused)";
                }
                comparison.push(series);
            }
            bar.finish_and_clear();
            let targets = o.targets.clone().unwrap_or_else(|| vec![1e-6, 1e-9, 1e-12]);
            md += &comparison.to_markdown(&targets);
            if !failures.is_empty() {
                md += "\nFailed runs (not in the table or the figure):\n\n";
                for f in &failures {
                    md += &format!("- {f}\n");
                }
            }
            csv = comparison.to_csv();
            if o.work_precision {
                let rel = format!("figures/{}-work-precision.svg", self.name);
                let path = opts.out.join(&rel);
                ensure_parent(&path).map_err(|e| self.err("output.work_precision", e))?;
                comparison
                    .to_svg(&path)
                    .map_err(|e| self.err("output.work_precision", e))?;
                summary.files.push(path);
            }
        }
        let histories =
            |list: &[RunSpec], key: &str| -> Result<Vec<(String, History)>, SceneError> {
                list.iter()
                    .enumerate()
                    .map(|(j, r)| {
                        let k = format!("output.{key}[{j}]");
                        let knob = run_knob(&self.file, &k, r)?;
                        let h = case
                            .history(r.method, knob, o.samples)
                            .map_err(|e| self.err(&k, e))?;
                        let n = h.t.len();
                        if n == 0 || h.q.len() != n || h.p.len() != n {
                            return Err(self.err(&k, "the run returned an empty or ragged history"));
                        }
                        Ok((short_label(r.method, knob), h))
                    })
                    .collect()
            };
        let spinner = spinner(
            opts.progress
                && !(o.phase_portrait.is_empty()
                    && o.energy_error.is_empty()
                    && o.invariants.is_empty()
                    && o.elements.is_empty()),
            format!("{}: histories", self.name),
        );
        if !o.phase_portrait.is_empty() {
            let pr = case.portrait();
            let mut fig = Figure::new(
                format!("{} — phase portrait", self.title),
                pr.x_label,
                pr.y_label,
            );
            if pr.equal_aspect {
                fig = fig.equal_aspect();
            }
            for (label, h) in histories(&o.phase_portrait, "phase_portrait")? {
                let pts: Vec<(f64, f64)> =
                    h.q.iter()
                        .zip(&h.p)
                        .map(|(q, p)| (pr.project)(q, p))
                        .collect();
                fig = fig.curve(label, pts, Style::Line);
            }
            self.figure(&opts.out, "phase-portrait", &fig, &mut summary.files)?;
        }
        if !o.energy_error.is_empty() {
            let runs = histories(&o.energy_error, "energy_error")?;
            // Every run starts from the scene's initial state: one H(0) for all. The error is
            // relative unless H(0) = 0, where it is absolute and the axis says so.
            let h0 = {
                let h = &runs[0].1;
                case.energy(h.t[0], &h.q[0], &h.p[0])
                    .map_err(|e| self.err("output.energy_error", e))?
            };
            let (scale, axis) = if h0 != 0.0 {
                (h0.abs(), "|H(t) − H(0)| / |H(0)|")
            } else {
                (1.0, "|H(t) − H(0)|  (H(0) = 0)")
            };
            let mut fig = Figure::new(format!("{} — energy error", self.title), "t", axis).log_y();
            for (label, h) in runs {
                let mut pts = Vec::with_capacity(h.t.len());
                for k in 0..h.t.len() {
                    let e = case
                        .energy(h.t[k], &h.q[k], &h.p[k])
                        .map_err(|e| self.err("output.energy_error", e))?;
                    pts.push((h.t[k], (e - h0).abs() / scale));
                }
                fig = fig.curve(label, pts, Style::Line);
            }
            self.figure(&opts.out, "energy-error", &fig, &mut summary.files)?;
        }
        if !o.invariants.is_empty() {
            let mut fig = Figure::new(
                format!("{} — conserved quantities", self.title),
                "t",
                "|I(t) − I(0)| / |I(0)|  (absolute where I(0) = 0)",
            )
            .log_y();
            for (label, h) in histories(&o.invariants, "invariants")? {
                let values: Vec<Vec<Invariant>> = (0..h.t.len())
                    .map(|k| case.invariants(h.t[k], &h.q[k], &h.p[k]))
                    .collect::<crate::Result<_>>()
                    .map_err(|e| self.err("output.invariants", e))?;
                let first = &values[0];
                for (j, inv) in first.iter().enumerate() {
                    let scale = if inv.value != 0.0 {
                        inv.value.abs()
                    } else {
                        1.0
                    };
                    let pts: Vec<(f64, f64)> =
                        h.t.iter()
                            .zip(&values)
                            .map(|(&t, v)| {
                                let x = v.get(j).map_or(f64::NAN, |w| w.value);
                                (t, (x - inv.value).abs() / scale)
                            })
                            .collect();
                    fig = fig.curve(format!("{}: {label}", inv.name), pts, Style::Line);
                }
            }
            self.figure(&opts.out, "invariants", &fig, &mut summary.files)?;
        }
        if !o.elements.is_empty() {
            let names = case.element_names().unwrap_or(&[]);
            let mut fig = Figure::new(
                format!("{} — osculating elements", self.title),
                "t",
                "|element(t) − element(0)|",
            )
            .log_y();
            let mut curves: Vec<(Curve, bool)> = Vec::new();
            for (label, h) in histories(&o.elements, "elements")? {
                let els: Vec<Vec<f64>> =
                    h.q.iter()
                        .zip(&h.p)
                        .map(|(q, p)| case.elements(q, p))
                        .collect::<crate::Result<_>>()
                        .map_err(|e| self.err("output.elements", e))?;
                if els.iter().any(|e| e.len() != names.len()) {
                    return Err(self.err(
                        "output.elements",
                        format!("the element map does not give {} elements", names.len()),
                    ));
                }
                let mut constant = Vec::new();
                for (j, n) in names.iter().enumerate() {
                    let e0 = els[0][j];
                    let pts: Vec<(f64, f64)> =
                        h.t.iter()
                            .zip(&els)
                            .map(|(&t, e)| (t, angle_aware_diff(n, e[j], e0)))
                            .collect();
                    // An element that a theory holds constant differs from its initial value
                    // only by the rounding of the element map (a few ulps): named, and drawn
                    // only if nothing else is.
                    let floor = 64.0 * f64::EPSILON * e0.abs().max(1.0);
                    let is_constant = pts.iter().all(|&(_, d)| d <= floor);
                    if is_constant {
                        constant.push(*n);
                    }
                    let curve = Curve {
                        label: format!("{n}: {label}"),
                        points: pts,
                        style: Style::Line,
                    };
                    curves.push((curve, is_constant));
                }
                if !constant.is_empty() {
                    md += &format!(
                        "Elements constant to rounding along {label}: {}.\n\n",
                        constant.join(", ")
                    );
                }
            }
            let all_constant = curves.iter().all(|c| c.1);
            fig.curves.extend(
                curves
                    .into_iter()
                    .filter(|c| all_constant || !c.1)
                    .map(|c| c.0),
            );
            self.figure(&opts.out, "elements", &fig, &mut summary.files)?;
        }
        spinner.finish_and_clear();
        // The tables last, so that they carry every note of the histories too.
        if o.table {
            self.write(
                &opts.out,
                &format!("tables/{}.md", self.name),
                &md,
                &mut summary.files,
            )?;
            self.write(
                &opts.out,
                &format!("tables/{}.csv", self.name),
                &csv,
                &mut summary.files,
            )?;
        }
        summary.markdown = md;
        Ok(summary)
    }

    fn figure(
        &self,
        out: &Path,
        what: &str,
        fig: &Figure,
        files: &mut Vec<PathBuf>,
    ) -> Result<(), SceneError> {
        let path = out.join(format!("figures/{}-{what}.svg", self.name));
        let key = format!("output.{}", what.replace('-', "_"));
        ensure_parent(&path).map_err(|e| self.err(&key, e))?;
        fig.to_svg(&path).map_err(|e| self.err(&key, e))?;
        files.push(path);
        Ok(())
    }
}

/// Differences of the angles Ω, ω and ϖ are taken modulo 2π.
fn angle_aware_diff(name: &str, x: f64, x0: f64) -> f64 {
    let d = x - x0;
    if ["Ω", "ω", "ϖ"].contains(&name) {
        (d + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
    } else {
        d
    }
    .abs()
}

fn ensure_parent(path: &Path) -> Result<(), String> {
    match path.parent() {
        Some(dir) => std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display())),
        None => Ok(()),
    }
}

fn progress_bar(show: bool, total: u64, name: &str) -> indicatif::ProgressBar {
    if !show {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::new(total);
    if let Ok(style) =
        indicatif::ProgressStyle::with_template("{prefix:>24} [{bar:30}] {pos}/{len} {msg}")
    {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_prefix(name.to_string());
    bar
}

/// A spinner with a message while a long, unmetered computation runs (hidden when `show` is
/// false or stderr is not a terminal).
fn spinner(show: bool, message: String) -> indicatif::ProgressBar {
    if !show {
        return indicatif::ProgressBar::hidden();
    }
    let s = indicatif::ProgressBar::new_spinner();
    s.set_message(message);
    s.enable_steady_tick(std::time::Duration::from_millis(200));
    s
}

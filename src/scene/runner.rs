//! Runs a scene: checks it against its system, sweeps the methods it names, and writes only the
//! outputs it asks for (tables under `<out>/tables/`, figures under `<out>/figures/`).

use super::case::{Case, History, ADAPTIVE_MAX_STEPS};
use super::catalogue::Catalogue;
use super::parameter_sweep::{check_sweep, run_sweep, sweep_values, SweepPoint, SweepSpec};
use super::spec::{
    Knob, Length, MethodKind, MethodSpec, OutputSpec, PortraitAxes, RunSpec, SceneError, SceneFile,
    SpectrumSpec, TheoryKind,
};
use crate::error::fmt_num;
use crate::integrate::methods::Construction;
use crate::plot::render::parse_length;
use crate::plot::{DataFormat, Figure, Format, Size, Style};
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
    /// `[sweep]`: the values, with the catalogue that builds the system at each.
    sweep: Option<(SweepSpec, Vec<f64>, Catalogue)>,
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
    /// Figure settings that override the scene's `[output]`.
    pub figures: FigureOptions,
}

/// Figure settings given on the command line; each one given overrides the scene's `[output]`
/// key of the same name.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FigureOptions {
    /// Width: a length with its unit (`3.4in`, `8.6cm`, `1020px`) or inches.
    pub width: Option<String>,
    /// Height, as the width.
    pub height: Option<String>,
    /// Base font size in points.
    pub font_size: Option<f64>,
    /// PNG resolution in dots per inch.
    pub dpi: Option<f64>,
    /// Formats: `svg`, `png`, `pdf`.
    pub formats: Option<Vec<String>>,
    /// Data format: `csv` or `npy`.
    pub data: Option<String>,
}

/// How a scene's figures are written: size, formats, data format.
#[derive(Clone, Debug, PartialEq)]
pub struct FigureSetup {
    /// Physical size and font size.
    pub size: Size,
    /// File formats (SVG first).
    pub formats: Vec<Format>,
    /// Format of the data beside each figure.
    pub data: DataFormat,
}

impl FigureSetup {
    /// The setup of `o`, with the command line's `cli` overriding it. Errors name the scene key
    /// (`output.width`) or the option (`--width`) that gave the bad value.
    ///
    /// # Errors
    /// A [`SceneError`] for a bad length, font size, resolution, format or data format, or a
    /// size that fails [`Size::check`].
    pub fn new(file: &str, o: &OutputSpec, cli: &FigureOptions) -> Result<Self, SceneError> {
        let err = |key: &str, m: String| SceneError::new(file, key, m);
        let pick = |c: bool, opt: &'static str, key: &'static str| if c { opt } else { key };
        let mut size = Size::default();
        let dpi_key = pick(cli.dpi.is_some(), "--dpi", "output.dpi");
        if let Some(d) = cli.dpi.or(o.dpi) {
            size.dpi = d;
        }
        let length = |key: &str, cl: &Option<String>, sc: &Option<Length>, d: f64| match (cl, sc) {
            (Some(t), _) | (None, Some(Length::Text(t))) => {
                parse_length(t, d).map_err(|e| err(key, e.to_string()))
            }
            (None, Some(Length::Inches(v))) => {
                parse_length(&v.to_string(), d).map_err(|e| err(key, e.to_string()))
            }
            (None, None) => Ok(f64::NAN),
        };
        let wkey = pick(cli.width.is_some(), "--width", "output.width");
        let hkey = pick(cli.height.is_some(), "--height", "output.height");
        let w = length(wkey, &cli.width, &o.width, size.dpi)?;
        let h = length(hkey, &cli.height, &o.height, size.dpi)?;
        if !w.is_nan() {
            size.width = w;
        }
        if !h.is_nan() {
            size.height = h;
        }
        let fkey = pick(cli.font_size.is_some(), "--font-size", "output.font_size");
        if let Some(f) = cli.font_size.or(o.font_size) {
            size.font_size = f;
        }
        size.check().map_err(|e| {
            let m = e.to_string();
            let key = if m.contains("font") {
                fkey
            } else if m.contains("resolution") || m.contains("pixels") {
                dpi_key
            } else if m.contains("height") {
                hkey
            } else {
                wkey
            };
            err(key, m)
        })?;
        let fmt_key = pick(cli.formats.is_some(), "--format", "output.formats");
        let names = cli
            .formats
            .clone()
            .or_else(|| o.formats.clone())
            .unwrap_or_else(|| vec!["svg".into(), "png".into()]);
        let mut formats = vec![Format::Svg];
        for n in &names {
            let f = Format::from_key(n.trim()).ok_or_else(|| {
                err(
                    fmt_key,
                    format!("unknown format {n:?}: expected svg, png or pdf"),
                )
            })?;
            if !formats.contains(&f) {
                formats.push(f);
            }
        }
        let data_key = pick(cli.data.is_some(), "--data", "output.data");
        let data = match cli.data.as_ref().or(o.data.as_ref()) {
            None => DataFormat::Csv,
            Some(d) => DataFormat::from_key(d).ok_or_else(|| {
                err(
                    data_key,
                    format!("unknown data format {d:?}: expected csv or npy"),
                )
            })?,
        };
        Ok(Self {
            size,
            formats,
            data,
        })
    }

    /// The files a figure at `stem` is written to, in order (see [`Figure::write`]).
    pub fn files(&self, stem: &str) -> Vec<PathBuf> {
        let mut v: Vec<PathBuf> = self
            .formats
            .iter()
            .map(|f| PathBuf::from(format!("{stem}.{}", f.ext())))
            .collect();
        if self.data == DataFormat::Npy {
            v.push(PathBuf::from(format!("{stem}.npy")));
        }
        v.push(PathBuf::from(format!("{stem}.csv")));
        v.push(PathBuf::from(format!("{stem}.caption.txt")));
        v
    }
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
        (Knob::Ds, m.ds.is_some()),
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
                format!("`{}` takes {expected}, not `{}`", m.kind.key(), k.key()),
            ));
        }
    }
    let values: Vec<f64> = match want {
        Knob::None => return Ok(vec![1.0]),
        Knob::Steps => m.steps.iter().flatten().map(|&n| n as f64).collect(),
        Knob::Rtol => m.rtol.clone().unwrap_or_default(),
        Knob::Orders => m.orders.iter().flatten().map(|&n| f64::from(n)).collect(),
        Knob::Ds => m.ds.clone().unwrap_or_default(),
    };
    if values.is_empty() {
        return Err(SceneError::new(
            file,
            key(want.key()),
            format!(
                "missing: `{}` needs a non-empty list `{}`",
                m.kind.key(),
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
        Knob::Steps if !(1.0..=1e9).contains(&v) => Err(format!(
            "expected a step count in 1..=10⁹, found {}",
            fmt_num(v)
        )),
        Knob::Rtol if !(v.is_finite() && v > 0.0 && v < 1.0) => Err(format!(
            "expected a tolerance in (0, 1), found {}",
            fmt_num(v)
        )),
        Knob::Orders if !(1.0..=64.0).contains(&v) => {
            Err(format!("expected an order in 1..=64, found {}", fmt_num(v)))
        }
        Knob::Ds if !(v.is_finite() && v > 0.0) => Err(format!(
            "expected a positive finite step in fictitious time, found {}",
            fmt_num(v)
        )),
        _ => Ok(()),
    }
}

fn run_knob(file: &str, key: &str, r: &RunSpec) -> Result<f64, SceneError> {
    let want = r.method.knob();
    let given: [(Knob, Option<f64>); 4] = [
        (Knob::Steps, r.steps.map(|n| n as f64)),
        (Knob::Rtol, r.rtol),
        (Knob::Orders, r.order.map(f64::from)),
        (Knob::Ds, r.ds),
    ];
    let mut value = None;
    for (k, v) in given {
        let name = k.singular();
        match v {
            Some(_) if k != want => {
                return Err(SceneError::new(
                    file,
                    format!("{key}.{name}"),
                    format!("`{}` does not take `{name}`", r.method.key()),
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
                format!("missing: `{}` needs `{name}`", r.method.key()),
            ))
        }
    }
}

fn label_of(m: &MethodSpec) -> String {
    m.label.clone().unwrap_or_else(|| m.kind.label())
}

/// One value of a kind's knob in words: `400 steps`, `rtol 1e-10`, `order 8` (none without a
/// knob).
fn knob_text(kind: MethodKind, knob: f64) -> Option<String> {
    match kind.knob() {
        Knob::Steps => Some(format!("{knob:.0} steps")),
        Knob::Rtol => Some(format!("rtol {knob:.0e}")),
        Knob::Orders => Some(format!("order {knob:.0}")),
        Knob::Ds => Some(format!("ds {}", fmt_num(knob))),
        Knob::None => None,
    }
}

/// A run named by its key and knob value, as the scene file names it (progress, failures).
fn short_label(kind: MethodKind, knob: f64) -> String {
    match knob_text(kind, knob) {
        Some(k) => format!("{} ({k})", kind.key()),
        None => kind.key().to_string(),
    }
}

/// A run named by its label and knob value (figure legends).
fn legend_label(kind: MethodKind, knob: f64) -> String {
    match knob_text(kind, knob) {
        Some(k) => format!("{} ({k})", kind.label()),
        None => kind.label(),
    }
}

/// Whether `kind` is Dormand–Prince, whose step count the span check bounds.
fn is_dop853(kind: MethodKind) -> bool {
    kind.integrator()
        .is_some_and(|m| m.construction == Construction::Dop853)
}

/// The longest scene name: it prefixes file names of up to 19 more bytes
/// (`-phase-portrait.svg`), and file systems allow 255 bytes in one name.
pub const MAX_NAME_LEN: usize = 200;

/// The phase resolution a scene's reference must keep: after `N` periods the phase `2πN` is
/// known in double precision only to `±2πN·ε` (the rounding of the end time alone moves the
/// state along the orbit by that fraction of its size), so errors below it cannot be told from
/// the reference's own rounding. The tables resolve errors down to their targets
/// (`10⁻⁶ … 10⁻¹²` by default); a scene whose reference is uncertain by more than `10⁻⁶` of the
/// orbit (about `7·10⁸` periods) is refused.
const PHASE_RESOLUTION: f64 = 1e-6;

/// A lower bound on the steps DOP853 attempts over `periods` periods at tolerance `rtol`:
/// `½ · rtol^(−1/8)` per period. The step of an order-8 method grows like `rtol^(1/8)`
/// (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4); on the catalogue's smoothest motions (the
/// circular Kepler orbit, the pendulum at amplitude 0.1, the J2 orbit) DOP853 takes
/// `0.8 … 1.4 · rtol^(−1/8)` steps per period for `rtol` from 0.9 down to `10⁻¹²`.
fn dop853_steps_at_least(periods: f64, rtol: f64) -> f64 {
    0.5 * periods * rtol.powf(-0.125)
}

/// The scene's name: letters, digits, `-`, `_`, `.`, at most [`MAX_NAME_LEN`] of them.
fn check_name(file: &str, name: &str) -> Result<(), SceneError> {
    let n = name.chars().count();
    if n > MAX_NAME_LEN {
        return Err(SceneError::new(
            file,
            "name",
            format!(
                "a name of {n} characters is too long: at most {MAX_NAME_LEN} (it names the \
                 output files, and file systems allow 255 bytes in a file name)"
            ),
        ));
    }
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
    {
        return Err(SceneError::new(
            file,
            "name",
            format!(
                "expected letters, digits, `-`, `_` or `.` (it names the output files), found \
                 {name:?}"
            ),
        ));
    }
    Ok(())
}

/// The end time of a scene with a span, and the key that gave it.
pub(super) fn end_time(
    file: &str,
    spec: &SceneFile,
    case: &dyn Case,
) -> Result<(f64, &'static str), SceneError> {
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
            format!("expected a positive, finite number, found {}", fmt_num(v)),
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
            format!("the span {} overflows the time axis", fmt_num(v)),
        ));
    }
    Ok((t1, key))
}

/// Refuse a span whose reference has lost its phase, or whose DOP853 runs (or integrated
/// reference) would exceed their step limit: see [`PHASE_RESOLUTION`] and
/// [`dop853_steps_at_least`].
fn check_span_work(
    file: &str,
    key: &str,
    periods: f64,
    spec: &SceneFile,
    case: &dyn Case,
) -> Result<(), SceneError> {
    let dphi = std::f64::consts::TAU * periods * f64::EPSILON;
    if dphi > PHASE_RESOLUTION {
        return Err(SceneError::new(
            file,
            key,
            format!(
                "the phase is lost: after {} periods the phase 2πN is known in double precision \
                 only to ±2πN·ε = {} rad, more than the {} the tables resolve; give at most {} \
                 periods",
                fmt_num(periods),
                fmt_num(dphi),
                fmt_num(PHASE_RESOLUTION),
                fmt_num((PHASE_RESOLUTION / (std::f64::consts::TAU * f64::EPSILON)).floor())
            ),
        ));
    }
    let limit = ADAPTIVE_MAX_STEPS as f64;
    let mut adaptive: Vec<(String, f64)> = Vec::new();
    if let Some(rtol) = case.integrated_reference_rtol() {
        adaptive.push(("the DOP853 reference".to_string(), rtol));
    }
    for (i, m) in spec.methods.iter().enumerate() {
        if is_dop853(m.kind) {
            for (j, &r) in m.rtol.iter().flatten().enumerate() {
                adaptive.push((format!("method[{i}].rtol[{j}]"), r));
            }
        }
    }
    let o = &spec.output;
    for (list, name) in history_outputs(o) {
        for (j, r) in list.iter().enumerate() {
            if let (true, Some(rtol)) = (is_dop853(r.method), r.rtol) {
                adaptive.push((format!("output.{name}[{j}]"), rtol));
            }
        }
    }
    for (what, rtol) in adaptive {
        let steps = dop853_steps_at_least(periods, rtol);
        if steps > limit {
            return Err(SceneError::new(
                file,
                key,
                format!(
                    "too long for DOP853: {what} at rtol {} would take at least {} steps over {} \
                     periods (½·rtol^(−1/8) per period), more than the {} a run may take; \
                     shorten the span or loosen the tolerance",
                    fmt_num(rtol),
                    fmt_num(steps.round()),
                    fmt_num(periods),
                    fmt_num(limit)
                ),
            ));
        }
    }
    Ok(())
}

/// The history outputs of a scene with their keys.
fn history_outputs(o: &OutputSpec) -> [(&[RunSpec], &'static str); 5] {
    [
        (&o.phase_portrait, "phase_portrait"),
        (&o.energy_error, "energy_error"),
        (&o.position_error, "position_error"),
        (&o.invariants, "invariants"),
        (&o.elements, "elements"),
    ]
}

/// What a rendered output holds, written by [`Scene::write`].
enum Content {
    /// A text file (Markdown, CSV).
    Text(String),
    /// A figure, written as SVG.
    Figure(Box<Figure>),
    /// The work-precision diagram of a sweep, written as SVG.
    WorkPrecision(Comparison),
}

/// One file a scene's output renders: where it goes (relative to the output directory), the
/// scene key that asked for it (named in errors) and its content.
struct Artifact {
    rel: String,
    key: &'static str,
    content: Content,
}

/// The sweep of every `[[method]]` over its knob: the comparison and the runs that failed.
struct Sweep {
    comparison: Comparison,
    failures: Vec<String>,
}

impl Sweep {
    /// The table's Markdown: errors and costs, "time to reach" columns, failed runs.
    fn markdown(&self, targets: &[f64]) -> String {
        let mut md = self.comparison.to_markdown(targets);
        if !self.failures.is_empty() {
            md += "\nFailed runs (not in the table or the figure):\n\n";
            for f in &self.failures {
                md += &format!("- {f}\n");
            }
        }
        md
    }
}

impl Scene {
    /// Check a parsed scene against the catalogue: the system and its keys, the name, the span
    /// (finite, with a reference that keeps its phase and runs within their step limits), every
    /// method (applies to the system, has the right knob with valid values) and every output
    /// (histories name methods the scene runs).
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
        check_name(file, &name)?;
        let title = spec.title.clone().unwrap_or_else(|| case.describe());
        let t1 = if case.has_table() {
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
            Some(end_time(file, &spec, &*case)?)
        };
        for (i, m) in spec.methods.iter().enumerate() {
            if !case.supports(m.kind) {
                return Err(SceneError::new(
                    file,
                    format!("method[{i}].kind"),
                    format!(
                        "`{}` ({}) does not apply to this system",
                        m.kind.key(),
                        m.kind.description()
                    ),
                ));
            }
            knob_values(file, i, m)?;
        }
        if t1.is_some() && spec.methods.is_empty() {
            return Err(SceneError::new(
                file,
                "method",
                "missing: the scene runs no method; give at least one `[[method]]` (`hj list` \
                 shows the kinds)",
            ));
        }
        let o = &spec.output;
        if let Some(targets) = &o.targets {
            for (j, &x) in targets.iter().enumerate() {
                if !(x.is_finite() && x > 0.0) {
                    return Err(SceneError::new(
                        file,
                        format!("output.targets[{j}]"),
                        format!("expected a positive, finite error, found {}", fmt_num(x)),
                    ));
                }
            }
        }
        if !(1..=100_000).contains(&o.samples) {
            return Err(SceneError::new(
                file,
                "output.samples",
                format!("expected 1..=100000 points, found {}", o.samples),
            ));
        }
        let mut runs: Vec<&str> = Vec::new();
        for m in &spec.methods {
            if !runs.contains(&m.kind.key()) {
                runs.push(m.kind.key());
            }
        }
        for (list, key) in history_outputs(o) {
            for (j, r) in list.iter().enumerate() {
                let k = format!("output.{key}[{j}]");
                if !case.supports(r.method) {
                    return Err(SceneError::new(
                        file,
                        format!("{k}.method"),
                        format!("`{}` does not apply to this system", r.method.key()),
                    ));
                }
                if !runs.contains(&r.method.key()) {
                    return Err(SceneError::new(
                        file,
                        format!("{k}.method"),
                        format!(
                            "`{}` is not one of the methods the scene runs ({}); add a \
                             `[[method]]` of kind \"{}\"",
                            r.method.key(),
                            runs.join(", "),
                            r.method.key()
                        ),
                    ));
                }
                if r.method == TheoryKind::Lindstedt.into() {
                    return Err(SceneError::new(
                        file,
                        format!("{k}.method"),
                        format!("`{}` gives the angle only, not a state", r.method.key()),
                    ));
                }
                run_knob(file, &k, r)?;
            }
        }
        if let Some(sp) = &o.spectrum {
            check_spectrum(file, sp, &*case)?;
        }
        if !o.elements.is_empty() && case.element_names().is_none() {
            return Err(SceneError::new(
                file,
                "output.elements",
                "this system has no osculating elements",
            ));
        }
        if let (Some((t1, key)), Some(period)) = (t1, case.period()) {
            check_span_work(file, key, t1 / period, &spec, &*case)?;
        }
        FigureSetup::new(file, o, &FigureOptions::default())?;
        if let Some(axes) = &o.portrait {
            for (k, v) in [("x", &axes.x), ("y", &axes.y)] {
                if variable(v).is_none() {
                    return Err(SceneError::new(
                        file,
                        format!("output.portrait.{k}"),
                        format!("expected a coordinate `q0`, `q1`, … or a momentum `p0`, `p1`, …, found {v:?}"),
                    ));
                }
            }
        }
        let sweep = match &spec.sweep {
            None => None,
            Some(sw) => {
                if t1.is_none() {
                    return Err(SceneError::new(
                        file,
                        "sweep",
                        "this system is a table of its own and takes no sweep",
                    ));
                }
                let values = sweep_values(file, &spec, sw)?;
                check_sweep(file, &spec, sw, &values, catalogue)?;
                Some((sw.clone(), values, catalogue.clone()))
            }
        };
        Ok(Self {
            file: file.to_string(),
            name,
            title,
            spec,
            case,
            t1: t1.map(|t| t.0),
            sweep,
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
            v.push(PathBuf::from(self.table_path("md")));
            v.push(PathBuf::from(self.table_path("csv")));
        }
        // Checked when the scene was made: the scene's own setup is valid.
        let setup = FigureSetup::new(&self.file, o, &FigureOptions::default()).ok();
        let figure = |v: &mut Vec<PathBuf>, stem: String| match &setup {
            Some(s) => v.extend(s.files(&stem)),
            None => v.push(PathBuf::from(format!("{stem}.svg"))),
        };
        if o.work_precision {
            figure(&mut v, self.figure_path("work-precision"));
        }
        for what in self.case.table_figures() {
            figure(&mut v, self.figure_path(what));
        }
        for (list, key) in history_outputs(o) {
            if !list.is_empty() {
                figure(&mut v, self.figure_path(&key.replace('_', "-")));
            }
        }
        if o.spectrum.is_some() {
            figure(&mut v, self.figure_path("spectrum"));
        }
        if self.sweep.is_some() {
            figure(&mut v, self.figure_path("sweep"));
        }
        v
    }

    fn table_path(&self, ext: &str) -> String {
        format!("tables/{}.{ext}", self.name)
    }

    fn figure_path(&self, what: &str) -> String {
        format!("figures/{}-{what}", self.name)
    }

    fn err(&self, key: impl Into<String>, e: impl std::fmt::Display) -> SceneError {
        SceneError::new(&self.file, key, e.to_string())
    }

    /// Run the scene and write its outputs: prepare the reference, sweep the methods, render
    /// each output the scene asks for, write them.
    ///
    /// # Errors
    /// Failures of a method (naming the `[[method]]` entry or the output) or of writing a file.
    pub fn run(mut self, opts: &RunOptions) -> Result<RunSummary, SceneError> {
        let o = self.spec.output.clone();
        let mut md = format!("## {}\n\n{}\n\n", self.title, self.case.describe());
        if let Some(table) = self.case.table() {
            let (table, figures) = table.map_err(|e| self.err("system", e))?;
            md += &table.to_markdown();
            let mut artifacts = if o.table {
                self.tables(&md, table.to_csv())
            } else {
                Vec::new()
            };
            for (what, fig) in figures {
                artifacts.push(Artifact {
                    rel: self.figure_path(&what),
                    key: "system",
                    content: Content::Figure(Box::new(fig)),
                });
            }
            return self.write(opts, md, artifacts);
        }
        let t1 = self.prepare(opts)?;
        md += &format!("Span t = {t1:.6e}; {}.\n\n", self.case.reference_note());
        let sweep = self.sweep(opts)?;
        let mut artifacts = Vec::new();
        let mut csv = String::new();
        if let Some(sweep) = sweep {
            let targets = o.targets.clone().unwrap_or_else(|| vec![1e-6, 1e-9, 1e-12]);
            md += &sweep.markdown(&targets);
            csv = sweep.comparison.to_csv();
            if o.work_precision {
                artifacts.push(Artifact {
                    rel: self.figure_path("work-precision"),
                    key: "output.work_precision",
                    content: Content::WorkPrecision(sweep.comparison),
                });
            }
        }
        let spinner = spinner(
            opts.progress && history_outputs(&o).iter().any(|(l, _)| !l.is_empty()),
            format!("{}: histories", self.name),
        );
        if !o.phase_portrait.is_empty() {
            artifacts.push(self.phase_portrait(&o.phase_portrait, o.samples)?);
        }
        if !o.energy_error.is_empty() {
            artifacts.push(self.energy_error(&o.energy_error, o.samples)?);
        }
        if !o.position_error.is_empty() {
            artifacts.push(self.position_error(&o.position_error, o.samples)?);
        }
        if !o.invariants.is_empty() {
            artifacts.push(self.invariants(&o.invariants, o.samples)?);
        }
        if !o.elements.is_empty() {
            let (figure, notes) = self.elements(&o.elements, o.samples)?;
            artifacts.push(figure);
            md += &notes;
        }
        spinner.finish_and_clear();
        if let Some(sp) = &o.spectrum {
            let (figure, notes) = self.spectrum(sp)?;
            artifacts.push(figure);
            md += &notes;
        }
        if let Some(sw) = &self.sweep {
            let (figure, notes) = self.parameter_sweep(sw, opts)?;
            artifacts.push(figure);
            md += &notes;
        }
        // The tables last, so that they carry every note of the histories too.
        if o.table {
            artifacts.extend(self.tables(&md, csv));
        }
        self.write(opts, md, artifacts)
    }

    /// The end time, and the reference state there (once, before any run).
    fn prepare(&mut self, opts: &RunOptions) -> Result<f64, SceneError> {
        let t1 = self.t1.unwrap_or(1.0);
        let waiting = spinner(opts.progress, format!("{}: reference solution", self.name));
        self.case
            .prepare(t1)
            .map_err(|e| self.err("system", format!("reference solution: {e}")))?;
        waiting.finish_and_clear();
        Ok(t1)
    }

    /// Every `[[method]]` at every value of its knob, timed, when a table or a work-precision
    /// diagram asks for it. A run that fails (e.g. an implicit method whose step is too large for
    /// its Newton iteration) is reported, not plotted, and the sweep goes on.
    fn sweep(&self, opts: &RunOptions) -> Result<Option<Sweep>, SceneError> {
        let o = &self.spec.output;
        if !(o.table || o.work_precision) || self.spec.methods.is_empty() {
            return Ok(None);
        }
        let case = &*self.case;
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
        Ok(Some(Sweep {
            comparison,
            failures,
        }))
    }

    /// `[sweep]`: every method at every knob at each parameter value (on every core), the
    /// final errors against the parameter as a figure and a table.
    fn parameter_sweep(
        &self,
        (sw, values, catalogue): &(SweepSpec, Vec<f64>, Catalogue),
        opts: &RunOptions,
    ) -> Result<(Artifact, String), SceneError> {
        let knobs = self
            .spec
            .methods
            .iter()
            .enumerate()
            .map(|(i, m)| knob_values(&self.file, i, m))
            .collect::<Result<Vec<_>, _>>()?;
        let bar = progress_bar(opts.progress, values.len() as u64, &self.name);
        bar.set_message(format!("sweep of {}", sw.key));
        let tick = || bar.inc(1);
        let points: Vec<SweepPoint> =
            run_sweep(&self.file, &self.spec, sw, values, &knobs, catalogue, &tick)?;
        bar.finish_and_clear();
        let labels: Vec<String> = points[0]
            .runs
            .iter()
            .map(|r| legend_label(self.spec.methods[r.method].kind, r.knob))
            .collect();
        let mut fig = Figure::new(
            format!("{} — error against {}", self.title, sw.key),
            sw.key.clone(),
            self.case.error_label(),
        )
        .log_y()
        .caption(format!(
            "Final error of each run against system.{} ({} values); failed runs are left out.",
            sw.key,
            values.len()
        ));
        if sw.log {
            fig = fig.log_x();
        }
        let mut md = format!(
            "\n### Sweep of system.{}\n\n| {} | {} |\n|---|{}\n",
            sw.key,
            sw.key,
            labels.join(" | "),
            "---|".repeat(labels.len())
        );
        let mut failures = Vec::new();
        for p in &points {
            let cells: Vec<String> = p
                .runs
                .iter()
                .map(|r| match &r.error {
                    Ok(e) => format!("{e:.2e}"),
                    Err(_) => "failed".to_string(),
                })
                .collect();
            md += &format!("| {} | {} |\n", fmt_num(p.value), cells.join(" | "));
            for (r, label) in p.runs.iter().zip(&labels) {
                if let Err(e) = &r.error {
                    failures.push(format!("{} = {}: {label}: {e}", sw.key, fmt_num(p.value)));
                }
            }
        }
        for (j, label) in labels.iter().enumerate() {
            let pts: Vec<(f64, f64)> = points
                .iter()
                .filter_map(|p| match p.runs[j].error {
                    Ok(e) if e > 0.0 && e.is_finite() => Some((p.value, e)),
                    _ => None,
                })
                .collect();
            fig = fig.curve(label.clone(), pts, Style::Line);
        }
        if !failures.is_empty() {
            md += "\nFailed runs of the sweep:\n\n";
            for f in failures {
                md += &format!("- {f}\n");
            }
        }
        Ok((self.figure_artifact("sweep", "sweep", fig), md))
    }

    /// The runs of one history output (`key` names it), each with its legend label.
    fn histories(
        &self,
        list: &[RunSpec],
        key: &str,
        samples: usize,
    ) -> Result<Vec<(String, History)>, SceneError> {
        list.iter()
            .enumerate()
            .map(|(j, r)| {
                let k = format!("output.{key}[{j}]");
                let knob = run_knob(&self.file, &k, r)?;
                let h = self
                    .case
                    .history(r.method, knob, samples)
                    .map_err(|e| self.err(&k, e))?;
                let n = h.t.len();
                if n == 0 || h.q.len() != n || h.p.len() != n {
                    return Err(self.err(&k, "the run returned an empty or ragged history"));
                }
                Ok((legend_label(r.method, knob), h))
            })
            .collect()
    }

    fn figure_artifact(&self, what: &str, key: &'static str, fig: Figure) -> Artifact {
        Artifact {
            rel: self.figure_path(what),
            key,
            content: Content::Figure(Box::new(fig)),
        }
    }

    /// `output.phase_portrait`: the runs in the system's projection of phase space.
    fn phase_portrait(&self, runs: &[RunSpec], samples: usize) -> Result<Artifact, SceneError> {
        let pr = self.case.portrait();
        let axes = self.spec.output.portrait.clone();
        let (what, x_label, y_label) = match &axes {
            None => (
                pr.title.to_string(),
                pr.x_label.to_string(),
                pr.y_label.to_string(),
            ),
            Some(PortraitAxes { x, y }) => {
                let kinds = (x.starts_with('q'), y.starts_with('q'));
                let what = match kinds {
                    (true, true) => "configuration space",
                    (false, false) => "momentum space",
                    _ => "phase portrait",
                };
                (what.to_string(), x.clone(), y.clone())
            }
        };
        let mut fig = Figure::new(format!("{} — {what}", self.title), x_label, y_label);
        if axes.is_none() && pr.equal_aspect {
            fig = fig.equal_aspect();
        }
        for (label, h) in self.histories(runs, "phase_portrait", samples)? {
            let pts: Vec<(f64, f64)> = match &axes {
                None => {
                    h.q.iter()
                        .zip(&h.p)
                        .map(|(q, p)| (pr.project)(q, p))
                        .collect()
                }
                Some(a) => {
                    let (vx, vy) = (variable(&a.x), variable(&a.y));
                    let pick = |v: Option<(bool, usize)>, q: &[f64], p: &[f64]| match v {
                        Some((true, i)) => q.get(i).copied(),
                        Some((false, i)) => p.get(i).copied(),
                        None => None,
                    };
                    let dim = h.q[0].len();
                    for (k, v) in [("x", vx), ("y", vy)] {
                        if v.is_some_and(|(_, i)| i >= dim) {
                            return Err(self.err(
                                format!("output.portrait.{k}"),
                                format!(
                                    "the system has {dim} degrees of freedom: indices 0…{}",
                                    dim.saturating_sub(1)
                                ),
                            ));
                        }
                    }
                    h.q.iter()
                        .zip(&h.p)
                        .map(|(q, p)| {
                            (
                                pick(vx, q, p).unwrap_or(f64::NAN),
                                pick(vy, q, p).unwrap_or(f64::NAN),
                            )
                        })
                        .collect()
                }
            };
            fig = fig.curve(label, pts, Style::Line);
        }
        Ok(self.figure_artifact("phase-portrait", "output.phase_portrait", fig))
    }

    /// `output.energy_error`: `|H(t) − H(0)|`, relative unless `H(0) = 0`, along the runs.
    fn energy_error(&self, runs: &[RunSpec], samples: usize) -> Result<Artifact, SceneError> {
        let case = &*self.case;
        let runs = self.histories(runs, "energy_error", samples)?;
        // Every run starts from the scene's initial state: one H(0) for all. The error is
        // relative unless H(0) = 0, where it is absolute and the axis says so.
        let h0 = {
            let h = &runs[0].1;
            case.energy(h.t[0], &h.q[0], &h.p[0])
                .map_err(|e| self.err("output.energy_error", e))?
        };
        let (scale, axis, caption) = if h0 != 0.0 {
            (
                h0.abs(),
                "|ΔH / H₀|",
                "Relative energy error |H(t) − H(0)| / |H(0)| along each run.",
            )
        } else {
            (
                1.0,
                "|ΔH|",
                "Energy error |H(t) − H(0)| along each run (absolute: H(0) = 0).",
            )
        };
        let mut fig = Figure::new(format!("{} — energy error", self.title), "t", axis)
            .log_y()
            .caption(caption);
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
        Ok(self.figure_artifact("energy-error", "output.energy_error", fig))
    }

    /// `output.position_error`: `|q(t) − q_ref(t)|` along the runs, `t > 0` (every run starts at
    /// the reference's initial state).
    fn position_error(&self, runs: &[RunSpec], samples: usize) -> Result<Artifact, SceneError> {
        let key = "output.position_error";
        let caption = format!(
            "Distance |q(t) − q_ref(t)| from the reference solution along each run, t > 0 \
             ({}).",
            self.case.reference_note()
        );
        let mut fig = Figure::new(format!("{} — position error", self.title), "t", "|Δq|")
            .log_y()
            .caption(caption);
        for (label, h) in self.histories(runs, "position_error", samples)? {
            let reference = self
                .case
                .reference_coordinates(&h.t)
                .map_err(|e| self.err(key, e))?;
            let pts: Vec<(f64, f64)> =
                h.t.iter()
                    .zip(&h.q)
                    .zip(&reference)
                    .filter(|((&t, _), _)| t > 0.0)
                    .map(|((&t, q), r)| {
                        let d2: f64 = q.iter().zip(r).map(|(a, b)| (a - b) * (a - b)).sum();
                        (t, d2.sqrt())
                    })
                    .collect();
            fig = fig.curve(label, pts, Style::Line);
        }
        Ok(self.figure_artifact("position-error", key, fig))
    }

    /// `output.invariants`: the drift of every conserved quantity the system knows, one panel
    /// per quantity (titled `|ΔI/I₀|` with the quantity's name), one colour per run.
    fn invariants(&self, runs: &[RunSpec], samples: usize) -> Result<Artifact, SceneError> {
        let case = &*self.case;
        let mut panels: Vec<String> = Vec::new();
        // (panel, legend label, points) of every curve.
        type Drift = (usize, String, Vec<(f64, f64)>);
        let mut curves: Vec<Drift> = Vec::new();
        let mut absolute: Vec<&str> = Vec::new();
        for (label, h) in self.histories(runs, "invariants", samples)? {
            let values: Vec<Vec<Invariant>> = (0..h.t.len())
                .map(|k| case.invariants(h.t[k], &h.q[k], &h.p[k]))
                .collect::<crate::Result<_>>()
                .map_err(|e| self.err("output.invariants", e))?;
            let first = &values[0];
            if panels.is_empty() {
                for inv in first {
                    let n = inv.name;
                    panels.push(if inv.value != 0.0 {
                        format!("|Δ{n} / {n}₀|")
                    } else {
                        absolute.push(n);
                        format!("|Δ{n}|")
                    });
                }
            }
            if first.len() != panels.len() {
                return Err(self.err(
                    "output.invariants",
                    format!(
                        "the runs give {} and {} conserved quantities",
                        panels.len(),
                        first.len()
                    ),
                ));
            }
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
                curves.push((j, label.clone(), pts));
            }
        }
        let mut caption = "Change of each conserved quantity I along each run, one panel per \
                           quantity: relative, |I(t) − I(0)| / |I(0)|"
            .to_string();
        if absolute.is_empty() {
            caption += ".";
        } else {
            caption += &format!(
                "; absolute, |I(t) − I(0)|, for {} (I(0) = 0).",
                absolute.join(", ")
            );
        }
        let mut fig = Figure::new(format!("{} — conserved quantities", self.title), "t", "")
            .log_y()
            .panels(panels)
            .caption(caption);
        // Panel by panel, the runs in the same order: one colour per run in every panel.
        curves.sort_by_key(|c| c.0);
        for (j, label, pts) in curves {
            fig = fig.curve_in(j, label, pts, Style::Line);
        }
        Ok(self.figure_artifact("invariants", "output.invariants", fig))
    }

    /// `output.elements`: the osculating-element histories, one panel per element on linear
    /// axes (angles continued across 2π), every run in each panel; and a note for the table
    /// naming the elements a run holds constant to rounding.
    fn elements(&self, runs: &[RunSpec], samples: usize) -> Result<(Artifact, String), SceneError> {
        let case = &*self.case;
        let names = case.element_names().unwrap_or(&[]);
        let mut notes = String::new();
        let angles: Vec<&str> = names.iter().copied().filter(|n| is_angle(n)).collect();
        let mut caption = "Osculating elements against time, one panel each.".to_string();
        if !angles.is_empty() {
            caption += &format!(
                " The angles ({}) are in radians, continued across 2π.",
                angles.join(", ")
            );
        }
        let mut fig = Figure::new(format!("{} — osculating elements", self.title), "t", "")
            .panels(names.iter().copied())
            .caption(caption);
        for (label, h) in self.histories(runs, "elements", samples)? {
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
                let mut prev = e0;
                let mut value = e0;
                let mut pts = Vec::with_capacity(h.t.len());
                for (&t, e) in h.t.iter().zip(&els) {
                    value += if is_angle(n) {
                        angle_step(e[j], prev)
                    } else {
                        e[j] - prev
                    };
                    prev = e[j];
                    pts.push((t, value));
                }
                // An element that a theory holds constant differs from its initial value
                // only by the rounding of the element map (a few ulps).
                let floor = 64.0 * f64::EPSILON * e0.abs().max(1.0);
                if pts.iter().all(|&(_, v)| (v - e0).abs() <= floor) {
                    constant.push(*n);
                }
                fig = fig.curve_in(j, label.clone(), pts, Style::Line);
            }
            if !constant.is_empty() {
                notes += &format!(
                    "Elements constant to rounding along {label}: {}.\n\n",
                    constant.join(", ")
                );
            }
        }
        Ok((
            self.figure_artifact("elements", "output.elements", fig),
            notes,
        ))
    }

    /// `output.spectrum`: the real parts of the transverse eigenvalues of the steady motions
    /// against their parameter, one curve per eigenvalue, each crossing of zero marked on the
    /// axis; and a note for the table listing the crossings.
    fn spectrum(&self, sp: &SpectrumSpec) -> Result<(Artifact, String), SceneError> {
        let key = "output.spectrum";
        let name = self.case.steady_motion_parameter().unwrap_or("μ");
        let study = self
            .case
            .parameter_study(sp.from, sp.to, sp.samples)
            .map_err(|e| self.err(key, e))?;
        let branches = study
            .spectra
            .iter()
            .map(|s| s.spectrum.transverse.len())
            .max()
            .unwrap_or(0);
        let caption = format!(
            "Real parts of the transverse eigenvalues of the linearisation about the steady \
             motions against {name} ({} values in [{}, {}]; the zero eigenvalues of the family \
             of steady motions factored out); the markers on the axis are the values of {name} \
             where a real part crosses zero, located by Brent's method to 1e−12.",
            sp.samples,
            fmt_num(sp.from),
            fmt_num(sp.to)
        );
        let mut fig = Figure::new(
            format!("{} — eigenvalues against {name}", self.title),
            name,
            "Re λ",
        )
        .caption(caption);
        for k in 0..branches {
            let pts: Vec<(f64, f64)> = study
                .spectra
                .iter()
                .map(|s| {
                    let re = s.spectrum.transverse.get(k).map_or(f64::NAN, |l| l.re);
                    (s.parameter, re)
                })
                .collect();
            fig = fig.curve(format!("Re λ{}", subscript(k + 1)), pts, Style::Line);
        }
        let mut notes = String::new();
        if study.crossings.is_empty() {
            notes += &format!(
                "No real part crosses zero for {name} in [{}, {}].\n\n",
                fmt_num(sp.from),
                fmt_num(sp.to)
            );
        }
        for c in &study.crossings {
            fig = fig.curve(
                format!("{name}* = {:.12}", c.parameter),
                vec![(c.parameter, 0.0)],
                Style::Markers,
            );
            notes += &format!(
                "A real part crosses zero at {name} = {:.15} ({:?}; unstable eigenvalues {} → {}).\n\n",
                c.parameter, c.kind, c.unstable_counts.0, c.unstable_counts.1
            );
        }
        Ok((self.figure_artifact("spectrum", key, fig), notes))
    }

    /// `output.table`: the report as Markdown and the sweep as CSV.
    fn tables(&self, md: &str, csv: String) -> Vec<Artifact> {
        vec![
            Artifact {
                rel: self.table_path("md"),
                key: "",
                content: Content::Text(md.to_string()),
            },
            Artifact {
                rel: self.table_path("csv"),
                key: "",
                content: Content::Text(csv),
            },
        ]
    }

    /// Write the rendered outputs in order under the output directory.
    fn write(
        &self,
        opts: &RunOptions,
        markdown: String,
        artifacts: Vec<Artifact>,
    ) -> Result<RunSummary, SceneError> {
        let setup = FigureSetup::new(&self.file, &self.spec.output, &opts.figures)?;
        let mut files = Vec::with_capacity(artifacts.len());
        for a in artifacts {
            let path = opts.out.join(&a.rel);
            ensure_parent(&path).map_err(|e| self.err(a.key, e))?;
            let fig = match a.content {
                Content::Text(text) => {
                    std::fs::write(&path, text)
                        .map_err(|e| self.err(a.key, format!("{}: {e}", path.display())))?;
                    files.push(path);
                    continue;
                }
                Content::Figure(fig) => *fig,
                Content::WorkPrecision(c) => crate::plot::work_precision(&c),
            };
            // A figure of several panels is taller: a quarter of the height more per panel.
            let mut size = setup.size;
            let panels = fig.panel_labels.len();
            if panels > 1 {
                let taller = Size {
                    height: size.height * (1.0 + 0.25 * (panels - 1) as f64),
                    ..size
                };
                if taller.check().is_ok() {
                    size = taller;
                }
            }
            let written = fig
                .size(size)
                .write(&path, &setup.formats, setup.data)
                .map_err(|e| self.err(a.key, e))?;
            files.extend(written);
        }
        Ok(RunSummary { markdown, files })
    }
}

/// A phase-space variable by name: `q<i>` (coordinate, `true`) or `p<i>` (momentum, `false`).
fn variable(name: &str) -> Option<(bool, usize)> {
    let (kind, index) = name.split_at_checked(1)?;
    let i: usize = index.parse().ok()?;
    match kind {
        "q" => Some((true, i)),
        "p" => Some((false, i)),
        _ => None,
    }
}

/// `output.spectrum`: the system has a family of steady motions, the range is finite and
/// increasing, and the number of values in `2..=100000`.
fn check_spectrum(file: &str, sp: &SpectrumSpec, case: &dyn Case) -> Result<(), SceneError> {
    let key = "output.spectrum";
    if case.steady_motion_parameter().is_none() {
        return Err(SceneError::new(
            file,
            key,
            "this system has no family of steady motions",
        ));
    }
    if !(sp.from.is_finite()
        && sp.to.is_finite()
        && sp.from < sp.to
        && (sp.to - sp.from).is_finite())
    {
        return Err(SceneError::new(
            file,
            format!("{key}.to"),
            format!(
                "expected finite `from` < `to`, found from = {}, to = {}",
                fmt_num(sp.from),
                fmt_num(sp.to)
            ),
        ));
    }
    if !(2..=100_000).contains(&sp.samples) {
        return Err(SceneError::new(
            file,
            format!("{key}.samples"),
            format!("expected 2..=100000 values, found {}", sp.samples),
        ));
    }
    Ok(())
}

/// `n` in subscript digits.
fn subscript(n: usize) -> String {
    n.to_string()
        .chars()
        .map(|c| {
            c.to_digit(10)
                .and_then(|d| char::from_u32(0x2080 + d))
                .unwrap_or(c)
        })
        .collect()
}

/// Whether the element named `name` is an angle (Ω, ω, ϖ), continued across 2π.
fn is_angle(name: &str) -> bool {
    ["Ω", "ω", "ϖ"].contains(&name)
}

/// The change of an angle from `x0` to `x`, reduced to `[−π, π)`.
fn angle_step(x: f64, x0: f64) -> f64 {
    (x - x0 + std::f64::consts::PI).rem_euclid(std::f64::consts::TAU) - std::f64::consts::PI
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

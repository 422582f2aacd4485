//! The scene file format: what a TOML scene may say, parsed with serde and checked key by key.
//!
//! Every error names the file, the key (as a dotted path, e.g. `method[2].steps`) and what was
//! expected, on one line: [`SceneError`].

use crate::integrate::methods::{self, MethodInfo, METHODS};
use crate::nonholonomic::{ConstrainedInfo, CONSTRAINED_METHODS};
use serde::Deserialize;
use std::fmt;

/// An error in a scene: the file, the key and what was wrong, printed on one line as
/// `file: key: message`.
#[derive(Clone, Debug, PartialEq)]
pub struct SceneError {
    /// The scene file (or built-in scene name).
    pub file: String,
    /// The key, as a dotted path (`system.eccentricity`, `method[1].steps`); empty for the
    /// whole file.
    pub key: String,
    /// What was expected or what went wrong.
    pub message: String,
}

impl SceneError {
    /// A new error at `key` of `file`.
    pub fn new(
        file: impl Into<String>,
        key: impl Into<String>,
        message: impl Into<String>,
    ) -> Self {
        let one_line = |s: String| s.split_whitespace().collect::<Vec<_>>().join(" ");
        Self {
            file: file.into(),
            key: key.into(),
            message: one_line(message.into()),
        }
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if self.key.is_empty() {
            write!(f, "{}: {}", self.file, self.message)
        } else {
            write!(f, "{}: {}: {}", self.file, self.key, self.message)
        }
    }
}

impl std::error::Error for SceneError {}

/// A theory a scene can compare with the integrators: a state at any time from a formula,
/// a series or a reduced system (described in [`THEORIES`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TheoryKind {
    /// The Hamilton–Jacobi solution by quadrature through the turning points.
    HamiltonJacobi,
    /// Lie-series normal form of the pendulum to order N.
    NormalForm,
    /// Lindstedt–Poincaré series of the pendulum to order N.
    Lindstedt,
    /// Osculating elements by Lagrange's planetary equations, integrated by Dormand–Prince.
    OsculatingElements,
    /// Mean elements with first-order secular rates.
    MeanElements,
    /// Brouwer–Lyddane theory: second-order secular rates, first-order periodic terms.
    BrouwerLyddane,
}

/// A theory, described once: its key in scene files, its label in tables and legends, what it
/// is (for `hj list`), and its knob.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TheoryInfo {
    /// Which theory.
    pub kind: TheoryKind,
    /// Key in scene files.
    pub key: &'static str,
    /// Label in tables and legends.
    pub label: &'static str,
    /// What it is.
    pub description: &'static str,
    /// The knob it is swept over.
    pub knob: Knob,
}

/// Every theory, in the order of [`TheoryKind`]'s variants (`THEORIES[k as usize].kind == k`).
pub const THEORIES: [TheoryInfo; 6] = [
    TheoryInfo {
        kind: TheoryKind::HamiltonJacobi,
        key: "hamilton-jacobi",
        label: "Hamilton–Jacobi quadrature",
        description: "Hamilton–Jacobi solution by quadrature",
        knob: Knob::None,
    },
    TheoryInfo {
        kind: TheoryKind::NormalForm,
        key: "normal-form",
        label: "Lie-series normal form",
        description: "Lie-series normal form to order N (pendulum)",
        knob: Knob::Orders,
    },
    TheoryInfo {
        kind: TheoryKind::Lindstedt,
        key: "lindstedt",
        label: "Lindstedt–Poincaré",
        description: "Lindstedt–Poincaré series to order N (pendulum)",
        knob: Knob::Orders,
    },
    TheoryInfo {
        kind: TheoryKind::OsculatingElements,
        key: "osculating-elements",
        label: "osculating elements (planetary equations)",
        description: "osculating elements by Lagrange's planetary equations + Dormand–Prince \
                      (J2 orbit)",
        knob: Knob::Rtol,
    },
    TheoryInfo {
        kind: TheoryKind::MeanElements,
        key: "mean-elements",
        label: "mean elements (secular J2)",
        description: "mean elements, first-order secular rates (J2 orbit)",
        knob: Knob::None,
    },
    TheoryInfo {
        kind: TheoryKind::BrouwerLyddane,
        key: "brouwer-lyddane",
        label: "Brouwer–Lyddane theory (J2)",
        description: "Brouwer–Lyddane theory: second-order secular rates, first-order \
                      short- and long-period terms closed in e (J2 orbit)",
        knob: Knob::None,
    },
];

impl TheoryKind {
    /// The theory's entry in [`THEORIES`].
    pub fn info(self) -> &'static TheoryInfo {
        &THEORIES[self as usize]
    }
}

/// What a scene names in `[[method]] kind = "…"` (and a history's `method = "…"`): an
/// integration method of [`METHODS`], a method for constrained systems of
/// [`CONSTRAINED_METHODS`] or a theory of [`THEORIES`], by key. Everything said about it — key,
/// label, description, knob — comes from those three tables.
#[derive(Clone, Copy, Debug, Deserialize)]
#[serde(try_from = "String")]
pub enum MethodKind {
    /// An integration method.
    Integrator(&'static MethodInfo),
    /// A method for constrained systems.
    Constrained(&'static ConstrainedInfo),
    /// A theory.
    Theory(TheoryKind),
}

impl PartialEq for MethodKind {
    fn eq(&self, other: &Self) -> bool {
        self.key() == other.key()
    }
}

impl Eq for MethodKind {}

impl std::hash::Hash for MethodKind {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        self.key().hash(state);
    }
}

impl From<TheoryKind> for MethodKind {
    fn from(kind: TheoryKind) -> Self {
        MethodKind::Theory(kind)
    }
}

impl TryFrom<String> for MethodKind {
    type Error = String;
    fn try_from(key: String) -> Result<Self, String> {
        MethodKind::from_key(&key).ok_or_else(|| {
            format!(
                "unknown method kind `{key}`; the kinds are: {}",
                MethodKind::all()
                    .map(MethodKind::key)
                    .collect::<Vec<_>>()
                    .join(", ")
            )
        })
    }
}

/// The knob a method is swept over.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Knob {
    /// Number of fixed steps.
    Steps,
    /// Relative (and absolute) tolerance.
    Rtol,
    /// Order of a series.
    Orders,
    /// Step in fictitious time (time-transformed splittings).
    Ds,
    /// No knob: one run.
    None,
}

impl From<methods::Knob> for Knob {
    fn from(knob: methods::Knob) -> Self {
        match knob {
            methods::Knob::Steps => Knob::Steps,
            methods::Knob::Tolerance => Knob::Rtol,
            methods::Knob::FictitiousStep => Knob::Ds,
        }
    }
}

impl Knob {
    /// The knob's key for one value (a history run, a table cell): `steps`, `rtol`, `order`.
    pub fn singular(self) -> &'static str {
        match self {
            Knob::Orders => "order",
            k => k.key(),
        }
    }

    /// The scene key of the knob's list in a `[[method]]`.
    pub fn key(self) -> &'static str {
        match self {
            Knob::Steps => "steps",
            Knob::Rtol => "rtol",
            Knob::Orders => "orders",
            Knob::Ds => "ds",
            Knob::None => "",
        }
    }
}

impl MethodKind {
    /// Every kind, in the order `hj list` shows them: the integration methods, the methods for
    /// constrained systems, then the theories.
    pub fn all() -> impl Iterator<Item = MethodKind> {
        METHODS
            .iter()
            .map(MethodKind::Integrator)
            .chain(CONSTRAINED_METHODS.iter().map(MethodKind::Constrained))
            .chain(THEORIES.iter().map(|t| MethodKind::Theory(t.kind)))
    }

    /// The kind with key `key`, if there is one.
    pub fn from_key(key: &str) -> Option<MethodKind> {
        MethodKind::all().find(|k| k.key() == key)
    }

    /// The key used in scene files, e.g. `"gauss3"`.
    pub fn key(self) -> &'static str {
        match self {
            MethodKind::Integrator(m) => m.key,
            MethodKind::Constrained(m) => m.key,
            MethodKind::Theory(t) => t.info().key,
        }
    }

    /// Label for tables and legends, e.g. `"Gauss–Legendre, 3 stages, order 6"`.
    pub fn label(self) -> String {
        match self {
            MethodKind::Integrator(m) => m.label(),
            MethodKind::Constrained(m) => m.label.to_string(),
            MethodKind::Theory(t) => t.info().label.to_string(),
        }
    }

    /// What the method is, for `hj list` and error messages.
    pub fn description(self) -> String {
        match self {
            MethodKind::Integrator(m) => m.description(),
            MethodKind::Constrained(m) => m.description.to_string(),
            MethodKind::Theory(t) => t.info().description.to_string(),
        }
    }

    /// The knob this method is swept over.
    pub fn knob(self) -> Knob {
        match self {
            MethodKind::Integrator(m) => m.knob.into(),
            MethodKind::Constrained(m) => m.knob.into(),
            MethodKind::Theory(t) => t.info().knob,
        }
    }

    /// The integration method, if the kind is one.
    pub fn integrator(self) -> Option<&'static MethodInfo> {
        match self {
            MethodKind::Integrator(m) => Some(m),
            MethodKind::Constrained(_) | MethodKind::Theory(_) => None,
        }
    }

    /// The method for constrained systems, if the kind is one.
    pub fn constrained(self) -> Option<&'static ConstrainedInfo> {
        match self {
            MethodKind::Constrained(m) => Some(m),
            MethodKind::Integrator(_) | MethodKind::Theory(_) => None,
        }
    }
}

/// `[span]`: how long to follow the motion: `periods` (in units of the system's period) or
/// `time`, exactly one of them.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SpanSpec {
    /// Number of periods of the unperturbed motion.
    pub periods: Option<f64>,
    /// Length of time.
    pub time: Option<f64>,
}

/// `[[method]]`: one method or theory and the values of its knob.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct MethodSpec {
    /// Which method.
    pub kind: MethodKind,
    /// Step counts (fixed-step methods).
    pub steps: Option<Vec<u64>>,
    /// Tolerances (adaptive methods).
    pub rtol: Option<Vec<f64>>,
    /// Orders (series theories).
    pub orders: Option<Vec<u32>>,
    /// Steps in fictitious time (time-transformed splittings).
    pub ds: Option<Vec<f64>>,
    /// Label in tables and legends (default: the method's label, [`MethodKind::label`]).
    pub label: Option<String>,
}

/// One run for a history output: a method and one value of its knob.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RunSpec {
    /// Which method.
    pub method: MethodKind,
    /// Steps (fixed-step methods).
    pub steps: Option<u64>,
    /// Tolerance (adaptive methods).
    pub rtol: Option<f64>,
    /// Order (series theories).
    pub order: Option<u32>,
    /// Step in fictitious time (time-transformed splittings).
    pub ds: Option<f64>,
}

fn yes() -> bool {
    true
}

fn default_samples() -> usize {
    400
}

/// `[output]`: what to produce. The runner computes only what is asked for.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// A Markdown/CSV table of every method's error and cost (default on).
    #[serde(default = "yes")]
    pub table: bool,
    /// Target errors for the table's "time to reach" columns.
    pub targets: Option<Vec<f64>>,
    /// An SVG work-precision diagram (error against wall time, log axes).
    #[serde(default)]
    pub work_precision: bool,
    /// Phase portraits of these runs.
    #[serde(default)]
    pub phase_portrait: Vec<RunSpec>,
    /// Relative energy error against time (log axis) of these runs.
    #[serde(default)]
    pub energy_error: Vec<RunSpec>,
    /// Distance `|q(t) − q_ref(t)|` of these runs from the reference solution (log axis).
    #[serde(default)]
    pub position_error: Vec<RunSpec>,
    /// Drift of every conserved quantity the system knows (energy, angular momenta,
    /// Runge–Lenz vector, …) along these runs (log axis).
    #[serde(default)]
    pub invariants: Vec<RunSpec>,
    /// Osculating-element histories of these runs (Kepler-type systems).
    #[serde(default)]
    pub elements: Vec<RunSpec>,
    /// The real parts of the transverse eigenvalues of the system's steady motions against
    /// their parameter (the forward speed of a rolling body), the crossings of zero marked.
    pub spectrum: Option<SpectrumSpec>,
    /// Points per history: every k-th step end of a fixed-step method (never interpolated; at
    /// most `steps + 1` points), uniform times for adaptive methods (dense output) and theories.
    #[serde(default = "default_samples")]
    pub samples: usize,
    /// The phase portrait's variables by name, `{ x = "q0", y = "p0" }` (coordinates `q0`, `q1`,
    /// … and momenta `p0`, `p1`, …); default: the system's own projection (an orbit in the
    /// plane for Kepler-type systems, `(θ, p_θ)` for the pendulum).
    pub portrait: Option<PortraitAxes>,
    /// Figure width: inches as a number, or a length with its unit (`"3.4in"`, `"8.6cm"`,
    /// `"1020px"` at `dpi`); default 6.4 in.
    pub width: Option<Length>,
    /// Figure height, as `width`; default 4.2 in.
    pub height: Option<Length>,
    /// Base font size in points (tick labels and legend); default 9.
    pub font_size: Option<f64>,
    /// Resolution of PNG figures in dots per inch; default 150.
    pub dpi: Option<f64>,
    /// Figure formats among `svg`, `png`, `pdf` (SVG is always written); default
    /// `["svg", "png"]`.
    pub formats: Option<Vec<String>>,
    /// How the data behind each figure is written: `"csv"` (every point in the table, the
    /// default) or `"npy"` (a CSV header and the points in a NumPy file).
    pub data: Option<String>,
}

/// `spectrum = { from = 0.5, to = 3.5, samples = 241 }`: the parameter range of a stability
/// study ([`crate::stability::parameter_study`]).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SpectrumSpec {
    /// Lowest parameter value.
    pub from: f64,
    /// Highest parameter value.
    pub to: f64,
    /// Number of equally spaced parameter values (at least 2).
    pub samples: usize,
}

/// `portrait = { x = "q0", y = "p0" }`: the variables of a phase portrait.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct PortraitAxes {
    /// Horizontal axis: `q<i>` or `p<i>`.
    pub x: String,
    /// Vertical axis: `q<i>` or `p<i>`.
    pub y: String,
}

/// A length in a scene: inches as a number, or text with a unit (`"8.6cm"`).
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(untagged)]
pub enum Length {
    /// Inches.
    Inches(f64),
    /// A number with its unit: `in`, `cm`, `mm`, `pt`, `px`.
    Text(String),
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            table: true,
            targets: None,
            work_precision: false,
            phase_portrait: Vec::new(),
            energy_error: Vec::new(),
            position_error: Vec::new(),
            invariants: Vec::new(),
            elements: Vec::new(),
            spectrum: None,
            samples: default_samples(),
            portrait: None,
            width: None,
            height: None,
            font_size: None,
            dpi: None,
            formats: None,
            data: None,
        }
    }
}

/// A scene file as written.
#[derive(Clone, Debug, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Short name (file names of the outputs); default: the file stem.
    pub name: Option<String>,
    /// Title of tables and figures.
    pub title: Option<String>,
    /// `[system]`: `name = "…"` from the catalogue and the system's own keys (parameters and
    /// initial state), checked by the catalogue entry.
    pub system: toml::Table,
    /// `[span]`.
    pub span: Option<SpanSpec>,
    /// `[[method]]` entries.
    #[serde(default, rename = "method")]
    pub methods: Vec<MethodSpec>,
    /// `[output]`.
    #[serde(default)]
    pub output: OutputSpec,
    /// `[sweep]`: one number of `[system]` varied, every method's error against it
    /// ([`super::parameter_sweep`]).
    pub sweep: Option<super::parameter_sweep::SweepSpec>,
}

/// Parse a scene from TOML text; `file` names it in errors.
///
/// # Errors
/// A [`SceneError`] naming the key for TOML syntax errors, missing keys, wrong types and
/// unknown keys or method kinds.
pub fn parse_scene_file(file: &str, text: &str) -> Result<SceneFile, SceneError> {
    let de = toml::Deserializer::parse(text).map_err(|e| syntax_error(file, text, &e))?;
    serde_path_to_error::deserialize(de).map_err(|e| {
        let path = e.path().to_string();
        let inner = e.into_inner();
        let message = inner.message().to_string();
        let key = if path == "." { String::new() } else { path };
        // A missing field is reported at its parent: name the field itself.
        let key = match missing_field(&message) {
            Some(field) if key.is_empty() => field.to_string(),
            Some(field) => format!("{key}.{field}"),
            None => key,
        };
        SceneError::new(file, key, message)
    })
}

fn missing_field(message: &str) -> Option<&str> {
    let rest = message.strip_prefix("missing field `")?;
    rest.split('`').next()
}

fn syntax_error(file: &str, text: &str, e: &toml::de::Error) -> SceneError {
    let at = e
        .span()
        .map(|s| {
            let line = text[..s.start.min(text.len())].matches('\n').count() + 1;
            format!("line {line}")
        })
        .unwrap_or_default();
    SceneError::new(
        file,
        at,
        format!("TOML syntax error: {}", e.message().trim()),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `TheoryKind::info` indexes [`THEORIES`] by the variant.
    #[test]
    fn theories_are_indexed_by_their_kind() {
        for (i, t) in THEORIES.iter().enumerate() {
            assert_eq!(t.kind as usize, i, "{}", t.key);
            assert_eq!(t.kind.info(), t);
            assert_eq!(
                MethodKind::from_key(t.key),
                Some(MethodKind::Theory(t.kind))
            );
        }
    }

    /// A scene's `kind` parses to the table entry of its key; an unknown key is refused with
    /// every key.
    #[test]
    fn kinds_parse_by_key() {
        let spec = parse_scene_file(
            "k.toml",
            "[system]\nname = \"kepler\"\n[[method]]\nkind = \"gauss3\"\nsteps = [10]\n",
        )
        .unwrap();
        let kind = spec.methods[0].kind;
        assert_eq!(kind.label(), "Gauss–Legendre, 3 stages, order 6");
        assert_eq!(kind.knob(), Knob::Steps);
        let e = parse_scene_file(
            "k.toml",
            "[system]\nname = \"kepler\"\n[[method]]\nkind = \"gauss-3\"\n",
        )
        .unwrap_err();
        assert_eq!(e.key, "method[0].kind");
        for k in MethodKind::all() {
            assert!(e.message.contains(k.key()), "{e}");
        }
    }
}

//! The scene file format: what a TOML scene may say, parsed with serde and checked key by key.
//!
//! Every error names the file, the key (as a dotted path, e.g. `method[2].steps`) and what was
//! expected, on one line: [`SceneError`].

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

/// Every method and theory a scene can name in `[[method]] kind = "…"`, with its knob.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum MethodKind {
    /// Classical Runge–Kutta 4 (`steps`).
    Rk4,
    /// Symplectic Euler, kick then drift (`steps`).
    SymplecticEuler,
    /// Störmer–Verlet, kick–drift–kick (`steps`).
    Verlet,
    /// Störmer–Verlet, drift–kick–drift (`steps`).
    VerletDkd,
    /// Yoshida's triple-jump composition of order 4 (`steps`).
    Yoshida4,
    /// Suzuki's 5-stage composition of order 4 (`steps`).
    Suzuki4,
    /// Blanes–Moan SRKN₆ᵇ, order 4 (`steps`).
    BlanesMoan4,
    /// Yoshida 6A, order 6 (`steps`).
    Yoshida6,
    /// Kahan–Li s = 9, order 6 (`steps`).
    KahanLi6,
    /// Yoshida 8D, order 8 (`steps`).
    Yoshida8,
    /// Kahan–Li s = 17, order 8 (`steps`).
    KahanLi8,
    /// Sofroniou–Spaletta s = 35, order 10 (`steps`).
    SofroniouSpaletta10,
    /// Implicit midpoint rule, order 2 (`steps`).
    ImplicitMidpoint,
    /// Gauss–Legendre, 2 stages, order 4 (`steps`).
    Gauss2,
    /// Gauss–Legendre, 3 stages, order 6 (`steps`).
    Gauss3,
    /// Gauss–Legendre, 4 stages, order 8 (`steps`).
    Gauss4,
    /// Wisdom–Holman Kepler splitting (`steps`; perturbed Kepler problems).
    WisdomHolman,
    /// Laskar–Robutel SABA₂ (`steps`; perturbed Kepler problems).
    Saba2,
    /// Laskar–Robutel SABA₃ (`steps`; perturbed Kepler problems).
    Saba3,
    /// Laskar–Robutel SABA₄ (`steps`; perturbed Kepler problems).
    Saba4,
    /// Dormand–Prince 8(5,3) with step control (`rtol`, with `atol = rtol`).
    Dop853,
    /// The system's exact flow, applied in `steps` steps.
    Exact,
    /// The Hamilton–Jacobi solution by quadrature through the turning points (no knob).
    HamiltonJacobi,
    /// Lie-series normal form of the pendulum to order N (`orders`).
    NormalForm,
    /// Lindstedt–Poincaré series of the pendulum to order N (`orders`).
    Lindstedt,
    /// Osculating elements by Lagrange's planetary equations, integrated by DOP853 (`rtol`).
    OsculatingElements,
    /// Mean elements with first-order secular rates (no knob).
    MeanElements,
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
    /// No knob: one run.
    None,
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
            Knob::None => "",
        }
    }
}

impl MethodKind {
    /// Every kind, in the order `hj list` shows them.
    pub const ALL: [MethodKind; 27] = [
        MethodKind::Rk4,
        MethodKind::SymplecticEuler,
        MethodKind::Verlet,
        MethodKind::VerletDkd,
        MethodKind::Yoshida4,
        MethodKind::Suzuki4,
        MethodKind::BlanesMoan4,
        MethodKind::Yoshida6,
        MethodKind::KahanLi6,
        MethodKind::Yoshida8,
        MethodKind::KahanLi8,
        MethodKind::SofroniouSpaletta10,
        MethodKind::ImplicitMidpoint,
        MethodKind::Gauss2,
        MethodKind::Gauss3,
        MethodKind::Gauss4,
        MethodKind::WisdomHolman,
        MethodKind::Saba2,
        MethodKind::Saba3,
        MethodKind::Saba4,
        MethodKind::Dop853,
        MethodKind::Exact,
        MethodKind::HamiltonJacobi,
        MethodKind::NormalForm,
        MethodKind::Lindstedt,
        MethodKind::OsculatingElements,
        MethodKind::MeanElements,
    ];

    /// The name used in scene files.
    pub fn name(self) -> &'static str {
        match self {
            MethodKind::Rk4 => "rk4",
            MethodKind::SymplecticEuler => "symplectic-euler",
            MethodKind::Verlet => "verlet",
            MethodKind::VerletDkd => "verlet-dkd",
            MethodKind::Yoshida4 => "yoshida4",
            MethodKind::Suzuki4 => "suzuki4",
            MethodKind::BlanesMoan4 => "blanes-moan4",
            MethodKind::Yoshida6 => "yoshida6",
            MethodKind::KahanLi6 => "kahan-li6",
            MethodKind::Yoshida8 => "yoshida8",
            MethodKind::KahanLi8 => "kahan-li8",
            MethodKind::SofroniouSpaletta10 => "sofroniou-spaletta10",
            MethodKind::ImplicitMidpoint => "implicit-midpoint",
            MethodKind::Gauss2 => "gauss2",
            MethodKind::Gauss3 => "gauss3",
            MethodKind::Gauss4 => "gauss4",
            MethodKind::WisdomHolman => "wisdom-holman",
            MethodKind::Saba2 => "saba2",
            MethodKind::Saba3 => "saba3",
            MethodKind::Saba4 => "saba4",
            MethodKind::Dop853 => "dop853",
            MethodKind::Exact => "exact",
            MethodKind::HamiltonJacobi => "hamilton-jacobi",
            MethodKind::NormalForm => "normal-form",
            MethodKind::Lindstedt => "lindstedt",
            MethodKind::OsculatingElements => "osculating-elements",
            MethodKind::MeanElements => "mean-elements",
        }
    }

    /// Short label for tables and legends.
    pub fn label(self) -> &'static str {
        match self {
            MethodKind::Rk4 => "RK4",
            MethodKind::SymplecticEuler => "symplectic Euler",
            MethodKind::Verlet => "Störmer–Verlet",
            MethodKind::VerletDkd => "Störmer–Verlet (DKD)",
            MethodKind::Yoshida4 => "Yoshida 4",
            MethodKind::Suzuki4 => "Suzuki 4",
            MethodKind::BlanesMoan4 => "Blanes–Moan 4",
            MethodKind::Yoshida6 => "Yoshida 6",
            MethodKind::KahanLi6 => "Kahan–Li 6",
            MethodKind::Yoshida8 => "Yoshida 8",
            MethodKind::KahanLi8 => "Kahan–Li 8",
            MethodKind::SofroniouSpaletta10 => "Sofroniou–Spaletta 10",
            MethodKind::ImplicitMidpoint => "implicit midpoint",
            MethodKind::Gauss2 => "Gauss–Legendre 4",
            MethodKind::Gauss3 => "Gauss–Legendre 6",
            MethodKind::Gauss4 => "Gauss–Legendre 8",
            MethodKind::WisdomHolman => "Wisdom–Holman",
            MethodKind::Saba2 => "SABA2",
            MethodKind::Saba3 => "SABA3",
            MethodKind::Saba4 => "SABA4",
            MethodKind::Dop853 => "DOP853",
            MethodKind::Exact => "exact flow",
            MethodKind::HamiltonJacobi => "Hamilton–Jacobi quadrature",
            MethodKind::NormalForm => "Lie-series normal form",
            MethodKind::Lindstedt => "Lindstedt–Poincaré",
            MethodKind::OsculatingElements => "osculating elements (planetary equations)",
            MethodKind::MeanElements => "mean elements (secular J2)",
        }
    }

    /// What the method is, for `hj list`.
    pub fn description(self) -> &'static str {
        match self {
            MethodKind::Rk4 => "classical Runge–Kutta, order 4",
            MethodKind::SymplecticEuler => "symplectic Euler, order 1 (separable H)",
            MethodKind::Verlet => "Störmer–Verlet kick–drift–kick, order 2 (separable H)",
            MethodKind::VerletDkd => "Störmer–Verlet drift–kick–drift, order 2 (separable H)",
            MethodKind::Yoshida4 => "Yoshida triple jump, order 4 (separable H)",
            MethodKind::Suzuki4 => "Suzuki 5-stage, order 4 (separable H)",
            MethodKind::BlanesMoan4 => "Blanes–Moan SRKN6b, order 4 (separable H)",
            MethodKind::Yoshida6 => "Yoshida 6A, order 6 (separable H)",
            MethodKind::KahanLi6 => "Kahan–Li s = 9, order 6 (separable H)",
            MethodKind::Yoshida8 => "Yoshida 8D, order 8 (separable H)",
            MethodKind::KahanLi8 => "Kahan–Li s = 17, order 8 (separable H)",
            MethodKind::SofroniouSpaletta10 => "Sofroniou–Spaletta s = 35, order 10 (separable H)",
            MethodKind::ImplicitMidpoint => "implicit midpoint, order 2 (any H)",
            MethodKind::Gauss2 => "Gauss–Legendre 2 stages, order 4 (any H)",
            MethodKind::Gauss3 => "Gauss–Legendre 3 stages, order 6 (any H)",
            MethodKind::Gauss4 => "Gauss–Legendre 4 stages, order 8 (any H)",
            MethodKind::WisdomHolman => "Wisdom–Holman Kepler splitting (perturbed Kepler)",
            MethodKind::Saba2 => "Laskar–Robutel SABA2 (perturbed Kepler)",
            MethodKind::Saba3 => "Laskar–Robutel SABA3 (perturbed Kepler)",
            MethodKind::Saba4 => "Laskar–Robutel SABA4 (perturbed Kepler)",
            MethodKind::Dop853 => "Dormand–Prince 8(5,3), adaptive (any H)",
            MethodKind::Exact => "the system's exact flow",
            MethodKind::HamiltonJacobi => "Hamilton–Jacobi solution by quadrature",
            MethodKind::NormalForm => "Lie-series normal form to order N (pendulum)",
            MethodKind::Lindstedt => "Lindstedt–Poincaré series to order N (pendulum)",
            MethodKind::OsculatingElements => {
                "osculating elements by Lagrange's planetary equations + DOP853 (J2 orbit)"
            }
            MethodKind::MeanElements => "mean elements, first-order secular rates (J2 orbit)",
        }
    }

    /// The knob this method is swept over.
    pub fn knob(self) -> Knob {
        match self {
            MethodKind::Dop853 | MethodKind::OsculatingElements => Knob::Rtol,
            MethodKind::NormalForm | MethodKind::Lindstedt => Knob::Orders,
            MethodKind::HamiltonJacobi | MethodKind::MeanElements => Knob::None,
            _ => Knob::Steps,
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
    /// Label in tables and legends (default: the method's description).
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
    /// Drift of every conserved quantity the system knows (energy, angular momenta,
    /// Runge–Lenz vector, …) along these runs (log axis).
    #[serde(default)]
    pub invariants: Vec<RunSpec>,
    /// Osculating-element histories of these runs (Kepler-type systems).
    #[serde(default)]
    pub elements: Vec<RunSpec>,
    /// Points per history: every k-th step end of a fixed-step method (never interpolated; at
    /// most `steps + 1` points), uniform times for adaptive methods (dense output) and theories.
    #[serde(default = "default_samples")]
    pub samples: usize,
}

impl Default for OutputSpec {
    fn default() -> Self {
        Self {
            table: true,
            targets: None,
            work_precision: false,
            phase_portrait: Vec::new(),
            energy_error: Vec::new(),
            invariants: Vec::new(),
            elements: Vec::new(),
            samples: default_samples(),
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

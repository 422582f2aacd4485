//! Scenes: comparisons set up in a TOML file instead of Rust, run by the `hj` binary.
//!
//! A scene names a system from the [catalogue] with its parameters and initial
//! state (or defines its own by a Hamiltonian, a Lagrangian with constraints or a disturbing
//! function written as expressions, [`expression`]), the time span, the methods and theories to compare with the values of their knob, and
//! the outputs wanted. Nothing is computed that the scene does not ask for.
//!
//! ```toml
//! name = "pendulum-large"                 # prefix of the output files (default: file stem)
//! title = "Pendulum, amplitude 2.5"       # default: the system's description
//!
//! [system]                                # a catalogue entry and its own keys
//! name = "pendulum"
//! amplitude = 2.5                         # or gap = π − amplitude, or q = [..], p = [..]
//!
//! [span]                                  # exactly one of:
//! periods = 100                           #   multiples of the system's period
//! # time = 628.3                          #   or a length of time
//!
//! [[method]]                              # at least one of these
//! kind = "kahan-li17"                      # `hj list` shows every kind and its knob
//! steps = [250, 500, 1000, 2000]
//!
//! [[method]]
//! kind = "dop853"
//! rtol = [1e-8, 1e-10, 1e-12]
//!
//! [[method]]
//! kind = "normal-form"
//! orders = [1, 2, 4, 8]
//!
//! [[method]]
//! kind = "exact"
//! steps = [100]
//!
//! [[method]]
//! kind = "verlet-kdk"
//! steps = [1000, 4000]
//!
//! [[method]]
//! kind = "rk4"
//! steps = [1000, 4000]
//!
//! [output]
//! table = true                            # tables/<name>.md and .csv (default true)
//! targets = [1e-6, 1e-9]                  # "time to reach" columns of the table
//! work_precision = true                   # figures/<name>-work-precision.svg
//! # Histories name methods the scene runs (a `[[method]]` kind), each with its own knob value.
//! phase_portrait = [{ method = "exact", steps = 4000 }]       # figures/<name>-phase-portrait.svg
//! energy_error = [{ method = "verlet-kdk", steps = 4000 }]        # figures/<name>-energy-error.svg
//! position_error = [{ method = "dop853", rtol = 1e-8 }]           # figures/<name>-position-error.svg
//! invariants = [{ method = "rk4", steps = 4000 }]             # figures/<name>-invariants.svg
//! # elements = [{ method = "kahan-li17", steps = 8000 }]       # Kepler-type systems
//! samples = 400                           # points per history: step ends of fixed-step
//!                                         # methods, uniform times otherwise
//! # portrait = { x = "q0", y = "p0" }     # the portrait's variables (default: the system's)
//! width = "6.4in"                         # figure size: a number (inches) or a length with
//! height = "4.2in"                        #   its unit: in, cm, mm, pt, px (at `dpi`)
//! font_size = 9                           # base font size in points
//! dpi = 150                               # PNG resolution
//! formats = ["svg", "png"]                # any of svg, png, pdf (SVG always)
//! data = "csv"                            # the data beside each figure: csv or npy
//! ```
//!
//! Every figure `figures/<name>-<what>.svg` comes with its data, `…-<what>.csv` (every point
//! drawn, see [`crate::plot::data`]), and its caption, `…-<what>.caption.txt`; `hj plot
//! FILE.csv` redraws it, at another size or in another format.
//!
//! Every mistake is reported on one line as `file: key: what was expected`
//! ([`SceneError`]): TOML syntax, missing keys, wrong types, unknown keys, systems or method
//! kinds, non-finite numbers, a method that does not apply to the system, a knob of the wrong
//! kind, a negative span, a span so long that the reference's phase is lost (beyond about
//! 7·10⁸ periods) or a DOP853 run would exceed its step limit, a history of a method the scene
//! does not run, a scene that runs no method, a name unusable as a file name, a directory.

pub mod case;
pub mod catalogue;
pub mod constrained;
pub mod expression;
pub mod gallery;
pub mod henon_heiles;
pub mod impulse;
pub mod megno;
pub mod parameter_sweep;
pub mod rigid_body;
pub mod runner;
pub mod spec;
pub mod stability;

pub use case::{Case, HamiltonianCase, History, Outcome, Table};
pub use catalogue::{Catalogue, Params};
pub use runner::{FigureOptions, FigureSetup, RunOptions, RunSummary, Scene};
pub use spec::{parse_scene_file, Knob, MethodKind, SceneError, SceneFile, TheoryKind};

/// The built-in scenes, embedded in the binary: `(name, TOML text)`.
pub const BUILTIN: [(&str, &str); 23] = [
    ("kepler-e0", include_str!("builtin/kepler-e0.toml")),
    ("kepler-e0.5", include_str!("builtin/kepler-e0.5.toml")),
    ("kepler-e0.9", include_str!("builtin/kepler-e0.9.toml")),
    ("kepler-e0.99", include_str!("builtin/kepler-e0.99.toml")),
    (
        "kepler-precession",
        include_str!("builtin/kepler-precession.toml"),
    ),
    (
        "pendulum-small",
        include_str!("builtin/pendulum-small.toml"),
    ),
    (
        "pendulum-moderate",
        include_str!("builtin/pendulum-moderate.toml"),
    ),
    (
        "pendulum-large",
        include_str!("builtin/pendulum-large.toml"),
    ),
    (
        "pendulum-near-separatrix",
        include_str!("builtin/pendulum-near-separatrix.toml"),
    ),
    ("j2-orbit", include_str!("builtin/j2-orbit.toml")),
    ("j2-theory", include_str!("builtin/j2-theory.toml")),
    ("heavy-top", include_str!("builtin/heavy-top.toml")),
    (
        "henon-heiles-expression",
        include_str!("builtin/henon-heiles-expression.toml"),
    ),
    (
        "spherical-pendulum-expression",
        include_str!("builtin/spherical-pendulum-expression.toml"),
    ),
    (
        "chaplygin-sleigh",
        include_str!("builtin/chaplygin-sleigh.toml"),
    ),
    (
        "chaplygin-sleigh-expression",
        include_str!("builtin/chaplygin-sleigh-expression.toml"),
    ),
    ("rolling-disk", include_str!("builtin/rolling-disk.toml")),
    (
        "transformation-gallery",
        include_str!("builtin/transformation-gallery.toml"),
    ),
    (
        "double-pendulum-spectrum",
        include_str!("builtin/double-pendulum-spectrum.toml"),
    ),
    (
        "free-rigid-body",
        include_str!("builtin/free-rigid-body.toml"),
    ),
    ("megno-map", include_str!("builtin/megno-map.toml")),
    ("struck-rods", include_str!("builtin/struck-rods.toml")),
    (
        "henon-heiles-normal-form",
        include_str!("builtin/henon-heiles-normal-form.toml"),
    ),
];

/// The scenes `hj` runs with no arguments (the showcase): one of each kind, quick.
pub const SHOWCASE: [&str; 5] = [
    "kepler-e0.5",
    "pendulum-near-separatrix",
    "j2-orbit",
    "heavy-top",
    "transformation-gallery",
];

/// Parse and check a scene; `file` names it in errors.
///
/// # Errors
/// A [`SceneError`] naming the key.
pub fn parse(file: &str, text: &str, catalogue: &Catalogue) -> Result<Scene, SceneError> {
    let spec = parse_scene_file(file, text)?;
    Scene::new(file, spec, catalogue)
}

/// The TOML text of a built-in scene.
pub fn builtin_text(name: &str) -> Option<&'static str> {
    BUILTIN.iter().find(|(n, _)| *n == name).map(|(_, t)| *t)
}

/// Load a scene from a file path or a built-in name: an argument ending in `.toml`, or naming
/// an existing file, is read from disk; anything else must be a built-in name.
///
/// # Errors
/// A directory, an unreadable file, an unknown built-in name, or any [`SceneError`] of the
/// scene.
pub fn load(arg: &str, catalogue: &Catalogue) -> Result<Scene, SceneError> {
    let path = std::path::Path::new(arg);
    if path.is_dir() {
        return Err(SceneError::new(
            arg,
            "",
            "is a directory, not a scene file: name the `.toml` files in it (e.g. `hj run DIR/*.toml`)",
        ));
    }
    if arg.ends_with(".toml") || path.is_file() {
        let text = std::fs::read_to_string(path)
            .map_err(|e| SceneError::new(arg, "", format!("cannot read the scene file: {e}")))?;
        return parse(arg, &text, catalogue);
    }
    match builtin_text(arg) {
        Some(text) => parse(&format!("built-in scene {arg}"), text, catalogue),
        None => {
            let names: Vec<&str> = BUILTIN.iter().map(|(n, _)| *n).collect();
            Err(SceneError::new(
                arg,
                "",
                format!(
                    "no such file, and not a built-in scene (built-in: {})",
                    names.join(", ")
                ),
            ))
        }
    }
}

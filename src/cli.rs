//! The `hj` command line as a library: [`cli_main`](crate::cli::cli_main) runs it on any
//! [`Catalogue`](crate::scene::Catalogue), so that a
//! five-line binary gives systems of one's own the whole command line — `list`, `show`, `run`,
//! `reproduce`, `plot`, `new` — and scene files in TOML:
//!
//! ```no_run
//! use hamilton_jacobi::scene::{Catalogue, HamiltonianCase};
//! use hamilton_jacobi::{hamiltonian, nalgebra::SVector};
//!
//! hamiltonian!(Duffing<1> |_s, _t, q, p| kinetic = p[0] * p[0] * 0.5,
//!     potential = q[0] * q[0] * 0.5 + q[0].powi(4) * 0.25);
//!
//! fn main() -> std::process::ExitCode {
//!     let mut catalogue = Catalogue::builtin();
//!     catalogue.register("duffing", "Duffing oscillator", Box::new(|s| {
//!         let q = s.or("amplitude", 1.0)?;
//!         let case = HamiltonianCase::new(Duffing, SVector::from([q]), SVector::from([0.0]), "Duffing")
//!             .map_err(|e| s.library(e))?;
//!         Ok(Box::new(case))
//!     }));
//!     hamilton_jacobi::cli::cli_main(catalogue)
//! }
//! ```
//!
//! `examples/cli_user_system.rs` is a complete program of this kind.
//!
//! The subcommands:
//! * no subcommand — the built-in showcase: a few scenes, tables on stdout, figures and their
//!   data under `out/`;
//! * `list` — built-in scenes, systems of the catalogue and method kinds, each with a
//!   description;
//! * `show <name>` — the TOML of a built-in scene (a starting point for your own);
//! * `new <scene>` — a commented scene template written to `<scene>.toml`;
//! * `run <scene.toml | built-in name>...` — run scenes;
//! * `reproduce` — every built-in scene: all tables and figures the paper uses;
//! * `plot <figure.csv | figure.npy>...` — redraw figures from their data files.
//!
//! Figures are written as SVG and PNG (PDF with `--format svg,png,pdf`), each with its data
//! (`.csv`) and caption (`.caption.txt`); `--width`, `--height`, `--font-size`, `--dpi`,
//! `--format` and `--data` override the scenes' `[output]`.
//!
//! Exit codes: 0 success, 1 a run failed, 2 a bad command line or scene.

use crate::plot;
use crate::scene::spec::{Length, OutputSpec};
use crate::scene::{
    self, Catalogue, FigureOptions, FigureSetup, MethodKind, RunOptions, Scene, SceneError,
};
use crate::workprecision::Timing;
use clap::{Parser, Subcommand};
use std::ffi::OsString;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::{Duration, Instant};

/// Analytical dynamics: Hamilton–Jacobi theory, canonical transformations, perturbation
/// theory and integrators, measured against exact solutions on one error-versus-cost axis.
///
/// With no subcommand, runs the built-in showcase (Kepler e = 0.5, the pendulum near its
/// separatrix, a J2-perturbed orbit, the heavy top, the transformation gallery).
#[derive(Parser, Debug)]
#[command(name = "hj", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Output directory: tables under OUT/tables, figures under OUT/figures.
    #[arg(long, global = true, default_value = "out")]
    out: PathBuf,
    /// Least wall time per timed sample, in milliseconds (the fastest of the repeats counts).
    #[arg(long, global = true, default_value_t = 20)]
    min_time_ms: u64,
    /// No progress bars.
    #[arg(long, global = true)]
    quiet: bool,
    /// Figure width: a length with its unit (3.4in, 8.6cm, 86mm, 245pt, 1020px at --dpi) or
    /// inches.
    #[arg(long, global = true, allow_hyphen_values = true)]
    width: Option<String>,
    /// Figure height, as --width.
    #[arg(long, global = true, allow_hyphen_values = true)]
    height: Option<String>,
    /// Base font size of figures in points (tick labels, legend).
    #[arg(long, global = true, allow_hyphen_values = true)]
    font_size: Option<f64>,
    /// Resolution of PNG figures in dots per inch.
    #[arg(long, global = true, allow_hyphen_values = true)]
    dpi: Option<f64>,
    /// Figure formats, comma-separated: svg, png, pdf (SVG is always written).
    #[arg(long, global = true, value_delimiter = ',')]
    format: Option<Vec<String>>,
    /// Data beside each figure: csv (every point in the table) or npy (points in a NumPy file).
    #[arg(long, global = true)]
    data: Option<String>,
}

impl Cli {
    /// The figure options given on the command line.
    fn figures(&self) -> FigureOptions {
        FigureOptions {
            width: self.width.clone(),
            height: self.height.clone(),
            font_size: self.font_size,
            dpi: self.dpi,
            formats: self.format.clone(),
            data: self.data.clone(),
        }
    }
}

#[derive(Subcommand, Debug)]
enum Command {
    /// List the built-in scenes, the systems of the catalogue and the method kinds.
    List,
    /// Print the TOML of a built-in scene.
    Show {
        /// Built-in scene name.
        name: String,
    },
    /// Run scene files or built-in scenes.
    Run {
        /// Scene files (`*.toml`) or built-in scene names.
        #[arg(required = true)]
        scenes: Vec<String>,
    },
    /// Regenerate every table and figure the paper uses (all built-in scenes).
    Reproduce,
    /// Write a commented scene template, SCENE.toml, to start a scene of your own from.
    New {
        /// Scene name (the file is SCENE.toml unless SCENE already ends in `.toml`).
        scene: String,
        /// Replace an existing file.
        #[arg(long)]
        force: bool,
    },
    /// Redraw figures from their data files (`*.csv` written beside every figure, or the
    /// `*.npy` beside one), with the size, font and format options given here (default: as
    /// recorded in the file).
    Plot {
        /// Data files of figures (`.csv`, or the `.npy` file beside one).
        #[arg(required = true, value_name = "DATA")]
        files: Vec<PathBuf>,
        /// Output file stem (one data file only): writes STEM.svg, STEM.png, …; default: the
        /// data file's stem, beside it.
        #[arg(long = "to")]
        to: Option<PathBuf>,
    },
}

enum Failure {
    /// A bad scene or command line (exit code 2).
    Usage(String),
    /// A run failed (exit code 1).
    Run(String),
}

/// Write a line to stdout; a closed pipe (`hj list | head`) ends the program quietly.
fn out(text: &str) {
    use std::io::Write;
    let mut o = std::io::stdout().lock();
    if let Err(e) = writeln!(o, "{text}") {
        if e.kind() == std::io::ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
        eprintln!("hj: cannot write to stdout: {e}");
        std::process::exit(1);
    }
}

fn scene_error(e: SceneError) -> Failure {
    Failure::Usage(e.to_string())
}

fn run_scenes(names: &[String], cli: &Cli, catalogue: &Catalogue) -> Result<(), Failure> {
    // Check every scene before running any: a typo in the last file fails at once.
    let scenes: Vec<Scene> = names
        .iter()
        .map(|n| scene::load(n, catalogue))
        .collect::<Result<_, _>>()
        .map_err(scene_error)?;
    let mut seen = std::collections::BTreeSet::new();
    for s in &scenes {
        if !seen.insert(s.name().to_string()) {
            return Err(Failure::Usage(format!(
                "two scenes are named `{}`: their outputs would overwrite each other",
                s.name()
            )));
        }
    }
    let opts = RunOptions {
        out: cli.out.clone(),
        timing: Timing {
            min_time: Duration::from_millis(cli.min_time_ms),
            max_runs: 1000,
        },
        progress: !cli.quiet,
        figures: cli.figures(),
    };
    let start = Instant::now();
    let mut written = 0;
    for s in scenes {
        let t = Instant::now();
        let name = s.name().to_string();
        let summary = s.run(&opts).map_err(|e| Failure::Run(e.to_string()))?;
        out(&summary.markdown);
        for f in &summary.files {
            out(&format!("wrote {}", f.display()));
        }
        out(&format!("({name}: {:.1} s)\n", t.elapsed().as_secs_f64()));
        written += summary.files.len();
    }
    eprintln!(
        "hj: {} scene(s), {written} file(s) under {}, {:.1} s",
        names.len(),
        cli.out.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

/// `hj plot`: redraw each figure from its data file.
fn plot_data(files: &[PathBuf], to: Option<&PathBuf>, cli: &Cli) -> Result<(), Failure> {
    if to.is_some() && files.len() > 1 {
        return Err(Failure::Usage(
            "--to names one output: give one data file".to_string(),
        ));
    }
    for file in files {
        let mut fig = plot::data::read(file)
            .map_err(|e| Failure::Usage(format!("{}: {e}", file.display())))?;
        // The recorded size, overridden by the command line; formats default to SVG and PNG.
        let recorded = OutputSpec {
            width: Some(Length::Inches(fig.size.width)),
            height: Some(Length::Inches(fig.size.height)),
            font_size: Some(fig.size.font_size),
            dpi: Some(fig.size.dpi),
            ..OutputSpec::default()
        };
        let setup = FigureSetup::new(&file.display().to_string(), &recorded, &cli.figures())
            .map_err(scene_error)?;
        fig.size = setup.size;
        let (formats, data) = (setup.formats, setup.data);
        let stem = match to {
            Some(t) => t.clone(),
            None => file.with_extension(""),
        };
        // Redrawn in place, the data file is rewritten with the same points.
        let written = fig
            .write(&stem, &formats, data)
            .map_err(|e| Failure::Run(format!("{}: {e}", file.display())))?;
        for w in written {
            out(&format!("wrote {}", w.display()));
        }
    }
    Ok(())
}

fn list(catalogue: &Catalogue) {
    out("Built-in scenes (hj run <name>; hj show <name> prints the TOML):");
    for (name, text) in scene::BUILTIN {
        let title = scene::parse(name, text, catalogue)
            .map(|s| s.title().to_string())
            .unwrap_or_else(|e| format!("(invalid: {e})"));
        let star = if scene::SHOWCASE.contains(&name) {
            "*"
        } else {
            " "
        };
        out(&format!("  {star} {name:<26} {title}"));
    }
    out("  (* part of the showcase that `hj` runs with no arguments)\n");
    out("Systems ([system] name = ...):");
    for (name, description) in catalogue.list() {
        out(&format!("    {name:<26} {description}"));
    }
    out("\nMethods and theories ([[method]] kind = ..., with its knob):");
    for k in MethodKind::all() {
        let knob = match k.knob().key() {
            "" => "—".to_string(),
            key => key.to_string(),
        };
        out(&format!(
            "    {:<26} {:<7} {}",
            k.key(),
            knob,
            k.description()
        ));
    }
}

/// The commented scene template of `hj new`, with `{name}` standing for the scene's name.
pub const SCENE_TEMPLATE: &str = include_str!("scene/template.toml");

/// The scene template of `hj new` for a scene called `name`.
pub fn scene_template(name: &str) -> String {
    SCENE_TEMPLATE.replace("{name}", name)
}

/// `hj new`: write the template to `scene` (`.toml` appended unless present); an existing file
/// is kept unless `force`.
fn new_scene(scene: &str, force: bool, catalogue: &Catalogue) -> Result<(), Failure> {
    let path = if scene.ends_with(".toml") {
        PathBuf::from(scene)
    } else {
        PathBuf::from(format!("{scene}.toml"))
    };
    let name = path
        .file_stem()
        .and_then(|s| s.to_str())
        .filter(|s| !s.is_empty() && !s.starts_with('.'))
        .ok_or_else(|| Failure::Usage(format!("{scene}: not a usable scene name")))?;
    let text = scene_template(name);
    // The template must be a scene this catalogue runs (a catalogue without the pendulum, of a
    // user's own binary, still gets the file, with the note).
    if let Err(e) = scene::parse(&path.display().to_string(), &text, catalogue) {
        eprintln!("hj: note: the template's system is not in this catalogue ({e}); edit [system]");
    }
    if path.exists() && !force {
        return Err(Failure::Usage(format!(
            "{}: exists; choose another name or pass --force to replace it",
            path.display()
        )));
    }
    write_new(&path, &text)
        .map_err(|e| Failure::Run(format!("{}: cannot write: {e}", path.display())))?;
    out(&format!(
        "wrote {} (run it with `hj run {}`)",
        path.display(),
        path.display()
    ));
    Ok(())
}

fn write_new(path: &Path, text: &str) -> std::io::Result<()> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)?;
    }
    std::fs::write(path, text)
}

/// Run the `hj` command line on `catalogue`, with the arguments of this process.
///
/// Parses the command line ([`std::env::args_os`]), runs the subcommand and returns the exit
/// code: 0 success, 1 a run failed, 2 a bad command line or scene (with one line on stderr).
/// Built-in scenes whose system is missing from `catalogue` are listed as invalid by `hj list`.
pub fn cli_main(catalogue: Catalogue) -> ExitCode {
    cli_main_from(catalogue, std::env::args_os())
}

/// [`cli_main`] with the arguments given, the first being the program name (as
/// [`std::env::args_os`] gives them).
pub fn cli_main_from<I, T>(catalogue: Catalogue, args: I) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => {
            // --help and --version print to stdout and succeed; usage errors exit 2.
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::from(2)
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let catalogue = &catalogue;
    let result = match &cli.command {
        None => run_scenes(&scene::SHOWCASE.map(String::from), &cli, catalogue),
        Some(Command::List) => {
            list(catalogue);
            Ok(())
        }
        Some(Command::Show { name }) => match scene::builtin_text(name) {
            Some(text) => {
                out(text.trim_end_matches('\n'));
                Ok(())
            }
            None => Err(Failure::Usage(format!(
                "{name}: not a built-in scene (see `hj list`)"
            ))),
        },
        Some(Command::New { scene, force }) => new_scene(scene, *force, catalogue),
        Some(Command::Run { scenes }) => run_scenes(scenes, &cli, catalogue),
        Some(Command::Plot { files, to }) => plot_data(files, to.as_ref(), &cli),
        Some(Command::Reproduce) => {
            let all: Vec<String> = scene::BUILTIN.iter().map(|(n, _)| n.to_string()).collect();
            run_scenes(&all, &cli, catalogue)
        }
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(Failure::Usage(m)) => {
            eprintln!("hj: {m}");
            ExitCode::from(2)
        }
        Err(Failure::Run(m)) => {
            eprintln!("hj: {m}");
            ExitCode::from(1)
        }
    }
}

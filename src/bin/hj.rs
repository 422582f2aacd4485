//! `hj`: the hamilton-jacobi command line.
//!
//! * `hj` — the built-in showcase: a few scenes, tables on stdout, CSV and SVG under `out/`;
//! * `hj list` — built-in scenes, systems and method kinds;
//! * `hj show <name>` — the TOML of a built-in scene (a starting point for your own);
//! * `hj run <scene.toml | built-in name>...` — run scenes;
//! * `hj reproduce` — every built-in scene: all tables and figures the paper uses;
//! * `hj plot <figure.csv | figure.npy>...` — redraw figures from their data files.
//!
//! Figures are written as SVG and PNG (PDF with `--format svg,png,pdf`), each with its data
//! (`.csv`) and caption (`.caption.txt`); `--width`, `--height`, `--font-size`, `--dpi`,
//! `--format` and `--data` override the scenes' `[output]`.
//!
//! Exit codes: 0 success, 1 a run failed, 2 a bad command line or scene.

use clap::{Parser, Subcommand};
use hamilton_jacobi::plot;
use hamilton_jacobi::scene::spec::{Length, OutputSpec};
use hamilton_jacobi::scene::{
    self, Catalogue, FigureOptions, FigureSetup, MethodKind, RunOptions, Scene, SceneError,
};
use hamilton_jacobi::workprecision::Timing;
use std::path::PathBuf;
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

fn run_scenes(names: &[String], cli: &Cli) -> Result<(), Failure> {
    let catalogue = Catalogue::builtin();
    // Check every scene before running any: a typo in the last file fails at once.
    let scenes: Vec<Scene> = names
        .iter()
        .map(|n| scene::load(n, &catalogue))
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

fn list() {
    out("Built-in scenes (hj run <name>; hj show <name> prints the TOML):");
    let catalogue = Catalogue::builtin();
    for (name, text) in scene::BUILTIN {
        let title = scene::parse(name, text, &catalogue)
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

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        None => run_scenes(&scene::SHOWCASE.map(String::from), &cli),
        Some(Command::List) => {
            list();
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
        Some(Command::Run { scenes }) => run_scenes(scenes, &cli),
        Some(Command::Plot { files, to }) => plot_data(files, to.as_ref(), &cli),
        Some(Command::Reproduce) => {
            let all: Vec<String> = scene::BUILTIN.iter().map(|(n, _)| n.to_string()).collect();
            run_scenes(&all, &cli)
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

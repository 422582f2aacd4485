//! `hj`: the hamilton-jacobi command line.
//!
//! * `hj` — the built-in showcase: a few scenes, tables on stdout, CSV and SVG under `out/`;
//! * `hj list` — built-in scenes, systems and method kinds;
//! * `hj show <name>` — the TOML of a built-in scene (a starting point for your own);
//! * `hj run <scene.toml | built-in name>...` — run scenes;
//! * `hj reproduce` — every built-in scene: all tables and figures the paper uses.
//!
//! Exit codes: 0 success, 1 a run failed, 2 a bad command line or scene.

use clap::{Parser, Subcommand};
use hamilton_jacobi::scene::{self, Catalogue, MethodKind, RunOptions, Scene, SceneError};
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

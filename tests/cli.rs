//! The `hj` binary: help, listing, exit codes, one-line errors on stderr, outputs under `--out`.
#![cfg(feature = "cli")]

use std::path::PathBuf;
use std::process::{Command, Output};

fn hj(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_hj"))
        .args(args)
        .output()
        .expect("run hj")
}

fn temp_dir(tag: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("hj-cli-test-{tag}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn help_lists_the_subcommands() {
    let o = hj(&["--help"]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    for word in ["list", "show", "run", "reproduce", "--out"] {
        assert!(text.contains(word), "--help lacks {word}:\n{text}");
    }
}

#[test]
fn list_and_show() {
    let o = hj(&["list"]);
    assert!(o.status.success());
    let text = String::from_utf8(o.stdout).unwrap();
    assert!(text.contains("kepler-e0.99"));
    // Every method of the table, by key with its label.
    for m in &hamilton_jacobi::integrate::METHODS {
        let line = text
            .lines()
            .find(|l| l.split_whitespace().next() == Some(m.key))
            .unwrap_or_else(|| panic!("hj list lacks {}:\n{text}", m.key));
        assert!(line.contains(&m.label()), "{line}");
    }
    let o = hj(&["show", "heavy-top"]);
    assert!(o.status.success());
    assert!(String::from_utf8(o.stdout)
        .unwrap()
        .contains("name = \"heavy-top\""));
    let o = hj(&["show", "no-such-scene"]);
    assert_eq!(o.status.code(), Some(2));
}

#[test]
fn bad_scene_exits_2_with_one_line() {
    let dir = temp_dir("bad");
    let path = dir.join("bad.toml");
    std::fs::write(
        &path,
        "[system]\nname = \"kepler\"\neccentricity = 0.5\n[span]\nperiods = -1\n",
    )
    .unwrap();
    let o = hj(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8(o.stderr).unwrap();
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("bad.toml: span.periods:"), "{err}");
    let o = hj(&["run", "missing-file.toml"]);
    assert_eq!(o.status.code(), Some(2));
    let o = hj(&["frobnicate"]);
    assert_eq!(o.status.code(), Some(2));
    std::fs::remove_dir_all(&dir).ok();
}

/// Run a one-period pendulum scene with a work-precision figure in `dir`: the scene file, the
/// output directory and the run's output.
fn run_tiny(dir: &std::path::Path) -> (PathBuf, PathBuf, Output) {
    let path = dir.join("tiny.toml");
    std::fs::write(
        &path,
        "[system]\nname = \"pendulum\"\namplitude = 1.0\n[span]\nperiods = 1\n\
         [[method]]\nkind = \"verlet-kdk\"\nsteps = [50, 100]\n[output]\nwork_precision = true\n",
    )
    .unwrap();
    let out = dir.join("results");
    let o = hj(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--min-time-ms",
        "0",
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    (path, out, o)
}

#[test]
fn run_writes_under_out() {
    let dir = temp_dir("run");
    let (_, out, o) = run_tiny(&dir);
    for f in [
        "tables/tiny.md",
        "tables/tiny.csv",
        "figures/tiny-work-precision.svg",
    ] {
        assert!(out.join(f).is_file(), "{f} not written");
    }
    let stdout = String::from_utf8(o.stdout).unwrap();
    assert!(stdout.contains("Störmer–Verlet"), "{stdout}");
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn plot_redraws_a_figure_from_its_data_file() {
    let dir = temp_dir("plot");
    let (path, out, _) = run_tiny(&dir);
    let csv = out.join("figures/tiny-work-precision.csv");
    let svg = std::fs::read_to_string(out.join("figures/tiny-work-precision.svg")).unwrap();
    // Redrawn elsewhere at the recorded size: the same drawing.
    let again = dir.join("again");
    let o = hj(&[
        "plot",
        csv.to_str().unwrap(),
        "--to",
        again.to_str().unwrap(),
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert_eq!(std::fs::read_to_string(dir.join("again.svg")).unwrap(), svg);
    // At column width, as PDF too.
    let column = dir.join("column");
    let o = hj(&[
        "plot",
        csv.to_str().unwrap(),
        "--to",
        column.to_str().unwrap(),
        "--width",
        "3.4in",
        "--height",
        "2.4in",
        "--font-size",
        "8",
        "--format",
        "svg,pdf",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(std::fs::read_to_string(dir.join("column.svg"))
        .unwrap()
        .contains("width=\"3.4in\""));
    assert!(std::fs::read(dir.join("column.pdf"))
        .unwrap()
        .starts_with(b"%PDF"));
    // A file that is not a figure's data: a usage error, not a panic.
    let o = hj(&["plot", path.to_str().unwrap()]);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn duplicate_scene_names_and_closed_pipes() {
    let o = hj(&["run", "heavy-top", "heavy-top", "--quiet"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8(o.stderr).unwrap().contains("overwrite"));
    // `hj list | head -1`: a closed stdout ends the program quietly, without a panic.
    let mut child = Command::new(env!("CARGO_BIN_EXE_hj"))
        .arg("list")
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let o = child.wait_with_output().unwrap();
    assert_eq!(
        o.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
}

/// Write `text` as `<dir>/<file>` and run it; the exit code, stderr and the elapsed time.
fn run_scene(dir: &std::path::Path, file: &str, text: &str) -> (Option<i32>, String, f64) {
    let path = dir.join(file);
    std::fs::write(&path, text).unwrap();
    let t = std::time::Instant::now();
    let o = hj(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        dir.join("out").to_str().unwrap(),
        "--quiet",
        "--min-time-ms",
        "0",
    ]);
    (
        o.status.code(),
        String::from_utf8(o.stderr).unwrap(),
        t.elapsed().as_secs_f64(),
    )
}

/// Every refusal is one line on stderr with exit code 2, printed before anything runs.
fn assert_refused(dir: &std::path::Path, file: &str, text: &str, words: &[&str]) {
    let (code, err, secs) = run_scene(dir, file, text);
    assert_eq!(code, Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    for w in words {
        assert!(err.contains(w), "{err} lacks {w:?}");
    }
    // Numbers in exponent notation: no run of zeros from a huge or tiny magnitude.
    assert!(!err.contains("0000000000"), "{err}");
    assert!(err.len() < 500, "{} bytes: {err}", err.len());
    assert!(secs < 10.0, "{secs} s before the refusal");
    assert!(!dir.join("out").exists(), "a refused scene wrote files");
}

const KEPLER: &str = "[system]\nname = \"kepler\"\neccentricity = 0.5\n[span]\nperiods = 1\n";

#[test]
fn hostile_scenes_exit_2_at_once() {
    let dir = temp_dir("hostile");
    let dop = format!("{KEPLER}[[method]]\nkind = \"dop853\"\nrtol = [1e-8]\n");
    // A history of a method the scene does not run.
    assert_refused(
        &dir,
        "portrait.toml",
        &format!("{dop}[output]\nphase_portrait = [{{ method = \"rk4\", steps = 100 }}]\n"),
        &["output.phase_portrait[0].method", "rk4", "(dop853)"],
    );
    // The reference's phase is lost after 10¹⁵ periods (it reported a 1e31 "error").
    assert_refused(
        &dir,
        "periods.toml",
        &dop.replace("periods = 1", "periods = 1e15"),
        &["span.periods", "phase is lost"],
    );
    // 10³⁰⁰ time units of DOP853 (it ran 17 s and printed the time with 300 digits).
    assert_refused(
        &dir,
        "time.toml",
        &dop.replace("periods = 1", "time = 1e300"),
        &["span.time", "phase is lost"],
    );
    // Within the phase bound, beyond DOP853's step limit.
    assert_refused(
        &dir,
        "steps.toml",
        &dop.replace("periods = 1", "periods = 1e8"),
        &["span.periods", "DOP853", "step"],
    );
    // A 5000-character name (it failed writing the files, exit 1).
    let long = "n".repeat(5000);
    assert_refused(
        &dir,
        "long.toml",
        &format!("name = \"{long}\"\n{dop}"),
        &["name", "too long"],
    );
    // No method (it wrote an empty table).
    assert_refused(&dir, "none.toml", KEPLER, &["method", "runs no method"]);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn running_a_directory_says_it_is_a_directory() {
    let dir = temp_dir("directory");
    let o = hj(&["run", dir.to_str().unwrap(), "--quiet"]);
    assert_eq!(o.status.code(), Some(2));
    let err = String::from_utf8(o.stderr).unwrap();
    assert!(err.contains("is a directory"), "{err}");
    assert!(!err.contains("no such file"), "{err}");
    let toml_dir = dir.join("scenes.toml");
    std::fs::create_dir_all(&toml_dir).unwrap();
    let o = hj(&["run", toml_dir.to_str().unwrap(), "--quiet"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8(o.stderr)
        .unwrap()
        .contains("is a directory"));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn new_writes_a_commented_template_that_runs() {
    let dir = temp_dir("new");
    let stem = dir.join("my-scene");
    let o = hj(&["new", stem.to_str().unwrap()]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let path = dir.join("my-scene.toml");
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("name = \"my-scene\""), "{text}");
    assert!(text.lines().filter(|l| l.starts_with('#')).count() >= 3);
    // The template is a scene the built-in catalogue runs.
    let out = dir.join("out");
    let o = hj(&[
        "run",
        path.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(out.join("tables/my-scene.md").exists());
    // An existing file is kept unless --force.
    let o = hj(&["new", path.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--force"));
    let o = hj(&["new", path.to_str().unwrap(), "--force"]);
    assert!(o.status.success());
    // No usable name, or a place that cannot be written: one line, no panic.
    let o = hj(&["new", dir.join(".toml").to_str().unwrap()]);
    assert_eq!(
        o.status.code(),
        Some(2),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    let o = hj(&["new", "/proc/no-such-dir/scene"]);
    assert_eq!(
        o.status.code(),
        Some(1),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    assert_eq!(String::from_utf8_lossy(&o.stderr).lines().count(), 1);
}

#[allow(dead_code)]
#[path = "../examples/cli_user_system.rs"]
mod user_system;

#[test]
fn a_user_system_registered_through_cli_main_runs_a_scene() {
    use hamilton_jacobi::cli::cli_main_from;
    use std::process::ExitCode;
    let dir = temp_dir("user");
    let scene = dir.join("duffing.toml");
    std::fs::write(
        &scene,
        "[system]\nname = \"duffing\"\nbeta = 0.5\namplitude = 1.2\n[span]\ntime = 20\n\
         [[method]]\nkind = \"verlet-kdk\"\nsteps = [400, 800]\n\
         [[method]]\nkind = \"dop853\"\nrtol = [1e-10]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let args = [
        "hj",
        "run",
        scene.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--quiet",
    ];
    let code = cli_main_from(user_system::catalogue(), args);
    assert_eq!(format!("{code:?}"), format!("{:?}", ExitCode::SUCCESS));
    let table = std::fs::read_to_string(out.join("tables/duffing.md")).unwrap();
    assert!(table.contains("Duffing oscillator"), "{table}");
    // Verlet's error falls by 4 when the step halves: over t = 20 at h = 0.05 the phase error
    // (≈ h²ω³t/24 ≈ 2e-3) is small, so the final position error is q̇(t)·δt ∝ h² to O(h⁴).
    let errors: Vec<f64> = table
        .lines()
        .filter(|l| l.contains("Störmer–Verlet") && l.contains("steps ="))
        .map(|l| l.split('|').nth(3).unwrap().trim().parse::<f64>().unwrap())
        .collect();
    assert_eq!(errors.len(), 2, "{table}");
    let ratio = errors[0] / errors[1];
    assert!(
        (ratio - 4.0).abs() < 0.4,
        "Verlet error ratio {ratio}:\n{table}"
    );
    // An unknown key of the user's system is refused with the keys it takes.
    std::fs::write(&scene, "[system]\nname = \"duffing\"\ngamma = 1\n[span]\ntime = 1\n[[method]]\nkind = \"rk4\"\nsteps = [10]\n").unwrap();
    let code = cli_main_from(
        user_system::catalogue(),
        ["hj", "run", scene.to_str().unwrap()],
    );
    assert_eq!(format!("{code:?}"), format!("{:?}", ExitCode::from(2)));
}

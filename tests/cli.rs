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
    assert!(text.contains("kepler-e0.99") && text.contains("sofroniou-spaletta10"));
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

#[test]
fn run_writes_under_out() {
    let dir = temp_dir("run");
    let path = dir.join("tiny.toml");
    std::fs::write(
        &path,
        "[system]\nname = \"pendulum\"\namplitude = 1.0\n[span]\nperiods = 1\n\
         [[method]]\nkind = \"verlet\"\nsteps = [50, 100]\n[output]\nwork_precision = true\n",
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

//! `[sweep]` in scene files: one number of `[system]` varied, every method's final error
//! against it, run on every core with results independent of the thread count.
#![cfg(feature = "cli")]

mod common;

use hamilton_jacobi::scene::parameter_sweep::{run_sweep, sweep_values, SweepPoint};
use hamilton_jacobi::scene::{self, parse_scene_file, Catalogue, MethodKind};

const PENDULUM_SWEEP: &str = r#"
name = "pendulum-sweep"
[system]
name = "pendulum"
amplitude = 1.0
[span]
periods = 5.25
[[method]]
kind = "verlet-kdk"
steps = [500, 1000]
[[method]]
kind = "dop853"
rtol = [1e-11]
[sweep]
key = "amplitude"
from = 0.2
to = 2.5
samples = 8
log = true
[output]
table = true
"#;

fn sweep_in_pool(threads: usize) -> (Vec<f64>, Vec<SweepPoint>) {
    let spec = parse_scene_file("s.toml", PENDULUM_SWEEP).unwrap();
    let sw = spec.sweep.clone().unwrap();
    let values = sweep_values("s.toml", &spec, &sw).unwrap();
    let knobs = vec![vec![500.0, 1000.0], vec![1e-11]];
    let catalogue = Catalogue::builtin();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let points = pool
        .install(|| run_sweep("s.toml", &spec, &sw, &values, &knobs, &catalogue, &|| {}))
        .unwrap();
    (values, points)
}

/// The values of a log range: geometric, ends exact.
#[test]
fn a_log_range_is_geometric_with_exact_ends() {
    let (values, _) = sweep_in_pool(1);
    assert_eq!(values.len(), 8);
    assert_eq!(values[0], 0.2);
    assert_eq!(values[7], 2.5);
    let ratio = (2.5f64 / 0.2).powf(1.0 / 7.0);
    for w in values.windows(2) {
        assert!((w[1] / w[0] - ratio).abs() < 1e-14 * ratio);
    }
}

/// One thread or two: the same errors, bit for bit, in the order of the values; and each is the
/// error of the same run made directly on the system built at that value (the value reached the
/// system), with Verlet's second order visible at every amplitude below the separatrix.
#[test]
fn sweeps_are_bitwise_independent_of_threads_and_reach_the_system() {
    let (values, serial) = sweep_in_pool(1);
    let (_, parallel) = sweep_in_pool(2);
    assert_eq!(serial, parallel);
    let catalogue = Catalogue::builtin();
    let verlet = MethodKind::from_key("verlet-kdk").unwrap();
    for (p, &v) in serial.iter().zip(&values) {
        assert_eq!(p.value, v);
        let mut table = toml::Table::new();
        table.insert("name".into(), "pendulum".into());
        table.insert("amplitude".into(), v.into());
        let mut case = catalogue.build("direct", &table).unwrap();
        case.prepare(5.25 * case.period().unwrap()).unwrap();
        let direct = case.run(verlet, 1000.0).unwrap().error;
        assert_eq!(p.runs[1].error, Ok(direct), "amplitude {v}");
        // Fixed steps per period: the error at 500 steps is 4× that at 1000 (order 2), to the
        // O(h²) relative correction of the asymptotic constant (h ≤ T/500). The span ends a
        // quarter period past a whole number of periods, where q̇ is largest, so the final
        // position error is q̇·δt ∝ h² (at a turning point it would be ½q̈δt² ∝ h⁴).
        let (e500, e1000) = (p.runs[0].error.clone().unwrap(), direct);
        let ratio = e500 / e1000;
        assert!((ratio - 4.0).abs() < 0.5, "amplitude {v}: ratio {ratio}");
        // DOP853 at rtol 1e-11 against the exact elliptic-function solution: far below Verlet's
        // O(h²) error at h = T/1000.
        let dop = p.runs[2].error.clone().unwrap();
        assert!(
            dop < 1e-3 * e1000,
            "amplitude {v}: DOP853 {dop:e}, Verlet {e1000:e}"
        );
    }
}

/// The scene runs through the runner: a figure and a table section of the sweep.
#[test]
fn a_scene_with_a_sweep_writes_its_figure_and_table() {
    let dir = std::env::temp_dir().join(format!("hj-sweep-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let catalogue = Catalogue::builtin();
    let s = scene::parse("s.toml", PENDULUM_SWEEP, &catalogue).unwrap();
    let planned = s.planned_outputs();
    assert!(planned
        .iter()
        .any(|p| p.to_string_lossy().contains("pendulum-sweep-sweep")));
    let summary = s.run(&common::quick(&dir)).unwrap();
    assert!(
        summary.markdown.contains("### Sweep of system.amplitude"),
        "{}",
        summary.markdown
    );
    let rows = summary
        .markdown
        .lines()
        .skip_while(|l| !l.starts_with("### Sweep"))
        .filter(|l| l.starts_with("| ") && !l.starts_with("| amplitude"))
        .count();
    assert_eq!(rows, 8);
    assert!(dir.join("figures/pendulum-sweep-sweep.svg").exists());
    assert!(dir.join("figures/pendulum-sweep-sweep.csv").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad sweeps are refused when the scene is loaded, naming the key (and the value).
#[test]
fn bad_sweeps_name_the_key() {
    let catalogue = Catalogue::builtin();
    let with = |sweep: &str| {
        let text = PENDULUM_SWEEP.replace(
            "[sweep]\nkey = \"amplitude\"\nfrom = 0.2\nto = 2.5\nsamples = 8\nlog = true\n",
            sweep,
        );
        assert_ne!(text, PENDULUM_SWEEP);
        match scene::parse("s.toml", &text, &catalogue) {
            Ok(_) => panic!("accepted: {sweep}"),
            Err(e) => e.to_string(),
        }
    };
    let cases: [(&str, &[&str]); 9] = [
        (
            "[sweep]\nkey = \"n\"\nvalues = [1.0]\n",
            &["not a key of [system]", "amplitude"],
        ),
        (
            "[sweep]\nkey = \"name\"\nvalues = [1.0]\n",
            &["name cannot be swept"],
        ),
        ("[sweep]\nkey = \"amplitude\"\n", &["give either"]),
        (
            "[sweep]\nkey = \"amplitude\"\nvalues = []\n",
            &["1..=10000"],
        ),
        (
            "[sweep]\nkey = \"amplitude\"\nvalues = [1.0, nan]\n",
            &["values[1]", "finite"],
        ),
        (
            "[sweep]\nkey = \"amplitude\"\nfrom = -1.0\nto = 1.0\nsamples = 3\nlog = true\n",
            &["positive ends"],
        ),
        (
            "[sweep]\nkey = \"amplitude\"\nfrom = 0.1\nto = 1.0\nsamples = 100000\n",
            &["2..=10000"],
        ),
        (
            "[sweep]\nkey = \"amplitude\"\nvalues = [1.0, 4.0]\n",
            &["amplitude = 4", "(0, π)"],
        ),
        (
            "[sweep]\nkey = \"amplitude\"\nvalues = [1.0]\nfrom = 1.0\n",
            &["give either"],
        ),
    ];
    for (sweep, words) in cases {
        let e = with(sweep);
        for w in words {
            assert!(e.contains(w), "{sweep}: {e}");
        }
    }
}

/// A dotted key reaches a number inside a table of `[system]`: here a parameter of a system
/// defined by expression, each value's runs equal to those of the system written with it.
#[test]
fn a_dotted_key_sweeps_a_parameter_of_an_expression() {
    let text = r#"
[system]
hamiltonian = "(p_x^2 + p_y^2)/2 + (x^2 + y^2)/2 + lambda*(x^2*y - y^3/3)"
coordinates = ["x", "y"]
parameters = { lambda = 1.0 }
q = [0.0, 0.1]
p = [0.39665266081716044, 0.0]
[span]
time = 20.0
[[method]]
kind = "verlet-kdk"
steps = [400]
[sweep]
key = "parameters.lambda"
values = [0.0, 0.5, 1.0]
"#;
    let spec = parse_scene_file("e.toml", text).unwrap();
    let sw = spec.sweep.clone().unwrap();
    let values = sweep_values("e.toml", &spec, &sw).unwrap();
    let catalogue = Catalogue::builtin();
    let points = run_sweep(
        "e.toml",
        &spec,
        &sw,
        &values,
        &[vec![400.0]],
        &catalogue,
        &|| {},
    )
    .unwrap();
    let verlet = MethodKind::from_key("verlet-kdk").unwrap();
    for (p, &v) in points.iter().zip(&values) {
        let mut table = spec.system.clone();
        let mut parameters = toml::Table::new();
        parameters.insert("lambda".into(), v.into());
        table.insert("parameters".into(), parameters.into());
        let mut case = catalogue.build("direct", &table).unwrap();
        case.prepare(20.0).unwrap();
        assert_eq!(
            p.runs[0].error,
            Ok(case.run(verlet, 400.0).unwrap().error),
            "λ = {v}"
        );
    }
    assert_ne!(points[0].runs[0].error, points[2].runs[0].error);
    // `parameters` itself is a table, not a number.
    let e = scene::parse(
        "e.toml",
        &text.replace("parameters.lambda", "parameters"),
        &catalogue,
    )
    .err()
    .unwrap();
    assert!(e.to_string().contains("not a number"), "{e}");
}

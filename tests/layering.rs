//! The crate in layers: each top-level module of `src/` imports only from its own layer or the
//! layers below it, and the modules of one layer import each other without cycles.
//!
//! ```text
//! core        error, phase, ad, vector_space, implicit, special, series, record
//! mechanics   hamiltonian, lagrangian, brackets, constraints, particles, action
//! models      systems, expression
//! methods     transform, hamilton_jacobi, integrate, perturbation, nonholonomic, stability,
//!             impulse, inverse_problem, chaos, frequency_analysis, least_action
//! harness     workprecision
//! front end   plot, scene, bin
//! ```
//!
//! The test reads every `.rs` file under `src/`, drops comments, and collects the paths
//! `crate::<module>` (and `$crate::<module>` in macros) each file names.

use std::collections::{BTreeMap, BTreeSet};
use std::fs;
use std::path::{Path, PathBuf};

/// The layers, lowest first.
const LAYERS: &[(&str, &[&str])] = &[
    (
        "core",
        &[
            "error",
            "phase",
            "ad",
            "vector_space",
            "implicit",
            "special",
            "series",
            "record",
        ],
    ),
    (
        "mechanics",
        &[
            "hamiltonian",
            "lagrangian",
            "brackets",
            "constraints",
            "particles",
            "action",
        ],
    ),
    ("models", &["systems", "expression"]),
    (
        "methods",
        &[
            "transform",
            "hamilton_jacobi",
            "integrate",
            "perturbation",
            "nonholonomic",
            "impulse",
            "stability",
            "inverse_problem",
            "chaos",
            "frequency_analysis",
            "least_action",
        ],
    ),
    ("harness", &["workprecision"]),
    ("front end", &["plot", "scene", "cli", "bin"]),
];

fn layer_of(module: &str) -> Option<usize> {
    LAYERS.iter().position(|(_, ms)| ms.contains(&module))
}

fn rust_files(dir: &Path, out: &mut Vec<PathBuf>) {
    for entry in fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        if path.is_dir() {
            rust_files(&path, out);
        } else if path.extension().is_some_and(|e| e == "rs") {
            out.push(path);
        }
    }
}

/// The top-level module a file of `src/` belongs to (`None` for `lib.rs`).
fn module_of(src: &Path, file: &Path) -> Option<String> {
    let rel = file.strip_prefix(src).unwrap();
    let first = rel.components().next()?.as_os_str().to_str()?.to_string();
    if first == "lib.rs" {
        return None;
    }
    Some(first.trim_end_matches(".rs").to_string())
}

/// The text of a file without `//` comments (line and doc comments) and string literals'
/// contents are left alone (module paths do not occur in them).
fn code_of(text: &str) -> String {
    text.lines()
        .map(|line| match line.find("//") {
            Some(i) => &line[..i],
            None => line,
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// The modules named as `crate::m` in the code.
fn imports(code: &str) -> BTreeSet<String> {
    let mut out = BTreeSet::new();
    let mut rest = code;
    while let Some(i) = rest.find("crate::") {
        let after = &rest[i + "crate::".len()..];
        let name: String = after
            .chars()
            .take_while(|c| c.is_ascii_alphanumeric() || *c == '_')
            .collect();
        if !name.is_empty() {
            out.insert(name);
        }
        rest = after;
    }
    out
}

#[test]
fn no_module_imports_from_a_layer_above_it_and_no_cycles() {
    let src = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let mut files = Vec::new();
    rust_files(&src, &mut files);
    files.sort();
    let mut graph: BTreeMap<String, BTreeSet<String>> = BTreeMap::new();
    let mut upward = Vec::new();
    let mut unknown = BTreeSet::new();
    for file in &files {
        let Some(module) = module_of(&src, file) else {
            continue;
        };
        let Some(from) = layer_of(&module) else {
            unknown.insert(module.clone());
            continue;
        };
        let code = code_of(&fs::read_to_string(file).unwrap());
        for target in imports(&code) {
            if target == module {
                continue;
            }
            // Re-exports of the crate root (`crate::Error`, `crate::nalgebra`, macros) are not
            // modules of a layer.
            let Some(to) = layer_of(&target) else {
                continue;
            };
            if to > from {
                upward.push(format!(
                    "{} ({}) imports crate::{target} ({})",
                    file.strip_prefix(&src).unwrap().display(),
                    LAYERS[from].0,
                    LAYERS[to].0
                ));
            }
            graph.entry(module.clone()).or_default().insert(target);
        }
    }
    assert!(
        unknown.is_empty(),
        "modules not assigned to a layer: {unknown:?}"
    );
    assert!(upward.is_empty(), "upward imports:\n{}", upward.join("\n"));
    // No cycles between top-level modules (within a layer): depth-first search.
    fn visit(
        m: &str,
        graph: &BTreeMap<String, BTreeSet<String>>,
        stack: &mut Vec<String>,
        done: &mut BTreeSet<String>,
    ) -> Option<Vec<String>> {
        if let Some(i) = stack.iter().position(|s| s == m) {
            let mut cycle = stack[i..].to_vec();
            cycle.push(m.to_string());
            return Some(cycle);
        }
        if done.contains(m) {
            return None;
        }
        stack.push(m.to_string());
        for next in graph.get(m).into_iter().flatten() {
            if let Some(c) = visit(next, graph, stack, done) {
                return Some(c);
            }
        }
        stack.pop();
        done.insert(m.to_string());
        None
    }
    let mut done = BTreeSet::new();
    for m in graph.keys() {
        let mut stack = Vec::new();
        if let Some(cycle) = visit(m, &graph, &mut stack, &mut done) {
            panic!("modules import each other: {}", cycle.join(" → "));
        }
    }
    println!(
        "{} files, {} modules, {} module-to-module imports, none upward, no cycle",
        files.len(),
        graph.len(),
        graph.values().map(|s| s.len()).sum::<usize>()
    );
}

/// The checker itself: an upward import and a comment are told apart.
#[test]
fn the_checker_sees_imports_and_ignores_comments() {
    let code = code_of("use crate::error::Result; // crate::scene\n/// [`crate::plot`]\nfn f() { crate::ad::lift(); }");
    let found = imports(&code);
    assert_eq!(
        found,
        ["ad", "error"].iter().map(|s| s.to_string()).collect()
    );
}

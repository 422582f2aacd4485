//! The MEGNO map of Hénon–Heiles at `E = 1/8`: the mean exponential growth factor of nearby
//! orbits `⟨Y⟩` (Cincotta & Simó 2000) at `t = 10³` over a grid of the surface of section
//! `x = 0` (`p_x > 0` from the energy), each orbit by Störmer–Verlet with its tangent map carrying
//! the deviation vector (`hamilton_jacobi::chaos`), on every core (`rayon`), by
//! [`henon_heiles_megno_map`], the computation of the scene `megno-map`.
//!
//! Invariant tori show `⟨Y⟩ ≈ 2`, stable periodic orbits `⟨Y⟩ ≈ 0` (the island centres), the
//! chaotic sea `⟨Y⟩ ≈ λt/2 ≫ 2`; the colour scale is clipped at 8. Cells outside the energy's
//! allowed region (`p_x² < 0`) and orbits that fail have no value.
//!
//! `cargo run --release --example megno_map [-- N [T [h]]]` (default `N = 512`, `T = 1000`,
//! `h = 0.1`) writes `out/henon-heiles-megno-map.svg`, `.png`, the values of the `N × N` grid as
//! `.npy` (with a CSV header beside it) and the caption, and prints the time taken and the
//! number of threads.

use hamilton_jacobi::plot::{DataFormat, Format};
use hamilton_jacobi::scene::megno::henon_heiles_megno_map;
use hamilton_jacobi::{Error, Result};
use std::time::Instant;

/// Energy.
const ENERGY: f64 = 0.125;
/// Display clip of `⟨Y⟩`.
const CLIP: f64 = 8.0;

fn arg<T: std::str::FromStr>(i: usize, default: T) -> Result<T> {
    match std::env::args().nth(i) {
        None => Ok(default),
        Some(s) => s
            .parse()
            .map_err(|_| Error::invalid(format!("argument {i}"), format!("cannot parse {s:?}"))),
    }
}

fn main() -> Result<()> {
    let n: usize = arg(1, 512)?;
    let t1: f64 = arg(2, 1000.0)?;
    let h: f64 = arg(3, 0.1)?;
    let threads = rayon::current_num_threads();
    let clock = Instant::now();
    let map = henon_heiles_megno_map(ENERGY, n, t1, h, CLIP)?;
    let elapsed = clock.elapsed();
    let orbit_steps = map.orbits as f64 * map.steps as f64;
    println!(
        "{n} × {n} grid, {} orbits inside the energy's region, {} Verlet steps each (h = {h}, \
         t = {t1}): {:.1} s on {threads} threads ({:.0} ns per orbit step per thread)",
        map.orbits,
        map.steps,
        elapsed.as_secs_f64(),
        elapsed.as_secs_f64() * threads as f64 / orbit_steps * 1e9
    );
    println!(
        "⟨Y⟩ ≤ 2.5 (regular) in {} cells, > 2.5 (chaotic) in {} ({:.1} % chaotic); median ⟨Y⟩ of \
         the regular cells {:?}",
        map.regular,
        map.chaotic,
        100.0 * map.chaotic as f64 / map.orbits.max(1) as f64,
        map.regular_median
    );
    let fig = map.figure(ENERGY, t1, h);
    std::fs::create_dir_all("out").map_err(|e| Error::invalid("directory out", e.to_string()))?;
    let files = fig.write(
        std::path::Path::new("out/henon-heiles-megno-map"),
        &[Format::Svg, Format::Png],
        DataFormat::Npy,
    )?;
    for f in files {
        let bytes = std::fs::metadata(&f).map(|m| m.len()).unwrap_or(0);
        println!("wrote {} ({bytes} bytes)", f.display());
    }
    Ok(())
}

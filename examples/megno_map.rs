//! The MEGNO map of Hénon–Heiles at `E = 1/8`: the mean exponential growth factor of nearby
//! orbits `⟨Y⟩` (Cincotta & Simó 2000) at `t = 10³` over a grid of the surface of section
//! `x = 0` (`p_x > 0` from the energy), each orbit by Störmer–Verlet with its tangent map carrying
//! the deviation vector (`hamilton_jacobi::chaos`), on every core (`rayon`).
//!
//! Invariant tori show `⟨Y⟩ ≈ 2`, stable periodic orbits `⟨Y⟩ ≈ 0` (the island centres), the
//! chaotic sea `⟨Y⟩ ≈ λt/2 ≫ 2`; the colour scale is clipped at 8. Cells outside the energy's
//! allowed region (`p_x² < 0`) and orbits that fail have no value.
//!
//! `cargo run --release --example megno_map [-- N [T [h]]]` (default `N = 512`, `T = 1000`,
//! `h = 0.1`) writes `out/henon-heiles-megno-map.svg`, `.png`, the values of the `N × N` grid as
//! `.npy` (with a CSV header beside it) and the caption, and prints the time taken and the
//! number of threads.

use hamilton_jacobi::chaos::chaos_map;
use hamilton_jacobi::integrate::{Fixed, Splitting};
use hamilton_jacobi::nalgebra::SVector;
use hamilton_jacobi::plot::{DataFormat, Figure, Format, Grid, Scale};
use hamilton_jacobi::systems::HenonHeiles;
use hamilton_jacobi::{Error, Result};
use std::time::Instant;

/// Energy, and the section's extent at that energy: `y ∈ [−0.45, 0.7]`, `p_y ∈ [−0.52, 0.52]`
/// (the allowed region `p_y² + y² − 2y³/3 ≤ 2E` touches `y ≈ −0.44` and `y ≈ 0.68`).
const ENERGY: f64 = 0.125;
const Y: (f64, f64) = (-0.45, 0.7);
const PY: (f64, f64) = (-0.52, 0.52);
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
    let grid = Grid::new(n, n, Y, PY, vec![0.0; n * n])?;
    let (ys, pys) = (
        grid.centres(true, Scale::Linear),
        grid.centres(false, Scale::Linear),
    );
    // Row by row from the bottom (Grid's order): cell k·n + i is (ys[i], pys[k]).
    let mut cells = Vec::new();
    let mut starts = Vec::new();
    for &py in &pys {
        for &y in &ys {
            match HenonHeiles::section_start(ENERGY, y, py) {
                Ok(s) => {
                    cells.push(Some(starts.len()));
                    starts.push(s);
                }
                Err(_) => cells.push(None),
            }
        }
    }
    let steps = (t1 / h).round() as usize;
    let method = Fixed::new(Splitting::VERLET_KDK, steps)?;
    let deviation = (SVector::from([1.0, 0.5]), SVector::from([0.3, -0.7]));
    let threads = rayon::current_num_threads();
    let clock = Instant::now();
    let map = chaos_map(&HenonHeiles, &starts, t1, &method, &deviation)?;
    let elapsed = clock.elapsed();
    let orbit_steps = starts.len() as f64 * steps as f64;
    println!(
        "{n} × {n} grid, {} orbits inside the energy's region, {steps} Verlet steps each (h = {h}, \
         t = {t1}): {:.1} s on {threads} threads ({:.0} ns per orbit step per thread)",
        starts.len(),
        elapsed.as_secs_f64(),
        elapsed.as_secs_f64() * threads as f64 / orbit_steps * 1e9
    );
    let values: Vec<f64> = cells
        .iter()
        .map(|c| match c.and_then(|k| map[k]) {
            Some(ind) => ind.mean_megno.min(CLIP),
            None => f64::NAN,
        })
        .collect();
    let (mut regular, mut chaotic) = (0usize, 0usize);
    for v in values.iter().filter(|v| v.is_finite()) {
        if *v <= 2.5 {
            regular += 1;
        } else {
            chaotic += 1;
        }
    }
    println!(
        "⟨Y⟩ ≤ 2.5 (regular) in {regular} cells, > 2.5 (chaotic) in {chaotic} ({:.1} % chaotic)",
        100.0 * chaotic as f64 / (regular + chaotic).max(1) as f64
    );
    let grid = Grid { values, ..grid }.label(format!("⟨Y⟩ (clipped at {CLIP})"));
    let fig = Figure::new(
        "Hénon–Heiles at E = 1/8: MEGNO map of the section x = 0",
        "y",
        "p_y",
    )
    .caption(format!(
        "Mean MEGNO ⟨Y⟩ at t = {t1} of the Hénon–Heiles orbits H = ½(p² + x² + y²) + x²y − y³/3 \
         = 1/8 started on the section x = 0 at (y, p_y) with p_x > 0, on a {n} × {n} grid, by \
         Störmer–Verlet (h = {h}) with the deviation vector carried by its tangent map. \
         ⟨Y⟩ ≈ 2 on invariant tori, ≈ 0 at stable periodic orbits, ≈ λt/2 in the chaotic sea; \
         the colour scale is clipped at {CLIP}. Grey: outside the energy's allowed region."
    ))
    .heat_map(grid);
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

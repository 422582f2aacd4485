//! The MEGNO map of Hénon–Heiles at `E = 1/8` (issue §2; Cincotta & Simó, *Astron. Astrophys.
//! Suppl.* 147 (2000) 205–228, Fig. 3): the mean exponential growth factor of nearby orbits
//! `⟨Y⟩` at `t₁` over a grid of the surface of section `x = 0` (`p_x > 0` from the energy), each
//! orbit by Störmer–Verlet with its tangent map carrying the deviation vector
//! ([`crate::chaos`]), on every core.
//!
//! Invariant tori show `⟨Y⟩ ≈ 2`, stable periodic orbits `⟨Y⟩ ≈ 0`, the chaotic sea
//! `⟨Y⟩ ≈ λt/2 ≫ 2`. The values are a [`Grid`] (row by row from the lowest `p_y`), written with the
//! figure as a NumPy file of little-endian `float64` of shape `(n, n)` beside a CSV header naming
//! the grid's edges ([`crate::plot::data`]).

use super::case::Table;
use crate::chaos::chaos_map;
use crate::error::{finite, fmt_num, positive, Error, Result};
use crate::integrate::{Fixed, Splitting};
use crate::plot::{Figure, Grid, Scale};
use crate::systems::HenonHeiles;
use nalgebra::SVector;

/// The `what` of the map's figure: `figures/<scene>-megno`.
pub const MAP_FIGURE: &str = "megno";

/// The section's extent in `y` at `E ≤ 1/6` (the allowed region `p_y² + y² − 2y³/3 ≤ 2E` spans
/// `y ∈ [−0.44, 0.68]` at `E = 1/8`).
const Y: (f64, f64) = (-0.45, 0.7);
/// The section's extent in `p_y` (`|p_y| ≤ √(2E) = 0.5` at `E = 1/8`).
const PY: (f64, f64) = (-0.52, 0.52);
/// `⟨Y⟩` at or below which a cell counts as regular.
const REGULAR: f64 = 2.5;
/// The largest grid side.
const MAX_SIDE: usize = 4096;

/// A MEGNO map of the Hénon–Heiles section `x = 0` and its summary.
#[derive(Clone, Debug, PartialEq)]
pub struct MegnoMap {
    /// `⟨Y⟩(t₁)` of each cell clipped at the map's clip (`NaN` outside the energy's allowed
    /// region and where an orbit fails), as a grid over `(y, p_y)`.
    pub grid: Grid,
    /// Orbits run (the cells inside the allowed region).
    pub orbits: usize,
    /// Cells with `⟨Y⟩ ≤ 2.5` (regular).
    pub regular: usize,
    /// Cells with `⟨Y⟩ > 2.5` (chaotic).
    pub chaotic: usize,
    /// Orbits that failed (none expected: the motion at `E < 1/6` is bounded).
    pub failed: usize,
    /// The median `⟨Y⟩` of the regular cells (`2` on tori); `None` without regular cells.
    pub regular_median: Option<f64>,
    /// Verlet steps per orbit.
    pub steps: usize,
}

/// The MEGNO map of Hénon–Heiles at `energy` on an `n × n` grid of the section `x = 0` over
/// `y ∈ [−0.45, 0.7]`, `p_y ∈ [−0.52, 0.52]`, each orbit to `t1` by Störmer–Verlet (kick–drift–
/// kick) with step `h` (rounded to a whole number of steps), the deviation
/// `(δq, δp) = ((1, 0.5), (0.3, −0.7))`; `⟨Y⟩` clipped at `clip` for display.
///
/// # Errors
/// [`Error::OutOfDomain`]/[`Error::NonFinite`] for `energy ∉ (0, 1/6)` (the escape energy),
/// `n ∉ [2, 4096]`, non-positive or non-finite `t1`, `h`, `clip`, more than 10⁸ steps per orbit;
/// the errors of [`chaos_map`].
pub fn henon_heiles_megno_map(
    energy: f64,
    n: usize,
    t1: f64,
    h: f64,
    clip: f64,
) -> Result<MegnoMap> {
    let energy = positive("energy E", energy)?;
    if energy >= 1.0 / 6.0 {
        return Err(Error::out_of_domain(
            "energy E",
            energy,
            "(0, 1/6): bounded motion below the escape energy",
        ));
    }
    if !(2..=MAX_SIDE).contains(&n) {
        return Err(Error::out_of_domain(
            "grid side n",
            n as f64,
            format!("[2, {MAX_SIDE}]"),
        ));
    }
    let (t1, h, clip) = (
        positive("time t₁", t1)?,
        positive("step h", h)?,
        positive("clip of ⟨Y⟩", clip)?,
    );
    let steps = finite("steps t₁/h", (t1 / h).round())?;
    if !(1.0..=1e8).contains(&steps) {
        return Err(Error::out_of_domain(
            "steps per orbit t₁/h",
            steps,
            "[1, 10⁸]",
        ));
    }
    let steps = steps as usize;
    let grid = Grid::new(n, n, Y, PY, vec![0.0; n * n])?;
    let (ys, pys) = (
        grid.centres(true, Scale::Linear),
        grid.centres(false, Scale::Linear),
    );
    // Row by row from the bottom (Grid's order): cell k·n + i is (ys[i], pys[k]).
    let mut cells = Vec::with_capacity(n * n);
    let mut starts = Vec::new();
    for &py in &pys {
        for &y in &ys {
            match HenonHeiles::section_start(energy, y, py) {
                Ok(s) => {
                    cells.push(Some(starts.len()));
                    starts.push(s);
                }
                Err(_) => cells.push(None),
            }
        }
    }
    let method = Fixed::new(Splitting::VERLET_KDK, steps)?;
    let deviation = (SVector::from([1.0, 0.5]), SVector::from([0.3, -0.7]));
    let map = chaos_map(&HenonHeiles, &starts, t1, &method, &deviation)?;
    let failed = map.iter().filter(|c| c.is_none()).count();
    let raw: Vec<f64> = map
        .iter()
        .filter_map(|c| c.map(|ind| ind.mean_megno))
        .collect();
    let mut regular_values: Vec<f64> = raw.iter().copied().filter(|v| *v <= REGULAR).collect();
    regular_values.sort_by(f64::total_cmp);
    let regular_median = regular_values.get(regular_values.len() / 2).copied();
    let values: Vec<f64> = cells
        .iter()
        .map(|c| match c.and_then(|k| map[k]) {
            Some(ind) => ind.mean_megno.min(clip),
            None => f64::NAN,
        })
        .collect();
    Ok(MegnoMap {
        grid: Grid { values, ..grid }.label(format!("⟨Y⟩ (clipped at {})", fmt_num(clip))),
        orbits: starts.len(),
        regular: regular_values.len(),
        chaotic: raw.len() - regular_values.len(),
        failed,
        regular_median,
        steps,
    })
}

impl MegnoMap {
    /// The map as a heat map of `⟨Y⟩` over `(y, p_y)`, captioned with the run's parameters.
    pub fn figure(&self, energy: f64, t1: f64, h: f64) -> Figure {
        let n = self.grid.nx;
        Figure::new(
            format!(
                "Hénon–Heiles at E = {}: MEGNO map of the section x = 0",
                fmt_num(energy)
            ),
            "y",
            "p_y",
        )
        .caption(format!(
            "Mean MEGNO ⟨Y⟩ at t = {} of the Hénon–Heiles orbits H = ½(p² + x² + y²) + x²y − y³/3 \
             = {} started on the section x = 0 at (y, p_y) with p_x > 0, on a {n} × {n} grid, by \
             Störmer–Verlet ({} steps, h = {}) with the deviation vector carried by its tangent \
             map. ⟨Y⟩ ≈ 2 on invariant tori (the islands), ≈ 0 at stable periodic orbits, ≈ λt/2 \
             in the chaotic sea; {} of {} orbits have ⟨Y⟩ ≤ {REGULAR}. {} Grey: outside the \
             energy's allowed region.",
            fmt_num(t1),
            fmt_num(energy),
            self.steps,
            fmt_num(h),
            self.regular,
            self.orbits,
            self.grid.label,
        ))
        .heat_map(self.grid.clone())
    }

    /// The summary table of the map.
    pub fn table(&self) -> Table {
        let n = self.grid.nx;
        let share = |k: usize| fmt_num(100.0 * k as f64 / self.orbits.max(1) as f64);
        Table {
            header: vec!["quantity".into(), "value".into()],
            rows: vec![
                vec!["grid".into(), format!("{n} × {n}")],
                vec![
                    "orbits (cells inside the allowed region)".into(),
                    self.orbits.to_string(),
                ],
                vec!["Verlet steps per orbit".into(), self.steps.to_string()],
                vec![
                    format!("regular cells (⟨Y⟩ ≤ {REGULAR}), %"),
                    format!("{} ({} %)", self.regular, share(self.regular)),
                ],
                vec![
                    format!("chaotic cells (⟨Y⟩ > {REGULAR}), %"),
                    format!("{} ({} %)", self.chaotic, share(self.chaotic)),
                ],
                vec![
                    "median ⟨Y⟩ of the regular cells (tori: 2)".into(),
                    self.regular_median.map_or_else(|| "—".to_string(), fmt_num),
                ],
                vec!["failed orbits".into(), self.failed.to_string()],
            ],
        }
    }
}

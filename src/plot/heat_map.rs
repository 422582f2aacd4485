//! Heat maps: a regular grid of values drawn as coloured cells, with a colour bar — for
//! stability and MEGNO maps, error maps over two parameters, densities.
//!
//! A [`Grid`] holds `nx × ny` values on cells that are regular on the figure's axes (uniform in
//! log₁₀ of the coordinate on a logarithmic axis), given by the outer edges of the grid. A
//! figure with a grid ([`Figure::heat_map`](crate::plot::Figure::heat_map)) draws it in the
//! plotting area with the colour bar in the column beside it:
//!
//! * **Colours.** Values map to viridis (van der Walt & Smith, matplotlib 2.0's default colour
//!   map; Nuñez, Anderton & Renslow, PLoS ONE 13 (2018) e0199239, doi:10.1371/journal.pone.0199239),
//!   perceptually uniform and legible in grey-scale: a value `v` of the colour range `[lo, hi]`
//!   takes entry `min(⌊256 t⌋, 255)` of its 256-entry table, `t = (v − lo) / (hi − lo)` (on a
//!   logarithmic colour scale, of log₁₀ v). The range is that of the finite values (positive
//!   ones on a logarithmic scale), widened as an axis range if it is a single value.
//! * **No value.** A cell without a finite value (NaN, ±∞), or with a negative value on a
//!   logarithmic colour scale, is drawn in light grey, shown as "no value" below the colour bar,
//!   and the caption counts such cells. Zeros on a logarithmic colour scale are drawn at a floor
//!   a decade below the smallest positive value, as on a logarithmic axis.
//! * **Large grids.** A grid with more columns (rows) than the plotting area has canvas units
//!   across (down) is drawn in blocks of `kx × ky` cells, each block in the colour of its largest
//!   value (so that an isolated peak stays visible); the caption says so and the data file keeps
//!   every cell.
//! * **Data.** The data file is a tidy table `x,y,value` of the cell centres, row by row from
//!   the bottom; grids of at least [`NPY_THRESHOLD`](crate::plot::data::NPY_THRESHOLD) cells
//!   are also written as a NumPy array of shape `(ny, nx)` (see [`data`](crate::plot::data)).

use super::{font, text_width, ticks, AxisMap, Figure, Scale, Ticks};
use super::{DESC_PX, MARGIN, TICK_LEN, TICK_PX};
use crate::error::{Error, Result};
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// Width of the colour bar, in canvas units.
const BAR_W: f64 = 14.0;
/// Room left of the colour bar within its column.
const BAR_LEFT: f64 = 6.0;
/// Label of the swatch of cells without a value.
const NO_VALUE_LABEL: &str = "no value";

/// Viridis: 256 colours, 8-bit sRGB, from dark blue (low) to yellow (high); the published
/// table of matplotlib's `_viridis_data` (van der Walt & Smith, CC0), rounded to 8 bits.
pub const VIRIDIS: [[u8; 3]; 256] = [
    [68, 1, 84],
    [68, 2, 86],
    [69, 4, 87],
    [69, 5, 89],
    [70, 7, 90],
    [70, 8, 92],
    [70, 10, 93],
    [70, 11, 94],
    [71, 13, 96],
    [71, 14, 97],
    [71, 16, 99],
    [71, 17, 100],
    [71, 19, 101],
    [72, 20, 103],
    [72, 22, 104],
    [72, 23, 105],
    [72, 24, 106],
    [72, 26, 108],
    [72, 27, 109],
    [72, 28, 110],
    [72, 29, 111],
    [72, 31, 112],
    [72, 32, 113],
    [72, 33, 115],
    [72, 35, 116],
    [72, 36, 117],
    [72, 37, 118],
    [72, 38, 119],
    [72, 40, 120],
    [72, 41, 121],
    [71, 42, 122],
    [71, 44, 122],
    [71, 45, 123],
    [71, 46, 124],
    [71, 47, 125],
    [70, 48, 126],
    [70, 50, 126],
    [70, 51, 127],
    [70, 52, 128],
    [69, 53, 129],
    [69, 55, 129],
    [69, 56, 130],
    [68, 57, 131],
    [68, 58, 131],
    [68, 59, 132],
    [67, 61, 132],
    [67, 62, 133],
    [66, 63, 133],
    [66, 64, 134],
    [66, 65, 134],
    [65, 66, 135],
    [65, 68, 135],
    [64, 69, 136],
    [64, 70, 136],
    [63, 71, 136],
    [63, 72, 137],
    [62, 73, 137],
    [62, 74, 137],
    [62, 76, 138],
    [61, 77, 138],
    [61, 78, 138],
    [60, 79, 138],
    [60, 80, 139],
    [59, 81, 139],
    [59, 82, 139],
    [58, 83, 139],
    [58, 84, 140],
    [57, 85, 140],
    [57, 86, 140],
    [56, 88, 140],
    [56, 89, 140],
    [55, 90, 140],
    [55, 91, 141],
    [54, 92, 141],
    [54, 93, 141],
    [53, 94, 141],
    [53, 95, 141],
    [52, 96, 141],
    [52, 97, 141],
    [51, 98, 141],
    [51, 99, 141],
    [50, 100, 142],
    [50, 101, 142],
    [49, 102, 142],
    [49, 103, 142],
    [49, 104, 142],
    [48, 105, 142],
    [48, 106, 142],
    [47, 107, 142],
    [47, 108, 142],
    [46, 109, 142],
    [46, 110, 142],
    [46, 111, 142],
    [45, 112, 142],
    [45, 113, 142],
    [44, 113, 142],
    [44, 114, 142],
    [44, 115, 142],
    [43, 116, 142],
    [43, 117, 142],
    [42, 118, 142],
    [42, 119, 142],
    [42, 120, 142],
    [41, 121, 142],
    [41, 122, 142],
    [41, 123, 142],
    [40, 124, 142],
    [40, 125, 142],
    [39, 126, 142],
    [39, 127, 142],
    [39, 128, 142],
    [38, 129, 142],
    [38, 130, 142],
    [38, 130, 142],
    [37, 131, 142],
    [37, 132, 142],
    [37, 133, 142],
    [36, 134, 142],
    [36, 135, 142],
    [35, 136, 142],
    [35, 137, 142],
    [35, 138, 141],
    [34, 139, 141],
    [34, 140, 141],
    [34, 141, 141],
    [33, 142, 141],
    [33, 143, 141],
    [33, 144, 141],
    [33, 145, 140],
    [32, 146, 140],
    [32, 146, 140],
    [32, 147, 140],
    [31, 148, 140],
    [31, 149, 139],
    [31, 150, 139],
    [31, 151, 139],
    [31, 152, 139],
    [31, 153, 138],
    [31, 154, 138],
    [30, 155, 138],
    [30, 156, 137],
    [30, 157, 137],
    [31, 158, 137],
    [31, 159, 136],
    [31, 160, 136],
    [31, 161, 136],
    [31, 161, 135],
    [31, 162, 135],
    [32, 163, 134],
    [32, 164, 134],
    [33, 165, 133],
    [33, 166, 133],
    [34, 167, 133],
    [34, 168, 132],
    [35, 169, 131],
    [36, 170, 131],
    [37, 171, 130],
    [37, 172, 130],
    [38, 173, 129],
    [39, 173, 129],
    [40, 174, 128],
    [41, 175, 127],
    [42, 176, 127],
    [44, 177, 126],
    [45, 178, 125],
    [46, 179, 124],
    [47, 180, 124],
    [49, 181, 123],
    [50, 182, 122],
    [52, 182, 121],
    [53, 183, 121],
    [55, 184, 120],
    [56, 185, 119],
    [58, 186, 118],
    [59, 187, 117],
    [61, 188, 116],
    [63, 188, 115],
    [64, 189, 114],
    [66, 190, 113],
    [68, 191, 112],
    [70, 192, 111],
    [72, 193, 110],
    [74, 193, 109],
    [76, 194, 108],
    [78, 195, 107],
    [80, 196, 106],
    [82, 197, 105],
    [84, 197, 104],
    [86, 198, 103],
    [88, 199, 101],
    [90, 200, 100],
    [92, 200, 99],
    [94, 201, 98],
    [96, 202, 96],
    [99, 203, 95],
    [101, 203, 94],
    [103, 204, 92],
    [105, 205, 91],
    [108, 205, 90],
    [110, 206, 88],
    [112, 207, 87],
    [115, 208, 86],
    [117, 208, 84],
    [119, 209, 83],
    [122, 209, 81],
    [124, 210, 80],
    [127, 211, 78],
    [129, 211, 77],
    [132, 212, 75],
    [134, 213, 73],
    [137, 213, 72],
    [139, 214, 70],
    [142, 214, 69],
    [144, 215, 67],
    [147, 215, 65],
    [149, 216, 64],
    [152, 216, 62],
    [155, 217, 60],
    [157, 217, 59],
    [160, 218, 57],
    [162, 218, 55],
    [165, 219, 54],
    [168, 219, 52],
    [170, 220, 50],
    [173, 220, 48],
    [176, 221, 47],
    [178, 221, 45],
    [181, 222, 43],
    [184, 222, 41],
    [186, 222, 40],
    [189, 223, 38],
    [192, 223, 37],
    [194, 223, 35],
    [197, 224, 33],
    [200, 224, 32],
    [202, 225, 31],
    [205, 225, 29],
    [208, 225, 28],
    [210, 226, 27],
    [213, 226, 26],
    [216, 226, 25],
    [218, 227, 25],
    [221, 227, 24],
    [223, 227, 24],
    [226, 228, 24],
    [229, 228, 25],
    [231, 228, 25],
    [234, 229, 26],
    [236, 229, 27],
    [239, 229, 28],
    [241, 229, 29],
    [244, 230, 30],
    [246, 230, 32],
    [248, 230, 33],
    [251, 231, 35],
    [253, 231, 37],
];

/// Colour of cells without a value (light grey, outside viridis).
pub(crate) const NO_VALUE: RGBColor = RGBColor(217, 217, 217);

/// A regular grid of values: `ny` rows of `nx` cells, row 0 at the bottom (lowest y), column 0
/// at the left.
#[derive(Clone, Debug, PartialEq)]
pub struct Grid {
    /// Number of columns (cells along x).
    pub nx: usize,
    /// Number of rows (cells along y).
    pub ny: usize,
    /// Left edge of the first column and right edge of the last, in units of x.
    pub x: (f64, f64),
    /// Lower edge of the first row and upper edge of the last, in units of y.
    pub y: (f64, f64),
    /// The values, row by row from the bottom: `values[k · nx + i]` is the cell of column `i`,
    /// row `k`.
    pub values: Vec<f64>,
    /// Title of the colour bar: the quantity and its unit.
    pub label: String,
    /// Colour scale.
    pub scale: Scale,
}

impl Grid {
    /// A grid of `nx × ny` values (row by row from the bottom) over the cells between the edges
    /// `x` and `y`, on a linear colour scale with an untitled colour bar.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] if `nx` or `ny` is 0, `values` does not hold `nx · ny` values, or
    /// an edge is not finite or the edges are not increasing.
    pub fn new(
        nx: usize,
        ny: usize,
        x: (f64, f64),
        y: (f64, f64),
        values: Vec<f64>,
    ) -> Result<Self> {
        let g = Self {
            nx,
            ny,
            x,
            y,
            values,
            label: String::new(),
            scale: Scale::Linear,
        };
        g.check()?;
        Ok(g)
    }

    /// Set the colour bar's title.
    pub fn label(mut self, label: impl Into<String>) -> Self {
        self.label = label.into();
        self
    }

    /// Make the colour scale logarithmic.
    pub fn log(mut self) -> Self {
        self.scale = Scale::Log;
        self
    }

    /// Check the sizes and edges (see [`Grid::new`]).
    ///
    /// # Errors
    /// As [`Grid::new`].
    pub fn check(&self) -> Result<()> {
        let bad = |why: String| Err(Error::invalid("heat map grid", why));
        if self.nx == 0 || self.ny == 0 {
            return bad(format!(
                "{} × {} cells: expected at least one",
                self.nx, self.ny
            ));
        }
        if self.nx.checked_mul(self.ny) != Some(self.values.len()) {
            return bad(format!(
                "{} values for {} × {} cells",
                self.values.len(),
                self.nx,
                self.ny
            ));
        }
        for (axis, (a, b)) in [("x", self.x), ("y", self.y)] {
            if !(a.is_finite() && b.is_finite() && a < b) {
                return bad(format!(
                    "edges {a} … {b} along {axis}: expected finite and increasing"
                ));
            }
        }
        Ok(())
    }

    /// The centres of the columns (`along_x`) or rows along an axis of scale `scale`.
    pub fn centres(&self, along_x: bool, scale: Scale) -> Vec<f64> {
        let (n, (a, b)) = if along_x {
            (self.nx, self.x)
        } else {
            (self.ny, self.y)
        };
        (0..n)
            .map(|i| {
                let f = (i as f64 + 0.5) / n as f64;
                match scale {
                    Scale::Linear => a + (b - a) * f,
                    Scale::Log => 10f64.powf(a.log10() + (b.log10() - a.log10()) * f),
                }
            })
            .collect()
    }
}

/// The colour range of a grid's values and how they map to colours.
#[derive(Clone, Copy, Debug)]
pub(crate) struct ColourScale {
    /// Scale and zero floor.
    pub map: AxisMap,
    /// The range, in plot coordinates (log₁₀ on a logarithmic scale).
    pub range: (f64, f64),
}

impl ColourScale {
    /// The scale of the values: their range, widened if it is one value; `None` if no value
    /// can be drawn.
    pub fn of(values: &[f64], scale: Scale) -> Option<Self> {
        let map = AxisMap {
            scale,
            floor: super::zero_floor(values.iter().copied()),
        };
        let mut r = (f64::INFINITY, f64::NEG_INFINITY);
        for v in values
            .iter()
            .filter(|v| v.is_finite())
            .filter_map(|&v| map.map(v))
        {
            r = (r.0.min(v), r.1.max(v));
        }
        if r.0 > r.1 {
            return None;
        }
        let range = if r.1 - r.0 > 1e-12 * r.0.abs().max(r.1.abs()) && r.1 > r.0 {
            r
        } else {
            super::padded(r.0, r.1, scale)
        };
        ((range.1 - range.0).is_finite()).then_some(Self { map, range })
    }

    /// The position of `v` in the range, `0…1`; `None` for a cell without a value.
    pub fn position(&self, v: f64) -> Option<f64> {
        if !v.is_finite() {
            return None;
        }
        let p = self.map.map(v)?;
        Some(((p - self.range.0) / (self.range.1 - self.range.0)).clamp(0.0, 1.0))
    }

    /// The index into [`VIRIDIS`] of `v`; `None` for a cell without a value.
    pub fn level(&self, v: f64) -> Option<usize> {
        self.position(v)
            .map(|t| ((t * 256.0).floor() as usize).min(255))
    }
}

/// The colour of entry `level` of [`VIRIDIS`].
pub(crate) fn colour(level: usize) -> RGBColor {
    let [r, g, b] = VIRIDIS[level.min(255)];
    RGBColor(r, g, b)
}

/// The drawn cells: blocks of `kx × ky` cells so that at most `max_cols × max_rows` are drawn,
/// each with the level of its largest value (`None`: no cell of the block has a value).
pub(crate) struct Blocks {
    pub kx: usize,
    pub ky: usize,
    pub cols: usize,
    pub rows: usize,
    pub levels: Vec<Option<usize>>,
}

/// The levels of the grid's cells, in blocks no smaller than a canvas unit.
pub(crate) fn blocks(g: &Grid, c: &ColourScale, max_cols: usize, max_rows: usize) -> Blocks {
    let kx = g.nx.div_ceil(max_cols.max(1)).max(1);
    let ky = g.ny.div_ceil(max_rows.max(1)).max(1);
    let (cols, rows) = (g.nx.div_ceil(kx), g.ny.div_ceil(ky));
    let mut levels = vec![None; cols * rows];
    for k in 0..g.ny {
        for i in 0..g.nx {
            if let Some(l) = c.level(g.values[k * g.nx + i]) {
                let b = &mut levels[(k / ky) * cols + i / kx];
                *b = Some(b.map_or(l, |m: usize| m.max(l)));
            }
        }
    }
    Blocks {
        kx,
        ky,
        cols,
        rows,
        levels,
    }
}

/// The SVG of the drawn cells: one path per colour, horizontal runs of equal colour merged,
/// edges on whole canvas units (`crispEdges`, no seams between cells). `xs` and `ys` are the
/// canvas positions of the block edges (`cols + 1` from the left, `rows + 1` from the bottom).
pub(crate) fn cells_svg(b: &Blocks, xs: &[i32], ys: &[i32]) -> String {
    let mut paths: Vec<String> = vec![String::new(); 257];
    for r in 0..b.rows {
        let (y_lo, y_hi) = (ys[r], ys[r + 1]);
        let (top, h) = (y_lo.min(y_hi), (y_lo - y_hi).abs());
        if h == 0 {
            continue;
        }
        let mut i = 0;
        while i < b.cols {
            let l = b.levels[r * b.cols + i];
            let mut j = i + 1;
            while j < b.cols && b.levels[r * b.cols + j] == l {
                j += 1;
            }
            let w = xs[j] - xs[i];
            if w > 0 {
                let slot = l.unwrap_or(256);
                paths[slot] += &format!("M{} {top}h{w}v{h}h-{w}z", xs[i]);
            }
            i = j;
        }
    }
    let mut out = String::new();
    for (slot, d) in paths.iter().enumerate() {
        if d.is_empty() {
            continue;
        }
        let c = if slot == 256 { NO_VALUE } else { colour(slot) };
        out += &format!(
            "<path d=\"{d}\" fill=\"{}\" stroke=\"none\" shape-rendering=\"crispEdges\"/>\n",
            super::svg_color(c)
        );
    }
    out
}

/// A heat map ready to draw: the grid, its colours, its edges in plot coordinates, the cells
/// without a value, and (once the plotting area's size is known) the drawn blocks.
pub(crate) struct Heat {
    pub grid: Grid,
    pub colours: ColourScale,
    /// Edges in plot coordinates.
    pub x: (f64, f64),
    pub y: (f64, f64),
    /// Cells without a value.
    pub missing: usize,
    pub blocks: Option<Blocks>,
}

impl Heat {
    /// Prepare the heat map of `fig`, adding its notes (cells without a value, zero floor).
    pub fn new(
        fig: &Figure,
        g: &Grid,
        xm: AxisMap,
        ym: AxisMap,
        notes: &mut Vec<String>,
    ) -> Result<Self> {
        g.check().map_err(|e| fig.error(e))?;
        if !fig.curves.is_empty() || fig.panel_labels.len() > 1 {
            return Err(fig.error("a heat map has no curves and one panel"));
        }
        let edge = |m: AxisMap, v: (f64, f64), axis: &str| {
            let ok = |e: f64| {
                (m.scale == Scale::Linear || e > 0.0)
                    .then(|| m.map(e))
                    .flatten()
            };
            match (ok(v.0), ok(v.1)) {
                (Some(a), Some(b)) if b > a && (b - a).is_finite() => Ok((a, b)),
                _ => Err(fig.error(format!(
                    "the grid's edges {} … {} cannot be drawn on the {axis} axis",
                    v.0, v.1
                ))),
            }
        };
        let x = edge(xm, g.x, "horizontal")?;
        let y = edge(ym, g.y, "vertical")?;
        let colours = ColourScale::of(&g.values, g.scale)
            .ok_or_else(|| fig.error("no cell of the grid has a value that can be drawn"))?;
        let missing = g
            .values
            .iter()
            .filter(|&&v| colours.position(v).is_none())
            .count();
        if missing > 0 {
            let log = if g.scale == Scale::Log {
                ", or negative on the logarithmic colour scale"
            } else {
                ""
            };
            notes.push(format!(
                "{missing} of {} cells have no value (NaN or infinite{log}) and are drawn in \
                 light grey (\u{201c}{NO_VALUE_LABEL}\u{201d}).",
                g.values.len()
            ));
        }
        if g.scale == Scale::Log && g.values.contains(&0.0) {
            notes.push(
                format!(
                    "Zeros of {} are drawn at 1e{} (logarithmic colour scale).",
                    super::quoted_axis(&g.label),
                    colours.map.floor.log10().round() as i32
                )
                .replace('-', "\u{2212}"),
            );
        }
        Ok(Self {
            grid: g.clone(),
            colours,
            x,
            y,
            missing,
            blocks: None,
        })
    }

    /// Height of the colour bar beside a plotting area `plot_h` high (room is left below it
    /// for the "no value" swatch).
    fn bar_h(&self, plot_h: f64) -> f64 {
        let below = if self.missing > 0 { 2.0 * TICK_PX } else { 0.0 };
        (plot_h - below).max(10.0)
    }

    /// The colour bar's ticks.
    fn ticks(&self, plot_h: f64) -> Ticks {
        ticks(
            self.grid.scale,
            self.colours.range,
            self.bar_h(plot_h),
            false,
        )
    }

    /// Widest tick label (or the "no value" label).
    fn labels_w(&self, plot_h: f64) -> f64 {
        let no_value = if self.missing > 0 {
            text_width(NO_VALUE_LABEL, TICK_PX)
        } else {
            0.0
        };
        self.ticks(plot_h).max_label_width().max(no_value)
    }

    /// Width of the colour bar's column: bar, ticks, labels and the title along it.
    pub fn column_width(&self, plot_h: f64) -> u32 {
        let title = if self.grid.label.is_empty() {
            0.0
        } else {
            1.3 * DESC_PX + 4.0
        };
        (BAR_LEFT + BAR_W + (2 * TICK_LEN) as f64 + self.labels_w(plot_h) + 8.0 + title).ceil()
            as u32
    }

    /// Choose the drawn blocks for a plotting area of `plot_w × plot_h` canvas units, with a
    /// note if cells are drawn in blocks.
    pub fn block(&mut self, plot_w: f64, plot_h: f64, notes: &mut Vec<String>) {
        let b = blocks(
            &self.grid,
            &self.colours,
            plot_w.max(1.0) as usize,
            plot_h.max(1.0) as usize,
        );
        if b.kx > 1 || b.ky > 1 {
            notes.push(format!(
                "The {} × {} cells are drawn in blocks of {} × {} (each in the colour of its \
                 largest value); the data file holds every cell.",
                self.grid.nx, self.grid.ny, b.kx, b.ky
            ));
        }
        self.blocks = Some(b);
    }

    /// The SVG of the cells, given the map from plot coordinates to canvas positions.
    pub fn cells(&self, at: impl Fn(f64, f64) -> (i32, i32)) -> String {
        let Some(b) = &self.blocks else {
            return String::new();
        };
        let g = &self.grid;
        let xs: Vec<i32> = (0..=b.cols)
            .map(|c| {
                let e = (c * b.kx).min(g.nx) as f64 / g.nx as f64;
                at(self.x.0 + (self.x.1 - self.x.0) * e, self.y.0).0
            })
            .collect();
        let ys: Vec<i32> = (0..=b.rows)
            .map(|r| {
                let e = (r * b.ky).min(g.ny) as f64 / g.ny as f64;
                at(self.x.0, self.y.0 + (self.y.1 - self.y.0) * e).1
            })
            .collect();
        cells_svg(b, &xs, &ys)
    }

    /// Draw the colour bar in its column: the bar level with the plotting area (`plot_h` high,
    /// its top `MARGIN.0` below the column's), ticks and labels on its right, the title along
    /// it, and the "no value" swatch below it if a cell has no value.
    pub fn draw_bar<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        plot_h: f64,
        title_px: f64,
    ) -> std::result::Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
        let bar_h = self.bar_h(plot_h);
        let top = MARGIN.0 as f64;
        let x0 = BAR_LEFT.round() as i32;
        let x1 = (BAR_LEFT + BAR_W).round() as i32;
        let y_of = |t: f64| (top + (1.0 - t) * bar_h).round() as i32;
        // Strips from the bottom, each reaching one unit into the next (drawn over it), so
        // that no seam shows between them.
        for l in 0..256 {
            let (lo, hi) = (y_of(l as f64 / 256.0), y_of((l + 1) as f64 / 256.0));
            let hi = if l < 255 { hi - 1 } else { hi };
            area.draw(&Rectangle::new([(x0, hi), (x1, lo)], colour(l).filled()))?;
        }
        area.draw(&Rectangle::new(
            [(x0, y_of(1.0)), (x1, y_of(0.0))],
            BLACK.stroke_width(1),
        ))?;
        let label_style = font(TICK_PX).pos(Pos::new(HPos::Left, VPos::Center));
        let (lo, hi) = self.colours.range;
        for (v, label) in &self.ticks(plot_h).major {
            let y = y_of((v - lo) / (hi - lo));
            area.draw(&PathElement::new(
                vec![(x1, y), (x1 + TICK_LEN, y)],
                BLACK.stroke_width(1),
            ))?;
            area.draw_text(label, &label_style, (x1 + 2 * TICK_LEN, y))?;
        }
        if self.missing > 0 {
            let y = y_of(0.0) + (1.0 * TICK_PX).round() as i32;
            let half = (0.45 * TICK_PX).round() as i32;
            area.draw(&Rectangle::new(
                [(x0, y - half), (x1, y + half)],
                NO_VALUE.filled(),
            ))?;
            area.draw(&Rectangle::new(
                [(x0, y - half), (x1, y + half)],
                BLACK.stroke_width(1),
            ))?;
            area.draw_text(NO_VALUE_LABEL, &label_style, (x1 + 2 * TICK_LEN, y))?;
        }
        if !self.grid.label.is_empty() {
            let x = (BAR_LEFT + BAR_W + (2 * TICK_LEN) as f64 + self.labels_w(plot_h) + 8.0).round()
                as i32;
            let style = font(title_px)
                .transform(FontTransform::Rotate270)
                .pos(Pos::new(HPos::Center, VPos::Top));
            let fits = text_width(&self.grid.label, title_px) <= bar_h;
            let px = if fits {
                title_px
            } else {
                (title_px * bar_h / text_width(&self.grid.label, title_px)).max(9.0)
            };
            let style = if fits {
                style
            } else {
                font(px)
                    .transform(FontTransform::Rotate270)
                    .pos(Pos::new(HPos::Center, VPos::Top))
            };
            area.draw_text(&self.grid.label, &style, (x, y_of(0.5)))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_matches_its_published_colours() {
        // The five-colour viridis of matplotlib's documentation: #440154, #3b528b, #21918c,
        // #5ec962, #fde725 at 0, 1/4, 1/2, 3/4, 1.
        let hex = |l: usize| super::super::svg_color(colour(l));
        assert_eq!(hex(0), "#440154");
        assert_eq!(hex(64), "#3B528B");
        assert_eq!(hex(128), "#21918C");
        assert_eq!(hex(192), "#5EC962");
        assert_eq!(hex(255), "#FDE725");
        // Perceptually ordered: luminance rises monotonically along the table.
        let lum = |c: [u8; 3]| 0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64;
        assert!(VIRIDIS.windows(2).all(|w| lum(w[1]) >= lum(w[0]) - 0.5));
    }

    #[test]
    fn levels_follow_the_range_and_skip_missing_values() {
        let c = ColourScale::of(&[0.0, 1.0, f64::NAN], Scale::Linear).unwrap();
        assert_eq!(c.level(0.0), Some(0));
        assert_eq!(c.level(1.0), Some(255));
        assert_eq!(c.level(0.5), Some(128));
        assert_eq!(c.level(f64::NAN), None);
        assert_eq!(c.level(f64::INFINITY), None);
        let l = ColourScale::of(&[1.0, 100.0, -1.0], Scale::Log).unwrap();
        assert_eq!(l.level(10.0), Some(128));
        assert_eq!(l.level(-1.0), None);
        assert!(ColourScale::of(&[f64::NAN], Scale::Linear).is_none());
        // One value: widened like an axis.
        let one = ColourScale::of(&[2.0, 2.0], Scale::Linear).unwrap();
        assert!((one.position(2.0).unwrap() - 0.5).abs() < 1e-12);
    }

    #[test]
    fn grids_are_checked() {
        assert!(Grid::new(2, 2, (0.0, 1.0), (0.0, 1.0), vec![0.0; 4]).is_ok());
        assert!(Grid::new(0, 2, (0.0, 1.0), (0.0, 1.0), vec![]).is_err());
        assert!(Grid::new(2, 2, (0.0, 1.0), (0.0, 1.0), vec![0.0; 3]).is_err());
        assert!(Grid::new(2, 2, (1.0, 0.0), (0.0, 1.0), vec![0.0; 4]).is_err());
        assert!(Grid::new(2, 2, (0.0, f64::NAN), (0.0, 1.0), vec![0.0; 4]).is_err());
        assert!(Grid::new(usize::MAX, 2, (0.0, 1.0), (0.0, 1.0), vec![]).is_err());
        let g = Grid::new(4, 1, (1e-3, 1e1), (0.0, 1.0), vec![0.0; 4]).unwrap();
        let c = g.centres(true, Scale::Log);
        assert!((c[0] - 1e-3 * 10f64.powf(0.5)).abs() < 1e-15);
        assert_eq!(g.centres(false, Scale::Linear), [0.5]);
    }

    #[test]
    fn blocks_keep_the_largest_value() {
        let mut v = vec![0.0; 16];
        v[5] = 1.0;
        let g = Grid::new(4, 4, (0.0, 1.0), (0.0, 1.0), v).unwrap();
        let c = ColourScale::of(&g.values, Scale::Linear).unwrap();
        let b = blocks(&g, &c, 2, 2);
        assert_eq!((b.kx, b.ky, b.cols, b.rows), (2, 2, 2, 2));
        assert_eq!(b.levels, [Some(255), Some(0), Some(0), Some(0)]);
    }
}

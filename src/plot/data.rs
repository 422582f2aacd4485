//! The data behind a figure: every point of every curve, written beside the figure so that it
//! can be redrawn (`hj plot`) or re-plotted in another tool without re-running anything.
//!
//! The data file `NAME.csv` is a tidy long table (RFC 4180) after a block of comment lines that
//! describe the figure:
//!
//! ```text
//! # hamilton-jacobi figure data
//! # title: Kepler, e = 0.5 — energy error
//! # x: t
//! # y: |ΔE/E|
//! # x_scale: linear
//! # y_scale: log
//! # equal_aspect: false
//! # size: 6.4in x 4.2in, 9pt, 150dpi
//! # caption: Relative energy error …
//! # note: Zeros of “|ΔE/E|” are drawn at 1e−17 (logarithmic axis).
//! # series 0: line: Gauss–Legendre, 3 stages, order 6 (400 steps)
//! panel,series,label,x,y
//! 0,0,"Gauss–Legendre, 3 stages, order 6 (400 steps)",0,0
//! ```
//!
//! One row per point, in drawing order, with every point of the curve (also those a large curve
//! does not draw, and non-finite ones: `NaN`, `inf`); numbers are written so that they read
//! back exactly. The header's text values escape `\` as `\\` and line breaks as `\n`, `\r`.
//! `note` lines (what the drawing adds to the caption) are derived and ignored on reading.
//!
//! A heat map's data file ([`Grid`]) names the grid in its header (`grid:
//! NX x NY`, the edges `grid_x: A B` and `grid_y: A B`, the colour bar's title `value:` and
//! `value_scale:`) and holds the table `x,y,value`: one row per cell, at the cell's centre, row
//! by row from the lowest y.
//!
//! NumPy files: figure data of at least [`NPY_THRESHOLD`] values (points of all curves, or
//! cells; 512 × 512) is also written to `NAME.npy`, which the header names in a `# points:` or
//! `# cells:` line — the points as an array of `float64` of shape `(N, 4)` with columns panel,
//! series, x, y, a grid's values as an array of shape `(ny, nx)`, row 0 the lowest y (NumPy
//! format 1.0). With [`DataFormat::Npy`] the NumPy file is written at any size and the CSV holds
//! the header only. A figure is read back from the CSV's table if it has one, else from the
//! NumPy file; [`read`] given the `.npy` file reads the header beside it and the values from
//! the NumPy file.

use super::{Figure, Grid, Rendered, Scale, Size, Style};
use crate::error::{Error, Result};
use crate::workprecision::csv_field;
use std::path::Path;

/// Figure data of at least this many values (points of all curves, or cells of a grid) is
/// also written as a NumPy file: 512 × 512.
pub const NPY_THRESHOLD: usize = 512 * 512;

/// How the points behind a figure are written.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum DataFormat {
    /// Every point in the CSV table (and in a NumPy file too at [`NPY_THRESHOLD`] values or
    /// more).
    #[default]
    Csv,
    /// The points in a NumPy `.npy` file beside the CSV header.
    Npy,
}

impl DataFormat {
    /// The format's key: `csv`, `npy`.
    pub fn key(self) -> &'static str {
        match self {
            DataFormat::Csv => "csv",
            DataFormat::Npy => "npy",
        }
    }

    /// The format with key `key`.
    pub fn from_key(key: &str) -> Option<Self> {
        [DataFormat::Csv, DataFormat::Npy]
            .into_iter()
            .find(|f| f.key() == key)
    }
}

/// First line of a figure's data file.
const MAGIC: &str = "# hamilton-jacobi figure data";
/// The column header of the table.
const COLUMNS: &str = "panel,series,label,x,y";
/// The column header of the table of a figure with error bands.
const BAND_COLUMNS: &str = "panel,series,label,x,y,lower,upper";
/// The column header of a heat map's table.
const GRID_COLUMNS: &str = "x,y,value";

/// Number of values of the figure's data: cells of its grid, or points of its curves.
pub fn count(fig: &Figure) -> usize {
    match &fig.grid {
        Some(g) => g.values.len(),
        None => fig.curves.iter().map(|c| c.points.len()).sum(),
    }
}

/// A number written so that it reads back exactly (shortest round-trip digits; scientific
/// notation outside 10⁻⁴ … 10¹⁵).
fn num(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e15).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A header value with `\`, line feeds and carriage returns escaped.
fn escape(s: &str) -> String {
    s.replace('\\', "\\\\")
        .replace('\n', "\\n")
        .replace('\r', "\\r")
}

/// Undo [`escape`].
fn unescape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut chars = s.chars();
    while let Some(c) = chars.next() {
        if c != '\\' {
            out.push(c);
            continue;
        }
        match chars.next() {
            Some('n') => out.push('\n'),
            Some('r') => out.push('\r'),
            Some(other) => out.push(other),
            None => out.push('\\'),
        }
    }
    out
}

fn scale_key(s: Scale) -> &'static str {
    match s {
        Scale::Linear => "linear",
        Scale::Log => "log",
    }
}

/// The figure's data file: the header (naming the NumPy file `npy` if given) and, if `table`,
/// every point (or cell).
pub fn to_csv(fig: &Figure, rendered: &Rendered, npy: Option<&str>, table: bool) -> String {
    let mut out = String::new();
    let mut line = |k: &str, v: &str| {
        out.push_str(&format!("# {k}: {}\n", escape(v)));
    };
    line("title", &fig.title);
    line("x", &fig.x_label);
    line("y", &fig.y_label);
    line("x_scale", scale_key(fig.x_scale));
    line("y_scale", scale_key(fig.y_scale));
    line(
        "equal_aspect",
        if fig.equal_aspect { "true" } else { "false" },
    );
    line("size", &fig.size.describe());
    line("caption", &fig.caption);
    for (p, y) in fig.panel_labels.iter().enumerate() {
        line(&format!("panel {p}"), y);
    }
    if let Some(g) = &fig.grid {
        line("grid", &format!("{} x {}", g.nx, g.ny));
        line("grid_x", &format!("{} {}", num(g.x.0), num(g.x.1)));
        line("grid_y", &format!("{} {}", num(g.y.0), num(g.y.1)));
        line("value", &g.label);
        line("value_scale", scale_key(g.scale));
    }
    for n in &rendered.notes {
        line("note", n);
    }
    for (i, c) in fig.curves.iter().enumerate() {
        let band = if c.band.is_empty() { "" } else { BAND };
        line(
            &format!("series {i}"),
            &format!("{}{band}: {}", c.style.key(), c.label),
        );
    }
    if let Some(name) = npy {
        match &fig.grid {
            Some(g) => line(
                "cells",
                &format!(
                    "{name} (float64, shape ({}, {}): rows from the lowest y)",
                    g.ny, g.nx
                ),
            ),
            None => line(
                "points",
                &format!(
                    "{name} (float64, shape ({}, 4): panel, series, x, y)",
                    count(fig)
                ),
            ),
        }
    }
    let columns = if fig.grid.is_some() {
        GRID_COLUMNS
    } else if has_bands(fig) {
        BAND_COLUMNS
    } else {
        COLUMNS
    };
    let mut out = format!("{MAGIC}\n{out}{columns}\n");
    if table {
        if let Some(g) = &fig.grid {
            let xs = g.centres(true, fig.x_scale);
            let ys = g.centres(false, fig.y_scale);
            for (k, y) in ys.iter().enumerate() {
                for (i, x) in xs.iter().enumerate() {
                    out += &format!("{},{},{}\n", num(*x), num(*y), num(g.values[k * g.nx + i]));
                }
            }
        }
        let bands = has_bands(fig);
        for (i, c) in fig.curves.iter().enumerate() {
            let label = csv_field(&c.label);
            for (k, &(x, y)) in c.points.iter().enumerate() {
                out += &format!("{},{i},{label},{},{}", c.panel, num(x), num(y));
                if bands {
                    match c.band.get(k) {
                        Some(&(lo, hi)) => out += &format!(",{},{}", num(lo), num(hi)),
                        None => out += ",,",
                    }
                }
                out.push('\n');
            }
        }
    }
    out
}

/// Marks a series with an error band in the header (`series 0: line+band: label`).
const BAND: &str = "+band";

/// Whether a curve of the figure has an error band.
fn has_bands(fig: &Figure) -> bool {
    fig.curves.iter().any(|c| !c.band.is_empty())
}

/// The figure's values as a NumPy file: a grid's values of shape `(ny, nx)`, or every point
/// (see [`points_npy`]).
pub fn values_npy(fig: &Figure) -> Vec<u8> {
    match &fig.grid {
        Some(g) => npy(&[g.ny, g.nx], &g.values),
        None => points_npy(fig),
    }
}

/// Every point of the figure as a NumPy array of shape `(N, 4)`: panel, series, x, y; with
/// error bands, of shape `(N, 6)` with the lower and upper bound (NaN for curves without one).
pub fn points_npy(fig: &Figure) -> Vec<u8> {
    let n: usize = fig.curves.iter().map(|c| c.points.len()).sum();
    let cols = if has_bands(fig) { 6 } else { 4 };
    let mut values = Vec::with_capacity(cols * n);
    for (i, c) in fig.curves.iter().enumerate() {
        for (k, &(x, y)) in c.points.iter().enumerate() {
            values.extend([c.panel as f64, i as f64, x, y]);
            if cols == 6 {
                let (lo, hi) = c.band.get(k).copied().unwrap_or((f64::NAN, f64::NAN));
                values.extend([lo, hi]);
            }
        }
    }
    npy(&[n, cols], &values)
}

/// A NumPy `.npy` file (format version 1.0) of little-endian `float64` values in C order of
/// the given shape: magic `\x93NUMPY`, version 1.0, the header length, the header dictionary
/// padded with spaces to a multiple of 64 bytes, then the data (NumPy Enhancement Proposal 1).
pub fn npy(shape: &[usize], values: &[f64]) -> Vec<u8> {
    let dims = match shape {
        [n] => format!("({n},)"),
        _ => format!(
            "({})",
            shape
                .iter()
                .map(usize::to_string)
                .collect::<Vec<_>>()
                .join(", ")
        ),
    };
    let mut header = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {dims}, }}");
    let unpadded = 10 + header.len() + 1;
    header.push_str(&" ".repeat(unpadded.next_multiple_of(64) - unpadded));
    header.push('\n');
    let mut out = Vec::with_capacity(10 + header.len() + 8 * values.len());
    out.extend_from_slice(b"\x93NUMPY\x01\x00");
    out.extend_from_slice(&(header.len() as u16).to_le_bytes());
    out.extend_from_slice(header.as_bytes());
    for v in values {
        out.extend_from_slice(&v.to_le_bytes());
    }
    out
}

/// Read a `.npy` file written by [`npy`]: the shape and the values.
///
/// # Errors
/// [`Error::InvalidInput`] if the bytes are not a version 1.0 `<f8` C-order array, or are
/// truncated.
pub fn read_npy(bytes: &[u8]) -> Result<(Vec<usize>, Vec<f64>)> {
    let bad = |why: &str| Error::invalid("NumPy file", why.to_string());
    if bytes.len() < 10 || &bytes[..8] != b"\x93NUMPY\x01\x00" {
        return Err(bad("not a NumPy 1.0 file"));
    }
    let hlen = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = bytes
        .get(10..10 + hlen)
        .and_then(|h| std::str::from_utf8(h).ok())
        .ok_or_else(|| bad("truncated header"))?;
    if !header.contains("'descr': '<f8'") || !header.contains("'fortran_order': False") {
        return Err(bad("expected little-endian float64 in C order"));
    }
    let shape_text = header
        .split("'shape': (")
        .nth(1)
        .and_then(|s| s.split(')').next())
        .ok_or_else(|| bad("no shape"))?;
    let shape: Vec<usize> = shape_text
        .split(',')
        .map(str::trim)
        .filter(|s| !s.is_empty())
        .map(|s| s.parse::<usize>().map_err(|_| bad("bad shape")))
        .collect::<Result<_>>()?;
    let count = shape
        .iter()
        .try_fold(1usize, |a, &d| a.checked_mul(d))
        .ok_or_else(|| bad("shape overflows"))?;
    let data = &bytes[10 + hlen..];
    if count.checked_mul(8) != Some(data.len()) {
        return Err(bad("the data does not match the shape"));
    }
    let values = data
        .chunks_exact(8)
        .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
        .collect();
    Ok((shape, values))
}

/// The records of CSV text (RFC 4180: quoted fields may hold commas, quotes doubled, line
/// breaks); lines starting with `#` outside quotes at the start of a record are skipped.
fn records(text: &str) -> Result<Vec<Vec<String>>> {
    let mut out = Vec::new();
    let mut rec: Vec<String> = Vec::new();
    let mut field = String::new();
    let mut chars = text.chars().peekable();
    let mut at_start = true;
    let mut quoted_field = false;
    while let Some(c) = chars.next() {
        if at_start && c == '#' {
            for c in chars.by_ref() {
                if c == '\n' {
                    break;
                }
            }
            continue;
        }
        at_start = false;
        match c {
            '"' if field.is_empty() && !quoted_field => {
                quoted_field = true;
                loop {
                    match chars.next() {
                        Some('"') if chars.peek() == Some(&'"') => {
                            chars.next();
                            field.push('"');
                        }
                        Some('"') => break,
                        Some(c) => field.push(c),
                        None => {
                            return Err(Error::invalid("CSV data", "unterminated quoted field"))
                        }
                    }
                }
            }
            ',' => {
                rec.push(std::mem::take(&mut field));
                quoted_field = false;
            }
            '\r' if chars.peek() == Some(&'\n') => {}
            '\n' => {
                rec.push(std::mem::take(&mut field));
                out.push(std::mem::take(&mut rec));
                quoted_field = false;
                at_start = true;
            }
            c => field.push(c),
        }
    }
    if !at_start {
        rec.push(field);
        out.push(rec);
    }
    Ok(out)
}

/// Read a figure back from its data file at `path` (and the `.npy` file its header names,
/// beside it): title, axes, scales, size, caption, every curve with its style, label and
/// points. Drawing the result gives the same SVG as the figure that wrote the file.
///
/// # Errors
/// [`Error::InvalidInput`] if a file cannot be read or is not a figure's data file.
pub fn read(path: &Path) -> Result<Figure> {
    let from_npy = path.extension().is_some_and(|e| e == "npy");
    let csv = if from_npy {
        path.with_extension("csv")
    } else {
        path.to_path_buf()
    };
    let text = std::fs::read_to_string(&csv)
        .map_err(|e| Error::invalid(format!("data file {}", csv.display()), e.to_string()))?;
    let dir = csv.parent().unwrap_or(Path::new("."));
    parse(
        &text,
        |name| {
            let p = dir.join(name);
            std::fs::read(&p)
                .map_err(|e| Error::invalid(format!("NumPy file {}", p.display()), e.to_string()))
        },
        from_npy,
    )
}

/// Read a figure from the text of its data file; `npy` reads the points' file a `# points:`
/// line names.
///
/// # Errors
/// [`Error::InvalidInput`] if the text is not a figure's data file.
pub fn from_csv(text: &str, npy: impl Fn(&str) -> Result<Vec<u8>>) -> Result<Figure> {
    parse(text, npy, false)
}

/// Read a figure from the text of its data file, its values from the NumPy file the header
/// names if `from_npy` or if the text has no table.
fn parse(text: &str, npy: impl Fn(&str) -> Result<Vec<u8>>, from_npy: bool) -> Result<Figure> {
    let bad = |why: String| Error::invalid("figure data", why);
    let mut lines = text.lines();
    if lines.next().map(str::trim_end) != Some(MAGIC) {
        return Err(bad(format!("expected the first line {MAGIC:?}")));
    }
    let mut fig = Figure::new("", "", "");
    let mut points_file = None;
    let mut grid = Grid {
        nx: 0,
        ny: 0,
        x: (0.0, 1.0),
        y: (0.0, 1.0),
        values: Vec::new(),
        label: String::new(),
        scale: Scale::Linear,
    };
    let mut has_grid = false;
    let mut banded: Vec<bool> = Vec::new();
    for l in text.lines().skip(1) {
        let Some(rest) = l.strip_prefix("# ") else {
            break;
        };
        let Some((key, value)) = rest.split_once(": ") else {
            return Err(bad(format!("header line without `key: value`: {l:?}")));
        };
        let value = unescape(value.trim_end_matches('\r'));
        let scale = |v: &str| match v {
            "linear" => Ok(Scale::Linear),
            "log" => Ok(Scale::Log),
            _ => Err(bad(format!("unknown scale {v:?}"))),
        };
        match key {
            "title" => fig.title = value,
            "x" => fig.x_label = value,
            "y" => fig.y_label = value,
            "x_scale" => fig.x_scale = scale(&value)?,
            "y_scale" => fig.y_scale = scale(&value)?,
            "equal_aspect" => fig.equal_aspect = value == "true",
            "size" => fig.size = Size::parse(&value)?,
            "caption" => fig.caption = value,
            "points" | "cells" => {
                let name = value.split(" (").next().unwrap_or_default().to_string();
                points_file = Some(name);
            }
            "grid" => {
                let (nx, ny) = value
                    .split_once(" x ")
                    .and_then(|(a, b)| Some((a.trim().parse().ok()?, b.trim().parse().ok()?)))
                    .ok_or_else(|| bad(format!("expected `grid: NX x NY`, found {value:?}")))?;
                grid.nx = nx;
                grid.ny = ny;
                has_grid = true;
            }
            "grid_x" | "grid_y" => {
                let e: Vec<f64> = value
                    .split_whitespace()
                    .map(|v| v.parse::<f64>())
                    .collect::<std::result::Result<_, _>>()
                    .map_err(|_| bad(format!("expected two edges in {l:?}")))?;
                let [a, b] = e[..] else {
                    return Err(bad(format!("expected two edges in {l:?}")));
                };
                if key == "grid_x" {
                    grid.x = (a, b);
                } else {
                    grid.y = (a, b);
                }
            }
            "value" => grid.label = value,
            "value_scale" => grid.scale = scale(&value)?,
            k if k.starts_with("panel ") => {
                if k[6..].parse() != Ok(fig.panel_labels.len()) {
                    return Err(bad(format!("panel out of order in {l:?}")));
                }
                fig.panel_labels.push(value);
            }
            k if k.starts_with("series ") => {
                let i: usize = k[7..]
                    .parse()
                    .map_err(|_| bad(format!("bad series number in {l:?}")))?;
                if i != fig.curves.len() {
                    return Err(bad(format!("series {i} out of order")));
                }
                let (style, label) = value
                    .split_once(": ")
                    .ok_or_else(|| bad(format!("expected `style: label` in {l:?}")))?;
                let (style, band) = match style.strip_suffix(BAND) {
                    Some(s) => (s, true),
                    None => (style, false),
                };
                let style = Style::from_key(style)
                    .ok_or_else(|| bad(format!("unknown style {style:?}")))?;
                fig = fig.curve(label, Vec::new(), style);
                banded.push(band);
            }
            _ => {}
        }
    }
    let mut panels: Vec<(usize, usize)> = Vec::new();
    let bands = banded.contains(&true);
    let mut push = |series: f64, x: f64, y: f64, band: Option<(f64, f64)>| -> Result<()> {
        let i = series as usize;
        match fig.curves.get_mut(i) {
            Some(c) if series == i as f64 => {
                c.points.push((x, y));
                if banded[i] {
                    c.band.push(band.unwrap_or((f64::NAN, f64::NAN)));
                }
                Ok(())
            }
            _ => Err(bad(format!(
                "a point of series {series}, which the header does not name"
            ))),
        }
    };
    let columns = if has_grid {
        GRID_COLUMNS
    } else if bands {
        BAND_COLUMNS
    } else {
        COLUMNS
    };
    let width = if bands { 7 } else { 5 };
    let mut recs = records(text)?.into_iter();
    match recs.next() {
        Some(h) if h.join(",") == columns => {}
        _ => return Err(bad(format!("expected the column header {columns:?}"))),
    }
    let rows: Vec<Vec<String>> = recs.collect();
    let npy_file = match (&points_file, from_npy || rows.is_empty()) {
        (Some(name), true) => Some(name.clone()),
        (None, true) if from_npy => {
            return Err(bad("the data file names no NumPy file".to_string()));
        }
        _ => None,
    };
    if has_grid {
        let n = grid.nx.saturating_mul(grid.ny);
        grid.values = if let Some(name) = npy_file {
            let (shape, values) = read_npy(&npy(&name)?)?;
            if shape != [grid.ny, grid.nx] {
                return Err(bad(format!(
                    "{name}: expected shape ({}, {}), found {shape:?}",
                    grid.ny, grid.nx
                )));
            }
            values
        } else {
            if rows.len() != n {
                return Err(bad(format!(
                    "{} rows for a grid of {} × {} cells",
                    rows.len(),
                    grid.nx,
                    grid.ny
                )));
            }
            rows.iter()
                .enumerate()
                .map(|(k, r)| match &r[..] {
                    [x, y, v] if x.parse::<f64>().is_ok() && y.parse::<f64>().is_ok() => v
                        .parse::<f64>()
                        .map_err(|_| bad(format!("row {}: not a number: {v:?}", k + 1))),
                    _ => Err(bad(format!(
                        "row {}: expected three numbers x, y, value",
                        k + 1
                    ))),
                })
                .collect::<Result<_>>()?
        };
        grid.check().map_err(|e| bad(e.to_string()))?;
        fig.grid = Some(grid);
        return Ok(fig);
    }
    if let Some(name) = npy_file {
        let (shape, values) = read_npy(&npy(&name)?)?;
        let cols = width - 1;
        if shape.len() != 2 || shape[1] != cols {
            return Err(bad(format!(
                "{name}: expected shape (N, {cols}), found {shape:?}"
            )));
        }
        for v in values.chunks_exact(cols) {
            if !(v[0] >= 0.0 && v[0] < 1e6 && v[0].fract() == 0.0) {
                return Err(bad(format!("{name}: not a panel number: {}", v[0])));
            }
            panels.push((v[1] as usize, v[0] as usize));
            push(v[1], v[2], v[3], bands.then(|| (v[4], v[5])))?;
        }
    } else {
        for (k, r) in rows.into_iter().enumerate() {
            if r.len() != width {
                return Err(bad(format!(
                    "row {}: expected {width} fields, found {}",
                    k + 1,
                    r.len()
                )));
            }
            let n = |s: &str| {
                s.parse::<f64>()
                    .map_err(|_| bad(format!("row {}: not a number: {s:?}", k + 1)))
            };
            let panel: usize = r[0]
                .parse()
                .map_err(|_| bad(format!("row {}: not a panel number: {:?}", k + 1, r[0])))?;
            let series = n(&r[1])?;
            panels.push((series as usize, panel));
            let band = if bands && !(r[5].is_empty() && r[6].is_empty()) {
                Some((n(&r[5])?, n(&r[6])?))
            } else {
                None
            };
            push(series, n(&r[3])?, n(&r[4])?, band)?;
        }
    }
    for (series, panel) in panels {
        if let Some(c) = fig.curves.get_mut(series) {
            c.panel = panel;
        }
    }
    Ok(fig)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn npy_header_is_padded_and_reads_back() {
        let v = [1.0, -2.5, f64::NAN, 1e-300, 3.0, 4.0];
        let bytes = npy(&[2, 3], &v);
        let hlen = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert_eq!((10 + hlen) % 64, 0);
        assert_eq!(bytes[10 + hlen - 1], b'\n');
        let (shape, back) = read_npy(&bytes).unwrap();
        assert_eq!(shape, [2, 3]);
        assert_eq!(back.len(), 6);
        assert!(back[2].is_nan() && back[3] == 1e-300 && back[1] == -2.5);
        assert!(read_npy(&bytes[..bytes.len() - 1]).is_err());
        assert!(read_npy(b"nonsense").is_err());
        let one = npy(&[4], &[0.0; 4]);
        assert_eq!((one.len() - 32) % 64, 0);
        assert!(String::from_utf8_lossy(&one[10..one.len() - 32]).contains("'shape': (4,)"));
    }

    #[test]
    fn records_follow_rfc_4180() {
        let text = "# c\na,\"b,\"\"c\"\"\r\nd\", e \n\"\",x\r\n";
        let r = records(text).unwrap();
        assert_eq!(r, [vec!["a", "b,\"c\"\r\nd", " e "], vec!["", "x"]]);
        for s in [
            "plain",
            "a,b",
            "say \"hi\"",
            "cr\rhere",
            "lf\nhere",
            " lead",
            "trail ",
        ] {
            let line = format!("{},{}\n", csv_field(s), csv_field("z"));
            assert_eq!(
                records(&line).unwrap(),
                [vec![s.to_string(), "z".into()]],
                "{s:?}"
            );
        }
        assert!(records("\"open").is_err());
    }

    #[test]
    fn numbers_read_back_exactly() {
        for v in [
            0.0,
            -0.0,
            1.0,
            0.1,
            1e-300,
            5e-324,
            f64::MAX,
            -1.5e17,
            12345.678,
            f64::NAN,
        ] {
            let back: f64 = num(v).parse().unwrap();
            assert!(
                back.to_bits() == v.to_bits() || (v.is_nan() && back.is_nan()),
                "{v}"
            );
        }
    }
}

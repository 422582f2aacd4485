//! Figures: labelled curves (lines, markers, or dots for sections of many points, with error
//! bands) on linear or logarithmic axes, in one panel or a column of panels sharing the
//! horizontal axis, with a legend beside the plotting area; and heat maps with a colour bar. The library returns data; this module (feature `cli`) draws
//! it.
//!
//! A [`Figure`](crate::plot::Figure) is built with a few chained calls and written with
//! [`Figure::write`](crate::plot::Figure::write) — SVG, PNG and PDF at its [`Size`](crate::plot::Size), the data
//! file beside it ([`data`](crate::plot::data)) and the caption — or drawn by
//! [`Figure::render`](crate::plot::Figure::render):
//!
//! ```no_run
//! use hamilton_jacobi::plot::{Figure, Style};
//!
//! let t: Vec<f64> = (0..200).map(|i| i as f64 * 0.1).collect();
//! let drift: Vec<(f64, f64)> = t.iter().map(|&t| (t, 1e-12 * (1.0 + t * t))).collect();
//! Figure::new("energy error", "t", "|ΔE / E|")
//!     .log_y()
//!     .curve("leapfrog, h = 0.1", drift, Style::Line)
//!     .to_svg(std::path::Path::new("energy.svg"))?;
//! # Ok::<(), hamilton_jacobi::Error>(())
//! ```
//!
//! The drawing is laid out on a canvas whose size follows the figure's physical size and font
//! size ([`render`](crate::plot::render)): text keeps its size in points at any figure size.
//!
//! * **Legend.** The legend sits in a column to the right of the plotting area, as wide as the
//!   longest label needs (at most a third of the figure; longer labels are wrapped onto several
//!   lines), so it never covers a curve. Each entry shows the curve's line and/or marker as drawn.
//!   Curves with an empty label have no entry. On a narrow figure (a journal column: less than
//!   about 5 in at 9 pt), or when the entries do not fit beside the plot at full size, the legend
//!   goes below the plot instead, in as many columns as make it lowest, and the figure grows by
//!   its height (at most 1.5 times, [`Size`](crate::plot::Size) limits kept; the remaining entries are then
//!   summarised as "… and N more" and named in the caption), so that the plot keeps its size and
//!   every label its font. A long title is wrapped (at most three lines).
//! * **Colours, dashes and markers.** Curves take the colours of a ten-colour palette in order,
//!   with lines 2 pixels wide: the first ten solid, each further cycle through the palette with
//!   a dash pattern of its own, so that no two curves share colour and dash pattern. Markers
//!   cycle through circle, square, triangle and diamond, shifted by one shape in each cycle
//!   through the colours and open (unfilled) from the fifth cycle on, so that the first eighty
//!   curves with markers differ in colour, shape or fill.
//! * **Error bands.** A curve may carry a lower and an upper bound at each point
//!   ([`Figure::band`](crate::plot::Figure::band)): the band between them is shaded in the
//!   curve's colour under every line (a long band is thinned to its envelope), and its legend
//!   swatch shows the shading.
//! * **Heat maps.** A figure may instead draw a regular grid of values as coloured cells with a
//!   colour bar ([`heat_map`](crate::plot::heat_map)).
//! * **Points that cannot be drawn.** A point with a NaN or infinite coordinate is omitted; so is a
//!   point with a negative coordinate on a logarithmic axis. A line is interrupted where points
//!   were omitted (a point left alone between omitted ones is drawn as a dot), and the curve's
//!   legend label says how many were omitted, e.g. "(3 non-finite points omitted)".
//! * **Zeros on a logarithmic axis.** A coordinate of exactly 0 on a logarithmic axis is drawn at
//!   a floor: the power of ten at least one decade below the smallest positive value on that axis
//!   (10⁻¹⁷ if there is none), and the caption says so (the axis title stays short).
//! * **Coinciding curves.** A line that lies within the line width of an earlier one at every
//!   point is drawn dashed (with a dash length of its own if several coincide with the same
//!   curve), and its legend entry and the caption say which curve it coincides with. Curves
//!   sampled at different abscissae are compared on common abscissae when x increases along both
//!   (each against the other interpolated linearly), so that histories sampled at different
//!   times are recognised too.
//! * **Ranges and ticks.** Ranges cover every drawable point, padded by 5 % of the span on a linear
//!   axis and by a factor 2 on a logarithmic one; a range of a single value is widened (±10 % of
//!   the value, ±1 if it is 0; one decade either side on a logarithmic axis). Logarithmic axes are
//!   labelled at powers of ten (`1e-6`), every few decades if the range is wide, and at 2 and 5
//!   times powers of ten (`2e-6`) if it spans less than three of them; linear axes at multiples of
//!   1, 2 or 5 times a power of ten, with as many digits as the step needs (scientific notation
//!   if the largest label is 10⁵ or more, or below 10⁻³). Tick labels are spaced so that they do
//!   not collide; axis titles too long for their axis are set smaller.
//! * **Equal aspect.** With [`Figure::equal_aspect`](crate::plot::Figure::equal_aspect) one unit
//!   has the same length on both axes (on a logarithmic axis: one decade), the shorter range being
//!   widened about its centre — for orbits and phase portraits.
//! * **Large curves.** A curve with more than [`MAX_DRAWN_POINTS`](crate::plot::MAX_DRAWN_POINTS)
//!   drawable points is thinned for drawing: a line keeps the first, lowest, highest and last
//!   point of every run of consecutive points (so that an oscillation keeps its envelope, without
//!   aliasing), markers every k-th point. With many curves the allowance per curve is lower: the
//!   lines of a figure share 32 000 points (at least 1 000 per curve) and its markers 6 000 (at
//!   least 300 per curve), so that files stay below about a megabyte. The legend entry says how
//!   many points are drawn, the caption how, and the data file keeps them all. Dots
//!   ([`Style::Dots`](crate::plot::Style::Dots)) are never thinned; they are drawn as one path, one dot per canvas unit.
//! * **Errors.** A figure without a single drawable point is an error, not a blank file, as is a
//!   range too wide to represent in floating point.

pub mod data;
pub mod heat_map;
pub mod render;

pub use data::DataFormat;
pub use heat_map::Grid;
pub use render::{Format, Size};

use crate::error::{Error, Result};
use crate::workprecision::Comparison;
use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::text_anchor::{HPos, Pos, VPos};

/// A curve with more drawable points than this is thinned for drawing (every k-th point, plus the
/// first and last point of every unbroken stretch).
pub const MAX_DRAWN_POINTS: usize = 4000;

/// Points of the lines of one figure, shared among the curves drawn with lines (each of them gets
/// at most [`MAX_DRAWN_POINTS`] and at least [`MIN_LINE_POINTS_PER_CURVE`]).
const LINE_BUDGET: usize = 32_000;
/// Every curve drawn with a line may draw at least this many points of it.
const MIN_LINE_POINTS_PER_CURVE: usize = 1000;

/// Markers of one figure, shared among the curves drawn with markers (each of them gets at most
/// [`MAX_DRAWN_POINTS`] and at least [`MIN_MARKERS_PER_CURVE`]).
const MARKER_BUDGET: usize = 6000;
/// Every curve drawn with markers may draw at least this many.
const MIN_MARKERS_PER_CURVE: usize = 300;

/// Where a value of exactly 0 is drawn on a logarithmic axis that has no positive value.
const DEFAULT_ZERO_FLOOR: f64 = 1e-17;

/// The ten-colour palette, in the order curves take it.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// Dash lengths of curves drawn dashed because they coincide with an earlier curve: the k-th
/// curve coinciding with the same earlier one takes entry `k mod 5` (odd lengths, so that no
/// pattern of a coinciding curve is one of the palette's, whose dash lengths are even).
const COINCIDENT_DASHES: [i32; 5] = [7, 3, 11, 5, 9];
/// Opacity of the shading of error bands.
const BAND_OPACITY: f64 = 0.15;
/// Diameter of the dots of [`Style::Dots`], in SVG units.
const DOT_WIDTH: f64 = 2.2;
/// Font family of every text.
const FONT: &str = "sans-serif";
/// Font sizes in SVG pixels: the title.
const TITLE_PX: f64 = 20.0;
/// Axis titles (before shrinking to fit their axis).
const DESC_PX: f64 = 16.0;
/// Tick labels: the base font size of a figure maps to it.
const TICK_PX: f64 = render::BASE_UNITS;
/// Legend labels (before shrinking to fit the height).
const LEGEND_PX: f64 = 14.0;
/// Legend labels shrink no further than this.
const MIN_LEGEND_PX: f64 = 10.0;
/// Figures narrower than this many SVG units (about 5 in at 9 pt) have their legend below the plot.
const NARROW_CANVAS: f64 = 560.0;
/// A vertical axis title that would have to shrink below this goes on two lines of this size.
const MIN_Y_DESC_PX: f64 = 12.0;
/// A wrapped title keeps at most this many lines.
const MAX_TITLE_LINES: usize = 3;
/// Margins of the chart inside its region (top, bottom, left, right), in pixels.
const MARGIN: (u32, u32, u32, u32) = (10, 6, 6, 30);
/// Tick mark length; plotters puts the tick labels twice as far from the axis.
const TICK_LEN: i32 = 5;
/// Legend geometry, in pixels: padding inside the legend box.
const LEGEND_PAD: f64 = 10.0;
/// Length of the line of a legend swatch.
const SWATCH_W: f64 = 30.0;
/// Gap between a legend swatch and its label.
const SWATCH_GAP: f64 = 8.0;
/// Room left beside the legend box within its column.
const LEGEND_OUTER: f64 = 10.0;
/// Line width of the curves.
const STROKE: u32 = 2;
/// Marker radius on a line ([`Style::LineMarkers`]).
const LINE_MARKER_R: i32 = 4;
/// Marker radius without a line ([`Style::Markers`]).
const SCATTER_MARKER_R: i32 = 3;

/// How an axis maps values to positions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Scale {
    /// Uniform.
    #[default]
    Linear,
    /// Logarithmic (base 10): equal ratios at equal distances. Only positive values can be drawn;
    /// zeros are drawn at a floor (see the [module documentation](self)).
    Log,
}

/// How a curve is drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Style {
    /// A polyline through the points.
    #[default]
    Line,
    /// A polyline with a marker at every point (markers of very long curves are thinned).
    LineMarkers,
    /// Markers only (a scatter plot).
    Markers,
    /// Small round dots, one per point, never thinned: Poincaré sections and other clouds of
    /// many points. Drawn as one path of round-capped dots of the line's width, at most one per
    /// SVG unit of the canvas (points closer than that coincide on paper).
    Dots,
}

impl Style {
    /// Whether the points are joined by a line.
    fn line(self) -> bool {
        matches!(self, Style::Line | Style::LineMarkers)
    }

    /// The style's key in data files: `line`, `line-markers`, `markers`, `dots`.
    pub fn key(self) -> &'static str {
        match self {
            Style::Line => "line",
            Style::LineMarkers => "line-markers",
            Style::Markers => "markers",
            Style::Dots => "dots",
        }
    }

    /// The style with key `key`.
    pub fn from_key(key: &str) -> Option<Style> {
        [Style::Line, Style::LineMarkers, Style::Markers, Style::Dots]
            .into_iter()
            .find(|s| s.key() == key)
    }

    /// Whether a marker is drawn at every point.
    fn markers(self) -> bool {
        matches!(self, Style::LineMarkers | Style::Markers)
    }

    /// Radius of the markers, in pixels.
    fn marker_radius(self) -> i32 {
        if self == Style::Markers {
            SCATTER_MARKER_R
        } else {
            LINE_MARKER_R
        }
    }
}

/// One labelled curve: points `(x, y)` in drawing order.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Legend label (no legend entry if empty).
    pub label: String,
    /// The points, in order along the curve.
    pub points: Vec<(f64, f64)>,
    /// Line, markers or both.
    pub style: Style,
    /// The panel the curve is drawn in (0 for a figure of one panel).
    pub panel: usize,
    /// An error band: the lower and upper bound at each point, drawn as a shaded band in the
    /// curve's colour under every line (empty: no band).
    pub band: Vec<(f64, f64)>,
}

/// A figure: title, axis titles and scales, curves. See the [module documentation](self) for how
/// it is drawn.
#[derive(Clone, Debug, PartialEq)]
pub struct Figure {
    /// Title, above the plot (none if empty).
    pub title: String,
    /// Title of the horizontal axis.
    pub x_label: String,
    /// Title of the vertical axis.
    pub y_label: String,
    /// Scale of the horizontal axis.
    pub x_scale: Scale,
    /// Scale of the vertical axis.
    pub y_scale: Scale,
    /// The curves, drawn in order (later curves on top) and listed in the legend in order.
    pub curves: Vec<Curve>,
    /// One unit (one decade on a logarithmic axis) has the same length on both axes.
    pub equal_aspect: bool,
    /// The caption: what the figure shows, in sentences (written beside the figure, with the
    /// notes the drawing adds: zero floors, thinning, coinciding curves).
    pub caption: String,
    /// Physical size and font size.
    pub size: Size,
    /// Vertical axis titles of the panels, from the top, for a figure of several panels sharing
    /// the horizontal axis (see [`Figure::panels`]); empty for one panel titled `y_label`.
    pub panel_labels: Vec<String>,
    /// The grid of a heat map, drawn as coloured cells with a colour bar (see [`heat_map`]); a
    /// figure with a grid has no curves and one panel.
    pub grid: Option<Grid>,
}

/// The work-precision diagram of a [`Comparison`]: error (x, log) against wall time (y, log),
/// one line with markers per series through the fastest time of each sample, legend beside the
/// plot; where samples were timed over several runs, a band shades the range from the fastest
/// run to the median. Errors of exactly 0 are drawn at the plot's zero floor, which the
/// caption states.
pub fn work_precision(c: &Comparison) -> Figure {
    let spread = c
        .series
        .iter()
        .flat_map(|s| &s.samples)
        .any(|x| x.median > x.seconds);
    let fig = Figure::new(&c.title, &c.error_label, "wall time [s]")
        .log_x()
        .log_y();
    let fig = if spread {
        fig.caption(
            "Wall time against error: the line joins the fastest of the repeated runs of each \
             sample; the shaded band reaches up to their median.",
        )
    } else {
        fig
    };
    c.series.iter().fold(fig, |f, s| {
        if spread {
            f.band(
                &s.label,
                s.samples
                    .iter()
                    .map(|x| (x.error, x.seconds, x.seconds, x.median.max(x.seconds))),
                Style::LineMarkers,
            )
        } else {
            f.curve(
                &s.label,
                s.samples.iter().map(|x| (x.error, x.seconds)),
                Style::LineMarkers,
            )
        }
    })
}

impl Figure {
    /// A figure with linear axes and no curves.
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_scale: Scale::Linear,
            y_scale: Scale::Linear,
            curves: Vec::new(),
            equal_aspect: false,
            caption: String::new(),
            size: Size::default(),
            panel_labels: Vec::new(),
            grid: None,
        }
    }

    /// Make the figure a heat map of `grid` (see [`heat_map`]): its cells fill the plotting
    /// area, which spans the grid's edges, and the colour bar stands beside it.
    pub fn heat_map(mut self, grid: Grid) -> Self {
        self.grid = Some(grid);
        self
    }

    /// Set the caption.
    pub fn caption(mut self, caption: impl Into<String>) -> Self {
        self.caption = caption.into();
        self
    }

    /// Set the size.
    pub fn size(mut self, size: Size) -> Self {
        self.size = size;
        self
    }

    /// Make the horizontal axis logarithmic.
    pub fn log_x(mut self) -> Self {
        self.x_scale = Scale::Log;
        self
    }

    /// Make the vertical axis logarithmic.
    pub fn log_y(mut self) -> Self {
        self.y_scale = Scale::Log;
        self
    }

    /// Give one unit the same length on both axes (for orbits and phase portraits).
    pub fn equal_aspect(mut self) -> Self {
        self.equal_aspect = true;
        self
    }

    /// Add a curve.
    pub fn curve(
        self,
        label: impl Into<String>,
        points: impl IntoIterator<Item = (f64, f64)>,
        style: Style,
    ) -> Self {
        self.curve_in(0, label, points, style)
    }

    /// Add a curve to panel `panel` (see [`Figure::panels`]).
    pub fn curve_in(
        self,
        panel: usize,
        label: impl Into<String>,
        points: impl IntoIterator<Item = (f64, f64)>,
        style: Style,
    ) -> Self {
        let points = points.into_iter().map(|(x, y)| (x, f64::NAN, y, f64::NAN));
        let mut fig = self.band_in(panel, label, points, style);
        if let Some(c) = fig.curves.last_mut() {
            c.band.clear();
        }
        fig
    }

    /// Add a curve with an error band: points `(x, lower, y, upper)`, the curve through
    /// `(x, y)` and the band shaded between `(x, lower)` and `(x, upper)`.
    pub fn band(
        self,
        label: impl Into<String>,
        points: impl IntoIterator<Item = (f64, f64, f64, f64)>,
        style: Style,
    ) -> Self {
        self.band_in(0, label, points, style)
    }

    /// Add a curve with an error band to panel `panel` (see [`Figure::band`]).
    pub fn band_in(
        mut self,
        panel: usize,
        label: impl Into<String>,
        points: impl IntoIterator<Item = (f64, f64, f64, f64)>,
        style: Style,
    ) -> Self {
        let (points, band) = points
            .into_iter()
            .map(|(x, lo, y, hi)| ((x, y), (lo, hi)))
            .unzip();
        self.curves.push(Curve {
            label: label.into(),
            points,
            style,
            panel,
            band,
        });
        self
    }

    /// Make the figure a column of panels sharing the horizontal axis, with the given vertical
    /// axis titles (from the top); curves go to a panel with [`Figure::curve_in`]. The title is
    /// above the first panel, the horizontal axis title below the last, and the legend, beside
    /// the first panel, is that of its curves (give every panel the same series, in the same
    /// order, and they keep their colours).
    pub fn panels<S: Into<String>>(mut self, y_labels: impl IntoIterator<Item = S>) -> Self {
        self.panel_labels = y_labels.into_iter().map(Into::into).collect();
        self
    }

    /// Write the figure as an SVG file at `path`. Nothing is written if the figure cannot be drawn
    /// (see [`Figure::render`]).
    ///
    /// # Errors
    /// As [`Figure::render`], or if the file cannot be written.
    pub fn to_svg(&self, path: &std::path::Path) -> Result<()> {
        let svg = self.to_svg_string()?;
        write_file(path, svg.as_bytes())
    }

    /// The figure as SVG text (see [`Figure::render`]).
    ///
    /// # Errors
    /// As [`Figure::render`].
    pub fn to_svg_string(&self) -> Result<String> {
        Ok(self.render()?.svg)
    }

    /// Draw the figure: the SVG, and the notes the drawing adds to the caption. Fails if the
    /// size fails [`Size::check`], if no point of any curve can be drawn, or if a range is too
    /// wide to represent.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the figure.
    pub fn render(&self) -> Result<Rendered> {
        self.size.check()?;
        let (w, h) = self.size.canvas();
        let (layouts, legend) = self.layouts()?;
        let extra = legend.as_ref().map_or(0, |l| l.height);
        let size = Size {
            // To a thousandth of an inch (a third of a pixel at 300 dpi).
            height: (1e3 * self.size.height * f64::from(h + extra) / f64::from(h)).round() / 1e3,
            ..self.size
        };
        let mut svg = String::new();
        let dots = {
            let root = SVGBackend::with_string(&mut svg, (w, h + extra)).into_drawing_area();
            let mut dots = String::new();
            let mut rest = root.clone();
            for l in &layouts {
                let (area, below) = rest.split_vertically(l.height);
                dots += &l.draw(&area).map_err(|e| self.error(e))?;
                rest = below;
            }
            if let Some(legend) = &legend {
                legend.draw(&rest, &layouts[0]).map_err(|e| self.error(e))?;
            }
            root.present().map_err(|e| self.error(e))?;
            dots
        };
        // The physical size; the canvas stays the view box.
        svg = svg.replacen(
            &format!("<svg width=\"{w}\" height=\"{}\"", h + extra),
            &format!(
                "<svg width=\"{}in\" height=\"{}in\"",
                size.width, size.height
            ),
            1,
        );
        if !dots.is_empty() {
            if let Some(end) = svg.rfind("</svg>") {
                svg.insert_str(end, &dots);
            }
        }
        let mut notes: Vec<String> = layouts.into_iter().flat_map(|l| l.notes).collect();
        if let Some(n) = legend.as_ref().and_then(LegendBelow::note) {
            notes.push(n);
        }
        Ok(Rendered { svg, notes, size })
    }

    /// The layouts of the panels, from the top (one for a figure of one panel). Panels share
    /// the canvas width, the legend column and the width of the vertical axes' label area, so
    /// that their horizontal axes line up.
    fn layouts(&self) -> Result<(Vec<Layout>, Option<LegendBelow>)> {
        let side = self.layouts_with(false)?;
        let first = &side[0];
        let (w, h) = self.size.canvas();
        let crowded = first.legend_px < LEGEND_PX || first.legend_more > 0;
        if first.heat.is_some()
            || first.legend.is_empty() && first.legend_more == 0
            || f64::from(w) >= NARROW_CANVAS && !crowded
        {
            return Ok((side, None));
        }
        let below = self.layouts_with(true)?;
        let legend = LegendBelow::new(&below[0], w, f64::from(h) * (self.size.max_growth() - 1.0))?;
        Ok((below, Some(legend)))
    }

    /// [`Figure::layouts`] with the legend beside the first panel or below the figure.
    fn layouts_with(&self, legend_below: bool) -> Result<Vec<Layout>> {
        let (w, h) = self.size.canvas();
        let n_panels = self.panel_labels.len().max(1);
        if let Some(c) = self.curves.iter().find(|c| c.panel >= n_panels) {
            return Err(self.error(format!(
                "the curve {:?} is in panel {}, but the figure has {n_panels} panel(s)",
                c.label, c.panel
            )));
        }
        if self.panel_labels.len() <= 1 {
            let mut fig = self.clone();
            if let Some(y) = self.panel_labels.first() {
                fig.y_label = y.clone();
            }
            return Ok(vec![Layout::new(
                &fig,
                Shared {
                    legend_below,
                    ..Shared::canvas((w, h))
                },
            )?]);
        }
        let n = self.panel_labels.len() as u32;
        let sub: Vec<Figure> = (0..self.panel_labels.len())
            .map(|p| {
                let mut f = Figure::new(
                    if p == 0 {
                        self.title.clone()
                    } else {
                        String::new()
                    },
                    if p + 1 == self.panel_labels.len() {
                        self.x_label.clone()
                    } else {
                        String::new()
                    },
                    self.panel_labels[p].clone(),
                );
                f.x_scale = self.x_scale;
                f.y_scale = self.y_scale;
                f.size = self.size;
                f.curves = self
                    .curves
                    .iter()
                    .filter(|c| c.panel == p)
                    .map(|c| Curve {
                        panel: 0,
                        ..c.clone()
                    })
                    .collect();
                f
            })
            .collect();
        // The first panel carries the title and the legend (which may reach down beside the
        // others), the last the horizontal axis' labels; the plots share the rest equally.
        let legend_h = Some(f64::from(h));
        let first = Layout::new(
            &sub[0],
            Shared {
                legend_h,
                x_labels: false,
                panel: Some(0),
                legend_below,
                ..Shared::canvas((w, h / n))
            },
        )?;
        let extra = x_label_area(true) - x_label_area(false);
        let share = h.saturating_sub(first.title_h + extra) / n;
        let heights: Vec<u32> = (0..n)
            .map(|p| {
                share + if p == 0 { first.title_h } else { 0 } + if p + 1 == n { extra } else { 0 }
            })
            .collect();
        let shared = |y_area: Option<u32>, p: usize| Shared {
            canvas: (w, heights[p]),
            legend_w: Some(first.legend_w),
            y_area,
            legend_h,
            x_labels: p + 1 == n as usize,
            panel: Some(p),
            legend_below,
        };
        let mut layouts: Vec<Layout> = sub
            .iter()
            .enumerate()
            .map(|(p, f)| Layout::new(f, shared(None, p)))
            .collect::<Result<_>>()?;
        let y_area = layouts.iter().map(|l| l.y_area).max();
        if layouts.iter().any(|l| Some(l.y_area) != y_area) {
            layouts = sub
                .iter()
                .enumerate()
                .map(|(p, f)| Layout::new(f, shared(y_area, p)))
                .collect::<Result<_>>()?;
        }
        Ok(layouts)
    }

    /// The caption with the notes of the drawing `r` of this figure.
    pub fn full_caption(&self, r: &Rendered) -> String {
        let mut parts: Vec<&str> = Vec::new();
        if !self.caption.trim().is_empty() {
            parts.push(self.caption.trim());
        }
        parts.extend(r.notes.iter().map(String::as_str));
        parts.join(" ")
    }

    /// Write the figure beside its data: `STEM.svg` and the other `formats` (`STEM.png`,
    /// `STEM.pdf`), the data file `STEM.csv` (with the values also in `STEM.npy` for
    /// [`DataFormat::Npy`] or at [`data::NPY_THRESHOLD`] values or more; see [`data`]) and the
    /// caption `STEM.caption.txt`. Nothing is written if the figure cannot be drawn. Returns the
    /// files written.
    ///
    /// # Errors
    /// As [`Figure::render`], or if a file cannot be rendered or written.
    pub fn write(
        &self,
        stem: &std::path::Path,
        formats: &[Format],
        data: DataFormat,
    ) -> Result<Vec<std::path::PathBuf>> {
        let r = self.render()?;
        let mut files = Vec::new();
        let mut put = |ext: &str, bytes: &[u8]| -> Result<()> {
            let path = with_suffix(stem, ext);
            write_file(&path, bytes)?;
            files.push(path);
            Ok(())
        };
        let mut formats: Vec<Format> = formats.to_vec();
        if !formats.contains(&Format::Svg) {
            formats.insert(0, Format::Svg);
        }
        for f in formats {
            match f {
                Format::Svg => put("svg", r.svg.as_bytes())?,
                Format::Png => put("png", &render::png(&r.svg, &r.size)?)?,
                Format::Pdf => put("pdf", &render::pdf(&r.svg)?)?,
            }
        }
        let caption = self.full_caption(&r);
        let npy = data == DataFormat::Npy || data::count(self) >= data::NPY_THRESHOLD;
        let name = npy.then(|| {
            with_suffix(stem, "npy")
                .file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        });
        if npy {
            put("npy", &data::values_npy(self))?;
        }
        let table = data == DataFormat::Csv;
        put(
            "csv",
            data::to_csv(self, &r, name.as_deref(), table).as_bytes(),
        )?;
        put("caption.txt", format!("{caption}\n").as_bytes())?;
        Ok(files)
    }

    /// How errors name the figure.
    fn what(&self) -> String {
        if self.title.is_empty() {
            "SVG figure".to_string()
        } else {
            format!("SVG figure \"{}\"", self.title)
        }
    }

    /// An [`Error::InvalidInput`] naming the figure.
    fn error(&self, why: impl std::fmt::Display) -> Error {
        Error::invalid(self.what(), why.to_string())
    }
}

// ---------------------------------------------------------------------------------------------
// Preparation: which points are drawn where.

/// A drawn figure: the SVG, and the notes the drawing adds to the caption (zero floors of
/// logarithmic axes, thinned curves, coinciding curves).
#[derive(Clone, Debug, PartialEq)]
pub struct Rendered {
    /// The SVG text.
    pub svg: String,
    /// Notes for the caption, one sentence each.
    pub notes: Vec<String>,
    /// The size drawn: the figure's, taller by the legend when it is drawn below the plot.
    pub size: Size,
}

/// `stem` with `.ext` appended (a stem may contain dots: `kepler-e0.5-orbit`).
pub(crate) fn with_suffix(stem: &std::path::Path, ext: &str) -> std::path::PathBuf {
    let mut s = stem.as_os_str().to_os_string();
    s.push(".");
    s.push(ext);
    std::path::PathBuf::from(s)
}

/// Write `bytes` to `path`, naming the file in the error.
pub(crate) fn write_file(path: &std::path::Path, bytes: &[u8]) -> Result<()> {
    std::fs::write(path, bytes)
        .map_err(|e| Error::invalid(format!("file {}", path.display()), e.to_string()))
}

/// One axis: scale and, on a logarithmic axis with zeros, where the zeros go.
#[derive(Clone, Copy, Debug)]
pub(crate) struct AxisMap {
    scale: Scale,
    floor: f64,
}

impl AxisMap {
    /// Plot coordinate of `v` (log10 on a logarithmic axis); `None` if it cannot be drawn.
    fn map(self, v: f64) -> Option<f64> {
        match self.scale {
            Scale::Linear => Some(v),
            Scale::Log if v > 0.0 => Some(v.log10()),
            Scale::Log if v == 0.0 => Some(self.floor.log10()),
            Scale::Log => None,
        }
    }
}

/// The floor for zeros on a logarithmic axis: the power of ten at least one decade below the
/// smallest positive value, or [`DEFAULT_ZERO_FLOOR`].
fn zero_floor(values: impl Iterator<Item = f64>) -> f64 {
    let min = values
        .filter(|v| v.is_finite() && *v > 0.0)
        .min_by(f64::total_cmp);
    match min {
        None => DEFAULT_ZERO_FLOOR,
        Some(m) => {
            let f = 10f64.powi(m.log10().floor() as i32 - 1);
            if f > 0.0 && f < m {
                f
            } else {
                m
            }
        }
    }
}

/// A curve ready to draw, in plot coordinates: legend label, polylines and dots.
struct Prepared {
    label: String,
    style: Style,
    index: usize,
    /// Unbroken stretches of drawable points.
    segments: Vec<Vec<(f64, f64)>>,
    /// Number of drawable points.
    drawable: usize,
    /// Polylines to draw (stretches of two or more points, thinned); set by [`Prepared::thin`].
    lines: Vec<Vec<(f64, f64)>>,
    /// Markers to draw (thinned), or for a line the points left alone between omitted ones.
    dots: Vec<(f64, f64)>,
    /// The curve lies within the line width of this earlier curve everywhere (drawn dashed).
    coincides_with: Option<usize>,
    /// Dash and gap lengths of the line; `None` for a solid line.
    dash: Option<(u32, u32)>,
    /// Stretches of the error band, `(x, lower, upper)` in plot coordinates, thinned to keep
    /// its envelope.
    bands: Vec<Vec<(f64, f64, f64)>>,
}

impl Prepared {
    /// Sort the points of curve number `index` into drawable stretches, counting the others.
    fn new(index: usize, curve: &Curve, xm: AxisMap, ym: AxisMap) -> Self {
        let (mut non_finite, mut negative) = (0usize, 0usize);
        let mut segments: Vec<Vec<(f64, f64)>> = Vec::new();
        let mut current: Vec<(f64, f64)> = Vec::new();
        for &(x, y) in &curve.points {
            let p = if !(x.is_finite() && y.is_finite()) {
                non_finite += 1;
                None
            } else {
                match (xm.map(x), ym.map(y)) {
                    (Some(px), Some(py)) => Some((px, py)),
                    _ => {
                        negative += 1;
                        None
                    }
                }
            };
            match p {
                Some(p) => current.push(p),
                None if !current.is_empty() => segments.push(std::mem::take(&mut current)),
                None => {}
            }
        }
        if !current.is_empty() {
            segments.push(current);
        }
        let drawable = segments.iter().map(Vec::len).sum();
        let label = legend_label(&curve.label, non_finite, negative);
        let mut bands: Vec<Vec<(f64, f64, f64)>> = Vec::new();
        let mut current: Vec<(f64, f64, f64)> = Vec::new();
        for (&(x, _), &(lo, hi)) in curve.points.iter().zip(&curve.band) {
            let finite = x.is_finite() && lo.is_finite() && hi.is_finite();
            match (finite, xm.map(x), ym.map(lo), ym.map(hi)) {
                (true, Some(px), Some(pl), Some(ph)) => current.push((px, pl, ph)),
                _ if !current.is_empty() => bands.push(std::mem::take(&mut current)),
                _ => {}
            }
        }
        if !current.is_empty() {
            bands.push(current);
        }
        let bands = thin_band(bands, MAX_DRAWN_POINTS);
        Self {
            label,
            style: curve.style,
            index,
            segments,
            drawable,
            lines: Vec::new(),
            dots: Vec::new(),
            coincides_with: None,
            dash: series_dash(index),
            bands,
        }
    }

    /// Choose what is drawn: lines thinned to `line_cap` points, markers to `marker_cap`.
    fn thin(&mut self, line_cap: usize, marker_cap: usize) {
        if self.style.line() {
            self.lines = thin_extremes(&self.segments, line_cap)
                .into_iter()
                .filter(|s| s.len() >= 2)
                .collect();
        }
        self.dots = if self.style == Style::Dots {
            self.segments.concat()
        } else if self.style.markers() {
            thin(&self.segments, marker_cap).concat()
        } else {
            self.segments
                .iter()
                .filter(|s| s.len() == 1)
                .flatten()
                .copied()
                .collect()
        };
    }

    /// Radius of the dots: markers, or a dot the width of the line.
    fn dot_radius(&self) -> i32 {
        match self.style {
            Style::Line | Style::Dots => STROKE as i32,
            s => s.marker_radius(),
        }
    }

    /// The curve's colour ([`dot_color`] for dots, which have no dash pattern to tell cycles
    /// apart).
    fn color(&self) -> RGBColor {
        if self.style == Style::Dots {
            dot_color(self.index)
        } else {
            series_color(self.index)
        }
    }

    /// The curve's marker: shape, and whether it is filled.
    fn marker(&self) -> (Shape, bool) {
        series_marker(self.index)
    }
}

/// The colour of series `i`: the palette's colours in order, cycled.
fn series_color(i: usize) -> RGBColor {
    PALETTE[i % PALETTE.len()]
}

/// The colour of dot series `i` (Poincaré sections: dots have no dash pattern): the palette's
/// colours in the first cycle; in cycle `c ≥ 1` through the palette the colour mixed towards black
/// (odd `c`) or white (even `c`) by `0.3 + 0.15 ⌊(c − 1)/2⌋` (at most 0.75), so that the shades
/// of one palette colour stay apart and no two of the first 60 dot series share a colour.
fn dot_color(i: usize) -> RGBColor {
    let base = series_color(i);
    let c = i / PALETTE.len();
    if c == 0 {
        return base;
    }
    let f = (0.3 + 0.15 * ((c - 1) / 2) as f64).min(0.75);
    let towards = if c % 2 == 1 { 0.0 } else { 255.0 };
    let mix = |v: u8| (f64::from(v) * (1.0 - f) + towards * f).round() as u8;
    RGBColor(mix(base.0), mix(base.1), mix(base.2))
}

/// The dash pattern (dash, gap) of series `i`: solid for the first ten series; each further
/// cycle through the palette's colours takes a dash pattern of its own, cycle `c ≥ 1` dashes of
/// `2 + 4 · ((c − 1) mod 5)` with gaps of `3 + 2 · ⌊(c − 1) / 5⌋` units. No two series share
/// colour and dash pattern.
fn series_dash(i: usize) -> Option<(u32, u32)> {
    let c = i / PALETTE.len();
    if c == 0 {
        return None;
    }
    let k = c - 1;
    let d = 2 + 4 * (k % 5) as u32;
    let g = 3 + 2 * u32::try_from(k / 5).unwrap_or(u32::MAX / 4).min(1000);
    Some((d, g))
}

/// The marker of series `i`: shape `(i + c) mod 4` in cycle `c = ⌊i / 10⌋` through the
/// palette's colours, filled in cycles 0–3, open in cycles 4–7 (and so on): no two of the first
/// eighty series share colour, shape and fill.
fn series_marker(i: usize) -> (Shape, bool) {
    let c = i / PALETTE.len();
    (
        SHAPES[(i + c) % SHAPES.len()],
        (c / SHAPES.len()).is_multiple_of(2),
    )
}

/// How notes name a curve: its label in quotes, or its number.
fn name_of(label: &str, index: usize) -> String {
    if label.is_empty() {
        format!("curve {}", index + 1)
    } else {
        format!("\u{201c}{label}\u{201d}")
    }
}

/// How notes name an axis: its title in quotes.
fn quoted_axis(label: &str) -> String {
    format!("\u{201c}{label}\u{201d}")
}

/// A label with a note in parentheses.
fn with_note(label: &str, note: &str) -> String {
    if label.is_empty() {
        format!("({note})")
    } else {
        format!("{label} ({note})")
    }
}

/// An SVG colour `#RRGGBB`, as plotters writes it.
fn svg_color(c: RGBColor) -> String {
    format!("#{:02X}{:02X}{:02X}", c.0, c.1, c.2)
}

/// The legend label with a note on omitted points.
fn legend_label(label: &str, non_finite: usize, negative: usize) -> String {
    let points = |n: usize| if n == 1 { "point" } else { "points" };
    let note = match (non_finite, negative) {
        (0, 0) => return label.to_string(),
        (n, 0) => format!("{n} non-finite {} omitted", points(n)),
        (0, m) => format!("{m} negative {} omitted", points(m)),
        (n, m) => format!("{n} non-finite and {m} negative {} omitted", points(n + m)),
    };
    if label.is_empty() {
        format!("({note})")
    } else {
        format!("{label} ({note})")
    }
}

/// Whether the polyline `b` lies within the line width of `a` everywhere, given the pixels per
/// unit `px` along x and y (plot coordinates). Curves sampled at the same abscissae are compared
/// point by point. Curves whose abscissae increase along the whole curve (functions of x, such
/// as histories sampled at different times) are compared on common abscissae: each curve's
/// points against the other curve interpolated linearly there, over x-ranges that agree to
/// within the line width; a point of one curve in a gap of the other does not coincide.
fn coincide(a: &[Vec<(f64, f64)>], b: &[Vec<(f64, f64)>], px: (f64, f64)) -> bool {
    let tol = STROKE as f64;
    let close = |ya: f64, yb: f64| (ya - yb).abs() * px.1 < tol;
    if a.len() == b.len()
        && a.iter()
            .zip(b)
            .all(|(sa, sb)| sa.len() == sb.len() && sa.iter().zip(sb).all(|(pa, pb)| pa.0 == pb.0))
    {
        return a
            .iter()
            .zip(b)
            .all(|(sa, sb)| sa.iter().zip(sb).all(|(pa, pb)| close(pa.1, pb.1)));
    }
    let increasing = |c: &[Vec<(f64, f64)>]| {
        let mut prev = f64::NEG_INFINITY;
        c.iter().flatten().all(|p| {
            let up = p.0 > prev;
            prev = p.0;
            up
        })
    };
    let ends = |c: &[Vec<(f64, f64)>]| {
        let first = c.first().and_then(|s| s.first()).map(|p| p.0);
        let last = c.last().and_then(|s| s.last()).map(|p| p.0);
        first.zip(last)
    };
    let (Some((a0, a1)), Some((b0, b1))) = (ends(a), ends(b)) else {
        return false;
    };
    if !(increasing(a) && increasing(b)) {
        // Closed or folded curves (orbits, phase portraits): the same path in the plane.
        return near_path(a, b, px, tol) && near_path(b, a, px, tol);
    }
    if (a0 - b0).abs() * px.0 >= tol || (a1 - b1).abs() * px.0 >= tol {
        return false;
    }
    // Every point of `c` within the line width of `d` interpolated at its abscissa (clamped to
    // d's range, which agrees with c's to within the line width).
    let follows = |c: &[Vec<(f64, f64)>], d: &[Vec<(f64, f64)>]| {
        let (d0, d1) = ends(d).unwrap_or((0.0, 0.0));
        c.iter().flatten().all(|&(x, y)| {
            let x = x.clamp(d0, d1);
            let Some(seg) = d.iter().find(|s| {
                s.first().is_some_and(|p| p.0 <= x) && s.last().is_some_and(|p| p.0 >= x)
            }) else {
                return false;
            };
            let k = seg.partition_point(|p| p.0 < x);
            let yd = match k {
                0 => seg[0].1,
                k if k >= seg.len() => seg[seg.len() - 1].1,
                k => {
                    let (p, q) = (seg[k - 1], seg[k]);
                    p.1 + (q.1 - p.1) * (x - p.0) / (q.0 - p.0)
                }
            };
            close(y, yd)
        })
    };
    follows(b, a) && follows(a, b)
}

/// Whether every point of `c` lies within `tol` pixels of the polyline `d` (`px` pixels per unit
/// along x and y): one direction of the Hausdorff distance of the drawn paths. The segments of
/// `d` are hashed into square cells of side `max(tol, 4)` pixels by walking each segment in
/// half-cell steps, so a point looks only at the segments through its cell and the eight around
/// it (any segment within `tol` of the point passes through one of them): the work is linear in
/// the drawn length, not the product of the point counts.
fn near_path(c: &[Vec<(f64, f64)>], d: &[Vec<(f64, f64)>], px: (f64, f64), tol: f64) -> bool {
    use std::collections::HashMap;
    let to_px = |p: (f64, f64)| (p.0 * px.0, p.1 * px.1);
    let cell = tol.max(4.0);
    let key = |p: (f64, f64)| ((p.0 / cell).floor() as i64, (p.1 / cell).floor() as i64);
    type Segment = ((f64, f64), (f64, f64));
    let mut cells: HashMap<(i64, i64), Vec<Segment>> = HashMap::new();
    let mut pieces = 0usize;
    for seg in d {
        for w in seg.windows(2) {
            let (p, q) = (to_px(w[0]), to_px(w[1]));
            let len = (q.0 - p.0).hypot(q.1 - p.1);
            if !len.is_finite() {
                return false;
            }
            // A segment longer than the canvas many times over is not drawn in pieces: such
            // paths are not compared (bounded work).
            let steps = (2.0 * len / cell).ceil() as usize + 1;
            pieces += steps;
            if pieces > 4_000_000 {
                return false;
            }
            let mut last = None;
            for k in 0..=steps {
                let t = k as f64 / steps as f64;
                let cell_key = key((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
                if last != Some(cell_key) {
                    cells.entry(cell_key).or_default().push((p, q));
                    last = Some(cell_key);
                }
            }
        }
        if seg.len() == 1 {
            let p = to_px(seg[0]);
            cells.entry(key(p)).or_default().push((p, p));
        }
    }
    let distance = |x: (f64, f64), (p, q): Segment| {
        let (dx, dy) = (q.0 - p.0, q.1 - p.1);
        let l2 = dx * dx + dy * dy;
        let t = if l2 > 0.0 {
            (((x.0 - p.0) * dx + (x.1 - p.1) * dy) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (x.0 - p.0 - t * dx).hypot(x.1 - p.1 - t * dy)
    };
    c.iter().flatten().all(|&point| {
        let x = to_px(point);
        let (i, j) = key(x);
        (-1..=1).any(|di| {
            (-1..=1).any(|dj| {
                cells
                    .get(&(i + di, j + dj))
                    .is_some_and(|v| v.iter().any(|&s| distance(x, s) < tol))
            })
        })
    })
}

/// A line thinned to at most `max` points without losing its extremes: the points are taken in
/// runs of `k` consecutive points (within a stretch), and of each run the first, the lowest, the
/// highest and the last are kept, in order. The drawn line covers the full vertical range of
/// every run, so thinning cannot alias an oscillation into spikes or gaps (the "min/max per
/// column" decimation of time-series plotting).
fn thin_extremes(segments: &[Vec<(f64, f64)>], max: usize) -> Vec<Vec<(f64, f64)>> {
    let n: usize = segments.iter().map(Vec::len).sum();
    let max = max.max(8);
    if n <= max {
        return segments.to_vec();
    }
    // At most 4 points per run, plus up to 4 for the partial run at the end of each stretch.
    let runs = (max / 4).saturating_sub(segments.len()).max(1);
    let k = n.div_ceil(runs).max(2);
    segments
        .iter()
        .map(|seg| {
            let mut kept: Vec<(f64, f64)> = Vec::new();
            for run in seg.chunks(k) {
                let last = run.len() - 1;
                let lo = (0..run.len())
                    .min_by(|&a, &b| run[a].1.total_cmp(&run[b].1))
                    .unwrap_or(0);
                let hi = (0..run.len())
                    .max_by(|&a, &b| run[a].1.total_cmp(&run[b].1))
                    .unwrap_or(0);
                let mut idx = [0, lo, hi, last];
                idx.sort_unstable();
                let mut prev = None;
                for i in idx {
                    if prev != Some(i) {
                        kept.push(run[i]);
                        prev = Some(i);
                    }
                }
            }
            kept
        })
        .collect()
}

/// An error band thinned to at most about `max` points: in runs of `k` consecutive points, the
/// first and last abscissa of the run with the run's lowest lower and highest upper bound, so
/// that the drawn band covers the whole band.
fn thin_band(bands: Vec<Vec<(f64, f64, f64)>>, max: usize) -> Vec<Vec<(f64, f64, f64)>> {
    let n: usize = bands.iter().map(Vec::len).sum();
    if n <= max.max(4) {
        return bands;
    }
    let k = n.div_ceil(max.max(4) / 2).max(2);
    bands
        .iter()
        .map(|b| {
            b.chunks(k)
                .flat_map(|run| {
                    let lo = run.iter().map(|p| p.1).fold(f64::INFINITY, f64::min);
                    let hi = run.iter().map(|p| p.2).fold(f64::NEG_INFINITY, f64::max);
                    let (first, last) = (run[0].0, run[run.len() - 1].0);
                    [(first, lo, hi), (last, lo, hi)]
                })
                .collect()
        })
        .collect()
}

/// Every k-th point (k chosen so that at most `max` remain), plus the first and last point of
/// every stretch. Global index runs over all stretches.
fn thin(segments: &[Vec<(f64, f64)>], max: usize) -> Vec<Vec<(f64, f64)>> {
    let n: usize = segments.iter().map(Vec::len).sum();
    let max = max.max(2);
    if n <= max {
        return segments.to_vec();
    }
    let k = n.div_ceil(max - 1);
    let mut g = 0usize;
    segments
        .iter()
        .map(|seg| {
            let last = seg.len().saturating_sub(1);
            let kept = seg
                .iter()
                .enumerate()
                .filter(|&(i, _)| i == 0 || i == last || (g + i).is_multiple_of(k))
                .map(|(_, &p)| p)
                .collect();
            g += seg.len();
            kept
        })
        .collect()
}

// ---------------------------------------------------------------------------------------------
// Ranges and ticks.

/// Padded range of the plot coordinates `lo..=hi`.
fn padded(lo: f64, hi: f64, scale: Scale) -> (f64, f64) {
    match scale {
        Scale::Log => {
            if hi - lo < 1e-9 {
                (lo - 1.0, hi + 1.0)
            } else {
                let p = 2f64.log10();
                (lo - p, hi + p)
            }
        }
        Scale::Linear => {
            let span = hi - lo;
            let mag = lo.abs().max(hi.abs());
            if span <= 1e-12 * mag || span == 0.0 {
                let c = 0.5 * (lo + hi);
                let half = if c == 0.0 { 1.0 } else { 0.1 * c.abs() };
                (c - half, c + half)
            } else {
                (lo - 0.05 * span, hi + 0.05 * span)
            }
        }
    }
}

/// Widen the range of one axis so that both have the same units per pixel.
fn equalise(x: &mut (f64, f64), y: &mut (f64, f64), w: f64, h: f64) {
    let ux = (x.1 - x.0) / w;
    let uy = (y.1 - y.0) / h;
    let widen = |r: &mut (f64, f64), span: f64| {
        let c = 0.5 * (r.0 + r.1);
        *r = (c - 0.5 * span, c + 0.5 * span);
    };
    if ux > uy {
        widen(y, ux * h);
    } else if uy > ux {
        widen(x, uy * w);
    }
}

/// Tick positions (plot coordinates) with labels, and positions of light grid lines.
#[derive(Clone, Debug, Default)]
struct Ticks {
    major: Vec<(f64, String)>,
    light: Vec<f64>,
}

impl Ticks {
    /// The label of the tick at `v`.
    fn label(&self, v: f64) -> String {
        self.major
            .iter()
            .min_by(|a, b| (a.0 - v).abs().total_cmp(&(b.0 - v).abs()))
            .map(|(_, s)| s.clone())
            .unwrap_or_default()
    }

    /// Estimated width of the widest label, in pixels.
    fn max_label_width(&self) -> f64 {
        self.major
            .iter()
            .map(|(_, s)| text_width(s, TICK_PX))
            .fold(0.0, f64::max)
    }

    /// Whether labels `pixels` apart along the axis would collide.
    fn fits(&self, pixels_per_unit: f64, horizontal: bool) -> bool {
        let need = if horizontal {
            self.max_label_width() + 14.0
        } else {
            2.2 * TICK_PX
        };
        self.major
            .windows(2)
            .all(|w| (w[1].0 - w[0].0) * pixels_per_unit >= need)
    }
}

/// A linear plotters coordinate over `lo..hi` with given key points (bold and light).
struct TickedAxis {
    lo: f64,
    hi: f64,
    bold: Vec<f64>,
    light: Vec<f64>,
}

impl TickedAxis {
    /// The coordinate over `range` with the positions of `ticks`.
    fn new(range: (f64, f64), ticks: &Ticks) -> Self {
        Self {
            lo: range.0,
            hi: range.1,
            bold: ticks.major.iter().map(|t| t.0).collect(),
            light: ticks.light.clone(),
        }
    }
}

impl Ranged for TickedAxis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let t = (v - self.lo) / (self.hi - self.lo);
        let len = f64::from(limit.1 - limit.0);
        let p = f64::from(limit.0) + len * t;
        // Far outside points are clamped well beyond the drawing, never wrapped around.
        p.round().clamp(-1e6, 1e6) as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.light.clone()
        } else {
            self.bold.clone()
        }
    }

    fn range(&self) -> std::ops::Range<f64> {
        self.lo..self.hi
    }
}

/// Labels of a linear axis at multiples of `step` = m · 10^e (m ∈ {1, 2, 5}).
fn linear_ticks_with_step(lo: f64, hi: f64, m: f64, e: i32) -> Ticks {
    let step = m * 10f64.powi(e);
    let mut ticks = Ticks::default();
    // A step that underflows (subnormal ranges) or tick indices beyond i64 give no ticks.
    let (a, b) = (lo / step, hi / step);
    if !(step > 0.0 && a.is_finite() && b.is_finite() && a.abs() < 1e15 && b.abs() < 1e15) {
        return ticks;
    }
    let first = a.ceil() as i64;
    let last = b.floor() as i64;
    if last < first || last - first > 200 {
        return ticks;
    }
    let values: Vec<f64> = (first..=last).map(|i| i as f64 * step).collect();
    let max_abs = values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let scientific = !(1e-3..1e5).contains(&max_abs);
    for v in values {
        let v = if v.abs() < 1e-6 * step { 0.0 } else { v };
        let label = if scientific {
            if v == 0.0 {
                "0".to_string()
            } else {
                // Mantissa digits down to the step: 1.5e5, 2e-7.
                let exp = v.abs().log10().floor() as i32;
                format!("{:.*e}", (exp - e).max(0) as usize, v)
            }
        } else {
            format!("{:.*}", (-e).max(0) as usize, v)
        };
        ticks.major.push((v, label));
    }
    let half = 0.5 * step;
    if !((lo / half).abs() < 1e15 && (hi / half).abs() < 1e15) {
        return ticks;
    }
    let first_h = (lo / half).ceil() as i64;
    let last_h = (hi / half).floor() as i64;
    ticks.light = (first_h..=last_h)
        .filter(|i| i.rem_euclid(2) == 1)
        .map(|i| i as f64 * half)
        .collect();
    ticks
}

/// Ticks of a linear axis of `pixels` length: the densest 1-2-5 step that gives at most a couple
/// of labels more than one per 100 (horizontal) or 60 (vertical) pixels, and whose labels do not
/// collide.
fn linear_ticks(lo: f64, hi: f64, pixels: f64, horizontal: bool) -> Ticks {
    let target = (pixels / if horizontal { 100.0 } else { 60.0 }).clamp(3.0, 10.0);
    let raw = (hi - lo) / target;
    let mut e = raw.log10().floor() as i32;
    let f = raw / 10f64.powi(e);
    let ms = [1.0, 2.0, 5.0];
    let mut mi = if f < 2.0 {
        0
    } else if f < 5.0 {
        1
    } else {
        2
    };
    let mut fallback = None;
    for _ in 0..12 {
        let t = linear_ticks_with_step(lo, hi, ms[mi], e);
        let n = t.major.len();
        if n >= 2 && n as f64 <= target + 2.0 && t.fits(pixels / (hi - lo), horizontal) {
            return t;
        }
        if n < 2 {
            break;
        }
        // The sparsest labels with at least two ticks, if none fits.
        fallback = Some(t);
        mi += 1;
        if mi == 3 {
            mi = 0;
            e += 1;
        }
    }
    fallback.unwrap_or_else(|| linear_ticks_with_step(lo, hi, ms[mi], e))
}

/// Label of m · 10^k on a logarithmic axis.
fn log_label(m: i32, k: i32) -> String {
    format!("{m}e{k}")
}

/// Ticks of a logarithmic axis (plot coordinates are log10 of the values).
fn log_ticks(lo: f64, hi: f64, pixels: f64, horizontal: bool) -> Ticks {
    let ppu = pixels / (hi - lo);
    let eps = 1e-9;
    let kmin = (lo - eps).ceil() as i32;
    let kmax = (hi + eps).floor() as i32;
    let inside = |v: f64| v >= lo - eps && v <= hi + eps;
    if kmax - kmin + 1 >= 3 {
        // Powers of ten, every s decades.
        let mut chosen = None;
        for s in [1, 2, 3, 4, 5, 10, 20, 25, 50, 100] {
            let major: Vec<(f64, String)> = (kmin..=kmax)
                .filter(|k| k.rem_euclid(s) == 0)
                .map(|k| (k as f64, log_label(1, k)))
                .collect();
            let t = Ticks {
                major,
                light: Vec::new(),
            };
            if t.major.len() >= 2 && t.fits(ppu, horizontal) {
                chosen = Some((s, t));
                break;
            }
            if t.major.len() < 2 {
                chosen = Some((s, t));
                break;
            }
        }
        let (s, mut t) = chosen.unwrap_or((
            1,
            Ticks {
                major: vec![(kmin as f64, log_label(1, kmin))],
                light: Vec::new(),
            },
        ));
        if s == 1 {
            if ppu >= 50.0 {
                t.light = (kmin - 1..=kmax)
                    .flat_map(|k| (2..=9).map(move |m| (m as f64).log10() + k as f64))
                    .filter(|&v| inside(v))
                    .collect();
            }
        } else {
            t.light = (kmin..=kmax)
                .filter(|k| k.rem_euclid(s) != 0)
                .map(|k| k as f64)
                .collect();
        }
        t
    } else {
        // Less than three powers of ten: label m · 10^k for m in a sub-sequence of 1…9.
        let candidates = |ms: &[i32]| -> Vec<(f64, String)> {
            (kmin - 2..=kmax + 1)
                .flat_map(|k| ms.iter().map(move |&m| (m, k)))
                .map(|(m, k)| ((m as f64).log10() + k as f64, log_label(m, k)))
                .filter(|&(v, _)| inside(v))
                .collect()
        };
        let all: Vec<i32> = (1..=9).collect();
        let mut best = None;
        for ms in [&all[..], &[1, 2, 5], &[1, 3], &[1]] {
            let t = Ticks {
                major: candidates(ms),
                light: Vec::new(),
            };
            if t.major.len() >= 2 && t.fits(ppu, horizontal) {
                best = Some(t);
                break;
            }
        }
        let mut t = best.unwrap_or_else(|| Ticks {
            major: candidates(&[1, 2, 5]),
            light: Vec::new(),
        });
        t.light = candidates(&all)
            .into_iter()
            .map(|(v, _)| v)
            .filter(|v| t.major.iter().all(|(m, _)| (m - v).abs() > 1e-9))
            .collect();
        t
    }
}

/// Ticks of an axis of `pixels` length over `range` (plot coordinates).
fn ticks(scale: Scale, range: (f64, f64), pixels: f64, horizontal: bool) -> Ticks {
    match scale {
        Scale::Linear => linear_ticks(range.0, range.1, pixels, horizontal),
        Scale::Log => log_ticks(range.0, range.1, pixels, horizontal),
    }
}

// ---------------------------------------------------------------------------------------------
// Text measurement and wrapping (estimates for a DejaVu/Arial-like sans-serif font).

/// Estimated advance width of `c`, in ems.
fn char_em(c: char) -> f64 {
    match c {
        'i' | 'j' | 'l' | '\'' | '|' | '.' | ',' | ':' | ';' | '!' => 0.3,
        ' ' | 'f' | 't' | 'r' | 'I' | '(' | ')' | '[' | ']' | '{' | '}' | '/' | '\\' | '-' => 0.4,
        'm' | 'w' | 'M' | 'W' | '%' | '@' | '—' => 0.92,
        'A'..='Z' => 0.72,
        '0'..='9' => 0.64,
        c if (c as u32) >= 0x2E80 => 1.0,
        _ => 0.62,
    }
}

/// Estimated width of `s` in pixels at font size `px`.
fn text_width(s: &str, px: f64) -> f64 {
    s.chars().map(char_em).sum::<f64>() * px
}

/// Break `s` into lines no wider than `max` pixels at size `px`, at whitespace; a word wider than
/// `max` is broken between characters.
fn wrap(s: &str, max: f64, px: f64) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    for word in s.split_whitespace() {
        let candidate = if line.is_empty() {
            word.to_string()
        } else {
            format!("{line} {word}")
        };
        if text_width(&candidate, px) <= max {
            line = candidate;
            continue;
        }
        if !line.is_empty() {
            lines.push(std::mem::take(&mut line));
        }
        // The word alone: break it if it is still too wide.
        for c in word.chars() {
            let mut next = line.clone();
            next.push(c);
            if !line.is_empty() && text_width(&next, px) > max {
                lines.push(std::mem::take(&mut line));
                line.push(c);
            } else {
                line = next;
            }
        }
    }
    if !line.is_empty() {
        lines.push(line);
    }
    lines
}

/// plotters' font size for a size in SVG pixels (its SVG backend writes `size / 1.24`).
fn font(px: f64) -> TextStyle<'static> {
    TextStyle::from((FONT, px * 1.24).into_font()).color(&BLACK)
}

// ---------------------------------------------------------------------------------------------
// Layout and drawing.

/// Marker shapes, cycled through by curve index.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
enum Shape {
    Circle,
    Square,
    Triangle,
    Diamond,
}

/// The order in which curves take marker shapes.
const SHAPES: [Shape; 4] = [
    Shape::Circle,
    Shape::Square,
    Shape::Triangle,
    Shape::Diamond,
];

/// One legend entry: swatch of curve `curve`, wrapped label lines.
struct Entry {
    curve: usize,
    lines: Vec<String>,
}

/// What the panels of one figure share: each panel's canvas (the figure's width, its share of
/// the height), and when given, the legend column's width and the vertical axis label area.
#[derive(Clone, Copy, Debug)]
struct Shared {
    canvas: (u32, u32),
    legend_w: Option<u32>,
    y_area: Option<u32>,
    /// Height the legend may take (default: the panel's).
    legend_h: Option<f64>,
    /// Whether the horizontal axis has tick labels and its title (panels above the last have
    /// neither).
    x_labels: bool,
    /// The panel's number in a figure of several panels (`None` for a figure of one). Only the
    /// first panel has a legend (that of every panel), and notes name the panel.
    panel: Option<usize>,
    /// Whether the legend is drawn below the figure ([`LegendBelow`]) instead of beside it: the
    /// panel then has no legend column.
    legend_below: bool,
}

impl Shared {
    /// A panel of the given canvas, sharing nothing.
    fn canvas(canvas: (u32, u32)) -> Self {
        Self {
            canvas,
            legend_w: None,
            y_area: None,
            legend_h: None,
            x_labels: true,
            panel: None,
            legend_below: false,
        }
    }
}

/// Height of the area below the plot: tick marks, and with labels, tick labels and axis title.
fn x_label_area(labels: bool) -> u32 {
    if labels {
        ((2 * TICK_LEN) as f64 + 1.25 * TICK_PX + 10.0 + 1.3 * DESC_PX).ceil() as u32
    } else {
        (TICK_LEN + 6) as u32
    }
}

/// Everything decided before drawing.
struct Layout {
    /// Whether the horizontal axis is labelled.
    x_labels: bool,
    /// Canvas width and height in SVG units.
    width: u32,
    height: u32,
    /// Notes for the caption.
    notes: Vec<String>,
    title_lines: Vec<String>,
    /// Font size of the title: shrunk on a narrow figure if that saves a line.
    title_px: f64,
    title_h: u32,
    curves: Vec<Prepared>,
    x_desc: String,
    /// The vertical axis title, on two lines when one would have to shrink below
    /// [`MIN_Y_DESC_PX`].
    y_desc: Vec<String>,
    /// Font sizes of the axis titles (x, y): shrunk if longer than their axis.
    desc_px: (f64, f64),
    /// Height of the plotting area in pixels.
    plot_h: f64,
    x_range: (f64, f64),
    y_range: (f64, f64),
    x_ticks: Ticks,
    y_ticks: Ticks,
    x_area: u32,
    y_area: u32,
    legend: Vec<Entry>,
    /// Entries not shown for lack of room.
    legend_more: usize,
    legend_px: f64,
    legend_w: u32,
    /// The heat map, if the figure is one.
    heat: Option<heat_map::Heat>,
}

impl Layout {
    /// Decide everything about the drawing of `fig`; fails if nothing can be drawn.
    fn new(fig: &Figure, shared: Shared) -> Result<Self> {
        let err = |why: &str| fig.error(why);
        let (width, height) = shared.canvas;
        let mut notes: Vec<String> = Vec::new();
        // Zero floors from the points with two finite coordinates.
        let finite = || {
            fig.curves
                .iter()
                .flat_map(|c| c.points.iter())
                .filter(|(x, y)| x.is_finite() && y.is_finite())
        };
        let xm = AxisMap {
            scale: fig.x_scale,
            floor: zero_floor(finite().map(|p| p.0)),
        };
        let ym = AxisMap {
            scale: fig.y_scale,
            floor: zero_floor(finite().map(|p| p.1)),
        };
        let x_zero =
            fig.x_scale == Scale::Log && finite().any(|p| p.0 == 0.0 && ym.map(p.1).is_some());
        let y_zero =
            fig.y_scale == Scale::Log && finite().any(|p| p.1 == 0.0 && xm.map(p.0).is_some());

        if let Some(c) = fig
            .curves
            .iter()
            .find(|c| !c.band.is_empty() && c.band.len() != c.points.len())
        {
            return Err(err(&format!(
                "the band of {} has {} bounds for {} points",
                name_of(&c.label, 0),
                c.band.len(),
                c.points.len()
            )));
        }
        let mut curves: Vec<Prepared> = fig
            .curves
            .iter()
            .enumerate()
            .map(|(i, c)| Prepared::new(i, c, xm, ym))
            .collect();
        let heat = match &fig.grid {
            Some(g) => Some(heat_map::Heat::new(fig, g, xm, ym, &mut notes)?),
            None => None,
        };
        if heat.is_none() && curves.iter().all(|c| c.drawable == 0) {
            return Err(err(if fig.curves.is_empty() {
                "the figure has no curves"
            } else {
                "no curve has a drawable point (all are non-finite, or negative on a logarithmic axis)"
            }));
        }

        // Data ranges in plot coordinates.
        let mut xr = (f64::INFINITY, f64::NEG_INFINITY);
        let mut yr = (f64::INFINITY, f64::NEG_INFINITY);
        for &(x, y) in curves.iter().flat_map(|c| c.segments.iter().flatten()) {
            xr = (xr.0.min(x), xr.1.max(x));
            yr = (yr.0.min(y), yr.1.max(y));
        }
        for &(x, lo, hi) in curves.iter().flat_map(|c| c.bands.iter().flatten()) {
            xr = (xr.0.min(x), xr.1.max(x));
            yr = (yr.0.min(lo.min(hi)), yr.1.max(lo.max(hi)));
        }
        let (x_range, y_range) = match &heat {
            Some(h) => (h.x, h.y),
            None => (
                padded(xr.0, xr.1, fig.x_scale),
                padded(yr.0, yr.1, fig.y_scale),
            ),
        };
        let representable = |r: (f64, f64)| (r.1 - r.0).is_finite() && r.1 > r.0;
        if !representable(x_range) || !representable(y_range) {
            return Err(err("the range of the points is too wide to draw"));
        }

        // Thinning: each kind of drawing shares a budget among the curves that use it.
        let cap = |uses: fn(Style) -> bool, budget: usize, min: usize| {
            let n = curves
                .iter()
                .filter(|c| uses(c.style) && c.drawable > 0)
                .count()
                .max(1);
            (budget / n).clamp(min, MAX_DRAWN_POINTS)
        };
        let line_cap = cap(Style::line, LINE_BUDGET, MIN_LINE_POINTS_PER_CURVE);
        let marker_cap = cap(Style::markers, MARKER_BUDGET, MIN_MARKERS_PER_CURVE);
        for c in &mut curves {
            c.thin(line_cap, marker_cap);
            let lone = c.segments.iter().filter(|s| s.len() == 1).count();
            let line_drawn = c.lines.iter().map(Vec::len).sum::<usize>() + lone;
            let (drawn, what) = if c.style.line() && line_drawn < c.drawable {
                (
                    line_drawn,
                    "the line drawn through the first, lowest, highest and last of every run of \
                     consecutive points",
                )
            } else if c.style.markers() && c.dots.len() < c.drawable {
                (c.dots.len(), "markers at every k-th point")
            } else {
                (c.drawable, "")
            };
            if drawn < c.drawable {
                notes.push(format!(
                    "{}: thinned for drawing, {drawn} of {} points shown ({what}); the data file holds every point.",
                    name_of(&c.label, c.index),
                    c.drawable
                ));
                c.label = with_note(&c.label, &format!("{drawn} of {} points drawn", c.drawable));
            }
        }

        // Zero floors: a note for the caption, not the axis title.
        let floor_note = |axis: &str, m: AxisMap| {
            format!(
                "Zeros of {axis} are drawn at 1e{} (logarithmic axis).",
                (m.floor.log10().round() as i32)
            )
            .replace('-', "\u{2212}")
        };
        if x_zero {
            notes.push(floor_note(&quoted_axis(&fig.x_label), xm));
        }
        if y_zero {
            notes.push(floor_note(&quoted_axis(&fig.y_label), ym));
        }
        let x_desc = fig.x_label.clone();

        // Title: wrapped, at most MAX_TITLE_LINES lines (the last one cut short with "…"); a title
        // of three lines or more shrinks (to the axis titles' size at least) if that saves lines.
        let title_fit = |px: f64| wrap(&fig.title, width as f64 - 40.0, px).len();
        let full = title_fit(TITLE_PX);
        let title_px = (0..=(TITLE_PX - DESC_PX) as usize)
            .map(|k| TITLE_PX - k as f64)
            .find(|&px| {
                title_fit(px)
                    <= if full > MAX_TITLE_LINES {
                        MAX_TITLE_LINES
                    } else {
                        2
                    }
            })
            .filter(|_| full > 2)
            .unwrap_or(TITLE_PX);
        let mut title_lines = wrap(&fig.title, width as f64 - 40.0, title_px);
        if title_lines.len() > MAX_TITLE_LINES {
            title_lines.truncate(MAX_TITLE_LINES);
            if let Some(last) = title_lines.last_mut() {
                while !last.is_empty() && text_width(last, title_px) > width as f64 - 60.0 {
                    last.pop();
                }
                last.push('…');
            }
        }
        let title_h = if title_lines.is_empty() {
            8
        } else {
            (title_lines.len() as f64 * title_px * 1.25 + 14.0).ceil() as u32
        };

        // Legend: column width from the labels, font shrunk if the entries do not fit the height.
        let body_h = (height - title_h) as f64;
        let x_area = x_label_area(shared.x_labels);
        let plot_h = (body_h - (MARGIN.0 + MARGIN.1 + x_area) as f64).max(10.0);
        // The vertical axis title: one line, or two at a smaller size if one line would have to
        // shrink further than that to fit the height of the plot (short panels).
        let y_desc = {
            let shrunk = DESC_PX * plot_h / text_width(&fig.y_label, DESC_PX).max(1.0);
            let two = wrap(&fig.y_label, plot_h, MIN_Y_DESC_PX);
            if shrunk < MIN_Y_DESC_PX && two.len() == 2 {
                two
            } else {
                vec![fig.y_label.clone()]
            }
        };
        let y_desc_lines = y_desc.len() as f64;

        // Curves that lie within the line width of an earlier one everywhere are drawn dashed,
        // and the legend and caption say so. The plot is at most the canvas wide: pixels per
        // unit along x are bounded by the canvas width over the range.
        let px = (
            f64::from(width) / (x_range.1 - x_range.0),
            plot_h / (y_range.1 - y_range.0),
        );
        let mut coinciding = vec![0usize; curves.len()];
        for j in 0..curves.len() {
            if !curves[j].style.line() || curves[j].drawable < 2 {
                continue;
            }
            let same = (0..j).find(|&i| {
                curves[i].style.line()
                    && curves[i].coincides_with.is_none()
                    && coincide(&curves[i].segments, &curves[j].segments, px)
            });
            if let Some(i) = same {
                let other = name_of(&curves[i].label, i);
                let place = if fig.y_label.is_empty() || shared.panel.is_none() {
                    String::new()
                } else {
                    format!("In the panel of {}, ", quoted_axis(&fig.y_label))
                };
                let this = name_of(&curves[j].label, j);
                notes.push(format!(
                    "{place}{this} coincides with {other} to within the line width everywhere \
                     (drawn dashed).",
                ));
                let k = coinciding[i];
                coinciding[i] += 1;
                curves[j].dash = Some((
                    COINCIDENT_DASHES[k % COINCIDENT_DASHES.len()] as u32,
                    5 + 2 * (k / COINCIDENT_DASHES.len()).min(1000) as u32,
                ));
                curves[j].coincides_with = Some(i);
                curves[j].label =
                    with_note(&curves[j].label, &format!("dashed: coincides with {other}"));
            }
        }
        let avail_h = shared.legend_h.unwrap_or(body_h) - MARGIN.0 as f64 - 10.0;
        let max_text_w =
            width as f64 / 3.0 - 2.0 * LEGEND_PAD - SWATCH_W - SWATCH_GAP - LEGEND_OUTER;
        let labelled: Vec<usize> = (0..curves.len())
            .filter(|&i| {
                !curves[i].label.is_empty()
                    && shared.panel.unwrap_or(0) == 0
                    && !(shared.legend_below && heat.is_none())
            })
            .collect();
        let mut legend_px = LEGEND_PX;
        let (legend, legend_more) = loop {
            let entries: Vec<Entry> = labelled
                .iter()
                .map(|&i| Entry {
                    curve: i,
                    lines: wrap(&curves[i].label, max_text_w, legend_px),
                })
                .collect();
            let heights: Vec<f64> = entries
                .iter()
                .map(|e| legend_entry_h(e.lines.len(), legend_px))
                .collect();
            let total: f64 = 2.0 * LEGEND_PAD + heights.iter().sum::<f64>();
            if total <= avail_h {
                break (entries, 0);
            }
            if legend_px > MIN_LEGEND_PX {
                legend_px -= 1.0;
                continue;
            }
            // Keep what fits, leaving a line for "… and N more".
            let mut used = 2.0 * LEGEND_PAD + legend_entry_h(1, legend_px);
            let mut keep = 0;
            for h in &heights {
                if used + h > avail_h {
                    break;
                }
                used += h;
                keep += 1;
            }
            let more = entries.len() - keep;
            let mut entries = entries;
            entries.truncate(keep);
            break (entries, more);
        };
        let text_w = legend
            .iter()
            .flat_map(|e| e.lines.iter())
            .map(|l| text_width(l, legend_px))
            .chain(std::iter::once(if legend_more > 0 {
                text_width(&more_label(legend_more), legend_px)
            } else {
                0.0
            }))
            .fold(0.0, f64::max);
        let legend_w = if let Some(w) = shared.legend_w {
            w
        } else if let Some(h) = &heat {
            h.column_width(plot_h)
        } else if legend.is_empty() && legend_more == 0 {
            0
        } else {
            (2.0 * LEGEND_PAD + SWATCH_W + SWATCH_GAP + text_w + LEGEND_OUTER).ceil() as u32
        };

        // Axes: label areas and ticks, iterated because the width of the y labels decides the
        // width of the plotting area, and with equal aspect the ranges depend on both sizes.
        let region_w = (width - legend_w) as f64;
        let plot_w_for = |y_area: u32| (region_w - (MARGIN.2 + MARGIN.3 + y_area) as f64).max(10.0);
        let axes = |y_area: u32| {
            let plot_w = plot_w_for(y_area);
            let (mut xr, mut yr) = (x_range, y_range);
            if fig.equal_aspect {
                equalise(&mut xr, &mut yr, plot_w, plot_h);
            }
            let yt = ticks(fig.y_scale, yr, plot_h, false);
            let xt = ticks(fig.x_scale, xr, plot_w, true);
            let need = 1.3 * DESC_PX * y_desc_lines
                + 8.0
                + yt.max_label_width()
                + (2 * TICK_LEN) as f64
                + 4.0;
            (xr, yr, xt, yt, need.ceil() as u32)
        };
        let mut y_area = shared.y_area.unwrap_or(60);
        let mut attempt = axes(y_area);
        for _ in 0..4 {
            if attempt.4 <= y_area {
                break;
            }
            y_area = attempt.4.div_ceil(10) * 10;
            attempt = axes(y_area);
        }
        let (x_range, y_range, x_ticks, y_ticks, _) = attempt;
        let plot_w = plot_w_for(y_area);

        // Axis titles shrink if longer than their axis.
        let fit = |s: &str, len: f64| {
            let w = text_width(s, DESC_PX);
            if w > len {
                (DESC_PX * len / w).max(9.0)
            } else {
                DESC_PX
            }
        };
        let desc_px = (
            fit(&x_desc, plot_w),
            if y_desc.len() > 1 {
                MIN_Y_DESC_PX
            } else {
                fit(&y_desc[0], plot_h)
            },
        );
        let mut heat = heat;
        if let Some(h) = &mut heat {
            h.block(plot_w, plot_h, &mut notes);
        }

        Ok(Self {
            x_labels: shared.x_labels,
            width,
            height,
            notes,
            title_lines,
            title_px,
            title_h,
            curves,
            x_desc,
            y_desc,
            desc_px,
            plot_h,
            x_range,
            y_range,
            x_ticks,
            y_ticks,
            x_area,
            y_area,
            legend,
            legend_more,
            legend_px,
            legend_w,
            heat,
        })
    }

    /// Draw title, axes, curves and legend; returns the SVG of the curves drawn as dots (one
    /// path each), to be added to the drawing.
    fn draw<'a>(
        &self,
        root: &DrawingArea<SVGBackend<'a>, Shift>,
    ) -> std::result::Result<
        String,
        DrawingAreaErrorKind<<SVGBackend<'a> as DrawingBackend>::ErrorType>,
    > {
        root.fill(&WHITE)?;
        let title_style = font(self.title_px).pos(Pos::new(HPos::Center, VPos::Top));
        for (i, line) in self.title_lines.iter().enumerate() {
            let y = 8 + (i as f64 * self.title_px * 1.25).round() as i32;
            root.draw_text(line, &title_style, (self.width as i32 / 2, y))?;
        }
        let (_, body) = root.split_vertically(self.title_h);
        let (region, legend_area) = body.split_horizontally(self.width - self.legend_w);

        let x_spec = TickedAxis::new(self.x_range, &self.x_ticks);
        let y_spec = TickedAxis::new(self.y_range, &self.y_ticks);
        let mut chart = ChartBuilder::on(&region)
            .margin_top(MARGIN.0)
            .margin_bottom(MARGIN.1)
            .margin_left(MARGIN.2)
            .margin_right(MARGIN.3)
            .x_label_area_size(self.x_area)
            .y_label_area_size(self.y_area)
            .build_cartesian_2d(x_spec, y_spec)?;
        let fx = |v: &f64| {
            if self.x_labels {
                self.x_ticks.label(*v)
            } else {
                String::new()
            }
        };
        let fy = |v: &f64| self.y_ticks.label(*v);
        chart
            .configure_mesh()
            .set_all_tick_mark_size(TICK_LEN)
            .bold_line_style(BLACK.mix(0.16))
            .light_line_style(BLACK.mix(0.06))
            .axis_style(BLACK)
            .label_style(font(TICK_PX))
            .axis_desc_style(font(self.desc_px.0))
            .x_desc(self.x_desc.as_str())
            .x_label_formatter(&fx)
            .y_label_formatter(&fy)
            .draw()?;
        // The y axis title, at the left edge of the label area, in its own size.
        let y_desc_style = font(self.desc_px.1)
            .transform(FontTransform::Rotate270)
            .pos(Pos::new(HPos::Center, VPos::Top));
        let y_mid = MARGIN.0 as i32 + (0.5 * self.plot_h).round() as i32;
        for (j, line) in self.y_desc.iter().enumerate() {
            let x = MARGIN.2 as f64 + j as f64 * 1.25 * self.desc_px.1;
            region.draw_text(line, &y_desc_style, (x.round() as i32, y_mid))?;
        }

        // Close the frame (the axes draw its left and bottom sides).
        chart.plotting_area().draw(&PathElement::new(
            vec![
                (self.x_range.0, self.y_range.1),
                (self.x_range.1, self.y_range.1),
                (self.x_range.1, self.y_range.0),
            ],
            BLACK.stroke_width(1),
        ))?;

        let mut dot_paths = String::new();
        if let Some(h) = &self.heat {
            // The cells over the grid lines, and the frame over the cells.
            dot_paths += &h.cells(|x, y| chart.backend_coord(&(x, y)));
            let (a, b) = (
                chart.backend_coord(&(self.x_range.0, self.y_range.1)),
                chart.backend_coord(&(self.x_range.1, self.y_range.0)),
            );
            dot_paths += &format!(
                "<rect x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"none\" \
                 stroke=\"#000000\" stroke-width=\"1\"/>\n",
                a.0,
                a.1,
                b.0 - a.0,
                b.1 - a.1
            );
            h.draw_bar(&legend_area, self.plot_h, DESC_PX)?;
        }
        // Error bands under every line.
        for c in &self.curves {
            let fill = c.color().mix(BAND_OPACITY).filled();
            chart.draw_series(c.bands.iter().filter(|b| b.len() >= 2).map(|b| {
                let outline: Vec<(f64, f64)> = b
                    .iter()
                    .map(|p| (p.0, p.1))
                    .chain(b.iter().rev().map(|p| (p.0, p.2)))
                    .collect();
                Polygon::new(outline, fill)
            }))?;
        }
        for c in &self.curves {
            let color = c.color();
            if let Some((d, g)) = c.dash {
                // Dashed lines as SVG dash arrays (one element per stretch), on top of the
                // solid ones.
                for s in &c.lines {
                    let pts: Vec<String> = s
                        .iter()
                        .map(|p| {
                            let (x, y) = chart.backend_coord(p);
                            format!("{x},{y}")
                        })
                        .collect();
                    dot_paths += &format!(
                        "<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"{STROKE}\" \
                         stroke-dasharray=\"{d} {g}\" points=\"{}\"/>\n",
                        svg_color(color),
                        pts.join(" ")
                    );
                }
            } else {
                chart.draw_series(
                    c.lines
                        .iter()
                        .map(|s| PathElement::new(s.clone(), color.stroke_width(STROKE))),
                )?;
            }
            if c.dots.is_empty() {
                continue;
            }
            if c.style == Style::Dots {
                let mut seen = std::collections::HashSet::new();
                let mut d = String::new();
                for p in &c.dots {
                    let (x, y) = chart.backend_coord(p);
                    if seen.insert((x, y)) {
                        d += &format!("M{x} {y}h0");
                    }
                }
                dot_paths += &format!(
                    "<path d=\"{d}\" fill=\"none\" stroke=\"{}\" stroke-width=\"{DOT_WIDTH}\" \
                     stroke-linecap=\"round\"/>\n",
                    svg_color(color)
                );
                continue;
            }
            let r = c.dot_radius();
            let pts = c.dots.iter().copied();
            let (shape, filled) = if c.style.markers() {
                c.marker()
            } else {
                (Shape::Circle, true)
            };
            let style = if filled {
                color.filled()
            } else {
                color.stroke_width(1)
            };
            match shape {
                Shape::Circle => chart.draw_series(
                    pts.map(|p| EmptyElement::at(p) + Circle::new((0, 0), r, style)),
                )?,
                Shape::Square => {
                    let a = r - 1;
                    chart.draw_series(
                        pts.map(|p| {
                            EmptyElement::at(p) + Rectangle::new([(-a, -a), (a, a)], style)
                        }),
                    )?
                }
                Shape::Triangle => chart.draw_series(
                    pts.map(|p| EmptyElement::at(p) + Polygon::new(triangle(r), style)),
                )?,
                Shape::Diamond => chart.draw_series(
                    pts.map(|p| EmptyElement::at(p) + Polygon::new(diamond(r), style)),
                )?,
            };
        }

        self.draw_legend(&legend_area)?;
        Ok(dot_paths)
    }

    /// Draw the legend box in its column.
    fn draw_legend<'a>(
        &self,
        area: &DrawingArea<SVGBackend<'a>, Shift>,
    ) -> std::result::Result<(), DrawingAreaErrorKind<<SVGBackend<'a> as DrawingBackend>::ErrorType>>
    {
        if self.legend_w == 0 || (self.legend.is_empty() && self.legend_more == 0) {
            return Ok(());
        }
        let px = self.legend_px;
        let line_h = legend_line_h(px);
        let box_w = self.legend_w as f64 - LEGEND_OUTER;
        let mut h = 2.0 * LEGEND_PAD
            + self
                .legend
                .iter()
                .map(|e| legend_entry_h(e.lines.len(), px))
                .sum::<f64>();
        if self.legend_more > 0 {
            h += legend_entry_h(1, px);
        }
        h -= legend_gap(px);
        let (x0, y0) = (2i32, MARGIN.0 as i32);
        area.draw(&Rectangle::new(
            [(x0, y0), (x0 + box_w as i32, y0 + h.round() as i32)],
            ShapeStyle::from(&WHITE).filled(),
        ))?;
        area.draw(&Rectangle::new(
            [(x0, y0), (x0 + box_w as i32, y0 + h.round() as i32)],
            BLACK.mix(0.4).stroke_width(1),
        ))?;
        let text_style = font(px).pos(Pos::new(HPos::Left, VPos::Center));
        let sx = x0 as f64 + LEGEND_PAD;
        let tx = (sx + SWATCH_W + SWATCH_GAP).round() as i32;
        let mut y = y0 as f64 + LEGEND_PAD;
        for e in &self.legend {
            let yc = (y + 0.5 * line_h).round() as i32;
            draw_swatch(area, &self.curves[e.curve], sx, yc, line_h)?;
            for (j, line) in e.lines.iter().enumerate() {
                let ly = (y + (j as f64 + 0.5) * line_h).round() as i32;
                area.draw_text(line, &text_style, (tx, ly))?;
            }
            y += legend_entry_h(e.lines.len(), px);
        }
        if self.legend_more > 0 {
            let ly = (y + 0.5 * line_h).round() as i32;
            area.draw_text(&more_label(self.legend_more), &text_style, (tx, ly))?;
        }
        Ok(())
    }
}

/// Draw the legend swatch of curve `c` (its band, line or dashes, dots, marker) starting at `sx`,
/// centred on the row `yc` of a legend line `line_h` high.
fn draw_swatch<'a>(
    area: &DrawingArea<SVGBackend<'a>, Shift>,
    c: &Prepared,
    sx: f64,
    yc: i32,
    line_h: f64,
) -> std::result::Result<(), DrawingAreaErrorKind<<SVGBackend<'a> as DrawingBackend>::ErrorType>> {
    let color = c.color();
    let swatch = vec![(sx as i32, yc), ((sx + SWATCH_W) as i32, yc)];
    if !c.bands.is_empty() {
        let half = (0.4 * line_h).round() as i32;
        area.draw(&Rectangle::new(
            [(sx as i32, yc - half), ((sx + SWATCH_W) as i32, yc + half)],
            color.mix(BAND_OPACITY).filled(),
        ))?;
    }
    match (c.style.line(), c.dash) {
        (true, Some((d, g))) => area.draw(&DashedPathElement::new(
            swatch,
            d,
            g,
            color.stroke_width(STROKE),
        ))?,
        (true, None) => area.draw(&PathElement::new(swatch, color.stroke_width(STROKE)))?,
        _ => {}
    }
    if c.style == Style::Dots {
        for k in 0..3 {
            let at = ((sx + (0.2 + 0.3 * k as f64) * SWATCH_W) as i32, yc);
            area.draw(&Circle::new(at, STROKE as i32, color.filled()))?;
        }
    }
    if c.style.markers() {
        let r = c.style.marker_radius();
        let (shape, filled) = c.marker();
        let style = if filled {
            color.filled()
        } else {
            color.stroke_width(1)
        };
        let at = ((sx + 0.5 * SWATCH_W) as i32, yc);
        match shape {
            Shape::Circle => area.draw(&(EmptyElement::at(at) + Circle::new((0, 0), r, style)))?,
            Shape::Square => {
                let a = r - 1;
                area.draw(&(EmptyElement::at(at) + Rectangle::new([(-a, -a), (a, a)], style)))?
            }
            Shape::Triangle => {
                area.draw(&(EmptyElement::at(at) + Polygon::new(triangle(r), style)))?
            }
            Shape::Diamond => {
                area.draw(&(EmptyElement::at(at) + Polygon::new(diamond(r), style)))?
            }
        }
    }
    Ok(())
}

/// A legend below the plot, for figures too narrow for a legend column beside it (or with more
/// entries than the column holds at full size): the entries in rows of `cols` columns, each label
/// wrapped to its column, at the full legend font. The figure grows by its height (up to a bound,
/// [`Size::max_growth`]; entries beyond it are summarised as "… and N more" and named in the
/// caption).
struct LegendBelow {
    entries: Vec<Entry>,
    /// Entries not shown for lack of room.
    more: usize,
    /// The labels of the entries not shown, for the caption.
    omitted: Vec<String>,
    cols: usize,
    col_w: f64,
    /// Height of each row of entries.
    rows: Vec<f64>,
    /// Height added to the figure, in SVG units.
    height: u32,
}

impl LegendBelow {
    /// Lay out the legend of `first` (the top panel's curves) on a canvas `width` wide, at most
    /// `max_h` high: the number of columns that gives the lowest legend (labels wrapped to their
    /// column, columns no narrower than needed for a short word).
    fn new(first: &Layout, width: u32, max_h: f64) -> Result<Self> {
        let px = LEGEND_PX;
        let labelled: Vec<usize> = (0..first.curves.len())
            .filter(|&i| !first.curves[i].label.is_empty())
            .collect();
        let avail_w = f64::from(width) - 2.0 * f64::from(MARGIN.2) - LEGEND_OUTER;
        let text_w = |cols: usize| avail_w / cols as f64 - 2.0 * LEGEND_PAD - SWATCH_W - SWATCH_GAP;
        let layout = |cols: usize| {
            let entries: Vec<Entry> = labelled
                .iter()
                .map(|&i| Entry {
                    curve: i,
                    lines: wrap(&first.curves[i].label, text_w(cols), px),
                })
                .collect();
            let rows: Vec<f64> = entries
                .chunks(cols)
                .map(|row| {
                    row.iter()
                        .map(|e| legend_entry_h(e.lines.len(), px))
                        .fold(0.0, f64::max)
                })
                .collect();
            (entries, rows)
        };
        let total = |rows: &[f64]| 2.0 * LEGEND_PAD + rows.iter().sum::<f64>() - legend_gap(px);
        let widest = labelled
            .iter()
            .map(|&i| text_width(&first.curves[i].label, px))
            .fold(0.0, f64::max);
        let mut best = (1, layout(1));
        for cols in 2..=labelled.len() {
            // Columns narrower than a short word break words; wider than every label are waste.
            if text_w(cols) < 8.0 * px || text_w(cols - 1) >= widest {
                break;
            }
            let candidate = layout(cols);
            // More columns only if they save at least a line (fewer wrapped labels read better).
            if total(&candidate.1) < total(&best.1 .1) - legend_line_h(px) {
                best = (cols, candidate);
            }
        }
        let (cols, (mut entries, mut rows)) = best;
        // Rows beyond the bound are summarised in one line.
        let mut omitted = Vec::new();
        let mut more = 0;
        if total(&rows) + 2.0 * LEGEND_PAD > max_h {
            let mut used = 2.0 * LEGEND_PAD + legend_entry_h(1, px) + 2.0 * LEGEND_PAD;
            let keep = rows
                .iter()
                .take_while(|h| {
                    used += **h;
                    used <= max_h
                })
                .count();
            rows.truncate(keep);
            let rest = entries.split_off((keep * cols).min(entries.len()));
            more = rest.len();
            omitted = rest
                .iter()
                .map(|e| first.curves[e.curve].label.clone())
                .collect();
            rows.push(legend_entry_h(1, px));
        }
        if entries.is_empty() && more == 0 {
            return Err(Error::invalid("figure legend", "no labelled curve to list"));
        }
        let height = (total(&rows) + 2.0 * LEGEND_PAD).ceil() as u32;
        Ok(Self {
            entries,
            more,
            omitted,
            cols,
            col_w: avail_w / cols as f64,
            rows,
            height,
        })
    }

    /// The caption's note on entries not shown.
    fn note(&self) -> Option<String> {
        (self.more > 0).then(|| {
            format!(
                "The legend omits {} curve(s) for lack of room: {}.",
                self.more,
                self.omitted.join("; ")
            )
        })
    }

    /// Draw the legend in `area` (the strip below the panels), with the swatches of `first`.
    fn draw<'a>(
        &self,
        area: &DrawingArea<SVGBackend<'a>, Shift>,
        first: &Layout,
    ) -> std::result::Result<(), DrawingAreaErrorKind<<SVGBackend<'a> as DrawingBackend>::ErrorType>>
    {
        let px = LEGEND_PX;
        let line_h = legend_line_h(px);
        let used_cols = self.cols.min(self.entries.len().max(1));
        let box_w = (used_cols as f64 * self.col_w).round() as i32;
        let box_h =
            (self.rows.iter().sum::<f64>() - legend_gap(px) + 2.0 * LEGEND_PAD).round() as i32;
        let (x0, y0) = (MARGIN.2 as i32, LEGEND_PAD as i32);
        area.draw(&Rectangle::new(
            [(x0, y0), (x0 + box_w, y0 + box_h)],
            BLACK.mix(0.4).stroke_width(1),
        ))?;
        let text_style = font(px).pos(Pos::new(HPos::Left, VPos::Center));
        let mut y = f64::from(y0) + LEGEND_PAD;
        for (r, row) in self.entries.chunks(self.cols).enumerate() {
            for (k, e) in row.iter().enumerate() {
                let sx = f64::from(x0) + LEGEND_PAD + k as f64 * self.col_w;
                let yc = (y + 0.5 * line_h).round() as i32;
                draw_swatch(area, &first.curves[e.curve], sx, yc, line_h)?;
                let tx = (sx + SWATCH_W + SWATCH_GAP).round() as i32;
                for (j, line) in e.lines.iter().enumerate() {
                    let ly = (y + (j as f64 + 0.5) * line_h).round() as i32;
                    area.draw_text(line, &text_style, (tx, ly))?;
                }
            }
            y += self.rows[r];
        }
        if self.more > 0 {
            let tx = (f64::from(x0) + LEGEND_PAD + SWATCH_W + SWATCH_GAP).round() as i32;
            let ly = (y + 0.5 * line_h).round() as i32;
            area.draw_text(&more_label(self.more), &text_style, (tx, ly))?;
        }
        Ok(())
    }
}

/// Height of a line of legend text.
fn legend_line_h(px: f64) -> f64 {
    1.3 * px
}

/// Vertical gap between legend entries.
fn legend_gap(px: f64) -> f64 {
    0.5 * px
}

/// Height of a legend entry of `lines` lines, including the gap below it.
fn legend_entry_h(lines: usize, px: f64) -> f64 {
    lines.max(1) as f64 * legend_line_h(px) + legend_gap(px)
}

/// The last legend line when `n` entries do not fit.
fn more_label(n: usize) -> String {
    format!("… and {n} more")
}

/// A triangle marker about the origin, for a nominal radius `r`.
fn triangle(r: i32) -> Vec<(i32, i32)> {
    let r = r + 1;
    vec![(0, -r), (r, r - 1), (-r, r - 1)]
}

/// A diamond marker about the origin, for a nominal radius `r`.
fn diamond(r: i32) -> Vec<(i32, i32)> {
    let r = r + 1;
    vec![(0, -r), (r, 0), (0, r), (-r, 0)]
}

/// Unit tests of layout, ticks, legend, thinning and errors.
#[cfg(test)]
mod tests {
    use super::*;

    fn wp_series(points: &[(f64, f64)]) -> crate::workprecision::Series {
        crate::workprecision::Series {
            label: "m".into(),
            knob: "steps".into(),
            samples: points
                .iter()
                .enumerate()
                .map(|(i, &(error, seconds))| crate::workprecision::Sample {
                    knob: i as f64,
                    error,
                    seconds,
                    median: seconds,
                    work: crate::integrate::Work::default(),
                })
                .collect(),
        }
    }

    #[test]
    fn svg_draws_every_series_and_states_the_zero_floor() {
        let mut c = Comparison::new("oscillator", "final error");
        c.push(wp_series(&[(1e-4, 1e-3), (1e-8, 1e-1)]));
        let mut exact = wp_series(&[(0.0, 2e-3), (1e-12, 1e-2)]);
        exact.label = "exact".into();
        c.push(exact);
        let r = work_precision(&c).render().unwrap();
        let svg = r.svg.clone();
        assert!(
            r.notes
                .iter()
                .any(|n| n.contains("final error") && n.contains("drawn at 1e\u{2212}13")),
            "{:?}",
            r.notes
        );
        assert!(!svg.contains("0 drawn at"));
        assert!(svg.contains("wall time [s]"));
        assert!(svg.contains("exact"));
        let path = std::env::temp_dir().join(format!("hj-wp-{}.svg", std::process::id()));
        work_precision(&c).to_svg(&path).unwrap();
        let written = std::fs::read_to_string(&path).unwrap();
        let _ = std::fs::remove_file(&path);
        assert_eq!(written, svg);
        assert!(work_precision(&Comparison::new("empty", "error"))
            .to_svg(&path)
            .is_err());
        assert!(!path.exists());
    }

    /// The contents of the SVG's text elements.
    fn texts(svg: &str) -> Vec<String> {
        svg.split("<text")
            .skip(1)
            .filter_map(|t| {
                let body = &t[t.find('>')? + 1..t.find("</text>")?];
                Some(body.trim().to_string())
            })
            .collect()
    }

    /// Whether `text` is drawn, possibly wrapped over consecutive text elements.
    fn has_text(svg: &str, text: &str) -> bool {
        let escaped = text
            .replace('&', "&amp;")
            .replace('<', "&lt;")
            .replace('>', "&gt;")
            .replace('"', "&quot;")
            .replace('\'', "&apos;");
        texts(svg).join(" ").contains(&escaped)
    }

    /// Number of points of each polyline drawn in `color`.
    fn polyline_points(svg: &str, color: &str) -> Vec<usize> {
        svg.lines()
            .filter(|l| l.contains("<polyline") && l.contains(color))
            .filter_map(|l| {
                let start = l.find("points=\"")? + 8;
                let end = start + l[start..].find('"')?;
                Some(l[start..end].split_whitespace().count())
            })
            .collect()
    }

    #[test]
    fn subnormal_and_huge_ranges_do_not_panic() {
        for pts in [
            vec![(0.0, 1e-310), (1.0, 2e-310)],
            vec![(1e-320, 0.0), (3e-320, 1.0)],
            vec![(0.0, -1e300), (1.0, 1e300)],
        ] {
            let fig = Figure::new("edge", "x", "y").curve("c", pts, Style::Line);
            // Drawn or refused with an error, never a panic.
            let _ = fig.to_svg_string();
        }
    }

    #[test]
    fn svg_has_title_axis_titles_and_every_label() {
        let long = "osculating elements (planetary equations, DOP853)";
        let svg = Figure::new("Kepler, e = 0.9", "time t", "energy E")
            .curve("exact", [(0.0, 1.0), (1.0, 2.0)], Style::Line)
            .curve(
                "RK4 & friends <h>",
                [(0.0, 1.5), (1.0, 2.5)],
                Style::LineMarkers,
            )
            .curve(long, [(0.5, 1.0), (0.7, 2.0)], Style::Markers)
            .to_svg_string()
            .unwrap();
        for text in [
            "Kepler, e = 0.9",
            "time t",
            "energy E",
            "exact",
            "RK4 & friends <h>",
            long,
        ] {
            assert!(has_text(&svg, text), "{text}: {:?}", texts(&svg));
        }
        // The long label is wrapped.
        assert!(!texts(&svg).iter().any(|t| t == long));
    }

    #[test]
    fn log_axis_with_zeros_names_the_floor() {
        let fig = Figure::new("t", "error", "time [s]").log_x().log_y().curve(
            "a",
            [(0.0, 1e-3), (1e-8, 1e-4), (1e-4, 1e-5)],
            Style::LineMarkers,
        );
        let r = fig.render().unwrap();
        // Smallest positive error 1e-8: zeros are drawn a decade lower; the caption says so.
        assert_eq!(
            r.notes,
            ["Zeros of \u{201c}error\u{201d} are drawn at 1e\u{2212}9 (logarithmic axis)."]
        );
        assert!(has_text(&r.svg, "error"));
        assert!(has_text(&r.svg, "time [s]"));
        // Without any positive value the floor is 1e-17.
        let r = Figure::new("t", "x", "y")
            .log_y()
            .curve("a", [(0.0, 0.0), (1.0, 0.0)], Style::Line)
            .render()
            .unwrap();
        assert!(
            r.notes[0].contains("drawn at 1e\u{2212}17"),
            "{:?}",
            r.notes
        );
        assert_eq!(zero_floor([3e-7, 2.0].into_iter()), 1e-8);
        assert_eq!(zero_floor([1e-6].into_iter()), 1e-7);
    }

    #[test]
    fn log_ticks_are_powers_of_ten() {
        let svg = Figure::new("t", "x", "y")
            .log_x()
            .log_y()
            .curve("a", [(1e-10, 1e-6), (1e-2, 1e-3)], Style::Line)
            .to_svg_string()
            .unwrap();
        assert!(has_text(&svg, "1e-6"), "{:?}", texts(&svg));
        assert!(has_text(&svg, "1e-4"));
        // Narrow range: 1-2-5 multiples.
        let t = log_ticks(0.2f64.log10(), 0.9f64.log10(), 500.0, false);
        assert!(t.major.len() >= 2);
        assert!(t.major.iter().all(|(_, l)| l.ends_with("e-1")), "{t:?}");
    }

    #[test]
    fn linear_tick_labels_have_sensible_digits() {
        let t = linear_ticks(0.0, 1.0, 600.0, true);
        let labels: Vec<&str> = t.major.iter().map(|(_, l)| l.as_str()).collect();
        assert_eq!(labels, ["0.0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
        let t = linear_ticks(-3e6, 3e6, 400.0, false);
        assert!(
            t.major.iter().any(|(_, l)| l == "2e6" || l == "1e6"),
            "{t:?}"
        );
        assert!(t.major.iter().any(|(_, l)| l == "0"));
    }

    #[test]
    fn empty_figure_is_an_error() {
        assert!(Figure::new("t", "x", "y").to_svg_string().is_err());
        let nan = Figure::new("t", "x", "y").curve("a", [(f64::NAN, 1.0)], Style::Line);
        assert!(nan.to_svg_string().is_err());
        let negative = Figure::new("t", "x", "y")
            .log_y()
            .curve("a", [(1.0, -1.0)], Style::Line);
        assert!(negative.to_svg_string().is_err());
        // Nothing is written on error.
        let path = std::env::temp_dir().join(format!("hj-plot-empty-{}.svg", std::process::id()));
        assert!(Figure::new("t", "x", "y").to_svg(&path).is_err());
        assert!(!path.exists());
    }

    #[test]
    fn omitted_points_are_counted_in_the_label() {
        let pts = [
            (0.0, 1.0),
            (1.0, f64::NAN),
            (2.0, f64::INFINITY),
            (f64::NEG_INFINITY, 3.0),
            (4.0, 2.0),
        ];
        let svg = Figure::new("t", "x", "y")
            .curve("leapfrog", pts, Style::Line)
            .curve("other", [(0.0, 0.0), (1.0, 1.0)], Style::Line)
            .to_svg_string()
            .unwrap();
        assert!(
            has_text(&svg, "leapfrog (3 non-finite points omitted)"),
            "{:?}",
            texts(&svg)
        );
        assert!(has_text(&svg, "other"));
        let svg = Figure::new("t", "x", "y")
            .log_y()
            .curve("b", [(0.0, -1.0), (1.0, 1.0), (2.0, f64::NAN)], Style::Line)
            .to_svg_string()
            .unwrap();
        assert!(has_text(
            &svg,
            "b (1 non-finite and 1 negative points omitted)"
        ));
    }

    #[test]
    fn large_curves_are_thinned() {
        let n = 100_000;
        let line: Vec<(f64, f64)> = (0..n)
            .map(|i| (i as f64, (i as f64 * 1e-3).sin()))
            .collect();
        let svg = Figure::new("t", "x", "y")
            .curve("big", line.clone(), Style::Line)
            .to_svg_string()
            .unwrap();
        let counts = polyline_points(&svg, "#1F77B4");
        let drawn: usize = counts.iter().sum::<usize>() - 2; // minus the legend swatch
        assert!(drawn <= MAX_DRAWN_POINTS, "{counts:?}");
        assert!(drawn > MAX_DRAWN_POINTS / 2);
        assert!(svg.len() < 1_000_000, "{}", svg.len());

        let mut fig = Figure::new("t", "x", "y");
        for k in 0..4 {
            fig = fig.curve(format!("c{k}"), line.clone(), Style::LineMarkers);
        }
        let svg = fig.to_svg_string().unwrap();
        let circles = svg.matches("<circle").count();
        assert!(circles <= MARKER_BUDGET / 4 + 1, "{circles}");
        assert!(svg.len() < 1_000_000, "{}", svg.len());

        // Thinning keeps the ends of every stretch.
        let segs = vec![(0..10).map(|i| (i as f64, 0.0)).collect::<Vec<_>>(); 3];
        let t = thin(&segs, 10);
        assert!(t
            .iter()
            .all(|s| s.first() == Some(&(0.0, 0.0)) && s.last() == Some(&(9.0, 0.0))));
        assert!(t.iter().map(Vec::len).sum::<usize>() < 30);
    }

    #[test]
    fn equal_aspect_gives_equal_units() {
        let mut x = (0.0, 1.0);
        let mut y = (0.0, 4.0);
        equalise(&mut x, &mut y, 600.0, 400.0);
        assert_eq!(y, (0.0, 4.0));
        assert!(((x.1 - x.0) / 600.0 - 4.0 / 400.0).abs() < 1e-12);
        assert!((x.0 + x.1 - 1.0).abs() < 1e-12);
        let ellipse: Vec<(f64, f64)> = (0..=100)
            .map(|i| {
                let t = i as f64 * std::f64::consts::TAU / 100.0;
                (3.0 * t.cos(), t.sin())
            })
            .collect();
        let fig =
            Figure::new("orbit", "x", "y")
                .equal_aspect()
                .curve("ellipse", ellipse, Style::Line);
        let layout = Layout::new(&fig, Shared::canvas(fig.size.canvas())).unwrap();
        let plot_w = (layout.width - layout.legend_w - MARGIN.2 - MARGIN.3 - layout.y_area) as f64;
        let plot_h = (layout.height - layout.title_h - MARGIN.0 - MARGIN.1 - layout.x_area) as f64;
        let ux = (layout.x_range.1 - layout.x_range.0) / plot_w;
        let uy = (layout.y_range.1 - layout.y_range.0) / plot_h;
        assert!((ux / uy - 1.0).abs() < 1e-9, "{ux} {uy}");
    }

    #[test]
    fn degenerate_ranges_are_widened() {
        let svg = Figure::new("t", "x", "y")
            .curve("one point", [(2.0, 5.0)], Style::Markers)
            .to_svg_string()
            .unwrap();
        assert!(svg.contains("<circle"));
        let svg = Figure::new("t", "x", "y")
            .log_x()
            .log_y()
            .curve("flat", [(1e-3, 0.0), (1e-3, 0.0)], Style::Line)
            .to_svg_string()
            .unwrap();
        assert!(has_text(&svg, "flat"));
        assert_eq!(padded(0.0, 0.0, Scale::Linear), (-1.0, 1.0));
        assert!(Figure::new("t", "x", "y")
            .curve("huge", [(-f64::MAX, 0.0), (f64::MAX, 1.0)], Style::Line)
            .to_svg_string()
            .is_err());
    }

    #[test]
    fn wrapping_respects_the_width() {
        let lines = wrap(
            "osculating elements (planetary equations, DOP853)",
            200.0,
            14.0,
        );
        assert!(lines.len() >= 2);
        assert!(lines.iter().all(|l| text_width(l, 14.0) <= 200.0));
        let lines = wrap("averyveryveryveryveryveryveryverylongword", 100.0, 14.0);
        assert!(lines.len() >= 2);
        assert!(lines.iter().all(|l| text_width(l, 14.0) <= 100.0));
    }

    /// A figure with every kind of curve, thinning, zeros on a log axis and awkward labels.
    fn busy_figure() -> Figure {
        let long: Vec<(f64, f64)> = (0..20_000)
            .map(|i| {
                let t = i as f64 * 0.01;
                (t, 1e-12 * (1.0 + t) * (1.0 + (37.0 * t).sin().abs()))
            })
            .collect();
        Figure::new("busy, \"quoted\"\nand broken", "t", "|ΔE/E|")
            .log_y()
            .caption("A caption, with a comma.")
            .curve("thinned, \"label\"\r\n", long.clone(), Style::Line)
            .curve(" padded ", long, Style::Line)
            .curve(
                "zeros",
                [(0.0, 0.0), (1.0, 1e-10), (2.0, f64::NAN)],
                Style::LineMarkers,
            )
            .curve("dots", [(3.0, 1e-9), (4.0, 2e-9)], Style::Dots)
            .band(
                "band",
                (0..6000).map(|i| {
                    let t = i as f64 * 0.03;
                    let y = 1e-8 * (1.0 + 0.5 * (3.0 * t).sin());
                    (t, 0.5 * y, y, if i == 7 { f64::NAN } else { 2.0 * y })
                }),
                Style::Line,
            )
            .size(Size::column())
    }

    #[test]
    fn data_file_holds_every_point_and_redraws_the_same_svg() {
        let fig = busy_figure();
        let r = fig.render().unwrap();
        // The long curves are thinned for drawing; the notes say so; the second coincides.
        assert!(
            r.notes.iter().any(|n| n.contains("thinned for drawing")),
            "{:?}",
            r.notes
        );
        assert!(
            r.notes.iter().any(|n| n.contains("coincides with")),
            "{:?}",
            r.notes
        );
        assert!(
            r.notes.iter().any(|n| n.contains("Zeros of")),
            "{:?}",
            r.notes
        );
        for format in [DataFormat::Csv, DataFormat::Npy] {
            let dir = std::env::temp_dir().join(format!(
                "hj-plot-data-{}-{}",
                std::process::id(),
                format.key()
            ));
            std::fs::create_dir_all(&dir).unwrap();
            let stem = dir.join("busy.fig");
            let files = fig.write(&stem, &[Format::Svg], format).unwrap();
            assert!(files.iter().any(|f| f.ends_with("busy.fig.caption.txt")));
            let back = data::read(&with_suffix(&stem, "csv")).unwrap();
            assert_eq!(back.curves.len(), fig.curves.len());
            for (a, b) in back.curves.iter().zip(&fig.curves) {
                assert_eq!(a.label, b.label);
                assert_eq!(a.style, b.style);
                assert_eq!(a.points.len(), b.points.len());
                assert_eq!(a.band.len(), b.band.len());
                for (p, q) in a.band.iter().zip(&b.band) {
                    let same =
                        |u: f64, v: f64| u.to_bits() == v.to_bits() || (u.is_nan() && v.is_nan());
                    assert!(same(p.0, q.0) && same(p.1, q.1));
                }
                for (p, q) in a.points.iter().zip(&b.points) {
                    assert!(p.0.to_bits() == q.0.to_bits());
                    assert!(p.1.to_bits() == q.1.to_bits() || (p.1.is_nan() && q.1.is_nan()));
                }
            }
            let svg = std::fs::read_to_string(with_suffix(&stem, "svg")).unwrap();
            assert_eq!(back.to_svg_string().unwrap(), svg);
            let _ = std::fs::remove_dir_all(&dir);
        }
    }

    #[test]
    fn sections_of_many_points_are_one_compact_path() {
        // A quasi-periodic cloud of 10^5 points.
        let pts: Vec<(f64, f64)> = (0..100_000)
            .map(|i| {
                let a = i as f64 * 0.618_033_988_749_895 * std::f64::consts::TAU;
                let r = 0.2 + 0.1 * (i % 7) as f64;
                (r * a.cos(), 0.5 * r * a.sin())
            })
            .collect();
        let svg = Figure::new("section", "y", "p_y")
            .equal_aspect()
            .curve("orbit", pts, Style::Dots)
            .to_svg_string()
            .unwrap();
        assert_eq!(svg.matches("stroke-linecap=\"round\"").count(), 1);
        assert!(svg.len() < 2_000_000, "{}", svg.len());
        assert!(svg.contains("width=\"6.4in\""));
    }

    #[test]
    fn png_and_pdf_are_rendered_from_the_svg() {
        let fig = busy_figure();
        let r = fig.render().unwrap();
        let svg = r.svg;
        let png = render::png(&svg, &r.size).unwrap();
        assert_eq!(&png[1..4], b"PNG");
        // Width and height in the IHDR chunk: 3.4 in × 2.4 in at 300 dpi, taller by the legend
        // below the plot.
        let w = u32::from_be_bytes([png[16], png[17], png[18], png[19]]);
        let h = u32::from_be_bytes([png[20], png[21], png[22], png[23]]);
        assert_eq!((w, h), r.size.pixels());
        assert!(w == 1020 && h > 720, "{w} × {h}");
        let pdf = render::pdf(&svg).unwrap();
        assert!(pdf.starts_with(b"%PDF"));
        assert!(render::png("<svg", &fig.size).is_err());
    }

    #[test]
    fn a_narrow_figure_has_its_legend_below_the_plot_in_full() {
        let t: Vec<f64> = (0..100).map(|i| i as f64 * 0.1).collect();
        let labels: Vec<String> = (0..12)
            .map(|k| format!("method number {k} (order {}, {} stages)", k + 2, 3 * k + 1))
            .collect();
        let mut fig = Figure::new("a column figure with many curves", "t", "y");
        fig.size = Size::column();
        for (k, l) in labels.iter().enumerate() {
            fig = fig.curve(
                l.clone(),
                t.iter().map(|&t| (t, (t + k as f64).sin())),
                Style::Line,
            );
        }
        let (layouts, legend) = fig.layouts().unwrap();
        let legend = legend.expect("a narrow figure has its legend below");
        // No legend column: the plot takes the width; every entry is listed.
        assert_eq!(layouts[0].legend_w, 0);
        assert_eq!(legend.entries.len(), labels.len());
        assert_eq!(legend.more, 0);
        assert!(legend.cols >= 1);
        let r = fig.render().unwrap();
        // Every label is drawn whole, at the full legend font, no word broken across lines.
        let all = texts(&r.svg);
        for l in &labels {
            assert!(has_text(&r.svg, l), "{l}");
        }
        for word in labels.iter().flat_map(|l| l.split_whitespace()) {
            assert!(
                all.iter().any(|t| t.split_whitespace().any(|w| w == word)),
                "{word}"
            );
        }
        assert!(!r.svg.contains("more"));
        // The figure grew by the legend's height, its width did not change.
        let (w, h) = fig.size.canvas();
        assert!(r
            .svg
            .contains(&format!("viewBox=\"0 0 {w} {}\"", h + legend.height)));
        assert!(r.size.width == fig.size.width && r.size.height > fig.size.height);
        let grown = fig.size.height * f64::from(h + legend.height) / f64::from(h);
        assert!(
            (r.size.height - grown).abs() <= 5e-4,
            "{} {grown}",
            r.size.height
        );
        // A page-wide figure with a few labels keeps the legend beside the plot.
        let mut wide = fig.clone();
        wide.size = Size::default();
        wide.curves.truncate(3);
        let (l, below) = wide.layouts().unwrap();
        assert!(below.is_none() && l[0].legend_w > 0);
        // So many labels that even the taller figure cannot hold them: summarised and named.
        let mut crowded = fig.clone();
        for k in 0..200 {
            crowded = crowded.curve(
                format!("extra curve {k}"),
                [(0.0, 0.0), (1.0, 1.0)],
                Style::Line,
            );
        }
        let r = crowded.render().unwrap();
        assert!(r.size.height <= fig.size.height * 2.5 + 1e-12);
        assert!(r.notes.iter().any(|n| n.contains("extra curve 199")));
        assert!(has_text(&r.svg, "more"));
    }

    #[test]
    fn panels_share_the_horizontal_axis_and_read_back() {
        let t: Vec<f64> = (0..200).map(|i| i as f64 * 0.1).collect();
        let mut fig = Figure::new("elements", "t", "").panels(["a", "e", "Ω"]);
        for (p, f) in [1.0, 0.1, -0.01].into_iter().enumerate() {
            fig = fig
                .curve_in(
                    p,
                    "truth",
                    t.iter().map(|&t| (t, f * t + (5.0 * t).sin() * 1e-3)),
                    Style::Line,
                )
                .curve_in(p, "theory", t.iter().map(|&t| (t, f * t)), Style::Line);
        }
        let r = fig.render().unwrap();
        assert!(has_text(&r.svg, "Ω") && has_text(&r.svg, "truth") && has_text(&r.svg, "elements"));
        // One legend: two entries.
        assert_eq!(texts(&r.svg).iter().filter(|t| *t == "truth").count(), 1);
        let (layouts, _) = fig.layouts().unwrap();
        assert_eq!(layouts.len(), 3);
        assert!(layouts
            .iter()
            .all(|l| l.y_area == layouts[0].y_area && l.legend_w == layouts[0].legend_w));
        let heights: u32 = layouts.iter().map(|l| l.height).sum();
        assert!(heights <= fig.size.canvas().1);
        let back = data::from_csv(&data::to_csv(&fig, &r, None, true), |_| Ok(Vec::new())).unwrap();
        assert_eq!(back, fig);
        assert!(Figure::new("t", "x", "")
            .panels(["a"])
            .curve_in(3, "lost", [(0.0, 1.0)], Style::Line)
            .render()
            .is_err());
    }

    /// A heat map of `n × m` cells of `exp(−r²)` on a logarithmic colour scale, with NaN cells.
    fn heat_figure(nx: usize, ny: usize) -> Figure {
        let mut v = Vec::with_capacity(nx * ny);
        for k in 0..ny {
            for i in 0..nx {
                let (x, y) = (
                    -2.0 + 4.0 * (i as f64 + 0.5) / nx as f64,
                    -1.0 + 2.0 * (k as f64 + 0.5) / ny as f64,
                );
                v.push(if i == k {
                    f64::NAN
                } else {
                    (-(x * x + y * y)).exp()
                });
            }
        }
        Figure::new("density", "q", "p")
            .caption("A Gaussian bump.")
            .heat_map(
                Grid::new(nx, ny, (-2.0, 2.0), (-1.0, 1.0), v)
                    .unwrap()
                    .label("ρ(q, p)")
                    .log(),
            )
            .size(Size::column())
    }

    #[test]
    fn heat_maps_draw_cells_colour_bar_and_missing_values() {
        let fig = heat_figure(40, 20);
        let r = fig.render().unwrap();
        // One path per colour; the NaN cells in light grey, said in the caption and the bar.
        assert!(r.svg.contains("fill=\"#D9D9D9\""));
        assert!(has_text(&r.svg, "no value"), "{:?}", texts(&r.svg));
        assert!(has_text(&r.svg, "ρ(q, p)"));
        assert!(
            r.notes
                .iter()
                .any(|n| n.contains("20 of 800 cells have no value")),
            "{:?}",
            r.notes
        );
        // The largest value (≈ e^{-0.0025}) is the top of viridis, the smallest its bottom.
        assert!(r.svg.contains("fill=\"#FDE725\"") && r.svg.contains("fill=\"#440154\""));
        // Curves and heat maps do not mix; a grid of bad size is refused.
        assert!(heat_figure(4, 4)
            .curve("c", [(0.0, 0.0)], Style::Line)
            .render()
            .is_err());
        let mut bad = heat_figure(4, 4);
        if let Some(g) = &mut bad.grid {
            g.values.pop();
        }
        assert!(bad.render().is_err());
        // Cells beyond the plot's resolution are drawn in blocks; the caption says so.
        let r = heat_figure(1500, 30).render().unwrap();
        assert!(
            r.notes.iter().any(|n| n.contains("drawn in blocks of")),
            "{:?}",
            r.notes
        );
        assert!(r.svg.len() < 1_000_000, "{}", r.svg.len());
    }

    #[test]
    fn heat_map_data_holds_every_cell_and_redraws_the_same_svg() {
        // Below the threshold the CSV holds every cell; at 512 × 512 a NumPy file is written too,
        // and the figure redraws from either.
        for (nx, ny, npy) in [(30, 20, false), (512, 512, true)] {
            let fig = heat_figure(nx, ny);
            let dir = std::env::temp_dir().join(format!("hj-heat-{}-{nx}", std::process::id()));
            std::fs::create_dir_all(&dir).unwrap();
            let stem = dir.join("heat");
            let files = fig.write(&stem, &[Format::Svg], DataFormat::Csv).unwrap();
            assert_eq!(
                files.iter().any(|f| f.ends_with("heat.npy")),
                npy,
                "{files:?}"
            );
            let svg = std::fs::read_to_string(with_suffix(&stem, "svg")).unwrap();
            let csv = std::fs::read_to_string(with_suffix(&stem, "csv")).unwrap();
            assert_eq!(
                csv.lines().filter(|l| !l.starts_with('#')).count(),
                1 + nx * ny
            );
            let mut routes = vec![with_suffix(&stem, "csv")];
            if npy {
                routes.push(with_suffix(&stem, "npy"));
            }
            for route in routes {
                let back = data::read(&route).unwrap();
                let (a, b) = (back.grid.as_ref().unwrap(), fig.grid.as_ref().unwrap());
                assert_eq!(
                    (a.nx, a.ny, a.x, a.y, &a.label, a.scale),
                    (b.nx, b.ny, b.x, b.y, &b.label, b.scale)
                );
                assert!(a
                    .values
                    .iter()
                    .zip(&b.values)
                    .all(|(p, q)| p.to_bits() == q.to_bits() || (p.is_nan() && q.is_nan())));
                assert_eq!(back.to_svg_string().unwrap(), svg, "{}", route.display());
            }
            let _ = std::fs::remove_dir_all(&dir);
        }
    }

    #[test]
    fn no_two_series_share_colour_and_dash() {
        let n = 60;
        let lines: std::collections::HashSet<_> =
            (0..n).map(|i| (series_color(i), series_dash(i))).collect();
        assert_eq!(lines.len(), n);
        let markers: std::collections::HashSet<_> = (0..80)
            .map(|i| (series_color(i), series_marker(i)))
            .collect();
        assert_eq!(markers.len(), 80);
        // The first ten are solid; the eleventh repeats the first colour, dashed.
        assert!((0..10).all(|i| series_dash(i).is_none()));
        assert_eq!(series_color(10), series_color(0));
        assert!(series_dash(10).is_some());
        // Coinciding curves take dashes of odd length, never a palette pattern.
        assert!((0..1000).filter_map(series_dash).all(|(d, _)| d % 2 == 0));
        assert!(COINCIDENT_DASHES.iter().all(|d| d % 2 == 1));
        // Drawn: twelve parallel lines, the last two dashed in the first two colours.
        let mut fig = Figure::new("many", "x", "y");
        for k in 0..12 {
            fig = fig.curve(
                format!("c{k}"),
                [(0.0, k as f64), (1.0, k as f64 + 0.5)],
                Style::Line,
            );
        }
        let svg = fig.to_svg_string().unwrap();
        assert_eq!(svg.matches("stroke-dasharray=\"2 3\"").count(), 2, "{svg}"); // Dot series (no dashes) differ by colour alone: shades beyond the palette.
        let dots: std::collections::HashSet<_> = (0..60).map(dot_color).collect();
        assert_eq!(dots.len(), 60);
        assert_eq!(dot_color(3), series_color(3));
        assert_ne!(dot_color(13), series_color(13));
    }

    #[test]
    fn coincidence_is_found_across_different_sample_times() {
        // The same decaying curve sampled at 200 and at 1000 times, and a different one.
        let f = |t: f64| (-t).exp();
        let coarse: Vec<(f64, f64)> = (0..=200)
            .map(|i| i as f64 * 0.05)
            .map(|t| (t, f(t)))
            .collect();
        let fine: Vec<(f64, f64)> = (0..=1000)
            .map(|i| i as f64 * 0.01)
            .map(|t| (t, f(t)))
            .collect();
        let other: Vec<(f64, f64)> = fine.iter().map(|&(t, y)| (t, y + 0.05)).collect();
        let r = Figure::new("t", "t", "y")
            .curve("coarse", coarse.clone(), Style::Line)
            .curve("fine", fine, Style::Line)
            .curve("other", other, Style::Line)
            .render()
            .unwrap();
        let said: Vec<&String> = r.notes.iter().filter(|n| n.contains("coincides")).collect();
        assert_eq!(said.len(), 1, "{:?}", r.notes);
        assert!(said[0].contains("\u{201c}fine\u{201d} coincides with \u{201c}coarse\u{201d}"));
        // A curve over half the span does not coincide with one over all of it.
        let half: Vec<(f64, f64)> = coarse.iter().copied().filter(|p| p.0 <= 5.0).collect();
        let r = Figure::new("t", "t", "y")
            .curve("coarse", coarse, Style::Line)
            .curve("half", half, Style::Line)
            .render()
            .unwrap();
        assert!(
            !r.notes.iter().any(|n| n.contains("coincides")),
            "{:?}",
            r.notes
        );
    }

    #[test]
    fn closed_orbits_on_the_same_path_coincide() {
        // The unit circle traversed 3 times from angle 0 with 900 points, and once from angle 1
        // with 257 points (different samples, different start): the same path. A circle of
        // radius 1.02 (0.02 of a range of 2.2, several line widths on any canvas) does not
        // coincide, nor does a half circle with the whole.
        let circle = |n: usize, turns: f64, start: f64, r: f64| -> Vec<(f64, f64)> {
            (0..=n)
                .map(|k| start + turns * std::f64::consts::TAU * k as f64 / n as f64)
                .map(|a| (r * a.cos(), r * a.sin()))
                .collect()
        };
        let r = Figure::new("orbits", "x", "y")
            .equal_aspect()
            .curve("exact", circle(900, 3.0, 0.0, 1.0), Style::Line)
            .curve("method", circle(257, 1.0, 1.0, 1.0), Style::Line)
            .curve("larger", circle(400, 1.0, 0.0, 1.02), Style::Line)
            .curve("half", circle(200, 0.5, 0.0, 1.0), Style::Line)
            .render()
            .unwrap();
        let said: Vec<&String> = r.notes.iter().filter(|n| n.contains("coincides")).collect();
        // The half circle lies on the whole one, but not the whole on the half: the paths differ.
        assert!(
            said.len() == 1
                && said[0].contains("\u{201c}method\u{201d} coincides with \u{201c}exact\u{201d}"),
            "{:?}",
            r.notes
        );
    }

    #[test]
    fn error_bands_are_shaded_under_the_line() {
        let fig = Figure::new("t", "x", "y").band(
            "mean ± σ",
            (0..50).map(|i| (i as f64, i as f64 - 1.0, i as f64, i as f64 + 1.0)),
            Style::Line,
        );
        let r = fig.render().unwrap();
        // One shaded polygon (and the legend's swatch), in the line's colour, translucent.
        assert!(r.svg.matches("<polygon").count() >= 1, "{}", r.svg);
        assert!(r.svg.contains("opacity=\"0.15\""), "{}", r.svg);
        // The range covers the band.
        let (l, _) = fig.layouts().unwrap();
        assert!(l[0].y_range.0 < -1.0 && l[0].y_range.1 > 50.0);
        // Bounds that do not match the points are refused.
        let mut bad = fig.clone();
        bad.curves[0].band.pop();
        assert!(bad.render().is_err());
        // A band of many points is thinned to its envelope.
        let wide: Vec<Vec<(f64, f64, f64)>> = vec![(0..10_000)
            .map(|i| (i as f64, -((i % 7) as f64), (i % 5) as f64))
            .collect()];
        let t = thin_band(wide, 1000);
        assert!(t[0].len() <= 1002);
        assert!(t[0].iter().any(|p| p.1 == -6.0) && t[0].iter().any(|p| p.2 == 4.0));
    }
}

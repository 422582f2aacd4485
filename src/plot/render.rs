//! Sizes and formats of figures: every figure is drawn once, as SVG; PNG (by `resvg`) and PDF (by
//! `svg2pdf`) are rendered from that same SVG, with text set in the embedded DejaVu Sans, so that
//! the three files are the same drawing and do not depend on the fonts of the machine.
//!
//! A figure's [`Size`] is physical: width and height in inches and a base font size in points
//! (tick labels and legend; axis titles are 8/7 of it and the title 10/7). The drawing is laid
//! out on a canvas of `width · 72 · 14 / font_size` by `height · 72 · 14 / font_size` SVG units
//! with 14-unit tick labels, and the SVG states its physical size, so text keeps its size in
//! points at any figure size: a 3.4 in column figure at 8 pt is laid out on a canvas of 428 units,
//! a 6.4 in page figure at 9 pt on one of 717.

use crate::error::{Error, Result};
use std::sync::{Arc, OnceLock};

/// Font size of the tick labels in SVG units; the base font size maps to it.
pub(crate) const BASE_UNITS: f64 = 14.0;

/// Smallest canvas (SVG units) a figure is laid out on: below it, the text would crowd out the
/// plot (the font is too large for the figure).
const MIN_CANVAS: (f64, f64) = (320.0, 220.0);

/// Largest bitmap a figure may be rendered to, in pixels (width × height).
const MAX_PIXELS: f64 = 6.4e7;

/// Size of a figure: physical width and height, base font size, resolution of bitmaps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Size {
    /// Width in inches.
    pub width: f64,
    /// Height in inches.
    pub height: f64,
    /// Base font size in points (tick labels, legend).
    pub font_size: f64,
    /// Resolution of PNG output, in dots per inch.
    pub dpi: f64,
}

impl Default for Size {
    /// 6.4 in × 4.2 in at 9 pt (a full-width figure of a page), PNG at 150 dpi.
    fn default() -> Self {
        Self {
            width: 6.4,
            height: 4.2,
            font_size: 9.0,
            dpi: 150.0,
        }
    }
}

impl Size {
    /// A journal column: 3.4 in × 2.4 in at 8 pt, PNG at 300 dpi.
    pub fn column() -> Self {
        Self {
            width: 3.4,
            height: 2.4,
            font_size: 8.0,
            dpi: 300.0,
        }
    }

    /// Check the size before anything is drawn or allocated: finite, positive, width and height
    /// in 1…40 in, font size in 4…48 pt, resolution in 30…1200 dpi, at most 6.4·10⁷ pixels, and a
    /// font small enough for the figure (a canvas of at least 320 × 220 units).
    ///
    /// # Errors
    /// [`Error::InvalidInput`] naming the offending value.
    pub fn check(&self) -> Result<()> {
        let range = |what: &str, v: f64, lo: f64, hi: f64, unit: &str| {
            if v.is_finite() && (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(Error::invalid(
                    "figure size",
                    format!("{what} {v} {unit} is outside {lo}…{hi} {unit}"),
                ))
            }
        };
        range("width", self.width, 1.0, 40.0, "in")?;
        range("height", self.height, 1.0, 40.0, "in")?;
        range("font size", self.font_size, 4.0, 48.0, "pt")?;
        range("resolution", self.dpi, 30.0, 1200.0, "dpi")?;
        let px = self.width * self.dpi * self.height * self.dpi;
        if px > MAX_PIXELS {
            return Err(Error::invalid(
                "figure size",
                format!(
                    "{px:.3e} pixels at {} dpi is more than {MAX_PIXELS:e}",
                    self.dpi
                ),
            ));
        }
        let (w, h) = self.canvas_f64();
        if w < MIN_CANVAS.0 || h < MIN_CANVAS.1 {
            return Err(Error::invalid(
                "figure size",
                format!(
                    "a {} pt font is too large for a {} in × {} in figure (the text would crowd \
                     out the plot); use a smaller font or a larger figure",
                    self.font_size, self.width, self.height
                ),
            ));
        }
        Ok(())
    }

    fn canvas_f64(&self) -> (f64, f64) {
        let k = 72.0 * BASE_UNITS / self.font_size;
        (self.width * k, self.height * k)
    }

    /// The canvas the figure is laid out on, in SVG units (see the [module documentation](self)).
    pub(crate) fn canvas(&self) -> (u32, u32) {
        let (w, h) = self.canvas_f64();
        (w.round() as u32, h.round() as u32)
    }

    /// The largest factor by which the figure's height may grow (for a legend below it) and still
    /// pass [`Size::check`]: at most 2.5, at most 40 in high, at most 6.4·10⁷ pixels.
    pub(crate) fn max_growth(&self) -> f64 {
        let (w, h) = self.pixels();
        2.5f64
            .min(40.0 / self.height)
            .min(MAX_PIXELS / (f64::from(w) * f64::from(h)))
            .max(1.0)
    }

    /// Width and height of the PNG in pixels.
    pub fn pixels(&self) -> (u32, u32) {
        (
            (self.width * self.dpi).round() as u32,
            (self.height * self.dpi).round() as u32,
        )
    }

    /// `6.4in x 4.2in, 9pt, 150dpi`: how the size is recorded in data files.
    pub fn describe(&self) -> String {
        format!(
            "{}in x {}in, {}pt, {}dpi",
            self.width, self.height, self.font_size, self.dpi
        )
    }

    /// Parse [`Size::describe`]'s text.
    ///
    /// # Errors
    /// [`Error::InvalidInput`] if the text is not of that form or the size fails [`Size::check`].
    pub fn parse(text: &str) -> Result<Self> {
        let bad = || {
            Error::invalid(
                "figure size",
                format!("expected `6.4in x 4.2in, 9pt, 150dpi`, found {text:?}"),
            )
        };
        let (wh, rest) = text.split_once(',').ok_or_else(bad)?;
        let (w, h) = wh.split_once('x').ok_or_else(bad)?;
        let (font, dpi) = rest.split_once(',').ok_or_else(bad)?;
        let num = |s: &str, unit: &str| -> Result<f64> {
            s.trim()
                .strip_suffix(unit)
                .and_then(|v| v.trim().parse::<f64>().ok())
                .ok_or_else(bad)
        };
        let size = Size {
            width: num(w, "in")?,
            height: num(h, "in")?,
            font_size: num(font, "pt")?,
            dpi: num(dpi, "dpi")?,
        };
        size.check()?;
        Ok(size)
    }
}

/// A length with its unit, in inches: `3.4in`, `8.6cm`, `86mm`, `245pt`, `1020px` (pixels at
/// `dpi`); a bare number is in inches.
///
/// # Errors
/// [`Error::InvalidInput`] for an unknown unit, a number that does not parse, or a length that
/// is not positive and finite.
pub fn parse_length(text: &str, dpi: f64) -> Result<f64> {
    let t = text.trim();
    let (num, per_inch) = [
        ("in", 1.0),
        ("cm", 2.54),
        ("mm", 25.4),
        ("pt", 72.0),
        ("px", dpi),
    ]
    .iter()
    .find_map(|&(u, k)| t.strip_suffix(u).map(|n| (n, k)))
    .unwrap_or((t, 1.0));
    let v: f64 = num.trim().parse().map_err(|_| {
        Error::invalid(
            "length",
            format!("expected a number with a unit in, cm, mm, pt or px, found {text:?}"),
        )
    })?;
    let inches = v / per_inch;
    if !(inches.is_finite() && inches > 0.0) {
        return Err(Error::invalid(
            "length",
            format!("expected a positive, finite length, found {text:?}"),
        ));
    }
    Ok(inches)
}

/// The file formats of a figure.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// SVG, as drawn.
    Svg,
    /// PNG, rendered from the SVG at the size's resolution.
    Png,
    /// PDF, converted from the SVG (vector, text as glyphs of the embedded font).
    Pdf,
}

impl Format {
    /// Every format.
    pub const ALL: [Format; 3] = [Format::Svg, Format::Png, Format::Pdf];

    /// The file extension, which is also the format's key: `svg`, `png`, `pdf`.
    pub fn ext(self) -> &'static str {
        match self {
            Format::Svg => "svg",
            Format::Png => "png",
            Format::Pdf => "pdf",
        }
    }

    /// The format with key `key` (`svg`, `png`, `pdf`).
    pub fn from_key(key: &str) -> Option<Format> {
        Format::ALL.into_iter().find(|f| f.ext() == key)
    }
}

/// The font database of PNG and PDF output: DejaVu Sans (regular, bold, oblique), which is also
/// every generic family.
fn fonts() -> Arc<resvg::usvg::fontdb::Database> {
    static DB: OnceLock<Arc<resvg::usvg::fontdb::Database>> = OnceLock::new();
    DB.get_or_init(|| {
        let mut db = resvg::usvg::fontdb::Database::new();
        for face in [
            dejavu::sans::regular(),
            dejavu::sans::bold(),
            dejavu::sans::oblique(),
        ] {
            db.load_font_data(face.to_vec());
        }
        let family = "DejaVu Sans";
        db.set_sans_serif_family(family);
        db.set_serif_family(family);
        db.set_monospace_family(family);
        db.set_cursive_family(family);
        db.set_fantasy_family(family);
        Arc::new(db)
    })
    .clone()
}

/// The SVG parsed for rendering, text resolved against [`fonts`].
fn tree(svg: &str) -> Result<resvg::usvg::Tree> {
    let opt = resvg::usvg::Options {
        font_family: "DejaVu Sans".to_string(),
        fontdb: fonts(),
        ..Default::default()
    };
    resvg::usvg::Tree::from_str(svg, &opt)
        .map_err(|e| Error::invalid("SVG figure", format!("cannot be parsed for rendering: {e}")))
}

/// The SVG rendered as PNG at `size` (white background, pixels from [`Size::pixels`]).
///
/// # Errors
/// [`Error::InvalidInput`] if the size fails [`Size::check`] or the SVG cannot be rendered.
pub fn png(svg: &str, size: &Size) -> Result<Vec<u8>> {
    size.check()?;
    let tree = tree(svg)?;
    let (w, h) = size.pixels();
    let mut pixmap = resvg::tiny_skia::Pixmap::new(w, h)
        .ok_or_else(|| Error::invalid("PNG figure", format!("cannot allocate {w} × {h} pixels")))?;
    pixmap.fill(resvg::tiny_skia::Color::WHITE);
    let ts = tree.size();
    let transform =
        resvg::tiny_skia::Transform::from_scale(w as f32 / ts.width(), h as f32 / ts.height());
    resvg::render(&tree, transform, &mut pixmap.as_mut());
    pixmap
        .encode_png()
        .map_err(|e| Error::invalid("PNG figure", e.to_string()))
}

/// The SVG converted to a one-page PDF of its physical size.
///
/// # Errors
/// [`Error::InvalidInput`] if the SVG cannot be converted.
pub fn pdf(svg: &str) -> Result<Vec<u8>> {
    let tree = tree(svg)?;
    svg2pdf::to_pdf(
        &tree,
        svg2pdf::ConversionOptions::default(),
        svg2pdf::PageOptions { dpi: 96.0 },
    )
    .map_err(|e| Error::invalid("PDF figure", e.to_string()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_checked_and_round_trip() {
        assert!(Size::default().check().is_ok());
        assert!(Size::column().check().is_ok());
        assert_eq!(Size::column().canvas(), (428, 302));
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e9] {
            let s = Size {
                width: bad,
                ..Size::default()
            };
            assert!(s.check().is_err(), "{bad}");
            let s = Size {
                dpi: bad,
                ..Size::default()
            };
            assert!(s.check().is_err(), "{bad}");
        }
        let big_font = Size {
            font_size: 40.0,
            ..Size::column()
        };
        assert!(big_font.check().is_err());
        let s = Size::parse(&Size::column().describe()).unwrap();
        assert_eq!(s, Size::column());
        assert!(Size::parse("3in x 2in").is_err());
        assert!((parse_length("8.636cm", 100.0).unwrap() - 3.4).abs() < 1e-12);
        assert_eq!(parse_length("300px", 100.0).unwrap(), 3.0);
        assert_eq!(parse_length("2", 100.0).unwrap(), 2.0);
        assert!(parse_length("-2in", 100.0).is_err());
        assert!(parse_length("2 furlongs", 100.0).is_err());
    }
}

//! Pictures for people: maps with paths and markers, scalar-field (terrain) top views and
//! convergence curves, written as PNG and SVG.
//!
//! Coordinates are the planner's: cell units, `(x, y)` = (column, row), `(0, 0)` the upper-left
//! cell, y growing downwards; a point with integer coordinates is a cell centre and cell
//! `(x, y)` covers `[x - 0.5, x + 0.5] x [y - 0.5, y + 0.5]`. Every picture carries a title, a
//! legend listing each layer and marker with its colour, axis ticks in cell coordinates and a
//! scale bar; start and goal are marked (green and red) and labelled.
//!
//! ```ignore
//! let mut pic = MapPicture::new(grid.view(), "warehouse-10-20-10-2-1: best paths");
//! pic.layers.push(Layer::new("A*", &astar_path, Style::palette(0)));
//! pic.start = Some(start);
//! pic.goal = Some(goal);
//! pic.save_png(Path::new("out/paths.png"))?;
//! pic.save_svg(Path::new("out/paths.svg"))?;
//! ```
//!
//! Drawing is done with `plotters`; PNG text uses the DejaVu Sans font compiled into the binary
//! (`assets/DejaVuSans.ttf`), SVG text names the `sans-serif` family. Output files' parent
//! directories are created when missing.
//!
//! Big maps: a map picture is at most [`MAX_MAP_PX`] pixels a side; a bigger map is
//! downsampled, one pixel per block of cells, shaded from white (no cell blocked) to the
//! blocked colour (all blocked) by the share of blocked cells.
//! Wherever a cell is one pixel or less the occupancy is drawn as pixels (`raster`), not as
//! rectangles.

mod loglog;
mod map;
mod plot;
mod raster;

pub use loglog::{Points, loglog_plot};
pub use map::{FieldPicture, MAX_MAP_PX, MapPicture};
pub use plot::{Series, convergence_plot};

use anyhow::{Context, bail};
use planner_core::geometry::Point;
use plotters::coord::Shift;
use plotters::prelude::*;
use plotters::style::{FontFamily, FontStyle};
use std::fmt::Display;
use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::Path;
use std::sync::OnceLock;

/// An RGB colour.
pub type Rgb = [u8; 3];

/// Colours for lines and series, in the order [`Style::palette`] hands them out: the
/// colour-blind-safe Okabe-Ito set (without yellow, too faint on white) and black.
pub const PALETTE: [Rgb; 7] = [
    [0, 114, 178],   // blue
    [213, 94, 0],    // vermillion
    [0, 158, 115],   // bluish green
    [204, 121, 167], // reddish purple
    [230, 159, 0],   // orange
    [86, 180, 233],  // sky blue
    [0, 0, 0],       // black
];

/// Colour of the start marker.
pub const START_COLOR: Rgb = [40, 180, 60];
/// Colour of the goal marker.
pub const GOAL_COLOR: Rgb = [220, 30, 30];

/// How a polyline is stroked.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Style {
    /// Line colour.
    pub color: Rgb,
    /// Line width in pixels (rounded; at least 1).
    pub width: f32,
    /// Dashed instead of solid.
    pub dashed: bool,
}

impl Style {
    /// A solid line.
    pub const fn solid(color: Rgb, width: f32) -> Self {
        Style {
            color,
            width,
            dashed: false,
        }
    }

    /// A dashed line.
    pub const fn dashed(color: Rgb, width: f32) -> Self {
        Style {
            color,
            width,
            dashed: true,
        }
    }

    /// The `i`-th colour of [`PALETTE`] (cycling), solid, 3 px wide.
    pub const fn palette(i: usize) -> Self {
        Style::solid(PALETTE[i % PALETTE.len()], 3.0)
    }
}

/// A polyline in cell units, listed in the legend under `label`.
#[derive(Clone, Copy, Debug)]
pub struct Layer<'a> {
    /// Legend text (an empty label keeps the layer out of the legend).
    pub label: &'a str,
    /// Waypoints in cell units; non-finite points break the line.
    pub points: &'a [Point],
    /// Stroke.
    pub style: Style,
}

impl<'a> Layer<'a> {
    /// A layer.
    pub const fn new(label: &'a str, points: &'a [Point], style: Style) -> Self {
        Layer {
            label,
            points,
            style,
        }
    }
}

/// The shape of a [`Marker`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// Filled circle.
    Circle,
    /// Filled square.
    Square,
    /// Filled triangle, pointing up.
    Triangle,
    /// Diagonal cross.
    Cross,
}

/// A point symbol (waypoint, robot, pick station...), listed in the legend under `label`.
/// Markers with the same label, shape and colour share one legend entry.
#[derive(Clone, Copy, Debug)]
pub struct Marker<'a> {
    /// Legend text (empty: not in the legend).
    pub label: &'a str,
    /// Centre, in cell units.
    pub at: Point,
    /// Symbol.
    pub shape: Shape,
    /// Fill colour.
    pub color: Rgb,
    /// Radius in cells; drawn at least 4 px wide so it stays visible on big maps.
    pub radius_cells: f32,
}

/// A translucent disc in cell units: a dynamic obstacle or a robot footprint. Discs with the
/// same label and colour share one legend entry.
#[derive(Clone, Copy, Debug)]
pub struct Disc<'a> {
    /// Legend text (empty: not in the legend).
    pub label: &'a str,
    /// Centre, in cell units.
    pub at: Point,
    /// Radius in cells.
    pub radius_cells: f32,
    /// Colour (filled translucent, outlined opaque).
    pub color: Rgb,
}

/// Font family name used for every text.
const FAMILY: &str = "sans-serif";

/// The bundled font (see `assets/README.md`).
static FONT: &[u8] = include_bytes!("../../assets/DejaVuSans.ttf");

/// Registers the bundled font with plotters once; text can be measured and drawn afterwards.
fn ensure_font() -> anyhow::Result<()> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let ok = *REGISTERED
        .get_or_init(|| plotters::style::register_font(FAMILY, FontStyle::Normal, FONT).is_ok());
    if !ok {
        bail!("the bundled font assets/DejaVuSans.ttf cannot be parsed");
    }
    Ok(())
}

/// A text style of the bundled font.
fn font(size: f64) -> FontDesc<'static> {
    FontDesc::new(FontFamily::Name(FAMILY), size, FontStyle::Normal)
}

/// Width and height in pixels of `text` at `size` (an estimate if the font fails).
fn text_size(text: &str, size: f64) -> (i32, i32) {
    match font(size).box_size(text) {
        Ok((w, h)) => (w as i32, h as i32),
        Err(_) => (
            (text.chars().count() as f64 * size * 0.6) as i32,
            size as i32,
        ),
    }
}

fn rgb(c: Rgb) -> RGBColor {
    RGBColor(c[0], c[1], c[2])
}

/// A drawing error as `anyhow` (plotters' errors are not always `'static`).
fn drawing_error(e: impl Display) -> anyhow::Error {
    anyhow::anyhow!("drawing failed: {e}")
}

/// Something that draws itself on a canvas of a known size.
trait Figure {
    /// Canvas size in pixels.
    fn size(&self) -> (u32, u32);
    /// Pixels that go under everything [`draw`](Self::draw) draws (the writers paint them on
    /// the white canvas first).
    fn raster(&self) -> Option<raster::Raster> {
        None
    }
    /// Draws on `root` (white, with the [`raster`](Self::raster) already on it).
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>;
}

fn create_file(path: &Path) -> anyhow::Result<BufWriter<File>> {
    if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir)
            .with_context(|| format!("cannot create directory {}", dir.display()))?;
    }
    let file = File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    Ok(BufWriter::new(file))
}

/// Renders `figure` into an RGB buffer and writes it as PNG.
/// Writes `figure` as PNG and/or SVG, whichever paths are given.
fn write_files(figure: &impl Figure, png: Option<&Path>, svg: Option<&Path>) -> anyhow::Result<()> {
    if let Some(path) = png {
        write_png(figure, path)?;
    }
    if let Some(path) = svg {
        write_svg(figure, path)?;
    }
    Ok(())
}

fn write_png(figure: &impl Figure, path: &Path) -> anyhow::Result<()> {
    ensure_font()?;
    let (w, h) = figure.size();
    // White, then the raster, then the rest.
    let mut buf = vec![255u8; w as usize * h as usize * 3];
    if let Some(r) = figure.raster() {
        r.paint(&mut buf, (w, h));
    }
    {
        let root = BitMapBackend::with_buffer(&mut buf, (w, h)).into_drawing_area();
        figure.draw(&root)?;
        root.present().map_err(drawing_error)?;
    }
    let out = create_file(path)?;
    let mut encoder = png::Encoder::new(out, w, h);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    let context = || format!("cannot write PNG {}", path.display());
    let mut writer = encoder.write_header().with_context(context)?;
    writer.write_image_data(&buf).with_context(context)?;
    writer.finish().with_context(context)?;
    Ok(())
}

/// Renders `figure` as SVG text and writes it.
fn write_svg(figure: &impl Figure, path: &Path) -> anyhow::Result<()> {
    ensure_font()?;
    let mut text = String::new();
    let (w, h) = figure.size();
    {
        let root = SVGBackend::with_string(&mut text, (w, h)).into_drawing_area();
        figure.draw(&root)?;
        root.present().map_err(drawing_error)?;
    }
    // The white canvas and the raster go first, right after the opening `<svg ...>` tag.
    let mut under =
        format!("\n<rect x=\"0\" y=\"0\" width=\"{w}\" height=\"{h}\" fill=\"#FFFFFF\"/>");
    if let Some(r) = figure.raster() {
        under.push('\n');
        under.push_str(&r.svg_image()?);
    }
    let open_end = text
        .find("<svg")
        .and_then(|i| text[i..].find('>').map(|j| i + j + 1))
        .ok_or_else(|| anyhow::anyhow!("drawing failed: no <svg> element"))?;
    text.insert_str(open_end, &under);
    // Cells are adjacent rectangles: without crisp edges, viewers' anti-aliasing shows hairline
    // seams between them.
    let text = text.replace("<rect ", "<rect shape-rendering=\"crispEdges\" ");
    let mut out = create_file(path)?;
    out.write_all(text.as_bytes())
        .and_then(|()| out.flush())
        .with_context(|| format!("cannot write SVG {}", path.display()))?;
    Ok(())
}

/// A "nice" step (1, 2, 5 times a power of ten) at least `min`.
fn nice_step(min: f64) -> f64 {
    if !(min.is_finite() && min > 0.0) {
        return 1.0;
    }
    let mut p = 10f64.powf(min.log10().floor());
    loop {
        for m in [1.0, 2.0, 5.0] {
            if m * p >= min {
                return m * p;
            }
        }
        p *= 10.0;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nice_steps() {
        assert_eq!(nice_step(0.9), 1.0);
        assert_eq!(nice_step(1.0), 1.0);
        assert_eq!(nice_step(1.1), 2.0);
        assert_eq!(nice_step(7.0), 10.0);
        assert_eq!(nice_step(31.0), 50.0);
        assert_eq!(nice_step(0.03), 0.05);
        assert_eq!(nice_step(f64::NAN), 1.0);
    }

    #[test]
    fn bundled_font_registers_and_measures() {
        ensure_font().unwrap();
        let (w, h) = text_size("10 cells", 14.0);
        assert!(w > 30 && w < 120, "{w}");
        assert!(h > 5 && h < 30, "{h}");
    }
}

/// Helpers shared by the tests of the submodules.
#[cfg(test)]
pub(crate) mod testutil {
    use std::path::PathBuf;

    /// A fresh directory under the system's temporary directory.
    pub fn temp_dir(name: &str) -> PathBuf {
        let dir =
            std::env::temp_dir().join(format!("host-sim-render-{}-{name}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        dir
    }

    /// Checks the PNG signature and returns the decoded width and height.
    pub fn png_size(path: &std::path::Path) -> (u32, u32) {
        let bytes = std::fs::read(path).unwrap();
        assert!(bytes.len() > 1000, "PNG too small: {} bytes", bytes.len());
        assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
        let decoder = png::Decoder::new(std::io::Cursor::new(bytes));
        let mut reader = decoder.read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        (info.width, info.height)
    }
}

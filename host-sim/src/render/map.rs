//! Top views: an occupancy grid ([`MapPicture`]) or a scalar field such as terrain heights
//! ([`FieldPicture`]), with polylines, markers, discs, start and goal, legend, ticks and scale.

use super::raster::Raster;
use super::{
    Disc, Figure, GOAL_COLOR, Layer, Marker, Rgb, START_COLOR, Shape, Style, drawing_error,
    ensure_font, font, nice_step, rgb, text_size, write_png, write_svg,
};
use anyhow::bail;
use planner_core::geometry::Point;
use planner_core::grid::GridRef;
use planner_mapfile::MapFrame;
use planner_mapfile::frame::metres;
use plotters::coord::Shift;
use plotters::element::DashedPathElement;
use plotters::prelude::*;
use plotters::style::FontTransform;
use plotters::style::text_anchor::{HPos, Pos, VPos};
use std::path::Path;

/// An occupancy map with paths and markers: blocked cells dark, free cells white.
#[derive(Clone, Debug)]
pub struct MapPicture<'a> {
    /// The map.
    pub grid: GridRef<'a>,
    /// Title drawn on top.
    pub title: &'a str,
    /// Polylines, drawn in order (later on top).
    pub layers: Vec<Layer<'a>>,
    /// Point symbols, drawn over the layers.
    pub markers: Vec<Marker<'a>>,
    /// Translucent discs (dynamic obstacles, footprints), drawn under the layers.
    pub discs: Vec<Disc<'a>>,
    /// Start, marked green and labelled.
    pub start: Option<Point>,
    /// Goal, marked red and labelled.
    pub goal: Option<Point>,
    /// Unknown space (a ROS map's), drawn in its own colour rather than as blocked.
    pub unknown: Option<GridRef<'a>>,
    /// The map's world frame: scale bar, axes and the legend's start and goal in metres
    /// (cells without it).
    pub world: Option<MapFrame>,
    /// Pixels per cell; `None` picks one so that the map is about 600 to 1300 px wide, or,
    /// for a map of more than [`MAX_MAP_PX`] cells a side, one pixel per block of cells so
    /// that it is at most [`MAX_MAP_PX`] pixels a side (shaded by the share of blocked cells
    /// under it).
    pub cell_px: Option<u32>,
}

/// Largest side, in pixels, of the map area of an automatically sized [`MapPicture`]: bigger
/// maps are downsampled (a pixel's shade is the share of blocked cells under it).
pub const MAX_MAP_PX: usize = 2000;

impl<'a> MapPicture<'a> {
    /// A picture of `grid` with nothing on it yet.
    pub fn new(grid: GridRef<'a>, title: &'a str) -> Self {
        MapPicture {
            grid,
            title,
            layers: Vec::new(),
            markers: Vec::new(),
            discs: Vec::new(),
            start: None,
            goal: None,
            unknown: None,
            world: None,
            cell_px: None,
        }
    }

    /// Writes the picture as PNG.
    pub fn save_png(&self, path: &Path) -> anyhow::Result<()> {
        write_png(&self.scene()?, path)
    }

    /// Writes the picture as SVG.
    pub fn save_svg(&self, path: &Path) -> anyhow::Result<()> {
        write_svg(&self.scene()?, path)
    }

    /// Picture size in pixels (width, height).
    pub fn size_px(&self) -> anyhow::Result<(u32, u32)> {
        Ok(self.scene()?.size())
    }

    fn scene(&self) -> anyhow::Result<Scene<'_>> {
        Scene::new(
            SceneParts {
                width: self.grid.width(),
                height: self.grid.height(),
                title: self.title,
                background: Background::Occupancy(self.grid),
                layers: &self.layers,
                markers: &self.markers,
                discs: &self.discs,
                start: self.start,
                goal: self.goal,
                unknown: self.unknown,
                world: self.world,
            },
            self.cell_px,
        )
    }
}

/// A scalar field (terrain heights, costs...) seen from above: a light-to-dark colour ramp,
/// optionally banded with contour lines between bands, with the same overlays, legend, ticks and
/// scale as [`MapPicture`] plus a colour bar.
#[derive(Clone, Debug)]
pub struct FieldPicture<'a> {
    /// Columns.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width * height` values, row by row (`values[y * width + x]`); non-finite values are
    /// drawn grey.
    pub values: &'a [f32],
    /// What the values are, shown over the colour bar (e.g. `"height (m)"`).
    pub value_label: &'a str,
    /// Quantise the ramp into this many bands and draw contour lines between them.
    pub bands: Option<u32>,
    /// Blocked cells drawn black over the field (must be `width x height`).
    pub blocked: Option<GridRef<'a>>,
    /// Title drawn on top.
    pub title: &'a str,
    /// Polylines, drawn in order (later on top).
    pub layers: Vec<Layer<'a>>,
    /// Point symbols, drawn over the layers.
    pub markers: Vec<Marker<'a>>,
    /// Translucent discs, drawn under the layers.
    pub discs: Vec<Disc<'a>>,
    /// Start, marked green and labelled.
    pub start: Option<Point>,
    /// Goal, marked red and labelled.
    pub goal: Option<Point>,
    /// Pixels per cell; `None` picks one automatically.
    pub cell_px: Option<u32>,
}

impl<'a> FieldPicture<'a> {
    /// A picture of the `width x height` field `values` (row by row) with nothing on it yet.
    pub fn new(width: usize, height: usize, values: &'a [f32], title: &'a str) -> Self {
        FieldPicture {
            width,
            height,
            values,
            value_label: "value",
            bands: None,
            blocked: None,
            title,
            layers: Vec::new(),
            markers: Vec::new(),
            discs: Vec::new(),
            start: None,
            goal: None,
            cell_px: None,
        }
    }

    /// Writes the picture as PNG.
    pub fn save_png(&self, path: &Path) -> anyhow::Result<()> {
        write_png(&self.scene()?, path)
    }

    /// Writes the picture as SVG.
    pub fn save_svg(&self, path: &Path) -> anyhow::Result<()> {
        write_svg(&self.scene()?, path)
    }

    fn scene(&self) -> anyhow::Result<Scene<'_>> {
        let cells = self.width.checked_mul(self.height);
        if cells != Some(self.values.len()) {
            bail!(
                "field of {} values is not {} x {}",
                self.values.len(),
                self.width,
                self.height
            );
        }
        if let Some(b) = self.blocked
            && (b.width() != self.width || b.height() != self.height)
        {
            bail!(
                "blocked mask is {} x {}, field is {} x {}",
                b.width(),
                b.height(),
                self.width,
                self.height
            );
        }
        let finite = self.values.iter().copied().filter(|v| v.is_finite());
        let (lo, hi) = finite.fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| {
            (lo.min(v), hi.max(v))
        });
        let range = if lo <= hi { (lo, hi) } else { (0.0, 0.0) };
        Scene::new(
            SceneParts {
                width: self.width,
                height: self.height,
                title: self.title,
                background: Background::Field {
                    values: self.values,
                    bands: self.bands.filter(|&n| n >= 2),
                    blocked: self.blocked,
                    label: self.value_label,
                    range,
                },
                layers: &self.layers,
                markers: &self.markers,
                discs: &self.discs,
                start: self.start,
                goal: self.goal,
                unknown: None,
                world: None,
            },
            self.cell_px,
        )
    }
}

// ---------------------------------------------------------------------------------------------
// Layout and drawing shared by both pictures.

const TITLE_PT: f64 = 22.0;
const TEXT_PT: f64 = 15.0;
const TICK_PT: f64 = 13.0;
const MARGIN: i32 = 14;
const TICK_LEN: i32 = 5;
const ROW_H: i32 = 24;
const PAD: i32 = 12;
const SWATCH_W: i32 = 36;
const COLOR_BAR_H: i32 = 150;

const BLOCKED: Rgb = [45, 45, 50];
/// Unknown space: a cool grey, apart from occupied cells and free floor.
const UNKNOWN_SPACE: Rgb = [160, 175, 195];
const GRID_LINE: Rgb = [225, 225, 225];
const FRAME: Rgb = [0, 0, 0];
const UNKNOWN: Rgb = [190, 190, 190];
const CONTOUR: Rgb = [95, 65, 35];

enum Background<'s> {
    Occupancy(GridRef<'s>),
    Field {
        values: &'s [f32],
        bands: Option<u32>,
        blocked: Option<GridRef<'s>>,
        label: &'s str,
        range: (f32, f32),
    },
}

struct SceneParts<'s> {
    width: usize,
    height: usize,
    title: &'s str,
    background: Background<'s>,
    layers: &'s [Layer<'s>],
    markers: &'s [Marker<'s>],
    discs: &'s [Disc<'s>],
    start: Option<Point>,
    goal: Option<Point>,
    unknown: Option<GridRef<'s>>,
    world: Option<MapFrame>,
}

impl SceneParts<'_> {
    /// A point for the legend: metres in the world frame, or cells.
    fn point_text(&self, p: Point) -> String {
        match self.world {
            Some(f) => {
                let [x, y] = f.to_world(p.x as f64, p.y as f64);
                format!("({}, {}) m", metres_short(x), metres_short(y))
            }
            None => fmt_point(p),
        }
    }
}

/// Metres for legends and ticks: at most three decimals.
fn metres_short(v: f64) -> String {
    metres((v * 1000.0).round() / 1000.0)
}

/// Axis ticks (pixel offset, label) along x and y, and the two axis captions.
type Ticks = (
    Vec<(i32, String)>,
    Vec<(i32, String)>,
    (&'static str, &'static str),
);

enum Swatch {
    Line(Style),
    Symbol(Shape, Rgb),
    Disc(Rgb),
    Fill(Rgb),
}

struct Entry {
    swatch: Swatch,
    text: String,
}

/// A picture ready to draw: parts plus pixel layout.
struct Scene<'s> {
    parts: SceneParts<'s>,
    entries: Vec<Entry>,
    /// Pixels per block of cells (1 when `block > 1`).
    cell: i32,
    /// Cells per block, along each axis: 1, or more on a downsampled map.
    block: usize,
    /// Upper-left corner of the map area.
    map_x: i32,
    map_y: i32,
    /// Legend panel.
    legend_x: i32,
    legend_y: i32,
    legend_w: i32,
    legend_h: i32,
    /// Scale bar length in cells, and its label.
    scale_cells: f64,
    scale_text: String,
    /// Canvas.
    width_px: i32,
    height_px: i32,
}

/// Pixels per cell so that the map is about 600 to 1300 px wide and at most ~900 px high.
fn auto_cell_px(width: usize, height: usize) -> i32 {
    let w = width.max(1) as i32;
    let h = height.max(1) as i32;
    (1200 / w).min(900 / h).clamp(1, 64)
}

/// The largest 1, 2, 5 x 10^k not above `max` (at least 1).
fn nice_below(max: f64) -> f64 {
    let up = nice_step(max);
    if up <= max {
        return up;
    }
    let mantissa = up / 10f64.powf(up.log10().floor());
    // 5 -> 2, 2 -> 1, 1 -> 0.5 (times the same power of ten).
    let below = if mantissa > 4.0 { up * 0.4 } else { up * 0.5 };
    below.max(1.0)
}

/// Formats a point for the legend: integers without decimals.
fn fmt_point(p: Point) -> String {
    let f = |v: f32| {
        if v.fract() == 0.0 && v.abs() < 1e7 {
            format!("{}", v as i64)
        } else {
            format!("{v:.1}")
        }
    };
    format!("({}, {})", f(p.x), f(p.y))
}

/// Formats a colour-bar value with as many decimals as the range `span` needs.
fn fmt_value(v: f32, span: f32) -> String {
    if !(v.is_finite() && span.is_finite()) || v.abs() >= 1e6 {
        return format!("{v:.3e}");
    }
    let digits = if span > 0.0 {
        (2.0 - span.log10().floor()).clamp(0.0, 6.0) as usize
    } else {
        2
    };
    format!("{v:.digits$}")
}

impl<'s> Scene<'s> {
    fn new(parts: SceneParts<'s>, cell_px: Option<u32>) -> anyhow::Result<Self> {
        ensure_font()?;
        let (w, h) = (parts.width, parts.height);
        if w == 0 || h == 0 {
            bail!("cannot draw an empty {w} x {h} map");
        }
        let downsample = matches!(parts.background, Background::Occupancy(_));
        let (cell, block) = match cell_px {
            Some(0) => bail!("cell size must be at least 1 pixel"),
            Some(c) => (c.min(256) as i32, 1),
            None if downsample && w.max(h) > MAX_MAP_PX => (1, w.max(h).div_ceil(MAX_MAP_PX)),
            None => (auto_cell_px(w, h), 1),
        };
        let (map_w, map_h) = (
            w.div_ceil(block) as i64 * cell as i64,
            h.div_ceil(block) as i64 * cell as i64,
        );
        if map_w > 30_000 || map_h > 30_000 {
            bail!("a {w} x {h} map at {cell} px per cell is too big to draw");
        }
        let (map_w, map_h) = (map_w as i32, map_h as i32);
        let scale = cell as f64 / block as f64;

        let entries = legend_entries(&parts, block);
        let (scale_cells, scale_text) = match parts.world {
            Some(f) => {
                let m = nice_metres(160.0 / scale * f.resolution);
                (m / f.resolution, format!("{} m", metres_short(m)))
            }
            None => {
                let cells = nice_below(160.0 / scale);
                (cells, scale_label(cells as i32))
            }
        };

        // Legend panel size.
        let mut legend_w = entries
            .iter()
            .map(|e| SWATCH_W + 8 + text_size(&e.text, TEXT_PT).0)
            .max()
            .unwrap_or(0);
        legend_w = legend_w
            .max((scale_cells * scale).round() as i32)
            .max(text_size(&scale_text, TEXT_PT).0);
        // Entries, then the scale bar with its label.
        let mut legend_h = entries.len() as i32 * ROW_H + 8 + 32;
        if let Background::Field { label, range, .. } = &parts.background {
            let label_w = text_size(label, TEXT_PT).0;
            let values_w = text_size(&fmt_value(range.0, range.1 - range.0), TICK_PT)
                .0
                .max(text_size(&fmt_value(range.1, range.1 - range.0), TICK_PT).0);
            legend_w = legend_w.max(label_w).max(18 + 8 + values_w);
            legend_h += ROW_H + COLOR_BAR_H + 16;
        }
        let legend_w = legend_w + 2 * PAD;
        let legend_h = legend_h + 2 * PAD;

        // Margins around the map area.
        let title_h = text_size(parts.title, TITLE_PT).1.max(TITLE_PT as i32);
        let text_h = TEXT_PT as i32;
        let tick_h = TICK_PT as i32;
        let max_tick_w = text_size(&format!("{}", h.saturating_sub(1)), TICK_PT).0;
        let top = MARGIN + title_h + 16;
        let left = MARGIN + text_h + 10 + max_tick_w + 4 + TICK_LEN;
        let bottom = TICK_LEN + 4 + tick_h + 10 + text_h + MARGIN;
        let legend_x = left + map_w + 28;
        let width_px =
            (legend_x + legend_w + MARGIN).max(text_size(parts.title, TITLE_PT).0 + 2 * MARGIN);
        let height_px = (top + map_h + bottom).max(top + legend_h + MARGIN);
        Ok(Scene {
            parts,
            entries,
            cell,
            block,
            map_x: left,
            map_y: top,
            legend_x,
            legend_y: top,
            legend_w,
            legend_h,
            scale_cells,
            scale_text,
            width_px,
            height_px,
        })
    }

    /// Pixels per cell (below 1 on a downsampled map).
    fn scale(&self) -> f64 {
        self.cell as f64 / self.block as f64
    }

    /// Pixel of a point in cell units, unrounded and unbounded.
    fn pxf(&self, p: Point) -> (f64, f64) {
        let c = self.scale();
        (
            self.map_x as f64 + (p.x as f64 + 0.5) * c,
            self.map_y as f64 + (p.y as f64 + 0.5) * c,
        )
    }

    /// Pixel of a point if it lies within `margin` pixels of the canvas.
    fn px_near(&self, p: Point, margin: f64) -> Option<(i32, i32)> {
        let (x, y) = self.pxf(p);
        let inside = |v: f64, max: i32| v >= -margin && v <= max as f64 + margin;
        (inside(x, self.width_px) && inside(y, self.height_px))
            .then(|| (x.round() as i32, y.round() as i32))
    }

    fn map_w(&self) -> i32 {
        self.parts.width.div_ceil(self.block) as i32 * self.cell
    }

    fn map_h(&self) -> i32 {
        self.parts.height.div_ceil(self.block) as i32 * self.cell
    }

    /// Whether the occupancy is drawn as pixels ([`Figure::raster`]): wherever a cell is one
    /// pixel or less.
    fn occupancy_as_pixels(&self) -> bool {
        matches!(self.parts.background, Background::Occupancy(_)) && self.cell == 1
    }
}

/// The largest 1, 2, 5 x 10^k metres not above `max` (any power of ten).
fn nice_metres(max: f64) -> f64 {
    if !(max.is_finite() && max > 0.0) {
        return 1.0;
    }
    let p = 10f64.powf(max.log10().floor());
    [5.0, 2.0, 1.0]
        .into_iter()
        .map(|m| m * p)
        .find(|&v| v <= max)
        .unwrap_or(p)
}

fn scale_label(cells: i32) -> String {
    if cells == 1 {
        "1 cell".into()
    } else {
        format!("{cells} cells")
    }
}

fn legend_entries(parts: &SceneParts<'_>, block: usize) -> Vec<Entry> {
    let mut entries = Vec::new();
    match &parts.background {
        Background::Occupancy(_) if block > 1 => entries.push(Entry {
            swatch: Swatch::Fill(BLOCKED),
            text: format!("blocked (a pixel is {block} x {block} cells: darker, more blocked)"),
        }),
        Background::Occupancy(_) => entries.push(Entry {
            swatch: Swatch::Fill(BLOCKED),
            text: if parts.unknown.is_some() {
                "occupied cell".into()
            } else {
                "blocked cell".into()
            },
        }),
        Background::Field {
            blocked: Some(_), ..
        } => entries.push(Entry {
            swatch: Swatch::Fill(BLOCKED),
            text: "blocked cell".into(),
        }),
        Background::Field { .. } => {}
    }
    if parts.unknown.is_some_and(|u| u.blocked_count() > 0) {
        entries.push(Entry {
            swatch: Swatch::Fill(UNKNOWN_SPACE),
            text: "unknown space".into(),
        });
    }
    if let Some(p) = parts.start {
        entries.push(Entry {
            swatch: Swatch::Symbol(Shape::Circle, START_COLOR),
            text: format!("start {}", parts.point_text(p)),
        });
    }
    if let Some(p) = parts.goal {
        entries.push(Entry {
            swatch: Swatch::Symbol(Shape::Square, GOAL_COLOR),
            text: format!("goal {}", parts.point_text(p)),
        });
    }
    for layer in parts.layers.iter().filter(|l| !l.label.is_empty()) {
        entries.push(Entry {
            swatch: Swatch::Line(layer.style),
            text: layer.label.to_string(),
        });
    }
    let mut seen_markers: Vec<(&str, Shape, Rgb)> = Vec::new();
    for m in parts.markers.iter().filter(|m| !m.label.is_empty()) {
        let key = (m.label, m.shape, m.color);
        if !seen_markers.contains(&key) {
            seen_markers.push(key);
            entries.push(Entry {
                swatch: Swatch::Symbol(m.shape, m.color),
                text: m.label.to_string(),
            });
        }
    }
    let mut seen_discs: Vec<(&str, Rgb)> = Vec::new();
    for d in parts.discs.iter().filter(|d| !d.label.is_empty()) {
        let key = (d.label, d.color);
        if !seen_discs.contains(&key) {
            seen_discs.push(key);
            entries.push(Entry {
                swatch: Swatch::Disc(d.color),
                text: d.label.to_string(),
            });
        }
    }
    entries
}

/// The field's colour ramp at `t` in `[0, 1]`: pale sand (low) to dark brown (high), muted so
/// that coloured paths stay visible on it.
fn ramp(t: f32) -> Rgb {
    const STOPS: [(f32, Rgb); 5] = [
        (0.0, [250, 248, 240]),
        (0.3, [232, 218, 180]),
        (0.55, [205, 175, 125]),
        (0.8, [160, 120, 80]),
        (1.0, [110, 80, 55]),
    ];
    let t = if t.is_finite() {
        t.clamp(0.0, 1.0)
    } else {
        0.0
    };
    for pair in STOPS.windows(2) {
        let ((t0, c0), (t1, c1)) = (pair[0], pair[1]);
        if t <= t1 {
            let u = (t - t0) / (t1 - t0);
            let mix = |a: u8, b: u8| (a as f32 + (b as f32 - a as f32) * u).round() as u8;
            return [mix(c0[0], c1[0]), mix(c0[1], c1[1]), mix(c0[2], c1[2])];
        }
    }
    STOPS[STOPS.len() - 1].1
}

/// Band index (with bands) or ramp level 0..=255 of a value; `None` for non-finite values.
fn level(v: f32, (lo, hi): (f32, f32), bands: Option<u32>) -> Option<u32> {
    if !v.is_finite() {
        return None;
    }
    let t = if hi > lo { (v - lo) / (hi - lo) } else { 0.5 };
    let n = bands.unwrap_or(256);
    Some(((t * n as f32) as u32).min(n - 1))
}

fn level_color(level: Option<u32>, bands: Option<u32>) -> Rgb {
    match level {
        None => UNKNOWN,
        Some(l) => {
            let n = bands.unwrap_or(256);
            ramp(if n <= 1 {
                0.5
            } else {
                l as f32 / (n - 1) as f32
            })
        }
    }
}

/// Liang-Barsky: the part of segment `a`-`b` inside `(x0, y0, x1, y1)`, if any.
fn clip_segment(
    a: (f64, f64),
    b: (f64, f64),
    (x0, y0, x1, y1): (f64, f64, f64, f64),
) -> Option<((f64, f64), (f64, f64))> {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (p, q) in [
        (-dx, a.0 - x0),
        (dx, x1 - a.0),
        (-dy, a.1 - y0),
        (dy, y1 - a.1),
    ] {
        if p == 0.0 {
            if q < 0.0 {
                return None;
            }
        } else {
            let r = q / p;
            if p < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    // Also rejects NaN (points are finite, but products of huge values may not be).
    if t0.partial_cmp(&t1).is_none_or(|o| o.is_gt()) {
        return None;
    }
    let at = |t: f64| {
        if t == 0.0 {
            a
        } else if t == 1.0 {
            b
        } else {
            (a.0 + t * dx, a.1 + t * dy)
        }
    };
    Some((at(t0), at(t1)))
}

type DResult = anyhow::Result<()>;

fn fill_rect<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    (x0, y0): (i32, i32),
    (x1, y1): (i32, i32),
    color: Rgb,
) -> DResult {
    root.draw(&Rectangle::new([(x0, y0), (x1, y1)], rgb(color).filled()))
        .map_err(drawing_error)
}

fn stroke_rect<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    (x0, y0): (i32, i32),
    (x1, y1): (i32, i32),
    color: Rgb,
) -> DResult {
    root.draw(&PathElement::new(
        vec![(x0, y0), (x1, y0), (x1, y1), (x0, y1), (x0, y0)],
        rgb(color).stroke_width(1),
    ))
    .map_err(drawing_error)
}

fn line<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    pts: Vec<(i32, i32)>,
    style: Style,
) -> DResult {
    let width = style.width.round().max(1.0) as u32;
    let shape = rgb(style.color).stroke_width(width);
    if style.dashed {
        let dash = 4 * width as i32 + 4;
        root.draw(&DashedPathElement::new(pts, dash, dash * 2 / 3, shape))
    } else {
        root.draw(&PathElement::new(pts, shape))
    }
    .map_err(drawing_error)
}

fn text<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    s: &str,
    at: (i32, i32),
    size: f64,
    pos: Pos,
) -> DResult {
    // plotters places the baseline differently per backend and anchor (ab_glyph in PNGs puts
    // "centred" text visibly high). Anchoring at the bottom agrees within a pixel in PNG and
    // SVG: the baseline lands about 0.26 x size above the anchor. So compute the baseline
    // from the wanted anchor (glyph tops, middle of capitals, or baseline) and anchor there.
    let baseline = match pos.v_pos {
        VPos::Top => at.1 as f64 + 0.66 * size,
        VPos::Center => at.1 as f64 + 0.31 * size,
        VPos::Bottom => at.1 as f64,
    };
    let anchor = (at.0, (baseline + 0.26 * size).round() as i32);
    let style = font(size)
        .color(&BLACK)
        .pos(Pos::new(pos.h_pos, VPos::Bottom));
    root.draw(&Text::new(s, anchor, style))
        .map_err(drawing_error)
}

/// A symbol of radius `r` px centred at `c`, outlined black.
fn symbol<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    shape: Shape,
    (x, y): (i32, i32),
    r: i32,
    color: Rgb,
) -> DResult {
    let fill = rgb(color).filled();
    let outline = BLACK.stroke_width(1);
    match shape {
        Shape::Circle => {
            root.draw(&Circle::new((x, y), r, fill))
                .map_err(drawing_error)?;
            root.draw(&Circle::new((x, y), r, outline))
                .map_err(drawing_error)
        }
        Shape::Square => {
            let s = (r as f32 * 0.85).round() as i32;
            fill_rect(root, (x - s, y - s), (x + s, y + s), color)?;
            stroke_rect(root, (x - s, y - s), (x + s, y + s), FRAME)
        }
        Shape::Triangle => {
            let h = (r as f32 * 0.5).round() as i32;
            let dx = (r as f32 * 0.87).round() as i32;
            let pts = vec![(x, y - r), (x + dx, y + h), (x - dx, y + h)];
            root.draw(&Polygon::new(pts.clone(), fill))
                .map_err(drawing_error)?;
            let mut closed = pts;
            closed.push((x, y - r));
            root.draw(&PathElement::new(closed, outline))
                .map_err(drawing_error)
        }
        Shape::Cross => {
            let s = (r as f32 * 0.8).round() as i32;
            let w = (r / 3).max(2) as f32;
            line(
                root,
                vec![(x - s, y - s), (x + s, y + s)],
                Style::solid(color, w),
            )?;
            line(
                root,
                vec![(x - s, y + s), (x + s, y - s)],
                Style::solid(color, w),
            )
        }
    }
}

impl Figure for Scene<'_> {
    fn size(&self) -> (u32, u32) {
        (self.width_px as u32, self.height_px as u32)
    }

    fn raster(&self) -> Option<Raster> {
        match self.parts.background {
            Background::Occupancy(grid) if self.occupancy_as_pixels() => Some(Raster::occupancy(
                grid,
                self.parts.unknown.map(|u| (u, UNKNOWN_SPACE)),
                self.block,
                (self.map_x, self.map_y),
                BLOCKED,
            )),
            _ => None,
        }
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DResult {
        self.draw_background(root)?;
        self.draw_overlays(root)?;
        self.draw_axes(root)?;
        text(
            root,
            self.parts.title,
            (self.width_px / 2, MARGIN),
            TITLE_PT,
            Pos::new(HPos::Center, VPos::Top),
        )?;
        self.draw_legend(root)
    }
}

impl Scene<'_> {
    fn draw_background<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DResult {
        let (w, h, c) = (self.parts.width, self.parts.height, self.cell);
        let (x0, y0) = (self.map_x, self.map_y);
        // Horizontal runs of equal colour: one rectangle each.
        let runs = |color_of: &dyn Fn(usize, usize) -> Option<Rgb>| -> DResult {
            for y in 0..h {
                let mut x = 0;
                while x < w {
                    let color = color_of(x, y);
                    let mut end = x + 1;
                    while end < w && color_of(end, y) == color {
                        end += 1;
                    }
                    if let Some(color) = color {
                        fill_rect(
                            root,
                            (x0 + x as i32 * c, y0 + y as i32 * c),
                            (x0 + end as i32 * c, y0 + (y as i32 + 1) * c),
                            color,
                        )?;
                    }
                    x = end;
                }
            }
            Ok(())
        };
        match &self.parts.background {
            // Drawn as pixels by the writers (`Figure::raster`).
            Background::Occupancy(_) if self.occupancy_as_pixels() => {}
            Background::Occupancy(grid) => {
                if c >= 8 {
                    self.draw_grid_lines(root)?;
                }
                let unknown = self.parts.unknown;
                runs(&|x, y| {
                    let (x, y) = (x as isize, y as isize);
                    if unknown.is_some_and(|u| u.is_blocked(x, y)) {
                        Some(UNKNOWN_SPACE)
                    } else {
                        grid.is_blocked(x, y).then_some(BLOCKED)
                    }
                })?;
            }
            Background::Field {
                values,
                bands,
                blocked,
                range,
                ..
            } => {
                let is_blocked = |x: usize, y: usize| {
                    blocked.is_some_and(|b| b.is_blocked(x as isize, y as isize))
                };
                // Blocked cells count as one band of their own: no contours inside them.
                let lv = |x: usize, y: usize| {
                    if is_blocked(x, y) {
                        Some(u32::MAX)
                    } else {
                        level(values[y * w + x], *range, *bands)
                    }
                };
                runs(&|x, y| {
                    if is_blocked(x, y) {
                        Some(BLOCKED)
                    } else {
                        Some(level_color(lv(x, y), *bands))
                    }
                })?;
                if bands.is_some() {
                    self.draw_contours(root, &lv)?;
                }
            }
        }
        stroke_rect(
            root,
            (x0, y0),
            (x0 + self.map_w(), y0 + self.map_h()),
            FRAME,
        )
    }

    fn draw_grid_lines<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DResult {
        let (x0, y0, c) = (self.map_x, self.map_y, self.cell);
        let (x1, y1) = (x0 + self.map_w(), y0 + self.map_h());
        let style = Style::solid(GRID_LINE, 1.0);
        for i in 1..self.parts.width as i32 {
            line(root, vec![(x0 + i * c, y0), (x0 + i * c, y1)], style)?;
        }
        for j in 1..self.parts.height as i32 {
            line(root, vec![(x0, y0 + j * c), (x1, y0 + j * c)], style)?;
        }
        Ok(())
    }

    /// Lines on cell borders between different bands, merged along each border line.
    fn draw_contours<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        lv: &dyn Fn(usize, usize) -> Option<u32>,
    ) -> DResult {
        let (w, h, c) = (self.parts.width, self.parts.height, self.cell);
        let (x0, y0) = (self.map_x, self.map_y);
        let style = Style::solid(CONTOUR, 1.0);
        // Vertical borders between columns x-1 and x.
        for x in 1..w {
            let mut y = 0;
            while y < h {
                if lv(x - 1, y) != lv(x, y) {
                    let start = y;
                    while y < h && lv(x - 1, y) != lv(x, y) {
                        y += 1;
                    }
                    let px = x0 + x as i32 * c;
                    line(
                        root,
                        vec![(px, y0 + start as i32 * c), (px, y0 + y as i32 * c)],
                        style,
                    )?;
                } else {
                    y += 1;
                }
            }
        }
        // Horizontal borders between rows y-1 and y.
        for y in 1..h {
            let mut x = 0;
            while x < w {
                if lv(x, y - 1) != lv(x, y) {
                    let start = x;
                    while x < w && lv(x, y - 1) != lv(x, y) {
                        x += 1;
                    }
                    let py = y0 + y as i32 * c;
                    line(
                        root,
                        vec![(x0 + start as i32 * c, py), (x0 + x as i32 * c, py)],
                        style,
                    )?;
                } else {
                    x += 1;
                }
            }
        }
        Ok(())
    }

    fn draw_overlays<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DResult {
        // Geometry is user data: nothing may reach plotters with coordinates or radii so big
        // that its rasterisers overflow or spin, so sizes are capped and lines clipped.
        let c = self.scale() as f32;
        let canvas = (self.width_px + self.height_px) as f32;
        for d in self.parts.discs {
            if !d.radius_cells.is_finite() {
                continue;
            }
            let r = (d.radius_cells * c).round().clamp(2.0, canvas) as i32;
            let Some(center) = self.px_near(d.at, r as f64) else {
                continue;
            };
            root.draw(&Circle::new(center, r, rgb(d.color).mix(0.35).filled()))
                .map_err(drawing_error)?;
            root.draw(&Circle::new(center, r, rgb(d.color).stroke_width(2)))
                .map_err(drawing_error)?;
        }
        for layer in self.parts.layers {
            // Non-finite points split the polyline.
            for piece in layer.points.split(|p| !p.is_finite()) {
                if let [p] = piece {
                    if let Some(at) = self.px_near(*p, 0.0) {
                        let r = (layer.style.width * 1.5).round().clamp(2.0, 20.0) as i32;
                        root.draw(&Circle::new(at, r, rgb(layer.style.color).filled()))
                            .map_err(drawing_error)?;
                    }
                    continue;
                }
                for run in self.clipped_runs(piece) {
                    line(root, run, layer.style)?;
                }
            }
        }
        for m in self.parts.markers {
            if !m.radius_cells.is_finite() {
                continue;
            }
            let r = (m.radius_cells * c).round().clamp(4.0, 200.0) as i32;
            if let Some(at) = self.px_near(m.at, r as f64) {
                symbol(root, m.shape, at, r, m.color)?;
            }
        }
        let end_r = (0.6 * c).round().clamp(6.0, 14.0) as i32;
        for (p, shape, color, name) in [
            (self.parts.start, Shape::Circle, START_COLOR, "start"),
            (self.parts.goal, Shape::Square, GOAL_COLOR, "goal"),
        ] {
            let Some(at) = p.and_then(|p| self.px_near(p, end_r as f64)) else {
                continue;
            };
            symbol(root, shape, at, end_r, color)?;
            self.tag(root, name, at, end_r)?;
        }
        Ok(())
    }

    /// A polyline's pixels, clipped to the canvas (plus a margin): runs of connected points.
    fn clipped_runs(&self, points: &[Point]) -> Vec<Vec<(i32, i32)>> {
        const M: f64 = 50.0;
        let rect = (-M, -M, self.width_px as f64 + M, self.height_px as f64 + M);
        let round = |(x, y): (f64, f64)| (x.round() as i32, y.round() as i32);
        let mut runs: Vec<Vec<(i32, i32)>> = Vec::new();
        let mut open = false;
        for seg in points.windows(2) {
            let (a, b) = (self.pxf(seg[0]), self.pxf(seg[1]));
            let Some((ca, cb)) = clip_segment(a, b, rect) else {
                open = false;
                continue;
            };
            match runs.last_mut() {
                Some(run) if open && ca == a => run.push(round(cb)),
                _ => runs.push(vec![round(ca), round(cb)]),
            }
            open = cb == b;
        }
        runs
    }

    /// A label on a white box beside a marker, kept inside the map area where possible.
    fn tag<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
        name: &str,
        (x, y): (i32, i32),
        r: i32,
    ) -> DResult {
        let (tw, th) = text_size(name, TEXT_PT);
        let right_end = self.map_x + self.map_w();
        let left = if x + r + 4 + tw + 4 <= right_end {
            x + r + 3
        } else {
            x - r - 3 - tw - 4
        };
        let top = if y - r - th - 4 >= self.map_y {
            y - r - th - 2
        } else {
            y + r + 2
        };
        root.draw(&Rectangle::new(
            [(left, top), (left + tw + 4, top + th + 4)],
            WHITE.mix(0.85).filled(),
        ))
        .map_err(drawing_error)?;
        stroke_rect(
            root,
            (left, top),
            (left + tw + 4, top + th + 4),
            [120, 120, 120],
        )?;
        text(
            root,
            name,
            (left + 2 + tw / 2, top + 2 + th / 2),
            TEXT_PT,
            Pos::new(HPos::Center, VPos::Center),
        )
    }

    fn draw_axes<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DResult {
        let bottom = self.map_y + self.map_h();
        let axis = Style::solid(FRAME, 1.0);
        // Ticks: (pixel offset from the map's left or top edge, label).
        let (xs, ys, captions) = match self.parts.world {
            Some(f) => self.world_ticks(&f),
            None => self.cell_ticks(),
        };
        for (x, label) in xs {
            let x = self.map_x + x;
            line(root, vec![(x, bottom), (x, bottom + TICK_LEN)], axis)?;
            text(
                root,
                &label,
                (x, bottom + TICK_LEN + 3),
                TICK_PT,
                Pos::new(HPos::Center, VPos::Top),
            )?;
        }
        for (y, label) in ys {
            let y = self.map_y + y;
            line(
                root,
                vec![(self.map_x - TICK_LEN, y), (self.map_x, y)],
                axis,
            )?;
            text(
                root,
                &label,
                (self.map_x - TICK_LEN - 4, y),
                TICK_PT,
                Pos::new(HPos::Right, VPos::Center),
            )?;
        }
        let caption_y = bottom + TICK_LEN + 4 + TICK_PT as i32 + 10;
        text(
            root,
            captions.0,
            (self.map_x + self.map_w() / 2, caption_y),
            TEXT_PT,
            Pos::new(HPos::Center, VPos::Top),
        )?;
        let style = font(TEXT_PT)
            .transform(FontTransform::Rotate270)
            .color(&BLACK)
            .pos(Pos::new(HPos::Center, VPos::Top));
        root.draw(&Text::new(
            captions.1,
            (MARGIN, self.map_y + self.map_h() / 2),
            style,
        ))
        .map_err(drawing_error)
    }

    /// Ticks at cell centres (column and row numbers).
    fn cell_ticks(&self) -> Ticks {
        let (w, h, c) = (
            self.parts.width as i32,
            self.parts.height as i32,
            self.scale(),
        );
        // Centre of cell `k` along an axis, in pixels from the map's edge.
        let centre = |k: i32| ((k as f64 + 0.5) * c).floor() as i32;
        let step_x = (nice_step(48.0 / c) as i32).max(1) as usize;
        let step_y = (nice_step(30.0 / c) as i32).max(1) as usize;
        (
            (0..w)
                .step_by(step_x)
                .map(|k| (centre(k), k.to_string()))
                .collect(),
            (0..h)
                .step_by(step_y)
                .map(|k| (centre(k), k.to_string()))
                .collect(),
            ("x (column, cells)", "y (row, cells)"),
        )
    }

    /// Ticks at round metres of the map frame (y up).
    fn world_ticks(&self, f: &MapFrame) -> Ticks {
        let px_per_m = self.scale() / f.resolution;
        let [[x0, y0], [x1, y1]] = f.extent();
        let ticks = |lo: f64, hi: f64, min_px: f64, to_px: &dyn Fn(f64) -> f64| {
            let step = nice_step(min_px / px_per_m);
            let mut out = Vec::new();
            let mut k = (lo / step).ceil();
            while k * step <= hi + 1e-9 && out.len() < 1000 {
                let v = k * step;
                out.push((to_px(v).round() as i32, metres_short(v)));
                k += 1.0;
            }
            out
        };
        (
            ticks(x0, x1, 60.0, &|v| (v - x0) * px_per_m),
            ticks(y0, y1, 30.0, &|v| (y1 - v) * px_per_m),
            ("x (m, map frame)", "y (m, map frame)"),
        )
    }

    fn draw_legend<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> DResult {
        let (lx, ly) = (self.legend_x, self.legend_y);
        fill_rect(
            root,
            (lx, ly),
            (lx + self.legend_w, ly + self.legend_h),
            [255, 255, 255],
        )?;
        stroke_rect(
            root,
            (lx, ly),
            (lx + self.legend_w, ly + self.legend_h),
            [120, 120, 120],
        )?;
        let x = lx + PAD;
        let mut y = ly + PAD + ROW_H / 2;
        let mid = x + SWATCH_W / 2;
        for e in &self.entries {
            match e.swatch {
                Swatch::Line(style) => line(root, vec![(x, y), (x + SWATCH_W, y)], style)?,
                Swatch::Symbol(shape, color) => symbol(root, shape, (mid, y), 7, color)?,
                Swatch::Disc(color) => {
                    root.draw(&Circle::new((mid, y), 8, rgb(color).mix(0.35).filled()))
                        .map_err(drawing_error)?;
                    root.draw(&Circle::new((mid, y), 8, rgb(color).stroke_width(2)))
                        .map_err(drawing_error)?;
                }
                Swatch::Fill(color) => {
                    fill_rect(root, (mid - 8, y - 8), (mid + 8, y + 8), color)?;
                    stroke_rect(root, (mid - 8, y - 8), (mid + 8, y + 8), FRAME)?;
                }
            }
            text(
                root,
                &e.text,
                (x + SWATCH_W + 8, y),
                TEXT_PT,
                Pos::new(HPos::Left, VPos::Center),
            )?;
            y += ROW_H;
        }
        // Scale bar.
        y += 8 - ROW_H / 2 + 6;
        let len = (self.scale_cells * self.scale()).round() as i32;
        let bar = Style::solid(FRAME, 2.0);
        line(root, vec![(x, y), (x + len, y)], bar)?;
        line(root, vec![(x, y - 5), (x, y + 5)], bar)?;
        line(root, vec![(x + len, y - 5), (x + len, y + 5)], bar)?;
        text(
            root,
            &self.scale_text,
            (x, y + 9),
            TEXT_PT,
            Pos::new(HPos::Left, VPos::Top),
        )?;
        y += 38;
        if let Background::Field {
            bands,
            label,
            range,
            ..
        } = &self.parts.background
        {
            text(
                root,
                label,
                (x, y + 4),
                TEXT_PT,
                Pos::new(HPos::Left, VPos::Top),
            )?;
            y += ROW_H + 4;
            let (top, bar_w) = (y, 18);
            // High values at the top.
            for i in 0..COLOR_BAR_H {
                let t = 1.0 - (i as f32 + 0.5) / COLOR_BAR_H as f32;
                let v = range.0 + t * (range.1 - range.0);
                let color = level_color(level(v, *range, *bands), *bands);
                fill_rect(root, (x, top + i), (x + bar_w, top + i + 1), color)?;
            }
            stroke_rect(root, (x, top), (x + bar_w, top + COLOR_BAR_H), FRAME)?;
            let at = |v: f32, yy: i32, vpos: VPos| {
                text(
                    root,
                    &fmt_value(v, range.1 - range.0),
                    (x + bar_w + 6, yy),
                    TICK_PT,
                    Pos::new(HPos::Left, vpos),
                )
            };
            at(range.1, top, VPos::Top)?;
            at(
                (range.0 + range.1) / 2.0,
                top + COLOR_BAR_H / 2,
                VPos::Center,
            )?;
            at(range.0, top + COLOR_BAR_H, VPos::Bottom)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::testutil::{png_size, temp_dir};
    use super::*;
    use planner_core::grid::GridBuf;

    fn small_grid() -> GridBuf {
        GridBuf::parse_rows(
            b"..........\n..........\n..@@@.....\n....@.....\n....@..@@.\n\
              ..........\n.@@.......\n..........\n.....@@@..\n..........\n",
        )
        .unwrap()
    }

    #[test]
    fn auto_cell_size_keeps_pictures_readable() {
        for (w, h) in [(10, 10), (32, 32), (161, 63), (340, 164), (8, 8)] {
            let c = auto_cell_px(w, h);
            let map_w = w as i32 * c;
            assert!(
                (500..=1300).contains(&map_w),
                "{w}x{h}: cell {c}, {map_w} px"
            );
        }
    }

    #[test]
    fn segments_are_clipped_to_the_rectangle() {
        let r = (0.0, 0.0, 10.0, 10.0);
        assert_eq!(
            clip_segment((1.0, 1.0), (2.0, 3.0), r),
            Some(((1.0, 1.0), (2.0, 3.0)))
        );
        assert_eq!(
            clip_segment((-10.0, 5.0), (20.0, 5.0), r),
            Some(((0.0, 5.0), (10.0, 5.0)))
        );
        assert_eq!(clip_segment((-10.0, -1.0), (20.0, -1.0), r), None);
        assert_eq!(clip_segment((11.0, 0.0), (20.0, 10.0), r), None);
        let (a, b) = clip_segment((5.0, 5.0), (5.0e9, -5.0e9), r).unwrap();
        assert_eq!(a, (5.0, 5.0));
        assert!((b.0 - 10.0).abs() < 1e-6 && b.1.abs() < 1e-6, "{b:?}");
    }

    #[test]
    fn nice_below_rounds_down() {
        assert_eq!(nice_below(160.0 / 64.0), 2.0);
        assert_eq!(nice_below(160.0 / 3.0), 50.0);
        assert_eq!(nice_below(160.0 / 7.0), 20.0);
        assert_eq!(nice_below(160.0), 100.0);
        assert_eq!(nice_below(0.3), 1.0);
    }

    #[test]
    fn map_picture_writes_png_and_svg_with_labels() {
        let grid = small_grid();
        let path = [
            Point::new(0.0, 0.0),
            Point::new(5.0, 1.0),
            Point::new(9.0, 9.0),
        ];
        let other = [
            Point::new(0.0, 0.0),
            Point::new(0.0, 9.0),
            Point::new(9.0, 9.0),
        ];
        let mut pic = MapPicture::new(grid.view(), "small & <test>");
        pic.layers
            .push(Layer::new("A* path", &path, Style::palette(0)));
        pic.layers.push(Layer::new(
            "Theta* path",
            &other,
            Style::dashed([213, 94, 0], 2.0),
        ));
        pic.markers.push(Marker {
            label: "waypoint",
            at: Point::new(5.0, 1.0),
            shape: Shape::Triangle,
            color: [0, 158, 115],
            radius_cells: 0.3,
        });
        pic.discs.push(Disc {
            label: "dynamic obstacle",
            at: Point::new(7.0, 6.0),
            radius_cells: 1.2,
            color: [204, 121, 167],
        });
        pic.start = Some(Point::new(0.0, 0.0));
        pic.goal = Some(Point::new(9.0, 9.0));
        let dir = temp_dir("map");
        let png = dir.join("map.png");
        pic.save_png(&png).unwrap();
        let (w, h) = png_size(&png);
        assert_eq!((w, h), pic.size_px().unwrap());
        assert!((600..=1600).contains(&w), "{w}");
        let svg_path = dir.join("sub/map.svg");
        pic.save_svg(&svg_path).unwrap();
        let svg = std::fs::read_to_string(&svg_path).unwrap();
        for label in [
            "A* path",
            "Theta* path",
            "waypoint",
            "dynamic obstacle",
            "start (0, 0)",
            "goal (9, 9)",
            "small &amp; &lt;test&gt;",
            "2 cells",
            "blocked cell",
        ] {
            assert!(svg.contains(label), "SVG lacks {label:?}");
        }
        std::fs::remove_dir_all(dir).unwrap();
    }

    /// Decodes an RGB PNG into (width, pixels).
    fn decode(path: &Path) -> (usize, Vec<u8>) {
        let file = std::io::BufReader::new(std::fs::File::open(path).unwrap());
        let mut reader = png::Decoder::new(file).read_info().unwrap();
        let mut buf = vec![0; reader.output_buffer_size().unwrap()];
        let info = reader.next_frame(&mut buf).unwrap();
        assert_eq!(info.color_type, png::ColorType::Rgb);
        (info.width as usize, buf)
    }

    #[test]
    fn cells_land_where_the_convention_says() {
        // Cell (4, 3) is blocked: column 4, row 3 from the top.
        let grid = small_grid();
        let mut pic = MapPicture::new(grid.view(), "convention");
        pic.start = Some(Point::new(1.0, 8.0));
        pic.goal = Some(Point::new(8.0, 1.0));
        let scene = pic.scene().unwrap();
        let dir = temp_dir("convention");
        let png = dir.join("c.png");
        pic.save_png(&png).unwrap();
        let (w, pixels) = decode(&png);
        let at = |p: Point| {
            let (x, y) = scene.px_near(p, 0.0).unwrap();
            let i = (y as usize * w + x as usize) * 3;
            [pixels[i], pixels[i + 1], pixels[i + 2]]
        };
        assert_eq!(at(Point::new(4.0, 3.0)), BLOCKED);
        assert_eq!(at(Point::new(3.0, 4.0)), [255, 255, 255]);
        assert_eq!(at(Point::new(1.0, 8.0)), START_COLOR);
        assert_eq!(at(Point::new(8.0, 1.0)), GOAL_COLOR);
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn legend_lists_each_label_once() {
        let grid = small_grid();
        let mut pic = MapPicture::new(grid.view(), "t");
        for i in 0..5 {
            pic.discs.push(Disc {
                label: "obstacle",
                at: Point::new(i as f32, 1.0),
                radius_cells: 0.5,
                color: [1, 2, 3],
            });
            pic.markers.push(Marker {
                label: if i == 0 { "" } else { "robot" },
                at: Point::new(i as f32, 2.0),
                shape: Shape::Square,
                color: [4, 5, 6],
                radius_cells: 0.3,
            });
        }
        let texts: Vec<String> = pic
            .scene()
            .unwrap()
            .entries
            .into_iter()
            .map(|e| e.text)
            .collect();
        assert_eq!(texts, ["blocked cell", "robot", "obstacle"]);
    }

    #[test]
    fn big_map_stays_within_width_limits() {
        let mut grid = GridBuf::new(340, 164).unwrap();
        grid.set_blocked(3, 4, true).unwrap();
        let pic = MapPicture::new(grid.view(), "340 x 164");
        let (w, _) = pic.size_px().unwrap();
        assert!((600..=1600).contains(&w), "{w}");
        let dir = temp_dir("big");
        pic.save_png(&dir.join("big.png")).unwrap();
        assert_eq!(png_size(&dir.join("big.png")).0, w);
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn maps_over_max_px_are_downsampled_shaded_by_blocked_cells() {
        // 4100 cells wide: 3 x 3 cells a pixel, 1367 pixels.
        let mut grid = GridBuf::new(4100, 60).unwrap();
        grid.set_blocked(3001, 31, true).unwrap(); // pixel (1000, 10)
        grid.set_blocked(4099, 59, true).unwrap(); // pixel (1366, 19), a partial block
        let path = [Point::new(10.0, 10.0), Point::new(4000.0, 50.0)];
        let mut pic = MapPicture::new(grid.view(), "4100 x 60");
        pic.layers
            .push(Layer::new("path", &path, Style::palette(0)));
        let scene = pic.scene().unwrap();
        assert_eq!((scene.block, scene.map_w(), scene.map_h()), (3, 1367, 20));
        assert!(scene.entries[0].text.contains("3 x 3 cells"));
        let dir = temp_dir("downsampled");
        let png = dir.join("d.png");
        pic.save_png(&png).unwrap();
        let (w, pixels) = decode(&png);
        let at = |x: i32, y: i32| {
            let i = ((scene.map_y + y) as usize * w + (scene.map_x + x) as usize) * 3;
            [pixels[i], pixels[i + 1], pixels[i + 2]]
        };
        // One cell of nine, one of three (the last column holds 4099 alone).
        assert!(at(1000, 10)[0] < 255 && at(1000, 10)[0] > at(1366, 19)[0]);
        assert!(at(1366, 19) != BLOCKED && at(1366, 19) != [255, 255, 255]);
        for (x, y) in [
            (999, 10),
            (1001, 10),
            (1000, 9),
            (1000, 11),
            (1365, 19),
            (1366, 18),
        ] {
            assert_eq!(at(x, y), [255, 255, 255], "({x}, {y})");
        }
        assert!(w < MAX_MAP_PX + 700, "{w}");
        pic.save_svg(&dir.join("d.svg")).unwrap();
        let svg = std::fs::read_to_string(dir.join("d.svg")).unwrap();
        assert_eq!(svg.matches("<image ").count(), 1);
        assert!(
            svg.contains("width=\"1367\" height=\"20\""),
            "no map image of 1367 x 20"
        );
        assert!(
            svg.contains("3 x 3 cells") && svg.len() < 200_000,
            "{} bytes",
            svg.len()
        );
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn field_picture_draws_bands_and_colour_bar() {
        let (w, h) = (20, 12);
        let values: Vec<f32> = (0..w * h)
            .map(|i| ((i % w) as f32 * 0.3).sin() + (i / w) as f32 * 0.2)
            .collect();
        let path = [Point::new(1.0, 1.0), Point::new(18.0, 10.0)];
        let mut pic = FieldPicture::new(w, h, &values, "terrain");
        pic.value_label = "height (m)";
        pic.bands = Some(6);
        pic.layers
            .push(Layer::new("route", &path, Style::palette(0)));
        pic.start = Some(path[0]);
        pic.goal = Some(path[1]);
        let dir = temp_dir("field");
        pic.save_png(&dir.join("f.png")).unwrap();
        assert!(png_size(&dir.join("f.png")).0 >= 600);
        pic.save_svg(&dir.join("f.svg")).unwrap();
        let svg = std::fs::read_to_string(dir.join("f.svg")).unwrap();
        assert!(svg.contains("height (m)") && svg.contains("route"));
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn bad_inputs_are_errors_not_panics() {
        let values = [1.0f32; 5];
        let pic = FieldPicture::new(2, 3, &values, "wrong size");
        let err = pic.save_png(Path::new("unused.png")).unwrap_err();
        assert!(err.to_string().contains("not 2 x 3"), "{err}");

        let grid = small_grid();
        let dir = temp_dir("bad");
        let blocker = dir.join("file");
        std::fs::write(&blocker, b"x").unwrap();
        let pic = MapPicture::new(grid.view(), "t");
        let err = pic.save_png(&blocker.join("x.png")).unwrap_err();
        assert!(format!("{err:#}").contains("cannot create"), "{err:#}");
        let mut zero = MapPicture::new(grid.view(), "t");
        zero.cell_px = Some(0);
        assert!(zero.save_svg(&dir.join("z.svg")).is_err());
        // Non-finite geometry is skipped, not drawn or panicked on.
        let weird = [
            Point::new(f32::NAN, 1.0),
            Point::new(1.0, 1.0),
            Point::new(f32::INFINITY, 2.0),
        ];
        let mut pic = MapPicture::new(grid.view(), "nan");
        pic.layers
            .push(Layer::new("nan", &weird, Style::palette(1)));
        pic.start = Some(Point::new(f32::NAN, 0.0));
        pic.save_png(&dir.join("nan.png")).unwrap();
        // Far-away geometry neither hangs nor panics.
        let far = [
            Point::new(1.0, 1.0),
            Point::new(3e9, -2e9),
            Point::new(-1e7, 5.0),
        ];
        let mut pic = MapPicture::new(grid.view(), "far");
        pic.layers
            .push(Layer::new("far", &far, Style::dashed([0, 0, 0], 2.0)));
        pic.discs.push(Disc {
            label: "huge",
            at: Point::new(2.0, 2.0),
            radius_cells: 1e9,
            color: [1, 2, 3],
        });
        pic.markers.push(Marker {
            label: "far",
            at: Point::new(-1e9, 1e9),
            shape: Shape::Triangle,
            color: [1, 2, 3],
            radius_cells: 1e8,
        });
        pic.goal = Some(Point::new(1e10, 0.0));
        pic.save_png(&dir.join("far.png")).unwrap();
        pic.save_svg(&dir.join("far.svg")).unwrap();
        std::fs::remove_dir_all(dir).unwrap();
    }
}

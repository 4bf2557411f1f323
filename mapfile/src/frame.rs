//! The world frame of a map (SPEC section 1): a map with resolution `r` (metres per cell)
//! and origin `(ox, oy)` (metres, the lower-left corner of the image) puts cell `(x, y)` of
//! an image of height `H` at `(ox + (x + 0.5) r, oy + (H - 1 - y + 0.5) r)`, as
//! nav2_map_server and RViz show it. The same affine map carries fractional waypoints.
//!
//! Cells have y down (image rows), the world has y up. A ROS map declares its frame in its
//! YAML; a Moving AI map or a generated layout has none ([`MapFrame::assumed`]: 1 m a cell,
//! origin at the lower-left corner), so metres are accepted on input only from a map that
//! declares them ([`MapFrame::declared`]).

use planner_core::geometry::Cell;
use std::fmt;

/// Where a map sits in the world.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapFrame {
    /// Metres per cell (positive, finite).
    pub resolution: f64,
    /// World position of the lower-left corner of the map (metres).
    pub origin: [f64; 2],
    /// Width in cells.
    pub width: usize,
    /// Height in cells (the y flip needs it).
    pub height: usize,
    /// Whether the map file declared this frame (a ROS YAML), or it is assumed.
    pub declared: bool,
}

/// Which coordinates a start, goal or query is given in (`--frame`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Frame {
    /// Grid cells `(column, row)`, row 0 at the top (Moving AI).
    #[default]
    Cells,
    /// Metres in the map frame (ROS `map`): the YAML's origin and resolution, y up.
    World,
}

/// A world point that falls in no cell of the map.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct OutsideMap {
    /// The point (metres).
    pub point: [f64; 2],
    /// The map's lower-left and upper-right corners (metres).
    pub extent: [[f64; 2]; 2],
}

impl fmt::Display for OutsideMap {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [[x0, y0], [x1, y1]] = self.extent.map(|p| p.map(metres));
        write!(
            f,
            "({}, {}) m is outside the map (x {x0} to {x1} m, y {y0} to {y1} m)",
            self.point[0], self.point[1]
        )
    }
}

impl std::error::Error for OutsideMap {}

impl MapFrame {
    /// The frame a map without one is given: 1 m a cell, the lower-left corner at the origin.
    pub fn assumed(width: usize, height: usize) -> Self {
        MapFrame {
            resolution: 1.0,
            origin: [0.0, 0.0],
            width,
            height,
            declared: false,
        }
    }

    /// World coordinates (metres) of the point `(x, y)` in cell units (cell centres are
    /// integers; fractional waypoints allowed).
    pub fn to_world(&self, x: f64, y: f64) -> [f64; 2] {
        let r = self.resolution;
        [
            self.origin[0] + (x + 0.5) * r,
            self.origin[1] + (self.height as f64 - 1.0 - y + 0.5) * r,
        ]
    }

    /// Cell units of a world point: the inverse of [`to_world`](Self::to_world).
    pub fn to_cells(&self, wx: f64, wy: f64) -> [f64; 2] {
        let r = self.resolution;
        [
            (wx - self.origin[0]) / r - 0.5,
            self.height as f64 - 1.0 - ((wy - self.origin[1]) / r - 0.5),
        ]
    }

    /// The cell holding a world point (a point on the edge between two cells belongs to
    /// the one right of it or above it, as `floor` puts it), or why there is none.
    pub fn cell_at(&self, wx: f64, wy: f64) -> Result<Cell, OutsideMap> {
        let outside = OutsideMap {
            point: [wx, wy],
            extent: self.extent(),
        };
        let column = cell_floor((wx - self.origin[0]) / self.resolution);
        let row_up = cell_floor((wy - self.origin[1]) / self.resolution);
        let inside = |v: f64, n: usize| v >= 0.0 && v < n as f64 && v <= u16::MAX as f64;
        if !(inside(column, self.width) && inside(row_up, self.height)) {
            return Err(outside);
        }
        Ok(Cell::new(
            column as u16,
            (self.height - 1 - row_up as usize) as u16,
        ))
    }

    /// The map's lower-left and upper-right corners (metres).
    pub fn extent(&self) -> [[f64; 2]; 2] {
        let r = self.resolution;
        [
            self.origin,
            [
                self.origin[0] + self.width as f64 * r,
                self.origin[1] + self.height as f64 * r,
            ],
        ]
    }

    /// A length in metres as cells.
    pub fn cells_of(&self, metres: f64) -> f64 {
        metres / self.resolution
    }

    /// The inflation (in cells, the radius of `GridBuf::inflated`, which blocks every cell
    /// whose square comes closer than it to a blocked square) that blocks every cell whose
    /// centre lies within `radius_m` of an obstacle: `radius_m / resolution - 0.5`, at
    /// least 0. A centre is at least half a cell farther from a square than its own square
    /// is, so every cell left free has its centre at least `radius_m` from every obstacle
    /// (Nav2 plans on cell centres the same way, with an inscribed radius).
    pub fn inflation_cells(&self, radius_m: f64) -> f64 {
        (self.cells_of(radius_m) - 0.5).max(0.0)
    }
}

/// `floor` of a position in cells, where a position within rounding of a cell edge counts
/// as on it: `(1.7 + 10) / 0.05` is 233.99999999999997 in binary, and the user meant the
/// edge at 234.
fn cell_floor(v: f64) -> f64 {
    let edge = v.round();
    if (v - edge).abs() <= 1e-9 * edge.abs().max(1.0) {
        edge
    } else {
        v.floor()
    }
}

/// Metres for messages: at most six decimals (a micrometre), trailing zeros dropped.
pub fn metres(v: f64) -> String {
    let text = format!("{v:.6}");
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".into()
    } else {
        text.into()
    }
}

/// Parses `X,Y`: two decimal numbers (metres, or cells with a fractional part).
pub fn parse_point(text: &str) -> Result<[f64; 2], String> {
    let (x, y) = text.split_once(',').ok_or("expected X,Y")?;
    let num = |s: &str| {
        let v = s
            .trim()
            .parse::<f64>()
            .map_err(|e| format!("{:?}: {e}", s.trim()))?;
        if v.is_finite() {
            Ok(v)
        } else {
            Err(format!("{:?}: not a finite number", s.trim()))
        }
    };
    Ok([num(x)?, num(y)?])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame() -> MapFrame {
        MapFrame {
            resolution: 0.05,
            origin: [-10.0, -10.5],
            width: 384,
            height: 200,
            declared: true,
        }
    }

    #[test]
    fn cells_and_metres_follow_the_spec_rule() {
        let f = frame();
        // SPEC: (ox + (x + 0.5) r, oy + (H - 1 - y + 0.5) r).
        for (x, y) in [(0usize, 0usize), (383, 199), (17, 123)] {
            let w = f.to_world(x as f64, y as f64);
            let want = [
                -10.0 + (x as f64 + 0.5) * 0.05,
                -10.5 + ((200 - 1 - y) as f64 + 0.5) * 0.05,
            ];
            assert!((w[0] - want[0]).abs() < 1e-12 && (w[1] - want[1]).abs() < 1e-12);
            assert_eq!(f.cell_at(w[0], w[1]), Ok(Cell::new(x as u16, y as u16)));
            let back = f.to_cells(w[0], w[1]);
            assert!((back[0] - x as f64).abs() < 1e-9 && (back[1] - y as f64).abs() < 1e-9);
        }
        // The lower-left corner of the image is the origin: cell (0, H - 1).
        assert_eq!(f.cell_at(-10.0, -10.5), Ok(Cell::new(0, 199)));
        assert_eq!(f.cell_at(-9.951, -10.451), Ok(Cell::new(0, 199)));
        assert_eq!(f.extent(), [[-10.0, -10.5], [-10.0 + 384.0 * 0.05, -0.5]]);
        // A point on a cell edge belongs to the cell right of it (above it), though
        // (1.7 + 10) / 0.05 is just below 234 in binary.
        assert_eq!(f.cell_at(1.7, -10.0), Ok(Cell::new(234, 189)));
        assert_eq!(f.cell_at(1.6999, -10.0001), Ok(Cell::new(233, 190)));
    }

    #[test]
    fn points_off_the_map_name_the_point_and_the_extent() {
        let f = frame();
        for p in [
            [-10.01, 0.0],
            [0.0, -10.51],
            [9.21, -5.0],
            [0.0, -0.5],
            [f64::NAN, 0.0],
        ] {
            let e = f.cell_at(p[0], p[1]).unwrap_err();
            assert!(e.to_string().contains("outside the map"), "{e}");
        }
        let e = f.cell_at(50.0, 1.0).unwrap_err();
        assert_eq!(
            e.to_string(),
            "(50, 1) m is outside the map (x -10 to 9.2 m, y -10.5 to -0.5 m)"
        );
    }

    #[test]
    fn assumed_frame_is_one_metre_a_cell() {
        let f = MapFrame::assumed(10, 4);
        assert!(!f.declared);
        assert_eq!(f.to_world(0.0, 3.0), [0.5, 0.5]);
        assert_eq!(f.to_world(9.0, 0.0), [9.5, 3.5]);
        assert_eq!(f.cells_of(0.25), 0.25);
        assert_eq!(f.inflation_cells(0.25), 0.0);
        assert_eq!(frame().inflation_cells(0.25), 4.5);
    }

    #[test]
    fn metres_print_to_the_micrometre() {
        assert_eq!(metres(9.200000000000003), "9.2");
        assert_eq!(metres(-10.0), "-10");
        assert_eq!(metres(0.0000004), "0");
        assert_eq!(metres(1.2345678), "1.234568");
    }

    #[test]
    fn points_parse_as_two_finite_numbers() {
        assert_eq!(parse_point("1.5, -2"), Ok([1.5, -2.0]));
        assert!(parse_point("1.5").is_err());
        assert!(parse_point("x,1").is_err());
        assert!(parse_point("inf,1").is_err());
    }
}

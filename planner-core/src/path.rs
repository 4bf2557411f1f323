//! Fixed-capacity paths (polylines of waypoints in cell units) and their metrics.
//!
//! A planner writes into a caller-owned `heapless` vector through its capacity-free view
//! ([`PathView`]), so one planner function serves every capacity:
//!
//! ```
//! use planner_core::{geometry::Point, path::{length, Path, PathView}};
//!
//! let mut path: Path<8> = Path::new();
//! let view: &mut PathView = &mut path;
//! view.push(Point::new(0.0, 0.0)).unwrap();
//! view.push(Point::new(3.0, 4.0)).unwrap();
//! assert_eq!(length(&path), 5.0);
//! ```

use crate::geometry::{Cell, Point, segment_clearance, segment_is_clear};
use crate::grid::GridRef;

/// A path of at most `N` waypoints.
pub type Path<const N: usize> = heapless::Vec<Point, N>;

/// The capacity-free view of a [`Path`] that planners write into.
pub type PathView = heapless::VecView<Point>;

/// Why [`validate`] rejected a path.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum PathViolation {
    /// The path has no waypoint.
    Empty,
    /// The first waypoint is not the start cell's centre.
    WrongStart,
    /// The last waypoint is not the goal cell's centre.
    WrongGoal,
    /// Segment `index` (from waypoint `index` to `index + 1`) touches a blocked cell or
    /// leaves the map.
    Collision {
        /// Index of the segment's first waypoint.
        index: usize,
    },
}

/// Checks a path under the collision rule: it starts at `start`, ends at `goal` and every
/// segment is clear. A single waypoint is valid when start equals goal and the cell is free.
pub fn validate(
    grid: GridRef<'_>,
    path: &[Point],
    start: Cell,
    goal: Cell,
) -> Result<(), PathViolation> {
    let (Some(first), Some(last)) = (path.first(), path.last()) else {
        return Err(PathViolation::Empty);
    };
    if *first != start.center() {
        return Err(PathViolation::WrongStart);
    }
    if *last != goal.center() {
        return Err(PathViolation::WrongGoal);
    }
    if path.len() == 1 && !segment_is_clear(grid, *first, *first) {
        return Err(PathViolation::Collision { index: 0 });
    }
    match path
        .windows(2)
        .position(|w| !segment_is_clear(grid, w[0], w[1]))
    {
        Some(index) => Err(PathViolation::Collision { index }),
        None => Ok(()),
    }
}

/// Total Euclidean length.
pub fn length(path: &[Point]) -> f32 {
    path.windows(2).map(|w| w[0].distance(w[1])).sum()
}

/// Number of direction changes after merging collinear nodes (`Lei2024Warehouse`'s metric `P`).
pub fn turns(path: &[Point]) -> usize {
    let mut count = 0;
    let mut heading: Option<(f32, f32)> = None;
    for w in path.windows(2) {
        let d = (w[1].x - w[0].x, w[1].y - w[0].y);
        if d.0 == 0.0 && d.1 == 0.0 {
            continue;
        }
        if let Some(h) = heading
            && !same_direction(h, d)
        {
            count += 1;
        }
        heading = Some(d);
    }
    count
}

/// The smallest distance from the path to a blocked cell or the map border, capped at `max`.
pub fn clearance(grid: GridRef<'_>, path: &[Point], max: f32) -> f32 {
    match path {
        [] => 0.0,
        [p] => segment_clearance(grid, *p, *p, max),
        _ => path
            .windows(2)
            .map(|w| segment_clearance(grid, w[0], w[1], max))
            .fold(max, f32::min),
    }
}

fn same_direction(a: (f32, f32), b: (f32, f32)) -> bool {
    let cross = a.0 * b.1 - a.1 * b.0;
    let dot = a.0 * b.0 + a.1 * b.1;
    let scale = (a.0.abs() + a.1.abs()) * (b.0.abs() + b.1.abs());
    dot > 0.0 && cross.abs() <= 1e-6 * scale
}

/// Whether `b` lies on the segment from `a` to `c`, strictly between them: exactly, not
/// within a tolerance. (A relative tolerance like that of [`turns`] let a node 8e-5 off a
/// 340-cell chord go, moving the path by more than `TOUCH_EPS` towards an obstacle it
/// had been clearing.) The differences of `f32` coordinates are exact in `f64` and the
/// products carry a relative error below 1e-16, so "exactly" holds to that precision; the
/// `f64` cost is paid once per node, off the planners' hot paths.
fn continues_straight(a: Point, b: Point, c: Point) -> bool {
    let (ux, uy) = (b.x as f64 - a.x as f64, b.y as f64 - a.y as f64);
    let (vx, vy) = (c.x as f64 - b.x as f64, c.y as f64 - b.y as f64);
    ux * vy == uy * vx && ux * vx + uy * vy > 0.0
}

/// Removes repeated waypoints and interior nodes that lie on a straight line with their
/// neighbours (the patent's first pruning step). Never changes the path's shape: only
/// nodes exactly on the segment between their neighbours go, so a valid path stays valid.
pub fn prune_collinear(path: &mut PathView) {
    let mut kept = 0usize;
    for i in 0..path.len() {
        let p = path[i];
        if kept > 0 && path[kept - 1] == p {
            continue;
        }
        if kept >= 2 {
            let (a, b) = (path[kept - 2], path[kept - 1]);
            if continues_straight(a, b, p) {
                path[kept - 1] = p;
                continue;
            }
        }
        path[kept] = p;
        kept += 1;
    }
    path.truncate(kept);
}

/// Greedy line-of-sight shortcutting (the patent's second pruning step): from each kept
/// node, jump to the farthest later node that is visible under the collision rule.
/// A valid path stays valid and never gets longer (triangle inequality).
pub fn shortcut(grid: GridRef<'_>, path: &mut PathView) {
    let n = path.len();
    if n < 3 {
        return;
    }
    let mut kept = 1usize; // path[0] stays
    let mut anchor = 0usize;
    while anchor < n - 1 {
        let mut next = anchor + 1;
        for j in (anchor + 2..n).rev() {
            if segment_is_clear(grid, path[anchor], path[j]) {
                next = j;
                break;
            }
        }
        path[kept] = path[next];
        kept += 1;
        anchor = next;
    }
    path.truncate(kept);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};

    type G = Grid<{ words_for(8, 8) }>;

    fn pts(list: &[(f32, f32)]) -> Path<32> {
        list.iter().map(|&(x, y)| Point::new(x, y)).collect()
    }

    #[test]
    fn turns_ignore_collinear_and_repeated_nodes() {
        assert_eq!(
            turns(&pts(&[(0., 0.), (1., 0.), (1., 0.), (2., 0.), (3., 0.)])),
            0
        );
        assert_eq!(
            turns(&pts(&[(0., 0.), (1., 1.), (2., 2.), (2., 3.), (3., 4.)])),
            2
        );
        assert_eq!(turns(&pts(&[(0., 0.), (2., 0.), (1., 0.)])), 1); // reversal
    }

    #[test]
    fn validate_reports_each_violation() {
        let g = G::parse_rows(b"...\n.@.\n...\n").unwrap();
        let (s, t) = (Cell::new(0, 0), Cell::new(2, 2));
        assert_eq!(validate(g.view(), &[], s, t), Err(PathViolation::Empty));
        assert_eq!(
            validate(g.view(), &pts(&[(1., 0.), (2., 2.)]), s, t),
            Err(PathViolation::WrongStart)
        );
        assert_eq!(
            validate(g.view(), &pts(&[(0., 0.), (2., 1.)]), s, t),
            Err(PathViolation::WrongGoal)
        );
        assert_eq!(
            validate(
                g.view(),
                &pts(&[(0., 0.), (2., 0.), (2., 2.), (0., 0.), (2., 2.)]),
                s,
                t
            ),
            Err(PathViolation::Collision { index: 2 })
        );
        assert_eq!(
            validate(g.view(), &pts(&[(0., 0.), (2., 0.), (2., 2.)]), s, t),
            Ok(())
        );
    }

    #[test]
    fn pruning_keeps_shape_then_shortcuts() {
        let g = G::parse_rows(b"....\n.@..\n....\n....\n").unwrap();
        let mut p = pts(&[
            (0., 0.),
            (1., 0.),
            (2., 0.),
            (3., 0.),
            (3., 1.),
            (3., 2.),
            (3., 3.),
            (2., 3.),
        ]);
        let before = length(&p);
        prune_collinear(&mut p);
        assert_eq!(p, pts(&[(0., 0.), (3., 0.), (3., 3.), (2., 3.)]));
        assert_eq!(length(&p), before);
        shortcut(g.view(), &mut p);
        // (0,0) cannot see (2,3) past the obstacle at (1,1), but (3,0) can.
        assert_eq!(p, pts(&[(0., 0.), (3., 0.), (2., 3.)]));
        assert!(validate(g.view(), &p, Cell::new(0, 0), Cell::new(2, 3)).is_ok());
    }
}

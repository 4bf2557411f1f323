//! From the exact shortest path, whose corners touch obstacles, to a valid one.
//!
//! The collision rule forbids touching a blocked cell, so the shortest length is an
//! infimum: every corner the path bends at (or grazes) moves `eps` per axis into the free
//! quadrant on the path's side. A leg between moved corners can then come within `eps` of
//! another obstacle corner it passed close by; such legs are found by the `f32` check the
//! validator uses, and the nearby corners join the path, moved off the same way.

use crate::error::PlanError;
use crate::geometry::{Point, segment_is_clear};
use crate::grid::GridRef;
use crate::path::PathView;

/// Rounds of inserting nearby corners before a larger margin is tried.
const ROUNDS: usize = 4;

/// The margin for a map: above the `f32` check's band and the rounding of coordinates of
/// this size (8 units in the last place of the longest side).
pub(super) fn margin(grid: GridRef<'_>) -> f32 {
    let side = grid.width().max(grid.height()) as f32;
    let ulp = f32::from_bits((side.to_bits() & 0x7F80_0000).saturating_sub(23 << 23));
    (8.0 * ulp).max(2.5 * crate::geometry::TOUCH_EPS)
}

/// The exact lattice point (doubled coordinates) a written waypoint was moved off.
fn exact(p: Point) -> (i32, i32) {
    (
        libm::roundf(2.0 * p.x + 1.0) as i32,
        libm::roundf(2.0 * p.y + 1.0) as i32,
    )
}

/// Rewrites `path`, holding the exact corners in doubled coordinates (start and goal are
/// cell centres), as a valid path in cell units with corners moved `eps` off.
pub(super) fn witness(grid: GridRef<'_>, path: &mut PathView, eps: f32) -> Result<(), PlanError> {
    let n = path.len();
    let mut prev = None;
    for i in 0..n {
        let v = (path[i].x as i32, path[i].y as i32);
        let next = path.get(i + 1).map(|p| (p.x as i32, p.y as i32));
        path[i] = match (prev, next) {
            (Some(a), Some(b)) => moved(grid, a, v, b, eps),
            _ => centre(v),
        };
        prev = Some(v);
    }
    for _ in 0..ROUNDS {
        let mut i = 0;
        let mut clean = true;
        while i + 1 < path.len() {
            if segment_is_clear(grid, path[i], path[i + 1]) {
                i += 1;
                continue;
            }
            clean = false;
            let inserted = insert_near(grid, path, i, eps)?;
            i += inserted + 1;
        }
        if clean {
            return Ok(());
        }
    }
    Err(PlanError::NoValidPath)
}

/// A point given in doubled coordinates, in cell units.
fn centre(v: (i32, i32)) -> Point {
    Point::new((v.0 - 1) as f32 / 2.0, (v.1 - 1) as f32 / 2.0)
}

/// Corner `v` of the path `a -> v -> b` moved `eps` per axis into the free quadrant that
/// lies farthest out of the turn (or, for a straight pass, away from the blocked cells).
fn moved(grid: GridRef<'_>, a: (i32, i32), v: (i32, i32), b: (i32, i32), eps: f32) -> Point {
    let unit = |d: (i32, i32)| {
        let (x, y) = (d.0 as f32, d.1 as f32);
        let len = crate::math::sqrt(x * x + y * y);
        if len == 0.0 {
            (0.0, 0.0)
        } else {
            (x / len, y / len)
        }
    };
    let u = unit((v.0 - a.0, v.1 - a.1));
    let w = unit((b.0 - v.0, b.1 - v.1));
    let mut out = (u.0 - w.0, u.1 - w.1);
    let (cx, cy) = (v.0 as isize / 2, v.1 as isize / 2);
    // Quadrant (sx, sy) holds cell (cx + (sx - 1) / 2, cy + (sy - 1) / 2).
    let blocked = |sx: isize, sy: isize| grid.is_blocked(cx + (sx - 1) / 2, cy + (sy - 1) / 2);
    if out.0 * out.0 + out.1 * out.1 < 1e-10 {
        // Straight through: away from the blocked cells, across the direction of travel.
        let normal = (-u.1, u.0);
        let mut side = 0.0;
        for (sx, sy) in [(-1, -1), (1, -1), (-1, 1), (1, 1)] {
            if blocked(sx, sy) {
                side += normal.0 * sx as f32 + normal.1 * sy as f32;
            }
        }
        out = if side > 0.0 {
            (-normal.0, -normal.1)
        } else {
            normal
        };
    }
    let mut best = (0isize, 0isize);
    let mut best_dot = f32::NEG_INFINITY;
    for (sx, sy) in [(-1, -1), (1, -1), (-1, 1), (1, 1)] {
        let dot = out.0 * sx as f32 + out.1 * sy as f32;
        if !blocked(sx, sy) && dot > best_dot {
            (best, best_dot) = ((sx, sy), dot);
        }
    }
    let c = centre(v);
    Point::new(c.x + eps * best.0 as f32, c.y + eps * best.1 as f32)
}

/// Inserts after waypoint `i` the obstacle corners within `2 eps` of the exact leg to
/// waypoint `i + 1`, each moved off as a straight pass; returns how many.
fn insert_near(
    grid: GridRef<'_>,
    path: &mut PathView,
    i: usize,
    eps: f32,
) -> Result<usize, PlanError> {
    let (a, b) = (exact(path[i]), exact(path[i + 1]));
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    // Along the major axis, lattice lines strictly between the ends; on each, the even
    // minor coordinates within the band (doubled units) of the leg.
    let band = 4.0 * eps;
    let steep = dy.abs() > dx.abs();
    let (a_major, a_minor, d_major, d_minor) = if steep {
        (a.1, a.0, dy, dx)
    } else {
        (a.0, a.1, dx, dy)
    };
    if d_major == 0 {
        return Ok(0);
    }
    let step = d_major.signum();
    // From the lattice line at or just past `a` to the one at or just before `b`.
    let first = if step > 0 {
        (a_major + 1) & !1
    } else {
        a_major & !1
    };
    let mut count = 0;
    let mut m = first;
    while (m - (a_major + d_major)) * step <= 0 {
        let minor = a_minor as f32 + (m - a_major) as f32 * d_minor as f32 / d_major as f32;
        let lo = libm::ceilf((minor - band) / 2.0) as i32 * 2;
        let hi = libm::floorf((minor + band) / 2.0) as i32 * 2;
        let mut k = lo;
        while k <= hi {
            let v = if steep { (k, m) } else { (m, k) };
            let (cx, cy) = (v.0 as isize / 2, v.1 as isize / 2);
            let touches = [(-1, -1), (0, -1), (-1, 0), (0, 0)]
                .iter()
                .any(|&(ox, oy)| grid.is_blocked(cx + ox, cy + oy));
            if touches && v != a && v != b {
                let p = moved(grid, a, v, b, eps);
                path.insert(i + 1 + count, p)
                    .map_err(|_| PlanError::CapacityExceeded)?;
                count += 1;
            }
            k += 2;
        }
        m += 2 * step;
    }
    Ok(count)
}

//! Preparing the corridor encoding's guide route from a shortest path.

use crate::geometry::{Point, segment_is_clear};
use crate::grid::GridRef;
use crate::path::{self, PathView};

/// Moves each interior waypoint of a shortest path (which keeps a margin off the obstacle
/// corner it wraps) further off that corner, up to `reach` cells per axis (at most half a
/// cell: the centre of the free cell diagonal to it), as far as its two legs stay clear.
/// The route keeps its homotopy class; the corridor's stations then sit in free space
/// rather than on obstacle corners, where candidate legs graze the obstacle and take the
/// slow judgement.
pub(super) fn relax(grid: GridRef<'_>, route: &mut PathView, reach: f32) {
    for i in 1..route.len().saturating_sub(1) {
        let (prev, p, next) = (route[i - 1], route[i], route[i + 1]);
        // The corner is the nearest lattice point; the waypoint sits off it diagonally.
        let corner = |v: f32| libm::roundf(v - 0.5) + 0.5;
        let (cx, cy) = (corner(p.x), corner(p.y));
        let (sx, sy) = (sign(p.x - cx), sign(p.y - cy));
        if sx == 0.0 || sy == 0.0 {
            continue;
        }
        let mut reach = reach.min(0.5);
        while reach > (p.x - cx).abs() {
            let q = Point::new(cx + sx * reach, cy + sy * reach);
            if segment_is_clear(grid, prev, q) && segment_is_clear(grid, q, next) {
                route[i] = q;
                break;
            }
            reach *= 0.5;
        }
    }
}

fn sign(v: f32) -> f32 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

/// Writes `route` into `guide` with extra points along its segments, about one per cell of
/// length (fewer if `guide` is short of room), so that corridor stations can sit anywhere on
/// it. A segment keeps its extra points only if every piece is clear under the `f32` rule (the
/// corridor checks pieces with it); otherwise it stays whole, which is clear by the exact rule.
pub(super) fn resample(grid: GridRef<'_>, route: &PathView, guide: &mut PathView) {
    guide.clear();
    let total = path::length(route);
    let room = guide.capacity().saturating_sub(route.len());
    let step = if room == 0 {
        f32::INFINITY
    } else {
        (total / room as f32).max(1.0)
    };
    let Some(&first) = route.first() else {
        return;
    };
    let _ = guide.push(first);
    for pair in route.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let pieces = if step.is_finite() {
            (libm::floorf(a.distance(b) / step) as usize).max(1)
        } else {
            1
        };
        let at = |k: usize| match k {
            0 => a,
            k if k == pieces => b,
            k => {
                let t = k as f32 / pieces as f32;
                Point::new(a.x + t * (b.x - a.x), a.y + t * (b.y - a.y))
            }
        };
        let clear = (0..pieces).all(|k| segment_is_clear(grid, at(k), at(k + 1)));
        if clear && guide.len() + pieces <= guide.capacity() {
            for k in 1..pieces {
                let _ = guide.push(at(k));
            }
        }
        let _ = guide.push(b);
    }
}

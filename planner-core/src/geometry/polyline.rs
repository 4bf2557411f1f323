//! Polylines (a global path as its points): the distance to one, the nearest point ahead along
//! it, and the point a given arc further along it. The local planner follows its global path
//! with them.

use super::types::Point;
use crate::math::{clamp, sqrt};

/// Distance from `p` to segment `ab` and the projection parameter in `[0, 1]`.
pub(super) fn project(p: Point, a: Point, b: Point) -> (f32, f32) {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = Point::new(a.x + dx * t, a.y + dy * t);
    (p.distance(q), t)
}

/// The point of `path` nearest to `p` among the stretch that starts at parameter `t0` of
/// segment `seg0` and runs `span` cells of arc further: `(distance, segment, parameter)`.
/// Ties go to the later point (corners). `path` has at least two points.
pub(crate) fn nearest_ahead(
    p: Point,
    path: &[Point],
    seg0: usize,
    t0: f32,
    span: f32,
) -> (f32, usize, f32) {
    let last = path.len() - 2;
    let seg0 = seg0.min(last);
    let t0 = t0.clamp(0.0, 1.0);
    let mut best = (f32::INFINITY, seg0, t0);
    let mut arc = 0.0f32;
    for s in seg0..=last {
        let (a, b) = (path[s], path[s + 1]);
        let lo = if s == seg0 { t0 } else { 0.0 };
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let len2 = dx * dx + dy * dy;
        let len = sqrt(len2);
        let t = if len2 > 0.0 {
            clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, lo, 1.0)
        } else {
            lo
        };
        // Do not look past the end of the stretch.
        let t = if len > 0.0 {
            t.min(lo + (span - arc).max(0.0) / len)
        } else {
            t
        };
        let q = Point::new(a.x + dx * t, a.y + dy * t);
        let d = p.distance(q);
        if d <= best.0 + 1e-4 {
            best = (d, s, t);
        }
        arc += len * (1.0 - lo);
        if arc >= span {
            break;
        }
    }
    best
}

/// The point `dist` cells of arc further along `path` than parameter `t` of segment `seg`
/// (the last point when the path ends first). `path` has at least two points.
pub(crate) fn advance(path: &[Point], seg: usize, t: f32, dist: f32) -> Point {
    let last = path.len() - 2;
    let seg = seg.min(last);
    let (a, b) = (path[seg], path[seg + 1]);
    let mut from = Point::new(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t);
    let mut left = dist;
    for s in seg..=last {
        let to = path[s + 1];
        let len = from.distance(to);
        if len >= left && len > 0.0 {
            let k = left / len;
            return Point::new(from.x + (to.x - from.x) * k, from.y + (to.y - from.y) * k);
        }
        left -= len;
        from = to;
    }
    path[path.len() - 1]
}

/// Distance from `p` to the polyline (to the point for a one-point path).
pub fn distance_to_polyline(p: Point, path: &[Point]) -> f32 {
    match path {
        [] => f32::INFINITY,
        [only] => p.distance(*only),
        _ => path
            .windows(2)
            .map(|s| project(p, s[0], s[1]).0)
            .fold(f32::INFINITY, f32::min),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distance_to_a_polyline() {
        let path = [Point::new(0.0, 0.0), Point::new(10.0, 0.0)];
        assert!((distance_to_polyline(Point::new(5.0, 2.0), &path) - 2.0).abs() < 1e-6);
    }
}

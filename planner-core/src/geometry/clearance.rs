//! Clearance: the distance from a segment or a point to the nearest blocked cell (cells off
//! the map count as blocked).

use super::polyline::project;
use super::types::Point;
use crate::grid::GridRef;
use crate::math::{at_least_zero, lesser, sqrt};

/// Distance from a segment to the nearest blocked cell (or the map's outside), capped at
/// `max`. Zero when the segment touches a blocked cell.
pub fn segment_clearance(grid: GridRef<'_>, a: Point, b: Point, max: f32) -> f32 {
    if !a.is_finite() || !b.is_finite() || max.is_nan() || max < 0.0 {
        return 0.0;
    }
    // An end on or beyond the map's edge touches an outside cell. (The scan below only
    // visits the ring of outside cells next to the map, so it used to report the distance
    // to that ring instead.) With both ends strictly inside, the whole segment is.
    let on_map = |p: Point| {
        p.x > -0.5
            && p.y > -0.5
            && p.x < grid.width() as f32 - 0.5
            && p.y < grid.height() as f32 - 0.5
    };
    if !on_map(a) || !on_map(b) {
        return 0.0;
    }
    let max = max.min((grid.width() + grid.height()) as f32);
    let reach = max + 1.0;
    let clamp = |v: f32, hi: usize| libm::floorf(v).clamp(-1.0, hi as f32) as isize;
    let x0 = clamp(a.x.min(b.x) - reach, grid.width());
    let x1 = clamp(a.x.max(b.x) + reach + 1.0, grid.width());
    let y0 = clamp(a.y.min(b.y) - reach, grid.height());
    let y1 = clamp(a.y.max(b.y) + reach + 1.0, grid.height());
    let mut best = max;
    for y in y0..=y1 {
        for x in x0..=x1 {
            if grid.is_blocked(x, y) {
                best = best.min(segment_square_distance(
                    a,
                    b,
                    Point::new(x as f32, y as f32),
                ));
            }
        }
    }
    best
}

/// Distance between segment `ab` and the closed unit square centred on `c`.
fn segment_square_distance(a: Point, b: Point, c: Point) -> f32 {
    if segment_meets_square(a, b, c) {
        return 0.0;
    }
    // Two disjoint convex sets are closest at a vertex of one of them.
    let corners = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)];
    let mut best = point_square_distance(a, c).min(point_square_distance(b, c));
    for (ox, oy) in corners {
        best = best.min(project(Point::new(c.x + ox, c.y + oy), a, b).0);
    }
    best
}

fn point_square_distance(p: Point, c: Point) -> f32 {
    let gx = ((p.x - c.x).abs() - 0.5).max(0.0);
    let gy = ((p.y - c.y).abs() - 0.5).max(0.0);
    crate::math::sqrt(gx * gx + gy * gy)
}

/// Liang-Barsky clip of segment `ab` against the closed square centred on `c`.
fn segment_meets_square(a: Point, b: Point, c: Point) -> bool {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let (mut t0, mut t1) = (0.0f32, 1.0f32);
    let edges = [
        (-dx, a.x - (c.x - 0.5)),
        (dx, (c.x + 0.5) - a.x),
        (-dy, a.y - (c.y - 0.5)),
        (dy, (c.y + 0.5) - a.y),
    ];
    for (p, q) in edges {
        if p == 0.0 {
            if q < 0.0 {
                return false;
            }
        } else {
            let t = q / p;
            if p < 0.0 {
                t0 = t0.max(t);
            } else {
                t1 = t1.min(t);
            }
            if t0 > t1 {
                return false;
            }
        }
    }
    true
}

/// Distance from `p` to the nearest blocked cell square (cells outside the map are
/// blocked), capped at `cap`; 0 inside a blocked cell or off the map.
pub fn point_clearance(grid: GridRef<'_>, p: Point, cap: f32) -> f32 {
    if !p.is_finite() || !cap.is_finite() || cap < 0.0 {
        return 0.0;
    }
    let cap = cap.min((grid.width() + grid.height()) as f32);
    let reach = cap + 0.5;
    let x0 = crate::math::floor_i(p.x - reach + 0.5).max(-1);
    let x1 = crate::math::ceil_i(p.x + reach - 0.5).min(grid.width() as isize);
    let y0 = crate::math::floor_i(p.y - reach + 0.5).max(-1);
    let y1 = crate::math::ceil_i(p.y + reach - 0.5).min(grid.height() as isize);
    let mut best2 = cap * cap;
    for y in y0..=y1 {
        let gy = at_least_zero((p.y - y as f32).abs() - 0.5);
        // Most rows near a robot on open floor hold no blocked cell: one bit test of the
        // whole run skips them (cells off the map count as blocked here too).
        if gy * gy >= best2 || !grid.row_run_blocked(y, x0, x1) {
            continue;
        }
        for x in x0..=x1 {
            if grid.is_blocked(x, y) {
                let gx = at_least_zero((p.x - x as f32).abs() - 0.5);
                best2 = lesser(best2, gx * gx + gy * gy);
            }
        }
    }
    sqrt(best2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};

    type G = Grid<{ words_for(16, 16) }>;

    fn grid(rows: &[u8]) -> G {
        G::parse_rows(rows).unwrap()
    }

    fn empty() -> Grid<{ words_for(20, 20) }> {
        Grid::new(20, 20).unwrap()
    }

    #[test]
    fn clearance_is_exact_for_simple_cases() {
        let g = grid(b".....\n.....\n..@..\n.....\n.....\n");
        let c = segment_clearance(g.view(), Point::new(0.0, 0.0), Point::new(4.0, 0.0), 10.0);
        // The obstacle's top edge is at y = 1.5; the map border is 0.5 above the segment.
        assert!((c - 0.5).abs() < 1e-6, "{c}");
        let c = segment_clearance(g.view(), Point::new(1.0, 1.0), Point::new(1.0, 1.0), 10.0);
        // Nearest is the obstacle's corner at (1.5, 1.5).
        assert!((c - core::f32::consts::FRAC_1_SQRT_2).abs() < 1e-6, "{c}");
        assert_eq!(
            segment_clearance(g.view(), Point::new(2.0, 0.0), Point::new(2.0, 4.0), 9.0),
            0.0
        );
    }

    /// The distance to the nearest blocked square over every cell (the definition).
    fn clearance_by_every_cell(grid: GridRef<'_>, p: Point, cap: f32) -> f32 {
        let mut best2 = cap * cap;
        for y in -1..=grid.height() as isize {
            for x in -1..=grid.width() as isize {
                if grid.is_blocked(x, y) {
                    let gx = ((p.x - x as f32).abs() - 0.5).max(0.0);
                    let gy = ((p.y - y as f32).abs() - 0.5).max(0.0);
                    best2 = best2.min(gx * gx + gy * gy);
                }
            }
        }
        sqrt(best2)
    }

    #[test]
    fn clearance_is_the_distance_to_the_nearest_blocked_square() {
        let mut rng = crate::optim::random::Random::new(0x9E37_79B9);
        let mut next = |n: usize| rng.index(n);
        for _ in 0..200 {
            let mut g = empty();
            for _ in 0..next(120) {
                g.set_blocked(next(20), next(20), true).unwrap();
            }
            for _ in 0..50 {
                let p = Point::new(
                    next(2400) as f32 / 100.0 - 2.0,
                    next(2400) as f32 / 100.0 - 2.0,
                );
                // Off the map, blocked squares beyond the border ring count too.
                if p.x <= -0.5 || p.y <= -0.5 || p.x >= 19.5 || p.y >= 19.5 {
                    continue;
                }
                for cap in [0.3, 1.3, 2.0, 5.0] {
                    let want = clearance_by_every_cell(g.view(), p, cap);
                    let got = point_clearance(g.view(), p, cap);
                    assert_eq!(got.to_bits(), want.to_bits(), "{p:?} cap {cap}");
                }
            }
        }
    }

    #[test]
    fn clearance_matches_geometry() {
        let mut g = empty();
        g.set_blocked(10, 10, true).unwrap();
        let d = point_clearance(g.view(), Point::new(8.0, 10.0), 5.0);
        assert!((d - 1.5).abs() < 1e-5, "{d}");
        let d = point_clearance(g.view(), Point::new(9.0, 9.0), 5.0);
        assert!((d - sqrt(0.5)).abs() < 1e-5, "{d}");
        assert_eq!(point_clearance(g.view(), Point::new(10.2, 10.0), 5.0), 0.0);
        // The map edge counts.
        let d = point_clearance(g.view(), Point::new(0.0, 5.0), 5.0);
        assert!((d - 0.5).abs() < 1e-5);
        assert_eq!(
            point_clearance(g.view(), Point::new(f32::NAN, 5.0), 5.0),
            0.0
        );
    }
}

//! Hull tests: whether the convex hull of four points keeps clear of every blocked cell, which
//! settles a whole family of segments at once (the corridor encoding caches one per pair of
//! waypoint intervals), and which few blocked cells can block a segment inside it, from
//! which [`segment_is_clear`]'s verdict follows.

use super::segment::{Strips, TOUCH_EPS, centre_cell, ordered, segment_is_clear};
use super::types::{Cell, Point};
use crate::grid::GridRef;

/// The least margin [`hull_is_clear`] accepts for a map of this size: 1/64 cell, or more on
/// maps so large that `f32` coordinates carry fewer than about 128 ulps in it. Far above
/// [`TOUCH_EPS`] and the rounding of [`segment_is_clear`], so whatever this margin proves
/// clear, that check finds clear too.
pub fn hull_margin(grid: GridRef<'_>) -> f32 {
    (1.0 / 64.0f32).max(grid.width().max(grid.height()) as f32 / 65_536.0)
}

/// Whether the convex hull of `points` stays farther than `margin` from every blocked cell
/// and from the map's edge.
///
/// Conservative: `true` proves that every segment between two points of the hull keeps
/// that margin (the union of those segments is the hull), `false` proves nothing. With a
/// margin of at least [`hull_margin`], every such segment passes [`segment_is_clear`]. It
/// lets a caller settle a whole family of segments with one test (the corridor encoding
/// caches one per pair of waypoint intervals).
///
/// ```
/// use planner_core::{geometry::{hull_is_clear, hull_margin, Point}, grid::{words_for, Grid}};
///
/// let grid: Grid<{ words_for(5, 3) }> = Grid::parse_rows(b".....\n..@..\n.....\n")?;
/// let m = hull_margin(grid.view());
/// let p = |x, y| Point::new(x, y);
/// // The band along the top row misses the obstacle; one that crosses row 1 does not.
/// assert!(hull_is_clear(grid.view(), &[p(0.0, 0.0), p(0.0, 0.4), p(4.0, 0.0), p(4.0, 0.4)], m));
/// assert!(!hull_is_clear(grid.view(), &[p(0.0, 0.0), p(0.0, 2.0), p(4.0, 0.0), p(4.0, 0.4)], m));
/// # Ok::<(), planner_core::error::MapError>(())
/// ```
pub fn hull_is_clear(grid: GridRef<'_>, points: &[Point; 4], margin: f32) -> bool {
    hull_blockers(grid, points, margin, &mut []) == Some(0)
}

/// The blocked cells that may come within `margin` of the convex hull of `points`, written
/// to the front of `out`: `Some(count)`, or `None` when there are more than `out` holds, when
/// the hull comes within `margin` of the map's edge, or for non-finite input. Every blocked
/// cell closer than `margin` to the hull is listed (some farther ones may be too).
///
/// With `Some(0)` this is [`hull_is_clear`]. Otherwise, for a segment inside the hull, the
/// cells listed are the only ones that can block it: [`segment_is_clear_among`] then gives
/// [`segment_is_clear`]'s verdict from them alone.
pub fn hull_blockers(
    grid: GridRef<'_>,
    points: &[Point; 4],
    margin: f32,
    out: &mut [Cell],
) -> Option<usize> {
    if !points.iter().all(|p| p.is_finite()) || margin.is_nan() || margin < 0.0 {
        return None;
    }
    // Comparisons, not `min`/`max` (libm calls on a Cortex-M4); the points are finite.
    let (mut x0, mut y0, mut x1, mut y1) = (points[0].x, points[0].y, points[0].x, points[0].y);
    for p in &points[1..] {
        (x0, x1) = (crate::math::lesser(x0, p.x), crate::math::greater(x1, p.x));
        (y0, y1) = (crate::math::lesser(y0, p.y), crate::math::greater(y1, p.y));
    }
    if x0 - margin <= -0.5
        || y0 - margin <= -0.5
        || x1 + margin >= grid.width() as f32 - 0.5
        || y1 + margin >= grid.height() as f32 - 0.5
    {
        return None;
    }
    // Separating axes: the normals of the hull's edges (pairs of points with the others on
    // one side); the cell's own axes are settled by the range of cells visited below. A gap
    // along one unit axis bounds the Euclidean distance from below, so any subset of axes
    // is conservative: ties and degenerate hulls can only lose a proof, never fake one.
    let mut axes = [(0.0f32, 0.0f32, 0.0f32, 0.0f32); 4];
    let mut count = 0;
    for i in 0..4 {
        for j in i + 1..4 {
            let (dx, dy) = (points[j].x - points[i].x, points[j].y - points[i].y);
            let len = crate::math::sqrt(dx * dx + dy * dy);
            if len <= 1e-6 || count == axes.len() {
                continue;
            }
            let (nx, ny) = (-dy / len, dx / len);
            let (mut lo, mut hi) = (f32::INFINITY, f32::NEG_INFINITY);
            for p in points {
                let d = p.x * nx + p.y * ny;
                (lo, hi) = (crate::math::lesser(lo, d), crate::math::greater(hi, d));
            }
            let d = points[i].x * nx + points[i].y * ny;
            if d - lo <= 1e-5 || hi - d <= 1e-5 {
                axes[count] = (nx, ny, lo - margin, hi + margin);
                count += 1;
            }
        }
    }
    let axes = &axes[..count];
    // Cells whose square comes within the margin of the bounding box.
    let cx0 = crate::math::ceil_i(x0 - margin - 0.5);
    let cx1 = crate::math::floor_i(x1 + margin + 0.5);
    let cy0 = crate::math::ceil_i(y0 - margin - 0.5);
    let cy1 = crate::math::floor_i(y1 + margin + 0.5);
    let mut count = 0;
    for cy in cy0..=cy1 {
        if !grid.row_run_blocked(cy, cx0, cx1) {
            continue;
        }
        for cx in cx0..=cx1 {
            if grid.is_blocked(cx, cy)
                && !axes.iter().any(|&(nx, ny, lo, hi)| {
                    let (c, r) = (cx as f32 * nx + cy as f32 * ny, 0.5 * (nx.abs() + ny.abs()));
                    c - r > hi || c + r < lo
                })
            {
                // On the map (the hull is inside it by the margin), so a `Cell`.
                let (Ok(x), Ok(y)) = (u16::try_from(cx), u16::try_from(cy)) else {
                    return None;
                };
                *out.get_mut(count)? = Cell::new(x, y);
                count += 1;
            }
        }
    }
    Some(count)
}

/// [`segment_is_clear`]'s verdict on `a -> b` from the only blocked cells that can block it:
/// `blockers` must list every blocked cell within `margin` (at least [`hull_margin`]) of the
/// segment and no free cell (as [`hull_blockers`] does for a hull that holds the segment),
/// and the segment must be inside the map by that margin. Bit for bit the strip scan's
/// verdict: for each blocker it computes only that cell's strip of the scan, the same way. A
/// non-finite end point is blocked, as in [`segment_is_clear`].
///
/// Most cells are settled by a separating-axis test first, a few dozen instructions: a
/// segment farther than a thin band from the cell (at most `margin / 8`, see `quick_band`)
/// is not touched by it, and one that enters it by more than that is blocked by it. Only
/// a segment that grazes the cell's edge takes the strip scan's computation.
pub fn segment_is_clear_among(
    grid: GridRef<'_>,
    a: Point,
    b: Point,
    blockers: &[Cell],
    margin: f32,
) -> bool {
    if !(a.is_finite() && b.is_finite()) {
        return false;
    }
    let centre = |c: &Cell| Point::new(f32::from(c.x), f32::from(c.y));
    clear_among(
        grid,
        a,
        b,
        blockers.iter().map(centre),
        quick_band(grid, margin),
    )
}

/// The band around a blocked cell's square inside which [`clear_among`] takes the strip scan's own
/// computation for a segment that passes `margin` (at least [`hull_margin`]) from the other
/// blocked cells. Outside it, the separating-axis tests agree with the scan: a segment that
/// misses the square grown by the band (in the maximum norm, as the scan widens its strips)
/// is clear of the cell, one that enters the square shrunk by it is blocked.
///
/// The scan decides within [`TOUCH_EPS`] of the square plus its rounding, a few ulps of the
/// map's size at most (the quick tests' own rounding is relative to the distances involved,
/// a cell or two). The band is four times `TOUCH_EPS` plus 32 ulps of the size, and at most
/// an eighth of `margin`: 5.5e-4 cells on a 40 x 40 map, `margin / 8` (1/512) from about
/// 400 cells a side. Taut legs graze obstacle corners, so the band decides how often the
/// computation is needed (measured in `docs/perf-notes.md`).
pub(crate) fn quick_band(grid: GridRef<'_>, margin: f32) -> f32 {
    let size = grid.width().max(grid.height()) as f32;
    let rounding = size * (32.0 / 8_388_608.0);
    crate::math::lesser(margin * 0.125, 4.0 * TOUCH_EPS + rounding)
}

/// [`segment_is_clear_among`] with the blocked cells given by their centres (integral
/// coordinates on the map), as the corridor encoding stores them, and finite end points
/// (the corridor's waypoints always are).
#[inline]
pub(crate) fn clear_among(
    grid: GridRef<'_>,
    a: Point,
    b: Point,
    centres: impl Iterator<Item = Point> + Clone,
    m: f32,
) -> bool {
    // The quick tests, on `a -> b` as given, with the band `m` of [`quick_band`]. They hold
    // for the exact rule between cell centres too (it blocks on touching).
    let (ex, ey) = (b.x - a.x, b.y - a.y);
    let reach = libm::fabsf(ex) + libm::fabsf(ey);
    let (xl, xh) = ordered(a.x, b.x);
    let (yl, yh) = ordered(a.y, b.y);
    // `Some(blocked)` when the quick tests settle cell `c`.
    let quick = |c: &Point| {
        let (cx, cy) = (c.x, c.y);
        // Distance from the cell's centre to the line, times |ab|, against the square's
        // half-width projected on the line's normal, times |ab|.
        let off = libm::fabsf(ex * (cy - a.y) - ey * (cx - a.x));
        let gap = |h: f32| xl > cx + h || xh < cx - h || yl > cy + h || yh < cy - h;
        if off > (0.5 + m) * reach || gap(0.5 + m) {
            Some(false)
        } else if off < (0.5 - m) * reach && !gap(0.5 - m) {
            Some(true)
        } else {
            None
        }
    };
    let mut grazed = false;
    for c in centres.clone() {
        match quick(&c) {
            Some(true) => return false,
            Some(false) => {}
            None => grazed = true,
        }
    }
    if !grazed {
        return true;
    }
    // Between cell centres the exact rule decides; it is rare here, so it takes the full check.
    if centre_cell(a).is_some() && centre_cell(b).is_some() {
        return segment_is_clear(grid, a, b);
    }
    // The grazed cells: the scan's own strips.
    let strips = Strips::new(a, b);
    !centres
        .filter(|c| quick(c).is_none())
        .any(|c| strips.visits(c))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};

    type G = Grid<{ words_for(16, 16) }>;

    fn grid(rows: &[u8]) -> G {
        G::parse_rows(rows).unwrap()
    }

    #[test]
    fn judging_among_blocked_cells_refuses_non_finite_ends() {
        let g = grid(b".....\n..@..\n.....\n");
        let m = hull_margin(g.view());
        let (p, q) = (Point::new(0.25, 0.0), Point::new(4.0, 0.25));
        let wall = [Cell::new(2, 1)];
        assert!(segment_is_clear_among(g.view(), p, q, &wall, m));
        assert!(!segment_is_clear_among(
            g.view(),
            p,
            Point::new(4.0, 1.0),
            &wall,
            m
        ));
        for bad in [f32::NAN, f32::INFINITY] {
            let r = Point::new(bad, 0.25);
            assert!(!segment_is_clear_among(g.view(), p, r, &wall, m));
            assert!(!segment_is_clear_among(g.view(), r, q, &[], m));
        }
    }
}

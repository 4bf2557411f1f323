//! The collision rule for segments between arbitrary points, in `f32`:
//! [`segment_is_clear`], conservative by [`TOUCH_EPS`], and its strip scan [`Strips`], which
//! the hull module's judgements from blocked cells share.

use super::sight::line_of_sight;
use super::types::{Cell, Point};
use crate::grid::GridRef;

/// How far a fractional segment may pass from a blocked cell and still count as touching
/// it. It only makes [`segment_is_clear`] conservative against `f32` rounding. Segments
/// between two cell centres never use it: [`segment_is_clear`] hands them to the exact
/// [`line_of_sight`], so both implementations of the rule agree there on maps of any size
/// (in `f32` alone they did not: on a 4096 x 4096 map the rounding of `y` near 3000 is
/// larger than `1/8192 - TOUCH_EPS`, the smallest margin by which such a segment misses).
pub const TOUCH_EPS: f32 = 1e-4;

/// Collision check of a segment between arbitrary points under the same rule, in `f32`
/// (conservative by [`TOUCH_EPS`]). Non-finite points and points on or beyond the map's
/// outer edge are invalid.
pub fn segment_is_clear(grid: GridRef<'_>, a: Point, b: Point) -> bool {
    // Between cell centres the exact rule decides (the planners use it, so their paths
    // always validate); `f32` rounding would otherwise reject some of them on big maps.
    // (`b` is looked at only when `a` is a centre: waypoints between stations rarely are.)
    if let Some(ca) = centre_cell(a)
        && let Some(cb) = centre_cell(b)
    {
        return line_of_sight(grid, ca, cb);
    }
    // NaN fails every comparison and an infinity one of them: no separate finiteness test.
    let inside = |p: Point| {
        p.x > -0.5 + TOUCH_EPS
            && p.y > -0.5 + TOUCH_EPS
            && p.x < grid.width() as f32 - 0.5 - TOUCH_EPS
            && p.y < grid.height() as f32 - 0.5 - TOUCH_EPS
    };
    // The map is convex, so both ends inside bound every loop below by the map size.
    if !inside(a) || !inside(b) {
        return false;
    }
    let strips = Strips::new(a, b);
    if strips.columns {
        strips.scan(|c, lo, hi| grid.column_run_blocked(c, lo, hi))
    } else {
        strips.scan(|r, lo, hi| grid.row_run_blocked(r, lo, hi))
    }
}

/// A segment between fractional points cut into unit strips, as [`segment_is_clear`] scans
/// it ([`exact_strips`](super::sight::exact_strips) for fractional end points, widened by [`TOUCH_EPS`] on every side):
/// strips `s0..=s1` across the coordinate `u`, each with the run of cells along `v` that the
/// segment touches. [`clear_among`](super::hull::clear_among) looks at single strips of the same scan, so both give
/// the same verdict bit for bit.
pub(super) struct Strips {
    /// Strips are columns (`u = x`, for a segment steeper than 45 degrees), else rows.
    columns: bool,
    u0: f32,
    v0: f32,
    u1: f32,
    v1: f32,
    du: f32,
    dv: f32,
    s0: isize,
    s1: isize,
}

impl Strips {
    #[inline(always)]
    pub(super) fn new(a: Point, b: Point) -> Self {
        let columns = (b.y - a.y).abs() > (b.x - a.x).abs();
        let (a, b) = if columns {
            ((a.x, a.y), (b.x, b.y))
        } else {
            ((a.y, a.x), (b.y, b.x))
        };
        let ((u0, v0), (u1, v1)) = if a.0 <= b.0 { (a, b) } else { (b, a) };
        Strips {
            columns,
            u0,
            v0,
            u1,
            v1,
            du: u1 - u0,
            dv: v1 - v0,
            s0: crate::math::ceil_i(u0 - 0.5 - TOUCH_EPS),
            s1: crate::math::floor_i(u1 + 0.5 + TOUCH_EPS),
        }
    }

    /// `v` on the strip edge at `u`, clamped to the segment: a strip reached only through
    /// TOUCH_EPS is touched near an end point, and extrapolating the line there would run
    /// away when du is tiny. Multiply before dividing: exact whenever the true value is
    /// representable, which keeps corner touches exact. (Not for `du == 0`.)
    #[inline(always)]
    fn edge(&self, u: f32) -> f32 {
        self.v0 + (between(u, self.u0, self.u1) - self.u0) * self.dv / self.du
    }

    /// The run of cells of a strip that the segment crosses between `v = lo` and `v = hi`.
    #[inline(always)]
    fn run(&self, (lo, hi): (f32, f32)) -> (isize, isize) {
        (
            crate::math::ceil_i(lo - 0.5 - TOUCH_EPS),
            crate::math::floor_i(hi + 0.5 + TOUCH_EPS),
        )
    }

    /// Scans the strips in order; false as soon as `blocked(strip, first, last)` is.
    #[inline(always)]
    fn scan(&self, mut blocked: impl FnMut(isize, isize, isize) -> bool) -> bool {
        // Neighbouring strips share an edge (`s + 0.5` and `(s + 1) - 0.5` are the same
        // float for any map size), so each edge is computed once.
        let mut vl = if self.du == 0.0 {
            self.v0
        } else {
            self.edge(self.s0 as f32 - 0.5)
        };
        for s in self.s0..=self.s1 {
            let (p0, p1) = self.run(if self.du == 0.0 {
                ordered(self.v0, self.v1)
            } else {
                let vr = self.edge(s as f32 + 0.5);
                let span = ordered(vl, vr);
                vl = vr;
                span
            });
            if blocked(s, p0, p1) {
                return false;
            }
        }
        true
    }

    /// Whether the scan visits the cell centred on `c` (integral coordinates): its strip is
    /// scanned and its run holds it. The strip's left edge is computed afresh, which gives
    /// the scan's value (see [`scan`](Self::scan)).
    #[inline(always)]
    pub(super) fn visits(&self, c: Point) -> bool {
        let (s, p) = if self.columns {
            (c.x as isize, c.y as isize)
        } else {
            (c.y as isize, c.x as isize)
        };
        if s < self.s0 || s > self.s1 {
            return false;
        }
        let (p0, p1) = self.run(if self.du == 0.0 {
            ordered(self.v0, self.v1)
        } else {
            ordered(self.edge(s as f32 - 0.5), self.edge(s as f32 + 0.5))
        });
        p0 <= p && p <= p1
    }
}

/// `x.clamp(lo, hi)` for `lo <= hi` without `clamp`'s assertion, whose message formats
/// floats (14 KiB of flash on Cortex-M). Same value as `clamp` for every non-NaN `x`.
#[inline]
fn between(x: f32, lo: f32, hi: f32) -> f32 {
    if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    }
}

/// `(min, max)` of two finite values by one comparison. `f32::min`/`max` are a libm call on
/// Cortex-M4 (no `VMINNM`); they may differ from this only in the sign of a zero, which the
/// callers' `lo - 0.5 - TOUCH_EPS` and `hi + 0.5 + TOUCH_EPS` erase, so results are unchanged.
#[inline]
pub(super) fn ordered(a: f32, b: f32) -> (f32, f32) {
    if b < a { (b, a) } else { (a, b) }
}

/// The cell whose centre is exactly `p`, if `p` has integral coordinates in `u16` range.
pub(super) fn centre_cell(p: Point) -> Option<Cell> {
    // The cast saturates (NaN to 0), so only integers in `0..=u16::MAX` come back equal
    // (and -0.0, which is 0).
    let integral = |v: f32| (v as u16) as f32 == v;
    (integral(p.x) && integral(p.y)).then(|| Cell::new(p.x as u16, p.y as u16))
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
    fn diagonal_step_needs_both_side_cells() {
        for rows in [&b"..\n@.\n"[..], b".@\n..\n"] {
            let g = grid(rows);
            assert!(!line_of_sight(g.view(), Cell::new(0, 0), Cell::new(1, 1)));
            assert!(!segment_is_clear(
                g.view(),
                Point::new(0.0, 0.0),
                Point::new(1.0, 1.0)
            ));
        }
        let g = grid(b"..\n..\n");
        assert!(line_of_sight(g.view(), Cell::new(0, 0), Cell::new(1, 1)));
        assert!(segment_is_clear(
            g.view(),
            Point::new(0.0, 0.0),
            Point::new(1.0, 1.0)
        ));
    }

    #[test]
    fn corner_touch_on_a_long_line_is_a_collision() {
        // (0,0) -> (3,1) passes through (1.5, 0.5), the corner of cells (1,0),(2,0),(1,1),(2,1).
        for blocked in [(2usize, 1usize), (1, 1), (2, 0), (1, 0)] {
            let mut g = G::new(4, 3).unwrap();
            g.set_blocked(blocked.0, blocked.1, true).unwrap();
            assert!(
                !line_of_sight(g.view(), Cell::new(0, 0), Cell::new(3, 1)),
                "{blocked:?}"
            );
            assert!(!segment_is_clear(
                g.view(),
                Point::new(0.0, 0.0),
                Point::new(3.0, 1.0)
            ));
        }
        // A cell the line misses by a margin stays irrelevant.
        let mut g = G::new(4, 3).unwrap();
        g.set_blocked(0, 1, true).unwrap();
        assert!(line_of_sight(g.view(), Cell::new(0, 0), Cell::new(3, 1)));
        assert!(segment_is_clear(
            g.view(),
            Point::new(0.0, 0.0),
            Point::new(3.0, 1.0)
        ));
    }

    #[test]
    fn leaving_the_map_is_blocked() {
        let g = G::new(3, 3).unwrap();
        assert!(!segment_is_clear(
            g.view(),
            Point::new(0.0, 0.0),
            Point::new(-0.6, 0.0)
        ));
        assert!(!segment_is_clear(
            g.view(),
            Point::new(0.0, 0.0),
            Point::new(f32::NAN, 0.0)
        ));
        assert!(segment_is_clear(
            g.view(),
            Point::new(0.0, 0.0),
            Point::new(2.0, 2.0)
        ));
    }

    #[test]
    fn fractional_segments() {
        let g = grid(b"...\n.@.\n...\n");
        assert!(segment_is_clear(
            g.view(),
            Point::new(0.0, 0.0),
            Point::new(2.0, 0.0)
        ));
        // y = 0.4 keeps 0.1 away from the blocked square's top edge at 0.5.
        assert!(segment_is_clear(
            g.view(),
            Point::new(0.0, 0.4),
            Point::new(2.0, 0.4)
        ));
        assert!(!segment_is_clear(
            g.view(),
            Point::new(0.0, 0.5),
            Point::new(2.0, 0.5)
        ));
        assert!(!segment_is_clear(
            g.view(),
            Point::new(0.2, 0.2),
            Point::new(1.8, 1.8)
        ));
    }
}

//! Points, cells and the collision rule shared by every planner and every check.
//!
//! SPEC section 1: cell `(x, y)` is the closed unit square centred on `(x, y)`; a segment is
//! valid only if it touches no blocked cell at all, not even an edge or a corner, and leaving
//! the map counts as blocked. For one diagonal step between cell centres this is exactly
//! "no corner cutting": the segment passes through the shared corner, so both side cells
//! must be free.
//!
//! Two implementations of the rule exist on purpose: [`line_of_sight`] is exact integer
//! arithmetic for segments between cell centres (what the search planners use), and
//! [`segment_is_clear`] handles fractional waypoints in `f32`, erring on the blocked side by
//! [`TOUCH_EPS`]; between two cell centres it defers to the exact check, so the two always
//! agree there (the tests check it).

use crate::grid::GridRef;

/// A grid cell, `(x, y)` = (column, row).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Cell {
    /// Column.
    pub x: u16,
    /// Row (grows downwards).
    pub y: u16,
}

impl Cell {
    /// A cell from its column and row.
    pub const fn new(x: u16, y: u16) -> Self {
        Cell { x, y }
    }

    /// The continuous point at the cell's centre.
    pub fn center(self) -> Point {
        Point::new(self.x as f32, self.y as f32)
    }
}

/// A continuous point in cell units: `(x, y)` = the centre of cell `(x, y)` when integral.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Point {
    /// Horizontal coordinate (column units).
    pub x: f32,
    /// Vertical coordinate (row units, downwards).
    pub y: f32,
}

impl Point {
    /// A point from its coordinates.
    pub const fn new(x: f32, y: f32) -> Self {
        Point { x, y }
    }

    /// Euclidean distance.
    pub fn distance(self, other: Point) -> f32 {
        let (dx, dy) = (other.x - self.x, other.y - self.y);
        crate::math::sqrt(dx * dx + dy * dy)
    }

    /// Whether both coordinates are finite.
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }

    /// The cell whose square contains the point (ties go to the lower index), if on the map.
    pub fn cell(self, grid: GridRef<'_>) -> Option<Cell> {
        if !self.is_finite() {
            return None;
        }
        // ceil(v - 1/2): a point on the edge between two cells goes to the lower index.
        // (floor(v + 1/2) sent ties upwards, and its rounding sent 0.49999997 to cell 1.)
        let (x, y) = (libm::ceilf(self.x - 0.5), libm::ceilf(self.y - 0.5));
        grid.contains(x as isize, y as isize)
            .then(|| Cell::new(x as u16, y as u16))
    }
}

impl From<Cell> for Point {
    fn from(cell: Cell) -> Self {
        cell.center()
    }
}

/// Octile distance between cells: the shortest 8-connected length on an empty map.
pub fn octile(a: Cell, b: Cell) -> f32 {
    let dx = (a.x as i32 - b.x as i32).unsigned_abs() as f32;
    let dy = (a.y as i32 - b.y as i32).unsigned_abs() as f32;
    let (lo, hi) = if dx < dy { (dx, dy) } else { (dy, dx) };
    hi + (core::f32::consts::SQRT_2 - 1.0) * lo
}

/// How far a fractional segment may pass from a blocked cell and still count as touching
/// it. It only makes [`segment_is_clear`] conservative against `f32` rounding. Segments
/// between two cell centres never use it: [`segment_is_clear`] hands them to the exact
/// [`line_of_sight`], so both implementations of the rule agree there on maps of any size
/// (in `f32` alone they did not: on a 4096 x 4096 map the rounding of `y` near 3000 is
/// larger than `1/8192 - TOUCH_EPS`, the smallest margin by which such a segment misses).
pub const TOUCH_EPS: f32 = 1e-4;

/// Exact collision check of the segment between two cell centres (integer arithmetic).
///
/// ```
/// use planner_core::{geometry::{line_of_sight, Cell}, grid::{words_for, Grid}};
///
/// let grid: Grid<{ words_for(3, 3) }> = Grid::parse_rows(b"...\n.@.\n...\n")?;
/// assert!(line_of_sight(grid.view(), Cell::new(0, 0), Cell::new(2, 0)));
/// assert!(!line_of_sight(grid.view(), Cell::new(0, 0), Cell::new(2, 2)));
/// // A diagonal step past the obstacle touches its corner: no corner cutting.
/// assert!(!line_of_sight(grid.view(), Cell::new(1, 0), Cell::new(2, 1)));
/// # Ok::<(), planner_core::error::MapError>(())
/// ```
pub fn line_of_sight(grid: GridRef<'_>, a: Cell, b: Cell) -> bool {
    let (dx, dy) = (b.x as i64 - a.x as i64, b.y as i64 - a.y as i64);
    // Walk the strips across the segment's short side; each strip is one run of cells.
    if dy.abs() > dx.abs() {
        exact_strips(
            (a.x as i64, a.y as i64),
            (b.x as i64, b.y as i64),
            |c, lo, hi| grid.column_run_blocked(c as isize, lo as isize, hi as isize),
        )
    } else {
        exact_strips(
            (a.y as i64, a.x as i64),
            (b.y as i64, b.x as i64),
            |r, lo, hi| grid.row_run_blocked(r as isize, lo as isize, hi as isize),
        )
    }
}

/// The number of blocked cells (or cells outside the map) the segment between two cell
/// centres touches under the collision rule: 0 exactly when [`line_of_sight`] holds. A
/// graded measure of "how blocked" a segment is, for penalties that guide an optimizer.
pub fn blocked_cells_touched(grid: GridRef<'_>, a: Cell, b: Cell) -> u32 {
    let (dx, dy) = (b.x as i64 - a.x as i64, b.y as i64 - a.y as i64);
    if dx.abs() <= 1 {
        return steep_blocked_cells(grid, a, b);
    }
    let mut count = 0;
    if dy.abs() > dx.abs() {
        exact_strips(
            (a.x as i64, a.y as i64),
            (b.x as i64, b.y as i64),
            |c, lo, hi| {
                count += grid.column_run_count(c as isize, lo as isize, hi as isize);
                false
            },
        );
    } else {
        exact_strips(
            (a.y as i64, a.x as i64),
            (b.y as i64, b.x as i64),
            |r, lo, hi| {
                count += grid.row_run_count(r as isize, lo as isize, hi as isize);
                false
            },
        );
    }
    count
}

/// [`blocked_cells_touched`] for a segment at most one column wide (seed 000's column
/// encoding is made of them): [`exact_strips`] over its one or two columns with `du = 1`
/// written out, so that its divisions become shifts. In half cells, column `x0` holds the
/// segment's `v` from `2 y0` to `y0 + y1` (its height at the column boundary), column `x1`
/// from there to `2 y1`; a cell `p` is touched when `[2p - 1, 2p + 1]` meets that range.
fn steep_blocked_cells(grid: GridRef<'_>, a: Cell, b: Cell) -> u32 {
    let (a, b) = if a.x <= b.x { (a, b) } else { (b, a) };
    let (x0, y0, y1) = (a.x as isize, a.y as isize, b.y as isize);
    if a.x == b.x {
        return grid.column_run_count(x0, y0.min(y1), y0.max(y1));
    }
    if y0 == y1 {
        return grid.row_run_count(y0, x0, x0 + 1);
    }
    // Rows touched by the half-cell range [lo2, hi2]: ceil((lo2 - 1) / 2) ..= floor((hi2 + 1) / 2).
    let run = |x: isize, from2: isize, to2: isize| {
        let (lo2, hi2) = if from2 <= to2 {
            (from2, to2)
        } else {
            (to2, from2)
        };
        grid.column_run_count(x, -((1 - lo2) >> 1), (hi2 + 1) >> 1)
    };
    let mid2 = y0 + y1;
    run(x0, 2 * y0, mid2) + run(x0 + 1, mid2, 2 * y1)
}

/// The exact rule in strip form, for a segment between lattice points `(u, v)`: strip `s`
/// spans `u` in `[s - 1/2, s + 1/2]`; the cells it touches are the `v` run whose closed
/// intervals `[p - 1/2, p + 1/2]` meet the segment's `v` range over the strip (corners
/// count). `blocked(s, lo, hi)` tests one run. Integer arithmetic in units of `1/(2 du)`.
fn exact_strips(a: (i64, i64), b: (i64, i64), blocked: impl FnMut(i64, i64, i64) -> bool) -> bool {
    // With |u|, |v| < 2^13 the strip bounds below stay under 2 du |v0| + 2 du |dv| + du <
    // 2^30 (maps up to 8192 cells a side), so 32-bit arithmetic gives the same integers; its division is a single instruction
    // on Cortex-M4 (`SDIV`), where a 64-bit one is a library call, and faster on x86 too.
    const SMALL: i64 = 1 << 13;
    let small = |p: (i64, i64)| p.0.abs() < SMALL && p.1.abs() < SMALL;
    if small(a) && small(b) {
        let narrow = |p: (i64, i64)| (p.0 as i32, p.1 as i32);
        strips::<i32>(narrow(a), narrow(b), blocked)
    } else {
        strips::<i64>(a, b, blocked)
    }
}

/// The integers [`strips`] computes in.
trait StripInt:
    Copy
    + Ord
    + Into<i64>
    + From<i32>
    + core::ops::Add<Output = Self>
    + core::ops::Sub<Output = Self>
    + core::ops::Mul<Output = Self>
    + core::ops::Div<Output = Self>
    + core::ops::Rem<Output = Self>
    + core::ops::Neg<Output = Self>
{
}
impl StripInt for i32 {}
impl StripInt for i64 {}

fn strips<T: StripInt>(
    a: (T, T),
    b: (T, T),
    mut blocked: impl FnMut(i64, i64, i64) -> bool,
) -> bool {
    let ((u0, v0), (u1, v1)) = if a.0 <= b.0 { (a, b) } else { (b, a) };
    let (du, dv) = (u1 - u0, v1 - v0);
    let (zero, one, two) = (T::from(0), T::from(1), T::from(2));
    if du == zero {
        return !blocked(u0.into(), v0.min(v1).into(), v0.max(v1).into());
    }
    let mut s = u0;
    while s <= u1 {
        let left2 = (two * s - one).max(two * u0);
        let right2 = (two * s + one).min(two * u1);
        let h_left = two * du * v0 + (left2 - two * u0) * dv;
        let h_right = two * du * v0 + (right2 - two * u0) * dv;
        let (lo, hi) = if h_left <= h_right {
            (h_left, h_right)
        } else {
            (h_right, h_left)
        };
        if blocked(
            s.into(),
            div_ceil(lo - du, two * du).into(),
            div_floor(hi + du, two * du).into(),
        ) {
            return false;
        }
        s = s + one;
    }
    true
}

fn div_floor<T: StripInt>(a: T, b: T) -> T {
    let zero = T::from(0);
    let q = a / b;
    if (a % b != zero) && ((a < zero) != (b < zero)) {
        q - T::from(1)
    } else {
        q
    }
}

fn div_ceil<T: StripInt>(a: T, b: T) -> T {
    -div_floor(-a, b)
}

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
        strips.walk(|c, lo, hi| grid.column_run_blocked(c, lo, hi))
    } else {
        strips.walk(|r, lo, hi| grid.row_run_blocked(r, lo, hi))
    }
}

/// A segment between fractional points cut into unit strips, as [`segment_is_clear`] walks
/// it ([`exact_strips`] for fractional end points, widened by [`TOUCH_EPS`] on every side):
/// strips `s0..=s1` across the coordinate `u`, each with the run of cells along `v` that the
/// segment touches. [`clear_among`] looks at single strips of the same walk, so both give
/// the same verdict bit for bit.
struct Strips {
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
    fn new(a: Point, b: Point) -> Self {
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

    /// Walks the strips in order; false as soon as `blocked(strip, first, last)` is.
    #[inline(always)]
    fn walk(&self, mut blocked: impl FnMut(isize, isize, isize) -> bool) -> bool {
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

    /// Whether the walk visits the cell centred on `c` (integral coordinates): its strip is
    /// walked and its run holds it. The strip's left edge is computed afresh, which gives
    /// the walk's value (see [`walk`](Self::walk)).
    #[inline(always)]
    fn visits(&self, c: Point) -> bool {
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
fn ordered(a: f32, b: f32) -> (f32, f32) {
    if b < a { (b, a) } else { (a, b) }
}

/// The cell whose centre is exactly `p`, if `p` has integral coordinates in `u16` range.
fn centre_cell(p: Point) -> Option<Cell> {
    // The cast saturates (NaN to 0), so only integers in `0..=u16::MAX` come back equal
    // (and -0.0, which is 0).
    let integral = |v: f32| (v as u16) as f32 == v;
    (integral(p.x) && integral(p.y)).then(|| Cell::new(p.x as u16, p.y as u16))
}

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
/// and the segment must be inside the map by that margin. Bit for bit the walk's verdict:
/// for each blocker it computes only that cell's strip of the walk, the same way. A
/// non-finite end point is blocked, as in [`segment_is_clear`].
///
/// Most cells are settled by a separating-axis test first, a few dozen instructions: a
/// segment farther than a thin band from the cell (at most `margin / 8`, see `quick_band`)
/// is not walked through it, and one that enters it by more than that is blocked by it. Only
/// a segment that grazes the cell's edge takes the walk's computation.
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

/// The band around a blocked cell's square inside which [`clear_among`] takes the walk's own
/// computation for a segment that passes `margin` (at least [`hull_margin`]) from the other
/// blocked cells. Outside it, the separating-axis tests agree with the walk: a segment that
/// misses the square grown by the band (in the maximum norm, as the walk widens its strips)
/// is clear of the cell, one that enters the square shrunk by it is blocked.
///
/// The walk decides within [`TOUCH_EPS`] of the square plus its rounding, a few ulps of the
/// map's size at most (the quick tests' own rounding is relative to the distances involved,
/// a cell or two). The band is four times `TOUCH_EPS` plus 32 ulps of the size, and at most
/// an eighth of `margin`: 5.5e-4 cells on a 40 x 40 map, `margin / 8` (1/512) from about
/// 400 cells a side. (A property test near blocked corners fails with a band of 1.2e-4.)
/// Taut legs graze obstacle corners, so the band decides how often the computation is
/// needed: 1/512 on small maps sent a fifth of the corridor's set judgements of a TCLHHO
/// plan there.
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
    // Between cell centres the exact rule decides; it is rare here, so it walks.
    if centre_cell(a).is_some() && centre_cell(b).is_some() {
        return segment_is_clear(grid, a, b);
    }
    // The grazed cells: the walk's own strips.
    let strips = Strips::new(a, b);
    !centres
        .filter(|c| quick(c).is_none())
        .any(|c| strips.visits(c))
}

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
        best = best.min(point_segment_distance(Point::new(c.x + ox, c.y + oy), a, b));
    }
    best
}

fn point_square_distance(p: Point, c: Point) -> f32 {
    let gx = ((p.x - c.x).abs() - 0.5).max(0.0);
    let gy = ((p.y - c.y).abs() - 0.5).max(0.0);
    crate::math::sqrt(gx * gx + gy * gy)
}

fn point_segment_distance(p: Point, a: Point, b: Point) -> f32 {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    p.distance(Point::new(a.x + t * dx, a.y + t * dy))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};

    type G = Grid<{ words_for(16, 16) }>;

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

    #[test]
    fn strips_in_32_and_64_bits_agree() {
        // Near the 32-bit path's limit (|u|, |v| < 2^13) and on small segments.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = |range: i64| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state % (2 * range as u64 + 1)) as i64 - range
        };
        for k in 0..4000 {
            let r = if k % 2 == 0 { 8191 } else { 40 };
            let (a, b) = ((next(r), next(r)), (next(r), next(r)));
            let (mut c32, mut c64) = (std::vec::Vec::new(), std::vec::Vec::new());
            let narrow = |p: (i64, i64)| (p.0 as i32, p.1 as i32);
            strips::<i32>(narrow(a), narrow(b), |s, lo, hi| {
                c32.push((s, lo, hi));
                false
            });
            strips::<i64>(a, b, |s, lo, hi| {
                c64.push((s, lo, hi));
                false
            });
            assert_eq!(c32, c64, "{a:?} {b:?}");
        }
    }

    #[test]
    fn integer_division_helpers() {
        assert_eq!(
            (div_floor(-3, 2), div_floor(3, 2), div_floor(4, 2)),
            (-2, 1, 2)
        );
        assert_eq!(
            (div_ceil(-3, 2), div_ceil(3, 2), div_ceil(4, 2)),
            (-1, 2, 2)
        );
    }

    #[test]
    fn octile_matches_definition() {
        assert_eq!(octile(Cell::new(0, 0), Cell::new(3, 0)), 3.0);
        let d = octile(Cell::new(0, 0), Cell::new(3, 5));
        assert!((d - (2.0 + 3.0 * core::f32::consts::SQRT_2)).abs() < 1e-5);
    }
}

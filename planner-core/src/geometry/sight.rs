//! The collision rule between cell centres, exactly, in integer arithmetic:
//! [`line_of_sight`] and [`blocked_cells_touched`], both by the strips of [`exact_strips`].

use super::types::Cell;
use crate::grid::GridRef;

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
    // Scan the strips across the segment's short side; each strip is one run of cells.
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

/// [`blocked_cells_touched`] for a segment at most one column wide (`Lei2024Warehouse`'s column
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
pub(super) fn exact_strips(
    a: (i64, i64),
    b: (i64, i64),
    blocked: impl FnMut(i64, i64, i64) -> bool,
) -> bool {
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

#[cfg(test)]
mod tests {
    use super::*;

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
}

//! The occupancy grid: bit-packed, fixed capacity, parsed from Moving AI `.map` text.
//!
//! Coordinates follow SPEC section 1: `(x, y)` = (column, row), `(0, 0)` is the upper-left
//! cell and `y` grows downwards. A set bit means *blocked*; everything outside the map is
//! blocked too, so planners never need a separate bounds rule.
//!
//! [`Grid`] owns its storage (`WORDS` 32-bit words, see [`words_for`]) so firmware can keep
//! it in a `static`; algorithms take the non-generic [`GridRef`] view so that their code is
//! not duplicated for every capacity.
//!
//! ```
//! use planner_core::grid::{words_for, Grid};
//!
//! let text = b"type octile\nheight 2\nwidth 3\nmap\n..@\n...\n";
//! let grid: Grid<{ words_for(3, 2) }> = Grid::parse_movingai(text)?;
//! assert!(grid.view().is_blocked(2, 0));
//! assert!(grid.view().is_blocked(-1, 0)); // outside counts as blocked
//! # Ok::<(), planner_core::error::MapError>(())
//! ```

use crate::error::{GridError, MapError};
use crate::geometry::Cell;

/// The number of 32-bit words a `width x height` grid needs: use it as the capacity.
pub const fn words_for(width: usize, height: usize) -> usize {
    (width * height).div_ceil(32)
}

/// Largest side length: cell coordinates are stored as `u16`.
pub const MAX_SIDE: usize = u16::MAX as usize;

/// A bit-packed occupancy grid holding up to `WORDS * 32` cells.
///
/// The bits are kept twice, row-major and column-major, so that any run of cells along a
/// row or a column is tested with a few word operations: segment checks, the planners' inner
/// loop, then cost O(short side of the segment) instead of O(cells touched). The second
/// copy costs one bit per cell.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Grid<const WORDS: usize> {
    width: usize,
    height: usize,
    bits: [u32; WORDS],
    columns: [u32; WORDS],
}

/// A borrowed, capacity-independent view of a grid.
#[derive(Clone, Copy, Debug)]
pub struct GridRef<'a> {
    width: usize,
    height: usize,
    bits: &'a [u32],
    columns: &'a [u32],
}

impl<const WORDS: usize> Grid<WORDS> {
    /// The number of cells this grid type can hold.
    pub const CAPACITY: usize = WORDS * 32;

    /// An all-free grid of the given size.
    pub const fn new(width: usize, height: usize) -> Result<Self, GridError> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(GridError::CapacityExceeded);
        }
        match width.checked_mul(height) {
            Some(cells) if cells <= Self::CAPACITY => Ok(Grid {
                width,
                height,
                bits: [0; WORDS],
                columns: [0; WORDS],
            }),
            _ => Err(GridError::CapacityExceeded),
        }
    }

    /// Width in cells.
    pub const fn width(&self) -> usize {
        self.width
    }

    /// Height in cells.
    pub const fn height(&self) -> usize {
        self.height
    }

    /// The capacity-independent view that planners take.
    pub fn view(&self) -> GridRef<'_> {
        GridRef {
            width: self.width,
            height: self.height,
            bits: &self.bits,
            columns: &self.columns,
        }
    }

    /// Marks a cell blocked (`true`) or free (`false`).
    pub fn set_blocked(&mut self, x: usize, y: usize, blocked: bool) -> Result<(), GridError> {
        if x >= self.width || y >= self.height {
            return Err(GridError::OutOfBounds);
        }
        set_bit(&mut self.bits, y * self.width + x, blocked)?;
        set_bit(&mut self.columns, x * self.height + y, blocked)
    }

    /// Parses Moving AI `.map` text: `type octile`, `height H`, `width W`, `map`, then `H`
    /// rows of `W` characters. `.` and `G` are free; `@ O T S W` are blocked (stricter than
    /// the format page for `S` and `W`, as SPEC says). CRLF line ends are accepted.
    pub fn parse_movingai(text: &[u8]) -> Result<Self, MapError> {
        let mut lines = Lines::new(text);
        let mut width = None;
        let mut height = None;
        let mut saw_type = false;
        loop {
            let (no, line) = lines.next().ok_or(MapError::MalformedHeader {
                line: lines.line_no + 1,
            })?;
            let mut words = line
                .split(|b| *b == b' ' || *b == b'\t')
                .filter(|w| !w.is_empty());
            let key = words.next();
            let value = words.next();
            if words.next().is_some() {
                return Err(MapError::MalformedHeader { line: no });
            }
            match (key, value) {
                (Some(b"type"), Some(kind)) if !saw_type => {
                    if kind != b"octile" {
                        return Err(MapError::UnsupportedType);
                    }
                    saw_type = true;
                }
                (Some(b"height"), Some(v)) if height.is_none() => {
                    height =
                        Some(parse_dimension(v).ok_or(MapError::MalformedHeader { line: no })?);
                }
                (Some(b"width"), Some(v)) if width.is_none() => {
                    width = Some(parse_dimension(v).ok_or(MapError::MalformedHeader { line: no })?);
                }
                (Some(b"map"), None) => break,
                _ => return Err(MapError::MalformedHeader { line: no }),
            }
        }
        let (Some(width), Some(height), true) = (width, height, saw_type) else {
            return Err(MapError::MalformedHeader {
                line: lines.line_no,
            });
        };
        let mut grid = Self::new(width, height).map_err(|_| {
            if width == 0 || height == 0 {
                MapError::EmptyMap
            } else {
                MapError::CapacityExceeded { width, height }
            }
        })?;
        for row in 0..height {
            let (_, line) = lines.next().ok_or(MapError::MissingRows {
                expected: height,
                found: row,
            })?;
            grid.fill_row(row, line)?;
        }
        for (no, line) in lines {
            if !line.iter().all(|b| b.is_ascii_whitespace()) {
                return Err(MapError::TrailingData { line: no });
            }
        }
        Ok(grid)
    }

    /// Parses bare rows of terrain characters (no header): all rows must have the same length.
    /// Handy for tests and generated maps.
    pub fn parse_rows(text: &[u8]) -> Result<Self, MapError> {
        let mut lines = Lines::new(text).filter(|(_, l)| !l.is_empty());
        let mut height = 0;
        let mut width = 0;
        for (_, line) in lines.by_ref() {
            if height == 0 {
                width = line.len();
            }
            height += 1;
        }
        let mut grid = Self::new(width, height).map_err(|_| {
            if width == 0 || height == 0 {
                MapError::EmptyMap
            } else {
                MapError::CapacityExceeded { width, height }
            }
        })?;
        for (row, (_, line)) in Lines::new(text).filter(|(_, l)| !l.is_empty()).enumerate() {
            grid.fill_row(row, line)?;
        }
        Ok(grid)
    }

    /// Writes the grid as Moving AI `.map` text (`.` free, `@` blocked), the inverse of
    /// [`parse_movingai`](Self::parse_movingai).
    pub fn write_movingai(&self, out: &mut impl core::fmt::Write) -> core::fmt::Result {
        write!(
            out,
            "type octile\nheight {}\nwidth {}\nmap\n",
            self.height, self.width
        )?;
        let view = self.view();
        for y in 0..self.height as isize {
            for x in 0..self.width as isize {
                out.write_char(if view.is_blocked(x, y) { '@' } else { '.' })?;
            }
            out.write_char('\n')?;
        }
        Ok(())
    }

    fn fill_row(&mut self, row: usize, line: &[u8]) -> Result<(), MapError> {
        if line.len() != self.width {
            return Err(MapError::WrongRowLength {
                row: row + 1,
                expected: self.width,
                found: line.len(),
            });
        }
        for (x, &byte) in line.iter().enumerate() {
            let blocked = match byte {
                b'.' | b'G' => false,
                b'@' | b'O' | b'T' | b'S' | b'W' => true,
                _ => {
                    return Err(MapError::UnknownCharacter {
                        row: row + 1,
                        column: x + 1,
                        byte,
                    });
                }
            };
            // Cannot fail: row < height and x < width were checked above.
            let _ = self.set_blocked(x, row, blocked);
        }
        Ok(())
    }

    /// Writes into `out` this grid inflated by a robot `radius` (in cells): a cell becomes
    /// blocked when its square comes *closer* than `radius` to a blocked cell's square.
    ///
    /// Every point of a free cell of the result is then at least `radius` from every
    /// obstacle of this grid (including the map border), so a path that is valid on the
    /// inflated grid keeps that clearance. `radius == 0` copies the grid.
    pub fn inflate_into<const W2: usize>(
        &self,
        radius: f32,
        out: &mut Grid<W2>,
    ) -> Result<(), GridError> {
        if !radius.is_finite() || radius < 0.0 {
            return Err(GridError::InvalidRadius);
        }
        *out = Grid::new(self.width, self.height)?;
        // Offsets (dx, dy) whose squares lie closer than `radius`: the gap between two unit
        // squares whose centres differ by d is max(|d| - 1, 0) on each axis.
        // Offsets are capped at one past the longer side: a longer one lands outside the map,
        // and so does the capped offset, which is closer. Without the cap a huge finite
        // radius (1e30) made the scan loop for ever.
        let cap = self.width.max(self.height) as isize + 1;
        let reach = (libm::ceilf(radius) as isize).min(cap);
        let view = self.view();
        for y in 0..self.height as isize {
            for x in 0..self.width as isize {
                let mut blocked = view.is_blocked(x, y);
                'scan: for dy in -reach..=reach {
                    for dx in -reach..=reach {
                        let gx = (dx.unsigned_abs() as f32 - 1.0).max(0.0);
                        let gy = (dy.unsigned_abs() as f32 - 1.0).max(0.0);
                        if gx * gx + gy * gy < radius * radius && view.is_blocked(x + dx, y + dy) {
                            blocked = true;
                            break 'scan;
                        }
                    }
                }
                if blocked {
                    out.set_blocked(x as usize, y as usize, true)?;
                }
            }
        }
        Ok(())
    }
}

impl<'a> GridRef<'a> {
    /// Width in cells.
    pub const fn width(&self) -> usize {
        self.width
    }

    /// Height in cells.
    pub const fn height(&self) -> usize {
        self.height
    }

    /// Number of cells.
    pub const fn cells(&self) -> usize {
        self.width * self.height
    }

    /// Whether `(x, y)` lies on the map.
    pub fn contains(&self, x: isize, y: isize) -> bool {
        x >= 0 && y >= 0 && (x as usize) < self.width && (y as usize) < self.height
    }

    /// Blocked cells and cells outside the map are blocked.
    #[inline]
    pub fn is_blocked(&self, x: isize, y: isize) -> bool {
        if !self.contains(x, y) {
            return true;
        }
        let i = y as usize * self.width + x as usize;
        match self.bits.get(i / 32) {
            Some(word) => word & (1 << (i % 32)) != 0,
            None => true,
        }
    }

    /// Whether any cell of row `y`, columns `x0..=x1`, is blocked (cells outside the map are).
    #[inline]
    pub fn row_run_blocked(&self, y: isize, x0: isize, x1: isize) -> bool {
        if x0 > x1 {
            return false;
        }
        if y < 0 || x0 < 0 || y as usize >= self.height || x1 as usize >= self.width {
            return true;
        }
        let base = y as usize * self.width;
        any_set(self.bits, base + x0 as usize, base + x1 as usize)
    }

    /// Whether any cell of column `x`, rows `y0..=y1`, is blocked (cells outside the map are).
    #[inline]
    pub fn column_run_blocked(&self, x: isize, y0: isize, y1: isize) -> bool {
        if y0 > y1 {
            return false;
        }
        if x < 0 || y0 < 0 || x as usize >= self.width || y1 as usize >= self.height {
            return true;
        }
        let base = x as usize * self.height;
        any_set(self.columns, base + y0 as usize, base + y1 as usize)
    }

    /// Number of blocked cells in row `y`, columns `x0..=x1` (cells outside the map count).
    #[inline]
    pub fn row_run_count(&self, y: isize, x0: isize, x1: isize) -> u32 {
        run_count(self.bits, self.height, self.width, y, x0, x1)
    }

    /// Number of blocked cells in column `x`, rows `y0..=y1` (cells outside the map count).
    #[inline]
    pub fn column_run_count(&self, x: isize, y0: isize, y1: isize) -> u32 {
        run_count(self.columns, self.width, self.height, x, y0, y1)
    }

    /// Whether a cell is on the map and free.
    #[inline]
    pub fn is_free(&self, cell: Cell) -> bool {
        !self.is_blocked(cell.x as isize, cell.y as isize)
    }

    /// Row-major index of a cell (`y * width + x`); `None` outside the map.
    #[inline]
    pub fn index(&self, cell: Cell) -> Option<usize> {
        let (x, y) = (cell.x as usize, cell.y as usize);
        (x < self.width && y < self.height).then_some(y * self.width + x)
    }

    /// The cell of a row-major index.
    #[inline]
    pub fn cell(&self, index: usize) -> Cell {
        Cell::new((index % self.width) as u16, (index / self.width) as u16)
    }

    /// Number of blocked cells on the map.
    pub fn blocked_count(&self) -> usize {
        (0..self.cells())
            .filter(|&i| self.is_blocked((i % self.width) as isize, (i / self.width) as isize))
            .count()
    }
}

fn set_bit(bits: &mut [u32], i: usize, value: bool) -> Result<(), GridError> {
    let slot = bits.get_mut(i / 32).ok_or(GridError::OutOfBounds)?;
    if value {
        *slot |= 1 << (i % 32);
    } else {
        *slot &= !(1 << (i % 32));
    }
    Ok(())
}

/// Whether any bit in `first..=last` is set (missing words count as set).
#[inline]
fn any_set(bits: &[u32], first: usize, last: usize) -> bool {
    let (w0, w1) = (first / 32, last / 32);
    let head = !0u32 << (first % 32);
    let tail = !0u32 >> (31 - last % 32);
    if w0 == w1 {
        return bits.get(w0).is_none_or(|w| w & head & tail != 0);
    }
    match (bits.get(w0), bits.get(w1), bits.get(w0 + 1..w1)) {
        (Some(a), Some(b), Some(mid)) => {
            a & head != 0 || b & tail != 0 || mid.iter().any(|w| *w != 0)
        }
        _ => true,
    }
}

/// Blocked cells at positions `lo..=hi` of line `line` in a bitset of `lines` lines of `len`
/// cells each (rows or columns); positions and lines off the map count as blocked.
#[inline]
fn run_count(bits: &[u32], lines: usize, len: usize, line: isize, lo: isize, hi: isize) -> u32 {
    if lo > hi {
        return 0;
    }
    let span = (hi - lo + 1) as u32;
    let (inside_lo, inside_hi) = (lo.max(0), hi.min(len as isize - 1));
    if line < 0 || line as usize >= lines || inside_lo > inside_hi {
        return span;
    }
    let base = line as usize * len;
    let inside = (inside_hi - inside_lo + 1) as u32;
    span - inside + count_set(bits, base + inside_lo as usize, base + inside_hi as usize)
}

/// Number of set bits in `first..=last` (missing words count as all set).
fn count_set(bits: &[u32], first: usize, last: usize) -> u32 {
    let (w0, w1) = (first / 32, last / 32);
    let head = !0u32 << (first % 32);
    let tail = !0u32 >> (31 - last % 32);
    // Most runs are free: test for zero before counting (neither x86_64's baseline nor the
    // Cortex-M4 has a population-count instruction, so `count_ones` is a dozen operations).
    let count = |w: usize, mask: u32| match bits.get(w) {
        Some(v) if v & mask == 0 => 0,
        Some(v) => (v & mask).count_ones(),
        None => mask.count_ones(),
    };
    if w0 == w1 {
        return count(w0, head & tail);
    }
    (w0 + 1..w1).map(|w| count(w, !0)).sum::<u32>() + count(w0, head) + count(w1, tail)
}

/// Parses a decimal side length; `None` for anything but 1-6 ASCII digits.
fn parse_dimension(text: &[u8]) -> Option<usize> {
    if text.is_empty() || text.len() > 6 {
        return None;
    }
    text.iter().try_fold(0usize, |acc, &b| {
        b.is_ascii_digit().then(|| acc * 10 + (b - b'0') as usize)
    })
}

/// Lines of a byte slice with 1-based numbers, without the `\n` or `\r\n`.
struct Lines<'t> {
    rest: &'t [u8],
    line_no: usize,
}

impl<'t> Lines<'t> {
    fn new(text: &'t [u8]) -> Self {
        Lines {
            rest: text,
            line_no: 0,
        }
    }
}

impl<'t> Iterator for Lines<'t> {
    type Item = (usize, &'t [u8]);

    fn next(&mut self) -> Option<Self::Item> {
        if self.rest.is_empty() {
            return None;
        }
        let (line, rest) = match self.rest.iter().position(|&b| b == b'\n') {
            Some(n) => (&self.rest[..n], &self.rest[n + 1..]),
            None => (self.rest, &[][..]),
        };
        self.rest = rest;
        self.line_no += 1;
        let line = line.strip_suffix(b"\r").unwrap_or(line);
        Some((self.line_no, line))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type Small = Grid<{ words_for(8, 8) }>;

    const HEADER: &[u8] = b"type octile\nheight 2\nwidth 3\nmap\n";

    fn with_rows(rows: &[u8]) -> heapless::Vec<u8, 256> {
        let mut v = heapless::Vec::new();
        v.extend_from_slice(HEADER).unwrap();
        v.extend_from_slice(rows).unwrap();
        v
    }

    #[test]
    fn parses_terrain_codes() {
        let g = Small::parse_movingai(&with_rows(b".G@\nOTS\n")).unwrap();
        let v = g.view();
        assert!(!v.is_blocked(0, 0) && !v.is_blocked(1, 0));
        assert!((0..3).all(|x| v.is_blocked(x, 1)) && v.is_blocked(2, 0));
        assert_eq!((v.width(), v.height()), (3, 2));
    }

    #[test]
    fn accepts_crlf_and_trailing_blank_lines() {
        let g = Small::parse_movingai(
            b"type octile\r\nheight 2\r\nwidth 3\r\nmap\r\n...\r\n..@\r\n\r\n",
        )
        .unwrap();
        assert!(g.view().is_blocked(2, 1));
    }

    #[test]
    fn every_map_error_is_reachable() {
        let cases: [(&[u8], MapError); 9] = [
            (b"", MapError::MalformedHeader { line: 1 }),
            (
                b"type octile\nheight x\n",
                MapError::MalformedHeader { line: 2 },
            ),
            (b"type grid\n", MapError::UnsupportedType),
            (b"type octile\nheight 0\nwidth 3\nmap\n", MapError::EmptyMap),
            (
                b"type octile\nheight 9\nwidth 9\nmap\n",
                MapError::CapacityExceeded {
                    width: 9,
                    height: 9,
                },
            ),
            (
                &with_rows(b"...\n....\n"),
                MapError::WrongRowLength {
                    row: 2,
                    expected: 3,
                    found: 4,
                },
            ),
            (
                &with_rows(b"...\n.x.\n"),
                MapError::UnknownCharacter {
                    row: 2,
                    column: 2,
                    byte: b'x',
                },
            ),
            (
                &with_rows(b"...\n"),
                MapError::MissingRows {
                    expected: 2,
                    found: 1,
                },
            ),
            (
                &with_rows(b"...\n...\n...\n"),
                MapError::TrailingData { line: 7 },
            ),
        ];
        for (text, want) in cases {
            assert_eq!(
                Small::parse_movingai(text),
                Err(want),
                "{:?}",
                core::str::from_utf8(text)
            );
        }
    }

    #[test]
    fn rejects_header_without_map_line_and_duplicates() {
        assert!(matches!(
            Small::parse_movingai(b"type octile\nheight 2\nwidth 2\n"),
            Err(MapError::MalformedHeader { .. })
        ));
        assert!(matches!(
            Small::parse_movingai(b"type octile\nheight 2\nheight 2\nwidth 2\nmap\n..\n..\n"),
            Err(MapError::MalformedHeader { line: 3 })
        ));
    }

    #[test]
    fn outside_is_blocked_and_index_round_trips() {
        let g = Small::new(5, 4).unwrap();
        let v = g.view();
        assert!(v.is_blocked(-1, 0) && v.is_blocked(5, 0) && v.is_blocked(0, 4));
        for i in 0..v.cells() {
            assert_eq!(v.index(v.cell(i)), Some(i));
        }
        assert_eq!(v.index(Cell::new(5, 0)), None);
    }

    #[test]
    fn writes_what_it_parses() {
        let g = Small::parse_rows(b"..@.\n@...\n").unwrap();
        let mut text: heapless::String<128> = heapless::String::new();
        g.write_movingai(&mut text).unwrap();
        assert_eq!(
            text.as_str(),
            "type octile\nheight 2\nwidth 4\nmap\n..@.\n@...\n"
        );
        assert_eq!(Small::parse_movingai(text.as_bytes()).unwrap(), g);
    }

    #[test]
    fn runs_agree_with_cells() {
        let g = Small::parse_rows(b"........\n...@....\n........\n.......@\n@.......\n").unwrap();
        let v = g.view();
        for a in -1..9isize {
            for b in a..9 {
                for line in -1..9isize {
                    let row = (a..=b).any(|x| v.is_blocked(x, line));
                    assert_eq!(v.row_run_blocked(line, a, b), row, "row {line} {a}..{b}");
                    let col = (a..=b).any(|y| v.is_blocked(line, y));
                    assert_eq!(v.column_run_blocked(line, a, b), col, "col {line} {a}..{b}");
                }
            }
        }
        assert!(!v.row_run_blocked(0, 3, 2));
        for a in -2..10isize {
            for b in a..10 {
                for line in -1..9isize {
                    let row = (a..=b).filter(|&x| v.is_blocked(x, line)).count() as u32;
                    assert_eq!(v.row_run_count(line, a, b), row, "row {line} {a}..{b}");
                    let col = (a..=b).filter(|&y| v.is_blocked(line, y)).count() as u32;
                    assert_eq!(v.column_run_count(line, a, b), col, "col {line} {a}..{b}");
                }
            }
        }
        let mut wide = Grid::<{ words_for(100, 2) }>::new(100, 2).unwrap();
        wide.set_blocked(70, 1, true).unwrap();
        assert!(wide.view().row_run_blocked(1, 5, 95));
        assert!(!wide.view().row_run_blocked(1, 5, 69));
        assert!(!wide.view().row_run_blocked(0, 0, 99));
    }

    #[test]
    fn new_and_set_report_errors() {
        assert_eq!(Small::new(0, 3), Err(GridError::CapacityExceeded));
        assert_eq!(Small::new(9, 8), Err(GridError::CapacityExceeded));
        let mut g = Small::new(2, 2).unwrap();
        assert_eq!(g.set_blocked(2, 0, true), Err(GridError::OutOfBounds));
    }

    #[test]
    fn inflation_blocks_squares_closer_than_radius() {
        let mut g = Small::new(7, 7).unwrap();
        g.set_blocked(3, 3, true).unwrap();
        let mut out = Small::new(1, 1).unwrap();
        g.inflate_into(0.0, &mut out).unwrap();
        assert_eq!(out, g);
        g.inflate_into(0.5, &mut out).unwrap();
        // The eight neighbours touch the obstacle square; cells two away are 1.0 away.
        // The border ring touches the outside, which counts as blocked.
        assert_eq!(out.view().blocked_count(), 9 + 24);
        g.inflate_into(f32::NAN, &mut out).unwrap_err();
        assert_eq!(
            g.inflate_into(-1.0, &mut out),
            Err(GridError::InvalidRadius)
        );
    }
}

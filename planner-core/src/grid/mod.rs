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
use crate::geometry::types::Cell;

#[cfg(feature = "alloc")]
mod buf;
mod inflate;
mod movingai;

#[cfg(feature = "alloc")]
pub use buf::GridBuf;

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
        self.view_mut().set_blocked(x, y, blocked)
    }

    /// Parses Moving AI `.map` text: `type octile`, `height H`, `width W`, `map`, then `H`
    /// rows of `W` characters. `.` and `G` are free; `@ O T S W` are blocked (stricter than
    /// the format page for `S` and `W`). CRLF line ends are accepted.
    pub fn parse_movingai(text: &[u8]) -> Result<Self, MapError> {
        let (width, height, mut body) = movingai::header(text)?;
        let mut grid = Self::new(width, height).map_err(|_| movingai::size_error(width, height))?;
        movingai::fill(&mut grid.view_mut(), &mut body)?;
        Ok(grid)
    }

    /// Parses bare rows of terrain characters (no header): all rows must have the same length.
    /// Handy for tests and generated maps.
    pub fn parse_rows(text: &[u8]) -> Result<Self, MapError> {
        let (width, height) = movingai::rows_size(text);
        let mut grid = Self::new(width, height).map_err(|_| movingai::size_error(width, height))?;
        movingai::fill_rows(&mut grid.view_mut(), text)?;
        Ok(grid)
    }

    /// Writes the grid as Moving AI `.map` text (`.` free, `@` blocked), the inverse of
    /// [`parse_movingai`](Self::parse_movingai).
    pub fn write_movingai(&self, out: &mut impl core::fmt::Write) -> core::fmt::Result {
        movingai::write(self.view(), out)
    }

    /// The mutable capacity-independent view.
    pub fn view_mut(&mut self) -> GridMut<'_> {
        GridMut {
            width: self.width,
            height: self.height,
            bits: &mut self.bits,
            columns: &mut self.columns,
        }
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
        inflate::check_radius(radius)?;
        *out = Grid::new(self.width, self.height)?;
        inflate::inflate(self.view(), radius, &mut out.view_mut())
    }
}

/// A mutable, capacity-independent view of a grid (what [`Grid`] and, with the `alloc`
/// feature, [`GridBuf`] lend to the loaders and to inflation).
#[derive(Debug)]
pub struct GridMut<'a> {
    width: usize,
    height: usize,
    bits: &'a mut [u32],
    columns: &'a mut [u32],
}

impl<'a> GridMut<'a> {
    /// A mutable view of a grid whose bits live elsewhere (see [`GridRef::from_words`]);
    /// writing through it keeps both layouts in step.
    pub fn from_words(
        width: usize,
        height: usize,
        rows: &'a mut [u32],
        columns: &'a mut [u32],
    ) -> Result<Self, GridError> {
        check_words(width, height, rows.len(), columns.len())?;
        Ok(GridMut {
            width,
            height,
            bits: rows,
            columns,
        })
    }
}

impl GridMut<'_> {
    /// The read-only view.
    pub fn view(&self) -> GridRef<'_> {
        GridRef {
            width: self.width,
            height: self.height,
            bits: self.bits,
            columns: self.columns,
        }
    }

    /// Marks a cell blocked (`true`) or free (`false`).
    pub fn set_blocked(&mut self, x: usize, y: usize, blocked: bool) -> Result<(), GridError> {
        if x >= self.width || y >= self.height {
            return Err(GridError::OutOfBounds);
        }
        set_bit(self.bits, y * self.width + x, blocked)?;
        set_bit(self.columns, x * self.height + y, blocked)
    }

    /// Sets every row at once: `row(y, words)` fills row `y` into `words` (bit `x % 32` of
    /// word `x / 32` is cell `x`, set = blocked; bits past the width are ignored). Faster
    /// than [`set_blocked`](Self::set_blocked) cell by cell on big maps: whole words, then
    /// one transposition for the column layout. Rows of up to [`MAX_ROW_WORDS`] words
    /// (8192 cells); wider maps are [`GridError::CapacityExceeded`].
    pub fn fill_rows(&mut self, mut row: impl FnMut(usize, &mut [u32])) -> Result<(), GridError> {
        let row_words = self.width.div_ceil(32);
        if row_words > MAX_ROW_WORDS {
            return Err(GridError::CapacityExceeded);
        }
        let mut words = [0u32; MAX_ROW_WORDS];
        for y in 0..self.height {
            words[..row_words].fill(0);
            row(y, &mut words[..row_words]);
            self.write_row(y, &words[..row_words]);
        }
        self.rebuild_columns();
        Ok(())
    }

    /// Writes row `y` of the row-major bits from aligned words (cell `x` is bit `x % 32` of
    /// word `x / 32`); the column layout is left stale until [`rebuild_columns`].
    pub(crate) fn write_row(&mut self, y: usize, row: &[u32]) {
        let w = self.width;
        if y >= self.height {
            return;
        }
        for (i, &word) in row.iter().enumerate().take(w.div_ceil(32)) {
            let n = (w - 32 * i).min(32);
            write_bits(self.bits, y * w + 32 * i, word, n);
        }
    }

    /// Recomputes the column-major bits from the row-major ones, 32 x 32 blocks at a time.
    pub(crate) fn rebuild_columns(&mut self) {
        let (w, h) = (self.width, self.height);
        let mut block = [0u32; 32];
        for y0 in (0..h).step_by(32) {
            let rows = (h - y0).min(32);
            for x0 in (0..w).step_by(32) {
                let cols = (w - x0).min(32);
                let mask = if cols == 32 { !0 } else { (1u32 << cols) - 1 };
                for (r, slot) in block.iter_mut().enumerate() {
                    *slot = if r < rows {
                        word_at(self.bits, (y0 + r) * w + x0) & mask
                    } else {
                        0
                    };
                }
                transpose32(&mut block);
                for (c, &word) in block.iter().enumerate().take(cols) {
                    write_bits(self.columns, (x0 + c) * h + y0, word, rows);
                }
            }
        }
    }
}

/// Longest row, in words, that [`GridMut::fill_rows`] and inflation take: 8192 cells.
pub const MAX_ROW_WORDS: usize = 256;

/// The 32 bits starting at bit `start` (bits past the slice read as 0).
#[inline]
pub(crate) fn word_at(bits: &[u32], start: usize) -> u32 {
    let (i, r) = (start / 32, (start % 32) as u32);
    let lo = bits.get(i).copied().unwrap_or(0);
    if r == 0 {
        return lo;
    }
    let hi = bits.get(i + 1).copied().unwrap_or(0);
    (lo >> r) | (hi << (32 - r))
}

/// Writes the low `n` bits of `value` at bit `start` (`n <= 32`; bits past the slice are
/// dropped).
fn write_bits(bits: &mut [u32], start: usize, value: u32, n: usize) {
    if n == 0 {
        return;
    }
    let mask = (1u64 << n.min(32)) - 1;
    let (i, r) = (start / 32, start % 32);
    let wide = ((value as u64) & mask) << r;
    let wide_mask = mask << r;
    if let Some(lo) = bits.get_mut(i) {
        *lo = (*lo & !(wide_mask as u32)) | wide as u32;
    }
    if wide_mask >> 32 != 0
        && let Some(hi) = bits.get_mut(i + 1)
    {
        *hi = (*hi & !((wide_mask >> 32) as u32)) | (wide >> 32) as u32;
    }
}

/// Transposes a 32 x 32 bit matrix in place: bit `c` of word `r` moves to bit `r` of word
/// `c` (Hacker's Delight, 7-3). Public for packers of the grid's column-major words (the
/// planner service's map frames).
pub fn transpose32(m: &mut [u32; 32]) {
    let mut j = 16;
    let mut mask: u32 = 0x0000_FFFF;
    while j != 0 {
        let mut k = 0;
        while k < 32 {
            let t = ((m[k] >> j) ^ m[k + j]) & mask;
            m[k] ^= t << j;
            m[k + j] ^= t;
            k = (k + j + 1) & !j;
        }
        j >>= 1;
        mask ^= mask << j;
    }
}

impl<'a> GridRef<'a> {
    /// A view of a grid whose bits live elsewhere (shared memory, a frame from a peer): `rows`
    /// holds the row-major bits and `columns` the column-major ones, each at least
    /// [`words_for`]`(width, height)` words. Nothing is copied, and nothing checks that the
    /// two layouts agree: they must be one grid's (as [`GridMut`] keeps them), or planners
    /// answer for a map that is neither. [`GridError::CapacityExceeded`] for a zero side, a
    /// side above [`MAX_SIDE`], or too few words.
    pub fn from_words(
        width: usize,
        height: usize,
        rows: &'a [u32],
        columns: &'a [u32],
    ) -> Result<Self, GridError> {
        check_words(width, height, rows.len(), columns.len())?;
        Ok(GridRef {
            width,
            height,
            bits: rows,
            columns,
        })
    }

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

    /// The 32 cells of row `y` from column `x` on, as bits (bit `i` is cell `x + i`; set =
    /// blocked, cells past the row's end or off the map are blocked).
    #[inline]
    pub fn row_bits(&self, y: usize, x: usize) -> u32 {
        if y >= self.height || x >= self.width {
            return !0;
        }
        let left = self.width - x;
        let bits = word_at(self.bits, y * self.width + x);
        if left >= 32 {
            bits
        } else {
            bits | (!0u32 << left)
        }
    }

    /// The first blocked column of row `y` at or after `x` (`width` when there is none).
    #[inline]
    pub fn next_blocked(&self, y: usize, mut x: usize) -> usize {
        while x < self.width {
            let bits = self.row_bits(y, x);
            if bits != 0 {
                return (x + bits.trailing_zeros() as usize).min(self.width);
            }
            x += 32;
        }
        self.width
    }

    /// The first free column of row `y` at or after `x` (`width` when there is none).
    #[inline]
    pub fn next_free(&self, y: usize, mut x: usize) -> usize {
        while x < self.width {
            let free = !self.row_bits(y, x);
            if free != 0 {
                return (x + free.trailing_zeros() as usize).min(self.width);
            }
            x += 32;
        }
        self.width
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

/// The size checks of the `from_words` views.
fn check_words(width: usize, height: usize, rows: usize, columns: usize) -> Result<(), GridError> {
    if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
        return Err(GridError::CapacityExceeded);
    }
    let words = words_for(width, height);
    if rows < words || columns < words {
        return Err(GridError::CapacityExceeded);
    }
    Ok(())
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
    fn views_of_outside_words_read_and_write_both_layouts() {
        let (mut rows, mut cols) = ([0u32; 4], [0u32; 4]);
        let mut g = GridMut::from_words(10, 9, &mut rows, &mut cols).unwrap();
        g.set_blocked(7, 3, true).unwrap();
        let v = g.view();
        assert!(v.is_blocked(7, 3) && v.row_run_blocked(3, 0, 9) && v.column_run_blocked(7, 0, 8));
        let v = GridRef::from_words(10, 9, &rows, &cols).unwrap();
        assert!(v.is_blocked(7, 3) && !v.is_blocked(3, 7));
        assert_eq!(
            GridRef::from_words(10, 13, &rows, &cols).err(),
            Some(GridError::CapacityExceeded)
        );
        assert!(GridRef::from_words(0, 1, &rows, &cols).is_err());
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

#[cfg(test)]
mod bit_tests {
    #[test]
    fn transpose32_moves_bit_c_of_row_r_to_bit_r_of_row_c() {
        let mut m = [0u32; 32];
        let mut seed = 0x9E37_79B9u32;
        for w in m.iter_mut() {
            seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            *w = seed;
        }
        let orig = m;
        super::transpose32(&mut m);
        for (r, row) in orig.iter().enumerate() {
            for (c, column) in m.iter().enumerate() {
                assert_eq!((column >> r) & 1, (row >> c) & 1, "r {r} c {c}");
            }
        }
    }
}

//! The map frame: a header (`planner.v1.MapHeader`, 32 bytes, 4-aligned, the iceoryx2 user
//! header of the `P/map` publish-subscribe service) and a slice of `u32` words holding the
//! cells; how the cells pack into the words, and the checks a receiver runs.

use super::{ServiceError, WIRE_VERSION};
use iceoryx2::prelude::ZeroCopySend;
use planner_core::error::GridError;
use planner_core::grid::{GridBuf, GridMut, GridRef, MAX_SIDE};
use serde::{Deserialize, Serialize};

/// The header of a map frame. A frame is this header (iceoryx2 user header) plus a slice
/// of 32-bit words holding the cells bit-packed as planner-core's grid holds them (set =
/// blocked), in one or two layouts that [`MapHeader::layout`] names:
///
/// - [`LAYOUT_ROWS_AND_COLUMNS`] (what this build's client sends): `2 * n` words, `n =
///   ceil(width * height / 32)` ([`MapHeader::words`]). Words `0..n` are the row-major
///   bits (cell `(x, y)` is bit `i % 32` of word `i / 32`, `i = y * width + x`), words
///   `n..2n` the column-major bits (cell `(x, y)` is bit `j % 32` of word `n + j / 32`,
///   `j = x * height + y`). Neither layout pads its lines. The server plans on a view of
///   the frame as it lies in shared memory, so **both layouts must describe the same
///   map**: a sender writing raw words must write both (a
///   [`MapLoan`](crate::client::MapLoan)'s `GridMut` keeps them in step). The server
///   checks them against each other only when started with `--verify-maps`
///   ([`first_disagreement`]); otherwise a frame whose layouts disagree is planned on as
///   sent, and answers follow whichever layout a planner reads.
/// - [`LAYOUT_ROWS`] (simplest for a foreign sender, and byte-stream peers): `n` words, the
///   row-major bits only; the receiver builds its own grid from them ([`grid_from_bits`]).
///
/// Words past the layouts are ignored. Sizes are checked by the receiver ([`frame_grid`],
/// [`MapHeader::check`]): another wire version is [`ServiceError::UnsupportedVersion`]; a
/// zero side, an unknown layout, a reserved byte not zero or fewer words than the layout
/// needs is [`ServiceError::InvalidRequest`]; a side beyond 65535 or more cells than the
/// server's limit is [`ServiceError::MapTooLarge`].
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend, Serialize, Deserialize)]
#[type_name("planner.v1.MapHeader")]
#[repr(C)]
pub struct MapHeader {
    /// [`WIRE_VERSION`].
    pub wire_version: u16,
    /// Which layouts the words hold: [`LAYOUT_ROWS`] or [`LAYOUT_ROWS_AND_COLUMNS`].
    pub layout: u8,
    /// Reserved, zero.
    pub reserved: u8,
    /// Which map (several maps may be served at once).
    pub map_id: u32,
    /// Version of this map id, increasing with every upload; requests name the version
    /// they plan against.
    pub map_version: u32,
    /// Width in cells.
    pub width: u32,
    /// Height in cells.
    pub height: u32,
    /// Metres per cell (informational; planning is in cell units).
    pub resolution: f32,
    /// World position of cell `(0, 0)`'s centre (the upper-left cell), metres
    /// (informational).
    pub origin: [f32; 2],
}

impl Default for MapHeader {
    fn default() -> Self {
        MapHeader {
            wire_version: WIRE_VERSION,
            layout: LAYOUT_ROWS_AND_COLUMNS,
            reserved: 0,
            map_id: 0,
            map_version: 1,
            width: 0,
            height: 0,
            resolution: 0.0,
            origin: [0.0; 2],
        }
    }
}

/// [`MapHeader::layout`]: the row-major bits only (`n` words).
pub const LAYOUT_ROWS: u8 = 0;
/// [`MapHeader::layout`]: the row-major bits, then the column-major bits (`2 * n` words).
pub const LAYOUT_ROWS_AND_COLUMNS: u8 = 1;

/// Metadata of a map, without its cells.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapMeta {
    /// Map id.
    pub map_id: u32,
    /// The map's version.
    pub version: u32,
    /// Metres per cell.
    pub resolution: f32,
    /// World position of cell `(0, 0)`'s centre, metres.
    pub origin: [f32; 2],
}

impl MapHeader {
    /// The header's metadata.
    pub fn meta(&self) -> MapMeta {
        MapMeta {
            map_id: self.map_id,
            version: self.map_version,
            resolution: self.resolution,
            origin: self.origin,
        }
    }

    /// Words one layout of the cells takes (`ceil(width * height / 32)`), saturating on
    /// garbage sizes.
    pub fn words(&self) -> usize {
        (self.width as usize)
            .saturating_mul(self.height as usize)
            .div_ceil(32)
    }

    /// Words the frame's payload takes: [`words`](Self::words) per layout it holds (`None`
    /// for an unknown layout).
    pub fn payload_words(&self) -> Option<usize> {
        match self.layout {
            LAYOUT_ROWS => Some(self.words()),
            LAYOUT_ROWS_AND_COLUMNS => Some(self.words().saturating_mul(2)),
            _ => None,
        }
    }

    /// Checks the wire version, the layout, the reserved byte and the map version (from 1
    /// up); the sizes are checked with the words, by [`frame_grid`] and [`grid_from_bits`].
    pub fn check(&self) -> Result<(), ServiceError> {
        if self.wire_version != WIRE_VERSION {
            return Err(ServiceError::UnsupportedVersion);
        }
        if self.payload_words().is_none() || self.reserved != 0 || self.map_version == 0 {
            return Err(ServiceError::InvalidRequest);
        }
        Ok(())
    }
}

/// The frame header of a `width x height` map with the given layout.
pub fn frame_header(meta: MapMeta, width: usize, height: usize, layout: u8) -> MapHeader {
    MapHeader {
        wire_version: WIRE_VERSION,
        reserved: 0,
        map_id: meta.map_id,
        map_version: meta.version,
        // Callers pass sides of at most 65535 (`planner_core::grid::MAX_SIDE`).
        width: u32::try_from(width).unwrap_or(u32::MAX),
        height: u32::try_from(height).unwrap_or(u32::MAX),
        resolution: meta.resolution,
        origin: meta.origin,
        layout,
    }
}

/// Packs a grid into a rows-only frame ([`LAYOUT_ROWS`]: header and words) in a vector:
/// what a byte-stream peer sends.
pub fn pack_map(meta: MapMeta, grid: GridRef<'_>, words: &mut Vec<u32>) -> MapHeader {
    let header = frame_header(meta, grid.width(), grid.height(), LAYOUT_ROWS);
    let mut packer = FramePacker::new(grid);
    words.clear();
    words.extend((0..header.words()).map(|_| packer.next_word()));
    header
}

/// Produces a grid's frame words in order, one per call (cell `i = y * width + x` is bit
/// `i % 32` of word `i / 32`), so that a publisher can fill its loaned slice in place
/// (`loan_slice_uninit(n).write_from_fn(|_| packer.next_word())`): no intermediate buffer.
///
/// Bits come from run counts over 32-cell pieces of a row, split in halves only where a
/// piece is mixed, so free and fully blocked stretches (most of a warehouse) cost one test
/// per word.
pub struct FramePacker<'a> {
    grid: GridRef<'a>,
    /// Next row and column to take bits from.
    y: usize,
    x: usize,
    /// Bits taken but not yet returned (low bits first).
    pending: u64,
    pending_bits: u32,
}

impl<'a> FramePacker<'a> {
    /// A packer at the first cell of `grid`.
    pub fn new(grid: GridRef<'a>) -> Self {
        FramePacker {
            grid,
            y: 0,
            x: 0,
            pending: 0,
            pending_bits: 0,
        }
    }

    /// The next word; zero past the last cell.
    pub fn next_word(&mut self) -> u32 {
        let (w, h) = (self.grid.width(), self.grid.height());
        while self.pending_bits < 32 && self.y < h {
            let n = (w - self.x).min(32);
            let piece = row_bits(self.grid, self.y as isize, self.x as isize, n as u32);
            self.pending |= u64::from(piece) << self.pending_bits;
            self.pending_bits += n as u32;
            self.x += n;
            if self.x == w {
                self.x = 0;
                self.y += 1;
            }
        }
        let word = self.pending as u32;
        self.pending >>= 32;
        self.pending_bits = self.pending_bits.saturating_sub(32);
        word
    }
}

/// Cells `x0..x0 + n` of row `y` (`1 <= n <= 32`, inside the map) as bits, cell `x0` lowest.
fn row_bits(grid: GridRef<'_>, y: isize, x0: isize, n: u32) -> u32 {
    let blocked = grid.row_run_count(y, x0, x0 + n as isize - 1);
    if blocked == 0 {
        0
    } else if blocked == n {
        u32::MAX >> (32 - n)
    } else if n <= 4 {
        (0..n).fold(0, |bits, i| {
            bits | (u32::from(grid.is_blocked(x0 + i as isize, y)) << i)
        })
    } else {
        let half = n / 2;
        row_bits(grid, y, x0, half) | row_bits(grid, y, x0 + half as isize, n - half) << half
    }
}

/// The 32 bits from bit `start` of `bits` (bits past the slice read as 0).
fn bits_at(bits: &[u32], start: usize) -> u32 {
    let (i, r) = (start / 32, start % 32);
    let lo = bits.get(i).copied().unwrap_or(0);
    if r == 0 {
        return lo;
    }
    let hi = bits.get(i + 1).copied().unwrap_or(0);
    (lo >> r) | (hi << (32 - r))
}

/// Validates a frame's size and builds its grid straight from the frame's words (a
/// subscriber passes the sample's payload: the only copy is into the grid). `max_cells` is
/// the receiver's limit. Errors: a zero side or fewer words than the cells need is
/// [`ServiceError::InvalidRequest`]; a side beyond 65535 or more than `max_cells` cells is
/// [`ServiceError::MapTooLarge`]. Words past the cells are ignored.
pub fn grid_from_bits(
    width: u32,
    height: u32,
    bits: &[u32],
    max_cells: usize,
) -> Result<GridBuf, ServiceError> {
    let (w, h) = (width as usize, height as usize);
    if w == 0 || h == 0 {
        return Err(ServiceError::InvalidRequest);
    }
    if w > MAX_SIDE || h > MAX_SIDE || w * h > max_cells {
        return Err(ServiceError::MapTooLarge);
    }
    let cells = w * h;
    if bits.len() < cells.div_ceil(32) {
        return Err(ServiceError::InvalidRequest);
    }
    let mut grid = GridBuf::new(w, h).map_err(|_| ServiceError::MapTooLarge)?;
    let words = &bits[..cells.div_ceil(32)];
    // A sparse map (under one blocked cell in 16) is fastest cell by cell; a denser one
    // by whole rows of words (which then transposes every 32 x 32 block for the
    // column-major copy), also the only way that does not grow with the blocked cells.
    let blocked: usize = words.iter().map(|w| w.count_ones() as usize).sum();
    let by_rows = blocked >= cells / 16
        && grid
            .view_mut()
            .fill_rows(|y, row| {
                for (i, word) in row.iter_mut().enumerate() {
                    *word = bits_at(words, y * w + 32 * i);
                }
            })
            .is_ok();
    if !by_rows {
        // Sparse maps, and rows wider than the row fill takes (8192 cells).
        for (word_index, &word) in words.iter().enumerate() {
            let mut rest = word;
            while rest != 0 {
                let bit = rest.trailing_zeros() as usize;
                rest &= rest - 1;
                let i = word_index * 32 + bit;
                if i < cells {
                    grid.set_blocked(i % w, i / w, true)
                        .map_err(|_| ServiceError::Internal)?;
                }
            }
        }
    }
    Ok(grid)
}

/// Validates a [`LAYOUT_ROWS_AND_COLUMNS`] frame and returns the grid view of its words, as
/// they lie (a subscriber passes the sample's payload: nothing is copied or rebuilt).
/// `max_cells` is the receiver's limit. Errors: those of [`MapHeader::check`]; another
/// layout, a zero side or fewer than
/// `2 * n` words is [`ServiceError::InvalidRequest`]; a side beyond 65535 or more than
/// `max_cells` cells is [`ServiceError::MapTooLarge`]. Whether the two layouts agree is not
/// checked here (see [`first_disagreement`]).
pub fn frame_grid<'a>(
    header: &MapHeader,
    words: &'a [u32],
    max_cells: usize,
) -> Result<GridRef<'a>, ServiceError> {
    header.check()?;
    let (w, h) = (header.width as usize, header.height as usize);
    if header.layout != LAYOUT_ROWS_AND_COLUMNS || w == 0 || h == 0 {
        return Err(ServiceError::InvalidRequest);
    }
    if w > MAX_SIDE || h > MAX_SIDE || w * h > max_cells {
        return Err(ServiceError::MapTooLarge);
    }
    let n = (w * h).div_ceil(32);
    let (rows, rest) = words
        .split_at_checked(n)
        .ok_or(ServiceError::InvalidRequest)?;
    let columns = rest.get(..n).ok_or(ServiceError::InvalidRequest)?;
    GridRef::from_words(w, h, rows, columns).map_err(|_| ServiceError::MapTooLarge)
}

/// The first cell (`(x, y)`, by 32 x 32 blocks in row-major block order) where the
/// row-major bits `rows` and the column-major bits `columns` of a `width x height` grid
/// disagree, or `None` when they describe the same grid. Missing words read as free.
/// Costs one 32 x 32 bit transposition per block (about a millisecond a 4096 x 4096 map,
/// see the planner-ipc README); what `planner-server --verify-maps` runs on every frame.
pub fn first_disagreement(
    width: usize,
    height: usize,
    rows: &[u32],
    columns: &[u32],
) -> Option<(usize, usize)> {
    let (w, h) = (width, height);
    let low = |n: usize| if n >= 32 { u32::MAX } else { (1u32 << n) - 1 };
    let aligned = w % 32 == 0 && h % 32 == 0;
    let mut block = [0u32; 32];
    for y0 in (0..h).step_by(32) {
        let nr = (h - y0).min(32);
        for x0 in (0..w).step_by(32) {
            let nc = (w - x0).min(32);
            // Sides that are multiples of 32 (most large maps) read whole words in place.
            let word = |bits: &[u32], start: usize| match aligned {
                true => bits.get(start / 32).copied().unwrap_or(0),
                false => bits_at(bits, start),
            };
            let mut any = 0;
            for (r, slot) in block.iter_mut().enumerate() {
                *slot = if r < nr {
                    word(rows, (y0 + r) * w + x0) & low(nc)
                } else {
                    0
                };
                any |= *slot;
            }
            if any != 0 {
                planner_core::grid::transpose32(&mut block);
            }
            for (c, &want) in block.iter().enumerate().take(nc) {
                let diff = (word(columns, (x0 + c) * h + y0) & low(nr)) ^ want;
                if diff != 0 {
                    return Some((x0 + c, y0 + diff.trailing_zeros() as usize));
                }
            }
        }
    }
    None
}

/// Writes `grid` into `out`, a grid of the same size (both layouts: whole rows of words,
/// then the column-major bits by 32 x 32 transpositions, or cell by cell for rows wider than
/// 8192 cells). What [`PlannerClient::upload_map`](crate::client::PlannerClient::upload_map)
/// does into its loaned frame: planner-core lends a grid's cells only through such reads,
/// so the column layout is rebuilt rather than copied.
pub fn write_grid(grid: GridRef<'_>, out: &mut GridMut<'_>) -> Result<(), GridError> {
    let (w, h) = (grid.width(), grid.height());
    if out.view().width() != w || out.view().height() != h {
        return Err(GridError::SizeMismatch);
    }
    let by_rows = out.fill_rows(|y, words| {
        for (i, word) in words.iter_mut().enumerate() {
            // Bits past the row's end read as blocked; fill_rows ignores them.
            *word = grid.row_bits(y, 32 * i);
        }
    });
    if by_rows.is_ok() {
        return Ok(());
    }
    // Rows wider than fill_rows takes.
    for y in 0..h {
        for x in (0..w).step_by(32) {
            let bits = grid.row_bits(y, x);
            for bit in 0..(w - x).min(32) {
                out.set_blocked(x + bit, y, bits >> bit & 1 != 0)?;
            }
        }
    }
    Ok(())
}

/// The serde form of a map frame (for byte streams): only the used words.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapMsg {
    /// Metadata.
    pub meta: MapMeta,
    /// Width in cells.
    pub width: u32,
    /// Height in cells.
    pub height: u32,
    /// `ceil(width * height / 32)` words, packed as in [`MapHeader`].
    pub bits: Vec<u32>,
}

impl MapMsg {
    /// The serde form of a frame.
    pub fn new(header: &MapHeader, words: &[u32]) -> Self {
        MapMsg {
            meta: header.meta(),
            width: header.width,
            height: header.height,
            bits: words[..header.words().min(words.len())].to_vec(),
        }
    }
}

impl MapMsg {
    /// Validates and rebuilds the grid (see [`grid_from_bits`]).
    pub fn to_grid(&self, max_cells: usize) -> Result<GridBuf, ServiceError> {
        grid_from_bits(self.width, self.height, &self.bits, max_cells)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::DEFAULT_MAX_CELLS;

    #[test]
    fn frame_round_trips_a_grid_and_rejects_garbage() {
        let grid = GridBuf::parse_rows(b"..@.\n@...\n...@\n").unwrap();
        let meta = MapMeta {
            map_id: 7,
            version: 3,
            resolution: 0.05,
            origin: [1.0, 2.0],
        };
        let mut words = Vec::new();
        let mut header = pack_map(meta, grid.view(), &mut words);
        assert_eq!(words, [0b1000_0001_0100]);
        assert_eq!(header.meta(), meta);
        let back = grid_from_bits(header.width, header.height, &words, DEFAULT_MAX_CELLS);
        assert_eq!(back.unwrap(), grid);
        let msg = MapMsg::new(&header, &words);
        let bytes = postcard::to_allocvec(&msg).unwrap();
        let msg2: MapMsg = postcard::from_bytes(&bytes).unwrap();
        assert_eq!(msg2.to_grid(DEFAULT_MAX_CELLS).unwrap(), grid);
        // Server-side limit, garbage sizes, too few words.
        let to_grid = |h: &MapHeader, max| grid_from_bits(h.width, h.height, &words, max);
        assert_eq!(to_grid(&header, 11).unwrap_err(), ServiceError::MapTooLarge);
        assert_eq!(to_grid(&header, 12), Ok(grid.clone()));
        header.width = u32::MAX;
        assert_eq!(
            to_grid(&header, usize::MAX).unwrap_err(),
            ServiceError::MapTooLarge
        );
        // A side beyond u16 even under a huge limit, before the missing words are noticed.
        header.width = 65_536;
        header.height = 1;
        assert_eq!(
            to_grid(&header, usize::MAX).unwrap_err(),
            ServiceError::MapTooLarge
        );
        header.width = 0;
        assert_eq!(
            to_grid(&header, DEFAULT_MAX_CELLS).unwrap_err(),
            ServiceError::InvalidRequest
        );
        header.width = 40;
        header.height = 3;
        assert_eq!(
            to_grid(&header, DEFAULT_MAX_CELLS).unwrap_err(),
            ServiceError::InvalidRequest
        );
    }

    /// A deterministic pseudo-random map: runs of blocked and free cells of random lengths
    /// (like shelves and aisles; free runs up to `free_max` long), so words are free, full
    /// and mixed.
    fn runs_map(width: usize, height: usize, seed: u64, free_max: u64) -> GridBuf {
        let mut grid = GridBuf::new(width, height).unwrap();
        let mut state = seed | 1;
        let mut next = move || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            state
        };
        let (mut blocked, mut left) = (false, 0u64);
        for y in 0..height {
            for x in 0..width {
                if left == 0 {
                    blocked = !blocked;
                    left = 1 + next() % if blocked { 12 } else { free_max };
                }
                left -= 1;
                grid.set_blocked(x, y, blocked).unwrap();
            }
        }
        grid
    }

    /// The in-place packer writes what the definition says, bit for bit, for widths that
    /// are and are not multiples of 32, and the receiver rebuilds the same grid, by rows
    /// (dense maps), cell by cell (sparse maps) and for rows wider than the row fill takes.
    #[test]
    fn packer_matches_the_cell_definition_and_round_trips() {
        for (w, h, seed, free_max) in [
            (1, 1, 1, 70),
            (1, 70, 2, 70),
            (31, 9, 3, 70),
            (32, 5, 4, 70),
            (33, 33, 5, 70),
            (64, 3, 6, 70),
            (100, 37, 7, 70),
            (100, 37, 7, 900),
            (8200, 3, 8, 70),
        ] {
            let grid = runs_map(w, h, seed, free_max);
            let view = grid.view();
            let cells = w * h;
            let mut naive = vec![0u32; cells.div_ceil(32)];
            for i in 0..cells {
                if view.is_blocked((i % w) as isize, (i / w) as isize) {
                    naive[i / 32] |= 1 << (i % 32);
                }
            }
            let meta = MapMeta {
                map_id: 1,
                version: 1,
                resolution: 1.0,
                origin: [0.0; 2],
            };
            let mut words = Vec::new();
            let header = pack_map(meta, view, &mut words);
            assert_eq!(words, naive, "{w} x {h}");
            assert_eq!(header.words(), words.len());
            // Garbage past the last cell is ignored by the receiver.
            words.push(u32::MAX);
            if cells % 32 != 0 {
                *words.last_mut().unwrap() = u32::MAX;
                words[cells / 32] |= u32::MAX << (cells % 32);
            }
            let back = grid_from_bits(w as u32, h as u32, &words, usize::MAX).unwrap();
            assert!(back == grid, "{w} x {h} did not round trip");
        }
    }

    /// Both layouts of `grid` as a frame's words (rows, then columns), by [`write_grid`].
    fn both_layouts(grid: GridRef<'_>) -> Vec<u32> {
        let n = planner_core::grid::words_for(grid.width(), grid.height());
        let mut words = vec![0u32; 2 * n];
        let (rows, columns) = words.split_at_mut(n);
        let mut out = GridMut::from_words(grid.width(), grid.height(), rows, columns).unwrap();
        write_grid(grid, &mut out).unwrap();
        words
    }

    /// `write_grid` writes both layouts of any grid, by rows and (past 8192 cells a row)
    /// cell by cell, over whatever the frame held; the frame's view is the same grid, and
    /// the layouts agree.
    #[test]
    fn frames_of_both_layouts_are_viewed_in_place() {
        for (w, h, seed, free_max) in [
            (1, 1, 1, 70),
            (31, 9, 3, 70),
            (33, 33, 5, 70),
            (100, 37, 7, 900),
            (8200, 3, 8, 70),
        ] {
            let grid = runs_map(w, h, seed, free_max);
            let n = planner_core::grid::words_for(w, h);
            let mut words = both_layouts(grid.view());
            // Writing over garbage gives the same cells in both layouts.
            let mut dirty = vec![u32::MAX; 2 * n];
            let (rows, columns) = dirty.split_at_mut(n);
            let mut out = GridMut::from_words(w, h, rows, columns).unwrap();
            write_grid(grid.view(), &mut out).unwrap();
            let (rows, columns) = dirty.split_at(n);
            assert_eq!(first_disagreement(w, h, rows, columns), None, "{w} x {h}");
            let dirty_view = GridRef::from_words(w, h, rows, columns).unwrap();
            assert!(
                (0..w * h).all(|i| {
                    let (x, y) = ((i % w) as isize, (i / w) as isize);
                    dirty_view.is_blocked(x, y) == grid.view().is_blocked(x, y)
                }),
                "{w} x {h}"
            );
            let (rows, columns) = words.split_at(n);
            assert_eq!(first_disagreement(w, h, rows, columns), None, "{w} x {h}");
            let header = MapHeader {
                width: w as u32,
                height: h as u32,
                layout: LAYOUT_ROWS_AND_COLUMNS,
                ..Default::default()
            };
            assert_eq!(header.payload_words(), Some(2 * n));
            let view = frame_grid(&header, &words, DEFAULT_MAX_CELLS).unwrap();
            assert!(GridBuf::from_view(view) == grid, "{w} x {h}");
            for y in 0..h as isize {
                for x in 0..w as isize {
                    assert_eq!(view.is_blocked(x, y), grid.view().is_blocked(x, y));
                }
            }
            for y in 0..h {
                let x = (y * 7) % w;
                assert_eq!(
                    view.column_run_count(x as isize, 0, h as isize - 1),
                    grid.view().column_run_count(x as isize, 0, h as isize - 1)
                );
            }
            // Words past both layouts are ignored.
            words.push(u32::MAX);
            assert!(frame_grid(&header, &words, DEFAULT_MAX_CELLS).is_ok());
        }
        assert_eq!(
            write_grid(
                GridBuf::new(3, 3).unwrap().view(),
                &mut GridBuf::new(3, 4).unwrap().view_mut()
            ),
            Err(GridError::SizeMismatch)
        );
    }

    #[test]
    fn frame_grid_rejects_garbage() {
        let grid = runs_map(40, 30, 9, 20);
        let words = both_layouts(grid.view());
        let good = MapHeader {
            map_id: 1,
            map_version: 1,
            width: 40,
            height: 30,
            layout: LAYOUT_ROWS_AND_COLUMNS,
            ..Default::default()
        };
        let check = |f: &dyn Fn(&mut MapHeader), words: &[u32], max: usize| {
            let mut h = good;
            f(&mut h);
            frame_grid(&h, words, max).map(|v| (v.width(), v.height()))
        };
        assert_eq!(check(&|_| {}, &words, 1200), Ok((40, 30)));
        assert_eq!(check(&|_| {}, &words, 1199), Err(ServiceError::MapTooLarge));
        // The columns cut short, or only the rows sent.
        assert_eq!(
            check(&|_| {}, &words[..75], 1200),
            Err(ServiceError::InvalidRequest)
        );
        assert_eq!(
            check(&|_| {}, &words[..38], 1200),
            Err(ServiceError::InvalidRequest)
        );
        for layout in [LAYOUT_ROWS, 2, u8::MAX] {
            assert_eq!(
                check(&|h| h.layout = layout, &words, 1200),
                Err(ServiceError::InvalidRequest),
                "layout {layout}"
            );
        }
        assert_eq!(good.payload_words(), Some(76));
        assert_eq!(MapHeader { layout: 7, ..good }.payload_words(), None);
        assert_eq!(
            check(&|h| h.wire_version = 0, &words, 1200),
            Err(ServiceError::UnsupportedVersion)
        );
        assert_eq!(
            check(&|h| h.reserved = 1, &words, 1200),
            Err(ServiceError::InvalidRequest)
        );
        assert_eq!(
            check(&|h| h.map_version = 0, &words, 1200),
            Err(ServiceError::InvalidRequest)
        );
        assert_eq!(
            check(&|h| h.width = 0, &words, usize::MAX),
            Err(ServiceError::InvalidRequest)
        );
        assert_eq!(
            check(&|h| h.width = 65_536, &words, usize::MAX),
            Err(ServiceError::MapTooLarge)
        );
        assert_eq!(
            check(
                &|h| (h.width, h.height) = (u32::MAX, u32::MAX),
                &words,
                usize::MAX
            ),
            Err(ServiceError::MapTooLarge)
        );
    }

    /// A flipped bit in either layout is found at its cell, in every position of a block
    /// and on maps whose sides are not multiples of 32.
    #[test]
    fn disagreeing_layouts_are_found_at_the_cell() {
        for (w, h) in [(40usize, 30usize), (64, 64), (5, 70)] {
            let grid = runs_map(w, h, 11, 30);
            let n = planner_core::grid::words_for(w, h);
            let words = both_layouts(grid.view());
            for (x, y) in [
                (0, 0),
                (w - 1, h - 1),
                (w / 2, h / 3),
                (w - 1, 0),
                (0, h - 1),
            ] {
                let mut rows_flipped = words.clone();
                let i = y * w + x;
                rows_flipped[i / 32] ^= 1 << (i % 32);
                let (rows, columns) = rows_flipped.split_at(n);
                assert_eq!(first_disagreement(w, h, rows, columns), Some((x, y)));
                let mut columns_flipped = words.clone();
                let j = x * h + y;
                columns_flipped[n + j / 32] ^= 1 << (j % 32);
                let (rows, columns) = columns_flipped.split_at(n);
                assert_eq!(first_disagreement(w, h, rows, columns), Some((x, y)));
            }
            // All-zero columns for a map with obstacles: found.
            let (rows, _) = words.split_at(n);
            assert!(first_disagreement(w, h, rows, &vec![0; n]).is_some());
        }
    }
}

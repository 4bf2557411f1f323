//! Wire types: the fixed-layout (`#[repr(C)]`, [`ZeroCopySend`]) payloads that travel through
//! iceoryx2 shared memory (a fixed header plus a slice of fixed elements where the size
//! varies: map words, path waypoints), their conversion to and from planner-core types with validation,
//! and serde mirrors for byte streams (postcard over a socket, logs).
//!
//! Every field a peer writes is untrusted: conversions check ranges and finiteness and turn
//! garbage into a typed [`ServiceError`] or [`PlanError`], never a panic.
//!
//! Status codes of a [`PlanResponseHeader`]: `0` = ok; `1..=8` = [`PlanError::ALL`] in order
//! (index + 1); `100..` = [`ServiceError`] (see [`ServiceError::code`]).

use iceoryx2::prelude::ZeroCopySend;
use planner_core::PlanError;
use planner_core::error::GridError;
use planner_core::geometry::{Cell, Point};
use planner_core::grid::{GridBuf, GridMut, GridRef, MAX_SIDE};
use planner_core::optim::any::AlgorithmKind;
use planner_core::planner::PlannerKind;
use serde::{Deserialize, Serialize};
use std::fmt;

/// The largest map a server takes by default: 4096 x 4096 cells (`planner-server
/// --max-cells` changes it). A frame itself may carry any map whose sides fit in `u16`
/// ([`MAX_SIDE`]); the publisher's shared memory grows to the largest map sent.
pub const DEFAULT_MAX_CELLS: usize = 4096 * 4096;
/// Most waypoints a [`PlanResponseHeader`] carries (an A* path lists every cell: a route
/// across a 4096 x 4096 warehouse takes 4096-8192); a longer path is
/// [`PlanError::CapacityExceeded`].
pub const MAX_WAYPOINTS: usize = 16_384;
/// Largest robot radius a request may ask for, in cells (larger is
/// [`PlanError::InvalidParameters`]; inflation costs grow with the radius).
pub const MAX_RADIUS: f32 = 1024.0;

/// Why the service (not the planner) refused or failed a request.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ServiceError {
    /// The server has no map with this id.
    UnknownMap,
    /// The server holds a newer version of this map than the request names.
    StaleMapVersion,
    /// The map exceeds the server's configured limit (`planner-server --max-cells`) or has a
    /// side beyond 65535 cells. The response header says the limit (see
    /// [`PlanResponseHeader::map_limit`]).
    MapTooLarge,
    /// The algorithm code names no planner this server serves.
    UnknownAlgorithm,
    /// A request field is out of range (garbage, bad coordinates type, bad kind).
    InvalidRequest,
    /// The client gave up on the request before the server answered it.
    Cancelled,
    /// The server is shutting down and did not plan this request.
    ServerShuttingDown,
    /// The request's deadline passed before planning started.
    DeadlineExceeded,
    /// The server hit an internal error (see its log).
    Internal,
}

impl ServiceError {
    /// Every variant, in code order.
    pub const ALL: [ServiceError; 9] = [
        ServiceError::UnknownMap,
        ServiceError::StaleMapVersion,
        ServiceError::MapTooLarge,
        ServiceError::UnknownAlgorithm,
        ServiceError::InvalidRequest,
        ServiceError::Cancelled,
        ServiceError::ServerShuttingDown,
        ServiceError::DeadlineExceeded,
        ServiceError::Internal,
    ];

    /// The wire status code (`101..`).
    pub const fn code(self) -> u16 {
        101 + self as u16
    }

    /// The variant's name, as printed in JSON lines.
    pub const fn name(self) -> &'static str {
        match self {
            ServiceError::UnknownMap => "UnknownMap",
            ServiceError::StaleMapVersion => "StaleMapVersion",
            ServiceError::MapTooLarge => "MapTooLarge",
            ServiceError::UnknownAlgorithm => "UnknownAlgorithm",
            ServiceError::InvalidRequest => "InvalidRequest",
            ServiceError::Cancelled => "Cancelled",
            ServiceError::ServerShuttingDown => "ServerShuttingDown",
            ServiceError::DeadlineExceeded => "DeadlineExceeded",
            ServiceError::Internal => "Internal",
        }
    }
}

impl fmt::Display for ServiceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::error::Error for ServiceError {}

/// What a request may fail with on the server: a planner error or a service error.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Failure {
    /// The planner's own error (Nav2-like codes).
    Plan(PlanError),
    /// The service's error.
    Service(ServiceError),
}

impl Failure {
    /// The name printed in JSON lines.
    pub const fn name(self) -> &'static str {
        match self {
            Failure::Plan(e) => e.name(),
            Failure::Service(e) => e.name(),
        }
    }
}

impl From<PlanError> for Failure {
    fn from(e: PlanError) -> Self {
        Failure::Plan(e)
    }
}

impl From<ServiceError> for Failure {
    fn from(e: ServiceError) -> Self {
        Failure::Service(e)
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Plan(e) => write!(f, "{}: {e}", e.name()),
            Failure::Service(e) => f.write_str(e.name()),
        }
    }
}

impl std::error::Error for Failure {}

/// Status code `0`: success.
pub const STATUS_OK: u16 = 0;

/// Encodes a result as a wire status code.
pub fn status_code(result: Result<(), Failure>) -> u16 {
    match result {
        Ok(()) => STATUS_OK,
        Err(Failure::Plan(e)) => {
            // ALL lists every variant, so the position always exists.
            PlanError::ALL.iter().position(|x| *x == e).unwrap_or(0) as u16 + 1
        }
        Err(Failure::Service(e)) => e.code(),
    }
}

/// Decodes a wire status code; `None` for a code this build does not know.
pub fn decode_status(code: u16) -> Option<Result<(), Failure>> {
    match code {
        STATUS_OK => Some(Ok(())),
        1..=100 => PlanError::ALL
            .get(code as usize - 1)
            .map(|e| Err(Failure::Plan(*e))),
        _ => ServiceError::ALL
            .iter()
            .find(|e| e.code() == code)
            .map(|e| Err(Failure::Service(*e))),
    }
}

/// The planners the service knows: every planner of planner-core. Wire code =
/// discriminant; `0` is never a planner. Adding a planner is one variant here, one line in
/// [`Algorithm::ALL`] and one arm in [`Algorithm::kind`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
pub enum Algorithm {
    /// A*: shortest 8-connected path.
    AStar = 1,
    /// Theta*: any-angle path.
    ThetaStar = 2,
    /// Seed 000's ant colony.
    Aco = 3,
    /// TCLHHO (seed 000).
    Tclhho = 4,
    /// IGWO (seed 003).
    Igwo = 5,
    /// HHO.
    Hho = 6,
    /// GWO.
    Gwo = 7,
    /// TGWO.
    Tgwo = 8,
    /// PSO.
    Pso = 9,
    /// GA.
    Ga = 10,
    /// Sparrow search.
    Ssa = 11,
    /// SSA-GWO (seed 001).
    SsaGwo = 12,
    /// The exact any-angle shortest path.
    AnyAngle = 13,
}

impl Algorithm {
    /// Every served planner.
    pub const ALL: [Algorithm; 13] = [
        Algorithm::AStar,
        Algorithm::ThetaStar,
        Algorithm::Aco,
        Algorithm::Tclhho,
        Algorithm::Igwo,
        Algorithm::Hho,
        Algorithm::Gwo,
        Algorithm::Tgwo,
        Algorithm::Pso,
        Algorithm::Ga,
        Algorithm::Ssa,
        Algorithm::SsaGwo,
        Algorithm::AnyAngle,
    ];

    /// The wire code.
    pub const fn code(self) -> u8 {
        self as u8
    }

    /// The planner of a wire code, or [`ServiceError::UnknownAlgorithm`].
    pub fn from_code(code: u8) -> Result<Self, ServiceError> {
        Self::ALL
            .into_iter()
            .find(|a| a.code() == code)
            .ok_or(ServiceError::UnknownAlgorithm)
    }

    /// planner-core's planner.
    pub const fn kind(self) -> PlannerKind {
        match self {
            Algorithm::AStar => PlannerKind::AStar,
            Algorithm::ThetaStar => PlannerKind::Theta,
            Algorithm::Aco => PlannerKind::Aco,
            Algorithm::Tclhho => PlannerKind::Swarm(AlgorithmKind::Tclhho),
            Algorithm::Igwo => PlannerKind::Swarm(AlgorithmKind::Igwo),
            Algorithm::Hho => PlannerKind::Swarm(AlgorithmKind::Hho),
            Algorithm::Gwo => PlannerKind::Swarm(AlgorithmKind::Gwo),
            Algorithm::Tgwo => PlannerKind::Swarm(AlgorithmKind::Tgwo),
            Algorithm::Pso => PlannerKind::Swarm(AlgorithmKind::Pso),
            Algorithm::Ga => PlannerKind::Swarm(AlgorithmKind::Ga),
            Algorithm::Ssa => PlannerKind::Swarm(AlgorithmKind::Ssa),
            Algorithm::SsaGwo => PlannerKind::Swarm(AlgorithmKind::SsaGwo),
            Algorithm::AnyAngle => PlannerKind::AnyAngle,
        }
    }

    /// The name used on command lines and in JSON lines (same as `host-sim plan --algo`).
    pub fn name(self) -> &'static str {
        self.kind().name()
    }

    /// The planner of a name, or [`ServiceError::UnknownAlgorithm`].
    pub fn from_name(name: &str) -> Result<Self, ServiceError> {
        Self::ALL
            .into_iter()
            .find(|a| a.name() == name)
            .ok_or(ServiceError::UnknownAlgorithm)
    }
}

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
/// - [`LAYOUT_ROWS`] (frames of earlier builds, byte-stream peers): `n` words, the row-major
///   bits only; the receiver builds its own grid from them ([`grid_from_bits`]).
///
/// Words past the layouts are ignored. Sizes are checked by the receiver ([`frame_grid`],
/// [`grid_from_bits`]): a zero side, an unknown layout or fewer words than the layout
/// needs is [`ServiceError::InvalidRequest`]; a side beyond 65535 or more cells than the
/// server's limit is [`ServiceError::MapTooLarge`].
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend, Serialize, Deserialize)]
#[repr(C)]
pub struct MapHeader {
    /// Which map (several maps may be served at once).
    pub map_id: u32,
    /// Monotonic version of this map id; requests name the version they planned against.
    pub version: u32,
    /// Width in cells.
    pub width: u32,
    /// Height in cells.
    pub height: u32,
    /// Metres per cell (informational; planning is in cell units).
    pub resolution: f32,
    /// World position of cell `(0, 0)`'s centre, metres (informational).
    pub origin: [f32; 2],
    /// Which layouts the words hold: [`LAYOUT_ROWS`] (0; this field was reserved, zero, in
    /// earlier builds) or [`LAYOUT_ROWS_AND_COLUMNS`] (1); anything else is
    /// [`ServiceError::InvalidRequest`].
    pub layout: u32,
}

/// [`MapHeader::layout`]: the row-major bits only (`n` words).
pub const LAYOUT_ROWS: u32 = 0;
/// [`MapHeader::layout`]: the row-major bits, then the column-major bits (`2 * n` words).
pub const LAYOUT_ROWS_AND_COLUMNS: u32 = 1;

/// Metadata of a map, without its cells.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct MapMeta {
    /// Map id.
    pub map_id: u32,
    /// Version.
    pub version: u32,
    /// Metres per cell.
    pub resolution: f32,
    /// World position of cell `(0, 0)`, metres.
    pub origin: [f32; 2],
}

impl MapHeader {
    /// The header's metadata.
    pub fn meta(&self) -> MapMeta {
        MapMeta {
            map_id: self.map_id,
            version: self.version,
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
}

/// The frame header of a `width x height` map with the given layout.
pub fn frame_header(meta: MapMeta, width: usize, height: usize, layout: u32) -> MapHeader {
    MapHeader {
        map_id: meta.map_id,
        version: meta.version,
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
/// `max_cells` is the receiver's limit. Errors: another layout, a zero side or fewer than
/// `2 * n` words is [`ServiceError::InvalidRequest`]; a side beyond 65535 or more than
/// `max_cells` cells is [`ServiceError::MapTooLarge`]. Whether the two layouts agree is not
/// checked here (see [`first_disagreement`]).
pub fn frame_grid<'a>(
    header: &MapHeader,
    words: &'a [u32],
    max_cells: usize,
) -> Result<GridRef<'a>, ServiceError> {
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

/// What a [`PlanRequest`] asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[repr(u8)]
pub enum RequestKind {
    /// Plan a path.
    Plan = 0,
    /// Only check that the server holds this map id and version (answers ok or the map
    /// error); used to confirm an upload. An ok answer has no path; its `turns` and
    /// `evaluations` are the map's width and height, its `length` the microseconds the
    /// server took to build its grid from the frame (0 from older servers).
    MapStatus = 1,
}

/// Planner parameters; `0` means the planner's default. All must be finite and not
/// negative (else [`PlanError::InvalidParameters`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend, Serialize, Deserialize)]
#[repr(C)]
pub struct PlanParams {
    /// Robot radius in cells: the map is inflated so that paths keep this clearance.
    pub radius: f32,
    /// Population size (swarm planners).
    pub population: f32,
    /// Iterations (swarm planners).
    pub iterations: f32,
    /// Planner-specific extras: `extra[0]` = stagnation window in iterations (0: run to
    /// the horizon); `extra[1]` = the swarm planners' guide route (0: the exact shortest
    /// any-angle route, 1: A*; see `planner_core::planner::GuideKind`); the rest
    /// reserved, zero.
    pub extra: [f32; 5],
}

impl PlanParams {
    /// The guide route that `extra[1]` names, if it names one.
    pub fn guide(&self) -> Option<planner_core::planner::GuideKind> {
        Self::guide_of(self.extra[1])
    }

    /// The `extra[1]` code of a guide route (the inverse of [`guide`](Self::guide)).
    pub fn guide_code(guide: planner_core::planner::GuideKind) -> f32 {
        use planner_core::planner::GuideKind;
        match guide {
            GuideKind::AnyAngle => 0.0,
            GuideKind::AStar => 1.0,
        }
    }

    fn guide_of(code: f32) -> Option<planner_core::planner::GuideKind> {
        use planner_core::planner::GuideKind;
        match code {
            0.0 => Some(GuideKind::AnyAngle),
            1.0 => Some(GuideKind::AStar),
            _ => None,
        }
    }

    /// Checks every field: finite, not negative; counts integral and below 2^24.
    pub fn validate(&self) -> Result<(), PlanError> {
        let all = [self.radius, self.population, self.iterations];
        let ok = all
            .iter()
            .chain(self.extra.iter())
            .all(|v| v.is_finite() && *v >= 0.0)
            && [self.population, self.iterations, self.extra[0]]
                .iter()
                .all(|v| v.fract() == 0.0 && *v < 16_777_216.0)
            && Self::guide_of(self.extra[1]).is_some()
            && self.radius <= MAX_RADIUS;
        if ok {
            Ok(())
        } else {
            Err(PlanError::InvalidParameters)
        }
    }
}

/// A plan request (fixed layout, travels zero-copy).
#[derive(Debug, Clone, Copy, ZeroCopySend, Serialize, Deserialize)]
#[repr(C)]
pub struct PlanRequest {
    /// Chosen by the client; echoed in the response to match them up.
    pub request_id: u64,
    /// Seed of the random number generator (stochastic planners).
    pub seed: u64,
    /// Time budget in microseconds from the server's receipt of the request; `0` = none.
    /// A request still queued past it is answered [`ServiceError::DeadlineExceeded`].
    pub deadline_us: u64,
    /// Token of the client's wake-up event service (`0`: the client polls, do not notify).
    pub wake_token: u64,
    /// Wall-clock time (ns since the Unix epoch) until which the client polls for the
    /// answer before it sleeps on its wake event: an answer sent clearly before needs no
    /// wake-up syscall. `0`: always notify.
    pub polls_until_ns: u64,
    /// Map id.
    pub map_id: u32,
    /// Map version the client planned against.
    pub map_version: u32,
    /// Start cell `(x, y)`; anything outside the map is `StartOutsideMap`.
    pub start: [i32; 2],
    /// Goal cell `(x, y)`.
    pub goal: [i32; 2],
    /// [`Algorithm`] code.
    pub algorithm: u8,
    /// [`RequestKind`] code.
    pub kind: u8,
    /// Reserved, zero.
    pub reserved: [u8; 6],
    /// Planner parameters.
    pub params: PlanParams,
}

impl PlanRequest {
    /// A plan request with default parameters and no deadline.
    pub fn new(map: (u32, u32), start: [i32; 2], goal: [i32; 2], algorithm: Algorithm) -> Self {
        PlanRequest {
            request_id: 0,
            seed: 0,
            deadline_us: 0,
            wake_token: 0,
            polls_until_ns: 0,
            map_id: map.0,
            map_version: map.1,
            start,
            goal,
            algorithm: algorithm.code(),
            kind: RequestKind::Plan as u8,
            reserved: [0; 6],
            params: PlanParams::default(),
        }
    }

    /// The request kind, or [`ServiceError::InvalidRequest`].
    pub fn kind(&self) -> Result<RequestKind, ServiceError> {
        match self.kind {
            0 => Ok(RequestKind::Plan),
            1 => Ok(RequestKind::MapStatus),
            _ => Err(ServiceError::InvalidRequest),
        }
    }
}

/// Converts a requested `(x, y)` into a cell; out of `u16` range is outside every map.
pub fn to_cell(xy: [i32; 2], outside: PlanError) -> Result<Cell, PlanError> {
    match (u16::try_from(xy[0]), u16::try_from(xy[1])) {
        (Ok(x), Ok(y)) => Ok(Cell::new(x, y)),
        _ => Err(outside),
    }
}

/// One waypoint of a response path, in cell units.
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend, Serialize, Deserialize)]
#[repr(C)]
pub struct Waypoint {
    /// Column coordinate.
    pub x: f32,
    /// Row coordinate.
    pub y: f32,
}

/// The header of a plan response (iceoryx2 user header); the path follows as a slice of
/// [`Waypoint`]s (at most [`MAX_WAYPOINTS`], only the used ones travel).
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend, Serialize, Deserialize)]
#[repr(C)]
pub struct PlanResponseHeader {
    /// The request's id.
    pub request_id: u64,
    /// Status: `0` ok, else a planner or service error code (see the module docs).
    pub status: u16,
    /// The request's algorithm code.
    pub algorithm: u8,
    /// Reserved, zero.
    pub reserved: u8,
    /// Map id planned on.
    pub map_id: u32,
    /// Map version planned on.
    pub map_version: u32,
    /// Waypoints in the slice.
    pub waypoints: u32,
    /// Path length (cell units).
    pub length: f32,
    /// Direction changes.
    pub turns: u32,
    /// Cells expanded (reference searches) or objective evaluations (swarm planners). In a
    /// [`ServiceError::MapTooLarge`] answer: the server's limit in cells (saturating; `0`
    /// from servers that do not report it), see [`map_limit`](Self::map_limit).
    pub evaluations: u32,
    /// Server-side planning time, microseconds.
    pub time_us: f32,
}

impl PlanResponseHeader {
    /// The header for `result` answering `request`.
    pub fn new(request: &PlanRequest, result: &PlanResult) -> Self {
        let mut h = PlanResponseHeader {
            request_id: result.request_id,
            algorithm: request.algorithm,
            map_id: request.map_id,
            map_version: request.map_version,
            time_us: result.time_us,
            ..Default::default()
        };
        match &result.outcome {
            Ok(ok) => {
                h.status = STATUS_OK;
                h.waypoints = ok.path.len().min(MAX_WAYPOINTS) as u32;
                h.length = ok.length;
                h.turns = ok.turns;
                h.evaluations = ok.evaluations;
            }
            Err(f) => h.status = status_code(Err(*f)),
        }
        h
    }

    /// Records the server's map limit (cells) in a [`ServiceError::MapTooLarge`] answer;
    /// other answers are left as they are.
    pub fn set_map_limit(&mut self, max_cells: usize) {
        if self.status == ServiceError::MapTooLarge.code() {
            self.evaluations = u32::try_from(max_cells).unwrap_or(u32::MAX);
        }
    }

    /// The server's map limit (cells) that a [`ServiceError::MapTooLarge`] answer carries;
    /// `None` for other answers and from servers that do not report it.
    pub fn map_limit(&self) -> Option<u64> {
        (self.status == ServiceError::MapTooLarge.code() && self.evaluations > 0)
            .then_some(u64::from(self.evaluations))
    }

    /// Decodes a received header and path into an owned result, validating the status,
    /// the count and the numbers.
    pub fn decode(&self, path: &[Waypoint]) -> Result<PlanResult, DecodeError> {
        match decode_status(self.status) {
            None => Err(DecodeError::UnknownStatus(self.status)),
            Some(Err(f)) => Ok(PlanResult {
                request_id: self.request_id,
                outcome: Err(f),
                time_us: self.time_us,
            }),
            Some(Ok(())) => {
                if self.waypoints as usize != path.len() || path.len() > MAX_WAYPOINTS {
                    return Err(DecodeError::BadPath);
                }
                let path: Vec<Point> = path.iter().map(|p| Point::new(p.x, p.y)).collect();
                if !path.iter().all(|p| p.is_finite()) || !self.length.is_finite() {
                    return Err(DecodeError::BadPath);
                }
                Ok(PlanResult {
                    request_id: self.request_id,
                    outcome: Ok(PlanOk {
                        path,
                        length: self.length,
                        turns: self.turns,
                        evaluations: self.evaluations,
                    }),
                    time_us: self.time_us,
                })
            }
        }
    }
}

/// A response that does not decode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DecodeError {
    /// A status code this build does not know.
    UnknownStatus(u16),
    /// An ok response whose path is too long or not finite.
    BadPath,
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DecodeError::UnknownStatus(c) => write!(f, "unknown status code {c}"),
            DecodeError::BadPath => f.write_str("malformed path in an ok response"),
        }
    }
}

impl std::error::Error for DecodeError {}

/// A found path and its metrics (owned).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanOk {
    /// Waypoints in cell units, start first.
    pub path: Vec<Point>,
    /// Length (cell units).
    pub length: f32,
    /// Direction changes.
    pub turns: u32,
    /// Cells expanded or objective evaluations.
    pub evaluations: u32,
}

/// A decoded response (owned; also the serde/postcard form of a response).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanResult {
    /// The request's id.
    pub request_id: u64,
    /// The path or why there is none.
    pub outcome: Result<PlanOk, Failure>,
    /// Server-side planning time, microseconds.
    pub time_us: f32,
}

impl PlanResult {
    /// The path as wire waypoints (empty for an error).
    pub fn waypoints(&self) -> impl Iterator<Item = Waypoint> + '_ {
        self.outcome
            .as_ref()
            .map(|ok| &ok.path[..ok.path.len().min(MAX_WAYPOINTS)])
            .unwrap_or(&[])
            .iter()
            .map(|p| Waypoint { x: p.x, y: p.y })
    }
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

/// Wall-clock nanoseconds since the Unix epoch (the clock both processes share).
pub fn unix_ns() -> u64 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as u64)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_codes_round_trip() {
        assert_eq!(decode_status(status_code(Ok(()))), Some(Ok(())));
        for e in PlanError::ALL {
            let f = Failure::Plan(e);
            assert_eq!(decode_status(status_code(Err(f))), Some(Err(f)));
        }
        for e in ServiceError::ALL {
            let f = Failure::Service(e);
            assert_eq!(decode_status(status_code(Err(f))), Some(Err(f)));
        }
        for garbage in [9u16, 100, 200, u16::MAX] {
            assert_eq!(decode_status(garbage), None, "{garbage}");
        }
    }

    #[test]
    fn algorithm_codes_and_names() {
        for a in Algorithm::ALL {
            assert_eq!(Algorithm::from_code(a.code()), Ok(a));
            assert_eq!(Algorithm::from_name(a.name()), Ok(a));
        }
        for bad in [0u8, 14, 99, 255] {
            assert_eq!(
                Algorithm::from_code(bad),
                Err(ServiceError::UnknownAlgorithm)
            );
        }
        // Every planner of planner-core is served, under the same names as `host-sim plan`.
        assert_eq!(Algorithm::ALL.len(), PlannerKind::ALL.len());
        for kind in PlannerKind::ALL {
            assert_eq!(
                Algorithm::from_name(kind.name()).map(Algorithm::kind),
                Ok(kind)
            );
        }
        assert_eq!(
            Algorithm::from_name("dijkstra"),
            Err(ServiceError::UnknownAlgorithm)
        );
    }

    #[test]
    fn params_reject_nan_and_negative() {
        assert!(PlanParams::default().validate().is_ok());
        let bad = [
            PlanParams {
                radius: f32::NAN,
                ..Default::default()
            },
            PlanParams {
                radius: -1.0,
                ..Default::default()
            },
            PlanParams {
                iterations: f32::INFINITY,
                ..Default::default()
            },
            PlanParams {
                population: 2.5,
                ..Default::default()
            },
            PlanParams {
                extra: [0.0, 0.0, f32::NAN, 0.0, 0.0],
                ..Default::default()
            },
            // No such guide route.
            PlanParams {
                extra: [0.0, 3.0, 0.0, 0.0, 0.0],
                ..Default::default()
            },
            PlanParams {
                extra: [0.0, 0.5, 0.0, 0.0, 0.0],
                ..Default::default()
            },
        ];
        for p in bad {
            assert_eq!(p.validate(), Err(PlanError::InvalidParameters), "{p:?}");
        }
        use planner_core::planner::GuideKind;
        let guide = |code: f32| {
            PlanParams {
                extra: [0.0, code, 0.0, 0.0, 0.0],
                ..Default::default()
            }
            .guide()
        };
        assert_eq!(guide(0.0), Some(GuideKind::AnyAngle));
        assert_eq!(guide(1.0), Some(GuideKind::AStar));
        assert_eq!(guide(2.0), None);
        for g in [GuideKind::AnyAngle, GuideKind::AStar] {
            assert_eq!(guide(PlanParams::guide_code(g)), Some(g));
        }
    }

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
            version: 1,
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
        for layout in [LAYOUT_ROWS, 2, u32::MAX] {
            assert_eq!(
                check(&|h| h.layout = layout, &words, 1200),
                Err(ServiceError::InvalidRequest),
                "layout {layout}"
            );
        }
        assert_eq!(good.payload_words(), Some(76));
        assert_eq!(MapHeader { layout: 7, ..good }.payload_words(), None);
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

    #[test]
    fn map_too_large_answers_carry_the_limit() {
        let req = PlanRequest::new((1, 1), [0, 0], [1, 1], Algorithm::AStar);
        let refused = PlanResult {
            request_id: 1,
            outcome: Err(Failure::Service(ServiceError::MapTooLarge)),
            time_us: 0.0,
        };
        let mut header = PlanResponseHeader::new(&req, &refused);
        assert_eq!(header.map_limit(), None, "an older server says nothing");
        header.set_map_limit(DEFAULT_MAX_CELLS);
        assert_eq!(header.map_limit(), Some(4096 * 4096));
        assert_eq!(header.decode(&[]).unwrap(), refused);
        header.set_map_limit(usize::MAX);
        assert_eq!(header.map_limit(), Some(u64::from(u32::MAX)));
        // Other answers are not touched.
        let other = PlanResult {
            request_id: 1,
            outcome: Err(Failure::Service(ServiceError::UnknownMap)),
            time_us: 0.0,
        };
        let mut header = PlanResponseHeader::new(&req, &other);
        header.set_map_limit(100);
        assert_eq!((header.evaluations, header.map_limit()), (0, None));
    }

    #[test]
    fn responses_decode_and_reject_garbage() {
        let req = PlanRequest::new((1, 1), [0, 0], [1, 1], Algorithm::AStar);
        let ok = PlanResult {
            request_id: 5,
            outcome: Ok(PlanOk {
                path: vec![Point::new(0.0, 0.0), Point::new(1.0, 1.0)],
                length: core::f32::consts::SQRT_2,
                turns: 0,
                evaluations: 2,
            }),
            time_us: 1.5,
        };
        let mut header = PlanResponseHeader::new(&req, &ok);
        let mut path: Vec<Waypoint> = ok.waypoints().collect();
        assert_eq!(header.decode(&path).unwrap(), ok);
        let bytes = postcard::to_allocvec(&ok).unwrap();
        assert_eq!(postcard::from_bytes::<PlanResult>(&bytes).unwrap(), ok);
        header.waypoints = 3;
        assert_eq!(header.decode(&path).unwrap_err(), DecodeError::BadPath);
        header.waypoints = 2;
        path[1].x = f32::NAN;
        assert_eq!(header.decode(&path).unwrap_err(), DecodeError::BadPath);
        header.status = 4242;
        assert_eq!(
            header.decode(&path).unwrap_err(),
            DecodeError::UnknownStatus(4242)
        );
        let err = PlanResult {
            request_id: 6,
            outcome: Err(Failure::Plan(PlanError::NoValidPath)),
            time_us: 0.5,
        };
        let header = PlanResponseHeader::new(&req, &err);
        assert_eq!(err.waypoints().count(), 0);
        assert_eq!(header.decode(&[]).unwrap(), err);
    }

    #[test]
    fn out_of_range_coordinates_are_outside() {
        assert_eq!(
            to_cell([-1, 0], PlanError::StartOutsideMap),
            Err(PlanError::StartOutsideMap)
        );
        assert_eq!(
            to_cell([70000, 0], PlanError::GoalOutsideMap),
            Err(PlanError::GoalOutsideMap)
        );
        assert_eq!(
            to_cell([3, 4], PlanError::GoalOutsideMap),
            Ok(Cell::new(3, 4))
        );
    }
}

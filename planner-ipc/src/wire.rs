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
use planner_core::geometry::{Cell, Point};
use planner_core::grid::{Grid, GridRef, words_for};
use planner_core::optim::any::AlgorithmKind;
use planner_core::planner::PlannerKind;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Side of the largest square map a map frame carries.
pub const MAP_CAPACITY_SIDE: usize = 512;
/// Cells a map frame can carry (`512 x 512`); larger maps are [`ServiceError::MapTooLarge`].
pub const MAP_CAPACITY_CELLS: usize = MAP_CAPACITY_SIDE * MAP_CAPACITY_SIDE;
/// 32-bit words of a frame's bit-packed grid.
pub const MAP_WORDS: usize = words_for(MAP_CAPACITY_CELLS, 1);
/// Most waypoints a [`PlanResponseHeader`] carries; a longer path is [`PlanError::CapacityExceeded`].
pub const MAX_WAYPOINTS: usize = 2048;

/// The grid type that holds any map a frame can carry.
pub type WireGrid = Grid<MAP_WORDS>;

/// Why the service (not the planner) refused or failed a request.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ServiceError {
    /// The server has no map with this id.
    UnknownMap,
    /// The server holds a newer version of this map than the request names.
    StaleMapVersion,
    /// The map exceeds the frame capacity or the server's configured capacity.
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
}

impl Algorithm {
    /// Every served planner.
    pub const ALL: [Algorithm; 12] = [
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
/// of [`MapHeader::words`] bit-packed 32-bit words, packed like planner-core's grid (cell
/// `i = y * width + x` is bit `i % 32` of word `i / 32`; set = blocked). The publisher's
/// slice capacity is [`MAP_WORDS`] (512 x 512 cells): larger maps are
/// [`ServiceError::MapTooLarge`]. Only the used words travel.
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
    /// Reserved, zero.
    pub reserved: u32,
}

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

    /// Words the cells take (`ceil(width * height / 32)`), saturating on garbage sizes.
    pub fn words(&self) -> usize {
        (self.width as usize)
            .saturating_mul(self.height as usize)
            .div_ceil(32)
    }
}

/// Packs a grid into a frame: header and words. Errors with [`ServiceError::MapTooLarge`]
/// beyond the frame capacity.
pub fn pack_map(
    meta: MapMeta,
    grid: GridRef<'_>,
    words: &mut Vec<u32>,
) -> Result<MapHeader, ServiceError> {
    let (w, h) = (grid.width(), grid.height());
    if w == 0 || h == 0 || w.saturating_mul(h) > MAP_CAPACITY_CELLS {
        return Err(ServiceError::MapTooLarge);
    }
    let cells = w * h;
    words.clear();
    words.resize(cells.div_ceil(32), 0);
    for (word_index, word) in words.iter_mut().enumerate() {
        let base = word_index * 32;
        for bit in 0..32.min(cells - base) {
            let i = base + bit;
            if grid.is_blocked((i % w) as isize, (i / w) as isize) {
                *word |= 1 << bit;
            }
        }
    }
    Ok(MapHeader {
        map_id: meta.map_id,
        version: meta.version,
        width: w as u32,
        height: h as u32,
        resolution: meta.resolution,
        origin: meta.origin,
        reserved: 0,
    })
}

/// Validates a frame's size and rebuilds its grid: `max_cells` is the receiver's own
/// limit (at most [`MAP_CAPACITY_CELLS`]).
pub fn grid_from_bits(
    width: u32,
    height: u32,
    bits: &[u32],
    max_cells: usize,
) -> Result<Box<WireGrid>, ServiceError> {
    let (w, h) = (width as usize, height as usize);
    if w == 0 || h == 0 {
        return Err(ServiceError::InvalidRequest);
    }
    let cells = w
        .checked_mul(h)
        .filter(|&c| c <= max_cells.min(MAP_CAPACITY_CELLS))
        .ok_or(ServiceError::MapTooLarge)?;
    if bits.len() < cells.div_ceil(32) {
        return Err(ServiceError::InvalidRequest);
    }
    let mut grid = Box::new(WireGrid::new(w, h).map_err(|_| ServiceError::MapTooLarge)?);
    for (word_index, &word) in bits.iter().enumerate().take(cells.div_ceil(32)) {
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
    Ok(grid)
}

/// What a [`PlanRequest`] asks for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[repr(u8)]
pub enum RequestKind {
    /// Plan a path.
    Plan = 0,
    /// Only check that the server holds this map id and version (answers ok or the map
    /// error); used to confirm an upload.
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
    /// the horizon); `extra[1]` = the swarm planners' guide route (0: the visibility graph's
    /// shortest route, 1: A*; see `planner_core::planner::GuideKind`); the rest
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
            GuideKind::Visibility => 0.0,
            GuideKind::AStar => 1.0,
        }
    }

    fn guide_of(code: f32) -> Option<planner_core::planner::GuideKind> {
        use planner_core::planner::GuideKind;
        match code {
            0.0 => Some(GuideKind::Visibility),
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
            && self.radius <= MAP_CAPACITY_SIDE as f32;
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
    /// Cells expanded (reference searches) or objective evaluations (swarm planners).
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
    pub fn to_grid(&self, max_cells: usize) -> Result<Box<WireGrid>, ServiceError> {
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
        for bad in [0u8, 13, 99, 255] {
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
        assert_eq!(guide(0.0), Some(GuideKind::Visibility));
        assert_eq!(guide(1.0), Some(GuideKind::AStar));
        assert_eq!(guide(2.0), None);
        for g in [GuideKind::Visibility, GuideKind::AStar] {
            assert_eq!(guide(PlanParams::guide_code(g)), Some(g));
        }
    }

    #[test]
    fn frame_round_trips_a_grid_and_rejects_garbage() {
        let grid = WireGrid::parse_rows(b"..@.\n@...\n...@\n").unwrap();
        let meta = MapMeta {
            map_id: 7,
            version: 3,
            resolution: 0.05,
            origin: [1.0, 2.0],
        };
        let mut words = Vec::new();
        let mut header = pack_map(meta, grid.view(), &mut words).unwrap();
        assert_eq!(words.len(), 1);
        assert_eq!(header.meta(), meta);
        let back = grid_from_bits(header.width, header.height, &words, MAP_CAPACITY_CELLS);
        assert_eq!(*back.unwrap(), grid);
        let msg = MapMsg::new(&header, &words);
        let bytes = postcard::to_allocvec(&msg).unwrap();
        let msg2: MapMsg = postcard::from_bytes(&bytes).unwrap();
        assert_eq!(*msg2.to_grid(MAP_CAPACITY_CELLS).unwrap(), grid);
        // Server-side limit, garbage sizes, too few words.
        let to_grid = |h: &MapHeader, max| grid_from_bits(h.width, h.height, &words, max);
        assert_eq!(to_grid(&header, 5).unwrap_err(), ServiceError::MapTooLarge);
        header.width = u32::MAX;
        assert_eq!(
            to_grid(&header, MAP_CAPACITY_CELLS).unwrap_err(),
            ServiceError::MapTooLarge
        );
        header.width = 0;
        assert_eq!(
            to_grid(&header, MAP_CAPACITY_CELLS).unwrap_err(),
            ServiceError::InvalidRequest
        );
        header.width = 40;
        assert_eq!(
            to_grid(&header, MAP_CAPACITY_CELLS).unwrap_err(),
            ServiceError::InvalidRequest
        );
        let huge = planner_core::grid::Grid::<{ words_for(600, 600) }>::new(600, 600).unwrap();
        assert_eq!(
            pack_map(meta, huge.view(), &mut words).unwrap_err(),
            ServiceError::MapTooLarge
        );
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

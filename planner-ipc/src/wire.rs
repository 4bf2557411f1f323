//! Wire types: the fixed-layout (`#[repr(C)]`, [`ZeroCopySend`]) payloads that travel through
//! iceoryx2 shared memory, their conversion to and from planner-core types with validation,
//! and serde mirrors for byte streams (postcard over a socket, logs).
//!
//! Every field a peer writes is untrusted: conversions check ranges and finiteness and turn
//! garbage into a typed [`ServiceError`] or [`PlanError`], never a panic.
//!
//! Status codes of a [`PlanResponse`]: `0` = ok; `1..=8` = [`PlanError::ALL`] in order
//! (index + 1); `100..` = [`ServiceError`] (see [`ServiceError::code`]).

use iceoryx2::prelude::ZeroCopySend;
use planner_core::PlanError;
use planner_core::geometry::{Cell, Point};
use planner_core::grid::{Grid, GridRef, words_for};
use serde::{Deserialize, Serialize};
use std::fmt;

/// Side of the largest square map a [`MapFrame`] carries.
pub const MAP_CAPACITY_SIDE: usize = 512;
/// Cells a [`MapFrame`] can carry (`512 x 512`); larger maps are [`ServiceError::MapTooLarge`].
pub const MAP_CAPACITY_CELLS: usize = MAP_CAPACITY_SIDE * MAP_CAPACITY_SIDE;
/// 32-bit words of a frame's bit-packed grid.
pub const MAP_WORDS: usize = words_for(MAP_CAPACITY_CELLS, 1);
/// Most waypoints a [`PlanResponse`] carries; a longer path is [`PlanError::CapacityExceeded`].
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

/// The planners the service knows. Wire code = discriminant; `0` is never a planner.
///
/// Adding a planner (the swarm optimizers: `tclhho`, `igwo`, `hho`, `gwo`, `tgwo`, `pso`,
/// `ga`, `aco`, ...) is one variant here, one line in [`Algorithm::ALL`] and one match arm
/// in the server's engine (`engine::run_planner`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
pub enum Algorithm {
    /// A*: shortest 8-connected path.
    AStar = 1,
    /// Theta*: any-angle path.
    ThetaStar = 2,
}

impl Algorithm {
    /// Every served planner.
    pub const ALL: [Algorithm; 2] = [Algorithm::AStar, Algorithm::ThetaStar];

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

    /// The name used on command lines and in JSON lines (same as `host-sim plan --algo`).
    pub const fn name(self) -> &'static str {
        match self {
            Algorithm::AStar => "astar",
            Algorithm::ThetaStar => "theta",
        }
    }

    /// The planner of a name, or [`ServiceError::UnknownAlgorithm`].
    pub fn from_name(name: &str) -> Result<Self, ServiceError> {
        Self::ALL
            .into_iter()
            .find(|a| a.name() == name)
            .ok_or(ServiceError::UnknownAlgorithm)
    }
}

/// A map frame: an occupancy grid of up to [`MAP_CAPACITY_CELLS`] cells, bit-packed like
/// planner-core's grid (cell `i = y * width + x` is bit `i % 32` of word `i / 32`; set =
/// blocked), with its identity and placement in the world.
#[derive(Debug, Clone, ZeroCopySend)]
#[repr(C)]
pub struct MapFrame {
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
    /// The bit-packed cells; words past `width * height` bits are ignored.
    pub bits: [u32; MAP_WORDS],
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

impl MapFrame {
    /// An empty frame (all words zero), for in-place filling.
    pub fn zeroed() -> Box<Self> {
        Box::new(MapFrame {
            map_id: 0,
            version: 0,
            width: 0,
            height: 0,
            resolution: 0.0,
            origin: [0.0; 2],
            reserved: 0,
            bits: [0; MAP_WORDS],
        })
    }

    /// Fills this frame from a grid. Errors with [`ServiceError::MapTooLarge`] when the grid
    /// has more cells than the frame holds.
    pub fn fill(&mut self, meta: MapMeta, grid: GridRef<'_>) -> Result<(), ServiceError> {
        let (w, h) = (grid.width(), grid.height());
        if w == 0 || h == 0 || w.saturating_mul(h) > MAP_CAPACITY_CELLS {
            return Err(ServiceError::MapTooLarge);
        }
        self.map_id = meta.map_id;
        self.version = meta.version;
        self.width = w as u32;
        self.height = h as u32;
        self.resolution = meta.resolution;
        self.origin = meta.origin;
        self.reserved = 0;
        let cells = w * h;
        for (word_index, word) in self.bits.iter_mut().enumerate() {
            *word = 0;
            let base = word_index * 32;
            if base >= cells {
                continue;
            }
            for bit in 0..32.min(cells - base) {
                let i = base + bit;
                if grid.is_blocked((i % w) as isize, (i / w) as isize) {
                    *word |= 1 << bit;
                }
            }
        }
        Ok(())
    }

    /// The frame's metadata.
    pub fn meta(&self) -> MapMeta {
        MapMeta {
            map_id: self.map_id,
            version: self.version,
            resolution: self.resolution,
            origin: self.origin,
        }
    }

    /// Validates the header and rebuilds the grid. `max_cells` is the receiver's own limit
    /// (at most [`MAP_CAPACITY_CELLS`]).
    pub fn to_grid(&self, max_cells: usize) -> Result<Box<WireGrid>, ServiceError> {
        grid_from_bits(self.width, self.height, &self.bits, max_cells)
    }
}

/// Rebuilds a grid from bit-packed words (shared by the frame and its serde mirror).
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
    /// Planner-specific extras (reserved for the swarm planners).
    pub extra: [f32; 5],
}

impl PlanParams {
    /// Checks every field: finite, not negative; counts integral and below 2^24.
    pub fn validate(&self) -> Result<(), PlanError> {
        let all = [self.radius, self.population, self.iterations];
        let ok = all
            .iter()
            .chain(self.extra.iter())
            .all(|v| v.is_finite() && *v >= 0.0)
            && [self.population, self.iterations]
                .iter()
                .all(|v| v.fract() == 0.0 && *v < 16_777_216.0)
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

/// A plan response (fixed layout, travels zero-copy).
#[derive(Debug, Clone, ZeroCopySend)]
#[repr(C)]
pub struct PlanResponse {
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
    /// Valid entries of `path`.
    pub waypoints: u32,
    /// Path length (cell units).
    pub length: f32,
    /// Direction changes.
    pub turns: u32,
    /// Cells expanded (reference searches) or objective evaluations (swarm planners).
    pub evaluations: u32,
    /// Server-side planning time, microseconds.
    pub time_us: f32,
    /// Waypoints `[x, y]` in cell units, start first.
    pub path: [[f32; 2]; MAX_WAYPOINTS],
}

impl PlanResponse {
    /// Writes the header of an empty response (no waypoints) for `request_id`.
    pub fn reset(&mut self, request: &PlanRequest) {
        self.request_id = request.request_id;
        self.status = STATUS_OK;
        self.algorithm = request.algorithm;
        self.reserved = 0;
        self.map_id = request.map_id;
        self.map_version = request.map_version;
        self.waypoints = 0;
        self.length = 0.0;
        self.turns = 0;
        self.evaluations = 0;
        self.time_us = 0.0;
    }

    /// A zeroed response on the heap.
    pub fn zeroed() -> Box<Self> {
        Box::new(PlanResponse {
            request_id: 0,
            status: 0,
            algorithm: 0,
            reserved: 0,
            map_id: 0,
            map_version: 0,
            waypoints: 0,
            length: 0.0,
            turns: 0,
            evaluations: 0,
            time_us: 0.0,
            path: [[0.0; 2]; MAX_WAYPOINTS],
        })
    }

    /// The valid waypoints; a garbage count is clamped to the capacity.
    pub fn path(&self) -> &[[f32; 2]] {
        &self.path[..(self.waypoints as usize).min(MAX_WAYPOINTS)]
    }

    /// Decodes the response into an owned result, validating the status and the path.
    pub fn to_result(&self) -> Result<PlanResult, DecodeError> {
        match decode_status(self.status) {
            None => Err(DecodeError::UnknownStatus(self.status)),
            Some(Err(f)) => Ok(PlanResult {
                request_id: self.request_id,
                outcome: Err(f),
                time_us: self.time_us,
            }),
            Some(Ok(())) => {
                if self.waypoints as usize > MAX_WAYPOINTS {
                    return Err(DecodeError::BadPath);
                }
                let path: Vec<Point> = self.path().iter().map(|p| Point::new(p[0], p[1])).collect();
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
    /// Encodes into a fixed-layout response.
    pub fn write_to(&self, out: &mut PlanResponse) {
        out.request_id = self.request_id;
        out.time_us = self.time_us;
        match &self.outcome {
            Ok(ok) => {
                let n = ok.path.len().min(MAX_WAYPOINTS);
                for (dst, p) in out.path.iter_mut().zip(&ok.path[..n]) {
                    *dst = [p.x, p.y];
                }
                out.status = STATUS_OK;
                out.waypoints = n as u32;
                out.length = ok.length;
                out.turns = ok.turns;
                out.evaluations = ok.evaluations;
            }
            Err(f) => {
                out.status = status_code(Err(*f));
                out.waypoints = 0;
            }
        }
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
    /// `ceil(width * height / 32)` words, same packing as [`MapFrame::bits`].
    pub bits: Vec<u32>,
}

impl From<&MapFrame> for MapMsg {
    fn from(f: &MapFrame) -> Self {
        let words = (f.width as usize)
            .saturating_mul(f.height as usize)
            .div_ceil(32)
            .min(MAP_WORDS);
        MapMsg {
            meta: f.meta(),
            width: f.width,
            height: f.height,
            bits: f.bits[..words].to_vec(),
        }
    }
}

impl MapMsg {
    /// Validates and rebuilds the grid (see [`MapFrame::to_grid`]).
    pub fn to_grid(&self, max_cells: usize) -> Result<Box<WireGrid>, ServiceError> {
        grid_from_bits(self.width, self.height, &self.bits, max_cells)
    }
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
        for bad in [0u8, 3, 99, 255] {
            assert_eq!(
                Algorithm::from_code(bad),
                Err(ServiceError::UnknownAlgorithm)
            );
        }
        assert_eq!(
            Algorithm::from_name("tclhho"),
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
        ];
        for p in bad {
            assert_eq!(p.validate(), Err(PlanError::InvalidParameters), "{p:?}");
        }
    }

    #[test]
    fn frame_round_trips_a_grid_and_rejects_garbage() {
        let grid = WireGrid::parse_rows(b"..@.\n@...\n...@\n").unwrap();
        let mut frame = MapFrame::zeroed();
        let meta = MapMeta {
            map_id: 7,
            version: 3,
            resolution: 0.05,
            origin: [1.0, 2.0],
        };
        frame.fill(meta, grid.view()).unwrap();
        let back = frame.to_grid(MAP_CAPACITY_CELLS).unwrap();
        assert_eq!(*back, grid);
        let msg = MapMsg::from(&*frame);
        assert_eq!(msg.bits.len(), 1);
        let bytes = postcard::to_allocvec(&msg).unwrap();
        let msg2: MapMsg = postcard::from_bytes(&bytes).unwrap();
        assert_eq!(*msg2.to_grid(MAP_CAPACITY_CELLS).unwrap(), grid);
        // Server-side limit, garbage sizes.
        assert_eq!(frame.to_grid(5).unwrap_err(), ServiceError::MapTooLarge);
        frame.width = u32::MAX;
        assert_eq!(
            frame.to_grid(MAP_CAPACITY_CELLS).unwrap_err(),
            ServiceError::MapTooLarge
        );
        frame.width = 0;
        assert_eq!(
            frame.to_grid(MAP_CAPACITY_CELLS).unwrap_err(),
            ServiceError::InvalidRequest
        );
    }

    #[test]
    fn responses_decode_and_reject_garbage() {
        let mut resp = PlanResponse::zeroed();
        let req = PlanRequest::new((1, 1), [0, 0], [1, 1], Algorithm::AStar);
        resp.reset(&req);
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
        ok.write_to(&mut resp);
        assert_eq!(resp.to_result().unwrap(), ok);
        let bytes = postcard::to_allocvec(&ok).unwrap();
        assert_eq!(postcard::from_bytes::<PlanResult>(&bytes).unwrap(), ok);
        resp.waypoints = u32::MAX;
        assert_eq!(resp.to_result().unwrap_err(), DecodeError::BadPath);
        resp.waypoints = 2;
        resp.path[1] = [f32::NAN, 0.0];
        assert_eq!(resp.to_result().unwrap_err(), DecodeError::BadPath);
        resp.status = 4242;
        assert_eq!(
            resp.to_result().unwrap_err(),
            DecodeError::UnknownStatus(4242)
        );
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

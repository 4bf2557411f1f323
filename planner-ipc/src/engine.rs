//! The transport-free part of the server: the map store (keyed by map id, holding the
//! newest version) and the planner dispatch. The iceoryx2 server and the socket benchmark
//! peer both run requests through [`Engine::handle`], so they do exactly the same work.
//!
//! A stored map's cells live either in the server's own memory ([`MapCells::Grid`]) or in
//! a received frame the store keeps as it is ([`MapCells::Frame`]: an iceoryx2 sample in
//! shared memory, planned on through a [`GridRef`] view of its words, never copied).

use crate::wire::{
    Algorithm, Failure, MAX_WAYPOINTS, MapFacts, MapMeta, PlanAnswer, PlanFound, PlanRequest,
    PlanResult, RequestKind, ServiceError, to_cell,
};
use planner_core::PlanError;
use planner_core::grid::{GridBuf, GridRef, words_for};
use planner_core::optim::any::AlgorithmKind;
use planner_core::path::{Path, PathView};
use planner_core::planner::aco::AcoParams;
use planner_core::planner::owned::{HostPlanner, PlanChoice};
use planner_core::planner::{PlanOptions, PlanParams};
use std::collections::HashMap;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, RwLock};
use std::time::Instant;

/// How many inflated variants (one per robot radius) a map keeps cached.
const INFLATED_CACHE: usize = 4;

/// Words of a received frame that the store keeps instead of copying them: the row-major
/// bits of a `width x height` grid in the first `n = words_for(width, height)` words, the
/// column-major bits in the next `n` (a
/// [`LAYOUT_ROWS_AND_COLUMNS`](crate::wire::LAYOUT_ROWS_AND_COLUMNS) frame).
pub trait FrameWords {
    /// The frame's words.
    fn words(&self) -> &[u32];
}

/// The frame type of a store that keeps no frames (every map in its own memory).
#[derive(Debug)]
pub enum NoFrame {}

impl FrameWords for NoFrame {
    fn words(&self) -> &[u32] {
        match *self {}
    }
}

/// Where a stored map's cells live.
pub enum MapCells<F = NoFrame> {
    /// The server's own memory (built from a rows-only frame, or copied).
    Grid(GridBuf),
    /// A received frame, planned on in place.
    Frame {
        /// The frame (its words hold both layouts).
        frame: F,
        /// Width in cells.
        width: usize,
        /// Height in cells.
        height: usize,
    },
}

impl<F: FrameWords> MapCells<F> {
    /// A kept frame of a `width x height` grid; [`ServiceError::InvalidRequest`] when it
    /// holds fewer words than both layouts need or has a zero side (so that
    /// [`view`](Self::view) never fails).
    pub fn frame(frame: F, width: usize, height: usize) -> Result<Self, ServiceError> {
        let cells = MapCells::Frame {
            frame,
            width,
            height,
        };
        match cells.view() {
            Some(_) => Ok(cells),
            None => Err(ServiceError::InvalidRequest),
        }
    }

    /// The grid view (`None` only for a frame [`frame`](Self::frame) refused).
    pub fn view(&self) -> Option<GridRef<'_>> {
        match self {
            MapCells::Grid(grid) => Some(grid.view()),
            MapCells::Frame {
                frame,
                width,
                height,
            } => {
                let words = frame.words();
                let n = words_for(*width, *height);
                let (rows, rest) = words.split_at_checked(n)?;
                GridRef::from_words(*width, *height, rows, rest.get(..n)?).ok()
            }
        }
    }
}

/// A grid ready for queries (possibly inflated); each worker's planner labels its
/// components once per grid it meets (by its `id`).
pub struct Prepared<F = NoFrame> {
    /// Unique for the life of the process: what a worker's scratch remembers (not the
    /// `Arc`, which would keep a frame borrowed after its map was replaced).
    id: u64,
    width: usize,
    height: usize,
    cells: MapCells<F>,
}

impl<F: FrameWords> Prepared<F> {
    fn new(cells: MapCells<F>) -> Result<Self, ServiceError> {
        static NEXT: AtomicU64 = AtomicU64::new(1);
        let view = cells.view().ok_or(ServiceError::InvalidRequest)?;
        Ok(Prepared {
            id: NEXT.fetch_add(1, Ordering::Relaxed),
            width: view.width(),
            height: view.height(),
            cells,
        })
    }

    /// The grid view; [`ServiceError::Internal`] never happens (checked when made).
    fn view(&self) -> Result<GridRef<'_>, ServiceError> {
        self.cells.view().ok_or(ServiceError::Internal)
    }
}

/// One map version held by the store.
pub struct StoredMap<F = NoFrame> {
    /// Identity and placement.
    pub meta: MapMeta,
    /// How long making the frame usable took, microseconds (building the grid from a
    /// rows-only frame; checking, and copying if the frame is not kept, a frame of both
    /// layouts): what a map-status answer reports; `0` when the caller did not say.
    pub decode_us: f32,
    base: Arc<Prepared<F>>,
    inflated: Mutex<Vec<(u32, Arc<Prepared<F>>)>>,
}

impl<F: FrameWords> StoredMap<F> {
    /// Width and height in cells.
    pub fn size(&self) -> (usize, usize) {
        (self.base.width, self.base.height)
    }

    /// Whether the cells are a kept frame (planned on in place) rather than the server's
    /// own copy.
    pub fn in_frame(&self) -> bool {
        matches!(self.base.cells, MapCells::Frame { .. })
    }

    /// The prepared grid for a robot radius (cached per radius).
    fn prepared(&self, radius: f32) -> Result<Arc<Prepared<F>>, Failure> {
        if radius == 0.0 {
            return Ok(self.base.clone());
        }
        let key = radius.to_bits();
        let mut cache = self
            .inflated
            .lock()
            .unwrap_or_else(|poisoned| poisoned.into_inner());
        if let Some((_, p)) = cache.iter().find(|(k, _)| *k == key) {
            return Ok(p.clone());
        }
        let out = match &self.base.cells {
            MapCells::Grid(grid) => grid.inflated(radius),
            // Inflation reads a GridBuf: one whole-word copy of the frame first.
            MapCells::Frame { .. } => GridBuf::from_view(self.base.view()?).inflated(radius),
        }
        .map_err(|_| PlanError::InvalidParameters)?;
        let p = Arc::new(Prepared::new(MapCells::Grid(out))?);
        if cache.len() >= INFLATED_CACHE {
            cache.remove(0);
        }
        cache.push((key, p.clone()));
        Ok(p)
    }
}

/// What happened to an incoming map frame.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapUpdate {
    /// Stored as the map id's current version.
    Stored,
    /// Ignored: the store already holds this or a newer version.
    Outdated,
    /// Rejected; requests naming this id and version get the error.
    Rejected(ServiceError),
}

enum Slot<F> {
    Ready(Arc<StoredMap<F>>),
    Rejected { version: u32, error: ServiceError },
}

impl<F> Slot<F> {
    fn version(&self) -> u32 {
        match self {
            Slot::Ready(m) => m.meta.version,
            Slot::Rejected { version, .. } => *version,
        }
    }
}

/// Maps by id (newest version only), shared between the receiving thread and the workers.
/// `F`: the frames it may keep ([`NoFrame`]: none).
pub struct MapStore<F = NoFrame> {
    max_cells: usize,
    max_maps: usize,
    maps: RwLock<HashMap<u32, Slot<F>>>,
}

impl MapStore {
    /// A store accepting maps of at most `max_cells` cells (the frames' decoders,
    /// [`grid_from_bits`](crate::wire::grid_from_bits) and
    /// [`frame_grid`](crate::wire::frame_grid), apply it) and at most `max_maps` map ids.
    pub fn new(max_cells: usize, max_maps: usize) -> Self {
        Self::keeping_frames(max_cells, max_maps)
    }
}

impl<F: FrameWords> MapStore<F> {
    /// Like [`MapStore::new`], for a store that may keep received frames of type `F`.
    pub fn keeping_frames(max_cells: usize, max_maps: usize) -> Self {
        MapStore {
            max_cells,
            max_maps: max_maps.max(1),
            maps: RwLock::new(HashMap::new()),
        }
    }

    /// The configured cell limit.
    pub fn max_cells(&self) -> usize {
        self.max_cells
    }

    /// How many map ids the store keeps at once.
    pub fn max_maps(&self) -> usize {
        self.max_maps
    }

    /// Takes a map version: `grid` is the decoded frame or the decoding error.
    pub fn update(&self, meta: MapMeta, grid: Result<GridBuf, ServiceError>) -> MapUpdate {
        self.update_decoded(meta, grid, 0.0)
    }

    /// Like [`update`](Self::update), also recording how long decoding the frame into
    /// `grid` took (microseconds; map-status answers report it).
    pub fn update_decoded(
        &self,
        meta: MapMeta,
        grid: Result<GridBuf, ServiceError>,
        decode_us: f32,
    ) -> MapUpdate {
        self.update_cells(meta, grid.map(MapCells::Grid), decode_us)
    }

    /// Whether a frame of `meta` would be stored (no newer or equal version held; versions
    /// count from 1, so version 0 never is): a receiver may skip checking an outdated frame.
    pub fn is_newer(&self, meta: &MapMeta) -> bool {
        let maps = self.maps.read().unwrap_or_else(|p| p.into_inner());
        meta.version > 0
            && maps
                .get(&meta.map_id)
                .is_none_or(|slot| slot.version() < meta.version)
    }

    /// Takes a map version whose cells are in the server's memory or in a kept frame (see
    /// [`update_decoded`](Self::update_decoded)).
    pub fn update_cells(
        &self,
        meta: MapMeta,
        grid: Result<MapCells<F>, ServiceError>,
        decode_us: f32,
    ) -> MapUpdate {
        if !self.is_newer(&meta) {
            return MapUpdate::Outdated;
        }
        // Prepare (labels) outside the lock: workers keep planning on the old version.
        let slot = match grid.and_then(Prepared::new) {
            Ok(prepared) => Slot::Ready(Arc::new(StoredMap {
                meta,
                decode_us,
                base: Arc::new(prepared),
                inflated: Mutex::new(Vec::new()),
            })),
            Err(error) => Slot::Rejected {
                version: meta.version,
                error,
            },
        };
        let result = match &slot {
            Slot::Ready(_) => MapUpdate::Stored,
            Slot::Rejected { error, .. } => MapUpdate::Rejected(*error),
        };
        let mut maps = self.maps.write().unwrap_or_else(|p| p.into_inner());
        if let Some(old) = maps.get(&meta.map_id)
            && old.version() >= meta.version
        {
            return MapUpdate::Outdated;
        }
        if !maps.contains_key(&meta.map_id) && maps.len() >= self.max_maps {
            // Evict the map with the smallest id to stay bounded (documented policy).
            if let Some(&victim) = maps.keys().min() {
                maps.remove(&victim);
            }
        }
        maps.insert(meta.map_id, slot);
        result
    }

    /// What the store holds of `map_id`: its newest version, and that version's size and
    /// decoding time when it was taken (zero for a rejected frame); `None` for an unknown id.
    pub fn facts(&self, map_id: u32) -> Option<MapFacts> {
        let maps = self.maps.read().unwrap_or_else(|p| p.into_inner());
        maps.get(&map_id).map(|slot| match slot {
            Slot::Ready(m) => MapFacts {
                version: m.meta.version,
                width: m.base.width as u32,
                height: m.base.height as u32,
                decode_us: m.decode_us,
            },
            Slot::Rejected { version, .. } => MapFacts {
                version: *version,
                ..MapFacts::default()
            },
        })
    }

    /// The map a request names, or why it cannot be used.
    pub fn lookup(&self, map_id: u32, version: u32) -> Result<Arc<StoredMap<F>>, ServiceError> {
        let maps = self.maps.read().unwrap_or_else(|p| p.into_inner());
        match maps.get(&map_id) {
            None => Err(ServiceError::UnknownMap),
            Some(slot) if slot.version() > version => Err(ServiceError::StaleMapVersion),
            Some(slot) if slot.version() < version => Err(ServiceError::UnknownMap),
            Some(Slot::Rejected { error, .. }) => Err(*error),
            Some(Slot::Ready(m)) => Ok(m.clone()),
        }
    }
}

/// Per-worker scratch: every planner's buffers and the path (no allocation per request once
/// warmed up to the largest map).
pub struct Scratch {
    planner: HostPlanner,
    /// The prepared grid the planner's labels belong to ([`Prepared`]'s id).
    prepared_for: Option<u64>,
    path: Box<Path<MAX_WAYPOINTS>>,
}

impl Default for Scratch {
    fn default() -> Self {
        Scratch {
            planner: HostPlanner::new(),
            prepared_for: None,
            path: Box::new(Path::new()),
        }
    }
}

/// The planning engine: a map store and the planner dispatch.
pub struct Engine<F = NoFrame> {
    /// The maps.
    pub store: MapStore<F>,
}

impl Engine {
    /// An engine over a fresh store.
    pub fn new(max_cells: usize, max_maps: usize) -> Self {
        Self::keeping_frames(max_cells, max_maps)
    }
}

impl<F: FrameWords> Engine<F> {
    /// An engine over a fresh store that may keep received frames of type `F`.
    pub fn keeping_frames(max_cells: usize, max_maps: usize) -> Self {
        Engine {
            store: MapStore::keeping_frames(max_cells, max_maps),
        }
    }

    /// Validates and runs one request. `cancelled` is polled before and after planning
    /// (planner-core's planners are synchronous; a cooperative hook for long swarm runs can
    /// be threaded through later).
    pub fn handle(
        &self,
        scratch: &mut Scratch,
        request: &PlanRequest,
        cancelled: &mut dyn FnMut() -> bool,
    ) -> PlanResult {
        self.handle_in_place(scratch, request, cancelled).to_owned()
    }

    /// Like [`handle`](Self::handle), leaving the path where it was planned: in `scratch`,
    /// until its next request (the server writes it from there straight into the answer's
    /// shared memory).
    pub fn handle_in_place<'s>(
        &self,
        scratch: &'s mut Scratch,
        request: &PlanRequest,
        cancelled: &mut dyn FnMut() -> bool,
    ) -> PlanAnswer<'s> {
        let began = Instant::now();
        let mut map = None;
        let outcome = self.handle_inner(scratch, request, &mut map, cancelled);
        let time_us = began.elapsed().as_secs_f32() * 1e6;
        PlanAnswer {
            request_id: request.request_id,
            outcome: outcome.map(|figures| PlanFound {
                path: if figures.planned {
                    &scratch.path[..]
                } else {
                    &[]
                },
                length: figures.length,
                turns: figures.turns,
                evaluations: figures.evaluations,
            }),
            map,
            time_us,
        }
    }

    fn handle_inner(
        &self,
        scratch: &mut Scratch,
        req: &PlanRequest,
        facts: &mut Option<MapFacts>,
        cancelled: &mut dyn FnMut() -> bool,
    ) -> Result<Figures, Failure> {
        let kind = req.kind()?;
        *facts = self.store.facts(req.map_id);
        let map = self.store.lookup(req.map_id, req.map_version)?;
        if kind == RequestKind::MapStatus {
            return Ok(Figures {
                planned: false,
                length: 0.0,
                turns: 0,
                evaluations: 0,
            });
        }
        let algorithm = Algorithm::from_code(req.algorithm)?;
        req.params.validate()?;
        if cancelled() {
            return Err(ServiceError::Cancelled.into());
        }
        let prepared = map.prepared(req.params.radius)?;
        let result = run_planner(algorithm, &prepared, scratch, req, cancelled)?;
        if cancelled() {
            return Err(ServiceError::Cancelled.into());
        }
        Ok(result)
    }
}

/// What a request produced besides the path (which stays in the scratch when `planned`).
struct Figures {
    planned: bool,
    length: f32,
    turns: u32,
    evaluations: u32,
}

/// Runs one planner. Swarm planners and ACO poll `cancelled` once per iteration (a client
/// that gave up stops the work; the caller then answers `Cancelled`).
fn run_planner<F: FrameWords>(
    algorithm: Algorithm,
    prepared: &Prepared<F>,
    scratch: &mut Scratch,
    req: &PlanRequest,
    cancelled: &mut dyn FnMut() -> bool,
) -> Result<Figures, Failure> {
    let grid = prepared.view()?;
    // The start is checked against the map before the goal is converted, so that a start
    // outside the map is reported as such whatever the goal (as the planners do).
    let start = to_cell(req.start, PlanError::StartOutsideMap)?;
    if start.x as usize >= grid.width() || start.y as usize >= grid.height() {
        return Err(PlanError::StartOutsideMap.into());
    }
    let goal = to_cell(req.goal, PlanError::GoalOutsideMap)?;
    if scratch.prepared_for != Some(prepared.id) {
        scratch.prepared_for = None;
        scratch.planner.prepare(grid)?;
        scratch.prepared_for = Some(prepared.id);
    }
    let defaults = PlanParams::new(AlgorithmKind::Tclhho);
    let count = |v: u32, default: usize| if v == 0 { default } else { v as usize };
    let stagnation = req.params.stagnation;
    let params = PlanParams {
        population: count(req.params.population, defaults.population),
        iterations: count(req.params.iterations, defaults.iterations as usize) as u32,
        stagnation: (stagnation > 0).then_some(stagnation),
        seed: req.seed,
        guide: req.params.guide().ok_or(PlanError::InvalidParameters)?,
        blend: req.params.blend(),
        ..defaults
    };
    let aco = AcoParams {
        ants: count(req.params.population, AcoParams::default().ants),
        iterations: count(
            req.params.iterations,
            AcoParams::default().iterations as usize,
        ) as u32,
        stagnation: params.stagnation,
        seed: req.seed,
        ..AcoParams::default()
    };
    let out: &mut PathView = &mut *scratch.path;
    let outcome = scratch.planner.plan(
        grid,
        start,
        goal,
        &PlanChoice {
            kind: algorithm.kind(),
            params,
            aco,
        },
        out,
        PlanOptions {
            history: &mut [],
            interrupt: Some(cancelled),
        },
    )?;
    Ok(Figures {
        planned: true,
        length: outcome.length,
        turns: outcome.turns as u32,
        evaluations: match (outcome.expanded, outcome.report) {
            (Some(e), _) => e,
            (None, Some(r)) => r.evaluations.min(u32::MAX as u64) as u32,
            (None, None) => 0,
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::PlanParams;

    fn meta(id: u32, version: u32) -> MapMeta {
        MapMeta {
            map_id: id,
            version,
            resolution: 1.0,
            origin: [0.0; 2],
        }
    }

    fn grid(rows: &[u8]) -> Result<GridBuf, ServiceError> {
        Ok(GridBuf::parse_rows(rows).unwrap())
    }

    #[test]
    fn store_versions_and_errors() {
        let e = Engine::new(100, 4);
        assert_eq!(
            e.store.update(meta(1, 2), grid(b"...\n...\n")),
            MapUpdate::Stored
        );
        assert_eq!(
            e.store.update(meta(1, 1), grid(b"...\n")),
            MapUpdate::Outdated
        );
        assert!(e.store.lookup(1, 2).is_ok());
        assert_eq!(
            e.store.lookup(1, 1).err(),
            Some(ServiceError::StaleMapVersion)
        );
        assert_eq!(e.store.lookup(1, 3).err(), Some(ServiceError::UnknownMap));
        assert_eq!(e.store.lookup(2, 1).err(), Some(ServiceError::UnknownMap));
        assert_eq!(
            e.store.update(meta(3, 1), Err(ServiceError::MapTooLarge)),
            MapUpdate::Rejected(ServiceError::MapTooLarge)
        );
        assert_eq!(e.store.lookup(3, 1).err(), Some(ServiceError::MapTooLarge));
        // A map-status answer: the size, and the decoding time the receiver recorded.
        assert_eq!(
            e.store
                .update_decoded(meta(4, 1), grid(b"....\n....\n....\n"), 12.5),
            MapUpdate::Stored
        );
        let status = PlanRequest::map_status((4, 1));
        let answer = e.handle(&mut Scratch::default(), &status, &mut || false);
        let facts = answer.map.unwrap();
        assert_eq!((facts.width, facts.height, facts.decode_us), (4, 3, 12.5));
        assert!(answer.outcome.unwrap().path.is_empty());
    }

    #[test]
    fn handle_plans_and_reports_typed_errors() {
        let e = Engine::new(crate::wire::DEFAULT_MAX_CELLS, 4);
        e.store.update(meta(1, 1), grid(b"....\n.@@.\n....\n"));
        let mut s = Scratch::default();
        let mut never = || false;
        let req = PlanRequest::new((1, 1), [0, 1], [3, 1], Algorithm::AStar);
        let r = e.handle(&mut s, &req, &mut never);
        assert_eq!(r.outcome.as_ref().unwrap().length, 5.0);
        let mut bad = req;
        bad.algorithm = 77;
        assert_eq!(
            e.handle(&mut s, &bad, &mut never).outcome.unwrap_err(),
            Failure::Service(ServiceError::UnknownAlgorithm)
        );
        bad = req;
        bad.params = PlanParams {
            radius: f32::NAN,
            ..Default::default()
        };
        assert_eq!(
            e.handle(&mut s, &bad, &mut never).outcome.unwrap_err(),
            Failure::Plan(PlanError::InvalidParameters)
        );
        bad = req;
        bad.start = [1, 1];
        assert_eq!(
            e.handle(&mut s, &bad, &mut never).outcome.unwrap_err(),
            Failure::Plan(PlanError::StartOccupied)
        );
        bad = req;
        bad.goal = [-5, 0];
        assert_eq!(
            e.handle(&mut s, &bad, &mut never).outcome.unwrap_err(),
            Failure::Plan(PlanError::GoalOutsideMap)
        );
        // Regression (fuzz target request_bytes): a start outside the map but within u16
        // with a goal beyond i32 -> u16 was reported GoalOutsideMap.
        bad = req;
        bad.start = [41, 0];
        bad.goal = [-100_663_289, 0];
        assert_eq!(
            e.handle(&mut s, &bad, &mut never).outcome.unwrap_err(),
            Failure::Plan(PlanError::StartOutsideMap)
        );
        bad = req;
        bad.kind = 9;
        assert_eq!(
            e.handle(&mut s, &bad, &mut never).outcome.unwrap_err(),
            Failure::Service(ServiceError::InvalidRequest)
        );
        let mut always = || true;
        assert_eq!(
            e.handle(&mut s, &req, &mut always).outcome.unwrap_err(),
            Failure::Service(ServiceError::Cancelled)
        );
        let mut theta = req;
        theta.algorithm = Algorithm::ThetaStar.code();
        theta.params.radius = 0.4;
        assert!(e.handle(&mut s, &theta, &mut never).outcome.is_err());
    }
}

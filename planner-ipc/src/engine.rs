//! The transport-free part of the server: the map store (keyed by map id, holding the
//! newest version) and the planner dispatch. The iceoryx2 server and the socket benchmark
//! peer both run requests through [`Engine::handle`], so they do exactly the same work.

use crate::wire::{
    Algorithm, Failure, MAP_CAPACITY_CELLS, MAX_WAYPOINTS, MapMeta, PlanOk, PlanRequest,
    PlanResult, RequestKind, ServiceError, WireGrid, to_cell,
};
use planner_core::PlanError;
use planner_core::optim::any::AlgorithmKind;
use planner_core::path::{Path, PathView};
use planner_core::planner::PlanParams;
use planner_core::planner::aco::AcoParams;
use planner_core::planner::owned::HostPlanner;
use std::collections::HashMap;
use std::sync::{Arc, Mutex, RwLock};
use std::time::Instant;

/// How many inflated variants (one per robot radius) a map keeps cached.
const INFLATED_CACHE: usize = 4;

/// A grid ready for queries (possibly inflated); each worker's planner labels its
/// components once per grid it meets.
pub struct Prepared {
    grid: Box<WireGrid>,
}

impl Prepared {
    fn new(grid: Box<WireGrid>) -> Result<Self, PlanError> {
        Ok(Prepared { grid })
    }
}

/// One map version held by the store.
pub struct StoredMap {
    /// Identity and placement.
    pub meta: MapMeta,
    base: Arc<Prepared>,
    inflated: Mutex<Vec<(u32, Arc<Prepared>)>>,
}

impl StoredMap {
    /// Width and height in cells.
    pub fn size(&self) -> (usize, usize) {
        (self.base.grid.width(), self.base.grid.height())
    }

    /// The prepared grid for a robot radius (cached per radius).
    fn prepared(&self, radius: f32) -> Result<Arc<Prepared>, PlanError> {
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
        let mut out = Box::new(WireGrid::new(1, 1).map_err(|_| PlanError::CapacityExceeded)?);
        self.base
            .grid
            .inflate_into(radius, &mut out)
            .map_err(|_| PlanError::InvalidParameters)?;
        let p = Arc::new(Prepared::new(out)?);
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

enum Slot {
    Ready(Arc<StoredMap>),
    Rejected { version: u32, error: ServiceError },
}

impl Slot {
    fn version(&self) -> u32 {
        match self {
            Slot::Ready(m) => m.meta.version,
            Slot::Rejected { version, .. } => *version,
        }
    }
}

/// Maps by id (newest version only), shared between the receiving thread and the workers.
pub struct MapStore {
    max_cells: usize,
    max_maps: usize,
    maps: RwLock<HashMap<u32, Slot>>,
}

impl MapStore {
    /// A store accepting maps of at most `max_cells` cells (capped at the frame capacity)
    /// and at most `max_maps` map ids.
    pub fn new(max_cells: usize, max_maps: usize) -> Self {
        MapStore {
            max_cells: max_cells.min(MAP_CAPACITY_CELLS),
            max_maps: max_maps.max(1),
            maps: RwLock::new(HashMap::new()),
        }
    }

    /// The configured cell limit.
    pub fn max_cells(&self) -> usize {
        self.max_cells
    }

    /// Takes a map version: `grid` is the decoded frame or the decoding error.
    pub fn update(&self, meta: MapMeta, grid: Result<Box<WireGrid>, ServiceError>) -> MapUpdate {
        {
            let maps = self.maps.read().unwrap_or_else(|p| p.into_inner());
            if let Some(slot) = maps.get(&meta.map_id)
                && slot.version() >= meta.version
            {
                return MapUpdate::Outdated;
            }
        }
        // Prepare (labels) outside the lock: workers keep planning on the old version.
        let slot = match grid.and_then(|g| Prepared::new(g).map_err(|_| ServiceError::Internal)) {
            Ok(prepared) => Slot::Ready(Arc::new(StoredMap {
                meta,
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

    /// The map a request names, or why it cannot be used.
    pub fn lookup(&self, map_id: u32, version: u32) -> Result<Arc<StoredMap>, ServiceError> {
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
    /// The prepared grid the planner's labels belong to (by address; the `Arc` keeps it
    /// alive, so the address cannot be reused while it is held).
    prepared_for: Option<Arc<Prepared>>,
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
pub struct Engine {
    /// The maps.
    pub store: MapStore,
}

impl Engine {
    /// An engine over a fresh store.
    pub fn new(max_cells: usize, max_maps: usize) -> Self {
        Engine {
            store: MapStore::new(max_cells, max_maps),
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
        let began = Instant::now();
        let outcome = self.handle_inner(scratch, request, cancelled);
        PlanResult {
            request_id: request.request_id,
            outcome,
            time_us: began.elapsed().as_secs_f32() * 1e6,
        }
    }

    fn handle_inner(
        &self,
        scratch: &mut Scratch,
        req: &PlanRequest,
        cancelled: &mut dyn FnMut() -> bool,
    ) -> Result<PlanOk, Failure> {
        let kind = req.kind()?;
        let map = self.store.lookup(req.map_id, req.map_version)?;
        if kind == RequestKind::MapStatus {
            let (w, h) = map.size();
            return Ok(PlanOk {
                path: Vec::new(),
                length: 0.0,
                turns: w as u32,
                evaluations: h as u32,
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

/// Runs one planner. Swarm planners and ACO poll `cancelled` once per iteration (a client
/// that gave up stops the work; the caller then answers `Cancelled`).
fn run_planner(
    algorithm: Algorithm,
    prepared: &Arc<Prepared>,
    scratch: &mut Scratch,
    req: &PlanRequest,
    cancelled: &mut dyn FnMut() -> bool,
) -> Result<PlanOk, PlanError> {
    let start = to_cell(req.start, PlanError::StartOutsideMap)?;
    let goal = to_cell(req.goal, PlanError::GoalOutsideMap)?;
    let grid = prepared.grid.view();
    if !scratch
        .prepared_for
        .as_ref()
        .is_some_and(|p| Arc::ptr_eq(p, prepared))
    {
        scratch.planner.prepare(grid)?;
        scratch.prepared_for = Some(prepared.clone());
    }
    let defaults = PlanParams::new(AlgorithmKind::Tclhho);
    let count = |v: f32, default: usize| if v == 0.0 { default } else { v as usize };
    let stagnation = req.params.extra[0] as u32;
    let params = PlanParams {
        population: count(req.params.population, defaults.population),
        iterations: count(req.params.iterations, defaults.iterations as usize) as u32,
        stagnation: (stagnation > 0).then_some(stagnation),
        seed: req.seed,
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
        algorithm.kind(),
        start,
        goal,
        &params,
        &aco,
        out,
        &mut [],
        cancelled,
    )?;
    Ok(PlanOk {
        path: out.to_vec(),
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

    fn grid(rows: &[u8]) -> Result<Box<WireGrid>, ServiceError> {
        Ok(Box::new(WireGrid::parse_rows(rows).unwrap()))
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
    }

    #[test]
    fn handle_plans_and_reports_typed_errors() {
        let e = Engine::new(MAP_CAPACITY_CELLS, 4);
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

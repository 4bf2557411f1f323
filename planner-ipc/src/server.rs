//! The serving loop.
//!
//! One thread owns the iceoryx2 ports: it drains the map subscriber (always before taking
//! requests, so a map published before a request is stored before that request is
//! planned), receives requests and either plans them inline (`workers == 1`, lowest
//! latency) or hands them to a pool of worker threads, each with its own search scratch.
//!
//! Map frames of both layouts are planned on in place: a server planning inline keeps the
//! received sample while its map version is current (at most
//! [`MAP_BORROWED_SAMPLES`](crate::services::MAP_BORROWED_SAMPLES)` - 1` frames from one
//! publisher; further ones are copied). A server with worker threads copies every frame
//! into its own memory (whole words, both layouts): iceoryx2's thread-safe samples may move
//! between threads but not be shared by several. Rows-only frames (earlier builds) are
//! built into a grid as before.
//! The answer goes back through the request's own `ActiveRequest`; a blocking client is
//! then woken through its wake event.
//!
//! Cancellation: a client that gives up drops its `PendingResponse`; the server checks
//! `ActiveRequest::is_connected()` before and after planning (planner-core's planners are
//! synchronous) and skips the work or the answer. Shutdown: the binary sets the shutdown
//! flag on SIGINT/SIGTERM; queued requests are answered `ServerShuttingDown`, running ones
//! finish, then the ports close.

use crate::engine::{Engine, FrameWords, MapCells, MapUpdate, NoFrame, Scratch};
use crate::services::{self, Limits, LocalSvc, Names, Svc};
use crate::wire::{
    Failure, LAYOUT_ROWS, MapHeader, PlanAnswer, PlanRequest, PlanResponseHeader, ServiceError,
    Waypoint, first_disagreement, frame_grid, grid_from_bits,
};
use iceoryx2::active_request::ActiveRequest;
use iceoryx2::identifiers::UniquePublisherId;
use iceoryx2::node::Node;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::sample::Sample;
use iceoryx2::service::Service;
use iceoryx2::service::port_factory::PortFactory;
use planner_core::grid::GridBuf;
use std::cell::Cell;
use std::collections::HashMap;
use std::rc::Rc;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, mpsc};
use std::time::{Duration, Instant};

/// How the server waits for work.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WaitMode {
    /// Spin on the ports (lowest latency, burns a core).
    Busy,
    /// Spin briefly, then sleep on the wake event (or the housekeeping tick).
    Blocking,
}

/// Server configuration.
#[derive(Clone, Debug)]
pub struct ServerConfig {
    /// Service names.
    pub names: Names,
    /// Service limits.
    pub limits: Limits,
    /// Planning threads; `1` plans inline on the port thread.
    pub workers: usize,
    /// Largest map accepted, in cells (`planner-server --max-cells`); larger maps are
    /// refused with [`ServiceError::MapTooLarge`], logged, and the answer names the limit.
    pub max_cells: usize,
    /// Map ids kept at once.
    pub max_maps: usize,
    /// Waiting mode.
    pub mode: WaitMode,
    /// Longest sleep between housekeeping checks (shutdown flag) in blocking mode.
    pub tick: Duration,
    /// How long to spin before sleeping in blocking mode.
    pub spin: Duration,
    /// Check that the two layouts of every received frame agree (`--verify-maps`; a frame
    /// whose layouts disagree is rejected with [`ServiceError::InvalidRequest`] and logged
    /// with the first cell that differs). Costs a transposition of the map per frame.
    pub verify_maps: bool,
}

impl Default for ServerConfig {
    fn default() -> Self {
        ServerConfig {
            names: Names::new("planner"),
            limits: Limits::default(),
            workers: 1,
            max_cells: crate::wire::DEFAULT_MAX_CELLS,
            max_maps: 16,
            mode: WaitMode::Blocking,
            tick: Duration::from_millis(50),
            spin: Duration::from_micros(200),
            verify_maps: false,
        }
    }
}

type Active<S> = ActiveRequest<S, PlanRequest, (), [Waypoint], PlanResponseHeader>;
type Jobs<S> = Arc<Mutex<mpsc::Receiver<(Active<S>, Option<Instant>)>>>;

/// State shared by the port thread and the workers.
struct Shared<S: Service, F = NoFrame> {
    node: Node<S>,
    names: Names,
    limits: Limits,
    engine: Arc<Engine<F>>,
    wakers: Mutex<HashMap<u64, Waker<S>>>,
    served: AtomicU64,
    cancelled: AtomicU64,
}

struct Waker<S: Service> {
    service: services::EventService<S>,
    notifier: Notifier<S>,
}

/// Runs the server until `shutdown` becomes true.
pub fn run(config: &ServerConfig, shutdown: &AtomicBool) -> anyhow::Result<()> {
    if config.workers > 1 {
        // Active requests cross to the workers: thread-safe ports.
        let engine = Arc::new(Engine::new(config.max_cells, config.max_maps));
        serve_ports::<Svc, NoFrame>(config, engine, shutdown, Some(spawn_workers))
    } else {
        // One thread owns everything: single-threaded ports, no mutex per port call, and
        // map frames planned on where they lie. The engine then holds frames of this
        // thread's ports and stays on it; the `Arc` is for the other flavour's workers.
        #[allow(clippy::arc_with_non_send_sync)]
        let engine = Arc::new(Engine::keeping_frames(config.max_cells, config.max_maps));
        serve_ports::<LocalSvc, Held>(config, engine, shutdown, None)
    }
}

/// Like [`run`], planning with an engine shared with another front end (the Zenoh one,
/// `planner-server --transport both`): every received frame is copied into the engine's
/// own memory (a frame kept in place would tie the engine to this thread). The engine's
/// limits are used; `config.max_cells` and `config.max_maps` are ignored.
pub fn run_with_engine(
    config: &ServerConfig,
    engine: Arc<Engine>,
    shutdown: &AtomicBool,
) -> anyhow::Result<()> {
    let config = ServerConfig {
        max_cells: engine.store.max_cells(),
        max_maps: engine.store.max_maps(),
        ..config.clone()
    };
    if config.workers > 1 {
        serve_ports::<Svc, NoFrame>(&config, engine, shutdown, Some(spawn_workers))
    } else {
        serve_ports::<LocalSvc, NoFrame>(&config, engine, shutdown, None)
    }
}

fn spawn_workers(
    shared: &Arc<Shared<Svc>>,
    jobs: &Jobs<Svc>,
    workers: usize,
) -> std::io::Result<Vec<std::thread::JoinHandle<()>>> {
    (0..workers)
        .map(|i| {
            let jobs = jobs.clone();
            let shared = shared.clone();
            std::thread::Builder::new()
                .name(format!("planner-worker-{i}"))
                .spawn(move || worker(&shared, &jobs))
        })
        .collect()
}

/// Starts `workers` planning threads on the job queue.
type SpawnWorkers<S, F> =
    fn(&Arc<Shared<S, F>>, &Jobs<S>, usize) -> std::io::Result<Vec<std::thread::JoinHandle<()>>>;

/// A received map frame.
type MapSample<S> = Sample<S, [u32], MapHeader>;

/// How a server on ports of flavour `S` keeps received frames of both layouts.
trait Keep<S: Service>: FrameWords + Sized {
    /// The frame kept as it is, or handed back to be copied.
    fn keep(sample: MapSample<S>, holds: &mut Holds) -> Result<Self, MapSample<S>>;
}

impl<S: Service> Keep<S> for NoFrame {
    fn keep(sample: MapSample<S>, _: &mut Holds) -> Result<Self, MapSample<S>> {
        Err(sample)
    }
}

/// A frame a server planning inline keeps while its map version is current.
struct Held {
    sample: MapSample<LocalSvc>,
    _count: HeldCount,
}

impl FrameWords for Held {
    fn words(&self) -> &[u32] {
        self.sample.payload()
    }
}

impl Keep<LocalSvc> for Held {
    fn keep(sample: MapSample<LocalSvc>, holds: &mut Holds) -> Result<Self, MapSample<LocalSvc>> {
        match holds.hold(sample.origin()) {
            Some(count) => Ok(Held {
                sample,
                _count: count,
            }),
            None => Err(sample),
        }
    }
}

/// The frames kept per publisher: iceoryx2 lets a subscriber borrow at most `limit`
/// samples from one publisher at once, and one must stay free to receive the next frame.
struct Holds {
    limit: usize,
    per_publisher: HashMap<UniquePublisherId, Rc<Cell<usize>>>,
}

impl Holds {
    /// A count for one more kept frame of `publisher`, or `None` when it would leave no
    /// borrow free.
    fn hold(&mut self, publisher: UniquePublisherId) -> Option<HeldCount> {
        // Forget publishers none of whose frames is kept any more.
        self.per_publisher.retain(|_, c| c.get() > 0);
        let count = self.per_publisher.entry(publisher).or_default();
        if count.get() + 1 >= self.limit {
            return None;
        }
        count.set(count.get() + 1);
        Some(HeldCount(count.clone()))
    }
}

/// One kept frame in its publisher's count (released with the frame).
struct HeldCount(Rc<Cell<usize>>);

impl Drop for HeldCount {
    fn drop(&mut self) {
        self.0.set(self.0.get().saturating_sub(1));
    }
}

/// The serving loop on ports of flavour `S`, keeping frames as `F`; with `spawn`,
/// `config.workers` threads plan, without it the port thread plans each request inline.
fn serve_ports<S: Service, F: Keep<S>>(
    config: &ServerConfig,
    engine: Arc<Engine<F>>,
    shutdown: &AtomicBool,
    spawn: Option<SpawnWorkers<S, F>>,
) -> anyhow::Result<()> {
    let node = services::node::<S>("planner-server")?;
    let cleaned = services::cleanup_dead_nodes(&node);
    log::info!(
        "planner-server: prefix {:?}, {} worker(s), {:?} mode, max map {} cells, {} map ids, {} clients; removed {} dead node(s)",
        config.names.prefix,
        config.workers,
        config.mode,
        config.max_cells,
        config.max_maps,
        config.limits.max_clients,
        cleaned
    );
    let (map_service, recorded) =
        services::map_service_for_server(&node, &config.names, &config.limits, config.max_cells)?;
    if recorded != Some(config.max_cells as u64) {
        // Clients refuse maps above the recorded limit before sending; this server decides.
        log::warn!(
            "the map service {:?} was created before this server with {}; clients check maps against that, this server accepts up to {} cells",
            config.names.prefix,
            recorded.map_or("no size limit recorded".to_string(), |c| format!(
                "a limit of {c} cells"
            )),
            config.max_cells
        );
    }
    let subscriber = map_service
        .subscriber_builder()
        .create()
        .map_err(|e| anyhow::anyhow!("map subscriber: {e:?}"))?;
    let mut holds = Holds {
        limit: services::map_borrow_limit(&map_service),
        per_publisher: HashMap::new(),
    };
    // The wake event first: a client that finds the plan service finds it too.
    let wake_service = services::event_service(&node, &config.names.plan_wake()?, &config.limits)?;
    let listener = wake_service
        .listener_builder()
        .create()
        .map_err(|e| anyhow::anyhow!("wake listener: {e:?}"))?;
    let plan_service = services::plan_service_create(&node, &config.names, &config.limits)?;
    let server = plan_service
        .server_builder()
        .initial_max_slice_len(services::PATH_SLICE_CAPACITY)
        .create()
        .map_err(|e| anyhow::anyhow!("plan server port: {e:?}"))?;

    // With kept frames (single-threaded ports) `Shared` is neither `Send` nor `Sync` and
    // stays on this thread; the `Arc` is for the worker pool of the other flavour.
    #[allow(clippy::arc_with_non_send_sync)]
    let shared = Arc::new(Shared {
        node,
        names: config.names.clone(),
        limits: config.limits.clone(),
        engine,
        wakers: Mutex::new(HashMap::new()),
        served: AtomicU64::new(0),
        cancelled: AtomicU64::new(0),
    });

    let (tx, rx) = mpsc::channel::<(Active<S>, Option<Instant>)>();
    let rx = Arc::new(Mutex::new(rx));
    let handles = match spawn {
        Some(spawn) => spawn(&shared, &rx, config.workers)?,
        None => Vec::new(),
    };
    let workers = handles.len().max(1);
    let mut scratch = Scratch::default();
    log::info!("planner-server ready");

    // Set on the first idle pass (only blocking mode reads it): no clock read per request.
    let mut idle_since: Option<Instant> = None;
    let mut passes = 0u32;
    while !shutdown.load(Ordering::Relaxed) {
        passes = passes.wrapping_add(1);
        // Every request drains the maps first (below), so a spinning server may look for
        // maps less often and spend its passes on the request port: a request then waits
        // less for the pass that sees it. A blocking server sleeps between passes.
        let look_for_maps =
            config.mode == WaitMode::Blocking || passes.is_multiple_of(BUSY_PASSES_PER_MAP_POLL);
        let mut busy = look_for_maps && drain_maps(&shared, &subscriber, &mut holds, config)?;
        while let Some(active) = server
            .receive()
            .map_err(|e| anyhow::anyhow!("receive: {e:?}"))?
        {
            busy = true;
            // Only a request with a deadline needs the time of its receipt.
            let now = (active.payload().deadline_us > 0).then(Instant::now);
            // A map published before this request may have landed after the drain above.
            drain_maps(&shared, &subscriber, &mut holds, config)?;
            if workers > 1 {
                if tx.send((active, now)).is_err() {
                    anyhow::bail!("worker pool stopped");
                }
            } else {
                serve(&shared, &mut scratch, active, now);
            }
        }
        if busy {
            idle_since = None;
            continue;
        }
        match config.mode {
            WaitMode::Busy => std::hint::spin_loop(),
            WaitMode::Blocking => {
                if idle_since.get_or_insert_with(Instant::now).elapsed() >= config.spin {
                    // Any notification sent after our last receive() is still pending in the
                    // listener, so no wake-up is lost between the check and the wait.
                    if let Err(e) = listener.timed_wait(|_| {}, config.tick) {
                        log::debug!("wake listener: {e:?}");
                    }
                } else {
                    // Yield rather than spin: a client woken by our answer may share this
                    // core, and its next request would wait for our time slice to end.
                    std::thread::yield_now();
                }
            }
        }
    }

    log::info!("shutdown requested: answering queued requests ServerShuttingDown");
    drop(tx);
    for h in handles {
        let _ = h.join();
    }
    let mut refused = 0u64;
    while let Ok(Some(active)) = server.receive() {
        let request = *active.payload();
        let result = PlanAnswer::failed(
            request.request_id,
            Failure::Service(ServiceError::ServerShuttingDown),
        );
        respond(&shared, active, &request, &result);
        refused += 1;
    }
    log::info!(
        "planner-server stopped: {} request(s) served, {} cancelled, {} refused at shutdown",
        shared.served.load(Ordering::Relaxed),
        shared.cancelled.load(Ordering::Relaxed),
        refused
    );
    Ok(())
}

/// How often a busy server's idle passes look for map frames.
const BUSY_PASSES_PER_MAP_POLL: u32 = 16;

/// Stores every map frame waiting in the subscriber; returns whether there was any.
fn drain_maps<S: Service, F: Keep<S>>(
    shared: &Shared<S, F>,
    subscriber: &iceoryx2::port::subscriber::Subscriber<S, [u32], MapHeader>,
    holds: &mut Holds,
    config: &ServerConfig,
) -> anyhow::Result<bool> {
    let mut any = false;
    while let Some(sample) = subscriber
        .receive()
        .map_err(|e| anyhow::anyhow!("map receive: {e:?}"))?
    {
        any = true;
        let frame = *sample.user_header();
        let meta = frame.meta();
        let store = &shared.engine.store;
        if !store.is_newer(&meta) {
            log::debug!(
                "map {} version {} ignored: not newer than the stored one",
                meta.map_id,
                meta.version
            );
            continue;
        }
        let words = sample.payload().len();
        let began = Instant::now();
        let (cells, how) = take_frame(sample, &frame, store.max_cells(), holds, config);
        let decode_us = began.elapsed().as_secs_f32() * 1e6;
        let result = store.update_cells(meta, cells, decode_us);
        match result {
            MapUpdate::Stored => log::info!(
                "map {} version {} stored: {}x{} cells, resolution {} m, origin {:?} ({how} in {:.0} us)",
                meta.map_id,
                meta.version,
                frame.width,
                frame.height,
                meta.resolution,
                meta.origin,
                decode_us
            ),
            MapUpdate::Outdated => log::debug!(
                "map {} version {} ignored: not newer than the stored one",
                meta.map_id,
                meta.version
            ),
            MapUpdate::Rejected(ServiceError::MapTooLarge) => log::warn!(
                "map {} version {} rejected: MapTooLarge: {} x {} = {} cells, this server's limit is {} cells (sides at most 65535); raise it with planner-server --max-cells",
                meta.map_id,
                meta.version,
                frame.width,
                frame.height,
                u64::from(frame.width) * u64::from(frame.height),
                store.max_cells()
            ),
            MapUpdate::Rejected(e) => log::warn!(
                "map {} version {} rejected: {} ({} x {} cells, layout {}, {} words sent{})",
                meta.map_id,
                meta.version,
                e,
                frame.width,
                frame.height,
                frame.layout,
                words,
                if how.is_empty() {
                    String::new()
                } else {
                    format!("; {how}")
                }
            ),
        }
    }
    Ok(any)
}

/// Makes a received frame usable: a rows-only frame is built into a grid (and the sample
/// returned), a frame of both layouts is checked and kept as it is when `F` can, else
/// copied (whole words). The second value says which, for the log.
fn take_frame<S: Service, F: Keep<S>>(
    sample: MapSample<S>,
    frame: &MapHeader,
    max_cells: usize,
    holds: &mut Holds,
    config: &ServerConfig,
) -> (Result<MapCells<F>, ServiceError>, String) {
    let (w, h) = (frame.width as usize, frame.height as usize);
    if let Err(e) = frame.check() {
        return (Err(e), String::new());
    }
    if frame.layout == LAYOUT_ROWS {
        let grid = grid_from_bits(frame.width, frame.height, sample.payload(), max_cells);
        return (grid.map(MapCells::Grid), "built from rows".into());
    }
    if let Err(e) = frame_grid(frame, sample.payload(), max_cells) {
        return (Err(e), String::new());
    }
    if config.verify_maps {
        let (rows, columns) = sample.payload().split_at(frame.words());
        if let Some((x, y)) = first_disagreement(w, h, rows, columns) {
            let detail = format!("its layouts disagree first at cell ({x}, {y})");
            return (Err(ServiceError::InvalidRequest), detail);
        }
    }
    let verified = if config.verify_maps { ", verified" } else { "" };
    match F::keep(sample, holds) {
        Ok(kept) => (
            MapCells::frame(kept, w, h),
            format!("kept in place{verified}"),
        ),
        Err(sample) => {
            let copied = frame_grid(frame, sample.payload(), max_cells).map(GridBuf::from_view);
            (copied.map(MapCells::Grid), format!("copied{verified}"))
        }
    }
}

fn worker(shared: &Shared<Svc>, rx: &Mutex<mpsc::Receiver<(Active<Svc>, Option<Instant>)>>) {
    let mut scratch = Scratch::default();
    loop {
        let job = {
            let rx = rx.lock().unwrap_or_else(|p| p.into_inner());
            rx.recv()
        };
        match job {
            Ok((active, received)) => serve(shared, &mut scratch, active, received),
            Err(_) => return,
        }
    }
}

/// Plans one request and answers it (unless the client gave up).
fn serve<S: Service, F: FrameWords>(
    shared: &Shared<S, F>,
    scratch: &mut Scratch,
    active: Active<S>,
    received: Option<Instant>,
) {
    let request = *active.payload();
    let late = received.is_some_and(|t| t.elapsed() > Duration::from_micros(request.deadline_us));
    let result = if late {
        PlanAnswer::failed(
            request.request_id,
            Failure::Service(ServiceError::DeadlineExceeded),
        )
    } else {
        shared
            .engine
            .handle_in_place(scratch, &request, &mut || !active.is_connected())
    };
    if let Err(f) = &result.outcome {
        log::debug!(
            "request {} (map {} v{}, {:?} -> {:?}, algo {}): {}",
            request.request_id,
            request.map_id,
            request.map_version,
            request.start,
            request.goal,
            request.algorithm,
            f
        );
    }
    if matches!(
        result.outcome,
        Err(Failure::Service(ServiceError::Cancelled))
    ) {
        shared.cancelled.fetch_add(1, Ordering::Relaxed);
        log::info!("request {} cancelled by its client", request.request_id);
        return;
    }
    respond(shared, active, &request, &result);
    shared.served.fetch_add(1, Ordering::Relaxed);
}

fn respond<S: Service, F: FrameWords>(
    shared: &Shared<S, F>,
    active: Active<S>,
    request: &PlanRequest,
    result: &PlanAnswer<'_>,
) {
    if !active.is_connected() {
        shared.cancelled.fetch_add(1, Ordering::Relaxed);
        log::info!(
            "request {}: client gone before the answer",
            request.request_id
        );
        return;
    }
    let header = PlanResponseHeader::new(request, result, shared.engine.store.max_cells());
    let path = match &result.outcome {
        Ok(found) => &found.path[..header.waypoints as usize],
        Err(_) => &[],
    };
    // Only the used waypoints are written into shared memory, straight from the scratch
    // the planner wrote them to.
    let sent = active
        .loan_slice_uninit(path.len())
        .map_err(|e| format!("{e:?}"))
        .and_then(|r| {
            let mut r = r.write_from_fn(|i| Waypoint {
                x: path[i].x,
                y: path[i].y,
            });
            *r.user_header_mut() = header;
            r.send().map_err(|e| format!("{e:?}"))
        });
    if let Err(e) = sent {
        log::warn!("request {}: cannot send response: {e}", request.request_id);
        return;
    }
    drop(active);
    // A client still polling for a while needs no wake-up syscall (2 us of margin for
    // the two processes' readings of the shared wall clock).
    if request.wake_token != 0
        && crate::wire::unix_ns().saturating_add(2_000) >= request.polls_until_ns
    {
        wake(shared, request.wake_token);
    }
}

/// Notifies a blocking client's wake event (opened once per client token, cached).
fn wake<S: Service, F: FrameWords>(shared: &Shared<S, F>, token: u64) {
    let mut wakers = shared.wakers.lock().unwrap_or_else(|p| p.into_inner());
    if !wakers.contains_key(&token) {
        // A new client: forget the events of clients that are gone (no listener left), so
        // that client churn does not pile up open events (descriptors and mappings).
        wakers.retain(|_, w| w.service.dynamic_config().number_of_listeners() > 0);
        if wakers.len() >= 4 * shared.limits.max_clients {
            wakers.clear();
        }
        let opened = shared.names.client_wake(token).and_then(|name| {
            // The client created its event; a token without one is not ours to create.
            let service = services::event_service_open(&shared.node, &name, &shared.limits)?;
            let notifier = service
                .notifier_builder()
                .create()
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
            Ok(Waker { service, notifier })
        });
        match opened {
            Ok(w) => {
                wakers.insert(token, w);
            }
            Err(e) => {
                log::warn!("cannot open wake event of client {token:016x}: {e}");
                return;
            }
        }
    }
    if let Some(w) = wakers.get(&token)
        && let Err(e) = w.notifier.notify()
    {
        log::warn!("cannot wake client {token:016x}: {e:?}");
        wakers.remove(&token);
    }
}

//! The serving loop.
//!
//! One thread owns the iceoryx2 ports: it drains the map subscriber (always before taking
//! requests, so a map published before a request is stored before that request is
//! planned), receives requests and either plans them inline (`workers == 1`, lowest
//! latency) or hands them to a pool of worker threads, each with its own search scratch.
//! The answer goes back through the request's own `ActiveRequest`; a blocking client is
//! then woken through its wake event.
//!
//! Cancellation: a client that gives up drops its `PendingResponse`; the server checks
//! `ActiveRequest::is_connected()` before and after planning (planner-core's planners are
//! synchronous) and skips the work or the answer. Shutdown: the binary sets the shutdown
//! flag on SIGINT/SIGTERM; queued requests are answered `ServerShuttingDown`, running ones
//! finish, then the ports close.

use crate::engine::{Engine, MapUpdate, Scratch};
use crate::services::{self, Limits, LocalSvc, Names, Svc};
use crate::wire::{
    Failure, MapHeader, PlanRequest, PlanResponseHeader, PlanResult, ServiceError, Waypoint,
    grid_from_bits,
};
use iceoryx2::active_request::ActiveRequest;
use iceoryx2::node::Node;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::service::Service;
use iceoryx2::service::port_factory::PortFactory;
use std::collections::HashMap;
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
    /// Largest map accepted, in cells (at most the frame capacity).
    pub max_cells: usize,
    /// Map ids kept at once.
    pub max_maps: usize,
    /// Waiting mode.
    pub mode: WaitMode,
    /// Longest sleep between housekeeping checks (shutdown flag) in blocking mode.
    pub tick: Duration,
    /// How long to spin before sleeping in blocking mode.
    pub spin: Duration,
}

impl Default for ServerConfig {
    fn default() -> Self {
        ServerConfig {
            names: Names::new("planner"),
            limits: Limits::default(),
            workers: 1,
            max_cells: crate::wire::MAP_CAPACITY_CELLS,
            max_maps: 16,
            mode: WaitMode::Blocking,
            tick: Duration::from_millis(50),
            spin: Duration::from_micros(200),
        }
    }
}

type Active<S> = ActiveRequest<S, PlanRequest, (), [Waypoint], PlanResponseHeader>;
type Jobs<S> = Arc<Mutex<mpsc::Receiver<(Active<S>, Option<Instant>)>>>;

/// State shared by the port thread and the workers.
struct Shared<S: Service> {
    node: Node<S>,
    names: Names,
    limits: Limits,
    engine: Engine,
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
        serve_ports::<Svc>(config, shutdown, Some(spawn_workers))
    } else {
        // One thread owns everything: single-threaded ports, no mutex per port call.
        serve_ports::<LocalSvc>(config, shutdown, None)
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
type SpawnWorkers<S> =
    fn(&Arc<Shared<S>>, &Jobs<S>, usize) -> std::io::Result<Vec<std::thread::JoinHandle<()>>>;

/// The serving loop on ports of flavour `S`; with `spawn`, `config.workers` threads plan,
/// without it the port thread plans each request inline.
fn serve_ports<S: Service>(
    config: &ServerConfig,
    shutdown: &AtomicBool,
    spawn: Option<SpawnWorkers<S>>,
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
    let map_service = services::map_service(&node, &config.names, &config.limits)?;
    let subscriber = map_service
        .subscriber_builder()
        .create()
        .map_err(|e| anyhow::anyhow!("map subscriber: {e:?}"))?;
    let plan_service = services::plan_service_create(&node, &config.names, &config.limits)?;
    let server = plan_service
        .server_builder()
        .initial_max_slice_len(services::PATH_SLICE_CAPACITY)
        .create()
        .map_err(|e| anyhow::anyhow!("plan server port: {e:?}"))?;
    let wake_service = services::event_service(&node, &config.names.plan_wake()?, &config.limits)?;
    let listener = wake_service
        .listener_builder()
        .create()
        .map_err(|e| anyhow::anyhow!("wake listener: {e:?}"))?;

    let shared = Arc::new(Shared {
        node,
        names: config.names.clone(),
        limits: config.limits.clone(),
        engine: Engine::new(config.max_cells, config.max_maps),
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
        let mut busy = look_for_maps && drain_maps(&shared, &subscriber)?;
        while let Some(active) = server
            .receive()
            .map_err(|e| anyhow::anyhow!("receive: {e:?}"))?
        {
            busy = true;
            // Only a request with a deadline needs the time of its receipt.
            let now = (active.payload().deadline_us > 0).then(Instant::now);
            // A map published before this request may have landed after the drain above.
            drain_maps(&shared, &subscriber)?;
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
        let result = PlanResult {
            request_id: request.request_id,
            outcome: Err(Failure::Service(ServiceError::ServerShuttingDown)),
            time_us: 0.0,
        };
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
fn drain_maps<S: Service>(
    shared: &Shared<S>,
    subscriber: &iceoryx2::port::subscriber::Subscriber<S, [u32], MapHeader>,
) -> anyhow::Result<bool> {
    let mut any = false;
    while let Some(sample) = subscriber
        .receive()
        .map_err(|e| anyhow::anyhow!("map receive: {e:?}"))?
    {
        any = true;
        let frame = *sample.user_header();
        let meta = frame.meta();
        let began = Instant::now();
        let grid = grid_from_bits(
            frame.width,
            frame.height,
            sample.payload(),
            shared.engine.store.max_cells(),
        );
        drop(sample);
        let result = shared.engine.store.update(meta, grid);
        match result {
            MapUpdate::Stored => log::info!(
                "map {} version {} stored: {}x{} cells, resolution {} m, origin {:?} ({:.0} us)",
                meta.map_id,
                meta.version,
                frame.width,
                frame.height,
                meta.resolution,
                meta.origin,
                began.elapsed().as_secs_f64() * 1e6
            ),
            MapUpdate::Outdated => log::debug!(
                "map {} version {} ignored: not newer than the stored one",
                meta.map_id,
                meta.version
            ),
            MapUpdate::Rejected(e) => log::warn!(
                "map {} version {} rejected: {} ({}x{} cells, limit {})",
                meta.map_id,
                meta.version,
                e,
                frame.width,
                frame.height,
                shared.engine.store.max_cells()
            ),
        }
    }
    Ok(any)
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
fn serve<S: Service>(
    shared: &Shared<S>,
    scratch: &mut Scratch,
    active: Active<S>,
    received: Option<Instant>,
) {
    let request = *active.payload();
    let late = received.is_some_and(|t| t.elapsed() > Duration::from_micros(request.deadline_us));
    let result = if late {
        PlanResult {
            request_id: request.request_id,
            outcome: Err(Failure::Service(ServiceError::DeadlineExceeded)),
            time_us: 0.0,
        }
    } else {
        shared
            .engine
            .handle(scratch, &request, &mut || !active.is_connected())
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

fn respond<S: Service>(
    shared: &Shared<S>,
    active: Active<S>,
    request: &PlanRequest,
    result: &PlanResult,
) {
    if !active.is_connected() {
        shared.cancelled.fetch_add(1, Ordering::Relaxed);
        log::info!(
            "request {}: client gone before the answer",
            request.request_id
        );
        return;
    }
    let header = PlanResponseHeader::new(request, result);
    let path = match &result.outcome {
        Ok(ok) => &ok.path[..header.waypoints as usize],
        Err(_) => &[],
    };
    // Only the used waypoints are written into shared memory.
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
fn wake<S: Service>(shared: &Shared<S>, token: u64) {
    let mut wakers = shared.wakers.lock().unwrap_or_else(|p| p.into_inner());
    if !wakers.contains_key(&token) {
        // A new client: forget the events of clients that are gone (no listener left), so
        // that client churn does not pile up open events (descriptors and mappings).
        wakers.retain(|_, w| w.service.dynamic_config().number_of_listeners() > 0);
        if wakers.len() >= 4 * shared.limits.max_clients {
            wakers.clear();
        }
        let opened = shared.names.client_wake(token).and_then(|name| {
            let service = services::event_service(&shared.node, &name, &shared.limits)?;
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

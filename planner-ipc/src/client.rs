//! The client library: map upload and `plan(request, timeout)` with typed errors.
//!
//! ```no_run
//! use planner_ipc::client::{ClientConfig, PlannerClient};
//! use planner_ipc::wire::{Algorithm, PlanRequest};
//! use std::time::Duration;
//!
//! let mut client = PlannerClient::new(ClientConfig::default())?;
//! let version = client.upload_map_file("warehouse.map".as_ref(), 1)?;
//! client.wait_for_map(1, version, Duration::from_secs(2))?;
//! let request = PlanRequest::new((1, version), [143, 57], [10, 16], Algorithm::ThetaStar);
//! let path = client.plan(&request, Duration::from_millis(500))?;
//! println!("{} waypoints, length {}", path.path.len(), path.length);
//! # Ok::<(), planner_ipc::client::ClientError>(())
//! ```
//!
//! Waiting: [`Wait::Busy`] spins on the response port (lowest latency, burns a core);
//! [`Wait::Blocking`] spins for a short while, then sleeps on the client's own wake event,
//! which the server notifies after answering.

use crate::services::{self, EventService, Limits, LocalSvc, MapService, Names, PlanService};
use crate::wire::{
    DecodeError, Failure, MAP_CAPACITY_CELLS, MapHeader, MapMeta, PlanOk, PlanRequest,
    PlanResponseHeader, RequestKind, ServiceError, Waypoint, WireGrid, pack_map,
};
use iceoryx2::node::Node;
use iceoryx2::port::client::Client;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::update_connections::UpdateConnections;
use iceoryx2::service::Service;
use planner_core::PlanError;
use planner_core::error::MapError;
use planner_core::grid::GridRef;
use std::collections::HashMap;
use std::fmt;
use std::path::Path;
use std::time::{Duration, Instant};

/// How [`PlannerClient::plan`] waits for the answer.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Wait {
    /// Spin on the response port.
    Busy,
    /// Spin for `spin`, then sleep on the wake event.
    Blocking {
        /// How long to spin first.
        spin: Duration,
    },
}

/// Client configuration.
#[derive(Clone, Debug)]
pub struct ClientConfig {
    /// Service names (must match the server's prefix).
    pub names: Names,
    /// Service limits (must match the server's).
    pub limits: Limits,
    /// Waiting mode.
    pub wait: Wait,
    /// Node name (shows in iceoryx2's node list).
    pub node_name: String,
    /// Notify the server's wake event after each request (needed when the server runs in
    /// blocking mode; a busy server polls, so a busy client may skip this syscall).
    pub notify_server: bool,
}

impl Default for ClientConfig {
    fn default() -> Self {
        ClientConfig {
            names: Names::new("planner"),
            limits: Limits::default(),
            wait: Wait::Blocking {
                spin: Duration::from_micros(50),
            },
            node_name: "planner-client".into(),
            notify_server: true,
        }
    }
}

/// Why a client call failed.
#[derive(Debug, Clone, PartialEq)]
pub enum ClientError {
    /// No server serves the plan service.
    NoServer,
    /// No answer within the timeout (the request is withdrawn; the server skips it).
    Timeout,
    /// The planner found no path (Nav2-like code).
    Plan(PlanError),
    /// The service refused the request.
    Service(ServiceError),
    /// A map file could not be parsed.
    InvalidMap(MapError),
    /// The response did not decode.
    BadResponse(DecodeError),
    /// A response for another request arrived (never expected; counted by the load test).
    Mismatch {
        /// The id sent.
        expected: u64,
        /// The id received.
        got: u64,
    },
    /// An I/O or iceoryx2 failure.
    Ipc(String),
}

impl ClientError {
    /// A short name (the JSON `error` field).
    pub fn name(&self) -> &'static str {
        match self {
            ClientError::NoServer => "NoServer",
            ClientError::Timeout => "Timeout",
            ClientError::Plan(e) => e.name(),
            ClientError::Service(e) => e.name(),
            ClientError::InvalidMap(_) => "InvalidMap",
            ClientError::BadResponse(_) => "BadResponse",
            ClientError::Mismatch { .. } => "Mismatch",
            ClientError::Ipc(_) => "Ipc",
        }
    }
}

impl fmt::Display for ClientError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ClientError::NoServer => f.write_str("no planner server is running"),
            ClientError::Timeout => f.write_str("the server did not answer in time"),
            ClientError::Plan(e) => write!(f, "{}: {e}", e.name()),
            ClientError::Service(e) => write!(f, "service error: {e}"),
            ClientError::InvalidMap(e) => write!(f, "invalid map: {e}"),
            ClientError::BadResponse(e) => write!(f, "bad response: {e}"),
            ClientError::Mismatch { expected, got } => {
                write!(f, "response {got} does not match request {expected}")
            }
            ClientError::Ipc(e) => write!(f, "iceoryx2: {e}"),
        }
    }
}

impl std::error::Error for ClientError {}

impl From<Failure> for ClientError {
    fn from(f: Failure) -> Self {
        match f {
            Failure::Plan(e) => ClientError::Plan(e),
            Failure::Service(e) => ClientError::Service(e),
        }
    }
}

fn ipc<E: fmt::Debug>(e: E) -> ClientError {
    ClientError::Ipc(format!("{e:?}"))
}

struct PlanPorts<S: Service> {
    _service: PlanService<S>,
    client: Client<S, PlanRequest, (), [Waypoint], PlanResponseHeader>,
    _wake_service: EventService<S>,
    wake_server: Notifier<S>,
}

struct MapPorts<S: Service> {
    _service: MapService<S>,
    publisher: Publisher<S, [u32], MapHeader>,
    words: Vec<u32>,
}

struct OwnWake<S: Service> {
    token: u64,
    _service: EventService<S>,
    listener: Listener<S>,
}

/// A connection to the planner service (one outstanding request at a time).
///
/// By default its ports are single-threaded ([`LocalSvc`]), the fastest flavour, so the
/// client cannot move to another thread; a `PlannerClient<services::Svc>` (made with
/// [`with_ports`](Self::with_ports)) can.
pub struct PlannerClient<S: Service = LocalSvc> {
    node: Node<S>,
    config: ClientConfig,
    plan: Option<PlanPorts<S>>,
    map: Option<MapPorts<S>>,
    wake: Option<OwnWake<S>>,
    next_id: u64,
    versions: HashMap<u32, u32>,
    last_server_time_us: Option<f32>,
}

impl PlannerClient {
    /// Creates the client's node (and, in blocking mode, its wake event). Connecting to
    /// the server is lazy: a client may start before the server.
    pub fn new(config: ClientConfig) -> Result<Self, ClientError> {
        Self::with_ports(config)
    }
}

impl<S: Service> PlannerClient<S> {
    /// Like [`PlannerClient::new`], with ports of the service flavour `S`.
    pub fn with_ports(config: ClientConfig) -> Result<Self, ClientError> {
        let node =
            services::node(&config.node_name).map_err(|e| ClientError::Ipc(e.to_string()))?;
        let wake = match config.wait {
            Wait::Busy => None,
            Wait::Blocking { .. } => {
                let token = unique_token();
                let name = config
                    .names
                    .client_wake(token)
                    .map_err(|e| ClientError::Ipc(e.to_string()))?;
                let service = services::event_service(&node, &name, &config.limits)
                    .map_err(|e| ClientError::Ipc(e.to_string()))?;
                let listener = service.listener_builder().create().map_err(ipc)?;
                Some(OwnWake {
                    token,
                    _service: service,
                    listener,
                })
            }
        };
        Ok(PlannerClient {
            node,
            config,
            plan: None,
            map: None,
            wake,
            next_id: 1,
            versions: HashMap::new(),
            last_server_time_us: None,
        })
    }

    fn plan_ports(&mut self) -> Result<&PlanPorts<S>, ClientError> {
        if self.plan.is_none() {
            let service =
                services::plan_service_open(&self.node, &self.config.names, &self.config.limits)
                    .map_err(|_| ClientError::NoServer)?;
            let client = service.client_builder().create().map_err(ipc)?;
            let name = self
                .config
                .names
                .plan_wake()
                .map_err(|e| ClientError::Ipc(e.to_string()))?;
            let wake_service = services::event_service(&self.node, &name, &self.config.limits)
                .map_err(|e| ClientError::Ipc(e.to_string()))?;
            let wake_server = wake_service.notifier_builder().create().map_err(ipc)?;
            self.plan = Some(PlanPorts {
                _service: service,
                client,
                _wake_service: wake_service,
                wake_server,
            });
        }
        self.plan.as_ref().ok_or(ClientError::NoServer)
    }

    fn map_ports(&mut self) -> Result<&mut MapPorts<S>, ClientError> {
        if self.map.is_none() {
            let service =
                services::map_service(&self.node, &self.config.names, &self.config.limits)
                    .map_err(|e| ClientError::Ipc(e.to_string()))?;
            let publisher = service
                .publisher_builder()
                .initial_max_slice_len(services::MAP_SLICE_CAPACITY)
                .create()
                .map_err(ipc)?;
            self.map = Some(MapPorts {
                _service: service,
                publisher,
                words: Vec::new(),
            });
        }
        self.map.as_mut().ok_or(ClientError::NoServer)
    }

    /// Publishes a map version. Errors: [`ServiceError::MapTooLarge`] beyond the frame
    /// capacity. The frame stays in the publisher's history, so a server that starts (or
    /// restarts) later still gets it while this client lives.
    pub fn upload_map(&mut self, meta: MapMeta, grid: GridRef<'_>) -> Result<(), ClientError> {
        let ports = self.map_ports()?;
        let mut words = std::mem::take(&mut ports.words);
        let header = pack_map(meta, grid, &mut words).map_err(ClientError::Service);
        let result = header.and_then(|h| self.publish_map(&h, &words));
        if let Some(ports) = self.map.as_mut() {
            ports.words = words;
        }
        result
    }

    /// Publishes a ready-made frame as is (the receiver validates it): only the used
    /// words are copied into shared memory.
    pub fn publish_map(&mut self, header: &MapHeader, words: &[u32]) -> Result<(), ClientError> {
        let ports = self.map_ports()?;
        if words.len() > services::MAP_SLICE_CAPACITY {
            return Err(ClientError::Service(ServiceError::MapTooLarge));
        }
        let sample = ports
            .publisher
            .loan_slice_uninit(words.len())
            .map_err(ipc)?;
        let mut sample = sample.write_from_slice(words);
        *sample.user_header_mut() = *header;
        sample.send().map_err(ipc)?;
        self.versions.insert(header.map_id, header.version);
        Ok(())
    }

    /// Parses a Moving AI `.map` file and publishes it as `map_id` with the next version
    /// this client uses for that id (starting at 1); returns the version.
    pub fn upload_map_file(&mut self, path: &Path, map_id: u32) -> Result<u32, ClientError> {
        let bytes = std::fs::read(path)
            .map_err(|e| ClientError::Ipc(format!("cannot read {}: {e}", path.display())))?;
        let grid = parse_map(&bytes)?;
        let version = self.versions.get(&map_id).map_or(1, |v| v + 1);
        self.upload_map(
            MapMeta {
                map_id,
                version,
                resolution: 1.0,
                origin: [0.0, 0.0],
            },
            grid.view(),
        )?;
        Ok(version)
    }

    /// Waits until the server holds `map_id` at `version` (or reports it rejected, e.g.
    /// [`ServiceError::MapTooLarge`]).
    pub fn wait_for_map(
        &mut self,
        map_id: u32,
        version: u32,
        timeout: Duration,
    ) -> Result<(), ClientError> {
        let deadline = Instant::now() + timeout;
        let mut request = PlanRequest::new(
            (map_id, version),
            [0, 0],
            [0, 0],
            crate::wire::Algorithm::AStar,
        );
        request.kind = RequestKind::MapStatus as u8;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.plan(&request, left) {
                Ok(_) => return Ok(()),
                Err(ClientError::Service(ServiceError::UnknownMap)) if !left.is_zero() => {
                    std::thread::sleep(Duration::from_millis(1));
                }
                Err(ClientError::NoServer) if !left.is_zero() => {
                    std::thread::sleep(Duration::from_millis(10));
                }
                Err(e) => return Err(e),
            }
        }
    }

    /// Sends one request and waits at most `timeout` for its answer. The request's
    /// `request_id` and `wake_token` are filled in by the client.
    pub fn plan(
        &mut self,
        request: &PlanRequest,
        timeout: Duration,
    ) -> Result<PlanOk, ClientError> {
        let (response, _) = self.plan_raw(request, timeout)?;
        Ok(response)
    }

    /// The server-side time (µs) of the last answered request, also when it was an error.
    pub fn last_server_time_us(&self) -> Option<f32> {
        self.last_server_time_us
    }

    /// Like [`plan`](Self::plan), also returning the server-side planning time (µs).
    pub fn plan_raw(
        &mut self,
        request: &PlanRequest,
        timeout: Duration,
    ) -> Result<(PlanOk, f32), ClientError> {
        let began = Instant::now();
        self.last_server_time_us = None;
        // A server that (re)started since the last call gets the current maps first.
        if let Some(map) = &self.map {
            let _ = map.publisher.update_connections();
        }
        let mut request = *request;
        request.request_id = self.next_id;
        self.next_id += 1;
        request.wake_token = self.wake.as_ref().map_or(0, |w| w.token);
        let wait = self.config.wait;
        let notify = self.config.notify_server;
        let ports = self.plan_ports()?;
        let deadline = began + timeout;
        let spin_until = match wait {
            Wait::Busy => deadline,
            Wait::Blocking { spin } => {
                // Wall clock first, then the monotonic one: the client polls at least until
                // the wall-clock time it announces, so an answer sent before it needs no
                // wake-up. (A busy client never sleeps: no wall clock read, 0 announced.)
                let wall = crate::wire::unix_ns();
                request.polls_until_ns = wall.saturating_add(spin.as_nanos() as u64);
                Instant::now() + spin
            }
        };
        let pending = ports.client.send_copy(request).map_err(ipc)?;
        if pending.number_of_server_connections() == 0 {
            return Err(ClientError::NoServer);
        }
        if notify {
            let _ = ports.wake_server.notify();
        }
        let mut polls = 0u32;
        loop {
            if let Some(response) = pending.receive().map_err(ipc)? {
                let header = response.user_header();
                if header.request_id != request.request_id {
                    return Err(ClientError::Mismatch {
                        expected: request.request_id,
                        got: header.request_id,
                    });
                }
                let result = header
                    .decode(response.payload())
                    .map_err(ClientError::BadResponse)?;
                self.last_server_time_us = Some(result.time_us);
                return match result.outcome {
                    Ok(ok) => Ok((ok, result.time_us)),
                    Err(f) => Err(f.into()),
                };
            }
            polls = polls.wrapping_add(1);
            if wait == Wait::Busy && !polls.is_multiple_of(BUSY_POLLS_PER_CLOCK_READ) {
                // A clock read costs about as much as a poll on the VM: reading it on every
                // poll would delay noticing the answer.
                std::hint::spin_loop();
                continue;
            }
            let now = Instant::now();
            if now >= deadline {
                // Dropping `pending` tells the server we gave up.
                return Err(ClientError::Timeout);
            }
            if now < spin_until {
                if matches!(wait, Wait::Blocking { .. }) {
                    // A server woken by our notification often runs on this core (the
                    // scheduler's wake affinity): spinning would keep it off until we sleep.
                    std::thread::yield_now();
                } else {
                    std::hint::spin_loop();
                }
            } else if let Some(w) = &self.wake {
                // Capped, so that even a missed wake-up costs at most 10 ms.
                let left = (deadline - now).min(Duration::from_millis(10));
                w.listener.timed_wait(|_| {}, left).map_err(ipc)?;
            } else {
                std::hint::spin_loop();
            }
        }
    }
}

/// How many polls a busy client makes between two checks of its deadline.
const BUSY_POLLS_PER_CLOCK_READ: u32 = 16;

/// Parses a Moving AI map into the wire grid: too large is [`ServiceError::MapTooLarge`].
pub fn parse_map(bytes: &[u8]) -> Result<Box<WireGrid>, ClientError> {
    match WireGrid::parse_movingai(bytes) {
        Ok(g) => Ok(Box::new(g)),
        Err(MapError::CapacityExceeded { .. }) => {
            Err(ClientError::Service(ServiceError::MapTooLarge))
        }
        Err(e) => Err(ClientError::InvalidMap(e)),
    }
}

/// A process-unique token for the wake event.
fn unique_token() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as u64);
    let pid = std::process::id() as u64;
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    (pid << 40) ^ (nanos & 0xff_ffff_ffff) ^ (n << 20) | 1
}

const _: () = assert!(MAP_CAPACITY_CELLS >= 340 * 164);

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
    DecodeError, Failure, LAYOUT_ROWS_AND_COLUMNS, MapFacts, MapHeader, MapMeta, PlanOk,
    PlanRequest, PlanResponseHeader, PlanView, ServiceError, Waypoint, decode_status, frame_header,
    write_grid,
};
use iceoryx2::node::Node;
use iceoryx2::port::client::Client;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::update_connections::UpdateConnections;
use iceoryx2::sample_mut::SampleMut;
use iceoryx2::service::Service;
use planner_core::PlanError;
use planner_core::error::MapError;
use planner_core::grid::{GridBuf, GridMut, GridRef, MAX_SIDE, words_for};
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
    /// A map over the service's size limit: refused by this client before sending (the
    /// limit the map service was created with) or by the server (its `--max-cells`). The
    /// message names the limit and the flag that raises it.
    MapTooLarge(MapTooLarge),
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
            ClientError::MapTooLarge(_) => "MapTooLarge",
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
            ClientError::MapTooLarge(e) => e.fmt(f),
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

/// Who refused a map that is too large.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refusal {
    /// This client, before sending: the map exceeds the limit the map service was created
    /// with (by the server, from its `--max-cells`).
    Client,
    /// The server (which logs it too).
    Server,
}

/// A map over the planner service's size limit, with the limit and what raises it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MapTooLarge {
    /// The map's width and height in cells, when known (this client uploaded it).
    pub size: Option<(u32, u32)>,
    /// The limit in cells, when known (servers before this change do not report it).
    pub max_cells: Option<u64>,
    /// Who refused it.
    pub refused_by: Refusal,
}

impl fmt::Display for MapTooLarge {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let whose = match self.refused_by {
            Refusal::Client => "the planner service's limit",
            Refusal::Server => "the planner server's limit",
        };
        match self.size {
            Some((w, h)) if w as usize > MAX_SIDE || h as usize > MAX_SIDE => {
                return write!(
                    f,
                    "map {w} x {h} has a side beyond {MAX_SIDE} cells, the most a map frame carries"
                );
            }
            Some((w, h)) => write!(
                f,
                "map {w} x {h} ({} cells) exceeds {whose}",
                u64::from(w) * u64::from(h)
            )?,
            None => write!(f, "the map exceeds {whose}")?,
        }
        if let Some(max) = self.max_cells {
            write!(f, " of {max} cells")?;
            let side = (max as f64).sqrt() as u64;
            if side * side == max {
                write!(f, " ({side} x {side})")?;
            }
        }
        match self.size {
            Some((w, h)) => write!(
                f,
                "; start planner-server with --max-cells {} or more to accept it",
                u64::from(w) * u64::from(h)
            ),
            None => f.write_str("; raise it with planner-server --max-cells"),
        }?;
        if self.refused_by == Refusal::Client {
            f.write_str(" (not sent)")?;
        }
        Ok(())
    }
}

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
    /// The limit (cells) the map service was created with, if it records one.
    max_cells: Option<u64>,
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
    /// Per map id: the last version this client published and its size.
    uploads: HashMap<u32, Upload>,
    last_server_time_us: Option<f32>,
    /// What the last answer said of its map id (see [`PlanResponseHeader::map`]).
    last_map: Option<MapFacts>,
}

#[derive(Clone, Copy)]
struct Upload {
    version: u32,
    width: u32,
    height: u32,
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
            uploads: HashMap::new(),
            last_server_time_us: None,
            last_map: None,
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
            let publisher =
                services::map_publisher(&service).map_err(|e| ClientError::Ipc(e.to_string()))?;
            self.map = Some(MapPorts {
                max_cells: services::recorded_max_cells(&service),
                _service: service,
                publisher,
            });
        }
        self.map.as_mut().ok_or(ClientError::NoServer)
    }

    /// The largest map (cells) the map service takes, as recorded by the server that
    /// created it; `None` when it records none (created by a client or an older server:
    /// the server then checks alone). Opens the map service.
    pub fn map_limit(&mut self) -> Result<Option<u64>, ClientError> {
        Ok(self.map_ports()?.max_cells)
    }

    /// Publishes a map version copied from `grid`: a [`MapLoan`] of its size, the grid
    /// written into it ([`write_grid`]: whole rows of words, then the column layout rebuilt
    /// by 32 x 32 transpositions, since planner-core lends a `GridRef`'s cells only through
    /// reads), then published. A map over the limit the map service was created with is
    /// refused before anything is sent ([`ClientError::MapTooLarge`]). The frame stays in
    /// the publisher's history, so a server that starts (or restarts) later still gets it
    /// while this client lives. To skip the copy, write the map into a
    /// [`loan_map`](Self::loan_map) in the first place.
    pub fn upload_map(&mut self, meta: MapMeta, grid: GridRef<'_>) -> Result<(), ClientError> {
        let mut loan = self.loan_map(meta, grid.width(), grid.height())?;
        write_grid(grid, &mut loan.grid())
            .map_err(|e| ClientError::Ipc(format!("cannot write the map into its frame: {e}")))?;
        loan.publish()
    }

    /// Lends a map frame of `width x height` cells in shared memory, all free, for the
    /// caller to write in place ([`MapLoan::grid`] is a `GridMut` over it, keeping both
    /// layouts in step) and publish ([`MapLoan::publish`]) without a copy: the server plans
    /// on the same memory. Sides must be 1..=65535 ([`ClientError::InvalidMap`] for a zero
    /// side) and the map within the limit the map service was created with
    /// ([`ClientError::MapTooLarge`], nothing loaned). Loaning zeroes the frame (both
    /// layouts: 4 MiB for 4096 x 4096 cells). One loan at a time; dropping it unpublished
    /// returns the memory.
    ///
    /// ```no_run
    /// # use planner_ipc::client::{ClientConfig, PlannerClient};
    /// # use planner_ipc::wire::MapMeta;
    /// let mut client = PlannerClient::new(ClientConfig::default())?;
    /// let meta = MapMeta { map_id: 1, version: 1, resolution: 0.05, origin: [0.0, 0.0] };
    /// let mut loan = client.loan_map(meta, 4096, 4096)?;
    /// loan.grid().fill_rows(|y, words| if y % 5 < 2 { words.fill(u32::MAX) }).unwrap();
    /// loan.publish()?;
    /// # Ok::<(), planner_ipc::client::ClientError>(())
    /// ```
    pub fn loan_map(
        &mut self,
        meta: MapMeta,
        width: usize,
        height: usize,
    ) -> Result<MapLoan<'_, S>, ClientError> {
        if width == 0 || height == 0 {
            return Err(ClientError::InvalidMap(MapError::EmptyMap));
        }
        let header = frame_header(meta, width, height, LAYOUT_ROWS_AND_COLUMNS);
        let ports = self.map_ports()?;
        let cells = u64::from(header.width) * u64::from(header.height);
        let over_limit = ports.max_cells.is_some_and(|max| cells > max);
        if over_limit || width > MAX_SIDE || height > MAX_SIDE {
            return Err(ClientError::MapTooLarge(MapTooLarge {
                size: Some((header.width, header.height)),
                max_cells: ports.max_cells,
                refused_by: Refusal::Client,
            }));
        }
        let words = words_for(width, height);
        let mut sample = ports
            .publisher
            .loan_slice_uninit(2 * words)
            .map_err(ipc)?
            .write_from_fn(|_| 0);
        *sample.user_header_mut() = header;
        Ok(MapLoan {
            sample,
            words,
            header,
            uploads: &mut self.uploads,
        })
    }

    /// Publishes a ready-made frame as is (the receiver validates it): the words are
    /// copied once, into the loaned shared-memory slice.
    pub fn publish_map(&mut self, header: &MapHeader, words: &[u32]) -> Result<(), ClientError> {
        let ports = self.map_ports()?;
        let sample = ports
            .publisher
            .loan_slice_uninit(words.len())
            .map_err(ipc)?;
        let mut sample = sample.write_from_slice(words);
        *sample.user_header_mut() = *header;
        sample.send().map_err(ipc)?;
        self.record_upload(header);
        Ok(())
    }

    fn record_upload(&mut self, header: &MapHeader) {
        record_upload(&mut self.uploads, header);
    }

    /// Parses a Moving AI `.map` file and publishes it as `map_id` with the next version
    /// this client uses for that id (starting at 1); returns the version. A file declaring
    /// more cells than the map service's limit is refused from its header
    /// ([`ClientError::MapTooLarge`]).
    pub fn upload_map_file(&mut self, path: &Path, map_id: u32) -> Result<u32, ClientError> {
        let bytes = std::fs::read(path)
            .map_err(|e| ClientError::Ipc(format!("cannot read {}: {e}", path.display())))?;
        let limit = self.map_limit()?;
        let max_cells = limit.map_or(usize::MAX, |c| usize::try_from(c).unwrap_or(usize::MAX));
        let grid = parse_map_limited(&bytes, max_cells).map_err(|e| match e {
            ClientError::MapTooLarge(m) => ClientError::MapTooLarge(MapTooLarge {
                max_cells: limit,
                ..m
            }),
            other => other,
        })?;
        let version = self.next_version(map_id, Duration::from_secs(1));
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

    /// The newest version of `map_id` the server holds (`0`: none), asked with a map-status
    /// request; [`ClientError::NoServer`] when no server runs.
    pub fn held_version(&mut self, map_id: u32, timeout: Duration) -> Result<u32, ClientError> {
        let request = PlanRequest::map_status((map_id, 0));
        match self.plan_in_place(&request, timeout, |_| ()) {
            // Version 0 is never held: any answer but these says what is.
            Ok(_) | Err(ClientError::Service(_)) => {}
            Err(e) => return Err(e),
        }
        Ok(self.last_map.map_or(0, |m| m.version))
    }

    /// A version for the next upload of `map_id`: above the server's (when one answers
    /// within `timeout`) and this client's own uploads, so that a new map under an id another
    /// process used is not ignored as outdated.
    pub fn next_version(&mut self, map_id: u32, timeout: Duration) -> u32 {
        let own = self.uploads.get(&map_id).map_or(0, |u| u.version);
        let held = self.held_version(map_id, timeout).unwrap_or(0);
        own.max(held).saturating_add(1)
    }

    /// Waits until the server holds `map_id` at `version` (or reports it rejected, e.g.
    /// [`ServiceError::MapTooLarge`]).
    pub fn wait_for_map(
        &mut self,
        map_id: u32,
        version: u32,
        timeout: Duration,
    ) -> Result<MapFacts, ClientError> {
        let deadline = Instant::now() + timeout;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            match self.map_status(map_id, version, left) {
                Ok(facts) => return Ok(facts),
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

    /// Asks once whether the server holds `map_id` at `version`: its size and how long the
    /// server took to build its grid, or the map error
    /// ([`ServiceError::UnknownMap`], [`ServiceError::StaleMapVersion`], a rejection).
    pub fn map_status(
        &mut self,
        map_id: u32,
        version: u32,
        timeout: Duration,
    ) -> Result<MapFacts, ClientError> {
        let request = PlanRequest::map_status((map_id, version));
        let (facts, _) = self.plan_in_place(&request, timeout, |view| view.header().map())?;
        facts.ok_or(ClientError::BadResponse(DecodeError::BadPath))
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
        self.plan_in_place(request, timeout, |view| view.to_owned())
    }

    /// Like [`plan_raw`](Self::plan_raw), handing `read` the answer where it arrived: its
    /// waypoints are read in shared memory, not copied (the answer is released when `read`
    /// returns).
    pub fn plan_in_place<T>(
        &mut self,
        request: &PlanRequest,
        timeout: Duration,
        read: impl FnOnce(PlanView<'_>) -> T,
    ) -> Result<(T, f32), ClientError> {
        let began = Instant::now();
        self.last_server_time_us = None;
        self.last_map = None;
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
                let status = decode_status(header.status).ok_or(ClientError::BadResponse(
                    DecodeError::UnknownStatus(header.status),
                ))?;
                self.last_server_time_us = Some(header.time_us);
                self.last_map = header.map();
                return match status {
                    Ok(()) => {
                        let view = PlanView::new(header, response.payload())
                            .map_err(ClientError::BadResponse)?;
                        Ok((read(view), header.time_us))
                    }
                    Err(Failure::Service(ServiceError::MapTooLarge)) => {
                        Err(ClientError::MapTooLarge(MapTooLarge {
                            // The size of the map named, if this client uploaded it.
                            size: self
                                .uploads
                                .get(&request.map_id)
                                .filter(|u| u.version == request.map_version)
                                .map(|u| (u.width, u.height)),
                            max_cells: Some(header.max_cells),
                            refused_by: Refusal::Server,
                        }))
                    }
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

fn record_upload(uploads: &mut HashMap<u32, Upload>, header: &MapHeader) {
    uploads.insert(
        header.map_id,
        Upload {
            version: header.map_version,
            width: header.width,
            height: header.height,
        },
    );
}

/// A map frame loaned in shared memory ([`PlannerClient::loan_map`]): write the map into
/// it in place, then [`publish`](Self::publish) it; the server plans on this memory.
///
/// The frame holds the map twice, row-major and column-major (see
/// [`MapHeader`]): [`grid`](Self::grid) writes both at once. A
/// caller writing raw words through [`words_mut`](Self::words_mut) must write both layouts
/// of the same map; the server does not check that they agree unless it runs with
/// `--verify-maps`.
pub struct MapLoan<'a, S: Service> {
    sample: SampleMut<S, [u32], MapHeader>,
    words: usize,
    header: MapHeader,
    uploads: &'a mut HashMap<u32, Upload>,
}

impl<S: Service> MapLoan<'_, S> {
    /// The frame's header (its layout is
    /// [`LAYOUT_ROWS_AND_COLUMNS`]).
    pub fn header(&self) -> &MapHeader {
        &self.header
    }

    /// The grid in the frame, mutable: writes keep both layouts in step
    /// (`GridMut::fill_rows` writes whole rows, then rebuilds the columns).
    pub fn grid(&mut self) -> GridMut<'_> {
        let (w, h) = (self.header.width as usize, self.header.height as usize);
        let (rows, columns) = self.words_mut();
        // loan_map checked the sides, and the frame holds both layouts' words.
        GridMut::from_words(w, h, rows, columns).expect("a loaned frame fits its map")
    }

    /// The raw words: the row-major bits and the column-major bits, `words_for(width,
    /// height)` each (layouts as documented on [`MapHeader`]).
    pub fn words_mut(&mut self) -> (&mut [u32], &mut [u32]) {
        self.sample.payload_mut().split_at_mut(self.words)
    }

    /// Publishes the frame as the map's version named at loan time.
    pub fn publish(self) -> Result<(), ClientError> {
        self.sample.send().map_err(ipc)?;
        record_upload(self.uploads, &self.header);
        Ok(())
    }
}

/// How many polls a busy client makes between two checks of its deadline.
const BUSY_POLLS_PER_CLOCK_READ: u32 = 16;

/// Parses a Moving AI map (any size a frame carries: sides up to 65535 cells).
pub fn parse_map(bytes: &[u8]) -> Result<GridBuf, ClientError> {
    parse_map_limited(bytes, usize::MAX)
}

/// Parses a Moving AI map of at most `max_cells` cells; a larger declared size is
/// [`ClientError::MapTooLarge`] before anything is allocated.
fn parse_map_limited(bytes: &[u8], max_cells: usize) -> Result<GridBuf, ClientError> {
    match GridBuf::parse_movingai(bytes, max_cells) {
        Ok(g) => Ok(g),
        Err(MapError::CapacityExceeded { width, height }) => {
            let side = |v: usize| u32::try_from(v).unwrap_or(u32::MAX);
            Err(ClientError::MapTooLarge(MapTooLarge {
                size: Some((side(width), side(height))),
                max_cells: None,
                refused_by: Refusal::Client,
            }))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::server::{self, ServerConfig};
    use std::sync::Arc;
    use std::sync::atomic::AtomicBool;

    fn meta(map_id: u32, version: u32) -> MapMeta {
        MapMeta {
            map_id,
            version,
            resolution: 1.0,
            origin: [0.0; 2],
        }
    }

    /// A server in this process with a limit of 100 cells: the map service records it, the
    /// client refuses a larger map before sending it, the server refuses one sent anyway,
    /// and both errors carry the limit; a map at the limit arrives bit for bit.
    #[test]
    fn maps_over_the_servers_limit_are_refused_with_the_limit() {
        let names = Names::new(&format!("unit-{}-limits", std::process::id()));
        let shutdown = Arc::new(AtomicBool::new(false));
        let config = ServerConfig {
            names: names.clone(),
            max_cells: 100,
            ..ServerConfig::default()
        };
        let stop = shutdown.clone();
        let server = std::thread::spawn(move || server::run(&config, &stop));
        let mut client = PlannerClient::new(ClientConfig {
            names,
            node_name: "unit-limits-client".into(),
            ..ClientConfig::default()
        })
        .unwrap();
        // Wait for the server (it creates the map service with its limit).
        let mut probe = PlanRequest::new((9, 1), [0, 0], [0, 0], crate::wire::Algorithm::AStar);
        probe.kind = crate::wire::RequestKind::MapStatus.code();
        let began = Instant::now();
        while client.plan(&probe, Duration::from_millis(200)) == Err(ClientError::NoServer) {
            assert!(began.elapsed() < Duration::from_secs(10), "no server");
            std::thread::sleep(Duration::from_millis(10));
        }
        assert_eq!(client.map_limit(), Ok(Some(100)));

        // 10 x 10 = 100 cells: accepted, every cell as sent.
        let mut fits = GridBuf::new(10, 10).unwrap();
        for (x, y) in [(0, 0), (9, 9), (3, 7), (7, 3)] {
            fits.set_blocked(x, y, true).unwrap();
        }
        client.upload_map(meta(1, 1), fits.view()).unwrap();
        client.wait_for_map(1, 1, Duration::from_secs(5)).unwrap();
        for i in 0..100 {
            let cell = [i % 10, i / 10];
            let r = PlanRequest::new((1, 1), cell, cell, crate::wire::Algorithm::AStar);
            let blocked = fits.view().is_blocked(cell[0] as isize, cell[1] as isize);
            let got = client.plan(&r, Duration::from_secs(5));
            assert_eq!(got.is_err(), blocked, "{cell:?}: {got:?}");
        }

        // 11 x 10: refused here, nothing sent.
        let over = GridBuf::new(11, 10).unwrap();
        let refused = client.upload_map(meta(2, 1), over.view()).unwrap_err();
        assert_eq!(
            refused,
            ClientError::MapTooLarge(MapTooLarge {
                size: Some((11, 10)),
                max_cells: Some(100),
                refused_by: Refusal::Client,
            })
        );
        assert_eq!(
            refused.to_string(),
            "map 11 x 10 (110 cells) exceeds the planner service's limit of 100 cells (10 x 10); \
             start planner-server with --max-cells 110 or more to accept it (not sent)"
        );
        // Sent anyway as a raw frame: the server refuses it and says its limit.
        let mut words = Vec::new();
        let header = crate::wire::pack_map(meta(2, 1), over.view(), &mut words);
        client.publish_map(&header, &words).unwrap();
        assert_eq!(
            client.wait_for_map(2, 1, Duration::from_secs(5)),
            Err(ClientError::MapTooLarge(MapTooLarge {
                size: Some((11, 10)),
                max_cells: Some(100),
                refused_by: Refusal::Server,
            }))
        );
        // A map named by a request but uploaded by someone else: no size, still the limit.
        let mut other = PlannerClient::new(ClientConfig {
            names: client.config.names.clone(),
            node_name: "unit-limits-other".into(),
            ..ClientConfig::default()
        })
        .unwrap();
        let plan_on_2 = PlanRequest::new((2, 1), [0, 0], [1, 1], crate::wire::Algorithm::AStar);
        let err = other.plan(&plan_on_2, Duration::from_secs(5)).unwrap_err();
        assert_eq!(
            err.to_string(),
            "the map exceeds the planner server's limit of 100 cells (10 x 10); \
             raise it with planner-server --max-cells"
        );

        shutdown.store(true, std::sync::atomic::Ordering::Relaxed);
        server.join().unwrap().unwrap();
    }

    /// Maps written in place into loaned frames are planned on as written, across many
    /// versions and more map ids than the server keeps frames of one publisher (it copies
    /// those): every version is stored, none is stuck behind borrowed frames, and a copied
    /// map plans like a kept one. `upload_map` of a grid gives the same answers.
    #[test]
    fn loaned_frames_are_planned_on_in_place() {
        let names = Names::new(&format!("unit-{}-loans", std::process::id()));
        let shutdown = Arc::new(AtomicBool::new(false));
        let config = ServerConfig {
            names: names.clone(),
            ..ServerConfig::default()
        };
        let stop = shutdown.clone();
        let server = std::thread::spawn(move || server::run(&config, &stop));
        let mut client = PlannerClient::new(ClientConfig {
            names,
            node_name: "unit-loans-client".into(),
            ..ClientConfig::default()
        })
        .unwrap();
        let mut probe = PlanRequest::new((99, 1), [0, 0], [0, 0], crate::wire::Algorithm::AStar);
        probe.kind = crate::wire::RequestKind::MapStatus.code();
        let began = Instant::now();
        while client.plan(&probe, Duration::from_millis(200)) == Err(ClientError::NoServer) {
            assert!(began.elapsed() < Duration::from_secs(10), "no server");
            std::thread::sleep(Duration::from_millis(10));
        }
        // A wall across a 50 x 20 map along row 10, open at column `gap`: which version the
        // server planned on shows in the blocked cells (row layout) and in Theta*'s vertical
        // sight lines (column runs): straight through the gap, bent beside it.
        let (w, h) = (50usize, 20usize);
        let theta = crate::wire::Algorithm::ThetaStar;
        let mut expected = HashMap::new();
        for round in 0..3u32 {
            for map_id in 1..=6u32 {
                let version = round + 1;
                let gap = (map_id as usize * 7 + round as usize * 5) % (w - 2) + 1;
                let mut loan = client.loan_map(meta(map_id, version), w, h).unwrap();
                {
                    let mut grid = loan.grid();
                    for x in (0..w).filter(|&x| x != gap) {
                        grid.set_blocked(x, 10, true).unwrap();
                    }
                }
                let (rows, columns) = loan.words_mut();
                assert!(rows.iter().any(|w| *w != 0) && columns.iter().any(|w| *w != 0));
                loan.publish().unwrap();
                client
                    .wait_for_map(map_id, version, Duration::from_secs(5))
                    .unwrap();
                expected.insert(map_id, (version, gap as i32));
            }
            for (&map_id, &(version, gap)) in &expected {
                let plan = |c: &mut PlannerClient, from: [i32; 2], to: [i32; 2]| {
                    let r = PlanRequest::new((map_id, version), from, to, theta);
                    c.plan(&r, Duration::from_secs(5))
                };
                let through = plan(&mut client, [gap, 0], [gap, 19]).unwrap();
                assert_eq!((through.path.len(), through.length), (2, 19.0), "{map_id}");
                let beside = plan(&mut client, [gap + 1, 0], [gap + 1, 19]).unwrap();
                assert!(beside.length > 19.01, "map {map_id}: {:?}", beside.path);
                assert_eq!(
                    plan(&mut client, [gap + 1, 10], [0, 0]),
                    Err(ClientError::Plan(PlanError::StartOccupied))
                );
            }
        }
        // The same map from a grid (upload_map) answers the same.
        let mut grid = GridBuf::new(w, h).unwrap();
        for x in (0..w).filter(|&x| x != 7) {
            grid.set_blocked(x, 10, true).unwrap();
        }
        client.upload_map(meta(7, 1), grid.view()).unwrap();
        client.wait_for_map(7, 1, Duration::from_secs(5)).unwrap();
        for (x, straight) in [(7, true), (8, false)] {
            let r = PlanRequest::new((7, 1), [x, 0], [x, 19], theta);
            let ok = client.plan(&r, Duration::from_secs(5)).unwrap();
            assert_eq!(ok.path.len() == 2, straight, "{x}: {:?}", ok.path);
        }
        // Loans are checked before anything is loaned.
        assert_eq!(
            client.loan_map(meta(8, 1), 0, 5).err(),
            Some(ClientError::InvalidMap(MapError::EmptyMap))
        );
        assert!(matches!(
            client.loan_map(meta(8, 1), 70_000, 1).err(),
            Some(ClientError::MapTooLarge(_))
        ));
        // A loan dropped unpublished sends nothing.
        drop(client.loan_map(meta(8, 1), 4, 4).unwrap());
        let mut status = PlanRequest::new((8, 1), [0, 0], [0, 0], crate::wire::Algorithm::AStar);
        status.kind = crate::wire::RequestKind::MapStatus.code();
        assert_eq!(
            client.plan(&status, Duration::from_secs(5)),
            Err(ClientError::Service(ServiceError::UnknownMap))
        );
        shutdown.store(true, std::sync::atomic::Ordering::Relaxed);
        server.join().unwrap().unwrap();
    }

    #[test]
    fn parse_refuses_a_side_beyond_a_frame_from_the_header() {
        let err = parse_map(b"type octile\nheight 70000\nwidth 2\nmap\n").unwrap_err();
        assert_eq!(
            err,
            ClientError::MapTooLarge(MapTooLarge {
                size: Some((2, 70000)),
                max_cells: None,
                refused_by: Refusal::Client,
            })
        );
        assert_eq!(
            err.to_string(),
            "map 2 x 70000 has a side beyond 65535 cells, the most a map frame carries"
        );
    }
}

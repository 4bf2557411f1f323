//! The client over Zenoh: `plan(request, timeout)` with typed errors, map upload with the
//! latest version served to planners that missed it.
//!
//! ```no_run
//! use planner_ipc::wire::{Algorithm, MapMeta, PlanRequest};
//! use planner_ipc::zenoh::{ClientConfig, ZenohClient};
//! use std::time::Duration;
//!
//! let mut client = ZenohClient::open(ClientConfig::connect_to("tcp/127.0.0.1:7447"))?;
//! let grid = planner_core::grid::GridBuf::new(64, 64).unwrap();
//! let meta = MapMeta { map_id: 1, version: 1, resolution: 0.05, origin: [0.0, 0.0] };
//! client.upload_map(meta, grid.view())?;
//! client.wait_for_map(1, 1, Duration::from_secs(2))?;
//! let request = PlanRequest::new((1, 1), [0, 0], [60, 40], Algorithm::ThetaStar);
//! let path = client.plan(&request, Duration::from_millis(500))?;
//! println!("{} waypoints, length {}", path.path.len(), path.length);
//! # Ok::<(), planner_ipc::zenoh::ZenohError>(())
//! ```
//!
//! What a caller sees (each a [`ZenohError`] at once or by the deadline, never a hang):
//! no planner alive under the prefix is [`ZenohError::NoPlanner`] at once (liveliness
//! tokens; a direct liveliness query when none is known yet); no router or peer reachable
//! is [`ZenohError::NotConnected`]; a query that ends without an answer (the planner died
//! or the route was lost) is [`ZenohError::PlannerLost`] at once; no answer by the request's
//! deadline plus [`ClientConfig::margin`] is [`ZenohError::Timeout`].
//! [`plan_retrying`](ZenohClient::plan_retrying) resends the same request (same id: the
//! planner answers a repeated request as before, without planning again) after the
//! transient ones until the deadline.

use super::config::{self, SessionKind, ZenohOptions};
use super::keys::Keys;
use super::proto::{self, PlannerInfo, Reassembly};
use crate::client::{MapTooLarge, Refusal};
use crate::wire::{
    DecodeError, Failure, MapFacts, MapMeta, MapMsg, PlanOk, PlanRequest, PlanResult, ServiceError,
    pack_map,
};
use ::zenoh::Wait;
use ::zenoh::handlers::FifoChannelHandler;
use ::zenoh::pubsub::{Publisher, Subscriber};
use ::zenoh::qos::CongestionControl;
use ::zenoh::query::{ConsolidationMode, Query, QueryTarget, Queryable};
use ::zenoh::sample::{Sample, SampleKind};
use planner_core::PlanError;
use planner_core::error::MapError;
use planner_core::grid::{GridRef, MAX_SIDE};
use std::collections::{HashMap, HashSet};
use std::fmt;
use std::sync::{Arc, Mutex, mpsc};
use std::time::{Duration, Instant};

/// How requests travel.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum RequestPath {
    /// A query on the planners' queryable `P/@v1/plan` (Zenoh picks one planner; a planner
    /// or route lost ends the query at once).
    Query,
    /// The publish-subscribe pair: the request published on `P/@v1/req/<zid>/<client>` to
    /// one live planner (by its liveliness token), the answer on this client's
    /// `P/@v1/rep/<client>`; about half the round trip of a query (`docs/zenoh.md`). A
    /// planner lost is noticed when its token goes (checked every 20 ms while waiting).
    Pair,
}

/// Client configuration.
#[derive(Clone, Debug)]
pub struct ClientConfig {
    /// Service prefix (the planners').
    pub prefix: String,
    /// How requests travel.
    pub path: RequestPath,
    /// Mode and endpoints.
    pub options: ZenohOptions,
    /// Added to a request's deadline for the answer's way back: the client waits the
    /// deadline plus this margin.
    pub margin: Duration,
    /// How long to wait for the planners' liveliness tokens when none is known yet (a
    /// liveliness query: it ends as soon as every connected node answered).
    pub probe: Duration,
    /// How long to poll for an answer (yielding the CPU between polls) before sleeping on
    /// it: an answer that arrives meanwhile costs no wake-up.
    pub spin: Duration,
}

impl ClientConfig {
    /// A peer connecting to `endpoint`, prefix `planner`.
    pub fn connect_to(endpoint: &str) -> Self {
        ClientConfig {
            options: ZenohOptions {
                connect: vec![endpoint.to_string()],
                ..ZenohOptions::default()
            },
            ..ClientConfig::default()
        }
    }
}

impl Default for ClientConfig {
    fn default() -> Self {
        ClientConfig {
            prefix: "planner".into(),
            path: RequestPath::Query,
            options: ZenohOptions::default(),
            margin: Duration::from_millis(250),
            probe: Duration::from_millis(500),
            spin: Duration::from_micros(100),
        }
    }
}

/// Why a call over Zenoh failed.
#[derive(Clone, Debug, PartialEq)]
pub enum ZenohError {
    /// No planner is alive under the prefix (no liveliness token), though this client is
    /// connected to the Zenoh network.
    NoPlanner {
        /// The service prefix.
        prefix: String,
    },
    /// No router or peer is reachable.
    NotConnected {
        /// The endpoints this client connects to.
        endpoints: Vec<String>,
    },
    /// The query ended without an answer: the planner that had it died, or the route to
    /// it was lost (a router restarting). Safe to retry (same request id).
    PlannerLost {
        /// The request.
        request_id: u64,
        /// When the query ended, after sending.
        after: Duration,
        /// Planners alive when it ended.
        planners_left: usize,
    },
    /// No answer within the request's deadline plus the margin.
    Timeout {
        /// The request.
        request_id: u64,
        /// How long the client waited.
        waited: Duration,
        /// The request's deadline (its `deadline_us`).
        deadline: Duration,
        /// The margin added.
        margin: Duration,
    },
    /// The planner found no path (Nav2-like code).
    Plan(PlanError),
    /// The service refused the request.
    Service(ServiceError),
    /// A map over the planners' cell limit: refused by this client before sending, or by
    /// a planner.
    MapTooLarge(MapTooLarge),
    /// A map message over the planners' message limit (their map session's
    /// `max_message_size`), refused before sending.
    MapMessageTooLarge {
        /// The map id.
        map_id: u32,
        /// Bytes of the encoded map.
        bytes: usize,
        /// The smallest limit among the planners.
        limit: u64,
    },
    /// The map cannot be sent (a zero side).
    InvalidMap(MapError),
    /// The planner refused the request's bytes (its error reply).
    Refused(String),
    /// An answer that does not decode or breaks the protocol.
    BadAnswer(String),
    /// An answer for another request.
    Mismatch {
        /// The id sent.
        expected: u64,
        /// The id received.
        got: u64,
    },
    /// Zenoh failed (opening a session, declaring, sending).
    Zenoh(String),
}

impl ZenohError {
    /// A short name (the JSON `error` field).
    pub fn name(&self) -> &'static str {
        match self {
            ZenohError::NoPlanner { .. } => "NoPlanner",
            ZenohError::NotConnected { .. } => "NotConnected",
            ZenohError::PlannerLost { .. } => "PlannerLost",
            ZenohError::Timeout { .. } => "Timeout",
            ZenohError::Plan(e) => e.name(),
            ZenohError::Service(e) => e.name(),
            ZenohError::MapTooLarge(_) | ZenohError::MapMessageTooLarge { .. } => "MapTooLarge",
            ZenohError::InvalidMap(_) => "InvalidMap",
            ZenohError::Refused(_) => "Refused",
            ZenohError::BadAnswer(_) => "BadAnswer",
            ZenohError::Mismatch { .. } => "Mismatch",
            ZenohError::Zenoh(_) => "Zenoh",
        }
    }

    /// Whether resending the same request may succeed (the route or the planner may come
    /// back): [`ZenohError::PlannerLost`] and [`ZenohError::NotConnected`].
    pub fn is_transient(&self) -> bool {
        matches!(
            self,
            ZenohError::PlannerLost { .. } | ZenohError::NotConnected { .. }
        )
    }
}

fn ms(d: Duration) -> f64 {
    d.as_secs_f64() * 1e3
}

impl fmt::Display for ZenohError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ZenohError::NoPlanner { prefix } => write!(
                f,
                "no planner is alive under {prefix:?} (no liveliness token {prefix}/@v1/alive/*)"
            ),
            ZenohError::NotConnected { endpoints } => write!(
                f,
                "not connected to any Zenoh router or peer (endpoints {endpoints:?})"
            ),
            ZenohError::PlannerLost {
                request_id,
                after,
                planners_left,
            } => write!(
                f,
                "request {request_id}: no answer, the planner or the route to it was lost after {:.1} ms ({planners_left} planner(s) alive); safe to retry",
                ms(*after)
            ),
            ZenohError::Timeout {
                request_id,
                waited,
                deadline,
                margin,
            } => write!(
                f,
                "request {request_id}: no answer within {:.0} ms (its deadline {:.0} ms plus a {:.0} ms margin)",
                ms(*waited),
                ms(*deadline),
                ms(*margin)
            ),
            ZenohError::Plan(e) => write!(f, "{}: {e}", e.name()),
            ZenohError::Service(e) => write!(f, "service error: {e}"),
            ZenohError::MapTooLarge(e) => e.fmt(f),
            ZenohError::MapMessageTooLarge {
                map_id,
                bytes,
                limit,
            } => write!(
                f,
                "map {map_id} encodes to {bytes} bytes, over the planners' map message limit of {limit} bytes (not sent)"
            ),
            ZenohError::InvalidMap(e) => write!(f, "invalid map: {e}"),
            ZenohError::Refused(why) => write!(f, "the planner refused the request: {why}"),
            ZenohError::BadAnswer(why) => write!(f, "bad answer: {why}"),
            ZenohError::Mismatch { expected, got } => {
                write!(f, "answer {got} does not match request {expected}")
            }
            ZenohError::Zenoh(e) => write!(f, "zenoh: {e}"),
        }
    }
}

impl std::error::Error for ZenohError {}

impl From<Failure> for ZenohError {
    fn from(f: Failure) -> Self {
        match f {
            Failure::Plan(e) => ZenohError::Plan(e),
            Failure::Service(e) => ZenohError::Service(e),
        }
    }
}

fn zerr(what: &str) -> impl Fn(::zenoh::Error) -> ZenohError + '_ {
    move |e| ZenohError::Zenoh(format!("{what}: {e}"))
}

/// The planners this client knows alive (liveliness), and whether it ever saw one.
#[derive(Default)]
struct Planners {
    alive: HashSet<String>,
    ever: bool,
}

/// Per map id: the version this client last published and its size.
#[derive(Clone, Copy)]
struct Upload {
    version: u32,
    width: u32,
    height: u32,
}

/// The map session: publishers, and the queryables answering each map's latest version
/// (replies sent by a thread of their own, never on Zenoh's).
struct MapSide {
    session: ::zenoh::Session,
    latest: Arc<Mutex<HashMap<u32, Arc<Vec<u8>>>>>,
    publishers: HashMap<u32, Publisher<'static>>,
    queryables: HashMap<u32, Queryable<()>>,
    queries: Option<mpsc::Sender<Query>>,
    replier: Option<std::thread::JoinHandle<()>>,
}

impl Drop for MapSide {
    fn drop(&mut self) {
        self.queryables.clear();
        self.queries = None;
        if let Some(t) = self.replier.take() {
            let _ = t.join();
        }
        let _ = self.session.close().wait();
    }
}

/// A connection to the planner service over Zenoh.
pub struct ZenohClient {
    keys: Keys,
    config: ClientConfig,
    session: ::zenoh::Session,
    planners: Arc<Mutex<Planners>>,
    _alive: Subscriber<()>,
    /// The pair's answers to this client (with [`RequestPath::Pair`]), and its name.
    answers: Option<(Subscriber<FifoChannelHandler<Sample>>, String)>,
    /// The pair's request publishers, by planner.
    requests: HashMap<String, Publisher<'static>>,
    maps: Option<MapSide>,
    next_id: u64,
    uploads: HashMap<u32, Upload>,
    limits: Option<PlannerInfo>,
    last_server_time_us: Option<f32>,
    retried: Vec<ZenohError>,
}

impl Drop for ZenohClient {
    fn drop(&mut self) {
        self.maps = None;
        let _ = self.session.close().wait();
    }
}

/// How long a retry waits after a transient failure.
const RETRY_PAUSE: Duration = Duration::from_millis(20);

/// How often a waiting client checks that its planner (the pair) or any planner alive at
/// sending (queries) is still alive.
const PAIR_CHECK: Duration = Duration::from_millis(20);

/// The next item of a handler: polled (yielding the CPU) for `spin`, then waited for until
/// `until` (`Ok(None)` then).
fn next<T>(
    handler: &FifoChannelHandler<T>,
    until: Instant,
    spin: Duration,
) -> ::zenoh::Result<Option<T>> {
    let spin_until = (Instant::now() + spin).min(until);
    loop {
        match handler.try_recv()? {
            Some(item) => return Ok(Some(item)),
            None if Instant::now() < spin_until => std::thread::yield_now(),
            None => return handler.recv_deadline(until),
        }
    }
}

/// An answer's bytes as a [`PlanResult`].
fn decode(bytes: &[u8]) -> Result<PlanResult, ZenohError> {
    postcard::from_bytes(bytes).map_err(|e| {
        ZenohError::BadAnswer(format!(
            "{} bytes do not decode as a planner.v1.PlanResult: {e}",
            bytes.len()
        ))
    })
}

impl ZenohClient {
    /// Opens the plan session and starts following the planners' liveliness. Fails with
    /// [`ZenohError::NotConnected`] when a client-mode session finds no router or peer at
    /// its endpoints; a peer keeps trying in the background.
    pub fn open(config: ClientConfig) -> Result<Self, ZenohError> {
        let keys = Keys::new(&config.prefix).map_err(|e| ZenohError::Zenoh(e.to_string()))?;
        let zconfig = config::session_config(&config.options, SessionKind::Plan)
            .map_err(|e| ZenohError::Zenoh(e.to_string()))?;
        let session = ::zenoh::open(zconfig).wait().map_err(|e| {
            if config.options.mode == config::Mode::Client {
                log::debug!("zenoh open: {e}");
                ZenohError::NotConnected {
                    endpoints: config.options.connect.clone(),
                }
            } else {
                ZenohError::Zenoh(format!("cannot open the plan session: {e}"))
            }
        })?;
        let planners = Arc::new(Mutex::new(Planners::default()));
        let seen = planners.clone();
        let alive_prefix = keys.alive("");
        let alive = session
            .liveliness()
            .declare_subscriber(keys.alive_all())
            .history(true)
            .callback(move |sample| {
                let Some(id) = sample.key_expr().as_str().strip_prefix(&alive_prefix) else {
                    return;
                };
                let mut p = seen.lock().unwrap_or_else(|p| p.into_inner());
                match sample.kind() {
                    SampleKind::Put => {
                        p.alive.insert(id.to_string());
                        p.ever = true;
                    }
                    SampleKind::Delete => {
                        p.alive.remove(id);
                    }
                }
            })
            .wait()
            .map_err(zerr("liveliness subscriber"))?;
        let answers = match config.path {
            RequestPath::Query => None,
            RequestPath::Pair => {
                let me = session.zid().to_string();
                let subscriber = session
                    .declare_subscriber(keys.reply(&me))
                    .with(::zenoh::handlers::FifoChannel::new(256))
                    .wait()
                    .map_err(zerr("answer subscriber"))?;
                Some((subscriber, me))
            }
        };
        Ok(ZenohClient {
            keys,
            config,
            session,
            planners,
            _alive: alive,
            answers,
            requests: HashMap::new(),
            maps: None,
            next_id: first_request_id(),
            uploads: HashMap::new(),
            limits: None,
            last_server_time_us: None,
            retried: Vec::new(),
        })
    }

    /// The planners alive now, by their plan session's Zenoh id.
    pub fn planners(&self) -> Vec<String> {
        let p = self.planners.lock().unwrap_or_else(|p| p.into_inner());
        let mut ids: Vec<String> = p.alive.iter().cloned().collect();
        ids.sort();
        ids
    }

    /// The server-side time (µs) of the last answer, also when it was an error.
    pub fn last_server_time_us(&self) -> Option<f32> {
        self.last_server_time_us
    }

    /// Ok when a planner is alive; else [`ZenohError::NoPlanner`] or
    /// [`ZenohError::NotConnected`], at once.
    pub fn check_planners(&mut self) -> Result<(), ZenohError> {
        if !self.planners().is_empty() {
            return Ok(());
        }
        // Just connected, the subscriber's history may still be on its way: ask directly.
        let replies = self
            .session
            .liveliness()
            .get(self.keys.alive_all())
            .timeout(self.config.probe)
            .wait()
            .map_err(zerr("liveliness query"))?;
        let alive_prefix = self.keys.alive("");
        while let Ok(reply) = replies.recv() {
            if let Ok(sample) = reply.result()
                && let Some(id) = sample.key_expr().as_str().strip_prefix(&alive_prefix)
            {
                let mut p = self.planners.lock().unwrap_or_else(|p| p.into_inner());
                p.alive.insert(id.to_string());
                p.ever = true;
            }
        }
        if !self.planners().is_empty() {
            return Ok(());
        }
        let connected = self.session.info().routers_zid().wait().count()
            + self.session.info().peers_zid().wait().count();
        if connected == 0 {
            Err(ZenohError::NotConnected {
                endpoints: self.config.options.connect.clone(),
            })
        } else {
            Err(ZenohError::NoPlanner {
                prefix: self.keys.prefix().to_string(),
            })
        }
    }

    fn fresh_id(&mut self) -> u64 {
        let id = self.next_id;
        self.next_id = self.next_id.wrapping_add(1);
        id
    }

    /// Gives the request a fresh id and a deadline (its own, else `timeout`); returns the
    /// deadline.
    fn prepare(&mut self, request: &PlanRequest, timeout: Duration) -> (PlanRequest, Duration) {
        let mut request = *request;
        request.request_id = self.fresh_id();
        if request.deadline_us == 0 {
            request.deadline_us = timeout.as_micros().clamp(1, u64::MAX as u128) as u64;
        }
        (request, Duration::from_micros(request.deadline_us))
    }

    /// Sends one request and returns the planner's answer as it came (a planner error is
    /// in the result's `outcome`). The request gets a fresh `request_id` and, when its
    /// `deadline_us` is 0, `timeout` as its deadline; the client waits the deadline plus
    /// [`ClientConfig::margin`].
    pub fn plan_result(
        &mut self,
        request: &PlanRequest,
        timeout: Duration,
    ) -> Result<PlanResult, ZenohError> {
        let (request, deadline) = self.prepare(request, timeout);
        self.send(&request, deadline, deadline + self.config.margin)
    }

    /// Like [`plan_result`](Self::plan_result), keeping the request's own `request_id`: a
    /// caller resending a request itself (same id, same fields) gets the planner's kept
    /// answer, not a second planning.
    pub fn plan_as_is(
        &mut self,
        request: &PlanRequest,
        timeout: Duration,
    ) -> Result<PlanResult, ZenohError> {
        let mut request = *request;
        if request.deadline_us == 0 {
            request.deadline_us = timeout.as_micros().clamp(1, u64::MAX as u128) as u64;
        }
        let deadline = Duration::from_micros(request.deadline_us);
        self.send(&request, deadline, deadline + self.config.margin)
    }

    /// Like [`plan_result`](Self::plan_result), resending the same request (same id) after
    /// [`transient`](ZenohError::is_transient) failures, after [`ZenohError::NoPlanner`]
    /// when this client has seen a planner before (one may be restarting, or its route
    /// coming back), and after an `UnknownMap` answer for a map version this client
    /// published (the planner fetches it from this client once the map session is back),
    /// until the deadline plus the margin; returns the last failure or answer when time
    /// runs out. [`retried`](Self::retried) lists the failures
    /// it went through.
    pub fn plan_retrying(
        &mut self,
        request: &PlanRequest,
        timeout: Duration,
    ) -> Result<PlanResult, ZenohError> {
        let (request, deadline) = self.prepare(request, timeout);
        let until = Instant::now() + deadline + self.config.margin;
        self.retried.clear();
        loop {
            let left = until.saturating_duration_since(Instant::now());
            match self.send(&request, deadline, left) {
                Ok(r) => {
                    // A planner without a map version this client published has not got it
                    // yet (it asks this client for it; the map session may be reconnecting).
                    let own_map_missing =
                        matches!(r.outcome, Err(Failure::Service(ServiceError::UnknownMap)))
                            && self
                                .uploads
                                .get(&request.map_id)
                                .is_some_and(|u| u.version == request.map_version);
                    if !own_map_missing || Instant::now() + RETRY_PAUSE >= until {
                        return Ok(r);
                    }
                    self.retried
                        .push(ZenohError::Service(ServiceError::UnknownMap));
                    std::thread::sleep(RETRY_PAUSE);
                }
                Err(e) => {
                    let ever = self.planners.lock().unwrap_or_else(|p| p.into_inner()).ever;
                    let retry =
                        e.is_transient() || (ever && matches!(e, ZenohError::NoPlanner { .. }));
                    if !retry || Instant::now() + RETRY_PAUSE >= until {
                        return Err(e);
                    }
                    self.retried.push(e);
                    std::thread::sleep(RETRY_PAUSE);
                }
            }
        }
    }

    /// The failures the last [`plan_retrying`](Self::plan_retrying) resent after.
    pub fn retried(&self) -> &[ZenohError] {
        &self.retried
    }

    /// Sends one request and waits for its path (a planner error is an `Err`).
    pub fn plan(&mut self, request: &PlanRequest, timeout: Duration) -> Result<PlanOk, ZenohError> {
        let result = self.plan_result(request, timeout)?;
        self.outcome(request, result)
    }

    /// Like [`plan`](Self::plan), also returning the planner's own time (µs).
    pub fn plan_raw(
        &mut self,
        request: &PlanRequest,
        timeout: Duration,
    ) -> Result<(PlanOk, f32), ZenohError> {
        let result = self.plan_result(request, timeout)?;
        let time = result.time_us;
        let ok = self.outcome(request, result)?;
        Ok((ok, time))
    }

    /// The path of a result, or its failure as an error (a map refused for its size names
    /// the planners' limit).
    fn outcome(&mut self, request: &PlanRequest, result: PlanResult) -> Result<PlanOk, ZenohError> {
        match result.outcome {
            Ok(ok) => Ok(ok),
            Err(Failure::Service(ServiceError::MapTooLarge)) => {
                let max_cells = self.limits.map(|l| l.max_cells);
                Err(ZenohError::MapTooLarge(MapTooLarge {
                    size: self
                        .uploads
                        .get(&request.map_id)
                        .filter(|u| u.version == request.map_version)
                        .map(|u| (u.width, u.height)),
                    max_cells,
                    refused_by: Refusal::Server,
                }))
            }
            Err(f) => Err(f.into()),
        }
    }

    /// One send of a prepared request; waits at most `wait`.
    fn send(
        &mut self,
        request: &PlanRequest,
        deadline: Duration,
        wait: Duration,
    ) -> Result<PlanResult, ZenohError> {
        self.last_server_time_us = None;
        self.check_planners()?;
        let bytes = postcard::to_allocvec(request)
            .map_err(|e| ZenohError::Zenoh(format!("cannot encode the request: {e}")))?;
        let result = match self.config.path {
            RequestPath::Query => self.send_query(request, bytes, deadline, wait),
            RequestPath::Pair => self.send_pair(request, bytes, deadline, wait),
        }?;
        check_path(&result)?;
        self.last_server_time_us = Some(result.time_us);
        Ok(result)
    }

    /// A request of the publish-subscribe pair: published to one live planner, the answer
    /// awaited on this client's answer key (answers to earlier requests are skipped).
    fn send_pair(
        &mut self,
        request: &PlanRequest,
        bytes: Vec<u8>,
        deadline: Duration,
        wait: Duration,
    ) -> Result<PlanResult, ZenohError> {
        let began = Instant::now();
        let planners = self.planners();
        if planners.is_empty() {
            return Err(ZenohError::NoPlanner {
                prefix: self.keys.prefix().to_string(),
            });
        }
        // Spread clients over the planners by request id; a resend may go to another.
        let planner = planners[(request.request_id % planners.len() as u64) as usize].clone();
        let (subscriber, me) = self
            .answers
            .as_ref()
            .ok_or_else(|| ZenohError::Zenoh("no answer subscriber".into()))?;
        // Answers to requests given up on may still be queued: skip them.
        while let Ok(Some(_)) = subscriber.try_recv() {}
        if !self.requests.contains_key(&planner) {
            // Publishers of planners gone are dropped now and then.
            if self.requests.len() >= 64 {
                self.requests.retain(|zid, _| planners.contains(zid));
            }
            let publisher = self
                .session
                .declare_publisher(self.keys.request(&planner, me))
                .wait()
                .map_err(zerr("pair publisher"))?;
            self.requests.insert(planner.clone(), publisher);
        }
        let publisher = self
            .requests
            .get(&planner)
            .ok_or_else(|| ZenohError::Zenoh("pair publisher missing".into()))?;
        publisher.put(bytes).wait().map_err(zerr("pair request"))?;
        let until = began + wait;
        let mut parts = Reassembly::default();
        let spin = self.config.spin;
        loop {
            let slice = (Instant::now() + PAIR_CHECK).min(until);
            match next(subscriber, slice, spin) {
                Ok(Some(sample)) => {
                    let payload = sample.payload().to_bytes();
                    let whole = match sample.attachment() {
                        None => payload.into_owned(),
                        Some(a) => {
                            let a = a.to_bytes();
                            let part = proto::part_of(&a)
                                .map_err(|e| ZenohError::BadAnswer(e.to_string()))?;
                            if part.request_id != request.request_id {
                                continue;
                            }
                            match parts
                                .add(Some(&a), &payload)
                                .map_err(|e| ZenohError::BadAnswer(e.to_string()))?
                            {
                                Some(whole) => whole,
                                None => continue,
                            }
                        }
                    };
                    let result = decode(&whole)?;
                    if result.request_id == request.request_id {
                        return Ok(result);
                    }
                }
                Ok(None) if Instant::now() >= until => {
                    return Err(self.timed_out(request, began.elapsed(), deadline));
                }
                Ok(None) => {
                    let alive = self.planners();
                    if !alive.contains(&planner) {
                        return Err(lost(request, began.elapsed(), alive.len()));
                    }
                }
                Err(e) => return Err(ZenohError::Zenoh(format!("answer subscriber: {e}"))),
            }
        }
    }

    /// `Timeout` for `request` after `waited`, naming its deadline and this client's margin.
    fn timed_out(&self, request: &PlanRequest, waited: Duration, deadline: Duration) -> ZenohError {
        ZenohError::Timeout {
            request_id: request.request_id,
            waited,
            deadline,
            margin: self.config.margin,
        }
    }

    /// A query on `P/@v1/plan`.
    fn send_query(
        &mut self,
        request: &PlanRequest,
        bytes: Vec<u8>,
        deadline: Duration,
        wait: Duration,
    ) -> Result<PlanResult, ZenohError> {
        let began = Instant::now();
        let asked = self.planners();
        let replies = self
            .session
            .get(self.keys.plan())
            .payload(bytes)
            .target(QueryTarget::BestMatching)
            .consolidation(ConsolidationMode::None)
            // Zenoh's own timeout after ours, so that ours decides.
            .timeout(wait + Duration::from_millis(100))
            .wait()
            .map_err(zerr("plan query"))?;
        let until = began + wait;
        let mut parts = Reassembly::default();
        loop {
            let slice = (Instant::now() + PAIR_CHECK).min(until);
            match next(&replies, slice, self.config.spin) {
                Ok(Some(reply)) => {
                    let sample = match reply.result() {
                        Ok(sample) => sample,
                        Err(e) => {
                            return Err(ZenohError::Refused(
                                String::from_utf8_lossy(&e.payload().to_bytes()).into_owned(),
                            ));
                        }
                    };
                    let attachment = sample.attachment().map(|a| a.to_bytes());
                    let payload = sample.payload().to_bytes();
                    let whole = parts
                        .add(attachment.as_deref(), &payload)
                        .map_err(|e| ZenohError::BadAnswer(e.to_string()))?;
                    let Some(whole) = whole else { continue };
                    let result = decode(&whole)?;
                    if result.request_id != request.request_id {
                        return Err(ZenohError::Mismatch {
                            expected: request.request_id,
                            got: result.request_id,
                        });
                    }
                    return Ok(result);
                }
                Ok(None) if Instant::now() >= until => {
                    return Err(self.timed_out(request, began.elapsed(), deadline));
                }
                Ok(None) => {
                    // A query sent while its planner's link was closing may never end (seen
                    // with Zenoh 1.10.2): every planner alive at sending gone is a loss.
                    let alive = self.planners();
                    if !asked.iter().any(|zid| alive.contains(zid)) {
                        return Err(lost(request, began.elapsed(), alive.len()));
                    }
                }
                Err(_) => {
                    let after = began.elapsed();
                    if after >= wait {
                        return Err(self.timed_out(request, after, deadline));
                    }
                    return Err(lost(request, after, self.planners().len()));
                }
            }
        }
    }

    /// The planners' limits (the smallest of each over the planners that answer), asked
    /// once and kept; `None` when no planner answers (a planner then checks alone).
    pub fn limits(&mut self) -> Option<PlannerInfo> {
        if self.limits.is_some() {
            return self.limits;
        }
        let replies = self
            .session
            .get(self.keys.info_all())
            .target(QueryTarget::All)
            .consolidation(ConsolidationMode::None)
            .timeout(self.config.probe)
            .wait()
            .ok()?;
        let mut min: Option<PlannerInfo> = None;
        while let Ok(reply) = replies.recv() {
            let Ok(sample) = reply.result() else { continue };
            let Ok(info) = postcard::from_bytes::<PlannerInfo>(&sample.payload().to_bytes()) else {
                continue;
            };
            min = Some(match min {
                None => info,
                Some(m) => PlannerInfo {
                    max_cells: m.max_cells.min(info.max_cells),
                    max_map_bytes: m.max_map_bytes.min(info.max_map_bytes),
                    max_maps: m.max_maps.min(info.max_maps),
                    ..m
                },
            });
        }
        self.limits = min;
        min
    }

    fn map_side(&mut self) -> Result<&mut MapSide, ZenohError> {
        if self.maps.is_none() {
            let zconfig = config::session_config(&self.config.options, SessionKind::Map)
                .map_err(|e| ZenohError::Zenoh(e.to_string()))?;
            let session = ::zenoh::open(zconfig)
                .wait()
                .map_err(zerr("cannot open the map session"))?;
            let latest: Arc<Mutex<HashMap<u32, Arc<Vec<u8>>>>> = Arc::default();
            let (tx, rx) = mpsc::channel::<Query>();
            let served = latest.clone();
            let keys = self.keys.clone();
            let replier = std::thread::Builder::new()
                .name("planner-map-replies".into())
                .spawn(move || {
                    while let Ok(query) = rx.recv() {
                        let key = query.key_expr().as_str().to_string();
                        let Some(id) = keys.map_id_of(&key) else {
                            continue;
                        };
                        let bytes = served
                            .lock()
                            .unwrap_or_else(|p| p.into_inner())
                            .get(&id)
                            .cloned();
                        if let Some(bytes) = bytes
                            && let Err(e) = query.reply(&key, bytes.to_vec()).wait()
                        {
                            log::debug!("map {id}: latest-version reply: {e}");
                        }
                    }
                })
                .map_err(|e| {
                    ZenohError::Zenoh(format!("cannot start the map reply thread: {e}"))
                })?;
            self.maps = Some(MapSide {
                session,
                latest,
                publishers: HashMap::new(),
                queryables: HashMap::new(),
                queries: Some(tx),
                replier: Some(replier),
            });
        }
        self.maps
            .as_mut()
            .ok_or_else(|| ZenohError::Zenoh("no map session".into()))
    }

    /// Publishes a map version from `grid` on `P/@v1/map/<id>` and serves it as the
    /// latest on that key's queryable (until a newer one, or until this client closes).
    ///
    /// Refused before sending, with the limit: a map over the planners' cell limit
    /// ([`ZenohError::MapTooLarge`], [`Refusal::Client`]), a side beyond 65535, a message
    /// over their map message limit ([`ZenohError::MapMessageTooLarge`]). When no planner
    /// answers yet, the planners check maps on arrival (a map-status request names the
    /// refusal).
    pub fn upload_map(&mut self, meta: MapMeta, grid: GridRef<'_>) -> Result<(), ZenohError> {
        let (w, h) = (grid.width(), grid.height());
        if w == 0 || h == 0 {
            return Err(ZenohError::InvalidMap(MapError::EmptyMap));
        }
        let limits = self.limits();
        let side = |v: usize| u32::try_from(v).unwrap_or(u32::MAX);
        let cells = (w as u64) * (h as u64);
        let max_cells = limits.map(|l| l.max_cells);
        if w > MAX_SIDE || h > MAX_SIDE || max_cells.is_some_and(|m| cells > m) {
            return Err(ZenohError::MapTooLarge(MapTooLarge {
                size: Some((side(w), side(h))),
                max_cells,
                refused_by: Refusal::Client,
            }));
        }
        let mut words = Vec::new();
        let header = pack_map(meta, grid, &mut words);
        let msg = MapMsg::new(&header, &words);
        self.publish_msg(&msg)?;
        self.uploads.insert(
            meta.map_id,
            Upload {
                version: meta.version,
                width: side(w),
                height: side(h),
            },
        );
        Ok(())
    }

    /// Publishes a ready map message as it is (the planners validate it), checking only
    /// the planners' message limit.
    pub fn publish_msg(&mut self, msg: &MapMsg) -> Result<(), ZenohError> {
        let bytes = postcard::to_allocvec(msg)
            .map_err(|e| ZenohError::Zenoh(format!("cannot encode the map: {e}")))?;
        let id = msg.meta.map_id;
        if let Some(limit) = self.limits().map(|l| l.max_map_bytes)
            && bytes.len() as u64 > limit
        {
            return Err(ZenohError::MapMessageTooLarge {
                map_id: id,
                bytes: bytes.len(),
                limit,
            });
        }
        let key = self.keys.map(id);
        let side = self.map_side()?;
        let bytes = Arc::new(bytes);
        side.latest
            .lock()
            .unwrap_or_else(|p| p.into_inner())
            .insert(id, bytes.clone());
        if !side.queryables.contains_key(&id) {
            let tx = side
                .queries
                .clone()
                .ok_or_else(|| ZenohError::Zenoh("map session closing".into()))?;
            let queryable = side
                .session
                .declare_queryable(key.clone())
                .complete(true)
                .callback(move |query| {
                    let _ = tx.send(query);
                })
                .wait()
                .map_err(zerr("map queryable"))?;
            side.queryables.insert(id, queryable);
        }
        if !side.publishers.contains_key(&id) {
            let publisher = side
                .session
                .declare_publisher(key)
                // A stopped or slow planner must not stall the sender: it misses the
                // message and fetches the latest version when it needs it.
                .congestion_control(CongestionControl::Drop)
                .wait()
                .map_err(zerr("map publisher"))?;
            side.publishers.insert(id, publisher);
        }
        let publisher = side
            .publishers
            .get(&id)
            .ok_or_else(|| ZenohError::Zenoh("map publisher missing".into()))?;
        publisher
            .put(bytes.to_vec())
            .wait()
            .map_err(zerr("map put"))
    }

    /// Asks once whether a planner holds `map_id` at `version` (it fetches the latest
    /// from this client's queryable if it has not got it): its size and decoding time, or
    /// the map error.
    pub fn map_status(
        &mut self,
        map_id: u32,
        version: u32,
        timeout: Duration,
    ) -> Result<MapFacts, ZenohError> {
        let request = PlanRequest::map_status((map_id, version));
        let result = self.plan_result(&request, timeout)?;
        let facts = result.map;
        self.outcome(&request, result)?;
        facts.ok_or(ZenohError::BadAnswer(DecodeError::BadPath.to_string()))
    }

    /// A version for the next upload of `map_id`: above what a planner holds (when one
    /// answers within `timeout`) and this client's own uploads, so that a new map under an
    /// id another process used is not ignored as outdated.
    pub fn next_version(&mut self, map_id: u32, timeout: Duration) -> u32 {
        let own = self.uploads.get(&map_id).map_or(0, |u| u.version);
        let request = PlanRequest::map_status((map_id, 0));
        // Version 0 is never held: every answer names the version that is (if any).
        let held = self
            .plan_result(&request, timeout)
            .ok()
            .and_then(|r| r.map)
            .map_or(0, |m| m.version);
        own.max(held).saturating_add(1)
    }

    /// Waits until a planner holds `map_id` at `version`, or names its refusal.
    pub fn wait_for_map(
        &mut self,
        map_id: u32,
        version: u32,
        timeout: Duration,
    ) -> Result<MapFacts, ZenohError> {
        let deadline = Instant::now() + timeout;
        loop {
            let left = deadline.saturating_duration_since(Instant::now());
            let attempt = left.clamp(Duration::from_millis(1), Duration::from_secs(1));
            match self.map_status(map_id, version, attempt) {
                Ok(facts) => return Ok(facts),
                Err(
                    ZenohError::Service(ServiceError::UnknownMap)
                    | ZenohError::NoPlanner { .. }
                    | ZenohError::NotConnected { .. }
                    | ZenohError::PlannerLost { .. }
                    | ZenohError::Timeout { .. },
                ) if !left.is_zero() => std::thread::sleep(Duration::from_millis(5)),
                Err(e) => return Err(e),
            }
        }
    }
}

/// A path must be finite.
fn check_path(result: &PlanResult) -> Result<(), ZenohError> {
    if let Ok(ok) = &result.outcome
        && (ok.path.iter().any(|p| !p.x.is_finite() || !p.y.is_finite()) || !ok.length.is_finite())
    {
        return Err(ZenohError::BadAnswer(DecodeError::BadPath.to_string()));
    }
    Ok(())
}

/// A request id base unique to this client (process, time, instance), so that planners
/// keeping answers by id never confuse two clients.
fn first_request_id() -> u64 {
    use std::sync::atomic::{AtomicU64, Ordering};
    static INSTANCE: AtomicU64 = AtomicU64::new(0);
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos() as u64);
    let mut x = nanos
        ^ (u64::from(std::process::id()) << 32)
        ^ INSTANCE
            .fetch_add(1, Ordering::Relaxed)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15);
    // splitmix64: spread the bits, then leave room below for this client's counter.
    x = (x ^ (x >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    x = (x ^ (x >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    (x ^ (x >> 31)) & !0xFFFF_FFFF | 1
}

/// `PlannerLost` for `request` after `after`, with how many planners are left.
fn lost(request: &PlanRequest, after: Duration, planners_left: usize) -> ZenohError {
    ZenohError::PlannerLost {
        request_id: request.request_id,
        after,
        planners_left,
    }
}

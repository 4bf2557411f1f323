//! The planner over Zenoh: the same [`Engine`] as the iceoryx2 server (one engine may
//! serve both at once, `planner-server --transport both`).
//!
//! Threads: Zenoh's runtime runs the callbacks, which only hand work over (a plan query to
//! the planning threads, a map sample to the map thread): with one runtime worker, a
//! callback that planned would stall every other message of the process. Planning threads
//! (`workers`, each with its own [`Scratch`]) answer queries; the map thread decodes and
//! stores maps. The main thread watches the shutdown flag.
//!
//! Requests ([`PlanRequest`], postcard) come as queries on `P/@v1/plan` or as messages of
//! the publish-subscribe pair on `P/@v1/req/<zid>/<client>`, and are answered with a
//! [`PlanResult`] (postcard) as replies or on `P/@v1/rep/<client>`, in parts when longer
//! than [`MAX_PART`](super::MAX_PART). A request with a `deadline_us`
//! still queued or planning past it is answered `DeadlineExceeded`. Answers are kept by
//! `request_id` ([`ServerConfig::answers_kept`]): a client retrying a request (same id,
//! same fields) gets the same answer without planning again. A request naming a map
//! version newer than the one held (or a map not held) makes the planner fetch the latest
//! version from the map owner's queryable first, so a planner that missed map messages
//! (started late, stopped, congested) catches up on demand.

use super::config::{self, SessionKind, ZenohOptions};
use super::keys::Keys;
use super::proto::{self, PlannerInfo};
use crate::engine::{Engine, MapUpdate, Scratch};
use crate::wire::{
    Failure, MapMsg, PlanRequest, PlanResult, RequestKind, ServiceError, WIRE_VERSION,
};
use ::zenoh::Wait;
use ::zenoh::qos::CongestionControl;
use ::zenoh::query::{ConsolidationMode, Query, QueryTarget};
use ::zenoh::sample::Sample;
use std::collections::{HashMap, VecDeque};
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, mpsc};
use std::time::{Duration, Instant};

/// Configuration of the Zenoh front end.
#[derive(Clone, Debug)]
pub struct ServerConfig {
    /// Service prefix `P`.
    pub prefix: String,
    /// Mode and endpoints.
    pub options: ZenohOptions,
    /// Planning threads.
    pub workers: usize,
    /// Route only: open the sessions (a router, with `Mode::Router`) and serve nothing.
    pub route_only: bool,
    /// Answers kept for retried requests (by request id).
    pub answers_kept: usize,
    /// How long a planner waits for a map owner's latest version.
    pub fetch_timeout: Duration,
    /// How long a planning thread polls for the next request (yielding the CPU) after
    /// answering, before sleeping: a client sending its next request meanwhile costs no
    /// wake-up.
    pub spin: Duration,
}

impl Default for ServerConfig {
    fn default() -> Self {
        ServerConfig {
            prefix: "planner".into(),
            options: ZenohOptions {
                listen: vec!["tcp/127.0.0.1:7447".into()],
                ..ZenohOptions::default()
            },
            workers: 1,
            route_only: false,
            answers_kept: 4096,
            fetch_timeout: Duration::from_secs(2),
            spin: Duration::from_micros(200),
        }
    }
}

/// Who asked, and where the answer goes.
enum Asker {
    /// A query on `P/@v1/plan`: replies.
    Query(Query),
    /// A request of the publish-subscribe pair: a put on this key (`P/@v1/rep/<client>`).
    Pair(String),
}

/// A request waiting for a planning thread.
struct Job {
    asker: Asker,
    payload: Vec<u8>,
    received: Instant,
}

/// Most bytes of kept answers (a long path takes 131 KB).
const ANSWER_BYTES: usize = 64 << 20;

/// Answers by request id, for retries (at most `limit` answers and [`ANSWER_BYTES`] bytes,
/// oldest dropped first).
struct Answers {
    limit: usize,
    bytes: usize,
    by_id: HashMap<u64, (PlanRequest, Arc<Vec<u8>>)>,
    order: VecDeque<u64>,
}

impl Answers {
    fn new(limit: usize) -> Self {
        Answers {
            limit,
            bytes: 0,
            by_id: HashMap::new(),
            order: VecDeque::new(),
        }
    }

    /// The answer given to this very request (same id and fields), if kept.
    fn get(&self, request: &PlanRequest) -> Option<Arc<Vec<u8>>> {
        match self.by_id.get(&request.request_id) {
            Some((asked, answer)) if asked == request => Some(answer.clone()),
            _ => None,
        }
    }

    fn keep(&mut self, request: PlanRequest, answer: Arc<Vec<u8>>) {
        if self.limit == 0 {
            return;
        }
        self.bytes += answer.len();
        match self.by_id.insert(request.request_id, (request, answer)) {
            None => self.order.push_back(request.request_id),
            Some((_, replaced)) => self.bytes -= replaced.len(),
        }
        while self.order.len() > self.limit || self.bytes > ANSWER_BYTES {
            let Some(old) = self.order.pop_front() else {
                break;
            };
            if let Some((_, answer)) = self.by_id.remove(&old) {
                self.bytes -= answer.len();
            }
        }
    }
}

/// What the threads share.
struct Shared {
    keys: Keys,
    engine: Arc<Engine>,
    plan_session: ::zenoh::Session,
    map_session: ::zenoh::Session,
    answers: Mutex<Answers>,
    fetch_timeout: Duration,
    spin: Duration,
    shutdown: Arc<AtomicBool>,
    served: AtomicU64,
    repeated: AtomicU64,
    fetched: AtomicU64,
}

/// Opens one of the sessions, naming the endpoints in the error.
fn open(
    config: ::zenoh::Config,
    what: &str,
    options: &ZenohOptions,
) -> anyhow::Result<::zenoh::Session> {
    ::zenoh::open(config).wait().map_err(|e| {
        anyhow::anyhow!(
            "cannot open the Zenoh {what} session (mode {}, listen {:?}, connect {:?}): {e}",
            options.mode.as_str(),
            options.listen,
            options.connect
        )
    })
}

/// Runs the Zenoh front end of `engine` until `shutdown` becomes true.
pub fn run(
    config: &ServerConfig,
    engine: Arc<Engine>,
    shutdown: Arc<AtomicBool>,
) -> anyhow::Result<()> {
    let keys = Keys::new(&config.prefix)?;
    let max_map_bytes = proto::map_message_limit(engine.store.max_cells());
    let plan_config = config::session_config(&config.options, SessionKind::Plan)?;
    let mut map_config = config::session_config(&config.options, SessionKind::Map)?;
    config::set_max_message_size(&mut map_config, max_map_bytes)?;
    let plan_session = open(plan_config, "plan", &config.options)?;
    let map_session = open(map_config, "map", &config.options)?;
    let zid = plan_session.zid().to_string();
    log::info!(
        "zenoh: {} session {zid} (plan, low-latency) and {} (maps); runtime {}",
        config.options.mode.as_str(),
        map_session.zid(),
        if config::runtime_env_is_one_worker() {
            "one worker".to_string()
        } else {
            format!(
                "{}={:?}",
                config::RUNTIME_ENV,
                std::env::var(config::RUNTIME_ENV).unwrap_or_default()
            )
        }
    );
    if config.route_only {
        log::info!("planner-server ready (zenoh router only, no planner)");
        while !shutdown.load(Ordering::Relaxed) {
            std::thread::sleep(Duration::from_millis(20));
        }
        let _ = plan_session.close().wait();
        let _ = map_session.close().wait();
        return Ok(());
    }

    let shared = Arc::new(Shared {
        keys: keys.clone(),
        engine,
        plan_session: plan_session.clone(),
        map_session: map_session.clone(),
        answers: Mutex::new(Answers::new(config.answers_kept)),
        fetch_timeout: config.fetch_timeout,
        spin: config.spin,
        shutdown: shutdown.clone(),
        served: AtomicU64::new(0),
        repeated: AtomicU64::new(0),
        fetched: AtomicU64::new(0),
    });
    let zerr = |what: &str| {
        let what = what.to_string();
        move |e: ::zenoh::Error| anyhow::anyhow!("zenoh {what}: {e}")
    };

    // Maps: the callback only queues (bounded: a burst beyond it is fetched on demand).
    let (map_tx, map_rx) = mpsc::sync_channel::<Sample>(MAP_QUEUE);
    let dropped_maps = Arc::new(AtomicU64::new(0));
    let dropped = dropped_maps.clone();
    let map_subscriber = map_session
        .declare_subscriber(keys.maps())
        .callback(move |sample| {
            if map_tx.try_send(sample).is_err() {
                dropped.fetch_add(1, Ordering::Relaxed);
            }
        })
        .wait()
        .map_err(zerr("map subscriber"))?;
    let map_thread = {
        let shared = shared.clone();
        std::thread::Builder::new()
            .name("planner-maps".into())
            .spawn(move || map_loop(&shared, &map_rx))?
    };

    // Plans: the callbacks queue the request for the planning threads.
    let (job_tx, job_rx) = mpsc::channel::<Job>();
    let pair_tx = job_tx.clone();
    let queryable = plan_session
        .declare_queryable(keys.plan())
        .complete(true)
        .callback(move |query| {
            let received = Instant::now();
            let payload = query
                .payload()
                .map(|p| p.to_bytes().into_owned())
                .unwrap_or_default();
            let _ = job_tx.send(Job {
                asker: Asker::Query(query),
                payload,
                received,
            });
        })
        .wait()
        .map_err(zerr("plan queryable"))?;
    let pair_keys = keys.clone();
    let pair_zid = zid.clone();
    let pair_subscriber = plan_session
        .declare_subscriber(keys.requests_to(&zid))
        .callback(move |sample| {
            let received = Instant::now();
            let Some(client) = pair_keys.client_of(&pair_zid, sample.key_expr().as_str()) else {
                return;
            };
            let _ = pair_tx.send(Job {
                asker: Asker::Pair(pair_keys.reply(client)),
                payload: sample.payload().to_bytes().into_owned(),
                received,
            });
        })
        .wait()
        .map_err(zerr("pair subscriber"))?;
    let job_rx = Arc::new(Mutex::new(job_rx));
    let workers = (0..config.workers.max(1))
        .map(|i| {
            let shared = shared.clone();
            let jobs = job_rx.clone();
            std::thread::Builder::new()
                .name(format!("planner-zenoh-{i}"))
                .spawn(move || worker(&shared, &jobs))
        })
        .collect::<std::io::Result<Vec<_>>>()?;

    let info = PlannerInfo {
        wire_version: WIRE_VERSION,
        max_cells: shared.engine.store.max_cells() as u64,
        max_map_bytes: max_map_bytes as u64,
        max_maps: shared.engine.store.max_maps() as u32,
        workers: config.workers.max(1) as u32,
    };
    let info_bytes = postcard::to_allocvec(&info)?;
    let info_key = keys.info(&zid);
    let info_reply_key = info_key.clone();
    let info_queryable = plan_session
        .declare_queryable(info_key)
        .complete(true)
        .callback(move |query| {
            // Tiny and never blocking for long: answered on Zenoh's thread.
            if let Err(e) = query.reply(&info_reply_key, info_bytes.clone()).wait() {
                log::debug!("info reply: {e}");
            }
        })
        .wait()
        .map_err(zerr("info queryable"))?;
    let token = plan_session
        .liveliness()
        .declare_token(keys.alive(&zid))
        .wait()
        .map_err(zerr("liveliness token"))?;
    log::info!(
        "planner-server ready (zenoh: {} on {:?}, maps on {:?}; {} worker(s), max map {} cells / {} bytes)",
        keys.plan(),
        config.options.listen,
        config.options.map_listen.clone().unwrap_or_else(|| config
            .options
            .listen
            .iter()
            .filter_map(|e| config::next_port(e).ok())
            .collect()),
        config.workers.max(1),
        info.max_cells,
        info.max_map_bytes
    );

    while !shutdown.load(Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(20));
    }
    log::info!(
        "zenoh: shutting down (liveliness token withdrawn; queued queries answered ServerShuttingDown)"
    );
    let _ = token.undeclare().wait();
    let _ = info_queryable.undeclare().wait();
    // Dropping the queryable and the pair's subscriber drops their callbacks and so the job
    // senders: the workers answer what is queued, then stop.
    let _ = queryable.undeclare().wait();
    let _ = pair_subscriber.undeclare().wait();
    for w in workers {
        let _ = w.join();
    }
    let _ = map_subscriber.undeclare().wait();
    let _ = map_thread.join();
    log::info!(
        "zenoh: stopped: {} request(s) answered ({} repeated from kept answers), {} map fetch(es), {} map message(s) dropped by a full queue",
        shared.served.load(Ordering::Relaxed),
        shared.repeated.load(Ordering::Relaxed),
        shared.fetched.load(Ordering::Relaxed),
        dropped_maps.load(Ordering::Relaxed)
    );
    let _ = plan_session.close().wait();
    let _ = map_session.close().wait();
    Ok(())
}

/// Map samples queued for the map thread at most.
const MAP_QUEUE: usize = 16;

/// Answer publishers of the pair, by client key (bounded: cleared when full).
type Repliers = HashMap<String, ::zenoh::pubsub::Publisher<'static>>;

fn worker(shared: &Shared, jobs: &Mutex<mpsc::Receiver<Job>>) {
    let mut scratch = Scratch::default();
    let mut repliers = Repliers::new();
    loop {
        let job = {
            let jobs = jobs.lock().unwrap_or_else(|p| p.into_inner());
            let spin_until = Instant::now() + shared.spin;
            loop {
                match jobs.try_recv() {
                    Ok(job) => break Ok(job),
                    Err(mpsc::TryRecvError::Empty) if Instant::now() < spin_until => {
                        std::thread::yield_now();
                    }
                    Err(_) => break jobs.recv(),
                }
            }
        };
        match job {
            Ok(job) => answer(shared, &mut scratch, &mut repliers, job),
            Err(_) => return,
        }
    }
}

/// Plans one request and answers it (in parts when long).
fn answer(shared: &Shared, scratch: &mut Scratch, repliers: &mut Repliers, job: Job) {
    let Job {
        asker,
        payload,
        received,
    } = job;
    let request: PlanRequest = match postcard::from_bytes(&payload) {
        Ok(r) => r,
        Err(e) => {
            let why = format!(
                "InvalidRequest: {} bytes do not decode as a planner.v1.PlanRequest (postcard): {e}",
                payload.len()
            );
            log::debug!("{why}");
            // A pair request has no id to answer under: its client times out.
            if let Asker::Query(query) = asker
                && let Err(e) = query.reply_err(why).wait()
            {
                log::debug!("error reply: {e}");
            }
            return;
        }
    };
    let bytes = if let Some(kept) = shared
        .answers
        .lock()
        .unwrap_or_else(|p| p.into_inner())
        .get(&request)
    {
        shared.repeated.fetch_add(1, Ordering::Relaxed);
        log::debug!(
            "request {}: repeated, answered as before",
            request.request_id
        );
        kept
    } else {
        let result = plan(shared, scratch, &request, received);
        let bytes = match postcard::to_allocvec(&result) {
            Ok(b) => Arc::new(b),
            Err(e) => {
                log::warn!(
                    "request {}: cannot encode the answer: {e}",
                    request.request_id
                );
                return;
            }
        };
        // Final answers are kept, refusals too (a retry must not turn a refusal into a
        // plan); not those a retry may change: the map not there yet, the time run out,
        // the planner stopping.
        if !matches!(
            result.outcome,
            Err(Failure::Service(
                ServiceError::UnknownMap
                    | ServiceError::DeadlineExceeded
                    | ServiceError::ServerShuttingDown
            ))
        ) {
            shared
                .answers
                .lock()
                .unwrap_or_else(|p| p.into_inner())
                .keep(request, bytes.clone());
        }
        bytes
    };
    let plan_key = shared.keys.plan();
    for (part, chunk) in proto::parts(request.request_id, &bytes) {
        let attachment = part.and_then(|p| postcard::to_allocvec(&p).ok());
        let sent = match &asker {
            Asker::Query(query) => query
                .reply(&plan_key, chunk.to_vec())
                .attachment(attachment)
                .wait(),
            Asker::Pair(key) => match replier(shared, repliers, key) {
                Ok(publisher) => publisher.put(chunk.to_vec()).attachment(attachment).wait(),
                Err(e) => Err(e),
            },
        };
        if let Err(e) = sent {
            log::warn!(
                "request {}: cannot send the answer: {e}",
                request.request_id
            );
            return;
        }
    }
    shared.served.fetch_add(1, Ordering::Relaxed);
}

/// The publisher of answers to a pair client (declared once per client).
fn replier<'r>(
    shared: &Shared,
    repliers: &'r mut Repliers,
    key: &str,
) -> ::zenoh::Result<&'r ::zenoh::pubsub::Publisher<'static>> {
    if !repliers.contains_key(key) {
        if repliers.len() >= 1024 {
            repliers.clear();
        }
        let publisher = shared
            .plan_session
            .declare_publisher(key.to_string())
            .wait()?;
        repliers.insert(key.to_string(), publisher);
    }
    repliers
        .get(key)
        .ok_or_else(|| "answer publisher missing".into())
}

/// The engine's answer to one request, after catching up on its map if needed.
fn plan(
    shared: &Shared,
    scratch: &mut Scratch,
    request: &PlanRequest,
    received: Instant,
) -> PlanResult {
    let deadline =
        (request.deadline_us > 0).then(|| received + Duration::from_micros(request.deadline_us));
    let failed = |e: ServiceError| PlanResult {
        request_id: request.request_id,
        outcome: Err(Failure::Service(e)),
        map: None,
        time_us: 0.0,
    };
    if shared.shutdown.load(Ordering::Relaxed) {
        return failed(ServiceError::ServerShuttingDown);
    }
    if deadline.is_some_and(|d| Instant::now() > d) {
        return failed(ServiceError::DeadlineExceeded);
    }
    // A map this planner has not got yet (or an older version of it): ask its owner.
    if request.kind().is_ok()
        && matches!(
            shared
                .engine
                .store
                .lookup(request.map_id, request.map_version),
            Err(ServiceError::UnknownMap)
        )
    {
        let budget = deadline.map_or(shared.fetch_timeout, |d| {
            d.saturating_duration_since(Instant::now())
                .min(shared.fetch_timeout)
        });
        fetch_latest(shared, request.map_id, budget);
    }
    let mut late = false;
    let result = shared.engine.handle(scratch, request, &mut || {
        late = deadline.is_some_and(|d| Instant::now() > d);
        late || shared.shutdown.load(Ordering::Relaxed)
    });
    match result.outcome {
        Err(Failure::Service(ServiceError::Cancelled)) if late => {
            failed(ServiceError::DeadlineExceeded)
        }
        Err(Failure::Service(ServiceError::Cancelled)) => failed(ServiceError::ServerShuttingDown),
        _ => {
            if request.kind() == Ok(RequestKind::Plan)
                && let Err(f) = &result.outcome
            {
                log::debug!(
                    "request {} (map {} v{}, {:?} -> {:?}, algo {}): {f}",
                    request.request_id,
                    request.map_id,
                    request.map_version,
                    request.start,
                    request.goal,
                    request.algorithm
                );
            }
            result
        }
    }
}

/// Asks the owner of `map_id` for its latest version and stores it if newer; returns the
/// version stored, if any.
fn fetch_latest(shared: &Shared, map_id: u32, budget: Duration) -> Option<u32> {
    if budget.is_zero() {
        return None;
    }
    shared.fetched.fetch_add(1, Ordering::Relaxed);
    let replies = match shared
        .map_session
        .get(shared.keys.map(map_id))
        .target(QueryTarget::All)
        .consolidation(ConsolidationMode::None)
        .congestion_control(CongestionControl::Block)
        .timeout(budget)
        .wait()
    {
        Ok(r) => r,
        Err(e) => {
            log::warn!("map {map_id}: cannot ask for the latest version: {e}");
            return None;
        }
    };
    let deadline = Instant::now() + budget;
    let mut best: Option<MapMsg> = None;
    while let Ok(Some(reply)) = replies.recv_deadline(deadline) {
        let Ok(sample) = reply.result() else { continue };
        match postcard::from_bytes::<MapMsg>(&sample.payload().to_bytes()) {
            Ok(msg) if msg.meta.map_id == map_id => {
                if best
                    .as_ref()
                    .is_none_or(|b| b.meta.version < msg.meta.version)
                {
                    best = Some(msg);
                }
            }
            Ok(msg) => log::warn!(
                "map {map_id}: its queryable answered map {} (ignored)",
                msg.meta.map_id
            ),
            Err(e) => log::warn!("map {map_id}: undecodable answer from its queryable: {e}"),
        }
    }
    let msg = best?;
    let version = msg.meta.version;
    store(shared, &msg, "fetched from its owner");
    Some(version)
}

/// Decodes and stores a map message (unless not newer); logs the outcome.
fn store(shared: &Shared, msg: &MapMsg, how: &str) -> MapUpdate {
    let store = &shared.engine.store;
    let meta = msg.meta;
    if !store.is_newer(&meta) {
        return MapUpdate::Outdated;
    }
    let began = Instant::now();
    let grid = msg.to_grid(store.max_cells());
    let decode_us = began.elapsed().as_secs_f32() * 1e6;
    let result = store.update_decoded(meta, grid, decode_us);
    match result {
        MapUpdate::Stored => log::info!(
            "map {} version {} stored: {}x{} cells, resolution {} m, origin {:?} ({how}, built in {:.0} us)",
            meta.map_id,
            meta.version,
            msg.width,
            msg.height,
            meta.resolution,
            meta.origin,
            decode_us
        ),
        MapUpdate::Outdated => {}
        MapUpdate::Rejected(ServiceError::MapTooLarge) => log::warn!(
            "map {} version {} rejected: MapTooLarge: {} x {} = {} cells, this server's limit is {} cells; raise it with planner-server --max-cells",
            meta.map_id,
            meta.version,
            msg.width,
            msg.height,
            u64::from(msg.width) * u64::from(msg.height),
            store.max_cells()
        ),
        MapUpdate::Rejected(e) => log::warn!(
            "map {} version {} rejected: {e} ({} x {} cells, {} words)",
            meta.map_id,
            meta.version,
            msg.width,
            msg.height,
            msg.bits.len()
        ),
    }
    result
}

/// The map thread: stores published maps; after a gap in an id's versions (messages
/// dropped for this planner), asks the owner for the latest.
fn map_loop(shared: &Shared, samples: &mpsc::Receiver<Sample>) {
    let mut last: HashMap<u32, u32> = HashMap::new();
    let mut gaps: Vec<u32> = Vec::new();
    loop {
        let sample = if gaps.is_empty() {
            samples.recv().ok()
        } else {
            match samples.try_recv() {
                Ok(s) => Some(s),
                Err(mpsc::TryRecvError::Empty) => {
                    // The burst is over: catch up on the ids that had a gap.
                    for id in std::mem::take(&mut gaps) {
                        if let Some(v) = fetch_latest(shared, id, shared.fetch_timeout) {
                            last.insert(id, v);
                        }
                    }
                    continue;
                }
                Err(mpsc::TryRecvError::Disconnected) => None,
            }
        };
        let Some(sample) = sample else { return };
        let key = sample.key_expr().as_str();
        let Some(id) = shared.keys.map_id_of(key) else {
            log::warn!("map message on {key}: not a map key of this service (ignored)");
            continue;
        };
        let msg = match postcard::from_bytes::<MapMsg>(&sample.payload().to_bytes()) {
            Ok(m) => m,
            Err(e) => {
                log::warn!(
                    "map message on {key}: {} bytes do not decode as a planner.v1 map (postcard): {e}",
                    sample.payload().len()
                );
                continue;
            }
        };
        if msg.meta.map_id != id {
            log::warn!(
                "map message on {key} carries map id {} (ignored)",
                msg.meta.map_id
            );
            continue;
        }
        let version = msg.meta.version;
        if let Some(&seen) = last.get(&id)
            && version > seen.saturating_add(1)
        {
            log::info!(
                "map {id}: versions {} to {} missed (version {version} arrived); asking for the latest",
                seen + 1,
                version - 1
            );
            gaps.push(id);
        }
        let seen = last.entry(id).or_insert(version);
        *seen = (*seen).max(version);
        store(shared, &msg, "published");
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::Algorithm;

    #[test]
    fn kept_answers_are_bounded_and_match_the_whole_request() {
        let mut answers = Answers::new(3);
        let request = |id: u64| {
            let mut r = PlanRequest::new((1, 1), [0, 0], [1, 1], Algorithm::AStar);
            r.request_id = id;
            r
        };
        for id in 1..=5 {
            answers.keep(request(id), Arc::new(vec![id as u8; 10]));
        }
        assert!(answers.get(&request(1)).is_none() && answers.get(&request(2)).is_none());
        assert_eq!(answers.get(&request(5)).unwrap().as_slice(), &[5; 10]);
        assert_eq!(answers.bytes, 30);
        let mut other = request(5);
        other.goal = [2, 2];
        assert!(answers.get(&other).is_none());
        // Replacing an answer, and the byte budget.
        answers.keep(request(5), Arc::new(vec![0; 20]));
        assert_eq!(answers.bytes, 40);
        answers.keep(request(6), Arc::new(vec![0; ANSWER_BYTES]));
        assert_eq!((answers.order.len(), answers.bytes), (1, ANSWER_BYTES));
    }
}

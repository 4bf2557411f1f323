//! Service names and the one place where every iceoryx2 service is declared, so that the
//! server and the clients open them with identical settings.
//!
//! Services under a configurable prefix `P` (tests use a unique prefix per test):
//! - `P/map`: publish-subscribe of map frames: [`MapHeader`] + `[u32]` words (host
//!   publishes, server subscribes and plans on the frames it holds; the
//!   publisher keeps a history so that a late or restarted server gets the current maps).
//!   A server creates it with the attribute [`MAX_CELLS_ATTRIBUTE`] (its `--max-cells`), which
//!   clients read to refuse a larger map before sending it. Publishers' shared memory starts
//!   at [`MAP_INITIAL_SLICE_LEN`] words a frame and grows in powers of two when a larger
//!   map is published, so small maps do not pay for the largest;
//! - `P/plan`: request-response [`PlanRequest`] -> [`PlanResponseHeader`] + `[Waypoint]`;
//! - `P/plan-wake`: event; clients notify it after sending a request so that a blocking
//!   server wakes up;
//! - `P/client-wake/T`: event per blocking client (token `T`); the server notifies it after
//!   answering that client.

use crate::wire::{MAX_WAYPOINTS, MapHeader, PlanRequest, PlanResponseHeader, Waypoint};
use iceoryx2::node::Node;
use iceoryx2::node::NodeView;
use iceoryx2::prelude::*;
use iceoryx2::service::Service;
use iceoryx2::service::attribute::{AttributeKey, AttributeValue};
use iceoryx2::service::port_factory::event::PortFactory as EventFactory;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory as PubSubFactory;
use iceoryx2::service::port_factory::request_response::PortFactory as ReqRespFactory;

/// Thread-safe ports, for a server that hands an active request to a worker thread.
pub type Svc = ipc_threadsafe::Service;

/// Single-threaded ports: no mutex around every port operation, which takes about 0.17 us
/// off each side of a round trip on the 2-core VM (`planner-bench raw`). The client and a
/// server planning inline use them. Both flavours share the shared-memory layout, so
/// either side may use either.
pub type LocalSvc = ipc::Service;

/// The map service's factory.
pub type MapService<S = Svc> = PubSubFactory<S, [u32], MapHeader>;
/// The plan service's factory.
pub type PlanService<S = Svc> = ReqRespFactory<S, PlanRequest, (), [Waypoint], PlanResponseHeader>;
/// An event service's factory.
pub type EventService<S = Svc> = EventFactory<S>;

/// Shared service limits. The server creates the services with these; clients open with
/// the same values (iceoryx2 checks that an opened service supports at least them).
#[derive(Clone, Debug)]
pub struct Limits {
    /// Plan clients (and map publishers) at once.
    pub max_clients: usize,
    /// Nodes that may open one service.
    pub max_nodes: usize,
    /// Map frames a publisher keeps for late subscribers (the last versions uploaded).
    pub map_history: usize,
    /// Map subscribers (servers) at once: a server and its restarted successor.
    pub map_subscribers: usize,
}

impl Default for Limits {
    fn default() -> Self {
        Limits {
            max_clients: 64,
            max_nodes: 128,
            map_history: 4,
            map_subscribers: 2,
        }
    }
}

impl Limits {
    /// Frames (shared-memory chunks) of one map publisher's data segment, as iceoryx2
    /// sizes it: every subscriber's buffer and borrowed samples, the history and the
    /// publisher's own loan. Each chunk holds one frame of the largest map published so far
    /// (rounded up to a power of two), but only the pages of chunks actually written take
    /// memory.
    pub fn map_chunks(&self) -> usize {
        self.map_subscribers * (self.map_buffer() + MAP_BORROWED_SAMPLES)
            + self.map_history
            + MAP_LOANED_SAMPLES
    }

    fn map_buffer(&self) -> usize {
        self.map_history.max(2)
    }
}

/// Frames a subscriber may hold at once from one publisher. A server plans on the frames it
/// holds (the current version of each map id, see [`crate::engine::MapCells::Frame`]) and
/// keeps one free to receive the next: it holds at most three maps from one publisher in
/// place and copies further ones into its own memory. (Earlier builds held one, only while
/// decoding; a service they created is opened as it is, and its server copies every frame.)
pub const MAP_BORROWED_SAMPLES: usize = 4;
/// Frames a client loans at once (one: it packs the map and sends it).
const MAP_LOANED_SAMPLES: usize = 1;

/// Service attribute of `P/map`: the largest map (cells) the server that created the
/// service accepts (`planner-server --max-cells`).
pub const MAX_CELLS_ATTRIBUTE: &str = "planner/max-cells";

/// Service names under a prefix.
#[derive(Clone, Debug)]
pub struct Names {
    /// The prefix, e.g. `planner` or `test-1234`.
    pub prefix: String,
}

impl Names {
    /// Names under `prefix`.
    pub fn new(prefix: &str) -> Self {
        Names {
            prefix: prefix.to_string(),
        }
    }

    fn name(&self, suffix: &str) -> Result<ServiceName, anyhow::Error> {
        let text = format!("{}/{suffix}", self.prefix);
        ServiceName::new(&text).map_err(|e| anyhow::anyhow!("bad service name {text:?}: {e:?}"))
    }

    /// `P/map`.
    pub fn map(&self) -> anyhow::Result<ServiceName> {
        self.name("map")
    }

    /// `P/plan`.
    pub fn plan(&self) -> anyhow::Result<ServiceName> {
        self.name("plan")
    }

    /// `P/plan-wake`.
    pub fn plan_wake(&self) -> anyhow::Result<ServiceName> {
        self.name("plan-wake")
    }

    /// `P/client-wake/T`.
    pub fn client_wake(&self, token: u64) -> anyhow::Result<ServiceName> {
        self.name(&format!("client-wake/{token:016x}"))
    }
}

/// A node with iceoryx2's own signal handling off (the binaries handle SIGINT/SIGTERM).
pub fn node<S: Service>(name: &str) -> anyhow::Result<Node<S>> {
    let name = NodeName::new(name).map_err(|e| anyhow::anyhow!("bad node name: {e:?}"))?;
    NodeBuilder::new()
        .name(&name)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<S>()
        .map_err(|e| anyhow::anyhow!("cannot create iceoryx2 node: {e:?}"))
}

/// Opens or creates the map service (a client: without the limit attribute, so that a
/// server started later is not bound by a client's guess).
pub fn map_service<S: Service>(
    node: &Node<S>,
    names: &Names,
    limits: &Limits,
) -> anyhow::Result<MapService<S>> {
    match map_builder(node, names, limits, MAP_BORROWED_SAMPLES)?.open_or_create() {
        Ok(service) => Ok(service),
        // Created by an earlier build, whose subscribers borrow one frame at a time: open
        // it as it is (a server then copies every frame, see `held_frames_limit`).
        Err(e) => map_builder(node, names, limits, 1)?
            .open()
            .map_err(|_| not_ours(&names.map(), e)),
    }
}

/// How many received frames a subscriber of `service` may hold from one publisher (its
/// `subscriber_max_borrowed_samples`).
pub fn map_borrow_limit<S: Service>(service: &MapService<S>) -> usize {
    service.static_config().subscriber_max_borrowed_samples()
}

/// Opens or creates the map service for a server accepting maps of at most `max_cells`
/// cells: a new service records the limit ([`MAX_CELLS_ATTRIBUTE`]). An existing service
/// created by a client or by a server with another limit is opened as it is; the second
/// value tells its recorded limit (`None`: none recorded).
pub fn map_service_for_server<S: Service>(
    node: &Node<S>,
    names: &Names,
    limits: &Limits,
    max_cells: usize,
) -> anyhow::Result<(MapService<S>, Option<u64>)> {
    let key = AttributeKey::try_from(MAX_CELLS_ATTRIBUTE)
        .map_err(|e| anyhow::anyhow!("attribute key: {e:?}"))?;
    let value = AttributeValue::try_from(max_cells.to_string().as_str())
        .map_err(|e| anyhow::anyhow!("attribute value: {e:?}"))?;
    let verifier = AttributeVerifier::new()
        .require(&key, &value)
        .map_err(|e| anyhow::anyhow!("attribute: {e:?}"))?;
    let service = match map_builder(node, names, limits, MAP_BORROWED_SAMPLES)?
        .open_or_create_with_attributes(&verifier)
    {
        Ok(service) => service,
        // Created earlier with another (or no) limit: the attribute cannot change.
        Err(_) => map_service(node, names, limits)?,
    };
    let recorded = recorded_max_cells(&service);
    Ok((service, recorded))
}

/// The limit (cells) recorded in the map service by the server that created it.
pub fn recorded_max_cells<S: Service>(service: &MapService<S>) -> Option<u64> {
    let key = AttributeKey::try_from(MAX_CELLS_ATTRIBUTE).ok()?;
    let value = service.attributes().key_value(&key, 0)?;
    value.to_string().parse().ok()
}

fn map_builder<S: Service>(
    node: &Node<S>,
    names: &Names,
    limits: &Limits,
    borrowed: usize,
) -> anyhow::Result<iceoryx2::service::builder::publish_subscribe::Builder<[u32], MapHeader, S>> {
    Ok(node
        .service_builder(&names.map()?)
        .publish_subscribe::<[u32]>()
        .user_header::<MapHeader>()
        .history_size(limits.map_history)
        .subscriber_max_buffer_size(limits.map_buffer())
        .subscriber_max_borrowed_samples(borrowed)
        .max_publishers(limits.max_clients)
        .max_subscribers(limits.map_subscribers)
        .max_nodes(limits.max_nodes))
}

/// A map publisher: one loan at a time, shared memory that grows in powers of two from
/// [`MAP_INITIAL_SLICE_LEN`] words a frame to the largest map published.
pub fn map_publisher<S: Service>(
    service: &MapService<S>,
) -> anyhow::Result<iceoryx2::port::publisher::Publisher<S, [u32], MapHeader>> {
    service
        .publisher_builder()
        .initial_max_slice_len(MAP_INITIAL_SLICE_LEN)
        .allocation_strategy(AllocationStrategy::PowerOfTwo)
        .max_loaned_samples(MAP_LOANED_SAMPLES)
        .create()
        .map_err(|e| anyhow::anyhow!("map publisher: {e:?}"))
}

/// Opens or creates the plan service (the server).
pub fn plan_service_create<S: Service>(
    node: &Node<S>,
    names: &Names,
    limits: &Limits,
) -> anyhow::Result<PlanService<S>> {
    plan_builder(node, names, limits)?
        .open_or_create()
        .map_err(|e| not_ours(&names.plan(), e))
}

/// The error of a server that cannot open a service someone else created with other
/// settings or types: most often a foreign client that called `open_or_create` with
/// iceoryx2's defaults before the server started (clients must only open services).
pub fn not_ours(name: &anyhow::Result<ServiceName>, e: impl core::fmt::Debug) -> anyhow::Error {
    let name = name
        .as_ref()
        .map_or_else(|_| "?".to_string(), |n| n.to_string());
    anyhow::anyhow!(
        "service {name:?} exists with settings or payload types this server cannot use \
         ({e:?}); it was most likely created by a client before the server started (clients \
         must open the services, never create them: docs/wire.md). Stop the processes that \
         hold it, or use another --prefix, then start planner-server again"
    )
}

/// Opens the plan service (a client): fails when no server ever created it.
pub fn plan_service_open<S: Service>(
    node: &Node<S>,
    names: &Names,
    limits: &Limits,
) -> anyhow::Result<PlanService<S>> {
    plan_builder(node, names, limits)?
        .open()
        .map_err(|e| anyhow::anyhow!("plan service: {e:?}"))
}

fn plan_builder<S: Service>(
    node: &Node<S>,
    names: &Names,
    limits: &Limits,
) -> anyhow::Result<
    iceoryx2::service::builder::request_response::Builder<
        PlanRequest,
        (),
        [Waypoint],
        PlanResponseHeader,
        S,
    >,
> {
    Ok(node
        .service_builder(&names.plan()?)
        .request_response::<PlanRequest, [Waypoint]>()
        .response_user_header::<PlanResponseHeader>()
        // Never overwrite a queued request or response: every request gets its answer.
        .enable_safe_overflow_for_requests(false)
        .enable_safe_overflow_for_responses(false)
        .max_active_requests_per_client(4)
        .max_response_buffer_size(4)
        .max_servers(2)
        .max_clients(limits.max_clients)
        .max_nodes(limits.max_nodes))
}

/// Opens or creates an event service.
pub fn event_service<S: Service>(
    node: &Node<S>,
    name: &ServiceName,
    limits: &Limits,
) -> anyhow::Result<EventService<S>> {
    node.service_builder(name)
        .event()
        .max_notifiers(limits.max_clients + 2)
        .max_listeners(4)
        .max_nodes(limits.max_nodes)
        .open_or_create()
        .map_err(|e| not_ours(&Ok(*name), e))
}

/// Opens an existing event service (a client's wake event, which the server never creates).
pub fn event_service_open<S: Service>(
    node: &Node<S>,
    name: &ServiceName,
    limits: &Limits,
) -> anyhow::Result<EventService<S>> {
    node.service_builder(name)
        .event()
        .max_notifiers(limits.max_clients + 2)
        .max_listeners(4)
        .max_nodes(limits.max_nodes)
        .open()
        .map_err(|e| anyhow::anyhow!("event service {name}: {e:?}"))
}

/// Removes what dead nodes (crashed servers or clients) left behind; returns how many
/// dead nodes were cleaned up.
pub fn cleanup_dead_nodes<S: Service>(node: &Node<S>) -> usize {
    let mut cleaned = 0;
    let result = Node::<S>::list(node.config(), |state| {
        if let NodeState::Dead(view) = state {
            let name = view
                .details()
                .as_ref()
                .map(|d| d.name().to_string())
                .unwrap_or_default();
            match view.blocking_remove_stale_resources(std::time::Duration::from_millis(500)) {
                Ok(()) => {
                    log::info!("removed stale resources of dead node {name:?}");
                    cleaned += 1;
                }
                Err(e) => log::warn!("cannot clean up dead node {name:?}: {e:?}"),
            }
        }
        CallbackProgression::Continue
    });
    if let Err(e) = result {
        log::warn!("cannot list nodes: {e:?}");
    }
    cleaned
}

/// Lowers iceoryx2's own log level to errors unless `RUST_LOG` mentions `iceoryx2` (it
/// warns about the missing optional config file on every start, and dumps whole configs).
pub fn quiet_iceoryx_logs() {
    let wanted = std::env::var("RUST_LOG").is_ok_and(|v| v.contains("iceoryx2"));
    if !wanted {
        iceoryx2::prelude::set_log_level(LogLevel::Error);
    }
}

/// Initial slice length of a map publisher, in words: a 512 x 512 map in both layouts
/// (64 KiB a frame).
/// Larger maps grow the publisher's shared memory (powers of two) when first published.
pub const MAP_INITIAL_SLICE_LEN: usize = 2 * 512 * 512 / 32;
/// Slice capacity of a plan server's responses: [`MAX_WAYPOINTS`] (128 KiB an answer).
///
/// Fixed (iceoryx2's static allocation), not grown on demand like the map frames: a
/// resizable data segment makes every client connection track up to 255 segments of all
/// the server's chunks (18 MiB of shared memory a client here, against 70 KiB). The
/// segment's size is virtual: only the pages of the waypoints actually written take memory
/// (a short answer touches the first page of its chunk).
pub const PATH_SLICE_CAPACITY: usize = MAX_WAYPOINTS;

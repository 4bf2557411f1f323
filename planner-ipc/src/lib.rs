//! The warehouse planner as a shared-memory service over iceoryx2 (issue 5).
//!
//! Layers, bottom up (like smoltcp):
//! - [`wire`]: fixed-layout `#[repr(C)]` [`ZeroCopySend`](iceoryx2::prelude::ZeroCopySend)
//!   payloads ([`wire::MapHeader`] + map words, [`wire::PlanRequest`],
//!   [`wire::PlanResponseHeader`] + [`wire::Waypoint`]s), status
//!   codes, typed errors, validation, and serde mirrors for byte streams (postcard);
//! - [`jsonl`]: the JSON-lines result format shared with `host-sim plan`;
//! - [`engine`]: the transport-free map store and planner dispatch;
//! - [`services`]: service names and settings, node creation, dead-node cleanup;
//! - [`server`]: the serving loop, worker threads, cancellation, shutdown;
//! - [`client`]: the client library (`plan(request, timeout)`, map upload, wait modes).
//!
//! Binaries: `planner-server`, `planner-client` (people's CLI), `planner-bench`.
#![deny(unsafe_code)]
#![warn(missing_docs)]

pub mod cli;
pub mod client;
pub mod engine;
pub mod jsonl;
pub mod server;
pub mod services;
pub mod wire;

//! The warehouse planner as a shared-memory service over iceoryx2 (issue 5).
//!
//! Layers, bottom up (like smoltcp):
//! - [`wire`]: wire v1, fixed-layout `#[repr(C)]`
//!   [`ZeroCopySend`](iceoryx2::prelude::ZeroCopySend) payloads with versioned type names,
//!   one module per message ([`wire::map_frame`], [`wire::plan_request`],
//!   [`wire::plan_response`]), status and algorithm codes, validation, serde mirrors for byte
//!   streams (postcard), and the ABI table behind the C header ([`wire::abi`]); the
//!   protocol reference for other languages is `docs/wire.md`;
//! - [`jsonl`]: the JSON-lines result format shared with `host-sim plan`;
//! - [`engine`]: the transport-free map store and planner dispatch;
//! - [`services`]: service names and settings, node creation, dead-node cleanup;
//! - [`server`]: the serving loop, worker threads, cancellation, shutdown;
//! - [`client`]: the client library (`plan(request, timeout)`, map upload, wait modes);
//! - `zenoh` (feature `zenoh`): the same engine and wire types over Zenoh, across hosts
//!   (`docs/zenoh.md`).
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
#[cfg(feature = "zenoh")]
pub mod zenoh;

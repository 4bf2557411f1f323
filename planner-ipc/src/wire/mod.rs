//! Wire v1: the fixed-layout (`#[repr(C)]`,
//! [`ZeroCopySend`](iceoryx2::prelude::ZeroCopySend)) payloads that travel through
//! iceoryx2 shared memory (a fixed header plus a slice of fixed elements where the size
//! varies: map words, path waypoints), their conversion to and from planner-core types with
//! validation, and serde mirrors for byte streams (postcard over a socket, logs).
//!
//! One module per message: [`map_frame`] (a map published to the server), [`plan_request`]
//! and [`plan_response`] (the request-response pair), and what they share: [`status`]
//! codes, [`algorithm`] and guide codes, the [`clock`] both processes read. [`abi`] lists
//! every payload's fields, offsets and sizes, and writes the C header of the ABI from them
//! (`clients/c/planner_wire.h`); `docs/wire.md` is the protocol reference for clients in
//! other languages.
//!
//! Versioning: every payload header starts with `wire_version: u16` ([`WIRE_VERSION`]), and
//! every payload type has an explicit, stable iceoryx2 type name carrying the version
//! (`planner.v1.PlanRequest`, see [`TYPE_NAMES`]), so that iceoryx2 refuses a client of
//! another wire version when it opens a service (`IncompatibleTypes`) instead of letting it
//! misread the bytes; a server also refuses a request whose `wire_version` differs
//! ([`ServiceError::UnsupportedVersion`]). A change of any layout or meaning bumps the
//! version.
//!
//! Every field a peer writes is untrusted: conversions check ranges and finiteness and turn
//! garbage into a typed [`ServiceError`] or [`PlanError`](planner_core::PlanError), never a
//! panic.

pub mod abi;
pub mod algorithm;
pub mod clock;
pub mod map_frame;
pub mod plan_request;
pub mod plan_response;
pub mod status;

pub use algorithm::{Algorithm, Guide};
pub use clock::unix_ns;
pub use map_frame::{
    FramePacker, LAYOUT_ROWS, LAYOUT_ROWS_AND_COLUMNS, MapHeader, MapMeta, MapMsg,
    first_disagreement, frame_grid, frame_header, grid_from_bits, pack_map, write_grid,
};
pub use plan_request::{PlanParams, PlanRequest, RequestKind, to_cell};
pub use plan_response::{
    DecodeError, MapFacts, PlanAnswer, PlanFound, PlanOk, PlanResponseHeader, PlanResult, PlanView,
    Waypoint,
};
pub use status::{Failure, STATUS_OK, ServiceError, decode_status, status_code};

/// The wire version this build speaks (the first field of every payload header).
pub const WIRE_VERSION: u16 = 1;

/// The iceoryx2 type names of the payloads, as foreign clients must declare them: the
/// request header is `()` and the map words are `u32` (Rust's names of those types).
pub const TYPE_NAMES: [(&str, &str); 4] = [
    ("MapHeader", "planner.v1.MapHeader"),
    ("PlanRequest", "planner.v1.PlanRequest"),
    ("PlanResponseHeader", "planner.v1.PlanResponseHeader"),
    ("Waypoint", "planner.v1.Waypoint"),
];

/// The largest map a server takes by default: 4096 x 4096 cells (`planner-server
/// --max-cells` changes it). A frame itself may carry any map whose sides fit in `u16`
/// ([`MAX_SIDE`](planner_core::grid::MAX_SIDE)); the publisher's shared memory grows to the
/// largest map sent.
pub const DEFAULT_MAX_CELLS: usize = 4096 * 4096;
/// Most waypoints a [`PlanResponseHeader`] carries (an A* path lists every cell: a route
/// across a 4096 x 4096 warehouse takes 4096-8192); a longer path is
/// [`PlanError::CapacityExceeded`](planner_core::PlanError::CapacityExceeded).
pub const MAX_WAYPOINTS: usize = 16_384;
/// Largest robot radius a request may ask for, in cells (larger is
/// [`PlanError::InvalidParameters`](planner_core::PlanError::InvalidParameters); inflation costs grow with the radius).
pub const MAX_RADIUS: f32 = 1024.0;
/// Largest population or iteration count a request may ask for (larger is
/// [`PlanError::InvalidParameters`](planner_core::PlanError::InvalidParameters)).
pub const MAX_COUNT: u32 = 1 << 24;

#[cfg(test)]
mod tests {
    use super::*;
    use iceoryx2::prelude::ZeroCopySend;

    /// The names iceoryx2 compares when a client opens a service: stable, versioned, and
    /// independent of where the types live in this crate.
    #[test]
    #[allow(unsafe_code)] // `type_name` is unsafe to implement, not to call: no invariant.
    fn type_names_are_pinned() {
        // SAFETY: reading a `&'static str`; the derive implemented the trait.
        let names = unsafe {
            [
                MapHeader::type_name(),
                PlanRequest::type_name(),
                PlanResponseHeader::type_name(),
                Waypoint::type_name(),
            ]
        };
        for ((short, pinned), name) in TYPE_NAMES.iter().zip(names) {
            assert_eq!(name, *pinned, "{short}");
            assert!(name.ends_with(short) && name.contains(".v1."));
        }
        // SAFETY: as above.
        let (word, unit) = unsafe { (u32::type_name(), <()>::type_name()) };
        assert_eq!((word, unit), ("u32", "()"));
    }
}

//! Status codes of a [`PlanResponseHeader`](super::PlanResponseHeader) (`u16`): `0` ok,
//! `1..=8` a planner error ([`PlanError`], Nav2-like), `101..=110` a service error
//! ([`ServiceError`]). Each code is written out here, not derived from an ordering, so that
//! reordering an enum cannot change the wire.

use planner_core::PlanError;
use serde::{Deserialize, Serialize};
use std::fmt;

/// Status code `0`: success.
pub const STATUS_OK: u16 = 0;

/// Why the service (not the planner) refused or failed a request.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum ServiceError {
    /// The server has no map with this id.
    UnknownMap,
    /// The server holds a newer version of this map than the request names.
    StaleMapVersion,
    /// The map exceeds the server's configured limit (`planner-server --max-cells`) or has a
    /// side beyond 65535 cells. The response header's `max_cells` says the limit.
    MapTooLarge,
    /// The algorithm code names no planner this server serves.
    UnknownAlgorithm,
    /// A request field is out of range (garbage, bad coordinates type, bad kind).
    InvalidRequest,
    /// The client gave up on the request before the server answered it.
    Cancelled,
    /// The server is shutting down and did not plan this request.
    ServerShuttingDown,
    /// The request's deadline passed before planning started.
    DeadlineExceeded,
    /// The server hit an internal error (see its log).
    Internal,
    /// The request's `wire_version` is not the one this server speaks.
    UnsupportedVersion,
}

impl ServiceError {
    /// Every variant, in code order.
    pub const ALL: [ServiceError; 10] = [
        ServiceError::UnknownMap,
        ServiceError::StaleMapVersion,
        ServiceError::MapTooLarge,
        ServiceError::UnknownAlgorithm,
        ServiceError::InvalidRequest,
        ServiceError::Cancelled,
        ServiceError::ServerShuttingDown,
        ServiceError::DeadlineExceeded,
        ServiceError::Internal,
        ServiceError::UnsupportedVersion,
    ];

    /// The wire status code.
    pub const fn code(self) -> u16 {
        match self {
            ServiceError::UnknownMap => 101,
            ServiceError::StaleMapVersion => 102,
            ServiceError::MapTooLarge => 103,
            ServiceError::UnknownAlgorithm => 104,
            ServiceError::InvalidRequest => 105,
            ServiceError::Cancelled => 106,
            ServiceError::ServerShuttingDown => 107,
            ServiceError::DeadlineExceeded => 108,
            ServiceError::Internal => 109,
            ServiceError::UnsupportedVersion => 110,
        }
    }

    /// The variant's name, as printed in JSON lines.
    pub const fn name(self) -> &'static str {
        match self {
            ServiceError::UnknownMap => "UnknownMap",
            ServiceError::StaleMapVersion => "StaleMapVersion",
            ServiceError::MapTooLarge => "MapTooLarge",
            ServiceError::UnknownAlgorithm => "UnknownAlgorithm",
            ServiceError::InvalidRequest => "InvalidRequest",
            ServiceError::Cancelled => "Cancelled",
            ServiceError::ServerShuttingDown => "ServerShuttingDown",
            ServiceError::DeadlineExceeded => "DeadlineExceeded",
            ServiceError::Internal => "Internal",
            ServiceError::UnsupportedVersion => "UnsupportedVersion",
        }
    }
}

impl fmt::Display for ServiceError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl std::error::Error for ServiceError {}

/// The wire status code of a planner error.
pub const fn plan_error_code(e: PlanError) -> u16 {
    match e {
        PlanError::StartOutsideMap => 1,
        PlanError::GoalOutsideMap => 2,
        PlanError::StartOccupied => 3,
        PlanError::GoalOccupied => 4,
        PlanError::NoValidPath => 5,
        PlanError::CapacityExceeded => 6,
        PlanError::InvalidParameters => 7,
        PlanError::BudgetExhausted => 8,
    }
}

/// What a request may fail with on the server: a planner error or a service error.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Failure {
    /// The planner's own error (Nav2-like codes).
    Plan(PlanError),
    /// The service's error.
    Service(ServiceError),
}

impl Failure {
    /// The name printed in JSON lines.
    pub const fn name(self) -> &'static str {
        match self {
            Failure::Plan(e) => e.name(),
            Failure::Service(e) => e.name(),
        }
    }
}

impl From<PlanError> for Failure {
    fn from(e: PlanError) -> Self {
        Failure::Plan(e)
    }
}

impl From<ServiceError> for Failure {
    fn from(e: ServiceError) -> Self {
        Failure::Service(e)
    }
}

impl fmt::Display for Failure {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Failure::Plan(e) => write!(f, "{}: {e}", e.name()),
            Failure::Service(e) => f.write_str(e.name()),
        }
    }
}

impl std::error::Error for Failure {}

/// Encodes a result as a wire status code.
pub const fn status_code(result: Result<(), Failure>) -> u16 {
    match result {
        Ok(()) => STATUS_OK,
        Err(Failure::Plan(e)) => plan_error_code(e),
        Err(Failure::Service(e)) => e.code(),
    }
}

/// Decodes a wire status code; `None` for a code this build does not know.
pub fn decode_status(code: u16) -> Option<Result<(), Failure>> {
    if code == STATUS_OK {
        return Some(Ok(()));
    }
    let plan = PlanError::ALL
        .into_iter()
        .find(|e| plan_error_code(*e) == code)
        .map(Failure::Plan);
    let service = ServiceError::ALL
        .into_iter()
        .find(|e| e.code() == code)
        .map(Failure::Service);
    plan.or(service).map(Err)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn status_codes_round_trip() {
        assert_eq!(decode_status(status_code(Ok(()))), Some(Ok(())));
        for e in PlanError::ALL {
            let f = Failure::Plan(e);
            assert_eq!(decode_status(status_code(Err(f))), Some(Err(f)));
        }
        for e in ServiceError::ALL {
            let f = Failure::Service(e);
            assert_eq!(decode_status(status_code(Err(f))), Some(Err(f)));
        }
        for garbage in [9u16, 100, 111, 200, u16::MAX] {
            assert_eq!(decode_status(garbage), None, "{garbage}");
        }
    }

    /// The codes as `docs/wire.md` and the C header list them.
    #[test]
    fn codes_are_pinned() {
        let plan: Vec<(u16, &str)> = PlanError::ALL
            .iter()
            .map(|e| (plan_error_code(*e), e.name()))
            .collect();
        assert_eq!(
            plan,
            [
                (1, "StartOutsideMap"),
                (2, "GoalOutsideMap"),
                (3, "StartOccupied"),
                (4, "GoalOccupied"),
                (5, "NoValidPath"),
                (6, "CapacityExceeded"),
                (7, "InvalidParameters"),
                (8, "BudgetExhausted"),
            ]
        );
        let service: Vec<(u16, &str)> = ServiceError::ALL
            .iter()
            .map(|e| (e.code(), e.name()))
            .collect();
        assert_eq!(
            service,
            [
                (101, "UnknownMap"),
                (102, "StaleMapVersion"),
                (103, "MapTooLarge"),
                (104, "UnknownAlgorithm"),
                (105, "InvalidRequest"),
                (106, "Cancelled"),
                (107, "ServerShuttingDown"),
                (108, "DeadlineExceeded"),
                (109, "Internal"),
                (110, "UnsupportedVersion"),
            ]
        );
    }
}

//! The plan request (`planner.v1.PlanRequest`, 104 bytes, 8-aligned): the request payload of
//! the `P/plan` request-response service (its request header is `()`).

use super::{Algorithm, Guide, MAX_COUNT, MAX_RADIUS, ServiceError, WIRE_VERSION};
use iceoryx2::prelude::ZeroCopySend;
use planner_core::PlanError;
use planner_core::geometry::Cell;
use planner_core::planner::{Blend, GuideKind};
use serde::{Deserialize, Serialize};

/// What a [`PlanRequest`] asks for (wire code `u8`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[repr(u8)]
pub enum RequestKind {
    /// Plan a path.
    Plan = 0,
    /// Only check that the server holds this map id and version (answers ok or the map
    /// error); used to confirm an upload. An ok answer has no path; it names the map's
    /// size and how long the server took to build its grid from the frame.
    MapStatus = 1,
}

impl RequestKind {
    /// The wire code.
    pub const fn code(self) -> u8 {
        self as u8
    }

    /// The kind of a wire code, or [`ServiceError::InvalidRequest`].
    pub fn from_code(code: u8) -> Result<Self, ServiceError> {
        match code {
            0 => Ok(RequestKind::Plan),
            1 => Ok(RequestKind::MapStatus),
            _ => Err(ServiceError::InvalidRequest),
        }
    }
}

/// Planner parameters (32 bytes); `0` means the planner's default. Checked by
/// [`validate`](Self::validate): anything else is [`PlanError::InvalidParameters`].
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend, Serialize, Deserialize)]
#[type_name("planner.v1.PlanParams")]
#[repr(C)]
pub struct PlanParams {
    /// Robot radius in cells (finite, `0..=`[`MAX_RADIUS`]): the map is inflated so that
    /// paths keep this clearance; `0` plans for a point.
    pub radius: f32,
    /// Population size of the swarm planners, ants of the ant colony (`0`: default; at most
    /// [`MAX_COUNT`]).
    pub population: u32,
    /// Iterations of the swarm planners and the ant colony (`0`: default; at most
    /// [`MAX_COUNT`]).
    pub iterations: u32,
    /// Stop after this many iterations without improvement (`0`: run to the horizon; at
    /// most [`MAX_COUNT`]).
    pub stagnation: u32,
    /// Desired clearance from obstacles in cells of the inflated map, for the swarm
    /// planners' blended objective ([`Blend`]; finite, at least 0; `0`: no clearance term).
    pub clearance: f32,
    /// Cost per cell of path per cell of missing clearance (finite, at least 0).
    pub clearance_weight: f32,
    /// Cost in cells per radian of turning and per quarter radian of each turn (finite, at
    /// least 0; `0`: no turning term). All three `0`: length alone.
    pub turn_weight: f32,
    /// [`Guide`] code of the swarm planners' corridor encoding.
    pub guide: u8,
    /// Reserved, zero.
    pub reserved: [u8; 3],
}

impl PlanParams {
    /// The guide route, if the code names one.
    pub fn guide(&self) -> Option<GuideKind> {
        Guide::from_code(self.guide).map(Guide::kind)
    }

    /// The blended objective these fields describe.
    pub fn blend(&self) -> Blend {
        Blend {
            clearance: self.clearance,
            clearance_weight: self.clearance_weight,
            turn_weight: self.turn_weight,
        }
    }

    /// Checks every field: radius finite and within [`MAX_RADIUS`], counts within
    /// [`MAX_COUNT`], a known guide, the blended objective's terms finite and not negative,
    /// reserved bytes zero.
    pub fn validate(&self) -> Result<(), PlanError> {
        let ok = self.radius.is_finite()
            && self.blend().is_valid()
            && (0.0..=MAX_RADIUS).contains(&self.radius)
            && [self.population, self.iterations, self.stagnation]
                .iter()
                .all(|v| *v <= MAX_COUNT)
            && self.guide().is_some()
            && self.reserved == [0; 3];
        if ok {
            Ok(())
        } else {
            Err(PlanError::InvalidParameters)
        }
    }
}

/// A plan request (fixed layout, travels zero-copy).
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend, Serialize, Deserialize)]
#[type_name("planner.v1.PlanRequest")]
#[repr(C)]
pub struct PlanRequest {
    /// [`WIRE_VERSION`]; a server answers another version
    /// [`ServiceError::UnsupportedVersion`].
    pub wire_version: u16,
    /// [`RequestKind`] code.
    pub kind: u8,
    /// [`Algorithm`] code.
    pub algorithm: u8,
    /// Reserved, zero.
    pub reserved: u32,
    /// Chosen by the client; echoed in the response to match them up.
    pub request_id: u64,
    /// Seed of the random number generator (stochastic planners).
    pub seed: u64,
    /// Time budget in microseconds from the server's receipt of the request; `0` = none.
    /// A request still queued past it is answered [`ServiceError::DeadlineExceeded`].
    pub deadline_us: u64,
    /// Token of the client's wake-up event service `P/client-wake/<token as 16 hex
    /// digits>` (`0`: the client polls, do not notify).
    pub wake_token: u64,
    /// Wall-clock time (ns since the Unix epoch) until which the client polls for the
    /// answer before it sleeps on its wake event: an answer sent clearly before needs no
    /// wake-up syscall. `0`: always notify.
    pub polls_until_ns: u64,
    /// Map id.
    pub map_id: u32,
    /// Map version the client planned against.
    pub map_version: u32,
    /// Start cell `(x, y)`; anything outside the map is `StartOutsideMap`.
    pub start: [i32; 2],
    /// Goal cell `(x, y)`.
    pub goal: [i32; 2],
    /// Planner parameters.
    pub params: PlanParams,
}

impl PlanRequest {
    /// A plan request with default parameters and no deadline.
    pub fn new(map: (u32, u32), start: [i32; 2], goal: [i32; 2], algorithm: Algorithm) -> Self {
        PlanRequest {
            wire_version: WIRE_VERSION,
            kind: RequestKind::Plan.code(),
            algorithm: algorithm.code(),
            reserved: 0,
            request_id: 0,
            seed: 0,
            deadline_us: 0,
            wake_token: 0,
            polls_until_ns: 0,
            map_id: map.0,
            map_version: map.1,
            start,
            goal,
            params: PlanParams::default(),
        }
    }

    /// A map-status request for map `map.0` version `map.1`.
    pub fn map_status(map: (u32, u32)) -> Self {
        PlanRequest {
            kind: RequestKind::MapStatus.code(),
            ..PlanRequest::new(map, [0, 0], [0, 0], Algorithm::AStar)
        }
    }

    /// Checks the version and the kind: [`ServiceError::UnsupportedVersion`] or
    /// [`ServiceError::InvalidRequest`] (reserved fields not zero, unknown kind).
    pub fn kind(&self) -> Result<RequestKind, ServiceError> {
        if self.wire_version != WIRE_VERSION {
            return Err(ServiceError::UnsupportedVersion);
        }
        if self.reserved != 0 {
            return Err(ServiceError::InvalidRequest);
        }
        RequestKind::from_code(self.kind)
    }
}

/// Converts a requested `(x, y)` into a cell; out of `u16` range is outside every map.
pub fn to_cell(xy: [i32; 2], outside: PlanError) -> Result<Cell, PlanError> {
    match (u16::try_from(xy[0]), u16::try_from(xy[1])) {
        (Ok(x), Ok(y)) => Ok(Cell::new(x, y)),
        _ => Err(outside),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn params_reject_nan_negative_and_unknown_codes() {
        assert!(PlanParams::default().validate().is_ok());
        let bad = [
            PlanParams {
                radius: f32::NAN,
                ..Default::default()
            },
            PlanParams {
                radius: -1.0,
                ..Default::default()
            },
            PlanParams {
                radius: f32::INFINITY,
                ..Default::default()
            },
            PlanParams {
                radius: MAX_RADIUS + 1.0,
                ..Default::default()
            },
            PlanParams {
                iterations: MAX_COUNT + 1,
                ..Default::default()
            },
            PlanParams {
                population: u32::MAX,
                ..Default::default()
            },
            PlanParams {
                stagnation: MAX_COUNT + 1,
                ..Default::default()
            },
            // No such guide route.
            PlanParams {
                guide: 2,
                ..Default::default()
            },
            PlanParams {
                reserved: [0, 1, 0],
                ..Default::default()
            },
            PlanParams {
                clearance: f32::INFINITY,
                ..Default::default()
            },
            PlanParams {
                turn_weight: f32::NAN,
                ..Default::default()
            },
            PlanParams {
                clearance_weight: -1.0,
                ..Default::default()
            },
        ];
        for p in bad {
            assert_eq!(p.validate(), Err(PlanError::InvalidParameters), "{p:?}");
        }
        let guide = |code: u8| {
            PlanParams {
                guide: code,
                ..Default::default()
            }
            .guide()
        };
        assert_eq!(guide(0), Some(GuideKind::AnyAngle));
        assert_eq!(guide(1), Some(GuideKind::AStar));
        assert_eq!(guide(2), None);
    }

    #[test]
    fn version_reserved_and_kind_are_checked() {
        let req = PlanRequest::new((1, 1), [0, 0], [1, 1], Algorithm::AStar);
        assert_eq!(req.kind(), Ok(RequestKind::Plan));
        assert_eq!(
            PlanRequest::map_status((1, 1)).kind(),
            Ok(RequestKind::MapStatus)
        );
        let versions = [0u16, 2, u16::MAX].map(|v| PlanRequest {
            wire_version: v,
            ..req
        });
        for r in versions {
            assert_eq!(r.kind(), Err(ServiceError::UnsupportedVersion));
        }
        for r in [
            PlanRequest { kind: 2, ..req },
            PlanRequest { reserved: 1, ..req },
        ] {
            assert_eq!(r.kind(), Err(ServiceError::InvalidRequest));
        }
    }

    #[test]
    fn out_of_range_coordinates_are_outside() {
        assert_eq!(
            to_cell([-1, 0], PlanError::StartOutsideMap),
            Err(PlanError::StartOutsideMap)
        );
        assert_eq!(
            to_cell([70000, 0], PlanError::GoalOutsideMap),
            Err(PlanError::GoalOutsideMap)
        );
        assert_eq!(
            to_cell([3, 4], PlanError::GoalOutsideMap),
            Ok(Cell::new(3, 4))
        );
    }
}

//! The plan response: a header (`planner.v1.PlanResponseHeader`, 72 bytes, 8-aligned, the
//! iceoryx2 user header of the `P/plan` response) and a slice of
//! [`Waypoint`]s (`planner.v1.Waypoint`, 8 bytes: only the used ones travel). Also the owned
//! and borrowed forms of a result that the engine, the client and byte streams use.

use super::{
    Failure, MAX_WAYPOINTS, PlanRequest, STATUS_OK, WIRE_VERSION, decode_status, status_code,
};
use iceoryx2::prelude::ZeroCopySend;
use planner_core::geometry::Point;
use serde::{Deserialize, Serialize};
use std::fmt;

/// One waypoint of a response path, in cell units (the centre of cell `(x, y)` is
/// `(x, y)`).
#[derive(Debug, Clone, Copy, Default, PartialEq, ZeroCopySend, Serialize, Deserialize)]
#[type_name("planner.v1.Waypoint")]
#[repr(C)]
pub struct Waypoint {
    /// Column coordinate.
    pub x: f32,
    /// Row coordinate.
    pub y: f32,
}

/// The header of a plan response (iceoryx2 user header); the path follows as a slice of
/// [`Waypoint`]s (at most [`MAX_WAYPOINTS`]).
#[derive(Debug, Clone, Copy, PartialEq, ZeroCopySend, Serialize, Deserialize)]
#[type_name("planner.v1.PlanResponseHeader")]
#[repr(C)]
pub struct PlanResponseHeader {
    /// [`WIRE_VERSION`].
    pub wire_version: u16,
    /// Status: `0` ok, else a planner or service error code ([`super::status`]).
    pub status: u16,
    /// The request's algorithm code.
    pub algorithm: u8,
    /// The request's kind code.
    pub kind: u8,
    /// Reserved, zero.
    pub reserved: [u8; 2],
    /// The request's id.
    pub request_id: u64,
    /// Map id planned on.
    pub map_id: u32,
    /// The request's map version.
    pub map_version: u32,
    /// The newest version of this map id the server holds (`0`: none), whatever the
    /// request named: a client uploads its next version above it.
    pub held_version: u32,
    /// The width in cells of the held version (`0` when none, or rejected).
    pub map_width: u32,
    /// The height in cells of the held version (`0` when none, or rejected).
    pub map_height: u32,
    /// Waypoints in the slice (`0` unless ok and planned).
    pub waypoints: u32,
    /// Path length in cells.
    pub length: f32,
    /// Direction changes along the path.
    pub turns: u32,
    /// Cells expanded (reference searches) or objective evaluations (swarm planners).
    pub evaluations: u32,
    /// Server-side handling time of this request, microseconds.
    pub time_us: f32,
    /// How long the server took to make the held version's frame usable, microseconds (a
    /// one-time cost per map version; `0` when none).
    pub map_decode_us: f32,
    /// Reserved, zero.
    pub reserved_end: u32,
    /// The server's map limit in cells (`planner-server --max-cells`), in every answer.
    pub max_cells: u64,
}

impl Default for PlanResponseHeader {
    /// An ok header of this wire version with every other field zero.
    fn default() -> Self {
        PlanResponseHeader {
            wire_version: WIRE_VERSION,
            status: STATUS_OK,
            algorithm: 0,
            kind: 0,
            reserved: [0; 2],
            request_id: 0,
            map_id: 0,
            map_version: 0,
            held_version: 0,
            map_width: 0,
            map_height: 0,
            waypoints: 0,
            length: 0.0,
            turns: 0,
            evaluations: 0,
            time_us: 0.0,
            map_decode_us: 0.0,
            reserved_end: 0,
            max_cells: 0,
        }
    }
}

impl PlanResponseHeader {
    /// The header for `answer` to `request` from a server whose limit is `max_cells`.
    pub fn new(request: &PlanRequest, answer: &PlanAnswer<'_>, max_cells: usize) -> Self {
        let map = answer.map.unwrap_or_default();
        let mut h = PlanResponseHeader {
            wire_version: WIRE_VERSION,
            algorithm: request.algorithm,
            kind: request.kind,
            request_id: answer.request_id,
            map_id: request.map_id,
            map_version: request.map_version,
            held_version: map.version,
            map_width: map.width,
            map_height: map.height,
            map_decode_us: map.decode_us,
            time_us: answer.time_us,
            max_cells: max_cells as u64,
            ..Default::default()
        };
        match &answer.outcome {
            Ok(found) => {
                h.status = STATUS_OK;
                h.waypoints = found.path.len().min(MAX_WAYPOINTS) as u32;
                h.length = found.length;
                h.turns = found.turns;
                h.evaluations = found.evaluations;
            }
            Err(f) => h.status = status_code(Err(*f)),
        }
        h
    }

    /// What the server holds of the map id (`None`: nothing).
    pub fn map(&self) -> Option<MapFacts> {
        (self.held_version > 0).then_some(MapFacts {
            version: self.held_version,
            width: self.map_width,
            height: self.map_height,
            decode_us: self.map_decode_us,
        })
    }

    /// Decodes a received header and path into an owned result, validating the version,
    /// the status, the count and the numbers.
    pub fn decode(&self, path: &[Waypoint]) -> Result<PlanResult, DecodeError> {
        if self.wire_version != WIRE_VERSION {
            return Err(DecodeError::UnsupportedVersion(self.wire_version));
        }
        let outcome = match decode_status(self.status) {
            None => return Err(DecodeError::UnknownStatus(self.status)),
            Some(Err(f)) => Err(f),
            Some(Ok(())) => Ok(PlanView::new(self, path)?.to_owned()),
        };
        Ok(PlanResult {
            request_id: self.request_id,
            outcome,
            map: self.map(),
            time_us: self.time_us,
        })
    }
}

/// What an answer says of the map id it named: the server's newest version of it (every
/// answer from a server that holds the id, whichever version the request named).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MapFacts {
    /// The newest version held (a version from 1 up).
    pub version: u32,
    /// Width in cells (`0` for a rejected frame).
    pub width: u32,
    /// Height in cells (`0` for a rejected frame).
    pub height: u32,
    /// How long the server took to make the frame usable, microseconds.
    pub decode_us: f32,
}

/// An ok response read where it was received (the waypoints stay in shared memory),
/// checked like [`PlanResponseHeader::decode`]: the count matches, every number is finite.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanView<'a> {
    header: &'a PlanResponseHeader,
    waypoints: &'a [Waypoint],
}

impl<'a> PlanView<'a> {
    /// Checks an ok response's header and waypoints.
    pub fn new(
        header: &'a PlanResponseHeader,
        waypoints: &'a [Waypoint],
    ) -> Result<Self, DecodeError> {
        if header.wire_version != WIRE_VERSION {
            return Err(DecodeError::UnsupportedVersion(header.wire_version));
        }
        if header.status != STATUS_OK {
            return Err(DecodeError::UnknownStatus(header.status));
        }
        if header.waypoints as usize != waypoints.len()
            || waypoints.len() > MAX_WAYPOINTS
            || !header.length.is_finite()
            || !waypoints.iter().all(|p| p.x.is_finite() && p.y.is_finite())
        {
            return Err(DecodeError::BadPath);
        }
        Ok(PlanView { header, waypoints })
    }

    /// The waypoints in cell units, start first.
    pub fn waypoints(&self) -> &'a [Waypoint] {
        self.waypoints
    }

    /// The response header (length, turns, evaluations, server time).
    pub fn header(&self) -> &'a PlanResponseHeader {
        self.header
    }

    /// The owned path and metrics (copies the waypoints).
    pub fn to_owned(&self) -> PlanOk {
        PlanOk {
            path: self
                .waypoints
                .iter()
                .map(|p| Point::new(p.x, p.y))
                .collect(),
            length: self.header.length,
            turns: self.header.turns,
            evaluations: self.header.evaluations,
        }
    }
}

/// A response that does not decode.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DecodeError {
    /// A status code this build does not know.
    UnknownStatus(u16),
    /// An ok response whose path is too long or not finite.
    BadPath,
    /// A response of another wire version.
    UnsupportedVersion(u16),
}

impl fmt::Display for DecodeError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            DecodeError::UnknownStatus(c) => write!(f, "unknown status code {c}"),
            DecodeError::BadPath => f.write_str("malformed path in an ok response"),
            DecodeError::UnsupportedVersion(v) => {
                write!(f, "wire version {v}, this build speaks {WIRE_VERSION}")
            }
        }
    }
}

impl std::error::Error for DecodeError {}

/// A found path and its metrics (owned).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanOk {
    /// Waypoints in cell units, start first.
    pub path: Vec<Point>,
    /// Length (cell units).
    pub length: f32,
    /// Direction changes.
    pub turns: u32,
    /// Cells expanded or objective evaluations.
    pub evaluations: u32,
}

/// A found path borrowed from where it was planned, and its metrics.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanFound<'a> {
    /// Waypoints in cell units, start first.
    pub path: &'a [Point],
    /// Length (cell units).
    pub length: f32,
    /// Direction changes.
    pub turns: u32,
    /// Cells expanded or objective evaluations.
    pub evaluations: u32,
}

/// A result whose path is borrowed ([`PlanResult`] owns its path).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanAnswer<'a> {
    /// The request's id.
    pub request_id: u64,
    /// The path or why there is none (a map-status request's ok has no path).
    pub outcome: Result<PlanFound<'a>, Failure>,
    /// The map named, when the server holds it.
    pub map: Option<MapFacts>,
    /// Server-side handling time, microseconds.
    pub time_us: f32,
}

impl<'a> PlanAnswer<'a> {
    /// An answer that is only a failure.
    pub fn failed(request_id: u64, failure: Failure) -> Self {
        PlanAnswer {
            request_id,
            outcome: Err(failure),
            map: None,
            time_us: 0.0,
        }
    }

    /// The owned result (copies the path).
    pub fn to_owned(&self) -> PlanResult {
        PlanResult {
            request_id: self.request_id,
            outcome: self.outcome.map(|found| PlanOk {
                path: found.path.to_vec(),
                length: found.length,
                turns: found.turns,
                evaluations: found.evaluations,
            }),
            map: self.map,
            time_us: self.time_us,
        }
    }
}

/// A decoded response (owned; also the serde/postcard form of a response).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct PlanResult {
    /// The request's id.
    pub request_id: u64,
    /// The path or why there is none.
    pub outcome: Result<PlanOk, Failure>,
    /// The map named, when the server holds it.
    pub map: Option<MapFacts>,
    /// Server-side handling time, microseconds.
    pub time_us: f32,
}

impl PlanResult {
    /// The result with its path borrowed.
    pub fn borrowed(&self) -> PlanAnswer<'_> {
        PlanAnswer {
            request_id: self.request_id,
            outcome: match &self.outcome {
                Ok(ok) => Ok(PlanFound {
                    path: &ok.path,
                    length: ok.length,
                    turns: ok.turns,
                    evaluations: ok.evaluations,
                }),
                Err(f) => Err(*f),
            },
            map: self.map,
            time_us: self.time_us,
        }
    }

    /// The path as wire waypoints (empty for an error).
    pub fn waypoints(&self) -> impl Iterator<Item = Waypoint> + '_ {
        self.outcome
            .as_ref()
            .map(|ok| &ok.path[..ok.path.len().min(MAX_WAYPOINTS)])
            .unwrap_or(&[])
            .iter()
            .map(|p| Waypoint { x: p.x, y: p.y })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::wire::{Algorithm, DEFAULT_MAX_CELLS, ServiceError};
    use planner_core::PlanError;

    #[test]
    fn every_answer_carries_the_limit_and_the_map() {
        let req = PlanRequest::new((1, 1), [0, 0], [1, 1], Algorithm::AStar);
        let refused = PlanAnswer::failed(1, Failure::Service(ServiceError::MapTooLarge));
        let header = PlanResponseHeader::new(&req, &refused, DEFAULT_MAX_CELLS);
        assert_eq!(header.max_cells, 4096 * 4096);
        assert_eq!(header.map(), None);
        assert_eq!(header.decode(&[]).unwrap(), refused.to_owned());
        let status = PlanRequest::map_status((1, 1));
        let facts = MapFacts {
            version: 1,
            width: 30,
            height: 20,
            decode_us: 12.5,
        };
        let stored = PlanAnswer {
            request_id: 2,
            outcome: Ok(PlanFound {
                path: &[],
                length: 0.0,
                turns: 0,
                evaluations: 0,
            }),
            map: Some(facts),
            time_us: 1.0,
        };
        let header = PlanResponseHeader::new(&status, &stored, 100);
        assert_eq!((header.kind, header.max_cells), (1, 100));
        assert_eq!(header.map(), Some(facts));
        assert_eq!(header.decode(&[]).unwrap(), stored.to_owned());
    }

    #[test]
    fn responses_decode_and_reject_garbage() {
        let req = PlanRequest::new((1, 1), [0, 0], [1, 1], Algorithm::AStar);
        let ok = PlanResult {
            request_id: 5,
            outcome: Ok(PlanOk {
                path: vec![Point::new(0.0, 0.0), Point::new(1.0, 1.0)],
                length: core::f32::consts::SQRT_2,
                turns: 0,
                evaluations: 2,
            }),
            map: Some(MapFacts {
                version: 1,
                width: 2,
                height: 2,
                decode_us: 0.5,
            }),
            time_us: 1.5,
        };
        let mut header = PlanResponseHeader::new(&req, &ok.borrowed(), DEFAULT_MAX_CELLS);
        let mut path: Vec<Waypoint> = ok.waypoints().collect();
        assert_eq!(header.decode(&path).unwrap(), ok);
        let bytes = postcard::to_allocvec(&ok).unwrap();
        assert_eq!(postcard::from_bytes::<PlanResult>(&bytes).unwrap(), ok);
        header.waypoints = 3;
        assert_eq!(header.decode(&path).unwrap_err(), DecodeError::BadPath);
        header.waypoints = 2;
        path[1].x = f32::NAN;
        assert_eq!(header.decode(&path).unwrap_err(), DecodeError::BadPath);
        header.status = 4242;
        assert_eq!(
            header.decode(&path).unwrap_err(),
            DecodeError::UnknownStatus(4242)
        );
        header.wire_version = 2;
        assert_eq!(
            header.decode(&path).unwrap_err(),
            DecodeError::UnsupportedVersion(2)
        );
        let err = PlanResult {
            request_id: 6,
            outcome: Err(Failure::Plan(PlanError::NoValidPath)),
            map: None,
            time_us: 0.5,
        };
        let header = PlanResponseHeader::new(&req, &err.borrowed(), DEFAULT_MAX_CELLS);
        assert_eq!(err.waypoints().count(), 0);
        assert_eq!(header.decode(&[]).unwrap(), err);
    }
}

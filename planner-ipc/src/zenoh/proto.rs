//! What travels on the Zenoh keys besides wire v1's postcard types
//! ([`PlanRequest`](crate::wire::PlanRequest), [`PlanResult`](crate::wire::PlanResult),
//! [`MapMsg`](crate::wire::MapMsg)): a planner's limits, and the parts of an answer too
//! long for one message of the low-latency transport.

use serde::{Deserialize, Serialize};
use std::fmt;

/// Most payload bytes in one message of the plan session. The low-latency transport
/// cannot fragment, and a receiver closes the link that brings a message over its batch
/// size: the link's MTU, which Zenoh's TCP link derives from the TCP MSS (the largest
/// multiple of half the MSS below 65,495 bytes: 32,741 bytes on loopback, 65,160 on
/// Ethernet), so never less than about 32,700 bytes. The key (a prefix of at most
/// [`MAX_PREFIX`](super::keys::MAX_PREFIX) bytes), the attachment and Zenoh's headers fit
/// in the rest.
pub const MAX_PART: usize = 30_000;

/// Most bytes an answer may take in all its parts: far above the longest
/// [`PlanResult`](crate::wire::PlanResult) (16,384 waypoints of 8 bytes); a larger claim
/// is a malformed answer.
pub const MAX_ANSWER_BYTES: usize = 1 << 20;

/// A planner's limits (`P/@v1/info/<zid>`, postcard): what a client checks a map against
/// before sending it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct PlannerInfo {
    /// The wire version the planner speaks.
    pub wire_version: u16,
    /// The largest map it takes, cells (`planner-server --max-cells`).
    pub max_cells: u64,
    /// The largest map message its map session accepts, bytes (the postcard
    /// [`MapMsg`](crate::wire::MapMsg); Zenoh's `transport/link/rx/max_message_size`).
    pub max_map_bytes: u64,
    /// Map ids it keeps at once.
    pub max_maps: u32,
    /// Its planning threads.
    pub workers: u32,
}

/// The largest postcard [`MapMsg`](crate::wire::MapMsg) of a map of at most `max_cells`
/// cells: 5 bytes per word at worst (postcard's variable-length `u32`), the words of the
/// largest map of a side of 65,535, and the header.
pub fn map_message_limit(max_cells: usize) -> usize {
    let words = max_cells.div_ceil(32) + planner_core::grid::MAX_SIDE;
    words.saturating_mul(5).saturating_add(1024).max(1 << 16)
}

/// The attachment of one part of an answer sent in several (postcard).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub struct Part {
    /// The request the answer belongs to.
    pub request_id: u64,
    /// Which part, from 0.
    pub index: u32,
    /// How many parts.
    pub count: u32,
    /// Bytes of the whole answer.
    pub total: u32,
}

/// The parts of the answer `bytes` to `request_id`: one without a [`Part`] when it fits in
/// [`MAX_PART`], else parts of at most [`MAX_PART`] bytes each with its [`Part`].
pub fn parts(request_id: u64, bytes: &[u8]) -> Vec<(Option<Part>, &[u8])> {
    if bytes.len() <= MAX_PART {
        return vec![(None, bytes)];
    }
    let count = bytes.len().div_ceil(MAX_PART) as u32;
    bytes
        .chunks(MAX_PART)
        .enumerate()
        .map(|(i, chunk)| {
            let part = Part {
                request_id,
                index: i as u32,
                count,
                total: bytes.len() as u32,
            };
            (Some(part), chunk)
        })
        .collect()
}

/// Why the parts of an answer do not make one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum PartError {
    /// A part's attachment does not decode.
    Attachment(String),
    /// The parts claim more than [`MAX_ANSWER_BYTES`] or disagree with each other.
    Inconsistent(String),
}

impl fmt::Display for PartError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PartError::Attachment(e) => write!(f, "undecodable part attachment: {e}"),
            PartError::Inconsistent(e) => write!(f, "inconsistent answer parts: {e}"),
        }
    }
}

impl std::error::Error for PartError {}

/// Decodes a part's attachment.
pub fn part_of(attachment: &[u8]) -> Result<Part, PartError> {
    postcard::from_bytes(attachment).map_err(|e| PartError::Attachment(e.to_string()))
}

/// Collects the parts of one answer (in any order).
#[derive(Debug, Default)]
pub struct Reassembly {
    head: Option<Part>,
    parts: Vec<Option<Vec<u8>>>,
    received: usize,
}

impl Reassembly {
    /// Adds one reply's payload and attachment (`None`: a whole answer); returns the whole
    /// answer once complete.
    pub fn add(
        &mut self,
        attachment: Option<&[u8]>,
        payload: &[u8],
    ) -> Result<Option<Vec<u8>>, PartError> {
        let Some(attachment) = attachment else {
            if self.head.is_some() {
                return Err(PartError::Inconsistent("a whole answer among parts".into()));
            }
            return Ok(Some(payload.to_vec()));
        };
        let part = part_of(attachment)?;
        let bad = |what: String| Err(PartError::Inconsistent(what));
        if part.total as usize > MAX_ANSWER_BYTES {
            return bad(format!(
                "{} bytes claimed, at most {MAX_ANSWER_BYTES} expected",
                part.total
            ));
        }
        if part.count as usize != (part.total as usize).div_ceil(MAX_PART).max(1)
            || part.index >= part.count
        {
            return bad(format!(
                "{part:?} does not describe parts of {MAX_PART} bytes"
            ));
        }
        let expected_len = if part.index + 1 == part.count {
            part.total as usize - MAX_PART * part.index as usize
        } else {
            MAX_PART
        };
        if payload.len() != expected_len {
            return bad(format!(
                "part {} holds {} bytes, {expected_len} expected",
                part.index,
                payload.len()
            ));
        }
        match self.head {
            None => {
                self.head = Some(part);
                self.parts = vec![None; part.count as usize];
            }
            Some(head)
                if (head.request_id, head.count, head.total)
                    != (part.request_id, part.count, part.total) =>
            {
                return bad(format!("{part:?} after {head:?}"));
            }
            Some(_) => {}
        }
        let slot = &mut self.parts[part.index as usize];
        if slot.is_some() {
            return bad(format!("part {} twice", part.index));
        }
        *slot = Some(payload.to_vec());
        self.received += 1;
        if self.received < self.parts.len() {
            return Ok(None);
        }
        let whole: Vec<u8> = self
            .parts
            .iter_mut()
            .flat_map(|p| p.take().unwrap_or_default())
            .collect();
        Ok(Some(whole))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn feed(r: &mut Reassembly, p: &(Option<Part>, &[u8])) -> Result<Option<Vec<u8>>, PartError> {
        let a = p.0.map(|part| postcard::to_allocvec(&part).unwrap());
        r.add(a.as_deref(), p.1)
    }

    #[test]
    fn answers_split_and_join_in_any_order() {
        let small = vec![1u8; 100];
        let whole = parts(1, &small);
        assert_eq!(whole.len(), 1);
        assert_eq!(
            feed(&mut Reassembly::default(), &whole[0]).unwrap(),
            Some(small)
        );
        let big: Vec<u8> = (0..(2 * MAX_PART + 17)).map(|i| i as u8).collect();
        let mut split = parts(1, &big);
        assert_eq!(split.len(), 3);
        split.reverse();
        let mut r = Reassembly::default();
        assert_eq!(feed(&mut r, &split[0]).unwrap(), None);
        assert_eq!(feed(&mut r, &split[1]).unwrap(), None);
        assert_eq!(feed(&mut r, &split[2]).unwrap(), Some(big.clone()));
        // Garbage: a part twice, a lying size, a claim over the limit, a bad attachment.
        let mut r = Reassembly::default();
        feed(&mut r, &split[0]).unwrap();
        assert!(feed(&mut r, &split[0]).is_err());
        let short = (split[1].0, &split[1].1[..10]);
        assert!(feed(&mut Reassembly::default(), &short).is_err());
        let huge = Part {
            request_id: 1,
            index: 0,
            count: 100,
            total: (MAX_ANSWER_BYTES + 1) as u32,
        };
        assert!(feed(&mut Reassembly::default(), &(Some(huge), &big[..MAX_PART])).is_err());
        assert!(Reassembly::default().add(Some(&[0xff; 3]), &big).is_err());
    }

    #[test]
    fn map_limits_cover_the_largest_map() {
        // 4096 x 4096 cells: 524,288 words, at most 5 bytes each.
        let limit = map_message_limit(4096 * 4096);
        assert!(limit >= 524_288 * 5);
        assert!(limit < 3 << 20);
    }
}

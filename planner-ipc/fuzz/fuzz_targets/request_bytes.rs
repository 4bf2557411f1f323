//! The planner service's request handling with arbitrary payload bytes, below the
//! transport: what `planner-server` does with a received map frame (`MapHeader` user
//! header + word slice -> `grid_from_bits` for rows-only frames, `frame_grid` (+ the copy a
//! server with workers makes) for frames of both layouts -> `MapStore::update`) and a received
//! `PlanRequest` (`Engine::handle` -> `PlanResponseHeader::new` + waypoints -> the client's
//! `decode`), plus the postcard forms a byte-stream peer decodes (`MapMsg`, `PlanRequest`,
//! `PlanResult`).
//!
//! The input is a sequence of at most 8 operations (one byte each: frame, raw request,
//! postcard frame, postcard request; a length byte before slices and postcard bytes); payloads are raw bytes reinterpreted as the
//! `#[repr(C)]` wire types (every bit pattern is a value of these all-integer/float
//! structs, as it is for a peer writing shared memory). Checks: no panic; every refusal is
//! the typed error the validation rules name (kind, map, algorithm, parameters,
//! endpoints); the response header encodes a known status and decodes back to the same
//! result; an ok path starts and ends at the requested cell centres inside the map.
//!
//! Bounds for speed, not for validity: the engine takes maps of at most 32 x 32 cells (the
//! server's configurable `max_cells`), and an accepted request's swarm population and
//! iteration counts are reduced modulo small numbers before planning (huge counts are
//! valid and would only make an input slow).
#![no_main]

use arbitrary::Unstructured;
use libfuzzer_sys::fuzz_target;
use planner_core::PlanError;
use planner_core::grid::GridBuf;
use planner_core::path;
use planner_ipc::engine::{Engine, MapUpdate, Scratch};
use planner_ipc::wire::{
    Algorithm, Failure, LAYOUT_ROWS, LAYOUT_ROWS_AND_COLUMNS, MapHeader, MapMsg, PlanParams,
    PlanRequest, PlanResponseHeader, PlanResult, RequestKind, ServiceError, WIRE_VERSION,
    decode_status, first_disagreement, frame_grid, grid_from_bits, to_cell,
};
use std::cell::RefCell;
use std::collections::HashMap;

const MAX_CELLS: usize = 32 * 32;
const MAX_OPS: usize = 8;

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

fn u32_at(b: &[u8], i: usize) -> u32 {
    u32::from_le_bytes(b[i..i + 4].try_into().unwrap())
}

fn u64_at(b: &[u8], i: usize) -> u64 {
    u64::from_le_bytes(b[i..i + 8].try_into().unwrap())
}

fn f32_at(b: &[u8], i: usize) -> f32 {
    f32::from_bits(u32_at(b, i))
}

/// Up to `n` bytes, zero-padded (a short payload is the tail of a peer's write).
fn take<const N: usize>(u: &mut Unstructured<'_>) -> [u8; N] {
    let mut out = [0u8; N];
    let n = u.len().min(N);
    out[..n].copy_from_slice(u.bytes(n).unwrap_or(&[]));
    out
}

fn u16_at(b: &[u8], i: usize) -> u16 {
    u16::from_le_bytes(b[i..i + 2].try_into().unwrap())
}

/// Mostly the current wire version (a version byte below 0xf0), sometimes garbage.
fn version(raw: u16) -> u16 {
    if raw & 0xff < 0xf0 { WIRE_VERSION } else { raw }
}

/// A `MapHeader` from its 32 `#[repr(C)]` bytes (wire v1 offsets).
fn map_header(b: &[u8; 32]) -> MapHeader {
    assert_eq!(std::mem::size_of::<MapHeader>(), 32);
    MapHeader {
        wire_version: version(u16_at(b, 0)),
        // Mostly the two known layouts, sometimes garbage.
        layout: match b[2] {
            l if l < 0x80 => l % 2,
            l => l,
        },
        reserved: if b[3] < 0xf0 { 0 } else { b[3] },
        map_id: u32_at(b, 4),
        map_version: u32_at(b, 8),
        width: u32_at(b, 12),
        height: u32_at(b, 16),
        resolution: f32_at(b, 20),
        origin: [f32_at(b, 24), f32_at(b, 28)],
    }
}

/// A `PlanRequest` from its 104 `#[repr(C)]` bytes (wire v1 offsets, no padding).
fn plan_request(b: &[u8; 104]) -> PlanRequest {
    assert_eq!(std::mem::size_of::<PlanRequest>(), 104);
    PlanRequest {
        wire_version: version(u16_at(b, 0)),
        kind: b[2],
        algorithm: b[3],
        reserved: if b[4] < 0xf0 { 0 } else { u32_at(b, 4) },
        request_id: u64_at(b, 8),
        seed: u64_at(b, 16),
        deadline_us: u64_at(b, 24),
        wake_token: u64_at(b, 32),
        polls_until_ns: u64_at(b, 40),
        map_id: u32_at(b, 48),
        map_version: u32_at(b, 52),
        start: [u32_at(b, 56) as i32, u32_at(b, 60) as i32],
        goal: [u32_at(b, 64) as i32, u32_at(b, 68) as i32],
        params: PlanParams {
            radius: f32_at(b, 72),
            population: u32_at(b, 76),
            iterations: u32_at(b, 80),
            stagnation: u32_at(b, 84),
            // Mostly zero (this build plans for length only), sometimes any bits.
            clearance: if b[100] < 0xf0 { 0.0 } else { f32_at(b, 88) },
            clearance_weight: if b[101] < 0xf0 { 0.0 } else { f32_at(b, 92) },
            turn_weight: if b[102] < 0xf0 { 0.0 } else { f32_at(b, 96) },
            guide: b[100],
            reserved: if b[103] < 0xf0 { [0; 3] } else { [b[101], b[102], b[103]] },
        },
    }
}

/// What the harness knows of the store: per map id the newest version and either the base
/// grid or the rejection.
type Model = HashMap<u32, (u32, Result<GridBuf, ServiceError>)>;

fn frame(engine: &Engine, model: &mut Model, header: &MapHeader, words: &[u32]) {
    let (w, h) = (header.width as usize, header.height as usize);
    let max = engine.store.max_cells();
    let layouts = match header.layout {
        LAYOUT_ROWS => 1,
        LAYOUT_ROWS_AND_COLUMNS => 2,
        _ => 0,
    };
    let grid = match (header.check(), layouts) {
        // The server checks the version, layout and reserved byte first.
        (Err(e), _) => Err(e),
        (Ok(()), 1) => grid_from_bits(header.width, header.height, words, max),
        // The copy a server with worker threads makes (one planning inline keeps the view).
        (Ok(()), _) => frame_grid(header, words, max).map(GridBuf::from_view),
    };
    let needed = w.checked_mul(h);
    match &grid {
        Ok(g) => {
            let cells = needed.unwrap();
            assert!(w > 0 && h > 0 && cells <= MAX_CELLS);
            let n = cells.div_ceil(32);
            assert!(layouts > 0 && words.len() >= layouts * n);
            assert_eq!((g.width(), g.height()), (w, h));
            let view = g.view();
            for i in 0..cells {
                let bit = words[i / 32] >> (i % 32) & 1 == 1;
                assert_eq!(view.is_blocked((i % w) as isize, (i / w) as isize), bit);
            }
            if layouts == 2 {
                // Columns are taken as sent: the view's column runs read them.
                for x in 0..w {
                    let sent = (0..h)
                        .filter(|&y| {
                            let j = x * h + y;
                            words[n + j / 32] >> (j % 32) & 1 == 1
                        })
                        .count() as u32;
                    assert_eq!(view.column_run_count(x as isize, 0, h as isize - 1), sent);
                }
                let agree = (0..cells).all(|i| {
                    let (x, y) = (i % w, i / w);
                    let j = x * h + y;
                    (words[i / 32] >> (i % 32) & 1) == (words[n + j / 32] >> (j % 32) & 1)
                });
                assert_eq!(
                    first_disagreement(w, h, &words[..n], &words[n..2 * n]).is_none(),
                    agree
                );
            }
        }
        Err(e) => {
            let expected = if header.wire_version != WIRE_VERSION {
                ServiceError::UnsupportedVersion
            } else if layouts == 0
                || header.reserved != 0
                || header.map_version == 0
                || w == 0
                || h == 0
            {
                ServiceError::InvalidRequest
            } else if w > 65_535 || h > 65_535 || needed.is_none_or(|c| c > MAX_CELLS) {
                ServiceError::MapTooLarge
            } else {
                ServiceError::InvalidRequest // too few words for the declared size
            };
            assert_eq!(*e, expected, "frame {header:?} with {} words", words.len());
        }
    }
    let kept = grid.clone();
    let meta = header.meta();
    // Versions count from 1: a frame of version 0 is never stored.
    let newer = meta.version > 0
        && model
            .get(&meta.map_id)
            .is_none_or(|(v, _)| *v < meta.version);
    let update = engine.store.update(meta, grid);
    match update {
        MapUpdate::Outdated => assert!(!newer, "a newer version was ignored"),
        MapUpdate::Stored => {
            assert!(newer && kept.is_ok());
        }
        MapUpdate::Rejected(e) => {
            assert!(newer);
            assert_eq!(kept.as_ref().err(), Some(&e));
        }
    }
    if newer {
        // The store keeps at most 4 ids (evicting the smallest); mirror it.
        if !model.contains_key(&meta.map_id) && model.len() >= 4 {
            let victim = *model.keys().min().unwrap();
            model.remove(&victim);
        }
        model.insert(meta.map_id, (meta.version, kept));
    }
}

fn request(engine: &Engine, model: &Model, mut req: PlanRequest) {
    // Keep accepted requests fast: huge swarm counts are valid but slow.
    if req.params.validate().is_ok() {
        req.params.population %= 24;
        req.params.iterations = req.params.iterations % 12 + 1;
        req.params.stagnation %= 8;
        assert!(req.params.validate().is_ok());
    }
    let result: PlanResult =
        SCRATCH.with(|s| engine.handle(&mut s.borrow_mut(), &req, &mut || false));
    assert_eq!(result.request_id, req.request_id);

    // The expected refusal, by the documented order of checks.
    let expected: Option<Failure> = (|| {
        if req.wire_version != WIRE_VERSION {
            return Some(ServiceError::UnsupportedVersion.into());
        }
        let kind = match (req.kind, req.reserved) {
            (0, 0) => RequestKind::Plan,
            (1, 0) => RequestKind::MapStatus,
            _ => return Some(ServiceError::InvalidRequest.into()),
        };
        let Some((version, map)) = model.get(&req.map_id) else {
            return Some(ServiceError::UnknownMap.into());
        };
        if *version > req.map_version {
            return Some(ServiceError::StaleMapVersion.into());
        }
        if *version < req.map_version {
            return Some(ServiceError::UnknownMap.into());
        }
        if let Err(e) = map {
            return Some((*e).into());
        }
        if kind == RequestKind::MapStatus {
            return None;
        }
        if Algorithm::from_code(req.algorithm).is_err() {
            return Some(ServiceError::UnknownAlgorithm.into());
        }
        if req.params.validate().is_err() {
            return Some(PlanError::InvalidParameters.into());
        }
        None
    })();
    match (&expected, &result.outcome) {
        (Some(e), outcome) => assert_eq!(outcome.as_ref().err(), Some(e), "{req:?}"),
        (None, Err(Failure::Service(e))) => panic!("unexpected service error {e:?} for {req:?}"),
        (None, Err(Failure::Plan(e))) => {
            // Planner refusals are endpoint, connectivity, capacity or budget errors.
            let (_, map) = &model[&req.map_id];
            let g = map.as_ref().unwrap();
            let (w, h) = (g.width() as i64, g.height() as i64);
            let inside =
                |xy: [i32; 2]| (0..w).contains(&(xy[0] as i64)) && (0..h).contains(&(xy[1] as i64));
            match e {
                PlanError::StartOutsideMap => assert!(!inside(req.start)),
                PlanError::GoalOutsideMap => {
                    assert!(inside(req.start) && !inside(req.goal), "{req:?} on {w}x{h}")
                }
                PlanError::InvalidParameters => {
                    // Only a swarm planner's own limits (e.g. population 1) or an
                    // inflation radius the map cannot take.
                    let alg = Algorithm::from_code(req.algorithm).unwrap();
                    assert!(
                        !matches!(alg, Algorithm::AStar | Algorithm::ThetaStar)
                            || req.params.radius != 0.0,
                        "{req:?}"
                    );
                }
                _ => {}
            }
        }
        (None, Ok(ok)) => {
            let (_, map) = &model[&req.map_id];
            let g = map.as_ref().unwrap();
            if req.kind == RequestKind::MapStatus.code() {
                let facts = result.map.expect("a held map's facts");
                assert_eq!(
                    (facts.width as usize, facts.height as usize),
                    (g.width(), g.height())
                );
                assert!(ok.path.is_empty());
            } else {
                let start = to_cell(req.start, PlanError::StartOutsideMap).unwrap();
                let goal = to_cell(req.goal, PlanError::GoalOutsideMap).unwrap();
                assert_eq!(ok.path.first(), Some(&start.center()), "{req:?}");
                assert_eq!(ok.path.last(), Some(&goal.center()), "{req:?}");
                assert!(ok.length.is_finite() && ok.length >= 0.0);
                let alg = Algorithm::from_code(req.algorithm).unwrap();
                if matches!(
                    alg,
                    Algorithm::AStar | Algorithm::ThetaStar | Algorithm::AnyAngle
                ) {
                    let inflated = g.inflated(req.params.radius).unwrap();
                    assert_eq!(
                        path::validate(inflated.view(), &ok.path, start, goal),
                        Ok(()),
                        "{req:?}: {:?}",
                        ok.path
                    );
                }
            }
        }
    }

    // The response as the server writes it and the client reads it.
    let header = PlanResponseHeader::new(&req, &result.borrowed(), MAX_CELLS);
    assert!(
        decode_status(header.status).is_some(),
        "unknown status {}",
        header.status
    );
    let waypoints: Vec<_> = result.waypoints().collect();
    assert_eq!(header.waypoints as usize, waypoints.len());
    let decoded = header.decode(&waypoints).expect("own response decodes");
    assert_eq!(decoded.request_id, result.request_id);
    assert_eq!(decoded.outcome, result.outcome);
    assert_eq!(decoded.map, result.map);
    // And in the byte-stream form.
    let bytes = postcard::to_allocvec(&result).unwrap();
    let back: PlanResult = postcard::from_bytes(&bytes).unwrap();
    assert_eq!(back.outcome, result.outcome);
}

fuzz_target!(|data: &[u8]| {
    let engine = Engine::new(MAX_CELLS, 4);
    let mut model = Model::new();
    let mut u = Unstructured::new(data);
    for _ in 0..MAX_OPS {
        if u.is_empty() {
            break;
        }
        let op = u.arbitrary::<u8>().unwrap_or(0);
        match op % 4 {
            0 => {
                let header = map_header(&take::<32>(&mut u));
                // The slice length the publisher loaned, then the words (missing ones zero).
                let n = u.arbitrary::<u8>().unwrap_or(0) % 65;
                let words: Vec<u32> = (0..n)
                    .map(|_| u32::from_le_bytes(take::<4>(&mut u)))
                    .collect();
                frame(&engine, &mut model, &header, &words);
            }
            1 => request(&engine, &model, plan_request(&take::<104>(&mut u))),
            2 => {
                let len = (u.arbitrary::<u8>().unwrap_or(0) as usize).min(u.len());
                let bytes = u.bytes(len).unwrap_or(&[]);
                if let Ok(msg) = postcard::from_bytes::<MapMsg>(bytes) {
                    let header = MapHeader {
                        map_id: msg.meta.map_id,
                        map_version: msg.meta.version,
                        width: msg.width,
                        height: msg.height,
                        resolution: msg.meta.resolution,
                        origin: msg.meta.origin,
                        layout: LAYOUT_ROWS,
                        ..MapHeader::default()
                    };
                    // `MapMsg::to_grid` is `grid_from_bits` on the same fields.
                    assert_eq!(
                        msg.to_grid(MAX_CELLS),
                        grid_from_bits(msg.width, msg.height, &msg.bits, MAX_CELLS)
                    );
                    frame(&engine, &mut model, &header, &msg.bits);
                }
            }
            _ => {
                let len = (u.arbitrary::<u8>().unwrap_or(0) as usize).min(u.len());
                let bytes = u.bytes(len).unwrap_or(&[]);
                if let Ok(req) = postcard::from_bytes::<PlanRequest>(bytes) {
                    request(&engine, &model, req);
                }
            }
        }
    }
});

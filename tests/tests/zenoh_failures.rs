//! The planner service over Zenoh when things break, across real processes on 127.0.0.1:
//! a router restarted mid-run, a planner killed mid-query, a map consumer stopped
//! (SIGSTOP) while maps are published. Each ends with a typed error or the correct answer,
//! never a hang, a wrong answer or a lost map; what the client saw is printed
//! (`cargo test --test zenoh_failures -- --nocapture`).

mod common;

use common::*;
use planner_core::grid::GridBuf;
use planner_ipc::wire::{Algorithm, PlanParams, PlanRequest};
use planner_ipc::zenoh::{Mode, RequestPath, ZenohError};
use std::collections::BTreeMap;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

const T: Duration = Duration::from_secs(10);

/// Counts of errors by name.
fn tally(errors: &[ZenohError]) -> BTreeMap<&'static str, usize> {
    let mut t = BTreeMap::new();
    for e in errors {
        *t.entry(e.name()).or_default() += 1;
    }
    t
}

/// A router (`--mode router --route-only`) killed and restarted on the same port while a
/// client plans through it, in client mode (planner and client connected only to the
/// router) and in peer mode (the planner also listens, so the peers meet through gossip):
/// every request ends with the correct answer, resent (same id) after the transient
/// failures the client saw.
#[test]
fn router_restarted_mid_run() {
    for mode in [Mode::Client, Mode::Peer] {
        let p = prefix(&format!("zrestart-{mode:?}").to_lowercase());
        let router_ep = zendpoint(zport());
        let router_args = ["--mode", "router", "--route-only", "--listen", &router_ep];
        let router = start_zenoh_server(&p, &router_args);
        let planner_ep = zendpoint(zport());
        let planner_args: Vec<&str> = match mode {
            Mode::Client => vec!["--mode", "client", "--connect", &router_ep],
            _ => vec!["--connect", &router_ep, "--listen", &planner_ep],
        };
        let _planner = start_zenoh_server(&p, &planner_args);
        let mut c = zclient(&p, mode, std::slice::from_ref(&router_ep));
        wait_for_planner(&mut c);
        upload_warehouse(&mut c, 1);
        let good = PlanRequest::new((1, 1), [143, 57], [10, 16], Algorithm::AStar);
        let expected = c.plan(&good, T).unwrap();

        let done = Arc::new(AtomicUsize::new(0));
        let seen = done.clone();
        let (p2, args2) = (
            p.clone(),
            router_args
                .iter()
                .map(|s| s.to_string())
                .collect::<Vec<_>>(),
        );
        let restarter = std::thread::spawn(move || {
            let mut router = router;
            while seen.load(Ordering::Relaxed) < 100 {
                std::thread::sleep(Duration::from_millis(1));
            }
            router.kill();
            let killed_at = Instant::now();
            std::thread::sleep(Duration::from_millis(200));
            let args: Vec<&str> = args2.iter().map(String::as_str).collect();
            let router = start_zenoh_server(&p2, &args);
            (router, killed_at.elapsed())
        });
        let (mut resent, mut errors) = (0, Vec::new());
        let began = Instant::now();
        for _ in 0..400 {
            let result = c.plan_retrying(&good, T).unwrap_or_else(|e| {
                panic!("{mode:?}: failed for good: {e} (after {:?})", c.retried())
            });
            assert_eq!(
                result.outcome.as_ref(),
                Ok(&expected),
                "{mode:?}: wrong answer"
            );
            if !c.retried().is_empty() {
                resent += 1;
                errors.extend_from_slice(c.retried());
            }
            done.fetch_add(1, Ordering::Relaxed);
        }
        let (_router, restart) = restarter.join().unwrap();
        eprintln!(
            "router restarted ({mode:?} mode; new router ready {restart:?} after the kill): 400 of 400 plans correct in {:?}, {resent} resent; failures seen before the resends: {:?}",
            began.elapsed(),
            tally(&errors)
        );
        for e in &errors {
            assert!(
                e.is_transient() || matches!(e, ZenohError::NoPlanner { .. }),
                "{e}"
            );
        }
    }
}

/// A planner killed (SIGKILL) while it plans a long request: the client's query ends at
/// once with `PlannerLost`; the next request fails at once too (`NotConnected`: the
/// planner was this peer's only connection, or `NoPlanner` / `PlannerLost` while its link
/// closes); a planner started again
/// on the same endpoint never saw the map, fetches it from the client's map queryable, and
/// the request resent with its id is answered.
/// The same with the publish-subscribe pair: `PlannerLost` once the planner's liveliness
/// token is gone (checked every 20 ms while waiting).
#[test]
fn planner_killed_mid_query() {
    for path in [RequestPath::Query, RequestPath::Pair] {
        planner_killed(path);
    }
}

fn planner_killed(path: RequestPath) {
    let p = prefix(&format!("zkill-{path:?}").to_lowercase());
    let ep = zendpoint(zport());
    let planner = start_zenoh_server(&p, &["--listen", &ep]);
    let mut c = zclient_on(&p, Mode::Peer, std::slice::from_ref(&ep), path);
    wait_for_planner(&mut c);
    upload_warehouse(&mut c, 1);
    let mut slow = PlanRequest::new((1, 1), [143, 57], [10, 16], Algorithm::Tclhho);
    slow.params = PlanParams {
        population: 60,
        iterations: 1 << 20,
        ..PlanParams::default()
    };
    let killer = std::thread::spawn(move || {
        let mut planner = planner;
        std::thread::sleep(Duration::from_millis(500));
        planner.kill();
        Instant::now()
    });
    let e = c.plan(&slow, Duration::from_secs(60)).unwrap_err();
    let ended = Instant::now();
    let killed = killer.join().unwrap();
    let after_kill = ended.saturating_duration_since(killed);
    eprintln!("planner killed mid-request ({path:?}): {e}; {after_kill:?} after the kill");
    assert!(matches!(e, ZenohError::PlannerLost { .. }), "{e}");
    assert!(after_kill < Duration::from_secs(2), "{after_kill:?}");

    let good = PlanRequest::new((1, 1), [143, 57], [10, 16], Algorithm::AStar);
    let began = Instant::now();
    let e = c.plan(&good, T).unwrap_err();
    eprintln!("next request ({path:?}): {e} after {:?}", began.elapsed());
    // NotConnected once the planner's link is gone (it was this peer's only one), NoPlanner
    // while Zenoh still lists the closing link, PlannerLost while the dead planner's token
    // still shows (within 20 ms of its going): all at once.
    assert!(
        matches!(
            e,
            ZenohError::NotConnected { .. }
                | ZenohError::NoPlanner { .. }
                | ZenohError::PlannerLost { .. }
        ),
        "{e}"
    );
    assert!(began.elapsed() < Duration::from_secs(1));

    let again = start_zenoh_server(&p, &["--listen", &ep]);
    let result = c.plan_retrying(&good, T).unwrap();
    assert!(result.outcome.is_ok(), "{:?}", result.outcome);
    eprintln!(
        "restarted planner answered ({path:?}) after {} resend(s): {:?}",
        c.retried().len(),
        tally(c.retried())
    );
    assert!(
        again.log_text().contains("fetched from its owner"),
        "{}",
        again.log_text()
    );
}

/// A map `version` of 2048 x 2048 cells: noise above row 1200 (so that messages are large
/// and do not compress), open below but for a wall on row 1600 with a gap whose column
/// depends on the version.
fn versioned_map(version: u32) -> (GridBuf, usize) {
    let (w, h) = (2048usize, 2048usize);
    let gap = 1100 + (version as usize * 37) % 800;
    let mut grid = GridBuf::new(w, h).unwrap();
    let mut state = 0x9E37_79B9_7F4A_7C15u64 ^ u64::from(version);
    grid.view_mut()
        .fill_rows(|y, words| {
            if y < 1200 {
                for word in words.iter_mut() {
                    state ^= state << 13;
                    state ^= state >> 7;
                    state ^= state << 17;
                    *word = state as u32 & 0x1111_1111;
                }
            } else if y == 1600 {
                words.fill(u32::MAX);
            }
        })
        .unwrap();
    grid.set_blocked(gap, 1600, false).unwrap();
    (grid, gap)
}

/// A map consumer stopped (SIGSTOP) while 30 versions of a 2048 x 2048 map are published:
/// no publication blocks the sender (congestion control `Drop` on the map session), and
/// once resumed the planner answers on the last version, fetching it from the owner when
/// it missed it: nothing is lost.
#[test]
fn slow_map_consumer_loses_nothing() {
    let p = prefix("zslow");
    let ep = zendpoint(zport());
    let planner = start_zenoh_server(&p, &["--listen", &ep]);
    let mut c = zclient(&p, Mode::Peer, std::slice::from_ref(&ep));
    wait_for_planner(&mut c);
    let (grid, _) = versioned_map(1);
    c.upload_map(meta(1, 1), grid.view()).unwrap();
    c.wait_for_map(1, 1, T).unwrap();
    let maps: Vec<(GridBuf, usize)> = (2..=30).map(versioned_map).collect();

    planner.stop();
    let mut slowest = Duration::ZERO;
    let began = Instant::now();
    for (v, (grid, _)) in (2..=30).zip(&maps) {
        let t = Instant::now();
        c.upload_map(meta(1, v), grid.view()).unwrap();
        slowest = slowest.max(t.elapsed());
    }
    let publishing = began.elapsed();
    std::thread::sleep(Duration::from_millis(300));
    planner.signal("CONT");
    eprintln!(
        "29 map versions published to a stopped planner in {publishing:?}, the slowest upload {slowest:?}"
    );
    assert!(slowest < Duration::from_millis(500), "{slowest:?}");

    // The last version: straight through its gap; through the previous version's gap, bent.
    let gap = maps[maps.len() - 1].1 as i32;
    let theta = |x: i32| PlanRequest::new((1, 30), [x, 1300], [x, 2047], Algorithm::ThetaStar);
    let through = c.plan_retrying(&theta(gap), T).unwrap().outcome.unwrap();
    assert_eq!(through.path.len(), 2, "{:?}", through.path);
    let old_gap = maps[maps.len() - 2].1 as i32;
    let old = c
        .plan_retrying(&theta(old_gap), T)
        .unwrap()
        .outcome
        .unwrap();
    assert!(old.path.len() > 2 && old.length > 748.0, "{:?}", old.path);
    let log = planner.log_text();
    let stored = log.matches("map 1 version").count();
    eprintln!(
        "the planner logged {stored} map line(s); fetched from the owner: {}; missed versions noticed: {}",
        log.matches("fetched from its owner").count(),
        log.matches("missed").count()
    );
}

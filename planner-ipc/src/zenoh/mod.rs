//! The planner service over Zenoh (feature `zenoh`): the same [`Engine`](crate::engine::Engine)
//! and wire v1 postcard types as the iceoryx2 service, reachable from other hosts.
//!
//! - [`keys`]: the key expressions (`P/@v1/plan`, `P/@v1/map/<id>`, `P/@v1/alive/<zid>`,
//!   `P/@v1/info/<zid>`);
//! - [`config`]: the sessions' settings (the low-latency plan session, the map session on
//!   the next port, the one-worker runtime);
//! - [`proto`]: the planner's limits and the parts of long answers;
//! - [`server`]: the front end of an engine (`planner-server --transport zenoh|both`);
//! - [`client`]: [`ZenohClient`] (`planner-client --transport zenoh`).
//!
//! `docs/zenoh.md` describes the keys, the settings, the failure behaviour and the
//! measurements.

pub mod client;
pub mod config;
pub mod keys;
pub mod proto;
pub mod server;

pub use client::{ClientConfig, RequestPath, ZenohClient, ZenohError};
pub use config::{Mode, ZenohOptions};
pub use keys::Keys;
pub use proto::{MAX_PART, PlannerInfo};

#[cfg(test)]
mod tests {
    use super::config::free_port_pair;
    use super::server::{self, ServerConfig};
    use super::*;
    use crate::engine::{Engine, Scratch};
    use crate::wire::{Algorithm, DEFAULT_MAX_CELLS, MapMeta, PlanRequest, ServiceError};
    use planner_core::grid::GridBuf;
    use std::sync::Arc;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::time::{Duration, Instant};

    /// A corridor winding through a `w x h` map: walls on every odd row, open at the right
    /// end on rows 1, 5, 9, ... and at the left end on rows 3, 7, 11, ...: A* lists every
    /// cell of it, so the path is long.
    fn serpentine(w: usize, h: usize) -> GridBuf {
        let mut g = GridBuf::new(w, h).unwrap();
        for y in (1..h).step_by(2) {
            let gap = if (y / 2) % 2 == 0 { w - 1 } else { 0 };
            for x in (0..w).filter(|&x| x != gap) {
                g.set_blocked(x, y, true).unwrap();
            }
        }
        g
    }

    /// A planner and a client in this process over loopback: answers equal the engine's
    /// own, a path over the low-latency transport's message limit arrives in parts, a
    /// request resent with its id gets the kept answer, a map published before the planner
    /// existed is fetched from its owner, and after shutdown there is no planner.
    #[test]
    fn planner_and_client_in_one_process() {
        let port = free_port_pair().unwrap();
        let endpoint = format!("tcp/127.0.0.1:{port}");
        let prefix = format!("unit-{}-zenoh", std::process::id());
        let mut client = ZenohClient::open(ClientConfig {
            prefix: prefix.clone(),
            ..ClientConfig::connect_to(&endpoint)
        })
        .unwrap();
        // No planner yet: a typed error at once (nothing listens at the endpoint).
        let began = Instant::now();
        let no = client.check_planners().unwrap_err();
        assert!(matches!(no, ZenohError::NotConnected { .. }), "{no}");
        assert!(began.elapsed() < Duration::from_secs(2));
        // The map is published before any planner runs: the planner fetches it later.
        let grid = serpentine(128, 121);
        let meta = MapMeta {
            map_id: 3,
            version: 1,
            resolution: 0.05,
            origin: [0.0, 0.0],
        };
        client.upload_map(meta, grid.view()).unwrap();

        let shutdown = Arc::new(AtomicBool::new(false));
        let engine = Arc::new(Engine::new(DEFAULT_MAX_CELLS, 16));
        let config = ServerConfig {
            prefix: prefix.clone(),
            options: ZenohOptions {
                listen: vec![endpoint.clone()],
                ..ZenohOptions::default()
            },
            ..ServerConfig::default()
        };
        let stop = shutdown.clone();
        let planner = std::thread::spawn(move || server::run(&config, engine, stop));
        let began = Instant::now();
        while client.check_planners().is_err() {
            assert!(began.elapsed() < Duration::from_secs(20), "no planner");
            std::thread::sleep(Duration::from_millis(20));
        }
        assert_eq!(client.planners().len(), 1);
        let limits = client.limits().unwrap();
        assert_eq!(limits.max_cells, DEFAULT_MAX_CELLS as u64);
        let facts = client.wait_for_map(3, 1, Duration::from_secs(10)).unwrap();
        assert_eq!((facts.width, facts.height), (128, 121));

        let local = Engine::new(DEFAULT_MAX_CELLS, 4);
        local.store.update(meta, Ok(grid.clone()));
        let mut scratch = Scratch::default();
        for (algo, goal) in [
            (Algorithm::AStar, [0, 120]),
            (Algorithm::ThetaStar, [127, 40]),
            (Algorithm::Tclhho, [5, 60]),
        ] {
            let mut request = PlanRequest::new((3, 1), [0, 0], goal, algo);
            request.seed = 11;
            let got = client
                .plan_result(&request, Duration::from_secs(20))
                .unwrap();
            request.request_id = got.request_id;
            request.deadline_us = 20_000_000;
            let want = local.handle(&mut scratch, &request, &mut || false);
            assert_eq!(got.outcome, want.outcome, "{algo:?}");
        }
        // The A* answer lists about 7,800 cells: over 60,000 bytes, so it came in parts.
        let request = PlanRequest::new((3, 1), [0, 0], [0, 120], Algorithm::AStar);
        let got = client
            .plan_result(&request, Duration::from_secs(20))
            .unwrap();
        let bytes = postcard::to_allocvec(&got).unwrap().len();
        assert!(bytes > MAX_PART, "{bytes} bytes");

        // The publish-subscribe pair: the same answers, the long one in parts too.
        let mut pair = ZenohClient::open(ClientConfig {
            prefix: prefix.clone(),
            path: RequestPath::Pair,
            ..ClientConfig::connect_to(&endpoint)
        })
        .unwrap();
        let began = Instant::now();
        while pair.check_planners().is_err() {
            assert!(began.elapsed() < Duration::from_secs(20), "no planner");
            std::thread::sleep(Duration::from_millis(20));
        }
        let by_pair = pair.plan_result(&request, Duration::from_secs(20)).unwrap();
        assert_eq!(by_pair.outcome, got.outcome);
        let theta = PlanRequest::new((3, 1), [0, 0], [127, 40], Algorithm::ThetaStar);
        assert_eq!(
            pair.plan_result(&theta, Duration::from_secs(5))
                .unwrap()
                .outcome,
            client
                .plan_result(&theta, Duration::from_secs(5))
                .unwrap()
                .outcome
        );

        // A request resent with its id is answered as before (the planner's time too).
        let mut again = PlanRequest::new((3, 1), [0, 0], [127, 120], Algorithm::ThetaStar);
        again.request_id = 0xfeed_0001;
        let first = client.plan_as_is(&again, Duration::from_secs(5)).unwrap();
        let second = client.plan_as_is(&again, Duration::from_secs(5)).unwrap();
        assert_eq!(first, second);
        // The same id with other fields is another request: planned, not repeated.
        again.goal = [126, 120];
        let other = client.plan_as_is(&again, Duration::from_secs(5)).unwrap();
        assert_ne!(other.outcome, first.outcome);
        // A version nobody published: UnknownMap after asking the owner.
        let stale = PlanRequest::new((3, 9), [0, 0], [1, 0], Algorithm::AStar);
        assert_eq!(
            client.plan(&stale, Duration::from_secs(5)),
            Err(ZenohError::Service(ServiceError::UnknownMap))
        );

        shutdown.store(true, Ordering::Relaxed);
        planner.join().unwrap().unwrap();
        let began = Instant::now();
        loop {
            match client.plan(&request, Duration::from_secs(2)) {
                Err(ZenohError::NoPlanner { .. }) | Err(ZenohError::NotConnected { .. }) => break,
                other => assert!(
                    began.elapsed() < Duration::from_secs(5),
                    "still answered after shutdown: {other:?}"
                ),
            }
            std::thread::sleep(Duration::from_millis(20));
        }
    }
}

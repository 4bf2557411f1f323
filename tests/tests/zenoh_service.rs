//! The planner service over Zenoh across real processes on 127.0.0.1 (ports chosen free at
//! run time): `planner-server --transport zenoh|both` (linked here as `ipc-test-server`),
//! clients in this test process and in the `planner-client` CLI (`ipc-test-client`), peer
//! to peer and through a router of our own; the same paths as the engine in this process
//! and as over iceoryx2; no planner, oversized maps, and a stopped planner.

mod common;

use common::*;
use planner_core::grid::GridBuf;
use planner_ipc::client::{MapTooLarge, Refusal, parse_map};
use planner_ipc::engine::{Engine, Scratch};
use planner_ipc::wire::{Algorithm, DEFAULT_MAX_CELLS, MapMsg, PlanRequest, pack_map};
use planner_ipc::zenoh::{Mode, RequestPath, ZenohError};
use std::process::Command;
use std::time::{Duration, Instant};

const T: Duration = Duration::from_secs(10);

/// Requests on the warehouse map, each planner kind, answered by the engine in this
/// process; compared with what came over Zenoh.
fn check_against_engine(client: &mut planner_ipc::zenoh::ZenohClient, map: (u32, u32)) {
    let grid = parse_map(&std::fs::read(data(WAREHOUSE)).unwrap()).unwrap();
    let local = Engine::new(DEFAULT_MAX_CELLS, 4);
    local.store.update(meta(map.0, map.1), Ok(grid));
    let mut scratch = Scratch::default();
    for (algo, start, goal) in [
        (Algorithm::AStar, [143, 57], [10, 16]),
        (Algorithm::ThetaStar, [143, 57], [10, 16]),
        (Algorithm::Tclhho, [143, 57], [10, 16]),
        // Occupied start: a typed planner error, as the engine says.
        (Algorithm::AStar, [14, 12], [10, 16]),
    ] {
        let mut request = PlanRequest::new(map, start, goal, algo);
        request.seed = 5;
        let got = client.plan_result(&request, T).unwrap();
        request.request_id = got.request_id;
        request.deadline_us = T.as_micros() as u64;
        let want = local.handle(&mut scratch, &request, &mut || false);
        assert_eq!(got.outcome, want.outcome, "{algo:?} {start:?} -> {goal:?}");
    }
}

/// Runs `planner-client` and returns its JSON lines (it must succeed).
fn cli(args: &[&str]) -> Vec<serde_json::Value> {
    let out = Command::new(env!("CARGO_BIN_EXE_ipc-test-client"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "planner-client {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

/// The line without its timing.
fn untimed(mut line: serde_json::Value) -> serde_json::Value {
    let fields = line.as_object_mut().unwrap();
    fields.remove("time_us");
    fields.remove("round_trip_us");
    line
}

/// Peer to peer: a planner listening, a client connecting to it; plans equal the engine's,
/// and the CLI prints the same line as over iceoryx2 would (the keys of `plan`).
#[test]
fn peer_to_peer_plans() {
    let p = prefix("zpeer");
    let ep = zendpoint(zport());
    let server = start_zenoh_server(&p, &["--listen", &ep]);
    let mut c = zclient(&p, Mode::Peer, std::slice::from_ref(&ep));
    wait_for_planner(&mut c);
    upload_warehouse(&mut c, 1);
    check_against_engine(&mut c, (1, 1));
    // The publish-subscribe pair: the same answers.
    let mut pair = zclient_on(&p, Mode::Peer, std::slice::from_ref(&ep), RequestPath::Pair);
    wait_for_planner(&mut pair);
    check_against_engine(&mut pair, (1, 1));

    let map = data(WAREHOUSE);
    let map = map.to_str().unwrap();
    let lines = cli(&[
        "--transport",
        "zenoh",
        "--connect",
        &ep,
        "--prefix",
        &p,
        "plan",
        "--map",
        map,
        "--map-id",
        "2",
        "--start",
        "143,57",
        "--goal",
        "10,16",
        "--algo",
        "tclhho",
        "--seed",
        "5",
    ]);
    assert_eq!(lines.len(), 1);
    assert_eq!(line_keys(&lines[0]), PLAN_LINE_KEYS);
    let mut request = PlanRequest::new((2, 1), [143, 57], [10, 16], Algorithm::Tclhho);
    request.seed = 5;
    let ok = c.plan(&request, T).unwrap();
    let path: Vec<[f32; 2]> = lines[0]["path"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| [p[0].as_f64().unwrap() as f32, p[1].as_f64().unwrap() as f32])
        .collect();
    let want: Vec<[f32; 2]> = ok.path.iter().map(|p| [p.x, p.y]).collect();
    assert_eq!(path.len(), want.len());
    for (a, b) in path.iter().zip(&want) {
        assert!(
            (a[0] - b[0]).abs() < 1e-3 && (a[1] - b[1]).abs() < 1e-3,
            "{a:?} {b:?}"
        );
    }
    drop(server);
}

/// Through a router of our own (`--mode router --route-only`): planner and client both in
/// client mode, connected only to the router; the CLI in client mode too.
#[test]
fn plans_through_a_router() {
    let p = prefix("zrouter");
    let router_ep = zendpoint(zport());
    let router = start_zenoh_server(
        &p,
        &["--mode", "router", "--route-only", "--listen", &router_ep],
    );
    assert!(router.log_text().contains("router only"));
    let _planner = start_zenoh_server(&p, &["--mode", "client", "--connect", &router_ep]);
    let mut c = zclient(&p, Mode::Client, std::slice::from_ref(&router_ep));
    wait_for_planner(&mut c);
    upload_warehouse(&mut c, 1);
    check_against_engine(&mut c, (1, 1));
    let map = data(WAREHOUSE);
    let lines = cli(&[
        "--transport",
        "zenoh",
        "--mode",
        "client",
        "--connect",
        &router_ep,
        "--prefix",
        &p,
        "plan",
        "--map",
        map.to_str().unwrap(),
        "--map-id",
        "3",
        "--start",
        "143,57",
        "--goal",
        "10,16",
        "--algo",
        "theta",
    ]);
    assert!(lines[0]["length"].as_f64().unwrap() > 100.0, "{}", lines[0]);
}

/// One server, both transports (`--transport both`, one engine): the same request and seed
/// give the same path over Zenoh as over iceoryx2, in the library and in the CLI.
#[test]
fn same_path_over_zenoh_as_over_iceoryx2() {
    let p = prefix("zboth");
    let ep = zendpoint(zport());
    let _server = start_server(&p, &["--transport", "both", "--listen", &ep]);
    let mut z = zclient(&p, Mode::Peer, std::slice::from_ref(&ep));
    wait_for_planner(&mut z);
    let mut ice = client(&p);
    let grid = parse_map(&std::fs::read(data(WAREHOUSE)).unwrap()).unwrap();
    // The map goes in over iceoryx2 only: the Zenoh front end plans on the same store.
    ice.upload_map(meta(1, 1), grid.view()).unwrap();
    ice.wait_for_map(1, 1, T).unwrap();
    z.wait_for_map(1, 1, T).unwrap();
    for (algo, seed) in [
        (Algorithm::Tclhho, 7),
        (Algorithm::Igwo, 3),
        (Algorithm::ThetaStar, 0),
        (Algorithm::AStar, 0),
    ] {
        let mut r = PlanRequest::new((1, 1), [143, 57], [10, 16], algo);
        r.seed = seed;
        let over_ice = ice.plan(&r, T).unwrap();
        let over_zenoh = z.plan(&r, T).unwrap();
        assert_eq!(over_ice, over_zenoh, "{algo:?} seed {seed}");
    }
    // The CLI: the same line over both transports, timing aside.
    let map = data(WAREHOUSE);
    let map = map.to_str().unwrap();
    let common = [
        "plan", "--map", map, "--start", "143,57", "--goal", "10,16", "--algo", "tclhho", "--seed",
        "7",
    ];
    let mut over_ice = vec!["--prefix", &p, "--transport", "iceoryx2"];
    over_ice.extend(common);
    over_ice.extend(["--map-id", "5"]);
    let mut over_zenoh = vec!["--prefix", &p, "--transport", "zenoh", "--connect", &ep];
    over_zenoh.extend(common);
    over_zenoh.extend(["--map-id", "6"]);
    let a = cli(&over_ice);
    let b = cli(&over_zenoh);
    assert_eq!(untimed(a[0].clone()), untimed(b[0].clone()));
    over_zenoh.extend(["--request", "pair"]);
    let c = cli(&over_zenoh);
    assert_eq!(untimed(a[0].clone()), untimed(c[0].clone()));
}

/// No planner: a client connected to a router without planners gets `NoPlanner` at once,
/// one with nothing at its endpoint `NotConnected` at once; the CLI exits with status 1
/// naming it.
#[test]
fn no_planner_is_a_typed_error_at_once() {
    let p = prefix("znone");
    let router_ep = zendpoint(zport());
    let _router = start_zenoh_server(
        &p,
        &["--mode", "router", "--route-only", "--listen", &router_ep],
    );
    let r = PlanRequest::new((1, 1), [0, 0], [1, 1], Algorithm::AStar);
    for mode in [Mode::Client, Mode::Peer] {
        let mut c = zclient(&p, mode, std::slice::from_ref(&router_ep));
        let began = Instant::now();
        let e = c.plan(&r, T).unwrap_err();
        let took = began.elapsed();
        eprintln!("no planner, {mode:?} mode: {e} after {took:?}");
        assert!(matches!(e, ZenohError::NoPlanner { .. }), "{e}");
        assert!(took < Duration::from_secs(1), "{took:?}");
    }
    let nobody = zendpoint(zport());
    let mut c = zclient(&p, Mode::Peer, std::slice::from_ref(&nobody));
    let began = Instant::now();
    let e = c.plan(&r, T).unwrap_err();
    eprintln!("nothing at the endpoint: {e} after {:?}", began.elapsed());
    assert!(matches!(e, ZenohError::NotConnected { .. }), "{e}");
    assert!(began.elapsed() < Duration::from_secs(1));
    // A client-mode session finds no router: NotConnected when opening.
    let opened = planner_ipc::zenoh::ZenohClient::open(planner_ipc::zenoh::ClientConfig {
        prefix: p.clone(),
        options: planner_ipc::zenoh::ZenohOptions {
            mode: Mode::Client,
            connect: vec![nobody.clone()],
            ..Default::default()
        },
        ..Default::default()
    });
    assert!(matches!(opened, Err(ZenohError::NotConnected { .. })));
    let out = Command::new(env!("CARGO_BIN_EXE_ipc-test-client"))
        .args([
            "--transport",
            "zenoh",
            "--connect",
            &router_ep,
            "--prefix",
            &p,
        ])
        .args(["plan", "--map"])
        .arg(data(WAREHOUSE))
        .args(["--start", "143,57", "--goal", "10,16"])
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains("no planner is alive"), "{stderr}");
}

/// Oversized maps: the sender refuses a map over the planner's cell limit before sending,
/// naming the limit; a map message sent anyway (bypassing the check) is refused by the
/// planner, and a map-status request names the refusal and the limit: never a silent drop.
#[test]
fn oversized_maps_are_refused_with_the_limit() {
    let p = prefix("zlarge");
    let ep = zendpoint(zport());
    let server = start_zenoh_server(&p, &["--listen", &ep, "--max-cells", "10000"]);
    let mut c = zclient(&p, Mode::Peer, std::slice::from_ref(&ep));
    wait_for_planner(&mut c);
    assert_eq!(c.limits().unwrap().max_cells, 10_000);
    let over = GridBuf::new(101, 100).unwrap();
    let e = c.upload_map(meta(1, 1), over.view()).unwrap_err();
    assert_eq!(
        e,
        ZenohError::MapTooLarge(MapTooLarge {
            size: Some((101, 100)),
            max_cells: Some(10_000),
            refused_by: Refusal::Client,
        })
    );
    assert_eq!(
        e.to_string(),
        "map 101 x 100 (10100 cells) exceeds the planner service's limit of 10000 cells \
         (100 x 100); start planner-server with --max-cells 10100 or more to accept it (not sent)"
    );
    // At the limit: accepted.
    let fits = GridBuf::new(100, 100).unwrap();
    c.upload_map(meta(2, 1), fits.view()).unwrap();
    c.wait_for_map(2, 1, T).unwrap();
    // Sent anyway as a raw message: the planner refuses and says so when asked.
    let mut words = Vec::new();
    let header = pack_map(meta(3, 1), over.view(), &mut words);
    c.publish_msg(&MapMsg::new(&header, &words)).unwrap();
    let e = c.wait_for_map(3, 1, T).unwrap_err();
    assert_eq!(
        e,
        ZenohError::MapTooLarge(MapTooLarge {
            size: None,
            max_cells: Some(10_000),
            refused_by: Refusal::Server,
        })
    );
    let began = Instant::now();
    while !server
        .log_text()
        .contains("map 3 version 1 rejected: MapTooLarge")
    {
        assert!(began.elapsed() < T, "{}", server.log_text());
        std::thread::sleep(Duration::from_millis(10));
    }
}

/// A planner stopped (SIGSTOP) with a request in flight: the client gets `Timeout` at the
/// request's deadline plus the margin, naming both, and no hang (queries and the pair);
/// after SIGCONT it answers.
#[test]
fn a_stopped_planner_times_out_at_the_deadline() {
    for path in [RequestPath::Query, RequestPath::Pair] {
        stopped_planner_times_out(path);
    }
}

fn stopped_planner_times_out(path: RequestPath) {
    let p = prefix(&format!("zstop-{path:?}").to_lowercase());
    let ep = zendpoint(zport());
    let server = start_zenoh_server(&p, &["--listen", &ep]);
    let mut c = zclient_on(&p, Mode::Peer, std::slice::from_ref(&ep), path);
    wait_for_planner(&mut c);
    upload_warehouse(&mut c, 1);
    let mut r = PlanRequest::new((1, 1), [143, 57], [10, 16], Algorithm::AStar);
    r.deadline_us = 300_000;
    server.stop();
    let began = Instant::now();
    let answer = c.plan(&r, T);
    let took = began.elapsed();
    server.signal("CONT");
    let e = match answer {
        Err(e) => e,
        Ok(ok) => panic!("{path:?}: a stopped planner answered after {took:?}: {ok:?}"),
    };
    eprintln!("stopped planner ({path:?}): {e} after {took:?}");
    match &e {
        ZenohError::Timeout {
            deadline, margin, ..
        } => {
            assert_eq!(*deadline, Duration::from_millis(300));
            let due = *deadline + *margin;
            assert!(
                took >= due && took < due + Duration::from_secs(1),
                "{took:?}"
            );
        }
        other => panic!("{other}"),
    }
    assert!(
        e.to_string()
            .contains("its deadline 300 ms plus a 250 ms margin")
    );
    c.plan(&r, T).unwrap();
}

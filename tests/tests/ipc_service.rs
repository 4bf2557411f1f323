//! The planner service across real processes: one `planner-server` process (linked here
//! as `ipc-test-server`), clients in this test process, in `ipc-test-driver` processes and
//! in the `planner-client` CLI (`ipc-test-client`).

mod common;

use common::*;
use planner_core::PlanError;
use planner_core::grid::GridBuf;
use planner_ipc::client::{ClientError, MapTooLarge, Refusal, parse_map};
use planner_ipc::wire::{
    Algorithm, LAYOUT_ROWS, LAYOUT_ROWS_AND_COLUMNS, MapHeader, MapMeta, PlanParams, PlanRequest,
    RequestKind, ServiceError,
};
use std::process::Command;
use std::time::{Duration, Instant};

const WAREHOUSE: &str = "warehouse-10-20-10-2-1.map";
const T: Duration = Duration::from_secs(5);

fn req(map: (u32, u32), start: [i32; 2], goal: [i32; 2], algo: Algorithm) -> PlanRequest {
    PlanRequest::new(map, start, goal, algo)
}

/// Garbage in every field a peer controls: map frames whose declared size does not match
/// the words sent (beyond them, overflowing, zero, beyond capacity) and requests with
/// out-of-range enums, counts beyond their limits, fractional counts, NaN/inf/negative
/// floats and extreme coordinates. Each gets its typed error, the server keeps serving.
#[test]
fn garbage_fields_get_typed_errors() {
    let p = prefix("garbage");
    let server = start_server(&p, &["--max-cells", "100000"]);
    let mut c = client(&p);
    let v1 = c.upload_map_file(&data(WAREHOUSE), 1).unwrap();
    c.wait_for_map(1, v1, T).unwrap();
    let good = req((1, v1), [143, 57], [10, 16], Algorithm::AStar);
    let ok = c.plan(&good, T).unwrap();

    let frame = |id: u32, width: u32, height: u32| MapHeader {
        map_id: id,
        map_version: 1,
        width,
        height,
        resolution: f32::NAN,
        origin: [f32::INFINITY, f32::NAN],
        layout: LAYOUT_ROWS,
        ..MapHeader::default()
    };
    let with_layout = |header: MapHeader, layout: u8| MapHeader { layout, ..header };
    let frames: Vec<(MapHeader, Vec<u32>, ServiceError)> = vec![
        // 64 x 64 cells need 128 words; 3 sent.
        (
            frame(10, 64, 64),
            vec![u32::MAX; 3],
            ServiceError::InvalidRequest,
        ),
        // Zero sides.
        (frame(11, 0, 64), vec![0; 8], ServiceError::InvalidRequest),
        (frame(12, 64, 0), vec![0; 8], ServiceError::InvalidRequest),
        // Sizes whose product overflows 32 bits, or exceeds the frame and server capacity.
        (
            frame(13, u32::MAX, u32::MAX),
            vec![0; 8],
            ServiceError::MapTooLarge,
        ),
        (
            frame(14, 1 << 16, 1 << 16),
            vec![0; 8],
            ServiceError::MapTooLarge,
        ),
        (frame(15, 400, 300), vec![0; 8], ServiceError::MapTooLarge),
        // Layouts: unknown; both announced but only the rows (or less) sent.
        (
            with_layout(frame(17, 4, 4), 0xef),
            vec![0; 8],
            ServiceError::InvalidRequest,
        ),
        // Another wire version; a reserved byte set.
        (
            MapHeader {
                wire_version: 7,
                ..frame(22, 4, 4)
            },
            vec![0; 8],
            ServiceError::UnsupportedVersion,
        ),
        (
            MapHeader {
                reserved: 1,
                ..frame(23, 4, 4)
            },
            vec![0; 8],
            ServiceError::InvalidRequest,
        ),
        (
            with_layout(frame(18, 64, 64), LAYOUT_ROWS_AND_COLUMNS),
            vec![0; 128],
            ServiceError::InvalidRequest,
        ),
        (
            with_layout(frame(19, 64, 64), LAYOUT_ROWS_AND_COLUMNS),
            vec![0; 255],
            ServiceError::InvalidRequest,
        ),
        (
            with_layout(frame(20, 400, 300), LAYOUT_ROWS_AND_COLUMNS),
            vec![0; 7500],
            ServiceError::MapTooLarge,
        ),
    ];
    for (header, words, want) in &frames {
        // Raw frames are sent as they are (no client-side check): the server judges them.
        c.publish_map(header, words).unwrap();
        let want = match want {
            ServiceError::MapTooLarge => ClientError::MapTooLarge(MapTooLarge {
                size: Some((header.width, header.height)),
                max_cells: Some(100_000),
                refused_by: Refusal::Server,
            }),
            other => ClientError::Service(*other),
        };
        assert_eq!(
            c.wait_for_map(header.map_id, 1, T),
            Err(want),
            "{header:?} with {} words",
            words.len()
        );
        assert_eq!(c.plan(&good, T).as_ref(), Ok(&ok), "server stopped serving");
    }
    // NaN metadata is informational only: a frame with enough words is stored, in either
    // layout.
    c.publish_map(&frame(16, 4, 4), &[0]).unwrap();
    c.wait_for_map(16, 1, T).unwrap();
    c.publish_map(
        &with_layout(frame(21, 4, 4), LAYOUT_ROWS_AND_COLUMNS),
        &[0, 0],
    )
    .unwrap();
    c.wait_for_map(21, 1, T).unwrap();
    for id in [16, 21] {
        assert!(
            c.plan(&req((id, 1), [0, 0], [3, 3], Algorithm::AStar), T)
                .is_ok()
        );
    }

    let with = |f: &dyn Fn(&mut PlanRequest)| {
        let mut r = good;
        f(&mut r);
        r
    };
    let service = |e| ClientError::Service(e);
    let invalid = ClientError::Plan(PlanError::InvalidParameters);
    let cases: Vec<(PlanRequest, ClientError)> = vec![
        (
            with(&|r| r.algorithm = 0),
            service(ServiceError::UnknownAlgorithm),
        ),
        (
            with(&|r| r.algorithm = 14),
            service(ServiceError::UnknownAlgorithm),
        ),
        (
            with(&|r| r.algorithm = u8::MAX),
            service(ServiceError::UnknownAlgorithm),
        ),
        (with(&|r| r.kind = 2), service(ServiceError::InvalidRequest)),
        (
            with(&|r| r.kind = u8::MAX),
            service(ServiceError::InvalidRequest),
        ),
        (
            with(&|r| r.map_version = u32::MAX),
            service(ServiceError::UnknownMap),
        ),
        (
            with(&|r| r.map_id = u32::MAX),
            service(ServiceError::UnknownMap),
        ),
        // Counts beyond 2^24, unknown guide codes, reserved bytes, another wire version.
        (with(&|r| r.params.population = u32::MAX), invalid.clone()),
        (with(&|r| r.params.iterations = 16_777_217), invalid.clone()),
        (with(&|r| r.params.stagnation = 1 << 30), invalid.clone()),
        (with(&|r| r.params.guide = 2), invalid.clone()),
        // The blended objective's terms: finite and not negative.
        (with(&|r| r.params.clearance = -2.0), invalid.clone()),
        (
            with(&|r| r.params.clearance_weight = f32::INFINITY),
            invalid.clone(),
        ),
        (with(&|r| r.params.turn_weight = f32::NAN), invalid.clone()),
        (with(&|r| r.params.reserved = [0, 0, 9]), invalid.clone()),
        (
            with(&|r| r.reserved = 1),
            service(ServiceError::InvalidRequest),
        ),
        (
            with(&|r| r.wire_version = 0),
            service(ServiceError::UnsupportedVersion),
        ),
        (with(&|r| r.params.radius = f32::NAN), invalid.clone()),
        (with(&|r| r.params.radius = -0.5), invalid.clone()),
        // A robot radius beyond the largest map side, or not finite.
        (with(&|r| r.params.radius = 1e6), invalid.clone()),
        (with(&|r| r.params.radius = f32::INFINITY), invalid.clone()),
        // Coordinates at the ends of the i32 range.
        (
            with(&|r| r.start = [i32::MIN, i32::MAX]),
            ClientError::Plan(PlanError::StartOutsideMap),
        ),
        (
            with(&|r| r.goal = [i32::MAX, 0]),
            ClientError::Plan(PlanError::GoalOutsideMap),
        ),
        (
            with(&|r| r.goal = [65_535, 65_535]),
            ClientError::Plan(PlanError::GoalOutsideMap),
        ),
    ];
    for (request, want) in cases {
        assert_eq!(c.plan(&request, T), Err(want), "{request:?}");
        assert_eq!(c.plan(&good, T).as_ref(), Ok(&ok), "server stopped serving");
    }
    // An absurd deadline does not change the answer.
    let odd = with(&|r| {
        r.deadline_us = u64::MAX;
    });
    assert_eq!(c.plan(&odd, T), Ok(ok));
    let log = server.log_text();
    assert!(log.contains("rejected"), "{log}");
}

/// Every bad request gets its typed error and the server keeps serving the good ones;
/// SIGTERM then stops the server cleanly.
#[test]
fn typed_errors_while_the_server_keeps_serving() {
    let p = prefix("errors");
    let dir = scratch_dir(&p);
    // This server accepts at most 100,000 cells (the frame carries up to 512 x 512).
    let mut server = start_server(&p, &["--max-cells", "100000"]);
    let mut c = client(&p);
    let v1 = c.upload_map_file(&data(WAREHOUSE), 1).unwrap();
    c.wait_for_map(1, v1, T).unwrap();
    let good = req((1, v1), [143, 57], [10, 16], Algorithm::ThetaStar);
    let ok = c.plan(&good, T).unwrap();
    assert!((ok.length - 157.0114).abs() < 1e-3, "{}", ok.length);
    assert_eq!(ok.path.len(), 4);
    // Every planner of planner-core is served; the swarm planners are deterministic per seed.
    for algo in Algorithm::ALL {
        let mut r = req((1, v1), [143, 57], [10, 16], algo);
        r.params.iterations = 40;
        r.seed = 7;
        let a = c
            .plan(&r, T)
            .unwrap_or_else(|e| panic!("{}: {e}", algo.name()));
        assert!(
            a.length < 160.53 * 1.2 && a.length > 140.0,
            "{}: {}",
            algo.name(),
            a.length
        );
        assert_eq!(a.path.first().map(|p| (p.x, p.y)), Some((143.0, 57.0)));
        assert_eq!(a.path.last().map(|p| (p.x, p.y)), Some((10.0, 16.0)));
        if algo.kind().is_stochastic() {
            assert_eq!(
                c.plan(&r, T).unwrap(),
                a,
                "{} is not deterministic",
                algo.name()
            );
        }
    }
    let still_serving = |c: &mut planner_ipc::client::PlannerClient, map: (u32, u32)| {
        let mut r = good;
        r.map_id = map.0;
        r.map_version = map.1;
        assert!(c.plan(&r, T).is_ok(), "server stopped serving");
    };

    // A map beyond the server's configured limit: 400 x 300 = 120,000 cells. The map
    // service records the limit (the server created it), so the client refuses before
    // sending, naming the limit and the flag that raises it.
    assert_eq!(c.map_limit(), Ok(Some(100_000)));
    let big = dir.join("big.map");
    write_map(&big, 400, 300, |x, y| x % 7 == 3 && y % 5 != 0);
    let refused = c.upload_map_file(&big, 2).unwrap_err();
    assert_eq!(
        refused,
        ClientError::MapTooLarge(MapTooLarge {
            size: Some((400, 300)),
            max_cells: Some(100_000),
            refused_by: Refusal::Client,
        })
    );
    assert_eq!(
        refused.to_string(),
        "map 400 x 300 (120000 cells) exceeds the planner service's limit of 100000 cells; \
         start planner-server with --max-cells 120000 or more to accept it (not sent)"
    );
    // The same frame sent anyway (as a client of an older build would): the server refuses
    // it, logs it, and its answers name the limit.
    let grid = parse_map(&std::fs::read(&big).unwrap()).unwrap();
    let mut words = Vec::new();
    let meta = MapMeta {
        map_id: 2,
        version: 1,
        resolution: 1.0,
        origin: [0.0; 2],
    };
    let header = planner_ipc::wire::pack_map(meta, grid.view(), &mut words);
    c.publish_map(&header, &words).unwrap();
    let by_server = ClientError::MapTooLarge(MapTooLarge {
        size: Some((400, 300)),
        max_cells: Some(100_000),
        refused_by: Refusal::Server,
    });
    assert_eq!(c.wait_for_map(2, 1, T), Err(by_server.clone()));
    assert_eq!(
        c.plan(&req((2, 1), [0, 0], [1, 1], Algorithm::AStar), T),
        Err(by_server.clone())
    );
    assert_eq!(
        by_server.to_string(),
        "map 400 x 300 (120000 cells) exceeds the planner server's limit of 100000 cells; \
         start planner-server with --max-cells 120000 or more to accept it"
    );
    assert_eq!(by_server.name(), "MapTooLarge");
    still_serving(&mut c, (1, v1));

    // Stale and unknown map versions.
    let v1b = c.upload_map_file(&data(WAREHOUSE), 1).unwrap();
    assert_eq!(v1b, v1 + 1);
    c.wait_for_map(1, v1b, T).unwrap();
    assert_eq!(
        c.plan(&good, T),
        Err(ClientError::Service(ServiceError::StaleMapVersion))
    );
    assert_eq!(
        c.plan(&req((1, v1b + 5), [143, 57], [10, 16], Algorithm::AStar), T),
        Err(ClientError::Service(ServiceError::UnknownMap))
    );
    assert_eq!(
        c.plan(&req((99, 1), [143, 57], [10, 16], Algorithm::AStar), T),
        Err(ClientError::Service(ServiceError::UnknownMap))
    );
    still_serving(&mut c, (1, v1b));

    // Blocked and outside endpoints.
    let grid = parse_map(&std::fs::read(data(WAREHOUSE)).unwrap()).unwrap();
    let view = grid.view();
    let blocked = (0..view.cells())
        .map(|i| view.cell(i))
        .find(|c| !view.is_free(*c))
        .unwrap();
    let blocked = [blocked.x as i32, blocked.y as i32];
    let cases: Vec<(PlanRequest, ClientError)> = vec![
        (
            req((1, v1b), blocked, [10, 16], Algorithm::AStar),
            ClientError::Plan(PlanError::StartOccupied),
        ),
        (
            req((1, v1b), [143, 57], blocked, Algorithm::ThetaStar),
            ClientError::Plan(PlanError::GoalOccupied),
        ),
        (
            req((1, v1b), [-1, 57], [10, 16], Algorithm::AStar),
            ClientError::Plan(PlanError::StartOutsideMap),
        ),
        (
            req((1, v1b), [143, 57], [10, 6000], Algorithm::AStar),
            ClientError::Plan(PlanError::GoalOutsideMap),
        ),
        (
            PlanRequest {
                algorithm: 200,
                ..req((1, v1b), [143, 57], [10, 16], Algorithm::AStar)
            },
            ClientError::Service(ServiceError::UnknownAlgorithm),
        ),
        (
            PlanRequest {
                params: PlanParams {
                    radius: f32::NAN,
                    ..PlanParams::default()
                },
                ..req((1, v1b), [143, 57], [10, 16], Algorithm::AStar)
            },
            ClientError::Plan(PlanError::InvalidParameters),
        ),
        (
            PlanRequest {
                params: PlanParams {
                    iterations: u32::MAX,
                    population: 1 << 25,
                    ..PlanParams::default()
                },
                ..req((1, v1b), [143, 57], [10, 16], Algorithm::ThetaStar)
            },
            ClientError::Plan(PlanError::InvalidParameters),
        ),
        (
            PlanRequest {
                kind: 42,
                ..req((1, v1b), [143, 57], [10, 16], Algorithm::AStar)
            },
            ClientError::Service(ServiceError::InvalidRequest),
        ),
    ];
    for (request, want) in cases {
        assert_eq!(c.plan(&request, T), Err(want.clone()), "{request:?}");
        still_serving(&mut c, (1, v1b));
    }
    let mut status = req((1, v1b), [0, 0], [0, 0], Algorithm::AStar);
    status.kind = RequestKind::MapStatus.code();
    assert!(c.plan(&status, T).is_ok());

    // SIGTERM: clean shutdown with exit status 0 and a final log line.
    server.signal("TERM");
    let exit = server.wait_exit(T).expect("server ignored SIGTERM");
    assert!(exit.success(), "{exit:?}\n{}", server.log_text());
    let log = server.log_text();
    assert!(log.contains("planner-server stopped"), "{log}");
    assert!(
        log.contains(
            "map 2 version 1 rejected: MapTooLarge: 400 x 300 = 120000 cells, this server's limit is 100000 cells"
        ) && log.contains("raise it with planner-server --max-cells"),
        "{log}"
    );
    // Without a server the client reports it (no hang).
    drop(c);
    let mut c = client(&p);
    let err = c.plan(&good, Duration::from_millis(300)).unwrap_err();
    assert!(
        matches!(err, ClientError::NoServer | ClientError::Timeout),
        "{err:?}"
    );
}

/// The CLI for people prints the same JSON lines as `host-sim plan`; SIGINT stops the server.
#[test]
fn cli_prints_host_sim_json_lines() {
    let p = prefix("cli");
    let dir = scratch_dir(&p);
    let mut server = start_server(&p, &["--workers", "2"]);
    let queries = dir.join("q.txt");
    std::fs::write(&queries, "143 57 10 16\n0 0 5 5\nnot a query\n1 1 1 1\n").unwrap();
    let map = data(WAREHOUSE);
    let out = Command::new(env!("CARGO_BIN_EXE_ipc-test-client"))
        .args(["--prefix", &p, "plan", "--map"])
        .arg(&map)
        .args(["--algo", "theta", "--queries"])
        .arg(&queries)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let lines: Vec<serde_json::Value> = String::from_utf8(out.stdout)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(lines.len(), 4);
    assert_eq!(line_keys(&lines[0]), PLAN_LINE_KEYS);
    assert_eq!(
        lines[0]["path"],
        serde_json::json!([[143, 57], [135, 43], [25, 43], [10, 16]])
    );
    assert_eq!(lines[0]["length"], serde_json::json!(157.0114));
    assert_eq!(lines[0]["algo"], "theta");
    assert_eq!(
        line_keys(&lines[1]),
        ["start", "goal", "error", "time_us", "algo", "seed"]
    );
    assert_eq!(lines[2]["error"], "MalformedQuery");
    assert_eq!(lines[3]["path"], serde_json::json!([[1, 1]]));
    // An algorithm the server does not serve comes back typed.
    let out = Command::new(env!("CARGO_BIN_EXE_ipc-test-client"))
        .args(["--prefix", &p, "plan", "--map"])
        .arg(&map)
        .args(["--algo", "dijkstra", "--start", "143,57", "--goal", "10,16"])
        .output()
        .unwrap();
    let line: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(line["error"], "UnknownAlgorithm");
    server.signal("INT");
    let exit = server.wait_exit(T).expect("server ignored SIGINT");
    assert!(exit.success(), "{}", server.log_text());
}

/// Two `planner-client` runs upload different maps under the same map id: the second plans
/// on its own map, not on the version the server already holds from the first.
#[test]
fn a_new_map_under_a_used_id_is_planned_on() {
    let p = prefix("reupload");
    let dir = scratch_dir(&p);
    let _server = start_server(&p, &[]);
    let (open, blocked) = (dir.join("open.map"), dir.join("blocked.map"));
    write_map(&open, 3, 3, |_, _| false);
    write_map(&blocked, 3, 3, |x, y| (x, y) == (2, 2));
    let plan = |map: &std::path::Path| -> serde_json::Value {
        let out = Command::new(env!("CARGO_BIN_EXE_ipc-test-client"))
            .args(["--prefix", &p, "plan", "--map-id", "5", "--map"])
            .arg(map)
            .args(["--algo", "astar", "--start", "0,0", "--goal", "2,2"])
            .output()
            .unwrap();
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).unwrap()
    };
    assert_eq!(plan(&open)["length"], serde_json::json!(2.828427));
    assert_eq!(plan(&blocked)["error"], "GoalOccupied");
    assert_eq!(plan(&open)["length"], serde_json::json!(2.828427));
}

/// A 512 x 512 serpentine: Theta* from one corner to the other expands almost every cell,
/// so one request keeps the server busy for a noticeable time.
fn write_serpentine(path: &std::path::Path) {
    write_map(path, 512, 512, |x, y| {
        (x % 4 == 1 && y != 511) || (x % 4 == 3 && y != 0)
    });
}

/// A client process killed mid-request leaves the server unaffected, and a client that
/// gives up (timeout) has its request skipped and gets no stale answer later.
#[test]
fn client_killed_mid_request_leaves_server_unaffected() {
    let p = prefix("kill");
    let dir = scratch_dir(&p);
    let server = start_server(&p, &[]);
    let maze = dir.join("serpentine.map");
    write_serpentine(&maze);
    let mut c = client(&p);
    let v = c.upload_map_file(&maze, 1).unwrap();
    c.wait_for_map(1, v, T).unwrap();
    let long = req((1, v), [0, 0], [510, 511], Algorithm::ThetaStar);
    let began = Instant::now();
    let expected = c.plan(&long, Duration::from_secs(30)).unwrap();
    let one_plan = began.elapsed();
    eprintln!("one long plan: {one_plan:?}");

    // A hammering client process, killed with SIGKILL while its requests are in flight.
    let v_text = v.to_string();
    for _ in 0..3 {
        let mut hammer = driver(&["hammer", &p, "1", &v_text, "0", "0", "510", "511"]);
        std::thread::sleep(one_plan / 2 + Duration::from_millis(20));
        hammer.kill();
    }
    // This client's own give-up: a timeout far below one plan (about 6 ms on the server).
    // On a loaded 2-core machine the client may not run again until the answer is in (4-10
    // ms later), and then it takes it; so it asks until one request times out.
    let gave_up = (0..20).any(|_| match c.plan(&long, Duration::from_millis(1)) {
        Err(ClientError::Timeout) => true,
        Ok(late) => {
            assert_eq!(late, expected, "a late answer is the right one");
            false
        }
        Err(e) => panic!("unexpected {e:?}"),
    });
    assert!(gave_up, "no 1 ms request timed out in 20 tries");
    // The server goes on serving, with the right answer for the right request.
    let short = req((1, v), [0, 0], [0, 5], Algorithm::AStar);
    let got = c.plan(&short, Duration::from_secs(30)).unwrap();
    assert_eq!(got.path.len(), 6);
    let again = c.plan(&long, Duration::from_secs(30)).unwrap();
    assert_eq!(again, expected);
    let log = server.log_text();
    assert!(
        log.contains("cancelled") || log.contains("client gone"),
        "the server did not notice a client giving up:\n{log}"
    );
}

/// Client churn does not pile up descriptors in the server: each blocking client has a wake
/// event the server opens on its first answer; the server forgets the events of clients
/// that are gone (regression: the soak saw ~4 descriptors per departed client).
#[test]
fn client_churn_leaves_no_descriptors_behind() {
    let p = prefix("churnfds");
    let server = start_server(&p, &[]);
    let mut host = client(&p);
    let v = host.upload_map_file(&data(WAREHOUSE), 1).unwrap();
    host.wait_for_map(1, v, T).unwrap();
    let good = req((1, v), [143, 57], [10, 16], Algorithm::AStar);
    let fds = || {
        std::fs::read_dir(format!("/proc/{}/fd", server.child.id()))
            .unwrap()
            .count()
    };
    let churn = |n: usize| {
        for _ in 0..n {
            let mut c = client(&p);
            c.plan(&good, T).unwrap();
        }
    };
    churn(5);
    let before = fds();
    churn(30);
    let after = fds();
    eprintln!("server descriptors: {before} after 5 clients, {after} after 35");
    assert!(
        after <= before + 6,
        "descriptors grew with client churn: {before} -> {after}"
    );
}

/// A 4096 x 4096 map: a clear diagonal, scattered pallets off it, a wall along the far
/// end of the last row and one down the last column (so that the frame's last words
/// matter).
fn large_map() -> GridBuf {
    let side = 4096;
    let mut grid = GridBuf::new(side, side).unwrap();
    grid.view_mut()
        .fill_rows(|y, words| {
            for (i, word) in words.iter_mut().enumerate() {
                for bit in 0..32 {
                    let x = 32 * i + bit;
                    let pallet = (x * 7 + y * 13).is_multiple_of(997) && x.abs_diff(y) > 2;
                    let wall = (y == side - 1 && (4000..4090).contains(&x))
                        || (x == side - 1 && (10..100).contains(&y));
                    if pallet || wall {
                        *word |= 1 << bit;
                    }
                }
            }
        })
        .unwrap();
    grid
}

/// A 4096 x 4096 map (a 2 MiB frame) goes through the map service, packed in place into
/// shared memory, and is planned on: every sampled cell (the first and last words of the
/// frame included) is blocked on the server exactly when it is here, and A* from corner to
/// corner answers all 4096 cells of the diagonal (more than the 2048 waypoints an answer
/// carried before).
#[test]
fn a_4096_map_is_served_and_planned_on() {
    let p = prefix("large");
    let server = start_server(&p, &[]);
    let mut c = client(&p);
    assert_eq!(c.map_limit(), Ok(Some(4096 * 4096)));
    let grid = large_map();
    let meta = MapMeta {
        map_id: 1,
        version: 1,
        resolution: 0.05,
        origin: [0.0; 2],
    };
    c.upload_map(meta, grid.view()).unwrap();
    c.wait_for_map(1, 1, Duration::from_secs(30)).unwrap();
    let view = grid.view();
    let mut samples: Vec<(usize, usize)> = vec![(0, 0), (4095, 4095), (4050, 4095), (4095, 50)];
    samples.extend((0..1500).map(|i| ((i * 2731 + 17) % 4096, (i * 1237 + 5) % 4096)));
    // The first obstacle of every 41st row and its neighbours, where a shifted bit would show.
    for y in (0..4096).step_by(41) {
        if let Some(x) = (0..4096usize).find(|&x| view.is_blocked(x as isize, y as isize)) {
            samples.extend([(x, y), (x.saturating_sub(1), y), ((x + 1).min(4095), y)]);
        }
    }
    let blocked = samples
        .iter()
        .filter(|&&(x, y)| view.is_blocked(x as isize, y as isize))
        .count();
    assert!(blocked > 100 && blocked < samples.len() - 100, "{blocked}");
    for &(x, y) in &samples {
        let cell = [x as i32, y as i32];
        let got = c.plan(&req((1, 1), cell, cell, Algorithm::AStar), T);
        if view.is_blocked(x as isize, y as isize) {
            assert_eq!(
                got,
                Err(ClientError::Plan(PlanError::StartOccupied)),
                "{x},{y}"
            );
        } else {
            assert_eq!(got.map(|ok| ok.path.len()), Ok(1), "{x},{y}");
        }
    }
    let diagonal = c
        .plan(
            &req((1, 1), [0, 0], [4095, 4095], Algorithm::AStar),
            Duration::from_secs(60),
        )
        .unwrap();
    assert_eq!(diagonal.path.len(), 4096);
    assert!(
        diagonal
            .path
            .iter()
            .enumerate()
            .all(|(i, p)| (p.x, p.y) == (i as f32, i as f32))
    );
    assert!(
        // The planner sums the steps in f32.
        (diagonal.length / (4095.0 * std::f32::consts::SQRT_2) - 1.0).abs() < 1e-4,
        "{}",
        diagonal.length
    );
    let log = server.log_text();
    assert!(
        log.contains("map 1 version 1 stored: 4096x4096 cells"),
        "{log}"
    );
    // Planned on where it was published (the frame of both layouts is kept, not copied).
    assert!(log.contains("(kept in place in "), "{log}");
}

/// Above the default limit (4096 x 4096 cells) the client refuses before sending, and a
/// frame sent anyway is refused by the server; both errors name the limit and the flag
/// that raises it, and the server logs its refusal.
#[test]
fn a_map_over_the_default_limit_gets_a_typed_error_naming_the_limit() {
    let p = prefix("overlimit");
    let server = start_server(&p, &[]);
    let mut c = client(&p);
    let over = GridBuf::new(4097, 4096).unwrap();
    let meta = MapMeta {
        map_id: 5,
        version: 1,
        resolution: 0.05,
        origin: [0.0; 2],
    };
    let refused = c.upload_map(meta, over.view()).unwrap_err();
    assert_eq!(
        refused,
        ClientError::MapTooLarge(MapTooLarge {
            size: Some((4097, 4096)),
            max_cells: Some(4096 * 4096),
            refused_by: Refusal::Client,
        })
    );
    assert_eq!(
        refused.to_string(),
        "map 4097 x 4096 (16781312 cells) exceeds the planner service's limit of 16777216 cells \
         (4096 x 4096); start planner-server with --max-cells 16781312 or more to accept it \
         (not sent)"
    );
    let header = MapHeader {
        map_id: 5,
        map_version: 1,
        width: 4097,
        height: 4096,
        resolution: 0.05,
        origin: [0.0; 2],
        layout: LAYOUT_ROWS,
        ..MapHeader::default()
    };
    c.publish_map(&header, &vec![0; header.words()]).unwrap();
    let by_server = c.wait_for_map(5, 1, T).unwrap_err();
    assert_eq!(
        by_server,
        ClientError::MapTooLarge(MapTooLarge {
            size: Some((4097, 4096)),
            max_cells: Some(4096 * 4096),
            refused_by: Refusal::Server,
        })
    );
    assert!(by_server.to_string().contains("--max-cells 16781312"));
    // The server goes on serving.
    let v = c.upload_map_file(&data(WAREHOUSE), 1).unwrap();
    c.wait_for_map(1, v, T).unwrap();
    assert!(
        c.plan(&req((1, v), [143, 57], [10, 16], Algorithm::AStar), T)
            .is_ok()
    );
    let log = server.log_text();
    assert!(
        log.contains(
            "map 5 version 1 rejected: MapTooLarge: 4097 x 4096 = 16781312 cells, this server's limit is 16777216 cells"
        ),
        "{log}"
    );
}

/// A map written in place into a loaned frame is planned on where it lies, and goes on
/// being planned on after its publisher is gone (the server holds the frame while the
/// version is current). A frame whose two layouts disagree is stored and planned on as sent
/// by default (each planner reads the layout it reads) and refused, naming the first cell
/// that differs, by a server started with `--verify-maps`; both servers keep serving.
#[test]
fn kept_frames_outlive_their_publisher_and_verify_maps_checks_layouts() {
    let p = prefix("kept");
    let server = start_server(&p, &[]);
    let meta = |map_id| MapMeta {
        map_id,
        version: 1,
        resolution: 0.05,
        origin: [0.0; 2],
    };
    // A wall along row 15 of a 40 x 30 map, open at column 39.
    let wall = |x: usize, y: usize| y == 15 && x < 39;
    {
        let mut publisher = client(&p);
        let mut loan = publisher.loan_map(meta(1), 40, 30).unwrap();
        {
            let mut grid = loan.grid();
            for (x, y) in (0..40).flat_map(|x| (0..30).map(move |y| (x, y))) {
                grid.set_blocked(x, y, wall(x, y)).unwrap();
            }
        }
        loan.publish().unwrap();
        publisher.wait_for_map(1, 1, T).unwrap();
    }
    let mut c = client(&p);
    let around = c
        .plan(&req((1, 1), [5, 0], [5, 29], Algorithm::ThetaStar), T)
        .unwrap();
    assert!(around.length > 60.0, "{:?}", around.path);
    assert!(around.path.iter().any(|p| p.x >= 38.0), "{:?}", around.path);
    assert_eq!(
        c.plan(&req((1, 1), [5, 15], [5, 0], Algorithm::AStar), T),
        Err(ClientError::Plan(PlanError::StartOccupied))
    );
    let log = server.log_text();
    assert!(
        log.contains("map 1 version 1 stored: 40x30 cells") && log.contains("kept in place"),
        "{log}"
    );

    // Rows with the wall, columns left all free (a raw writer that forgot them).
    let n = (40 * 30usize).div_ceil(32);
    let mut words = vec![0u32; 2 * n];
    for i in (0..40 * 30).filter(|i| wall(i % 40, i / 40)) {
        words[i / 32] |= 1 << (i % 32);
    }
    let header = MapHeader {
        map_id: 2,
        map_version: 1,
        width: 40,
        height: 30,
        resolution: 0.05,
        origin: [0.0; 2],
        layout: LAYOUT_ROWS_AND_COLUMNS,
        ..MapHeader::default()
    };
    c.publish_map(&header, &words).unwrap();
    c.wait_for_map(2, 1, T).unwrap();
    // Stored and planned on as sent: the rows block (5, 15).
    assert_eq!(
        c.plan(&req((2, 1), [5, 15], [5, 0], Algorithm::AStar), T),
        Err(ClientError::Plan(PlanError::StartOccupied))
    );
    assert!(
        c.plan(&req((2, 1), [5, 0], [5, 29], Algorithm::ThetaStar), T)
            .is_ok()
    );

    let pv = prefix("verify");
    let verifying = start_server(&pv, &["--verify-maps"]);
    let mut v = client(&pv);
    v.publish_map(&header, &words).unwrap();
    assert_eq!(
        v.wait_for_map(2, 1, T),
        Err(ClientError::Service(ServiceError::InvalidRequest))
    );
    let log = verifying.log_text();
    assert!(
        log.contains("map 2 version 1 rejected: InvalidRequest")
            && log.contains("its layouts disagree first at cell (0, 15)"),
        "{log}"
    );
    // Both layouts written: accepted, verified.
    for i in (0..40 * 30).filter(|i| wall(i % 40, i / 40)) {
        let j = (i % 40) * 30 + i / 40;
        words[n + j / 32] |= 1 << (j % 32);
    }
    v.publish_map(
        &MapHeader {
            map_version: 2,
            ..header
        },
        &words,
    )
    .unwrap();
    v.wait_for_map(2, 2, T).unwrap();
    assert!(verifying.log_text().contains("verified"));
    let around = v
        .plan(&req((2, 2), [5, 0], [5, 29], Algorithm::ThetaStar), T)
        .unwrap();
    assert!(around.length > 60.0, "{:?}", around.path);
    assert!(
        c.plan(&req((1, 1), [0, 0], [39, 29], Algorithm::AStar), T)
            .is_ok()
    );
}

/// A foreign client that creates the plan service with iceoryx2's defaults before any
/// server runs: the server refuses to start and its error names the cause.
#[test]
fn a_service_created_by_a_client_is_named_at_start_up() {
    use iceoryx2::prelude::*;
    let p = prefix("foreign");
    let node = NodeBuilder::new()
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<ipc::Service>()
        .unwrap();
    let name = ServiceName::new(&format!("{p}/plan")).unwrap();
    let _foreign = node
        .service_builder(&name)
        .request_response::<u64, u64>()
        .open_or_create()
        .unwrap();
    let log = scratch_dir(&p).join("server.log");
    let child = Command::new(env!("CARGO_BIN_EXE_ipc-test-server"))
        .args(["--prefix", &p])
        .stdout(std::process::Stdio::null())
        .stderr(std::fs::File::create(&log).unwrap())
        .spawn()
        .unwrap();
    let mut server = Proc {
        child,
        log: Some(log),
    };
    let status = server
        .wait_exit(Duration::from_secs(20))
        .expect("the server should refuse to start");
    assert!(!status.success());
    let text = server.log_text();
    assert!(
        text.contains(&format!("service \"{p}/plan\" exists"))
            && text.contains("created by a client")
            && text.contains("docs/wire.md"),
        "{text}"
    );
}

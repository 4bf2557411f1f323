//! `host-sim plan` end to end: the JSON-lines contract, error objects, bad files.

use serde_json::Value;
use std::path::PathBuf;
use std::process::Command;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/movingai")
        .join(name)
}

fn host_sim(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args(args)
        .output()
        .unwrap()
}

fn lines(out: &std::process::Output) -> Vec<Value> {
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8(out.stdout.clone())
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn single_query_matches_published_optimum() {
    let map = data("warehouse-10-20-10-2-1.map");
    let out = host_sim(&[
        "plan",
        "--map",
        map.to_str().unwrap(),
        "--start",
        "143,57",
        "--goal",
        "10,16",
        "--algo",
        "astar",
    ]);
    let rows = lines(&out);
    assert_eq!(rows.len(), 1);
    let r = &rows[0];
    assert_eq!(r["start"], serde_json::json!([143, 57]));
    assert_eq!(r["goal"], serde_json::json!([10, 16]));
    assert!((r["length"].as_f64().unwrap() - 160.52691193).abs() < 1e-3);
    let path = r["path"].as_array().unwrap();
    assert_eq!(path.first().unwrap(), &serde_json::json!([143, 57]));
    assert_eq!(path.last().unwrap(), &serde_json::json!([10, 16]));
    assert!(r["time_us"].as_f64().unwrap() >= 0.0);
}

#[test]
fn queries_file_in_order_with_errors_and_out_file() {
    let dir = std::env::temp_dir().join(format!("host-sim-plan-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let queries = dir.join("q.txt");
    let results = dir.join("r.jsonl");
    // free->free, blocked start (border is a shelf 'T'), outside goal, malformed, unreachable-free.
    std::fs::write(
        &queries,
        "143 57 10 16\n0 0 5 5\n1 1 500 1\nnot a query\n1 1 1 1\n",
    )
    .unwrap();
    let map = data("warehouse-10-20-10-2-1.map");
    let out = host_sim(&[
        "plan",
        "--map",
        map.to_str().unwrap(),
        "--queries",
        queries.to_str().unwrap(),
        "--algo",
        "theta",
        "--out",
        results.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    assert!(out.stdout.is_empty());
    let rows: Vec<Value> = std::fs::read_to_string(&results)
        .unwrap()
        .lines()
        .map(|l| serde_json::from_str(l).unwrap())
        .collect();
    assert_eq!(rows.len(), 5);
    assert!(rows[0]["length"].as_f64().unwrap() < 160.52691193);
    assert_eq!(rows[1]["error"], "StartOccupied");
    assert_eq!(rows[2]["error"], "GoalOutsideMap");
    assert_eq!(rows[3]["error"], "MalformedQuery");
    assert_eq!(rows[3]["line"], 4);
    assert_eq!(rows[4]["length"].as_f64().unwrap(), 0.0);
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn unreachable_goal_is_no_valid_path() {
    let dir = std::env::temp_dir().join(format!("host-sim-walled-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let map = dir.join("walled.map");
    std::fs::write(
        &map,
        "type octile\nheight 3\nwidth 5\nmap\n..@..\n..@..\n..@..\n",
    )
    .unwrap();
    for algo in ["astar", "theta"] {
        let out = host_sim(&[
            "plan",
            "--map",
            map.to_str().unwrap(),
            "--start",
            "0,0",
            "--goal",
            "4,2",
            "--algo",
            algo,
        ]);
        assert_eq!(lines(&out)[0]["error"], "NoValidPath");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn malformed_map_is_a_clear_error() {
    let dir = std::env::temp_dir().join(format!("host-sim-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let map = dir.join("bad.map");
    std::fs::write(&map, "type octile\nheight 2\nwidth 3\nmap\n...\n.x.\n").unwrap();
    let out = host_sim(&[
        "plan",
        "--map",
        map.to_str().unwrap(),
        "--start",
        "0,0",
        "--goal",
        "1,0",
    ]);
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        err.contains("unknown map character") && err.contains("row 2"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn every_planner_returns_a_valid_path_with_its_figures() {
    let map = data("warehouse-10-20-10-2-1.map");
    for algo in [
        "astar", "theta", "aco", "tclhho", "igwo", "hho", "gwo", "tgwo", "pso", "ga", "ssa",
        "ssagwo",
    ] {
        let out = host_sim(&[
            "plan",
            "--map",
            map.to_str().unwrap(),
            "--start",
            "134,28",
            "--goal",
            "91,6",
            "--algo",
            algo,
            "--iters",
            "60",
            "--seed",
            "3",
        ]);
        let r = &lines(&out)[0];
        assert!(r.get("error").is_none(), "{algo}: {r}");
        let length = r["length"].as_f64().unwrap();
        // Published octile optimum of this row: 65.0; any-angle may be shorter, never below
        // the straight line (sqrt(43^2 + 22^2) = 48.3).
        assert!(length > 48.3 && length < 65.0 * 1.3, "{algo}: {length}");
        if algo != "astar" && algo != "theta" {
            assert!(r["evaluations"].as_u64().unwrap() > 0, "{algo}");
            assert!(
                r["final_cost"].as_f64().unwrap()
                    <= r["initial_cost"].as_f64().unwrap_or(f64::INFINITY),
                "{algo}"
            );
        }
        assert_eq!(r["algo"], algo);
    }
    let out = host_sim(&[
        "plan",
        "--map",
        map.to_str().unwrap(),
        "--start",
        "1,1",
        "--goal",
        "2,2",
        "--algo",
        "dijkstra",
    ]);
    assert!(!out.status.success());
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown planner"));
}

#[test]
fn swarm_planners_report_the_right_errors_on_a_real_warehouse() {
    // Wall off the free cell (1, 1) of the vendored map by blocking its neighbours.
    let text = std::fs::read_to_string(data("warehouse-10-20-10-2-1.map")).unwrap();
    let mut rows: Vec<Vec<u8>> = text.lines().map(|l| l.as_bytes().to_vec()).collect();
    let header = 4;
    assert_eq!(rows[header + 1][1], b'.');
    for (x, y) in [(2usize, 1usize), (1, 2), (2, 2)] {
        rows[header + y][x] = b'T';
    }
    let dir = std::env::temp_dir().join(format!("host-sim-walled-wh-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let map = dir.join("walled.map");
    std::fs::write(
        &map,
        rows.join(&b'\n')
            .iter()
            .copied()
            .chain([b'\n'])
            .collect::<Vec<u8>>(),
    )
    .unwrap();
    let queries = dir.join("q.txt");
    // unreachable, start on a shelf border, goal outside, start == goal
    std::fs::write(&queries, "1 1 91 6\n0 0 91 6\n91 6 500 6\n91 6 91 6\n").unwrap();
    for algo in ["tclhho", "igwo", "aco"] {
        let out = host_sim(&[
            "plan",
            "--map",
            map.to_str().unwrap(),
            "--queries",
            queries.to_str().unwrap(),
            "--algo",
            algo,
            "--iters",
            "30",
        ]);
        let rows = lines(&out);
        assert_eq!(rows[0]["error"], "NoValidPath", "{algo}");
        assert_eq!(rows[1]["error"], "StartOccupied", "{algo}");
        assert_eq!(rows[2]["error"], "GoalOutsideMap", "{algo}");
        assert_eq!(rows[3]["length"].as_f64().unwrap(), 0.0, "{algo}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn movingai_bench_validates_every_path_independently() {
    let dir = std::env::temp_dir().join(format!("host-sim-bench-mai-{}", std::process::id()));
    let data_dir = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data/movingai");
    let out = host_sim(&[
        "bench",
        "movingai",
        "--data",
        data_dir.to_str().unwrap(),
        "--rows",
        "6",
        "--iters",
        "60",
        "--algos",
        "theta,tclhho,igwo",
        "--maps",
        "warehouse-10-20-10-2-1,warehouse-20-40-10-2-2",
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let summary: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("movingai.json")).unwrap()).unwrap();
    for s in summary.as_array().unwrap() {
        assert_eq!(s["valid"], s["rows"], "{s}");
        assert!(s["max_ratio"].as_f64().unwrap() <= 1.02, "{s}");
    }
    std::fs::remove_dir_all(&dir).ok();
}

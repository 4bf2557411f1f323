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

//! `planner-client plan --frame world` against a real `planner-server` on the vendored ROS
//! maps (and in cells on Moving AI maps): every printed path, read back from the text as a
//! consumer reads it (JSON numbers as `f64`), validates on the map inflated as the server
//! inflated it, in cells and in metres; the same check refuses a corrupted line.

mod common;

use common::{prefix, scratch_dir, start_server};
use host_sim::printed::check_line;
use planner_core::grid::{GridBuf, GridRef};
use planner_mapfile::{MapOptions, load_map};
use std::path::{Path, PathBuf};
use std::process::Command;

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}

/// Free cells of `grid` spread over it: every `step`-th free cell in row-major order.
fn spread(grid: GridRef<'_>, n: usize) -> Vec<(u16, u16)> {
    let free: Vec<_> = (0..grid.cells())
        .map(|i| grid.cell(i))
        .filter(|c| grid.is_free(*c))
        .collect();
    let step = (free.len() / n).max(1);
    free.iter().step_by(step).map(|c| (c.x, c.y)).collect()
}

/// Queries pairing cells from both ends of the list (long ones).
fn queries(cells: &[(u16, u16)], world: Option<&planner_mapfile::MapFrame>) -> String {
    let n = cells.len();
    (0..n / 2)
        .map(|i| {
            let (s, g) = (cells[i], cells[n - 1 - i]);
            match world {
                Some(f) => {
                    let [sx, sy] = f.to_world(s.0 as f64, s.1 as f64);
                    let [gx, gy] = f.to_world(g.0 as f64, g.1 as f64);
                    format!("{sx} {sy} {gx} {gy}\n")
                }
                None => format!("{} {} {} {}\n", s.0, s.1, g.0, g.1),
            }
        })
        .collect()
}

#[test]
fn printed_client_paths_validate_when_read_back() {
    let p = prefix("ros-round-trip");
    let dir = scratch_dir(&p);
    let mut server = start_server(&p, &["--workers", "2"]);
    let mut checked = 0;
    let cases = [
        ("tests/data/ros/turtlebot3/map.yaml", true),
        ("tests/data/ros/nav2_depot/depot.yaml", true),
        ("tests/data/ros/aws_small_warehouse_005/map.yaml", true),
        ("tests/data/movingai/warehouse-10-20-10-2-1.map", false),
        ("tests/data/movingai/random-32-32-10.map", false),
    ];
    for (map_id, (map, world)) in cases.into_iter().enumerate() {
        let path = repo(map);
        let loaded = load_map(&path, &MapOptions::default()).unwrap();
        // The client's default on a ROS map: a 0.25 m robot, 4.5 cells at 0.05 m.
        let planned_on: GridBuf = if world {
            loaded.grid.inflated(4.5).unwrap()
        } else {
            loaded.grid.clone()
        };
        let frame = world.then_some(&loaded.frame);
        let file = dir.join(format!("q{map_id}.txt"));
        std::fs::write(&file, queries(&spread(planned_on.view(), 40), frame)).unwrap();
        for algo in ["anyangle", "theta", "igwo"] {
            let mut cmd = Command::new(env!("CARGO_BIN_EXE_ipc-test-client"));
            cmd.args(["--prefix", &p, "plan", "--map"])
                .arg(&path)
                .args([
                    "--map-id",
                    &(map_id + 1).to_string(),
                    "--algo",
                    algo,
                    "--queries",
                ])
                .arg(&file);
            if world {
                cmd.args(["--frame", "world"]);
            }
            let out = cmd.output().unwrap();
            assert!(
                out.status.success(),
                "{map} {algo}: {}",
                String::from_utf8_lossy(&out.stderr)
            );
            let text = String::from_utf8(out.stdout).unwrap();
            let mut paths = 0;
            for line in text.lines() {
                check_line(line, planned_on.view(), frame)
                    .unwrap_or_else(|e| panic!("{map} {algo}: {e}: {line}"));
                let v: serde_json::Value = serde_json::from_str(line).unwrap();
                if v.get("path").is_some() {
                    paths += 1;
                    assert_eq!(v.get("path_m").is_some(), world, "{line}");
                }
            }
            assert!(paths >= 10, "{map} {algo}: {paths} paths\n{text}");
            checked += paths;
            // Negative control: the first path with a waypoint moved onto a blocked corner.
            let line = text.lines().find(|l| l.contains("\"path\"")).unwrap();
            let mut v: serde_json::Value = serde_json::from_str(line).unwrap();
            let blocked = (0..planned_on.view().cells())
                .map(|i| planned_on.view().cell(i))
                .find(|c| !planned_on.view().is_free(*c))
                .unwrap();
            v["path"].as_array_mut().unwrap().insert(
                1,
                serde_json::json!([blocked.x as f64 - 0.5, blocked.y as f64 - 0.5]),
            );
            assert!(check_line(&v.to_string(), planned_on.view(), None).is_err());
        }
    }
    eprintln!("{checked} printed client paths validated when read back");
    assert!(checked >= 150, "{checked} paths checked");
    server.signal("INT");
    server.wait_exit(std::time::Duration::from_secs(10));
}

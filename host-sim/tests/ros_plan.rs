//! `host-sim plan --frame world` on the vendored ROS maps (and, in cells, on Moving AI maps):
//! every printed path, read back from the text as a consumer reads it, validates on the map
//! inflated as the planner inflated it, in cells and in metres; the default robot is 0.25 m;
//! a corrupted line is refused by the same check (the check can fail).

use host_sim::printed::check_line;
use planner_core::geometry::Cell;
use planner_core::grid::{GridBuf, GridRef};
use planner_mapfile::{MapOptions, load_map};
use rand_core::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

fn repo(rel: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("..").join(rel)
}

/// `n` pairs of free cells of `grid` (free on the inflated map, so that most are plannable).
fn pairs(grid: GridRef<'_>, n: usize, seed: u64) -> Vec<(Cell, Cell)> {
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed);
    let mut free = || loop {
        let i = (rng.next_u64() % grid.cells() as u64) as usize;
        if !grid.is_blocked((i % grid.width()) as isize, (i / grid.width()) as isize) {
            return grid.cell(i);
        }
    };
    (0..n).map(|_| (free(), free())).collect()
}

struct Checked {
    paths: usize,
    errors: usize,
}

/// Plans `queries` (text) with `extra` options and checks every printed line on `planned_on`.
fn plan_and_check(
    map: &Path,
    queries: &str,
    extra: &[&str],
    planned_on: GridRef<'_>,
    world: bool,
) -> Checked {
    let dir = std::env::temp_dir().join(format!("ros-plan-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join(format!("q-{}.txt", extra.join("_")));
    std::fs::write(&file, queries).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args(["plan", "--map", map.to_str().unwrap()])
        .args(["--queries", file.to_str().unwrap()])
        .args(extra)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let frame = load_map(map, &MapOptions::default()).unwrap().frame;
    let (mut paths, mut errors) = (0, 0);
    for text in String::from_utf8(out.stdout).unwrap().lines() {
        let line: Value = serde_json::from_str(text).unwrap();
        assert_ne!(line["error"], "InvalidPath", "{text}");
        if line.get("path").is_some() {
            paths += 1;
            assert_eq!(line.get("path_m").is_some(), world, "{text}");
        } else {
            errors += 1;
        }
        check_line(text, planned_on, world.then_some(&frame))
            .unwrap_or_else(|e| panic!("{} {extra:?}: {e}: {text}", map.display()));
    }
    std::fs::remove_file(file).unwrap();
    Checked { paths, errors }
}

#[test]
fn printed_paths_on_ros_maps_validate_when_read_back() {
    let mut total = 0;
    for map in [
        "tests/data/ros/turtlebot3/map.yaml",
        "tests/data/ros/nav2_depot/depot.yaml",
        "tests/data/ros/aws_small_warehouse_005/map.yaml",
    ] {
        let path = repo(map);
        let loaded = load_map(&path, &MapOptions::default()).unwrap();
        let frame = loaded.frame;
        // The default robot (0.25 m: 4.5 cells at 0.05 m) and a point robot.
        let inflated: GridBuf = loaded.grid.inflated(4.5).unwrap();
        let queries: String = pairs(inflated.view(), 25, 11)
            .iter()
            .map(|(s, g)| {
                let [sx, sy] = frame.to_world(s.x as f64, s.y as f64);
                let [gx, gy] = frame.to_world(g.x as f64, g.y as f64);
                format!("{sx} {sy} {gx} {gy}\n")
            })
            .collect();
        for algo in ["anyangle", "theta", "igwo", "tclhho"] {
            let c = plan_and_check(
                &path,
                &queries,
                &["--frame", "world", "--algo", algo],
                inflated.view(),
                true,
            );
            // Pairs of the largest region plan; others are NoValidPath, never many.
            assert!(c.paths >= 5 && c.paths + c.errors == 25, "{map} {algo}");
            total += c.paths;
            let c = plan_and_check(
                &path,
                &queries,
                &["--frame", "world", "--algo", algo, "--robot-radius", "0"],
                loaded.grid.view(),
                true,
            );
            assert!(c.paths >= 5, "{map} {algo} point robot");
            total += c.paths;
        }
    }
    eprintln!("{total} printed plan paths validated when read back");
    assert!(total >= 200, "{total} paths checked");
}

#[test]
fn printed_paths_on_movingai_maps_validate_when_read_back() {
    for map in [
        "tests/data/movingai/warehouse-10-20-10-2-1.map",
        "tests/data/movingai/maze-32-32-2.map",
    ] {
        let path = repo(map);
        let grid = load_map(&path, &MapOptions::default()).unwrap().grid;
        let queries: String = pairs(grid.view(), 25, 5)
            .iter()
            .map(|(s, g)| format!("{} {} {} {}\n", s.x, s.y, g.x, g.y))
            .collect();
        for algo in ["anyangle", "igwo"] {
            let c = plan_and_check(&path, &queries, &["--algo", algo], grid.view(), false);
            assert!(c.paths >= 10, "{map} {algo}");
        }
    }
}

#[test]
fn the_check_refuses_a_path_that_touches_a_corner() {
    let map = repo("tests/data/ros/turtlebot3/map.yaml");
    let loaded = load_map(&map, &MapOptions::default()).unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args(["plan", "--map", map.to_str().unwrap(), "--algo", "anyangle"])
        .args([
            "--frame", "world", "--start", "1.7,0.9", "--goal", "-0.4,1.4",
        ])
        .output()
        .unwrap();
    let text = String::from_utf8(out.stdout).unwrap();
    let inflated = loaded.grid.inflated(4.5).unwrap();
    assert_eq!(
        check_line(text.trim(), inflated.view(), Some(&loaded.frame)),
        Ok(())
    );
    let mut line: Value = serde_json::from_str(text.trim()).unwrap();
    // A waypoint moved onto the corner of a cell the inflation blocks.
    let blocked = (0..inflated.view().cells())
        .map(|i| inflated.view().cell(i))
        .find(|c| !inflated.view().is_free(*c))
        .unwrap();
    let corner = [blocked.x as f64 - 0.5, blocked.y as f64 - 0.5];
    line["path"]
        .as_array_mut()
        .unwrap()
        .insert(1, corner.into());
    let e = check_line(&line.to_string(), inflated.view(), None).unwrap_err();
    assert!(e.contains("touches a blocked cell"), "{e}");
}

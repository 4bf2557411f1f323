//! Maps of 4096 x 4096 cells through the CLI: `plan` on Moving AI text and on ROS YAML + PGM
//! of the same generated warehouse, `run` on a generated one (simulator and downsampled
//! pictures), and the `--max-cells` limit.

use host_sim::warehouse_gen::{WarehouseParams, generate};
use planner_core::geometry::Cell;
use planner_core::grid::{GridBuf, GridRef};
use planner_mapfile::{DEFAULT_MAX_CELLS, MapOptions};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

const SIDE: usize = 4096;

fn host_sim(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args(args)
        .output()
        .unwrap()
}

fn temp_dir(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("host-sim-big-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn layout() -> WarehouseParams {
    WarehouseParams {
        width: SIDE,
        height: SIDE,
        ..WarehouseParams::default()
    }
}

/// The free cell nearest `(x, y)` along its row (the generated layout has free aisles every
/// few columns).
fn free_near(g: GridRef<'_>, x: usize, y: usize) -> Cell {
    (0..g.width())
        .flat_map(|d| [x.saturating_sub(d), (x + d).min(g.width() - 1)])
        .map(|x| Cell::new(x as u16, y as u16))
        .find(|c| g.is_free(*c))
        .unwrap()
}

/// Writes `grid` as a binary PGM (free white, blocked black) and a map_server YAML naming it.
fn write_ros(grid: &GridBuf, dir: &Path) -> PathBuf {
    let v = grid.view();
    let mut pgm = format!("P5\n{} {}\n255\n", v.width(), v.height()).into_bytes();
    pgm.reserve(v.cells());
    for y in 0..v.height() as isize {
        pgm.extend((0..v.width() as isize).map(|x| if v.is_blocked(x, y) { 0u8 } else { 254 }));
    }
    std::fs::write(dir.join("big.pgm"), pgm).unwrap();
    let yaml = dir.join("big.yaml");
    std::fs::write(
        &yaml,
        "image: big.pgm\nresolution: 0.05\norigin: [0.0, 0.0, 0.0]\nnegate: 0\n\
         occupied_thresh: 0.65\nfree_thresh: 0.196\n",
    )
    .unwrap();
    yaml
}

fn json_lines(text: &[u8]) -> Vec<Value> {
    String::from_utf8_lossy(text)
        .lines()
        .filter(|l| l.starts_with('{'))
        .map(|l| serde_json::from_str(l).unwrap())
        .collect()
}

#[test]
fn plan_on_a_4096_warehouse_as_movingai_and_as_ros_map() {
    let w = generate(&layout(), &MapOptions::default()).unwrap();
    let g = w.grid.view();
    let start = free_near(g, 5, 3);
    let goal = free_near(g, SIDE - 7, SIDE - 5);
    let dir = temp_dir("plan");
    let mut text = String::with_capacity(SIDE * (SIDE + 1) + 64);
    w.grid.write_movingai(&mut text).unwrap();
    let map = dir.join("big.map");
    std::fs::write(&map, text).unwrap();
    let yaml = write_ros(&w.grid, &dir);
    let (s, t) = (
        format!("{},{}", start.x, start.y),
        format!("{},{}", goal.x, goal.y),
    );
    let mut lengths = Vec::new();
    for file in [&map, &yaml] {
        let out = host_sim(&[
            "plan",
            "--map",
            file.to_str().unwrap(),
            "--start",
            &s,
            "--goal",
            &t,
            "--algo",
            "astar",
            // The same cells either way: no robot inflation on the ROS map (it would block
            // the start by the wall).
            "--radius",
            "0",
        ]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "{}", stderr);
        // The one-time costs come apart from the query, on standard error.
        let costs = &json_lines(&out.stderr)[0];
        assert_eq!(costs["map"], file.to_str().unwrap());
        assert_eq!(
            (costs["width"].as_u64(), costs["height"].as_u64()),
            (Some(4096), Some(4096))
        );
        for key in ["load_ms", "inflate_ms", "prepare_ms", "warmup_ms"] {
            assert!(
                costs[key].as_f64().is_some_and(|v| v >= 0.0),
                "{key}: {costs}"
            );
        }
        let rows = json_lines(&out.stdout);
        assert_eq!(rows.len(), 1);
        let r = &rows[0];
        assert!(r.get("error").is_none(), "{r}");
        let path = r["path"].as_array().unwrap();
        assert_eq!(
            path.first().unwrap(),
            &serde_json::json!([start.x, start.y])
        );
        assert_eq!(path.last().unwrap(), &serde_json::json!([goal.x, goal.y]));
        lengths.push(r["length"].as_f64().unwrap());
    }
    // Both files hold the same map: the same optimum, at least the octile distance.
    let (dx, dy) = ((goal.x - start.x) as f64, (goal.y - start.y) as f64);
    let octile = dx.max(dy) + (2f64.sqrt() - 1.0) * dx.min(dy);
    assert!(lengths[0] >= octile - 1e-3, "{lengths:?} vs {octile}");
    assert!((lengths[0] - lengths[1]).abs() < 1e-3, "{lengths:?}");
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn run_on_a_generated_4096_warehouse_draws_downsampled_pictures() {
    let g = generate(&layout(), &MapOptions::default()).unwrap().grid;
    let start = free_near(g.view(), 2050, 2049);
    let goal = free_near(g.view(), 2070, 2063);
    let dir = temp_dir("run");
    let out = host_sim(&[
        "run",
        "--width",
        "4096",
        "--height",
        "4096",
        "--planner",
        "inproc",
        "--algo",
        "astar",
        "--start",
        &format!("{},{}", start.x, start.y),
        "--goal",
        &format!("{},{}", goal.x, goal.y),
        "--out",
        dir.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}\n{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    let report: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).unwrap()).unwrap();
    assert_eq!(report["outcome"], "Arrived", "{report}");
    assert_eq!(report["collisions_static"], 0, "{report}");
    // The picture is downsampled: 4096 cells in at most 2000 pixels, plus axes and legend.
    let png = std::fs::read(dir.join("trajectory.png")).unwrap();
    let info = png::Decoder::new(std::io::Cursor::new(png))
        .read_info()
        .unwrap()
        .info()
        .clone();
    assert!(
        info.width < 2000 + 700 && info.height < 2000 + 200,
        "{info:?}"
    );
    let svg = std::fs::read_to_string(dir.join("trajectory.svg")).unwrap();
    assert!(
        svg.contains("data:image/png;base64,"),
        "no embedded map image"
    );
    assert!(svg.len() < 8 << 20, "SVG of {} bytes", svg.len());
    std::fs::remove_dir_all(dir).ok();
}

#[test]
fn maps_over_the_limit_are_typed_errors_naming_the_flag() {
    let dir = temp_dir("limit");
    let vendored = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/movingai/warehouse-10-20-10-2-1.map");
    let small = generate(
        &WarehouseParams {
            width: 60,
            height: 40,
            ..WarehouseParams::default()
        },
        &MapOptions::default(),
    )
    .unwrap();
    let yaml = write_ros(&small.grid, &dir);
    // Moving AI (161 x 63) and ROS (60 x 40) files under a small limit, each with `plan`;
    // the ROS map with `run`, and a generated warehouse over the default limit.
    let (map, ros) = (vendored.to_str().unwrap(), yaml.to_str().unwrap());
    let cases: [(Vec<&str>, &str, &str); 4] = [
        (
            vec![
                "plan",
                "--map",
                map,
                "--start",
                "1,1",
                "--goal",
                "2,2",
                "--max-cells",
                "100x100",
            ],
            map,
            "161 x 63",
        ),
        (
            vec![
                "plan",
                "--map",
                ros,
                "--start",
                "1,1",
                "--goal",
                "2,2",
                "--max-cells",
                "2399",
            ],
            ros,
            "60 x 40",
        ),
        (
            vec![
                "run",
                "--map",
                ros,
                "--planner",
                "inproc",
                "--max-cells",
                "2000",
            ],
            ros,
            "60 x 40",
        ),
        (
            vec![
                "run",
                "--width",
                "5000",
                "--height",
                "4096",
                "--planner",
                "inproc",
            ],
            "generated warehouse",
            "5000 x 4096",
        ),
    ];
    for (args, source, size) in cases {
        let out = host_sim(&args);
        assert!(!out.status.success(), "{args:?}");
        let err = String::from_utf8_lossy(&out.stderr);
        for part in [source, size, "over the limit", "--max-cells"] {
            assert!(err.contains(part), "{args:?}: {err}");
        }
    }
    // Raising the limit lets the same map through.
    let out = host_sim(&[
        "plan",
        "--map",
        vendored.to_str().unwrap(),
        "--start",
        "143,57",
        "--goal",
        "10,16",
        "--max-cells",
        "161x63",
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    assert_eq!(DEFAULT_MAX_CELLS, 4096 * 4096);
    std::fs::remove_dir_all(dir).ok();
}

//! `host-sim terrain` end to end, checked independently: every path the CLI reports as valid
//! (the paths behind tables 2-7 and the pictures) is re-checked in `f64` by
//! `host_sim::terrain_check`, which shares no geometry with planner-core: on the map, on the
//! ground (a ground robot, SPEC section 4) or at/above it (literal mode), and outside every
//! cylinder and cone, sampled every 2.5 m along every segment. The checker is also shown to
//! reject paths through the experiments' obstacles.

use host_sim::terrain_check::{Ground, Heights, Kind, Report, Solid, Violation, check};
use serde_json::Value;
use std::path::{Path, PathBuf};
use std::process::Command;

const STEP: f64 = 0.0025;
const ON_GROUND: Heights = Heights::OnGround { tol: 1e-4 };

fn run_cli(dir: &Path, args: &[&str]) -> Value {
    let out = Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .arg("terrain")
        .args(args)
        .arg("--out")
        .arg(dir)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(dir.join("results.json")).unwrap();
    serde_json::from_str(&text).unwrap()
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("host-sim-terrain-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap()
}

fn pair(v: &Value) -> (f64, f64) {
    (f(&v[0]), f(&v[1]))
}

/// The terrain samples of a `results.json`.
fn samples(doc: &Value) -> Vec<f32> {
    doc["terrain"]["z"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| f(v) as f32)
        .collect()
}

fn ground<'a>(doc: &Value, z: &'a [f32]) -> Ground<'a> {
    let t = &doc["terrain"];
    Ground::new(
        t["width"].as_u64().unwrap() as usize,
        t["height"].as_u64().unwrap() as usize,
        f(&t["spacing"]),
        z,
    )
    .unwrap()
}

fn solids(doc: &Value) -> Vec<Solid> {
    doc["experiment"]["obstacles"]
        .as_array()
        .unwrap()
        .iter()
        .map(|o| Solid {
            kind: match o["shape"].as_str().unwrap() {
                "Cylinder" => Kind::Cylinder,
                "Cone" => Kind::Cone,
                other => panic!("unknown shape {other}"),
            },
            x: f(&o["x"]),
            y: f(&o["y"]),
            radius: f(&o["radius"]),
            foot: f(&o["base"]),
            height: f(&o["height"]),
        })
        .collect()
}

fn path(run: &Value) -> Vec<[f64; 3]> {
    run["path"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| [f(&p[0]), f(&p[1]), f(&p[2])])
        .collect()
}

/// Checks every run of `doc`; returns the number of valid runs per algorithm.
fn check_all(doc: &Value, heights: Heights) -> Vec<(String, usize, usize)> {
    let z = samples(doc);
    let g = ground(doc, &z);
    let obs = solids(doc);
    let start = pair(&doc["experiment"]["start"]);
    let goal = pair(&doc["experiment"]["goal"]);
    let e = &doc["objective"]["energy"];
    let per_km = f(&e["a"]) * f(&e["v"]).powi(2)
        + f(&e["b"]) * f(&e["acc"]).powi(2)
        + f(&e["c"]) * f(&e["mu"])
        + f(&e["d"]) * f(&e["load"]);
    assert!((per_km - 6.5).abs() < 1e-6, "Zhu2025Orchard: E = 6.5 L");
    let mut counts: Vec<(String, usize, usize)> = Vec::new();
    for run in doc["results"].as_array().unwrap() {
        let name = run["algorithm"].as_str().unwrap().to_string();
        let valid = run["valid"].as_bool().unwrap();
        if !counts.iter().any(|c| c.0 == name) {
            counts.push((name.clone(), 0, 0));
        }
        let c = counts.iter_mut().find(|c| c.0 == name).unwrap();
        c.2 += 1;
        if !valid {
            continue;
        }
        c.1 += 1;
        let p = path(run);
        let report: Report = check(&g, &obs, &p, start, goal, heights, STEP)
            .unwrap_or_else(|v| panic!("{name} run {}: {v:?}", run["run"]));
        if matches!(heights, Heights::OnGround { .. }) && !obs.is_empty() {
            // A ground robot meets the obstacles at their foot: the whole base disc is kept.
            assert!(report.min_base_clearance > 0.0, "{name}: {report:?}");
        }
        // The tables' numbers are those of the checked path.
        let length = f(&run["best"]["length"]);
        let energy = f(&run["best"]["energy"]);
        assert!(
            (report.length - length).abs() <= 1e-3 * length,
            "{name}: reported L {length}, checked {}",
            report.length
        );
        assert!((energy - per_km * report.length).abs() <= 1e-3 * energy);
        assert_eq!(f(&run["best"]["obstacle"]), 0.0);
    }
    counts
}

#[test]
fn reported_terrain_paths_stay_on_the_ground_and_outside_every_obstacle() {
    for e in ["1", "2", "3"] {
        let dir = tmp(&format!("exp{e}"));
        let doc = run_cli(
            &dir,
            &[
                "--experiment",
                e,
                "--runs",
                "2",
                "--iterations",
                "40",
                "--population",
                "30",
            ],
        );
        assert_eq!(doc["mode"], "terrain");
        let counts = check_all(&doc, ON_GROUND);
        assert_eq!(counts.len(), 5, "{counts:?}");
        for (name, valid, total) in &counts {
            assert_eq!(*total, 2);
            // SSA-GWO must find valid paths even in this short run.
            if name == "SSA-GWO" {
                assert_eq!(valid, total, "experiment {e}: {counts:?}");
            }
        }
        assert!(dir.join("tables.csv").exists() && dir.join("paths.png").exists());
        let _ = std::fs::remove_dir_all(&dir);
    }
}

#[test]
fn shifted_search_box_reports_unshifted_valid_paths() {
    // `--shift 5`: the optimizers search offset + 5 km; the reported paths must still be the
    // evaluated ones (valid, and their L the one in the tables).
    let dir = tmp("shift");
    let doc = run_cli(
        &dir,
        &[
            "--experiment",
            "3",
            "--shift",
            "5",
            "--runs",
            "1",
            "--iterations",
            "40",
            "--population",
            "30",
        ],
    );
    assert_eq!(f(&doc["shift"]), 5.0);
    let counts = check_all(&doc, ON_GROUND);
    let ssa_gwo = counts.iter().find(|c| c.0 == "SSA-GWO").unwrap();
    assert_eq!(ssa_gwo.1, 1, "{counts:?}");
    // Reporting the searched `v` instead of the offsets would move the path 5 km sideways.
    let run = doc["results"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["algorithm"] == "SSA-GWO")
        .unwrap();
    let length = f(&run["best"]["length"]);
    println!("SSA-GWO with --shift 5: L = {length} km");
    assert!(length < 32.0, "{length}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn literal_mode_paths_stay_above_the_ground_and_outside_every_obstacle() {
    let dir = tmp("literal");
    let doc = run_cli(
        &dir,
        &[
            "--experiment",
            "3",
            "--literal",
            "--runs",
            "1",
            "--iterations",
            "40",
            "--population",
            "30",
        ],
    );
    assert_eq!(doc["mode"], "free");
    let counts = check_all(&doc, Heights::AtOrAbove { tol: 1e-4 });
    // ACO has no literal form.
    assert_eq!(counts.len(), 4, "{counts:?}");
    assert!(counts.iter().any(|c| c.1 > 0), "{counts:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn the_check_rejects_paths_through_the_experiments_obstacles() {
    let dir = tmp("reject");
    let doc = run_cli(
        &dir,
        &[
            "--experiment",
            "3",
            "--runs",
            "1",
            "--iterations",
            "30",
            "--population",
            "20",
        ],
    );
    let z = samples(&doc);
    let g = ground(&doc, &z);
    let obs = solids(&doc);
    assert_eq!(obs.len(), 3);
    let start = pair(&doc["experiment"]["start"]);
    let goal = pair(&doc["experiment"]["goal"]);
    // Experiment 3 puts its obstacles across the straight line: draped over the ground, it is
    // rejected.
    let straight: Vec<[f64; 3]> = (0..=200)
        .map(|k| {
            let t = f64::from(k) / 200.0;
            let (x, y) = (
                start.0 + t * (goal.0 - start.0),
                start.1 + t * (goal.1 - start.1),
            );
            [x, y, g.height(x, y)]
        })
        .collect();
    assert!(matches!(
        check(&g, &obs, &straight, start, goal, ON_GROUND, STEP),
        Err(Violation::Collision { .. })
    ));
    // A valid reported path with one vertex moved next to the cone's axis (on the ground) is
    // rejected; so is one lifted off the ground or pushed off the map.
    let run = doc["results"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["valid"].as_bool().unwrap())
        .expect("a valid run");
    let good = path(run);
    assert!(check(&g, &obs, &good, start, goal, ON_GROUND, STEP).is_ok());
    let cone = obs.iter().find(|o| o.kind == Kind::Cone).unwrap();
    let mut bad = good.clone();
    let m = bad.len() / 2;
    let (x, y) = (cone.x + 0.1 * cone.radius, cone.y);
    bad[m] = [x, y, g.height(x, y)];
    assert!(matches!(
        check(&g, &obs, &bad, start, goal, ON_GROUND, STEP),
        Err(Violation::Collision { .. })
    ));
    let mut lifted = good.clone();
    lifted[m][2] += 0.05;
    assert!(matches!(
        check(&g, &obs, &lifted, start, goal, ON_GROUND, STEP),
        Err(Violation::Height { .. })
    ));
    let mut off = good.clone();
    off[m][1] = -0.5;
    off[m][2] = g.height(off[m][0], 0.0);
    assert!(check(&g, &obs, &off, start, goal, ON_GROUND, STEP).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Re-checks saved full runs: `TERRAIN_RESULTS=a/results.json:b/results.json cargo test -p
/// host-sim --test terrain_cli -- --ignored` (the runs behind `docs/terrain-results.md`).
#[test]
#[ignore = "needs TERRAIN_RESULTS, the results.json files of full runs"]
fn saved_results_pass_the_check() {
    let list = std::env::var("TERRAIN_RESULTS").expect("set TERRAIN_RESULTS");
    for file in list.split(':').filter(|s| !s.is_empty()) {
        let doc: Value = serde_json::from_str(&std::fs::read_to_string(file).unwrap()).unwrap();
        let heights = if doc["mode"] == "free" {
            Heights::AtOrAbove { tol: 1e-4 }
        } else {
            ON_GROUND
        };
        let counts = check_all(&doc, heights);
        println!("{file}: (algorithm, valid paths checked, runs) {counts:?}");
    }
}

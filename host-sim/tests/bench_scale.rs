//! `host-sim bench scale`, small: two generated warehouses (one with clutter), a few long
//! queries, the exact any-angle planner, A* and TCLHHO at the host's defaults. The figures
//! of the issue come from the full run (`host-sim bench scale`, minutes); this checks the
//! contract: every path valid, the any-angle length the shortest, TCLHHO within 0.1% of it,
//! the one-time cost apart, the heap counted, and the table, JSON, CSV and plot written.

use serde_json::Value;
use std::process::Command;

#[test]
fn small_scale_bench_reports_valid_exact_and_near_exact_paths() {
    let out_dir = std::env::temp_dir().join(format!("bench-scale-{}", std::process::id()));
    let out = Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args([
            "bench",
            "scale",
            "--maps",
            "256x128,512x256",
            "--clutter",
            "both",
            "--queries",
            "5",
            "--algos",
            "astar,anyangle,theta,tclhho",
            "--out",
            out_dir.to_str().unwrap(),
        ])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("| 512x256+clutter |"), "{stdout}");
    let records: Vec<Value> =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("scale.json")).unwrap())
            .unwrap();
    // Two maps, with and without clutter, four planners.
    assert_eq!(records.len(), 16);
    for r in &records {
        let planner = r["planner"].as_str().unwrap();
        let map = r["map"].as_str().unwrap();
        assert_eq!(r["queries"], 5, "{map} {planner}");
        assert_eq!(r["valid"], 5, "{map} {planner}: every path valid");
        let ratio = r["mean_length_ratio"].as_f64().unwrap();
        match planner {
            "anyangle" => assert!((ratio - 1.0).abs() < 1e-12),
            "tclhho" => assert!((1.0 - 1e-4..=1.001).contains(&ratio), "{map}: {ratio}"),
            // Theta* and A* bend at cell centres: never shorter than the exact length.
            _ => assert!(ratio >= 1.0 - 1e-4, "{map} {planner}: {ratio}"),
        }
        assert!(r["mean_ms"].as_f64().unwrap() > 0.0);
        assert!(r["prepare_ms"].as_f64().unwrap() > 0.0);
        assert!(r["ratio_to_astar"].as_f64().unwrap().is_finite());
        // The binary counts its heap: at least the map's own bits.
        assert!(r["peak_mb"].as_f64().unwrap() > 0.0, "{r}");
    }
    for file in ["scale.csv", "scale-time.png", "scale-time.svg"] {
        assert!(out_dir.join(file).exists(), "{file}");
    }
    std::fs::remove_dir_all(out_dir).unwrap();
}

#[test]
fn bad_map_sizes_are_refused_with_the_value() {
    let out = Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .args([
            "bench",
            "scale",
            "--maps",
            "8192x8192",
            "--out",
            "/nonexistent-never-written",
        ])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("8192x8192"), "{stderr}");
}

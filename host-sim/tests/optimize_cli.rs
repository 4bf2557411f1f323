//! `host-sim optimize`: JSON shape, determinism per seed, errors for unknown names.

use std::process::Command;

fn run(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_host-sim"))
        .arg("optimize")
        .args(args)
        .output()
        .expect("host-sim runs")
}

fn json(args: &[&str]) -> serde_json::Value {
    let out = run(args);
    assert!(
        out.status.success(),
        "stderr: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("valid JSON")
}

#[test]
fn json_shape() {
    let v = json(&[
        "--function",
        "sphere",
        "--dim",
        "5",
        "--shift",
        "37.5",
        "--algo",
        "tclhho",
        "--pop",
        "10",
        "--iters",
        "20",
        "--runs",
        "3",
        "--seed",
        "7",
    ]);
    assert_eq!(v["function"], "sphere");
    assert_eq!(v["algo"], "tclhho");
    assert_eq!(v["dim"], 5);
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 3);
    for (k, r) in runs.iter().enumerate() {
        assert_eq!(r["run"], k);
        assert_eq!(r["seed"], 7 + k as u64);
        assert!(r["best_cost"].as_f64().unwrap() >= 0.0);
        // The HHO family spends more than N (T + 1) evaluations.
        assert!(r["evaluations"].as_u64().unwrap() > 10 * 21);
        assert!(r["best_iteration"].as_u64().unwrap() <= 20);
        assert!(r["time_us"].as_f64().unwrap() >= 0.0);
        assert_eq!(r["stop"], "iterations");
    }
    for key in ["best_cost", "evaluations", "best_iteration", "time_us"] {
        for stat in ["mean", "std", "min", "max", "median"] {
            assert!(v["summary"][key][stat].is_number(), "{key}.{stat}");
        }
    }
    let min = v["summary"]["best_cost"]["min"].as_f64().unwrap();
    let max = v["summary"]["best_cost"]["max"].as_f64().unwrap();
    let mean = v["summary"]["best_cost"]["mean"].as_f64().unwrap();
    assert!(min <= mean && mean <= max);
}

#[test]
fn deterministic_per_seed() {
    let args = [
        "--function",
        "f9",
        "--algo",
        "igwo",
        "--iters",
        "30",
        "--runs",
        "2",
        "--seed",
        "11",
    ];
    let (a, b) = (json(&args), json(&args));
    for k in 0..2 {
        assert_eq!(a["runs"][k]["best_cost"], b["runs"][k]["best_cost"]);
        assert_eq!(a["runs"][k]["evaluations"], b["runs"][k]["evaluations"]);
        assert_eq!(
            a["runs"][k]["best_iteration"],
            b["runs"][k]["best_iteration"]
        );
    }
    // Run 1 of base seed 11 is run 0 of base seed 12.
    let c = json(&[
        "--function",
        "f9",
        "--algo",
        "igwo",
        "--iters",
        "30",
        "--runs",
        "1",
        "--seed",
        "12",
    ]);
    assert_eq!(a["runs"][1]["best_cost"], c["runs"][0]["best_cost"]);
}

#[test]
fn every_algorithm_and_table_function_runs() {
    for algo in [
        "hho", "tclhho", "gwo", "tgwo", "igwo", "ssa", "ssagwo", "pso", "ga",
    ] {
        for f in ["f1", "f4", "f10", "f11", "rastrigin"] {
            let v = json(&[
                "--function",
                f,
                "--algo",
                algo,
                "--iters",
                "5",
                "--pop",
                "6",
            ]);
            assert!(
                v["runs"][0]["evaluations"].as_u64().unwrap() > 0,
                "{algo} {f}"
            );
        }
    }
}

#[test]
fn stop_criteria_reported() {
    let v = json(&[
        "--function",
        "sphere",
        "--dim",
        "3",
        "--algo",
        "gwo",
        "--iters",
        "500",
        "--target",
        "100",
    ]);
    assert_eq!(v["runs"][0]["stop"], "target");
    let v = json(&[
        "--function",
        "sphere",
        "--dim",
        "3",
        "--algo",
        "gwo",
        "--iters",
        "500",
        "--max-evals",
        "100",
    ]);
    assert_eq!(v["runs"][0]["stop"], "evaluations");
}

#[test]
fn errors_for_unknown_names_and_bad_sizes() {
    for args in [
        &["--function", "sphere", "--algo", "aco"][..],
        &["--function", "nope", "--algo", "gwo"],
        &["--function", "f12", "--algo", "gwo"],
        &["--function", "f1", "--dim", "4", "--algo", "gwo"],
        &["--function", "sphere", "--dim", "129", "--algo", "gwo"],
        &["--function", "sphere", "--algo", "gwo", "--pop", "129"],
        &[
            "--function",
            "rastrigin",
            "--shift",
            "37.5",
            "--algo",
            "gwo",
        ],
        &["--function", "sphere", "--algo", "gwo", "--iters", "0"],
    ] {
        let out = run(args);
        assert!(!out.status.success(), "{args:?} should fail");
        assert!(!out.stderr.is_empty());
    }
    let out = run(&["--function", "sphere", "--algo", "aco"]);
    assert!(String::from_utf8_lossy(&out.stderr).contains("unknown algorithm"));
}

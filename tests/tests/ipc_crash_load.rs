//! The server killed with SIGKILL while several client processes are under load, in its
//! own test binary (see `ipc_restart.rs`). The clients are not restarted: during the outage
//! they get timeout / no-server errors (or unknown-map until the new server has the map),
//! then success from the new server; no request is ever answered with another request's
//! response or a wrong outcome (each answer is checked against the same engine in the
//! client process). The map's owner is this test process: it confirms its map with the new
//! server (`wait_for_map`), which hands over the publisher's history.

mod common;

use common::*;
use std::time::{Duration, Instant};

#[test]
fn server_sigkilled_under_load_clients_recover() {
    let p = prefix("crashload");
    let mut server = start_server(&p, &["--workers", "2"]);
    let map = data("random-32-32-10.map");
    // This process's client keeps the map in its publisher history: the restarted server
    // gets it as a late subscriber.
    let mut c = client(&p);
    let v = c.upload_map_file(&map, 1).unwrap();
    c.wait_for_map(1, v, Duration::from_secs(5)).unwrap();

    let clients = 4;
    let seconds = 9.0;
    let (map_text, v_text, secs) = (
        map.to_str().unwrap().to_string(),
        v.to_string(),
        seconds.to_string(),
    );
    let mut drivers: Vec<Proc> = (0..clients)
        .map(|i| {
            let seed = (i + 11).to_string();
            let planners = if i == 0 { "all" } else { "search" };
            driver(&[
                "churn", &p, &map_text, "1", &v_text, &secs, &seed, planners, "0",
            ])
        })
        .collect();
    // Load for 2.5 s, then the crash; 1.5 s without a server; then a new one.
    std::thread::sleep(Duration::from_millis(2500));
    let pid = server.child.id();
    server.signal("KILL");
    let status = server
        .wait_exit(Duration::from_secs(5))
        .expect("server reaped");
    assert!(!status.success());
    let killed_at = Instant::now();
    std::thread::sleep(Duration::from_millis(1500));
    let restarted = start_server(&p, &["--workers", "2"]);
    eprintln!(
        "server {pid} SIGKILLed; restarted after {:.2} s",
        killed_at.elapsed().as_secs_f64()
    );
    // The map's owner (this process) hands its publisher history to the new server when it
    // next talks to the service, as a map host confirming its map after a restart does.
    c.wait_for_map(1, v, Duration::from_secs(5)).unwrap();

    let mut total_ok = 0;
    for (i, d) in drivers.iter_mut().enumerate() {
        let out = driver_output(d, Duration::from_secs(60));
        let s: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        eprintln!("client {i}: {s}");
        let n = |k: &str| s[k].as_u64().unwrap();
        assert_eq!(n("mismatched"), 0, "client {i}: a wrong or foreign answer");
        assert_eq!(n("unexpected"), 0, "client {i}: an unexpected error");
        assert!(n("outage") > 0, "client {i} never noticed the crash");
        assert!(n("ok_after_outage") > 0, "client {i} did not recover");
        assert_eq!(n("sent"), n("ok") + n("outage"));
        total_ok += n("ok");
    }
    assert!(total_ok > 0);
    assert!(restarted.log_text().contains("planner-server ready"));
}

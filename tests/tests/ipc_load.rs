//! Load: 8 client processes x 10,000 requests against one server process; every response
//! is matched to its request (id, and the exact outcome the same engine computes locally
//! in the client process). Zero lost and zero mismatched; p50/p99 round trip printed.
//!
//! `PLANNER_LOAD_REQUESTS` overrides the per-client count; `PLANNER_LOAD_MODE=busy` makes
//! the clients spin instead of sleeping on their wake events.

mod common;

use common::*;
use std::time::{Duration, Instant};

#[test]
fn eight_clients_ten_thousand_requests_each() {
    let count: usize = std::env::var("PLANNER_LOAD_REQUESTS")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(10_000);
    let mode = std::env::var("PLANNER_LOAD_MODE").unwrap_or_else(|_| "blocking".into());
    let clients = 8;
    let p = prefix("load");
    let server = start_server(&p, &[]);
    let map = data("random-32-32-10.map");
    let mut c = client(&p);
    let v = c.upload_map_file(&map, 1).unwrap();
    c.wait_for_map(1, v, Duration::from_secs(5)).unwrap();

    let began = Instant::now();
    let map_text = map.to_str().unwrap().to_string();
    let (v_text, count_text) = (v.to_string(), count.to_string());
    let mut drivers: Vec<Proc> = (0..clients)
        .map(|i| {
            let seed = (i + 1).to_string();
            driver(&[
                "load",
                &p,
                &map_text,
                "1",
                &v_text,
                &count_text,
                &seed,
                &mode,
            ])
        })
        .collect();
    let mut latencies: Vec<f64> = Vec::with_capacity(clients * count);
    let (mut ok, mut lost, mut mismatched, mut sent) = (0u64, 0u64, 0u64, 0u64);
    for d in &mut drivers {
        let out = driver_output(d, Duration::from_secs(600));
        let summary: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
        sent += summary["sent"].as_u64().unwrap();
        ok += summary["ok"].as_u64().unwrap();
        lost += summary["lost"].as_u64().unwrap();
        mismatched += summary["mismatched"].as_u64().unwrap();
        latencies.extend(
            summary["latency_us"]
                .as_array()
                .unwrap()
                .iter()
                .map(|v| v.as_f64().unwrap()),
        );
    }
    let wall = began.elapsed();
    latencies.sort_by(f64::total_cmp);
    let pct = |q: f64| latencies[((latencies.len() - 1) as f64 * q).round() as usize];
    eprintln!(
        "load: {clients} client processes x {count} requests ({mode} wait): sent {sent}, ok {ok}, lost {lost}, mismatched {mismatched}; round trip p50 {:.1} us, p99 {:.1} us, max {:.1} us; wall {:.2} s ({:.0} req/s)",
        pct(0.5),
        pct(0.99),
        latencies.last().copied().unwrap_or(0.0),
        wall.as_secs_f64(),
        sent as f64 / wall.as_secs_f64()
    );
    assert_eq!(sent, (clients * count) as u64);
    assert_eq!(lost, 0, "lost responses");
    assert_eq!(mismatched, 0, "mismatched responses");
    assert_eq!(ok, sent);
    assert!(server.log_text().contains("planner-server ready"));
}

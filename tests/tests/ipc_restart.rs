//! Server crash and restart, in its own test binary: no other test creates iceoryx2 nodes
//! meanwhile (node creation cleans up dead nodes, which would turn the expected timeout
//! into `NoServer`).

mod common;

use common::*;
use planner_ipc::client::ClientError;
use planner_ipc::wire::{Algorithm, PlanRequest};
use std::time::{Duration, Instant};

const T: Duration = Duration::from_secs(5);

/// A late server gets the current map; a server killed and restarted: the client (not restarted) first gets a timeout, then
/// success once the new server is up; the new server got the map from the client's
/// publisher history.
#[test]
fn server_killed_and_restarted() {
    let p = prefix("restart");
    // The map is published before any server exists: the server is a late subscriber.
    let mut c = client(&p);
    let v = c
        .upload_map_file(&data("warehouse-10-20-10-2-1.map"), 1)
        .unwrap();
    let good = PlanRequest::new((1, v), [143, 57], [10, 16], Algorithm::AStar);
    assert_eq!(c.plan(&good, T), Err(ClientError::NoServer));
    let mut server = start_server(&p, &[]);
    c.wait_for_map(1, v, T).unwrap();
    let first = c.plan(&good, T).unwrap();

    server.kill();
    assert_eq!(
        c.plan(&good, Duration::from_millis(200)),
        Err(ClientError::Timeout)
    );

    let restarted = start_server(&p, &[]);
    // The new server normally removes the dead server's leftovers at start (logged); any
    // other process creating an iceoryx2 node on this machine may have done it first.
    eprintln!(
        "restarted server cleaned dead nodes: {}",
        restarted.log_text().contains("dead node")
    );
    let began = Instant::now();
    let second = loop {
        match c.plan(&good, Duration::from_millis(500)) {
            Ok(ok) => break ok,
            Err(e) => {
                assert!(
                    began.elapsed() < Duration::from_secs(10),
                    "no success after restart: {e:?}\n{}",
                    restarted.log_text()
                );
                std::thread::sleep(Duration::from_millis(20));
            }
        }
    };
    assert_eq!(first, second);
}

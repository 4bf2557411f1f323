//! Shared-memory resources left by a crashed server (SIGKILL) are removed when the next
//! server starts, in its own test binary (no other test creates iceoryx2 nodes meanwhile,
//! which would clean the dead node first).
//!
//! Checked through the iceoryx2 node list (the dead server's node is listed as dead after
//! the crash and is gone after the restart) and on disk: the node's directory and monitor
//! files under iceoryx2's root (`/tmp/iceoryx2/nodes` with the default configuration) exist
//! while it is alive and are gone after the restart. Another process on the machine that
//! creates an iceoryx2 node may clean up first; then the "dead" listing is skipped, but the
//! files must be gone all the same.

mod common;

use common::*;
use iceoryx2::config::Config;
use iceoryx2::node::{Node, NodeState, NodeView};
use iceoryx2::prelude::CallbackProgression;
use planner_ipc::services::Svc;
use planner_ipc::wire::{Algorithm, PlanRequest};
use std::path::PathBuf;
use std::time::{Duration, Instant};

#[derive(Debug, PartialEq)]
enum Seen {
    Alive,
    Dead,
}

/// The node created by process `pid` (id and state), if listed.
fn node_of_pid(pid: u32) -> Option<(u128, Seen)> {
    let mut found = None;
    Node::<Svc>::list(Config::global_config(), |state| {
        let (id, details, seen) = match &state {
            NodeState::Alive(v) => (v.id().value(), v.details().clone(), Seen::Alive),
            NodeState::Dead(v) => (v.id().value(), v.details().clone(), Seen::Dead),
            _ => return CallbackProgression::Continue,
        };
        if details.is_some_and(|d| d.process_id().value() as u32 == pid) {
            found = Some((id, seen));
            return CallbackProgression::Stop;
        }
        CallbackProgression::Continue
    })
    .unwrap();
    found
}

/// Whether node `id` is listed at all (any state).
fn listed(id: u128) -> bool {
    let mut seen = false;
    Node::<Svc>::list(Config::global_config(), |state| {
        let this = match &state {
            NodeState::Alive(v) => v.id().value(),
            NodeState::Dead(v) => v.id().value(),
            NodeState::Inaccessible(i) | NodeState::Undefined(i) => i.value(),
        };
        seen |= this == id;
        CallbackProgression::Continue
    })
    .unwrap();
    seen
}

/// The node's files: its directory and its `iox2_<id>.node_monitor*` files.
fn node_files(id: u128) -> Vec<PathBuf> {
    let root = PathBuf::from(Config::global_config().global.root_path().as_str()).join("nodes");
    let Ok(entries) = std::fs::read_dir(&root) else {
        return Vec::new();
    };
    let id = id.to_string();
    entries
        .filter_map(|e| e.ok())
        .map(|e| e.path())
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n == id || n.starts_with(&format!("iox2_{id}.")))
        })
        .collect()
}

#[test]
fn crashed_server_resources_removed_at_next_start() {
    let p = prefix("cleanup");
    let mut c = client(&p);
    let v = c.upload_map_file(&data("random-32-32-10.map"), 1).unwrap();
    let good = PlanRequest::new((1, v), [0, 0], [31, 31], Algorithm::AStar);
    let mut server = start_server(&p, &[]);
    c.wait_for_map(1, v, Duration::from_secs(5)).unwrap();
    let first = c.plan(&good, Duration::from_secs(5));
    assert!(!matches!(
        first,
        Err(planner_ipc::client::ClientError::Timeout | planner_ipc::client::ClientError::NoServer)
    ));

    let pid = server.child.id();
    let (id, state) = node_of_pid(pid).expect("the running server's node is listed");
    assert_eq!(state, Seen::Alive);
    let files = node_files(id);
    eprintln!("server {pid}: node {id}, files {files:?}");
    assert!(
        files.iter().any(|f| f.is_dir()) && files.len() >= 2,
        "node files of a live server not found: {files:?}"
    );

    server.signal("KILL");
    server
        .wait_exit(Duration::from_secs(5))
        .expect("server reaped");
    match node_of_pid(pid) {
        Some((dead, Seen::Dead)) => {
            assert_eq!(dead, id);
            assert!(
                !node_files(id).is_empty(),
                "dead node's files vanished by themselves"
            );
            eprintln!("after SIGKILL: node {id} listed dead, files still there");
        }
        other => {
            eprintln!("after SIGKILL: node {id} already cleaned by another process ({other:?})")
        }
    }

    let restarted = start_server(&p, &[]);
    assert!(
        !listed(id),
        "the dead server's node is still listed after the restart:\n{}",
        restarted.log_text()
    );
    let left = node_files(id);
    assert!(left.is_empty(), "dead node's files left: {left:?}");
    eprintln!(
        "restart log: {}",
        restarted
            .log_text()
            .lines()
            .filter(|l| l.contains("dead node"))
            .collect::<Vec<_>>()
            .join(" | ")
    );

    // The new server serves on the same service names: the crashed server's port is gone.
    let began = Instant::now();
    loop {
        match c.plan(&good, Duration::from_millis(500)) {
            r @ (Ok(_) | Err(planner_ipc::client::ClientError::Plan(_))) => {
                assert_eq!(r, first);
                break;
            }
            Err(e) => {
                assert!(
                    began.elapsed() < Duration::from_secs(10),
                    "no answer: {e:?}"
                );
                std::thread::sleep(Duration::from_millis(20));
            }
        }
    }
}

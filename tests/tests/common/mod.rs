//! Helpers for the cross-process tests: child processes that are always killed and
//! reaped (no zombies, no servers left running), unique service prefixes, test maps.

#![allow(dead_code)]

use planner_ipc::client::{ClientConfig, PlannerClient};
use planner_ipc::services::Names;
use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// The keys of a `planner-client plan` line, in order.
pub const PLAN_LINE_KEYS: [&str; 10] = [
    "start",
    "goal",
    "path",
    "length",
    "time_us",
    "turns",
    "expanded",
    "algo",
    "seed",
    "round_trip_us",
];

/// The keys of a JSON line (an object), in order.
pub fn line_keys(line: &serde_json::Value) -> Vec<&str> {
    line.as_object()
        .map_or_else(Vec::new, |o| o.keys().map(String::as_str).collect())
}

/// A unique service prefix for one test (process id + test name).
pub fn prefix(test: &str) -> String {
    format!("it-{}-{test}", std::process::id())
}

/// A vendored Moving AI map.
pub fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("data/movingai")
        .join(name)
}

/// A scratch directory for one test.
pub fn scratch_dir(prefix: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(prefix);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

/// Writes a Moving AI map of `width x height` where `blocked(x, y)` marks obstacles.
pub fn write_map(path: &Path, width: usize, height: usize, blocked: impl Fn(usize, usize) -> bool) {
    let mut text = format!("type octile\nheight {height}\nwidth {width}\nmap\n");
    for y in 0..height {
        for x in 0..width {
            text.push(if blocked(x, y) { '@' } else { '.' });
        }
        text.push('\n');
    }
    std::fs::write(path, text).unwrap();
}

/// A child process that is killed and reaped when dropped.
pub struct Proc {
    pub child: Child,
    pub log: Option<PathBuf>,
}

impl Proc {
    /// Sends a signal by name (`TERM`, `INT`, `KILL`) through `kill(1)`.
    pub fn signal(&self, name: &str) {
        let status = Command::new("kill")
            .arg(format!("-{name}"))
            .arg(self.child.id().to_string())
            .status()
            .unwrap();
        assert!(status.success());
    }

    /// Sends `STOP` and waits until every thread of the process is stopped: `kill` returns
    /// once the signal is queued, and a thread of a busy machine stops when next scheduled.
    pub fn stop(&self) {
        self.signal("STOP");
        let tasks = PathBuf::from(format!("/proc/{}/task", self.child.id()));
        let stopped = |task: std::fs::DirEntry| {
            let stat = std::fs::read_to_string(task.path().join("stat")).unwrap_or_default();
            // The state follows the command's closing parenthesis.
            let state = stat
                .rsplit_once(')')
                .and_then(|(_, r)| r.trim().chars().next());
            matches!(state, Some('T' | 't'))
        };
        let began = Instant::now();
        while !std::fs::read_dir(&tasks)
            .unwrap()
            .all(|t| t.map(stopped).unwrap_or(true))
        {
            assert!(began.elapsed() < Duration::from_secs(10), "not stopped");
            std::thread::sleep(Duration::from_millis(1));
        }
    }

    /// Waits for the exit status, at most `timeout`.
    pub fn wait_exit(&mut self, timeout: Duration) -> Option<std::process::ExitStatus> {
        let began = Instant::now();
        while began.elapsed() < timeout {
            if let Some(status) = self.child.try_wait().unwrap() {
                return Some(status);
            }
            std::thread::sleep(Duration::from_millis(10));
        }
        None
    }

    /// The log written so far.
    pub fn log_text(&self) -> String {
        self.log
            .as_ref()
            .and_then(|p| std::fs::read_to_string(p).ok())
            .unwrap_or_default()
    }

    /// Kills (SIGKILL) and reaps the process now.
    pub fn kill(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

impl Drop for Proc {
    fn drop(&mut self) {
        self.kill();
    }
}

/// Starts `ipc-test-server` (the `planner-server` program) and waits until it is ready.
pub fn start_server(prefix: &str, extra: &[&str]) -> Proc {
    let log = scratch_dir(prefix).join(format!("server-{}.log", rand_suffix()));
    let file = std::fs::File::create(&log).unwrap();
    let child = Command::new(env!("CARGO_BIN_EXE_ipc-test-server"))
        .args(["--prefix", prefix])
        .args(extra)
        .env("RUST_LOG", "info")
        .stdout(Stdio::null())
        .stderr(file)
        .spawn()
        .unwrap();
    let proc = Proc {
        child,
        log: Some(log),
    };
    let began = Instant::now();
    while !proc.log_text().contains("planner-server ready") {
        assert!(
            began.elapsed() < Duration::from_secs(20),
            "server did not start:\n{}",
            proc.log_text()
        );
        std::thread::sleep(Duration::from_millis(10));
    }
    proc
}

fn rand_suffix() -> u128 {
    std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .unwrap()
        .as_nanos()
}

/// Spawns `ipc-test-driver` with piped stdout.
pub fn driver(args: &[&str]) -> Proc {
    let child = Command::new(env!("CARGO_BIN_EXE_ipc-test-driver"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .unwrap();
    Proc { child, log: None }
}

/// Reads a driver's whole stdout (until it closes it), then reaps the driver.
pub fn driver_output(proc: &mut Proc, timeout: Duration) -> String {
    let mut out = String::new();
    // Read first: a driver blocked on a full pipe would never exit.
    proc.child
        .stdout
        .take()
        .unwrap()
        .read_to_string(&mut out)
        .unwrap();
    let status = proc.wait_exit(timeout).expect("driver did not finish");
    assert!(status.success(), "driver failed: {status:?}");
    out
}

/// An in-process client (the test process is itself a client process).
pub fn client(prefix: &str) -> PlannerClient {
    PlannerClient::new(ClientConfig {
        names: Names::new(prefix),
        node_name: format!("test-client-{}", std::process::id()),
        ..ClientConfig::default()
    })
    .unwrap()
}

/// Zenoh: a port of 127.0.0.1 free now whose next port (the map session's) is free too.
pub fn zport() -> u16 {
    planner_ipc::zenoh::config::free_port_pair().unwrap()
}

/// Zenoh: the TCP endpoint of a port of 127.0.0.1.
pub fn zendpoint(port: u16) -> String {
    format!("tcp/127.0.0.1:{port}")
}

/// Starts `ipc-test-server --transport zenoh` with more options and waits until it is
/// ready (a planner, or a router with `--route-only`).
pub fn start_zenoh_server(prefix: &str, extra: &[&str]) -> Proc {
    let mut args = vec!["--transport", "zenoh"];
    args.extend_from_slice(extra);
    start_server(prefix, &args)
}

/// A Zenoh client in this process (requests as queries).
pub fn zclient(
    prefix: &str,
    mode: planner_ipc::zenoh::Mode,
    connect: &[String],
) -> planner_ipc::zenoh::ZenohClient {
    zclient_on(
        prefix,
        mode,
        connect,
        planner_ipc::zenoh::RequestPath::Query,
    )
}

/// A Zenoh client in this process, requests travelling by `path`.
pub fn zclient_on(
    prefix: &str,
    mode: planner_ipc::zenoh::Mode,
    connect: &[String],
    path: planner_ipc::zenoh::RequestPath,
) -> planner_ipc::zenoh::ZenohClient {
    use planner_ipc::zenoh::{ClientConfig, ZenohClient, ZenohOptions};
    ZenohClient::open(ClientConfig {
        prefix: prefix.to_string(),
        path,
        options: ZenohOptions {
            mode,
            connect: connect.to_vec(),
            ..ZenohOptions::default()
        },
        ..ClientConfig::default()
    })
    .unwrap()
}

/// Waits until a Zenoh client sees a planner (at most 20 s).
pub fn wait_for_planner(client: &mut planner_ipc::zenoh::ZenohClient) {
    let began = Instant::now();
    while let Err(e) = client.check_planners() {
        assert!(began.elapsed() < Duration::from_secs(20), "no planner: {e}");
        std::thread::sleep(Duration::from_millis(20));
    }
}

/// The Moving AI warehouse the Zenoh tests plan on.
pub const WAREHOUSE: &str = "warehouse-10-20-10-2-1.map";

/// Map metadata in cells (no world frame).
pub fn meta(map_id: u32, version: u32) -> planner_ipc::wire::MapMeta {
    planner_ipc::wire::MapMeta {
        map_id,
        version,
        resolution: 1.0,
        origin: [0.0, 0.0],
    }
}

/// Uploads [`WAREHOUSE`] over Zenoh as map `map_id` version 1 and waits until a planner
/// has it, at its size.
pub fn upload_warehouse(client: &mut planner_ipc::zenoh::ZenohClient, map_id: u32) {
    let grid = planner_ipc::client::parse_map(&std::fs::read(data(WAREHOUSE)).unwrap()).unwrap();
    client.upload_map(meta(map_id, 1), grid.view()).unwrap();
    let facts = client
        .wait_for_map(map_id, 1, Duration::from_secs(10))
        .unwrap();
    assert_eq!(
        (facts.width, facts.height),
        (grid.width() as u32, grid.height() as u32)
    );
}

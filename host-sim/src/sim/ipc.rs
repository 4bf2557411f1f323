//! The global planner over iceoryx2: a client of `planner-server` (crate `planner-ipc`).
//!
//! [`IpcPlanner::connect_or_start`] uses a server already serving the given service prefix,
//! or starts one as a child process (this very binary's hidden `serve` subcommand) under a
//! prefix of its own (`host-sim-<pid>-<n>`), so the demo needs no setup and two simulators
//! never share a server they did not ask for. The child's standard input is a pipe from this
//! process: when the planner is dropped the child gets SIGTERM, and if this process dies
//! the pipe closes and the child shuts itself down.

use super::planner::{GlobalPlanRequest, GlobalPlanner, PlanFailure, PlannedPath};
use planner_core::geometry::Cell;
use planner_core::grid::GridRef;
use planner_core::planner::PlannerKind;
use planner_ipc::client::{ClientConfig, ClientError, PlannerClient};
use planner_ipc::services::Names;
use planner_ipc::wire::{self, Algorithm, MapMeta};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::atomic::{AtomicU32, Ordering};
use std::time::{Duration, Instant};

/// Map id the simulator publishes under.
pub(crate) const MAP_ID: u32 = 1;

/// A `planner-server` client implementing [`GlobalPlanner`].
pub struct IpcPlanner {
    client: PlannerClient,
    server: Option<(Child, ChildStdin)>,
    prefix: String,
    version: u32,
    timeout: Duration,
}

/// A service prefix no other process uses.
pub fn private_prefix() -> String {
    static N: AtomicU32 = AtomicU32::new(0);
    format!(
        "host-sim-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    )
}

fn client(prefix: &str) -> anyhow::Result<PlannerClient> {
    planner_ipc::services::quiet_iceoryx_logs();
    static N: AtomicU32 = AtomicU32::new(0);
    let config = ClientConfig {
        names: Names::new(prefix),
        node_name: format!(
            "host-sim-{}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ),
        ..ClientConfig::default()
    };
    PlannerClient::new(config).map_err(|e| anyhow::anyhow!("iceoryx2 client: {e}"))
}

impl IpcPlanner {
    /// Connects to a server serving `prefix` if one answers within `probe`; otherwise
    /// starts a private server (see the module documentation). `log` receives the started
    /// server's standard error (discarded when `None`).
    pub fn connect_or_start(
        prefix: &str,
        probe: Duration,
        log: Option<&std::path::Path>,
    ) -> anyhow::Result<Self> {
        if !probe.is_zero() {
            let mut planner = IpcPlanner {
                client: client(prefix)?,
                server: None,
                prefix: prefix.to_string(),
                version: 0,
                timeout: Duration::from_secs(60),
            };
            if planner.server_answers(probe) {
                return Ok(planner);
            }
        }
        Self::start(log)
    }

    /// Starts a private server (this executable's `serve`) and connects to it.
    pub fn start(log: Option<&std::path::Path>) -> anyhow::Result<Self> {
        Self::start_with(&std::env::current_exe()?, log)
    }

    /// Starts a private server with `exe serve` (a `host-sim` binary) and connects to it.
    pub fn start_with(
        exe: &std::path::Path,
        log: Option<&std::path::Path>,
    ) -> anyhow::Result<Self> {
        let prefix = private_prefix();
        let stderr = match log {
            Some(path) => Stdio::from(std::fs::File::create(path)?),
            None => Stdio::null(),
        };
        let mut child = Command::new(exe)
            .args(["serve", "--prefix", &prefix, "--exit-on-stdin-eof"])
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(stderr)
            .spawn()?;
        let Some(stdin) = child.stdin.take() else {
            let _ = child.kill();
            let _ = child.wait();
            anyhow::bail!("cannot open a pipe to the planner server");
        };
        let mut planner = IpcPlanner {
            client: client(&prefix)?,
            server: Some((child, stdin)),
            prefix: prefix.clone(),
            version: 0,
            timeout: Duration::from_secs(60),
        };
        if !planner.server_answers(Duration::from_secs(20)) {
            anyhow::bail!("started planner-server (prefix {prefix}) but it does not answer");
        }
        Ok(planner)
    }

    /// Whether this planner started the server it talks to.
    pub fn started_server(&self) -> bool {
        self.server.is_some()
    }

    /// Process id of the server this planner started.
    pub fn server_pid(&self) -> Option<u32> {
        self.server.as_ref().map(|(child, _)| child.id())
    }

    /// The service prefix in use.
    pub fn prefix(&self) -> &str {
        &self.prefix
    }

    /// A server answers a status request for a map nobody published with `UnknownMap`.
    fn server_answers(&mut self, within: Duration) -> bool {
        let deadline = Instant::now() + within;
        let mut probe = wire::PlanRequest::new((u32::MAX, 1), [0, 0], [0, 0], Algorithm::AStar);
        probe.kind = wire::RequestKind::MapStatus.code();
        loop {
            if let Some((child, _)) = self.server.as_mut()
                && let Ok(Some(_)) = child.try_wait()
            {
                return false;
            }
            let left = deadline.saturating_duration_since(Instant::now());
            match self.client.plan(
                &probe,
                left.clamp(Duration::from_millis(20), Duration::from_secs(1)),
            ) {
                Err(ClientError::NoServer) | Err(ClientError::Timeout) if !left.is_zero() => {
                    std::thread::sleep(Duration::from_millis(20));
                }
                Ok(_) | Err(ClientError::Service(_)) | Err(ClientError::Plan(_)) => return true,
                Err(_) => return false,
            }
        }
    }
}

impl Drop for IpcPlanner {
    fn drop(&mut self) {
        if let Some((mut child, stdin)) = self.server.take() {
            // Closing the pipe asks the server to stop (it raises SIGTERM on itself, answers
            // what is queued and removes its services).
            drop(stdin);
            let deadline = Instant::now() + Duration::from_secs(5);
            while Instant::now() < deadline {
                if let Ok(Some(_)) = child.try_wait() {
                    return;
                }
                std::thread::sleep(Duration::from_millis(10));
            }
            let _ = child.kill();
            let _ = child.wait();
        }
    }
}

/// The planner service's request for a simulator request on map `(id, version)`.
pub(crate) fn wire_request(
    request: &GlobalPlanRequest,
    map: (u32, u32),
) -> Result<wire::PlanRequest, PlanFailure> {
    let algorithm = Algorithm::ALL
        .into_iter()
        .find(|a| a.kind() == request.algo)
        .ok_or_else(|| PlanFailure::Transport(format!("{} is not served", request.algo.name())))?;
    let cell = |c: Cell| [c.x as i32, c.y as i32];
    let mut r = wire::PlanRequest::new(map, cell(request.start), cell(request.goal), algorithm);
    r.seed = request.seed;
    if matches!(request.algo, PlannerKind::Swarm(_)) {
        // Counts beyond the wire's range are refused by the server as InvalidParameters.
        r.params.population = u32::try_from(request.params.population).unwrap_or(u32::MAX);
        r.params.iterations = request.params.iterations;
        r.params.stagnation = request.params.stagnation.unwrap_or(0);
        r.params.guide = wire::Guide::of(request.params.guide).code();
        r.params.clearance = request.params.blend.clearance;
        r.params.clearance_weight = request.params.blend.clearance_weight;
        r.params.turn_weight = request.params.blend.turn_weight;
    }
    Ok(r)
}

/// The simulator's map `MAP_ID` at `version`, in cells (no world frame).
pub(crate) fn map_meta(version: u32) -> MapMeta {
    MapMeta {
        map_id: MAP_ID,
        version,
        resolution: 1.0,
        origin: [0.0, 0.0],
    }
}

/// A service's answer as the simulator's planned path, planned in `time`.
pub(crate) fn planned(ok: wire::PlanOk, time: Duration) -> PlannedPath {
    PlannedPath {
        points: ok.path,
        length: ok.length,
        history: Vec::new(),
        evaluations: ok.evaluations as u64,
        time,
    }
}

fn failure(e: ClientError) -> PlanFailure {
    match e {
        ClientError::Plan(p) => p.into(),
        e @ ClientError::MapTooLarge(_) => PlanFailure::MapTooLarge(e.to_string()),
        other => PlanFailure::Transport(other.to_string()),
    }
}

impl GlobalPlanner for IpcPlanner {
    fn name(&self) -> &'static str {
        "ipc"
    }

    fn set_map(&mut self, grid: GridRef<'_>) -> Result<(), PlanFailure> {
        self.version += 1;
        self.client
            .upload_map(map_meta(self.version), grid)
            .map_err(failure)?;
        self.client
            .wait_for_map(MAP_ID, self.version, self.timeout)
            .map_err(failure)?;
        Ok(())
    }

    fn plan(&mut self, request: &GlobalPlanRequest) -> Result<PlannedPath, PlanFailure> {
        let r = wire_request(request, (MAP_ID, self.version))?;
        let t0 = Instant::now();
        let ok = self.client.plan(&r, self.timeout).map_err(failure)?;
        Ok(planned(ok, t0.elapsed()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_ipc::client::{MapTooLarge, Refusal};

    /// Transport failures carry the client error's message (naming the limit and the flag
    /// that raises it), not its `Debug` form.
    #[test]
    fn transport_failures_print_the_message() {
        let e = ClientError::MapTooLarge(MapTooLarge {
            size: Some((5000, 5000)),
            max_cells: Some(4096 * 4096),
            refused_by: Refusal::Client,
        });
        let want = e.to_string();
        assert!(want.contains("--max-cells 25000000"), "{want}");
        match failure(e) {
            PlanFailure::MapTooLarge(message) => assert_eq!(message, want),
            other => panic!("{other:?}"),
        }
        assert_eq!(
            failure(ClientError::Timeout).to_string(),
            "transport: the server did not answer in time"
        );
    }
}

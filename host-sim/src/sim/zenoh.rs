//! The global planner over Zenoh (feature `zenoh`): a client of `planner-server
//! --transport zenoh` (crate `planner-ipc`), on this host or another.
//!
//! [`ZenohPlanner::connect_or_start`] uses a planner alive at the given endpoint, or starts
//! one as a child process (this very binary's hidden `serve`, with `--transport zenoh` on
//! free ports of 127.0.0.1 and a prefix of its own), like [`super::ipc::IpcPlanner`]: the
//! child stops when the planner is dropped or this process dies (its standard input closes).

use super::ipc::{MAP_ID, map_meta, planned, private_prefix, wire_request};
use super::planner::{GlobalPlanRequest, GlobalPlanner, PlanFailure, PlannedPath};
use planner_core::grid::GridRef;
use planner_ipc::zenoh::config::{ONE_WORKER_RUNTIME, RUNTIME_ENV, free_port_pair};
use planner_ipc::zenoh::{ClientConfig, ZenohClient, ZenohError, ZenohOptions};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::time::{Duration, Instant};

/// The endpoint `--planner zenoh` looks for a planner at before starting its own.
pub const DEFAULT_ENDPOINT: &str = "tcp/127.0.0.1:7447";

/// A `planner-server --transport zenoh` client implementing [`GlobalPlanner`].
pub struct ZenohPlanner {
    client: ZenohClient,
    server: Option<(Child, ChildStdin)>,
    endpoint: String,
    prefix: String,
    version: u32,
    timeout: Duration,
}

fn open(prefix: &str, endpoint: &str) -> Result<ZenohClient, ZenohError> {
    ZenohClient::open(ClientConfig {
        prefix: prefix.to_string(),
        options: ZenohOptions {
            connect: vec![endpoint.to_string()],
            ..ZenohOptions::default()
        },
        ..ClientConfig::default()
    })
}

impl ZenohPlanner {
    /// Connects to a planner alive at `endpoint` under `prefix` if one shows within `probe`;
    /// otherwise starts a private one (module documentation). `log` receives the started
    /// server's standard error (discarded when `None`).
    pub fn connect_or_start(
        endpoint: &str,
        prefix: &str,
        probe: Duration,
        log: Option<&std::path::Path>,
    ) -> anyhow::Result<Self> {
        if !probe.is_zero()
            && let Ok(mut client) = open(prefix, endpoint)
        {
            let until = Instant::now() + probe;
            loop {
                if client.check_planners().is_ok() {
                    return Ok(ZenohPlanner {
                        client,
                        server: None,
                        endpoint: endpoint.to_string(),
                        prefix: prefix.to_string(),
                        version: 0,
                        timeout: Duration::from_secs(60),
                    });
                }
                if Instant::now() >= until {
                    break;
                }
                std::thread::sleep(Duration::from_millis(20));
            }
        }
        Self::start(log)
    }

    /// Starts a private server (this executable's `serve`) and connects to it.
    pub fn start(log: Option<&std::path::Path>) -> anyhow::Result<Self> {
        Self::start_with(&std::env::current_exe()?, log)
    }

    /// Starts a private server with `exe serve -- --transport zenoh ...` (a `host-sim`
    /// binary) on free ports of 127.0.0.1 and connects to it.
    pub fn start_with(
        exe: &std::path::Path,
        log: Option<&std::path::Path>,
    ) -> anyhow::Result<Self> {
        let prefix = private_prefix();
        let port = free_port_pair()?;
        let endpoint = format!("tcp/127.0.0.1:{port}");
        let stderr = match log {
            Some(path) => Stdio::from(std::fs::File::create(path)?),
            None => Stdio::null(),
        };
        let mut child = Command::new(exe)
            .args(["serve", "--prefix", &prefix, "--exit-on-stdin-eof", "--"])
            .args(["--transport", "zenoh", "--listen", &endpoint])
            .env(RUNTIME_ENV, ONE_WORKER_RUNTIME)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(stderr)
            .spawn()?;
        let Some(stdin) = child.stdin.take() else {
            let _ = child.kill();
            let _ = child.wait();
            anyhow::bail!("cannot open a pipe to the planner server");
        };
        let mut server = Some((child, stdin));
        let began = Instant::now();
        let client = loop {
            if let Some((child, _)) = server.as_mut()
                && let Ok(Some(status)) = child.try_wait()
            {
                anyhow::bail!("the started planner-server ({endpoint}) exited: {status}");
            }
            let ready = open(&prefix, &endpoint).and_then(|mut c| c.check_planners().map(|()| c));
            match ready {
                Ok(client) => break client,
                Err(e) if began.elapsed() > Duration::from_secs(20) => {
                    if let Some((mut child, _)) = server.take() {
                        let _ = child.kill();
                        let _ = child.wait();
                    }
                    anyhow::bail!(
                        "started planner-server ({endpoint}, prefix {prefix}) but it does not answer: {e}"
                    );
                }
                Err(_) => std::thread::sleep(Duration::from_millis(20)),
            }
        };
        Ok(ZenohPlanner {
            client,
            server,
            endpoint,
            prefix,
            version: 0,
            timeout: Duration::from_secs(60),
        })
    }

    /// Whether this planner started the server it talks to.
    pub fn started_server(&self) -> bool {
        self.server.is_some()
    }

    /// Process id of the server this planner started.
    pub fn server_pid(&self) -> Option<u32> {
        self.server.as_ref().map(|(child, _)| child.id())
    }

    /// The endpoint of the planner.
    pub fn endpoint(&self) -> &str {
        &self.endpoint
    }

    /// The service prefix in use.
    pub fn prefix(&self) -> &str {
        &self.prefix
    }
}

impl Drop for ZenohPlanner {
    fn drop(&mut self) {
        if let Some((mut child, stdin)) = self.server.take() {
            // Closing the pipe asks the server to stop (SIGTERM on itself).
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

fn failure(e: ZenohError) -> PlanFailure {
    match e {
        ZenohError::Plan(p) => p.into(),
        e @ (ZenohError::MapTooLarge(_) | ZenohError::MapMessageTooLarge { .. }) => {
            PlanFailure::MapTooLarge(e.to_string())
        }
        other => PlanFailure::Transport(other.to_string()),
    }
}

impl GlobalPlanner for ZenohPlanner {
    fn name(&self) -> &'static str {
        "zenoh"
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
        let result = self
            .client
            .plan_retrying(&r, self.timeout)
            .map_err(failure)?;
        let ok = result.outcome.map_err(|f| failure(f.into()))?;
        Ok(planned(ok, t0.elapsed()))
    }
}

//! The global planner as the simulator sees it: a [`GlobalPlanner`] takes a map once and then
//! answers plan requests. [`InProcess`] runs `planner-core` in this process;
//! [`super::ipc::IpcPlanner`], a client of `planner-server` over iceoryx2, implements the
//! same trait (`--planner ipc`).

use planner_core::PlanError;
use planner_core::geometry::{Cell, Point};
use planner_core::grid::{GridBuf, GridRef};
use planner_core::path::{Path, PathView};
use planner_core::planner::aco::AcoParams;
use planner_core::planner::owned::{HostPlanner, PlanChoice};
use planner_core::planner::{PlanOptions, PlanParams, PlannerKind};
use std::time::{Duration, Instant};

/// One request to a [`GlobalPlanner`]. The planner service's request is another type,
/// `planner_ipc::wire::PlanRequest`, which [`super::ipc::IpcPlanner`] builds from this one.
#[derive(Clone, Copy, Debug)]
pub struct GlobalPlanRequest {
    /// Start cell.
    pub start: Cell,
    /// Goal cell.
    pub goal: Cell,
    /// The planner.
    pub algo: PlannerKind,
    /// Swarm parameters (their `seed` is replaced by `seed`).
    pub params: PlanParams,
    /// The seed of this request.
    pub seed: u64,
}

/// A planned path with the planner's figures.
#[derive(Clone, Debug, Default)]
pub struct PlannedPath {
    /// Waypoints, cell units.
    pub points: Vec<Point>,
    /// Length (cells).
    pub length: f32,
    /// Best cost per iteration (swarm planners and ACO; empty for A* and Theta*).
    pub history: Vec<f32>,
    /// Objective evaluations (swarm planners), or cells expanded (A*, Theta*).
    pub evaluations: u64,
    /// Wall-clock planning time.
    pub time: Duration,
}

/// Why no path came back.
#[derive(Clone, Debug, PartialEq)]
pub enum PlanFailure {
    /// Start and goal lie in different components: the goal is walled off.
    Unreachable,
    /// Any other planner error (an endpoint, budget, parameters, capacity).
    Planner(PlanError),
    /// The planner service does not take a map this large (the message names its limit).
    MapTooLarge(String),
    /// The transport to a planner service failed.
    Transport(String),
}

impl std::fmt::Display for PlanFailure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            PlanFailure::Unreachable => f.write_str("Unreachable"),
            PlanFailure::Planner(e) => write!(f, "{}: {e}", e.name()),
            PlanFailure::MapTooLarge(e) => write!(f, "MapTooLarge: {e}"),
            PlanFailure::Transport(e) => write!(f, "transport: {e}"),
        }
    }
}

impl std::error::Error for PlanFailure {}

impl From<PlanError> for PlanFailure {
    fn from(e: PlanError) -> Self {
        match e {
            PlanError::NoValidPath => PlanFailure::Unreachable,
            other => PlanFailure::Planner(other),
        }
    }
}

/// A global planner: the in-process one or a service client.
pub trait GlobalPlanner {
    /// Short name for reports (`inproc`, `ipc`).
    fn name(&self) -> &'static str;
    /// Replaces the map (the simulator calls it again with temporary obstacles to replan).
    fn set_map(&mut self, grid: GridRef<'_>) -> Result<(), PlanFailure>;
    /// Plans on the current map.
    fn plan(&mut self, request: &GlobalPlanRequest) -> Result<PlannedPath, PlanFailure>;
}

/// `planner-core` in this process.
pub struct InProcess {
    planner: HostPlanner,
    grid: Option<GridBuf>,
    out: Box<Path<{ 1 << 16 }>>,
    aco: AcoParams,
}

impl Default for InProcess {
    fn default() -> Self {
        Self::new()
    }
}

impl InProcess {
    /// A planner without a map.
    pub fn new() -> Self {
        InProcess {
            planner: HostPlanner::new(),
            grid: None,
            out: Box::new(Path::new()),
            aco: AcoParams::default(),
        }
    }
}

impl GlobalPlanner for InProcess {
    fn name(&self) -> &'static str {
        "inproc"
    }

    fn set_map(&mut self, grid: GridRef<'_>) -> Result<(), PlanFailure> {
        let own = GridBuf::from_view(grid);
        self.planner.prepare(own.view())?;
        self.grid = Some(own);
        Ok(())
    }

    fn plan(&mut self, request: &GlobalPlanRequest) -> Result<PlannedPath, PlanFailure> {
        let grid = self
            .grid
            .as_ref()
            .ok_or_else(|| PlanFailure::Transport("no map set".into()))?;
        let params = PlanParams {
            seed: request.seed,
            ..request.params
        };
        let aco = AcoParams {
            seed: request.seed,
            ..self.aco
        };
        let mut history = vec![f32::NAN; params.iterations.max(aco.iterations) as usize + 1];
        let out: &mut PathView = &mut *self.out;
        let t0 = Instant::now();
        let outcome = self.planner.plan(
            grid.view(),
            request.start,
            request.goal,
            &PlanChoice {
                kind: request.algo,
                params,
                aco,
            },
            out,
            PlanOptions {
                history: &mut history,
                interrupt: None,
            },
        )?;
        let time = t0.elapsed();
        let n = outcome.report.map_or(0, |r| r.history_len);
        history.truncate(n);
        Ok(PlannedPath {
            points: out.to_vec(),
            length: outcome.length,
            history,
            evaluations: outcome
                .report
                .map_or(outcome.expanded.unwrap_or(0) as u64, |r| r.evaluations),
            time,
        })
    }
}

/// Which planner to use (`--planner`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum PlannerChoice {
    /// `planner-core` in this process.
    Inproc,
    /// `planner-server` over iceoryx2: a server already serving the prefix `planner`, or
    /// one this process starts (under a private prefix; stopped when it ends).
    Ipc,
    /// `planner-server --transport zenoh`: a planner alive at tcp/127.0.0.1:7447 under the
    /// prefix `planner`, or one this process starts (free ports of 127.0.0.1, a private
    /// prefix; stopped when it ends). Feature `zenoh`.
    #[cfg(feature = "zenoh")]
    Zenoh,
}

impl PlannerChoice {
    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            PlannerChoice::Inproc => "inproc",
            PlannerChoice::Ipc => "ipc",
            #[cfg(feature = "zenoh")]
            PlannerChoice::Zenoh => "zenoh",
        }
    }

    /// The transport of a planner service, `None` in this process.
    pub fn transport(self) -> Option<&'static str> {
        match self {
            PlannerChoice::Inproc => None,
            PlannerChoice::Ipc => Some("iceoryx2"),
            #[cfg(feature = "zenoh")]
            PlannerChoice::Zenoh => Some("Zenoh"),
        }
    }

    /// The planner this choice names; a started server logs to `log`.
    pub fn build(self, log: Option<&std::path::Path>) -> anyhow::Result<Box<dyn GlobalPlanner>> {
        match self {
            PlannerChoice::Inproc => Ok(Box::new(InProcess::new())),
            PlannerChoice::Ipc => Ok(Box::new(super::ipc::IpcPlanner::connect_or_start(
                "planner",
                Duration::from_millis(300),
                log,
            )?)),
            #[cfg(feature = "zenoh")]
            PlannerChoice::Zenoh => Ok(Box::new(super::zenoh::ZenohPlanner::connect_or_start(
                super::zenoh::DEFAULT_ENDPOINT,
                "planner",
                Duration::from_millis(300),
                log,
            )?)),
        }
    }
}

//! Heap-allocated scratch for hosts (feature `alloc`): one [`HostPlanner`] serves every
//! planner of the crate on maps of any size, growing its buffers when a bigger map comes.
//!
//! Firmware uses [`plan`], [`aco::plan`] and the search
//! functions directly with static buffers; this is the convenience layer for the CLI and the
//! planner service.

extern crate alloc;

use alloc::boxed::Box;
use alloc::vec;
use alloc::vec::Vec;

use super::aco::{self, AcoParams, AcoWorkspace};
use super::{
    AnyAngleWorkspace, PlanOptions, PlanParams, PlanReport, PlanStorageMut, PlannerKind, plan,
};
use crate::encoding::corridor::Station;
use crate::error::PlanError;
use crate::geometry::Cell;
use crate::grid::GridRef;
use crate::optim::any::AnyOptimizer;
use crate::path::{self, Path, PathView};
use crate::search::anyangle::{self, MeshBuf, Node, Roots, Scratch};
use crate::search::astar::{AStarNode, OpenSlot, open_capacity};
use crate::search::{SearchNode, astar, connectivity, theta};

/// Population capacity of host plans.
pub const HOST_POPULATION: usize = 128;
/// Dimension capacity of host plans (column encoding: map width).
pub const HOST_DIMENSION: usize = 128;
/// Longest guide route, in waypoints.
pub const GUIDE_CAPACITY: usize = 1 << 16;

/// Which planner [`HostPlanner::plan`] runs, with its parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PlanChoice {
    /// The planner.
    pub kind: PlannerKind,
    /// Parameters of the swarm planners (the others ignore them).
    pub params: PlanParams,
    /// Parameters of the ant colony (the others ignore them).
    pub aco: AcoParams,
}

/// What any planner reports.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Outcome {
    /// Path length.
    pub length: f32,
    /// Direction changes.
    pub turns: usize,
    /// Cells expanded (A*, Theta*).
    pub expanded: Option<u32>,
    /// Optimizer figures (swarm planners and ACO).
    pub report: Option<PlanReport>,
}

/// Host scratch for every planner; call [`HostPlanner::prepare`] when the map changes.
pub struct HostPlanner {
    cells: usize,
    labels: Vec<u32>,
    nodes: Vec<AStarNode>,
    open: Vec<OpenSlot>,
    /// Theta* nodes (24 bytes a cell): made on first use.
    theta_nodes: Vec<SearchNode>,
    guide: Box<Path<GUIDE_CAPACITY>>,
    visited: Vec<u32>,
    tau: Vec<f32>,
    delta: Vec<f32>,
    tour: Vec<u32>,
    best: Vec<u32>,
    stations: Box<[Station; HOST_DIMENSION]>,
    optimizer: Box<AnyOptimizer<HOST_POPULATION, HOST_DIMENSION>>,
    /// The prepared map's mesh for the any-angle planner and guide (built by `prepare`).
    mesh: MeshBuf,
    /// Any-angle query scratch: one slot per rectangle, and the open list (grown when a
    /// search outgrows it).
    roots: Vec<Roots>,
    search_open: Vec<Node>,
}

/// Maps above this many cells plan blended without the Theta* guide candidate: its nodes
/// (24 bytes a cell, 96 MiB here) and its unbounded search would outgrow the plan itself.
pub const THETA_GUIDE_MAX_CELLS: usize = 1 << 22;

/// First size of the any-angle open list (2.1 MB); a search that outgrows it is run again
/// with twice the room, up to [`SEARCH_OPEN_MAX`].
const SEARCH_OPEN: usize = 1 << 16;
/// The largest any-angle open list a host grows (134 MB).
const SEARCH_OPEN_MAX: usize = 1 << 22;

impl Default for HostPlanner {
    fn default() -> Self {
        Self::new()
    }
}

impl HostPlanner {
    /// Empty scratch; buffers grow on [`prepare`](Self::prepare).
    pub fn new() -> Self {
        HostPlanner {
            cells: 0,
            labels: Vec::new(),
            nodes: Vec::new(),
            open: Vec::new(),
            theta_nodes: Vec::new(),
            guide: Box::new(Path::new()),
            visited: Vec::new(),
            tau: Vec::new(),
            delta: Vec::new(),
            tour: Vec::new(),
            best: Vec::new(),
            stations: Box::new([Station::EMPTY; HOST_DIMENSION]),
            optimizer: Box::new(AnyOptimizer::unconfigured()),
            mesh: MeshBuf::default(),
            roots: Vec::new(),
            search_open: vec![Node::EMPTY; SEARCH_OPEN],
        }
    }

    /// Sizes the buffers for `grid`, labels its components and builds its any-angle mesh
    /// (O(cells), the one-time cost of a map).
    pub fn prepare(&mut self, grid: GridRef<'_>) -> Result<(), PlanError> {
        let cells = grid.cells();
        if self.nodes.len() < cells {
            self.nodes = vec![AStarNode::EMPTY; cells];
            self.open = vec![OpenSlot::EMPTY; open_capacity(cells)];
            self.theta_nodes.clear();
            self.labels = vec![0; cells];
            self.visited = vec![0; cells / 32 + 1];
            self.tour = vec![0; cells];
            self.best = vec![0; cells];
            // The ACO buffers are the largest (8 floats a cell twice): made on first use.
            self.tau.clear();
            self.delta.clear();
        }
        self.cells = cells;
        connectivity::label(grid, &mut self.labels)?;
        self.mesh = MeshBuf::build(grid)?;
        self.roots = vec![Roots::EMPTY; self.mesh.mesh().rects()];
        Ok(())
    }

    /// Heap bytes of the prepared map's any-angle mesh.
    pub fn mesh_bytes(&self) -> usize {
        self.mesh.heap_bytes()
    }

    /// The exact any-angle path on the prepared map into `out`, with an open list grown
    /// until the search fits without dropping a node that could matter.
    fn anyangle(
        &mut self,
        grid: GridRef<'_>,
        start: Cell,
        goal: Cell,
        out: &mut PathView,
    ) -> Result<anyangle::AnyAngleStats, PlanError> {
        loop {
            let scratch = Scratch {
                roots: &mut self.roots,
                open: &mut self.search_open,
            };
            let result = anyangle::plan(grid, &self.mesh.mesh(), start, goal, scratch, out);
            let short = match &result {
                Ok(stats) => !stats.exact,
                Err(e) => *e == PlanError::CapacityExceeded,
            };
            if !short || self.search_open.len() >= SEARCH_OPEN_MAX {
                return result;
            }
            let more = self.search_open.len() * 2;
            self.search_open = vec![Node::EMPTY; more];
        }
    }

    /// The component labels of the prepared map.
    pub fn labels(&self) -> &[u32] {
        &self.labels[..self.cells]
    }

    /// One swarm plan with the host's workspace.
    fn swarm(
        &mut self,
        grid: GridRef<'_>,
        start: Cell,
        goal: Cell,
        params: &PlanParams,
        out: &mut PathView,
        options: PlanOptions<'_>,
    ) -> Result<PlanReport, PlanError> {
        // A blended plan may prefer the Theta* route as its guide.
        let theta: &mut [SearchNode] =
            if params.blend.is_length() || self.cells > THETA_GUIDE_MAX_CELLS {
                &mut []
            } else {
                if self.theta_nodes.len() < self.cells {
                    self.theta_nodes = vec![SearchNode::EMPTY; self.cells];
                }
                &mut self.theta_nodes
            };
        let mut storage = PlanStorageMut {
            anyangle: Some(AnyAngleWorkspace {
                mesh: self.mesh.mesh(),
                scratch: Scratch {
                    roots: &mut self.roots,
                    open: &mut self.search_open,
                },
            }),
            nodes: &mut self.nodes,
            open: &mut self.open,
            theta,
            guide: &mut *self.guide,
            visited: &mut self.visited,
            stations: &mut self.stations[..],
            optimizer: &mut *self.optimizer,
            out,
        };
        plan(grid, start, goal, params, &mut storage, options)
    }

    /// Plans with any planner on the prepared map (`grid` must be the one passed to
    /// [`prepare`](Self::prepare)): `choice` names the planner and its parameters.
    pub fn plan(
        &mut self,
        grid: GridRef<'_>,
        start: Cell,
        goal: Cell,
        choice: &PlanChoice,
        out: &mut PathView,
        options: PlanOptions<'_>,
    ) -> Result<Outcome, PlanError> {
        let PlanOptions {
            history,
            mut interrupt,
        } = options;
        let (kind, params, aco_params) = (choice.kind, &choice.params, &choice.aco);
        if grid.cells() != self.cells {
            return Err(PlanError::InvalidParameters);
        }
        let labels = &self.labels[..self.cells];
        match kind {
            PlannerKind::AStar | PlannerKind::Theta => {
                let labels = Some(labels);
                let stats = if kind == PlannerKind::AStar {
                    let (nodes, open) = (&mut self.nodes, &mut self.open);
                    astar::plan_with_labels(grid, start, goal, labels, nodes, open, out)?
                } else {
                    if self.theta_nodes.len() < self.cells {
                        self.theta_nodes = vec![SearchNode::EMPTY; self.cells];
                    }
                    let nodes = &mut self.theta_nodes;
                    theta::plan_with_labels(grid, start, goal, labels, nodes, out)?
                };
                Ok(Outcome {
                    length: stats.length,
                    turns: path::turns(out),
                    expanded: Some(stats.expanded),
                    report: None,
                })
            }
            PlannerKind::AnyAngle => {
                let stats = self.anyangle(grid, start, goal, out)?;
                Ok(Outcome {
                    length: stats.length,
                    turns: path::turns(out),
                    expanded: Some(stats.expanded),
                    report: None,
                })
            }
            PlannerKind::Aco => {
                if self.tau.len() < 8 * self.cells {
                    self.tau = vec![0.0; 8 * self.cells];
                    self.delta = vec![0.0; 8 * self.cells];
                }
                let mut ws = AcoWorkspace {
                    tau: &mut self.tau,
                    delta: &mut self.delta,
                    visited: &mut self.visited,
                    tour: &mut self.tour,
                    best: &mut self.best,
                    labels,
                };
                let report = aco::plan(grid, start, goal, aco_params, &mut ws, out, history)?;
                Ok(Outcome {
                    length: report.length,
                    turns: report.turns,
                    expanded: None,
                    report: Some(report),
                })
            }
            PlannerKind::Swarm(algorithm) => {
                if !connectivity::connected(grid, labels, start, goal)? {
                    return Err(PlanError::NoValidPath);
                }
                let params = PlanParams {
                    algorithm,
                    ..*params
                };
                let options = PlanOptions {
                    history: &mut *history,
                    // Shortens the closure's lifetime bound, which `Option` does not coerce.
                    interrupt: match interrupt.as_mut() {
                        Some(f) => Some(&mut **f),
                        None => None,
                    },
                };
                let report = match self.swarm(grid, start, goal, &params, out, options) {
                    // The guide's open list may have been short: grow it by a search of its
                    // own, then plan once more.
                    Err(PlanError::CapacityExceeded)
                        if params.guide == super::GuideKind::AnyAngle
                            && self.search_open.len() < SEARCH_OPEN_MAX =>
                    {
                        let had = self.search_open.len();
                        self.anyangle(grid, start, goal, out)?;
                        if self.search_open.len() == had {
                            return Err(PlanError::CapacityExceeded);
                        }
                        let options = PlanOptions { history, interrupt };
                        self.swarm(grid, start, goal, &params, out, options)?
                    }
                    other => other?,
                };
                Ok(Outcome {
                    length: report.length,
                    turns: report.turns,
                    expanded: None,
                    report: Some(report),
                })
            }
        }
    }
}

//! `host-sim plan`: the contract every planner plugs into.
//!
//! ```text
//! host-sim plan --map FILE.map --queries Q.txt --algo NAME [--seed N] [planner options] [--out RESULTS.jsonl]
//! host-sim plan --map FILE.map --start X,Y --goal X,Y --algo astar
//! ```
//! `NAME` is any planner of `planner-core`: `astar`, `theta`, `aco`, `tclhho`, `igwo`, `hho`,
//! `gwo`, `tgwo`, `pso`, `ga`, `ssa`, `ssagwo`.
//! `Q.txt` holds one query a line, `sx sy gx gy` in cell coordinates (blank lines and lines
//! starting with `#` are skipped). Output: one JSON object a line, in query order:
//! `{"start":[sx,sy],"goal":[gx,gy],"path":[[x,y],...],"length":L,"time_us":T,...}` or
//! `{"start":[..],"goal":[..],"error":"NoValidPath"}`. A line that is not a query yields
//! `{"line":N,"error":"MalformedQuery","detail":"..."}` and planning goes on.

use crate::maps::{HostGrid, load_movingai};
use anyhow::Context;
use clap::ValueEnum;
use planner_core::PlanError;
use planner_core::encoding::walk::CornerRule;
use planner_core::geometry::Cell;
use planner_core::optim::any::AlgorithmKind;
use planner_core::path::{Path, PathView};
use planner_core::planner::aco::AcoParams;
use planner_core::planner::owned::HostPlanner;
use planner_core::planner::{EncodingKind, GuideKind, InitKind, PlanParams, PlannerKind};
use planner_ipc::jsonl::{self, QueryLine};
use serde_json::{Value, json};
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::Instant;

/// Longest path (in waypoints) the host accepts.
const PATH_CAPACITY: usize = 1 << 16;

/// Arguments of `host-sim plan`.
#[derive(clap::Args, Debug)]
pub struct PlanArgs {
    /// Moving AI `.map` file.
    #[arg(long)]
    pub map: PathBuf,
    /// File of queries, one `sx sy gx gy` a line.
    #[arg(long, required_unless_present = "start", conflicts_with_all = ["start", "goal"])]
    pub queries: Option<PathBuf>,
    /// Start cell `X,Y` (single query).
    #[arg(long, value_parser = parse_xy, requires = "goal")]
    pub start: Option<(i64, i64)>,
    /// Goal cell `X,Y` (single query).
    #[arg(long, value_parser = parse_xy, requires = "start")]
    pub goal: Option<(i64, i64)>,
    /// Planner: astar, theta, aco, tclhho, igwo, hho, gwo, tgwo, pso, ga, ssa, ssagwo.
    #[arg(long, value_parser = parse_planner, default_value = "astar")]
    pub algo: PlannerKind,
    /// Seed of the random number generator (stochastic planners; recorded in the output).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Robot radius in cells: the map is inflated so that paths keep this clearance.
    #[arg(long, default_value_t = 0.0)]
    pub radius: f32,
    /// Write results here instead of standard output.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Options of the swarm planners and ACO.
    #[command(flatten)]
    pub swarm: SwarmArgs,
}

/// Options shared by every command that runs swarm planners.
#[derive(clap::Args, Debug, Clone)]
pub struct SwarmArgs {
    /// Population size (swarm planners) or ants (ACO).
    #[arg(long)]
    pub pop: Option<usize>,
    /// Iterations.
    #[arg(long)]
    pub iters: Option<u32>,
    /// Stop after this many iterations without improvement.
    #[arg(long)]
    pub stagnation: Option<u32>,
    /// Path encoding: corridor (any map), column (seed 000), walk (seed 003).
    #[arg(long, value_enum, default_value_t = EncodingArg::Corridor)]
    pub encoding: EncodingArg,
    /// Initial population: the optimizer's own, or the patent's diffusion (column encoding).
    #[arg(long, value_enum, default_value_t = InitArg::Optimizer)]
    pub init: InitArg,
    /// Corner rule of the walk encoding (loose = seed 003's literal rule).
    #[arg(long, value_enum, default_value_t = CornerArg::Strict)]
    pub corner_rule: CornerArg,
    /// Skip the patent's node pruning.
    #[arg(long)]
    pub no_prune: bool,
    /// Corridor encoding: guide length between stations.
    #[arg(long)]
    pub corridor_spacing: Option<f32>,
    /// Corridor encoding: lateral reach of a waypoint.
    #[arg(long)]
    pub corridor_radius: Option<f32>,
    /// Corridor encoding: the route the stations sit on.
    #[arg(long, value_enum, default_value_t = GuideArg::Visibility)]
    pub guide: GuideArg,
    /// Walk encoding: maximum steps.
    #[arg(long)]
    pub walk_steps: Option<usize>,
}

/// `--guide` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum GuideArg {
    /// The octile A* route.
    Astar,
    /// The shortest any-angle route of the map's visibility graph (built once per map).
    Visibility,
}

impl GuideArg {
    /// The planner-core value.
    pub fn kind(self) -> GuideKind {
        match self {
            GuideArg::Astar => GuideKind::AStar,
            GuideArg::Visibility => GuideKind::Visibility,
        }
    }
}

/// `--encoding` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EncodingArg {
    /// Waypoints across an exact guide route (any map).
    Corridor,
    /// Seed 000's column encoding.
    Column,
    /// Seed 003's 8-connected walk.
    Walk,
}

/// `--init` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum InitArg {
    /// The optimizer's own initialisation.
    Optimizer,
    /// The patent's square-neighbourhood diffusion.
    Diffusion,
}

/// `--corner-rule` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum CornerArg {
    /// No corner cutting (SPEC).
    Strict,
    /// Seed 003's rule.
    Loose,
}

impl SwarmArgs {
    /// The planner-core parameters these options describe, for `seed`.
    pub fn params(&self, seed: u64) -> (PlanParams, AcoParams) {
        let base = PlanParams::new(AlgorithmKind::Tclhho);
        let params = PlanParams {
            population: self.pop.unwrap_or(base.population),
            iterations: self.iters.unwrap_or(base.iterations),
            stagnation: self.stagnation,
            seed,
            encoding: match self.encoding {
                EncodingArg::Corridor => EncodingKind::Corridor,
                EncodingArg::Column => EncodingKind::Column,
                EncodingArg::Walk => EncodingKind::Walk,
            },
            init: match self.init {
                InitArg::Optimizer => InitKind::Optimizer,
                InitArg::Diffusion => InitKind::Diffusion,
            },
            corner_rule: match self.corner_rule {
                CornerArg::Strict => CornerRule::Strict,
                CornerArg::Loose => CornerRule::Loose,
            },
            prune: !self.no_prune,
            corridor_spacing: self.corridor_spacing.unwrap_or(base.corridor_spacing),
            corridor_radius: self.corridor_radius.unwrap_or(base.corridor_radius),
            guide: self.guide.kind(),
            walk_steps: self.walk_steps.unwrap_or(base.walk_steps),
            ..base
        };
        let aco_base = AcoParams::default();
        let aco = AcoParams {
            ants: self.pop.unwrap_or(aco_base.ants),
            iterations: self.iters.unwrap_or(aco_base.iterations),
            stagnation: self.stagnation,
            seed,
            prune: !self.no_prune,
            ..aco_base
        };
        (params, aco)
    }
}

fn parse_planner(text: &str) -> Result<PlannerKind, String> {
    text.parse().map_err(|_| {
        let names: Vec<&str> = PlannerKind::ALL.iter().map(|k| k.name()).collect();
        format!(
            "unknown planner {text:?}; expected one of {}",
            names.join(", ")
        )
    })
}

fn parse_xy(text: &str) -> Result<(i64, i64), String> {
    let (x, y) = text.split_once(',').ok_or("expected X,Y")?;
    let num = |s: &str| s.trim().parse::<i64>().map_err(|e| format!("{s:?}: {e}"));
    Ok((num(x)?, num(y)?))
}

/// A query as read: coordinates may be anything an `i64` holds; range is the planner's job.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Query {
    /// Start `(x, y)`.
    pub start: (i64, i64),
    /// Goal `(x, y)`.
    pub goal: (i64, i64),
}

/// A map prepared for repeated queries: the inflated grid and the planners' scratch.
pub struct PreparedMap {
    grid: Box<HostGrid>,
    planner: HostPlanner,
    path: Box<Path<PATH_CAPACITY>>,
}

/// The outcome of one query.
pub struct Outcome {
    /// The path, or why there is none.
    pub result: Result<PlanSummary, PlanError>,
    /// Planning time in microseconds.
    pub time_us: f64,
}

/// A found path and its metrics.
pub struct PlanSummary {
    /// Waypoints (cell units).
    pub path: Vec<[f32; 2]>,
    /// The planner's figures.
    pub outcome: planner_core::planner::owned::Outcome,
}

impl PreparedMap {
    /// Inflates `grid` by `radius` and labels its components.
    pub fn new(grid: &HostGrid, radius: f32) -> anyhow::Result<Self> {
        let mut inflated = Box::new(HostGrid::new(1, 1).map_err(anyhow::Error::msg)?);
        grid.inflate_into(radius, &mut inflated)
            .map_err(anyhow::Error::msg)?;
        let mut planner = HostPlanner::new();
        planner
            .prepare(inflated.view())
            .map_err(anyhow::Error::msg)?;
        Ok(PreparedMap {
            grid: inflated,
            planner,
            path: Box::new(Path::new()),
        })
    }

    /// Plans one query; `history` receives the best cost per iteration (swarm planners).
    pub fn plan(
        &mut self,
        kind: PlannerKind,
        params: &PlanParams,
        aco: &AcoParams,
        query: Query,
        history: &mut [f32],
    ) -> Outcome {
        let began = Instant::now();
        let result = self.plan_inner(kind, params, aco, query, history);
        Outcome {
            result,
            time_us: began.elapsed().as_secs_f64() * 1e6,
        }
    }

    fn plan_inner(
        &mut self,
        kind: PlannerKind,
        params: &PlanParams,
        aco: &AcoParams,
        query: Query,
        history: &mut [f32],
    ) -> Result<PlanSummary, PlanError> {
        let start = to_cell(query.start).ok_or(PlanError::StartOutsideMap)?;
        let goal = to_cell(query.goal).ok_or(PlanError::GoalOutsideMap)?;
        let out: &mut PathView = &mut *self.path;
        let outcome = self.planner.plan(
            self.grid.view(),
            kind,
            start,
            goal,
            params,
            aco,
            out,
            history,
            &mut || false,
        )?;
        Ok(PlanSummary {
            path: out.iter().map(|p| [p.x, p.y]).collect(),
            outcome,
        })
    }
}

fn to_cell((x, y): (i64, i64)) -> Option<Cell> {
    Some(Cell::new(u16::try_from(x).ok()?, u16::try_from(y).ok()?))
}

/// The JSON line of one query (the format lives in `planner_ipc::jsonl`, shared with
/// `planner-client`).
pub fn outcome_json(kind: PlannerKind, seed: u64, query: Query, outcome: &Outcome) -> Value {
    let result = match &outcome.result {
        Ok(s) => Ok(jsonl::PathLine {
            path: &s.path,
            length: s.outcome.length,
            turns: s.outcome.turns,
            expanded: s.outcome.expanded,
            report: s.outcome.report.as_ref(),
        }),
        Err(e) => Err(e.name()),
    };
    jsonl::plan_line(
        query.start,
        query.goal,
        result,
        outcome.time_us,
        kind.name(),
        seed,
    )
}

/// Runs `host-sim plan`.
pub fn run(args: &PlanArgs) -> anyhow::Result<()> {
    let grid = load_movingai(&args.map)?;
    let mut prepared = PreparedMap::new(&grid, args.radius).context("invalid --radius")?;
    let (params, aco) = args.swarm.params(args.seed);
    let lines = match (&args.queries, args.start, args.goal) {
        (Some(file), _, _) => {
            let text = std::fs::read_to_string(file)
                .with_context(|| format!("cannot read queries {}", file.display()))?;
            jsonl::parse_queries(&text)
        }
        (None, Some(start), Some(goal)) => vec![QueryLine::Query { start, goal }],
        _ => anyhow::bail!("give --queries FILE or both --start and --goal"),
    };
    let sink: Box<dyn Write> = match &args.out {
        Some(path) => Box::new(
            std::fs::File::create(path)
                .with_context(|| format!("cannot create {}", path.display()))?,
        ),
        None => Box::new(std::io::stdout().lock()),
    };
    let mut out = BufWriter::new(sink);
    for line in lines {
        let value = match line {
            QueryLine::Query { start, goal } => {
                let q = Query { start, goal };
                let outcome = prepared.plan(args.algo, &params, &aco, q, &mut []);
                outcome_json(args.algo, args.seed, q, &outcome)
            }
            QueryLine::Malformed { line, detail } => {
                json!({"line": line, "error": "MalformedQuery", "detail": detail})
            }
        };
        serde_json::to_writer(&mut out, &value)?;
        out.write_all(b"\n")?;
    }
    out.flush()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn out_of_range_coordinates_are_outside_the_map() {
        let grid = HostGrid::parse_rows(b"...\n...\n").unwrap();
        let mut map = PreparedMap::new(&grid, 0.0).unwrap();
        let q = |s, g| Query { start: s, goal: g };
        let (p, a) = (PlanParams::new(AlgorithmKind::Tclhho), AcoParams::default());
        for kind in PlannerKind::ALL {
            let r = map.plan(kind, &p, &a, q((-1, 0), (0, 0)), &mut []).result;
            assert!(matches!(r, Err(PlanError::StartOutsideMap)), "{kind:?}");
            let r = map
                .plan(kind, &p, &a, q((0, 0), (0, 70000)), &mut [])
                .result;
            assert!(matches!(r, Err(PlanError::GoalOutsideMap)), "{kind:?}");
            assert!(
                map.plan(kind, &p, &a, q((0, 0), (2, 1)), &mut [])
                    .result
                    .is_ok(),
                "{kind:?}"
            );
        }
    }
}

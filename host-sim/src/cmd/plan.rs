//! `host-sim plan`: the contract every planner plugs into.
//!
//! ```text
//! host-sim plan --map FILE.map|FILE.yaml --queries Q.txt --algo NAME [--frame cells|world] [--seed N]
//!               [--radius R | --robot-radius M] [--unknown blocked|free] [--max-cells N|WxH]
//!               [planner options] [--out RESULTS.jsonl]
//! host-sim plan --map FILE.map --start X,Y --goal X,Y --algo astar
//! ```
//! `NAME` is any planner of `planner-core`: `astar`, `theta`, `anyangle`, `aco`, `tclhho`,
//! `igwo`, `hho`, `gwo`, `tgwo`, `pso`, `ga`, `ssa`, `ssagwo`.
//! `Q.txt` holds one query a line, `sx sy gx gy`: cells, or with `--frame world` metres in
//! the map frame of a ROS map (blank lines and lines starting with `#` are skipped).
//! Output: one JSON object a line, in query order (the format of `planner_ipc::jsonl`):
//! `{"start":[sx,sy],"goal":[gx,gy],"path":[[x,y],...],"length":L,"time_us":T,...}` (plus
//! `path_m` and `length_m` in metres on a ROS map, `start_m` and `goal_m` for queries in
//! metres) or `{"start":[..],"goal":[..],"error":"NoValidPath"}` (with a `detail` when there
//! is more to say: a point off the map, unknown space, `StartInflated` for a start that only
//! the inflation by the robot radius blocks). A line that is not a query yields
//! `{"line":N,"error":"MalformedQuery","detail":"..."}` and planning goes on.
//!
//! Every path is printed exactly and checked as printed: the line is read back as text (the
//! numbers as `f64`) and validated independently ([`crate::printed`]) on the map it was
//! planned on, in cells and in metres; a path that would fail is printed as the error
//! `InvalidPath` with its reason, never as a path.
//!
//! What a map costs once is not in any query's `time_us`: standard error gets one JSON
//! object first, `{"map":..,"width":..,"height":..,"load_ms":..,"inflate_ms":..,
//! "prepare_ms":..,"warmup_ms":..}` (reading and parsing the file; inflating by the radius;
//! `HostPlanner::prepare`: scratch, component labels, the any-angle mesh; a query from a
//! free cell to itself, which builds whatever the planner makes on first use: Theta* nodes,
//! ACO pheromones).
//!
//! Exit status ([`crate::exit`]): 0 when every query was answered (a query's failure is a
//! line), 2 for bad input (map, query file, options).

use crate::exit::bad;
use anyhow::Context;
use clap::ValueEnum;
use planner_core::PlanError;
use planner_core::encoding::walk::CornerRule;
use planner_core::geometry::Cell;
use planner_core::grid::GridBuf;
use planner_core::optim::any::AlgorithmKind;
use planner_core::path::{Path, PathView};
use planner_core::planner::aco::AcoParams;
use planner_core::planner::owned::{HostPlanner, PlanChoice};
use planner_core::planner::{
    Blend, EncodingKind, GuideKind, InitKind, PlanOptions, PlanParams, PlannerKind,
};
use planner_ipc::jsonl::{self, Endpoint, ErrorLine, LineContext, QueryLine};
use planner_mapfile::{Frame, MapOptions, load_map};
use serde_json::{Value, json};
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::Instant;

/// Longest path (in waypoints) the host accepts.
const PATH_CAPACITY: usize = 1 << 16;

/// Arguments of `host-sim plan`.
#[derive(clap::Args, Debug)]
pub struct PlanArgs {
    /// Moving AI `.map` or ROS map_server `.yaml` (PGM/PNG image) file.
    #[arg(long)]
    pub map: PathBuf,
    /// File of queries, one `sx sy gx gy` a line (cells, or metres with `--frame world`).
    #[arg(long, required_unless_present = "start", conflicts_with_all = ["start", "goal"])]
    pub queries: Option<PathBuf>,
    /// Start `X,Y` (single query): a cell, or metres with `--frame world`.
    #[arg(long, requires = "goal", allow_hyphen_values = true)]
    pub start: Option<String>,
    /// Goal `X,Y` (single query): a cell, or metres with `--frame world`.
    #[arg(long, requires = "start", allow_hyphen_values = true)]
    pub goal: Option<String>,
    /// What starts, goals and queries are in: cells, or metres in the map frame of a ROS
    /// map (its YAML's origin and resolution, y up).
    #[arg(long, value_enum, default_value_t = Frame::Cells)]
    pub frame: Frame,
    /// Planner: astar, theta, anyangle, aco, tclhho, igwo, hho, gwo, tgwo, pso, ga, ssa, ssagwo.
    #[arg(long, value_parser = parse_planner, default_value = "astar")]
    pub algo: PlannerKind,
    /// Seed of the random number generator (stochastic planners; recorded in the output).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Robot radius in cells: the map is inflated so that paths keep this clearance.
    #[arg(long, conflicts_with = "robot_radius")]
    pub radius: Option<f32>,
    /// Robot radius in metres (a ROS map; default 0.25 there, 0 plans for a point): every
    /// cell whose centre lies within it of an obstacle is blocked for planning.
    #[arg(long)]
    pub robot_radius: Option<f64>,
    /// Write results here instead of standard output.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Size limit and unknown space of the map.
    #[command(flatten)]
    pub limits: MapOptions,
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
    /// Stop after this many iterations without a 1e-4 relative improvement (0: run every
    /// iteration, as the papers do).
    #[arg(long, default_value_t = planner_core::planner::HOST_STAGNATION)]
    pub stagnation: u32,
    /// Path encoding: corridor (any map), column (Lei2024Warehouse), walk (Liu2020Igwo).
    #[arg(long, value_enum, default_value_t = EncodingArg::Corridor)]
    pub encoding: EncodingArg,
    /// Initial population: the optimizer's own, or the patent's diffusion (column encoding).
    #[arg(long, value_enum, default_value_t = InitArg::Optimizer)]
    pub init: InitArg,
    /// Corner rule of the walk encoding (loose = Liu2020Igwo's literal rule).
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
    #[arg(long, value_enum, default_value_t = GuideArg::Anyangle)]
    pub guide: GuideArg,
    /// Walk encoding: maximum steps.
    #[arg(long)]
    pub walk_steps: Option<usize>,
    /// Blended objective (corridor encoding): desired clearance from obstacles, in cells of
    /// the grid planned on (on an inflated map, the margin beyond the robot); 0: none.
    #[arg(long, default_value_t = 0.0, value_parser = non_negative)]
    pub clearance: f32,
    /// Blended objective: cost (cells) per cell of path per cell of missing clearance.
    #[arg(long, default_value_t = 16.0, value_parser = non_negative)]
    pub clearance_weight: f32,
    /// Blended objective: cost (cells) per radian of turning, plus a quarter radian per turn;
    /// 0: none.
    #[arg(long, default_value_t = 0.0, value_parser = non_negative)]
    pub turn_weight: f32,
}

/// A finite number at or above 0 (the blended objective's options).
fn non_negative(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(v) if v.is_finite() && v >= 0.0 => Ok(v),
        _ => Err(format!("{text:?}: must be a finite number at or above 0")),
    }
}

/// `--guide` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum GuideArg {
    /// The octile A* route.
    Astar,
    /// The exact shortest any-angle route (`anyangle`; its mesh is built once per map).
    Anyangle,
}

impl GuideArg {
    /// The planner-core value.
    pub fn kind(self) -> GuideKind {
        match self {
            GuideArg::Astar => GuideKind::AStar,
            GuideArg::Anyangle => GuideKind::AnyAngle,
        }
    }
}

/// `--encoding` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum EncodingArg {
    /// Waypoints across an exact guide route (any map).
    Corridor,
    /// Lei2024Warehouse's column encoding.
    Column,
    /// Liu2020Igwo's 8-connected walk.
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
    /// Liu2020Igwo's rule.
    Loose,
}

impl SwarmArgs {
    /// The planner-core parameters these options describe, for `seed`.
    pub fn params(&self, seed: u64) -> (PlanParams, AcoParams) {
        let base = PlanParams::new(AlgorithmKind::Tclhho);
        let params = PlanParams {
            population: self.pop.unwrap_or(base.population),
            iterations: self.iters.unwrap_or(base.iterations),
            stagnation: (self.stagnation > 0).then_some(self.stagnation),
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
            blend: Blend {
                clearance: self.clearance,
                clearance_weight: self.clearance_weight,
                turn_weight: self.turn_weight,
            },
            ..base
        };
        let aco_base = AcoParams::default();
        let aco = AcoParams {
            ants: self.pop.unwrap_or(aco_base.ants),
            iterations: self.iters.unwrap_or(aco_base.iterations),
            stagnation: (self.stagnation > 0).then_some(self.stagnation),
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

/// `X,Y` in the frame asked for: integers for cells, numbers for metres.
pub fn endpoint(text: &str, frame: Frame, what: &str) -> anyhow::Result<Endpoint> {
    let [x, y] = planner_mapfile::frame::parse_point(text)
        .map_err(|e| bad(format!("--{what} {text}: {e}")))?;
    match frame {
        Frame::World => Ok(Endpoint::World([x, y])),
        Frame::Cells if x.fract() == 0.0 && y.fract() == 0.0 && x.abs() < 1e15 => {
            Ok(Endpoint::Cell(x as i64, y as i64))
        }
        Frame::Cells => Err(bad(format!(
            "--{what} {text}: cells are integers (--frame world takes metres)"
        ))),
    }
}

/// The error of an option that needs metres on a map without a world frame.
pub fn no_frame(map: &std::path::Path, option: &str) -> anyhow::Error {
    bad(format!(
        "{}: a Moving AI map has no world frame (it is in cells); {option} needs a ROS map \
         YAML with a resolution and an origin",
        map.display()
    ))
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
    grid: GridBuf,
    planner: HostPlanner,
    path: Box<Path<PATH_CAPACITY>>,
    costs: MapCosts,
}

/// What preparing a map cost once, in milliseconds (never part of a query's time).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MapCosts {
    /// Inflating the grid by the robot radius.
    pub inflate_ms: f64,
    /// `HostPlanner::prepare`: sizing the planners' scratch, labelling components, building
    /// the any-angle mesh.
    pub prepare_ms: f64,
    /// The first-use structures of a planner ([`PreparedMap::warm_up`]).
    pub warmup_ms: f64,
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
    /// Inflates `grid` by `radius` (a radius of 0 keeps it as it is) and labels its
    /// components.
    pub fn new(grid: GridBuf, radius: f32) -> anyhow::Result<Self> {
        let began = Instant::now();
        let grid = if radius == 0.0 {
            grid
        } else {
            grid.inflated(radius).map_err(anyhow::Error::msg)?
        };
        let inflate_ms = ms(began);
        let began = Instant::now();
        let mut planner = HostPlanner::new();
        planner.prepare(grid.view()).map_err(anyhow::Error::msg)?;
        Ok(PreparedMap {
            grid,
            planner,
            path: Box::new(Path::new()),
            costs: MapCosts {
                inflate_ms,
                prepare_ms: ms(began),
                warmup_ms: 0.0,
            },
        })
    }

    /// Plans once from the first free cell to itself, so that whatever `kind` builds on first
    /// use (Theta* nodes, ACO pheromones, anything a planner keeps per map) is
    /// built now and counted in [`MapCosts::warmup_ms`], not in the first query's time.
    pub fn warm_up(&mut self, kind: PlannerKind, params: &PlanParams, aco: &AcoParams) {
        let g = self.grid.view();
        let Some(free) = (0..g.cells()).map(|i| g.cell(i)).find(|&c| g.is_free(c)) else {
            return;
        };
        let at = (free.x as i64, free.y as i64);
        let query = Query {
            start: at,
            goal: at,
        };
        let began = Instant::now();
        // The outcome does not matter: only what the planner keeps for the next queries.
        let _ = self.plan_inner(kind, params, aco, query, &mut []);
        self.costs.warmup_ms = ms(began);
    }

    /// What preparing this map cost.
    pub fn costs(&self) -> MapCosts {
        self.costs
    }

    /// The grid queries are planned on (inflated by the radius).
    pub fn grid(&self) -> &GridBuf {
        &self.grid
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
            start,
            goal,
            &PlanChoice {
                kind,
                params: *params,
                aco: *aco,
            },
            out,
            PlanOptions {
                history,
                interrupt: None,
            },
        )?;
        Ok(PlanSummary {
            path: out.iter().map(|p| [p.x, p.y]).collect(),
            outcome,
        })
    }
}

/// Milliseconds since `began`.
fn ms(began: Instant) -> f64 {
    began.elapsed().as_secs_f64() * 1e3
}

/// Rounds milliseconds to microseconds for JSON.
fn ms_json(value: f64) -> Value {
    json!((value * 1e3).round() / 1e3)
}

/// The standard-error line of a map's one-time costs (see the module documentation).
pub fn costs_json(map: &std::path::Path, grid: &GridBuf, load_ms: f64, costs: MapCosts) -> Value {
    json!({
        "map": map.display().to_string(),
        "width": grid.width(),
        "height": grid.height(),
        "load_ms": ms_json(load_ms),
        "inflate_ms": ms_json(costs.inflate_ms),
        "prepare_ms": ms_json(costs.prepare_ms),
        "warmup_ms": ms_json(costs.warmup_ms),
    })
}

fn to_cell((x, y): (i64, i64)) -> Option<Cell> {
    Some(Cell::new(u16::try_from(x).ok()?, u16::try_from(y).ok()?))
}

/// The JSON line of one query (the format lives in `planner_ipc::jsonl`, shared with
/// `planner-client`).
pub fn outcome_json(
    query: &jsonl::Query,
    cells: jsonl::CellPair,
    outcome: &Outcome,
    error: impl FnOnce(PlanError) -> ErrorLine,
    ctx: &LineContext<'_>,
) -> Value {
    let result = match &outcome.result {
        Ok(s) => Ok(jsonl::PathLine {
            path: &s.path,
            length: s.outcome.length,
            turns: s.outcome.turns,
            expanded: s.outcome.expanded,
            report: s.outcome.report.as_ref(),
        }),
        Err(e) => Err(error(*e)),
    };
    jsonl::plan_line(query, Some(cells), result, outcome.time_us, ctx)
}

/// Runs `host-sim plan`.
pub fn run(args: &PlanArgs) -> anyhow::Result<()> {
    let began = Instant::now();
    let loaded = load_map(&args.map, &args.limits)?;
    let load_ms = ms(began);
    let frame = loaded.frame;
    if args.frame == Frame::World && !frame.declared {
        return Err(no_frame(&args.map, "--frame world"));
    }
    let inflation = jsonl::inflation(args.radius, args.robot_radius, &frame)
        .map_err(|e| bad(format!("{}: {e}", args.map.display())))?;
    let mut prepared = PreparedMap::new(loaded.grid.clone(), inflation.cells as f32)
        .context("invalid --radius")?;
    let (params, aco) = args.swarm.params(args.seed);
    prepared.warm_up(args.algo, &params, &aco);
    eprintln!(
        "{}",
        costs_json(&args.map, prepared.grid(), load_ms, prepared.costs())
    );
    let lines = match (&args.queries, &args.start, &args.goal) {
        (Some(file), _, _) => {
            let text = std::fs::read_to_string(file)
                .map_err(|e| bad(format!("cannot read queries {}: {e}", file.display())))?;
            jsonl::parse_queries(&text, args.frame)
        }
        (None, Some(start), Some(goal)) => vec![QueryLine::Query(jsonl::Query {
            start: endpoint(start, args.frame, "start")?,
            goal: endpoint(goal, args.frame, "goal")?,
        })],
        _ => return Err(bad("give --queries FILE or both --start and --goal")),
    };
    let sink: Box<dyn Write> = match &args.out {
        Some(path) => Box::new(
            std::fs::File::create(path)
                .with_context(|| format!("cannot create {}", path.display()))?,
        ),
        None => Box::new(std::io::stdout().lock()),
    };
    let mut out = BufWriter::new(sink);
    let name = args.algo.name();
    let ctx = LineContext {
        algo: name,
        seed: args.seed,
        frame: frame.declared.then_some(&frame),
    };
    let unknown = loaded.unknown.as_ref().map(|u| u.view());
    let radius_text = inflation.text.as_deref();
    for line in lines {
        let value = match line {
            QueryLine::Query(query) => match query.resolve(&frame) {
                Err(e) => jsonl::plan_line(&query, None, Err(e), 0.0, &ctx),
                Ok(cells) => {
                    let q = Query {
                        start: cells.0,
                        goal: cells.1,
                    };
                    let outcome = prepared.plan(args.algo, &params, &aco, q, &mut []);
                    let explain = |e: PlanError| {
                        jsonl::explain(
                            ErrorLine::named(e.name()),
                            loaded.grid.view(),
                            unknown,
                            cells,
                            radius_text,
                        )
                    };
                    let value = outcome_json(&query, cells, &outcome, explain, &ctx);
                    // What is printed, read back, must validate on the map planned on.
                    let text = value.to_string();
                    match crate::printed::check_line(&text, prepared.grid().view(), ctx.frame) {
                        Ok(()) => value,
                        Err(why) => {
                            let error = ErrorLine {
                                name: "InvalidPath".into(),
                                detail: Some(why),
                            };
                            jsonl::plan_line(&query, Some(cells), Err(error), outcome.time_us, &ctx)
                        }
                    }
                }
            },
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
    fn warm_up_is_timed_apart_and_changes_no_result() {
        let rows = b"..........@.........\n..@@@@....@...@@@...\n..@.......@.....@...\n\
                     ..@...@@@@@@....@...\n..........@.........\n....@@@.......@@@@..\n\
                     ....................\n";
        let q = Query {
            start: (0, 0),
            goal: (19, 6),
        };
        let (mut p, a) = (PlanParams::new(AlgorithmKind::Tclhho), AcoParams::default());
        p.iterations = 40;
        let a = AcoParams {
            iterations: 20,
            ..a
        };
        for kind in PlannerKind::ALL {
            let fresh = || PreparedMap::new(GridBuf::parse_rows(rows).unwrap(), 0.0).unwrap();
            let mut cold = fresh();
            let mut warm = fresh();
            warm.warm_up(kind, &p, &a);
            assert_eq!(cold.costs().warmup_ms, 0.0);
            assert!(warm.costs().warmup_ms > 0.0, "{kind:?}");
            let (c, w) = (
                cold.plan(kind, &p, &a, q, &mut []).result.unwrap(),
                warm.plan(kind, &p, &a, q, &mut []).result.unwrap(),
            );
            assert_eq!(c.path, w.path, "{kind:?}");
            assert_eq!(c.outcome, w.outcome, "{kind:?}");
        }
    }

    #[test]
    fn radius_zero_keeps_the_grid_and_a_bad_radius_is_an_error() {
        let grid = GridBuf::parse_rows(b"...\n.@.\n...\n").unwrap();
        let kept = PreparedMap::new(grid.clone(), 0.0).unwrap();
        assert_eq!(kept.grid, grid);
        let inflated = PreparedMap::new(grid.clone(), 0.5).unwrap();
        assert_eq!(inflated.grid, grid.inflated(0.5).unwrap());
        assert!(PreparedMap::new(grid.clone(), -1.0).is_err());
        assert!(PreparedMap::new(grid, f32::NAN).is_err());
    }

    #[test]
    fn out_of_range_coordinates_are_outside_the_map() {
        let grid = GridBuf::parse_rows(b"...\n...\n").unwrap();
        let mut map = PreparedMap::new(grid, 0.0).unwrap();
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

//! `host-sim plan`: the contract every planner plugs into.
//!
//! ```text
//! host-sim plan --map FILE.map --queries Q.txt --algo astar|theta [--seed N] [--radius R] [--out RESULTS.jsonl]
//! host-sim plan --map FILE.map --start X,Y --goal X,Y --algo astar
//! ```
//! `Q.txt` holds one query a line, `sx sy gx gy` in cell coordinates (blank lines and lines
//! starting with `#` are skipped). Output: one JSON object a line, in query order:
//! `{"start":[sx,sy],"goal":[gx,gy],"path":[[x,y],...],"length":L,"time_us":T,...}` or
//! `{"start":[..],"goal":[..],"error":"NoValidPath"}`. A line that is not a query yields
//! `{"line":N,"error":"MalformedQuery","detail":"..."}` and planning goes on.

use crate::maps::{HostGrid, load_movingai};
use anyhow::Context;
use clap::ValueEnum;
use planner_core::PlanError;
use planner_core::geometry::Cell;
use planner_core::path::{self, Path, PathView};
use planner_core::search::{SearchNode, astar, connectivity, theta};
use planner_ipc::jsonl;
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
    /// Planner.
    #[arg(long, value_enum, default_value_t = Algo::Astar)]
    pub algo: Algo,
    /// Seed of the random number generator (stochastic planners; recorded in the output).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Robot radius in cells: the map is inflated so that paths keep this clearance.
    #[arg(long, default_value_t = 0.0)]
    pub radius: f32,
    /// Write results here instead of standard output.
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// Planners selectable with `--algo`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Algo {
    /// A*: shortest 8-connected path (octile costs, no corner cutting).
    Astar,
    /// Theta*: any-angle path, never longer than A*'s.
    Theta,
}

impl Algo {
    fn name(self) -> &'static str {
        match self {
            Algo::Astar => "astar",
            Algo::Theta => "theta",
        }
    }
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

/// One line of a queries file.
#[derive(Debug, PartialEq, Eq)]
pub enum QueryLine {
    /// A well-formed query.
    Query(Query),
    /// A line that is not four integers.
    Malformed {
        /// 1-based line number.
        line: usize,
        /// What was wrong.
        detail: String,
    },
}

/// Parses a queries file; comments and blank lines are skipped.
pub fn parse_queries(text: &str) -> Vec<QueryLine> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .map(|(i, l)| {
            let fields: Vec<&str> = l.split_whitespace().collect();
            let nums: Result<Vec<i64>, _> = fields.iter().map(|f| f.parse::<i64>()).collect();
            match nums {
                Ok(n) if n.len() == 4 => QueryLine::Query(Query {
                    start: (n[0], n[1]),
                    goal: (n[2], n[3]),
                }),
                Ok(n) => QueryLine::Malformed {
                    line: i + 1,
                    detail: format!("expected 4 integers, found {}", n.len()),
                },
                Err(e) => QueryLine::Malformed {
                    line: i + 1,
                    detail: e.to_string(),
                },
            }
        })
        .collect()
}

/// A map prepared for repeated queries: inflated grid, component labels, search storage.
pub struct PreparedMap {
    grid: Box<HostGrid>,
    labels: Vec<u32>,
    nodes: Vec<SearchNode>,
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
    /// Path length.
    pub length: f32,
    /// Direction changes.
    pub turns: usize,
    /// Cells expanded by the search.
    pub expanded: u32,
}

impl PreparedMap {
    /// Inflates `grid` by `radius` and labels its components.
    pub fn new(grid: &HostGrid, radius: f32) -> anyhow::Result<Self> {
        let mut inflated = Box::new(HostGrid::new(1, 1).map_err(anyhow::Error::msg)?);
        grid.inflate_into(radius, &mut inflated)
            .map_err(anyhow::Error::msg)?;
        let cells = inflated.view().cells();
        let mut labels = vec![0u32; cells];
        connectivity::label(inflated.view(), &mut labels).map_err(anyhow::Error::msg)?;
        Ok(PreparedMap {
            grid: inflated,
            labels,
            nodes: vec![SearchNode::EMPTY; cells],
            path: Box::new(Path::new()),
        })
    }

    /// Plans one query with `algo`.
    pub fn plan(&mut self, algo: Algo, query: Query) -> Outcome {
        let began = Instant::now();
        let result = self.plan_inner(algo, query);
        Outcome {
            result,
            time_us: began.elapsed().as_secs_f64() * 1e6,
        }
    }

    fn plan_inner(&mut self, algo: Algo, query: Query) -> Result<PlanSummary, PlanError> {
        let start = to_cell(query.start).ok_or(PlanError::StartOutsideMap)?;
        let goal = to_cell(query.goal).ok_or(PlanError::GoalOutsideMap)?;
        let grid = self.grid.view();
        let out: &mut PathView = &mut *self.path;
        let stats = match algo {
            Algo::Astar => astar::plan_with_labels(
                grid,
                start,
                goal,
                Some(&self.labels),
                &mut self.nodes,
                out,
            )?,
            Algo::Theta => theta::plan_with_labels(
                grid,
                start,
                goal,
                Some(&self.labels),
                &mut self.nodes,
                out,
            )?,
        };
        Ok(PlanSummary {
            path: out.iter().map(|p| [p.x, p.y]).collect(),
            length: stats.length,
            turns: path::turns(out),
            expanded: stats.expanded,
        })
    }
}

fn to_cell((x, y): (i64, i64)) -> Option<Cell> {
    Some(Cell::new(u16::try_from(x).ok()?, u16::try_from(y).ok()?))
}

/// The JSON line of one query (the format lives in `planner_ipc::jsonl`, shared with
/// `planner-client`).
pub fn outcome_json(algo: Algo, seed: u64, query: Query, outcome: &Outcome) -> Value {
    let result = match &outcome.result {
        Ok(s) => Ok(jsonl::PathLine {
            path: &s.path,
            length: s.length,
            turns: s.turns,
            expanded: s.expanded,
        }),
        Err(e) => Err(e.name()),
    };
    jsonl::plan_line(
        query.start,
        query.goal,
        result,
        outcome.time_us,
        algo.name(),
        seed,
    )
}

/// Runs `host-sim plan`.
pub fn run(args: &PlanArgs) -> anyhow::Result<()> {
    let grid = load_movingai(&args.map)?;
    let mut prepared = PreparedMap::new(&grid, args.radius).context("invalid --radius")?;
    let lines = match (&args.queries, args.start, args.goal) {
        (Some(file), _, _) => {
            let text = std::fs::read_to_string(file)
                .with_context(|| format!("cannot read queries {}", file.display()))?;
            parse_queries(&text)
        }
        (None, Some(start), Some(goal)) => vec![QueryLine::Query(Query { start, goal })],
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
            QueryLine::Query(q) => {
                outcome_json(args.algo, args.seed, q, &prepared.plan(args.algo, q))
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
    fn parses_queries_and_reports_malformed_lines() {
        let got = parse_queries("# header\n1 2 3 4\n\n1 2 x 4\n-1 0 0 99999999\n1 2 3\n");
        assert_eq!(
            got[0],
            QueryLine::Query(Query {
                start: (1, 2),
                goal: (3, 4)
            })
        );
        assert!(matches!(got[1], QueryLine::Malformed { line: 4, .. }));
        assert_eq!(
            got[2],
            QueryLine::Query(Query {
                start: (-1, 0),
                goal: (0, 99999999)
            })
        );
        assert!(matches!(got[3], QueryLine::Malformed { line: 6, .. }));
    }

    #[test]
    fn out_of_range_coordinates_are_outside_the_map() {
        let grid = HostGrid::parse_rows(b"...\n...\n").unwrap();
        let mut map = PreparedMap::new(&grid, 0.0).unwrap();
        let q = |s, g| Query { start: s, goal: g };
        assert!(matches!(
            map.plan(Algo::Astar, q((-1, 0), (0, 0))).result,
            Err(PlanError::StartOutsideMap)
        ));
        assert!(matches!(
            map.plan(Algo::Theta, q((0, 0), (0, 70000))).result,
            Err(PlanError::GoalOutsideMap)
        ));
        assert!(map.plan(Algo::Theta, q((0, 0), (2, 1))).result.is_ok());
    }
}

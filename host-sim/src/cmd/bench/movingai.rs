//! `host-sim bench movingai`: validity, length and time of every planner on the Moving AI
//! warehouse maps, against the published octile optima.
//!
//! For each map, the first `--rows` rows of its `random-1` scenario file (rows of length 0
//! skipped). Every returned path is checked by the independent validator
//! ([`crate::validate`]); a planner error on these (all reachable) rows counts as invalid.

use super::{fmt, mean_std, print_table, progress, write_csv, write_json};
use anyhow::Context;
use planner_core::geometry::Cell;
use planner_core::optim::any::AlgorithmKind;
use planner_core::path::{Path, PathView};
use planner_core::planner::aco::AcoParams;
use planner_core::planner::owned::{HostPlanner, PlanChoice};
use planner_core::planner::{PlanOptions, PlanParams, PlannerKind};
use planner_mapfile::{MapOptions, load_map};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

/// The Moving AI warehouse maps vendored in `tests/data/movingai`.
pub const WAREHOUSES: [&str; 4] = [
    "warehouse-10-20-10-2-1",
    "warehouse-10-20-10-2-2",
    "warehouse-20-40-10-2-1",
    "warehouse-20-40-10-2-2",
];

/// Arguments of `host-sim bench movingai`.
#[derive(clap::Args, Debug)]
pub struct MovingaiArgs {
    /// Folder with the `.map` and `.scen` files.
    #[arg(long, default_value = "tests/data/movingai")]
    pub data: PathBuf,
    /// Scenario rows per map.
    #[arg(long, default_value_t = 200)]
    pub rows: usize,
    /// Maps (names without `.map`); default: the four warehouses.
    #[arg(long, value_delimiter = ',')]
    pub maps: Vec<String>,
    /// Planners, comma separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "astar,theta,hho,gwo,tclhho,igwo"
    )]
    pub algos: Vec<String>,
    /// Iterations of the swarm planners.
    #[arg(long, default_value_t = 500)]
    pub iters: u32,
    /// Stagnation stop of the swarm planners (iterations without improvement).
    #[arg(long)]
    pub stagnation: Option<u32>,
    /// Seed (row `k` uses `seed + k`).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// The corridor encoding's guide route.
    #[arg(long, value_enum, default_value_t = crate::cmd::plan::GuideArg::Anyangle)]
    pub guide: crate::cmd::plan::GuideArg,
    /// Output folder.
    #[arg(long, default_value = "bench-out/movingai")]
    pub out: PathBuf,
    /// Size limit of the loaded maps.
    #[command(flatten)]
    pub limits: MapOptions,
}

/// A scenario row.
#[derive(Clone, Copy, Debug)]
pub struct ScenRow {
    /// Start.
    pub start: Cell,
    /// Goal.
    pub goal: Cell,
    /// Published optimal octile length.
    pub optimal: f64,
}

/// Reads the rows of a Moving AI `.scen` file (version line skipped).
pub fn read_scen(text: &str) -> anyhow::Result<Vec<ScenRow>> {
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        let f: Vec<&str> = line.split('\t').collect();
        if f.len() != 9 {
            anyhow::bail!("scenario line {}: expected 9 fields", i + 1);
        }
        let n = |k: usize| {
            f[k].parse::<u16>()
                .with_context(|| format!("scenario line {}", i + 1))
        };
        rows.push(ScenRow {
            start: Cell::new(n(4)?, n(5)?),
            goal: Cell::new(n(6)?, n(7)?),
            optimal: f[8]
                .parse()
                .with_context(|| format!("scenario line {}", i + 1))?,
        });
    }
    Ok(rows)
}

/// One planner on one map.
#[derive(Serialize)]
pub struct Summary {
    /// Map.
    pub map: String,
    /// Planner.
    pub algo: String,
    /// Rows planned.
    pub rows: usize,
    /// Rows with a path accepted by the independent validator.
    pub valid: usize,
    /// Mean of length / published optimum.
    pub mean_ratio: f64,
    /// Largest length / published optimum.
    pub max_ratio: f64,
    /// Sum of lengths / sum of optima.
    pub total_ratio: f64,
    /// Mean time per plan (ms).
    pub mean_ms: f64,
    /// Mean best cost after initialisation / final best cost (swarm planners).
    pub init_over_final: f64,
    /// Mean evaluations.
    pub evaluations: f64,
}

/// Runs `host-sim bench movingai`.
pub fn run(args: &MovingaiArgs) -> anyhow::Result<()> {
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let kinds: Vec<PlannerKind> = args
        .algos
        .iter()
        .map(|a| {
            a.parse()
                .map_err(|_| anyhow::anyhow!("unknown planner {a}"))
        })
        .collect::<anyhow::Result<_>>()?;
    let maps: Vec<String> = if args.maps.is_empty() {
        WAREHOUSES.iter().map(|s| s.to_string()).collect()
    } else {
        args.maps.clone()
    };
    let mut summaries = Vec::new();
    for name in &maps {
        let grid = load_map(&args.data.join(format!("{name}.map")), &args.limits)?.grid;
        let scen_path = args.data.join(format!("{name}-random-1.scen"));
        let text = std::fs::read_to_string(&scen_path)
            .with_context(|| format!("cannot read {}", scen_path.display()))?;
        let rows: Vec<ScenRow> = read_scen(&text)?
            .into_iter()
            .filter(|r| r.optimal > 0.0)
            .take(args.rows)
            .collect();
        let mut planner = HostPlanner::new();
        planner.prepare(grid.view()).map_err(anyhow::Error::msg)?;
        let mut out: Box<Path<65536>> = Box::new(Path::new());
        let bar = progress((rows.len() * kinds.len()) as u64, name);
        for &kind in &kinds {
            let (mut ratios, mut times, mut gains, mut evals) =
                (Vec::new(), Vec::new(), Vec::new(), Vec::new());
            let (mut valid, mut total_len, mut total_opt) = (0usize, 0.0f64, 0.0f64);
            for (k, row) in rows.iter().enumerate() {
                let params = PlanParams {
                    iterations: args.iters,
                    stagnation: args.stagnation,
                    seed: args.seed + k as u64,
                    guide: args.guide.kind(),
                    ..PlanParams::new(AlgorithmKind::Tclhho)
                };
                let view: &mut PathView = &mut *out;
                let began = Instant::now();
                let result = planner.plan(
                    grid.view(),
                    row.start,
                    row.goal,
                    &PlanChoice {
                        kind,
                        params,
                        aco: AcoParams::default(),
                    },
                    view,
                    PlanOptions::default(),
                );
                times.push(began.elapsed().as_secs_f64() * 1e3);
                bar.inc(1);
                let Ok(outcome) = result else { continue };
                let path: Vec<[f32; 2]> = out.iter().map(|p| [p.x, p.y]).collect();
                if crate::validate::check(
                    grid.view(),
                    &path,
                    (row.start.x, row.start.y),
                    (row.goal.x, row.goal.y),
                )
                .is_err()
                {
                    continue;
                }
                valid += 1;
                ratios.push(outcome.length as f64 / row.optimal);
                total_len += outcome.length as f64;
                total_opt += row.optimal;
                if let Some(r) = outcome.report {
                    gains.push(r.initial_cost as f64 / r.final_cost as f64);
                    evals.push(r.evaluations as f64);
                }
            }
            summaries.push(Summary {
                map: name.clone(),
                algo: kind.name().into(),
                rows: rows.len(),
                valid,
                mean_ratio: mean_std(&ratios).0,
                max_ratio: ratios.iter().copied().fold(f64::NAN, f64::max),
                total_ratio: total_len / total_opt,
                mean_ms: mean_std(&times).0,
                init_over_final: mean_std(&gains).0,
                evaluations: mean_std(&evals).0,
            });
        }
        bar.finish_and_clear();
    }
    let header = [
        "map",
        "planner",
        "valid",
        "mean L/opt",
        "max L/opt",
        "sum L/sum opt",
        "ms/plan",
        "init/final",
        "evals",
    ];
    let rows: Vec<Vec<String>> = summaries
        .iter()
        .map(|s| {
            vec![
                s.map.clone(),
                s.algo.clone(),
                format!("{}/{}", s.valid, s.rows),
                fmt(s.mean_ratio, 4),
                fmt(s.max_ratio, 4),
                fmt(s.total_ratio, 4),
                fmt(s.mean_ms, 3),
                fmt(s.init_over_final, 3),
                fmt(s.evaluations, 0),
            ]
        })
        .collect();
    print_table(
        &format!(
            "Moving AI warehouses, {} rows each, {} iterations, stagnation {:?}",
            args.rows, args.iters, args.stagnation
        ),
        &header,
        &rows,
    );
    write_csv(&args.out.join("movingai.csv"), &header, &rows)?;
    write_json(&args.out.join("movingai.json"), &summaries)?;
    Ok(())
}

//! `host-sim bench speed`: time per plan of the swarm planners as a ratio to A* on the same
//! queries in the same process, with and without stagnation stopping, and the lengths, so
//! that the cost and the benefit of stopping early are both visible.
//!
//! For each swarm planner it also times the optimizer alone: the same algorithm, population,
//! iterations, seeds and dimension (the mean over the plans), on a sphere in `[-1, 1]^D`
//! whose evaluation costs next to nothing. That is the floor no encoding can go below, the
//! cost of the search itself (random draws, Levy flights, bookkeeping), and it says how far
//! the ratio to A* can fall at these settings.

use super::{fmt, mean_std, print_table, write_json};
use anyhow::Context;
use planner_core::grid::{GridBuf, words_for};
use planner_core::maps::{MapKind, lei2024_warehouse};
use planner_core::optim::any::{AlgorithmKind, AnyOptimizer};
use planner_core::optim::{Bounds, Optimizer, Settings, Stop};
use planner_core::path::{Path, PathView};
use planner_core::planner::aco::AcoParams;
use planner_core::planner::owned::{HostPlanner, PlanChoice};
use planner_core::planner::{EncodingKind, PlanOptions, PlanParams, PlannerKind};
use planner_mapfile::{MapOptions, load_map};
use std::path::PathBuf;
use std::time::Instant;

use super::movingai::{ScenRow, read_scen};

/// Arguments of `host-sim bench speed`.
#[derive(clap::Args, Debug)]
pub struct SpeedArgs {
    /// Folder with the Moving AI files.
    #[arg(long, default_value = "tests/data/movingai")]
    pub data: PathBuf,
    /// Queries on the Moving AI map.
    #[arg(long, default_value_t = 50)]
    pub rows: usize,
    /// Repetitions of the seed-map query.
    #[arg(long, default_value_t = 20)]
    pub repeats: usize,
    /// Planners to time.
    #[arg(long, value_delimiter = ',', default_value = "tclhho,igwo")]
    pub algos: Vec<String>,
    /// Stagnation window for the early-stopping rows.
    #[arg(long, default_value_t = 50)]
    pub stagnation: u32,
    /// The corridor encoding's guide route (the Moving AI map).
    #[arg(long, value_enum, default_value_t = crate::cmd::plan::GuideArg::Anyangle)]
    pub guide: crate::cmd::plan::GuideArg,
    /// Output folder.
    #[arg(long, default_value = "bench-out/speed")]
    pub out: PathBuf,
    /// Size limit of the loaded maps.
    #[command(flatten)]
    pub limits: MapOptions,
}

/// Runs `host-sim bench speed`.
pub fn run(args: &SpeedArgs) -> anyhow::Result<()> {
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let paper_map = lei2024_warehouse::<{ words_for(40, 40) }>(MapKind::Warehouse, 40)
        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
    let paper_grid = GridBuf::from_view(paper_map.grid.view());
    let paper_rows = vec![
        ScenRow {
            start: paper_map.start,
            goal: paper_map.goal,
            optimal: f64::NAN
        };
        args.repeats
    ];
    let wh = load_map(&args.data.join("warehouse-10-20-10-2-1.map"), &args.limits)?.grid;
    let text = std::fs::read_to_string(args.data.join("warehouse-10-20-10-2-1-random-1.scen"))?;
    let wh_rows: Vec<ScenRow> = read_scen(&text)?
        .into_iter()
        .filter(|r| r.optimal > 0.0)
        .take(args.rows)
        .collect();
    let kinds: Vec<PlannerKind> = args
        .algos
        .iter()
        .map(|a| {
            a.parse()
                .map_err(|_| anyhow::anyhow!("unknown planner {a}"))
        })
        .collect::<anyhow::Result<_>>()?;

    let mut table = Vec::new();
    let mut records = Vec::new();
    // "seed000": `Lei2024Warehouse` (docs/references.md); the label stays as earlier results
    // files (`"map"`) have it.
    let cases: [(&str, &GridBuf, &[ScenRow], EncodingKind); 3] = [
        (
            "seed000 warehouse 40x40",
            &paper_grid,
            &paper_rows,
            EncodingKind::Corridor,
        ),
        (
            "seed000 warehouse 40x40",
            &paper_grid,
            &paper_rows,
            EncodingKind::Column,
        ),
        (
            "warehouse-10-20-10-2-1",
            &wh,
            &wh_rows,
            EncodingKind::Corridor,
        ),
    ];
    for (name, grid, rows, encoding) in cases {
        let mut planner = HostPlanner::new();
        planner.prepare(grid.view()).map_err(anyhow::Error::msg)?;
        let mut out: Box<Path<65536>> = Box::new(Path::new());
        let time = |planner: &mut HostPlanner,
                    out: &mut PathView,
                    kind: PlannerKind,
                    params: &PlanParams|
         -> (f64, f64, f64) {
            let (mut t, mut l, mut d) = (Vec::new(), Vec::new(), Vec::new());
            // One untimed plan first: it warms the caches.
            if let Some(r) = rows.first() {
                let _ = planner.plan(
                    grid.view(),
                    r.start,
                    r.goal,
                    &PlanChoice {
                        kind,
                        params: *params,
                        aco: AcoParams::default(),
                    },
                    out,
                    PlanOptions::default(),
                );
            }
            for (k, r) in rows.iter().enumerate() {
                let params = PlanParams {
                    seed: k as u64 + 1,
                    ..*params
                };
                let began = Instant::now();
                let res = planner.plan(
                    grid.view(),
                    r.start,
                    r.goal,
                    &PlanChoice {
                        kind,
                        params,
                        aco: AcoParams::default(),
                    },
                    out,
                    PlanOptions::default(),
                );
                t.push(began.elapsed().as_secs_f64());
                l.push(res.as_ref().map_or(f64::NAN, |o| o.length as f64));
                d.push(
                    res.ok()
                        .and_then(|o| o.report)
                        .map_or(f64::NAN, |r| r.dimension as f64),
                );
            }
            (mean_std(&t).0, mean_std(&l).0, mean_std(&d).0)
        };
        let base = PlanParams {
            encoding,
            guide: args.guide.kind(),
            ..PlanParams::new(AlgorithmKind::Tclhho)
        };
        let (t_astar, l_astar, _) = time(&mut planner, &mut *out, PlannerKind::AStar, &base);
        table.push(vec![
            name.into(),
            "astar".into(),
            "-".into(),
            fmt(t_astar * 1e3, 3),
            "1.0".into(),
            fmt(l_astar, 3),
        ]);
        // One row of the table and of the JSON (no length for an optimizer alone).
        let mut push = |label: String, stop: String, t: f64, length: Option<f64>| {
            records.push(serde_json::json!({"map": name, "planner": label, "stop": stop, "ms": t * 1e3, "ratio_to_astar": t / t_astar, "mean_length": length}));
            table.push(vec![
                name.into(),
                label,
                stop,
                fmt(t * 1e3, 3),
                fmt(t / t_astar, 1),
                length.map_or("-".into(), |l| fmt(l, 3)),
            ]);
        };
        for &kind in &kinds {
            let mut dimension = f64::NAN;
            for stagnation in [None, Some(args.stagnation)] {
                let params = PlanParams { stagnation, ..base };
                let (t, l, d) = time(&mut planner, &mut *out, kind, &params);
                if stagnation.is_none() {
                    dimension = d;
                }
                let label = format!("{} {}", kind.name(), encoding.name());
                let stop =
                    stagnation.map_or("500 iterations".to_string(), |s| format!("stagnation {s}"));
                push(label, stop, t, Some(l));
            }
            if let (PlannerKind::Swarm(algo), true) = (kind, dimension.is_finite()) {
                let dim = dimension.round() as usize;
                let t = optimizer_floor(algo, dim, base.population, base.iterations, rows.len())?;
                let label = format!("{} alone, D = {dim}", kind.name());
                push(label, format!("{} iterations", base.iterations), t, None);
            }
        }
    }
    print_table(
        "Time per plan (population 30, 500 iterations), ratio to A* in the same run",
        &["map", "planner", "stop", "ms/plan", "x A*", "mean length"],
        &table,
    );
    write_json(&args.out.join("speed.json"), &records)?;
    Ok(())
}

/// Mean time of `runs` runs (seeds 1..=runs, as the plans) of `algo` alone on a shifted
/// sphere in `[-1, 1]^dim`: what the search costs without an encoding.
fn optimizer_floor(
    algo: AlgorithmKind,
    dim: usize,
    population: usize,
    iterations: u32,
    runs: usize,
) -> anyhow::Result<f64> {
    const MAX_DIM: usize = planner_core::planner::owned::HOST_DIMENSION;
    let bounds = Bounds::<MAX_DIM>::uniform(dim, -1.0, 1.0).map_err(anyhow::Error::msg)?;
    let stop = Stop {
        max_iterations: Some(iterations),
        ..Stop::default()
    };
    // Centred off the origin: swarms converging on 0 would work in subnormal floats, which
    // cost x86 a hundred cycles an operation and no plan ever meets.
    let mut sphere = |x: &[f32]| {
        x.iter()
            .enumerate()
            .map(|(i, v)| {
                let d = v - ((i * 7 % 10) as f32 / 10.0 - 0.45);
                d * d
            })
            .sum::<f32>()
    };
    let mut times = Vec::with_capacity(runs);
    for k in 0..runs.max(1) {
        let settings = Settings {
            population,
            iterations,
            seed: k as u64 + 1,
        };
        let mut opt: Box<AnyOptimizer<{ planner_core::planner::owned::HOST_POPULATION }, MAX_DIM>> =
            Box::new(AnyOptimizer::new(algo, settings, &bounds).map_err(anyhow::Error::msg)?);
        let began = Instant::now();
        opt.run(&mut sphere, None, &stop, &mut [])
            .map_err(anyhow::Error::msg)?;
        times.push(began.elapsed().as_secs_f64());
    }
    Ok(mean_std(&times).0)
}

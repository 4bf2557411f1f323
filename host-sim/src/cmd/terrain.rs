//! `host-sim terrain`: 3D terrain planning with SSA-GWO and the baselines (`Zhu2025Orchard` in
//! `docs/references.md`, SPEC section 4); reproduces the paper's tables 2 to 7. The
//! experiments, terrains and runs are [`host_sim::terrain`]'s; this command parses the
//! arguments, prints the tables and writes the files.
//!
//! ACO, PSO, GWO, SSA and SSA-GWO, population 100, 500 iterations, `--runs` runs each; per
//! algorithm the min, max, range, std (population) and mean of the best path's length and
//! energy over the runs whose best path is valid. Writes `results.json`, `tables.csv`,
//! `paths.png` (top view) and `convergence.png` under `--out`. `--heightmap FILE` replaces the
//! generated terrain by a DEM (16-bit PNG or PGM). `--bench` times SSA-GWO runs and single
//! evaluations instead, beside a baseline in the same process (decoding the waypoints and
//! summing their horizontal segment lengths).

use super::bench::{fmt, mean_std, print_table, progress, write_csv, write_json};
use crate::render::{Disc, FieldPicture, Layer, Series, Style, convergence_plot};
use anyhow::{Context, bail};
use host_sim::terrain::{
    self, ALGORITHMS, Experiment, HostTerrain, MAX_DIM, MAX_POPULATION, PAPER, RunOptions,
    RunResult, Stats, load_heightmap,
};
use planner_core::geometry::Point;
use planner_core::optim::Bounds;
use planner_core::terrain::objective::{ObjectiveParams, TerrainObjective};
use planner_core::terrain::obstacles::Shape;
use planner_core::terrain::planes::HeightMode;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Arguments of `host-sim terrain`.
#[derive(clap::Args, Debug)]
pub struct TerrainArgs {
    /// Experiment 1 (terrain only), 2 (two cylinders) or 3 (30 x 30 km, cylinders and a cone).
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u8).range(1..=3))]
    pub experiment: u8,
    /// Runs per algorithm (the paper uses 30).
    #[arg(long, default_value_t = 30)]
    pub runs: u32,
    /// Iterations per run (the paper uses 500).
    #[arg(long, default_value_t = 500)]
    pub iterations: u32,
    /// Population (ants for ACO; the paper uses 100).
    #[arg(long, default_value_t = 100)]
    pub population: usize,
    /// Seed of the runs: run `k` of algorithm `a` uses a seed derived from `(seed, k, a)`.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Seed of the generated terrain (default: the experiment's own).
    #[arg(long)]
    pub terrain_seed: Option<u64>,
    /// Interior planes (default: 20 for experiments 1 and 2, 28 for experiment 3).
    #[arg(long)]
    pub planes: Option<usize>,
    /// Diagnostic: the continuous optimizers search `v = t + shift` (km) instead of each
    /// lateral offset `t`, the box shifted alike, so that the box's origin is no longer the
    /// straight line (an origin-biased optimizer gains nothing from it). ACO is unaffected.
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    pub shift: f32,
    /// Literal mode: waypoint heights are decision variables too (ACO is skipped).
    #[arg(long)]
    pub literal: bool,
    /// Import the terrain from a 16-bit (or 8-bit) grey PNG or PGM instead of generating it.
    #[arg(long)]
    pub heightmap: Option<PathBuf>,
    /// Sample spacing of an imported heightmap (km).
    #[arg(long, default_value_t = 1.0)]
    pub spacing: f32,
    /// Height (km) of the largest sample value of an imported heightmap (65535 or 255).
    #[arg(long, default_value_t = 2.0)]
    pub max_height: f32,
    /// Time SSA-GWO runs (population and iterations as given) and single evaluations.
    #[arg(long)]
    pub bench: bool,
    /// Output folder (default `bench-out/terrain/expN`).
    #[arg(long)]
    pub out: Option<PathBuf>,
}

/// A table row: the algorithm's name, then the statistics with `digits` decimals.
fn stats_row(s: &Stats, name: &str, digits: usize) -> Vec<String> {
    vec![
        name.to_string(),
        fmt(s.min, digits),
        fmt(s.max, digits),
        fmt(s.range, digits),
        fmt(s.std, digits),
        fmt(s.mean, digits),
    ]
}

/// Runs `host-sim terrain`.
pub fn run(args: &TerrainArgs) -> anyhow::Result<()> {
    let mut exp = Experiment::new(args.experiment)?;
    if let Some(p) = args.planes {
        exp.planes = p;
    }
    let terrain = match &args.heightmap {
        Some(path) => load_heightmap(path, args.spacing, args.max_height)?,
        None => exp.generate_terrain(args.terrain_seed.unwrap_or(exp.terrain_seed))?,
    };
    let view = terrain.view()?;
    exp.place_obstacles(&view);
    let mode = if args.literal {
        HeightMode::Free
    } else {
        HeightMode::Terrain
    };
    let objective = terrain::objective(&exp, view, mode)?;
    let bounds = terrain::search_box(&objective)?;
    if !args.shift.is_finite() || (args.bench && args.shift != 0.0) {
        bail!("--shift must be finite, and is not used with --bench");
    }
    let bounds = terrain::shift_box(bounds, objective.encoding().planes(), args.shift)?;
    if args.population == 0 || args.population > MAX_POPULATION {
        bail!("--population must be 1..={MAX_POPULATION}");
    }
    if args.iterations == 0 || args.runs == 0 {
        bail!("--iterations and --runs must be at least 1");
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("bench-out/terrain/exp{}", exp.number)));
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create {}", out.display()))?;
    let options = RunOptions {
        runs: args.runs,
        seed: args.seed,
        population: args.population,
        iterations: args.iterations,
        shift: args.shift,
    };
    if args.bench {
        return bench(args, &options, &objective, &bounds, &out);
    }

    let algorithms = terrain::algorithms(mode);
    let bar = progress(
        u64::from(args.runs) * algorithms.len() as u64,
        &format!("terrain exp {}", exp.number),
    );
    let results = terrain::run_experiment(&algorithms, &options, &objective, &bounds, &mut || {
        bar.inc(1)
    })?;
    bar.finish_and_clear();

    // Tables.
    let header = ["algorithm", "min", "max", "range", "std", "mean"];
    let (tl, te) = exp.tables();
    let mut csv = Vec::new();
    let mut summary = Vec::new();
    for (q, (what, table)) in [("path length L (km)", tl), ("energy E", te)]
        .iter()
        .enumerate()
    {
        let mut ours = Vec::new();
        let mut paper = Vec::new();
        for (a, name) in ALGORITHMS.iter().enumerate() {
            let vals: Vec<f64> = results
                .iter()
                .filter(|r| r.algorithm == *name && r.valid)
                .map(|r| f64::from(if q == 0 { r.best.length } else { r.best.energy }))
                .collect();
            if algorithms.contains(name) {
                let s = Stats::of(&vals);
                ours.push(stats_row(&s, name, 4));
                let mut row = vec![format!("{}", table), "ours".to_string()];
                row.extend(stats_row(&s, name, 4));
                csv.push(row);
            }
            let s = Stats::from_row(PAPER[usize::from(exp.number - 1)][q][a]);
            paper.push(stats_row(&s, name, 4));
            let mut row = vec![format!("{}", table), "paper".to_string()];
            row.extend(stats_row(&s, name, 4));
            csv.push(row);
        }
        print_table(
            &format!(
                "Experiment {} (table {table}): {what}, ours ({} runs, valid paths only)",
                exp.number, args.runs
            ),
            &header,
            &ours,
        );
        print_table(
            &format!("Zhu2025Orchard table {table} (paper's map and units)"),
            &header,
            &paper,
        );
    }
    for name in &algorithms {
        let rs: Vec<&RunResult> = results.iter().filter(|r| r.algorithm == *name).collect();
        let valid = rs.iter().filter(|r| r.valid).count();
        let f: Vec<f64> = rs.iter().map(|r| f64::from(r.best.cost)).collect();
        let t: Vec<f64> = rs.iter().map(|r| r.seconds).collect();
        let it: Vec<f64> = rs.iter().map(|r| f64::from(r.best_iteration)).collect();
        let clear = rs
            .iter()
            .map(|r| f64::from(r.best.min_clearance))
            .fold(f64::INFINITY, f64::min);
        summary.push(vec![
            name.to_string(),
            format!("{valid}/{}", rs.len()),
            fmt(mean_std(&f).0, 3),
            fmt(mean_std(&it).0, 1),
            fmt(mean_std(&t).0 * 1e3, 1),
            if clear.is_finite() {
                fmt(clear, 3)
            } else {
                "—".to_string()
            },
        ]);
    }
    print_table(
        &format!(
            "Experiment {}: valid runs, mean F, mean iteration of the best, mean time, least clearance",
            exp.number
        ),
        &[
            "algorithm",
            "valid",
            "F mean",
            "I mean",
            "ms/run",
            "clearance km",
        ],
        &summary,
    );
    write_csv(
        &out.join("tables.csv"),
        &[
            "table",
            "source",
            "algorithm",
            "min",
            "max",
            "range",
            "std",
            "mean",
        ],
        &csv,
    )?;
    #[derive(Serialize)]
    struct Output<'a> {
        experiment: &'a Experiment,
        mode: &'static str,
        shift: f32,
        runs: u32,
        iterations: u32,
        population: usize,
        objective: ObjectiveParams,
        terrain: &'a HostTerrain,
        results: &'a [RunResult],
    }
    write_json(
        &out.join("results.json"),
        &Output {
            experiment: &exp,
            mode: if args.literal { "free" } else { "terrain" },
            shift: args.shift,
            runs: args.runs,
            iterations: args.iterations,
            population: args.population,
            objective: *objective.params(),
            terrain: &terrain,
            results: &results,
        },
    )?;
    // A best F at or above one intrusion's weighted penalty is a path still inside an
    // obstacle: left out of the convergence plot so that the valid part is readable.
    let p = objective.params();
    let invalid_from = (1.0 - p.w1 - p.w2) * p.penalty;
    pictures(&exp, &terrain, &algorithms, &results, invalid_from, &out)?;
    eprintln!("wrote {}", out.display());
    Ok(())
}
fn pictures(
    exp: &Experiment,
    terrain: &HostTerrain,
    algorithms: &[&str],
    results: &[RunResult],
    invalid_from: f32,
    out: &Path,
) -> anyhow::Result<()> {
    // Best valid run per algorithm (lowest F).
    let s = terrain.spacing;
    let mut paths: Vec<(String, Vec<Point>)> = Vec::new();
    let mut curves: Vec<(String, Vec<f32>)> = Vec::new();
    for name in algorithms {
        let rs: Vec<&RunResult> = results.iter().filter(|r| r.algorithm == *name).collect();
        if let Some(best) = rs
            .iter()
            .filter(|r| r.valid)
            .min_by(|a, b| a.best.cost.total_cmp(&b.best.cost))
        {
            let pts = best
                .path
                .iter()
                .map(|p| Point::new(p[0] / s, p[1] / s))
                .collect();
            paths.push((format!("{name} (L = {:.2} km)", best.best.length), pts));
        }
        // Median over runs of the best F after each iteration.
        let len = rs.iter().map(|r| r.history.len()).min().unwrap_or(0);
        let median: Vec<f32> = (0..len)
            .map(|i| {
                let mut v: Vec<f32> = rs.iter().map(|r| r.history[i]).collect();
                v.sort_by(f32::total_cmp);
                let m = v[v.len() / 2];
                if m < invalid_from { m } else { f32::NAN }
            })
            .collect();
        curves.push((name.to_string(), median));
    }
    let title = format!(
        "Zhu2025Orchard experiment {}: best path of each algorithm over {} x {} km terrain (y down)",
        exp.number,
        (terrain.width - 1) as f32 * s,
        (terrain.height - 1) as f32 * s
    );
    let mut pic = FieldPicture::new(terrain.width, terrain.height, &terrain.z, &title);
    pic.value_label = "height (km)";
    pic.bands = Some(10);
    pic.cell_px = Some(if terrain.width <= 40 { 28 } else { 4 });
    for (i, (label, pts)) in paths.iter().enumerate() {
        pic.layers.push(Layer::new(label, pts, Style::palette(i)));
    }
    for o in &exp.obstacles {
        pic.discs.push(Disc {
            label: match o.shape {
                Shape::Cylinder => "cylinder",
                Shape::Cone => "cone",
            },
            at: Point::new(o.x / s, o.y / s),
            radius_cells: o.radius / s,
            color: match o.shape {
                Shape::Cylinder => [120, 0, 0],
                Shape::Cone => [90, 40, 140],
            },
        });
    }
    pic.start = Some(Point::new(exp.start.0 / s, exp.start.1 / s));
    pic.goal = Some(Point::new(exp.goal.0 / s, exp.goal.1 / s));
    pic.save_png(&out.join("paths.png"))?;
    pic.save_svg(&out.join("paths.svg"))?;
    let series: Vec<Series<'_>> = curves.iter().map(|(n, v)| Series::new(n, v)).collect();
    convergence_plot(
        &format!(
            "Zhu2025Orchard experiment {}: median best F over runs (gap: inside an obstacle)",
            exp.number
        ),
        "iteration",
        "F = w1 E + w2 L + (1 - w1 - w2) T",
        &series,
        Some(&out.join("convergence.png")),
        Some(&out.join("convergence.svg")),
    )?;
    Ok(())
}

fn bench(
    args: &TerrainArgs,
    options: &RunOptions,
    objective: &TerrainObjective<'_>,
    bounds: &Bounds<MAX_DIM>,
    out: &Path,
) -> anyhow::Result<()> {
    let evaluation = terrain::time_evaluations(objective, bounds, args.seed);
    let (dim, per_eval_ns, baseline_ns) = (
        evaluation.dim,
        evaluation.ns_per_evaluation,
        evaluation.ns_per_baseline,
    );
    // Whole SSA-GWO runs.
    let runs = args.runs.clamp(1, 10);
    let bar = progress(u64::from(runs), "ssa-gwo bench");
    let timing = terrain::time_runs(objective, bounds, options, runs, &mut || bar.inc(1))?;
    bar.finish_and_clear();
    let (mean, std, evals) = (timing.seconds_mean, timing.seconds_std, timing.evaluations);
    let rows = vec![vec![
        format!("{}", args.experiment),
        format!("{dim}"),
        format!("{}x{}", args.population, args.iterations),
        format!("{runs}"),
        fmt(mean * 1e3, 1),
        fmt(std * 1e3, 1),
        format!("{evals}"),
        fmt(mean * 1e9 / evals as f64, 0),
        fmt(per_eval_ns, 0),
        fmt(baseline_ns, 0),
        fmt(per_eval_ns / baseline_ns, 1),
    ]];
    print_table(
        "SSA-GWO on the terrain objective (release build recommended)",
        &[
            "exp",
            "D",
            "pop x iters",
            "runs",
            "ms/run",
            "std ms",
            "evals/run",
            "ns/eval in run",
            "ns/eval alone",
            "ns/baseline",
            "eval/baseline",
        ],
        &rows,
    );
    #[derive(Serialize)]
    struct BenchOut {
        experiment: u8,
        dim: usize,
        population: usize,
        iterations: u32,
        runs: u32,
        ms_per_run_mean: f64,
        ms_per_run_std: f64,
        evaluations_per_run: u64,
        ns_per_evaluation_in_run: f64,
        ns_per_evaluation_alone: f64,
        ns_per_baseline: f64,
        evaluation_over_baseline: f64,
    }
    write_json(
        &out.join("bench.json"),
        &BenchOut {
            experiment: args.experiment,
            dim,
            population: args.population,
            iterations: args.iterations,
            runs,
            ms_per_run_mean: mean * 1e3,
            ms_per_run_std: std * 1e3,
            evaluations_per_run: evals,
            ns_per_evaluation_in_run: mean * 1e9 / evals as f64,
            ns_per_evaluation_alone: per_eval_ns,
            ns_per_baseline: baseline_ns,
            evaluation_over_baseline: per_eval_ns / baseline_ns,
        },
    )
}

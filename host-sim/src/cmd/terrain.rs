//! `host-sim terrain`: 3D terrain planning with SSA-GWO and the baselines (seed 001, SPEC
//! section 4); reproduces the paper's tables 2 to 7.
//!
//! Units are kilometres everywhere (horizontal and vertical). The three experiments:
//! 1. a seeded 21 x 21 km "sum of peaks" terrain (22 x 22 samples, 1 km apart), start `(1, 15)`,
//!    goal `(21, 8)`, no obstacles (tables 2 and 3);
//! 2. the same terrain with two cylinders of radius 1 km at `(11, 16)` and `(12, 4)` (tables 4
//!    and 5);
//! 3. a 30 x 30 km terrain, start `(1, 13)`, goal `(30, 11)`, cylinders of radius 1.5 and 2 km
//!    and a cone of radius 3 km placed across the straight line (ours; tables 6 and 7).
//!
//! ACO, PSO (`w = 0.7`), GWO, SSA and SSA-GWO (`ST = 0.6, PD = 0.4, SD = 0.2`), population 100,
//! 500 iterations, `--runs` runs each; per algorithm the min, max, range, std (population)
//! and mean of the best path's length and energy over the runs whose best path is valid.
//! Writes `results.json`, `tables.csv`, `paths.png` (top view) and `convergence.png` under
//! `--out`. `--heightmap FILE` replaces the generated terrain by a DEM (16-bit PNG or PGM).
//! `--bench` times SSA-GWO runs and single evaluations instead.

use super::bench::{fmt, mean_std, print_table, progress, write_csv, write_json};
use crate::render::{Disc, FieldPicture, Layer, Series, Style, convergence_plot};
use anyhow::{Context, bail};
use planner_core::geometry::Point;
use planner_core::optim::gwo::{Gwo, GwoParams};
use planner_core::optim::pso::{Pso, PsoParams};
use planner_core::optim::random::Random;
use planner_core::optim::ssa::{Ssa, SsaParams};
use planner_core::optim::ssa_gwo::{SsaGwo, SsaGwoParams};
use planner_core::optim::{Bounds, Optimizer, Settings, Stop};
use planner_core::terrain::aco::{Aco, AcoParams};
use planner_core::terrain::objective::{Evaluation, ObjectiveParams, TerrainObjective};
use planner_core::terrain::obstacles::{Obstacle, Shape};
use planner_core::terrain::planes::{HeightMode, MAX_PLANES, PlaneEncoding};
use planner_core::terrain::{Heightmap, Peaks, Point3, TerrainView};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Population capacity.
const N: usize = 100;
/// Dimension capacity (the free-height mode needs `2n`).
const D: usize = 64;

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

/// The five algorithms, in the paper's order.
pub const ALGORITHMS: [&str; 5] = ["ACO", "PSO", "GWO", "SSA", "SSA-GWO"];

/// One experiment's setting.
#[derive(Debug, Clone, Serialize)]
pub struct Experiment {
    /// 1, 2 or 3.
    pub number: u8,
    /// Samples per row and rows.
    pub samples: (usize, usize),
    /// Seed of the generated terrain.
    pub terrain_seed: u64,
    /// Start `(x, y)` km.
    pub start: (f32, f32),
    /// Goal `(x, y)` km.
    pub goal: (f32, f32),
    /// Interior planes.
    pub planes: usize,
    /// Obstacles (their foot is set on the terrain when the map is built).
    pub obstacles: Vec<Obstacle>,
}

impl Experiment {
    /// The settings of experiment `n` (1 to 3).
    pub fn new(n: u8) -> anyhow::Result<Self> {
        let ob = |shape, x, y, radius, height| Obstacle {
            shape,
            x,
            y,
            radius,
            base: 0.0,
            height,
        };
        Ok(match n {
            1 | 2 => Self {
                number: n,
                samples: (22, 22),
                terrain_seed: 2025,
                start: (1.0, 15.0),
                goal: (21.0, 8.0),
                planes: 20,
                obstacles: if n == 2 {
                    vec![
                        ob(Shape::Cylinder, 11.0, 16.0, 1.0, 0.6),
                        ob(Shape::Cylinder, 12.0, 4.0, 1.0, 0.6),
                    ]
                } else {
                    vec![]
                },
            },
            3 => Self {
                number: 3,
                samples: (31, 31),
                terrain_seed: 2030,
                start: (1.0, 13.0),
                goal: (30.0, 11.0),
                planes: 28,
                obstacles: vec![
                    ob(Shape::Cylinder, 9.0, 12.5, 1.5, 0.6),
                    ob(Shape::Cone, 16.0, 13.0, 3.0, 0.8),
                    ob(Shape::Cylinder, 23.0, 10.5, 2.0, 0.6),
                ],
            },
            _ => bail!("experiment must be 1, 2 or 3"),
        })
    }
}

/// A terrain owned by the host (generated or imported).
#[derive(Debug, Clone, Serialize)]
pub struct HostTerrain {
    /// Samples per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// Spacing (km).
    pub spacing: f32,
    /// Heights (km), row by row.
    pub z: Vec<f32>,
}

impl HostTerrain {
    /// The core's view.
    pub fn view(&self) -> anyhow::Result<TerrainView<'_>> {
        TerrainView::new(self.width, self.height, self.spacing, &self.z)
            .map_err(|e| anyhow::anyhow!("terrain: {e}"))
    }
}

/// Reads a grey PNG (8 or 16 bit) or PGM (P2/P5, 8 or 16 bit) as heights: the largest
/// possible sample value maps to `max_height` km, row 0 of the image is `y = 0`.
pub fn load_heightmap(path: &Path, spacing: f32, max_height: f32) -> anyhow::Result<HostTerrain> {
    if !(max_height.is_finite() && max_height > 0.0) {
        bail!("--max-height must be positive");
    }
    let img = image::ImageReader::open(path)
        .with_context(|| format!("cannot open {}", path.display()))?
        .with_guessed_format()?
        .decode()
        .with_context(|| format!("cannot decode {} (PNG or PGM expected)", path.display()))?;
    let luma = img.to_luma16();
    let (w, h) = (luma.width() as usize, luma.height() as usize);
    let z: Vec<f32> = luma
        .pixels()
        .map(|p| f32::from(p.0[0]) / 65535.0 * max_height)
        .collect();
    let t = HostTerrain {
        width: w,
        height: h,
        spacing,
        z,
    };
    t.view()?;
    Ok(t)
}

fn generated(exp: &Experiment, seed: u64) -> anyhow::Result<HostTerrain> {
    let (w, h) = exp.samples;
    let map = Box::new(
        Heightmap::<1024>::peaks(w, h, 1.0, &Peaks::seed_001(), seed)
            .map_err(|e| anyhow::anyhow!("terrain: {e}"))?,
    );
    Ok(HostTerrain {
        width: w,
        height: h,
        spacing: 1.0,
        z: map.view().samples().to_vec(),
    })
}

/// One run's result.
#[derive(Debug, Clone, Serialize)]
pub struct RunResult {
    /// Algorithm.
    pub algorithm: String,
    /// Run index.
    pub run: u32,
    /// Seed.
    pub seed: u64,
    /// Whether the best path keeps out of every obstacle (obstacle term 0).
    pub valid: bool,
    /// Objective parts of the best.
    pub best: Evaluation,
    /// Evaluations spent.
    pub evaluations: u64,
    /// Wall time (s).
    pub seconds: f64,
    /// First iteration reaching the best.
    pub best_iteration: u32,
    /// The best decision vector.
    pub x: Vec<f32>,
    /// The ground path (waypoints draped over the terrain), `[x, y, z]` km.
    pub path: Vec<[f32; 3]>,
    /// Best `F` after each iteration.
    #[serde(skip)]
    pub history: Vec<f32>,
}

/// Statistics of one quantity over the valid runs.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Stats {
    /// Minimum.
    pub min: f64,
    /// Maximum.
    pub max: f64,
    /// `max - min`.
    pub range: f64,
    /// Population standard deviation.
    pub std: f64,
    /// Mean.
    pub mean: f64,
}

impl Stats {
    fn of(values: &[f64]) -> Self {
        let (mean, std) = mean_std(values);
        let min = values.iter().copied().fold(f64::INFINITY, f64::min);
        let max = values.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        let (min, max) = if values.is_empty() {
            (f64::NAN, f64::NAN)
        } else {
            (min, max)
        };
        Stats {
            min,
            max,
            range: max - min,
            std,
            mean,
        }
    }

    fn row(&self, name: &str, digits: usize) -> Vec<String> {
        vec![
            name.to_string(),
            fmt(self.min, digits),
            fmt(self.max, digits),
            fmt(self.range, digits),
            fmt(self.std, digits),
            fmt(self.mean, digits),
        ]
    }
}

/// Seed 001's tables 2 to 7: per experiment, `[length, energy]` rows of
/// `[min, max, range, std, mean]` for ACO, PSO, GWO, SSA, SSA-GWO.
pub const PAPER: [[[[f64; 5]; 5]; 2]; 3] = [
    [
        [
            [149.6663, 191.4581, 41.7918, 15.5970, 168.9484],
            [144.7143, 189.8517, 45.1374, 17.7630, 167.0636],
            [140.8393, 184.3135, 43.4742, 15.7357, 159.8855],
            [141.8269, 214.2755, 72.4486, 24.3029, 171.5948],
            [134.5713, 176.9491, 42.3778, 15.0146, 158.0545],
        ],
        [
            [972.8310, 1244.4777, 271.6467, 91.7885, 1062.2138],
            [940.6430, 1234.0360, 293.3930, 102.2331, 1052.2307],
            [915.4555, 1198.0377, 282.5822, 92.5851, 1009.3028],
            [921.8749, 1392.7908, 470.9159, 122.3257, 1077.1887],
            [874.3175, 1150.1691, 275.8516, 88.5135, 998.3213],
        ],
    ],
    [
        [
            [141.7895, 195.5316, 53.7421, 16.5302, 161.3494],
            [145.2387, 190.0627, 44.8240, 16.2062, 161.6348],
            [140.6405, 185.5469, 44.9064, 14.7627, 151.5492],
            [143.6147, 200.1423, 56.5276, 17.5925, 172.1767],
            [138.6868, 187.1938, 48.5070, 15.2193, 157.0285],
        ],
        [
            [921.6318, 1270.9554, 349.3236, 103.7387, 1066.7411],
            [944.0516, 1235.4075, 291.3559, 101.9120, 1067.7798],
            [914.1632, 1206.0548, 291.8916, 98.9760, 1002.6026],
            [933.4955, 1300.9250, 367.4295, 109.1228, 1130.1016],
            [901.4642, 1216.7597, 315.2955, 96.1434, 1038.6963],
        ],
    ],
    [
        [
            [180.7574, 265.1705, 84.4131, 26.8453, 218.1328],
            [177.7292, 282.8334, 105.1042, 32.4006, 234.6666],
            [176.8882, 263.0176, 86.1294, 26.9033, 217.2953],
            [174.5129, 277.0057, 102.4928, 29.5361, 223.2483],
            [169.4212, 266.9059, 97.4847, 26.2822, 216.0278],
        ],
        [
            [1174.9231, 1723.6082, 548.6851, 176.1745, 1483.8426],
            [1155.2398, 1838.4171, 683.1773, 205.1630, 1586.7851],
            [1149.7733, 1709.6144, 559.8411, 176.5195, 1479.4307],
            [1134.3338, 1800.5370, 666.2032, 191.5314, 1517.6665],
            [1101.2378, 1734.8883, 633.6505, 172.5509, 1470.6071],
        ],
    ],
];

/// Runs `host-sim terrain`.
pub fn run(args: &TerrainArgs) -> anyhow::Result<()> {
    let mut exp = Experiment::new(args.experiment)?;
    if let Some(p) = args.planes {
        exp.planes = p;
    }
    let terrain = match &args.heightmap {
        Some(path) => load_heightmap(path, args.spacing, args.max_height)?,
        None => generated(&exp, args.terrain_seed.unwrap_or(exp.terrain_seed))?,
    };
    let view = terrain.view()?;
    // Obstacles stand on the terrain.
    for o in &mut exp.obstacles {
        o.base = view.height_clamped(o.x, o.y);
    }
    let mode = if args.literal {
        HeightMode::Free
    } else {
        HeightMode::Terrain
    };
    let encoding = PlaneEncoding::new(&view, exp.start, exp.goal, exp.planes, mode)
        .map_err(|e| anyhow::anyhow!("encoding: {e}"))?;
    let objective = TerrainObjective::new(
        view,
        &exp.obstacles,
        encoding.clone(),
        ObjectiveParams::seed_001(),
    )
    .map_err(|e| anyhow::anyhow!("objective: {e}"))?;
    let bounds: Bounds<D> = encoding
        .bounds_box()
        .map_err(|e| anyhow::anyhow!("bounds: {e}"))?;
    if args.population == 0 || args.population > N {
        bail!("--population must be 1..={N}");
    }
    if args.iterations == 0 || args.runs == 0 {
        bail!("--iterations and --runs must be at least 1");
    }
    let out = args
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("bench-out/terrain/exp{}", exp.number)));
    std::fs::create_dir_all(&out).with_context(|| format!("cannot create {}", out.display()))?;
    if args.bench {
        return bench(args, &objective, &bounds, &out);
    }

    let algorithms: Vec<&str> = ALGORITHMS
        .iter()
        .copied()
        .filter(|a| !(args.literal && *a == "ACO"))
        .collect();
    let bar = progress(
        u64::from(args.runs) * algorithms.len() as u64,
        &format!("terrain exp {}", exp.number),
    );
    let mut results: Vec<RunResult> = Vec::new();
    for run in 0..args.runs {
        for (a, name) in algorithms.iter().enumerate() {
            let seed = run_seed(args.seed, run, a);
            results.push(one_run(name, run, seed, args, &objective, &bounds)?);
            bar.inc(1);
        }
    }
    bar.finish_and_clear();

    // Tables.
    let header = ["algorithm", "min", "max", "range", "std", "mean"];
    let (tl, te) = match exp.number {
        1 => (2, 3),
        2 => (4, 5),
        _ => (6, 7),
    };
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
                ours.push(s.row(name, 4));
                let mut row = vec![format!("{}", table), "ours".to_string()];
                row.extend(s.row(name, 4));
                csv.push(row);
            }
            let p = PAPER[usize::from(exp.number - 1)][q][a];
            let s = Stats {
                min: p[0],
                max: p[1],
                range: p[2],
                std: p[3],
                mean: p[4],
            };
            paper.push(s.row(name, 4));
            let mut row = vec![format!("{}", table), "paper".to_string()];
            row.extend(s.row(name, 4));
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
            &format!("Seed 001 table {table} (paper's map and units)"),
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
            runs: args.runs,
            iterations: args.iterations,
            population: args.population,
            objective: *objective.params(),
            terrain: &terrain,
            results: &results,
        },
    )?;
    pictures(&exp, &terrain, &algorithms, &results, &out)?;
    eprintln!("wrote {}", out.display());
    Ok(())
}

fn run_seed(seed: u64, run: u32, algorithm: usize) -> u64 {
    seed.wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(u64::from(run) * 16 + algorithm as u64)
}

fn one_run(
    name: &str,
    run: u32,
    seed: u64,
    args: &TerrainArgs,
    objective: &TerrainObjective<'_>,
    bounds: &Bounds<D>,
) -> anyhow::Result<RunResult> {
    let settings = Settings {
        population: args.population,
        iterations: args.iterations,
        seed,
    };
    let mut history = vec![0.0f32; args.iterations as usize];
    let t0 = Instant::now();
    let (x, evaluations, best_iteration) = match name {
        "ACO" => {
            let mut aco = Box::new(Aco::<MAX_PLANES, 32>::new());
            let params = AcoParams {
                ants: args.population,
                iterations: args.iterations,
                seed,
                ..AcoParams::seed_001()
            };
            let r = aco
                .run(objective, &params, &mut history)
                .map_err(|e| anyhow::anyhow!("ACO: {e}"))?;
            (
                aco.best_position().to_vec(),
                r.evaluations,
                r.best_iteration,
            )
        }
        "PSO" => drive(
            Box::new(Pso::<N, D>::new(settings, bounds, PsoParams::seed_001()).map_err(oe)?),
            objective,
            &mut history,
        )?,
        "GWO" => drive(
            Box::new(Gwo::<N, D>::new(settings, bounds, GwoParams::gwo()).map_err(oe)?),
            objective,
            &mut history,
        )?,
        "SSA" => drive(
            Box::new(Ssa::<N, D>::new(settings, bounds, SsaParams::seed_001()).map_err(oe)?),
            objective,
            &mut history,
        )?,
        "SSA-GWO" => drive(
            Box::new(SsaGwo::<N, D>::new(settings, bounds, SsaGwoParams::seed_001()).map_err(oe)?),
            objective,
            &mut history,
        )?,
        other => bail!("unknown algorithm {other}"),
    };
    let seconds = t0.elapsed().as_secs_f64();
    let best = objective.evaluate(&x);
    let mut path = vec![Point3::default(); (MAX_PLANES + 1) * 16 + 1];
    let n = objective
        .ground_path(&x, &mut path)
        .map_err(|e| anyhow::anyhow!("path: {e}"))?;
    Ok(RunResult {
        algorithm: name.to_string(),
        run,
        seed,
        valid: best.obstacle == 0.0 && best.cost.is_finite(),
        best,
        evaluations,
        seconds,
        best_iteration,
        x,
        path: path[..n].iter().map(|p| [p.x, p.y, p.z]).collect(),
        history,
    })
}

fn oe(e: planner_core::optim::OptimError) -> anyhow::Error {
    anyhow::anyhow!("optimizer: {e}")
}

// Boxed by the callers: a population of 100 x D floats is too big to pass by value.
#[allow(clippy::boxed_local)]
fn drive<O: Optimizer>(
    mut opt: Box<O>,
    objective: &TerrainObjective<'_>,
    history: &mut [f32],
) -> anyhow::Result<(Vec<f32>, u64, u32)> {
    let mut obj = objective.clone();
    let r = opt
        .run(&mut obj, None, &Stop::default(), history)
        .map_err(oe)?;
    Ok((
        opt.best_position().to_vec(),
        r.evaluations,
        r.best_iteration,
    ))
}

fn pictures(
    exp: &Experiment,
    terrain: &HostTerrain,
    algorithms: &[&str],
    results: &[RunResult],
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
                v[v.len() / 2]
            })
            .collect();
        curves.push((name.to_string(), median));
    }
    let title = format!(
        "Seed 001 experiment {}: best path of each algorithm over {} x {} km terrain (y down)",
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
            "Seed 001 experiment {}: median best F over runs per iteration",
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
    objective: &TerrainObjective<'_>,
    bounds: &Bounds<D>,
    out: &Path,
) -> anyhow::Result<()> {
    // Single evaluations on uniform random points of the box.
    let dim = bounds.dim();
    let count = 200_000usize;
    let mut rng = Random::new(args.seed);
    let points: Vec<f32> = (0..count * dim.max(1))
        .map(|i| {
            let j = i % dim;
            rng.range(bounds.lower()[j], bounds.upper()[j])
        })
        .collect();
    let t0 = Instant::now();
    let mut acc = 0.0f32;
    for x in points.chunks(dim) {
        acc += std::hint::black_box(objective.evaluate(std::hint::black_box(x))).cost;
    }
    let per_eval_ns = t0.elapsed().as_secs_f64() * 1e9 / count as f64;
    std::hint::black_box(acc);
    // Whole SSA-GWO runs.
    let runs = args.runs.clamp(1, 10);
    let mut times = Vec::new();
    let mut evals = 0u64;
    let bar = progress(u64::from(runs), "ssa-gwo bench");
    for run in 0..runs {
        let settings = Settings {
            population: args.population,
            iterations: args.iterations,
            seed: run_seed(args.seed, run, 4),
        };
        let opt =
            Box::new(SsaGwo::<N, D>::new(settings, bounds, SsaGwoParams::seed_001()).map_err(oe)?);
        let t = Instant::now();
        let (_, e, _) = drive(opt, objective, &mut [])?;
        times.push(t.elapsed().as_secs_f64());
        evals = e;
        bar.inc(1);
    }
    bar.finish_and_clear();
    let (mean, std) = mean_std(&times);
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
        },
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sixteen_bit_png_and_pgm_import() {
        let dir = std::env::temp_dir().join(format!("terrain-import-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (w, h) = (5u32, 3u32);
        let vals: Vec<u16> = (0..w * h).map(|i| (i * 4000) as u16).collect();
        // PNG, 16-bit grey.
        let png_path = dir.join("dem.png");
        {
            let f = std::fs::File::create(&png_path).unwrap();
            let mut enc = png::Encoder::new(std::io::BufWriter::new(f), w, h);
            enc.set_color(png::ColorType::Grayscale);
            enc.set_depth(png::BitDepth::Sixteen);
            let mut wr = enc.write_header().unwrap();
            let bytes: Vec<u8> = vals.iter().flat_map(|v| v.to_be_bytes()).collect();
            wr.write_image_data(&bytes).unwrap();
        }
        // PGM, binary, maxval 65535 (big endian).
        let pgm_path = dir.join("dem.pgm");
        let mut pgm = format!("P5\n{w} {h}\n65535\n").into_bytes();
        pgm.extend(vals.iter().flat_map(|v| v.to_be_bytes()));
        std::fs::write(&pgm_path, pgm).unwrap();
        for p in [&png_path, &pgm_path] {
            let t = load_heightmap(p, 0.5, 2.0).unwrap();
            assert_eq!((t.width, t.height), (5, 3));
            for (z, v) in t.z.iter().zip(&vals) {
                assert!((z - f32::from(*v) / 65535.0 * 2.0).abs() < 1e-6);
            }
            let view = t.view().unwrap();
            assert_eq!(view.extent(), (2.0, 1.0));
            // Sample (1, 2) = 4000 * 11 at (0.5 km, 1 km).
            assert!((view.height(0.5, 1.0).unwrap() - 44000.0 / 65535.0 * 2.0).abs() < 1e-5);
        }
        assert!(load_heightmap(&dir.join("missing.png"), 1.0, 2.0).is_err());
        std::fs::write(dir.join("junk.pgm"), b"P5\n2 2\n").unwrap();
        assert!(load_heightmap(&dir.join("junk.pgm"), 1.0, 2.0).is_err());
        let _ = std::fs::remove_dir_all(&dir);
    }

    #[test]
    fn experiments_are_consistent() {
        for n in 1..=3 {
            let e = Experiment::new(n).unwrap();
            let t = generated(&e, e.terrain_seed).unwrap();
            let v = t.view().unwrap();
            assert!(v.contains(e.start.0, e.start.1) && v.contains(e.goal.0, e.goal.1));
            for o in &e.obstacles {
                assert!(v.contains(o.x, o.y));
            }
        }
        assert!(Experiment::new(4).is_err());
    }
}

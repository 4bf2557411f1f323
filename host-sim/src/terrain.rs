//! 3D terrain planning on the host (`Zhu2025Orchard`, the SSA-GWO orchard terrain paper of
//! `docs/references.md`; SPEC section 4): the paper's three experiments, their terrains
//! (generated, or imported from a DEM), the five algorithms' runs, their statistics beside the
//! paper's tables 2 to 7, and a timing of the objective. `host-sim terrain` is the command over
//! this module (arguments, tables, files and pictures).
//!
//! Units are kilometres everywhere (horizontal and vertical). The three experiments:
//! 1. a seeded 21 x 21 km "sum of peaks" terrain (22 x 22 samples, 1 km apart), start `(1, 15)`,
//!    goal `(21, 8)`, no obstacles (tables 2 and 3);
//! 2. the same terrain with two cylinders of radius 1 km at `(11, 16)` and `(12, 4)` (tables 4
//!    and 5);
//! 3. a 30 x 30 km terrain, start `(1, 13)`, goal `(30, 11)`, cylinders of radius 1.5 and 2 km
//!    and a cone of radius 3 km placed across the straight line (ours; tables 6 and 7).
//!
//! ACO, PSO (`w = 0.7`), GWO, SSA and SSA-GWO (`ST = 0.6, PD = 0.4, SD = 0.2`), population up
//! to [`MAX_POPULATION`]; per algorithm the min, max, range, std (population) and mean of the
//! best path's length and energy over the runs whose best path is valid ([`Stats`]).
//!
//! ```no_run
//! use host_sim::terrain::{self, Experiment, RunOptions};
//! use planner_core::terrain::planes::HeightMode;
//!
//! let mut exp = Experiment::new(2)?;
//! let terrain = exp.generate_terrain(exp.terrain_seed)?;
//! let view = terrain.view()?;
//! exp.place_obstacles(&view);
//! let objective = terrain::objective(&exp, view, HeightMode::Terrain)?;
//! let bounds = terrain::search_box(&objective)?;
//! let options = RunOptions { runs: 3, seed: 1, population: 100, iterations: 500, shift: 0.0 };
//! let algorithms = terrain::algorithms(HeightMode::Terrain);
//! let results = terrain::run_experiment(&algorithms, &options, &objective, &bounds, &mut || {})?;
//! let lengths: Vec<f64> = results
//!     .iter()
//!     .filter(|r| r.algorithm == "SSA-GWO" && r.valid)
//!     .map(|r| f64::from(r.best.length))
//!     .collect();
//! println!("{:?}", terrain::Stats::of(&lengths));
//! # Ok::<(), anyhow::Error>(())
//! ```

use crate::stats::mean_std;
use anyhow::{Context, bail};
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
use std::path::Path;
use std::time::Instant;

/// Population capacity.
pub const MAX_POPULATION: usize = 100;
/// Dimension capacity (the free-height mode needs `2n`).
pub const MAX_DIM: usize = 64;

/// The five algorithms, in the paper's order.
pub const ALGORITHMS: [&str; 5] = ["ACO", "PSO", "GWO", "SSA", "SSA-GWO"];

/// The algorithms that run in `mode`, in the paper's order: all five, less ACO in the free
/// (literal) mode, where waypoint heights are decision variables too.
pub fn algorithms(mode: HeightMode) -> Vec<&'static str> {
    ALGORITHMS
        .iter()
        .copied()
        .filter(|a| !(mode == HeightMode::Free && *a == "ACO"))
        .collect()
}

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

    /// The paper's tables of this experiment: `(path length, energy)`.
    pub fn tables(&self) -> (u8, u8) {
        match self.number {
            1 => (2, 3),
            2 => (4, 5),
            _ => (6, 7),
        }
    }

    /// The experiment's generated terrain ("sum of peaks", 1 km spacing) from `seed`.
    pub fn generate_terrain(&self, seed: u64) -> anyhow::Result<HostTerrain> {
        let (w, h) = self.samples;
        let map = Box::new(
            Heightmap::<1024>::peaks(w, h, 1.0, &Peaks::zhu2025_orchard(), seed)
                .map_err(|e| anyhow::anyhow!("terrain: {e}"))?,
        );
        Ok(HostTerrain {
            width: w,
            height: h,
            spacing: 1.0,
            z: map.view().samples().to_vec(),
        })
    }

    /// Stands every obstacle on the terrain (its foot at the ground height of its axis).
    pub fn place_obstacles(&mut self, view: &TerrainView<'_>) {
        for o in &mut self.obstacles {
            o.base = view.height_clamped(o.x, o.y);
        }
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

/// The objective of experiment `exp` on `view` (its obstacles already placed, see
/// [`Experiment::place_obstacles`]): `exp.planes` interior planes, heights as `mode` says,
/// the paper's weights.
pub fn objective<'a>(
    exp: &'a Experiment,
    view: TerrainView<'a>,
    mode: HeightMode,
) -> anyhow::Result<TerrainObjective<'a>> {
    let encoding = PlaneEncoding::new(&view, exp.start, exp.goal, exp.planes, mode)
        .map_err(|e| anyhow::anyhow!("encoding: {e}"))?;
    TerrainObjective::new(
        view,
        &exp.obstacles,
        encoding.clone(),
        ObjectiveParams::zhu2025_orchard(),
    )
    .map_err(|e| anyhow::anyhow!("objective: {e}"))
}

/// The continuous optimizers' search box of `objective` (the encoding's box).
pub fn search_box(objective: &TerrainObjective<'_>) -> anyhow::Result<Bounds<MAX_DIM>> {
    objective
        .encoding()
        .bounds_box()
        .map_err(|e| anyhow::anyhow!("bounds: {e}"))
}

/// `bounds` with `shift` added to the lateral offsets (the first `planes` entries; see
/// [`RunOptions::shift`]); `bounds` itself when `shift` is 0.
pub fn shift_box(
    bounds: Bounds<MAX_DIM>,
    planes: usize,
    shift: f32,
) -> anyhow::Result<Bounds<MAX_DIM>> {
    if shift == 0.0 {
        return Ok(bounds);
    }
    let lo: Vec<f32> = shifted(bounds.lower(), planes, shift);
    let hi: Vec<f32> = shifted(bounds.upper(), planes, shift);
    Bounds::from_slices(&lo, &hi).map_err(|e| anyhow::anyhow!("bounds: {e}"))
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
    /// The statistics of `values` (all `NaN` when there are none).
    pub fn of(values: &[f64]) -> Self {
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

    /// A row of [`PAPER`]: `[min, max, range, std, mean]`.
    pub fn from_row(p: [f64; 5]) -> Self {
        Stats {
            min: p[0],
            max: p[1],
            range: p[2],
            std: p[3],
            mean: p[4],
        }
    }
}

/// `Zhu2025Orchard`'s tables 2 to 7: per experiment, `[length, energy]` rows of
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

/// How the algorithms run.
#[derive(Debug, Clone, Copy)]
pub struct RunOptions {
    /// Runs per algorithm.
    pub runs: u32,
    /// Seed of the runs: run `k` of algorithm `a` uses [`run_seed`]`(seed, k, a)`.
    pub seed: u64,
    /// Population (ants for ACO), at most [`MAX_POPULATION`].
    pub population: usize,
    /// Iterations per run.
    pub iterations: u32,
    /// Diagnostic: the continuous optimizers search `v = t + shift` (km) instead of each
    /// lateral offset `t`, in the box shifted alike ([`shift_box`]), so that the box's origin
    /// is no longer the straight line. ACO is unaffected.
    pub shift: f32,
}

/// The seed of run `run` of the algorithm at index `algorithm`.
pub fn run_seed(seed: u64, run: u32, algorithm: usize) -> u64 {
    seed.wrapping_mul(0x9E37_79B9_7F4A_7C15)
        .wrapping_add(u64::from(run) * 16 + algorithm as u64)
}

/// Runs `options.runs` runs of each of `algorithms` (names from [`ALGORITHMS`]; the index in
/// `algorithms` seeds the runs), run by run; `on_run` is called after each.
pub fn run_experiment(
    algorithms: &[&str],
    options: &RunOptions,
    objective: &TerrainObjective<'_>,
    bounds: &Bounds<MAX_DIM>,
    on_run: &mut dyn FnMut(),
) -> anyhow::Result<Vec<RunResult>> {
    let mut results: Vec<RunResult> = Vec::new();
    for run in 0..options.runs {
        for (a, name) in algorithms.iter().enumerate() {
            let seed = run_seed(options.seed, run, a);
            results.push(run_algorithm(name, run, seed, options, objective, bounds)?);
            on_run();
        }
    }
    Ok(results)
}

/// One run of algorithm `name` with `seed` (`options.runs` is not used).
pub fn run_algorithm(
    name: &str,
    run: u32,
    seed: u64,
    options: &RunOptions,
    objective: &TerrainObjective<'_>,
    bounds: &Bounds<MAX_DIM>,
) -> anyhow::Result<RunResult> {
    const N: usize = MAX_POPULATION;
    const D: usize = MAX_DIM;
    let settings = Settings {
        population: options.population,
        iterations: options.iterations,
        seed,
    };
    let mut history = vec![0.0f32; options.iterations as usize];
    let t0 = Instant::now();
    let (x, evaluations, best_iteration) = match name {
        "ACO" => {
            let mut aco = Box::new(Aco::<MAX_PLANES, 32>::new());
            let params = AcoParams {
                ants: options.population,
                iterations: options.iterations,
                seed,
                ..AcoParams::zhu2025_orchard()
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
            Box::new(Pso::<N, D>::new(settings, bounds, PsoParams::zhu2025_orchard()).map_err(oe)?),
            objective,
            options.shift,
            &mut history,
        )?,
        "GWO" => drive(
            Box::new(Gwo::<N, D>::new(settings, bounds, GwoParams::gwo()).map_err(oe)?),
            objective,
            options.shift,
            &mut history,
        )?,
        "SSA" => drive(
            Box::new(Ssa::<N, D>::new(settings, bounds, SsaParams::zhu2025_orchard()).map_err(oe)?),
            objective,
            options.shift,
            &mut history,
        )?,
        "SSA-GWO" => drive(
            Box::new(
                SsaGwo::<N, D>::new(settings, bounds, SsaGwoParams::zhu2025_orchard())
                    .map_err(oe)?,
            ),
            objective,
            options.shift,
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

/// `v` with `shift` added to its first `planes` entries.
fn shifted(v: &[f32], planes: usize, shift: f32) -> Vec<f32> {
    v.iter()
        .enumerate()
        .map(|(i, x)| if i < planes { x + shift } else { *x })
        .collect()
}

fn oe(e: planner_core::optim::OptimError) -> anyhow::Error {
    anyhow::anyhow!("optimizer: {e}")
}

// Boxed by the callers: a population of 100 x D floats is too big to pass by value.
#[allow(clippy::boxed_local)]
fn drive<O: Optimizer>(
    mut opt: Box<O>,
    objective: &TerrainObjective<'_>,
    shift: f32,
    history: &mut [f32],
) -> anyhow::Result<(Vec<f32>, u64, u32)> {
    const D: usize = MAX_DIM;
    let planes = objective.encoding().planes();
    let r = if shift == 0.0 {
        let mut obj = objective.clone();
        opt.run(&mut obj, None, &Stop::default(), history)
    } else {
        // `v` is searched; the objective sees `t = v - shift` on the lateral offsets.
        let mut obj = |v: &[f32]| {
            let mut t = [0.0f32; D];
            let n = v.len().min(D);
            t[..n].copy_from_slice(&v[..n]);
            for x in t.iter_mut().take(planes.min(n)) {
                *x -= shift;
            }
            objective.evaluate(&t[..n]).cost
        };
        opt.run(&mut obj, None, &Stop::default(), history)
    }
    .map_err(oe)?;
    Ok((
        shifted(opt.best_position(), planes, -shift),
        r.evaluations,
        r.best_iteration,
    ))
}

/// Single evaluations timed by [`time_evaluations`].
#[derive(Debug, Clone, Copy)]
pub struct EvaluationTiming {
    /// Dimension of the search box.
    pub dim: usize,
    /// Time of one evaluation of the objective (ns).
    pub ns_per_evaluation: f64,
    /// Time of the baseline on the same points (ns): decoding the waypoints and summing their
    /// horizontal segment lengths, without draping over the terrain or obstacles.
    pub ns_per_baseline: f64,
}

/// Times single evaluations of `objective` on 200,000 uniform random points of `bounds`
/// (drawn from `seed`), and the baseline on the same points, in the same process: the ratio
/// is less sensitive to the machine's load than the absolute times.
pub fn time_evaluations(
    objective: &TerrainObjective<'_>,
    bounds: &Bounds<MAX_DIM>,
    seed: u64,
) -> EvaluationTiming {
    let dim = bounds.dim();
    let count = 200_000usize;
    let mut rng = Random::new(seed);
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
    // Baseline on the same points, in the same process: decode the waypoints and sum the
    // horizontal (2D) segment lengths, without draping over the terrain or obstacles.
    let t0 = Instant::now();
    let mut acc = 0.0f32;
    let mut wp = [Point3::default(); MAX_PLANES + 2];
    for x in points.chunks(dim) {
        let n = objective
            .waypoints(std::hint::black_box(x), &mut wp)
            .unwrap_or(0);
        acc += wp[..n]
            .windows(2)
            .map(|w| (w[1].x - w[0].x).hypot(w[1].y - w[0].y))
            .sum::<f32>();
    }
    let baseline_ns = t0.elapsed().as_secs_f64() * 1e9 / count as f64;
    std::hint::black_box(acc);
    EvaluationTiming {
        dim,
        ns_per_evaluation: per_eval_ns,
        ns_per_baseline: baseline_ns,
    }
}

/// Whole SSA-GWO runs timed by [`time_runs`].
#[derive(Debug, Clone, Copy)]
pub struct RunTiming {
    /// Mean wall time of a run (s).
    pub seconds_mean: f64,
    /// Population standard deviation of the runs' wall times (s).
    pub seconds_std: f64,
    /// Objective evaluations of a run (the last one's).
    pub evaluations: u64,
}

/// Times `runs` whole SSA-GWO runs (population and iterations from `options`, run `k` seeded
/// with [`run_seed`]`(options.seed, k, 4)`, SSA-GWO's index in [`ALGORITHMS`]); `on_run` is
/// called after each.
pub fn time_runs(
    objective: &TerrainObjective<'_>,
    bounds: &Bounds<MAX_DIM>,
    options: &RunOptions,
    runs: u32,
    on_run: &mut dyn FnMut(),
) -> anyhow::Result<RunTiming> {
    let mut times = Vec::new();
    let mut evals = 0u64;
    for run in 0..runs {
        let settings = Settings {
            population: options.population,
            iterations: options.iterations,
            seed: run_seed(options.seed, run, 4),
        };
        let opt = Box::new(
            SsaGwo::<MAX_POPULATION, MAX_DIM>::new(
                settings,
                bounds,
                SsaGwoParams::zhu2025_orchard(),
            )
            .map_err(oe)?,
        );
        let t = Instant::now();
        let (_, e, _) = drive(opt, objective, 0.0, &mut [])?;
        times.push(t.elapsed().as_secs_f64());
        evals = e;
        on_run();
    }
    let (mean, std) = mean_std(&times);
    Ok(RunTiming {
        seconds_mean: mean,
        seconds_std: std,
        evaluations: evals,
    })
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
            let t = e.generate_terrain(e.terrain_seed).unwrap();
            let v = t.view().unwrap();
            assert!(v.contains(e.start.0, e.start.1) && v.contains(e.goal.0, e.goal.1));
            for o in &e.obstacles {
                assert!(v.contains(o.x, o.y));
            }
        }
        assert!(Experiment::new(4).is_err());
    }
}

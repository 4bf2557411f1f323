//! `host-sim optimize`: any optimizer on a benchmark function, K seeded runs, JSON out.
//!
//! Run `k` (0-based) uses seed `seed + k` (wrapping) for the optimizer and
//! `(seed + k) ^ 0x9E37_79B9_7F4A_7C15` for the noise of `f4`. Times are wall-clock
//! microseconds of `Optimizer::run` alone (initialisation included, process start excluded).
//! `std` in the summary is the sample standard deviation (0 for a single run).

use std::time::Instant;

use anyhow::{Context, anyhow, bail};
use planner_core::optim::any::{AlgorithmKind, AnyOptimizer};
use planner_core::optim::functions::{Benchmark, FunctionKind};
use planner_core::optim::gwo::{Gwo, GwoParams};
use planner_core::optim::hho::{HawkMean, Hho, HhoParams};
use planner_core::optim::{Optimizer, Settings, Stop};
use serde::Serialize;

/// Population capacity on the host.
pub const MAX_POP: usize = 128;
/// Dimension capacity on the host.
pub const MAX_DIM: usize = 128;

/// Arguments of `host-sim optimize`.
#[derive(clap::Args, Debug, Clone)]
pub struct OptimizeArgs {
    /// Function: f1..f11 (Liu2020Igwo table 1; f12 is illegible there) or sphere, rastrigin,
    /// rosenbrock, ackley (shifted by --shift).
    #[arg(long)]
    pub function: String,
    /// Dimension (must match the fixed dimension of f1..f11; default: that, or 30).
    #[arg(long)]
    pub dim: Option<usize>,
    /// Shift of the optimum of sphere/rastrigin/rosenbrock/ackley: it moves to (S, ..., S).
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    pub shift: f32,
    /// Algorithm: hho, tclhho, gwo, tgwo, igwo, ssa, ssagwo, pso, ga.
    #[arg(long)]
    pub algo: String,
    /// Population size (1..=128).
    #[arg(long, default_value_t = 30)]
    pub pop: usize,
    /// Iterations (the horizon T).
    #[arg(long, default_value_t = 500)]
    pub iters: u32,
    /// Number of independent runs.
    #[arg(long, default_value_t = 1)]
    pub runs: u32,
    /// Base seed; run k uses seed + k.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Optional: stop once the best cost is at or below this.
    #[arg(long, allow_negative_numbers = true)]
    pub target: Option<f32>,
    /// Optional: evaluation budget.
    #[arg(long)]
    pub max_evals: Option<u64>,
    /// Optional: stop after this many iterations without improvement.
    #[arg(long)]
    pub stagnation: Option<u32>,
    /// GWO family only: keep a wolf's move only if it improves it (mealpy's OriginalGWO
    /// variant; SPEC's GWO has no greedy selection).
    #[arg(long)]
    pub greedy: bool,
    /// HHO family only: take the hawks' mean `X_m` as one scalar over every coordinate
    /// (mealpy's OriginalHHO reading, for like-for-like comparisons; SPEC and HHO.m take it
    /// per dimension).
    #[arg(long)]
    pub scalar_mean: bool,
}

#[derive(Serialize)]
struct RunOut {
    run: u32,
    seed: u64,
    best_cost: f64,
    evaluations: u64,
    best_iteration: u32,
    iterations: u32,
    time_us: f64,
    stop: &'static str,
}

#[derive(Serialize)]
struct Stats {
    mean: f64,
    std: f64,
    min: f64,
    max: f64,
    median: f64,
}

#[derive(Serialize)]
struct Summary {
    best_cost: Stats,
    evaluations: Stats,
    best_iteration: Stats,
    time_us: Stats,
}

#[derive(Serialize)]
struct Output {
    function: &'static str,
    dim: usize,
    shift: f32,
    optimum: f32,
    algo: &'static str,
    greedy: bool,
    scalar_mean: bool,
    pop: usize,
    iters: u32,
    seed: u64,
    runs: Vec<RunOut>,
    summary: Summary,
}

fn stats(values: &[f64]) -> Stats {
    let n = values.len();
    if n == 0 {
        return Stats {
            mean: f64::NAN,
            std: f64::NAN,
            min: f64::NAN,
            max: f64::NAN,
            median: f64::NAN,
        };
    }
    let mean = values.iter().sum::<f64>() / n as f64;
    let var = if n > 1 {
        values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1) as f64
    } else {
        0.0
    };
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let median = if n % 2 == 1 {
        sorted[n / 2]
    } else {
        (sorted[n / 2 - 1] + sorted[n / 2]) / 2.0
    };
    Stats {
        mean,
        std: var.sqrt(),
        min: sorted[0],
        max: sorted[n - 1],
        median,
    }
}

/// Runs the command and prints its JSON to stdout.
pub fn run(args: &OptimizeArgs) -> anyhow::Result<()> {
    let out = execute(args)?;
    println!("{}", serde_json::to_string_pretty(&out)?);
    Ok(())
}

fn execute(args: &OptimizeArgs) -> anyhow::Result<Output> {
    let kind: FunctionKind = args.function.parse().map_err(|_| {
        if args.function == "f12" {
            anyhow!("function `f12`: Liu2020Igwo's table 1 lost its definition (only its optimum 2.471 is printed)")
        } else {
            anyhow!("unknown function `{}` (f1..f11, sphere, rastrigin, rosenbrock, ackley)", args.function)
        }
    })?;
    let algo: AlgorithmKind = args.algo.parse().map_err(|_| {
        anyhow!(
            "unknown algorithm `{}` (hho, tclhho, gwo, tgwo, igwo, ssa, ssagwo, pso, ga)",
            args.algo
        )
    })?;
    let dim = args.dim.or(kind.fixed_dim()).unwrap_or(30);
    if dim > MAX_DIM {
        bail!("dimension {dim} above the host capacity {MAX_DIM}");
    }
    if args.pop > MAX_POP {
        bail!("population {} above the host capacity {MAX_POP}", args.pop);
    }
    if args.runs == 0 {
        bail!("--runs must be at least 1");
    }
    let stop = Stop {
        max_iterations: None,
        max_evaluations: args.max_evals,
        target_cost: args.target,
        stagnation: args.stagnation,
    };
    let mut runs = Vec::with_capacity(args.runs as usize);
    for k in 0..args.runs {
        let seed = args.seed.wrapping_add(u64::from(k));
        let mut objective = Benchmark::new(kind, dim, args.shift, seed ^ 0x9E37_79B9_7F4A_7C15)
            .map_err(|e| {
                anyhow!(
                    "function `{}` at dimension {dim}, shift {}: {e}",
                    kind.name(),
                    args.shift
                )
            })?;
        let bounds = objective
            .bounds::<MAX_DIM>()
            .map_err(|e| anyhow!("bounds: {e}"))?;
        let settings = Settings {
            population: args.pop,
            iterations: args.iters,
            seed,
        };
        let built = if args.scalar_mean {
            let base = match algo {
                AlgorithmKind::Hho => HhoParams::hho(),
                AlgorithmKind::Tclhho => HhoParams::tclhho(),
                _ => bail!("--scalar-mean applies to hho and tclhho only"),
            };
            if args.greedy {
                bail!("--greedy and --scalar-mean do not combine");
            }
            Hho::new(
                settings,
                &bounds,
                HhoParams {
                    mean: HawkMean::Scalar,
                    ..base
                },
            )
            .map(AnyOptimizer::Hho)
        } else if args.greedy {
            let base = match algo {
                AlgorithmKind::Gwo => GwoParams::gwo(),
                AlgorithmKind::Tgwo => GwoParams::tgwo(),
                AlgorithmKind::Igwo => GwoParams::igwo(),
                _ => bail!("--greedy applies to gwo, tgwo and igwo only"),
            };
            Gwo::new(
                settings,
                &bounds,
                GwoParams {
                    greedy: true,
                    ..base
                },
            )
            .map(AnyOptimizer::Gwo)
        } else {
            AnyOptimizer::new(algo, settings, &bounds)
        };
        let mut opt: Box<AnyOptimizer<MAX_POP, MAX_DIM>> =
            Box::new(built.map_err(|e| anyhow!("algorithm `{}`: {e}", algo.name()))?);
        let start = Instant::now();
        let report = opt
            .run(&mut objective, None, &stop, &mut [])
            .map_err(|e| anyhow!("run {k}: {e}"))
            .context("optimize")?;
        let time_us = start.elapsed().as_secs_f64() * 1e6;
        runs.push(RunOut {
            run: k,
            seed,
            best_cost: f64::from(report.best_cost),
            evaluations: report.evaluations,
            best_iteration: report.best_iteration,
            iterations: report.iterations,
            time_us,
            stop: report.stop.name(),
        });
    }
    let col = |f: fn(&RunOut) -> f64| stats(&runs.iter().map(f).collect::<Vec<_>>());
    let summary = Summary {
        best_cost: col(|r| r.best_cost),
        evaluations: col(|r| r.evaluations as f64),
        best_iteration: col(|r| f64::from(r.best_iteration)),
        time_us: col(|r| r.time_us),
    };
    Ok(Output {
        function: kind.name(),
        dim,
        shift: args.shift,
        optimum: kind.optimum(),
        algo: algo.name(),
        greedy: args.greedy,
        scalar_mean: args.scalar_mean,
        pop: args.pop,
        iters: args.iters,
        seed: args.seed,
        runs,
        summary,
    })
}

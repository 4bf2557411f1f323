//! `host-sim bench paper`: `Lei2024Warehouse`'s tables 2 (sparse maps) and 3 (warehouse maps)
//! and `Liu2020Igwo`'s table 3 (20 x 20 lab), on the project's versions of the papers' maps
//! (`planner_core::maps`; the papers print theirs only as figures, so compare shapes, not
//! digits). Table ids keep the seed numbers of the table atop `docs/references.md`, as results
//! files and scripts match them: `seed000-table2` and `seed000-table3` are `Lei2024Warehouse`'s,
//! `seed003-table3` is `Liu2020Igwo`'s.
//!
//! `Lei2024Warehouse`: TCLHHO, HHO, TGWO, GWO with the column encoding (the paper's own, no
//! pruning) and the ant colony, population 30, 500 iterations, `--runs` runs each; metrics
//! `L_mean`, `P_mean`, `S` (std of `L`), `T_mean`, `I_mean` over the runs that found a valid
//! path, and the success rate (a run whose best is infeasible is the paper's "—").
//! `Liu2020Igwo`: IGWO, GWO, PSO, GA with the 8-connected walk encoding.

use super::{fmt, mean_std, print_table, progress, write_csv, write_json};
use anyhow::Context;
use planner_core::encoding::walk::CornerRule;
use planner_core::geometry::Cell;
use planner_core::grid::{GridBuf, words_for};
use planner_core::maps::{MapKind, PaperMap, lab_20x20, lei2024_warehouse};
use planner_core::optim::any::AlgorithmKind;
use planner_core::path::{Path, PathView};
use planner_core::planner::aco::AcoParams;
use planner_core::planner::owned::{HostPlanner, PlanChoice};
use planner_core::planner::{EncodingKind, PlanOptions, PlanParams, PlannerKind};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `host-sim bench paper`.
#[derive(clap::Args, Debug)]
pub struct PaperArgs {
    /// Runs per algorithm and map (the papers use 30).
    #[arg(long, default_value_t = 30)]
    pub runs: u32,
    /// Iterations per run (the papers use 500).
    #[arg(long, default_value_t = 500)]
    pub iters: u32,
    /// Seed of the first run; run `k` uses `seed + k`.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Liu2020Igwo with its literal corner rule (a diagonal is forbidden only when both side
    /// cells are blocked) instead of SPEC's.
    #[arg(long)]
    pub loose_corners: bool,
    /// Output folder for JSON, CSV and the maps.
    #[arg(long, default_value = "bench-out/paper")]
    pub out: PathBuf,
}

/// One run.
#[derive(Serialize, Clone)]
pub struct Run {
    /// Table id: `seed000-table2`, `seed000-table3` (`Lei2024Warehouse`) or `seed003-table3`
    /// (`Liu2020Igwo`).
    pub table: String,
    /// Map name.
    pub map: String,
    /// Planner name.
    pub algo: String,
    /// Seed.
    pub seed: u64,
    /// Whether a valid path was found.
    pub success: bool,
    /// Path length.
    pub length: f64,
    /// Turns.
    pub turns: usize,
    /// Wall time in seconds.
    pub time_s: f64,
    /// First iteration reaching the final best.
    pub best_iteration: u32,
    /// Objective evaluations.
    pub evaluations: u64,
    /// Best cost per iteration.
    pub history: Vec<f32>,
    /// The path (cell units), empty on failure.
    pub path: Vec<[f32; 2]>,
}

/// Aggregates of one (map, algorithm) cell of a table.
#[derive(Serialize, Clone)]
pub struct Row {
    /// Table.
    pub table: String,
    /// Map name.
    pub map: String,
    /// Planner.
    pub algo: String,
    /// Mean length over successful runs.
    pub l_mean: f64,
    /// Best length.
    pub l_best: f64,
    /// Mean turns.
    pub p_mean: f64,
    /// Standard deviation of the length.
    pub s: f64,
    /// Mean time (s).
    pub t_mean: f64,
    /// Mean first iteration of the final best.
    pub i_mean: f64,
    /// Successful runs / runs.
    pub success_rate: f64,
}

fn to_host<const W: usize>(m: &PaperMap<W>) -> GridBuf {
    GridBuf::from_view(m.grid.view())
}

struct Case {
    table: &'static str,
    name: String,
    grid: GridBuf,
    start: Cell,
    goal: Cell,
}

fn cases() -> anyhow::Result<(Vec<Case>, Case)> {
    let mut warehouse_cases = Vec::new();
    for (table, kind) in [
        ("seed000-table2", MapKind::Sparse),
        ("seed000-table3", MapKind::Warehouse),
    ] {
        for size in [10, 30, 40] {
            let m = lei2024_warehouse::<{ words_for(40, 40) }>(kind, size)
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
            warehouse_cases.push(Case {
                table,
                name: format!("{}-{size}x{size}", kind.name()),
                grid: to_host(&m),
                start: m.start,
                goal: m.goal,
            });
        }
    }
    let lab = lab_20x20::<{ words_for(20, 20) }>().map_err(|e| anyhow::anyhow!("{e:?}"))?;
    let lab_case = Case {
        table: "seed003-table3",
        name: "lab-20x20".into(),
        grid: to_host(&lab),
        start: lab.start,
        goal: lab.goal,
    };
    Ok((warehouse_cases, lab_case))
}

/// Runs `host-sim bench paper`.
pub fn run(args: &PaperArgs) -> anyhow::Result<()> {
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let (warehouse_cases, lab) = cases()?;
    let hho_family = [
        PlannerKind::Swarm(AlgorithmKind::Tclhho),
        PlannerKind::Swarm(AlgorithmKind::Hho),
        PlannerKind::Swarm(AlgorithmKind::Tgwo),
        PlannerKind::Swarm(AlgorithmKind::Gwo),
        PlannerKind::Aco,
    ];
    let gwo_family = [
        PlannerKind::Swarm(AlgorithmKind::Igwo),
        PlannerKind::Swarm(AlgorithmKind::Gwo),
        PlannerKind::Swarm(AlgorithmKind::Pso),
        PlannerKind::Swarm(AlgorithmKind::Ga),
    ];
    let total =
        (warehouse_cases.len() * hho_family.len() + gwo_family.len()) as u64 * args.runs as u64;
    let bar = progress(total, "paper tables");
    let mut runs = Vec::new();
    for case in &warehouse_cases {
        for kind in hho_family {
            let params = PlanParams {
                encoding: EncodingKind::Column,
                prune: false,
                iterations: args.iters,
                ..PlanParams::new(AlgorithmKind::Tclhho)
            };
            let aco = AcoParams {
                iterations: args.iters,
                prune: false,
                ..AcoParams::default()
            };
            runs.extend(run_case(case, kind, &params, &aco, args, &bar)?);
        }
    }
    let rule = if args.loose_corners {
        CornerRule::Loose
    } else {
        CornerRule::Strict
    };
    for kind in gwo_family {
        let params = PlanParams {
            encoding: EncodingKind::Walk,
            corner_rule: rule,
            walk_steps: 80,
            prune: false,
            iterations: args.iters,
            ..PlanParams::new(AlgorithmKind::Igwo)
        };
        runs.extend(run_case(
            &lab,
            kind,
            &params,
            &AcoParams::default(),
            args,
            &bar,
        )?);
    }
    bar.finish_and_clear();

    let rows = aggregate(&runs);
    let header = [
        "map",
        "algorithm",
        "L_mean",
        "L_best",
        "P_mean",
        "S",
        "T_mean (s)",
        "I_mean",
        "success",
    ];
    let mut csv = Vec::new();
    for (table, title) in [
        (
            "seed000-table2",
            "Lei2024Warehouse table 2: sparse maps, column encoding (30 runs)",
        ),
        (
            "seed000-table3",
            "Lei2024Warehouse table 3: warehouse maps, column encoding",
        ),
        (
            "seed003-table3",
            "Liu2020Igwo table 3: 20x20 lab, 8-connected walk",
        ),
    ] {
        let cells: Vec<Vec<String>> = rows
            .iter()
            .filter(|r| r.table == table)
            .map(|r| {
                vec![
                    r.map.clone(),
                    r.algo.clone(),
                    fmt(r.l_mean, 4),
                    fmt(r.l_best, 4),
                    fmt(r.p_mean, 1),
                    fmt(r.s, 4),
                    fmt(r.t_mean, 4),
                    fmt(r.i_mean, 0),
                    format!("{:.0}%", 100.0 * r.success_rate),
                ]
            })
            .collect();
        print_table(title, &header, &cells);
        csv.extend(cells.into_iter().map(|mut c| {
            c.insert(0, table.to_string());
            c
        }));
    }
    let mut csv_header = vec!["table"];
    csv_header.extend(header);
    write_csv(&args.out.join("paper.csv"), &csv_header, &csv)?;
    write_json(
        &args.out.join("paper.json"),
        &serde_json::json!({ "rows": rows, "runs": runs }),
    )?;
    for case in warehouse_cases.iter().chain(std::iter::once(&lab)) {
        let mut text = String::new();
        case.grid.write_movingai(&mut text)?;
        std::fs::write(args.out.join(format!("{}.map", case.name)), text)?;
        figures(case, &runs, &args.out)?;
    }
    println!("\nwrote {}", args.out.display());
    Ok(())
}

/// The papers' figures for one map: the best path of each algorithm over the map, and the
/// convergence curve (best cost per iteration) of each algorithm's best run. Costs that still
/// carry an infeasibility penalty are left out of the curves (a gap until feasible).
fn figures(case: &Case, runs: &[Run], out: &std::path::Path) -> anyhow::Result<()> {
    use crate::render::{Layer, MapPicture, Series, Style, convergence_plot};
    use planner_core::geometry::Point;
    let penalty = planner_core::encoding::infeasible_penalty(case.grid.view());
    let mut algos: Vec<&str> = Vec::new();
    for r in runs.iter().filter(|r| r.map == case.name) {
        if !algos.contains(&r.algo.as_str()) {
            algos.push(&r.algo);
        }
    }
    let best: Vec<(&str, Option<&Run>)> = algos
        .iter()
        .map(|a| {
            let best = runs
                .iter()
                .filter(|r| r.map == case.name && r.algo == *a && r.success)
                .min_by(|x, y| x.length.total_cmp(&y.length));
            (*a, best)
        })
        .collect();
    let paths: Vec<(String, Vec<Point>)> = best
        .iter()
        .filter_map(|(a, r)| {
            r.map(|r| {
                (
                    format!("{a} (L = {:.2})", r.length),
                    r.path.iter().map(|p| Point::new(p[0], p[1])).collect(),
                )
            })
        })
        .collect();
    let title = format!("{}: best path of each algorithm", case.name);
    let mut picture = MapPicture::new(case.grid.view(), &title);
    for (i, (label, points)) in paths.iter().enumerate() {
        let style = if i % 2 == 1 {
            Style::dashed(Style::palette(i).color, 2.5)
        } else {
            Style::palette(i)
        };
        picture.layers.push(Layer::new(label, points, style));
    }
    picture.start = Some(case.start.center());
    picture.goal = Some(case.goal.center());
    picture.save_png(&out.join(format!("{}-paths.png", case.name)))?;
    picture.save_svg(&out.join(format!("{}-paths.svg", case.name)))?;
    let curves: Vec<(String, Vec<f32>)> = best
        .iter()
        .filter_map(|(a, r)| {
            r.map(|r| {
                (
                    a.to_string(),
                    r.history
                        .iter()
                        .map(|&v| if v < penalty { v } else { f32::NAN })
                        .collect(),
                )
            })
        })
        .collect();
    let series: Vec<Series> = curves.iter().map(|(a, v)| Series::new(a, v)).collect();
    let title = format!("{}: convergence of the best run", case.name);
    convergence_plot(
        &title,
        "iteration",
        "best path cost",
        &series,
        Some(&out.join(format!("{}-convergence.png", case.name))),
        Some(&out.join(format!("{}-convergence.svg", case.name))),
    )
}

fn run_case(
    case: &Case,
    kind: PlannerKind,
    params: &PlanParams,
    aco: &AcoParams,
    args: &PaperArgs,
    bar: &indicatif::ProgressBar,
) -> anyhow::Result<Vec<Run>> {
    let mut planner = HostPlanner::new();
    planner
        .prepare(case.grid.view())
        .map_err(anyhow::Error::msg)?;
    let mut out: Box<Path<4096>> = Box::new(Path::new());
    let mut runs = Vec::new();
    for k in 0..args.runs {
        let seed = args.seed + k as u64;
        let params = PlanParams { seed, ..*params };
        let aco = AcoParams { seed, ..*aco };
        let mut history = vec![0.0f32; args.iters as usize];
        let view: &mut PathView = &mut *out;
        let began = Instant::now();
        let result = planner.plan(
            case.grid.view(),
            case.start,
            case.goal,
            &PlanChoice { kind, params, aco },
            view,
            PlanOptions {
                history: &mut history,
                interrupt: None,
            },
        );
        let time_s = began.elapsed().as_secs_f64();
        let report = result.as_ref().ok().and_then(|o| o.report);
        let path: Vec<[f32; 2]> = if result.is_ok() {
            out.iter().map(|p| [p.x, p.y]).collect()
        } else {
            Vec::new()
        };
        if result.is_ok() {
            let start = (case.start.x, case.start.y);
            let goal = (case.goal.x, case.goal.y);
            // The loose corner rule's paths are checked by the walk validator inside the core.
            if params.corner_rule == CornerRule::Strict {
                crate::validate::check(case.grid.view(), &path, start, goal).map_err(|e| {
                    anyhow::anyhow!("{} on {}: invalid path {e:?}", kind.name(), case.name)
                })?;
            }
        }
        let len = report.map_or(0, |r| r.history_len);
        history.truncate(len);
        runs.push(Run {
            table: case.table.into(),
            map: case.name.clone(),
            algo: kind.name().into(),
            seed,
            success: result.is_ok(),
            length: result.as_ref().map_or(f64::NAN, |o| o.length as f64),
            turns: result.as_ref().map_or(0, |o| o.turns),
            time_s,
            best_iteration: report.map_or(0, |r| r.best_iteration),
            evaluations: report.map_or(0, |r| r.evaluations),
            history,
            path,
        });
        bar.inc(1);
    }
    Ok(runs)
}

fn aggregate(runs: &[Run]) -> Vec<Row> {
    let mut rows: Vec<Row> = Vec::new();
    let mut keys: Vec<(String, String, String)> = Vec::new();
    for r in runs {
        let key = (r.table.clone(), r.map.clone(), r.algo.clone());
        if !keys.contains(&key) {
            keys.push(key);
        }
    }
    for (table, map, algo) in keys {
        let all: Vec<&Run> = runs
            .iter()
            .filter(|r| r.table == table && r.map == map && r.algo == algo)
            .collect();
        let ok: Vec<&Run> = all.iter().copied().filter(|r| r.success).collect();
        let lengths: Vec<f64> = ok.iter().map(|r| r.length).collect();
        let (l_mean, s) = mean_std(&lengths);
        rows.push(Row {
            table,
            map,
            algo,
            l_mean,
            l_best: lengths.iter().copied().fold(f64::NAN, f64::min),
            p_mean: mean_std(&ok.iter().map(|r| r.turns as f64).collect::<Vec<_>>()).0,
            s,
            t_mean: mean_std(&all.iter().map(|r| r.time_s).collect::<Vec<_>>()).0,
            i_mean: mean_std(
                &ok.iter()
                    .map(|r| r.best_iteration as f64)
                    .collect::<Vec<_>>(),
            )
            .0,
            success_rate: ok.len() as f64 / all.len().max(1) as f64,
        });
    }
    rows
}

//! `host-sim bench safety`: margins and turns of the exact planners against the swarm
//! planners with the blended objective ([`Blend`]).
//!
//! On the Moving AI warehouses (the longest rows of each `random-1` scenario) and on
//! generated warehouses (with and without clutter), per planner: length against the exact
//! any-angle path, the smallest clearance of any path, how many paths keep the desired
//! clearance where their endpoints allow it, the share of length closer than it, turns,
//! total turning and time; and per map a lower bound on the length of any path that keeps
//! the desired clearance ([`clearance_bound`](super::clearance_bound)), which says where a
//! length goal cannot be met with that clearance.

use super::clearance_bound::{ClearanceBound, WidestRoute};
use super::movingai::{WAREHOUSES, read_scen};
use super::scale::make_case;
use super::{fmt, mean_std, print_table, write_csv, write_json};
use crate::render::{Layer, MapPicture, Style};
use anyhow::Context;
use planner_core::encoding::blend::{share_within, total_turning};
use planner_core::geometry::{Cell, Point};
use planner_core::grid::GridBuf;
use planner_core::optim::any::AlgorithmKind;
use planner_core::path::{self, Path};
use planner_core::planner::aco::AcoParams;
use planner_core::planner::owned::{HostPlanner, PlanChoice};
use planner_core::planner::{Blend, PlanOptions, PlanParams, PlannerKind};
use planner_mapfile::{MapOptions, load_map};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `host-sim bench safety`.
#[derive(clap::Args, Debug)]
pub struct SafetyArgs {
    /// Folder with the Moving AI `.map` and `.scen` files.
    #[arg(long, default_value = "tests/data/movingai")]
    pub data: PathBuf,
    /// Queries per map (the longest scenario rows; random far pairs on generated maps).
    #[arg(long, default_value_t = 20)]
    pub queries: usize,
    /// Generated warehouses `WxH` (each also with clutter); none: `--generated ''`.
    #[arg(long, value_delimiter = ',', default_value = "256x256")]
    pub generated: Vec<String>,
    /// Desired clearance, cells.
    #[arg(long, default_value_t = 1.0)]
    pub clearance: f32,
    /// Weight of missing clearance.
    #[arg(long, default_value_t = 16.0)]
    pub clearance_weight: f32,
    /// Weight of turning.
    #[arg(long, default_value_t = 1.0)]
    pub turn_weight: f32,
    /// Seed (query `k` uses `seed + k`).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Output folder.
    #[arg(long, default_value = "bench-out/safety")]
    pub out: PathBuf,
}

/// A map's name, grid and queries.
type Case = (String, GridBuf, Vec<(Cell, Cell)>);

/// One planner on one map.
#[derive(Serialize)]
pub struct Summary {
    /// Map.
    pub map: String,
    /// Planner (`+blend`: the blended objective).
    pub planner: String,
    /// Queries.
    pub queries: usize,
    /// Valid paths.
    pub valid: usize,
    /// Mean of length / the any-angle length.
    pub mean_ratio: f64,
    /// Largest length / the any-angle length.
    pub max_ratio: f64,
    /// Smallest clearance of any path (cells, capped at twice the desired).
    pub min_clearance: f64,
    /// Paths whose clearance is at least the desired one, or where no route has it, that
    /// of the widest route over cell centres ([`WidestRoute`]).
    pub kept: usize,
    /// Mean share of length closer than the desired clearance.
    pub share_within: f64,
    /// Mean turns.
    pub turns: f64,
    /// Mean total turning, degrees.
    pub turning_deg: f64,
    /// Mean time per plan, ms.
    pub mean_ms: f64,
}

/// The lower bound on one map.
#[derive(Serialize)]
pub struct BoundSummary {
    /// Map.
    pub map: String,
    /// Queries.
    pub queries: usize,
    /// Queries with a path that keeps the clearance (the desired one, or the widest
    /// route's where less).
    pub possible: usize,
    /// Mean of bound / the any-angle length.
    pub mean_ratio: f64,
    /// Largest bound / the any-angle length.
    pub max_ratio: f64,
    /// Queries whose bound is over 1.03 x the any-angle length.
    pub over_3pct: usize,
}

/// The planners compared: exact ones by length, the swarm planners blended.
const PLANNERS: [(PlannerKind, bool); 5] = [
    (PlannerKind::AnyAngle, false),
    (PlannerKind::Theta, false),
    (PlannerKind::AStar, false),
    (PlannerKind::Swarm(AlgorithmKind::Tclhho), true),
    (PlannerKind::Swarm(AlgorithmKind::Igwo), true),
];

/// Runs `host-sim bench safety`.
pub fn run(args: &SafetyArgs) -> anyhow::Result<()> {
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let blend = Blend {
        clearance: args.clearance,
        clearance_weight: args.clearance_weight,
        turn_weight: args.turn_weight,
    };
    anyhow::ensure!(
        blend.is_valid() && args.clearance > 0.0,
        "--clearance, --clearance-weight, --turn-weight: finite, at least 0 (clearance above 0)"
    );
    let mut cases: Vec<Case> = Vec::new();
    for name in WAREHOUSES {
        let grid = load_map(
            &args.data.join(format!("{name}.map")),
            &MapOptions::default(),
        )?
        .grid;
        let scen = args.data.join(format!("{name}-random-1.scen"));
        let text = std::fs::read_to_string(&scen)
            .with_context(|| format!("cannot read {}", scen.display()))?;
        let mut rows = read_scen(&text)?;
        rows.sort_by(|a, b| b.optimal.total_cmp(&a.optimal));
        let queries = rows.iter().take(args.queries).map(|r| (r.start, r.goal));
        cases.push((name.to_string(), grid, queries.collect()));
    }
    for size in args.generated.iter().filter(|s| !s.is_empty()) {
        let (w, h) = size
            .split_once(['x', 'X'])
            .and_then(|(w, h)| Some((w.parse().ok()?, h.parse().ok()?)))
            .with_context(|| format!("--generated {size}: expected WIDTHxHEIGHT"))?;
        for clutter in [false, true] {
            let case = make_case(w, h, clutter, args.queries, args.seed)?;
            // Saved beside the paths, so that both can be looked at again.
            let mut text = String::new();
            case.grid.write_movingai(&mut text)?;
            let file = args.out.join(format!("{}.map", case.name));
            std::fs::write(&file, text)
                .with_context(|| format!("cannot write {}", file.display()))?;
            cases.push((case.name, case.grid, case.queries));
        }
    }
    let mut summaries = Vec::new();
    let mut bounds = Vec::new();
    let mut paths = String::new();
    for (name, grid, queries) in &cases {
        eprintln!("{name}: {} queries", queries.len());
        // What each query can keep: the desired clearance, or less where no route has it.
        let widest = WidestRoute::new(grid, args.clearance);
        let keep: Vec<f32> = queries
            .iter()
            .map(|&(s, g)| widest.clearance(s, g).min(args.clearance))
            .collect();
        let (rows, exact) = run_case(name, grid, queries, &keep, blend, args, &mut paths)?;
        summaries.extend(rows);
        bounds.push(bound_case(name, grid, queries, &keep, &exact)?);
    }
    let file = args.out.join("paths.jsonl");
    std::fs::write(&file, paths).with_context(|| format!("cannot write {}", file.display()))?;
    report(args, &summaries)?;
    report_bounds(args, &bounds)
}

/// The clearance bound of each query of a map, keeping `keep`, against its any-angle
/// length `exact`.
fn bound_case(
    name: &str,
    grid: &GridBuf,
    queries: &[(Cell, Cell)],
    keep: &[f32],
    exact: &[f64],
) -> anyhow::Result<BoundSummary> {
    // One fine grid per clearance kept (in thousandths).
    let mut fine: std::collections::HashMap<u32, ClearanceBound> = Default::default();
    let (mut ratios, mut possible) = (Vec::new(), 0);
    for ((&(s, g), &len), &r) in queries.iter().zip(exact).zip(keep) {
        let key = (r * 1000.0).floor() as u32;
        if key == 0 {
            continue;
        }
        let bound = match fine.entry(key) {
            std::collections::hash_map::Entry::Occupied(e) => e.into_mut(),
            std::collections::hash_map::Entry::Vacant(e) => {
                e.insert(ClearanceBound::new(grid, key as f32 / 1000.0)?)
            }
        };
        if let Some(b) = bound.length(s, g)? {
            possible += 1;
            ratios.push(b / len);
        }
    }
    Ok(BoundSummary {
        map: name.to_string(),
        queries: queries.len(),
        possible,
        mean_ratio: mean_std(&ratios).0,
        max_ratio: ratios.iter().copied().fold(f64::NAN, f64::max),
        over_3pct: ratios.iter().filter(|&&r| r > 1.03).count(),
    })
}

fn report_bounds(args: &SafetyArgs, bounds: &[BoundSummary]) -> anyhow::Result<()> {
    let header = [
        "map",
        "keep possible",
        "mean bound/anyangle",
        "max bound/anyangle",
        "bound over 1.03",
    ];
    let rows: Vec<Vec<String>> = bounds
        .iter()
        .map(|b| {
            vec![
                b.map.clone(),
                format!("{}/{}", b.possible, b.queries),
                fmt(b.mean_ratio, 4),
                fmt(b.max_ratio, 4),
                format!("{}/{}", b.over_3pct, b.possible),
            ]
        })
        .collect();
    print_table(
        &format!(
            "Lower bound on the length of a path keeping {} cells (or the widest route's clearance)",
            args.clearance
        ),
        &header,
        &rows,
    );
    write_csv(&args.out.join("bound.csv"), &header, &rows)?;
    write_json(&args.out.join("bound.json"), &bounds)
}

fn run_case(
    name: &str,
    grid: &GridBuf,
    queries: &[(Cell, Cell)],
    keep: &[f32],
    blend: Blend,
    args: &SafetyArgs,
    paths: &mut String,
) -> anyhow::Result<(Vec<Summary>, Vec<f64>)> {
    let mut planner = HostPlanner::new();
    planner.prepare(grid.view()).map_err(anyhow::Error::msg)?;
    let mut out: Box<Path<65536>> = Box::new(Path::new());
    let cap = 2.0 * args.clearance;
    let mut exact_len = vec![f64::NAN; queries.len()];
    let mut summaries = Vec::new();
    // The first query's shortest and blended TCLHHO paths, drawn on one picture.
    let (mut shortest, mut smooth): (Vec<Point>, Vec<Point>) = (Vec::new(), Vec::new());
    for (kind, blended) in PLANNERS {
        let (mut ratios, mut shares, mut turns, mut turning, mut times) =
            (vec![], vec![], vec![], vec![], vec![]);
        let (mut valid, mut kept, mut min_clear) = (0, 0, f64::INFINITY);
        for (k, &(s, g)) in queries.iter().enumerate() {
            let params = PlanParams {
                seed: args.seed + k as u64,
                blend: if blended { blend } else { Blend::LENGTH },
                ..PlanParams::host(AlgorithmKind::Tclhho)
            };
            let choice = PlanChoice {
                kind,
                params,
                aco: AcoParams::default(),
            };
            let began = Instant::now();
            let result = planner.plan(
                grid.view(),
                s,
                g,
                &choice,
                &mut *out,
                PlanOptions::default(),
            );
            times.push(began.elapsed().as_secs_f64() * 1e3);
            let Ok(outcome) = result else { continue };
            let pts: Vec<[f32; 2]> = out.iter().map(|p| [p.x, p.y]).collect();
            if crate::validate::check(grid.view(), &pts, (s.x, s.y), (g.x, g.y)).is_err() {
                continue;
            }
            let line = serde_json::json!({
                "map": name, "planner": kind.name(), "blend": blended, "query": k,
                "path": pts,
            });
            paths.push_str(&format!("{line}\n"));
            valid += 1;
            if k == 0 && kind == PlannerKind::AnyAngle {
                shortest = out.iter().copied().collect();
            } else if k == 0 && kind == PLANNERS[3].0 {
                smooth = out.iter().copied().collect();
            }
            if kind == PlannerKind::AnyAngle {
                exact_len[k] = outcome.length as f64;
            }
            ratios.push(outcome.length as f64 / exact_len[k]);
            let c = path::clearance(grid.view(), &out, cap) as f64;
            min_clear = min_clear.min(c);
            if c >= keep[k] as f64 - 1e-3 {
                kept += 1;
            }
            shares.push(share_within(grid.view(), &out, args.clearance) as f64);
            turns.push(outcome.turns as f64);
            turning.push(total_turning(&out).to_degrees() as f64);
        }
        let suffix = if blended { "+blend" } else { "" };
        summaries.push(Summary {
            map: name.to_string(),
            planner: format!("{}{suffix}", kind.name()),
            queries: queries.len(),
            valid,
            mean_ratio: mean_std(&ratios).0,
            max_ratio: ratios.iter().copied().fold(f64::NAN, f64::max),
            min_clearance: min_clear,
            kept,
            share_within: mean_std(&shares).0,
            turns: mean_std(&turns).0,
            turning_deg: mean_std(&turning).0,
            mean_ms: mean_std(&times).0,
        });
    }
    if let Some(&(s, g)) = queries.first() {
        let title = format!("{name}: anyangle (shortest) and TCLHHO with the blend");
        let mut picture = MapPicture::new(grid.view(), &title);
        picture.layers = vec![
            Layer::new(
                "anyangle (shortest)",
                &shortest,
                Style::solid([0, 114, 178], 2.0),
            ),
            Layer::new("TCLHHO + blend", &smooth, Style::solid([213, 94, 0], 2.0)),
        ];
        (picture.start, picture.goal) = (Some(s.center()), Some(g.center()));
        picture.save_png(&args.out.join(format!("{name}-paths.png")))?;
    }
    Ok((summaries, exact_len))
}

fn report(args: &SafetyArgs, summaries: &[Summary]) -> anyhow::Result<()> {
    let header = [
        "map",
        "planner",
        "valid",
        "mean L/anyangle",
        "max L/anyangle",
        "min clearance",
        "kept clearance",
        "share within",
        "turns",
        "turning deg",
        "ms/plan",
    ];
    let rows: Vec<Vec<String>> = summaries
        .iter()
        .map(|s| {
            vec![
                s.map.clone(),
                s.planner.clone(),
                format!("{}/{}", s.valid, s.queries),
                fmt(s.mean_ratio, 4),
                fmt(s.max_ratio, 4),
                fmt(s.min_clearance, 3),
                format!("{}/{}", s.kept, s.valid),
                fmt(s.share_within, 3),
                fmt(s.turns, 2),
                fmt(s.turning_deg, 1),
                fmt(s.mean_ms, 3),
            ]
        })
        .collect();
    print_table(
        &format!(
            "Safety: desired clearance {} cells, clearance weight {}, turn weight {}",
            args.clearance, args.clearance_weight, args.turn_weight
        ),
        &header,
        &rows,
    );
    write_csv(&args.out.join("safety.csv"), &header, &rows)?;
    write_json(&args.out.join("safety.json"), &summaries)?;
    Ok(())
}

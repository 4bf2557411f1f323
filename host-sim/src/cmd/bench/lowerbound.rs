//! `host-sim bench lowerbound`: a rigorous lower bound on the length of *any* valid path
//! for the Moving AI warehouse rows that `host-sim bench movingai` plans, next to the
//! published octile optimum.
//!
//! The bound is the length of the shortest path in the closure of the free space, from the
//! reduced visibility graph of the obstacle corners (`planner_core::search::visibility`, where
//! the method and its tests against a brute force live). It is shown to be attained: the
//! *witness* moves each corner the path turns at (or grazes) `--eps` away from its blocked
//! cell, and the independent validator ([`crate::validate`]) checks the result; its length
//! exceeds the bound by `O(eps)`.

use super::movingai::{ScenRow, WAREHOUSES, read_scen};
use super::{fmt, mean_std, print_table, progress, write_csv, write_json};
use anyhow::Context;
use planner_core::path::{Path, PathView};
use planner_core::search::visibility::VisibilityGraph;
use planner_core::search::{SearchNode, theta};
use planner_mapfile::{MapOptions, load_map};
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `host-sim bench lowerbound`.
#[derive(clap::Args, Debug)]
pub struct LowerboundArgs {
    /// Folder with the `.map` and `.scen` files.
    #[arg(long, default_value = "tests/data/movingai")]
    pub data: PathBuf,
    /// Scenario rows per map (the same rows as `bench movingai`).
    #[arg(long, default_value_t = 200)]
    pub rows: usize,
    /// Maps (names without `.map`); default: the four warehouses.
    #[arg(long, value_delimiter = ',')]
    pub maps: Vec<String>,
    /// Offset (cell units, per axis) by which the witness path keeps off each corner.
    #[arg(long, default_value_t = 1e-3)]
    pub eps: f64,
    /// Output folder.
    #[arg(long, default_value = "bench-out/lowerbound")]
    pub out: PathBuf,
    /// Size limit of the loaded maps.
    #[command(flatten)]
    pub limits: MapOptions,
}

#[derive(Serialize)]
pub struct Summary {
    /// Map.
    pub map: String,
    /// Rows.
    pub rows: usize,
    /// Visibility-graph vertices (obstacle corners and pinch points).
    pub vertices: usize,
    /// Visibility-graph edges (corner to corner, tangent at both ends).
    pub edges: usize,
    /// Mean of lower bound / published octile optimum.
    pub mean_lb_ratio: f64,
    /// Smallest lower bound / optimum.
    pub min_lb_ratio: f64,
    /// Largest lower bound / optimum.
    pub max_lb_ratio: f64,
    /// Sum of lower bounds / sum of optima.
    pub total_lb_ratio: f64,
    /// Mean of Theta* length / optimum.
    pub mean_theta_ratio: f64,
    /// Mean of Theta* length / lower bound.
    pub mean_theta_over_lb: f64,
    /// Rows whose witness (the bound's path kept `eps` off the corners, in `f32`) the
    /// independent validator accepts.
    pub witness_valid: usize,
    /// Mean of witness length / optimum over those rows.
    pub mean_witness_ratio: f64,
    /// Rows where the bound exceeded Theta* (must be 0).
    pub violations: usize,
    /// Graph build time (ms).
    pub build_ms: f64,
    /// Mean time per query (ms).
    pub query_ms: f64,
}

/// Runs `host-sim bench lowerbound`.
pub fn run(args: &LowerboundArgs) -> anyhow::Result<()> {
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let maps: Vec<String> = if args.maps.is_empty() {
        WAREHOUSES.iter().map(|s| s.to_string()).collect()
    } else {
        args.maps.clone()
    };
    let mut summaries = Vec::new();
    let mut per_row = Vec::new();
    for name in &maps {
        let grid = load_map(&args.data.join(format!("{name}.map")), &args.limits)?.grid;
        let view = grid.view();
        let scen_path = args.data.join(format!("{name}-random-1.scen"));
        let text = std::fs::read_to_string(&scen_path)
            .with_context(|| format!("cannot read {}", scen_path.display()))?;
        let rows: Vec<ScenRow> = read_scen(&text)?
            .into_iter()
            .filter(|r| r.optimal > 0.0)
            .take(args.rows)
            .collect();
        let began = Instant::now();
        let vg = VisibilityGraph::new(view);
        let build_ms = began.elapsed().as_secs_f64() * 1e3;
        let mut nodes = vec![SearchNode::EMPTY; view.cells()];
        let mut path: Box<Path<65536>> = Box::new(Path::new());
        let bar = progress(rows.len() as u64, name);
        let (mut lb_ratios, mut theta_ratios, mut theta_over_lb) =
            (Vec::new(), Vec::new(), Vec::new());
        let (mut total_lb, mut total_opt, mut violations) = (0.0f64, 0.0f64, 0usize);
        let mut query_s = 0.0;
        let mut witness_ratios = Vec::new();
        for (k, row) in rows.iter().enumerate() {
            let began = Instant::now();
            let lb = vg
                .shortest(view, row.start, row.goal)
                .with_context(|| format!("{name} row {k}: no path in the closure"))?;
            query_s += began.elapsed().as_secs_f64();
            let out: &mut PathView = &mut *path;
            let theta_len = theta::plan(view, row.start, row.goal, &mut nodes, out)
                .map(|st| st.length as f64)
                .unwrap_or(f64::NAN);
            let witness: Option<Vec<[f32; 2]>> = vg
                .witness(view, row.start, row.goal, args.eps)
                .map(|w| w.iter().map(|p| [p[0] as f32, p[1] as f32]).collect());
            let witness_len = match witness {
                Some(w)
                    if crate::validate::check(
                        view,
                        &w,
                        (row.start.x, row.start.y),
                        (row.goal.x, row.goal.y),
                    )
                    .is_ok() =>
                {
                    let len: f64 = w
                        .windows(2)
                        .map(|s| {
                            let dx = s[1][0] as f64 - s[0][0] as f64;
                            let dy = s[1][1] as f64 - s[0][1] as f64;
                            (dx * dx + dy * dy).sqrt()
                        })
                        .sum();
                    witness_ratios.push(len / row.optimal);
                    len
                }
                _ => f64::NAN,
            };
            if lb > theta_len + 1e-4 {
                violations += 1;
            }
            lb_ratios.push(lb / row.optimal);
            theta_ratios.push(theta_len / row.optimal);
            theta_over_lb.push(theta_len / lb);
            total_lb += lb;
            total_opt += row.optimal;
            per_row.push(vec![
                name.clone(),
                k.to_string(),
                format!("{} {}", row.start.x, row.start.y),
                format!("{} {}", row.goal.x, row.goal.y),
                format!("{:.6}", row.optimal),
                format!("{lb:.6}"),
                fmt(theta_len, 6),
                fmt(witness_len, 6),
                format!("{:.6}", lb / row.optimal),
            ]);
            bar.inc(1);
        }
        bar.finish_and_clear();
        summaries.push(Summary {
            map: name.clone(),
            rows: rows.len(),
            vertices: vg.vertices(),
            edges: vg.edges(),
            mean_lb_ratio: mean_std(&lb_ratios).0,
            min_lb_ratio: lb_ratios.iter().copied().fold(f64::NAN, f64::min),
            max_lb_ratio: lb_ratios.iter().copied().fold(f64::NAN, f64::max),
            total_lb_ratio: total_lb / total_opt,
            mean_theta_ratio: mean_std(&theta_ratios).0,
            mean_theta_over_lb: mean_std(&theta_over_lb).0,
            witness_valid: witness_ratios.len(),
            mean_witness_ratio: mean_std(&witness_ratios).0,
            violations,
            build_ms,
            query_ms: query_s * 1e3 / rows.len().max(1) as f64,
        });
    }
    let header = [
        "map",
        "rows",
        "vertices",
        "edges",
        "mean LB/opt",
        "min LB/opt",
        "max LB/opt",
        "sum LB/sum opt",
        "mean Theta*/opt",
        "mean Theta*/LB",
        "witness valid",
        "mean witness/opt",
        "LB>Theta*",
        "build ms",
        "ms/query",
    ];
    let rows: Vec<Vec<String>> = summaries
        .iter()
        .map(|s| {
            vec![
                s.map.clone(),
                s.rows.to_string(),
                s.vertices.to_string(),
                s.edges.to_string(),
                fmt(s.mean_lb_ratio, 4),
                fmt(s.min_lb_ratio, 4),
                fmt(s.max_lb_ratio, 4),
                fmt(s.total_lb_ratio, 4),
                fmt(s.mean_theta_ratio, 4),
                fmt(s.mean_theta_over_lb, 4),
                format!("{}/{}", s.witness_valid, s.rows),
                fmt(s.mean_witness_ratio, 4),
                s.violations.to_string(),
                fmt(s.build_ms, 0),
                fmt(s.query_ms, 2),
            ]
        })
        .collect();
    print_table(
        &format!(
            "Lower bound on any valid path (shortest path touching obstacles), Moving AI warehouses, {} rows each",
            args.rows
        ),
        &header,
        &rows,
    );
    write_csv(&args.out.join("lowerbound.csv"), &header, &rows)?;
    write_csv(
        &args.out.join("lowerbound-rows.csv"),
        &[
            "map",
            "row",
            "start",
            "goal",
            "optimal",
            "lower_bound",
            "theta",
            "witness",
            "lb_over_opt",
        ],
        &per_row,
    )?;
    write_json(&args.out.join("lowerbound.json"), &summaries)?;
    Ok(())
}

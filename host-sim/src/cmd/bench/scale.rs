//! `host-sim bench scale`: the planners on generated warehouses from 256 to 4096 cells a
//! side, on the same long queries: time per query (one-time costs apart) and its ratio to
//! A* in the same run, length against the exact any-angle length, validity under the
//! collision rule, and the process's peak heap. A table, JSON, CSV and a log-log plot of
//! time against map size.
//!
//! The layouts scale with the map, one unit `u` = the longest side / 256 cells (16 cells,
//! 0.8 m at 0.05 m a cell, on 4096): racks `u` deep in back-to-back pairs, `24u` long,
//! aisles `3u`, cross aisles `4u`, a `6u` lane around; clutter adds pallets of `u x u`
//! cells at random (one per 48 `u x u` squares of the map).

use super::{fmt, print_table, write_csv, write_json};
use crate::render::{Points, Style, loglog_plot};
use crate::warehouse_gen::{WarehouseParams, generate};
use anyhow::{Context, bail};
use host_sim::heap;
use planner_core::geometry::Cell;
use planner_core::grid::GridBuf;
use planner_core::path::{self, Path};
use planner_core::planner::aco::AcoParams;
use planner_core::planner::owned::{HostPlanner, PlanChoice};
use planner_core::planner::{PlanOptions, PlanParams, PlannerKind};
use planner_core::search::connectivity;
use planner_mapfile::MapOptions;
use rand_core::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro256PlusPlus;
use serde::Serialize;
use std::path::PathBuf;
use std::time::Instant;

/// Arguments of `host-sim bench scale`.
#[derive(clap::Args, Debug)]
pub struct ScaleArgs {
    /// Maps, `WIDTHxHEIGHT`, comma separated.
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "256x256,512x512,1024x512,2048x1024,4096x2048,4096x4096"
    )]
    pub maps: Vec<String>,
    /// Clutter (pallets in the aisles): `off`, `on` or `both` (every map twice).
    #[arg(long, value_enum, default_value_t = Clutter::Both)]
    pub clutter: Clutter,
    /// Queries per map (pairs of free cells at least half the longest side apart).
    #[arg(long, default_value_t = 20)]
    pub queries: usize,
    /// Planners, comma separated (`polyanya`: the `polyanya` crate on the same rectangles,
    /// with host-sim's cargo feature `polyanya`).
    #[arg(
        long,
        value_delimiter = ',',
        default_value = "astar,theta,anyangle,polyanya,tclhho,igwo"
    )]
    pub algos: Vec<String>,
    /// Stagnation stop of the swarm planners (iterations without a 1e-4 relative
    /// improvement; 0 runs every iteration). The default is the host's.
    #[arg(long, default_value_t = planner_core::planner::HOST_STAGNATION)]
    pub stagnation: u32,
    /// Seed of the layouts' clutter, the queries and the swarm planners.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Output folder.
    #[arg(long, default_value = "bench-out/scale")]
    pub out: PathBuf,
}

/// `--clutter` values.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
pub enum Clutter {
    /// Racks and aisles only.
    Off,
    /// With pallets.
    On,
    /// Every map without, then with pallets.
    Both,
}

/// One planner on one map.
#[derive(Clone, Debug, Serialize)]
pub struct Record {
    /// Map name (`WxH`, `+clutter`).
    pub map: String,
    /// Width in cells.
    pub width: usize,
    /// Height in cells.
    pub height: usize,
    /// Pallets on the map.
    pub clutter: bool,
    /// Planner name.
    pub planner: String,
    /// Queries run.
    pub queries: usize,
    /// Paths valid under the collision rule (`polyanya`'s touch obstacle corners, which the
    /// rule forbids).
    pub valid: usize,
    /// One-time cost of the map for this planner (ms): its share of preparing the map
    /// (labels and the any-angle mesh for the host planners; the mesh for `polyanya`).
    pub prepare_ms: f64,
    /// Mean time per query (ms), one-time costs excluded.
    pub mean_ms: f64,
    /// `mean_ms` over A*'s on the same queries in this run.
    pub ratio_to_astar: f64,
    /// Mean over the queries of length / the exact any-angle length.
    pub mean_length_ratio: f64,
    /// Largest such ratio.
    pub max_length_ratio: f64,
    /// Peak heap of the process while this planner prepared and ran (MB; `None` when the
    /// binary does not count its heap).
    pub peak_mb: Option<f64>,
}

/// A generated map and its queries.
pub(super) struct Case {
    pub(super) name: String,
    pub(super) grid: GridBuf,
    clutter: bool,
    pub(super) queries: Vec<(Cell, Cell)>,
}

/// Runs `host-sim bench scale`.
pub fn run(args: &ScaleArgs) -> anyhow::Result<()> {
    let sizes: Vec<(usize, usize)> = args
        .maps
        .iter()
        .map(|m| parse_size(m))
        .collect::<anyhow::Result<_>>()?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let kinds: Vec<Planner> = args
        .algos
        .iter()
        .map(|a| Planner::parse(a))
        .collect::<anyhow::Result<_>>()?;
    let clutters: &[bool] = match args.clutter {
        Clutter::Off => &[false],
        Clutter::On => &[true],
        Clutter::Both => &[false, true],
    };
    let mut records = Vec::new();
    for &(w, h) in &sizes {
        for &clutter in clutters {
            let case = make_case(w, h, clutter, args.queries, args.seed)?;
            eprintln!(
                "{}: {} queries (mean straight distance {:.0} cells)",
                case.name,
                case.queries.len(),
                case.queries
                    .iter()
                    .map(|(s, g)| s.center().distance(g.center()) as f64)
                    .sum::<f64>()
                    / case.queries.len().max(1) as f64
            );
            records.extend(run_case(&case, &kinds, args)?);
        }
    }
    report(args, &records)
}

/// `WxH`.
fn parse_size(text: &str) -> anyhow::Result<(usize, usize)> {
    let (w, h) = text
        .split_once(['x', 'X'])
        .with_context(|| format!("map size {text:?}: expected WIDTHxHEIGHT"))?;
    let (w, h): (usize, usize) = (w.trim().parse()?, h.trim().parse()?);
    if !(32..=4096).contains(&w) || !(32..=4096).contains(&h) {
        bail!("map size {text}: each side from 32 to 4096 cells");
    }
    Ok((w, h))
}

/// The scaled layout, its clutter and its queries.
pub(super) fn make_case(
    w: usize,
    h: usize,
    clutter: bool,
    queries: usize,
    seed: u64,
) -> anyhow::Result<Case> {
    let u = (w.max(h) / 256).max(1);
    let params = WarehouseParams {
        width: w,
        height: h,
        shelf_depth: 2 * u,
        shelf_len: 24 * u,
        aisle: 3 * u,
        cross: 4 * u,
        margin: 6 * u,
        chargers: 0,
    };
    let mut grid = generate(&params, &MapOptions::default())?.grid;
    let mut rng = Xoshiro256PlusPlus::seed_from_u64(seed ^ (w * 4099 + h) as u64);
    if clutter {
        for _ in 0..(w / u) * (h / u) / 48 {
            let x = (rng.next_u64() % (w - u) as u64) as usize;
            let y = (rng.next_u64() % (h - u) as u64) as usize;
            for dy in 0..u {
                for dx in 0..u {
                    grid.set_blocked(x + dx, y + dy, true)?;
                }
            }
        }
    }
    // Queries within the largest component, at least half the longest side apart.
    let mut planner = HostPlanner::new();
    planner.prepare(grid.view()).map_err(anyhow::Error::msg)?;
    let labels = planner.labels();
    let mut sizes = std::collections::HashMap::new();
    for &l in labels.iter().filter(|&&l| l != connectivity::BLOCKED) {
        *sizes.entry(l).or_insert(0usize) += 1;
    }
    let Some((&main, _)) = sizes.iter().max_by_key(|&(l, n)| (*n, *l)) else {
        bail!("{w}x{h}: no free cell");
    };
    let v = grid.view();
    let mut pick = || loop {
        let i = (rng.next_u64() % v.cells() as u64) as usize;
        if labels[i] == main {
            return v.cell(i);
        }
    };
    let far = w.max(h) as f32 / 2.0;
    let mut list = Vec::new();
    for _ in 0..queries * 1000 {
        if list.len() == queries {
            break;
        }
        let (s, g) = (pick(), pick());
        if s.center().distance(g.center()) >= far {
            list.push((s, g));
        }
    }
    Ok(Case {
        name: format!("{w}x{h}{}", if clutter { "+clutter" } else { "" }),
        grid,
        clutter,
        queries: list,
    })
}

/// A planner of the bench.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Planner {
    Host(PlannerKind),
    Polyanya,
}

impl Planner {
    fn parse(name: &str) -> anyhow::Result<Self> {
        if name.eq_ignore_ascii_case("polyanya") {
            return Ok(Planner::Polyanya);
        }
        name.parse()
            .map(Planner::Host)
            .map_err(|_| anyhow::anyhow!("unknown planner {name}"))
    }

    fn name(self) -> &'static str {
        match self {
            Planner::Host(k) => k.name(),
            Planner::Polyanya => "polyanya",
        }
    }
}

/// What one planner did on one query.
pub(super) struct Run {
    /// Time (ms).
    pub ms: f64,
    /// Length of the path found (`None`: none).
    pub length: Option<f64>,
    /// Whether the path is valid under the collision rule.
    pub valid: bool,
}

fn run_case(case: &Case, kinds: &[Planner], args: &ScaleArgs) -> anyhow::Result<Vec<Record>> {
    // The exact any-angle planner first (the length baseline), then A* (the time baseline).
    let mut order: Vec<Planner> = kinds.to_vec();
    order.sort_by_key(|k| match k {
        Planner::Host(PlannerKind::AnyAngle) => 0,
        Planner::Host(PlannerKind::AStar) => 1,
        _ => 2,
    });
    let mut exact: Vec<Option<f64>> = vec![None; case.queries.len()];
    let mut records = Vec::new();
    for kind in order {
        heap::reset_peak();
        let (prepare_ms, runs) = match kind {
            Planner::Host(k) => run_host(case, k, args)?,
            Planner::Polyanya => match run_polyanya(case)? {
                Some(r) => r,
                None => {
                    eprintln!("polyanya: not built (host-sim's cargo feature `polyanya`)");
                    continue;
                }
            },
        };
        let peak_mb = heap::counting().then(|| heap::peak() as f64 / 1e6);
        let mean_ms = runs.iter().map(|r| r.ms).sum::<f64>() / runs.len().max(1) as f64;
        if kind == Planner::Host(PlannerKind::AnyAngle) {
            exact = runs.iter().map(|r| r.length).collect();
        }
        let ratios: Vec<f64> = runs
            .iter()
            .zip(&exact)
            .filter_map(|(r, e)| Some(r.length? / (*e)?))
            .collect();
        let record = Record {
            map: case.name.clone(),
            width: case.grid.width(),
            height: case.grid.height(),
            clutter: case.clutter,
            planner: kind.name().into(),
            queries: runs.len(),
            valid: runs.iter().filter(|r| r.valid).count(),
            prepare_ms,
            mean_ms,
            ratio_to_astar: f64::NAN,
            mean_length_ratio: ratios.iter().sum::<f64>() / ratios.len().max(1) as f64,
            max_length_ratio: ratios.iter().copied().fold(f64::NAN, f64::max),
            peak_mb,
        };
        eprintln!(
            "  {:>9}: {:>3}/{} valid, {:>10} ms/query, L/exact {} (max {}), one-time {} ms, peak {} MB",
            record.planner,
            record.valid,
            record.queries,
            fmt(record.mean_ms, 3),
            fmt(record.mean_length_ratio, 5),
            fmt(record.max_length_ratio, 5),
            fmt(record.prepare_ms, 1),
            record.peak_mb.map_or("—".into(), |m| fmt(m, 0)),
        );
        records.push(record);
    }
    let astar_ms = records
        .iter()
        .find(|r| r.planner == PlannerKind::AStar.name())
        .map_or(f64::NAN, |r| r.mean_ms);
    for r in &mut records {
        r.ratio_to_astar = r.mean_ms / astar_ms;
    }
    Ok(records)
}

/// A planner of `HostPlanner` on every query: preparing the map is its one-time cost.
fn run_host(case: &Case, kind: PlannerKind, args: &ScaleArgs) -> anyhow::Result<(f64, Vec<Run>)> {
    let grid = case.grid.view();
    let mut planner = HostPlanner::new();
    let began = Instant::now();
    planner.prepare(grid).map_err(anyhow::Error::msg)?;
    let prepare_ms = began.elapsed().as_secs_f64() * 1e3;
    let mut out: Box<Path<65536>> = Box::new(Path::new());
    let mut runs = Vec::new();
    for (k, &(s, g)) in case.queries.iter().enumerate() {
        let params = PlanParams {
            seed: args.seed.wrapping_add(k as u64),
            stagnation: (args.stagnation > 0).then_some(args.stagnation),
            ..PlanParams::new(match kind {
                PlannerKind::Swarm(a) => a,
                _ => planner_core::optim::any::AlgorithmKind::Tclhho,
            })
        };
        let began = Instant::now();
        let result = planner.plan(
            grid,
            s,
            g,
            &PlanChoice {
                kind,
                params,
                aco: AcoParams::default(),
            },
            &mut *out,
            PlanOptions::default(),
        );
        let ms = began.elapsed().as_secs_f64() * 1e3;
        if let Err(e) = &result {
            eprintln!("    {} {s:?} -> {g:?}: {e}", kind.name());
        }
        let found = result.is_ok();
        runs.push(Run {
            ms,
            length: found.then(|| path::length(&out[..]) as f64),
            valid: found && path::validate(grid, &out[..], s, g).is_ok(),
        });
    }
    Ok((prepare_ms, runs))
}

#[cfg(feature = "polyanya")]
fn run_polyanya(case: &Case) -> anyhow::Result<Option<(f64, Vec<Run>)>> {
    super::polyanya::run(&case.grid, &case.queries).map(Some)
}

#[cfg(not(feature = "polyanya"))]
fn run_polyanya(_case: &Case) -> anyhow::Result<Option<(f64, Vec<Run>)>> {
    Ok(None)
}

/// The table, the files and the plot.
fn report(args: &ScaleArgs, records: &[Record]) -> anyhow::Result<()> {
    let header = [
        "map",
        "planner",
        "valid",
        "one-time ms",
        "ms/query",
        "x A*",
        "mean L/exact",
        "max L/exact",
        "peak MB",
    ];
    let rows: Vec<Vec<String>> = records
        .iter()
        .map(|r| {
            vec![
                r.map.clone(),
                r.planner.clone(),
                format!("{}/{}", r.valid, r.queries),
                fmt(r.prepare_ms, 1),
                fmt(r.mean_ms, 3),
                fmt(r.ratio_to_astar, 3),
                fmt(r.mean_length_ratio, 5),
                fmt(r.max_length_ratio, 5),
                r.peak_mb.map_or("—".into(), |m| fmt(m, 0)),
            ]
        })
        .collect();
    print_table(
        &format!(
            "Generated warehouses, {} long queries each (seed {})",
            args.queries, args.seed
        ),
        &header,
        &rows,
    );
    write_json(&args.out.join("scale.json"), &records)?;
    write_csv(&args.out.join("scale.csv"), &header, &rows)?;
    // Time per query against the map's side (square root of its cells), one line per
    // planner and clutter setting.
    struct Line {
        label: String,
        points: Vec<(f64, f64)>,
        style: Style,
    }
    let mut lines: Vec<Line> = Vec::new();
    let planners: Vec<&str> = {
        let mut seen = Vec::new();
        for r in records {
            if !seen.contains(&r.planner.as_str()) {
                seen.push(r.planner.as_str());
            }
        }
        seen
    };
    for (i, planner) in planners.iter().enumerate() {
        for clutter in [false, true] {
            let points: Vec<(f64, f64)> = records
                .iter()
                .filter(|r| r.planner == *planner && r.clutter == clutter)
                .map(|r| (((r.width * r.height) as f64).sqrt(), r.mean_ms))
                .collect();
            if points.is_empty() {
                continue;
            }
            let style = Style {
                width: 2.0,
                dashed: clutter,
                ..Style::palette(i)
            };
            let label = if clutter {
                format!("{planner} (clutter)")
            } else {
                planner.to_string()
            };
            lines.push(Line {
                label,
                points,
                style,
            });
        }
    }
    let lines: Vec<Points<'_>> = lines
        .iter()
        .map(|line| Points {
            label: &line.label,
            points: &line.points,
            style: Some(line.style),
        })
        .collect();
    loglog_plot(
        "Time per query on generated warehouses",
        "map side, cells (square root of the cell count)",
        "ms per query (one-time costs apart)",
        &lines,
        Some(&args.out.join("scale-time.png")),
        Some(&args.out.join("scale-time.svg")),
    )?;
    eprintln!(
        "wrote {}/scale.json, scale.csv, scale-time.png, scale-time.svg",
        args.out.display()
    );
    Ok(())
}

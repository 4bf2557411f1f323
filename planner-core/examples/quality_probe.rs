//! Probe: corridor-encoded planners vs A* / Theta* on Moving AI scenario rows.
//! cargo run --release -p planner-core --example quality_probe -- MAP SCEN ROWS ALGO ITERS [STAG] [RADIUS] [SPACING]
use planner_core::encoding::corridor::Station;
use planner_core::geometry::Cell;
use planner_core::grid::{Grid, words_for};
use planner_core::optim::any::{AlgorithmKind, AnyOptimizer};
use planner_core::path::{Path, validate};
use planner_core::planner::{GuideKind, PlanOptions, PlanParams, PlanStorageMut, plan};
use planner_core::search::astar::{AStarNode, OpenSlot, open_capacity};
use planner_core::search::{SearchNode, astar, theta};
use std::time::Instant;

type G = Grid<{ words_for(340, 164) }>;

fn main() {
    let a: Vec<String> = std::env::args().collect();
    let grid = G::parse_movingai(&std::fs::read(&a[1]).unwrap()).unwrap();
    let scen = std::fs::read_to_string(&a[2]).unwrap();
    let rows: usize = a[3].parse().unwrap();
    let algo: AlgorithmKind = a[4].parse().unwrap();
    let iters: u32 = a[5].parse().unwrap();
    let stag: Option<u32> = a.get(6).and_then(|s| s.parse().ok()).filter(|&v| v > 0);
    let radius: f32 = a.get(7).and_then(|s| s.parse().ok()).unwrap_or(5.0);
    let spacing: f32 = a.get(8).and_then(|s| s.parse().ok()).unwrap_or(3.0);
    let cells = grid.view().cells();
    let mut nodes = vec![SearchNode::EMPTY; cells];
    let mut astar_nodes = vec![AStarNode::EMPTY; cells];
    let mut open = vec![OpenSlot::EMPTY; open_capacity(cells)];
    let mut guide: Box<Path<4096>> = Box::new(Path::new());
    let mut visited = vec![0u32; cells / 32 + 1];
    let (mut sum_opt, mut sum_a, mut sum_th, mut sum_ours, mut worst) =
        (0.0, 0.0, 0.0, 0.0, 0.0f64);
    let (mut t_a, mut t_th, mut t_ours) = (0.0, 0.0, 0.0);
    let mut n = 0;
    let mut improv = 0.0;
    for line in scen.lines().skip(1).take(rows) {
        let f: Vec<&str> = line.split('\t').collect();
        let (sx, sy, gx, gy): (u16, u16, u16, u16) = (
            f[4].parse().unwrap(),
            f[5].parse().unwrap(),
            f[6].parse().unwrap(),
            f[7].parse().unwrap(),
        );
        let opt: f64 = f[8].parse().unwrap();
        if opt == 0.0 {
            continue;
        }
        let (s, g) = (Cell::new(sx, sy), Cell::new(gx, gy));
        let mut p: Box<Path<4096>> = Box::new(Path::new());
        let t0 = Instant::now();
        let ar = astar::plan(grid.view(), s, g, &mut astar_nodes, &mut open, &mut *p).unwrap();
        t_a += t0.elapsed().as_secs_f64();
        let t0 = Instant::now();
        let tr = theta::plan(grid.view(), s, g, &mut nodes, &mut *p).unwrap();
        t_th += t0.elapsed().as_secs_f64();
        let params = PlanParams {
            iterations: iters,
            stagnation: stag,
            corridor_radius: radius,
            corridor_spacing: spacing,
            seed: n as u64,
            guide: GuideKind::AStar,
            ..PlanParams::new(algo)
        };
        let mut ws = PlanStorageMut {
            anyangle: None,
            nodes: &mut astar_nodes,
            open: &mut open,
            theta: &mut [],
            guide: &mut *guide,
            visited: &mut visited,
            stations: &mut [Station::EMPTY; 64],
            optimizer: &mut AnyOptimizer::<30, 64>::unconfigured(),
            out: &mut *p,
        };
        let t0 = Instant::now();
        let r = plan(grid.view(), s, g, &params, &mut ws, PlanOptions::default()).unwrap();
        t_ours += t0.elapsed().as_secs_f64();
        assert!(validate(grid.view(), &p, s, g).is_ok());
        sum_opt += opt;
        sum_a += ar.length as f64;
        sum_th += tr.length as f64;
        sum_ours += r.length as f64;
        worst = worst.max(r.length as f64 / opt);
        improv += (r.initial_cost / r.final_cost) as f64;
        n += 1;
    }
    println!(
        "rows {n}: astar/opt {:.4} theta/opt {:.4} ours/opt {:.4} worst {:.4} ours/theta {:.4} init/final {:.3}",
        sum_a / sum_opt,
        sum_th / sum_opt,
        sum_ours / sum_opt,
        worst,
        sum_ours / sum_th,
        improv / n as f64
    );
    println!(
        "time per query us: astar {:.1} theta {:.1} ours {:.1} ratio ours/astar {:.1}",
        t_a / n as f64 * 1e6,
        t_th / n as f64 * 1e6,
        t_ours / n as f64 * 1e6,
        t_ours / t_a
    );
}

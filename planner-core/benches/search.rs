//! Per-query time of our A*, our Theta* and the `pathfinding` crate's `astar` on Moving AI
//! warehouse maps, over the first 100 rows of each map's `random-1` scenario.
//!
//! `pathfinding` gets the same successor rule (8-connected, no corner cutting) with integer
//! costs `1e9` / `round(1e9 sqrt 2)`: over paths of at most a few thousand steps the integer
//! rounding (< 1e-6 in total) is far below the smallest gap between two distinct octile
//! lengths of that size, so it finds a truly optimal path; the setup asserts that its length
//! equals ours (within 1e-3) on every row before anything is timed.
//!
//! Each benchmark plans all 100 queries once per iteration; the throughput line gives
//! queries per second, and time / 100 is the per-query time.
//!
//! ```text
//! cargo bench -p planner-core --bench search -- --warm-up-time 1 --measurement-time 3
//! ```

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use planner_core::geometry::Cell;
use planner_core::grid::{Grid, GridRef, words_for};
use planner_core::path::Path;
use planner_core::search::astar::{AStarNode, OpenSlot, open_capacity};
use planner_core::search::{SearchNode, astar, theta};
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

type Map = Grid<{ words_for(340, 164) }>;
const QUERIES: usize = 100;

const UNIT: u64 = 1_000_000_000;
const DIAG: u64 = 1_414_213_562; // round(1e9 * sqrt 2)

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/movingai")
        .join(name)
}

fn queries(scen: &str) -> Vec<(Cell, Cell)> {
    std::fs::read_to_string(data(scen))
        .unwrap()
        .lines()
        .skip(1)
        .take(QUERIES)
        .map(|l| {
            let f: Vec<u16> = l
                .split('\t')
                .skip(4)
                .take(4)
                .map(|v| v.parse().unwrap())
                .collect();
            (Cell::new(f[0], f[1]), Cell::new(f[2], f[3]))
        })
        .collect()
}

/// `pathfinding::directed::astar::astar` with our successor rule; returns the length.
fn pathfinding_astar(g: GridRef<'_>, s: Cell, t: Cell) -> Option<(Vec<u32>, u64)> {
    let w = g.width() as isize;
    let (tx, ty) = (t.x as isize, t.y as isize);
    let goal = (ty * w + tx) as u32;
    let start = s.y as u32 * w as u32 + s.x as u32;
    pathfinding::directed::astar::astar(
        &start,
        |&i| {
            let (x, y) = (i as isize % w, i as isize / w);
            let mut out = heapless::Vec::<(u32, u64), 8>::new();
            for dy in -1isize..=1 {
                for dx in -1isize..=1 {
                    if (dx, dy) == (0, 0) || g.is_blocked(x + dx, y + dy) {
                        continue;
                    }
                    let diagonal = dx != 0 && dy != 0;
                    if diagonal && (g.is_blocked(x + dx, y) || g.is_blocked(x, y + dy)) {
                        continue;
                    }
                    let j = ((y + dy) * w + x + dx) as u32;
                    let _ = out.push((j, if diagonal { DIAG } else { UNIT }));
                }
            }
            out
        },
        |&i| {
            let (x, y) = (i as isize % w, i as isize / w);
            let dx = (x - tx).unsigned_abs() as u64;
            let dy = (y - ty).unsigned_abs() as u64;
            let (lo, hi) = (dx.min(dy), dx.max(dy));
            hi * UNIT + lo * (DIAG - UNIT)
        },
        |&i| i == goal,
    )
}

fn bench_map(c: &mut Criterion, map: &str) {
    let grid = Box::new(
        Map::parse_movingai(&std::fs::read(data(&format!("{map}.map"))).unwrap()).unwrap(),
    );
    let g = grid.view();
    let qs = queries(&format!("{map}-random-1.scen"));
    assert_eq!(qs.len(), QUERIES);
    let mut nodes = vec![SearchNode::EMPTY; g.cells()];
    let mut astar_nodes = vec![AStarNode::EMPTY; g.cells()];
    let mut open = vec![OpenSlot::EMPTY; open_capacity(g.cells())];
    let mut out: Box<Path<4096>> = Box::new(Path::new());

    // Same answers before timing anything.
    let mut expanded = 0u64;
    for &(s, t) in &qs {
        let ours = astar::plan(g, s, t, &mut astar_nodes, &mut open, &mut *out).unwrap();
        expanded += ours.expanded as u64;
        let (pf_path, pf_cost) = pathfinding_astar(g, s, t).unwrap();
        let pf = pf_cost as f64 / UNIT as f64;
        assert!(
            (ours.length as f64 - pf).abs() <= 1e-3,
            "{map} {s:?}->{t:?}: ours {} pathfinding {pf}",
            ours.length
        );
        assert_eq!(
            pf_path.first(),
            Some(&(s.y as u32 * g.width() as u32 + s.x as u32))
        );
        let th = theta::plan(g, s, t, &mut nodes, &mut *out).unwrap();
        assert!(th.length <= ours.length + 1e-3);
    }
    eprintln!(
        "{map}: {}x{}, {QUERIES} queries, our A* expands {:.0} cells/query on average",
        g.width(),
        g.height(),
        expanded as f64 / QUERIES as f64
    );

    // Interleaved rounds (ours, then pathfinding, 100 queries each): on a shared machine
    // the best round of each is a fairer ratio than two measurements minutes apart.
    let (mut ours_best, mut pf_best) = (f64::INFINITY, f64::INFINITY);
    for _ in 0..20 {
        let t0 = Instant::now();
        for &(s, t) in &qs {
            black_box(astar::plan(g, s, t, &mut astar_nodes, &mut open, &mut *out).unwrap());
        }
        ours_best = ours_best.min(t0.elapsed().as_secs_f64());
        let t0 = Instant::now();
        for &(s, t) in &qs {
            black_box(pathfinding_astar(g, s, t).unwrap());
        }
        pf_best = pf_best.min(t0.elapsed().as_secs_f64());
    }
    let per_query = |t: f64| t / QUERIES as f64 * 1e6;
    eprintln!(
        "{map}: interleaved best of 20: our A* {:.1} us/query, pathfinding {:.1} us/query, \
         ours/pathfinding = {:.2}",
        per_query(ours_best),
        per_query(pf_best),
        ours_best / pf_best
    );

    let mut group = c.benchmark_group(map);
    group.throughput(Throughput::Elements(QUERIES as u64));
    group.bench_function("astar_ours", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for &(s, t) in &qs {
                sum += astar::plan(g, s, t, &mut astar_nodes, &mut open, &mut *out)
                    .unwrap()
                    .length;
            }
            black_box(sum)
        })
    });
    group.bench_function("theta_ours", |b| {
        b.iter(|| {
            let mut sum = 0.0f32;
            for &(s, t) in &qs {
                sum += theta::plan(g, s, t, &mut nodes, &mut *out).unwrap().length;
            }
            black_box(sum)
        })
    });
    group.bench_function("astar_pathfinding", |b| {
        b.iter(|| {
            let mut sum = 0u64;
            for &(s, t) in &qs {
                sum += pathfinding_astar(g, s, t).unwrap().1;
            }
            black_box(sum)
        })
    });
    group.finish();
}

fn search(c: &mut Criterion) {
    bench_map(c, "warehouse-10-20-10-2-1");
    bench_map(c, "warehouse-20-40-10-2-2");
}

criterion_group!(benches, search);
criterion_main!(benches);

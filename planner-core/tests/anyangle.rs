//! The exact any-angle planner against the visibility graph of obstacle corners (an
//! independent exact method, quadratic, host only, feature `alloc`): equal lengths wherever
//! the graph's path is a valid one, never shorter, and every returned path valid; and,
//! as properties on random maps, against Theta* (never longer, same reachability).

use planner_core::PlanError;
use planner_core::geometry::Cell;
use planner_core::grid::{Grid, GridRef, words_for};
use planner_core::path::{self, Path};
use planner_core::search::anyangle::{self, Link, Mesh, Node, Rect, Roots, Scratch};
use planner_core::search::{SearchNode, theta};
#[cfg(feature = "alloc")]
use planner_core::{grid::GridBuf, search::visibility::VisibilityGraph};
use proptest::prelude::*;
use proptest::test_runner::Config;

struct Planner {
    rects: Vec<Rect>,
    links: Vec<Link>,
    roots: Vec<Roots>,
    open: Vec<Node>,
}

impl Planner {
    fn new(grid: GridRef<'_>) -> Self {
        // Sized exactly: a short buffer would fail the build.
        let (rects, links) = Mesh::count(grid);
        let (w, h) = (grid.width(), grid.height());
        assert!(rects <= anyangle::rects_for(w, h) && links <= anyangle::links_for(w, h));
        Planner {
            rects: vec![Rect::EMPTY; rects],
            links: vec![Link::EMPTY; links],
            roots: vec![Roots::EMPTY; rects],
            open: vec![Node::EMPTY; 1 << 16],
        }
    }

    fn plan(
        &mut self,
        grid: GridRef<'_>,
        s: Cell,
        g: Cell,
        out: &mut Path<4096>,
    ) -> Result<anyangle::AnyAngleStats, PlanError> {
        let mesh = Mesh::build(grid, &mut self.rects, &mut self.links)?;
        let scratch = Scratch {
            roots: &mut self.roots,
            open: &mut self.open,
        };
        anyangle::plan(grid, &mesh, s, g, scratch, out)
    }
}

#[cfg(feature = "alloc")]
#[cfg(feature = "alloc")]
fn random_grid(w: usize, h: usize, density: u32, seed: u64) -> GridBuf {
    let mut state = seed | 1;
    let mut grid = GridBuf::new(w, h).unwrap();
    for y in 0..h {
        for x in 0..w {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            if (state % 100) < density as u64 {
                grid.set_blocked(x, y, true).unwrap();
            }
        }
    }
    grid
}

#[cfg(feature = "alloc")]
#[cfg(feature = "alloc")]
fn check_map(grid: &GridBuf, queries: usize, seed: u64) -> (usize, usize) {
    let v = grid.view();
    let vg = VisibilityGraph::new(v);
    let mut planner = Planner::new(v);
    let free: Vec<Cell> = (0..v.cells())
        .map(|i| v.cell(i))
        .filter(|&c| v.is_free(c))
        .collect();
    let mut state = seed | 1;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state as usize
    };
    let (mut compared, mut exact) = (0, 0);
    for _ in 0..queries {
        if free.len() < 2 {
            break;
        }
        let s = free[next() % free.len()];
        let g = free[next() % free.len()];
        let mut out = Path::<4096>::new();
        let got = planner.plan(v, s, g, &mut out);
        let lb = vg.shortest(v, s, g);
        match (got, lb) {
            (Ok(stats), Some(lb)) => {
                path::validate(v, &out, s, g)
                    .unwrap_or_else(|e| panic!("{s:?}->{g:?}: {e:?} {:?}", &out[..]));
                assert!(
                    stats.optimum as f64 >= lb * (1.0 - 1e-6) - 1e-5,
                    "{s:?}->{g:?} shorter than the bound: {} < {lb}",
                    stats.optimum
                );
                compared += 1;
                if vg.witness(v, s, g, 1e-3).is_some() {
                    let rel = (stats.optimum as f64 - lb) / lb.max(1.0);
                    assert!(rel.abs() < 1e-5, "{s:?}->{g:?}: {} vs {lb}", stats.optimum);
                    let rel = (stats.length as f64 - lb) / lb.max(1.0);
                    assert!(rel < 1e-3, "{s:?}->{g:?}: path {} vs {lb}", stats.length);
                    exact += 1;
                }
            }
            (Err(PlanError::NoValidPath), None) => {}
            (Err(PlanError::NoValidPath), Some(lb)) => {
                // The graph's bound may pass a pinch point that no valid path can.
                assert!(
                    vg.witness(v, s, g, 1e-3).is_none(),
                    "{s:?}->{g:?} reachable ({lb})"
                );
            }
            (got, lb) => panic!("{s:?}->{g:?}: {got:?} vs {lb:?}"),
        }
    }
    (compared, exact)
}

#[cfg(feature = "alloc")]
#[cfg(feature = "alloc")]
#[test]
fn random_maps_match_the_visibility_graph() {
    let mut totals = (0, 0);
    for seed in 1..60u64 {
        let density = [5, 15, 25, 35][seed as usize % 4];
        let grid = random_grid(
            12 + (seed as usize % 7) * 3,
            10 + (seed as usize % 5) * 3,
            density,
            seed,
        );
        let (c, e) = check_map(&grid, 40, seed * 7919);
        totals.0 += c;
        totals.1 += e;
    }
    eprintln!("compared {totals:?}");
    assert!(totals.1 > 1000, "{totals:?}");
}

#[cfg(feature = "alloc")]
#[cfg(feature = "alloc")]
fn movingai(name: &str) -> GridBuf {
    let path = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../tests/data/movingai")
        .join(name);
    let text = std::fs::read(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    GridBuf::parse_movingai(&text, 1 << 20).unwrap()
}

#[cfg(feature = "alloc")]
#[cfg(feature = "alloc")]
#[test]
fn moving_ai_maps_match_the_visibility_graph() {
    for (name, queries) in [
        ("maze-32-32-2.map", 150),
        ("room-32-32-4.map", 150),
        ("random-32-32-10.map", 150),
        ("warehouse-10-20-10-2-1.map", 120),
        ("warehouse-20-40-10-2-2.map", 60),
    ] {
        let grid = movingai(name);
        let (c, e) = check_map(&grid, queries, 0xC0FFEE);
        eprintln!("{name}: compared {c}, exact {e}");
        assert!(e * 10 >= queries * 8, "{name}: {c} {e}");
    }
}

const SIDE: usize = 24;
type Small = Grid<{ words_for(SIDE, SIDE) }>;

fn small_map() -> impl Strategy<Value = (Small, Cell, Cell)> {
    (1..=SIDE, 1..=SIDE, 0u32..50)
        .prop_flat_map(|(w, h, density)| {
            (
                Just((w, h)),
                proptest::collection::vec(0u32..100, w * h),
                Just(density),
                0..w,
                0..h,
                0..w,
                0..h,
            )
        })
        .prop_map(|((w, h), rolls, density, sx, sy, gx, gy)| {
            let mut g = Small::new(w, h).unwrap();
            for (i, roll) in rolls.iter().enumerate() {
                g.set_blocked(i % w, i / w, *roll < density).unwrap();
            }
            let (s, t) = (
                Cell::new(sx as u16, sy as u16),
                Cell::new(gx as u16, gy as u16),
            );
            g.set_blocked(sx, sy, false).unwrap();
            g.set_blocked(gx, gy, false).unwrap();
            (g, s, t)
        })
}

proptest! {
    #![proptest_config(Config { cases: 3000, ..Config::default() })]

    /// Valid paths from start to goal, never longer than Theta*'s (which bends only at
    /// cell centres), the same reachability, and a length within the margin of the
    /// optimum.
    #[test]
    fn never_longer_than_theta_and_always_valid((grid, s, t) in small_map()) {
        let v = grid.view();
        let mut planner = Planner::new(v);
        let mut out = Path::<4096>::new();
        let got = planner.plan(v, s, t, &mut out);
        let mut nodes = vec![SearchNode::EMPTY; v.cells()];
        let mut theta_path = Path::<4096>::new();
        let reference = theta::plan(v, s, t, &mut nodes, &mut theta_path);
        match (got, reference) {
            (Ok(stats), Ok(theta)) => {
                prop_assert!(path::validate(v, &out, s, t).is_ok(), "{:?}", &out[..]);
                prop_assert!(stats.optimum <= theta.length + 1e-4, "{} > {}", stats.optimum, theta.length);
                prop_assert!(stats.length <= theta.length + 2e-3, "{} > {}", stats.length, theta.length);
                prop_assert!(stats.optimum <= stats.length + 1e-4);
                // Each waypoint moves at most eps * sqrt 2 off its corner.
                let slack = 4.0 * anyangle::margin(v) * out.len() as f32;
                prop_assert!(stats.length <= stats.optimum + slack + 1e-4);
            }
            (Err(PlanError::NoValidPath), Err(PlanError::NoValidPath)) => {}
            (got, reference) => prop_assert!(false, "{got:?} vs {reference:?}"),
        }
    }
}

#[test]
fn endpoints_are_checked_and_a_cell_to_itself_is_one_waypoint() {
    let g = Small::parse_rows(b"...\n.@.\n...\n").unwrap();
    let v = g.view();
    let mut planner = Planner::new(v);
    let mut out = Path::<4096>::new();
    let c = |x, y| Cell::new(x, y);
    assert_eq!(
        planner.plan(v, c(1, 1), c(0, 0), &mut out).err(),
        Some(PlanError::StartOccupied)
    );
    assert_eq!(
        planner.plan(v, c(0, 0), c(1, 1), &mut out).err(),
        Some(PlanError::GoalOccupied)
    );
    assert_eq!(
        planner.plan(v, c(3, 0), c(0, 0), &mut out).err(),
        Some(PlanError::StartOutsideMap)
    );
    assert_eq!(
        planner.plan(v, c(0, 0), c(0, 3), &mut out).err(),
        Some(PlanError::GoalOutsideMap)
    );
    let stats = planner.plan(v, c(2, 2), c(2, 2), &mut out).unwrap();
    assert_eq!((out.len(), stats.length), (1, 0.0));
    // Diagonal past the corner is a straight line: touching is the limit, and the
    // returned path bends a margin away from it.
    let stats = planner.plan(v, c(0, 1), c(1, 0), &mut out).unwrap();
    assert!((stats.optimum - 2f32.sqrt()).abs() < 1e-5);
    assert!(path::validate(v, &out, c(0, 1), c(1, 0)).is_ok());
    assert_eq!(out.len(), 3);
}

#[test]
fn pinch_points_are_not_passages() {
    // (1,0) and (0,1) meet only at a corner between two blocked cells.
    let g = Small::parse_rows(b"@.\n.@\n").unwrap();
    let v = g.view();
    let mut planner = Planner::new(v);
    let mut out = Path::<4096>::new();
    assert_eq!(
        planner
            .plan(v, Cell::new(1, 0), Cell::new(0, 1), &mut out)
            .err(),
        Some(PlanError::NoValidPath)
    );
}

#[test]
fn checkerboards_fit_the_documented_bounds() {
    for (w, h) in [(1, 1), (2, 3), (7, 5), (24, 24), (23, 1)] {
        let mut g = Small::new(w, h).unwrap();
        for y in 0..h {
            for x in 0..w {
                g.set_blocked(x, y, (x + y) % 2 == 1).unwrap();
            }
        }
        let (rects, links) = Mesh::count(g.view());
        assert!(rects <= anyangle::rects_for(w, h), "{w}x{h}: {rects}");
        assert!(links <= anyangle::links_for(w, h), "{w}x{h}: {links}");
    }
}

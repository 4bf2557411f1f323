use super::*;
use crate::encoding::corridor::Station;
use crate::grid::{Grid, words_for};
use crate::maps::{MapKind, lab_20x20, lei2024_warehouse};
use crate::optim::any::AnyOptimizer;
use crate::path::{Path, validate};
use crate::search::anyangle::{Link, Node, Rect, Roots};
use crate::search::connectivity;
use std::{boxed::Box, vec};

type G = Grid<{ words_for(40, 40) }>;

struct Scratch {
    nodes: [AStarNode; 1600],
    open: [OpenSlot; 1600],
    guide: Path<1600>,
    visited: [u32; 51],
    rects: [Rect; 1600],
    links: [Link; 1700],
    roots: [Roots; 1600],
    search: [Node; 1600],
}

impl Scratch {
    fn new() -> Box<Self> {
        Box::new(Scratch {
            nodes: [AStarNode::EMPTY; 1600],
            open: [OpenSlot::EMPTY; 1600],
            guide: Path::new(),
            visited: [0; 51],
            rects: [Rect::EMPTY; 1600],
            links: [Link::EMPTY; 1700],
            roots: [Roots::EMPTY; 1600],
            search: [Node::EMPTY; 1600],
        })
    }

    /// The storage for plans on `g` (its mesh built here).
    fn workspace<'a, O>(
        &'a mut self,
        g: &G,
        stations: &'a mut [Station],
        optimizer: &'a mut O,
        out: &'a mut PathView,
    ) -> PlanStorageMut<'a, O> {
        let mesh = Mesh::build(g.view(), &mut self.rects, &mut self.links).unwrap();
        PlanStorageMut {
            anyangle: Some(AnyAngleWorkspace {
                mesh,
                scratch: anyangle::Scratch {
                    roots: &mut self.roots,
                    open: &mut self.search,
                },
            }),
            nodes: &mut self.nodes,
            open: &mut self.open,
            theta: &mut [],
            guide: &mut self.guide,
            visited: &mut self.visited,
            stations,
            optimizer,
            out,
        }
    }

    fn run(
        &mut self,
        g: &G,
        s: Cell,
        t: Cell,
        p: &PlanParams,
    ) -> Result<(PlanReport, Path<1600>), PlanError> {
        let mut stations = [Station::EMPTY; 64];
        let mut out: Path<1600> = Path::new();
        let mut optimizer = AnyOptimizer::<30, 64>::unconfigured();
        let mut ws = self.workspace(g, &mut stations, &mut optimizer, &mut out);
        let r = plan(g.view(), s, t, p, &mut ws, PlanOptions::default())?;
        Ok((r, out))
    }
}

fn quick(algo: AlgorithmKind) -> PlanParams {
    PlanParams {
        iterations: 120,
        ..PlanParams::new(algo)
    }
}

#[test]
fn corridor_paths_are_valid_and_improve_on_initialisation() {
    let mut sc = Scratch::new();
    for kind in [MapKind::Sparse, MapKind::Warehouse] {
        let m = lei2024_warehouse::<{ words_for(40, 40) }>(kind, 40).unwrap();
        for algo in [
            AlgorithmKind::Tclhho,
            AlgorithmKind::Igwo,
            AlgorithmKind::Hho,
            AlgorithmKind::Gwo,
        ] {
            let (r, p) = sc.run(&m.grid, m.start, m.goal, &quick(algo)).unwrap();
            assert_eq!(
                validate(m.grid.view(), &p, m.start, m.goal),
                Ok(()),
                "{kind:?} {algo:?}"
            );
            assert!(r.final_cost < r.initial_cost, "{kind:?} {algo:?} {r:?}");
            assert!(r.length <= r.final_cost + 1e-3);
            assert!(r.evaluations > 0 && r.dimension > 0);
        }
    }
}

#[test]
fn same_seed_same_path_different_seed_may_differ() {
    let mut sc = Scratch::new();
    let m = lei2024_warehouse::<{ words_for(40, 40) }>(MapKind::Sparse, 30).unwrap();
    let p = PlanParams {
        seed: 9,
        ..quick(AlgorithmKind::Tclhho)
    };
    let (a, pa) = sc.run(&m.grid, m.start, m.goal, &p).unwrap();
    let (b, pb) = sc.run(&m.grid, m.start, m.goal, &p).unwrap();
    assert_eq!(a, b);
    assert_eq!(pa, pb);
}

#[test]
fn column_encoding_reproduces_lei2024_warehouse() {
    let mut sc = Scratch::new();
    let m = lei2024_warehouse::<{ words_for(40, 40) }>(MapKind::Sparse, 10).unwrap();
    let p = PlanParams {
        encoding: EncodingKind::Column,
        ..PlanParams::new(AlgorithmKind::Tclhho)
    };
    let (r, path) = sc.run(&m.grid, m.start, m.goal, &p).unwrap();
    assert_eq!(validate(m.grid.view(), &path, m.start, m.goal), Ok(()));
    assert!(r.final_cost < 20.0, "{r:?}");
    let diff = PlanParams {
        init: InitKind::Diffusion,
        ..p
    };
    let (r2, _) = sc.run(&m.grid, m.start, m.goal, &diff).unwrap();
    assert!(r2.final_cost < 20.0, "{r2:?}");
    // Diffusion is only defined for the column encoding.
    let bad = PlanParams {
        encoding: EncodingKind::Corridor,
        ..diff
    };
    assert_eq!(
        sc.run(&m.grid, m.start, m.goal, &bad).unwrap_err(),
        PlanError::InvalidParameters
    );
}

#[test]
fn walk_encoding_reproduces_liu2020_igwo() {
    let mut sc = Scratch::new();
    let lab = lab_20x20::<{ words_for(40, 40) }>().unwrap();
    for rule in [CornerRule::Strict, CornerRule::Loose] {
        let p = PlanParams {
            encoding: EncodingKind::Walk,
            corner_rule: rule,
            walk_steps: 60,
            ..PlanParams::new(AlgorithmKind::Igwo)
        };
        let (r, path) = sc.run(&lab.grid, lab.start, lab.goal, &p).unwrap();
        assert!(validate_walk(lab.grid.view(), &path, rule) || rule == CornerRule::Strict);
        if rule == CornerRule::Strict {
            assert_eq!(
                validate(lab.grid.view(), &path, lab.start, lab.goal),
                Ok(())
            );
        }
        // Octile optimum is at least 19 sqrt 2 = 26.87.
        assert!(
            r.final_cost >= 26.8 && r.final_cost < 40.0,
            "{rule:?} {r:?}"
        );
    }
}

#[test]
fn every_error_from_bad_input() {
    let mut sc = Scratch::new();
    let g = G::parse_rows(b"....@...\n....@...\n....@...\n").unwrap();
    let p = quick(AlgorithmKind::Tclhho);
    let c = Cell::new;
    assert_eq!(
        sc.run(&g, c(9, 0), c(0, 0), &p).unwrap_err(),
        PlanError::StartOutsideMap
    );
    assert_eq!(
        sc.run(&g, c(0, 0), c(0, 9), &p).unwrap_err(),
        PlanError::GoalOutsideMap
    );
    assert_eq!(
        sc.run(&g, c(4, 0), c(0, 0), &p).unwrap_err(),
        PlanError::StartOccupied
    );
    assert_eq!(
        sc.run(&g, c(0, 0), c(4, 1), &p).unwrap_err(),
        PlanError::GoalOccupied
    );
    assert_eq!(
        sc.run(&g, c(0, 0), c(7, 2), &p).unwrap_err(),
        PlanError::NoValidPath
    );
    for bad in [
        PlanParams {
            corridor_radius: f32::NAN,
            ..p
        },
        PlanParams {
            corridor_spacing: -1.0,
            ..p
        },
        PlanParams { population: 0, ..p },
        PlanParams { iterations: 0, ..p },
        PlanParams {
            stagnation: Some(0),
            ..p
        },
        PlanParams {
            walk_beta: f32::INFINITY,
            ..p
        },
        PlanParams {
            guide_relax: f32::NAN,
            ..p
        },
        PlanParams {
            guide_relax: -0.1,
            ..p
        },
        PlanParams {
            guide_relax: 0.6,
            ..p
        },
    ] {
        assert_eq!(
            sc.run(&g, c(0, 0), c(3, 2), &bad).unwrap_err(),
            PlanError::InvalidParameters
        );
    }
    assert_eq!(
        sc.run(
            &g,
            c(0, 0),
            c(3, 2),
            &PlanParams {
                population: 31,
                ..p
            }
        )
        .unwrap_err(),
        PlanError::CapacityExceeded
    );
    // Column encoding cannot go right to left.
    let col = PlanParams {
        encoding: EncodingKind::Column,
        ..p
    };
    assert_eq!(
        sc.run(&g, c(3, 2), c(0, 0), &col).unwrap_err(),
        PlanError::InvalidParameters
    );
    // A wall the column encoding cannot pass in 3 rows: infeasible best -> BudgetExhausted.
    let u = G::parse_rows(b".@...\n.@.@.\n...@.\n").unwrap();
    let col = PlanParams {
        encoding: EncodingKind::Column,
        iterations: 20,
        ..p
    };
    assert_eq!(
        sc.run(&u, c(0, 0), c(4, 0), &col).unwrap_err(),
        PlanError::BudgetExhausted
    );
    // Small buffers.
    let mut nodes = [AStarNode::EMPTY; 4];
    let mut open = [OpenSlot::EMPTY; 4];
    let mut guide: Path<4> = Path::new();
    let mut visited = [0u32; 1];
    let mut out: Path<4> = Path::new();
    let mut ws = PlanStorageMut {
        anyangle: None,
        nodes: &mut nodes,
        open: &mut open,
        theta: &mut [],
        guide: &mut guide,
        visited: &mut visited,
        stations: &mut [Station::EMPTY; 64],
        optimizer: &mut AnyOptimizer::<30, 8>::unconfigured(),
        out: &mut out,
    };
    let p = PlanParams {
        guide: GuideKind::AStar,
        ..p
    };
    assert_eq!(
        plan(
            g.view(),
            c(0, 0),
            c(3, 2),
            &p,
            &mut ws,
            PlanOptions::default(),
        )
        .unwrap_err(),
        PlanError::CapacityExceeded
    );
}

#[test]
fn trivial_queries_and_interrupts() {
    let mut sc = Scratch::new();
    let g = G::new(8, 8).unwrap();
    let (r, p) = sc
        .run(
            &g,
            Cell::new(2, 2),
            Cell::new(2, 2),
            &quick(AlgorithmKind::Tclhho),
        )
        .unwrap();
    assert_eq!((r.length, r.stop, p.len()), (0.0, PlanStop::Trivial, 1));
    let (r, _) = sc
        .run(
            &g,
            Cell::new(2, 2),
            Cell::new(3, 3),
            &quick(AlgorithmKind::Tclhho),
        )
        .unwrap();
    assert_eq!(r.stop, PlanStop::Trivial);
    let m = lei2024_warehouse::<{ words_for(40, 40) }>(MapKind::Warehouse, 30).unwrap();
    let mut stations = [Station::EMPTY; 64];
    let mut out: Path<1600> = Path::new();
    let mut optimizer = AnyOptimizer::<30, 64>::unconfigured();
    let mut ws = sc.workspace(&m.grid, &mut stations, &mut optimizer, &mut out);
    let mut calls = 0;
    let mut hist = [0.0f32; 500];
    let mut interrupt = || {
        calls += 1;
        calls > 5
    };
    let options = PlanOptions {
        history: &mut hist,
        interrupt: Some(&mut interrupt),
    };
    let r = plan(
        m.grid.view(),
        m.start,
        m.goal,
        &quick(AlgorithmKind::Tclhho),
        &mut ws,
        options,
    )
    .unwrap();
    assert_eq!(
        (r.stop, r.iterations, r.history_len),
        (PlanStop::Interrupted, 5, 5)
    );
    assert!(hist[..5].windows(2).all(|w| w[1] <= w[0]));
    assert_eq!(validate(m.grid.view(), &out, m.start, m.goal), Ok(()));
}

#[test]
fn aco_baseline_finds_valid_paths() {
    let m = lei2024_warehouse::<{ words_for(40, 40) }>(MapKind::Sparse, 30).unwrap();
    let cells = 900;
    let mut labels = [0u32; 900];
    connectivity::label(m.grid.view(), &mut labels).unwrap();
    let (mut tau, mut delta) = (vec![0.0f32; 8 * cells], vec![0.0f32; 8 * cells]);
    let (mut tour, mut best) = (vec![0u32; cells], vec![0u32; cells]);
    let mut visited = [0u32; 29];
    let mut ws = aco::AcoWorkspace {
        tau: &mut tau,
        delta: &mut delta,
        visited: &mut visited,
        tour: &mut tour,
        best: &mut best,
        labels: &labels,
    };
    let mut out: Path<1600> = Path::new();
    let p = aco::AcoParams {
        iterations: 40,
        ..Default::default()
    };
    let r = aco::plan(
        m.grid.view(),
        m.start,
        m.goal,
        &p,
        &mut ws,
        &mut out,
        &mut [],
    )
    .unwrap();
    assert_eq!(validate(m.grid.view(), &out, m.start, m.goal), Ok(()));
    assert!(r.final_cost >= 29.0 * 2f32.sqrt() - 1e-3);
    let bad = aco::AcoParams { rho: 0.0, ..p };
    assert_eq!(
        aco::plan(
            m.grid.view(),
            m.start,
            m.goal,
            &bad,
            &mut ws,
            &mut out,
            &mut []
        )
        .unwrap_err(),
        PlanError::InvalidParameters
    );
}

/// A lattice of shelves (1-cell gaps every 6 columns, aisles every 3 rows): every staircase
/// ties under octile costs, so the A* route's class is arbitrary; the any-angle route's is
/// the shortest one (checked against the visibility graph's bound).
#[cfg(feature = "alloc")]
#[test]
fn anyangle_guide_finds_the_shortest_class() {
    use crate::search::visibility::VisibilityGraph;
    let mut rows = std::string::String::new();
    for y in 0..30 {
        for x in 0..40 {
            let shelf = y % 3 != 2 && x % 6 != 0;
            rows.push(if shelf && (2..28).contains(&y) {
                '@'
            } else {
                '.'
            });
        }
        rows.push('\n');
    }
    let g = G::parse_rows(rows.as_bytes()).unwrap();
    let (s, t) = (Cell::new(39, 29), Cell::new(0, 0));
    let vg = VisibilityGraph::new(g.view());
    let bound = vg.shortest(g.view(), s, t).unwrap() as f32;
    let base = PlanParams {
        iterations: 200,
        ..PlanParams::new(AlgorithmKind::Tclhho)
    };
    let mut scratch = Scratch::new();
    let astar = PlanParams {
        guide: GuideKind::AStar,
        ..base
    };
    let (astar_guided, _) = scratch.run(&g, s, t, &astar).unwrap();
    let (report, path) = scratch.run(&g, s, t, &base).unwrap();
    assert_eq!(validate(g.view(), &path, s, t), Ok(()));
    assert!(report.length >= bound - 1e-3);
    assert!(
        report.length <= bound * 1.002,
        "{} vs {bound}",
        report.length
    );
    assert!(report.length < astar_guided.length - 0.5);
    // Stations half a cell off the corners: still in the shortest class, a little longer.
    let relaxed = PlanParams {
        guide_relax: 0.5,
        ..base
    };
    let (report, path) = scratch.run(&g, s, t, &relaxed).unwrap();
    assert_eq!(validate(g.view(), &path, s, t), Ok(()));
    assert!(
        report.length <= bound * 1.05,
        "{} vs {bound}",
        report.length
    );
    assert!(report.length < astar_guided.length, "{}", report.length);
}

/// The any-angle guide needs its workspace: without one the plan is refused.
#[test]
fn anyangle_guide_without_its_workspace_is_invalid() {
    let g = G::new(8, 8).unwrap();
    let (mut nodes, mut open) = ([AStarNode::EMPTY; 64], [OpenSlot::EMPTY; 64]);
    let mut guide: Path<64> = Path::new();
    let mut out: Path<64> = Path::new();
    let mut ws = PlanStorageMut {
        anyangle: None,
        nodes: &mut nodes,
        open: &mut open,
        theta: &mut [],
        guide: &mut guide,
        visited: &mut [],
        stations: &mut [Station::EMPTY; 16],
        optimizer: &mut AnyOptimizer::<30, 16>::unconfigured(),
        out: &mut out,
    };
    let r = plan(
        g.view(),
        Cell::new(0, 0),
        Cell::new(7, 7),
        &quick(AlgorithmKind::Tclhho),
        &mut ws,
        PlanOptions::default(),
    );
    assert_eq!(r.unwrap_err(), PlanError::InvalidParameters);
}

/// Only the walk encoding reads `visited`: the others plan with an empty slice (firmware
/// saves the bitset), and the walk encoding refuses it with a typed error, not a panic.
#[test]
fn visited_bitset_only_for_the_walk_encoding() {
    let lab = lab_20x20::<{ words_for(40, 40) }>().unwrap();
    let mut nodes = vec![AStarNode::EMPTY; 400];
    let mut open = vec![OpenSlot::EMPTY; 400];
    let mut guide: Path<400> = Path::new();
    let mut out: Path<400> = Path::new();
    for (encoding, want) in [
        (EncodingKind::Corridor, None),
        (EncodingKind::Column, None),
        (EncodingKind::Walk, Some(PlanError::CapacityExceeded)),
    ] {
        let mut ws = PlanStorageMut {
            anyangle: None,
            nodes: &mut nodes,
            open: &mut open,
            theta: &mut [],
            guide: &mut guide,
            visited: &mut [],
            stations: &mut [Station::EMPTY; 64],
            optimizer: &mut *Box::new(AnyOptimizer::<30, 64>::unconfigured()),
            out: &mut out,
        };
        let p = PlanParams {
            encoding,
            iterations: 20,
            guide: GuideKind::AStar,
            ..PlanParams::new(AlgorithmKind::Igwo)
        };
        let r = plan(
            lab.grid.view(),
            lab.start,
            lab.goal,
            &p,
            &mut ws,
            PlanOptions::default(),
        );
        match want {
            Some(e) => assert_eq!(r.unwrap_err(), e, "{encoding:?}"),
            // The column encoding may end infeasible (BudgetExhausted); never a capacity error.
            None => assert_ne!(r.err(), Some(PlanError::CapacityExceeded), "{encoding:?}"),
        }
    }
}

/// On a dense lattice of two-cell racks the exact search would cost far more than A*: past
/// its bound the A* route guides the plan, and the report says so. (The lattice is large
/// enough for the bound to be a quarter of its cells, above the small maps' floor.)
#[cfg(feature = "alloc")]
#[test]
fn dense_lattices_fall_back_to_the_a_star_guide() {
    use super::aco::AcoParams;
    use super::owned::{HostPlanner, PlanChoice};
    use crate::grid::GridBuf;
    let side = 600;
    let mut g = GridBuf::new(side, side).unwrap();
    for y in 2..side - 2 {
        for x in 2..side - 2 {
            if (y - 2) % 8 < 6 && (x - 2) % 4 < 2 {
                g.set_blocked(x, y, true).unwrap();
            }
        }
    }
    let mut planner = HostPlanner::new();
    planner.prepare(g.view()).unwrap();
    let mut out: Box<Path<65536>> = Box::new(Path::new());
    let params = PlanParams {
        iterations: 30,
        ..PlanParams::new(AlgorithmKind::Tclhho)
    };
    let (s, t) = (Cell::new(0, 0), Cell::new(599, 599));
    let run = |planner: &mut HostPlanner, out: &mut Path<65536>, s: Cell, t: Cell| {
        planner
            .plan(
                g.view(),
                s,
                t,
                &PlanChoice {
                    kind: PlannerKind::Swarm(AlgorithmKind::Tclhho),
                    params,
                    aco: AcoParams::default(),
                },
                out,
                PlanOptions::default(),
            )
            .unwrap()
    };
    let far = run(&mut planner, &mut out, s, t);
    assert_eq!(far.report.unwrap().guide, Some(GuideRoute::AStar));
    assert_eq!(validate(g.view(), &out[..], s, t), Ok(()));
    // A short query stays within the bound.
    let near = run(&mut planner, &mut out, s, Cell::new(20, 1));
    assert_eq!(near.report.unwrap().guide, Some(GuideRoute::AnyAngle));
}

/// [`PlanStorage`] plans as [`plan`] does over the same buffers with [`HhoOrGwo`], switches
/// family in place, and refuses a map it was not prepared for.
#[test]
fn plan_storage_plans_like_the_borrowed_buffers() {
    let m = lei2024_warehouse::<{ words_for(40, 40) }>(MapKind::Warehouse, 40).unwrap();
    let mut storage = Box::new(PlanStorage::<30, 64, 256, 144, 272, 300>::new());
    let p = |algo| PlanParams {
        iterations: 40,
        ..PlanParams::new(algo)
    };
    assert_eq!(
        storage.plan(
            m.grid.view(),
            m.start,
            m.goal,
            &p(AlgorithmKind::Tclhho),
            PlanOptions::default()
        ),
        Err(PlanError::InvalidParameters),
        "not prepared"
    );
    storage.prepare(m.grid.view()).unwrap();
    for algo in [
        AlgorithmKind::Tclhho,
        AlgorithmKind::Igwo,
        AlgorithmKind::Tclhho,
    ] {
        let r = storage
            .plan(
                m.grid.view(),
                m.start,
                m.goal,
                &p(algo),
                PlanOptions::default(),
            )
            .unwrap();
        assert_eq!(
            validate(m.grid.view(), storage.path(), m.start, m.goal),
            Ok(())
        );
        // The same plan over borrowed buffers.
        let mut sc = Scratch::new();
        let mut stations = [Station::EMPTY; 64];
        let mut out: Path<1600> = Path::new();
        let mut optimizer = Box::new(HhoOrGwo::<30, 64>::unconfigured());
        let mut ws = sc.workspace(&m.grid, &mut stations, &mut *optimizer, &mut out);
        let again = plan(
            m.grid.view(),
            m.start,
            m.goal,
            &p(algo),
            &mut ws,
            PlanOptions::default(),
        )
        .unwrap();
        assert_eq!(
            (r.length, r.evaluations),
            (again.length, again.evaluations),
            "{algo:?}"
        );
        assert_eq!(&storage.path()[..], &out[..]);
    }
    // PSO is not in the HHO or GWO family.
    assert_eq!(
        storage.plan(
            m.grid.view(),
            m.start,
            m.goal,
            &p(AlgorithmKind::Pso),
            PlanOptions::default()
        ),
        Err(PlanError::InvalidParameters)
    );
    // Another map (one more blocked cell) needs its own mesh.
    let mut other = m.grid.clone();
    let free = (0..1600)
        .map(|i| other.view().cell(i))
        .find(|c| other.view().is_free(*c) && *c != m.start && *c != m.goal);
    let c = free.unwrap();
    other.set_blocked(c.x as usize, c.y as usize, true).unwrap();
    assert_eq!(
        storage.plan(
            other.view(),
            m.start,
            m.goal,
            &p(AlgorithmKind::Tclhho),
            PlanOptions::default()
        ),
        Err(PlanError::InvalidParameters)
    );
}

/// Fewer stations than the optimizer's dimension would cap the plan silently: refused.
#[test]
fn fewer_stations_than_dimensions_is_a_capacity_error() {
    let m = lei2024_warehouse::<{ words_for(40, 40) }>(MapKind::Warehouse, 40).unwrap();
    let mut sc = Scratch::new();
    let mut stations = [Station::EMPTY; 63];
    let mut out: Path<1600> = Path::new();
    let mut optimizer = Box::new(HhoOrGwo::<30, 64>::unconfigured());
    let mut ws = sc.workspace(&m.grid, &mut stations, &mut *optimizer, &mut out);
    let p = PlanParams::new(AlgorithmKind::Tclhho);
    assert_eq!(
        plan(
            m.grid.view(),
            m.start,
            m.goal,
            &p,
            &mut ws,
            PlanOptions::default()
        ),
        Err(PlanError::CapacityExceeded)
    );
}

/// The blended objective keeps the desired clearance where the free space allows it and
/// stays valid; length alone hugs the obstacle's corners; bad weights are refused.
#[cfg(all(feature = "alloc", feature = "blend"))]
#[test]
fn blended_plans_keep_their_clearance() {
    use super::aco::AcoParams;
    use super::owned::{HostPlanner, PlanChoice};
    use crate::encoding::blend::Blend;
    use crate::grid::GridBuf;
    use crate::path::clearance;
    // A block in the middle of a 30 x 13 room, 5 free rows above and below it.
    let mut g = GridBuf::new(30, 13).unwrap();
    for y in 5..=7 {
        for x in 12..=17 {
            g.set_blocked(x, y, true).unwrap();
        }
    }
    let mut planner = HostPlanner::new();
    planner.prepare(g.view()).unwrap();
    let (s, t) = (Cell::new(2, 6), Cell::new(27, 6));
    let mut out: Box<Path<1024>> = Box::new(Path::new());
    let mut run = |algorithm, blend| {
        let choice = PlanChoice {
            kind: PlannerKind::Swarm(algorithm),
            params: PlanParams {
                blend,
                ..PlanParams::host(algorithm)
            },
            aco: AcoParams::default(),
        };
        let r = planner.plan(g.view(), s, t, &choice, &mut *out, PlanOptions::default());
        r.map(|o| (o, out.to_vec()))
    };
    let wide = Blend {
        clearance: 2.0,
        clearance_weight: 4.0,
        turn_weight: 0.5,
    };
    for algorithm in [AlgorithmKind::Tclhho, AlgorithmKind::Igwo] {
        let (short, short_path) = run(algorithm, Blend::LENGTH).unwrap();
        let (blended, path) = run(algorithm, wide).unwrap();
        assert_eq!(validate(g.view(), &path, s, t), Ok(()));
        let (c_short, c_blend) = (
            clearance(g.view(), &short_path, 10.0),
            clearance(g.view(), &path, 10.0),
        );
        assert!(
            c_short < 0.1,
            "{algorithm:?} length alone: clearance {c_short}"
        );
        assert!(
            c_blend >= 1.95,
            "{algorithm:?} blended: clearance {c_blend} {path:?}"
        );
        assert!(blended.length < short.length * 1.1, "{blended:?} {short:?}");
    }
    let nan = Blend {
        turn_weight: f32::NAN,
        ..Blend::LENGTH
    };
    assert_eq!(
        run(AlgorithmKind::Tclhho, nan).err(),
        Some(PlanError::InvalidParameters)
    );
}

/// With a turning term, a blended plan across a block of one-cell aisles takes the Theta*
/// route as its guide (along an aisle) instead of the shortest path's staircase through the
/// shelf gaps, and keeps to the aisle centres (half a cell, the most there is).
#[cfg(all(feature = "alloc", feature = "blend"))]
#[test]
fn blended_plans_prefer_the_smoother_guide() {
    use super::aco::AcoParams;
    use super::owned::{HostPlanner, PlanChoice};
    use crate::encoding::blend::Blend;
    use crate::grid::GridBuf;
    use crate::path::{clearance, turns};
    // Shelves two rows deep between one-cell aisles, a one-cell gap every 11 columns, open
    // floor left and right (Moving AI's warehouse-10-20-10-2-1 in small).
    let (w, h) = (70, 31);
    let mut g = GridBuf::new(w, h).unwrap();
    for y in 2..h - 2 {
        for x in 12..w - 12 {
            if (y - 2) % 3 < 2 && (x - 12) % 11 < 10 {
                g.set_blocked(x, y, true).unwrap();
            }
        }
    }
    let mut planner = HostPlanner::new();
    planner.prepare(g.view()).unwrap();
    let (s, t) = (Cell::new(66, 28), Cell::new(3, 2));
    let mut out: Box<Path<1024>> = Box::new(Path::new());
    let mut run = |kind, blend| {
        let choice = PlanChoice {
            kind,
            params: PlanParams {
                blend,
                ..PlanParams::host(AlgorithmKind::Tclhho)
            },
            aco: AcoParams::default(),
        };
        let o = planner
            .plan(g.view(), s, t, &choice, &mut *out, PlanOptions::default())
            .unwrap();
        (o, out.to_vec())
    };
    let smooth = Blend {
        clearance: 0.5,
        clearance_weight: 16.0,
        turn_weight: 1.0,
    };
    let (_, shortest) = run(PlannerKind::AnyAngle, Blend::LENGTH);
    let (_, theta) = run(PlannerKind::Theta, Blend::LENGTH);
    let (blended, path) = run(PlannerKind::Swarm(AlgorithmKind::Tclhho), smooth);
    assert_eq!(validate(g.view(), &path, s, t), Ok(()));
    let report = blended.report.unwrap();
    assert_eq!(report.guide, Some(GuideRoute::Theta));
    assert!(turns(&shortest) > 2 * turns(&path), "{shortest:?} {path:?}");
    assert!(turns(&path) <= turns(&theta), "{theta:?} {path:?}");
    let c = clearance(g.view(), &path, 1.0);
    assert!(c >= 0.49, "clearance {c}: {path:?}");
}

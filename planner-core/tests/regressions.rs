//! Regression tests for bugs found while proving the core (one test per bug).

use planner_core::geometry::{Cell, Point, line_of_sight, segment_is_clear};
use planner_core::grid::{Grid, words_for};

type Big = Grid<{ words_for(4096, 4096) }>;

/// `segment_is_clear` used to evaluate cell-centre segments in `f32` too, and on big maps
/// its rounding (ulp 2.4e-4 near y = 3000) exceeded the `1/8192 - TOUCH_EPS` margin by
/// which such a segment can miss a cell: it rejected this segment, which misses cell
/// (3072, 3001) by 1/8192, while `line_of_sight` accepted it. Theta* (which uses the exact
/// check) would then return paths that `path::validate` rejects.
#[test]
fn segment_is_clear_agrees_with_line_of_sight_on_a_4096_map() {
    // The grid is several MiB and may be built on the stack before it is boxed.
    std::thread::Builder::new()
        .stack_size(64 << 20)
        .spawn(segment_check_on_a_4096_map)
        .unwrap()
        .join()
        .unwrap();
}

fn segment_check_on_a_4096_map() {
    let mut g: Box<Big> = Box::new(Big::new(4096, 4096).unwrap());
    g.set_blocked(3072, 3001, true).unwrap();
    let (a, b) = (Cell::new(0, 3000), Cell::new(4095, 3002));
    assert!(line_of_sight(g.view(), a, b));
    assert!(segment_is_clear(g.view(), a.center(), b.center()));
    assert!(segment_is_clear(g.view(), b.center(), a.center()));
    // A real crossing on the same line stays a collision: at x = 2047.5 the line is at
    // y = 3001 exactly, inside row 3001 of column 2048...
    g.set_blocked(2048, 3001, true).unwrap();
    assert!(!line_of_sight(g.view(), a, b));
    assert!(!segment_is_clear(g.view(), a.center(), b.center()));
    // ...and fractional points still go through the conservative f32 path.
    assert!(!segment_is_clear(
        g.view(),
        Point::new(0.0, 3000.0),
        Point::new(4095.0, 3002.5)
    ));
}

/// `Point::cell` documents "ties go to the lower index" but computed `floor(v + 1/2)`,
/// which sends a point on the edge between two cells to the upper one, and rounds
/// 0.49999997 + 0.5 up to 1.0, sending a point strictly inside cell 0 to cell 1.
#[test]
fn point_cell_sends_ties_to_the_lower_index() {
    let g = Grid::<{ words_for(4, 4) }>::new(4, 4).unwrap();
    let v = g.view();
    assert_eq!(Point::new(0.5, 1.5).cell(v), Some(Cell::new(0, 1)));
    assert_eq!(Point::new(0.499_999_97, 0.0).cell(v), Some(Cell::new(0, 0)));
    assert_eq!(Point::new(0.500_000_06, 0.0).cell(v), Some(Cell::new(1, 0)));
    assert_eq!(Point::new(2.0, 3.0).cell(v), Some(Cell::new(2, 3)));
    assert_eq!(Point::new(3.51, 0.0).cell(v), None);
    assert_eq!(Point::new(-0.4, 0.0).cell(v), Some(Cell::new(0, 0)));
    // Ties go to the lower index at the map's edges too: -0.5 lies between cell -1
    // (outside) and cell 0, and 3.5 between cell 3 and cell 4 (outside).
    assert_eq!(Point::new(-0.5, 0.0).cell(v), None);
    assert_eq!(Point::new(3.5, 0.0).cell(v), Some(Cell::new(3, 0)));
    assert_eq!(Point::new(f32::NAN, 0.0).cell(v), None);
}

/// The planners no longer clear all search nodes per query: they reset what they touched
/// on every exit. After an early error (path buffer too small, mid-way through writing the
/// path) and after interleaved A* / Theta* runs, the same storage still gives the answers
/// of fresh storage. (Test builds also `debug_assert` that storage is clean on entry.)
#[test]
fn search_storage_is_clean_after_every_exit() {
    use planner_core::PlanError;
    use planner_core::path::Path;
    use planner_core::search::astar::{AStarNode, OpenSlot};
    use planner_core::search::{SearchNode, astar, theta};
    let g = Grid::<{ words_for(8, 6) }>::parse_rows(
        b"........\n.@@@@@..\n......@.\n.@@@@.@.\n.@....@.\n...@@...\n",
    )
    .unwrap();
    let v = g.view();
    let (s, t) = (Cell::new(0, 0), Cell::new(7, 5));
    let mut reused = vec![SearchNode::EMPTY; v.cells()];
    let mut astar_reused = vec![AStarNode::EMPTY; v.cells()];
    let mut open = vec![OpenSlot::EMPTY; v.cells()];
    let mut tiny: Path<3> = Path::new();
    for _ in 0..3 {
        assert_eq!(
            astar::plan(v, s, t, &mut astar_reused, &mut open, &mut tiny),
            Err(PlanError::CapacityExceeded)
        );
        assert_eq!(
            theta::plan(v, Cell::new(2, 4), t, &mut reused, &mut tiny),
            Err(PlanError::CapacityExceeded)
        );
        for (a, b) in [(s, t), (t, s), (Cell::new(2, 4), Cell::new(7, 0))] {
            let (mut p1, mut p2): (Path<64>, Path<64>) = (Path::new(), Path::new());
            let mut fresh = vec![AStarNode::EMPTY; v.cells()];
            let mut fresh_open = vec![OpenSlot::EMPTY; v.cells()];
            assert_eq!(
                astar::plan(v, a, b, &mut astar_reused, &mut open, &mut p1),
                astar::plan(v, a, b, &mut fresh, &mut fresh_open, &mut p2)
            );
            assert_eq!(p1, p2);
            let mut fresh = vec![SearchNode::EMPTY; v.cells()];
            assert_eq!(
                theta::plan(v, a, b, &mut reused, &mut p1),
                theta::plan(v, a, b, &mut fresh, &mut p2)
            );
            assert_eq!(p1, p2);
        }
    }
}

/// `prune_collinear` merged "collinear" nodes with a relative tolerance of 1e-6, so on a
/// warehouse-sized map it removed a node 8e-5 off the chord: the valid path
/// (0, y0) -> (170, y0 - 8e-5) -> (340, y0), which clears the blocked cell (170, 2) by
/// 1.5e-4, became the chord at y0 = 1.5 - 7e-5, which `validate` rejects (it passes within
/// `TOUCH_EPS` of the cell). The doc promises the shape never changes: only exactly
/// collinear nodes may go.
#[test]
fn prune_collinear_keeps_a_bend_that_avoids_an_obstacle() {
    use planner_core::path::{self, Path};
    let mut g = Grid::<{ words_for(341, 5) }>::new(341, 5).unwrap();
    g.set_blocked(170, 2, true).unwrap();
    let v = g.view();
    let y0 = 1.5f32 - 7e-5;
    let mut p: Path<4> = [
        Point::new(0.0, y0),
        Point::new(170.0, y0 - 8e-5),
        Point::new(340.0, y0),
    ]
    .into_iter()
    .collect();
    let valid = |p: &[Point]| p.windows(2).all(|w| segment_is_clear(v, w[0], w[1]));
    assert!(valid(&p));
    path::prune_collinear(&mut p);
    assert_eq!(p.len(), 3, "{p:?}");
    assert!(valid(&p));
    // Exactly collinear nodes (also fractional ones) still go.
    let mut q: Path<4> = [
        Point::new(0.0, 0.5),
        Point::new(100.0, 1.0),
        Point::new(200.0, 1.5),
    ]
    .into_iter()
    .collect();
    path::prune_collinear(&mut q);
    assert_eq!(&q[..], &[Point::new(0.0, 0.5), Point::new(200.0, 1.5)]);
}

/// `segment_clearance` scanned only the ring of outside cells next to the map, so for a
/// segment with an end beyond that ring it returned the distance to the ring instead of 0
/// (the segment touches outside cells, which count as blocked). Found by the property
/// test `segment_clearance_matches_oracle`.
#[test]
fn segment_clearance_is_zero_off_the_map() {
    use planner_core::geometry::segment_clearance;
    let g = Grid::<{ words_for(3, 3) }>::new(3, 3).unwrap();
    let v = g.view();
    let c = |a: (f32, f32), b: (f32, f32)| {
        segment_clearance(v, Point::new(a.0, a.1), Point::new(b.0, b.1), 5.0)
    };
    assert_eq!(c((-3.0, 0.0), (-3.0, 2.0)), 0.0); // was 1.5
    assert_eq!(c((1.0, 1.0), (9.0, 1.0)), 0.0); // ends beyond the ring
    assert_eq!(c((1.0, 1.0), (1.0, 2.5)), 0.0); // ends on the map's edge
    let tiny = Grid::<1>::new(1, 1).unwrap();
    let d = segment_clearance(
        tiny.view(),
        Point::new(0.0, 1.59375),
        Point::new(18.53125, 0.4375),
        4.0,
    );
    assert_eq!(d, 0.0); // was 1.6e-4
    // On the map nothing changes: the centre of a free 3 x 3 map is 1.5 from the outside.
    assert_eq!(c((1.0, 1.0), (1.0, 1.0)), 1.5);
}

/// Firmware keeps one `AStarNode` per cell and an open list in `static`s under a 48 KiB
/// RAM budget (issue 8): 4 bytes a cell and 12 an open slot. Theta*'s node stays 24 bytes.
#[test]
fn search_node_sizes() {
    use planner_core::search::astar::{AStarNode, OpenSlot};
    assert_eq!(core::mem::size_of::<AStarNode>(), 4);
    assert_eq!(core::mem::size_of::<OpenSlot>(), 12);
    assert_eq!(core::mem::size_of::<planner_core::search::SearchNode>(), 24);
}

/// A search that outgrows a caller-chosen open list fails with `CapacityExceeded`, leaves
/// the nodes clean (the next search with room is identical to one on fresh storage), and
/// `open_peak` is exactly the capacity it needed.
#[test]
fn astar_open_list_capacity() {
    use planner_core::PlanError;
    use planner_core::path::Path;
    use planner_core::search::astar::{self, AStarNode, OpenSlot};
    let g = Grid::<{ words_for(8, 6) }>::parse_rows(
        b"........\n.@@@@@..\n......@.\n.@@@@.@.\n.@....@.\n...@@...\n",
    )
    .unwrap();
    let v = g.view();
    let (s, t) = (Cell::new(0, 0), Cell::new(7, 5));
    let mut nodes = vec![AStarNode::EMPTY; v.cells()];
    let mut open = vec![OpenSlot::EMPTY; astar::open_capacity(v.cells())];
    let mut p: Path<64> = Path::new();
    let full = astar::plan(v, s, t, &mut nodes, &mut open, &mut p).unwrap();
    let want = p.clone();
    let peak = full.open_peak as usize;
    for cap in 0..peak {
        assert_eq!(
            astar::plan(v, s, t, &mut nodes, &mut open[..cap], &mut p),
            Err(PlanError::CapacityExceeded),
            "capacity {cap}"
        );
    }
    assert_eq!(
        astar::plan(v, s, t, &mut nodes, &mut open[..peak], &mut p),
        Ok(full)
    );
    assert_eq!(p, want);
}

/// Found by the `search_inflate` fuzz target: `inflate_into` scanned `ceil(radius)` cells
/// in every direction, so a huge finite radius (1e30) looped for ever. Offsets beyond the
/// map's longer side now stop there (they land outside the map, which is blocked anyway),
/// and a huge radius blocks every cell, as the border is within reach of all of them.
#[test]
fn inflate_with_a_huge_radius_terminates_and_blocks_everything() {
    let g = Grid::<{ words_for(6, 4) }>::parse_rows(b"......\n......\n......\n......\n").unwrap();
    let mut out = Grid::<{ words_for(6, 4) }>::new(1, 1).unwrap();
    for radius in [1e30f32, f32::MAX, 1e6, 7.5] {
        g.inflate_into(radius, &mut out).unwrap();
        assert_eq!(out.view().blocked_count(), 24, "radius {radius}");
    }
    // A radius of one cell blocks exactly the border ring (outside the map is blocked).
    g.inflate_into(1.0, &mut out).unwrap();
    assert_eq!(out.view().blocked_count(), 6 * 4 - 4 * 2);
}

//! Property tests of the grid, the collision rule and the reference planners on random maps.
//!
//! Every oracle here is written from scratch in this file and shares no code with the
//! crate: an exact integer segment/square test (separating axes), a BFS over the 8-connected
//! moves, and an `f64` Dijkstra. The crate's own `path::validate`, `segment_is_clear` and
//! `line_of_sight` are only ever the things under test.
//!
//! Random maps are 1..=24 cells a side with obstacle density 0..0.5; endpoints may be
//! blocked or up to two cells outside. What each property proves:
//! - `planners_agree_with_oracles`: (a) A* and Theta* paths start and end at the requested
//!   centres and pass the exact separating-axis validator; (b) Theta* <= A* + 1e-3;
//!   (c) the error is `NoValidPath` exactly when BFS and `connected` say unreachable, and the
//!   endpoint errors are the right variants in the documented order; (e) A* = `f64`
//!   Dijkstra; (f) pruning and shortcutting the planners' paths keeps them valid and no
//!   longer;
//! - `labels_match_bfs_components`: (c) labels partition free cells as BFS does;
//! - `pruning_keeps_random_routes_valid`, `pruning_keeps_fractional_paths_valid`: (f) on
//!   grid routes with revisits, reversals and repeats, and on fractional (dyadic) waypoints;
//! - `collision_checks_agree`: (d) `line_of_sight` = `segment_is_clear` on every pair of
//!   cell centres (and = the exact validator on a sample);
//! - `line_of_sight_on_large_maps`: (d) the same oracle on sparse maps up to 300 x 300;
//! - `segment_is_clear_is_conservative`: on fractional points, accepted => exactly clear,
//!   and a segment a whole cell away from everything is accepted;
//! - `blocked_cells_touched_counts_exactly`: the count of blocked (or outside) cells a
//!   segment between cell centres touches equals the exact oracle's, for every pair within
//!   one column of each other (the column encoding's steps) and a sample of others;
//! - `hull_blockers_decide_their_segments`: on segments in a hull, the blocked cells
//!   `hull_blockers` lists give `segment_is_clear`'s verdict exactly
//!   (`segment_is_clear_among`);
//! - `hull_is_clear_proves_its_segments`: a hull accepted by `hull_is_clear` holds only
//!   segments that `segment_is_clear` and the exact rule accept, and a hull a cell and a half
//!   away from everything is accepted;
//! - `segment_clearance_matches_oracle`: clearance = an `f64` segment/square distance oracle;
//! - `inflation_matches_oracle`: `inflate_into` blocks exactly the cells closer than `r`;
//! - `parser_*`: (g) no panic on arbitrary or mutated input, and generated maps round-trip.

use planner_core::PlanError;
use planner_core::geometry::{
    Cell, Point, blocked_cells_touched, hull_blockers, hull_is_clear, hull_margin, line_of_sight,
    segment_clearance, segment_is_clear, segment_is_clear_among,
};
use planner_core::grid::{Grid, words_for};
use planner_core::path::{self, Path};
use planner_core::search::astar::{AStarNode, OpenSlot, open_capacity};
use planner_core::search::{SearchNode, astar, connectivity, theta};
use proptest::prelude::*;
use proptest::test_runner::Config;
use std::cmp::Reverse;
use std::collections::{BinaryHeap, VecDeque};

const MAX_SIDE: usize = 24;
type G = Grid<{ words_for(MAX_SIDE, MAX_SIDE) }>;
type Buf = Path<{ MAX_SIDE * MAX_SIDE + 1 }>;

/// A random map: its size and row-major blocked flags.
#[derive(Clone, Debug)]
struct Map {
    w: usize,
    h: usize,
    blocked: Vec<bool>,
}

impl Map {
    fn blocked(&self, x: i64, y: i64) -> bool {
        x < 0
            || y < 0
            || x >= self.w as i64
            || y >= self.h as i64
            || self.blocked[y as usize * self.w + x as usize]
    }

    fn grid(&self) -> G {
        let mut g = G::new(self.w, self.h).unwrap();
        for y in 0..self.h {
            for x in 0..self.w {
                g.set_blocked(x, y, self.blocked[y * self.w + x]).unwrap();
            }
        }
        g
    }

    fn text(&self) -> String {
        let mut s = format!("type octile\nheight {}\nwidth {}\nmap\n", self.h, self.w);
        for y in 0..self.h {
            for x in 0..self.w {
                s.push(if self.blocked[y * self.w + x] {
                    '@'
                } else {
                    '.'
                });
            }
            s.push('\n');
        }
        s
    }
}

fn map_strategy() -> impl Strategy<Value = Map> {
    (1..=MAX_SIDE, 1..=MAX_SIDE, 0.0..0.5f64).prop_flat_map(|(w, h, density)| {
        proptest::collection::vec(0.0..1.0f64, w * h).prop_map(move |u| Map {
            w,
            h,
            blocked: u.into_iter().map(|v| v < density).collect(),
        })
    })
}

/// A map with a start and a goal that may be blocked or up to two cells outside.
fn query_strategy() -> impl Strategy<Value = (Map, Cell, Cell)> {
    map_strategy().prop_flat_map(|m| {
        let (w, h) = (m.w as u16, m.h as u16);
        let cell = move || (0..w + 2, 0..h + 2).prop_map(|(x, y)| Cell::new(x, y));
        (Just(m), cell(), cell())
    })
}

/// A map with a start and a goal on free cells (when the map has any).
fn free_query_strategy() -> impl Strategy<Value = (Map, Cell, Cell)> {
    (
        map_strategy(),
        any::<prop::sample::Index>(),
        any::<prop::sample::Index>(),
    )
        .prop_map(|(m, i, j)| {
            let free: Vec<Cell> = (0..m.h as u16)
                .flat_map(|y| (0..m.w as u16).map(move |x| Cell::new(x, y)))
                .filter(|c| !m.blocked(c.x as i64, c.y as i64))
                .collect();
            let pick = |k: prop::sample::Index| {
                if free.is_empty() {
                    Cell::new(0, 0)
                } else {
                    free[k.index(free.len())]
                }
            };
            let (s, t) = (pick(i), pick(j));
            (m, s, t)
        })
}

// ---------------------------------------------------------------------------------------
// Independent oracles.

/// Exact test: does the segment between integer points `a`, `b` touch the closed unit
/// square centred on `c`? Doubled coordinates keep everything integral; by the separating
/// axis theorem the two convex sets are disjoint iff the square's axes or the segment's
/// normal separate them strictly.
fn touches(a: (i64, i64), b: (i64, i64), c: (i64, i64)) -> bool {
    let (ax, ay, bx, by) = (2 * a.0, 2 * a.1, 2 * b.0, 2 * b.1);
    let (x0, x1, y0, y1) = (2 * c.0 - 1, 2 * c.0 + 1, 2 * c.1 - 1, 2 * c.1 + 1);
    if ax.max(bx) < x0 || ax.min(bx) > x1 || ay.max(by) < y0 || ay.min(by) > y1 {
        return false;
    }
    let side = |px: i64, py: i64| ((bx - ax) * (py - ay) - (by - ay) * (px - ax)).signum();
    let s = [side(x0, y0), side(x1, y0), side(x0, y1), side(x1, y1)];
    !(s.iter().all(|&v| v > 0) || s.iter().all(|&v| v < 0))
}

/// Whether the segment between two on-map cell centres is valid: it touches no blocked cell.
/// (Its bounding box lies inside the map, so it cannot touch the outside.)
fn segment_ok(m: &Map, a: (i64, i64), b: (i64, i64)) -> bool {
    if m.blocked(a.0, a.1) || m.blocked(b.0, b.1) {
        return false;
    }
    for y in a.1.min(b.1) - 1..=a.1.max(b.1) + 1 {
        for x in a.0.min(b.0) - 1..=a.0.max(b.0) + 1 {
            if m.blocked(x, y) && touches(a, b, (x, y)) {
                return false;
            }
        }
    }
    true
}

/// Validates a path of integral waypoints from `s` to `t` under the collision rule.
fn check_path(m: &Map, p: &[Point], s: Cell, t: Cell) -> Result<(), String> {
    let pts: Vec<(i64, i64)> = p
        .iter()
        .map(|q| {
            if q.x.fract() != 0.0 || q.y.fract() != 0.0 {
                Err(format!("fractional waypoint {q:?}"))
            } else {
                Ok((q.x as i64, q.y as i64))
            }
        })
        .collect::<Result<_, _>>()?;
    match (pts.first(), pts.last()) {
        (Some(&f), Some(&l)) => {
            if f != (s.x as i64, s.y as i64) {
                return Err(format!("starts at {f:?}, not {s:?}"));
            }
            if l != (t.x as i64, t.y as i64) {
                return Err(format!("ends at {l:?}, not {t:?}"));
            }
        }
        _ => return Err("empty path".into()),
    }
    if pts.len() == 1 && !segment_ok(m, pts[0], pts[0]) {
        return Err("single waypoint on a blocked cell".into());
    }
    for (i, w) in pts.windows(2).enumerate() {
        if !segment_ok(m, w[0], w[1]) {
            return Err(format!("segment {i} {:?} -> {:?} collides", w[0], w[1]));
        }
    }
    Ok(())
}

/// Fractional waypoints are generated on a grid of `1 / FRAC` (dyadic, so exact in `f32`),
/// and the exact oracle works in units of `1 / FRAC`.
const FRAC: i64 = 1 << 16;

/// `p` in units of `1 / FRAC`; panics unless exact.
fn scaled(p: Point) -> (i64, i64) {
    let (x, y) = (p.x as f64 * FRAC as f64, p.y as f64 * FRAC as f64);
    assert!(
        x.fract() == 0.0 && y.fract() == 0.0,
        "{p:?} is not on the 1/FRAC grid"
    );
    (x as i64, y as i64)
}

/// Exact: does the segment between `a` and `b` (units of `1 / FRAC`) touch the closed unit
/// square of cell `c`? Separating axes, as in [`touches`].
fn touches_scaled(a: (i64, i64), b: (i64, i64), c: (i64, i64)) -> bool {
    touches_box(a, b, c, FRAC / 2)
}

/// Exact: does the segment touch the closed square of half-side `h` (units of `1 / FRAC`)
/// centred on cell `c`?
fn touches_box(a: (i64, i64), b: (i64, i64), c: (i64, i64), h: i64) -> bool {
    let (x0, x1, y0, y1) = (
        c.0 * FRAC - h,
        c.0 * FRAC + h,
        c.1 * FRAC - h,
        c.1 * FRAC + h,
    );
    if a.0.max(b.0) < x0 || a.0.min(b.0) > x1 || a.1.max(b.1) < y0 || a.1.min(b.1) > y1 {
        return false;
    }
    let side = |px: i64, py: i64| {
        ((b.0 - a.0) as i128 * (py - a.1) as i128 - (b.1 - a.1) as i128 * (px - a.0) as i128)
            .signum()
    };
    let s = [side(x0, y0), side(x1, y0), side(x0, y1), side(x1, y1)];
    !(s.iter().all(|&v| v > 0) || s.iter().all(|&v| v < 0))
}

/// Exact rule for arbitrary (dyadic) points: the segment touches no blocked cell and no
/// cell outside the map.
/// A random map, a hull's base point and three offsets (see [`sampled_hull`]), and 24
/// weight triples for [`hull_point`].
#[allow(clippy::type_complexity)]
fn hull_case_strategy()
-> impl Strategy<Value = (Map, (i32, i32), Vec<(i32, i32)>, Vec<(u8, u8, u8)>)> {
    (
        map_strategy(),
        (0i32..24 * 16, 0i32..24 * 16),
        proptest::collection::vec((-48i32..=48, -48i32..=48), 3),
        proptest::collection::vec((0u8..=16, 0u8..=16, 0u8..=16), 24),
    )
}

/// Four points in 1/16 cell, `base` and `base + offsets` (in f64 and as `Point`s): a random
/// hull for the hull tests. Samples mix them with weights in 1/16 ([`hull_point`]), so the
/// sampled points are multiples of 2^-12, exact in f32 and in the oracle's 2^-16 units.
fn sampled_hull(base: (i32, i32), offsets: &[(i32, i32)]) -> (Vec<(f64, f64)>, [Point; 4]) {
    let q = |v: i32| f64::from(v) / 16.0;
    let b = (q(base.0), q(base.1));
    let pts: Vec<(f64, f64)> = core::iter::once(b)
        .chain(offsets.iter().map(|&(dx, dy)| (b.0 + q(dx), b.1 + q(dy))))
        .collect();
    let hull = core::array::from_fn(|i| Point::new(pts[i].0 as f32, pts[i].1 as f32));
    (pts, hull)
}

/// A point of the hull of `pts` (four points): on the segment between a point of edge 0-1
/// and one of edge 2-3 (those segments sweep the whole hull), weights in 1/16.
fn hull_point(pts: &[(f64, f64)], (t1, t2, t3): (u8, u8, u8)) -> Point {
    let lerp = |a: (f64, f64), b: (f64, f64), t: u8| {
        let t = f64::from(t) / 16.0;
        (a.0 + (b.0 - a.0) * t, a.1 + (b.1 - a.1) * t)
    };
    let p = lerp(lerp(pts[0], pts[1], t1), lerp(pts[2], pts[3], t2), t3);
    Point::new(p.0 as f32, p.1 as f32)
}

fn segment_ok_frac(m: &Map, a: Point, b: Point) -> bool {
    let (sa, sb) = (scaled(a), scaled(b));
    let lo = |v: i64| v.div_euclid(FRAC) - 1;
    let hi = |v: i64| v.div_euclid(FRAC) + 2;
    for y in lo(sa.1.min(sb.1))..=hi(sa.1.max(sb.1)) {
        for x in lo(sa.0.min(sb.0))..=hi(sa.0.max(sb.0)) {
            if m.blocked(x, y) && touches_scaled(sa, sb, (x, y)) {
                return false;
            }
        }
    }
    true
}

/// Least distance (f64) from segment `ab` to a blocked or outside cell's square, looking
/// at cells up to `reach` away from the segment's bounding box; 0 when it touches one.
fn clearance_oracle(m: &Map, a: Point, b: Point, reach: f64) -> f64 {
    let (sa, sb) = (scaled(a), scaled(b));
    let (a, b) = ((a.x as f64, a.y as f64), (b.x as f64, b.y as f64));
    let point_seg = |p: (f64, f64)| {
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len2 = dx * dx + dy * dy;
        let t = if len2 > 0.0 {
            (((p.0 - a.0) * dx + (p.1 - a.1) * dy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (p.0 - a.0 - t * dx).hypot(p.1 - a.1 - t * dy)
    };
    let point_square = |p: (f64, f64), c: (f64, f64)| {
        let gx = ((p.0 - c.0).abs() - 0.5).max(0.0);
        let gy = ((p.1 - c.1).abs() - 0.5).max(0.0);
        gx.hypot(gy)
    };
    let r = reach.ceil() as i64 + 1;
    let mut best = f64::INFINITY;
    for y in a.1.min(b.1).floor() as i64 - r..=a.1.max(b.1).ceil() as i64 + r {
        for x in a.0.min(b.0).floor() as i64 - r..=a.0.max(b.0).ceil() as i64 + r {
            if !m.blocked(x, y) {
                continue;
            }
            if touches_scaled(sa, sb, (x, y)) {
                return 0.0;
            }
            let c = (x as f64, y as f64);
            let mut d = point_square(a, c).min(point_square(b, c));
            for (ox, oy) in [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)] {
                d = d.min(point_seg((c.0 + ox, c.1 + oy)));
            }
            best = best.min(d);
        }
    }
    best
}

fn len64(p: &[Point]) -> f64 {
    p.windows(2)
        .map(|w| ((w[1].x - w[0].x) as f64).hypot((w[1].y - w[0].y) as f64))
        .sum()
}

/// The 8-connected moves allowed from `(x, y)` (no corner cutting), with `f64` costs.
fn moves(m: &Map, x: i64, y: i64) -> impl Iterator<Item = (i64, i64, f64)> + '_ {
    (-1..=1)
        .flat_map(|dy| (-1..=1).map(move |dx| (dx, dy)))
        .filter(move |&(dx, dy)| {
            (dx, dy) != (0, 0)
                && !m.blocked(x + dx, y + dy)
                && !m.blocked(x + dx, y)
                && !m.blocked(x, y + dy)
        })
        .map(move |(dx, dy)| {
            let c = if dx != 0 && dy != 0 {
                std::f64::consts::SQRT_2
            } else {
                1.0
            };
            (x + dx, y + dy, c)
        })
}

fn bfs_reachable(m: &Map, s: Cell, t: Cell) -> bool {
    let mut seen = vec![false; m.w * m.h];
    let mut queue = VecDeque::from([(s.x as i64, s.y as i64)]);
    seen[s.y as usize * m.w + s.x as usize] = true;
    while let Some((x, y)) = queue.pop_front() {
        if (x, y) == (t.x as i64, t.y as i64) {
            return true;
        }
        for (nx, ny, _) in moves(m, x, y) {
            let k = ny as usize * m.w + nx as usize;
            if !seen[k] {
                seen[k] = true;
                queue.push_back((nx, ny));
            }
        }
    }
    false
}

/// Shortest 8-connected distance in `f64` (`None` when unreachable).
fn dijkstra(m: &Map, s: Cell, t: Cell) -> Option<f64> {
    let mut dist = vec![f64::INFINITY; m.w * m.h];
    let mut heap = BinaryHeap::new();
    let key = |d: f64| Reverse((d * 1e9) as u64); // exact order for these magnitudes
    dist[s.y as usize * m.w + s.x as usize] = 0.0;
    heap.push((key(0.0), s.x as i64, s.y as i64));
    while let Some((_, x, y)) = heap.pop() {
        let d = dist[y as usize * m.w + x as usize];
        if (x, y) == (t.x as i64, t.y as i64) {
            return Some(d);
        }
        for (nx, ny, c) in moves(m, x, y) {
            let k = ny as usize * m.w + nx as usize;
            if d + c < dist[k] - 1e-12 {
                dist[k] = d + c;
                heap.push((key(d + c), nx, ny));
            }
        }
    }
    None
}

/// What the planners must return for bad endpoints, in the documented order.
fn expected_endpoint_error(m: &Map, s: Cell, t: Cell) -> Option<PlanError> {
    let outside = |c: Cell| c.x as usize >= m.w || c.y as usize >= m.h;
    if outside(s) {
        Some(PlanError::StartOutsideMap)
    } else if outside(t) {
        Some(PlanError::GoalOutsideMap)
    } else if m.blocked(s.x as i64, s.y as i64) {
        Some(PlanError::StartOccupied)
    } else if m.blocked(t.x as i64, t.y as i64) {
        Some(PlanError::GoalOccupied)
    } else {
        None
    }
}

// ---------------------------------------------------------------------------------------
// The oracle itself, on hand-made cases.

#[test]
fn oracle_sanity() {
    // Corner touches count; near misses do not.
    assert!(touches((0, 0), (1, 1), (1, 0)));
    assert!(touches((0, 0), (3, 1), (1, 1)));
    assert!(touches((0, 0), (3, 1), (2, 0)));
    assert!(!touches((0, 0), (3, 1), (0, 1)));
    assert!(!touches((0, 0), (2, 0), (1, 1)));
    let m = Map {
        w: 2,
        h: 2,
        blocked: vec![false, true, true, false],
    };
    assert!(!bfs_reachable(&m, Cell::new(0, 0), Cell::new(1, 1)));
    assert_eq!(dijkstra(&m, Cell::new(0, 0), Cell::new(1, 1)), None);
    let open = Map {
        w: 3,
        h: 2,
        blocked: vec![false; 6],
    };
    let d = dijkstra(&open, Cell::new(0, 0), Cell::new(2, 1)).unwrap();
    assert!((d - (1.0 + std::f64::consts::SQRT_2)).abs() < 1e-12);
    let p = [Point::new(0.0, 0.0), Point::new(2.0, 1.0)];
    assert!(check_path(&open, &p, Cell::new(0, 0), Cell::new(2, 1)).is_ok());
    assert!(check_path(&m, &p[..1], Cell::new(0, 0), Cell::new(0, 0)).is_ok());
    assert!(check_path(&m, &p[..1], Cell::new(1, 0), Cell::new(1, 0)).is_err());
}

// ---------------------------------------------------------------------------------------
// Properties.

proptest! {
    #![proptest_config(Config { cases: 1000, ..Config::default() })]

    /// (a) valid paths, (b) Theta* <= A*, (c) errors exactly as BFS/connectivity/endpoint
    /// checks say, (e) A* length = Dijkstra, (f) pruning keeps paths valid and not longer.
    #[test]
    fn planners_agree_with_oracles((m, s, t) in query_strategy()) {
        let grid = m.grid();
        let g = grid.view();
        let mut nodes = vec![SearchNode::EMPTY; g.cells()];
        let mut astar_nodes = vec![AStarNode::EMPTY; g.cells()];
        let mut open = vec![OpenSlot::EMPTY; open_capacity(g.cells())];
        let mut labels = vec![0u32; g.cells()];
        connectivity::label(g, &mut labels).unwrap();
        let mut a_path = Buf::new();
        let mut t_path = Buf::new();
        let a = astar::plan(g, s, t, &mut astar_nodes, &mut open, &mut a_path);
        let th = theta::plan(g, s, t, &mut nodes, &mut t_path);
        let conn = connectivity::connected(g, &labels, s, t);

        if let Some(err) = expected_endpoint_error(&m, s, t) {
            prop_assert_eq!(a, Err(err));
            prop_assert_eq!(th, Err(err));
            prop_assert_eq!(conn, Err(err));
            return Ok(());
        }
        let reachable = bfs_reachable(&m, s, t);
        prop_assert_eq!(conn, Ok(reachable));
        let dist = dijkstra(&m, s, t);
        prop_assert_eq!(dist.is_some(), reachable);
        let mut l_path = Buf::new();
        let labelled = astar::plan_with_labels(g, s, t, Some(&labels), &mut astar_nodes, &mut open, &mut l_path);
        prop_assert_eq!(labelled, a);
        let Some(dist) = dist else {
            prop_assert_eq!(a, Err(PlanError::NoValidPath));
            prop_assert_eq!(th, Err(PlanError::NoValidPath));
            return Ok(());
        };
        let (a, th) = (a.unwrap(), th.unwrap());

        check_path(&m, &a_path, s, t).map_err(TestCaseError::fail)?;
        check_path(&m, &t_path, s, t).map_err(TestCaseError::fail)?;
        // A* visits every cell centre on its way: unit steps only.
        for w in a_path.windows(2) {
            let (dx, dy) = ((w[1].x - w[0].x).abs(), (w[1].y - w[0].y).abs());
            prop_assert!(dx.max(dy) == 1.0, "{:?}", w);
        }
        prop_assert!((a.length as f64 - dist).abs() < 1e-4, "A* {} vs Dijkstra {}", a.length, dist);
        prop_assert!((len64(&a_path) - dist).abs() < 1e-9);
        prop_assert!((len64(&t_path) - th.length as f64).abs() < 1e-4);
        prop_assert!(th.length <= a.length + 1e-3, "Theta* {} > A* {}", th.length, a.length);
        let straight = ((s.x as f64 - t.x as f64).hypot(s.y as f64 - t.y as f64)) as f32;
        prop_assert!(th.length >= straight - 1e-3);

        for (name, original) in [("A*", &a_path), ("Theta*", &t_path)] {
            let before = len64(original);
            let mut p = original.clone();
            path::prune_collinear(&mut p);
            check_path(&m, &p, s, t).map_err(|e| TestCaseError::fail(format!("{name} pruned: {e}")))?;
            prop_assert!((len64(&p) - before).abs() < 1e-4, "prune changed the shape");
            let pruned = len64(&p);
            path::shortcut(g, &mut p);
            check_path(&m, &p, s, t).map_err(|e| TestCaseError::fail(format!("{name} shortcut: {e}")))?;
            prop_assert!(len64(&p) <= pruned + 1e-9);
            let mut q = original.clone();
            path::shortcut(g, &mut q);
            check_path(&m, &q, s, t).map_err(|e| TestCaseError::fail(format!("{name} shortcut: {e}")))?;
            prop_assert!(len64(&q) <= before + 1e-9);
        }
    }

    /// (c) Component labels partition the free cells exactly as BFS over the 8-connected
    /// moves (no corner cutting) does, and the count is the number of BFS components.
    #[test]
    fn labels_match_bfs_components(m in map_strategy()) {
        let grid = m.grid();
        let g = grid.view();
        let mut labels = vec![0u32; g.cells()];
        let count = connectivity::label(g, &mut labels).unwrap();
        let mut comp = vec![usize::MAX; m.w * m.h];
        let mut components = 0;
        for start in 0..m.w * m.h {
            let (sx, sy) = ((start % m.w) as i64, (start / m.w) as i64);
            if m.blocked(sx, sy) {
                prop_assert_eq!(labels[start], connectivity::BLOCKED);
                continue;
            }
            if comp[start] != usize::MAX {
                continue;
            }
            comp[start] = components;
            let mut queue = VecDeque::from([(sx, sy)]);
            while let Some((x, y)) = queue.pop_front() {
                for (nx, ny, _) in moves(&m, x, y) {
                    let k = ny as usize * m.w + nx as usize;
                    if comp[k] == usize::MAX {
                        comp[k] = components;
                        queue.push_back((nx, ny));
                    }
                }
            }
            components += 1;
        }
        prop_assert_eq!(count as usize, components);
        for a in 0..m.w * m.h {
            for b in 0..m.w * m.h {
                if comp[a] != usize::MAX && comp[b] != usize::MAX {
                    prop_assert_eq!(labels[a] == labels[b], comp[a] == comp[b]);
                }
            }
        }
    }

    /// (f) on arbitrary valid grid routes (revisits, reversals, repeated waypoints): pruning and
    /// shortcutting keep them valid and never make them longer.
    #[test]
    fn pruning_keeps_random_routes_valid(
        m in map_strategy(),
        seed in any::<u64>(),
        steps in 0usize..60,
    ) {
        let grid = m.grid();
        let g = grid.view();
        let free: Vec<(i64, i64)> = (0..m.h as i64)
            .flat_map(|y| (0..m.w as i64).map(move |x| (x, y)))
            .filter(|&(x, y)| !m.blocked(x, y))
            .collect();
        prop_assume!(!free.is_empty());
        let mut rng = seed;
        let mut next = |n: usize| {
            rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            ((rng >> 33) % n as u64) as usize
        };
        let mut cur = free[next(free.len())];
        let start = Cell::new(cur.0 as u16, cur.1 as u16);
        let mut route = Buf::new();
        route.push(Point::new(cur.0 as f32, cur.1 as f32)).unwrap();
        for _ in 0..steps {
            let options: Vec<_> = moves(&m, cur.0, cur.1).collect();
            // Sometimes stay put: repeated waypoints must be handled too.
            if options.is_empty() || next(8) == 0 {
                route.push(Point::new(cur.0 as f32, cur.1 as f32)).unwrap();
                continue;
            }
            let (x, y, _) = options[next(options.len())];
            cur = (x, y);
            route.push(Point::new(x as f32, y as f32)).unwrap();
        }
        let goal = Cell::new(cur.0 as u16, cur.1 as u16);
        check_path(&m, &route, start, goal).map_err(TestCaseError::fail)?;
        let before = len64(&route);
        let mut p = route.clone();
        path::prune_collinear(&mut p);
        check_path(&m, &p, start, goal).map_err(TestCaseError::fail)?;
        prop_assert!((len64(&p) - before).abs() < 1e-4);
        path::shortcut(g, &mut p);
        check_path(&m, &p, start, goal).map_err(TestCaseError::fail)?;
        prop_assert!(len64(&p) <= before + 1e-4);
        let mut q = route.clone();
        path::shortcut(g, &mut q);
        check_path(&m, &q, start, goal).map_err(TestCaseError::fail)?;
        prop_assert!(len64(&q) <= before + 1e-4);
    }

    /// (d) `line_of_sight` (integer) and `segment_is_clear` agree on every pair of cell
    /// centres (including cells just outside the map). Since `segment_is_clear` hands
    /// centre-to-centre segments to `line_of_sight`, the real check is the second one:
    /// `line_of_sight` = the separating-axis oracle from 6 random sources to every cell.
    #[test]
    fn collision_checks_agree(m in map_strategy(), seed in any::<u64>()) {
        let grid = m.grid();
        let g = grid.view();
        let cells: Vec<Cell> = (0..m.h as u16 + 1)
            .flat_map(|y| (0..m.w as u16 + 1).map(move |x| Cell::new(x, y)))
            .collect();
        for &a in &cells {
            for &b in &cells {
                let los = line_of_sight(g, a, b);
                let seg = segment_is_clear(g, a.center(), b.center());
                prop_assert_eq!(los, seg, "{:?} -> {:?}", a, b);
            }
        }
        let mut rng = seed;
        for _ in 0..6 {
            rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let a = cells[(rng >> 33) as usize % cells.len()];
            for &b in &cells {
                let on_map = |c: Cell| (c.x as usize) < m.w && (c.y as usize) < m.h;
                let want = on_map(a)
                    && on_map(b)
                    && segment_ok(&m, (a.x as i64, a.y as i64), (b.x as i64, b.y as i64));
                prop_assert_eq!(line_of_sight(g, a, b), want, "{:?} -> {:?}", a, b);
                prop_assert_eq!(line_of_sight(g, b, a), want, "{:?} -> {:?}", b, a);
            }
        }
    }

    /// (d) `blocked_cells_touched` counts exactly the blocked or outside cells that the
    /// exact oracle says the segment touches: every pair at most one column apart (both
    /// orders), and every pair from a few random cells.
    #[test]
    fn blocked_cells_touched_counts_exactly(m in map_strategy(), seed in any::<u64>()) {
        let grid = m.grid();
        let g = grid.view();
        let oracle = |a: Cell, b: Cell| {
            let (sa, sb) = (
                (a.x as i64 * FRAC, a.y as i64 * FRAC),
                (b.x as i64 * FRAC, b.y as i64 * FRAC),
            );
            let (x0, x1) = (a.x.min(b.x) as i64 - 1, a.x.max(b.x) as i64 + 1);
            let (y0, y1) = (a.y.min(b.y) as i64 - 1, a.y.max(b.y) as i64 + 1);
            (y0..=y1)
                .flat_map(|y| (x0..=x1).map(move |x| (x, y)))
                .filter(|&(x, y)| m.blocked(x, y) && touches_box(sa, sb, (x, y), FRAC / 2))
                .count() as u32
        };
        let cells: Vec<Cell> = (0..m.h as u16 + 1)
            .flat_map(|y| (0..m.w as u16 + 1).map(move |x| Cell::new(x, y)))
            .collect();
        for &a in &cells {
            for &b in &cells {
                if a.x.abs_diff(b.x) <= 1 {
                    prop_assert_eq!(blocked_cells_touched(g, a, b), oracle(a, b), "{:?} -> {:?}", a, b);
                }
            }
        }
        let mut rng = seed;
        for _ in 0..4 {
            rng = rng.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let a = cells[(rng >> 33) as usize % cells.len()];
            for &b in &cells {
                prop_assert_eq!(blocked_cells_touched(g, a, b), oracle(a, b), "{:?} -> {:?}", a, b);
            }
        }
    }

    /// `segment_is_clear` is conservative: whenever it accepts a segment between
    /// arbitrary (fractional, possibly off-map) points, the exact rule accepts it too.
    /// And it is not absurdly strict: segments that stay a whole cell away from every
    /// blocked cell and the border are accepted.
    #[test]
    fn segment_is_clear_is_conservative(
        m in map_strategy(),
        pts in proptest::collection::vec((-80i32..=24 * 64 + 80, -80i32..=24 * 64 + 80), 2..40),
    ) {
        let grid = m.grid();
        let g = grid.view();
        let p = |(x, y): (i32, i32)| Point::new(x as f32 / 64.0, y as f32 / 64.0);
        for w in pts.windows(2) {
            let (a, b) = (p(w[0]), p(w[1]));
            let fast = segment_is_clear(g, a, b);
            let exact = segment_ok_frac(&m, a, b);
            prop_assert!(!fast || exact, "{:?} -> {:?}: f32 says clear, exact rule says not", a, b);
            // A whole cell away from everything: the segment misses the 3 x 3 block
            // around every blocked (or outside) cell.
            let (sa, sb) = (scaled(a), scaled(b));
            let lo = |v: i64| v.div_euclid(FRAC) - 3;
            let hi = |v: i64| v.div_euclid(FRAC) + 4;
            let far = (lo(sa.1.min(sb.1))..=hi(sa.1.max(sb.1))).all(|y| {
                (lo(sa.0.min(sb.0))..=hi(sa.0.max(sb.0)))
                    .all(|x| !m.blocked(x, y) || !touches_box(sa, sb, (x, y), 3 * FRAC / 2))
            });
            if far {
                prop_assert!(fast, "{:?} -> {:?} is a cell away from everything", a, b);
            }
        }
    }

    /// `hull_blockers` lists what can block a segment in the hull: for every sampled segment
    /// between two points of the hull, `segment_is_clear_among` on the listed cells gives
    /// `segment_is_clear`'s verdict exactly, and every listed cell is blocked.
    #[test]
    fn hull_blockers_decide_their_segments(
        (m, base, offsets, samples) in hull_case_strategy(),
    ) {
        let grid = m.grid();
        let g = grid.view();
        let margin = hull_margin(g);
        let (pts, hull) = sampled_hull(base, &offsets);
        let mut cells = [Cell::new(0, 0); 4];
        let Some(n) = hull_blockers(g, &hull, margin, &mut cells) else {
            return Ok(());
        };
        prop_assert_eq!(n == 0, hull_is_clear(g, &hull, margin));
        for c in &cells[..n] {
            prop_assert!(m.blocked(i64::from(c.x), i64::from(c.y)));
        }
        let point = |t| hull_point(&pts, t);
        let mut segments: Vec<(Point, Point)> = samples.windows(2).map(|w| (point(w[0]), point(w[1]))).collect();
        for i in 0..4 {
            for j in 0..4 {
                segments.push((hull[i], hull[j]));
            }
        }
        for (a, b) in segments {
            prop_assert_eq!(
                segment_is_clear_among(g, a, b, &cells[..n], margin),
                segment_is_clear(g, a, b),
                "{:?} -> {:?} among {:?}", a, b, &cells[..n]
            );
        }
    }

    /// `hull_is_clear` is a proof: when it accepts the hull of four points, every segment
    /// between two points of that hull (sampled on a dyadic lattice, so the exact rule can
    /// judge it) passes `segment_is_clear` and the exact rule. And it is not absurdly strict:
    /// a hull whose bounding box stays a cell and a half from every blocked cell and the
    /// border is accepted.
    #[test]
    fn hull_is_clear_proves_its_segments(
        (m, base, offsets, samples) in hull_case_strategy(),
    ) {
        let grid = m.grid();
        let g = grid.view();
        let (pts, hull) = sampled_hull(base, &offsets);
        let accepted = hull_is_clear(g, &hull, hull_margin(g));
        if accepted {
            let point = |t| hull_point(&pts, t);
            for w in samples.windows(2) {
                let (a, b) = (point(w[0]), point(w[1]));
                prop_assert!(segment_is_clear(g, a, b), "{:?}: {:?} -> {:?}", hull, a, b);
                prop_assert!(segment_ok_frac(&m, a, b), "{:?}: {:?} -> {:?}", hull, a, b);
            }
            for i in 0..4 {
                for j in i + 1..4 {
                    prop_assert!(segment_ok_frac(&m, hull[i], hull[j]));
                }
            }
        }
        let (x0, x1) = pts.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| (lo.min(p.0), hi.max(p.0)));
        let (y0, y1) = pts.iter().fold((f64::MAX, f64::MIN), |(lo, hi), p| (lo.min(p.1), hi.max(p.1)));
        // Cells whose square comes within 1.5 of the box: centres within 2 of it.
        let cells = |lo: f64, hi: f64| (lo - 2.0).floor() as i64..=(hi + 2.0).ceil() as i64;
        let far = cells(y0, y1).all(|y| {
            cells(x0, x1).all(|x| {
                let gap_x = (x as f64 - 0.5 - x1).max(x0 - (x as f64 + 0.5)).max(0.0);
                let gap_y = (y as f64 - 0.5 - y1).max(y0 - (y as f64 + 0.5)).max(0.0);
                !m.blocked(x, y) || gap_x.max(gap_y) >= 1.5
            })
        });
        if far {
            prop_assert!(accepted, "{:?} is a cell and a half away from everything", hull);
        }
    }

    /// (f) with fractional waypoints: a valid path (a planner's path with nodes nudged
    /// off the grid and exact midpoints inserted) stays valid and not longer after
    /// `prune_collinear` and `shortcut`, checked by both `validate` and the exact rule.
    #[test]
    fn pruning_keeps_fractional_paths_valid(
        (m, s, t) in free_query_strategy(),
        nudges in proptest::collection::vec((-19_000i32..19_000, -19_000i32..19_000, 0u8..4), 64),
    ) {
        let grid = m.grid();
        let g = grid.view();
        let mut nodes = vec![SearchNode::EMPTY; g.cells()];
        let mut base = Buf::new();
        if theta::plan(g, s, t, &mut nodes, &mut base).is_err() {
            return Ok(()); // blocked or unreachable: covered elsewhere
        }
        let mut p: Vec<Point> = base.to_vec();
        for (k, &(dx, dy, kind)) in nudges.iter().enumerate() {
            if p.len() < 2 {
                break;
            }
            let i = k % (p.len() - 1);
            let (a, b) = (p[i], p[i + 1]);
            match kind {
                // Insert the exact midpoint (when on the 1/FRAC grid): collinear, removable.
                0 => {
                    let mid = Point::new((a.x + b.x) / 2.0, (a.y + b.y) / 2.0);
                    let on_grid = |v: f32| (v as f64 * FRAC as f64).fract() == 0.0;
                    if on_grid(mid.x) && on_grid(mid.y) {
                        p.insert(i + 1, mid);
                    }
                }
                // Nudge an interior node if both its segments stay valid.
                _ if i > 0 => {
                    let q = Point::new(
                        a.x + dx as f32 / FRAC as f32,
                        a.y + dy as f32 / FRAC as f32,
                    );
                    if segment_is_clear(g, p[i - 1], q) && segment_is_clear(g, q, b) {
                        p[i] = q;
                    }
                }
                _ => {}
            }
        }
        let p: Buf = p.into_iter().collect();
        prop_assert_eq!(path::validate(g, &p, s, t), Ok(()));
        let exact_ok = |q: &[Point]| q.windows(2).all(|w| segment_ok_frac(&m, w[0], w[1]));
        prop_assert!(exact_ok(&p));
        let before = len64(&p);
        let mut q = p.clone();
        path::prune_collinear(&mut q);
        prop_assert_eq!(path::validate(g, &q, s, t), Ok(()), "pruned {:?}", q);
        prop_assert!(exact_ok(&q));
        prop_assert!(len64(&q) <= before + 1e-4);
        path::shortcut(g, &mut q);
        prop_assert_eq!(path::validate(g, &q, s, t), Ok(()), "shortcut {:?}", q);
        prop_assert!(exact_ok(&q));
        prop_assert!(len64(&q) <= before + 1e-4);
    }

    /// `segment_clearance` equals an `f64` oracle (0 when the segment touches a blocked or
    /// outside cell, else the least distance to such a cell's square), capped at `max`.
    #[test]
    fn segment_clearance_matches_oracle(
        (m, pts) in map_strategy().prop_flat_map(|m| {
            // Mostly on the map, sometimes a little off it (units of 1/64 cell).
            let (w, h) = (m.w as i32 * 64, m.h as i32 * 64);
            let pts = proptest::collection::vec((-48..w + 16, -48..h + 16), 2..12);
            (Just(m), pts)
        }),
        max in 0.0f32..6.0,
    ) {
        let grid = m.grid();
        let g = grid.view();
        let p = |(x, y): (i32, i32)| Point::new(x as f32 / 64.0, y as f32 / 64.0);
        for w in pts.windows(2) {
            let (a, b) = (p(w[0]), p(w[1]));
            let got = segment_clearance(g, a, b, max);
            let want = clearance_oracle(&m, a, b, max as f64 + 2.0).min(max as f64);
            prop_assert!(
                (got as f64 - want).abs() <= 1e-4,
                "{:?} -> {:?} max {}: got {}, want {}", a, b, max, got, want
            );
        }
    }

    /// `inflate_into` blocks exactly the cells that are blocked or whose square comes closer
    /// than the radius to a blocked or outside cell's square (radii k/8: exact in `f32`).
    #[test]
    fn inflation_matches_oracle(m in map_strategy(), k in 0u32..=24) {
        let r = k as f64 / 8.0;
        let grid = m.grid();
        let mut out = G::new(1, 1).unwrap();
        grid.inflate_into(r as f32, &mut out).unwrap();
        let v = out.view();
        prop_assert_eq!((v.width(), v.height()), (m.w, m.h));
        let reach = r.ceil() as i64 + 1;
        for y in 0..m.h as i64 {
            for x in 0..m.w as i64 {
                let mut want = m.blocked(x, y);
                for dy in -reach..=reach {
                    for dx in -reach..=reach {
                        let gx = (dx.abs() - 1).max(0) as f64;
                        let gy = (dy.abs() - 1).max(0) as f64;
                        if m.blocked(x + dx, y + dy) && gx.hypot(gy) < r {
                            want = true;
                        }
                    }
                }
                prop_assert_eq!(v.is_blocked(x as isize, y as isize), want, "({}, {}) r {}", x, y, r);
            }
        }
    }

    /// (g) The parsers never panic on arbitrary bytes.
    #[test]
    fn parser_never_panics_on_bytes(bytes in any::<Vec<u8>>()) {
        let _ = G::parse_movingai(&bytes);
        let _ = G::parse_rows(&bytes);
    }

    /// (g) Generated maps round-trip, and any mutation of them parses or fails cleanly.
    #[test]
    fn parser_round_trips_and_survives_mutations(
        m in map_strategy(),
        crlf in any::<bool>(),
        edits in proptest::collection::vec((any::<prop::sample::Index>(), 0u8..3, any::<u8>()), 0..6),
    ) {
        let mut text = m.text();
        if crlf {
            text = text.replace('\n', "\r\n");
        }
        let parsed = G::parse_movingai(text.as_bytes()).unwrap();
        prop_assert_eq!(&parsed, &m.grid());
        let v = parsed.view();
        prop_assert_eq!((v.width(), v.height()), (m.w, m.h));
        for y in 0..m.h {
            for x in 0..m.w {
                prop_assert_eq!(v.is_blocked(x as isize, y as isize), m.blocked[y * m.w + x]);
            }
        }
        let body = text.split_once("map\n").or_else(|| text.split_once("map\r\n")).unwrap().1;
        prop_assert_eq!(&G::parse_rows(body.as_bytes()).unwrap(), &m.grid());

        let mut bytes = text.into_bytes();
        for (at, kind, byte) in edits {
            match kind {
                0 if !bytes.is_empty() => {
                    let i = at.index(bytes.len());
                    bytes[i] = byte;
                }
                1 => {
                    let i = at.index(bytes.len() + 1);
                    bytes.insert(i, byte);
                }
                _ if !bytes.is_empty() => {
                    let i = at.index(bytes.len());
                    bytes.remove(i);
                }
                _ => {}
            }
        }
        if let Ok(g) = G::parse_movingai(&bytes) {
            let v = g.view();
            prop_assert!(v.width() >= 1 && v.height() >= 1 && v.cells() <= G::CAPACITY);
        }
        let _ = G::parse_rows(&bytes);
    }
}

proptest! {
    #![proptest_config(Config { cases: 256, ..Config::default() })]

    /// (d) on maps up to 300 x 300 with sparse obstacles: long and steep lines, checked
    /// against the separating-axis oracle over every blocked cell.
    #[test]
    fn line_of_sight_on_large_maps(
        (w, h, cells, pairs) in (1usize..=300, 1usize..=300, 0.0..0.05f64).prop_flat_map(|(w, h, d)| {
            let n = ((w * h) as f64 * d) as usize;
            (
                Just(w),
                Just(h),
                proptest::collection::vec((0..w as u16, 0..h as u16), n),
                proptest::collection::vec((0..w as u16, 0..h as u16, 0..w as u16, 0..h as u16), 100),
            )
        }),
    ) {
        let mut grid: Box<Grid<{ words_for(300, 300) }>> = Box::new(Grid::new(w, h).unwrap());
        for &(x, y) in &cells {
            grid.set_blocked(x as usize, y as usize, true).unwrap();
        }
        let g = grid.view();
        for (ax, ay, bx, by) in pairs {
            let (a, b) = ((ax as i64, ay as i64), (bx as i64, by as i64));
            let want = cells.iter().all(|&(x, y)| !touches(a, b, (x as i64, y as i64)));
            let (ca, cb) = (Cell::new(ax, ay), Cell::new(bx, by));
            prop_assert_eq!(line_of_sight(g, ca, cb), want, "{:?} -> {:?}", ca, cb);
            prop_assert_eq!(line_of_sight(g, cb, ca), want, "{:?} -> {:?}", cb, ca);
        }
    }
}

proptest! {
    #![proptest_config(Config { cases: 2000, ..Config::default() })]

    /// The quick tests of `segment_is_clear_among` near their band: on maps of 40 and 1024
    /// cells a side, segments pass a corner or along an edge of a blocked cell near the far
    /// edge of the map (where coordinates round most) at distances from -3e-3 to 3e-3 cells,
    /// which covers the band (5.5e-4 and 1/512 cells) and TOUCH_EPS (1e-4). The verdict
    /// from that cell alone must be the strip scan's.
    #[test]
    fn blocked_cell_judgement_agrees_with_the_strip_scan_near_the_band(
        large in any::<bool>(),
        corner in (0usize..2, 0usize..2),
        angle in prop_oneof![(0u32..8).prop_map(|k| k as f64 * 45.0), 0.0..360.0f64],
        distance in -3_000i32..=3_000,
        ends in (0.0..2.5f64, 0.0..2.5f64),
    ) {
        let side = if large { 1024 } else { 40 };
        let mut grid: Box<Grid<{ words_for(1024, 1024) }>> =
            Box::new(Grid::new(side, side).unwrap());
        let cell = Cell::new(side as u16 - 5, side as u16 - 5);
        grid.set_blocked(usize::from(cell.x), usize::from(cell.y), true).unwrap();
        let g = grid.view();
        let sign = |c: usize| if c == 0 { -0.5 } else { 0.5 };
        let k = (f64::from(cell.x) + sign(corner.0), f64::from(cell.y) + sign(corner.1));
        let (dx, dy) = (angle.to_radians().cos(), angle.to_radians().sin());
        // The line through the corner moved by `distance` (in 1e-6 cells) along its normal.
        let d = f64::from(distance) * 1e-6;
        let (px, py) = (k.0 - dy * d, k.1 + dx * d);
        let a = Point::new((px - dx * ends.0) as f32, (py - dy * ends.0) as f32);
        let b = Point::new((px + dx * ends.1) as f32, (py + dy * ends.1) as f32);
        prop_assert_eq!(
            segment_is_clear_among(g, a, b, &[cell], hull_margin(g)),
            segment_is_clear(g, a, b),
            "{:?} -> {:?} on {}", a, b, side
        );
    }
}

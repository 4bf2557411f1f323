//! The reduced visibility graph of a grid's obstacle corners (feature `alloc`): shortest
//! any-angle paths, exact up to touching obstacles (host only: it needs O(V + E) memory,
//! about 6 MB for a 340 x 164 Moving AI warehouse).
//!
//! Two uses: a rigorous lower bound on the length of any valid path (`host-sim bench
//! lowerbound`), and an independent check of the exact any-angle planner
//! ([`anyangle`](super::anyangle), which replaced this graph's route as the corridor's guide:
//! building the graph is quadratic in the corners).
//!
//! # What is computed
//!
//! Let `B` be the union of the closed unit squares of the blocked cells (cells outside the map
//! included) and `F` its complement. A valid path (SPEC section 1: it touches no blocked cell)
//! lies in `F`, hence in its closure `cl F = R^2 \ int B`. [`VisibilityGraph::shortest`] is the
//! Euclidean length of a shortest path from the start centre to the goal centre inside
//! `cl F`: every valid path is a path in `cl F`, so none is shorter (it is the infimum of the
//! valid lengths, except where `cl F` also offers the pinch point between two diagonally
//! blocked cells, which valid paths cannot use: that only lowers the bound).
//!
//! # Method
//!
//! `cl F` is a closed polygonal domain. A shortest path in it is a polyline whose turning
//! points are reflex vertices of the domain (Lozano-Pérez & Wesley 1979): the lattice points
//! `(i + 1/2, j + 1/2)` with exactly one of the four cells around them blocked (convex
//! obstacle corners), and the pinch points (two diagonal cells blocked). Two vertices are
//! joined when the open segment between them avoids `int B` (see `visible`, exact integer
//! arithmetic). Edges are kept only when they are *tangent* at each obstacle corner they end
//! at (the reduced visibility graph): if the segment's line entered the corner's blocked cell,
//! the bend could be shortcut. Each query adds the start and goal edges and runs A*
//! (Euclidean heuristic, consistent) in `f64`.
//!
//! The *witness* ([`VisibilityGraph::witness`]) moves each corner the path turns at (or
//! grazes) `eps` away from its blocked cell: a valid path whose length exceeds the bound by
//! `O(eps)`.
//!
//! ```
//! use planner_core::{geometry::Cell, grid::{words_for, Grid}, search::visibility::VisibilityGraph};
//!
//! let grid: Grid<{ words_for(5, 3) }> = Grid::parse_rows(b".....\n..@..\n.....\n")?;
//! let vg = VisibilityGraph::new(grid.view());
//! let d = vg.shortest(grid.view(), Cell::new(0, 1), Cell::new(4, 1)).unwrap();
//! // Over the blocked cell's two top corners.
//! assert!((d - (1.0 + 2.0 * 2.5f64.sqrt())).abs() < 1e-12);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

extern crate alloc;

use alloc::collections::BinaryHeap;
use alloc::vec;
use alloc::vec::Vec;
use core::cmp::Ordering;

use crate::geometry::Cell;
use crate::grid::GridRef;

/// A vertex in doubled coordinates: cell `(x, y)` is the open square
/// `(2x - 1, 2x + 1) x (2y - 1, 2y + 1)`, so cell centres are even and corners odd.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Vertex {
    x: i64,
    y: i64,
    /// For a convex obstacle corner, the signs `(sx, sy)` pointing to its one blocked cell;
    /// `None` (pinch points, start, goal): no tangency pruning.
    quad: Option<(i64, i64)>,
}

impl Vertex {
    /// Whether a segment leaving this vertex in direction `(dx, dy)` may be part of a
    /// shortest path: its line must not enter the blocked cell of a corner.
    fn tangent(&self, dx: i64, dy: i64) -> bool {
        match self.quad {
            None => true,
            Some((sx, sy)) => dx.signum() * dy.signum() * sx * sy <= 0,
        }
    }

    fn dist(&self, other: &Vertex) -> f64 {
        let (dx, dy) = ((other.x - self.x) as f64, (other.y - self.y) as f64);
        0.5 * libm::sqrt(dx * dx + dy * dy)
    }

    fn centre(c: Cell) -> Vertex {
        Vertex {
            x: 2 * c.x as i64,
            y: 2 * c.y as i64,
            quad: None,
        }
    }
}

/// `floor(a / b)` for `b > 0`.
fn floor_div(a: i64, b: i64) -> i64 {
    a.div_euclid(b)
}

/// `ceil(a / b)` for `b > 0`.
fn ceil_div(a: i64, b: i64) -> i64 {
    -((-a).div_euclid(b))
}

/// Whether the open segment `(a0, b0)-(a1, b1)` avoids the interior of the blocked region,
/// in doubled coordinates along a major axis `a` (`|a1 - a0| >= |b1 - b0|`, not both 0).
/// `run(c, lo, hi)`: whether any cell with major index `c` and minor index in `lo..=hi` is
/// blocked (cells outside the map are).
fn sweep(
    (mut a0, mut b0): (i64, i64),
    (mut a1, mut b1): (i64, i64),
    run: impl Fn(i64, i64, i64) -> bool,
) -> bool {
    if a0 > a1 {
        (a0, b0, a1, b1) = (a1, b1, a0, b0);
    }
    let (da, db) = (a1 - a0, b1 - b0);
    // Strips c whose open range (2c - 1, 2c + 1) meets the open range (a0, a1).
    let c_first = floor_div(a0 + 1, 2);
    let c_last = ceil_div(a1 + 1, 2) - 1;
    if db == 0 {
        if b0 % 2 == 0 {
            // Inside the row of minor cells b0 / 2: any blocked one is entered.
            let m = b0 / 2;
            return !(c_first..=c_last).any(|c| run(c, m, m));
        }
        // Along the grid line between minor cells lo and lo + 1: the open segment is in
        // int B exactly where both sides are blocked (a lattice point with all four cells
        // blocked has such a pair beside it).
        let lo = floor_div(b0, 2);
        return !(c_first..=c_last).any(|c| run(c, lo, lo) && run(c, lo + 1, lo + 1));
    }
    // Not axis-aligned: it enters int B iff it enters the open square of a blocked cell
    // (it crosses edges and lattice points transversally, into the cells beyond them).
    for c in c_first..=c_last {
        let al = (2 * c - 1).max(a0);
        let ar = (2 * c + 1).min(a1);
        // Minor coordinate times da at al and ar; over the open strip the segment covers
        // the open range (lo, hi) / da.
        let at = |a: i64| b0 * da + (a - a0) * db;
        let (lo, hi) = if db > 0 {
            (at(al), at(ar))
        } else {
            (at(ar), at(al))
        };
        // Minor cells m with (2m + 1) da > lo and (2m - 1) da < hi.
        let m_lo = ceil_div(floor_div(lo, da), 2);
        let m_hi = floor_div(ceil_div(hi, da), 2);
        if run(c, m_lo, m_hi) {
            return false;
        }
    }
    true
}

/// Whether the open segment between `p` and `q` (doubled coordinates) avoids the interior of
/// the blocked region: touching blocked cells (edges, corners, a pinch point between two
/// diagonal cells) is allowed, running between two blocked cells along their shared edge
/// is not.
fn visible(grid: GridRef<'_>, p: (i64, i64), q: (i64, i64)) -> bool {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    if dx == 0 && dy == 0 {
        return true;
    }
    if dx.abs() >= dy.abs() {
        sweep(p, q, |c, lo, hi| {
            grid.column_run_blocked(c as isize, lo as isize, hi as isize)
        })
    } else {
        sweep((p.1, p.0), (q.1, q.0), |c, lo, hi| {
            grid.row_run_blocked(c as isize, lo as isize, hi as isize)
        })
    }
}

fn visible_v(grid: GridRef<'_>, p: &Vertex, q: &Vertex) -> bool {
    visible(grid, (p.x, p.y), (q.x, q.y))
}

/// The reduced visibility graph of one map's obstacle corners (built once per map; queries
/// pass the same grid again).
pub struct VisibilityGraph {
    corners: Vec<Vertex>,
    /// Edges of vertex `i`: `edges[offsets[i]..offsets[i + 1]]` (compressed rows).
    offsets: Vec<u32>,
    edges: Vec<(u32, f64)>,
}

/// Convex obstacle corners and pinch points of a grid (map boundary included).
fn corners(grid: GridRef<'_>) -> Vec<Vertex> {
    let (w, h) = (grid.width() as isize, grid.height() as isize);
    let mut out = Vec::new();
    for j in -1..h {
        for i in -1..w {
            let b = [
                grid.is_blocked(i, j),
                grid.is_blocked(i + 1, j),
                grid.is_blocked(i, j + 1),
                grid.is_blocked(i + 1, j + 1),
            ];
            let quads = [(-1, -1), (1, -1), (-1, 1), (1, 1)];
            let count = b.iter().filter(|&&x| x).count();
            let quad = match count {
                1 => Some(quads[b.iter().position(|&x| x).unwrap_or(0)]),
                2 if b[0] == b[3] => None,
                _ => continue,
            };
            out.push(Vertex {
                x: 2 * i as i64 + 1,
                y: 2 * j as i64 + 1,
                quad,
            });
        }
    }
    out
}

/// `f64` ordered for the heap (smallest first).
#[derive(PartialEq)]
struct Key(f64, u32);
impl Eq for Key {}
impl PartialOrd for Key {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Key {
    fn cmp(&self, other: &Self) -> Ordering {
        other.0.total_cmp(&self.0).then(other.1.cmp(&self.1))
    }
}

impl VisibilityGraph {
    /// Builds the corner-to-corner graph of `grid`: O(V^2) segment tests for V corners
    /// (about 0.3 s for the 3,200 corners of a 340 x 164 Moving AI warehouse).
    pub fn new(grid: GridRef<'_>) -> Self {
        let corners = corners(grid);
        let n = corners.len();
        let mut found: Vec<(u32, u32, f64)> = Vec::new();
        for (i, p) in corners.iter().enumerate() {
            for (j, q) in corners.iter().enumerate().skip(i + 1) {
                let (dx, dy) = (q.x - p.x, q.y - p.y);
                if p.tangent(dx, dy) && q.tangent(-dx, -dy) && visible_v(grid, p, q) {
                    found.push((i as u32, j as u32, p.dist(q)));
                }
            }
        }
        let mut degree = vec![0u32; n + 1];
        for &(i, j, _) in &found {
            degree[i as usize] += 1;
            degree[j as usize] += 1;
        }
        let mut offsets = vec![0u32; n + 1];
        for i in 0..n {
            offsets[i + 1] = offsets[i] + degree[i];
        }
        let mut fill = offsets.clone();
        let mut edges = vec![(0u32, 0.0f64); 2 * found.len()];
        for &(i, j, d) in &found {
            edges[fill[i as usize] as usize] = (j, d);
            fill[i as usize] += 1;
            edges[fill[j as usize] as usize] = (i, d);
            fill[j as usize] += 1;
        }
        VisibilityGraph {
            corners,
            offsets,
            edges,
        }
    }

    fn adjacent(&self, u: usize) -> &[(u32, f64)] {
        &self.edges[self.offsets[u] as usize..self.offsets[u + 1] as usize]
    }

    /// Number of vertices (corners and pinch points).
    pub fn vertices(&self) -> usize {
        self.corners.len()
    }

    /// Number of (undirected) edges.
    pub fn edges(&self) -> usize {
        self.edges.len() / 2
    }

    /// Length of a shortest path from the centre of `start` to the centre of `goal` in the
    /// closure of the free space; `None` when an end is blocked or there is none.
    pub fn shortest(&self, grid: GridRef<'_>, start: Cell, goal: Cell) -> Option<f64> {
        self.shortest_path(grid, start, goal).map(|(d, _)| d)
    }

    /// Like [`shortest`](Self::shortest), with the path's vertices (doubled coordinates,
    /// start first).
    fn shortest_path(
        &self,
        grid: GridRef<'_>,
        start: Cell,
        goal: Cell,
    ) -> Option<(f64, Vec<Vertex>)> {
        if grid.is_blocked(start.x as isize, start.y as isize)
            || grid.is_blocked(goal.x as isize, goal.y as isize)
        {
            return None;
        }
        let (s, t) = (Vertex::centre(start), Vertex::centre(goal));
        if visible_v(grid, &s, &t) {
            return Some((s.dist(&t), vec![s, t]));
        }
        let n = self.corners.len();
        let links = |end: &Vertex| -> Vec<f64> {
            self.corners
                .iter()
                .map(|v| {
                    if v.tangent(end.x - v.x, end.y - v.y) && visible_v(grid, v, end) {
                        v.dist(end)
                    } else {
                        f64::INFINITY
                    }
                })
                .collect()
        };
        let to_goal = links(&t);
        let from_start = links(&s);
        let h: Vec<f64> = self.corners.iter().map(|v| v.dist(&t)).collect();
        // Vertex n is the goal; parent n + 1 is the start.
        let mut g = vec![f64::INFINITY; n + 1];
        let mut parent = vec![u32::MAX; n + 1];
        let mut closed = vec![false; n + 1];
        let mut heap = BinaryHeap::new();
        for (v, &d) in from_start.iter().enumerate() {
            if d.is_finite() {
                g[v] = d;
                parent[v] = n as u32 + 1;
                heap.push(Key(d + h[v], v as u32));
            }
        }
        while let Some(Key(_, u)) = heap.pop() {
            let u = u as usize;
            if closed[u] {
                continue;
            }
            if u == n {
                let mut path = vec![t];
                let mut at = parent[n] as usize;
                while at < n {
                    path.push(self.corners[at]);
                    at = parent[at] as usize;
                }
                path.push(s);
                path.reverse();
                return Some((g[n], path));
            }
            closed[u] = true;
            let gu = g[u];
            let mut relax = |v: usize, d: f64, heap: &mut BinaryHeap<Key>| {
                if d < g[v] {
                    g[v] = d;
                    parent[v] = u as u32;
                    heap.push(Key(d + if v == n { 0.0 } else { h[v] }, v as u32));
                }
            };
            if to_goal[u].is_finite() {
                relax(n, gu + to_goal[u], &mut heap);
            }
            for &(v, d) in self.adjacent(u) {
                if !closed[v as usize] {
                    relax(v as usize, gu + d, &mut heap);
                }
            }
        }
        None
    }

    /// A valid-path candidate near the shortest one: each corner it turns at is moved `eps`
    /// (per axis) away from its blocked cell. `None` when there is no path or it turns at a
    /// pinch point (which cannot be moved off).
    pub fn witness(
        &self,
        grid: GridRef<'_>,
        start: Cell,
        goal: Cell,
        eps: f64,
    ) -> Option<Vec<[f64; 2]>> {
        let (_, turns) = self.shortest_path(grid, start, goal)?;
        // Add the corners each segment grazes on its way (collinear, strictly inside): the
        // moved segments would otherwise cut them.
        let mut path = vec![turns[0]];
        for w in turns.windows(2) {
            let (a, b) = (w[0], w[1]);
            let (dx, dy) = (b.x - a.x, b.y - a.y);
            let mut on: Vec<(i64, Vertex)> = self
                .corners
                .iter()
                .filter_map(|&c| {
                    let (ex, ey) = (c.x - a.x, c.y - a.y);
                    let dot = ex * dx + ey * dy;
                    (ex * dy == ey * dx && dot > 0 && dot < dx * dx + dy * dy).then_some((dot, c))
                })
                .collect();
            on.sort_by_key(|&(dot, _)| dot);
            path.extend(on.into_iter().map(|(_, c)| c));
            path.push(b);
        }
        let last = path.len() - 1;
        path.iter()
            .enumerate()
            .map(|(k, v)| {
                let (x, y) = (v.x as f64 / 2.0, v.y as f64 / 2.0);
                match v.quad {
                    Some((sx, sy)) => Some([x - eps * sx as f64, y - eps * sy as f64]),
                    None if k == 0 || k == last => Some([x, y]),
                    None => None,
                }
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    extern crate std;
    use super::*;
    use crate::grid::{Grid, words_for};
    use crate::path::Path;
    use crate::search::astar::{AStarNode, OpenSlot};
    use crate::search::{SearchNode, astar, theta};
    use alloc::boxed::Box;

    type G = Grid<{ words_for(16, 16) }>;

    fn lb(g: &G, s: (u16, u16), t: (u16, u16)) -> Option<f64> {
        VisibilityGraph::new(g.view()).shortest(g.view(), Cell::new(s.0, s.1), Cell::new(t.0, t.1))
    }

    #[test]
    fn empty_map_is_the_straight_line() {
        let g = G::new(10, 6).unwrap();
        let d = lb(&g, (0, 0), (9, 4)).unwrap();
        assert!((d - 97f64.sqrt()).abs() < 1e-12);
        let d = lb(&g, (3, 5), (3, 0)).unwrap();
        assert!((d - 5.0).abs() < 1e-12);
    }

    #[test]
    fn one_blocked_cell_gives_two_tangents_and_its_side() {
        let g = G::parse_rows(b".....\n..@..\n.....\n").unwrap();
        let d = lb(&g, (0, 1), (4, 1)).unwrap();
        // (0,1) -> corner (1.5,0.5) -> corner (2.5,0.5) -> (4,1).
        assert!((d - (1.0 + 2.0 * 2.5f64.sqrt())).abs() < 1e-12, "{d}");
        // Diagonal past the cell's corner: touching it is allowed, so the straight line.
        let d = lb(&g, (0, 2), (2, 0)).unwrap();
        assert!((d - 8f64.sqrt()).abs() < 1e-12, "{d}");
    }

    #[test]
    fn seams_between_blocked_cells_are_not_free() {
        // A 2-thick wall: the grid line between its rows is inside the blocked region.
        let g = G::parse_rows(b".....\n.@@@.\n.@@@.\n.....\n").unwrap();
        assert!(!visible(g.view(), (1, 3), (7, 3)));
        assert!(visible(g.view(), (1, 1), (7, 1)));
        // The map border is blocked outside: running along it is touching, allowed.
        assert!(visible(g.view(), (-1, -1), (9, -1)));
        assert!(!visible(g.view(), (-3, 0), (0, 0)));
    }

    #[test]
    fn pinch_point_between_diagonal_cells_is_passable() {
        let g = G::parse_rows(b"...\n.@.\n..@\n").unwrap();
        // (2,1)-(1,2) crosses the pinch (1.5,1.5) between (1,1) and (2,2): allowed.
        assert!(visible(g.view(), (4, 2), (2, 4)));
        assert!(!visible(g.view(), (2, 2), (4, 4)));
        assert!(
            corners(g.view())
                .iter()
                .any(|v| (v.x, v.y, v.quad) == (3, 3, None))
        );
    }

    /// A small xorshift generator for the random tests.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 << 13;
            self.0 ^= self.0 >> 7;
            self.0 ^= self.0 << 17;
            self.0
        }
        fn below(&mut self, n: u64) -> u64 {
            self.next() % n
        }
    }

    fn random_grid(rng: &mut Rng, w: usize, h: usize, percent: u64) -> G {
        let mut g = G::new(w, h).unwrap();
        for y in 0..h {
            for x in 0..w {
                g.set_blocked(x, y, rng.below(100) < percent).unwrap();
            }
        }
        g
    }

    /// Exact independent test: does the open segment p-q (doubled coordinates) meet the
    /// interior of the blocked region? Every blocked cell (a ring outside the map included)
    /// is clipped against the open segment, and every shared edge of two blocked neighbours.
    fn brute_blocked(g: GridRef<'_>, p: (i64, i64), q: (i64, i64)) -> bool {
        let (dx, dy) = (q.0 - p.0, q.1 - p.1);
        // Open parameter range (num / den) of t in (0, 1) with lo < p + t d < hi.
        // Represent t bounds as fractions with the common denominator 1 (t in (0,1)) and
        // compare lo_t < hi_t by cross multiplication.
        fn range(p: i64, d: i64, lo: i64, hi: i64) -> Option<((i64, i64), (i64, i64))> {
            if d == 0 {
                return (lo < p && p < hi).then_some(((0, 1), (1, 1)));
            }
            let (a, b) = ((lo - p, d), (hi - p, d));
            let (a, b) = if d > 0 { (a, b) } else { (b, a) };
            let norm = |(n, m): (i64, i64)| if m < 0 { (-n, -m) } else { (n, m) };
            Some((norm(a), norm(b)))
        }
        let less = |a: (i64, i64), b: (i64, i64)| a.0 * b.1 < b.0 * a.1;
        let max = |a: (i64, i64), b: (i64, i64)| if less(a, b) { b } else { a };
        let min = |a: (i64, i64), b: (i64, i64)| if less(a, b) { a } else { b };
        let hits = |xr: (i64, i64), yr: (i64, i64)| -> bool {
            let (Some((x0, x1)), Some((y0, y1))) =
                (range(p.0, dx, xr.0, xr.1), range(p.1, dy, yr.0, yr.1))
            else {
                return false;
            };
            let lo = max(max(x0, y0), (0, 1));
            let hi = min(min(x1, y1), (1, 1));
            less(lo, hi)
        };
        let (w, h) = (g.width() as i64, g.height() as i64);
        for y in -2..=h + 1 {
            for x in -2..=w + 1 {
                if !g.is_blocked(x as isize, y as isize) {
                    continue;
                }
                if hits((2 * x - 1, 2 * x + 1), (2 * y - 1, 2 * y + 1)) {
                    return true;
                }
                // Shared edges with the right and lower neighbours, collinear overlap only
                // (a transversal crossing enters a cell and is caught above).
                if g.is_blocked(x as isize + 1, y as isize)
                    && dx == 0
                    && p.0 == 2 * x + 1
                    && hits((2 * x, 2 * x + 2), (2 * y - 1, 2 * y + 1))
                {
                    return true;
                }
                if g.is_blocked(x as isize, y as isize + 1)
                    && dy == 0
                    && p.1 == 2 * y + 1
                    && hits((2 * x - 1, 2 * x + 1), (2 * y, 2 * y + 2))
                {
                    return true;
                }
            }
        }
        false
    }

    #[test]
    fn visibility_matches_brute_force() {
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        for _ in 0..300 {
            let (w, h) = (1 + rng.below(9) as usize, 1 + rng.below(9) as usize);
            let g = random_grid(&mut rng, w, h, 30);
            for _ in 0..200 {
                // Any point of the half-lattice in or on the map (centres, edge midpoints, corners).
                let mut pt = || {
                    (
                        rng.below(2 * w as u64 + 1) as i64 - 1,
                        rng.below(2 * h as u64 + 1) as i64 - 1,
                    )
                };
                let (p, q) = (pt(), pt());
                if p == q {
                    continue;
                }
                assert_eq!(
                    visible(g.view(), p, q),
                    !brute_blocked(g.view(), p, q),
                    "{w}x{h} {p:?} {q:?}"
                );
            }
        }
    }

    /// Dijkstra over every lattice point and the ends, no pruning, brute-force visibility.
    fn brute_shortest(g: GridRef<'_>, s: Cell, t: Cell) -> Option<f64> {
        let mut pts = vec![
            (2 * s.x as i64, 2 * s.y as i64),
            (2 * t.x as i64, 2 * t.y as i64),
        ];
        for y in 0..=g.height() as i64 {
            for x in 0..=g.width() as i64 {
                pts.push((2 * x - 1, 2 * y - 1));
            }
        }
        let n = pts.len();
        let d = |a: (i64, i64), b: (i64, i64)| {
            0.5 * (((a.0 - b.0).pow(2) + (a.1 - b.1).pow(2)) as f64).sqrt()
        };
        let mut dist = vec![f64::INFINITY; n];
        let mut done = vec![false; n];
        dist[0] = 0.0;
        loop {
            let u = (0..n)
                .filter(|&i| !done[i] && dist[i].is_finite())
                .min_by(|&a, &b| dist[a].total_cmp(&dist[b]))?;
            if u == 1 {
                return Some(dist[1]);
            }
            done[u] = true;
            for v in 0..n {
                if !done[v] && !brute_blocked(g, pts[u], pts[v]) {
                    dist[v] = dist[v].min(dist[u] + d(pts[u], pts[v]));
                }
            }
        }
    }

    #[test]
    fn matches_unpruned_brute_force_on_random_maps() {
        let mut rng = Rng(12345);
        let mut compared = 0;
        for _ in 0..60 {
            let (w, h) = (2 + rng.below(6) as usize, 2 + rng.below(6) as usize);
            let g = random_grid(&mut rng, w, h, 25);
            let vg = VisibilityGraph::new(g.view());
            for _ in 0..4 {
                let s = Cell::new(rng.below(w as u64) as u16, rng.below(h as u64) as u16);
                let t = Cell::new(rng.below(w as u64) as u16, rng.below(h as u64) as u16);
                if !g.view().is_free(s) || !g.view().is_free(t) {
                    continue;
                }
                let (a, b) = (vg.shortest(g.view(), s, t), brute_shortest(g.view(), s, t));
                match (a, b) {
                    (Some(a), Some(b)) => assert!((a - b).abs() < 1e-9, "{a} vs {b}"),
                    _ => assert_eq!(a, b),
                }
                compared += 1;
            }
        }
        assert!(compared > 50);
    }

    #[test]
    fn never_above_theta_star_or_the_octile_optimum() {
        let mut rng = Rng(777);
        let mut nodes = vec![SearchNode::EMPTY; 256];
        let mut astar_nodes = vec![AStarNode::EMPTY; 256];
        let mut open = vec![OpenSlot::EMPTY; 256];
        let mut out: Box<Path<256>> = Box::new(Path::new());
        let mut strict = 0;
        let mut checked = 0;
        let mut witnesses = 0;
        for _ in 0..40 {
            let g = random_grid(&mut rng, 16, 16, 25);
            let vg = VisibilityGraph::new(g.view());
            for _ in 0..20 {
                let s = Cell::new(rng.below(16) as u16, rng.below(16) as u16);
                let t = Cell::new(rng.below(16) as u16, rng.below(16) as u16);
                let Ok(th) = theta::plan(g.view(), s, t, &mut nodes, &mut *out) else {
                    continue;
                };
                let a =
                    astar::plan(g.view(), s, t, &mut astar_nodes, &mut open, &mut *out).unwrap();
                let bound = vg.shortest(g.view(), s, t).expect("a valid path exists");
                assert!(bound <= th.length as f64 + 1e-4, "{bound} > {}", th.length);
                assert!(bound <= a.length as f64 + 1e-4);
                // The witness (when it turns at no pinch point) is about as long.
                if let Some(w) = vg.witness(g.view(), s, t, 1e-3) {
                    let len: f64 = w
                        .windows(2)
                        .map(|p| ((p[1][0] - p[0][0]).powi(2) + (p[1][1] - p[0][1]).powi(2)).sqrt())
                        .sum();
                    assert!(
                        len >= bound - 1e-4 && len <= bound + 0.05,
                        "{len} vs {bound}"
                    );
                    witnesses += 1;
                }
                if bound < th.length as f64 - 1e-3 {
                    strict += 1;
                }
                checked += 1;
            }
        }
        assert!(checked > 200, "{checked}");
        assert!(witnesses > 100, "{witnesses}");
        assert!(strict > 0);
    }
}

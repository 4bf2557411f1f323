//! The interval search: Polyanya (Cui, Harabor, Grastien, IJCAI 2017) on the rectangle mesh,
//! in exact integer geometry.
//!
//! A search node is a *root* (the start, or an obstacle corner the path bends at) and a
//! cone of directions from it that passes through a piece of a rectangle's top or bottom
//! edge into that rectangle. Expanding it projects the cone across the rectangle onto the
//! pieces of the opposite edge (same root), and, where the cone was cut by an obstacle
//! corner, turns around that corner: the corner becomes the root of the part of the
//! rectangle the cone could not see. A path may also run along a grid line over the top of
//! a row of blocked cells and bend down behind it: *flat* nodes carry those.
//!
//! Coordinates are doubled integers (cell `(x, y)` spans `[2x, 2x + 2] x [2y, 2y + 2]`, its
//! centre is `(2x + 1, 2y + 1)`, corners are even). A cone is a range of slopes `dx / dy`,
//! each a fraction of small integers (the offset to a lattice point), so every projection
//! and comparison is exact: no tolerance decides which side of a corner a ray passes.
//! Lengths are `f32` (they only order the search; the path's corners are exact).

use super::mesh::{Mesh, NONE, Rect};
use crate::error::PlanError;
use crate::grid::GridRef;

/// The root key of the start point (other roots are `rect * 4 + corner`).
pub(super) const START: u32 = u32::MAX;

/// A point in doubled coordinates.
pub(super) type P2 = (i32, i32);

/// A direction as `p / q` (horizontal per vertical travel), `q > 0`: differences of
/// doubled coordinates, which fit an `i16` on maps of up to [`MAX_SIDE`] cells a side.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub(super) struct Slope {
    p: i16,
    q: i16,
}

/// The longest side the search takes (doubled coordinates fit an `i16`).
pub const MAX_SIDE: usize = (i16::MAX as usize - 1) / 2;

impl Slope {
    /// Callers pass differences of doubled coordinates of a map of at most [`MAX_SIDE`]
    /// cells a side (`plan` checks the size), so the casts keep the values.
    fn new(p: i32, q: i32) -> Self {
        Slope {
            p: p as i16,
            q: q as i16,
        }
    }

    /// `self < other`, exactly.
    fn lt(self, other: Slope) -> bool {
        (self.p as i64) * (other.q as i64) < (other.p as i64) * (self.q as i64)
    }

    fn le(self, other: Slope) -> bool {
        !other.lt(self)
    }

    fn max(self, other: Slope) -> Slope {
        if self.lt(other) { other } else { self }
    }

    fn min(self, other: Slope) -> Slope {
        if other.lt(self) { other } else { self }
    }

    /// The x reached after travelling `t` vertically from `x0`, as an `f32`.
    fn at(self, x0: i32, t: i32) -> f32 {
        x0 as f32 + self.p as f32 * t as f32 / self.divisor() as f32
    }

    /// The denominator as a divisor (cones always have `q > 0`; 1 keeps a broken node from
    /// dividing by zero).
    fn divisor(self) -> i64 {
        (self.q as i64).max(1)
    }

    /// The x reached after travelling `t` from `x0`, rounded down.
    fn floor_at(self, x0: i32, t: i32) -> i32 {
        x0 + (self.p as i64 * t as i64).div_euclid(self.divisor()) as i32
    }

    /// The x reached after travelling `t` from `x0`, rounded up.
    fn ceil_at(self, x0: i32, t: i32) -> i32 {
        x0 - (-(self.p as i64) * t as i64).div_euclid(self.divisor()) as i32
    }

    /// The x reached after travelling `t` from `x0`, when it is an integer.
    fn exact_at(self, x0: i32, t: i32) -> Option<i32> {
        let num = self.p as i64 * t as i64;
        let q = self.divisor();
        (num % q == 0).then(|| x0 + (num / q) as i32)
    }
}

/// What a node carries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[repr(u8)]
enum Kind {
    /// A cone of slopes `[lo, hi]` from the root into `rect`.
    #[default]
    Cone,
    /// A stretch `[lo.p, hi.p]` of the grid line the root lies on, leading into `rect`.
    Flat,
    /// The goal, reached from the root at cost `g`.
    Goal,
}

/// An open search node (32 bytes).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Node {
    f: f32,
    g: f32,
    root: u32,
    rect: u32,
    from: u32,
    lo: Slope,
    hi: Slope,
    kind: Kind,
}

impl Node {
    /// An unused slot (all zero bytes).
    pub const EMPTY: Node = Node {
        f: 0.0,
        g: 0.0,
        root: 0,
        rect: 0,
        from: 0,
        lo: Slope { p: 0, q: 0 },
        hi: Slope { p: 0, q: 0 },
        kind: Kind::Cone,
    };

    /// Heap order: least `f`, ties to the largest `g` (deeper first). Costs are finite and
    /// not negative, so their bit patterns order like the values.
    fn before(&self, other: &Node) -> bool {
        (self.f.to_bits(), !self.g.to_bits()) < (other.f.to_bits(), !other.g.to_bits())
    }
}

/// The best known cost of reaching each corner of a rectangle as a root, and the root it
/// was reached from (32 bytes a rectangle).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roots {
    g: [f32; 4],
    parent: [u32; 4],
}

impl Roots {
    /// An unused slot (all zero bytes; a query resets the slots it uses).
    pub const EMPTY: Roots = Roots {
        g: [0.0; 4],
        parent: [0; 4],
    };
    const FRESH: Roots = Roots {
        g: [f32::INFINITY; 4],
        parent: [START; 4],
    };
}

/// What a search reports besides the corners.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Counts {
    pub expanded: u32,
    pub pushed: u32,
    pub open_peak: u32,
    /// The least `f` of the nodes a full open list dropped (infinite when none was): a
    /// path found at no more than this cost is still the shortest.
    pub dropped: f32,
}

impl Default for Counts {
    fn default() -> Self {
        Counts {
            expanded: 0,
            pushed: 0,
            open_peak: 0,
            dropped: f32::INFINITY,
        }
    }
}

/// The binary min-heap of open nodes in the caller's slice.
struct Heap<'a> {
    nodes: &'a mut [Node],
    len: usize,
}

impl Heap<'_> {
    /// Pushes `node`. When the list is full, the thirty-second of it that comes last in heap
    /// order (at least one node) is dropped first: one selection and one heap rebuild, so a
    /// full list costs O(1) a push on average (dropping one node at a time scanned the
    /// leaves on every push: minutes with millions of nodes). The least `f` dropped is
    /// returned.
    fn push(&mut self, node: Node) -> Option<f32> {
        let mut dropped = None;
        if self.len == self.nodes.len() {
            if self.len == 0 {
                return Some(node.f);
            }
            let keep = self.len - (self.len / 32).max(1);
            select(&mut self.nodes[..self.len], keep);
            let first_dropped = self.nodes[keep];
            dropped = Some(first_dropped.f);
            self.len = keep;
            for i in (0..keep / 2).rev() {
                let node = self.nodes[i];
                self.sift_down(i, node);
            }
            if !node.before(&self.nodes[keep]) {
                // The new node is no better than the best one dropped.
                return dropped;
            }
        }
        self.len += 1;
        self.sift_up(self.len - 1, node);
        dropped
    }

    /// Places `node` at slot `i` (a leaf or the new end) and moves it up to its place.
    fn sift_up(&mut self, mut i: usize, node: Node) {
        while i > 0 {
            let parent = (i - 1) / 2;
            if !node.before(&self.nodes[parent]) {
                break;
            }
            self.nodes[i] = self.nodes[parent];
            i = parent;
        }
        self.nodes[i] = node;
    }

    fn pop(&mut self) -> Option<Node> {
        if self.len == 0 {
            return None;
        }
        let top = self.nodes[0];
        self.len -= 1;
        let last = self.nodes[self.len];
        self.sift_down(0, last);
        Some(top)
    }

    /// Places `node` at slot `i` and moves it down to its place among `..len`.
    fn sift_down(&mut self, mut i: usize, node: Node) {
        loop {
            let l = 2 * i + 1;
            if l >= self.len {
                break;
            }
            let r = l + 1;
            let c = if r < self.len && self.nodes[r].before(&self.nodes[l]) {
                r
            } else {
                l
            };
            if !self.nodes[c].before(&node) {
                break;
            }
            self.nodes[i] = self.nodes[c];
            i = c;
        }
        self.nodes[i] = node;
    }
}

/// Reorders `nodes` so that the node at `k` is the one heap order puts there, those before
/// it come no later and those after no earlier: Hoare's selection (median of three, equal
/// keys split between the sides). Small code: the library's `select_nth_unstable_by` added
/// 4 KiB of flash.
fn select(nodes: &mut [Node], k: usize) {
    if nodes.is_empty() {
        return;
    }
    let (mut lo, mut hi) = (0usize, nodes.len() - 1);
    while lo < hi {
        let mid = lo + (hi - lo) / 2;
        if nodes[mid].before(&nodes[lo]) {
            nodes.swap(mid, lo);
        }
        if nodes[hi].before(&nodes[lo]) {
            nodes.swap(hi, lo);
        }
        if nodes[hi].before(&nodes[mid]) {
            nodes.swap(hi, mid);
        }
        let pivot = nodes[mid];
        // Hoare's partition: afterwards `lo..=p` come no later than the pivot and
        // `p + 1..=hi` no earlier, with `lo <= p < hi`.
        let (mut i, mut j) = (lo, hi);
        let p = loop {
            while nodes[i].before(&pivot) {
                i += 1;
            }
            while pivot.before(&nodes[j]) {
                j -= 1;
            }
            if i >= j {
                break j;
            }
            nodes.swap(i, j);
            i += 1;
            j -= 1;
        };
        if k <= p {
            hi = p;
        } else {
            lo = p + 1;
        }
    }
}

/// One query's state.
pub(super) struct Search<'q, 'm> {
    grid: GridRef<'q>,
    mesh: Mesh<'m>,
    roots: &'q mut [Roots],
    heap: Heap<'q>,
    start: P2,
    goal: P2,
    goal_rect: u32,
    pub counts: Counts,
}

/// Which end of a cone.
#[derive(Clone, Copy, PartialEq, Eq)]
enum Side {
    Left,
    Right,
}

impl<'q, 'm> Search<'q, 'm> {
    /// A search from the centre of cell `start` (in rectangle `start_rect`) to the centre of
    /// `goal` (in `goal_rect`).
    pub(super) fn new(
        grid: GridRef<'q>,
        mesh: Mesh<'m>,
        roots: &'q mut [Roots],
        open: &'q mut [Node],
        start: P2,
        goal: P2,
        goal_rect: u32,
    ) -> Result<Self, PlanError> {
        let roots = roots
            .get_mut(..mesh.rects())
            .ok_or(PlanError::CapacityExceeded)?;
        roots.fill(Roots::FRESH);
        Ok(Search {
            grid,
            mesh,
            roots,
            heap: Heap {
                nodes: open,
                len: 0,
            },
            start,
            goal,
            goal_rect,
            counts: Counts::default(),
        })
    }

    /// Runs the search from the start's rectangle, expanding at most `max_expanded` nodes
    /// ([`PlanError::BudgetExhausted`] beyond); the root keys of the shortest path are then
    /// read back with [`Search::parent`] from the returned key (the last corner before the
    /// goal, or [`START`]). `Ok(None)`: the goal is unreachable.
    pub(super) fn run(
        &mut self,
        start_rect: u32,
        max_expanded: u32,
    ) -> Result<Option<(u32, f32)>, PlanError> {
        let mesh = self.mesh;
        let s = mesh.rect(start_rect);
        if start_rect == self.goal_rect {
            return Ok(Some((START, dist(self.start, self.goal))));
        }
        for up in [true, false] {
            let line = 2 * if up { s.y0 } else { s.y1 } as i32;
            let t = (line - self.start.1).abs();
            for q in neighbours(&mesh, start_rect, up) {
                let (pl, pr) = portal(&s, &mesh.rect(q));
                let (lo, hi) = (
                    Slope::new(pl - self.start.0, t),
                    Slope::new(pr - self.start.0, t),
                );
                self.push_cone(START, 0.0, self.start, (q, start_rect), lo, hi)?;
            }
        }
        while let Some(node) = self.heap.pop() {
            if node.kind == Kind::Goal {
                return Ok(Some((node.root, node.g)));
            }
            if node.root != START && node.g > self.root_g(node.root) {
                continue; // its root was reached more cheaply since
            }
            if self.counts.expanded >= max_expanded {
                return Err(PlanError::BudgetExhausted);
            }
            self.counts.expanded += 1;
            match node.kind {
                Kind::Cone => self.expand_cone(&node)?,
                Kind::Flat => self.expand_flat(&node)?,
                Kind::Goal => {}
            }
        }
        // Out of nodes: the goal is unreachable, unless a node was dropped for room.
        if self.counts.dropped.is_finite() {
            return Err(PlanError::CapacityExceeded);
        }
        Ok(None)
    }

    /// The root a root was reached from ([`START`] for the start).
    pub(super) fn parent(&self, key: u32) -> u32 {
        self.roots
            .get(key as usize / 4)
            .map_or(START, |r| r.parent[key as usize % 4])
    }

    /// The point of a root.
    pub(super) fn point(&self, key: u32) -> P2 {
        if key == START {
            return self.start;
        }
        corner_point(&self.mesh.rect(key / 4), key % 4)
    }

    fn root_g(&self, key: u32) -> f32 {
        self.roots
            .get(key as usize / 4)
            .map_or(f32::INFINITY, |r| r.g[key as usize % 4])
    }

    /// Records `key` reached at cost `g` from `parent`; false when it was known as cheap.
    fn improve(&mut self, key: u32, g: f32, parent: u32) -> bool {
        match self.roots.get_mut(key as usize / 4) {
            Some(r) if g < r.g[key as usize % 4] => {
                r.g[key as usize % 4] = g;
                r.parent[key as usize % 4] = parent;
                true
            }
            _ => false,
        }
    }

    fn push(&mut self, node: Node) -> Result<(), PlanError> {
        if let Some(f) = self.heap.push(node) {
            self.counts.dropped = self.counts.dropped.min(f);
        }
        self.counts.pushed += 1;
        self.counts.open_peak = self.counts.open_peak.max(self.heap.len as u32);
        Ok(())
    }

    /// Pushes the cone `[lo, hi]` of root `root` (at `r`, reached at cost `g`) into
    /// rectangle `rect`, entered from rectangle `from`.
    fn push_cone(
        &mut self,
        root: u32,
        g: f32,
        r: P2,
        (rect, from): (u32, u32),
        lo: Slope,
        hi: Slope,
    ) -> Result<(), PlanError> {
        let target = self.mesh.rect(rect);
        let line = near_line(&target, r);
        let h = self.h_cone(r, lo, hi, line);
        self.push(Node {
            f: g + h,
            g,
            root,
            rect,
            from,
            lo,
            hi,
            kind: Kind::Cone,
        })
    }

    fn push_flat(
        &mut self,
        root: u32,
        g: f32,
        c: P2,
        rect: u32,
        from: u32,
        (l, r): (i32, i32),
    ) -> Result<(), PlanError> {
        let near = if c.0 >= r { r } else { l };
        let h = (c.0 - near).abs() as f32 + dist((near, c.1), self.goal);
        self.push(Node {
            f: g + h,
            g,
            root,
            rect,
            from,
            lo: Slope::new(l, 0),
            hi: Slope::new(r, 0),
            kind: Kind::Flat,
        })
    }

    fn push_goal(&mut self, root: u32, cost: f32) -> Result<(), PlanError> {
        self.push(Node {
            f: cost,
            g: cost,
            root,
            kind: Kind::Goal,
            ..Node::EMPTY
        })
    }

    /// Admissible estimate of the rest of a path through the cone `[lo, hi]` from `r`,
    /// crossing line `y` (the goal is mirrored when it lies on the root's side).
    fn h_cone(&self, r: P2, lo: Slope, hi: Slope, y: i32) -> f32 {
        let t = (y - r.1).abs();
        let (a, b) = (lo.at(r.0, t), hi.at(r.0, t));
        let (gx, mut gy) = (self.goal.0 as f32, self.goal.1);
        if (gy - y).signum() == (r.1 - y).signum() {
            gy = 2 * y - gy;
        }
        let (rx, ry, gyf, yf) = (r.0 as f32, r.1 as f32, gy as f32, y as f32);
        let cross = rx + (gx - rx) * (yf - ry) / (gyf - ry);
        let via = |x: f32| dist_f((rx, ry), (x, yf)) + dist_f((x, yf), (gx, gyf));
        if cross < a {
            via(a)
        } else if cross > b {
            via(b)
        } else {
            dist_f((rx, ry), (gx, gyf))
        }
    }

    fn expand_cone(&mut self, n: &Node) -> Result<(), PlanError> {
        let mesh = self.mesh;
        let p = mesh.rect(n.rect);
        let r = self.point(n.root);
        let up = r.1 >= 2 * p.y1 as i32;
        let (yn, yf) = if up {
            (2 * p.y1 as i32, 2 * p.y0 as i32)
        } else {
            (2 * p.y0 as i32, 2 * p.y1 as i32)
        };
        let (tn, tf) = ((yn - r.1).abs(), (yf - r.1).abs());
        // Seen from the root: the pieces of the far edge inside the cone.
        let (xl, xr) = (n.lo.floor_at(r.0, tf), n.hi.ceil_at(r.0, tf));
        for q in mesh.neighbours_in(n.rect, up, xl, xr) {
            let (pl, pr) = portal(&p, &mesh.rect(q));
            let lo = n.lo.max(Slope::new(pl - r.0, tf));
            let hi = n.hi.min(Slope::new(pr - r.0, tf));
            if lo.le(hi) {
                self.push_cone(n.root, n.g, r, (q, n.rect), lo, hi)?;
            }
        }
        let goal_slope = (n.rect == self.goal_rect)
            .then(|| Slope::new(self.goal.0 - r.0, (self.goal.1 - r.1).abs()));
        if let Some(s) = goal_slope
            && n.lo.le(s)
            && s.le(n.hi)
        {
            self.push_goal(n.root, n.g + dist(r, self.goal))?;
        }
        // Around the corners that cut the cone.
        for side in [Side::Left, Side::Right] {
            let edge = if side == Side::Left { n.lo } else { n.hi };
            let Some(ax) = edge.exact_at(r.0, tn) else {
                continue;
            };
            if ax & 1 != 0 {
                continue;
            }
            let col = if side == Side::Left {
                ax / 2 - 1
            } else {
                ax / 2
            };
            let (front_row, back_row) = if up {
                (yn / 2 - 1, yn / 2)
            } else {
                (yn / 2, yn / 2 - 1)
            };
            let front = self.grid.is_blocked(col as isize, front_row as isize);
            let back = self.grid.is_blocked(col as isize, back_row as isize);
            if front == back {
                continue; // open space, or a straight wall: nothing to turn around
            }
            let owner = if front { n.rect } else { n.from };
            let Some(key) = corner_key(&mesh, owner, (ax, yn), side == Side::Right) else {
                continue;
            };
            let a = (ax, yn);
            let ga = n.g + dist(r, a);
            if !self.improve(key, ga, n.root) {
                continue;
            }
            // The part of the rectangle beyond the cone's edge, seen from the corner.
            let t = (yf - yn).abs();
            let (from, to) = if side == Side::Left {
                (2 * p.x0 as i32, edge.ceil_at(ax, t))
            } else {
                (edge.floor_at(ax, t), 2 * p.x1 as i32)
            };
            for q in mesh.neighbours_in(n.rect, up, from, to) {
                let (pl, pr) = portal(&p, &mesh.rect(q));
                let (lo, hi) = if side == Side::Left {
                    (Slope::new(pl - ax, t), Slope::new(pr - ax, t).min(edge))
                } else {
                    (Slope::new(pl - ax, t).max(edge), Slope::new(pr - ax, t))
                };
                if lo.le(hi) {
                    self.push_cone(key, ga, a, (q, n.rect), lo, hi)?;
                }
            }
            if let Some(s) = goal_slope {
                let beyond = if side == Side::Left {
                    s.lt(edge)
                } else {
                    edge.lt(s)
                };
                if beyond {
                    self.push_goal(key, ga + dist(a, self.goal))?;
                }
            }
            // Along the line over the blocked cells behind, then down behind them.
            if back {
                let (from, to) = if side == Side::Left {
                    (2 * p.x0 as i32, ax)
                } else {
                    (ax, 2 * p.x1 as i32)
                };
                for d in mesh.neighbours_in(n.rect, !up, from, to) {
                    if d == n.from {
                        continue;
                    }
                    let (l, rr) = portal(&p, &mesh.rect(d));
                    let beyond = if side == Side::Left {
                        rr <= ax
                    } else {
                        l >= ax
                    };
                    if beyond {
                        self.push_flat(key, ga, a, d, n.rect, (l, rr))?;
                    }
                }
            }
        }
        Ok(())
    }

    fn expand_flat(&mut self, n: &Node) -> Result<(), PlanError> {
        let mesh = self.mesh;
        let c = self.point(n.root);
        let (l, r) = (n.lo.p as i32, n.hi.p as i32);
        let leftwards = c.0 >= r;
        let nx = if leftwards { r } else { l };
        let t = mesh.rect(n.rect);
        // The stretch ends at a wall of the rectangle beyond the line (or of the one the
        // path ran along).
        let owner = if (leftwards && 2 * t.x1 as i32 == nx) || (!leftwards && 2 * t.x0 as i32 == nx)
        {
            n.rect
        } else {
            n.from
        };
        let Some(key) = corner_key(&mesh, owner, (nx, c.1), leftwards) else {
            return Ok(());
        };
        let m = (nx, c.1);
        let gm = n.g + (c.0 - nx).abs() as f32;
        if !self.improve(key, gm, n.root) {
            return Ok(());
        }
        // All of the rectangle is in view of its corner.
        let up = c.1 == 2 * t.y1 as i32;
        let height = 2 * (t.y1 - t.y0) as i32;
        for q in neighbours(&mesh, n.rect, up) {
            let (pl, pr) = portal(&t, &mesh.rect(q));
            let (lo, hi) = (Slope::new(pl - nx, height), Slope::new(pr - nx, height));
            self.push_cone(key, gm, m, (q, n.rect), lo, hi)?;
        }
        if n.rect == self.goal_rect {
            self.push_goal(key, gm + dist(m, self.goal))?;
        }
        // Further along the line, over this rectangle's edge.
        let (from, to) = if leftwards {
            (2 * t.x0 as i32, nx)
        } else {
            (nx, 2 * t.x1 as i32)
        };
        for u in mesh.neighbours_in(n.rect, !up, from, to) {
            if u == n.from {
                continue;
            }
            let (ul, ur) = portal(&t, &mesh.rect(u));
            let beyond = if leftwards { ur <= nx } else { ul >= nx };
            if beyond {
                self.push_flat(key, gm, m, u, n.rect, (ul, ur))?;
            }
        }
        Ok(())
    }
}

/// The neighbours of `r` above (`up`) or below it.
fn neighbours<'a>(mesh: &'a Mesh<'_>, r: u32, up: bool) -> impl Iterator<Item = u32> + 'a {
    let (mut a, mut b) = (None, None);
    if up {
        a = Some(mesh.above(r));
    } else {
        b = Some(mesh.below(r));
    }
    a.into_iter().flatten().chain(b.into_iter().flatten())
}

/// The piece of grid line two vertically adjacent rectangles share, doubled x.
fn portal(a: &Rect, b: &Rect) -> (i32, i32) {
    (2 * a.x0.max(b.x0) as i32, 2 * a.x1.min(b.x1) as i32)
}

/// The line through which a root at `r` enters `rect`: its bottom when the root is below.
fn near_line(rect: &Rect, r: P2) -> i32 {
    if r.1 >= 2 * rect.y1 as i32 {
        2 * rect.y1 as i32
    } else {
        2 * rect.y0 as i32
    }
}

/// Corner `k` of a rectangle: 0 top left, 1 top right, 2 bottom left, 3 bottom right.
fn corner_point(r: &Rect, k: u32) -> P2 {
    let x = if k & 1 == 0 { r.x0 } else { r.x1 };
    let y = if k & 2 == 0 { r.y0 } else { r.y1 };
    (2 * x as i32, 2 * y as i32)
}

/// The root key of point `at` as a corner of rectangle `owner` (left or right end of its
/// edge on `at`'s line); `None` if it is not one.
fn corner_key(mesh: &Mesh<'_>, owner: u32, at: P2, right: bool) -> Option<u32> {
    if owner == NONE {
        return None;
    }
    let rect = mesh.rect(owner);
    let bottom = if at.1 == 2 * rect.y1 as i32 {
        2
    } else if at.1 == 2 * rect.y0 as i32 {
        0
    } else {
        return None;
    };
    let k = bottom + right as u32;
    (corner_point(&rect, k) == at).then_some(owner * 4 + k)
}

pub(super) fn dist(a: P2, b: P2) -> f32 {
    dist_f((a.0 as f32, a.1 as f32), (b.0 as f32, b.1 as f32))
}

fn dist_f(a: (f32, f32), b: (f32, f32)) -> f32 {
    let (dx, dy) = (b.0 - a.0, b.1 - a.1);
    crate::math::sqrt(dx * dx + dy * dy)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sizes_are_as_documented() {
        assert_eq!(core::mem::size_of::<Node>(), 32);
        assert_eq!(core::mem::size_of::<Roots>(), 32);
        assert_eq!(core::mem::size_of::<Rect>(), 24);
        assert_eq!(core::mem::size_of::<super::super::Link>(), 8);
    }

    #[test]
    fn a_full_open_list_drops_its_worst_and_says_how_good_they_were() {
        let mut store = [Node::EMPTY; 64];
        let mut heap = Heap {
            nodes: &mut store,
            len: 0,
        };
        let node = |f: f32| Node { f, ..Node::EMPTY };
        for i in 0..64 {
            assert_eq!(heap.push(node((i * 7 % 64) as f32)), None);
        }
        // Full: 64 nodes, f 0..64; the worst two (62, 63) go, then 3.5 joins.
        assert_eq!(heap.push(node(3.5)), Some(62.0));
        assert_eq!(heap.len, 63);
        assert_eq!(heap.push(node(70.0)), None);
        // Full again: 70 and 61 go; 80, no better than them, is not kept either.
        assert_eq!(heap.push(node(80.0)), Some(61.0));
        assert_eq!(heap.len, 62);
        let order: std::vec::Vec<f32> = core::iter::from_fn(|| heap.pop().map(|n| n.f)).collect();
        assert!(order.windows(2).all(|w| w[0] <= w[1]), "{order:?}");
        assert_eq!((order.len(), order.first()), (62, Some(&0.0)));
        assert!(!order.contains(&62.0) && !order.contains(&70.0) && order.contains(&3.5));
    }

    #[test]
    fn selection_splits_around_the_kth() {
        let node = |f: f32| Node { f, ..Node::EMPTY };
        let mut seed = 7u32;
        for len in [1usize, 2, 3, 10, 100, 257] {
            for k in [0, len / 3, len / 2, len - 1] {
                // Many ties: 8 distinct keys.
                let mut nodes: std::vec::Vec<Node> = (0..len)
                    .map(|_| {
                        seed = seed.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
                        node((seed >> 29) as f32)
                    })
                    .collect();
                let mut sorted: std::vec::Vec<f32> = nodes.iter().map(|n| n.f).collect();
                sorted.sort_by(f32::total_cmp);
                select(&mut nodes, k);
                assert_eq!(nodes[k].f, sorted[k], "len {len} k {k}");
                assert!(nodes[..k].iter().all(|n| n.f <= nodes[k].f));
                assert!(nodes[k + 1..].iter().all(|n| n.f >= nodes[k].f));
            }
        }
        // All equal: no quadratic descent, and still split.
        let mut same = std::vec![node(1.0); 4096];
        select(&mut same, 2048);
        assert_eq!(same[2048].f, 1.0);
    }

    #[test]
    fn slopes_compare_exactly() {
        let a = Slope::new(1, 3);
        let b = Slope::new(2, 6);
        assert!(a.le(b) && b.le(a) && !a.lt(b));
        assert!(Slope::new(-8190, 1).lt(Slope::new(-8189, 1)));
        assert_eq!(Slope::new(3, 2).exact_at(10, 4), Some(16));
        assert_eq!(Slope::new(3, 2).exact_at(10, 3), None);
    }
}

//! Exact reference planners on the 8-connected grid and connectivity labelling.
//!
//! - [`astar`]: A* with octile costs and no corner cutting: the shortest 8-connected path
//!   (Moving AI's published optimal lengths are golden values for it);
//! - [`theta`]: Theta*, any-angle paths never longer than A*'s;
//! - [`connectivity`]: component labels, so that an unreachable goal is reported at once.
//!
//! The search state lives in a caller-owned slice of [`SearchNode`] with one entry per map
//! cell (a `static` array in firmware, a `Vec` on a host), so no planner allocates and the
//! same code serves every map size.
//!
//! ```
//! use planner_core::{geometry::Cell, grid::{words_for, Grid}, path::Path, search};
//!
//! let grid: Grid<{ words_for(4, 3) }> = Grid::parse_rows(b"....\n.@@.\n....\n")?;
//! let mut nodes = [search::SearchNode::EMPTY; 12];
//! let mut path: Path<16> = Path::new();
//! let stats = search::astar::plan(grid.view(), Cell::new(0, 1), Cell::new(3, 1), &mut nodes, &mut path)?;
//! // Around the wall: no diagonal may cut the corners of (1,1) and (2,1).
//! assert_eq!(path.len(), 6);
//! assert_eq!(stats.length, 5.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod astar;
pub mod connectivity;
pub mod theta;

use crate::error::PlanError;
use crate::geometry::{Cell, Point};
use crate::grid::GridRef;
use crate::path::PathView;

/// Per-cell search state. Keep one per map cell; the contents between calls are scratch.
#[derive(Clone, Copy, Debug)]
pub struct SearchNode {
    g: f32,
    f: f32,
    parent: u32,
    /// Position of this cell in the open heap while open.
    heap_pos: u32,
    /// The binary heap of open cells is stored in this field across the node array: slot
    /// `i` of the heap is `nodes[i].heap_slot`. Reusing the array saves a second buffer.
    heap_slot: u32,
    state: NodeState,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum NodeState {
    New,
    Open,
    Closed,
}

impl SearchNode {
    /// An unused node (for array initialisers).
    pub const EMPTY: SearchNode = SearchNode {
        g: 0.0,
        f: 0.0,
        parent: 0,
        heap_pos: 0,
        heap_slot: 0,
        state: NodeState::New,
    };
}

/// Owned search storage of `N` nodes, for a `static` in firmware.
pub struct SearchStorage<const N: usize> {
    /// The nodes; pass `&mut storage.nodes` to a planner.
    pub nodes: [SearchNode; N],
}

impl<const N: usize> SearchStorage<N> {
    /// Fresh storage.
    pub const fn new() -> Self {
        SearchStorage {
            nodes: [SearchNode::EMPTY; N],
        }
    }
}

impl<const N: usize> Default for SearchStorage<N> {
    fn default() -> Self {
        Self::new()
    }
}

/// What a reference search reports besides the path.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SearchStats {
    /// Length of the returned path (cell units).
    pub length: f32,
    /// Cells taken off the open list.
    pub expanded: u32,
}

/// The eight moves with their costs; diagonals need both side cells free.
pub(crate) const MOVES: [(i8, i8, f32); 8] = [
    (1, 0, 1.0),
    (-1, 0, 1.0),
    (0, 1, 1.0),
    (0, -1, 1.0),
    (1, 1, core::f32::consts::SQRT_2),
    (1, -1, core::f32::consts::SQRT_2),
    (-1, 1, core::f32::consts::SQRT_2),
    (-1, -1, core::f32::consts::SQRT_2),
];

/// Whether the 8-connected move from `(x, y)` by `(dx, dy)` is allowed (no corner cutting).
#[inline]
pub(crate) fn move_allowed(grid: GridRef<'_>, x: isize, y: isize, dx: isize, dy: isize) -> bool {
    !grid.is_blocked(x + dx, y + dy)
        && (dx == 0 || dy == 0 || (!grid.is_blocked(x + dx, y) && !grid.is_blocked(x, y + dy)))
}

/// The checks every planner makes before searching, in the order of [`PlanError`].
pub fn check_endpoints(grid: GridRef<'_>, start: Cell, goal: Cell) -> Result<(), PlanError> {
    if grid.index(start).is_none() {
        return Err(PlanError::StartOutsideMap);
    }
    if grid.index(goal).is_none() {
        return Err(PlanError::GoalOutsideMap);
    }
    if !grid.is_free(start) {
        return Err(PlanError::StartOccupied);
    }
    if !grid.is_free(goal) {
        return Err(PlanError::GoalOccupied);
    }
    Ok(())
}

/// The open list: an indexed binary min-heap on `(f, -g)` stored inside the node array.
pub(crate) struct Open<'n> {
    nodes: &'n mut [SearchNode],
    len: usize,
}

impl<'n> Open<'n> {
    /// Resets every node (O(cells), a memset-like pass) and returns an empty open list.
    pub(crate) fn new(nodes: &'n mut [SearchNode]) -> Self {
        for n in nodes.iter_mut() {
            n.state = NodeState::New;
        }
        Open { nodes, len: 0 }
    }

    pub(crate) fn node(&self, i: usize) -> &SearchNode {
        &self.nodes[i]
    }

    pub(crate) fn is_closed(&self, i: usize) -> bool {
        self.nodes[i].state == NodeState::Closed
    }

    pub(crate) fn g(&self, i: usize) -> f32 {
        self.nodes[i].g
    }

    /// Opens cell `i` or lowers its cost; ignores closed cells and worse costs.
    pub(crate) fn relax(&mut self, i: usize, g: f32, h: f32, parent: usize) {
        let node = &mut self.nodes[i];
        match node.state {
            NodeState::Closed => {}
            NodeState::Open if g >= node.g => {}
            NodeState::Open => {
                node.g = g;
                node.f = g + h;
                node.parent = parent as u32;
                let pos = node.heap_pos as usize;
                self.sift_up(pos);
            }
            NodeState::New => {
                node.g = g;
                node.f = g + h;
                node.parent = parent as u32;
                node.state = NodeState::Open;
                let pos = self.len;
                self.len += 1;
                self.place(pos, i);
                self.sift_up(pos);
            }
        }
    }

    /// Takes the open cell of least `f` (ties: largest `g`) and closes it.
    pub(crate) fn pop(&mut self) -> Option<usize> {
        if self.len == 0 {
            return None;
        }
        let top = self.nodes[0].heap_slot as usize;
        self.len -= 1;
        if self.len > 0 {
            let last = self.nodes[self.len].heap_slot as usize;
            self.place(0, last);
            self.sift_down(0);
        }
        self.nodes[top].state = NodeState::Closed;
        Some(top)
    }

    fn place(&mut self, pos: usize, cell: usize) {
        self.nodes[pos].heap_slot = cell as u32;
        self.nodes[cell].heap_pos = pos as u32;
    }

    fn less(&self, a: usize, b: usize) -> bool {
        let (na, nb) = (&self.nodes[a], &self.nodes[b]);
        na.f < nb.f || (na.f == nb.f && na.g > nb.g)
    }

    fn sift_up(&mut self, mut pos: usize) {
        let cell = self.nodes[pos].heap_slot as usize;
        while pos > 0 {
            let parent_pos = (pos - 1) / 2;
            let parent = self.nodes[parent_pos].heap_slot as usize;
            if !self.less(cell, parent) {
                break;
            }
            self.place(pos, parent);
            pos = parent_pos;
        }
        self.place(pos, cell);
    }

    fn sift_down(&mut self, mut pos: usize) {
        let cell = self.nodes[pos].heap_slot as usize;
        loop {
            let left = 2 * pos + 1;
            if left >= self.len {
                break;
            }
            let mut child = left;
            let right = left + 1;
            if right < self.len
                && self.less(
                    self.nodes[right].heap_slot as usize,
                    self.nodes[left].heap_slot as usize,
                )
            {
                child = right;
            }
            let child_cell = self.nodes[child].heap_slot as usize;
            if !self.less(child_cell, cell) {
                break;
            }
            self.place(pos, child_cell);
            pos = child;
        }
        self.place(pos, cell);
    }

    /// Writes the parent chain from `goal` back to `start` into `out`, start first.
    pub(crate) fn write_path(
        &self,
        grid: GridRef<'_>,
        start: usize,
        goal: usize,
        out: &mut PathView,
    ) -> Result<(), PlanError> {
        out.clear();
        let mut i = goal;
        loop {
            out.push(grid.cell(i).center())
                .map_err(|_| PlanError::CapacityExceeded)?;
            if i == start {
                break;
            }
            let parent = self.nodes[i].parent as usize;
            // A parent chain longer than the map would be a cycle: treat as corruption.
            if out.len() > grid.cells() {
                return Err(PlanError::NoValidPath);
            }
            i = parent;
        }
        out.reverse();
        Ok(())
    }
}

/// Octile heuristic between row-major indices' cells, without division in the hot loop.
#[inline]
pub(crate) fn octile_xy(ax: isize, ay: isize, bx: isize, by: isize) -> f32 {
    let dx = (ax - bx).unsigned_abs() as f32;
    let dy = (ay - by).unsigned_abs() as f32;
    let (lo, hi) = if dx < dy { (dx, dy) } else { (dy, dx) };
    hi + (core::f32::consts::SQRT_2 - 1.0) * lo
}

/// Euclidean heuristic.
#[inline]
pub(crate) fn euclid_xy(ax: isize, ay: isize, bx: isize, by: isize) -> f32 {
    Point::new(ax as f32, ay as f32).distance(Point::new(bx as f32, by as f32))
}

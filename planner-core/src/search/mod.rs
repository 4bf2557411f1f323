//! Exact reference planners on the 8-connected grid and connectivity labelling.
//!
//! - [`astar`]: A* with octile costs and no corner cutting: the shortest 8-connected path
//!   (Moving AI's published optimal lengths are golden values for it);
//! - [`theta`]: Theta*, any-angle paths never longer than A*'s;
//! - [`anyangle`]: the exact shortest any-angle path (Polyanya's interval search on the free
//!   space cut into rectangles, built once per map in linear time), with exact
//!   unreachability;
//! - [`connectivity`]: component labels, so that an unreachable goal is reported at once;
//! - `visibility` (feature `alloc`, host only): the reduced visibility graph of the obstacle
//!   corners (quadratic to build), an independent check of `anyangle` and a lower bound.
//!
//! The search state lives in caller-owned slices with one entry per map cell (a `static`
//! array in firmware, a `Vec` on a host), so no planner allocates and the same code serves
//! every map size: A* takes 4-byte [`astar::AStarNode`]s plus an open list of
//! [`astar::OpenSlot`]s whose length the caller chooses (see [`astar`]); Theta* takes
//! 24-byte [`SearchNode`]s.
//!
//! ```
//! use planner_core::{geometry::Cell, grid::{words_for, Grid}, path::Path, search};
//! use search::astar::{AStarNode, OpenSlot};
//!
//! let grid: Grid<{ words_for(4, 3) }> = Grid::parse_rows(b"....\n.@@.\n....\n")?;
//! let mut nodes = [AStarNode::EMPTY; 12];
//! let mut open = [OpenSlot::EMPTY; search::astar::open_capacity(12)];
//! let mut path: Path<16> = Path::new();
//! let stats = search::astar::plan(grid.view(), Cell::new(0, 1), Cell::new(3, 1), &mut nodes, &mut open, &mut path)?;
//! // Around the wall: no diagonal may cut the corners of (1,1) and (2,1).
//! assert_eq!(path.len(), 6);
//! assert_eq!(stats.length, 5.0);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod anyangle;
pub mod astar;
pub mod connectivity;
pub mod theta;
#[cfg(feature = "alloc")]
#[cfg_attr(docsrs, doc(cfg(feature = "alloc")))]
pub mod visibility;

use crate::error::PlanError;
use crate::geometry::{Cell, Point};
use crate::grid::GridRef;
use crate::path::PathView;

/// Per-cell Theta* state (24 bytes). Keep one per map cell. Planners leave every node as
/// they found it (reset), so storage is never cleared in O(cells) between calls.
#[derive(Clone, Copy, Debug)]
pub struct SearchNode {
    g: f32,
    parent: u32,
    /// The cell's state: `NEW`, `CLOSED`, or else open at heap position `heap_pos - 2`.
    heap_pos: u32,
    /// Slot `i` of the open heap (or of the stack of closed cells, which grows down from
    /// the end of the array) is stored in `nodes[i]`: the cell and, for the heap, its key
    /// `(f, g)`, so that heap comparisons read consecutive slots instead of random cells.
    /// Reusing the array saves a second buffer.
    slot_f: u32,
    slot_g: u32,
    slot_cell: u32,
}

/// `heap_pos` of a cell not reached yet. Zero, so that [`SearchNode::EMPTY`] is all-zero
/// bytes and a `static` node array lands in `.bss` (no flash image). Open cells store their
/// heap position plus 2 (heap positions stay below the cell count, at most 65535^2, so
/// this never overflows).
const NEW: u32 = 0;
/// `heap_pos` of a closed cell.
const CLOSED: u32 = 1;
/// Offset of a stored heap position.
const OPEN_BASE: u32 = 2;

impl SearchNode {
    /// An unused node (for array initialisers).
    pub const EMPTY: SearchNode = SearchNode {
        g: 0.0,
        parent: 0,
        heap_pos: NEW,
        slot_f: 0,
        slot_g: 0,
        slot_cell: 0,
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
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SearchStats {
    /// Length of the returned path (cell units).
    pub length: f32,
    /// Cells taken off the open list.
    pub expanded: u32,
    /// Largest number of cells open at once: an A* open list of this many slots suffices
    /// for the same query (see [`astar::open_capacity`]).
    #[cfg_attr(feature = "serde", serde(default))]
    pub open_peak: u32,
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

/// The free cells of the 3 x 3 block around `(x, y)`: bit `3 (dy + 1) + (dx + 1)` is set
/// when `(x + dx, y + dy)` is on the map and free. Read once per expansion, so the eight
/// moves cost nine grid lookups instead of sixteen.
#[inline]
fn free_around(grid: GridRef<'_>, x: isize, y: isize) -> u16 {
    let mut mask = 0;
    for dy in -1..=1 {
        for dx in -1..=1 {
            if !grid.is_blocked(x + dx, y + dy) {
                mask |= 1 << (3 * (dy + 1) + dx + 1);
            }
        }
    }
    mask
}

/// Whether the 8-connected move by `(dx, dy)` is allowed (no corner cutting), given the
/// [`free_around`] mask of the cell it starts from.
const fn move_allowed(free: u16, dx: isize, dy: isize) -> bool {
    const fn is_free(free: u16, dx: isize, dy: isize) -> bool {
        free & (1 << (3 * (dy + 1) + dx + 1)) != 0
    }
    is_free(free, dx, dy) && (dx == 0 || dy == 0 || (is_free(free, dx, 0) && is_free(free, 0, dy)))
}

/// For every [`free_around`] mask, the allowed moves: bit `k` set when `MOVES[k]` is.
/// A table lookup instead of eight data-dependent branches per expansion.
static ALLOWED: [u8; 512] = {
    let mut table = [0u8; 512];
    let mut free = 0;
    while free < 512 {
        let mut k = 0;
        while k < MOVES.len() {
            if move_allowed(free as u16, MOVES[k].0 as isize, MOVES[k].1 as isize) {
                table[free] |= 1 << k;
            }
            k += 1;
        }
        free += 1;
    }
    table
};

/// The moves allowed from `(x, y)`: bit `k` set when `MOVES[k]` is. Visit them in
/// ascending `k` (the order of [`MOVES`]).
#[inline]
pub(crate) fn allowed_moves(grid: GridRef<'_>, x: isize, y: isize) -> u8 {
    ALLOWED[free_around(grid, x, y) as usize & 511]
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
///
/// Every node is `NEW` when the list is created and again when it is dropped: the cells
/// it touched are exactly those in the heap (slots `0..len`) and those on the closed stack
/// (slots `n - closed..n`; `len + closed` never exceeds the number of cells opened), so
/// dropping resets them in O(touched) instead of clearing all cells on every query.
pub(crate) struct Open<'n> {
    nodes: &'n mut [SearchNode],
    len: usize,
    closed: usize,
    peak: usize,
}

/// A heap entry: the cell and its key, `(f, g)` packed into one integer so that the heap
/// order "least `f`, ties to the largest `g`" is a single unsigned comparison.
///
/// Costs are never negative (nor NaN), and for such `f32` values the bit patterns order
/// like the values (and `+0.0` is the only zero that arises), so `key(a) < key(b)` is
/// exactly `a.f < b.f || (a.f == b.f && a.g > b.g)`.
#[derive(Clone, Copy)]
pub(crate) struct Entry {
    key: u64,
    cell: u32,
}

impl Entry {
    #[inline]
    fn new(f: f32, g: f32, cell: usize) -> Self {
        debug_assert!(f >= 0.0 && g >= 0.0);
        Entry {
            key: pack(f.to_bits(), !g.to_bits()),
            cell: cell as u32,
        }
    }

    /// Heap order: least `f`, ties to the largest `g`.
    #[inline]
    fn less(&self, other: &Entry) -> bool {
        self.key < other.key
    }
}

#[inline]
fn pack(hi: u32, lo: u32) -> u64 {
    (hi as u64) << 32 | lo as u64
}

impl<'n> Open<'n> {
    /// An empty open list over `nodes`, which must all be `NEW` (as planners leave them).
    pub(crate) fn new(nodes: &'n mut [SearchNode]) -> Self {
        debug_assert!(nodes.iter().all(|n| n.heap_pos == NEW));
        Open {
            nodes,
            len: 0,
            closed: 0,
            peak: 0,
        }
    }

    pub(crate) fn node(&self, i: usize) -> &SearchNode {
        &self.nodes[i]
    }

    pub(crate) fn is_closed(&self, i: usize) -> bool {
        self.nodes[i].heap_pos == CLOSED
    }

    pub(crate) fn g(&self, i: usize) -> f32 {
        self.nodes[i].g
    }

    /// Opens cell `i` or lowers its cost; ignores closed cells and worse costs.
    #[inline]
    pub(crate) fn relax(&mut self, i: usize, g: f32, h: f32, parent: usize) {
        let node = &mut self.nodes[i];
        // The cell's `heap_pos` is (re)written when `sift_up` places it.
        let pos = match node.heap_pos {
            CLOSED => return,
            NEW => {
                self.len += 1;
                self.peak = self.peak.max(self.len);
                self.len - 1
            }
            _ if g >= node.g => return,
            pos => (pos - OPEN_BASE) as usize,
        };
        node.g = g;
        node.parent = parent as u32;
        self.sift_up(pos, Entry::new(g + h, g, i));
    }

    /// Takes the open cell of least `f` (ties: largest `g`) and closes it.
    pub(crate) fn pop(&mut self) -> Option<usize> {
        if self.len == 0 {
            return None;
        }
        let top = self.nodes[0].slot_cell as usize;
        self.len -= 1;
        if self.len > 0 {
            let last = self.slot(self.len);
            self.sift_down(0, last);
        }
        self.nodes[top].heap_pos = CLOSED;
        self.closed += 1;
        let n = self.nodes.len();
        self.nodes[n - self.closed].slot_cell = top as u32;
        Some(top)
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

/// A binary min-heap whose slots live in caller storage: Theta* keeps them in its node
/// array, A* in a separate open list, and both record a cell's heap position on every
/// move. The sift algorithms are shared here; `place` does the bookkeeping.
pub(crate) trait HeapSlots {
    /// What a slot holds (the cell and its key).
    type Slot: Copy;
    /// Slots in use.
    fn heap_len(&self) -> usize;
    /// The slot at `pos`.
    fn slot(&self, pos: usize) -> Self::Slot;
    /// Stores `slot` at `pos` (and records the position for its cell).
    fn place(&mut self, pos: usize, slot: Self::Slot);
    /// Heap order.
    fn less(a: &Self::Slot, b: &Self::Slot) -> bool;

    /// Moves `slot`, to be stored at `pos`, up to its place.
    #[inline]
    fn sift_up(&mut self, mut pos: usize, slot: Self::Slot) {
        while pos > 0 {
            let parent_pos = (pos - 1) / 2;
            let parent = self.slot(parent_pos);
            if !Self::less(&slot, &parent) {
                break;
            }
            self.place(pos, parent);
            pos = parent_pos;
        }
        self.place(pos, slot);
    }

    /// Moves `slot`, to be stored at `pos`, down to its place.
    ///
    /// Floyd's variant: the hole first runs down the path of least children to the bottom
    /// (one comparison per level, not two), then `slot` climbs back while its parent is not
    /// less than it. Along that path the keys never decrease, so `slot` ends exactly where
    /// the textbook sift-down (stop at the first child not less than `slot`) puts it, and
    /// the heap, hence the order of expansion, is the same.
    #[inline]
    fn sift_down(&mut self, mut pos: usize, slot: Self::Slot) {
        let start = pos;
        let len = self.heap_len();
        loop {
            let left = 2 * pos + 1;
            if left >= len {
                break;
            }
            // Which child is less is a coin toss for the branch predictor: select it by
            // arithmetic on the index, not by a branch.
            let right = left + 1;
            let take_right = right < len && Self::less(&self.slot(right), &self.slot(left));
            let child = left + take_right as usize;
            let child_slot = self.slot(child);
            self.place(pos, child_slot);
            pos = child;
        }
        while pos > start {
            let parent_pos = (pos - 1) / 2;
            let parent = self.slot(parent_pos);
            if Self::less(&parent, &slot) {
                break;
            }
            self.place(pos, parent);
            pos = parent_pos;
        }
        self.place(pos, slot);
    }
}

impl HeapSlots for Open<'_> {
    type Slot = Entry;

    #[inline]
    fn heap_len(&self) -> usize {
        self.len
    }

    #[inline]
    fn slot(&self, pos: usize) -> Entry {
        let slot = &self.nodes[pos];
        Entry {
            key: pack(slot.slot_f, slot.slot_g),
            cell: slot.slot_cell,
        }
    }

    #[inline]
    fn place(&mut self, pos: usize, e: Entry) {
        let slot = &mut self.nodes[pos];
        slot.slot_f = (e.key >> 32) as u32;
        slot.slot_g = e.key as u32;
        slot.slot_cell = e.cell;
        self.nodes[e.cell as usize].heap_pos = pos as u32 + OPEN_BASE;
    }

    #[inline]
    fn less(a: &Entry, b: &Entry) -> bool {
        a.less(b)
    }
}

impl Drop for Open<'_> {
    /// Resets every touched node to `NEW` (runs on every exit of a planner).
    fn drop(&mut self) {
        let n = self.nodes.len();
        for pos in (0..self.len).chain(n - self.closed..n) {
            let cell = self.nodes[pos].slot_cell as usize;
            self.nodes[cell].heap_pos = NEW;
        }
    }
}

/// One neighbour offered to a planner's relaxation rule by [`best_first`].
pub(crate) struct Step {
    /// The cell being expanded.
    pub i: usize,
    /// The neighbour.
    pub j: usize,
    /// The neighbour's coordinates.
    pub nx: isize,
    /// The neighbour's coordinates.
    pub ny: isize,
    /// Cost of the grid move `i -> j` (1 or sqrt 2).
    pub cost: f32,
    /// Heuristic of the neighbour.
    pub h: f32,
}

/// What [`best_first`] searches: the map, the endpoints and, if given, the map's component
/// labels (an unreachable goal is then refused before the search).
pub(crate) struct Query<'a> {
    pub grid: GridRef<'a>,
    pub start: Cell,
    pub goal: Cell,
    pub labels: Option<&'a [u32]>,
}

/// A best-first loop over [`SearchNode`]s: endpoint checks, storage and reachability checks,
/// the open list, the allowed 8-connected moves, and the path at the end; the planner gives
/// the heuristic and how a neighbour is relaxed (`relax`, called for every allowed move to a
/// cell that is not closed yet). Theta* runs on it; A* has its own loop over compact storage
/// (see [`astar`]), since its parents are neighbours and it never reads a closed cell's `g`.
pub(crate) fn best_first(
    query: Query<'_>,
    nodes: &mut [SearchNode],
    out: &mut PathView,
    heuristic: fn(isize, isize, isize, isize) -> f32,
    mut relax: impl FnMut(&mut Open<'_>, &Step),
) -> Result<SearchStats, PlanError> {
    let Query {
        grid,
        start,
        goal,
        labels,
    } = query;
    check_endpoints(grid, start, goal)?;
    if nodes.len() < grid.cells() {
        return Err(PlanError::CapacityExceeded);
    }
    if let Some(labels) = labels
        && !connectivity::connected(grid, labels, start, goal)?
    {
        return Err(PlanError::NoValidPath);
    }
    let width = grid.width() as isize;
    let (Some(s), Some(t)) = (grid.index(start), grid.index(goal)) else {
        return Err(PlanError::StartOutsideMap);
    };
    let (gx, gy) = (goal.x as isize, goal.y as isize);
    let mut open = Open::new(nodes);
    open.relax(
        s,
        0.0,
        heuristic(start.x as isize, start.y as isize, gx, gy),
        s,
    );
    let mut expanded = 0u32;
    while let Some(i) = open.pop() {
        expanded += 1;
        if i == t {
            let length = open.g(t);
            open.write_path(grid, s, t, out)?;
            return Ok(SearchStats {
                length,
                expanded,
                open_peak: open.peak as u32,
            });
        }
        let (x, y) = ((i as isize) % width, (i as isize) / width);
        let mut moves = allowed_moves(grid, x, y);
        while moves != 0 {
            let (dx, dy, cost) = MOVES[moves.trailing_zeros() as usize];
            moves &= moves - 1;
            let (nx, ny) = (x + dx as isize, y + dy as isize);
            let j = (ny * width + nx) as usize;
            if open.is_closed(j) {
                continue;
            }
            let h = heuristic(nx, ny, gx, gy);
            relax(
                &mut open,
                &Step {
                    i,
                    j,
                    nx,
                    ny,
                    cost,
                    h,
                },
            );
        }
    }
    Err(PlanError::NoValidPath)
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

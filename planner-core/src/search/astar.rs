//! A* on the 8-connected grid: octile costs (1 and sqrt 2), no corner cutting, octile
//! heuristic (consistent, so the first time the goal is taken off the open list its cost is
//! optimal). Ties on `f` prefer the larger `g`, which expands fewer cells on open floors.
//!
//! # Storage
//!
//! Two caller-owned slices, sized by the caller (heapless style):
//!
//! - `nodes`: one [`AStarNode`] (4 bytes) per map cell: new, closed with the direction it was
//!   reached from (3 bits), or open at a position of the heap;
//! - `open`: the open list, an indexed binary min-heap of [`OpenSlot`]s (12 bytes: `f`, `g`
//!   and the cell with its direction). It holds each open cell once (decrease-key), so it
//!   never needs more than [`open_capacity`]`(cells)` slots; a smaller buffer is allowed and
//!   a search that outgrows it returns [`PlanError::CapacityExceeded`].
//!
//! Why this layout (a 4-byte record per cell and a caller-sized decrease-key heap, not 24
//! bytes a cell nor a lazy-deletion heap): `docs/design/astar-storage.md`.
//!
//! Theta* keeps [`SearchNode`](super::SearchNode): its parents are arbitrary cells, not
//! neighbours, and it reads the `g` of closed cells.
//!
//! ```
//! use planner_core::{geometry::Cell, grid::{words_for, Grid}, path::Path};
//! use planner_core::search::astar::{self, AStarNode, OpenSlot};
//!
//! let grid: Grid<{ words_for(8, 3) }> = Grid::parse_rows(b"........\n.@@@@@@.\n........\n")?;
//! let mut nodes = [AStarNode::EMPTY; 24];
//! // Always enough: one slot per cell.
//! let mut open = [OpenSlot::EMPTY; astar::open_capacity(24)];
//! let mut path: Path<32> = Path::new();
//! let stats = astar::plan(grid.view(), Cell::new(0, 1), Cell::new(7, 1), &mut nodes, &mut open, &mut path)?;
//! assert_eq!(stats.length, 9.0); // over the wall's end: no corner cutting
//! assert!(stats.open_peak as usize <= open.len());
//! // A smaller open list is the caller's choice; outgrowing it is an error, not a panic.
//! let mut tiny = [OpenSlot::EMPTY; 1];
//! assert_eq!(
//!     astar::plan(grid.view(), Cell::new(0, 1), Cell::new(7, 1), &mut nodes, &mut tiny, &mut path),
//!     Err(planner_core::PlanError::CapacityExceeded)
//! );
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use super::{
    HeapSlots, MOVES, SearchStats, allowed_moves, check_endpoints, connectivity, octile_xy,
};
use crate::error::PlanError;
use crate::geometry::Cell;
use crate::grid::GridRef;
use crate::path::PathView;

/// Per-cell A* state (4 bytes): keep one per map cell. Planners leave every node as they
/// found it, so storage is never cleared in O(cells) between calls.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AStarNode(u32);

// `AStarNode` states. Zero is "new", so that a `static` node array is all-zero bytes and
// lands in `.bss`. A closed cell keeps the index into `MOVES` of the move that reached it in
// the top three bits (its parent is one step back); an open cell keeps its heap position
// (plus `OPEN_BASE`) and its direction travels in its heap slot instead, so that moving a
// slot rewrites the state without masking.
const NEW: u32 = 0;
const CLOSED: u32 = 1;
const OPEN_BASE: u32 = 2;
const DIR_SHIFT: u32 = 29;
const STATE_MASK: u32 = (1 << DIR_SHIFT) - 1;
/// Most cells a map may have: the heap slot stores `cell << 3 | direction` in 32 bits.
pub const MAX_CELLS: usize = 1 << DIR_SHIFT;

impl AStarNode {
    /// An unused node (for array initialisers).
    pub const EMPTY: AStarNode = AStarNode(NEW);
}

impl Default for AStarNode {
    fn default() -> Self {
        Self::EMPTY
    }
}

/// One slot of the A* open list (12 bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct OpenSlot {
    /// `f` bits: costs are never negative nor NaN, and such `f32`s order like their bits.
    f: u32,
    /// `!g` bits, so that `(f, !g)` as one `u64` orders "least `f`, ties to the largest `g`".
    not_g: u32,
    /// `cell << 3 | direction`.
    cell_dir: u32,
}

impl OpenSlot {
    /// An unused slot (for array initialisers).
    pub const EMPTY: OpenSlot = OpenSlot {
        f: 0,
        not_g: 0,
        cell_dir: 0,
    };

    #[inline]
    fn key(&self) -> u64 {
        (self.f as u64) << 32 | self.not_g as u64
    }

    #[inline]
    fn g(&self) -> f32 {
        f32::from_bits(!self.not_g)
    }
}

impl Default for OpenSlot {
    fn default() -> Self {
        Self::EMPTY
    }
}

/// Open-list slots that can never overflow on a map of `cells` cells (each cell is open at
/// most once at a time). Hosts size a `Vec` with it; firmware may choose fewer from the
/// [`SearchStats::open_peak`] of its maps and handle [`PlanError::CapacityExceeded`].
pub const fn open_capacity(cells: usize) -> usize {
    cells
}

/// Plans the shortest 8-connected path from `start` to `goal`, writing every cell centre
/// along it into `out` (start first).
///
/// `nodes` needs one entry per map cell; `open` any number of slots (see the module docs and
/// [`open_capacity`]). Errors: the endpoint checks of [`check_endpoints`],
/// [`PlanError::CapacityExceeded`] when `nodes`, `open` or `out` is too small (or the map has
/// more than [`MAX_CELLS`] cells), [`PlanError::NoValidPath`] when the goal is unreachable.
pub fn plan(
    grid: GridRef<'_>,
    start: Cell,
    goal: Cell,
    nodes: &mut [AStarNode],
    open: &mut [OpenSlot],
    out: &mut PathView,
) -> Result<SearchStats, PlanError> {
    plan_with_labels(grid, start, goal, None, nodes, open, out)
}

/// Like [`plan`], but first consults precomputed component labels (see
/// [`connectivity::label`]) so that an unreachable goal costs O(1) instead of a full search.
pub fn plan_with_labels(
    grid: GridRef<'_>,
    start: Cell,
    goal: Cell,
    labels: Option<&[u32]>,
    nodes: &mut [AStarNode],
    open: &mut [OpenSlot],
    out: &mut PathView,
) -> Result<SearchStats, PlanError> {
    check_endpoints(grid, start, goal)?;
    if nodes.len() < grid.cells() || grid.cells() > MAX_CELLS {
        return Err(PlanError::CapacityExceeded);
    }
    if let Some(labels) = labels
        && !connectivity::connected(grid, labels, start, goal)?
    {
        return Err(PlanError::NoValidPath);
    }
    let (Some(s), Some(t)) = (grid.index(start), grid.index(goal)) else {
        return Err(PlanError::StartOutsideMap);
    };
    let width = grid.width() as isize;
    let (gx, gy) = (goal.x as isize, goal.y as isize);
    let (sx, sy) = (start.x as isize, start.y as isize);
    let mut heap = Heap::new(&mut nodes[..grid.cells()], open, grid.width());
    heap.relax(s, sx, sy, 0.0, octile_xy(sx, sy, gx, gy), 0)?;
    let mut expanded = 0u32;
    while let Some((i, g)) = heap.pop() {
        expanded += 1;
        let (x, y) = ((i as isize) % width, (i as isize) / width);
        heap.expanding(x as usize, y as usize);
        if i == t {
            heap.write_path(grid, s, t, out)?;
            return Ok(SearchStats {
                length: g,
                expanded,
                open_peak: heap.peak as u32,
            });
        }
        let mut moves = allowed_moves(grid, x, y);
        while moves != 0 {
            let k = moves.trailing_zeros();
            let (dx, dy, cost) = MOVES[k as usize];
            moves &= moves - 1;
            let (nx, ny) = (x + dx as isize, y + dy as isize);
            let j = (ny * width + nx) as usize;
            heap.relax_with(j, nx, ny, g + cost, k, |nx, ny| octile_xy(nx, ny, gx, gy))?;
        }
    }
    Err(PlanError::NoValidPath)
}

/// The open list over `open` and the cell states in `nodes`.
///
/// Every node is `NEW` when the heap is created and again when it is dropped. The touched
/// cells are the open ones (in the heap) and the closed ones, whose indices are recorded
/// three to a slot in the unused top of `open` while the heap leaves room; dropping resets
/// exactly those (O(touched), e.g. 3,600 cells for a 1,200-cell diagonal whose bounding box
/// holds 1.44 million). When the heap grows into the record, or the record is large next to
/// the box, dropping clears the bounding box of the expanded cells grown by one row by row
/// instead (every touched cell is the start or a neighbour of an expanded cell). The record
/// never takes a slot the heap needs, so capacity errors are those of the heap alone.
struct Heap<'n> {
    nodes: &'n mut [AStarNode],
    open: &'n mut [OpenSlot],
    width: usize,
    len: usize,
    peak: usize,
    /// Bounding box of the expanded cells, `x0 > x1` while empty.
    x0: usize,
    x1: usize,
    y0: usize,
    y1: usize,
    /// Closed cells recorded at the top of `open` (three `u32` indices a slot), while
    /// `recording`.
    closed: usize,
    recording: bool,
}

impl<'n> Heap<'n> {
    fn new(nodes: &'n mut [AStarNode], open: &'n mut [OpenSlot], width: usize) -> Self {
        debug_assert!(nodes.iter().all(|n| n.0 == NEW));
        // Open states store `position + OPEN_BASE` below the direction bits.
        let cap = open.len().min((STATE_MASK - OPEN_BASE) as usize);
        Heap {
            nodes,
            open: &mut open[..cap],
            width,
            len: 0,
            peak: 0,
            x0: usize::MAX,
            x1: 0,
            y0: usize::MAX,
            y1: 0,
            closed: 0,
            recording: true,
        }
    }

    /// Slots the closed-cell record occupies at the top of `open`.
    #[inline]
    fn record_slots(&self) -> usize {
        self.closed.div_ceil(3)
    }

    /// Records closed cell `cell` at the top of `open`, or stops recording when the heap
    /// needs that room.
    #[inline]
    fn record_closed(&mut self, cell: u32) {
        if !self.recording {
            return;
        }
        let slot_pos = self.open.len() - 1 - self.closed / 3;
        if slot_pos <= self.len {
            self.recording = false;
            return;
        }
        let slot = &mut self.open[slot_pos];
        match self.closed % 3 {
            0 => slot.f = cell,
            1 => slot.not_g = cell,
            _ => slot.cell_dir = cell,
        }
        self.closed += 1;
    }

    #[inline]
    fn relax(
        &mut self,
        i: usize,
        x: isize,
        y: isize,
        g: f32,
        h: f32,
        dir: u32,
    ) -> Result<(), PlanError> {
        self.relax_with(i, x, y, g, dir, |_, _| h)
    }

    /// Opens cell `i` at `(x, y)`, reached by move `dir` at cost `g`, or lowers its cost;
    /// ignores closed cells and worse costs. The heuristic is computed only for a change.
    #[inline]
    fn relax_with(
        &mut self,
        i: usize,
        x: isize,
        y: isize,
        g: f32,
        dir: u32,
        h: impl FnOnce(isize, isize) -> f32,
    ) -> Result<(), PlanError> {
        let state = self.nodes[i].0;
        let pos = if state == NEW {
            if self.len == self.open.len() {
                return Err(PlanError::CapacityExceeded);
            }
            if self.recording && self.len + self.record_slots() >= self.open.len() {
                // The heap's next slot holds part of the record: the box clears instead.
                self.recording = false;
            }
            self.len += 1;
            self.peak = self.peak.max(self.len);
            self.len - 1
        } else if state & STATE_MASK == CLOSED {
            return Ok(());
        } else {
            let pos = (state - OPEN_BASE) as usize;
            if g >= self.open[pos].g() {
                return Ok(());
            }
            pos
        };
        debug_assert!(g >= 0.0);
        let slot = OpenSlot {
            f: (g + h(x, y)).to_bits(),
            not_g: !g.to_bits(),
            cell_dir: (i as u32) << 3 | dir,
        };
        self.sift_up(pos, slot);
        Ok(())
    }

    /// Records that the cell at `(x, y)` is being expanded (see the type's docs).
    #[inline]
    fn expanding(&mut self, x: usize, y: usize) {
        self.x0 = self.x0.min(x);
        self.x1 = self.x1.max(x);
        self.y0 = self.y0.min(y);
        self.y1 = self.y1.max(y);
    }

    /// Takes the open cell of least `f` (ties: largest `g`), closes it and returns it with
    /// its `g`.
    fn pop(&mut self) -> Option<(usize, f32)> {
        if self.len == 0 {
            return None;
        }
        let top = self.open[0];
        self.len -= 1;
        if self.len > 0 {
            let last = self.open[self.len];
            self.sift_down(0, last);
        }
        let cell = (top.cell_dir >> 3) as usize;
        self.nodes[cell].0 = CLOSED | (top.cell_dir & 7) << DIR_SHIFT;
        self.record_closed(cell as u32);
        Some((cell, top.g()))
    }

    /// Writes the path from `start` to `goal` (closed) into `out`, start first, by following
    /// the stored directions back from `goal`.
    fn write_path(
        &self,
        grid: GridRef<'_>,
        start: usize,
        goal: usize,
        out: &mut PathView,
    ) -> Result<(), PlanError> {
        out.clear();
        let width = self.width as isize;
        let mut i = goal;
        loop {
            out.push(grid.cell(i).center())
                .map_err(|_| PlanError::CapacityExceeded)?;
            if i == start {
                break;
            }
            // A chain longer than the map would be a cycle: treat as corruption.
            if out.len() > grid.cells() {
                return Err(PlanError::NoValidPath);
            }
            let (dx, dy, _) = MOVES[(self.nodes[i].0 >> DIR_SHIFT) as usize];
            let back = i as isize - (dy as isize * width + dx as isize);
            i = match usize::try_from(back) {
                Ok(p) if p < self.nodes.len() => p,
                _ => return Err(PlanError::NoValidPath),
            };
        }
        out.reverse();
        Ok(())
    }
}

impl HeapSlots for Heap<'_> {
    type Slot = OpenSlot;

    #[inline]
    fn heap_len(&self) -> usize {
        self.len
    }

    #[inline]
    fn slot(&self, pos: usize) -> OpenSlot {
        self.open[pos]
    }

    #[inline]
    fn place(&mut self, pos: usize, slot: OpenSlot) {
        self.open[pos] = slot;
        self.nodes[(slot.cell_dir >> 3) as usize].0 = pos as u32 + OPEN_BASE;
    }

    #[inline]
    fn less(a: &OpenSlot, b: &OpenSlot) -> bool {
        a.key() < b.key()
    }
}

impl Drop for Heap<'_> {
    /// Resets every touched node to `NEW` (runs on every exit of the planner).
    fn drop(&mut self) {
        if self.x0 > self.x1 {
            // Nothing expanded: at most the start was opened.
            if let Some(slot) = self.open.first().filter(|_| self.len > 0) {
                let cell = (slot.cell_dir >> 3) as usize;
                if let Some(node) = self.nodes.get_mut(cell) {
                    *node = AStarNode::EMPTY;
                }
            }
            return;
        }
        let height = self.nodes.len() / self.width.max(1);
        let (x0, x1) = (self.x0.saturating_sub(1), (self.x1 + 1).min(self.width - 1));
        let (y0, y1) = (self.y0.saturating_sub(1), (self.y1 + 1).min(height - 1));
        let boxed = (x1 - x0 + 1) * (y1 - y0 + 1);
        // Scattered stores cost several times a sequential fill per cell.
        if self.recording && 8 * (self.closed + self.len) < boxed {
            let top = self.open.len();
            for k in 0..self.closed {
                let slot = &self.open[top - 1 - k / 3];
                let cell = match k % 3 {
                    0 => slot.f,
                    1 => slot.not_g,
                    _ => slot.cell_dir,
                };
                if let Some(node) = self.nodes.get_mut(cell as usize) {
                    *node = AStarNode::EMPTY;
                }
            }
            for pos in 0..self.len {
                let cell = (self.open[pos].cell_dir >> 3) as usize;
                if let Some(node) = self.nodes.get_mut(cell) {
                    *node = AStarNode::EMPTY;
                }
            }
            return;
        }
        for y in y0..=y1 {
            let row = y * self.width;
            if let Some(cells) = self.nodes.get_mut(row + x0..=row + x1) {
                cells.fill(AStarNode::EMPTY);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};
    use crate::path::{Path, length, validate};

    type G = Grid<{ words_for(16, 16) }>;

    fn run(
        rows: &[u8],
        s: (u16, u16),
        t: (u16, u16),
    ) -> Result<(SearchStats, Path<256>), PlanError> {
        let g = G::parse_rows(rows).unwrap();
        let mut nodes = [AStarNode::EMPTY; 256];
        let mut open = [OpenSlot::EMPTY; 256];
        let mut out = Path::new();
        plan(
            g.view(),
            Cell::new(s.0, s.1),
            Cell::new(t.0, t.1),
            &mut nodes,
            &mut open,
            &mut out,
        )
        .map(|st| (st, out))
    }

    #[test]
    fn straight_and_diagonal() {
        let (st, p) = run(b".....\n.....\n.....\n", (0, 0), (4, 2)).unwrap();
        assert!((st.length - (2.0 + 2.0 * core::f32::consts::SQRT_2)).abs() < 1e-6);
        assert_eq!(p.len(), 5);
        assert_eq!(length(&p), st.length);
    }

    #[test]
    fn start_equals_goal() {
        let (st, p) = run(b"..\n..\n", (1, 1), (1, 1)).unwrap();
        assert_eq!((st.length, p.len()), (0.0, 1));
    }

    #[test]
    fn every_error_variant_from_bad_input() {
        let open = b"...\n.@.\n...\n";
        assert_eq!(
            run(open, (3, 0), (0, 0)).unwrap_err(),
            PlanError::StartOutsideMap
        );
        assert_eq!(
            run(open, (0, 0), (0, 3)).unwrap_err(),
            PlanError::GoalOutsideMap
        );
        assert_eq!(
            run(open, (1, 1), (0, 0)).unwrap_err(),
            PlanError::StartOccupied
        );
        assert_eq!(
            run(open, (0, 0), (1, 1)).unwrap_err(),
            PlanError::GoalOccupied
        );
        assert_eq!(
            run(b".@.\n.@.\n.@.\n", (0, 0), (2, 2)).unwrap_err(),
            PlanError::NoValidPath
        );
        // Diagonal gap: blocked because corner cutting is forbidden.
        assert_eq!(
            run(b".@\n@.\n", (0, 0), (1, 1)).unwrap_err(),
            PlanError::NoValidPath
        );
        let g = G::parse_rows(open).unwrap();
        let mut small = [AStarNode::EMPTY; 4];
        let mut open = [OpenSlot::EMPTY; 9];
        let mut out: Path<16> = Path::new();
        assert_eq!(
            plan(
                g.view(),
                Cell::new(0, 0),
                Cell::new(2, 2),
                &mut small,
                &mut open,
                &mut out
            ),
            Err(PlanError::CapacityExceeded)
        );
        let mut nodes = [AStarNode::EMPTY; 9];
        let mut tiny: Path<2> = Path::new();
        assert_eq!(
            plan(
                g.view(),
                Cell::new(0, 0),
                Cell::new(2, 2),
                &mut nodes,
                &mut open,
                &mut tiny
            ),
            Err(PlanError::CapacityExceeded)
        );
    }

    #[test]
    fn path_is_valid_and_hugs_no_corner() {
        let rows = b"......\n.@@@@.\n.@....\n.@.@@@\n...@..\n";
        let g = G::parse_rows(rows).unwrap();
        let mut nodes = [AStarNode::EMPTY; 256];
        let mut open = [OpenSlot::EMPTY; 256];
        let mut out: Path<64> = Path::new();
        let (s, t) = (Cell::new(2, 2), Cell::new(0, 4));
        let st = plan(g.view(), s, t, &mut nodes, &mut open, &mut out).unwrap();
        assert_eq!(validate(g.view(), &out, s, t), Ok(()));
        assert!((length(&out) - st.length).abs() < 1e-5);
    }

    /// A caller-chosen open list that is too small is an error, leaves the nodes reset,
    /// and the exact capacity found by `open_peak` suffices.
    #[test]
    fn small_open_list_is_an_error_and_peak_suffices() {
        let rows = b"..........\n.@@@@@@@@.\n..........\n.@@@@@@@@.\n..........\n";
        let g = G::parse_rows(rows).unwrap();
        let (s, t) = (Cell::new(0, 2), Cell::new(9, 2));
        let mut nodes = [AStarNode::EMPTY; 256];
        let mut open = [OpenSlot::EMPTY; 256];
        let mut out: Path<64> = Path::new();
        let full = plan(g.view(), s, t, &mut nodes, &mut open, &mut out).unwrap();
        let peak = full.open_peak as usize;
        assert!(peak > 2);
        assert_eq!(
            plan(g.view(), s, t, &mut nodes, &mut open[..peak - 1], &mut out),
            Err(PlanError::CapacityExceeded)
        );
        assert!(nodes.iter().all(|n| *n == AStarNode::EMPTY));
        assert_eq!(
            plan(g.view(), s, t, &mut nodes, &mut open[..peak], &mut out),
            Ok(full)
        );
        assert_eq!(
            plan(g.view(), s, t, &mut nodes, &mut [], &mut out),
            Err(PlanError::CapacityExceeded)
        );
        // Every exit leaves the nodes reset: found at once, path too long, unreachable.
        let _ = plan(g.view(), s, s, &mut nodes, &mut open, &mut out);
        assert!(nodes.iter().all(|n| *n == AStarNode::EMPTY));
        let mut short: Path<2> = Path::new();
        let _ = plan(g.view(), s, t, &mut nodes, &mut open, &mut short);
        assert!(nodes.iter().all(|n| *n == AStarNode::EMPTY));
        let walled = G::parse_rows(b"..@..\n..@..\n").unwrap();
        let r = plan(
            walled.view(),
            Cell::new(0, 0),
            Cell::new(4, 1),
            &mut nodes,
            &mut open,
            &mut out,
        );
        assert_eq!(r, Err(PlanError::NoValidPath));
        assert!(nodes.iter().all(|n| *n == AStarNode::EMPTY));
    }

    /// The diagonal of an open map: the record of closed cells resets exactly the touched
    /// cells (the box is the whole map); with an open list too short for the record, the
    /// box does; either way the nodes end reset and the paths agree.
    #[test]
    fn touched_cells_reset_with_and_without_the_record() {
        const W: usize = 64;
        let g: Grid<{ words_for(W, W) }> = Grid::new(W, W).unwrap();
        let (s, t) = (Cell::new(0, 0), Cell::new(W as u16 - 1, W as u16 - 1));
        let mut nodes = [AStarNode::EMPTY; W * W];
        let mut out: Path<128> = Path::new();
        let mut open = [OpenSlot::EMPTY; W * W];
        let full = plan(g.view(), s, t, &mut nodes, &mut open, &mut out).unwrap();
        assert_eq!(full.expanded as usize, W);
        assert!(nodes.iter().all(|n| *n == AStarNode::EMPTY));
        // Room for the heap, not for the record of 64 closed cells beside it.
        let slots = full.open_peak as usize + 1;
        let short = plan(g.view(), s, t, &mut nodes, &mut open[..slots], &mut out).unwrap();
        assert!(nodes.iter().all(|n| *n == AStarNode::EMPTY));
        assert_eq!(short, full);
    }
}

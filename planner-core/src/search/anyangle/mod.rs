//! Exact any-angle shortest paths (`anyangle`): Polyanya's interval search on the grid's
//! free space cut into rectangles, with no preprocessing beyond that cut (linear in the
//! map, done once per map) and memory linear in the number of cells.
//!
//! The length found is the infimum of the lengths of valid paths under the collision rule
//! (a path may not touch a blocked cell, corners included, and cannot pass between two
//! blocked cells that meet at a corner): the taut path around obstacle corners. The
//! returned path moves each corner it wraps a small margin off (see [`margin`]: `2.5e-4`
//! cells on maps up to 1024 cells a side, `2e-3` at 4096), so it is valid, and longer than
//! the infimum by about twice the margin per right-angle turn. An unreachable goal is
//! reported exactly ([`PlanError::NoValidPath`] once the search has run out of nodes).
//!
//! # Memory (caller-owned, `no_std`, no allocator)
//!
//! - per map, [`Mesh::build`]: 24-byte [`Rect`]s and 8-byte [`Link`]s. A map of `c` cells and
//!   `h` rows needs at most [`rects_for`]`= c / 2 + h` rectangles and [`links_for`]`= c + 2h`
//!   links (a checkerboard); warehouses need far fewer (a 340 x 164 Moving AI warehouse:
//!   see the tests), and too little room is [`PlanError::CapacityExceeded`].
//! - per query: one 32-byte [`Roots`] per rectangle and an open list of 40-byte [`Node`]s
//!   whose length the caller chooses (a search that outgrows it is
//!   [`PlanError::CapacityExceeded`]).
//!
//! So at worst 12 bytes a cell for the map and 16 for a query, plus the open list.
//!
//! ```
//! use planner_core::{geometry::Cell, grid::{words_for, Grid}, path::Path};
//! use planner_core::search::anyangle::{self, Link, Mesh, Node, Rect, Roots, Scratch};
//!
//! let grid: Grid<{ words_for(5, 3) }> = Grid::parse_rows(b".....\n..@..\n.....\n")?;
//! let (mut rects, mut links) = ([Rect::EMPTY; 16], [Link::EMPTY; 32]);
//! let mesh = Mesh::build(grid.view(), &mut rects, &mut links)?;
//! let (mut roots, mut open) = ([Roots::EMPTY; 16], [Node::EMPTY; 64]);
//! let mut path: Path<16> = Path::new();
//! let scratch = Scratch { roots: &mut roots, open: &mut open };
//! let stats = anyangle::plan(grid.view(), &mesh, Cell::new(0, 1), Cell::new(4, 1), scratch, &mut path)?;
//! // Over the blocked cell's two top corners.
//! assert!((stats.optimum - (1.0 + 2.0 * 2.5f32.sqrt())).abs() < 1e-5);
//! assert_eq!(path.len(), 4);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod mesh;
mod search;
mod witness;

#[cfg(feature = "alloc")]
pub use mesh::MeshBuf;
pub use mesh::{Link, Mesh, Rect};
pub use search::{Node, Roots};

use crate::error::PlanError;
use crate::geometry::{Cell, Point};
use crate::grid::GridRef;
use crate::path::{self, PathView};
pub use search::MAX_SIDE;
use search::{START, Search};

/// Rectangles a map of `width x height` cells can need at most.
pub const fn rects_for(width: usize, height: usize) -> usize {
    width * height / 2 + height
}

/// Links a map of `width x height` cells can need at most.
pub const fn links_for(width: usize, height: usize) -> usize {
    width * height + 2 * height
}

/// The margin (cells, per axis) by which returned paths keep off the corners they wrap on
/// `grid`: 8 units in the last place of its longest side, at least `2.5 TOUCH_EPS`.
pub fn margin(grid: GridRef<'_>) -> f32 {
    witness::margin(grid)
}

/// A query's scratch: one [`Roots`] per rectangle of the mesh, and the open list.
pub struct Scratch<'a> {
    /// At least [`Mesh::rects`] entries.
    pub roots: &'a mut [Roots],
    /// The open list; its length is the most nodes open at once.
    pub open: &'a mut [Node],
}

/// What [`plan`] reports besides the path.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct AnyAngleStats {
    /// Length of the returned path (cells).
    pub length: f32,
    /// The length of the corner path the returned path approaches: the infimum of valid
    /// lengths when `exact`.
    pub optimum: f32,
    /// Whether the path is proven shortest. It is, unless a full open list dropped nodes
    /// that a shorter path could have gone through (then it is a valid path of the same
    /// kind, and a longer open list gives the shortest).
    pub exact: bool,
    /// Search nodes expanded.
    pub expanded: u32,
    /// Search nodes pushed.
    pub pushed: u32,
    /// Most nodes open at once.
    pub open_peak: u32,
}

/// Owned storage for the mesh of one map of up to `RECTS` rectangles and `LINKS` links (a
/// firmware `static`; all zero bytes until built).
pub struct MeshStorage<const RECTS: usize, const LINKS: usize> {
    rects: [Rect; RECTS],
    links: [Link; LINKS],
    /// Rectangles and links of the mesh built last, and its map's size.
    built: (usize, usize, usize, usize),
}

impl<const RECTS: usize, const LINKS: usize> MeshStorage<RECTS, LINKS> {
    /// Empty storage.
    pub const fn new() -> Self {
        MeshStorage {
            rects: [Rect::EMPTY; RECTS],
            links: [Link::EMPTY; LINKS],
            built: (0, 0, 0, 0),
        }
    }

    /// Builds the mesh of `grid` here (replacing the previous one).
    pub fn build(&mut self, grid: GridRef<'_>) -> Result<Mesh<'_>, PlanError> {
        self.built = (0, 0, 0, 0);
        let mesh = Mesh::build(grid, &mut self.rects, &mut self.links)?;
        self.built = (mesh.rects(), mesh.links(), grid.width(), grid.height());
        Ok(mesh)
    }

    /// The mesh built last (empty before any).
    pub fn mesh(&self) -> Mesh<'_> {
        let (r, l, w, h) = self.built;
        Mesh::from_parts(&self.rects[..r], &self.links[..l], w, h)
    }
}

impl<const RECTS: usize, const LINKS: usize> Default for MeshStorage<RECTS, LINKS> {
    fn default() -> Self {
        Self::new()
    }
}

/// Owned storage for queries on meshes of up to `RECTS` rectangles with `OPEN` open nodes.
pub struct QueryStorage<const RECTS: usize, const OPEN: usize> {
    /// The roots.
    pub roots: [Roots; RECTS],
    /// The open list.
    pub open: [Node; OPEN],
}

impl<const RECTS: usize, const OPEN: usize> QueryStorage<RECTS, OPEN> {
    /// Empty storage.
    pub const fn new() -> Self {
        QueryStorage {
            roots: [Roots::EMPTY; RECTS],
            open: [Node::EMPTY; OPEN],
        }
    }

    /// The scratch view [`plan`] takes.
    pub fn scratch(&mut self) -> Scratch<'_> {
        Scratch {
            roots: &mut self.roots,
            open: &mut self.open,
        }
    }
}

impl<const RECTS: usize, const OPEN: usize> Default for QueryStorage<RECTS, OPEN> {
    fn default() -> Self {
        Self::new()
    }
}

/// The shortest valid path from the centre of `start` to the centre of `goal` on `grid`
/// (the grid `mesh` was built from), written to `out`.
///
/// Errors: the endpoint checks of [`check_endpoints`](crate::search::check_endpoints),
/// [`PlanError::NoValidPath`] when the goal is unreachable, [`PlanError::CapacityExceeded`]
/// when a side exceeds [`MAX_SIDE`], when `out` or the roots are too short, or when the open list had to drop the only way to
/// the goal, [`PlanError::InvalidParameters`] when `mesh`
/// was built from a grid of another size.
pub fn plan(
    grid: GridRef<'_>,
    mesh: &Mesh<'_>,
    start: Cell,
    goal: Cell,
    scratch: Scratch<'_>,
    out: &mut PathView,
) -> Result<AnyAngleStats, PlanError> {
    plan_within(grid, mesh, start, goal, scratch, out, u32::MAX)
}

/// [`plan`] that gives up with [`PlanError::BudgetExhausted`] after expanding
/// `max_expanded` nodes.
///
/// The search's work grows with the number of rectangles (about as its power 1.5 on
/// lattices of racks, where many taut routes nearly tie), not with the cells: on realistic
/// layouts it takes a small fraction of A*'s time, but a lattice of two-cell racks and
/// aisles 2048 cells a side has 130,000 rectangles, and there A*, whose work grows with the
/// cells, is faster. Callers that only need a route in the shortest path's class (the
/// corridor's guide) bound it and fall back.
pub fn plan_within(
    grid: GridRef<'_>,
    mesh: &Mesh<'_>,
    start: Cell,
    goal: Cell,
    scratch: Scratch<'_>,
    out: &mut PathView,
    max_expanded: u32,
) -> Result<AnyAngleStats, PlanError> {
    super::check_endpoints(grid, start, goal)?;
    if mesh.size() != (grid.width(), grid.height()) {
        return Err(PlanError::InvalidParameters);
    }
    if grid.width().max(grid.height()) > MAX_SIDE {
        return Err(PlanError::CapacityExceeded);
    }
    let at = |c: Cell| (2 * c.x as i32 + 1, 2 * c.y as i32 + 1);
    let locate = |c: Cell| mesh.locate(grid, c.x as usize, c.y as usize);
    let (Some(start_rect), Some(goal_rect)) = (locate(start), locate(goal)) else {
        return Err(PlanError::InvalidParameters);
    };
    let mut search = Search::new(
        grid,
        *mesh,
        scratch.roots,
        scratch.open,
        at(start),
        at(goal),
        goal_rect,
    )?;
    let (last, cost) = search
        .run(start_rect, max_expanded)?
        .ok_or(PlanError::NoValidPath)?;
    // The corners, goal first, then reversed (doubled coordinates until the witness).
    out.clear();
    let push = |out: &mut PathView, p: (i32, i32)| {
        out.push(Point::new(p.0 as f32, p.1 as f32))
            .map_err(|_| PlanError::CapacityExceeded)
    };
    push(out, at(goal))?;
    let mut key = last;
    let mut optimum = 0.0f32;
    let mut prev = at(goal);
    // Parents always cost less than their children, so the chain ends; the bound guards
    // against a broken table all the same.
    for _ in 0..=4 * mesh.rects() {
        let p = search.point(key);
        if p != prev {
            optimum += search::dist(prev, p);
            push(out, p)?;
            prev = p;
        }
        if key == START {
            break;
        }
        key = search.parent(key);
    }
    if prev != at(start) {
        return Err(PlanError::NoValidPath);
    }
    out.reverse();
    let counts = search.counts;
    let mut eps = witness::margin(grid);
    // A larger margin is tried if corners keep failing the check (never seen; a failed
    // attempt leaves every waypoint within the margin of its lattice point, so rounding
    // gives the corners back, with the ones it inserted).
    for attempt in 0.. {
        match witness::witness(grid, out, eps) {
            Ok(()) => break,
            Err(PlanError::NoValidPath) if attempt < 3 => {
                for p in out.iter_mut() {
                    *p = Point::new(libm::roundf(2.0 * p.x + 1.0), libm::roundf(2.0 * p.y + 1.0));
                }
                eps *= 2.0;
            }
            Err(e) => return Err(e),
        }
    }
    Ok(AnyAngleStats {
        length: path::length(out),
        optimum: optimum / 2.0,
        exact: cost <= counts.dropped,
        expanded: counts.expanded,
        pushed: counts.pushed,
        open_peak: counts.open_peak,
    })
}

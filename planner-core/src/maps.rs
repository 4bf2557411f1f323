//! The papers' maps, generated deterministically (the papers print theirs only as figures;
//! the keys are those of `docs/references.md`). Behind the `maps` feature (on by default).
//!
//! - The TCLHHO warehouse paper (`Lei2024Warehouse`), [`lei2024_warehouse`]: `size x size` maps for `size` in 10, 30, 40, start at the top-left cell and goal
//!   at the bottom-right cell, in two kinds: [`MapKind::Sparse`] ("discrete": scattered small
//!   obstacles) and [`MapKind::Warehouse`] (regular shelf rows with aisles and cross-aisles).
//! - The IGWO grid paper (`Liu2020Igwo`), [`lab_20x20`]: a 20 x 20 lab with start cell 1 = `(0, 0)` and goal cell
//!   400 = `(19, 19)`.
//!
//! Every generated map is checked to admit an x-monotone path under the collision rule (the
//! column encoding of `Lei2024Warehouse` can only represent those), so all planners can be compared.

use crate::geometry::{Cell, line_of_sight};
use crate::grid::{Grid, GridRef};
use rand_core::{Rng, SeedableRng};
use rand_xoshiro::Xoshiro128PlusPlus;

/// The two map kinds of the TCLHHO warehouse paper (`Lei2024Warehouse`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum MapKind {
    /// Scattered small obstacles ("discrete" maps, table 2).
    Sparse,
    /// Regular shelf blocks ("warehouse" maps, table 3).
    Warehouse,
}

impl MapKind {
    /// `sparse` or `warehouse`.
    pub const fn name(self) -> &'static str {
        match self {
            MapKind::Sparse => "sparse",
            MapKind::Warehouse => "warehouse",
        }
    }
}

/// A generated map with its start and goal.
#[derive(Clone, Debug)]
pub struct PaperMap<const WORDS: usize> {
    /// The grid.
    pub grid: Grid<WORDS>,
    /// Start cell (top-left).
    pub start: Cell,
    /// Goal cell (bottom-right).
    pub goal: Cell,
}

/// Why a map could not be generated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub enum MapGenError {
    /// The size is below 6 or the grid capacity is too small.
    BadSize,
}

/// `Lei2024Warehouse`'s maps: `size x size` (10, 30 and 40 in the paper; any size from 6 works).
///
/// ```
/// use planner_core::{grid::words_for, maps::{lei2024_warehouse, MapKind}};
///
/// let map = lei2024_warehouse::<{ words_for(40, 40) }>(MapKind::Warehouse, 40)?;
/// assert_eq!((map.start.x, map.start.y, map.goal.x, map.goal.y), (0, 0, 39, 39));
/// # Ok::<(), planner_core::maps::MapGenError>(())
/// ```
pub fn lei2024_warehouse<const WORDS: usize>(
    kind: MapKind,
    size: usize,
) -> Result<PaperMap<WORDS>, MapGenError> {
    if size < 6 {
        return Err(MapGenError::BadSize);
    }
    let start = Cell::new(0, 0);
    let goal = Cell::new(size as u16 - 1, size as u16 - 1);
    let grid = match kind {
        MapKind::Warehouse => warehouse_shelves(size)?,
        MapKind::Sparse => {
            // Fixed seeds per size; try successive seeds until the map admits an x-monotone
            // path, so the result is deterministic and usable by every encoding.
            let mut found = None;
            for attempt in 0..64u64 {
                let g = sparse(size, 0x5EED_0000 + size as u64 * 1000 + attempt)?;
                if x_monotone_feasible(g.view(), start, goal) {
                    found = Some(g);
                    break;
                }
            }
            found.ok_or(MapGenError::BadSize)?
        }
    };
    Ok(PaperMap { grid, start, goal })
}

/// `Liu2020Igwo`'s 20 x 20 lab: furniture blocks and a U-shaped bench facing the start (a local
/// optimum for paths that head straight for the goal); start `(0, 0)`, goal `(19, 19)`.
pub fn lab_20x20<const WORDS: usize>() -> Result<PaperMap<WORDS>, MapGenError> {
    // A U-shaped bench opens towards the start: greedy diagonal paths run into it.
    const ROWS: [&[u8; 20]; 20] = [
        b"....................",
        b"........@@..........",
        b"..@@@...@@......@@..",
        b"..@@@...@@......@@..",
        b"................@@..",
        b".............@@.....",
        b".............@@.....",
        b".@@...@@@@...@@.....",
        b".@@...@@@@...@@.....",
        b".@@..........@@.@@@.",
        b".@@..@@......@@.@@@.",
        b".....@@......@@.....",
        b".............@@.....",
        b".....@@@@@@@@@@.....",
        b".....@@@@@@@@@@.....",
        b".................@..",
        b"..@@.......@@....@..",
        b"..@@...@@@@@@....@..",
        b"..@@.......@@....@..",
        b"...........@@.......",
    ];
    let mut grid = Grid::new(20, 20).map_err(|_| MapGenError::BadSize)?;
    for (y, row) in ROWS.iter().enumerate() {
        for (x, &c) in row.iter().enumerate() {
            grid.set_blocked(x, y, c == b'@')
                .map_err(|_| MapGenError::BadSize)?;
        }
    }
    Ok(PaperMap {
        grid,
        start: Cell::new(0, 0),
        goal: Cell::new(19, 19),
    })
}

/// Shelf blocks two cells wide, separated by one-cell aisles, broken by cross-aisles; the
/// first and last two rows and columns stay free (docking areas at start and goal).
fn warehouse_shelves<const WORDS: usize>(size: usize) -> Result<Grid<WORDS>, MapGenError> {
    let mut grid = Grid::new(size, size).map_err(|_| MapGenError::BadSize)?;
    // Shelf length grows with the map so the 10x10 map keeps a single block row.
    let shelf_len = if size <= 12 { 3 } else { 6 };
    let margin = 2;
    for y in margin..size - margin {
        // Cross-aisle every shelf_len + 2 rows (two free rows).
        let in_block = (y - margin) % (shelf_len + 2) < shelf_len;
        if !in_block {
            continue;
        }
        for x in margin..size - margin {
            // Pattern: shelf, shelf, aisle, aisle.
            if (x - margin) % 4 < 2 {
                grid.set_blocked(x, y, true)
                    .map_err(|_| MapGenError::BadSize)?;
            }
        }
    }
    Ok(grid)
}

/// Scattered obstacles of 1 x 1 to 2 x 2 cells covering about 10% of the map, none in the
/// first or last column.
fn sparse<const WORDS: usize>(size: usize, seed: u64) -> Result<Grid<WORDS>, MapGenError> {
    let mut grid = Grid::new(size, size).map_err(|_| MapGenError::BadSize)?;
    let mut rng = Xoshiro128PlusPlus::seed_from_u64(seed);
    let target = size * size / 10;
    let mut placed = 0;
    let mut tries = 0;
    while placed < target && tries < size * size * 4 {
        tries += 1;
        let w = 1 + (rng.next_u32() % 2) as usize;
        let h = 1 + (rng.next_u32() % 2) as usize;
        let x = (rng.next_u32() as usize) % size;
        let y = (rng.next_u32() as usize) % size;
        // Keep the start and goal columns free: `Lei2024Warehouse`'s column encoding moves vertically
        // only there, so an obstacle in them would leave nothing for the optimizers to do.
        if x == 0 || x + w >= size {
            continue;
        }
        for yy in y..(y + h).min(size) {
            for xx in x..(x + w).min(size) {
                if !grid.view().is_blocked(xx as isize, yy as isize) {
                    placed += 1;
                }
                grid.set_blocked(xx, yy, true)
                    .map_err(|_| MapGenError::BadSize)?;
            }
        }
    }
    Ok(grid)
}

/// Whether a path start -> (start column, r0) -> (next column, r1) -> ... -> goal exists
/// (the shape `Lei2024Warehouse`'s column encoding represents), by dynamic programming over columns.
pub fn x_monotone_feasible(grid: GridRef<'_>, start: Cell, goal: Cell) -> bool {
    let h = grid.height();
    if start.x > goal.x || h > 256 {
        return false;
    }
    let mut reach = [false; 256];
    for (r, slot) in reach.iter_mut().enumerate().take(h) {
        *slot = line_of_sight(grid, start, Cell::new(start.x, r as u16));
    }
    for x in start.x + 1..=goal.x {
        let mut next = [false; 256];
        for (r, slot) in next.iter_mut().enumerate().take(h) {
            *slot = (0..h).any(|p| {
                reach[p] && line_of_sight(grid, Cell::new(x - 1, p as u16), Cell::new(x, r as u16))
            });
        }
        reach = next;
    }
    (0..h).any(|r| reach[r] && line_of_sight(grid, Cell::new(goal.x, r as u16), goal))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::words_for;
    use crate::search::astar::{self, AStarNode, OpenSlot};

    type G = Grid<{ words_for(40, 40) }>;

    #[test]
    fn all_seed_maps_are_deterministic_and_solvable() {
        for kind in [MapKind::Sparse, MapKind::Warehouse] {
            for size in [10, 30, 40] {
                let a = lei2024_warehouse::<{ words_for(40, 40) }>(kind, size).unwrap();
                let b = lei2024_warehouse::<{ words_for(40, 40) }>(kind, size).unwrap();
                assert_eq!(a.grid, b.grid);
                assert!(
                    x_monotone_feasible(a.grid.view(), a.start, a.goal),
                    "{kind:?} {size}"
                );
                let mut nodes = [AStarNode::EMPTY; 1600];
                let mut open = [OpenSlot::EMPTY; 1600];
                let mut path: crate::path::Path<400> = crate::path::Path::new();
                astar::plan(
                    a.grid.view(),
                    a.start,
                    a.goal,
                    &mut nodes,
                    &mut open,
                    &mut path,
                )
                .unwrap();
                let blocked = a.grid.view().blocked_count() as f32 / (size * size) as f32;
                assert!(blocked > 0.05 && blocked < 0.5, "{kind:?} {size} {blocked}");
            }
        }
    }

    #[test]
    fn lab_map_is_solvable() {
        let lab = lab_20x20::<{ words_for(20, 20) }>().unwrap();
        let mut nodes = [AStarNode::EMPTY; 400];
        let mut open = [OpenSlot::EMPTY; 400];
        let mut path: crate::path::Path<400> = crate::path::Path::new();
        astar::plan(
            lab.grid.view(),
            lab.start,
            lab.goal,
            &mut nodes,
            &mut open,
            &mut path,
        )
        .unwrap();
    }

    #[test]
    fn bad_sizes_are_errors() {
        assert_eq!(
            lei2024_warehouse::<{ words_for(40, 40) }>(MapKind::Sparse, 5).unwrap_err(),
            MapGenError::BadSize
        );
        assert!(lei2024_warehouse::<{ words_for(8, 8) }>(MapKind::Warehouse, 40).is_err());
        let _ = G::new(1, 1);
    }
}

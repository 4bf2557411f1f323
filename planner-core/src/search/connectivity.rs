//! Connected components of the free space, so that an unreachable goal is reported exactly
//! and at once instead of by exhausting a search or an optimizer's budget.
//!
//! Under the collision rule a diagonal step needs both side cells free, so two diagonal
//! neighbours are also joined through a side cell: reachability by 8-connected moves, and
//! by any valid any-angle segment, is exactly 4-connectivity of the free cells. That makes
//! a single-array union-find (two raster passes, no queue) sufficient.

use super::check_endpoints;
use crate::error::PlanError;
use crate::geometry::Cell;
use crate::grid::GridRef;

/// Label of a blocked cell.
pub const BLOCKED: u32 = u32::MAX;

/// Writes a component label per cell into `labels` (one entry per cell; blocked cells get
/// [`BLOCKED`]) and returns the number of components. The label of a free cell is the
/// row-major index of its component's first cell.
pub fn label(grid: GridRef<'_>, labels: &mut [u32]) -> Result<u32, PlanError> {
    let cells = grid.cells();
    if labels.len() < cells || cells > BLOCKED as usize {
        return Err(PlanError::CapacityExceeded);
    }
    let width = grid.width();
    for i in 0..cells {
        let (x, y) = ((i % width) as isize, (i / width) as isize);
        if grid.is_blocked(x, y) {
            labels[i] = BLOCKED;
            continue;
        }
        labels[i] = i as u32;
        if !grid.is_blocked(x - 1, y) {
            union(labels, i - 1, i);
        }
        if !grid.is_blocked(x, y - 1) {
            union(labels, i - width, i);
        }
    }
    // Links always point to a smaller index, so one ascending pass flattens every chain.
    let mut components = 0;
    for i in 0..cells {
        let parent = labels[i];
        if parent == BLOCKED {
            continue;
        }
        if parent as usize == i {
            components += 1;
        } else {
            labels[i] = labels[parent as usize];
        }
    }
    Ok(components)
}

/// Whether `a` and `b` are in the same component, after the endpoint checks.
pub fn connected(grid: GridRef<'_>, labels: &[u32], a: Cell, b: Cell) -> Result<bool, PlanError> {
    check_endpoints(grid, a, b)?;
    let (Some(ia), Some(ib)) = (grid.index(a), grid.index(b)) else {
        return Err(PlanError::StartOutsideMap);
    };
    match (labels.get(ia), labels.get(ib)) {
        (Some(la), Some(lb)) => Ok(la == lb && *la != BLOCKED),
        _ => Err(PlanError::CapacityExceeded),
    }
}

fn find(labels: &mut [u32], mut x: usize) -> usize {
    while labels[x] as usize != x {
        let grand = labels[labels[x] as usize];
        labels[x] = grand;
        x = grand as usize;
    }
    x
}

fn union(labels: &mut [u32], a: usize, b: usize) {
    let (ra, rb) = (find(labels, a), find(labels, b));
    if ra != rb {
        let (lo, hi) = if ra < rb { (ra, rb) } else { (rb, ra) };
        labels[hi] = lo as u32;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};

    type G = Grid<{ words_for(8, 8) }>;

    #[test]
    fn counts_components_and_ignores_diagonal_gaps() {
        // A U-shaped component whose arms merge late (tests union of two roots) and an
        // isolated cell reachable only through a diagonal gap (which is not a passage).
        let g = G::parse_rows(b".@.@\n.@.@\n...@\n@@@.\n").unwrap();
        let mut labels = [0u32; 16];
        assert_eq!(label(g.view(), &mut labels).unwrap(), 2);
        assert!(connected(g.view(), &labels, Cell::new(0, 0), Cell::new(2, 0)).unwrap());
        assert!(!connected(g.view(), &labels, Cell::new(0, 0), Cell::new(3, 3)).unwrap());
        assert_eq!(labels[1], BLOCKED);
    }

    #[test]
    fn errors() {
        let g = G::parse_rows(b"..\n.@\n").unwrap();
        let mut short = [0u32; 3];
        assert_eq!(
            label(g.view(), &mut short),
            Err(PlanError::CapacityExceeded)
        );
        let mut labels = [0u32; 4];
        label(g.view(), &mut labels).unwrap();
        assert_eq!(
            connected(g.view(), &labels, Cell::new(0, 0), Cell::new(1, 1)),
            Err(PlanError::GoalOccupied)
        );
        assert_eq!(
            connected(g.view(), &labels, Cell::new(2, 0), Cell::new(0, 0)),
            Err(PlanError::StartOutsideMap)
        );
    }
}

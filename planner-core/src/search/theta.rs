//! Theta*: A* whose nodes may take their grandparent as parent when it is in line of sight,
//! giving any-angle paths (Nash, Daniel, Koenig & Felner 2007).
//!
//! Line of sight is the exact collision rule ([`line_of_sight`]). The result is never longer
//! than A*'s: every relaxation offers at most the grid step's cost (triangle inequality), so
//! the first time the goal is closed its cost is at most the octile optimum.

use super::{Query, SearchNode, SearchStats, best_first, euclid_xy};
use crate::error::PlanError;
use crate::geometry::{Cell, line_of_sight};
use crate::grid::GridRef;
use crate::path::PathView;

/// Plans an any-angle path from `start` to `goal` into `out` (its turning points, start
/// first). Storage and errors as for [`astar::plan`](super::astar::plan).
pub fn plan(
    grid: GridRef<'_>,
    start: Cell,
    goal: Cell,
    nodes: &mut [SearchNode],
    out: &mut PathView,
) -> Result<SearchStats, PlanError> {
    plan_with_labels(grid, start, goal, None, nodes, out)
}

/// Like [`plan`], consulting component labels first.
pub fn plan_with_labels(
    grid: GridRef<'_>,
    start: Cell,
    goal: Cell,
    labels: Option<&[u32]>,
    nodes: &mut [SearchNode],
    out: &mut PathView,
) -> Result<SearchStats, PlanError> {
    let width = grid.width() as isize;
    let query = Query {
        grid,
        start,
        goal,
        labels,
    };
    best_first(query, nodes, out, euclid_xy, |open, s| {
        // Path 1: straight from the expanded cell's parent, if it sees the neighbour.
        let parent = open.node(s.i).parent as usize;
        if parent != s.i && line_of_sight(grid, grid.cell(parent), grid.cell(s.j)) {
            let (px, py) = ((parent as isize) % width, (parent as isize) / width);
            open.relax(
                s.j,
                open.g(parent) + euclid_xy(px, py, s.nx, s.ny),
                s.h,
                parent,
            );
        } else {
            open.relax(s.j, open.g(s.i) + s.cost, s.h, s.i);
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};
    use crate::path::{Path, length, validate};
    use crate::search::astar;

    type G = Grid<{ words_for(16, 16) }>;

    #[test]
    fn open_floor_is_a_straight_line() {
        let g = G::new(10, 6).unwrap();
        let mut nodes = [SearchNode::EMPTY; 256];
        let mut out: Path<32> = Path::new();
        let st = plan(
            g.view(),
            Cell::new(0, 0),
            Cell::new(9, 4),
            &mut nodes,
            &mut out,
        )
        .unwrap();
        assert_eq!(out.len(), 2);
        assert!((st.length - (81.0f32 + 16.0).sqrt()).abs() < 1e-4);
    }

    #[test]
    fn around_a_wall_not_longer_than_astar() {
        let g =
            G::parse_rows(b"..........\n....@@....\n....@@....\n....@@....\n..........\n").unwrap();
        let (s, t) = (Cell::new(0, 2), Cell::new(9, 2));
        let mut nodes = [SearchNode::EMPTY; 256];
        let mut out: Path<32> = Path::new();
        let st = plan(g.view(), s, t, &mut nodes, &mut out).unwrap();
        assert_eq!(validate(g.view(), &out, s, t), Ok(()));
        assert!((length(&out) - st.length).abs() < 1e-4);
        let mut grid_path: Path<64> = Path::new();
        let mut astar_nodes = [astar::AStarNode::EMPTY; 256];
        let mut open = [astar::OpenSlot::EMPTY; 256];
        let a = astar::plan(g.view(), s, t, &mut astar_nodes, &mut open, &mut grid_path).unwrap();
        assert!(st.length <= a.length + 1e-4);
        assert!(st.length < a.length); // any-angle is strictly shorter here
    }

    #[test]
    fn errors_match_astar() {
        let g = G::parse_rows(b".@\n@.\n").unwrap();
        let mut nodes = [SearchNode::EMPTY; 4];
        let mut out: Path<8> = Path::new();
        assert_eq!(
            plan(
                g.view(),
                Cell::new(0, 0),
                Cell::new(1, 1),
                &mut nodes,
                &mut out
            ),
            Err(PlanError::NoValidPath)
        );
        assert_eq!(
            plan(
                g.view(),
                Cell::new(1, 0),
                Cell::new(1, 1),
                &mut nodes,
                &mut out
            ),
            Err(PlanError::StartOccupied)
        );
    }
}

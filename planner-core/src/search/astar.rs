//! A* on the 8-connected grid: octile costs (1 and sqrt 2), no corner cutting, octile
//! heuristic (consistent, so the first time the goal is taken off the open list its cost is
//! optimal). Ties on `f` prefer the larger `g`, which expands fewer cells on open floors.

use super::{SearchNode, SearchStats, best_first, octile_xy};
use crate::error::PlanError;
use crate::geometry::Cell;
use crate::grid::GridRef;
use crate::path::PathView;

/// Plans the shortest 8-connected path from `start` to `goal`, writing every cell centre
/// along it into `out` (start first).
///
/// `nodes` needs one entry per map cell. Errors: the endpoint checks of
/// [`check_endpoints`], [`PlanError::CapacityExceeded`] when `nodes`
/// or `out` is too small, [`PlanError::NoValidPath`] when the goal is unreachable.
pub fn plan(
    grid: GridRef<'_>,
    start: Cell,
    goal: Cell,
    nodes: &mut [SearchNode],
    out: &mut PathView,
) -> Result<SearchStats, PlanError> {
    plan_with_labels(grid, start, goal, None, nodes, out)
}

/// Like [`plan`], but first consults precomputed component labels (see
/// [`connectivity::label`]) so that an unreachable goal costs O(1) instead of a full search.
pub fn plan_with_labels(
    grid: GridRef<'_>,
    start: Cell,
    goal: Cell,
    labels: Option<&[u32]>,
    nodes: &mut [SearchNode],
    out: &mut PathView,
) -> Result<SearchStats, PlanError> {
    best_first(
        grid,
        start,
        goal,
        labels,
        nodes,
        out,
        octile_xy,
        |open, s| {
            open.relax(s.j, open.g(s.i) + s.cost, s.h, s.i);
        },
    )
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
        let mut nodes = [SearchNode::EMPTY; 256];
        let mut out = Path::new();
        plan(
            g.view(),
            Cell::new(s.0, s.1),
            Cell::new(t.0, t.1),
            &mut nodes,
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
        let mut small = [SearchNode::EMPTY; 4];
        let mut out: Path<16> = Path::new();
        assert_eq!(
            plan(
                g.view(),
                Cell::new(0, 0),
                Cell::new(2, 2),
                &mut small,
                &mut out
            ),
            Err(PlanError::CapacityExceeded)
        );
        let mut nodes = [SearchNode::EMPTY; 9];
        let mut tiny: Path<2> = Path::new();
        assert_eq!(
            plan(
                g.view(),
                Cell::new(0, 0),
                Cell::new(2, 2),
                &mut nodes,
                &mut tiny
            ),
            Err(PlanError::CapacityExceeded)
        );
    }

    #[test]
    fn path_is_valid_and_hugs_no_corner() {
        let rows = b"......\n.@@@@.\n.@....\n.@.@@@\n...@..\n";
        let g = G::parse_rows(rows).unwrap();
        let mut nodes = [SearchNode::EMPTY; 256];
        let mut out: Path<64> = Path::new();
        let (s, t) = (Cell::new(2, 2), Cell::new(0, 4));
        let st = plan(g.view(), s, t, &mut nodes, &mut out).unwrap();
        assert_eq!(validate(g.view(), &out, s, t), Ok(()));
        assert!((length(&out) - st.length).abs() < 1e-5);
    }
}

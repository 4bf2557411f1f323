//! Regression tests for bugs found while proving the core (one test per bug).

use planner_core::geometry::{Cell, Point, line_of_sight, segment_is_clear};
use planner_core::grid::{Grid, words_for};

type Big = Grid<{ words_for(4096, 4096) }>;

/// `segment_is_clear` used to evaluate cell-centre segments in `f32` too, and on big maps
/// its rounding (ulp 2.4e-4 near y = 3000) exceeded the `1/8192 - TOUCH_EPS` margin by
/// which such a segment can miss a cell: it rejected this segment, which misses cell
/// (3072, 3001) by 1/8192, while `line_of_sight` accepted it. Theta* (which uses the exact
/// check) would then return paths that `path::validate` rejects.
#[test]
fn segment_is_clear_agrees_with_line_of_sight_on_a_4096_map() {
    let mut g: Box<Big> = Box::new(Big::new(4096, 4096).unwrap());
    g.set_blocked(3072, 3001, true).unwrap();
    let (a, b) = (Cell::new(0, 3000), Cell::new(4095, 3002));
    assert!(line_of_sight(g.view(), a, b));
    assert!(segment_is_clear(g.view(), a.center(), b.center()));
    assert!(segment_is_clear(g.view(), b.center(), a.center()));
    // A real crossing on the same line stays a collision: at x = 2047.5 the line is at
    // y = 3001 exactly, inside row 3001 of column 2048...
    g.set_blocked(2048, 3001, true).unwrap();
    assert!(!line_of_sight(g.view(), a, b));
    assert!(!segment_is_clear(g.view(), a.center(), b.center()));
    // ...and fractional points still go through the conservative f32 path.
    assert!(!segment_is_clear(
        g.view(),
        Point::new(0.0, 3000.0),
        Point::new(4095.0, 3002.5)
    ));
}

/// `Point::cell` documents "ties go to the lower index" but computed `floor(v + 1/2)`,
/// which sends a point on the edge between two cells to the upper one, and rounds
/// 0.49999997 + 0.5 up to 1.0, sending a point strictly inside cell 0 to cell 1.
#[test]
fn point_cell_sends_ties_to_the_lower_index() {
    let g = Grid::<{ words_for(4, 4) }>::new(4, 4).unwrap();
    let v = g.view();
    assert_eq!(Point::new(0.5, 1.5).cell(v), Some(Cell::new(0, 1)));
    assert_eq!(Point::new(0.499_999_97, 0.0).cell(v), Some(Cell::new(0, 0)));
    assert_eq!(Point::new(0.500_000_06, 0.0).cell(v), Some(Cell::new(1, 0)));
    assert_eq!(Point::new(2.0, 3.0).cell(v), Some(Cell::new(2, 3)));
    assert_eq!(Point::new(3.5, 0.0).cell(v), Some(Cell::new(3, 0)));
    assert_eq!(Point::new(3.51, 0.0).cell(v), None);
    assert_eq!(Point::new(-0.4, 0.0).cell(v), Some(Cell::new(0, 0)));
    // The map's outer edge belongs to the outside (as in `segment_is_clear`).
    assert_eq!(Point::new(-0.5, 0.0).cell(v), None);
    assert_eq!(Point::new(f32::NAN, 0.0).cell(v), None);
}

//! Points, cells and the collision rule shared by every planner and every check.
//!
//! SPEC section 1: cell `(x, y)` is the closed unit square centred on `(x, y)`; a segment is
//! valid only if it touches no blocked cell at all, not even an edge or a corner, and leaving
//! the map counts as blocked. For one diagonal step between cell centres this is exactly
//! "no corner cutting": the segment passes through the shared corner, so both side cells
//! must be free.
//!
//! Two implementations of the rule exist on purpose: [`line_of_sight`] is exact integer
//! arithmetic for segments between cell centres (what the search planners use), and
//! [`segment_is_clear`] handles fractional waypoints in `f32`, erring on the blocked side by
//! [`TOUCH_EPS`]; between two cell centres it defers to the exact check, so the two always
//! agree there (the tests check it).
//!
//! Files, one concern each (everything public is re-exported here):
//! - `types`: [`Cell`], [`Point`] and [`octile`]; a leaf module, so that the grid can use
//!   cells while the rest of `geometry` uses the grid;
//! - `sight`: the exact rule between cell centres ([`line_of_sight`],
//!   [`blocked_cells_touched`]);
//! - `segment`: the `f32` rule ([`segment_is_clear`], [`TOUCH_EPS`]);
//! - `hull`: hull tests ([`hull_is_clear`], [`hull_blockers`], [`segment_is_clear_among`]);
//! - `clearance`: distances to the nearest blocked cell ([`segment_clearance`],
//!   [`point_clearance`]);
//! - `polyline`: following a path given as points ([`distance_to_polyline`]).

mod clearance;
mod hull;
mod polyline;
mod segment;
mod sight;
pub(crate) mod types;

pub use clearance::{point_clearance, segment_clearance};
pub(crate) use hull::{clear_among, quick_band};
pub use hull::{hull_blockers, hull_is_clear, hull_margin, segment_is_clear_among};
pub use polyline::distance_to_polyline;
pub(crate) use polyline::{advance, nearest_ahead};
pub use segment::{TOUCH_EPS, segment_is_clear};
pub use sight::{blocked_cells_touched, line_of_sight};
pub use types::{Cell, Point, octile};

use crate::grid::GridRef;

// Here rather than in `types`, which does not depend on the grid.
impl Point {
    /// The cell whose square contains the point (ties go to the lower index), if on the map.
    pub fn cell(self, grid: GridRef<'_>) -> Option<Cell> {
        if !self.is_finite() {
            return None;
        }
        // ceil(v - 1/2): a point on the edge between two cells goes to the lower index.
        // (floor(v + 1/2) sent ties upwards, and its rounding sent 0.49999997 to cell 1.)
        let (x, y) = (libm::ceilf(self.x - 0.5), libm::ceilf(self.y - 0.5));
        grid.contains(x as isize, y as isize)
            .then(|| Cell::new(x as u16, y as u16))
    }
}

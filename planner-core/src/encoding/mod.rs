//! Path encodings: how a point of the optimizer's box `[lb, ub]^D` becomes a path.
//!
//! The papers vary exactly this, so it is a trait ([`Encoding`]):
//! - [`column`](mod@column): `Lei2024Warehouse`'s column encoding (one row per map column; x-monotone paths only),
//!   a reproduction mode;
//! - [`walk`]: `Liu2020Igwo`'s 8-connected cell walk without revisits, a reproduction mode (its
//!   looser corner rule behind an option);
//! - [`corridor`]: the general encoding for any map: waypoints that slide across an exact
//!   guide route, with a repairing decoder, so every decoded path is valid.
//!
//! Costs are path lengths; an infeasible decoding (only the reproduction modes have them)
//! costs [`infeasible_penalty`] per violation on top, far above any length on the map.

pub mod blend;
pub mod column;
pub mod corridor;
pub mod walk;

use crate::error::PlanError;
use crate::grid::GridRef;
use crate::path::PathView;

/// A decision-vector-to-path mapping with a cost.
pub trait Encoding {
    /// Number of decision variables.
    fn dim(&self) -> usize;

    /// Lower and upper bound of variable `i`.
    fn bounds(&self, i: usize) -> (f32, f32);

    /// The cost of `x`: the decoded path's length, plus penalties if it is infeasible.
    ///
    /// It must depend on `x` alone (the `&mut self` is for scratch and hints, never for the
    /// value): [`Costs`] tells optimizers the cost is pure, so they may compute it again
    /// later instead of keeping it ([`Objective::pure`](crate::optim::Objective::pure)).
    fn cost(&mut self, x: &[f32]) -> f32;

    /// `cost(x)` when it is below `bound`, otherwise any value `>= bound`
    /// ([`Objective::cost_below`](crate::optim::Objective::cost_below)). The default is
    /// `cost(x)`.
    fn cost_below(&mut self, x: &[f32], bound: f32) -> f32 {
        let _ = bound;
        self.cost(x)
    }

    /// Writes the path `x` decodes to (before pruning). [`PlanError::BudgetExhausted`] if `x`
    /// decodes to an infeasible path; [`PlanError::CapacityExceeded`] if `out` is too small.
    fn decode(&mut self, x: &[f32], out: &mut PathView) -> Result<(), PlanError>;
}

/// The penalty per constraint violation: above the length of any path on the map (a path
/// visiting every cell once is shorter than `cells * sqrt 2`).
pub fn infeasible_penalty(grid: GridRef<'_>) -> f32 {
    2.0 * grid.cells() as f32 + 1000.0
}

/// An [`Encoding`]'s cost as an optimizer [`Objective`](crate::optim::Objective), bounded
/// evaluations included.
pub struct Costs<'e, E: ?Sized>(pub &'e mut E);

impl<E: Encoding + ?Sized> crate::optim::Objective for Costs<'_, E> {
    fn cost(&mut self, x: &[f32]) -> f32 {
        self.0.cost(x)
    }

    fn cost_below(&mut self, x: &[f32], bound: f32) -> f32 {
        self.0.cost_below(x, bound)
    }

    /// Decoded lengths depend on the decision vector alone.
    fn pure(&self) -> bool {
        true
    }
}

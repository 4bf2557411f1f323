//! `Lei2024Warehouse`'s column encoding: variable `j` is the row of the waypoint in map column
//! `start.x + j`.
//!
//! The path is `start -> (start.x, x_0) -> (start.x + 1, x_1) -> ... -> (goal.x, x_last) ->
//! goal`. Its length follows the paper's own 10 x 10 value (SPEC section 3):
//! `L = |x_0 - r_start| + sum_j sqrt((x_j - x_{j-1})^2 + 1) + |r_goal - x_last|`, rows rounded
//! and clamped to the map. Every segment is checked under the collision rule; each blocked
//! one adds [`infeasible_penalty`]. Only x-monotone paths can be
//! represented, so this is a reproduction mode, not the general planner.

use super::{Encoding, infeasible_penalty};
use crate::error::PlanError;
use crate::geometry::{Cell, blocked_cells_touched};
use crate::grid::GridRef;
use crate::path::PathView;

/// `Lei2024Warehouse`'s column encoding.
#[derive(Clone, Copy, Debug)]
pub struct ColumnEncoding<'g> {
    grid: GridRef<'g>,
    start: Cell,
    goal: Cell,
    penalty: f32,
}

impl<'g> ColumnEncoding<'g> {
    /// The encoding for `start -> goal`; [`PlanError::InvalidParameters`] unless
    /// `start.x <= goal.x` (the representable direction).
    pub fn new(grid: GridRef<'g>, start: Cell, goal: Cell) -> Result<Self, PlanError> {
        if start.x > goal.x {
            return Err(PlanError::InvalidParameters);
        }
        Ok(ColumnEncoding {
            grid,
            start,
            goal,
            penalty: infeasible_penalty(grid),
        })
    }

    fn row(&self, v: f32) -> u16 {
        let max = (self.grid.height() - 1) as f32;
        // `roundf` (half away from zero) and the clamp without the libm call, which was a
        // fifth of an evaluation, and with one float-to-integer cast instead of three (each
        // saturating, a handful of instructions on x86_64). On the map (`0 <= v <= max <
        // 2^16`; NaN fails both tests) the cast truncates exactly and the fraction
        // `v - trunc(v)` is exact; every other value goes where `roundf` and the clamp put
        // it: `max` above, 0 below and for NaN.
        if v >= 0.0 && v <= max {
            let t = v as u32;
            (t + u32::from(v - t as f32 >= 0.5)) as u16
        } else if v > max {
            max as u16
        } else {
            0
        }
    }

    /// The path length alone (the cost without penalties), summed as in [`Self::trace`].
    fn length(&self, x: &[f32]) -> f32 {
        let mut length = 0.0;
        let mut prev = self.start;
        for (j, &v) in x.iter().enumerate() {
            let cell = Cell::new(self.start.x + j as u16, self.row(v));
            length += step_length(prev, cell);
            prev = cell;
        }
        length + step_length(prev, self.goal)
    }

    /// The two parts of the cost: the path length and the number of blocked cells (or cells
    /// off the map) its segments touch, each segment counting its own cells; the cost is
    /// `length + penalty * blocked`. For cross-checks of other implementations (the
    /// `column_cost` example).
    pub fn length_and_blocked(&self, x: &[f32]) -> (f32, u32) {
        self.trace(x, |_| Ok(())).unwrap_or((f32::INFINITY, 0))
    }

    /// The penalty per blocked cell, [`infeasible_penalty`] of the map.
    pub fn penalty(&self) -> f32 {
        self.penalty
    }

    /// Visits the path's vertices; returns (length, blocked cells touched).
    fn trace(
        &self,
        x: &[f32],
        mut visit: impl FnMut(Cell) -> Result<(), PlanError>,
    ) -> Result<(f32, u32), PlanError> {
        let mut length = 0.0;
        let mut blocked = 0;
        let mut prev = self.start;
        visit(prev)?;
        let step = |from: Cell, to: Cell, length: &mut f32, blocked: &mut u32| {
            *length += step_length(from, to);
            *blocked += blocked_cells_touched(self.grid, from, to);
        };
        for (j, &v) in x.iter().enumerate() {
            let cell = Cell::new(self.start.x + j as u16, self.row(v));
            step(prev, cell, &mut length, &mut blocked);
            if cell != prev {
                visit(cell)?;
            }
            prev = cell;
        }
        step(prev, self.goal, &mut length, &mut blocked);
        if self.goal != prev {
            visit(self.goal)?;
        }
        Ok((length, blocked))
    }
}

/// Euclidean length of the segment between two cell centres.
fn step_length(from: Cell, to: Cell) -> f32 {
    // Integer differences, then one conversion each: the same exact values.
    let dx = (i32::from(to.x) - i32::from(from.x)) as f32;
    let dy = (i32::from(to.y) - i32::from(from.y)) as f32;
    crate::math::sqrt(dx * dx + dy * dy)
}

impl Encoding for ColumnEncoding<'_> {
    fn dim(&self) -> usize {
        (self.goal.x - self.start.x) as usize + 1
    }

    fn bounds(&self, _i: usize) -> (f32, f32) {
        (0.0, (self.grid.height() - 1) as f32)
    }

    fn cost(&mut self, x: &[f32]) -> f32 {
        let (length, blocked) = self.length_and_blocked(x);
        length + self.penalty * blocked as f32
    }

    fn cost_below(&mut self, x: &[f32], bound: f32) -> f32 {
        if bound.is_nan() || bound == f32::INFINITY {
            return self.cost(x);
        }
        // Penalties only add, so the length is a lower bound that needs no collision check,
        // and so is the length plus the penalties found so far (`f32` addition and
        // multiplication by a positive penalty are monotone).
        let length = self.length(x);
        if length >= bound {
            return length;
        }
        let mut blocked = 0u32;
        let mut prev = self.start;
        let cells = x
            .iter()
            .enumerate()
            .map(|(j, &v)| Cell::new(self.start.x + j as u16, self.row(v)))
            .chain(core::iter::once(self.goal));
        for cell in cells {
            let n = blocked_cells_touched(self.grid, prev, cell);
            if n > 0 {
                blocked += n;
                let cost = length + self.penalty * blocked as f32;
                if cost >= bound {
                    return cost;
                }
            }
            prev = cell;
        }
        length + self.penalty * blocked as f32
    }

    fn decode(&mut self, x: &[f32], out: &mut PathView) -> Result<(), PlanError> {
        out.clear();
        let (_, blocked) = self.trace(x, |c| {
            out.push(c.center())
                .map_err(|_| PlanError::CapacityExceeded)
        })?;
        if blocked > 0 {
            return Err(PlanError::BudgetExhausted);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};
    use crate::path::{Path, length, validate};

    #[test]
    fn reproduces_the_papers_10x10_length() {
        // Rows 0 -> 9 over ten columns with five steps of 1 and two of 2: 2 + 5 sqrt2 + 2 sqrt5.
        let g: Grid<{ words_for(10, 10) }> = Grid::new(10, 10).unwrap();
        let mut enc = ColumnEncoding::new(g.view(), Cell::new(0, 0), Cell::new(9, 9)).unwrap();
        let x = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0, 8.0, 8.0, 10.4];
        // |1-0| + (1,1,1,1,1 diagonal) sqrt2*5 + sqrt5 (6->8) + 1 + 1 + sqrt(1+1) (8->9 clamped) + 0
        let want = 1.0 + 5.0 * 2f32.sqrt() + 5f32.sqrt() + 2.0 + 2f32.sqrt();
        assert!((enc.cost(&x) - want).abs() < 1e-4);
        let paper = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 7.0, 9.0, 9.0, 9.0];
        let paper_len = enc.cost(&paper);
        assert!((paper_len - 13.5432).abs() < 1e-3, "{paper_len}");
        let mut p: Path<32> = Path::new();
        enc.decode(&paper, &mut p).unwrap();
        assert!((length(&p) - paper_len).abs() < 1e-4);
        assert_eq!(
            validate(g.view(), &p, Cell::new(0, 0), Cell::new(9, 9)),
            Ok(())
        );
    }

    #[test]
    fn blocked_segments_are_penalised_and_not_decoded() {
        let g: Grid<{ words_for(4, 4) }> = Grid::parse_rows(b"....\n.@..\n....\n....\n").unwrap();
        let mut enc = ColumnEncoding::new(g.view(), Cell::new(0, 0), Cell::new(3, 3)).unwrap();
        let through = [0.0, 2.0, 3.0, 3.0]; // (0,0)->(1,2) touches (1,1)? it passes x=0.5 at y=1.
        assert!(enc.cost(&through) > infeasible_penalty(g.view()));
        let (length, blocked) = enc.length_and_blocked(&through);
        assert_eq!(blocked, 1); // (0,0)->(0,0), (0,0)->(1,2) touches (1,1), then free
        assert_eq!(enc.penalty(), infeasible_penalty(g.view()));
        assert_eq!(enc.cost(&through), length + enc.penalty() * blocked as f32);
        let mut p: Path<16> = Path::new();
        assert_eq!(
            enc.decode(&through, &mut p),
            Err(PlanError::BudgetExhausted)
        );
        assert!(enc.cost(&[0.0, 0.0, 0.0, 3.0]) < 10.0);
        assert!(enc.cost(&[f32::NAN, 0.0, 0.0, 3.0]).is_finite());
    }

    #[test]
    fn rows_round_half_away_from_zero_and_clamp() {
        let g: Grid<{ words_for(4, 40) }> = Grid::new(4, 40).unwrap();
        let enc = ColumnEncoding::new(g.view(), Cell::new(0, 0), Cell::new(3, 3)).unwrap();
        let want = |v: f32| {
            let r = libm::roundf(v);
            if r.is_nan() || r < 0.0 {
                0
            } else {
                r.min(39.0) as u16
            }
        };
        let fixed = [
            0.0,
            -0.0,
            0.5,
            0.499_999_97,
            1.5,
            2.5,
            38.5,
            38.499_996,
            39.0,
            39.4,
            39.5,
            40.0,
            -0.4,
            -0.5,
            -3.7,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e9,
            -1e9,
            f32::MIN_POSITIVE,
        ];
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let random = core::iter::repeat_with(|| {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            [
                (state >> 40) as f32 / (1u64 << 24) as f32 * 50.0 - 5.0,
                f32::from_bits(state as u32),
            ]
        })
        .take(100_000)
        .flatten();
        for v in fixed.into_iter().chain(random) {
            assert_eq!(enc.row(v), want(v), "{v} ({:#x})", v.to_bits());
        }
    }

    #[test]
    fn start_right_of_goal_is_invalid() {
        let g: Grid<{ words_for(4, 4) }> = Grid::new(4, 4).unwrap();
        assert!(ColumnEncoding::new(g.view(), Cell::new(3, 0), Cell::new(0, 3)).is_err());
    }
}

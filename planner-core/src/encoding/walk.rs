//! `Liu2020Igwo`'s 8-connected cell walk: variable `k` chooses the `k`-th step among the free,
//! not yet visited neighbours (no revisits, so no loops), costs 1 and sqrt 2.
//!
//! The paper does not say how a real number picks a neighbour; here `x_k` in `[0, 1)` is the
//! uniform draw of a roulette wheel whose weights favour neighbours closer to the goal
//! (`exp(-beta (h - h_min))`, octile `h`): the optimizer steers the draws, the bias keeps
//! random walks from wandering off. A walk that dead-ends or runs out of steps is infeasible:
//! its cost is [`infeasible_penalty`] plus its length plus the
//! octile distance still to go, so that the optimizer can still rank infeasible walks.
//!
//! Corner rule: [`CornerRule::Strict`] is SPEC's (no corner cutting); [`CornerRule::Loose`] is
//! the paper's (a diagonal is forbidden only when *both* side cells are blocked). Paths of the
//! loose rule may touch blocked corners; check them with [`validate_walk`].

use super::{Encoding, infeasible_penalty};
use crate::error::PlanError;
use crate::geometry::{Cell, octile};
use crate::grid::GridRef;
use crate::path::PathView;
use crate::search::MOVES;

/// Which diagonal steps are allowed.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum CornerRule {
    /// SPEC's rule: both side cells must be free (no corner cutting).
    #[default]
    Strict,
    /// `Liu2020Igwo`'s rule: forbidden only when both side cells are blocked.
    Loose,
}

impl CornerRule {
    /// Whether the king move from `(x, y)` by `(dx, dy)` is allowed onto a free cell.
    pub fn allows(self, grid: GridRef<'_>, x: isize, y: isize, dx: isize, dy: isize) -> bool {
        if grid.is_blocked(x + dx, y + dy) {
            return false;
        }
        if dx == 0 || dy == 0 {
            return true;
        }
        let (a, b) = (grid.is_blocked(x + dx, y), grid.is_blocked(x, y + dy));
        match self {
            CornerRule::Strict => !a && !b,
            CornerRule::Loose => !(a && b),
        }
    }
}

/// `Liu2020Igwo`'s walk encoding. `visited` is a caller-owned bitset of `cells / 32 + 1` words.
#[derive(Debug)]
pub struct WalkEncoding<'g, 'b> {
    grid: GridRef<'g>,
    start: Cell,
    goal: Cell,
    steps: usize,
    rule: CornerRule,
    beta: f32,
    visited: &'b mut [u32],
    penalty: f32,
}

impl<'g, 'b> WalkEncoding<'g, 'b> {
    /// A walk of at most `steps` moves; `beta` is the roulette's greediness (2 is a good
    /// default; NaN or negative is [`PlanError::InvalidParameters`]).
    pub fn new(
        grid: GridRef<'g>,
        start: Cell,
        goal: Cell,
        steps: usize,
        rule: CornerRule,
        beta: f32,
        visited: &'b mut [u32],
    ) -> Result<Self, PlanError> {
        if steps == 0 || !beta.is_finite() || beta < 0.0 {
            return Err(PlanError::InvalidParameters);
        }
        if visited.len() < grid.cells() / 32 + 1 {
            return Err(PlanError::CapacityExceeded);
        }
        Ok(WalkEncoding {
            grid,
            start,
            goal,
            steps,
            rule,
            beta,
            visited,
            penalty: infeasible_penalty(grid),
        })
    }

    /// Runs the walk, calling `visit` on each cell; returns (length, reached goal, last cell).
    fn run(
        &mut self,
        x: &[f32],
        mut visit: impl FnMut(Cell) -> Result<(), PlanError>,
    ) -> Result<(f32, bool, Cell), PlanError> {
        self.visited.iter_mut().for_each(|w| *w = 0);
        let width = self.grid.width();
        let mark = |visited: &mut [u32], c: Cell| {
            let i = c.y as usize * width + c.x as usize;
            if let Some(w) = visited.get_mut(i / 32) {
                *w |= 1 << (i % 32);
            }
        };
        let seen = |visited: &[u32], c: Cell| {
            let i = c.y as usize * width + c.x as usize;
            visited.get(i / 32).is_none_or(|w| w & (1 << (i % 32)) != 0)
        };
        let mut cur = self.start;
        mark(self.visited, cur);
        visit(cur)?;
        let mut length = 0.0;
        for &draw in x.iter().take(self.steps) {
            if cur == self.goal {
                break;
            }
            // Candidates with their octile distance to the goal.
            let mut cand: [(Cell, f32, f32); 8] = [(cur, 0.0, 0.0); 8];
            let mut n = 0;
            let mut h_min = f32::INFINITY;
            for (dx, dy, cost) in MOVES {
                let (x0, y0) = (cur.x as isize, cur.y as isize);
                if !self
                    .rule
                    .allows(self.grid, x0, y0, dx as isize, dy as isize)
                {
                    continue;
                }
                let next = Cell::new((x0 + dx as isize) as u16, (y0 + dy as isize) as u16);
                if seen(self.visited, next) {
                    continue;
                }
                let h = octile(next, self.goal);
                h_min = h_min.min(h);
                cand[n] = (next, h, cost);
                n += 1;
            }
            if n == 0 {
                break; // dead end
            }
            // Closest first, so that small draws pick good steps (stable: ties keep MOVES order).
            cand[..n].sort_unstable_by(|a, b| a.1.total_cmp(&b.1).then(a.0.cmp(&b.0)));
            let mut total = 0.0;
            for c in cand.iter_mut().take(n) {
                c.1 = libm::expf(-self.beta * (c.1 - h_min));
                total += c.1;
            }
            let draw = if draw.is_finite() {
                draw.clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut target = draw * total;
            let mut pick = n - 1;
            for (i, c) in cand.iter().enumerate().take(n) {
                if target < c.1 {
                    pick = i;
                    break;
                }
                target -= c.1;
            }
            let (next, _, cost) = cand[pick];
            length += cost;
            cur = next;
            mark(self.visited, cur);
            visit(cur)?;
        }
        Ok((length, cur == self.goal, cur))
    }
}

impl Encoding for WalkEncoding<'_, '_> {
    fn dim(&self) -> usize {
        self.steps
    }

    fn bounds(&self, _i: usize) -> (f32, f32) {
        (0.0, 1.0)
    }

    fn cost(&mut self, x: &[f32]) -> f32 {
        match self.run(x, |_| Ok(())) {
            Ok((length, true, _)) => length,
            Ok((length, false, last)) => self.penalty + length + octile(last, self.goal),
            Err(_) => f32::INFINITY,
        }
    }

    fn decode(&mut self, x: &[f32], out: &mut PathView) -> Result<(), PlanError> {
        out.clear();
        let (_, reached, _) = self.run(x, |c| {
            out.push(c.center())
                .map_err(|_| PlanError::CapacityExceeded)
        })?;
        if reached {
            Ok(())
        } else {
            Err(PlanError::BudgetExhausted)
        }
    }
}

/// Checks a walk (king moves between cell centres) under a corner rule.
pub fn validate_walk(grid: GridRef<'_>, path: &[crate::geometry::Point], rule: CornerRule) -> bool {
    path.windows(2).all(|w| {
        let (dx, dy) = (w[1].x - w[0].x, w[1].y - w[0].y);
        dx.abs() <= 1.0
            && dy.abs() <= 1.0
            && (dx != 0.0 || dy != 0.0)
            && libm::truncf(w[0].x) == w[0].x
            && libm::truncf(w[0].y) == w[0].y
            && rule.allows(
                grid,
                w[0].x as isize,
                w[0].y as isize,
                dx as isize,
                dy as isize,
            )
    }) && path
        .first()
        .is_some_and(|p| !grid.is_blocked(p.x as isize, p.y as isize))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};
    use crate::path::{Path, length, validate};

    type G = Grid<{ words_for(8, 8) }>;

    #[test]
    fn greedy_draws_walk_straight_to_the_goal() {
        let g = G::new(6, 6).unwrap();
        let mut bits = [0u32; 2];
        let mut enc = WalkEncoding::new(
            g.view(),
            Cell::new(0, 0),
            Cell::new(5, 3),
            10,
            CornerRule::Strict,
            8.0,
            &mut bits,
        )
        .unwrap();
        let x = [0.0; 10];
        let c = enc.cost(&x);
        assert!((c - (2.0 + 3.0 * 2f32.sqrt())).abs() < 1e-5, "{c}");
        let mut p: Path<16> = Path::new();
        enc.decode(&x, &mut p).unwrap();
        assert_eq!(
            validate(g.view(), &p, Cell::new(0, 0), Cell::new(5, 3)),
            Ok(())
        );
        assert!((length(&p) - c).abs() < 1e-5);
    }

    #[test]
    fn loose_rule_allows_one_blocked_side_only() {
        let g = G::parse_rows(b".@\n..\n").unwrap();
        assert!(!CornerRule::Strict.allows(g.view(), 0, 0, 1, 1));
        assert!(CornerRule::Loose.allows(g.view(), 0, 0, 1, 1));
        let g = G::parse_rows(b".@\n@.\n").unwrap();
        assert!(!CornerRule::Loose.allows(g.view(), 0, 0, 1, 1));
    }

    #[test]
    fn dead_ends_and_short_walks_are_penalised() {
        let g = G::parse_rows(b"...@.\n.@@@.\n.....\n").unwrap();
        let mut bits = [0u32; 2];
        let mut enc = WalkEncoding::new(
            g.view(),
            Cell::new(0, 0),
            Cell::new(4, 0),
            3,
            CornerRule::Strict,
            2.0,
            &mut bits,
        )
        .unwrap();
        assert!(enc.cost(&[0.0, 0.0, 0.0]) > infeasible_penalty(g.view()));
        let mut p: Path<16> = Path::new();
        assert_eq!(
            enc.decode(&[0.0; 3], &mut p),
            Err(PlanError::BudgetExhausted)
        );
        let mut bits = [0u32; 1];
        assert_eq!(
            WalkEncoding::new(
                g.view(),
                Cell::new(0, 0),
                Cell::new(4, 0),
                3,
                CornerRule::Strict,
                f32::NAN,
                &mut bits
            )
            .unwrap_err(),
            PlanError::InvalidParameters
        );
    }
}

//! `Lei2024Warehouse`'s ant colony baseline (ACA): ants move over the 8-connected grid from the start,
//! choosing among free, unvisited neighbours with probability proportional to
//! `tau^alpha * eta^beta`, `eta = 1 / (distance to goal)`; pheromone lives on directed moves,
//! evaporates by `rho` each iteration and every ant that reached the goal deposits `Q / L` on
//! its moves (ant-cycle rule, applied after all ants of the iteration moved).
//!
//! Random numbers: per ant, one uniform draw per step (the roulette), nothing else.

use crate::encoding::walk::CornerRule;
use crate::error::PlanError;
use crate::geometry::{Cell, Point};
use crate::grid::GridRef;
use crate::optim::random::Random;
use crate::path::{self, PathView};
use crate::search::{MOVES, check_endpoints, connectivity};

use super::{PlanReport, PlanStop};

/// ACO parameters (`Lei2024Warehouse`'s values by default).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct AcoParams {
    /// Ants per iteration (10).
    pub ants: usize,
    /// Pheromone exponent (1).
    pub alpha: f32,
    /// Heuristic exponent (7).
    pub beta: f32,
    /// Evaporation rate (0.35).
    pub rho: f32,
    /// Deposit constant (1).
    pub q: f32,
    /// Iterations.
    pub iterations: u32,
    /// Stop after this many iterations without improvement.
    pub stagnation: Option<u32>,
    /// The seed.
    pub seed: u64,
    /// Apply node pruning to the result.
    pub prune: bool,
}

impl Default for AcoParams {
    fn default() -> Self {
        AcoParams {
            ants: 10,
            alpha: 1.0,
            beta: 7.0,
            rho: 0.35,
            q: 1.0,
            iterations: 100,
            stagnation: None,
            seed: 0,
            prune: true,
        }
    }
}

/// Caller-owned ACO storage: `8 * cells` floats each for pheromone and its per-iteration
/// increment, a `cells / 32 + 1`-word visited bitset, and two cell-index buffers (the
/// current ant's tour and the best tour) of up to `cells` entries.
pub struct AcoWorkspace<'a> {
    /// Pheromone per directed move.
    pub tau: &'a mut [f32],
    /// Deposits of the current iteration.
    pub delta: &'a mut [f32],
    /// Visited bitset.
    pub visited: &'a mut [u32],
    /// The tour being built.
    pub tour: &'a mut [u32],
    /// The best tour so far.
    pub best: &'a mut [u32],
    /// Component labels of the map (from [`connectivity::label`]).
    pub labels: &'a [u32],
}

/// Runs the ant colony; `history` gets the best length per iteration.
pub fn plan(
    grid: GridRef<'_>,
    start: Cell,
    goal: Cell,
    params: &AcoParams,
    ws: &mut AcoWorkspace<'_>,
    out: &mut PathView,
    history: &mut [f32],
) -> Result<PlanReport, PlanError> {
    check_endpoints(grid, start, goal)?;
    let ok = |v: f32| v.is_finite() && v >= 0.0;
    if params.ants == 0
        || params.iterations == 0
        || params.stagnation == Some(0)
        || !ok(params.alpha)
        || !ok(params.beta)
        || !(params.rho.is_finite() && params.rho > 0.0 && params.rho <= 1.0)
        || !(params.q.is_finite() && params.q > 0.0)
    {
        return Err(PlanError::InvalidParameters);
    }
    let cells = grid.cells();
    if ws.tau.len() < 8 * cells
        || ws.delta.len() < 8 * cells
        || ws.visited.len() < cells / 32 + 1
        || ws.tour.len() < cells
        || ws.best.len() < cells
    {
        return Err(PlanError::CapacityExceeded);
    }
    if !connectivity::connected(grid, ws.labels, start, goal)? {
        return Err(PlanError::NoValidPath);
    }
    let width = grid.width();
    let idx = |c: Cell| c.y as usize * width + c.x as usize;
    ws.tau[..8 * cells].iter_mut().for_each(|t| *t = 1.0);
    let mut rng = Random::new(params.seed);
    let mut best_len = f32::INFINITY;
    let mut best_steps = 0usize;
    let mut best_iteration = 0u32;
    let mut initial_cost = f32::INFINITY;
    let mut iteration = 0u32;
    let mut evaluations = 0u64;
    let mut written = 0;
    let goal_pt = goal.center();
    let stop = loop {
        if iteration >= params.iterations {
            break PlanStop::Iterations;
        }
        if params
            .stagnation
            .is_some_and(|k| iteration - best_iteration >= k)
            && best_len.is_finite()
        {
            break PlanStop::Stagnation;
        }
        ws.delta[..8 * cells].iter_mut().for_each(|d| *d = 0.0);
        for _ in 0..params.ants {
            evaluations += 1;
            ws.visited.iter_mut().for_each(|w| *w = 0);
            let mut cur = start;
            let mut steps = 0usize;
            let mut length = 0.0f32;
            ws.tour[0] = idx(cur) as u32;
            mark(ws.visited, idx(cur));
            while cur != goal && steps + 1 < cells {
                let mut weight = [0.0f32; 8];
                let mut total = 0.0;
                for (m, (dx, dy, _)) in MOVES.iter().enumerate() {
                    let (x, y) = (cur.x as isize, cur.y as isize);
                    let (dx, dy) = (*dx as isize, *dy as isize);
                    if !CornerRule::Strict.allows(grid, x, y, dx, dy) {
                        continue;
                    }
                    let next = Cell::new((x + dx) as u16, (y + dy) as u16);
                    if is_marked(ws.visited, idx(next)) {
                        continue;
                    }
                    let d = next.center().distance(goal_pt);
                    let eta = 1.0 / d.max(0.5);
                    let w = libm::powf(ws.tau[8 * idx(cur) + m], params.alpha)
                        * libm::powf(eta, params.beta);
                    weight[m] = if w.is_finite() { w } else { f32::MAX / 16.0 };
                    total += weight[m];
                }
                if total <= 0.0 {
                    break; // dead end: this ant fails
                }
                let mut target = rng.unit() * total;
                let mut pick = None;
                for (m, &w) in weight.iter().enumerate() {
                    if w > 0.0 {
                        pick = Some(m);
                        if target < w {
                            break;
                        }
                        target -= w;
                    }
                }
                let Some(m) = pick else { break };
                let (dx, dy, cost) = MOVES[m];
                cur = Cell::new(
                    (cur.x as isize + dx as isize) as u16,
                    (cur.y as isize + dy as isize) as u16,
                );
                steps += 1;
                length += cost;
                ws.tour[steps] = idx(cur) as u32;
                mark(ws.visited, idx(cur));
            }
            if cur != goal {
                continue;
            }
            for s in 0..steps {
                if let Some(m) = move_index(ws.tour[s] as usize, ws.tour[s + 1] as usize, width) {
                    ws.delta[8 * ws.tour[s] as usize + m] += params.q / length;
                }
            }
            if length < best_len {
                best_len = length;
                best_steps = steps;
                best_iteration = iteration + 1;
                ws.best[..=steps].copy_from_slice(&ws.tour[..=steps]);
            }
        }
        for (t, d) in ws.tau[..8 * cells].iter_mut().zip(ws.delta.iter()) {
            *t = (1.0 - params.rho) * *t + d;
        }
        iteration += 1;
        if iteration == 1 {
            initial_cost = best_len;
        }
        if let Some(slot) = history.get_mut(written) {
            *slot = best_len;
            written += 1;
        }
    };
    if !best_len.is_finite() {
        return Err(PlanError::BudgetExhausted);
    }
    out.clear();
    for &i in &ws.best[..=best_steps] {
        let c = grid.cell(i as usize);
        out.push(Point::new(c.x as f32, c.y as f32))
            .map_err(|_| PlanError::CapacityExceeded)?;
    }
    if path::validate(grid, out, start, goal).is_err() {
        return Err(PlanError::NoValidPath);
    }
    if params.prune {
        path::prune_collinear(out);
        path::shortcut(grid, out);
    }
    Ok(PlanReport {
        length: path::length(out),
        turns: path::turns(out),
        initial_cost,
        final_cost: best_len,
        evaluations,
        iterations: iteration,
        best_iteration,
        dimension: 0,
        stop,
        history_len: written,
        guide: None,
    })
}

fn mark(bits: &mut [u32], i: usize) {
    if let Some(w) = bits.get_mut(i / 32) {
        *w |= 1 << (i % 32);
    }
}

fn is_marked(bits: &[u32], i: usize) -> bool {
    bits.get(i / 32).is_none_or(|w| w & (1 << (i % 32)) != 0)
}

fn move_index(from: usize, to: usize, width: usize) -> Option<usize> {
    let (fx, fy) = ((from % width) as isize, (from / width) as isize);
    let (tx, ty) = ((to % width) as isize, (to / width) as isize);
    MOVES
        .iter()
        .position(|&(dx, dy, _)| fx + dx as isize == tx && fy + dy as isize == ty)
}

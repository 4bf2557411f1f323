//! A lower bound on the length of any path that keeps a clearance `r`, for `bench safety`.
//!
//! The map is cut into `K x K` subcells per cell; a subcell is blocked where every point of
//! it is closer than `r` to an obstacle (its centre's clearance plus half its diagonal is
//! below `r`: clearance changes no faster than distance). A path that keeps `r` touches no
//! blocked subcell, so it is a valid path of the fine grid, and the exact any-angle path of
//! the fine grid is no longer than it. When the fine grid has no path, no path keeps `r`.

use planner_core::error::PlanError;
use planner_core::geometry::{Cell, point_clearance};
use planner_core::grid::GridBuf;
use planner_core::optim::any::AlgorithmKind;
use planner_core::path::Path;
use planner_core::planner::aco::AcoParams;
use planner_core::planner::owned::{HostPlanner, PlanChoice};
use planner_core::planner::{PlanOptions, PlanParams, PlannerKind};

/// Subcells per cell a side (odd: a cell's centre is a subcell's centre).
const K: usize = 5;

/// The fine grid of one map for one clearance, prepared for queries.
pub struct ClearanceBound {
    fine: GridBuf,
    planner: HostPlanner,
    out: Box<Path<65536>>,
}

impl ClearanceBound {
    /// The fine grid of `grid` for clearance `r` (cells).
    pub fn new(grid: &GridBuf, r: f32) -> anyhow::Result<Self> {
        let view = grid.view();
        let (w, h) = (view.width(), view.height());
        let mut fine = GridBuf::new(w * K, h * K).map_err(|e| anyhow::anyhow!("{e:?}"))?;
        let half_diagonal = core::f32::consts::SQRT_2 / (2 * K) as f32;
        let centre = |i: usize| (i as f32 - (K / 2) as f32) / K as f32;
        for j in 0..h * K {
            for i in 0..w * K {
                let (x, y) = (i / K, j / K);
                let p = planner_core::geometry::Point::new(centre(i), centre(j));
                let near = point_clearance(view, p, r) + half_diagonal < r;
                if view.is_blocked(x as isize, y as isize) || near {
                    fine.set_blocked(i, j, true)
                        .map_err(|e| anyhow::anyhow!("{e:?}"))?;
                }
            }
        }
        let mut planner = HostPlanner::new();
        planner.prepare(fine.view()).map_err(anyhow::Error::msg)?;
        Ok(ClearanceBound {
            fine,
            planner,
            out: Box::new(Path::new()),
        })
    }

    /// The bound on the length (cells) of a path `s -> g` that keeps the clearance; `None`
    /// where no path keeps it. `s` and `g` must themselves have the clearance.
    pub fn length(&mut self, s: Cell, g: Cell) -> anyhow::Result<Option<f64>> {
        let fine = |c: Cell| {
            Cell::new(
                c.x * K as u16 + (K / 2) as u16,
                c.y * K as u16 + (K / 2) as u16,
            )
        };
        let choice = PlanChoice {
            kind: PlannerKind::AnyAngle,
            params: PlanParams::host(AlgorithmKind::Tclhho),
            aco: AcoParams::default(),
        };
        let result = self.planner.plan(
            self.fine.view(),
            fine(s),
            fine(g),
            &choice,
            &mut *self.out,
            PlanOptions::default(),
        );
        match result {
            Ok(o) => Ok(Some(o.length as f64 / K as f64)),
            Err(PlanError::NoValidPath) => Ok(None),
            Err(e) => Err(anyhow::anyhow!("clearance bound {s:?} -> {g:?}: {e}")),
        }
    }
}

/// The clearance a path can surely keep: the widest route over cell centres (moves to the
/// eight neighbours, each move as clear as its segment), capped at `cap`.
pub struct WidestRoute {
    width: usize,
    height: usize,
    /// Clearance of the move from each cell to its neighbour E, S, SE, SW (0: no move).
    moves: Vec<[f32; 4]>,
}

/// The moves [`WidestRoute::moves`] stores, as (dx, dy).
const FORWARD: [(isize, isize); 4] = [(1, 0), (0, 1), (1, 1), (-1, 1)];

impl WidestRoute {
    /// The moves of `grid` up to clearance `cap`.
    pub fn new(grid: &GridBuf, cap: f32) -> Self {
        let view = grid.view();
        let (width, height) = (view.width(), view.height());
        let mut moves = vec![[0.0f32; 4]; width * height];
        for y in 0..height as isize {
            for x in 0..width as isize {
                if view.is_blocked(x, y) {
                    continue;
                }
                let a = Cell::new(x as u16, y as u16).center();
                for (k, (dx, dy)) in FORWARD.into_iter().enumerate() {
                    let (nx, ny) = (x + dx, y + dy);
                    let inside =
                        nx >= 0 && ny >= 0 && (nx as usize) < width && (ny as usize) < height;
                    if !inside || view.is_blocked(nx, ny) {
                        continue;
                    }
                    let b = Cell::new(nx as u16, ny as u16).center();
                    moves[y as usize * width + x as usize][k] =
                        planner_core::geometry::segment_clearance(view, a, b, cap);
                }
            }
        }
        WidestRoute {
            width,
            height,
            moves,
        }
    }

    /// The largest smallest-clearance of a route `s -> g` over cell centres (0 without one).
    pub fn clearance(&self, s: Cell, g: Cell) -> f32 {
        use std::collections::BinaryHeap;
        let index = |c: Cell| c.y as usize * self.width + c.x as usize;
        let mut best = vec![-1.0f32; self.width * self.height];
        // Widths are at least 0, so their bit patterns order as the values do.
        let mut heap = BinaryHeap::new();
        best[index(s)] = f32::INFINITY;
        heap.push((f32::INFINITY.to_bits(), s.x, s.y));
        while let Some((bits, x, y)) = heap.pop() {
            let (w, here) = (f32::from_bits(bits), Cell::new(x, y));
            if here == g {
                return w;
            }
            if w < best[index(here)] {
                continue;
            }
            let (x, y) = (x as isize, y as isize);
            for (k, (dx, dy)) in FORWARD.into_iter().enumerate() {
                for sign in [1, -1] {
                    let (nx, ny) = (x + sign * dx, y + sign * dy);
                    if nx < 0 || ny < 0 || nx as usize >= self.width || ny as usize >= self.height {
                        continue;
                    }
                    // A move is stored at the cell it leaves in the forward direction.
                    let from = if sign == 1 { (x, y) } else { (nx, ny) };
                    let clear = self.moves[from.1 as usize * self.width + from.0 as usize][k];
                    let there = Cell::new(nx as u16, ny as u16);
                    let through = w.min(clear);
                    if clear > 0.0 && through > best[index(there)] {
                        best[index(there)] = through;
                        heap.push((through.to_bits(), there.x, there.y));
                    }
                }
            }
        }
        0.0
    }
}

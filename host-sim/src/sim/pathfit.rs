//! Clearance-aware global paths: the planners' any-angle paths touch shelf corners and run
//! along walls (their collision rule only keeps the segments out of blocked cells), which a
//! robot with a footprint cannot follow. Before DWA follows a path, its points are pushed
//! away from walls up to a target clearance and the result is smoothed:
//!
//! 1. resample the polyline every `spacing` cells;
//! 2. repeat: move each interior point up the clearance gradient while its clearance is
//!    below `target`, plus a small pull towards the middle of its neighbours (smoothing); a
//!    move that lowers a point's clearance below what it had (or below `target`) is refused;
//! 3. the end points stay where they are (the robot and the goal).
//!
//! In a one-cell aisle the gradient vanishes on the centre line, so the path settles in the
//! middle of the aisle; round a shelf end it swings out.

use planner_core::geometry::{Point, point_clearance};
use planner_core::grid::GridRef;

/// Parameters of [`fit`].
#[derive(Clone, Copy, Debug)]
pub struct FitParams {
    /// Resampling step (cells).
    pub spacing: f32,
    /// Clearance wanted between the path and obstacles (cells, from the path's centre line).
    pub target: f32,
    /// Iterations.
    pub iterations: u32,
}

impl Default for FitParams {
    fn default() -> Self {
        FitParams {
            spacing: 0.25,
            target: 1.0,
            iterations: 40,
        }
    }
}

/// `path` resampled every `spacing` cells (the original vertices are kept).
pub fn resample(path: &[Point], spacing: f32) -> Vec<Point> {
    let mut out = Vec::with_capacity(path.len() * 4);
    if let Some(first) = path.first() {
        out.push(*first);
    }
    for s in path.windows(2) {
        let (a, b) = (s[0], s[1]);
        let len = a.distance(b);
        let n = (len / spacing).ceil().max(1.0) as usize;
        for k in 1..=n {
            let t = k as f32 / n as f32;
            out.push(Point::new(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t));
        }
    }
    out.dedup_by(|a, b| a.distance(*b) < 1e-4);
    out
}

/// The path pushed away from obstacles and smoothed (see the module documentation).
pub fn fit(grid: GridRef<'_>, path: &[Point], params: &FitParams) -> Vec<Point> {
    if path.len() < 2 {
        return path.to_vec();
    }
    let mut pts = resample(path, params.spacing);
    let n = pts.len();
    if n < 3 {
        return pts;
    }
    let cap = params.target + 0.5;
    let clear = |p: Point| point_clearance(grid, p, cap);
    let h = 0.05f32;
    for _ in 0..params.iterations {
        let mut moved = 0.0f32;
        for i in 1..n - 1 {
            let p = pts[i];
            let c = clear(p);
            // Push: up the clearance gradient while below the target.
            let mut push = (0.0f32, 0.0f32);
            if c < params.target {
                let gx = clear(Point::new(p.x + h, p.y)) - clear(Point::new(p.x - h, p.y));
                let gy = clear(Point::new(p.x, p.y + h)) - clear(Point::new(p.x, p.y - h));
                let g = (gx * gx + gy * gy).sqrt();
                if g > 1e-6 {
                    let k = (0.5 * (params.target - c)).min(0.1) / g;
                    push = (gx * k, gy * k);
                }
            }
            // Smooth: towards the middle of the neighbours.
            let mid = Point::new(
                0.5 * (pts[i - 1].x + pts[i + 1].x),
                0.5 * (pts[i - 1].y + pts[i + 1].y),
            );
            let pull = (0.25 * (mid.x - p.x), 0.25 * (mid.y - p.y));
            let floor = c.min(params.target) - 1e-3;
            let candidates = [
                Point::new(p.x + push.0 + pull.0, p.y + push.1 + pull.1),
                Point::new(p.x + push.0, p.y + push.1),
            ];
            for q in candidates {
                if q.is_finite() && q.distance(p) > 1e-6 && clear(q) >= floor {
                    moved = moved.max(q.distance(p));
                    pts[i] = q;
                    break;
                }
            }
        }
        if moved < 1e-3 {
            break;
        }
    }
    pts
}

/// Polyline length.
pub fn length(path: &[Point]) -> f32 {
    path.windows(2).map(|s| s[0].distance(s[1])).sum()
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_core::grid::GridBuf;

    #[test]
    fn centres_a_path_in_a_one_cell_aisle_and_keeps_its_ends() {
        let rows = "..........\n@@@@.@@@@@\n@@@@.@@@@@\n@@@@.@@@@@\n..........";
        let g = GridBuf::parse_rows(rows.as_bytes()).unwrap();
        // A path hugging the left wall of the aisle (x = 3.6 instead of 4).
        let path = [
            Point::new(0.0, 0.0),
            Point::new(3.6, 0.6),
            Point::new(3.6, 3.4),
            Point::new(9.0, 4.0),
        ];
        let out = fit(g.view(), &path, &FitParams::default());
        assert_eq!(out.first(), path.first());
        assert_eq!(out.last(), path.last());
        for p in out.iter().filter(|p| p.y > 1.5 && p.y < 2.5) {
            assert!((p.x - 4.0).abs() < 0.1, "{p:?}");
        }
        // Every point keeps at least the clearance it had, and the aisle points gain.
        let before = resample(&path, 0.25);
        let worst_before = before
            .iter()
            .map(|p| point_clearance(g.view(), *p, 2.0))
            .fold(f32::INFINITY, f32::min);
        let worst_after = out
            .iter()
            .map(|p| point_clearance(g.view(), *p, 2.0))
            .fold(f32::INFINITY, f32::min);
        assert!(
            worst_after > worst_before + 0.2,
            "{worst_before} -> {worst_after}"
        );
    }
}

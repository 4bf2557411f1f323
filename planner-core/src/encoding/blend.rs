//! The blended objective: path length plus a turning term and a clearance term.
//!
//! Length alone gives the shortest path, which grazes every obstacle corner it wraps; a
//! warehouse robot wants margin from shelves and few turns (a differential-drive robot
//! slows down or stops at each). The blended cost of a polyline is
//!
//! `length + turn_weight * sum over turns (angle + TURN_FIXED)
//!         + clearance_weight * sum over legs (integral of max(0, clearance - d(p)) ds
//!                                             + max of max(0, clearance - d(p)))`
//!
//! where `d(p)` is the distance from `p` to the nearest blocked cell ([`point_clearance`])
//! (see [`shortfall`]).
//! The collision rule is unchanged: the terms only rank valid paths. All weights zero is
//! [`Blend::LENGTH`], the papers' objective, and costs are then bit for bit the lengths.
//!
//! ```
//! use planner_core::encoding::blend::Blend;
//! use planner_core::geometry::Point;
//! use planner_core::grid::{Grid, words_for};
//!
//! let mut grid = Grid::<{ words_for(16, 16) }>::new(16, 16).unwrap();
//! grid.set_blocked(8, 4, true).unwrap();
//! let blend = Blend { clearance: 1.5, clearance_weight: 1.0, turn_weight: 0.0 };
//! // Cell centres are integer points: the row next to the blocked cell passes half a cell
//! // from it and pays for the missing clearance; four rows further, the same length is free.
//! let hugging = [Point::new(3.0, 5.0), Point::new(12.0, 5.0)];
//! let wide = [Point::new(3.0, 9.0), Point::new(12.0, 9.0)];
//! assert!(blend.path_cost(grid.view(), &hugging) > 9.5);
//! assert_eq!(blend.path_cost(grid.view(), &wide), 9.0);
//! ```

use crate::geometry::{Point, point_clearance, segment_clearance, segment_is_clear};
use crate::grid::GridRef;
use crate::path::PathView;

/// Turning cost of a turn besides its angle, in radians: a robot that stops to turn spends
/// about as long starting and stopping as turning this much more, and it makes one turn
/// cheaper than two of the same total angle.
pub const TURN_FIXED: f32 = 0.25;

/// Spacing of the clearance term's samples along a leg, in cells (the midpoint rule).
pub const CLEARANCE_STEP: f32 = 0.5;

/// Interior waypoints [`Blend::simplify`] tries to remove, in passes over the path.
const SIMPLIFY_PASSES: usize = 8;

/// Passes of [`Blend::polish`] over the path.
const POLISH_PASSES: usize = 16;

/// First and last step of [`Blend::polish`]'s moves, in cells (halved in between).
const POLISH_STEPS: (f32, f32) = (1.0, 1.0 / 64.0);

/// The weights of the blended objective (see the [module](self) docs).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Blend {
    /// Desired clearance from obstacles, in cells (of the grid planned on: on a map
    /// inflated by the robot's radius, the margin beyond the footprint).
    pub clearance: f32,
    /// Cost per cell of path per cell of missing clearance.
    pub clearance_weight: f32,
    /// Cost per radian of turning (and per [`TURN_FIXED`] of each turn), in cells.
    pub turn_weight: f32,
}

impl Blend {
    /// Length alone.
    pub const LENGTH: Blend = Blend {
        clearance: 0.0,
        clearance_weight: 0.0,
        turn_weight: 0.0,
    };

    /// Whether the cost is the length alone.
    pub fn is_length(&self) -> bool {
        self.turn_weight == 0.0 && !self.has_clearance()
    }

    /// Whether the clearance term counts.
    fn has_clearance(&self) -> bool {
        self.clearance > 0.0 && self.clearance_weight > 0.0
    }

    /// Whether every weight is finite and not negative.
    pub fn is_valid(&self) -> bool {
        [self.clearance, self.clearance_weight, self.turn_weight]
            .iter()
            .all(|v| v.is_finite() && *v >= 0.0)
    }

    /// The clearance term of the segment `a -> b` (weighted).
    pub fn leg_cost(&self, grid: GridRef<'_>, a: Point, b: Point) -> f32 {
        if !self.has_clearance() {
            return 0.0;
        }
        self.clearance_weight * shortfall(grid, a, b, self.clearance)
    }

    /// [`leg_cost`](Self::leg_cost) with the deepest point found exactly
    /// ([`segment_clearance`]) instead of among the samples: a final path's leg may pass a
    /// corner between two samples.
    fn leg_cost_exact(&self, grid: GridRef<'_>, a: Point, b: Point) -> f32 {
        if !self.has_clearance() || a == b {
            return 0.0;
        }
        let c = self.clearance;
        let (integral, deepest) = shortfall_parts(grid, a, b, c);
        let exact = c - segment_clearance(grid, a, b, c);
        self.clearance_weight * (integral + deepest.max(exact))
    }

    /// The turning term at `b` between `a -> b` and `b -> c` (weighted; 0 without a turn).
    pub fn turn_cost(&self, a: Point, b: Point, c: Point) -> f32 {
        if self.turn_weight == 0.0 {
            return 0.0;
        }
        match turn_angle(a, b, c) {
            Some(angle) => self.turn_weight * (angle + TURN_FIXED),
            None => 0.0,
        }
    }

    /// The blended cost of a polyline: its length plus both terms.
    pub fn path_cost(&self, grid: GridRef<'_>, path: &[Point]) -> f32 {
        let mut trace = Trace::new(*self);
        for &p in path {
            trace.push(grid, p);
        }
        trace.total()
    }

    /// Removes interior waypoints while that lowers the blended cost and the shortcut is
    /// clear (the blended counterpart of [`path::shortcut`](crate::path::shortcut), which
    /// would cut the margins away). A valid path stays valid.
    pub fn simplify(&self, grid: GridRef<'_>, path: &mut PathView) {
        for _ in 0..SIMPLIFY_PASSES {
            let mut removed = false;
            let mut i = 1;
            while i + 1 < path.len() {
                let (lo, hi) = (i.saturating_sub(2), (i + 2).min(path.len() - 1));
                let before = &path[lo..=hi];
                let mut after = [Point::new(0.0, 0.0); 4];
                let mut n = 0;
                for (k, p) in before.iter().enumerate() {
                    if lo + k != i {
                        after[n] = *p;
                        n += 1;
                    }
                }
                if segment_is_clear(grid, path[i - 1], path[i + 1])
                    && self.window_cost(grid, &after[..n]) < self.window_cost(grid, before)
                {
                    path.remove(i);
                    removed = true;
                } else {
                    i += 1;
                }
            }
            if !removed {
                break;
            }
        }
    }

    /// Moves interior waypoints, one at a time, in eight directions by steps from
    /// one cell down to 1/64 cell (halved in between), wherever that lowers the blended cost and keeps
    /// both legs clear: a swarm's waypoints settle near the right place, and the last
    /// fraction of a cell is where a corner is grazed or cleared. Each waypoint then moves onto
    /// the half-cell lattice (an aisle's centre line) where that costs no more. A valid path
    /// stays valid.
    pub fn polish(&self, grid: GridRef<'_>, path: &mut PathView) {
        const D: f32 = core::f32::consts::FRAC_1_SQRT_2;
        const DIRS: [(f32, f32); 8] = [
            (1.0, 0.0),
            (-1.0, 0.0),
            (0.0, 1.0),
            (0.0, -1.0),
            (D, D),
            (-D, D),
            (D, -D),
            (-D, -D),
        ];
        for _ in 0..POLISH_PASSES {
            let mut moved = false;
            for i in 1..path.len().saturating_sub(1) {
                let (lo, hi) = (i.saturating_sub(2), (i + 2).min(path.len() - 1));
                let mut window = [Point::new(0.0, 0.0); 5];
                let n = hi - lo + 1;
                window[..n].copy_from_slice(&path[lo..=hi]);
                let at = i - lo;
                let mut cost = self.moved_cost(grid, &window[..n], at);
                let mut step = POLISH_STEPS.0;
                while step >= POLISH_STEPS.1 {
                    let p = window[at];
                    let mut best: Option<(f32, Point)> = None;
                    for (dx, dy) in DIRS {
                        let q = Point::new(p.x + dx * step, p.y + dy * step);
                        window[at] = q;
                        let c = self.moved_cost(grid, &window[..n], at);
                        if c < best.map_or(cost, |b| b.0)
                            && segment_is_clear(grid, window[at - 1], q)
                            && segment_is_clear(grid, q, window[at + 1])
                        {
                            best = Some((c, q));
                        }
                    }
                    match best {
                        Some((c, q)) => {
                            window[at] = q;
                            cost = c;
                            moved = true;
                        }
                        None => {
                            window[at] = p;
                            step *= 0.5;
                        }
                    }
                }
                // Aisle centres lie on the half-cell lattice; the steps stop 1/64 short.
                let p = window[at];
                let half = |v: f32| libm::roundf(v * 2.0) * 0.5;
                for q in [
                    Point::new(half(p.x), half(p.y)),
                    Point::new(half(p.x), p.y),
                    Point::new(p.x, half(p.y)),
                ] {
                    window[at] = q;
                    if q != p
                        && self.moved_cost(grid, &window[..n], at) <= cost
                        && segment_is_clear(grid, window[at - 1], q)
                        && segment_is_clear(grid, q, window[at + 1])
                    {
                        break;
                    }
                    window[at] = p;
                }
                path[i] = window[at];
            }
            if !moved {
                break;
            }
        }
    }

    /// The part of [`window_cost`](Self::window_cost) that moving `window[at]` changes: its
    /// two legs and the turns at it and its neighbours.
    fn moved_cost(&self, grid: GridRef<'_>, window: &[Point], at: usize) -> f32 {
        let (p, prev, next) = (window[at], window[at - 1], window[at + 1]);
        let legs = prev.distance(p)
            + p.distance(next)
            + self.leg_cost_exact(grid, prev, p)
            + self.leg_cost_exact(grid, p, next);
        let turns: f32 = window
            .windows(3)
            .enumerate()
            .filter(|(k, _)| (at - 1..=at + 1).contains(&(k + 1)))
            .map(|(_, w)| self.turn_cost(w[0], w[1], w[2]))
            .sum();
        legs + turns
    }

    /// The cost of a window of a path: its legs and the turns at its interior waypoints
    /// (the turns at its ends belong to the neighbouring windows); legs exactly
    /// ([`leg_cost_exact`](Self::leg_cost_exact)).
    fn window_cost(&self, grid: GridRef<'_>, window: &[Point]) -> f32 {
        let legs: f32 = window
            .windows(2)
            .map(|w| w[0].distance(w[1]) + self.leg_cost_exact(grid, w[0], w[1]))
            .sum();
        let turns: f32 = window
            .windows(3)
            .map(|w| self.turn_cost(w[0], w[1], w[2]))
            .sum();
        legs + turns
    }
}

impl Default for Blend {
    fn default() -> Self {
        Blend::LENGTH
    }
}

/// The blended cost of a polyline fed point by point (repeated points are skipped).
#[derive(Clone, Copy, Debug)]
pub struct Trace {
    blend: Blend,
    last: Option<Point>,
    before: Option<Point>,
    length: f32,
    extra: f32,
}

impl Trace {
    /// An empty polyline.
    pub const fn new(blend: Blend) -> Self {
        Trace {
            blend,
            last: None,
            before: None,
            length: 0.0,
            extra: 0.0,
        }
    }

    /// Appends `p`.
    #[inline]
    pub fn push(&mut self, grid: GridRef<'_>, p: Point) {
        if let Some(last) = self.last {
            // 0 for a repeated point, which `push_extra` then skips.
            self.length += last.distance(p);
        }
        self.push_extra(grid, p);
    }

    /// Appends `p` whose leg length the caller counts itself: only the terms accrue.
    #[inline]
    pub fn push_extra(&mut self, grid: GridRef<'_>, p: Point) {
        let Some(last) = self.last else {
            self.last = Some(p);
            return;
        };
        if last == p {
            return;
        }
        if let Some(before) = self.before {
            self.extra += self.blend.turn_cost(before, last, p);
        }
        self.extra += self.blend.leg_cost(grid, last, p);
        self.before = Some(last);
        self.last = Some(p);
    }

    /// The terms so far (without the length).
    pub fn extra(&self) -> f32 {
        self.extra
    }

    /// Length plus terms so far.
    pub fn total(&self) -> f32 {
        self.length + self.extra
    }
}

/// The turning angle at `b` in radians, `None` where the path goes straight on (or a leg
/// has no length).
pub fn turn_angle(a: Point, b: Point, c: Point) -> Option<f32> {
    let (ux, uy) = (b.x - a.x, b.y - a.y);
    let (vx, vy) = (c.x - b.x, c.y - b.y);
    let cross = ux * vy - uy * vx;
    let dot = ux * vx + uy * vy;
    if (ux == 0.0 && uy == 0.0) || (vx == 0.0 && vy == 0.0) || (cross == 0.0 && dot > 0.0) {
        return None;
    }
    Some(libm::atan2f(libm::fabsf(cross), dot))
}

/// The missing clearance along `a -> b`: `integral of max(0, clearance - d(p)) ds` (by the
/// midpoint rule at [`CLEARANCE_STEP`]) plus its largest value once. The integral alone has
/// no slope where the path just touches the desired clearance (the part within it shrinks to
/// nothing), so plans would settle short of it; the deepest point keeps a slope there.
pub fn shortfall(grid: GridRef<'_>, a: Point, b: Point, clearance: f32) -> f32 {
    let (integral, deepest) = shortfall_parts(grid, a, b, clearance);
    integral + deepest
}

/// [`shortfall`]'s integral and its deepest sample, apart.
fn shortfall_parts(grid: GridRef<'_>, a: Point, b: Point, clearance: f32) -> (f32, f32) {
    let length = a.distance(b);
    if length.is_nan() || length <= 0.0 || clearance.is_nan() || clearance <= 0.0 {
        return (0.0, 0.0);
    }
    let n = libm::ceilf(length / CLEARANCE_STEP).max(1.0);
    let step = 1.0 / n;
    let (mut sum, mut deepest) = (0.0f32, 0.0f32);
    let mut k = 0.5;
    while k < n {
        let t = k * step;
        let p = Point::new(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t);
        let missing = clearance - point_clearance(grid, p, clearance);
        sum += missing;
        deepest = deepest.max(missing);
        k += 1.0;
    }
    (sum * length * step, deepest)
}

/// The share of a path's length (0 to 1) that passes closer than `clearance` to an
/// obstacle, sampled as [`shortfall`] is.
pub fn share_within(grid: GridRef<'_>, path: &[Point], clearance: f32) -> f32 {
    let (mut within, mut total) = (0.0f32, 0.0f32);
    for w in path.windows(2) {
        let length = w[0].distance(w[1]);
        if length.is_nan() || length <= 0.0 {
            continue;
        }
        let n = libm::ceilf(length / CLEARANCE_STEP).max(1.0);
        let mut k = 0.5;
        while k < n {
            let t = k / n;
            let p = Point::new(
                w[0].x + (w[1].x - w[0].x) * t,
                w[0].y + (w[1].y - w[0].y) * t,
            );
            if point_clearance(grid, p, clearance) < clearance {
                within += length / n;
            }
            k += 1.0;
        }
        total += length;
    }
    if total > 0.0 { within / total } else { 0.0 }
}

/// Total turning angle of a path in radians.
pub fn total_turning(path: &[Point]) -> f32 {
    let mut kept: [Option<Point>; 2] = [None, None];
    let mut total = 0.0;
    for &p in path {
        match kept {
            [_, Some(last)] if last == p => continue,
            [Some(a), Some(b)] => total += turn_angle(a, b, p).unwrap_or(0.0),
            _ => {}
        }
        kept = [kept[1], Some(p)];
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};
    use crate::path::Path;

    type G = Grid<{ words_for(16, 16) }>;

    fn open() -> G {
        G::new(16, 16).unwrap()
    }

    #[test]
    fn length_alone_costs_the_length() {
        let g = open();
        let p = [
            Point::new(0.5, 0.5),
            Point::new(5.5, 3.5),
            Point::new(9.5, 12.5),
        ];
        assert_eq!(
            Blend::LENGTH.path_cost(g.view(), &p),
            crate::path::length(&p)
        );
        assert!(Blend::LENGTH.is_length());
    }

    #[test]
    fn a_right_angle_costs_its_angle_and_the_fixed_part() {
        let b = Blend {
            turn_weight: 2.0,
            ..Blend::LENGTH
        };
        let (a, m, c) = (
            Point::new(1.0, 1.0),
            Point::new(4.0, 1.0),
            Point::new(4.0, 5.0),
        );
        let want = 2.0 * (core::f32::consts::FRAC_PI_2 + TURN_FIXED);
        assert!((b.turn_cost(a, m, c) - want).abs() < 1e-6);
        assert_eq!(b.turn_cost(a, m, Point::new(9.0, 1.0)), 0.0);
        assert!((total_turning(&[a, m, m, c]) - core::f32::consts::FRAC_PI_2).abs() < 1e-6);
    }

    #[test]
    fn shortfall_is_the_missing_clearance_along_the_leg() {
        // One blocked cell at (8, 8) (the square 7.5..8.5): row 9 passes half a cell from it.
        let mut g = open();
        g.set_blocked(8, 8, true).unwrap();
        let far = shortfall(g.view(), Point::new(3.0, 12.0), Point::new(12.0, 12.0), 2.0);
        assert!(far.abs() < 1e-6, "{far}");
        let near = shortfall(g.view(), Point::new(3.0, 9.0), Point::new(12.0, 9.0), 2.0);
        assert!(near > 1.0, "{near}");
        // Within 2 cells where the horizontal gap is under sqrt(4 - 0.25): 4.87 of 9 cells.
        let share = share_within(
            g.view(),
            &[Point::new(3.0, 9.0), Point::new(12.0, 9.0)],
            2.0,
        );
        assert!((share - 4.87 / 9.0).abs() < 0.06, "{share}");
        assert!(
            !Blend {
                clearance: f32::NAN,
                ..Blend::LENGTH
            }
            .is_valid()
        );
    }

    #[test]
    fn simplify_removes_wiggles_but_keeps_margins() {
        let g = open();
        let b = Blend {
            turn_weight: 0.5,
            ..Blend::LENGTH
        };
        let mut p: Path<8> = Path::new();
        for q in [(0.0, 0.0), (4.0, 0.1), (8.0, 0.0), (12.0, 0.1), (15.0, 0.0)] {
            p.push(Point::new(q.0, q.1)).unwrap();
        }
        b.simplify(g.view(), &mut p);
        assert_eq!(&p[..], &[Point::new(0.0, 0.0), Point::new(15.0, 0.0)]);
        // A detour that buys clearance stays when clearance is worth it.
        let mut g = open();
        for x in 4..12 {
            g.set_blocked(x, 4, true).unwrap();
        }
        let b = Blend {
            clearance: 2.0,
            clearance_weight: 4.0,
            turn_weight: 0.1,
        };
        let mut p: Path<8> = Path::new();
        for q in [(0.0, 6.0), (4.0, 7.0), (12.0, 7.0), (15.0, 6.0)] {
            p.push(Point::new(q.0, q.1)).unwrap();
        }
        let before = b.path_cost(g.view(), &p);
        b.simplify(g.view(), &mut p);
        assert!(b.path_cost(g.view(), &p) <= before);
        assert_eq!(p.len(), 4);
    }

    #[test]
    fn polish_moves_waypoints_off_obstacles_and_keeps_legs_clear() {
        let mut g = open();
        g.set_blocked(8, 8, true).unwrap();
        let b = Blend {
            clearance: 2.0,
            clearance_weight: 4.0,
            turn_weight: 0.1,
        };
        let mut p: Path<8> = Path::new();
        for q in [(2.0, 9.0), (8.0, 9.0), (14.0, 9.0)] {
            p.push(Point::new(q.0, q.1)).unwrap();
        }
        let before = (
            b.path_cost(g.view(), &p),
            crate::path::clearance(g.view(), &p, 5.0),
        );
        b.polish(g.view(), &mut p);
        let after = (
            b.path_cost(g.view(), &p),
            crate::path::clearance(g.view(), &p, 5.0),
        );
        assert!(after.0 < before.0, "{before:?} {after:?}");
        assert!(after.1 > before.1 + 0.5, "{before:?} {after:?} {p:?}");
        assert!(p.windows(2).all(|w| segment_is_clear(g.view(), w[0], w[1])));
        assert_eq!((p[0], p[2]), (Point::new(2.0, 9.0), Point::new(14.0, 9.0)));
    }
}

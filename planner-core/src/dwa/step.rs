//! One control step: the dynamic window, the roll-out of each sample and the two passes of
//! the scoring (see the module documentation).

use super::{Command, Dwa, DwaError, DwaState, DynamicDisc, Event, Mode, wrap};
use crate::geometry::{Point, advance, nearest_ahead, point_clearance};
use crate::grid::GridRef;
use crate::math::{clamp, lesser};
use core::f32::consts::PI;

/// Speeds below this (cells/s) count as standing.
const STANDING_V: f32 = 1e-3;

/// Bearing error to the carrot (rad) above which turning in place may be chosen.
const ROTATE_IN_PLACE_ABOVE: f32 = core::f32::consts::FRAC_PI_4;

/// Clearance (cells) below which a roll-out counts as touching: a small safety margin over
/// the footprint radius, so that discretisation of the roll-out never lets the robot scrape.
const CONTACT_MARGIN: f32 = 0.02;

/// How much closer than it is (cells) a robot inside its static margin may come per step.
const MARGIN_SLIP: f32 = 0.01;

/// Smallest spans of the min-max normalisation (rad, cells, cells): see [`Range::norm`].
const FLOOR_HEADING: f32 = 0.2;
const FLOOR_DIST: f32 = 0.05;
const FLOOR_FIT: f32 = 0.5;

/// Terms of one sample, before normalisation.
#[derive(Clone, Copy)]
struct Terms {
    heading: f32,
    dist: f32,
    vel: f32,
    fit: f32,
}

/// Windows up to this many samples keep pass 1's terms for pass 2 (on the stack, 2 KiB)
/// instead of rolling every sample out twice; larger windows roll out twice. (The default
/// window has 7 x 15 = 105 samples.)
const CACHED_SAMPLES: usize = 128;

/// Pass 1's terms by sample index (`None`: inadmissible), when the window fits.
type TermCache = [Option<Terms>; CACHED_SAMPLES];

#[derive(Clone, Copy)]
struct Range {
    lo: f32,
    hi: f32,
}

impl Range {
    const EMPTY: Range = Range {
        lo: f32::INFINITY,
        hi: f32::NEG_INFINITY,
    };
    fn add(&mut self, v: f32) {
        self.lo = self.lo.min(v);
        self.hi = self.hi.max(v);
    }
    /// Min-max normalisation; 0 when the term is constant over the window. The span is at
    /// least `floor`, so differences too small to matter (a few hundredths of a cell in a
    /// narrow window) are not blown up to the full weight of the term.
    fn norm(&self, v: f32, floor: f32) -> f32 {
        let span = (self.hi - self.lo).max(floor);
        if span > 1e-9 {
            (v - self.lo) / span
        } else {
            0.0
        }
    }
}

/// What a control step sees: the robot, the map, the dynamic discs and the global path.
pub(super) struct Scene<'a> {
    state: &'a DwaState,
    pub(super) grid: GridRef<'a>,
    pub(super) discs: &'a [DynamicDisc],
    path: &'a [Point],
}

/// The dynamic window: the velocities reachable within `dt` under the acceleration limits,
/// intersected with the velocity limits, sampled on a `v_samples x w_samples` lattice.
struct Window {
    v: (f32, f32),
    w: (f32, f32),
    v_samples: u16,
    w_samples: u16,
}

impl Window {
    /// The window under the limits, forward speed at most `v_cap` (the protective field's).
    fn new(c: &super::DwaConfig, state: &DwaState, v_cap: f32) -> Self {
        let v_lo = (state.v - c.acc_v * c.dt).max(c.v_min);
        let v_hi = (state.v + c.acc_v * c.dt).min(c.v_max).min(v_cap);
        let w_lo = (state.w - c.acc_w * c.dt).max(-c.w_max);
        let w_hi = (state.w + c.acc_w * c.dt).min(c.w_max);
        let v = if v_lo <= v_hi {
            (v_lo, v_hi)
        } else {
            // Outside the limits (e.g. reversing): the reachable value nearest to them.
            let v = v_hi.max(c.v_min).min(v_lo);
            (v, v)
        };
        let w = if w_lo <= w_hi {
            (w_lo, w_hi)
        } else {
            let w = w_hi.max(-c.w_max).min(w_lo);
            (w, w)
        };
        Window {
            v,
            w,
            v_samples: c.v_samples,
            w_samples: c.w_samples,
        }
    }

    /// Speed sample `i`.
    fn v(&self, i: u16) -> f32 {
        sample(self.v, self.v_samples, i)
    }

    /// Yaw-rate sample `j`.
    fn w(&self, j: u16) -> f32 {
        sample(self.w, self.w_samples, j)
    }

    /// Whether pass 1's terms fit a [`TermCache`].
    fn cached(&self) -> bool {
        self.v_samples as usize * self.w_samples as usize <= CACHED_SAMPLES
    }

    /// The [`TermCache`] index of sample `(i, j)`.
    fn index(&self, i: u16, j: u16) -> usize {
        i as usize * self.w_samples as usize + j as usize
    }
}

/// Sample `i` of `n` spread evenly over `[lo, hi]` (the middle when `n` is 1).
fn sample((lo, hi): (f32, f32), n: u16, i: u16) -> f32 {
    if n <= 1 {
        0.5 * (lo + hi)
    } else {
        lo + (hi - lo) * i as f32 / (n - 1) as f32
    }
}

/// Pass 1's result: ranges of the terms over the admissible samples, over all of them and
/// over the moving ones (contact-free, not standing), and how many there are of each.
struct Survey {
    ranges: [Range; 4],
    ranges_moving: [Range; 4],
    admissible: u32,
    admissible_moving: u32,
}

/// [`DwaError`] for a non-finite state, an empty or non-finite path, or a bad disc.
fn check_inputs(state: &DwaState, discs: &[DynamicDisc], path: &[Point]) -> Result<(), DwaError> {
    if !state.is_finite() {
        return Err(DwaError::InvalidState);
    }
    if path.is_empty() || path.iter().any(|p| !p.is_finite()) {
        return Err(DwaError::InvalidPath);
    }
    if discs.iter().any(|d| {
        !(d.x.is_finite()
            && d.y.is_finite()
            && d.vx.is_finite()
            && d.vy.is_finite()
            && d.r.is_finite()
            && d.r >= 0.0)
    }) {
        return Err(DwaError::InvalidObstacle);
    }
    Ok(())
}

impl Dwa {
    /// One control step: the command to apply for `dt`.
    pub fn step(
        &mut self,
        state: &DwaState,
        grid: GridRef<'_>,
        discs: &[DynamicDisc],
        path: &[Point],
    ) -> Result<Command, DwaError> {
        let c = self.config;
        c.validate()?;
        check_inputs(state, discs, path)?;
        self.clock += c.dt;
        let pos = state.position();
        // In narrow places the carrot comes closer (down to half a cell in a one-cell
        // aisle), so that the robot follows the path to a corner before turning.
        self.lookahead = clamp(point_clearance(grid, pos, c.lookahead), 0.5, c.lookahead);
        let (carrot, cross_track) = self.carrot(pos, path);
        let goal = path[path.len() - 1];
        let mut cmd = Command {
            v: 0.0,
            w: 0.0,
            mode: Mode::Track,
            event: Event::None,
            admissible: 0,
            samples: 0,
            score: 0.0,
            carrot,
            cross_track,
        };
        if pos.distance(goal) <= c.goal_tolerance {
            cmd.mode = Mode::Arrived;
            self.anchor = pos;
            self.anchor_time = self.clock;
            return Ok(cmd);
        }

        let scene = Scene {
            state,
            grid,
            discs,
            path,
        };
        self.floor = self.static_floor(grid, pos);
        let window = Window::new(&c, state, self.field_limit(state, discs));
        let mut cache: TermCache = [None; CACHED_SAMPLES];
        let survey = self.survey(&scene, &window, &mut cache);
        // A standing sample's roll-out ends where the robot is, on the path: it would win
        // the curvefit term whenever the robot is slightly off the path. Standing (turning in
        // place) is therefore a choice only when the robot faces away from the path or when
        // no moving sample is admissible without contact (then all samples compete).
        let facing = wrap(libm::atan2f(carrot.y - pos.y, carrot.x - pos.x) - state.theta).abs();
        let moving_only = survey.admissible_moving > 0 && facing < ROTATE_IN_PLACE_ABOVE;
        let ranges = if moving_only {
            survey.ranges_moving
        } else {
            survey.ranges
        };
        cmd.samples = c.v_samples as u32 * c.w_samples as u32;
        cmd.admissible = survey.admissible;

        if survey.admissible > 0 {
            (cmd.score, cmd.v, cmd.w) = self.best(&scene, &window, &cache, &ranges, moving_only);
            // A window whose best choice is to stand still without turning is a dead end
            // too: fall through to the recovery rules below.
            if cmd.v.abs() > 1e-3 || cmd.w.abs() > 1e-3 {
                self.rotations = 0;
            } else {
                self.recover(state, &scene, carrot, &mut cmd);
            }
        } else {
            self.recover(state, &scene, carrot, &mut cmd);
        }
        cmd.event = self.supervise(pos, &cmd);
        Ok(cmd)
    }

    /// This step's static margin: [`super::DwaConfig::margin`], or less when the robot is
    /// already closer (it may come [`MARGIN_SLIP`] closer, never touch).
    fn static_floor(&self, grid: GridRef<'_>, pos: Point) -> f32 {
        let c = &self.config;
        if c.margin <= 0.0 {
            return 0.0;
        }
        let now = point_clearance(grid, pos, c.radius + c.margin + 1.0) - c.radius;
        clamp(now - CONTACT_MARGIN - MARGIN_SLIP, 0.0, c.margin)
    }

    /// The protective field's speed limit: `v_max` without a field or beyond `protect_slow`
    /// of every disc in front (not behind the robot's axle line), 0 inside `protect_stop`.
    fn field_limit(&self, state: &DwaState, discs: &[DynamicDisc]) -> f32 {
        let c = &self.config;
        if c.protect_slow <= 0.0 {
            return c.v_max;
        }
        let (sin_th, cos_th) = libm::sincosf(state.theta);
        let gap = discs
            .iter()
            .filter(|d| (d.x - state.x) * cos_th + (d.y - state.y) * sin_th >= 0.0)
            .map(|d| state.position().distance(Point::new(d.x, d.y)) - d.r - c.radius)
            .fold(f32::INFINITY, lesser);
        let span = c.protect_slow - c.protect_stop;
        let share = if span > 0.0 {
            (gap - c.protect_stop) / span
        } else if gap > c.protect_stop {
            1.0
        } else {
            0.0
        };
        c.v_max * clamp(share, 0.0, 1.0)
    }

    /// Pass 1: rolls every sample of the window out, keeping the terms in `cache` when the
    /// window fits (evaluation is pure, so pass 2 reads exactly what it would recompute).
    fn survey(&self, scene: &Scene<'_>, window: &Window, cache: &mut TermCache) -> Survey {
        let mut s = Survey {
            ranges: [Range::EMPTY; 4],
            ranges_moving: [Range::EMPTY; 4],
            admissible: 0,
            admissible_moving: 0,
        };
        let cached = window.cached();
        for i in 0..window.v_samples {
            let v = window.v(i);
            for j in 0..window.w_samples {
                let w = window.w(j);
                let terms = self.evaluate(scene.state, v, w, scene.grid, scene.discs, scene.path);
                if cached {
                    cache[window.index(i, j)] = terms;
                }
                if let Some(t) = terms {
                    s.admissible += 1;
                    let terms = [t.heading, t.dist, t.vel, t.fit];
                    for (r, x) in s.ranges.iter_mut().zip(terms) {
                        r.add(x);
                    }
                    if v.abs() >= STANDING_V && t.dist > 0.0 {
                        s.admissible_moving += 1;
                        for (r, x) in s.ranges_moving.iter_mut().zip(terms) {
                            r.add(x);
                        }
                    }
                }
            }
        }
        s
    }

    /// Pass 2: the best normalised score `(score, v, w)` (ties keep the first sample), among
    /// the moving contact-free samples only when `moving_only`.
    fn best(
        &self,
        scene: &Scene<'_>,
        window: &Window,
        cache: &TermCache,
        ranges: &[Range; 4],
        moving_only: bool,
    ) -> (f32, f32, f32) {
        let c = &self.config;
        let cached = window.cached();
        let mut best = (f32::NEG_INFINITY, 0.0, 0.0);
        for i in 0..window.v_samples {
            let v = window.v(i);
            for j in 0..window.w_samples {
                let w = window.w(j);
                if moving_only && v.abs() < STANDING_V {
                    continue;
                }
                let terms = if cached {
                    cache[window.index(i, j)]
                } else {
                    self.evaluate(scene.state, v, w, scene.grid, scene.discs, scene.path)
                };
                if let Some(t) = terms {
                    if moving_only && t.dist <= 0.0 {
                        continue;
                    }
                    let g = c.heading * ranges[0].norm(t.heading, FLOOR_HEADING)
                        + c.dist * ranges[1].norm(t.dist, FLOOR_DIST)
                        + c.velocity * ranges[2].norm(t.vel, 0.0)
                        + c.curvefit * (1.0 - ranges[3].norm(t.fit, FLOOR_FIT));
                    if g > best.0 {
                        best = (g, v, w);
                    }
                }
            }
        }
        best
    }

    /// The robot's place on the path, its carrot and the cross-track distance. Tracking is
    /// monotone along the path: the projection is searched from the last one on, over a
    /// bounded stretch of arc (so a later leg of the path that passes nearby, as in a U-turn,
    /// is not taken for the current one).
    fn carrot(&mut self, pos: Point, path: &[Point]) -> (Point, f32) {
        if path.len() == 1 {
            return (path[0], pos.distance(path[0]));
        }
        if self.segment > path.len() - 2 || !self.seg_t.is_finite() {
            self.segment = 0;
            self.seg_t = 0.0;
        }
        let span = self.config.lookahead + self.config.v_max * self.config.predict + 1.0;
        let (d, s, t) = nearest_ahead(pos, path, self.segment, self.seg_t, span);
        self.segment = s;
        self.seg_t = t;
        (advance(path, s, t, self.lookahead), d)
    }

    /// Rolls `(v, w)` out; `None` when inadmissible.
    // The scene's parts as separate arguments: behind a `&Scene` the roll-out loop cost 0.3%
    // more instructions on a Cortex-M4.
    fn evaluate(
        &self,
        state: &DwaState,
        v: f32,
        w: f32,
        grid: GridRef<'_>,
        discs: &[DynamicDisc],
        path: &[Point],
    ) -> Option<Terms> {
        let c = self.config;
        let steps = libm::ceilf(c.predict / c.dt) as u32;
        let (mut x, mut y, mut th) = (state.x, state.y, state.theta);
        let mut min_clear = c.clearance_cap;
        let mut arc = 0.0f32;
        let standing = v.abs() < 1e-3;
        let mut contact = false;
        // The current pose (t = 0) counts for standing samples only; a robot already too
        // close to something must be able to move away.
        // Static clearance is counted beyond this step's margin.
        let (reach, inner) = (
            c.clearance_cap + c.radius + self.floor,
            c.radius + self.floor,
        );
        if standing {
            let cl = point_clearance(grid, Point::new(x, y), reach) - inner;
            min_clear = min_clear.min(cl.max(0.0));
        }
        // The heading turns by the same angle every step, so its cosine and sine are rotated
        // along instead of computed per step: libm's `sinf`/`cosf` work in `f64`, which a
        // Cortex-M4F emulates in software (they were two thirds of a control step there).
        // Over a roll-out (30 steps by default) the rotation drifts by a few ulps.
        let (turn_sin, turn_cos) = libm::sincosf(w * c.dt);
        let (mut sin_th, mut cos_th) = libm::sincosf(th);
        for k in 1..=steps {
            th += w * c.dt;
            (cos_th, sin_th) = (
                cos_th * turn_cos - sin_th * turn_sin,
                sin_th * turn_cos + cos_th * turn_sin,
            );
            x += v * cos_th * c.dt;
            y += v * sin_th * c.dt;
            arc += v.abs() * c.dt;
            let t = k as f32 * c.dt;
            let p = Point::new(x, y);
            let mut cl = point_clearance(grid, p, reach) - inner;
            if !standing && t <= c.dynamic_horizon {
                for d in discs {
                    let q = Point::new(d.x + d.vx * t, d.y + d.vy * t);
                    let dc = p.distance(q) - d.r - c.radius;
                    // A moving disc keeps coming while the robot brakes: meeting one within
                    // the horizon is never admissible.
                    if dc <= CONTACT_MARGIN && d.vx * d.vx + d.vy * d.vy > 0.0025 {
                        return None;
                    }
                    cl = lesser(cl, dc);
                }
            }
            if cl <= CONTACT_MARGIN {
                // Contact: admissible only if the robot can brake before it.
                let brake = v * v / (2.0 * c.acc_v);
                if brake + 0.02 < arc - v.abs() * c.dt {
                    min_clear = 0.0;
                    contact = true;
                    break;
                }
                return None;
            }
            min_clear = lesser(min_clear, cl);
            if standing && w.abs() < 1e-6 {
                break;
            }
        }
        // The carrot of this sample: the roll-out's end projected onto the path ahead of the
        // robot, then `lookahead` further along it.
        let end = Point::new(x, y);
        let (fit, carrot) = if path.len() == 1 {
            (end.distance(path[0]), path[0])
        } else {
            let span = c.v_max * c.predict + c.lookahead + 1.0;
            let (d, s, t) = nearest_ahead(end, path, self.segment, self.seg_t, span);
            (d, advance(path, s, t, self.lookahead))
        };
        let bearing = libm::atan2f(carrot.y - y, carrot.x - x);
        let heading = if end.distance(carrot) < 1e-3 {
            PI
        } else {
            PI - wrap(bearing - th).abs()
        };
        Some(Terms {
            heading,
            dist: min_clear,
            // Speed towards a contact earns nothing (among such samples the slowest wins).
            vel: if contact { 0.0 } else { v },
            fit,
        })
    }
}

//! Dynamic Window Approach local planner (SPEC section 5, seed 004).
//!
//! Units: **cells and seconds**. One cell is the map's resolution; the defaults assume the
//! common 1 m cell of warehouse grid maps, so `v_max = 1.0` cell/s is 1 m/s. Poses use the
//! map's frame (SPEC section 1): `x` to the right, `y` **down**, `theta` measured from `+x`
//! towards `+y` (clockwise on screen), so `x += v cos(theta) dt`, `y += v sin(theta) dt`.
//!
//! Each control step samples the dynamic window (velocities reachable within `dt` under the
//! acceleration limits, intersected with the velocity limits) on a regular
//! `v_samples x w_samples` lattice, rolls every sample out for `predict` seconds and scores
//! the admissible ones with
//!
//! `G(v, w) = sigma [eps heading + tau dist + gamma vel + kappa curvefit]`
//!
//! - `heading`: `pi - |angle from the rolled-out end heading to the sample's carrot|`; each
//!   sample has its own carrot: the roll-out's end is projected onto the stretch of the
//!   global path ahead of the robot, and the carrot is `lookahead` cells further along the
//!   path from there (a carrot fixed just ahead of the robot rewards arcs that circle round
//!   it);
//! - `dist`: smallest clearance (distance from the footprint's rim to a blocked cell or a
//!   dynamic disc) along the roll-out, capped at `clearance_cap`;
//! - `vel`: the forward speed `v` (0 for a roll-out that ends in a contact it can brake
//!   before);
//! - `curvefit`: distance from the roll-out's end to the global path polyline, the stretch
//!   ahead of the robot (smaller is better, so it enters as `max - value`).
//!
//! **Normalisation**: min-max over the admissible samples of the window,
//! `(x - min) / max(max - min, floor)`, each term in `[0, 1]` (a term that is constant over the
//! window contributes 0; the floors, 0.2 rad for heading, 0.05 cell for dist and 0.5 cell for
//! curvefit, keep differences too small to matter from counting fully when the window is
//! narrow, e.g. when starting from standstill). `sigma` is a monotone smoothing and does not change the argmax, so it is
//! the identity here. The min and max need a first pass over the window, the choice a second
//! one: samples are iterated, never stored, so memory is fixed and no allocator is needed.
//!
//! A sample is **admissible** when its roll-out touches no blocked cell and no dynamic disc,
//! or when it does but the robot can still brake before the contact (Fox et al.'s rule,
//! `v^2 / (2 a) < arc length to the contact`); meeting a moving disc is never admissible
//! (it keeps coming while the robot brakes). Dynamic discs move with their velocity during
//! the roll-out and are considered for `dynamic_horizon` seconds only; a robot standing
//! still is never blamed for a disc walking into it.
//!
//! **Standing samples** (`v = 0`, turning in place) end where the robot is, which the
//! curvefit term rewards whenever the robot is a little off the path; they compete only when
//! the robot faces more than 45 degrees away from its carrot or when no moving sample is
//! admissible with a contact-free roll-out (only contact-free moving samples compete when
//! standing is excluded).
//!
//! Safety rules around the scoring:
//! - **anti-stuck**: when no sample is admissible the robot brakes; standing, it rotates in
//!   place towards the carrot (a disc footprint can always turn), and when it has turned
//!   `recovery_rotations` times without finding a way it backs off at `backoff_speed` if the
//!   cells behind are clear;
//! - **progress checker**: when the robot has not moved `progress_distance` within
//!   `progress_timeout` seconds, the step reports [`Event::Stuck`] (once per timeout);
//! - **oscillation counter**: sign flips of `w` (above `oscillation_w_eps`) and of `v`
//!   are counted; `oscillation_flips` flips within `oscillation_window` seconds report
//!   [`Event::Oscillation`].
//!
//! Bad input (non-finite state, parameters, path or discs, an empty path) is a [`DwaError`];
//! nothing here panics or allocates.

use crate::geometry::Point;
use crate::grid::GridRef;
use crate::math::{at_least_zero, clamp, lesser, sqrt};
use core::f32::consts::PI;

/// Speeds below this (cells/s) count as standing.
const STANDING_V: f32 = 1e-3;

/// Bearing error to the carrot (rad) above which turning in place may be chosen.
const ROTATE_IN_PLACE_ABOVE: f32 = core::f32::consts::FRAC_PI_4;

/// Clearance (cells) below which a roll-out counts as touching: a small safety margin over
/// the footprint radius, so that discretisation of the roll-out never lets the robot scrape.
const CONTACT_MARGIN: f32 = 0.02;

/// Smallest spans of the min-max normalisation (rad, cells, cells): see [`Range::norm`].
const FLOOR_HEADING: f32 = 0.2;
const FLOOR_DIST: f32 = 0.05;
const FLOOR_FIT: f32 = 0.5;

/// Parameters of the local planner (cells, seconds, radians).
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DwaConfig {
    /// Control period and roll-out step (s). Default 0.1.
    pub dt: f32,
    /// Roll-out horizon (s). Default 3.0.
    pub predict: f32,
    /// Forward speed limit (cells/s). Default 1.0 (1 m/s on 1 m cells).
    pub v_max: f32,
    /// Lowest speed the sampler uses (cells/s, 0 = no reversing in normal driving).
    pub v_min: f32,
    /// Yaw-rate limit (rad/s). Default 1.2.
    pub w_max: f32,
    /// Linear acceleration limit (cells/s^2). Default 1.0.
    pub acc_v: f32,
    /// Yaw acceleration limit (rad/s^2). Default 3.0.
    pub acc_w: f32,
    /// Samples along `v` (at least 1). Default 7.
    pub v_samples: u16,
    /// Samples along `w` (at least 1). Default 15.
    pub w_samples: u16,
    /// Weight `eps` of the heading term.
    pub heading: f32,
    /// Weight `tau` of the clearance term.
    pub dist: f32,
    /// Weight `gamma` of the velocity term.
    pub velocity: f32,
    /// Weight `kappa` of the curvefit term.
    pub curvefit: f32,
    /// Footprint radius (cells). Default 0.3 (fits a one-cell aisle with 0.2 to spare).
    pub radius: f32,
    /// Distance to the path's last point that counts as arrived (cells).
    pub goal_tolerance: f32,
    /// Clearance above this counts the same in the `dist` term (cells).
    pub clearance_cap: f32,
    /// Carrot distance along the global path (cells); near obstacles it shrinks to the
    /// robot centre's clearance, but not below half a cell.
    pub lookahead: f32,
    /// How long dynamic discs are predicted (s).
    pub dynamic_horizon: f32,
    /// Progress checker: required displacement (cells) ...
    pub progress_distance: f32,
    /// ... within this time (s).
    pub progress_timeout: f32,
    /// Oscillation counter: `|w|` below this is no sign (rad/s).
    pub oscillation_w_eps: f32,
    /// Oscillation counter: flips that make an event ...
    pub oscillation_flips: u16,
    /// ... within this window (s).
    pub oscillation_window: f32,
    /// Anti-stuck: reverse speed (cells/s, positive).
    pub backoff_speed: f32,
    /// Anti-stuck: in-place rotation steps before backing off.
    pub recovery_rotations: u16,
}

impl Default for DwaConfig {
    fn default() -> Self {
        DwaConfig {
            dt: 0.1,
            predict: 3.0,
            v_max: 1.0,
            v_min: 0.0,
            w_max: 1.2,
            acc_v: 1.0,
            acc_w: 3.0,
            v_samples: 7,
            w_samples: 15,
            heading: 0.8,
            dist: 0.3,
            velocity: 0.4,
            curvefit: 1.0,
            radius: 0.3,
            goal_tolerance: 0.3,
            clearance_cap: 1.0,
            lookahead: 1.5,
            dynamic_horizon: 1.5,
            progress_distance: 0.3,
            progress_timeout: 6.0,
            oscillation_w_eps: 0.05,
            oscillation_flips: 6,
            oscillation_window: 3.0,
            backoff_speed: 0.2,
            recovery_rotations: 30,
        }
    }
}

impl DwaConfig {
    /// Checks every parameter is finite and in range.
    pub fn validate(&self) -> Result<(), DwaError> {
        let positive = [
            self.dt,
            self.predict,
            self.v_max,
            self.w_max,
            self.acc_v,
            self.acc_w,
            self.radius,
            self.goal_tolerance,
            self.clearance_cap,
            self.lookahead,
            self.progress_timeout,
            self.oscillation_window,
        ];
        let non_negative = [
            self.heading,
            self.dist,
            self.velocity,
            self.curvefit,
            self.dynamic_horizon,
            self.progress_distance,
            self.oscillation_w_eps,
            self.backoff_speed,
        ];
        if positive.iter().any(|v| !v.is_finite() || *v <= 0.0)
            || non_negative.iter().any(|v| !v.is_finite() || *v < 0.0)
            || !self.v_min.is_finite()
            || self.v_min > self.v_max
            || self.v_samples == 0
            || self.w_samples == 0
            || self.predict < self.dt
            || self.predict / self.dt > 10_000.0
        {
            return Err(DwaError::InvalidConfig);
        }
        Ok(())
    }
}

/// The robot's pose and velocities.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DwaState {
    /// Position, column units.
    pub x: f32,
    /// Position, row units (down).
    pub y: f32,
    /// Heading (rad, from `+x` towards `+y`).
    pub theta: f32,
    /// Forward speed (cells/s).
    pub v: f32,
    /// Yaw rate (rad/s).
    pub w: f32,
}

impl DwaState {
    fn is_finite(&self) -> bool {
        self.x.is_finite()
            && self.y.is_finite()
            && self.theta.is_finite()
            && self.v.is_finite()
            && self.w.is_finite()
    }

    /// The position.
    pub fn position(&self) -> Point {
        Point::new(self.x, self.y)
    }
}

/// A moving or parked obstacle: a disc with an optional velocity used for prediction.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct DynamicDisc {
    /// Centre, column units.
    pub x: f32,
    /// Centre, row units.
    pub y: f32,
    /// Radius (cells).
    pub r: f32,
    /// Velocity (cells/s), if known; `(0, 0)` otherwise.
    pub vx: f32,
    /// Velocity, row component.
    pub vy: f32,
}

/// Why the local planner refused to plan.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum DwaError {
    /// A configuration value is non-finite or out of range.
    InvalidConfig,
    /// The state has a non-finite value.
    InvalidState,
    /// The global path is empty or has a non-finite point.
    InvalidPath,
    /// A dynamic disc has a non-finite value or a negative radius.
    InvalidObstacle,
}

impl core::fmt::Display for DwaError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.write_str(match self {
            DwaError::InvalidConfig => "InvalidConfig",
            DwaError::InvalidState => "InvalidState",
            DwaError::InvalidPath => "InvalidPath",
            DwaError::InvalidObstacle => "InvalidObstacle",
        })
    }
}

/// What produced a command.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Mode {
    /// The best admissible sample of the window.
    Track,
    /// Within the goal tolerance: stop.
    Arrived,
    /// No admissible sample while moving: maximal deceleration.
    Brake,
    /// No admissible sample while standing: rotate in place towards the carrot.
    Rotate,
    /// Rotation did not help: reverse slowly.
    BackOff,
}

/// Something the supervisor should know about.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Event {
    /// Nothing.
    None,
    /// The progress checker fired: no progress for `progress_timeout` seconds.
    Stuck,
    /// The oscillation counter fired.
    Oscillation,
}

/// One control output.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Command {
    /// Forward speed to apply for `dt` (cells/s).
    pub v: f32,
    /// Yaw rate to apply for `dt` (rad/s).
    pub w: f32,
    /// How it was chosen.
    pub mode: Mode,
    /// Progress checker and oscillation counter.
    pub event: Event,
    /// Admissible samples in the window.
    pub admissible: u32,
    /// Samples evaluated.
    pub samples: u32,
    /// The chosen sample's score (0 outside [`Mode::Track`]).
    pub score: f32,
    /// The carrot the heading term aimed at.
    pub carrot: Point,
    /// Distance from the robot to the global path.
    pub cross_track: f32,
}

/// The local planner with its supervision state (progress, oscillation, recovery).
#[derive(Clone, Debug)]
pub struct Dwa {
    /// The parameters.
    pub config: DwaConfig,
    segment: usize,
    seg_t: f32,
    lookahead: f32,
    clock: f32,
    anchor: Point,
    anchor_time: f32,
    last_w_sign: i8,
    last_v_sign: i8,
    flips: u16,
    window_start: f32,
    rotations: u16,
    stuck_events: u32,
    oscillation_events: u32,
}

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

impl Dwa {
    /// A planner with `config` (validated).
    pub fn new(config: DwaConfig) -> Result<Self, DwaError> {
        config.validate()?;
        Ok(Dwa {
            config,
            segment: 0,
            seg_t: 0.0,
            lookahead: config.lookahead,
            clock: 0.0,
            anchor: Point::new(f32::NAN, f32::NAN),
            anchor_time: 0.0,
            last_w_sign: 0,
            last_v_sign: 0,
            flips: 0,
            window_start: 0.0,
            rotations: 0,
            stuck_events: 0,
            oscillation_events: 0,
        })
    }

    /// Call when the global path changes: path tracking restarts from its first segment and
    /// the progress checker and recovery restart.
    pub fn reset_path(&mut self) {
        self.segment = 0;
        self.seg_t = 0.0;
        self.anchor = Point::new(f32::NAN, f32::NAN);
        self.anchor_time = self.clock;
        self.rotations = 0;
    }

    /// Stuck events so far.
    pub fn stuck_events(&self) -> u32 {
        self.stuck_events
    }

    /// Oscillation events so far.
    pub fn oscillation_events(&self) -> u32 {
        self.oscillation_events
    }

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

        // The dynamic window.
        let v_lo = (state.v - c.acc_v * c.dt).max(c.v_min);
        let v_hi = (state.v + c.acc_v * c.dt).min(c.v_max);
        let w_lo = (state.w - c.acc_w * c.dt).max(-c.w_max);
        let w_hi = (state.w + c.acc_w * c.dt).min(c.w_max);
        let (v_lo, v_hi) = if v_lo <= v_hi {
            (v_lo, v_hi)
        } else {
            // Outside the limits (e.g. reversing): the reachable value nearest to them.
            let v = v_hi.max(c.v_min).min(v_lo);
            (v, v)
        };
        let (w_lo, w_hi) = if w_lo <= w_hi {
            (w_lo, w_hi)
        } else {
            let w = w_hi.max(-c.w_max).min(w_lo);
            (w, w)
        };
        let sample = |lo: f32, hi: f32, n: u16, i: u16| {
            if n <= 1 {
                0.5 * (lo + hi)
            } else {
                lo + (hi - lo) * i as f32 / (n - 1) as f32
            }
        };

        // Pass 1: ranges of the terms over the admissible samples, over all of them and
        // over the moving ones.
        let mut ranges = [Range::EMPTY; 4];
        let mut ranges_moving = [Range::EMPTY; 4];
        let mut admissible = 0u32;
        let mut admissible_moving = 0u32;
        // Pass 1's terms, by sample index, when the window fits (evaluation is pure, so
        // pass 2 reads exactly what it would recompute).
        let total = c.v_samples as usize * c.w_samples as usize;
        let mut cache = [None::<Terms>; CACHED_SAMPLES];
        let cached = total <= CACHED_SAMPLES;
        for i in 0..c.v_samples {
            let v = sample(v_lo, v_hi, c.v_samples, i);
            for j in 0..c.w_samples {
                let w = sample(w_lo, w_hi, c.w_samples, j);
                let terms = self.evaluate(state, v, w, grid, discs, path);
                if cached {
                    cache[i as usize * c.w_samples as usize + j as usize] = terms;
                }
                if let Some(t) = terms {
                    admissible += 1;
                    let terms = [t.heading, t.dist, t.vel, t.fit];
                    for (r, x) in ranges.iter_mut().zip(terms) {
                        r.add(x);
                    }
                    if v.abs() >= STANDING_V && t.dist > 0.0 {
                        admissible_moving += 1;
                        for (r, x) in ranges_moving.iter_mut().zip(terms) {
                            r.add(x);
                        }
                    }
                }
            }
        }
        // A standing sample's roll-out ends where the robot is, on the path: it would win
        // the curvefit term whenever the robot is slightly off the path. Standing (turning in
        // place) is therefore a choice only when the robot faces away from the path or when
        // no moving sample is admissible without contact (then all samples compete).
        let facing = wrap(libm::atan2f(carrot.y - pos.y, carrot.x - pos.x) - state.theta).abs();
        let moving_only = admissible_moving > 0 && facing < ROTATE_IN_PLACE_ABOVE;
        if moving_only {
            ranges = ranges_moving;
        }
        cmd.samples = c.v_samples as u32 * c.w_samples as u32;
        cmd.admissible = admissible;

        if admissible > 0 {
            // Pass 2: the best normalised score (ties keep the first sample).
            let mut best = (f32::NEG_INFINITY, 0.0, 0.0);
            for i in 0..c.v_samples {
                let v = sample(v_lo, v_hi, c.v_samples, i);
                for j in 0..c.w_samples {
                    let w = sample(w_lo, w_hi, c.w_samples, j);
                    if moving_only && v.abs() < STANDING_V {
                        continue;
                    }
                    let terms = if cached {
                        cache[i as usize * c.w_samples as usize + j as usize]
                    } else {
                        self.evaluate(state, v, w, grid, discs, path)
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
            cmd.score = best.0;
            cmd.v = best.1;
            cmd.w = best.2;
            // A window whose best choice is to stand still without turning is a dead end
            // too: fall through to the recovery rules below.
            if cmd.v.abs() > 1e-3 || cmd.w.abs() > 1e-3 {
                self.rotations = 0;
            } else {
                self.recover(state, grid, carrot, &mut cmd);
            }
        } else {
            self.recover(state, grid, carrot, &mut cmd);
        }
        cmd.event = self.supervise(pos, &cmd);
        Ok(cmd)
    }

    /// Anti-stuck rule (see the module documentation).
    fn recover(&mut self, state: &DwaState, grid: GridRef<'_>, carrot: Point, cmd: &mut Command) {
        let c = self.config;
        if state.v.abs() > c.acc_v * c.dt {
            cmd.mode = Mode::Brake;
            let dv = c.acc_v * c.dt;
            cmd.v = if state.v > 0.0 {
                state.v - dv
            } else {
                state.v + dv
            };
            cmd.w = 0.0;
            return;
        }
        self.rotations = self.rotations.saturating_add(1);
        let bearing = libm::atan2f(carrot.y - state.y, carrot.x - state.x);
        let err = wrap(bearing - state.theta);
        if self.rotations <= c.recovery_rotations && err.abs() > 0.1 {
            cmd.mode = Mode::Rotate;
            cmd.v = 0.0;
            let w = clamp(2.0 * err, -c.w_max, c.w_max);
            // Reachable within one step, but never beyond the limit (a robot turning faster
            // than `w_max` is commanded down to it, as the window does).
            let reachable = clamp(w, state.w - c.acc_w * c.dt, state.w + c.acc_w * c.dt);
            cmd.w = clamp(reachable, -c.w_max, c.w_max);
            return;
        }
        // Back off if the cells behind are clear, else wait (rotation counter keeps going).
        let back = Point::new(
            state.x - libm::cosf(state.theta) * 0.3,
            state.y - libm::sinf(state.theta) * 0.3,
        );
        if point_clearance(grid, back, c.radius + 0.5) > c.radius + 0.05 {
            cmd.mode = Mode::BackOff;
            cmd.v = (-c.backoff_speed).max(state.v - c.acc_v * c.dt);
            cmd.w = 0.0;
        } else {
            cmd.mode = Mode::Rotate;
            cmd.v = 0.0;
            cmd.w = 0.0;
        }
        if self.rotations > c.recovery_rotations.saturating_mul(2) {
            self.rotations = 0;
        }
    }

    /// Progress checker and oscillation counter.
    fn supervise(&mut self, pos: Point, cmd: &Command) -> Event {
        let c = self.config;
        let mut event = Event::None;
        if !self.anchor.is_finite() || pos.distance(self.anchor) >= c.progress_distance {
            self.anchor = pos;
            self.anchor_time = self.clock;
        } else if self.clock - self.anchor_time >= c.progress_timeout {
            self.stuck_events += 1;
            self.anchor_time = self.clock;
            event = Event::Stuck;
        }
        let sign = |x: f32, eps: f32| -> i8 {
            if x > eps {
                1
            } else if x < -eps {
                -1
            } else {
                0
            }
        };
        let ws = sign(cmd.w, c.oscillation_w_eps);
        let vs = sign(cmd.v, 1e-3);
        if self.clock - self.window_start > c.oscillation_window {
            self.window_start = self.clock;
            self.flips = 0;
        }
        if ws != 0 {
            if self.last_w_sign != 0 && ws != self.last_w_sign {
                self.flips += 1;
            }
            self.last_w_sign = ws;
        }
        if vs != 0 {
            if self.last_v_sign != 0 && vs != self.last_v_sign {
                self.flips += 1;
            }
            self.last_v_sign = vs;
        }
        if self.flips >= c.oscillation_flips {
            self.flips = 0;
            self.window_start = self.clock;
            self.oscillation_events += 1;
            if event == Event::None {
                event = Event::Oscillation;
            }
        }
        event
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
        (walk(path, s, t, self.lookahead), d)
    }

    /// Rolls `(v, w)` out; `None` when inadmissible.
    #[allow(clippy::too_many_arguments)]
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
        if standing {
            let cl = point_clearance(grid, Point::new(x, y), c.clearance_cap + c.radius) - c.radius;
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
            let mut cl = point_clearance(grid, p, c.clearance_cap + c.radius) - c.radius;
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
            (d, walk(path, s, t, self.lookahead))
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

/// Angle wrapped to `(-pi, pi]`.
pub fn wrap(a: f32) -> f32 {
    let mut a = libm::fmodf(a, 2.0 * PI);
    if a > PI {
        a -= 2.0 * PI;
    } else if a <= -PI {
        a += 2.0 * PI;
    }
    a
}

/// Distance from `p` to segment `ab` and the projection parameter in `[0, 1]`.
fn project(p: Point, a: Point, b: Point) -> (f32, f32) {
    let (dx, dy) = (b.x - a.x, b.y - a.y);
    let len2 = dx * dx + dy * dy;
    let t = if len2 > 0.0 {
        (((p.x - a.x) * dx + (p.y - a.y) * dy) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let q = Point::new(a.x + dx * t, a.y + dy * t);
    (p.distance(q), t)
}

/// The point of `path` nearest to `p` among the stretch that starts at parameter `t0` of
/// segment `seg0` and runs `span` cells of arc further: `(distance, segment, parameter)`.
/// Ties go to the later point (corners). `path` has at least two points.
fn nearest_ahead(p: Point, path: &[Point], seg0: usize, t0: f32, span: f32) -> (f32, usize, f32) {
    let last = path.len() - 2;
    let seg0 = seg0.min(last);
    let t0 = t0.clamp(0.0, 1.0);
    let mut best = (f32::INFINITY, seg0, t0);
    let mut arc = 0.0f32;
    for s in seg0..=last {
        let (a, b) = (path[s], path[s + 1]);
        let lo = if s == seg0 { t0 } else { 0.0 };
        let (dx, dy) = (b.x - a.x, b.y - a.y);
        let len2 = dx * dx + dy * dy;
        let len = sqrt(len2);
        let t = if len2 > 0.0 {
            clamp(((p.x - a.x) * dx + (p.y - a.y) * dy) / len2, lo, 1.0)
        } else {
            lo
        };
        // Do not look past the end of the stretch.
        let t = if len > 0.0 {
            t.min(lo + (span - arc).max(0.0) / len)
        } else {
            t
        };
        let q = Point::new(a.x + dx * t, a.y + dy * t);
        let d = p.distance(q);
        if d <= best.0 + 1e-4 {
            best = (d, s, t);
        }
        arc += len * (1.0 - lo);
        if arc >= span {
            break;
        }
    }
    best
}

/// The point `dist` cells of arc further along `path` than parameter `t` of segment `seg`
/// (the last point when the path ends first). `path` has at least two points.
fn walk(path: &[Point], seg: usize, t: f32, dist: f32) -> Point {
    let last = path.len() - 2;
    let seg = seg.min(last);
    let (a, b) = (path[seg], path[seg + 1]);
    let mut from = Point::new(a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t);
    let mut left = dist;
    for s in seg..=last {
        let to = path[s + 1];
        let len = from.distance(to);
        if len >= left && len > 0.0 {
            let k = left / len;
            return Point::new(from.x + (to.x - from.x) * k, from.y + (to.y - from.y) * k);
        }
        left -= len;
        from = to;
    }
    path[path.len() - 1]
}

/// Distance from `p` to the polyline (to the point for a one-point path).
pub fn distance_to_polyline(p: Point, path: &[Point]) -> f32 {
    match path {
        [] => f32::INFINITY,
        [only] => p.distance(*only),
        _ => path
            .windows(2)
            .map(|s| project(p, s[0], s[1]).0)
            .fold(f32::INFINITY, f32::min),
    }
}

/// Distance from `p` to the nearest blocked cell square (cells outside the map are
/// blocked), capped at `cap`; 0 inside a blocked cell or off the map.
pub fn point_clearance(grid: GridRef<'_>, p: Point, cap: f32) -> f32 {
    if !p.is_finite() || !cap.is_finite() || cap < 0.0 {
        return 0.0;
    }
    let cap = cap.min((grid.width() + grid.height()) as f32);
    let reach = cap + 0.5;
    let x0 = crate::math::floor_i(p.x - reach + 0.5).max(-1);
    let x1 = crate::math::ceil_i(p.x + reach - 0.5).min(grid.width() as isize);
    let y0 = crate::math::floor_i(p.y - reach + 0.5).max(-1);
    let y1 = crate::math::ceil_i(p.y + reach - 0.5).min(grid.height() as isize);
    let mut best2 = cap * cap;
    for y in y0..=y1 {
        let gy = at_least_zero((p.y - y as f32).abs() - 0.5);
        // Most rows near a robot on open floor hold no blocked cell: one bit test of the
        // whole run skips them (cells off the map count as blocked here too).
        if gy * gy >= best2 || !grid.row_run_blocked(y, x0, x1) {
            continue;
        }
        for x in x0..=x1 {
            if grid.is_blocked(x, y) {
                let gx = at_least_zero((p.x - x as f32).abs() - 0.5);
                best2 = lesser(best2, gx * gx + gy * gy);
            }
        }
    }
    sqrt(best2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};

    type G = Grid<{ words_for(20, 20) }>;

    fn empty() -> G {
        G::new(20, 20).unwrap()
    }

    /// The distance to the nearest blocked square over every cell (the definition).
    fn clearance_by_every_cell(grid: GridRef<'_>, p: Point, cap: f32) -> f32 {
        let mut best2 = cap * cap;
        for y in -1..=grid.height() as isize {
            for x in -1..=grid.width() as isize {
                if grid.is_blocked(x, y) {
                    let gx = ((p.x - x as f32).abs() - 0.5).max(0.0);
                    let gy = ((p.y - y as f32).abs() - 0.5).max(0.0);
                    best2 = best2.min(gx * gx + gy * gy);
                }
            }
        }
        sqrt(best2)
    }

    #[test]
    fn clearance_is_the_distance_to_the_nearest_blocked_square() {
        let mut rng = crate::optim::random::Random::new(0x9E37_79B9);
        let mut next = |n: usize| rng.index(n);
        for _ in 0..200 {
            let mut g = empty();
            for _ in 0..next(120) {
                g.set_blocked(next(20), next(20), true).unwrap();
            }
            for _ in 0..50 {
                let p = Point::new(
                    next(2400) as f32 / 100.0 - 2.0,
                    next(2400) as f32 / 100.0 - 2.0,
                );
                // Off the map, blocked squares beyond the border ring count too.
                if p.x <= -0.5 || p.y <= -0.5 || p.x >= 19.5 || p.y >= 19.5 {
                    continue;
                }
                for cap in [0.3, 1.3, 2.0, 5.0] {
                    let want = clearance_by_every_cell(g.view(), p, cap);
                    let got = point_clearance(g.view(), p, cap);
                    assert_eq!(got.to_bits(), want.to_bits(), "{p:?} cap {cap}");
                }
            }
        }
    }

    /// Drives the robot with perfect kinematics until arrival or `max` steps.
    fn drive(
        dwa: &mut Dwa,
        grid: &G,
        mut s: DwaState,
        path: &[Point],
        discs: &[DynamicDisc],
        max: usize,
    ) -> (DwaState, bool, f32) {
        let mut min_clear = f32::INFINITY;
        for _ in 0..max {
            let cmd = dwa.step(&s, grid.view(), discs, path).unwrap();
            if cmd.mode == Mode::Arrived {
                return (s, true, min_clear);
            }
            s.v = cmd.v;
            s.w = cmd.w;
            s.theta += s.w * dwa.config.dt;
            s.x += s.v * libm::cosf(s.theta) * dwa.config.dt;
            s.y += s.v * libm::sinf(s.theta) * dwa.config.dt;
            min_clear = min_clear.min(point_clearance(grid.view(), s.position(), 5.0));
        }
        (s, false, min_clear)
    }

    #[test]
    fn reaches_goal_on_empty_map() {
        let g = empty();
        let mut dwa = Dwa::new(DwaConfig::default()).unwrap();
        let path = [Point::new(2.0, 2.0), Point::new(15.0, 10.0)];
        let s = DwaState {
            x: 2.0,
            y: 2.0,
            ..Default::default()
        };
        let (_, ok, clear) = drive(&mut dwa, &g, s, &path, &[], 600);
        assert!(ok);
        assert!(clear > 0.3);
    }

    #[test]
    fn goal_behind_turns_around() {
        let g = empty();
        let mut dwa = Dwa::new(DwaConfig::default()).unwrap();
        let path = [Point::new(10.0, 10.0), Point::new(4.0, 10.0)];
        let s = DwaState {
            x: 10.0,
            y: 10.0,
            theta: 0.0,
            ..Default::default()
        };
        let (end, ok, _) = drive(&mut dwa, &g, s, &path, &[], 600);
        assert!(ok, "{end:?}");
    }

    #[test]
    fn follows_a_one_cell_aisle_without_touching() {
        // Rows 8 and 10 blocked from x = 3 to 16: a one-cell aisle along row 9.
        let mut g = empty();
        for x in 3..17 {
            g.set_blocked(x, 8, true).unwrap();
            g.set_blocked(x, 10, true).unwrap();
        }
        let mut dwa = Dwa::new(DwaConfig::default()).unwrap();
        let path = [Point::new(1.0, 9.0), Point::new(18.0, 9.0)];
        let s = DwaState {
            x: 1.0,
            y: 9.0,
            ..Default::default()
        };
        let (_, ok, clear) = drive(&mut dwa, &g, s, &path, &[], 800);
        assert!(ok);
        assert!(clear > dwa.config.radius, "{clear}");
    }

    #[test]
    fn stops_for_a_disc_ahead() {
        let g = empty();
        let mut dwa = Dwa::new(DwaConfig::default()).unwrap();
        let path = [Point::new(2.0, 10.0), Point::new(18.0, 10.0)];
        let disc = [DynamicDisc {
            x: 6.0,
            y: 10.0,
            r: 0.3,
            ..Default::default()
        }];
        let mut s = DwaState {
            x: 2.0,
            y: 10.0,
            ..Default::default()
        };
        for _ in 0..300 {
            let cmd = dwa.step(&s, g.view(), &disc, &path).unwrap();
            s.v = cmd.v;
            s.w = cmd.w;
            s.theta += s.w * 0.1;
            s.x += s.v * libm::cosf(s.theta) * 0.1;
            s.y += s.v * libm::sinf(s.theta) * 0.1;
            let d = s.position().distance(Point::new(6.0, 10.0));
            assert!(d > 0.6, "collided: {s:?}");
        }
    }

    #[test]
    fn bad_input_is_a_typed_error() {
        let g = empty();
        let mut dwa = Dwa::new(DwaConfig::default()).unwrap();
        let path = [Point::new(1.0, 1.0), Point::new(5.0, 5.0)];
        let ok = DwaState {
            x: 1.0,
            y: 1.0,
            ..Default::default()
        };
        let nan = DwaState { x: f32::NAN, ..ok };
        assert_eq!(
            dwa.step(&nan, g.view(), &[], &path),
            Err(DwaError::InvalidState)
        );
        let inf = DwaState {
            v: f32::INFINITY,
            ..ok
        };
        assert_eq!(
            dwa.step(&inf, g.view(), &[], &path),
            Err(DwaError::InvalidState)
        );
        assert_eq!(
            dwa.step(&ok, g.view(), &[], &[]),
            Err(DwaError::InvalidPath)
        );
        let bad_path = [Point::new(f32::NAN, 0.0)];
        assert_eq!(
            dwa.step(&ok, g.view(), &[], &bad_path),
            Err(DwaError::InvalidPath)
        );
        let bad_disc = [DynamicDisc {
            r: -1.0,
            ..Default::default()
        }];
        assert_eq!(
            dwa.step(&ok, g.view(), &bad_disc, &path),
            Err(DwaError::InvalidObstacle)
        );
        for f in [f32::NAN, f32::INFINITY, -1.0, 0.0] {
            let cfg = DwaConfig {
                dt: f,
                ..DwaConfig::default()
            };
            assert_eq!(Dwa::new(cfg).err(), Some(DwaError::InvalidConfig));
        }
        dwa.config.heading = f32::NAN;
        assert_eq!(
            dwa.step(&ok, g.view(), &[], &path),
            Err(DwaError::InvalidConfig)
        );
        let cfg = DwaConfig {
            v_samples: 0,
            ..DwaConfig::default()
        };
        assert!(Dwa::new(cfg).is_err());
    }

    #[test]
    fn boxed_in_robot_recovers_without_moving_into_walls() {
        // A robot in a dead-end pocket facing the wall: no forward sample is admissible.
        let mut g = empty();
        for y in 8..=12 {
            g.set_blocked(12, y, true).unwrap();
        }
        let mut dwa = Dwa::new(DwaConfig::default()).unwrap();
        let s = DwaState {
            x: 11.0,
            y: 10.0,
            theta: 0.0,
            v: 0.5,
            w: 0.0,
        };
        let cmd = dwa
            .step(&s, g.view(), &[], &[Point::new(4.0, 10.0)])
            .unwrap();
        assert!(cmd.v < s.v, "{cmd:?}");
    }

    #[test]
    fn progress_checker_fires_when_blocked() {
        // Goal enclosed: the robot cannot make progress and reports Stuck.
        let mut g = empty();
        for i in 8..=12 {
            g.set_blocked(i, 8, true).unwrap();
            g.set_blocked(i, 12, true).unwrap();
            g.set_blocked(8, i, true).unwrap();
            g.set_blocked(12, i, true).unwrap();
        }
        let mut dwa = Dwa::new(DwaConfig::default()).unwrap();
        let path = [Point::new(4.0, 10.0), Point::new(10.0, 10.0)];
        let mut s = DwaState {
            x: 4.0,
            y: 10.0,
            ..Default::default()
        };
        let mut stuck = false;
        for _ in 0..400 {
            let cmd = dwa.step(&s, g.view(), &[], &path).unwrap();
            stuck |= cmd.event == Event::Stuck;
            s.v = cmd.v;
            s.w = cmd.w;
            s.theta += s.w * 0.1;
            s.x += s.v * libm::cosf(s.theta) * 0.1;
            s.y += s.v * libm::sinf(s.theta) * 0.1;
            assert!(point_clearance(g.view(), s.position(), 2.0) > 0.29);
        }
        assert!(stuck);
        assert!(dwa.stuck_events() >= 1);
    }

    #[test]
    fn clearance_matches_geometry() {
        let mut g = empty();
        g.set_blocked(10, 10, true).unwrap();
        let d = point_clearance(g.view(), Point::new(8.0, 10.0), 5.0);
        assert!((d - 1.5).abs() < 1e-5, "{d}");
        let d = point_clearance(g.view(), Point::new(9.0, 9.0), 5.0);
        assert!((d - sqrt(0.5)).abs() < 1e-5, "{d}");
        assert_eq!(point_clearance(g.view(), Point::new(10.2, 10.0), 5.0), 0.0);
        // The map edge counts.
        let d = point_clearance(g.view(), Point::new(0.0, 5.0), 5.0);
        assert!((d - 0.5).abs() < 1e-5);
        assert_eq!(
            point_clearance(g.view(), Point::new(f32::NAN, 5.0), 5.0),
            0.0
        );
    }

    #[test]
    fn wrap_and_polyline() {
        assert!((wrap(3.0 * PI) - PI).abs() < 1e-5);
        assert!((wrap(-0.5) + 0.5).abs() < 1e-6);
        let path = [Point::new(0.0, 0.0), Point::new(10.0, 0.0)];
        assert!((distance_to_polyline(Point::new(5.0, 2.0), &path) - 2.0).abs() < 1e-6);
    }
}

//! Dynamic Window Approach local planner (SPEC section 5, `Hu2023HhoDwa`).
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
//! still is never blamed for a disc moving into it.
//!
//! **Standing samples** (`v = 0`, turning in place) end where the robot is, which the
//! curvefit term rewards whenever the robot is a little off the path; they compete only when
//! the robot faces more than 45 degrees away from its carrot or when no moving sample is
//! admissible with a contact-free roll-out (only contact-free moving samples compete when
//! standing is excluded).
//!
//! Safety rules around the scoring:
//! - **static margin** (`margin`): roll-outs are checked against the footprint grown by the
//!   margin; a robot already inside it (pushed there, or starting there) may not get closer
//!   than it is by more than a hundredth of a cell a step, so it can always move along or
//!   away;
//! - **protective field** (`protect_stop`, `protect_slow`): the forward speed is limited by the
//!   distance from the footprint to the nearest dynamic disc in front of the robot (0 inside
//!   `protect_stop`, `v_max` beyond `protect_slow`, linear between), as the protective fields of
//!   driverless trucks do (ISO 3691-4); the window brakes to the limit at the acceleration
//!   limit, and backing off needs the field behind the robot clear too;
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
//!
//! Files: this one holds the configuration, the types and the planner's state; `step` the
//! control step (window, roll-outs, scoring); `recovery` the anti-stuck rule, the progress
//! checker and the oscillation counter. The path-following helpers and the point clearance
//! it uses are in [`crate::geometry`].

mod recovery;
mod step;
#[cfg(test)]
mod tests;

use crate::geometry::Point;
use core::f32::consts::PI;

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
    /// Static margin (cells): clearance the footprint keeps from blocked cells. A roll-out
    /// coming closer counts as a contact; a robot already closer may not get closer by more
    /// than a hundredth of a cell a step. Default 0 (the footprint alone).
    pub margin: f32,
    /// Protective field, stop distance (cells): with a dynamic disc this close to the
    /// footprint, in front of the robot, the robot does not drive forward. Default 0.
    pub protect_stop: f32,
    /// Protective field, slow-down distance (cells): between `protect_stop` and this the
    /// speed limit scales linearly from 0 to `v_max`. Default 0 (no field).
    pub protect_slow: f32,
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
            margin: 0.0,
            protect_stop: 0.0,
            protect_slow: 0.0,
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
            self.margin,
            self.protect_stop,
            self.protect_slow,
        ];
        if positive.iter().any(|v| !v.is_finite() || *v <= 0.0)
            || non_negative.iter().any(|v| !v.is_finite() || *v < 0.0)
            || !self.v_min.is_finite()
            || self.v_min > self.v_max
            || self.v_samples == 0
            || self.w_samples == 0
            || self.predict < self.dt
            || self.predict / self.dt > 10_000.0
            || self.protect_slow < self.protect_stop
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
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
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
    /// This step's static margin (see [`DwaConfig::margin`]).
    floor: f32,
    stuck_events: u32,
    oscillation_events: u32,
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
            floor: 0.0,
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

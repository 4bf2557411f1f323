//! The safety rules around the scoring (see the module documentation): the anti-stuck rule
//! and the supervisor's progress checker and oscillation counter.

use super::step::Scene;
use super::{Command, Dwa, DwaState, Event, Mode, wrap};
use crate::geometry::{Point, point_clearance};
use crate::math::clamp;

impl Dwa {
    /// Anti-stuck rule (see the module documentation).
    pub(super) fn recover(
        &mut self,
        state: &DwaState,
        scene: &Scene<'_>,
        carrot: Point,
        cmd: &mut Command,
    ) {
        let (c, grid) = (self.config, scene.grid);
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
        // With a protective field, nobody may stand within it behind the robot either.
        let behind_clear = c.protect_slow <= 0.0
            || scene
                .discs
                .iter()
                .all(|d| back.distance(Point::new(d.x, d.y)) > d.r + c.radius + c.protect_stop);
        if behind_clear
            && point_clearance(grid, back, c.radius + 0.5) > c.radius + 0.05 + self.floor
        {
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
    pub(super) fn supervise(&mut self, pos: Point, cmd: &Command) -> Event {
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
}

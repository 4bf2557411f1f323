//! Differential-drive kinematics with wheel, velocity and acceleration limits.

use planner_core::dwa::DwaState;

/// Limits of the simulated robot (cells, seconds).
#[derive(Clone, Copy, Debug, serde::Serialize)]
pub struct DiffDrive {
    /// Distance between the wheels (cells).
    pub track: f32,
    /// Wheel speed limit (cells/s).
    pub wheel_max: f32,
    /// Body speed limit (cells/s).
    pub v_max: f32,
    /// Reverse speed limit (cells/s, positive).
    pub v_reverse: f32,
    /// Yaw-rate limit (rad/s).
    pub w_max: f32,
    /// Linear acceleration limit (cells/s^2).
    pub acc_v: f32,
    /// Yaw acceleration limit (rad/s^2).
    pub acc_w: f32,
}

impl Default for DiffDrive {
    fn default() -> Self {
        DiffDrive {
            track: 0.5,
            wheel_max: 1.4,
            v_max: 1.0,
            v_reverse: 0.3,
            w_max: 1.2,
            acc_v: 1.0,
            acc_w: 3.0,
        }
    }
}

impl DiffDrive {
    /// Applies the command `(v, w)` for `dt`: limits, then wheel limits (scaling both wheels
    /// so the curvature is kept), then integration (heading first, as the DWA roll-out).
    pub fn step(&self, s: &mut DwaState, v: f32, w: f32, dt: f32) {
        let (v, w) = if v.is_finite() && w.is_finite() {
            (v, w)
        } else {
            (0.0, 0.0)
        };
        let mut v = v
            .clamp(-self.v_reverse, self.v_max)
            .clamp(s.v - self.acc_v * dt, s.v + self.acc_v * dt);
        let mut w = w
            .clamp(-self.w_max, self.w_max)
            .clamp(s.w - self.acc_w * dt, s.w + self.acc_w * dt);
        let (left, right) = (v - w * self.track / 2.0, v + w * self.track / 2.0);
        let peak = left.abs().max(right.abs());
        if peak > self.wheel_max {
            let k = self.wheel_max / peak;
            v *= k;
            w *= k;
        }
        s.v = v;
        s.w = w;
        s.theta = planner_core::dwa::wrap(s.theta + w * dt);
        s.x += v * s.theta.cos() * dt;
        s.y += v * s.theta.sin() * dt;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn limits_hold() {
        let d = DiffDrive::default();
        let mut s = DwaState::default();
        d.step(&mut s, 5.0, 9.0, 0.1);
        assert!((s.v - 0.1).abs() < 1e-6 && (s.w - 0.3).abs() < 1e-6);
        for _ in 0..100 {
            d.step(&mut s, 5.0, 9.0, 0.1);
        }
        assert!(s.v <= d.v_max + 1e-6 && s.w <= d.w_max + 1e-6);
        let left = s.v - s.w * d.track / 2.0;
        let right = s.v + s.w * d.track / 2.0;
        assert!(left.abs().max(right.abs()) <= d.wheel_max + 1e-5);
        d.step(&mut s, f32::NAN, 0.0, 0.1);
        assert!(s.v.is_finite());
    }
}

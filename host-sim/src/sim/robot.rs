//! The simulated robot in world units (metres, m/s, m/s^2), and what it becomes in the cell
//! units the local planner, the drive and the movers work in on a map of a given resolution.
//!
//! The defaults are a typical warehouse AMR: 0.25 m radius, 1.0 m/s, 0.5 m/s^2. On a map
//! without a world frame a cell counts as a metre.

use super::kinematics::DiffDrive;
use planner_core::dwa::DwaConfig;
use std::fmt;

/// The robot's footprint and limits.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Robot {
    /// Footprint radius (m).
    pub radius: f32,
    /// Forward speed limit (m/s).
    pub max_speed: f32,
    /// Linear acceleration limit (m/s^2).
    pub max_accel: f32,
}

/// A robot figure that cannot be simulated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BadRobot {
    /// The option's name (`--robot-radius`).
    pub option: &'static str,
    /// Its value.
    pub value: f32,
    /// What it must be.
    pub rule: &'static str,
}

impl fmt::Display for BadRobot {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{} {}: {}", self.option, self.value, self.rule)
    }
}

impl std::error::Error for BadRobot {}

impl Robot {
    /// A typical warehouse AMR.
    pub const AMR: Robot = Robot {
        radius: 0.25,
        max_speed: 1.0,
        max_accel: 0.5,
    };

    /// Every figure finite and above 0, or the first one that is not.
    pub fn check(&self) -> Result<(), BadRobot> {
        for (option, value) in [
            ("--robot-radius", self.radius),
            ("--max-speed", self.max_speed),
            ("--max-accel", self.max_accel),
        ] {
            if !(value.is_finite() && value > 0.0) {
                return Err(BadRobot {
                    option,
                    value,
                    rule: "must be a finite number above 0",
                });
            }
        }
        Ok(())
    }

    /// The local planner for this robot on a map of `cells_per_metre`: the default's
    /// distances (which are metres on 1 m cells) scaled, its speed and acceleration this
    /// robot's.
    pub fn dwa(&self, cells_per_metre: f32) -> DwaConfig {
        let k = cells_per_metre;
        let d = DwaConfig::default();
        DwaConfig {
            v_max: self.max_speed * k,
            acc_v: self.max_accel * k,
            radius: self.radius * k,
            goal_tolerance: d.goal_tolerance * k,
            clearance_cap: d.clearance_cap * k,
            lookahead: d.lookahead * k,
            progress_distance: d.progress_distance * k,
            backoff_speed: d.backoff_speed * k,
            ..d
        }
    }

    /// The drive for this robot on a map of `cells_per_metre` (the default's wheel base and
    /// its wheel and reverse limits in proportion to the speed limit).
    pub fn drive(&self, cells_per_metre: f32) -> DiffDrive {
        let k = cells_per_metre;
        let d = DiffDrive::default();
        let speed = self.max_speed / d.v_max;
        DiffDrive {
            track: d.track * k,
            wheel_max: d.wheel_max * speed * k,
            v_max: self.max_speed * k,
            v_reverse: d.v_reverse * speed * k,
            acc_v: self.max_accel * k,
            ..d
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_metre_cells_keep_the_defaults_but_speed_and_radius() {
        let r = Robot {
            radius: 0.3,
            max_speed: 1.0,
            max_accel: 1.0,
        };
        let (dwa, d) = (r.dwa(1.0), DwaConfig::default());
        assert_eq!(
            (dwa.v_max, dwa.acc_v, dwa.radius, dwa.lookahead),
            (d.v_max, d.acc_v, d.radius, d.lookahead)
        );
        let drive = r.drive(1.0);
        assert_eq!(drive.v_max, DiffDrive::default().v_max);
        assert_eq!(drive.wheel_max, DiffDrive::default().wheel_max);
    }

    #[test]
    fn a_fine_map_scales_distances_and_speeds_by_its_cells_per_metre() {
        let dwa = Robot::AMR.dwa(20.0);
        assert_eq!(dwa.radius, 5.0);
        assert_eq!(dwa.v_max, 20.0);
        assert_eq!(dwa.acc_v, 10.0);
        assert_eq!(dwa.w_max, DwaConfig::default().w_max);
        assert!(planner_core::dwa::Dwa::new(dwa).is_ok());
        assert_eq!(Robot::AMR.drive(20.0).acc_v, 10.0);
    }

    #[test]
    fn bad_figures_name_their_option() {
        let r = Robot {
            max_speed: f32::NAN,
            ..Robot::AMR
        };
        assert_eq!(r.check().unwrap_err().option, "--max-speed");
        let r = Robot {
            radius: 0.0,
            ..Robot::AMR
        };
        assert_eq!(
            r.check().unwrap_err().to_string(),
            "--robot-radius 0: must be a finite number above 0"
        );
    }
}

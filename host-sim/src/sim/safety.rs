//! The robot's safety profile: the static margin it keeps from shelves and the protective
//! field that limits its speed near people and robots (ISO 3691-4 style), in metres.
//!
//! On a map without a world frame a cell counts as a metre. The local planner gets them in
//! cells ([`Safety::apply`]); the global path is pushed off the walls by more than the
//! footprint and the margin (`pathfit`'s target), so both aim at the same clearance.

use super::robot::BadRobot;
use planner_core::dwa::DwaConfig;

/// Static margin and protective field (m).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Safety {
    /// Clearance kept between the footprint and shelves (m).
    pub shelf_margin: f32,
    /// No forward driving with a person or robot this close in front (m, footprint to
    /// footprint).
    pub field_stop: f32,
    /// Full speed only with nobody this close in front; linear from `field_stop` (m).
    pub field_slow: f32,
}

impl Safety {
    /// A typical warehouse AMR's: 0.1 m margin, stop at 0.25 m, full speed beyond 1.25 m.
    pub const AMR: Safety = Safety {
        shelf_margin: 0.1,
        field_stop: 0.25,
        field_slow: 1.25,
    };

    /// None: the footprint alone, no field (the simulator before margins).
    pub const NONE: Safety = Safety {
        shelf_margin: 0.0,
        field_stop: 0.0,
        field_slow: 0.0,
    };

    /// Every figure finite and at least 0, the slow-down distance at least the stop distance.
    pub fn check(&self) -> Result<(), BadRobot> {
        for (option, value) in [
            ("--shelf-margin", self.shelf_margin),
            ("--field-stop", self.field_stop),
            ("--field-slow", self.field_slow),
        ] {
            if !(value.is_finite() && value >= 0.0) {
                return Err(BadRobot {
                    option,
                    value,
                    rule: "must be a finite number of at least 0",
                });
            }
        }
        if self.field_slow < self.field_stop {
            return Err(BadRobot {
                option: "--field-slow",
                value: self.field_slow,
                rule: "must be at least --field-stop",
            });
        }
        Ok(())
    }

    /// `dwa` with this margin and field, on a map of `cells_per_metre`.
    pub fn apply(&self, dwa: DwaConfig, cells_per_metre: f32) -> DwaConfig {
        let k = cells_per_metre;
        DwaConfig {
            margin: self.shelf_margin * k,
            protect_stop: self.field_stop * k,
            protect_slow: self.field_slow * k,
            ..dwa
        }
    }
}

/// The safety options of `run`, `demo`, `scenarios` and `soak`.
#[derive(clap::Args, Clone, Copy, Debug)]
pub struct SafetyArgs {
    /// Static margin kept between the robot's footprint and shelves (m; cells on a map
    /// without a world frame). 0: the footprint alone.
    #[arg(long, default_value_t = Safety::AMR.shelf_margin)]
    pub shelf_margin: f32,
    /// Protective field: no forward driving with a person or robot this close in front (m).
    #[arg(long, default_value_t = Safety::AMR.field_stop)]
    pub field_stop: f32,
    /// Protective field: full speed only with nobody this close in front (m; 0 turns the
    /// field off).
    #[arg(long, default_value_t = Safety::AMR.field_slow)]
    pub field_slow: f32,
}

impl SafetyArgs {
    /// The profile, checked.
    pub fn safety(&self) -> Result<Safety, BadRobot> {
        let s = Safety {
            shelf_margin: self.shelf_margin,
            field_stop: self.field_stop,
            field_slow: self.field_slow,
        };
        s.check()?;
        Ok(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn none_leaves_the_local_planner_as_it_was() {
        let d = DwaConfig::default();
        assert_eq!(Safety::NONE.apply(d, 1.0), d);
        let amr = Safety::AMR.apply(d, 20.0);
        assert_eq!(
            (amr.margin, amr.protect_stop, amr.protect_slow),
            (2.0, 5.0, 25.0)
        );
        assert!(planner_core::dwa::Dwa::new(amr).is_ok());
    }

    #[test]
    fn bad_figures_name_their_option() {
        let s = Safety {
            shelf_margin: f32::NAN,
            ..Safety::AMR
        };
        assert_eq!(s.check().unwrap_err().option, "--shelf-margin");
        let s = Safety {
            field_slow: 0.1,
            ..Safety::AMR
        };
        assert_eq!(
            s.check().unwrap_err().to_string(),
            "--field-slow 0.1: must be at least --field-stop"
        );
    }
}

//! DWA regressions found by the `dwa_step` fuzz target (planner-core/fuzz), public API only.

use planner_core::dwa::{Dwa, DwaConfig, DwaState, Mode};
use planner_core::geometry::Point;
use planner_core::grid::{Grid, words_for};

type Small = Grid<{ words_for(16, 16) }>;

/// In-place rotation honoured the acceleration limit over the yaw-rate limit: a robot
/// turning at 2 rad/s with `w_max` = 1e-6 (a valid configuration) was commanded 1.7 rad/s.
/// The command must stay within `[-w_max, w_max]`, as the window's choice does.
#[test]
fn rotate_in_place_never_exceeds_w_max() {
    let config = DwaConfig {
        v_max: 1e-6,
        w_max: 1e-6,
        ..DwaConfig::default()
    };
    let mut dwa = Dwa::new(config).unwrap();
    let grid = Small::new(16, 16).unwrap();
    let state = DwaState {
        x: 5.0,
        y: 5.0,
        theta: 0.0,
        v: 0.0,
        w: 2.0,
    };
    // The goal is straight "up" (y down): the robot must turn, it cannot move.
    let path = [Point::new(5.0, 5.0), Point::new(5.0, 0.0)];
    let cmd = dwa.step(&state, grid.view(), &[], &path).unwrap();
    assert_eq!(cmd.mode, Mode::Rotate, "{cmd:?}");
    assert!(cmd.w.abs() <= config.w_max, "{cmd:?}");
    assert_eq!(cmd.v, 0.0);
}

/// The carrot distance shrinks to the robot's clearance but not below half a cell: with a
/// configured `lookahead` under half a cell that was `f32::clamp(0.5, lookahead)` with its
/// bounds the wrong way round, a panic (found when the firmware's flash grew by the float
/// formatting of `clamp`'s assertion message). Any valid configuration must step.
#[test]
fn a_short_lookahead_does_not_panic() {
    for lookahead in [0.05, 0.3, 0.49] {
        let config = DwaConfig {
            lookahead,
            ..DwaConfig::default()
        };
        let mut dwa = Dwa::new(config).unwrap();
        let grid = Small::new(16, 16).unwrap();
        let state = DwaState {
            x: 2.0,
            y: 2.0,
            ..DwaState::default()
        };
        let path = [Point::new(2.0, 2.0), Point::new(10.0, 2.0)];
        let cmd = dwa.step(&state, grid.view(), &[], &path).unwrap();
        assert!(cmd.v.is_finite() && cmd.w.is_finite(), "{cmd:?}");
    }
}

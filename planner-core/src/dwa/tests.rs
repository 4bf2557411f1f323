use super::*;
use crate::geometry::point_clearance;
use crate::grid::{Grid, words_for};

type G = Grid<{ words_for(20, 20) }>;

fn empty() -> G {
    G::new(20, 20).unwrap()
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
fn wrap_is_into_minus_pi_to_pi() {
    assert!((wrap(3.0 * PI) - PI).abs() < 1e-5);
    assert!((wrap(-0.5) + 0.5).abs() < 1e-6);
}

#[test]
fn a_margin_keeps_the_footprint_off_a_wall_the_path_runs_along() {
    // Row 5 blocked: a wall whose edge is at y = 5.5; the path runs at y = 6, where the
    // footprint (0.3) keeps 0.2 from it.
    let mut g = empty();
    for x in 0..20 {
        g.set_blocked(x, 5, true).unwrap();
    }
    let path = [Point::new(2.0, 6.0), Point::new(17.0, 6.0)];
    let s = DwaState {
        x: 2.0,
        y: 6.2,
        ..Default::default()
    };
    let plain = Dwa::new(DwaConfig::default()).unwrap();
    let (_, ok, clear) = drive(&mut plain.clone(), &g, s, &path, &[], 600);
    assert!(
        ok && clear - 0.3 < 0.3,
        "without a margin it hugs the path: {clear}"
    );
    let config = DwaConfig {
        margin: 0.4,
        ..DwaConfig::default()
    };
    let mut dwa = Dwa::new(config).unwrap();
    let (_, ok, clear) = drive(&mut dwa, &g, s, &path, &[], 600);
    assert!(ok, "arrives with the margin");
    // It may settle a contact margin and a slip (0.03) inside it, never further.
    assert!(clear - 0.3 >= 0.37, "footprint clearance {}", clear - 0.3);
}

#[test]
fn a_robot_inside_its_margin_may_move_along_but_not_closer() {
    // Started 0.1 from the wall (margin 0.4): it drives, never closer than it started.
    let mut g = empty();
    for x in 0..20 {
        g.set_blocked(x, 5, true).unwrap();
    }
    let config = DwaConfig {
        margin: 0.4,
        ..DwaConfig::default()
    };
    let mut dwa = Dwa::new(config).unwrap();
    let path = [Point::new(2.0, 5.9), Point::new(17.0, 5.9)];
    let s = DwaState {
        x: 2.0,
        y: 5.9,
        ..Default::default()
    };
    let (_, ok, clear) = drive(&mut dwa, &g, s, &path, &[], 600);
    assert!(ok, "arrives");
    assert!(
        clear - 0.3 >= 0.1 - 0.011,
        "footprint clearance {}",
        clear - 0.3
    );
}

/// The protective field's configuration: stop within 0.25, full speed beyond 1.25.
fn fielded() -> DwaConfig {
    DwaConfig {
        protect_stop: 0.25,
        protect_slow: 1.25,
        ..DwaConfig::default()
    }
}

/// A disc of radius 0.25 standing at `x` on row 10.
fn person(x: f32) -> DynamicDisc {
    DynamicDisc {
        x,
        y: 10.0,
        r: 0.25,
        vx: 0.0,
        vy: 0.0,
    }
}

#[test]
fn the_protective_field_scales_speed_with_the_gap_in_front() {
    let g = empty();
    let path = [Point::new(2.0, 10.0), Point::new(18.0, 10.0)];
    let cruising = DwaState {
        x: 2.0,
        y: 10.0,
        v: 1.0,
        ..Default::default()
    };
    // Gap 0.75 (footprint to footprint): half way through the field, at most half speed
    // (commanded at once; the drive brakes at its limit).
    let mut dwa = Dwa::new(fielded()).unwrap();
    let disc = [person(2.0 + 0.3 + 0.25 + 0.75)];
    let cmd = dwa.step(&cruising, g.view(), &disc, &path).unwrap();
    assert!(cmd.v <= 0.5 + 1e-5, "half speed at most: {}", cmd.v);
    let slow = DwaState { v: 0.5, ..cruising };
    let cmd = dwa.step(&slow, g.view(), &disc, &path).unwrap();
    assert!(cmd.v <= 0.5 + 1e-5, "half speed at most: {}", cmd.v);
    // Inside the stop distance: no forward driving, standing or not.
    let near = [person(2.0 + 0.3 + 0.25 + 0.2)];
    for v in [0.0, 0.3] {
        let s = DwaState { v, ..cruising };
        let cmd = Dwa::new(fielded())
            .unwrap()
            .step(&s, g.view(), &near, &path)
            .unwrap();
        assert!(cmd.v <= (v - 0.1).max(0.0) + 1e-5, "v {v} -> {}", cmd.v);
    }
    // Behind the robot the field does not count.
    let behind = [person(2.0 - 0.3 - 0.25 - 0.2)];
    let cmd = Dwa::new(fielded())
        .unwrap()
        .step(&slow, g.view(), &behind, &path)
        .unwrap();
    assert!(cmd.v > 0.5, "behind: {}", cmd.v);
}

#[test]
fn backing_off_needs_the_field_behind_clear() {
    // Boxed in ahead; a person stands right behind: rotate or wait, never reverse into them.
    let mut g = empty();
    for y in 8..13 {
        g.set_blocked(11, y, true).unwrap();
    }
    let config = DwaConfig {
        recovery_rotations: 2,
        ..fielded()
    };
    let mut dwa = Dwa::new(config).unwrap();
    let path = [Point::new(10.0, 10.0), Point::new(12.0, 10.0)];
    let s = DwaState {
        x: 9.9,
        y: 10.0,
        ..Default::default()
    };
    let behind = [person(9.9 - 0.3 - 0.25 - 0.1)];
    for _ in 0..20 {
        let cmd = dwa.step(&s, g.view(), &behind, &path).unwrap();
        assert!(cmd.v >= 0.0, "{cmd:?}");
    }
}

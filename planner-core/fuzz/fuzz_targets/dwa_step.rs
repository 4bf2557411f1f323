//! A few DWA control steps with arbitrary configuration, states, dynamic discs, global
//! path and map (floats incl. NaN/inf/huge, zero and negative limits): no panic; an
//! invalid configuration or input is the matching `DwaError`; with an accepted
//! configuration every command is finite and respects the configured limits.
//!
//! Only the public API of `planner_core::dwa` is used. Sample counts and the roll-out
//! horizon (`predict / dt` steps) are kept small so that one input stays fast; every float
//! limit is arbitrary.
#![no_main]

mod common;

use arbitrary::Arbitrary;
use common::{FloatInput, MapInput};
use libfuzzer_sys::fuzz_target;
use planner_core::dwa::{Command, Dwa, DwaConfig, DwaError, DwaState, DynamicDisc, Mode};
use planner_core::geometry::Point;

/// A float limit: often a sensible value (as in the default configuration), sometimes
/// anything (negative, zero, NaN, inf, huge).
#[derive(Arbitrary, Debug, Clone, Copy)]
enum Limit {
    Default,
    Any(FloatInput),
    Negated(FloatInput),
}

impl Limit {
    fn get(self, default: f32) -> f32 {
        match self {
            Limit::Default => default,
            Limit::Any(f) => f.get(),
            Limit::Negated(f) => -f.get(),
        }
    }
}

#[derive(Arbitrary, Debug)]
struct ConfigInput {
    dt: Limit,
    /// Roll-out steps (`predict = dt * steps`) unless `predict_raw` overrides.
    steps: u8,
    predict_raw: Option<FloatInput>,
    v_max: Limit,
    v_min: Limit,
    w_max: Limit,
    acc_v: Limit,
    acc_w: Limit,
    v_samples: u8,
    w_samples: u8,
    weights: [Limit; 4],
    radius: Limit,
    goal_tolerance: Limit,
    clearance_cap: Limit,
    lookahead: Limit,
    dynamic_horizon: Limit,
    progress_distance: Limit,
    progress_timeout: Limit,
    oscillation_w_eps: Limit,
    oscillation_flips: u16,
    oscillation_window: Limit,
    backoff_speed: Limit,
    recovery_rotations: u8,
    /// Static margin, protective field stop and slow-down distances (off when `None`).
    safety: Option<[Limit; 3]>,
}

impl ConfigInput {
    fn build(&self) -> DwaConfig {
        let d = DwaConfig::default();
        let dt = self.dt.get(d.dt);
        let predict = match self.predict_raw {
            Some(p) => p.get(),
            None => dt * (self.steps % 40 + 1) as f32,
        };
        DwaConfig {
            dt,
            predict,
            v_max: self.v_max.get(d.v_max),
            v_min: self.v_min.get(d.v_min),
            w_max: self.w_max.get(d.w_max),
            acc_v: self.acc_v.get(d.acc_v),
            acc_w: self.acc_w.get(d.acc_w),
            // 0 (invalid) .. 12 samples per axis.
            v_samples: (self.v_samples % 13) as u16,
            w_samples: (self.w_samples % 13) as u16,
            heading: self.weights[0].get(d.heading),
            dist: self.weights[1].get(d.dist),
            velocity: self.weights[2].get(d.velocity),
            curvefit: self.weights[3].get(d.curvefit),
            radius: self.radius.get(d.radius),
            goal_tolerance: self.goal_tolerance.get(d.goal_tolerance),
            clearance_cap: self.clearance_cap.get(d.clearance_cap),
            lookahead: self.lookahead.get(d.lookahead),
            dynamic_horizon: self.dynamic_horizon.get(d.dynamic_horizon),
            progress_distance: self.progress_distance.get(d.progress_distance),
            progress_timeout: self.progress_timeout.get(d.progress_timeout),
            oscillation_w_eps: self.oscillation_w_eps.get(d.oscillation_w_eps),
            oscillation_flips: self.oscillation_flips,
            oscillation_window: self.oscillation_window.get(d.oscillation_window),
            backoff_speed: self.backoff_speed.get(d.backoff_speed),
            recovery_rotations: self.recovery_rotations as u16,
            margin: self.safety.map_or(d.margin, |s| s[0].get(0.1)),
            protect_stop: self.safety.map_or(d.protect_stop, |s| s[1].get(0.25)),
            protect_slow: self.safety.map_or(d.protect_slow, |s| s[2].get(1.25)),
        }
    }

    /// Whether the configuration can be run fast enough for fuzzing: the sample counts are
    /// bounded by construction; the horizon is bounded here.
    fn fast(c: &DwaConfig) -> bool {
        c.predict / c.dt <= 64.0
    }
}

#[derive(Arbitrary, Debug, Clone, Copy)]
struct StateInput {
    x: FloatInput,
    y: FloatInput,
    theta: FloatInput,
    v: FloatInput,
    w: FloatInput,
}

impl StateInput {
    fn get(self) -> DwaState {
        DwaState {
            x: self.x.get() * 3.0,
            y: self.y.get() * 3.0,
            theta: self.theta.get() - 8.0,
            v: self.v.get() - 2.0,
            w: self.w.get() - 2.0,
        }
    }
}

#[derive(Arbitrary, Debug, Clone, Copy)]
struct DiscInput {
    x: FloatInput,
    y: FloatInput,
    r: FloatInput,
    vx: FloatInput,
    vy: FloatInput,
}

#[derive(Arbitrary, Debug)]
enum Next {
    /// Integrate the previous command for `dt` (a closed loop).
    Integrate,
    /// Jump to an arbitrary state.
    Jump(StateInput),
    /// A new global path is installed (`reset_path`).
    ResetPath,
}

#[derive(Arbitrary, Debug)]
struct Input {
    config: ConfigInput,
    map: MapInput,
    start: StateInput,
    next: Vec<Next>,
    discs: Vec<DiscInput>,
    path: Vec<(FloatInput, FloatInput)>,
}

const TOL: f32 = 1e-4;

fn close_le(a: f32, b: f32) -> bool {
    a <= b + TOL * b.abs().max(1.0)
}

/// Checks a command against an accepted configuration and the state it answered.
fn check(c: &DwaConfig, s: &DwaState, cmd: &Command) {
    assert!(
        cmd.v.is_finite() && cmd.w.is_finite(),
        "non-finite command {cmd:?}"
    );
    assert!(
        close_le(cmd.w.abs(), c.w_max),
        "|w| = {} above w_max {} ({cmd:?}, state {s:?})",
        cmd.w.abs(),
        c.w_max
    );
    assert!(cmd.admissible <= cmd.samples);
    match cmd.mode {
        Mode::Arrived => assert!(cmd.v == 0.0 && cmd.w == 0.0, "{cmd:?}"),
        Mode::Track => {
            assert!(
                close_le(c.v_min, cmd.v) && close_le(cmd.v, c.v_max),
                "v = {} outside [{}, {}] ({cmd:?}, state {s:?})",
                cmd.v,
                c.v_min,
                c.v_max
            );
            assert!(cmd.admissible > 0 && cmd.samples > 0, "{cmd:?}");
        }
        Mode::Brake => {
            // Decelerating from a speed beyond one step's change: strictly slower, same
            // direction, no turning.
            assert!(cmd.w == 0.0, "{cmd:?}");
            assert!(
                close_le(cmd.v.abs(), s.v.abs()),
                "brake sped up: {cmd:?}, {s:?}"
            );
            assert!(cmd.v * s.v >= 0.0, "brake reversed: {cmd:?}, {s:?}");
        }
        Mode::Rotate => assert!(cmd.v == 0.0, "{cmd:?}"),
        Mode::BackOff => {
            assert!(cmd.w == 0.0, "{cmd:?}");
            assert!(
                close_le(-c.backoff_speed, cmd.v) && cmd.v <= 0.0,
                "back-off speed {} outside [-{}, 0]",
                cmd.v,
                c.backoff_speed
            );
        }
    }
}

fuzz_target!(|input: Input| {
    let config = input.config.build();
    let grid = input.map.build();
    let valid = config.validate();
    let mut dwa = match Dwa::new(config) {
        Ok(d) => {
            assert!(valid.is_ok());
            d
        }
        Err(e) => {
            assert_eq!(e, DwaError::InvalidConfig);
            assert_eq!(valid, Err(DwaError::InvalidConfig));
            return;
        }
    };
    if !ConfigInput::fast(&config) {
        return;
    }
    let discs: Vec<DynamicDisc> = input
        .discs
        .iter()
        .take(4)
        .map(|d| DynamicDisc {
            x: d.x.get() * 3.0,
            y: d.y.get() * 3.0,
            r: d.r.get() - 0.5,
            vx: d.vx.get() - 1.0,
            vy: d.vy.get() - 1.0,
        })
        .collect();
    let path: Vec<Point> = input
        .path
        .iter()
        .take(16)
        .map(|(x, y)| Point::new(x.get() * 3.0, y.get() * 3.0))
        .collect();
    let bad_discs = discs
        .iter()
        .any(|d| ![d.x, d.y, d.vx, d.vy, d.r].iter().all(|v| v.is_finite()) || d.r < 0.0);
    let bad_path = path.is_empty() || path.iter().any(|p| !p.is_finite());

    let mut state = input.start.get();
    for next in input
        .next
        .iter()
        .take(6)
        .chain(core::iter::once(&Next::Integrate))
    {
        let bad_state = ![state.x, state.y, state.theta, state.v, state.w]
            .iter()
            .all(|v| v.is_finite());
        match dwa.step(&state, grid.view(), &discs, &path) {
            Ok(cmd) => {
                assert!(!bad_state && !bad_path && !bad_discs, "bad input accepted");
                check(&config, &state, &cmd);
                match next {
                    Next::Integrate => {
                        let dt = config.dt;
                        state = DwaState {
                            x: state.x + cmd.v * state.theta.cos() * dt,
                            y: state.y + cmd.v * state.theta.sin() * dt,
                            theta: state.theta + cmd.w * dt,
                            v: cmd.v,
                            w: cmd.w,
                        };
                    }
                    Next::Jump(s) => state = s.get(),
                    Next::ResetPath => dwa.reset_path(),
                }
            }
            Err(e) => {
                let expected = if bad_state {
                    DwaError::InvalidState
                } else if bad_path {
                    DwaError::InvalidPath
                } else {
                    DwaError::InvalidObstacle
                };
                assert!(
                    bad_state || bad_path || bad_discs,
                    "good input refused: {e:?}"
                );
                assert_eq!(e, expected);
                match next {
                    Next::Jump(s) => state = s.get(),
                    _ => return,
                }
            }
        }
    }
});

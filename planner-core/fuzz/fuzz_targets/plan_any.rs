//! Every planner on an arbitrary small map with arbitrary endpoints and parameters.
//!
//! Errors are fine; a returned path must be valid (the collision rule, or `Liu2020Igwo`'s walk
//! rule for the loose corner rule), start and end at the requested centres, and agree with
//! exact connectivity; endpoint errors must be the documented ones.
#![no_main]

mod common;

use std::cell::RefCell;

use arbitrary::Arbitrary;
use common::{EndpointInput, FloatInput, MapInput, SizeInput};
use libfuzzer_sys::fuzz_target;
use planner_core::encoding::walk::{CornerRule, validate_walk};
use planner_core::error::PlanError;
use planner_core::path::{self, Path};
use planner_core::planner::aco::AcoParams;
use planner_core::planner::owned::{HostPlanner, PlanChoice};
use planner_core::planner::{Blend, EncodingKind, InitKind, PlanOptions, PlanParams, PlannerKind};
use planner_core::search::check_endpoints;

#[derive(Arbitrary, Debug)]
struct Input {
    map: MapInput,
    start: EndpointInput,
    goal: EndpointInput,
    kind: u8,
    // Swarm parameters.
    population: SizeInput,
    iterations: u8,
    stagnation: Option<u8>,
    seed: u64,
    encoding: u8,
    diffusion: bool,
    prune: bool,
    loose: bool,
    spacing: FloatInput,
    radius: FloatInput,
    walk_steps: SizeInput,
    walk_beta: FloatInput,
    // ACO parameters.
    ants: u8,
    alpha: FloatInput,
    beta: FloatInput,
    rho: FloatInput,
    q: FloatInput,
    aco_iterations: u8,
    aco_stagnation: Option<u8>,
    // Interrupt after this many calls (None: never).
    interrupt_after: Option<u8>,
    // The blended objective: clearance, its weight, the turn weight (None: length alone).
    blend: Option<(FloatInput, FloatInput, FloatInput)>,
}

thread_local! {
    static PLANNER: RefCell<HostPlanner> = RefCell::new(HostPlanner::new());
}

fuzz_target!(|input: Input| {
    let grid = input.map.build();
    let view = grid.view();
    let start = input.start.cell(grid.width(), grid.height());
    let goal = input.goal.cell(grid.width(), grid.height());
    let kind = PlannerKind::ALL[input.kind as usize % PlannerKind::ALL.len()];
    let encoding = [
        EncodingKind::Corridor,
        EncodingKind::Column,
        EncodingKind::Walk,
    ][input.encoding as usize % 3];
    let corner_rule = if input.loose {
        CornerRule::Loose
    } else {
        CornerRule::Strict
    };
    let params = PlanParams {
        encoding,
        population: input.population.get(40),
        iterations: (input.iterations % 21) as u32,
        stagnation: input.stagnation.map(|s| (s % 8) as u32),
        seed: input.seed,
        init: if input.diffusion {
            InitKind::Diffusion
        } else {
            InitKind::Optimizer
        },
        prune: input.prune,
        corner_rule,
        corridor_spacing: input.spacing.get(),
        corridor_radius: input.radius.get(),
        walk_steps: input.walk_steps.get(160),
        walk_beta: input.walk_beta.get(),
        blend: input.blend.map_or(Blend::LENGTH, |(c, w, t)| Blend {
            clearance: c.get(),
            clearance_weight: w.get(),
            turn_weight: t.get(),
        }),
        ..PlanParams::new(planner_core::optim::any::AlgorithmKind::Tclhho)
    };
    let aco = AcoParams {
        ants: (input.ants % 9) as usize,
        alpha: input.alpha.get(),
        beta: input.beta.get(),
        rho: input.rho.get(),
        q: input.q.get(),
        iterations: (input.aco_iterations % 9) as u32,
        stagnation: input.aco_stagnation.map(|s| (s % 4) as u32),
        seed: input.seed,
        prune: input.prune,
    };
    let mut out: Path<1024> = Path::new();
    let mut history = [0.0f32; 32];
    let mut calls = 0u32;
    let limit = input.interrupt_after.map(u32::from);
    let mut interrupt = || {
        calls += 1;
        limit.is_some_and(|l| calls > l)
    };

    PLANNER.with(|p| {
        let mut planner = p.borrow_mut();
        planner.prepare(view).expect("labels fit");
        let endpoint_error = check_endpoints(view, start, goal).err();
        let connected = endpoint_error.is_none() && {
            let labels = planner.labels();
            let (a, b) = (view.index(start).unwrap(), view.index(goal).unwrap());
            labels[a] == labels[b]
        };
        let choice = PlanChoice { kind, params, aco };
        let options = PlanOptions {
            history: &mut history,
            interrupt: Some(&mut interrupt),
        };
        let result = planner.plan(view, start, goal, &choice, &mut out, options);
        if let Some(e) = endpoint_error {
            assert_eq!(result.err(), Some(e), "endpoint error expected");
            return;
        }
        match result {
            Ok(outcome) => {
                assert!(connected, "a path between unconnected cells: {out:?}");
                assert_eq!(out.first(), Some(&start.center()));
                assert_eq!(out.last(), Some(&goal.center()));
                let loose_walk = matches!(kind, PlannerKind::Swarm(_))
                    && encoding == EncodingKind::Walk
                    && corner_rule == CornerRule::Loose
                    && start != goal;
                if loose_walk {
                    assert!(
                        validate_walk(view, &out, CornerRule::Loose),
                        "invalid loose walk {out:?}"
                    );
                } else {
                    assert_eq!(
                        path::validate(view, &out, start, goal),
                        Ok(()),
                        "invalid path {out:?}"
                    );
                }
                assert!(outcome.length.is_finite() && outcome.length >= 0.0);
                let len = path::length(&out);
                assert!(
                    (outcome.length - len).abs() <= 1e-3 * (1.0 + len),
                    "length {} vs {len}",
                    outcome.length
                );
                if let Some(r) = outcome.report {
                    assert!(r.history_len <= history.len());
                }
            }
            Err(PlanError::NoValidPath) => {
                assert!(!connected, "NoValidPath on a connected pair ({kind:?})");
            }
            Err(
                PlanError::StartOutsideMap
                | PlanError::GoalOutsideMap
                | PlanError::StartOccupied
                | PlanError::GoalOccupied,
            ) => panic!("endpoint error on valid endpoints"),
            Err(PlanError::CapacityExceeded | PlanError::InvalidParameters) => {}
            Err(PlanError::BudgetExhausted) => {
                assert!(
                    kind == PlannerKind::Aco || encoding != EncodingKind::Corridor,
                    "the corridor encoding never runs out of budget"
                );
            }
        }
    });
});

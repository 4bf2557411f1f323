//! Every optimizer with arbitrary bounds (NaN, inverted, huge), sizes, seeds and a few
//! iterations on a cheap function: no panic, and every best position lies inside the box.
#![no_main]

mod common;

use arbitrary::Arbitrary;
use common::{FloatInput, SizeInput};
use libfuzzer_sys::fuzz_target;
use planner_core::optim::any::{AlgorithmKind, AnyOptimizer};
use planner_core::optim::functions::{Benchmark, FunctionKind};
use planner_core::optim::{Bounds, Objective, Optimizer, Settings, Stop};

const N: usize = 24;
const D: usize = 8;

#[derive(Arbitrary, Debug)]
struct Input {
    algorithm: u8,
    dim: SizeInput,
    lower: [FloatInput; D],
    width: [FloatInput; D],
    population: SizeInput,
    iterations: u8,
    steps: u8,
    seed: u64,
    function: u8,
    /// Objective quirk: 0 sphere, 1 benchmark, 2 NaN everywhere, 3 constant, 4 +inf.
    objective: u8,
    use_run: bool,
    stop_target: Option<FloatInput>,
    stop_evals: Option<u16>,
    stop_stagnation: Option<u8>,
    initial: Option<[FloatInput; D]>,
}

fn check_inside(bounds: &Bounds<D>, x: &[f32]) {
    assert_eq!(x.len(), bounds.dim());
    for ((v, l), u) in x.iter().zip(bounds.lower()).zip(bounds.upper()) {
        assert!(*v >= *l && *v <= *u, "best {x:?} outside [{l}, {u}]");
    }
}

fuzz_target!(|input: Input| {
    let kind = AlgorithmKind::ALL[input.algorithm as usize % AlgorithmKind::ALL.len()];
    let dim = input.dim.get(D + 1).min(D);
    let mut lower = [0.0f32; D];
    let mut upper = [0.0f32; D];
    for i in 0..D {
        lower[i] = input.lower[i].get() - 8.0;
        upper[i] = lower[i] + input.width[i].get();
    }
    let Ok(bounds) = Bounds::<D>::from_slices(&lower[..dim], &upper[..dim]) else {
        return;
    };
    assert!(dim >= 1 && dim <= D);
    let settings = Settings {
        population: input.population.get(N + 2),
        iterations: (input.iterations % 16) as u32,
        seed: input.seed,
    };
    let Ok(mut opt) = AnyOptimizer::<N, D>::new(kind, settings, &bounds) else {
        return;
    };
    let function = [
        FunctionKind::Sphere,
        FunctionKind::Rastrigin,
        FunctionKind::Rosenbrock,
        FunctionKind::Ackley,
    ][input.function as usize % 4];
    let mut bench = Benchmark::new(function, dim, 0.0, input.seed).ok();
    let quirk = input.objective % 5;
    let mut objective = |x: &[f32]| -> f32 {
        assert_eq!(x.len(), dim);
        assert!(x.iter().all(|v| v.is_finite()), "NaN/inf reached the objective: {x:?}");
        match quirk {
            0 => x.iter().map(|v| v * v).sum(),
            1 => bench.as_mut().map_or(0.0, |b| b.cost(x)),
            2 => f32::NAN,
            3 => 1.0,
            _ => f32::INFINITY,
        }
    };
    let initial_rows = input.initial.map(|row| {
        let mut r = [0.0f32; D];
        for (v, f) in r.iter_mut().zip(row) {
            *v = f.get();
        }
        r
    });
    let refs: Option<[&[f32]; 1]> = initial_rows.as_ref().map(|r| [&r[..dim]]);
    let initial = refs.as_ref().map(|r| &r[..]);
    if input.use_run {
        let stop = Stop {
            max_iterations: None,
            max_evaluations: input.stop_evals.map(u64::from),
            target_cost: input.stop_target.map(FloatInput::get),
            stagnation: input.stop_stagnation.map(|s| (s % 6) as u32),
        };
        let mut history = [0.0f32; 8];
        if let Ok(report) = opt.run(&mut objective, initial, &stop, &mut history) {
            assert!(report.iterations <= settings.iterations);
            assert!(report.history_len <= history.len());
            check_inside(&bounds, opt.best_position());
        }
        return;
    }
    if opt.init(&mut objective, initial).is_err() {
        return;
    }
    check_inside(&bounds, opt.best_position());
    for _ in 0..input.steps % 16 {
        let before = opt.best_cost();
        if opt.step(&mut objective).is_err() {
            assert!(opt.iteration() >= opt.horizon(), "step failed before the horizon");
            break;
        }
        check_inside(&bounds, opt.best_position());
        // The best never gets worse (NaN costs count as +inf).
        let after = opt.best_cost();
        assert!(!(after > before), "best cost rose from {before} to {after}");
    }
});

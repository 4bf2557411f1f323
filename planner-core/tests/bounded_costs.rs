//! Bounded evaluations (`Encoding::cost_below`, `Objective::cost_below`) change how much work
//! an evaluation does, never what an optimizer decides:
//! - the contract: below the bound the result is the exact cost, bit for bit; otherwise it is
//!   at or above the bound;
//! - runs of HHO, TCLHHO, GWO and IGWO through the bounded adapter (`encoding::Costs`) are
//!   bit-identical to runs through a plain closure that always computes the exact cost.

use planner_core::encoding::column::ColumnEncoding;
use planner_core::encoding::corridor::{CorridorEncoding, Station};
use planner_core::encoding::{Costs, Encoding};
use planner_core::grid::words_for;
use planner_core::maps::{MapKind, PaperMap, lei2024_warehouse};
use planner_core::optim::gwo::{Gwo, GwoParams};
use planner_core::optim::hho::{Hho, HhoParams};
use planner_core::optim::{Bounds, Optimizer, Settings, Stop};
use planner_core::path::Path;
use planner_core::search::astar::{self, AStarNode, OpenSlot};

const WORDS: usize = words_for(40, 40);

fn warehouse() -> PaperMap<WORDS> {
    lei2024_warehouse::<WORDS>(MapKind::Warehouse, 40).unwrap()
}

fn guide(map: &PaperMap<WORDS>) -> Path<256> {
    let mut nodes = vec![AStarNode::EMPTY; 40 * 40];
    let mut open = vec![OpenSlot::EMPTY; astar::open_capacity(40 * 40)];
    let mut p = Path::new();
    astar::plan(
        map.grid.view(),
        map.start,
        map.goal,
        &mut nodes,
        &mut open,
        &mut p,
    )
    .unwrap();
    p
}

struct XorShift(u64);

impl XorShift {
    fn unit(&mut self) -> f32 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        (self.0 >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// Random points of the encoding's box, some pulled towards a base point so that costs fall
/// on both sides of the bounds; bounds around the exact cost, including the cost itself.
fn check_contract<E: Encoding>(enc: &mut E, seed: u64) {
    let mut rng = XorShift(seed);
    let dim = enc.dim();
    let base: Vec<f32> = (0..dim)
        .map(|i| {
            let (lo, hi) = enc.bounds(i);
            lo + rng.unit() * (hi - lo)
        })
        .collect();
    let (mut below, mut above) = (0, 0);
    for k in 0..3000 {
        let spread = if k % 2 == 0 { 1.0 } else { 0.05 };
        let x: Vec<f32> = (0..dim)
            .map(|i| {
                let (lo, hi) = enc.bounds(i);
                (base[i] + spread * (rng.unit() - 0.5) * (hi - lo)).clamp(lo, hi)
            })
            .collect();
        let exact = enc.cost(&x);
        let factor = [0.9, 0.99, 0.999, 1.0, 1.001, 1.01, 1.1][k % 7];
        let bound = match k % 11 {
            0 => exact,
            1 => f32::from_bits(exact.to_bits() + 1),
            2 => f32::from_bits(exact.to_bits() - 1),
            _ => exact * factor,
        };
        let got = enc.cost_below(&x, bound);
        if exact < bound {
            assert_eq!(got.to_bits(), exact.to_bits(), "x {x:?} bound {bound}");
            below += 1;
        } else {
            assert!(
                got >= bound,
                "x {x:?}: {got} < bound {bound} (cost {exact})"
            );
            assert!(
                got <= exact,
                "x {x:?}: {got} is not a lower bound of {exact}"
            );
            above += 1;
        }
    }
    assert!(below > 500 && above > 500, "{below} below, {above} above");
}

/// The corridor over the warehouse's A* route, stations every `spacing` cells, at most
/// `max_vars` variables (the station buffer holds them all).
fn corridor_contract(spacing: f32, max_vars: usize, seed: u64) -> usize {
    let map = warehouse();
    let guide = guide(&map);
    let mut stations = vec![Station::EMPTY; max_vars + 2];
    let mut enc = CorridorEncoding::build(
        map.grid.view(),
        &guide,
        spacing,
        5.0,
        max_vars,
        &mut stations,
    )
    .unwrap();
    check_contract(&mut enc, seed);
    enc.dim()
}

#[test]
fn corridor_cost_below_keeps_its_contract() {
    let dim = corridor_contract(8.0, 64, 7);
    assert!(dim > 5, "{dim}");
}

/// More legs than a leg set holds (64): the legs beyond are checked in order and lift the
/// bound only when reached.
#[test]
fn corridor_cost_below_keeps_its_contract_beyond_64_legs() {
    let dim = corridor_contract(1.0, 128, 13);
    assert!(dim + 1 > 64, "{} legs", dim + 1);
}

/// Variables beyond `[-1, 1]` or NaN (never from an optimizer, which keeps them in the box)
/// are clamped, or taken as 0, by the bounded evaluation as by the exact one.
#[test]
fn corridor_cost_below_keeps_its_contract_out_of_range() {
    let map = warehouse();
    let guide = guide(&map);
    let mut stations = vec![Station::EMPTY; 66];
    let mut enc =
        CorridorEncoding::build(map.grid.view(), &guide, 8.0, 5.0, 64, &mut stations).unwrap();
    let mut rng = XorShift(21);
    let mut outside = 0;
    for k in 0..2000 {
        let reach = if k % 2 == 0 { 3.0 } else { 1.9 };
        let x: Vec<f32> = (0..enc.dim())
            .map(|i| match (k + i) % 37 {
                0 => f32::NAN,
                _ => reach * (rng.unit() - 0.5),
            })
            .collect();
        outside += usize::from(x.iter().any(|v| v.is_nan() || v.abs() > 1.0));
        let exact = enc.cost(&x);
        assert!(exact.is_finite(), "{x:?}");
        for bound in [exact, exact * 1.01, exact * 0.99] {
            let got = enc.cost_below(&x, bound);
            if exact < bound {
                assert_eq!(got.to_bits(), exact.to_bits(), "x {x:?} bound {bound}");
            } else {
                assert!(
                    got >= bound && got <= exact,
                    "x {x:?}: {got}, bound {bound}"
                );
            }
        }
    }
    assert!(outside > 1000, "{outside}");
}

#[test]
fn column_cost_below_keeps_its_contract() {
    let map = warehouse();
    let mut enc = ColumnEncoding::new(map.grid.view(), map.start, map.goal).unwrap();
    check_contract(&mut enc, 11);
}

/// Everything a run decides, as bits.
#[derive(Debug, PartialEq)]
struct Trace {
    best_cost: u32,
    best: Vec<u32>,
    evaluations: u64,
    best_iteration: u32,
}

fn trace<O: Optimizer>(opt: &O) -> Trace {
    Trace {
        best_cost: opt.best_cost().to_bits(),
        best: opt.best_position().iter().map(|v| v.to_bits()).collect(),
        evaluations: opt.evaluations(),
        best_iteration: opt.best_iteration(),
    }
}

/// Runs `make()` once through `Costs` (bounded) and once through a closure (exact).
fn same_run<E: Encoding, O: Optimizer>(enc: &mut E, mut make: impl FnMut(&Bounds<64>) -> O) {
    let dim = enc.dim();
    let lower: Vec<f32> = (0..dim).map(|i| enc.bounds(i).0).collect();
    let upper: Vec<f32> = (0..dim).map(|i| enc.bounds(i).1).collect();
    let bounds = Bounds::<64>::from_slices(&lower, &upper).unwrap();
    let stop = Stop::default();
    let mut bounded = make(&bounds);
    bounded.run(&mut Costs(enc), None, &stop, &mut []).unwrap();
    let mut exact = make(&bounds);
    exact
        .run(&mut |x: &[f32]| enc.cost(x), None, &stop, &mut [])
        .unwrap();
    assert_eq!(trace(&bounded), trace(&exact));
}

fn settings(seed: u64) -> Settings {
    Settings {
        population: 30,
        iterations: 200,
        seed,
    }
}

#[test]
fn bounded_runs_are_bit_identical_to_exact_runs() {
    let map = warehouse();
    let guide = guide(&map);
    let mut stations = [Station::EMPTY; 66];
    let mut corridor =
        CorridorEncoding::build(map.grid.view(), &guide, 8.0, 5.0, 64, &mut stations).unwrap();
    let mut column = ColumnEncoding::new(map.grid.view(), map.start, map.goal).unwrap();
    for seed in [1, 2] {
        for params in [HhoParams::hho(), HhoParams::tclhho()] {
            let make = |b: &Bounds<64>| Hho::<30, 64>::new(settings(seed), b, params).unwrap();
            same_run(&mut corridor, make);
            same_run(&mut column, make);
        }
        let greedy = GwoParams {
            greedy: true,
            ..GwoParams::igwo()
        };
        for params in [GwoParams::gwo(), GwoParams::igwo(), greedy] {
            let make = |b: &Bounds<64>| Gwo::<30, 64>::new(settings(seed), b, params).unwrap();
            same_run(&mut corridor, make);
            same_run(&mut column, make);
        }
    }
}

//! Harris Hawks Optimization (Heidari et al. 2019) and TCLHHO (`Lei2024Warehouse`), one implementation.
//!
//! The authors' `HHO.m` is the oracle: in-place updates, per-hawk scalars, `E0 ~ U(-1, 1)`
//! redrawn per hawk and iteration, `|E| >= 1` explores, otherwise soft/hard besiege and the two
//! progressive rapid dives (`Y` first, `Z = Y + S .* Levy` only if `Y` did not improve; neither
//! replaces the hawk unless it improves). Differences from `HHO.m`, all asked by SPEC: every
//! new position is clamped and evaluated at once (so the rabbit follows every improving
//! evaluation and the final moves are not lost), and the hawk's cost is cached instead of being
//! re-evaluated in the dive comparisons. `Z` is built from the unclamped `Y`, as in `HHO.m`.
//! The Levy factor defaults to the paper's 0.01 (eq. 9, SPEC); `HHO.m`'s `Levy` has none
//! (factor 1, [`HhoParams::levy_scale`]): on the shifted 30-D sphere the two give the same
//! median.
//!
//! mealpy's `OriginalHHO` is not `HHO.m`: it takes `X_m` as the mean of *all* coordinates of
//! all hawks (a scalar, `np.mean` without an axis), updates synchronously with a greedy
//! selection of the whole population, and scales the Levy dive by `S ~ U(lb, ub)`. Its better
//! median on the sphere shifted to `(37.5, ..., 37.5)` comes from the scalar mean, which
//! exploits an optimum whose coordinates are all equal (it does not help when they differ);
//! see `host-sim/bench/mealpy_vs_ours.sh`.
//!
//! TCLHHO is HHO with [`HhoParams::tclhho`]: Tent initialisation, exponential escape energy
//! (`a = 1.2`), and the Cauchy / opposition mutation of the rabbit once per iteration.
//!
//! ```
//! use planner_core::optim::{Bounds, Optimizer, Settings, Stop};
//! use planner_core::optim::hho::{Hho, HhoParams};
//!
//! let bounds = Bounds::<10>::uniform(10, -100.0, 100.0)?;
//! let settings = Settings { population: 30, iterations: 300, seed: 1 };
//! let mut hawks = Hho::<30, 10>::new(settings, &bounds, HhoParams::tclhho())?;
//! let mut shifted = |x: &[f32]| x.iter().map(|v| (v - 37.5) * (v - 37.5)).sum::<f32>();
//! let report = hawks.run(&mut shifted, None, &Stop::default(), &mut [])?;
//! assert!(report.best_cost < 1.0); // HHO steps scale with |rabbit|: shifted optima cost precision
//! assert!(report.evaluations > 30 * 300); // dives and mutations evaluate extra points
//! # Ok::<(), planner_core::optim::OptimError>(())
//! ```

use super::schedule::{EscapeEnergy, Schedule};
use super::{
    Bounds, Initialisation, Objective, OptimError, Optimizer, Population, Settings, SwarmState,
    check_param, clamp_into, swarm_accessors,
};

/// Where TCLHHO's Cauchy / opposition mutation of the rabbit happens.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Mutation {
    /// No mutation (HHO).
    Off,
    /// Once per iteration after all hawks moved, on a copy of the rabbit, kept only if better
    /// (`Lei2024Warehouse` text, section 2.3; the default for TCLHHO).
    AfterUpdates,
    /// Literal reading of `Lei2024Warehouse`'s algorithm 1: a hawk with `|E| >= 1` takes the mutated
    /// rabbit *instead of* exploring (unconditionally, like the exploration it replaces).
    ReplacesExploration,
}

/// How the opposition branch of the mutation (`P < 0.5`) is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum OppositionForm {
    /// `Xo = K1 (ub + lb) - Xb`, `X' = Xo + K2 (Xb - Xo)` (`Lei2024Warehouse` eq. 17-18, SPEC).
    Interpolated,
    /// Literal `Lei2024Warehouse` eq. 19: `X' = K2 (Xb - (K1 (ub + lb) - Xb))`.
    Literal,
}

/// Options of the HHO family.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct HhoParams {
    /// Initial population.
    pub init: Initialisation,
    /// The escape energy schedule `E1`.
    pub energy: EscapeEnergy,
    /// The Cauchy / opposition mutation of the rabbit.
    pub mutation: Mutation,
    /// The opposition formula of the mutation.
    pub opposition: OppositionForm,
    /// Factor on the Mantegna Levy step (the paper's 0.01).
    pub levy_scale: f32,
    /// How the hawks' mean position `X_m` is taken.
    pub mean: HawkMean,
}

/// The hawks' mean position `X_m` of the exploration and the hard-besiege dives.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum HawkMean {
    /// Per dimension, as `HHO.m` and the paper (`mean(X)` over hawks): SPEC's reading.
    #[default]
    PerDimension,
    /// One scalar, the mean of every coordinate of every hawk, used in every dimension
    /// (mealpy's `np.mean(pop)` without an axis). Only for like-for-like comparisons with
    /// mealpy: it pools all coordinates, which helps only when the optimum's coordinates are
    /// all equal (a sphere shifted along the diagonal).
    Scalar,
}

impl HhoParams {
    /// Plain HHO: uniform init, `E1 = 2 (1 - t/T)`, no mutation.
    pub const fn hho() -> Self {
        Self {
            init: Initialisation::Uniform,
            energy: EscapeEnergy::Linear,
            mutation: Mutation::Off,
            opposition: OppositionForm::Interpolated,
            levy_scale: 0.01,
            mean: HawkMean::PerDimension,
        }
    }

    /// TCLHHO as SPEC resolves `Lei2024Warehouse`: Tent init, `a = 1.2`, mutation after the updates.
    pub const fn tclhho() -> Self {
        Self {
            init: Initialisation::TENT,
            energy: EscapeEnergy::TCLHHO,
            mutation: Mutation::AfterUpdates,
            opposition: OppositionForm::Interpolated,
            levy_scale: 0.01,
            mean: HawkMean::PerDimension,
        }
    }

    /// TCLHHO read literally from algorithm 1: `a = 0.5`, mutation in place of exploration,
    /// eq. 19's opposition.
    pub const fn tclhho_literal() -> Self {
        Self {
            init: Initialisation::TENT,
            energy: EscapeEnergy::TCLHHO_PSEUDOCODE,
            mutation: Mutation::ReplacesExploration,
            opposition: OppositionForm::Literal,
            levy_scale: 0.01,
            mean: HawkMean::PerDimension,
        }
    }

    fn validate(&self) -> Result<(), OptimError> {
        self.init.validate()?;
        self.energy.validate()?;
        check_param(self.levy_scale, 0.0, f32::MAX, "levy_scale")
    }
}

/// HHO / TCLHHO with capacity `N` hawks of `D` dimensions.
#[derive(Debug, Clone)]
pub struct Hho<const N: usize, const D: usize> {
    swarm: SwarmState<N, D>,
    params: HhoParams,
    /// Running sum of the hawks' positions, for the mean `X_m` of the in-place population.
    sum: [f32; D],
    /// Candidate `Y` (and the new position of non-dive moves).
    y: [f32; D],
    /// Candidate `Z`.
    z: [f32; D],
    /// Whether hawk `i`'s cached cost is only a lower bound. With a
    /// [`pure`](Objective::pure) objective a hawk that moves unconditionally is evaluated
    /// only against the rabbit (its cost matters again only if it dives later, and is
    /// recomputed then unless `Y` beats the bound); otherwise every cost is exact. (False
    /// for exact, so that an unconfigured instance is all zero bytes, see
    /// [`SwarmState::unconfigured`](super::SwarmState::unconfigured).)
    bounded: [bool; N],
}

impl<const N: usize, const D: usize> Hho<N, D> {
    /// Validates and builds; call [`Optimizer::init`] next. Needs at least 2 hawks.
    pub fn new(
        settings: Settings,
        bounds: &Bounds<D>,
        params: HhoParams,
    ) -> Result<Self, OptimError> {
        let mut s = Self::unconfigured();
        s.configure(settings, bounds, params)?;
        Ok(s)
    }

    /// An unconfigured instance for `const`/`static` initialisers (firmware keeps the state
    /// in a `static` and calls [`configure`](Self::configure) on it, so no large temporary
    /// passes through the stack); `init` fails until it is configured.
    pub const fn unconfigured() -> Self {
        Self {
            swarm: SwarmState::unconfigured(),
            // Zero where `hho()` is not; `configure` sets the real ones.
            params: HhoParams {
                levy_scale: 0.0,
                ..HhoParams::hho()
            },
            sum: [0.0; D],
            y: [0.0; D],
            z: [0.0; D],
            bounded: [false; N],
        }
    }

    /// Validates and takes a configuration in place (needs at least 2 members); on
    /// error nothing changes. Call [`Optimizer::init`] next.
    pub fn configure(
        &mut self,
        settings: Settings,
        bounds: &Bounds<D>,
        params: HhoParams,
    ) -> Result<(), OptimError> {
        params.validate()?;
        self.swarm.configure(settings, bounds, 2)?;
        self.params = params;
        Ok(())
    }

    /// The options in use.
    pub fn params(&self) -> &HhoParams {
        &self.params
    }

    fn recompute_sum(&mut self) {
        self.swarm.pop.sum_positions(&mut self.sum);
    }

    /// Moves hawk `i` to `self.y` whatever its cost and evaluates it there (the mutated
    /// rabbit that replaces exploration in [`Mutation::ReplacesExploration`]).
    fn move_hawk_unconditionally<O: Objective + ?Sized>(&mut self, objective: &mut O, i: usize) {
        // The cost is set by `evaluate_moved`.
        move_hawk(
            &mut self.sum,
            &mut self.swarm.pop,
            i,
            &self.y,
            f32::INFINITY,
        );
        self.evaluate_moved(objective, i);
    }

    /// Moves hawk `i` in place, coordinate `d` to `new(rabbit_d, x_d, sum_d, bounds_d)`
    /// clamped, keeping the running sum: a besieging or exploring hawk moves whatever the
    /// cost (a copy through `Y` cost more than the move itself on a Cortex-M4). Each
    /// coordinate reads only the same coordinate, before it is written.
    #[inline(always)]
    fn move_in_place(&mut self, i: usize, new: impl Fn(f32, f32, f32, (f32, f32)) -> f32) {
        let sw = &mut self.swarm;
        for (((x, rb), s), (l, u)) in sw
            .pop
            .position_mut(i)
            .iter_mut()
            .zip(sw.tracker.best())
            .zip(self.sum.iter_mut())
            .zip(sw.bounds.pairs())
        {
            let v = clamp_into(new(*rb, *x, *s, (l, u)), l, u);
            *s += v - *x;
            *x = v;
        }
    }

    /// Evaluates hawk `i` after a move whatever the cost. With a pure objective, only
    /// against the rabbit: the cost is exact when it beats the rabbit (or there was none),
    /// else possibly a lower bound (see `bounded`).
    #[inline(always)]
    fn evaluate_moved<O: Objective + ?Sized>(&mut self, objective: &mut O, i: usize) {
        let sw = &mut self.swarm;
        let pure = objective.pure();
        let rabbit = sw.tracker.best_cost;
        let bound = if pure {
            f32::NEG_INFINITY
        } else {
            f32::INFINITY
        };
        let cost = sw
            .tracker
            .evaluate_below(objective, sw.pop.position(i), bound);
        sw.pop.set_cost(i, cost);
        if pure && let Some(b) = self.bounded.get_mut(i) {
            *b = !(rabbit == f32::INFINITY || cost < rabbit);
        }
    }

    /// Hawk `i`'s exact cost, recomputed if only a lower bound is cached (not counted as an
    /// evaluation: it repeats one, and a pure objective gives the same value).
    fn exact_cost<O: Objective + ?Sized>(&mut self, objective: &mut O, i: usize) -> f32 {
        if self.bounded.get(i).copied().unwrap_or(false) {
            let raw = objective.cost(self.swarm.pop.position(i));
            let cost = if raw.is_nan() { f32::INFINITY } else { raw };
            self.swarm.pop.set_cost(i, cost);
            self.mark_exact(i);
        }
        self.swarm.pop.cost(i)
    }

    /// A dive moves hawk `i` to `self.y`, whose exact cost is `cost`, keeping the running sum.
    fn move_hawk_to_y(&mut self, i: usize, cost: f32) {
        move_hawk(&mut self.sum, &mut self.swarm.pop, i, &self.y, cost);
        self.mark_exact(i);
    }

    /// [`move_hawk_to_y`](Self::move_hawk_to_y) for `self.z` (`Y` is rewritten before its
    /// next use, so no swap).
    fn move_hawk_to_z(&mut self, i: usize, cost: f32) {
        move_hawk(&mut self.sum, &mut self.swarm.pop, i, &self.z, cost);
        self.mark_exact(i);
    }

    /// Hawk `i`'s cached cost is exact (a dive that moved it below its known lower bound
    /// had left it marked, and its next dive recomputed it).
    fn mark_exact(&mut self, i: usize) {
        if let Some(b) = self.bounded.get_mut(i) {
            *b = false;
        }
    }

    /// Writes the mutated rabbit into `self.y` (draws `P`, then Cauchy or `K1, K2`).
    fn mutate_rabbit(&mut self) {
        let sw = &mut self.swarm;
        let p = sw.rng.unit();
        let best = sw.tracker.best();
        if p >= 0.5 {
            for ((y, b), (l, u)) in self.y.iter_mut().zip(best).zip(sw.bounds.pairs()) {
                *y = clamp_into(b + b * sw.rng.cauchy(), l, u);
            }
        } else {
            let k1 = sw.rng.unit();
            let k2 = sw.rng.unit();
            for ((y, b), (l, u)) in self.y.iter_mut().zip(best).zip(sw.bounds.pairs()) {
                let xo = k1 * (u + l) - b;
                let v = match self.params.opposition {
                    OppositionForm::Interpolated => xo + k2 * (b - xo),
                    OppositionForm::Literal => k2 * (b - xo),
                };
                *y = clamp_into(v, l, u);
            }
        }
    }

    /// Evaluates `Y` where only a cost below `bound` (or the rabbit's) matters. Every loop
    /// that writes a candidate clamps it into the box as it goes (one pass instead of a second
    /// one over the candidate), so it is evaluated as it is.
    #[inline(always)]
    fn evaluate_y_below<O: Objective + ?Sized>(&mut self, objective: &mut O, bound: f32) -> f32 {
        let dim = self.swarm.dim();
        let y = self.y.get(..dim).unwrap_or(&[]);
        self.swarm.tracker.evaluate_below(objective, y, bound)
    }

    /// `Y`'s cost below `bound` once more, for a dive that evaluated it against a lower
    /// bound of the hawk's cost (not counted: it repeats that evaluation; the caller knows
    /// that `Y` does not beat the rabbit).
    fn repeat_y_below<O: Objective + ?Sized>(&mut self, objective: &mut O, bound: f32) -> f32 {
        let dim = self.swarm.dim();
        let y = self.y.get(..dim).unwrap_or(&[]);
        let raw = objective.cost_below(y, bound);
        if raw.is_nan() { f32::INFINITY } else { raw }
    }

    /// [`evaluate_y_below`](Self::evaluate_y_below) for `Z`.
    #[inline(always)]
    fn evaluate_z_below<O: Objective + ?Sized>(&mut self, objective: &mut O, bound: f32) -> f32 {
        let dim = self.swarm.dim();
        let z = self.z.get(..dim).unwrap_or(&[]);
        self.swarm.tracker.evaluate_below(objective, z, bound)
    }

    /// `X_m` as one number ([`HawkMean::Scalar`]), or `None` for the per-dimension mean.
    fn scalar_mean(&self) -> Option<f32> {
        match self.params.mean {
            HawkMean::PerDimension => None,
            HawkMean::Scalar => {
                let dim = self.swarm.dim();
                let total: f32 = self.sum.iter().take(dim).sum();
                Some(total / (self.swarm.n() * dim.max(1)) as f32)
            }
        }
    }

    /// `|E| >= 1`: perch on a random hawk or relative to the rabbit and the mean, in place
    /// (see [`move_in_place`](Self::move_in_place); the perch on another hawk reads the same
    /// coordinate of that hawk).
    fn explore(&mut self, i: usize) {
        let n = self.swarm.n();
        let inv_n = 1.0 / n as f32;
        let sw = &mut self.swarm;
        let q = sw.rng.unit();
        let k = sw.rng.index(n);
        if q < 0.5 {
            let r1 = sw.rng.unit();
            let r2 = sw.rng.unit();
            let perch = |xr: f32, x: f32| xr - r1 * libm::fabsf(xr - 2.0 * r2 * x);
            let step = |x: &mut f32, s: &mut f32, xr: f32, (l, u): (f32, f32)| {
                let v = clamp_into(perch(xr, *x), l, u);
                *s += v - *x;
                *x = v;
            };
            if let Some((other, hawk)) = sw.pop.read_write(k, i) {
                for (((x, s), xr), b) in hawk
                    .iter_mut()
                    .zip(self.sum.iter_mut())
                    .zip(other)
                    .zip(sw.bounds.pairs())
                {
                    step(x, s, *xr, b);
                }
            } else {
                // The hawk perches relative to itself.
                for ((x, s), b) in sw
                    .pop
                    .position_mut(i)
                    .iter_mut()
                    .zip(self.sum.iter_mut())
                    .zip(sw.bounds.pairs())
                {
                    step(x, s, *x, b);
                }
            }
        } else {
            let r3 = sw.rng.unit();
            let r4 = sw.rng.unit();
            let scalar_mean = self.scalar_mean();
            self.move_in_place(i, |rb, _, s, (l, u)| {
                let m = match scalar_mean {
                    Some(m) => m,
                    None => s * inv_n,
                };
                (rb - m) - r3 * (l + r4 * (u - l))
            });
        }
    }

    /// The dive target `rabbit - E |J rabbit - base|` into `self.y` and `self.z`, `base` =
    /// hawk or mean. `Z` starts from the unclamped `Y` (see [`dive`](Self::dive)): writing
    /// both here saves copying the whole capacity-sized `Y` afterwards.
    fn dive_target(&mut self, i: usize, e: f32, j: f32, from_mean: bool) {
        let inv_n = 1.0 / self.swarm.n() as f32;
        let scalar_mean = self.scalar_mean();
        let sw = &self.swarm;
        let rabbit = sw.tracker.best();
        let target = |rb: f32, base: f32| rb - e * libm::fabsf(j * rb - base);
        let yz = self
            .y
            .iter_mut()
            .zip(self.z.iter_mut())
            .zip(rabbit)
            .zip(sw.bounds.pairs());
        // One loop per kind of base, so that the loops carry no per-coordinate choice. `Y` is
        // clamped, `Z` keeps the unclamped value.
        match (from_mean, scalar_mean) {
            (false, _) => {
                for ((((y, z), rb), (l, u)), x) in yz.zip(sw.pop.position(i)) {
                    *z = target(*rb, *x);
                    *y = clamp_into(*z, l, u);
                }
            }
            (true, Some(m)) => {
                for (((y, z), rb), (l, u)) in yz {
                    *z = target(*rb, m);
                    *y = clamp_into(*z, l, u);
                }
            }
            (true, None) => {
                for ((((y, z), rb), (l, u)), s) in yz.zip(&self.sum) {
                    *z = target(*rb, s * inv_n);
                    *y = clamp_into(*z, l, u);
                }
            }
        }
    }

    fn dive<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        i: usize,
        e: f32,
        from_mean: bool,
    ) {
        let j = 2.0 * (1.0 - self.swarm.rng.unit());
        // `Z` starts from the unclamped `Y`, as in `HHO.m` (`X2 = Rabbit - E |J Rabbit - X|
        // + S .* Levy`): evaluating `Y` clamps it in place, so `dive_target` writes both.
        self.dive_target(i, e, j, from_mean);
        // A dive only replaces the hawk by a better point: costs at or above the hawk's are
        // never used, so the objective may stop as soon as it knows.
        let current = if self.bounded.get(i).copied().unwrap_or(false) {
            // Only a lower bound of the hawk's cost is known (see `bounded`). `Y` below it
            // beats the hawk whatever its exact cost, which then need not be recomputed (a
            // third of the dives of bounded hawks in a TCLHHO plan).
            let known = self.swarm.pop.cost(i);
            let fy = self.evaluate_y_below(objective, known);
            if fy < known {
                self.move_hawk_to_y(i, fy);
                return;
            }
            let current = self.exact_cost(objective, i);
            if fy < current {
                // `fy` is a lower bound of `Y`'s cost: judge `Y` against the exact cost. Not
                // a new evaluation but the same one with a higher bound, and no change to
                // the rabbit: `Y` costs at least `fy >= known`, itself at least the rabbit's.
                let fy = self.repeat_y_below(objective, current);
                if fy < current {
                    self.move_hawk_to_y(i, fy);
                    return;
                }
            }
            current
        } else {
            let current = self.swarm.pop.cost(i);
            let fy = self.evaluate_y_below(objective, current);
            if fy < current {
                self.move_hawk_to_y(i, fy);
                return;
            }
            current
        };
        let scale = self.params.levy_scale;
        let dim = self.swarm.dim();
        // The steps `S .* Levy` first, into `Y` (rejected, and rewritten before its next
        // use), from a local copy of the generator, then `Z`: with the bounds and `Z` in the
        // same loop, the generator's state and the ziggurat's tables did not fit in a
        // Cortex-M4's registers and went through the stack for every draw.
        let mut rng = self.swarm.rng.clone();
        for step in self.y.iter_mut().take(dim) {
            let s = rng.unit();
            *step = s * scale * rng.levy();
        }
        self.swarm.rng = rng;
        for ((z, step), (l, u)) in self
            .z
            .iter_mut()
            .zip(&self.y)
            .take(dim)
            .zip(self.swarm.bounds.pairs())
        {
            *z = clamp_into(*z + step, l, u);
        }
        let fz = self.evaluate_z_below(objective, current);
        if fz < current {
            self.move_hawk_to_z(i, fz);
        }
    }
}

/// Moves hawk `i` to `to` with cost `cost`, keeping the running `sum` of the positions.
///
/// One pass: each coordinate updates the sum from the old value and is then overwritten.
fn move_hawk<const N: usize, const D: usize>(
    sum: &mut [f32; D],
    pop: &mut Population<N, D>,
    i: usize,
    to: &[f32; D],
    cost: f32,
) {
    for ((s, old), new) in sum.iter_mut().zip(pop.position_mut(i)).zip(to) {
        *s += new - *old;
        *old = *new;
    }
    pop.set_cost(i, cost);
}

impl<const N: usize, const D: usize> Optimizer for Hho<N, D> {
    fn init<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        initial: Option<&[&[f32]]>,
    ) -> Result<(), OptimError> {
        self.bounded = [false; N];
        self.swarm.initialise(objective, self.params.init, initial)
    }

    fn step<O: Objective + ?Sized>(&mut self, objective: &mut O) -> Result<(), OptimError> {
        let t = self.swarm.begin_step()?;
        let e1 = self.params.energy.value(t, self.swarm.settings.iterations);
        self.recompute_sum();
        for i in 0..self.swarm.n() {
            let e = e1 * (2.0 * self.swarm.rng.unit() - 1.0);
            let abs_e = libm::fabsf(e);
            if abs_e >= 1.0 {
                if self.params.mutation == Mutation::ReplacesExploration {
                    self.mutate_rabbit();
                    self.move_hawk_unconditionally(objective, i);
                } else {
                    self.explore(i);
                    self.evaluate_moved(objective, i);
                }
                continue;
            }
            let r = self.swarm.rng.unit();
            match (r >= 0.5, abs_e >= 0.5) {
                (true, false) => {
                    // Hard besiege.
                    self.move_in_place(i, |rb, x, _, _| rb - e * libm::fabsf(rb - x));
                    self.evaluate_moved(objective, i);
                }
                (true, true) => {
                    // Soft besiege.
                    let j = 2.0 * (1.0 - self.swarm.rng.unit());
                    self.move_in_place(i, |rb, x, _, _| (rb - x) - e * libm::fabsf(j * rb - x));
                    self.evaluate_moved(objective, i);
                }
                (false, true) => self.dive(objective, i, e, false),
                (false, false) => self.dive(objective, i, e, true),
            }
        }
        if self.params.mutation == Mutation::AfterUpdates {
            // The tracker keeps the mutant as the new rabbit only if it is better, so only a
            // cost below the rabbit's matters.
            self.mutate_rabbit();
            self.evaluate_y_below(objective, f32::NEG_INFINITY);
        }
        Ok(())
    }

    swarm_accessors!();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::Stop;

    fn shifted_sphere(x: &[f32]) -> f32 {
        x.iter().map(|v| (v - 37.5) * (v - 37.5)).sum()
    }

    /// `N` hawks (the whole capacity) over `D` coordinates, each in `[lo, hi]`.
    fn hawks<const N: usize, const D: usize>(
        params: HhoParams,
        (lo, hi): (f32, f32),
        iterations: u32,
        seed: u64,
    ) -> Hho<N, D> {
        let b = Bounds::<D>::uniform(D, lo, hi).unwrap();
        let s = Settings {
            population: N,
            iterations,
            seed,
        };
        Hho::new(s, &b, params).unwrap()
    }

    fn run(params: HhoParams, seed: u64) -> (f32, u64) {
        let mut h = hawks::<20, 10>(params, (-100.0, 100.0), 100, seed);
        let r = h
            .run(&mut shifted_sphere, None, &Stop::default(), &mut [])
            .unwrap();
        (r.best_cost, r.evaluations)
    }

    #[test]
    fn scalar_mean_pools_every_coordinate_of_every_hawk() {
        let scalar = HhoParams {
            mean: HawkMean::Scalar,
            ..HhoParams::hho()
        };
        let mut h = hawks::<4, 3>(scalar, (-10.0, 10.0), 10, 3);
        let rows: [&[f32]; 4] = [
            &[1.0, 2.0, 3.0],
            &[4.0, 5.0, 6.0],
            &[7.0, 8.0, 9.0],
            &[0.0; 3],
        ];
        h.init(&mut shifted_sphere, Some(&rows)).unwrap();
        // (Each step starts from the sum over the population, as it stands then.)
        h.recompute_sum();
        assert_eq!(h.scalar_mean(), Some(45.0 / 12.0));
        // HHO.m's reading keeps one mean per dimension.
        let mut h = hawks::<4, 3>(HhoParams::hho(), (-10.0, 10.0), 10, 3);
        h.init(&mut shifted_sphere, Some(&rows)).unwrap();
        h.recompute_sum();
        assert_eq!(h.scalar_mean(), None);
        assert_eq!(&h.sum, &[12.0, 15.0, 18.0]);
        // And the two readings search differently.
        assert_ne!(run(scalar, 5), run(HhoParams::hho(), 5));
    }

    #[test]
    fn deterministic_per_seed() {
        assert_eq!(run(HhoParams::tclhho(), 5), run(HhoParams::tclhho(), 5));
        assert_ne!(run(HhoParams::tclhho(), 5), run(HhoParams::tclhho(), 6));
    }

    #[test]
    fn evaluations_are_counted_exactly() {
        for params in [
            HhoParams::hho(),
            HhoParams::tclhho(),
            HhoParams::tclhho_literal(),
        ] {
            let mut h = hawks::<10, 4>(params, (-5.0, 5.0), 30, 3);
            let mut calls = 0u64;
            let mut obj = |x: &[f32]| {
                calls += 1;
                x.iter().map(|v| v * v).sum::<f32>()
            };
            let r = h.run(&mut obj, None, &Stop::default(), &mut []).unwrap();
            assert_eq!(r.evaluations, calls);
            assert!(r.evaluations > 10 + 10 * 30);
        }
    }

    #[test]
    fn every_evaluated_point_is_in_the_box() {
        // Candidates are clamped by the loops that compute them: a narrow box off the
        // optimum makes every move and the mutation leave it often.
        for params in [
            HhoParams::hho(),
            HhoParams::tclhho(),
            HhoParams::tclhho_literal(),
            HhoParams {
                mean: HawkMean::Scalar,
                ..HhoParams::tclhho()
            },
        ] {
            let mut h = hawks::<8, 6>(params, (2.0, 3.0), 60, 11);
            let mut outside = 0u32;
            let mut obj = |x: &[f32]| {
                outside += x.iter().filter(|v| !(2.0..=3.0).contains(*v)).count() as u32;
                x.iter().map(|v| v * v).sum::<f32>()
            };
            h.run(&mut obj, None, &Stop::default(), &mut []).unwrap();
            assert_eq!(outside, 0, "{params:?}");
        }
    }

    #[test]
    fn best_so_far_never_worsens_and_matches_its_position() {
        let mut h = hawks::<12, 5>(HhoParams::tclhho(), (-10.0, 10.0), 40, 8);
        let mut obj = |x: &[f32]| x.iter().map(|v| (v - 1.0).abs()).sum::<f32>();
        let mut hist = [0.0f32; 40];
        h.run(&mut obj, None, &Stop::default(), &mut hist).unwrap();
        assert!(hist.windows(2).all(|w| w[1] <= w[0]));
        assert_eq!(obj(h.best_position()), h.best_cost());
    }

    #[test]
    fn levy_dive_starts_from_the_unclamped_y() {
        // HHO.m: `X2 = Rabbit - E |J Rabbit - X| + S .* Levy(D)`, i.e. `Z` from the raw `Y`.
        // Here `Y = -9` lies below the box `[0, 10]`: `Z` must be `clamp(-9 + step)` = 0, not
        // `clamp(0 + step)` (which is positive for every positive Levy step).
        let mut h = hawks::<2, 6>(HhoParams::hho(), (0.0, 10.0), 10, 4);
        let mut last = [f32::NAN; 6];
        // A constant cost: neither `Y` nor `Z` improves on the hawk, so both are evaluated.
        let mut obj = |x: &[f32]| {
            last.copy_from_slice(x);
            1.0f32
        };
        h.init(&mut obj, None).unwrap();
        h.swarm.pop.replace(0, &[10.0; 6], 1.0);
        h.swarm.tracker.best = [0.0; 6];
        let e = 0.9;
        let mut rng = h.swarm.rng.clone();
        let j = 2.0 * (1.0 - rng.unit());
        let mut want = [0.0f32; 6];
        for w in &mut want {
            let y = 0.0 - e * libm::fabsf(j * 0.0 - 10.0);
            let s = rng.unit();
            *w = (y + s * 0.01 * rng.levy()).clamp(0.0, 10.0);
        }
        h.dive(&mut obj, 0, e, false);
        assert_eq!(last, want);
        assert_eq!(want, [0.0; 6]);
        assert_eq!(h.swarm.pop.position(0), &[10.0; 6]);
    }

    #[test]
    fn invalid_params() {
        let b = Bounds::<2>::uniform(2, -1.0, 1.0).unwrap();
        let s = Settings {
            population: 5,
            iterations: 5,
            seed: 0,
        };
        let mut p = HhoParams::tclhho();
        p.levy_scale = f32::NAN;
        assert!(Hho::<5, 2>::new(s, &b, p).is_err());
        let mut p = HhoParams::tclhho();
        p.init = Initialisation::Tent { u: 1.0 };
        assert!(Hho::<5, 2>::new(s, &b, p).is_err());
        let s1 = Settings {
            population: 1,
            iterations: 5,
            seed: 0,
        };
        assert_eq!(
            Hho::<5, 2>::new(s1, &b, HhoParams::hho()).err(),
            Some(OptimError::PopulationOutOfRange)
        );
    }

    #[test]
    fn mutation_is_kept_only_if_better() {
        // With a mutation after the updates, the rabbit's cost never increases: checked by the
        // history in `best_so_far_never_worsens...`; here check the mutation draws change the
        // result relative to HHO with the same other options.
        let mut with = HhoParams::hho();
        with.mutation = Mutation::AfterUpdates;
        let (a, ea) = run(with, 2);
        let (b, eb) = run(HhoParams::hho(), 2);
        assert_ne!(a, b);
        assert!(ea > eb - 200);
    }
}

//! The engine every algorithm shares ([`SwarmState`]): configuration, generator, population
//! and the best point so far ([`Tracker`]), how the initial population is generated
//! ([`Initialisation`]), and the accessors of [`Optimizer`](super::Optimizer) over them.

use super::random::Random;
use super::{Bounds, Objective, OptimError, Population, Settings, copy, opposition, tent};

/// How the initial population is generated (before any caller-supplied rows replace rows).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Initialisation {
    /// Independent uniform points in the box.
    Uniform,
    /// The Tent chaotic sequence along the population (`Lei2024Warehouse`, see [`tent`]).
    Tent {
        /// The map's break point `u` in `(0, 1)`; 0.5 is the classic tent.
        u: f32,
    },
    /// Opposition-based: the best `N` of `N` uniform points and their opposites (`Zhu2025Orchard`).
    Opposition,
}

impl Initialisation {
    /// Tent with `u = 0.5` (perturbed so it never collapses, see [`tent::TentMap`]).
    pub const TENT: Self = Self::Tent { u: 0.5 };

    pub(super) fn validate(&self) -> Result<(), OptimError> {
        match self {
            Self::Tent { u } if !(*u > 0.0 && *u < 1.0) => {
                Err(OptimError::InvalidParameter("tent.u"))
            }
            _ => Ok(()),
        }
    }
}

/// Counts evaluations and keeps the best point ever evaluated.
#[derive(Debug, Clone)]
pub(crate) struct Tracker<const D: usize> {
    pub best: [f32; D],
    pub best_cost: f32,
    pub best_iteration: u32,
    pub evaluations: u64,
    pub iteration: u32,
    pub dim: usize,
}

impl<const D: usize> Tracker<D> {
    /// All zero bytes (see [`SwarmState::unconfigured`]): [`reset`](Self::reset) makes it a
    /// tracker, before any evaluation.
    pub const fn unconfigured() -> Self {
        Self {
            best: [0.0; D],
            best_cost: 0.0,
            best_iteration: 0,
            evaluations: 0,
            iteration: 0,
            dim: 0,
        }
    }

    pub fn reset(&mut self, dim: usize) {
        self.best_cost = f32::INFINITY;
        self.best_iteration = 0;
        self.evaluations = 0;
        self.iteration = 0;
        self.dim = dim.min(D);
    }

    /// Evaluates `x`, counting it and taking it as the new best if it improves.
    pub fn evaluate<O: Objective + ?Sized>(&mut self, objective: &mut O, x: &[f32]) -> f32 {
        self.evaluate_below(objective, x, f32::INFINITY)
    }

    /// [`evaluate`](Self::evaluate) for a caller that only needs the cost when it is below
    /// `bound` ([`Objective::cost_below`]): the result is exact below `bound` and below the
    /// best cost (so the best point is tracked exactly), else some value at or above both.
    // Inlined into each optimizer's call sites: one call per evaluation fewer (0.7% of a
    // TCLHHO plan on a Cortex-M4, for 0.8 KiB of flash).
    #[inline(always)]
    pub fn evaluate_below<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        x: &[f32],
        bound: f32,
    ) -> f32 {
        let bound = if bound.is_nan() {
            f32::INFINITY
        } else if bound > self.best_cost {
            bound
        } else {
            self.best_cost
        };
        let raw = if bound == f32::INFINITY {
            objective.cost(x)
        } else {
            objective.cost_below(x, bound)
        };
        let cost = if raw.is_nan() { f32::INFINITY } else { raw };
        self.evaluations += 1;
        if cost < self.best_cost || self.evaluations == 1 {
            if cost < self.best_cost {
                self.best_iteration = self.iteration;
            }
            self.best_cost = cost;
            copy(&mut self.best, x);
        }
        cost
    }

    pub fn best(&self) -> &[f32] {
        if self.evaluations == 0 {
            &[]
        } else {
            self.best.get(..self.dim).unwrap_or(&[])
        }
    }
}

/// The state every algorithm shares: configuration, generator, population and best-so-far.
#[derive(Debug, Clone)]
pub(crate) struct SwarmState<const N: usize, const D: usize> {
    pub settings: Settings,
    pub bounds: Bounds<D>,
    pub rng: Random,
    pub pop: Population<N, D>,
    pub tracker: Tracker<D>,
    pub initialised: bool,
}

impl<const N: usize, const D: usize> SwarmState<N, D> {
    /// An unconfigured swarm, for `const`/`static` initialisers.
    ///
    /// Its bytes are all zero, like every optimizer's `unconfigured()` built on it: a
    /// firmware `static` of one then lives in `.bss` instead of being copied from a flash
    /// image, and assigning one is a `memset` rather than a copy of a constant kept in flash
    /// (which cost 37 KiB of flash for the firmware's TCLHHO/IGWO state).
    /// [`configure`](Self::configure) and `initialise` set every field before a draw or an
    /// evaluation.
    pub const fn unconfigured() -> Self {
        Self {
            settings: Settings {
                population: 0,
                iterations: 0,
                seed: 0,
            },
            bounds: Bounds::unconfigured(),
            rng: Random::unset(),
            pop: Population::empty(),
            tracker: Tracker::unconfigured(),
            initialised: false,
        }
    }

    /// Validates and takes a configuration in place; on error nothing changes.
    pub fn configure(
        &mut self,
        settings: Settings,
        bounds: &Bounds<D>,
        min_population: usize,
    ) -> Result<(), OptimError> {
        settings.validate::<N>(min_population)?;
        let dim = bounds.dim();
        if dim == 0 || dim > D {
            return Err(OptimError::DimensionOutOfRange);
        }
        self.settings = settings;
        self.bounds.clone_from(bounds);
        self.pop.resize(settings.population, dim);
        self.tracker.reset(dim);
        self.initialised = false;
        Ok(())
    }

    pub fn n(&self) -> usize {
        self.pop.size()
    }

    pub fn dim(&self) -> usize {
        self.pop.dim()
    }

    /// Resets the generator and counters, generates and evaluates the initial population.
    pub fn initialise<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        how: Initialisation,
        initial: Option<&[&[f32]]>,
    ) -> Result<(), OptimError> {
        if self.settings.population == 0 {
            return Err(OptimError::NotConfigured);
        }
        let n = self.n();
        let dim = self.dim();
        if let Some(rows) = initial
            && (rows.len() > n
                || rows
                    .iter()
                    .any(|r| r.len() != dim || r.iter().any(|v| v.is_nan())))
        {
            return Err(OptimError::InvalidInitialPopulation);
        }
        self.rng.reseed(self.settings.seed);
        self.tracker.reset(dim);
        self.initialised = false;
        match how {
            Initialisation::Uniform | Initialisation::Opposition => {
                for i in 0..n {
                    let row = self.pop.position_mut(i);
                    for ((v, l), u) in row
                        .iter_mut()
                        .zip(self.bounds.lower())
                        .zip(self.bounds.upper())
                    {
                        *v = self.rng.range(*l, *u);
                    }
                }
            }
            Initialisation::Tent { u } => tent::fill(&mut self.pop, &self.bounds, &mut self.rng, u),
        }
        if let Some(rows) = initial {
            for (i, row) in rows.iter().enumerate() {
                let dst = self.pop.position_mut(i);
                copy(dst, row);
                self.bounds.clamp(dst);
            }
        }
        for i in 0..n {
            let cost = self.tracker.evaluate(objective, self.pop.position(i));
            self.pop.set_cost(i, cost);
        }
        if how == Initialisation::Opposition {
            opposition::select_best_of_opposites(
                &mut self.pop,
                &self.bounds,
                &mut self.tracker,
                objective,
            );
        }
        self.initialised = true;
        Ok(())
    }

    /// Checks that a step may run and advances the iteration counter; returns `t = k - 1`.
    pub fn begin_step(&mut self) -> Result<u32, OptimError> {
        if !self.initialised {
            return Err(OptimError::NotInitialised);
        }
        if self.tracker.iteration >= self.settings.iterations {
            return Err(OptimError::Exhausted);
        }
        let t = self.tracker.iteration;
        self.tracker.iteration += 1;
        Ok(t)
    }

    /// Clamps `x`, evaluates it and returns its cost.
    pub fn clamp_and_evaluate<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        x: &mut [f32],
    ) -> f32 {
        self.bounds.clamp(x);
        self.tracker.evaluate(objective, x)
    }

    /// [`clamp_and_evaluate`](Self::clamp_and_evaluate) where only a cost below `bound`
    /// matters ([`Tracker::evaluate_below`]).
    pub fn clamp_and_evaluate_below<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        x: &mut [f32],
        bound: f32,
    ) -> f32 {
        self.bounds.clamp(x);
        self.tracker.evaluate_below(objective, x, bound)
    }
}

/// Implements the accessor part of [`Optimizer`] for a type with a `swarm: SwarmState<N, D>` field.
macro_rules! swarm_accessors {
    () => {
        fn best_position(&self) -> &[f32] {
            self.swarm.tracker.best()
        }
        fn best_cost(&self) -> f32 {
            self.swarm.tracker.best_cost
        }
        fn iteration(&self) -> u32 {
            self.swarm.tracker.iteration
        }
        fn evaluations(&self) -> u64 {
            self.swarm.tracker.evaluations
        }
        fn best_iteration(&self) -> u32 {
            self.swarm.tracker.best_iteration
        }
        fn horizon(&self) -> u32 {
            self.swarm.settings.iterations
        }
    };
}
pub(crate) use swarm_accessors;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::Optimizer;
    use crate::optim::gwo::{Gwo, GwoParams};

    fn sphere(x: &[f32]) -> f32 {
        x.iter().map(|v| v * v).sum()
    }

    #[test]
    fn nan_objective_counts_as_infinity_and_step_errors() {
        let b = Bounds::<2>::uniform(2, -1.0, 1.0).unwrap();
        let s = Settings {
            population: 5,
            iterations: 2,
            seed: 3,
        };
        let mut g = Gwo::<5, 2>::new(s, &b, GwoParams::gwo()).unwrap();
        let mut nan = |_: &[f32]| f32::NAN;
        assert_eq!(g.step(&mut nan), Err(OptimError::NotInitialised));
        g.init(&mut nan, None).unwrap();
        assert_eq!(g.best_cost(), f32::INFINITY);
        g.step(&mut nan).unwrap();
        g.step(&mut nan).unwrap();
        assert_eq!(g.step(&mut nan), Err(OptimError::Exhausted));
    }

    #[test]
    fn initial_population_is_used_and_validated() {
        let b = Bounds::<2>::uniform(2, -1.0, 1.0).unwrap();
        let s = Settings {
            population: 4,
            iterations: 2,
            seed: 3,
        };
        let mut g = Gwo::<4, 2>::new(s, &b, GwoParams::gwo()).unwrap();
        let mut obj = sphere;
        let good: [&[f32]; 2] = [&[0.0, 0.0], &[5.0, 0.5]];
        g.init(&mut obj, Some(&good)).unwrap();
        assert_eq!(g.best_cost(), 0.0);
        let short: [&[f32]; 1] = [&[0.0]];
        assert_eq!(
            g.init(&mut obj, Some(&short)),
            Err(OptimError::InvalidInitialPopulation)
        );
        let nan: [&[f32]; 1] = [&[f32::NAN, 0.0]];
        assert_eq!(
            g.init(&mut obj, Some(&nan)),
            Err(OptimError::InvalidInitialPopulation)
        );
        let too_many: [&[f32]; 5] = [&[0.0, 0.0]; 5];
        assert_eq!(
            g.init(&mut obj, Some(&too_many)),
            Err(OptimError::InvalidInitialPopulation)
        );
    }
}

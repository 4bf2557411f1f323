//! What every optimizer promises and is given: the [`Objective`] it minimises, the
//! step-wise [`Optimizer`] interface with its [`Settings`], [`Stop`] criteria and [`Report`],
//! and the [`OptimError`]s it refuses with.

/// Writes [`Optimizer`] for an enum of optimizers `Enum<N, D>` whose variants each hold one:
/// every method forwards to the variant's.
macro_rules! forward_optimizer {
    ($enum:ident: $($variant:ident),+) => {
        impl<const N: usize, const D: usize> $crate::optim::Optimizer for $enum<N, D> {
            fn init<O: $crate::optim::Objective + ?Sized>(
                &mut self,
                objective: &mut O,
                initial: Option<&[&[f32]]>,
            ) -> Result<(), $crate::optim::OptimError> {
                match self { $($enum::$variant(o) => o.init(objective, initial),)+ }
            }
            fn step<O: $crate::optim::Objective + ?Sized>(
                &mut self,
                objective: &mut O,
            ) -> Result<(), $crate::optim::OptimError> {
                match self { $($enum::$variant(o) => o.step(objective),)+ }
            }
            fn best_position(&self) -> &[f32] {
                match self { $($enum::$variant(o) => o.best_position(),)+ }
            }
            fn best_cost(&self) -> f32 {
                match self { $($enum::$variant(o) => o.best_cost(),)+ }
            }
            fn iteration(&self) -> u32 {
                match self { $($enum::$variant(o) => o.iteration(),)+ }
            }
            fn evaluations(&self) -> u64 {
                match self { $($enum::$variant(o) => o.evaluations(),)+ }
            }
            fn best_iteration(&self) -> u32 {
                match self { $($enum::$variant(o) => o.best_iteration(),)+ }
            }
            fn horizon(&self) -> u32 {
                match self { $($enum::$variant(o) => o.horizon(),)+ }
            }
        }
    };
}
pub(crate) use forward_optimizer;

/// Why an optimizer refused a configuration or a call.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum OptimError {
    /// A bound is NaN or infinite, `lb > ub`, or the two bound slices differ in length.
    InvalidBounds,
    /// The population size is 0, above the capacity `N`, or too small for the algorithm.
    PopulationOutOfRange,
    /// The dimension is 0 or above the capacity `D`.
    DimensionOutOfRange,
    /// The iteration horizon `T` is 0.
    IterationsZero,
    /// A named algorithm parameter is NaN or out of its range.
    InvalidParameter(&'static str),
    /// A caller-supplied initial population has a wrong row count, row length or a NaN.
    InvalidInitialPopulation,
    /// `init` was called on an optimizer built with `unconfigured()` and never configured.
    NotConfigured,
    /// `step` was called before `init`.
    NotInitialised,
    /// `step` was called after the iteration horizon `T` was reached.
    Exhausted,
    /// A name did not match any algorithm or function.
    UnknownName,
}

impl core::fmt::Display for OptimError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::InvalidBounds => f.write_str("invalid bounds (NaN, infinite or lb > ub)"),
            Self::PopulationOutOfRange => f.write_str("population size out of range"),
            Self::DimensionOutOfRange => f.write_str("dimension out of range"),
            Self::IterationsZero => f.write_str("iteration count must be at least 1"),
            Self::InvalidParameter(name) => write!(f, "invalid parameter `{name}`"),
            Self::InvalidInitialPopulation => f.write_str("invalid initial population"),
            Self::NotConfigured => f.write_str("optimizer not configured"),
            Self::NotInitialised => f.write_str("optimizer not initialised"),
            Self::Exhausted => f.write_str("iteration horizon reached"),
            Self::UnknownName => f.write_str("unknown name"),
        }
    }
}

/// A cost to minimise.
///
/// `&mut self` lets objectives keep state (a noise generator, an evaluation log). Any
/// `FnMut(&[f32]) -> f32` closure is an objective.
pub trait Objective {
    /// The cost of `x` (`x.len()` is the runtime dimension). NaN is read as `+inf`.
    fn cost(&mut self, x: &[f32]) -> f32;

    /// The cost of `x` when it is below `bound`; otherwise any value `>= bound`.
    ///
    /// Optimizers call this where only "is `x` better than `bound`?" decides what happens
    /// (a dive against the hawk it would replace, a wolf against the leaders), so an objective
    /// that can prove `cost(x) >= bound` cheaply (a lower bound, checked before the expensive
    /// part) may stop early. Whenever the true cost is below `bound` the result must be
    /// exactly `cost(x)`, bit for bit: runs are then identical to runs that call `cost`.
    /// The default is `cost(x)`.
    fn cost_below(&mut self, x: &[f32], bound: f32) -> f32 {
        let _ = bound;
        self.cost(x)
    }

    /// Whether `cost` is a pure function of `x` (no noise, no log), so that an optimizer may
    /// postpone an exact cost and compute it again later with the same result. The default is
    /// `false`: every cost an optimizer keeps is then computed exactly when the point is.
    fn pure(&self) -> bool {
        false
    }
}

impl<F: FnMut(&[f32]) -> f32> Objective for F {
    fn cost(&mut self, x: &[f32]) -> f32 {
        self(x)
    }
}

/// The sizes and the seed of one run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Settings {
    /// Population size, `1..=N` (some algorithms need more, see their docs).
    pub population: usize,
    /// The iteration horizon `T` the schedules are computed against; a run never does more.
    pub iterations: u32,
    /// The explicit seed: same seed and inputs give bit-identical results on every target.
    pub seed: u64,
}

impl Settings {
    pub(super) fn validate<const N: usize>(&self, min_population: usize) -> Result<(), OptimError> {
        if self.population == 0 || self.population > N || self.population < min_population {
            return Err(OptimError::PopulationOutOfRange);
        }
        if self.iterations == 0 {
            return Err(OptimError::IterationsZero);
        }
        Ok(())
    }
}

/// When [`Optimizer::run`] stops; any combination, the first criterion met wins.
///
/// The iteration horizon [`Settings::iterations`] always applies.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Stop {
    /// At most this many iterations (capped by the horizon).
    pub max_iterations: Option<u32>,
    /// Stop once this many evaluations were spent; checked between iterations, so a run may
    /// exceed it by at most one iteration's evaluations (the report gives the exact count).
    pub max_evaluations: Option<u64>,
    /// Stop once the best cost is at or below this value.
    pub target_cost: Option<f32>,
    /// Stop after this many consecutive iterations without improvement of the best cost.
    pub stagnation: Option<u32>,
}

impl Stop {
    fn validate(&self) -> Result<(), OptimError> {
        if self.target_cost.is_some_and(f32::is_nan) {
            return Err(OptimError::InvalidParameter("target_cost"));
        }
        if self.stagnation == Some(0) {
            return Err(OptimError::InvalidParameter("stagnation"));
        }
        Ok(())
    }
}

/// Which criterion ended a run.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum StopReason {
    /// The horizon or [`Stop::max_iterations`] was reached.
    Iterations,
    /// [`Stop::max_evaluations`] was reached.
    Evaluations,
    /// [`Stop::target_cost`] was reached.
    Target,
    /// [`Stop::stagnation`] iterations passed without improvement.
    Stagnation,
}

impl StopReason {
    /// A short lower-case name (`iterations`, `evaluations`, `target`, `stagnation`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Iterations => "iterations",
            Self::Evaluations => "evaluations",
            Self::Target => "target",
            Self::Stagnation => "stagnation",
        }
    }
}

/// The outcome of [`Optimizer::run`]; the best point itself is [`Optimizer::best_position`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Report {
    /// The best cost found.
    pub best_cost: f32,
    /// Iterations done (initialisation not counted).
    pub iterations: u32,
    /// Objective evaluations spent, exactly.
    pub evaluations: u64,
    /// The first iteration at which the final best cost was reached (0 = initialisation).
    pub best_iteration: u32,
    /// Which criterion stopped the run.
    pub stop: StopReason,
    /// History entries written (one per iteration while the buffer lasts).
    pub history_len: usize,
    /// True if the history buffer was shorter than the number of iterations.
    pub history_truncated: bool,
}

/// The step-wise interface every optimizer implements.
///
/// Firmware calls [`init`](Optimizer::init) once, then [`step`](Optimizer::step) in time slices
/// and reads [`best_cost`](Optimizer::best_cost) between them; hosts call
/// [`run`](Optimizer::run).
///
/// ```
/// use planner_core::optim::{Bounds, Optimizer, Settings};
/// use planner_core::optim::ssa_gwo::{SsaGwo, SsaGwoParams};
///
/// // Firmware keeps this in a `static`; `unconfigured` is `const`.
/// let mut opt = SsaGwo::<30, 64>::unconfigured();
/// let bounds = Bounds::<64>::uniform(12, -1.0, 1.0)?;
/// opt.configure(Settings { population: 30, iterations: 100, seed: 42 }, &bounds, SsaGwoParams::zhu2025_orchard())?;
/// let mut cost = |x: &[f32]| x.iter().map(|v| (v - 0.25).abs()).sum::<f32>();
/// opt.init(&mut cost, None)?;
/// while opt.iteration() < opt.horizon() {
///     // one time slice
///     opt.step(&mut cost)?;
/// }
/// assert!(opt.best_cost() < 1e-2);
/// assert_eq!(opt.best_position().len(), 12);
/// # Ok::<(), planner_core::optim::OptimError>(())
/// ```
pub trait Optimizer {
    /// Builds and evaluates the initial population, replacing the generated rows by the
    /// caller's `initial` rows if given (each of length `dim`, clamped into the box; at most
    /// `population` rows, the rest generated as usual). Restarts the optimizer.
    fn init<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        initial: Option<&[&[f32]]>,
    ) -> Result<(), OptimError>;

    /// One iteration. Errors if not initialised or once the horizon is reached.
    fn step<O: Objective + ?Sized>(&mut self, objective: &mut O) -> Result<(), OptimError>;

    /// The best point found so far (empty before `init`).
    fn best_position(&self) -> &[f32];

    /// The best cost found so far (`+inf` before `init`).
    fn best_cost(&self) -> f32;

    /// Iterations done since `init`.
    fn iteration(&self) -> u32;

    /// Evaluations spent since `init`.
    fn evaluations(&self) -> u64;

    /// The first iteration at which the current best cost was reached (0 = initialisation).
    fn best_iteration(&self) -> u32;

    /// The iteration horizon `T`.
    fn horizon(&self) -> u32;

    /// Initialises and iterates until a [`Stop`] criterion or the horizon is met, writing the
    /// best cost after each iteration into `history` as long as it has room.
    fn run<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        initial: Option<&[&[f32]]>,
        stop: &Stop,
        history: &mut [f32],
    ) -> Result<Report, OptimError> {
        stop.validate()?;
        self.init(objective, initial)?;
        let max_iterations = stop
            .max_iterations
            .map_or(self.horizon(), |m| m.min(self.horizon()));
        let mut written = 0usize;
        let mut truncated = false;
        let reason = loop {
            if stop.target_cost.is_some_and(|t| self.best_cost() <= t) {
                break StopReason::Target;
            }
            if stop
                .max_evaluations
                .is_some_and(|m| self.evaluations() >= m)
            {
                break StopReason::Evaluations;
            }
            if stop
                .stagnation
                .is_some_and(|k| self.iteration() - self.best_iteration() >= k)
            {
                break StopReason::Stagnation;
            }
            if self.iteration() >= max_iterations {
                break StopReason::Iterations;
            }
            self.step(objective)?;
            match history.get_mut(written) {
                Some(slot) => {
                    *slot = self.best_cost();
                    written += 1;
                }
                None => truncated = true,
            }
        };
        Ok(Report {
            best_cost: self.best_cost(),
            iterations: self.iteration(),
            evaluations: self.evaluations(),
            best_iteration: self.best_iteration(),
            stop: reason,
            history_len: written,
            history_truncated: truncated,
        })
    }
}

/// Checks that `v` is finite and in `[lo, hi]`.
pub(crate) fn check_param(v: f32, lo: f32, hi: f32, name: &'static str) -> Result<(), OptimError> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(())
    } else {
        Err(OptimError::InvalidParameter(name))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::gwo::{Gwo, GwoParams};
    use crate::optim::{Bounds, Optimizer};

    fn sphere(x: &[f32]) -> f32 {
        x.iter().map(|v| v * v).sum()
    }

    #[test]
    fn settings_are_validated() {
        let b = Bounds::<4>::uniform(2, -1.0, 1.0).unwrap();
        let p = GwoParams::gwo();
        let bad = |population, iterations| {
            Gwo::<8, 4>::new(
                Settings {
                    population,
                    iterations,
                    seed: 1,
                },
                &b,
                p,
            )
        };
        assert_eq!(bad(0, 10).err(), Some(OptimError::PopulationOutOfRange));
        assert_eq!(bad(9, 10).err(), Some(OptimError::PopulationOutOfRange));
        assert_eq!(bad(8, 0).err(), Some(OptimError::IterationsZero));
    }

    #[test]
    fn stop_criteria_and_history() {
        let b = Bounds::<4>::uniform(4, -5.0, 5.0).unwrap();
        let s = Settings {
            population: 10,
            iterations: 50,
            seed: 3,
        };
        let mut g = Gwo::<10, 4>::new(s, &b, GwoParams::gwo()).unwrap();
        let mut obj = sphere;
        let mut short = [0.0f32; 5];
        let r = g.run(&mut obj, None, &Stop::default(), &mut short).unwrap();
        assert_eq!(r.stop, StopReason::Iterations);
        assert_eq!(r.iterations, 50);
        assert_eq!(r.evaluations, 10 + 500);
        assert_eq!((r.history_len, r.history_truncated), (5, true));
        assert!(short.windows(2).all(|w| w[1] <= w[0]));

        let stop = Stop {
            max_evaluations: Some(35),
            ..Stop::default()
        };
        let r = g.run(&mut obj, None, &stop, &mut []).unwrap();
        assert_eq!(
            (r.stop, r.evaluations, r.iterations),
            (StopReason::Evaluations, 40, 3)
        );

        let stop = Stop {
            target_cost: Some(1.0),
            ..Stop::default()
        };
        let r = g.run(&mut obj, None, &stop, &mut []).unwrap();
        assert_eq!(r.stop, StopReason::Target);
        assert!(r.best_cost <= 1.0);

        let mut flat = |_: &[f32]| 1.0f32;
        let stop = Stop {
            stagnation: Some(4),
            ..Stop::default()
        };
        let r = g.run(&mut flat, None, &stop, &mut []).unwrap();
        assert_eq!(
            (r.stop, r.iterations, r.best_iteration),
            (StopReason::Stagnation, 4, 0)
        );

        let stop = Stop {
            max_iterations: Some(7),
            ..Stop::default()
        };
        let r = g.run(&mut obj, None, &stop, &mut []).unwrap();
        assert_eq!((r.stop, r.iterations), (StopReason::Iterations, 7));
    }
}

//! Swarm optimizers over a box `[lb, ub]^D` with fixed capacity (SPEC section 2).
//!
//! Every optimizer minimises an [`Objective`] over [`Bounds`] with a population of at most `N`
//! members of at most `D` dimensions; the runtime sizes live in [`Settings`] and in the bounds.
//! All state is inline (no allocator), so firmware can keep an optimizer in a `static` and drive
//! it in time slices through the step-wise [`Optimizer`] API, while hosts call
//! [`Optimizer::run`].
//!
//! Shared conventions:
//! - costs are `f32`; an objective returning NaN counts as `+inf`;
//! - every candidate is clamped into the box before it is evaluated;
//! - the best-so-far point is updated by *every* evaluation that improves on it, so
//!   [`Optimizer::best_cost`] is exact at any time, and the iteration at which it was first
//!   reached is kept ([`Optimizer::best_iteration`], 0 = initialisation);
//! - evaluations are counted exactly, including the HHO dives and the TCLHHO mutation;
//! - iteration `k` (1-based) of a run of horizon `T` uses the schedules at `t = k - 1`, so
//!   `t` runs over `0..T`, as in the authors' Matlab code.
//!
//! The order in which each algorithm draws random numbers is documented in [`random`].
//!
//! Firmware: every optimizer has a `const fn unconfigured()` and a `configure(..)` that
//! validates and takes a configuration in place, so the state can live in a `static` without
//! a large temporary on the stack; `new(..)` is `unconfigured()` plus `configure(..)`.
//!
//! # Example
//!
//! ```
//! use planner_core::optim::{Bounds, Optimizer, Settings, Stop};
//! use planner_core::optim::gwo::{Gwo, GwoParams};
//!
//! let bounds = Bounds::<8>::uniform(8, -10.0, 10.0)?;
//! let settings = Settings { population: 20, iterations: 200, seed: 7 };
//! let mut wolves = Gwo::<20, 8>::new(settings, &bounds, GwoParams::igwo())?;
//! let mut sphere = |x: &[f32]| x.iter().map(|v| (v - 3.0) * (v - 3.0)).sum::<f32>();
//! let mut history = [0.0f32; 200];
//! let report = wolves.run(&mut sphere, None, &Stop::default(), &mut history)?;
//! assert!(report.best_cost < 0.1);
//! assert_eq!(report.history_len, 200);
//! assert_eq!(report.evaluations, 20 + 20 * 200);
//! # Ok::<(), planner_core::optim::OptimError>(())
//! ```

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

pub mod any;
pub mod functions;
pub mod ga;
pub mod gwo;
pub mod hho;
pub mod opposition;
pub mod pso;
pub mod random;
pub mod schedule;
pub mod ssa;
pub mod ssa_gwo;
pub mod tent;
mod ziggurat;

use random::Random;

/// Why an optimizer refused a configuration or a call.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
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

/// Per-dimension box bounds with capacity `D`.
#[derive(Debug, Clone, PartialEq)]
pub struct Bounds<const D: usize> {
    lower: [f32; D],
    upper: [f32; D],
    dim: usize,
}

impl<const D: usize> Bounds<D> {
    /// The same interval `[lower, upper]` on each of `dim` dimensions.
    pub fn uniform(dim: usize, lower: f32, upper: f32) -> Result<Self, OptimError> {
        if dim == 0 || dim > D {
            return Err(OptimError::DimensionOutOfRange);
        }
        check_interval(lower, upper)?;
        Ok(Self {
            lower: [lower; D],
            upper: [upper; D],
            dim,
        })
    }

    /// Bounds from two slices of equal length (the dimension).
    pub fn from_slices(lower: &[f32], upper: &[f32]) -> Result<Self, OptimError> {
        if lower.len() != upper.len() {
            return Err(OptimError::InvalidBounds);
        }
        Self::from_fn(lower.len(), |i| {
            (
                lower.get(i).copied().unwrap_or(f32::NAN),
                upper.get(i).copied().unwrap_or(f32::NAN),
            )
        })
    }

    /// Bounds of `dim` dimensions, `(lower, upper)` of dimension `i` from `interval(i)`
    /// (without two capacity-sized arrays on the caller's stack).
    pub fn from_fn(
        dim: usize,
        mut interval: impl FnMut(usize) -> (f32, f32),
    ) -> Result<Self, OptimError> {
        if dim == 0 || dim > D {
            return Err(OptimError::DimensionOutOfRange);
        }
        let mut b = Self {
            lower: [0.0; D],
            upper: [0.0; D],
            dim,
        };
        for (i, (sl, su)) in b
            .lower
            .iter_mut()
            .zip(b.upper.iter_mut())
            .take(dim)
            .enumerate()
        {
            let (l, u) = interval(i);
            check_interval(l, u)?;
            *sl = l;
            *su = u;
        }
        Ok(b)
    }

    /// The runtime dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Lower bounds, one per dimension.
    pub fn lower(&self) -> &[f32] {
        self.lower.get(..self.dim).unwrap_or(&[])
    }

    /// Upper bounds, one per dimension.
    pub fn upper(&self) -> &[f32] {
        self.upper.get(..self.dim).unwrap_or(&[])
    }

    /// Clamps `x` into the box; NaN coordinates go to the lower bound.
    pub fn clamp(&self, x: &mut [f32]) {
        for (v, (l, u)) in x.iter_mut().zip(self.pairs()) {
            *v = clamp_into(*v, l, u);
        }
    }

    /// `(lower, upper)` per dimension.
    pub(crate) fn pairs(&self) -> impl Iterator<Item = (f32, f32)> + '_ {
        self.lower()
            .iter()
            .copied()
            .zip(self.upper().iter().copied())
    }
}

/// One coordinate of [`Bounds::clamp`], for loops that clamp while they compute a candidate.
#[inline]
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub(crate) fn clamp_into(v: f32, l: f32, u: f32) -> f32 {
    // A NaN becomes the lower bound, which keeps NaN out of every objective call. Comparisons
    // rather than `max`/`min` (libm calls on Cortex-M4); the result is the same as
    // `v.max(l).min(u)` except possibly for the sign of a zero on a zero bound.
    // `!(v >= l)` is `v.is_nan() || v < l` in one comparison (unordered fails `>=`).
    if !(v >= l) {
        l
    } else if v > u {
        u
    } else {
        v
    }
}

fn check_interval(lower: f32, upper: f32) -> Result<(), OptimError> {
    if !lower.is_finite() || !upper.is_finite() || lower > upper {
        return Err(OptimError::InvalidBounds);
    }
    Ok(())
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
    fn validate<const N: usize>(&self, min_population: usize) -> Result<(), OptimError> {
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
/// opt.configure(Settings { population: 30, iterations: 100, seed: 42 }, &bounds, SsaGwoParams::seed_001())?;
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

/// Positions and cached costs of a population with capacity `N x D`.
#[derive(Debug, Clone)]
pub struct Population<const N: usize, const D: usize> {
    positions: [[f32; D]; N],
    costs: [f32; N],
    size: usize,
    dim: usize,
}

impl<const N: usize, const D: usize> Population<N, D> {
    /// An empty population of runtime size `size <= N` and dimension `dim <= D` (all zero,
    /// costs `+inf`).
    pub fn new(size: usize, dim: usize) -> Self {
        let mut p = Self::empty();
        p.resize(size, dim);
        p
    }

    /// A population of size 0, all zero bytes (usable in `const` and `static` initialisers,
    /// like every optimizer's `unconfigured()`). [`resize`](Self::resize) sets the costs.
    pub const fn empty() -> Self {
        Self {
            positions: [[0.0; D]; N],
            costs: [0.0; N],
            size: 0,
            dim: 0,
        }
    }

    /// Sets the runtime sizes in place (clamped to the capacity); costs become `+inf`.
    pub fn resize(&mut self, size: usize, dim: usize) {
        self.size = size.min(N);
        self.dim = dim.min(D);
        self.costs = [f32::INFINITY; N];
    }

    /// Runtime population size.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Runtime dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The sum of the members' positions, coordinate by coordinate (0 beyond the dimension),
    /// adding the members in order. One coordinate at a time, in a register: row by row,
    /// each partial sum was loaded and stored back per member.
    pub fn sum_positions(&self, sum: &mut [f32; D]) {
        let rows = self.positions.get(..self.size).unwrap_or(&[]);
        for (d, s) in sum.iter_mut().enumerate() {
            let mut total = 0.0;
            if d < self.dim {
                for row in rows {
                    total += row[d];
                }
            }
            *s = total;
        }
    }

    /// Member `k` to read and member `i` to write, or `None` unless both exist and differ.
    pub fn read_write(&mut self, k: usize, i: usize) -> Option<(&[f32], &mut [f32])> {
        if k >= self.size || i >= self.size {
            return None;
        }
        let dim = self.dim;
        let (read, write) = if k < i {
            let (before, from) = self.positions.split_at_mut_checked(i)?;
            (before.get(k)?, from.first_mut()?)
        } else if i < k {
            let (before, from) = self.positions.split_at_mut_checked(k)?;
            (&*from.first_mut()?, before.get_mut(i)?)
        } else {
            return None;
        };
        Some((read.get(..dim)?, write.get_mut(..dim)?))
    }

    /// Member `i` (empty if `i >= size`).
    pub fn position(&self, i: usize) -> &[f32] {
        match self.positions.get(i) {
            Some(row) if i < self.size => row.get(..self.dim).unwrap_or(&[]),
            _ => &[],
        }
    }

    /// Member `i`, mutable (empty if `i >= size`).
    pub fn position_mut(&mut self, i: usize) -> &mut [f32] {
        let (size, dim) = (self.size, self.dim);
        match self.positions.get_mut(i) {
            Some(row) if i < size => row.get_mut(..dim).unwrap_or(&mut []),
            _ => &mut [],
        }
    }

    /// Cached cost of member `i` (`+inf` if `i >= size`).
    pub fn cost(&self, i: usize) -> f32 {
        if i < self.size {
            self.costs.get(i).copied().unwrap_or(f32::INFINITY)
        } else {
            f32::INFINITY
        }
    }

    /// Sets the cached cost of member `i` (ignored if `i >= size`).
    pub fn set_cost(&mut self, i: usize, cost: f32) {
        if i < self.size
            && let Some(c) = self.costs.get_mut(i)
        {
            *c = cost;
        }
    }

    /// Copies `x` into member `i` with its cost.
    pub fn replace(&mut self, i: usize, x: &[f32], cost: f32) {
        copy(self.position_mut(i), x);
        self.set_cost(i, cost);
    }

    /// Index of the lowest cost (first on ties; 0 if empty).
    pub fn best_index(&self) -> usize {
        let mut best = 0;
        for i in 1..self.size {
            if self.cost(i) < self.cost(best) {
                best = i;
            }
        }
        best
    }

    /// Index of the highest cost (first on ties; 0 if empty).
    pub fn worst_index(&self) -> usize {
        let mut worst = 0;
        for i in 1..self.size {
            if self.cost(i) > self.cost(worst) {
                worst = i;
            }
        }
        worst
    }

    /// Fills `order[..size]` with member indices sorted by ascending cost (stable).
    ///
    /// Insertion sort: populations are small and it needs no buffer.
    pub fn sort_indices(&self, order: &mut [usize; N]) {
        for (k, o) in order.iter_mut().enumerate() {
            *o = k;
        }
        let n = self.size.min(N);
        for k in 1..n {
            let mut j = k;
            while j > 0 && self.cost(order[j]) < self.cost(order[j - 1]) {
                order.swap(j, j - 1);
                j -= 1;
            }
        }
    }
}

/// Copies `src` into `dst` over their common length.
pub(crate) fn copy(dst: &mut [f32], src: &[f32]) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d = *s;
    }
}

/// Square root: [`crate::math::sqrt`] (the FPU's `VSQRT.F32` on hard-float targets).
pub(crate) use crate::math::sqrt as sqrtf;

/// How the initial population is generated (before any caller-supplied rows replace rows).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Initialisation {
    /// Independent uniform points in the box.
    Uniform,
    /// The Tent chaotic sequence along the population (seed 000, see [`tent`]).
    Tent {
        /// The map's break point `u` in `(0, 1)`; 0.5 is the classic tent.
        u: f32,
    },
    /// Opposition-based: the best `N` of `N` uniform points and their opposites (seed 001).
    Opposition,
}

impl Initialisation {
    /// Tent with `u = 0.5` (perturbed so it never collapses, see [`tent::TentMap`]).
    pub const TENT: Self = Self::Tent { u: 0.5 };

    fn validate(&self) -> Result<(), OptimError> {
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
    /// All zero bytes (see [`Swarm::unconfigured`]): [`reset`](Self::reset) makes it a
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
pub(crate) struct Swarm<const N: usize, const D: usize> {
    pub settings: Settings,
    pub bounds: Bounds<D>,
    pub rng: Random,
    pub pop: Population<N, D>,
    pub tracker: Tracker<D>,
    pub initialised: bool,
}

impl<const N: usize, const D: usize> Swarm<N, D> {
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
            bounds: Bounds {
                lower: [0.0; D],
                upper: [0.0; D],
                dim: 0,
            },
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
        self.pop.size
    }

    pub fn dim(&self) -> usize {
        self.pop.dim
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

/// Implements the accessor part of [`Optimizer`] for a type with a `swarm: Swarm<N, D>` field.
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

    fn sphere(x: &[f32]) -> f32 {
        x.iter().map(|v| v * v).sum()
    }

    #[test]
    fn bounds_are_validated() {
        assert_eq!(
            Bounds::<4>::uniform(0, 0.0, 1.0),
            Err(OptimError::DimensionOutOfRange)
        );
        assert_eq!(
            Bounds::<4>::uniform(5, 0.0, 1.0),
            Err(OptimError::DimensionOutOfRange)
        );
        assert_eq!(
            Bounds::<4>::uniform(2, 1.0, 0.0),
            Err(OptimError::InvalidBounds)
        );
        assert_eq!(
            Bounds::<4>::uniform(2, f32::NAN, 0.0),
            Err(OptimError::InvalidBounds)
        );
        assert_eq!(
            Bounds::<4>::uniform(2, 0.0, f32::INFINITY),
            Err(OptimError::InvalidBounds)
        );
        assert_eq!(
            Bounds::<4>::from_slices(&[0.0], &[1.0, 2.0]),
            Err(OptimError::InvalidBounds)
        );
        let b = Bounds::<4>::from_slices(&[0.0, -1.0], &[1.0, 1.0]).unwrap();
        let mut x = [5.0, f32::NAN];
        b.clamp(&mut x);
        assert_eq!(x, [1.0, -1.0]);
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

    #[test]
    fn population_sorting() {
        let mut p = Population::<4, 1>::new(4, 1);
        for (i, c) in [3.0, 1.0, 2.0, 1.0].iter().enumerate() {
            p.set_cost(i, *c);
        }
        let mut order = [0; 4];
        p.sort_indices(&mut order);
        assert_eq!(order, [1, 3, 2, 0]);
        assert_eq!((p.best_index(), p.worst_index()), (1, 0));
        assert!(p.position(4).is_empty());
    }

    #[test]
    fn population_rows_and_sums() {
        let mut p = Population::<4, 3>::new(3, 2);
        for i in 0..3 {
            for (d, v) in p.position_mut(i).iter_mut().enumerate() {
                *v = (10 * i + d) as f32;
            }
        }
        // Sums in member order, 0 beyond the dimension.
        let mut sum = [7.0; 3];
        p.sum_positions(&mut sum);
        assert_eq!(sum, [30.0, 33.0, 0.0]);
        // One member to read, another to write, whichever comes first.
        for (k, i) in [(0, 2), (2, 0)] {
            let (read, write) = p.read_write(k, i).unwrap();
            assert_eq!((read.len(), read[0]), (2, (10 * k) as f32));
            write[1] = -1.0;
            assert_eq!(p.position(i)[1], -1.0);
        }
        assert!(p.read_write(1, 1).is_none());
        assert!(p.read_write(3, 0).is_none());
        assert!(p.read_write(0, 3).is_none());
    }
}

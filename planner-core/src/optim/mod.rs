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
//!
//! Files: `contracts` (the [`Objective`] and [`Optimizer`] traits, [`Settings`], [`Stop`],
//! [`Report`], [`OptimError`]), `bounds` ([`Bounds`]), `population` ([`Population`]) and
//! `swarm` (the engine every algorithm shares: generator, population, best so far); then one
//! module per algorithm, and their building blocks.

mod bounds;
mod contracts;
mod population;
mod swarm;

pub mod any;
#[cfg(feature = "functions")]
#[cfg_attr(docsrs, doc(cfg(feature = "functions")))]
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

pub use bounds::Bounds;
pub(crate) use bounds::clamp_into;
pub use contracts::{Objective, OptimError, Optimizer, Report, Settings, Stop, StopReason};
pub(crate) use contracts::{check_param, forward_optimizer};
pub use population::Population;
pub(crate) use population::copy;
pub use swarm::Initialisation;
pub(crate) use swarm::{SwarmState, Tracker, swarm_accessors};

/// Square root: [`crate::math::sqrt`] (the FPU's `VSQRT.F32` on hard-float targets).
pub(crate) use crate::math::sqrt as sqrtf;

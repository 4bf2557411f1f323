//! Allocation-free path planning for warehouse robots.
//!
//! `planner-core` is `#![no_std]`, uses no allocator and never panics on input: every
//! capacity is chosen by the caller through const generics and every bad input is a typed
//! error. It builds for the host and for `thumbv7em-none-eabihf` (Cortex-M4F firmware).
//!
//! A plan: a map, a [`planner::PlanStorage`] (everything a plan needs, sized by constants;
//! all zero bytes, so firmware keeps it in a `static`), and the planner's parameters.
//!
//! ```
//! use planner_core::{Cell, Grid, words_for};
//! use planner_core::planner::{AlgorithmKind, PlanOptions, PlanParams, PlanStorage};
//!
//! let grid: Grid<{ words_for(12, 6) }> = Grid::parse_rows(
//!     b"............\n....@@@@....\n....@@@@....\n............\n..@@@@@@@@..\n............\n")?;
//! // Population 30, dimension 16, paths of 128 waypoints, a mesh of up to 16 rectangles and
//! // 32 links, 64 open nodes of the any-angle search.
//! let mut storage = Box::new(PlanStorage::<30, 16, 128, 16, 32, 64>::new());
//! storage.prepare(grid.view())?; // once per map
//! let params = PlanParams::new(AlgorithmKind::Tclhho);
//! let (start, goal) = (Cell::new(0, 2), Cell::new(11, 3));
//! let report = storage.plan(grid.view(), start, goal, &params, PlanOptions::default())?;
//! assert_eq!(planner_core::path::validate(grid.view(), storage.path(), start, goal), Ok(()));
//! assert!(report.length <= report.initial_cost);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Layers, bottom up:
//! - [`math`]: `f32` helpers that give the same results on the MCU and the host;
//! - [`grid`]: the bit-packed occupancy grid, Moving AI `.map` parsing, inflation;
//! - [`geometry`]: points, cells and the one collision rule every planner and check shares;
//! - [`path`]: fixed-capacity paths and their metrics;
//! - [`search`]: exact reference planners (A*, Theta*, the exact any-angle planner
//!   [`search::anyangle`]) and connectivity labelling;
//! - [`optim`]: the swarm optimizers of the papers (HHO, TCLHHO, GWO, IGWO, SSA, ...);
//! - [`encoding`]: how a decision vector becomes a path (corridor, column, walk);
//! - [`planner`]: one planning API over every optimizer and encoding ([`planner::plan`],
//!   [`planner::PlanStorage`]), and the ant colony baseline;
//! - [`dwa`]: the Dynamic Window Approach local planner (seed 004);
//! - [`terrain`]: 3D terrain planning (seed 001);
//! - [`maps`]: the papers' maps; [`error`]: every error type.
#![no_std]
#![deny(unsafe_code)]
#![warn(missing_docs)]

#[cfg(test)]
extern crate std;

pub mod dwa;
pub mod error;
pub mod geometry;
pub mod grid;
pub mod math;
pub mod optim;
pub mod path;
pub mod search;
pub mod terrain;

pub use error::{GridError, MapError, PlanError};
pub use geometry::{Cell, Point};
pub use grid::{Grid, GridRef, words_for};
pub mod encoding;
pub mod maps;
pub mod planner;

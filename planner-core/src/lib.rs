//! Allocation-free path planning for warehouse robots.
//!
//! `planner-core` is `#![no_std]`, uses no allocator and never panics on input: every
//! capacity is chosen by the caller through const generics and every bad input is a typed
//! error. It builds for the host and for `thumbv7em-none-eabihf` (Cortex-M4F firmware).
//!
//! Layers, bottom up:
//! - [`grid`]: the bit-packed occupancy grid, Moving AI `.map` parsing, inflation;
//! - [`geometry`]: points, cells and the one collision rule every planner and check shares;
//! - [`path`]: fixed-capacity paths and their metrics;
//! - [`search`]: exact reference planners (A*, Theta*, the exact any-angle planner
//!   [`search::anyangle`]) and connectivity labelling;
//! - [`optim`]: the swarm optimizers of the papers (HHO, TCLHHO, GWO, IGWO, SSA, ...).
//! - [`dwa`]: the Dynamic Window Approach local planner (seed 004).
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

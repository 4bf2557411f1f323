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
//! - [`dwa`]: the Dynamic Window Approach local planner (of the HHO+DWA patent,
//!   `Hu2023HhoDwa`);
//! - [`terrain`]: 3D terrain planning (of the SSA-GWO orchard paper, `Zhu2025Orchard`);
//! - [`maps`]: the papers' maps (the TCLHHO warehouse paper's, `Lei2024Warehouse`, and the
//!   IGWO grid paper's lab, `Liu2020Igwo`); [`error`]: every error type.
//!
//! Papers are named by the keys of `docs/references.md`, which gives each one's citation.
//!
//! # Features
//!
//! | feature | default | what |
//! |---|---|---|
//! | `terrain` | yes | [`terrain`], 3D terrain planning of `Zhu2025Orchard` |
//! | `functions` | yes | [`optim::functions`], the optimizers' benchmark test functions |
//! | `maps` | yes | [`maps`], the papers' maps, generated |
//! | `blend` | yes | blended objectives ([`planner::Blend`]: length, turning, missing clearance) for the corridor encoding; without it only length is accepted and the code is not linked |
//! | `defmt` | no | `defmt::Format` on the error types, [`Cell`], [`Point`] and the small report and stats structs ([`planner::PlanReport`], [`optim::Report`], [`search::SearchStats`], ...), for firmware logging |
//! | `serde` | no | `Serialize` and `Deserialize` on the public data types |
//! | `alloc` | no | heap-allocated scratch for hosts (`planner::owned`, `search::visibility`) |
//! | `soft-sqrt` | no | the software square root (`libm`) on hard-float ARM instead of `VSQRT.F32` (same results) |
//!
//! Firmware takes `default-features = false` and names what it uses (the firmware proof in
//! `tests/firmware` takes `maps`); everything else builds without any feature, for the host and
//! for `thumbv7em-none-eabihf`.
#![no_std]
#![cfg_attr(docsrs, feature(doc_cfg))]
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
#[cfg(feature = "terrain")]
#[cfg_attr(docsrs, doc(cfg(feature = "terrain")))]
pub mod terrain;

pub use error::{GridError, MapError, PlanError};
pub use geometry::{Cell, Point};
pub use grid::{Grid, GridRef, words_for};
pub mod encoding;
#[cfg(feature = "maps")]
#[cfg_attr(docsrs, doc(cfg(feature = "maps")))]
pub mod maps;
pub mod planner;

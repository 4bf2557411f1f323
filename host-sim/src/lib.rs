//! `host-sim` as a library: the parts that integration tests, fuzz targets and other tools
//! reuse. The CLI in `main.rs` is a thin layer over these modules.
//!
//! - [`exit`]: the exit statuses (0 done, 1 other failure, 2 bad input, 3 mission failed);
//! - [`heap`]: heap bytes in use, counted by the binary's allocator (peak-memory figures);
//! - [`mapfile`]: map files (Moving AI, ROS `map_server`), the `planner-mapfile` crate
//!   re-exported: one loader ([`mapfile::load_map`]) under one size limit (`--max-cells`),
//!   into grids sized at run time (`planner_core::grid::GridBuf`);
//! - [`printed`]: printed paths read back as a consumer reads them and checked;
//! - [`render`]: PNG/SVG pictures;
//! - [`sim`]: the warehouse simulator (diff-drive robot, DWA, dynamic obstacles, missions);
//! - [`stats`]: mean and standard deviation of the benchmarks' and experiments' figures;
//! - [`terrain`]: 3D terrain planning (`Zhu2025Orchard`): the experiments, generated and imported
//!   terrains, the algorithms' runs and their statistics (`host-sim terrain` prints them);
//! - [`validate`]: an independent f64 path validator (also of printed paths read back);
//! - [`terrain_check`]: an independent f64 checker of 3D terrain paths (`Zhu2025Orchard`);
//! - [`warehouse_gen`]: generated warehouse layouts (shelves, aisles, stations) under the
//!   same size limit.
//!
//! The papers are named by their keys in `docs/references.md` (`Lei2024Warehouse`, the TCLHHO
//! warehouse paper; `Zhu2025Orchard`, the SSA-GWO orchard terrain paper; `Liu2020Igwo`, the
//! IGWO grid paper; `Hu2023HhoDwa`, the HHO+DWA patent), which also gives their citations.
//!
//! "Maps" has one meaning here: `planner_core::maps`, the papers' built-in maps, which
//! `host-sim maps` writes out as `.map` files. Map files are [`mapfile`]'s, generated
//! warehouses [`warehouse_gen`]'s.

pub mod exit;
pub mod heap;
pub mod printed;
pub mod render;
pub mod sim;
pub mod stats;
pub mod terrain;
pub mod terrain_check;
pub mod validate;
pub mod warehouse_gen;

/// Map files into planner grids: the `planner-mapfile` crate, which every command that reads
/// a map file goes through, re-exported for tools built on this library (the fuzz targets).
pub use planner_mapfile as mapfile;

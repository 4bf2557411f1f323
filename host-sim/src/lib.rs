//! `host-sim` as a library: the parts that integration tests, fuzz targets and other tools
//! reuse. The CLI in `main.rs` is a thin layer over these modules.
//!
//! - [`exit`]: the exit statuses (0 done, 1 other failure, 2 bad input, 3 mission failed);
//! - [`mapsrc`]: maps from files (Moving AI, ROS `map_server`) and generated warehouses, one
//!   loader ([`mapsrc::load_map`]) under one size limit (`--max-cells`), into grids sized at
//!   run time (`planner_core::grid::GridBuf`);
//! - [`printed`]: printed paths read back as a consumer reads them and checked;
//! - [`render`]: PNG/SVG pictures;
//! - [`sim`]: the warehouse simulator (diff-drive robot, DWA, dynamic obstacles, missions);
//! - [`validate`]: an independent f64 path validator (also of printed paths read back);
//! - [`terrain_check`]: an independent f64 checker of 3D terrain paths (seed 001).

pub mod exit;
pub mod heap;
pub mod mapsrc;
pub mod printed;
pub mod render;
pub mod sim;
pub mod terrain_check;
pub mod validate;

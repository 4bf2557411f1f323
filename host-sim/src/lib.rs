//! `host-sim` as a library: the parts that integration tests, fuzz targets and other tools
//! reuse. The CLI in `main.rs` is a thin layer over these modules.
//!
//! - [`maps`]: Moving AI loading and host-sized grids;
//! - [`mapsrc`]: simulator map sources (generated warehouses, Moving AI, ROS `map_server`);
//! - [`render`]: PNG/SVG pictures;
//! - [`sim`]: the warehouse simulator (diff-drive robot, DWA, dynamic obstacles, missions);
//! - [`validate`]: an independent f64 path validator;
//! - [`terrain_check`]: an independent f64 checker of 3D terrain paths (seed 001).

pub mod maps;
pub mod mapsrc;
pub mod render;
pub mod sim;
pub mod terrain_check;
pub mod validate;

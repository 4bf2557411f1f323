//! Where maps come from, all into a [`GridBuf`](planner_core::grid::GridBuf) sized at run
//! time under one size limit ([`MapOptions`], `--max-cells`): map files through the loader
//! every command shares with `planner-client` (the `planner-mapfile` crate: Moving AI
//! `.map`, ROS `map_server` YAML + PGM/PNG, unknown space, world frame), and generated
//! warehouse layouts ([`warehouse`]).
//!
//! [`load_map`] is the loader every command uses for a map file; every failure is a
//! [`MapLoadError`] naming the file.

pub mod warehouse;

pub use planner_mapfile::{
    DEFAULT_MAX_CELLS, Frame, LoadedMap, MapFrame, MapLoadError, MapOptions, Unknown, display_name,
    error, frame, limit, load_map, movingai, options, ros,
};

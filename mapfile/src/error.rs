//! Why a map could not be loaded or generated: every variant names the file (or the
//! generator) it is about.

use crate::limit::describe_cells;
use crate::ros::RosMapError;
use planner_core::error::MapError;
use std::fmt;
use std::path::PathBuf;

/// A map that could not be loaded or generated.
#[derive(Debug)]
pub enum MapLoadError {
    /// The file could not be read.
    Read {
        /// The file.
        path: PathBuf,
        /// What the system said.
        error: std::io::Error,
    },
    /// The map is bigger than `--max-cells`.
    TooLarge {
        /// The file, or what generated the map.
        source: String,
        /// Declared width in cells.
        width: usize,
        /// Declared height in cells.
        height: usize,
        /// The limit in force.
        max_cells: usize,
    },
    /// Moving AI `.map` text that does not parse.
    MovingAi {
        /// The file.
        path: PathBuf,
        /// The parser's error.
        error: MapError,
    },
    /// A ROS `map_server` YAML or its image that does not load.
    Ros {
        /// The YAML file.
        path: PathBuf,
        /// The loader's error (it names the image file when the image is at fault).
        error: RosMapError,
    },
    /// A generated layout whose parameters do not make a map.
    Layout(String),
}

impl fmt::Display for MapLoadError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MapLoadError::Read { path, error } => {
                write!(f, "cannot read map {}: {error}", path.display())
            }
            MapLoadError::TooLarge {
                source,
                width,
                height,
                max_cells,
            } => {
                let cells = width.saturating_mul(*height);
                write!(
                    f,
                    "{source}: map of {width} x {height} = {cells} cells is over the limit of {}; \
                     raise it with --max-cells (e.g. --max-cells {width}x{height})",
                    describe_cells(*max_cells)
                )
            }
            MapLoadError::MovingAi { path, error } => {
                write!(f, "invalid map {}: {error}", path.display())
            }
            MapLoadError::Ros { path, error } => {
                write!(f, "invalid ROS map {}: {error}", path.display())
            }
            MapLoadError::Layout(detail) => write!(f, "generated warehouse: {detail}"),
        }
    }
}

impl std::error::Error for MapLoadError {}

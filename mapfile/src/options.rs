//! What every command that loads a map file lets its user choose: the size limit
//! (`--max-cells`) and what unknown space is (`--unknown blocked|free`).

use crate::error::MapLoadError;
use crate::limit::{DEFAULT_MAX_CELLS, parse_max_cells};

/// What unknown cells of a ROS map (neither free nor occupied by the YAML's thresholds, or
/// transparent) are for planning. Moving AI maps have no unknown cells.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, clap::ValueEnum)]
pub enum Unknown {
    /// Unknown space is blocked (the safe default, as Nav2's planners treat it with
    /// `allow_unknown: false`).
    #[default]
    Blocked,
    /// Unknown space is free (Nav2's `allow_unknown: true`).
    Free,
}

impl Unknown {
    /// The flag value.
    pub fn name(self) -> &'static str {
        match self {
            Unknown::Blocked => "blocked",
            Unknown::Free => "free",
        }
    }
}

/// Options of the map loader and generators (`--max-cells`, `--unknown`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::Args)]
pub struct MapOptions {
    /// Largest map accepted, in cells: a count (`16777216`) or `WxH` (`4096x4096`).
    #[arg(long = "max-cells", value_parser = parse_max_cells, default_value = "4096x4096")]
    pub max_cells: usize,
    /// Unknown space of a ROS map (grey, between the YAML's thresholds): blocked or free.
    #[arg(long, value_enum, default_value_t = Unknown::Blocked)]
    pub unknown: Unknown,
}

impl Default for MapOptions {
    fn default() -> Self {
        MapOptions {
            max_cells: DEFAULT_MAX_CELLS,
            unknown: Unknown::Blocked,
        }
    }
}

impl MapOptions {
    /// A `width x height` map from `source` (a file name, "generated warehouse"...) is within
    /// the limit, or the typed error naming the source, the size, the limit and the flag.
    pub fn check(&self, source: &str, width: usize, height: usize) -> Result<(), MapLoadError> {
        if width
            .checked_mul(height)
            .is_some_and(|c| c <= self.max_cells)
        {
            return Ok(());
        }
        Err(MapLoadError::TooLarge {
            source: source.to_string(),
            width,
            height,
            max_cells: self.max_cells,
        })
    }
}

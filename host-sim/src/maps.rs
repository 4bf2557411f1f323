//! Loading maps into the host's fixed-capacity grid.

use anyhow::Context;
use planner_core::grid::{Grid, words_for};
use std::path::Path;

/// Largest map the host tools accept: 1024 x 1024 cells (the biggest Moving AI warehouse
/// is 340 x 164).
pub const HOST_WORDS: usize = words_for(1024, 1024);

/// The host's grid type.
pub type HostGrid = Grid<HOST_WORDS>;

/// Reads and parses a Moving AI `.map` file.
pub fn load_movingai(path: &Path) -> anyhow::Result<Box<HostGrid>> {
    let bytes =
        std::fs::read(path).with_context(|| format!("cannot read map {}", path.display()))?;
    let grid = HostGrid::parse_movingai(&bytes)
        .with_context(|| format!("invalid map {}", path.display()))?;
    Ok(Box::new(grid))
}

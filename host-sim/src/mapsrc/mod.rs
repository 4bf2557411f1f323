//! Where simulator maps come from: generated warehouse layouts ([`warehouse`]), Moving AI
//! `.map` files and ROS `map_server` YAML + PGM/PNG ([`ros`]).

pub mod ros;
pub mod warehouse;

use crate::maps::{HostGrid, load_movingai};
use planner_core::geometry::Cell;
use std::path::Path;

/// A loaded map with its named places.
pub struct LoadedMap {
    /// The grid (blocked = occupied or unknown).
    pub grid: Box<HostGrid>,
    /// A short name for titles.
    pub name: String,
    /// Pick stations (generated layouts).
    pub picks: Vec<Cell>,
    /// Charging stations (generated layouts).
    pub chargers: Vec<Cell>,
    /// Metres per cell, when the source says (ROS maps).
    pub resolution: Option<f64>,
}

/// Loads a `.map` (Moving AI) or `.yaml` (ROS map_server) file.
pub fn load(path: &Path) -> anyhow::Result<LoadedMap> {
    let name = path
        .file_stem()
        .map_or_else(|| "map".into(), |s| s.to_string_lossy().into_owned());
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase());
    match ext.as_deref() {
        Some("yaml") | Some("yml") => {
            let m = ros::load(path)?;
            Ok(LoadedMap {
                grid: m.grid,
                name,
                picks: Vec::new(),
                chargers: Vec::new(),
                resolution: Some(m.meta.resolution),
            })
        }
        _ => Ok(LoadedMap {
            grid: load_movingai(path)?,
            name,
            picks: Vec::new(),
            chargers: Vec::new(),
            resolution: None,
        }),
    }
}

//! Generated warehouse layouts: blocks of shelves with aisles between them, cross-aisles
//! across the blocks, a free margin around (the main travel lane), pick stations in front
//! of the aisles on the bottom lane and charging stations along the left wall.
//!
//! ```text
//! margin | shelf shelf aisle shelf shelf aisle ... | margin
//! ```
//! Shelf units are `shelf_depth` cells wide (double-sided racks), `shelf_len` cells long;
//! aisles are `aisle` cells wide; `cross` free rows separate the shelf blocks.

use crate::maps::HostGrid;
use anyhow::{Context, bail};
use planner_core::geometry::Cell;

/// Layout parameters (cells).
#[derive(Clone, Copy, Debug, clap::Args, serde::Serialize)]
pub struct WarehouseParams {
    /// Map width.
    #[arg(long, default_value_t = 40)]
    pub width: usize,
    /// Map height.
    #[arg(long, default_value_t = 40)]
    pub height: usize,
    /// Shelf depth (cells across a rack).
    #[arg(long, default_value_t = 2)]
    pub shelf_depth: usize,
    /// Shelf length (cells along a rack).
    #[arg(long, default_value_t = 6)]
    pub shelf_len: usize,
    /// Aisle width.
    #[arg(long, default_value_t = 2)]
    pub aisle: usize,
    /// Cross-aisle width.
    #[arg(long, default_value_t = 2)]
    pub cross: usize,
    /// Free margin around the racks (travel lane).
    #[arg(long, default_value_t = 2)]
    pub margin: usize,
    /// Charging stations along the left wall.
    #[arg(long, default_value_t = 3)]
    pub chargers: usize,
}

impl Default for WarehouseParams {
    fn default() -> Self {
        WarehouseParams {
            width: 40,
            height: 40,
            shelf_depth: 2,
            shelf_len: 6,
            aisle: 2,
            cross: 2,
            margin: 2,
            chargers: 3,
        }
    }
}

/// A generated layout.
pub struct Warehouse {
    /// The grid.
    pub grid: Box<HostGrid>,
    /// Pick stations: bottom lane, in front of each aisle.
    pub picks: Vec<Cell>,
    /// Charging stations: left wall.
    pub chargers: Vec<Cell>,
}

/// Generates a layout.
pub fn generate(p: &WarehouseParams) -> anyhow::Result<Warehouse> {
    if p.width < 2 * p.margin + p.shelf_depth + 1
        || p.height < 2 * p.margin + p.shelf_len + 1
        || p.shelf_depth == 0
        || p.shelf_len == 0
        || p.aisle == 0
        || p.margin == 0
        || p.width > 1024
        || p.height > 1024
    {
        bail!("warehouse layout does not fit: {p:?}");
    }
    let mut grid = Box::new(HostGrid::new(p.width, p.height).context("warehouse size")?);
    let period_x = p.shelf_depth + p.aisle;
    let period_y = p.shelf_len + p.cross;
    let mut picks = Vec::new();
    for y in p.margin..p.height - p.margin {
        if (y - p.margin) % period_y >= p.shelf_len {
            continue;
        }
        for x in p.margin..p.width - p.margin {
            if (x - p.margin) % period_x < p.shelf_depth {
                grid.set_blocked(x, y, true)?;
            }
        }
    }
    // Pick stations: the bottom lane cell in front of each aisle.
    let yp = p.height - 1 - (p.margin - 1) / 2;
    for x in p.margin..p.width - p.margin {
        if (x - p.margin) % period_x == p.shelf_depth {
            picks.push(Cell::new(x as u16, yp as u16));
        }
    }
    let chargers = (0..p.chargers)
        .map(|i| {
            let y = p.margin + (i + 1) * (p.height - 2 * p.margin) / (p.chargers + 1);
            Cell::new(0, y as u16)
        })
        .collect();
    Ok(Warehouse {
        grid,
        picks,
        chargers,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn default_layout_has_racks_aisles_and_stations() {
        let w = generate(&WarehouseParams::default()).unwrap();
        let g = w.grid.view();
        assert!(g.is_blocked(2, 2) && g.is_blocked(3, 2));
        assert!(!g.is_blocked(4, 2) && !g.is_blocked(5, 2));
        // Cross-aisle after 6 rows.
        assert!(!g.is_blocked(2, 8) && !g.is_blocked(2, 9));
        assert!(!w.picks.is_empty() && w.chargers.len() == 3);
        for c in w.picks.iter().chain(&w.chargers) {
            assert!(g.is_free(*c));
        }
    }

    #[test]
    fn bad_parameters_are_errors() {
        let p = WarehouseParams {
            width: 3,
            ..WarehouseParams::default()
        };
        assert!(generate(&p).is_err());
    }
}

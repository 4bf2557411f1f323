//! Generated warehouse layouts: blocks of shelves with aisles between them, cross-aisles
//! across the blocks, a free margin around (the main travel lane), pick stations in front
//! of the aisles on the bottom lane and charging stations along the left wall.
//!
//! ```text
//! margin | shelf shelf aisle shelf shelf aisle ... | margin
//! ```
//! Shelf units are `shelf_depth` cells wide (double-sided racks), `shelf_len` cells long;
//! aisles are `aisle` cells wide; `cross` free rows separate the shelf blocks.

use planner_core::geometry::Cell;
use planner_core::grid::GridBuf;
use planner_mapfile::{MapLoadError, MapOptions};

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
#[derive(Debug)]
pub struct Warehouse {
    /// The grid.
    pub grid: GridBuf,
    /// Pick stations: bottom lane, in front of each aisle.
    pub picks: Vec<Cell>,
    /// Charging stations: left wall.
    pub chargers: Vec<Cell>,
}

/// Generates a layout; a map of more than `options.max_cells` cells is
/// [`MapLoadError::TooLarge`].
pub fn generate(p: &WarehouseParams, options: &MapOptions) -> Result<Warehouse, MapLoadError> {
    if p.width < 2 * p.margin + p.shelf_depth + 1
        || p.height < 2 * p.margin + p.shelf_len + 1
        || p.shelf_depth == 0
        || p.shelf_len == 0
        || p.aisle == 0
        || p.margin == 0
    {
        return Err(MapLoadError::Layout(format!("layout does not fit: {p:?}")));
    }
    options.check("generated warehouse", p.width, p.height)?;
    let mut grid = GridBuf::new(p.width, p.height)
        .map_err(|e| MapLoadError::Layout(format!("{} x {}: {e}", p.width, p.height)))?;
    let period_x = p.shelf_depth + p.aisle;
    let period_y = p.shelf_len + p.cross;
    // One shelf row's bits, then every row that holds shelves gets them.
    let mut shelf_row = vec![0u32; p.width.div_ceil(32)];
    for x in p.margin..p.width - p.margin {
        if (x - p.margin) % period_x < p.shelf_depth {
            shelf_row[x / 32] |= 1 << (x % 32);
        }
    }
    let shelves = |y: usize| {
        (p.margin..p.height - p.margin).contains(&y) && (y - p.margin) % period_y < p.shelf_len
    };
    grid.view_mut()
        .fill_rows(|y, words| {
            if shelves(y) {
                words.copy_from_slice(&shelf_row);
            }
        })
        .map_err(|e| MapLoadError::Layout(format!("{} x {}: {e}", p.width, p.height)))?;
    let mut picks = Vec::new();
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
        let w = generate(&WarehouseParams::default(), &MapOptions::default()).unwrap();
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
        let e = generate(&p, &MapOptions::default()).unwrap_err();
        assert!(matches!(e, MapLoadError::Layout(_)), "{e:?}");
    }

    #[test]
    fn rows_match_the_layout_rule_and_the_limit_holds() {
        let p = WarehouseParams {
            width: 77,
            height: 50,
            shelf_depth: 2,
            shelf_len: 5,
            aisle: 3,
            cross: 2,
            margin: 3,
            chargers: 2,
        };
        let g = generate(&p, &MapOptions::default()).unwrap().grid;
        let v = g.view();
        for y in 0..p.height {
            for x in 0..p.width {
                let inside = (3..p.width - 3).contains(&x) && (3..p.height - 3).contains(&y);
                let shelf = inside && (x - 3) % 5 < 2 && (y - 3) % 7 < 5;
                assert_eq!(v.is_blocked(x as isize, y as isize), shelf, "({x}, {y})");
            }
        }
        let e = generate(
            &p,
            &MapOptions {
                max_cells: 77 * 50 - 1,
                ..MapOptions::default()
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("--max-cells"), "{e}");
        assert!(
            generate(
                &p,
                &MapOptions {
                    max_cells: 77 * 50,
                    ..MapOptions::default()
                }
            )
            .is_ok()
        );
    }
}

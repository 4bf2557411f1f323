//! The cell and point types. A leaf module (it uses only [`crate::math`]): [`crate::grid`]
//! builds on [`Cell`], and the rest of `geometry` builds on the grid.

/// A grid cell, `(x, y)` = (column, row).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Cell {
    /// Column.
    pub x: u16,
    /// Row (grows downwards).
    pub y: u16,
}

impl Cell {
    /// A cell from its column and row.
    pub const fn new(x: u16, y: u16) -> Self {
        Cell { x, y }
    }

    /// The continuous point at the cell's centre.
    pub fn center(self) -> Point {
        Point::new(self.x as f32, self.y as f32)
    }
}

/// A continuous point in cell units: `(x, y)` = the centre of cell `(x, y)` when integral.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Point {
    /// Horizontal coordinate (column units).
    pub x: f32,
    /// Vertical coordinate (row units, downwards).
    pub y: f32,
}

impl Point {
    /// A point from its coordinates.
    pub const fn new(x: f32, y: f32) -> Self {
        Point { x, y }
    }

    /// Euclidean distance.
    pub fn distance(self, other: Point) -> f32 {
        let (dx, dy) = (other.x - self.x, other.y - self.y);
        crate::math::sqrt(dx * dx + dy * dy)
    }

    /// Whether both coordinates are finite.
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite()
    }
}

impl From<Cell> for Point {
    fn from(cell: Cell) -> Self {
        cell.center()
    }
}

/// Octile distance between cells: the shortest 8-connected length on an empty map.
pub fn octile(a: Cell, b: Cell) -> f32 {
    let dx = (a.x as i32 - b.x as i32).unsigned_abs() as f32;
    let dy = (a.y as i32 - b.y as i32).unsigned_abs() as f32;
    let (lo, hi) = if dx < dy { (dx, dy) } else { (dy, dx) };
    hi + (core::f32::consts::SQRT_2 - 1.0) * lo
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn octile_matches_definition() {
        assert_eq!(octile(Cell::new(0, 0), Cell::new(3, 0)), 3.0);
        let d = octile(Cell::new(0, 0), Cell::new(3, 5));
        assert!((d - (2.0 + 3.0 * core::f32::consts::SQRT_2)).abs() < 1e-5);
    }
}

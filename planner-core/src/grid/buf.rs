//! [`GridBuf`]: a grid whose storage is sized at run time on the heap (feature `alloc`),
//! for hosts that load maps of any size. Everything that reads a grid takes the same
//! [`GridRef`] view as for the fixed-capacity [`Grid`](super::Grid).

extern crate alloc;

use alloc::vec;
use alloc::vec::Vec;

use super::{GridMut, GridRef, MAX_SIDE, inflate, movingai};
use crate::error::{GridError, MapError};

/// A bit-packed occupancy grid sized at run time (row- and column-major bits, as
/// [`Grid`](super::Grid): 2 bits a cell).
///
/// ```
/// use planner_core::grid::GridBuf;
///
/// let text = b"type octile\nheight 2\nwidth 3\nmap\n..@\n...\n";
/// let grid = GridBuf::parse_movingai(text, 4096 * 4096)?;
/// assert!(grid.view().is_blocked(2, 0));
/// # Ok::<(), planner_core::error::MapError>(())
/// ```
#[derive(Clone, PartialEq, Eq)]
pub struct GridBuf {
    width: usize,
    height: usize,
    bits: Vec<u32>,
    columns: Vec<u32>,
}

impl core::fmt::Debug for GridBuf {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        write!(f, "GridBuf({} x {})", self.width, self.height)
    }
}

impl GridBuf {
    /// An all-free grid; a zero side or a side above [`MAX_SIDE`] is
    /// [`GridError::CapacityExceeded`].
    pub fn new(width: usize, height: usize) -> Result<Self, GridError> {
        if width == 0 || height == 0 || width > MAX_SIDE || height > MAX_SIDE {
            return Err(GridError::CapacityExceeded);
        }
        let words = (width * height).div_ceil(32);
        Ok(GridBuf {
            width,
            height,
            bits: vec![0; words],
            columns: vec![0; words],
        })
    }

    /// A copy of any grid.
    pub fn from_view(grid: GridRef<'_>) -> Self {
        GridBuf {
            width: grid.width,
            height: grid.height,
            bits: grid.bits.to_vec(),
            columns: grid.columns.to_vec(),
        }
    }

    /// Parses Moving AI `.map` text (see [`Grid::parse_movingai`](super::Grid::parse_movingai));
    /// a declared size of more than `max_cells` cells is [`MapError::CapacityExceeded`]
    /// before anything is allocated.
    pub fn parse_movingai(text: &[u8], max_cells: usize) -> Result<Self, MapError> {
        let (width, height, mut body) = movingai::header(text)?;
        let mut grid = Self::sized(width, height, max_cells)?;
        movingai::fill(&mut grid.view_mut(), &mut body)?;
        Ok(grid)
    }

    /// Parses bare rows of terrain characters (see [`Grid::parse_rows`](super::Grid::parse_rows)).
    pub fn parse_rows(text: &[u8]) -> Result<Self, MapError> {
        let (width, height) = movingai::rows_size(text);
        let mut grid = Self::sized(width, height, usize::MAX)?;
        movingai::fill_rows(&mut grid.view_mut(), text)?;
        Ok(grid)
    }

    fn sized(width: usize, height: usize, max_cells: usize) -> Result<Self, MapError> {
        if width
            .checked_mul(height)
            .is_none_or(|cells| cells > max_cells)
        {
            return Err(movingai::size_error(width, height));
        }
        Self::new(width, height).map_err(|_| movingai::size_error(width, height))
    }

    /// Width in cells.
    pub const fn width(&self) -> usize {
        self.width
    }

    /// Height in cells.
    pub const fn height(&self) -> usize {
        self.height
    }

    /// The view that planners take.
    pub fn view(&self) -> GridRef<'_> {
        GridRef {
            width: self.width,
            height: self.height,
            bits: &self.bits,
            columns: &self.columns,
        }
    }

    /// The mutable view (loaders, bulk row writes).
    pub fn view_mut(&mut self) -> GridMut<'_> {
        GridMut {
            width: self.width,
            height: self.height,
            bits: &mut self.bits,
            columns: &mut self.columns,
        }
    }

    /// Marks a cell blocked (`true`) or free (`false`).
    pub fn set_blocked(&mut self, x: usize, y: usize, blocked: bool) -> Result<(), GridError> {
        self.view_mut().set_blocked(x, y, blocked)
    }

    /// This grid inflated by a robot `radius` in cells (see
    /// [`Grid::inflate_into`](super::Grid::inflate_into)).
    pub fn inflated(&self, radius: f32) -> Result<GridBuf, GridError> {
        inflate::check_radius(radius)?;
        let mut out = GridBuf::new(self.width, self.height)?;
        inflate::inflate(self.view(), radius, &mut out.view_mut())?;
        Ok(out)
    }

    /// Writes the grid as Moving AI `.map` text.
    pub fn write_movingai(&self, out: &mut impl core::fmt::Write) -> core::fmt::Result {
        movingai::write(self.view(), out)
    }

    /// Bytes of heap this grid holds.
    pub fn heap_bytes(&self) -> usize {
        4 * (self.bits.len() + self.columns.len())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};

    #[test]
    fn parses_like_the_fixed_grid_and_refuses_huge_headers_before_allocating() {
        let text = b"type octile\nheight 3\nwidth 4\nmap\n..@.\n@...\n...@\n";
        let buf = GridBuf::parse_movingai(text, 100).unwrap();
        let fixed = Grid::<{ words_for(4, 3) }>::parse_movingai(text).unwrap();
        for y in -1..4 {
            for x in -1..5 {
                assert_eq!(buf.view().is_blocked(x, y), fixed.view().is_blocked(x, y));
            }
        }
        assert_eq!(
            GridBuf::parse_movingai(
                b"type octile\nheight 60000\nwidth 60000\nmap\n",
                4096 * 4096
            ),
            Err(MapError::CapacityExceeded {
                width: 60000,
                height: 60000
            })
        );
        assert_eq!(GridBuf::new(0, 3), Err(GridError::CapacityExceeded));
    }
}

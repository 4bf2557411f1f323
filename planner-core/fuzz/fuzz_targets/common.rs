//! Input pieces shared by the structured targets.
#![allow(dead_code)]

use arbitrary::Arbitrary;
use planner_core::geometry::Cell;
use planner_core::grid::{Grid, words_for};

/// Largest side of a fuzzed map.
pub const SIDE: usize = 24;
/// Maps of up to 24 x 24 cells.
pub type SmallGrid = Grid<{ words_for(SIDE, SIDE) }>;

/// A small map: size and occupancy bits (missing bits are free).
#[derive(Arbitrary, Debug)]
pub struct MapInput {
    pub width: u8,
    pub height: u8,
    /// Keep only every `sparsity`-th set bit's worth of walls: 0/1 keep all.
    pub sparsity: u8,
    pub bits: [u64; 9],
}

impl MapInput {
    pub fn build(&self) -> SmallGrid {
        let w = self.width as usize % SIDE + 1;
        let h = self.height as usize % SIDE + 1;
        let mut g = SmallGrid::new(w, h).expect("24 x 24 fits");
        let keep = self.sparsity % 4;
        for y in 0..h {
            for x in 0..w {
                let i = y * w + x;
                let mut bit = self.bits[i / 64] >> (i % 64) & 1 == 1;
                // Thin the walls out so that most maps stay connected.
                if keep > 0 && bit {
                    bit = self.bits[(i + 17) % 576 / 64] >> ((i + 17) % 64) & 1 == 1;
                    if keep > 1 {
                        bit = bit && self.bits[(i + 101) % 576 / 64] >> ((i + 101) % 64) & 1 == 1;
                    }
                }
                g.set_blocked(x, y, bit).expect("in bounds");
            }
        }
        g
    }
}

/// An endpoint: usually inside the map, sometimes any `u16` pair.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum EndpointInput {
    Inside(u8, u8),
    Raw(u16, u16),
}

impl EndpointInput {
    pub fn cell(self, width: usize, height: usize) -> Cell {
        match self {
            EndpointInput::Inside(x, y) => {
                Cell::new((x as usize % width) as u16, (y as usize % height) as u16)
            }
            EndpointInput::Raw(x, y) => Cell::new(x, y),
        }
    }
}

/// A float parameter: usually a sensible value, sometimes any bit pattern (NaN, inf, ...).
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum FloatInput {
    /// `n / 8`.
    Nice(u8),
    Raw(f32),
    Special(u8),
}

impl FloatInput {
    pub fn get(self) -> f32 {
        match self {
            FloatInput::Nice(n) => n as f32 / 8.0,
            FloatInput::Raw(v) => v,
            FloatInput::Special(k) => [
                f32::NAN,
                f32::INFINITY,
                f32::NEG_INFINITY,
                0.0,
                -0.0,
                f32::MAX,
                f32::MIN,
                f32::MIN_POSITIVE,
                f32::EPSILON,
                1e-30,
                1e30,
                -1.0,
            ][k as usize % 12],
        }
    }
}

/// A size parameter: usually small, sometimes zero or huge.
#[derive(Arbitrary, Debug, Clone, Copy)]
pub enum SizeInput {
    Small(u8),
    Huge(u8),
}

impl SizeInput {
    pub fn get(self, small_max: usize) -> usize {
        match self {
            SizeInput::Small(n) => n as usize % (small_max + 1),
            SizeInput::Huge(k) => [usize::MAX, usize::MAX / 2, u32::MAX as usize, 1 << 20, 129, 257]
                [k as usize % 6],
        }
    }
}

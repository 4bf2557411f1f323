//! Error types, one small enum per operation.
//!
//! [`PlanError`] follows the result codes of Nav2's `ComputePathToPose` action so that a
//! fleet manager can map them one to one; [`MapError`] and [`GridError`] belong to map
//! loading, editing and inflation.

use core::fmt;

/// Why a planner returned no path.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum PlanError {
    /// The start cell lies outside the map.
    StartOutsideMap,
    /// The goal cell lies outside the map.
    GoalOutsideMap,
    /// The start cell is blocked.
    StartOccupied,
    /// The goal cell is blocked.
    GoalOccupied,
    /// No collision-free path connects start and goal (detected exactly, by connectivity).
    NoValidPath,
    /// A caller-supplied buffer (search storage, path, population) is too small.
    CapacityExceeded,
    /// A parameter is NaN, infinite or outside its documented range.
    InvalidParameters,
    /// The evaluation, iteration or expansion budget ran out before a valid path was found.
    BudgetExhausted,
}

impl PlanError {
    /// Every variant, in declaration order (handy for exhaustive tests and wire codes).
    pub const ALL: [PlanError; 8] = [
        PlanError::StartOutsideMap,
        PlanError::GoalOutsideMap,
        PlanError::StartOccupied,
        PlanError::GoalOccupied,
        PlanError::NoValidPath,
        PlanError::CapacityExceeded,
        PlanError::InvalidParameters,
        PlanError::BudgetExhausted,
    ];

    /// The variant's name, as printed in JSON results (`"NoValidPath"`).
    pub const fn name(self) -> &'static str {
        match self {
            PlanError::StartOutsideMap => "StartOutsideMap",
            PlanError::GoalOutsideMap => "GoalOutsideMap",
            PlanError::StartOccupied => "StartOccupied",
            PlanError::GoalOccupied => "GoalOccupied",
            PlanError::NoValidPath => "NoValidPath",
            PlanError::CapacityExceeded => "CapacityExceeded",
            PlanError::InvalidParameters => "InvalidParameters",
            PlanError::BudgetExhausted => "BudgetExhausted",
        }
    }
}

impl fmt::Display for PlanError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let text = match self {
            PlanError::StartOutsideMap => "start lies outside the map",
            PlanError::GoalOutsideMap => "goal lies outside the map",
            PlanError::StartOccupied => "start cell is occupied",
            PlanError::GoalOccupied => "goal cell is occupied",
            PlanError::NoValidPath => "no collision-free path connects start and goal",
            PlanError::CapacityExceeded => "a buffer is too small for this map or path",
            PlanError::InvalidParameters => "invalid planner parameters",
            PlanError::BudgetExhausted => "budget exhausted before a valid path was found",
        };
        f.write_str(text)
    }
}

impl core::error::Error for PlanError {}

/// Why a Moving AI `.map` text was rejected. Lines and rows are 1-based as in an editor.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum MapError {
    /// A header line is missing, misspelt or has a malformed number.
    MalformedHeader {
        /// 1-based line number of the offending line.
        line: usize,
    },
    /// The header names a map type other than `octile`.
    UnsupportedType,
    /// Width or height is zero.
    EmptyMap,
    /// The map has more cells than the grid's capacity (or a side above 65535).
    CapacityExceeded {
        /// Declared width.
        width: usize,
        /// Declared height.
        height: usize,
    },
    /// A map row does not have exactly `width` characters.
    WrongRowLength {
        /// 1-based map row.
        row: usize,
        /// The declared width.
        expected: usize,
        /// The characters found.
        found: usize,
    },
    /// A character that is not a Moving AI terrain code.
    UnknownCharacter {
        /// 1-based map row.
        row: usize,
        /// 1-based column.
        column: usize,
        /// The offending byte.
        byte: u8,
    },
    /// Fewer rows than the declared height.
    MissingRows {
        /// The declared height.
        expected: usize,
        /// Rows found.
        found: usize,
    },
    /// Non-empty text after the last map row.
    TrailingData {
        /// 1-based line number of the first extra line.
        line: usize,
    },
}

impl fmt::Display for MapError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match *self {
            MapError::MalformedHeader { line } => write!(f, "malformed map header at line {line}"),
            MapError::UnsupportedType => f.write_str("unsupported map type (expected octile)"),
            MapError::EmptyMap => f.write_str("map width or height is zero"),
            MapError::CapacityExceeded { width, height } => {
                write!(f, "map {width}x{height} exceeds the grid capacity")
            }
            MapError::WrongRowLength {
                row,
                expected,
                found,
            } => write!(f, "map row {row} has {found} cells, expected {expected}"),
            MapError::UnknownCharacter { row, column, byte } => {
                write!(
                    f,
                    "unknown map character 0x{byte:02x} at row {row}, column {column}"
                )
            }
            MapError::MissingRows { expected, found } => {
                write!(f, "map has {found} rows, expected {expected}")
            }
            MapError::TrailingData { line } => {
                write!(f, "unexpected data after the map at line {line}")
            }
        }
    }
}

impl core::error::Error for MapError {}

/// Why a grid could not be built, edited or inflated.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum GridError {
    /// Width or height is zero, or the cell count exceeds the capacity.
    CapacityExceeded,
    /// A cell coordinate lies outside the map.
    OutOfBounds,
    /// The robot radius is negative, NaN or infinite.
    InvalidRadius,
    /// Source and destination grids differ in size.
    SizeMismatch,
}

impl fmt::Display for GridError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            GridError::CapacityExceeded => "grid size is zero or exceeds the capacity",
            GridError::OutOfBounds => "cell lies outside the map",
            GridError::InvalidRadius => "robot radius must be finite and not negative",
            GridError::SizeMismatch => "grids differ in size",
        })
    }
}

impl core::error::Error for GridError {}

//! Debug tool: evaluates `Lei2024Warehouse`'s column-encoding objective (the one `host-sim plan
//! --encoding column` optimises) on vectors read from standard input, for cross-checking
//! other implementations (`host-sim/bench/mealpy_column.py --validate`).
//!
//! ```text
//! cargo run --release -p planner-core --example column_cost -- MAP SX,SY GX,GY < vectors
//! ```
//!
//! Each input line is one vector (whitespace-separated numbers, read as `f32`, one per map
//! column from `SX` to `GX`); each output line is `length blocked cost`: the path length, the
//! number of blocked cells its segments touch (each segment counting its own), and the
//! objective value `length + penalty * blocked` in `f32`. The first output line is
//! `penalty P`.

use std::error::Error;
use std::io::{BufRead, Write};

use planner_core::encoding::Encoding;
use planner_core::encoding::column::ColumnEncoding;
use planner_core::geometry::Cell;
use planner_core::grid::{Grid, words_for};

type Big = Grid<{ words_for(1024, 1024) }>;

fn cell(s: &str) -> Result<Cell, Box<dyn Error>> {
    let (x, y) = s.split_once(',').ok_or("a cell is X,Y")?;
    Ok(Cell::new(x.trim().parse()?, y.trim().parse()?))
}

fn main() -> Result<(), Box<dyn Error>> {
    let args: Vec<String> = std::env::args().collect();
    let [_, map, start, goal] = args.as_slice() else {
        return Err("usage: column_cost MAP SX,SY GX,GY < vectors".into());
    };
    let grid = Box::new(Big::parse_movingai(&std::fs::read(map)?)?);
    let mut enc = ColumnEncoding::new(grid.view(), cell(start)?, cell(goal)?)?;
    let dim = enc.dim();
    let mut out = std::io::BufWriter::new(std::io::stdout().lock());
    writeln!(out, "penalty {}", enc.penalty())?;
    for line in std::io::stdin().lock().lines() {
        let line = line?;
        if line.trim().is_empty() {
            continue;
        }
        let x = line
            .split_whitespace()
            .map(str::parse::<f32>)
            .collect::<Result<Vec<_>, _>>()?;
        if x.len() != dim {
            return Err(format!("expected {dim} numbers, got {}", x.len()).into());
        }
        let (length, blocked) = enc.length_and_blocked(&x);
        writeln!(out, "{length} {blocked} {}", enc.cost(&x))?;
    }
    Ok(())
}

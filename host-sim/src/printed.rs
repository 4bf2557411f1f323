//! Paths as printed, read back the way a consumer reads them (JSON numbers as `f64`) and
//! checked with the independent validator ([`crate::validate`]): `host-sim plan` runs every
//! line it prints through [`check_line`] before printing it, and the round-trip tests run
//! the printed output of whole query files through it.
//!
//! `path` (cells) must run from the start cell's centre to the goal cell's centre with no
//! segment touching a blocked cell of the map it was planned on; `path_m` (metres, a map
//! with a world frame) is turned back into cells in `f64` and must do the same, its ends
//! within 1e-9 cell of the centres (the conversion's rounding).

use crate::validate::{Invalid, check_f64, check_segments};
use planner_core::grid::GridRef;
use planner_mapfile::MapFrame;
use serde_json::Value;

/// The waypoints of `key` (`path` or `path_m`) as numbers read back, if the line has them.
pub fn waypoints(line: &Value, key: &str) -> Option<Result<Vec<[f64; 2]>, String>> {
    let points = line.get(key)?;
    let read = || -> Option<Vec<[f64; 2]>> {
        points
            .as_array()?
            .iter()
            .map(|p| Some([p.get(0)?.as_f64()?, p.get(1)?.as_f64()?]))
            .collect()
    };
    Some(read().ok_or_else(|| format!("{key} is not a list of [x, y] numbers")))
}

fn cell_of(line: &Value, key: &str) -> Option<(u16, u16)> {
    let c = line.get(key)?;
    let v = |i: usize| c.get(i)?.as_u64().and_then(|v| u16::try_from(v).ok());
    Some((v(0)?, v(1)?))
}

fn describe(key: &str, e: Invalid) -> String {
    match e {
        Invalid::Empty => format!("{key} has no waypoint"),
        Invalid::Endpoints => format!("{key} does not run from the start to the goal centre"),
        Invalid::Collision { index } => format!(
            "segment {index} of {key}, read back from the printed text, touches a blocked cell"
        ),
    }
}

/// Checks one printed line (JSON text) on `grid`, the map the path was planned on; `frame`
/// converts `path_m` back to cells. A line without a path (an error) passes.
pub fn check_line(text: &str, grid: GridRef<'_>, frame: Option<&MapFrame>) -> Result<(), String> {
    let line: Value = serde_json::from_str(text).map_err(|e| format!("not JSON: {e}"))?;
    let Some(path) = waypoints(&line, "path") else {
        return Ok(());
    };
    let path = path?;
    let (Some(start), Some(goal)) = (cell_of(&line, "start"), cell_of(&line, "goal")) else {
        return Err("a path without its start and goal cells".into());
    };
    check_f64(grid, &path, start, goal).map_err(|e| describe("path", e))?;
    if let (Some(frame), Some(metres)) = (frame, waypoints(&line, "path_m")) {
        let cells: Vec<[f64; 2]> = metres?.iter().map(|p| frame.to_cells(p[0], p[1])).collect();
        let near = |p: Option<&[f64; 2]>, c: (u16, u16)| {
            p.is_some_and(|p| (p[0] - c.0 as f64).abs() < 1e-9 && (p[1] - c.1 as f64).abs() < 1e-9)
        };
        if cells.len() != path.len() || !near(cells.first(), start) || !near(cells.last(), goal) {
            return Err(describe("path_m", Invalid::Endpoints));
        }
        check_segments(grid, &cells).map_err(|e| describe("path_m", e))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_core::grid::GridBuf;

    #[test]
    fn printed_lines_are_checked_as_read_back() {
        let g = GridBuf::parse_rows(b"...\n.@.\n...\n").unwrap();
        let v = g.view();
        let ok = r#"{"start":[0,0],"goal":[2,2],"path":[[0,0],[2,0],[2,2]],"length":4}"#;
        assert_eq!(check_line(ok, v, None), Ok(()));
        let corner = r#"{"start":[0,0],"goal":[2,2],"path":[[0,0],[2,2]]}"#;
        assert!(
            check_line(corner, v, None)
                .unwrap_err()
                .contains("segment 0 of path")
        );
        let ends = r#"{"start":[0,0],"goal":[2,2],"path":[[0,0],[2,0]]}"#;
        assert!(check_line(ends, v, None).is_err());
        assert_eq!(check_line(r#"{"error":"NoValidPath"}"#, v, None), Ok(()));
        // Metres: the frame of a 3 x 3 map at 0.5 m a cell, origin (1, 1).
        let frame = MapFrame {
            resolution: 0.5,
            origin: [1.0, 1.0],
            width: 3,
            height: 3,
            declared: true,
        };
        let m = |x: f64, y: f64| frame.to_world(x, y);
        let line = serde_json::json!({"start":[0,0],"goal":[2,2],
            "path":[[0,0],[2,0],[2,2]], "path_m":[m(0.,0.), m(2.,0.), m(2.,2.)]});
        assert_eq!(check_line(&line.to_string(), v, Some(&frame)), Ok(()));
        let cut = serde_json::json!({"start":[0,0],"goal":[2,2],
            "path":[[0,0],[2,0],[2,2]], "path_m":[m(0.,0.), m(2.,2.), m(2.,2.)]});
        let e = check_line(&cut.to_string(), v, Some(&frame)).unwrap_err();
        assert!(e.contains("path_m"), "{e}");
    }
}

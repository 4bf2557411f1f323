//! The JSON-lines result format of `host-sim plan`, shared by `host-sim` and
//! `planner-client` so that both print byte-identical lines:
//!
//! ```json
//! {"start":[143,57],"goal":[10,16],"path":[[143,57],[135,43]],"length":157.0114,"time_us":410.2,"turns":2,"expanded":1955,"algo":"theta","seed":0}
//! {"start":[0,0],"goal":[1,1],"error":"StartOccupied","time_us":1.0,"algo":"theta","seed":0}
//! ```

use serde_json::{Value, json};

/// A found path as printed.
#[derive(Clone, Copy, Debug)]
pub struct PathLine<'a> {
    /// Waypoints `[x, y]` in cell units.
    pub path: &'a [[f32; 2]],
    /// Path length.
    pub length: f32,
    /// Direction changes.
    pub turns: usize,
    /// Cells expanded (A*, Theta*).
    pub expanded: Option<u32>,
    /// The optimizer's figures (swarm planners, ACO).
    pub report: Option<&'a planner_core::planner::PlanReport>,
}

/// The JSON object of one query: `result` is the path or the error's name.
pub fn plan_line(
    start: (i64, i64),
    goal: (i64, i64),
    result: Result<PathLine<'_>, &str>,
    time_us: f64,
    algo: &str,
    seed: u64,
) -> Value {
    let mut map = serde_json::Map::new();
    map.insert("start".into(), json!([start.0, start.1]));
    map.insert("goal".into(), json!([goal.0, goal.1]));
    match result {
        Ok(s) => {
            map.insert(
                "path".into(),
                Value::Array(
                    s.path
                        .iter()
                        .map(|p| json!([coord(p[0]), coord(p[1])]))
                        .collect(),
                ),
            );
            map.insert("length".into(), num(s.length));
            map.insert("time_us".into(), micros(time_us));
            map.insert("turns".into(), json!(s.turns));
            if let Some(e) = s.expanded {
                map.insert("expanded".into(), json!(e));
            }
            if let Some(r) = s.report {
                map.insert("evaluations".into(), json!(r.evaluations));
                map.insert("iterations".into(), json!(r.iterations));
                map.insert("best_iteration".into(), json!(r.best_iteration));
                map.insert("initial_cost".into(), num(r.initial_cost));
                map.insert("final_cost".into(), num(r.final_cost));
                map.insert("dimension".into(), json!(r.dimension));
                map.insert("stop".into(), json!(r.stop.name()));
            }
        }
        Err(name) => {
            map.insert("error".into(), json!(name));
            map.insert("time_us".into(), micros(time_us));
        }
    }
    map.insert("algo".into(), json!(algo));
    map.insert("seed".into(), json!(seed));
    Value::Object(map)
}

/// A coordinate as JSON: integral values print as integers (cell centres).
pub fn coord(v: f32) -> Value {
    if v.fract() == 0.0 && v.abs() < 1e9 {
        json!(v as i64)
    } else {
        num(v)
    }
}

/// An `f32` as the shortest decimal that reads back to it (not its `f64` expansion).
pub fn num(v: f32) -> Value {
    v.to_string()
        .parse::<f64>()
        .map_or(Value::Null, |x| json!(x))
}

/// Microseconds rounded to 0.1 µs.
pub fn micros(t: f64) -> Value {
    json!((t * 10.0).round() / 10.0)
}

/// One line of a queries file (`sx sy gx gy`; blank lines and `#` comments are skipped).
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum QueryLine {
    /// A well-formed query.
    Query {
        /// Start `(x, y)`.
        start: (i64, i64),
        /// Goal `(x, y)`.
        goal: (i64, i64),
    },
    /// A line that is not four integers.
    Malformed {
        /// 1-based line number.
        line: usize,
        /// What was wrong.
        detail: String,
    },
}

/// Parses a queries file in the format of `host-sim plan --queries`.
pub fn parse_queries(text: &str) -> Vec<QueryLine> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .map(|(i, l)| {
            let nums: Result<Vec<i64>, _> = l.split_whitespace().map(str::parse::<i64>).collect();
            match nums {
                Ok(n) if n.len() == 4 => QueryLine::Query {
                    start: (n[0], n[1]),
                    goal: (n[2], n[3]),
                },
                Ok(n) => QueryLine::Malformed {
                    line: i + 1,
                    detail: format!("expected 4 integers, found {}", n.len()),
                },
                Err(e) => QueryLine::Malformed {
                    line: i + 1,
                    detail: e.to_string(),
                },
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_queries_and_reports_malformed_lines() {
        let got = parse_queries("# header\n1 2 3 4\n\n1 2 x 4\n-1 0 0 99999999\n1 2 3\n");
        assert_eq!(
            got[0],
            QueryLine::Query {
                start: (1, 2),
                goal: (3, 4)
            }
        );
        assert!(matches!(got[1], QueryLine::Malformed { line: 4, .. }));
        assert_eq!(
            got[2],
            QueryLine::Query {
                start: (-1, 0),
                goal: (0, 99999999)
            }
        );
        assert!(matches!(got[3], QueryLine::Malformed { line: 6, .. }));
    }

    #[test]
    fn formats_like_host_sim() {
        let path = [[0.0, 0.0], [1.5, 2.0]];
        let ok = PathLine {
            path: &path,
            length: 2.5,
            turns: 0,
            expanded: Some(3),
            report: None,
        };
        let line = plan_line((0, 0), (1, 2), Ok(ok), 12.34, "theta", 7);
        assert_eq!(
            line.to_string(),
            r#"{"start":[0,0],"goal":[1,2],"path":[[0,0],[1.5,2]],"length":2.5,"time_us":12.3,"turns":0,"expanded":3,"algo":"theta","seed":7}"#
        );
        let err = plan_line((0, 0), (1, 2), Err("NoValidPath"), 1.0, "astar", 0);
        assert_eq!(
            err.to_string(),
            r#"{"start":[0,0],"goal":[1,2],"error":"NoValidPath","time_us":1.0,"algo":"astar","seed":0}"#
        );
    }
}

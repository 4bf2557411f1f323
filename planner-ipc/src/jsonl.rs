//! The JSON-lines result format of `host-sim plan`, shared by `host-sim` and
//! `planner-client` so that both print byte-identical lines:
//!
//! ```json
//! {"start":[143,57],"goal":[10,16],"path":[[143,57],[135,43]],"length":157.0114,"time_us":410.2,"turns":2,"expanded":1955,"algo":"theta","seed":0}
//! {"start":[0,0],"goal":[1,1],"error":"StartOccupied","time_us":1.0,"algo":"theta","seed":0}
//! ```
//!
//! On a map with a world frame (a ROS YAML) a path also comes in metres (`path_m`,
//! `length_m`); queries given in metres (`--frame world`) echo them (`start_m`, `goal_m`)
//! beside the cells they fall in. An error says more than its name when there is more to
//! say (`detail`): a point off the map, an unknown cell, a cell that only the inflation by
//! the robot radius blocks (`StartInflated`, `GoalInflated`).
//!
//! Waypoints are printed exactly: a fractional coordinate is the `f32` the planner returned,
//! written as the shortest decimal that reads back to the same binary64 value, which is that
//! `f32` exactly, so a reader that parses numbers as `f64` (or `f32`) gets the planner's
//! waypoint bit for bit and the path validates as it did in the planner. (The shortest
//! decimal that reads back to the same `f32`, printed before, is off by up to half an `f32`
//! step: read as a binary64 or exact decimal it moved a waypoint by up to 7.6e-6 cell at
//! 200 cells, enough to touch an obstacle corner that the path cleared by less.) Metres are
//! computed in `f64` from those values and printed the same way.

use planner_core::grid::GridRef;
use planner_mapfile::frame::{Frame, MapFrame, OutsideMap, metres};
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

/// A failed query as printed: the error's name and, when it helps, what exactly failed.
#[derive(Clone, Debug, PartialEq)]
pub struct ErrorLine {
    /// `PlanError` names (`StartOccupied`...), service errors, or `StartInflated`,
    /// `GoalInflated`.
    pub name: String,
    /// What exactly failed, when the name does not say it all.
    pub detail: Option<String>,
}

impl ErrorLine {
    /// An error with its name only.
    pub fn named(name: &str) -> Self {
        ErrorLine {
            name: name.into(),
            detail: None,
        }
    }
}

/// One end of a query as given: a cell, or a point in metres in the map frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Endpoint {
    /// Cell `(x, y)`, any integers (range is the planner's job).
    Cell(i64, i64),
    /// Metres in the map frame.
    World([f64; 2]),
}

impl Endpoint {
    /// The cell this end is, or the error line of a point off the map (`which` is `Start`
    /// or `Goal`).
    pub fn resolve(self, frame: &MapFrame, which: &str) -> Result<(i64, i64), ErrorLine> {
        match self {
            Endpoint::Cell(x, y) => Ok((x, y)),
            Endpoint::World([wx, wy]) => frame
                .cell_at(wx, wy)
                .map(|c| (c.x as i64, c.y as i64))
                .map_err(|e: OutsideMap| ErrorLine {
                    name: format!("{which}OutsideMap"),
                    detail: Some(format!("{} {e}", which.to_ascii_lowercase())),
                }),
        }
    }

    fn metres(self) -> Option<[f64; 2]> {
        match self {
            Endpoint::World(p) => Some(p),
            Endpoint::Cell(..) => None,
        }
    }
}

/// A query as read and, when both ends fall on the map's cells, the cells it is planned
/// between.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Query {
    /// The start as given.
    pub start: Endpoint,
    /// The goal as given.
    pub goal: Endpoint,
}

/// A query's start and goal cells `((x, y), (x, y))`, as read (range is the planner's job).
pub type CellPair = ((i64, i64), (i64, i64));

impl Query {
    /// A query between two cells.
    pub fn cells(start: (i64, i64), goal: (i64, i64)) -> Self {
        Query {
            start: Endpoint::Cell(start.0, start.1),
            goal: Endpoint::Cell(goal.0, goal.1),
        }
    }

    /// Both ends as cells, or the error line of the first one off the map.
    pub fn resolve(&self, frame: &MapFrame) -> Result<CellPair, ErrorLine> {
        Ok((
            self.start.resolve(frame, "Start")?,
            self.goal.resolve(frame, "Goal")?,
        ))
    }
}

/// How a line is labelled: the planner's name, the seed, and the map's world frame when it
/// declares one (paths then also print in metres).
#[derive(Clone, Copy, Debug)]
pub struct LineContext<'a> {
    /// Planner name.
    pub algo: &'a str,
    /// Seed.
    pub seed: u64,
    /// The map's declared world frame, if any.
    pub frame: Option<&'a MapFrame>,
}

/// The JSON object of one query: `cells` are the resolved ends (absent when one is off the
/// map), `result` the path or the error.
pub fn plan_line(
    query: &Query,
    cells: Option<CellPair>,
    result: Result<PathLine<'_>, ErrorLine>,
    time_us: f64,
    ctx: &LineContext<'_>,
) -> Value {
    let mut map = serde_json::Map::new();
    if let Some((start, goal)) = cells {
        map.insert("start".into(), json!([start.0, start.1]));
        map.insert("goal".into(), json!([goal.0, goal.1]));
    }
    if let Some(p) = query.start.metres() {
        map.insert("start_m".into(), json!(p));
    }
    if let Some(p) = query.goal.metres() {
        map.insert("goal_m".into(), json!(p));
    }
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
            if let Some(frame) = ctx.frame {
                map.insert("path_m".into(), path_metres(frame, s.path));
            }
            map.insert("length".into(), num(s.length));
            if let Some(frame) = ctx.frame {
                let m = s.length as f64 * frame.resolution;
                map.insert("length_m".into(), json!((m * 1e6).round() / 1e6));
            }
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
        Err(e) => {
            map.insert("error".into(), json!(e.name));
            if let Some(d) = e.detail {
                map.insert("detail".into(), json!(d));
            }
            map.insert("time_us".into(), micros(time_us));
        }
    }
    map.insert("algo".into(), json!(ctx.algo));
    map.insert("seed".into(), json!(ctx.seed));
    Value::Object(map)
}

/// A path's waypoints in metres in `frame`, computed in `f64` from the exact `f32` cells.
pub fn path_metres(frame: &MapFrame, path: &[[f32; 2]]) -> Value {
    Value::Array(
        path.iter()
            .map(|p| json!(frame.to_world(p[0] as f64, p[1] as f64)))
            .collect(),
    )
}

/// A waypoint coordinate as JSON, exactly: integral values print as integers (cell
/// centres), others as the shortest decimal of the `f32`'s binary64 value (see the module
/// documentation).
pub fn coord(v: f32) -> Value {
    if v.fract() == 0.0 && v.abs() < 1e9 {
        json!(v as i64)
    } else if v.is_finite() {
        json!(v as f64)
    } else {
        Value::Null
    }
}

/// An `f32` figure (a length, a cost) as the shortest decimal that reads back to it as an
/// `f32` (not its `f64` expansion): figures are read, waypoints are computed with.
pub fn num(v: f32) -> Value {
    v.to_string()
        .parse::<f64>()
        .map_or(Value::Null, |x| json!(x))
}

/// Microseconds rounded to 0.1 µs.
pub fn micros(t: f64) -> Value {
    json!((t * 10.0).round() / 10.0)
}

/// What an endpoint error means on this map: a blocked start or goal that is free on the
/// map (`raw`) was blocked by the inflation by the robot radius (`radius` says how much,
/// e.g. `0.25 m (4.5 cells)`); one in unknown space says so. Other errors pass unchanged.
pub fn explain(
    error: ErrorLine,
    raw: GridRef<'_>,
    unknown: Option<GridRef<'_>>,
    cells: CellPair,
    radius: Option<&str>,
) -> ErrorLine {
    let (which, (x, y)) = match error.name.as_str() {
        "StartOccupied" => ("Start", cells.0),
        "GoalOccupied" => ("Goal", cells.1),
        _ => return error,
    };
    let lower = which.to_ascii_lowercase();
    let (xi, yi) = (x as isize, y as isize);
    if unknown.is_some_and(|u| u.contains(xi, yi) && u.is_blocked(xi, yi)) && raw.is_blocked(xi, yi)
    {
        return ErrorLine {
            name: error.name,
            detail: Some(format!(
                "{lower} cell ({x}, {y}) is unknown space, blocked (--unknown free plans through it)"
            )),
        };
    }
    match radius {
        Some(r) if raw.contains(xi, yi) && !raw.is_blocked(xi, yi) => ErrorLine {
            name: format!("{which}Inflated"),
            detail: Some(format!(
                "{lower} cell ({x}, {y}) is free on the map but within the robot radius \
                 {r} of an obstacle: the inflated map blocks it"
            )),
        },
        _ => error,
    }
}

/// The robot radius planned for on a map with a world frame when none is given (m): a
/// typical warehouse AMR.
pub const DEFAULT_ROBOT_RADIUS_M: f64 = 0.25;

/// How much a query's map is inflated, the one rule of `host-sim plan`, `run` and
/// `planner-client`.
#[derive(Clone, Debug, PartialEq)]
pub struct Inflation {
    /// The radius of `GridBuf::inflated` (cells; 0 = none).
    pub cells: f64,
    /// How messages name it (`0.25 m (4.5 cells)`, `of 2 cells`); `None` without inflation.
    pub text: Option<String>,
}

/// The inflation of `--radius` (cells) or `--robot-radius` (metres, which needs the map's
/// declared world frame), or, with neither, [`DEFAULT_ROBOT_RADIUS_M`] on a map with a world
/// frame and none on a map in cells. `--robot-radius 0` plans for a point. The error says
/// which value is wrong (the caller names the map).
pub fn inflation(
    radius: Option<f32>,
    robot_radius: Option<f64>,
    frame: &MapFrame,
) -> Result<Inflation, String> {
    let of_metres = |m: f64| {
        let cells = frame.inflation_cells(m);
        Inflation {
            cells,
            text: (cells > 0.0).then(|| radius_text(m, cells)),
        }
    };
    match (radius, robot_radius) {
        (Some(r), _) if !(r.is_finite() && r >= 0.0) => {
            Err(format!("--radius {r}: must be a finite number >= 0"))
        }
        (Some(r), _) => Ok(Inflation {
            cells: r as f64,
            text: (r > 0.0).then(|| format!("of {} cells", metres(r as f64))),
        }),
        (None, Some(m)) if !(m.is_finite() && m >= 0.0) => Err(format!(
            "--robot-radius {m}: must be a finite number of metres >= 0"
        )),
        (None, Some(_)) if !frame.declared => Err(
            "a map in cells (no world frame); --robot-radius needs a ROS map YAML with a \
             resolution and an origin (--radius takes cells)"
                .into(),
        ),
        (None, Some(m)) => Ok(of_metres(m)),
        (None, None) if frame.declared => Ok(of_metres(DEFAULT_ROBOT_RADIUS_M)),
        (None, None) => Ok(Inflation {
            cells: 0.0,
            text: None,
        }),
    }
}

/// A length in metres with the cells it is, for messages: `0.25 m (5 cells)`.
pub fn radius_text(radius_m: f64, cells: f64) -> String {
    format!("{} m ({} cells)", metres(radius_m), metres(cells))
}

/// One line of a queries file (`sx sy gx gy`; blank lines and `#` comments are skipped).
#[derive(Clone, Debug, PartialEq)]
pub enum QueryLine {
    /// A well-formed query.
    Query(Query),
    /// A line that is not a query in the frame asked for.
    Malformed {
        /// 1-based line number.
        line: usize,
        /// What was wrong.
        detail: String,
    },
}

/// Parses a queries file in the format of `host-sim plan --queries`: four integers (cells)
/// a line, or four decimals (metres) in the world frame.
pub fn parse_queries(text: &str, frame: Frame) -> Vec<QueryLine> {
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .map(|(i, l)| {
            let malformed = |detail: String| QueryLine::Malformed {
                line: i + 1,
                detail,
            };
            let words: Vec<&str> = l.split_whitespace().collect();
            if words.len() != 4 {
                let unit = match frame {
                    Frame::Cells => "integers (cells)",
                    Frame::World => "numbers (metres)",
                };
                return malformed(format!("expected 4 {unit}, found {}", words.len()));
            }
            match frame {
                Frame::Cells => {
                    let nums: Result<Vec<i64>, _> = words.iter().map(|w| w.parse()).collect();
                    match nums {
                        Ok(n) => QueryLine::Query(Query::cells((n[0], n[1]), (n[2], n[3]))),
                        Err(e) => malformed(format!(
                            "{e} (cells are integers; --frame world takes metres)"
                        )),
                    }
                }
                Frame::World => {
                    let nums: Result<Vec<f64>, String> = words
                        .iter()
                        .map(|w| match w.parse::<f64>() {
                            Ok(v) if v.is_finite() => Ok(v),
                            Ok(_) => Err(format!("{w:?}: not a finite number")),
                            Err(e) => Err(format!("{w:?}: {e}")),
                        })
                        .collect();
                    match nums {
                        Ok(n) => QueryLine::Query(Query {
                            start: Endpoint::World([n[0], n[1]]),
                            goal: Endpoint::World([n[2], n[3]]),
                        }),
                        Err(e) => malformed(e),
                    }
                }
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use planner_core::grid::GridBuf;

    fn ctx(algo: &str, seed: u64) -> LineContext<'_> {
        LineContext {
            algo,
            seed,
            frame: None,
        }
    }

    #[test]
    fn parses_queries_and_reports_malformed_lines() {
        let got = parse_queries(
            "# header\n1 2 3 4\n\n1 2 x 4\n-1 0 0 99999999\n1 2 3\n1.5 2 3 4\n",
            Frame::Cells,
        );
        assert_eq!(got[0], QueryLine::Query(Query::cells((1, 2), (3, 4))));
        assert!(matches!(got[1], QueryLine::Malformed { line: 4, .. }));
        assert_eq!(
            got[2],
            QueryLine::Query(Query::cells((-1, 0), (0, 99999999)))
        );
        assert!(matches!(got[3], QueryLine::Malformed { line: 6, .. }));
        assert!(
            matches!(&got[4], QueryLine::Malformed { line: 7, detail } if detail.contains("--frame world"))
        );
        let world = parse_queries("-1.5 2 3e-1 4\n1 2 nan 4\n", Frame::World);
        assert_eq!(
            world[0],
            QueryLine::Query(Query {
                start: Endpoint::World([-1.5, 2.0]),
                goal: Endpoint::World([0.3, 4.0]),
            })
        );
        assert!(matches!(world[1], QueryLine::Malformed { line: 2, .. }));
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
        let q = Query::cells((0, 0), (1, 2));
        let cells = Some(((0, 0), (1, 2)));
        let line = plan_line(&q, cells, Ok(ok), 12.34, &ctx("theta", 7));
        assert_eq!(
            line.to_string(),
            r#"{"start":[0,0],"goal":[1,2],"path":[[0,0],[1.5,2]],"length":2.5,"time_us":12.3,"turns":0,"expanded":3,"algo":"theta","seed":7}"#
        );
        let err = plan_line(
            &q,
            cells,
            Err(ErrorLine::named("NoValidPath")),
            1.0,
            &ctx("astar", 0),
        );
        assert_eq!(
            err.to_string(),
            r#"{"start":[0,0],"goal":[1,2],"error":"NoValidPath","time_us":1.0,"algo":"astar","seed":0}"#
        );
    }

    /// The issue's IGWO waypoint: the shortest decimal of the f32 (196.50002) is not the
    /// f32; what is printed now reads back, as f64 and as f32, to the f32 itself.
    #[test]
    fn waypoints_read_back_bit_for_bit() {
        let v = 196.50002f32;
        assert_ne!(v.to_string().parse::<f64>().unwrap(), v as f64);
        for v in [v, 185.50189, 0.1, 1e-30, 4095.9995, -0.4999, 7.0e-6, 3.0] {
            let text = coord(v).to_string();
            assert_eq!(text.parse::<f64>().unwrap(), v as f64, "{v} -> {text}");
            assert_eq!(text.parse::<f32>().unwrap(), v, "{v} -> {text}");
        }
        assert_eq!(coord(3.0).to_string(), "3");
        assert_eq!(coord(f32::NAN), Value::Null);
    }

    #[test]
    fn world_frame_adds_metres_and_points_off_the_map_are_errors() {
        let frame = MapFrame {
            resolution: 0.05,
            origin: [-10.0, -10.0],
            width: 4,
            height: 3,
            declared: true,
        };
        let path = [[0.0, 2.0], [3.0, 0.0]];
        let ok = PathLine {
            path: &path,
            length: 3.6055512,
            turns: 0,
            expanded: None,
            report: None,
        };
        let q = Query {
            start: Endpoint::World([-9.975, -9.975]),
            goal: Endpoint::World([-9.82, -9.86]),
        };
        let cells = q.resolve(&frame).unwrap();
        assert_eq!(cells, ((0, 2), (3, 0)));
        let c = LineContext {
            frame: Some(&frame),
            ..ctx("theta", 0)
        };
        let line = plan_line(&q, Some(cells), Ok(ok), 1.0, &c);
        assert_eq!(line["start_m"], json!([-9.975, -9.975]));
        assert_eq!(line["path_m"][0], json!(frame.to_world(0.0, 2.0)));
        assert_eq!(line["path_m"][1], json!(frame.to_world(3.0, 0.0)));
        assert_eq!(line["length_m"], json!(0.180278));
        let off = Query {
            goal: Endpoint::World([0.0, 0.0]),
            ..q
        };
        let e = off.resolve(&frame).unwrap_err();
        assert_eq!(e.name, "GoalOutsideMap");
        assert!(
            e.detail
                .as_deref()
                .unwrap()
                .starts_with("goal (0, 0) m is outside")
        );
        let line = plan_line(&off, None, Err(e), 0.0, &c);
        assert!(line.get("start").is_none() && line["goal_m"] == json!([0.0, 0.0]));
    }

    #[test]
    fn explain_tells_inflation_and_unknown_space_apart() {
        let raw = GridBuf::parse_rows(b"@..\n...\n").unwrap();
        let mut unknown = GridBuf::new(3, 2).unwrap();
        unknown.set_blocked(0, 0, true).unwrap();
        let cells = ((1, 0), (0, 0));
        let r = Some("0.25 m (4.5 cells)");
        let e = explain(
            ErrorLine::named("StartOccupied"),
            raw.view(),
            None,
            cells,
            r,
        );
        assert_eq!(e.name, "StartInflated");
        assert!(
            e.detail.unwrap().contains(
                "(1, 0) is free on the map but within the robot radius 0.25 m (4.5 cells)"
            )
        );
        let e = explain(
            ErrorLine::named("StartOccupied"),
            raw.view(),
            None,
            cells,
            None,
        );
        assert_eq!(e, ErrorLine::named("StartOccupied"));
        let e = explain(ErrorLine::named("GoalOccupied"), raw.view(), None, cells, r);
        assert_eq!(e, ErrorLine::named("GoalOccupied"));
        let e = explain(
            ErrorLine::named("GoalOccupied"),
            raw.view(),
            Some(unknown.view()),
            cells,
            r,
        );
        assert_eq!(e.name, "GoalOccupied");
        assert!(e.detail.unwrap().contains("unknown space"));
        let e = explain(ErrorLine::named("NoValidPath"), raw.view(), None, cells, r);
        assert_eq!(e, ErrorLine::named("NoValidPath"));
    }
}

//! Where a mission takes place: the map the robot collides with, the map inflated by its
//! radius that the global planner plans on, the unknown space and the world frame; and
//! starts and goals checked against them (each failure its own named error) or drawn at
//! random within one connected region of the inflated map.

use planner_core::geometry::{Cell, point_clearance};
use planner_core::grid::{GridBuf, GridRef};
use planner_core::search::connectivity::{self, BLOCKED};
use planner_ipc::jsonl::{self, ErrorLine};
use planner_mapfile::MapFrame;
use rand_core::Rng;
use rand_xoshiro::Xoshiro256PlusPlus;

/// A map prepared for a robot.
pub struct Site {
    /// The map: occupied (and unknown, unless free by `--unknown`) cells blocked.
    pub grid: GridBuf,
    /// `grid` inflated by the robot's radius (`None`: no inflation).
    pub inflated: Option<GridBuf>,
    /// Unknown space, where the map has any.
    pub unknown: Option<GridBuf>,
    /// The world frame (assumed 1 m a cell when the map declares none).
    pub frame: MapFrame,
    /// How the inflation is named in messages (`0.25 m (4.5 cells)`).
    pub radius_text: Option<String>,
}

/// A start or goal that cannot be used: a [`planner_core::PlanError`] name (or
/// `StartInflated`, `GoalInflated`) with what exactly is wrong.
#[derive(Clone, Debug, PartialEq)]
pub struct BadEndpoint(pub ErrorLine);

impl std::fmt::Display for BadEndpoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match &self.0.detail {
            Some(detail) => write!(f, "{}: {detail}", self.0.name),
            None => f.write_str(&self.0.name),
        }
    }
}

impl std::error::Error for BadEndpoint {}

impl Site {
    /// What the planner plans on.
    pub fn plan_grid(&self) -> GridRef<'_> {
        self.inflated.as_ref().unwrap_or(&self.grid).view()
    }

    /// `cell` as the mission's start (`which` = `Start`) or goal (`Goal`): on the map, free
    /// on it, and free after the inflation.
    pub fn check(&self, which: &str, (x, y): (i64, i64)) -> Result<Cell, BadEndpoint> {
        let raw = self.grid.view();
        let lower = which.to_ascii_lowercase();
        let on_map = (0..raw.width() as i64).contains(&x) && (0..raw.height() as i64).contains(&y);
        if !on_map {
            return Err(BadEndpoint(ErrorLine {
                name: format!("{which}OutsideMap"),
                detail: Some(format!(
                    "{lower} cell ({x}, {y}) is outside the map ({} x {} cells)",
                    raw.width(),
                    raw.height()
                )),
            }));
        }
        let cell = Cell::new(x as u16, y as u16);
        let occupied = format!("{which}Occupied");
        let explain = |error: ErrorLine| {
            jsonl::explain(
                error,
                raw,
                self.unknown.as_ref().map(GridBuf::view),
                ((x, y), (x, y)),
                self.radius_text.as_deref(),
            )
        };
        if raw.is_blocked(x as isize, y as isize) {
            let named = explain(ErrorLine::named(&occupied));
            return Err(BadEndpoint(ErrorLine {
                detail: named
                    .detail
                    .or_else(|| Some(format!("{lower} cell ({x}, {y}) is occupied on the map"))),
                ..named
            }));
        }
        if self.plan_grid().is_blocked(x as isize, y as isize) {
            return Err(BadEndpoint(explain(ErrorLine::named(&occupied))));
        }
        Ok(cell)
    }

    /// A start and a goal at least `min_gap` cells apart, free on the inflated map and in its
    /// largest connected region, clear of obstacles by `keep` cells where such cells are
    /// found; `stations` (when not empty) are drawn half of the time.
    pub fn random_pair(
        &self,
        rng: &mut Xoshiro256PlusPlus,
        stations: &[Cell],
        min_gap: f32,
        keep: f32,
    ) -> Option<(Cell, Cell)> {
        let grid = self.plan_grid();
        let mut labels = vec![0u32; grid.cells()];
        connectivity::label(grid, &mut labels).ok()?;
        let largest = largest_label(&labels)?;
        let members: Vec<Cell> = stations
            .iter()
            .copied()
            .filter(|c| grid.index(*c).is_some_and(|i| labels[i] == largest))
            .collect();
        let draw = |rng: &mut Xoshiro256PlusPlus| -> Option<Cell> {
            if !members.is_empty() && rng.next_u32().is_multiple_of(2) {
                return Some(members[(rng.next_u64() % members.len() as u64) as usize]);
            }
            let mut any = None;
            (0..10_000)
                .find_map(|_| {
                    let i = (rng.next_u64() % labels.len() as u64) as usize;
                    if labels[i] != largest {
                        return None;
                    }
                    let cell = grid.cell(i);
                    any = any.or(Some(cell));
                    (point_clearance(grid, cell.center(), keep) >= keep).then_some(cell)
                })
                .or(any)
        };
        (0..1000).find_map(|_| {
            let (a, b) = (draw(rng)?, draw(rng)?);
            (a.center().distance(b.center()) >= min_gap).then_some((a, b))
        })
    }
}

/// The label of the most cells (not [`BLOCKED`]).
fn largest_label(labels: &[u32]) -> Option<u32> {
    let mut count = std::collections::HashMap::<u32, usize>::new();
    for &l in labels.iter().filter(|&&l| l != BLOCKED) {
        *count.entry(l).or_default() += 1;
    }
    count
        .into_iter()
        .max_by_key(|&(l, n)| (n, l))
        .map(|(l, _)| l)
}

#[cfg(test)]
mod tests {
    use super::*;
    use rand_core::SeedableRng;

    /// A 6 x 5 room with a pillar at (4, 2) and, walled off on the right, two pockets.
    fn site(radius: Option<f32>) -> Site {
        let rows = b"......@...\n......@...\n....@.@@@@\n......@...\n......@...\n";
        let grid = GridBuf::parse_rows(rows).unwrap();
        let inflated = radius.map(|r| grid.inflated(r).unwrap());
        Site {
            frame: MapFrame::assumed(grid.width(), grid.height()),
            grid,
            inflated,
            unknown: None,
            radius_text: radius.map(|r| format!("{r} cells")),
        }
    }

    #[test]
    fn each_bad_end_has_its_name() {
        let s = site(Some(0.5));
        // Off the map counts as blocked for the inflation: (0, 0) is blocked, (1, 1) free.
        assert_eq!(s.check("Start", (1, 1)), Ok(Cell::new(1, 1)));
        assert_eq!(
            s.check("Start", (0, 0)).unwrap_err().0.name,
            "StartInflated"
        );
        let e = s.check("Start", (10, 0)).unwrap_err();
        assert_eq!(e.0.name, "StartOutsideMap");
        assert_eq!(
            e.to_string(),
            "StartOutsideMap: start cell (10, 0) is outside the map (10 x 5 cells)"
        );
        let e = s.check("Goal", (4, 2)).unwrap_err();
        assert_eq!(
            e.to_string(),
            "GoalOccupied: goal cell (4, 2) is occupied on the map"
        );
        let e = s.check("Goal", (3, 2)).unwrap_err();
        assert_eq!(e.0.name, "GoalInflated");
        assert!(e.to_string().contains("0.5 cells"), "{e}");
        assert_eq!(site(None).check("Goal", (3, 2)), Ok(Cell::new(3, 2)));
    }

    #[test]
    fn random_missions_stay_in_the_largest_region() {
        let s = site(None);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(3);
        for _ in 0..50 {
            let (a, b) = s
                .random_pair(&mut rng, &[Cell::new(8, 0)], 2.0, 0.0)
                .unwrap();
            assert!(a.x < 6 && b.x < 6, "{a:?} {b:?}");
            assert!(a.center().distance(b.center()) >= 2.0);
        }
    }

    /// Random ends keep the asked clearance where the region has cells that do.
    #[test]
    fn random_ends_keep_the_margin() {
        let s = site(None);
        let mut rng = Xoshiro256PlusPlus::seed_from_u64(5);
        for _ in 0..50 {
            let (a, b) = s.random_pair(&mut rng, &[], 1.0, 1.0).unwrap();
            for c in [a, b] {
                let clear = point_clearance(s.plan_grid(), c.center(), 1.0);
                assert!(clear >= 1.0, "{c:?}: {clear}");
            }
        }
    }
}

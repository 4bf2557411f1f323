//! Inflation, A*, Theta* and connectivity on an arbitrary small map: A* succeeds exactly
//! when the labels say the endpoints are connected, Theta* agrees, both paths are valid,
//! and inflation only ever adds obstacles.
#![no_main]

mod common;

use arbitrary::Arbitrary;
use common::{EndpointInput, FloatInput, MapInput, SmallGrid};
use libfuzzer_sys::fuzz_target;
use planner_core::error::PlanError;
use planner_core::path::{self, Path};
use planner_core::search::astar::{AStarNode, OpenSlot};
use planner_core::search::{SearchNode, astar, check_endpoints, connectivity, theta};

#[derive(Arbitrary, Debug)]
struct Input {
    map: MapInput,
    radius: FloatInput,
    start: EndpointInput,
    goal: EndpointInput,
    use_labels: bool,
}

fuzz_target!(|input: Input| {
    let base = input.map.build();
    let radius = input.radius.get();
    let mut grid = SmallGrid::new(1, 1).unwrap();
    match base.inflate_into(radius, &mut grid) {
        Ok(()) => {
            assert_eq!((grid.width(), grid.height()), (base.width(), base.height()));
            let (b, g) = (base.view(), grid.view());
            for y in 0..base.height() as isize {
                for x in 0..base.width() as isize {
                    assert!(!b.is_blocked(x, y) || g.is_blocked(x, y), "inflation freed a cell");
                }
            }
            if radius == 0.0 {
                assert_eq!(grid, base);
            }
        }
        Err(_) => {
            assert!(!radius.is_finite() || radius < 0.0, "inflate_into rejected {radius}");
            grid = base.clone();
        }
    }
    let view = grid.view();
    let start = input.start.cell(grid.width(), grid.height());
    let goal = input.goal.cell(grid.width(), grid.height());
    let mut labels = [0u32; 576];
    connectivity::label(view, &mut labels).expect("labels fit");
    let mut nodes = [SearchNode::EMPTY; 576];
    let mut astar_nodes = [AStarNode::EMPTY; 576];
    let mut open = [OpenSlot::EMPTY; 576];
    let mut out: Path<600> = Path::new();
    let labels_opt = if input.use_labels { Some(&labels[..]) } else { None };
    let a = astar::plan_with_labels(view, start, goal, labels_opt, &mut astar_nodes, &mut open, &mut out);
    let endpoint = check_endpoints(view, start, goal);
    let connected = connectivity::connected(view, &labels, start, goal);
    match endpoint {
        Err(e) => {
            assert_eq!(a.err(), Some(e));
            assert_eq!(connected, Err(e));
            return;
        }
        Ok(()) => {}
    }
    let connected = connected.expect("endpoints checked");
    match a {
        Ok(stats) => {
            assert!(connected, "A* found a path between unconnected cells");
            assert_eq!(path::validate(view, &out, start, goal), Ok(()));
            // A* emits every cell centre: king moves only.
            assert!(out.windows(2).all(|w| {
                let (dx, dy) = ((w[1].x - w[0].x).abs(), (w[1].y - w[0].y).abs());
                dx <= 1.0 && dy <= 1.0 && dx + dy > 0.0
            }));
            assert!((stats.length - path::length(&out)).abs() <= 1e-3 * (1.0 + stats.length));
            let astar_len = stats.length;
            let t = theta::plan_with_labels(view, start, goal, labels_opt, &mut nodes, &mut out)
                .expect("Theta* finds a path where A* did");
            assert_eq!(path::validate(view, &out, start, goal), Ok(()));
            // Any-angle paths are never longer than the 8-connected optimum.
            assert!(t.length <= astar_len + 1e-3 * (1.0 + astar_len), "{} > {astar_len}", t.length);
        }
        Err(PlanError::NoValidPath) => {
            assert!(!connected, "A* found no path between connected cells");
            let t = theta::plan_with_labels(view, start, goal, labels_opt, &mut nodes, &mut out);
            assert_eq!(t.err(), Some(PlanError::NoValidPath));
        }
        Err(e) => panic!("unexpected A* error {e:?}"),
    }
    // Nodes are left reusable: a second run gives the same answer.
    let again = astar::plan(view, start, goal, &mut astar_nodes, &mut open, &mut out);
    assert_eq!(again.is_ok(), connected);
});

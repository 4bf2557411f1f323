//! The exact any-angle planner on an arbitrary small map with storage of arbitrary (maybe
//! too small) size: never a panic; a path exactly when the endpoints are connected, valid
//! and, when the search kept every node it needed (`exact`), never longer than Theta*'s;
//! `CapacityExceeded` only when a buffer was short.
#![no_main]

mod common;

use arbitrary::Arbitrary;
use common::{EndpointInput, MapInput};
use libfuzzer_sys::fuzz_target;
use planner_core::error::PlanError;
use planner_core::path::{self, Path};
use planner_core::search::anyangle::{self, Link, Mesh, Node, Rect, Roots, Scratch};
use planner_core::search::{SearchNode, check_endpoints, connectivity, theta};

#[derive(Arbitrary, Debug)]
struct Input {
    map: MapInput,
    start: EndpointInput,
    goal: EndpointInput,
    /// Storage sizes: 0 means "what the map needs", other values are taken as given.
    rects: u16,
    links: u16,
    open: u16,
    short_out: bool,
}

fuzz_target!(|input: Input| {
    let grid = input.map.build();
    let view = grid.view();
    let start = input.start.cell(grid.width(), grid.height());
    let goal = input.goal.cell(grid.width(), grid.height());
    let (need_rects, need_links) = Mesh::count(view);
    assert!(need_rects <= anyangle::rects_for(grid.width(), grid.height()));
    assert!(need_links <= anyangle::links_for(grid.width(), grid.height()));
    let size = |given: u16, need: usize| if given == 0 { need } else { given as usize % 700 };
    let mut rects = vec![Rect::EMPTY; size(input.rects, need_rects)];
    let mut links = vec![Link::EMPTY; size(input.links, need_links)];
    let short_mesh = rects.len() < need_rects || links.len() < need_links;
    let mesh = match Mesh::build(view, &mut rects, &mut links) {
        Ok(mesh) => {
            assert!(!short_mesh, "built in too little room");
            mesh
        }
        Err(e) => {
            assert_eq!(e, PlanError::CapacityExceeded);
            assert!(short_mesh, "refused with room enough");
            return;
        }
    };
    let mut roots = vec![Roots::EMPTY; mesh.rects()];
    let mut open = vec![Node::EMPTY; size(input.open, 4096)];
    // Sometimes a path buffer too short for most paths.
    let mut long: Path<600> = Path::new();
    let mut short: Path<4> = Path::new();
    let out: &mut path::PathView = if input.short_out { &mut short } else { &mut long };
    let scratch = Scratch { roots: &mut roots, open: &mut open };
    let result = anyangle::plan(view, &mesh, start, goal, scratch, out);
    let mut labels = [0u32; 576];
    connectivity::label(view, &mut labels).expect("labels fit");
    if let Err(e) = check_endpoints(view, start, goal) {
        assert_eq!(result.err(), Some(e));
        return;
    }
    let connected = connectivity::connected(view, &labels, start, goal).expect("endpoints checked");
    match result {
        Ok(stats) => {
            assert!(connected, "a path between unconnected cells");
            assert_eq!(path::validate(view, out, start, goal), Ok(()));
            let mut nodes = [SearchNode::EMPTY; 576];
            let mut theta_path: Path<600> = Path::new();
            let t = theta::plan(view, start, goal, &mut nodes, &mut theta_path).expect("connected");
            if stats.exact {
                assert!(stats.optimum <= t.length + 1e-4, "{} > {}", stats.optimum, t.length);
                assert!(stats.length <= t.length + 2e-3, "{} > {}", stats.length, t.length);
            } else {
                // Only an open list too short to keep every node can cost exactness.
                assert!(input.open != 0, "inexact with an open list of 4096");
            }
        }
        Err(PlanError::NoValidPath) => assert!(!connected, "no path between connected cells"),
        Err(PlanError::CapacityExceeded) => {
            assert!(input.open != 0 || input.short_out, "open list of 4096 outgrown")
        }
        Err(e) => panic!("unexpected error {e:?}"),
    }
});

//! The `polyanya` crate (vleue/polyanya, Polyanya on navigation meshes, `f32`) on the same
//! rectangles as `anyangle`, for `bench scale` (cargo feature `polyanya`). The crate's mesh
//! is built from ours: its vertices are the rectangles' corners and the points where a
//! neighbour's edge ends on theirs, each with the rectangles around it in counter-clockwise
//! order (`y` flipped up), and its polygons the rectangles with those points on their
//! edges. Building it (our cut, the conversion, the crate's baking) is the one-time cost.

use super::scale::Run;
use planner_core::geometry::{Cell, Point};
use planner_core::grid::GridBuf;
use planner_core::path;
use planner_core::search::anyangle::MeshBuf;
use std::collections::HashMap;
use std::time::Instant;

/// Runs every query; returns the build time (ms) and the runs.
pub(super) fn run(grid: &GridBuf, queries: &[(Cell, Cell)]) -> anyhow::Result<(f64, Vec<Run>)> {
    let began = Instant::now();
    let mesh = to_polyanya(grid)?;
    let build_ms = began.elapsed().as_secs_f64() * 1e3;
    let h = grid.height() as f32;
    // Cell centres in the crate's frame: corners on integers, y up.
    let at = |c: Cell| glam::Vec2::new(c.x as f32 + 0.5, h - c.y as f32 - 0.5);
    let back = |p: glam::Vec2| Point::new(p.x - 0.5, h - p.y - 0.5);
    let mut runs = Vec::new();
    for &(s, g) in queries {
        let began = Instant::now();
        let found = mesh.path(at(s), at(g));
        let ms = began.elapsed().as_secs_f64() * 1e3;
        let run = match found {
            Some(p) => {
                let mut points = vec![s.center()];
                points.extend(p.path.iter().map(|&v| back(v)));
                Run {
                    ms,
                    length: Some(p.length as f64),
                    valid: path::validate(grid.view(), &points, s, g).is_ok(),
                }
            }
            None => Run {
                ms,
                length: None,
                valid: false,
            },
        };
        runs.push(run);
    }
    Ok((build_ms, runs))
}

fn to_polyanya(grid: &GridBuf) -> anyhow::Result<polyanya::Mesh> {
    let ours = MeshBuf::build(grid.view()).map_err(anyhow::Error::msg)?;
    let mesh = ours.mesh();
    let (w, h) = (grid.width(), grid.height());
    let n = mesh.rects() as u32;
    let mut index: HashMap<(usize, usize), u32> = HashMap::new();
    let mut points: Vec<(usize, usize)> = Vec::new();
    let mut id = |p: (usize, usize)| -> u32 {
        *index.entry(p).or_insert_with(|| {
            points.push(p);
            (points.len() - 1) as u32
        })
    };
    let ends = |rects: &mut dyn Iterator<Item = u32>, x0: usize, x1: usize| {
        let mut xs: Vec<usize> = rects
            .flat_map(|r| {
                let (a, _, b, _) = mesh.bounds(r);
                [a, b]
            })
            .filter(|&x| x > x0 && x < x1)
            .collect();
        xs.sort_unstable();
        xs.dedup();
        xs
    };
    let mut polygons = Vec::with_capacity(n as usize);
    for r in 0..n {
        let (x0, y0, x1, y1) = mesh.bounds(r);
        // Counter-clockwise with y up: the bottom edge (grid row y1) left to right, then the
        // top edge (grid row y0) right to left.
        let mut list = vec![id((x0, y1))];
        list.extend(
            ends(&mut mesh.below(r), x0, x1)
                .into_iter()
                .map(|x| id((x, y1))),
        );
        list.push(id((x1, y1)));
        list.push(id((x1, y0)));
        list.extend(
            ends(&mut mesh.above(r), x0, x1)
                .into_iter()
                .rev()
                .map(|x| id((x, y0))),
        );
        list.push(id((x0, y0)));
        let one_way = mesh.below(r).count() + mesh.above(r).count() == 1;
        polygons.push(polyanya::Polygon::new(list, one_way));
    }
    // The rectangle of every cell, to list the polygons around each vertex.
    let mut owner = vec![u32::MAX; w * h];
    for r in 0..n {
        let (x0, y0, x1, y1) = mesh.bounds(r);
        for y in y0..y1 {
            owner[y * w + x0..y * w + x1].fill(r);
        }
    }
    let cell = |x: isize, y: isize| {
        if x < 0 || y < 0 || x as usize >= w || y as usize >= h {
            u32::MAX
        } else {
            owner[y as usize * w + x as usize]
        }
    };
    let vertices = points
        .iter()
        .map(|&(x, y)| {
            let (x, y) = (x as isize, y as isize);
            // Counter-clockwise (y up) from east: the cells above-right, above-left,
            // below-left, below-right of the point (rows grow downwards in the grid).
            let around = [
                cell(x, y - 1),
                cell(x - 1, y - 1),
                cell(x - 1, y),
                cell(x, y),
            ];
            let mut list: Vec<u32> = Vec::new();
            for p in around {
                if list.last() != Some(&p) {
                    list.push(p);
                }
            }
            while list.len() > 1 && list.first() == list.last() {
                list.pop();
            }
            polyanya::Vertex::new(glam::Vec2::new(x as f32, (h as isize - y) as f32), list)
        })
        .collect();
    let mut out = polyanya::Mesh::new(vertices, polygons)
        .map_err(|e| anyhow::anyhow!("polyanya mesh: {e:?}"))?;
    out.bake();
    Ok(out)
}

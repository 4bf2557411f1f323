//! `host-sim render-demo` (hidden): writes example pictures, to look at the renderer.
//!
//! ```text
//! host-sim render-demo [--map FILE.map|FILE.yaml] [--start X,Y] [--goal X,Y] [--out DIR] [--max-cells N]
//! ```
//! Writes into `DIR` (default `target/render-demo`): `warehouse.{png,svg}` (real A* and Theta*
//! paths on the map), `small.{png,svg}` (a 10 x 10 map with a path, a marker and a disc),
//! `field.{png,svg}` (a synthetic height field with a
//! blocked block) and `convergence.{png,svg}` (two made-up
//! decreasing series, titled as such).

use crate::render::{
    Disc, FieldPicture, Layer, MapPicture, Marker, Series, Shape, Style, convergence_plot,
};
use anyhow::Context;
use planner_core::geometry::{Cell, Point};
use planner_core::grid::{GridBuf, GridRef};
use planner_core::path::{Path, PathView};
use planner_core::search::astar::{AStarNode, OpenSlot, open_capacity};
use planner_core::search::{SearchNode, astar, theta};
use planner_mapfile::{MapOptions, load_map};
use std::path::PathBuf;

/// Arguments of `host-sim render-demo`.
#[derive(clap::Args, Debug)]
pub struct RenderDemoArgs {
    /// Moving AI `.map` file.
    #[arg(long, default_value = "tests/data/movingai/warehouse-10-20-10-2-1.map")]
    pub map: PathBuf,
    /// Start cell `X,Y`.
    #[arg(long, value_parser = parse_cell, default_value = "143,57")]
    pub start: Cell,
    /// Goal cell `X,Y`.
    #[arg(long, value_parser = parse_cell, default_value = "10,16")]
    pub goal: Cell,
    /// Output directory.
    #[arg(long, default_value = "target/render-demo")]
    pub out: PathBuf,
    /// Size limit of the map.
    #[command(flatten)]
    pub limits: MapOptions,
}

fn parse_cell(text: &str) -> Result<Cell, String> {
    let (x, y) = text.split_once(',').ok_or("expected X,Y")?;
    let num = |s: &str| s.trim().parse::<u16>().map_err(|e| format!("{s:?}: {e}"));
    Ok(Cell::new(num(x)?, num(y)?))
}

/// Plans with A* and Theta*; returns both paths and their lengths.
fn plan_both(grid: GridRef<'_>, start: Cell, goal: Cell) -> anyhow::Result<[(Vec<Point>, f32); 2]> {
    let mut nodes = vec![SearchNode::EMPTY; grid.cells()];
    let mut astar_nodes = vec![AStarNode::EMPTY; grid.cells()];
    let mut open = vec![OpenSlot::EMPTY; open_capacity(grid.cells())];
    let mut path: Box<Path<{ 1 << 16 }>> = Box::new(Path::new());
    let out: &mut PathView = &mut *path;
    let a = astar::plan(grid, start, goal, &mut astar_nodes, &mut open, out)
        .map_err(anyhow::Error::msg)?;
    let a_path = out.to_vec();
    let t = theta::plan(grid, start, goal, &mut nodes, out).map_err(anyhow::Error::msg)?;
    Ok([(a_path, a.length), (out.to_vec(), t.length)])
}

/// Runs `host-sim render-demo`.
pub fn run(args: &RenderDemoArgs) -> anyhow::Result<()> {
    let out = |name: &str| args.out.join(name);
    // A real map with real paths.
    let grid = load_map(&args.map, &args.limits)?.grid;
    let [(a_path, a_len), (t_path, t_len)] =
        plan_both(grid.view(), args.start, args.goal).context("planning the demo query")?;
    let map_name = args
        .map
        .file_stem()
        .map_or_else(|| "map".into(), |s| s.to_string_lossy().into_owned());
    let title = format!("{map_name}: A* and Theta* paths");
    let a_label = format!("A* (length {a_len:.1})");
    let t_label = format!("Theta* (length {t_len:.1})");
    let mut pic = MapPicture::new(grid.view(), &title);
    pic.layers
        .push(Layer::new(&a_label, &a_path, Style::palette(0)));
    pic.layers.push(Layer::new(
        &t_label,
        &t_path,
        Style::dashed([213, 94, 0], 3.0),
    ));
    pic.start = Some(args.start.center());
    pic.goal = Some(args.goal.center());
    let (w, h) = pic.size_px()?;
    println!("warehouse picture: {w} x {h} px");
    pic.save_png(&out("warehouse.png"))?;
    pic.save_svg(&out("warehouse.svg"))?;

    // A small map with every kind of overlay.
    let small = GridBuf::parse_rows(
        b"..........\n..........\n..@@@@....\n.....@....\n.....@..@.\n\
          ..@......@\n..@...@@..\n..@.......\n......@...\n..........\n",
    )
    .map_err(anyhow::Error::msg)?;
    let [(s_path, s_len), _] = plan_both(small.view(), Cell::new(0, 0), Cell::new(9, 9))?;
    let s_label = format!("A* (length {s_len:.2})");
    let mut pic = MapPicture::new(small.view(), "10 x 10 example: path, marker, disc");
    pic.layers
        .push(Layer::new(&s_label, &s_path, Style::palette(0)));
    pic.markers.push(Marker {
        label: "pick station (example)",
        at: Point::new(7.0, 2.0),
        shape: Shape::Triangle,
        color: [230, 159, 0],
        radius_cells: 0.35,
    });
    pic.markers.push(Marker {
        label: "parked robot (example)",
        at: Point::new(9.0, 0.0),
        shape: Shape::Cross,
        color: [0, 0, 0],
        radius_cells: 0.35,
    });
    pic.discs.push(Disc {
        label: "dynamic obstacle (example)",
        at: Point::new(3.5, 8.0),
        radius_cells: 0.9,
        color: [204, 121, 167],
    });
    pic.start = Some(Point::new(0.0, 0.0));
    pic.goal = Some(Point::new(9.0, 9.0));
    pic.save_png(&out("small.png"))?;
    pic.save_svg(&out("small.svg"))?;

    // A synthetic height field (two hills) with a straight line across it.
    let (w, h) = (60usize, 40usize);
    let heights: Vec<f32> = (0..w * h)
        .map(|i| {
            let (x, y) = ((i % w) as f32, (i / w) as f32);
            let hill = |cx: f32, cy: f32, r: f32, top: f32| {
                top * (-((x - cx).powi(2) + (y - cy).powi(2)) / (r * r)).exp()
            };
            hill(18.0, 14.0, 9.0, 4.0) + hill(42.0, 26.0, 12.0, 2.5)
        })
        .collect();
    // A shelf across the valley, to show blocked cells over the field.
    let mut shelves = GridBuf::new(w, h).map_err(anyhow::Error::msg)?;
    for x in 28..34 {
        for y in 8..20 {
            shelves
                .set_blocked(x, y, true)
                .map_err(anyhow::Error::msg)?;
        }
    }
    let line = [Point::new(2.0, 37.0), Point::new(57.0, 3.0)];
    let mut field = FieldPicture::new(
        w,
        h,
        &heights,
        "Synthetic terrain (two hills, one shelf), top view",
    );
    field.value_label = "height (m)";
    field.bands = Some(8);
    field.blocked = Some(shelves.view());
    field.layers.push(Layer::new(
        "straight line (not a plan)",
        &line,
        Style::palette(0),
    ));
    field.start = Some(line[0]);
    field.goal = Some(line[1]);
    field.save_png(&out("field.png"))?;
    field.save_svg(&out("field.svg"))?;

    // Made-up convergence curves.
    let a: Vec<f32> = (0..200)
        .map(|i| 160.0 + 60.0 * (-(i as f32) / 25.0).exp())
        .collect();
    let b: Vec<f32> = (0..200)
        .map(|i| 158.0 + 80.0 / (1.0 + i as f32 / 10.0) + if i % 37 < 20 { 1.5 } else { 0.0 })
        .collect();
    convergence_plot(
        "Convergence (made-up data)",
        "iteration",
        "best path length (cells)",
        &[
            Series::new("optimizer A", &a),
            Series::new("optimizer B", &b).with_style(Style::dashed([213, 94, 0], 2.0)),
        ],
        Some(&out("convergence.png")),
        Some(&out("convergence.svg")),
    )?;
    println!("pictures written to {}", args.out.display());
    Ok(())
}

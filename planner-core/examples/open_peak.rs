//! Peak A* open-list sizes (`SearchStats::open_peak`), to size a firmware's open list.
//!
//! ```text
//! cargo run --release -p planner-core --example open_peak
//! ```
//! Prints, per Moving AI map in `tests/data/movingai` (every row of its scenario files) and
//! for `Lei2024Warehouse`'s warehouses, the largest open list, the mean, and the map's cell count.
use planner_core::grid::{Grid, words_for};
use planner_core::maps::{MapKind, lei2024_warehouse};
use planner_core::path::Path;
use planner_core::search::astar::{self, AStarNode, OpenSlot, open_capacity};

type G = Grid<{ words_for(512, 512) }>;

fn main() {
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data/movingai");
    let mut maps: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.extension().is_some_and(|x| x == "map"))
        .collect();
    maps.sort();
    let mut out: Box<Path<{ 1 << 16 }>> = Box::new(Path::new());
    for map in maps {
        let grid = Box::new(G::parse_movingai(&std::fs::read(&map).unwrap()).unwrap());
        let g = grid.view();
        let mut nodes = vec![AStarNode::EMPTY; g.cells()];
        let mut open = vec![OpenSlot::EMPTY; open_capacity(g.cells())];
        let stem = map.file_stem().unwrap().to_string_lossy().into_owned();
        let (mut peak, mut sum, mut n) = (0u32, 0u64, 0u64);
        for scen in std::fs::read_dir(&dir).unwrap().filter_map(|e| e.ok()) {
            let name = scen.file_name().to_string_lossy().into_owned();
            if !(name.starts_with(&format!("{stem}-")) && name.ends_with(".scen")) {
                continue;
            }
            let text = std::fs::read_to_string(scen.path()).unwrap();
            for line in text.lines().skip(1) {
                let f: Vec<&str> = line.split('\t').collect();
                let v = |k: usize| f[k].parse::<u16>().unwrap();
                let (s, t) = (
                    planner_core::geometry::Cell::new(v(4), v(5)),
                    planner_core::geometry::Cell::new(v(6), v(7)),
                );
                let st = astar::plan(g, s, t, &mut nodes, &mut open, &mut *out).unwrap();
                peak = peak.max(st.open_peak);
                sum += st.open_peak as u64;
                n += 1;
            }
        }
        println!(
            "{stem}: {}x{} ({} cells), {n} queries: open peak max {peak}, mean {:.1}",
            g.width(),
            g.height(),
            g.cells(),
            sum as f64 / n.max(1) as f64
        );
    }
    for side in [40, 64] {
        let m = lei2024_warehouse::<{ words_for(64, 64) }>(MapKind::Warehouse, side).unwrap();
        let g = m.grid.view();
        let mut nodes = vec![AStarNode::EMPTY; g.cells()];
        let mut open = vec![OpenSlot::EMPTY; open_capacity(g.cells())];
        let st = astar::plan(g, m.start, m.goal, &mut nodes, &mut open, &mut *out).unwrap();
        // Every free cell to every other would be O(cells^2): from the scenario's start to
        // every free cell instead, which covers the corridor guides' queries.
        let mut worst = 0;
        for i in 0..g.cells() {
            let c = g.cell(i);
            if g.is_free(c)
                && let Ok(s) = astar::plan(g, m.start, c, &mut nodes, &mut open, &mut *out)
            {
                worst = worst.max(s.open_peak);
            }
        }
        println!(
            "Lei2024Warehouse warehouse {side}x{side}: start->goal open peak {}, start->any free cell max {worst}",
            st.open_peak
        );
    }
}

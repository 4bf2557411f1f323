//! `host-sim maps`: the papers' built-in maps (`planner_core::maps`: `Lei2024Warehouse`'s
//! sparse and warehouse maps, `Liu2020Igwo`'s lab) as Moving AI `.map` files.

use anyhow::Context;
use planner_core::grid::words_for;
use planner_core::maps::{MapKind, lab_20x20, lei2024_warehouse};
use std::path::PathBuf;

/// Arguments of `host-sim maps`.
#[derive(clap::Args, Debug)]
pub struct MapsArgs {
    /// Output folder.
    #[arg(long, default_value = "bench-out/maps")]
    pub out: PathBuf,
}

/// Writes `seed000-{sparse,warehouse}-{10,30,40}.map` and `seed003-lab-20x20.map`, with the
/// start and goal in a comment file beside them. The file names keep the seed numbers of the
/// table atop `docs/references.md` (000: `Lei2024Warehouse`, 003: `Liu2020Igwo`).
pub fn run(args: &MapsArgs) -> anyhow::Result<()> {
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("cannot create {}", args.out.display()))?;
    let mut index = String::from("# map start_x start_y goal_x goal_y\n");
    let mut write = |name: String,
                     grid: &dyn Fn(&mut String) -> std::fmt::Result,
                     s: (u16, u16),
                     g: (u16, u16)|
     -> anyhow::Result<()> {
        let mut text = String::new();
        grid(&mut text)?;
        let path = args.out.join(&name);
        std::fs::write(&path, text).with_context(|| format!("cannot write {}", path.display()))?;
        index.push_str(&format!("{name} {} {} {} {}\n", s.0, s.1, g.0, g.1));
        println!("{}", path.display());
        Ok(())
    };
    for kind in [MapKind::Sparse, MapKind::Warehouse] {
        for size in [10, 30, 40] {
            let m = lei2024_warehouse::<{ words_for(40, 40) }>(kind, size)
                .map_err(|e| anyhow::anyhow!("{e:?}"))?;
            write(
                format!("seed000-{}-{size}.map", kind.name()),
                &|t| m.grid.write_movingai(t),
                (m.start.x, m.start.y),
                (m.goal.x, m.goal.y),
            )?;
        }
    }
    let lab = lab_20x20::<{ words_for(20, 20) }>().map_err(|e| anyhow::anyhow!("{e:?}"))?;
    write(
        "seed003-lab-20x20.map".into(),
        &|t| lab.grid.write_movingai(t),
        (lab.start.x, lab.start.y),
        (lab.goal.x, lab.goal.y),
    )?;
    std::fs::write(args.out.join("README.txt"), index)?;
    Ok(())
}

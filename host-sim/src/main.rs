//! `host-sim`: the front door of the warehouse planner.
//!
//! Subcommands:
//! - `plan`: plan queries on a Moving AI `.map` and print one JSON object a line.
//! - `render-demo` (hidden): write example pictures (see `render`) into `target/render-demo/`.

use clap::{Parser, Subcommand};

mod cmd;
mod maps;
mod render;

#[derive(Parser)]
#[command(
    name = "host-sim",
    version,
    about = "Warehouse robot path planning: planners, simulator and benchmarks"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Plan paths on a map; one JSON object per query.
    Plan(cmd::plan::PlanArgs),
    /// Write example pictures (maps, terrain, convergence) to look at the renderer.
    #[command(hide = true)]
    RenderDemo(cmd::render_demo::RenderDemoArgs),
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().command {
        Command::Plan(args) => cmd::plan::run(&args),
        Command::RenderDemo(args) => cmd::render_demo::run(&args),
    }
}

//! `host-sim`: the front door of the warehouse planner.
//!
//! Subcommands:
//! - `demo`, `run`, `scenarios`, `soak`: the simulator (see `sim`);
//! - `plan`: plan queries on a map file and print one JSON object a line;
//! - `optimize`: run a swarm optimizer on benchmark functions (JSON statistics);
//! - `bench paper|movingai|speed`: the papers' tables, quality and speed benchmarks;
//! - `maps`: write the papers' built-in maps (`planner_core::maps`) as `.map` files;
//! - `terrain`: 3D terrain planning, `Zhu2025Orchard`'s experiments 1-3 (tables 2-7) and a
//!   benchmark;
//! - `serve` (hidden): the planner service over iceoryx2, started by `--planner ipc`;
//! - `render-demo` (hidden): write example pictures (see `render`) into `target/render-demo/`.

use clap::{Parser, Subcommand};

mod cmd;

/// Counts heap bytes for the benches' peak-memory figures.
#[global_allocator]
static ALLOCATOR: host_sim::heap::Counting = host_sim::heap::Counting;

// The library's modules, bound at the crate root so `crate::sim` etc. resolve in `cmd`.
use host_sim::{exit, printed, render, sim, validate, warehouse_gen};

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
    /// The demo: a 40x40 warehouse, TCLHHO global paths, a robot driven with DWA among
    /// people and robots; pictures and a JSON report in bench-out/demo.
    Demo(cmd::sim::DemoArgs),
    /// Simulate one mission on any map (.map, ROS .yaml) or a generated warehouse.
    Run(cmd::sim::RunArgs),
    /// The hard cases of the simulator; exit status 1 if one fails.
    Scenarios(cmd::sim::ScenariosArgs),
    /// Many random missions on generated warehouses with dynamic obstacles.
    Soak(cmd::sim::SoakArgs),
    /// Plan paths on a map; one JSON object per query.
    Plan(cmd::plan::PlanArgs),
    /// Run a swarm optimizer on a benchmark function and print JSON statistics.
    Optimize(cmd::optimize::OptimizeArgs),
    /// Benchmarks: the papers' tables, Moving AI quality, speed.
    Bench(cmd::bench::BenchArgs),
    /// Write the papers' maps (Lei2024Warehouse's sparse and warehouse maps, Liu2020Igwo's
    /// lab) as Moving AI `.map` files.
    Maps(cmd::maps::MapsArgs),
    /// 3D terrain planning (Zhu2025Orchard, SSA-GWO): experiments 1-3 (tables 2-7), pictures,
    /// benchmark.
    Terrain(cmd::terrain::TerrainArgs),
    /// Write example pictures (maps, terrain, convergence) to look at the renderer.
    #[command(hide = true)]
    RenderDemo(cmd::render_demo::RenderDemoArgs),
    /// The planner service over iceoryx2 (what `--planner ipc` starts when none runs).
    #[command(hide = true)]
    Serve(cmd::serve::ServeArgs),
}

/// Runs the command; the exit status says how it ended ([`host_sim::exit`]: 0 done, 1 other
/// failure, 2 bad input, 3 a mission failed). Errors print with their causes, never as
/// `Debug` text.
fn main() -> std::process::ExitCode {
    match run(Cli::parse().command) {
        Ok(()) => std::process::ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("Error: {e:#}");
            std::process::ExitCode::from(host_sim::exit::status(&e))
        }
    }
}

fn run(command: Command) -> anyhow::Result<()> {
    match command {
        Command::Demo(args) => cmd::sim::demo(&args),
        Command::Run(args) => cmd::sim::run(&args),
        Command::Scenarios(args) => cmd::sim::scenarios(&args),
        Command::Soak(args) => cmd::sim::soak(&args),
        Command::Plan(args) => cmd::plan::run(&args),
        Command::Optimize(args) => cmd::optimize::run(&args),
        Command::Bench(args) => cmd::bench::run(&args),
        Command::Maps(args) => cmd::maps::run(&args),
        Command::Terrain(args) => cmd::terrain::run(&args),
        Command::RenderDemo(args) => cmd::render_demo::run(&args),
        Command::Serve(args) => cmd::serve::run(&args),
    }
}

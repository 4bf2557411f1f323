//! `host-sim`: the front door of the warehouse planner.
//!
//! Subcommands:
//! - `plan`: plan queries on a Moving AI `.map` and print one JSON object a line;
//! - `optimize`: run a swarm optimizer on benchmark functions (JSON statistics).

use clap::{Parser, Subcommand};

mod cmd;
mod maps;

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
    /// Run a swarm optimizer on a benchmark function and print JSON statistics.
    Optimize(cmd::optimize::OptimizeArgs),
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().command {
        Command::Plan(args) => cmd::plan::run(&args),
        Command::Optimize(args) => cmd::optimize::run(&args),
    }
}

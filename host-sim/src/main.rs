//! Host simulator and benchmark CLI for the planner core.

mod cmd;

use clap::{Parser, Subcommand};

#[derive(Parser)]
#[command(
    name = "host-sim",
    about = "Host simulator for the warehouse path planner"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a swarm optimizer on a benchmark function and print JSON statistics.
    Optimize(cmd::optimize::OptimizeArgs),
}

fn main() -> anyhow::Result<()> {
    match Cli::parse().command {
        Command::Optimize(args) => cmd::optimize::run(&args),
    }
}

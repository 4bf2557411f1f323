//! `planner-server`: serves every planner-core planner over iceoryx2.
//!
//! ```text
//! planner-server [--prefix planner] [--workers 1] [--mode blocking|busy] [--max-cells N]
//!                [--max-maps 16] [--max-clients 64] [--verify-maps]
//! ```
//! Logs go to standard error (`RUST_LOG=debug` for per-request errors). SIGINT and SIGTERM
//! shut it down cleanly.

use crate::server::{self, ServerConfig, WaitMode};
use crate::services::{Limits, Names};
use clap::{Parser, ValueEnum};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

#[derive(Clone, Copy, Debug, ValueEnum)]
enum Mode {
    /// Sleep on the wake event when idle.
    Blocking,
    /// Spin on the ports (lowest latency, burns a core).
    Busy,
}

#[derive(Parser, Debug)]
#[command(
    name = "planner-server",
    version,
    about = "Path planner service over iceoryx2 shared memory"
)]
struct Args {
    /// Service name prefix (clients must use the same).
    #[arg(long, default_value = "planner")]
    prefix: String,
    /// Planning threads (1 = plan on the port thread, lowest latency).
    #[arg(long, default_value_t = 1)]
    workers: usize,
    /// Waiting mode when idle.
    #[arg(long, value_enum, default_value_t = Mode::Blocking)]
    mode: Mode,
    /// Largest map accepted, in cells (default 4096 x 4096; sides are at most 65535). Larger
    /// maps are refused with MapTooLarge, logged, and the client's error names this limit.
    #[arg(long, default_value_t = crate::wire::DEFAULT_MAX_CELLS)]
    max_cells: usize,
    /// Map ids kept at once.
    #[arg(long, default_value_t = 16)]
    max_maps: usize,
    /// Clients (and map publishers) at once.
    #[arg(long, default_value_t = 64)]
    max_clients: usize,
    /// Blocking mode: how long to keep polling after the last request before sleeping
    /// on the wake event, microseconds (longer than a client's wake-up latency keeps a
    /// loaded server from falling asleep between back-to-back requests).
    #[arg(long, default_value_t = 200)]
    spin_us: u64,
    /// Check that the row- and column-major layouts of every received map frame agree (a
    /// frame whose layouts disagree is rejected and logged with the first differing cell);
    /// costs a transposition of the map per frame. Off: frames are planned on as sent.
    #[arg(long)]
    verify_maps: bool,
}

/// The binary's entry point (also linked into test binaries).
pub fn main() -> anyhow::Result<()> {
    serve(Args::parse())
}

/// Serves with the default settings under `prefix` until SIGINT or SIGTERM: how other
/// programs (the simulator's `host-sim serve`) embed the server without a separate binary.
pub fn serve_prefix(prefix: &str) -> anyhow::Result<()> {
    serve(Args::parse_from(["planner-server", "--prefix", prefix]))
}

fn serve(args: Args) -> anyhow::Result<()> {
    let _ = env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info"))
        .try_init();
    crate::services::quiet_iceoryx_logs();
    let shutdown = Arc::new(AtomicBool::new(false));
    for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(signal, shutdown.clone())?;
    }
    let config = ServerConfig {
        names: Names::new(&args.prefix),
        limits: Limits {
            max_clients: args.max_clients,
            ..Limits::default()
        },
        workers: args.workers.max(1),
        max_cells: args.max_cells,
        max_maps: args.max_maps,
        mode: match args.mode {
            Mode::Blocking => WaitMode::Blocking,
            Mode::Busy => WaitMode::Busy,
        },
        spin: std::time::Duration::from_micros(args.spin_us),
        verify_maps: args.verify_maps,
        ..ServerConfig::default()
    };
    server::run(&config, &shutdown)
}

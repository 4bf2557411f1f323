//! `host-sim serve` (hidden): the planner service inside this binary, so that `demo`, `run`
//! and `soak --planner ipc` can start a server when none is running without a separate
//! build (see `sim::ipc`).

use std::io::Read;

/// Arguments of `host-sim serve`.
#[derive(clap::Args, Debug)]
pub struct ServeArgs {
    /// Service name prefix (clients must use the same).
    #[arg(long, default_value = "planner")]
    pub prefix: String,
    /// Shut down when standard input closes (the parent process ended or let go).
    #[arg(long)]
    pub exit_on_stdin_eof: bool,
}

/// Serves until SIGINT or SIGTERM (or the end of standard input with
/// `--exit-on-stdin-eof`).
pub fn run(args: &ServeArgs) -> anyhow::Result<()> {
    if args.exit_on_stdin_eof {
        std::thread::spawn(|| {
            let mut sink = [0u8; 64];
            let mut stdin = std::io::stdin();
            while matches!(stdin.read(&mut sink), Ok(n) if n > 0) {}
            // The server stops cleanly on SIGTERM (answers what is queued, removes its
            // services).
            let _ = signal_hook::low_level::raise(signal_hook::consts::SIGTERM);
        });
    }
    planner_ipc::cli::server::serve_prefix(&args.prefix)
}

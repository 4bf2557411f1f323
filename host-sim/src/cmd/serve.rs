//! `host-sim serve` (hidden): the planner service inside this binary, so that `demo`, `run`
//! and `soak --planner ipc|zenoh` can start a server when none is running without a
//! separate build (see `sim::ipc` and `sim::zenoh`).

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
    /// More `planner-server` options, after `--` (`-- --transport zenoh --listen
    /// tcp/127.0.0.1:7447`; what `--planner zenoh` starts).
    #[arg(last = true)]
    pub server_options: Vec<String>,
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
    let mut options = vec!["--prefix".to_string(), args.prefix.clone()];
    options.extend(args.server_options.iter().cloned());
    planner_ipc::cli::server::serve_with(options)
}

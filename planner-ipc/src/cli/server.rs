//! `planner-server`: serves every planner-core planner over iceoryx2.
//!
//! ```text
//! planner-server [--prefix planner] [--workers 1] [--mode blocking|busy] [--max-cells N]
//!                [--max-maps 16] [--max-clients 64] [--verify-maps]
//!                [--transport iceoryx2|zenoh|both] [--mode peer|client|router]
//!                [--listen ENDPOINT]... [--connect ENDPOINT]... [--zenoh-config FILE]
//!                [--map-listen ENDPOINT]... [--map-connect ENDPOINT]... [--route-only]
//! ```
//! `--transport zenoh` serves over Zenoh (feature `zenoh`, `docs/zenoh.md`), `both` serves
//! one engine (one map store) over both. `--mode` takes iceoryx2's waiting mode
//! (blocking, busy) and Zenoh's mode (peer, client, router), once each at most. `--mode
//! router --route-only` is a Zenoh router of our own (no planner), so that no `zenohd` is
//! needed.
//!
//! Logs go to standard error (`RUST_LOG=debug` for per-request errors). SIGINT and SIGTERM
//! shut it down cleanly.

use crate::server::{self, ServerConfig, WaitMode};
use crate::services::{Limits, Names};
use clap::{Parser, ValueEnum};
use std::sync::Arc;
use std::sync::atomic::AtomicBool;

/// Which transports serve the planner.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Transport {
    /// Shared memory, this host only.
    Iceoryx2,
    /// Zenoh (TCP), across hosts (feature `zenoh`).
    Zenoh,
    /// Both, one engine and map store.
    Both,
}

/// `--mode`: the iceoryx2 server's waiting mode, and the Zenoh sessions' mode (give
/// both as two `--mode` options).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
enum Mode {
    /// iceoryx2: sleep on the wake event when idle (default).
    Blocking,
    /// iceoryx2: spin on the ports (lowest latency, burns a core).
    Busy,
    /// Zenoh: connect to the endpoints given and the peers learnt of; accept peers (default).
    Peer,
    /// Zenoh: connect to one router or peer.
    Client,
    /// Zenoh: route for clients and peers (no zenohd needed).
    Router,
}

#[derive(Parser, Debug)]
#[command(
    name = "planner-server",
    version,
    about = "Path planner service over iceoryx2 shared memory and Zenoh"
)]
struct Args {
    /// Service name prefix (clients must use the same).
    #[arg(long, default_value = "planner")]
    prefix: String,
    /// Planning threads (1 = plan on the port thread, lowest latency).
    #[arg(long, default_value_t = 1)]
    workers: usize,
    /// iceoryx2's waiting mode when idle (blocking, busy) and the Zenoh mode (peer,
    /// client, router); repeat the option for both (`--mode busy --mode router`).
    #[arg(long, value_enum)]
    mode: Vec<Mode>,
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
    /// Transports serving the planner.
    #[arg(long, value_enum, default_value_t = Transport::Iceoryx2)]
    transport: Transport,
    /// Zenoh: endpoint to listen on for plans (repeatable; default tcp/127.0.0.1:7447 for a
    /// peer or router, none for a client). Maps use the next port unless --map-listen.
    #[arg(long)]
    listen: Vec<String>,
    /// Zenoh: endpoint to connect to (a router or peer; repeatable).
    #[arg(long)]
    connect: Vec<String>,
    /// Zenoh: endpoint of the map session to listen on (default: each --listen, next port).
    #[arg(long)]
    map_listen: Vec<String>,
    /// Zenoh: endpoint of the map session to connect to (default: each --connect, next port).
    #[arg(long)]
    map_connect: Vec<String>,
    /// Zenoh: a configuration file (JSON5) for everything else; the options above and the
    /// service's settings (docs/zenoh.md) are applied on top of it.
    #[arg(long)]
    zenoh_config: Option<std::path::PathBuf>,
    /// Zenoh: route only, serve no planner (with --zenoh-mode router: a router of our own).
    #[arg(long)]
    route_only: bool,
}

/// The binary's entry point (also linked into test binaries). With the `zenoh` feature it
/// first sets `ZENOH_RUNTIME` to one worker unless set
/// (`zenoh::config::set_runtime_env_if_unset`): call it
/// first thing in `main`, before any thread starts.
pub fn main() -> anyhow::Result<()> {
    #[cfg(feature = "zenoh")]
    #[allow(unsafe_code)]
    // SAFETY: called first in the process's `main`, which has started no thread.
    unsafe {
        crate::zenoh::config::set_runtime_env_if_unset();
    }
    serve(Args::parse())
}

/// Serves with the default settings under `prefix` until SIGINT or SIGTERM: how other
/// programs (the simulator's `host-sim serve`) embed the server without a separate binary.
pub fn serve_prefix(prefix: &str) -> anyhow::Result<()> {
    serve(Args::parse_from(["planner-server", "--prefix", prefix]))
}

/// Serves with the given `planner-server` options (without the program name) until SIGINT
/// or SIGTERM: [`serve_prefix`] with any options (`host-sim serve --transport zenoh`).
pub fn serve_with<I, T>(options: I) -> anyhow::Result<()>
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let argv = std::iter::once(std::ffi::OsString::from("planner-server"))
        .chain(options.into_iter().map(Into::into));
    serve(Args::try_parse_from(argv)?)
}

fn serve(args: Args) -> anyhow::Result<()> {
    let _ = env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("info"))
        .try_init();
    crate::services::quiet_iceoryx_logs();
    let shutdown = Arc::new(AtomicBool::new(false));
    for signal in [signal_hook::consts::SIGINT, signal_hook::consts::SIGTERM] {
        signal_hook::flag::register(signal, shutdown.clone())?;
    }
    let waits = args
        .mode
        .iter()
        .filter(|m| matches!(m, Mode::Blocking | Mode::Busy))
        .count();
    if waits > 1 || args.mode.len() - waits > 1 {
        anyhow::bail!(
            "--mode {:?}: give at most one of blocking|busy (iceoryx2) and one of peer|client|router (Zenoh)",
            args.mode
        );
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
        mode: if args.mode.contains(&Mode::Busy) {
            WaitMode::Busy
        } else {
            WaitMode::Blocking
        },
        spin: std::time::Duration::from_micros(args.spin_us),
        verify_maps: args.verify_maps,
        ..ServerConfig::default()
    };
    match args.transport {
        Transport::Iceoryx2 => server::run(&config, &shutdown),
        Transport::Zenoh | Transport::Both => serve_zenoh(&args, &config, shutdown),
    }
}

#[cfg(not(feature = "zenoh"))]
fn serve_zenoh(args: &Args, _: &ServerConfig, _: Arc<AtomicBool>) -> anyhow::Result<()> {
    anyhow::bail!(
        "--transport {:?}: this planner-server was built without Zenoh (cargo build -p planner-ipc --features zenoh)",
        args.transport
    )
}

/// Serves over Zenoh (and iceoryx2 with `--transport both`, one engine).
#[cfg(feature = "zenoh")]
fn serve_zenoh(
    args: &Args,
    config: &ServerConfig,
    shutdown: Arc<AtomicBool>,
) -> anyhow::Result<()> {
    use crate::zenoh::config::{Mode as ZMode, ZenohOptions};
    let mode = match args
        .mode
        .iter()
        .find(|m| matches!(m, Mode::Client | Mode::Router))
    {
        Some(Mode::Client) => ZMode::Client,
        Some(Mode::Router) => ZMode::Router,
        _ => ZMode::Peer,
    };
    let listen = if args.listen.is_empty() && mode != ZMode::Client {
        vec!["tcp/127.0.0.1:7447".to_string()]
    } else {
        args.listen.clone()
    };
    let list = |v: &Vec<String>| (!v.is_empty()).then(|| v.clone());
    let zconfig = crate::zenoh::server::ServerConfig {
        prefix: args.prefix.clone(),
        options: ZenohOptions {
            mode,
            listen,
            connect: args.connect.clone(),
            map_listen: list(&args.map_listen),
            map_connect: list(&args.map_connect),
            config_file: args.zenoh_config.clone(),
        },
        workers: args.workers.max(1),
        route_only: args.route_only,
        ..crate::zenoh::server::ServerConfig::default()
    };
    let engine = Arc::new(crate::engine::Engine::new(args.max_cells, args.max_maps));
    if args.transport == Transport::Zenoh {
        return crate::zenoh::server::run(&zconfig, engine, shutdown);
    }
    let zenoh = {
        let engine = engine.clone();
        let shutdown = shutdown.clone();
        std::thread::Builder::new()
            .name("planner-zenoh".into())
            .spawn(move || {
                let result = crate::zenoh::server::run(&zconfig, engine, shutdown.clone());
                // Either front end failing stops the other.
                shutdown.store(true, std::sync::atomic::Ordering::Relaxed);
                result
            })?
    };
    let ice = server::run_with_engine(config, engine, &shutdown);
    shutdown.store(true, std::sync::atomic::Ordering::Relaxed);
    let z = zenoh
        .join()
        .map_err(|_| anyhow::anyhow!("the Zenoh front end panicked"))?;
    ice.and(z)
}

//! `planner-client`: upload a map file to a running `planner-server` and request plans,
//! printing the same JSON lines as `host-sim plan`.
//!
//! ```text
//! planner-client [--prefix P] [--busy] upload --map FILE.map|FILE.yaml [--map-id 1] [--unknown blocked|free]
//! planner-client [--prefix P] [--busy] plan --map FILE.map|FILE.yaml [--map-id 1] --algo NAME
//!                (--queries Q.txt | --start X,Y --goal X,Y) [--frame cells|world]
//!                [--seed N] [--radius R | --robot-radius M] [--unknown blocked|free]
//!                [--timeout-ms 1000] [--out RESULTS.jsonl]
//! planner-client --transport zenoh [--connect tcp/127.0.0.1:7447]... [--mode peer|client]
//!                [--request query|pair] [--zenoh-config FILE] [--map-connect ENDPOINT]...
//!                upload|plan ...
//! ```
//! Over Zenoh (feature `zenoh`) the same commands print the same lines; a request that
//! loses its planner or route on the way is resent (same id) until `--timeout-ms` plus a
//! margin, and no planner at all is an error at once (exit status 1).
//! Maps are read by the loader every `host-sim` command uses (`planner-mapfile`: Moving AI
//! `.map`, ROS `map_server` YAML + PGM/PNG), up to the size the planner service takes. A
//! ROS map's resolution and origin go with the upload; `--frame world` takes starts, goals
//! and queries in metres in the map frame, and paths come back in cells and metres.
//! `plan` uploads the map first (the publisher keeps it for late servers while it lives),
//! waits until the server holds it, then sends one request per query.
//!
//! Exit status: 0 when every query was answered (a query's own failure is a JSON line), 2
//! for bad input (a map, query file or option that cannot be used), 1 when the service
//! cannot be reached.

use crate::client::{ClientConfig, ClientError, MapTooLarge, PlannerClient, Refusal, Wait};
use crate::jsonl::{self, Endpoint, ErrorLine, LineContext, PathLine, Query, QueryLine};
use crate::services::Names;
use crate::wire::{Algorithm, MapMeta, PlanOk, PlanParams, PlanRequest};
use anyhow::Context;
use clap::{Parser, Subcommand};
use planner_core::grid::GridRef;
use planner_mapfile::frame::parse_point;
use planner_mapfile::{Frame, LoadedMap, MapLoadError, MapOptions, Unknown, load_map};
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// Exit status for bad input (a map, query file or option that cannot be used).
pub const EXIT_BAD_INPUT: u8 = 2;

#[derive(Parser)]
#[command(
    name = "planner-client",
    version,
    about = "Talk to a running planner-server"
)]
struct Cli {
    /// Service name prefix (same as the server's).
    #[arg(long, default_value = "planner", global = true)]
    prefix: String,
    /// Spin while waiting for answers instead of sleeping (iceoryx2).
    #[arg(long, global = true)]
    busy: bool,
    /// How to reach the planner: iceoryx2 (this host) or zenoh (any host; feature `zenoh`).
    #[arg(long, value_enum, default_value_t = Transport::Iceoryx2, global = true)]
    transport: Transport,
    /// Zenoh: endpoint of a planner or router to connect to (repeatable).
    #[arg(long, global = true, default_value = "tcp/127.0.0.1:7447")]
    connect: Vec<String>,
    /// Zenoh: endpoint of the map session to connect to (default: each --connect, next port).
    #[arg(long, global = true)]
    map_connect: Vec<String>,
    /// Zenoh: mode of the sessions.
    #[arg(long, value_enum, default_value_t = ZenohMode::Peer, global = true)]
    mode: ZenohMode,
    /// Zenoh: a configuration file (JSON5) for everything else (docs/zenoh.md).
    #[arg(long, global = true)]
    zenoh_config: Option<PathBuf>,
    /// Zenoh: how requests travel: a query on the planners' queryable, or the
    /// publish-subscribe pair (about half the round trip).
    #[arg(long, value_enum, default_value_t = RequestPathArg::Query, global = true)]
    request: RequestPathArg,
    #[command(subcommand)]
    command: Command,
}

/// How to reach the planner.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum Transport {
    /// Shared memory, this host.
    Iceoryx2,
    /// Zenoh (TCP), any host.
    Zenoh,
}

/// How Zenoh requests travel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum RequestPathArg {
    /// A query on `P/@v1/plan`.
    Query,
    /// The publish-subscribe pair (`P/@v1/req/<planner>/<client>`, `P/@v1/rep/<client>`).
    Pair,
}

/// The Zenoh sessions' mode.
#[derive(Clone, Copy, Debug, PartialEq, Eq, clap::ValueEnum)]
enum ZenohMode {
    /// Connect to the endpoints given and the peers learnt of.
    Peer,
    /// Connect to one router or peer.
    Client,
}

#[derive(Subcommand)]
enum Command {
    /// Publish a map and wait until the server holds it.
    Upload {
        /// Moving AI `.map` or ROS map_server `.yaml` (PGM/PNG image) file.
        #[arg(long)]
        map: PathBuf,
        /// Map id.
        #[arg(long, default_value_t = 1)]
        map_id: u32,
        /// Unknown space of a ROS map: blocked or free.
        #[arg(long, value_enum, default_value_t = Unknown::Blocked)]
        unknown: Unknown,
        /// How long to wait for the server, milliseconds.
        #[arg(long, default_value_t = 5000)]
        wait_ms: u64,
    },
    /// Upload a map and plan queries on it; one JSON object per query.
    Plan(PlanArgs),
}

#[derive(clap::Args)]
struct PlanArgs {
    /// Moving AI `.map` or ROS map_server `.yaml` (PGM/PNG image) file.
    #[arg(long)]
    map: PathBuf,
    /// Map id.
    #[arg(long, default_value_t = 1)]
    map_id: u32,
    /// File of queries, one `sx sy gx gy` a line (cells, or metres with `--frame world`).
    #[arg(long, required_unless_present = "start", conflicts_with_all = ["start", "goal"])]
    queries: Option<PathBuf>,
    /// Start `X,Y` (a cell, or metres with `--frame world`).
    #[arg(long, requires = "goal", allow_hyphen_values = true)]
    start: Option<String>,
    /// Goal `X,Y` (a cell, or metres with `--frame world`).
    #[arg(long, requires = "start", allow_hyphen_values = true)]
    goal: Option<String>,
    /// What starts, goals and queries are in: cells, or metres in the map frame (a ROS map).
    #[arg(long, value_enum, default_value_t = Frame::Cells)]
    frame: Frame,
    /// Planner name (`astar`, `theta`, `anyangle`, swarm planners; unknown names reach the
    /// server and come back as `UnknownAlgorithm`).
    #[arg(long, default_value = "astar")]
    algo: String,
    /// Seed (stochastic planners).
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Inflation of the map by a robot radius, in cells.
    #[arg(long, conflicts_with = "robot_radius")]
    radius: Option<f32>,
    /// Robot radius in metres (a ROS map; default 0.25 there, 0 plans for a point): cells
    /// whose centre lies within it of an obstacle are blocked for planning.
    #[arg(long)]
    robot_radius: Option<f64>,
    /// Unknown space of a ROS map: blocked or free.
    #[arg(long, value_enum, default_value_t = Unknown::Blocked)]
    unknown: Unknown,
    /// Swarm planners' blended objective: desired clearance in cells of the inflated map
    /// (0: none; the server refuses a negative or non-finite value as InvalidParameters).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    clearance: f32,
    /// Blended objective: cost per cell of path per cell of missing clearance.
    #[arg(long, default_value_t = 16.0, allow_hyphen_values = true)]
    clearance_weight: f32,
    /// Blended objective: cost in cells per radian of turning (0: none).
    #[arg(long, default_value_t = 0.0, allow_hyphen_values = true)]
    turn_weight: f32,
    /// Per-request timeout, milliseconds.
    #[arg(long, default_value_t = 1000)]
    timeout_ms: u64,
    /// Write results here instead of standard output.
    #[arg(long)]
    out: Option<PathBuf>,
}

/// Bad input: exit status [`EXIT_BAD_INPUT`].
#[derive(Debug)]
struct BadInput(String);

impl std::fmt::Display for BadInput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for BadInput {}

fn bad(text: impl Into<String>) -> anyhow::Error {
    BadInput(text.into()).into()
}

/// `X,Y` in the frame asked for: integers for cells, numbers for metres.
fn endpoint(text: &str, frame: Frame, what: &str) -> anyhow::Result<Endpoint> {
    let [x, y] = parse_point(text).map_err(|e| bad(format!("--{what} {text}: {e}")))?;
    match frame {
        Frame::World => Ok(Endpoint::World([x, y])),
        Frame::Cells if x.fract() == 0.0 && y.fract() == 0.0 && x.abs() < 1e15 => {
            Ok(Endpoint::Cell(x as i64, y as i64))
        }
        Frame::Cells => Err(bad(format!(
            "--{what} {text}: cells are integers (--frame world takes metres)"
        ))),
    }
}

/// Why a plan call gave no path.
enum PlanFail {
    /// The service cannot be reached at all: exit status 1 with this message.
    Unreachable(String),
    /// A failure of this query: its JSON line (the error's name).
    Named(&'static str),
}

/// What the commands need from a transport's client.
trait PlanService {
    /// The largest map (cells) the service takes, if known.
    fn map_limit(&mut self) -> anyhow::Result<Option<u64>>;
    /// Publishes a map.
    fn upload_map(&mut self, meta: MapMeta, grid: GridRef<'_>) -> anyhow::Result<()>;
    /// Waits until the service holds a map version.
    fn wait_for_map(&mut self, map_id: u32, version: u32, wait: Duration) -> anyhow::Result<()>;
    /// A version above what the service and this client hold of `map_id`.
    fn next_version(&mut self, map_id: u32, wait: Duration) -> u32;
    /// One request: the path and the server's time (µs).
    fn plan_raw(
        &mut self,
        request: &PlanRequest,
        timeout: Duration,
    ) -> Result<(PlanOk, f32), PlanFail>;
    /// The server's time of the last answer, when there was one.
    fn last_server_time_us(&self) -> Option<f32>;
}

impl PlanService for PlannerClient {
    fn map_limit(&mut self) -> anyhow::Result<Option<u64>> {
        Ok(PlannerClient::map_limit(self)?)
    }

    fn upload_map(&mut self, meta: MapMeta, grid: GridRef<'_>) -> anyhow::Result<()> {
        Ok(PlannerClient::upload_map(self, meta, grid)?)
    }

    fn wait_for_map(&mut self, map_id: u32, version: u32, wait: Duration) -> anyhow::Result<()> {
        PlannerClient::wait_for_map(self, map_id, version, wait)?;
        Ok(())
    }

    fn next_version(&mut self, map_id: u32, wait: Duration) -> u32 {
        PlannerClient::next_version(self, map_id, wait)
    }

    fn plan_raw(
        &mut self,
        request: &PlanRequest,
        timeout: Duration,
    ) -> Result<(PlanOk, f32), PlanFail> {
        PlannerClient::plan_raw(self, request, timeout).map_err(|e| match e {
            ClientError::NoServer => PlanFail::Unreachable("no planner server is running".into()),
            e => PlanFail::Named(e.name()),
        })
    }

    fn last_server_time_us(&self) -> Option<f32> {
        PlannerClient::last_server_time_us(self)
    }
}

#[cfg(feature = "zenoh")]
impl PlanService for crate::zenoh::ZenohClient {
    fn map_limit(&mut self) -> anyhow::Result<Option<u64>> {
        Ok(self.limits().map(|l| l.max_cells))
    }

    fn upload_map(&mut self, meta: MapMeta, grid: GridRef<'_>) -> anyhow::Result<()> {
        Ok(crate::zenoh::ZenohClient::upload_map(self, meta, grid)?)
    }

    fn wait_for_map(&mut self, map_id: u32, version: u32, wait: Duration) -> anyhow::Result<()> {
        crate::zenoh::ZenohClient::wait_for_map(self, map_id, version, wait)?;
        Ok(())
    }

    fn next_version(&mut self, map_id: u32, wait: Duration) -> u32 {
        crate::zenoh::ZenohClient::next_version(self, map_id, wait)
    }

    fn plan_raw(
        &mut self,
        request: &PlanRequest,
        timeout: Duration,
    ) -> Result<(PlanOk, f32), PlanFail> {
        use crate::zenoh::ZenohError;
        let failed = |e: ZenohError| match e {
            ZenohError::NoPlanner { .. } | ZenohError::NotConnected { .. } => {
                PlanFail::Unreachable(e.to_string())
            }
            e => PlanFail::Named(e.name()),
        };
        let result = self.plan_retrying(request, timeout).map_err(failed)?;
        let time = result.time_us;
        match result.outcome {
            Ok(ok) => Ok((ok, time)),
            Err(f) => Err(failed(f.into())),
        }
    }

    fn last_server_time_us(&self) -> Option<f32> {
        crate::zenoh::ZenohClient::last_server_time_us(self)
    }
}

/// Loads `path` with the shared loader, within the map service's limit; a map over it is
/// the client's [`MapTooLarge`], named with the file.
fn load(client: &mut dyn PlanService, path: &Path, unknown: Unknown) -> anyhow::Result<LoadedMap> {
    let limit = client.map_limit()?;
    let options = MapOptions {
        max_cells: limit.map_or(usize::MAX, |c| usize::try_from(c).unwrap_or(usize::MAX)),
        unknown,
    };
    load_map(path, &options).map_err(|e| match e {
        MapLoadError::TooLarge { width, height, .. } => {
            let side = |v: usize| u32::try_from(v).unwrap_or(u32::MAX);
            let refused = MapTooLarge {
                size: Some((side(width), side(height))),
                max_cells: limit,
                refused_by: Refusal::Client,
            };
            bad(format!("{}: {refused}", path.display()))
        }
        other => bad(other.to_string()),
    })
}

/// Publishes `map` as `map_id` (above the version the service holds) and waits until it is
/// served.
fn upload(
    client: &mut dyn PlanService,
    map: &LoadedMap,
    map_id: u32,
    wait: Duration,
) -> anyhow::Result<u32> {
    // Above what the server holds: a map uploaded earlier under this id (by any process)
    // must not shadow this one.
    let version = client.next_version(map_id, wait);
    let cell0 = map.frame.to_world(0.0, 0.0);
    let meta = MapMeta {
        map_id,
        version,
        resolution: map.frame.resolution as f32,
        // The world position of cell (0, 0)'s centre.
        origin: [cell0[0] as f32, cell0[1] as f32],
    };
    client.upload_map(meta, map.grid.view())?;
    client
        .wait_for_map(map_id, version, wait)
        .context("the server did not take the map")?;
    Ok(version)
}

/// The binary's entry point (also linked into test binaries). Bad input exits with
/// [`EXIT_BAD_INPUT`] after the client is dropped (its iceoryx2 node removed).
pub fn main() -> anyhow::Result<()> {
    #[cfg(feature = "zenoh")]
    #[allow(unsafe_code)]
    // SAFETY: called first in the process's `main`, which has started no thread.
    unsafe {
        crate::zenoh::config::set_runtime_env_if_unset();
    }
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    crate::services::quiet_iceoryx_logs();
    match run(Cli::parse()) {
        Err(e) if e.downcast_ref::<BadInput>().is_some() => {
            eprintln!("Error: {e:#}");
            std::process::exit(EXIT_BAD_INPUT.into())
        }
        other => other,
    }
}

fn run(cli: Cli) -> anyhow::Result<()> {
    let mut client: Box<dyn PlanService> = match cli.transport {
        Transport::Iceoryx2 => {
            let config = ClientConfig {
                names: Names::new(&cli.prefix),
                wait: if cli.busy {
                    Wait::Busy
                } else {
                    ClientConfig::default().wait
                },
                ..ClientConfig::default()
            };
            Box::new(PlannerClient::new(config)?)
        }
        Transport::Zenoh => zenoh_client(&cli)?,
    };
    let client = &mut *client;
    match cli.command {
        Command::Upload {
            map,
            map_id,
            unknown,
            wait_ms,
        } => {
            let loaded = load(client, &map, unknown)?;
            let version = upload(client, &loaded, map_id, Duration::from_millis(wait_ms))?;
            eprintln!("map {map_id} version {version} is served");
            Ok(())
        }
        Command::Plan(args) => plan(client, &args),
    }
}

#[cfg(not(feature = "zenoh"))]
fn zenoh_client(_: &Cli) -> anyhow::Result<Box<dyn PlanService>> {
    anyhow::bail!(
        "--transport zenoh: this planner-client was built without Zenoh (cargo build -p planner-ipc --features zenoh)"
    )
}

#[cfg(feature = "zenoh")]
fn zenoh_client(cli: &Cli) -> anyhow::Result<Box<dyn PlanService>> {
    use crate::zenoh::{ClientConfig, Mode, RequestPath, ZenohClient, ZenohOptions};
    let config = ClientConfig {
        prefix: cli.prefix.clone(),
        path: match cli.request {
            RequestPathArg::Query => RequestPath::Query,
            RequestPathArg::Pair => RequestPath::Pair,
        },
        options: ZenohOptions {
            mode: match cli.mode {
                ZenohMode::Peer => Mode::Peer,
                ZenohMode::Client => Mode::Client,
            },
            connect: cli.connect.clone(),
            map_connect: (!cli.map_connect.is_empty()).then(|| cli.map_connect.clone()),
            config_file: cli.zenoh_config.clone(),
            ..ZenohOptions::default()
        },
        ..ClientConfig::default()
    };
    Ok(Box::new(ZenohClient::open(config)?))
}

fn plan(client: &mut dyn PlanService, args: &PlanArgs) -> anyhow::Result<()> {
    let loaded = load(client, &args.map, args.unknown)?;
    let frame = loaded.frame;
    if args.frame == Frame::World && !frame.declared {
        return Err(bad(format!(
            "{}: a Moving AI map has no world frame (it is in cells); --frame world needs a \
             ROS map YAML with a resolution and an origin",
            args.map.display()
        )));
    }
    let inflation = jsonl::inflation(args.radius, args.robot_radius, &frame)
        .map_err(|e| bad(format!("{}: {e}", args.map.display())))?;
    let radius_cells = inflation.cells;
    let lines = match (&args.queries, &args.start, &args.goal) {
        (Some(file), _, _) => {
            let text = std::fs::read_to_string(file)
                .map_err(|e| bad(format!("cannot read queries {}: {e}", file.display())))?;
            jsonl::parse_queries(&text, args.frame)
        }
        (None, Some(s), Some(g)) => vec![QueryLine::Query(Query {
            start: endpoint(s, args.frame, "start")?,
            goal: endpoint(g, args.frame, "goal")?,
        })],
        _ => return Err(bad("give --queries FILE or both --start and --goal")),
    };
    let version = upload(client, &loaded, args.map_id, Duration::from_secs(5))?;
    // Unknown names are sent as code 0 so that the server answers UnknownAlgorithm.
    let code = Algorithm::from_name(&args.algo).map_or(0, |a| a.code());
    let sink: Box<dyn Write> = match &args.out {
        Some(path) => Box::new(
            std::fs::File::create(path)
                .map_err(|e| bad(format!("cannot create {}: {e}", path.display())))?,
        ),
        None => Box::new(std::io::stdout().lock()),
    };
    let mut sink = BufWriter::new(sink);
    let ctx = LineContext {
        algo: &args.algo,
        seed: args.seed,
        frame: frame.declared.then_some(&frame),
    };
    for line in lines {
        let value = match line {
            QueryLine::Query(query) => match query.resolve(&frame) {
                Err(e) => jsonl::plan_line(&query, None, Err(e), 0.0, &ctx),
                Ok(cells) => {
                    let (start, goal) = cells;
                    let clamp = |v: i64| v.clamp(i32::MIN as i64, i32::MAX as i64) as i32;
                    let mut request = PlanRequest::new(
                        (args.map_id, version),
                        [clamp(start.0), clamp(start.1)],
                        [clamp(goal.0), clamp(goal.1)],
                        Algorithm::AStar,
                    );
                    request.algorithm = code;
                    request.seed = args.seed;
                    request.params = PlanParams {
                        radius: radius_cells as f32,
                        clearance: args.clearance,
                        clearance_weight: args.clearance_weight,
                        turn_weight: args.turn_weight,
                        ..PlanParams::default()
                    };
                    let began = Instant::now();
                    let result = client.plan_raw(&request, Duration::from_millis(args.timeout_ms));
                    let round_trip = began.elapsed().as_secs_f64() * 1e6;
                    match result {
                        Ok((ok, time_us)) => {
                            let path: Vec<[f32; 2]> = ok.path.iter().map(|p| [p.x, p.y]).collect();
                            let found = PathLine {
                                path: &path,
                                length: ok.length,
                                turns: ok.turns as usize,
                                expanded: Some(ok.evaluations),
                                report: None,
                            };
                            let mut line = jsonl::plan_line(
                                &query,
                                Some(cells),
                                Ok(found),
                                time_us as f64,
                                &ctx,
                            );
                            // What the client waited, beside the server's `time_us`.
                            line["round_trip_us"] = round_trip.round().into();
                            line
                        }
                        Err(PlanFail::Unreachable(why)) => anyhow::bail!("{why}"),
                        Err(PlanFail::Named(name)) => {
                            let error = jsonl::explain(
                                ErrorLine::named(name),
                                loaded.grid.view(),
                                loaded.unknown.as_ref().map(|u| u.view()),
                                cells,
                                inflation.text.as_deref(),
                            );
                            // The server's time when it answered, else the round trip.
                            let time = client.last_server_time_us().map_or(round_trip, f64::from);
                            jsonl::plan_line(&query, Some(cells), Err(error), time, &ctx)
                        }
                    }
                }
            },
            QueryLine::Malformed { line, detail } => {
                serde_json::json!({"line": line, "error": "MalformedQuery", "detail": detail})
            }
        };
        serde_json::to_writer(&mut sink, &value)?;
        sink.write_all(b"\n")?;
    }
    sink.flush()?;
    Ok(())
}

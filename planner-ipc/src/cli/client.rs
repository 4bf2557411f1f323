//! `planner-client`: upload a Moving AI `.map` to a running `planner-server` and request
//! plans, printing the same JSON lines as `host-sim plan`.
//!
//! ```text
//! planner-client [--prefix P] [--busy] upload --map FILE.map [--map-id 1]
//! planner-client [--prefix P] [--busy] plan --map FILE.map [--map-id 1] --algo astar|theta
//!                (--queries Q.txt | --start X,Y --goal X,Y) [--seed N] [--radius R]
//!                [--timeout-ms 1000] [--out RESULTS.jsonl]
//! ```
//! `plan` uploads the map first (the publisher keeps it for late servers while it lives),
//! waits until the server holds it, then sends one request per query.

use crate::client::{ClientConfig, ClientError, PlannerClient, Wait};
use crate::jsonl::{self, PathLine};
use crate::services::Names;
use crate::wire::{Algorithm, PlanParams, PlanRequest};
use anyhow::Context;
use clap::{Parser, Subcommand};
use std::io::{BufWriter, Write};
use std::path::PathBuf;
use std::time::{Duration, Instant};

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
    /// Spin while waiting for answers instead of sleeping.
    #[arg(long, global = true)]
    busy: bool,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Publish a map and wait until the server holds it.
    Upload {
        /// Moving AI `.map` file.
        #[arg(long)]
        map: PathBuf,
        /// Map id.
        #[arg(long, default_value_t = 1)]
        map_id: u32,
        /// How long to wait for the server, milliseconds.
        #[arg(long, default_value_t = 5000)]
        wait_ms: u64,
    },
    /// Upload a map and plan queries on it; one JSON object per query.
    Plan {
        /// Moving AI `.map` file.
        #[arg(long)]
        map: PathBuf,
        /// Map id.
        #[arg(long, default_value_t = 1)]
        map_id: u32,
        /// File of queries, one `sx sy gx gy` a line.
        #[arg(long, required_unless_present = "start", conflicts_with_all = ["start", "goal"])]
        queries: Option<PathBuf>,
        /// Start cell `X,Y`.
        #[arg(long, value_parser = parse_xy, requires = "goal")]
        start: Option<(i64, i64)>,
        /// Goal cell `X,Y`.
        #[arg(long, value_parser = parse_xy, requires = "start")]
        goal: Option<(i64, i64)>,
        /// Planner name (`astar`, `theta`; unknown names reach the server and come back
        /// as `UnknownAlgorithm`).
        #[arg(long, default_value = "astar")]
        algo: String,
        /// Seed (stochastic planners).
        #[arg(long, default_value_t = 0)]
        seed: u64,
        /// Robot radius in cells.
        #[arg(long, default_value_t = 0.0)]
        radius: f32,
        /// Per-request timeout, milliseconds.
        #[arg(long, default_value_t = 1000)]
        timeout_ms: u64,
        /// Write results here instead of standard output.
        #[arg(long)]
        out: Option<PathBuf>,
    },
}

fn parse_xy(text: &str) -> Result<(i64, i64), String> {
    let (x, y) = text.split_once(',').ok_or("expected X,Y")?;
    let num = |s: &str| s.trim().parse::<i64>().map_err(|e| format!("{s:?}: {e}"));
    Ok((num(x)?, num(y)?))
}

/// The binary's entry point (also linked into test binaries).
pub fn main() -> anyhow::Result<()> {
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    crate::services::quiet_iceoryx_logs();
    let cli = Cli::parse();
    let config = ClientConfig {
        names: Names::new(&cli.prefix),
        wait: if cli.busy {
            Wait::Busy
        } else {
            ClientConfig::default().wait
        },
        ..ClientConfig::default()
    };
    let mut client = PlannerClient::new(config)?;
    match cli.command {
        Command::Upload {
            map,
            map_id,
            wait_ms,
        } => {
            let version = client.upload_map_file(&map, map_id)?;
            client
                .wait_for_map(map_id, version, Duration::from_millis(wait_ms))
                .context("the server did not take the map")?;
            eprintln!("map {map_id} version {version} is served");
        }
        Command::Plan {
            map,
            map_id,
            queries,
            start,
            goal,
            algo,
            seed,
            radius,
            timeout_ms,
            out,
        } => {
            let version = client.upload_map_file(&map, map_id)?;
            client
                .wait_for_map(map_id, version, Duration::from_secs(5))
                .context("the server did not take the map")?;
            let lines = match (&queries, start, goal) {
                (Some(file), _, _) => {
                    let text = std::fs::read_to_string(file)
                        .with_context(|| format!("cannot read queries {}", file.display()))?;
                    jsonl::parse_queries(&text)
                }
                (None, Some(s), Some(g)) => vec![jsonl::QueryLine::Query { start: s, goal: g }],
                _ => anyhow::bail!("give --queries FILE or both --start and --goal"),
            };
            // Unknown names are sent as code 0 so that the server answers UnknownAlgorithm.
            let code = Algorithm::from_name(&algo).map_or(0, |a| a.code());
            let sink: Box<dyn Write> = match &out {
                Some(path) => Box::new(
                    std::fs::File::create(path)
                        .with_context(|| format!("cannot create {}", path.display()))?,
                ),
                None => Box::new(std::io::stdout().lock()),
            };
            let mut sink = BufWriter::new(sink);
            for line in lines {
                let value = match line {
                    jsonl::QueryLine::Query { start, goal } => {
                        let clamp = |v: i64| v.clamp(i32::MIN as i64, i32::MAX as i64) as i32;
                        let mut request = PlanRequest::new(
                            (map_id, version),
                            [clamp(start.0), clamp(start.1)],
                            [clamp(goal.0), clamp(goal.1)],
                            Algorithm::AStar,
                        );
                        request.algorithm = code;
                        request.seed = seed;
                        request.params = PlanParams {
                            radius,
                            ..PlanParams::default()
                        };
                        let began = Instant::now();
                        let result = client.plan_raw(&request, Duration::from_millis(timeout_ms));
                        let round_trip = began.elapsed().as_secs_f64() * 1e6;
                        match result {
                            Ok((ok, time_us)) => {
                                let path: Vec<[f32; 2]> =
                                    ok.path.iter().map(|p| [p.x, p.y]).collect();
                                jsonl::plan_line(
                                    start,
                                    goal,
                                    Ok(PathLine {
                                        path: &path,
                                        length: ok.length,
                                        turns: ok.turns as usize,
                                        expanded: Some(ok.evaluations),
                                        report: None,
                                    }),
                                    time_us as f64,
                                    &algo,
                                    seed,
                                )
                            }
                            Err(ClientError::NoServer) => {
                                anyhow::bail!("no planner server is running")
                            }
                            Err(e) => jsonl::plan_line(
                                start,
                                goal,
                                Err(e.name()),
                                // The server's time when it answered, else the round trip.
                                client.last_server_time_us().map_or(round_trip, f64::from),
                                &algo,
                                seed,
                            ),
                        }
                    }
                    jsonl::QueryLine::Malformed { line, detail } => {
                        serde_json::json!({"line": line, "error": "MalformedQuery", "detail": detail})
                    }
                };
                serde_json::to_writer(&mut sink, &value)?;
                sink.write_all(b"\n")?;
            }
            sink.flush()?;
        }
    }
    Ok(())
}

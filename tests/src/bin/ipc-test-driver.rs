//! A client process for the cross-process tests.
//!
//! ```text
//! ipc-test-driver load PREFIX MAP_FILE MAP_ID VERSION COUNT SEED busy|blocking
//! ipc-test-driver hammer PREFIX MAP_ID VERSION SX SY GX GY
//! ipc-test-driver churn PREFIX MAP_FILE MAP_ID VERSION SECONDS SEED search|all PAUSE_MS
//! ```
//! `load` sends COUNT requests between pseudo-random cells (free, blocked or unreachable)
//! and checks every answer against the same engine run locally: the response must belong
//! to the request (id) and carry exactly the expected outcome (path, length or error). It
//! prints one JSON object: counts and every round-trip latency in microseconds.
//! `hammer` sends the same (long) request forever; the tests kill it mid-request.
//! `churn` sends requests for SECONDS (A*/Theta*, or every planner with small swarm
//! settings), PAUSE_MS apart, with a short timeout, through server crashes: each answer is
//! checked against the local engine like `load`; it prints counts of ok answers, outage
//! errors (timeout, no server, unknown map while a new server has not got the map yet),
//! ok answers after the first outage error, mismatches and unexpected errors.

use planner_ipc::client::{ClientConfig, ClientError, PlannerClient, Wait, parse_map};
use planner_ipc::engine::{Engine, Scratch};
use planner_ipc::services::Names;
use planner_ipc::wire::{Algorithm, MapMeta, PlanRequest, ServiceError};
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize| -> anyhow::Result<&str> {
        args.get(i)
            .map(String::as_str)
            .ok_or_else(|| anyhow::anyhow!("missing argument {i}"))
    };
    match arg(0)? {
        "load" => load(
            arg(1)?,
            arg(2)?,
            arg(3)?.parse()?,
            arg(4)?.parse()?,
            arg(5)?.parse()?,
            arg(6)?.parse()?,
            arg(7)? == "busy",
        ),
        "hammer" => hammer(
            arg(1)?,
            (arg(2)?.parse()?, arg(3)?.parse()?),
            [arg(4)?.parse()?, arg(5)?.parse()?],
            [arg(6)?.parse()?, arg(7)?.parse()?],
        ),
        "churn" => churn(
            arg(1)?,
            arg(2)?,
            (arg(3)?.parse()?, arg(4)?.parse()?),
            Duration::from_secs_f64(arg(5)?.parse()?),
            arg(6)?.parse()?,
            arg(7)? == "all",
            Duration::from_millis(arg(8)?.parse()?),
        ),
        other => anyhow::bail!("unknown command {other}"),
    }
}

fn client(prefix: &str, busy: bool) -> anyhow::Result<PlannerClient> {
    let mut config = ClientConfig {
        names: Names::new(prefix),
        node_name: format!("driver-{}", std::process::id()),
        ..ClientConfig::default()
    };
    if busy {
        config.wait = Wait::Busy;
    }
    Ok(PlannerClient::new(config)?)
}

fn load(
    prefix: &str,
    map_file: &str,
    map_id: u32,
    version: u32,
    count: usize,
    seed: u64,
    busy: bool,
) -> anyhow::Result<()> {
    let (local, w, h) = local_engine(map_file, (map_id, version))?;
    let mut scratch = Scratch::default();
    let mut client = client(prefix, busy)?;
    let mut next = xorshift(seed);
    let (mut ok, mut mismatched, mut lost) = (0usize, 0usize, 0usize);
    let mut errors: BTreeMap<String, usize> = BTreeMap::new();
    let mut latencies = Vec::with_capacity(count);
    for i in 0..count {
        let r = next();
        let cell = |v: u64| [(v % w) as i32, ((v / w) % h) as i32];
        let algo = if i % 2 == 0 {
            Algorithm::AStar
        } else {
            Algorithm::ThetaStar
        };
        let request = PlanRequest::new(
            (map_id, version),
            cell(r & 0xffff_ffff),
            cell(r >> 32),
            algo,
        );
        let expected = local.handle(&mut scratch, &request, &mut || false).outcome;
        let began = Instant::now();
        let got = client.plan(&request, Duration::from_secs(5));
        latencies.push(began.elapsed().as_secs_f64() * 1e6);
        match (got, expected) {
            (Ok(a), Ok(b)) if a.path == b.path && a.length == b.length => ok += 1,
            (Err(ClientError::Plan(a)), Err(planner_ipc::wire::Failure::Plan(b))) if a == b => {
                ok += 1;
                *errors.entry(a.name().to_string()).or_default() += 1;
            }
            (Err(ClientError::Timeout), _) => lost += 1,
            (Err(ClientError::Mismatch { .. }), _) => mismatched += 1,
            (got, want) => {
                mismatched += 1;
                eprintln!("request {i}: got {got:?}, expected {want:?}");
            }
        }
    }
    let summary = serde_json::json!({
        "sent": count,
        "ok": ok,
        "lost": lost,
        "mismatched": mismatched,
        "planner_errors": errors,
        "latency_us": latencies,
    });
    println!("{summary}");
    Ok(())
}

fn hammer(prefix: &str, map: (u32, u32), start: [i32; 2], goal: [i32; 2]) -> anyhow::Result<()> {
    let mut client = client(prefix, false)?;
    let request = PlanRequest::new(map, start, goal, Algorithm::ThetaStar);
    loop {
        println!("sending");
        let _ = client.plan(&request, Duration::from_secs(30));
    }
}

fn churn(
    prefix: &str,
    map_file: &str,
    map: (u32, u32),
    duration: Duration,
    seed: u64,
    all_planners: bool,
    pause: Duration,
) -> anyhow::Result<()> {
    let (local, w, h) = local_engine(map_file, map)?;
    let mut scratch = Scratch::default();
    let mut client = client(prefix, false)?;
    let mut next = xorshift(seed);
    let (mut sent, mut ok, mut outage, mut ok_after_outage, mut mismatched, mut unexpected) =
        (0u64, 0u64, 0u64, 0u64, 0u64, 0u64);
    let mut kinds: BTreeMap<String, u64> = BTreeMap::new();
    let began = Instant::now();
    let mut i = 0u64;
    while began.elapsed() < duration {
        let r = next();
        let cell = |v: u64| [(v % w) as i32, ((v / w) % h) as i32];
        let algo = if all_planners {
            Algorithm::ALL[(i % Algorithm::ALL.len() as u64) as usize]
        } else if i.is_multiple_of(2) {
            Algorithm::AStar
        } else {
            Algorithm::ThetaStar
        };
        let mut request = PlanRequest::new(map, cell(r & 0xffff_ffff), cell(r >> 32), algo);
        request.seed = r;
        request.params.population = 8;
        request.params.iterations = 10;
        i += 1;
        let expected = local.handle(&mut scratch, &request, &mut || false).outcome;
        let got = client.plan(&request, Duration::from_millis(400));
        sent += 1;
        let good = match (&got, &expected) {
            (Ok(a), Ok(b)) => a.path == b.path && a.length == b.length,
            (Err(ClientError::Plan(a)), Err(planner_ipc::wire::Failure::Plan(b))) => a == b,
            _ => false,
        };
        if good {
            ok += 1;
            if outage > 0 {
                ok_after_outage += 1;
            }
        } else {
            *kinds
                .entry(format!("{got:?}").chars().take(40).collect())
                .or_default() += 1;
            match got {
                Err(ClientError::Timeout)
                | Err(ClientError::NoServer)
                | Err(ClientError::Service(ServiceError::UnknownMap)) => outage += 1,
                Err(ClientError::Mismatch { .. }) | Ok(_) | Err(ClientError::Plan(_)) => {
                    mismatched += 1;
                    eprintln!("request {i}: got {got:?}, expected {expected:?}");
                }
                Err(e) => {
                    unexpected += 1;
                    eprintln!("request {i}: unexpected {e:?}");
                }
            }
            // Back off a little while the server is away.
            std::thread::sleep(Duration::from_millis(20));
        }
        if !pause.is_zero() {
            std::thread::sleep(pause);
        }
    }
    let summary = serde_json::json!({
        "sent": sent,
        "ok": ok,
        "outage": outage,
        "ok_after_outage": ok_after_outage,
        "mismatched": mismatched,
        "unexpected": unexpected,
        "errors": kinds,
    });
    println!("{summary}");
    Ok(())
}

/// An in-process engine holding `map_file` as `(map_id, version)`: the oracle every answer
/// from the server is compared with. Also returns the map's width and height.
fn local_engine(map_file: &str, map: (u32, u32)) -> anyhow::Result<(Engine, u64, u64)> {
    let grid = parse_map(&std::fs::read(map_file)?)?;
    let (w, h) = (grid.width() as u64, grid.height() as u64);
    let local = Engine::new(usize::MAX, 1);
    let meta = MapMeta {
        map_id: map.0,
        version: map.1,
        resolution: 1.0,
        origin: [0.0; 2],
    };
    local.store.update(meta, Ok(grid));
    Ok((local, w, h))
}

/// xorshift64* from `seed`: the driver's query stream.
fn xorshift(seed: u64) -> impl FnMut() -> u64 {
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    move || {
        state ^= state >> 12;
        state ^= state << 25;
        state ^= state >> 27;
        state.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }
}

//! `planner-bench`: iceoryx2 against a Unix domain socket with postcard framing, in one run.
//!
//! ```text
//! cargo build --release -p planner-ipc --bins
//! target/release/planner-bench [--iterations 10000] [--map-updates 100] [--mode busy|blocking]
//!                              [--only small|large|long]
//! ```
//! For a 64x64 and a 340x164 empty map (`small`), in busy and blocking modes, it measures:
//! - the round trip of a trivial plan (A* from (0,0) to (3,2)): iceoryx2 against the
//!   `planner-server` binary (spawned from the same directory) and the socket against a
//!   peer process (this binary, `uds-peer`) running the same engine; both report the
//!   server-side planning time, so the transport share is printed too;
//! - publishing a map update: the sender's cost of handing a whole map over (iceoryx2:
//!   loan + write + send of a map frame (header + used words); socket: postcard encoding + write), and the full
//!   update until the server confirms it holds the new version (it has built the planner's
//!   grid from the frame, so the map is usable).
//!
//! `large`: the same on a 4096 x 4096 warehouse (shelf rows, cross aisles, scattered
//! pallets; a 2 MiB frame), `--map-updates` updates (default 100) and a tenth of the plan
//! round trips. `long`: a plan answer of 1200 waypoints (A* along the diagonal of an empty
//! 1200 x 1200 map; both transports pay the same server-side planning, the "of which
//! transport" row takes it out).
//!
//! `planner-bench raw [N]` prints the floors under the plan round trip (see [`raw_floor`]).
//!
//! `planner-bench zenoh ...` (feature `zenoh`): the planner over Zenoh against a plain TCP +
//! postcard baseline, a 4096 x 4096 map to 8 subscribers, 32 client processes x 1,000 plans
//! (see the `zenoh` module).
//!
//! Socket framing: a little-endian `u32` length, then the postcard bytes of a
//! [`UdsRequest`] or [`UdsResponse`]. Busy mode spins on non-blocking sockets; blocking
//! mode blocks in `read`.

use anyhow::Context;
use iceoryx2::prelude::*;
use iceoryx2::service::port_factory::publish_subscribe::PortFactory as PubSubFactory;
use iceoryx2::service::port_factory::request_response::PortFactory as ReqRespFactory;
use planner_core::grid::{GridBuf, GridMut, words_for};
use planner_ipc::client::{ClientConfig, ClientError, PlannerClient, Wait};
use planner_ipc::engine::{Engine, Scratch};
use planner_ipc::services::Names;
use planner_ipc::wire::{
    Algorithm, DEFAULT_MAX_CELLS, LAYOUT_ROWS_AND_COLUMNS, MapHeader, MapMeta, MapMsg, PlanRequest,
    PlanResponseHeader, PlanResult, Waypoint, first_disagreement, frame_grid, frame_header,
    grid_from_bits, write_grid,
};
use serde::{Deserialize, Serialize};
use std::io::{ErrorKind, Read, Write};
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

/// What the socket peer receives (decoded into owned values).
#[derive(Deserialize)]
enum UdsRequest {
    Map(MapMsg),
    Plan(PlanRequest),
}

/// What the socket client sends: the same postcard bytes as [`UdsRequest`], serialized from
/// borrowed words (no copy of the frame before encoding).
#[derive(Serialize)]
enum UdsRequestRef<'a> {
    Map(MapMsgRef<'a>),
    Plan(PlanRequest),
}

/// [`MapMsg`] with borrowed words (a slice encodes like a `Vec`).
#[derive(Serialize)]
struct MapMsgRef<'a> {
    meta: MapMeta,
    width: u32,
    height: u32,
    bits: &'a [u32],
}

impl<'a> MapMsgRef<'a> {
    fn new(frame: &'a Frame) -> Self {
        MapMsgRef {
            meta: frame.header.meta(),
            width: frame.header.width,
            height: frame.header.height,
            // A byte-stream peer sends the rows; the receiver builds its grid from them.
            bits: &frame.words[..frame.header.words()],
        }
    }
}

/// Socket buffers: a 4096 x 4096 frame encodes to at most 5 bytes a word (2.5 MiB).
const UDS_BUFFER: usize = 8 << 20;

#[derive(Serialize, Deserialize)]
enum UdsResponse {
    /// The map is stored; how long building its grid took (µs).
    MapTaken(f32),
    Plan(PlanResult),
}

#[cfg(feature = "zenoh")]
mod zbench;

fn main() -> anyhow::Result<()> {
    #[cfg(feature = "zenoh")]
    #[allow(unsafe_code)]
    // SAFETY: first thing in `main`: no other thread runs yet.
    unsafe {
        planner_ipc::zenoh::config::set_runtime_env_if_unset();
    }
    env_logger::Builder::from_env(env_logger::Env::default().default_filter_or("warn")).init();
    planner_ipc::services::quiet_iceoryx_logs();
    let args: Vec<String> = std::env::args().skip(1).collect();
    if args.first().map(String::as_str) == Some("uds-peer") {
        let path = PathBuf::from(args.get(1).context("uds-peer PATH busy|blocking")?);
        let busy = args.get(2).map(String::as_str) == Some("busy");
        return uds_peer(&path, busy);
    }
    if args.first().map(String::as_str) == Some("echo") {
        return echo(&args[1..]);
    }
    if args.first().map(String::as_str) == Some("raw") {
        return raw_floor(args.get(1).map_or(Ok(20_000), |v| v.parse())?);
    }
    if args.first().is_some_and(|a| a.starts_with("zenoh")) {
        #[cfg(feature = "zenoh")]
        return zbench::main(&args);
        #[cfg(not(feature = "zenoh"))]
        anyhow::bail!(
            "{}: this planner-bench was built without Zenoh (cargo build --release -p planner-ipc --features zenoh --bins)",
            args[0]
        );
    }
    let value = |name: &str| -> anyhow::Result<Option<&String>> {
        match args.iter().position(|a| a == name) {
            Some(i) => Ok(Some(
                args.get(i + 1).with_context(|| format!("{name} VALUE"))?,
            )),
            None => Ok(None),
        }
    };
    let iterations: usize = value("--iterations")?.map_or(Ok(10_000), |v| v.parse())?;
    let map_updates: usize = value("--map-updates")?.map_or(Ok(100), |v| v.parse())?;
    // `--mode busy|blocking`: only that waiting mode.
    let only_mode = value("--mode")?.map(|m| m == "busy");
    let only = value("--only")?.map(String::as_str);
    println!(
        "planner-bench: {iterations} round trips per case; trivial plan = A* (0,0)->(3,2) on an empty map"
    );
    println!(
        "{:<9} {:<8} {:<36} {:>10} {:>10} {:>10} {:>10} {:>8}",
        "map", "mode", "what", "ipc p50", "ipc p99", "uds p50", "uds p99", "ratio"
    );
    let trivial = PlanRequest::new((1, 1), [0, 0], [3, 2], Algorithm::AStar);
    let mut cases = Vec::new();
    if only.is_none_or(|o| o == "small") {
        for (w, h) in [(64usize, 64usize), (340, 164)] {
            let grid = GridBuf::new(w, h).map_err(anyhow::Error::msg)?;
            cases.push(Case {
                name: format!("{w}x{h}"),
                frame: Frame::of(grid),
                request: trivial,
                plan: "plan round trip",
                iterations,
                updates: (iterations / 20).max(50),
            });
        }
    }
    if only.is_none_or(|o| o == "large") {
        cases.push(Case {
            name: "4096x4096".into(),
            frame: Frame::of(warehouse(4096, 4096)),
            request: trivial,
            plan: "plan round trip",
            iterations: iterations / 10,
            updates: map_updates,
        });
    }
    if only.is_none_or(|o| o == "long") {
        let grid = GridBuf::new(1200, 1200).map_err(anyhow::Error::msg)?;
        cases.push(Case {
            name: "1200x1200".into(),
            frame: Frame::of(grid),
            request: PlanRequest::new((1, 1), [0, 0], [1199, 1199], Algorithm::AStar),
            plan: "plan, 1200 waypoints",
            iterations: iterations / 5,
            updates: 0,
        });
    }
    for case in &mut cases {
        for busy in [true, false] {
            if only_mode.is_none_or(|o| o == busy) {
                run_case(case, busy)?;
            }
        }
        if case.updates > 0 {
            receiver_costs(case);
        }
    }
    println!(
        "ratio = iceoryx2 p50 / socket p50 (goals: plan round trip <= 0.4 in busy mode, map publish <= 0.2; 4096x4096 map update <= 0.05; 1200-waypoint plan <= 0.3)"
    );
    Ok(())
}

/// A generated warehouse: two-cell-deep shelf rows 40 cells long with three-cell aisles,
/// a five-cell cross aisle every 200 cells, a clear border of 8 cells and a scattered
/// pallet in about one aisle cell of 600.
fn warehouse(width: usize, height: usize) -> GridBuf {
    let mut grid = GridBuf::new(width, height).expect("warehouse size");
    let mut state = 0x9E37_79B9_7F4A_7C15u64;
    let _ = grid.view_mut().fill_rows(|y, words| {
        let shelf_row = y >= 8 && y + 8 < height && y % 5 < 2;
        for (i, word) in words.iter_mut().enumerate() {
            for bit in 0..32 {
                let x = 32 * i + bit;
                if x >= width {
                    break;
                }
                let inside = x >= 8 && x + 8 < width && y >= 8 && y + 8 < height;
                let cross = x % 200 < 5 || y % 200 < 5;
                let shelf = shelf_row && x % 43 < 40;
                state ^= state << 13;
                state ^= state >> 7;
                state ^= state << 17;
                let pallet = state.is_multiple_of(600);
                if inside && !cross && (shelf || pallet) {
                    *word |= 1 << bit;
                }
            }
        }
    });
    grid
}

/// One row group of the table: a map, the plan request to time, how many round trips and
/// map updates.
struct Case {
    name: String,
    frame: Frame,
    request: PlanRequest,
    plan: &'static str,
    iterations: usize,
    updates: usize,
}

struct Kill(Child);

impl Drop for Kill {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn percentile(samples: &mut [f64], q: f64) -> f64 {
    samples.sort_by(f64::total_cmp);
    samples[((samples.len() - 1) as f64 * q).round() as usize]
}

fn row(map: &str, mode: &str, what: &str, ipc: &mut [f64], uds: &mut [f64]) {
    let (i50, i99) = (percentile(ipc, 0.5), percentile(ipc, 0.99));
    let (u50, u99) = (percentile(uds, 0.5), percentile(uds, 0.99));
    println!(
        "{map:<9} {mode:<8} {what:<36} {i50:>8.2}us {i99:>8.2}us {u50:>8.2}us {u99:>8.2}us {:>8.3}",
        i50 / u50
    );
}

fn run_case(case: &mut Case, busy: bool) -> anyhow::Result<()> {
    let mode = if busy { "busy" } else { "blocking" };
    let warmup = case.iterations / 10 + 10;
    // One transport at a time: with 2 cores, a spinning idle peer would distort the other.
    let mut ipc = ipc_phase(case, busy, warmup)?;
    let mut uds = uds_phase(case, busy, warmup)?;
    let name = &case.name;
    if case.iterations > 0 {
        row(name, mode, case.plan, &mut ipc.rt, &mut uds.rt);
        row(
            name,
            mode,
            "  of which transport",
            &mut ipc.net,
            &mut uds.net,
        );
        row(
            name,
            mode,
            "  answer read in place",
            &mut ipc.rt_in_place,
            &mut uds.rt,
        );
        row(
            name,
            mode,
            "    of which transport",
            &mut ipc.net_in_place,
            &mut uds.net,
        );
    }
    if case.updates > 0 {
        for (how, update) in &mut ipc.updates {
            let what = format!("map publish, {how} (sender)");
            row(
                name,
                mode,
                &what,
                &mut update.publish,
                &mut uds.update.publish,
            );
            let what = format!("  until usable, {how}");
            row(name, mode, &what, &mut update.full, &mut uds.update.full);
            let what = format!("    of which transport, {how}");
            row(name, mode, &what, &mut update.net, &mut uds.update.net);
        }
    }
    Ok(())
}

/// Map updates: the sender's publish, until the server confirms it can plan on the new
/// version (a map-status answer), and that without the receiver's work on the frame (both
/// servers report it: building the grid, or checking the frame and, if not kept, copying).
#[derive(Default)]
struct Updates {
    publish: Vec<f64>,
    full: Vec<f64>,
    net: Vec<f64>,
}

/// Plan round trips, their transport share (without server-side planning), map updates.
#[derive(Default)]
struct Samples {
    rt: Vec<f64>,
    net: Vec<f64>,
    update: Updates,
}

/// The iceoryx2 side: plans with the answer copied out and read in place, the map updates
/// three ways.
struct IpcSamples {
    rt: Vec<f64>,
    net: Vec<f64>,
    rt_in_place: Vec<f64>,
    net_in_place: Vec<f64>,
    updates: Vec<(&'static str, Updates)>,
}

/// A map frame as published: both layouts (rows, then columns), and the grid.
struct Frame {
    header: MapHeader,
    words: Vec<u32>,
    grid: GridBuf,
}

impl Frame {
    fn of(grid: GridBuf) -> Self {
        let meta = MapMeta {
            map_id: 1,
            version: 1,
            resolution: 0.05,
            origin: [0.0, 0.0],
        };
        let (w, h) = (grid.width(), grid.height());
        let n = words_for(w, h);
        let mut words = vec![0u32; 2 * n];
        let (rows, columns) = words.split_at_mut(n);
        let mut out = GridMut::from_words(w, h, rows, columns).expect("frame size");
        write_grid(grid.view(), &mut out).expect("same size");
        let header = frame_header(meta, w, h, LAYOUT_ROWS_AND_COLUMNS);
        Frame {
            header,
            words,
            grid,
        }
    }
}

/// What the receiver does with a frame, in this process (p50 / p99 of 20): the view of a
/// frame of both layouts (the server's work when it keeps the frame), the layout check of
/// `planner-server --verify-maps`, the copy when it does not keep the frame, and building
/// the grid from the rows (what a rows-only frame, and the socket peer, cost).
fn receiver_costs(case: &Case) {
    let frame = &case.frame;
    let header = &frame.header;
    let (w, h, n) = (
        header.width as usize,
        header.height as usize,
        header.words(),
    );
    let measure = |what: &str, f: &mut dyn FnMut() -> bool| {
        let mut t: Vec<f64> = (0..20)
            .map(|_| {
                let (ok, t) = timed(&mut *f);
                assert!(ok, "{what}");
                t
            })
            .collect();
        println!(
            "{:<9} receiver {what:<36} {:>8.2}us {:>8.2}us",
            case.name,
            percentile(&mut t, 0.5),
            percentile(&mut t, 0.99)
        );
    };
    let words = &frame.words;
    measure("view of both layouts", &mut || {
        frame_grid(header, words, DEFAULT_MAX_CELLS).is_ok()
    });
    measure("layout check (--verify-maps)", &mut || {
        first_disagreement(w, h, &words[..n], &words[n..]).is_none()
    });
    measure("copy of both layouts", &mut || {
        frame_grid(header, words, DEFAULT_MAX_CELLS)
            .map(GridBuf::from_view)
            .is_ok()
    });
    measure("grid built from rows", &mut || {
        grid_from_bits(header.width, header.height, &words[..n], DEFAULT_MAX_CELLS).is_ok()
    });
}

/// How long `f` takes, microseconds.
fn timed<T>(f: impl FnOnce() -> T) -> (T, f64) {
    let began = Instant::now();
    let value = f();
    (value, began.elapsed().as_secs_f64() * 1e6)
}

fn ipc_phase(case: &mut Case, busy: bool, warmup: usize) -> anyhow::Result<IpcSamples> {
    let (frame, iterations, updates_wanted) = (&mut case.frame, case.iterations, case.updates);
    let mode = if busy { "busy" } else { "blocking" };
    let prefix = format!(
        "bench-{}-{}x{}-{mode}",
        std::process::id(),
        frame.header.width,
        frame.header.height
    );
    let exe_dir = std::env::current_exe()?
        .parent()
        .context("no exe dir")?
        .to_path_buf();
    let _server = Kill(
        Command::new(exe_dir.join("planner-server"))
            .args(["--prefix", &prefix, "--mode", mode])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .context("cannot start planner-server (build it: cargo build --release -p planner-ipc --bins)")?,
    );
    let mut client = PlannerClient::new(ClientConfig {
        names: Names::new(&prefix),
        wait: if busy {
            Wait::Busy
        } else {
            // The library default: spin 50 us, then sleep on the wake event.
            ClientConfig::default().wait
        },
        node_name: "planner-bench".into(),
        // A busy server polls its ports: no wake-up syscall needed.
        notify_server: !busy,
        ..ClientConfig::default()
    })?;
    frame.header.map_version = 1;
    client.publish_map(&frame.header, &frame.words)?;
    client.wait_for_map(1, 1, Duration::from_secs(10))?;
    let request = case.request;
    let (mut rt, mut net) = (Vec::new(), Vec::new());
    // No warm-up either when the case times no plans.
    let rounds = if iterations == 0 {
        0
    } else {
        warmup + iterations
    };
    let (mut rt_in_place, mut net_in_place) = (Vec::new(), Vec::new());
    for i in 0..rounds {
        let began = Instant::now();
        // Every other answer read where it arrived (each waypoint read once, none copied).
        let in_place = i % 2 == 1;
        let server_us = if in_place {
            let (sum, server_us) =
                client.plan_in_place(&request, Duration::from_secs(5), |view| {
                    view.waypoints().iter().map(|p| p.x + p.y).sum::<f32>()
                })?;
            std::hint::black_box(sum);
            server_us
        } else {
            client.plan_raw(&request, Duration::from_secs(5))?.1
        };
        let t = began.elapsed().as_secs_f64() * 1e6;
        if i >= warmup {
            let (rt, net) = if in_place {
                (&mut rt_in_place, &mut net_in_place)
            } else {
                (&mut rt, &mut net)
            };
            rt.push(t);
            net.push(t - server_us as f64);
        }
    }
    let mut updates: Vec<(&'static str, Updates)> = ["copy", "in place", "upload_map"]
        .into_iter()
        .map(|how| (how, Updates::default()))
        .collect();
    let base = frame.header.meta();
    let meta = |version| MapMeta { version, ..base };
    let (w, h) = (frame.header.width as usize, frame.header.height as usize);
    let mut version = 1;
    for _ in 0..updates_wanted {
        // The three ways in turn, so that they share the machine's state.
        for (how, samples) in &mut updates {
            version += 1;
            let (publish, began) = match *how {
                // Ready words (both layouts) copied into the loan: loan + copy + send.
                "copy" => {
                    frame.header.map_version = version;
                    let (sent, t) = timed(|| client.publish_map(&frame.header, &frame.words));
                    sent?;
                    (t, Instant::now() - Duration::from_secs_f64(t / 1e6))
                }
                // Written where it is published: the loan (zeroed) and the send are timed,
                // not the caller writing its map (a socket sender writes its own grid too).
                "in place" => {
                    let (loan, t_loan) = timed(|| client.loan_map(meta(version), w, h));
                    let mut loan = loan?;
                    let (rows, columns) = loan.words_mut();
                    let n = rows.len();
                    rows.copy_from_slice(&frame.words[..n]);
                    columns.copy_from_slice(&frame.words[n..]);
                    let began = Instant::now();
                    loan.publish()?;
                    let t = t_loan + began.elapsed().as_secs_f64() * 1e6;
                    (t, began - Duration::from_secs_f64(t_loan / 1e6))
                }
                // From a GridRef: rows by words, columns rebuilt by transposition.
                _ => {
                    let (sent, t) = timed(|| client.upload_map(meta(version), frame.grid.view()));
                    sent?;
                    (t, Instant::now() - Duration::from_secs_f64(t / 1e6))
                }
            };
            let stored = client.map_status(1, version, Duration::from_secs(5))?;
            let t = began.elapsed().as_secs_f64() * 1e6;
            samples.publish.push(publish);
            samples.full.push(t);
            samples.net.push(t - stored.decode_us as f64);
        }
    }
    Ok(IpcSamples {
        rt,
        net,
        rt_in_place,
        net_in_place,
        updates,
    })
}

fn uds_phase(case: &mut Case, busy: bool, warmup: usize) -> anyhow::Result<Samples> {
    let (frame, iterations, updates) = (&mut case.frame, case.iterations, case.updates);
    let mode = if busy { "busy" } else { "blocking" };
    let sock = std::env::temp_dir().join(format!(
        "planner-bench-{}-{}x{}-{mode}.sock",
        std::process::id(),
        frame.header.width,
        frame.header.height
    ));
    let _ = std::fs::remove_file(&sock);
    let _peer = Kill(
        Command::new(std::env::current_exe()?)
            .args(["uds-peer", sock.to_str().context("path")?, mode])
            .spawn()?,
    );
    let mut stream = connect(&sock)?;
    stream.set_nonblocking(busy)?;
    let mut buf = vec![0u8; UDS_BUFFER];
    frame.header.map_version = 1;
    uds_call(
        &mut stream,
        &UdsRequestRef::Map(MapMsgRef::new(frame)),
        &mut buf,
    )?;
    let request = case.request;
    let (mut rt, mut net) = (Vec::new(), Vec::new());
    // No warm-up either when the case times no plans.
    let rounds = if iterations == 0 {
        0
    } else {
        warmup + iterations
    };
    for i in 0..rounds {
        let began = Instant::now();
        let reply = uds_call(&mut stream, &UdsRequestRef::Plan(request), &mut buf)?;
        let t = began.elapsed().as_secs_f64() * 1e6;
        let UdsResponse::Plan(result) = reply else {
            anyhow::bail!("unexpected socket reply");
        };
        anyhow::ensure!(result.outcome.is_ok(), "socket plan failed");
        if i >= warmup {
            rt.push(t);
            net.push(t - result.time_us as f64);
        }
    }
    let mut update = Updates::default();
    for version in 2..updates as u32 + 2 {
        frame.header.map_version = version;
        let began = Instant::now();
        // The socket has to carry bytes: encoding the frame is part of publishing it.
        uds_send(
            &mut stream,
            &UdsRequestRef::Map(MapMsgRef::new(frame)),
            &mut buf,
        )?;
        let published = began.elapsed().as_secs_f64() * 1e6;
        let UdsResponse::MapTaken(decode_us) = uds_recv(&mut stream, &mut buf)? else {
            anyhow::bail!("unexpected socket reply");
        };
        let t = began.elapsed().as_secs_f64() * 1e6;
        update.publish.push(published);
        update.full.push(t);
        update.net.push(t - decode_us as f64);
    }
    drop(stream);
    let _ = std::fs::remove_file(&sock);
    Ok(Samples { rt, net, update })
}

fn connect(path: &Path) -> anyhow::Result<UnixStream> {
    let began = Instant::now();
    loop {
        match UnixStream::connect(path) {
            Ok(s) => return Ok(s),
            Err(e) if began.elapsed() > Duration::from_secs(10) => {
                return Err(e).context("socket peer did not start");
            }
            Err(_) => std::thread::sleep(Duration::from_millis(5)),
        }
    }
}

fn uds_call<S: Read + Write>(
    stream: &mut S,
    request: &UdsRequestRef<'_>,
    buf: &mut [u8],
) -> anyhow::Result<UdsResponse> {
    uds_send(stream, request, buf)?;
    uds_recv(stream, buf)
}

/// The baseline server's answer to one socket request, as planner-server would give it
/// (a map's time is that of building the grid from the received frame).
fn answer(engine: &Engine, scratch: &mut Scratch, request: UdsRequest) -> UdsResponse {
    match request {
        UdsRequest::Map(msg) => {
            let began = Instant::now();
            let grid = msg.to_grid(engine.store.max_cells());
            let decode_us = began.elapsed().as_secs_f32() * 1e6;
            engine.store.update_decoded(msg.meta, grid, decode_us);
            UdsResponse::MapTaken(decode_us)
        }
        UdsRequest::Plan(req) => UdsResponse::Plan(engine.handle(scratch, &req, &mut || false)),
    }
}

fn uds_send<T: Serialize, S: Write>(
    stream: &mut S,
    value: &T,
    buf: &mut [u8],
) -> anyhow::Result<()> {
    let (head, body) = buf.split_at_mut(4);
    let n = postcard::to_slice(value, body)?.len();
    head.copy_from_slice(&(n as u32).to_le_bytes());
    write_all_spin(stream, &buf[..4 + n])
}

fn uds_recv<T: for<'de> Deserialize<'de>, S: Read>(
    stream: &mut S,
    buf: &mut [u8],
) -> anyhow::Result<T> {
    let mut head = [0u8; 4];
    read_exact_spin(stream, &mut head)?;
    let n = u32::from_le_bytes(head) as usize;
    anyhow::ensure!(n <= buf.len(), "frame too large");
    read_exact_spin(stream, &mut buf[..n])?;
    Ok(postcard::from_bytes(&buf[..n])?)
}

/// `read_exact` that also works on a non-blocking socket (spinning on `WouldBlock`).
fn read_exact_spin<S: Read>(stream: &mut S, mut out: &mut [u8]) -> anyhow::Result<()> {
    while !out.is_empty() {
        match stream.read(out) {
            Ok(0) => anyhow::bail!("socket closed"),
            Ok(n) => out = &mut out[n..],
            Err(e) if e.kind() == ErrorKind::WouldBlock => std::hint::spin_loop(),
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(e) => return Err(e.into()),
        }
    }
    Ok(())
}

fn write_all_spin<S: Write>(stream: &mut S, mut data: &[u8]) -> anyhow::Result<()> {
    while !data.is_empty() {
        match stream.write(data) {
            Ok(n) => data = &data[n..],
            Err(e) if e.kind() == ErrorKind::WouldBlock => std::hint::spin_loop(),
            Err(e) if e.kind() == ErrorKind::Interrupted => {}
            Err(e) => return Err(e.into()),
        }
    }
    Ok(())
}

/// The socket server: the same engine as `planner-server`, one connection.
fn uds_peer(path: &Path, busy: bool) -> anyhow::Result<()> {
    let listener = UnixListener::bind(path)?;
    let (mut stream, _) = listener.accept()?;
    stream.set_nonblocking(busy)?;
    let engine = Engine::new(DEFAULT_MAX_CELLS, 4);
    let mut scratch = Scratch::default();
    let mut buf = vec![0u8; UDS_BUFFER];
    loop {
        let request: UdsRequest = match uds_recv(&mut stream, &mut buf) {
            Ok(r) => r,
            Err(_) => return Ok(()), // client closed
        };
        let reply = answer(&engine, &mut scratch, request);
        uds_send(&mut stream, &reply, &mut buf)?;
    }
}

/// Which iceoryx2 service flavour a floor measurement uses.
#[derive(Clone, Copy, Debug)]
enum Flavour {
    /// `ipc_threadsafe::Service` (what the crate uses: ports behind a mutex).
    ThreadSafe,
    /// `ipc::Service` (single-threaded ports, no mutex).
    Local,
}

impl Flavour {
    fn name(self) -> &'static str {
        match self {
            Flavour::ThreadSafe => "ts",
            Flavour::Local => "local",
        }
    }

    fn parse(text: Option<&String>) -> anyhow::Result<Self> {
        match text.map(String::as_str) {
            Some("ts") => Ok(Flavour::ThreadSafe),
            Some("local") => Ok(Flavour::Local),
            other => anyhow::bail!("flavour ts|local, got {other:?}"),
        }
    }
}

fn ice<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow::anyhow!("{e:?}")
}

fn raw_node<S: iceoryx2::service::Service>(name: &str) -> anyhow::Result<Node<S>> {
    NodeBuilder::new()
        .name(&NodeName::new(name).map_err(ice)?)
        .signal_handling_mode(SignalHandlingMode::Disabled)
        .create::<S>()
        .map_err(ice)
}

fn raw_name(prefix: &str, suffix: &str) -> anyhow::Result<ServiceName> {
    ServiceName::new(&format!("{prefix}/{suffix}")).map_err(ice)
}

/// The bare request-response service: the plan service's types, at most one request in
/// flight per client.
fn rr_service<S: iceoryx2::service::Service>(
    node: &Node<S>,
    prefix: &str,
) -> anyhow::Result<ReqRespFactory<S, PlanRequest, (), [Waypoint], PlanResponseHeader>> {
    node.service_builder(&raw_name(prefix, "plan")?)
        .request_response::<PlanRequest, [Waypoint]>()
        .response_user_header::<PlanResponseHeader>()
        .enable_safe_overflow_for_requests(false)
        .enable_safe_overflow_for_responses(false)
        .open_or_create()
        .map_err(ice)
}

/// `planner-bench echo plan|rr|ps ts|local PREFIX`: the far side of a floor measurement, for a
/// minute at most.
fn echo(args: &[String]) -> anyhow::Result<()> {
    let prefix = args.get(2).context("echo plan|rr|ps ts|local PREFIX")?;
    match (
        args.first().map(String::as_str),
        Flavour::parse(args.get(1))?,
    ) {
        (Some("plan"), Flavour::ThreadSafe) => plan_echo::<planner_ipc::services::Svc>(prefix),
        (Some("plan"), Flavour::Local) => plan_echo::<planner_ipc::services::LocalSvc>(prefix),
        (Some("rr"), Flavour::ThreadSafe) => rr_echo::<ipc_threadsafe::Service>(prefix),
        (Some("rr"), Flavour::Local) => rr_echo::<ipc::Service>(prefix),
        (Some("ps"), Flavour::ThreadSafe) => ps_echo::<ipc_threadsafe::Service>(prefix),
        (Some("ps"), Flavour::Local) => ps_echo::<ipc::Service>(prefix),
        (other, _) => anyhow::bail!("echo plan|rr|ps, got {other:?}"),
    }
}

/// The bare echo server on the plan service itself (as the server creates it).
fn plan_echo<S: iceoryx2::service::Service>(prefix: &str) -> anyhow::Result<()> {
    let node = planner_ipc::services::node::<S>("planner-bench-echo")?;
    let limits = planner_ipc::services::Limits::default();
    rr_serve(&planner_ipc::services::plan_service_create(
        &node,
        &Names::new(prefix),
        &limits,
    )?)
}

/// Answers every request at once with an empty ok header (no engine).
fn rr_echo<S: iceoryx2::service::Service>(prefix: &str) -> anyhow::Result<()> {
    let node = raw_node::<S>("planner-bench-echo")?;
    rr_serve(&rr_service(&node, prefix)?)
}

fn rr_serve<S: iceoryx2::service::Service>(
    service: &ReqRespFactory<S, PlanRequest, (), [Waypoint], PlanResponseHeader>,
) -> anyhow::Result<()> {
    let server = service
        .server_builder()
        .initial_max_slice_len(planner_ipc::services::PATH_SLICE_CAPACITY)
        .create()
        .map_err(ice)?;
    let began = Instant::now();
    while began.elapsed() < Duration::from_secs(60) {
        if let Some(active) = server.receive().map_err(ice)? {
            let header = PlanResponseHeader {
                request_id: active.payload().request_id,
                ..Default::default()
            };
            let mut r = active
                .loan_slice_uninit(0)
                .map_err(ice)?
                .write_from_fn(|_| Waypoint::default());
            *r.user_header_mut() = header;
            r.send().map_err(ice)?;
        } else {
            std::hint::spin_loop();
        }
    }
    Ok(())
}

fn rr_ping<S: iceoryx2::service::Service>(
    prefix: &str,
    iterations: usize,
) -> anyhow::Result<Vec<f64>> {
    let node = raw_node::<S>("planner-bench-rr")?;
    let service = rr_service(&node, prefix)?;
    let client = service.client_builder().create().map_err(ice)?;
    let mut request = PlanRequest::new((1, 1), [0, 0], [3, 2], Algorithm::AStar);
    let began = Instant::now();
    while service.dynamic_config().number_of_servers() == 0 {
        anyhow::ensure!(began.elapsed() < Duration::from_secs(10), "no echo server");
        std::thread::sleep(Duration::from_millis(5));
    }
    let mut rt = Vec::new();
    for i in 0..iterations + iterations / 10 {
        request.request_id = i as u64;
        let began = Instant::now();
        let pending = client.send_copy(request).map_err(ice)?;
        loop {
            if let Some(r) = pending.receive().map_err(ice)? {
                anyhow::ensure!(r.user_header().request_id == request.request_id);
                break;
            }
            anyhow::ensure!(began.elapsed() < Duration::from_secs(5), "no answer");
            std::hint::spin_loop();
        }
        drop(pending);
        if i >= iterations / 10 {
            rt.push(began.elapsed().as_secs_f64() * 1e6);
        }
    }
    Ok(rt)
}

/// The ping and pong services of the publish-subscribe floor (the request type both ways,
/// so that the same bytes travel as in a plan request).
#[allow(clippy::type_complexity)]
fn ps_services<S: iceoryx2::service::Service>(
    node: &Node<S>,
    prefix: &str,
) -> anyhow::Result<(
    PubSubFactory<S, PlanRequest, ()>,
    PubSubFactory<S, PlanRequest, ()>,
)> {
    let open = |suffix: &str| {
        node.service_builder(&raw_name(prefix, suffix)?)
            .publish_subscribe::<PlanRequest>()
            .open_or_create()
            .map_err(ice)
    };
    Ok((open("ping")?, open("pong")?))
}

/// Publishes every ping back as a pong.
fn ps_echo<S: iceoryx2::service::Service>(prefix: &str) -> anyhow::Result<()> {
    let node = raw_node::<S>("planner-bench-ps-echo")?;
    let (ping, pong) = ps_services(&node, prefix)?;
    let subscriber = ping.subscriber_builder().create().map_err(ice)?;
    let publisher = pong.publisher_builder().create().map_err(ice)?;
    let began = Instant::now();
    while began.elapsed() < Duration::from_secs(60) {
        if let Some(sample) = subscriber.receive().map_err(ice)? {
            let value = *sample.payload();
            drop(sample);
            publisher.send_copy(value).map_err(ice)?;
        } else {
            std::hint::spin_loop();
        }
    }
    Ok(())
}

fn ps_ping<S: iceoryx2::service::Service>(
    prefix: &str,
    iterations: usize,
) -> anyhow::Result<Vec<f64>> {
    let node = raw_node::<S>("planner-bench-ps")?;
    let (ping, pong) = ps_services(&node, prefix)?;
    let publisher = ping.publisher_builder().create().map_err(ice)?;
    let subscriber = pong.subscriber_builder().create().map_err(ice)?;
    let began = Instant::now();
    while ping.dynamic_config().number_of_subscribers() == 0
        || pong.dynamic_config().number_of_publishers() == 0
    {
        anyhow::ensure!(began.elapsed() < Duration::from_secs(10), "no echo");
        std::thread::sleep(Duration::from_millis(5));
    }
    let mut request = PlanRequest::new((1, 1), [0, 0], [3, 2], Algorithm::AStar);
    let mut rt = Vec::new();
    for i in 0..iterations + iterations / 10 {
        request.request_id = i as u64;
        let began = Instant::now();
        publisher.send_copy(request).map_err(ice)?;
        loop {
            match subscriber.receive().map_err(ice)? {
                Some(s) if s.payload().request_id == request.request_id => break,
                Some(_) => {}
                None => {
                    anyhow::ensure!(began.elapsed() < Duration::from_secs(5), "no pong");
                    std::hint::spin_loop();
                }
            }
        }
        if i >= iterations / 10 {
            rt.push(began.elapsed().as_secs_f64() * 1e6);
        }
    }
    Ok(rt)
}

fn atomic_ping(iterations: usize) -> Vec<f64> {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicU64, Ordering};
    let ball = Arc::new(AtomicU64::new(0));
    let other = ball.clone();
    let rounds = (iterations + iterations / 10) as u64;
    let echo = std::thread::spawn(move || {
        for i in 0..rounds {
            while other.load(Ordering::Acquire) != 2 * i + 1 {
                std::hint::spin_loop();
            }
            other.store(2 * i + 2, Ordering::Release);
        }
    });
    let mut rt = Vec::new();
    for i in 0..rounds {
        let began = Instant::now();
        ball.store(2 * i + 1, Ordering::Release);
        while ball.load(Ordering::Acquire) != 2 * i + 2 {
            std::hint::spin_loop();
        }
        if i >= rounds / 11 {
            rt.push(began.elapsed().as_secs_f64() * 1e6);
        }
    }
    let _ = echo.join();
    rt
}

/// Like [`atomic_ping`], the echo thread also writing `words` 32-bit words into a buffer the
/// pinging thread then reads: what moving an answer of that size between two cores costs
/// with no transport at all (its cache lines are written on one core, read on the other).
fn handover_ping(iterations: usize, words: usize) -> Vec<f64> {
    use std::sync::Arc;
    use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};
    let ball = Arc::new(AtomicU64::new(0));
    let buffer: Arc<Vec<AtomicU32>> = Arc::new((0..words).map(|_| AtomicU32::new(0)).collect());
    let (other, written) = (ball.clone(), buffer.clone());
    let rounds = (iterations + iterations / 10) as u64;
    let echo = std::thread::spawn(move || {
        for i in 0..rounds {
            while other.load(Ordering::Acquire) != 2 * i + 1 {
                std::hint::spin_loop();
            }
            for (k, w) in written.iter().enumerate() {
                w.store(i as u32 ^ k as u32, Ordering::Relaxed);
            }
            other.store(2 * i + 2, Ordering::Release);
        }
    });
    let mut rt = Vec::new();
    for i in 0..rounds {
        let began = Instant::now();
        ball.store(2 * i + 1, Ordering::Release);
        while ball.load(Ordering::Acquire) != 2 * i + 2 {
            std::hint::spin_loop();
        }
        let sum = buffer
            .iter()
            .fold(0u32, |a, w| a.wrapping_add(w.load(Ordering::Relaxed)));
        std::hint::black_box(sum);
        if i >= rounds / 11 {
            rt.push(began.elapsed().as_secs_f64() * 1e6);
        }
    }
    let _ = echo.join();
    rt
}

/// `planner-bench raw [N]`: the floors under the plan round trip, busy polling on both
/// sides, each against an echo process: the plan client library against a bare
/// request-response echo server, bare iceoryx2 request-response and a pair of
/// publish-subscribe services (ping and pong), each with thread-safe and single-threaded
/// ports, and two threads bouncing an atomic (what the cores alone cost), also with a
/// 1200-waypoint answer's bytes written by one and read by the other.
fn raw_floor(iterations: usize) -> anyhow::Result<()> {
    let exe = std::env::current_exe()?;
    let mut case = 0;
    let mut measure = |pattern: &str, flavour: Flavour| -> anyhow::Result<Vec<f64>> {
        case += 1;
        let prefix = format!("bench-raw-{}-{case}", std::process::id());
        let far = if pattern == "client" { "plan" } else { pattern };
        let _echo = Kill(
            Command::new(&exe)
                .args(["echo", far, flavour.name(), &prefix])
                .spawn()?,
        );
        match (pattern, flavour) {
            ("rr", Flavour::ThreadSafe) => rr_ping::<ipc_threadsafe::Service>(&prefix, iterations),
            ("rr", Flavour::Local) => rr_ping::<ipc::Service>(&prefix, iterations),
            ("ps", Flavour::ThreadSafe) => ps_ping::<ipc_threadsafe::Service>(&prefix, iterations),
            ("ps", Flavour::Local) => ps_ping::<ipc::Service>(&prefix, iterations),
            ("client", _) => {
                // The client library on the plan service, against the bare echo server.
                let mut client = PlannerClient::new(ClientConfig {
                    names: Names::new(&prefix),
                    wait: Wait::Busy,
                    notify_server: false,
                    node_name: "planner-bench-raw".into(),
                    ..ClientConfig::default()
                })?;
                let request = PlanRequest::new((1, 1), [0, 0], [3, 2], Algorithm::AStar);
                let began = Instant::now();
                while matches!(
                    client.plan_raw(&request, Duration::from_secs(5)),
                    Err(ClientError::NoServer)
                ) {
                    anyhow::ensure!(began.elapsed() < Duration::from_secs(10), "no echo server");
                    std::thread::sleep(Duration::from_millis(5));
                }
                let mut rt = Vec::new();
                for i in 0..iterations + iterations / 10 {
                    let began = Instant::now();
                    client.plan_raw(&request, Duration::from_secs(5))?;
                    if i >= iterations / 10 {
                        rt.push(began.elapsed().as_secs_f64() * 1e6);
                    }
                }
                Ok(rt)
            }
            _ => unreachable!(),
        }
    };
    let print = |what: &str, rt: &mut [f64]| {
        println!(
            "{what:<52} p50 {:>6.2} us   p99 {:>7.2} us",
            percentile(rt, 0.5),
            percentile(rt, 0.99)
        );
    };
    print(
        "plan client library -> bare echo server (local)",
        &mut measure("client", Flavour::Local)?,
    );
    for flavour in [Flavour::ThreadSafe, Flavour::Local] {
        let what = format!("bare request-response echo ({})", flavour.name());
        print(&what, &mut measure("rr", flavour)?);
        let what = format!("bare publish-subscribe ping/pong ({})", flavour.name());
        print(&what, &mut measure("ps", flavour)?);
    }
    print(
        "two threads bouncing an atomic",
        &mut atomic_ping(iterations),
    );
    print(
        "  and handing over 1200 waypoints (9.6 KB)",
        &mut handover_ping(iterations, 2 * 1200),
    );
    Ok(())
}

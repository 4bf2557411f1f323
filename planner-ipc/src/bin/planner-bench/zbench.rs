//! `planner-bench zenoh` (feature `zenoh`): the planner over Zenoh, measured.
//!
//! ```text
//! cargo build --release -p planner-ipc --features zenoh --bins
//! target/release/planner-bench zenoh [--iterations 10000] [--only rt|map|load]
//!                                    [--client-spin-us 100] [--server-spin-us 200]
//!                                    [--subscribers 8] [--versions 20]
//!                                    [--clients 32] [--plans 1000] [--workers 2]
//!                                    [--path query|pair]
//! ```
//! - `rt`: the round trip of a plan over Zenoh (query/queryable, `ZenohClient::plan_result`)
//!   against a plain TCP + postcard baseline written for the bench (blocking std sockets,
//!   `TCP_NODELAY`, a little-endian `u32` length then the postcard bytes of the same
//!   `PlanRequest` and `PlanResult`), both served by one peer process (`zenoh-peer`: the
//!   Zenoh front end and the TCP server on one engine) to this process, in alternating
//!   blocks; a trivial plan (A* (0,0)->(3,2) on 64 x 64), a 1,200-waypoint answer (9.6 KB)
//!   and a 7,800-waypoint answer (62 KB, three parts on Zenoh's low-latency transport);
//! - `map`: a 4096 x 4096 warehouse published (`ZenohClient::upload_map`) to `--subscribers`
//!   processes (`zenoh-sub`: a map session configured as a planner's, decoding each map into
//!   a grid as a planner does and acknowledging it), `--versions` times: the sender's time
//!   (packing, encoding, put) and the time until every subscriber has the grid;
//! - `load`: `--clients` processes (`zenoh-load`) each sending `--plans` requests (A* and
//!   Theta* between pseudo-random free cells of a 512 x 512 warehouse) to one
//!   `planner-server --transport zenoh --workers W`, each answer compared with the engine
//!   run in the client process: lost (no answer) and mismatched (another answer) must be 0.

use super::{
    Kill, MapMsgRef, UDS_BUFFER, UdsRequest, UdsRequestRef, UdsResponse, answer, percentile,
    uds_call, uds_recv, uds_send, warehouse,
};
use ::zenoh::Wait;
use anyhow::Context;
use planner_core::grid::GridBuf;
use planner_ipc::engine::{Engine, Scratch};
use planner_ipc::wire::{
    Algorithm, DEFAULT_MAX_CELLS, MapMeta, MapMsg, PlanRequest, PlanResult, pack_map,
};
use planner_ipc::zenoh::config::{self, SessionKind, free_port_pair};
use planner_ipc::zenoh::{ClientConfig, Mode, RequestPath, ZenohClient, ZenohError, ZenohOptions};
use std::collections::BTreeMap;
use std::io::{BufRead, BufReader};
use std::net::{TcpListener, TcpStream};
use std::process::{Command, Stdio};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// The service prefix of the bench's processes.
fn bench_prefix() -> String {
    format!("zbench-{}", std::process::id())
}

fn endpoint(port: u16) -> String {
    format!("tcp/127.0.0.1:{port}")
}

/// Dispatches `planner-bench zenoh*`.
pub fn main(args: &[String]) -> anyhow::Result<()> {
    let arg = |i: usize| -> anyhow::Result<&str> {
        args.get(i)
            .map(String::as_str)
            .with_context(|| format!("{}: missing argument {i}", args[0]))
    };
    match args[0].as_str() {
        "zenoh-peer" => peer(arg(1)?.parse()?, arg(2)?, arg(3)?, arg(4)?.parse()?),
        "zenoh-sub" => subscriber(arg(1)?.parse()?, arg(2)?, arg(3)?),
        "zenoh-load" => load_client(
            arg(1)?,
            arg(2)?,
            arg(3)?.parse()?,
            arg(4)?.parse()?,
            arg(5)? == "pair",
        ),
        "zenoh" => {
            let value = |name: &str| -> anyhow::Result<Option<&String>> {
                match args.iter().position(|a| a == name) {
                    Some(i) => Ok(Some(
                        args.get(i + 1).with_context(|| format!("{name} VALUE"))?,
                    )),
                    None => Ok(None),
                }
            };
            let number = |name: &str, default: usize| -> anyhow::Result<usize> {
                Ok(value(name)?.map_or(Ok(default), |v| v.parse())?)
            };
            let only = value("--only")?.map(String::as_str);
            if only.is_none_or(|o| o == "rt") {
                let spin = |name: &str, default: usize| -> anyhow::Result<Duration> {
                    Ok(Duration::from_micros(number(name, default)? as u64))
                };
                round_trips(
                    number("--iterations", 10_000)?,
                    spin("--client-spin-us", 100)?,
                    spin("--server-spin-us", 200)?,
                )?;
            }
            if only.is_none_or(|o| o == "map") {
                map_distribution(number("--subscribers", 8)?, number("--versions", 20)?)?;
            }
            if only.is_none_or(|o| o == "load") {
                load(
                    number("--clients", 32)?,
                    number("--plans", 1000)?,
                    number("--workers", 2)?,
                    value("--path")?.is_some_and(|p| p == "pair"),
                )?;
            }
            Ok(())
        }
        other => anyhow::bail!("unknown command {other}"),
    }
}

fn zclient(prefix: &str, mode: Mode, connect: Vec<String>) -> anyhow::Result<ZenohClient> {
    zclient_on(prefix, mode, connect, RequestPath::Query)
}

fn zclient_on(
    prefix: &str,
    mode: Mode,
    connect: Vec<String>,
    path: RequestPath,
) -> anyhow::Result<ZenohClient> {
    zclient_spinning(prefix, mode, connect, path, ClientConfig::default().spin)
}

fn zclient_spinning(
    prefix: &str,
    mode: Mode,
    connect: Vec<String>,
    path: RequestPath,
    spin: Duration,
) -> anyhow::Result<ZenohClient> {
    Ok(ZenohClient::open(ClientConfig {
        prefix: prefix.to_string(),
        path,
        spin,
        options: ZenohOptions {
            mode,
            connect,
            ..ZenohOptions::default()
        },
        ..ClientConfig::default()
    })?)
}

fn wait_for_planner(client: &mut ZenohClient) -> anyhow::Result<()> {
    let began = Instant::now();
    while let Err(e) = client.check_planners() {
        if began.elapsed() > Duration::from_secs(20) {
            anyhow::bail!("no planner after 20 s: {e}");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    Ok(())
}

fn meta(map_id: u32, version: u32) -> MapMeta {
    MapMeta {
        map_id,
        version,
        resolution: 0.05,
        origin: [0.0, 0.0],
    }
}

/// The peer process of the round trips: the Zenoh front end (plan endpoint `zenoh`) and a
/// TCP + postcard server on `tcp_port`, one engine.
fn peer(tcp_port: u16, zenoh: &str, prefix: &str, spin_us: u64) -> anyhow::Result<()> {
    // The floor: a session of the plan session's settings on the next port but one, echoing
    // `bench/echo/inline` from Zenoh's thread and `bench/echo/thread` from a thread of ours.
    let echo_ep = config::next_port(&config::next_port(zenoh)?)?;
    let echo_options = ZenohOptions {
        listen: vec![echo_ep],
        ..ZenohOptions::default()
    };
    let echo = ::zenoh::open(config::session_config(&echo_options, SessionKind::Plan)?)
        .wait()
        .map_err(anyhow::Error::msg)?;
    let back = echo
        .declare_publisher("bench/echo/back")
        .wait()
        .map_err(anyhow::Error::msg)?;
    let _inline = echo
        .declare_subscriber("bench/echo/inline")
        .callback(move |sample| {
            let _ = back.put(sample.payload().clone()).wait();
        })
        .wait()
        .map_err(anyhow::Error::msg)?;
    let (tx, rx) = std::sync::mpsc::channel::<::zenoh::bytes::ZBytes>();
    let _threaded = echo
        .declare_subscriber("bench/echo/thread")
        .callback(move |sample| {
            let _ = tx.send(sample.payload().clone());
        })
        .wait()
        .map_err(anyhow::Error::msg)?;
    let back2 = echo
        .declare_publisher("bench/echo/back")
        .wait()
        .map_err(anyhow::Error::msg)?;
    std::thread::spawn(move || {
        while let Ok(payload) = rx.recv() {
            let _ = back2.put(payload).wait();
        }
    });
    let engine = Arc::new(Engine::new(DEFAULT_MAX_CELLS, 16));
    let shutdown = Arc::new(std::sync::atomic::AtomicBool::new(false));
    let config = planner_ipc::zenoh::server::ServerConfig {
        prefix: prefix.to_string(),
        options: ZenohOptions {
            listen: vec![zenoh.to_string()],
            ..ZenohOptions::default()
        },
        spin: Duration::from_micros(spin_us),
        ..Default::default()
    };
    {
        let engine = engine.clone();
        std::thread::spawn(move || {
            if let Err(e) = planner_ipc::zenoh::server::run(&config, engine, shutdown) {
                eprintln!("zenoh-peer: {e:#}");
                std::process::exit(1);
            }
        });
    }
    let listener = TcpListener::bind(("127.0.0.1", tcp_port))?;
    // One connection at a time, like the socket peer of the iceoryx2 rows; the process
    // ends when its parent kills it.
    for stream in listener.incoming() {
        let mut stream = stream?;
        stream.set_nodelay(true)?;
        let mut scratch = Scratch::default();
        let mut buf = vec![0u8; UDS_BUFFER];
        while let Ok(request) = uds_recv::<UdsRequest, _>(&mut stream, &mut buf) {
            let reply = answer(&engine, &mut scratch, request);
            if uds_send(&mut stream, &reply, &mut buf).is_err() {
                break;
            }
        }
    }
    Ok(())
}

/// A corridor winding through a `w x h` map (walls on odd rows, open at alternate ends): A*
/// lists every cell, so its answer is long.
fn serpentine(w: usize, h: usize) -> GridBuf {
    let mut g = GridBuf::new(w, h).expect("serpentine size");
    for y in (1..h).step_by(2) {
        let gap = if (y / 2) % 2 == 0 { w - 1 } else { 0 };
        for x in (0..w).filter(|&x| x != gap) {
            let _ = g.set_blocked(x, y, true);
        }
    }
    g
}

fn row(what: &str, tcp: &mut [f64], query: &mut [f64], pair: &mut [f64]) {
    let (t50, t99) = (percentile(tcp, 0.5), percentile(tcp, 0.99));
    let (q50, q99) = (percentile(query, 0.5), percentile(query, 0.99));
    let (p50, p99) = (percentile(pair, 0.5), percentile(pair, 0.99));
    println!(
        "{what:<36} {t50:>7.1}us {t99:>7.1}us {q50:>7.1}us {q99:>7.1}us {p50:>7.1}us {p99:>7.1}us {:>6.2} {:>6.2}",
        q50 / t50,
        p50 / t50
    );
}

/// Plan round trips over Zenoh and over TCP + postcard, one peer process, same requests;
/// the Zenoh client and planner poll for `client_spin` and `server_spin` before sleeping.
fn round_trips(
    iterations: usize,
    client_spin: Duration,
    server_spin: Duration,
) -> anyhow::Result<()> {
    let prefix = bench_prefix();
    let (tcp_port, zport) = (free_port_pair()?, free_port_pair()?);
    let _peer = Kill(
        Command::new(std::env::current_exe()?)
            .args([
                "zenoh-peer",
                &tcp_port.to_string(),
                &endpoint(zport),
                &prefix,
            ])
            .arg(server_spin.as_micros().to_string())
            .stdout(Stdio::null())
            .spawn()?,
    );
    let began = Instant::now();
    let mut tcp = loop {
        match TcpStream::connect(("127.0.0.1", tcp_port)) {
            Ok(s) => break s,
            Err(e) if began.elapsed() > Duration::from_secs(20) => {
                return Err(e).context("the zenoh-peer's TCP server did not start");
            }
            Err(_) => std::thread::sleep(Duration::from_millis(10)),
        }
    };
    tcp.set_nodelay(true)?;
    let mut z = zclient(&prefix, Mode::Peer, vec![endpoint(zport)])?;
    wait_for_planner(&mut z)?;
    let mut zp = zclient_on(
        &prefix,
        Mode::Peer,
        vec![endpoint(zport)],
        RequestPath::Pair,
    )?;
    wait_for_planner(&mut zp)?;
    let mut buf = vec![0u8; UDS_BUFFER];
    println!(
        "planner-bench zenoh: plan round trips, one peer process serving all three (Zenoh: low-latency transport, one runtime worker, client polling {} us and planner {} us before sleeping; query = query/queryable, pair = publish-subscribe request/answer; TCP: blocking std socket, TCP_NODELAY, u32 length + postcard)",
        client_spin.as_micros(),
        server_spin.as_micros()
    );
    println!(
        "{:<36} {:>9} {:>9} {:>9} {:>9} {:>9} {:>9} {:>6} {:>6}",
        "what",
        "tcp p50",
        "tcp p99",
        "query p50",
        "query p99",
        "pair p50",
        "pair p99",
        "q/tcp",
        "p/tcp"
    );
    let cases: Vec<(&str, GridBuf, PlanRequest, usize)> = vec![
        (
            "64x64, trivial plan",
            GridBuf::new(64, 64).map_err(anyhow::Error::msg)?,
            PlanRequest::new((1, 1), [0, 0], [3, 2], Algorithm::AStar),
            iterations,
        ),
        (
            "1200x1200, 1200 waypoints (9.6 KB)",
            GridBuf::new(1200, 1200).map_err(anyhow::Error::msg)?,
            PlanRequest::new((1, 1), [0, 0], [1199, 1199], Algorithm::AStar),
            iterations / 5,
        ),
        (
            "128x121 serpentine, 7808 waypoints",
            serpentine(128, 121),
            PlanRequest::new((1, 1), [0, 0], [0, 120], Algorithm::AStar),
            iterations / 10,
        ),
    ];
    let mut t_trivial = Vec::new();
    for (version, (name, grid, mut request, n)) in (1u32..).zip(cases) {
        // One map version per case, stored once in the engine both front ends serve.
        let mut words = Vec::new();
        let header = pack_map(meta(1, version), grid.view(), &mut words);
        let msg = MapMsgRef {
            meta: header.meta(),
            width: header.width,
            height: header.height,
            bits: &words,
        };
        uds_call(&mut tcp, &UdsRequestRef::Map(msg), &mut buf)?;
        z.wait_for_map(1, version, Duration::from_secs(10))?;
        request.map_version = version;
        let (mut t_rt, mut t_net, mut z_rt, mut z_net) = (vec![], vec![], vec![], vec![]);
        let (mut p_rt, mut p_net) = (vec![], vec![]);
        let blocks = 10;
        let warmup = n / 10 + 10;
        for block in 0..=blocks {
            let count = if block == 0 { warmup } else { n / blocks };
            for _ in 0..count {
                let t0 = Instant::now();
                let reply = uds_call(&mut tcp, &UdsRequestRef::Plan(request), &mut buf)?;
                let t = t0.elapsed().as_secs_f64() * 1e6;
                let UdsResponse::Plan(result) = reply else {
                    anyhow::bail!("unexpected TCP reply");
                };
                anyhow::ensure!(
                    result.outcome.is_ok(),
                    "TCP plan failed: {:?}",
                    result.outcome
                );
                if block > 0 {
                    t_rt.push(t);
                    t_net.push(t - result.time_us as f64);
                }
            }
            for (client, rt, net) in [
                (&mut z, &mut z_rt, &mut z_net),
                (&mut zp, &mut p_rt, &mut p_net),
            ] {
                for _ in 0..count {
                    let t0 = Instant::now();
                    let result = client.plan_result(&request, Duration::from_secs(5))?;
                    let t = t0.elapsed().as_secs_f64() * 1e6;
                    anyhow::ensure!(
                        result.outcome.is_ok(),
                        "Zenoh plan failed: {:?}",
                        result.outcome
                    );
                    if block > 0 {
                        rt.push(t);
                        net.push(t - result.time_us as f64);
                    }
                }
            }
        }
        row(name, &mut t_rt, &mut z_rt, &mut p_rt);
        row("  of which transport", &mut t_net, &mut z_net, &mut p_net);
        if t_trivial.is_empty() {
            t_trivial = t_rt;
        }
    }
    println!("q/tcp, p/tcp = Zenoh p50 / TCP p50 (goal for the trivial plan: <= 3)");
    echo_floor(zport, iterations, &mut t_trivial)?;
    Ok(())
}

/// The floor under the pair: a 64-byte message echoed by the peer's echo session, from
/// Zenoh's own thread (no planning possible there) and handed to a thread of its own (what
/// a planner must do), against the trivial plan's TCP round trips.
fn echo_floor(zport: u16, iterations: usize, tcp: &mut [f64]) -> anyhow::Result<()> {
    let echo_ep = config::next_port(&config::next_port(&endpoint(zport))?)?;
    let options = ZenohOptions {
        connect: vec![echo_ep],
        ..ZenohOptions::default()
    };
    let session = ::zenoh::open(config::session_config(&options, SessionKind::Plan)?)
        .wait()
        .map_err(anyhow::Error::msg)?;
    let answers = session
        .declare_subscriber("bench/echo/back")
        .with(::zenoh::handlers::FifoChannel::new(16))
        .wait()
        .map_err(anyhow::Error::msg)?;
    let t50 = percentile(tcp, 0.5);
    for (what, key) in [
        ("echo from Zenoh's thread", "bench/echo/inline"),
        ("echo handed to a thread", "bench/echo/thread"),
    ] {
        let publisher = session
            .declare_publisher(key)
            .wait()
            .map_err(anyhow::Error::msg)?;
        std::thread::sleep(Duration::from_millis(300));
        let mut t = Vec::with_capacity(iterations);
        for i in 0..iterations + iterations / 10 {
            let t0 = Instant::now();
            publisher
                .put(vec![7u8; 64])
                .wait()
                .map_err(anyhow::Error::msg)?;
            answers
                .recv_timeout(Duration::from_secs(5))
                .map_err(anyhow::Error::msg)?
                .context("no echo")?;
            if i >= iterations / 10 {
                t.push(t0.elapsed().as_secs_f64() * 1e6);
            }
        }
        let (e50, e99) = (percentile(&mut t, 0.5), percentile(&mut t, 0.99));
        println!(
            "floor: pub/sub {what:<26} p50 {e50:>7.1}us p99 {e99:>7.1}us  {:.2} x the TCP plan p50",
            e50 / t50
        );
    }
    Ok(())
}

/// A subscriber of the map distribution: a map session as a planner's, listening on
/// `listen`; every map decoded into a grid, then acknowledged on `bench/ack/<index>`
/// (`version decode_us` as text).
fn subscriber(index: usize, listen: &str, prefix: &str) -> anyhow::Result<()> {
    let options = ZenohOptions {
        map_listen: Some(vec![listen.to_string()]),
        map_connect: Some(Vec::new()),
        ..ZenohOptions::default()
    };
    let mut zconfig = config::session_config(&options, SessionKind::Map)?;
    config::set_max_message_size(
        &mut zconfig,
        planner_ipc::zenoh::proto::map_message_limit(DEFAULT_MAX_CELLS),
    )?;
    let session = ::zenoh::open(zconfig).wait().map_err(anyhow::Error::msg)?;
    let acks = session
        .declare_publisher(format!("bench/ack/{index}"))
        .wait()
        .map_err(anyhow::Error::msg)?;
    let subscriber = session
        .declare_subscriber(planner_ipc::zenoh::Keys::new(prefix)?.maps())
        .wait()
        .map_err(anyhow::Error::msg)?;
    println!("ready");
    while let Ok(sample) = subscriber.recv() {
        let began = Instant::now();
        let msg: MapMsg = postcard::from_bytes(&sample.payload().to_bytes())?;
        let grid = msg.to_grid(DEFAULT_MAX_CELLS);
        let decode_us = began.elapsed().as_secs_f64() * 1e6;
        anyhow::ensure!(grid.is_ok(), "map {:?}: {:?}", msg.meta, grid.err());
        acks.put(format!("{} {decode_us:.0}", msg.meta.version))
            .wait()
            .map_err(anyhow::Error::msg)?;
    }
    Ok(())
}

/// A 4096 x 4096 map published to `subscribers` processes, `versions` times.
fn map_distribution(subscribers: usize, versions: usize) -> anyhow::Result<()> {
    let prefix = bench_prefix();
    let mut subs = Vec::new();
    let mut endpoints = Vec::new();
    for i in 0..subscribers {
        let ep = endpoint(free_port_pair()?);
        let mut child = Command::new(std::env::current_exe()?)
            .args(["zenoh-sub", &i.to_string(), &ep, &prefix])
            .stdout(Stdio::piped())
            .spawn()?;
        let mut line = String::new();
        BufReader::new(child.stdout.take().context("subscriber stdout")?).read_line(&mut line)?;
        anyhow::ensure!(line.trim() == "ready", "subscriber {i} did not start");
        subs.push(Kill(child));
        endpoints.push(ep);
    }
    // The publisher: the client library's map session, connected to every subscriber.
    let mut client = ZenohClient::open(ClientConfig {
        prefix: prefix.clone(),
        options: ZenohOptions {
            map_connect: Some(endpoints.clone()),
            ..ZenohOptions::default()
        },
        ..ClientConfig::default()
    })?;
    // Acknowledgements, on a session of the map network of its own.
    let options = ZenohOptions {
        map_connect: Some(endpoints),
        ..ZenohOptions::default()
    };
    let acks_session = ::zenoh::open(config::session_config(&options, SessionKind::Map)?)
        .wait()
        .map_err(anyhow::Error::msg)?;
    let acks = acks_session
        .declare_subscriber("bench/ack/*")
        .wait()
        .map_err(anyhow::Error::msg)?;
    let grid = warehouse(4096, 4096);
    let mut words = Vec::new();
    let header = pack_map(meta(1, 1), grid.view(), &mut words);
    let bytes = postcard::to_allocvec(&MapMsg::new(&header, &words))?.len();
    println!(
        "planner-bench zenoh: a 4096 x 4096 warehouse ({bytes} bytes as a postcard map message) to {subscribers} subscriber processes, {versions} versions (map session: default transport, congestion control Drop)"
    );
    // Encoding alone (what the sender does before the put), p50 of 5.
    let mut encode: Vec<f64> = (0..5)
        .map(|_| {
            let t0 = Instant::now();
            let header = pack_map(meta(1, 1), grid.view(), &mut words);
            let bytes = postcard::to_allocvec(&MapMsg::new(&header, &words)).map(|b| b.len());
            std::hint::black_box(bytes.ok());
            t0.elapsed().as_secs_f64() * 1e3
        })
        .collect();
    // An untimed version 0 opens the map session and lets the declarations meet.
    client.upload_map(meta(1, 0), grid.view())?;
    std::thread::sleep(Duration::from_millis(500));
    while acks.try_recv().map_err(anyhow::Error::msg)?.is_some() {}
    let (mut sender, mut all, mut first, mut decode) = (vec![], vec![], vec![], vec![]);
    let mut lost = 0;
    for version in 1..=versions as u32 {
        let t0 = Instant::now();
        client.upload_map(meta(1, version), grid.view())?;
        sender.push(t0.elapsed().as_secs_f64() * 1e3);
        let mut got: BTreeMap<String, f64> = BTreeMap::new();
        let deadline = t0 + Duration::from_secs(10);
        while got.len() < subscribers {
            match acks.recv_deadline(deadline) {
                Ok(Some(sample)) => {
                    let text = sample.payload().try_to_string()?.into_owned();
                    let mut parts = text.split(' ');
                    let v: u32 = parts.next().unwrap_or("0").parse()?;
                    let us: f64 = parts.next().unwrap_or("0").parse()?;
                    if v == version {
                        let t = t0.elapsed().as_secs_f64() * 1e3;
                        if got.is_empty() {
                            first.push(t);
                        }
                        got.insert(sample.key_expr().as_str().to_string(), t);
                        decode.push(us / 1e3);
                    }
                }
                _ => break,
            }
        }
        lost += subscribers - got.len();
        if got.len() == subscribers {
            all.push(t0.elapsed().as_secs_f64() * 1e3);
        }
        // Space the versions out: a map every 200 ms at most.
        std::thread::sleep(Duration::from_millis(200).saturating_sub(t0.elapsed()));
    }
    let p = |v: &mut Vec<f64>| {
        if v.is_empty() {
            (f64::NAN, f64::NAN)
        } else {
            (percentile(v, 0.5), percentile(v, 0.99))
        }
    };
    let ((s50, s99), (f50, f99), (a50, a99), (d50, d99)) =
        (p(&mut sender), p(&mut first), p(&mut all), p(&mut decode));
    println!("  sender (pack, encode, put)          p50 {s50:>8.2} ms  p99 {s99:>8.2} ms");
    println!(
        "    of which packing and encoding     p50 {:>8.2} ms",
        percentile(&mut encode, 0.5)
    );
    println!("  first subscriber has the grid       p50 {f50:>8.2} ms  p99 {f99:>8.2} ms");
    println!(
        "  all {subscribers} subscribers have the grid     p50 {a50:>8.2} ms  p99 {a99:>8.2} ms"
    );
    println!("  of which a subscriber's decoding    p50 {d50:>8.2} ms  p99 {d99:>8.2} ms");
    println!(
        "  delivered {} of {} (subscriber, version) pairs; lost {lost} (a planner fetches a missed version from the owner)",
        versions * subscribers - lost,
        versions * subscribers
    );
    drop(subs);
    Ok(())
}

/// One load client: `count` requests to the planner at `endpoint`, each answer checked
/// against the engine run here; prints one JSON line.
fn load_client(
    endpoint: &str,
    prefix: &str,
    seed: u64,
    count: usize,
    pair: bool,
) -> anyhow::Result<()> {
    let grid = warehouse(512, 512);
    let local = Engine::new(DEFAULT_MAX_CELLS, 4);
    local.store.update(meta(1, 1), Ok(grid.clone()));
    let mut scratch = Scratch::default();
    let path = if pair {
        RequestPath::Pair
    } else {
        RequestPath::Query
    };
    let mut z = zclient_on(prefix, Mode::Client, vec![endpoint.to_string()], path)?;
    wait_for_planner(&mut z)?;
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        state
    };
    let free_cell = |next: &mut dyn FnMut() -> u64| loop {
        let (x, y) = ((next() % 512) as i32, (next() % 512) as i32);
        if !grid.view().is_blocked(x as isize, y as isize) {
            return [x, y];
        }
    };
    let (mut ok, mut mismatched, mut lost) = (0usize, 0usize, 0usize);
    let mut errors: BTreeMap<&'static str, usize> = BTreeMap::new();
    let mut rt = Vec::with_capacity(count);
    for i in 0..count {
        let algo = if i % 2 == 0 {
            Algorithm::AStar
        } else {
            Algorithm::ThetaStar
        };
        let mut request =
            PlanRequest::new((1, 1), free_cell(&mut next), free_cell(&mut next), algo);
        let t0 = Instant::now();
        match z.plan_result(&request, Duration::from_secs(10)) {
            Ok(got) => {
                rt.push(t0.elapsed().as_secs_f64() * 1e6);
                request.request_id = got.request_id;
                request.deadline_us = 10_000_000;
                let want: PlanResult = local.handle(&mut scratch, &request, &mut || false);
                if got.outcome == want.outcome {
                    ok += 1;
                } else {
                    mismatched += 1;
                }
            }
            Err(ZenohError::Mismatch { .. }) => mismatched += 1,
            Err(e) => {
                lost += 1;
                *errors.entry(e.name()).or_default() += 1;
            }
        }
    }
    println!(
        "{}",
        serde_json::json!({"ok": ok, "mismatched": mismatched, "lost": lost, "errors": errors, "rt_us": rt})
    );
    Ok(())
}

/// `clients` processes x `plans` requests against one `planner-server --transport zenoh`.
fn load(clients: usize, plans: usize, workers: usize, pair: bool) -> anyhow::Result<()> {
    let prefix = bench_prefix();
    let port = free_port_pair()?;
    let exe_dir = std::env::current_exe()?
        .parent()
        .context("no exe dir")?
        .to_path_buf();
    let _server = Kill(
        Command::new(exe_dir.join("planner-server"))
            .args(["--prefix", &prefix, "--transport", "zenoh", "--listen", &endpoint(port)])
            .args(["--workers", &workers.to_string()])
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .context("cannot start planner-server (cargo build --release -p planner-ipc --features zenoh --bins)")?,
    );
    // The map's owner: this process (its queryable answers planners that missed it).
    let mut owner = zclient(&prefix, Mode::Peer, vec![endpoint(port)])?;
    wait_for_planner(&mut owner)?;
    owner.upload_map(meta(1, 1), warehouse(512, 512).view())?;
    owner.wait_for_map(1, 1, Duration::from_secs(10))?;
    println!(
        "planner-bench zenoh: {clients} client processes (client mode, {}) x {plans} plans (A* and Theta* between random free cells of a 512 x 512 warehouse), planner-server --workers {workers}",
        if pair {
            "publish-subscribe pair"
        } else {
            "queries"
        }
    );
    let began = Instant::now();
    let children: Vec<_> = (0..clients)
        .map(|i| {
            Command::new(std::env::current_exe()?)
                .args(["zenoh-load", &endpoint(port), &prefix, &(i + 1).to_string()])
                .arg(plans.to_string())
                .arg(if pair { "pair" } else { "query" })
                .stdout(Stdio::piped())
                .spawn()
                .map(Kill)
        })
        .collect::<std::io::Result<_>>()?;
    let (mut ok, mut mismatched, mut lost) = (0u64, 0u64, 0u64);
    let mut rt: Vec<f64> = Vec::new();
    let mut errors: BTreeMap<String, u64> = BTreeMap::new();
    for mut child in children {
        let mut out = String::new();
        if let Some(stdout) = child.0.stdout.take() {
            BufReader::new(stdout).read_line(&mut out)?;
        }
        let status = child.0.wait()?;
        anyhow::ensure!(status.success(), "a load client failed: {status}");
        let v: serde_json::Value = serde_json::from_str(&out)?;
        ok += v["ok"].as_u64().unwrap_or(0);
        mismatched += v["mismatched"].as_u64().unwrap_or(0);
        lost += v["lost"].as_u64().unwrap_or(0);
        if let Some(e) = v["errors"].as_object() {
            for (name, n) in e {
                *errors.entry(name.clone()).or_default() += n.as_u64().unwrap_or(0);
            }
        }
        if let Some(a) = v["rt_us"].as_array() {
            rt.extend(a.iter().filter_map(|x| x.as_f64()));
        }
    }
    let wall = began.elapsed().as_secs_f64();
    let total = clients * plans;
    if rt.is_empty() {
        rt.push(f64::NAN);
    }
    println!(
        "  {total} requests in {wall:.1} s ({:.0} plans/s): {ok} correct, {lost} lost {errors:?}, {mismatched} mismatched; round trip p50 {:.0} us, p99 {:.0} us",
        total as f64 / wall,
        percentile(&mut rt, 0.5),
        percentile(&mut rt, 0.99)
    );
    anyhow::ensure!(
        lost == 0 && mismatched == 0 && ok == total as u64,
        "load: {lost} lost, {mismatched} mismatched of {total}"
    );
    Ok(())
}

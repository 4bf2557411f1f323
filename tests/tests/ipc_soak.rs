//! Soak (not in CI): mixed load against one server for `PLANNER_SOAK_SECS` (default 1800)
//! while the server's resident memory (`VmRSS` of `/proc/PID/status`) and open file
//! descriptors (`/proc/PID/fd`) are sampled every `PLANNER_SOAK_SAMPLE_SECS` (default 30).
//!
//! Load, kept low (the machine is shared): two client processes at a time, each living
//! `PLANNER_SOAK_CLIENT_SECS` (default 20) and then replaced by a new one (client churn;
//! every fourth is SIGKILLed mid-run instead), one sending A*/Theta* requests, the other
//! cycling through every planner with small swarm settings, every answer checked against
//! the local engine; meanwhile this process uploads new versions of three more maps
//! (random 64 x 64 grids) every few seconds and plans on them.
//!
//! ```sh
//! cargo test -p integration-tests --release --test ipc_soak -- --ignored --nocapture
//! ```
//!
//! Fails on a mismatched or unexpected answer, or when memory or descriptors grow: the last
//! sample may not exceed the first by more than 50 % + 16 MiB of RSS or 16 descriptors.

mod common;

use common::*;
use planner_ipc::wire::{Algorithm, PlanRequest};
use std::time::{Duration, Instant};

fn env_secs(name: &str, default: f64) -> Duration {
    Duration::from_secs_f64(
        std::env::var(name)
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or(default),
    )
}

#[derive(Clone, Copy, Debug)]
struct Sample {
    t: f64,
    rss_kb: u64,
    fds: usize,
}

fn sample(pid: u32, t: f64) -> Sample {
    let status = std::fs::read_to_string(format!("/proc/{pid}/status")).unwrap();
    let rss_kb = status
        .lines()
        .find_map(|l| l.strip_prefix("VmRSS:"))
        .and_then(|v| v.trim().trim_end_matches("kB").trim().parse().ok())
        .unwrap();
    let fds = std::fs::read_dir(format!("/proc/{pid}/fd"))
        .unwrap()
        .count();
    Sample { t, rss_kb, fds }
}

/// The server's open descriptors, grouped by target with the numbers of iceoryx2 ids
/// blanked out, most frequent first.
fn fd_targets(pid: u32) -> String {
    let mut groups: std::collections::BTreeMap<String, usize> = Default::default();
    for e in std::fs::read_dir(format!("/proc/{pid}/fd"))
        .unwrap()
        .flatten()
    {
        let target = std::fs::read_link(e.path())
            .map(|t| t.display().to_string())
            .unwrap_or_default();
        let key: String = target
            .chars()
            .map(|c| if c.is_ascii_digit() { '#' } else { c })
            .collect();
        *groups.entry(key).or_default() += 1;
    }
    let mut v: Vec<_> = groups.into_iter().collect();
    v.sort_by_key(|e| std::cmp::Reverse(e.1));
    v.iter()
        .map(|(k, n)| format!("{n:5} {k}"))
        .collect::<Vec<_>>()
        .join("\n")
}

struct Driver {
    proc: Proc,
    began: Instant,
    kill_early: bool,
}

#[test]
#[ignore = "30-minute soak; run by hand"]
fn soak_mixed_load() {
    let total = env_secs("PLANNER_SOAK_SECS", 1800.0);
    let every = env_secs("PLANNER_SOAK_SAMPLE_SECS", 30.0);
    let client_secs = env_secs("PLANNER_SOAK_CLIENT_SECS", 20.0);
    let p = prefix("soak");
    let dir = scratch_dir(&p);
    let server = start_server(&p, &["--workers", "2"]);
    let pid = server.child.id();
    let map = data("random-32-32-10.map");
    let mut c = client(&p);
    let v = c.upload_map_file(&map, 1).unwrap();
    c.wait_for_map(1, v, Duration::from_secs(5)).unwrap();
    let (map_text, v_text) = (map.to_str().unwrap().to_string(), v.to_string());
    let secs_text = client_secs.as_secs_f64().to_string();

    let mut rng = 0x2545_F491_4F6C_DD1Du64;
    let mut next = move || {
        rng ^= rng >> 12;
        rng ^= rng << 25;
        rng ^= rng >> 27;
        rng.wrapping_mul(0x2545_F491_4F6C_DD1D)
    };
    let began = Instant::now();
    let mut spawned = 0u64;
    let spawn = |spawned: &mut u64| {
        *spawned += 1;
        let planners = if spawned.is_multiple_of(2) {
            "all"
        } else {
            "search"
        };
        Driver {
            proc: driver(&[
                "churn",
                &p,
                &map_text,
                "1",
                &v_text,
                &secs_text,
                &spawned.to_string(),
                planners,
                "5",
            ]),
            began: Instant::now(),
            kill_early: spawned.is_multiple_of(4),
        }
    };
    let mut drivers = vec![spawn(&mut spawned), spawn(&mut spawned)];
    let mut samples = vec![sample(pid, 0.0)];
    eprintln!(
        "soak sample t=0s rss_kb={} fds={}",
        samples[0].rss_kb, samples[0].fds
    );
    let (mut finished, mut killed, mut answered, mut uploads) = (0u64, 0u64, 0u64, 0u64);
    let mut next_sample = every;
    let mut next_upload = Duration::ZERO;
    while began.elapsed() < total {
        // Client churn.
        for d in drivers.iter_mut() {
            let early = d.kill_early && d.began.elapsed() > client_secs / 3;
            let done = matches!(d.proc.child.try_wait(), Ok(Some(_)));
            if early {
                d.proc.kill();
                killed += 1;
            } else if done {
                let out = driver_output(&mut d.proc, Duration::from_secs(5));
                let s: serde_json::Value = serde_json::from_str(out.trim()).unwrap();
                let n = |k: &str| s[k].as_u64().unwrap();
                assert_eq!(n("mismatched"), 0, "{s}");
                assert_eq!(n("unexpected"), 0, "{s}");
                assert_eq!(n("outage"), 0, "{s}");
                answered += n("ok");
                finished += 1;
            } else {
                continue;
            }
            *d = spawn(&mut spawned);
        }
        // Map uploads: a new version of one of three random maps, then a plan on it.
        if began.elapsed() >= next_upload {
            next_upload += Duration::from_secs(4);
            let id = 2 + (uploads % 3) as u32;
            let file = dir.join(format!("soak-{id}.map"));
            let r = next();
            write_map(&file, 64, 64, |x, y| {
                (x * 31 + y * 17 + r as usize).is_multiple_of(11)
                    && (x, y) != (0, 0)
                    && (x, y) != (63, 63)
            });
            let version = c.upload_map_file(&file, id).unwrap();
            c.wait_for_map(id, version, Duration::from_secs(5)).unwrap();
            let algo = Algorithm::ALL[(r % Algorithm::ALL.len() as u64) as usize];
            let mut request = PlanRequest::new((id, version), [0, 0], [63, 63], algo);
            request.params.population = 8;
            request.params.iterations = 10;
            request.seed = r;
            match c.plan(&request, Duration::from_secs(5)) {
                Ok(_) | Err(planner_ipc::client::ClientError::Plan(_)) => {}
                Err(e) => panic!("plan on uploaded map {id} v{version}: {e:?}"),
            }
            uploads += 1;
        }
        if began.elapsed() >= next_sample {
            next_sample += every;
            let s = sample(pid, began.elapsed().as_secs_f64());
            eprintln!(
                "soak sample t={:.0}s rss_kb={} fds={} (clients finished {finished}, killed {killed}, answers {answered}, map uploads {uploads})",
                s.t, s.rss_kb, s.fds
            );
            samples.push(s);
        }
        std::thread::sleep(Duration::from_millis(100));
    }
    for d in &mut drivers {
        d.proc.kill();
    }
    let last = sample(pid, began.elapsed().as_secs_f64());
    samples.push(last);
    let first = samples[1.min(samples.len() - 1)];
    let max_rss = samples.iter().max_by_key(|s| s.rss_kb).unwrap();
    let max_fds = samples.iter().max_by_key(|s| s.fds).unwrap();
    eprintln!(
        "soak summary: {:.0} s, {} samples; first (t={:.0}s) rss {} kB fds {}; last rss {} kB fds {}; max rss {} kB (t={:.0}s), max fds {} (t={:.0}s); clients finished {finished}, killed {killed}, spawned {spawned}; answers checked {answered}; map uploads {uploads}",
        last.t,
        samples.len(),
        first.t,
        first.rss_kb,
        first.fds,
        last.rss_kb,
        last.fds,
        max_rss.rss_kb,
        max_rss.t,
        max_fds.fds,
        max_fds.t
    );
    eprintln!("server descriptors at the end:\n{}", fd_targets(pid));
    assert!(finished > 0 && answered > 0 && uploads > 0);
    assert!(
        last.rss_kb <= first.rss_kb * 3 / 2 + 16 * 1024,
        "server memory grew: {} kB -> {} kB",
        first.rss_kb,
        last.rss_kb
    );
    assert!(
        last.fds <= first.fds + 16,
        "server descriptors grew: {} -> {}",
        first.fds,
        last.fds
    );
    assert!(server.log_text().contains("planner-server ready"));
}

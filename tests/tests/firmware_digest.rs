//! The firmware scenario on the host: the same code (`tests/firmware/src/scenario.rs`) must
//! give the same digest as the emulated Cortex-M4F. `tests/firmware/DIGEST` holds the digest
//! the MCU printed; `tests/firmware/run.sh` checks the MCU against it and against this test's
//! output, so a change on either side fails.
//!
//! `cargo test -p integration-tests --test firmware_digest -- --nocapture` prints the same
//! `case ...` lines (without the tick counts) and `digest=...` as the firmware.

#[allow(dead_code)]
#[path = "../firmware/src/scenario.rs"]
mod scenario;

use scenario::{CASES, Nodes, Site, Storage};

/// The firmware's `case` line without its tick and instruction counts (run.sh compares them).
fn print_case(name: &str, o: &scenario::Outcome) {
    println!(
        "case {name} status={} valid={} length_milli={} length_bits={:#010x} evaluations={} iterations={} waypoints={} digest={:#018x}",
        o.status,
        o.valid,
        o.length_milli,
        o.length_bits,
        o.evaluations,
        o.iterations,
        o.waypoints,
        o.digest
    );
}

#[test]
fn host_digest_matches_the_mcu() {
    let mut s = Box::new(Site::new());
    let mut storage = Box::new(Storage::new());
    let mut nodes = Box::new(Nodes::new());
    let mut digests = Vec::new();
    let mut loaded = 0;
    for (i, case) in CASES.iter().enumerate() {
        if case.side != loaded {
            scenario::load(&mut s, case.side).unwrap();
            loaded = case.side;
            let o = scenario::prepare(&s, &mut storage);
            print_case(if loaded == 40 { "mesh-40" } else { "mesh-64" }, &o);
            assert_eq!(o.status, 0, "mesh of the {loaded} map");
            digests.push(o.digest);
        }
        let o = scenario::run_case(&s, &mut storage, i);
        print_case(case.name, &o);
        assert_eq!((o.status, o.valid), (0, 1), "{}", case.name);
        digests.push(o.digest);
    }
    let o = scenario::dwa_control_loop(&s, &mut nodes).expect("a route for the DWA loop");
    print_case("dwa", &o);
    assert_eq!(
        (o.status, o.valid),
        (0, 1),
        "the DWA loop must arrive without a collision"
    );
    digests.push(o.digest);
    let digest = format!("{:#018x}", scenario::combine(&digests));
    println!("digest={digest}");
    let mcu = include_str!("../firmware/DIGEST").trim();
    assert_eq!(
        digest, mcu,
        "host digest differs from the one the emulated MCU printed (tests/firmware/DIGEST)"
    );
}

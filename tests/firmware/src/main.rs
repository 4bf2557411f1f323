//! Firmware proof for QEMU's `mps2-an386` (Cortex-M4F): runs the shared [`scenario`] with
//! every piece of planner state in a `static`, prints integer results, the cost of each plan
//! in SysTick ticks (instructions under `-icount shift=0`), the peak stack (painting) and
//! the digest over semihosting, and exits 0 when every plan succeeded with a valid path,
//! 1 otherwise.
#![no_std]
#![no_main]

use core::mem::ManuallyDrop;
use core::ptr::addr_of_mut;
use core::sync::atomic::{AtomicU32, Ordering};

use cortex_m::peripheral::SYST;
use cortex_m::peripheral::syst::SystClkSource;
use cortex_m_rt::{entry, exception};
use cortex_m_semihosting::{debug, hprintln};
use panic_semihosting as _;

mod scenario;
use scenario::{CASES, Nodes, Outcome, Site, Storage};

/// All planner state lives in statics (the linker checks them against the RAM budget), all
/// zero bytes: `.bss`. The plans use the plan storage, then the DWA loop's route the A*
/// state, in the same memory.
static mut PLANNER: Planner = Planner {
    plan: ManuallyDrop::new(Storage::new()),
};

/// Memory shared by the two phases. Every field is valid as all-zero bytes (integers,
/// floats, enums whose first variant is 0), which is how each phase finds it.
#[repr(C)]
union Planner {
    plan: ManuallyDrop<Storage>,
    astar: ManuallyDrop<Nodes>,
}
/// The map, its start and goal.
static mut SITE: Site = Site::new();

/// SysTick wraps (the counter is 24 bits).
static WRAPS: AtomicU32 = AtomicU32::new(0);
const RELOAD: u32 = 0x00FF_FFFF;

#[exception]
fn SysTick() {
    WRAPS.fetch_add(1, Ordering::Relaxed);
}

/// Ticks since SysTick started (core clock: with `-icount shift=0` one instruction is 1 ns
/// and the 25 MHz SysTick ticks every 40 instructions).
fn ticks() -> u64 {
    loop {
        let w = WRAPS.load(Ordering::Relaxed);
        let cvr = SYST::get_current();
        if WRAPS.load(Ordering::Relaxed) == w && !SYST::has_wrapped_peek() {
            return w as u64 * (RELOAD as u64 + 1) + (RELOAD - cvr) as u64;
        }
    }
}

trait PeekWrap {
    fn has_wrapped_peek() -> bool;
}
impl PeekWrap for SYST {
    /// Whether a wrap is pending (COUNTFLAG would clear on read, so look at the ICSR
    /// PENDSTSET bit instead).
    fn has_wrapped_peek() -> bool {
        cortex_m::peripheral::SCB::is_pendst_pending()
    }
}

/// Bytes of stack ever used: the painted region below the stack top that was overwritten.
fn peak_stack() -> u32 {
    unsafe extern "C" {
        static mut _stack_start: u32;
        static mut _stack_end: u32;
    }
    let (top, end) = (
        addr_of_mut!(_stack_start) as usize,
        addr_of_mut!(_stack_end) as usize,
    );
    let mut p = end;
    while p < top {
        // SAFETY: `p` lies in the stack region, word-aligned, below the live stack.
        let v = unsafe { core::ptr::read_volatile(p as *const u32) };
        if v != cortex_m_rt::STACK_PAINT_VALUE {
            break;
        }
        p += 4;
    }
    (top - p) as u32
}

fn print(name: &str, o: &Outcome, ticks: u64) {
    hprintln!(
        "case {} status={} valid={} length_milli={} length_bits={:#010x} evaluations={} iterations={} waypoints={} ticks={} instructions={} digest={:#018x}",
        name,
        o.status,
        o.valid,
        o.length_milli,
        o.length_bits,
        o.evaluations,
        o.iterations,
        o.waypoints,
        ticks,
        ticks * 40,
        o.digest
    );
}

#[entry]
fn main() -> ! {
    let mut cp = cortex_m::Peripherals::take().unwrap();
    cp.SYST.set_clock_source(SystClkSource::Core);
    cp.SYST.set_reload(RELOAD);
    cp.SYST.clear_current();
    cp.SYST.enable_interrupt();
    cp.SYST.enable_counter();
    // The counter reads 0 until its first reload: wait for it so that tick readings are
    // monotonic from the start.
    while SYST::get_current() == 0 {}

    // SAFETY: the only reference to SITE, taken once before any interrupt could use it
    // (the SysTick handler does not touch it).
    let s: &mut Site = unsafe { &mut *addr_of_mut!(SITE) };
    // SAFETY: the only reference to PLANNER while the plans run; PLANNER starts as the plan
    // storage, all zero bytes.
    let storage: &mut Storage = unsafe { &mut (*addr_of_mut!(PLANNER)).plan };
    let mut digests = [0u64; CASES.len() + 3];
    let mut count = 0;
    let mut ok = true;
    let mut loaded = 0;
    for (i, case) in CASES.iter().enumerate() {
        if case.side != loaded {
            if scenario::load(s, case.side).is_err() {
                hprintln!("map {} failed", case.side);
                debug::exit(debug::EXIT_FAILURE);
            }
            loaded = case.side;
            let t0 = ticks();
            let o = scenario::prepare(s, storage);
            let t = ticks() - t0;
            print(if loaded == 40 { "mesh-40" } else { "mesh-64" }, &o, t);
            ok &= o.status == 0;
            digests[count] = o.digest;
            count += 1;
        }
        let t0 = ticks();
        let o = scenario::run_case(s, storage, i);
        let t = ticks() - t0;
        print(case.name, &o, t);
        ok &= o.status == 0 && o.valid == 1;
        digests[count] = o.digest;
        count += 1;
    }
    #[cfg(feature = "optimizer-alone")]
    optimizer_alone(storage);
    // SAFETY: the plans are done and `storage` is not used again; the A* state is valid as
    // all zero bytes, written here over the plan storage before the only reference to it is
    // taken.
    let nodes: &mut Nodes = unsafe {
        let memory = addr_of_mut!(PLANNER);
        core::ptr::write_bytes(memory as *mut u8, 0, core::mem::size_of::<Planner>());
        &mut (*memory).astar
    };
    let t0 = ticks();
    match scenario::dwa_control_loop(s, nodes) {
        Some(o) => {
            let t = ticks() - t0;
            print("dwa", &o, t);
            ok &= o.status == 0;
            digests[count] = o.digest;
            count += 1;
        }
        None => {
            hprintln!("case dwa: no route");
            ok = false;
        }
    }
    hprintln!("stack_peak_bytes={}", peak_stack());
    hprintln!("digest={:#018x}", scenario::combine(&digests[..count]));
    debug::exit(if ok {
        debug::EXIT_SUCCESS
    } else {
        debug::EXIT_FAILURE
    });
    loop {
        cortex_m::asm::wfi();
    }
}

/// Times each swarm optimizer of the scenario alone: the 40x40 plan's population, iterations,
/// seed and dimension (9), on a shifted sphere (a few instructions per variable).
#[cfg(feature = "optimizer-alone")]
fn optimizer_alone(storage: &mut Storage) {
    use planner_core::optim::any::AlgorithmKind;
    use planner_core::optim::{Bounds, Optimizer, Settings};
    use planner_core::planner::PlanOptimizer;
    const DIM: usize = 9;
    for kind in [AlgorithmKind::Tclhho, AlgorithmKind::Igwo] {
        let Ok(bounds) = Bounds::<{ scenario::DIM }>::uniform(DIM, -1.0, 1.0) else {
            return;
        };
        let settings = Settings {
            population: scenario::POP,
            iterations: 500,
            seed: scenario::SEED,
        };
        let mut sphere = |x: &[f32]| x.iter().map(|v| (v - 0.25) * (v - 0.25)).sum::<f32>();
        let t0 = ticks();
        let swarm = storage.optimizer_mut();
        let ok = swarm.configure_kind(kind, settings, &bounds).is_ok()
            && swarm.init(&mut sphere, None).is_ok()
            && (0..500).all(|_| swarm.step(&mut sphere).is_ok());
        let t = ticks() - t0;
        hprintln!(
            "alone {:?} ok={} dimension={} evaluations={} instructions={}",
            kind,
            ok,
            DIM,
            swarm.evaluations(),
            t * 40
        );
    }
}

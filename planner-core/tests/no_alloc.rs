//! Proves that the reference planners never touch the heap: a counting global allocator
//! wraps the system one, and repeated `astar::plan` / `theta::plan` (and connectivity)
//! calls on a Moving AI warehouse map must not allocate, reallocate or free at all.
//!
//! The counters are per thread (the test harness may allocate on its own threads), and
//! only count while this test's thread has switched counting on.

use planner_core::geometry::Cell;
use planner_core::grid::{Grid, words_for};
use planner_core::path::Path;
use planner_core::search::astar::{AStarNode, OpenSlot, open_capacity};
use planner_core::search::{SearchNode, astar, connectivity, theta};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell as StdCell;

struct Counting;

thread_local! {
    static COUNTING: StdCell<bool> = const { StdCell::new(false) };
    static EVENTS: StdCell<usize> = const { StdCell::new(0) };
}

fn note() {
    // `try_with`: during thread teardown the locals may be gone; never panic in here.
    let on = COUNTING.try_with(|c| c.get()).unwrap_or(false);
    if on {
        let _ = EVENTS.try_with(|e| e.set(e.get() + 1));
    }
}

// SAFETY: forwards every call unchanged to `System`, only bumping a thread-local counter
// (const-initialised thread locals never allocate).
unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        note();
        unsafe { System.alloc(layout) }
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        note();
        unsafe { System.alloc_zeroed(layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        note();
        unsafe { System.realloc(ptr, layout, new_size) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        note();
        unsafe { System.dealloc(ptr, layout) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Heap events on this thread while `f` runs.
fn heap_events(f: impl FnOnce()) -> usize {
    EVENTS.with(|e| e.set(0));
    COUNTING.with(|c| c.set(true));
    f();
    COUNTING.with(|c| c.set(false));
    EVENTS.with(|e| e.get())
}

type Map = Grid<{ words_for(170, 84) }>;

#[test]
fn the_counter_sees_allocations() {
    let n = heap_events(|| {
        let v = std::hint::black_box(vec![1u8; 100]);
        drop(v);
    });
    assert_eq!(n, 2);
}

#[test]
fn planners_do_not_allocate() {
    let dir = std::path::PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../tests/data/movingai");
    let text = std::fs::read(dir.join("warehouse-10-20-10-2-2.map")).unwrap();
    let grid = Box::new(Map::parse_movingai(&text).unwrap());
    let g = grid.view();
    // Queries from the scenario file (some long ones), parsed before counting.
    let scen = std::fs::read_to_string(dir.join("warehouse-10-20-10-2-2-random-1.scen")).unwrap();
    let queries: Vec<(Cell, Cell)> = scen
        .lines()
        .skip(1)
        .take(60)
        .map(|l| {
            let f: Vec<u16> = l
                .split('\t')
                .skip(4)
                .take(4)
                .map(|v| v.parse().unwrap())
                .collect();
            (Cell::new(f[0], f[1]), Cell::new(f[2], f[3]))
        })
        .collect();
    let mut nodes = vec![SearchNode::EMPTY; g.cells()];
    let mut astar_nodes = vec![AStarNode::EMPTY; g.cells()];
    let mut open = vec![OpenSlot::EMPTY; open_capacity(g.cells())];
    let mut labels = vec![0u32; g.cells()];
    let mut out: Box<Path<2048>> = Box::new(Path::new());
    let mut total = 0.0f32;

    let events = heap_events(|| {
        connectivity::label(g, &mut labels).unwrap();
        for _ in 0..3 {
            for &(s, t) in &queries {
                total += astar::plan(g, s, t, &mut astar_nodes, &mut open, &mut *out)
                    .unwrap()
                    .length;
                total += theta::plan(g, s, t, &mut nodes, &mut *out).unwrap().length;
                total += astar::plan_with_labels(
                    g,
                    s,
                    t,
                    Some(&labels),
                    &mut astar_nodes,
                    &mut open,
                    &mut *out,
                )
                .unwrap()
                .length;
                total += theta::plan_with_labels(g, s, t, Some(&labels), &mut nodes, &mut *out)
                    .unwrap()
                    .length;
            }
            // Error paths too.
            let blocked = Cell::new(0, 0);
            assert!(
                astar::plan(
                    g,
                    blocked,
                    queries[0].1,
                    &mut astar_nodes,
                    &mut open,
                    &mut *out
                )
                .is_err()
            );
            assert!(
                theta::plan(g, queries[0].0, Cell::new(999, 0), &mut nodes, &mut *out).is_err()
            );
        }
    });
    assert_eq!(events, 0, "heap events during planning");
    assert!(total > 0.0);
}

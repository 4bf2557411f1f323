//! Arbitrary bytes through the Moving AI `.map` parser and the bare-rows parser.
//!
//! An accepted map must survive `write_movingai` -> `parse_movingai` unchanged; the bare
//! rows of an accepted `parse_rows` input must parse as the body of a Moving AI map.
#![no_main]

use libfuzzer_sys::fuzz_target;
use planner_core::grid::{Grid, words_for};

/// Up to 4096 cells (64 x 64 and any other shape of that area).
type G = Grid<{ words_for(64, 64) }>;

/// A fixed-capacity `fmt::Write` sink (no allocation, like firmware would use).
struct Buf {
    data: [u8; 1 << 14],
    len: usize,
}

impl core::fmt::Write for Buf {
    fn write_str(&mut self, s: &str) -> core::fmt::Result {
        let end = self.len + s.len();
        if end > self.data.len() {
            return Err(core::fmt::Error);
        }
        self.data[self.len..end].copy_from_slice(s.as_bytes());
        self.len = end;
        Ok(())
    }
}

fn round_trip(grid: &G) {
    let mut buf = Buf {
        data: [0; 1 << 14],
        len: 0,
    };
    grid.write_movingai(&mut buf)
        .expect("a 4096-cell map fits in 16 KiB of text");
    let again = G::parse_movingai(&buf.data[..buf.len]).expect("written map re-parses");
    assert_eq!(&again, grid, "round trip changed the map");
    assert_eq!(again.view().blocked_count(), grid.view().blocked_count());
}

fuzz_target!(|data: &[u8]| {
    if let Ok(grid) = G::parse_movingai(data) {
        assert!(grid.width() >= 1 && grid.height() >= 1);
        assert!(grid.width() * grid.height() <= G::CAPACITY);
        round_trip(&grid);
    }
    if let Ok(grid) = G::parse_rows(data) {
        round_trip(&grid);
        // Every cell outside the map reads as blocked.
        let v = grid.view();
        assert!(v.is_blocked(-1, 0) && v.is_blocked(0, -1));
        assert!(v.is_blocked(grid.width() as isize, 0));
        assert!(v.is_blocked(0, grid.height() as isize));
    }
});

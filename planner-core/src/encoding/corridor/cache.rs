//! The corridor encoding's leg cache: for each pair of waypoint intervals of a leg (an eighth
//! of the offset range at each end), what is known of every leg between them, on three
//! levels: clear outright, judged from one or two blocked cells near the pair's hull, or
//! left to the exact segment check (see [`PairState`]). Three bits a pair in [`PairStates`]; the blocked cells in a
//! few sets shared by the leg's pairs ([`Blockers`]); both together a station's [`LegCache`].

/// Intervals per station in the leg cache: the offset range `[-1, 1]` in 8 equal parts, so
/// that the 8 x 8 interval pairs of a leg fit in 64 bits (16: see `docs/perf-notes.md`).
const BUCKETS: usize = 8;

/// Most blocked cells in one set (see [`PairState`]); a pair near more of them takes the exact check. Sets
/// of three cost more instructions than they save (`docs/perf-notes.md`).
pub(super) const LISTED: usize = 2;

/// Sets of blocked cells per station (at most four: a set index is two bits); how rarely a
/// pair finds its set replaced is in `docs/perf-notes.md`.
const SETS: usize = 4;

/// What the cache knows of one interval pair of a leg.
///
/// Most legs that the hull test cannot prove clear pass an obstacle's corner: the hull of
/// their pair comes near one or two blocked cells, and only those can block them. Knowing
/// them, [`segment_is_clear_among`](crate::geometry::segment_is_clear_among) gives the
/// exact check's verdict from those cells alone (mostly by a separating-axis test; a fifth
/// of its cost on average). Neighbouring pairs mostly share the same cells, so pairs point to a
/// few shared sets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum PairState {
    /// Not tested yet.
    Untested,
    /// Every leg between the two intervals is clear.
    Clear,
    /// Too many blocked cells near the hull (or the map's edge): each leg needs the exact
    /// segment check.
    Exact,
    /// Its blocked cells were in a set that has been replaced since: test again.
    Displaced,
    /// Its blocked cells are set `k` (below [`SETS`]) of the station's [`Blockers`].
    InSet(u8),
}

impl PairState {
    /// The state's three bits in [`PairStates`]: 0 to 3 in the order above, `4 + k` for
    /// `InSet(k)`.
    #[inline(always)]
    const fn bits(self) -> u32 {
        match self {
            PairState::Untested => 0,
            PairState::Clear => 1,
            PairState::Exact => 2,
            PairState::Displaced => 3,
            PairState::InSet(k) => 4 + (k as u32 & 3),
        }
    }

    /// The state of three bits (the inverse of [`bits`](Self::bits)).
    #[inline(always)]
    const fn from_bits(bits: u32) -> Self {
        match bits & 7 {
            0 => PairState::Untested,
            1 => PairState::Clear,
            2 => PairState::Exact,
            3 => PairState::Displaced,
            k => PairState::InSet((k - 4) as u8),
        }
    }
}

/// The [`PairState`] of each interval pair of a leg: three bits a pair, one in each of three
/// 64-bit planes (two 32-bit words each, addressed by [`pair_bit`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct PairStates([[u32; 2]; 3]);

impl PairStates {
    const EMPTY: PairStates = PairStates([[0; 2]; 3]);

    /// Whether the pair is [`PairState::Clear`] (`0b001`), from the three words at once:
    /// most leg checks end here.
    #[inline(always)]
    fn is_clear(&self, (w, bit): (usize, u32)) -> bool {
        let [p0, p1, p2] = &self.0;
        p0[w] & !(p1[w] | p2[w]) & bit != 0
    }

    /// The pair's state.
    #[inline(always)]
    fn get(&self, (w, bit): (usize, u32)) -> PairState {
        let [p0, p1, p2] = &self.0;
        let on = |plane: &[u32; 2], shift: u32| u32::from(plane[w] & bit != 0) << shift;
        PairState::from_bits(on(p0, 0) | on(p1, 1) | on(p2, 2))
    }

    /// Sets the pair's state.
    fn set(&mut self, (w, bit): (usize, u32), state: PairState) {
        let state = state.bits();
        for (plane, b) in self.0.iter_mut().zip(0..) {
            if state >> b & 1 != 0 {
                plane[w] |= bit;
            } else {
                plane[w] &= !bit;
            }
        }
    }

    /// Every pair in state `state` goes to [`PairState::Displaced`] (`0b011`).
    fn displace(&mut self, state: PairState) {
        let state = state.bits();
        let [p0, p1, p2] = &mut self.0;
        let pick = |plane: u32, on: bool| if on { plane } else { !plane };
        for w in 0..2 {
            let hit = pick(p0[w], state & 1 != 0)
                & pick(p1[w], state & 2 != 0)
                & pick(p2[w], state & 4 != 0);
            p0[w] |= hit;
            p1[w] |= hit;
            p2[w] &= !hit;
        }
    }
}

/// A station's sets of blocked cells, each cell as its offset from the station's cell (two
/// bytes instead of four; a cell beyond +-127 of it is not listed: its pair takes the exact check).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Blockers {
    cells: [[[i8; 2]; LISTED]; SETS],
    /// The number of cells of set `k`, in bits `2k..2k + 2` (one byte for all: the RAM
    /// budget of the firmware left no room for a fourth set otherwise).
    lens: u8,
    /// The set indices, two bits each, the most recently used in the lowest bits (a
    /// permutation, set by `build`).
    order: u8,
}

impl Blockers {
    const EMPTY: Blockers = Blockers {
        cells: [[[0; 2]; LISTED]; SETS],
        lens: 0,
        order: 0,
    };

    /// Fresh sets in the initial order (0 most recent).
    const FRESH: Blockers = Blockers {
        order: {
            let mut order = 0;
            let mut k = 0;
            while k < SETS {
                order |= (k as u8) << (2 * k);
                k += 1;
            }
            order
        },
        ..Blockers::EMPTY
    };

    /// The number of cells of set `k`.
    fn len(&self, k: usize) -> usize {
        usize::from(self.lens >> (2 * (k % SETS)) & 3)
    }

    /// Sets set `k`'s cells.
    fn put(&mut self, k: usize, cells: [[i8; 2]; LISTED], len: usize) {
        let k = k % SETS;
        self.cells[k] = cells;
        self.lens = self.lens & !(3 << (2 * k)) | ((len as u8 & 3) << (2 * k));
    }

    /// The least recently used set.
    fn oldest(&self) -> usize {
        usize::from(self.order >> (2 * (SETS - 1)) & 3)
    }

    /// Marks set `k` the most recently used.
    #[inline(always)]
    fn touch(&mut self, k: usize) {
        if usize::from(self.order & 3) != k {
            self.promote(k);
        }
    }

    /// [`touch`](Self::touch) for a set that is not the most recent one.
    #[inline(never)]
    fn promote(&mut self, k: usize) {
        let order = u32::from(self.order);
        let k = (k % SETS) as u32;
        let at = (1..SETS as u32)
            .find(|&p| order >> (2 * p) & 3 == k)
            .unwrap_or(SETS as u32 - 1);
        let below = order & ((1 << (2 * at)) - 1);
        let above = order & !((1 << (2 * at + 2)) - 1);
        self.order = (above | below << 2 | k) as u8;
    }
}

/// The cache of one leg (kept by the station the leg starts at): the state of each interval
/// pair and the sets of blocked cells they point to.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub(super) struct LegCache {
    states: PairStates,
    blockers: Blockers,
}

impl LegCache {
    /// An unused cache (for array and `static` initialisers).
    pub(super) const EMPTY: LegCache = LegCache {
        states: PairStates::EMPTY,
        blockers: Blockers::EMPTY,
    };

    /// Every pair untested, the sets in their initial order.
    pub(super) const FRESH: LegCache = LegCache {
        states: PairStates::EMPTY,
        blockers: Blockers::FRESH,
    };

    /// Whether pair `pair` ([`pair_bit`]) is [`PairState::Clear`].
    #[inline(always)]
    pub(super) fn is_clear(&self, pair: (usize, u32)) -> bool {
        self.states.is_clear(pair)
    }

    /// The state of pair `pair` ([`pair_bit`]).
    #[inline(always)]
    pub(super) fn state(&self, pair: (usize, u32)) -> PairState {
        self.states.get(pair)
    }

    /// Records what the test of pair `pair` found near its hull and returns the pair's new
    /// state: no blocked cell (`Some(0)`), the first `n` of `cells` (`Some(n)`, offsets from
    /// the station's cell), or too many to list (`None`). Listed cells go in a set: one with
    /// the same cells, or the least recently used one, whose pairs become
    /// [`PairState::Displaced`].
    pub(super) fn record(
        &mut self,
        pair: (usize, u32),
        found: Option<usize>,
        cells: [[i8; 2]; LISTED],
    ) -> PairState {
        let state = match found {
            Some(0) => PairState::Clear,
            None => PairState::Exact,
            Some(n) => {
                let b = &mut self.blockers;
                let same =
                    (0..SETS).find(|&k| b.len(k) == n && b.cells[k].get(..n) == cells.get(..n));
                let k = same.unwrap_or_else(|| {
                    let k = b.oldest();
                    b.put(k, cells, n);
                    // Pairs that pointed to the replaced set must test again.
                    self.states.displace(PairState::InSet(k as u8));
                    k
                });
                self.blockers.touch(k);
                PairState::InSet(k as u8)
            }
        };
        self.states.set(pair, state);
        state
    }

    /// The cells of set `k` (offsets from the station's cell), marking the set the most
    /// recently used.
    #[inline(always)]
    pub(super) fn use_set(&mut self, k: u8) -> impl Iterator<Item = &[i8; 2]> + Clone {
        let k = usize::from(k) % SETS;
        self.blockers.touch(k);
        let b = &self.blockers;
        b.cells[k].iter().take(b.len(k))
    }
}

/// The word and bit of interval pair `(i, j)` (`i, j < BUCKETS`) in a station's cache: bit
/// `BUCKETS * i + j` of 64, in two 32-bit words (a variable `u64` shift is a branch and
/// several instructions on a 32-bit core).
#[inline(always)]
pub(super) fn pair_bit(i: usize, j: usize) -> (usize, u32) {
    let k = i * BUCKETS + j;
    ((k / 32) % 2, 1 << (k % 32))
}

/// The cache interval of an offset in `[-1, 1]`.
pub(super) fn bucket(v: f32) -> usize {
    (((v + 1.0) * (BUCKETS as f32 / 2.0)) as usize).min(BUCKETS - 1)
}

/// The offsets that bound cache interval `i`.
pub(super) fn interval(i: usize) -> (f32, f32) {
    let w = 2.0 / BUCKETS as f32;
    (i as f32 * w - 1.0, (i + 1) as f32 * w - 1.0)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pair_states_round_trip_through_their_bits() {
        let all = [
            PairState::Untested,
            PairState::Clear,
            PairState::Exact,
            PairState::Displaced,
            PairState::InSet(0),
            PairState::InSet(1),
            PairState::InSet(2),
            PairState::InSet(3),
        ];
        for (bits, state) in all.into_iter().enumerate() {
            assert_eq!(state.bits(), bits as u32);
            assert_eq!(PairState::from_bits(bits as u32), state);
        }
        let mut states = PairStates::EMPTY;
        for (i, state) in all.into_iter().enumerate() {
            states.set(pair_bit(i, 7 - i), state);
        }
        for (i, state) in all.into_iter().enumerate() {
            assert_eq!(states.get(pair_bit(i, 7 - i)), state);
            assert_eq!(
                states.is_clear(pair_bit(i, 7 - i)),
                state == PairState::Clear
            );
        }
        // Replacing set 2 displaces the pairs that pointed to it, and only them.
        states.displace(PairState::InSet(2));
        assert_eq!(states.get(pair_bit(6, 1)), PairState::Displaced);
        assert_eq!(states.get(pair_bit(7, 0)), PairState::InSet(3));
        assert_eq!(states.get(pair_bit(1, 6)), PairState::Clear);
    }

    #[test]
    fn sets_are_reused_and_replaced_least_recently_used_first() {
        let mut cache = LegCache::FRESH;
        let cells = |a: i8| [[a, 0], [0, a]];
        // Four sets fill up, least recently used first (fresh sets: 3 is the oldest); the
        // same cells again point to the same set.
        for a in 0..4 {
            let state = cache.record(pair_bit(0, a as usize), Some(1), cells(a));
            assert_eq!(state, PairState::InSet(3 - a as u8));
        }
        assert_eq!(
            cache.record(pair_bit(1, 0), Some(1), cells(0)),
            PairState::InSet(3)
        );
        // A fifth set replaces the least recently used one (set 2, of pair (0, 1)),
        // displacing its pair.
        assert_eq!(
            cache.record(pair_bit(1, 1), Some(2), cells(9)),
            PairState::InSet(2)
        );
        assert_eq!(cache.state(pair_bit(0, 1)), PairState::Displaced);
        assert_eq!(cache.state(pair_bit(0, 2)), PairState::InSet(1));
        assert_eq!(
            cache.use_set(2).copied().collect::<std::vec::Vec<_>>(),
            [[9, 0], [0, 9]]
        );
        assert_eq!(
            cache.record(pair_bit(2, 2), Some(0), cells(0)),
            PairState::Clear
        );
        assert_eq!(
            cache.record(pair_bit(2, 3), None, cells(0)),
            PairState::Exact
        );
        assert!(cache.is_clear(pair_bit(2, 2)));
    }
}

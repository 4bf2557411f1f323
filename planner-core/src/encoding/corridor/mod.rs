//! The general encoding: waypoints that slide across an exact guide route.
//!
//! `Lei2024Warehouse`'s column encoding cannot turn back, and a free-form waypoint encoding leaves the
//! optimizer to discover feasibility by itself (which is how the papers' GWO and TGWO failed
//! on 30 x 30 warehouses). Here an exact reference route (the A* path, octile-optimal but
//! stair-stepped) fixes the *homotopy* and guarantees feasibility; the optimizer decides the
//! *geometry*, which is where any-angle length is won:
//!
//! - `K` stations are spread evenly along the guide; station `k` has a normal and the clear
//!   extents `[-neg_k, pos_k]` (at most `radius`) along it;
//! - variable `x_k` in `[-1, 1]` places waypoint `w_k = g_k + n_k * x_k * (pos_k or neg_k)`;
//! - the path is `start, w_1, ..., w_K, goal`; a leg `w_k -> w_{k+1}` that is blocked is
//!   *repaired* as `w_k -> g_k -> (guide) -> g_{k+1} -> w_{k+1}`, every part of which is clear
//!   by construction, so every decision vector decodes to a valid path.
//!
//! The cost is the decoded length. Random decision vectors give zig-zags and detours; the
//! optimizer's work is to pull the string taut within the corridor (the planner then prunes
//! collinear nodes and shortcuts).
//!
//! The leg cache, which spares most legs the exact segment check (see [`CorridorEncoding`]), is in
//! the `cache` submodule.

mod cache;

use super::Encoding;
use super::blend::{Blend, Trace};
use crate::error::PlanError;
use crate::geometry::{
    Cell, Point, clear_among, hull_blockers, hull_margin, quick_band, segment_is_clear,
};
use crate::grid::GridRef;
use crate::path::PathView;
use cache::{LISTED, LegCache, PairState, bucket, interval, pair_bit};

/// A station on the guide route.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Station {
    /// Index of the station in the guide.
    index: u32,
    /// The guide point.
    point: Point,
    /// The clear extents along the guide's unit normal at the station: `reach_+ * normal`
    /// and `reach_- * normal`, indexed by the sign bit of an offset (the waypoint at offset
    /// `v` is `point + v * side`).
    side: [(f32, f32); 2],
    /// Guide length from this station to the next.
    arc_to_next: f32,
    /// The leg to the next station, cached per pair of waypoint intervals, with the blocked
    /// cells near the pairs' hulls.
    cache: LegCache,
    /// The waypoint of the candidate under evaluation, its offset in `[-1, 1]` (0 at the
    /// fixed ends), and the straight length of its leg to the next waypoint: written by
    /// [`CorridorEncoding::straight`], read by the leg checks of that evaluation (placing
    /// each waypoint again per pass cost more than a tenth of a plan on a Cortex-M4, and
    /// reading the offset from the decision vector a bounds check and an end test per leg).
    waypoint: Point,
    offset: f32,
    straight: f32,
}

impl Station {
    /// An unused station (for array and `static` initialisers).
    pub const EMPTY: Station = Station {
        index: 0,
        point: Point::new(0.0, 0.0),
        side: [(0.0, 0.0); 2],
        arc_to_next: 0.0,
        cache: LegCache::EMPTY,
        waypoint: Point::new(0.0, 0.0),
        offset: 0.0,
        straight: 0.0,
    };

    /// The waypoint at offset `v` in `[-1, 1]` (for a movable station).
    #[inline(always)]
    fn slide(&self, v: f32) -> Point {
        // The extent on the offset's side, picked by its sign bit: a float comparison is
        // three or four instructions on a Cortex-M4, and this runs for every waypoint of
        // every evaluation. (-0.0 takes the negative side, giving a -0.0 displacement.) The
        // sides are scaled by their extents at build time: one multiplication and one load
        // fewer per waypoint than the extent times the normal.
        let (dx, dy) = self.side[(v.to_bits() >> 31) as usize];
        Point::new(self.point.x + v * dx, self.point.y + v * dy)
    }
}

/// A variable as an offset: clamped to `[-1, 1]`, 0 if not finite.
#[inline(always)]
fn offset_of(v: f32) -> f32 {
    if v.is_finite() {
        v.clamp(-1.0, 1.0)
    } else {
        0.0
    }
}

/// The sign bit of an `f32`.
const SIGN: u32 = 0x8000_0000;

/// The bits of `1.0f32`: `|v| <= 1` exactly when `v.to_bits() & !SIGN <= ONE`.
const ONE: u32 = 0x3f80_0000;

/// Step of the extent scan along a normal, in cells.
const EXTENT_STEP: f32 = 0.25;

/// Bisection rounds that refine the extent past the last clear step. Shortest paths turn
/// at obstacle corners: a reach stopped a quarter cell short costs about a quarter cell at
/// every turn (0.2-0.3 cells per aisle crossing on the Moving AI warehouses), so the extent
/// is refined to `EXTENT_STEP / 2^EXTENT_BISECTIONS` (under 1e-3 cells).
const EXTENT_BISECTIONS: u32 = 9;

/// Most movable stations, whatever the capacity (see [`slack`]).
const MAX_MOVABLE: usize = 998;

/// The factor that turns a sum of leg lengths, some straight where the cost has them
/// repaired, into a lower bound of the cost in `f32`, for `legs` legs: `1 - (5 legs + 8)
/// 2^-24` (exact in `f32` up to [`MAX_MOVABLE`]).
///
/// The bound is raised leg by leg as repairs are found, not summed again in the cost's order
/// (a pass over every leg per repair was a seventh of a plan on a Cortex-M4), so monotone
/// rounding alone does not keep it below the cost. With `u = 2^-24` and `T` the real sum of
/// the cost's terms: the cost, a recursive `f32` sum of `legs` terms, is at least
/// `T (1 - legs u)`. The raised sum adds at most `2 legs` terms (straight lengths, then one
/// rounded difference per repair) whose magnitudes total at most `2 T`, so it is at most
/// `T (1 + 4 legs u)` plus `5 u T` for a repaired leg computed a few ulps shorter than its
/// straight one and for the rounded differences. Shrinking by `(5 legs + 8) u` covers all
/// of it and the product's own rounding: a candidate is rejected early only when its cost is
/// at or above the bound, so costs and accept or reject decisions are bit for bit those of
/// the exact sum.
fn slack(legs: usize) -> f32 {
    1.0 - (5 * legs + 8) as f32 * (1.0 / 16_777_216.0)
}

/// The corridor encoding over a guide route.
///
/// Most legs of a candidate run through open floor, yet an exact check scans every cell
/// strip they cross. So each leg caches, per pair of waypoint intervals (an eighth of the
/// offset range at each end), what the convex hull of the two intervals (the union of all
/// legs between them) comes near (see [`hull_blockers`]): nothing within [`hull_margin`],
/// and every leg in it is clear without the exact check; one or two blocked cells, and a leg is
/// judged from those cells alone ([`segment_is_clear_among`]); more, and the exact check decides. The
/// cache only skips work: costs and decodings are bit for bit those of the exact check
/// alone.
///
/// [`segment_is_clear_among`]: crate::geometry::segment_is_clear_among
#[derive(Debug)]
pub struct CorridorEncoding<'a> {
    grid: GridRef<'a>,
    guide: &'a [Point],
    /// Stations `0..=K+1`: the start, `K` movable ones, the goal; each also holds the leg
    /// cache of its leg to the next.
    stations: &'a mut [Station],
    /// Clearance that a cached interval pair must keep ([`hull_margin`]).
    margin: f32,
    /// The band of the judgements from blocked cells ([`quick_band`]).
    band: f32,
    /// Legs that needed a repair in an earlier exact pass of `cost_below`: checked first,
    /// since the swarm keeps probing the same corners.
    hot: HotLegs,
    /// [`slack`] for the legs here.
    slack: f32,
    /// The objective beyond length ([`Blend::LENGTH`]: length alone).
    blend: Blend,
}

/// A set of legs, bit `s` for leg `s`: one machine word (a `u64` took two registers per set
/// and a carry per bit operation on a Cortex-M4, about 30 instructions per hot leg). Legs
/// from 32 on are never in a set: they are checked in order like the others, and a repair
/// there lifts the lower bound only when the exact pass reaches it (a weaker bound, the same
/// costs).
type LegSet = u32;

/// The bit of leg `s` in a [`LegSet`] (0 from leg 32 on).
fn leg_bit(s: usize) -> LegSet {
    if s < 32 { 1 << s } else { 0 }
}

/// The legs (below 32) that needed a repair in an earlier exact pass, in the order a bounded
/// evaluation checks them: the one whose repair last proved a cost too high first, the others
/// in the order they last did (move to front): 1.67 checks on average before a rejection,
/// against 3.05 with the others by index (`docs/perf-notes.md`).
#[derive(Clone, Copy, Debug)]
struct HotLegs {
    order: [u8; 32],
    len: usize,
    set: LegSet,
}

impl HotLegs {
    const EMPTY: HotLegs = HotLegs {
        order: [0; 32],
        len: 0,
        set: 0,
    };

    /// Adds leg `s` last (if it is below 32 and not in yet).
    fn insert(&mut self, s: usize) {
        let bit = leg_bit(s);
        if bit != 0
            && self.set & bit == 0
            && let Some(slot) = self.order.get_mut(self.len)
        {
            self.set |= bit;
            *slot = s as u8;
            self.len += 1;
        }
    }

    /// Moves the leg at position `k` of the order to the front.
    #[inline(always)]
    fn promote(&mut self, k: usize) {
        if k > 0
            && let Some(front) = self.order.get_mut(..=k)
        {
            front.rotate_right(1);
        }
    }

    /// Moves leg `s` to the front, if it is in.
    fn promote_leg(&mut self, s: usize) {
        let mut order = self.order.iter().take(self.len);
        if let Some(k) = order.position(|&h| usize::from(h) == s) {
            self.promote(k);
        }
    }
}

impl<'a> CorridorEncoding<'a> {
    /// Builds the stations over `guide` (a valid path, start first) into `stations`.
    ///
    /// `spacing` is the guide length between stations (cells); the number of movable stations
    /// is capped by `max_vars`, by `stations.len() - 2` and at 998. `radius` caps the
    /// lateral reach.
    /// Errors: [`PlanError::InvalidParameters`] for a NaN, infinite or non-positive `spacing`
    /// or `radius`, or a guide with fewer than two points.
    pub fn build(
        grid: GridRef<'a>,
        guide: &'a [Point],
        spacing: f32,
        radius: f32,
        max_vars: usize,
        stations: &'a mut [Station],
    ) -> Result<Self, PlanError> {
        if !(spacing.is_finite() && spacing > 0.0 && radius.is_finite() && radius > 0.0)
            || guide.len() < 2
        {
            return Err(PlanError::InvalidParameters);
        }
        let last = guide.len() - 1;
        // Candidate stations: the turning points of the guide pulled taut (a forward greedy
        // line-of-sight pass: a key is the last guide point visible from the previous key),
        // which is where length is won by cutting corners, plus evenly spaced points on runs
        // longer than `spacing`. (Every bend of the stair-stepped A* route would give many
        // variables that matter little.)
        let candidates = |emit: &mut dyn FnMut(usize)| {
            let spaced = |from: usize, to: usize, emit: &mut dyn FnMut(usize)| {
                let extra = libm::ceilf(guide[from].distance(guide[to]) / spacing) as usize;
                let steps = to - from;
                for e in 1..extra.min(steps) {
                    emit(from + e * steps / extra.min(steps));
                }
            };
            let mut anchor = 0usize;
            let mut i = 1usize;
            while i < last {
                if segment_is_clear(grid, guide[anchor], guide[i + 1]) {
                    i += 1;
                    continue;
                }
                spaced(anchor, i, emit);
                emit(i);
                anchor = i;
                i = anchor + 1;
            }
            spaced(anchor, last, emit);
        };
        let mut count = 0usize;
        candidates(&mut |_| count += 1);
        let k = count
            .min(max_vars)
            .min(MAX_MOVABLE)
            .min(stations.len().saturating_sub(2));
        // Thin evenly when there are more candidates than variables.
        stations[0] = Station {
            index: 0,
            point: guide[0],
            waypoint: guide[0],
            ..Station::default()
        };
        let mut seen = 0usize;
        let mut kept = 0usize;
        candidates(&mut |index| {
            // Exactly k of the count candidates, evenly: keep the ones where floor(seen k / count) steps.
            if kept < k && (seen + 1) * k / count > seen * k / count {
                kept += 1;
                stations[kept] = Station {
                    index: index as u32,
                    point: guide[index],
                    ..Station::default()
                };
            }
            seen += 1;
        });
        let k = kept;
        stations[k + 1] = Station {
            index: last as u32,
            point: guide[last],
            waypoint: guide[last],
            ..Station::default()
        };
        for s in 0..k + 2 {
            stations[s].cache = LegCache::FRESH;
            let i = stations[s].index as usize;
            if s + 1 < k + 2 {
                let j = stations[s + 1].index as usize;
                stations[s].arc_to_next = crate::path::length(&guide[i..=j]);
            }
            if s == 0 || s == k + 1 {
                continue;
            }
            let (a, b) = (guide[i - 1], guide[i + 1]);
            let (dx, dy) = (b.x - a.x, b.y - a.y);
            let len = crate::math::sqrt(dx * dx + dy * dy);
            let normal = if len > 0.0 {
                (-dy / len, dx / len)
            } else {
                (0.0, 1.0)
            };
            let g = guide[i];
            let reach = |sign: f32| {
                let mut ext = 0.0;
                let mut t = EXTENT_STEP;
                while t <= radius {
                    let p = Point::new(g.x + sign * t * normal.0, g.y + sign * t * normal.1);
                    if !segment_is_clear(grid, g, p) {
                        break;
                    }
                    ext = t;
                    t += EXTENT_STEP;
                }
                // The scan stopped at the first blocked step (or at `radius`): the boundary
                // lies in (ext, min(t, radius)]. Bisect it, keeping the clear side.
                let mut hi = t.min(radius);
                if hi > ext {
                    for _ in 0..EXTENT_BISECTIONS {
                        let mid = 0.5 * (ext + hi);
                        let p =
                            Point::new(g.x + sign * mid * normal.0, g.y + sign * mid * normal.1);
                        if segment_is_clear(grid, g, p) {
                            ext = mid;
                        } else {
                            hi = mid;
                        }
                    }
                }
                ext
            };
            let side = |ext: f32| (ext * normal.0, ext * normal.1);
            stations[s].side = [side(reach(1.0)), side(reach(-1.0))];
        }
        let margin = hull_margin(grid);
        Ok(CorridorEncoding {
            grid,
            guide,
            stations: &mut stations[..k + 2],
            margin,
            band: quick_band(grid, margin),
            hot: HotLegs::EMPTY,
            slack: slack(k + 1),
            blend: Blend::LENGTH,
        })
    }

    /// Costs paths by `blend` (length plus its turning and clearance terms) instead of
    /// their length; decoding is unchanged.
    pub fn with_blend(mut self, blend: Blend) -> Self {
        self.blend = blend;
        self
    }

    /// Whether the cost is length alone (always without the `blend` feature).
    fn length_only(&self) -> bool {
        !cfg!(feature = "blend") || self.blend.is_length()
    }

    /// `length` (the placed waypoints' decoded length) plus the blend's terms over the
    /// decoded path (repaired legs along the guide, as [`decode`](Encoding::decode) gives
    /// them); stops adding once the sum reaches `bound`, which is then a lower bound.
    #[inline(never)]
    fn blended(&mut self, length: f32, bound: f32) -> f32 {
        let grid = self.grid;
        let mut trace = Trace::new(self.blend);
        trace.push_extra(grid, self.stations[0].waypoint);
        for s in 0..self.stations.len() - 1 {
            if !self.leg_is_clear(s) {
                let (i, j) = (
                    self.stations[s].index as usize,
                    self.stations[s + 1].index as usize,
                );
                for &g in self.guide.get(i..j).unwrap_or(&[]) {
                    trace.push_extra(grid, g);
                }
                trace.push_extra(grid, self.stations[s + 1].point);
            }
            trace.push_extra(grid, self.stations[s + 1].waypoint);
            if length + trace.extra() >= bound {
                break;
            }
        }
        length + trace.extra()
    }

    /// The guide indices of the movable stations.
    pub fn station_indices(&self) -> impl Iterator<Item = usize> + '_ {
        self.stations[1..self.stations.len() - 1]
            .iter()
            .map(|s| s.index as usize)
    }

    /// Length of leg `s` (`a -> b`) repaired along the guide: `a -> g_s -> (guide) ->
    /// g_{s+1} -> b`.
    #[inline(always)]
    fn repaired_leg(&self, s: usize, a: Point, b: Point) -> f32 {
        a.distance(self.stations[s].point)
            + self.stations[s].arc_to_next
            + self.stations[s + 1].point.distance(b)
    }

    /// The offset in `[-1, 1]` of station `s` (0 at the fixed ends and for a non-finite
    /// variable).
    #[inline(always)]
    fn offset(&self, s: usize, x: &[f32]) -> f32 {
        if s == 0 || s + 1 == self.stations.len() {
            return 0.0;
        }
        offset_of(x.get(s - 1).copied().unwrap_or(0.0))
    }

    /// The waypoint of station `s` at offset `v` (the station itself at the fixed ends).
    #[inline(always)]
    fn at(&self, s: usize, v: f32) -> Point {
        let st = &self.stations[s];
        if s == 0 || s + 1 == self.stations.len() {
            return st.point;
        }
        st.slide(v)
    }

    #[inline(always)]
    fn waypoint(&self, s: usize, x: &[f32]) -> Point {
        self.at(s, self.offset(s, x))
    }

    /// Places the waypoints of `x` in the stations (with their offsets and the straight
    /// lengths of the legs) and returns the sum of the straight legs, in the cost's order. A
    /// repaired leg is never shorter than the straight one (triangle inequality), so the sum
    /// bounds the cost from below, once shrunk by [`slack`] for rounding.
    #[inline(always)]
    fn straight(&mut self, x: &[f32]) -> f32 {
        // The usual case steps through the movable stations and the variables side by side, without
        // an index check or end test per leg: this is the hottest loop of a plan on a
        // Cortex-M4 (every bounded evaluation starts with it).
        if let Some((first, rest)) = self.stations.split_first_mut()
            && let Some((last, movable)) = rest.split_last_mut()
            && x.len() >= movable.len()
        {
            // Optimizers keep every variable in `[-1, 1]`, where `offset_of` is the identity:
            // the loop takes them as they are and checks afterwards, on the bits, that they
            // were: `|v| <= 1` exactly when `(bits & !SIGN) + (SIGN - 1 - ONE)` leaves the
            // sign bit clear (NaN's bits are above; nothing wraps), so the sign bits of all
            // of them are or-ed. Three integer instructions per variable on a Cortex-M4,
            // where the finiteness test and the clamp took a dozen.
            let mut total = 0.0;
            let mut a = first.point;
            let mut leg = &mut first.straight;
            let mut beyond = 0u32;
            for (st, &v) in movable.iter_mut().zip(x) {
                beyond |= (v.to_bits() & !SIGN) + (SIGN - 1 - ONE);
                let b = st.slide(v);
                *leg = a.distance(b);
                total += *leg;
                st.waypoint = b;
                st.offset = v;
                leg = &mut st.straight;
                a = b;
            }
            if beyond & SIGN == 0 {
                *leg = a.distance(last.point);
                return total + *leg;
            }
        }
        // A variable out of range, or fewer variables than movable stations (never from an
        // optimizer): by index, with `offset_of`'s clamp and default offset. One loop over a
        // chain of the two cases, a fold or a closure instead cost 2-13% more instructions
        // per plan on the Cortex-M4.
        let mut total = 0.0;
        let mut a = self.stations[0].point;
        for s in 0..self.stations.len() - 1 {
            let v = self.offset(s + 1, x);
            let b = self.at(s + 1, v);
            let leg = a.distance(b);
            total += leg;
            self.stations[s + 1].waypoint = b;
            self.stations[s + 1].offset = v;
            self.stations[s].straight = leg;
            a = b;
        }
        total
    }

    /// Raises `sum` (the [`straight`](Self::straight) sum, or one raised before) by leg `s`,
    /// now known to need a repair: its repaired length in place of its straight one. Returns
    /// the raised sum shrunk by [`slack`]: a lower bound of the cost.
    #[inline(always)]
    fn raise(&self, sum: &mut f32, s: usize) -> f32 {
        *sum += self.repaired(s) - self.stations[s].straight;
        *sum * self.slack
    }

    /// The repaired length of leg `s` between the placed waypoints.
    #[inline(always)]
    fn repaired(&self, s: usize) -> f32 {
        let (a, b) = (self.stations[s].waypoint, self.stations[s + 1].waypoint);
        self.repaired_leg(s, a, b)
    }

    /// Tests interval pair `(i, j)` of leg `s` into the cache: its new [`PairState`], with
    /// the blocked cells near its hull put in a set ([`LegCache::record`]).
    /// Out of line: it runs a few hundred times per plan, and inlined, its locals would
    /// deepen the stack frame of every evaluation.
    #[inline(never)]
    fn test_pair(&mut self, s: usize, i: usize, j: usize) -> PairState {
        let pair = pair_bit(i, j);
        let ((a0, a1), (b0, b1)) = (interval(i), interval(j));
        let hull = [
            self.at(s, a0),
            self.at(s, a1),
            self.at(s + 1, b0),
            self.at(s + 1, b1),
        ];
        let mut found = [Cell::new(0, 0); LISTED];
        let count = hull_blockers(self.grid, &hull, self.margin, &mut found);
        let st = &mut self.stations[s];
        let (bx, by) = (st.point.x as i32, st.point.y as i32);
        // Offsets from the station's cell; `None` if one does not fit, or if the station is
        // not at a cell centre (a guide that is not a grid path), which the offsets assume.
        let centred = bx as f32 == st.point.x && by as f32 == st.point.y;
        let mut cells = [[0i8; 2]; LISTED];
        let fits = count.filter(|&n| {
            n == 0
                || centred
                    && found.iter().zip(&mut cells).take(n).all(|(c, o)| {
                        let (dx, dy) = (i32::from(c.x) - bx, i32::from(c.y) - by);
                        match (i8::try_from(dx), i8::try_from(dy)) {
                            (Ok(dx), Ok(dy)) => {
                                *o = [dx, dy];
                                true
                            }
                            _ => false,
                        }
                    })
        });
        st.cache.record(pair, fits, cells)
    }

    /// Whether leg `s` from `a` to `b` is clear, decided from set `k` of the station's
    /// blocked cells (those of the leg's interval pair).
    #[inline(always)]
    fn clear_among_set(&mut self, s: usize, a: Point, b: Point, k: u8) -> bool {
        let st = &mut self.stations[s];
        // The station's point is a cell centre (the guide is a grid path), so the cells'
        // centres are its coordinates plus the offsets.
        let p = st.point;
        let centres = st.cache.use_set(k);
        let centres = centres.map(|o| Point::new(p.x + f32::from(o[0]), p.y + f32::from(o[1])));
        clear_among(self.grid, a, b, centres, self.band)
    }

    /// Whether leg `s` between the placed waypoints is clear, by what its interval pair's
    /// [`PairState`] allows: clear outright (most legs, so this part is inlined), or
    /// [`leg_is_clear_beyond`](Self::leg_is_clear_beyond).
    #[inline(always)]
    fn leg_is_clear(&mut self, s: usize) -> bool {
        let (from, to) = (&self.stations[s], &self.stations[s + 1]);
        let (i, j) = (bucket(from.offset), bucket(to.offset));
        if from.cache.is_clear(pair_bit(i, j)) {
            return true;
        }
        self.leg_is_clear_beyond(s, i, j)
    }

    /// [`leg_is_clear`](Self::leg_is_clear) for a pair that is not known clear: from the
    /// pair's set of blocked cells, or by the exact check (testing the pair first if needed).
    #[inline(always)]
    fn leg_is_clear_beyond(&mut self, s: usize, i: usize, j: usize) -> bool {
        let mut state = self.stations[s].cache.state(pair_bit(i, j));
        if matches!(state, PairState::Untested | PairState::Displaced) {
            state = self.test_pair(s, i, j);
        }
        let (a, b) = (self.stations[s].waypoint, self.stations[s + 1].waypoint);
        match state {
            PairState::Clear => true,
            PairState::InSet(k) => self.clear_among_set(s, a, b, k),
            // (A tested pair is never untested or displaced.)
            PairState::Exact | PairState::Untested | PairState::Displaced => {
                segment_is_clear(self.grid, a, b)
            }
        }
    }

    /// The cost of the placed waypoints, leg by leg in order, where the legs in `clear` and
    /// `repaired` (`known`) are already known. With `BOUNDED`, each newly repaired leg raises `sum`
    /// (see [`raise`](Self::raise)) and the pass returns the lower bound as soon as it reaches
    /// `bound`.
    #[inline(always)]
    fn exact<const BOUNDED: bool>(
        &mut self,
        known: (LegSet, LegSet),
        sum: &mut f32,
        bound: f32,
    ) -> f32 {
        let (clear, mut repaired) = known;
        let mut total = 0.0;
        // `leg_bit(s)`, shifted along (out of the set from leg 32 on).
        let mut bit: LegSet = 1;
        for s in 0..self.stations.len() - 1 {
            let is_clear = if (repaired | clear) & bit != 0 {
                clear & bit != 0
            } else {
                self.leg_is_clear(s)
            };
            if is_clear {
                total += self.stations[s].straight;
            } else {
                total += self.repaired(s);
                if BOUNDED && repaired & bit == 0 {
                    repaired |= bit;
                    self.hot.insert(s);
                    let bound_now = self.raise(sum, s);
                    if bound_now >= bound {
                        self.hot.promote_leg(s);
                        return bound_now;
                    }
                }
            }
            bit <<= 1;
        }
        total
    }
}

impl Encoding for CorridorEncoding<'_> {
    fn dim(&self) -> usize {
        self.stations.len() - 2
    }

    fn bounds(&self, _i: usize) -> (f32, f32) {
        (-1.0, 1.0)
    }

    fn cost(&mut self, x: &[f32]) -> f32 {
        let mut sum = self.straight(x);
        let length = self.exact::<false>((0, 0), &mut sum, f32::INFINITY);
        if self.length_only() {
            return length;
        }
        self.blended(length, f32::INFINITY)
    }

    fn cost_below(&mut self, x: &[f32], bound: f32) -> f32 {
        if bound.is_nan() || bound == f32::INFINITY {
            return self.cost(x);
        }
        let legs = self.stations.len() - 1;
        let mut sum = self.straight(x);
        if sum * self.slack >= bound {
            return sum * self.slack;
        }
        // Legs that needed a repair in earlier evaluations are checked first (see
        // `HotLegs`): one of them is usually what makes a candidate worse than the bound.
        let mut repaired: LegSet = 0;
        let mut clear: LegSet = 0;
        let mut k = 0;
        while k < self.hot.len {
            let Some(&s) = self.hot.order.get(k) else {
                break;
            };
            let (s, bit) = (usize::from(s), leg_bit(usize::from(s)));
            k += 1;
            if s >= legs {
                continue;
            }
            if self.leg_is_clear(s) {
                clear |= bit;
            } else {
                repaired |= bit;
                let bound_now = self.raise(&mut sum, s);
                if bound_now >= bound {
                    self.hot.promote(k - 1);
                    return bound_now;
                }
            }
        }
        // The exact sum, in `cost`'s order; each newly repaired leg raises the bound again.
        let length = self.exact::<true>((clear, repaired), &mut sum, bound);
        // The terms are never negative: a length at or above the bound bounds the blend too.
        if self.length_only() || length >= bound {
            return length;
        }
        self.blended(length, bound)
    }

    fn decode(&mut self, x: &[f32], out: &mut PathView) -> Result<(), PlanError> {
        out.clear();
        let push = |out: &mut PathView, p: Point| {
            if out.last() != Some(&p) {
                out.push(p).map_err(|_| PlanError::CapacityExceeded)?;
            }
            Ok(())
        };
        let mut a = self.waypoint(0, x);
        push(out, a)?;
        for s in 0..self.stations.len() - 1 {
            let b = self.waypoint(s + 1, x);
            if !segment_is_clear(self.grid, a, b) {
                let (i, j) = (
                    self.stations[s].index as usize,
                    self.stations[s + 1].index as usize,
                );
                for &g in &self.guide[i..j] {
                    push(out, g)?;
                }
                push(out, self.stations[s + 1].point)?;
            }
            push(out, b)?;
            a = b;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Cell;
    use crate::grid::{Grid, words_for};
    use crate::path::{Path, length, validate};
    use crate::search::astar::{self, AStarNode, OpenSlot};

    type G = Grid<{ words_for(32, 32) }>;

    fn guide_for(g: &G, s: Cell, t: Cell) -> Path<256> {
        let mut nodes = [AStarNode::EMPTY; 1024];
        let mut open = [OpenSlot::EMPTY; 1024];
        let mut p = Path::new();
        astar::plan(g.view(), s, t, &mut nodes, &mut open, &mut p).unwrap();
        p
    }

    #[test]
    fn every_decision_vector_decodes_to_a_valid_path_of_its_cost() {
        let g = G::parse_rows(
            b"..........\n..@@@@@...\n..@.......\n..@.@@@@..\n....@.....\n@@@@@..@@.\n..........\n",
        )
        .unwrap();
        let (s, t) = (Cell::new(0, 0), Cell::new(0, 6));
        let guide = guide_for(&g, s, t);
        let mut buf = [Station::default(); 16];
        let mut enc = CorridorEncoding::build(g.view(), &guide, 2.0, 4.0, 14, &mut buf).unwrap();
        assert!(enc.dim() >= 3);
        let mut state = 12345u32;
        for _ in 0..500 {
            let x: heapless::Vec<f32, 16> = (0..enc.dim())
                .map(|_| {
                    state ^= state << 13;
                    state ^= state >> 17;
                    state ^= state << 5;
                    (state % 2001) as f32 / 1000.0 - 1.0
                })
                .collect();
            let mut p: Path<512> = Path::new();
            enc.decode(&x, &mut p).unwrap();
            assert_eq!(validate(g.view(), &p, s, t), Ok(()), "{x:?}");
            assert!((length(&p) - enc.cost(&x)).abs() < 1e-3);
        }
    }

    #[test]
    fn zero_offsets_follow_the_guide_and_extents_stay_clear() {
        let g = G::parse_rows(b"........\n.@@@@@@.\n........\n").unwrap();
        let (s, t) = (Cell::new(0, 0), Cell::new(7, 2));
        let guide = guide_for(&g, s, t);
        let mut buf = [Station::default(); 8];
        let mut enc = CorridorEncoding::build(g.view(), &guide, 1.0, 3.0, 6, &mut buf).unwrap();
        let zero = [0.0; 6];
        assert!((enc.cost(&zero[..enc.dim()]) - length(&guide)).abs() < 1e-4);
        for st in enc.stations {
            for sign in [-1.0, 1.0] {
                let p = st.slide(sign);
                assert!(segment_is_clear(g.view(), st.point, p));
            }
        }
    }

    #[test]
    fn out_of_range_variables_cost_as_clamped() {
        let g = G::parse_rows(b"..........\n..@@@@@...\n..@.......\n..........\n").unwrap();
        let guide = guide_for(&g, Cell::new(0, 0), Cell::new(9, 2));
        let mut buf = [Station::default(); 16];
        let mut enc = CorridorEncoding::build(g.view(), &guide, 1.5, 3.0, 14, &mut buf).unwrap();
        let n = enc.dim();
        assert!(n >= 3);
        let odd = [1.5, f32::NAN, -f32::INFINITY, -0.0, 1.0000001, -1.0, 0.25];
        let x: heapless::Vec<f32, 16> = (0..n).map(|k| odd[k % odd.len()]).collect();
        let clamped: heapless::Vec<f32, 16> = x.iter().map(|&v| offset_of(v)).collect();
        let want = enc.cost(&clamped);
        assert_eq!(enc.cost(&x).to_bits(), want.to_bits());
        // The waypoints were placed at the clamped offsets, also when the only variable out
        // of range is the next float above 1.
        let mut barely = clamped.clone();
        barely[1] = 1.0000001;
        for x in [&x, &barely] {
            enc.cost(x);
            for (st, &v) in enc.stations[1..=n].iter().zip(x.iter()) {
                assert_eq!(st.offset.to_bits(), offset_of(v).to_bits(), "{v}");
            }
        }
        // Bounded: the exact cost below a higher bound, a lower bound at or above a lower one.
        assert_eq!(enc.cost_below(&x, want + 1.0).to_bits(), want.to_bits());
        assert!(enc.cost_below(&x, want - 1.0) >= want - 1.0);
        // Fewer variables than stations: the missing ones are 0.
        let short = &clamped[..n - 1];
        let mut padded = clamped.clone();
        padded[n - 1] = 0.0;
        assert_eq!(enc.cost(short).to_bits(), enc.cost(&padded).to_bits());
    }

    #[test]
    fn hot_legs_keep_the_last_decisive_first() {
        let mut hot = HotLegs::EMPTY;
        for s in [3, 7, 3, 40, 1] {
            hot.insert(s);
        }
        // Leg 40 is beyond a leg set; 3 is in once.
        assert_eq!(&hot.order[..hot.len], &[3, 7, 1]);
        hot.promote(2);
        assert_eq!(&hot.order[..hot.len], &[1, 3, 7]);
        hot.promote_leg(7);
        hot.promote_leg(9);
        assert_eq!(&hot.order[..hot.len], &[7, 1, 3]);
        assert_eq!(hot.set, (1 << 1) | (1 << 3) | (1 << 7));
        for s in 0..32 {
            hot.insert(s);
        }
        assert_eq!(hot.len, 32);
    }

    #[test]
    fn bad_parameters_are_errors() {
        let g = G::new(4, 4).unwrap();
        let guide = guide_for(&g, Cell::new(0, 0), Cell::new(3, 3));
        let mut buf = [Station::default(); 8];
        assert!(CorridorEncoding::build(g.view(), &guide, f32::NAN, 3.0, 4, &mut buf).is_err());
        assert!(CorridorEncoding::build(g.view(), &guide, 1.0, 0.0, 4, &mut buf).is_err());
        assert!(CorridorEncoding::build(g.view(), &guide[..1], 1.0, 1.0, 4, &mut buf).is_err());
    }
}

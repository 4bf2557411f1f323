//! The plane-by-plane encoding (SPEC section 4, `Zhu2025Orchard` section 1.2).
//!
//! The straight line from start `S` to goal `G` is cut into `n + 1` equal parts; the `n`
//! planes through the cut points are perpendicular to it (vertical planes). Decision variable
//! `t_j` is the signed lateral offset (km, positive to the left of `S -> G`) of the path in
//! plane `j`, so waypoint `j` is `S + j/(n+1) (G - S) + t_j n_left`. Each `t_j` is bounded so
//! that the waypoint stays on the map; the map is convex, so the whole polyline does.
//!
//! Heights: in [`HeightMode::Terrain`] (the default, a ground robot) the height is the
//! terrain's; in [`HeightMode::Free`] (`Zhu2025Orchard`'s literal reading, `d = 2n`) variables
//! `n..2n` are the waypoints' heights, bounded by the terrain's range, and the objective
//! penalises waypoints below the ground.

use super::{Point3, TerrainError, TerrainView};
use crate::optim::{Bounds, OptimError};

/// The most interior planes an encoding can have.
pub const MAX_PLANES: usize = 62;

/// How waypoint heights are obtained.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum HeightMode {
    /// Heights follow the terrain (ground robot); `n` decision variables.
    #[default]
    Terrain,
    /// Literal mode: heights are decision variables too; `2n` variables.
    Free,
}

/// The plane-by-plane encoding of one start/goal pair on one map.
#[derive(Debug, Clone)]
pub struct PlaneEncoding {
    start: (f32, f32),
    goal: (f32, f32),
    planes: usize,
    mode: HeightMode,
    normal: (f32, f32),
    lo: [f32; MAX_PLANES],
    hi: [f32; MAX_PLANES],
    z_range: (f32, f32),
    extent: (f32, f32),
}

impl PlaneEncoding {
    /// `planes` interior planes between `start` and `goal` (km) on `map`.
    pub fn new(
        map: &TerrainView<'_>,
        start: (f32, f32),
        goal: (f32, f32),
        planes: usize,
        mode: HeightMode,
    ) -> Result<Self, TerrainError> {
        if planes == 0 {
            return Err(TerrainError::InvalidParameter("planes"));
        }
        if planes > MAX_PLANES {
            return Err(TerrainError::CapacityExceeded);
        }
        if !map.contains(start.0, start.1) || !map.contains(goal.0, goal.1) {
            return Err(TerrainError::OutsideMap);
        }
        let (dx, dy) = (goal.0 - start.0, goal.1 - start.1);
        let len = crate::math::sqrt(dx * dx + dy * dy);
        // NaN counts as zero here: `len > 0.0` is false for both.
        if len.is_nan() || len <= 0.0 {
            return Err(TerrainError::InvalidParameter("start equals goal"));
        }
        let normal = (-dy / len, dx / len);
        let extent = map.extent();
        let mut lo = [0.0; MAX_PLANES];
        let mut hi = [0.0; MAX_PLANES];
        for j in 0..planes {
            let f = (j + 1) as f32 / (planes + 1) as f32;
            let c = (start.0 + f * dx, start.1 + f * dy);
            let (mut a, mut b) = (f32::NEG_INFINITY, f32::INFINITY);
            for (cv, nv, max) in [(c.0, normal.0, extent.0), (c.1, normal.1, extent.1)] {
                if nv.abs() > 1e-9 {
                    let t0 = (0.0 - cv) / nv;
                    let t1 = (max - cv) / nv;
                    a = a.max(t0.min(t1));
                    b = b.min(t0.max(t1));
                }
            }
            // Inside the map by construction (convex map, `c` on the segment S-G).
            lo[j] = a.min(0.0);
            hi[j] = b.max(0.0);
        }
        Ok(Self {
            start,
            goal,
            planes,
            mode,
            normal,
            lo,
            hi,
            z_range: map.range(),
            extent,
        })
    }

    /// Number of interior planes `n`.
    pub fn planes(&self) -> usize {
        self.planes
    }

    /// The height mode.
    pub fn mode(&self) -> HeightMode {
        self.mode
    }

    /// Start `(x, y)` (km).
    pub fn start(&self) -> (f32, f32) {
        self.start
    }

    /// Goal `(x, y)` (km).
    pub fn goal(&self) -> (f32, f32) {
        self.goal
    }

    /// Number of decision variables: `n`, or `2n` in the free-height mode.
    pub fn dim(&self) -> usize {
        match self.mode {
            HeightMode::Terrain => self.planes,
            HeightMode::Free => 2 * self.planes,
        }
    }

    /// Bounds of variable `i` (`(0, 0)` beyond the dimension).
    pub fn bounds(&self, i: usize) -> (f32, f32) {
        if i < self.planes {
            (self.lo[i], self.hi[i])
        } else if i < self.dim() {
            self.z_range
        } else {
            (0.0, 0.0)
        }
    }

    /// The optimizer's box.
    pub fn bounds_box<const D: usize>(&self) -> Result<Bounds<D>, OptimError> {
        let mut lo = [0.0f32; D];
        let mut hi = [0.0f32; D];
        let dim = self.dim();
        if dim > D {
            return Err(OptimError::DimensionOutOfRange);
        }
        for i in 0..dim {
            (lo[i], hi[i]) = self.bounds(i);
        }
        Bounds::from_slices(&lo[..dim], &hi[..dim])
    }

    /// The horizontal waypoint of plane `j` (0-based) at lateral offset `t`, clamped onto the
    /// map.
    pub fn waypoint(&self, j: usize, t: f32) -> (f32, f32) {
        let f = (j + 1) as f32 / (self.planes + 1) as f32;
        let t = if t.is_finite() { t } else { 0.0 };
        let x = self.start.0 + f * (self.goal.0 - self.start.0) + t * self.normal.0;
        let y = self.start.1 + f * (self.goal.1 - self.start.1) + t * self.normal.1;
        (x.max(0.0).min(self.extent.0), y.max(0.0).min(self.extent.1))
    }

    /// Writes the `n + 2` waypoints (start, one per plane, goal) of `x` into `out` and returns
    /// their number. Heights are the terrain's, or `x[n + j]` in the free mode (start and goal
    /// on the ground). Errors if `x` is shorter than [`dim`](Self::dim) or `out` too small.
    pub fn decode(
        &self,
        map: &TerrainView<'_>,
        x: &[f32],
        out: &mut [Point3],
    ) -> Result<usize, TerrainError> {
        let n = self.planes;
        if x.len() < self.dim() {
            return Err(TerrainError::InvalidParameter("decision vector too short"));
        }
        if out.len() < n + 2 {
            return Err(TerrainError::CapacityExceeded);
        }
        let ground = |p: (f32, f32)| Point3 {
            x: p.0,
            y: p.1,
            z: map.height_clamped(p.0, p.1),
        };
        out[0] = ground(self.start);
        for j in 0..n {
            let mut p = ground(self.waypoint(j, x[j]));
            if self.mode == HeightMode::Free {
                let z = x[n + j];
                p.z = if z.is_finite() { z } else { p.z };
            }
            out[j + 1] = p;
        }
        out[n + 1] = ground(self.goal);
        Ok(n + 2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::terrain::Heightmap;

    #[test]
    fn zero_offsets_decode_to_the_straight_line_and_bounds_stay_on_the_map() {
        let map = Heightmap::<484>::from_samples(22, 22, 1.0, &[0.5; 484]).unwrap();
        let v = map.view();
        let enc =
            PlaneEncoding::new(&v, (1.0, 15.0), (21.0, 8.0), 20, HeightMode::Terrain).unwrap();
        assert_eq!(enc.dim(), 20);
        let mut out = [Point3::default(); 22];
        assert_eq!(enc.decode(&v, &[0.0; 20], &mut out).unwrap(), 22);
        for (k, p) in out.iter().enumerate() {
            let f = k as f32 / 21.0;
            assert!((p.x - (1.0 + 20.0 * f)).abs() < 1e-4 && (p.y - (15.0 - 7.0 * f)).abs() < 1e-4);
            assert_eq!(p.z, 0.5);
        }
        for j in 0..20 {
            let (lo, hi) = enc.bounds(j);
            assert!(lo < 0.0 && hi > 0.0);
            for t in [lo, hi] {
                let (x, y) = enc.waypoint(j, t);
                assert!(v.contains(x, y));
            }
            // The bounds are tight: one of the two ends touches the border.
            let (x, y) = enc.waypoint(j, hi);
            assert!(x < 1e-3 || y < 1e-3 || x > 21.0 - 1e-3 || y > 21.0 - 1e-3);
        }
        let b = enc.bounds_box::<64>().unwrap();
        assert_eq!(b.dim(), 20);
        let free = PlaneEncoding::new(&v, (1.0, 15.0), (21.0, 8.0), 20, HeightMode::Free).unwrap();
        assert_eq!(free.dim(), 40);
        let mut x = [0.0f32; 40];
        x[20..].fill(1.25);
        free.decode(&v, &x, &mut out).unwrap();
        assert_eq!(out[3].z, 1.25);
        assert_eq!(out[21].z, 0.5);
    }

    #[test]
    fn errors() {
        let map = Heightmap::<16>::from_samples(4, 4, 1.0, &[0.0; 16]).unwrap();
        let v = map.view();
        let e = |s, g, n| PlaneEncoding::new(&v, s, g, n, HeightMode::Terrain).err();
        assert_eq!(
            e((0.0, 0.0), (3.0, 3.0), 0),
            Some(TerrainError::InvalidParameter("planes"))
        );
        assert_eq!(
            e((0.0, 0.0), (3.0, 3.0), 63),
            Some(TerrainError::CapacityExceeded)
        );
        assert_eq!(e((0.0, 0.0), (3.5, 3.0), 5), Some(TerrainError::OutsideMap));
        assert_eq!(
            e((f32::NAN, 0.0), (3.0, 3.0), 5),
            Some(TerrainError::OutsideMap)
        );
        assert!(e((1.0, 1.0), (1.0, 1.0), 5).is_some());
        let enc = PlaneEncoding::new(&v, (0.0, 0.0), (3.0, 3.0), 5, HeightMode::Terrain).unwrap();
        let mut out = [Point3::default(); 6];
        assert_eq!(
            enc.decode(&v, &[0.0; 5], &mut out).err(),
            Some(TerrainError::CapacityExceeded)
        );
        let mut out = [Point3::default(); 7];
        assert!(enc.decode(&v, &[0.0; 4], &mut out).is_err());
        assert!(enc.bounds_box::<4>().is_err());
    }
}

//! 3D terrain planning (SPEC section 4, `Zhu2025Orchard`): a heightmap, cylinder and cone obstacles,
//! the plane-by-plane path encoding, `Zhu2025Orchard`'s objective and a plane-by-plane ACO.
//!
//! Behind the `terrain` feature (on by default).
//!
//! # Units and axes
//! One unit system, **kilometres**, horizontally and vertically (`Zhu2025Orchard`'s map is
//! 21 km x 21 km x 2 km). A heightmap of `w x h` samples with spacing `s` km covers
//! `[0, (w - 1) s] x [0, (h - 1) s]`; sample `(i, j)` is the height at `(i s, j s)`, stored
//! row by row (`z[j * w + i]`). With `s = 1` and `22 x 22` samples, `Zhu2025Orchard`'s 1-based
//! coordinates (start `(1, 15)`, goal `(21, 8)`, obstacles at `(11, 16)`, `(12, 4)`) are used
//! as they are printed.
//!
//! A ground robot's height follows the terrain; the paper's start/goal heights (1400, 1000)
//! are not used by the default mode.
//!
//! Modules:
//! - [`obstacles`]: vertical cylinders and cones, distances and inside tests;
//! - [`planes`]: the plane-by-plane encoding (lateral offset per interior plane, heights as
//!   decision variables in the literal mode);
//! - [`objective`]: `F = w1 E + w2 L + (1 - w1 - w2) T` with `Zhu2025Orchard`'s energy eq. (3);
//! - [`aco`]: the plane-by-plane discrete ant colony.
//!
//! ```
//! use planner_core::terrain::{Heightmap, Peaks};
//!
//! let map = Heightmap::<484>::peaks(22, 22, 1.0, &Peaks::zhu2025_orchard(), 7)?;
//! let view = map.view();
//! let z = view.height(10.5, 3.25)?;
//! assert!(z >= 0.0 && z <= 2.0);
//! # Ok::<(), planner_core::terrain::TerrainError>(())
//! ```

pub mod aco;
pub mod objective;
pub mod obstacles;
pub mod planes;

use crate::optim::random::Random;

/// Why a terrain operation refused its input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum TerrainError {
    /// A size is below 2 x 2 samples, or the samples do not match `w x h`.
    InvalidSize,
    /// More samples, planes or nodes than the fixed capacity.
    CapacityExceeded,
    /// A named parameter is NaN, infinite or out of its range.
    InvalidParameter(&'static str),
    /// A query point (or the start or goal) lies outside the map.
    OutsideMap,
    /// The start or the goal lies inside an obstacle.
    InsideObstacle,
}

impl core::fmt::Display for TerrainError {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            Self::InvalidSize => f.write_str("heightmap size invalid or samples do not match it"),
            Self::CapacityExceeded => f.write_str("size beyond the fixed capacity"),
            Self::InvalidParameter(p) => write!(f, "invalid parameter `{p}`"),
            Self::OutsideMap => f.write_str("point outside the map"),
            Self::InsideObstacle => f.write_str("start or goal inside an obstacle"),
        }
    }
}

/// A point in kilometres; `z` is the height.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Point3 {
    /// East (km).
    pub x: f32,
    /// North (km).
    pub y: f32,
    /// Height (km).
    pub z: f32,
}

/// A borrowed heightmap: `w x h` samples, spacing `spacing` km, row by row.
#[derive(Debug, Clone, Copy)]
pub struct TerrainView<'a> {
    w: usize,
    h: usize,
    spacing: f32,
    z: &'a [f32],
}

impl<'a> TerrainView<'a> {
    /// A view of `z` (`w * h` finite samples, row by row) with spacing `spacing` km.
    pub fn new(w: usize, h: usize, spacing: f32, z: &'a [f32]) -> Result<Self, TerrainError> {
        if w < 2 || h < 2 || w.checked_mul(h) != Some(z.len()) {
            return Err(TerrainError::InvalidSize);
        }
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(TerrainError::InvalidParameter("spacing"));
        }
        if z.iter().any(|v| !v.is_finite()) {
            return Err(TerrainError::InvalidParameter("height sample"));
        }
        Ok(Self { w, h, spacing, z })
    }

    /// Samples per row.
    pub fn width(&self) -> usize {
        self.w
    }

    /// Rows.
    pub fn height_samples(&self) -> usize {
        self.h
    }

    /// Sample spacing (km).
    pub fn spacing(&self) -> f32 {
        self.spacing
    }

    /// The samples, row by row.
    pub fn samples(&self) -> &'a [f32] {
        self.z
    }

    /// Extent `(x_max, y_max)` in km; the map is `[0, x_max] x [0, y_max]`.
    pub fn extent(&self) -> (f32, f32) {
        (
            (self.w - 1) as f32 * self.spacing,
            (self.h - 1) as f32 * self.spacing,
        )
    }

    /// Whether `(x, y)` lies on the map (borders included).
    pub fn contains(&self, x: f32, y: f32) -> bool {
        let (xm, ym) = self.extent();
        x >= 0.0 && y >= 0.0 && x <= xm && y <= ym
    }

    /// The lowest and highest sample.
    pub fn range(&self) -> (f32, f32) {
        self.z
            .iter()
            .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(*v), hi.max(*v))
            })
    }

    fn sample(&self, i: usize, j: usize) -> f32 {
        self.z.get(j * self.w + i).copied().unwrap_or(0.0)
    }

    /// The cell containing `(x, y)` and the fractions inside it (caller checked `contains`).
    fn locate(&self, x: f32, y: f32) -> (usize, usize, f32, f32) {
        let gx = x / self.spacing;
        let gy = y / self.spacing;
        let i = (crate::math::floor_i(gx).max(0) as usize).min(self.w - 2);
        let j = (crate::math::floor_i(gy).max(0) as usize).min(self.h - 2);
        (i, j, gx - i as f32, gy - j as f32)
    }

    /// Bilinear height at `(x, y)`; [`TerrainError::OutsideMap`] off the map or for NaN.
    pub fn height(&self, x: f32, y: f32) -> Result<f32, TerrainError> {
        if !self.contains(x, y) {
            return Err(TerrainError::OutsideMap);
        }
        Ok(self.height_clamped(x, y))
    }

    /// Bilinear height at `(x, y)` clamped onto the map (NaN reads as the origin).
    pub fn height_clamped(&self, x: f32, y: f32) -> f32 {
        let (xm, ym) = self.extent();
        let x = x.max(0.0).min(xm);
        let y = y.max(0.0).min(ym);
        let (i, j, fx, fy) = self.locate(x, y);
        let z00 = self.sample(i, j);
        let z10 = self.sample(i + 1, j);
        let z01 = self.sample(i, j + 1);
        let z11 = self.sample(i + 1, j + 1);
        let a = z00 + (z10 - z00) * fx;
        let b = z01 + (z11 - z01) * fx;
        a + (b - a) * fy
    }

    /// The gradient `(dz/dx, dz/dy)` of the bilinear surface at `(x, y)`.
    pub fn gradient(&self, x: f32, y: f32) -> Result<(f32, f32), TerrainError> {
        if !self.contains(x, y) {
            return Err(TerrainError::OutsideMap);
        }
        let (i, j, fx, fy) = self.locate(x, y);
        let z00 = self.sample(i, j);
        let z10 = self.sample(i + 1, j);
        let z01 = self.sample(i, j + 1);
        let z11 = self.sample(i + 1, j + 1);
        let dx = ((z10 - z00) * (1.0 - fy) + (z11 - z01) * fy) / self.spacing;
        let dy = ((z01 - z00) * (1.0 - fx) + (z11 - z10) * fx) / self.spacing;
        Ok((dx, dy))
    }

    /// Slope at `(x, y)`: the gradient's magnitude (rise over run, dimensionless).
    pub fn slope(&self, x: f32, y: f32) -> Result<f32, TerrainError> {
        let (dx, dy) = self.gradient(x, y)?;
        Ok(crate::math::sqrt(dx * dx + dy * dy))
    }
}

/// The "sum of smooth peaks" generator: `z = base + sum_k h_k exp(-((x - x_k)/s_k)^2 -
/// ((y - y_k)/s_k)^2)`, clamped to `[0, max_height]`.
///
/// Draw order (one [`Random`] seeded with the seed): per peak `x_k`, `y_k` (uniform on the
/// map), `h_k` (uniform in `height`), `s_k` (uniform in `width`).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Peaks {
    /// Number of peaks, `1..=64`.
    pub count: u32,
    /// Base height (km).
    pub base: f32,
    /// Peak height range (km).
    pub height: (f32, f32),
    /// Peak width range (km, the Gaussian's `s`).
    pub width: (f32, f32),
    /// Heights are clamped to `[0, max_height]` (km).
    pub max_height: f32,
}

impl Peaks {
    /// Hilly orchard terrain like `Zhu2025Orchard`'s figures: 8 peaks of 0.4 to 1.6 km, 1.5 to 4 km
    /// wide, on a 0.2 km base, at most 2 km.
    pub const fn zhu2025_orchard() -> Self {
        Self {
            count: 8,
            base: 0.2,
            height: (0.4, 1.6),
            width: (1.5, 4.0),
            max_height: 2.0,
        }
    }

    fn validate(&self) -> Result<(), TerrainError> {
        let ok = |v: f32| v.is_finite() && v >= 0.0;
        if self.count == 0 || self.count > 64 {
            return Err(TerrainError::InvalidParameter("peaks.count"));
        }
        if !ok(self.base) {
            return Err(TerrainError::InvalidParameter("peaks.base"));
        }
        if !(ok(self.height.0) && ok(self.height.1) && self.height.0 <= self.height.1) {
            return Err(TerrainError::InvalidParameter("peaks.height"));
        }
        if !(ok(self.width.0) && ok(self.width.1) && self.width.0 > 0.0)
            || self.width.0 > self.width.1
        {
            return Err(TerrainError::InvalidParameter("peaks.width"));
        }
        if !(ok(self.max_height) && self.max_height > 0.0) {
            return Err(TerrainError::InvalidParameter("peaks.max_height"));
        }
        Ok(())
    }
}

/// A heightmap with a fixed capacity of `CELLS` samples.
#[derive(Debug, Clone)]
pub struct Heightmap<const CELLS: usize> {
    w: usize,
    h: usize,
    spacing: f32,
    z: [f32; CELLS],
}

impl<const CELLS: usize> Heightmap<CELLS> {
    /// A copy of `samples` (`w * h`, row by row).
    pub fn from_samples(
        w: usize,
        h: usize,
        spacing: f32,
        samples: &[f32],
    ) -> Result<Self, TerrainError> {
        TerrainView::new(w, h, spacing, samples)?;
        if samples.len() > CELLS {
            return Err(TerrainError::CapacityExceeded);
        }
        let mut z = [0.0; CELLS];
        z[..samples.len()].copy_from_slice(samples);
        Ok(Self { w, h, spacing, z })
    }

    /// A seeded "sum of smooth peaks" terrain of `w x h` samples.
    pub fn peaks(
        w: usize,
        h: usize,
        spacing: f32,
        peaks: &Peaks,
        seed: u64,
    ) -> Result<Self, TerrainError> {
        peaks.validate()?;
        if w < 2 || h < 2 {
            return Err(TerrainError::InvalidSize);
        }
        if w.checked_mul(h).is_none_or(|n| n > CELLS) {
            return Err(TerrainError::CapacityExceeded);
        }
        if !(spacing.is_finite() && spacing > 0.0) {
            return Err(TerrainError::InvalidParameter("spacing"));
        }
        let (xm, ym) = ((w - 1) as f32 * spacing, (h - 1) as f32 * spacing);
        let mut rng = Random::new(seed);
        let mut list = [(0.0f32, 0.0f32, 0.0f32, 1.0f32); 64];
        for p in list.iter_mut().take(peaks.count as usize) {
            let x = rng.range(0.0, xm);
            let y = rng.range(0.0, ym);
            let hk = rng.range(peaks.height.0, peaks.height.1);
            let s = rng.range(peaks.width.0, peaks.width.1);
            *p = (x, y, hk, s);
        }
        let mut z = [0.0; CELLS];
        for j in 0..h {
            for i in 0..w {
                let (x, y) = (i as f32 * spacing, j as f32 * spacing);
                let mut v = peaks.base;
                for &(px, py, hk, s) in list.iter().take(peaks.count as usize) {
                    let (dx, dy) = ((x - px) / s, (y - py) / s);
                    v += hk * libm::expf(-(dx * dx + dy * dy));
                }
                z[j * w + i] = v.max(0.0).min(peaks.max_height);
            }
        }
        Ok(Self { w, h, spacing, z })
    }

    /// The borrowed view with the queries.
    pub fn view(&self) -> TerrainView<'_> {
        TerrainView {
            w: self.w,
            h: self.h,
            spacing: self.spacing,
            z: self.z.get(..self.w * self.h).unwrap_or(&[]),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_reproduces_samples_and_planes() {
        // z = 0.1 x + 0.2 y is reproduced exactly by bilinear interpolation.
        let mut s = [0.0f32; 12];
        for j in 0..3 {
            for i in 0..4 {
                s[j * 4 + i] = 0.1 * i as f32 * 2.0 + 0.2 * j as f32 * 2.0;
            }
        }
        let map = Heightmap::<16>::from_samples(4, 3, 2.0, &s).unwrap();
        let v = map.view();
        assert_eq!(v.extent(), (6.0, 4.0));
        for &(x, y) in &[(0.0, 0.0), (6.0, 4.0), (3.3, 1.7), (5.99, 0.01)] {
            let z = v.height(x, y).unwrap();
            assert!((z - (0.1 * x + 0.2 * y)).abs() < 1e-5, "{x} {y} {z}");
            let (gx, gy) = v.gradient(x, y).unwrap();
            assert!((gx - 0.1).abs() < 1e-5 && (gy - 0.2).abs() < 1e-5);
            assert!((v.slope(x, y).unwrap() - libm::sqrtf(0.05)).abs() < 1e-5);
        }
        assert_eq!(v.height(-0.1, 0.0), Err(TerrainError::OutsideMap));
        assert_eq!(v.height(f32::NAN, 0.0), Err(TerrainError::OutsideMap));
        assert_eq!(v.height(0.0, 4.01), Err(TerrainError::OutsideMap));
    }

    #[test]
    fn errors_are_typed() {
        assert_eq!(
            Heightmap::<4>::from_samples(3, 3, 1.0, &[0.0; 9]).err(),
            Some(TerrainError::CapacityExceeded)
        );
        assert_eq!(
            Heightmap::<16>::from_samples(3, 3, 1.0, &[0.0; 8]).err(),
            Some(TerrainError::InvalidSize)
        );
        assert_eq!(
            Heightmap::<16>::from_samples(2, 2, f32::NAN, &[0.0; 4]).err(),
            Some(TerrainError::InvalidParameter("spacing"))
        );
        assert_eq!(
            Heightmap::<16>::from_samples(2, 2, 1.0, &[0.0, f32::NAN, 0.0, 0.0]).err(),
            Some(TerrainError::InvalidParameter("height sample"))
        );
        assert_eq!(
            Heightmap::<400>::peaks(22, 22, 1.0, &Peaks::zhu2025_orchard(), 1).err(),
            Some(TerrainError::CapacityExceeded)
        );
        let bad = Peaks {
            count: 0,
            ..Peaks::zhu2025_orchard()
        };
        assert!(Heightmap::<484>::peaks(22, 22, 1.0, &bad, 1).is_err());
    }

    #[test]
    fn peaks_are_seeded_and_bounded() {
        let a = Heightmap::<961>::peaks(31, 31, 1.0, &Peaks::zhu2025_orchard(), 5).unwrap();
        let b = Heightmap::<961>::peaks(31, 31, 1.0, &Peaks::zhu2025_orchard(), 5).unwrap();
        let c = Heightmap::<961>::peaks(31, 31, 1.0, &Peaks::zhu2025_orchard(), 6).unwrap();
        assert_eq!(a.view().samples(), b.view().samples());
        assert_ne!(a.view().samples(), c.view().samples());
        let (lo, hi) = a.view().range();
        assert!(lo >= 0.2 - 1e-6 && hi <= 2.0 && hi > 0.6, "{lo} {hi}");
    }
}

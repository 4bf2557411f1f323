//! Vertical cylinders and cones standing on the terrain (`Zhu2025Orchard`'s obstacle models).
//!
//! A ground robot meets an obstacle at its foot, so both shapes block the disc of their base
//! radius; a cone narrows with height ([`Obstacle::radius_at`]) which only matters for
//! drawing and for the literal (free-height) mode, where the path's own height is used.

use super::TerrainError;

/// The shape of an obstacle.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum Shape {
    /// A vertical cylinder.
    Cylinder,
    /// A vertical cone, base on the ground.
    Cone,
}

/// A cylinder or cone: centre `(x, y)` (km), base radius `radius` (km), height `height` (km)
/// above its foot `base` (km, usually the terrain height at the centre).
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Obstacle {
    /// Cylinder or cone.
    pub shape: Shape,
    /// Centre, east (km).
    pub x: f32,
    /// Centre, north (km).
    pub y: f32,
    /// Base radius (km), positive.
    pub radius: f32,
    /// Height of the foot (km).
    pub base: f32,
    /// Height above the foot (km), positive.
    pub height: f32,
}

impl Obstacle {
    /// A cylinder of radius `radius` and height `height` standing at `(x, y)` on `base`.
    pub fn cylinder(
        x: f32,
        y: f32,
        radius: f32,
        base: f32,
        height: f32,
    ) -> Result<Self, TerrainError> {
        Self {
            shape: Shape::Cylinder,
            x,
            y,
            radius,
            base,
            height,
        }
        .validated()
    }

    /// A cone of base radius `radius` and height `height` standing at `(x, y)` on `base`.
    pub fn cone(x: f32, y: f32, radius: f32, base: f32, height: f32) -> Result<Self, TerrainError> {
        Self {
            shape: Shape::Cone,
            x,
            y,
            radius,
            base,
            height,
        }
        .validated()
    }

    /// `self` if every field is finite and radius and height are positive.
    pub fn validated(self) -> Result<Self, TerrainError> {
        if !(self.x.is_finite() && self.y.is_finite() && self.base.is_finite()) {
            return Err(TerrainError::InvalidParameter("obstacle centre"));
        }
        if !(self.radius.is_finite() && self.radius > 0.0) {
            return Err(TerrainError::InvalidParameter("obstacle radius"));
        }
        if !(self.height.is_finite() && self.height > 0.0) {
            return Err(TerrainError::InvalidParameter("obstacle height"));
        }
        Ok(self)
    }

    /// The horizontal radius at height `z` (0 above the top; the base radius below the foot).
    pub fn radius_at(&self, z: f32) -> f32 {
        let t = ((z - self.base) / self.height).max(0.0);
        match self.shape {
            Shape::Cylinder if t <= 1.0 => self.radius,
            Shape::Cone if t <= 1.0 => self.radius * (1.0 - t),
            _ => 0.0,
        }
    }

    /// Horizontal distance from `(px, py)` to the axis.
    pub fn axis_distance(&self, px: f32, py: f32) -> f32 {
        let (dx, dy) = (px - self.x, py - self.y);
        crate::math::sqrt(dx * dx + dy * dy)
    }

    /// Whether the ground point `(px, py)` is strictly inside the base disc.
    pub fn contains(&self, px: f32, py: f32) -> bool {
        self.axis_distance(px, py) < self.radius
    }

    /// Horizontal distance from the axis to the segment `a -> b` (exact).
    pub fn segment_distance(&self, a: (f32, f32), b: (f32, f32)) -> f32 {
        let (ux, uy) = (b.0 - a.0, b.1 - a.1);
        let (wx, wy) = (self.x - a.0, self.y - a.1);
        let len2 = ux * ux + uy * uy;
        let t = if len2 > 0.0 {
            ((wx * ux + wy * uy) / len2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        self.axis_distance(a.0 + t * ux, a.1 + t * uy)
    }

    /// Clearance of the segment `a -> b` (horizontal): distance to the axis minus the base
    /// radius; negative when the segment cuts the base disc.
    pub fn segment_clearance(&self, a: (f32, f32), b: (f32, f32)) -> f32 {
        self.segment_distance(a, b) - self.radius
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances() {
        let c = Obstacle::cylinder(5.0, 5.0, 1.0, 0.0, 0.5).unwrap();
        assert!(c.contains(5.5, 5.5));
        assert!(!c.contains(6.0, 5.0));
        assert!((c.segment_distance((0.0, 7.0), (10.0, 7.0)) - 2.0).abs() < 1e-6);
        assert!((c.segment_clearance((0.0, 5.0), (3.0, 5.0)) - 1.0).abs() < 1e-6);
        assert!(c.segment_clearance((0.0, 5.0), (10.0, 5.0)) < 0.0);
        assert!((c.segment_distance((1.0, 1.0), (1.0, 1.0)) - libm::sqrtf(32.0)).abs() < 1e-5);
        let k = Obstacle::cone(0.0, 0.0, 3.0, 1.0, 0.6).unwrap();
        assert_eq!(k.radius_at(1.0), 3.0);
        assert!((k.radius_at(1.3) - 1.5).abs() < 1e-6);
        assert_eq!(k.radius_at(2.0), 0.0);
        assert_eq!(c.radius_at(0.4), 1.0);
        assert!(Obstacle::cylinder(0.0, 0.0, -1.0, 0.0, 1.0).is_err());
        assert!(Obstacle::cone(f32::NAN, 0.0, 1.0, 0.0, 1.0).is_err());
        assert!(Obstacle::cone(0.0, 0.0, 1.0, 0.0, 0.0).is_err());
    }
}

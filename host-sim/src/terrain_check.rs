//! An independent checker for 3D terrain paths (`Zhu2025Orchard`, SPEC section 4): `f64`
//! arithmetic, its own bilinear surface and its own obstacle shapes, written without
//! planner-core's terrain code, so a bug in the planner's geometry cannot hide itself.
//!
//! What "valid" means (SPEC section 4: a ground robot's height follows the terrain):
//! - the path runs from the start to the goal (horizontally);
//! - every point of every segment, sampled every `step` km, lies on the map
//!   `[0, (w - 1) s] x [0, (h - 1) s]`;
//! - [`Heights::OnGround`] (the default planning mode): every vertex lies on the surface
//!   (`|z - ground| <= tol`), and between vertices the robot drives on the ground, so the
//!   path's height at a sample is the ground's there;
//!   [`Heights::AtOrAbove`] (the literal, free-height mode): every vertex is at or above the
//!   ground (`z >= ground - tol`), and the height between vertices is the straight 3D segment's
//!   (the literal model constrains the vertices only; [`Report::max_depth_below_ground`] says
//!   how deep a segment dips);
//! - at every sample the horizontal distance to each obstacle's axis is larger than the
//!   obstacle's radius *at the path's height*: a cylinder's radius between its foot and its
//!   top, a cone's `radius (1 - (z - foot) / height)` (the base radius below the foot, nothing
//!   above the top / tip).
//!
//! The sampling misses an intrusion of depth below `step^2 / (8 radius)` at most; the default
//! step of 2.5 m makes that below a millimetre for the 1 km obstacles of `Zhu2025Orchard`.

/// A heightmap: `w x h` samples `z` (row by row) with spacing `spacing`.
#[derive(Debug, Clone, Copy)]
pub struct Ground<'a> {
    w: usize,
    h: usize,
    spacing: f64,
    z: &'a [f32],
}

impl<'a> Ground<'a> {
    /// `None` unless `w, h >= 2`, `z.len() == w h` and `spacing > 0`.
    pub fn new(w: usize, h: usize, spacing: f64, z: &'a [f32]) -> Option<Self> {
        (w >= 2 && h >= 2 && w.checked_mul(h) == Some(z.len()) && spacing > 0.0).then_some(Self {
            w,
            h,
            spacing,
            z,
        })
    }

    /// `(x_max, y_max)`.
    pub fn extent(&self) -> (f64, f64) {
        (
            (self.w - 1) as f64 * self.spacing,
            (self.h - 1) as f64 * self.spacing,
        )
    }

    /// Whether `(x, y)` is on the map, with tolerance `tol`.
    pub fn contains(&self, x: f64, y: f64, tol: f64) -> bool {
        let (xm, ym) = self.extent();
        x >= -tol && y >= -tol && x <= xm + tol && y <= ym + tol
    }

    /// Bilinear height at `(x, y)`, clamped onto the map.
    pub fn height(&self, x: f64, y: f64) -> f64 {
        let (xm, ym) = self.extent();
        let (u, v) = (
            x.clamp(0.0, xm) / self.spacing,
            y.clamp(0.0, ym) / self.spacing,
        );
        let col = (u.floor() as usize).min(self.w - 2);
        let row = (v.floor() as usize).min(self.h - 2);
        let (fu, fv) = (u - col as f64, v - row as f64);
        let at = |c: usize, r: usize| f64::from(self.z[r * self.w + c]);
        at(col, row) * (1.0 - fu) * (1.0 - fv)
            + at(col + 1, row) * fu * (1.0 - fv)
            + at(col, row + 1) * (1.0 - fu) * fv
            + at(col + 1, row + 1) * fu * fv
    }
}

/// An obstacle's shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    /// Vertical cylinder.
    Cylinder,
    /// Vertical cone, widest at its foot.
    Cone,
}

/// A vertical cylinder or cone: axis `(x, y)`, base radius, foot height and height above it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Solid {
    /// Shape.
    pub kind: Kind,
    /// Axis, east.
    pub x: f64,
    /// Axis, north.
    pub y: f64,
    /// Base radius.
    pub radius: f64,
    /// Height of the foot.
    pub foot: f64,
    /// Height above the foot.
    pub height: f64,
}

impl Solid {
    /// Horizontal radius at height `z`.
    pub fn radius_at(&self, z: f64) -> f64 {
        if z > self.foot + self.height {
            return 0.0;
        }
        match self.kind {
            Kind::Cylinder => self.radius,
            Kind::Cone => {
                let t = ((z - self.foot) / self.height).max(0.0);
                self.radius * (1.0 - t)
            }
        }
    }
}

/// How a path's heights relate to the ground.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Heights {
    /// A ground robot: vertices on the surface within `tol`, the ground's height in between.
    OnGround {
        /// Tolerance on the vertices' heights.
        tol: f64,
    },
    /// The literal mode: vertices at or above the ground (within `tol`), straight segments.
    AtOrAbove {
        /// Tolerance on the vertices' heights.
        tol: f64,
    },
}

/// Why a path is invalid.
#[derive(Debug, Clone, PartialEq)]
pub enum Violation {
    /// Fewer than two points.
    TooShort,
    /// The first point is not the start or the last not the goal.
    Endpoints,
    /// A sample of segment `segment` lies off the map.
    OffMap {
        /// Index of the segment's first vertex.
        segment: usize,
        /// The sample.
        at: (f64, f64),
    },
    /// Vertex `vertex` is off the surface (`OnGround`) or below it (`AtOrAbove`).
    Height {
        /// Index of the vertex.
        vertex: usize,
        /// Its height minus the ground's.
        gap: f64,
    },
    /// A sample of segment `segment` is inside obstacle `obstacle`.
    Collision {
        /// Index of the segment's first vertex.
        segment: usize,
        /// Index of the obstacle.
        obstacle: usize,
        /// The sample `(x, y, z)`.
        at: (f64, f64, f64),
        /// Horizontal distance to the axis minus the radius at `z` (negative or zero).
        clearance: f64,
    },
}

/// Measurements of a valid path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Report {
    /// 3D length of the polyline through the vertices.
    pub length: f64,
    /// Smallest clearance (distance to the axis minus the radius at the path's height) over
    /// all samples and obstacles (`+inf` without obstacles).
    pub min_clearance: f64,
    /// Smallest horizontal clearance to any obstacle's *base* disc (a ground robot meets the
    /// obstacles at their foot; `+inf` without obstacles).
    pub min_base_clearance: f64,
    /// Largest `|z - ground|` at a vertex.
    pub max_vertex_gap: f64,
    /// Largest depth of a straight segment below the ground between vertices (0 if none).
    pub max_depth_below_ground: f64,
    /// Number of samples checked.
    pub samples: usize,
}

/// Checks `path` (`[x, y, z]` points) from `start` to `goal` on `ground` among `solids`,
/// sampling every segment every `step` (and at both ends). See the module documentation.
pub fn check(
    ground: &Ground<'_>,
    solids: &[Solid],
    path: &[[f64; 3]],
    start: (f64, f64),
    goal: (f64, f64),
    heights: Heights,
    step: f64,
) -> Result<Report, Violation> {
    const END_TOL: f64 = 1e-4;
    const MAP_TOL: f64 = 1e-6;
    if path.len() < 2 {
        return Err(Violation::TooShort);
    }
    let near = |p: &[f64; 3], q: (f64, f64)| (p[0] - q.0).hypot(p[1] - q.1) <= END_TOL;
    if !near(&path[0], start) || !near(&path[path.len() - 1], goal) {
        return Err(Violation::Endpoints);
    }
    let mut report = Report {
        length: 0.0,
        min_clearance: f64::INFINITY,
        min_base_clearance: f64::INFINITY,
        max_vertex_gap: 0.0,
        max_depth_below_ground: 0.0,
        samples: 0,
    };
    for (vertex, p) in path.iter().enumerate() {
        let gap = p[2] - ground.height(p[0], p[1]);
        report.max_vertex_gap = report.max_vertex_gap.max(gap.abs());
        let bad = match heights {
            Heights::OnGround { tol } => gap.abs() > tol,
            Heights::AtOrAbove { tol } => gap < -tol,
        };
        if bad || !gap.is_finite() {
            return Err(Violation::Height { vertex, gap });
        }
    }
    let step = if step > 0.0 { step } else { 0.0025 };
    for (segment, w) in path.windows(2).enumerate() {
        let (a, b) = (w[0], w[1]);
        let (dx, dy, dz) = (b[0] - a[0], b[1] - a[1], b[2] - a[2]);
        report.length += (dx * dx + dy * dy + dz * dz).sqrt();
        let n = ((dx.hypot(dy) / step).ceil() as usize).max(1);
        for k in 0..=n {
            let f = k as f64 / n as f64;
            let (x, y) = (a[0] + f * dx, a[1] + f * dy);
            report.samples += 1;
            if !ground.contains(x, y, MAP_TOL) {
                return Err(Violation::OffMap {
                    segment,
                    at: (x, y),
                });
            }
            let g = ground.height(x, y);
            let z = match heights {
                Heights::OnGround { .. } => g,
                Heights::AtOrAbove { .. } => {
                    let z = a[2] + f * dz;
                    report.max_depth_below_ground = report.max_depth_below_ground.max(g - z);
                    z
                }
            };
            for (obstacle, s) in solids.iter().enumerate() {
                let d = (x - s.x).hypot(y - s.y);
                report.min_base_clearance = report.min_base_clearance.min(d - s.radius);
                let r = s.radius_at(z);
                if r <= 0.0 {
                    continue;
                }
                let clearance = d - r;
                report.min_clearance = report.min_clearance.min(clearance);
                if clearance <= 0.0 {
                    return Err(Violation::Collision {
                        segment,
                        obstacle,
                        at: (x, y, z),
                        clearance,
                    });
                }
            }
        }
    }
    Ok(report)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 11 x 11 km ramp `z = 0.05 x` sampled every km.
    fn ramp() -> Vec<f32> {
        (0..121).map(|i| 0.05 * (i % 11) as f32).collect()
    }

    fn draped(g: &Ground<'_>, pts: &[(f64, f64)]) -> Vec<[f64; 3]> {
        pts.iter().map(|&(x, y)| [x, y, g.height(x, y)]).collect()
    }

    const ON: Heights = Heights::OnGround { tol: 1e-4 };

    #[test]
    fn bilinear_is_exact_on_a_ramp() {
        let z = ramp();
        let g = Ground::new(11, 11, 1.0, &z).unwrap();
        for &(x, y) in &[(0.0, 0.0), (10.0, 10.0), (3.7, 8.2), (9.99, 0.5)] {
            assert!((g.height(x, y) - 0.05 * x).abs() < 1e-6);
        }
        assert!(Ground::new(11, 10, 1.0, &z).is_none());
    }

    #[test]
    fn accepts_a_detour_and_rejects_a_path_through_a_cylinder() {
        let z = ramp();
        let g = Ground::new(11, 11, 1.0, &z).unwrap();
        let cyl = [Solid {
            kind: Kind::Cylinder,
            x: 5.0,
            y: 5.0,
            radius: 1.0,
            foot: 0.25,
            height: 0.5,
        }];
        let (s, t) = ((1.0, 5.0), (9.0, 5.0));
        let detour = draped(&g, &[s, (5.0, 6.2), t]);
        let r = check(&g, &cyl, &detour, s, t, ON, 0.0025).unwrap();
        assert!(r.min_clearance > 0.0 && r.min_clearance < 0.2, "{r:?}");
        assert!(r.samples > 3000);
        // Straight through: rejected.
        let straight = draped(&g, &[s, t]);
        assert!(matches!(
            check(&g, &cyl, &straight, s, t, ON, 0.0025),
            Err(Violation::Collision { obstacle: 0, .. })
        ));
        // Vertices outside the disc but the segment between them cuts it (a chord): rejected.
        let chord = draped(&g, &[s, (4.0, 5.5), (6.0, 5.5), t]);
        assert!(matches!(
            check(&g, &cyl, &chord, s, t, ON, 0.0025),
            Err(Violation::Collision { segment: 1, .. })
        ));
        // Grazing the disc by 1 mm is caught with samples 2.5 m apart.
        let graze = draped(&g, &[s, (4.0, 5.999), (6.0, 5.999), t]);
        assert!(check(&g, &cyl, &graze, s, t, ON, 0.0025).is_err());
    }

    #[test]
    fn cones_narrow_with_height() {
        let z = vec![0.0f32; 121];
        let g = Ground::new(11, 11, 1.0, &z).unwrap();
        let cone = [Solid {
            kind: Kind::Cone,
            x: 5.0,
            y: 5.0,
            radius: 2.0,
            foot: 0.0,
            height: 1.0,
        }];
        let (s, t) = ((1.0, 6.5), (9.0, 6.5));
        // 1.5 km from the axis on the ground: inside the 2 km base.
        let low: Vec<[f64; 3]> = vec![[1.0, 6.5, 0.0], [9.0, 6.5, 0.0]];
        assert!(check(&g, &cone, &low, s, t, ON, 0.0025).is_err());
        // At 0.5 km high the radius is 1 km: a free-height path passes.
        let high: Vec<[f64; 3]> = vec![[1.0, 6.5, 0.0], [5.0, 6.5, 0.5], [9.0, 6.5, 0.0]];
        let r = check(
            &g,
            &cone,
            &high,
            s,
            t,
            Heights::AtOrAbove { tol: 1e-6 },
            0.0025,
        )
        .unwrap();
        assert!(r.min_clearance > 0.0 && r.min_base_clearance < 0.0, "{r:?}");
        // ... but not as a ground robot (its vertex is off the surface).
        assert!(matches!(
            check(&g, &cone, &high, s, t, ON, 0.0025),
            Err(Violation::Height { vertex: 1, .. })
        ));
        // Above the tip nothing blocks.
        assert_eq!(cone[0].radius_at(1.01), 0.0);
        assert_eq!(cone[0].radius_at(-1.0), 2.0);
    }

    #[test]
    fn rejects_off_map_off_ground_and_wrong_ends() {
        let z = ramp();
        let g = Ground::new(11, 11, 1.0, &z).unwrap();
        let (s, t) = ((1.0, 1.0), (9.0, 1.0));
        let out = draped(&g, &[s, (5.0, -0.5), t]);
        assert!(matches!(
            check(&g, &[], &out, s, t, ON, 0.0025),
            Err(Violation::OffMap { segment: 0, .. })
        ));
        let mut lifted = draped(&g, &[s, (5.0, 2.0), t]);
        assert!(check(&g, &[], &lifted, s, t, ON, 0.0025).is_ok());
        lifted[1][2] += 0.01;
        assert!(matches!(
            check(&g, &[], &lifted, s, t, ON, 0.0025),
            Err(Violation::Height { vertex: 1, .. })
        ));
        let above = Heights::AtOrAbove { tol: 1e-6 };
        assert!(check(&g, &[], &lifted, s, t, above, 0.0025).is_ok());
        lifted[1][2] -= 0.02;
        assert!(check(&g, &[], &lifted, s, t, above, 0.0025).is_err());
        let p = draped(&g, &[s, t]);
        assert_eq!(
            check(&g, &[], &p, s, (9.0, 2.0), ON, 0.0025),
            Err(Violation::Endpoints)
        );
        assert_eq!(
            check(&g, &[], &p[..1], s, t, ON, 0.0025),
            Err(Violation::TooShort)
        );
        let r = check(&g, &[], &p, s, t, ON, 0.0025).unwrap();
        assert!((r.length - 8.0f64.hypot(0.4)).abs() < 1e-9);
        assert_eq!(r.min_clearance, f64::INFINITY);
    }
}

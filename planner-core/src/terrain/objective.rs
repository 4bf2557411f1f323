//! `Zhu2025Orchard`'s objective `F = w1 E + w2 L + (1 - w1 - w2) T` (eq. (1)).
//!
//! - `L` (eq. (2)): the 3D length of the path. In the terrain mode each segment between two
//!   planes is the straight horizontal segment draped over the terrain, measured with
//!   `subdivisions` chords (1 = eq. (2) literally: one chord per plane step).
//! - `E` (eq. (3)): `E = E1 + sum_i (A v^2 + B a^2 + C mu + D l0) S_i (+ climb * ascent)`.
//!   With constant speed, acceleration, friction and load this is `E1 + k L`; the paper's
//!   tables show `E = 6.5 L` exactly, and [`EnergyModel::zhu2025_orchard`] is a split of `k = 6.5`
//!   (`E1 = 0`, no climb term). The `climb` term (energy per km of ascent) is ours, 0 by
//!   default.
//! - `T`: the printed term (sum of distances to obstacle centres, eqs. (4)-(6)) *rewards*
//!   approaching obstacles; SPEC replaces it by a penalty that is 0 when every segment keeps
//!   `radius + margin` from every obstacle axis and at least `penalty` otherwise, growing
//!   linearly with the depth of the intrusion so that optimizers are led out. In the free
//!   (literal) height mode, waypoints below the ground cost `penalty (1 + depth)` each.

use super::obstacles::Obstacle;
use super::planes::{HeightMode, MAX_PLANES, PlaneEncoding};
use super::{Point3, TerrainError, TerrainView};
use crate::optim::Objective;

/// `Zhu2025Orchard`'s energy model, eq. (3), with constant per-segment factors.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct EnergyModel {
    /// `E1`, a fixed energy (e.g. start-up).
    pub e1: f32,
    /// `A`, weight of the speed term.
    pub a: f32,
    /// `v`, speed.
    pub v: f32,
    /// `B`, weight of the acceleration term.
    pub b: f32,
    /// `a`, acceleration.
    pub acc: f32,
    /// `C`, weight of the friction term.
    pub c: f32,
    /// `mu`, friction coefficient.
    pub mu: f32,
    /// `D`, weight of the load term.
    pub d: f32,
    /// `l0`, load.
    pub load: f32,
    /// Energy per km of ascent (ours; 0 in `Zhu2025Orchard`).
    pub climb: f32,
}

impl EnergyModel {
    /// `E = 6.5 L`: `A v^2 = 1 * 2^2`, `B a^2 = 1 * 0.5^2`, `C mu = 1 * 0.25`, `D l0 = 1 * 2`.
    pub const fn zhu2025_orchard() -> Self {
        Self {
            e1: 0.0,
            a: 1.0,
            v: 2.0,
            b: 1.0,
            acc: 0.5,
            c: 1.0,
            mu: 0.25,
            d: 1.0,
            load: 2.0,
            climb: 0.0,
        }
    }

    /// Energy per km of path, `A v^2 + B a^2 + C mu + D l0`.
    pub fn per_km(&self) -> f32 {
        self.a * self.v * self.v
            + self.b * self.acc * self.acc
            + self.c * self.mu
            + self.d * self.load
    }

    /// `E` of a path of length `length` and total ascent `ascent`.
    pub fn energy(&self, length: f32, ascent: f32) -> f32 {
        self.e1 + self.per_km() * length + self.climb * ascent
    }

    fn validate(&self) -> Result<(), TerrainError> {
        let all = [
            self.e1, self.a, self.v, self.b, self.acc, self.c, self.mu, self.d, self.load,
            self.climb,
        ];
        if all.iter().all(|v| v.is_finite() && *v >= 0.0) {
            Ok(())
        } else {
            Err(TerrainError::InvalidParameter("energy model"))
        }
    }
}

impl Default for EnergyModel {
    fn default() -> Self {
        Self::zhu2025_orchard()
    }
}

/// Weights and constants of the objective.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct ObjectiveParams {
    /// `w1`, weight of the energy, `>= 0`.
    pub w1: f32,
    /// `w2`, weight of the length, `>= 0`; `w1 + w2 < 1` (the rest weighs the obstacles).
    pub w2: f32,
    /// The energy model.
    pub energy: EnergyModel,
    /// Safety margin around every obstacle (km), `>= 0`.
    pub margin: f32,
    /// Penalty of one intrusion, `> 0`, far above any `w1 E + w2 L` on the map.
    pub penalty: f32,
    /// Chords per segment when draping it over the terrain, `1..=16`.
    pub subdivisions: u32,
}

impl ObjectiveParams {
    /// `Zhu2025Orchard` as SPEC resolves it; the paper prints no weights: `w1 = w2 = 0.4` (ours).
    pub const fn zhu2025_orchard() -> Self {
        Self {
            w1: 0.4,
            w2: 0.4,
            energy: EnergyModel::zhu2025_orchard(),
            margin: 0.05,
            penalty: 1.0e4,
            subdivisions: 4,
        }
    }

    fn validate(&self) -> Result<(), TerrainError> {
        let ok = |v: f32| v.is_finite() && v >= 0.0;
        if !(ok(self.w1) && ok(self.w2) && self.w1 + self.w2 < 1.0) {
            return Err(TerrainError::InvalidParameter("weights"));
        }
        if !ok(self.margin) {
            return Err(TerrainError::InvalidParameter("margin"));
        }
        if !(ok(self.penalty) && self.penalty > 0.0) {
            return Err(TerrainError::InvalidParameter("penalty"));
        }
        if self.subdivisions == 0 || self.subdivisions > 16 {
            return Err(TerrainError::InvalidParameter("subdivisions"));
        }
        self.energy.validate()
    }
}

impl Default for ObjectiveParams {
    fn default() -> Self {
        Self::zhu2025_orchard()
    }
}

/// The parts of one evaluation.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct Evaluation {
    /// `F`.
    pub cost: f32,
    /// `L` (km).
    pub length: f32,
    /// `E`.
    pub energy: f32,
    /// `T`, the obstacle (and underground) penalty; 0 for a valid path.
    pub obstacle: f32,
    /// Total ascent (km).
    pub ascent: f32,
    /// Smallest horizontal clearance of any segment to any obstacle's base disc (km,
    /// `+inf` without obstacles).
    pub min_clearance: f32,
}

/// The objective of one planning problem: map, obstacles, encoding and parameters.
#[derive(Debug, Clone)]
pub struct TerrainObjective<'a> {
    map: TerrainView<'a>,
    obstacles: &'a [Obstacle],
    encoding: PlaneEncoding,
    params: ObjectiveParams,
}

impl<'a> TerrainObjective<'a> {
    /// Validates the parameters and obstacles and checks that start and goal are outside
    /// every obstacle (with the margin).
    pub fn new(
        map: TerrainView<'a>,
        obstacles: &'a [Obstacle],
        encoding: PlaneEncoding,
        params: ObjectiveParams,
    ) -> Result<Self, TerrainError> {
        params.validate()?;
        for o in obstacles {
            o.validated()?;
            for p in [encoding.start(), encoding.goal()] {
                if o.axis_distance(p.0, p.1) <= o.radius + params.margin {
                    return Err(TerrainError::InsideObstacle);
                }
            }
        }
        Ok(Self {
            map,
            obstacles,
            encoding,
            params,
        })
    }

    /// The map.
    pub fn map(&self) -> &TerrainView<'a> {
        &self.map
    }

    /// The obstacles.
    pub fn obstacles(&self) -> &'a [Obstacle] {
        self.obstacles
    }

    /// The encoding.
    pub fn encoding(&self) -> &PlaneEncoding {
        &self.encoding
    }

    /// The parameters.
    pub fn params(&self) -> &ObjectiveParams {
        &self.params
    }

    /// The waypoints of `x` (see [`PlaneEncoding::decode`]).
    pub fn waypoints(&self, x: &[f32], out: &mut [Point3]) -> Result<usize, TerrainError> {
        self.encoding.decode(&self.map, x, out)
    }

    /// The path a robot drives: the waypoints with each segment draped over the terrain in
    /// `subdivisions` chords (the free mode: the waypoints themselves). Returns the number of
    /// points written.
    pub fn ground_path(&self, x: &[f32], out: &mut [Point3]) -> Result<usize, TerrainError> {
        let mut wp = [Point3::default(); MAX_PLANES + 2];
        let n = self.encoding.decode(&self.map, x, &mut wp)?;
        let k = match self.encoding.mode() {
            HeightMode::Terrain => self.params.subdivisions as usize,
            HeightMode::Free => 1,
        };
        let total = (n - 1) * k + 1;
        if out.len() < total {
            return Err(TerrainError::CapacityExceeded);
        }
        let mut m = 0;
        for w in wp[..n].windows(2) {
            for s in 0..k {
                out[m] = self.lerp_ground(w[0], w[1], s, k);
                m += 1;
            }
        }
        out[m] = wp[n - 1];
        Ok(m + 1)
    }

    fn lerp_ground(&self, a: Point3, b: Point3, s: usize, k: usize) -> Point3 {
        if s == 0 {
            return a;
        }
        let f = s as f32 / k as f32;
        let (x, y) = (a.x + f * (b.x - a.x), a.y + f * (b.y - a.y));
        Point3 {
            x,
            y,
            z: self.map.height_clamped(x, y),
        }
    }

    /// `F` and its parts at `x` (`x` shorter than the dimension costs `+inf`).
    pub fn evaluate(&self, x: &[f32]) -> Evaluation {
        let mut wp = [Point3::default(); MAX_PLANES + 2];
        let Ok(n) = self.encoding.decode(&self.map, x, &mut wp) else {
            return Evaluation {
                cost: f32::INFINITY,
                length: f32::INFINITY,
                energy: f32::INFINITY,
                obstacle: f32::INFINITY,
                ascent: 0.0,
                min_clearance: f32::NEG_INFINITY,
            };
        };
        let p = &self.params;
        let k = match self.encoding.mode() {
            HeightMode::Terrain => p.subdivisions as usize,
            HeightMode::Free => 1,
        };
        let mut length = 0.0f32;
        let mut ascent = 0.0f32;
        let mut penalty = 0.0f32;
        let mut min_clearance = f32::INFINITY;
        for w in wp[..n].windows(2) {
            let (a, b) = (w[0], w[1]);
            let mut prev = a;
            for s in 1..=k {
                let q = if s == k {
                    b
                } else {
                    self.lerp_ground(a, b, s, k)
                };
                let (dx, dy, dz) = (q.x - prev.x, q.y - prev.y, q.z - prev.z);
                length += crate::math::sqrt(dx * dx + dy * dy + dz * dz);
                ascent += dz.max(0.0);
                prev = q;
            }
            for o in self.obstacles {
                let d = o.segment_distance((a.x, a.y), (b.x, b.y));
                min_clearance = min_clearance.min(d - o.radius);
                let keep = o.radius + p.margin;
                if d < keep {
                    penalty += p.penalty * (1.0 + (keep - d) / keep);
                }
            }
        }
        if self.encoding.mode() == HeightMode::Free {
            for q in &wp[1..n - 1] {
                let depth = self.map.height_clamped(q.x, q.y) - q.z;
                if depth > 0.0 {
                    penalty += p.penalty * (1.0 + depth);
                }
            }
        }
        let energy = p.energy.energy(length, ascent);
        let cost = p.w1 * energy + p.w2 * length + (1.0 - p.w1 - p.w2) * penalty;
        Evaluation {
            cost,
            length,
            energy,
            obstacle: penalty,
            ascent,
            min_clearance,
        }
    }
}

impl Objective for TerrainObjective<'_> {
    fn cost(&mut self, x: &[f32]) -> f32 {
        self.evaluate(x).cost
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::terrain::Heightmap;

    fn flat() -> Heightmap<484> {
        Heightmap::from_samples(22, 22, 1.0, &[0.3; 484]).unwrap()
    }

    #[test]
    fn flat_straight_line_has_the_euclidean_length_and_e_is_6_5_l() {
        let map = flat();
        let v = map.view();
        let enc =
            PlaneEncoding::new(&v, (1.0, 15.0), (21.0, 8.0), 20, HeightMode::Terrain).unwrap();
        let obj = TerrainObjective::new(v, &[], enc, ObjectiveParams::zhu2025_orchard()).unwrap();
        let e = obj.evaluate(&[0.0; 20]);
        let l = libm::sqrtf(400.0 + 49.0);
        assert!((e.length - l).abs() < 1e-3, "{}", e.length);
        assert!((e.energy - 6.5 * e.length).abs() < 1e-3);
        assert_eq!(e.obstacle, 0.0);
        assert!((e.cost - (0.4 * 6.5 * e.length + 0.4 * e.length)).abs() < 1e-3);
        let mut out = [Point3::default(); 100];
        assert_eq!(obj.ground_path(&[0.0; 20], &mut out).unwrap(), 21 * 4 + 1);
    }

    #[test]
    fn obstacles_are_penalised_and_start_inside_is_refused() {
        let map = flat();
        let v = map.view();
        let enc =
            PlaneEncoding::new(&v, (1.0, 10.0), (21.0, 10.0), 20, HeightMode::Terrain).unwrap();
        let obs = [Obstacle::cylinder(11.0, 10.0, 1.0, 0.3, 0.5).unwrap()];
        let obj = TerrainObjective::new(v, &obs, enc.clone(), ObjectiveParams::zhu2025_orchard())
            .unwrap();
        let straight = obj.evaluate(&[0.0; 20]);
        assert!(straight.obstacle >= 1.0e4 && straight.min_clearance < 0.0);
        // A detour two km to the side is free.
        let mut x = [0.0f32; 20];
        for (j, t) in x.iter_mut().enumerate() {
            *t = if (7..=12).contains(&j) { 2.5 } else { 0.0 };
        }
        let detour = obj.evaluate(&x);
        assert_eq!(detour.obstacle, 0.0);
        assert!(detour.min_clearance > 0.0);
        assert!(detour.cost < straight.cost);
        let inside = [Obstacle::cone(1.5, 10.0, 1.0, 0.3, 0.5).unwrap()];
        assert_eq!(
            TerrainObjective::new(v, &inside, enc.clone(), ObjectiveParams::zhu2025_orchard())
                .err(),
            Some(TerrainError::InsideObstacle)
        );
        let bad = ObjectiveParams {
            w1: 0.6,
            w2: 0.5,
            ..ObjectiveParams::zhu2025_orchard()
        };
        assert!(TerrainObjective::new(v, &[], enc, bad).is_err());
    }

    #[test]
    fn free_mode_penalises_underground_waypoints() {
        let map = flat();
        let v = map.view();
        let enc = PlaneEncoding::new(&v, (1.0, 10.0), (21.0, 10.0), 5, HeightMode::Free).unwrap();
        let obj = TerrainObjective::new(v, &[], enc, ObjectiveParams::zhu2025_orchard()).unwrap();
        let mut x = [0.0f32; 10];
        x[5..].fill(0.3);
        assert_eq!(obj.evaluate(&x).obstacle, 0.0);
        x[7] = 0.1;
        assert!(obj.evaluate(&x).obstacle > 1.0e4);
        assert_eq!(obj.evaluate(&x[..3]).cost, f32::INFINITY);
    }
}

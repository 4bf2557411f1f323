//! Plane-by-plane discrete ant colony (`Zhu2025Orchard`'s ACO baseline).
//!
//! Each interior plane `j` of the [`PlaneEncoding`](super::planes::PlaneEncoding) is discretised into `nodes` lateral
//! positions spread evenly over its bounds. An ant goes from the start through one node per
//! plane to the goal. From point `p`, node `c` of the next plane is chosen with weight
//! `tau^alpha eta^beta`, `eta = 1 / (|p c| + |c G| + intrusion)` (3D distances on the terrain,
//! `intrusion` = the objective's penalty if segment `p -> c` cuts an obstacle's
//! `radius + margin`). With probability `delta` the choice is the roulette, otherwise the
//! node of largest weight (`Zhu2025Orchard`'s table 1 gives `delta = 0.7` as "the randomness of the
//! choice"). Each complete tour is one evaluation of the full objective. After every
//! iteration: `tau <- (1 - rho) tau`, then each ant deposits `Q / F` on its nodes and the
//! best-so-far tour deposits `Q / F_best` again (elitist), `tau >= 1e-6`.
//!
//! Draws (one [`Random`] per run): per ant, per plane: one `unit` for the `delta` test, and one
//! `unit` for the roulette when it is used.

use super::objective::TerrainObjective;
use super::planes::HeightMode;
use super::{Point3, TerrainError};
use crate::optim::random::Random;

/// Options of the plane-by-plane ACO.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct AcoParams {
    /// Ants per iteration, `>= 1`.
    pub ants: usize,
    /// Iterations, `>= 1`.
    pub iterations: u32,
    /// Lateral nodes per plane, `2..=NODES`.
    pub nodes: usize,
    /// Pheromone exponent.
    pub alpha: f32,
    /// Heuristic exponent.
    pub beta: f32,
    /// Evaporation rate in `(0, 1]`.
    pub rho: f32,
    /// Deposit scale, `> 0`.
    pub q: f32,
    /// Probability of the roulette (else greedy) choice, in `[0, 1]`.
    pub delta: f32,
    /// The run's seed.
    pub seed: u64,
}

impl AcoParams {
    /// `Zhu2025Orchard`'s table 1 (`alpha = 1, beta = 3, rho = 0.2, Q = 1, delta = 0.7`) with 100
    /// ants, 500 iterations and 21 nodes per plane.
    pub const fn zhu2025_orchard() -> Self {
        Self {
            ants: 100,
            iterations: 500,
            nodes: 21,
            alpha: 1.0,
            beta: 3.0,
            rho: 0.2,
            q: 1.0,
            delta: 0.7,
            seed: 0,
        }
    }

    fn validate<const NODES: usize>(&self) -> Result<(), TerrainError> {
        let fin = |v: f32| v.is_finite() && v >= 0.0;
        if self.ants == 0 || self.iterations == 0 {
            return Err(TerrainError::InvalidParameter("ants/iterations"));
        }
        if self.nodes < 2 {
            return Err(TerrainError::InvalidParameter("nodes"));
        }
        if self.nodes > NODES {
            return Err(TerrainError::CapacityExceeded);
        }
        if !(fin(self.alpha) && fin(self.beta) && fin(self.q) && self.q > 0.0) {
            return Err(TerrainError::InvalidParameter("alpha/beta/q"));
        }
        if !(self.rho > 0.0 && self.rho <= 1.0) {
            return Err(TerrainError::InvalidParameter("rho"));
        }
        if !(self.delta >= 0.0 && self.delta <= 1.0) {
            return Err(TerrainError::InvalidParameter("delta"));
        }
        Ok(())
    }
}

impl Default for AcoParams {
    fn default() -> Self {
        Self::zhu2025_orchard()
    }
}

/// The outcome of [`Aco::run`].
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "defmt", derive(defmt::Format))]
pub struct AcoReport {
    /// Best `F`.
    pub best_cost: f32,
    /// Iterations done.
    pub iterations: u32,
    /// Objective evaluations (one per ant tour).
    pub evaluations: u64,
    /// First iteration (1-based) reaching the best.
    pub best_iteration: u32,
    /// Entries written to the history.
    pub history_len: usize,
}

/// Plane-by-plane ACO with capacity `PLANES` planes of `NODES` nodes.
#[derive(Debug, Clone)]
pub struct Aco<const PLANES: usize, const NODES: usize> {
    tau: [[f32; NODES]; PLANES],
    offsets: [[f32; NODES]; PLANES],
    points: [[Point3; NODES]; PLANES],
    best: [f32; PLANES],
    dim: usize,
}

impl<const PLANES: usize, const NODES: usize> Default for Aco<PLANES, NODES> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const PLANES: usize, const NODES: usize> Aco<PLANES, NODES> {
    /// Empty state (fill it with [`run`](Self::run)).
    pub const fn new() -> Self {
        Self {
            tau: [[1.0; NODES]; PLANES],
            offsets: [[0.0; NODES]; PLANES],
            points: [[Point3 {
                x: 0.0,
                y: 0.0,
                z: 0.0,
            }; NODES]; PLANES],
            best: [0.0; PLANES],
            dim: 0,
        }
    }

    /// The best decision vector (lateral offsets) of the last run.
    pub fn best_position(&self) -> &[f32] {
        self.best.get(..self.dim).unwrap_or(&[])
    }

    /// Runs the colony on `objective` (terrain height mode only), writing the best cost after
    /// each iteration into `history` while it has room.
    // Index loops mirror the pheromone matrix's (plane, level) layout.
    #[allow(clippy::needless_range_loop)]
    pub fn run(
        &mut self,
        objective: &TerrainObjective<'_>,
        params: &AcoParams,
        history: &mut [f32],
    ) -> Result<AcoReport, TerrainError> {
        params.validate::<NODES>()?;
        let enc = objective.encoding();
        if enc.mode() != HeightMode::Terrain {
            return Err(TerrainError::InvalidParameter(
                "ACO needs the terrain height mode",
            ));
        }
        let n = enc.planes();
        if n > PLANES {
            return Err(TerrainError::CapacityExceeded);
        }
        let m = params.nodes;
        let map = objective.map();
        for j in 0..n {
            let (lo, hi) = enc.bounds(j);
            for k in 0..m {
                let t = lo + (hi - lo) * k as f32 / (m - 1) as f32;
                let (x, y) = enc.waypoint(j, t);
                self.offsets[j][k] = t;
                self.points[j][k] = Point3 {
                    x,
                    y,
                    z: map.height_clamped(x, y),
                };
                self.tau[j][k] = 1.0;
            }
        }
        let ground = |p: (f32, f32)| Point3 {
            x: p.0,
            y: p.1,
            z: map.height_clamped(p.0, p.1),
        };
        let start = ground(enc.start());
        let goal = ground(enc.goal());
        let op = objective.params();
        let intrusion = |a: Point3, b: Point3| {
            let mut pen = 0.0f32;
            for o in objective.obstacles() {
                let d = o.segment_distance((a.x, a.y), (b.x, b.y));
                if d < o.radius + op.margin {
                    pen += op.penalty;
                }
            }
            pen
        };
        let dist = |a: Point3, b: Point3| {
            let (dx, dy, dz) = (a.x - b.x, a.y - b.y, a.z - b.z);
            crate::math::sqrt(dx * dx + dy * dy + dz * dz)
        };
        let mut rng = Random::new(params.seed);
        let mut best_cost = f32::INFINITY;
        let mut best_iteration = 0u32;
        let mut evaluations = 0u64;
        let mut written = 0usize;
        let mut choice = [0usize; PLANES];
        let mut x = [0.0f32; PLANES];
        let mut weights = [0.0f32; NODES];
        // Deposits of this iteration, applied after evaporation.
        let mut deposit = [[0.0f32; NODES]; PLANES];
        for it in 1..=params.iterations {
            for row in deposit.iter_mut().take(n) {
                row[..m].fill(0.0);
            }
            for _ant in 0..params.ants {
                let mut prev = start;
                for j in 0..n {
                    let mut total = 0.0f32;
                    let mut arg = 0usize;
                    let mut argw = f32::NEG_INFINITY;
                    for k in 0..m {
                        let c = self.points[j][k];
                        let eta = 1.0 / (dist(prev, c) + dist(c, goal) + intrusion(prev, c) + 1e-6);
                        let w = pow(self.tau[j][k], params.alpha) * pow(eta, params.beta);
                        let w = if w.is_finite() { w } else { 0.0 };
                        weights[k] = w;
                        total += w;
                        if w > argw {
                            argw = w;
                            arg = k;
                        }
                    }
                    let pick = if rng.unit() < params.delta && total > 0.0 {
                        let mut r = rng.unit() * total;
                        let mut pick = m - 1;
                        for (k, w) in weights[..m].iter().enumerate() {
                            r -= *w;
                            if r < 0.0 {
                                pick = k;
                                break;
                            }
                        }
                        pick
                    } else {
                        arg
                    };
                    choice[j] = pick;
                    x[j] = self.offsets[j][pick];
                    prev = self.points[j][pick];
                }
                let f = objective.evaluate(&x[..n]).cost;
                evaluations += 1;
                if f < best_cost {
                    best_cost = f;
                    best_iteration = it;
                    self.best[..n].copy_from_slice(&x[..n]);
                    self.dim = n;
                }
                let d = if f.is_finite() && f > 0.0 {
                    params.q / f
                } else {
                    0.0
                };
                for j in 0..n {
                    deposit[j][choice[j]] += d;
                }
            }
            // Elitist deposit on the best-so-far tour.
            let e = if best_cost.is_finite() && best_cost > 0.0 {
                params.q / best_cost
            } else {
                0.0
            };
            for j in 0..n {
                let (lo, hi) = enc.bounds(j);
                let span = hi - lo;
                let k = if span > 0.0 {
                    let r = (self.best[j] - lo) / span * (m - 1) as f32 + 0.5;
                    (crate::math::floor_i(r).max(0) as usize).min(m - 1)
                } else {
                    0
                };
                deposit[j][k] += e;
                for kk in 0..m {
                    let t = (1.0 - params.rho) * self.tau[j][kk] + deposit[j][kk];
                    self.tau[j][kk] = t.max(1e-6);
                }
            }
            if let Some(slot) = history.get_mut(written) {
                *slot = best_cost;
                written += 1;
            }
        }
        Ok(AcoReport {
            best_cost,
            iterations: params.iterations,
            evaluations,
            best_iteration,
            history_len: written,
        })
    }
}

/// `b^e` with the exponents 1, 2 and 3 done by multiplication (the common settings).
fn pow(b: f32, e: f32) -> f32 {
    if e == 1.0 {
        b
    } else if e == 2.0 {
        b * b
    } else if e == 3.0 {
        b * b * b
    } else {
        libm::powf(b, e)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::terrain::objective::ObjectiveParams;
    use crate::terrain::obstacles::Obstacle;
    use crate::terrain::planes::PlaneEncoding;
    use crate::terrain::{Heightmap, Peaks};

    #[test]
    fn aco_avoids_an_obstacle_on_the_straight_line_and_is_deterministic() {
        let map = Heightmap::<484>::peaks(22, 22, 1.0, &Peaks::zhu2025_orchard(), 3).unwrap();
        let v = map.view();
        let enc =
            PlaneEncoding::new(&v, (1.0, 10.0), (21.0, 10.0), 20, HeightMode::Terrain).unwrap();
        let obs = [Obstacle::cylinder(11.0, 10.0, 1.5, 0.0, 0.5).unwrap()];
        let obj = TerrainObjective::new(v, &obs, enc, ObjectiveParams::zhu2025_orchard()).unwrap();
        let params = AcoParams {
            ants: 20,
            iterations: 30,
            seed: 9,
            ..AcoParams::zhu2025_orchard()
        };
        let mut aco = Aco::<24, 32>::new();
        let mut hist = [0.0f32; 30];
        let r = aco.run(&obj, &params, &mut hist).unwrap();
        assert_eq!(r.evaluations, 600);
        assert_eq!(r.history_len, 30);
        let e = obj.evaluate(aco.best_position());
        assert_eq!(e.cost, r.best_cost);
        assert_eq!(e.obstacle, 0.0);
        assert!(hist.windows(2).all(|w| w[1] <= w[0]));
        let mut again = Aco::<24, 32>::new();
        let r2 = again.run(&obj, &params, &mut []).unwrap();
        assert_eq!(r2.best_cost.to_bits(), r.best_cost.to_bits());
        assert_eq!(again.best_position(), aco.best_position());
        let too_many = AcoParams {
            nodes: 33,
            ..params
        };
        assert_eq!(
            again.run(&obj, &too_many, &mut []).err(),
            Some(TerrainError::CapacityExceeded)
        );
        assert!(Aco::<8, 32>::new().run(&obj, &params, &mut []).is_err());
    }
}

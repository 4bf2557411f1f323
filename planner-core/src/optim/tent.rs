//! Tent chaotic initialisation (`Lei2024Warehouse` section 2.1).
//!
//! `z_{k+1} = z_k / u` if `z_k <= u`, else `(1 - z_k) / (1 - u)`, iterated *along the
//! population* for each dimension, `X_k = lb + z_k (ub - lb)`.
//!
//! In floating point the classic `u = 0.5` tent doubles the value each step and loses one
//! mantissa bit per step, so every orbit reaches exactly 0 within ~25 steps in `f32` and stays
//! there. [`TentMap`] therefore adds a small random term mod 1 after each step (the fix of
//! Teng et al. 2018, `Lei2024Warehouse`'s ref. 23) and redraws in the rare event that the result is
//! exactly 0 or 1, so it never emits either.

use super::random::Random;
use super::{Bounds, Population};

/// Size of the perturbation added mod 1 after each tent step: small against the map's own
/// spreading, large enough to keep refreshing the low mantissa bits.
pub const TENT_PERTURBATION: f32 = 1.0e-3;

/// A Tent chaotic sequence in the open interval `(0, 1)`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TentMap {
    z: f32,
    u: f32,
}

impl TentMap {
    /// Starts at a uniform `z_1` in `(0, 1)`; `u` must be in `(0, 1)` (callers validate it).
    pub fn new(rng: &mut Random, u: f32) -> Self {
        Self {
            z: rng.open_unit(),
            u,
        }
    }

    /// The current value, in `(0, 1)`.
    pub fn value(&self) -> f32 {
        self.z
    }

    /// Advances one step and returns the new value, in `(0, 1)`.
    pub fn next(&mut self, rng: &mut Random) -> f32 {
        let z = self.z;
        let mut next = if z <= self.u {
            z / self.u
        } else {
            (1.0 - z) / (1.0 - self.u)
        };
        next += TENT_PERTURBATION * rng.unit();
        if next >= 1.0 {
            next -= 1.0;
        }
        if !(next > 0.0 && next < 1.0) {
            next = rng.open_unit();
        }
        self.z = next;
        next
    }
}

/// Fills `pop` with the Tent sequence along the population, dimension by dimension.
pub(crate) fn fill<const N: usize, const D: usize>(
    pop: &mut Population<N, D>,
    bounds: &Bounds<D>,
    rng: &mut Random,
    u: f32,
) {
    let n = pop.size();
    for (d, (l, h)) in bounds.lower().iter().zip(bounds.upper()).enumerate() {
        let mut map = TentMap::new(rng, u);
        for i in 0..n {
            let z = if i == 0 { map.value() } else { map.next(rng) };
            if let Some(v) = pop.position_mut(i).get_mut(d) {
                *v = l + z * (h - l);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tent_never_emits_0_or_1_over_a_million_steps() {
        for (seed, u) in [(1u64, 0.5f32), (2, 0.7), (3, 0.3)] {
            let mut rng = Random::new(seed);
            let mut map = TentMap::new(&mut rng, u);
            let mut sum = 0.0f64;
            let mut below_tenth = 0u32;
            for _ in 0..1_000_000 {
                let z = map.next(&mut rng);
                assert!(z > 0.0 && z < 1.0, "{z}");
                sum += f64::from(z);
                below_tenth += u32::from(z < 0.1);
            }
            // It must not collapse either: the tent's invariant density is uniform.
            let mean = sum / 1e6;
            assert!((mean - 0.5).abs() < 0.01, "mean {mean}");
            assert!((f64::from(below_tenth) / 1e6 - 0.1).abs() < 0.01);
        }
    }

    #[test]
    fn unperturbed_half_tent_collapses_in_f32() {
        // Why the perturbation exists.
        let mut z = 0.123_456_7f32;
        for _ in 0..60 {
            z = if z <= 0.5 { z / 0.5 } else { (1.0 - z) / 0.5 };
        }
        assert_eq!(z, 0.0);
    }

    #[test]
    fn fill_stays_in_the_box() {
        let b = Bounds::<3>::from_slices(&[-1.0, 0.0, 10.0], &[1.0, 5.0, 11.0]).unwrap();
        let mut p = Population::<50, 3>::new(50, 3);
        let mut rng = Random::new(4);
        fill(&mut p, &b, &mut rng, 0.5);
        for i in 0..50 {
            for (d, v) in p.position(i).iter().enumerate() {
                assert!(*v >= b.lower()[d] && *v <= b.upper()[d]);
            }
        }
    }
}

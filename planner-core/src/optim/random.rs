//! The one source of randomness: a seeded `Xoshiro128PlusPlus` and the draws built on it.
//!
//! `Xoshiro128PlusPlus` works on 32-bit words, which suits the Cortex-M4; it is seeded with
//! `SeedableRng::seed_from_u64` (SplitMix64), so a `u64` seed fully determines a run. Every
//! draw below uses only integer operations and `libm`, so sequences are bit-identical on
//! x86_64 and thumbv7em.
//!
//! # Draws
//! - [`Random::unit`]: `[0, 1)` from the 24 high bits of one word (every value exact in `f32`);
//! - [`Random::open_unit`]: `(0, 1)`, the 23 high bits with the lowest bit forced to one;
//! - [`Random::index`]: below `n` by Lemire's multiply-shift of one word (bias below `n / 2^32`);
//! - [`Random::normal`]: Marsaglia's polar method, two `unit` draws per attempt, attempts
//!   repeat until `0 < s < 1` (about 1.27 attempts on average); the second normal of the pair is
//!   discarded so that each call's draw count depends only on its own attempts;
//! - [`Random::cauchy`]: `u / v` for a point `(u, v)` uniform in the unit disc, two `unit`
//!   draws per attempt, attempts repeat until `u^2 + v^2 < 1` and `v != 0`;
//! - [`Random::levy`]: Mantegna's algorithm, `beta = 1.5`: `u` then `v`, two standard normals
//!   by the ziggurat (one word each in 98.8% of draws, see `ziggurat.rs`), `u` scaled by
//!   `sigma`, `step = u / |v|^(1/beta)` (computed as `cbrt(v^2)`). Levy steps are the hottest
//!   draws (one per coordinate of every failed dive); `normal` keeps the polar method, whose
//!   streams GA's and SSA's reference tables were measured with.
//!
//! # Order of draws per algorithm (one generator per optimizer, reset by `init`)
//! - **Initialisation**: uniform: member-major, dimension-minor, one `unit` per coordinate.
//!   Tent: dimension-major: one `open_unit` for `z_1`, then per further member one `unit`
//!   (the perturbation, see [`crate::optim::tent`]). Opposition: uniform draws only.
//! - **HHO / TCLHHO**, per iteration, per hawk in index order: `E0`; if `|E| >= 1`: `q`, the
//!   random hawk's index, then `r1, r2` (`q < 0.5`) or `r3, r4` (literal TCLHHO variant: the
//!   mutation draws instead of all of these); else `r`, then `J` for the three moves that use it;
//!   a failed dive `Y` then draws per dimension `S_j` and one Levy step. After all hawks
//!   (TCLHHO): `P`, then per dimension a Cauchy draw (`P >= 0.5`) or `K1, K2` (opposition).
//! - **GWO / TGWO / IGWO**, per wolf, per dimension, per leader (alpha, beta, delta): `r1, r2`
//!   (the same with or without the greedy option).
//! - **SSA**: `R2`; per producer in rank order one `alpha` (`R2 < ST`) or one normal `Q`;
//!   per scrounger in rank order: worse half one normal `Q`, better half one sign per
//!   dimension; scouts: partial Fisher-Yates (one `index` per scout), then per scout either one
//!   normal per dimension or one `unit` for `K`.
//! - **SSA-GWO**: the GWO draws, then the SSA draws, each iteration; the PSO-style variant
//!   ([`crate::optim::ssa_gwo::SsaGwoPso`]) draws the PSO draws instead of the SSA ones.
//! - **PSO**: per particle, per dimension: `r1, r2`.
//! - **GA**: per offspring pair: two tournaments (two `index` each), the crossover test, the
//!   blend weight, then per gene of each child the mutation test and, if mutated, one normal.

use rand_core::SeedableRng;
use rand_xoshiro::Xoshiro128PlusPlus;

/// Mantegna's `sigma_u` for `beta = 1.5`:
/// `(Gamma(1 + b) sin(pi b / 2) / (Gamma((1 + b) / 2) b 2^((b - 1) / 2)))^(1 / b)`.
pub const LEVY_SIGMA_1_5: f32 = 0.696_574_2;

/// The Levy stability index used by HHO (Mantegna's method).
pub const LEVY_BETA: f32 = 1.5;

/// A seeded generator and the draws the optimizers need.
///
/// The `Xoshiro128PlusPlus` state words themselves, stepped here exactly as `rand_xoshiro`
/// steps them (a test compares the sequences): a generator that can sit in a `const`
/// initialiser without an `Option`, whose check cost every draw.
#[derive(Debug, Clone)]
pub struct Random {
    s: [u32; 4],
}

/// `Xoshiro128PlusPlus::seed_from_u64(seed)`'s state in a `const fn`: two SplitMix64 words,
/// little-endian, as `rand_xoshiro` fills its seed (they are never both zero, so its zero-seed
/// remapping never applies).
const fn splitmix_state(seed: u64) -> [u32; 4] {
    const fn next(x: u64) -> u64 {
        let mut z = x;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    const PHI: u64 = 0x9e37_79b9_7f4a_7c15;
    let a = next(seed.wrapping_add(PHI));
    let b = next(seed.wrapping_add(PHI).wrapping_add(PHI));
    [a as u32, (a >> 32) as u32, b as u32, (b >> 32) as u32]
}

impl Random {
    /// A generator fully determined by `seed`.
    pub fn new(seed: u64) -> Self {
        let mut r = Self::unseeded();
        r.reseed(seed);
        r
    }

    /// A generator for `const` initialisers; draws as if seeded with 0 until reseeded.
    pub const fn unseeded() -> Self {
        Self {
            s: splitmix_state(0),
        }
    }

    /// The all-zero state, for the all-zero `unconfigured()` optimizers (see
    /// [`SwarmState::unconfigured`](super::SwarmState::unconfigured)), which reseed before their first
    /// draw. Xoshiro's zero state is a fixed point: it draws 0 forever, so `normal` and
    /// `cauchy` would never return. Not public for that reason.
    pub(crate) const fn unset() -> Self {
        Self { s: [0; 4] }
    }

    /// Restarts the sequence of `seed`.
    pub fn reseed(&mut self, seed: u64) {
        // Seeded by the crate itself; only the stepping is done here.
        let bytes = Xoshiro128PlusPlus::seed_from_u64(seed).state();
        for (w, b) in self.s.iter_mut().zip(bytes.chunks_exact(4)) {
            if let Ok(b) = b.try_into() {
                *w = u32::from_le_bytes(b);
            }
        }
    }

    /// The next raw 32-bit word (`Xoshiro128PlusPlus::next_u32`).
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        let [s0, s1, s2, s3] = self.s;
        let result = s0.wrapping_add(s3).rotate_left(7).wrapping_add(s0);
        let t = s1 << 9;
        let s2 = s2 ^ s0;
        let s3 = s3 ^ s1;
        let s1 = s1 ^ s2;
        let s0 = s0 ^ s3;
        self.s = [s0, s1, s2 ^ t, s3.rotate_left(11)];
        result
    }

    /// Uniform in `[0, 1)`.
    #[inline]
    pub fn unit(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / 16_777_216.0)
    }

    /// Uniform in the open interval `(0, 1)`: never exactly 0 or 1.
    #[inline]
    pub fn open_unit(&mut self) -> f32 {
        ((self.next_u32() >> 8) | 1) as f32 * (1.0 / 16_777_216.0)
    }

    /// Uniform in `[lo, hi]` (`hi` only through rounding).
    #[inline]
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let v = lo + (hi - lo) * self.unit();
        v.min(hi)
    }

    /// Uniform index in `0..n` (0 if `n == 0`).
    #[inline]
    pub fn index(&mut self, n: usize) -> usize {
        ((u64::from(self.next_u32()) * n as u64) >> 32) as usize
    }

    /// Standard normal, Marsaglia's polar method (the pair's second value is discarded).
    pub fn normal(&mut self) -> f32 {
        loop {
            let u = 2.0 * self.unit() - 1.0;
            let v = 2.0 * self.unit() - 1.0;
            let s = u * u + v * v;
            if s > 0.0 && s < 1.0 {
                return u * super::sqrtf(-2.0 * libm::logf(s) / s);
            }
        }
    }

    /// Standard Cauchy draw: `u / v` for a point `(u, v)` uniform in the unit disc (its
    /// angle is uniform, so the ratio is `tan` of a uniform angle, the standard Cauchy).
    ///
    /// Not `tan(pi (r - 1/2))`: libm's `tanf` works in `f64`, which a Cortex-M4F emulates in
    /// software; this takes two uniforms and one division per accepted point (acceptance
    /// pi/4).
    pub fn cauchy(&mut self) -> f32 {
        loop {
            let u = 2.0 * self.unit() - 1.0;
            let v = 2.0 * self.unit() - 1.0;
            let s = u * u + v * v;
            if s < 1.0 && v != 0.0 {
                return u / v;
            }
        }
    }

    /// One Mantegna Levy step with `beta = 1.5`, unscaled (HHO multiplies it by 0.01).
    ///
    /// Its normals come from the ziggurat: a polar pair cost a `logf`, a square root and a
    /// division, plus rejected attempts, and Levy steps were a seventh of a TCLHHO plan on a
    /// Cortex-M4. Over 200 seeds of the firmware's 40x40 and 64x64 plans the mean path
    /// lengths are the same as with polar normals (63.52 vs 63.50 and 102.89 vs 102.91 cells,
    /// standard errors 0.04 and 0.06).
    pub fn levy(&mut self) -> f32 {
        let u = super::ziggurat::normal(self) * LEVY_SIGMA_1_5;
        // Only `v^2` is used, so `v`'s sign is not applied.
        let v = super::ziggurat::magnitude(self);
        // |v|^(1/1.5) = cbrt(v^2) (libm's powf costs several times a cube root). A zero `v`
        // (probability ~0) would give an infinite step; keep it finite anyway: `cbrt_positive`
        // takes at least `f32::MIN_POSITIVE`. A nonzero `v` is at least `W[127]` (1.6e-8),
        // so `v^2 + MIN_POSITIVE` rounds to `v^2` (2^-126 is below half an ulp of anything
        // above 2^-100) and to `MIN_POSITIVE` for a zero `v`: the same value as that range
        // check, in one addition instead of comparisons.
        u / cbrt_normal(v * v + f32::MIN_POSITIVE)
    }
}

/// Cube root of `x`, taken as at least `f32::MIN_POSITIVE` (so the result is positive and
/// finite for every finite `x`), in `f32` arithmetic only.
///
/// libm's `cbrtf` refines in `f64`, which a Cortex-M4F emulates in software: it was the
/// largest single cost of a TCLHHO plan there (one per coordinate of every Levy dive). Here:
/// an exponent-thirding bit estimate (within 4%), then four Newton steps, each of which about
/// squares the relative error (4e-2, 2e-3, 4e-6, 2e-11: `f32` rounding then decides, so the
/// result is within 2 ulp of the true root). Plain `f32` operations round the same way on
/// every target, so plans stay bit-identical between hosts and the MCU.
pub fn cbrt_positive(x: f32) -> f32 {
    // Comparisons, not `max`, which is a libm call on Cortex-M4 and lets NaN through.
    // `!(x >= MIN_POSITIVE)` also catches NaN, in one comparison instead of a range test.
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    let x = if !(x >= f32::MIN_POSITIVE) {
        f32::MIN_POSITIVE
    } else if x > f32::MAX {
        f32::MAX
    } else {
        x
    };
    cbrt_normal(x)
}

/// [`cbrt_positive`] of a finite `x >= f32::MIN_POSITIVE` (the range that the estimate and
/// the Newton steps handle).
#[inline(always)]
fn cbrt_normal(x: f32) -> f32 {
    // Dividing the biased exponent by three: bits / 3 + 2/3 of the bias (709,958,130 is
    // musl's constant for the same estimate).
    let y = f32::from_bits(x.to_bits() / 3 + 709_958_130);
    // Written out: firmware builds for size (`opt-level = "s"`) and would keep the loop
    // counter and branch of `for _ in 0..4` (one Levy step per coordinate of every dive).
    let newton = |y: f32| (2.0 * y + x / (y * y)) * (1.0 / 3.0);
    newton(newton(newton(newton(y))))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn unit_ranges() {
        let mut r = Random::new(1);
        for _ in 0..100_000 {
            let u = r.unit();
            assert!((0.0..1.0).contains(&u));
            let o = r.open_unit();
            assert!(o > 0.0 && o < 1.0);
            assert!(r.index(7) < 7);
            let x = r.range(-2.0, 3.0);
            assert!((-2.0..=3.0).contains(&x));
        }
        assert_eq!(r.index(0), 0);
    }

    #[test]
    fn steps_like_rand_xoshiro() {
        use rand_core::Rng;
        for seed in [0u64, 1, 42, 0x5EED_0008, u64::MAX, 0x9e37_79b9_7f4a_7c15] {
            let mut ours = Random::new(seed);
            let mut theirs = Xoshiro128PlusPlus::seed_from_u64(seed);
            for _ in 0..10_000 {
                assert_eq!(ours.next_u32(), theirs.next_u32(), "seed {seed}");
            }
        }
        let mut unseeded = Random::unseeded();
        let mut zero = Xoshiro128PlusPlus::seed_from_u64(0);
        for _ in 0..100 {
            assert_eq!(unseeded.next_u32(), zero.next_u32());
        }
        for seed in [0u64, 7, 0xdead_beef, u64::MAX] {
            let bytes = Xoshiro128PlusPlus::seed_from_u64(seed).state();
            let mut words = [0u32; 4];
            for (w, b) in words.iter_mut().zip(bytes.chunks_exact(4)) {
                *w = u32::from_le_bytes([b[0], b[1], b[2], b[3]]);
            }
            assert_eq!(splitmix_state(seed), words, "seed {seed}");
        }
    }

    #[test]
    fn same_seed_same_sequence() {
        let (mut a, mut b) = (Random::new(42), Random::new(42));
        for _ in 0..1000 {
            assert_eq!(a.normal().to_bits(), b.normal().to_bits());
            assert_eq!(a.levy().to_bits(), b.levy().to_bits());
        }
    }

    #[test]
    fn normal_moments() {
        let mut r = Random::new(9);
        let n = 200_000;
        let (mut s, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let x = f64::from(r.normal());
            s += x;
            s2 += x * x;
        }
        let mean = s / f64::from(n);
        let var = s2 / f64::from(n) - mean * mean;
        // Standard errors: 1/sqrt(n) = 0.0022 for the mean, sqrt(2/n) = 0.0032 for the variance.
        assert!(mean.abs() < 0.01, "{mean}");
        assert!((var - 1.0).abs() < 0.015, "{var}");
    }

    #[test]
    fn cauchy_quartiles() {
        // The standard Cauchy has quartiles -1 and 1: about half of the draws lie in [-1, 1].
        let mut r = Random::new(5);
        let n = 100_000;
        let draws: std::vec::Vec<f32> = (0..n).map(|_| r.cauchy()).collect();
        let frac =
            |f: &dyn Fn(f32) -> bool| draws.iter().filter(|&&x| f(x)).count() as f64 / f64::from(n);
        assert!((frac(&|x| x.abs() <= 1.0) - 0.5).abs() < 0.01);
        // P(X <= -1) = 1/4 (symmetry), P(|X| <= tan(pi/10)) = 1/5, P(|X| <= tan(2pi/5)) = 4/5.
        assert!((frac(&|x| x <= -1.0) - 0.25).abs() < 0.01);
        assert!((frac(&|x| x.abs() <= 0.324_919_7) - 0.2).abs() < 0.01);
        assert!((frac(&|x| x.abs() <= 3.077_683_5) - 0.8).abs() < 0.01);
    }

    #[test]
    fn cube_roots_are_within_two_ulp() {
        let mut x = f32::MIN_POSITIVE;
        while x < 1e30 {
            for k in 0..7 {
                let v = x * (1.0 + k as f32 / 7.0);
                let want = libm::cbrt(f64::from(v));
                let got = f64::from(cbrt_positive(v));
                let ulp = f64::from(f32::EPSILON) * want;
                assert!((got - want).abs() <= 2.0 * ulp, "{v}: {got} vs {want}");
            }
            x *= 3.7;
        }
        assert_eq!(cbrt_positive(27.0), 3.0);
        assert_eq!(cbrt_positive(0.0), cbrt_positive(f32::MIN_POSITIVE));
        assert_eq!(cbrt_positive(f32::NAN), cbrt_positive(f32::MIN_POSITIVE));
        assert!(cbrt_positive(f32::INFINITY).is_finite());
    }

    #[test]
    fn levy_steps_have_the_mantegna_scale() {
        // sigma from Mantegna's formula, in f64 with libm's gamma.
        let b = 1.5f64;
        let ratio = libm::tgamma(1.0 + b) * libm::sin(core::f64::consts::PI * b / 2.0)
            / (libm::tgamma((1.0 + b) / 2.0) * b * libm::pow(2.0, (b - 1.0) / 2.0));
        let sigma = libm::pow(ratio, 1.0 / b);
        assert!((sigma - f64::from(LEVY_SIGMA_1_5)).abs() < 1e-6, "{sigma}");
        // The step u/|v|^(2/3) is symmetric with median |step| equal to sigma times the median
        // of |N1|/|N2|^(2/3); that median is a fixed number (0.905 by a 2*10^6-sample f64
        // simulation), so the sample median of |step| checks the scale.
        let mut r = Random::new(11);
        let mut v: [f32; 20001] = [0.0; 20001];
        for x in v.iter_mut() {
            *x = r.levy().abs();
        }
        v.sort_unstable_by(f32::total_cmp);
        let median = f64::from(v[10000]);
        let expected = sigma * 0.905;
        assert!(
            (median / expected - 1.0).abs() < 0.03,
            "{median} vs {expected}"
        );
    }
}

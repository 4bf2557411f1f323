//! Benchmark functions: `Liu2020Igwo`'s table 1 and shifted sphere / Rastrigin / Rosenbrock /
//! Ackley at any dimension, as [`Objective`]s.
//!
//! Behind the `functions` feature (on by default).
//!
//! `Liu2020Igwo`'s table 1 announces twelve functions but its typesetting lost two of them: `f1` to
//! `f10` are printed (the classic De Jong suite, Schaffer F6/F7, Goldstein-Price, Shubert and
//! the six-hump camel), and only the optima `-15` and `2.471` of the two "functions with
//! complex constraints" survive. `f11` is read as the standard constrained problem with
//! optimum `-15`, g01 of Floudas & Pardalos (13 variables, 9 linear constraints), handled with
//! an exact penalty. `f12` cannot be identified from what is printed (its GA/PSO/GWO/IGWO
//! means 2.37-2.43 all lie *below* 2.471, so it is probably a maximisation); it is not
//! provided.
//!
//! Readings: `f3`'s "integer" is `floor` (optimum `5 * floor(-5.12) = -30`); `f5` is
//! printed as the reciprocal of Shekel's foxholes (its optimum 0.998 is that of
//! `1 / (0.002 + sum ...)`), which is used; `f4`'s `Gauss(0, 1)` noise is drawn from the
//! benchmark's own seeded generator (its optimum 0 is the noiseless one:
//! [`Benchmark::noiseless`]).
//!
//! The shifted functions move the optimum to `(s, ..., s)` inside a fixed box, because several
//! algorithms are biased towards the origin (SPEC section 2).
//!
//! ```
//! use planner_core::optim::functions::{Benchmark, FunctionKind};
//! use planner_core::optim::Objective;
//!
//! let mut f: Benchmark = Benchmark::new("sphere".parse()?, 30, 37.5, 0)?;
//! assert_eq!(f.cost(&[37.5; 30]), 0.0);
//! assert_eq!(FunctionKind::GoldsteinPrice.optimum(), 3.0);
//! # Ok::<(), planner_core::optim::OptimError>(())
//! ```

use core::f32::consts::{E, PI};
use core::str::FromStr;

use super::random::Random;
use super::{Bounds, Objective, OptimError, sqrtf};

/// Which benchmark function.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum FunctionKind {
    /// `f1`: De Jong sphere, 3-D, `[-5.12, 5.12]`, optimum 0.
    DeJongSphere,
    /// `f2`: De Jong / Rosenbrock, 2-D, `[-2.048, 2.048]`, optimum 0.
    DeJongRosenbrock,
    /// `f3`: De Jong step `sum floor(x_i)`, 5-D, `[-5.12, 5.12]`, optimum -30.
    DeJongStep,
    /// `f4`: De Jong quartic with noise `sum i x_i^4 + N(0, 1)`, 30-D, `[-1.28, 1.28]`, optimum 0.
    DeJongQuartic,
    /// `f5`: Shekel's foxholes, 2-D, `[-65.536, 65.536]`, optimum 0.998.
    ShekelFoxholes,
    /// `f6`: Schaffer F6, 2-D, `[-100, 100]`, optimum 0.
    SchafferF6,
    /// `f7`: Schaffer F7, 2-D, `[-100, 100]`, optimum 0.
    SchafferF7,
    /// `f8`: Goldstein-Price, 2-D, `[-2, 2]`, optimum 3.
    GoldsteinPrice,
    /// `f9`: Shubert, 2-D, `[-10, 10]`, optimum -186.731.
    Shubert,
    /// `f10`: six-hump camel, `x in [-3, 3]`, `y in [-2, 2]`, optimum -1.0316.
    SixHumpCamel,
    /// `f11`: constrained g01 (13-D, exact penalty), optimum -15.
    G01,
    /// Shifted sphere, any dimension, `[-100, 100]`.
    Sphere,
    /// Shifted Rastrigin, any dimension, `[-5.12, 5.12]`.
    Rastrigin,
    /// Shifted Rosenbrock, dimension >= 2, `[-30, 30]`.
    Rosenbrock,
    /// Shifted Ackley, any dimension, `[-32.768, 32.768]`.
    Ackley,
}

/// `Liu2020Igwo`'s table 1 functions that can be read, in order `f1..f11`.
pub const TABLE_1: [FunctionKind; 11] = [
    FunctionKind::DeJongSphere,
    FunctionKind::DeJongRosenbrock,
    FunctionKind::DeJongStep,
    FunctionKind::DeJongQuartic,
    FunctionKind::ShekelFoxholes,
    FunctionKind::SchafferF6,
    FunctionKind::SchafferF7,
    FunctionKind::GoldsteinPrice,
    FunctionKind::Shubert,
    FunctionKind::SixHumpCamel,
    FunctionKind::G01,
];

/// The shifted functions of any dimension.
pub const SHIFTED: [FunctionKind; 4] = [
    FunctionKind::Sphere,
    FunctionKind::Rastrigin,
    FunctionKind::Rosenbrock,
    FunctionKind::Ackley,
];

impl FunctionKind {
    /// The command-line name: `f1`..`f11`, `sphere`, `rastrigin`, `rosenbrock`, `ackley`.
    pub fn name(self) -> &'static str {
        match self {
            Self::DeJongSphere => "f1",
            Self::DeJongRosenbrock => "f2",
            Self::DeJongStep => "f3",
            Self::DeJongQuartic => "f4",
            Self::ShekelFoxholes => "f5",
            Self::SchafferF6 => "f6",
            Self::SchafferF7 => "f7",
            Self::GoldsteinPrice => "f8",
            Self::Shubert => "f9",
            Self::SixHumpCamel => "f10",
            Self::G01 => "f11",
            Self::Sphere => "sphere",
            Self::Rastrigin => "rastrigin",
            Self::Rosenbrock => "rosenbrock",
            Self::Ackley => "ackley",
        }
    }

    /// The fixed dimension of a table function, `None` for the shifted ones.
    pub fn fixed_dim(self) -> Option<usize> {
        match self {
            Self::DeJongSphere => Some(3),
            Self::DeJongStep => Some(5),
            Self::DeJongQuartic => Some(30),
            Self::G01 => Some(13),
            Self::Sphere | Self::Rastrigin | Self::Rosenbrock | Self::Ackley => None,
            _ => Some(2),
        }
    }

    /// True for the shifted functions (the only ones accepting a shift).
    pub fn is_shifted(self) -> bool {
        self.fixed_dim().is_none()
    }

    /// The known optimum (table 1's "true value"; 0 for the shifted functions).
    pub fn optimum(self) -> f32 {
        match self {
            Self::DeJongStep => -30.0,
            Self::ShekelFoxholes => 0.998_004,
            Self::GoldsteinPrice => 3.0,
            Self::Shubert => -186.730_9,
            Self::SixHumpCamel => -1.031_628,
            Self::G01 => -15.0,
            _ => 0.0,
        }
    }

    /// The interval of dimension `d`.
    pub fn interval(self, d: usize) -> (f32, f32) {
        match self {
            Self::DeJongSphere | Self::DeJongStep | Self::Rastrigin => (-5.12, 5.12),
            Self::DeJongRosenbrock => (-2.048, 2.048),
            Self::DeJongQuartic => (-1.28, 1.28),
            Self::ShekelFoxholes => (-65.536, 65.536),
            Self::SchafferF6 | Self::SchafferF7 | Self::Sphere => (-100.0, 100.0),
            Self::GoldsteinPrice => (-2.0, 2.0),
            Self::Shubert => (-10.0, 10.0),
            Self::SixHumpCamel => {
                if d == 0 {
                    (-3.0, 3.0)
                } else {
                    (-2.0, 2.0)
                }
            }
            Self::G01 => {
                if (9..12).contains(&d) {
                    (0.0, 100.0)
                } else {
                    (0.0, 1.0)
                }
            }
            Self::Rosenbrock => (-30.0, 30.0),
            Self::Ackley => (-32.768, 32.768),
        }
    }
}

impl FromStr for FunctionKind {
    type Err = OptimError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        TABLE_1
            .iter()
            .chain(SHIFTED.iter())
            .copied()
            .find(|k| k.name() == s)
            .ok_or(OptimError::UnknownName)
    }
}

/// A benchmark function at a dimension, with a shift and (for `f4`) a noise generator.
#[derive(Debug, Clone)]
pub struct Benchmark {
    kind: FunctionKind,
    dim: usize,
    shift: f32,
    noise: Random,
}

impl Benchmark {
    /// Checks the dimension (fixed for table functions, >= 1 for shifted ones, >= 2 for
    /// Rosenbrock) and the shift (only for shifted functions, finite and inside the box).
    /// `noise_seed` seeds `f4`'s noise.
    pub fn new(
        kind: FunctionKind,
        dim: usize,
        shift: f32,
        noise_seed: u64,
    ) -> Result<Self, OptimError> {
        match kind.fixed_dim() {
            Some(d) if d != dim => return Err(OptimError::DimensionOutOfRange),
            None if dim == 0 || (kind == FunctionKind::Rosenbrock && dim < 2) => {
                return Err(OptimError::DimensionOutOfRange);
            }
            _ => {}
        }
        let (lo, hi) = kind.interval(0);
        if !shift.is_finite() || (shift != 0.0 && !kind.is_shifted()) || shift < lo || shift > hi {
            return Err(OptimError::InvalidParameter("shift"));
        }
        Ok(Self {
            kind,
            dim,
            shift,
            noise: Random::new(noise_seed),
        })
    }

    /// The function.
    pub fn kind(&self) -> FunctionKind {
        self.kind
    }

    /// The dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The box, at capacity `D`.
    pub fn bounds<const D: usize>(&self) -> Result<Bounds<D>, OptimError> {
        if self.dim > D {
            return Err(OptimError::DimensionOutOfRange);
        }
        let mut lo = [0.0f32; D];
        let mut hi = [0.0f32; D];
        for (d, (l, h)) in lo.iter_mut().zip(hi.iter_mut()).enumerate().take(self.dim) {
            (*l, *h) = self.kind.interval(d);
        }
        Bounds::from_slices(
            lo.get(..self.dim).unwrap_or(&[]),
            hi.get(..self.dim).unwrap_or(&[]),
        )
    }

    /// The value without `f4`'s noise (identical to [`Objective::cost`] for the others).
    pub fn noiseless(&self, x: &[f32]) -> f32 {
        let s = self.shift;
        match self.kind {
            FunctionKind::DeJongSphere => x.iter().map(|v| v * v).sum(),
            FunctionKind::DeJongRosenbrock | FunctionKind::Rosenbrock => {
                let mut sum = 0.0;
                // z = x - s + 1 puts the optimum (1, ..., 1) of Rosenbrock at (s, ..., s).
                let off = if self.kind == FunctionKind::Rosenbrock {
                    1.0 - s
                } else {
                    0.0
                };
                for w in x.windows(2) {
                    let (a, b) = (w[0] + off, w[1] + off);
                    sum += 100.0 * (a * a - b) * (a * a - b) + (1.0 - a) * (1.0 - a);
                }
                sum
            }
            FunctionKind::DeJongStep => x.iter().map(|v| libm::floorf(*v)).sum(),
            FunctionKind::DeJongQuartic => x
                .iter()
                .enumerate()
                .map(|(i, v)| (i + 1) as f32 * (v * v) * (v * v))
                .sum(),
            FunctionKind::ShekelFoxholes => {
                const A: [f32; 5] = [-32.0, -16.0, 0.0, 16.0, 32.0];
                let (x0, x1) = (
                    x.first().copied().unwrap_or(0.0),
                    x.get(1).copied().unwrap_or(0.0),
                );
                let mut sum = 0.0;
                for j in 0..25 {
                    let d0 = x0 - A[j % 5];
                    let d1 = x1 - A[j / 5];
                    let p = |d: f32| {
                        let d2 = d * d;
                        d2 * d2 * d2
                    };
                    sum += 1.0 / ((j + 1) as f32 + p(d0) + p(d1));
                }
                1.0 / (0.002 + sum)
            }
            FunctionKind::SchafferF6 => {
                let r2: f32 = x.iter().map(|v| v * v).sum();
                let s = libm::sinf(sqrtf(r2));
                let d = 1.0 + 0.001 * r2;
                0.5 + (s * s - 0.5) / (d * d)
            }
            FunctionKind::SchafferF7 => {
                let r2: f32 = x.iter().map(|v| v * v).sum();
                let s = libm::sinf(50.0 * libm::powf(r2, 0.1));
                libm::powf(r2, 0.25) * (s * s + 1.0)
            }
            FunctionKind::GoldsteinPrice => {
                let (a, b) = (
                    x.first().copied().unwrap_or(0.0),
                    x.get(1).copied().unwrap_or(0.0),
                );
                let p = a + b + 1.0;
                let q = 2.0 * a - 3.0 * b;
                (1.0 + p
                    * p
                    * (19.0 - 14.0 * a + 3.0 * a * a - 14.0 * b + 6.0 * a * b + 3.0 * b * b))
                    * (30.0
                        + q * q
                            * (18.0 - 32.0 * a + 12.0 * a * a + 48.0 * b - 36.0 * a * b
                                + 27.0 * b * b))
            }
            FunctionKind::Shubert => {
                let term = |v: f32| -> f32 {
                    (1..=5)
                        .map(|i| i as f32 * libm::cosf((i + 1) as f32 * v + i as f32))
                        .sum()
                };
                term(x.first().copied().unwrap_or(0.0)) * term(x.get(1).copied().unwrap_or(0.0))
            }
            FunctionKind::SixHumpCamel => {
                let (a, b) = (
                    x.first().copied().unwrap_or(0.0),
                    x.get(1).copied().unwrap_or(0.0),
                );
                let a2 = a * a;
                (4.0 - 2.1 * a2 + a2 * a2 / 3.0) * a2 + a * b + (-4.0 + 4.0 * b * b) * b * b
            }
            FunctionKind::G01 => g01(x),
            FunctionKind::Sphere => x.iter().map(|v| (v - s) * (v - s)).sum(),
            FunctionKind::Rastrigin => x
                .iter()
                .map(|v| (v - s) * (v - s) - 10.0 * libm::cosf(2.0 * PI * (v - s)) + 10.0)
                .sum(),
            FunctionKind::Ackley => {
                let n = x.len().max(1) as f32;
                let sq: f32 = x.iter().map(|v| (v - s) * (v - s)).sum();
                let cs: f32 = x.iter().map(|v| libm::cosf(2.0 * PI * (v - s))).sum();
                // max(0): rounding can leave -1e-7 at the optimum.
                (-20.0 * libm::expf(-0.2 * sqrtf(sq / n)) - libm::expf(cs / n) + 20.0 + E).max(0.0)
            }
        }
    }
}

/// Penalty weight of g01 (L1 penalty on the violations). The KKT conditions at the optimum
/// (for `x10`: `-1 + l1 + l2 + l7 = 0`, likewise `x11`, `x12`) bound every multiplier by 1,
/// so any weight above 1 makes the penalty exact: the penalised minimum is the constrained
/// one; 100 leaves a wide margin.
pub const G01_PENALTY: f32 = 100.0;

fn g01(x: &[f32]) -> f32 {
    let v = |i: usize| x.get(i).copied().unwrap_or(0.0);
    let f = 5.0 * (v(0) + v(1) + v(2) + v(3))
        - 5.0 * (v(0) * v(0) + v(1) * v(1) + v(2) * v(2) + v(3) * v(3))
        - (4..13).map(v).sum::<f32>();
    let g = [
        2.0 * v(0) + 2.0 * v(1) + v(9) + v(10) - 10.0,
        2.0 * v(0) + 2.0 * v(2) + v(9) + v(11) - 10.0,
        2.0 * v(1) + 2.0 * v(2) + v(10) + v(11) - 10.0,
        -8.0 * v(0) + v(9),
        -8.0 * v(1) + v(10),
        -8.0 * v(2) + v(11),
        -2.0 * v(3) - v(4) + v(9),
        -2.0 * v(5) - v(6) + v(10),
        -2.0 * v(7) - v(8) + v(11),
    ];
    f + G01_PENALTY * g.iter().map(|c| c.max(0.0)).sum::<f32>()
}

impl Objective for Benchmark {
    fn cost(&mut self, x: &[f32]) -> f32 {
        let base = self.noiseless(x);
        if self.kind == FunctionKind::DeJongQuartic {
            base + self.noise.normal()
        } else {
            base
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn at(kind: FunctionKind, x: &[f32]) -> f32 {
        Benchmark::new(kind, x.len(), 0.0, 0).unwrap().noiseless(x)
    }

    #[test]
    fn known_optima() {
        assert_eq!(at(FunctionKind::DeJongSphere, &[0.0; 3]), 0.0);
        assert_eq!(at(FunctionKind::DeJongRosenbrock, &[1.0, 1.0]), 0.0);
        assert_eq!(at(FunctionKind::DeJongStep, &[-5.1; 5]), -30.0);
        assert_eq!(at(FunctionKind::DeJongQuartic, &[0.0; 30]), 0.0);
        assert!((at(FunctionKind::ShekelFoxholes, &[-32.0, -32.0]) - 0.998_004).abs() < 1e-5);
        assert_eq!(at(FunctionKind::SchafferF6, &[0.0, 0.0]), 0.0);
        assert_eq!(at(FunctionKind::SchafferF7, &[0.0, 0.0]), 0.0);
        assert!((at(FunctionKind::GoldsteinPrice, &[0.0, -1.0]) - 3.0).abs() < 1e-5);
        assert!((at(FunctionKind::Shubert, &[-7.0835, 4.8580]) + 186.7309).abs() < 1e-2);
        assert!((at(FunctionKind::SixHumpCamel, &[0.0898, -0.7126]) + 1.031_628).abs() < 1e-5);
        let mut g = [1.0f32; 13];
        g[9] = 3.0;
        g[10] = 3.0;
        g[11] = 3.0;
        assert_eq!(at(FunctionKind::G01, &g), -15.0);
        // A violated constraint costs more than it gains.
        g[9] = 4.0;
        assert!(at(FunctionKind::G01, &g) > -15.0);
    }

    #[test]
    fn shifted_optima() {
        for kind in SHIFTED {
            let f = Benchmark::new(kind, 10, 2.5, 0).unwrap();
            assert!(f.noiseless(&[2.5; 10]) < 1e-5, "{kind:?}");
            assert!(f.noiseless(&[0.0; 10]) > 1.0, "{kind:?}");
        }
    }

    #[test]
    fn validation_and_names() {
        assert_eq!(
            "f10".parse::<FunctionKind>(),
            Ok(FunctionKind::SixHumpCamel)
        );
        assert_eq!("nope".parse::<FunctionKind>(), Err(OptimError::UnknownName));
        assert!(Benchmark::new(FunctionKind::DeJongSphere, 4, 0.0, 0).is_err());
        assert!(Benchmark::new(FunctionKind::DeJongSphere, 3, 1.0, 0).is_err());
        assert!(Benchmark::new(FunctionKind::Rastrigin, 3, 37.5, 0).is_err());
        assert!(Benchmark::new(FunctionKind::Rosenbrock, 1, 0.0, 0).is_err());
        assert!(
            Benchmark::new(FunctionKind::Sphere, 30, 37.5, 0)
                .unwrap()
                .bounds::<16>()
                .is_err()
        );
        let b = Benchmark::new(FunctionKind::SixHumpCamel, 2, 0.0, 0)
            .unwrap()
            .bounds::<2>()
            .unwrap();
        assert_eq!((b.lower(), b.upper()), (&[-3.0, -2.0][..], &[3.0, 2.0][..]));
    }

    #[test]
    fn quartic_noise_is_seeded() {
        let mut a = Benchmark::new(FunctionKind::DeJongQuartic, 30, 0.0, 9).unwrap();
        let mut b = Benchmark::new(FunctionKind::DeJongQuartic, 30, 0.0, 9).unwrap();
        let x = [0.0f32; 30];
        assert_eq!(a.cost(&x), b.cost(&x));
        assert_ne!(a.cost(&x), 0.0);
    }
}

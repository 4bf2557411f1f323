//! The deterministic schedules the papers vary: HHO's escape energy and GWO's convergence
//! factor `a`.
//!
//! Each is a [`Schedule`]: a value at iteration `t` of a horizon `T`, with `t` in `0..T`.

use super::OptimError;

/// A value that depends only on the iteration `t` and the horizon `T`.
pub trait Schedule {
    /// The value at iteration `t` (`0..T`) of horizon `horizon = T`.
    fn value(&self, t: u32, horizon: u32) -> f32;
}

fn fraction(t: u32, horizon: u32) -> f32 {
    if horizon == 0 {
        1.0
    } else {
        t as f32 / horizon as f32
    }
}

/// The energy factor `E1` that scales HHO's escape energy `E = E0 * E1`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum EscapeEnergy {
    /// `E1 = 2 (1 - t/T)` (HHO, Heidari et al. 2019).
    Linear,
    /// `E1 = 2 (1 - (t/T)^a)` (TCLHHO, `Lei2024Warehouse` eq. 13, `a = 1.2`; the pseudocode's 0.5 is
    /// the literal reading, with the opposite shape).
    Exponential {
        /// The exponent `a > 0`.
        a: f32,
    },
}

impl EscapeEnergy {
    /// TCLHHO's text and table 1: `a = 1.2`.
    pub const TCLHHO: Self = Self::Exponential { a: 1.2 };
    /// TCLHHO's pseudocode (algorithm 1) literally: `a = 0.5`.
    pub const TCLHHO_PSEUDOCODE: Self = Self::Exponential { a: 0.5 };

    pub(crate) fn validate(&self) -> Result<(), OptimError> {
        match self {
            Self::Exponential { a } if !(a.is_finite() && *a > 0.0) => {
                Err(OptimError::InvalidParameter("energy.a"))
            }
            _ => Ok(()),
        }
    }
}

impl Schedule for EscapeEnergy {
    fn value(&self, t: u32, horizon: u32) -> f32 {
        let f = fraction(t, horizon);
        match self {
            Self::Linear => 2.0 * (1.0 - f),
            Self::Exponential { a } => 2.0 * (1.0 - libm::powf(f, *a)),
        }
    }
}

/// GWO's convergence factor `a`, which sets `A = 2 a r1 - a`.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ConvergenceFactor {
    /// `a = 2 - 2 t/T` (GWO, Mirjalili 2014).
    Linear,
    /// `a = a_init exp(-lambda t/T)` (IGWO, `Liu2020Igwo` eq. 9 as SPEC resolves it).
    Exponential {
        /// Initial value (2).
        a_init: f32,
        /// Decay rate (2): `a` ends at `a_init e^-lambda`, 0.27 for the defaults.
        lambda: f32,
    },
    /// Literal `Liu2020Igwo` eq. 9: `a = a_init - exp(-lambda t/T)`, which *rises* from 1 to 1.86.
    ExponentialLiteral {
        /// Initial value (2).
        a_init: f32,
        /// Rate (2).
        lambda: f32,
    },
    /// `a = 4 / (1 + e^(10 t/T))`, from 2 towards 0 (SSA-GWO, `Zhu2025Orchard` eq. 9 mirrored).
    MirroredSigmoid,
    /// Literal `Zhu2025Orchard` eq. 9: `a = 2 / (1 + e^(-10 t/T)) - 1`, which rises from 0 to 1.
    SigmoidLiteral,
}

impl ConvergenceFactor {
    /// IGWO's defaults: `a_init = 2`, `lambda = 2`.
    pub const IGWO: Self = Self::Exponential {
        a_init: 2.0,
        lambda: 2.0,
    };

    pub(crate) fn validate(&self) -> Result<(), OptimError> {
        match self {
            Self::Exponential { a_init, lambda } | Self::ExponentialLiteral { a_init, lambda } => {
                if !a_init.is_finite() || *a_init < 0.0 {
                    return Err(OptimError::InvalidParameter("a_init"));
                }
                if !lambda.is_finite() {
                    return Err(OptimError::InvalidParameter("lambda"));
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
}

impl Schedule for ConvergenceFactor {
    fn value(&self, t: u32, horizon: u32) -> f32 {
        let f = fraction(t, horizon);
        match self {
            Self::Linear => 2.0 - 2.0 * f,
            Self::Exponential { a_init, lambda } => a_init * libm::expf(-lambda * f),
            Self::ExponentialLiteral { a_init, lambda } => a_init - libm::expf(-lambda * f),
            Self::MirroredSigmoid => 4.0 / (1.0 + libm::expf(10.0 * f)),
            Self::SigmoidLiteral => 2.0 / (1.0 + libm::expf(-10.0 * f)) - 1.0,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tclhho_e1_at_start_middle_end() {
        let e = EscapeEnergy::TCLHHO;
        let t_max = 500;
        assert_eq!(e.value(0, t_max), 2.0);
        // 2 (1 - 0.5^1.2) = 1.129_449
        assert!(
            (e.value(250, t_max) - 1.129_449).abs() < 1e-5,
            "{}",
            e.value(250, t_max)
        );
        // 2 (1 - (499/500)^1.2) = 0.004_797
        assert!(
            (e.value(499, t_max) - 0.004_797).abs() < 1e-5,
            "{}",
            e.value(499, t_max)
        );
        // The exponent bends E1 above the linear schedule: more exploration mid-run; the
        // pseudocode's 0.5 bends it below (the opposite shape).
        assert!(e.value(250, t_max) > EscapeEnergy::Linear.value(250, t_max));
        assert!(EscapeEnergy::TCLHHO_PSEUDOCODE.value(250, t_max) < 1.0);
    }

    #[test]
    fn hho_e1_linear() {
        assert_eq!(EscapeEnergy::Linear.value(0, 10), 2.0);
        assert_eq!(EscapeEnergy::Linear.value(5, 10), 1.0);
        assert!((EscapeEnergy::Linear.value(9, 10) - 0.2).abs() < 1e-6);
    }

    #[test]
    fn igwo_factor_falls_from_2_to_about_0_27() {
        let a = ConvergenceFactor::IGWO;
        assert_eq!(a.value(0, 500), 2.0);
        let end = a.value(500, 500);
        assert!(
            (end - 2.0 * libm::expf(-2.0)).abs() < 1e-6 && (end - 0.27).abs() < 0.01,
            "{end}"
        );
        let mut prev = f32::INFINITY;
        for t in 0..=500 {
            let v = a.value(t, 500);
            assert!(v < prev);
            prev = v;
        }
        // The printed formula rises from 1 to 1.86 instead.
        let lit = ConvergenceFactor::ExponentialLiteral {
            a_init: 2.0,
            lambda: 2.0,
        };
        assert_eq!(lit.value(0, 500), 1.0);
        assert!((lit.value(500, 500) - 1.8647).abs() < 1e-3);
    }

    #[test]
    fn ssa_gwo_factor_falls_from_2_towards_0() {
        let a = ConvergenceFactor::MirroredSigmoid;
        assert_eq!(a.value(0, 500), 2.0);
        assert!(a.value(500, 500) < 2e-4);
        assert!((a.value(250, 500) - 4.0 / (1.0 + libm::expf(5.0))).abs() < 1e-6);
        let mut prev = f32::INFINITY;
        for t in 0..=500 {
            let v = a.value(t, 500);
            assert!(v < prev);
            prev = v;
        }
        // The printed sigmoid rises from 0 to 1 (never above 1: no exploration ever).
        assert_eq!(ConvergenceFactor::SigmoidLiteral.value(0, 500), 0.0);
        assert!(ConvergenceFactor::SigmoidLiteral.value(500, 500) < 1.0);
    }

    #[test]
    fn gwo_factor_linear() {
        assert_eq!(ConvergenceFactor::Linear.value(0, 4), 2.0);
        assert_eq!(ConvergenceFactor::Linear.value(2, 4), 1.0);
    }

    #[test]
    fn validation() {
        assert!(
            EscapeEnergy::Exponential { a: f32::NAN }
                .validate()
                .is_err()
        );
        assert!(EscapeEnergy::Exponential { a: 0.0 }.validate().is_err());
        assert!(
            ConvergenceFactor::Exponential {
                a_init: 2.0,
                lambda: f32::NAN
            }
            .validate()
            .is_err()
        );
        assert!(ConvergenceFactor::IGWO.validate().is_ok());
    }
}

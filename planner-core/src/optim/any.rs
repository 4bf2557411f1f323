//! Selecting an algorithm by name: [`AlgorithmKind`] and the dispatcher [`AnyOptimizer`].
//!
//! ```
//! use planner_core::optim::any::{AlgorithmKind, AnyOptimizer};
//! use planner_core::optim::{Bounds, Optimizer, Settings, Stop};
//!
//! let kind: AlgorithmKind = "tclhho".parse()?;
//! let bounds = Bounds::<4>::uniform(4, -5.0, 5.0)?;
//! let settings = Settings { population: 10, iterations: 50, seed: 3 };
//! let mut opt = AnyOptimizer::<10, 4>::new(kind, settings, &bounds)?;
//! let mut f = |x: &[f32]| x.iter().map(|v| v * v).sum::<f32>();
//! let report = opt.run(&mut f, None, &Stop::default(), &mut [])?;
//! assert!(report.best_cost < 1e-3);
//! assert!("aco".parse::<AlgorithmKind>().is_err());
//! # Ok::<(), planner_core::optim::OptimError>(())
//! ```

use core::str::FromStr;

use super::ga::{Ga, GaParams};
use super::gwo::{Gwo, GwoParams};
use super::hho::{Hho, HhoParams};
use super::pso::{Pso, PsoParams};
use super::ssa::{Ssa, SsaParams};
use super::ssa_gwo::{SsaGwo, SsaGwoParams};
use super::{Bounds, Objective, OptimError, Optimizer, Settings};

/// The algorithms, by their command-line names.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum AlgorithmKind {
    /// `hho`
    Hho,
    /// `tclhho`
    Tclhho,
    /// `gwo`
    Gwo,
    /// `tgwo`
    Tgwo,
    /// `igwo`
    Igwo,
    /// `ssa`
    Ssa,
    /// `ssagwo`
    SsaGwo,
    /// `pso`
    Pso,
    /// `ga`
    Ga,
}

impl AlgorithmKind {
    /// Every algorithm, in a fixed order.
    pub const ALL: [Self; 9] =
        [Self::Hho, Self::Tclhho, Self::Gwo, Self::Tgwo, Self::Igwo, Self::Ssa, Self::SsaGwo, Self::Pso, Self::Ga];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            Self::Hho => "hho",
            Self::Tclhho => "tclhho",
            Self::Gwo => "gwo",
            Self::Tgwo => "tgwo",
            Self::Igwo => "igwo",
            Self::Ssa => "ssa",
            Self::SsaGwo => "ssagwo",
            Self::Pso => "pso",
            Self::Ga => "ga",
        }
    }
}

impl FromStr for AlgorithmKind {
    type Err = OptimError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL.iter().copied().find(|k| k.name().eq_ignore_ascii_case(s)).ok_or(OptimError::UnknownName)
    }
}

/// Any optimizer with its default (paper) parameters, behind one type.
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)]
pub enum AnyOptimizer<const N: usize, const D: usize> {
    /// HHO or TCLHHO.
    Hho(Hho<N, D>),
    /// GWO, TGWO or IGWO.
    Gwo(Gwo<N, D>),
    /// SSA.
    Ssa(Ssa<N, D>),
    /// SSA-GWO.
    SsaGwo(SsaGwo<N, D>),
    /// PSO.
    Pso(Pso<N, D>),
    /// GA.
    Ga(Ga<N, D>),
}

impl<const N: usize, const D: usize> AnyOptimizer<N, D> {
    /// The algorithm `kind` with its default parameters.
    pub fn new(kind: AlgorithmKind, settings: Settings, bounds: &Bounds<D>) -> Result<Self, OptimError> {
        Ok(match kind {
            AlgorithmKind::Hho => Self::Hho(Hho::new(settings, bounds, HhoParams::hho())?),
            AlgorithmKind::Tclhho => Self::Hho(Hho::new(settings, bounds, HhoParams::tclhho())?),
            AlgorithmKind::Gwo => Self::Gwo(Gwo::new(settings, bounds, GwoParams::gwo())?),
            AlgorithmKind::Tgwo => Self::Gwo(Gwo::new(settings, bounds, GwoParams::tgwo())?),
            AlgorithmKind::Igwo => Self::Gwo(Gwo::new(settings, bounds, GwoParams::igwo())?),
            AlgorithmKind::Ssa => Self::Ssa(Ssa::new(settings, bounds, SsaParams::ssa())?),
            AlgorithmKind::SsaGwo => Self::SsaGwo(SsaGwo::new(settings, bounds, SsaGwoParams::seed_001())?),
            AlgorithmKind::Pso => Self::Pso(Pso::new(settings, bounds, PsoParams::seed_003())?),
            AlgorithmKind::Ga => Self::Ga(Ga::new(settings, bounds, GaParams::seed_003())?),
        })
    }
}

macro_rules! dispatch {
    ($self:ident, $o:ident => $e:expr) => {
        match $self {
            AnyOptimizer::Hho($o) => $e,
            AnyOptimizer::Gwo($o) => $e,
            AnyOptimizer::Ssa($o) => $e,
            AnyOptimizer::SsaGwo($o) => $e,
            AnyOptimizer::Pso($o) => $e,
            AnyOptimizer::Ga($o) => $e,
        }
    };
}

impl<const N: usize, const D: usize> Optimizer for AnyOptimizer<N, D> {
    fn init<O: Objective + ?Sized>(&mut self, objective: &mut O, initial: Option<&[&[f32]]>) -> Result<(), OptimError> {
        dispatch!(self, o => o.init(objective, initial))
    }
    fn step<O: Objective + ?Sized>(&mut self, objective: &mut O) -> Result<(), OptimError> {
        dispatch!(self, o => o.step(objective))
    }
    fn best_position(&self) -> &[f32] {
        dispatch!(self, o => o.best_position())
    }
    fn best_cost(&self) -> f32 {
        dispatch!(self, o => o.best_cost())
    }
    fn iteration(&self) -> u32 {
        dispatch!(self, o => o.iteration())
    }
    fn evaluations(&self) -> u64 {
        dispatch!(self, o => o.evaluations())
    }
    fn best_iteration(&self) -> u32 {
        dispatch!(self, o => o.best_iteration())
    }
    fn horizon(&self) -> u32 {
        dispatch!(self, o => o.horizon())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for k in AlgorithmKind::ALL {
            assert_eq!(k.name().parse::<AlgorithmKind>(), Ok(k));
        }
        assert_eq!("ACO".parse::<AlgorithmKind>(), Err(OptimError::UnknownName));
        assert_eq!("TCLHHO".parse::<AlgorithmKind>(), Ok(AlgorithmKind::Tclhho));
    }

    /// The capacities only bound the sizes: the same runtime sizes and seed give bit-identical
    /// runs whatever `N` and `D` are (the firmware's 30 x 64 and the host's 128 x 128 agree).
    #[test]
    fn results_do_not_depend_on_capacity() {
        use crate::optim::Stop;
        let mut f = |x: &[f32]| x.iter().enumerate().map(|(i, v)| (v - i as f32) * (v - i as f32)).sum::<f32>();
        for kind in AlgorithmKind::ALL {
            let s = Settings { population: 12, iterations: 40, seed: 77 };
            let small = Bounds::<6>::uniform(6, -10.0, 10.0).unwrap();
            let big = Bounds::<20>::uniform(6, -10.0, 10.0).unwrap();
            let mut a = AnyOptimizer::<12, 6>::new(kind, s, &small).unwrap();
            let mut b = AnyOptimizer::<40, 20>::new(kind, s, &big).unwrap();
            let ra = a.run(&mut f, None, &Stop::default(), &mut []).unwrap();
            let rb = b.run(&mut f, None, &Stop::default(), &mut []).unwrap();
            assert_eq!(ra, rb, "{kind:?}");
            assert_eq!(a.best_position(), b.best_position(), "{kind:?}");
        }
    }
}

//! The optimizers [`plan`](super::plan) can run: [`PlanOptimizer`] configures an algorithm
//! in place, and [`HhoOrGwo`] is the storage of a firmware plan (the papers' TCLHHO and IGWO
//! families in the space of the larger, a third of [`AnyOptimizer`]'s).

use crate::optim::any::{AlgorithmKind, AnyOptimizer};
use crate::optim::gwo::{Gwo, GwoParams};
use crate::optim::hho::{Hho, HhoParams};
use crate::optim::{Bounds, OptimError, Optimizer, Settings};

/// The optimizer storage [`plan`](super::plan) runs: it configures the algorithm in place, so firmware can
/// keep the whole optimizer state in a `static` (no large temporary on the stack).
///
/// [`AnyOptimizer`] serves every [`AlgorithmKind`]; its size is that of its largest variant
/// (PSO). [`Hho`] serves HHO and TCLHHO only and [`Gwo`] GWO, TGWO and IGWO only (about a
/// third of that size), [`HhoOrGwo`] both families in the space of the larger: other kinds
/// are [`PlanError::InvalidParameters`](crate::PlanError::InvalidParameters).
pub trait PlanOptimizer<const N: usize, const D: usize>: Optimizer {
    /// Configures `kind` with its default (paper) parameters, in place.
    fn configure_kind(
        &mut self,
        kind: AlgorithmKind,
        settings: Settings,
        bounds: &Bounds<D>,
    ) -> Result<(), OptimError>;
}

impl<const N: usize, const D: usize> PlanOptimizer<N, D> for AnyOptimizer<N, D> {
    fn configure_kind(
        &mut self,
        kind: AlgorithmKind,
        settings: Settings,
        bounds: &Bounds<D>,
    ) -> Result<(), OptimError> {
        self.configure(kind, settings, bounds)
    }
}

impl<const N: usize, const D: usize> PlanOptimizer<N, D> for Hho<N, D> {
    fn configure_kind(
        &mut self,
        kind: AlgorithmKind,
        settings: Settings,
        bounds: &Bounds<D>,
    ) -> Result<(), OptimError> {
        let params = match kind {
            AlgorithmKind::Hho => HhoParams::hho(),
            AlgorithmKind::Tclhho => HhoParams::tclhho(),
            _ => return Err(OptimError::UnknownName),
        };
        self.configure(settings, bounds, params)
    }
}

impl<const N: usize, const D: usize> PlanOptimizer<N, D> for Gwo<N, D> {
    fn configure_kind(
        &mut self,
        kind: AlgorithmKind,
        settings: Settings,
        bounds: &Bounds<D>,
    ) -> Result<(), OptimError> {
        let params = match kind {
            AlgorithmKind::Gwo => GwoParams::gwo(),
            AlgorithmKind::Tgwo => GwoParams::tgwo(),
            AlgorithmKind::Igwo => GwoParams::igwo(),
            _ => return Err(OptimError::UnknownName),
        };
        self.configure(settings, bounds, params)
    }
}

/// HHO and TCLHHO, or GWO, TGWO and IGWO: what a firmware plan runs, in the space of the
/// larger family. Configuring a kind of the other family replaces the variant in place (from a
/// constant, so no large temporary lands on the stack).
#[allow(clippy::large_enum_variant)]
pub enum HhoOrGwo<const N: usize, const D: usize> {
    /// HHO or TCLHHO.
    Hho(Hho<N, D>),
    /// GWO, TGWO or IGWO.
    Gwo(Gwo<N, D>),
}

impl<const N: usize, const D: usize> HhoOrGwo<N, D> {
    // Switching family assigns from these constants: the value is copied into place, where
    // `HhoOrGwo::Gwo(Gwo::unconfigured())` built a 9 KiB temporary on the MCU's stack first.
    const HHO: Self = HhoOrGwo::Hho(Hho::unconfigured());
    const GWO: Self = HhoOrGwo::Gwo(Gwo::unconfigured());

    /// Unconfigured (HHO family), all zero bytes: a `static` of it is in `.bss`.
    pub const fn unconfigured() -> Self {
        Self::HHO
    }
}

impl<const N: usize, const D: usize> Default for HhoOrGwo<N, D> {
    fn default() -> Self {
        Self::unconfigured()
    }
}

crate::optim::forward_optimizer!(HhoOrGwo: Hho, Gwo);

impl<const N: usize, const D: usize> PlanOptimizer<N, D> for HhoOrGwo<N, D> {
    fn configure_kind(
        &mut self,
        kind: AlgorithmKind,
        settings: Settings,
        bounds: &Bounds<D>,
    ) -> Result<(), OptimError> {
        let hho = matches!(kind, AlgorithmKind::Hho | AlgorithmKind::Tclhho);
        match self {
            HhoOrGwo::Hho(_) if !hho => *self = Self::GWO,
            HhoOrGwo::Gwo(_) if hho => *self = Self::HHO,
            _ => {}
        }
        match self {
            HhoOrGwo::Hho(o) => o.configure_kind(kind, settings, bounds),
            HhoOrGwo::Gwo(o) => o.configure_kind(kind, settings, bounds),
        }
    }
}

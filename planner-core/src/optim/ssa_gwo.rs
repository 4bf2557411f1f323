//! SSA-GWO (seed 001): a grey-wolf step then a sparrow-search step on the same population
//! each iteration.
//!
//! As SPEC resolves the paper: opposition-based initialisation (the best `N` of `N` uniform
//! points and their opposites `lb + ub - x`; the printed formula is the identity), the mirrored
//! sigmoid convergence factor `a = 4 / (1 + e^(10 t/T))` (2 towards 0; the printed sigmoid
//! rises 0 -> 1 and is [`ConvergenceFactor::SigmoidLiteral`]), greedy keep in both phases, and
//! the three leaders recomputed from the population after both phases. The "SSA phase" is real
//! sparrow search ([`crate::optim::ssa`]) with `ST = 0.6`, `PD = 0.4`, `SD = 0.2`.
//!
//! Evaluations: `2N` at initialisation, then `2N + round(SD N)` per iteration.

use super::gwo::{Leaders, hunt};
use super::schedule::{ConvergenceFactor, Schedule};
use super::ssa::{SsaParams, sparrow_step};
use super::{
    Bounds, Initialisation, Objective, OptimError, Optimizer, Settings, Swarm, swarm_accessors,
};

/// Options of SSA-GWO.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SsaGwoParams {
    /// The GWO phase's convergence factor.
    pub factor: ConvergenceFactor,
    /// The sparrow phase (its `init` is the whole algorithm's initialisation).
    pub sparrow: SsaParams,
}

impl SsaGwoParams {
    /// Seed 001 as SPEC resolves it.
    pub const fn seed_001() -> Self {
        let mut sparrow = SsaParams::seed_001();
        sparrow.init = Initialisation::Opposition;
        Self {
            factor: ConvergenceFactor::MirroredSigmoid,
            sparrow,
        }
    }

    fn validate(&self) -> Result<(), OptimError> {
        self.factor.validate()?;
        self.sparrow.validate()
    }
}

impl Default for SsaGwoParams {
    fn default() -> Self {
        Self::seed_001()
    }
}

/// SSA-GWO with capacity `N` of `D` dimensions.
#[derive(Debug, Clone)]
pub struct SsaGwo<const N: usize, const D: usize> {
    swarm: Swarm<N, D>,
    params: SsaGwoParams,
    leaders: Leaders<D>,
}

impl<const N: usize, const D: usize> SsaGwo<N, D> {
    /// Validates and builds; call [`Optimizer::init`] next. Needs at least 3 members.
    pub fn new(
        settings: Settings,
        bounds: &Bounds<D>,
        params: SsaGwoParams,
    ) -> Result<Self, OptimError> {
        params.validate()?;
        Ok(Self {
            swarm: Swarm::new(settings, bounds, 3)?,
            params,
            leaders: Leaders::new(),
        })
    }

    /// The leaders as recomputed after the last iteration.
    pub fn leaders(&self) -> &Leaders<D> {
        &self.leaders
    }
}

impl<const N: usize, const D: usize> Optimizer for SsaGwo<N, D> {
    fn init<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        initial: Option<&[&[f32]]>,
    ) -> Result<(), OptimError> {
        self.swarm
            .initialise(objective, self.params.sparrow.init, initial)?;
        self.leaders = Leaders::from_population(&self.swarm.pop);
        Ok(())
    }

    fn step<O: Objective + ?Sized>(&mut self, objective: &mut O) -> Result<(), OptimError> {
        let t = self.swarm.begin_step()?;
        let a = self.params.factor.value(t, self.swarm.settings.iterations);
        let sw = &mut self.swarm;
        let dim = sw.dim();
        let mut cand = [0.0f32; D];
        for i in 0..sw.n() {
            hunt(sw.pop.position(i), &self.leaders, a, &mut sw.rng, &mut cand);
            let c = cand.get_mut(..dim).unwrap_or(&mut []);
            sw.bounds.clamp(c);
            let cost = sw.tracker.evaluate(objective, c);
            if cost < sw.pop.cost(i) {
                sw.pop.replace(i, c, cost);
            }
        }
        sparrow_step(
            &mut sw.pop,
            &sw.bounds,
            &mut sw.rng,
            &mut sw.tracker,
            objective,
            &self.params.sparrow,
            sw.settings.iterations,
        );
        self.leaders = Leaders::from_population(&sw.pop);
        Ok(())
    }

    swarm_accessors!();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::Stop;

    #[test]
    fn counts_and_leaders() {
        let b = Bounds::<5>::uniform(5, -10.0, 10.0).unwrap();
        let s = Settings {
            population: 20,
            iterations: 25,
            seed: 2,
        };
        let mut a = SsaGwo::<20, 5>::new(s, &b, SsaGwoParams::seed_001()).unwrap();
        let mut obj = |x: &[f32]| x.iter().map(|v| (v - 3.0) * (v - 3.0)).sum::<f32>();
        let r = a.run(&mut obj, None, &Stop::default(), &mut []).unwrap();
        assert_eq!(r.evaluations, 40 + 25 * (20 + 20 + 4));
        // Greedy keep: the population holds the best point ever seen, which is alpha.
        assert_eq!(a.leaders().alpha.cost, r.best_cost);
    }
}

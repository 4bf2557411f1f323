//! SSA-GWO (`Zhu2025Orchard`): a grey-wolf step then a sparrow-search step on the same population
//! each iteration.
//!
//! As SPEC resolves the paper: opposition-based initialisation (the best `N` of `N` uniform
//! points and their opposites `lb + ub - x`; the printed formula is the identity), the mirrored
//! sigmoid convergence factor `a = 4 / (1 + e^(10 t/T))` (2 towards 0; the printed sigmoid
//! rises 0 -> 1 and is [`ConvergenceFactor::SigmoidLiteral`]), greedy keep in both phases, and
//! the three leaders recomputed from the population after both phases. The "SSA phase" is real
//! sparrow search ([`crate::optim::ssa`]) with `ST = 0.6`, `PD = 0.4`, `SD = 0.2`; the
//! PSO-style reading is the variant [`SsaGwoPso`].
//!
//! Evaluations: `2N` at initialisation, then `2N + round(SD N)` per iteration.

use super::gwo::{Leaders, hunt};
use super::pso::PsoParams;
use super::schedule::{ConvergenceFactor, Schedule};
use super::ssa::{SsaParams, sparrow_step};
use super::{
    Bounds, Initialisation, Objective, OptimError, Optimizer, Settings, SwarmState, copy,
    swarm_accessors,
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
    /// `Zhu2025Orchard` as SPEC resolves it.
    pub const fn zhu2025_orchard() -> Self {
        let mut sparrow = SsaParams::zhu2025_orchard();
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
        Self::zhu2025_orchard()
    }
}

/// SSA-GWO with capacity `N` of `D` dimensions.
#[derive(Debug, Clone)]
pub struct SsaGwo<const N: usize, const D: usize> {
    swarm: SwarmState<N, D>,
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
        let mut s = Self::unconfigured();
        s.configure(settings, bounds, params)?;
        Ok(s)
    }

    /// An unconfigured instance for `const`/`static` initialisers (firmware keeps the state
    /// in a `static` and calls [`configure`](Self::configure) on it, so no large temporary
    /// passes through the stack); `init` fails until it is configured.
    pub const fn unconfigured() -> Self {
        Self {
            swarm: SwarmState::unconfigured(),
            params: SsaGwoParams::zhu2025_orchard(),
            leaders: Leaders::new(),
        }
    }

    /// Validates and takes a configuration in place (needs at least 3 members); on
    /// error nothing changes. Call [`Optimizer::init`] next.
    pub fn configure(
        &mut self,
        settings: Settings,
        bounds: &Bounds<D>,
        params: SsaGwoParams,
    ) -> Result<(), OptimError> {
        params.validate()?;
        self.swarm.configure(settings, bounds, 3)?;
        self.params = params;
        Ok(())
    }

    /// The leaders as recomputed after the last iteration.
    pub fn leaders(&self) -> &Leaders<D> {
        &self.leaders
    }

    /// Starts an iteration and runs its grey-wolf phase (greedy keep).
    fn wolf_phase<O: Objective + ?Sized>(&mut self, objective: &mut O) -> Result<(), OptimError> {
        let t = self.swarm.begin_step()?;
        let a = self.params.factor.value(t, self.swarm.settings.iterations);
        let sw = &mut self.swarm;
        let dim = sw.dim();
        let mut cand = [0.0f32; D];
        for i in 0..sw.n() {
            hunt(
                sw.pop.position(i),
                &self.leaders,
                a,
                &mut sw.rng,
                &mut cand,
                false,
            );
            let c = cand.get_mut(..dim).unwrap_or(&mut []);
            let cost = sw.clamp_and_evaluate(objective, c);
            if cost < sw.pop.cost(i) {
                sw.pop.replace(i, c, cost);
            }
        }
        Ok(())
    }
}

/// The literal reading of `Zhu2025Orchard`'s second phase: PSO equations (eq. 10-11) instead of
/// sparrow search, as a variant only (SPEC).
///
/// After each grey-wolf phase every member moves by `v = w v + c1 r1 (p - x) + c2 r2 (g - x)`,
/// `x' = x + v` (velocities clamped as in [`crate::optim::pso`]), with `p` its own best (the
/// greedy population itself, so the cognitive term is zero, as the paper's equations imply)
/// and `g` the alpha; `x'` is kept only if better. It needs a velocity buffer of `N x D`, which
/// is why it is a separate type. Evaluations: `2N` at initialisation, then `2N` per iteration.
#[derive(Debug, Clone)]
pub struct SsaGwoPso<const N: usize, const D: usize> {
    inner: SsaGwo<N, D>,
    pso: PsoParams,
    velocity: [[f32; D]; N],
}

impl<const N: usize, const D: usize> SsaGwoPso<N, D> {
    /// Validates and builds; `params.sparrow` only supplies the initialisation.
    pub fn new(
        settings: Settings,
        bounds: &Bounds<D>,
        params: SsaGwoParams,
        pso: PsoParams,
    ) -> Result<Self, OptimError> {
        let mut s = Self::unconfigured();
        s.configure(settings, bounds, params, pso)?;
        Ok(s)
    }

    /// An unconfigured instance for `const`/`static` initialisers.
    pub const fn unconfigured() -> Self {
        Self {
            inner: SsaGwo::unconfigured(),
            pso: PsoParams::zhu2025_orchard(),
            velocity: [[0.0; D]; N],
        }
    }

    /// Validates and takes a configuration in place; on error nothing changes.
    pub fn configure(
        &mut self,
        settings: Settings,
        bounds: &Bounds<D>,
        params: SsaGwoParams,
        pso: PsoParams,
    ) -> Result<(), OptimError> {
        pso.validate()?;
        self.inner.configure(settings, bounds, params)?;
        self.pso = pso;
        Ok(())
    }
}

impl<const N: usize, const D: usize> Optimizer for SsaGwoPso<N, D> {
    fn init<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        initial: Option<&[&[f32]]>,
    ) -> Result<(), OptimError> {
        self.velocity = [[0.0; D]; N];
        self.inner.init(objective, initial)
    }

    fn step<O: Objective + ?Sized>(&mut self, objective: &mut O) -> Result<(), OptimError> {
        self.inner.wolf_phase(objective)?;
        let p = self.pso;
        let sw = &mut self.inner.swarm;
        let dim = sw.dim();
        let mut cand = [0.0f32; D];
        let mut alpha = [0.0f32; D];
        copy(&mut alpha, sw.tracker.best());
        for (i, vel) in self.velocity.iter_mut().enumerate().take(sw.n()) {
            let x = sw.pop.position(i);
            for (d, ((v, c), (xd, g))) in vel
                .iter_mut()
                .zip(cand.iter_mut())
                .zip(x.iter().zip(&alpha))
                .enumerate()
            {
                // r1 belongs to the cognitive term c1 r1 (p - x), which is zero here (the
                // population holds each member's best, p = x); it is drawn all the same so the
                // draws follow the equation.
                let _r1 = sw.rng.unit();
                let r2 = sw.rng.unit();
                let width = sw.bounds.upper().get(d).copied().unwrap_or(0.0)
                    - sw.bounds.lower().get(d).copied().unwrap_or(0.0);
                let vmax = p.vmax_fraction * width;
                let nv = p.w * *v + p.c2 * r2 * (g - xd);
                *v = nv.max(-vmax).min(vmax);
                *c = xd + *v;
            }
            let c = cand.get_mut(..dim).unwrap_or(&mut []);
            let cost = sw.clamp_and_evaluate(objective, c);
            if cost < sw.pop.cost(i) {
                sw.pop.replace(i, c, cost);
            }
        }
        self.inner.leaders = Leaders::from_population(&sw.pop);
        Ok(())
    }

    fn best_position(&self) -> &[f32] {
        self.inner.best_position()
    }
    fn best_cost(&self) -> f32 {
        self.inner.best_cost()
    }
    fn iteration(&self) -> u32 {
        self.inner.iteration()
    }
    fn evaluations(&self) -> u64 {
        self.inner.evaluations()
    }
    fn best_iteration(&self) -> u32 {
        self.inner.best_iteration()
    }
    fn horizon(&self) -> u32 {
        self.inner.horizon()
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
        self.wolf_phase(objective)?;
        sparrow_step(&mut self.swarm, objective, &self.params.sparrow);
        self.leaders = Leaders::from_population(&self.swarm.pop);
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
        let mut a = SsaGwo::<20, 5>::new(s, &b, SsaGwoParams::zhu2025_orchard()).unwrap();
        let mut obj = |x: &[f32]| x.iter().map(|v| (v - 3.0) * (v - 3.0)).sum::<f32>();
        let r = a.run(&mut obj, None, &Stop::default(), &mut []).unwrap();
        assert_eq!(r.evaluations, 40 + 25 * (20 + 20 + 4));
        // Greedy keep: the population holds the best point ever seen, which is alpha.
        assert_eq!(a.leaders().alpha.cost, r.best_cost);
    }

    #[test]
    fn pso_variant_counts_and_improves() {
        let b = Bounds::<5>::uniform(5, -10.0, 10.0).unwrap();
        let s = Settings {
            population: 20,
            iterations: 50,
            seed: 2,
        };
        let mut a = SsaGwoPso::<20, 5>::new(
            s,
            &b,
            SsaGwoParams::zhu2025_orchard(),
            PsoParams::zhu2025_orchard(),
        )
        .unwrap();
        let mut obj = |x: &[f32]| x.iter().map(|v| (v - 3.0) * (v - 3.0)).sum::<f32>();
        let mut hist = [0.0f32; 50];
        let r = a.run(&mut obj, None, &Stop::default(), &mut hist).unwrap();
        assert_eq!(r.evaluations, 40 + 50 * 40);
        assert!(r.best_cost < hist[0]);
        let mut bad = PsoParams::zhu2025_orchard();
        bad.w = f32::NAN;
        assert!(SsaGwoPso::<20, 5>::new(s, &b, SsaGwoParams::zhu2025_orchard(), bad).is_err());
    }
}

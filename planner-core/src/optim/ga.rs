//! Real-coded generational genetic algorithm (baseline of `Liu2020Igwo`: crossover 0.9,
//! mutation 0.1).
//!
//! Each generation keeps the best member (elitism) and fills the rest of the next generation
//! with children of binary-tournament parents: with the crossover probability, a blend
//! `c1 = b p1 + (1 - b) p2`, `c2 = (1 - b) p1 + b p2` (`b ~ U(0, 1)`), else copies; then each
//! gene mutates with the mutation probability by a Gaussian step of
//! `sigma (ub - lb) (1 - t/T)` (shrinking so the GA can refine late), clamped to the box.
//! `Liu2020Igwo` gives only the two rates; the operators are the common textbook choices.
//!
//! Evaluations: `N` at initialisation, then `N - 1` per generation (the elite is not
//! re-evaluated).

use super::{
    Bounds, Initialisation, Objective, OptimError, Optimizer, Population, Settings, SwarmState,
    check_param, swarm_accessors,
};

/// Options of the GA.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GaParams {
    /// Initial population.
    pub init: Initialisation,
    /// Probability that a parent pair is recombined, in `[0, 1]`.
    pub crossover: f32,
    /// Probability that a gene mutates, in `[0, 1]`.
    pub mutation: f32,
    /// Initial mutation step as a fraction of the box width, in `[0, 1]`.
    pub sigma: f32,
}

impl GaParams {
    /// `Liu2020Igwo`: crossover 0.9, mutation 0.1 (step 0.1 of the width).
    pub const fn liu2020_igwo() -> Self {
        Self {
            init: Initialisation::Uniform,
            crossover: 0.9,
            mutation: 0.1,
            sigma: 0.1,
        }
    }

    fn validate(&self) -> Result<(), OptimError> {
        self.init.validate()?;
        check_param(self.crossover, 0.0, 1.0, "crossover")?;
        check_param(self.mutation, 0.0, 1.0, "mutation")?;
        check_param(self.sigma, 0.0, 1.0, "sigma")
    }
}

impl Default for GaParams {
    fn default() -> Self {
        Self::liu2020_igwo()
    }
}

/// The GA with capacity `N` individuals of `D` genes.
#[derive(Debug, Clone)]
pub struct Ga<const N: usize, const D: usize> {
    swarm: SwarmState<N, D>,
    params: GaParams,
    offspring: Population<N, D>,
}

impl<const N: usize, const D: usize> Ga<N, D> {
    /// Validates and builds; call [`Optimizer::init`] next. Needs at least 2 individuals.
    pub fn new(
        settings: Settings,
        bounds: &Bounds<D>,
        params: GaParams,
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
            params: GaParams::liu2020_igwo(),
            offspring: Population::empty(),
        }
    }

    /// Validates and takes a configuration in place (needs at least 2 members); on
    /// error nothing changes. Call [`Optimizer::init`] next.
    pub fn configure(
        &mut self,
        settings: Settings,
        bounds: &Bounds<D>,
        params: GaParams,
    ) -> Result<(), OptimError> {
        params.validate()?;
        self.swarm.configure(settings, bounds, 2)?;
        self.params = params;
        self.offspring.resize(settings.population, bounds.dim());
        Ok(())
    }

    fn tournament(&mut self) -> usize {
        let n = self.swarm.n();
        let a = self.swarm.rng.index(n);
        let b = self.swarm.rng.index(n);
        if self.swarm.pop.cost(b) < self.swarm.pop.cost(a) {
            b
        } else {
            a
        }
    }
}

impl<const N: usize, const D: usize> Optimizer for Ga<N, D> {
    fn init<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        initial: Option<&[&[f32]]>,
    ) -> Result<(), OptimError> {
        self.swarm.initialise(objective, self.params.init, initial)
    }

    fn step<O: Objective + ?Sized>(&mut self, objective: &mut O) -> Result<(), OptimError> {
        let t = self.swarm.begin_step()?;
        let n = self.swarm.n();
        let dim = self.swarm.dim();
        let p = self.params;
        let shrink = 1.0 - t as f32 / self.swarm.settings.iterations as f32;
        let elite = self.swarm.pop.best_index();
        self.offspring.replace(
            0,
            self.swarm.pop.position(elite),
            self.swarm.pop.cost(elite),
        );
        let mut k = 1;
        let mut c1 = [0.0f32; D];
        let mut c2 = [0.0f32; D];
        while k < n {
            let pa = self.tournament();
            let pb = self.tournament();
            let sw = &mut self.swarm;
            let recombine = sw.rng.unit() < p.crossover;
            let blend = sw.rng.unit();
            for ((x1, x2), (a, b)) in c1
                .iter_mut()
                .zip(c2.iter_mut())
                .zip(sw.pop.position(pa).iter().zip(sw.pop.position(pb)))
            {
                if recombine {
                    *x1 = blend * a + (1.0 - blend) * b;
                    *x2 = (1.0 - blend) * a + blend * b;
                } else {
                    *x1 = *a;
                    *x2 = *b;
                }
            }
            for child in [&mut c1, &mut c2] {
                if k >= n {
                    break;
                }
                for (g, (l, u)) in child
                    .iter_mut()
                    .zip(sw.bounds.lower().iter().zip(sw.bounds.upper()))
                {
                    if sw.rng.unit() < p.mutation {
                        *g += sw.rng.normal() * p.sigma * (u - l) * shrink;
                    }
                }
                let c = child.get_mut(..dim).unwrap_or(&mut []);
                let cost = sw.clamp_and_evaluate(objective, c);
                self.offspring.replace(k, c, cost);
                k += 1;
            }
        }
        core::mem::swap(&mut self.swarm.pop, &mut self.offspring);
        Ok(())
    }

    swarm_accessors!();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::Stop;

    #[test]
    fn ga_improves_and_counts() {
        let b = Bounds::<4>::uniform(4, -10.0, 10.0).unwrap();
        let s = Settings {
            population: 21,
            iterations: 100,
            seed: 1,
        };
        let mut ga = Ga::<21, 4>::new(s, &b, GaParams::liu2020_igwo()).unwrap();
        let mut obj = |x: &[f32]| x.iter().map(|v| (v - 3.0) * (v - 3.0)).sum::<f32>();
        let r = ga.run(&mut obj, None, &Stop::default(), &mut []).unwrap();
        assert_eq!(r.evaluations, 21 + 100 * 20);
        assert!(r.best_cost < 1e-2, "{}", r.best_cost);
    }

    #[test]
    fn params_validated() {
        let b = Bounds::<2>::uniform(2, -1.0, 1.0).unwrap();
        let s = Settings {
            population: 5,
            iterations: 5,
            seed: 0,
        };
        let mut p = GaParams::liu2020_igwo();
        p.mutation = 1.1;
        assert!(Ga::<5, 2>::new(s, &b, p).is_err());
        p = GaParams::liu2020_igwo();
        p.crossover = f32::NAN;
        assert!(Ga::<5, 2>::new(s, &b, p).is_err());
    }
}

//! Particle Swarm Optimization with inertia (baseline of `Zhu2025Orchard` and `Liu2020Igwo`).
//!
//! `v = w v + c1 r1 (p - x) + c2 r2 (g - x)`, `x = x + v`, with `r1, r2 ~ U(0, 1)` per
//! dimension, velocities clamped to `vmax = vmax_fraction (ub - lb)` (the usual guard: with
//! `Liu2020Igwo`'s `w = 0.9`, `c1 = c2 = 2` an unclamped swarm diverges), positions clamped to the
//! box. The global best `g` is the best point ever evaluated and is updated at once
//! (asynchronous PSO). The inertia may fall linearly from `w` to `w_end` over the horizon
//! (`w_end = w`, constant, by default as in the papers).
//!
//! Evaluations: `N` at initialisation, then `N` per iteration.

use super::{
    Bounds, Initialisation, Objective, OptimError, Optimizer, Population, Settings, SwarmState,
    check_param, swarm_accessors,
};

/// Options of PSO.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct PsoParams {
    /// Initial population.
    pub init: Initialisation,
    /// Inertia weight at the start, in `[0, 1]`.
    pub w: f32,
    /// Inertia weight at the horizon, in `[0, 1]`.
    pub w_end: f32,
    /// Cognitive coefficient, in `[0, 4]`.
    pub c1: f32,
    /// Social coefficient, in `[0, 4]`.
    pub c2: f32,
    /// Velocity limit as a fraction of each box width, in `(0, 1]`.
    pub vmax_fraction: f32,
}

impl PsoParams {
    /// `Liu2020Igwo`: `w = 0.9`, `c1 = c2 = 2`.
    pub const fn liu2020_igwo() -> Self {
        Self {
            init: Initialisation::Uniform,
            w: 0.9,
            w_end: 0.9,
            c1: 2.0,
            c2: 2.0,
            vmax_fraction: 0.2,
        }
    }

    /// `Zhu2025Orchard`: `w = 0.7`, `c1 = c2 = 2`.
    pub const fn zhu2025_orchard() -> Self {
        Self {
            w: 0.7,
            w_end: 0.7,
            ..Self::liu2020_igwo()
        }
    }

    pub(crate) fn validate(&self) -> Result<(), OptimError> {
        self.init.validate()?;
        check_param(self.w, 0.0, 1.0, "w")?;
        check_param(self.w_end, 0.0, 1.0, "w_end")?;
        check_param(self.c1, 0.0, 4.0, "c1")?;
        check_param(self.c2, 0.0, 4.0, "c2")?;
        check_param(self.vmax_fraction, f32::MIN_POSITIVE, 1.0, "vmax_fraction")
    }
}

impl Default for PsoParams {
    fn default() -> Self {
        Self::liu2020_igwo()
    }
}

/// PSO with capacity `N` particles of `D` dimensions.
#[derive(Debug, Clone)]
pub struct Pso<const N: usize, const D: usize> {
    swarm: SwarmState<N, D>,
    params: PsoParams,
    velocity: [[f32; D]; N],
    personal: Population<N, D>,
}

impl<const N: usize, const D: usize> Pso<N, D> {
    /// Validates and builds; call [`Optimizer::init`] next.
    pub fn new(
        settings: Settings,
        bounds: &Bounds<D>,
        params: PsoParams,
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
            params: PsoParams::liu2020_igwo(),
            velocity: [[0.0; D]; N],
            personal: Population::empty(),
        }
    }

    /// Validates and takes a configuration in place (needs at least 1 members); on
    /// error nothing changes. Call [`Optimizer::init`] next.
    pub fn configure(
        &mut self,
        settings: Settings,
        bounds: &Bounds<D>,
        params: PsoParams,
    ) -> Result<(), OptimError> {
        params.validate()?;
        self.swarm.configure(settings, bounds, 1)?;
        self.params = params;
        self.personal.resize(settings.population, bounds.dim());
        Ok(())
    }
}

impl<const N: usize, const D: usize> Optimizer for Pso<N, D> {
    fn init<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        initial: Option<&[&[f32]]>,
    ) -> Result<(), OptimError> {
        self.swarm
            .initialise(objective, self.params.init, initial)?;
        self.velocity = [[0.0; D]; N];
        self.personal = self.swarm.pop.clone();
        Ok(())
    }

    fn step<O: Objective + ?Sized>(&mut self, objective: &mut O) -> Result<(), OptimError> {
        let t = self.swarm.begin_step()?;
        let p = self.params;
        let horizon = self.swarm.settings.iterations;
        let w = p.w + (p.w_end - p.w) * (t as f32 / horizon as f32);
        let sw = &mut self.swarm;
        let mut x_new = [0.0f32; D];
        for (i, vel) in self.velocity.iter_mut().enumerate().take(sw.pop.size()) {
            let x = sw.pop.position(i);
            let pb = self.personal.position(i);
            let g = sw.tracker.best();
            for (d, ((((v, xn), xd), pd), gd)) in vel
                .iter_mut()
                .zip(x_new.iter_mut())
                .zip(x)
                .zip(pb)
                .zip(g)
                .enumerate()
            {
                let r1 = sw.rng.unit();
                let r2 = sw.rng.unit();
                let width = sw.bounds.upper().get(d).copied().unwrap_or(0.0)
                    - sw.bounds.lower().get(d).copied().unwrap_or(0.0);
                let vmax = p.vmax_fraction * width;
                let nv = w * *v + p.c1 * r1 * (pd - xd) + p.c2 * r2 * (gd - xd);
                *v = nv.max(-vmax).min(vmax);
                *xn = xd + *v;
            }
            let dim = sw.dim();
            let xs = x_new.get_mut(..dim).unwrap_or(&mut []);
            let cost = sw.clamp_and_evaluate(objective, xs);
            sw.pop.replace(i, xs, cost);
            if cost < self.personal.cost(i) {
                self.personal.replace(i, xs, cost);
            }
        }
        Ok(())
    }

    swarm_accessors!();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::Stop;

    #[test]
    fn pso_converges_on_a_bowl_and_counts() {
        let b = Bounds::<4>::uniform(4, -10.0, 10.0).unwrap();
        let s = Settings {
            population: 20,
            iterations: 200,
            seed: 1,
        };
        let mut pso = Pso::<20, 4>::new(s, &b, PsoParams::zhu2025_orchard()).unwrap();
        let mut obj = |x: &[f32]| x.iter().map(|v| (v - 3.0) * (v - 3.0)).sum::<f32>();
        let r = pso.run(&mut obj, None, &Stop::default(), &mut []).unwrap();
        assert_eq!(r.evaluations, 20 * 201);
        assert!(r.best_cost < 1e-3, "{}", r.best_cost);
    }

    #[test]
    fn params_validated() {
        let b = Bounds::<2>::uniform(2, -1.0, 1.0).unwrap();
        let s = Settings {
            population: 5,
            iterations: 5,
            seed: 0,
        };
        let mut p = PsoParams::liu2020_igwo();
        p.c1 = f32::NAN;
        assert!(Pso::<5, 2>::new(s, &b, p).is_err());
        let mut p = PsoParams::liu2020_igwo();
        p.w = 1.5;
        assert!(Pso::<5, 2>::new(s, &b, p).is_err());
    }
}

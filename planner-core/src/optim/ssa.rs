//! Sparrow Search Algorithm (Xue & Shen 2020), as in the widely copied `SSA.m`.
//!
//! Each iteration, with the sparrows ranked by cost at its start:
//! - **producers** (the best `round(PD N)`): if the alarm `R2 < ST`,
//!   `X = X exp(-i / (alpha T))` (`i` the 1-based rank, `alpha ~ U(0, 1]`), else `X = X + Q L`
//!   (`Q ~ N(0, 1)`, `L` a row of ones);
//! - **scroungers** (the others): rank `i > N/2`: `X = Q exp((X_worst - X) / i^2)`; else
//!   `X = X_p + |X - X_p| A+ L`, `X_p` the best position after the producers moved. As in
//!   `SSA.m`, `|X - X_p| A+ L` is one scalar, `sum_j |X_j - X_pj| A_j / D`, broadcast to every
//!   dimension ([`ScroungerRule::Broadcast`]); the per-dimension reading is an option;
//! - **scouts** (`round(SD N)` random sparrows): if `f > f_best`,
//!   `X = X_best + beta |X - X_best|` (`beta ~ N(0, 1)` per dimension), else
//!   `X = X + K |X - X_worst| / (f - f_worst + eps)`, `K ~ U(-1, 1)`.
//!
//! Every move is clamped, evaluated and kept only if it improves the sparrow (`SSA.m` keeps a
//! personal best per sparrow, which is this population; keeping it per move instead of per
//! iteration needs no second `N x D` buffer).
//!
//! Evaluations: `N` at initialisation, then `N + round(SD N)` per iteration.

use super::{
    Bounds, Initialisation, Objective, OptimError, Optimizer, Population, Settings, SwarmState,
    Tracker, check_param, copy, swarm_accessors,
};

/// How the better scroungers' term `|X - X_p| A+ L` is read.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum ScroungerRule {
    /// One scalar `sum_j |X_j - X_pj| A_j / D` added to every dimension (`SSA.m`, default).
    Broadcast,
    /// Per dimension: `X_pj + A_j |X_j - X_pj|`.
    PerDimension,
}

/// Options of the sparrow search.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct SsaParams {
    /// Initial population.
    pub init: Initialisation,
    /// Safety threshold `ST` in `[0, 1]`.
    pub safety_threshold: f32,
    /// Producer fraction `PD` in `[0, 1]` (at least one producer).
    pub producers: f32,
    /// Scout fraction `SD` in `[0, 1]`.
    pub scouts: f32,
    /// The better scroungers' rule.
    pub scrounger_rule: ScroungerRule,
}

impl SsaParams {
    /// `SSA.m` defaults: `ST = 0.8`, `PD = 0.2`, `SD = 0.2`.
    pub const fn ssa() -> Self {
        Self {
            init: Initialisation::Uniform,
            safety_threshold: 0.8,
            producers: 0.2,
            scouts: 0.2,
            scrounger_rule: ScroungerRule::Broadcast,
        }
    }

    /// `Zhu2025Orchard`'s settings: `ST = 0.6`, `PD = 0.4`, `SD = 0.2`.
    pub const fn zhu2025_orchard() -> Self {
        Self {
            safety_threshold: 0.6,
            producers: 0.4,
            ..Self::ssa()
        }
    }

    pub(crate) fn validate(&self) -> Result<(), OptimError> {
        self.init.validate()?;
        check_param(self.safety_threshold, 0.0, 1.0, "ST")?;
        check_param(self.producers, 0.0, 1.0, "PD")?;
        check_param(self.scouts, 0.0, 1.0, "SD")
    }
}

fn count(fraction: f32, n: usize) -> usize {
    // round half away from zero, as Matlab's round
    ((fraction * n as f32) + 0.5) as usize
}

/// One sparrow-search iteration on the swarm's population (the shared state of SSA and
/// SSA-GWO).
///
/// The swarm's horizon is `T` in the producers' `exp(-i / (alpha T))`.
pub(crate) fn sparrow_step<const N: usize, const D: usize, O: Objective + ?Sized>(
    swarm: &mut SwarmState<N, D>,
    objective: &mut O,
    params: &SsaParams,
) {
    let SwarmState {
        settings,
        bounds,
        rng,
        pop,
        tracker,
        ..
    } = swarm;
    let (bounds, horizon) = (&*bounds, settings.iterations);
    let n = pop.size();
    let dim = pop.dim();
    if n == 0 {
        return;
    }
    let mut order = [0usize; N];
    pop.sort_indices(&mut order);
    let worst_index = order.get(n - 1).copied().unwrap_or(0);
    let mut worst = [0.0f32; D];
    copy(&mut worst, pop.position(worst_index));
    let worst_cost = pop.cost(worst_index);
    let mut cand = [0.0f32; D];
    let producers = count(params.producers, n).max(1).min(n);

    let alarm = rng.unit();
    for (rank, &i) in order.iter().enumerate().take(producers) {
        if alarm < params.safety_threshold {
            // alpha in (0, 1]: 1 - unit() is never 0.
            let alpha = 1.0 - rng.unit();
            let f = libm::expf(-((rank + 1) as f32) / (alpha * horizon as f32));
            for (c, x) in cand.iter_mut().zip(pop.position(i)) {
                *c = x * f;
            }
        } else {
            let q = rng.normal();
            for (c, x) in cand.iter_mut().zip(pop.position(i)) {
                *c = x + q;
            }
        }
        try_move(pop, bounds, tracker, objective, i, &mut cand, dim);
    }

    let mut leader = [0.0f32; D];
    copy(&mut leader, pop.position(pop.best_index()));
    for (rank, &i) in order.iter().enumerate().take(n).skip(producers) {
        if rank + 1 > n / 2 {
            let q = rng.normal();
            let div = ((rank + 1) * (rank + 1)) as f32;
            for ((c, x), w) in cand.iter_mut().zip(pop.position(i)).zip(&worst) {
                *c = q * libm::expf((w - x) / div);
            }
        } else {
            match params.scrounger_rule {
                ScroungerRule::Broadcast => {
                    let mut s = 0.0;
                    for (x, p) in pop.position(i).iter().zip(&leader) {
                        let sign = if rng.next_u32() & 1 == 0 { -1.0 } else { 1.0 };
                        s += libm::fabsf(x - p) * sign;
                    }
                    let s = s / dim as f32;
                    for (c, p) in cand.iter_mut().zip(&leader) {
                        *c = p + s;
                    }
                }
                ScroungerRule::PerDimension => {
                    for ((c, x), p) in cand.iter_mut().zip(pop.position(i)).zip(&leader) {
                        let sign = if rng.next_u32() & 1 == 0 { -1.0 } else { 1.0 };
                        *c = p + sign * libm::fabsf(x - p);
                    }
                }
            }
        }
        try_move(pop, bounds, tracker, objective, i, &mut cand, dim);
    }

    // Scouts: a partial Fisher-Yates shuffle picks distinct sparrows.
    let scouts = count(params.scouts, n).min(n);
    let mut pick = [0usize; N];
    for (k, p) in pick.iter_mut().enumerate() {
        *p = k;
    }
    for k in 0..scouts {
        let j = k + rng.index(n - k);
        pick.swap(k, j.min(n - 1));
        let i = pick.get(k).copied().unwrap_or(0);
        let cost = pop.cost(i);
        if cost > tracker.best_cost {
            let best = tracker.best();
            for ((c, x), b) in cand.iter_mut().zip(pop.position(i)).zip(best) {
                *c = b + rng.normal() * libm::fabsf(x - b);
            }
        } else {
            let k_step = 2.0 * rng.unit() - 1.0;
            // f32 has no room for SSA.m's 1e-50.
            let denom = (cost - worst_cost) + 1e-30;
            for ((c, x), w) in cand.iter_mut().zip(pop.position(i)).zip(&worst) {
                *c = x + k_step * libm::fabsf(x - w) / denom;
            }
        }
        try_move(pop, bounds, tracker, objective, i, &mut cand, dim);
    }
}

/// Clamps and evaluates `cand`, and keeps it as member `i` if it is better.
fn try_move<const N: usize, const D: usize, O: Objective + ?Sized>(
    pop: &mut Population<N, D>,
    bounds: &Bounds<D>,
    tracker: &mut Tracker<D>,
    objective: &mut O,
    i: usize,
    cand: &mut [f32; D],
    dim: usize,
) {
    let c = cand.get_mut(..dim).unwrap_or(&mut []);
    bounds.clamp(c);
    let cost = tracker.evaluate(objective, c);
    if cost < pop.cost(i) {
        pop.replace(i, c, cost);
    }
}

/// Sparrow search with capacity `N` sparrows of `D` dimensions.
#[derive(Debug, Clone)]
pub struct Ssa<const N: usize, const D: usize> {
    swarm: SwarmState<N, D>,
    params: SsaParams,
}

impl<const N: usize, const D: usize> Ssa<N, D> {
    /// Validates and builds; call [`Optimizer::init`] next. Needs at least 2 sparrows.
    pub fn new(
        settings: Settings,
        bounds: &Bounds<D>,
        params: SsaParams,
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
            params: SsaParams::ssa(),
        }
    }

    /// Validates and takes a configuration in place (needs at least 2 members); on
    /// error nothing changes. Call [`Optimizer::init`] next.
    pub fn configure(
        &mut self,
        settings: Settings,
        bounds: &Bounds<D>,
        params: SsaParams,
    ) -> Result<(), OptimError> {
        params.validate()?;
        self.swarm.configure(settings, bounds, 2)?;
        self.params = params;
        Ok(())
    }
}

impl<const N: usize, const D: usize> Optimizer for Ssa<N, D> {
    fn init<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        initial: Option<&[&[f32]]>,
    ) -> Result<(), OptimError> {
        self.swarm.initialise(objective, self.params.init, initial)
    }

    fn step<O: Objective + ?Sized>(&mut self, objective: &mut O) -> Result<(), OptimError> {
        self.swarm.begin_step()?;
        sparrow_step(&mut self.swarm, objective, &self.params);
        Ok(())
    }

    swarm_accessors!();
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optim::Stop;

    #[test]
    fn counts_and_determinism() {
        let b = Bounds::<5>::uniform(5, -10.0, 10.0).unwrap();
        let s = Settings {
            population: 20,
            iterations: 30,
            seed: 2,
        };
        let mut a = Ssa::<20, 5>::new(s, &b, SsaParams::ssa()).unwrap();
        let mut obj = |x: &[f32]| x.iter().map(|v| (v - 3.0) * (v - 3.0)).sum::<f32>();
        let r1 = a.run(&mut obj, None, &Stop::default(), &mut []).unwrap();
        // N at init, then N + round(0.2 N) = 24 per iteration.
        assert_eq!(r1.evaluations, 20 + 30 * 24);
        let r2 = a.run(&mut obj, None, &Stop::default(), &mut []).unwrap();
        assert_eq!(r1, r2);
        assert!(r1.best_cost < 1.0);
    }

    #[test]
    fn params_validated() {
        let b = Bounds::<2>::uniform(2, -1.0, 1.0).unwrap();
        let s = Settings {
            population: 5,
            iterations: 5,
            seed: 0,
        };
        for f in [
            |p: &mut SsaParams| p.safety_threshold = f32::NAN,
            |p: &mut SsaParams| p.producers = 1.5,
            |p: &mut SsaParams| p.scouts = -0.1,
        ] {
            let mut p = SsaParams::ssa();
            f(&mut p);
            assert!(matches!(
                Ssa::<5, 2>::new(s, &b, p),
                Err(OptimError::InvalidParameter(_))
            ));
        }
    }
}

//! Grey Wolf Optimizer (Mirjalili 2014), TGWO (`Lei2024Warehouse`) and IGWO (`Liu2020Igwo`), one
//! implementation.
//!
//! Per iteration, as in `GWO.m`: every wolf moves towards the three leaders with
//! `X = (X1 + X2 + X3) / 3`, `Xk = X_leader - A |C X_leader - X|`, `A = 2 a r1 - a`,
//! `C = 2 r2`, fresh `r1, r2` per leader and dimension, no greedy selection; then all wolves are
//! clamped and evaluated and the leaders updated. The leaders are an all-time archive that
//! cascades (a new alpha demotes alpha to beta and beta to delta); `GWO.m`'s
//! non-cascading update is [`LeaderUpdate::Original`]. The absolute bars of `Liu2020Igwo` eq. 7 are
//! typesetting: the canonical update is used.
//!
//! Evaluations: `N` at initialisation, then `N` per iteration.

use super::schedule::{ConvergenceFactor, Schedule};
use super::{
    Bounds, Initialisation, Objective, OptimError, Optimizer, Population, Settings, SwarmState,
    copy, swarm_accessors,
};

/// How the leader archive absorbs a newly evaluated wolf.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub enum LeaderUpdate {
    /// A new alpha demotes alpha to beta and beta to delta; a new beta demotes beta (default).
    Cascade,
    /// `GWO.m` as published: each slot is overwritten without demotion (a known bug: the old
    /// alpha is lost instead of becoming beta).
    Original,
}

/// Options of the GWO family.
#[derive(Debug, Clone, Copy, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct GwoParams {
    /// Initial population.
    pub init: Initialisation,
    /// The convergence factor `a(t)`.
    pub factor: ConvergenceFactor,
    /// Leader archive update.
    pub leaders: LeaderUpdate,
    /// Keep a wolf's move only if it improves the wolf (mealpy's `OriginalGWO` does this;
    /// `GWO.m` and SPEC do not: off by default).
    pub greedy: bool,
    /// Literal `Liu2020Igwo` eq. 7, `X_k = |X_leader - A D|` (the bars are typesetting: off by
    /// default, canonical GWO).
    pub literal_abs: bool,
}

impl GwoParams {
    /// GWO: uniform init, `a = 2 - 2t/T`, cascading leaders.
    pub const fn gwo() -> Self {
        Self {
            init: Initialisation::Uniform,
            factor: ConvergenceFactor::Linear,
            leaders: LeaderUpdate::Cascade,
            greedy: false,
            literal_abs: false,
        }
    }

    /// TGWO: GWO with the Tent initialisation (`Lei2024Warehouse`'s comparison).
    pub const fn tgwo() -> Self {
        Self {
            init: Initialisation::TENT,
            ..Self::gwo()
        }
    }

    /// IGWO: `a = 2 exp(-2 t/T)` (`Liu2020Igwo` eq. 9 as SPEC resolves it).
    pub const fn igwo() -> Self {
        Self {
            factor: ConvergenceFactor::IGWO,
            ..Self::gwo()
        }
    }

    fn validate(&self) -> Result<(), OptimError> {
        self.init.validate()?;
        self.factor.validate()
    }
}

/// One leader: a position and its cost.
#[derive(Debug, Clone, Copy)]
pub struct Wolf<const D: usize> {
    /// Position (first `dim` entries used).
    pub position: [f32; D],
    /// Cost (`+inf` while unset).
    pub cost: f32,
}

impl<const D: usize> Wolf<D> {
    const EMPTY: Self = Self {
        position: [0.0; D],
        cost: f32::INFINITY,
    };

    /// All zero bytes (see [`Gwo::unconfigured`]); [`Optimizer::init`] resets the leaders.
    const UNSET: Self = Self {
        position: [0.0; D],
        cost: 0.0,
    };

    fn set(&mut self, x: &[f32], cost: f32) {
        copy(&mut self.position, x);
        self.cost = cost;
    }
}

/// The alpha, beta and delta wolves.
#[derive(Debug, Clone, Copy)]
pub struct Leaders<const D: usize> {
    /// Best.
    pub alpha: Wolf<D>,
    /// Second.
    pub beta: Wolf<D>,
    /// Third.
    pub delta: Wolf<D>,
}

impl<const D: usize> Leaders<D> {
    /// No leaders yet.
    pub const fn new() -> Self {
        Self {
            alpha: Wolf::EMPTY,
            beta: Wolf::EMPTY,
            delta: Wolf::EMPTY,
        }
    }

    /// The highest cost among the three: a wolf at or above it changes no leader under
    /// either [`LeaderUpdate`] rule.
    pub fn worst_cost(&self) -> f32 {
        let ab = if self.beta.cost > self.alpha.cost {
            self.beta.cost
        } else {
            self.alpha.cost
        };
        if self.delta.cost > ab {
            self.delta.cost
        } else {
            ab
        }
    }

    /// Takes a newly evaluated wolf into the archive.
    pub fn offer(&mut self, x: &[f32], cost: f32, rule: LeaderUpdate) {
        match rule {
            LeaderUpdate::Cascade => {
                if cost < self.alpha.cost {
                    self.delta = self.beta;
                    self.beta = self.alpha;
                    self.alpha.set(x, cost);
                } else if cost < self.beta.cost {
                    self.delta = self.beta;
                    self.beta.set(x, cost);
                } else if cost < self.delta.cost {
                    self.delta.set(x, cost);
                }
            }
            LeaderUpdate::Original => {
                // GWO.m, line for line.
                if cost < self.alpha.cost {
                    self.alpha.set(x, cost);
                }
                if cost > self.alpha.cost && cost < self.beta.cost {
                    self.beta.set(x, cost);
                }
                if cost > self.alpha.cost && cost > self.beta.cost && cost < self.delta.cost {
                    self.delta.set(x, cost);
                }
            }
        }
    }

    /// The three leaders, recomputed from scratch as the best three members of `pop`
    /// (SSA-GWO recomputes them after both phases).
    pub fn from_population<const N: usize>(pop: &Population<N, D>) -> Self {
        let mut l = Self::new();
        if pop.size() > 0 {
            // Start every slot at a real member so that a population of infinite costs still
            // has leaders inside the box.
            let x = pop.position(0);
            l.alpha.set(x, f32::INFINITY);
            l.beta.set(x, f32::INFINITY);
            l.delta.set(x, f32::INFINITY);
        }
        for i in 0..pop.size() {
            l.offer(pop.position(i), pop.cost(i), LeaderUpdate::Cascade);
        }
        l
    }
}

impl<const D: usize> Default for Leaders<D> {
    fn default() -> Self {
        Self::new()
    }
}

/// Writes wolf `x`'s move towards the leaders with factor `a` into `out` (no evaluation),
/// drawing `r1, r2` per dimension and leader.
pub(crate) fn hunt<const D: usize>(
    x: &[f32],
    leaders: &Leaders<D>,
    a: f32,
    rng: &mut super::random::Random,
    out: &mut [f32],
    literal_abs: bool,
) {
    // The same draws from a local copy of the generator, which can stay in registers
    // (through `rng` its state was loaded and stored for every draw: a fifth of an IGWO plan
    // on a Cortex-M4).
    let mut r = rng.clone();
    let leaders = [&leaders.alpha, &leaders.beta, &leaders.delta];
    for (d, (o, xd)) in out.iter_mut().zip(x).enumerate() {
        let mut sum = 0.0;
        for leader in leaders {
            let lp = leader.position.get(d).copied().unwrap_or(0.0);
            let r1 = r.unit();
            let r2 = r.unit();
            let big_a = 2.0 * a * r1 - a;
            let c = 2.0 * r2;
            let xk = lp - big_a * libm::fabsf(c * lp - xd);
            sum += if literal_abs { libm::fabsf(xk) } else { xk };
        }
        *o = sum / 3.0;
    }
    *rng = r;
}

/// GWO / TGWO / IGWO with capacity `N` wolves of `D` dimensions.
#[derive(Debug, Clone)]
pub struct Gwo<const N: usize, const D: usize> {
    swarm: SwarmState<N, D>,
    params: GwoParams,
    leaders: Leaders<D>,
}

impl<const N: usize, const D: usize> Gwo<N, D> {
    /// Validates and builds; call [`Optimizer::init`] next. Needs at least 3 wolves.
    pub fn new(
        settings: Settings,
        bounds: &Bounds<D>,
        params: GwoParams,
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
            params: GwoParams::gwo(),
            leaders: Leaders {
                alpha: Wolf::UNSET,
                beta: Wolf::UNSET,
                delta: Wolf::UNSET,
            },
        }
    }

    /// Validates and takes a configuration in place (needs at least 3 members); on
    /// error nothing changes. Call [`Optimizer::init`] next.
    pub fn configure(
        &mut self,
        settings: Settings,
        bounds: &Bounds<D>,
        params: GwoParams,
    ) -> Result<(), OptimError> {
        params.validate()?;
        self.swarm.configure(settings, bounds, 3)?;
        self.params = params;
        Ok(())
    }

    /// The current leaders.
    pub fn leaders(&self) -> &Leaders<D> {
        &self.leaders
    }

    fn absorb_population(&mut self) {
        for i in 0..self.swarm.n() {
            self.leaders.offer(
                self.swarm.pop.position(i),
                self.swarm.pop.cost(i),
                self.params.leaders,
            );
        }
    }
}

impl<const N: usize, const D: usize> Optimizer for Gwo<N, D> {
    fn init<O: Objective + ?Sized>(
        &mut self,
        objective: &mut O,
        initial: Option<&[&[f32]]>,
    ) -> Result<(), OptimError> {
        self.swarm
            .initialise(objective, self.params.init, initial)?;
        self.leaders = Leaders::from_population(&self.swarm.pop);
        if self.params.leaders == LeaderUpdate::Original {
            self.leaders = Leaders::new();
            self.absorb_population();
        }
        Ok(())
    }

    fn step<O: Objective + ?Sized>(&mut self, objective: &mut O) -> Result<(), OptimError> {
        let t = self.swarm.begin_step()?;
        let a = self.params.factor.value(t, self.swarm.settings.iterations);
        let mut row = [0.0f32; D];
        if self.params.greedy {
            // Leaders stay fixed during the pass, as in the plain variant.
            let leaders = self.leaders;
            let dim = self.swarm.dim();
            for i in 0..self.swarm.n() {
                let sw = &mut self.swarm;
                hunt(
                    sw.pop.position(i),
                    &leaders,
                    a,
                    &mut sw.rng,
                    &mut row,
                    self.params.literal_abs,
                );
                let cand = row.get_mut(..dim).unwrap_or(&mut []);
                // Only a cost below the wolf's own or a leader's is used.
                let worst = self.leaders.worst_cost();
                let own = sw.pop.cost(i);
                let bound = if own > worst { own } else { worst };
                let cost = sw.clamp_and_evaluate_below(objective, cand, bound);
                if cost < sw.pop.cost(i) {
                    sw.pop.replace(i, cand, cost);
                }
                self.leaders.offer(cand, cost, self.params.leaders);
            }
            return Ok(());
        }
        for i in 0..self.swarm.n() {
            let sw = &mut self.swarm;
            hunt(
                sw.pop.position(i),
                &self.leaders,
                a,
                &mut sw.rng,
                &mut row,
                self.params.literal_abs,
            );
            copy(sw.pop.position_mut(i), &row);
        }
        for i in 0..self.swarm.n() {
            let sw = &mut self.swarm;
            sw.bounds.clamp(sw.pop.position_mut(i));
            // Without greedy selection a wolf's cost only feeds the leaders, so a cost at or
            // above the worst leader's need not be exact (the stored value is then a lower
            // bound, which nothing reads).
            let bound = self.leaders.worst_cost();
            let cost = sw
                .tracker
                .evaluate_below(objective, sw.pop.position(i), bound);
            sw.pop.set_cost(i, cost);
            self.leaders
                .offer(sw.pop.position(i), cost, self.params.leaders);
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
    fn gwo_leaders_cascade() {
        let mut l = Leaders::<1>::new();
        for (x, c) in [(1.0, 5.0), (2.0, 4.0), (3.0, 3.0)] {
            l.offer(&[x], c, LeaderUpdate::Cascade);
        }
        // Each new alpha pushed the old ones down.
        assert_eq!(
            (l.alpha.position[0], l.beta.position[0], l.delta.position[0]),
            (3.0, 2.0, 1.0)
        );
        assert_eq!((l.alpha.cost, l.beta.cost, l.delta.cost), (3.0, 4.0, 5.0));
        // A new beta demotes beta to delta.
        l.offer(&[9.0], 3.5, LeaderUpdate::Cascade);
        assert_eq!(
            (l.alpha.position[0], l.beta.position[0], l.delta.position[0]),
            (3.0, 9.0, 2.0)
        );
        // A worse wolf only enters as delta if it beats delta.
        l.offer(&[7.0], 3.9, LeaderUpdate::Cascade);
        assert_eq!(l.delta.position[0], 7.0);
        l.offer(&[8.0], 10.0, LeaderUpdate::Cascade);
        assert_eq!(l.delta.position[0], 7.0);
    }

    #[test]
    fn original_gwo_m_loses_the_old_alpha() {
        let mut l = Leaders::<1>::new();
        for (x, c) in [(1.0, 5.0), (2.0, 4.0), (3.0, 3.0)] {
            l.offer(&[x], c, LeaderUpdate::Original);
        }
        // GWO.m: every improvement only overwrote alpha; beta and delta stay empty.
        assert_eq!(l.alpha.position[0], 3.0);
        assert_eq!(l.beta.cost, f32::INFINITY);
        assert_eq!(l.delta.cost, f32::INFINITY);
    }

    #[test]
    fn leaders_from_population_are_the_best_three() {
        let mut p = Population::<5, 1>::new(5, 1);
        for (i, c) in [4.0, 1.0, 3.0, 0.5, 2.0].iter().enumerate() {
            p.replace(i, &[i as f32], *c);
        }
        let l = Leaders::from_population(&p);
        assert_eq!(
            (l.alpha.position[0], l.beta.position[0], l.delta.position[0]),
            (3.0, 1.0, 4.0)
        );
    }

    #[test]
    fn alpha_is_the_best_so_far() {
        let b = Bounds::<6>::uniform(6, -10.0, 10.0).unwrap();
        for params in [GwoParams::gwo(), GwoParams::tgwo(), GwoParams::igwo()] {
            let s = Settings {
                population: 12,
                iterations: 50,
                seed: 4,
            };
            let mut g = Gwo::<12, 6>::new(s, &b, params).unwrap();
            let mut obj = |x: &[f32]| x.iter().map(|v| (v - 2.0) * (v - 2.0)).sum::<f32>();
            let r = g.run(&mut obj, None, &Stop::default(), &mut []).unwrap();
            assert_eq!(g.leaders().alpha.cost, r.best_cost);
            assert!(g.leaders().alpha.cost <= g.leaders().beta.cost);
            assert!(g.leaders().beta.cost <= g.leaders().delta.cost);
            assert_eq!(r.evaluations, 12 * 51);
        }
    }

    #[test]
    fn literal_absolute_bars_keep_wolves_non_negative() {
        // `Liu2020Igwo` eq. 7 read literally takes |.| of each leader term, so after the first
        // move no wolf has a negative coordinate: an optimum at -5 is out of reach.
        let b = Bounds::<3>::uniform(3, -10.0, 10.0).unwrap();
        let s = Settings {
            population: 10,
            iterations: 30,
            seed: 1,
        };
        let p = GwoParams {
            literal_abs: true,
            ..GwoParams::igwo()
        };
        let mut g = Gwo::<10, 3>::new(s, &b, p).unwrap();
        let mut obj = |x: &[f32]| x.iter().map(|v| (v + 5.0) * (v + 5.0)).sum::<f32>();
        g.init(&mut obj, None).unwrap();
        g.step(&mut obj).unwrap();
        for i in 0..10 {
            assert!(g.swarm.pop.position(i).iter().all(|v| *v >= 0.0));
        }
        let mut canonical = Gwo::<10, 3>::new(s, &b, GwoParams::igwo()).unwrap();
        let r = canonical
            .run(&mut obj, None, &Stop::default(), &mut [])
            .unwrap();
        assert!(r.best_cost < 1.0);
    }

    #[test]
    fn greedy_variant_never_loses_a_wolf() {
        let b = Bounds::<6>::uniform(6, -100.0, 100.0).unwrap();
        let s = Settings {
            population: 12,
            iterations: 100,
            seed: 4,
        };
        let mut obj = |x: &[f32]| x.iter().map(|v| (v - 37.5) * (v - 37.5)).sum::<f32>();
        let mut g = Gwo::<12, 6>::new(
            s,
            &b,
            GwoParams {
                greedy: true,
                ..GwoParams::gwo()
            },
        )
        .unwrap();
        let mut hist = [0.0f32; 100];
        let r = g.run(&mut obj, None, &Stop::default(), &mut hist).unwrap();
        assert_eq!(r.evaluations, 12 * 101);
        assert_eq!(g.leaders().alpha.cost, r.best_cost);
    }
}

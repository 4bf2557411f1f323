//! Algorithm codes (`u8`) of a [`PlanRequest`](super::PlanRequest) and guide codes (`u8`)
//! of its [`PlanParams`](super::PlanParams).

use super::ServiceError;
use planner_core::optim::any::AlgorithmKind;
use planner_core::planner::{GuideKind, PlannerKind};
use serde::{Deserialize, Serialize};

/// The planners the service knows: every planner of planner-core. Wire code =
/// discriminant; `0` is never a planner. Adding a planner is one variant here, one line in
/// [`Algorithm::ALL`] and one arm in [`Algorithm::kind`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
pub enum Algorithm {
    /// A*: shortest 8-connected path.
    AStar = 1,
    /// Theta*: any-angle path.
    ThetaStar = 2,
    /// The ant colony of the TCLHHO warehouse paper.
    Aco = 3,
    /// TCLHHO.
    Tclhho = 4,
    /// IGWO.
    Igwo = 5,
    /// HHO.
    Hho = 6,
    /// GWO.
    Gwo = 7,
    /// TGWO.
    Tgwo = 8,
    /// PSO.
    Pso = 9,
    /// GA.
    Ga = 10,
    /// Sparrow search.
    Ssa = 11,
    /// SSA-GWO.
    SsaGwo = 12,
    /// The exact any-angle shortest path.
    AnyAngle = 13,
}

impl Algorithm {
    /// Every served planner.
    pub const ALL: [Algorithm; 13] = [
        Algorithm::AStar,
        Algorithm::ThetaStar,
        Algorithm::Aco,
        Algorithm::Tclhho,
        Algorithm::Igwo,
        Algorithm::Hho,
        Algorithm::Gwo,
        Algorithm::Tgwo,
        Algorithm::Pso,
        Algorithm::Ga,
        Algorithm::Ssa,
        Algorithm::SsaGwo,
        Algorithm::AnyAngle,
    ];

    /// The wire code.
    pub const fn code(self) -> u8 {
        self as u8
    }

    /// The planner of a wire code, or [`ServiceError::UnknownAlgorithm`].
    pub fn from_code(code: u8) -> Result<Self, ServiceError> {
        Self::ALL
            .into_iter()
            .find(|a| a.code() == code)
            .ok_or(ServiceError::UnknownAlgorithm)
    }

    /// planner-core's planner.
    pub const fn kind(self) -> PlannerKind {
        match self {
            Algorithm::AStar => PlannerKind::AStar,
            Algorithm::ThetaStar => PlannerKind::Theta,
            Algorithm::Aco => PlannerKind::Aco,
            Algorithm::Tclhho => PlannerKind::Swarm(AlgorithmKind::Tclhho),
            Algorithm::Igwo => PlannerKind::Swarm(AlgorithmKind::Igwo),
            Algorithm::Hho => PlannerKind::Swarm(AlgorithmKind::Hho),
            Algorithm::Gwo => PlannerKind::Swarm(AlgorithmKind::Gwo),
            Algorithm::Tgwo => PlannerKind::Swarm(AlgorithmKind::Tgwo),
            Algorithm::Pso => PlannerKind::Swarm(AlgorithmKind::Pso),
            Algorithm::Ga => PlannerKind::Swarm(AlgorithmKind::Ga),
            Algorithm::Ssa => PlannerKind::Swarm(AlgorithmKind::Ssa),
            Algorithm::SsaGwo => PlannerKind::Swarm(AlgorithmKind::SsaGwo),
            Algorithm::AnyAngle => PlannerKind::AnyAngle,
        }
    }

    /// The name used on command lines and in JSON lines (same as `host-sim plan --algo`).
    pub fn name(self) -> &'static str {
        self.kind().name()
    }

    /// The planner of a name, or [`ServiceError::UnknownAlgorithm`].
    pub fn from_name(name: &str) -> Result<Self, ServiceError> {
        Self::ALL
            .into_iter()
            .find(|a| a.name() == name)
            .ok_or(ServiceError::UnknownAlgorithm)
    }
}

/// The route a swarm planner's corridor encoding starts from ([`GuideKind`]): wire code
/// `0` the exact any-angle path (the default), `1` the octile A* route.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[repr(u8)]
pub enum Guide {
    /// The exact shortest any-angle path.
    #[default]
    AnyAngle = 0,
    /// The octile A* route.
    AStar = 1,
}

impl Guide {
    /// Every guide, in code order.
    pub const ALL: [Guide; 2] = [Guide::AnyAngle, Guide::AStar];

    /// The wire code.
    pub const fn code(self) -> u8 {
        self as u8
    }

    /// The guide of a wire code (`None` for an unknown code).
    pub fn from_code(code: u8) -> Option<Self> {
        Self::ALL.into_iter().find(|g| g.code() == code)
    }

    /// planner-core's guide.
    pub const fn kind(self) -> GuideKind {
        match self {
            Guide::AnyAngle => GuideKind::AnyAngle,
            Guide::AStar => GuideKind::AStar,
        }
    }

    /// The wire guide of planner-core's guide.
    pub const fn of(kind: GuideKind) -> Self {
        match kind {
            GuideKind::AnyAngle => Guide::AnyAngle,
            GuideKind::AStar => Guide::AStar,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn algorithm_codes_and_names() {
        for a in Algorithm::ALL {
            assert_eq!(Algorithm::from_code(a.code()), Ok(a));
            assert_eq!(Algorithm::from_name(a.name()), Ok(a));
        }
        for bad in [0u8, 14, 99, 255] {
            assert_eq!(
                Algorithm::from_code(bad),
                Err(ServiceError::UnknownAlgorithm)
            );
        }
        // Every planner of planner-core is served, under the same names as `host-sim plan`.
        assert_eq!(Algorithm::ALL.len(), PlannerKind::ALL.len());
        for kind in PlannerKind::ALL {
            assert_eq!(
                Algorithm::from_name(kind.name()).map(Algorithm::kind),
                Ok(kind)
            );
        }
        assert_eq!(
            Algorithm::from_name("dijkstra"),
            Err(ServiceError::UnknownAlgorithm)
        );
    }

    /// The codes as `docs/wire.md` and the C header list them.
    #[test]
    fn codes_are_pinned() {
        let codes: Vec<(u8, &str)> = Algorithm::ALL
            .iter()
            .map(|a| (a.code(), a.name()))
            .collect();
        assert_eq!(
            codes,
            [
                (1, "astar"),
                (2, "theta"),
                (3, "aco"),
                (4, "tclhho"),
                (5, "igwo"),
                (6, "hho"),
                (7, "gwo"),
                (8, "tgwo"),
                (9, "pso"),
                (10, "ga"),
                (11, "ssa"),
                (12, "ssagwo"),
                (13, "anyangle"),
            ]
        );
        for g in Guide::ALL {
            assert_eq!(Guide::from_code(g.code()), Some(g));
            assert_eq!(Guide::of(g.kind()), g);
        }
        assert_eq!((Guide::AnyAngle.code(), Guide::AStar.code()), (0, 1));
        assert_eq!(Guide::from_code(2), None);
        assert_eq!(Guide::default().kind(), GuideKind::default());
    }
}

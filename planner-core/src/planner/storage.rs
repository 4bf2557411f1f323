//! [`PlanStorage`]: everything a corridor plan on the any-angle guide needs, in one value
//! sized by const generics (heapless style), so that firmware keeps it in a zeroed `static`.

use super::optimizers::HhoOrGwo;
use super::{AnyAngleWorkspace, PlanOptions, PlanParams, PlanReport, PlanStorageMut, plan};
use crate::encoding::corridor::Station;
use crate::error::PlanError;
use crate::geometry::Cell;
use crate::grid::GridRef;
use crate::path::{Path, PathView};
use crate::search::anyangle::{self, AnyAngleStats, Mesh, MeshStorage, QueryStorage};

/// The storage of a plan with the any-angle guide and the corridor encoding (the firmware
/// planners TCLHHO, HHO, IGWO, GWO, TGWO):
///
/// - `RECTS`, `LINKS`: the map's any-angle mesh (24 and 8 bytes each; built by
///   [`prepare`](Self::prepare), once per map);
/// - `OPEN`: the any-angle search's open list (40 bytes a node);
/// - `POP`, `DIM`: the optimizer's population and dimension ([`HhoOrGwo`]), and `DIM`
///   corridor stations;
/// - `PATH`: waypoints of the guide route and of the planned path.
///
/// ```
/// use planner_core::{geometry::Cell, grid::{words_for, Grid}};
/// use planner_core::planner::{AlgorithmKind, PlanOptions, PlanParams, PlanStorage};
///
/// // Zero bytes: a `static` of it is in `.bss`.
/// static mut STORAGE: PlanStorage<30, 16, 128, 16, 32, 64> = PlanStorage::new();
///
/// let grid: Grid<{ words_for(12, 6) }> = Grid::parse_rows(
///     b"............\n....@@@@....\n....@@@@....\n............\n..@@@@@@@@..\n............\n")?;
/// let storage = unsafe { &mut *core::ptr::addr_of_mut!(STORAGE) };
/// storage.prepare(grid.view())?;
/// let params = PlanParams { iterations: 60, ..PlanParams::new(AlgorithmKind::Tclhho) };
/// let report = storage.plan(grid.view(), Cell::new(0, 2), Cell::new(11, 3), &params, PlanOptions::default())?;
/// assert_eq!(storage.path().len(), report.turns + 2);
/// # Ok::<(), Box<dyn std::error::Error>>(())
/// ```
pub struct PlanStorage<
    const POP: usize,
    const DIM: usize,
    const PATH: usize,
    const RECTS: usize,
    const LINKS: usize,
    const OPEN: usize,
> {
    mesh: MeshStorage<RECTS, LINKS>,
    query: QueryStorage<RECTS, OPEN>,
    guide: Path<PATH>,
    stations: [Station; DIM],
    optimizer: HhoOrGwo<POP, DIM>,
    out: Path<PATH>,
    /// A fingerprint of the grid the mesh was built from (0: none yet).
    prepared: u64,
}

impl<
    const POP: usize,
    const DIM: usize,
    const PATH: usize,
    const RECTS: usize,
    const LINKS: usize,
    const OPEN: usize,
> PlanStorage<POP, DIM, PATH, RECTS, LINKS, OPEN>
{
    /// Empty storage, all zero bytes.
    pub const fn new() -> Self {
        PlanStorage {
            mesh: MeshStorage::new(),
            query: QueryStorage::new(),
            guide: Path::new(),
            stations: [Station::EMPTY; DIM],
            optimizer: HhoOrGwo::unconfigured(),
            out: Path::new(),
            prepared: 0,
        }
    }

    /// Builds `grid`'s any-angle mesh: once per map, before [`plan`](Self::plan).
    /// [`PlanError::CapacityExceeded`] when the map needs more than `RECTS` rectangles or
    /// `LINKS` links.
    pub fn prepare(&mut self, grid: GridRef<'_>) -> Result<(), PlanError> {
        self.prepared = 0;
        self.mesh.build(grid)?;
        self.prepared = fingerprint(grid);
        Ok(())
    }

    /// The mesh of the prepared map (empty before [`prepare`](Self::prepare)).
    pub fn mesh(&self) -> Mesh<'_> {
        self.mesh.mesh()
    }

    /// Plans `start -> goal` on `grid`, the map last [`prepare`](Self::prepare)d (another
    /// map is [`PlanError::InvalidParameters`]), into [`path`](Self::path). Errors as
    /// [`plan`](super::plan).
    pub fn plan(
        &mut self,
        grid: GridRef<'_>,
        start: Cell,
        goal: Cell,
        params: &PlanParams,
        options: PlanOptions<'_>,
    ) -> Result<PlanReport, PlanError> {
        if self.prepared == 0 || self.prepared != fingerprint(grid) {
            return Err(PlanError::InvalidParameters);
        }
        let mut view = PlanStorageMut {
            anyangle: Some(AnyAngleWorkspace {
                mesh: self.mesh.mesh(),
                scratch: self.query.scratch(),
            }),
            nodes: &mut [],
            open: &mut [],
            theta: &mut [],
            guide: &mut self.guide,
            visited: &mut [],
            stations: &mut self.stations,
            optimizer: &mut self.optimizer,
            out: &mut self.out,
        };
        plan(grid, start, goal, params, &mut view, options)
    }

    /// The exact any-angle path (as [`anyangle::plan`]) on `grid`, the map last
    /// [`prepare`](Self::prepare)d, into [`path`](Self::path).
    pub fn anyangle(
        &mut self,
        grid: GridRef<'_>,
        start: Cell,
        goal: Cell,
    ) -> Result<AnyAngleStats, PlanError> {
        if self.prepared == 0 || self.prepared != fingerprint(grid) {
            return Err(PlanError::InvalidParameters);
        }
        let mesh = self.mesh.mesh();
        anyangle::plan(
            grid,
            &mesh,
            start,
            goal,
            self.query.scratch(),
            &mut self.out,
        )
    }

    /// The path of the last successful [`plan`](Self::plan) or
    /// [`anyangle`](Self::anyangle).
    pub fn path(&self) -> &PathView {
        &self.out
    }

    /// The optimizer, to run it on other objectives between plans (a plan configures it
    /// anew).
    pub fn optimizer_mut(&mut self) -> &mut HhoOrGwo<POP, DIM> {
        &mut self.optimizer
    }
}

impl<
    const POP: usize,
    const DIM: usize,
    const PATH: usize,
    const RECTS: usize,
    const LINKS: usize,
    const OPEN: usize,
> Default for PlanStorage<POP, DIM, PATH, RECTS, LINKS, OPEN>
{
    fn default() -> Self {
        Self::new()
    }
}

/// FNV-1a over the grid's size and blocked cells, never 0: which map a mesh belongs to.
fn fingerprint(grid: GridRef<'_>) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    let mut mix = |v: u32| {
        h ^= v as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    };
    mix(grid.width() as u32);
    mix(grid.height() as u32);
    for y in 0..grid.height() {
        for x in (0..grid.width()).step_by(32) {
            mix(grid.row_bits(y, x));
        }
    }
    h | 1
}

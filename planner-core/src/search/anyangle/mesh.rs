//! The free space of a grid cut into rectangles: each maximal run of free cells in a row,
//! stacked over the rows where the same run repeats. Built once per map in one pass over
//! the rows (whole words of the row bits at a time); the any-angle search moves between
//! rectangles through the pieces of their top and bottom edges that they share (the side
//! edges of a rectangle are always blocked, since its runs are maximal).
//!
//! Two rectangles that touch only at a corner (two free cells meeting diagonally between
//! two blocked ones) share no edge, so no path passes between them: that is the collision
//! rule's pinch.

#[cfg(feature = "alloc")]
extern crate alloc;

use crate::error::PlanError;
use crate::grid::GridRef;

/// "No rectangle" in links and in the build's open list.
pub(super) const NONE: u32 = u32::MAX;

/// A free rectangle of cells `[x0, x1) x [y0, y1)` with its neighbours above and below
/// (24 bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    pub(super) x0: u16,
    pub(super) x1: u16,
    pub(super) y0: u16,
    pub(super) y1: u16,
    /// First [`Link`] whose `below` is this rectangle (its neighbours above), and how many.
    top: u32,
    top_len: u16,
    /// How many links follow `bottom` (its neighbours below).
    bottom_len: u16,
    /// First [`Link`] whose `above` is this rectangle.
    bottom: u32,
    /// While building: the next rectangle of the previous row's runs.
    next: u32,
}

impl Rect {
    /// An unused slot (all zero bytes, so a `static` array lands in `.bss`).
    pub const EMPTY: Rect = Rect {
        x0: 0,
        x1: 0,
        y0: 0,
        y1: 0,
        top: 0,
        top_len: 0,
        bottom_len: 0,
        bottom: 0,
        next: 0,
    };
}

/// Two rectangles sharing a piece of a horizontal grid line: `above` ends on the row over
/// the line, `below` starts on the row under it (8 bytes).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Link {
    pub(super) above: u32,
    pub(super) below: u32,
}

impl Link {
    /// An unused slot (all zero bytes).
    pub const EMPTY: Link = Link { above: 0, below: 0 };
}

/// The rectangles of one map, borrowed from the caller's storage.
#[derive(Clone, Copy, Debug)]
pub struct Mesh<'s> {
    pub(super) rects: &'s [Rect],
    pub(super) links: &'s [Link],
    width: usize,
    height: usize,
}

impl<'s> Mesh<'s> {
    /// Cuts the free space of `grid` into rectangles, written to `rects` and `links`.
    /// [`PlanError::CapacityExceeded`] when either is too short (a map of `c` cells never
    /// needs more than `c / 2 + h` rectangles and `c + 2 h` links for `h` rows).
    pub fn build(
        grid: GridRef<'_>,
        rects: &'s mut [Rect],
        links: &'s mut [Link],
    ) -> Result<Self, PlanError> {
        let (w, h) = (grid.width(), grid.height());
        let mut n_rects = 0usize;
        let mut n_links = 0usize;
        // The rectangles holding the previous row's runs, in x order, linked through `next`.
        let mut open = NONE;
        for y in 0..h {
            let (mut head, mut tail) = (NONE, NONE);
            for (x, end) in Runs::new(grid, y) {
                let (a, b) = (x as u16, end as u16);
                while open != NONE && rect(rects, open)?.x1 <= a {
                    open = rect(rects, open)?.next;
                }
                let same = open != NONE && {
                    let u = rect(rects, open)?;
                    u.x0 == a && u.x1 == b
                };
                let r = if same {
                    let r = open;
                    rect_mut(rects, r)?.y1 = y as u16 + 1;
                    r
                } else {
                    let r = n_rects;
                    let slot = rects.get_mut(r).ok_or(PlanError::CapacityExceeded)?;
                    *slot = Rect {
                        x0: a,
                        x1: b,
                        y0: y as u16,
                        y1: y as u16 + 1,
                        top: n_links as u32,
                        top_len: 0,
                        bottom_len: 0,
                        bottom: 0,
                        next: NONE,
                    };
                    n_rects += 1;
                    r as u32
                };
                // Links with every rectangle of the row above that overlaps this run.
                let mut u = open;
                while u != NONE && rect(rects, u)?.x0 < b {
                    if u != r {
                        *links.get_mut(n_links).ok_or(PlanError::CapacityExceeded)? =
                            Link { above: u, below: r };
                        let above = rect_mut(rects, u)?;
                        if above.bottom_len == 0 {
                            above.bottom = n_links as u32;
                        }
                        above.bottom_len += 1;
                        rect_mut(rects, r)?.top_len += 1;
                        n_links += 1;
                    }
                    u = rect(rects, u)?.next;
                }
                // Rectangles ending inside this run overlap no later run.
                while open != NONE && rect(rects, open)?.x1 <= b {
                    open = rect(rects, open)?.next;
                }
                rect_mut(rects, r)?.next = NONE;
                if tail == NONE {
                    head = r;
                } else {
                    rect_mut(rects, tail)?.next = r;
                }
                tail = r;
            }
            open = head;
        }
        Ok(Mesh {
            rects: &rects[..n_rects],
            links: &links[..n_links],
            width: w,
            height: h,
        })
    }

    /// The rectangles and links [`build`](Self::build) will need for `grid`, counted
    /// without storing anything (one pass over the rows), so that a host can size its
    /// storage exactly.
    pub fn count(grid: GridRef<'_>) -> (usize, usize) {
        let (mut rects, mut links) = (0, 0);
        for y in 0..grid.height() {
            let mut above = Runs::new(grid, y.wrapping_sub(1));
            let mut here = Runs::new(grid, y);
            let (mut u, mut r) = (above.next(), here.next());
            // Runs of this row that repeat a run of the row above continue its rectangle.
            let mut repeats = 0;
            while let (Some(a), Some(b)) = (u, r) {
                if a.0 < b.1 && b.0 < a.1 {
                    if a == b {
                        repeats += 1;
                    } else {
                        links += 1;
                    }
                }
                if a.1 <= b.1 {
                    u = above.next();
                }
                if b.1 <= a.1 {
                    r = here.next();
                }
            }
            rects += Runs::new(grid, y).count() - repeats;
        }
        (rects, links)
    }

    /// The mesh held by storage that [`build`](Self::build) filled (owned storage types
    /// keep the lengths it returned).
    pub(super) fn from_parts(
        rects: &'s [Rect],
        links: &'s [Link],
        width: usize,
        height: usize,
    ) -> Self {
        Mesh {
            rects,
            links,
            width,
            height,
        }
    }

    /// Number of rectangles.
    pub fn rects(&self) -> usize {
        self.rects.len()
    }

    /// Number of links (shared edge pieces).
    pub fn links(&self) -> usize {
        self.links.len()
    }

    /// The map's width and height in cells.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    pub(super) fn rect(&self, r: u32) -> Rect {
        self.rects.get(r as usize).copied().unwrap_or(Rect::EMPTY)
    }

    /// Rectangle `r` as cells `[x0, x1) x [y0, y1)`: `(x0, y0, x1, y1)`.
    pub fn bounds(&self, r: u32) -> (usize, usize, usize, usize) {
        let rect = self.rect(r);
        (
            rect.x0 as usize,
            rect.y0 as usize,
            rect.x1 as usize,
            rect.y1 as usize,
        )
    }

    /// The neighbours of `r` above it (`up`) or below it, left to right, that reach into
    /// the doubled x range `[from, to]` (binary search: rectangles spanning a cross aisle
    /// have a neighbour per aisle, and a cone sees a few of them).
    pub(super) fn neighbours_in(
        &self,
        r: u32,
        up: bool,
        from: i32,
        to: i32,
    ) -> impl Iterator<Item = u32> + '_ {
        let rect = self.rect(r);
        let (start, len) = if up {
            (rect.top as usize, rect.top_len as usize)
        } else {
            (rect.bottom as usize, rect.bottom_len as usize)
        };
        let links = self.links.get(start..start + len).unwrap_or(&[]);
        let id = move |l: &Link| if up { l.above } else { l.below };
        let first = links.partition_point(|l| 2 * (self.rect(id(l)).x1 as i32) < from);
        links[first..]
            .iter()
            .map(id)
            .take_while(move |&q| 2 * (self.rect(q).x0 as i32) <= to)
    }

    /// The neighbours above `r`, left to right.
    pub fn above(&self, r: u32) -> impl Iterator<Item = u32> + '_ {
        let rect = self.rect(r);
        let start = rect.top as usize;
        self.links
            .get(start..start + rect.top_len as usize)
            .unwrap_or(&[])
            .iter()
            .map(|l| l.above)
    }

    /// The neighbours below `r`, left to right.
    pub fn below(&self, r: u32) -> impl Iterator<Item = u32> + '_ {
        let rect = self.rect(r);
        let start = rect.bottom as usize;
        self.links
            .get(start..start + rect.bottom_len as usize)
            .unwrap_or(&[])
            .iter()
            .map(|l| l.below)
    }

    /// The rectangle holding the free cell `(x, y)` of `grid` (the grid it was built from).
    pub(super) fn locate(&self, grid: GridRef<'_>, x: usize, y: usize) -> Option<u32> {
        if grid.is_blocked(x as isize, y as isize) {
            return None;
        }
        // The run holding x, then up while the row above has the same run.
        let a = (0..=x)
            .rev()
            .find(|&c| c == 0 || grid.is_blocked(c as isize - 1, y as isize))
            .unwrap_or(0);
        let b = grid.next_blocked(y, x);
        let same_run = |row: usize| {
            !grid.row_run_blocked(row as isize, a as isize, b as isize - 1)
                && grid.is_blocked(a as isize - 1, row as isize)
                && grid.is_blocked(b as isize, row as isize)
        };
        let mut top = y;
        while top > 0 && same_run(top - 1) {
            top -= 1;
        }
        // Rectangles are stored in order of (top row, left column).
        let key = (top as u16, a as u16);
        self.rects
            .binary_search_by(|r| (r.y0, r.x0).cmp(&key))
            .ok()
            .map(|i| i as u32)
    }
}

/// The free runs `[a, b)` of one row, left to right (none for a row off the map).
struct Runs<'g> {
    grid: GridRef<'g>,
    y: usize,
    x: usize,
}

impl<'g> Runs<'g> {
    fn new(grid: GridRef<'g>, y: usize) -> Self {
        let x = if y < grid.height() {
            grid.next_free(y, 0)
        } else {
            grid.width()
        };
        Runs { grid, y, x }
    }
}

impl Iterator for Runs<'_> {
    type Item = (usize, usize);

    fn next(&mut self) -> Option<(usize, usize)> {
        if self.x >= self.grid.width() {
            return None;
        }
        let end = self.grid.next_blocked(self.y, self.x);
        let run = (self.x, end);
        self.x = self.grid.next_free(self.y, end);
        Some(run)
    }
}

/// A mesh in storage sized at run time (feature `alloc`), for hosts: built once per map,
/// then lent as a [`Mesh`] to every query.
#[cfg(feature = "alloc")]
#[derive(Clone, Debug, Default)]
pub struct MeshBuf {
    rects: alloc::vec::Vec<Rect>,
    links: alloc::vec::Vec<Link>,
    width: usize,
    height: usize,
}

#[cfg(feature = "alloc")]
impl MeshBuf {
    /// Counts, then builds, the mesh of `grid` in storage of exactly the size it needs.
    pub fn build(grid: GridRef<'_>) -> Result<Self, PlanError> {
        let (rects, links) = Mesh::count(grid);
        let mut buf = MeshBuf {
            rects: alloc::vec![Rect::EMPTY; rects],
            links: alloc::vec![Link::EMPTY; links],
            width: grid.width(),
            height: grid.height(),
        };
        Mesh::build(grid, &mut buf.rects, &mut buf.links)?;
        Ok(buf)
    }

    /// The mesh.
    pub fn mesh(&self) -> Mesh<'_> {
        Mesh::from_parts(&self.rects, &self.links, self.width, self.height)
    }

    /// Bytes of heap the mesh holds.
    pub fn heap_bytes(&self) -> usize {
        self.rects.len() * core::mem::size_of::<Rect>()
            + self.links.len() * core::mem::size_of::<Link>()
    }
}

fn rect(rects: &[Rect], r: u32) -> Result<&Rect, PlanError> {
    rects.get(r as usize).ok_or(PlanError::CapacityExceeded)
}

fn rect_mut(rects: &mut [Rect], r: u32) -> Result<&mut Rect, PlanError> {
    rects.get_mut(r as usize).ok_or(PlanError::CapacityExceeded)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::{Grid, words_for};

    type G = Grid<{ words_for(64, 64) }>;

    fn build(g: &G) -> (std::vec::Vec<Rect>, std::vec::Vec<Link>, usize, usize) {
        let mut rects = std::vec![Rect::EMPTY; 64 * 64];
        let mut links = std::vec![Link::EMPTY; 2 * 64 * 64];
        let m = Mesh::build(g.view(), &mut rects, &mut links).unwrap();
        let (nr, nl) = (m.rects(), m.links());
        assert_eq!(Mesh::count(g.view()), (nr, nl));
        (rects, links, nr, nl)
    }

    #[test]
    fn rectangles_tile_the_free_cells_and_links_are_shared_edges() {
        let g = G::parse_rows(
            b"..........\n.@@@..@@..\n.@@@..@@..\n..........\n@........@\n...@@@@...\n...@@@@...\n",
        )
        .unwrap();
        let (rects, links, nr, nl) = build(&g);
        let mesh = Mesh {
            rects: &rects[..nr],
            links: &links[..nl],
            width: 10,
            height: 7,
        };
        let v = g.view();
        // Every free cell is in exactly one rectangle, located by `locate`.
        for y in 0..7 {
            for x in 0..10 {
                let holders: std::vec::Vec<usize> = (0..nr)
                    .filter(|&i| {
                        let r = rects[i];
                        (r.x0 as usize..r.x1 as usize).contains(&x)
                            && (r.y0 as usize..r.y1 as usize).contains(&y)
                    })
                    .collect();
                let free = !v.is_blocked(x as isize, y as isize);
                assert_eq!(holders.len(), free as usize, "cell {x},{y}");
                if free {
                    assert_eq!(mesh.locate(v, x, y), Some(holders[0] as u32));
                } else {
                    assert_eq!(mesh.locate(v, x, y), None);
                }
            }
        }
        // Side edges are blocked (runs are maximal).
        for r in &rects[..nr] {
            for y in r.y0..r.y1 {
                assert!(v.is_blocked(r.x0 as isize - 1, y as isize));
                assert!(v.is_blocked(r.x1 as isize, y as isize));
            }
        }
        // Links: exactly the pairs that share a piece of a grid line.
        for i in 0..nr {
            for j in 0..nr {
                let (a, b) = (rects[i], rects[j]);
                let shares = a.y1 == b.y0 && a.x0.max(b.x0) < a.x1.min(b.x1);
                let linked = links[..nl]
                    .iter()
                    .any(|l| l.above == i as u32 && l.below == j as u32);
                assert_eq!(shares, linked, "{i} {j}");
                assert_eq!(shares, mesh.below(i as u32).any(|k| k == j as u32));
                assert_eq!(shares, mesh.above(j as u32).any(|k| k == i as u32));
            }
        }
        // The open area at the top merges rows 1-2 between the blocks.
        assert!(
            rects[..nr]
                .iter()
                .any(|r| r.x0 == 4 && r.x1 == 6 && r.y0 == 1 && r.y1 == 3)
        );
    }

    #[test]
    fn short_storage_is_capacity_exceeded() {
        let g = G::parse_rows(b".@.@.\n@.@.@\n").unwrap();
        let mut rects = [Rect::EMPTY; 4];
        let mut links = [Link::EMPTY; 16];
        assert_eq!(
            Mesh::build(g.view(), &mut rects, &mut links).err(),
            Some(PlanError::CapacityExceeded)
        );
    }
}

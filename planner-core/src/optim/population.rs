//! A population: positions and cached costs, with capacity `N x D`.

/// Positions and cached costs of a population with capacity `N x D`.
#[derive(Debug, Clone)]
pub struct Population<const N: usize, const D: usize> {
    positions: [[f32; D]; N],
    costs: [f32; N],
    size: usize,
    dim: usize,
}

impl<const N: usize, const D: usize> Population<N, D> {
    /// An empty population of runtime size `size <= N` and dimension `dim <= D` (all zero,
    /// costs `+inf`).
    pub fn new(size: usize, dim: usize) -> Self {
        let mut p = Self::empty();
        p.resize(size, dim);
        p
    }

    /// A population of size 0, all zero bytes (usable in `const` and `static` initialisers,
    /// like every optimizer's `unconfigured()`). [`resize`](Self::resize) sets the costs.
    pub const fn empty() -> Self {
        Self {
            positions: [[0.0; D]; N],
            costs: [0.0; N],
            size: 0,
            dim: 0,
        }
    }

    /// Sets the runtime sizes in place (clamped to the capacity); costs become `+inf`.
    pub fn resize(&mut self, size: usize, dim: usize) {
        self.size = size.min(N);
        self.dim = dim.min(D);
        self.costs = [f32::INFINITY; N];
    }

    /// Runtime population size.
    pub fn size(&self) -> usize {
        self.size
    }

    /// Runtime dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// The sum of the members' positions, coordinate by coordinate (0 beyond the dimension),
    /// adding the members in order. One coordinate at a time, in a register: row by row,
    /// each partial sum was loaded and stored back per member.
    pub fn sum_positions(&self, sum: &mut [f32; D]) {
        let rows = self.positions.get(..self.size).unwrap_or(&[]);
        for (d, s) in sum.iter_mut().enumerate() {
            let mut total = 0.0;
            if d < self.dim {
                for row in rows {
                    total += row[d];
                }
            }
            *s = total;
        }
    }

    /// Member `k` to read and member `i` to write, or `None` unless both exist and differ.
    pub fn read_write(&mut self, k: usize, i: usize) -> Option<(&[f32], &mut [f32])> {
        if k >= self.size || i >= self.size {
            return None;
        }
        let dim = self.dim;
        let (read, write) = if k < i {
            let (before, from) = self.positions.split_at_mut_checked(i)?;
            (before.get(k)?, from.first_mut()?)
        } else if i < k {
            let (before, from) = self.positions.split_at_mut_checked(k)?;
            (&*from.first_mut()?, before.get_mut(i)?)
        } else {
            return None;
        };
        Some((read.get(..dim)?, write.get_mut(..dim)?))
    }

    /// Member `i` (empty if `i >= size`).
    pub fn position(&self, i: usize) -> &[f32] {
        match self.positions.get(i) {
            Some(row) if i < self.size => row.get(..self.dim).unwrap_or(&[]),
            _ => &[],
        }
    }

    /// Member `i`, mutable (empty if `i >= size`).
    pub fn position_mut(&mut self, i: usize) -> &mut [f32] {
        let (size, dim) = (self.size, self.dim);
        match self.positions.get_mut(i) {
            Some(row) if i < size => row.get_mut(..dim).unwrap_or(&mut []),
            _ => &mut [],
        }
    }

    /// Cached cost of member `i` (`+inf` if `i >= size`).
    pub fn cost(&self, i: usize) -> f32 {
        if i < self.size {
            self.costs.get(i).copied().unwrap_or(f32::INFINITY)
        } else {
            f32::INFINITY
        }
    }

    /// Sets the cached cost of member `i` (ignored if `i >= size`).
    pub fn set_cost(&mut self, i: usize, cost: f32) {
        if i < self.size
            && let Some(c) = self.costs.get_mut(i)
        {
            *c = cost;
        }
    }

    /// Copies `x` into member `i` with its cost.
    pub fn replace(&mut self, i: usize, x: &[f32], cost: f32) {
        copy(self.position_mut(i), x);
        self.set_cost(i, cost);
    }

    /// Index of the lowest cost (first on ties; 0 if empty).
    pub fn best_index(&self) -> usize {
        let mut best = 0;
        for i in 1..self.size {
            if self.cost(i) < self.cost(best) {
                best = i;
            }
        }
        best
    }

    /// Index of the highest cost (first on ties; 0 if empty).
    pub fn worst_index(&self) -> usize {
        let mut worst = 0;
        for i in 1..self.size {
            if self.cost(i) > self.cost(worst) {
                worst = i;
            }
        }
        worst
    }

    /// Fills `order[..size]` with member indices sorted by ascending cost (stable).
    ///
    /// Insertion sort: populations are small and it needs no buffer.
    pub fn sort_indices(&self, order: &mut [usize; N]) {
        for (k, o) in order.iter_mut().enumerate() {
            *o = k;
        }
        let n = self.size.min(N);
        for k in 1..n {
            let mut j = k;
            while j > 0 && self.cost(order[j]) < self.cost(order[j - 1]) {
                order.swap(j, j - 1);
                j -= 1;
            }
        }
    }
}

/// Copies `src` into `dst` over their common length.
pub(crate) fn copy(dst: &mut [f32], src: &[f32]) {
    for (d, s) in dst.iter_mut().zip(src) {
        *d = *s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn population_sorting() {
        let mut p = Population::<4, 1>::new(4, 1);
        for (i, c) in [3.0, 1.0, 2.0, 1.0].iter().enumerate() {
            p.set_cost(i, *c);
        }
        let mut order = [0; 4];
        p.sort_indices(&mut order);
        assert_eq!(order, [1, 3, 2, 0]);
        assert_eq!((p.best_index(), p.worst_index()), (1, 0));
        assert!(p.position(4).is_empty());
    }

    #[test]
    fn population_rows_and_sums() {
        let mut p = Population::<4, 3>::new(3, 2);
        for i in 0..3 {
            for (d, v) in p.position_mut(i).iter_mut().enumerate() {
                *v = (10 * i + d) as f32;
            }
        }
        // Sums in member order, 0 beyond the dimension.
        let mut sum = [7.0; 3];
        p.sum_positions(&mut sum);
        assert_eq!(sum, [30.0, 33.0, 0.0]);
        // One member to read, another to write, whichever comes first.
        for (k, i) in [(0, 2), (2, 0)] {
            let (read, write) = p.read_write(k, i).unwrap();
            assert_eq!((read.len(), read[0]), (2, (10 * k) as f32));
            write[1] = -1.0;
            assert_eq!(p.position(i)[1], -1.0);
        }
        assert!(p.read_write(1, 1).is_none());
        assert!(p.read_write(3, 0).is_none());
        assert!(p.read_write(0, 3).is_none());
    }
}

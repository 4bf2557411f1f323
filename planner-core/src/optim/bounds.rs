//! The box `[lb, ub]^D` an optimizer searches, and clamping into it.

use super::OptimError;

/// Per-dimension box bounds with capacity `D`.
#[derive(Debug, Clone, PartialEq)]
pub struct Bounds<const D: usize> {
    lower: [f32; D],
    upper: [f32; D],
    dim: usize,
}

impl<const D: usize> Bounds<D> {
    /// Bounds of dimension 0, all zero bytes (for [`SwarmState::unconfigured`](super::SwarmState::unconfigured)).
    pub(super) const fn unconfigured() -> Self {
        Self {
            lower: [0.0; D],
            upper: [0.0; D],
            dim: 0,
        }
    }

    /// The same interval `[lower, upper]` on each of `dim` dimensions.
    pub fn uniform(dim: usize, lower: f32, upper: f32) -> Result<Self, OptimError> {
        if dim == 0 || dim > D {
            return Err(OptimError::DimensionOutOfRange);
        }
        check_interval(lower, upper)?;
        Ok(Self {
            lower: [lower; D],
            upper: [upper; D],
            dim,
        })
    }

    /// Bounds from two slices of equal length (the dimension).
    pub fn from_slices(lower: &[f32], upper: &[f32]) -> Result<Self, OptimError> {
        if lower.len() != upper.len() {
            return Err(OptimError::InvalidBounds);
        }
        Self::from_fn(lower.len(), |i| {
            (
                lower.get(i).copied().unwrap_or(f32::NAN),
                upper.get(i).copied().unwrap_or(f32::NAN),
            )
        })
    }

    /// Bounds of `dim` dimensions, `(lower, upper)` of dimension `i` from `interval(i)`
    /// (without two capacity-sized arrays on the caller's stack).
    pub fn from_fn(
        dim: usize,
        mut interval: impl FnMut(usize) -> (f32, f32),
    ) -> Result<Self, OptimError> {
        if dim == 0 || dim > D {
            return Err(OptimError::DimensionOutOfRange);
        }
        let mut b = Self {
            lower: [0.0; D],
            upper: [0.0; D],
            dim,
        };
        for (i, (sl, su)) in b
            .lower
            .iter_mut()
            .zip(b.upper.iter_mut())
            .take(dim)
            .enumerate()
        {
            let (l, u) = interval(i);
            check_interval(l, u)?;
            *sl = l;
            *su = u;
        }
        Ok(b)
    }

    /// The runtime dimension.
    pub fn dim(&self) -> usize {
        self.dim
    }

    /// Lower bounds, one per dimension.
    pub fn lower(&self) -> &[f32] {
        self.lower.get(..self.dim).unwrap_or(&[])
    }

    /// Upper bounds, one per dimension.
    pub fn upper(&self) -> &[f32] {
        self.upper.get(..self.dim).unwrap_or(&[])
    }

    /// Clamps `x` into the box; NaN coordinates go to the lower bound.
    pub fn clamp(&self, x: &mut [f32]) {
        for (v, (l, u)) in x.iter_mut().zip(self.pairs()) {
            *v = clamp_into(*v, l, u);
        }
    }

    /// `(lower, upper)` per dimension.
    pub(crate) fn pairs(&self) -> impl Iterator<Item = (f32, f32)> + '_ {
        self.lower()
            .iter()
            .copied()
            .zip(self.upper().iter().copied())
    }
}

/// One coordinate of [`Bounds::clamp`], for loops that clamp while they compute a candidate.
#[inline]
#[allow(clippy::neg_cmp_op_on_partial_ord)]
pub(crate) fn clamp_into(v: f32, l: f32, u: f32) -> f32 {
    // A NaN becomes the lower bound, which keeps NaN out of every objective call. Comparisons
    // rather than `max`/`min` (libm calls on Cortex-M4); the result is the same as
    // `v.max(l).min(u)` except possibly for the sign of a zero on a zero bound.
    // `!(v >= l)` is `v.is_nan() || v < l` in one comparison (unordered fails `>=`).
    if !(v >= l) {
        l
    } else if v > u {
        u
    } else {
        v
    }
}

fn check_interval(lower: f32, upper: f32) -> Result<(), OptimError> {
    if !lower.is_finite() || !upper.is_finite() || lower > upper {
        return Err(OptimError::InvalidBounds);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bounds_are_validated() {
        assert_eq!(
            Bounds::<4>::uniform(0, 0.0, 1.0),
            Err(OptimError::DimensionOutOfRange)
        );
        assert_eq!(
            Bounds::<4>::uniform(5, 0.0, 1.0),
            Err(OptimError::DimensionOutOfRange)
        );
        assert_eq!(
            Bounds::<4>::uniform(2, 1.0, 0.0),
            Err(OptimError::InvalidBounds)
        );
        assert_eq!(
            Bounds::<4>::uniform(2, f32::NAN, 0.0),
            Err(OptimError::InvalidBounds)
        );
        assert_eq!(
            Bounds::<4>::uniform(2, 0.0, f32::INFINITY),
            Err(OptimError::InvalidBounds)
        );
        assert_eq!(
            Bounds::<4>::from_slices(&[0.0], &[1.0, 2.0]),
            Err(OptimError::InvalidBounds)
        );
        let b = Bounds::<4>::from_slices(&[0.0, -1.0], &[1.0, 1.0]).unwrap();
        let mut x = [5.0, f32::NAN];
        b.clamp(&mut x);
        assert_eq!(x, [1.0, -1.0]);
    }
}

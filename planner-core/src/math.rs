//! Scalar maths shared by the crate, so that a faster target-specific routine can replace
//! a `libm` one in a single place without changing results.

/// Square root. `libm::sqrtf` is correctly rounded, so a hardware `VSQRT.F32` (also
/// correctly rounded, IEEE 754) may replace it without changing any result.
#[inline]
pub fn sqrt(x: f32) -> f32 {
    libm::sqrtf(x)
}

/// `floor` for values well inside the `isize` range (coordinates on a map), without the
/// software rounding routine: truncation, then one correction for negative fractions.
#[inline]
pub fn floor_i(x: f32) -> isize {
    let i = x as isize;
    if (i as f32) > x { i - 1 } else { i }
}

/// `ceil` counterpart of [`floor_i`].
#[inline]
pub fn ceil_i(x: f32) -> isize {
    let i = x as isize;
    if (i as f32) < x { i + 1 } else { i }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floor_and_ceil_match_libm() {
        for k in -4000..4000 {
            let x = k as f32 * 0.37 - 0.5;
            for v in [x, x + 1e-4, x - 1e-4, (k / 4) as f32, -0.0, 0.5, -0.5] {
                assert_eq!(floor_i(v), libm::floorf(v) as isize, "{v}");
                assert_eq!(ceil_i(v), libm::ceilf(v) as isize, "{v}");
            }
        }
    }
}

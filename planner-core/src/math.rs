//! Scalar maths shared by the crate, so that a faster target-specific routine can replace
//! a `libm` one in a single place without changing results.

/// Square root. `libm::sqrtf` is correctly rounded, so a hardware `VSQRT.F32` (also
/// correctly rounded, IEEE 754) may replace it without changing any result.
#[inline]
pub fn sqrt(x: f32) -> f32 {
    libm::sqrtf(x)
}

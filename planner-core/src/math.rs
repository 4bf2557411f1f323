//! Scalar maths shared by the crate, so that a faster target-specific routine can replace
//! a `libm` one in a single place without changing results.

/// Square root, correctly rounded (IEEE 754), the single square root of the crate.
///
/// On hard-float ARM targets (`thumbv7em-none-eabihf`: Cortex-M4F/M7F) this is the FPU's
/// `VSQRT.F32`; elsewhere, and with the feature `soft-sqrt`, `libm::sqrtf`. Both are
/// correctly rounded, so results are bit-identical either way (the firmware digest is
/// checked with and without it).
#[inline]
pub fn sqrt(x: f32) -> f32 {
    #[cfg(all(target_arch = "arm", target_abi = "eabihf", not(feature = "soft-sqrt")))]
    {
        vsqrt(x)
    }
    #[cfg(not(all(target_arch = "arm", target_abi = "eabihf", not(feature = "soft-sqrt"))))]
    {
        libm::sqrtf(x)
    }
}

/// `VSQRT.F32` on a hard-float ARM core. The value goes in and out through a core register
/// (`vmov`): an `f32` operand in an FPU register class needs the double-precision FPU on
/// thumbv7em, which the Cortex-M4F does not have.
#[cfg(all(target_arch = "arm", target_abi = "eabihf", not(feature = "soft-sqrt")))]
#[allow(unsafe_code)]
#[inline]
fn vsqrt(x: f32) -> f32 {
    let mut bits = x.to_bits();
    // SAFETY: the `eabihf` ABI guarantees a single-precision FPU, so VMOV and VSQRT.F32 are
    // valid instructions. The block reads and writes only `bits` (a core register) and `s0`,
    // which is declared clobbered; it touches no memory and no stack, and VSQRT has no side
    // effect beyond the FPSCR cumulative flags (which Rust code never reads).
    unsafe {
        core::arch::asm!(
            "vmov s0, {v}",
            "vsqrt.f32 s0, s0",
            "vmov {v}, s0",
            v = inout(reg) bits,
            out("s0") _,
            options(pure, nomem, nostack),
        );
    }
    f32::from_bits(bits)
}

/// `a.min(b)` for a non-NaN `a`, by one comparison: `f32::min` is a libm call on Cortex-M4
/// (no `VMINNM`). Same value (up to the sign of a zero); a NaN `b` gives `a`, like `min`.
#[inline]
pub fn lesser(a: f32, b: f32) -> f32 {
    if b < a { b } else { a }
}

/// `a.max(b)` for a non-NaN `a`, by one comparison (see [`lesser`]).
#[inline]
pub fn greater(a: f32, b: f32) -> f32 {
    if b > a { b } else { a }
}

/// `x.max(0.0)` by one comparison (see [`lesser`]); NaN gives 0, like `max`.
#[inline]
pub fn at_least_zero(x: f32) -> f32 {
    if x > 0.0 { x } else { 0.0 }
}

/// `floor` for values well inside the `isize` range (coordinates on a map), without the
/// software rounding routine: truncation, then one correction for negative fractions.
#[inline]
pub fn floor_i(x: f32) -> isize {
    let i = x as isize;
    if (i as f32) > x { i - 1 } else { i }
}

/// `x` limited to `[lo, hi]` with no panic: `f32::clamp` asserts `lo <= hi` (input-dependent
/// bounds could trip it) and its message formats floats, about 20 KiB of flash on Cortex-M.
/// Equal to `x.clamp(lo, hi)` whenever that does not panic; with `lo > hi` it gives `lo` or
/// `hi`; NaN stays NaN.
#[inline]
pub fn clamp(x: f32, lo: f32, hi: f32) -> f32 {
    if x < lo {
        lo
    } else if x > hi {
        hi
    } else {
        x
    }
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
    fn clamp_matches_std_and_never_panics() {
        for x in [
            -3.0f32,
            -0.5,
            0.0,
            0.25,
            1.0,
            7.5,
            f32::INFINITY,
            f32::NEG_INFINITY,
        ] {
            assert_eq!(clamp(x, -1.0, 1.0), x.clamp(-1.0, 1.0));
        }
        assert!(clamp(f32::NAN, 0.0, 1.0).is_nan());
        // Bounds the wrong way round (std would panic).
        assert!([2.0, 1.0].contains(&clamp(1.5, 2.0, 1.0)));
    }

    #[test]
    fn lesser_greater_and_at_least_zero_match_std() {
        let values = [
            -3.0f32,
            -0.5,
            0.0,
            0.25,
            1.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
        ];
        for a in values.into_iter().filter(|a| !a.is_nan()) {
            for b in values {
                assert_eq!(lesser(a, b), a.min(b), "{a} {b}");
                assert_eq!(greater(a, b), a.max(b), "{a} {b}");
            }
        }
        for x in values {
            assert_eq!(at_least_zero(x), x.max(0.0), "{x}");
        }
    }

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

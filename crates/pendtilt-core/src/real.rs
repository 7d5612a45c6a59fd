//! The scalar type every algorithm is generic over: `f32` on a microcontroller, `f64` on a PC.

use nalgebra::RealField;

/// A real scalar: `f32` or `f64`.
///
/// All math goes through [`nalgebra::RealField`] (which uses `libm` without `std`), so the
/// same code runs on a Cortex-M4F and on a PC.
pub trait Real: RealField + Copy + Default + core::fmt::Debug {
    /// Converts an `f64` constant to this type (rounding to nearest for `f32`).
    fn lit(x: f64) -> Self;
    /// Converts to `f64` (exact for both `f32` and `f64`).
    fn to_f64(self) -> f64;
    /// Not a number: the marker of a missing input.
    fn nan() -> Self;
}

impl Real for f64 {
    #[inline(always)]
    fn lit(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn nan() -> Self {
        f64::NAN
    }
}

impl Real for f32 {
    #[inline(always)]
    fn lit(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline(always)]
    fn nan() -> Self {
        f32::NAN
    }
}

/// True when `x > 0`; false for zero, negative and NaN (a time step must pass this).
#[inline(always)]
pub(crate) fn is_positive<T: Real>(x: T) -> bool {
    x > T::zero()
}

//! The floating-point type of a run (f32 or f64, chosen at run time by the host).
//!
//! Every operation used here is correctly rounded in IEEE 754 (add, sub, mul, div, sqrt, floor), so the host and
//! the GPU produce bitwise-equal results for the same sequence of operations, as long as no FMA contraction is
//! applied (rustc emits none by default; ../shared/GPU.md).

use bytemuck::Pod;
use core::ops::{Add, AddAssign, Div, Mul, MulAssign, Neg, Sub, SubAssign};

pub trait Real:
    Pod
    + Default
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
    + AddAssign
    + SubAssign
    + MulAssign
    + Send
    + Sync
    + core::fmt::Debug
    + 'static
{
    /// Name used in reports and PTX entry points.
    const NAME: &'static str;
    const ZERO: Self;
    const ONE: Self;
    /// Machine epsilon.
    const EPSILON: Self;
    /// Packed 2-vector with the alignment that gives one vector load on the GPU.
    type V2: Vector<Self>;
    /// Packed 3-vector, padded to 4 lanes for 16-byte loads.
    type V3: Vector<Self>;
    /// Plane-strain symmetric tensor (4 components).
    type S2: SymTensor<Self>;
    /// 3D symmetric tensor (6 components).
    type S3: SymTensor<Self>;

    fn from_f64(x: f64) -> Self;
    /// Exact widening (f32 → f64 is exact).
    fn to_f64(self) -> f64;
    fn sqrt(self) -> Self;
    fn floor(self) -> Self;
    fn abs(self) -> Self;
    fn is_finite(self) -> bool;
    #[inline]
    fn max(self, o: Self) -> Self {
        if o > self { o } else { self }
    }
    #[inline]
    fn min(self, o: Self) -> Self {
        if o < self { o } else { self }
    }
}

use crate::vector::{S2f32, S2f64, S3f32, S3f64, SymTensor, V2f32, V2f64, V3f32, V3f64, Vector};

macro_rules! real_impl {
    ($t:ty, $name:literal, $v2:ty, $v3:ty, $s2:ty, $s3:ty, $libsqrt:path, $libfloor:path, $gpusqrt:path, $gpufloor:path) => {
        impl Real for $t {
            const NAME: &'static str = $name;
            const ZERO: Self = 0.0;
            const ONE: Self = 1.0;
            const EPSILON: Self = <$t>::EPSILON;
            type V2 = $v2;
            type V3 = $v3;
            type S2 = $s2;
            type S3 = $s3;
            #[inline(always)]
            fn from_f64(x: f64) -> Self {
                x as $t
            }
            #[inline(always)]
            fn to_f64(self) -> f64 {
                self as f64
            }
            #[inline(always)]
            fn sqrt(self) -> Self {
                // Correctly rounded on both sides: libm on the host, `sqrt.rn` on the GPU.
                #[cfg(target_arch = "nvptx64")]
                {
                    $gpusqrt(self)
                }
                #[cfg(not(target_arch = "nvptx64"))]
                {
                    $libsqrt(self)
                }
            }
            #[inline(always)]
            fn floor(self) -> Self {
                #[cfg(target_arch = "nvptx64")]
                {
                    $gpufloor(self)
                }
                #[cfg(not(target_arch = "nvptx64"))]
                {
                    $libfloor(self)
                }
            }
            #[inline(always)]
            fn abs(self) -> Self {
                <$t>::abs(self)
            }
            #[inline(always)]
            fn is_finite(self) -> bool {
                <$t>::is_finite(self)
            }
        }
    };
}

real_impl!(
    f32,
    "f32",
    V2f32,
    V3f32,
    S2f32,
    S3f32,
    libm::sqrtf,
    libm::floorf,
    core::f32::math::sqrt,
    core::f32::math::floor
);
real_impl!(
    f64,
    "f64",
    V2f64,
    V3f64,
    S2f64,
    S3f64,
    libm::sqrt,
    libm::floor,
    core::f64::math::sqrt,
    core::f64::math::floor
);

/// Floor in f64, identical on host and GPU (the grid arithmetic is always f64, see `neighbour::grid`).
#[inline(always)]
pub fn floor_f64(x: f64) -> f64 {
    <f64 as Real>::floor(x)
}

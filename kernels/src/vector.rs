//! Packed small vectors, one per dimension and precision, aligned so that the GPU loads each with vector
//! instructions (an `[f32; 2]` has 4-byte alignment and splits into scalar loads: ../shared/GPU.md "Loads").
//! 3-vectors are padded to 4 lanes (16 bytes in f32, 32 in f64).

use crate::real::Real;
use bytemuck::{Pod, Zeroable};

/// A position-like vector of `DIM` components of `R`.
pub trait Vector<R: Real>: Pod + Default + Send + Sync + core::fmt::Debug {
    const DIM: usize;
    /// Component `k` (`k < DIM`); components past `DIM` read as zero.
    fn get(&self, k: usize) -> R;
    /// Builds a vector from up to three components (those past `DIM` are ignored).
    fn new(c: [R; 3]) -> Self;
    #[inline(always)]
    fn dist2(&self, o: &Self) -> R {
        let mut s = R::ZERO;
        let mut k = 0;
        while k < Self::DIM {
            let d = self.get(k) - o.get(k);
            s += d * d;
            k += 1;
        }
        s
    }
}

macro_rules! vec_type {
    ($name:ident, $r:ty, $lanes:literal, $dim:literal, $align:literal) => {
        #[repr(C, align($align))]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
        pub struct $name(pub [$r; $lanes]);

        impl Vector<$r> for $name {
            const DIM: usize = $dim;
            #[inline(always)]
            fn get(&self, k: usize) -> $r {
                // SAFETY: k < DIM <= lanes.
                if k < $dim { unsafe { *self.0.get_unchecked(k) } } else { 0.0 }
            }
            #[inline(always)]
            fn new(c: [$r; 3]) -> Self {
                let mut v = [0.0; $lanes];
                let mut k = 0;
                while k < $dim {
                    // SAFETY: k < DIM <= min(3, lanes).
                    unsafe { *v.get_unchecked_mut(k) = *c.get_unchecked(k) };
                    k += 1;
                }
                $name(v)
            }
        }
    };
}

vec_type!(V2f32, f32, 2, 2, 8);
vec_type!(V2f64, f64, 2, 2, 16);
vec_type!(V3f32, f32, 4, 3, 16);
vec_type!(V3f64, f64, 4, 3, 16);

/// A symmetric tensor stored by its independent components: 2D plane strain (xx, xy, yy, zz), 3D
/// (xx, xy, xz, yy, yz, zz) (roethlin-solver.md §2.3, §5.1).
pub trait SymTensor<R: Real>: Pod + Default + Send + Sync + core::fmt::Debug {
    const COMPONENTS: usize;
    /// The stored components (2D: xx, xy, yy, zz; 3D: xx, xy, xz, yy, yz, zz).
    fn components(&self) -> &[R];
    fn components_mut(&mut self) -> &mut [R];
}

macro_rules! sym_type {
    ($name:ident, $r:ty, $n:literal, $align:literal) => {
        #[repr(C, align($align))]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
        pub struct $name(pub [$r; $n]);
        impl SymTensor<$r> for $name {
            const COMPONENTS: usize = $n;
            #[inline(always)]
            fn components(&self) -> &[$r] {
                &self.0
            }
            #[inline(always)]
            fn components_mut(&mut self) -> &mut [$r] {
                &mut self.0
            }
        }
    };
}

sym_type!(S2f32, f32, 4, 16);
sym_type!(S2f64, f64, 4, 16);
sym_type!(S3f32, f32, 6, 8);
sym_type!(S3f64, f64, 6, 16);

/// The spatial dimension of a run (2D plane strain or 3D), chosen at run time by the host.
pub trait Dim: Copy + Default + PartialEq + core::fmt::Debug + Send + Sync + 'static {
    const D: usize;
    const NAME: &'static str;
    type Vec<R: Real>: Vector<R>;
    type Sym<R: Real>: SymTensor<R>;
}

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dim2;
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dim3;

impl Dim for Dim2 {
    const D: usize = 2;
    const NAME: &'static str = "2d";
    type Vec<R: Real> = R::V2;
    type Sym<R: Real> = R::S2;
}
impl Dim for Dim3 {
    const D: usize = 3;
    const NAME: &'static str = "3d";
    type Vec<R: Real> = R::V3;
    type Sym<R: Real> = R::S3;
}

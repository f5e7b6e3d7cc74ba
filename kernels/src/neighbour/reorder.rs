//! One row of a fused reorder: every particle field is gathered through the cell list's permutation in a single
//! launch (one block row per field), instead of one launch per field.

/// A field to gather: `dst[i] = src[perm[i]]` for elements of `bytes` bytes (a multiple of 4). The addresses are
/// the backend's (device pointers on the GPU).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, bytemuck::Pod, bytemuck::Zeroable)]
pub struct GatherField {
    pub src: u64,
    pub dst: u64,
    pub bytes: u32,
    pub _pad: u32,
}

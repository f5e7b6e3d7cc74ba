// The replacement of the original's texture references (removed in CUDA 12) by plain read-only loads. Ours, not
// the original's: ci/original/port.py copies it into original/src, includes it from interactions_gpu.cu, turns
// each `texture<...> NAME;` into nothing, each `cudaBindTexture(0, NAME, PTR, ...)` into
// `swarf_tex_h.f_NAME = PTR;`, drops `cudaUnbindTexture(NAME)`, and uploads the pointers before each kernel launch
// of that file. The kernels' texfetch1/2/4(NAME, i) and tex1Dfetch(NAME, i) become __ldg(&NAME[i]): the same
// values, bit for bit (the original's double fetch reassembled each double from two ints).
#ifndef SWARF_TEX_CUH_
#define SWARF_TEX_CUH_

#include "types.h"

// The arrays the original bound to textures (interactions_gpu.cu), by the texture's name. port.py checks that the
// original declares exactly these textures with these element types.
struct swarf_tex_ptrs {
    const float2_t *f_pos_tex;
    const float2_t *f_vel_tex;
    const float4_t *f_S_tex;
    const float4_t *f_R_tex;
    const float_t *f_h_tex;
    const float_t *f_rho_tex;
    const float_t *f_p_tex;
    const float_t *f_T_tex;
    const float_t *f_tool_particle_tex;
    const int *f_hashes_tex;
    const float2_t *f_pos_to_tex;
    const float_t *f_h_to_tex;
    const float_t *f_T_to_tex;
    const int *f_hashes_to_tex;
    const int *f_cells_start_tex;
    const int *f_cells_end_tex;
};

__constant__ static swarf_tex_ptrs swarf_tex;
static swarf_tex_ptrs swarf_tex_h;

static void swarf_tex_upload() {
    cudaMemcpyToSymbol(swarf_tex, &swarf_tex_h, sizeof(swarf_tex_ptrs), 0, cudaMemcpyHostToDevice);
}

#define pos_tex (swarf_tex.f_pos_tex)
#define vel_tex (swarf_tex.f_vel_tex)
#define S_tex (swarf_tex.f_S_tex)
#define R_tex (swarf_tex.f_R_tex)
#define h_tex (swarf_tex.f_h_tex)
#define rho_tex (swarf_tex.f_rho_tex)
#define p_tex (swarf_tex.f_p_tex)
#define T_tex (swarf_tex.f_T_tex)
#define tool_particle_tex (swarf_tex.f_tool_particle_tex)
#define hashes_tex (swarf_tex.f_hashes_tex)
#define pos_to_tex (swarf_tex.f_pos_to_tex)
#define h_to_tex (swarf_tex.f_h_to_tex)
#define T_to_tex (swarf_tex.f_T_to_tex)
#define hashes_to_tex (swarf_tex.f_hashes_to_tex)
#define cells_start_tex (swarf_tex.f_cells_start_tex)
#define cells_end_tex (swarf_tex.f_cells_end_tex)

// __ldg has overloads for the scalar and 2-vector types; a double4 is read as two aligned double2.
template <class T> __device__ __forceinline__ T swarf_ldg(const T *p) {
    return __ldg(p);
}
__device__ __forceinline__ double4 swarf_ldg(const double4 *p) {
    const double2 *q = reinterpret_cast<const double2 *>(p);
    double2 a = __ldg(q), b = __ldg(q + 1);
    return make_double4(a.x, a.y, b.x, b.y);
}

#undef texfetch1
#undef texfetch2
#undef texfetch4
#define texfetch1(t, i) swarf_ldg((t) + (i))
#define texfetch2(t, i) swarf_ldg((t) + (i))
#define texfetch4(t, i) swarf_ldg((t) + (i))

#endif

/* tests/test_cl_texture.c: every bin of every level of each texel. */
#include "texture.clh"

__kernel void texel_bins(__global const float4 *texels, int level, __global float *out)
{
    int i = get_global_id(0), bins = SPM_LEVEL_BINS(level);
    float4 t = texels[i];
    for (int b = 0; b < bins; b++)
        out[i * bins + b] = spm_texel_bin(t.xyz, t.w, level, b);
}

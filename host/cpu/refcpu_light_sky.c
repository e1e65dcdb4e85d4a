/* The CPU reference's background kind (kernels/light_sky.clh): two colours
 * by hemisphere, met by escaping rays only, never sampled. */
#include "refcpu_lights.h"

spm_u32 spm_ref_light_background(const spm_trace_params *p, const float d[3])
{
    return d[1] > 0.0f ? p->bg_up : p->bg_down; /* MiniLight: sky for an upward ray */
}

int spm_ref_light_sample_SKY(const spm_geometry *g, const spm_material *mats, const spm_emitter *e,
                             const spm_ref_key *k, spm_u32 dim, const float x[3], spm_u32 hit,
                             const spm_ref_hit *h, spm_ref_lsample *ls)
{
    (void)g, (void)mats, (void)e, (void)k, (void)dim, (void)x, (void)hit, (void)h, (void)ls;
    return 0;
}

void spm_ref_light_sample_emission_SKY(const spm_geometry *g, const spm_emitter *e,
                                       const float u[4], float o[3], float d[3], float *pdf_pos,
                                       float *pdf_dir)
{
    (void)g, (void)e, (void)u, (void)o, (void)d;
    *pdf_pos = *pdf_dir = 0.0f;
}

void spm_ref_light_pdf_emission_SKY(const spm_geometry *g, const spm_emitter *e, const float o[3],
                                    const float d[3], float *pdf_pos, float *pdf_dir)
{
    (void)g, (void)e, (void)o, (void)d;
    *pdf_pos = *pdf_dir = 0.0f;
}

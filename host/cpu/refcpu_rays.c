/* Where the reference's rays go when a caller records them (refcpu.h
 * spm_ref_rays: the traversal benchmark replays a render's rays): the path
 * loop's rays and the light kinds' shadow rays alike, so the light files and
 * the loop both call down to this file rather than into each other. */
#include "refcpu.h"
#include "refcpu_lights.h"

_Thread_local spm_ref_ray_sink spm_ref_rays;

void spm_ref_record_ray(const float o[3], const float d[3], spm_u32 skip, spm_u32 emitter)
{
    if (!spm_ref_rays.fn)
        return;
    spm_ray r = {{o[0], o[1], o[2]}, skip, {d[0], d[1], d[2]}, emitter};
    spm_ref_rays.fn(spm_ref_rays.ctx, &r);
}

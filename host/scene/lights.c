/* The light kinds' descriptors (lights.h), from include/spm_lights.h. */
#include "lights.h"
#include <math.h>
#include <stdio.h>
#include <string.h>
#include "colour.h"

#define SPM_LIGHT_KIND(name, ...) [SPM_LIGHT_##name] = {.tag = SPM_LIGHT_##name, __VA_ARGS__},
const spm_light_desc spm_light_kinds[] = {
#include "spm_lights.h"
};
#undef SPM_LIGHT_KIND
const int spm_nlight_kinds = (int)(sizeof spm_light_kinds / sizeof spm_light_kinds[0]);

const spm_light_desc *spm_light_kind_find(const char *kw)
{
    for (int i = 0; i < spm_nlight_kinds; i++)
        if (spm_light_kinds[i].keyword && !strcmp(spm_light_kinds[i].keyword, kw))
            return &spm_light_kinds[i];
    return NULL;
}

int spm_light_defines(const spm_emitter *em, int n, char *buf, size_t size)
{
    int used[SPM_LIGHT_NKINDS] = {0}, len = 0;
    for (int i = 0; i < n; i++)
        if (em[i].kind < SPM_LIGHT_NKINDS)
            used[em[i].kind] = 1;
    buf[0] = '\0';
    for (int k = 0; k < spm_nlight_kinds; k++)
        if (used[k] && spm_light_kinds[k].define && len < (int)size)
            len += snprintf(buf + len, size - (size_t)len, "-D%s ", spm_light_kinds[k].define);
    return len;
}

double spm_light_power(const spm_scene *sc, const spm_scene_light *l)
{
    double xyz[3];
    spm_xyz_emission(&sc->colours[l->colour].s, xyz);
    double y = xyz[1] > 0.0 ? xyz[1] : 0.0;
    return y * (double)l->p[SPM_LIGHT_P_SCALE] * spm_light_kinds[l->kind].solid / M_PI;
}

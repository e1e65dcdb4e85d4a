#include "backends.h"
#include <string.h>
#include "backend_cpu.h"
#include "backend_cl.h"

const spm_backend_kind *const spm_backend_kinds[] = {&spm_backend_kind_opencl,
                                                     &spm_backend_kind_cpu, NULL};

const spm_backend_kind *spm_backend_kind_find(const char *name)
{
    for (int i = 0; spm_backend_kinds[i]; i++)
        if (!strcmp(spm_backend_kinds[i]->name, name))
            return spm_backend_kinds[i];
    return NULL;
}

void spm_render_config_defaults(spm_render_config *c)
{
    memset(c, 0, sizeof *c);
    c->backend = spm_backend_kinds[0];
    c->mode = SPM_MODE_ML;
    c->seed = 1;
    spm_pretest_defaults(&c->pretest);
}

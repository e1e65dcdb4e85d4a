/* The composition root of a render: the kinds of backend there are, above
 * run/, opencl/ and cpu/, so that run/ knows only the backend interface
 * (backend.h) and neither backend knows the other. */
#ifndef SPM_BACKENDS_H
#define SPM_BACKENDS_H
#include "render_setup.h"

/* Every kind, the default first; NULL-terminated. */
extern const spm_backend_kind *const spm_backend_kinds[];
/* The kind named `name` (--backend), or NULL. */
const spm_backend_kind *spm_backend_kind_find(const char *name);
/* A render's defaults: the first kind (OpenCL), mode ml, seed 1, the pretest's
 * defaults. */
void spm_render_config_defaults(spm_render_config *c);
#endif

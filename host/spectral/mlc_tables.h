/* Composite Model tables (mlc mode): smooth parts at every level plus the
 * scene's spike lanes. Part of spm_tables_build. */
#ifndef SPM_MLC_TABLES_H
#define SPM_MLC_TABLES_H
#include "tables.h"
/* Fills the mlc_* arrays, which spm_tables_alloc made; mlc_pretest and
 * mlc_lvlk only with `levels` (spm_tables_levels). */
int spm_mlc_tables_build(const spm_scene *sc, const spm_pretest_opts *po, spm_tables *t,
                         int levels, spm_error *err);
#endif

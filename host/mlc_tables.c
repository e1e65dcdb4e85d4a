/* Composite Model tables. Until spike detection is wired in, every spectrum
 * is its own smooth part and the scene has no spike lanes (mlc == ml). */
#include "mlc_tables.h"
#include <string.h>

int spm_mlc_tables_build(const spm_scene *sc, const spm_pretest_opts *po, spm_tables *t,
                         spm_error *err)
{
    (void)po;
    (void)err;
    int n = sc->ncolours;
    t->nspikes = 0;
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        int nb = SPM_LEVEL_BINS(l);
        t->mlc_lvl[l] = spm_xcalloc((size_t)n * SPM_MLC_STRIDE(l) + 1, sizeof(float));
        for (int c = 0; c < n; c++)
            memcpy(&t->mlc_lvl[l][(size_t)c * SPM_MLC_STRIDE(l)], &t->lvl[l][(size_t)c * nb],
                   (size_t)nb * sizeof(float));
    }
    t->mlc_lvlk = spm_xcalloc((size_t)n * SPM_PRETEST_KMAX + 1, 1);
    memcpy(t->mlc_lvlk, t->lvlk, (size_t)n * SPM_PRETEST_KMAX);
    return 0;
}

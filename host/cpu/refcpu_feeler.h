/* The CPU reference's level feeler, which both integrators' trace stages
 * run over the colours a path meets (refcpu.h: the order of the feel). */
#ifndef SPM_REFCPU_FEELER_H
#define SPM_REFCPU_FEELER_H
#include <stdint.h>
#include "spm_shared.h"

/* The level feeler: the finest (smallest) level among the colours met,
 * starting from the coarsest level in use; a colour lowers it only when
 * strictly finer, so "set by" names the first colour that needed it. */
typedef struct {
    int level;
    spm_u32 setby;
} feeler;

static inline void feel(feeler *f, const uint8_t *lvlk, spm_u32 colour, int k, spm_u32 who)
{
    if (!lvlk)
        return;
    int kk = k < SPM_PRETEST_KMAX ? k : SPM_PRETEST_KMAX;
    int l = lvlk[colour * SPM_PRETEST_KMAX + (spm_u32)(kk - 1)];
    if (l < f->level)
        f->level = l, f->setby = who;
}

/* Occurrences of reflectance colour r among vertices 0..j of the record. */
static inline int occurrences(const spm_path *path, int j, spm_u32 r)
{
    int k = 0;
    for (int i = 0; i <= j; i++)
        k += (path->v[i].ids & 0xFFFFu) == r;
    return k;
}

#endif

/* The quantised wide BVH (include/spm_bvhq.h, bvh_quant.h): every wide node
 * again, its children's boxes as 8-bit codes in a frame per node, rounded
 * outward on the float values the kernel computes. */
#include "bvh_quant.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

_Static_assert(sizeof(spm_bvhq_node) == 64, "a quantised node is one 64-byte cache line");

int spm_bvhq_axis(float lo, float hi, float *origin, float *scale)
{
    /* 2^e >= (hi - lo) / 255 in exact arithmetic; the check below on the
     * float face settles what the rounding of hi - lo left open */
    double ext = (double)hi - (double)lo;
    int e = -149;
    if (ext > 0.0) {
        frexp(ext / 255.0, &e);
        e = e < -149 ? -149 : e;
    }
    for (; e <= 120; e++) {
        float s = ldexpf(1.0f, e);
        if (spm_bvhq_face(lo, s, 255) >= hi) {
            *origin = lo;
            *scale = s;
            return 0;
        }
    }
    return 1;
}

void spm_bvhq_codes(float origin, float scale, float lo, float hi, unsigned char *qlo,
                    unsigned char *qhi)
{
    /* the estimates in double, then each moved until its float face is on
     * the outer side: face(0) = origin <= lo and face(255) >= hi end both */
    double a = floor(((double)lo - origin) / scale), b = ceil(((double)hi - origin) / scale);
    unsigned l = a < 0 ? 0u : a > 255 ? 255u : (unsigned)a;
    unsigned h = b < 0 ? 0u : b > 255 ? 255u : (unsigned)b;
    while (l > 0 && spm_bvhq_face(origin, scale, l) > lo)
        l--;
    while (l < 255 && spm_bvhq_face(origin, scale, l + 1) <= lo)
        l++;
    while (h < 255 && spm_bvhq_face(origin, scale, h) < hi)
        h++;
    while (h > 0 && spm_bvhq_face(origin, scale, h - 1) >= hi)
        h--;
    *qlo = (unsigned char)l;
    *qhi = (unsigned char)h;
}

/* One wide node as a quantised one (its child slots mapped by the caller). */
static int quantise(const spm_bvh4_node *w, spm_bvhq_node *q)
{
    const float *lo[3] = {w->bmin_x, w->bmin_y, w->bmin_z};
    const float *hi[3] = {w->bmax_x, w->bmax_y, w->bmax_z};
    unsigned char *qlo[3] = {q->qlo_x, q->qlo_y, q->qlo_z};
    unsigned char *qhi[3] = {q->qhi_x, q->qhi_y, q->qhi_z};
    memset(q, 0, sizeof *q);
    for (int a = 0; a < 3; a++) {
        float l = INFINITY, h = -INFINITY;
        for (int i = 0; i < SPM_WIDE; i++)
            if (w->child[i] != SPM_WIDE_EMPTY) {
                l = lo[a][i] < l ? lo[a][i] : l;
                h = hi[a][i] > h ? hi[a][i] : h;
            }
        if (l > h) /* no child: never read */
            l = h = 0.0f;
        if (spm_bvhq_axis(l, h, &q->origin[a], &q->scale[a]))
            return 1;
        for (int i = 0; i < SPM_WIDE; i++)
            if (w->child[i] != SPM_WIDE_EMPTY)
                spm_bvhq_codes(q->origin[a], q->scale[a], lo[a][i], hi[a][i], &qlo[a][i],
                               &qhi[a][i]);
    }
    return 0;
}

int spm_bvhq_build(const spm_geometry *g, spm_bvhq_node **out, size_t *nslots, spm_error *err)
{
    *out = NULL;
    *nslots = 0;
    if (g->nwide == 0)
        return 0;
    /* the planes' slots, in the wide tree's 112 bytes and in 64 here */
    size_t pbytes = SPM_LEAF_PLANES_FLOATS((size_t)g->ntris) * sizeof(float);
    spm_u32 wp = (spm_u32)((pbytes + sizeof(spm_bvh4_node) - 1) / sizeof(spm_bvh4_node));
    spm_u32 qp = (spm_u32)((pbytes + sizeof(spm_bvhq_node) - 1) / sizeof(spm_bvhq_node));
    size_t n = 1 + qp + ((size_t)g->nwide - 1 - wp);
    spm_bvhq_node *q = spm_xmalloc(n * sizeof *q);
    memset(&q[1], 0, (size_t)qp * sizeof *q);
    memcpy(&q[1], &g->wide[1], pbytes);
    for (spm_u32 k = 0; k < (spm_u32)g->nwide; k = k ? k + 1 : 1 + wp) {
        spm_bvhq_node *o = &q[k ? k - wp + qp : 0];
        if (quantise(&g->wide[k], o)) {
            free(q);
            spm_errorf(err, "a BVH box too large to quantise (an extent beyond 2^127)");
            return 1;
        }
        for (int i = 0; i < SPM_WIDE; i++) {
            spm_u32 c = g->wide[k].child[i];
            o->child[i] = (c == SPM_WIDE_EMPTY || (c & SPM_WIDE_LEAF)) ? c : c - wp + qp;
        }
    }
    *out = q;
    *nslots = n;
    return 0;
}

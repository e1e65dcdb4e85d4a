/* The BVH builder as it was before it ran on several threads: serial,
 * binned SAH over an index array, qsort object medians. The tests compare the
 * parallel builder with it; with sah_max_depth 0 it is a plain object-median
 * builder, a baseline any SAH build must beat. */
#ifndef BVH_REFERENCE_H
#define BVH_REFERENCE_H
#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "geometry.h"
#include "interrupt.h"

#define NBINS 12
#define LEAF_MAX 2
#define BOX_PAD_REL 1e-5f

typedef struct {
    float lo[3], hi[3];
} ref_box;

typedef struct {
    ref_box b;
    float c[3]; /* centroid of the ref_box */
} ref_prim;

typedef struct {
    int node, begin, end, depth;
} ref_job;

static void ref_box_empty(ref_box *b)
{
    for (int i = 0; i < 3; i++)
        b->lo[i] = FLT_MAX, b->hi[i] = -FLT_MAX;
}

static void ref_box_add(ref_box *b, const ref_box *a)
{
    for (int i = 0; i < 3; i++) {
        b->lo[i] = fminf(b->lo[i], a->lo[i]);
        b->hi[i] = fmaxf(b->hi[i], a->hi[i]);
    }
}

static float ref_box_area(const ref_box *b)
{
    float d[3];
    for (int i = 0; i < 3; i++)
        d[i] = b->hi[i] > b->lo[i] ? b->hi[i] - b->lo[i] : 0.0f;
    return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

/* The ref_box of the triangle's three vertices. */
static void ref_tri_prim(const spm_tri *t, ref_prim *p)
{
    for (int i = 0; i < 3; i++) {
        float a = t->v0[i], b = t->v1[i], c = t->v2[i];
        p->b.lo[i] = fminf(a, fminf(b, c));
        p->b.hi[i] = fmaxf(a, fmaxf(b, c));
        p->c[i] = 0.5f * (p->b.lo[i] + p->b.hi[i]);
    }
}

typedef struct {
    int axis, split; /* left side: bins [0, split) on axis; axis -1: no SAH split */
} ref_sah_split;

static int ref_bin_of(float c, float lo, float scale)
{
    int b = (int)((c - lo) * scale);
    return b < 0 ? 0 : (b >= NBINS ? NBINS - 1 : b);
}

/* Cheapest binned SAH split of idx[begin, end) over all three axes. */
static ref_sah_split ref_find_sah(const ref_prim *pr, const int *idx, int begin, int end, const ref_box *cb)
{
    ref_sah_split best = {-1, 0};
    float best_cost = FLT_MAX;
    for (int axis = 0; axis < 3; axis++) {
        float ext = cb->hi[axis] - cb->lo[axis];
        if (!(ext > 0.0f))
            continue;
        float scale = NBINS / ext;
        ref_box bb[NBINS];
        int cnt[NBINS] = {0};
        for (int b = 0; b < NBINS; b++)
            ref_box_empty(&bb[b]);
        for (int i = begin; i < end; i++) {
            const ref_prim *p = &pr[idx[i]];
            int b = ref_bin_of(p->c[axis], cb->lo[axis], scale);
            cnt[b]++;
            ref_box_add(&bb[b], &p->b);
        }
        /* right-to-left sweep stores the right side's area*count per split */
        float right_cost[NBINS];
        ref_box acc;
        ref_box_empty(&acc);
        int n = 0;
        for (int s = NBINS - 1; s > 0; s--) {
            ref_box_add(&acc, &bb[s]);
            n += cnt[s];
            right_cost[s] = n ? ref_box_area(&acc) * (float)n : 0.0f;
        }
        ref_box_empty(&acc);
        n = 0;
        for (int s = 1; s < NBINS; s++) {
            ref_box_add(&acc, &bb[s - 1]);
            n += cnt[s - 1];
            int nr = end - begin - n;
            if (n == 0 || nr == 0)
                continue;
            float cost = ref_box_area(&acc) * (float)n + right_cost[s];
            if (cost < best_cost)
                best_cost = cost, best.axis = axis, best.split = s;
        }
    }
    return best;
}

static const ref_prim *ref_sort_prims;
static int ref_sort_axis;
static int ref_cmp_centroid(const void *a, const void *b)
{
    float ca = ref_sort_prims[*(const int *)a].c[ref_sort_axis], cb = ref_sort_prims[*(const int *)b].c[ref_sort_axis];
    return (ca > cb) - (ca < cb);
}

/* Partition idx[begin, end) and return the first index of the right side. */
static int ref_split_range(const ref_prim *pr, int *idx, int begin, int end, const ref_box *cb, int depth,
                           int sah_max_depth)
{
    ref_sah_split s = {-1, 0};
    if (depth < sah_max_depth)
        s = ref_find_sah(pr, idx, begin, end, cb);
    if (s.axis >= 0) {
        float scale = NBINS / (cb->hi[s.axis] - cb->lo[s.axis]);
        int i = begin, j = end - 1;
        while (i <= j) {
            if (ref_bin_of(pr[idx[i]].c[s.axis], cb->lo[s.axis], scale) < s.split) {
                i++;
            } else {
                int tmp = idx[i];
                idx[i] = idx[j], idx[j--] = tmp;
            }
        }
        if (i > begin && i < end)
            return i;
    }
    /* object median along the widest centroid axis (also when all coincide) */
    int axis = 0;
    for (int a = 1; a < 3; a++)
        if (cb->hi[a] - cb->lo[a] > cb->hi[axis] - cb->lo[axis])
            axis = a;
    ref_sort_prims = pr, ref_sort_axis = axis;
    qsort(idx + begin, (size_t)(end - begin), sizeof *idx, ref_cmp_centroid);
    return begin + (end - begin) / 2;
}

static float ref_box_magnitude(const float lo[3], const float hi[3])
{
    float m = 0.0f;
    for (int i = 0; i < 3; i++)
        m = fmaxf(m, fmaxf(fabsf(lo[i]), fabsf(hi[i])));
    return m;
}

/* The slab test and the triangle test round relative to the magnitudes of the
 * coordinates they subtract: the node's and the ray origin's. Rays start at
 * the eye or on a surface, so each node grows by BOX_PAD_REL times the larger
 * of its own largest |coordinate| (rays from surfaces near it) and the eye's
 * (camera rays). Per node, so a far-away emitter (a sun 1.5e11 away) pads its
 * own boxes by its own scale and leaves the room's boxes tight; a padding by
 * the scene's largest coordinate would let every ray into every node. */
static void ref_pad_boxes(spm_bvh_node *nodes, int nnodes, const float eye[3])
{
    float eye_mag = ref_box_magnitude(eye, eye);
    for (int k = 0; k < nnodes; k++) {
        float pad = BOX_PAD_REL * fmaxf(ref_box_magnitude(nodes[k].bmin, nodes[k].bmax), eye_mag) +
                    FLT_MIN;
        for (int i = 0; i < 3; i++)
            nodes[k].bmin[i] -= pad, nodes[k].bmax[i] += pad;
    }
}

static int ref_bvh_build(spm_geometry *g, int sah_max_depth, spm_error *err)
{
    int n = g->ntris;
    g->nodes = NULL;
    g->nnodes = 0;
    g->bvh = (spm_bvh_stats){0, 0.0, 0};
    if (n == 0)
        return 0;
    ref_prim *pr = spm_xmalloc((size_t)n * sizeof *pr);
    int *idx = spm_xmalloc((size_t)n * sizeof *idx);
    for (int i = 0; i < n; i++) {
        ref_tri_prim(&g->tris[i], &pr[i]);
        idx[i] = i;
    }
    spm_bvh_node *nodes = spm_xcalloc((size_t)2 * n, sizeof *nodes);
    ref_job *stack = spm_xmalloc((size_t)2 * n * sizeof *stack);
    int nnodes = 1, top = 0, fail = 0;
    stack[top++] = (ref_job){0, 0, n, 0};
    while (top > 0) {
        spm_test_pause("bvh");
        if (spm_stop_requested()) {
            fail = 2;
            break;
        }
        ref_job j = stack[--top];
        ref_box b, cb;
        ref_box_empty(&b);
        ref_box_empty(&cb);
        for (int i = j.begin; i < j.end; i++) {
            ref_box_add(&b, &pr[idx[i]].b);
            ref_box c = {{pr[idx[i]].c[0], pr[idx[i]].c[1], pr[idx[i]].c[2]},
                     {pr[idx[i]].c[0], pr[idx[i]].c[1], pr[idx[i]].c[2]}};
            ref_box_add(&cb, &c);
        }
        spm_bvh_node *nd = &nodes[j.node];
        memcpy(nd->bmin, b.lo, sizeof nd->bmin);
        memcpy(nd->bmax, b.hi, sizeof nd->bmax);
        if (j.depth >= SPM_BVH_STACK - 1) {
            fail = 1;
            break;
        }
        if (j.end - j.begin <= LEAF_MAX) {
            nd->first = (spm_u32)j.begin;
            nd->count = (spm_u32)(j.end - j.begin);
            continue;
        }
        int mid = ref_split_range(pr, idx, j.begin, j.end, &cb, j.depth, sah_max_depth);
        nd->first = (spm_u32)nnodes;
        nd->count = 0;
        stack[top++] = (ref_job){nnodes + 1, mid, j.end, j.depth + 1};
        stack[top++] = (ref_job){nnodes, j.begin, mid, j.depth + 1};
        nnodes += 2;
    }
    free(stack);
    free(pr);
    if (fail) {
        free(idx);
        free(nodes);
        if (fail == 2)
            spm_errorf(err, "interrupted while building the BVH (%d triangles)", n);
        else
            spm_errorf(err, "BVH deeper than %d levels (%d triangles)", SPM_BVH_STACK, n);
        return 1;
    }
    spm_tri *sorted = spm_xmalloc((size_t)n * sizeof *sorted);
    for (int i = 0; i < n; i++)
        sorted[i] = g->tris[idx[i]];
    memcpy(g->tris, sorted, (size_t)n * sizeof *sorted);
    free(sorted);
    free(idx);
    g->bvh.sah_cost = spm_bvh_sah_cost(nodes, nnodes, &g->bvh.leaves);
    ref_pad_boxes(nodes, nnodes, g->cam.eye);
    g->nodes = nodes;
    g->nnodes = nnodes;
    return 0;
}
#endif

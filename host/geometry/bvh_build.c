/* Binned-SAH BVH build: flattened nodes (children of an interior node are
 * adjacent) and the triangles reordered into leaf order.
 *
 * Parallel and deterministic: a node's split depends only on the triangles
 * of its range, and each range is partitioned in place by one thread, so the
 * leaf order and every box are those of a serial build whatever the thread
 * timing. Subtrees of at least TASK_MIN triangles become tasks for the other
 * threads; their nodes are allocated in whatever order the threads reach them
 * and then renumbered in the serial builder's order (renumber). */
#define _GNU_SOURCE /* qsort_r */
#include "geometry.h"
#include <float.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "interrupt.h"

#define NBINS 12
#define LEAF_MAX 2 /* 2: a wall quad gets its own flat box; measured 17% less trace time than 4 */
/* Below this depth SAH decides; deeper, object-median splits bound the depth
 * by 32 + log2(n) whatever the geometry. */
#define SAH_MAX_DEPTH 32
/* Node boxes grow by this fraction of a coordinate magnitude (pad_boxes), far
 * above float rounding in the slab test and the hit point (about 1e-7). */
#define BOX_PAD_REL 1e-5f
/* A subtree this large is worth handing to another thread; below it the
 * queue's lock would cost more than the work. */
#define TASK_MIN 4096
/* Fewer triangles than this build on the calling thread alone. */
#define PARALLEL_MIN 16384
#define MAX_THREADS 16

typedef struct {
    float lo[3], hi[3];
} box;

typedef struct {
    box b;
    float c[3]; /* centroid of the box */
    int id;     /* the triangle's index before the build */
} prim;

typedef struct {
    int node, begin, end, depth;
    box b, cb; /* the range's bounds and centroid bounds */
} job;

/* Plain comparisons rather than fminf/fmaxf (a call each): boxes hold no NaN. */
static inline float mn(float a, float b) { return a < b ? a : b; }
static inline float mx(float a, float b) { return a > b ? a : b; }

static void box_empty(box *b)
{
    for (int i = 0; i < 3; i++)
        b->lo[i] = FLT_MAX, b->hi[i] = -FLT_MAX;
}

static inline void box_add(box *b, const box *a)
{
    for (int i = 0; i < 3; i++) {
        b->lo[i] = mn(b->lo[i], a->lo[i]);
        b->hi[i] = mx(b->hi[i], a->hi[i]);
    }
}

static inline void box_add_point(box *b, const float c[3])
{
    for (int i = 0; i < 3; i++) {
        b->lo[i] = mn(b->lo[i], c[i]);
        b->hi[i] = mx(b->hi[i], c[i]);
    }
}

static float box_area(const box *b)
{
    float d[3];
    for (int i = 0; i < 3; i++)
        d[i] = b->hi[i] > b->lo[i] ? b->hi[i] - b->lo[i] : 0.0f;
    return 2.0f * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
}

/* The box of the triangle's three vertices. */
static void tri_prim(const spm_tri *t, prim *p)
{
    for (int i = 0; i < 3; i++) {
        float a = t->v0[i], b = t->v1[i], c = t->v2[i];
        p->b.lo[i] = mn(a, mn(b, c));
        p->b.hi[i] = mx(a, mx(b, c));
        p->c[i] = 0.5f * (p->b.lo[i] + p->b.hi[i]);
    }
}

typedef struct {
    int axis, split; /* left side: bins [0, split) on axis; axis -1: no SAH split */
} sah_split;

static inline int bin_of(float c, float lo, float scale)
{
    int b = (int)((c - lo) * scale);
    return b < 0 ? 0 : (b >= NBINS ? NBINS - 1 : b);
}

/* Cheapest binned SAH split of pr[begin, end) over all three axes, binned in
 * one pass. Bin contents (min, max, counts) do not depend on the order the
 * triangles are visited in, so the costs are those of binning axis by axis. */
static sah_split find_sah(const prim *pr, int begin, int end, const box *cb)
{
    sah_split best = {-1, 0};
    float best_cost = FLT_MAX, scale[3];
    int use[3];
    box bb[3][NBINS];
    int cnt[3][NBINS];
    for (int axis = 0; axis < 3; axis++) {
        float ext = cb->hi[axis] - cb->lo[axis];
        use[axis] = ext > 0.0f;
        scale[axis] = use[axis] ? NBINS / ext : 0.0f;
        for (int b = 0; b < NBINS; b++)
            box_empty(&bb[axis][b]), cnt[axis][b] = 0;
    }
    for (int i = begin; i < end; i++) {
        const prim *p = &pr[i];
        for (int axis = 0; axis < 3; axis++) {
            int b = bin_of(p->c[axis], cb->lo[axis], scale[axis]);
            cnt[axis][b]++;
            box_add(&bb[axis][b], &p->b);
        }
    }
    for (int axis = 0; axis < 3; axis++) {
        if (!use[axis])
            continue;
        /* right-to-left sweep stores the right side's area*count per split */
        float right_cost[NBINS];
        box acc;
        box_empty(&acc);
        int n = 0;
        for (int s = NBINS - 1; s > 0; s--) {
            box_add(&acc, &bb[axis][s]);
            n += cnt[axis][s];
            right_cost[s] = n ? box_area(&acc) * (float)n : 0.0f;
        }
        box_empty(&acc);
        n = 0;
        for (int s = 1; s < NBINS; s++) {
            box_add(&acc, &bb[axis][s - 1]);
            n += cnt[axis][s - 1];
            int nr = end - begin - n;
            if (n == 0 || nr == 0)
                continue;
            float cost = box_area(&acc) * (float)n + right_cost[s];
            if (cost < best_cost)
                best_cost = cost, best.axis = axis, best.split = s;
        }
    }
    return best;
}

static int cmp_centroid(const void *a, const void *b, void *axis)
{
    float ca = ((const prim *)a)->c[*(int *)axis], cb = ((const prim *)b)->c[*(int *)axis];
    return (ca > cb) - (ca < cb);
}

static void range_bounds(const prim *pr, int begin, int end, box *b, box *cb)
{
    box_empty(b);
    box_empty(cb);
    for (int i = begin; i < end; i++) {
        box_add(b, &pr[i].b);
        box_add_point(cb, pr[i].c);
    }
}

/* Partitions pr[j->begin, j->end) and fills the two children's jobs (ranges
 * and bounds; node and depth are the caller's). */
static void split_range(prim *pr, const job *j, job *l, job *r)
{
    int begin = j->begin, end = j->end, mid = -1;
    sah_split s = {-1, 0};
    if (j->depth < SAH_MAX_DEPTH)
        s = find_sah(pr, begin, end, &j->cb);
    if (s.axis >= 0) {
        int ax = s.axis;
        float lo = j->cb.lo[ax], scale = NBINS / (j->cb.hi[ax] - j->cb.lo[ax]);
        box_empty(&l->b), box_empty(&l->cb), box_empty(&r->b), box_empty(&r->cb);
        /* every triangle is classified once: kept on the left, or swapped to the right */
        int i = begin, k = end - 1;
        while (i <= k) {
            if (bin_of(pr[i].c[ax], lo, scale) < s.split) {
                box_add(&l->b, &pr[i].b), box_add_point(&l->cb, pr[i].c);
                i++;
            } else {
                prim tmp = pr[i];
                pr[i] = pr[k], pr[k--] = tmp;
                box_add(&r->b, &tmp.b), box_add_point(&r->cb, tmp.c);
            }
        }
        if (i > begin && i < end)
            mid = i;
    }
    if (mid < 0) {
        /* object median along the widest centroid axis (also when all coincide);
         * glibc's qsort_r is a merge sort here: stable, so ties keep their order */
        int axis = 0;
        for (int a = 1; a < 3; a++)
            if (j->cb.hi[a] - j->cb.lo[a] > j->cb.hi[axis] - j->cb.lo[axis])
                axis = a;
        qsort_r(pr + begin, (size_t)(end - begin), sizeof *pr, cmp_centroid, &axis);
        mid = begin + (end - begin) / 2;
        range_bounds(pr, begin, mid, &l->b, &l->cb);
        range_bounds(pr, mid, end, &r->b, &r->cb);
    }
    l->begin = begin, l->end = mid;
    r->begin = mid, r->end = end;
}

typedef struct {
    prim *pr;
    spm_bvh_node *nodes; /* in allocation order; renumber puts them in serial order */
    atomic_int next;     /* the next free node */
    atomic_int fail;     /* 1: too deep, 2: interrupted */
    int nthreads;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    job *queue;
    int nq, capq, active;
} build_ctx;

static void push_task(build_ctx *x, const job *j)
{
    pthread_mutex_lock(&x->mu);
    if (x->nq == x->capq) {
        x->capq = x->capq ? 2 * x->capq : 64;
        x->queue = spm_xrealloc(x->queue, (size_t)x->capq * sizeof *x->queue);
    }
    x->queue[x->nq++] = *j;
    pthread_cond_signal(&x->cv);
    pthread_mutex_unlock(&x->mu);
}

static void build_node(build_ctx *x, job j)
{
    for (;;) {
        spm_test_pause("bvh");
        if (spm_stop_requested()) {
            atomic_store(&x->fail, 2);
            return;
        }
        if (atomic_load_explicit(&x->fail, memory_order_relaxed))
            return;
        spm_bvh_node *nd = &x->nodes[j.node];
        memcpy(nd->bmin, j.b.lo, sizeof nd->bmin);
        memcpy(nd->bmax, j.b.hi, sizeof nd->bmax);
        if (j.depth >= SPM_BVH_STACK - 1) {
            atomic_store(&x->fail, 1);
            return;
        }
        if (j.end - j.begin <= LEAF_MAX) {
            nd->first = (spm_u32)j.begin;
            nd->count = (spm_u32)(j.end - j.begin);
            return;
        }
        job l, r;
        split_range(x->pr, &j, &l, &r);
        int c = atomic_fetch_add_explicit(&x->next, 2, memory_order_relaxed);
        nd->first = (spm_u32)c;
        nd->count = 0;
        l.node = c, r.node = c + 1;
        l.depth = r.depth = j.depth + 1;
        if (x->nthreads > 1 && r.end - r.begin >= TASK_MIN)
            push_task(x, &r);
        else
            build_node(x, r);
        j = l; /* the left child on this thread, without another stack frame */
    }
}

static void *worker(void *arg)
{
    build_ctx *x = arg;
    pthread_mutex_lock(&x->mu);
    for (;;) {
        while (x->nq == 0 && x->active > 0)
            pthread_cond_wait(&x->cv, &x->mu);
        if (x->nq == 0)
            break; /* nothing queued and nobody working: the tree is done */
        job j = x->queue[--x->nq];
        x->active++;
        pthread_mutex_unlock(&x->mu);
        build_node(x, j);
        pthread_mutex_lock(&x->mu);
        if (--x->active == 0 && x->nq == 0)
            pthread_cond_broadcast(&x->cv);
    }
    pthread_mutex_unlock(&x->mu);
    return NULL;
}

typedef struct {
    const spm_tri *tris;
    prim *pr;
    int begin, end;
    box b, cb;
} prim_chunk;

static void *make_prims(void *arg)
{
    prim_chunk *c = arg;
    box_empty(&c->b);
    box_empty(&c->cb);
    for (int i = c->begin; i < c->end; i++) {
        tri_prim(&c->tris[i], &c->pr[i]);
        c->pr[i].id = i;
        box_add(&c->b, &c->pr[i].b);
        box_add_point(&c->cb, c->pr[i].c);
    }
    return NULL;
}

/* Copies the tree into out[] numbered as a serial depth-first build numbers
 * it (children allocated when their parent is taken from a stack, left taken
 * first), so the node array does not depend on which thread built what. */
static void renumber(const spm_bvh_node *in, spm_bvh_node *out)
{
    int stack[2 * SPM_BVH_STACK][2], top = 0, nn = 1;
    stack[top][0] = 0, stack[top++][1] = 0;
    while (top > 0) {
        top--;
        int t = stack[top][0], k = stack[top][1];
        out[k] = in[t];
        if (in[t].count == 0) {
            int c = (int)in[t].first;
            out[k].first = (spm_u32)nn;
            stack[top][0] = c + 1, stack[top++][1] = nn + 1;
            stack[top][0] = c, stack[top++][1] = nn;
            nn += 2;
        }
    }
}

/* Puts tris into the order perm gives (tris[i] = old tris[perm[i]]) in place,
 * cycle by cycle; perm is used up. */
static void permute_tris(spm_tri *tris, int *perm, int n)
{
    for (int i = 0; i < n; i++) {
        if (perm[i] < 0)
            continue;
        spm_tri first = tris[i];
        int k = i;
        while (perm[k] != i) {
            int from = perm[k];
            tris[k] = tris[from];
            perm[k] = -1;
            k = from;
        }
        tris[k] = first;
        perm[k] = -1;
    }
}

static float box_magnitude(const float lo[3], const float hi[3])
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
static void pad_boxes(spm_bvh_node *nodes, int nnodes, const float eye[3])
{
    float eye_mag = box_magnitude(eye, eye);
    for (int k = 0; k < nnodes; k++) {
        /* relative, so it scales with the scene; FLT_MIN only keeps a box of
         * the coordinates 0 (and an eye at 0) from staying flat: it is below
         * half an ulp of the first term whenever that term exceeds 2e-31, so
         * it changes no box with a coordinate above 2e-26 */
        float pad = BOX_PAD_REL * fmaxf(box_magnitude(nodes[k].bmin, nodes[k].bmax), eye_mag) +
                    FLT_MIN;
        for (int i = 0; i < 3; i++)
            nodes[k].bmin[i] -= pad, nodes[k].bmax[i] += pad;
    }
}

int spm_bvh_default_threads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : (n > MAX_THREADS ? MAX_THREADS : (int)n);
}

int spm_bvh_build_threads(spm_geometry *g, int nthreads, spm_error *err)
{
    int n = g->ntris;
    g->nodes = NULL;
    g->nnodes = 0;
    g->bvh = (spm_bvh_stats){0, 0.0, 0};
    if (n == 0)
        return 0;
    if (nthreads < 1 || n < PARALLEL_MIN)
        nthreads = 1;
    if (nthreads > MAX_THREADS)
        nthreads = MAX_THREADS;
    build_ctx x;
    memset(&x, 0, sizeof x);
    x.pr = spm_xmalloc((size_t)n * sizeof *x.pr);
    /* at most 2n - 1 nodes (leaves hold at least one triangle); the pages of
     * the unused end are never touched */
    x.nodes = spm_xmalloc((size_t)2 * n * sizeof *x.nodes);
    atomic_init(&x.next, 1);
    atomic_init(&x.fail, 0);
    x.nthreads = nthreads;
    pthread_mutex_init(&x.mu, NULL);
    pthread_cond_init(&x.cv, NULL);
    pthread_t th[MAX_THREADS];
    int started = 0;

    prim_chunk chunks[MAX_THREADS];
    for (int t = 0; t < nthreads; t++)
        chunks[t] = (prim_chunk){g->tris, x.pr, (int)((long long)n * t / nthreads),
                                 (int)((long long)n * (t + 1) / nthreads), {{0}, {0}}, {{0}, {0}}};
    for (int t = 1; t < nthreads; t++)
        if (pthread_create(&th[t], NULL, make_prims, &chunks[t]) != 0)
            make_prims(&chunks[t]); /* no thread: this one does that part */
        else
            started |= 1 << t;
    make_prims(&chunks[0]);
    for (int t = 1; t < nthreads; t++)
        if (started & (1 << t))
            pthread_join(th[t], NULL);
    job root = {0, 0, n, 0, chunks[0].b, chunks[0].cb};
    for (int t = 1; t < nthreads; t++) {
        box_add(&root.b, &chunks[t].b);
        box_add(&root.cb, &chunks[t].cb);
    }

    /* the root's subtree on this thread; others take the queued subtrees */
    x.active = 1;
    started = 0;
    for (int t = 1; t < nthreads; t++)
        if (pthread_create(&th[t], NULL, worker, &x) == 0)
            started |= 1 << t;
    build_node(&x, root);
    pthread_mutex_lock(&x.mu);
    if (--x.active == 0 && x.nq == 0)
        pthread_cond_broadcast(&x.cv);
    pthread_mutex_unlock(&x.mu);
    worker(&x); /* help with what is queued, until all is done */
    for (int t = 1; t < nthreads; t++)
        if (started & (1 << t))
            pthread_join(th[t], NULL);
    pthread_mutex_destroy(&x.mu);
    pthread_cond_destroy(&x.cv);
    free(x.queue);

    int fail = atomic_load(&x.fail), nnodes = atomic_load(&x.next);
    if (fail) {
        free(x.pr);
        free(x.nodes);
        if (fail == 2)
            spm_errorf(err, "interrupted while building the BVH (%d triangles)", n);
        else
            spm_errorf(err, "BVH deeper than %d levels (%d triangles)", SPM_BVH_STACK, n);
        return 1;
    }
    int *perm = spm_xmalloc((size_t)n * sizeof *perm);
    for (int i = 0; i < n; i++)
        perm[i] = x.pr[i].id;
    free(x.pr);
    spm_geometry_uvs_permute(g, perm);
    spm_geometry_tangents_permute(g, perm);
    permute_tris(g->tris, perm, n);
    free(perm);
    spm_bvh_node *nodes = spm_xmalloc((size_t)nnodes * sizeof *nodes);
    renumber(x.nodes, nodes);
    free(x.nodes);
    g->bvh.sah_cost = spm_bvh_sah_cost(nodes, nnodes, &g->bvh.leaves);
    g->bvh.threads = nthreads;
    pad_boxes(nodes, nnodes, g->cam.eye);
    g->nodes = nodes;
    g->nnodes = nnodes;
    return spm_bvh_wide_build(g, err);
}

int spm_bvh_build(spm_geometry *g, spm_error *err)
{
    return spm_bvh_build_threads(g, spm_bvh_default_threads(), err);
}

/* The light tree's construction (include/spm_light_tree.h; pbrt-v4's
 * BVHLightSampler): each light's bounds (box, orientation cone, power), a
 * binary tree built top-down by the surface area orientation heuristic,
 * written after the per-triangle pmfs of g->light_pdf with every emitter's
 * trail from the root. */
#include "light_tree.h"
#include "util.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    double lo[3], hi[3], w[3];
    double cos_o, cos_e, phi;
    int twosided;
} lbounds;

typedef struct {
    lbounds b;
    double c[3]; /* the box's centre: what the split sorts */
    int em;      /* emitter index */
} litem;

typedef struct {
    float *f;     /* the nodes' words */
    int n, cap;
    spm_u32 *trail; /* per emitter, 2 words */
} tbuild;

static void put_u32(float *f, spm_u32 u)
{
    memcpy(f, &u, sizeof u);
}

int spm_light_placed(spm_u32 kind)
{
    return kind == SPM_LIGHT_AREA || kind == SPM_LIGHT_POINT || kind == SPM_LIGHT_SPOT;
}

/* a light's bounds: a triangle's box about its face normal (theta_o 0,
 * theta_e pi/2; all around when two-sided), a point's (theta_o pi), a
 * spot's axis with theta_o its beam, theta_e its falloff band (at least
 * LT_MIN_BAND: the walk's weight falls to 0 over theta_e, continuously) */
#define LT_MIN_BAND 0.02 /* radians */

static void light_bounds(const spm_geometry *g, const spm_material *mats, int i, lbounds *b)
{
    const spm_emitter *e = &g->emitters[i];
    memset(b, 0, sizeof *b);
    b->phi = g->light_w[i];
    b->cos_e = 0.0;
    b->w[2] = 1.0;
    if (e->kind == SPM_LIGHT_AREA) {
        const spm_tri *t = &g->tris[e->tri];
        const float *v[3] = {t->v0, t->v1, t->v2};
        for (int k = 0; k < 3; k++) {
            b->lo[k] = fmin(fmin(v[0][k], v[1][k]), v[2][k]);
            b->hi[k] = fmax(fmax(v[0][k], v[1][k]), v[2][k]);
            b->w[k] = t->n[k];
        }
        b->twosided = (mats[t->material].type & SPM_EMIT_TWOSIDED) != 0;
        b->cos_o = 1.0;
        return;
    }
    for (int k = 0; k < 3; k++)
        b->lo[k] = b->hi[k] = e->p[SPM_LIGHT_P_POS + k];
    if (e->kind == SPM_LIGHT_POINT) {
        b->cos_o = -1.0;
        return;
    }
    for (int k = 0; k < 3; k++)
        b->w[k] = e->p[SPM_LIGHT_P_DIR + k];
    double beam = e->p[SPM_LIGHT_P_B], cone = e->p[SPM_LIGHT_P_A];
    b->cos_o = cos(beam);
    b->cos_e = cos(fmin(fmax(cone - beam, LT_MIN_BAND), M_PI));
}

static double clampd(double x, double lo, double hi)
{
    return x < lo ? lo : x > hi ? hi : x;
}

/* pbrt-v4's DirectionCone Union: the smallest cone about both (axis a->w
 * rotated toward b->w by theta_o - theta_a) */
static void cone_union(lbounds *a, const lbounds *b)
{
    double ta = acos(clampd(a->cos_o, -1, 1)), tb = acos(clampd(b->cos_o, -1, 1));
    double dot = a->w[0] * b->w[0] + a->w[1] * b->w[1] + a->w[2] * b->w[2];
    double td = acos(clampd(dot, -1, 1));
    if (fmin(td + tb, M_PI) <= ta)
        return;
    if (fmin(td + ta, M_PI) <= tb) {
        memcpy(a->w, b->w, sizeof a->w);
        a->cos_o = b->cos_o;
        return;
    }
    double to = 0.5 * (ta + td + tb), wr[3];
    wr[0] = a->w[1] * b->w[2] - a->w[2] * b->w[1];
    wr[1] = a->w[2] * b->w[0] - a->w[0] * b->w[2];
    wr[2] = a->w[0] * b->w[1] - a->w[1] * b->w[0];
    double lr = sqrt(wr[0] * wr[0] + wr[1] * wr[1] + wr[2] * wr[2]);
    if (to >= M_PI || lr == 0.0) {
        a->cos_o = -1.0;
        return;
    }
    /* Rodrigues' rotation of a->w by theta_r about wr (perpendicular to it) */
    double tr = to - ta, c = cos(tr), s = sin(tr), k[3] = {wr[0] / lr, wr[1] / lr, wr[2] / lr};
    double kxw[3] = {k[1] * a->w[2] - k[2] * a->w[1], k[2] * a->w[0] - k[0] * a->w[2],
                     k[0] * a->w[1] - k[1] * a->w[0]};
    double w[3], l = 0.0;
    for (int i = 0; i < 3; i++) {
        w[i] = a->w[i] * c + kxw[i] * s;
        l += w[i] * w[i];
    }
    for (int i = 0; i < 3; i++)
        a->w[i] = w[i] / sqrt(l);
    a->cos_o = cos(to);
}

static void bounds_union(lbounds *a, const lbounds *b)
{
    if (!(a->phi > 0.0)) {
        *a = *b;
        return;
    }
    for (int k = 0; k < 3; k++) {
        a->lo[k] = fmin(a->lo[k], b->lo[k]);
        a->hi[k] = fmax(a->hi[k], b->hi[k]);
    }
    cone_union(a, b);
    a->cos_e = fmin(a->cos_e, b->cos_e);
    a->phi += b->phi;
    a->twosided |= b->twosided;
}

/* pbrt-v4's EvaluateCost: power x M_Omega (the cone's measure) x the box's
 * area, times Kr, the box's longest side over its side along the axis cut */
static double saoh_cost(const lbounds *b, const double diag[3], int dim)
{
    double to = acos(clampd(b->cos_o, -1, 1)), te = acos(clampd(b->cos_e, -1, 1));
    double tw = fmin(to + te, M_PI), so = sqrt(fmax(0.0, 1.0 - b->cos_o * b->cos_o));
    double m = 2.0 * M_PI * (1.0 - b->cos_o) +
               M_PI / 2.0 * (2.0 * tw * so - cos(to - 2.0 * tw) - 2.0 * to * so + b->cos_o);
    double d[3] = {b->hi[0] - b->lo[0], b->hi[1] - b->lo[1], b->hi[2] - b->lo[2]};
    double area = 2.0 * (d[0] * d[1] + d[1] * d[2] + d[2] * d[0]);
    double kr = fmax(diag[0], fmax(diag[1], diag[2])) / diag[dim];
    return b->phi * m * kr * area;
}

static int sort_dim;
static int by_centre(const void *a, const void *b)
{
    double x = ((const litem *)a)->c[sort_dim], y = ((const litem *)b)->c[sort_dim];
    return x < y ? -1 : x > y;
}

#define BUCKETS 12
/* Where to cut items [0, n): sorts them along the best axis and returns the
 * count of the first part, by the least SAOH cost over BUCKETS buckets of the
 * centres' box per axis (pbrt-v4's), or halves them by count where the
 * centres coincide or the tree grows too deep for a trail. */
static int split(litem *it, int n, const lbounds *all, int depth)
{
    double clo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, chi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (int i = 0; i < n; i++)
        for (int k = 0; k < 3; k++) {
            clo[k] = fmin(clo[k], it[i].c[k]);
            chi[k] = fmax(chi[k], it[i].c[k]);
        }
    double diag[3] = {all->hi[0] - all->lo[0], all->hi[1] - all->lo[1], all->hi[2] - all->lo[2]};
    double best = HUGE_VAL;
    int bdim = -1, bcut = 0;
    for (int dim = 0; dim < 3 && depth < SPM_LTREE_MAX_DEPTH - 24; dim++) {
        if (!(chi[dim] > clo[dim]))
            continue;
        lbounds bk[BUCKETS];
        int cnt[BUCKETS] = {0};
        memset(bk, 0, sizeof bk);
        for (int i = 0; i < n; i++) {
            int b = (int)(BUCKETS * (it[i].c[dim] - clo[dim]) / (chi[dim] - clo[dim]));
            b = b < 0 ? 0 : b >= BUCKETS ? BUCKETS - 1 : b;
            cnt[b]++;
            bounds_union(&bk[b], &it[i].b);
        }
        for (int cut = 1; cut < BUCKETS; cut++) {
            lbounds l, r;
            memset(&l, 0, sizeof l);
            memset(&r, 0, sizeof r);
            int nl = 0, nr = 0;
            for (int b = 0; b < BUCKETS; b++) {
                if (!cnt[b])
                    continue;
                bounds_union(b < cut ? &l : &r, &bk[b]);
                *(b < cut ? &nl : &nr) += cnt[b];
            }
            if (!nl || !nr)
                continue;
            double cost = saoh_cost(&l, diag, dim) + saoh_cost(&r, diag, dim);
            if (cost < best) {
                best = cost;
                bdim = dim;
                bcut = cut;
            }
        }
    }
    sort_dim = bdim < 0 ? 0 : bdim;
    qsort(it, (size_t)n, sizeof *it, by_centre);
    if (bdim < 0)
        return n / 2;
    int m = 0; /* the bucket of each item, as the cost counted it */
    while (m < n && (int)(BUCKETS * (it[m].c[bdim] - clo[bdim]) / (chi[bdim] - clo[bdim])) < bcut)
        m++;
    return m > 0 && m < n ? m : n / 2;
}

static void write_node(tbuild *t, int at, const lbounds *b, spm_u32 next, spm_u32 flags)
{
    float *f = &t->f[(size_t)at * SPM_LTREE_NODE];
    for (int k = 0; k < 3; k++) {
        f[SPM_LTN_LO + k] = (float)b->lo[k];
        f[SPM_LTN_HI + k] = (float)b->hi[k];
        f[SPM_LTN_W + k] = (float)b->w[k];
    }
    f[SPM_LTN_COS_O] = (float)b->cos_o;
    f[SPM_LTN_COS_E] = (float)b->cos_e;
    f[SPM_LTN_PHI] = (float)b->phi;
    put_u32(&f[SPM_LTN_NEXT], next);
    put_u32(&f[SPM_LTN_FLAGS], flags | (b->twosided ? SPM_LTF_TWOSIDED : 0u));
}

/* the subtree over items [0, n) at node index t->n, its lights' trails
 * continuing `trail` (depth bits so far); returns its bounds */
static lbounds build_node(tbuild *t, litem *it, int n, unsigned long long trail, int depth)
{
    int at = t->n++;
    if (t->n > t->cap) {
        t->cap = 2 * t->n;
        t->f = spm_xrealloc(t->f, (size_t)t->cap * SPM_LTREE_NODE * sizeof *t->f);
    }
    if (n == 1) {
        t->trail[2 * it[0].em] = (spm_u32)trail;
        t->trail[2 * it[0].em + 1] = (spm_u32)(trail >> 32);
        write_node(t, at, &it[0].b, (spm_u32)it[0].em, SPM_LTF_LEAF);
        return it[0].b;
    }
    lbounds all;
    memset(&all, 0, sizeof all);
    for (int i = 0; i < n; i++)
        bounds_union(&all, &it[i].b);
    int m = split(it, n, &all, depth);
    lbounds l = build_node(t, it, m, trail, depth + 1);
    int second = t->n;
    lbounds r = build_node(t, it + m, n - m, trail | (1ull << depth), depth + 1);
    bounds_union(&l, &r);
    write_node(t, at, &l, (spm_u32)second, 0u);
    return l;
}

void spm_light_tree_attach(spm_geometry *g, const spm_material *mats)
{
    int n = 0, ninf = 0, narea = 0;
    litem *it = spm_xcalloc((size_t)g->nemitters + 1, sizeof *it);
    spm_u32 *inf = spm_xcalloc((size_t)g->nemitters + 1, sizeof *inf);
    for (int i = 0; i < g->nemitters; i++) {
        narea += g->emitters[i].kind == SPM_LIGHT_AREA;
        if (!spm_light_placed(g->emitters[i].kind)) {
            inf[ninf++] = (spm_u32)i;
            continue;
        }
        light_bounds(g, mats, i, &it[n].b);
        for (int k = 0; k < 3; k++)
            it[n].c[k] = 0.5 * (it[n].b.lo[k] + it[n].b.hi[k]);
        it[n++].em = i;
    }
    tbuild t = {NULL, 0, 0, spm_xcalloc(2 * (size_t)g->nemitters + 1, sizeof(spm_u32))};
    if (n)
        build_node(&t, it, n, 0ull, 0);
    size_t head = SPM_LTREE_HEAD + (size_t)ninf, nodes = (size_t)t.n * SPM_LTREE_NODE;
    g->ntree = (int)(head + nodes + 2 * (size_t)g->nemitters);
    size_t words = (size_t)g->ntris + (size_t)g->ntree;
    g->light_pdf = spm_xrealloc(g->light_pdf, words * sizeof(float));
    float *f = g->light_pdf + g->ntris;
    memset(f, 0, (size_t)g->ntree * sizeof *f);
    put_u32(&f[SPM_LTREE_H_NODES], (spm_u32)t.n);
    put_u32(&f[SPM_LTREE_H_AREA], (spm_u32)narea);
    put_u32(&f[SPM_LTREE_H_INF], (spm_u32)ninf);
    for (int i = 0; i < ninf; i++)
        put_u32(&f[SPM_LTREE_HEAD + i], inf[i]);
    if (nodes)
        memcpy(f + head, t.f, nodes * sizeof *f);
    for (size_t i = 0; i < 2 * (size_t)g->nemitters; i++)
        put_u32(&f[head + nodes + i], t.trail[i]);
    free(t.f);
    free(t.trail);
    free(it);
    free(inf);
}

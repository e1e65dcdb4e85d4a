/* The prepared scene as bytes (prepared.h): a header, the structs with their
 * pointers cleared, then each array as its byte length and its bytes. */
#include "prepared.h"
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

/* Changes whenever the layout of what is packed changes: the magic and the
 * sizes of the packed structs make a block from another build an error. */
#define PREP_MAGIC 0x53504d51u /* "SPMQ" */

typedef struct {
    uint32_t magic;
    uint32_t sizes[6];
    spm_prepared_info info;
} prep_header;

static void header_sizes(uint32_t s[6])
{
    s[0] = sizeof(spm_geometry);
    s[1] = sizeof(spm_tables);
    s[2] = sizeof(spm_tri);
    s[3] = sizeof(spm_bvh_node);
    s[4] = sizeof(spm_material);
    s[5] = sizeof(spm_pretest_result);
}

typedef struct {
    unsigned char *p;
    size_t n, cap;
} writer;

static void put(writer *w, const void *src, size_t n)
{
    if (w->n + n > w->cap) {
        w->cap = (w->n + n) * 2 + 4096;
        w->p = spm_xrealloc(w->p, w->cap);
    }
    if (n)
        memcpy(w->p + w->n, src, n);
    w->n += n;
}

/* An array's length, or NO_ARRAY for none (NULL): an empty array (a count
 * of 0, as a scene without fluorescent materials has) arrives as one. */
#define NO_ARRAY UINT64_MAX
static void put_array(writer *w, const void *a, size_t n)
{
    uint64_t len = a ? n : NO_ARRAY;
    put(w, &len, sizeof len);
    if (a)
        put(w, a, (size_t)len);
}

typedef struct {
    const unsigned char *p;
    size_t n, at;
    int bad;
} reader;

static void get(reader *r, void *dst, size_t n)
{
    if (r->bad || n > r->n - r->at) {
        r->bad = 1;
        memset(dst, 0, n);
        return;
    }
    memcpy(dst, r->p + r->at, n);
    r->at += n;
}

/* An array of exactly `want` bytes, or NULL when packed as absent. */
static void *get_array(reader *r, size_t want)
{
    uint64_t len = 0;
    get(r, &len, sizeof len);
    if (r->bad || len == NO_ARRAY)
        return NULL;
    if (len != want || len > r->n - r->at) {
        r->bad = 1;
        return NULL;
    }
    /* one spare element, as the builders allocate (a count of zero stays valid) */
    void *a = spm_xcalloc((size_t)len + 16, 1);
    get(r, a, (size_t)len);
    return a;
}

/* The tables' arrays, from their one list (tables.h SPM_TABLES_ARRAYS):
 * cleared in the copy of the struct that travels (and in what arrives), then
 * each as its bytes. */
#define CLEAR_A(name, type, count) clr->name = NULL;
#define CLEAR_L(name, type, count)           \
    for (int l = 0; l < SPM_NUM_LEVELS; l++) \
        clr->name[l] = NULL;
#define PUT_A(name, type, count) put_array(&w, t->name, (count) * sizeof(type));
#define PUT_L(name, type, count)             \
    for (int l = 0; l < SPM_NUM_LEVELS; l++) \
        put_array(&w, t->name[l], (count) * sizeof(type));
#define GET_A(name, type, count) \
    if (!r.bad)                  \
        t->name = get_array(&r, (count) * sizeof(type));
#define GET_L(name, type, count)                          \
    for (int l = 0; l < SPM_NUM_LEVELS && !r.bad; l++)    \
        t->name[l] = get_array(&r, (count) * sizeof(type));

void *spm_prepared_pack(const spm_geometry *g, const spm_tables *t, const spm_prepared_info *info,
                        size_t *n)
{
    writer w = {0};
    prep_header h;
    memset(&h, 0, sizeof h);
    h.magic = PREP_MAGIC;
    header_sizes(h.sizes);
    h.info = *info;
    put(&w, &h, sizeof h);
    spm_geometry gs = *g;
    gs.tris = NULL;
    gs.nodes = NULL;
    gs.wide = NULL; /* collapsed again from the nodes on unpacking */
    gs.emitters = NULL;
    gs.light_pdf = NULL;
    gs.light_w = NULL;
    gs.vnormals = NULL;
    gs.disp = NULL;
    gs.uvs = NULL;
    gs.tex = NULL;
    gs.env = NULL;
    put(&w, &gs, sizeof gs);
    put_array(&w, g->tris, (size_t)g->ntris * sizeof *g->tris);
    put_array(&w, g->nodes, (size_t)g->nnodes * sizeof *g->nodes);
    put_array(&w, g->emitters, (size_t)g->nemitters * sizeof *g->emitters);
    put_array(&w, g->light_pdf, ((size_t)g->ntris + (size_t)g->ntree) * sizeof *g->light_pdf);
    put_array(&w, g->vnormals, (size_t)g->nvn * 9 * sizeof *g->vnormals);
    put_array(&w, g->disp, (size_t)g->ndisp * SPM_TRUTH_BINS * sizeof *g->disp);
    put_array(&w, g->uvs, g->ntex ? (size_t)g->ntris * 6 * sizeof *g->uvs : 0);
    put_array(&w, g->tex, g->ntex * sizeof *g->tex);
    put_array(&w, g->env, g->nenv * sizeof *g->env);
    spm_tables ts = *t, *clr = &ts;
    SPM_TABLES_ARRAYS(CLEAR_A, CLEAR_L)
    put(&w, &ts, sizeof ts);
    SPM_TABLES_ARRAYS(PUT_A, PUT_L)
    *n = w.n;
    return w.p;
}

int spm_prepared_unpack(const void *buf, size_t n, spm_geometry *g, spm_tables *t,
                        spm_prepared_info *info, spm_error *err)
{
    reader r = {buf, n, 0, 0};
    memset(g, 0, sizeof *g);
    memset(t, 0, sizeof *t);
    prep_header h, want;
    memset(&want, 0, sizeof want);
    header_sizes(want.sizes);
    get(&r, &h, sizeof h);
    if (r.bad || h.magic != PREP_MAGIC || memcmp(h.sizes, want.sizes, sizeof want.sizes)) {
        spm_errorf(err, "the prepared scene (%zu bytes) comes from another build of specmip", n);
        return 1;
    }
    *info = h.info;
    get(&r, g, sizeof *g);
    int ntris = g->ntris, nnodes = g->nnodes, nem = g->nemitters, nvn = g->nvn, ndisp = g->ndisp;
    if (ntris < 0 || nnodes < 0 || nem < 0 || nvn < 0 || ndisp < 0 || g->ntree < 0)
        r.bad = 1;
    g->tris = get_array(&r, (size_t)ntris * sizeof *g->tris);
    g->nodes = get_array(&r, (size_t)nnodes * sizeof *g->nodes);
    g->wide = NULL;
    g->emitters = get_array(&r, (size_t)nem * sizeof *g->emitters);
    g->light_pdf = get_array(&r, ((size_t)ntris + (size_t)g->ntree) * sizeof *g->light_pdf);
    g->vnormals = get_array(&r, (size_t)nvn * 9 * sizeof *g->vnormals);
    g->disp = get_array(&r, (size_t)ndisp * SPM_TRUTH_BINS * sizeof *g->disp);
    g->uvs = get_array(&r, g->ntex ? (size_t)ntris * 6 * sizeof *g->uvs : 0);
    g->tex = get_array(&r, g->ntex * sizeof *g->tex);
    g->env = get_array(&r, g->nenv * sizeof *g->env);
    get(&r, t, sizeof *t);
    spm_tables *clr = t; /* no address from another process */
    SPM_TABLES_ARRAYS(CLEAR_A, CLEAR_L)
    if (t->ncolours < 0 || t->nmaterials < 0)
        r.bad = 1;
    SPM_TABLES_ARRAYS(GET_A, GET_L)
    if (r.bad || r.at != n) {
        spm_errorf(err, "the prepared scene is damaged (%zu bytes, read %zu)", n, r.at);
        spm_geometry_free(g);
        spm_tables_free(t);
        return 1;
    }
    if (spm_bvh_wide_build(g, err)) {
        spm_geometry_free(g);
        spm_tables_free(t);
        return 1;
    }
    return 0;
}

uint64_t spm_prepared_hash(const spm_geometry *g, const spm_tables *t)
{
    spm_geometry gs = *g;
    memset(&gs.bvh, 0, sizeof gs.bvh); /* how the build ran (its threads), not what it built */
    spm_prepared_info none;
    memset(&none, 0, sizeof none);
    size_t n;
    void *buf = spm_prepared_pack(&gs, t, &none, &n);
    uint64_t h = spm_fnv1a64(SPM_FNV1A64_BASIS, buf, n);
    free(buf);
    return h;
}

#include "scene_hints.h"
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

typedef struct {
    float p[3];
    uint32_t at; /* 3 * triangle + corner */
} corner;

static int corner_cmp(const void *a, const void *b)
{
    const float *p = ((const corner *)a)->p, *q = ((const corner *)b)->p;
    for (int i = 0; i < 3; i++)
        if (p[i] != q[i])
            return p[i] < q[i] ? -1 : 1;
    return 0;
}

static int u64_cmp(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a, y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* Vertices numbered by position (sorted corners, equal runs one id), then the
 * edges as (lower id, higher id) keys, sorted: closed when every run of equal
 * keys is two long. O(n log n). */
int spm_tris_closed(const spm_scene_tri *t, int n)
{
    if (n < 4) /* a tetrahedron is the smallest closed mesh */
        return 0;
    size_t nc = 3 * (size_t)n;
    corner *c = spm_xmalloc(nc * sizeof *c);
    for (size_t k = 0; k < nc; k++) {
        memcpy(c[k].p, t[k / 3].p[k % 3], sizeof c[k].p);
        c[k].at = (uint32_t)k;
    }
    qsort(c, nc, sizeof *c, corner_cmp);
    uint32_t *id = spm_xmalloc(nc * sizeof *id);
    uint32_t next = 0;
    for (size_t k = 0; k < nc; k++) {
        if (k && corner_cmp(&c[k - 1], &c[k]))
            next++;
        id[c[k].at] = next;
    }
    free(c);
    uint64_t *e = spm_xmalloc(nc * sizeof *e);
    for (size_t k = 0; k < nc; k++) {
        uint64_t a = id[k], b = id[k - k % 3 + (k % 3 + 1) % 3];
        e[k] = a < b ? a << 32 | b : b << 32 | a;
    }
    free(id);
    qsort(e, nc, sizeof *e, u64_cmp);
    int closed = 1;
    for (size_t k = 0; k < nc && closed; k += 2)
        closed = k + 1 < nc && e[k] == e[k + 1] && (k + 2 >= nc || e[k + 2] != e[k]);
    free(e);
    return closed;
}

void spm_scene_hint_camera_inside(const spm_scene *s)
{
    for (int i = 0; i < s->nmeshes; i++) {
        const spm_scene_mesh *m = &s->meshes[i];
        int inside = m->n <= SPM_HINT_CLOSED_MAX_TRIS && m->first + m->n <= s->ntris;
        for (int a = 0; a < 3 && inside; a++)
            inside = m->lo[a] <= s->eye[a] && s->eye[a] <= m->hi[a];
        if (inside && spm_tris_closed(s->tris + m->first, m->n))
            spm_warnf("%s: camera inside the closed mesh '%s' (bounding box (%g %g %g) to "
                      "(%g %g %g), camera at (%g %g %g)): it may hide the scene; a model in "
                      "millimetres? ('scale 0.001' makes it metres)", m->where, m->name,
                      m->lo[0], m->lo[1], m->lo[2], m->hi[0], m->hi[1], m->hi[2], s->eye[0],
                      s->eye[1], s->eye[2]);
    }
}

/* PLY with triangle strips (mesh_ply.h): the header, then each element's
 * items in order, ASCII tokens or binary values of either byte order. The
 * reader streams: memory grows with the vertices and triangles read, never
 * with the counts a header declares. */
#include "mesh_ply.h"
#include "interrupt.h"
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef enum { P_NONE, P_I8, P_U8, P_I16, P_U16, P_I32, P_U32, P_F32, P_F64 } ply_type;
static const char *const type_names[][2] = {
    {"", ""}, {"char", "int8"}, {"uchar", "uint8"}, {"short", "int16"}, {"ushort", "uint16"},
    {"int", "int32"}, {"uint", "uint32"}, {"float", "float32"}, {"double", "float64"}};
static const int type_size[] = {0, 1, 1, 2, 2, 4, 4, 4, 8};

typedef struct {
    char name[32];
    ply_type type;       /* the value's, or a list's items' */
    ply_type count_type; /* P_NONE: not a list */
} ply_prop;

typedef struct {
    char name[32];
    uint64_t count;
    int nprops;
    ply_prop props[SPM_PLY_MAX_PROPERTIES];
} ply_elem;

enum { F_ASCII, F_LE, F_BE };

/* Binary values come out of a block read ahead (a call to fread per value
 * was most of a 1M-triangle file's reading time); ASCII tokens from getc. */
#define PLY_BLOCK 65536

typedef struct {
    FILE *f;
    const char *path;
    spm_error *err;
    int format, swap;
    long line;           /* ASCII: the line being read */
    uint64_t offset;     /* binary: bytes read */
    const ply_elem *e;   /* where reading is, for messages */
    uint64_t item;
    int failed;
    int strips;          /* the header declares tristrips */
    int polygon;         /* a face of more than three vertices, in a file without strips */
    unsigned char *block; /* binary: PLY_BLOCK bytes read ahead, [at, have) unread */
    size_t at, have;
} reader;

static void fail(reader *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void fail(reader *r, const char *fmt, ...)
{
    if (r->failed)
        return;
    r->failed = 1;
    char msg[600];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    if (!r->e)
        spm_errorf(r->err, "%s:%ld: %s", r->path, r->line, msg);
    else if (r->format == F_ASCII)
        spm_errorf(r->err, "%s:%ld: element %s item %llu: %s", r->path, r->line, r->e->name,
                   (unsigned long long)r->item + 1, msg);
    else
        spm_errorf(r->err, "%s: element %s item %llu (byte %llu): %s", r->path, r->e->name,
                   (unsigned long long)r->item + 1, (unsigned long long)r->offset, msg);
}

static ply_type type_of(const char *s)
{
    for (int t = P_I8; t <= P_F64; t++)
        if (!strcmp(s, type_names[t][0]) || !strcmp(s, type_names[t][1]))
            return (ply_type)t;
    return P_NONE;
}

/* ---- values ---------------------------------------------------------------- */

/* The next ASCII token (at most 63 characters), lines counted. */
static int token(reader *r, char tok[64])
{
    int c;
    while ((c = getc(r->f)) != EOF && isspace(c))
        r->line += c == '\n';
    if (c == EOF) {
        fail(r, "the file ends before the element's %llu items", (unsigned long long)r->e->count);
        return 1;
    }
    int n = 0;
    for (; c != EOF && !isspace(c); c = getc(r->f)) {
        if (n == 63) {
            fail(r, "a value longer than 63 characters");
            return 1;
        }
        tok[n++] = (char)c;
    }
    tok[n] = 0;
    if (c == '\n')
        ungetc(c, r->f); /* counted by the next token */
    return 0;
}

static const double type_min[] = {0, -128, 0, -32768, 0, -2147483648.0, 0, 0, 0};
static const double type_max[] = {0, 127, 255, 32767, 65535, 2147483647.0, 4294967295.0, 0, 0};

/* The next n (<= PLY_BLOCK) bytes of a binary file, consumed, or NULL at its end. */
static const unsigned char *need(reader *r, size_t n)
{
    if (r->have - r->at < n) {
        size_t left = r->have - r->at;
        memmove(r->block, r->block + r->at, left);
        r->at = 0;
        r->have = left + fread(r->block + left, 1, PLY_BLOCK - left, r->f);
        if (r->have < n) {
            fail(r, "the file ends before the element's %llu items",
                 (unsigned long long)r->e->count);
            return NULL;
        }
    }
    const unsigned char *b = r->block + r->at;
    r->at += n;
    r->offset += (uint64_t)n;
    return b;
}

/* The binary value of type t at p, bytes reversed when swap, as a double
 * (every integer type is exact in one). */
static inline double decode(const unsigned char *p, ply_type t, int swap)
{
    unsigned char b[8];
    int n = type_size[t];
    memcpy(b, p, (size_t)n);
    if (swap)
        for (int i = 0; i < n / 2; i++) {
            unsigned char x = b[i];
            b[i] = b[n - 1 - i];
            b[n - 1 - i] = x;
        }
    switch (t) {
    case P_I8: return (int8_t)b[0];
    case P_U8: return b[0];
    case P_I16: { int16_t x; memcpy(&x, b, 2); return x; }
    case P_U16: { uint16_t x; memcpy(&x, b, 2); return x; }
    case P_I32: { int32_t x; memcpy(&x, b, 4); return x; }
    case P_U32: { uint32_t x; memcpy(&x, b, 4); return x; }
    case P_F32: { float x; memcpy(&x, b, 4); return x; }
    default: { double x; memcpy(&x, b, 8); return x; }
    }
}

/* One value of type t as a double (every integer type is exact in one). */
static int value(reader *r, ply_type t, double *v)
{
    if (r->format == F_ASCII) {
        char tok[64], *end;
        if (token(r, tok))
            return 1;
        errno = 0;
        if (t == P_F32 || t == P_F64) {
            *v = strtod(tok, &end);
        } else {
            long long i = strtoll(tok, &end, 10);
            *v = (double)i;
            if (!*end && (errno || *v < type_min[t] || *v > type_max[t])) {
                fail(r, "'%s' is out of the range of %s", tok, type_names[t][0]);
                return 1;
            }
        }
        if (end == tok || *end) {
            fail(r, "'%s' is not a%s %s", tok, t == P_I8 || t == P_U8 || t == P_U32 ? "n" : "",
                 type_names[t][0]);
            return 1;
        }
        return 0;
    }
    const unsigned char *b = need(r, (size_t)type_size[t]);
    if (!b)
        return 1;
    *v = decode(b, t, r->swap);
    return 0;
}

/* ---- the header ------------------------------------------------------------- */

typedef struct {
    int format;
    int nelems;
    ply_elem elems[SPM_PLY_MAX_ELEMENTS];
} ply_header;

/* One header line into buf (its newline and any \r removed); 1 at the end of the file. */
static int header_line(reader *r, char *buf, size_t n)
{
    if (!fgets(buf, (int)n, r->f)) {
        fail(r, "the file ends before 'end_header'");
        return 1;
    }
    r->line++;
    size_t len = strlen(buf);
    if (len == n - 1 && buf[len - 1] != '\n') {
        fail(r, "a header line longer than %zu characters", n - 2);
        return 1;
    }
    while (len && (buf[len - 1] == '\n' || buf[len - 1] == '\r'))
        buf[--len] = 0;
    return 0;
}

static int parse_property(reader *r, ply_header *h, char *rest)
{
    if (h->nelems == 0) {
        fail(r, "a property before any element");
        return 1;
    }
    ply_elem *e = &h->elems[h->nelems - 1];
    if (e->nprops == SPM_PLY_MAX_PROPERTIES) {
        fail(r, "more than %d properties in element %s", SPM_PLY_MAX_PROPERTIES, e->name);
        return 1;
    }
    ply_prop *p = &e->props[e->nprops];
    char a[32], b[32] = "", c[32] = "", extra[2];
    int k = sscanf(rest, "%31s %31s %31s %1s", a, b, c, extra);
    if (k >= 1 && !strcmp(a, "list")) {
        char name[32];
        if (sscanf(rest, "%*s %*s %*s %31s %1s", name, extra) != 1) {
            fail(r, "expected 'property list COUNT_TYPE ITEM_TYPE NAME'");
            return 1;
        }
        p->count_type = type_of(b);
        p->type = type_of(c);
        if (p->count_type == P_NONE || p->type == P_NONE || p->count_type >= P_F32) {
            fail(r, "unknown list types '%s %s' (a count of an integer type, items of any)", b, c);
            return 1;
        }
        snprintf(p->name, sizeof p->name, "%s", name);
    } else {
        if (k != 2) {
            fail(r, "expected 'property TYPE NAME'");
            return 1;
        }
        p->type = type_of(a);
        p->count_type = P_NONE;
        if (p->type == P_NONE) {
            fail(r, "unknown property type '%s'", a);
            return 1;
        }
        snprintf(p->name, sizeof p->name, "%s", b);
    }
    e->nprops++;
    return 0;
}

static int parse_header(reader *r, ply_header *h)
{
    char buf[1026];
    memset(h, 0, sizeof *h);
    h->format = -1;
    if (header_line(r, buf, sizeof buf))
        return 1;
    if (strcmp(buf, "ply")) {
        fail(r, "not a PLY file (its first line is not 'ply')");
        return 1;
    }
    for (int n = 1;; n++) {
        if (n > SPM_PLY_MAX_HEADER_LINES) {
            fail(r, "a header of more than %d lines", SPM_PLY_MAX_HEADER_LINES);
            return 1;
        }
        if (header_line(r, buf, sizeof buf))
            return 1;
        char key[32] = "", *rest = buf;
        while (*rest == ' ' || *rest == '\t')
            rest++;
        int kl = 0;
        while (rest[kl] && rest[kl] != ' ' && rest[kl] != '\t')
            kl++;
        snprintf(key, sizeof key, "%.*s", kl < 31 ? kl : 31, rest);
        rest += kl;
        if (!strcmp(key, "end_header"))
            break;
        if (!strcmp(key, "comment") || !strcmp(key, "obj_info") || !key[0])
            continue;
        if (!strcmp(key, "format")) {
            char f[32], v[32], extra[2];
            if (sscanf(rest, "%31s %31s %1s", f, v, extra) != 2 || strcmp(v, "1.0")) {
                fail(r, "expected 'format ascii|binary_little_endian|binary_big_endian 1.0'");
                return 1;
            }
            h->format = !strcmp(f, "ascii") ? F_ASCII
                        : !strcmp(f, "binary_little_endian") ? F_LE
                        : !strcmp(f, "binary_big_endian") ? F_BE : -1;
            if (h->format < 0) {
                fail(r, "unknown format '%s'", f);
                return 1;
            }
        } else if (!strcmp(key, "element")) {
            if (h->nelems == SPM_PLY_MAX_ELEMENTS) {
                fail(r, "more than %d elements", SPM_PLY_MAX_ELEMENTS);
                return 1;
            }
            ply_elem *e = &h->elems[h->nelems];
            char count[32], extra[2];
            if (sscanf(rest, "%31s %31s %1s", e->name, count, extra) != 2) {
                fail(r, "expected 'element NAME COUNT'");
                return 1;
            }
            char *end;
            errno = 0;
            unsigned long long c = strtoull(count, &end, 10);
            if (*end || end == count || errno || count[0] == '-' || c > UINT32_MAX) {
                fail(r, "element %s: '%s' is not a count (0 to %u)", e->name, count, UINT32_MAX);
                return 1;
            }
            e->count = c;
            h->nelems++;
        } else if (!strcmp(key, "property")) {
            if (parse_property(r, h, rest))
                return 1;
        } else {
            fail(r, "unknown header line '%.40s'", buf);
            return 1;
        }
    }
    if (h->format < 0) {
        fail(r, "no 'format' line in the header");
        return 1;
    }
    return 0;
}

/* ---- the elements ------------------------------------------------------------ */

typedef struct {
    float *v;            /* per vertex: xyz, then nx ny nz, then u v (those it has) */
    int vstride;         /* floats per vertex: 3, 5, 6 or 8 */
    int nofs, uofs;      /* where the normal and the texture coordinates are, -1 none */
    uint64_t nv, capv;
    spm_mesh_tri *t;
    spm_mesh_normals *tn; /* per triangle when the vertices have normals */
    spm_mesh_uvs *tuv;    /* per triangle when they have texture coordinates */
    uint64_t nt, capt;
    uint32_t ignored;
    int have_vertices;
} ply_mesh;

static int find_prop(const ply_elem *e, const char *name)
{
    for (int i = 0; i < e->nprops; i++)
        if (!strcmp(e->props[i].name, name))
            return i;
    return -1;
}

/* The scalar properties `names` (n of them, all present) as the vertex's
 * next channels, after *stride: their offset, or -1 (then none is taken). */
static int vertex_channels(const ply_elem *e, const char *const *names, int n, int ch[8],
                           int *stride)
{
    for (int k = 0; k < n; k++) {
        int p = find_prop(e, names[k]);
        if (p < 0 || e->props[p].count_type != P_NONE)
            return -1;
        ch[*stride + k] = p;
    }
    *stride += n;
    return *stride - n;
}

/* the channel property k fills, or -1 */
static int channel_of(const int *ch, int n, int k)
{
    for (int c = 0; c < n; c++)
        if (ch[c] == k)
            return c;
    return -1;
}

static int add_tri(reader *r, ply_mesh *m, const double idx[3])
{
    if (m->nt == SPM_SCENE_MAX_TRIS) {
        fail(r, "more than %d triangles", SPM_SCENE_MAX_TRIS);
        return 1;
    }
    if (m->nt == m->capt) {
        m->capt = m->capt ? 2 * m->capt : 1024;
        m->t = spm_xrealloc(m->t, m->capt * sizeof *m->t);
        if (m->nofs >= 0)
            m->tn = spm_xrealloc(m->tn, m->capt * sizeof *m->tn);
        if (m->uofs >= 0)
            m->tuv = spm_xrealloc(m->tuv, m->capt * sizeof *m->tuv);
    }
    for (int k = 0; k < 3; k++) {
        const float *v = &m->v[(uint64_t)m->vstride * (uint64_t)idx[k]];
        if (m->nofs >= 0)
            memcpy(m->tn[m->nt].n[k], v + m->nofs, sizeof m->tn->n[k]);
        if (m->uofs >= 0)
            memcpy(m->tuv[m->nt].uv[k], v + m->uofs, sizeof m->tuv->uv[k]);
    }
    spm_mesh_tri *t = &m->t[m->nt++];
    for (int k = 0; k < 3; k++)
        memcpy(t->p[k], &m->v[(uint64_t)m->vstride * (uint64_t)idx[k]], sizeof t->p[k]);
    t->mat = 0;
    return 0;
}

/* A vertex index read from a list: an integer in [0, nv), or -1 where allowed. */
static int index_ok(reader *r, const ply_mesh *m, double i, int restart_ok)
{
    if (restart_ok && i == -1)
        return 1;
    if (i < 0 || i >= (double)m->nv || i != floor(i)) {
        fail(r, "vertex index %.17g is out of range (%llu vertices%s)", i,
             (unsigned long long)m->nv, restart_ok ? "; -1 restarts a strip" : "");
        return 0;
    }
    return 1;
}

/* A stop request (Ctrl-C), asked every 65536 items and every 65536 values of
 * a list (a strip's one list may hold the whole mesh): 1 and the error,
 * naming the item, and the value when within a list (k > 0). */
static int stop_requested(reader *r, double k)
{
    spm_test_pause("ply");
    if (!spm_stop_requested())
        return 0;
    if (k > 0)
        spm_errorf(r->err, "interrupted while loading %s (element %s, item %llu, value %.0f of "
                   "its list)", r->path, r->e->name, (unsigned long long)r->item + 1, k + 1);
    else
        spm_errorf(r->err, "interrupted while loading %s (element %s, item %llu)", r->path,
                   r->e->name, (unsigned long long)r->item + 1);
    r->failed = 1;
    return 1;
}

/* every 65536 values of a list, as items are counted, but not at its start
 * (the item's own check); k < count, a count of at most 2^32 */
#define LIST_STOP(r, k) ((k) > 0 && ((uint64_t)(k) & 0xffff) == 0 && stop_requested((r), (k)))

/* The list of face or strip indices: a face's polygon as a fan (v0, vi, vi+1);
 * a strip's triangle j (from its start or last -1) is (vj, vj+1, vj+2), its
 * first two vertices swapped for odd j so that every triangle keeps the
 * first one's winding; triangles with a repeated index (joins) are left out. */
static int read_indices(reader *r, ply_mesh *m, const ply_prop *p, int strip)
{
    double count, idx[3], i;
    if (value(r, p->count_type, &count))
        return 1;
    if (count < 0) {
        fail(r, "a list of %.0f indices", count);
        return 1;
    }
    if (!strip && count < 3)
        m->ignored |= SPM_MESH_IGN_POINTS_LINES;
    if (!strip && count > 3 && !r->strips) { /* Assimp's triangulation: the caller's */
        r->polygon = r->failed = 1;
        return 1;
    }
    /* binary: the whole list at once, r->offset kept at the index being read for messages */
    size_t isz = (size_t)type_size[p->type];
    const unsigned char *bulk = NULL;
    uint64_t at = r->offset;
    if (r->format != F_ASCII && count * (double)isz <= PLY_BLOCK) {
        if (!(bulk = need(r, (size_t)count * isz)))
            return 1;
        r->offset = at;
    }
    int have = 0, odd = 0;
    for (double k = 0; k < count; k++) {
        if (LIST_STOP(r, k))
            return 1;
        if (bulk) {
            i = decode(bulk + (size_t)k * isz, p->type, r->swap);
            r->offset += isz;
        } else if (value(r, p->type, &i)) {
            return 1;
        }
        if (!index_ok(r, m, i, strip))
            return 1;
        if (strip && i == -1) {
            have = odd = 0;
            continue;
        }
        if (have < 2) {
            idx[have++] = i;
            continue;
        }
        if (!strip) { /* fan: v0 stays */
            idx[2] = i;
            if (add_tri(r, m, idx))
                return 1;
            idx[1] = i;
            continue;
        }
        double t[3] = {odd ? idx[1] : idx[0], odd ? idx[0] : idx[1], i};
        if (t[0] != t[1] && t[1] != t[2] && t[0] != t[2] && add_tri(r, m, t))
            return 1;
        odd ^= 1;
        idx[0] = idx[1];
        idx[1] = i;
    }
    return 0;
}

static int skip_prop(reader *r, const ply_prop *p)
{
    double v, count = 1;
    if (p->count_type != P_NONE && value(r, p->count_type, &count))
        return 1;
    if (count < 0) {
        fail(r, "property %s: a list of %.0f items", p->name, count);
        return 1;
    }
    for (double k = 0; k < count; k++)
        if (LIST_STOP(r, k) || value(r, p->type, &v))
            return 1;
    return 0;
}

static int read_element(reader *r, ply_mesh *m, const ply_elem *e)
{
    int is_v = !strcmp(e->name, "vertex");
    int is_f = !strcmp(e->name, "face"), is_s = !strcmp(e->name, "tristrips");
    int ch[8], list = -1; /* the vertex's properties: x y z [nx ny nz] [u v] */
    r->e = e;
    r->item = 0;
    if (is_v) {
        if (m->have_vertices) {
            fail(r, "a second vertex element");
            return 1;
        }
        m->have_vertices = 1;
        for (int k = 0; k < 3; k++) {
            ch[k] = find_prop(e, (const char *[]){"x", "y", "z"}[k]);
            if (ch[k] < 0 || e->props[ch[k]].count_type != P_NONE) {
                fail(r, "the vertex element has no scalar property %c", "xyz"[k]);
                return 1;
            }
        }
        m->vstride = 3;
        m->nofs = vertex_channels(e, (const char *[]){"nx", "ny", "nz"}, 3, ch, &m->vstride);
        /* texture coordinates, v up (as OBJ's vt): the names PLY files use */
        static const char *uvn[][2] = {{"u", "v"}, {"s", "t"}, {"texture_u", "texture_v"},
                                       {"texture_s", "texture_t"}};
        m->uofs = -1;
        for (int k = 0; k < 4 && m->uofs < 0; k++)
            m->uofs = vertex_channels(e, uvn[k], 2, ch, &m->vstride);
        if (find_prop(e, "red") >= 0 || find_prop(e, "diffuse_red") >= 0)
            m->ignored |= SPM_MESH_IGN_COLOURS;
    } else if (is_f || is_s) {
        list = find_prop(e, "vertex_indices");
        if (list < 0)
            list = find_prop(e, "vertex_index");
        if (list < 0 || e->props[list].count_type == P_NONE || e->props[list].type >= P_F32) {
            fail(r, "no list of integer vertex_indices");
            return 1;
        }
        if (!m->have_vertices && e->count) {
            fail(r, "the element comes before the vertex element");
            return 1;
        }
    }
    if (e->nprops == 0)
        return (r->e = NULL, 0); /* no bytes to read: any count costs nothing */
    /* binary vertices of scalar properties: a record of fixed size at a time */
    size_t rec = 0, at[8];
    int scalar = is_v && r->format != F_ASCII;
    for (int k = 0; k < e->nprops && scalar; k++) {
        for (int c = 0; c < m->vstride; c++)
            if (k == ch[c])
                at[c] = rec;
        scalar = e->props[k].count_type == P_NONE;
        rec += (size_t)type_size[e->props[k].type];
    }
    for (; scalar && r->item < e->count; r->item++) {
        if ((r->item & 0xffff) == 0 && stop_requested(r, 0))
            return 1;
        const unsigned char *b = need(r, rec);
        if (!b)
            return 1;
        if (m->nv == m->capv) {
            m->capv = m->capv ? 2 * m->capv : 1024;
            m->v = spm_xrealloc(m->v, m->capv * (uint64_t)m->vstride * sizeof *m->v);
        }
        float *v = &m->v[(uint64_t)m->vstride * m->nv++];
        for (int c = 0; c < m->vstride; c++)
            v[c] = (float)decode(b + at[c], e->props[ch[c]].type, r->swap);
    }
    for (; r->item < e->count; r->item++) {
        if ((r->item & 0xffff) == 0 && stop_requested(r, 0))
            return 1;
        for (int k = 0; k < e->nprops; k++) {
            const ply_prop *p = &e->props[k];
            if (k == list) {
                if (read_indices(r, m, p, is_s))
                    return 1;
            } else if (is_v && channel_of(ch, m->vstride, k) >= 0) {
                double v;
                if (value(r, p->type, &v))
                    return 1;
                if (m->nv == m->capv) {
                    m->capv = m->capv ? 2 * m->capv : 1024;
                    m->v = spm_xrealloc(m->v, m->capv * (uint64_t)m->vstride * sizeof *m->v);
                }
                int c = channel_of(ch, m->vstride, k);
                m->v[(uint64_t)m->vstride * m->nv + (uint64_t)c] = (float)v;
            } else if (skip_prop(r, p)) {
                return 1;
            }
        }
        m->nv += is_v;
    }
    r->e = NULL;
    return 0;
}

int spm_ply_read(const spm_file *file, spm_mesh_data *out, spm_error *err)
{
    memset(out, 0, sizeof *out);
    const char *path = file->shown;
    FILE *f = spm_path_fopen(file, "rb");
    if (!f) {
        spm_errorf(err, "%s: cannot open: %s", path, strerror(errno));
        return 1;
    }
    reader r;
    memset(&r, 0, sizeof r);
    r.f = f, r.path = path, r.err = err;
    static ply_header h; /* 64 elements of 64 properties: kept off the stack */
    ply_mesh m;
    memset(&m, 0, sizeof m);
    int rc = parse_header(&r, &h);
    if (!rc) {
        for (int i = 0; i < h.nelems; i++)
            r.strips |= !strcmp(h.elems[i].name, "tristrips");
        if (h.format != F_ASCII)
            r.block = spm_xmalloc(PLY_BLOCK);
        uint16_t one = 1;
        int little = *(unsigned char *)&one == 1;
        r.format = h.format;
        r.swap = h.format != F_ASCII && (h.format == F_LE) != little;
        r.offset = (uint64_t)ftell(f);
        r.line++; /* the line after end_header */
        for (int i = 0; i < h.nelems && !rc; i++)
            rc = read_element(&r, &m, &h.elems[i]);
    }
    fclose(f);
    free(r.block);
    if (r.polygon)
        rc = SPM_PLY_POLYGONS;
    if (!rc && !m.have_vertices) {
        spm_errorf(err, "%s: the file has no vertex element", path);
        rc = 1;
    }
    if (!rc) {
        spm_mesh_material mat;
        memset(&mat, 0, sizeof mat);
        spm_mesh_data d = {m.ignored, 1, m.nt, &mat, m.t, m.nofs >= 0 ? m.tn : NULL,
                           m.uofs >= 0 ? m.tuv : NULL, NULL, "", NULL, 0, 0, NULL, NULL};
        size_t size;
        void *buf = spm_mesh_encode(&d, &size);
        rc = spm_mesh_decode(buf, size, path, out, err); /* no triangles: its error */
        if (rc)
            free(buf);
    }
    free(m.v);
    free(m.t);
    free(m.tn);
    free(m.tuv);
    return rc;
}

/* A plugin's properties: its children <float name=... value=...>,
 * <integer>, <boolean>, <string>, <point>, <vector>, <transform>, read by
 * name and checked by tag and value; each read one is marked, and what no
 * code read is warned about by name (mi_unused). Transforms compose as
 * Mitsuba's: each operation applies after the ones written before it. */
#include "mitsuba.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

static int tag_in(const char *tag, const char *tags)
{
    size_t n = strlen(tag);
    for (const char *s = tags; *s;) {
        const char *e = strchr(s, '|');
        size_t k = e ? (size_t)(e - s) : strlen(s);
        if (k == n && !strncmp(s, tag, n))
            return 1;
        s += k + (e != NULL);
    }
    return 0;
}

mi_node *mi_prop(mi_node *pl, const char *name, const char *tags, int *bad, spm_error *err)
{
    for (int i = 0; i < pl->nkids; i++) {
        mi_node *k = pl->kids[i];
        const char *kn = mi_attr(k, "name");
        if (!kn || strcmp(kn, name))
            continue;
        k->used = 1;
        if (!tag_in(k->tag, tags)) {
            spm_errorf(err, "%s: '%s' is a <%s>, not one of %s", k->where, name, k->tag, tags);
            *bad = 1;
            return NULL;
        }
        return k;
    }
    return NULL;
}

int mi_numbers(const char *s, double *out, int max)
{
    int n = 0;
    while (*s) {
        while (*s == ' ' || *s == ',' || *s == '\t' || *s == '\n' || *s == '\r')
            s++;
        if (!*s)
            break;
        char *end;
        double v = strtod(s, &end);
        if (end == s || n == max || !isfinite(v))
            return -1;
        out[n++] = v;
        s = end;
    }
    return n;
}

/* One number in attribute `attr` of n (strict: "1.5x" is an error). */
static int number(const mi_node *n, const char *attr, double *out, spm_error *err)
{
    const char *v = mi_attr(n, attr);
    if (!v || mi_numbers(v, out, 1) != 1) {
        const char *name = mi_attr(n, "name");
        spm_errorf(err, "%s: <%s%s%s%s> %s=\"%.60s\" is not a number", n->where, n->tag,
                   name ? " name=\"" : "", name ? name : "", name ? "\"" : "", attr,
                   v ? v : "(missing)");
        return 1;
    }
    return 0;
}

double mi_float(mi_node *pl, const char *name, double def, int *bad, spm_error *err)
{
    mi_node *k = mi_prop(pl, name, "float|integer", bad, err);
    double v = def;
    if (k && number(k, "value", &v, err))
        *bad = 1;
    return v;
}

int mi_int(mi_node *pl, const char *name, int def, int *bad, spm_error *err)
{
    mi_node *k = mi_prop(pl, name, "integer", bad, err);
    double v = def;
    if (k && (number(k, "value", &v, err) || v != floor(v) || fabs(v) > 2e9)) {
        if (v != floor(v) || fabs(v) > 2e9)
            spm_errorf(err, "%s: '%s' %g is not an integer", k->where, name, v);
        *bad = 1;
    }
    return (int)v;
}

int mi_bool(mi_node *pl, const char *name, int def, int *bad, spm_error *err)
{
    mi_node *k = mi_prop(pl, name, "boolean", bad, err);
    if (!k)
        return def;
    const char *v = mi_attr(k, "value");
    if (v && !strcmp(v, "true"))
        return 1;
    if (v && !strcmp(v, "false"))
        return 0;
    spm_errorf(err, "%s: '%s' is \"%s\": a boolean is true or false", k->where, name,
               v ? v : "(missing)");
    *bad = 1;
    return def;
}

const char *mi_string(mi_node *pl, const char *name, const char *def, int *bad,
                      spm_error *err)
{
    mi_node *k = mi_prop(pl, name, "string", bad, err);
    const char *v = k ? mi_attr(k, "value") : def;
    if (k && !v) {
        spm_errorf(err, "%s: <string> '%s' has no value", k->where, name);
        *bad = 1;
    }
    return v;
}

int mi_vec3(const mi_node *n, const char *attrs[3], const char *value_attr, double out[3],
            spm_error *err)
{
    const char *v = value_attr ? mi_attr(n, value_attr) : NULL;
    if (v) {
        int k = mi_numbers(v, out, 3);
        if (k == 1)
            out[1] = out[2] = out[0];
        if (k == 1 || k == 3)
            return 0;
        spm_errorf(err, "%s: <%s> %s=\"%.60s\": one or three numbers", n->where, n->tag,
                   value_attr, v);
        return 1;
    }
    for (int i = 0; i < 3; i++)
        if (mi_attr(n, attrs[i]) && number(n, attrs[i], &out[i], err))
            return 1;
    return 0;
}

/* Mitsuba's look_at: columns left = up x dir, up' = dir x left, dir, origin
 * (the inverse of pbrt's LookAt, whose right is the same up x dir). */
static int lookat(const mi_node *k, double m[4][4], spm_error *err)
{
    double o[3], t[3], u[3], inv[4][4];
    const char *names[3] = {"origin", "target", "up"};
    double *v[3] = {o, t, u};
    for (int i = 0; i < 3; i++) {
        const char *s = mi_attr(k, names[i]);
        if (!s && i == 2) { /* Mitsuba's default up: any vector normal to the view */
            u[0] = 0, u[1] = 1, u[2] = 0;
            continue;
        }
        if (!s || mi_numbers(s, v[i], 3) != 3) {
            spm_errorf(err, "%s: <lookat> %s: three numbers", k->where, names[i]);
            return 1;
        }
    }
    if (pbrt_mat_lookat(o, t, u, inv) || pbrt_mat_inverse(inv, m)) {
        spm_errorf(err, "%s: <lookat>: origin equals target, or up is along the view", k->where);
        return 1;
    }
    return 0;
}

/* One operation of a <transform>: its matrix. */
static int operation(const mi_node *k, double op[4][4], spm_error *err)
{
    const char *xyz[3] = {"x", "y", "z"};
    double v[3] = {0, 0, 0};
    pbrt_mat_identity(op);
    if (!strcmp(k->tag, "translate"))
        return mi_vec3(k, xyz, "value", v, err) || (pbrt_mat_translate(v, op), 0);
    if (!strcmp(k->tag, "scale")) {
        v[0] = v[1] = v[2] = 1;
        return mi_vec3(k, xyz, "value", v, err) || (pbrt_mat_scale(v, op), 0);
    }
    if (!strcmp(k->tag, "rotate")) {
        double a = 0;
        if (mi_vec3(k, xyz, "value", v, err) || number(k, "angle", &a, err))
            return 1;
        if (pbrt_mat_rotate(a, v, op)) {
            spm_errorf(err, "%s: <rotate> about a zero axis", k->where);
            return 1;
        }
        return 0;
    }
    if (!strcmp(k->tag, "matrix")) {
        double m[16];
        const char *s = mi_attr(k, "value");
        int n = s ? mi_numbers(s, m, 16) : -1;
        if (n != 16 && n != 9) {
            spm_errorf(err, "%s: <matrix> value: 16 numbers (or 9), row by row", k->where);
            return 1;
        }
        int w = n == 16 ? 4 : 3;
        for (int i = 0; i < w; i++)
            for (int j = 0; j < w; j++)
                op[i][j] = m[i * w + j];
        return 0;
    }
    if (!strcmp(k->tag, "lookat"))
        return lookat(k, op, err);
    spm_errorf(err, "%s: <%s> inside <transform> (Mitsuba has translate, rotate, scale, "
                    "matrix, lookat)", k->where, k->tag);
    return 1;
}

int mi_transform(mi_node *t, double m[4][4], spm_error *err)
{
    pbrt_mat_identity(m);
    for (int i = 0; i < t->nkids; i++) {
        double op[4][4], r[4][4];
        t->kids[i]->used = 1;
        if (operation(t->kids[i], op, err))
            return 1;
        pbrt_mat_mul(op, m, r);
        memcpy(m, r, sizeof r);
    }
    return 0;
}

int mi_to_world(mi_node *pl, double m[4][4], spm_error *err)
{
    int bad = 0;
    mi_node *t = mi_prop(pl, "to_world", "transform", &bad, err);
    if (bad)
        return 1;
    if (!t) {
        pbrt_mat_identity(m);
        return 0;
    }
    return mi_transform(t, m, err);
}

int mi_unused(mi_node *pl, const char *what, spm_error *err)
{
    for (int i = 0; i < pl->nkids; i++) {
        mi_node *k = pl->kids[i];
        if (k->used)
            continue;
        k->used = 1;
        char w[300];
        const char *name = mi_attr(k, "name");
        snprintf(w, sizeof w, "%s: <%.30s%s%.60s%s>", what, k->tag, name ? " name=\"" : "",
                 name ? name : "", name ? "\"" : "");
        if (pbrt_warn(k->where, w, "not rendered", err))
            return 1;
    }
    return 0;
}

mi_node *mi_ref(mi_ids *ids, mi_node *ref, spm_error *err)
{
    const char *id = mi_attr(ref, "id");
    int i = id ? spm_names_get(&ids->ids, id) : -1;
    ref->used = 1;
    if (i < 0) {
        spm_errorf(err, "%s: <ref id=\"%s\">: no element has this id",
                   ref->where, id ? id : "");
        return NULL;
    }
    return ids->nodes[i];
}

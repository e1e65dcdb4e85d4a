/* A directive's parameter list: "TYPE NAME" then one value or a bracketed
 * list, checked against the type (pbrt-v4's types; "point", "vector",
 * "normal3" and "color" are its older spellings). A lookup by name checks the
 * type the directive expects; what no lookup used is warned about. */
#include "pbrt.h"
#include "interrupt.h"
#include <stdlib.h>
#include <string.h>

typedef enum { V_NUM, V_STR, V_BOOL, V_SPEC } vkind;

static const struct {
    const char *name;
    pbrt_ptype type;
    vkind kind;
    int per;      /* values per item: the count must be a multiple (0: exactly per) */
    int exactly;  /* the count is exactly `per` */
} types[] = {
    {"integer", PP_INTEGER, V_NUM, 1, 0},  {"float", PP_FLOAT, V_NUM, 1, 0},
    {"point2", PP_POINT2, V_NUM, 2, 0},    {"vector2", PP_VECTOR2, V_NUM, 2, 0},
    {"point3", PP_POINT3, V_NUM, 3, 0},    {"point", PP_POINT3, V_NUM, 3, 0},
    {"vector3", PP_VECTOR3, V_NUM, 3, 0},  {"vector", PP_VECTOR3, V_NUM, 3, 0},
    {"normal", PP_NORMAL, V_NUM, 3, 0},    {"normal3", PP_NORMAL, V_NUM, 3, 0},
    {"bool", PP_BOOL, V_BOOL, 1, 0},       {"string", PP_STRING, V_STR, 1, 0},
    {"texture", PP_TEXTURE, V_STR, 1, 1},  {"rgb", PP_RGB, V_NUM, 3, 1},
    {"color", PP_RGB, V_NUM, 3, 1},        {"blackbody", PP_BLACKBODY, V_NUM, 1, 1},
    {"spectrum", PP_SPECTRUM, V_SPEC, 2, 0},
};
#define NTYPES ((int)(sizeof types / sizeof types[0]))

void pbrt_params_free(pbrt_params *ps)
{
    for (int i = 0; i < ps->n; i++) {
        free(ps->p[i].num);
        for (size_t k = 0; k < ps->p[i].nstr; k++)
            free(ps->p[i].str[k]);
        free(ps->p[i].str);
    }
    free(ps->p);
    ps->p = NULL;
    ps->n = 0;
}

/* Room for element n of an array that holds n: capacities are the powers
 * of two, so a mesh of a million values is not copied a million times. */
static void grow(void **a, size_t n, size_t size)
{
    if (n < 8 ? n == 0 : (n & (n - 1)) == 0)
        *a = spm_xrealloc(*a, (n < 8 ? 8 : 2 * n) * size);
}

/* One value token into pa, as its kind takes it. */
static int value(pbrt_lexer *lx, pbrt_param *pa, vkind kind, spm_error *err)
{
    int is_bool = lx->type != PT_NUMBER && (!strcmp(lx->text, "true") || !strcmp(lx->text, "false"));
    if (kind == V_BOOL && (lx->type == PT_WORD || lx->type == PT_STRING) && is_bool) {
        grow((void **)&pa->num, pa->nnum, sizeof *pa->num);
        pa->num[pa->nnum++] = !strcmp(lx->text, "true");
    } else if ((kind == V_NUM || kind == V_SPEC) && lx->type == PT_NUMBER && pa->nstr == 0) {
        if (pa->type == PP_INTEGER && lx->num != (double)(long)lx->num)
            return pbrt_lex_expected(lx, err, "a whole number (an 'integer' parameter)");
        grow((void **)&pa->num, pa->nnum, sizeof *pa->num);
        pa->num[pa->nnum++] = lx->num;
    } else if ((kind == V_STR || (kind == V_SPEC && pa->nnum == 0 && pa->nstr == 0)) &&
               lx->type == PT_STRING) {
        grow((void **)&pa->str, pa->nstr, sizeof *pa->str);
        size_t n = strlen(lx->text) + 1;
        pa->str[pa->nstr] = spm_xmalloc(n);
        memcpy(pa->str[pa->nstr++], lx->text, n);
    } else {
        char what[128];
        snprintf(what, sizeof what, "%s of the '%s' parameter '%s'",
                 kind == V_NUM ? "a number" : kind == V_STR ? "a quoted string"
                 : kind == V_BOOL ? "true or false" : "numbers or one string",
                 pa->type_name, pa->name);
        return pbrt_lex_expected(lx, err, what);
    }
    return pbrt_lex_next(lx, err);
}

/* "TYPE NAME" (the lexer on it) into pa's type and name. */
static int declaration(pbrt_lexer *lx, pbrt_param *pa, int *t, spm_error *err)
{
    char tname[64], name[SPM_NAME_MAX + 1], extra;
    int fields = sscanf(lx->text, " %63s %64s %c", tname, name, &extra);
    if (fields != 2 || strlen(name) >= SPM_NAME_MAX)
        return pbrt_lex_expected(lx, err, "a parameter declaration \"TYPE NAME\"");
    for (*t = 0; *t < NTYPES && strcmp(types[*t].name, tname); (*t)++)
        ;
    if (*t == NTYPES) {
        spm_errorf(err, "%s:%d:%d: unknown parameter type '%s' (of '%s'; pbrt-v4's types: "
                        "integer, float, point2, vector2, point3, vector3, normal, bool, "
                        "string, texture, rgb, blackbody, spectrum)",
                   lx->path, lx->tline, lx->tcol, tname, name);
        return 1;
    }
    pa->type = types[*t].type;
    snprintf(pa->type_name, sizeof pa->type_name, "%.15s", tname);
    snprintf(pa->name, sizeof pa->name, "%s", name);
    pbrt_lex_where(lx, pa->where, sizeof pa->where);
    return 0;
}

static int count_check(const pbrt_lexer *lx, const pbrt_param *pa, int t, spm_error *err)
{
    size_t n = pa->nnum + pa->nstr, per = (size_t)types[t].per;
    int ok = n > 0 && (types[t].exactly ? n == per : n % per == 0);
    if (types[t].kind == V_SPEC && pa->nstr)
        ok = pa->nstr == 1;
    if (types[t].kind != V_NUM && types[t].kind != V_SPEC && !types[t].exactly)
        ok = n > 0;
    if (!ok)
        spm_errorf(err, "%s: parameter '%s %s' has %zu value%s; it takes %s%zu", pa->where,
                   pa->type_name, pa->name, n, n == 1 ? "" : "s",
                   types[t].exactly ? "exactly " : "a non-zero multiple of ", per);
    (void)lx;
    return !ok;
}

int pbrt_params_read(pbrt_lexer *lx, pbrt_params *ps, spm_error *err)
{
    while (lx->type == PT_STRING) {
        ps->p = spm_xrealloc(ps->p, (size_t)(ps->n + 1) * sizeof *ps->p);
        pbrt_param *pa = &ps->p[ps->n++];
        memset(pa, 0, sizeof *pa);
        int t = 0;
        if (declaration(lx, pa, &t, err))
            return 1;
        for (int i = 0; i < ps->n - 1; i++)
            if (!strcmp(ps->p[i].name, pa->name)) {
                spm_errorf(err, "%s: parameter '%s' given twice (first at %s)", pa->where,
                           pa->name, ps->p[i].where);
                return 1;
            }
        if (pbrt_lex_next(lx, err))
            return 1;
        if (lx->type == PT_LBRACK) {
            char open[600];
            pbrt_lex_where(lx, open, sizeof open);
            if (pbrt_lex_next(lx, err))
                return 1;
            while (lx->type != PT_RBRACK) {
                if ((pa->nnum & 0xffff) == 0xffff && spm_stop_requested()) {
                    spm_errorf(err, "%s: interrupted while reading '%s'", pa->where, pa->name);
                    return 1;
                }
                if (lx->type == PT_EOF) {
                    spm_errorf(err, "%s: unterminated '[' (no ']' before the end of the file)",
                               open);
                    return 1;
                }
                if (value(lx, pa, types[t].kind, err))
                    return 1;
            }
            if (pbrt_lex_next(lx, err))
                return 1;
        } else if (value(lx, pa, types[t].kind, err)) {
            return 1;
        }
        if (count_check(lx, pa, t, err))
            return 1;
    }
    return 0;
}

pbrt_param *pbrt_param_find(pbrt_params *ps, const char *name, unsigned mask, int *bad,
                            spm_error *err)
{
    for (int i = 0; i < ps->n; i++) {
        pbrt_param *pa = &ps->p[i];
        if (strcmp(pa->name, name))
            continue;
        pa->used = 1;
        if (mask & (1u << pa->type))
            return pa;
        if (!*bad)
            spm_errorf(err, "%s: parameter '%s' cannot be of type '%s' here", pa->where, name,
                       pa->type_name);
        *bad = 1;
        return NULL;
    }
    return NULL;
}

static pbrt_param *single(pbrt_params *ps, const char *name, unsigned mask, int *bad,
                          spm_error *err)
{
    pbrt_param *pa = pbrt_param_find(ps, name, mask, bad, err);
    if (pa && pa->nnum + pa->nstr != 1) {
        if (!*bad)
            spm_errorf(err, "%s: parameter '%s' takes one value, not %zu", pa->where, name,
                       pa->nnum + pa->nstr);
        *bad = 1;
        return NULL;
    }
    return pa;
}

double pbrt_param_float(pbrt_params *ps, const char *name, double def, int *bad, spm_error *err)
{
    pbrt_param *pa = single(ps, name, 1u << PP_FLOAT | 1u << PP_INTEGER, bad, err);
    return pa ? pa->num[0] : def;
}

int pbrt_param_int(pbrt_params *ps, const char *name, int def, int *bad, spm_error *err)
{
    pbrt_param *pa = single(ps, name, 1u << PP_INTEGER, bad, err);
    if (pa && !(pa->num[0] >= -2147483647.0 && pa->num[0] <= 2147483647.0)) {
        if (!*bad)
            spm_errorf(err, "%s: parameter '%s': %g is out of range", pa->where, name, pa->num[0]);
        *bad = 1;
        return def;
    }
    return pa ? (int)pa->num[0] : def;
}

int pbrt_param_bool(pbrt_params *ps, const char *name, int def, int *bad, spm_error *err)
{
    pbrt_param *pa = single(ps, name, 1u << PP_BOOL, bad, err);
    return pa ? pa->num[0] != 0 : def;
}

const char *pbrt_param_string(pbrt_params *ps, const char *name, const char *def, int *bad,
                              spm_error *err)
{
    pbrt_param *pa = single(ps, name, 1u << PP_STRING, bad, err);
    return pa ? pa->str[0] : def;
}

int pbrt_params_unused(const pbrt_params *ps, const char *what, spm_error *err)
{
    for (int i = 0; i < ps->n; i++)
        if (!ps->p[i].used) {
            char w[256];
            snprintf(w, sizeof w, "%.120s: parameter '%s %s'", what, ps->p[i].type_name,
                     ps->p[i].name);
            if (pbrt_warn(ps->p[i].where, w, "not rendered", err))
                return 1;
        }
    return 0;
}

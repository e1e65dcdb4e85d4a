/* JSON by recursive descent (json.h). */
#include "json.h"
#include "util.h"
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_DEPTH 128

typedef struct {
    const char *s, *end, *line_start;
    int line, depth;
    char *why;
    size_t whylen;
} reader;

static int fail(reader *r, const char *what)
{
    if (r->why[0] == '\0')
        snprintf(r->why, r->whylen, "line %d, column %d: %s", r->line,
                 (int)(r->s - r->line_start) + 1, what);
    return 1;
}

static void skip_space(reader *r)
{
    while (r->s < r->end && (*r->s == ' ' || *r->s == '\t' || *r->s == '\r' || *r->s == '\n')) {
        if (*r->s == '\n') {
            r->line++;
            r->line_start = r->s + 1;
        }
        r->s++;
    }
}

static int hex4(reader *r, unsigned *out)
{
    *out = 0;
    for (int i = 0; i < 4; i++, r->s++) {
        int c = r->s < r->end ? (unsigned char)*r->s : -1, d;
        d = c >= '0' && c <= '9' ? c - '0' : c >= 'a' && c <= 'f' ? c - 'a' + 10
            : c >= 'A' && c <= 'F' ? c - 'A' + 10 : -1;
        if (d < 0)
            return fail(r, "four hexadecimal digits after \\u");
        *out = *out * 16 + (unsigned)d;
    }
    return 0;
}

static size_t put_utf8(char *o, unsigned cp)
{
    if (cp < 0x80) {
        o[0] = (char)cp;
        return 1;
    }
    if (cp < 0x800) {
        o[0] = (char)(0xC0 | cp >> 6);
        o[1] = (char)(0x80 | (cp & 0x3F));
        return 2;
    }
    if (cp < 0x10000) {
        o[0] = (char)(0xE0 | cp >> 12);
        o[1] = (char)(0x80 | (cp >> 6 & 0x3F));
        o[2] = (char)(0x80 | (cp & 0x3F));
        return 3;
    }
    o[0] = (char)(0xF0 | cp >> 18);
    o[1] = (char)(0x80 | (cp >> 12 & 0x3F));
    o[2] = (char)(0x80 | (cp >> 6 & 0x3F));
    o[3] = (char)(0x80 | (cp & 0x3F));
    return 4;
}

/* An escape after the backslash, into o: its byte count, 0 on error. */
static size_t escape(reader *r, char *o)
{
    static const char from[] = "\"\\/bfnrt", to[] = "\"\\/\b\f\n\r\t";
    char c = r->s < r->end ? *r->s : '\0';
    const char *k = c ? strchr(from, c) : NULL;
    if (k) {
        r->s++;
        *o = to[k - from];
        return 1;
    }
    if (c != 'u')
        return fail(r, "an escape (\\\" \\\\ \\/ \\b \\f \\n \\r \\t or \\uXXXX)"), 0;
    r->s++;
    unsigned cp, lo;
    if (hex4(r, &cp))
        return 0;
    if (cp >= 0xD800 && cp < 0xDC00) { /* a high surrogate wants its low half */
        if (r->end - r->s < 2 || r->s[0] != '\\' || r->s[1] != 'u')
            return fail(r, "the low half of a surrogate pair"), 0;
        r->s += 2;
        if (hex4(r, &lo) || lo < 0xDC00 || lo > 0xDFFF)
            return fail(r, "the low half of a surrogate pair"), 0;
        cp = 0x10000 + ((cp - 0xD800) << 10) + (lo - 0xDC00);
    } else if (cp >= 0xDC00 && cp < 0xE000) {
        return fail(r, "a high surrogate before a low one"), 0;
    }
    if (cp == 0)
        return fail(r, "a character other than \\u0000"), 0;
    return put_utf8(o, cp);
}

static int string(reader *r, char **out)
{
    r->s++; /* the opening quote */
    const char *q = r->s;
    while (q < r->end && *q != '"')
        q += *q == '\\' ? 2 : 1;
    if (q >= r->end)
        return fail(r, "the string's closing '\"'");
    char *o = spm_xmalloc((size_t)(q - r->s) * 2 + 1), *w = o;
    while (*r->s != '"') {
        unsigned char c = (unsigned char)*r->s;
        if (c < 0x20) {
            free(o);
            return fail(r, "no control character inside a string");
        }
        if (c == '\\') {
            r->s++;
            size_t k = escape(r, w);
            if (!k) {
                free(o);
                return 1;
            }
            w += k;
        } else {
            *w++ = (char)c;
            r->s++;
        }
    }
    r->s++;
    *w = '\0';
    *out = o;
    return 0;
}

static int number(reader *r, double *out)
{
    const char *p = r->s;
    if (p < r->end && *p == '-')
        p++;
    if (p >= r->end || *p < '0' || *p > '9')
        return fail(r, "a value (object, array, string, number, true, false or null)");
    char buf[64];
    size_t n = 0;
    const char *q = r->s;
    while (q < r->end && strchr("+-0123456789.eE", *q) && n < sizeof buf - 1)
        buf[n++] = *q++;
    buf[n] = '\0';
    char *e;
    *out = strtod(buf, &e);
    if (e == buf)
        return fail(r, "a number");
    r->s += e - buf;
    return 0;
}

static int value(reader *r, spm_json *v);

/* The members of an object or the items of an array, after its bracket. */
static int members(reader *r, spm_json *v, int object)
{
    char close = object ? '}' : ']';
    size_t cap = 0;
    r->s++;
    skip_space(r);
    if (r->s < r->end && *r->s == close) {
        r->s++;
        return 0;
    }
    for (;;) {
        if (v->n == cap) {
            cap = cap ? cap * 2 : 4;
            v->items = spm_xrealloc(v->items, cap * sizeof *v->items);
        }
        spm_json *it = &v->items[v->n];
        memset(it, 0, sizeof *it);
        v->n++;
        skip_space(r);
        if (object) {
            if (r->s >= r->end || *r->s != '"')
                return fail(r, "a member's name in quotes");
            if (string(r, &it->key))
                return 1;
            skip_space(r);
            if (r->s >= r->end || *r->s != ':')
                return fail(r, "':' after the member's name");
            r->s++;
        }
        if (value(r, it))
            return 1;
        skip_space(r);
        if (r->s < r->end && *r->s == ',') {
            r->s++;
            continue;
        }
        if (r->s < r->end && *r->s == close) {
            r->s++;
            return 0;
        }
        return fail(r, object ? "',' or '}'" : "',' or ']'");
    }
}

static int literal(reader *r, const char *word)
{
    size_t n = strlen(word);
    if ((size_t)(r->end - r->s) < n || memcmp(r->s, word, n))
        return fail(r, "a value (object, array, string, number, true, false or null)");
    r->s += n;
    return 0;
}

static int value(reader *r, spm_json *v)
{
    skip_space(r);
    if (r->s >= r->end)
        return fail(r, "a value, not the end of the text");
    if (r->depth >= MAX_DEPTH)
        return fail(r, "at most 128 nested arrays and objects");
    int rc;
    r->depth++;
    switch (*r->s) {
    case '{': v->type = SPM_JSON_OBJECT; rc = members(r, v, 1); break;
    case '[': v->type = SPM_JSON_ARRAY; rc = members(r, v, 0); break;
    case '"': v->type = SPM_JSON_STRING; rc = string(r, &v->string); break;
    case 't': v->type = SPM_JSON_BOOL; v->number = 1; rc = literal(r, "true"); break;
    case 'f': v->type = SPM_JSON_BOOL; rc = literal(r, "false"); break;
    case 'n': v->type = SPM_JSON_NULL; rc = literal(r, "null"); break;
    default: v->type = SPM_JSON_NUMBER; rc = number(r, &v->number); break;
    }
    r->depth--;
    return rc;
}

static void free_inner(spm_json *v)
{
    for (size_t i = 0; i < v->n; i++)
        free_inner(&v->items[i]);
    free(v->items);
    free(v->string);
    free(v->key);
}

void spm_json_free(spm_json *v)
{
    if (v) {
        free_inner(v);
        free(v);
    }
}

spm_json *spm_json_parse(const char *text, size_t len, char *why, size_t whylen)
{
    reader r = {text, text + len, text, 1, 0, why, whylen};
    why[0] = '\0';
    spm_json *v = spm_xcalloc(1, sizeof *v);
    int rc = value(&r, v);
    skip_space(&r);
    if (!rc && r.s != r.end)
        rc = fail(&r, "the end of the text after the value");
    if (rc) {
        spm_json_free(v);
        return NULL;
    }
    return v;
}

const spm_json *spm_json_get(const spm_json *v, const char *key)
{
    if (!v || v->type != SPM_JSON_OBJECT)
        return NULL;
    for (size_t i = 0; i < v->n; i++)
        if (strcmp(v->items[i].key, key) == 0)
            return &v->items[i];
    return NULL;
}

const char *spm_json_string(const spm_json *v, const char *key)
{
    const spm_json *m = spm_json_get(v, key);
    return m && m->type == SPM_JSON_STRING ? m->string : NULL;
}

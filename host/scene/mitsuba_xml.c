/* Mitsuba 3 XML files read into one tree of elements by expat (which
 * fetches no external entity and no DTD; its own guard bounds entity
 * expansion). Done while reading, in the file's order as Mitsuba does:
 * `default` gives a parameter its value unless the command line (-D) or an
 * earlier `default` did; `$name` in an attribute is replaced by its value
 * (an undefined one is an error); `include` reads a file, by the path rule,
 * and splices the children of its <scene> in place (cycles and nesting
 * deeper than MI_MAX_INCLUDE_DEPTH are errors); `path` adds a folder that
 * later file names are looked for in. */
#include "mitsuba.h"
#include "interrupt.h"
#include <errno.h>
#include <expat.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

static const char *mi_defines[MI_MAX_DEFINES];
static int mi_ndefines;

int spm_scene_define(const char *nv, spm_error *err)
{
    const char *eq = strchr(nv, '=');
    if (!eq || eq == nv) {
        spm_errorf(err, "-D %s: expected NAME=VALUE", nv);
        return 1;
    }
    if (mi_ndefines == MI_MAX_DEFINES) {
        spm_errorf(err, "-D %s: more than %d parameters", nv, MI_MAX_DEFINES);
        return 1;
    }
    mi_defines[mi_ndefines++] = nv;
    return 0;
}

typedef struct {
    mi_doc *doc;
    spm_error *err;
    char **pname, **pval;     /* parameters: -D ones first, then `default`s */
    int nparams;
    char canon[MI_MAX_INCLUDE_DEPTH][SPM_PATH_MAX];
    int depth;
} reader;

typedef struct {
    reader *r;
    XML_Parser xp;
    const char *shown, *dir;
    mi_node **stack;          /* the open elements; stack[0] a holder for the root */
    int nstack;
    int failed;
} frame;

static int read_file(reader *r, const spm_file *f, const char *where, mi_node *into);

const char *mi_attr(const mi_node *n, const char *name)
{
    for (int i = 0; i < n->nattr; i++)
        if (!strcmp(n->attr[2 * i], name))
            return n->attr[2 * i + 1];
    return NULL;
}

static void node_free(mi_node *n)
{
    if (!n)
        return;
    for (int i = 0; i < n->nkids; i++)
        node_free(n->kids[i]);
    for (int i = 0; i < 2 * n->nattr; i++)
        free(n->attr[i]);
    free(n->attr);
    free(n->kids);
    free(n->tag);
    free(n);
}

void mi_doc_free(mi_doc *doc)
{
    node_free(doc->root);
    for (int i = 0; i < doc->ndirs; i++)
        free(doc->dirs[i]);
    for (int i = 0; i < doc->nsearch; i++)
        free(doc->search[i]);
    free(doc->dirs);
    free(doc->search);
    memset(doc, 0, sizeof *doc);
}

static void add_kid(mi_node *parent, mi_node *kid)
{
    parent->kids = spm_xrealloc(parent->kids, (size_t)(parent->nkids + 1) * sizeof *kid);
    parent->kids[parent->nkids++] = kid;
}

static void where_now(frame *f, char *buf, size_t size)
{
    snprintf(buf, size, "%s:%lu:%lu", f->shown, (unsigned long)XML_GetCurrentLineNumber(f->xp),
             (unsigned long)XML_GetCurrentColumnNumber(f->xp) + 1);
}

static void fail(frame *f)
{
    f->failed = 1;
    XML_StopParser(f->xp, XML_FALSE);
}

static const char *param_get(const reader *r, const char *name)
{
    for (int i = 0; i < r->nparams; i++)
        if (!strcmp(r->pname[i], name))
            return r->pval[i];
    return NULL;
}

static void param_put(reader *r, const char *name, size_t nlen, const char *value)
{
    r->pname = spm_xrealloc(r->pname, (size_t)(r->nparams + 1) * sizeof *r->pname);
    r->pval = spm_xrealloc(r->pval, (size_t)(r->nparams + 1) * sizeof *r->pval);
    r->pname[r->nparams] = spm_xmalloc(nlen + 1);
    memcpy(r->pname[r->nparams], name, nlen);
    r->pname[r->nparams][nlen] = 0;
    r->pval[r->nparams++] = spm_xstrdup(value);
}

/* value with each $name replaced: a malloc'd string, or NULL with err. */
static char *substitute(frame *f, const char *where, const char *attr, const char *value)
{
    size_t cap = strlen(value) + 1, n = 0;
    char *out = spm_xmalloc(cap);
    for (const char *s = value; *s;) {
        size_t k = 0;
        if (*s == '$')
            while (s[1 + k] == '_' || (s[1 + k] >= 'a' && s[1 + k] <= 'z') ||
                   (s[1 + k] >= 'A' && s[1 + k] <= 'Z') || (s[1 + k] >= '0' && s[1 + k] <= '9'))
                k++;
        const char *rep = NULL;
        if (k) {
            char name[SPM_NAME_MAX];
            snprintf(name, sizeof name, "%.*s", (int)k, s + 1);
            rep = param_get(f->r, name);
            if (!rep) {
                spm_errorf(f->r->err, "%s: attribute %s=\"%.100s\": parameter '$%s' is not "
                                      "defined (a <default name=\"%s\" value=...> or -D %s=...)",
                           where, attr, value, name, name, name);
                free(out);
                return NULL;
            }
        }
        size_t add = rep ? strlen(rep) : 1;
        if (n + add + 1 > cap)
            out = spm_xrealloc(out, cap = 2 * (n + add + 1));
        memcpy(out + n, rep ? rep : s, add);
        n += add;
        s += rep ? k + 1 : 1;
    }
    out[n] = 0;
    return out;
}

static int on_default(frame *f, mi_node *n)
{
    const char *name = mi_attr(n, "name"), *value = mi_attr(n, "value");
    if (!name || !value || !*name) {
        spm_errorf(f->r->err, "%s: <default> needs 'name' and 'value'", n->where);
        return 1;
    }
    if (!param_get(f->r, name))
        param_put(f->r, name, strlen(name), value);
    return 0;
}

static int on_include(frame *f, mi_node *n, mi_node *parent)
{
    const char *ref = mi_attr(n, "filename");
    if (!ref) {
        spm_errorf(f->r->err, "%s: <include> needs 'filename'", n->where);
        return 1;
    }
    spm_file path;
    return mi_file(f->r->doc, n, ref, &path, f->r->err) ||
           read_file(f->r, &path, n->where, parent);
}

static int on_path(frame *f, mi_node *n)
{
    const char *ref = mi_attr(n, "value");
    spm_file path;
    if (!ref) {
        spm_errorf(f->r->err, "%s: <path> needs 'value'", n->where);
        return 1;
    }
    if (spm_path_check(n->dir, ref, n->where, &path, f->r->err))
        return 1;
    mi_doc *d = f->r->doc;
    d->search = spm_xrealloc(d->search, (size_t)(d->nsearch + 1) * sizeof *d->search);
    d->search[d->nsearch++] = spm_xstrdup(path.shown);
    return 0;
}

static void XMLCALL on_start(void *ud, const XML_Char *tag, const XML_Char **attrs)
{
    frame *f = ud;
    if (f->failed)
        return;
    mi_node *n = spm_xcalloc(1, sizeof *n);
    n->tag = spm_xstrdup(tag);
    n->dir = f->dir;
    where_now(f, n->where, sizeof n->where);
    for (int i = 0; attrs[i]; i += 2) {
        char *v = substitute(f, n->where, attrs[i], attrs[i + 1]);
        if (!v) {
            node_free(n);
            fail(f);
            return;
        }
        n->attr = spm_xrealloc(n->attr, (size_t)(n->nattr + 1) * 2 * sizeof *n->attr);
        n->attr[2 * n->nattr] = spm_xstrdup(attrs[i]);
        n->attr[2 * n->nattr++ + 1] = v;
    }
    mi_node *parent = f->stack[f->nstack - 1];
    int rc = 0;
    if (!strcmp(tag, "default"))
        rc = on_default(f, n);
    else if (!strcmp(tag, "include"))
        rc = on_include(f, n, parent);
    else if (!strcmp(tag, "path"))
        rc = on_path(f, n);
    if (rc)
        fail(f);
    add_kid(parent, n);
    f->stack = spm_xrealloc(f->stack, (size_t)(f->nstack + 1) * sizeof *f->stack);
    f->stack[f->nstack++] = n;
    n->used = !strcmp(tag, "default") || !strcmp(tag, "include") || !strcmp(tag, "path");
}

static void XMLCALL on_end(void *ud, const XML_Char *tag)
{
    frame *f = ud;
    (void)tag;
    if (f->nstack > 1)
        f->nstack--;
}

/* The file's bytes, whole. */
static char *slurp(const spm_file *p, size_t *n, spm_error *err)
{
    FILE *fp = spm_path_fopen(p, "rb");
    if (!fp) {
        spm_errorf(err, "%s: cannot open: %s", p->shown, strerror(errno));
        return NULL;
    }
    size_t cap = 1 << 16;
    char *buf = spm_xmalloc(cap);
    *n = 0;
    size_t got;
    while ((got = fread(buf + *n, 1, cap - *n, fp)) > 0) {
        *n += got;
        if (*n == cap) {
            if (cap >= MI_MAX_FILE_BYTES) {
                spm_errorf(err, "%s: larger than %llu bytes", p->shown,
                           (unsigned long long)MI_MAX_FILE_BYTES);
                fclose(fp);
                free(buf);
                return NULL;
            }
            buf = spm_xrealloc(buf, cap *= 2);
        }
    }
    fclose(fp);
    return buf;
}

/* Parses the checked file f; its root, a <scene>, is spliced into `into`
 * (the document's holder for the top file). */
static int read_file(reader *r, const spm_file *file, const char *where, mi_node *into)
{
    for (int i = 0; i < r->depth; i++)
        if (!strcmp(r->canon[i], file->path)) {
            spm_errorf(r->err, "%s: include cycle: '%s' is already being read", where,
                       file->shown);
            return 1;
        }
    if (r->depth == MI_MAX_INCLUDE_DEPTH) {
        spm_errorf(r->err, "%s: includes nested more than %d deep", where, MI_MAX_INCLUDE_DEPTH);
        return 1;
    }
    if (spm_stop_requested()) {
        spm_errorf(r->err, "interrupted while loading %s", file->shown);
        return 1;
    }
    size_t n;
    char *buf = slurp(file, &n, r->err);
    if (!buf)
        return 1;
    mi_doc *d = r->doc;
    char dir[SPM_PATH_MAX];
    d->dirs = spm_xrealloc(d->dirs, (size_t)(d->ndirs + 1) * sizeof *d->dirs);
    d->dirs[d->ndirs++] = spm_xstrdup(spm_path_dir(file->shown, dir, sizeof dir));
    snprintf(r->canon[r->depth++], SPM_PATH_MAX, "%s", file->path);
    mi_node holder = {0};
    frame f = {.r = r, .shown = file->shown, .dir = d->dirs[d->ndirs - 1]};
    f.stack = spm_xmalloc(sizeof *f.stack);
    f.stack[f.nstack++] = &holder;
    f.xp = XML_ParserCreate(NULL);
    XML_SetUserData(f.xp, &f);
    XML_SetElementHandler(f.xp, on_start, on_end);
    int ok = XML_Parse(f.xp, buf, (int)n, 1) == XML_STATUS_OK && !f.failed;
    if (!ok && !f.failed) {
        char w[SPM_PATH_MAX + 64];
        where_now(&f, w, sizeof w);
        spm_errorf(r->err, "%s: malformed XML: %s", w, XML_ErrorString(XML_GetErrorCode(f.xp)));
    }
    XML_ParserFree(f.xp);
    free(f.stack);
    free(buf);
    r->depth--;
    mi_node *root = holder.nkids ? holder.kids[0] : NULL;
    if (ok && (!root || strcmp(root->tag, "scene"))) {
        spm_errorf(r->err, "%s: the root element is <%s>, not <scene>",
                   root ? root->where : file->shown, root ? root->tag : "(none)");
        ok = 0;
    }
    if (ok && into) { /* an include: its scene's children in place */
        for (int i = 0; i < root->nkids; i++)
            add_kid(into, root->kids[i]);
        root->nkids = 0;
        node_free(root);
    } else if (ok) {
        d->root = root;
    } else {
        node_free(root);
    }
    free(holder.kids);
    return !ok;
}

int mi_doc_read(const spm_file *top, mi_doc *doc, spm_error *err)
{
    memset(doc, 0, sizeof *doc);
    reader r = {.doc = doc, .err = err};
    int rc = 0;
    for (int i = 0; i < mi_ndefines; i++) {
        const char *eq = strchr(mi_defines[i], '=');
        param_put(&r, mi_defines[i], (size_t)(eq - mi_defines[i]), eq + 1);
    }
    rc = rc || read_file(&r, top, "the command line", NULL);
    for (int i = 0; i < r.nparams; i++) {
        free(r.pname[i]);
        free(r.pval[i]);
    }
    free(r.pname);
    free(r.pval);
    if (rc)
        mi_doc_free(doc);
    return rc;
}

int mi_file(const mi_doc *doc, const mi_node *n, const char *ref, spm_file *out,
            spm_error *err)
{
    /* as Mitsuba's file resolver: the naming file's folder, the top file's,
     * then the <path> folders; the first where the file exists */
    struct stat st;
    char joined[2 * SPM_PATH_MAX + 2];
    for (int i = -2; ref[0] != '/' && i < doc->nsearch; i++) {
        const char *dir = i == -2 ? n->dir : i == -1 ? doc->dirs[0] : doc->search[i];
        snprintf(joined, sizeof joined, "%s/%s", dir, ref);
        if (stat(joined, &st) == 0)
            return spm_path_check(dir, ref, n->where, out, err);
    }
    if (spm_path_check(n->dir, ref, n->where, out, err))
        return 1;
    spm_errorf(err, "%s: file '%s' not found (or not a file)", n->where, ref);
    return 1;
}

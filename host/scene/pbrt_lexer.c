/* pbrt-v4's tokens: words (directives, bare numbers, true/false), quoted
 * strings (one line, with \" \\ \n \t escapes), '[' and ']'; '#' starts a
 * comment to the end of the line. A file is read whole: published scenes
 * hold their meshes inline, and a token may be any length. */
#include "pbrt.h"
#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

int pbrt_lex_open(pbrt_lexer *lx, const spm_file *p, spm_error *err)
{
    const char *shown = p->shown;
    memset(lx, 0, sizeof *lx);
    snprintf(lx->path, sizeof lx->path, "%s", shown);
    spm_path_dir(p->path, lx->dir, sizeof lx->dir);
    FILE *f = spm_path_fopen(p, "rb");
    if (!f) {
        spm_errorf(err, "%s: cannot open: %s", shown, strerror(errno));
        return 1;
    }
    size_t cap = 1 << 16;
    lx->buf = spm_xmalloc(cap + 1);
    size_t got;
    while ((got = fread(lx->buf + lx->n, 1, cap - lx->n, f)) > 0) {
        lx->n += got;
        if (lx->n == cap) {
            if (cap >= PBRT_MAX_FILE_BYTES) {
                fclose(f);
                spm_errorf(err, "%s: larger than %llu bytes", shown,
                           (unsigned long long)PBRT_MAX_FILE_BYTES);
                pbrt_lex_close(lx);
                return 1;
            }
            cap *= 2;
            lx->buf = spm_xrealloc(lx->buf, cap + 1);
        }
    }
    int bad = ferror(f);
    fclose(f);
    if (bad) {
        spm_errorf(err, "%s: read error", shown);
        pbrt_lex_close(lx);
        return 1;
    }
    lx->buf[lx->n] = '\0';
    lx->line = lx->col = 1;
    lx->cap = 256;
    lx->text = spm_xmalloc(lx->cap);
    return pbrt_lex_next(lx, err);
}

void pbrt_lex_close(pbrt_lexer *lx)
{
    free(lx->buf);
    free(lx->text);
    lx->buf = lx->text = NULL;
}

static int peek(const pbrt_lexer *lx) { return lx->pos < lx->n ? (unsigned char)lx->buf[lx->pos] : -1; }

static void advance(pbrt_lexer *lx)
{
    if (lx->buf[lx->pos++] == '\n') {
        lx->line++;
        lx->col = 1;
    } else {
        lx->col++;
    }
}

static void put(pbrt_lexer *lx, size_t *len, char c)
{
    if (*len + 2 > lx->cap) {
        lx->cap *= 2;
        lx->text = spm_xrealloc(lx->text, lx->cap);
    }
    lx->text[(*len)++] = c;
    lx->text[*len] = '\0';
}

static int string_token(pbrt_lexer *lx, spm_error *err)
{
    size_t len = 0;
    lx->text[0] = '\0';
    advance(lx); /* the opening quote */
    for (;;) {
        int c = peek(lx);
        if (c < 0 || c == '\n') {
            spm_errorf(err, "%s:%d:%d: unterminated string (it starts here; a string ends on "
                            "its line)", lx->path, lx->tline, lx->tcol);
            return 1;
        }
        if (c == '\0') {
            spm_errorf(err, "%s:%d:%d: a NUL byte inside a string", lx->path, lx->line, lx->col);
            return 1;
        }
        advance(lx);
        if (c == '"')
            return 0;
        if (c == '\\') {
            int e = peek(lx);
            static const char from[] = "\"\\ntbfr'", to[] = "\"\\\n\t\b\f\r'";
            const char *k = e > 0 ? strchr(from, e) : NULL;
            if (!k) {
                spm_errorf(err, "%s:%d:%d: unknown escape in a string", lx->path, lx->line,
                           lx->col - 1);
                return 1;
            }
            advance(lx);
            c = to[k - from];
        }
        put(lx, &len, (char)c);
    }
}

static int is_delim(int c)
{
    return c < 0 || c == ' ' || c == '\t' || c == '\n' || c == '\r' || c == '[' || c == ']' ||
           c == '"' || c == '#';
}

int pbrt_lex_next(pbrt_lexer *lx, spm_error *err)
{
    int c;
    for (;;) { /* spaces and comments */
        c = peek(lx);
        if (c == ' ' || c == '\t' || c == '\n' || c == '\r') {
            advance(lx);
        } else if (c == '#') {
            while (peek(lx) >= 0 && peek(lx) != '\n')
                advance(lx);
        } else {
            break;
        }
    }
    lx->tline = lx->line;
    lx->tcol = lx->col;
    lx->text[0] = '\0';
    if (c < 0) {
        lx->type = PT_EOF;
        return 0;
    }
    if (c == '[' || c == ']') {
        advance(lx);
        lx->type = c == '[' ? PT_LBRACK : PT_RBRACK;
        snprintf(lx->text, lx->cap, "%c", c);
        return 0;
    }
    if (c == '"') {
        lx->type = PT_STRING;
        return string_token(lx, err);
    }
    size_t len = 0;
    while (!is_delim(peek(lx))) {
        if (peek(lx) < ' ' || peek(lx) > '~') {
            spm_errorf(err, "%s:%d:%d: unexpected byte 0x%02x", lx->path, lx->line, lx->col,
                       peek(lx));
            return 1;
        }
        put(lx, &len, lx->buf[lx->pos]);
        advance(lx);
    }
    char *end;
    lx->num = strtod(lx->text, &end);
    int numeric = strchr("0123456789+-.", lx->text[0]) != NULL;
    lx->type = numeric && *end == '\0' ? PT_NUMBER : PT_WORD;
    if (lx->type == PT_NUMBER && !isfinite(lx->num)) {
        spm_errorf(err, "%s:%d:%d: '%s' is not a finite number", lx->path, lx->tline, lx->tcol,
                   lx->text);
        return 1;
    }
    if (numeric && lx->type == PT_WORD) {
        spm_errorf(err, "%s:%d:%d: '%s' is not a number", lx->path, lx->tline, lx->tcol,
                   lx->text);
        return 1;
    }
    return 0;
}

void pbrt_lex_where(const pbrt_lexer *lx, char *buf, size_t size)
{
    snprintf(buf, size, "%s:%d:%d", lx->path, lx->tline, lx->tcol);
}

int pbrt_lex_expected(const pbrt_lexer *lx, spm_error *err, const char *what)
{
    const char *kind[] = {"the end of the file", "", "string", "", "'['", "']'"};
    if (lx->type == PT_WORD || lx->type == PT_NUMBER)
        spm_errorf(err, "%s:%d:%d: expected %s, found '%.60s'", lx->path, lx->tline, lx->tcol,
                   what, lx->text);
    else if (lx->type == PT_STRING)
        spm_errorf(err, "%s:%d:%d: expected %s, found the string \"%.60s\"", lx->path, lx->tline,
                   lx->tcol, what, lx->text);
    else
        spm_errorf(err, "%s:%d:%d: expected %s, found %s", lx->path, lx->tline, lx->tcol, what,
                   kind[lx->type]);
    return 1;
}

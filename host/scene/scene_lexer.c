#include "scene_lexer.h"
#include <errno.h>
#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include "interrupt.h"

static void advance(spm_lexer *lx)
{
    if (lx->c == EOF)
        return;
    if (lx->c == '\n') {
        lx->line += lx->line < INT_MAX; /* saturate: no overflow on absurd files */
        lx->col = 1;
    } else {
        lx->col += lx->col < INT_MAX;
    }
    lx->c = getc_unlocked(lx->f); /* one thread reads a lexer's file: no lock per byte */
}

static int error_at(const spm_lexer *lx, spm_error *err, int line, int col, const char *what)
{
    spm_errorf(err, "%s:%d:%d: %s", lx->path, line, col, what);
    return 1;
}

int spm_lex_open(spm_lexer *lx, const spm_file *file, spm_error *err)
{
    memset(lx, 0, sizeof *lx);
    const char *path = lx->path = file->shown;
    lx->f = spm_path_fopen(file, "rb");
    if (!lx->f) {
        spm_errorf(err, "%s: cannot open: %s", path, strerror(errno));
        return 1;
    }
    lx->line = lx->col = 1;
    lx->c = getc(lx->f);
    if (spm_lex_next(lx, err)) {
        spm_lex_close(lx);
        return 1;
    }
    return 0;
}

void spm_lex_close(spm_lexer *lx)
{
    if (lx->f)
        fclose(lx->f);
    lx->f = NULL;
}

static int is_space(int c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }
static int is_word_byte(int c)
{
    return c > ' ' && c < 127 && c != '(' && c != ')' && c != '#' && c != '"';
}

static int read_string(spm_lexer *lx, spm_error *err)
{
    size_t n = 0;
    advance(lx); /* the opening quote */
    while (lx->c != '"') {
        if (lx->c == EOF || lx->c == '\n')
            return error_at(lx, err, lx->tline, lx->tcol, "unterminated string");
        if (lx->c < ' ' || lx->c == 127)
            return error_at(lx, err, lx->line, lx->col, "control character in a string");
        if (n + 1 >= SPM_TOK_MAX)
            return error_at(lx, err, lx->tline, lx->tcol, "string too long");
        lx->text[n++] = (char)lx->c;
        advance(lx);
    }
    advance(lx);
    lx->text[n] = 0;
    lx->type = SPM_TOK_STRING;
    return 0;
}

int spm_lex_next(spm_lexer *lx, spm_error *err)
{
    if (spm_stop_requested()) {
        spm_errorf(err, "interrupted while loading %s (line %d)", lx->path, lx->line);
        return 1;
    }
    for (;;) {
        if (is_space(lx->c)) {
            advance(lx);
        } else if (lx->c == '#') { /* a comment may hold any bytes: skip them unread */
            while (lx->c != '\n' && lx->c != EOF)
                advance(lx);
        } else {
            break;
        }
    }
    lx->tline = lx->line;
    lx->tcol = lx->col;
    lx->text[0] = 0;
    int c = lx->c;
    if (c == EOF) {
        if (ferror(lx->f))
            return error_at(lx, err, lx->line, lx->col, "read error");
        lx->type = SPM_TOK_EOF;
    } else if (c == '\n' || c == '(' || c == ')') {
        lx->type = c == '\n' ? SPM_TOK_NEWLINE : c == '(' ? SPM_TOK_LPAREN : SPM_TOK_RPAREN;
        if (c == '\n')
            spm_test_pause("load");
        lx->text[0] = (char)c;
        lx->text[1] = 0;
        advance(lx);
    } else if (c == '"') {
        return read_string(lx, err);
    } else if (is_word_byte(c)) {
        size_t n = 0;
        while (is_word_byte(lx->c)) {
            if (n + 1 >= SPM_TOK_MAX) {
                char msg[96];
                snprintf(msg, sizeof msg, "token longer than %d characters", SPM_TOK_MAX - 1);
                return error_at(lx, err, lx->tline, lx->tcol, msg);
            }
            lx->text[n++] = (char)lx->c;
            advance(lx);
        }
        lx->text[n] = 0;
        lx->type = SPM_TOK_WORD;
    } else {
        char msg[96];
        snprintf(msg, sizeof msg, "unexpected byte 0x%02x (not a text scene file?)", c);
        return error_at(lx, err, lx->line, lx->col, msg);
    }
    return 0;
}

int spm_lex_skip_newlines(spm_lexer *lx, spm_error *err)
{
    while (lx->type == SPM_TOK_NEWLINE)
        if (spm_lex_next(lx, err))
            return 1;
    return 0;
}

void spm_lex_where(const spm_lexer *lx, char *buf, size_t size)
{
    snprintf(buf, size, "%s:%d:%d", lx->path, lx->tline, lx->tcol);
}

int spm_lex_expected(const spm_lexer *lx, spm_error *err, const char *what)
{
    switch (lx->type) {
    case SPM_TOK_EOF:
        spm_errorf(err, "%s:%d:%d: expected %s, found end of file", lx->path, lx->tline,
                   lx->tcol, what);
        break;
    case SPM_TOK_NEWLINE:
        spm_errorf(err, "%s:%d:%d: expected %s, found end of line", lx->path, lx->tline,
                   lx->tcol, what);
        break;
    default: {
        const char *q = lx->type == SPM_TOK_STRING ? "\"" : "'";
        int long_tok = strlen(lx->text) > 40;
        spm_errorf(err, "%s:%d:%d: expected %s, found %s%.40s%s%s", lx->path, lx->tline,
                   lx->tcol, what, q, lx->text, long_tok ? "..." : "", q);
    }
    }
    return 1;
}

int spm_lex_is(const spm_lexer *lx, const char *w)
{
    return lx->type == SPM_TOK_WORD && strcmp(lx->text, w) == 0;
}

int spm_lex_is_number(const spm_lexer *lx)
{
    if (lx->type != SPM_TOK_WORD)
        return 0;
    char *end;
    strtod(lx->text, &end); /* "inf" and "nan" count: they are refused as numbers later */
    return strchr("0123456789+-.", lx->text[0]) || (end != lx->text && !*end);
}

/* "WHAT (lo to hi)" for messages; open ends are left out. */
static void describe_range(char *buf, size_t size, const char *what, double lo, double hi)
{
    if (lo == -HUGE_VAL && hi == HUGE_VAL)
        snprintf(buf, size, "%s", what);
    else if (hi == HUGE_VAL)
        snprintf(buf, size, "%s (at least %g)", what, lo);
    else if (lo == -HUGE_VAL)
        snprintf(buf, size, "%s (at most %g)", what, hi);
    else
        snprintf(buf, size, "%s (%g to %g)", what, lo, hi);
}

/* Clinger's fast path: a decimal of at most 15 significant digits times a
 * power of ten within 10^+-22 is two exact doubles, and one IEEE multiply or
 * divide of them rounds correctly, so the result equals strtod's. Returns 0
 * for anything else (more digits, larger exponents, hex, inf, nan, junk),
 * which strtod then reads. */
static int fast_decimal(const char *s, double *out)
{
    static const double pow10[23] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                     1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                     1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    int neg = 0, digits = 0, any = 0, exp10 = 0;
    unsigned long long m = 0;
    if (*s == '+' || *s == '-')
        neg = *s++ == '-';
    for (; *s >= '0' && *s <= '9'; s++, any = 1)
        if (m || *s != '0') {
            if (++digits > 15)
                return 0;
            m = m * 10 + (unsigned)(*s - '0');
        }
    if (*s == '.')
        for (s++; *s >= '0' && *s <= '9'; s++, any = 1) {
            if (m || *s != '0') {
                if (++digits > 15)
                    return 0;
                m = m * 10 + (unsigned)(*s - '0');
            }
            exp10--;
        }
    if (!any)
        return 0;
    if (*s == 'e' || *s == 'E') {
        s++;
        int eneg = 0, e = 0, edig = 0;
        if (*s == '+' || *s == '-')
            eneg = *s++ == '-';
        for (; *s >= '0' && *s <= '9'; s++, edig++)
            if (e < 1000)
                e = e * 10 + (*s - '0');
        if (!edig)
            return 0;
        exp10 += eneg ? -e : e;
    }
    if (*s)
        return 0;
    double v = (double)m; /* exact: m < 10^15 < 2^53 */
    if (m != 0) {
        if (exp10 < -22 || exp10 > 22)
            return 0;
        v = exp10 < 0 ? v / pow10[-exp10] : v * pow10[exp10];
    }
    *out = neg ? -v : v;
    return 1;
}

/* The token as a whole number of strtod's syntax; 0 when it is not one. */
static int parse_double(const char *text, double *out)
{
    if (fast_decimal(text, out))
        return 1;
    char *end;
    *out = strtod(text, &end);
    return end != text && !*end;
}

/* The message for a number that does not fit, formatted only then. */
static int number_error(spm_lexer *lx, const char *what, double lo, double hi, int finite,
                        spm_error *err)
{
    char desc[256];
    describe_range(desc, sizeof desc, what, lo, hi);
    if (finite)
        return spm_lex_expected(lx, err, desc);
    char msg[300];
    snprintf(msg, sizeof msg, "%s, a finite number", desc);
    return spm_lex_expected(lx, err, msg);
}

int spm_lex_number(spm_lexer *lx, const char *what, double lo, double hi, double *out,
                   spm_error *err)
{
    double v;
    if (lx->type != SPM_TOK_WORD || !parse_double(lx->text, &v))
        return number_error(lx, what, lo, hi, 1, err);
    if (!isfinite(v))
        return number_error(lx, what, lo, hi, 0, err);
    if (v < lo || v > hi)
        return number_error(lx, what, lo, hi, 1, err);
    *out = v;
    return spm_lex_next(lx, err);
}

int spm_lex_int(spm_lexer *lx, const char *what, long lo, long hi, long *out, spm_error *err)
{
    char *end;
    errno = 0;
    long v = 0;
    if (lx->type == SPM_TOK_WORD)
        v = strtol(lx->text, &end, 10);
    if (lx->type != SPM_TOK_WORD || end == lx->text || *end || errno == ERANGE || v < lo ||
        v > hi) {
        char desc[256];
        snprintf(desc, sizeof desc, "%s (an integer from %ld to %ld)", what, lo, hi);
        return spm_lex_expected(lx, err, desc);
    }
    *out = v;
    return spm_lex_next(lx, err);
}

static int is_name(const char *s)
{
    if (!(*s == '_' || (*s >= 'A' && *s <= 'Z') || (*s >= 'a' && *s <= 'z')))
        return 0;
    for (; *s; s++)
        if (!(*s == '_' || *s == '-' || *s == '.' || (*s >= 'A' && *s <= 'Z') ||
              (*s >= 'a' && *s <= 'z') || (*s >= '0' && *s <= '9')))
            return 0;
    return 1;
}

int spm_lex_name(spm_lexer *lx, const char *what, char *out, size_t size, spm_error *err)
{
    size_t n = lx->type == SPM_TOK_WORD ? strlen(lx->text) : 0;
    if (lx->type != SPM_TOK_WORD || !is_name(lx->text) || n >= size) {
        char desc[256];
        snprintf(desc, sizeof desc,
                 "%s (a name of letters, digits, '_', '-', '.', at most %zu long)", what,
                 size - 1);
        return spm_lex_expected(lx, err, desc);
    }
    memcpy(out, lx->text, n + 1);
    return spm_lex_next(lx, err);
}

int spm_lex_path(spm_lexer *lx, const char *what, char *out, size_t size, spm_error *err)
{
    if ((lx->type != SPM_TOK_WORD && lx->type != SPM_TOK_STRING) || !lx->text[0] ||
        strlen(lx->text) >= size)
        return spm_lex_expected(lx, err, what);
    snprintf(out, size, "%s", lx->text);
    return spm_lex_next(lx, err);
}

int spm_lex_punct(spm_lexer *lx, spm_tok_type t, spm_error *err)
{
    if (lx->type != t)
        return spm_lex_expected(lx, err, t == SPM_TOK_LPAREN ? "'('" : "')'");
    return spm_lex_next(lx, err);
}

int spm_lex_end_of_statement(spm_lexer *lx, spm_error *err)
{
    if (lx->type == SPM_TOK_EOF)
        return 0;
    if (lx->type != SPM_TOK_NEWLINE)
        return spm_lex_expected(lx, err, "end of line");
    return spm_lex_next(lx, err);
}

/* A directive's arguments, read from the innermost file: a quoted string,
 * numbers bare or in one bracketed list, the parameter list. */
#include "pbrt_parser.h"
#include <string.h>

int pbrt_arg_string(pbrt_parser *p, const char *what, char *out, size_t size)
{
    pbrt_lexer *lx = pbrt_lx(p);
    if (lx->type == PT_LBRACK) { /* pbrt accepts [ "x" ] as well */
        if (pbrt_lex_next(lx, p->err) || pbrt_arg_string(p, what, out, size))
            return 1;
        if (lx->type != PT_RBRACK)
            return pbrt_lex_expected(lx, p->err, "']'");
        return pbrt_lex_next(lx, p->err);
    }
    if (lx->type != PT_STRING)
        return pbrt_lex_expected(lx, p->err, what);
    if (strlen(lx->text) >= size) {
        spm_errorf(p->err, "%s:%d:%d: %s longer than %zu bytes", lx->path, lx->tline, lx->tcol,
                   what, size - 1);
        return 1;
    }
    snprintf(out, size, "%s", lx->text);
    return pbrt_lex_next(lx, p->err);
}

int pbrt_arg_numbers(pbrt_parser *p, int n, const char *what, double *out)
{
    pbrt_lexer *lx = pbrt_lx(p);
    int bracket = lx->type == PT_LBRACK;
    char open[600];
    pbrt_lex_where(lx, open, sizeof open);
    if (bracket && pbrt_lex_next(lx, p->err))
        return 1;
    for (int i = 0; i < n; i++) {
        if (lx->type != PT_NUMBER) {
            char w[160];
            snprintf(w, sizeof w, "%s (number %d of %d)", what, i + 1, n);
            if (bracket && lx->type == PT_EOF) {
                spm_errorf(p->err, "%s: unterminated '[' (no ']' before the end of the file)",
                           open);
                return 1;
            }
            return pbrt_lex_expected(lx, p->err, w);
        }
        out[i] = lx->num;
        if (pbrt_lex_next(lx, p->err))
            return 1;
    }
    if (bracket) {
        if (lx->type != PT_RBRACK)
            return pbrt_lex_expected(lx, p->err, "']' after the numbers");
        return pbrt_lex_next(lx, p->err);
    }
    return 0;
}

int pbrt_arg_params(pbrt_parser *p, pbrt_params *ps)
{
    memset(ps, 0, sizeof *ps);
    if (pbrt_params_read(pbrt_lx(p), ps, p->err)) {
        pbrt_params_free(ps); /* what was read before the error */
        return 1;
    }
    return 0;
}

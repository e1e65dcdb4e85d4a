/* Tokens of the text scene formats (the project's own and MiniLight's), read
 * byte by byte so that no line, however long, is ever held in memory: a token
 * longer than SPM_TOK_MAX - 1 bytes is an error, comments are skipped unread.
 * Every error names "file:line:col". */
#ifndef SPM_SCENE_LEXER_H
#define SPM_SCENE_LEXER_H
#include <stdio.h>
#include "util.h"
#include "paths.h"

#define SPM_TOK_MAX 256

typedef enum {
    SPM_TOK_EOF,
    SPM_TOK_NEWLINE,
    SPM_TOK_WORD,    /* a run of printable ASCII without spaces, parentheses, '#' or '"' */
    SPM_TOK_STRING,  /* "..." on one line (text holds the contents) */
    SPM_TOK_LPAREN,
    SPM_TOK_RPAREN
} spm_tok_type;

typedef struct {
    FILE *f;
    const char *path;
    int line, col;    /* position of the next unread byte */
    int c;            /* the next unread byte (EOF at end) */
    /* current token */
    spm_tok_type type;
    char text[SPM_TOK_MAX];
    int tline, tcol;
} spm_lexer;

/* Opens the file and reads the first token. On failure nothing is left open. */
int spm_lex_open(spm_lexer *lx, const spm_file *file, spm_error *err);
void spm_lex_close(spm_lexer *lx);
/* Moves to the next token. */
int spm_lex_next(spm_lexer *lx, spm_error *err);
int spm_lex_skip_newlines(spm_lexer *lx, spm_error *err);

/* "file:line:col: expected WHAT, found <current token>". Returns 1. */
int spm_lex_expected(const spm_lexer *lx, spm_error *err, const char *what);
/* "file:line:col" of the current token. */
void spm_lex_where(const spm_lexer *lx, char *buf, size_t size);

/* Is the current token the word `w`? */
int spm_lex_is(const spm_lexer *lx, const char *w);
/* Does the current token look like a number (starts with a digit, sign or '.',
 * or is one such as "inf" that strtod reads)? */
int spm_lex_is_number(const spm_lexer *lx);

/* Each of these checks the current token and, when it fits, advances past it.
 * Numbers must be finite and within [lo, hi]; NaN and Inf are refused. */
int spm_lex_number(spm_lexer *lx, const char *what, double lo, double hi, double *out,
                   spm_error *err);
int spm_lex_int(spm_lexer *lx, const char *what, long lo, long hi, long *out, spm_error *err);
/* A name: a letter or '_' then letters, digits, '_', '-', '.', shorter than `size`. */
int spm_lex_name(spm_lexer *lx, const char *what, char *out, size_t size, spm_error *err);
/* A path: a word or a quoted string. */
int spm_lex_path(spm_lexer *lx, const char *what, char *out, size_t size, spm_error *err);
int spm_lex_punct(spm_lexer *lx, spm_tok_type t, spm_error *err);
/* The end of a statement: a newline (consumed) or the end of the file. */
int spm_lex_end_of_statement(spm_lexer *lx, spm_error *err);
#endif

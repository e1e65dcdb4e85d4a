/* The scene lexer's numbers are strtod's, bit for bit: short decimals take a
 * fast path (scene_lexer.c fast_decimal), everything else strtod itself. The
 * tokens: random doubles printed with 1 to 17 significant digits in %g, %e
 * and %f styles, exponents up to the fast path's edge (10^+-22) and past it,
 * 15- and 16-digit mantissas, leading and trailing zeros, signs, "1." and
 * ".5". Refused tokens stay refused, with the range in the message. */
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "scene_lexer.h"
#include "testutil.h"

static unsigned long long rng_state = 987654321;
static double rnd(void)
{
    rng_state = rng_state * 6364136223846793005ULL + 1442695040888963407ULL;
    return (double)(rng_state >> 11) * (1.0 / 9007199254740992.0);
}

#define NTOK 60000

int main(void)
{
    static char tok[NTOK][64];
    int n = 0;
    const char *fixed[] = {"0",     "-0",   "+0.0",  "1.",    ".5",    "-.25", "007",
                           "1e22",  "1e23", "1e-22", "1e-23", "9007199254740993",
                           "123456789012345", "1234567890123456", "0.000000000000000000001",
                           "4.9406564584124654e-324", "1.7976931348623157e308", "2.5E+3",
                           "0.1",   "0.30000000000000004", "100000000000000000000000"};
    for (size_t i = 0; i < sizeof fixed / sizeof fixed[0]; i++)
        snprintf(tok[n++], sizeof tok[0], "%s", fixed[i]);
    const char *styles[] = {"%.*g", "%.*e", "%.*f"};
    while (n < NTOK) {
        double mag = pow(10.0, rnd() * 60 - 30);
        double v = (rnd() - 0.5) * mag;
        int digits = 1 + (int)(rnd() * 17), style = (int)(rnd() * 3);
        if (style == 2 && fabs(v) > 1e15)
            style = 0;
        snprintf(tok[n++], sizeof tok[0], styles[style], style == 0 ? digits : digits - 1, v);
    }
    char path[] = "/tmp/spm_numbers_XXXXXX";
    int fd = mkstemp(path);
    CHECK(fd >= 0, "temporary file");
    FILE *f = fdopen(fd, "w");
    for (int i = 0; i < n; i++)
        fprintf(f, "%s%c", tok[i], i % 9 == 8 ? '\n' : ' ');
    fprintf(f, "\n1e 0x 1.5.3 12abc\n");
    fclose(f);

    spm_lexer lx;
    spm_error err;
    spm_file file;
    CHECK(spm_paths_set_root(path, &file, &err) == 0 && spm_lex_open(&lx, &file, &err) == 0,
          "open: %s", err.msg);
    int differ = 0;
    for (int i = 0; i < n; i++) {
        if (lx.type == SPM_TOK_NEWLINE)
            spm_lex_next(&lx, &err);
        double v = 0.0, want = strtod(tok[i], NULL);
        if (spm_lex_number(&lx, "a number", -HUGE_VAL, HUGE_VAL, &v, &err) ||
            memcmp(&v, &want, sizeof v)) {
            if (differ++ < 5)
                fprintf(stderr, "'%s': %.17g, strtod %.17g\n", tok[i], v, want);
        }
    }
    CHECK(differ == 0, "%d of %d numbers differ from strtod's", differ, n);
    CHECK(spm_lex_skip_newlines(&lx, &err) == 0, "newlines");
    double v;
    CHECK(spm_lex_number(&lx, "a size", 0.0, 10.0, &v, &err) != 0 &&
              strstr(err.msg, "expected a size (0 to 10), found '1e'") &&
              strstr(err.msg, ":"),
          "'1e' refused with the range: %s", err.msg);
    const char *bad[] = {"0x", "1.5.3", "12abc"};
    for (int i = 0; i < 3; i++) {
        spm_lex_next(&lx, &err);
        CHECK(spm_lex_number(&lx, "a number", -HUGE_VAL, HUGE_VAL, &v, &err) != 0 &&
                  strstr(err.msg, bad[i]),
              "'%s' refused: %s", bad[i], err.msg);
    }
    spm_lex_close(&lx);
    unlink(path);
    TEST_END();
}

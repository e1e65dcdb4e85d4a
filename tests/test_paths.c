/* The path rule (host/util/paths.c): percent-decoding, canonical paths
 * through "..", links and missing parts, the root and --allow-path. */
#include "paths.h"
#include "testutil.h"
#include <stdlib.h>
#include <string.h>

static void uri_decode(void)
{
    char out[64];
    CHECK(spm_uri_decode("%2e%2E/a%20b.bin", out, sizeof out) == 0 && !strcmp(out, "../a b.bin"),
          "decoded: %s", out);
    CHECK(spm_uri_decode("a%2", out, sizeof out) != 0, "a cut escape refused");
    CHECK(spm_uri_decode("a%zz", out, sizeof out) != 0, "a non-hex escape refused");
    CHECK(spm_uri_decode("a%00b", out, sizeof out) != 0, "an escaped NUL refused");
    CHECK(spm_uri_decode("abcdefgh", out, 4) != 0, "too long for the buffer");
}

/* The rule on a folder tree: root/, root/in/, outside/, rootx/ (a name that
 * begins with the root's), root/ln -> ../outside */
static void rule(void)
{
    char tmpl[] = "/tmp/spm_test_paths.XXXXXX", p[512], q[1024];
    const char *t = mkdtemp(tmpl);
    CHECK(t != NULL, "temporary folder");
    if (!t)
        return;
    snprintf(p, sizeof p, "%s/root/in", t);
    snprintf(q, sizeof q, "mkdir -p %s %s/outside %s/rootx && ln -s ../outside %s/root/ln && "
                          "touch %s/root/s.scene %s/outside/x", p, t, t, t, t, t);
    CHECK(system(q) == 0, "tree made");
    spm_file top, f;
    spm_error err;
    snprintf(p, sizeof p, "%s/root/s.scene", t);
    CHECK(spm_paths_set_root(p, &top, &err) == 0, "root: %s", err.msg);
    snprintf(q, sizeof q, "%s/root", t);
    struct { const char *ref; int ok; const char *to; } cases[] = {
        {"in/../in/x", 1, "/root/in/x"},  {"in/missing/../../s.scene", 1, "/root/s.scene"},
        {"../outside/x", 0, "/outside/x"}, {"ln/x", 0, "/outside/x"},
        {"ln/../root/in", 1, "/root/in"},  {"in/nothing/../../../outside", 0, "/outside"},
        {"./././in//x", 1, "/root/in/x"}, {"../rootx/y", 0, "/rootx/y"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        int rc = spm_path_check(q, cases[i].ref, "here", &f, &err);
        char want[512] = "";
        if (cases[i].to)
            snprintf(want, sizeof want, "%s%s", t, cases[i].to);
        CHECK(rc == !cases[i].ok && (!cases[i].to || !strcmp(f.path, want)),
              "%s: %s (%s)", cases[i].ref, rc ? err.msg : "allowed", f.path);
        CHECK(cases[i].ok || (strstr(err.msg, "here: '") && strstr(err.msg, "--allow-path")),
              "%s: the error names where, the reference and the option: %s", cases[i].ref, err.msg);
    }
    snprintf(p, sizeof p, "%s/outside", t);
    CHECK(spm_paths_allow(p, &err) == 0, "allow: %s", err.msg);
    CHECK(spm_path_check(q, "../outside/x", "here", &f, &err) == 0, "allowed now: %s", err.msg);
    CHECK(spm_path_check(q, "ln/x", "here", &f, &err) == 0, "through the link too: %s", err.msg);
    spm_paths_clear_allowed();
    CHECK(spm_path_check(q, "ln/x", "here", &f, &err) != 0, "refused again once cleared");
    snprintf(p, sizeof p, "%s/outside/x", t);
    CHECK(spm_paths_allow(p, &err) != 0 && strstr(err.msg, "not a folder"), "a file is no folder: %s",
          err.msg);
    snprintf(q, sizeof q, "rm -rf %s", t);
    CHECK(system(q) == 0, "tree removed");
}

int main(void)
{
    uri_decode();
    rule();
    TEST_END();
}

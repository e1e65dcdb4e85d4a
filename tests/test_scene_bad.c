/* Every bad scene in tests/bad-inputs (*.scene, *.ml.txt) is refused with a
 * message naming FILE:LINE:, and 100 MB lines are handled without holding
 * them (generated here, not stored in the repository). */
#include "scene.h"
#include "testutil.h"
#include <dirent.h>
#include <stdlib.h>
#include <string.h>

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n >= m && strcmp(s + n - m, suffix) == 0;
}

/* Does msg contain "path:LINE:" with LINE a positive number? */
static int names_file_line(const char *msg, const char *path)
{
    size_t n = strlen(path);
    for (const char *p = strstr(msg, path); p; p = strstr(p + 1, path)) {
        const char *q = p + n;
        if (*q++ != ':' || *q < '1' || *q > '9')
            continue;
        while (*q >= '0' && *q <= '9')
            q++;
        if (*q == ':')
            return 1;
    }
    return 0;
}

static void check_bad(const char *path)
{
    FILE *f = fopen(path, "rb");
    int c = f ? getc(f) : EOF;
    if (f)
        fclose(f);
    CHECK(c == '#', "%s: first line is a comment saying what is wrong", path);
    spm_scene s;
    spm_error err;
    err.msg[0] = 0;
    spm_quiet_warnings = 1;
    int rc = spm_scene_load(path, &s, &err);
    spm_quiet_warnings = 0;
    CHECK(rc != 0, "%s is refused", path);
    CHECK(names_file_line(err.msg, path), "%s: message names file:line: %s", path, err.msg);
    CHECK(s.colours == NULL && s.tris == NULL && s.materials == NULL, "%s: nothing kept", path);
    printf("%s\n", err.msg);
    spm_scene_free(&s);
}

/* A valid small scene with `middle` (count bytes of byte b, after prefix) on line 2. */
static void write_long_line(const char *path, const char *prefix, int b, long count)
{
    FILE *f = fopen(path, "wb");
    CHECK(f != NULL, "cannot write %s", path);
    if (!f)
        return;
    fputs("image 4 4\n", f);
    fputs(prefix, f);
    char buf[65536];
    memset(buf, b, sizeof buf);
    for (long left = count; left > 0; left -= (long)sizeof buf)
        fwrite(buf, 1, left < (long)sizeof buf ? (size_t)left : sizeof buf, f);
    fputs("\ncamera position 0 1 -3 direction 0 0 1 fov 40\n"
          "spectrum flat equal\nmaterial light emit flat 1\ntri light 0 0 0 1 0 0 0 1 0\n",
          f);
    fclose(f);
}

static void test_long_lines(void)
{
    const long big = 100L << 20; /* a 100 MB line */
    spm_scene s;
    spm_error err;
    /* A long comment is skipped unread: the scene is valid. */
    write_long_line("long_comment.scene", "# ", 'x', big);
    CHECK(spm_scene_load("long_comment.scene", &s, &err) == 0, "100 MB comment: %s", err.msg);
    CHECK(s.ntris == 1, "the scene after the comment is read");
    spm_scene_free(&s);
    /* A long token is refused at its start, without reading it all. */
    write_long_line("long_token.scene", "spp ", '7', big);
    CHECK(spm_scene_load("long_token.scene", &s, &err) != 0, "100 MB token refused");
    CHECK(strstr(err.msg, "long_token.scene:2:5:") != NULL, "token error at 2:5: %s", err.msg);
    printf("%s\n", err.msg);
    remove("long_comment.scene");
    remove("long_token.scene");
}

int main(void)
{
    char dir[4096];
    spm_data_path("tests/bad-inputs", dir, sizeof dir);
    DIR *d = opendir(dir);
    CHECK(d != NULL, "cannot open %s", dir);
    int n = 0;
    for (struct dirent *e; d && (e = readdir(d));) {
        if (!ends_with(e->d_name, ".scene") && !ends_with(e->d_name, ".ml.txt"))
            continue;
        char path[4400];
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        check_bad(path);
        n++;
    }
    if (d)
        closedir(d);
    CHECK(n >= 40, "the corpus has its bad scenes (%d found)", n);
    test_long_lines();
    TEST_END();
}

/* Every material keyword appears in a bundled scene that a test renders: for
 * each word of the type table (include/spm_types.h: a material type's
 * keyword and each clause of every material and emitter type), a bundled
 * scene (scenes/ *.scene) with a 'material' statement that uses it, the one
 * using the most of the words (then the smallest); each such scene is
 * rendered here (CPU reference, 8x8, 4 spp, ml), and its image must be finite
 * and not black. A keyword added without a scene fails here, by name. */
#include <dirent.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include "materials.h"
#include "render_testlib.h"
#include "testutil.h"

#define MAX_SCENES 64

#define MAX_WORDS 64

typedef struct {
    char name[256];
    long size;
    int nwords; /* how many of the words it uses */
} scene_file;

static int by_use(const void *a, const void *b)
{
    const scene_file *x = a, *y = b;
    if (x->nwords != y->nwords)
        return x->nwords > y->nwords ? -1 : 1;
    return x->size != y->size ? (x->size < y->size ? -1 : 1) : strcmp(x->name, y->name);
}

static int list_scenes(scene_file *s)
{
    char dir[1024], path[1300];
    spm_data_path("scenes", dir, sizeof dir);
    DIR *d = opendir(dir);
    int n = 0;
    struct dirent *e;
    while (d && (e = readdir(d)) && n < MAX_SCENES) {
        size_t l = strlen(e->d_name);
        struct stat st;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        if (l > 6 && !strcmp(e->d_name + l - 6, ".scene") && !stat(path, &st)) {
            snprintf(s[n].name, sizeof s[n].name, "%s", e->d_name);
            s[n].nwords = 0;
            s[n++].size = (long)st.st_size;
        }
    }
    if (d)
        closedir(d);
    return n;
}

/* Whether a 'material' statement of the scene uses word (a whole token after its name). */
static int scene_uses(const char *scene, const char *word)
{
    char rel[512], path[1024], line[4096];
    snprintf(rel, sizeof rel, "scenes/%s", scene);
    FILE *f = fopen(spm_data_path(rel, path, sizeof path), "r");
    int found = 0;
    while (f && !found && fgets(line, sizeof line, f)) {
        char *save = NULL, *tok = strtok_r(line, " \t\r\n", &save);
        if (!tok || strcmp(tok, "material") || !strtok_r(NULL, " \t\r\n", &save))
            continue;
        while (!found && (tok = strtok_r(NULL, " \t\r\n", &save)))
            found = !strcmp(tok, word);
    }
    if (f)
        fclose(f);
    return found;
}

static int rendered[MAX_SCENES];

static void render_once(const scene_file *s, int i)
{
    if (rendered[i])
        return;
    rendered[i] = 1;
    rt_render_job j = {s->name, SPM_MODE_ML, 4, 1u, 8, 0.0, "cpu"};
    rt_render_out o;
    if (rt_render(&j, &o, NULL, NULL)) {
        CHECK(0, "%s does not render", s->name);
        return;
    }
    double sum = 0.0;
    int finite = 1;
    for (int p = 0; p < 3 * 8 * 8; p++) {
        finite &= isfinite(o.img.rgb[p]) != 0;
        sum += fabs(o.img.rgb[p]);
    }
    printf("  rendered %s: mean |rgb| %.4g\n", s->name, sum / (3 * 8 * 8));
    CHECK(finite && sum > 0.0, "%s: image %s", s->name, finite ? "black" : "not finite");
    free(o.img.rgb);
}

typedef struct {
    const char *word, *owner;
} keyword;

static void check_word(const keyword *k, scene_file *s, int n)
{
    for (int i = 0; i < n; i++)
        if (scene_uses(s[i].name, k->word)) {
            printf("%-10s (%s) in %s\n", k->word, k->owner, s[i].name);
            render_once(&s[i], i);
            return;
        }
    CHECK(0, "material keyword '%s' (%s) is in no bundled scene: add one that uses it", k->word,
          k->owner);
}

/* The words of a type table; an emitter type's keyword names no word of a
 * scene (its clauses do: 'emit'). */
static int type_words(const spm_mtype_desc *types, int n, int type_word, keyword *w, int nw)
{
    for (int t = 0; t < n; t++) {
        const spm_mtype_desc *d = &types[t];
        const char *owner = d->keyword ? d->keyword : "diffuse";
        if (type_word && d->keyword && nw < MAX_WORDS)
            w[nw++] = (keyword){d->keyword, owner};
        for (int p = 0; p < d->nparams; p++)
            if (d->params[p].clause && nw < MAX_WORDS)
                w[nw++] = (keyword){d->params[p].clause, owner};
    }
    return nw;
}

int main(void)
{
    scene_file s[MAX_SCENES];
    keyword w[MAX_WORDS];
    int ns = list_scenes(s);
    int nw = type_words(spm_material_types, spm_nmaterial_types, 1, w, 0);
    nw = type_words(spm_emitter_types, spm_nemitter_types, 0, w, nw);
    CHECK(ns > 0, "no scenes found");
    CHECK(nw >= 10, "only %d keywords in the type table", nw);
    for (int i = 0; i < ns; i++)
        for (int k = 0; k < nw; k++)
            s[i].nwords += scene_uses(s[i].name, w[k].word);
    qsort(s, (size_t)ns, sizeof *s, by_use);
    spm_quiet_warnings = 1;
    for (int k = 0; k < nw; k++)
        check_word(&w[k], s, ns);
    TEST_END();
}

/* An OBJ whose MTL files are missing: Assimp 5.2 then makes each `usemtl`
 * name a material of its own default grey and says nothing, so a missing
 * file would render as a grey model. Here the `mtllib` lines are read, each
 * file looked for beside the OBJ, and a material that no MTL found defines
 * loses its name: the rule of a mesh without materials applies to it (a
 * `material` clause or a `bind` gives it one, else the load fails). The
 * same reading marks the materials whose `illum` turns refraction on, which
 * Assimp does not pass on (SPM_MESH_HAS_REFRACT, mapped by mesh_pbr.c). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include "mesh.h"
#include "util.h"

#define MAX_LIBS 16

typedef struct {
    char *s;       /* names, one per line */
    size_t len, cap;
} name_list;

static void add_name(name_list *l, const char *name)
{
    size_t n = strlen(name);
    if (l->len + n + 2 > l->cap) {
        l->cap = (l->cap + n + 2) * 2;
        l->s = spm_xrealloc(l->s, l->cap);
    }
    memcpy(l->s + l->len, name, n);
    l->s[l->len + n] = '\n';
    l->len += n + 1;
    l->s[l->len] = '\0';
}

/* The `newmtl` names of an existing MTL file, appended to *names, and those
 * whose `illum` is 6 or 7 (refraction on; Assimp 5.2 does not pass illum
 * on) to *refract; 0 if the file cannot be opened. */
static int mtl_names(const spm_file *file, name_list *names, name_list *refract)
{
    FILE *f = spm_path_fopen(file, "r");
    if (!f)
        return 0;
    char line[512], name[SPM_NAME_MAX] = "";
    int illum;
    while (fgets(line, sizeof line, f)) {
        if (sscanf(line, " newmtl %63s", name) == 1)
            add_name(names, name);
        else if (name[0] && sscanf(line, " illum %d", &illum) == 1 && (illum == 6 || illum == 7))
            add_name(refract, name);
    }
    fclose(f);
    return 1;
}

static int listed(const char *names, const char *name)
{
    size_t n = strlen(name);
    for (const char *p = names; p && *p;) {
        const char *e = strchr(p, '\n');
        if ((size_t)(e - p) == n && !memcmp(p, name, n))
            return 1;
        p = e + 1;
    }
    return 0;
}

void spm_mesh_obj_mtl_check(const spm_file *file, const char *where, spm_mesh_data *d)
{
    const char *obj = file->shown;
    size_t olen = strlen(obj);
    if (olen < 4 || strcasecmp(obj + olen - 4, ".obj"))
        return;
    FILE *f = spm_path_fopen(file, "r");
    if (!f)
        return;
    char dir[SPM_PATH_MAX];
    spm_path_dir(file->path, dir, sizeof dir); /* where the importer found its MTL files */
    name_list names = {NULL, 0, 0}, refract = {NULL, 0, 0};
    char missing[512] = "";
    size_t nmiss = 0;
    int nlibs = 0;
    char line[1024];
    while (fgets(line, sizeof line, f) && nlibs < MAX_LIBS) {
        if (strncmp(line, "mtllib", 6) || (line[6] != ' ' && line[6] != '\t'))
            continue;
        for (char *tok = strtok(line + 6, " \t\r\n"); tok && nlibs < MAX_LIBS;
             tok = strtok(NULL, " \t\r\n"), nlibs++) {
            spm_file mtl; /* refused ones were refused before the import */
            spm_error refused;
            int found = !spm_path_check(dir, tok, where, &mtl, &refused) &&
                        mtl_names(&mtl, &names, &refract);
            if (!found && nmiss < sizeof missing - 80) {
                snprintf(missing + nmiss, sizeof missing - nmiss, "%s'%s'", nmiss ? ", " : "", tok);
                nmiss = strlen(missing);
            }
        }
    }
    fclose(f);
    for (uint32_t i = 0; i < d->nmats; i++)
        if (d->mats[i].name[0] && listed(refract.s, d->mats[i].name))
            d->mats[i].has |= SPM_MESH_HAS_REFRACT;
    if (missing[0]) {
        char lost[400] = "";
        size_t n = 0;
        for (uint32_t i = 0; i < d->nmats; i++)
            if (d->mats[i].name[0] && !listed(names.s, d->mats[i].name)) {
                if (n < sizeof lost - 80) {
                    snprintf(lost + n, sizeof lost - n, "%s'%s'", n ? ", " : "", d->mats[i].name);
                    n = strlen(lost);
                }
                d->mats[i].name[0] = '\0';
            }
        spm_warnf("%s: %s: MTL file %s not found beside it; %s%s", where, obj, missing,
                  n ? "without it these have no material: " : "no material depends on it",
                  n ? lost : "");
    }
    free(names.s);
    free(refract.s);
}

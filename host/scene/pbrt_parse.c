/* pbrt-v4 scene files (docs/PBRT.md): the file stack (Include and Import,
 * each file by the path rule of paths.h), the directives' arguments and
 * their dispatch. The directives themselves live by concept: the graphics
 * state (pbrt_state.c), the world's materials, lights, shapes and instances
 * (pbrt_world.c), the camera and rendering options (pbrt_options.c). */
#include "pbrt_parser.h"
#include "scene_parsers.h"
#include "interrupt.h"
#include <stdlib.h>
#include <string.h>

/* Opens the checked file p as the innermost one; an include cycle or too
 * deep a nesting is an error naming `where`. */
static int push_file(pbrt_parser *p, const spm_file *path, const char *where)
{
    for (int i = 0; i < p->depth; i++)
        if (!strcmp(p->canon[i], path->path)) {
            spm_errorf(p->err, "%s: include cycle: '%s' is already being read (by %s)", where,
                       path->shown, i ? p->files[i - 1]->path : "the command line");
            return 1;
        }
    if (p->depth == PBRT_MAX_INCLUDE_DEPTH) {
        spm_errorf(p->err, "%s: includes nested more than %d deep", where,
                   PBRT_MAX_INCLUDE_DEPTH);
        return 1;
    }
    pbrt_lexer *lx = spm_xmalloc(sizeof *lx);
    if (pbrt_lex_open(lx, path, p->err)) {
        free(lx);
        return 1;
    }
    snprintf(p->canon[p->depth], SPM_PATH_MAX, "%s", path->path);
    p->files[p->depth++] = lx;
    return 0;
}

static void pop_file(pbrt_parser *p)
{
    pbrt_lexer *lx = p->files[--p->depth];
    pbrt_lex_close(lx);
    free(lx);
}

/* Include "file" / Import "file": relative to the including file's folder. */
static int dir_include(pbrt_parser *p, const char *where)
{
    char ref[SPM_PATH_MAX], fwhere[600];
    pbrt_lexer *lx = pbrt_lx(p);
    pbrt_lex_where(lx, fwhere, sizeof fwhere);
    if (pbrt_arg_string(p, "a file name", ref, sizeof ref))
        return 1;
    spm_file path;
    if (spm_path_check(lx->dir, ref, fwhere, &path, p->err))
        return 1;
    FILE *f = spm_path_fopen(&path, "rb");
    if (!f) {
        spm_errorf(p->err, "%s: included file '%s' not found (or not readable)", fwhere, ref);
        return 1;
    }
    fclose(f);
    (void)where;
    return push_file(p, &path, fwhere);
}

static const pbrt_directive file_directives[] = {
    {"Include", dir_include}, {"Import", dir_include}, {NULL, NULL}};

static int directive(pbrt_parser *p)
{
    pbrt_lexer *lx = pbrt_lx(p);
    const pbrt_directive *tables[] = {file_directives, pbrt_state_directives,
                                      pbrt_world_directives, pbrt_option_directives};
    if (lx->type != PT_WORD)
        return pbrt_lex_expected(lx, p->err, "a directive (such as Shape, Material, Camera)");
    char where[600], name[64];
    pbrt_lex_where(lx, where, sizeof where);
    snprintf(name, sizeof name, "%s", lx->text);
    for (int t = 0; t < 4; t++)
        for (const pbrt_directive *d = tables[t]; d->name; d++)
            if (!strcmp(d->name, name))
                return pbrt_lex_next(lx, p->err) || d->fn(p, where);
    spm_errorf(p->err, "%s: unknown directive '%.60s'", where, name);
    return 1;
}

static void parser_init(pbrt_parser *p, spm_scene *out, const char *path, spm_error *err)
{
    memset(p, 0, sizeof *p);
    p->err = err;
    spm_sb_init(&p->b, out, path);
    p->sp.b = &p->b;
    p->sp.err = err;
    spm_names_init(&p->sp.rgb_fits);
    spm_names_init(&p->named_mats);
    spm_names_init(&p->coordsys);
    spm_names_init(&p->obj_names);
    spm_mesh_cache_init(&p->cache);
    pbrt_mat_identity(p->gs.ctm);
    p->gs.area_colour = -1;
    p->cur_obj = -1;
    p->fov = 90.0;
    p->focal_distance = 1e6;
    p->width = 1280;
    p->height = 720;
    p->spp = 16;
    pbrt_mat_identity(p->cam_ctm);
    p->protos = spm_xmalloc(sizeof *p->protos);
    p->nprotos = 1;
    pbrt_material_default(&p->sp, &p->protos[0]);
}

static void parser_free(pbrt_parser *p)
{
    while (p->depth)
        pop_file(p);
    pbrt_objects_free(p);
    free(p->stack);
    free(p->protos);
    free(p->cs);
    spm_names_free(&p->sp.rgb_fits);
    spm_names_free(&p->named_mats);
    spm_names_free(&p->coordsys);
    spm_names_free(&p->obj_names);
    spm_mesh_cache_free(&p->cache);
    pbrt_warn_reset();
}

int spm_scene_parse_pbrt(const spm_file *file, spm_scene *out, spm_error *err)
{
    pbrt_parser p;
    parser_init(&p, out, file->shown, err);
    int rc = push_file(&p, file, "the command line");
    char where[600] = "";
    while (!rc && p.depth) {
        pbrt_lexer *lx = pbrt_lx(&p);
        if (lx->type != PT_EOF) {
            if (spm_stop_requested()) {
                spm_errorf(err, "interrupted while loading %s", lx->path);
                rc = 1;
                break;
            }
            rc = directive(&p);
            continue;
        }
        pbrt_lex_where(lx, where, sizeof where);
        if (p.depth > 1)
            pop_file(&p);
        else
            break;
    }
    if (!rc && p.cur_obj >= 0) {
        spm_errorf(err, "%s: ObjectBegin \"%s\" has no ObjectEnd", where, p.objs[p.cur_obj].name);
        rc = 1;
    }
    if (!rc && !p.world)
        rc = pbrt_options_finish(&p, where);
    if (!rc)
        pbrt_warn_summary();
    rc = rc || spm_sb_finish(&p.b, where, err);
    parser_free(&p);
    spm_sb_done(&p.b, !rc);
    return rc;
}

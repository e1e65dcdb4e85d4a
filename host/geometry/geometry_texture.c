/* The textures as the trace stage reads them (geometry.h
 * spm_geometry_textures; the layout: spm_shared.h SPM_TEXD_*). */
#include "geometry.h"
#include "texture.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

static spm_u32 fbits(float f)
{
    spm_u32 u;
    memcpy(&u, &f, sizeof u);
    return u;
}

/* words of the whole layout, for the scene's materials and textures */
static size_t count_words(const spm_scene *s)
{
    size_t n = SPM_TEXD_HEAD + (size_t)s->nmaterials + 2 * (size_t)s->npalettes * SPM_TEX_NODES_ALL +
               SPM_TEX_GRID + (size_t)s->ntextures;
    for (int m = 0; m < s->nmaterials; m++)
        if (s->materials[m].etex) { /* the emission words (SPM_TEXD_EMIT) */
            n += 2 * (size_t)s->nmaterials;
            break;
        }
    for (int t = 0; t < s->ntextures; t++) {
        n += SPM_TEX_HEADER(s->textures[t].nlevels) + spm_geometry_uvx_words(&s->textures[t].uvx);
        for (int l = 0; l < s->textures[t].nlevels; l++)
            n += 3 * (size_t)s->textures[t].lv[l].w * s->textures[t].lv[l].h;
    }
    return n + spm_geometry_alpha_words(s) + spm_geometry_nmap_words(s);
}

/* texture t's header and texels from word w on; the word after them */
static size_t put_texture(const spm_texture *t, spm_u32 *x, size_t w)
{
    size_t h = w, texels = w + SPM_TEX_HEADER(t->nlevels);
    x[h] = (spm_u32)t->nlevels, x[h + 1] = (spm_u32)t->wrap[0], x[h + 2] = (spm_u32)t->wrap[1];
    for (int l = 0; l < t->nlevels; l++) {
        const spm_texmap *m = &t->lv[l];
        size_t n = 3 * (size_t)m->w * m->h;
        x[h + 4 + 4 * l] = (spm_u32)texels;
        x[h + 5 + 4 * l] = (spm_u32)m->w;
        x[h + 6 + 4 * l] = (spm_u32)m->h;
        for (size_t i = 0; i < n; i++)
            x[texels + i] = fbits(m->rgb[i]);
        texels += n;
    }
    return spm_geometry_uvx_put(&t->uvx, x, h, SPM_TEX_UVX, texels);
}

/* palette p's survival ratios from word w on (spm_shared.h SPM_TEXD_SURVIVE):
 * mean(colour) / the largest mean among the palette's colours, at least
 * SPM_TEX_SURVIVE_MIN; the word after */
static size_t put_survival(const spm_scene *s, int p, spm_u32 *x, size_t w)
{
    const int *pal = s->palette + (size_t)p * SPM_TEX_NODES_ALL;
    double top = 0.0;
    for (int i = 0; i < SPM_TEX_NODES_ALL; i++)
        if (pal[i] >= 0)
            top = fmax(top, spm_spectrum_mean(&s->colours[pal[i]].s));
    for (int i = 0; i < SPM_TEX_NODES_ALL; i++)
        x[w++] = fbits(pal[i] >= 0 && top > 0.0
                           ? (float)fmin(fmax(spm_spectrum_mean(&s->colours[pal[i]].s) / top,
                                            SPM_TEX_SURVIVE_MIN),
                                       1.0)
                           : 1.0f);
    return w;
}

void spm_geometry_textures(const spm_scene *s, spm_geometry *g)
{
    int any = 0;
    for (int m = 0; m < s->nmaterials; m++)
        any |= ((s->materials[m].tex != 0 || s->materials[m].etex != 0) && s->palette) ||
               s->materials[m].alpha_mode != 0 || s->materials[m].mix_metal != 0 ||
               s->materials[m].nmap != 0;
    if (!any)
        return;
    g->uvs = spm_xcalloc((size_t)g->ntris * 6 + 1, sizeof *g->uvs);
    for (int i = 0; i < s->ntris; i++)
        if (s->tris[i].uv > 0 && s->tris[i].uv <= s->nuvs)
            memcpy(g->uvs + 6 * (size_t)i, s->uvs[s->tris[i].uv - 1], 6 * sizeof *g->uvs);
    g->ntex = count_words(s);
    spm_u32 *x = g->tex = spm_xcalloc(g->ntex, sizeof *g->tex);
    const size_t ngrid = (size_t)s->npalettes * SPM_TEX_NODES_ALL;
    size_t w = SPM_TEXD_HEAD;
    x[SPM_TEXD_NPAL] = (spm_u32)s->npalettes;
    x[SPM_TEXD_MATS] = (spm_u32)w;
    for (int m = 0; m < s->nmaterials; m++)
        x[w++] = (spm_u32)s->materials[m].tex | (spm_u32)s->materials[m].tpal << 16;
    int emits = 0;
    for (int m = 0; m < s->nmaterials; m++)
        emits |= s->materials[m].etex != 0;
    if (emits) {
        x[SPM_TEXD_EMIT] = (spm_u32)w;
        for (int m = 0; m < s->nmaterials; m++) {
            const spm_scene_material *sm = &s->materials[m];
            x[w++] = (spm_u32)sm->etex | (spm_u32)sm->etpal << 16;
            x[w++] = fbits(sm->etex ? sm->escale : 0.0f);
        }
    }
    x[SPM_TEXD_PALETTE] = (spm_u32)w;
    for (size_t i = 0; i < ngrid; i++)
        x[w++] = s->palette && s->palette[i] >= 0 ? (spm_u32)s->palette[i] : SPM_NONE;
    x[SPM_TEXD_SURVIVE] = (spm_u32)w;
    for (int p = 0; p < s->npalettes && s->palette; p++)
        w = put_survival(s, p, x, w);
    if (!s->palette)
        w += ngrid;
    x[SPM_TEXD_NODES] = (spm_u32)w;
    float nodes[SPM_TEX_GRID];
    spm_tex_grid_nodes(nodes);
    for (int k = 0; k < SPM_TEX_GRID; k++)
        x[w++] = fbits(nodes[k]);
    x[SPM_TEXD_TEXS] = (spm_u32)w;
    size_t offs = w;
    w += (size_t)s->ntextures;
    for (int t = 0; t < s->ntextures; t++) {
        x[offs + (size_t)t] = (spm_u32)w;
        w = put_texture(&s->textures[t], x, w);
    }
    spm_geometry_nmap_put(s, x, spm_geometry_alpha_put(s, x, w));
}

void spm_geometry_uvs_permute(spm_geometry *g, const int *perm)
{
    if (!g->uvs)
        return;
    float *to = spm_xmalloc(((size_t)g->ntris * 6 + 1) * sizeof *to);
    for (int i = 0; i < g->ntris; i++)
        memcpy(to + 6 * (size_t)i, g->uvs + 6 * (size_t)perm[i], 6 * sizeof *to);
    free(g->uvs);
    g->uvs = to;
}

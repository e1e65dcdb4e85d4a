/* The colour grid of a scene's textures (scene_build.h spm_sb_texture_palette;
 * spm_shared.h SPM_TEX_GRID): the trace stage picks, for a texel of linear RGB
 * (r, g, b), one corner of the grid cell around it, along each axis the
 * upper node with probability f = (x - lo) / (hi - lo); so the corners a
 * texel can reach are the lower node always and the upper one when x > lo.
 * Each reachable node becomes a scene colour, lifted once as any RGB
 * reflectance is (scene_rgb.c); the expected linear RGB of the pick is the
 * texel's, and so is its expected colour under any light the lift's spectra
 * are metamers under. */
#include "scene_build.h"
#include "texture.h"
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void spm_tex_grid_nodes(float nodes[SPM_TEX_GRID])
{
    for (int k = 0; k < SPM_TEX_GRID; k++) {
        double c = (double)k / (SPM_TEX_GRID - 1); /* the sRGB code 255 k / (G - 1) */
        nodes[k] = (float)(c <= 0.04045 ? c / 12.92 : pow((c + 0.055) / 1.055, 2.4));
    }
}

int spm_tex_grid_cell(const float nodes[SPM_TEX_GRID], float x)
{
    int lo = 0, hi = SPM_TEX_GRID - 1; /* nodes[lo] <= x < nodes[hi], or x at the top */
    while (hi - lo > 1) {
        int mid = (lo + hi) / 2;
        if (nodes[mid] <= x)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* Marks the nodes texel x (clamped to [0, 1]) can reach, bit per node. */
static void mark_texel(const float nodes[SPM_TEX_GRID], const float *rgb, unsigned char *used)
{
    int k[3], up[3];
    for (int c = 0; c < 3; c++) {
        float x = rgb[c] > 0.0f ? (rgb[c] < 1.0f ? rgb[c] : 1.0f) : 0.0f;
        k[c] = spm_tex_grid_cell(nodes, x);
        up[c] = x > nodes[k[c]];
    }
    for (int a = 0; a <= up[0]; a++)
        for (int b = 0; b <= up[1]; b++)
            for (int d = 0; d <= up[2]; d++)
                used[((k[0] + a) * SPM_TEX_GRID + k[1] + b) * SPM_TEX_GRID + k[2] + d] = 1;
}

static double spectrum_mean(const spm_spectrum *s)
{
    double m = 0.0;
    for (int i = 0; i < SPM_TRUTH_BINS; i++)
        m += s->nm1[i];
    return m / SPM_TRUTH_BINS;
}

/* Whether texture t (0-based) is on a reflectance (which = 0; a texture no
 * emission names counts, as every adopted one did before emissions were
 * textured) or on an emission (which = 1). */
static int texture_for(const spm_scene *s, int t, int which)
{
    int refl = 0, emit = 0;
    for (int m = 0; m < s->nmaterials; m++)
        refl |= s->materials[m].tex == t + 1, emit |= s->materials[m].etex == t + 1;
    return which ? emit : refl || !emit;
}

/* The grid nodes the texels of the textures for `which` can reach. */
static unsigned char *mark_used(const spm_scene *s, const float nodes[SPM_TEX_GRID], int which)
{
    unsigned char *used = spm_xcalloc((size_t)SPM_TEX_NODES_ALL, 1);
    for (int t = 0; t < s->ntextures; t++)
        for (int l = 0; texture_for(s, t, which) && l < s->textures[t].nlevels; l++) {
            const spm_texmap *m = &s->textures[t].lv[l];
            for (size_t i = 0; i < (size_t)m->w * m->h; i++)
                mark_texel(nodes, m->rgb + 3 * i, used);
        }
    return used;
}

/* The palette of emission spectra (the second, after the lifted one) for
 * the textured emissions: node (r, g, b) lifted as an RGB emission is
 * (rgb2spec.h spm_rgb_to_emission: the lift of the colour over its largest
 * component times D65, its luminance the node's), so a texel's expected
 * luminance is its own and the texture's mean is the mean texel's; a black
 * node emits nothing (SPM_NONE). */
static int emission_palette(spm_scene_builder *b, const float nodes[SPM_TEX_GRID],
                            const char *where, spm_error *err)
{
    spm_scene *s = b->s;
    int k = s->npalettes++, rc = 0;
    s->palette = spm_xrealloc(s->palette, (size_t)s->npalettes * SPM_TEX_NODES_ALL * sizeof *s->palette);
    int *to = s->palette + (size_t)k * SPM_TEX_NODES_ALL;
    unsigned char *used = mark_used(s, nodes, 1);
    spm_names fits;
    spm_names_init(&fits);
    for (int i = 0; i < SPM_TEX_NODES_ALL; i++) {
        int r = i / (SPM_TEX_GRID * SPM_TEX_GRID), g = i / SPM_TEX_GRID % SPM_TEX_GRID;
        double rgb[3] = {nodes[r], nodes[g], nodes[i % SPM_TEX_GRID]};
        to[i] = -1;
        if (used[i] && !rc && (to[i] = spm_sb_rgb_colour(b, &fits, rgb, SPM_KIND_EMISSION, where, err)) < -1)
            rc = 1;
        to[i] = to[i] < 0 ? -1 : to[i];
    }
    spm_names_free(&fits);
    free(used);
    for (int m = 0; m < s->nmaterials; m++)
        s->materials[m].etpal = k;
    return rc;
}

int spm_sb_texture_palette(spm_scene_builder *b, const char *where, spm_error *err)
{
    spm_scene *s = b->s;
    if (!s->ntextures)
        return 0;
    const int n = SPM_TEX_GRID * SPM_TEX_GRID * SPM_TEX_GRID;
    float nodes[SPM_TEX_GRID];
    spm_tex_grid_nodes(nodes);
    unsigned char *used = mark_used(s, nodes, 0);
    s->palette = spm_xmalloc((size_t)n * sizeof *s->palette);
    s->npalettes = 1;
    spm_names fits;
    spm_names_init(&fits);
    int best = -1, rc = 0;
    double best_mean = -1.0;
    for (int i = 0; i < n && !rc; i++) {
        s->palette[i] = -1;
        if (!used[i])
            continue;
        int r = i / (SPM_TEX_GRID * SPM_TEX_GRID), g = i / SPM_TEX_GRID % SPM_TEX_GRID;
        double rgb[3] = {nodes[r], nodes[g], nodes[i % SPM_TEX_GRID]};
        int c = spm_sb_rgb_colour(b, &fits, rgb, SPM_KIND_REFLECTANCE, where, err);
        if (c == -1) { /* black */
            spm_spectrum zero;
            spm_spectrum_constant(0.0, SPM_KIND_REFLECTANCE, &zero);
            c = spm_sb_colour(b, "black", &zero, where, err);
        }
        if (c < 0) {
            rc = 1;
            break;
        }
        s->palette[i] = c;
        double mean = spectrum_mean(&s->colours[c].s);
        if (mean > best_mean)
            best_mean = mean, best = c;
    }
    spm_names_free(&fits);
    free(used);
    for (int m = 0; m < s->nmaterials && !rc; m++)
        if (s->materials[m].tex)
            s->materials[m].refl = best;
    for (int m = 0; m < s->nmaterials && !rc; m++)
        if (s->materials[m].etex)
            return emission_palette(b, nodes, where, err);
    return rc;
}

#include "render_stats.h"

static double kernel_s(const spm_pass_stats *p) { return p->trace_s + p->shade_s + p->accum_s; }

/* A device's own speed: its paths over the wall time it spent rendering them
 * (not over the whole render, which would count its idle wait at the end). */
static double device_rate(const spm_run_result *r, int i)
{
    return r->busy_s[i] > 0 ? (double)r->per_backend[i].paths / r->busy_s[i] : 0.0;
}

static double share(const spm_run_result *r, int i)
{
    return r->total.paths ? (double)r->per_backend[i].paths / (double)r->total.paths : 0.0;
}

static void json_string(FILE *f, const char *s)
{
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"' || *s == '\\')
            fprintf(f, "\\%c", *s);
        else if ((unsigned char)*s < 0x20)
            fprintf(f, "\\u%04x", *s);
        else
            fputc(*s, f);
    }
    fputc('"', f);
}

void spm_render_stats_text(FILE *f, const spm_render_config *c, const spm_render_setup *s,
                           const spm_run_result *r)
{
    const spm_pass_stats *t = &r->total;
    fprintf(f, "scene        %s (%dx%d, %d spp, mode %s, seed %u)\n", s->scene.path, s->scene.width,
            s->scene.height, r->spp_done, spm_mode_name(c->mode), c->seed);
    fprintf(f, "wall         %.3f s   %.3f Mpaths/s   process CPU %.3f s\n", r->wall_s,
            r->wall_s > 0 ? (double)t->paths / r->wall_s * 1e-6 : 0.0, r->cpu_s);
    fprintf(f, "stages       trace %.3f s   shade %.3f s   accumulate %.3f s\n", t->trace_s,
            t->shade_s, t->accum_s);
    fprintf(f, "paths        %llu   truncated %llu   non-finite %llu\n",
            (unsigned long long)t->paths, (unsigned long long)t->truncated,
            (unsigned long long)t->nonfinite);
    fprintf(f, "level  bins   paths      set by emitter  set by reflector  coarsest\n");
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        const uint64_t *lp = t->level_paths[l];
        uint64_t all = lp[0] + lp[1] + lp[2];
        if (!all)
            continue;
        fprintf(f, "%5d  %4d   %-10llu %-15llu %-17llu %llu\n", l, SPM_LEVEL_BINS(l),
                (unsigned long long)all, (unsigned long long)lp[SPM_SETBY_EMITTER],
                (unsigned long long)lp[SPM_SETBY_REFLECTOR], (unsigned long long)lp[SPM_SETBY_NONE]);
    }
    for (int i = 0; i < s->nb; i++) {
        const spm_pass_stats *d = &r->per_backend[i];
        fprintf(f,
                "device %d     %s: %llu paths (%.1f%%) in %d passes, kernel %.3f s, busy %.3f s, "
                "%.3f Mpaths/s%s\n",
                i, s->b[i]->name, (unsigned long long)d->paths, 100.0 * share(r, i),
                r->passes_by_backend[i], kernel_s(d), r->busy_s[i], device_rate(r, i) * 1e-6,
                r->failed[i] ? "  FAILED" : "");
    }
}

void spm_render_stats_json(FILE *f, const spm_render_config *c, const spm_render_setup *s,
                           const spm_run_result *r)
{
    const spm_pass_stats *t = &r->total;
    fprintf(f, "{\"scene\": ");
    json_string(f, s->scene.path);
    fprintf(f, ", \"mode\": \"%s\", \"width\": %d, \"height\": %d, \"spp\": %d, \"seed\": %u",
            spm_mode_name(c->mode), s->scene.width, s->scene.height, r->spp_done, c->seed);
    fprintf(f, ", \"wall_s\": %.6f, \"cpu_s\": %.6f, \"trace_s\": %.6f, \"shade_s\": %.6f, \"accum_s\": %.6f",
            r->wall_s, r->cpu_s, t->trace_s, t->shade_s, t->accum_s);
    fprintf(f, ", \"kernel_s\": %.6f, \"paths\": %llu, \"paths_per_s\": %.1f", kernel_s(t),
            (unsigned long long)t->paths, r->wall_s > 0 ? (double)t->paths / r->wall_s : 0.0);
    fprintf(f, ", \"truncated\": %llu, \"nonfinite\": %llu, \"interrupted\": %s",
            (unsigned long long)t->truncated, (unsigned long long)t->nonfinite,
            r->interrupted ? "true" : "false");
    fprintf(f, ", \"passes\": %d, \"passes_in_film\": %d", r->npasses, r->passes_in_film);
    fprintf(f, ", \"threshold\": %g, \"levels\": [", c->pretest.threshold);
    for (int l = 0; l < SPM_NUM_LEVELS; l++) {
        const uint64_t *lp = t->level_paths[l];
        fprintf(f, "%s{\"level\": %d, \"bins\": %d, \"paths\": %llu, \"set_by_emitter\": %llu, "
                   "\"set_by_reflector\": %llu, \"coarsest\": %llu}",
                l ? ", " : "", l, SPM_LEVEL_BINS(l), (unsigned long long)(lp[0] + lp[1] + lp[2]),
                (unsigned long long)lp[SPM_SETBY_EMITTER], (unsigned long long)lp[SPM_SETBY_REFLECTOR],
                (unsigned long long)lp[SPM_SETBY_NONE]);
    }
    fprintf(f, "], \"devices\": [");
    for (int i = 0; i < s->nb; i++) {
        const spm_pass_stats *d = &r->per_backend[i];
        fprintf(f, "%s{\"name\": ", i ? ", " : "");
        json_string(f, s->b[i]->name);
        fprintf(f, ", \"paths\": %llu, \"share\": %.4f, \"passes\": %d, \"kernel_s\": %.6f, "
                   "\"trace_s\": %.6f, \"shade_s\": %.6f, \"busy_s\": %.6f, "
                   "\"paths_per_s\": %.1f, \"failed\": %s}",
                (unsigned long long)d->paths, share(r, i), r->passes_by_backend[i], kernel_s(d),
                d->trace_s, d->shade_s, r->busy_s[i], device_rate(r, i),
                r->failed[i] ? "true" : "false");
    }
    fprintf(f, "]}\n");
}

int spm_render_warn_dropped(const spm_run_result *r, const spm_film *film)
{
    uint64_t samples = r->total.paths, bad = r->total.nonfinite;
    uint64_t sums = (uint64_t)film->width * (uint64_t)film->height * (uint64_t)r->passes_in_film;
    int warned = 0;
    if (samples && (double)bad > SPM_DROPPED_WARN * (double)samples) {
        spm_warnf("%.3g%% of the samples (%llu of %llu) were NaN or infinite and were left out: "
                  "the image is darker than the scene (an emission too bright for float "
                  "arithmetic?)",
                  100.0 * (double)bad / (double)samples, (unsigned long long)bad,
                  (unsigned long long)samples);
        warned = 1;
    }
    if (sums && (double)film->nonfinite > SPM_DROPPED_WARN * (double)sums) {
        spm_warnf("%.3g%% of the pixels' pass sums (%lld of %llu) overflowed to infinity and were "
                  "left out: the image is darker than the scene (an emission too bright for "
                  "float arithmetic?)",
                  100.0 * (double)film->nonfinite / (double)sums, film->nonfinite,
                  (unsigned long long)sums);
        warned = 1;
    }
    return warned;
}

#include "render_stats.h"
#include "scene_build.h"
#include <sys/resource.h>

/* The process's peak resident set so far (Linux reports ru_maxrss in KiB);
 * a mesh importer runs in a child process and is not counted. */
static long long peak_rss_bytes(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0)
        return 0;
    return (long long)ru.ru_maxrss * 1024;
}

static double kernel_s(const spm_pass_stats *p) { return p->trace_s + p->shade_s + p->accum_s; }

/* Kernel times are known unless a device gave none (Rusticl has no profiling). */
static int timed(const spm_pass_stats *p) { return p->untimed == 0; }

static int levelled(int mode) { return spm_mode(mode)->levelled; }

static double stages_total(const spm_stage_times *t)
{
    return t->load_s + t->bvh_s + t->tables_s + t->kernels_s + t->render_s + t->output_s;
}

/* "%.3f s", or "n/a" when not known. */
static const char *secs(char *buf, size_t n, double v, int known)
{
    if (known)
        snprintf(buf, n, "%.3f s", v);
    else
        snprintf(buf, n, "n/a");
    return buf;
}

/* A JSON number with 6 decimals, or null when not known. */
static void json_secs(FILE *f, const char *key, double v, int known)
{
    if (known)
        fprintf(f, ", \"%s\": %.6f", key, v);
    else
        fprintf(f, ", \"%s\": null", key);
}

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
    const spm_stage_times *st = &s->times;
    int spp = spm_render_spp(c, &s->scene);
    char a[32], b[32], d[32];
    fprintf(f, "scene        %s (%dx%d, %d", s->scene.path, s->scene.width, s->scene.height,
            r->spp_done);
    if (c->time_s > 0 && spp == SPM_SCENE_MAX_SPP) /* no --spp: the budget alone */
        fprintf(f, " in a %g s budget", c->time_s);
    else if (r->spp_done != spp)
        fprintf(f, " of %d", spp);
    fprintf(f, " spp, mode %s, seed %u)\n", spm_mode_name(c->mode), c->seed);
    fprintf(f, "stages       load %.3f s   BVH %.3f s   tables+pretest %.3f s   kernel build %.3f s"
               "   render %.3f s   output %.3f s   total %.3f s\n",
            st->load_s, st->bvh_s, st->tables_s, st->kernels_s, st->render_s, st->output_s,
            stages_total(st));
    if (st->compiled_in_render > 0)
        fprintf(f, "             (a kernel compiled during the timed render: its time includes "
                   "the compile)\n");
    const spm_geometry *g = &s->geom;
    fprintf(f, "bvh          %d triangles   %d nodes   %d leaves   SAH cost %.3f   %d threads\n",
            g->ntris, g->nnodes, g->bvh.leaves, g->bvh.sah_cost, g->bvh.threads);
    fprintf(f, "memory       peak RSS %.1f MB\n", (double)peak_rss_bytes() / 1e6);
    fprintf(f, "render       %.3f s   %.3f Mpaths/s   process CPU %.3f s\n", r->wall_s,
            r->wall_s > 0 ? (double)t->paths / r->wall_s * 1e-6 : 0.0, r->cpu_s);
    fprintf(f, "kernels      trace %s   shade %s   accumulate %s%s\n",
            secs(a, sizeof a, t->trace_s, timed(t)), secs(b, sizeof b, t->shade_s, timed(t)),
            secs(d, sizeof d, t->accum_s, timed(t)),
            timed(t) ? "" : "   (the device gives no kernel times)");
    fprintf(f, "paths        %llu   truncated %llu   non-finite %llu\n",
            (unsigned long long)t->paths, (unsigned long long)t->truncated,
            (unsigned long long)t->nonfinite);
    if (levelled(c->mode)) {
        fprintf(f, "level  bins   paths      set by emitter  set by reflector  coarsest\n");
        for (int l = 0; l < SPM_NUM_LEVELS; l++) {
            const uint64_t *lp = t->level_paths[l];
            uint64_t all = lp[0] + lp[1] + lp[2];
            if (!all)
                continue;
            fprintf(f, "%5d  %4d   %-10llu %-15llu %-17llu %llu\n", l, SPM_LEVEL_BINS(l),
                    (unsigned long long)all, (unsigned long long)lp[SPM_SETBY_EMITTER],
                    (unsigned long long)lp[SPM_SETBY_REFLECTOR],
                    (unsigned long long)lp[SPM_SETBY_NONE]);
        }
    }
    for (int i = 0; i < s->nb; i++) {
        const spm_pass_stats *dv = &r->per_backend[i];
        fprintf(f,
                "device %d     %s: %llu paths (%.1f%%) in %d passes, kernel %s, busy %.3f s, "
                "%.3f Mpaths/s%s\n",
                i, s->b[i]->name, (unsigned long long)dv->paths, 100.0 * share(r, i),
                r->passes_by_backend[i], secs(a, sizeof a, kernel_s(dv), timed(dv)), r->busy_s[i],
                device_rate(r, i) * 1e-6, r->failed[i] ? "  FAILED" : "");
    }
}

void spm_render_stats_json(FILE *f, const spm_render_config *c, const spm_render_setup *s,
                           const spm_run_result *r)
{
    const spm_pass_stats *t = &r->total;
    const spm_stage_times *st = &s->times;
    fprintf(f, "{\"version\": \"%s\", \"scene\": ", SPM_VERSION);
    json_string(f, s->scene.path);
    fprintf(f, ", \"mode\": \"%s\", \"width\": %d, \"height\": %d, \"spp\": %d, "
               "\"spp_requested\": %d, \"seed\": %u",
            spm_mode_name(c->mode), s->scene.width, s->scene.height, r->spp_done,
            spm_render_spp(c, &s->scene), c->seed);
    fprintf(f, ", \"time_budget_s\": %g, \"time_up\": %s", c->time_s,
            r->time_up ? "true" : "false");
    fprintf(f, ", \"stages\": {\"load_s\": %.6f, \"bvh_s\": %.6f, \"tables_s\": %.6f, "
               "\"kernel_build_s\": %.6f, \"render_s\": %.6f, \"output_s\": %.6f, "
               "\"total_s\": %.6f}",
            st->load_s, st->bvh_s, st->tables_s, st->kernels_s, st->render_s, st->output_s,
            stages_total(st));
    fprintf(f, ", \"compiled_during_timing\": %s",
            st->compiled_in_render < 0 ? "null" : st->compiled_in_render ? "true" : "false");
    const spm_geometry *g = &s->geom;
    fprintf(f, ", \"bvh\": {\"triangles\": %d, \"nodes\": %d, \"leaves\": %d, "
               "\"sah_cost\": %.6f, \"threads\": %d}",
            g->ntris, g->nnodes, g->bvh.leaves, g->bvh.sah_cost, g->bvh.threads);
    fprintf(f, ", \"peak_rss_bytes\": %lld", peak_rss_bytes());
    fprintf(f, ", \"wall_s\": %.6f, \"cpu_s\": %.6f", r->wall_s, r->cpu_s);
    json_secs(f, "trace_s", t->trace_s, timed(t));
    json_secs(f, "shade_s", t->shade_s, timed(t));
    json_secs(f, "accum_s", t->accum_s, timed(t));
    json_secs(f, "kernel_s", kernel_s(t), timed(t));
    fprintf(f, ", \"paths\": %llu, \"paths_per_s\": %.1f", (unsigned long long)t->paths,
            r->wall_s > 0 ? (double)t->paths / r->wall_s : 0.0);
    fprintf(f, ", \"truncated\": %llu, \"nonfinite\": %llu, \"interrupted\": %s",
            (unsigned long long)t->truncated, (unsigned long long)t->nonfinite,
            r->interrupted ? "true" : "false");
    fprintf(f, ", \"passes\": %d, \"passes_in_film\": %d", r->npasses, r->passes_in_film);
    if (levelled(c->mode)) {
        fprintf(f, ", \"threshold\": %g, \"metric\": \"%s\", \"coarsest_level\": %d, \"levels\": [",
                c->pretest.threshold, c->pretest.metric == SPM_METRIC_DEAB ? "deab" : "de00",
                c->pretest.coarsest_level);
        for (int l = 0; l < SPM_NUM_LEVELS; l++) {
            const uint64_t *lp = t->level_paths[l];
            fprintf(f, "%s{\"level\": %d, \"bins\": %d, \"paths\": %llu, \"set_by_emitter\": %llu, "
                       "\"set_by_reflector\": %llu, \"coarsest\": %llu}",
                    l ? ", " : "", l, SPM_LEVEL_BINS(l), (unsigned long long)(lp[0] + lp[1] + lp[2]),
                    (unsigned long long)lp[SPM_SETBY_EMITTER],
                    (unsigned long long)lp[SPM_SETBY_REFLECTOR],
                    (unsigned long long)lp[SPM_SETBY_NONE]);
        }
        fprintf(f, "]");
    } else {
        fprintf(f, ", \"threshold\": null, \"metric\": null, \"coarsest_level\": null, "
                   "\"levels\": null");
    }
    fprintf(f, ", \"devices\": [");
    for (int i = 0; i < s->nb; i++) {
        const spm_pass_stats *d = &r->per_backend[i];
        fprintf(f, "%s{\"name\": ", i ? ", " : "");
        json_string(f, s->b[i]->name);
        fprintf(f, ", \"paths\": %llu, \"share\": %.4f, \"passes\": %d",
                (unsigned long long)d->paths, share(r, i), r->passes_by_backend[i]);
        json_secs(f, "kernel_s", kernel_s(d), timed(d));
        json_secs(f, "trace_s", d->trace_s, timed(d));
        json_secs(f, "shade_s", d->shade_s, timed(d));
        fprintf(f, ", \"busy_s\": %.6f, \"paths_per_s\": %.1f, \"failed\": %s}", r->busy_s[i],
                device_rate(r, i), r->failed[i] ? "true" : "false");
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

/* The render loop's resume, time budget and checkpoints with stand-in
 * backends (no OpenCL; render_run.h): a film rendered to S samples on the
 * pass grid and continued to N is the N-sample film bit for bit, on one device
 * and on two of unequal speed; a film cut short keeps a run of whole passes
 * when asked to (contiguous); a time budget ends the loop within it plus a
 * pass, and a budget shorter than a pass still renders one; every checkpoint
 * is a copy of the film of the passes so far, equal to that many passes of a
 * render in one go. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "render_run.h"
#include "testutil.h"

#define W 6
#define H 4
#define NPIX (W * H)
#define P 3 /* samples per pixel a pass */

#include "fake_passes.h"

typedef struct {
    int delay_us; /* per pass */
    int batches;  /* > 1: a pass is this many batches, stoppable between them */
} fake;

static int fake_pass(spm_backend *b, spm_u32 first, spm_u32 spp, float *img, spm_pass_stats *st,
                     spm_error *err)
{
    (void)err;
    fake *f = b->impl;
    int n = f->batches > 1 ? f->batches : 1;
    for (int k = 0; k < n; k++) {
        usleep((useconds_t)(f->delay_us / n));
        if (k + 1 < n && spm_pass_batch_end(&b->ctl, (uint64_t)(k + 1) * NPIX * spp / (unsigned)n))
            return SPM_PASS_STOPPED;
    }
    fake_pass_image(first, spp, img);
    st->paths += (uint64_t)NPIX * spp;
    return 0;
}

static void fake_destroy(spm_backend *b) { (void)b; }

static void make(spm_backend *b, fake *f, int delay_us, int batches)
{
    f->delay_us = delay_us;
    f->batches = batches;
    memset(b, 0, sizeof *b);
    snprintf(b->name, sizeof b->name, "fake %d us", delay_us);
    b->pass = fake_pass;
    b->destroy = fake_destroy;
    b->impl = f;
}

/* The film of one render to spp: the grid's passes added in order. */
static void film_to(int spp, spm_film *film)
{
    spm_error err;
    spm_film_init(film, W, H, &err);
    float img[3 * NPIX];
    for (int first = 0; first < spp; first += P) {
        int n = spp - first < P ? spp - first : P;
        fake_pass_image((spm_u32)first, (spm_u32)n, img);
        spm_film_add_pass(film, img, n);
    }
}

static int same_film(const spm_film *a, const spm_film *b)
{
    return a->samples == b->samples && !memcmp(a->sum, b->sum, sizeof(double) * 3 * NPIX);
}

/* Renders into film (which holds o->start samples) with nb fakes. */
static int run(fake *f, int nb, const spm_run_opts *o, spm_film *film, spm_run_result *r)
{
    spm_backend bs[4], *b[4];
    for (int i = 0; i < nb; i++) {
        make(&bs[i], &f[i], f[i].delay_us, f[i].batches);
        b[i] = &bs[i];
    }
    spm_error err;
    err.msg[0] = 0;
    int rc = spm_render_run(b, nb, NPIX, o, film, r, &err);
    if (rc)
        fprintf(stderr, "render: %s\n", err.msg);
    return rc;
}

static void resumes(int nb)
{
    for (int start = 3; start <= 15; start += 12) { /* 1 pass, 5 passes: on the grid */
        fake f[2] = {{200, 1}, {900, 1}};
        spm_film film, one;
        spm_run_result r;
        spm_run_opts o = {.spp = start, .spp_per_pass = P};
        spm_film_init(&film, W, H, &(spm_error){0});
        CHECK(run(f, nb, &o, &film, &r) == 0 && film.samples == start, "%d devices: to %d", nb,
              start);
        o.spp = 37; /* the last pass of a single sample */
        o.start = start;
        CHECK(run(f, nb, &o, &film, &r) == 0, "%d devices: resumed from %d", nb, start);
        film_to(37, &one);
        CHECK(same_film(&one, &film), "%d devices: %d then 37 is not the 37-sample film", nb, start);
        CHECK(r.spp_done == 37 && r.passes_in_film == (37 - start + P - 1) / P,
              "%d devices from %d: spp %d, passes %d", nb, start, r.spp_done, r.passes_in_film);
        spm_film_free(&one);
        spm_film_free(&film);
    }
    /* off the grid (4 = a pass and a sample): the rest of pass 1 comes first */
    fake f[2] = {{200, 1}, {900, 1}};
    spm_film film;
    spm_run_result r;
    film_to(4, &film);
    spm_run_opts o = {.spp = 10, .spp_per_pass = P, .start = 4};
    CHECK(run(f, nb, &o, &film, &r) == 0 && film.samples == 10 && r.passes_in_film == 3,
          "off the grid: %lld samples, %d passes (2, 3, 3 samples)", film.samples, r.passes_in_film);
    spm_film_free(&film);
}

/* A stop while the slow device holds an early pass and the fast one has
 * finished the later ones: with contiguous, those beyond the gap are left
 * out, so the film is a run of whole passes; without, they go in. */
static volatile sig_atomic_t stop_flag;

static void *stop_later(void *arg)
{
    (void)arg;
    usleep(300000);
    stop_flag = 1;
    return NULL;
}

static void contiguous(void)
{
    setenv("SPECMIP_TEST_MEET", "2", 1); /* both devices take a first pass */
    for (int keep = 0; keep < 2; keep++) {
        /* the fast device renders the other 19 passes in ~40 ms (on a
         * loaded machine at least some of them before the stop at 0.3 s);
         * the slow one's first pass (2 s, in batches of 20 ms) is cut by it */
        fake f[2] = {{2000, 1}, {2000000, 100}};
        spm_film film, one;
        spm_run_result r;
        spm_run_opts o = {.spp = 60, .spp_per_pass = P, .stop = &stop_flag, .contiguous = keep};
        spm_film_init(&film, W, H, &(spm_error){0});
        stop_flag = 0;
        pthread_t th;
        pthread_create(&th, NULL, stop_later, NULL);
        CHECK(run(f, 2, &o, &film, &r) == 0 && r.interrupted, "contiguous %d: interrupted", keep);
        pthread_join(th, NULL);
        film_to((int)film.samples, &one);
        if (keep) {
            CHECK(r.passes_dropped >= 1 && r.passes_in_film + r.passes_dropped <= 19,
                  "contiguous: %d in the film, %d dropped", r.passes_in_film, r.passes_dropped);
            CHECK(same_film(&one, &film) && r.spp_done == film.samples,
                  "contiguous: the film is not the first %lld samples", film.samples);
        } else {
            CHECK(r.passes_dropped == 0 && r.passes_in_film >= 2,
                  "not contiguous: %d in the film, %d dropped", r.passes_in_film, r.passes_dropped);
        }
        spm_film_free(&one);
        spm_film_free(&film);
    }
    unsetenv("SPECMIP_TEST_MEET");
}

/* ---- checkpoints ---- */
typedef struct {
    int n, bad;
    long long last;
} ck_log;

static void on_checkpoint(void *ctx, const spm_film *film, const spm_run_result *r)
{
    ck_log *k = ctx;
    spm_film one;
    film_to((int)film->samples, &one);
    k->bad += !same_film(&one, film) || film->samples % P || film->samples <= k->last ||
              r->spp_done != film->samples;
    k->last = film->samples;
    k->n++;
    spm_film_free(&one);
}

static void checkpoints(void)
{
    fake f[2] = {{20000, 1}, {30000, 1}};
    ck_log k = {0, 0, 0};
    spm_film film, one;
    spm_run_result r;
    spm_run_opts o = {.spp = 90, .spp_per_pass = P, .checkpoint_s = 0.05,
                      .checkpoint = on_checkpoint, .checkpoint_ctx = &k};
    spm_film_init(&film, W, H, &(spm_error){0});
    CHECK(run(f, 2, &o, &film, &r) == 0, "checkpoints: the render");
    film_to(90, &one);
    CHECK(same_film(&one, &film), "checkpoints: the film is the one-go film");
    CHECK(k.n >= 3, "checkpoints: %d of them in ~0.5 s at one every 0.05 s", k.n);
    CHECK(!k.bad, "checkpoints: %d of %d were not the film of their passes", k.bad, k.n);
    spm_film_free(&one);
    spm_film_free(&film);
}

/* ---- the time budget ---- */
static void budget(void)
{
    /* 30 ms passes, a 0.3 s budget: ends within a pass of it (0.3 s more is
     * a generous bound on a loaded machine), having filled most of it */
    fake f[2] = {{30000, 3}, {30000, 3}};
    spm_film film;
    spm_run_result r;
    spm_run_opts o = {.spp = 3000, .spp_per_pass = P, .time_s = 0.3, .contiguous = 1};
    spm_film_init(&film, W, H, &(spm_error){0});
    CHECK(run(f, 2, &o, &film, &r) == 0, "budget: the render");
    CHECK(r.time_up && !r.interrupted, "budget: time_up %d, interrupted %d", r.time_up,
          r.interrupted);
    CHECK(r.wall_s < 0.6, "budget: %.3f s for a 0.3 s budget", r.wall_s);
    CHECK(r.passes_in_film >= 2 && film.samples == r.spp_done && film.samples % P == 0,
          "budget: %d passes, %lld samples", r.passes_in_film, film.samples);
    spm_film one;
    film_to((int)film.samples, &one);
    CHECK(same_film(&one, &film), "budget: the film is a run of whole passes");
    spm_film_free(&one);
    spm_film_free(&film);
    /* a budget shorter than a pass: the first pass still ends, alone */
    fake g[1] = {{50000, 5}};
    spm_run_opts q = {.spp = 3000, .spp_per_pass = P, .time_s = 0.01};
    spm_film_init(&film, W, H, &(spm_error){0});
    CHECK(run(g, 1, &q, &film, &r) == 0 && r.time_up && r.passes_in_film == 1,
          "short budget: %d passes, time_up %d", r.passes_in_film, r.time_up);
    spm_film_free(&film);
}

int main(void)
{
    resumes(1);
    resumes(2);
    contiguous();
    checkpoints();
    budget();
    TEST_END();
}

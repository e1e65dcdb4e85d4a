/* The render loop's scheduling with stand-in backends (no OpenCL): whatever
 * the number of devices, their speeds and failures, the film equals the one
 * device film bit for bit; a failed device's pass is rendered by another; when
 * all fail, every finished pass is still in the film; a stop ends passes in
 * flight at a batch boundary, dropping them, and is no failure; a fast device
 * runs ahead of a slow one only within the window; the end game's decision. */
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#include "render_run.h"
#include "testutil.h"

#define W 7
#define H 5
#define NPIX (W * H)
#define SPP 37
#define SPP_PER_PASS 3 /* 13 passes, the last one of a single sample */
#define NPASSES ((SPP + SPP_PER_PASS - 1) / SPP_PER_PASS)

#include "fake_passes.h"

typedef struct {
    int delay_us;               /* per pass: the device's speed */
    int fail_at;                /* its pass number (counted per device) that fails; -1 never */
    int first_delay_us;         /* extra on its first pass */
    int passes;                 /* passes it was handed */
    volatile sig_atomic_t *stop_after; /* set this flag after the device's second pass */
    int batches;                /* > 0: a pass is this many batches, with spm_pass_batch_end
                                   between them (stop_after then stops the third pass
                                   after its first batch) */
    int batch_calls;            /* batch ends the render loop was told of (ctl.batch_done set) */
    int done_first[NPASSES];    /* first samples of the passes it finished */
    int ndone;
    int meet;                   /* > 0: its first pass waits (up to 2 s) until this many
                                   devices have begun one, so that the test does not hang on
                                   which thread the system happens to start first */
} fake;

static int met;                 /* devices that have begun their first pass (meet) */

static volatile int slow_busy;  /* the window test: the slow device is in its first pass */
static int fast_while_slow;     /* passes another device finished meanwhile */

static int fake_pass(spm_backend *b, spm_u32 first, spm_u32 spp, float *img, spm_pass_stats *st,
                     spm_error *err)
{
    fake *f = b->impl;
    int n = f->passes++;
    if (n == f->fail_at) {
        spm_errorf(err, "injected failure");
        return 1;
    }
    if (n == 0 && f->meet) {
        __atomic_add_fetch(&met, 1, __ATOMIC_SEQ_CST);
        for (int t = 0; t < 2000 && __atomic_load_n(&met, __ATOMIC_SEQ_CST) < f->meet; t++)
            usleep(1000);
    }
    if (n == 0 && f->first_delay_us) {
        __atomic_store_n(&slow_busy, 1, __ATOMIC_SEQ_CST);
        usleep((useconds_t)f->first_delay_us);
        __atomic_store_n(&slow_busy, 0, __ATOMIC_SEQ_CST);
    } else if (__atomic_load_n(&slow_busy, __ATOMIC_SEQ_CST)) {
        __atomic_add_fetch(&fast_while_slow, 1, __ATOMIC_SEQ_CST);
    }
    usleep((useconds_t)f->delay_us);
    for (int k = 1; k < f->batches; k++) {
        if (f->stop_after && f->ndone == 2)
            *f->stop_after = 1;
        f->batch_calls += b->ctl.batch_done != NULL;
        if (spm_pass_batch_end(&b->ctl, (uint64_t)k * NPIX * spp / (unsigned)f->batches))
            return SPM_PASS_STOPPED;
    }
    fake_pass_image(first, spp, img);
    st->paths += (uint64_t)NPIX * spp;
    f->done_first[f->ndone++] = (int)first;
    if (f->stop_after && f->ndone == 2 && !f->batches)
        *f->stop_after = 1;
    return 0;
}

static void fake_destroy(spm_backend *b) { (void)b; }

static void make(spm_backend *b, fake *f, int delay_us, int fail_at)
{
    memset(f, 0, sizeof *f);
    f->delay_us = delay_us;
    f->fail_at = fail_at;
    memset(b, 0, sizeof *b);
    snprintf(b->name, sizeof b->name, "fake %d us", delay_us);
    b->pass = fake_pass;
    b->destroy = fake_destroy;
    b->impl = f;
}

static int run(spm_backend *bs, int nb, volatile sig_atomic_t *stop, size_t window_bytes,
               spm_film *film, spm_run_result *r, spm_error *err)
{
    spm_backend *b[SPM_MAX_BACKENDS];
    for (int i = 0; i < nb; i++)
        b[i] = &bs[i];
    spm_run_opts o = {.spp = SPP, .spp_per_pass = SPP_PER_PASS, .stop = stop, .progress = 0};
    spm_film_init(film, W, H, err);
    return window_bytes ? spm_render_run_window(b, nb, NPIX, &o, window_bytes, film, r, err)
                        : spm_render_run(b, nb, NPIX, &o, film, r, err);
}

static int same_film(const spm_film *a, const spm_film *b)
{
    return a->samples == b->samples && !memcmp(a->sum, b->sum, sizeof(double) * 3 * NPIX);
}

/* The film of exactly the passes whose first samples are marked, added in pass order. */
static void film_of(const int *marked, spm_film *film)
{
    spm_error err;
    spm_film_init(film, W, H, &err);
    float img[3 * NPIX];
    for (int p = 0; p < NPASSES; p++) {
        spm_u32 first = (spm_u32)p * SPP_PER_PASS, spp = SPP - first < SPP_PER_PASS ? SPP - first
                                                                                     : SPP_PER_PASS;
        if (marked[first]) {
            fake_pass_image(first, spp, img);
            spm_film_add_pass(film, img, (int)spp);
        }
    }
}

static void splits(const spm_film *ref)
{
    spm_backend b[3];
    fake f[3];
    spm_film film;
    spm_run_result r;
    spm_error err;
    /* unequal speeds: the devices take unequal shares, the film is the same */
    make(&b[0], &f[0], 300, -1);
    make(&b[1], &f[1], 1000, -1);
    make(&b[2], &f[2], 0, -1);
    met = 0;
    for (int i = 0; i < 3; i++)
        f[i].meet = 3;
    int rc = run(b, 3, NULL, 0, &film, &r, &err);
    CHECK(rc == 0, "3 devices: %s", err.msg);
    CHECK(same_film(ref, &film), "3 devices: film differs from one device's");
    CHECK(r.passes_by_backend[0] + r.passes_by_backend[1] + r.passes_by_backend[2] == NPASSES,
          "passes %d+%d+%d", r.passes_by_backend[0], r.passes_by_backend[1], r.passes_by_backend[2]);
    CHECK(r.total.paths == (uint64_t)NPIX * SPP && r.spp_done == SPP && r.passes_in_film == NPASSES,
          "paths %llu, spp %d", (unsigned long long)r.total.paths, r.spp_done);
    CHECK(!r.failed[0] && !r.failed[1] && !r.failed[2] && !r.interrupted, "no failure flagged");
    /* a device that asks for a pass before it has a time estimate gets one
     * (the first passes wait for each other, so every device has asked), and
     * the result reports what each one rendered */
    for (int i = 0; i < 3; i++) {
        uint64_t paths = 0;
        for (int j = 0; j < f[i].ndone; j++) {
            int left = SPP - f[i].done_first[j];
            paths += (uint64_t)NPIX * (uint64_t)(left < SPP_PER_PASS ? left : SPP_PER_PASS);
        }
        CHECK(f[i].ndone > 0 && r.passes_by_backend[i] == f[i].ndone &&
                  r.per_backend[i].paths == paths,
              "device %d rendered %d passes (%llu paths), reported %d (%llu)", i, f[i].ndone,
              (unsigned long long)paths, r.passes_by_backend[i],
              (unsigned long long)r.per_backend[i].paths);
    }
    spm_film_free(&film);

    /* device 1 fails on its second pass: device 0 renders it (their first
     * passes meet and device 0 is the slower, so that it cannot take every
     * pass before device 1's thread runs again on a loaded machine) */
    make(&b[0], &f[0], 3000, -1);
    make(&b[1], &f[1], 1000, 1);
    met = 0;
    f[0].meet = f[1].meet = 2;
    rc = run(b, 2, NULL, 0, &film, &r, &err);
    CHECK(rc == 0, "one device failing: %s", err.msg);
    CHECK(same_film(ref, &film), "one device failing: film differs from one device's");
    CHECK(r.failed[1] && !r.failed[0], "failed flags %d %d", r.failed[0], r.failed[1]);
    CHECK(r.passes_by_backend[1] == 1 && r.passes_by_backend[0] == NPASSES - 1,
          "passes %d + %d", r.passes_by_backend[0], r.passes_by_backend[1]);
    spm_film_free(&film);

    /* a device failing on its very first pass */
    make(&b[0], &f[0], 0, 0);
    make(&b[1], &f[1], 0, -1);
    rc = run(b, 2, NULL, 0, &film, &r, &err);
    CHECK(rc == 0 && same_film(ref, &film) && r.passes_by_backend[1] == NPASSES,
          "first device failing at once: rc %d, passes %d", rc, r.passes_by_backend[1]);
    spm_film_free(&film);
}

/* Every device fails: an error, and the film holds every finished pass (also
 * those after a pass that was never rendered), in pass order. */
static void all_fail(void)
{
    spm_backend b[2];
    fake f[2];
    spm_film film, want;
    spm_run_result r;
    spm_error err;
    make(&b[0], &f[0], 500, 4);
    make(&b[1], &f[1], 100, 3);
    int rc = run(b, 2, NULL, 0, &film, &r, &err);
    CHECK(rc == 1, "all devices failed, rc %d", rc);
    CHECK(strstr(err.msg, "every device failed") != NULL, "message '%s'", err.msg);
    CHECK(r.failed[0] && r.failed[1], "failed flags %d %d", r.failed[0], r.failed[1]);
    int marked[SPP] = {0}, spp = 0;
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < f[k].ndone; i++) {
            marked[f[k].done_first[i]] = 1;
            spp += SPP - f[k].done_first[i] < SPP_PER_PASS ? SPP - f[k].done_first[i] : SPP_PER_PASS;
        }
    CHECK(r.passes_in_film == f[0].ndone + f[1].ndone && r.passes_in_film == 7,
          "%d passes in the film, %d + %d finished", r.passes_in_film, f[0].ndone, f[1].ndone);
    CHECK(r.spp_done == spp && film.samples == spp, "spp %d, film %lld, finished %d", r.spp_done,
          film.samples, spp);
    film_of(marked, &want);
    CHECK(same_film(&want, &film), "film is not the finished passes in order");
    spm_film_free(&film);
    spm_film_free(&want);
}

/* A stop inside a pass: the pass ends at its next batch boundary and is
 * dropped; the device is not taken for failed; the film is the passes done. */
static void stopped_in_pass(void)
{
    for (int nb = 1; nb <= 2; nb++) {
        spm_backend b[2];
        fake f[2];
        spm_film film, want;
        spm_run_result r;
        spm_error err;
        volatile sig_atomic_t stop = 0;
        for (int i = 0; i < nb; i++) {
            make(&b[i], &f[i], i ? 3000 : 1000, -1);
            f[i].batches = 4;
            f[i].meet = nb; /* device 0 must get its passes: the others are slower */
        }
        met = 0;
        f[0].stop_after = &stop;
        int rc = run(b, nb, &stop, 0, &film, &r, &err);
        CHECK(rc == 0 && r.interrupted, "%d devices, stop in a pass: rc %d interrupted %d (%s)", nb,
              rc, r.interrupted, rc ? err.msg : "");
        CHECK(!r.failed[0] && !r.failed[1], "a stopped pass taken for a failure");
        CHECK(f[0].passes == 3, "device 0 was handed %d passes (2 done, 1 stopped)", f[0].passes);
        CHECK(f[0].batch_calls > 0, "the render loop did not follow the batches");
        CHECK(!b[0].ctl.batch_done && !b[0].ctl.ctx, "the backend keeps the loop's callback");
        int marked[SPP] = {0}, done = 0;
        for (int k = 0; k < nb; k++)
            for (int i = 0; i < f[k].ndone; i++, done++)
                marked[f[k].done_first[i]] = 1;
        /* never the last, shorter pass here */
        CHECK(r.passes_in_film == done && r.spp_done == done * SPP_PER_PASS,
              "%d passes, %d spp in the film; %d passes done", r.passes_in_film, r.spp_done, done);
        film_of(marked, &want);
        CHECK(same_film(&want, &film), "film is not the passes done");
        spm_film_free(&film);
        spm_film_free(&want);
    }
}

/* Stopping with passes that have no batch boundary: passes in flight finish,
 * no more are handed out, no error. */
static void stopped(void)
{
    spm_backend b[2];
    fake f[2];
    spm_film film, want;
    spm_run_result r;
    spm_error err;
    volatile sig_atomic_t stop = 0;
    make(&b[0], &f[0], 1000, -1);
    make(&b[1], &f[1], 3000, -1);
    met = 0;
    f[0].meet = f[1].meet = 2; /* device 0 must get its passes: device 1 is slower */
    f[0].stop_after = &stop;
    int rc = run(b, 2, &stop, 0, &film, &r, &err);
    CHECK(rc == 0 && r.interrupted, "stop: rc %d interrupted %d", rc, r.interrupted);
    CHECK(r.passes_in_film >= 2 && r.passes_in_film < NPASSES, "%d passes", r.passes_in_film);
    int marked[SPP] = {0};
    for (int p = 0; p < r.passes_in_film; p++)
        marked[p * SPP_PER_PASS] = 1; /* a prefix: nothing failed */
    film_of(marked, &want);
    CHECK(same_film(&want, &film), "stopped film is not the first passes");
    spm_film_free(&film);
    spm_film_free(&want);
}

/* A slow first pass on one device: with a window of 2 passes per device the
 * other finishes at most 4 passes meanwhile (without one, all 12 others). */
static void window(const spm_film *ref)
{
    spm_backend b[2];
    fake f[2];
    spm_film film;
    spm_run_result r;
    spm_error err;
    make(&b[0], &f[0], 0, -1);
    make(&b[1], &f[1], 0, -1);
    f[0].first_delay_us = 300000;
    fast_while_slow = 0;
    int rc = run(b, 2, NULL, 1, &film, &r, &err);
    CHECK(rc == 0 && same_film(ref, &film), "window: rc %d", rc);
    CHECK(fast_while_slow <= 4, "%d passes finished while one was in flight (window 4)",
          fast_while_slow);
    spm_film_free(&film);
}

/* The end game's decision (render_run.h): t_me * sum(1/t_other) <= work. */
static void end_game(void)
{
    double fast = 0.002, slow = 0.010, unknown = 0.0, two[2] = {0.004, 0.004};
    CHECK(spm_run_worth_taking(0.0, &fast, 1, 1), "no estimate yet: takes");
    CHECK(spm_run_worth_taking(fast, &slow, 1, 0), "the fastest takes the last pass");
    CHECK(spm_run_worth_taking(slow, &fast, 1, 5), "slow device, 5 passes ahead of the fast one: takes");
    CHECK(!spm_run_worth_taking(slow, &fast, 1, 4.5), "slow device, 4.5 passes ahead: leaves them");
    CHECK(spm_run_worth_taking(slow, &unknown, 1, 0), "other speed unknown: takes");
    CHECK(spm_run_worth_taking(0.004, two, 2, 0), "equal speeds: takes (a tie)");
    CHECK(spm_run_worth_taking(0.0041, &two[0], 1, 1.5),
          "a hair slower than the other, which is mid-pass: takes the last one");
    CHECK(!spm_run_worth_taking(0.008, two, 2, 3.5), "half the speed of two others, 3.5 ahead: leaves");
    CHECK(spm_run_worth_taking(0.008, two, 2, 4), "half the speed of two others, 4 ahead: takes");
}

static void arguments(void)
{
    /* passes depend only on the image size (and spp, as a cap) */
    CHECK(spm_spp_per_pass(65536, 100) == 1, "65536 px: %u", spm_spp_per_pass(65536, 100));
    CHECK(spm_spp_per_pass(4096, 100) == 16, "4096 px: %u", spm_spp_per_pass(4096, 100));
    CHECK(spm_spp_per_pass(4096, 5) == 5, "4096 px, 5 spp: %u", spm_spp_per_pass(4096, 5));
    CHECK(spm_spp_per_pass(1 << 22, 4) == 1, "4M px: %u", spm_spp_per_pass(1 << 22, 4));
    CHECK(spm_spp_per_pass(100, 0) == 1, "0 spp: %u", spm_spp_per_pass(100, 0));
    spm_backend b;
    fake f;
    spm_film film;
    spm_run_result r;
    spm_error err;
    make(&b, &f, 0, -1);
    spm_backend *bp = &b;
    spm_run_opts o = {.spp = SPP, .spp_per_pass = 0, .stop = NULL, .progress = 0};
    spm_film_init(&film, W, H, &err);
    CHECK(spm_render_run(&bp, 1, NPIX, &o, &film, &r, &err) == 1, "0 spp per pass accepted");
    o.spp_per_pass = 1;
    CHECK(spm_render_run(&bp, 0, NPIX, &o, &film, &r, &err) == 1, "0 devices accepted");
    CHECK(film.samples == 0, "film touched by a refused render");
    spm_film_free(&film);
}

int main(void)
{
    alarm(60); /* a scheduling deadlock fails the test instead of hanging it */
    spm_backend b;
    fake f;
    spm_film ref;
    spm_run_result r;
    spm_error err;
    make(&b, &f, 0, -1);
    CHECK(run(&b, 1, NULL, 0, &ref, &r, &err) == 0, "one device: %s", err.msg);
    int all[SPP];
    for (int i = 0; i < SPP; i++)
        all[i] = 1;
    spm_film direct;
    film_of(all, &direct);
    CHECK(same_film(&direct, &ref), "one device film is not the passes in order");
    spm_film_free(&direct);
    splits(&ref);
    all_fail();
    stopped();
    stopped_in_pass();
    window(&ref);
    end_game();
    arguments();
    spm_film_free(&ref);
    TEST_END();
}

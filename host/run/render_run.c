#include "render_run.h"
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define SPM_WAITING_BYTES_DEFAULT ((size_t)256 << 20)

spm_u32 spm_spp_per_pass(size_t npix, int spp)
{
    if (spp < 1)
        return 1;
    size_t want = (65536 + npix - 1) / (npix ? npix : 1);
    if (want < 1)
        want = 1;
    if (want > (size_t)spp)
        want = (size_t)spp;
    return (spm_u32)want;
}

typedef struct {
    /* shared state, guarded by mu */
    pthread_mutex_t mu;
    pthread_cond_t changed;         /* a pass finished or was given back */
    int in_flight;                  /* passes being rendered now */
    int next_pass, next_to_add;
    int *retry, nretry;             /* passes a failed device left behind */
    float **done;                   /* finished pass images waiting for their turn */
    int alive;                      /* backends that have not failed */
    double started[SPM_MAX_BACKENDS]; /* when each one's pass in flight began; 0: idle */
    uint64_t live_paths[SPM_MAX_BACKENDS]; /* paths done so far of each one's pass in flight */
    int met;                        /* backends that have taken their first pass (test hook) */
    /* fixed */
    int npasses, window, nb;
    int meet;                       /* SPECMIP_TEST_MEET (render_run.h); 0: off */
    spm_backend **b;
    size_t npix;
    const spm_run_opts *o;
    spm_film *film;
    spm_run_result *r;
    double t0;
    int first_grid;                 /* the grid pass the first one is in (start / spp_per_pass) */
    double deadline;                /* spm_now() at which the time budget ends; 0: none */
    double next_checkpoint;         /* spm_now() of the next checkpoint; 0: none */
    int checkpoint_passes;          /* passes in the film at the last checkpoint */
    int workers;                    /* worker threads still running */
    volatile sig_atomic_t halt;     /* the backends' stop: a signal, or the budget spent */
} run_state;

typedef struct {
    run_state *s;
    int idx;
} worker_arg;

enum { TAKE_NONE = -1, TAKE_WAIT = -2 };

static double cpu_now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int spm_run_worth_taking(double t_me, const double *t_other, int n, double work)
{
    if (t_me <= 0)
        return 1;
    double rate = 0.0; /* the others' passes per second */
    int fastest = 1;
    for (int i = 0; i < n; i++)
        if (t_other[i] > 0) {
            rate += 1.0 / t_other[i];
            fastest &= t_other[i] >= t_me; /* a tie: both may take */
        }
    return fastest || t_me * rate <= work;
}

/* Caller holds mu. Seconds per pass of backend i so far; 0: not known. */
static double pass_time(const run_state *s, int i)
{
    int n = s->r->passes_by_backend[i];
    return n > 0 ? s->r->busy_s[i] / n : 0.0;
}

/* Caller holds mu. spm_run_worth_taking for backend idx against the others
 * still working. */
static int worth_taking(const run_state *s, int idx)
{
    double other[SPM_MAX_BACKENDS], now = spm_now();
    double work = s->npasses - s->next_pass + s->nretry;
    int n = 0;
    for (int i = 0; i < s->nb; i++) {
        if (i == idx || s->r->failed[i])
            continue;
        double t = pass_time(s, i);
        other[n++] = t;
        if (t > 0 && s->started[i] > 0) { /* the part of its pass still to do */
            double rest = 1.0 - (now - s->started[i]) / t;
            work += rest > 0 ? rest : 0;
        }
    }
    return spm_run_worth_taking(pass_time(s, idx), other, n, work);
}

/* Pass p's samples: the grid's passes [k P, (k + 1) P) (P = spp_per_pass),
 * the first starting where the film left off and the last ending at spp. */
static int pass_first(const run_state *s, int pass)
{
    return pass ? (s->first_grid + pass) * (int)s->o->spp_per_pass : s->o->start;
}

static spm_u32 pass_spp(const run_state *s, int pass)
{
    int end = (s->first_grid + pass + 1) * (int)s->o->spp_per_pass;
    return (spm_u32)((end < s->o->spp ? end : s->o->spp) - pass_first(s, pass));
}

/* Caller holds mu. The budget is spent: no pass is begun, and those in flight
 * stop, once the film holds a pass (a first pass always ends). */
static int budget_spent(const run_state *s, double now)
{
    return s->deadline > 0 && now >= s->deadline && s->film->samples > 0;
}

/* Caller holds mu. A pass of backend idx begun now would end after the
 * budget (by its own passes' mean time; its first pass is its calibration). */
static int past_budget(const run_state *s, int idx)
{
    if (s->deadline <= 0)
        return 0;
    double now = spm_now();
    return budget_spent(s, now) || (pass_time(s, idx) > 0 && now + pass_time(s, idx) > s->deadline);
}

/* Caller holds mu. The next pass to render, TAKE_WAIT when one may come
 * later, or TAKE_NONE. A pass given back by a failed device goes first: it
 * holds up the film. */
static int take_pass(run_state *s, int idx)
{
    if ((s->o->stop && *s->o->stop) || s->halt || past_budget(s, idx))
        return TAKE_NONE;
    if ((s->nretry > 0 || s->next_pass < s->npasses) && !worth_taking(s, idx))
        return TAKE_WAIT; /* a faster device is due to finish it sooner */
    if (s->nretry > 0)
        return s->retry[--s->nretry];
    if (s->next_pass < s->npasses)
        return s->next_pass - s->next_to_add < s->window ? s->next_pass++ : TAKE_WAIT;
    /* all handed out, but a pass in flight may yet fail and come back */
    return s->in_flight > 0 ? TAKE_WAIT : TAKE_NONE;
}

/* Caller holds mu. Passes in the film, and the share of all paths done,
 * counting the batches of passes in flight. */
static void progress_line(run_state *s)
{
    double dt = spm_now() - s->t0;
    double paths = (double)s->r->total.paths;
    for (int i = 0; i < s->nb; i++)
        paths += (double)s->live_paths[i];
    double all = (double)s->npix * (s->o->spp - s->o->start);
    double done = paths < all ? paths / all : 1.0;
    if (s->deadline > 0 && dt / s->o->time_s > done) /* the budget ends it first */
        done = dt / s->o->time_s < 1.0 ? dt / s->o->time_s : 1.0;
    int left = s->npasses - s->next_to_add;
    double eta = done > 0 ? dt / done * (1.0 - done) : 0.0;
    fprintf(stderr, "\rspecmip: pass %d/%d  %3.0f%%  %.2f Mpaths/s  ETA %.0f s   ", s->next_to_add,
            s->npasses, 100.0 * done, dt > 0 ? paths / dt * 1e-6 : 0.0, eta);
    if (left == 0)
        fputc('\n', stderr);
}

/* A batch of backend a->idx's pass is done (spm_pass_ctl.batch_done). */
static void batch_done(void *ctx, uint64_t paths)
{
    worker_arg *a = ctx;
    run_state *s = a->s;
    pthread_mutex_lock(&s->mu);
    s->live_paths[a->idx] = paths;
    if ((s->o->stop && *s->o->stop) || budget_spent(s, spm_now()))
        s->halt = 1;
    if (s->o->progress && !(s->o->stop && *s->o->stop)) /* stopping: no line after the notice */
        progress_line(s);
    pthread_mutex_unlock(&s->mu);
}

/* Caller holds mu (or is alone). */
static void add_to_film(run_state *s, int p)
{
    spm_film_add_pass(s->film, s->done[p], (int)pass_spp(s, p));
    s->r->spp_done += (int)pass_spp(s, p);
    s->r->passes_in_film++;
    free(s->done[p]);
    s->done[p] = NULL;
}

/* Caller holds mu: add every finished pass that is next in order. */
static void flush_in_order(run_state *s)
{
    while (s->next_to_add < s->npasses && s->done[s->next_to_add]) {
        add_to_film(s, s->next_to_add++);
        if (s->o->progress)
            progress_line(s);
    }
}

/* Caller holds mu. The device is lost for this render: its pass goes back. */
static void device_failed(run_state *s, int idx, int pass, const spm_error *err)
{
    s->alive--;
    fprintf(stderr, "%sspecmip: device '%s' failed on pass %d: %s; %s\n",
            s->o->progress ? "\n" : "", s->b[idx]->name, pass, err->msg,
            s->alive ? "the other devices take over its work" : "no device is left");
    s->retry[s->nretry++] = pass;
    s->r->failed[idx] = 1;
}

/* Caller holds mu. The test hook's meeting: a backend that has just taken its
 * first pass waits (at most 30 s) until s->meet backends have taken theirs. */
static void meet_at_first_pass(run_state *s)
{
    s->met++;
    pthread_cond_broadcast(&s->changed);
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    until.tv_sec += 30;
    while (s->met < s->meet && pthread_cond_timedwait(&s->changed, &s->mu, &until) == 0)
        ;
}

static void *worker(void *argp)
{
    worker_arg *a = argp;
    run_state *s = a->s;
    spm_backend *b = s->b[a->idx];
    for (int first = 1;; first = 0) {
        pthread_mutex_lock(&s->mu);
        int pass;
        while ((pass = take_pass(s, a->idx)) == TAKE_WAIT)
            pthread_cond_wait(&s->changed, &s->mu);
        if (pass >= 0) {
            s->in_flight++;
            s->started[a->idx] = spm_now();
            if (first && s->meet)
                meet_at_first_pass(s);
        }
        pthread_mutex_unlock(&s->mu);
        if (pass < 0)
            break;
        float *img = spm_xcalloc(s->npix * (3 + (size_t)s->film->nspec), sizeof(float));
        spm_pass_stats st;
        memset(&st, 0, sizeof st);
        spm_error err;
        err.msg[0] = 0;
        b->ctl = (spm_pass_ctl){&s->halt, batch_done, a};
        double t0 = spm_now();
        int rc = b->pass(b, (spm_u32)pass_first(s, pass), pass_spp(s, pass), img, &st, &err);
        double busy = spm_now() - t0;
        pthread_mutex_lock(&s->mu);
        s->in_flight--;
        s->started[a->idx] = 0;
        s->live_paths[a->idx] = 0;
        if (rc == SPM_PASS_STOPPED) { /* interrupted: the part done is dropped */
            free(img);
        } else if (rc) {
            s->r->busy_s[a->idx] += busy;
            device_failed(s, a->idx, pass, &err);
            free(img);
        } else {
            s->r->busy_s[a->idx] += busy;
            spm_pass_stats_add(&s->r->total, &st);
            spm_pass_stats_add(&s->r->per_backend[a->idx], &st);
            s->r->passes_by_backend[a->idx]++;
            s->done[pass] = img;
            flush_in_order(s);
        }
        pthread_cond_broadcast(&s->changed);
        pthread_mutex_unlock(&s->mu);
        if (rc)
            break;
    }
    memset(&b->ctl, 0, sizeof b->ctl); /* a points into this render's state */
    pthread_mutex_lock(&s->mu);
    s->workers--;
    pthread_cond_broadcast(&s->changed);
    pthread_mutex_unlock(&s->mu);
    return NULL;
}

/* Caller holds mu: a copy of the film and of the result so far for the
 * checkpoint, written without the lock while the passes go on. */
static void checkpoint(run_state *s)
{
    spm_film copy;
    spm_film_copy(&copy, s->film);
    spm_run_result r = *s->r;
    r.wall_s = spm_now() - s->t0;
    s->checkpoint_passes = s->r->passes_in_film;
    pthread_mutex_unlock(&s->mu);
    s->o->checkpoint(s->o->checkpoint_ctx, &copy, &r);
    spm_film_free(&copy);
    pthread_mutex_lock(&s->mu);
}

/* The thread that started the workers, while they run: turns a signal or the
 * spent budget into the backends' stop, and writes the checkpoints. */
static void watch(run_state *s)
{
    pthread_mutex_lock(&s->mu);
    while (s->workers > 0) {
        struct timespec until;
        clock_gettime(CLOCK_REALTIME, &until);
        until.tv_nsec += 20000000; /* 20 ms: a signal or the deadline is seen soon */
        if (until.tv_nsec >= 1000000000) {
            until.tv_sec++;
            until.tv_nsec -= 1000000000;
        }
        pthread_cond_timedwait(&s->changed, &s->mu, &until);
        double now = spm_now();
        if ((s->o->stop && *s->o->stop) || budget_spent(s, now)) {
            if (!s->halt) /* workers waiting for a pass see there is none */
                pthread_cond_broadcast(&s->changed);
            s->halt = 1;
        }
        if (s->next_checkpoint > 0 && now >= s->next_checkpoint && !s->halt &&
            s->r->passes_in_film > s->checkpoint_passes) {
            checkpoint(s);
            s->next_checkpoint = spm_now() + s->o->checkpoint_s;
        }
    }
    pthread_mutex_unlock(&s->mu);
}

/* One thread per backend, watched by the caller's (watch); a thread that
 * cannot be started leaves its backend out, and with no thread at all the
 * caller's thread does the work (a signal and the budget are then seen by
 * batch_done and between passes, and no checkpoint is written). */
static void run_workers(run_state *s, int nb)
{
    pthread_t th[SPM_MAX_BACKENDS];
    worker_arg args[SPM_MAX_BACKENDS];
    int started[SPM_MAX_BACKENDS], nstarted = 0;
    s->workers = nb;
    for (int i = 0; i < nb; i++) {
        args[i] = (worker_arg){s, i};
        started[i] = pthread_create(&th[i], NULL, worker, &args[i]) == 0;
        nstarted += started[i];
        if (!started[i]) {
            pthread_mutex_lock(&s->mu);
            s->workers--;
            if (nb > 1)
                spm_warnf("no thread for device '%s': it is left out", s->b[i]->name);
            s->r->failed[i] = 1;
            s->alive--;
            pthread_mutex_unlock(&s->mu);
        }
    }
    if (!nstarted) {
        s->r->failed[0] = 0;
        s->alive = 1;
        s->workers = 1;
        worker(&args[0]);
    } else {
        watch(s);
    }
    for (int i = 0; i < nb; i++)
        if (started[i])
            pthread_join(th[i], NULL);
}

int spm_render_run(spm_backend **b, int nb, size_t npix, const spm_run_opts *o, spm_film *film,
                   spm_run_result *r, spm_error *err)
{
    return spm_render_run_window(b, nb, npix, o, SPM_WAITING_BYTES_DEFAULT, film, r, err);
}

int spm_render_run_window(spm_backend **b, int nb, size_t npix, const spm_run_opts *o,
                          size_t max_waiting_bytes, spm_film *film, spm_run_result *r,
                          spm_error *err)
{
    memset(r, 0, sizeof *r);
    if (nb < 1 || nb > SPM_MAX_BACKENDS || o->spp < 1 || o->spp_per_pass < 1 || npix < 1 ||
        o->start < 0 || o->start >= o->spp || film->samples != o->start) {
        spm_errorf(err, "render: %d devices (1 to %d), %d spp from %d (the film: %lld), %u spp "
                   "per pass, %zu pixels", nb, SPM_MAX_BACKENDS, o->spp, o->start,
                   film->samples, o->spp_per_pass, npix);
        return 1;
    }
    run_state s;
    memset(&s, 0, sizeof s);
    pthread_mutex_init(&s.mu, NULL);
    pthread_cond_init(&s.changed, NULL);
    s.first_grid = o->start / (int)o->spp_per_pass;
    s.npasses = (o->spp + (int)o->spp_per_pass - 1) / (int)o->spp_per_pass - s.first_grid;
    /* the window of passes handed out ahead of the film (render_run.h) */
    size_t fit = max_waiting_bytes / (npix * (3 + (size_t)film->nspec) * sizeof(float));
    s.window = fit > (size_t)(2 * nb) ? (fit < (size_t)s.npasses ? (int)fit : s.npasses) : 2 * nb;
    s.retry = spm_xcalloc((size_t)s.npasses, sizeof *s.retry);
    s.done = spm_xcalloc((size_t)s.npasses, sizeof *s.done);
    s.alive = nb;
    s.nb = nb;
    const char *meet = getenv("SPECMIP_TEST_MEET");
    s.meet = meet && nb > 1 ? atoi(meet) : 0;
    s.b = b;
    s.npix = npix;
    s.o = o;
    s.film = film;
    s.r = r;
    s.t0 = spm_now();
    s.deadline = o->time_s > 0 ? s.t0 + o->time_s : 0;
    s.next_checkpoint = o->checkpoint && o->checkpoint_s > 0 ? s.t0 + o->checkpoint_s : 0;
    double cpu0 = cpu_now();
    r->npasses = s.npasses;
    r->spp_done = o->start;
    run_workers(&s, nb);
    r->wall_s = spm_now() - s.t0;
    r->cpu_s = cpu_now() - cpu0;
    /* Cut short (every device failed, or stopped with a pass given back):
     * the passes finished beyond the gap still go in, in pass order; or are
     * dropped when the film must stay a run of whole passes (o->contiguous). */
    for (int p = s.next_to_add; p < s.npasses; p++)
        if (s.done[p] && o->contiguous) {
            r->passes_dropped++;
            free(s.done[p]);
        } else if (s.done[p]) {
            add_to_film(&s, p);
        }
    int complete = r->passes_in_film == s.npasses;
    if (o->progress && !complete)
        fputc('\n', stderr);
    r->interrupted = !complete && o->stop && *o->stop;
    r->time_up = !complete && !r->interrupted && s.deadline > 0 && s.alive > 0;
    free(s.done);
    free(s.retry);
    pthread_mutex_destroy(&s.mu);
    pthread_cond_destroy(&s.changed);
    if (!complete && !r->interrupted && !r->time_up) {
        spm_errorf(err, "every device failed; %d of %d passes rendered (%d of %d samples per pixel)",
                   r->passes_in_film, s.npasses, r->spp_done, o->spp);
        return 1;
    }
    return 0;
}

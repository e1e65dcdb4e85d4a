#include "interrupt.h"
#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

volatile sig_atomic_t spm_stop_flag;
static volatile sig_atomic_t signals_seen;

/* A slot is free (0), being filled (1) or armed (2); the handler reads only
 * armed ones, whose name is complete. */
#define TEMP_PATH_MAX 4096
static int temp_state[SPM_TEMP_SLOTS];
static char temp_path[SPM_TEMP_SLOTS][TEMP_PATH_MAX];

int spm_temp_register(const char *path)
{
    if (strlen(path) >= TEMP_PATH_MAX)
        return -1;
    for (int i = 0; i < SPM_TEMP_SLOTS; i++) {
        int expect = 0;
        if (__atomic_compare_exchange_n(&temp_state[i], &expect, 1, 0, __ATOMIC_SEQ_CST,
                                        __ATOMIC_SEQ_CST)) {
            strcpy(temp_path[i], path);
            __atomic_store_n(&temp_state[i], 2, __ATOMIC_SEQ_CST);
            return i;
        }
    }
    return -1;
}

void spm_temp_unregister(int slot)
{
    if (slot >= 0 && slot < SPM_TEMP_SLOTS)
        __atomic_store_n(&temp_state[slot], 0, __ATOMIC_SEQ_CST);
}

static void say(const char *s)
{
    ssize_t r = write(2, s, strlen(s));
    (void)r;
}

/* Only async-signal-safe calls: write, unlink, _exit. */
static void on_signal(int sig)
{
    (void)sig;
    if (spm_stop_flag) {
        for (int i = 0; i < SPM_TEMP_SLOTS; i++)
            if (__atomic_load_n(&temp_state[i], __ATOMIC_SEQ_CST) == 2)
                unlink(temp_path[i]);
        say("\nspecmip: interrupted again: exiting at once, nothing more written\n");
        _exit(130);
    }
    spm_stop_flag = 1;
    signals_seen++;
    say("\nspecmip: interrupted: stopping (interrupt again to exit at once without writing)\n");
}

/* The test hook's stages, from SPECMIP_TEST_PAUSE. */
#define MAX_PAUSES 8
static struct {
    char stage[16];
    long at, hits;
} pauses[MAX_PAUSES];
static int npauses;
int spm_test_pause_armed;
static pthread_mutex_t pause_mu = PTHREAD_MUTEX_INITIALIZER;

static void arm_test_pauses(void)
{
    const char *env = getenv("SPECMIP_TEST_PAUSE");
    npauses = 0;
    for (const char *p = env; p && *p && npauses < MAX_PAUSES;) {
        size_t n = strcspn(p, ",");
        char item[64];
        snprintf(item, sizeof item, "%.*s", (int)(n < sizeof item ? n : sizeof item - 1), p);
        char *colon = strchr(item, ':');
        long at = 1;
        if (colon) {
            *colon = 0;
            at = strtol(colon + 1, NULL, 10);
        }
        if (item[0] && at > 0 && strlen(item) < sizeof pauses[0].stage) {
            strcpy(pauses[npauses].stage, item);
            pauses[npauses].at = at;
            pauses[npauses++].hits = 0;
        }
        p += n + (p[n] == ',');
    }
    spm_test_pause_armed = npauses > 0;
}

void spm_test_pause_at(const char *stage)
{
    int hit = 0;
    pthread_mutex_lock(&pause_mu);
    for (int i = 0; i < npauses; i++)
        if (!strcmp(pauses[i].stage, stage) && ++pauses[i].hits == pauses[i].at)
            hit = 1;
    pthread_mutex_unlock(&pause_mu);
    if (!hit)
        return;
    sig_atomic_t seen = signals_seen;
    fprintf(stderr, "specmip: test pause at %s\n", stage);
    fflush(stderr);
    /* a bound, so that a test that never signals does not hang */
    for (int i = 0; i < 6000 && signals_seen == seen; i++)
        nanosleep(&(struct timespec){0, 10000000L}, NULL);
}

void spm_catch_interrupts(void)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = on_signal;
    sa.sa_flags = SA_RESTART; /* reads and writes in progress go on */
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
    arm_test_pauses();
}

void spm_release_interrupts(void)
{
    signal(SIGINT, SIG_DFL);
    signal(SIGTERM, SIG_DFL);
}

#include "bench_report.h"
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include "cl_core.h"
#include "modes.h"
#include "spectrum.h"
#include "util.h"

void spm_bench_write_meta(const char *dir, const char *what, int use_cpu, const int *devices,
                          int ndevices, int argc, char **argv)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s_meta.txt", dir, what);
    FILE *f = fopen(path, "w");
    if (!f)
        return;
    time_t now = time(NULL);
    char date[64];
    strftime(date, sizeof date, "%Y-%m-%d %H:%M UTC", gmtime(&now));
    fprintf(f, "date: %s\ncommand: specmip", date);
    for (int i = 0; i < argc; i++)
        fprintf(f, " %s", argv[i]);
    spm_cl_device d;
    spm_error e;
    static const int device0 = 0;
    if (ndevices == 0) {
        devices = &device0;
        ndevices = 1;
    }
    if (use_cpu)
        fprintf(f, "\ndevice: the CPU reference backend (scalar C)");
    else if (ndevices < 0)
        fprintf(f, "\ndevice: every device (--device all)");
    for (int i = 0; i < ndevices && !use_cpu; i++)
        if (!spm_cl_device_get(devices[i], &d, &e))
            fprintf(f, "\ndevice: %s (%s, %u compute units)", d.name, d.platform_name,
                    d.compute_units);
    double load[3];
    if (getloadavg(load, 3) == 3)
        fprintf(f, "\nload: %.2f %.2f %.2f (1, 5, 15 min)", load[0], load[1], load[2]);
    fprintf(f, "\n");
    fclose(f);
    /* the report's scripts take the modes from here (`specmip modes`) */
    snprintf(path, sizeof path, "%s/modes.tsv", dir);
    if ((f = fopen(path, "w"))) {
        spm_modes_print(f, 0);
        fclose(f);
    }
}

void spm_bench_meta_elapsed(const char *dir, const char *what, double seconds)
{
    char path[4096];
    snprintf(path, sizeof path, "%s/%s_meta.txt", dir, what);
    FILE *f = fopen(path, "a");
    if (!f)
        return;
    fprintf(f, "elapsed: %.0f s\n", seconds);
    fclose(f);
}

int spm_bench_report(const char *dir)
{
    char script[4096];
    spm_data_path("bench/report/bench_report.sh", script, sizeof script);
    fflush(NULL);
    pid_t pid = fork();
    if (pid == 0) {
        execlp("bash", "bash", script, dir, (char *)NULL);
        fprintf(stderr, "specmip bench: cannot run bash: %s\n", strerror(errno));
        _exit(127);
    }
    int status;
    if (pid < 0 || waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status)) {
        fprintf(stderr, "specmip bench: the charts could not be made (%s %s)\n", script, dir);
        return SPM_EXIT_RUNTIME;
    }
    return 0;
}

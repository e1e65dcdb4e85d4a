/* What `specmip bench` leaves next to its CSV: DIR/<what>_meta.txt (date,
 * command, device, load) and the charts and RESULTS.md made from the CSV by
 * bench/report/bench_report.sh (gnuplot). */
#ifndef SPM_BENCH_REPORT_H
#define SPM_BENCH_REPORT_H

/* what: "bench" or "ops"; the devices devices[0, ndevices) (0 of them:
 * device 0, -1: every device). A file that cannot be written is left out
 * quietly: the report then states less, the numbers are unaffected. */
void spm_bench_write_meta(const char *dir, const char *what, int use_cpu, const int *devices,
                          int ndevices, int argc, char **argv);
/* Appends "elapsed: S s" (the study's wall time) to DIR/<what>_meta.txt. */
void spm_bench_meta_elapsed(const char *dir, const char *what, double seconds);
/* Runs bash bench/report/bench_report.sh DIR; 0, or SPM_EXIT_RUNTIME with a message on stderr. */
int spm_bench_report(const char *dir);
#endif

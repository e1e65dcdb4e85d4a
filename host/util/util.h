/* Small shared helpers: error reporting with exit codes, checked allocation. */
#ifndef SPM_UTIL_H
#define SPM_UTIL_H
#include <stddef.h>
#include <stdint.h>
#include <stdarg.h>
#include <stdio.h>
#ifdef __cplusplus
extern "C" {
#endif

/* Exit codes (README: 0 ok, 1 runtime failure, 2 usage/input error, 130 interrupted). */
#define SPM_EXIT_OK 0
#define SPM_EXIT_RUNTIME 1
#define SPM_EXIT_INPUT 2
#define SPM_EXIT_INTERRUPTED 130

/* An error message filled in by a failing function, e.g. "scene.txt:12:5: expected a number".
 * Functions that can fail return 0 on success and non-zero on failure, filling *err. */
typedef struct {
    char msg[1024];
} spm_error;

void spm_errorf(spm_error *err, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
/* Warnings go to stderr prefixed "specmip: warning: "; tests may silence them. */
void spm_warnf(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
extern int spm_quiet_warnings;
/* Notes (what was loaded, to help place a camera) go to stderr prefixed
 * "specmip: "; --quiet silences them, and the progress line, not warnings. */
void spm_notef(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Creates a folder and its missing parents (`mkdir -p`): 0, or -1 with errno
 * set and the path that failed in failed (size bytes) when failed is given. */
int spm_make_dirs(const char *dir, char *failed, size_t size);
extern int spm_quiet_notes;

/* Allocation that aborts the program with a clear message when memory runs out. */
void *spm_xmalloc(size_t n);
void *spm_xcalloc(size_t count, size_t size);
void *spm_xrealloc(void *p, size_t n);
char *spm_xstrdup(const char *s);

/* Opens a file the scene names (the scene, its includes, spectrum files) for
 * reading. A test hook: while spm_input_files_refused names who refuses (e.g.
 * "rank 1"), every such open fails with EACCES and says so on stderr, which
 * proves a process rendered without reading any scene file. */
FILE *spm_fopen_input(const char *path, const char *mode);
extern const char *spm_input_files_refused;

/* FNV-1a, 64 bits: h = (h ^ byte) * 1099511628211 over the n bytes at p, from h
 * (SPM_FNV1A64_BASIS to start), for the host's hash tables and keys. Bit k of
 * the result depends on bits 0..k of every byte, so a power-of-two table of
 * 256 slots or more, masking the low bits, sees every input bit. */
#define SPM_FNV1A64_BASIS 1469598103934665603ull
uint64_t spm_fnv1a64(uint64_t h, const void *p, size_t n);

/* Monotonic wall clock in seconds. */
double spm_now(void);
/* Path of a bundled data file: $SPECMIP_DATA/<rel> if set, else the source tree's. */
const char *spm_data_path(const char *rel, char *buf, size_t bufsize);
#ifdef __cplusplus
}
#endif
#endif

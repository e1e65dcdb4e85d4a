/* The saved film (docs/RENDERING.md "The film file"): the film's per-pixel
 * sums as they are in memory, the samples they hold, the pass grid, and what
 * the render was made from, so that a later render can continue it. One file
 * beside the render's EXR, which names it in its header (specmip:film).
 *
 * Layout: a text header of "key=value" lines from "specmip film 1" to "end",
 * then each layer's values (the header's "layer=NAME TYPE CHANNELS" lines, in
 * their order, pixel-major, rows top to bottom), then the FNV-1a 64 of every
 * byte before it. Values are in the machine's byte order (a film moves between
 * machines of the same order, as the MPI ranks' prepared scene does). */
#ifndef SPM_FILM_FILE_H
#define SPM_FILM_FILE_H
#include "film.h"

/* What a film was rendered from: items a continuing render must match
 * (compared: the scene's fingerprint, mode, size, seed, ...) and items kept
 * for the reader (the scene's path, the backend). */
#define SPM_FILM_ITEMS 16
typedef struct {
    char key[32];
    char value[256];
    int compared;
} spm_film_item;
typedef struct {
    spm_film_item item[SPM_FILM_ITEMS];
    int n;
} spm_film_print;

/* Appends an item (value printf-style; a newline in it becomes '?'). */
void spm_film_print_add(spm_film_print *p, int compared, const char *key, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
/* The compared items of `saved` that `now` differs in, as "KEY SAVED (this
 * render: NOW)" joined by "; " into msg; items in `last` (a key, or NULL) are
 * named only when no other differs (the scene's fingerprint changes with the
 * size and the pretest's options too). Returns how many differ. */
int spm_film_print_diff(const spm_film_print *saved, const spm_film_print *now, const char *last,
                        char *msg, size_t size);
/* The value of an item, or NULL. */
const char *spm_film_print_get(const spm_film_print *p, const char *key);

/* Writes the film, its print and its pass grid (pass_spp) to path, through a
 * temporary file renamed over it once complete and flushed to disk: an error
 * (a full disk) or a second signal leaves the previous file as it was. The
 * test pause "film" (interrupt.h) holds it after the temporary file is made.
 * 0, or 1 with err filled naming the file. */
int spm_film_save(const char *path, const spm_film *f, const spm_film_print *p, int pass_spp,
                  spm_error *err);
/* Reads a film file into f (initialised here; spm_film_free it), its print
 * and pass grid. 0, or 1 with err naming the file and the problem: not a
 * film, truncated, corrupt (checksum), a layer this specmip does not know. */
int spm_film_load(const char *path, spm_film *f, spm_film_print *p, int *pass_spp,
                  spm_error *err);
#endif

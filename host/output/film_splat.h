/* Splats: what a light subpath adds to the pixels it reaches, and their
 * deterministic sum. A chunk's splats are summed in 64-bit fixed point, so a
 * pixel's sum does not depend on the order of the adds (a device adds them
 * with integer atomics in any order; the CPU reference in its own), and the
 * chunk sums are added to the pass image in chunk order. docs/ARCHITECTURE.md
 * "Light subpaths" derives the scale and why no sum overflows. */
#ifndef SPM_FILM_SPLAT_H
#define SPM_FILM_SPLAT_H
#include <stddef.h>
#include <stdint.h>
#include "util.h"

/* Light subpaths a chunk holds: a pass's subpaths [c 2^16, (c + 1) 2^16) are
 * chunk c whatever the device or its batch size, so the pass image does not
 * depend on how a pass is cut. */
#define SPM_SPLAT_CHUNK ((size_t)1 << 16)

/* A list of splats: pixel px[i] gets the ch floats at v[ch i] (XYZ, then
 * the spectral bins). */
typedef struct {
    size_t n, cap;
    int ch;
    uint32_t *px;
    float *v;
} spm_splats;

/* The accumulator of a pass image of npix pixels of ch floats: the fixed
 * point sums of one chunk at a time, zero between chunks. */
typedef struct {
    size_t npix;
    int ch;
    int64_t *acc;
    uint8_t *touched;
} spm_splat_acc;

void spm_splats_init(spm_splats *s, int ch);
void spm_splats_free(spm_splats *s);
/* room for one more splat into pixel px: its ch floats to fill */
float *spm_splats_push(spm_splats *s, uint32_t px);

void spm_splat_acc_init(spm_splat_acc *a, size_t npix, int ch);
void spm_splat_acc_free(spm_splat_acc *a);
/* Adds one chunk's splats s to the pass image pass (npix x ch floats): each
 * pixel's fixed-point sum of its splats, converted once. A splat with a
 * non-finite value is left out and counted in *nonfinite. Returns the
 * scale's exponent used (the fixed-point unit is 2^-shift). */
int spm_splats_add_chunk(spm_splat_acc *a, const spm_splats *s, float *pass, uint64_t *nonfinite);
/* The exponent of the fixed-point unit 2^-shift of a chunk of n splats whose
 * largest binary exponent among finite values is e (frexp's; -1074: none):
 * 62 - e - b with 2^b >= n. A device computes e and n itself and asks here. */
int spm_splat_shift(int e, size_t n);
#endif

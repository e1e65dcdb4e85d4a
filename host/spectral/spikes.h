/* Composite Model spike detection (docs/METHODS.md "Modes", mlc): split a spectrum
 * into a smooth part and a few spikes (centroid wavelength, energy), and merge
 * several lights' spikes into the scene-wide pattern table of spike lanes. */
#ifndef SPM_SPIKES_H
#define SPM_SPIKES_H
#include "spectrum.h"

/* One spike: a delta carrying the energy of its samples (not a height).
 * area = sum over truth bins first..last of (in - smooth) x 1 nm, in the
 * spectrum's units x nm; wl = energy-weighted mean of the bin centres. */
typedef struct {
    double wl;
    double area;
    int first, last;  /* truth bins it was taken from (to fold it back exactly) */
} spm_spike;

/* Two-pass Gaussian detector (defaults in spikes.c, with their reasons).
 * Pass 1 marks a truth bin whose excess over the blurred curve b1 (in - b1)
 * exceeds both rel1 x b1 and abs1 x mean(in); a marked run wider than
 * max_width_nm is a broad band, not a line, and is unmarked. Pass 2 replaces
 * the marked runs by the line between their unmarked neighbours, blurs that
 * again (b2) and adds to a run each neighbouring foothill bin whose excess over
 * b2 exceeds rel2 x b2 and abs2 x mean(in), one bin per side per round, until
 * no run grows or would grow past max_width_nm. A spike carrying less than
 * min_fraction of the spectrum's energy stays in the smooth part. */
typedef struct {
    double sigma1_nm, sigma2_nm;  /* blur standard deviations */
    double rel1, abs1;            /* pass 1 thresholds */
    double rel2, abs2;            /* pass 2 (foothill) thresholds */
    double max_width_nm;
    double min_fraction;
} spm_spike_opts;

void spm_spike_defaults(spm_spike_opts *o);

/* Split `in` into `smooth` (same kind, never negative, smooth = in outside
 * the spikes and min(in, base) inside them, base = the line between the
 * spike's unmarked neighbours) and at most max_spikes spikes (largest area
 * first kept; the rest stay in smooth), sorted by wavelength. Energy is
 * preserved: sum(in) = sum(smooth) + sum of areas, to rounding. `smooth` may
 * alias `in`. opts NULL = defaults. Returns the number of spikes found that did
 * not fit into max_spikes (they are part of smooth). */
int spm_spike_split(const spm_spectrum *in, spm_spectrum *smooth, spm_spike *spikes,
                    int max_spikes, int *nspikes, const spm_spike_opts *opts);

/* One light's part in the scene's pattern table. The caller fills the inputs;
 * spm_spike_pattern_merge fills lane_area and folds spikes left without a lane
 * back into *smooth (restoring `in` exactly over their bins). */
typedef struct {
    const spm_spectrum *in;     /* the spectrum as given */
    spm_spectrum *smooth;       /* its smooth part from spm_spike_split (updated) */
    const spm_spike *spikes;    /* its spikes from spm_spike_split */
    int nspikes;
    double luminance;           /* Y of `in`: a spike's rank is its area / luminance */
    double lane_area[SPM_MAX_SPIKES];  /* out: this light's energy in each lane */
    int spike_lane[SPM_MAX_SPIKES];    /* out: each spike's lane, -1: folded back */
    double norm;                       /* out: what its areas are divided by to rank them */
} spm_spike_light;

/* Build the scene-wide pattern table: spikes of all lights whose centroids lie
 * within merge_nm of a lane's first member share that lane (its wavelength is
 * the mean of the members' centroids weighted by area / luminance); at most
 * max_lanes (<= SPM_MAX_SPIKES) lanes are kept, the ones with the largest
 * sum of area / luminance. lane_wl gets the kept lanes in increasing
 * wavelength. Returns the number of lanes. Every light's energy is preserved:
 * sum(in) = sum(smooth) + sum(lane_area). */
int spm_spike_pattern_merge(spm_spike_light *lights, int nlights, double merge_nm, int max_lanes,
                            double lane_wl[SPM_MAX_SPIKES]);
#endif

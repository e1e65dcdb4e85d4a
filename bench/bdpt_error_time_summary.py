#!/usr/bin/env python3
"""The error and the summary of bench/bdpt_error_time.sh.

--error IMAGE REFERENCE MASK: prints "all,dielectric,rest", the mean absolute
difference from the reference over the pixels and channels of each region,
relative to the reference's mean over that region (the dielectric region: the
mask's pixels above half its brightest, those whose camera ray meets a
dielectric first).

ERROR_CSV ML_TRUTH_CSV COST_CSV NREF REF_PREFIX...: per scene and integrator
the cost of a sample (process CPU seconds of its long renders less those of
its 1-sample renders, over the difference in samples), the errors at the largest count (the mean over its seeds), the
error each would have at the path tracer's time (e sqrt(c / c_path)), and the
reference's own error (from the spread of its NREF seeds' renders,
REF_PREFIX-size-spp-k.exr); then ml against truth in bdpt."""
import csv
import glob
import math
import sys
from collections import defaultdict

import numpy as np


def read(path):
    import OpenImageIO as oiio
    img = oiio.ImageInput.open(path)
    px = np.asarray(img.read_image('float'), dtype=np.float64)[..., :3]
    img.close()
    return px


def regions(mask):
    m = mask.mean(axis=2)
    return m > 0.5 * m.max() if m.max() > 0 else np.zeros(m.shape, bool)


def rel_mae(a, ref, sel):
    if not sel.any():
        return float('nan')
    return float(np.abs(a[sel] - ref[sel]).mean() / max(ref[sel].mean(), 1e-30))


def errors(a, ref, mask):
    sel = regions(mask)
    return [rel_mae(a, ref, np.ones(sel.shape, bool)), rel_mae(a, ref, sel),
            rel_mae(a, ref, ~sel)]


def reference_error(prefix):
    """the reference's own relative MAE: the seeds' renders in two halves, the
    halves' difference over 2 (each half's error is the difference's over
    sqrt 2, the whole reference's the half's over sqrt 2)"""
    files = sorted(glob.glob(prefix + '-*-*-*.exr'))
    if len(files) < 2:
        return [float('nan')] * 3
    imgs = [read(f) for f in files]
    h = len(imgs) // 2
    a, b = sum(imgs[:h]) / h, sum(imgs[h:2 * h]) / h
    mask = read(prefix + '-mask.exr')
    return [e / 2 for e in errors(a, b, mask)] + [len(imgs)]


def costs(cost_csv):
    """(scene, integrator) -> CPU seconds a sample"""
    by = defaultdict(lambda: defaultdict(list))
    for r in csv.DictReader(open(cost_csv)):
        by[(r['scene'], r['integrator'])][int(r['spp'])].append(float(r['cpu_s']))
    out = {}
    for k, v in by.items():
        lo, hi = min(v), max(v)
        out[k] = (np.mean(v[hi]) - np.mean(v[lo])) / (hi - lo)
    return out


def summary(err_csv, ml_csv, cost_csv, refs):
    per = costs(cost_csv)
    rows = list(csv.DictReader(open(err_csv)))
    by = defaultdict(list)
    for r in rows:
        by[(r['scene'], r['integrator'])].append(r)
    # the chart's points: CPU seconds of rendering (spp x cost) and the mean
    # error over the seeds, per scene, integrator and sample count
    with open(err_csv.replace('.csv', '_plot.csv'), 'w') as f:
        f.write('scene,integrator,cpu_render_s,rel_mae,rel_mae_dielectric,rel_mae_rest\n')
        for (sc, i), rs in by.items():
            for n in sorted({int(r['spp']) for r in rs}):
                e = [np.mean([float(r[k]) for r in rs if int(r['spp']) == n])
                     for k in ('rel_mae', 'rel_mae_dielectric', 'rel_mae_rest')]
                f.write('%s,%s,%.4g,%.4g,%.4g,%.4g\n' % (sc, i, n * per[(sc, i)], *e))
    print('| scene | integrator | CPU s an spp | rel. MAE at max spp (dielectric / rest) | '
          'mean dE00 | rel. MAE at path\'s CPU time | path / it at equal time '
          '(dielectric / rest) |')
    print('| --- | --- | --- | --- | --- | --- | --- |')
    for s in dict.fromkeys(r['scene'] for r in rows):
        cost, err = {}, {}
        for i in ('path', 'light', 'bdpt'):
            rs = by[(s, i)]
            spp = sorted({int(r['spp']) for r in rs})
            cost[i] = per[(s, i)]
            top = [r for r in rs if int(r['spp']) == spp[-1]]
            err[i] = [np.mean([float(r[k]) for r in top]) for k in
                      ('rel_mae', 'rel_mae_dielectric', 'rel_mae_rest', 'mean_de00')]
        for i in ('path', 'light', 'bdpt'):
            f = math.sqrt(max(cost[i], 1e-9) / max(cost['path'], 1e-9))
            eq = [e * f for e in err[i][:3]]
            gain = [p / q if q > 0 else float('nan') for p, q in zip(err['path'][:3], eq)]
            print('| %s | %s | %.5f | %.4f (%.4f / %.4f) | %.3f | %.4f | %.2f (%.2f / %.2f) |' % (
                s, i, cost[i], err[i][0], err[i][1], err[i][2], err[i][3], eq[0], *gain))
    print('\n| scene | reference rel. MAE (dielectric / rest), renders |')
    print('| --- | --- |')
    for p in refs:
        e = reference_error(p)
        print('| %s | %.4f (%.4f / %.4f), %d |' % (p.rsplit('/', 1)[-1], *e))
    rows = list(csv.DictReader(open(ml_csv)))
    print('\n| scene | truth CPU s | ml CPU s | ml / truth | ml mean dE00 from truth |')
    print('| --- | --- | --- | --- | --- |')
    for s in dict.fromkeys(r['scene'] for r in rows):
        t = [float(r['cpu_s']) for r in rows if r['scene'] == s and r['mode'] == 'truth']
        m = [float(r['cpu_s']) for r in rows if r['scene'] == s and r['mode'] == 'ml']
        d = [float(r['de00_ml_vs_truth']) for r in rows if r['scene'] == s and r['mode'] == 'ml']
        print('| %s | %.2f | %.2f | %.2f | %.3f |' % (s, min(t), min(m), min(m) / min(t),
                                                     sum(d) / len(d)))


def main():
    if sys.argv[1] == '--error':
        print(','.join('%.6g' % e for e in errors(read(sys.argv[2]), read(sys.argv[3]),
                                                   read(sys.argv[4]))))
    else:
        summary(sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[5:])


if __name__ == '__main__':
    main()

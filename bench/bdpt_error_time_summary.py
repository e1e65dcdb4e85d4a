#!/usr/bin/env python3
"""The summary of bench/bdpt_error_time.sh: per scene and integrator the cost of
a sample (render seconds, the slope between the smallest and largest sample
count), the error at the largest count, and the error each would have at the
path tracer's time there (e sqrt(c / c_path)); then ml against truth in bdpt.
usage: bdpt_error_time_summary.py ERROR_CSV ML_TRUTH_CSV"""
import csv
import math
import sys
from collections import defaultdict


def main():
    rows = list(csv.DictReader(open(sys.argv[1])))
    by = defaultdict(list)
    for r in rows:
        by[(r['scene'], r['integrator'])].append(r)
    scenes = list(dict.fromkeys(r['scene'] for r in rows))
    print('| scene | integrator | render s an spp | rel. MAE at max spp | mean dE00 | '
          'rel. MAE at path\'s time | path / it at equal time |')
    print('| --- | --- | --- | --- | --- | --- | --- |')
    for s in scenes:
        cost, err = {}, {}
        for i in ('path', 'light', 'bdpt'):
            rs = sorted(by[(s, i)], key=lambda r: int(r['spp']))
            lo, hi = rs[0], rs[-1]
            cost[i] = (float(hi['render_s']) - float(lo['render_s'])) / (int(hi['spp']) - int(lo['spp']))
            err[i] = (float(hi['rel_mae']), float(hi['mean_de00']))
        for i in ('path', 'light', 'bdpt'):
            c = max(cost[i], 1e-9)
            eq = err[i][0] * math.sqrt(c / max(cost['path'], 1e-9))
            print('| %s | %s | %.3g | %.4f | %.3f | %.4f | %.2f |' % (
                s, i, cost[i], err[i][0], err[i][1], eq, err['path'][0] / eq))
    rows = list(csv.DictReader(open(sys.argv[2])))
    print('\n| scene | truth render s | ml render s | ml / truth time | ml mean dE00 from truth |')
    print('| --- | --- | --- | --- | --- |')
    for s in dict.fromkeys(r['scene'] for r in rows):
        t = [float(r['render_s']) for r in rows if r['scene'] == s and r['mode'] == 'truth']
        m = [float(r['render_s']) for r in rows if r['scene'] == s and r['mode'] == 'ml']
        d = [float(r['de00_ml_vs_truth']) for r in rows if r['scene'] == s and r['mode'] == 'ml']
        print('| %s | %.2f | %.2f | %.2f | %.3f |' % (s, min(t), min(m), min(m) / min(t),
                                                     sum(d) / len(d)))


if __name__ == '__main__':
    main()

# Charts of specmip bench (driven by bench/report/bench_report.sh, which sets):
#   csv     the bench.csv          out     directory for the PNGs
#   sel     command prefix selecting columns: sel.' -v scene=..." file'
#   scenes  scene names, space-separated     modes   mode names with main rows
#   dat     directory of the tables the report script prepared (bias, levels)
#   nsc     number of scenes
#   sweep   1 if the CSV has threshold-sweep rows     lvmodes  "ml mlc" (those present)
#   equal   1 if the CSV has equal-time rows
term = 'pngcairo font "DejaVu Sans,10" noenhanced'
set datafile missing "NaN"
cols = (nsc <= 1) ? 1 : (nsc <= 4 ? 2 : 3)
rows = (nsc + cols - 1) / cols
set terminal @term size (cols == 1 ? 640 : 420 * cols), (cols == 1 ? 440 : 300 * rows + 40)
q(s) = "'".s."'"
pick(scene, kind, mode, c) = "< ".sel." -v scene=".scene." -v kind=".kind." -v mode=".mode." -v cols=".c." ".q(csv)

# 1. error against time at equal time, log-log, one curve per mode over the
# budgets (the "equal" rows); the floor of two converged truths as a grey dashed
# line across each panel, labelled. Panels fill the width (up to 4 a row); the
# key is one row below them, so no panel is given to it.
if (equal) {
cols1 = nsc <= 3 ? nsc : (nsc == 4 ? 2 : 4)
rows1 = (nsc + cols1 - 1) / cols1
pw = cols1 == 1 ? 640 : 400; ph = cols1 == 1 ? 400 : 290   # pixels: a panel
top = 30                                    # pixels: the title
W = pw * cols1
kcols = W >= 800 ? 6 : 3                    # the key's entries a row (the floor is labelled in place)
keyh = W >= 800 ? 34 : 52                   # pixels: the key's rows
H = top + ph * rows1 + keyh
set terminal @term size W, H
set output out."/time_error.png"
set multiplot title "Error against a converged truth at equal time, each mode's spp set for the time (lower is better)" font ",10"
set logscale xy
set xlabel "wall time per render [s]" offset 0, 0.4
set ylabel "mean dE00 vs converged truth" offset 1, 0
set grid
set autoscale xfix
set autoscale yfix
set xtics (0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100, 200, 500)
set ytics (0.01, 0.02, 0.05, 0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50, 100, 200)
set offsets graph 0.05, graph 0.05, graph 0.15, graph 0.15
unset key
set size pw * 1.0 / W, ph * 1.0 / H
k = 0
do for [s in scenes] {
    set origin (k % cols1) * pw * 1.0 / W, (keyh + (rows1 - 1 - int(k / cols1)) * ph) * 1.0 / H
    set title s offset 0, -0.6
    undefine STATS_*
    stats pick(s, "equal", "", "wall_s,conv_floor_mean") using 2 nooutput
    fl = exists("STATS_max") ? STATS_max : NaN   # no floor in the CSV: none drawn
    unset label 1
    if (fl == fl) { set label 1 "floor: two converged truths apart" at graph 0.03, first fl offset 0, 0.55 font ",8" tc "gray30" }
    plot for [m in modes] pick(s, "equal", m, "wall_s,err_mean") using 1:2 with linespoints, \
         fl with lines dt 2 lw 1.5 lc "gray50"
    k = k + 1
}
unset label 1
set xtics autofreq
set ytics autofreq
# the key: one row below the panels
set origin 0, 0
set size 1, keyh * 1.0 / H
unset title
unset border
unset tics
unset grid
unset xlabel
unset ylabel
unset logscale
unset offsets
set autoscale xy
set xrange [0:1]
set yrange [0:1]
set key center center horizontal maxcols kcols font ",9" samplen 2
plot for [m in modes] NaN with linespoints title m
unset multiplot
set border
set tics
set grid
set autoscale xy
}

# 2. bias: same seed, same paths; what the spectral method alone costs
set terminal @term size 1000,440
set output out."/bias.png"
set multiplot layout 1, 2 title "Bias at the largest spp (same seed and paths), mean dE00"
set style data histograms
set style histogram clustered gap 1
set style fill solid 0.85 border -1
set boxwidth 0.9
set xtics rotate by -30 font ",8"
set key default
set key inside top left font ",8"
unset xlabel
set ylabel "mean dE00 (log scale; 0 not drawn)"
set logscale y
set yrange [0.01:*]
set title "against ref (5 nm)"
plot for [i = 2:words(modes) + 1] dat."/bias_ref.dat" using i:xtic(1) title columnheader(i)
set title "against truth (1 nm)"
plot for [i = 2:words(modes) + 1] dat."/bias_truth.dat" using i:xtic(1) title columnheader(i)
unset multiplot
unset logscale y

# 3. the threshold sweep: time relative to ref (left) and the dE00 it buys (right)
if (sweep) {
set terminal @term size (cols == 1 ? 640 : 420 * cols), (cols == 1 ? 440 : 300 * rows + 40)
set output out."/threshold.png"
set multiplot layout rows, cols title "ml threshold sweep: time / ref time (left) and dE00 vs ref (right)"
set style data linespoints
set xtics norotate font ",9"
set xlabel "pretest threshold dE00"
set ylabel "wall time / ref"
set y2label "dE00 vs ref"
set ytics nomirror
set y2tics
set yrange [0:*]
set y2range [0:*]
set key default
set key inside top center font ",8"
do for [s in scenes] {
    set title s
    plot pick(s, "sweep", "ml", "threshold,time_vs_ref") using 1:2 axes x1y1 title "time / ref", \
         pick(s, "sweep", "ml", "threshold,bias_ref_mean") using 1:2 axes x1y2 title "mean dE00", \
         pick(s, "sweep", "ml", "threshold,bias_ref_max") using 1:2 axes x1y2 title "max dE00"
}
unset multiplot
unset y2tics
unset y2label
set ytics mirror
}

# 4. paths per level (share of all paths) in ml and mlc
if (words(lvmodes) > 0) {
set terminal @term size 500 * words(lvmodes), 440
set output out."/levels.png"
set multiplot layout 1, words(lvmodes) title "Share of paths shaded at each level (largest spp)"
set style data histograms
set style histogram rowstacked
set style fill solid 0.85 border -1
set boxwidth 0.75
set xtics rotate by -30 font ",8"
unset xlabel
set ylabel "share of paths"
set yrange [0:1]
set key default
set key outside right font ",8"
do for [m in lvmodes] {
    set title m
    plot for [i = 2:6] dat."/levels_".m.".dat" using i:xtic(1) title columnheader(i)
}
unset multiplot
}

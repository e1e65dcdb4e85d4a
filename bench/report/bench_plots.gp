# Charts of specmip bench (driven by bench/report/bench_report.sh, which sets):
#   csv     the bench.csv          out     directory for the PNGs
#   sel     command prefix selecting columns: sel.' -v scene=..." file'
#   scenes  scene names, space-separated     modes   mode names with main rows
#   dat     directory of the tables the report script prepared (bias, levels)
#   nsc     number of scenes
#   sweep   1 if the CSV has threshold-sweep rows     lvmodes  "ml mlc" (those present)
term = 'pngcairo font "DejaVu Sans,10" noenhanced'
set datafile missing "NaN"
cols = (nsc <= 1) ? 1 : (nsc <= 4 ? 2 : 3)
rows = (nsc + cols - 1) / cols
set terminal @term size (cols == 1 ? 640 : 420 * cols), (cols == 1 ? 440 : 300 * rows + 40)
q(s) = "'".s."'"
pick(scene, kind, mode, c) = "< ".sel." -v scene=".scene." -v kind=".kind." -v mode=".mode." -v cols=".c." ".q(csv)

# 1. time against error, log-log, one curve per mode over the spp; floors dashed.
# The noise at each spp (same in every row of that spp) is drawn at truth's time if
# truth has rows, else at the first mode's. One more panel holds the key.
nmode = strstrt(" ".modes." ", " truth ") > 0 ? "truth" : word(modes, 1)
np = nsc + 1
cols1 = np <= 4 ? 2 : 3
rows1 = (np + cols1 - 1) / cols1
set terminal @term size 420 * cols1, 300 * rows1 + 40
set output out."/time_error.png"
set multiplot layout rows1, cols1 title "Error against a converged truth (mean dE00) vs wall time per render"
set logscale xy
set xlabel "wall time [s]"
set ylabel "mean dE00 vs converged truth"
set grid
unset key
do for [s in scenes] {
    set title s
    plot for [m in modes] pick(s, "main", m, "wall_s,err_mean") using 1:2 with linespoints, \
         pick(s, "main", nmode, "wall_s,noise_mean") using 1:2 with lines dt 2 lc "gray30", \
         pick(s, "main", "", "wall_s,conv_floor_mean") using 1:2 with lines dt 3 lc "black"
}
unset title
unset border
unset tics
unset grid
unset xlabel
unset ylabel
unset logscale
set xrange [0:1]
set yrange [0:1]
set key center center font ",9"
plot for [m in modes] NaN with linespoints title m, \
     NaN with lines dt 2 lc "gray30" title "noise: 2 truth renders, same spp", \
     NaN with lines dt 3 lc "black" title "floor: 2 converged truths"
unset multiplot
set border
set tics
set grid
set autoscale xy

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

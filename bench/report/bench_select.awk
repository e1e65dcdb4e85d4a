# Rows of specmip bench's bench.csv as whitespace-separated columns, picked by
# header name, so the charts do not depend on column positions.
#   awk -F, -f bench_select.awk -v cols=wall_s,err_mean [-v scene=S] [-v kind=K]
#       [-v mode=M] [-v spp=N] bench.csv
# Empty filters match every row; spp=max keeps each scene's largest spp.
NR == 1 {
    for (i = 1; i <= NF; i++)
        ix[$i] = i
    n = split(cols, want, ",")
    for (i = 1; i <= n; i++)
        if (!(want[i] in ix)) {
            print "bench_select.awk: no column '" want[i] "'" > "/dev/stderr"
            exit 2
        }
    next
}
{
    if (scene != "" && $ix["scene"] != scene) next
    if (kind != "" && $ix["kind"] != kind) next
    if (mode != "" && $ix["mode"] != mode) next
    if (spp != "" && spp != "max" && $ix["spp"] != spp) next
    row[++nrows] = $0
    if ($ix["spp"] + 0 > maxspp[$ix["scene"]]) maxspp[$ix["scene"]] = $ix["spp"] + 0
}
END {
    for (r = 1; r <= nrows; r++) {
        m = split(row[r], f, ",")
        if (spp == "max" && f[ix["spp"]] + 0 != maxspp[f[ix["scene"]]]) continue
        line = ""
        for (i = 1; i <= n; i++)
            line = line (i > 1 ? " " : "") f[ix[want[i]]]
        print line
    }
}

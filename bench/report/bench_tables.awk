# Tables for the bar charts from bench.csv (bench/report/bench_report.sh):
#   what=bias_ref|bias_truth  one row per scene, one column per mode: <what>_mean
#   what=levels mode=M        one row per scene: share of M's paths at levels 0..4
# Values at each scene's largest spp of the main rows.
BEGIN { FS = "," }
NR == 1 { for (i = 1; i <= NF; i++) ix[$i] = i; next }
$ix["kind"] == "main" {
    s = $ix["scene"]; sp = $ix["spp"] + 0
    if (!(s in maxspp)) order[++ns] = s
    if (sp > maxspp[s]) maxspp[s] = sp
    if (!($ix["mode"] in seenmode)) { seenmode[$ix["mode"]] = 1; modes[++nm] = $ix["mode"] }
    rows[++nr] = $0
}
END {
    for (r = 1; r <= nr; r++) {
        split(rows[r], f, ",")
        if (f[ix["spp"]] + 0 != maxspp[f[ix["scene"]]]) continue
        key = f[ix["scene"]] SUBSEP f[ix["mode"]]
        if (what == "levels") {
            tot = f[ix["paths"]] + 0
            for (l = 0; l < 5; l++)
                lv[key, l] = tot > 0 ? f[ix["l" l "_paths"]] / tot : 0
        } else {
            val[key] = f[ix[what "_mean"]]
        }
    }
    if (what == "levels") {
        print "scene \"level 0 (400)\" \"level 1 (80)\" \"level 2 (40)\" \"level 3 (20)\" \"level 4 (10)\""
        for (i = 1; i <= ns; i++)
            if ((order[i], mode, 0) in lv)
                printf "%s %.4f %.4f %.4f %.4f %.4f\n", order[i], lv[order[i], mode, 0],
                       lv[order[i], mode, 1], lv[order[i], mode, 2], lv[order[i], mode, 3],
                       lv[order[i], mode, 4]
        exit
    }
    line = "scene"
    for (j = 1; j <= nm; j++) line = line " " modes[j]
    print line
    for (i = 1; i <= ns; i++) {
        line = order[i]
        for (j = 1; j <= nm; j++) {
            k = order[i] SUBSEP modes[j]
            line = line " " ((k in val) ? val[k] : "NaN")
        }
        print line
    }
}

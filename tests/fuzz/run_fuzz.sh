#!/bin/bash
# Runs one libFuzzer harness until it has used CPU_SECONDS of CPU (the machine
# is shared: one job, rounds of at most the CPU time still owed), seeded with
# the bundled good files and tests/bad-inputs. Findings go to OUT/art_NAME/.
# usage: bash tests/fuzz/run_fuzz.sh BUILD_DIR scene|minilight|csv|mesh|ply|gltf|mitsuba OUT [CPU_SECONDS]
# (BUILD_DIR configured with CC=clang CXX=clang++ -DSPECMIP_FUZZ=ON)
set -u
BUILD=$(cd "${1:?build dir}" && pwd) NAME=${2:?harness} OUT=${3:?output dir} CPU=${4:-600}
ROOT=$(cd "$(dirname "$0")/../.." && pwd)
mkdir -p "$OUT" && OUT=$(cd "$OUT" && pwd)
cd "$OUT"
mkdir -p "seed_$NAME" "corpus_$NAME" "art_$NAME" "dir_$NAME"
dict=() maxlen=8192
case $NAME in
  scene) cp "$ROOT"/scenes/*.scene "$ROOT"/tests/data/scenes/*.scene "$ROOT"/tests/bad-inputs/*.scene "seed_$NAME/"
         # CSV files the seed scenes name, next to the fuzzed input
         cp "$ROOT"/tests/data/scenes/*.csv "$ROOT"/tests/bad-inputs/scene_helper_*.csv "dir_$NAME/"
         dict=(-dict="$ROOT/tests/fuzz/scene.dict") ;;
  minilight) cp "$ROOT"/tests/data/scenes/*.ml.txt "$ROOT"/tests/bad-inputs/*.ml.txt "seed_$NAME/" ;;
  csv) cp "$ROOT"/tests/bad-inputs/*.csv "$ROOT"/tests/data/spectra/*.csv "seed_$NAME/"
       for f in "$ROOT"/spectra/*.csv; do [ "$(stat -c %s "$f")" -lt 16384 ] && cp "$f" "seed_$NAME/"; done
       maxlen=16384 ;;
  mesh) # generated meshes, as bytes (the harness makes its meshes from any bytes)
         python3 "$ROOT/tools/gen_meshes.py" "seed_$NAME" > /dev/null
         maxlen=4096 ;;
  ply) # the generated PLY files, faces and strips, ASCII and binary
       python3 "$ROOT/tools/gen_meshes.py" "dir_$NAME/gen" > /dev/null
       cp "dir_$NAME"/gen/*.ply "seed_$NAME/" && rm -r "dir_$NAME/gen"
       maxlen=8192 ;;
  gltf) # the corpus's models, each behind the byte that picks .gltf, .glb, .obj or .mtl
        i=0
        for f in "$ROOT"/tests/bad-inputs/path_models/*.{gltf,glb,obj,mtl}; do
          case $f in *.gltf) b='\x00' ;; *.glb) b='\x01' ;; *.obj) b='\x02' ;; *) b='\x03' ;; esac
          { printf "$b"; cat "$f"; } > "seed_$NAME/m$((i++))"
        done
        # and models whose images are embedded (bufferViews, data: URIs)
        mkdir -p "dir_$NAME/emb" && python3 "$ROOT/tools/make_textured_gltf.py" "dir_$NAME/emb" &&
          python3 "$ROOT/tools/gltf_embed.py" "dir_$NAME/emb/maps.gltf" "dir_$NAME/emb/maps.glb" &&
          python3 "$ROOT/tools/gltf_embed.py" "dir_$NAME/emb/maps.gltf" "dir_$NAME/emb/data.gltf" &&
          { printf '\x01'; cat "dir_$NAME/emb/maps.glb"; } > "seed_$NAME/embedded_glb" &&
          { printf '\x00'; cat "dir_$NAME/emb/data.gltf"; } > "seed_$NAME/embedded_gltf"
        rm -rf "dir_$NAME/emb"
        maxlen=8192 ;;
  mitsuba) cp "$ROOT"/tests/bad-inputs/mitsuba_*.xml "$ROOT"/tests/data/mitsuba/box/*.xml "seed_$NAME/" ;;
  *) echo "unknown harness $NAME" >&2; exit 2 ;;
esac
used=0 round=0
while [ $used -lt "$CPU" ]; do
  round=$((round + 1))
  SPM_FUZZ_DIR="$OUT/dir_$NAME" SPECMIP_DATA="$ROOT" /usr/bin/time -f "%U %S" -o "time.$NAME" \
    "$BUILD/tests/fuzz/fuzz_$NAME" -max_len=$maxlen -timeout=10 -rss_limit_mb=2048 \
    -max_total_time=$((CPU - used + 10)) "${dict[@]}" -artifact_prefix="art_$NAME/" \
    -print_final_stats=1 "corpus_$NAME" "seed_$NAME" >> "log_$NAME.txt" 2>&1
  rc=$?
  used=$((used + $(tail -n 1 "time.$NAME" | awk '{printf "%d", $1 + $2}')))
  echo "round $round: exit $rc, CPU so far ${used} s" | tee -a "log_$NAME.txt"
  [ $rc -ne 0 ] && [ $round -ge 20 ] && break  # a finding every round: stop, look at art_$NAME
done
grep -E "^stat::number_of_executed_units|cov:" "log_$NAME.txt" | tail -n 2

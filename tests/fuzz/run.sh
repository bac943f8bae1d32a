#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan) in build-fuzz/ and runs
# each for RUNS inputs (default 10000: a smoke run; the documented long run is
# RUNS=1000000), seeded with valid files the tool itself writes.
#   tests/fuzz/run.sh [RUNS] [TARGET...]
# FUZZ_BUILD (default build-fuzz) is the build folder, FUZZ_BUILD_TYPE (default
# RelWithDebInfo) its CMake build type, BRDFSHOT_BIN (default
# build/apps/brdfshot) the tool that writes the seeds. ctest's fuzz_smoke runs
# it with 3000 runs per target on a Debug build (the whole smoke run 2 min
# against 2 min 50 s on 2 cores: docs/fuzzing.md); exit 77 (skipped) without
# clang.
set -euo pipefail
cd "$(dirname "$0")/../.."
RUNS=${1:-10000}; shift || true
TARGETS=${*:-merl probe basis_images observations json times exif raw}
FB=${FUZZ_BUILD:-build-fuzz}; B=${BRDFSHOT_BIN:-build/apps/brdfshot}
command -v clang++ >/dev/null || { echo "clang++ not installed: apt-get install clang"; exit 77; }
[ -x "$B" ] || { echo "build the tool first ($B writes the seeds)"; exit 77; }
CXX=clang++ CC=clang cmake -S . -B "$FB" -DBRDFSHOT_FUZZ=ON -DCMAKE_BUILD_TYPE="${FUZZ_BUILD_TYPE:-RelWithDebInfo}" >/dev/null
cmake --build "$FB" -j"$(nproc)" >/dev/null
S=$FB/seeds; A=samples/assets
if [ ! -d "$S" ]; then
  mkdir -p "$S"/{merl,probe,basis_images,observations,json,times,exif,raw}
  $B synth-db --data $A --grid 4x4x8 --materials demo-gold -o "$S/merl" >/dev/null
  $B synth-capture --probe $A/envmaps/studio_256.exr --standin demo-gold --db standin --data $A --grid 10x10x20 \
    --size 64x48 --radius 12 --probe-shot-width 64 -o "$S/cap" >/dev/null
  cp "$S/cap/photo/IMG_01.jpg" "$S/exif/"; cp "$S/cap/truth/sphere.json" "$S/json/"
  $B merge "$S/cap/probe" --save-response "$S/json/response.json" -o "$S/cap/p.exr" >/dev/null 2>&1
  cp "$S/cap/p.json" "$S/json/merge.json"
  $B calib --probe $A/envmaps/studio_256.exr --width 16 -o "$S/cap/small.exr" >/dev/null
  printf '\000' | cat - "$S/cap/small.exr" > "$S/probe/small.exr.seed"
  $B remap --photo "$S/cap/truth/photo.exr" --sphere "$S/cap/truth/sphere.json" -o "$S/observations/o.bsobs" >/dev/null
  $B basis --db standin --data $A --grid 10x10x20 --materials demo-gold --probe "$S/cap/small.exr" \
    --obs "$S/observations/o.bsobs" -o "$S/basis_images/b.bsbi" >/dev/null
  $B cluster --db standin --data $A --grid 10x10x20 -o "$S/json/classes.json" >/dev/null
  printf '1/60\n1/15\n0.25\n' > "$S/times/t.txt"
  for f in ../shared/real/raw/*; do [ -f "$f" ] && [ "$(stat -c %s "$f")" -lt 20000000 ] && cp "$f" "$S/raw/" && break; done || true
fi
for t in $TARGETS; do
  mkdir -p "$FB/corpus/$t"
  echo "== fuzz_$t: $RUNS runs"
  rc=0
  ASAN_OPTIONS=detect_leaks=0 "$FB/tests/fuzz/fuzz_$t" -runs="$RUNS" -seed=1 -artifact_prefix="$FB/" -max_len=65536 -rss_limit_mb=4096 \
    -print_final_stats=1 "$FB/corpus/$t" "$S/$t" > "$FB/fuzz_$t.log" 2>&1 || rc=$?
  grep -E "^(stat::number_of_executed_units|Done)|ERROR|SUMMARY" "$FB/fuzz_$t.log" || true
  [ "$rc" = 0 ] || { echo "fuzz_$t FAILED (rc $rc): see $FB/fuzz_$t.log"; exit 1; }
done

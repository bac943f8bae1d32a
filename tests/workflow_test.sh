#!/usr/bin/env bash
# samples/Snakefile against samples/Makefile on the same synthetic captures.
#
#   workflow_test.sh BRDFSHOT SOURCE local   # snakemake --cores 2, a bad capture among good ones
#   workflow_test.sh BRDFSHOT SOURCE slurm   # the same workflow through a one-node Slurm
#                                            # (tests/slurm_cluster.sh; exit 77 where it cannot start)
#
# Both runs write to the same output path in turn, so every result file must be
# byte-identical to the Makefile's, but for the wall times that fit.json,
# sphere.json, the merge sidecars, times.tsv and the report record.
# local: the bad capture fails only its own jobs and names itself; once it is
# mended, a re-run runs only its jobs; the sharded evaluation's table is one
# process's. KEEP=1 leaves the temporary folder for a look.
set -u
B=$(realpath "$1"); SRC=$(realpath "$2"); MODE="$3"
T=$(mktemp -d)
cleanup() { [ "$MODE" = slurm ] && bash "$SRC/tests/slurm_cluster.sh" stop "$T/slurm"; rm -rf "$T"; }
[ -n "${KEEP:-}" ] && trap - EXIT || trap cleanup EXIT
fail=0
command -v snakemake >/dev/null || { echo "SKIP: snakemake is not installed (Debian: snakemake)"; exit 77; }
export BRDFSHOT_CACHE="$T/cache"
ASSETS="$SRC/samples/assets"
DB="--db standin --data $ASSETS --grid 30x30x60"
if [ "$MODE" = slurm ]; then MATERIALS="demo-red-plastic demo-clay"; else MATERIALS="demo-red-plastic demo-car-blue demo-clay"; fi
for m in $MATERIALS; do
  "$B" synth-capture --standin "$m" --data "$ASSETS" --probe "$ASSETS/envmaps/studio_256.exr" \
    --size 320x240 --radius 60 --focal-px 450 -o "$T/captures/$m" > "$T/synth.log" 2>&1 ||
    { cat "$T/synth.log"; echo "FAIL synth-capture $m"; exit 1; }
done

# The Makefile's results, capture by capture, moved aside.
for m in $MATERIALS; do
  make --no-print-directory -C "$SRC/samples" BRDFSHOT="$B" OUT="$T/out" DATA="$ASSETS" CAPTURE="$T/captures/$m" \
    DBARGS="$DB" > "$T/make.log" 2>&1 || { cat "$T/make.log"; echo "FAIL make $m"; exit 1; }
done
mv "$T/out" "$T/make"

# Every file of a capture's results equal to the Makefile's; JSON files equal
# once their timings are dropped; times.tsv names the same stages (report.md,
# which quotes the timings, is not compared).
same_results() {
  local m="$1" a="$T/make/results/$1" b="$T/out/results/$1" f n=0
  while read -r f; do
    n=$((n + 1))
    [ -f "$b/$f" ] || { echo "FAIL $m: $f missing"; fail=1; continue; }
    case "$f" in
      times.tsv|report.md) continue ;;
      *.json) python3 - "$a/$f" "$b/$f" <<'EOF' || { echo "FAIL $m: $f differs beyond timings"; fail=1; }
import json, sys
def strip(v):
    if isinstance(v, dict):
        return {k: strip(x) for k, x in v.items() if k not in ("seconds", "timing")}
    return [strip(x) for x in v] if isinstance(v, list) else v
a, b = (strip(json.load(open(p))) for p in sys.argv[1:3])
sys.exit(0 if a == b else 1)
EOF
        ;;
      *) cmp -s "$a/$f" "$b/$f" || { echo "FAIL $m: $f not byte-identical"; fail=1; } ;;
    esac
  done < <(cd "$a" && find . -type f | sed 's|^\./||' | sort)
  [ "$n" -gt 20 ] || { echo "FAIL $m: only $n result files"; fail=1; }
  # (the class model, shared by all captures, is timed in Snakemake's benchmarks/)
  stages() { cut -f2 "$1" | awk '$2 != "cluster" {print $2}' | sort; }
  [ "$(stages "$a/times.tsv")" = "$(stages "$b/times.tsv")" ] ||
    { echo "FAIL $m: times.tsv names other stages"; fail=1; }
}

smk() {
  (cd "$T/work" && snakemake -s "$SRC/samples/Snakefile" "$@" \
    --config captures="$T/captures" out="$T/out" brdfshot="$B" data="$ASSETS" dbargs="$DB")
}
mkdir -p "$T/work"

if [ "$MODE" = slurm ]; then
  bash "$SRC/tests/slurm_cluster.sh" start "$T/slurm" || exit $?
  # shellcheck disable=SC1091
  source "$T/slurm/env"
  # Snakemake's cluster executor looks at its jobs every 10 s, every second
  # where CI=true: the job states are asked for the same way either way.
  CI=true smk --profile "$SRC/samples/slurm" --max-threads 2 > "$T/smk.log" 2>&1 || { tail -50 "$T/smk.log"; echo "FAIL snakemake through Slurm"; exit 1; }
  grep -q "with external jobid" "$T/smk.log" || { echo "FAIL no job went through Slurm"; fail=1; }
  for m in $MATERIALS; do same_results "$m"; done
  jobs=$(grep -c "with external jobid" "$T/smk.log")
  [ "$fail" = 0 ] && echo "workflow through a one-node Slurm: $jobs Slurm jobs, results of $(echo $MATERIALS | wc -w) captures equal to the Makefile's"
  exit $fail
fi

# local: a capture whose photo bracket holds a truncated JPEG, among good ones.
cp -r "$T/captures/demo-clay" "$T/captures/broken"
good_frame="$T/captures/broken/photo/IMG_03.jpg"
cp "$good_frame" "$T/good_frame.jpg"
head -c 3000 "$T/good_frame.jpg" > "$good_frame"
smk --cores 2 --keep-going > "$T/smk.log" 2>&1 && { echo "FAIL snakemake succeeded with a truncated frame"; fail=1; }
grep -q "captures/broken/photo " <(grep -A8 "^Error in rule" "$T/smk.log") ||
  { tail -40 "$T/smk.log"; echo "FAIL the failed job does not name the capture"; fail=1; }
grep -q "IMG_03.jpg" "$T/smk.log" || { echo "FAIL brdfshot's error does not name the frame"; fail=1; }
[ -e "$T/out/results/broken/photo.exr" ] && { echo "FAIL the failed job left its output"; fail=1; }
for m in $MATERIALS; do same_results "$m"; done

# Mended, the re-run runs the broken capture's jobs and nothing else.
cp "$T/good_frame.jpg" "$good_frame"
smk --cores 2 > "$T/rerun.log" 2>&1 || { tail -40 "$T/rerun.log"; echo "FAIL re-run"; fail=1; }
others=$(grep -o "wildcards: cap=[^ ,]*" "$T/rerun.log" | grep -vc "cap=broken$")
ran=$(grep -c "wildcards: cap=broken" "$T/rerun.log")
[ "$others" = 0 ] && [ "$ran" -ge 5 ] || { echo "FAIL the re-run ran $others jobs of good captures, $ran of the mended one"; fail=1; }
[ -s "$T/out/results/broken/report.md" ] || { echo "FAIL the mended capture has no report"; fail=1; }
grep -q "taken from $T/out/basis/" "$T/rerun.log" ||
  { echo "FAIL the mended capture (demo-clay's scene) did not take demo-clay's basis images"; fail=1; }

# The leave-one-out evaluation in three shard jobs and a merge: the table of
# one process's run.
EVAL="--db standin --data $ASSETS --grid 20x20x40 --sphere 16 --theta-samples 8 --phi-samples 12 --no-directional
  --probes $ASSETS/envmaps/studio_256.exr,$ASSETS/envmaps/forest_256.exr"
(cd "$T/work" && snakemake -s "$SRC/samples/Snakefile" --cores 2 eval \
  --config out="$T/out" brdfshot="$B" eval_shards=3 eval_args="$(echo $EVAL)") > "$T/eval.log" 2>&1 ||
  { tail -30 "$T/eval.log"; echo "FAIL the sharded evaluation"; fail=1; }
[ "$(grep -c "rule eval_shard:" "$T/eval.log")" = 3 ] || { echo "FAIL not three shard jobs"; fail=1; }
"$B" eval $EVAL -o "$T/eval_one" > "$T/eval_one.log" 2>&1 || { cat "$T/eval_one.log"; echo "FAIL eval in one process"; fail=1; }
cmp -s "$T/eval_one/eval.csv" "$T/out/eval/eval.csv" || { echo "FAIL the merged shards' eval.csv differs from one process's"; fail=1; }
[ "$fail" = 0 ] && echo "workflow: $(echo $MATERIALS | wc -w) captures equal to the Makefile's; a truncated frame fails only its capture; the re-run ran its $ran jobs only and shared its basis images; 3 evaluation shards merge to one process's table"
exit $fail

#!/usr/bin/env bash
# End-to-end checks of the brdfshot executable: bad input gives a message that
# names the file, a non-zero exit, and leaves the input untouched; the staged
# pipeline recovers a stand-in material from its synthetic photo.
set -u
B="$1"; SRC="$2"; T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
fail=0; pass=0
check() {  # check NAME EXPECTED_RC FRAGMENT -- command...
  local name=$1 want=$2 frag=$3; shift 4
  out=$("$@" 2>&1); rc=$?
  if [ "$rc" = "$want" ] && grep -qF -- "$frag" <<<"$out"; then pass=$((pass+1));
  else echo "FAIL $name: rc=$rc (want $want), output: $out"; fail=$((fail+1)); fi
}
DATA="$SRC/samples/assets"; DB="--db standin --data $DATA --grid 20x20x40"
PROBE="$DATA/envmaps/studio_256.exr"
printf 'junk' > "$T/bad.binary"; cp "$T/bad.binary" "$T/bad.orig"
check merl-bad 1 "$T/bad.binary" -- "$B" render --merl "$T/bad.binary" --probe "$PROBE" -o "$T/x.exr"
cmp -s "$T/bad.binary" "$T/bad.orig" && pass=$((pass+1)) || { echo "FAIL input modified"; fail=$((fail+1)); }
[ ! -e "$T/x.exr" ] && pass=$((pass+1)) || { echo "FAIL partial output"; fail=$((fail+1)); }
check probe-missing 1 "$T/none.exr" -- "$B" basis $DB --probe "$T/none.exr" -o "$T/y.bsbi"
check probe-folder 1 "is a folder" -- "$B" basis $DB --probe "$T" -o "$T/y.bsbi"
check out-folder 1 "is a folder" -- "$B" render --standin demo-gold $DB --probe "$PROBE" -o "$T"
check unknown-cmd 2 "unknown command" -- "$B" frobnicate
check bad-option 1 "see --help" -- "$B" eval --no-such-flag
check help 0 "--probe" -- "$B" basis --help
# Every registered command answers --help (an option registered twice — a
# command's own and a shared group's — is an internal error there).
for cmd in $("$B" 2>&1 | sed -n 's/^  \([a-z][a-z-]*\) .*/\1/p'); do
  check "help-$cmd" 0 "usage: brdfshot $cmd" -- "$B" "$cmd" --help
done
check bad-grid 1 "bad --grid" -- "$B" cluster --db standin --data "$DATA" --grid 9x9 -o "$T/c.json"
# merge: one frame, missing EXIF, then a two-frame bracket with a times file.
# Two PNG exposures of one render, 1 EV apart (the tone map's fixed exposure).
"$B" render --standin demo-felt $DB --probe "$PROBE" --sphere 32 -o "$T/m.exr" >/dev/null 2>&1
"$B" render --standin demo-felt $DB --probe "$PROBE" --sphere 32 --exposure 1 -o "$T/e1.exr" >/dev/null 2>&1
"$B" render --standin demo-felt $DB --probe "$PROBE" --sphere 32 --exposure 2 -o "$T/e2.exr" >/dev/null 2>&1
cp "$T/e1.png" "$T/f1.png"; cp "$T/e2.png" "$T/f2.png"; printf '1/4\n1/2\n' > "$T/times.txt"
check merge-one 1 "f1.png: is a single 8-bit frame" -- "$B" merge "$T/f1.png" -o "$T/merged.exr"
check merge-noexif 1 "f1.png: has no EXIF exposure time" -- "$B" merge "$T/f1.png" "$T/f2.png" -o "$T/merged.exr"
check merge-times 1 "times.txt: has 2 exposure times for 3 frames" -- "$B" merge "$T/f1.png" "$T/f2.png" "$T/m.png" --times "$T/times.txt" -o "$T/merged.exr"
cp "$T/f1.png" "$T/same.png"
check merge-identical 1 "do not constrain" -- "$B" merge "$T/f1.png" "$T/same.png" --times "$T/times.txt" -o "$T/merged.exr"
check merge-ok 0 "merged 2 frames" -- "$B" merge "$T/f1.png" "$T/f2.png" --times "$T/times.txt" -o "$T/merged.exr"
[ -s "$T/merged.exr" ] && [ -s "$T/merged_mask.png" ] && [ -s "$T/merged.json" ] && pass=$((pass+1)) || { echo "FAIL merge outputs"; fail=$((fail+1)); }
check merge-help 0 "--times" -- "$B" merge --help
check bench-help 0 "--reference-samples" -- "$B" bench-basis --help
check bench-bad 1 "bad sample setting '24-48'" -- "$B" bench-basis --qualities 24-48
# The pipeline on one capture.
check render 0 "wrote" -- "$B" render --standin demo-steel $DB --probe "$PROBE" --sphere 48 -o "$T/photo.exr"
check basis 0 "wrote" -- "$B" basis $DB --probe "$PROBE" --sphere 48 -o "$T/b.bsbi"
# Quality by error target: a loose target stops at the ladder's first rung and
# says so in the cache's header; a negative one is refused, naming the option.
check basis-target 0 "16x32" -- "$B" basis $DB --probe "$PROBE" --sphere 24 --error-target 0.5 --error-pixels 60 -o "$T/bt.bsbi"
grep -aq '"quality_search"' "$T/bt.bsbi" && grep -aq '"reached":true' "$T/bt.bsbi" && pass=$((pass+1)) \
  || { echo "FAIL basis-target: no quality_search with reached in the header"; fail=$((fail+1)); }
check basis-target-bad 1 "--error-target must be" -- "$B" basis $DB --probe "$PROBE" --sphere 24 --error-target -1 -o "$T/bt2.bsbi"
[ ! -e "$T/bt2.bsbi" ] && pass=$((pass+1)) || { echo "FAIL basis-target-bad wrote output"; fail=$((fail+1)); }
check cluster 0 "class sizes" -- "$B" cluster $DB -o "$T/c.json"
check fit 0 "chosen class" -- "$B" fit $DB --basis "$T/b.bsbi" --photo "$T/photo.exr" --classes "$T/c.json" --preview-probes "$PROBE" -o "$T/fit"
# The fitted BRDF relit must match the truth: the material is one of the bases.
"$B" render --weights "$T/fit/fit.json" --data "$DATA" --probe "$PROBE" --sphere 48 -o "$T/relit.exr" >/dev/null 2>&1
err=$("$B" compare "$T/photo.exr" "$T/relit.exr" | sed 's/relative RMSE \([0-9.]*\).*/\1/')
awk -v e="$err" 'BEGIN{exit !(e < 0.05)}' && pass=$((pass+1)) || { echo "FAIL relit error $err >= 0.05"; fail=$((fail+1)); }
# The fit records how λ was chosen and what it predicts; bad λ options are refused, naming them.
grep -q '"lambda_rule": "cv"' "$T/fit/fit.json" && grep -q '"predicted_relit_error"' "$T/fit/fit.json" && pass=$((pass+1)) \
  || { echo "FAIL fit.json lacks the λ choice"; fail=$((fail+1)); }
# The candidates: the model's classes, then every basis; the noise the bound followed.
python3 - "$T/fit/fit.json" "$T/c.json" <<'PY' && pass=$((pass+1)) || { echo "FAIL fit.json lacks the every-basis candidate or the bound's noise"; fail=$((fail+1)); }
import json, sys
f, c = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
n = len(f["bases"])
assert f["classes"][-1]["members"] == n, f["classes"][-1]
assert len(f["lambda_choice"]["score_per_class"]) == len(f["classes"])
b, p = f["lambda_choice"]["bound_noise"], f["lambda_choice"]["relative_pixel_noise"]
assert 0 <= b <= p, (b, p)
PY
# A fit scored on a photo under another probe (the fit's weights on that photo's
# basis images) against rendering the fit there and comparing: two routes to
# the relit error. The Lambert + GGX baseline is not exact, so its error is one
# both routes must find.
P2="$DATA/envmaps/forest_256.exr"
check render-other 0 "wrote" -- "$B" render --standin demo-steel $DB --probe "$P2" --sphere 48 -o "$T/photo2.exr"
check basis-other 0 "wrote" -- "$B" basis $DB --probe "$P2" --sphere 48 -o "$T/b2.bsbi"
check score 0 "held-out photo" -- "$B" score --fit "$T/fit/fit.json" --basis "$T/b2.bsbi" --photo "$T/photo2.exr"
line=$("$B" score --fit "$T/fit/fit.json" --basis "$T/b2.bsbi" --photo "$T/photo2.exr" --tsv)
"$B" render --merl "$T/fit/lambert_ggx.binary" --probe "$P2" --sphere 48 -o "$T/lggx2.exr" >/dev/null 2>&1
# Several BRDFs in one render: each image is its own render's; the outputs
# pair with the BRDFs in the order given, one each, and never an input.
L="$T/fit/lambert_ggx.binary"
check render-two 0 "2 BRDFs" -- "$B" render --probe "$P2" --sphere 48 --standin demo-steel $DB -o "$T/two_steel.exr" --merl "$L" -o "$T/two_lggx.exr"
for pair in "photo2.exr two_steel.exr" "lggx2.exr two_lggx.exr"; do
  set -- $pair
  e=$("$B" compare "$T/$1" "$T/$2" | sed 's/relative RMSE \([0-9.]*\).*/\1/')
  awk -v e="$e" 'BEGIN{exit !(e < 1e-4)}' && pass=$((pass+1)) || { echo "FAIL render of two: $2 against $1: $e"; fail=$((fail+1)); }
done
check render-outputs 1 "give one -o per BRDF: 2 BRDFs, 1 outputs" -- "$B" render --probe "$P2" --standin demo-steel $DB --merl "$L" -o "$T/x.exr"
cp "$L" "$T/lggx.orig"
check render-onto-input 1 "lambert_ggx.binary: is an input of this render" -- "$B" render --probe "$P2" --merl "$L" -o "$L"
cmp -s "$L" "$T/lggx.orig" && pass=$((pass+1)) || { echo "FAIL render overwrote its input"; fail=$((fail+1)); }
lg=$("$B" compare "$T/photo2.exr" "$T/lggx2.exr" | sed 's/relative RMSE \([0-9.]*\).*/\1/')
awk -v f="$(cut -f4 <<<"$line")" -v s="$(cut -f6 <<<"$line")" -v c="$lg" 'BEGIN{exit !(f < 0.05 && c > 0.005 && s > 0.8 * c && s < 1.2 * c)}' \
  && pass=$((pass+1)) || { echo "FAIL score $line against render + compare $lg"; fail=$((fail+1)); }
check score-no-photo 1 "give one of --obs and --photo" -- "$B" score --fit "$T/fit/fit.json" --basis "$T/b2.bsbi"
check score-photo-size 1 "basis images are for" -- "$B" score --fit "$T/fit/fit.json" --basis "$T/b2.bsbi" --photo "$PROBE"
check fit-fixed 0 "(fixed)" -- "$B" fit $DB --basis "$T/b.bsbi" --photo "$T/photo.exr" --classes "$T/c.json" --lambda 0.5 --preview-probes "$PROBE" -o "$T/fitl"
grep -q '"lambda": 0.5' "$T/fitl/fit.json" && pass=$((pass+1)) || { echo "FAIL --lambda 0.5 not recorded"; fail=$((fail+1)); }
# Several fits against one photo: one line each, the same as each alone.
two=$("$B" score --fit "$T/fit/fit.json,$T/fitl/fit.json" --basis "$T/b2.bsbi" --photo "$T/photo2.exr" --tsv)
lam=$("$B" score --fit "$T/fitl/fit.json" --basis "$T/b2.bsbi" --photo "$T/photo2.exr" --tsv)
[ "$two" = "$line"$'\n'"$lam" ] && pass=$((pass+1)) || { echo "FAIL score of two fits: $two"; fail=$((fail+1)); }
check fit-bad-rule 1 "unknown --lambda-rule 'best'" -- "$B" fit $DB --basis "$T/b.bsbi" --photo "$T/photo.exr" --classes "$T/c.json" --lambda-rule best -o "$T/fitb1"
check fit-bad-grid 1 "bad --lambda-grid '0.1,x'" -- "$B" fit $DB --basis "$T/b.bsbi" --photo "$T/photo.exr" --classes "$T/c.json" --lambda-grid 0.1,x -o "$T/fitb2"
check fit-bad-folds 1 "--folds must be at least 2" -- "$B" fit $DB --basis "$T/b.bsbi" --photo "$T/photo.exr" --classes "$T/c.json" --folds 1 -o "$T/fitb3"
check fit-bad-condition 1 "--max-condition must be 0 (from the photo's noise) or at least 1" -- "$B" fit $DB --basis "$T/b.bsbi" --photo "$T/photo.exr" --classes "$T/c.json" --max-condition 0.5 -o "$T/fitb4"
check fit-bad-margin 1 "--noise-margin must be positive" -- "$B" fit $DB --basis "$T/b.bsbi" --photo "$T/photo.exr" --classes "$T/c.json" --noise-margin 0 -o "$T/fitb5"
check eval-bad-min-condition 1 "--min-condition must lie in [1, 1e+12]" -- "$B" eval $DB --min-condition 1e13 -o "$T/evalb"
check eval-bad-noise-bound 1 "--max-noise-bound must be finite and at least 1" -- "$B" eval $DB --max-noise-bound 0.5 -o "$T/evalb"
check fit-bad-penalty 1 "--sensitivity-penalty must be finite and ≥ 0" -- "$B" fit $DB --basis "$T/b.bsbi" --photo "$T/photo.exr" --classes "$T/c.json" --sensitivity-penalty -1 -o "$T/fitb4"
check fit-bad-constraint 1 "unknown --constraint 'positive'" -- "$B" fit $DB --basis "$T/b.bsbi" --photo "$T/photo.exr" --classes "$T/c.json" --constraint positive -o "$T/fitb4"
[ ! -e "$T/fitb1" ] && [ ! -e "$T/fitb2" ] && [ ! -e "$T/fitb3" ] && [ ! -e "$T/fitb4" ] && pass=$((pass+1)) || { echo "FAIL a refused fit left an output folder"; fail=$((fail+1)); }
# The default keeps the BRDF non-negative and says so.
grep -q '"weights_constraint": "non-negative bins"' "$T/fit/fit.json" && pass=$((pass+1)) \
  || { echo "FAIL fit.json does not record the non-negative constraint"; fail=$((fail+1)); }
check photo-size 1 "basis images are for" -- "$B" fit $DB --basis "$T/b.bsbi" --photo "$PROBE" --classes "$T/c.json" -o "$T/fit2"
# The staged chain: detect the sphere in a padded render, remap, basis and fit on the observations.
check render-pad 0 "wrote" -- "$B" render --standin demo-steel $DB --probe "$PROBE" --sphere 64 --pad 20 -o "$T/padded.exr"
check normals 0 "rim points" -- "$B" normals "$T/padded.exr" -o "$T/sphere.json"
[ -s "$T/sphere.png" ] && pass=$((pass+1)) || { echo "FAIL normals overlay"; fail=$((fail+1)); }
check normals-none 1 "no sphere found" -- "$B" normals "$PROBE" -o "$T/none.json"
check calib 0 "rotation yaw 10.00" -- "$B" calib --probe "$PROBE" --rotate 10,0,0 -o "$T/probe.exr"
check calib-matrix 0 "rotation yaw 10.00 pitch 0.00 roll 0.00" -- "$B" calib --probe "$PROBE" --rotate-matrix 0.984807753,0,0.173648178,0,1,0,-0.173648178,0,0.984807753 -o "$T/probe-m.exr"
check calib-matrix-scaled 1 "is not a rotation" -- "$B" calib --probe "$PROBE" --rotate-matrix 2,0,0,0,2,0,0,0,2 -o "$T/probe2.exr"
check calib-matrix-mirror 1 "is not a rotation" -- "$B" calib --probe "$PROBE" --rotate-matrix -1,0,0,0,1,0,0,0,1 -o "$T/probe2.exr"
check calib-matrix-both 1 "give one of --rotate, --rotate-matrix and --rotate-from-ball" -- "$B" calib --probe "$PROBE" --rotate 5,0,0 --rotate-matrix 1,0,0,0,1,0,0,0,1 -o "$T/probe2.exr"
check calib-bad-rotate 1 "bad --rotate" -- "$B" calib --probe "$PROBE" --rotate 10,0 -o "$T/probe2.exr"
check calib-bad-layout 1 "unknown --layout" -- "$B" calib --probe "$PROBE" --layout cube -o "$T/probe2.exr"
check remap 0 "pixels of" -- "$B" remap --photo "$T/padded.exr" --sphere "$T/sphere.json" --calib "$T/probe.json" -o "$T/obs.bsobs"
# Any convex object: a normal map instead of a sphere. The detected sphere's own
# normal map (normals --normal-map-out) gives remap the same pixels as the sphere.
"$B" normals "$T/padded.exr" -o "$T/nsphere.json" --normal-map-out "$T/nmap.exr" >/dev/null
n1=$("$B" remap --photo "$T/padded.exr" --sphere "$T/nsphere.json" --rim-px 0 -o "$T/o1.bsobs" | sed -n 's/^\([0-9]*\) pixels.*/\1/p')
n2=$("$B" remap --photo "$T/padded.exr" --normal-map "$T/nmap.exr" --erode 0 -o "$T/o2.bsobs" | sed -n 's/^\([0-9]*\) pixels.*/\1/p')
[ -n "$n1" ] && [ "$n1" -gt 1000 ] && [ "$n1" = "$n2" ] && pass=$((pass+1)) || { echo "FAIL normal map pixels $n2 vs sphere $n1"; fail=$((fail+1)); }
check remap-both 1 "give exactly one of --sphere and --normal-map" -- "$B" remap --photo "$T/padded.exr" --sphere "$T/nsphere.json" --normal-map "$T/nmap.exr" -o "$T/o3.bsobs"
check remap-badmap 1 "nsphere.json: cannot decode normal map" -- "$B" remap --photo "$T/padded.exr" --normal-map "$T/nsphere.json" -o "$T/o3.bsobs"
check remap-mapsize 1 "is for a 256x128 photo" -- "$B" remap --photo "$T/padded.exr" --normal-map "$PROBE" -o "$T/o3.bsobs"
[ ! -e "$T/o3.bsobs" ] && pass=$((pass+1)) || { echo "FAIL remap wrote on bad input"; fail=$((fail+1)); }
# Radiometric scale from a reference card (here the render's sphere centre):
# halving the card's albedo doubles the scale, and remap divides by it.
check calib-card 0 "reference card: 16 px" -- "$B" calib --probe "$PROBE" --card "$T/padded.exr" --card-region 50,50,4,4 -o "$T/pc1.exr"
s1=$("$B" calib --probe "$PROBE" --card "$T/padded.exr" --card-region 50,50,4,4 -o "$T/pc1.exr" | sed -n 's/.*, scale \([0-9.e+-]*\) .*/\1/p')
s2=$("$B" calib --probe "$PROBE" --card "$T/padded.exr" --card-region 50,50,4,4 --card-albedo 0.09 -o "$T/pc2.exr" | sed -n 's/.*, scale \([0-9.e+-]*\) .*/\1/p')
awk -v a="$s1" -v b="$s2" 'BEGIN{exit !(a > 0 && b / a > 1.999 && b / a < 2.001)}' && pass=$((pass+1)) || { echo "FAIL card scale $s1 vs half albedo $s2"; fail=$((fail+1)); }
check remap-card 0 "divided by scale $s1" -- "$B" remap --photo "$T/padded.exr" --sphere "$T/sphere.json" --calib "$T/pc1.json" -o "$T/obs-card.bsobs"
check calib-card-out 1 "padded.exr: reference card region 100,50,40,4 is empty or leaves the 104x104 photo" -- "$B" calib --probe "$PROBE" --card "$T/padded.exr" --card-region 100,50,40,4 -o "$T/pc3.exr"
check calib-card-both 1 "give at most one of --scale, --card and --photo-merge/--probe-merge" -- "$B" calib --probe "$PROBE" --card "$T/padded.exr" --card-region 50,50,4,4 --scale 2 -o "$T/pc3.exr"
check calib-card-away 1 "sends no light onto the reference card" -- "$B" calib --sun 0,0,-1 --card "$T/padded.exr" --card-region 50,50,4,4 -o "$T/pc3.exr"
[ ! -e "$T/pc3.exr" ] && [ ! -e "$T/pc3.json" ] && pass=$((pass+1)) || { echo "FAIL calib wrote outputs on a bad card"; fail=$((fail+1)); }
# A perspective ball seen through a very long lens is an orthographic one:
# the same marked circle with --ball-focal-px 1e6 must unwrap to the same probe.
check calib-ball-ortho 0 "lat-long" -- "$B" calib --probe "$T/padded.exr" --layout mirrorball --ball-circle 52,52,40 --width 64 -o "$T/ball-o.exr"
check calib-ball-persp 0 "lat-long" -- "$B" calib --probe "$T/padded.exr" --layout mirrorball --ball-circle 52,52,40 --ball-focal-px 1e6 --width 64 -o "$T/ball-p.exr"
grep -q '"camera": "perspective"' "$T/ball-p.json" && pass=$((pass+1)) || { echo "FAIL perspective ball not recorded"; fail=$((fail+1)); }
be=$("$B" compare "$T/ball-o.exr" "$T/ball-p.exr" | sed -n 's/relative RMSE \([0-9.]*\).*/\1/p')
awk -v e="$be" 'BEGIN{exit !(e != "" && e < 1e-3)}' && pass=$((pass+1)) || { echo "FAIL long-lens ball vs orthographic: '$be'"; fail=$((fail+1)); }
# ...and through a short lens (the ball 23° across) it must not be.
"$B" calib --probe "$T/padded.exr" --layout mirrorball --ball-circle 52,52,40 --ball-focal-px 200 --width 64 -o "$T/ball-s.exr" >/dev/null
be=$("$B" compare "$T/ball-o.exr" "$T/ball-s.exr" | sed -n 's/relative RMSE \([0-9.]*\).*/\1/p')
awk -v e="$be" 'BEGIN{exit !(e != "" && e > 0.05)}' && pass=$((pass+1)) || { echo "FAIL short-lens ball same as orthographic: '$be'"; fail=$((fail+1)); }
check calib-ball-focal 1 "--ball-focal-px must be a focal length" -- "$B" calib --probe "$T/padded.exr" --layout mirrorball --ball-focal-px -5 -o "$T/pc5.exr"
check normals-focal 1 "--focal-px must be a focal length" -- "$B" normals "$T/padded.exr" --focal-px -5 -o "$T/pc5.json"
check calib-ball-circle 1 "bad --ball-circle" -- "$B" calib --probe "$PROBE" --rotate-from-ball "$T/padded.exr" --ball-circle 50,50 -o "$T/pc5.exr"
check calib-ball-both 1 "--ball-circle is ambiguous" -- "$B" calib --probe "$T/padded.exr" --layout mirrorball --rotate-from-ball "$T/padded.exr" --ball-circle 50,50,30 -o "$T/pc5.exr"
# From exposure metadata: one merge against itself is scale 1; half a pair is an error.
check calib-merges 0 "scale 1 1 1" -- "$B" calib --probe "$PROBE" --photo-merge "$T/merged.json" --probe-merge "$T/merged.json" -o "$T/pc6.exr"
check calib-merges-half 1 "--photo-merge and --probe-merge go together" -- "$B" calib --probe "$PROBE" --probe-merge "$T/merged.json" -o "$T/pc6.exr"
check calib-merges-notmerge 1 "pc6.json: not a brdfshot merge sidecar" -- "$B" calib --probe "$PROBE" --photo-merge "$T/pc6.json" --probe-merge "$T/merged.json" -o "$T/pc7.exr"
check calib-scale-rgb 0 "scale 1 2 3" -- "$B" calib --probe "$PROBE" --scale 1,2,3 -o "$T/pc4.exr"
check calib-scale-bad 1 "--scale must be positive" -- "$B" calib --probe "$PROBE" --scale 1,0,3 -o "$T/pc4.exr"
check remap-nocalib 0 "pixels of" -- "$B" remap --photo "$T/padded.exr" --sphere "$T/sphere.json" -o "$T/obs-nocalib.bsobs"
check remap-size 1 "sphere.json: is for a 104x104 photo" -- "$B" remap --photo "$T/photo.exr" --sphere "$T/sphere.json" -o "$T/obs2.bsobs"
# A number far beyond int where a size belongs (fuzz_json found it as UB): a named error.
sed 's/"width": [0-9]*/"width": 6444444444444444444444444444444444444444/' "$T/sphere.json" > "$T/wide.json"
check remap-hugewidth 1 "wide.json: 'width' must be an integer from 1 to 1048576" -- "$B" remap --photo "$T/padded.exr" --sphere "$T/wide.json" -o "$T/obs3.bsobs"
check remap-notjson 1 "bad.binary: not JSON" -- "$B" remap --photo "$T/padded.exr" --sphere "$T/bad.binary" -o "$T/obs2.bsobs"
check basis-obs 0 "wrote" -- "$B" basis $DB --probe "$T/probe.exr" --obs "$T/obs.bsobs" -o "$T/bo.bsbi"
check fit-obs 0 "chosen class" -- "$B" fit $DB --basis "$T/bo.bsbi" --obs "$T/obs.bsobs" --classes "$T/c.json" --preview-probes "$PROBE" -o "$T/fito"
check fit-no-previews 0 "and 0 relit previews" -- "$B" fit $DB --basis "$T/bo.bsbi" --obs "$T/obs.bsobs" --classes "$T/c.json" --preview-probes none -o "$T/fitn"
[ -s "$T/fitn/photo_vs_fit.png" ] && ! ls "$T/fitn"/relit_*.png >/dev/null 2>&1 && pass=$((pass+1)) || { echo "FAIL --preview-probes none wrote relit previews"; fail=$((fail+1)); }
check fit-obs-mismatch 1 "are not the ones" -- "$B" fit $DB --basis "$T/b.bsbi" --obs "$T/obs.bsobs" --classes "$T/c.json" -o "$T/fito2"
check fit-both 1 "exactly one of --photo and --obs" -- "$B" fit $DB --basis "$T/b.bsbi" --obs "$T/obs.bsobs" --photo "$T/photo.exr" --classes "$T/c.json" -o "$T/fito3"
check obs-bad 1 "bad.binary: not a brdfshot observation file" -- "$B" basis $DB --probe "$PROBE" --obs "$T/bad.binary" -o "$T/bo2.bsbi"
# bench-merge runs end to end on a small scene and beats OpenCV's Debevec there.
check bench-merge 0 "wrote" -- "$B" bench-merge --probes "$PROBE" --size 128x64 --methods ours,cv-debevec -o "$T/bm"
# The focal length from EXIF: synth-capture writes FocalLengthIn35mmFilm (480 px
# over a 320 px side is 54 mm), merge records it, normals --merge uses it.
"$B" synth-capture --probe "$PROBE" --standin demo-red-plastic $DB --size 320x240 --radius 70 --focal-px 480 \
  --probe-shot-width 64 -o "$T/fcap" >/dev/null && "$B" merge "$T/fcap/photo" -o "$T/fp.exr" >/dev/null
grep -q '"focal_35mm": 54.0' "$T/fp.json" && pass=$((pass+1)) || { echo "FAIL merge sidecar focal_35mm"; fail=$((fail+1)); }
# eval in independent jobs: two shards merged give the one-process table.
EV="--probes $DATA/envmaps/forest_256.exr,$PROBE --sphere 16 --no-directional"
check eval-shard0 0 "eval_shard_0_of_2.json" -- "$B" eval $DB $EV --shard 0/2 -o "$T/ev"
check eval-shard1 0 "eval_shard_1_of_2.json" -- "$B" eval $DB $EV --shard 1/2 -o "$T/ev"
check eval-merge 0 "eval.csv" -- "$B" eval --merge "$T/ev/eval_shard_0_of_2.json,$T/ev/eval_shard_1_of_2.json" -o "$T/evm"
check eval-whole 0 "eval.csv" -- "$B" eval $DB $EV -o "$T/evw"
cmp -s "$T/evm/eval.csv" "$T/evw/eval.csv" && pass=$((pass+1)) || { echo "FAIL merged shards differ from one run"; fail=$((fail+1)); }
check eval-merge-missing 1 "shard 1 of 2 is missing" -- "$B" eval --merge "$T/ev/eval_shard_0_of_2.json" -o "$T/evm2"
# Two photos of a material fitted as one, beside each photo alone.
check eval-joint 0 "Two photos of one material" -- "$B" eval $DB $EV --joint -o "$T/evj"
grep -q ',auto-joint,' "$T/evj/eval.csv" && pass=$((pass+1)) || { echo "FAIL eval --joint wrote no joint rows"; fail=$((fail+1)); }
check eval-joint-targets 0 "Two photos of one material" -- "$B" eval $DB $EV --joint --targets standin -o "$T/evj2"
# The whole table checked after every default fit, as fit does: no sampled bin of any auto fit below zero.
for kind in loo targets; do
  extra=$([ $kind = targets ] && echo "--targets standin --joint" || echo "")
  check eval-table-check-$kind 0 "(the whole table checked)" -- "$B" eval $DB $EV $extra --check-whole-table -o "$T/evt$kind"
  awk -F, '$1 == "material" { for (i = 1; i <= NF; ++i) col[$i] = i; next }
           col["method"] && $col["method"] ~ /^auto(-joint)?$/ && $col["negative_bins"] != 0 { bad = 1 }
           END { exit bad || !col["negative_bins"] }' "$T/evt$kind/eval.csv" \
    && pass=$((pass+1)) || { echo "FAIL eval --check-whole-table ($kind) left an auto fit with a negative bin"; fail=$((fail+1)); }
done
# merge-check on the same bracket: each inner frame predicted by ours and by OpenCV's merge.
check merge-check 0 "| brdfshot | " -- "$B" merge-check "$T/fcap/photo"
check merge-check-two 1 "needs a bracket of three frames or more" -- "$B" merge-check "$T/f1.png" "$T/f2.png" --times "$T/times.txt"
check merge-check-help 0 "--times" -- "$B" merge-check --help
check merge-align 0 "merged" -- "$B" merge "$T/fcap/photo" --align -o "$T/fpa.exr"
grep -q '"homography_to_reference"' "$T/fpa.json" && pass=$((pass+1)) || { echo "FAIL merge --align records the homographies"; fail=$((fail+1)); }
# A static bracket has (almost) no ghosts; the mask is written and named in the sidecar.
check merge-deghost 0 "moved between frames" -- "$B" merge "$T/fcap/photo" --deghost -o "$T/fpg.exr"
[ -s "$T/fpg_ghosts.png" ] && grep -q '"deghosted": true' "$T/fpg.json" && pass=$((pass+1)) || { echo "FAIL merge --deghost outputs"; fail=$((fail+1)); }
# merge --probe on JPEG frames: the clipping rule (capture/clipping.h) is on,
# recorded in the sidecar, and changes the studio's clipped lamps; without it
# (and on the photo) the merge is per channel.
"$B" merge "$T/fcap/probe" -o "$T/pp0.exr" >/dev/null && "$B" merge "$T/fcap/probe" --probe -o "$T/pp1.exr" >/dev/null
grep -q '"clip_reach": 2' "$T/pp1.json" && grep -q '"clip_reach": -1' "$T/pp0.json" && pass=$((pass+1)) ||
  { echo "FAIL merge --probe clip_reach in the sidecars"; fail=$((fail+1)); }
pd=$("$B" compare "$T/pp0.exr" "$T/pp1.exr" | sed -n 's/relative RMSE \([0-9.]*\).*/\1/p')
awk -v e="$pd" 'BEGIN{exit !(e != "" && e > 0)}' && pass=$((pass+1)) || { echo "FAIL merge --probe changed nothing ('$pd')"; fail=$((fail+1)); }
check normals-exif-focal 0 "(perspective, f 480 px from the EXIF 35 mm focal length in $T/fp.json)" -- "$B" normals "$T/fp.exr" --merge "$T/fp.json" -o "$T/fs.json"
c=$(sed -n 's/.*centre (\([0-9.]*\), \([0-9.]*\)).*/\1 \2/p' <<<"$out")
awk -v c="$c" 'BEGIN{split(c,a," "); exit !((a[1]-176.0)^2+(a[2]-110.4)^2 < 0.09)}' && pass=$((pass+1)) || { echo "FAIL EXIF-focal centre '$c', truth 176.0 110.4"; fail=$((fail+1)); }
printf '{"format": 5}' > "$T/fmt5.json"
check normals-merge-type 1 "fmt5.json: not a brdfshot merge sidecar" -- "$B" normals "$T/fp.exr" --merge "$T/fmt5.json" -o "$T/fs2.json"
check normals-merge-bad 1 "fs.json: not a brdfshot merge sidecar" -- "$B" normals "$T/fp.exr" --merge "$T/fs.json" -o "$T/fs2.json"
# synth-capture and report: help, bad options, bad folders.
check synth-help 0 "--format" -- "$B" synth-capture --help
check synth-size 1 "bad --size '64x2'" -- "$B" synth-capture --probe "$PROBE" --standin demo-gold $DB --size 64x2 -o "$T/cap"
check bench-detect-seeds 1 "--seeds must be at least 1" -- "$B" bench-detect --seeds 0
check bench-detect-size 1 "bad --sizes '64x2'" -- "$B" bench-detect --sizes 64x2
check synth-format 1 "unknown --format 'tiff'" -- "$B" synth-capture --probe "$PROBE" --standin demo-gold $DB --format tiff -o "$T/cap"
[ ! -e "$T/cap" ] && pass=$((pass+1)) || { echo "FAIL synth-capture wrote a folder on bad options"; fail=$((fail+1)); }
check report-help 0 "--results" -- "$B" report --help
check report-nofolder 1 "$T/none: is not a results folder" -- "$B" report --results "$T/none"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]

#!/usr/bin/env bash
# The bad-input table of the README ("Bad input"), row by row: each input gives
# a message naming the file and the problem, exit code 1, no output file (all
# writes are temp file + rename), and the input unchanged. Inputs are made here
# with printf/awk only (no Python on a fresh machine).
set -u
B="$1"; SRC="$2"; T=$(mktemp -d); trap 'chmod -R u+w "$T"; rm -rf "$T"' EXIT
DATA="$SRC/samples/assets"; DB="--db standin --data $DATA --grid 20x20x40"
PROBE="$DATA/envmaps/studio_256.exr"
fail=0; pass=0
# row NAME FRAGMENT OUTPUT INPUT -- command...: rc 1, FRAGMENT in the message,
# OUTPUT absent afterwards, INPUT byte-identical afterwards.
row() {
  local name=$1 frag=$2 output=$3 input=$4; shift 5
  local sum; sum=$(cksum < "$input" 2>/dev/null || echo folder)
  out=$("$@" 2>&1); rc=$?
  local why=""
  [ "$rc" = 1 ] || why="rc=$rc"
  grep -qF -- "$frag" <<<"$out" || why="$why no '$frag'"
  [ -e "$output" ] && why="$why wrote $output"
  [ "$(cksum < "$input" 2>/dev/null || echo folder)" = "$sum" ] || why="$why changed $input"
  if [ -z "$why" ]; then pass=$((pass+1)); else echo "FAIL $name:$why; output: $out"; fail=$((fail+1)); fi
}
ppm() {  # ppm FILE W H VALUE: a flat 8-bit RGB image
  { printf 'P6\n%d %d\n255\n' "$2" "$3"; head -c $(($2 * $3 * 3)) /dev/zero | tr '\0' "$(printf '\\%03o' "$4")"; } > "$1"
}
discs() {  # discs FILE W H "cx cy r ..." : bright shaded discs on a dark ramp (plain PPM)
  awk -v w="$2" -v h="$3" -v d="$4" 'BEGIN { n = split(d, a, " "); print "P3"; print w, h; print 255;
    for (y = 0; y < h; y++) { line = ""; for (x = 0; x < w; x++) { v = 20 + int(30 * x / w);
      for (i = 1; i <= n; i += 3) { dx = x + 0.5 - a[i]; dy = y + 0.5 - a[i+1]; r2 = (dx*dx + dy*dy) / (a[i+2]*a[i+2]);
        if (r2 < 1) v = int(60 + 180 * sqrt(1 - r2)) }
      line = line v " " v " " v " " } print line } }' > "$1"
}

: > "$T/empty.exr"
row zero-length-probe "empty.exr: not a readable OpenEXR file" "$T/p.exr" "$T/empty.exr" -- "$B" calib --probe "$T/empty.exr" -o "$T/p.exr"
head -c 1000 "$PROBE" > "$T/truncated.exr"
row truncated-probe "truncated.exr" "$T/p.exr" "$T/truncated.exr" -- "$B" calib --probe "$T/truncated.exr" -o "$T/p.exr"
{ printf 'PF\n8 4\n-1.0\n'; for i in $(seq 1 95); do printf '\000\000\200\077'; done; printf '\000\000\300\177'; } > "$T/nan.pfm"
row nan-probe "nan.pfm: contains NaN or Inf" "$T/x.exr" "$T/nan.pfm" -- "$B" render --standin demo-gold $DB --probe "$T/nan.pfm" --sphere 16 -o "$T/x.exr"
row nan-photo "nan.pfm: contains NaN or Inf" "$T/s.json" "$T/nan.pfm" -- "$B" normals "$T/nan.pfm" -o "$T/s.json"
printf 'BSHOTOB1' > "$T/short.bsobs"
row truncated-obs "short.bsobs" "$T/b.bsbi" "$T/short.bsobs" -- "$B" basis $DB --probe "$PROBE" --obs "$T/short.bsobs" -o "$T/b.bsbi"
# A JPEG frame cut short (an interrupted copy), which OpenCV alone decodes with grey rows.
"$B" synth-capture --standin demo-clay --data "$DATA" --probe "$PROBE" --size 160x120 --radius 30 --probe-shot-width 64 -o "$T/cut" > /dev/null 2>&1
head -c 2000 "$T/cut/photo/IMG_03.jpg" > "$T/IMG_03.part" && mv "$T/IMG_03.part" "$T/cut/photo/IMG_03.jpg"
row truncated-jpeg "IMG_03.jpg: truncated" "$T/m.exr" "$T/cut/photo/IMG_03.jpg" -- "$B" merge "$T/cut/photo" -o "$T/m.exr"
printf 'BSHOTBI1\377\377\377\377\377\377\377\177' > "$T/huge.bsbi"
row bad-header-bsbi "huge.bsbi" "$T/fit" "$T/huge.bsbi" -- "$B" fit $DB --basis "$T/huge.bsbi" --photo "$PROBE" --classes "$T/huge.bsbi" -o "$T/fit"
printf '1/4\n1/2\n' > "$T/times.txt"
ppm "$T/white1.ppm" 64 48 255; ppm "$T/white2.ppm" 64 48 255
row all-saturated "white1.ppm: is saturated everywhere" "$T/m.exr" "$T/white1.ppm" -- "$B" merge "$T/white1.ppm" "$T/white2.ppm" --times "$T/times.txt" -o "$T/m.exr"
discs "$T/scene1.ppm" 96 72 "30 30 15"; discs "$T/scene2.ppm" 96 72 "70 50 10 20 55 8"
row align-other-scene "scene1.ppm and " "$T/m.exr" "$T/scene2.ppm" -- "$B" merge "$T/scene1.ppm" "$T/scene2.ppm" --times "$T/times.txt" --align -o "$T/m.exr"
ppm "$T/black1.ppm" 64 48 0; ppm "$T/black2.ppm" 64 48 0
row all-black "black2.ppm: is black everywhere" "$T/m.exr" "$T/black1.ppm" -- "$B" merge "$T/black1.ppm" "$T/black2.ppm" --times "$T/times.txt" -o "$T/m.exr"
row clip-reach-range "--clip-reach must be -1 … 64" "$T/m.exr" "$T/black1.ppm" -- "$B" merge "$T/black1.ppm" "$T/black2.ppm" --times "$T/times.txt" --clip-reach 99 -o "$T/m.exr"
ppm "$T/small.ppm" 32 48 100
row frame-sizes "small.ppm: is 32x48, $T/black1.ppm is 64x48" "$T/m.exr" "$T/small.ppm" -- "$B" merge "$T/black1.ppm" "$T/small.ppm" --times "$T/times.txt" -o "$T/m.exr"
discs "$T/none.ppm" 320 240 ""
row no-sphere "none.ppm: no sphere found" "$T/s.json" "$T/none.ppm" -- "$B" normals "$T/none.ppm" -o "$T/s.json"
discs "$T/two.ppm" 320 240 "85 120 60 235 115 55"
row two-spheres "two.ppm: two spheres found, centred at (" "$T/s.json" "$T/two.ppm" -- "$B" normals "$T/two.ppm" -o "$T/s.json"
row near-outside "--near 400,10 lies outside the photo" "$T/s.json" "$T/two.ppm" -- "$B" normals "$T/two.ppm" --near 400,10 -o "$T/s.json"
# --near picks one of them: exit 0 and that sphere's circle.
out=$("$B" normals "$T/two.ppm" --near 240,100 -o "$T/two.json" 2>&1); rc=$?
near() {  # near FILE KEY VALUE: the JSON number KEY in FILE is within 0.1 of VALUE
  awk -v k="\"$2\":" -v v="$3" '$1 == k { x = $2 + 0; if (x - v < 0.1 && v - x < 0.1) ok = 1 } END { exit !ok }' "$1"
}
if [ "$rc" = 0 ] && near "$T/two.json" cx 235 && near "$T/two.json" cy 115 && near "$T/two.json" r 55; then pass=$((pass+1));
else echo "FAIL two-spheres-near: rc=$rc, output: $out"; fail=$((fail+1)); fi
# A sphere cut by the border is still measured (the visible rim fixes the
# circle): a warning naming the file, exit 0, and the right circle.
discs "$T/cut.ppm" 320 240 "290 120 80"
out=$("$B" normals "$T/cut.ppm" -o "$T/cut.json" 2>&1); rc=$?
if [ "$rc" = 0 ] && grep -qF "cut.ppm: the sphere is cut by the image border" <<<"$out" &&
   grep -q '"cx": 290.0' "$T/cut.json" && grep -q '"r": 80.0' "$T/cut.json"; then pass=$((pass+1));
else echo "FAIL cut-by-border: rc=$rc, output: $out"; fail=$((fail+1)); fi
row probe-is-folder "is a folder" "$T/p.exr" "$T/times.txt" -- "$B" calib --probe "$T" -o "$T/p.exr"
mkdir "$T/ro"; chmod 555 "$T/ro"
if [ -w "$T/ro" ]; then  # root ignores permissions: a folder that cannot hold files instead
  row readonly-output "/proc/brdfshot_x.exr: write failed" "/proc/brdfshot_x.exr" "$PROBE" -- "$B" calib --probe "$PROBE" -o /proc/brdfshot_x.exr
else
  row readonly-output "ro/p.exr" "$T/ro/p.exr" "$PROBE" -- "$B" calib --probe "$PROBE" -o "$T/ro/p.exr"
fi
echo "bad-input table: $pass passed, $fail failed"
[ "$fail" = 0 ]

#!/usr/bin/env bash
# Relighting checked on real photos: DiLiGenT's ball fitted from one photo
# (one LED, `make -C samples diligent-relight`) and scored with `brdfshot
# score` on two photos under other LEDs. Asserts the default fit predicts each
# held-out photo within 10 % relative RMSE and at four fifths or less of the
# error of the unregularised fit (λ = 0), which one lamp's photo leaves free
# to swing where it shows nothing. Skipped (77) without the DiLiGenT photos
# ($BRDFSHOT_DATA, then ../shared).
set -u
B="$1"; SRC="$2"; T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
DATA="${BRDFSHOT_DATA:-$SRC/../shared}"
[ -s "$DATA/real/diligent_ballPNG/040.png" ] || { echo "DiLiGenT's ball not found under $DATA/real: skipped"; exit 77; }
make --no-print-directory -C "$SRC/samples" diligent-relight BRDFSHOT="$B" OUT="$T/out" DATA="$DATA" \
  DL_FIT_IMAGES=040 DL_SCORE_IMAGES="016 064" DL_VARIANTS="auto lambda-0" DL_JOINT= > "$T/log" 2>&1 ||
  { cat "$T/log"; echo "FAIL make diligent-relight"; exit 1; }
S=$(ls -d "$T/out/diligent-relight/scores-"*)
fail=0
for j in 016 064; do
  auto=$(grep "/$j/basis.bsbi" "$S/040_auto.tsv" | cut -f4)
  free=$(grep "/$j/basis.bsbi" "$S/040_lambda-0.tsv" | cut -f4)
  awk -v a="$auto" -v f="$free" 'BEGIN{exit !(a != "" && f != "" && a < 0.10 && a <= 0.8 * f)}' ||
    { echo "FAIL photo $j predicted from photo 040: default $auto, λ = 0 $free"; fail=1; }
  echo "photo $j predicted from photo 040: default $auto, λ = 0 $free"
done
grep -q "| auto |" "$T/log" || { echo "FAIL no table"; fail=1; }
exit $fail

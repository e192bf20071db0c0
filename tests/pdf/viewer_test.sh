#!/usr/bin/env bash
# ctest pdf_viewers: real PDF viewers draw the export like `sdvi render` draws the .sdvi.
# For a full-frame image and an object image with a hole, at the image's size and at x4:
#   pdftoppm (poppler, over white), pdftocairo -transp (poppler's cairo backend, RGBA) and
#   mutool draw (MuPDF, RGBA)
# each must reach PSNR >= 35 dB against `sdvi render` of the same .sdvi at the same size
# (over the pixels both draw opaque), and the RGBA renders must leave the outside of the
# domain transparent and agree with sdvi's alpha on all but 1% of the domain's pixels.
#   viewer_test.sh SDVI FIXTURE WORK_DIR
# Exit 77 (ctest SKIP) only when a viewer is missing (poppler-utils, mupdf-tools).
set -u
sdvi=$1 fixture=$2 work=$3
min_psnr=35
for tool in pdftoppm pdftocairo mutool; do
  command -v $tool >/dev/null 2>&1 ||
    { echo "SKIP: $tool is not installed (Debian packages poppler-utils, mupdf-tools)"; exit 77; }
done
rm -rf "$work" && mkdir -p "$work" || exit 1

status=0
for spec in "gradient 96 64" "annulus 80 60"; do
  read -r kind w h <<<"$spec"
  "$fixture" sdvi "$kind" "$w" "$h" "$work/$kind.sdvi" || { echo "FAIL: fixture $kind"; exit 1; }
  "$fixture" pdf "$work/$kind.sdvi" "$work/$kind.pdf" >/dev/null || { echo "FAIL: export $kind"; exit 1; }
  for scale in 1 4; do
    ow=$((w * scale)) oh=$((h * scale)) base="$work/${kind}_x$scale"
    "$sdvi" render "$work/$kind.sdvi" -o "${base}_sdvi.png" --width $ow --height $oh >/dev/null ||
      { echo "FAIL: sdvi render $kind x$scale"; exit 1; }
    pdftoppm -png -singlefile -scale-to-x $ow -scale-to-y $oh "$work/$kind.pdf" "${base}_pdftoppm" &&
    pdftocairo -png -singlefile -transp -scale-to-x $ow -scale-to-y $oh "$work/$kind.pdf" "${base}_pdftocairo" &&
    mutool draw -q -c rgba -w $ow -h $oh -o "${base}_mutool.png" "$work/$kind.pdf" 1 ||
      { echo "FAIL: a viewer could not draw $work/$kind.pdf"; exit 1; }
    for viewer in pdftoppm pdftocairo mutool; do
      printf '%s x%d %s: ' "$kind" $scale $viewer
      "$fixture" compare "${base}_$viewer.png" "${base}_sdvi.png" $min_psnr || status=1
    done
  done
done
exit $status

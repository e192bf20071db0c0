#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest pdf_viewers / pdf_viewer_pdfjs: real PDF viewers draw the export like `sdvi render`
# draws the .sdvi. For a full-frame image and an object image with a hole, at the image's
# size and at x4, each viewer's drawing must reach PSNR >= 35 dB against `sdvi render` of
# the same .sdvi at the same size (over the pixels both draw opaque), and the RGBA drawings
# must leave the outside of the domain transparent and agree with sdvi's alpha everywhere
# but within one pixel of the domain's edge.
#   viewer_test.sh SDVI FIXTURE WORK_DIR native      pdftoppm (poppler, over white),
#                                                   pdftocairo -transp (poppler's cairo
#                                                   backend), mutool draw (MuPDF)
#   viewer_test.sh SDVI FIXTURE WORK_DIR pdfjs ROOT  pdf.js in headless Chromium
#                                                   (scripts/pdf_viewer.mjs)
#   viewer_test.sh SDVI FIXTURE WORK_DIR svg ROOT    `sdvi export-svg` instead of the PDF,
#                                                   drawn by Chromium's SVG renderer
#                                                   (scripts/svg_viewer.mjs)
# Exit 77 (ctest SKIP) only when a viewer is missing (poppler-utils, mupdf-tools; node,
# scripts/npm's pdfjs-dist and playwright-core, chromium).
set -u
sdvi=$1 fixture=$2 work=$3 kind=$4 root=${5:-}
min_psnr=35
if [ "$kind" = native ]; then
  viewers=(pdftoppm pdftocairo mutool)
  for tool in "${viewers[@]}"; do
    command -v $tool >/dev/null 2>&1 ||
      { echo "SKIP: $tool is not installed (Debian packages poppler-utils, mupdf-tools)"; exit 77; }
  done
else
  viewers=($kind)
  [ "$kind" = svg ] && viewers=(chromium)
  command -v node >/dev/null 2>&1 || { echo "SKIP: node is not installed"; exit 77; }
  packages=(pdfjs-dist playwright-core)
  [ "$kind" = svg ] && packages=(playwright-core)
  for pkg in "${packages[@]}"; do
    [ -f "$root/scripts/npm/node_modules/$pkg/package.json" ] ||
      { echo "SKIP: npm package $pkg missing: run npm install in scripts/npm"; exit 77; }
  done
  [ -x "${SDVI_CHROMIUM:-/usr/bin/chromium}" ] || { echo "SKIP: no Chromium (Debian package chromium)"; exit 77; }
fi
rm -rf "$work" && mkdir -p "$work" || exit 1

cases=()
pdfjs_args=()
svg_args=()
for spec in "gradient 96 64" "annulus 80 60"; do
  read -r image w h <<<"$spec"
  "$fixture" sdvi "$image" "$w" "$h" "$work/$image.sdvi" || { echo "FAIL: fixture $image"; exit 1; }
  if [ "$kind" = svg ]; then
    "$sdvi" export-svg "$work/$image.sdvi" -o "$work/$image.svg" --quiet || { echo "FAIL: export-svg $image"; exit 1; }
  else
    "$fixture" pdf "$work/$image.sdvi" "$work/$image.pdf" >/dev/null || { echo "FAIL: export $image"; exit 1; }
  fi
  for scale in 1 4; do
    ow=$((w * scale)) oh=$((h * scale)) base="$work/${image}_x$scale"
    "$sdvi" render "$work/$image.sdvi" -o "${base}_sdvi.png" --width $ow --height $oh >/dev/null ||
      { echo "FAIL: sdvi render $image x$scale"; exit 1; }
    cases+=("$image $scale")
    if [ "$kind" = native ]; then
      pdftoppm -png -singlefile -scale-to-x $ow -scale-to-y $oh "$work/$image.pdf" "${base}_pdftoppm" &&
      pdftocairo -png -singlefile -transp -scale-to-x $ow -scale-to-y $oh "$work/$image.pdf" "${base}_pdftocairo" &&
      mutool draw -q -c rgba -w $ow -h $oh -o "${base}_mutool.png" "$work/$image.pdf" 1 ||
        { echo "FAIL: a viewer could not draw $work/$image.pdf"; exit 1; }
    elif [ "$kind" = svg ]; then
      svg_args+=(--scale $scale "$work/$image.svg" -o "${base}_chromium.png")
    else
      pdfjs_args+=(--scale $scale "$work/$image.pdf" -o "${base}_pdfjs.png")
    fi
  done
done
if [ "$kind" = pdfjs ]; then
  node "$root/scripts/pdf_viewer.mjs" "${pdfjs_args[@]}" >/dev/null || { echo "FAIL: pdf.js"; exit 1; }
fi
if [ "$kind" = svg ]; then
  node "$root/scripts/svg_viewer.mjs" "${svg_args[@]}" >/dev/null || { echo "FAIL: Chromium"; exit 1; }
fi

status=0
for c in "${cases[@]}"; do
  read -r image scale <<<"$c"
  for viewer in "${viewers[@]}"; do
    printf '%s x%d %s: ' "$image" $scale $viewer
    "$fixture" compare "$work/${image}_x${scale}_$viewer.png" "$work/${image}_x${scale}_sdvi.png" $min_psnr || status=1
  done
done
exit $status

#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# The README's pictures, from the built-in sample image:
#   input.png      `sdvi sample` (512x384, generated in code)
#   sdvi_x1.png    the vectorized image rendered at the input's size
#   sdvi_x4.png    a 112x96 px part of it rendered 4x larger (--region)
#   bicubic_x4.png the same part of the input enlarged 4x by bicubic (Catmull-Rom) resampling
#   numbers.txt    what `sdvi vectorize` and `sdvi compare` report
# Usage: scripts/readme_pictures.sh [BUILD_DIR (build)] [OUT_DIR (docs/img)]
# Needs oiiotool (Debian openimageio-tools) for the bicubic enlargement.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build} out=${2:-docs/img}
sdvi="$build/cli/sdvi"
[ -x "$sdvi" ] || { echo "readme_pictures: $sdvi is not built (scripts/setup.sh)" >&2; exit 1; }
command -v oiiotool >/dev/null || { echo "readme_pictures: oiiotool missing (apt-get install openimageio-tools)" >&2; exit 1; }
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# The part enlarged 4x: input pixels x 240..351, y 120..215 (the disc's rim and the triangle's
# lower tip over the gradient).
x=240 y=120 w=112 h=96
"$sdvi" sample -o "$out/input.png"
"$sdvi" vectorize "$out/input.png" -o "$work/sample.sdvi" --report "$work/report.json" --quiet
"$sdvi" render "$work/sample.sdvi" -o "$out/sdvi_x1.png" --quiet
"$sdvi" render "$work/sample.sdvi" -o "$out/sdvi_x4.png" --scale 4 \
  --region $((4 * x)),$((4 * y)),$((4 * w)),$((4 * h)) --quiet
oiiotool "$out/input.png" --resize:filter=catmull-rom 2048x1536 \
  --cut "$((4 * w))x$((4 * h))+$((4 * x))+$((4 * y))" --origin +0+0 --fullpixels -o "$out/bicubic_x4.png"
{
  echo "sdvi vectorize (defaults) of the sample:"
  "$sdvi" info "$work/sample.sdvi" | grep -E "vertices|triangles|file size" || true
  echo "sdvi compare sdvi_x1.png input.png:"
  "$sdvi" compare "$out/sdvi_x1.png" "$out/input.png"
} > "$out/numbers.txt"
cat "$out/numbers.txt"
ls -l "$out"

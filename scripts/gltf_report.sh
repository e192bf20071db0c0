#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# glTF export report for one image: vectorize (or take a .sdvi), export plain and Draco
# .glb, validate both with the Khronos validator, show both in three.js (headless
# Chromium) and compare each screenshot with `sdvi render` at the source size.
#   scripts/gltf_report.sh IN.png|IN.sdvi OUT_DIR [BUILD_DIR]
# Prints a table (sizes, validator counts, PSNR vs sdvi render) and the side-by-side paths
# (three.js | sdvi render | 4 x |difference|).
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)
in=$1 out=$2 build=${3:-$root/build}
sdvi=$build/cli/sdvi fixture=$build/tests/gltf/sdvi_gltf_fixture
mkdir -p "$out"
name=$(basename "${in%.*}")
if [ "${in##*.}" = sdvi ]; then
  cp "$in" "$out/$name.sdvi"
else
  "$sdvi" vectorize "$in" -o "$out/$name.sdvi" --quiet
fi
"$sdvi" render "$out/$name.sdvi" -o "$out/${name}_sdvi.png" >/dev/null
"$sdvi" export-gltf "$out/$name.sdvi" -o "$out/$name.glb" --quiet
"$sdvi" export-gltf "$out/$name.sdvi" -o "$out/${name}_draco.glb" --draco --quiet
"$sdvi" export-gltf "$out/$name.sdvi" -o "$out/${name}_control.glb" --control-mesh --quiet
node "$root/scripts/gltf_validate.mjs" "$out/$name.glb" "$out/${name}_draco.glb" "$out/${name}_control.glb"
node "$root/scripts/gltf_viewer.mjs" "$out/$name.glb" -o "$out/${name}_three.png" \
  "$out/${name}_draco.glb" -o "$out/${name}_draco_three.png" >"$out/viewer.jsonl"
echo
echo "| file | bytes | PSNR three.js vs sdvi render (dB) | three.js load (ms) |"
echo "|---|---|---|---|"
for v in "" _draco; do
  psnr=$("$fixture" compare "$out/${name}${v}_three.png" "$out/${name}_sdvi.png" 0 \
         "$out/${name}${v}_side_by_side.png" | sed 's/.*"psnr": \([0-9.]*\).*/\1/')
  load=$(grep "${name}${v}.glb" "$out/viewer.jsonl" | sed 's/.*"load_ms":\([0-9]*\).*/\1/')
  echo "| ${name}${v}.glb | $(stat -c %s "$out/${name}${v}.glb") | $psnr | $load |"
done
echo
echo "side by side: $out/${name}_side_by_side.png $out/${name}_draco_side_by_side.png"

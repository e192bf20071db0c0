#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest gltf_viewer_three: a real viewer shows the image. For a full-frame image (at 2x)
# and an object image (at 1x), `sdvi export-gltf` (plain .glb, --draco .glb, and
# --draco --control-mesh .gltf, whose control mesh lies beside the frame) is loaded by
# three.js in headless Chromium with an orthographic camera framing the image, and each
# screenshot must match `sdvi render` of the same .sdvi at the same size with PSNR >= 30 dB.
#   viewer_test.sh SDVI FIXTURE REPO_ROOT WORK_DIR
# Writes WORK_DIR/<kind>_<variant>_side_by_side.png (three.js | sdvi render | 4x |diff|).
# Exit 77 (ctest SKIP) when node, the npm packages or Chromium are missing, or while this
# build's CLI still lacks the .sdvi reader or `sdvi render`.
set -u
sdvi=$1 fixture=$2 root=$3 work=$4
min_psnr=30
command -v node >/dev/null 2>&1 || { echo "SKIP: node is not installed"; exit 77; }
for pkg in three playwright-core; do
  [ -f "$root/scripts/npm/node_modules/$pkg/package.json" ] ||
    { echo "SKIP: npm package $pkg missing: run npm install in scripts/npm"; exit 77; }
done
chromium=${SDVI_CHROMIUM:-/usr/bin/chromium}
[ -x "$chromium" ] || { echo "SKIP: no Chromium at $chromium (Debian package chromium)"; exit 77; }
rm -rf "$work" && mkdir -p "$work" || exit 1

# run_cli LOG ARGS...: runs sdvi; exit 77 if the command is a placeholder in this build.
run_cli() {
  local log=$1; shift
  if ! "$sdvi" "$@" >"$log" 2>&1; then
    if grep -q "not built yet" "$log"; then echo "SKIP: sdvi $1: $(cat "$log")"; exit 77; fi
    echo "FAIL: sdvi $*"; cat "$log"; exit 1
  fi
}

# 1. Inputs, our renders and the exports.
cases=()
viewer_args=()
for spec in "gradient 96 64 2" "object 96 64 1"; do
  read -r kind w h scale <<<"$spec"
  ow=$((w * scale)) oh=$((h * scale))
  "$fixture" sdvi "$kind" "$w" "$h" "$work/$kind.sdvi" || { echo "FAIL: fixture $kind"; exit 1; }
  run_cli "$work/$kind.render.log" render "$work/$kind.sdvi" -o "$work/${kind}_sdvi.png" \
    --width "$ow" --height "$oh"
  viewer_args+=(--width "$ow" --height "$oh")
  for variant in plain draco control; do
    case $variant in
      plain) flags=(); ext=glb ;;
      draco) flags=(--draco); ext=glb ;;
      control) flags=(--draco --control-mesh); ext=gltf ;;  # the control mesh sits outside the frame
    esac
    glb="$work/${kind}_$variant.$ext"
    run_cli "$work/${kind}_$variant.export.log" export-gltf "$work/$kind.sdvi" -o "$glb" "${flags[@]}"
    viewer_args+=("$glb" -o "$work/${kind}_${variant}_three.png")
    cases+=("$kind $variant ${ow}x$oh")
  done
done

# 2. One browser session shows every file.
node "$root/scripts/gltf_viewer.mjs" --chromium "$chromium" "${viewer_args[@]}" ||
  { echo "FAIL: the three.js viewer"; exit 1; }

# 3. Screenshots against `sdvi render`.
status=0
for c in "${cases[@]}"; do
  read -r kind variant size <<<"$c"
  echo "$kind $variant ($size): three.js vs sdvi render:"
  "$fixture" compare "$work/${kind}_${variant}_three.png" "$work/${kind}_sdvi.png" "$min_psnr" \
    "$work/${kind}_${variant}_side_by_side.png" || status=1
  echo "  side by side: $work/${kind}_${variant}_side_by_side.png"
done
exit $status

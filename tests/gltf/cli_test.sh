#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest gltf_cli: `sdvi export-gltf` options, exit codes (0 ok, 1 failure, 2 usage) and
# atomic output (a failed export leaves no file).
#   cli_test.sh SDVI FIXTURE WORK_DIR
set -u
sdvi=$1 fixture=$2 work=$3
rm -rf "$work" && mkdir -p "$work" || exit 1
"$fixture" sdvi gradient 64 48 "$work/in.sdvi" || { echo "FAIL: fixture"; exit 1; }
if "$sdvi" export-gltf "$work/in.sdvi" -o "$work/probe.glb" --quiet 2>&1 | grep -q "not built yet"; then
  echo "SKIP: this build's CLI cannot read .sdvi files yet"; exit 77
fi
failures=0
# expect CODE OUTPUT_THAT_MUST_NOT_EXIST|- ARGS...
expect() {
  local code=$1 absent=$2; shift 2
  "$sdvi" export-gltf "$@" >"$work/stdout" 2>"$work/stderr"
  local got=$?
  if [ "$got" -ne "$code" ]; then
    echo "FAIL: export-gltf $* exited $got, expected $code: $(cat "$work/stderr")"; failures=$((failures + 1))
  elif [ "$absent" != - ] && [ -e "$absent" ]; then
    echo "FAIL: export-gltf $* left $absent behind"; failures=$((failures + 1))
  else
    echo "ok: export-gltf $* -> $got $(head -c 200 "$work/stderr")"
  fi
}
expect 2 "$work/out.png" "$work/in.sdvi" -o "$work/out.png"
expect 2 "$work/out.glb" "$work/in.sdvi" -o "$work/out.glb" --position-bits 10
expect 2 "$work/out.glb" "$work/in.sdvi" -o "$work/out.glb" --levels 9
expect 2 "$work/out.glb" "$work/in.sdvi" -o "$work/out.glb" --draco --color-bits 31
expect 2 "$work/out.glb" "$work/in.sdvi" -o "$work/out.glb" --levels two
expect 2 "$work/out.glb" "$work/in.sdvi" -o "$work/out.glb" --bogus
expect 2 - "$work/in.sdvi"
expect 1 "$work/out.glb" "$work/missing.sdvi" -o "$work/out.glb"
expect 1 "$work/nodir/out.glb" "$work/in.sdvi" -o "$work/nodir/out.glb"
printf 'not an sdvi file' >"$work/junk.sdvi"
expect 1 "$work/out.glb" "$work/junk.sdvi" -o "$work/out.glb"

expect 0 - "$work/in.sdvi" -o "$work/out.glb" --levels 1 --quiet
[ -s "$work/stdout" ] && { echo "FAIL: --quiet printed $(cat "$work/stdout")"; failures=$((failures + 1)); }
[ "$(head -c 4 "$work/out.glb")" = glTF ] || { echo "FAIL: out.glb is not a GLB"; failures=$((failures + 1)); }
expect 0 - "$work/in.sdvi" -o "$work/out.gltf" --draco --position-bits 12 --color-bits 10 --speed 0 \
  --control-mesh --copyright "CC0 test"
grep -q 'Draco surface' "$work/stdout" || { echo "FAIL: no summary line"; failures=$((failures + 1)); }
[ "$(head -c 1 "$work/out.gltf")" = "{" ] || { echo "FAIL: out.gltf is not JSON"; failures=$((failures + 1)); }
grep -q '"copyright": "CC0 test"' "$work/out.gltf" || { echo "FAIL: copyright missing"; failures=$((failures + 1)); }
grep -q '"uri": "out.bin"' "$work/out.gltf" && [ -s "$work/out.bin" ] ||
  { echo "FAIL: out.gltf does not refer to an out.bin beside it"; failures=$((failures + 1)); }
grep -q 'KHR_draco_mesh_compression' "$work/out.gltf" || { echo "FAIL: no Draco extension"; failures=$((failures + 1)); }
# --embed: one .gltf with the buffer inside and no .bin; --embed with .glb is a usage error.
expect 0 - "$work/in.sdvi" -o "$work/one.gltf" --levels 1 --embed --quiet
grep -q '"uri": "data:application/octet-stream;base64,' "$work/one.gltf" && [ ! -e "$work/one.bin" ] ||
  { echo "FAIL: --embed did not give one self-contained .gltf"; failures=$((failures + 1)); }
expect 2 "$work/embed.glb" "$work/in.sdvi" -o "$work/embed.glb" --embed
leftovers=$(find "$work" -name '*tmp*' | wc -l)
[ "$leftovers" -eq 0 ] || { echo "FAIL: temporary files left: $(find "$work" -name '*tmp*')"; failures=$((failures + 1)); }
echo "$failures failures"
[ "$failures" -eq 0 ]

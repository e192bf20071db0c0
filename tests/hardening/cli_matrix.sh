#!/usr/bin/env bash
# The bad-input matrix through the command line (issue 16): every command that reads an
# .sdvi file, on an empty file, truncations, single-byte flips, huge declared sizes and
# values no image has; convert and compress on non-manifold, duplicate and folded meshes.
# Each case: a non-zero exit below 128 (no crash), the expected code name and the input's
# name in the message, and no output file.
#   usage: cli_matrix.sh SDVI DATA_DIR WORK_DIR
set -uo pipefail
SDVI=$1 DATA=$2 WORK=$3
rm -rf "$WORK" && mkdir -p "$WORK"
GOLDEN=$DATA/golden_v1_0.sdvi
SIZE=$(stat -c %s "$GOLDEN")
cases=0 failures=0

# expect CODE INPUT OUTPUT -- sdvi arguments...
expect() {
  local code=$1 input=$2 output=$3
  shift 4
  cases=$((cases + 1))
  rm -f "$output"
  "$SDVI" "$@" >"$WORK/out.txt" 2>"$WORK/err.txt"
  local rc=$?
  local why=""
  if [ $rc -eq 0 ] || [ $rc -ge 128 ]; then why="exit $rc"; fi
  if [ -n "$code" ] && ! grep -q -- "$code" "$WORK/err.txt"; then why="$why; no '$code' in the message"; fi
  if ! grep -qF -- "$(basename "$input")" "$WORK/err.txt"; then why="$why; the message does not name $(basename "$input")"; fi
  if [ -n "$output" ] && [ -e "$output" ]; then why="$why; $output was written"; fi
  if [ -n "$(find "$WORK" -name '.*-tmp-*')" ]; then why="$why; a temporary file was left"; fi
  if [ -n "$why" ]; then
    failures=$((failures + 1))
    echo "FAIL: sdvi $*: $why" >&2
    sed 's/^/  stderr: /' "$WORK/err.txt" | head -3 >&2
  fi
}

# Every command that reads an .sdvi file, on input $1, with expected code $2 ('' = any).
every_reader() {
  local in=$1 code=$2
  expect "$code" "$in" "$WORK/o.png" -- render "$in" -o "$WORK/o.png"
  expect "$code" "$in" "" -- info "$in"
  expect "$code" "$in" "$WORK/o.json" -- convert "$in" "$WORK/o.json"
  expect "$code" "$in" "$WORK/o.ply" -- subdivide "$in" --levels 1 -o "$WORK/o.ply"
  expect "$code" "$in" "$WORK/o.glb" -- export-gltf "$in" -o "$WORK/o.glb"
  expect "$code" "$in" "$WORK/o.sdvi" -- compress "$in" -o "$WORK/o.sdvi"
  expect "$code" "$in" "$WORK/o.sdvi" -- decompress "$in" -o "$WORK/o.sdvi"
}

: >"$WORK/empty.sdvi"
every_reader "$WORK/empty.sdvi" empty_input
# Truncations at 12 lengths spread over the file, and single-byte flips at 12 places
# (every length and every byte: matrix_test.cpp, in the library).
for i in $(seq 0 11); do
  len=$(( (SIZE - 1) * i / 11 ))
  head -c "$len" "$GOLDEN" >"$WORK/cut$len.sdvi"
  every_reader "$WORK/cut$len.sdvi" ""
done
for i in $(seq 0 11); do
  at=$(( (SIZE - 1) * i / 11 ))
  cp "$GOLDEN" "$WORK/flip$at.sdvi"
  byte=$(od -An -tu1 -j "$at" -N1 "$GOLDEN" | tr -d ' ')
  printf "$(printf '\\%03o' $(( byte ^ 255 )))" | dd of="$WORK/flip$at.sdvi" bs=1 seek="$at" conv=notrunc status=none
  every_reader "$WORK/flip$at.sdvi" ""
done
# Values no image has, in files with a valid checksum (issue 16, cases 1 and 5).
every_reader "$DATA/bad/colour_-1.7e38.sdvi" value_out_of_range
every_reader "$DATA/bad/x_1e7.sdvi" value_out_of_range
every_reader "$DATA/bad/width_4294967295.sdvi" limit_exceeded
# Meshes the renderer refuses: the writers refuse them too.
for m in duplicate_triangle:duplicate_triangle non_manifold:non_manifold_edge folded:folded_triangle; do
  expect "${m#*:}" "${m%%:*}.json" "$WORK/m.sdvi" -- convert "$DATA/bad/${m%%:*}.json" "$WORK/m.sdvi"
done

echo "cli matrix: $cases cases, $failures failed"
[ $failures -eq 0 ]

#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
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
  expect "$code" "$in" "$WORK/o.pdf" -- export-pdf "$in" -o "$WORK/o.pdf"
  expect "$code" "$in" "$WORK/o.svg" -- export-svg "$in" -o "$WORK/o.svg"
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

# compress --reference: a reference that is no image, or is cut short, is named; nothing written.
: >"$WORK/empty.png"
"$SDVI" render "$GOLDEN" -o "$WORK/gref.png" --quiet
head -c "$(( $(stat -c %s "$WORK/gref.png") / 2 ))" "$WORK/gref.png" >"$WORK/half.png"
for ref in empty.png half.png; do
  expect "" "$ref" "$WORK/o.sdvi" -- compress "$GOLDEN" -o "$WORK/o.sdvi" --reference "$WORK/$ref"
done

# Output paths (issue 16, cases 2 and 6): checked before any work, inputs never replaced,
# non-regular targets written through, symlinks followed.
fail() { failures=$((failures + 1)); echo "FAIL: $*" >&2; }
"$SDVI" sample -o "$WORK/s.png" --width 48 --height 32 >/dev/null || fail "sample"
cp "$WORK/s.png" "$WORK/keep.png"
cp "$GOLDEN" "$WORK/g.sdvi"
for c in "vectorize $WORK/s.png -o $WORK/s.png" "vectorize $WORK/s.png -o $WORK/v.sdvi --report $WORK/s.png" \
         "render $WORK/g.sdvi -o $WORK/g.sdvi" "convert $WORK/g.sdvi $WORK/g.sdvi" "compress $WORK/g.sdvi -o $WORK/g.sdvi" \
         "compress $WORK/g.sdvi -o $WORK/s.png --reference $WORK/s.png"; do
  cases=$((cases + 1))
  # shellcheck disable=SC2086
  "$SDVI" $c >/dev/null 2>"$WORK/err.txt"; rc=$?
  [ $rc -eq 1 ] && grep -q "is the input file" "$WORK/err.txt" || fail "sdvi $c: exit $rc, $(head -1 "$WORK/err.txt")"
  cmp -s "$WORK/s.png" "$WORK/keep.png" && cmp -s "$WORK/g.sdvi" "$GOLDEN" || fail "sdvi $c: the input changed"
  [ ! -e "$WORK/v.sdvi" ] || fail "sdvi $c: wrote v.sdvi"
done
cases=$((cases + 1))
"$SDVI" vectorize "$WORK/s.png" -o "$WORK/v.sdvi" --report "$WORK/nodir/r.json" >/dev/null 2>"$WORK/err.txt"; rc=$?
[ $rc -eq 1 ] && grep -q "nodir" "$WORK/err.txt" && [ ! -e "$WORK/v.sdvi" ] ||
  fail "vectorize --report nodir/r.json: exit $rc, v.sdvi $( [ -e "$WORK/v.sdvi" ] && echo written)"
"$SDVI" render "$GOLDEN" -o "$WORK/ref.png" --quiet || fail "render to a regular file"
# A FIFO gets the bytes and stays a FIFO; a symlink stays a link and its target is replaced.
cases=$((cases + 2))
mkfifo "$WORK/fifo.png"
cat "$WORK/fifo.png" >"$WORK/from_fifo.png" &
"$SDVI" render "$GOLDEN" -o "$WORK/fifo.png" --quiet || fail "render to a FIFO"
wait
[ -p "$WORK/fifo.png" ] && cmp -s "$WORK/from_fifo.png" "$WORK/ref.png" || fail "render to a FIFO: not written through"
echo old >"$WORK/target.png" && chmod 640 "$WORK/target.png" && ln -s target.png "$WORK/link.png"
"$SDVI" render "$GOLDEN" -o "$WORK/link.png" --quiet || fail "render to a symlink"
[ -L "$WORK/link.png" ] && cmp -s "$WORK/target.png" "$WORK/ref.png" && [ "$(stat -c %a "$WORK/target.png")" = 640 ] ||
  fail "render to a symlink: the link was replaced, or the target's content or mode is wrong"
if [ -w /dev/full ]; then
  cases=$((cases + 1))
  "$SDVI" render "$GOLDEN" -o /dev/full --format png --quiet 2>"$WORK/err.txt"; rc=$?
  [ $rc -eq 1 ] && [ -c /dev/full ] || fail "render -o /dev/full: exit $rc (expected 1), $(head -1 "$WORK/err.txt")"
fi

# A memory limit turns a runaway into a clean limit error (issue 16, case 3). 5000 x 5000:
# vectorize holds about 39 bytes a pixel at its peak (spec/METHOD.md 5), so 600M stops it at
# the feature planes (a 4000 x 4000 sample now fits).
cases=$((cases + 1))
"$SDVI" sample -o "$WORK/big.png" --width 5000 --height 5000 >/dev/null || fail "sample 5000x5000"
"$SDVI" vectorize "$WORK/big.png" -o "$WORK/big.sdvi" --max-memory 600M >/dev/null 2>"$WORK/err.txt"; rc=$?
[ $rc -eq 1 ] && grep -q "limit_exceeded" "$WORK/err.txt" && grep -q "big.png" "$WORK/err.txt" && [ ! -e "$WORK/big.sdvi" ] ||
  fail "vectorize --max-memory 600M: exit $rc, $(head -1 "$WORK/err.txt")"
# Under tighter limits the command either finishes or stops cleanly, wherever the limit bites:
# before, the raster libraries loaded under the limit hung (log4cplus starting its threads)
# and a worker thread that could not start ended the process (signal 6). Not under ASan
# (scripts/sanitize.sh sets SDVI_SANITIZED): there a refused throwing operator new ends the
# process instead of throwing std::bad_alloc, wherever the limit happens to bite.
limits="150M 300M 450M"
if [ -n "${SDVI_SANITIZED:-}" ]; then limits=""; fi
if [ -n "$limits" ]; then
  "$SDVI" sample -o "$WORK/mid.png" --width 3000 --height 3000 >/dev/null || fail "sample 3000x3000"
fi
for limit in $limits; do
  cases=$((cases + 1))
  rm -f "$WORK/mid.sdvi"
  timeout 300 "$SDVI" vectorize "$WORK/mid.png" -o "$WORK/mid.sdvi" --max-memory $limit >/dev/null 2>"$WORK/err.txt"; rc=$?
  if [ $rc -eq 0 ]; then
    [ -s "$WORK/mid.sdvi" ] || fail "vectorize --max-memory $limit: exit 0 without a file"
  else
    [ $rc -eq 1 ] && grep -q "limit_exceeded: .*mid.png" "$WORK/err.txt" && [ ! -e "$WORK/mid.sdvi" ] ||
      fail "vectorize --max-memory $limit: exit $rc, $(head -1 "$WORK/err.txt")"
  fi
done

echo "cli matrix: $cases cases, $failures failed"
[ $failures -eq 0 ]

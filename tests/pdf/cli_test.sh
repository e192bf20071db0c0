#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest pdf_cli: `sdvi export-pdf` options, exit codes (0 ok, 1 failure, 2 usage) and no
# output left behind on failure.
#   cli_test.sh SDVI FIXTURE WORK_DIR
set -u
sdvi=$1 fixture=$2 work=$3
rm -rf "$work" && mkdir -p "$work" || exit 1
"$fixture" sdvi gradient 96 64 "$work/in.sdvi" || { echo "FAIL: fixture"; exit 1; }
status=0
expect() {  # expect CODE DESCRIPTION ARGS...
  local code=$1 what=$2; shift 2
  "$sdvi" "$@" >"$work/out.log" 2>&1
  local got=$?
  if [ $got -ne $code ]; then echo "FAIL: $what: exit $got, expected $code"; cat "$work/out.log"; status=1
  else echo "ok: $what"; fi
}
expect 0 "defaults" export-pdf "$work/in.sdvi" -o "$work/a.pdf"
grep -q "level 3, 6144 triangles, 96.0 x 64.0 pt" "$work/out.log" || { echo "FAIL: summary line"; cat "$work/out.log"; status=1; }
expect 0 "same input, same bytes" export-pdf "$work/in.sdvi" -o "$work/b.pdf" --quiet
cmp -s "$work/a.pdf" "$work/b.pdf" || { echo "FAIL: two exports differ"; status=1; }
[ ! -s "$work/out.log" ] || { echo "FAIL: --quiet printed"; status=1; }
expect 0 "--dpi 144 --background white --levels 1 --json" export-pdf "$work/in.sdvi" -o "$work/c.pdf" \
  --dpi 144 --background white --levels 1 --json
grep -q '"page_width_pt": 48' "$work/out.log" && grep -q '"level": 1' "$work/out.log" ||
  { echo "FAIL: --json content"; cat "$work/out.log"; status=1; }
expect 0 "--coordinate-bits 24 --color-bits 16 --json" export-pdf "$work/in.sdvi" -o "$work/f.pdf" \
  --coordinate-bits 24 --color-bits 16 --json
grep -q '"bits_per_coordinate": 24' "$work/out.log" && grep -q '"bits_per_component": 16' "$work/out.log" &&
  grep -q '"steep_triangles": ' "$work/out.log" || { echo "FAIL: bits in --json"; cat "$work/out.log"; status=1; }
expect 2 "--color-bits 10" export-pdf "$work/in.sdvi" -o "$work/e.pdf" --color-bits 10
expect 2 "--coordinate-bits 20" export-pdf "$work/in.sdvi" -o "$work/e.pdf" --coordinate-bits 20
expect 0 "--width-mm" export-pdf "$work/in.sdvi" -o "$work/d.pdf" --width-mm 50.8 --quiet
expect 2 "--dpi and --width-mm together" export-pdf "$work/in.sdvi" -o "$work/e.pdf" --dpi 72 --width-mm 10
expect 2 "--background gray" export-pdf "$work/in.sdvi" -o "$work/e.pdf" --background gray
expect 2 "--levels 9" export-pdf "$work/in.sdvi" -o "$work/e.pdf" --levels 9
expect 2 "--dpi 0" export-pdf "$work/in.sdvi" -o "$work/e.pdf" --dpi 0
expect 2 "no output" export-pdf "$work/in.sdvi"
expect 1 "page too large" export-pdf "$work/in.sdvi" -o "$work/e.pdf" --dpi 0.1
grep -q "in.sdvi" "$work/out.log" || { echo "FAIL: the error names the input"; status=1; }
printf 'not an sdvi file' >"$work/bad.sdvi"
expect 1 "not an sdvi file" export-pdf "$work/bad.sdvi" -o "$work/e.pdf"
expect 1 "missing input" export-pdf "$work/missing.sdvi" -o "$work/e.pdf"
expect 1 "output directory missing" export-pdf "$work/in.sdvi" -o "$work/no/such/dir/e.pdf"
[ ! -e "$work/e.pdf" ] || { echo "FAIL: a failed export left $work/e.pdf"; status=1; }
[ -z "$(find "$work" -name '*.tmp*')" ] || { echo "FAIL: temporary files left"; status=1; }
exit $status

#!/usr/bin/env bash
# SPDX-License-Identifier: GPL-3.0-or-later
# ctest cli_conventions: what every sdvi command shares (README "The command"):
#   --help of every command lists every option with its meaning, default and examples;
#   `sdvi help CMD` prints the same text; -V/--version; exit codes 0 ok, 1 failure, 2 usage;
#   '-' reads standard input and writes standard output; --json prints parseable JSON.
# usage: cli_conventions_test.sh SDVI WORK_DIR
set -uo pipefail
sdvi=$1 work=$2
rm -rf "$work" && mkdir -p "$work"
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }
# expect CODE ARGS...: runs sdvi, checks the exit code.
expect() {
  local code=$1; shift
  "$sdvi" "$@" >"$work/out" 2>"$work/err" </dev/null
  local got=$?
  [ "$got" = "$code" ] || fail "sdvi $* exited $got, expected $code: $(head -c 400 "$work/err")"
}

commands="vectorize import-svg render compare info convert subdivide export-gltf export-pdf export-svg edit compress decompress sample"
for c in $commands; do
  expect 0 "$c" --help
  grep -q "Examples:" "$work/out" || fail "$c --help has no examples"
  grep -q "Exit codes: 0 success, 1 failure, 2 usage error" "$work/out" || fail "$c --help has no exit codes"
  cp "$work/out" "$work/help_$c"
  expect 0 help "$c"
  cmp -s "$work/out" "$work/help_$c" || fail "sdvi help $c differs from sdvi $c --help"
done
# Options show their meaning and default.
grep -q -- "--compression-ratio FLOAT:FLOAT in \[1 - 1e+06\]=64" "$work/help_vectorize" ||
  grep -Eq -- "--compression-ratio.*64" "$work/help_vectorize" || fail "vectorize --help: no default of --compression-ratio"
grep -q "pixels per vertex" "$work/help_vectorize" || fail "vectorize --help: no meaning of --compression-ratio"
for opt in --target-psnr --max-triangles --iterations --mask --report --debug-dir --threads --compress --quiet --json; do
  grep -q -- "$opt" "$work/help_vectorize" || fail "vectorize --help misses $opt"
done
for opt in --position-bits --color-bits --speed --reference --reference-mse --keep-vertex-order --quiet; do
  grep -q -- "$opt" "$work/help_compress" || fail "compress --help misses $opt"
done
grep -q -- "--copyright" "$work/help_export-gltf" || fail "export-gltf --help misses --copyright"

expect 0 --version
grep -Eq "^sdvi [0-9]+\.[0-9]+\.[0-9]+$" "$work/out" || fail "--version: $(cat "$work/out")"
expect 0 -V
expect 0 --help
for c in $commands; do grep -q "$c" "$work/out" || fail "sdvi --help does not list $c"; done

# Usage errors: exit 2, a message naming the problem.
expect 2
expect 2 frobnicate
expect 2 help frobnicate
expect 2 render
expect 2 render in.sdvi
expect 2 render in.sdvi -o out.png --levels -7
expect 2 render in.sdvi -o out.png --threads -3
expect 2 render in.sdvi -o out.png --bogus
expect 2 vectorize in.png -o out.sdvi --compression-ratio zero
expect 2 compress in.sdvi -o out.sdvi --position-bits 31
grep -q "position-bits" "$work/err" || fail "compress --position-bits 31: message does not name the option"
expect 2 sample -o "$work/s.png" --width 4
[ ! -e "$work/s.png" ] || fail "a usage error wrote an output"

# Failures: exit 1, the message names the file.
expect 1 render "$work/missing.sdvi" -o "$work/out.png"
grep -q "missing.sdvi" "$work/err" || fail "render: the error does not name the input"
[ ! -e "$work/out.png" ] || fail "a failed render wrote an output"

# '-' is standard input and standard output.
expect 0 sample -o "$work/sample.png" --width 64 --height 48
"$sdvi" sample -o - --width 64 --height 48 >"$work/sample_stdout.png" || fail "sample -o -"
cmp -s "$work/sample.png" "$work/sample_stdout.png" || fail "sample -o - differs from the file output"
"$sdvi" vectorize - -o - --quiet <"$work/sample.png" >"$work/stdio.sdvi" || fail "vectorize - -o -"
expect 0 vectorize "$work/sample.png" -o "$work/file.sdvi" --quiet
cmp -s "$work/stdio.sdvi" "$work/file.sdvi" || fail "vectorize through stdin/stdout differs from files"
"$sdvi" info - --json <"$work/file.sdvi" >"$work/info.json" || fail "info - --json"
python3 -c "import json,sys; d=json.load(open(sys.argv[1])); assert d['vertices'] > 0" "$work/info.json" ||
  fail "info --json from stdin is not the expected JSON"
# info counts corners by the subdivision engine's rule: a triangle's three boundary
# vertices are creases (crease degree 2), a vertex on no triangle is a corner; a file with
# no triangles has its explicit corners only.
printf '%s' '{"format":"sdvi-mesh","version":1,"width":4,"height":4,"vertices":[[0,0,0,0,0],[3,0,0,0,0],[0,3,0,0,0],[2,2,1,1,1]],"triangles":[[0,1,2]]}' >"$work/corners.json"
printf '%s' '{"format":"sdvi-mesh","version":1,"width":4,"height":4,"vertices":[[0,0,0,0,0]],"triangles":[]}' >"$work/no_triangles.json"
for f in corners:1 no_triangles:0; do
  name=${f%%:*} want=${f##*:}
  expect 0 convert "$work/$name.json" "$work/$name.sdvi"
  expect 0 info "$work/$name.sdvi" --json
  python3 -c "import json,sys; assert json.load(open(sys.argv[1]))['corners'] == int(sys.argv[2])" "$work/out" "$want" ||
    fail "info $name.sdvi: corners is not $want"
done
"$sdvi" render - -o - --format png --scale 2 <"$work/file.sdvi" >"$work/x2_stdout.png" || fail "render - -o -"
expect 0 render "$work/file.sdvi" -o "$work/x2.png" --scale 2 --quiet
cmp -s "$work/x2.png" "$work/x2_stdout.png" || fail "render -o - differs from the file output"
expect 0 compress "$work/file.sdvi" -o "$work/c.sdvi" --quiet
"$sdvi" decompress - -o - <"$work/c.sdvi" >"$work/d_stdout.sdvi" || fail "decompress - -o -"
expect 0 decompress "$work/c.sdvi" -o "$work/d.sdvi"
cmp -s "$work/d.sdvi" "$work/d_stdout.sdvi" || fail "decompress -o - differs from the file output"
expect 2 render "$work/file.sdvi" -o - --json
# A summary never mixes into the data on standard output.
"$sdvi" compress "$work/file.sdvi" -o - >"$work/c_stdout.sdvi" 2>"$work/err" || fail "compress -o -"
cmp -s "$work/c.sdvi" "$work/c_stdout.sdvi" || fail "compress -o - differs from the file output"
grep -q "bytes" "$work/err" || fail "compress -o -: the summary should go to stderr"

# --json on every command that prints a result.
for args in "vectorize $work/sample.png -o $work/j.sdvi" "render $work/file.sdvi -o $work/j.png" \
            "compress $work/file.sdvi -o $work/jc.sdvi" "subdivide $work/file.sdvi -o $work/j.ply" \
            "export-gltf $work/file.sdvi -o $work/j.glb" "info $work/file.sdvi" \
            "compare $work/x2.png $work/x2_stdout.png"; do
  # shellcheck disable=SC2086
  "$sdvi" $args --json >"$work/j.json" 2>"$work/err" || fail "$args --json failed: $(cat "$work/err")"
  python3 -c "import json,sys; json.load(open(sys.argv[1]))" "$work/j.json" || fail "$args --json: not JSON"
done

[ "$failures" = 0 ] && echo "PASS" || { echo "$failures failure(s)"; exit 1; }
